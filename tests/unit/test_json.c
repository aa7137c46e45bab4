/* Scanning JSON text: string and container ends (escapes included), the
 * mark of a cut text, the excerpt near an error (never past the buffer,
 * which need not end in NUL), and the indented form. */
#include "test.h"

#include "core/err.h"
#include "core/json.h"
#include "weather/provider.h"

#include <stdlib.h>

static size_t len_of(const char *s) { return strlen(s); }

static void string_end_skips_escaped_quotes(void)
{
	const char *s = "\"a\\\"b\\\\\" , 1";    /* "a\"b\\" , 1 */
	CHECK(cs_json_string_end(s, len_of(s), 0) == 8);
	const char *cut = "\"abc\\\"";             /* "abc\"  (no close) */
	CHECK(cs_json_string_end(cut, len_of(cut), 0) == len_of(cut));
}

static void container_end_matches_brackets_outside_strings(void)
{
	const char *s = "{\"a\":\"}]\",\"b\":[1,{\"c\":2}]} tail";
	int flat;
	CHECK(cs_json_container_end(s, len_of(s), 0, &flat) == 26 && !flat);
	CHECK(cs_json_container_end(s, len_of(s), 14, &flat) == 25 && !flat);
	CHECK(cs_json_container_end(s, len_of(s), 17, &flat) == 24 && flat);
	CHECK(cs_json_container_end("[1,2", 4, 0, &flat) == 4);
}

static void cut_short_sees_open_strings_and_brackets(void)
{
	static const struct {
		const char *text;
		int cut;
	} t[] = {
		{"{\"a\":[1,2]}", 0},
		{"{\"a\":[1,2]", 1},
		{"{\"a\":\"xy", 1},
		{"{\"a\":\"x\\\"", 1},     /* ends on an escaped quote */
		{"{\"a\":\"[{\"}", 0},     /* brackets in a string do not count */
		{"{\"a\":1}}", 0},
		{"\"done\"", 0},
	};
	for (size_t i = 0; i < sizeof t / sizeof t[0]; i++)
		CHECK(cs_json_cut_short(t[i].text, len_of(t[i].text),
					len_of(t[i].text)) == t[i].cut);
	/* an error at byte 5 followed by more structure is no cut */
	const char *s = "{\"a\":x, \"b\":[1";
	CHECK(cs_json_cut_short(s, len_of(s), 5) == 0);
	CHECK(cs_json_cut_short(s, len_of(s), 13) == 1);
}

static void near_stays_inside_the_buffer_and_on_one_line(void)
{
	const char text[] = "{\"a\": 1,\n \"b\": tru";
	size_t len = sizeof text - 1;
	char *exact = malloc(len); /* no terminator: ASan sees an over-read */
	CHECK(exact != NULL);
	if (exact == NULL)
		return;
	memcpy(exact, text, len);
	size_t from, to;
	cs_json_near(exact, len, len, &from, &to);
	CHECK(from == 9 && to == len); /* " \"b\": tru", after the newline */
	cs_json_near(exact, len, 3, &from, &to);
	CHECK(from == 0 && to == 8);   /* stops at the newline */
	cs_json_near(exact, len, len + 5, &from, &to);
	CHECK(to <= len);
	free(exact);
}

static void provider_malformed_message_reads_only_len_bytes(void)
{
	const char text[] = "{\"metadata\": {\"name\": x}}";
	size_t len = sizeof text - 1;
	char *exact = malloc(len);
	CHECK(exact != NULL);
	if (exact == NULL)
		return;
	memcpy(exact, text, len);
	struct cs_problems pr;
	CHECK(cs_provider_check(exact, len, &pr) == CS_EDATA);
	CHECK(pr.count >= 1);
	if (pr.count >= 1)
		CHECK_STR_CONTAINS(pr.msg[0], "malformed JSON at byte offset");
	free(exact);
}

static void pretty_indents_and_keeps_flat_containers_on_one_line(void)
{
	char *out = NULL;
	CHECK(cs_json_pretty("{\"a\":1,\"b\":[1,2],\"c\":{\"d\":\"x, y\",\"e\":[{\"f\":null}]}}",
			     &out) == CS_OK);
	const char *want =
		"{\n"
		"  \"a\": 1,\n"
		"  \"b\": [1, 2],\n"
		"  \"c\": {\n"
		"    \"d\": \"x, y\",\n"
		"    \"e\": [\n"
		"      {\"f\": null}\n"
		"    ]\n"
		"  }\n"
		"}\n";
	CHECK(out != NULL && strcmp(out, want) == 0);
	if (out && strcmp(out, want) != 0)
		printf("%s", out);
	free(out);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(string_end_skips_escaped_quotes),
	CASE(container_end_matches_brackets_outside_strings),
	CASE(cut_short_sees_open_strings_and_brackets),
	CASE(near_stays_inside_the_buffer_and_on_one_line),
	CASE(provider_malformed_message_reads_only_len_bytes),
	CASE(pretty_indents_and_keeps_flat_containers_on_one_line),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
