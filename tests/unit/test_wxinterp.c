#include "render/cloud.h"
#include "core/err.h"
#include "core/fileio.h"
#include "core/json.h"
#include "test.h"
#include "core/time.h"
#include "apps/wxinterp_run.h"
#include "weather/wxset.h"
#include "astro/sun.h"
#include "core/vec.h"

#include <cjson/cJSON.h>
#include <stdlib.h>
#include <unistd.h>

static char tmpdir[256];

static const char *tmp(const char *name)
{
	/* a ring of buffers: options keep the pointers for a while */
	static char path[16][512];
	static int k;
	k = (k + 1) % 16;
	snprintf(path[k], sizeof path[k], "%s/%s", tmpdir, name);
	return path[k];
}

static const char *real_path(void)
{
	static char path[1024];
	const char *data = getenv("DATA");
	snprintf(path, sizeof path, "%s/weather/meteoblue-basic-clouds-solar-1h.json",
		 data && data[0] ? data : "../shared/data");
	return path;
}

static double utc(const char *s)
{
	double t = NAN;
	cs_time_parse(s, &t);
	return t;
}

/* A series at Bern of n hours from 2021-06-14T00:00Z, no variables yet. */
static void make_series(struct cs_series *s, int n, const char *start)
{
	memset(s, 0, sizeof *s);
	s->n = n;
	s->lat_deg = 46.95;
	s->lon_deg = 7.44;
	s->alt_m = 540;
	s->time_utc = malloc((size_t)n * sizeof *s->time_utc);
	for (int i = 0; i < n; i++)
		s->time_utc[i] = utc(start ? start : "2021-06-14T00:00Z") + 3600.0 * i;
}

static void set_var(struct cs_series *s, enum cs_wxvar k, const double *v)
{
	s->v[k] = malloc((size_t)s->n * sizeof *s->v[k]);
	memcpy(s->v[k], v, (size_t)s->n * sizeof *v);
	snprintf(s->key[k], sizeof s->key[k], "data_1h.var%d", (int)k);
}

/* ---- interpolation against the real capture ----------------------------- */

static const struct {
	const char *key;
	enum cs_wxvar var;
} real_vars[] = {
	{"lowclouds", CS_VAR_CLOUD_LOW}, {"midclouds", CS_VAR_CLOUD_MID},
	{"highclouds", CS_VAR_CLOUD_HIGH}, {"precipitation", CS_VAR_PRECIP},
	{"convective_precipitation", CS_VAR_CONV_PRECIP},
	{"windspeed", CS_VAR_WIND_SPEED}, {"winddirection", CS_VAR_WIND_FROM},
	{"visibility", CS_VAR_VISIBILITY}, {"fog_probability", CS_VAR_FOG_PROBABILITY},
	{"temperature", CS_VAR_TEMPERATURE}, {"relativehumidity", CS_VAR_HUMIDITY},
	{"snowfraction", CS_VAR_SNOW_FRACTION},
};
#define NREAL ((int)(sizeof real_vars / sizeof *real_vars))

/* The capture as parsed by the library and, independently, by cJSON. */
static int load_real(struct cs_series *s, cJSON **root)
{
	unsigned char *data;
	size_t len;
	if (cs_read_all(real_path(), 1 << 24, &data, &len) != CS_OK)
		return 0;
	*root = cJSON_ParseWithLength((char *)data, len);
	free(data);
	if (cs_series_read(real_path(), s) != CS_OK) {
		printf("  %s\n", cs_errmsg());
		t_case_failed = 1;
	}
	return 1;
}

static void real_data_at_exact_hours_equals_the_file(void)
{
	struct cs_series s;
	cJSON *root = NULL;
	if (!load_real(&s, &root))
		SKIP("%.200s is absent (the shared data folder is not here)", real_path());
	const cJSON *d = cJSON_GetObjectItem(root, "data_1h");
	int checked = 0;
	for (size_t k = 0; k < sizeof real_vars / sizeof *real_vars; k++) {
		const cJSON *arr = cJSON_GetObjectItem(d, real_vars[k].key);
		CHECK(cJSON_GetArraySize(arr) == 193);
		for (int i = 0; i < cJSON_GetArraySize(arr) && i < s.n; i++) {
			double v = NAN, want = cJSON_GetArrayItem(arr, i)->valuedouble;
			CHECK(cs_series_value(&s, real_vars[k].var, s.time_utc[i],
					      10800, &v) == CS_OK);
			if (v != want) {
				printf("  %s[%d] = %.17g, file %.17g\n",
				       real_vars[k].key, i, v, want);
				t_case_failed = 1;
			}
			checked++;
		}
	}
	CHECK(checked == NREAL * 193);
	/* and the state: coverage = percent / 100 at 2024-10-06T07:00Z */
	struct cs_wx_obs o;
	CHECK(cs_series_obs(&s, utc("2024-10-06T07:00Z"), 10800, &o) == CS_OK);
	CHECK(o.low == 64 / 100.0 && o.mid == 0 && o.high == 41 / 100.0);
	CHECK(o.wind_speed_m_s == 4.09 && o.wind_from_deg == 119);
	CHECK(o.visibility_m == 9460 && o.fog_probability == 6 / 100.0);
	cs_series_free(&s);
	cJSON_Delete(root);
}

static void real_data_half_way_is_the_mean(void)
{
	struct cs_series s;
	cJSON *root = NULL;
	if (!load_real(&s, &root))
		SKIP("%.200s is absent (the shared data folder is not here)", real_path());
	const cJSON *d = cJSON_GetObjectItem(root, "data_1h");
	for (size_t k = 0; k < sizeof real_vars / sizeof *real_vars; k++) {
		const cJSON *arr = cJSON_GetObjectItem(d, real_vars[k].key);
		for (int i = 0; i + 1 < s.n; i++) {
			double a = cJSON_GetArrayItem(arr, i)->valuedouble;
			double b = cJSON_GetArrayItem(arr, i + 1)->valuedouble;
			double want = (a + b) / 2, v = NAN;
			if (real_vars[k].var == CS_VAR_WIND_FROM && fabs(b - a) > 180)
				want = fmod(want + 180, 360); /* the short way */
			CHECK(cs_series_value(&s, real_vars[k].var,
					      s.time_utc[i] + 1800, 10800, &v) == CS_OK);
			if (!(fabs(v - want) <= 1e-9 * fmax(1, fabs(want)))) {
				printf("  %s between %d and %d: %.17g, mean %.17g\n",
				       real_vars[k].key, i, i + 1, v, want);
				t_case_failed = 1;
			}
		}
	}
	/* a quarter of the way, on one known pair: lowclouds 43 -> 30 */
	double v;
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, utc("2024-10-06T05:15Z"), 10800,
			      &v) == CS_OK);
	CHECK_NEAR(v, 43 + 0.25 * (30 - 43), 1e-12);
	cs_series_free(&s);
	cJSON_Delete(root);
}

