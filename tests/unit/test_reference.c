/* The reference path tracer against closed forms and published slab
 * values: energy conservation, single scattering, convergence, the
 * variance estimate, determinism. */
#include "core/color.h"
#include "core/err.h"
#include "core/hash.h"
#include "render/march.h"
#include "render/reference.h"
#include "render/scene.h"
#include "core/time.h"
#include "noise/volume.h"
#include "one_layer.h"
#include "test.h"

#include <stdlib.h>

/* A homogeneous plane-parallel slab of optical depth tau, 1 km thick at
 * 2..3 km, over black flat ground (which ends the paths that leave below,
 * as a black lower boundary does), lit by a sun of illuminance 1 at zenith
 * cosine mu0; one Henyey-Greenstein lobe of asymmetry g (or the two-lobe
 * mixture when two_lobe), single-scattering albedo w; no sky. */
static void slab(struct cs_scene *sc, double tau, double g, int two_lobe, double w,
		 double mu0)
{
	memset(sc, 0, sizeof *sc);
	sc->earth_radius_m = CS_EARTH_RADIUS_M;
	sc->nlayers = 1;
	sc->layers[0].kind = CS_LAYER_HOMOGENEOUS;
	sc->layers[0].base_m = 2000.0;
	sc->layers[0].top_m = 3000.0;
	sc->layers[0].homog_a = tau / 1000.0;
	sc->layers[0].coverage = 1.0;
	sc->albedo = w;
	if (two_lobe)
		sc->g_forward = 0.8, sc->g_back = -0.3, sc->w_forward = 0.75;
	else
		sc->g_forward = sc->g_back = g, sc->w_forward = 1.0;
	double th = acos(mu0);
	sc->sun_dir = v3(0.0, sin(th), mu0);
	sc->sun_illuminance[0] = sc->sun_illuminance[1] = sc->sun_illuminance[2] = 1.0;
	sc->effects = CS_FX_CLOUDS | CS_FX_SUN | CS_FX_GROUND;
}

/* The slab's plane albedo R and total transmittance T (direct beam
 * included) from n paths each way: radiance seen through cosine-weighted
 * directions just above and just below the slab, F = pi E[L]. */
static void slab_rt(const struct cs_scene *sc, int n, double *R, double *T)
{
	struct cs_reference_settings s = {1, 1, 0};
	struct cs_render_stats st = {0};
	double mu0 = sc->sun_dir.z, up = 0.0, down = 0.0;
	for (int i = 0; i < n; i++) {
		double u1 = cs_hash_unit(cs_hash3i(i, 0, 0, 99)), u2 = cs_hash_unit(cs_hash3i(i, 1, 0, 99));
		double r = sqrt(u1), phi = 2.0 * CS_PI * u2, z = sqrt(1.0 - u1), L[3], depth;
		uint64_t key = (uint64_t)cs_hash3i(i, 7, 3, 11) << 32 | cs_hash3i(i, 1, 2, 5);
		int hit;
		cs_reference_path(sc, &s, v3(0, 0, 3001), v3(r * cos(phi), r * sin(phi), -z), key, &st,
				  L, &hit, &depth);
		up += L[1];
		cs_reference_path(sc, &s, v3(0, 0, 1999), v3(r * cos(phi), r * sin(phi), z),
				  key ^ 0x9e3779b97f4a7c15ull, &st, L, &hit, &depth);
		down += L[1];
	}
	double tau = sc->layers[0].homog_a * 1000.0;
	*R = CS_PI * up / n / mu0;
	*T = CS_PI * down / n / mu0 + exp(-tau / mu0);
}

/* Plane albedo R and total transmittance T of homogeneous slabs against
 * the adding-doubling solution in tests/reference/slab-table.txt (an
 * independent solver that matches van de Hulst's 1980 tables to 1e-6),
 * isotropic, Henyey-Greenstein 0.85 and the clouds' two-lobe phase, with
 * and without absorption; with albedo 1 nothing is lost (R + T = 1). */
static void slab_matches_adding_doubling(void)
{
	static const struct {
		double tau, g;
		int two_lobe;
		double w, mu0, R, T;
		int n;
	} c[] = {
		{1.0, 0.0, 0, 1.0, 1.0, 0.3413288, 0.6586712, 8000},
		{4.0, 0.0, 0, 1.0, 1.0, 0.6909262, 0.3090738, 8000},
		{16.0, 0.0, 0, 1.0, 1.0, 0.9036315, 0.0963685, 8000},
		{4.0, 0.0, 0, 0.9, 1.0, 0.4081422, 0.1285237, 8000},
		{4.0, 0.85, 0, 1.0, 0.5, 0.4160225, 0.5839775, 60000},
		{16.0, 0.85, 0, 1.0, 0.5, 0.6974049, 0.3025951, 60000},
		{1.0, 0.0, 1, 0.99, 1.0, 0.1790525, 0.8075669, 30000},
		{8.0, 0.0, 1, 0.99, 1.0, 0.5932428, 0.2578325, 30000},
		{32.0, 0.0, 1, 1.0, 0.5, 0.9303116, 0.0696884, 30000},
	};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		struct cs_scene sc;
		slab(&sc, c[i].tau, c[i].g, c[i].two_lobe, c[i].w, c[i].mu0);
		double R, T;
		slab_rt(&sc, c[i].n, &R, &T);
		printf("  tau %g %s w %g mu0 %g: R %.4f (adding-doubling %.4f) T %.4f (%.4f)\n",
		       c[i].tau, c[i].two_lobe ? "two-lobe" : c[i].g > 0 ? "HG 0.85" : "isotropic",
		       c[i].w, c[i].mu0, R, c[i].R, T, c[i].T);
		CHECK_NEAR(R, c[i].R, 0.015);
		CHECK_NEAR(T, c[i].T, 0.015);
		if (c[i].w == 1.0)
			CHECK_NEAR(R + T, 1.0, 0.02);
	}
}

/* Single scattering (max_bounces 1) in a thin slab seen from above,
 * against the closed form L = w E p(theta) mu0 / (mu0 + mu)
 * (1 - exp(-tau (1/mu0 + 1/mu))) (e.g. Liou, An Introduction to
 * Atmospheric Radiation, 2002, eq. 6.2.3), for HG phase g = 0.85. */
static void single_scattering_matches_closed_form(void)
{
	static const double mus[] = {1.0, 0.5, 0.2};
	double tau = 0.2, mu0 = cos(40.0 * CS_PI / 180.0);
	struct cs_scene sc;
	slab(&sc, tau, 0.85, 0, 0.9, mu0);
	struct cs_reference_settings s = {1, 1, 1};
	for (int m = 0; m < 3; m++) {
		double mu = mus[m], sn = sqrt(1.0 - mu * mu);
		/* looking down, toward the sun's side: a scattering angle of
		 * acos(-mu mu0 - sn sin0) from the beam */
		cs_v3 d = v3(0.0, sn, -mu);
		struct cs_render_stats st = {0};
		double sum = 0.0, L[3], depth;
		int n = 60000, hit;
		for (int i = 0; i < n; i++) {
			uint64_t key = (uint64_t)cs_hash3i(i, m, 3, 11) << 32 | cs_hash3i(i, 1, m, 5);
			cs_reference_path(&sc, &s, v3(0, 0, 3001), d, key, &st, L, &hit, &depth);
			sum += L[1];
		}
		double cth = v3_dot(d, sc.sun_dir);
		double want = 0.9 * cs_phase_hg(cth, 0.85) * mu0 / (mu0 + mu) *
			      (1.0 - exp(-tau * (1.0 / mu0 + 1.0 / mu)));
		printf("  mu %.1f: L %.5f closed form %.5f\n", mu, sum / n, want);
		CHECK_NEAR(sum / n / want, 1.0, 0.03);
	}
}

