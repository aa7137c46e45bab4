/* test_advection.c - clouds carried by the integral of the wind: the drift
 * of a series (weather/series.h), its place in the weather state (cloudwx/2)
 * and how the renderer's cloud field follows it (render/cloud.h). */
#include "core/err.h"
#include "render/cloud.h"
#include "weather/genus_rules.h"
#include "weather/series.h"
#include "weather/wx.h"
#include "test.h"

#include <stdlib.h>

static struct cs_volume noise;

#define NH 6
static double hours[NH], speed[NH], from[NH];

/* A series of NH hours from 2021-06-14T00:00Z with only a wind. */
static void series(struct cs_series *s, const double *sp, const double *fr)
{
	memset(s, 0, sizeof *s);
	s->n = NH;
	s->time_utc = hours;
	for (int i = 0; i < NH; i++) {
		hours[i] = 1623628800.0 + 3600.0 * i;
		speed[i] = sp[i];
		from[i] = fr[i];
	}
	s->v[CS_VAR_WIND_SPEED] = speed;
	s->v[CS_VAR_WIND_FROM] = from;
}

/* The reference: the midpoint rule with 20000 steps an hour over the
 * wind as documented (speed linear, direction linear the short way round,
 * blowing toward from + 180 degrees), written here from the definition. */
static void reference(double t, double *e, double *n)
{
	*e = *n = 0.0;
	for (int i = 0; i + 1 < NH && hours[i] < t; i++) {
		double d = fmod(from[i + 1] - from[i] + 540.0, 360.0) - 180.0;
		/* times from the hour (not 1.6e9 s with 2.4e-7 s steps) */
		double len = fmin(t, hours[i + 1]) - hours[i], h = len / 20000;
		for (int j = 0; j < 20000; j++) {
			double f = (j + 0.5) * h / 3600.0;
			double sp = speed[i] + f * (speed[i + 1] - speed[i]);
			double to = (from[i] + f * d + 180.0) * CS_PI / 180.0;
			*e += sp * sin(to) * h;
			*n += sp * cos(to) * h;
		}
	}
}

/* The drift is the integral of the wind vector from the first hour: a
 * wind turning through north (350 -> 20), turning by 170 degrees in an
 * hour, speeding up and slowing down. */
static void drift_is_the_integral_of_the_wind_vector(void)
{
	static const double sp[NH] = {2, 6, 6, 1, 9, 9};
	static const double fr[NH] = {350, 20, 190, 90, 90, 300};
	struct cs_series s;
	struct cs_drift d;
	series(&s, sp, fr);
	CHECK(cs_drift_new(&d, &s, 10800) == CS_OK);
	CHECK(d.since_utc == hours[0]);
	static const double at[] = {0, 37 * 60, 3600, 2 * 3600 + 930.5, 3 * 3600,
				    4 * 3600 + 1, 5 * 3600};
	for (size_t k = 0; k < sizeof at / sizeof at[0]; k++) {
		double e, n, re, rn, t = hours[0] + at[k];
		CHECK(cs_drift_at(&d, &s, t, &e, &n) == CS_OK);
		reference(t, &re, &rn);
		/* the midpoint rule's own error is below 1e-4 m here */
		CHECK_NEAR(e, re, 1e-3);
		CHECK_NEAR(n, rn, 1e-3);
	}
	/* a first hour from the north, 2..6 m/s (4 on average), went south */
	double e, n;
	CHECK(cs_drift_at(&d, &s, hours[1], &e, &n) == CS_OK);
	CHECK(n < -0.95 * 4 * 3600 && n > -4 * 3600 && fabs(e) < 0.2 * 4 * 3600);
	/* the axis: where the mean of the hourly winds blows (written from
	 * the six vectors) */
	double me = 0, mn = 0;
	for (int i = 0; i < NH; i++) {
		me += sp[i] * sin((fr[i] + 180) * CS_PI / 180);
		mn += sp[i] * cos((fr[i] + 180) * CS_PI / 180);
	}
	double ax = atan2(me, mn) * 180 / CS_PI;
	CHECK_NEAR(d.axis_deg, ax < 0 ? ax + 360 : ax, 1e-9);
	CHECK(cs_drift_at(&d, &s, hours[NH - 1] + 1, &e, &n) == CS_EDATA);
	cs_drift_free(&d);
}