/* ---- crafted series ------------------------------------------------------- */

/* The state's snow fraction: the provider's (meteoblue), else Open-Meteo's
 * snowfall as water (7 cm = 10 mm) over the precipitation, else by the
 * temperature rule (snow <= 0.5 C, rain >= 2.5 C), else none. */
static void snow_fraction_comes_from_the_best_source_there_is(void)
{
	static const double zero[3] = {0, 0, 0}, wind[3] = {3, 3, 3};
	static const double precip[3] = {10, 10, 0}, snowfall[3] = {3.5, 7, 0};
	static const double mb_snow[3] = {0, 0.5, 1}, temp[3] = {1.5, 1.5, 1.0};
	struct cs_series s;
	struct cs_wx_obs o;
	double t0 = utc("2021-06-14T00:00Z");
	make_series(&s, 3, NULL);
	set_var(&s, CS_VAR_CLOUD_LOW, zero);
	set_var(&s, CS_VAR_CLOUD_MID, zero);
	set_var(&s, CS_VAR_CLOUD_HIGH, zero);
	set_var(&s, CS_VAR_WIND_SPEED, wind);
	set_var(&s, CS_VAR_WIND_FROM, wind);
	set_var(&s, CS_VAR_PRECIP, precip);
	/* nothing about snow or temperature: none */
	CHECK(cs_series_obs(&s, t0, 10800, &o) == CS_OK);
	CHECK(o.snow_fraction == 0);
	/* the temperature rule: 1.5 C is half way from 2.5 to 0.5 */
	set_var(&s, CS_VAR_TEMPERATURE, temp);
	CHECK(cs_series_obs(&s, t0, 10800, &o) == CS_OK);
	CHECK_NEAR(o.snow_fraction, 0.5, 1e-12);
	/* Open-Meteo snowfall: 3.5 cm is 5 mm of water of the 10 mm; at
	 * 00:30 5.25 cm (7.5 mm) of 10 mm; dry at 02:00: the rule (1 C) */
	set_var(&s, CS_VAR_SNOWFALL, snowfall);
	CHECK(cs_series_obs(&s, t0, 10800, &o) == CS_OK);
	CHECK_NEAR(o.snow_fraction, 0.5, 1e-12);
	CHECK(cs_series_obs(&s, t0 + 1800, 10800, &o) == CS_OK);
	CHECK_NEAR(o.snow_fraction, 0.75, 1e-12);
	CHECK(cs_series_obs(&s, t0 + 7200, 10800, &o) == CS_OK);
	CHECK_NEAR(o.snow_fraction, 0.75, 1e-12);
	/* the provider's own fraction wins, interpolated */
	set_var(&s, CS_VAR_SNOW_FRACTION, mb_snow);
	CHECK(cs_series_obs(&s, t0 + 5400, 10800, &o) == CS_OK);
	CHECK_NEAR(o.snow_fraction, 0.75, 1e-12);
	CHECK(cs_series_obs(&s, t0, 10800, &o) == CS_OK);
	CHECK(o.snow_fraction == 0);
	cs_series_free(&s);
}

/* wxinterp on the capture: snow_fraction and temperature_c of the state
 * are the file's snowfraction and temperature at that hour. */
static void real_data_state_has_the_files_snow_and_temperature(void)
{
	struct cs_series s;
	cJSON *root = NULL;
	if (!load_real(&s, &root))
		SKIP("%.200s is absent (the shared data folder is not here)", real_path());
	cs_series_free(&s);
	const cJSON *d = cJSON_GetObjectItem(root, "data_1h");
	const cJSON *times = cJSON_GetObjectItem(d, "time");
	int i = 0;
	while (i < cJSON_GetArraySize(times) &&
	       strcmp(cJSON_GetArrayItem(times, i)->valuestring, "2024-10-13 12:00"))
		i++;
	double want_t = cJSON_GetArrayItem(cJSON_GetObjectItem(d, "temperature"),
					   i)->valuedouble;
	double want_s = cJSON_GetArrayItem(cJSON_GetObjectItem(d, "snowfraction"),
					   i)->valuedouble;
	cJSON_Delete(root);
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = real_path();
	o.have_at = 1;
	o.at_utc = utc("2024-10-13T12:00Z"); /* the file's offset is GMT */
	o.output = tmp("real.json");
	CHECK(cs_wxinterp_run(&o, &res) == CS_OK);
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("real.json"), &wx) == CS_OK);
	CHECK(wx.temperature_c == want_t && want_t == 16.21);
	CHECK(wx.snow_fraction == want_s);
}