/* A small image of the thin slab from below, single scattering: its
 * pixels' error against the closed form halves as the paths quadruple,
 * and the reported variance is the squared error it predicts. */
static double image_error(const struct cs_scene *sc, int spp, double want, double *mean_var)
{
	struct cs_camera cam;
	memset(&cam, 0, sizeof cam);
	cs_camera_init(&cam, sc, v3(0, 0, 10), 0.0, 0.0, 89.9, 2.0, 16, 16);
	float *px = malloc(16 * 16 * 5 * sizeof *px), *var = malloc(16 * 16 * sizeof *var);
	struct cs_reference_settings s = {spp, 7, 1};
	struct cs_render_stats st;
	CHECK(cs_render_reference(sc, &cam, &s, 2, NULL, NULL, px, var, &st) == CS_OK);
	double e2 = 0.0, v = 0.0;
	for (int i = 0; i < 256; i++) {
		double y = cs_luminance(px[i * 5], px[i * 5 + 1], px[i * 5 + 2]);
		e2 += (y - want) * (y - want);
		v += var[i];
	}
	free(px);
	free(var);
	*mean_var = v / 256;
	return sqrt(e2 / 256);
}

static void error_halves_as_paths_quadruple(void)
{
	struct cs_scene sc;
	double tau = 0.5, mu0 = 1.0;
	slab(&sc, tau, 0.0, 0, 1.0, mu0);
	sc.effects &= ~(unsigned)CS_FX_GROUND;
	/* from below, looking (nearly) straight up: the transmitted single
	 * scattering of an isotropic slab at mu = mu0 = 1, w tau e^-tau / 4 pi */
	double want = tau * exp(-tau) / (4.0 * CS_PI);
	double v16, v64, v256;
	double e16 = image_error(&sc, 16, want, &v16);
	double e64 = image_error(&sc, 64, want, &v64);
	double e256 = image_error(&sc, 256, want, &v256);
	printf("  rms error 16 spp %.3g, 64 %.3g, 256 %.3g; predicted %.3g %.3g %.3g\n", e16,
	       e64, e256, sqrt(v16), sqrt(v64), sqrt(v256));
	CHECK_NEAR(e16 / e64, 2.0, 0.5);
	CHECK_NEAR(e64 / e256, 2.0, 0.5);
	CHECK_NEAR(sqrt(v64) / e64, 1.0, 0.25);
	CHECK_NEAR(sqrt(v256) / e256, 1.0, 0.25);
}

/* The same seed gives the same image on one thread and on three. */
static void same_image_for_any_thread_count(void)
{
	struct cs_scene sc;
	slab(&sc, 4.0, 0.85, 1, 0.99, 0.7);
	struct cs_camera cam;
	memset(&cam, 0, sizeof cam);
	cs_camera_init(&cam, &sc, v3(0, 0, 10), 0.0, 0.0, 30.0, 60.0, 12, 8);
	float a[12 * 8 * 5], b[12 * 8 * 5];
	struct cs_reference_settings s = {4, 3, 0};
	struct cs_render_stats st;
	CHECK(cs_render_reference(&sc, &cam, &s, 1, NULL, NULL, a, NULL, &st) == CS_OK);
	CHECK(cs_render_reference(&sc, &cam, &s, 3, NULL, NULL, b, NULL, &st) == CS_OK);
	CHECK(memcmp(a, b, sizeof a) == 0);
	s.seed = 4;
	CHECK(cs_render_reference(&sc, &cam, &s, 3, NULL, NULL, b, NULL, &st) == CS_OK);
	CHECK(memcmp(a, b, sizeof a) != 0);
	s.spp = 0;
	CHECK(cs_render_reference(&sc, &cam, &s, 1, NULL, NULL, b, NULL, &st) == CS_EINVAL);
}

/* A 50 m cloud around the eye in a 1 km layer, looked through
 * horizontally (an 80 km crossing of the shell): every preset sees it at
 * every jitter of its steps, and the march, stratified near the eye, is
 * unbiased there: over jitters spread evenly across a step its optical
 * depth averages sigma 50 m (within 3 %), where a capped uniform march
 * would spread its few samples over 80 km and see the clear sky. */
static void every_preset_sees_a_small_cloud_around_the_eye(void)
{
	static const char *const q[] = {"low", "medium", "high", "reference"};
	enum { JITTERS = 64 };
	struct cs_scene sc;
	slab(&sc, 1.0, 0.0, 0, 1.0, 1.0);
	sc.layers[0].base_m = 500.0, sc.layers[0].top_m = 1500.0;
	sc.layers[0].homog_a = 0.001, sc.layers[0].homog_radius_m = 50.0;
	sc.effects = CS_FX_CLOUDS;
	double want = 0.001 * 50.0;
	for (int i = 0; i < 4; i++) {
		struct cs_render_settings s;
		CHECK(cs_render_quality(q[i], &s) == CS_OK);
		double sum = 0.0, least = INFINITY;
		for (int k = 0; k < JITTERS; k++) {
			struct cs_render_stats st = {0};
			struct cs_ray_result r;
			cs_render_ray(&sc, &s, v3(0, 0, 1000.0), v3(1.0, 0.0, 0.0),
				      (k + 0.5) / JITTERS, &st, &r);
			double tau = -log(r.transmittance);
			sum += tau;
			least = tau < least ? tau : least;
		}
		printf("  %s: optical depth %.5f over %d jitters (least %.5f; closed form %.5f)\n",
		       q[i], sum / JITTERS, JITTERS, least, want);
		CHECK(least > 0.2 * want);
		CHECK_NEAR(sum / JITTERS, want, 0.03 * want);
	}
}

/* The clouds' phase function has the asymmetry of water droplets in the
 * visible, g = <cos theta> = 0.85 (Hansen & Travis 1974; what the light
 * under the decks, deck.c, assumes): integrated over the sphere here,
 * not read from the parameters. */
static void cloud_phase_has_the_droplets_asymmetry(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nlayers = 0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, NULL) == CS_OK);
	double norm = 0.0, g = 0.0;
	int n = 200000;
	for (int i = 0; i < n; i++) {
		double mu = -1.0 + (i + 0.5) * 2.0 / n;
		double p = cs_phase_two_lobe(mu, sc.g_forward, sc.g_back, sc.w_forward, 1.0);
		norm += 2.0 * CS_PI * p * 2.0 / n;
		g += 2.0 * CS_PI * p * mu * 2.0 / n;
	}
	printf("  phase: integral %.4f, mean cosine %.4f\n", norm, g);
	CHECK_NEAR(norm, 1.0, 0.01);
	CHECK_NEAR(g, 0.85, 0.02);
	CHECK(sc.albedo > 0.9999);
}

