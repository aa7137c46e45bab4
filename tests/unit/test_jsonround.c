/* JSON that people read: the numbers the programs write are rounded to
 * what they mean, and a state written, read back and written again is the
 * same bytes (so it renders the same: a renderer sees only the text). */
#include "test.h"

#include "core/err.h"
#include "core/fmt.h"
#include "weather/wx.h"

#include <stdlib.h>

static void num_round_gives_the_decimals_asked(void)
{
	/* the examples, and values whose decimal is not what the
	 * double holds (1.005 is 1.00499999999999989...) */
	CHECK(strcmp(cs_num_round(1271.8967441392303, 0).s, "1272") == 0);
	CHECK(strcmp(cs_num_round(4.4399999999999995, 2).s, "4.44") == 0);
	CHECK(strcmp(cs_num_round(0.0134, 3).s, "0.013") == 0);
	CHECK(strcmp(cs_num_round(0.0135001, 3).s, "0.014") == 0);
	CHECK(strcmp(cs_num_round(1.005, 2).s, "1") == 0);
	CHECK(strcmp(cs_num_round(-56.151733333, 6).s, "-56.151733") == 0);
	CHECK(strcmp(cs_num_round(-0.0004, 3).s, "0") == 0); /* never "-0" */
	CHECK(strcmp(cs_num_round(2600000.25, 0).s, "2600000") == 0);
	CHECK(strcmp(cs_num_round(1e300, 2).s, "1e+300") == 0);
	/* rounding what was read back changes nothing */
	double x = 0.1;
	for (int i = 0; i < 1000; i++, x = x * 1.37 + 0.013) {
		struct cs_num a = cs_num_round(x, 3);
		struct cs_num b = cs_num_round(strtod(a.s, NULL), 3);
		if (strcmp(a.s, b.s) != 0) {
			CHECK(strcmp(a.s, b.s) == 0);
			break;
		}
	}
}

static void wx_state_numbers_are_rounded_and_round_trip_to_the_same_bytes(void)
{
	struct cs_wx wx, back;
	cs_wx_default(&wx);
	wx.site.lat_deg = 46.951234567891;
	wx.site.lon_deg = 7.438765432198;
	wx.site.alt_m = 540.4999;
	wx.nlayers = 1;
	wx.layers[0].genus = CS_CUMULUS;
	wx.layers[0].coverage = 0.58716666666666667;
	wx.layers[0].base_m = 1271.8967441392303;
	wx.layers[0].top_m = 1282.4967441392303; /* the thinnest: 10.6 m */
	wx.wind_speed_m_s = 4.4399999999999995;
	wx.wind_from_deg = 44.56666666666666;
	wx.visibility_m = 13530.4;
	wx.precipitation_mm_h = 0.0041;
	wx.temperature_c = 17.822499999999998;
	wx.observed = (struct cs_wx_observed){1, 458.1149999, 507.1, 167.6, 1, 0.12345};
	char *a = NULL, *b = NULL;
	CHECK(cs_wx_to_json(&wx, &a) == CS_OK);
	if (a == NULL) {
		printf("  %s\n", cs_errmsg());
		return;
	}
	CHECK_STR_CONTAINS(a, "\"lat_deg\":46.951235,\"lon_deg\":7.438765,\"alt_m\":540}");
	CHECK_STR_CONTAINS(a, "\"coverage\":0.587,\"base_m\":1272,\"top_m\":1282}");
	CHECK_STR_CONTAINS(a, "\"speed_m_s\":4.44,\"from_deg\":44.6}");
	CHECK_STR_CONTAINS(a, "\"visibility_m\":13530,");
	CHECK_STR_CONTAINS(a, "\"precipitation_mm_h\":0.004,");
	CHECK_STR_CONTAINS(a, "\"temperature_c\":17.82,");
	CHECK_STR_CONTAINS(a, "{\"ghi_w_m2\":458.11,\"dni_w_m2\":507.1,\"dhi_w_m2\":167.6,"
			   "\"total_cloud_cover\":0.123}");
	CHECK(cs_wx_parse(a, strlen(a), &back) == CS_OK);
	CHECK(cs_wx_to_json(&back, &b) == CS_OK);
	CHECK(b != NULL && strcmp(a, b) == 0);
	free(a);
	free(b);
}

static const struct t_case t_cases[] = {
	CASE(num_round_gives_the_decimals_asked),
	CASE(wx_state_numbers_are_rounded_and_round_trip_to_the_same_bytes),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
