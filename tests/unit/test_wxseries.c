/* A series of weather states (cs_wx_series_*): every state of a JSON Lines
 * text, each state spread over lines as wxinterp --pretty writes it, and
 * errors that name the state and its line. */
#include "test.h"

#include "core/err.h"
#include "weather/wx.h"

#include <stdio.h>

#define STATE(time, cover)                                                    \
	"{\"schema\":\"cloudwx/1\",\"time_utc\":\"" time "\",\"site\":{\"lat_deg\":"  \
	"46.95,\"lon_deg\":7.44},\"layers\":[{\"genus\":\"cumulus\",\"coverage\":"     \
	cover ",\"base_m\":1500,\"top_m\":2700}]}"

static int parse(const char *text, struct cs_wx_series *s)
{
	return cs_wx_series_parse(text, strlen(text), s);
}

static void series_reads_every_line_in_order(void)
{
	struct cs_wx_series s;
	/* blank lines and CRLF between states are not states */
	const char *text = "\n" STATE("2021-06-14T12:00Z", "0.1") "\r\n\n"
			   STATE("2021-06-14T12:01Z", "0.2") "\n   \n"
			   STATE("2021-06-14T12:02Z", "0.3");
	CHECK(parse(text, &s) == CS_OK);
	CHECK(s.n == 3);
	struct cs_wx wx;
	for (int i = 0; i < s.n && i < 3; i++) {
		CHECK(cs_wx_series_get(&s, i, &wx) == CS_OK);
		/* 2021-06-14T12:00Z is 1623672000 s after the epoch (date -d) */
		CHECK_NEAR(wx.time_utc, 1623672000.0 + 60.0 * i, 0.0);
		CHECK_NEAR(wx.layers[0].coverage, 0.1 * (i + 1), 1e-12);
	}
	CHECK(cs_wx_series_get(&s, 3, &wx) == CS_EINVAL);
	CHECK(cs_wx_series_get(&s, -1, &wx) == CS_EINVAL);
	cs_wx_series_free(&s);
}

static void series_of_states_over_several_lines(void)
{
	struct cs_wx_series s;
	const char *text = "{\n  \"schema\": \"cloudwx/1\",\n  \"time_utc\": \"2021-06-14T12:00Z\",\n"
			   "  \"site\": {\"lat_deg\": 46.95, \"lon_deg\": 7.44},\n  \"layers\": []\n}\n"
			   "{\n  \"schema\": \"cloudwx/1\",\n  \"time_utc\": \"2021-06-14T13:00Z\",\n"
			   "  \"site\": {\"lat_deg\": 46.95, \"lon_deg\": 7.44},\n  \"layers\": []\n}\n";
	CHECK(parse(text, &s) == CS_OK);
	CHECK(s.n == 2);
	struct cs_wx wx;
	CHECK(s.n == 2 && cs_wx_series_get(&s, 1, &wx) == CS_OK &&
	      wx.time_utc == 1623672000.0 + 3600.0);
	cs_wx_series_free(&s);
	/* a single state is a series of one */
	CHECK(parse(STATE("2021-06-14T12:00Z", "0.5"), &s) == CS_OK && s.n == 1);
	cs_wx_series_free(&s);
}

static void series_errors_name_the_state_and_its_line(void)
{
	struct cs_wx_series s;
	const char *text = STATE("2021-06-14T12:00Z", "0.1") "\n\n"
			   STATE("2021-06-14T12:01Z", "1.5") "\n";
	CHECK(parse(text, &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "input: state 2 (line 3): layers[0].coverage: 1.5 "
			   "is outside 0..1");
	CHECK(s.n == 0 && s.text == NULL); /* nothing to free */
	/* the first state's errors read as a single state's always did */
	CHECK(parse(STATE("2021-06-14T12:00Z", "2"), &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "input: layers[0].coverage: 2 is outside 0..1");
	CHECK(strstr(cs_errmsg(), "state 1") == NULL);
	/* two states on one line are not JSON Lines */
	CHECK(parse(STATE("2021-06-14T12:00Z", "0.1") " " STATE("2021-06-14T12:01Z", "0.1"), &s)
	      == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "unexpected text after the JSON object");
	CHECK(parse("\n \n", &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "empty input");
	char nul[] = STATE("2021-06-14T12:00Z", "0.1") "\n" STATE("2021-06-14T12:00Z", "0.1");
	nul[sizeof nul - 20] = '\0';
	CHECK(cs_wx_series_parse(nul, sizeof nul - 1, &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "NUL byte");
}

static void series_reads_a_file_and_names_it(void)
{
	char path[] = "/tmp/cs-wxseries-XXXXXX";
	int fd = mkstemp(path);
	CHECK(fd >= 0);
	if (fd < 0)
		return;
	FILE *f = fdopen(fd, "w");
	fputs(STATE("2021-06-14T12:00Z", "0.1") "\n" STATE("2021-06-14T12:01Z", "x") "\n", f);
	fclose(f);
	struct cs_wx_series s;
	CHECK(cs_wx_series_read(path, &s) == CS_EDATA);
	char want[128];
	snprintf(want, sizeof want, "%s: state 2 (line 2): malformed JSON", path);
	CHECK_STR_CONTAINS(cs_errmsg(), want);
	remove(path);
	CHECK(cs_wx_series_read(path, &s) == CS_EIO);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(series_reads_every_line_in_order),
	CASE(series_of_states_over_several_lines),
	CASE(series_errors_name_the_state_and_its_line),
	CASE(series_reads_a_file_and_names_it),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
