/* test_beamfit.c - the clouds' optical depth fitted to the forecast's beam
 * (beam_fit.c; cloudrender(1), RADIATION).
 *
 * The expected values come from outside the fit: the forecast's DNI (the
 * test's input) over the clear sky's, which the radiometry (cs_irradiance_at,
 * the renderer's own conversion to W/m2) gives for the same state without
 * clouds; the delta-Eddington beam of Joseph, Wiscombe & Weinman (1976),
 * exp(-(1 - g^2) tau), with g = 0.852, the asymmetry of the scene's phase
 * function (0.96 x 0.9 + 0.04 x -0.3); and the render's own transmittance
 * toward the sun (cs_render_sun_transmittance, a march of its own). */
#include "core/err.h"
#include "core/vec.h"
#include "render/march.h"
#include "render/render.h"
#include "render/scene.h"
#include "astro/sun.h"
#include "weather/wx.h"
#include "test.h"

#include <stdio.h>
#include <string.h>

#define G_EFF 0.852

static struct cs_volume noise;

static struct cs_volume *get_noise(void)
{
	if (noise.data == NULL)
		CHECK(cs_volume_new(&noise, 32, 32) == CS_OK &&
		      cs_volume_bake(&noise, 0, NULL, NULL) == CS_OK);
	return &noise;
}

/* Bern, 2021-06-14T14:00Z (the sun 52 deg up), clear air, the layers. */
static void state(struct cs_wx *wx, int n, const struct cs_wx_layer *l)
{
	cs_wx_default(wx);
	wx->visibility_m = 30000.0;
	wx->nlayers = n;
	for (int i = 0; i < n; i++)
		wx->layers[i] = l[i];
	wx->observed.has_radiation = 0;
}

/* The clear sky's DNI at the scene's origin, W/m2. */
static double clear_dni(const struct cs_wx *wx)
{
	struct cs_wx w = *wx;
	w.nlayers = 0;
	w.observed.has_radiation = 0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &w, w.time_utc, get_noise()) == CS_OK);
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	struct cs_render_stats st;
	memset(&st, 0, sizeof st);
	struct cs_irradiance irr;
	cs_irradiance_at(&sc, &s, cs_irradiance_area_point(&sc, CS_IRRADIANCE_AREA_M, 1, 0, 0),
			 &irr, &st);
	return irr.dni_w_m2;
}

/* The mean of the render's beam transmittance toward the sun,
 * delta-scaled, over a square of side side_m (n x n points) 2 m above
 * the flat ground. */
static double scaled_beam(const struct cs_scene *sc, double side_m, int n)
{
	struct cs_render_settings s;
	cs_render_quality("high", &s);
	s.light_steps = 48;
	struct cs_render_stats st;
	memset(&st, 0, sizeof st);
	double sum = 0.0;
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			cs_v3 p = cs_irradiance_area_point(sc, side_m, n, i, j);
			sum += pow(cs_render_sun_transmittance(sc, &s, p, &st), 1.0 - G_EFF * G_EFF);
		}
	return sum / (n * n);
}

static struct cs_scene fitted, plain;

static void build_both(struct cs_wx *wx, double dni_w_m2)
{
	wx->observed.has_radiation = 1;
	wx->observed.dni_w_m2 = dni_w_m2;
	wx->observed.dhi_w_m2 = 100.0;
	wx->observed.ghi_w_m2 = 100.0;
	CHECK(cs_scene_build(&fitted, wx, wx->time_utc, get_noise()) == CS_OK);
	struct cs_wx w = *wx;
	w.observed.has_radiation = 0;
	CHECK(cs_scene_build(&plain, &w, w.time_utc, get_noise()) == CS_OK);
}

/* An overcast altostratus lets through the share of the clear sky's beam
 * that the forecast's DNI says, as a delta-scaled beam, whether that asks
 * for a thinner deck or a thicker one. */
