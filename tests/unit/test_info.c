/* The --info style (core/info.h): labelled lines, and the same facts as
 * JSON that a JSON parser reads back. */
#include "test.h"

#include "core/info.h"

#include <cjson/cJSON.h>
#include <stdlib.h>

static void build(struct cs_info *in)
{
	const double size[2] = {103, 140};
	cs_info_str(in, "file", "file", "a \"b\"\\c.exr");
	cs_info_nums(in, "size", "size", size, 2, 0, " x ", "samples");
	cs_info_open(in, "height_m", "height");
	cs_info_num(in, "min", "min", -0.0001, 3, "m");
	cs_info_num(in, "max", "max", 456.4963, 3, "m");
	cs_info_num(in, "none", "none", NAN, 3, NULL);
	cs_info_close(in);
	cs_info_num(in, "count", "count", 476, 0, NULL);
}

static void info_text_is_labelled_lines(void)
{
	struct cs_info in;
	char *text;
	cs_info_init(&in, 0);
	build(&in);
	CHECK(cs_info_finish(&in, &text) == 0);
	CHECK(strcmp(text, "file: a \"b\"\\c.exr\n"
			   "size: 103 x 140 samples\n"
			   "height:\n"
			   "  min: 0.000 m\n"
			   "  max: 456.496 m\n"
			   "  none: unknown\n"
			   "count: 476\n") == 0);
	free(text);
}

static void info_json_reads_back(void)
{
	struct cs_info in;
	char *text;
	cs_info_init(&in, 1);
	build(&in);
	CHECK(cs_info_finish(&in, &text) == 0);
	cJSON *j = cJSON_Parse(text);
	CHECK(cJSON_IsObject(j));
	if (j) {
		CHECK(strcmp(cJSON_GetObjectItem(j, "file")->valuestring, "a \"b\"\\c.exr") == 0);
		cJSON *sz = cJSON_GetObjectItem(j, "size");
		CHECK(cJSON_GetArraySize(sz) == 2 && cJSON_GetArrayItem(sz, 1)->valuedouble == 140);
		cJSON *h = cJSON_GetObjectItem(j, "height_m");
		CHECK(cJSON_GetObjectItem(h, "max")->valuedouble == 456.496);
		CHECK(cJSON_GetObjectItem(h, "min")->valuedouble == 0.0);
		CHECK(cJSON_IsNull(cJSON_GetObjectItem(h, "none")));
		CHECK(cJSON_GetObjectItem(j, "count")->valuedouble == 476);
	}
	cJSON_Delete(j);
	free(text);
}

static const struct t_case t_cases[] = {
	CASE(info_text_is_labelled_lines),
	CASE(info_json_reads_back),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
