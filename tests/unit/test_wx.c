#include "core/err.h"
#include "test.h"
#include "core/time.h"
#include "weather/wx.h"

#include <ctype.h>
#include <stdlib.h>
#include <unistd.h>

static char tmpdir[256];

static const char *tmp(const char *name)
{
	static char path[512];
	snprintf(path, sizeof path, "%s/%s", tmpdir, name);
	return path;
}

static int write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	if (f == NULL)
		return -1;
	fputs(text, f);
	return fclose(f);
}

/* The example of man 5 cloudwx.  Every value the tests edit is unique in
 * the text, so that one replacement changes exactly one field. */
static const char example[] =
	"{\n"
	"  \"schema\": \"cloudwx/1\",\n"
	"  \"time_utc\": \"2021-06-14T14:00:00Z\",\n"
	"  \"site\": {\"name\": \"Bern\", \"lat_deg\": 46.95, \"lon_deg\": 7.44, "
	"\"alt_m\": 540},\n"
	"  \"layers\": [\n"
	"    {\"genus\": \"cumulus\", \"coverage\": 0.35, \"base_m\": 1500, "
	"\"top_m\": 2700},\n"
	"    {\"genus\": \"cirrus\",  \"coverage\": 0.2,  \"base_m\": 9000, "
	"\"top_m\": 9600}\n"
	"  ],\n"
	"  \"precipitation_mm_h\": 0,\n"
	"  \"convective_mm_h\": 0,\n"
	"  \"wind\": {\"speed_m_s\": 4, \"from_deg\": 250},\n"
	"  \"visibility_m\": 30000,\n"
	"  \"fog_probability\": 0,\n"
	"  \"far\": [\n"
	"    {\"site\": {\"name\": \"Solothurn\", \"lat_deg\": 47.2088, "
	"\"lon_deg\": 7.5323, \"alt_m\": 432},\n"
	"     \"layers\": [{\"genus\": \"stratocumulus\", \"coverage\": 0.6, "
	"\"base_m\": 1200, \"top_m\": 1800}],\n"
	"     \"precipitation_mm_h\": 0.4, \"visibility_m\": 25000}\n"
	"  ]\n"
	"}\n";

/* Parses the example with the first occurrence of from replaced by to;
 * returns the status, or 99 if from is not in the example. */
static int parse_edited(const char *from, const char *to, struct cs_wx *wx)
{
	static char buf[8192];
	const char *at = strstr(example, from);
	if (at == NULL)
		return 99;
	int n = snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - example),
			 example, to, at + strlen(from));
	return cs_wx_parse(buf, (size_t)n, wx);
}

static int parse_str(const char *json, struct cs_wx *wx)
{
	return cs_wx_parse(json, strlen(json), wx);
}

static int same_site(const struct cs_wx_site *a, const struct cs_wx_site *b)
{
	return strcmp(a->name, b->name) == 0 && a->lat_deg == b->lat_deg &&
	       a->lon_deg == b->lon_deg && a->alt_m == b->alt_m;
}

static int same_layers(int n, const struct cs_wx_layer *a,
		       const struct cs_wx_layer *b)
{
	for (int i = 0; i < n; i++)
		if (a[i].genus != b[i].genus || a[i].coverage != b[i].coverage ||
		    a[i].base_m != b[i].base_m || a[i].top_m != b[i].top_m)
			return 0;
	return 1;
}

/* Every field, exactly. */
static int same_wx(const struct cs_wx *a, const struct cs_wx *b)
{
	if (a->time_utc != b->time_utc || !same_site(&a->site, &b->site) ||
	    a->nlayers != b->nlayers ||
	    !same_layers(a->nlayers, a->layers, b->layers) ||
	    a->precipitation_mm_h != b->precipitation_mm_h ||
	    a->convective_mm_h != b->convective_mm_h ||
	    a->wind_speed_m_s != b->wind_speed_m_s ||
	    a->wind_from_deg != b->wind_from_deg ||
	    a->visibility_m != b->visibility_m ||
	    a->fog_probability != b->fog_probability || a->nfar != b->nfar ||
	    a->snow_fraction != b->snow_fraction ||
	    memcmp(&a->observed, &b->observed, sizeof a->observed) != 0 ||
	    !(a->temperature_c == b->temperature_c ||
	      (isnan(a->temperature_c) && isnan(b->temperature_c))))
		return 0;
	for (int i = 0; i < a->nfar; i++) {
		const struct cs_wx_far *p = &a->far[i], *q = &b->far[i];
		if (!same_site(&p->site, &q->site) || p->nlayers != q->nlayers ||
		    !same_layers(p->nlayers, p->layers, q->layers) ||
		    p->precipitation_mm_h != q->precipitation_mm_h ||
		    p->visibility_m != q->visibility_m)
			return 0;
	}
	return 1;
}

static int round_trip(const struct cs_wx *wx, struct cs_wx *back)
{
	char *json = NULL;
	int rc = cs_wx_to_json(wx, &json);
	if (rc == CS_OK) {
		rc = parse_str(json, back);
		if (rc != CS_OK || strchr(json, '\n') != NULL)
			printf("  %s\n  %s\n", json, cs_errmsg());
	}
	free(json);
	return rc;
}