static void a_sheet_lets_the_forecasts_beam_through(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer as = {CS_ALTOSTRATUS, 1.0, 3000.0, 5000.0};
	state(&wx, 1, &as);
	double clear = clear_dni(&wx);
	CHECK(clear > 700.0 && clear < 1100.0);
	static const double shares[] = {0.03, 0.15, 0.4, 0.7};
	for (size_t i = 0; i < sizeof shares / sizeof shares[0]; i++) {
		build_both(&wx, shares[i] * clear);
		/* over the altostratus's base tile, 30 km across the wind */
		double got = scaled_beam(&fitted, 30000.0, 40);
		if (!(fabs(got - shares[i]) <= 0.03 * shares[i] + 0.002)) {
			printf("  share %g: the deck lets %.4f through (scale %.4f)\n", shares[i],
			       got, fitted.cloud_depth_scale);
			t_case_failed = 1;
		}
		/* the scale is what the layer's extinction took */
		CHECK_NEAR(fitted.layers[0].extinction_per_m,
			   plain.layers[0].extinction_per_m * fitted.cloud_depth_scale,
			   1e-12 * plain.layers[0].extinction_per_m);
		CHECK(plain.cloud_depth_scale == 1.0);
	}
	/* the genera's altostratus (tau 12) lets about exp(-0.27 x 12 /
	 * sin 52) = 1.6 % through: 3 % asks for a thinner one, 40 % for one
	 * far thinner */
	build_both(&wx, 0.03 * clear);
	CHECK(fitted.cloud_depth_scale < 1.0 && fitted.cloud_depth_scale > 0.5);
	build_both(&wx, 0.4 * clear);
	CHECK(fitted.cloud_depth_scale < 0.3);
	/* the whole beam: as thin as the fit goes */
	build_both(&wx, clear);
	CHECK_NEAR(fitted.cloud_depth_scale, CS_BEAM_FIT_K_MIN, 1e-6);
}

/* Heaped genera keep the genera's depth (their look is their contrast,
 * and their beam goes through their gaps); the sheet over them takes
 * the rest of the fit. */
static void heaps_keep_their_depth(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer l[2] = {{CS_CUMULUS, 0.4, 1200.0, 2200.0},
					 {CS_ALTOSTRATUS, 0.95, 3500.0, 5000.0}};
	state(&wx, 2, l);
	double clear = clear_dni(&wx);
	build_both(&wx, 0.2 * clear);
	CHECK(fitted.nlayers == 2);
	CHECK(fitted.layers[0].genus == CS_CUMULUS);
	CHECK(fitted.layers[0].extinction_per_m == plain.layers[0].extinction_per_m);
	CHECK(fitted.cloud_depth_scale < 1.0);
	CHECK_NEAR(fitted.layers[1].extinction_per_m,
		   plain.layers[1].extinction_per_m * fitted.cloud_depth_scale,
		   1e-12 * plain.layers[1].extinction_per_m);
	/* over 60 km: several of the cumulus's and the altostratus's tiles */
	CHECK_NEAR(scaled_beam(&fitted, 60000.0, 60), 0.2, 0.2 * 0.05);
	/* heaps alone: nothing to fit */
	state(&wx, 1, l);
	build_both(&wx, 0.9 * clear);
	CHECK(fitted.cloud_depth_scale == 1.0);
	CHECK(fitted.layers[0].extinction_per_m == plain.layers[0].extinction_per_m);
}

/* No fit without the forecast's beam, in fog, under a sun below 10 deg;
 * a weaker beam than the genera's does not thicken the sheets, a DNI of 0
 * thickens only sheets that let a beam through. */