/* The value of key at "2024-10-13 12:00" + hour hours in the capture. */
static double file_at(const cJSON *d, const char *key, int hour)
{
	const cJSON *times = cJSON_GetObjectItem(d, "time");
	int i = 0;
	while (i < cJSON_GetArraySize(times) &&
	       strcmp(cJSON_GetArrayItem(times, i)->valuestring, "2024-10-13 12:00"))
		i++;
	const cJSON *v = cJSON_GetArrayItem(cJSON_GetObjectItem(d, key), i + hour);
	return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* The capture's solar-1h _instant values and total cover come through to
 * the state's "observed" unchanged at the hour, as the mean half way, and
 * they close GHI = DNI cos(zenith) + DHI with the sun at that time. */
static void real_data_observed_radiation_equals_the_file(void)
{
	struct cs_series s;
	cJSON *root = NULL;
	if (!load_real(&s, &root))
		SKIP("%.200s is absent (the shared data folder is not here)", real_path());
	cs_series_free(&s);
	const cJSON *d = cJSON_GetObjectItem(root, "data_1h");
	const char *keys[4] = {"ghi_instant", "dni_instant", "dif_instant",
			       "totalcloudcover"};
	double want[2][4];
	for (int h = 0; h < 2; h++)
		for (int k = 0; k < 4; k++)
			want[h][k] = file_at(d, keys[k], h);
	cJSON_Delete(root);
	CHECK(want[0][0] == 458.11); /* looked up by hand too */
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = real_path();
	o.have_from = o.have_to = 1;
	o.from_utc = utc("2024-10-13T12:00Z");
	o.to_utc = utc("2024-10-13T12:30Z");
	o.step_s = 1800;
	o.output = tmp("observed.jsonl");
	CHECK(cs_wxinterp_run(&o, &res) == CS_OK && res.nstates == 2);
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("observed.jsonl"), &wx) == CS_OK);
	const struct cs_wx_observed *ob = &wx.observed;
	CHECK(ob->has_radiation && ob->has_cloud_cover);
	CHECK(ob->ghi_w_m2 == want[0][0] && ob->dni_w_m2 == want[0][1] &&
	      ob->dhi_w_m2 == want[0][2]);
	CHECK(ob->total_cloud_cover == want[0][3] / 100);
	struct cs_sun sun;
	CHECK(cs_sun_position(wx.time_utc, wx.site.lat_deg, wx.site.lon_deg,
			      &sun) == CS_OK);
	double closure = ob->dni_w_m2 * sin(sun.elevation_deg * CS_PI / 180) +
			 ob->dhi_w_m2;
	printf("  12:00Z: GHI %g, DNI cos z + DHI %.1f (sun %.2f deg)\n",
	       ob->ghi_w_m2, closure, sun.elevation_deg);
	CHECK_NEAR(closure / ob->ghi_w_m2, 1, 0.005);
	/* the second line: 12:30Z, half way */
	char *text = NULL;
	size_t len = 0;
	CHECK(cs_read_all(tmp("observed.jsonl"), 1 << 20, (unsigned char **)&text,
			  &len) == CS_OK);
	const char *line2 = text ? memchr(text, '\n', len) : NULL;
	CHECK(line2 != NULL);
	if (line2 != NULL) {
		line2++;
		CHECK(cs_wx_parse(line2, len - (size_t)(line2 - text), &wx) == CS_OK);
		/* written to 0.01 W/m^2 and 0.001 of cover (cloudwx(5)) */
		CHECK_NEAR(wx.observed.ghi_w_m2, (want[0][0] + want[1][0]) / 2, 0.005);
		CHECK_NEAR(wx.observed.dni_w_m2, (want[0][1] + want[1][1]) / 2, 0.005);
		CHECK_NEAR(wx.observed.dhi_w_m2, (want[0][2] + want[1][2]) / 2, 0.005);
		CHECK_NEAR(wx.observed.total_cloud_cover,
			   (want[0][3] + want[1][3]) / 200, 0.0005);
	}
	free(text);
}

static void wind_direction_across_north_passes_through_zero(void)
{
	struct cs_series s;
	make_series(&s, 3, NULL);
	set_var(&s, CS_VAR_WIND_FROM, (double[]){350, 10, 350});
	double t0 = s.time_utc[0], v;
	const double at[] = {0, 900, 1800, 2700, 3600, 4500, 5400, 6300};
	const double want[] = {350, 355, 0, 5, 10, 5, 0, 355};
	for (int i = 0; i < 8; i++) {
		CHECK(cs_series_value(&s, CS_VAR_WIND_FROM, t0 + at[i], 10800, &v) == CS_OK);
		CHECK_NEAR(v, want[i], 1e-9);
		CHECK(v >= 0 && v < 360);
	}
	/* opposite directions turn one fixed way; 90 -> 270 never gives 180 +- 90 */
	memcpy(s.v[CS_VAR_WIND_FROM], (double[]){90, 270, 0}, 3 * sizeof(double));
	CHECK(cs_series_value(&s, CS_VAR_WIND_FROM, t0 + 1800, 10800, &v) == CS_OK);
	CHECK(fabs(v - 0) < 1e-9 || fabs(v - 180) < 1e-9);
	cs_series_free(&s);
}

static void null_is_bridged_within_max_gap_and_reported_beyond(void)
{
	struct cs_series s;
	make_series(&s, 8, NULL);
	set_var(&s, CS_VAR_CLOUD_LOW, (double[]){10, NAN, NAN, 40, NAN, NAN, NAN, 80});
	double t0 = s.time_utc[0], v;
	/* 00:00 and 03:00 are 3 h apart: bridged */
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, t0 + 3600, 10800, &v) == CS_OK);
	CHECK_NEAR(v, 20, 1e-12);
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, t0 + 9000, 10800, &v) == CS_OK);
	CHECK_NEAR(v, 35, 1e-12);
	/* 03:00 and 07:00 are 4 h apart: an error naming variable and time */
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, t0 + 5 * 3600, 10800, &v) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "low cloud cover (data_1h.var1) has no value at "
			   "2021-06-14T05:00:00Z: the nearest valid hours, 2021-06-14T03:00:00Z "
			   "and 2021-06-14T07:00:00Z, are 4 h apart (at most 3 h are bridged: "
			   "--max-gap)");
	/* a wider window bridges it; the valid hours themselves always work */
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, t0 + 5 * 3600, 4 * 3600, &v) == CS_OK);
	CHECK_NEAR(v, 60, 1e-12);
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, t0 + 3 * 3600, 3600, &v) == CS_OK);
	CHECK_NEAR(v, 40, 0);
	cs_series_free(&s);
}

static void null_at_the_ends_is_reported_never_zero(void)
{
	struct cs_series s;
	make_series(&s, 5, NULL);
	set_var(&s, CS_VAR_PRECIP, (double[]){NAN, 1, 2, NAN, NAN});
	double t0 = s.time_utc[0], v = -1;
	CHECK(cs_series_value(&s, CS_VAR_PRECIP, t0, 10800, &v) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "precipitation (data_1h.var4) has no value at "
			   "2021-06-14T00:00:00Z: it is null from the start of the data to "
			   "2021-06-14T00:00:00Z");
	CHECK(cs_series_value(&s, CS_VAR_PRECIP, t0 + 3.5 * 3600, 10800, &v) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "null from 2021-06-14T03:00:00Z to the end of the data");
	CHECK(v == -1);
	for (int i = 0; i < 5; i++)
		s.v[CS_VAR_PRECIP][i] = NAN;
	CHECK(cs_series_value(&s, CS_VAR_PRECIP, t0, 10800, &v) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "is null at every hour");
	cs_series_free(&s);
}