static void default_state_is_the_documented_fair_weather_over_bern(void)
{
	struct cs_wx wx;
	double t;
	cs_wx_default(&wx);
	CHECK(cs_time_parse("2021-06-14T14:00:00Z", &t) == CS_OK);
	CHECK(wx.time_utc == t);
	CHECK(strcmp(wx.site.name, "Bern") == 0);
	CHECK(wx.site.lat_deg == 46.95 && wx.site.lon_deg == 7.44 &&
	      wx.site.alt_m == 540);
	CHECK(wx.nlayers == 2);
	CHECK(wx.layers[0].genus == CS_CUMULUS && wx.layers[0].coverage == 0.35 &&
	      wx.layers[0].base_m == 1500 && wx.layers[0].top_m == 2700);
	CHECK(wx.layers[1].genus == CS_CIRRUS && wx.layers[1].coverage == 0.2 &&
	      wx.layers[1].base_m == 9000 && wx.layers[1].top_m == 9600);
	CHECK(wx.wind_speed_m_s == 4 && wx.wind_from_deg == 250);
	CHECK(wx.visibility_m == 30000);
	CHECK(wx.precipitation_mm_h == 0 && wx.convective_mm_h == 0);
	CHECK(wx.fog_probability == 0 && wx.nfar == 0);
	CHECK(wx.snow_fraction == 0 && isnan(wx.temperature_c));
	CHECK(cs_wx_validate(&wx) == CS_OK);
}

static void default_state_round_trips_through_json_exactly(void)
{
	struct cs_wx wx, back;
	cs_wx_default(&wx);
	memset(&back, 0x5a, sizeof back);
	CHECK(round_trip(&wx, &back) == CS_OK);
	CHECK(same_wx(&wx, &back));
}

static void awkward_state_with_far_sites_round_trips_bit_exactly(void)
{
	struct cs_wx wx, back;
	cs_wx_default(&wx);
	wx.time_utc += 59 * 60 + 7;
	snprintf(wx.site.name, sizeof wx.site.name, "Qu\"o\\te\ttab Zürich");
	wx.site.lat_deg = 46.951234567890123;
	wx.site.lon_deg = -0.1;
	wx.site.alt_m = -12.5;
	wx.layers[0].coverage = 1.0 / 3.0;
	wx.layers[0].base_m = 1500.0000000000002;
	wx.layers[1].coverage = 1e-300;
	wx.precipitation_mm_h = 2.0 / 7.0;
	wx.convective_mm_h = 0.1;
	wx.wind_from_deg = 359.99999999999994;
	wx.visibility_m = 1234.5678;
	wx.fog_probability = 0.7;
	wx.snow_fraction = 1.0 / 3.0;
	wx.temperature_c = -0.1;
	wx.observed = (struct cs_wx_observed){1, 458.11, 507.1, 167.6, 1, 0.12};
	wx.nfar = CS_WX_MAX_FAR;
	for (int i = 0; i < wx.nfar; i++) {
		wx.far[i].site = wx.site;
		wx.far[i].site.lat_deg += i * 0.01;
		wx.far[i].nlayers = i;
		for (int j = 0; j < i; j++)
			wx.far[i].layers[j] = (struct cs_wx_layer){
				(enum cs_genus)((i * 3 + j) % CS_GENUS_COUNT), 0.3 + j * 0.01,
				600.0 * (j + 1), 600.0 * (j + 1) + 10};
		wx.far[i].precipitation_mm_h = 0.01 * i;
		wx.far[i].visibility_m = 1 + i;
	}
	/* written rounded to what each number means (cloudwx(5)); what was
	 * written reads back and is written again bit for bit */
	struct cs_wx again;
	CHECK(round_trip(&wx, &back) == CS_OK);
	CHECK(round_trip(&back, &again) == CS_OK);
	CHECK(same_wx(&back, &again));
	CHECK(strcmp(back.site.name, wx.site.name) == 0);
	CHECK(back.site.lat_deg == 46.951235 && back.layers[0].base_m == 1500);
	CHECK(back.layers[0].coverage == 0.333 && back.layers[1].coverage == 0);
	CHECK(back.precipitation_mm_h == 0.286 && back.visibility_m == 1235);
	CHECK(back.wind_from_deg == 360 && back.temperature_c == -0.1);
	CHECK(back.observed.ghi_w_m2 == 458.11);
}

