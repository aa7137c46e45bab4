/* fuzz_text - the small text parsers of the command lines: ISO 8601 times
 * (cs_time_parse, --at, --time), durations (cs_duration_parse, --step,
 * --max-gap) and play-mode edits (cs_wx_set_check, cs_wx_set: wxinterp
 * --set PATH=VALUE) on the default state, validated after.  A time that
 * parses formats back to text that parses to the same whole second. */
#include "core/time.h"
#include "weather/wx.h"
#include "weather/wxset.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size > 4096)
		return 0;
	char *s = malloc(size + 1);
	if (s == NULL)
		return 0;
	memcpy(s, data, size);
	s[size] = '\0';
	double t, d;
	if (cs_time_parse(s, &t) == 0 && isfinite(t) && fabs(t) < 1e14) {
		char buf[64];
		double back;
		cs_time_format(t, buf, sizeof buf);
		if (cs_time_parse(buf, &back) == 0 && back != floor(t))
			abort();
		(void)cs_julian_day(t);
	}
	(void)cs_duration_parse(s, &d);
	struct cs_wx wx;
	cs_wx_default(&wx);
	/* several edits separated by newlines, as several --set options */
	for (char *line = strtok(s, "\n"); line != NULL; line = strtok(NULL, "\n")) {
		(void)cs_wx_set_check(line);
		if (cs_wx_set(&wx, line) != 0)
			break;
	}
	if (cs_wx_validate(&wx) == 0) {
		char *json = NULL;
		if (cs_wx_to_json(&wx, &json) != 0)
			abort();
		free(json);
	}
	free(s);
	return 0;
}
