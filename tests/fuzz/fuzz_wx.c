/* fuzz_wx - the cloudwx parser (man 5 cloudwx): one state (cs_wx_parse)
 * and JSON Lines (cs_wx_parse_lines, what cs_wx_read does with a file).
 * A state either parser accepts must write back (cs_wx_to_json) to text
 * that parses to a state that writes the same text. */
#include "weather/wx.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void round_trip(const struct cs_wx *wx)
{
	char *a = NULL, *b = NULL;
	struct cs_wx back;
	if (cs_wx_to_json(wx, &a) != 0)
		abort(); /* a state the parser validated must be writable */
	if (cs_wx_parse(a, strlen(a), &back) != 0)
		abort();
	if (cs_wx_to_json(&back, &b) != 0 || strcmp(a, b) != 0)
		abort();
	free(a);
	free(b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	struct cs_wx wx;
	if (cs_wx_parse((const char *)data, size, &wx) == 0)
		round_trip(&wx);
	if (cs_wx_parse_lines((const char *)data, size, &wx) == 0)
		round_trip(&wx);
	return 0;
}