static void times_outside_the_data_say_the_covered_range(void)
{
	struct cs_series s;
	make_series(&s, 3, NULL);
	set_var(&s, CS_VAR_CLOUD_LOW, (double[]){1, 2, 3});
	double v;
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, utc("2021-06-14T02:01Z"), 10800, &v)
	      == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "2021-06-14T02:01:00Z is outside the data "
			   "(2021-06-14T00:00:00Z to 2021-06-14T02:00:00Z)");
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, utc("2021-06-13T23:59Z"), 10800, &v)
	      == CS_EDATA);
	CHECK(cs_series_value(&s, CS_VAR_CLOUD_LOW, utc("2021-06-14T02:00Z"), 10800, &v)
	      == CS_OK);
	CHECK_NEAR(v, 3, 0);
	CHECK(cs_series_value(&s, CS_VAR_VISIBILITY, s.time_utc[0], 10800, &v) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "no visibility in the data");
	cs_series_free(&s);
}

static void merge_unites_hours_and_the_later_file_wins(void)
{
	struct cs_series a, b, c;
	make_series(&a, 3, "2021-06-14T00:00Z");
	make_series(&b, 3, "2021-06-14T02:00Z");
	set_var(&a, CS_VAR_CLOUD_LOW, (double[]){1, 2, 3});
	set_var(&b, CS_VAR_CLOUD_LOW, (double[]){30, NAN, 50});
	set_var(&b, CS_VAR_VISIBILITY, (double[]){100, 200, 300});
	b.lat_deg += 0.01;
	double km;
	CHECK(cs_series_merge(&a, &b, &km) == CS_OK);
	CHECK_NEAR(km, 1.11, 0.01);
	CHECK(a.n == 5);
	CHECK_NEAR(a.time_utc[4], utc("2021-06-14T04:00Z"), 0);
	CHECK_NEAR(a.v[CS_VAR_CLOUD_LOW][1], 2, 0);
	CHECK_NEAR(a.v[CS_VAR_CLOUD_LOW][2], 30, 0);  /* b wins */
	CHECK(isnan(a.v[CS_VAR_CLOUD_LOW][3]));         /* a null in b only */
	CHECK(isnan(a.v[CS_VAR_VISIBILITY][0]));        /* b's variable, a's hours */
	CHECK_NEAR(a.v[CS_VAR_VISIBILITY][4], 300, 0);
	CHECK_NEAR(a.lat_deg, 46.95, 0);                /* a's site */
	/* a gap between files is missing data, filled within --max-gap */
	make_series(&c, 1, "2021-06-14T07:00Z");
	set_var(&c, CS_VAR_CLOUD_LOW, (double[]){80});
	CHECK(cs_series_merge(&a, &c, NULL) == CS_OK);
	CHECK(a.n == 8 && isnan(a.v[CS_VAR_CLOUD_LOW][5]));
	double v;
	CHECK(cs_series_value(&a, CS_VAR_CLOUD_LOW, a.time_utc[5], 10800, &v) == CS_OK);
	CHECK_NEAR(v, 60, 1e-12);
	cs_series_free(&c);
	/* another site, another hour grid */
	make_series(&c, 2, "2021-06-14T00:30Z");
	CHECK(cs_series_merge(&a, &c, NULL) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "its hours fall 30 min off the first file's hours");
	c.lat_deg = 47.2;
	CHECK(cs_series_merge(&a, &c, NULL) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "not the same site (a distant site is given with --far)");
	CHECK(a.n == 8); /* unchanged by a failed merge */
	cs_series_free(&a);
	cs_series_free(&b);
	cs_series_free(&c);
}

/* ---- play mode ------------------------------------------------------------ */

static void set_edits_each_kind_of_path(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx); /* cumulus 0.35, cirrus 0.2 */
	CHECK(cs_wx_set(&wx, "layer.low.coverage=0.8") == CS_OK);
	CHECK_NEAR(wx.layers[0].coverage, 0.8, 0);
	CHECK(cs_wx_set(&wx, "precipitation=2.5") == CS_OK);
	CHECK(cs_wx_set(&wx, "convective_mm_h=1") == CS_OK);
	CHECK(cs_wx_set(&wx, "visibility=5000") == CS_OK);
	CHECK(cs_wx_set(&wx, "wind.speed=3") == CS_OK);
	CHECK(cs_wx_set(&wx, "wind.from_deg=90") == CS_OK);
	CHECK(cs_wx_set(&wx, "fog=0.25") == CS_OK);
	CHECK(cs_wx_set(&wx, "site.name=Gurten") == CS_OK);
	CHECK(cs_wx_set(&wx, "site.alt=858") == CS_OK);
	CHECK(cs_wx_set(&wx, "time_utc=2024-01-01T13:00+01:00") == CS_OK);
	CHECK(wx.precipitation_mm_h == 2.5 && wx.convective_mm_h == 1 &&
	      wx.visibility_m == 5000 && wx.wind_speed_m_s == 3 &&
	      wx.wind_from_deg == 90 && wx.fog_probability == 0.25 && wx.site.alt_m == 858);
	CHECK(strcmp(wx.site.name, "Gurten") == 0);
	CHECK_NEAR(wx.time_utc, utc("2024-01-01T12:00Z"), 0);
	CHECK(cs_wx_set(&wx, "snow_fraction=0.4") == CS_OK && wx.snow_fraction == 0.4);
	CHECK(cs_wx_set(&wx, "snow=1") == CS_OK && wx.snow_fraction == 1);
	CHECK(cs_wx_set(&wx, "temperature_c=-2.5") == CS_OK && wx.temperature_c == -2.5);
	CHECK(cs_wx_set(&wx, "temperature=none") == CS_OK && isnan(wx.temperature_c));
	CHECK(cs_wx_set(&wx, "snow=none") == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "snow=none: 'none' is not a number");
	/* a missing étage is added with its default genus, in its place:
	 * the layers stay ordered low to high */
	CHECK(cs_wx_set(&wx, "layer.mid.coverage=0.6") == CS_OK);
	CHECK(wx.nlayers == 3 && wx.layers[1].genus == CS_ALTOCUMULUS);
	CHECK_NEAR(wx.layers[1].coverage, 0.6, 0);
	/* a genus change moves the layer to the genus's altitudes */
	CHECK(cs_wx_set(&wx, "layer.high=cirrostratus") == CS_OK);
	CHECK(wx.layers[2].genus == CS_CIRROSTRATUS);
	CHECK_NEAR(wx.layers[2].base_m, cs_genus_typical(CS_CIRROSTRATUS).base_m, 0);
	CHECK(cs_wx_set(&wx, "layers[0].genus=stratus") == CS_OK);
	CHECK_NEAR(wx.layers[0].base_m, 858 + cs_genus_typical(CS_STRATUS).base_m, 0);
	CHECK(cs_wx_set(&wx, "layers[0].base=1000") == CS_OK);
	CHECK(cs_wx_set(&wx, "layers[0].top_m=1400") == CS_OK);
	CHECK(wx.layers[0].base_m == 1000 && wx.layers[0].top_m == 1400);
	CHECK(cs_wx_set(&wx, "layers[3]=cumulonimbus") == CS_OK); /* adds */
	int cb = -1;
	for (int i = 0; i < wx.nlayers; i++)
		cb = wx.layers[i].genus == CS_CUMULONIMBUS ? i : cb;
	CHECK(wx.nlayers == 4 && cb >= 0 && wx.layers[cb].coverage == 0.5);
	CHECK(cs_wx_set(&wx, "layer.high=none") == CS_OK);
	CHECK(wx.nlayers == 3);
	for (int i = 0; i < wx.nlayers; i++)
		CHECK(wx.layers[i].genus != CS_CIRROSTRATUS);
	CHECK(cs_wx_set(&wx, "layers[0]=none") == CS_OK);
	CHECK(wx.nlayers == 2);
	for (int i = 1; i < wx.nlayers; i++)
		CHECK(wx.layers[i - 1].base_m <= wx.layers[i].base_m);
	CHECK(cs_wx_set(&wx, "layer.high=none") == CS_OK); /* none there: no-op */
	CHECK(cs_wx_validate(&wx) == CS_OK);
}

