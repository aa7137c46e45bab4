#include "core/err.h"
#include "core/fileio.h"
#include "weather/provider.h"
#include "test.h"
#include "core/time.h"

#include <stdlib.h>

/* The real capture of ../shared/data (never copied into the project). */
static const char *real_path(void)
{
	static char path[1024];
	const char *data = getenv("DATA");
	snprintf(path, sizeof path, "%s/weather/meteoblue-basic-clouds-solar-1h.json",
		 data && data[0] ? data : "../shared/data");
	return path;
}

/* A small meteoblue response: 3 hours at Bern.  Every value the tests edit
 * is unique in the text. */
static const char mb_base[] =
	"{\"metadata\":{\"name\":\"Test\",\"latitude\":46.95,\"longitude\":7.44,"
	"\"height\":540,\"timezone_abbrevation\":\"GMT\",\"utc_timeoffset\":0.0},"
	"\"units\":{\"time\":\"YYYY-MM-DD hh:mm\",\"cloudcover\":\"percent\","
	"\"precipitation\":\"mm\",\"windspeed\":\"ms-1\",\"winddirection\":\"degree\","
	"\"visibility\":\"m\",\"probability\":\"percent\",\"temperature\":\"C\"},"
	"\"data_1h\":{\"time\":[\"2021-06-14 00:00\",\"2021-06-14 01:00\","
	"\"2021-06-14 02:00\"],\"lowclouds\":[11,21,31],\"midclouds\":[0,0,0],"
	"\"highclouds\":[5,6,7],\"precipitation\":[0.0,0.5,1.5],"
	"\"convective_precipitation\":[0.0,0.25,0.75],\"windspeed\":[1.5,2.5,3.5],"
	"\"winddirection\":[350,10,20],\"visibility\":[10060,20000,30000],"
	"\"fog_probability\":[1,2,3],\"temperature\":[14.75,15.5,16.25],"
	"\"rainspot\":[\"00\",\"01\",\"02\"]}}";

/* A small Open-Meteo response: 2 hours at Sao Paulo's offset, km/h. */
static const char om_base[] =
	"{\"latitude\":-15.75,\"longitude\":-48.0,\"generationtime_ms\":2.04,"
	"\"utc_offset_seconds\":-10800,\"timezone\":\"America/Sao_Paulo\","
	"\"elevation\":1134.0,\"hourly_units\":{\"time\":\"iso8601\","
	"\"cloud_cover_low\":\"%\",\"cloud_cover_mid\":\"%\",\"cloud_cover_high\":\"%\","
	"\"precipitation\":\"mm\",\"showers\":\"mm\",\"wind_speed_10m\":\"km/h\","
	"\"wind_direction_10m\":\"\xc2\xb0\",\"temperature_2m\":\"\xc2\xb0""F\","
	"\"is_day\":\"\"},"
	"\"hourly\":{\"time\":[\"2023-10-25T00:00\",\"2023-10-25T01:00\"],"
	"\"cloud_cover_low\":[40,null],\"cloud_cover_mid\":[50,60],"
	"\"cloud_cover_high\":[70,80],\"precipitation\":[1.0,2.0],"
	"\"showers\":[0.5,0.25],\"wind_speed_10m\":[36.0,18.0],"
	"\"wind_direction_10m\":[90,180],\"temperature_2m\":[50,104],"
	"\"is_day\":[0,1]}}";

/* base with the first occurrence of from replaced by to (from must occur). */
static const char *edited(const char *base, const char *from, const char *to)
{
	static char buf[8192];
	const char *at = strstr(base, from);
	if (at == NULL) {
		printf("  edit '%s' not found\n", from);
		t_case_failed = 1;
		return base;
	}
	snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - base), base, to,
		 at + strlen(from));
	return buf;
}

static int check(const char *json, struct cs_problems *pr)
{
	return cs_provider_check(json, strlen(json), pr);
}

/* The problems of json, one of which must contain want. */
static void expect_problem(const char *json, const char *want)
{
	struct cs_problems pr;
	CHECK(check(json, &pr) == CS_EDATA);
	int found = 0;
	for (int i = 0; i < pr.count && i < 32; i++)
		found |= strstr(pr.msg[i], want) != NULL;
	if (!found) {
		printf("  no problem contains \"%s\"; got %d:\n", want, pr.count);
		for (int i = 0; i < pr.count && i < 5; i++)
			printf("    %s\n", pr.msg[i]);
		t_case_failed = 1;
	}
}