static void json_is_one_line_with_keys_in_schema_order_and_short_numbers(void)
{
	static const char *const order[] = {
		"\"schema\":\"cloudwx/2\"", "\"time_utc\":\"2021-06-14T14:00:00Z\"",
		"\"site\":{\"name\":\"Bern\",\"lat_deg\":46.95,\"lon_deg\":7.44,"
		"\"alt_m\":540}",
		"\"layers\":[{\"genus\":\"cumulus\",\"coverage\":0.35",
		"\"precipitation_mm_h\":0", "\"convective_mm_h\":0",
		"\"wind\":{\"speed_m_s\":4,\"from_deg\":250}",
		"\"visibility_m\":30000", "\"fog_probability\":0"};
	struct cs_wx wx;
	char *json = NULL;
	cs_wx_default(&wx);
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json == NULL)
		return;
	CHECK(strchr(json, '\n') == NULL);
	CHECK(json[0] == '{' && json[strlen(json) - 1] == '}');
	CHECK(strstr(json, "far") == NULL);
	const char *at = json;
	for (size_t i = 0; i < sizeof order / sizeof *order; i++) {
		const char *next = strstr(at, order[i]);
		if (next == NULL)
			printf("  \"%s\" missing or out of order in %s\n", order[i],
			       json);
		CHECK(next != NULL);
		at = next ? next : at;
	}
	free(json);
	wx.nfar = 1;
	wx.far[0].site = wx.site;
	wx.far[0].visibility_m = 5000;
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json != NULL)
		CHECK_STR_CONTAINS(json, ",\"far\":[{\"site\":{\"name\":\"Bern\"");
	free(json);
}

static void to_json_refuses_a_state_that_does_not_validate(void)
{
	struct cs_wx wx;
	char untouched[] = "untouched", *json = untouched;
	cs_wx_default(&wx);
	wx.layers[1].coverage = 2;
	CHECK(cs_wx_to_json(&wx, &json) == CS_EDATA);
	CHECK(json == NULL);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[1].coverage: 2 is outside 0..1");
}

static void full_example_with_far_site_parses_to_its_values(void)
{
	struct cs_wx wx, def;
	cs_wx_default(&def);
	CHECK(parse_str(example, &wx) == CS_OK);
	/* the example's near part is the default state */
	struct cs_wx near = wx;
	near.nfar = 0;
	CHECK(same_wx(&near, &def));
	CHECK(wx.nfar == 1);
	const struct cs_wx_far *f = &wx.far[0];
	CHECK(strcmp(f->site.name, "Solothurn") == 0);
	CHECK(f->site.lat_deg == 47.2088 && f->site.lon_deg == 7.5323 &&
	      f->site.alt_m == 432);
	CHECK(f->nlayers == 1 && f->layers[0].genus == CS_STRATOCUMULUS);
	CHECK(f->layers[0].coverage == 0.6 && f->layers[0].base_m == 1200 &&
	      f->layers[0].top_m == 1800);
	CHECK(f->precipitation_mm_h == 0.4 && f->visibility_m == 25000);
}

static void minimal_state_gets_the_documented_defaults(void)
{
	struct cs_wx wx;
	memset(&wx, 0x5a, sizeof wx);
	CHECK(parse_str("{\"schema\":\"cloudwx/1\",\"time_utc\":\"2021-06-14T"
			"16:00+02:00\",\"site\":{\"lat_deg\":1,\"lon_deg\":2},"
			"\"layers\":[],\"far\":[{\"site\":{\"lat_deg\":3,"
			"\"lon_deg\":4},\"layers\":[]}]}", &wx) == CS_OK);
	CHECK(wx.time_utc == 1623679200.0);
	CHECK(wx.site.name[0] == '\0' && wx.site.alt_m == 0);
	CHECK(wx.site.lat_deg == 1 && wx.site.lon_deg == 2);
	CHECK(wx.precipitation_mm_h == 0 && wx.convective_mm_h == 0);
	CHECK(wx.wind_speed_m_s == 0 && wx.wind_from_deg == 0);
	CHECK(wx.visibility_m == 30000 && wx.fog_probability == 0);
	CHECK(wx.snow_fraction == 0 && isnan(wx.temperature_c));
	CHECK(wx.nfar == 1 && wx.far[0].site.name[0] == '\0');
	CHECK(wx.far[0].site.alt_m == 0 && wx.far[0].nlayers == 0);
	CHECK(wx.far[0].precipitation_mm_h == 0 &&
	      wx.far[0].visibility_m == 30000);
}

static void empty_layers_is_a_valid_clear_sky(void)
{
	struct cs_wx wx;
	const char *layers = "\"layers\": [\n"
			     "    {\"genus\": \"cumulus\", \"coverage\": 0.35, "
			     "\"base_m\": 1500, \"top_m\": 2700},\n"
			     "    {\"genus\": \"cirrus\",  \"coverage\": 0.2,  "
			     "\"base_m\": 9000, \"top_m\": 9600}\n  ]";
	CHECK(parse_edited(layers, "\"layers\": []", &wx) == CS_OK);
	CHECK(wx.nlayers == 0 && wx.nfar == 1);
}

static void unknown_keys_are_ignored_at_every_level(void)
{
	struct cs_wx wx, ref;
	CHECK(parse_str(example, &ref) == CS_OK);
	CHECK(parse_edited("\"schema\": \"cloudwx/1\",",
			   "\"schema\": \"cloudwx/1\", \"future\": {\"x\": [1, "
			   "null]}, \"schema_note\": \"hi\",", &wx) == CS_OK);
	CHECK(same_wx(&wx, &ref));
	CHECK(parse_edited("\"alt_m\": 540", "\"alt_m\": 540, \"tz\": \"CET\"",
			   &wx) == CS_OK);
	CHECK(parse_edited("\"top_m\": 2700", "\"top_m\": 2700, \"ice\": true",
			   &wx) == CS_OK);
	CHECK(same_wx(&wx, &ref));
}