static void the_fit_only_where_it_is_asked_for(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer cs = {CS_CIRROSTRATUS, 1.0, 8000.0, 9000.0};
	state(&wx, 1, &cs);
	CHECK(cs_scene_build(&fitted, &wx, wx.time_utc, get_noise()) == CS_OK);
	CHECK(fitted.cloud_depth_scale == 1.0);
	/* fog */
	wx.visibility_m = 500.0;
	build_both(&wx, 100.0);
	CHECK(fitted.cloud_depth_scale == 1.0);
	CHECK(fitted.layers[0].extinction_per_m == plain.layers[0].extinction_per_m);
	wx.visibility_m = 30000.0;
	/* the sun 5 deg up (Bern, 2021-06-14 at 03:55 UTC: sunrise at 03:31) */
	struct cs_wx dawn = wx;
	dawn.time_utc -= 10 * 3600.0 + 5 * 60.0;
	build_both(&dawn, 100.0);
	double el = asin(fitted.sun_dir.z) * 180.0 / 3.14159265358979323846;
	CHECK(el > 0.0 && el < CS_BEAM_FIT_MIN_ELEVATION_DEG);
	CHECK(fitted.cloud_depth_scale == 1.0);
	/* a beam, but less than the thin cirrostratus lets through: that may
	 * be the forecast's clear sky, and the sheet stays as it is */
	build_both(&wx, 0.5 * clear_dni(&wx));
	CHECK(fitted.cloud_depth_scale == 1.0);
	CHECK(fitted.layers[0].extinction_per_m == plain.layers[0].extinction_per_m);
	/* no beam: the thin cirrostratus (tau 0.8) thickens as far as the fit
	 * goes, and still lets a beam through */
	build_both(&wx, 0.0);
	CHECK_NEAR(fitted.cloud_depth_scale, CS_BEAM_FIT_K_MAX, 1e-6);
	CHECK(scaled_beam(&fitted, 40000.0, 24) > 0.1);
	/* no beam: an altostratus (tau 12: 1.6 % of the beam, delta-scaled)
	 * thickens until its beam is 1 % of the clear sky's, no more */
	const struct cs_wx_layer as = {CS_ALTOSTRATUS, 1.0, 3000.0, 5000.0};
	state(&wx, 1, &as);
	build_both(&wx, 0.0);
	CHECK(fitted.cloud_depth_scale > 1.0 && fitted.cloud_depth_scale < 1.5);
	CHECK_NEAR(scaled_beam(&fitted, 30000.0, 40), CS_BEAM_FIT_NONE,
		   0.05 * CS_BEAM_FIT_NONE + 0.001);
	/* no beam, and nimbostratus (tau 40) lets none through already */
	const struct cs_wx_layer ns = {CS_NIMBOSTRATUS, 1.0, 800.0, 3500.0};
	state(&wx, 1, &ns);
	build_both(&wx, 0.0);
	CHECK(fitted.cloud_depth_scale == 1.0);
}

/* Where the wind has carried the clouds does not change the factor: a
 * series' frames follow the forecast, not which cumulus happen to lie
 * over the site (fitted over a 10 km square, the capture's overcast
 * afternoon jumped from 0.13 to 0.44 and back to 0.20 in 45 minutes). */
static void the_factor_does_not_follow_the_drift(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer l[2] = {{CS_CUMULUS, 0.55, 700.0, 1900.0},
					 {CS_ALTOSTRATUS, 0.99, 3000.0, 5000.0}};
	state(&wx, 2, l);
	double clear = clear_dni(&wx);
	wx.drift.known = 1;
	wx.drift.since_utc = wx.time_utc - 86400.0;
	wx.drift.axis_deg = 290.0;
	double k0 = 0.0, lo = INFINITY, hi = 0.0;
	for (int i = 0; i < 8; i++) {
		wx.drift.east_m = -650000.0 + 2500.0 * i * i;
		wx.drift.north_m = 27000.0 - 1300.0 * i;
		build_both(&wx, 0.12 * clear);
		double k = fitted.cloud_depth_scale;
		k0 = i == 0 ? k : k0;
		lo = k < lo ? k : lo;
		hi = k > hi ? k : hi;
	}
	CHECK(k0 < 0.9);
	if (!(hi <= 1.03 * lo)) {
		printf("  the factor from %.4f to %.4f over the drifts\n", lo, hi);
		t_case_failed = 1;
	}
}