/* The reference's ground irradiance under an isotropic slab of optical
 * depth 1 at a zenith sun of 1 klux: the beam exp(-1) (Beer-Lambert) and
 * the diffuse light the adding-doubling table's diffuse transmittance,
 * 0.2907918 klux, back from W/m^2 through the efficacies (95 lm/W beam at
 * 90 deg, 144 lm/W diffuse under a clear deck model). */
static void irradiance_under_a_slab(void)
{
	struct cs_scene sc;
	slab(&sc, 1.0, 0.0, 0, 1.0, 1.0);
	struct cs_reference_settings s = {1, 5, 0};
	struct cs_irradiance e;
	struct cs_render_stats st = {0};
	cs_reference_irradiance_at(&sc, &s, v3(0, 0, 600.0), 40000, &e, &st);
	double beam = e.dni_w_m2 * cs_beam_efficacy_lm_w(90.0) / 1000.0;
	double dif = e.dhi_w_m2 * cs_diffuse_efficacy_lm_w(1.0) / 1000.0;
	printf("  beam %.4f (exp(-1) %.4f), diffuse %.4f (adding-doubling 0.2908)\n", beam,
	       exp(-1.0), dif);
	CHECK_NEAR(beam, exp(-1.0), 0.01);
	CHECK_NEAR(dif, 0.2907918, 0.01);
}

/* A view of w x h pixels from eye_m above the site (azimuth, elevation,
 * field of view in degrees), rendered by the march at quality and by the
 * reference path tracer (an independent implementation of the transport:
 * delta tracking, no deck model, no octaves) with spp paths, the haze off
 * (the reference has none), its mean over the seeds 1 to seeds: the ratio
 * of their mean luminances, printed. */
enum { CMP_MAX_PX = 16 * 9 };
/* The same for nq presets against one set of references: ratio[i] of
 * qualities[i]. */
static void presets_over_references(const char *what, const struct cs_wx *wx,
				    const struct cs_volume *noise, double eye_m, double az,
				    double el, double fov, int w, int h,
				    const char *const *qualities, int nq, int spp, int seeds,
				    double *ratio)
{
	static struct cs_scene sc;
	CHECK(w * h <= CMP_MAX_PX);
	CHECK(cs_scene_build(&sc, wx, wx->time_utc, noise) == CS_OK);
	sc.haze_beta0_per_m = 0.0;
	struct cs_camera cam;
	CHECK(cs_camera_init(&cam, &sc, v3(0, 0, wx->site.alt_m + eye_m), wx->site.lat_deg, az, el,
			     fov, w, h) == CS_OK);
	static float m[CMP_MAX_PX * 5], r[CMP_MAX_PX * 5];
	struct cs_render_stats st;
	double yr = 0.0;
	for (int k = 1; k <= seeds; k++) {
		struct cs_reference_settings rs = {spp, (uint32_t)k, 0};
		CHECK(cs_render_reference(&sc, &cam, &rs, 2, NULL, NULL, r, NULL, &st) == CS_OK);
		for (int i = 0; i < w * h; i++)
			yr += cs_luminance(r[i * 5], r[i * 5 + 1], r[i * 5 + 2]) / seeds;
	}
	for (int q = 0; q < nq; q++) {
		struct cs_render_settings s;
		CHECK(cs_render_quality(qualities[q], &s) == CS_OK);
		CHECK(cs_render_image(&sc, &cam, &s, 2, NULL, NULL, m, &st) == CS_OK);
		double ym = 0.0;
		for (int i = 0; i < w * h; i++)
			ym += cs_luminance(m[i * 5], m[i * 5 + 1], m[i * 5 + 2]);
		printf("  %s: mean luminance: march (%s) %.4f, reference %.4f (%+.1f %%)\n", what,
		       qualities[q], ym / (w * h), yr / (w * h), 100.0 * (ym / yr - 1.0));
		ratio[q] = ym / yr;
	}
}

static double march_over_references(const char *what, const struct cs_wx *wx,
				    const struct cs_volume *noise, double eye_m, double az, double el,
				    double fov, int w, int h, const char *quality, int spp,
				    int seeds)
{
	double ratio;
	presets_over_references(what, wx, noise, eye_m, az, el, fov, w, h, &quality, 1, spp, seeds,
				&ratio);
	return ratio;
}

/* The same against one reference, of seed 1. */
static double march_over_reference(const char *what, const struct cs_wx *wx,
				   const struct cs_volume *noise, double eye_m, double az, double el,
				   double fov, int w, int h, const char *quality, int spp)
{
	return march_over_references(what, wx, noise, eye_m, az, el, fov, w, h, quality, spp, 1);
}

/* The 32^3 noise the march-against-path-tracer cases share, baked once
 * (freed by main). */
static struct cs_volume shared_noise;
static const struct cs_volume *noise32(void)
{
	if (shared_noise.data == NULL)
		CHECK(cs_volume_new(&shared_noise, 32, 32) == CS_OK &&
		      cs_volume_bake(&shared_noise, 0, NULL, NULL) == CS_OK);
	return &shared_noise;
}

/* Multiple scattering and sky light under a deck: a stratus of optical
 * depth 30 seen from below at noon, the march at "high", a small view up
 * into it (30 to 70 deg up): within 5 % (measured +0.7 % against 1024
 * paths a pixel, -1.6 % before the deck's lattice, tower_light.c's
 * deck_ratio; the accuracy study's overcast -0.6 %).  The deck's light
 * is its plane-parallel light field (cs_scene_deck_fields); the model of
 * the diffuse light that broken layers keep (the slab transmittances, the
 * escape function, the octaves) was -7.5 % here and -6.1 % in the study.
 * At 64 paths a pixel this view's reference scattered by 13 % (it said
 * +6.5 % for that model). */
static void overcast_from_below_matches_the_reference(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T11:00:00Z", CS_STRATUS, 1.0, 700.0, 1100.0, 20000.0);
	CHECK_NEAR(march_over_reference("overcast", &wx, noise32(), 2.0, 150.0, 50.0, 40.0, 8, 6, "high",
					1024),
		   1.0, 0.05);
}

/* Cumulus between the eye and a low sun (the silver lining, sun 9 deg up):
 * a small view toward the sun, the default preset's march within 15 %
 * (measured +2.3 %; +6.0 % when medium took 32 view and 8 light steps)
 * and the march at "high" within 8 % (-0.4 %) of the
 * reference path tracer.  A light march of equal steps over the long path
 * toward a low sun (2 km each) steps over the cloud around the point and
 * lights it: +44 % in the study, +29 % here, and this test fails; so it
 * does with the octaves' eccentricity halved at each order (Wrenninge's)
 * and the heaps' light taken over their footprint (-12.7 % at high). */