static void every_genus_name_maps_both_ways_ignoring_case(void)
{
	static const char *const names[CS_GENUS_COUNT] = {
		"cirrus", "cirrocumulus", "cirrostratus", "altocumulus",
		"altostratus", "nimbostratus", "stratocumulus", "stratus",
		"cumulus", "cumulonimbus"};
	for (int g = 0; g < CS_GENUS_COUNT; g++) {
		char mixed[32];
		CHECK(strcmp(cs_genus_name((enum cs_genus)g), names[g]) == 0);
		CHECK(cs_genus_from_name(names[g]) == g);
		for (size_t i = 0; i <= strlen(names[g]); i++)
			mixed[i] = i % 2 ? (char)toupper((unsigned char)names[g][i])
					 : names[g][i];
		CHECK(cs_genus_from_name(mixed) == g);
	}
	CHECK(cs_genus_from_name("cumulous") == -1);
	CHECK(cs_genus_from_name("") == -1);
	CHECK(cs_genus_from_name("cumulus ") == -1);
}

static void genus_in_json_is_case_insensitive_and_unknown_names_are_listed(void)
{
	struct cs_wx wx;
	CHECK(parse_edited("\"cumulus\"", "\"CuMuLoNiMbUs\"", &wx) == CS_OK);
	CHECK(wx.layers[0].genus == CS_CUMULONIMBUS);
	CHECK(parse_edited("\"cirrus\"", "\"NIMBOSTRATUS\"", &wx) == CS_OK);
	CHECK(wx.layers[1].genus == CS_NIMBOSTRATUS);
	CHECK(parse_edited("\"cumulus\"", "\"cumulous\"", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[0].genus: unknown genus "
			   "\"cumulous\" (expected one of cirrus, cirrocumulus, "
			   "cirrostratus, altocumulus, altostratus, nimbostratus, "
			   "stratocumulus, stratus, cumulus, cumulonimbus)");
	CHECK(parse_edited("\"stratocumulus\"", "\"fog\"", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "far[0].layers[0].genus: unknown genus "
			   "\"fog\"");
}

struct edit {
	const char *from, *to, *message;
};

static void check_edits(const struct edit *e, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		struct cs_wx wx;
		int rc = parse_edited(e[i].from, e[i].to, &wx);
		if (rc != CS_EDATA)
			printf("  %s -> %s: status %d\n", e[i].from, e[i].to, rc);
		CHECK(rc == CS_EDATA);
		CHECK_STR_CONTAINS(cs_errmsg(), e[i].message);
	}
}

static void each_range_violation_names_the_field_and_value(void)
{
	static const struct edit e[] = {
		{"46.95", "90.5", "site.lat_deg: 90.5 is outside -90..90"},
		{"46.95", "-91", "site.lat_deg: -91 is outside -90..90"},
		{"7.44", "180.000001", "site.lon_deg: 180.000001 is outside "
		 "-180..180"},
		{"540", "-501", "site.alt_m: -501 is outside -500..9000"},
		{"540", "9001", "site.alt_m: 9001 is outside -500..9000"},
		{"0.35", "-0.01", "layers[0].coverage: -0.01 is outside 0..1"},
		{"0.2,", "1.5,", "layers[1].coverage: 1.5 is outside 0..1"},
		{"1500", "-600", "layers[0].base_m: -600 is outside -500..20000"},
		{"9000", "20001", "layers[1].base_m: 20001 is outside -500..20000"},
		{"2700", "1500", "layers[0].top_m: 1500 is not at least 10 m "
		 "above base_m 1500"},
		{"2700", "1509.5", "layers[0].top_m: 1509.5 is not at least 10 m"},
		{"9600", "20000.5", "layers[1].top_m: 20000.5 is outside "
		 "-500..20000"},
		{"\"precipitation_mm_h\": 0,", "\"precipitation_mm_h\": -1,",
		 "precipitation_mm_h: -1 is outside 0..500"},
		{"\"precipitation_mm_h\": 0,", "\"precipitation_mm_h\": 501,",
		 "precipitation_mm_h: 501 is outside 0..500"},
		{"\"convective_mm_h\": 0", "\"convective_mm_h\": 0.5",
		 "convective_mm_h: 0.5 is outside 0..0"},
		{"\"speed_m_s\": 4", "\"speed_m_s\": -1",
		 "wind.speed_m_s: -1 is outside 0..100"},
		{"\"speed_m_s\": 4", "\"speed_m_s\": 100.5",
		 "wind.speed_m_s: 100.5 is outside 0..100"},
		{"250", "360.5", "wind.from_deg: 360.5 is outside 0..360"},
		{"250", "-1", "wind.from_deg: -1 is outside 0..360"},
		{"30000", "0.5", "visibility_m: 0.5 is outside 1..1000000"},
		{"30000", "1e7", "visibility_m: 10000000 is outside 1..1000000"},
		{"\"fog_probability\": 0", "\"fog_probability\": 1.01",
		 "fog_probability: 1.01 is outside 0..1"},
		{"\"fog_probability\": 0", "\"fog_probability\": -0.5",
		 "fog_probability: -0.5 is outside 0..1"},
		{"47.2088", "-95", "far[0].site.lat_deg: -95 is outside -90..90"},
		{"7.5323", "200", "far[0].site.lon_deg: 200 is outside -180..180"},
		{"432", "9500", "far[0].site.alt_m: 9500 is outside -500..9000"},
		{"0.6", "2", "far[0].layers[0].coverage: 2 is outside 0..1"},
		{"1800", "1200", "far[0].layers[0].top_m: 1200 is not at least"},
		{"0.4", "-0.4", "far[0].precipitation_mm_h: -0.4 is outside 0..500"},
		{"25000", "0", "far[0].visibility_m: 0 is outside 1..1000000"},
		{"\"fog_probability\": 0", "\"fog_probability\": 0, "
		 "\"snow_fraction\": 1.5", "snow_fraction: 1.5 is outside 0..1"},
		{"\"fog_probability\": 0", "\"fog_probability\": 0, "
		 "\"snow_fraction\": -0.1", "snow_fraction: -0.1 is outside 0..1"},
		{"\"fog_probability\": 0", "\"fog_probability\": 0, "
		 "\"temperature_c\": 70.5", "temperature_c: 70.5 is outside -100..70"},
		{"\"fog_probability\": 0", "\"fog_probability\": 0, "
		 "\"temperature_c\": \"cold\"", "temperature_c: expected a finite "
		 "number or null"},
	};
	check_edits(e, sizeof e / sizeof *e);
}

/* snow_fraction is always written; temperature_c only when known, and
 * absent or null reads back as unknown (NaN). */
static void snow_and_temperature_are_written_and_read_back(void)
{
	struct cs_wx wx, back;
	char *json = NULL;
	cs_wx_default(&wx);
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json != NULL) {
		CHECK_STR_CONTAINS(json, "\"fog_probability\":0,\"snow_fraction\":0}");
		CHECK(strstr(json, "temperature") == NULL);
	}
	free(json);
	wx.snow_fraction = 0.25;
	wx.temperature_c = -3.5;
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json != NULL)
		CHECK_STR_CONTAINS(json, "\"snow_fraction\":0.25,\"temperature_c\":-3.5}");
	free(json);
	CHECK(round_trip(&wx, &back) == CS_OK);
	CHECK(back.snow_fraction == 0.25 && back.temperature_c == -3.5);
	CHECK(parse_edited("\"fog_probability\": 0", "\"fog_probability\": 0, "
			   "\"temperature_c\": null, \"snow_fraction\": 1", &back)
	      == CS_OK);
	CHECK(isnan(back.temperature_c) && back.snow_fraction == 1);
	wx.temperature_c = INFINITY;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "temperature_c: ");
}