/* The bounds and the threshold as documented: at most 64 times thinner,
 * at most 4 times thicker, "no beam" below 1 % of the clear sky's; every
 * sheet genus fitted, no heap genus. */
static void the_documented_bounds_and_genera(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer as = {CS_ALTOSTRATUS, 1.0, 3000.0, 5000.0};
	state(&wx, 1, &as);
	double clear = clear_dni(&wx);
	build_both(&wx, clear);
	CHECK_NEAR(fitted.cloud_depth_scale, 0.015625, 1e-12);
	const struct cs_wx_layer cs = {CS_CIRROSTRATUS, 1.0, 8000.0, 9000.0};
	state(&wx, 1, &cs);
	build_both(&wx, 0.0);
	CHECK_NEAR(fitted.cloud_depth_scale, 4.0, 1e-9);
	/* between "none" and twice it the rules blend: no jump at 1 % */
	const struct cs_wx_layer ns = {CS_NIMBOSTRATUS, 1.0, 800.0, 3500.0};
	state(&wx, 1, &ns);
	double k[4], shares[4] = {0.0099, 0.0101, 0.015, 0.0201};
	for (int i = 0; i < 4; i++) {
		build_both(&wx, shares[i] * clear);
		k[i] = fitted.cloud_depth_scale;
	}
	CHECK(k[0] == 1.0);
	CHECK(k[1] < 1.0 && k[1] > 0.97);
	CHECK(k[2] < k[1] && k[3] < k[2]);
	/* at 2 % and more the nimbostratus (tau 40) lets the forecast's beam
	 * through */
	CHECK_NEAR(scaled_beam(&fitted, 30000.0, 40), 0.0201, 0.0201 * 0.05);
	/* which genera take the factor: a forecast with the whole clear beam
	 * thins every sheet as far as it goes and no heap */
	static const struct {
		enum cs_genus g;
		int sheet;
	} genera[] = {{CS_CIRRUS, 1},       {CS_CIRROCUMULUS, 1}, {CS_CIRROSTRATUS, 1},
		      {CS_ALTOCUMULUS, 0},  {CS_ALTOSTRATUS, 1},  {CS_NIMBOSTRATUS, 1},
		      {CS_STRATOCUMULUS, 0}, {CS_STRATUS, 1},     {CS_CUMULUS, 0},
		      {CS_CUMULONIMBUS, 0}};
	CHECK(sizeof genera / sizeof genera[0] == CS_GENUS_COUNT);
	for (size_t i = 0; i < sizeof genera / sizeof genera[0]; i++) {
		struct cs_wx_layer l = {genera[i].g, 0.9, 1500.0, 3500.0};
		if (genera[i].g == CS_CIRRUS || genera[i].g == CS_CIRROCUMULUS ||
		    genera[i].g == CS_CIRROSTRATUS)
			l.base_m = 8000.0, l.top_m = 9500.0;
		if (genera[i].g == CS_CUMULONIMBUS)
			l.top_m = 9000.0;
		state(&wx, 1, &l);
		build_both(&wx, clear);
		double want = genera[i].sheet ? 0.015625 : 1.0;
		if (!(fabs(fitted.cloud_depth_scale - want) <= 1e-12)) {
			printf("  %s: factor %g, expected %g\n", cs_genus_name(genera[i].g),
			       fitted.cloud_depth_scale, want);
			t_case_failed = 1;
		}
	}
}

/* The fit fades in with the sun between 8 and 12 deg: none below, all
 * of it above, and no jump at 10 deg. */