static void set_reports_bad_paths_values_and_targets(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	static const struct {
		const char *set, *msg;
	} bad[] = {
		{"bogus=1", "bogus=1: unknown path"},
		{"layer.low.coverage=abc", "'abc' is not a number"},
		{"precipitation=1e999", "is not a number"},
		{"wind.speed=", "'' is not a number"},
		{"layer.low=cirrus", "that genus is not of the low étage"},
		{"layers[0].genus=cumulous", "unknown genus 'cumulous'"},
		{"layer.side.coverage=1", "expected layer.low, layer.mid or layer.high"},
		{"layers[9].coverage=1", "expected layers[N] with N in 0..7"},
		{"layers[2].coverage=1", "no layer 2 (the state has 2; layers[2]=GENUS adds one)"},
		{"layers[5]=none", "no layer 5 (the state has 2)"},
		{"layers[0].colour=1", "a layer has the fields genus, coverage"},
		{"far[0].visibility=1", "no far site 0 (the state has 0; --far adds one)"},
		{"far[4].visibility=1", "expected far[N]. with N in 0..3"},
		{"far[0].wind.speed=1", "unknown path"},
		{"time_utc=2024-01-01T12:00", "no time zone"},
		{"noequals", "noequals: expected PATH=VALUE"},
		{"=3", "expected PATH=VALUE"},
		{"site.name=0123456789012345678901234567890123456789012345678901234567890123",
		 "at most 63 bytes"},
	};
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
		int rc = cs_wx_set(&wx, bad[i].set);
		if (rc != CS_EINVAL || strstr(cs_errmsg(), bad[i].msg) == NULL) {
			printf("  '%s': rc %d, \"%s\"; expected \"%s\"\n", bad[i].set, rc,
			       cs_errmsg(), bad[i].msg);
			t_case_failed = 1;
		}
	}
	/* ranges are the state's validation, with its messages */
	CHECK(cs_wx_set(&wx, "layer.low.coverage=1.5") == CS_OK);
	CHECK(cs_wx_validate(&wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "layers[0].coverage: 1.5 is outside 0..1");
	CHECK(cs_wx_set_check("layer.low.coverage=1.5") == CS_OK);
	CHECK(cs_wx_set_check("layers[7]=cumulus") == CS_OK); /* needs a state */
	CHECK(cs_wx_set_check("layer.mid=cirrus") == CS_EINVAL);
}

static void set_edits_far_sites(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nfar = 1;
	wx.far[0].site = wx.site;
	wx.far[0].site.alt_m = 432;
	wx.far[0].visibility_m = 30000;
	CHECK(cs_wx_set(&wx, "far[0].visibility=8000") == CS_OK);
	CHECK(cs_wx_set(&wx, "far[0].precipitation_mm_h=0.4") == CS_OK);
	CHECK(cs_wx_set(&wx, "far[0].site.name=Solothurn") == CS_OK);
	CHECK(cs_wx_set(&wx, "far[0].layer.low=stratocumulus") == CS_OK);
	CHECK(cs_wx_set(&wx, "far[0].layers[0].coverage=0.6") == CS_OK);
	CHECK(wx.far[0].visibility_m == 8000 && wx.far[0].precipitation_mm_h == 0.4);
	CHECK(wx.far[0].nlayers == 1 && wx.far[0].layers[0].coverage == 0.6);
	CHECK_NEAR(wx.far[0].layers[0].base_m,
		   432 + cs_genus_typical(CS_STRATOCUMULUS).base_m, 0);
	CHECK(strcmp(wx.far[0].site.name, "Solothurn") == 0);
	CHECK(wx.nlayers == 2); /* the near site is untouched */
	CHECK(cs_wx_validate(&wx) == CS_OK);
}

static void pretty_json_reads_back_with_flat_objects_on_one_line(void)
{
	struct cs_wx wx, back;
	cs_wx_default(&wx);
	wx.nfar = 1;
	wx.far[0].site = wx.site;
	snprintf(wx.far[0].site.name, sizeof wx.far[0].site.name, "a \"quoted\", [odd] {name}");
	wx.far[0].visibility_m = 30000;
	char *json = NULL, *pretty = NULL;
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	CHECK(cs_json_pretty(json, &pretty) == CS_OK);
	CHECK_STR_CONTAINS(pretty, "{\n  \"schema\": \"cloudwx/2\",\n");
	CHECK_STR_CONTAINS(pretty, "\n  \"layers\": [\n    {\"genus\": \"cumulus\", "
			   "\"coverage\": 0.35, \"base_m\": 1500, \"top_m\": 2700},\n");
	CHECK_STR_CONTAINS(pretty, "\n  \"wind\": {\"speed_m_s\": 4, \"from_deg\": 250},\n");
	CHECK_STR_CONTAINS(pretty, "\"name\": \"a \\\"quoted\\\", [odd] {name}\"");
	CHECK_STR_CONTAINS(pretty, "\n  ]\n}\n");
	CHECK(cs_wx_parse(pretty, strlen(pretty), &back) == CS_OK);
	CHECK(memcmp(&back.layers, &wx.layers, sizeof wx.layers) == 0);
	CHECK(strcmp(back.far[0].site.name, wx.far[0].site.name) == 0);
	free(json);
	free(pretty);
}