/* "observed": written only with what the provider had; the radiation keys
 * all three or none; ranges checked. */
static void observed_is_optional_and_written_only_when_known(void)
{
	struct cs_wx wx, back;
	char *json = NULL;
	cs_wx_default(&wx);
	CHECK(!wx.observed.has_radiation && !wx.observed.has_cloud_cover);
	wx.observed.has_cloud_cover = 1;
	wx.observed.total_cloud_cover = 0.5;
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json != NULL) {
		CHECK_STR_CONTAINS(json, ",\"observed\":{\"total_cloud_cover\":0.5}");
		CHECK(strstr(json, "ghi") == NULL);
	}
	free(json);
	CHECK(round_trip(&wx, &back) == CS_OK && same_wx(&wx, &back));
	wx.observed = (struct cs_wx_observed){1, 458.11, 507.1, 167.6, 0, 0};
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	if (json != NULL)
		CHECK_STR_CONTAINS(json, ",\"observed\":{\"ghi_w_m2\":458.11,"
				   "\"dni_w_m2\":507.1,\"dhi_w_m2\":167.6}}");
	free(json);
	CHECK(round_trip(&wx, &back) == CS_OK && same_wx(&wx, &back));
	const char *fog = "\"fog_probability\": 0";
	CHECK(parse_edited(fog, "\"fog_probability\": 0, \"observed\": "
			   "{\"ghi_w_m2\": 100, \"dhi_w_m2\": 100}", &back) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "observed.dni_w_m2: missing (required)");
	CHECK(parse_edited(fog, "\"fog_probability\": 0, \"observed\": "
			   "{\"ghi_w_m2\": 2001, \"dni_w_m2\": 0, \"dhi_w_m2\": 0}",
			   &back) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "observed.ghi_w_m2: 2001 is outside 0..2000");
	CHECK(parse_edited(fog, "\"fog_probability\": 0, \"observed\": "
			   "{\"total_cloud_cover\": 12}", &back) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "observed.total_cloud_cover: 12 is outside 0..1");
	CHECK(parse_edited(fog, "\"fog_probability\": 0, \"observed\": []",
			   &back) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "observed: expected an object");
	CHECK(parse_edited(fog, "\"fog_probability\": 0, \"observed\": {}",
			   &back) == CS_OK);
	CHECK(!back.observed.has_radiation && !back.observed.has_cloud_cover);
}