/* The drift at a time does not depend on what else is asked: it is the
 * same at an hour from either side (continuous), and asking in any order
 * gives the same bits. */
static void drift_is_continuous_and_the_same_whatever_is_asked(void)
{
	static const double sp[NH] = {3, 7, 2, 2, 5, 4};
	static const double fr[NH] = {100, 250, 260, 10, 10, 180};
	struct cs_series s;
	struct cs_drift d;
	series(&s, sp, fr);
	CHECK(cs_drift_new(&d, &s, 10800) == CS_OK);
	for (int i = 1; i < NH; i++) {
		double e0, n0, e1, n1;
		CHECK(cs_drift_at(&d, &s, hours[i] - 1e-3, &e0, &n0) == CS_OK);
		CHECK(cs_drift_at(&d, &s, hours[i], &e1, &n1) == CS_OK);
		/* 1 ms at under 8 m/s */
		CHECK(hypot(e1 - e0, n1 - n0) < 8e-3);
	}
	double e[2], n[2];
	CHECK(cs_drift_at(&d, &s, hours[2] + 1234, &e[0], &n[0]) == CS_OK);
	for (int k = 0; k < 47; k++) { /* 47 x 377 s < 5 h */
		double x, y;
		CHECK(cs_drift_at(&d, &s, hours[0] + 377.0 * k, &x, &y) == CS_OK);
	}
	CHECK(cs_drift_at(&d, &s, hours[2] + 1234, &e[1], &n[1]) == CS_OK);
	CHECK(e[0] == e[1] && n[0] == n[1]);
	cs_drift_free(&d);
}

/* Hours whose wind cannot be bridged (nulls over more than max_gap_s)
 * carry the air nowhere; the hours after go on from there. */
static void drift_over_an_unbridged_gap_adds_nothing(void)
{
	static const double sp[NH] = {4, NAN, NAN, NAN, NAN, 6};
	static const double fr[NH] = {270, NAN, NAN, NAN, NAN, 270};
	struct cs_series s;
	struct cs_drift d;
	series(&s, sp, fr);
	CHECK(cs_drift_new(&d, &s, 3 * 3600) == CS_OK);
	double e, n;
	CHECK(cs_drift_at(&d, &s, hours[NH - 1], &e, &n) == CS_OK);
	CHECK(e == 0 && n == 0);
	cs_drift_free(&d);
	/* bridged (5 h <= 6 h): 5 h of a west wind rising from 4 to 6 m/s */
	CHECK(cs_drift_new(&d, &s, 6 * 3600) == CS_OK);
	CHECK(cs_drift_at(&d, &s, hours[NH - 1], &e, &n) == CS_OK);
	CHECK_NEAR(e, 5 * 3600 * 5.0, 1e-6);
	CHECK_NEAR(n, 0, 1e-6);
	cs_drift_free(&d);
}

static const char v2[] =
	"{\"schema\":\"cloudwx/2\",\"time_utc\":\"2024-10-13T15:00:00Z\","
	"\"site\":{\"lat_deg\":-34.81,\"lon_deg\":-56.15,\"alt_m\":34},"
	"\"layers\":[],\"wind\":{\"speed_m_s\":3.44,\"from_deg\":110},"
	"\"drift\":{\"since_utc\":\"2024-10-06T00:00:00Z\",\"east_m\":-2156526.79,"
	"\"north_m\":731510.8,\"axis_deg\":289.5}}";

/* cloudwx/2 carries the drift and writes it back the same; a cloudwx/1
 * state has none, even with a "drift" key (unknown there, ignored). */