static void durations_take_s_m_h_d(void)
{
	double s;
	CHECK(cs_duration_parse("10m", &s) == CS_OK && s == 600);
	CHECK(cs_duration_parse("90", &s) == CS_OK && s == 90);
	CHECK(cs_duration_parse("30s", &s) == CS_OK && s == 30);
	CHECK(cs_duration_parse("1.5h", &s) == CS_OK && s == 5400);
	CHECK(cs_duration_parse("2d", &s) == CS_OK && s == 172800);
	const char *bad[] = {"", "m", "0", "-5m", "10x", "10mm", "nan", "inf", "1e999h"};
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++)
		CHECK(cs_duration_parse(bad[i], &s) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "is not a duration");
}

/* ---- the whole program ------------------------------------------------------- */

static void write_file(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	if (f) {
		fputs(text, f);
		fclose(f);
	}
}

/* Three hours at a site (UTC+2 wall times), visibility null at 01:00Z. */
static void crafted(const char *path, const char *name, double lat, double lon,
		    int low0, int low1)
{
	char j[2048];
	snprintf(j, sizeof j,
		 "{\"metadata\":{\"name\":\"%s\",\"latitude\":%g,\"longitude\":%g,"
		 "\"height\":540,\"utc_timeoffset\":2.0},\"units\":{\"cloudcover\":"
		 "\"percent\",\"precipitation\":\"mm\",\"windspeed\":\"ms-1\","
		 "\"winddirection\":\"degree\",\"visibility\":\"m\"},\"data_1h\":{"
		 "\"time\":[\"2021-06-14 02:00\",\"2021-06-14 03:00\",\"2021-06-14 04:00\"],"
		 "\"lowclouds\":[%d,%d,%d],\"midclouds\":[0,0,0],\"highclouds\":[0,0,0],"
		 "\"precipitation\":[0,0,0],\"windspeed\":[2,4,4],"
		 "\"winddirection\":[350,10,10],\"visibility\":[20000,null,30000]}}",
		 name, lat, lon, low0, low1, low1);
	write_file(path, j);
}

static void run_writes_states_with_far_sites_and_edits(void)
{
	crafted(tmp("near.json"), "", 46.95, 7.44, 20, 40);
	crafted(tmp("far.json"), "Solothurn", 47.2088, 7.5323, 60, 80);
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = tmp("near.json");
	o.far[o.nfar++] = tmp("far.json");
	o.have_at = 1;
	o.at_utc = utc("2021-06-14T00:30Z");
	o.sets[o.nsets++] = "precipitation=0.5";
	o.output = tmp("wx.json");
	CHECK(cs_wxinterp_run(&o, &res) == CS_OK);
	CHECK(res.nstates == 1);
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("wx.json"), &wx) == CS_OK);
	/* no metadata name: its coordinates, not the file's name */
	CHECK(strcmp(wx.site.name, "46.950N 7.440E") == 0);
	CHECK_NEAR(wx.layers[0].coverage, 0.3, 1e-12);
	CHECK_NEAR(wx.wind_from_deg, 0, 1e-9);
	CHECK_NEAR(wx.wind_speed_m_s, 3, 1e-12);
	CHECK_NEAR(wx.visibility_m, 22500, 1e-9); /* bridged 00:00 to 02:00 */
	CHECK_NEAR(wx.precipitation_mm_h, 0.5, 0);
	CHECK(wx.nfar == 1 && strcmp(wx.far[0].site.name, "Solothurn") == 0);
	CHECK_NEAR(wx.far[0].site.lat_deg, 47.2088, 0);
	CHECK_NEAR(wx.far[0].layers[0].coverage, 0.7, 1e-12);
	CHECK(wx.far[0].nlayers == 1);
	/* the file has no radiation and no total cover: no "observed" */
	CHECK(!wx.observed.has_radiation && !wx.observed.has_cloud_cover);
	char text[4096] = "";
	FILE *f = fopen(tmp("wx.json"), "r");
	size_t len = f ? fread(text, 1, sizeof text - 1, f) : 0;
	if (f)
		fclose(f);
	text[len] = '\0';
	CHECK(len > 0 && strstr(text, "\"snow_fraction\":0") != NULL);
	CHECK(strstr(text, "observed") == NULL);
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = tmp("near.json");
	o.have_at = 1;
	o.at_utc = utc("2021-06-14T00:30Z");
	o.output = tmp("wx.json");
	o.max_gap_s = 3600; /* bridges nothing */
	CHECK(cs_wxinterp_run(&o, &res) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "near.json: visibility (data_1h.visibility) has "
			   "no value at 2021-06-14T00:30:00Z: the nearest valid hours, "
			   "2021-06-14T00:00:00Z and 2021-06-14T02:00:00Z, are 2 h apart");
}

/* An Open-Meteo file of n hours from 2021-06-14T00:00Z (GMT) at a grid
 * cell of the given elevation: low cover `low` %, no rain, and the
 * visibility vis0 at hour 0 and vis at every other hour. */