static void range_limits_themselves_are_accepted(void)
{
	static const char *const e[][2] = {
		{"46.95", "-90"}, {"7.44", "180"}, {"540", "9000"},
		{"0.35", "1"}, {"1500", "-500"}, {"2700", "1510"},
		{"9600", "20000"}, {"250", "360"}, {"30000", "1e6"},
		{"\"fog_probability\": 0", "\"fog_probability\": 1"},
		{"25000", "1"}, {"\"precipitation_mm_h\": 0,",
				  "\"precipitation_mm_h\": 500,"},
	};
	for (size_t i = 0; i < sizeof e / sizeof *e; i++) {
		struct cs_wx wx;
		int rc = parse_edited(e[i][0], e[i][1], &wx);
		if (rc != CS_OK)
			printf("  %s -> %s: %s\n", e[i][0], e[i][1], cs_errmsg());
		CHECK(rc == CS_OK);
	}
}

static void validate_rejects_nan_and_impossible_counts_in_a_struct(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.layers[0].coverage = NAN;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[0].coverage: nan is outside");
	cs_wx_default(&wx);
	wx.layers[1].top_m = NAN;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[1].top_m: nan");
	cs_wx_default(&wx);
	wx.time_utc = INFINITY;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "time_utc:");
	cs_wx_default(&wx);
	wx.nlayers = CS_WX_MAX_LAYERS + 1;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers: 9 layers, at most 8");
	cs_wx_default(&wx);
	wx.nfar = -1;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	cs_wx_default(&wx);
	wx.layers[0].genus = CS_GENUS_COUNT;
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[0].genus:");
	cs_wx_default(&wx);
	memset(wx.site.name, 'x', sizeof wx.site.name);
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "site.name:");
}

static void missing_required_fields_are_named(void)
{
	static const struct edit e[] = {
		{"\"schema\"", "\"schemo\"", "schema: missing"},
		{"\"time_utc\"", "\"time\"", "time_utc: missing"},
		{"\"site\": {\"name\": \"Bern\"", "\"place\": {\"name\": \"Bern\"",
		 "site: missing"},
		{"\"lat_deg\": 46.95", "\"lat\": 46.95", "site.lat_deg: missing"},
		{"\"lon_deg\": 7.44", "\"lon\": 7.44", "site.lon_deg: missing"},
		{"\"layers\": [\n", "\"clouds\": [\n", "layers: missing"},
		{"\"genus\": \"cirrus\"", "\"kind\": \"cirrus\"",
		 "layers[1].genus: missing"},
		{"\"coverage\": 0.35", "\"cover\": 0.35",
		 "layers[0].coverage: missing"},
		{"\"base_m\": 1500", "\"base\": 1500", "layers[0].base_m: missing"},
		{"\"top_m\": 2700", "\"top\": 2700", "layers[0].top_m: missing"},
		{"\"from_deg\"", "\"from\"", "wind.from_deg: missing"},
		{"\"speed_m_s\"", "\"speed\"", "wind.speed_m_s: missing"},
		{"{\"site\": {\"name\": \"Solothurn\"",
		 "{\"place\": {\"name\": \"Solothurn\"", "far[0].site: missing"},
		{"\"lat_deg\": 47.2088", "\"lat\": 47.2088",
		 "far[0].site.lat_deg: missing"},
		{"\"layers\": [{", "\"clouds\": [{", "far[0].layers: missing"},
	};
	check_edits(e, sizeof e / sizeof *e);
}

static void wrong_json_types_are_named(void)
{
	static const struct edit e[] = {
		{"\"cloudwx/1\"", "1", "schema: expected a string"},
		{"\"2021-06-14T14:00:00Z\"", "1623679200",
		 "time_utc: expected a string"},
		{"\"site\": {", "\"site\": [], \"x\": {", "site: expected an object"},
		{"\"Bern\"", "null", "site.name: expected a string"},
		{"46.95", "\"46.95\"", "site.lat_deg: expected a number"},
		{"7.44", "true", "site.lon_deg: expected a number"},
		{"540", "[540]", "site.alt_m: expected a number"},
		{"\"layers\": [\n", "\"layers\": {}, \"x\": [\n",
		 "layers: expected an array"},
		{"\"layers\": [\n", "\"layers\": [3,\n",
		 "layers[0]: expected an object"},
		{"\"cumulus\"", "8", "layers[0].genus: expected a string"},
		{"0.35", "\"0.35\"", "layers[0].coverage: expected a number"},
		{"\"precipitation_mm_h\": 0,", "\"precipitation_mm_h\": \"0\",",
		 "precipitation_mm_h: expected a number"},
		{"{\"speed_m_s\": 4, \"from_deg\": 250}", "250",
		 "wind: expected an object"},
		{"30000", "null", "visibility_m: expected a number"},
		{"\"fog_probability\": 0", "\"fog_probability\": false",
		 "fog_probability: expected a number"},
		{"\"far\": [", "\"far\": {}, \"x\": [", "far: expected an array"},
		{"\"far\": [", "\"far\": [\"Solothurn\", ",
		 "far[0]: expected an object"},
		{"0.4", "\"0.4\"", "far[0].precipitation_mm_h: expected a number"},
		{"1500", "1e999", "layers[0].base_m: expected a finite number"},
		{"\"2021-06-14T14:00:00Z\"", "\"2021-06-14T14:00:00\"",
		 "time_utc: '2021-06-14T14:00:00' is not an ISO 8601"},
		{"\"2021-06-14T14:00:00Z\"", "\"2021-06-31T14:00:00Z\"",
		 "time_utc: '2021-06-31T14:00:00Z' is not an ISO 8601"},
	};
	check_edits(e, sizeof e / sizeof *e);
}