static void the_fit_fades_in_with_the_sun(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer as = {CS_ALTOSTRATUS, 1.0, 3000.0, 5000.0};
	state(&wx, 1, &as);
	double noon = wx.time_utc;
	/* the morning's times of these apparent elevations (bisection on the
	 * sun's position) */
	static const double want_deg[] = {7.8, 8.2, 9.95, 10.05, 12.2};
	double kk[5], at[5];
	for (int i = 0; i < 5; i++) {
		double lo = noon - 11.0 * 3600.0, hi = noon - 6.0 * 3600.0;
		for (int it = 0; it < 40; it++) {
			struct cs_sun sun;
			double mid = 0.5 * (lo + hi);
			CHECK(cs_sun_position(mid, wx.site.lat_deg, wx.site.lon_deg, &sun) == CS_OK);
			if (sun.apparent_elevation_deg < want_deg[i])
				lo = mid;
			else
				hi = mid;
		}
		at[i] = hi;
		wx.time_utc = hi;
		build_both(&wx, 200.0);
		double el = asin(fitted.sun_dir.z) * 180.0 / 3.14159265358979323846;
		CHECK_NEAR(el, want_deg[i], 0.01);
		kk[i] = fitted.cloud_depth_scale;
	}
	CHECK(kk[0] == 1.0);
	CHECK(kk[1] < 1.0 && kk[1] > 0.8);
	CHECK(kk[2] < kk[1] && kk[4] < kk[3]);
	CHECK(fabs(log(kk[3] / kk[2])) < 0.1 * fabs(log(kk[2])));
	/* above 12 deg the beam is the forecast's */
	wx.time_utc = at[4];
	build_both(&wx, 200.0);
	struct cs_wx w = wx;
	w.nlayers = 0;
	double clear = clear_dni(&w);
	CHECK_NEAR(scaled_beam(&fitted, 30000.0, 40), 200.0 / clear, 0.03 * 200.0 / clear);
}

/* A state with far sites is not fitted: their layers take over from the
 * site's across the area, and the layers' means do not multiply (under
 * a far site's altostratus and nimbostratus 15 km toward the sun, the
 * product had the site's altostratus let a forecast's 5 % through
 * unthinned). */
static void no_fit_with_far_sites(void)
{
	struct cs_wx wx;
	const struct cs_wx_layer as = {CS_ALTOSTRATUS, 0.99, 3000.0, 5000.0};
	state(&wx, 1, &as);
	double clear = clear_dni(&wx);
	wx.nfar = 1;
	wx.far[0].site = wx.site;
	snprintf(wx.far[0].site.name, sizeof wx.far[0].site.name, "west");
	wx.far[0].site.lon_deg -= 0.2; /* 15 km toward the afternoon sun */
	wx.far[0].precipitation_mm_h = 0.0;
	wx.far[0].visibility_m = 30000.0;
	wx.far[0].nlayers = 2;
	wx.far[0].layers[0] = (struct cs_wx_layer){CS_NIMBOSTRATUS, 1.0, 900.0, 2800.0};
	wx.far[0].layers[1] = as;
	build_both(&wx, 0.3 * clear);
	CHECK(fitted.cloud_depth_scale == 1.0);
	CHECK(fitted.nlayers == 3);
	for (int i = 0; i < fitted.nlayers; i++)
		CHECK(fitted.layers[i].extinction_per_m == plain.layers[i].extinction_per_m);
	wx.nfar = 0;
	build_both(&wx, 0.3 * clear);
	CHECK(fitted.cloud_depth_scale < 1.0);
}

static const struct t_case t_cases[] = {
	CASE(a_sheet_lets_the_forecasts_beam_through),
	CASE(heaps_keep_their_depth),
	CASE(the_fit_only_where_it_is_asked_for),
	CASE(the_factor_does_not_follow_the_drift),
	CASE(the_documented_bounds_and_genera),
	CASE(the_fit_fades_in_with_the_sun),
	CASE(no_fit_with_far_sites),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	cs_volume_free(&noise);
	TEST_EXIT();
}