static void silver_lining_matches_the_reference(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T18:20:00Z", CS_CUMULUS, 0.4, 1500.0, 2800.0, 40000.0);
	CHECK_NEAR(march_over_reference("silver lining", &wx, noise32(), 2.0, 295.0, 6.0, 60.0, 16, 9,
					"medium", 64),
		   1.0, 0.15);
	CHECK_NEAR(march_over_reference("silver lining, high", &wx, noise32(), 2.0, 295.0, 6.0, 60.0,
					16, 9, "high", 256),
		   1.0, 0.08);
}

/* Cirrus at dusk (sun 3 deg up), looked at 15 deg up toward the sun's
 * side: the default preset's march within 10 % of the reference path
 * tracer (measured -0.1 %; +6.3 % in the previous release; the accuracy
 * study at high: +5.7 % then, -0.6 % now).  A thin veil shows the bright
 * sky behind it, forward-scattered; with the dome's mean light instead
 * (deck.sky_through and deck.sky_forward 0) this view measures -14.1 %
 * (the study's scene -15 % in an earlier release), and this test fails. */
static void cirrus_at_dusk_matches_the_reference(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T19:20:00Z", CS_CIRRUS, 0.4, 8500.0, 9500.0, 40000.0);
	CHECK_NEAR(march_over_reference("cirrus at dusk", &wx, noise32(), 2.0, 300.0, 15.0, 70.0, 16, 9,
					"medium", 64),
		   1.0, 0.10);
}

/* The same cirrus toward the sun at dusk low over the horizon (1 to 15
 * deg up), where the rays cross the veil on long slant paths: the march
 * at "high" within 3.5 % of the reference path tracer (measured +0.3 %
 * against 1024 paths a pixel).  The sky's light that the forward lobe
 * keeps along the ray dims along it as the beam does, by the similarity
 * depth (the path's Tsky, deck.sky_forward); added at full strength at
 * every depth instead (the previous release) it measured +11.1 %, with
 * the lobe's share 20 % smaller -4.7 % (20 % larger +7.4 %), and this
 * test fails. */
static double veil_low_at_dusk(const char *what, enum cs_genus g, double cover, double base_m,
			       double top_m)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T19:20:00Z", g, cover, base_m, top_m, 40000.0);
	return march_over_reference(what, &wx, noise32(), 2.0, 300.0, 8.0, 70.0, 16, 3, "high", 1024);
}

static void cirrus_low_over_the_horizon_matches_the_reference(void)
{
	CHECK_NEAR(veil_low_at_dusk("cirrus low at dusk", CS_CIRRUS, 0.4, 8500.0, 9500.0), 1.0, 0.035);
}

/* Cirrocumulus (6 to 7 km, half the sky) toward the sun at dusk low over
 * the horizon, a veil of another genus than the one the change was
 * measured on (held out): the march at "high" within 7 % of the
 * reference path tracer, measured -5.3 % against 1024 paths a pixel.
 * The previous release measured +13.9 %, and with the similarity depth
 * of deck.sky_forward 20 % larger, -8.5 %: both fail (20 % smaller,
 * -1.7 %, does not).  Altocumulus the same way, not tested: -10.8 %
 * (the previous release -13.1 %). */
static void cirrocumulus_low_over_the_horizon_matches_the_reference(void)
{
	CHECK_NEAR(veil_low_at_dusk("cirrocumulus low at dusk", CS_CIRROCUMULUS, 0.5, 6000.0, 7000.0),
		   1.0, 0.07);
}

/* A stratus deck and cumulus at noon seen toward the horizon (about 5 to
 * 19 deg up): the diffuse light leaving a cloud's base at a grazing angle
 * is dimmer than toward the zenith (the deck's light field; the escape
 * function, cs_slab_escape, for broken cloud).  The march at "high"
 * against the reference path tracer: the stratus within 10 % (measured
 * -2.2 % against 1024 paths a pixel, -5.7 % against this test's 256; with
 * the slab's mean radiance in every direction, +41.7 %), the cumulus within
 * 15 % (-0.3 %; -6.5 % at the previous high, 96 view and 8 light steps;
 * +12.5 % without the escape function and the cloud's reflection from
 * below; the accuracy study's fair cumulus went from +13 % to -2 %). */
static void cloud_bases_toward_the_horizon_match_the_reference(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T11:00:00Z", CS_STRATUS, 1.0, 700.0, 1100.0, 20000.0);
	CHECK_NEAR(march_over_reference("stratus toward the horizon", &wx, noise32(), 2.0, 150.0, 12.0,
					24.0, 16, 9, "high", 256),
		   1.0, 0.10);
	one_layer_wx(&wx, "2021-06-14T11:00:00Z", CS_CUMULUS, 0.3, 1500.0, 2800.0, 40000.0);
	CHECK_NEAR(march_over_reference("cumulus toward the horizon", &wx, noise32(), 2.0, 150.0, 12.0,
					24.0, 16, 9, "high", 64),
		   1.0, 0.15);
}

/* From inside a stratocumulus of 90 % cover (1000-1600 m, the eye at
 * 1300 m) looking 10 deg down, what the eye sees is lit from below, by
 * what the cloud under each point sends back up; looking 30 deg up, by
 * the light come down through the column above.  The march at "high"
 * within 8 % of the reference path tracer each way (measured -4.6 % and
 * -4.6 %), with each point's light read from the plane-parallel light
 * fields of its own column (cs_deck_field_source).  The previous
 * release's model of the diffuse light (slab transmittances, octaves)
 * measured +12.9 % and +9.0 %, and this test fails; so does one field at
 * the layer's mean depth read at the point's depth from the top (+35 %
 * down), and the diffuse light without the cloud's reflection from below
 * (-34 % down). */
static void inside_a_deck_the_cloud_below_lights_it(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T11:00:00Z", CS_STRATOCUMULUS, 0.9, 1000.0, 1600.0, 40000.0);
	CHECK_NEAR(march_over_reference("inside stratocumulus, 10 deg down", &wx, noise32(),
					1300.0 - wx.site.alt_m, 150.0, -10.0, 40.0, 16, 9, "high",
					256),
		   1.0, 0.08);
	CHECK_NEAR(march_over_reference("inside stratocumulus, 30 deg up", &wx, noise32(),
					1300.0 - wx.site.alt_m, 150.0, 30.0, 40.0, 16, 9, "high",
					256),
		   1.0, 0.08);
}

/* Layers of middle cover (between broken heaps and full decks), the
 * accuracy study's held-out scenes at 16 x 9 on a 32^3 noise: from inside
 * stratocumulus of cover 0.75 (1200-1900 m, the eye at 1550 m, 5 deg
 * down toward the afternoon sun's side), the tops of stratocumulus of
 * cover 0.7 (1000-1700 m) seen from 800 m above them (15 deg down), and altocumulus of
 * cover 0.8 from the ground (25 deg up).  The march at "high" within
 * 10 % of the reference path tracer each (measured +0.7, -3.1 and
 * -1.8 %; -3.2 and -4.3 % for the tops and the altocumulus without the
 * octaves' share beside the fields, integrator.c's sample_source), each
 * point lit from the light fields of its own column.  The
 * previous release's model of the diffuse light, a slab of the layer's
 * mean depth under the local column above, measured -28.5, -30.3 and
 * -23.4 %, and this test fails. */