static void site_name_longer_than_63_bytes_is_an_error(void)
{
	struct cs_wx wx;
	char name[80];
	memset(name, 'n', 66);
	name[0] = name[65] = '"';
	name[66] = '\0';
	CHECK(parse_edited("\"Bern\"", name, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "site.name: longer than 63 bytes");
	name[64] = '"';
	name[65] = '\0';
	CHECK(parse_edited("\"Bern\"", name, &wx) == CS_OK);
	CHECK(strlen(wx.site.name) == 63);
}

static void malformed_json_says_where(void)
{
	struct cs_wx wx;
	/* truncated in the middle of the layers */
	CHECK(cs_wx_parse(example, 200, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "malformed JSON at byte offset ");
	CHECK_STR_CONTAINS(cs_errmsg(), "(end of input)");
	/* garbage inside the object, at byte offset 24 */
	CHECK(parse_str("{\"schema\": \"cloudwx/1\", x, \"time_utc\": 0}", &wx) ==
	      CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "malformed JSON at byte offset ");
	CHECK_STR_CONTAINS(cs_errmsg(), "near \"udwx/1\", x, \"time_utc\": 0}\"");
	/* cJSON reports the x itself or the byte after it */
	const char *off = strstr(cs_errmsg(), "offset ");
	CHECK(off != NULL && (atoi(off + 7) == 24 || atoi(off + 7) == 25));
	CHECK(parse_str("{\"schema\": \"cloudwx/1\",}", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "malformed JSON at byte offset");
	CHECK(parse_str("", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "empty input");
	CHECK(parse_str(" \n\t", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "empty input");
	CHECK(parse_str("[1, 2]", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "expected a JSON object");
	CHECK(cs_wx_parse("{\"a\":\0}", 7, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "NUL byte at byte offset 5");
}

static void text_after_the_object_is_an_error_in_a_string(void)
{
	struct cs_wx wx;
	char buf[4096];
	snprintf(buf, sizeof buf, "%s}", example);
	CHECK(parse_str(buf, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "unexpected text after the JSON object "
			   "at byte offset");
	snprintf(buf, sizeof buf, "%s%s", example, example);
	CHECK(parse_str(buf, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "unexpected text after the JSON object");
}

static void wrong_schema_version_is_named(void)
{
	struct cs_wx wx;
	CHECK(parse_edited("cloudwx/1", "cloudwx/3", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "schema: unsupported version "
			   "\"cloudwx/3\" (this program reads \"cloudwx/2\" and "
			   "\"cloudwx/1\")");
	CHECK(parse_edited("cloudwx/1", "CLOUDWX/1", &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "\"CLOUDWX/1\"");
}

/* The example with its (near) layers array replaced by n stratus layers. */
static int parse_with_layers(int n, struct cs_wx *wx)
{
	char layers[2048] = "\"layers\": [", buf[8192];
	for (int i = 0; i < n; i++)
		snprintf(layers + strlen(layers), sizeof layers - strlen(layers),
			 "%s{\"genus\":\"stratus\",\"coverage\":0.1,\"base_m\":%d,"
			 "\"top_m\":%d}", i ? "," : "", 100 * i, 100 * i + 50);
	const char *from = strstr(example, "\"layers\": [");
	const char *to = strstr(from, "],") + 1;
	int len = snprintf(buf, sizeof buf, "%.*s%s]%s", (int)(from - example),
			   example, layers, to);
	return cs_wx_parse(buf, (size_t)len, wx);
}

static void eight_layers_are_allowed_nine_are_too_many(void)
{
	struct cs_wx wx;
	CHECK(parse_with_layers(CS_WX_MAX_LAYERS, &wx) == CS_OK);
	CHECK(wx.nlayers == CS_WX_MAX_LAYERS);
	CHECK(wx.layers[7].base_m == 700 && wx.layers[7].genus == CS_STRATUS);
	CHECK(parse_with_layers(CS_WX_MAX_LAYERS + 1, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers: 9 layers, at most 8");
}

static void five_far_sites_are_too_many(void)
{
	struct cs_wx wx;
	const char *site = "{\"site\":{\"lat_deg\":47,\"lon_deg\":8},\"layers\":[]}";
	char far[1024] = "\"far\": [";
	for (int i = 0; i < CS_WX_MAX_FAR; i++)
		snprintf(far + strlen(far), sizeof far - strlen(far), "%s, ", site);
	CHECK(parse_edited("\"far\": [", far, &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "far: 5 sites, at most 4");
	far[strlen(far) - strlen(site) - 2] = '\0';
	CHECK(parse_edited("\"far\": [", far, &wx) == CS_OK);
	CHECK(wx.nfar == CS_WX_MAX_FAR && wx.far[0].site.lat_deg == 47);
	CHECK(strcmp(wx.far[3].site.name, "Solothurn") == 0);
}

static void failed_parse_leaves_the_state_untouched(void)
{
	struct cs_wx wx, before;
	cs_wx_default(&wx);
	before = wx;
	CHECK(parse_edited("0.35", "7", &wx) == CS_EDATA);
	CHECK(same_wx(&wx, &before));
}

static void read_gives_the_first_line_of_json_lines(void)
{
	struct cs_wx a, b, wx;
	char *ja = NULL, *jb = NULL, text[8192];
	cs_wx_default(&a);
	b = a;
	b.time_utc += 60;
	b.layers[0].coverage = 0.9;
	CHECK(cs_wx_to_json(&a, &ja) == CS_OK && cs_wx_to_json(&b, &jb) == CS_OK);
	if (ja == NULL || jb == NULL)
		return;
	snprintf(text, sizeof text, "\n \r\n%s\r\n%s\n", ja, jb);
	CHECK(write_file(tmp("lapse.jsonl"), text) == 0);
	CHECK(cs_wx_read(tmp("lapse.jsonl"), &wx) == CS_OK);
	CHECK(same_wx(&wx, &a));
	/* the same text is not one JSON object */
	CHECK(parse_str(text, &wx) == CS_EDATA);
	/* but text on the first line after the object is */
	snprintf(text, sizeof text, "%s %s\n", ja, jb);
	CHECK(write_file(tmp("bad.jsonl"), text) == 0);
	CHECK(cs_wx_read(tmp("bad.jsonl"), &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "unexpected text after the JSON object");
	free(ja);
	free(jb);
}

static void read_takes_a_multi_line_object(void)
{
	struct cs_wx wx;
	CHECK(write_file(tmp("wx.json"), example) == 0);
	CHECK(cs_wx_read(tmp("wx.json"), &wx) == CS_OK);
	CHECK(wx.nfar == 1 && wx.far[0].visibility_m == 25000);
}

static void read_errors_start_with_the_file_name(void)
{
	struct cs_wx wx;
	char want[600];
	CHECK(write_file(tmp("bad.json"), "{\"schema\": \"cloudwx/1\",\n"
			 "\"time_utc\": \"2021-06-14T14:00Z\", \"site\": "
			 "{\"lat_deg\": 0, \"lon_deg\": 0}, \"layers\": [{\"genus\":"
			 " \"stratus\", \"coverage\": 1.5, \"base_m\": 0, "
			 "\"top_m\": 100}]}") == 0);
	CHECK(cs_wx_read(tmp("bad.json"), &wx) == CS_EDATA);
	snprintf(want, sizeof want, "%s: layers[0].coverage: 1.5 is outside 0..1",
		 tmp("bad.json"));
	CHECK(strcmp(cs_errmsg(), want) == 0);
	CHECK(write_file(tmp("empty.json"), "") == 0);
	CHECK(cs_wx_read(tmp("empty.json"), &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), tmp("empty.json"));
}

static void read_of_a_missing_file_names_the_file(void)
{
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("no-such-wx.json"), &wx) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), tmp("no-such-wx.json"));
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(default_state_is_the_documented_fair_weather_over_bern),
	CASE(default_state_round_trips_through_json_exactly),
	CASE(awkward_state_with_far_sites_round_trips_bit_exactly),
	CASE(json_is_one_line_with_keys_in_schema_order_and_short_numbers),
	CASE(to_json_refuses_a_state_that_does_not_validate),
	CASE(full_example_with_far_site_parses_to_its_values),
	CASE(minimal_state_gets_the_documented_defaults),
	CASE(empty_layers_is_a_valid_clear_sky),
	CASE(unknown_keys_are_ignored_at_every_level),
	CASE(every_genus_name_maps_both_ways_ignoring_case),
	CASE(genus_in_json_is_case_insensitive_and_unknown_names_are_listed),
	CASE(each_range_violation_names_the_field_and_value),
	CASE(range_limits_themselves_are_accepted),
	CASE(snow_and_temperature_are_written_and_read_back),
	CASE(observed_is_optional_and_written_only_when_known),
	CASE(validate_rejects_nan_and_impossible_counts_in_a_struct),
	CASE(missing_required_fields_are_named),
	CASE(wrong_json_types_are_named),
	CASE(site_name_longer_than_63_bytes_is_an_error),
	CASE(malformed_json_says_where),
	CASE(text_after_the_object_is_an_error_in_a_string),
	CASE(wrong_schema_version_is_named),
	CASE(eight_layers_are_allowed_nine_are_too_many),
	CASE(five_far_sites_are_too_many),
	CASE(failed_parse_leaves_the_state_untouched),
	CASE(read_gives_the_first_line_of_json_lines),
	CASE(read_takes_a_multi_line_object),
	CASE(read_errors_start_with_the_file_name),
	CASE(read_of_a_missing_file_names_the_file),
};

int main(void)
{
	snprintf(tmpdir, sizeof tmpdir, "%s/cs-test-wx.XXXXXX",
		 getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
	if (mkdtemp(tmpdir) == NULL) {
		perror("mkdtemp");
		return 1;
	}
	T_RUN_TABLE(t_cases);
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		return 1;
	TEST_EXIT();
}