static void om_file(const char *path, int n, double elevation, int low,
		    double vis0, double vis)
{
	char j[16384], *p = j;
	char *end = j + sizeof j;
	p += snprintf(p, (size_t)(end - p),
		 "{\"latitude\":46.5,\"longitude\":9.9,\"elevation\":%g,"
		 "\"utc_offset_seconds\":0,\"hourly_units\":{\"time\":\"iso8601\","
		 "\"cloud_cover_low\":\"%%\",\"cloud_cover_mid\":\"%%\","
		 "\"cloud_cover_high\":\"%%\",\"precipitation\":\"mm\","
		 "\"wind_speed_10m\":\"m/s\",\"wind_direction_10m\":\"\xc2\xb0\","
		 "\"visibility\":\"m\"},\"hourly\":{\"time\":[", elevation);
	for (int i = 0; i < n; i++)
		p += snprintf(p, (size_t)(end - p), "%s\"2021-06-%02dT%02d:00\"",
			      i ? "," : "", 14 + i / 24, i % 24);
	const char *keys[] = {"cloud_cover_low", "cloud_cover_mid",
			      "cloud_cover_high", "precipitation",
			      "wind_speed_10m", "wind_direction_10m", "visibility"};
	for (int k = 0; k < 7; k++) {
		p += snprintf(p, (size_t)(end - p), "],\"%s\":[", keys[k]);
		for (int i = 0; i < n; i++) {
			double v = k == 0 ? low : k == 4 ? 3 : k == 5 ? 200 :
				   k == 6 ? (i == 0 ? vis0 : vis) : 0;
			p += snprintf(p, (size_t)(end - p), "%s%g", i ? "," : "", v);
		}
	}
	snprintf(p, (size_t)(end - p), "]}}");
	write_file(path, j);
}

static char notes[4096];

static void keep_note(void *user, int level, const char *msg)
{
	(void)user;
	(void)level;
	snprintf(notes + strlen(notes), sizeof notes - strlen(notes), "%s\n", msg);
}

/* One state at t from an Open-Meteo file, with the -v notes in `notes`. */
static int om_state(const char *path, const char *at, struct cs_wx *wx)
{
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = path;
	o.have_at = 1;
	o.at_utc = utc(at);
	o.output = tmp("om-state.json");
	o.note = keep_note;
	notes[0] = '\0';
	int rc = cs_wxinterp_run(&o, &res);
	if (rc == CS_OK)
		rc = cs_wx_read(tmp("om-state.json"), wx);
	return rc;
}

/* Quirk (b): Open-Meteo's visibility at its ~24 km ceiling, or one value
 * at every hour of a day or more, is a model default: unknown, so the
 * state gets the default 30000 m, and -v says why. */
static void openmeteo_default_visibility_is_taken_as_unknown(void)
{
	struct cs_wx wx;
	/* constant over 24 hours (and not at the ceiling): dropped */
	om_file(tmp("om-const.json"), 24, 500, 0, 18000, 18000);
	CHECK(om_state(tmp("om-const.json"), "2021-06-14T05:00Z", &wx) == CS_OK);
	CHECK(wx.visibility_m == CS_WX_DEFAULT_VIS_M);
	CHECK_STR_CONTAINS(notes, "om-const.json: hourly.visibility is 18000 m "
			   "at all 24 hours: a model's default, not used");
	/* 23 hours of one value are kept: too short to tell */
	om_file(tmp("om-short.json"), 23, 500, 0, 18000, 18000);
	CHECK(om_state(tmp("om-short.json"), "2021-06-14T05:00Z", &wx) == CS_OK);
	CHECK(wx.visibility_m == 18000);
	/* 24140 m (15 miles, the ceiling) at one hour: unknown there only */
	om_file(tmp("om-cap.json"), 3, 500, 0, 24140, 9000);
	CHECK(om_state(tmp("om-cap.json"), "2021-06-14T00:00Z", &wx) == CS_OK);
	CHECK(wx.visibility_m == CS_WX_DEFAULT_VIS_M);
	CHECK_STR_CONTAINS(notes, "visibility at Open-Meteo's ~24 km ceiling, a "
			   "model default: unknown, 30000 m used");
	CHECK(om_state(tmp("om-cap.json"), "2021-06-14T02:00Z", &wx) == CS_OK);
	CHECK(wx.visibility_m == 9000);
	CHECK(strstr(notes, "ceiling") == NULL);
	/* a varying file keeps every value, 24.5 km too (not the ceiling) */
	om_file(tmp("om-vary.json"), 30, 500, 0, 24500, 12000);
	CHECK(om_state(tmp("om-vary.json"), "2021-06-14T00:00Z", &wx) == CS_OK);
	CHECK(wx.visibility_m == 24500);
}

/* Quirk (a): Open-Meteo's low cover at a grid cell 1000 m or more above
 * sea level counts pressure levels below the ground: fog where the
 * visibility says fog (L2), else no low layer (L8).  Lower, it stays. */
static void openmeteo_low_cover_at_an_elevated_site_is_fog_or_nothing(void)
{
	struct cs_wx wx;
	om_file(tmp("om-low.json"), 3, 999, 80, 9000, 9000);
	CHECK(om_state(tmp("om-low.json"), "2021-06-14T01:00Z", &wx) == CS_OK);
	CHECK(wx.nlayers == 1 && wx.layers[0].genus == CS_STRATOCUMULUS);
	CHECK_NEAR(wx.layers[0].coverage, 0.8, 1e-12);
	om_file(tmp("om-high.json"), 3, 1000, 80, 9000, 9000);
	CHECK(om_state(tmp("om-high.json"), "2021-06-14T01:00Z", &wx) == CS_OK);
	CHECK(wx.nlayers == 0);
	CHECK_STR_CONTAINS(notes, "low 80%: L8 Open-Meteo low cover at ground >= "
			   "1000 m, no fog: dropped");
	/* fog by visibility (600 m at 00:00): stratus at the ground */
	om_file(tmp("om-fog.json"), 3, 1500, 80, 600, 9000);
	CHECK(om_state(tmp("om-fog.json"), "2021-06-14T00:00Z", &wx) == CS_OK);
	CHECK(wx.nlayers == 1 && wx.layers[0].genus == CS_STRATUS);
	CHECK(wx.layers[0].base_m == 1500 && wx.layers[0].top_m == 1800);
	CHECK(wx.visibility_m == 600);
	/* the fog (coverage 1) lasts until the visibility, rising linearly
	 * from 600 m to 9000 m in an hour, passes 1 km (2.86 min; the low
	 * cover is then dropped, L8), and fades over the genus-change window:
	 * it holds the window's 30 min before 00:00 (the data's first hour
	 * holds before it) and 2.86 min after */
	CHECK_NEAR(wx.layers[0].coverage, (30 + 400.0 / 8400 * 60) / 60, 1e-3);
	/* meteoblue at any height keeps its low cover (no such quirk known) */
	struct cs_wx_obs o;
	memset(&o, 0, sizeof o);
	o.low = 0.8;
	o.visibility_m = 9000;
	o.temperature_c = o.humidity_pct = o.sun_elevation_deg = NAN;
	enum cs_wx_rule r[3];
	cs_wx_rules(&o, r);
	CHECK(r[0] == CS_RULE_L7_SC);
	o.low_below_ground = 1;
	cs_wx_rules(&o, r);
	CHECK(r[0] == CS_RULE_L8_BELOW);
	/* rain and a mid sheet still make nimbostratus, from the mid cover */
	o.mid = 0.75;
	o.precipitation_mm_h = 1;
	struct cs_wx_layer l[CS_WX_MAX_LAYERS];
	int n = 0;
	cs_wx_layers(&o, 1500, l, &n, r);
	CHECK(n == 1 && l[0].genus == CS_NIMBOSTRATUS && r[0] == CS_RULE_L4_NS);
	CHECK_NEAR(l[0].coverage, 0.75, 1e-12);
}