static void state_drift_round_trips_and_cloudwx_1_has_none(void)
{
	struct cs_wx wx, back;
	CHECK(cs_wx_parse(v2, strlen(v2), &wx) == CS_OK);
	CHECK(wx.drift.known && wx.drift.east_m == -2156526.79 &&
	      wx.drift.north_m == 731510.8 && wx.drift.axis_deg == 289.5);
	CHECK(wx.drift.since_utc == 1728172800.0);
	char *json = NULL;
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	CHECK_STR_CONTAINS(json, "\"drift\":{\"since_utc\":\"2024-10-06T00:00:00Z\","
			   "\"east_m\":-2156526.79,\"north_m\":731510.8,\"axis_deg\":289.5}}");
	CHECK(cs_wx_parse(json, strlen(json), &back) == CS_OK);
	CHECK(memcmp(&back.drift, &wx.drift, sizeof wx.drift) == 0);
	free(json);
	char v1[sizeof v2];
	memcpy(v1, v2, sizeof v2);
	memcpy(strstr(v1, "cloudwx/2"), "cloudwx/1", 9);
	CHECK(cs_wx_parse(v1, strlen(v1), &wx) == CS_OK);
	CHECK(!wx.drift.known);
	CHECK(cs_wx_to_json(&wx, &json) == CS_OK);
	CHECK(strstr(json, "drift") == NULL);
	CHECK_STR_CONTAINS(json, "\"schema\":\"cloudwx/2\"");
	free(json);
	/* in cloudwx/2 the members are required and ranged */
	char bad[sizeof v2 + 16];
	snprintf(bad, sizeof bad, "%.*s}}", (int)(strstr(v2, ",\"axis_deg\"") - v2), v2);
	CHECK(cs_wx_parse(bad, strlen(bad), &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "drift.axis_deg: missing (required)");
	snprintf(bad, sizeof bad, "%.*s\"axis_deg\":361}}",
		 (int)(strstr(v2, "\"axis_deg\"") - v2), v2);
	CHECK(cs_wx_parse(bad, strlen(bad), &wx) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "drift.axis_deg: 361 is outside 0..360");
}

/* A state moved to another time carries its drift on by its own wind:
 * 3.44 m/s from 110 degrees blows toward 290 degrees. */
static void state_at_another_time_carries_its_drift_by_its_wind(void)
{
	struct cs_wx wx;
	CHECK(cs_wx_parse(v2, strlen(v2), &wx) == CS_OK);
	double t = wx.time_utc + 600, e0 = wx.drift.east_m, n0 = wx.drift.north_m;
	cs_wx_retime(&wx, t);
	CHECK(wx.time_utc == t);
	CHECK_NEAR(wx.drift.east_m, e0 + 3.44 * 600 * sin(290 * CS_PI / 180), 1e-6);
	CHECK_NEAR(wx.drift.north_m, n0 + 3.44 * 600 * cos(290 * CS_PI / 180), 1e-6);
	struct cs_wx def;
	cs_wx_default(&def);
	double e, n;
	cs_wx_drift_at(&def, def.time_utc + 600, &e, &n);
	CHECK(!def.drift.known && e == 0 && n == 0);
	/* the provider's instant values were the old time's: dropped, but
	 * kept where the time stays */
	CHECK(cs_wx_parse(v2, strlen(v2), &wx) == CS_OK);
	wx.observed.has_radiation = 1, wx.observed.dni_w_m2 = 120.0;
	wx.observed.has_cloud_cover = 1, wx.observed.total_cloud_cover = 0.9;
	cs_wx_retime(&wx, wx.time_utc);
	CHECK(wx.observed.has_radiation && wx.observed.has_cloud_cover);
	cs_wx_retime(&wx, wx.time_utc + 3600.0);
	CHECK(!wx.observed.has_radiation && !wx.observed.has_cloud_cover);
}

static long gcd(long a, long b)
{
	return b == 0 ? a : gcd(b, a % b);
}

/* The field moved by a drift D + delta is the field moved by D carried by
 * delta times the power law (height / 10 m)^(1/7) at the genus's typical
 * height above the ground, in any direction against the field's axis
 * (along it, across it); the offsets kept are reduced by true periods (an
 * unreduced copy samples the same). */
static void drift_moves_the_field_by_the_wind_aloft_in_any_direction(void)
{
	static const enum cs_genus gs[] = {CS_CUMULUS, CS_CIRRUS, CS_ALTOCUMULUS,
					   CS_STRATOCUMULUS};
	static const double axes[] = {0, 77, 289.5};
	unsigned st = 9;
	for (size_t k = 0; k < sizeof gs / sizeof gs[0]; k++)
		for (size_t a = 0; a < sizeof axes / sizeof axes[0]; a++) {
			struct cs_wx_layer wl = {gs[k], 0.5, 0, 0};
			double ground = 540;
			cs_genus_place(gs[k], ground, &wl.base_m, &wl.top_m);
			double f = pow((0.5 * (wl.base_m + wl.top_m) - ground) / 10, 1.0 / 7);
			/* the layer today is higher than typical: its own height
			 * must not change how it drifts (a cumulus base follows
			 * the temperature minute by minute) */
			wl.base_m += 317, wl.top_m += 317;
			struct cs_cloud_layer l0, l1, raw;
			cs_cloud_layer_init(&l0, &wl, &noise, 3, 110, ground, 0);
			l1 = l0;
			double de = t_uniform(&st, -4000, 4000), dn = t_uniform(&st, -4000, 4000);
			double e = -2156526.79, n = 731510.8;
			cs_cloud_layer_drift(&l0, e, n, axes[a], ground);
			cs_cloud_layer_drift(&l1, e + de, n + dn, axes[a], ground);
			const struct cs_genus_preset *p = cs_genus_preset(gs[k]);
			long ta = (long)p->tile_m, tb = (long)p->detail_tile_m;
			double across = (double)(ta / gcd(ta, tb) * tb);
			CHECK(fabs(l1.offset_along_m) < p->stretch * across);
			CHECK(fabs(l1.offset_across_m) < across);
			raw = l1;
			double ax = axes[a] * CS_PI / 180;
			raw.offset_along_m = f * ((e + de) * sin(ax) + (n + dn) * cos(ax));
			raw.offset_across_m = f * (-(e + de) * cos(ax) + (n + dn) * sin(ax));
			int nonzero = 0;
			for (int i = 0; i < 400; i++) {
				double x = t_uniform(&st, -2e4, 2e4), y = t_uniform(&st, -2e4, 2e4);
				double z = t_uniform(&st, wl.base_m, wl.top_m);
				double d0 = cs_cloud_extinction(&l0, &noise, x, y, z);
				double d1 = cs_cloud_extinction(&l1, &noise, x + f * de, y + f * dn, z);
				CHECK_NEAR(d1, d0, 1e-3 * l0.extinction_per_m);
				CHECK_NEAR(cs_cloud_extinction(&raw, &noise, x + f * de, y + f * dn, z),
					   d1, 1e-3 * l0.extinction_per_m);
				nonzero += d0 > 0;
			}
			CHECK(nonzero > 20);
		}
}

static const struct t_case t_cases[] = {
	CASE(drift_is_the_integral_of_the_wind_vector),
	CASE(drift_is_continuous_and_the_same_whatever_is_asked),
	CASE(drift_over_an_unbridged_gap_adds_nothing),
	CASE(state_drift_round_trips_and_cloudwx_1_has_none),
	CASE(state_at_another_time_carries_its_drift_by_its_wind),
	CASE(drift_moves_the_field_by_the_wind_aloft_in_any_direction),
};

int main(void)
{
	if (cs_volume_new(&noise, 32, 32) != 0 || cs_volume_bake(&noise, 0, NULL, NULL) != 0)
		return 1;
	T_RUN_TABLE(t_cases);
	cs_volume_free(&noise);
	TEST_EXIT();
}