static void middle_cover_matches_the_reference(void)
{
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T15:00:00Z", CS_STRATOCUMULUS, 0.75, 1200.0, 1900.0, 20000.0);
	CHECK_NEAR(march_over_reference("inside broken stratocumulus", &wx, noise32(),
					1550.0 - wx.site.alt_m, 200.0, -5.0, 70.0, 16, 9, "high", 256),
		   1.0, 0.10);
	one_layer_wx(&wx, "2021-06-14T12:00:00Z", CS_STRATOCUMULUS, 0.7, 1000.0, 1700.0, 20000.0);
	CHECK_NEAR(march_over_reference("stratocumulus tops from above", &wx, noise32(),
					2500.0 - wx.site.alt_m, 90.0, -15.0, 70.0, 16, 9, "high", 256),
		   1.0, 0.10);
	one_layer_wx(&wx, "2021-06-14T09:00:00Z", CS_ALTOCUMULUS, 0.8, 3500.0, 4300.0, 30000.0);
	CHECK_NEAR(march_over_reference("altocumulus from below", &wx, noise32(),
					600.0 - wx.site.alt_m, 120.0, 25.0, 70.0, 16, 9, "high", 256),
		   1.0, 0.10);
}

/* The cases that take most of this binary's time are left to the plain
 * and ASan runs under ThreadSanitizer (283 s with them there, 57 s
 * without, alone on a 2-core machine): their threads (the pool's renders,
 * the lattice's solve) are run there by same_image_for_any_thread_count,
 * test_tower_light's exchange_is_the_same_on_any_number_of_threads and
 * render_info.sh. */
#define SLOW_UNDER_TSAN()                                                             \
	do {                                                                          \
		if (t_under_tsan())                                                   \
			SKIP("minutes under ThreadSanitizer; the plain and ASan runs " \
			     "compare it");                                           \
	} while (0)

/* Cumulonimbus towers of 12 % cover from the ground, the march at "high"
 * against the reference path tracer: under a low evening sun looking at
 * their sunlit walls within 10 % (measured +7.8 %; +6.5 % without the
 * light the towers' faces exchange through clear air, +1.7 % without the
 * towers' diffused light, tower_light.c, and -4.3 % before the sky and
 * the ground were let in through the face the eye sees; the reference's
 * own scatter between seeds about 3 % at 256 paths a pixel), and under
 * an afternoon sun looking up at an anvil within 20 % (measured +8.6 %,
 * +6.0 % without the exchange, -8.5 % without the diffused light),
 * towers of 35 % cover under the low sun within 15 % (measured +11.1 %,
 * +11.2 % without the exchange, +3.2 % without the diffused light,
 * -2.3 % before the face).  The anvil and the 35 % cover are measured against the
 * mean of four seeds of 128 paths: one seed's scatter is 6 to 8 %.
 * The towers take the sun's diffuse light from their tilted columns
 * (cs_deck_tilt_source), 0.6 of it at their walls (integrator.c's
 * TILT_WALL), all of it up to 20 % cover and none from 50 %
 * (CS_DECK_TILT_FULL, CS_DECK_TILT_NONE): the octaves and vertical columns before measured -58.8 % on
 * the walls, and fail; all of the columns' light +32 %, 0.48 of it
 * -14.8 %, fail too (0.72 of it, +7.0 %, passes); the sky's light let in
 * through the thinnest face whichever way it faces made the anvil's
 * underside the sky's blue, +68.5 %, and fails; the columns' light at
 * every cover made the 35 % cover +46 %, and fails; read toward the
 * opposite direction (the sign of the direction's cosine with the way to
 * the sun flipped), the walls measured -26.6 %, and fail. */
static void cumulonimbus_matches_the_reference(void)
{
	SLOW_UNDER_TSAN();
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T18:00:00Z", CS_CUMULONIMBUS, 0.12, 1200.0, 11000.0, 40000.0);
	CHECK_NEAR(march_over_reference("cumulonimbus walls under a low sun", &wx, noise32(), 0.0,
					100.0, 10.0, 60.0, 8, 5, "high", 256),
		   1.0, 0.10);
	one_layer_wx(&wx, "2021-06-14T15:00:00Z", CS_CUMULONIMBUS, 0.12, 1200.0, 11000.0, 40000.0);
	CHECK_NEAR(march_over_references("cumulonimbus anvil from below", &wx, noise32(), 0.0,
					 150.0, 10.0, 60.0, 8, 5, "high", 128, 4),
		   1.0, 0.20);
	one_layer_wx(&wx, "2021-06-14T18:00:00Z", CS_CUMULONIMBUS, 0.35, 1200.0, 11000.0, 40000.0);
	CHECK_NEAR(march_over_references("cumulonimbus of 35 % cover under a low sun", &wx,
					 noise32(), 0.0, 100.0, 10.0, 60.0, 8, 5, "high", 128, 4),
		   1.0, 0.15);
}

/* Cumulonimbus walls in the shade: towers of 12 % cover under an
 * afternoon sun (42 deg up, azimuth 259 deg), seen from the ground
 * looking 10 deg up away from the sun (azimuth 50 deg), the march at
 * "high" against the mean of four references (seeds 1 to 4, 256 paths a
 * pixel each; one seed's mean luminance scatters by 7 % here) within
 * 11 % (measured +3.0 %, -1.8 % without the light the towers' faces
 * exchange through clear air; -6.9 % without the towers' diffused light,
 * tower_light.c, then -8.2 % against four of 1024 paths).  The walls
 * the eye sees there face away from the sun and are lit by the sky and
 * the ground they face: their light comes in through the face the eye
 * sees, its normal the way the extinction falls (integrator.c's
 * tilt_light).  Before it, with the sky's light let in only through the
 * faces toward the sun, away from it along the beam (looking down: 16 %
 * of the sky) and the top, they measured -15.6 %, and fail.  Without the
 * ground's light through that face -7.4 %, and with the face seeing 20 %
 * less of the sky -9.4 %, both within this noise: the sky's share of a
 * face has its own test (test_render's face_sky_share_is_the_view_factor). */
static void cumulonimbus_walls_in_the_shade_match_the_reference(void)
{
	SLOW_UNDER_TSAN();
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T15:00:00Z", CS_CUMULONIMBUS, 0.12, 1200.0, 11000.0, 40000.0);
	CHECK_NEAR(march_over_references("cumulonimbus walls in the shade", &wx, noise32(), 0.0,
					 50.0, 10.0, 60.0, 8, 5, "high", 256, 4),
		   1.0, 0.11);
}

/* Fog of 300 m visibility at a low morning sun (7 deg), looked through
 * horizontally, and 45 deg up toward the sun's azimuth and away from it:
 * the march's fog light (the scene's solution of the fog's light field,
 * cs_scene_fog_light) against the reference path tracer, mean luminance
 * within 5 % each (measured +0.1 %, +0.7 % and +1.9 %).  The droplets
 * scatter forward, so the light in the fog remembers where the sun is:
 * the reference sees 45 deg up 1.28 times brighter toward the sun than
 * away from it.  The field's azimuthal mean alone (one Fourier mode) was
 * -16 % and +14 % there; the isotropic fog light before it, +7 % along
 * the horizon but 1.5 times too bright along it against 20 deg up. */