static void run_series_is_json_lines_and_errors_leave_no_output(void)
{
	crafted(tmp("a.json"), "A", 46.95, 7.44, 20, 40);
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.inputs[o.ninputs++] = tmp("a.json");
	o.have_from = o.have_to = 1;
	o.from_utc = utc("2021-06-14T00:00Z");
	o.to_utc = utc("2021-06-14T00:50Z");
	o.step_s = 600;
	o.output = tmp("lapse.jsonl");
	CHECK(cs_wxinterp_run(&o, &res) == CS_OK);
	CHECK(res.nstates == 6);
	unsigned char *text;
	size_t len;
	CHECK(cs_read_all(tmp("lapse.jsonl"), 1 << 20, &text, &len) == CS_OK);
	int lines = 0;
	for (size_t i = 0; i < len; i++)
		lines += text[i] == '\n';
	CHECK(lines == 6);
	CHECK_STR_CONTAINS((char *)text, "\"time_utc\":\"2021-06-14T00:50:00Z\"");
	free(text);
	/* a bad --set or a time outside the data: the old file stays */
	o.sets[o.nsets++] = "layer.low.coverage=2";
	CHECK(cs_wxinterp_run(&o, &res) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "after --set: layers[0].coverage: 2 is outside 0..1");
	o.nsets = 0;
	o.to_utc = utc("2021-06-14T03:00Z");
	CHECK(cs_wxinterp_run(&o, &res) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "2021-06-14T03:00:00Z is outside the data: ");
	CHECK_STR_CONTAINS(cs_errmsg(), "a.json covers 2021-06-14T00:00:00Z to "
			   "2021-06-14T02:00:00Z");
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("lapse.jsonl"), &wx) == CS_OK); /* still the old one */
	o.have_to = 0; /* to the end of the data */
	o.pretty = 1;
	CHECK(cs_wxinterp_run(&o, &res) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "--pretty writes one state, not a series of 13");
}

static void run_template_and_option_errors(void)
{
	struct cs_wxinterp_opts o;
	struct cs_wxinterp_result res;
	cs_wxinterp_defaults(&o);
	o.template_state = 1;
	o.pretty = 1;
	o.sets[o.nsets++] = "layer.low=nimbostratus";
	o.output = tmp("t.json");
	CHECK(cs_wxinterp_run(&o, &res) == CS_OK);
	struct cs_wx wx;
	CHECK(cs_wx_read(tmp("t.json"), &wx) == CS_OK);
	CHECK(wx.layers[0].genus == CS_NIMBOSTRATUS && strcmp(wx.site.name, "Bern") == 0);
	o.inputs[o.ninputs++] = "x.json";
	CHECK(cs_wxinterp_run(&o, &res) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "--template takes no input files");
	cs_wxinterp_defaults(&o);
	CHECK(cs_wxinterp_run(&o, &res) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "no input");
	o.inputs[o.ninputs++] = "-";
	o.far[o.nfar++] = "-";
	CHECK(cs_wxinterp_run(&o, &res) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "standard input ('-') can be read only once");
	o.nfar = 0;
	o.inputs[0] = tmp("missing.json");
	CHECK(cs_wxinterp_run(&o, &res) == CS_EIO);
	CHECK_STR_CONTAINS(cs_errmsg(), "missing.json");
}

/* A layer added or moved by --set keeps the layers ordered low to high. */
static void set_keeps_layers_low_to_high(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx); /* cumulus, cirrus */
	CHECK(cs_wx_set(&wx, "layer.mid.coverage=0.5") == CS_OK);
	CHECK(wx.nlayers == 3);
	for (int i = 1; i < wx.nlayers; i++)
		CHECK(wx.layers[i - 1].base_m <= wx.layers[i].base_m);
	CHECK(wx.layers[1].genus == CS_ALTOCUMULUS);
	CHECK(cs_wx_set(&wx, "layers[2].base_m=500") == CS_OK);
	CHECK(wx.layers[0].base_m == 500 && wx.layers[0].genus == CS_CIRRUS);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(set_keeps_layers_low_to_high),
	CASE(real_data_at_exact_hours_equals_the_file),
	CASE(real_data_half_way_is_the_mean),
	CASE(snow_fraction_comes_from_the_best_source_there_is),
	CASE(real_data_state_has_the_files_snow_and_temperature),
	CASE(real_data_observed_radiation_equals_the_file),
	CASE(wind_direction_across_north_passes_through_zero),
	CASE(null_is_bridged_within_max_gap_and_reported_beyond),
	CASE(null_at_the_ends_is_reported_never_zero),
	CASE(times_outside_the_data_say_the_covered_range),
	CASE(merge_unites_hours_and_the_later_file_wins),
	CASE(set_edits_each_kind_of_path),
	CASE(set_reports_bad_paths_values_and_targets),
	CASE(set_edits_far_sites),
	CASE(pretty_json_reads_back_with_flat_objects_on_one_line),
	CASE(durations_take_s_m_h_d),
	CASE(run_writes_states_with_far_sites_and_edits),
	CASE(run_series_is_json_lines_and_errors_leave_no_output),
	CASE(openmeteo_default_visibility_is_taken_as_unknown),
	CASE(openmeteo_low_cover_at_an_elevated_site_is_fog_or_nothing),
	CASE(run_template_and_option_errors),
};

int main(void)
{
	snprintf(tmpdir, sizeof tmpdir, "/tmp/cs-test-wxinterp.XXXXXX");
	if (mkdtemp(tmpdir) == NULL)
		return 1;
	T_RUN_TABLE(t_cases);
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		printf("could not remove %s\n", tmpdir);
	TEST_EXIT();
}
