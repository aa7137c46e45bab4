/* test_edges.c - boundaries of parsing and calendar arithmetic, against
 * the standards that define them:
 *  - the proleptic Gregorian day count of Hinnant's days_from_civil
 *    (http://howardhinnant.github.io/date_algorithms.html): 0000-03-01 is
 *    day -719468 from 1970-01-01, and one 400-year era is 146097 days, so
 *    negative years fall in whole eras before it;
 *  - RFC 3339 section 5.6 (NOTE): "T" and "Z" may be lower case;
 *  - the weather state's rule (man 5 cloudwx): a layer's top at least
 *    10 m above its base. */
#include "core/err.h"
#include "core/time.h"
#include "test.h"
#include "weather/wx.h"

static void day_count_before_year_zero_is_whole_eras(void)
{
	CHECK(cs_days_from_civil(1970, 1, 1) == 0);
	CHECK(cs_days_from_civil(0, 3, 1) == -719468);
	CHECK(cs_days_from_civil(-400, 3, 1) == -719468 - 146097);
	CHECK(cs_days_from_civil(-800, 3, 1) == -719468 - 2 * 146097);
	/* -400 is a leap year (divisible by 400): January and February hold
	 * 31 + 29 days before 1 March */
	CHECK(cs_days_from_civil(-400, 1, 1) == -719468 - 146097 - 60);
	CHECK(cs_days_from_civil(-1, 12, 31) == -719468 - 61);
	/* and every day in between follows its predecessor */
	long prev = cs_days_from_civil(-801, 1, 1) - 1;
	static const int mdays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
	for (long y = -801; y <= 401; y++)
		for (int m = 1; m <= 12; m++) {
			int leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
			int n = mdays[m - 1] + (m == 2 && leap);
			for (int d = 1; d <= n; d++) {
				long v = cs_days_from_civil(y, m, d);
				if (v != prev + 1) {
					printf("  %ld-%02d-%02d is day %ld after %ld\n", y, m, d, v, prev);
					t_case_failed = 1;
					return;
				}
				prev = v;
			}
		}
}

static void times_take_lower_case_t_and_z(void)
{
	double a = NAN, b = NAN, c = NAN;
	CHECK(cs_time_parse("2021-06-14T15:00:00Z", &a) == CS_OK);
	CHECK(cs_time_parse("2021-06-14t15:00:00z", &b) == CS_OK);
	CHECK(cs_time_parse("2021-06-14t15:00Z", &c) == CS_OK);
	CHECK(a == b && a == c);
	CHECK(a == (cs_days_from_civil(2021, 6, 14) * 24 + 15) * 3600.0);
}

static void layers_thinner_than_10_m_are_refused(void)
{
	static const char *const fmt =
		"{\"schema\":\"cloudwx/1\",\"time_utc\":\"2021-06-14T15:00:00Z\","
		"\"site\":{\"lat_deg\":46.95,\"lon_deg\":7.44,\"alt_m\":540},"
		"\"layers\":[{\"genus\":\"stratus\",\"coverage\":1,\"base_m\":1000,\"top_m\":%g}]}";
	static const double tops[] = {1000, 1005, 1009.9, 1010, 1500};
	for (size_t k = 0; k < sizeof tops / sizeof tops[0]; k++) {
		char json[512];
		snprintf(json, sizeof json, fmt, tops[k]);
		struct cs_wx wx;
		int rc = cs_wx_parse(json, strlen(json), &wx);
		if (tops[k] >= 1010) {
			CHECK(rc == CS_OK);
		} else {
			CHECK(rc == CS_EDATA);
			CHECK_STR_CONTAINS(cs_errmsg(), "is not at least 10 m above base_m 1000");
		}
	}
}

static const struct t_case t_cases[] = {
	CASE(day_count_before_year_zero_is_whole_eras),
	CASE(times_take_lower_case_t_and_z),
	CASE(layers_thinner_than_10_m_are_refused),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