static void fog_at_low_sun_matches_the_reference(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	CHECK(cs_time_parse("2021-10-10T06:30:00Z", &wx.time_utc) == CS_OK);
	wx.nlayers = 0;
	wx.visibility_m = 300.0;
	wx.precipitation_mm_h = 0.0;
	/* the haze is off: the air above the fog, which the reference has not */
	CHECK_NEAR(march_over_reference("fog", &wx, NULL, 2.0, 105.0, 10.0, 30.0, 8, 4, "high", 256), 1.0,
		   0.05);
	CHECK_NEAR(march_over_reference("fog, 45 deg up toward the sun", &wx, NULL, 2.0, 105.0, 45.0,
					30.0, 8, 4, "high", 256),
		   1.0, 0.05);
	CHECK_NEAR(march_over_reference("fog, 45 deg up away from it", &wx, NULL, 2.0, 285.0, 45.0,
					30.0, 8, 4, "high", 256),
		   1.0, 0.05);
}

/* Where layer ui's column over 5 x 5 points 150 m apart around a point
 * of a 100 m grid over 8 x 8 km is least (a gap's middle) and most (a
 * cell's), into (x[0], y[0]) and (x[1], y[1]), the columns' means into
 * tau[]. */
static void gap_and_cell(const struct cs_scene *sc, int ui, double x[2], double y[2],
			 double tau[2])
{
	const struct cs_cloud_layer *u = &sc->layers[ui];
	tau[0] = INFINITY, tau[1] = -1.0;
	for (int j = -40; j <= 40; j++)
		for (int i = -40; i <= 40; i++) {
			double t = 0.0;
			for (int dj = -2; dj <= 2; dj++)
				for (int di = -2; di <= 2; di++)
					t += cs_cloud_column(u, sc->noise, i * 100.0 + di * 150.0,
							     j * 100.0 + dj * 150.0, u->base_m,
							     u->top_m, 24) /
					     25.0;
			int k = t < tau[0] ? 0 : t > tau[1] ? 1 : -1;
			if (k >= 0)
				tau[k] = t, x[k] = i * 100.0, y[k] = j * 100.0;
		}
}

/* Cumulus of 10 % cover (600-1400 m) under stratocumulus of 60 %
 * (2000-2800 m) at noon: the light at the cumulus's top under the
 * middle of a gap and of a cell of the stratocumulus, that of the column
 * over the point (cs_deck_top_shade), within 15 % of the reference path
 * tracer's irradiance there (GHI; measured -10.0 % in the gap, whose
 * walls and the ground's return add diffuse light, and -0.5 % under the
 * cell of optical depth 22).  The area's mean, which lit every point of
 * a layer under another before, measured -38 % and +164 %, and fails. */
/* The two layers of the cases below: cumulus of 10 % cover (600-1400 m)
 * under stratocumulus of 60 % (2000-2800 m) at time_utc over Bern;
 * index of the cumulus into *li. */
static void cumulus_under_a_deck(struct cs_scene *sc, const char *time_utc, int *li)
{
	struct cs_wx wx;
	two_layer_wx(&wx, time_utc, CS_CUMULUS, 0.1, 600.0, 1400.0, CS_STRATOCUMULUS, 0.6, 2000.0,
		     2800.0);
	wx.visibility_m = 40000.0;
	CHECK(cs_scene_build(sc, &wx, wx.time_utc, noise32()) == CS_OK);
	*li = sc->layers[0].genus == CS_CUMULUS ? 0 : 1;
	CHECK(sc->deck.over_mask[*li] == 1u << (1 - *li) && sc->deck.over_mask[1 - *li] == 0u);
}

/* The light at the top of layer li at (x, y) that cs_deck_top_shade
 * gives, the key light's depth from the light march as the march takes
 * it (cs_light_depth_over), against the reference path tracer's
 * irradiance there: the ratio of their GHI, printed. */
static double top_light_over_reference(const char *what, const struct cs_scene *sc, int li,
				       double x, double y)
{
	const struct cs_deck *d = &sc->deck;
	cs_v3 p = v3(x, y, sc->layers[li].top_m - sc->ground_alt_m);
	struct cs_render_settings s;
	CHECK(cs_render_quality("high", &s) == CS_OK);
	struct cs_render_stats st = {0};
	double tau_key, sun[3], dif[3];
	uint64_t n = 0;
	cs_light_depth_over(sc, &s, p, 1u << li, d->over_mask[li], &tau_key, &st);
	cs_deck_top_shade(sc, li, x, y, 24, 0, tau_key, sun, dif, &n);
	struct cs_irradiance m, r;
	cs_irradiance_from_klux(sc, p, sun[1] / d->mu0, dif[1], &m);
	struct cs_reference_settings rs = {1, 7, 0};
	cs_reference_irradiance_at(sc, &rs, p, 8192, &r, &st);
	printf("  %s: GHI %.1f W/m^2 (DHI %.1f), the reference's %.1f (%.1f) (%+.1f %%)\n", what,
	       m.ghi_w_m2, m.dhi_w_m2, r.ghi_w_m2, r.dhi_w_m2, 100.0 * (m.ghi_w_m2 / r.ghi_w_m2 - 1.0));
	return m.ghi_w_m2 / r.ghi_w_m2;
}

/* Cumulus under stratocumulus at noon (the sun 65 deg up): the light at
 * the cumulus's top under the middle of a gap and of a cell of the
 * stratocumulus, that of the columns over the point
 * (cs_deck_top_shade), within 15 % of the reference path tracer's
 * irradiance there (GHI; measured -10.0 % in the gap, whose walls and
 * the ground's return add diffuse light, and -0.6 % under the cell of
 * optical depth 22).  The area's mean, which lit every point of a layer
 * under another before, measured -38 % and +164 %, and fails. */
static void a_layer_under_a_broken_deck_is_lit_by_the_column_over_it(void)
{
	static struct cs_scene sc;
	int li;
	cumulus_under_a_deck(&sc, "2021-06-14T11:00:00Z", &li);
	double x[2], y[2], tau[2];
	gap_and_cell(&sc, 1 - li, x, y, tau);
	CHECK(tau[0] < 0.1 && tau[1] > 10.0);
	CHECK_NEAR(top_light_over_reference("under a gap", &sc, li, x[0], y[0]), 1.0, 0.15);
	CHECK_NEAR(top_light_over_reference("under a cell", &sc, li, x[1], y[1]), 1.0, 0.15);
}

/* The same under an afternoon sun (16:00 UTC, 32 deg up), at a point
 * whose column up is clear but whose path toward the sun crosses a cell
 * (optical depth 38), and at one the other way about (20.7 up): within
 * 25 % (measured +8.8 % and -18.9 %; the second, beside the cell's
 * sunlit side, takes 142 W/m^2 of diffuse light against the path
 * tracer's 300: the column up counts no side).  The column up for the
 * beam too measured +202 % and -83.5 %, and fails. */