static double utc(const char *s)
{
	double t = NAN;
	cs_time_parse(s, &t);
	return t;
}

static void real_meteoblue_capture_checks_clean_and_parses(void)
{
	unsigned char *data;
	size_t len;
	if (cs_read_all(real_path(), 1 << 24, &data, &len) != CS_OK)
		SKIP("%.200s is absent (the shared data folder is not here)", real_path());
	struct cs_problems pr;
	CHECK(cs_provider_check((char *)data, len, &pr) == CS_OK);
	CHECK(pr.count == 0);
	if (pr.count)
		printf("  first problem: %s\n", pr.msg[0]);
	enum cs_provider p = CS_PROVIDER_OPENMETEO;
	CHECK(cs_provider_detect((char *)data, len, &p) == CS_OK);
	CHECK(p == CS_PROVIDER_METEOBLUE);
	struct cs_series s;
	int rc = cs_provider_parse((char *)data, len, "real", &s);
	free(data);
	CHECK(rc == CS_OK);
	if (rc != CS_OK)
		return;
	CHECK(s.n == 193);
	CHECK_NEAR(s.lat_deg, -34.810272, 1e-12);
	CHECK_NEAR(s.lon_deg, -56.151733, 1e-12);
	CHECK_NEAR(s.alt_m, 34, 0);
	CHECK_NEAR(s.utc_offset_s, 0, 0);
	CHECK_NEAR(s.time_utc[0], utc("2024-10-06T00:00Z"), 0);
	CHECK_NEAR(s.time_utc[192], utc("2024-10-14T00:00Z"), 0);
	CHECK_NEAR(s.v[CS_VAR_CLOUD_LOW][7], 64, 0);
	CHECK_NEAR(s.v[CS_VAR_CLOUD_HIGH][3], 71, 0);
	CHECK_NEAR(s.v[CS_VAR_WIND_SPEED][0], 4.51, 0);
	CHECK_NEAR(s.v[CS_VAR_WIND_FROM][1], 115, 0);
	CHECK_NEAR(s.v[CS_VAR_VISIBILITY][3], 10520, 0);
	CHECK_NEAR(s.v[CS_VAR_FOG_PROBABILITY][6], 8, 0);
	CHECK_NEAR(s.v[CS_VAR_TEMPERATURE][0], 14.75, 0);
	CHECK_NEAR(s.v[CS_VAR_IS_DAY][9], 1, 0);
	CHECK(s.v[CS_VAR_CONV_PRECIP] != NULL && s.v[CS_VAR_HUMIDITY] != NULL);
	CHECK(s.v[CS_VAR_SNOW_FRACTION] != NULL && s.v[CS_VAR_SNOWFALL] == NULL);
	if (s.v[CS_VAR_SNOW_FRACTION] != NULL) /* 0.0 at every hour of the file */
		CHECK(s.v[CS_VAR_SNOW_FRACTION][180] == 0);
	CHECK_STR_CONTAINS(s.key[CS_VAR_CLOUD_LOW], "data_1h.lowclouds");
	/* solar-1h at "2024-10-13 12:00" (index 180), the _instant values:
	 * ghi 458.11, dni 507.1, dif 167.6 W/m2; totalcloudcover 12 at 179 */
	CHECK(s.v[CS_VAR_GHI] && s.v[CS_VAR_DNI] && s.v[CS_VAR_DHI] &&
	      s.v[CS_VAR_CLOUD_TOTAL]);
	if (s.v[CS_VAR_GHI] && s.v[CS_VAR_DNI] && s.v[CS_VAR_DHI] &&
	    s.v[CS_VAR_CLOUD_TOTAL]) {
		CHECK(s.v[CS_VAR_GHI][180] == 458.11);
		CHECK(s.v[CS_VAR_DNI][180] == 507.1);
		CHECK(s.v[CS_VAR_DHI][180] == 167.6);
		CHECK(s.v[CS_VAR_CLOUD_TOTAL][179] == 12);
	}
	CHECK_STR_CONTAINS(s.key[CS_VAR_DHI], "data_1h.dif_instant");
	cs_series_free(&s);
}