static void a_layer_under_a_broken_deck_takes_the_beam_of_its_slant_path(void)
{
	static struct cs_scene sc;
	int li;
	cumulus_under_a_deck(&sc, "2021-06-14T16:00:00Z", &li);
	const struct cs_cloud_layer *u = &sc.layers[1 - li];
	struct cs_render_settings s;
	CHECK(cs_render_quality("reference", &s) == CS_OK);
	struct cs_render_stats st = {0};
	/* the most depth toward the sun with a clear column up, and the
	 * most up with a clear path toward the sun */
	double best[2] = {0.0, 0.0}, x[2] = {0.0, 0.0}, y[2] = {0.0, 0.0};
	for (int j = -40; j <= 40; j++)
		for (int i = -40; i <= 40; i++) {
			double px = i * 100.0, py = j * 100.0;
			cs_v3 p = v3(px, py, sc.layers[li].top_m - sc.ground_alt_m);
			double up = cs_cloud_column(u, sc.noise, px, py, u->base_m, u->top_m, 24);
			double key = cs_layer_depth(&sc, &s, 1 - li, p, sc.sun_dir, &st);
			if (up < 0.01 && key > best[0])
				best[0] = key, x[0] = px, y[0] = py;
			if (key < 0.01 && up > best[1])
				best[1] = up, x[1] = px, y[1] = py;
		}
	printf("  clear up, %.1f toward the sun; clear toward the sun, %.1f up\n", best[0], best[1]);
	CHECK(best[0] > 5.0 && best[1] > 5.0);
	CHECK_NEAR(top_light_over_reference("clear up, a cell toward the sun", &sc, li, x[0], y[0]),
		   1.0, 0.25);
	CHECK_NEAR(top_light_over_reference("a cell up, clear toward the sun", &sc, li, x[1], y[1]),
		   1.0, 0.25);
}

/* The underside of a broken rain deck: nimbostratus (834-4034 m) from the
 * ground 15 deg up, away from an afternoon sun 35 deg up, against the
 * mean of two references of 128 paths a pixel.  Of 70 % cover within 6 %
 * (measured +0.2 %; -0.2 % without the octaves' share beside the fields,
 * below), of 60 % within 8 % (-3.3 %; -3.6 %), where the fields light
 * half of the light.
 * With each point lit by the fields of its own column alone, the light a
 * thick cell takes in through its sides from the gaps not counted (an
 * earlier release; --tower-cell 0), the 70 % measured -35.9 %; with the
 * lattice's ratio itself, not raised to CS_DECK_LATTICE_POWER, -8.7 %,
 * and raised to 1.5, +9.1 %; with the lattice's fluence taken where more
 * than the fields' (its radiance lacks the base's darkening toward the
 * horizon) +14.7 %.  The 60 % measured +12.1 % when the ratio scaled the
 * march's model's share of the light as well as the fields' (+22.1 %
 * with the power).  Each of those fails this test.  Low and medium
 * (whose lattice's faces toward the gaps take the sky's and the ground's
 * light, not the exchange) within 8 and 6 % of the 70 % and medium
 * within 8 % of the 60 % (measured +4.7, -1.1 and -5.4 %); with their
 * columns alone (--deck-lattice off, as earlier releases) -29.8, -33.6
 * and -20.0 %.  The 70 % raining 2 mm/h, seen 5 deg up (the rain in
 * front of the deck and over the ground): high and medium within 10 %,
 * low within 7 % (measured -8.0, -8.5 and -6.1 %); without the octaves'
 * share beside the fields (integrator.c, sample_source: the light the
 * beam brings in through a cell's nearer side, the glow around the sun
 * seen from under the deck, which lights the drops and the ground)
 * -10.7, -11.3 and -7.2 %, and with the ground lit by what comes down the
 * rain's column from under the base, and the drops by their column alone
 * (cs_ground_sky_field's one plane, an earlier release), -15.9, -16.0
 * and -11.6 %: both fail.  What is left is mostly the deck's underside
 * straight overhead, too dark from the ground (the study's
 * broken-deck-below). */
static void a_broken_deck_from_below_takes_light_through_its_cells_sides(void)
{
	SLOW_UNDER_TSAN();
	static const struct {
		double cover, rain_mm_h, el_deg;
		const char *what, *quality[3];
		double tolerance[3];
	} c[] = {{0.7, 0.0, 15.0, "nimbostratus of 70 % from below", {"high", "medium", "low"},
		  {0.06, 0.06, 0.08}},
		 {0.6, 0.0, 15.0, "nimbostratus of 60 % from below", {"high", "medium", NULL},
		  {0.08, 0.08, 0.0}},
		 {0.7, 2.0, 5.0, "nimbostratus of 70 % raining 2 mm/h", {"high", "medium", "low"},
		  {0.10, 0.10, 0.07}}};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		struct cs_wx wx;
		one_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_NIMBOSTRATUS, c[i].cover, 834.0, 4034.0,
			     20000.0);
		wx.precipitation_mm_h = c[i].rain_mm_h;
		int nq = c[i].quality[2] != NULL ? 3 : 2;
		double ratio[3];
		presets_over_references(c[i].what, &wx, noise32(), 2.0, 80.0, c[i].el_deg, 70.0, 16, 9,
					c[i].quality, nq, 128, 2, ratio);
		for (int q = 0; q < nq; q++)
			CHECK_NEAR(ratio[q], 1.0, c[i].tolerance[q]);
	}
}

/* Overcast under overcast: stratus of full cover (700-1100 m, as in
 * overcast_from_below_matches_the_reference) under altostratus of full
 * cover (3000-3800 m) at noon, seen from the ground straight up and 50
 * deg up away from the sun, the march at "high" within 5 % of the
 * reference path tracer (measured -1.0 and -0.3 %; -1.8 and -1.2 %
 * before the forward peak's light was the beam, deck.sun_lobe).  The
 * light that the
 * stratus's top and the ground send up, the altostratus sends back down,
 * over and over (deck.top_extra: 0.85 of what comes through it once,
 * here); without it the stratus's fields were lit by what comes through
 * the altostratus once, -46.9 and -46.5 %, as the capture's rain hour's
 * nimbostratus under its cirrostratus (the picture -16 %, +1 % with
 * it).  Toward the sun (150 deg) the march measured -8.3 % (-50.4 %
 * without), -7.5 % with the forward peak's light: the light the
 * altostratus lets through comes down near the sun's direction, and the
 * stratus's fields take most of it as the sky's, the same from every
 * side. */
static void a_deck_under_a_deck_takes_the_light_they_send_between_them(void)
{
	struct cs_wx wx;
	two_layer_wx(&wx, "2021-06-14T11:00:00Z", CS_STRATUS, 1.0, 700.0, 1100.0, CS_ALTOSTRATUS,
		     1.0, 3000.0, 3800.0);
	CHECK_NEAR(march_over_reference("stratus under altostratus, straight up", &wx, noise32(), 2.0,
					330.0, 90.0, 40.0, 8, 6, "high", 1024),
		   1.0, 0.05);
	CHECK_NEAR(march_over_reference("stratus under altostratus, away from the sun", &wx, noise32(),
					2.0, 330.0, 50.0, 40.0, 8, 6, "high", 1024),
		   1.0, 0.05);
}

/* What a layer takes from the layers over it (deck.top_extra, the light
 * sent between them; deck.sun_lobe, the forward peak's): nothing with no
 * layer over it, so that a scene of one layer renders the same bytes as
 * before they were (all of the accuracy study's scenes); nothing either
 * for cumulus whose top lies inside nimbostratus of 70 % (the capture's
 * rain hour: with it, its cumulus took the nimbostratus's own light as
 * sent between two layers and the picture was +44 %); and for stratus
 * under altostratus, light sent between them, and the forward peak's
 * light at least the unscattered beam. */
static void what_a_layer_takes_from_the_layers_over_it(void)
{
	static struct cs_scene sc;
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_NIMBOSTRATUS, 0.7, 834.0, 4034.0, 20000.0);
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, noise32()) == CS_OK);
	CHECK(memcmp(sc.deck.sun_lobe[0], sc.deck.sun_top[0], sizeof sc.deck.sun_top[0]) == 0);
	CHECK(sc.deck.top_extra[0][0] == 0.0 && sc.deck.top_extra[0][1] == 0.0 &&
	      sc.deck.top_extra[0][2] == 0.0);
	two_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_NIMBOSTRATUS, 0.7, 834.0, 4034.0, CS_CUMULUS,
		     0.1, 650.0, 1850.0);
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, noise32()) == CS_OK);
	int cu = sc.layers[0].genus == CS_CUMULUS ? 0 : 1;
	CHECK(sc.deck.top_extra[cu][1] == 0.0);
	two_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_STRATUS, 1.0, 700.0, 1100.0, CS_ALTOSTRATUS,
		     1.0, 3000.0, 3800.0);
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, noise32()) == CS_OK);
	int st = sc.layers[0].genus == CS_STRATUS ? 0 : 1;
	printf("  stratus under altostratus: sent between them %.2f klux, the forward peak's %.2f "
	       "(the beam %.4f)\n",
	       sc.deck.top_extra[st][1], sc.deck.sun_lobe[st][1], sc.deck.sun_top[st][1]);
	CHECK(sc.deck.top_extra[st][1] > 0.0 && sc.deck.top_extra[1 - st][1] == 0.0);
	CHECK(sc.deck.sun_lobe[st][1] > sc.deck.sun_top[st][1]);
}

/* A deck under a veil: altostratus of 99 % (3000-5000 m) under
 * cirrostratus of full cover (7500-9000 m) in the afternoon (the sun 35
 * deg up), seen from the ground 20 deg up away from the sun, the march at
 * "high" within 3 % of the mean of two references of 256 paths (measured
 * -1.7 %).  Of the sun's light that the cirrostratus scatters, its
 * forward peak keeps most along the beam, and the altostratus's fields
 * take that as the sun's beam (deck.sun_lobe); taken as the sky's light
 * from every side, as all of the scattered light was before, +9.6 %.
 * Toward the sun (250 deg) it is the other way about: +12.4 % with the
 * peak's light as the beam, -3.1 % without (it comes down spread over
 * the peak's width, some 20 deg, not along the beam; the capture's
 * overcast afternoon, whose cumulus are under its altostratus, toward
 * the sun -10.1 and -16.1 %, away +2.3 and +8.5 %). */
static void a_deck_under_a_veil_takes_its_forward_peak_as_the_beam(void)
{
	struct cs_wx wx;
	two_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_ALTOSTRATUS, 0.99, 3000.0, 5000.0,
		     CS_CIRROSTRATUS, 1.0, 7500.0, 9000.0);
	CHECK_NEAR(march_over_references("altostratus under cirrostratus, away from the sun", &wx,
					 noise32(), 2.0, 70.0, 20.0, 60.0, 16, 9, "high", 256, 2),
		   1.0, 0.03);
}

/* Rain under nimbostratus of full cover (834-4034 m), 16 mm/h (optical
 * depth 1.7 from the ground to the base), seen from the ground 5 deg up
 * away from an afternoon sun at medium, against the mean of two
 * references of 2048 paths a pixel: within 10 % (measured +9.4 %; +8.2 %
 * before the drops near the ground took the field's ground plane's light,
 * whose rays through the rain bring 2 % more than the two-stream column
 * gives under a uniform deck; +6.2 % before medium's deck took the
 * lattice's diffusion (deck_lattice), which brightens even a full deck's
 * thick spots; against two of 8192, +4.8 % then, and high +6.8 %, without
 * rain +0.3 %).  The drops
 * take the light of their column as the two-stream solution has it
 * (cs_rain_column), and the clouds over them see the rain and the ground
 * together as their floor (deck.albedo_in).  With single scattering of
 * the light that reaches the ground, high was -24.8 % (against 8192
 * paths); with the column's light but the plain ground as the clouds'
 * floor, -14.7 % (high -13.1 %).  At 512 paths the reference was still
 * 3 % off its converged value. */
static void rain_under_a_deck_matches_the_reference(void)
{
	SLOW_UNDER_TSAN();
	struct cs_wx wx;
	one_layer_wx(&wx, "2021-06-14T15:30:00Z", CS_NIMBOSTRATUS, 1.0, 834.0, 4034.0, 20000.0);
	wx.precipitation_mm_h = 16.0;
	CHECK_NEAR(march_over_references("16 mm/h under nimbostratus", &wx, noise32(), 2.0, 80.0, 5.0,
					 70.0, 16, 9, "medium", 2048, 2),
		   1.0, 0.10);
}

static const struct t_case t_cases[] = {
	CASE(slab_matches_adding_doubling),
	CASE(single_scattering_matches_closed_form),
	CASE(error_halves_as_paths_quadruple),
	CASE(same_image_for_any_thread_count),
	CASE(every_preset_sees_a_small_cloud_around_the_eye),
	CASE(cloud_phase_has_the_droplets_asymmetry),
	CASE(irradiance_under_a_slab),
	CASE(overcast_from_below_matches_the_reference),
	CASE(fog_at_low_sun_matches_the_reference),
	CASE(silver_lining_matches_the_reference),
	CASE(cloud_bases_toward_the_horizon_match_the_reference),
	CASE(inside_a_deck_the_cloud_below_lights_it),
	CASE(middle_cover_matches_the_reference),
	CASE(cumulonimbus_matches_the_reference),
	CASE(cumulonimbus_walls_in_the_shade_match_the_reference),
	CASE(cirrus_at_dusk_matches_the_reference),
	CASE(cirrus_low_over_the_horizon_matches_the_reference),
	CASE(cirrocumulus_low_over_the_horizon_matches_the_reference),
	CASE(a_layer_under_a_broken_deck_is_lit_by_the_column_over_it),
	CASE(a_layer_under_a_broken_deck_takes_the_beam_of_its_slant_path),
	CASE(a_broken_deck_from_below_takes_light_through_its_cells_sides),
	CASE(what_a_layer_takes_from_the_layers_over_it),
	CASE(a_deck_under_a_deck_takes_the_light_they_send_between_them),
	CASE(a_deck_under_a_veil_takes_its_forward_peak_as_the_beam),
	CASE(rain_under_a_deck_matches_the_reference),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	cs_volume_free(&shared_noise);
	TEST_EXIT();
}