/* Open-Meteo's instant irradiances in W/m2 (the unit as it spells it). */
static void openmeteo_instant_radiation_is_read_in_w_m2(void)
{
	char j[4096];
	snprintf(j, sizeof j, "%s", edited(om_base, "\"is_day\":\"\"",
		 "\"is_day\":\"\",\"shortwave_radiation_instant\":\"W/m\xc2\xb2\","
		 "\"direct_normal_irradiance_instant\":\"W/m\xc2\xb2\","
		 "\"diffuse_radiation_instant\":\"W/m\xc2\xb2\""));
	snprintf(j, sizeof j, "%s", edited(j, "\"is_day\":[0,1]",
		 "\"is_day\":[0,1],\"shortwave_radiation_instant\":[0,612.5],"
		 "\"direct_normal_irradiance_instant\":[0,701.25],"
		 "\"diffuse_radiation_instant\":[0,null]"));
	struct cs_series s;
	CHECK(cs_provider_parse(j, strlen(j), "om", &s) == CS_OK);
	if (s.v[CS_VAR_GHI] && s.v[CS_VAR_DNI] && s.v[CS_VAR_DHI]) {
		CHECK(s.v[CS_VAR_GHI][1] == 612.5 && s.v[CS_VAR_DNI][1] == 701.25);
		CHECK(s.v[CS_VAR_DHI][0] == 0 && isnan(s.v[CS_VAR_DHI][1]));
	} else {
		t_case_failed = 1;
	}
	cs_series_free(&s);
	expect_problem(edited(j, "[0,612.5]", "[0,2500]"),
		       "hourly.shortwave_radiation_instant[1]: 2500 is outside 0..2000");
	expect_problem(edited(j, "\"shortwave_radiation_instant\":\"W/m\xc2\xb2\"",
			      "\"shortwave_radiation_instant\":\"kW/m\xc2\xb2\""),
		       "hourly_units.shortwave_radiation_instant: unit \"kW/m\xc2\xb2\"");
}

static void provider_is_detected_from_content(void)
{
	enum cs_provider p;
	CHECK(cs_provider_detect(mb_base, strlen(mb_base), &p) == CS_OK);
	CHECK(p == CS_PROVIDER_METEOBLUE);
	CHECK(cs_provider_detect(om_base, strlen(om_base), &p) == CS_OK);
	CHECK(p == CS_PROVIDER_OPENMETEO);
	CHECK(cs_provider_detect("{\"a\":1}", 7, &p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "neither a meteoblue nor an Open-Meteo");
	const char *err = "{\"error\":true,\"reason\":\"Boom\"}";
	CHECK(cs_provider_detect(err, strlen(err), &p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "provider error (reason): Boom");
}

static void meteoblue_values_and_wall_times_convert_with_the_offset(void)
{
	struct cs_series s;
	const char *j = edited(mb_base, "\"utc_timeoffset\":0.0", "\"utc_timeoffset\":2.0");
	if (cs_provider_parse(j, strlen(j), "t", &s) != CS_OK) {
		printf("  %s\n", cs_errmsg());
		t_case_failed = 1;
		return;
	}
	CHECK(s.n == 3 && s.provider == CS_PROVIDER_METEOBLUE);
	CHECK_STR_CONTAINS(s.name, "Test");
	CHECK_NEAR(s.utc_offset_s, 7200, 0);
	CHECK_NEAR(s.time_utc[0], utc("2021-06-13T22:00Z"), 0);
	CHECK_NEAR(s.time_utc[2], utc("2021-06-14T00:00Z"), 0);
	CHECK_NEAR(s.v[CS_VAR_PRECIP][2], 1.5, 0);
	CHECK_NEAR(s.v[CS_VAR_CONV_PRECIP][1], 0.25, 0);
	CHECK(s.v[CS_VAR_HUMIDITY] == NULL); /* absent: NULL, not zeros */
	cs_series_free(&s);
	/* fractional-hour zones (Nepal +5:45) */
	j = edited(mb_base, "\"utc_timeoffset\":0.0", "\"utc_timeoffset\":5.75");
	CHECK(cs_provider_parse(j, strlen(j), "t", &s) == CS_OK);
	CHECK_NEAR(s.time_utc[0], utc("2021-06-13T18:15Z"), 0);
	cs_series_free(&s);
}

static void openmeteo_units_offset_and_showers_convert(void)
{
	struct cs_series s;
	if (cs_provider_parse(om_base, strlen(om_base), "om", &s) != CS_OK) {
		printf("  %s\n", cs_errmsg());
		t_case_failed = 1;
		return;
	}
	CHECK(s.provider == CS_PROVIDER_OPENMETEO);
	CHECK_NEAR(s.alt_m, 1134, 0);
	CHECK_NEAR(s.time_utc[0], utc("2023-10-25T03:00Z"), 0);
	CHECK_NEAR(s.v[CS_VAR_WIND_SPEED][0], 10, 1e-12);   /* 36 km/h */
	CHECK_NEAR(s.v[CS_VAR_WIND_SPEED][1], 5, 1e-12);
	CHECK_NEAR(s.v[CS_VAR_TEMPERATURE][0], 10, 1e-12);  /* 50 F */
	CHECK_NEAR(s.v[CS_VAR_TEMPERATURE][1], 40, 1e-12);  /* 104 F */
	CHECK_NEAR(s.v[CS_VAR_CONV_PRECIP][0], 0.5, 0);
	CHECK_NEAR(s.v[CS_VAR_IS_DAY][1], 1, 0);
	CHECK(s.v[CS_VAR_FOG_PROBABILITY] == NULL && s.v[CS_VAR_VISIBILITY] == NULL);
	CHECK_STR_CONTAINS(s.key[CS_VAR_CONV_PRECIP], "hourly.showers");
	cs_series_free(&s);
}

/* Open-Meteo's snowfall is in cm (inch with precipitation_unit=inch). */
static void openmeteo_snowfall_is_read_in_cm(void)
{
	char j[4096];
	snprintf(j, sizeof j, "%s", edited(om_base, "\"is_day\":\"\"",
					    "\"is_day\":\"\",\"snowfall\":\"cm\""));
	snprintf(j, sizeof j, "%s", edited(j, "\"is_day\":[0,1]",
					    "\"is_day\":[0,1],\"snowfall\":[0.7,null]"));
	struct cs_series s;
	CHECK(cs_provider_parse(j, strlen(j), "om", &s) == CS_OK);
	if (s.v[CS_VAR_SNOWFALL] != NULL) {
		CHECK(s.v[CS_VAR_SNOWFALL][0] == 0.7 && isnan(s.v[CS_VAR_SNOWFALL][1]));
		CHECK_STR_CONTAINS(s.key[CS_VAR_SNOWFALL], "hourly.snowfall");
	}
	CHECK(s.v[CS_VAR_SNOWFALL] != NULL && s.v[CS_VAR_SNOW_FRACTION] == NULL);
	cs_series_free(&s);
	snprintf(j, sizeof j, "%s", edited(j, "\"snowfall\":\"cm\"", "\"snowfall\":\"inch\""));
	CHECK(cs_provider_parse(j, strlen(j), "om", &s) == CS_OK);
	if (s.v[CS_VAR_SNOWFALL] != NULL)
		CHECK_NEAR(s.v[CS_VAR_SNOWFALL][0], 0.7 * 2.54, 1e-12);
	cs_series_free(&s);
	snprintf(j, sizeof j, "%s", edited(j, "[0.7,null]", "[-1,null]"));
	CHECK(cs_provider_parse(j, strlen(j), "om", &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "hourly.snowfall[0]: -1 inch");
}

static void openmeteo_legacy_names_and_unixtime_are_read(void)
{
	char j[4096];
	snprintf(j, sizeof j, "%s", edited(om_base, "\"cloud_cover_low\":[", "\"cloudcover_low\":["));
	snprintf(j, sizeof j, "%s", edited(j, "\"cloud_cover_low\":\"%\"", "\"cloudcover_low\":\"%\""));
	snprintf(j, sizeof j, "%s", edited(j, "[\"2023-10-25T00:00\",\"2023-10-25T01:00\"]",
					    "[1698202800,1698206400]"));
	struct cs_series s;
	if (cs_provider_parse(j, strlen(j), "om", &s) != CS_OK) {
		printf("  %s\n", cs_errmsg());
		t_case_failed = 1;
		return;
	}
	/* integers are UTC already: the offset is not applied */
	CHECK_NEAR(s.time_utc[0], 1698202800, 0);
	CHECK_NEAR(s.v[CS_VAR_CLOUD_LOW][0], 40, 0);
	CHECK_STR_CONTAINS(s.key[CS_VAR_CLOUD_LOW], "hourly.cloudcover_low");
	cs_series_free(&s);
}

static void arrays_of_another_length_name_the_field_and_index(void)
{
	expect_problem(edited(mb_base, "[11,21,31]", "[11,21]"),
		       "data_1h.lowclouds: 2 values but time has 3 (index 2 has no value)");
	expect_problem(edited(mb_base, "[1.5,2.5,3.5]", "[1.5,2.5,3.5,4.5]"),
		       "data_1h.windspeed: 4 values but time has 3 (index 3 has no time)");
	/* arrays cloudscape does not read are checked too */
	expect_problem(edited(mb_base, "[\"00\",\"01\",\"02\"]", "[\"00\"]"),
		       "data_1h.rainspot: 1 values but time has 3");
}

static void nulls_are_kept_as_nan_never_zero(void)
{
	const char *j = edited(mb_base, "[11,21,31]", "[11,null,31]");
	struct cs_problems pr;
	CHECK(check(j, &pr) == CS_OK);
	struct cs_series s;
	CHECK(cs_provider_parse(j, strlen(j), "t", &s) == CS_OK);
	CHECK(isnan(s.v[CS_VAR_CLOUD_LOW][1]));
	CHECK_NEAR(s.v[CS_VAR_CLOUD_LOW][2], 31, 0);
	cs_series_free(&s);
	struct cs_series o;
	CHECK(cs_provider_parse(om_base, strlen(om_base), "om", &o) == CS_OK);
	CHECK(isnan(o.v[CS_VAR_CLOUD_LOW][1]));
	cs_series_free(&o);
}

static void time_gaps_repeats_and_bad_times_are_reported(void)
{
	expect_problem(edited(mb_base, "\"2021-06-14 02:00\"", "\"2021-06-14 03:00\""),
		       "data_1h.time[2]: \"2021-06-14 03:00\" is 2 h after time[1] "
		       "\"2021-06-14 01:00\" (expected 1 h steps: hours are missing)");
	expect_problem(edited(mb_base, "\"2021-06-14 02:00\"", "\"2021-06-14 01:00\""),
		       "is 0 h after time[1] \"2021-06-14 01:00\" (expected 1 h steps: "
		       "a repeated hour, as at a daylight-saving change)");
	expect_problem(edited(mb_base, "\"2021-06-14 02:00\"", "\"2021-06-14 00:00\""),
		       "time goes back");
	expect_problem(edited(mb_base, "\"2021-06-14 01:00\"", "\"14.06.2021 01:00\""),
		       "data_1h.time[1]: \"14.06.2021 01:00\" is not a time");
	expect_problem(edited(mb_base, "\"2021-06-14 01:00\"", "\"2021-02-30 01:00\""),
		       "data_1h.time[1]: \"2021-02-30 01:00\" is not a time");
	expect_problem(edited(mb_base, "\"time\":[\"2021-06-14 00:00\",\"2021-06-14 01:00\","
			      "\"2021-06-14 02:00\"]", "\"time\":[]"), "data_1h.time: empty");
}

/* mbfetch's check wants exactly the units it requests (a provider that
 * ignored the request must not pass: km/h would be read as m/s by anyone
 * trusting the request); parsing reads and converts the others. */
static void units_other_than_requested_fail_the_check_but_parse(void)
{
	expect_problem(edited(mb_base, "\"ms-1\"", "\"bft\""),
		       "units.windspeed: unit \"bft\" is not the one cloudscape requests "
		       "(expected \"ms-1\")");
	expect_problem(edited(mb_base, "\"ms-1\"", "\"kn\""),
		       "units.windspeed: unit \"kn\" is not the one cloudscape requests");
	expect_problem(edited(mb_base, "\"degree\"", "\"2char\""),
		       "units.winddirection: unit \"2char\"");
	expect_problem(edited(mb_base, "\"cloudcover\":\"percent\",", ""),
		       "units.cloudcover: missing (the unit of data_1h.lowclouds)");
	expect_problem(om_base, "hourly_units.wind_speed_10m: unit \"km/h\" is not the one "
				"cloudscape requests (expected \"m/s\")");
	/* parsing converts what it can, and still refuses what it cannot */
	struct cs_series s;
	const char *kn = edited(mb_base, "\"ms-1\"", "\"kn\"");
	CHECK(cs_provider_parse(kn, strlen(kn), "kn", &s) == CS_OK);
	if (s.v[CS_VAR_WIND_SPEED])
		CHECK_NEAR(s.v[CS_VAR_WIND_SPEED][0], 1.5 * 1852.0 / 3600.0, 1e-12);
	cs_series_free(&s);
	const char *bft = edited(mb_base, "\"ms-1\"", "\"bft\"");
	CHECK(cs_provider_parse(bft, strlen(bft), "bft", &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "is not one cloudscape reads (expected \"ms-1\", \"kmh\", \"mph\", \"kn\")");
}

static void out_of_range_values_name_field_index_and_value(void)
{
	expect_problem(edited(mb_base, "[11,21,31]", "[11,130,31]"),
		       "data_1h.lowclouds[1]: 130 is outside 0..100");
	expect_problem(edited(mb_base, "[350,10,20]", "[350,10,-5]"),
		       "data_1h.winddirection[2]: -5 is outside 0..360");
	expect_problem(edited(mb_base, "[0.0,0.5,1.5]", "[0.0,-0.5,1.5]"),
		       "data_1h.precipitation[1]: -0.5 is outside 0..500");
	expect_problem(edited(mb_base, "[1,2,3]", "[1,2,300]"),
		       "data_1h.fog_probability[2]: 300 is outside 0..100");
	{ /* in a unit parsing converts, the range is checked after converting */
		struct cs_series s;
		const char *j = edited(om_base, "[36.0,18.0]", "[36.0,400]");
		CHECK(cs_provider_parse(j, strlen(j), "om", &s) == CS_EDATA);
		CHECK_STR_CONTAINS(cs_errmsg(), "hourly.wind_speed_10m[1]: 400 km/h "
				   "(111.1111111 m/s) is outside 0..100 m/s");
	}
	expect_problem(edited(mb_base, "\"latitude\":46.95", "\"latitude\":95"),
		       "metadata.latitude: 95 is outside -90..90");
	expect_problem(edited(mb_base, "[1.5,2.5,3.5]", "[1.5,\"2.5\",3.5]"),
		       "data_1h.windspeed[1]: expected a number or null, not a string");
}

static void provider_error_bodies_are_reported_verbatim(void)
{
	struct cs_problems pr;
	const char *mb = "{\"error_message\":\"MB_REQUEST::DISPATCH: Invalid api key\"}";
	CHECK(check(mb, &pr) == CS_EDATA && pr.count == 1);
	CHECK_STR_CONTAINS(pr.msg[0], "provider error (error_message): "
			   "MB_REQUEST::DISPATCH: Invalid api key");
	const char *om = "{\"reason\":\"Cannot initialize WeatherVariable from invalid "
			 "String value tempeture_2m for key hourly\",\"error\":true}";
	CHECK(check(om, &pr) == CS_EDATA && pr.count == 1);
	CHECK_STR_CONTAINS(pr.msg[0], "provider error (reason): Cannot initialize "
			   "WeatherVariable from invalid String value tempeture_2m for key hourly");
	/* a reason with a newline stays one line */
	CHECK(check("{\"error\":true,\"reason\":\"a\\nb\"}", &pr) == CS_EDATA);
	CHECK_STR_CONTAINS(pr.msg[0], "(reason): a b");
}

static void html_truncated_and_empty_bodies_are_reported(void)
{
	expect_problem("<!DOCTYPE html>\n<html><head><title>502 Bad Gateway</title></head>"
		       "<body>nginx</body></html>", "an HTML page, not JSON: \"502 Bad Gateway\"");
	char half[600];
	snprintf(half, sizeof half, "%.300s", mb_base);
	char msg[128];
	snprintf(msg, sizeof msg, "truncated JSON: the text ends at byte %zu", strlen(half));
	expect_problem(half, msg);
	expect_problem("{\"metadata\":{,}", "malformed JSON at byte offset");
	expect_problem("", "empty response (0 bytes, no JSON)");
	expect_problem(" \n", "empty response");
	expect_problem("[{\"hourly\":{}},{\"hourly\":{}}]", "a list of 2 responses");
	expect_problem("42", "expected a JSON object, not a number");
}

static void missing_objects_and_required_arrays_are_named(void)
{
	expect_problem(edited(mb_base, "\"lowclouds\":[11,21,31],", ""),
		       "data_1h.lowclouds: missing (cloudscape needs it; request basic-1h "
		       "and clouds-1h)");
	expect_problem(edited(om_base, "\"wind_direction_10m\":[90,180],", ""),
		       "hourly.wind_direction_10m: missing (cloudscape needs it; request "
		       "it in &hourly=)");
	expect_problem(edited(mb_base, "\"height\":540,", ""), "metadata.height: missing");
	expect_problem(edited(om_base, "\"utc_offset_seconds\":-10800,", ""),
		       "utc_offset_seconds: missing");
	expect_problem("{\"metadata\":{\"latitude\":1,\"longitude\":2,\"height\":3,"
		       "\"utc_timeoffset\":0},\"units\":{}}", "data_1h: missing");
	expect_problem(edited(mb_base, "\"units\":{", "\"unitz\":{"), "units: missing");
}

static void problems_are_one_line_each_and_all_counted(void)
{
	/* 40 bad values: 32 kept, 40 counted */
	char j[8192] = "{\"metadata\":{\"latitude\":1,\"longitude\":2,\"height\":3,"
		       "\"utc_timeoffset\":0},\"units\":{\"cloudcover\":\"percent\","
		       "\"precipitation\":\"mm\",\"windspeed\":\"ms-1\",\"winddirection\":"
		       "\"degree\"},\"data_1h\":{\"time\":[";
	for (int i = 0; i < 40; i++)
		snprintf(j + strlen(j), sizeof j - strlen(j), "%s\"2021-01-%02d %02d:00\"",
			 i ? "," : "", 1 + i / 24, i % 24);
	strcat(j, "],\"lowclouds\":[");
	for (int i = 0; i < 40; i++)
		strcat(j, i ? ",101" : "101");
	strcat(j, "]}}");
	struct cs_problems pr;
	CHECK(check(j, &pr) == CS_EDATA);
	/* 40 out of range + midclouds, highclouds, precipitation, windspeed,
	 * winddirection missing */
	CHECK(pr.count == 45);
	for (int i = 0; i < 32; i++)
		CHECK(strchr(pr.msg[i], '\n') == NULL && pr.msg[i][0] != '\0');
	CHECK_STR_CONTAINS(pr.msg[0], "data_1h.lowclouds[0]: 101 is outside 0..100");
}

static void parse_error_starts_with_the_name_and_counts_the_rest(void)
{
	const char *j = edited(mb_base, "[11,21,31]", "[11,130,131]");
	struct cs_series s;
	CHECK(cs_provider_parse(j, strlen(j), "site.json", &s) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "site.json: data_1h.lowclouds[1]: 130 is outside "
			   "0..100 (and 1 more problem)");
	CHECK(s.n == 0 && s.time_utc == NULL);
	cs_series_free(&s); /* safe on a failed parse */
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(real_meteoblue_capture_checks_clean_and_parses),
	CASE(provider_is_detected_from_content),
	CASE(meteoblue_values_and_wall_times_convert_with_the_offset),
	CASE(openmeteo_units_offset_and_showers_convert),
	CASE(openmeteo_snowfall_is_read_in_cm),
	CASE(openmeteo_instant_radiation_is_read_in_w_m2),
	CASE(openmeteo_legacy_names_and_unixtime_are_read),
	CASE(arrays_of_another_length_name_the_field_and_index),
	CASE(nulls_are_kept_as_nan_never_zero),
	CASE(time_gaps_repeats_and_bad_times_are_reported),
	CASE(units_other_than_requested_fail_the_check_but_parse),
	CASE(out_of_range_values_name_field_index_and_value),
	CASE(provider_error_bodies_are_reported_verbatim),
	CASE(html_truncated_and_empty_bodies_are_reported),
	CASE(missing_objects_and_required_arrays_are_named),
	CASE(problems_are_one_line_each_and_all_counted),
	CASE(parse_error_starts_with_the_name_and_counts_the_rest),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
