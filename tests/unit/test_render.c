#include "render/cloud.h"
#include "core/err.h"
#include "render/march.h"
#include "render/reference.h"
#include "render/render.h"
#include "render/scene.h"
#include "render/sky.h"
#include "test.h"
#include "core/color.h"
#include "core/time.h"

/* arrays of three doubles to and from cs_v3 */
#define V(a) v3((a)[0], (a)[1], (a)[2])
#define V_STORE(a, v) do { cs_v3 v_ = (v); (a)[0] = v_.x, (a)[1] = v_.y, (a)[2] = v_.z; } while (0)
#include "noise/volume.h"
#include "weather/wx.h"

#include <stdlib.h>

static struct cs_volume noise;

/* A scene with one homogeneous spherical shell (extinction a + b * relative
 * height) between base and top and nothing else: no ground, sky or haze. */
static void slab_scene(struct cs_scene *sc, double a, double b, double base,
		       double top)
{
	memset(sc, 0, sizeof *sc);
	sc->earth_radius_m = CS_EARTH_RADIUS_M;
	sc->nlayers = 1;
	sc->layers[0].kind = CS_LAYER_HOMOGENEOUS;
	sc->layers[0].base_m = base;
	sc->layers[0].top_m = top;
	sc->layers[0].homog_a = a;
	sc->layers[0].homog_b = b;
	sc->layers[0].coverage = 1.0;
	sc->albedo = 1.0;
	sc->g_forward = 0.8, sc->g_back = -0.3, sc->w_forward = 0.75;
	sc->sun_dir = v3(0.0, 0.0, 1.0);
	sc->effects = CS_FX_CLOUDS;
}

static struct cs_render_settings plain(int steps, int light_steps)
{
	struct cs_render_settings s = {steps, steps, light_steps, 1, 0, 0.0, 0, 0.0, 0, 0, 0, 1, 0.0, 0, CS_GROUND_SKY_COLUMNS, 0};
	return s;
}

static void trace(const struct cs_scene *sc, const struct cs_render_settings *s,
		  cs_v3 o, cs_v3 d, struct cs_ray_result *r)
{
	struct cs_render_stats st = {0};
	cs_render_ray(sc, s, o, d, 0.5, &st, r);
}

/* Chord length of a ray from o (inside radius r... or outside) through the
 * sphere of radius r about the Earth's centre, from t >= 0 on: independent
 * of the renderer's own intersection code. */
static double chord(cs_v3 o, cs_v3 d, double r)
{
	double R = CS_EARTH_RADIUS_M;
	double ox = o.x, oy = o.y, oz = o.z + R;
	double b = ox * d.x + oy * d.y + oz * d.z;
	double c = ox * ox + oy * oy + oz * oz - r * r;
	double disc = b * b - c;
	if (disc <= 0)
		return 0;
	double t0 = -b - sqrt(disc), t1 = -b + sqrt(disc);
	t0 = t0 > 0 ? t0 : 0;
	return t1 > t0 ? t1 - t0 : 0;
}

static void slab_transmittance_is_beer_lambert(void)
{
	static const double sigmas[] = {1e-4, 1e-3, 5e-3, 2e-2};
	static const double thick[] = {100, 1000, 3000};
	static const int steps[] = {1, 3, 16, 256};
	for (size_t i = 0; i < 4; i++)
		for (size_t j = 0; j < 3; j++)
			for (size_t k = 0; k < 4; k++) {
				struct cs_scene sc;
				slab_scene(&sc, sigmas[i], 0, 1000, 1000 + thick[j]);
				struct cs_render_settings s = plain(steps[k], 1);
				struct cs_ray_result r;
				/* straight up */
				trace(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), &r);
				CHECK_NEAR(r.transmittance, exp(-sigmas[i] * thick[j]), 1e-4);
				/* slanted, 20 degrees above the horizon: the path
				 * through the shell from an independent formula */
				cs_v3 d = v3(0, cos(0.349), sin(0.349));
				double L = chord(v3(0, 0, 0), d, CS_EARTH_RADIUS_M + 1000 + thick[j]) -
					   chord(v3(0, 0, 0), d, CS_EARTH_RADIUS_M + 1000);
				trace(&sc, &s, v3(0, 0, 0), d, &r);
				CHECK_NEAR(r.transmittance, exp(-sigmas[i] * L), 1e-4);
			}
}

static double phase2(const struct cs_scene *sc, double mu)
{
	return sc->w_forward * cs_phase_hg(mu, sc->g_forward) +
	       (1 - sc->w_forward) * cs_phase_hg(mu, sc->g_back);
}

/* Single scattering in a homogeneous slab lit by a sun of illuminance 1,
 * seen from below looking up, against the closed form of the integral
 * L = int_0^d sigma p T_view(t) T_sun(t) dt (flat-slab form; the shell's
 * curvature changes it by less than 1e-4 here). */
static void slab_single_scattering_matches_closed_form(void)
{
	static const double sigmas[] = {1e-3, 4e-3};
	static const double zenith_deg[] = {0.0, 30.0, 60.0};
	double d = 1000.0;
	for (size_t i = 0; i < 2; i++)
		for (size_t z = 0; z < 3; z++) {
			struct cs_scene sc;
			slab_scene(&sc, sigmas[i], 0, 2000, 2000 + d);
			double th = zenith_deg[z] * CS_PI / 180.0, mu = cos(th);
			sc.sun_dir = v3(0, sin(th), mu);
			sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
			sc.effects |= CS_FX_SUN;
			struct cs_render_settings s = plain(64, 8);
			struct cs_ray_result r;
			trace(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), &r);
			double sg = sigmas[i], p = phase2(&sc, mu), want;
			if (fabs(1 - 1 / mu) < 1e-12)
				want = sg * p * d * exp(-sg * d);
			else
				want = sg * p * exp(-sg * d / mu) *
				       (1 - exp(-sg * d * (1 - 1 / mu))) / (sg * (1 - 1 / mu));
			CHECK_NEAR(r.rgb[1] / want, 1.0, 0.01);
		}
}

/* Midpoint samples with analytic step integration converge at second order:
 * each doubling of the steps at least halves the error. */
static void doubling_steps_halves_the_error(void)
{
	struct cs_scene sc;
	double a = 0.0002, b = 0.002, d = 1500.0; /* rising 11x upward, depth 1.8 */
	slab_scene(&sc, a, b, 1000, 1000 + d);
	sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
	sc.effects |= CS_FX_SUN;
	/* reference: Simpson's rule on the exact integrand, 2*10^5 intervals */
	double p = phase2(&sc, 1.0), ref = 0.0;
	int N = 200000;
	for (int i = 0; i <= N; i++) {
		double t = d * i / N, h = t / d;
		double sig = a + b * h;
		double tv = a * t + b * t * t / (2 * d);                 /* view depth */
		double tsun = (a * d + b * d / 2) - tv;                  /* to the top */
		double f = sig * p * exp(-tv - tsun);
		ref += f * (i == 0 || i == N ? 1 : i % 2 ? 4 : 2);
	}
	ref *= d / N / 3;
	double prev = -1;
	for (int n = 4; n <= 64; n *= 2) {
		struct cs_render_settings s = plain(n, 4);
		struct cs_ray_result r;
		trace(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), &r);
		double err = fabs(r.rgb[0] - ref) / ref;
		printf("  steps %2d: relative error %.3g\n", n, err);
		if (prev > 0) {
			if (!(err <= prev / 2))
				printf("  steps %d: error %.3g, previous %.3g\n", n, err, prev);
			CHECK(err <= prev / 2);
		}
		prev = err;
	}
	CHECK(prev < 1e-3);
}

/* The adaptive march (--march adaptive) marches a step deeper than 0.5 in
 * optical depth again in ceil(depth / 0.5) parts, at most 4.  Through a
 * slab deep enough that every one of 4 steps splits into 4 (extinction
 * 0.02 to 0.03 /m over 400 m: 2 to 3 a step) it is the standard march of
 * 16 steps; through a slab rising from 0.001 to 0.021 /m over 300 m in 4
 * steps (depths at the midpoints 0.26, 0.64, 1.01, 1.39) it looks up
 * 4 + 2 + 3 + 3 samples; through a thin one (no step deeper than 0.5) it
 * is the standard march, bit for bit. */
static void adaptive_march_refines_dense_steps(void)
{
	struct cs_scene sc;
	struct cs_render_settings s;
	struct cs_ray_result rs, ra;
	struct cs_render_stats st = {0};
	static const struct { double a, b, d; int steps, fine; } deep[] = {
		{0.02, 0.01, 400.0, 4, 16}, {0.0002, 0.002, 1500.0, 8, 8}};
	for (int i = 0; i < 4; i++) { /* each at the jitter 0.5 and 0.2 */
		double u = i & 1 ? 0.2 : 0.5;
		slab_scene(&sc, deep[i / 2].a, deep[i / 2].b, 1000, 1000 + deep[i / 2].d);
		sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
		sc.effects |= CS_FX_SUN;
		s = plain(deep[i / 2].fine, 4);
		s.min_transmittance = 0.0;
		cs_render_ray(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), u, &st, &rs);
		s = plain(deep[i / 2].steps, 4);
		s.min_transmittance = 0.0;
		s.march = CS_MARCH_ADAPTIVE;
		cs_render_ray(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), u, &st, &ra);
		printf("  %d steps, jitter %.1f: standard with %d %.9g, adaptive %.9g\n",
		       deep[i / 2].steps, u, deep[i / 2].fine, rs.rgb[0], ra.rgb[0]);
		if (i < 2)
			CHECK_NEAR(ra.rgb[0] / rs.rgb[0], 1.0, 1e-9);
		else
			CHECK(ra.rgb[0] == rs.rgb[0] && ra.transmittance == rs.transmittance);
	}
	st = (struct cs_render_stats){0};
	slab_scene(&sc, 0.001, 0.02, 1000, 1300);
	s = plain(4, 4);
	s.min_transmittance = 0.0;
	s.march = CS_MARCH_ADAPTIVE;
	cs_render_ray(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), 0.5, &st, &ra);
	CHECK(st.density_samples == 4 + 2 + 3 + 3);
}

static void phase_hg_is_normalised(void)
{
	static const double gs[] = {-0.5, 0.0, 0.3, 0.8, 0.95};
	for (size_t i = 0; i < 5; i++) {
		double sum = 0;
		int n = 200000;
		for (int k = 0; k < n; k++) {
			double mu = -1 + 2 * (k + 0.5) / n;
			sum += cs_phase_hg(mu, gs[i]) * 2 * CS_PI * 2.0 / n;
		}
		CHECK_NEAR(sum, 1.0, 2e-3);
	}
}

static void fair_weather(struct cs_wx *wx, double coverage)
{
	cs_wx_default(wx);
	wx->nlayers = 1;
	wx->layers[0].genus = CS_CUMULUS;
	wx->layers[0].coverage = coverage;
	wx->layers[0].base_m = 1500;
	wx->layers[0].top_m = 2700;
}

static int render_small(const struct cs_wx *wx, int w, int h, double el,
			int threads, float *px, struct cs_render_stats *st)
{
	struct cs_scene *sc = malloc(sizeof *sc);
	int rc = cs_scene_build(sc, wx, wx->time_utc, &noise);
	if (rc == CS_OK) {
		struct cs_camera cam;
		cs_v3 pos = v3(0, 0, wx->site.alt_m + 2);
		rc = cs_camera_init(&cam, sc, pos, wx->site.lat_deg, 160, el, 70, w, h);
		struct cs_render_settings s;
		cs_render_quality("low", &s);
		if (rc == CS_OK)
			rc = cs_render_image(sc, &cam, &s, threads, NULL, NULL, px, st);
	}
	free(sc);
	return rc;
}

static void clear_sky_has_no_alpha_and_costs_nothing(void)
{
	struct cs_wx wx;
	fair_weather(&wx, 0.0);
	float px[32 * 18 * 5];
	struct cs_render_stats st;
	CHECK(render_small(&wx, 32, 18, 20, 2, px, &st) == CS_OK);
	int nonzero = 0;
	for (int i = 0; i < 32 * 18; i++)
		nonzero += px[i * 5 + 3] != 0.0f;
	CHECK(nonzero == 0);
	CHECK(st.density_samples == 0 && st.light_samples == 0);
}

/* Fair weather calls for none of fog, rain, snow and halo: they are not in
 * its effects, and a scene with their machinery switched off by hand
 * renders the same pixels with exactly the same number of samples. */
static void absent_effects_cost_nothing(void)
{
	struct cs_wx wx;
	fair_weather(&wx, 0.4);
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(!(sc.effects & (CS_FX_FOG | CS_FX_RAIN | CS_FX_SNOW | CS_FX_HALO)));
	struct cs_camera cam;
	CHECK(cs_camera_init(&cam, &sc, v3(0, 0, wx.site.alt_m + 2), wx.site.lat_deg, 160, 20,
			     70, 24, 14) == CS_OK);
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	static float a[24 * 14 * 5], b[24 * 14 * 5];
	struct cs_render_stats sa, sb;
	CHECK(cs_render_image(&sc, &cam, &s, 1, NULL, NULL, a, &sa) == CS_OK);
	sc.fog_beta_per_m = 0.0, sc.rain_extinction_per_m = 0.0;
	sc.effects &= ~(unsigned)(CS_FX_FOG | CS_FX_RAIN | CS_FX_SNOW | CS_FX_HALO);
	CHECK(cs_render_image(&sc, &cam, &s, 1, NULL, NULL, b, &sb) == CS_OK);
	CHECK(memcmp(a, b, sizeof a) == 0);
	CHECK(sa.density_samples == sb.density_samples && sa.light_samples == sb.light_samples);
	CHECK(sa.density_samples > 0);
}

static double mean_alpha(double coverage)
{
	struct cs_wx wx;
	fair_weather(&wx, coverage);
	enum { W = 40, H = 24 };
	static float px[W * H * 5];
	struct cs_render_stats st;
	if (render_small(&wx, W, H, 35, 0, px, &st) != CS_OK)
		return -1;
	double sum = 0;
	for (int i = 0; i < W * H; i++)
		sum += px[i * 5 + 3];
	return sum / (W * H);
}

static void more_coverage_gives_more_cloud(void)
{
	double prev = -1;
	for (double c = 0.1; c < 0.95; c += 0.2) {
		double a = mean_alpha(c);
		printf("  coverage %.1f: mean alpha %.3f\n", c, a);
		CHECK(a > prev + 0.01);
		prev = a;
	}
	CHECK(mean_alpha(0.0) == 0.0);
}

static void output_is_identical_for_any_thread_count(void)
{
	struct cs_wx wx;
	fair_weather(&wx, 0.5);
	enum { W = 48, H = 27 };
	static float a[W * H * 5], b[W * H * 5], c[W * H * 5];
	struct cs_render_stats sa, sb, sc;
	CHECK(render_small(&wx, W, H, 15, 1, a, &sa) == CS_OK);
	CHECK(render_small(&wx, W, H, 15, 2, b, &sb) == CS_OK);
	CHECK(render_small(&wx, W, H, 15, 5, c, &sc) == CS_OK);
	CHECK(memcmp(a, b, sizeof a) == 0 && memcmp(a, c, sizeof a) == 0);
	CHECK(sa.density_samples == sb.density_samples &&
	      sa.density_samples == sc.density_samples);
}

static int finite_result(const struct cs_ray_result *r)
{
	for (int k = 0; k < 3; k++)
		if (!isfinite(r->rgb[k]) || r->rgb[k] < 0)
			return 0;
	return isfinite(r->transmittance) && r->transmittance >= 0 &&
	       r->transmittance <= 1 && isfinite(r->depth_m) && r->depth_m >= 0;
}

/* A full scene (real clouds, sky, haze, ground) with the sun at elevation
 * sun_el_deg. */
static void real_scene(struct cs_scene *sc, double sun_el_deg, double extinction_scale)
{
	struct cs_wx wx;
	fair_weather(&wx, 0.6);
	wx.nlayers = 2;
	wx.layers[1] = (struct cs_wx_layer){CS_CIRRUS, 0.5, 9000, 9600};
	cs_scene_build(sc, &wx, wx.time_utc, &noise);
	double e = sun_el_deg * CS_PI / 180.0;
	double sd[3] = {0, cos(e), sin(e)};
	cs_sky_init(&sc->sky, V(sd), 3.0);
	sc->sun_dir = v3(sd[0], sd[1], sd[2]);
	memcpy(sc->sun_illuminance, sc->sky.sun_illuminance, sizeof sc->sun_illuminance);
	sc->effects |= CS_FX_SUN | CS_FX_CLOUD_SHADOWS;
	for (int i = 0; i < sc->nlayers; i++)
		sc->layers[i].extinction_per_m *= extinction_scale;
}

static void hard_rays_stay_finite(void)
{
	static const double sun_el[] = {90, 45, 1, 0, -0.0001, -5, -30, -90};
	static const double scale[] = {1, 1e-12, 1e6};
	double R = CS_EARTH_RADIUS_M;
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	struct cs_scene *sc = malloc(sizeof *sc);
	for (size_t i = 0; i < sizeof sun_el / sizeof sun_el[0]; i++)
		for (size_t j = 0; j < 3; j++) {
			real_scene(sc, sun_el[i], scale[j]);
			struct {
				cs_v3 o, d;
			} rays[] = {
				/* horizontal at the layer base: parallel to the boundary */
				{v3(0, 0, 1500), v3(1, 0, 0)},
				/* starting inside the layer, every way */
				{v3(0, 0, 2000), v3(0, 0, 1)},
				{v3(0, 0, 2000), v3(0, 0, -1)},
				{v3(0, 0, 2000), v3(0.6, 0.8, 0)},
				/* from 5 km, tangent to the top and to the base of the
				 * layer: grazing both spheres */
				{v3(0, 0, 5000), v3(0, (R + 2700) / (R + 5000),
						    -sqrt(1 - pow((R + 2700) / (R + 5000), 2)))},
				{v3(0, 0, 5000), v3(0, (R + 1500) / (R + 5000),
						    -sqrt(1 - pow((R + 1500) / (R + 5000), 2)))},
				/* from far above, and from a huge distance */
				{v3(0, 0, 1e5), v3(0, 0.99999, -0.0044)},
				{v3(5e6, -5e6, 1e6), v3_norm(v3(-1, 1, -0.3))},
				{v3(0, 0, 1e9), v3(0, 0, -1)},
				/* straight down onto the ground, and along it */
				{v3(0, 0, 600), v3(0, 0, -1)},
				{v3(0, 0, 540.0000001), v3(0, 1, 0)},
			};
			for (size_t k = 0; k < sizeof rays / sizeof rays[0]; k++) {
				struct cs_ray_result r;
				cs_v3 d = v3_norm(rays[k].d);
				trace(sc, &s, rays[k].o, d, &r);
				if (!finite_result(&r))
					printf("  sun %g, scale %g, ray %zu: rgb %g %g %g T %g Z %g\n",
					       sun_el[i], scale[j], k, r.rgb[0], r.rgb[1],
					       r.rgb[2], r.transmittance, r.depth_m);
				CHECK(finite_result(&r));
			}
		}
	free(sc);
}

/* Many random scenes: random genera, coverages, altitudes, times (so sun
 * positions, day and night), cameras and looks; every pixel finite.  The
 * plain run renders 120; under a sanitizer the first 40 of them (each
 * scene is about a second there, most of it the scene's and the frame's
 * light: 132 s of the ASan run's 416, which CI runs twice, with
 * ThreadSanitizer too). */
static void random_scenes_render_finite_pixels(void)
{
	unsigned st = 31;
	enum { W = 12, H = 8 };
	float px[W * H * 5];
	int bad = 0, scenes = t_under_sanitizer() ? 40 : 120;
	for (int n = 0; n < scenes; n++) {
		struct cs_wx wx;
		cs_wx_default(&wx);
		wx.time_utc += t_uniform(&st, 0, 365 * 86400.0);
		wx.nlayers = (int)t_uniform(&st, 0, 4);
		for (int i = 0; i < wx.nlayers; i++) {
			double base = t_uniform(&st, 600, 11000);
			wx.layers[i] = (struct cs_wx_layer){
				(enum cs_genus)t_uniform(&st, 0, CS_GENUS_COUNT),
				t_uniform(&st, 0, 1), base, base + t_uniform(&st, 10, 6000)};
			if (wx.layers[i].top_m > 20000)
				wx.layers[i].top_m = 20000;
		}
		wx.visibility_m = t_uniform(&st, 50, 100000);
		wx.precipitation_mm_h = t_uniform(&st, 0, 2) < 1 ? 0 : t_uniform(&st, 0, 50);
		wx.wind_speed_m_s = t_uniform(&st, 0, 40);
		struct cs_scene *sc = malloc(sizeof *sc);
		if (cs_scene_build(sc, &wx, wx.time_utc, &noise) != CS_OK) {
			printf("  scene %d: %s\n", n, cs_errmsg());
			bad++;
			free(sc);
			continue;
		}
		struct cs_camera cam;
		cs_v3 pos = cs_geo_to_world(wx.site.lat_deg, wx.site.lon_deg, sc->earth_radius_m,
					    wx.site.lat_deg + t_uniform(&st, -0.3, 0.3),
					    wx.site.lon_deg + t_uniform(&st, -0.3, 0.3),
					    wx.site.alt_m + t_uniform(&st, 0, 15000));
		struct cs_render_settings s;
		cs_render_quality(n % 2 ? "low" : "medium", &s);
		s.jitter = t_uniform(&st, 0, 1);
		struct cs_render_stats rs;
		if (cs_camera_init(&cam, sc, pos, wx.site.lat_deg, t_uniform(&st, 0, 360),
				   t_uniform(&st, -90, 90), t_uniform(&st, 1, 179), W, H) != CS_OK ||
		    cs_render_image(sc, &cam, &s, 2, NULL, NULL, px, &rs) != CS_OK) {
			bad++;
		} else {
			for (int i = 0; i < W * H * 5; i++)
				if (!isfinite(px[i]) || px[i] < 0) {
					bad++;
					break;
				}
		}
		free(sc);
	}
	CHECK(bad == 0);
}

/* A higher cloud between a lower one and the sun shades it: the lower
 * slab's single scattering drops by exactly the higher cloud's
 * transmittance along the sun (the view ray misses the higher cloud). */
static void higher_clouds_shade_lower_ones(void)
{
	struct cs_scene sc;
	slab_scene(&sc, 0.002, 0, 1000, 1200);
	double e = 45 * CS_PI / 180;
	sc.sun_dir = v3(cos(e), 0, sin(e));
	sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
	sc.effects |= CS_FX_SUN;
	struct cs_render_settings s = plain(64, 12);
	struct cs_ray_result alone, shaded;
	trace(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), &alone);
	/* a disc of cloud 5000..5500 m, 3 km across, 4.5 km east: in the sun's
	 * way from the slab, not in the view's */
	sc.nlayers = 2;
	sc.layers[1] = sc.layers[0];
	sc.layers[1].base_m = 5000, sc.layers[1].top_m = 5500;
	sc.layers[1].homog_a = 0.001;
	sc.layers[1].homog_radius_m = 3000, sc.layers[1].homog_x = 4500;
	trace(&sc, &s, v3(0, 0, 0), v3(0, 0, 1), &shaded);
	double want = exp(-0.001 * 500 / sin(e));
	CHECK_NEAR(shaded.rgb[1] / alone.rgb[1], want, 0.01 * want);
	CHECK_NEAR(shaded.transmittance, alone.transmittance, 1e-12);
}

/* With one round cloud and a low sun, the centroid of its shadow on flat
 * ground lies at height / tan(sun elevation) from its footprint, away from
 * the sun (the system this project follows cast shadows straight down). */
static void cloud_shadow_is_displaced_along_the_sun(void)
{
	static const double elev_deg[] = {10, 20, 35, 60};
	for (size_t k = 0; k < 4; k++) {
		struct cs_scene sc;
		slab_scene(&sc, 0.01, 0, 1000, 1400);
		sc.layers[0].homog_radius_m = 300;
		double e = elev_deg[k] * CS_PI / 180;
		sc.sun_dir = v3(cos(e), 0, sin(e)); /* the sun in the east */
		sc.effects |= CS_FX_SUN | CS_FX_CLOUD_SHADOWS;
		struct cs_render_settings s = plain(32, 32);
		struct cs_render_stats st = {0};
		double want = -1200 / tan(e), sw = 0, sx = 0, sy = 0;
		for (double y = -1000; y <= 1000; y += 20)
			for (double x = want - 2500; x <= want + 2500; x += 20) {
				/* the ground point on the sphere under (x, y) */
				double z = sqrt(CS_EARTH_RADIUS_M * CS_EARTH_RADIUS_M - x * x - y * y) -
					   CS_EARTH_RADIUS_M;
				double w = 1 - cs_render_sun_transmittance(&sc, &s, v3(x, y, z), &st);
				sw += w, sx += w * x, sy += w * y;
			}
		CHECK(sw > 0);
		printf("  sun %2.0f deg: shadow centroid x %.1f m, expected %.1f m\n",
		       elev_deg[k], sx / sw, want);
		CHECK_NEAR(sx / sw / want, 1.0, 0.03);
		CHECK_NEAR(sy / sw, 0.0, 10.0);
	}
}

/* A point of the cumulus layer (1500-2700 m) within 4 km of the site,
 * from the linear congruential sequence *h: x, y and altitude, 20 m
 * inside the base and the top. */
static void cumulus_point(uint32_t *h, double *x, double *y, double *alt)
{
	double r[3];
	for (int c = 0; c < 3; c++) {
		*h = *h * 1664525u + 1013904223u;
		r[c] = (*h >> 8) / 16777216.0;
	}
	*x = (r[0] - 0.5) * 8000, *y = (r[1] - 0.5) * 8000, *alt = 1520 + r[2] * 1160;
}

/* The light cache (--light-march cache) against a fine march toward the
 * sun through the same cumulus layer (512 equal steps, no cache code),
 * at 400 points inside the layer within 4 km of the site, under a sun 40
 * deg up in the south-west and a wind from 250 deg that has blown for a
 * day: the mean optical depth within 3 % and the transmittance within
 * 0.03 on average (a ray sheared the wrong way round, or a path 20 %
 * too long, fails both); a point moved by one period of the field along
 * and across the wind has the same depth, marched or looked up (the
 * periods cs_cloud_periods gives); a sun below 15 deg has no cache.
 * The vertical columns' volume against cs_cloud_column at 1000 points:
 * the depth above a point within 3 % on average, below it within 5 %. */
static void light_cache_agrees_with_a_fine_march(void)
{
	struct cs_scene sc;
	memset(&sc, 0, sizeof sc);
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	sc.nlayers = 1;
	sc.noise = &noise;
	struct cs_wx_layer wl = {CS_CUMULUS, 0.5, 1500, 2700};
	cs_cloud_layer_init(&sc.layers[0], &wl, &noise, 6.0, 250.0, 540.0, 86400.0);
	double e = 40.0 * CS_PI / 180, az = 225.0 * CS_PI / 180; /* from north, clockwise */
	sc.sun_dir = v3(cos(e) * sin(az), cos(e) * cos(az), sin(e));
	sc.effects = CS_FX_CLOUDS | CS_FX_SUN;
	struct cs_render_settings fine = plain(32, 512), cached = plain(32, 12);
	cached.light_march = CS_LIGHT_CACHE;
	uint64_t evals = 0;
	CHECK(cs_light_cache_build(&sc, &cached, 0.0, 2, &evals) == CS_OK);
	CHECK(sc.light_cache[0].depth != NULL);
	CHECK(evals == (uint64_t)sc.light_cache[0].nu * sc.light_cache[0].nv *
			       (sc.light_cache[0].nh + 1));
	struct cs_render_stats st = {0};
	double sum_f = 0, sum_c = 0, dT = 0, pa = 0, pc = 0;
	int n = 0;
	CHECK(cs_cloud_periods(&sc.layers[0], &pa, &pc) == 1);
	CHECK_NEAR(pa, 24000.0, 1e-9); /* 8 km and 1.5 km tiles */
	CHECK_NEAR(pc, 24000.0, 1e-9);
	uint32_t h = 12345;
	for (int k = 0; k < 400; k++) {
		double x, y, alt;
		cumulus_point(&h, &x, &y, &alt);
		double Ra = CS_EARTH_RADIUS_M + alt; /* the point alt above the sphere */
		cs_v3 p = v3(x, y, sqrt(Ra * Ra - x * x - y * y) - CS_EARTH_RADIUS_M);
		double tf = cs_light_depth(&sc, &fine, p, 1u, &st);
		double tc = cs_light_depth(&sc, &cached, p, 1u, &st);
		sum_f += tf, sum_c += tc, dT += fabs(exp(-tf) - exp(-tc)), n++;
		if (k < 20) { /* one period on: the same field, the same depth */
			const struct cs_cloud_layer *l = &sc.layers[0];
			double ox = pa * l->wind_x - pc * l->wind_y, oy = pa * l->wind_y + pc * l->wind_x;
			cs_v3 q = v3(x + ox, y + oy, 0);
			q.z = sqrt(Ra * Ra - q.x * q.x - q.y * q.y) - CS_EARTH_RADIUS_M;
			CHECK_NEAR(cs_cloud_extinction(l, &noise, x + ox, y + oy, alt),
				   cs_cloud_extinction(l, &noise, x, y, alt), 1e-9);
			CHECK_NEAR(cs_light_depth(&sc, &cached, q, 1u, &st), tc, 1e-4 * (1 + tc));
		}
	}
	printf("  mean depth: cache %.4f, fine march %.4f; mean |dT| %.4f\n", sum_c / n,
	       sum_f / n, dT / n);
	CHECK(sum_f / n > 1.0); /* the test sees cloud */
	CHECK_NEAR(sum_c / sum_f, 1.0, 0.03);
	CHECK(dT / n < 0.03);
	cs_light_cache_free(&sc);
	/* auto (the presets'): the volume only for a frame of a pixel for
	 * every 32 of its cells, the same volume then */
	double cells = (double)evals;
	struct cs_render_settings autom = cached;
	autom.light_march = CS_LIGHT_AUTO;
	CHECK(cs_light_cache_build(&sc, &autom, ceil(cells / 32.0), 2, &evals) == CS_OK);
	CHECK(sc.light_cache[0].depth != NULL && evals == (uint64_t)cells);
	cs_light_cache_free(&sc);
	CHECK(cs_light_cache_build(&sc, &autom, ceil(cells / 32.0) - 1.0, 2, &evals) == CS_OK);
	CHECK(sc.light_cache[0].depth == NULL && evals == 0);
	CHECK(cs_light_cache_build(&sc, &autom, cells / 32.0, 2, &evals) == CS_OK);
	CHECK(sc.light_cache[0].depth != NULL); /* (exactly 32 cells a pixel: built) */
	cs_light_cache_free(&sc);
	/* (then the geometric march: the same depth as without a cache) */
	autom.light_march = CS_LIGHT_GEOMETRIC;
	{
		cs_v3 p = v3(1000.0, 2000.0, 1700.0);
		struct cs_render_settings a2 = autom;
		a2.light_march = CS_LIGHT_AUTO;
		CHECK(cs_light_depth(&sc, &a2, p, 1u, &st) == cs_light_depth(&sc, &autom, p, 1u, &st));
	}
	CHECK(sc.light_cache[0].depth == NULL);
	CHECK(sc.column_cache[0].depth == NULL); /* no light fields: no columns */
	sc.sun_dir = v3(cos(0.2), 0, sin(0.2)); /* 11.5 deg */
	CHECK(cs_light_cache_build(&sc, &cached, 0.0, 2, &evals) == CS_OK);
	CHECK(sc.light_cache[0].depth == NULL && evals == 0);

	/* the vertical columns (the diffuse light's, with the light fields
	 * on): the depth above a point and below it against 400 midpoint
	 * samples of cs_cloud_column, the same bounds */
	sc.deck.on = 1;
	cached.ambient = 1;
	CHECK(cs_light_cache_build(&sc, &cached, 0.0, 2, &evals) == CS_OK);
	const struct cs_light_cache *vc = &sc.column_cache[0];
	CHECK(vc->depth != NULL && vc->shear_u == 0.0 && vc->shear_v == 0.0);
	const struct cs_cloud_layer *l = &sc.layers[0];
	double sa_c = 0, sa_f = 0, sb_c = 0, sb_f = 0, dA = 0;
	for (int k = 0; k < 1000; k++) {
		double x, y, alt;
		cumulus_point(&h, &x, &y, &alt);
		double above = cs_cached_depth(l, vc, x, y, alt);
		double below = cs_cached_depth(l, vc, x, y, l->base_m) - above;
		double fa = cs_cloud_column(l, &noise, x, y, alt, l->top_m, 400);
		double fb = cs_cloud_column(l, &noise, x, y, l->base_m, alt, 400);
		CHECK(below >= -1e-6);
		sa_c += above, sa_f += fa, sb_c += below, sb_f += fb;
		dA += fabs(exp(-above) - exp(-fa));
	}
	printf("  column above: cache %.4f, 400 samples %.4f (mean |dT| %.4f); below: %.4f, "
	       "%.4f\n", sa_c / 1000, sa_f / 1000, dA / 1000, sb_c / 1000, sb_f / 1000);
	CHECK(sa_f / 1000 > 0.5 && sb_f / 1000 > 0.5);
	CHECK_NEAR(sa_c / sa_f, 1.0, 0.03);
	/* (+3.1 %: the flat base of a heap falls between the volume's levels,
	 * 50 m apart, and its midpoints count it from the level below) */
	CHECK_NEAR(sb_c / sb_f, 1.0, 0.05);
	CHECK(dA / 1000 < 0.03);
	cs_light_cache_free(&sc);
	CHECK(sc.column_cache[0].depth == NULL);
}

/* A hill in the terrain: a ray toward it stops on its surface (the depth is
 * the heightfield's intersection), a ray beside it reaches the flat ground
 * around the grid, and every value is finite. */
static void terrain_is_the_ground_where_it_is(void)
{
	enum { W = 81 };
	static float z[W * W];
	for (int j = 0; j < W; j++)
		for (int i = 0; i < W; i++) {
			double dx = (i - 40) * 25.0, dy = (j - 40) * 25.0;
			z[j * W + i] = (float)(500 + 400 * exp(-(dx * dx + dy * dy) / (2 * 300.0 * 300.0)));
		}
	double a[3] = {40 + 4000 / 25.0, 1 / 25.0, 0}, b[3] = {40, 0, -1 / 25.0};
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, W, a, b, CS_EARTH_RADIUS_M) == CS_OK);
	struct cs_scene *sc = malloc(sizeof *sc);
	real_scene(sc, 40, 1.0);
	sc->ground_alt_m = 500;
	sc->terrain = &f;
	sc->effects |= CS_FX_TERRAIN;
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	/* the hill's top is at x = -4000, y = 0, 900 m */
	cs_v3 o = v3(-7000, 0, 700), d = v3_norm(v3(1, 0, 0.02));
	struct cs_ray_result r;
	double t;
	CHECK(cs_hfield_intersect(&f, o, d, 1e6, &t, NULL));
	trace(sc, &s, o, d, &r);
	CHECK(finite_result(&r));
	CHECK(r.depth_m <= t + 1e-6); /* a cloud may come first, never beyond the hill */
	sc->nlayers = 0;
	trace(sc, &s, o, d, &r);
	CHECK_NEAR(r.depth_m, t, 1e-6);
	/* beside the grid the flat ground at 500 m */
	cs_v3 d2 = v3_norm(v3(0, 1, -0.05));
	trace(sc, &s, o, d2, &r);
	CHECK(finite_result(&r) && r.depth_m < 1e5);
	CHECK_NEAR(cs_scene_altitude(sc, v3_mad(o, d2, r.depth_m)), 500.0, 1e-3);
	free(sc);
	cs_hfield_free(&f);
}

static void quality_presets_exist_and_rise(void)
{
	struct cs_render_settings lo, me, hi, ref;
	CHECK(cs_render_quality("low", &lo) == CS_OK);
	CHECK(cs_render_quality("medium", &me) == CS_OK);
	CHECK(cs_render_quality("high", &hi) == CS_OK);
	CHECK(cs_render_quality("reference", &ref) == CS_OK);
	/* each preset does at least as much as the one below in every knob,
	 * and more in some */
	const struct cs_render_settings *p[] = {&lo, &me, &hi, &ref};
	for (int i = 0; i < 3; i++) {
		const struct cs_render_settings *a = p[i], *b = p[i + 1];
		CHECK(a->steps <= b->steps && a->max_steps <= b->max_steps &&
		      a->light_steps <= b->light_steps && a->ms_octaves <= b->ms_octaves &&
		      a->haze_steps <= b->haze_steps && a->min_transmittance >= b->min_transmittance &&
		      (a->source_every > 1 ? a->source_every : 1) >=
			      (b->source_every > 1 ? b->source_every : 1));
		CHECK(a->steps < b->steps || a->light_steps < b->light_steps);
	}
	CHECK(cs_render_quality("ultra", &lo) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "unknown quality 'ultra'");
}

/* A thick plane-parallel cloud transmits like 1/tau: for water-droplet
 * asymmetry g = 0.85 and an overhead sun about 0.45 at tau = 16 and 0.15
 * at tau = 64 (the similarity relation, shared/RADIATION-NOTES.md),
 * between the two-stream brackets 1/(1 + (1-g) tau / 2) and
 * 1/(1 + 3 (1-g) tau / 4); a lower sun's beam by the escape function
 * K(mu0) ~ (3/7)(1 + 2 mu0) (van de Hulst 1980, the Eddington
 * approximation): (1 + 2 mu0) / 3 of the overhead sun's, and diffuse light
 * 2 integral K(mu) mu dmu / K(1) = 7/9 of it, within 8 % from tau 16. */
static void thick_slab_transmits_like_one_over_tau(void)
{
	CHECK_NEAR(cs_slab_beam_transmittance(16.0, 1.0), 0.45, 0.045);
	CHECK_NEAR(cs_slab_beam_transmittance(64.0, 1.0), 0.15, 0.015);
	for (double x = 2.0; x <= 40.0; x *= 1.5) {
		double t = cs_slab_beam_transmittance(x / 0.15, 1.0);
		CHECK(t <= 1.0 / (1.0 + 0.5 * x) && t >= 1.0 / (1.0 + 0.75 * x));
	}
	for (double tau = 16.0; tau <= 1000.0; tau *= 2.0) {
		double t1 = cs_slab_beam_transmittance(tau, 1.0);
		for (double mu = 0.2; mu < 0.95; mu += 0.25)
			CHECK_NEAR(cs_slab_beam_transmittance(tau, mu) / t1, (1.0 + 2.0 * mu) / 3.0,
				   0.08 * (1.0 + 2.0 * mu) / 3.0);
		CHECK_NEAR(cs_slab_diffuse_transmittance(tau) / t1, 7.0 / 9.0, 0.08 * 7.0 / 9.0);
	}
	CHECK_NEAR(cs_slab_beam_transmittance(0.0, 0.5), 1.0, 0.0);
	CHECK_NEAR(cs_slab_beam_transmittance(0.01, 1.0), 1.0, 0.011);
	CHECK_NEAR(cs_slab_diffuse_transmittance(0.01), 1.0, 0.011);
	/* never below the direct beam */
	CHECK(cs_slab_beam_transmittance(0.5, 0.9) >= exp(-0.5 / 0.9));
}

/* Fog lights the ground with the part of the sun's beam it scatters down,
 * but only of the beam that reaches it: under an opaque deck (optical depth
 * 64, the beam e^-64 / mu0) a fog of 300 m visibility (tau 3.9) adds no
 * sunlight to the ground, whose light is then at most what it is without
 * the fog (the fog only takes away); with nothing above, the fog's share of
 * the low sun is most of the ground's light.  (Once the fog diffused the
 * unclouded sun under any deck; fog under stratocumulus at a low sun was
 * +51 % against the path tracer on the ground.  The fog's solution takes
 * the beam at its top through the deck, cs_scene_fog_light.) */
static void fog_under_a_deck_adds_no_sunlight(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 64.0 / 3200.0, 0.0, 800.0, 4000.0);
	double e = 10.0 * CS_PI / 180.0;
	sc.sun_dir = v3(0.0, cos(e), sin(e));
	for (int c = 0; c < 3; c++)
		sc.sun_illuminance[c] = 20.0, sc.ground_albedo[c] = 0.2;
	sc.effects |= CS_FX_SUN | CS_FX_GROUND | CS_FX_CLOUD_SHADOWS;
	struct cs_render_settings s = plain(64, 16);
	struct cs_render_stats st = {0};
	double with[3], without[3], open[3];
	sc.fog_top_m = 300.0;
	sc.fog_beta_per_m = 3.912 / 300.0;
	cs_scene_deck_light(&sc, 1);
	CHECK(cs_scene_fog_light(&sc, 1) == CS_OK);
	cs_ground_light(&sc, &s, v3(0, 0, 0), v3(0, 0, -1), 0, &st, with);
	sc.fog_beta_per_m = 0.0;
	CHECK(cs_scene_fog_light(&sc, 1) == CS_OK);
	cs_ground_light(&sc, &s, v3(0, 0, 0), v3(0, 0, -1), 0, &st, without);
	sc.nlayers = 0;
	cs_scene_deck_light(&sc, 1);
	sc.fog_beta_per_m = 3.912 / 300.0;
	CHECK(cs_scene_fog_light(&sc, 1) == CS_OK);
	cs_ground_light(&sc, &s, v3(0, 0, 0), v3(0, 0, -1), 0, &st, open);
	printf("  ground under the deck: %.3g with fog, %.3g without; under fog alone %.3g\n",
	       with[1], without[1], open[1]);
	CHECK(open[1] > 0.01);
	CHECK(with[1] <= without[1] + 1e-9);
}

/* The escape function against Chandrasekhar's exact one for conservative
 * isotropic scattering, sqrt(3)/4 H(mu) (H from its integral equation,
 * 1 / H(mu) = 1/2 int_0^1 mu' H(mu') / (mu + mu') dmu', solved here by
 * iteration on 400 midpoints; H(1) = 2.9078 in Chandrasekhar's table):
 * within 6 % from grazing to the normal (the Eddington form is lowest
 * against it, by about 5 %, at mu ~ 0.1, where H rises steeply), and
 * normalised, 2 int K mu dmu = 1.  3/7 off by 20 % fails both. */
static void escape_function_is_chandrasekhars(void)
{
	enum { N = 400 };
	static double H[N];
	for (int i = 0; i < N; i++)
		H[i] = 1.0;
	for (int it = 0; it < 200; it++) {
		double area = 0.0;
		for (int i = 0; i < N; i++) {
			double mu = (i + 0.5) / N, sum = 0.0;
			for (int j = 0; j < N; j++) {
				double mj = (j + 0.5) / N;
				sum += mj * H[j] / (mu + mj) / N;
			}
			H[i] = 1.0 / (0.5 * sum);
			area += H[i] / N;
		}
		/* conservative scattering: int H dmu = 2 (it speeds the iteration) */
		for (int i = 0; i < N; i++)
			H[i] *= 2.0 / area;
	}
	double norm = 0.0, worst = 0.0;
	for (int i = 0; i < N; i++) {
		double mu = (i + 0.5) / N, exact = sqrt(3.0) / 4.0 * H[i];
		CHECK_NEAR(cs_slab_escape(mu), exact, 0.06 * exact);
		worst = fmax(worst, fabs(cs_slab_escape(mu) / exact - 1.0));
		norm += 2.0 * cs_slab_escape(mu) * mu / N;
	}
	printf("  H(%.4f) = %.4f (table H(1) 2.9078), largest difference %.1f %%\n",
	       (N - 0.5) / N, H[N - 1], 100.0 * worst);
	CHECK_NEAR(H[N - 1], 2.9078, 0.01);
	CHECK_NEAR(norm, 1.0, 1e-4);
	CHECK_NEAR(cs_slab_escape(-0.5), cs_slab_escape(0.0), 0.0);
	CHECK_NEAR(cs_slab_escape(3.0), cs_slab_escape(1.0), 0.0);
}

/* The sky's share of a tilted plane (cs_face_sky_share, which a
 * cumulonimbus's faces take in integrator.c's tilt_light) against its
 * view factor of the upper hemisphere integrated here: the irradiance on
 * a plane of outward normal n from a radiance of 1 over the directions
 * above the horizon, over pi (a horizontal plane facing up), by the
 * midpoint rule in the polar angle and azimuth.  The closed form
 * (1 + n_z) / 2: 1 facing up, 1/2 for a wall, 0 facing down; at 0.4
 * (1 + n_z), 20 % less, a wall's 0.4 fails. */
static void face_sky_share_is_the_view_factor(void)
{
	enum { NT = 400, NP = 800 };
	const double nzs[] = {-1.0, -0.67, -0.3, 0.0, 0.24, 0.67, 1.0};
	for (size_t k = 0; k < sizeof nzs / sizeof nzs[0]; k++) {
		double nz = nzs[k], nx = sqrt(1.0 - nz * nz), sum = 0.0;
		for (int i = 0; i < NT; i++) {
			double th = (i + 0.5) * (0.5 * CS_PI) / NT; /* from the zenith */
			for (int j = 0; j < NP; j++) {
				double ph = (j + 0.5) * 2.0 * CS_PI / NP;
				double c = nx * sin(th) * cos(ph) + nz * cos(th);
				if (c > 0.0)
					sum += c * sin(th) * (0.5 * CS_PI / NT) * (2.0 * CS_PI / NP);
			}
		}
		CHECK_NEAR(cs_face_sky_share(nz), sum / CS_PI, 2e-3);
	}
	CHECK_NEAR(cs_face_sky_share(2.0), 1.0, 0.0);
	CHECK_NEAR(cs_face_sky_share(-2.0), 0.0, 0.0);
}

/* A homogeneous layer 0.01 /m from 1000 to 2000 m, lit by the sun, and
 * the medium preset's settings. */
static void sunlit_slab(struct cs_scene *sc, struct cs_render_settings *s)
{
	slab_scene(sc, 0.01, 0.0, 1000.0, 2000.0);
	sc->effects |= CS_FX_SUN;
	CHECK(cs_render_quality("medium", s) == CS_OK);
}

/* Beer's law through sunlit_slab's layer from 1 mm above its base toward a
 * sun tilt radians from the zenith, over the slant path through the
 * spherical shell, sqrt((R + top)^2 - (R + alt)^2 sin^2) - (R + alt) cos. */
static double sunlit_slab_beer(double tilt)
{
	double R = CS_EARTH_RADIUS_M, a = R + 1000.001, b = R + 2000.0, sn = sin(tilt);
	return exp(-0.01 * (sqrt(b * b - a * a * sn * sn) - a * cos(tilt)));
}

/* The geometric light march toward a sun at every tilt from the zenith,
 * through sunlit_slab's layer from 1 mm above its base: Beer's law over
 * the slant path (the midpoint rule is exact for a constant); among the
 * tilts those whose path is a hair longer than the
 * layer's thickness (1 + 1e-12 .. 1 + 1e-6 times: a float ratio that
 * rounded to 1 made it 0 / 0 once, a black pixel in fog). */
static void light_march_toward_any_sun_is_beer_lambert(void)
{
	static struct cs_scene sc;
	struct cs_render_settings s;
	sunlit_slab(&sc, &s);
	/* medium's: the light cache, which a homogeneous layer does not
	 * have; the geometric march it takes there, as such */
	CHECK(s.light_march == CS_LIGHT_AUTO);
	s.light_march = CS_LIGHT_GEOMETRIC;
	double tilts[12] = {0.0, 1e-3, 1e-2, 0.3, 0.8, 1.2};
	static const double hair[6] = {1e-12, 1e-10, 1e-9, 3e-8, 1e-7, 1e-6};
	for (int k = 0; k < 6; k++) /* slant path / thickness = 1 + hair */
		tilts[6 + k] = acos(0.999999 / (1.0 + hair[k]));
	for (int k = 0; k < 12; k++) {
		sc.sun_dir = v3(sin(tilts[k]), 0.0, cos(tilts[k]));
		struct cs_render_stats st = {0};
		double T = cs_render_sun_transmittance(&sc, &s, v3(0.0, 0.0, 1000.001), &st);
		double want = sunlit_slab_beer(tilts[k]);
		CHECK(isfinite(T));
		CHECK_NEAR(T, want, 1e-6 * want);
	}
}

/* --source-every 2 looking straight up under an overhead sun, single
 * scattering.  Through a uniform slab of optical depth 4 the sun's light
 * falls by e^-4 from the top to the base, 18 % a step of 24, and every
 * other sample takes the mean of its neighbours' light: within 1 % of
 * the march that finds the light at every sample (+0.64 % measured: the
 * mean of an exponential's two values lies above its middle one, by
 * cosh(0.167) - 1 = 1.4 % for each waiting sample); holding the light of
 * the sample before instead misses by -7.7 %, weights of 0.6 and 0.5 by
 * +3.9 %.  Its last sample waits and the crossing ends: it finds its own
 * light, one light march more than half.  Through a slab whose density
 * rises fivefold, the ray ending at its 16th sample (transmittance under
 * 5 %), which waits and takes the 15th's light: within 2.5 % (-1.2 %
 * measured; with the waiting sample's light dropped at the ray's end
 * -8.4 %), half the light marches.  The density at every sample. */
static void source_every_other_sample_is_the_mean_of_its_neighbours(void)
{
	static struct cs_scene sc;
	/* a uniform slab; then one whose density rises from 0.002 to 0.010
	 * per m, the ray ending where it sees less than 5 % */
	static const double ab[2][3] = {{0.004, 0.0, 0.0}, {0.002, 0.008, 0.05}};
	for (int c = 0; c < 2; c++) {
		slab_scene(&sc, ab[c][0], ab[c][1], 1000.0, 2000.0);
		sc.effects |= CS_FX_SUN;
		sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
		struct cs_render_settings s = plain(24, 12);
		s.min_transmittance = ab[c][2];
		struct cs_ray_result r[2];
		struct cs_render_stats st[2] = {{0}, {0}};
		for (int k = 0; k < 2; k++) {
			s.source_every = k + 1;
			cs_render_ray(&sc, &s, v3(0.0, 0.0, 1000.001), v3(0.0, 0.0, 1.0), 0.5,
				      &st[k], &r[k]);
		}
		printf("  radiance %.6g every sample, %.6g every other (%+.3f %%); light samples "
		       "%llu, %llu; density samples %llu, %llu\n",
		       r[0].rgb[1], r[1].rgb[1], 100.0 * (r[1].rgb[1] / r[0].rgb[1] - 1.0),
		       (unsigned long long)st[0].light_samples,
		       (unsigned long long)st[1].light_samples,
		       (unsigned long long)st[0].density_samples,
		       (unsigned long long)st[1].density_samples);
		CHECK(r[0].rgb[1] > 0.0);
		CHECK_NEAR(r[1].rgb[1], r[0].rgb[1], (c == 0 ? 0.01 : 0.025) * r[0].rgb[1]);
		CHECK(r[1].transmittance == r[0].transmittance);
		CHECK(st[1].density_samples == st[0].density_samples);
		/* light marches of 12 steps: half, and at the crossing's end
		 * (not the ray's) one more */
		CHECK(st[1].light_samples * 2 == st[0].light_samples + (c == 0 ? 24 : 0));
	}
	/* The steps' parity, in the CPU's batches of CS_MARCH_BATCH samples
	 * and one at a time (the skip march's loop, which a GPU runs for
	 * every march): 21 steps through the uniform slab, the last batch
	 * odd, the odd steps waiting, the last (even) finding its light;
	 * the skip march, which skips nothing in the slab, gives the same
	 * light from the same light marches.  (A parity off by one in either
	 * loop differs: the waiting samples move to the even steps and the
	 * last waits till the crossing ends.) */
	slab_scene(&sc, 0.004, 0.0, 1000.0, 2000.0);
	sc.effects |= CS_FX_SUN;
	sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 1.0;
	struct cs_render_settings s = plain(21, 12);
	s.source_every = 2;
	struct cs_ray_result r[2];
	struct cs_render_stats st[2] = {{0}, {0}};
	for (int k = 0; k < 2; k++) {
		s.march = k == 0 ? CS_MARCH_STANDARD : CS_MARCH_SKIP;
		cs_render_ray(&sc, &s, v3(0.0, 0.0, 1000.001), v3(0.0, 0.0, 1.0), 0.5, &st[k], &r[k]);
	}
	printf("  21 steps: radiance %.9g standard, %.9g skip; light samples %llu, %llu\n",
	       r[0].rgb[1], r[1].rgb[1], (unsigned long long)st[0].light_samples,
	       (unsigned long long)st[1].light_samples);
	CHECK(st[0].light_samples == 11 * 12 && st[1].light_samples == 11 * 12);
	CHECK_NEAR(r[1].rgb[1], r[0].rgb[1], 1e-12 * r[0].rgb[1]);
	/* a GPU renders it too (scripts/gpu-check) */
	s = plain(24, 12);
	s.source_every = 2;
	CHECK(cs_render_settings_gpu_check(&s) == CS_OK);
}

/* The cone light march (--light-march cone) spreads the geometric steps'
 * samples across the path, in the horizontal: through sunlit_slab's layer
 * it is Beer's law over the slant path for an overhead sun and suns 45 and
 * 15 deg up (paths 1.4 and 3.9 times the thickness: the geometric steps),
 * and beside a cloud it sees some of it where the path itself misses it:
 * that layer as a column 100 m in radius, the point 150 m from its axis at
 * 500 m, the sun overhead (the cone's radius is 200 m at 1000 m from the
 * point). */
static void cone_light_march_sees_beside_the_path(void)
{
	static struct cs_scene sc;
	struct cs_render_settings s;
	sunlit_slab(&sc, &s);
	s.light_march = CS_LIGHT_CONE;
	static const double tilts[3] = {0.0, 45.0, 75.0};
	struct cs_render_stats st = {0};
	for (int k = 0; k < 3; k++) {
		double th = tilts[k] * CS_PI / 180.0;
		sc.sun_dir = v3(sin(th), 0.0, cos(th));
		double T = cs_render_sun_transmittance(&sc, &s, v3(0.0, 0.0, 1000.001), &st);
		double want = sunlit_slab_beer(th);
		printf("  uniform slab, sun %2.0f deg up: cone %.6g, Beer %.6g\n", 90.0 - tilts[k],
		       T, want);
		CHECK_NEAR(T, want, 1e-3 * want);
	}
	sc.sun_dir = v3(0.0, 0.0, 1.0);
	sc.layers[0].homog_radius_m = 100.0;
	double Tc = cs_render_sun_transmittance(&sc, &s, v3(150.0, 0.0, 500.0), &st);
	s.light_march = CS_LIGHT_GEOMETRIC;
	double Tg = cs_render_sun_transmittance(&sc, &s, v3(150.0, 0.0, 500.0), &st);
	printf("  beside the column: geometric %.4g, cone %.4g\n", Tg, Tc);
	CHECK(Tg == 1.0);
	CHECK(Tc < 0.9 && Tc > 0.0);
}

/* A tower's shadow reaches far under a low sun: a homogeneous cylinder
 * 1 km in radius, 0.001/m, from 1200 to 11000 m, 25 km from a point on
 * the ground toward a sun 15 deg up.  Beer's law over the chord, 2 km
 * across the beam's horizontal path through the axis, 2 km / cos 15 deg
 * along it (at 7 to 7.5 km altitude, inside the layer): T = exp(-0.001 x
 * 2070.6) = 0.126, to the uniform march's 19 m steps.  A light march
 * capped at 20 km of path, as in earlier releases, ends before it (T = 1:
 * a cumulonimbus at a low sun shadowed none of the ground its towers
 * shade, GHI 64 % too high against the path tracer). */
static void a_far_tower_shadows_the_ground_under_a_low_sun(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 0.001, 0.0, 1200.0, 11000.0);
	sc.layers[0].homog_radius_m = 1000.0, sc.layers[0].homog_x = 25000.0;
	sc.effects |= CS_FX_SUN;
	double e = 15.0 * CS_PI / 180.0;
	sc.sun_dir = v3(cos(e), 0.0, sin(e));
	struct cs_render_settings s = plain(32, 2000);
	struct cs_render_stats st = {0};
	double T = cs_render_sun_transmittance(&sc, &s, v3(0.0, 0.0, 540.0), &st);
	double want = exp(-0.001 * 2000.0 / cos(e));
	printf("  sun transmittance %.4f, Beer's law over the chord %.4f\n", T, want);
	CHECK_NEAR(T, want, 0.05 * want);
}

/* The same tower's shadow at 16, 48 and 128 light steps, the tower 24 to
 * 26 km away (21 places 100 m apart: its 2.07 km chord along the path is
 * the same at each): the ground's shadow march takes equal steps of at
 * most CS_SHADOW_STEP_M where its longest would be longer (here 37.9 km
 * of path: 95 steps; 128 at 128), where 32 geometric steps grow to about
 * 2.8 km and meet the tower or miss it by where it stands: measured 0.092
 * to 0.137 against Beer's law's 0.126 over the chord, 0.14 off (relative,
 * rms; 0.076 with 128 steps); 32 geometric steps gave 0.099 to 1 (missed),
 * 1.5 off. */
static void a_far_towers_shadow_at_the_presets_light_steps(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 0.001, 0.0, 1200.0, 11000.0);
	sc.layers[0].homog_radius_m = 1000.0;
	sc.effects |= CS_FX_SUN;
	double e = 15.0 * CS_PI / 180.0;
	sc.sun_dir = v3(cos(e), 0.0, sin(e));
	double want = exp(-0.001 * 2000.0 / cos(e));
	static const int light_steps[3] = {16, 48, 128};
	for (int k = 0; k < 3; k++) {
		struct cs_render_settings s = plain(32, light_steps[k]);
		s.light_march = CS_LIGHT_AUTO;
		struct cs_render_stats st = {0};
		double sq = 0.0, lo = 1.0, hi = 0.0;
		for (int i = 0; i <= 20; i++) {
			sc.layers[0].homog_x = 24000.0 + 100.0 * i;
			double T = cs_render_sun_transmittance(&sc, &s, v3(0.0, 0.0, 540.0), &st);
			sq += (T / want - 1.0) * (T / want - 1.0);
			lo = T < lo ? T : lo, hi = T > hi ? T : hi;
		}
		double rms = sqrt(sq / 21.0);
		printf("  %2d light steps: sun transmittance %.4f to %.4f (%llu samples), Beer's law "
		       "%.4f, off by %.3f rms\n", light_steps[k], lo, hi,
		       (unsigned long long)st.light_samples / 21, want, rms);
		CHECK(rms < 0.25);
	}
}

/* Under a homogeneous overcast of optical depth 64 the diffuse light is
 * what the deck transmits of the sun and sky above it, grey, and the
 * ground shows it: the ground's radiance is albedo x that light / pi (the
 * sun's beam is gone).  Expected values from the published transmittance
 * 0.15 of an overhead sun at tau 64, times the escape function's
 * (1 + 2 mu0) / 3 for the sun 30 deg up and 7/9 for the sky's diffuse
 * light, and the ground's return that the deck reflects back down,
 * 1 / (1 - albedo R) with R = 1 - 0.15 x 7/9; not from the renderer. */
static void overcast_ground_sees_the_transmitted_light(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 64.0 / 3200.0, 0.0, 800.0, 4000.0);
	double e = 30.0 * CS_PI / 180.0;
	sc.sun_dir = v3(0.0, cos(e), sin(e));
	double sun[3] = {80.0, 65.0, 42.0}, sky[3] = {7.0, 9.5, 14.5}; /* klux, kcd/m^2 */
	memcpy(sc.sun_illuminance, sun, sizeof sun);
	memcpy(sc.ambient_up, sky, sizeof sky);
	sc.ground_albedo[0] = sc.ground_albedo[1] = sc.ground_albedo[2] = 0.2;
	sc.effects |= CS_FX_SUN | CS_FX_SKY | CS_FX_GROUND | CS_FX_CLOUD_SHADOWS;
	cs_scene_deck_light(&sc, 1);
	CHECK(sc.effects & CS_FX_DECK);
	CHECK(sc.deck.direct_below < 1e-6);
	double below[3];
	for (int c = 0; c < 3; c++) {
		below[c] = 0.15 * ((1.0 + 2.0 * sin(e)) / 3.0 * sun[c] * sin(e) +
				   7.0 / 9.0 * CS_PI * sky[c]) / CS_PI /
			   (1.0 - 0.2 * (1.0 - 0.15 * 7.0 / 9.0));
		CHECK_NEAR(sc.deck.sky_below[c], below[c], 0.1 * below[c]);
	}
	/* grey: the clear dome's blue (B/R 2.1) is mostly gone under the deck */
	CHECK(sc.deck.sky_below[2] / sc.deck.sky_below[0] < 1.3);
	struct cs_render_settings s = plain(64, 16);
	struct cs_ray_result r;
	trace(&sc, &s, v3(0.0, 0.0, 100.0), v3(0.0, 0.0, -1.0), &r);
	for (int c = 0; c < 3; c++)
		CHECK_NEAR(r.rgb[c], 0.2 * below[c], 0.1 * 0.2 * below[c]);
	/* over snow (albedo 0.8) the series of reflections between ground and
	 * base brightens the light under the deck by (1 - 0.2 R) / (1 - 0.8 R)
	 * over the green case, R = 1 - 0.15 x 7/9: 2.8 times, within 5 % */
	double green = sc.deck.sky_below[1], R = 1.0 - 0.15 * 7.0 / 9.0;
	sc.ground_albedo[0] = sc.ground_albedo[1] = sc.ground_albedo[2] = 0.8;
	cs_scene_deck_light(&sc, 1);
	double want = (1.0 - 0.2 * R) / (1.0 - 0.8 * R);
	printf("  under the deck over snow: %.3f times the light over albedo 0.2 (closed form %.3f)\n",
	       sc.deck.sky_below[1] / green, want);
	CHECK_NEAR(sc.deck.sky_below[1] / green, want, 0.05 * want);
}

/* The base of a deep overcast seen from below dims like 1 / tau beyond
 * the deepest light field the deck solves (CS_DECK_FIELD_TAU_MAX, 128):
 * homogeneous slabs of optical depth 128 and 256 (20 km thick, so that
 * the view's steps are thin; the phase one Henyey-Greenstein lobe of
 * 0.85, water droplets), the sun overhead, and the zenith's radiance
 * against the published similarity transmittance T = 1 / (0.9 + 0.6
 * (1 - g) tau) (RADIATION-NOTES: within about 10 % for (1 - g) tau of 2
 * to 40) leaving the base with the escape function's 9/7 for the
 * vertical: pi L / E = 9/7 T, within 15 %.  Read unscaled, the field
 * of depth 128 lit the base of the 256 as its own (measured 0.0946
 * against 0.0537, +76 %; now 0.0531, -1 %: the diffusion's linear fall
 * of the light to the base, haze.c's fields_source). */
static void deep_overcast_base_dims_like_one_over_tau(void)
{
	static const double taus[] = {128.0, 256.0};
	for (size_t k = 0; k < sizeof taus / sizeof taus[0]; k++) {
		static struct cs_scene sc;
		slab_scene(&sc, taus[k] / 20000.0, 0.0, 800.0, 20800.0);
		sc.g_forward = sc.g_back = 0.85, sc.w_forward = 1.0;
		sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 100.0;
		sc.effects |= CS_FX_SUN | CS_FX_GROUND;
		cs_scene_deck_light(&sc, 1);
		CHECK(sc.deck.field_of[0] >= 0);
		struct cs_render_settings s;
		CHECK(cs_render_quality("high", &s) == CS_OK);
		s.jitter = 0.0, s.ground_sky = CS_GROUND_SKY_COLUMNS;
		struct cs_ray_result r;
		trace(&sc, &s, v3(0.0, 0.0, 2.0), v3(0.0, 0.0, 1.0), &r);
		double T = 1.0 / (0.9 + 0.6 * 0.15 * taus[k]), want = 9.0 / 7.0 * T;
		double got = CS_PI * r.rgb[1] / 100.0;
		printf("  tau %3.0f: the base's pi L / E %.4f, the similarity form's 9/7 T %.4f (%+.0f %%)\n",
		       taus[k], got, want, 100.0 * (got / want - 1.0));
		CHECK_NEAR(got, want, 0.15 * want);
	}
}

/* The renderer's two-lobe phase function and a sun of 100 klux at
 * cosine mu0 of its zenith angle over scene sc, its deck's light then
 * built; and the radiance (green) that "high" marches at the zenith from
 * z m, without jitter, the ground's light the columns'. */
static void veil_light(struct cs_scene *sc, double mu0)
{
	sc->g_forward = 0.9, sc->g_back = -0.3, sc->w_forward = 0.96;
	sc->sun_dir = v3(0.0, sqrt(1.0 - mu0 * mu0), mu0);
	sc->sun_illuminance[0] = sc->sun_illuminance[1] = sc->sun_illuminance[2] = 100.0;
	sc->effects |= CS_FX_SUN;
	cs_scene_deck_light(sc, 1);
}

static double zenith_at_high(const struct cs_scene *sc, double z)
{
	struct cs_render_settings s;
	CHECK(cs_render_quality("high", &s) == CS_OK);
	s.jitter = 0.0, s.ground_sky = CS_GROUND_SKY_COLUMNS;
	struct cs_ray_result r;
	trace(sc, &s, v3(0.0, 0.0, z), v3(0.0, 0.0, 1.0), &r);
	return r.rgb[1];
}

/* A thin veil seen from below at the zenith: a homogeneous layer from 8
 * to 10 km (cirrus) of cover 0.3 (a broken veil: no deck's fields by its
 * cover), the renderer's two-lobe phase function, no sky, a black ground,
 * the sun 30 deg up over optical depths 0.25 and 0.5 and 53 deg up over
 * 0.25, 0.5 and 0.8 (the beam's slant depth 1 or less).  The zenith's
 * radiance, pi L / E, against the adding-doubling solution of the same
 * slab (tests/reference/adding_doubling.py, Slab("hg2", wf 0.96, g1 0.9,
 * g2 -0.3), mu0 T(1, mu0), N = 32 a hemisphere; its single scattering
 * alone, 0.0136 at optical depth 1 and mu0 0.5, is the closed form's
 * 0.0135), within 5 %.  Lit by the march's model of the diffuse light
 * instead of light fields (fog.c, field_weight), the layer was 2.7 to 4.3
 * times as bright. */
static void a_thin_veil_is_as_bright_as_the_adding_doubling_slab(void)
{
	static const struct {
		double mu0, tau, want;
	} c[] = {{0.5, 0.25, 0.0150}, {0.5, 0.5, 0.0304}, {0.8, 0.25, 0.0511}, {0.8, 0.5, 0.0998},
		 {0.8, 0.8, 0.1549}};
	for (size_t k = 0; k < sizeof c / sizeof c[0]; k++) {
		static struct cs_scene sc;
		slab_scene(&sc, c[k].tau / 2000.0, 0.0, 8000.0, 10000.0);
		sc.layers[0].coverage = 0.3;
		veil_light(&sc, c[k].mu0);
		double got = CS_PI * zenith_at_high(&sc, 2.0) / 100.0;
		printf("  the sun %2.0f deg up, optical depth %.2f: pi L / E at the zenith %.4f, "
		       "adding-doubling %.4f (%+.1f %%)\n",
		       asin(c[k].mu0) * 180.0 / CS_PI, c[k].tau, got, c[k].want,
		       100.0 * (got / c[k].want - 1.0));
		CHECK_NEAR(got, c[k].want, 0.05 * c[k].want);
	}
}

/* Light fields change hands without a step in the light: two thin veils
 * of 30 % cover (optical depths 0.4 and 0.2, 9 to 10 and 6 to 7 km) over
 * a broken deck of 60 % cover (10, 2 to 3 km), which takes one of the two
 * sets of fields by its cover; the veils are thin for the sun's beam
 * (fog.c, field_weight) and share the other.  As the sun sinks from 11.5
 * to 5.7 deg, in steps of 0.03 deg or less, their beam's slant depths
 * cross each other's and the ramp's ends: the zenith's radiance seen
 * from between the deck and the veils changes by no more than 2 % a step
 * (the sun's own change: below 0.5 %).  The veil first in the layers'
 * order had kept the set until its share fell to none, and handed it to
 * the other at once: -26 % in one step. */
static void fields_change_hands_without_a_step(void)
{
	static struct cs_scene sc;
	double prev = -1.0, worst = 0.0, at = 0.0;
	for (double mu0 = 0.200; mu0 > 0.0995; mu0 -= 0.0005) {
		memset(&sc, 0, sizeof sc);
		sc.earth_radius_m = CS_EARTH_RADIUS_M;
		sc.nlayers = 3;
		static const double base[3] = {9000.0, 6000.0, 2000.0}, tau[3] = {0.4, 0.2, 10.0};
		static const double cover[3] = {0.3, 0.3, 0.6};
		for (int i = 0; i < 3; i++) {
			sc.layers[i].kind = CS_LAYER_HOMOGENEOUS;
			sc.layers[i].base_m = base[i], sc.layers[i].top_m = base[i] + 1000.0;
			sc.layers[i].homog_a = tau[i] / 1000.0;
			sc.layers[i].coverage = cover[i];
		}
		sc.albedo = 1.0;
		sc.effects = CS_FX_CLOUDS;
		veil_light(&sc, mu0);
		double L = zenith_at_high(&sc, 5000.0);
		double step = prev > 0.0 ? fabs(L / prev - 1.0) : 0.0;
		if (step > worst)
			worst = step, at = mu0;
		prev = L;
	}
	printf("  the largest step of the zenith's radiance: %.2f %% (at mu0 %.4f)\n", 100.0 * worst,
	       at);
	CHECK(worst < 0.02);
}

/* A cloud whose top reaches into a deck above it is lit through the part
 * of the deck over its top: a thin layer (optical depth 1) from 650 to
 * 1850 m under a homogeneous deck of optical depth 64 from 834 to 4034 m
 * (the capture's rain hour's cumulus and nimbostratus), the sun
 * overhead: the light reaching its top is that under the 68 % of the
 * deck above 1850 m, optical depth 43.7, whose published similarity
 * transmittance is 1 / (0.9 + 0.6 (1 - g) tau) (RADIATION-NOTES; g 0.85),
 * within 10 %.  Taken for side by side (neither wholly above the other),
 * the thin layer was lit by the open sun: 4.8 times that. */
static void a_cloud_reaching_into_a_deck_is_lit_through_it(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 64.0 / 3200.0, 0.0, 834.0, 4034.0);
	sc.layers[1] = sc.layers[0];
	sc.layers[0].base_m = 650.0, sc.layers[0].top_m = 1850.0;
	sc.layers[0].homog_a = 1.0 / 1200.0;
	sc.nlayers = 2;
	sc.g_forward = sc.g_back = 0.85, sc.w_forward = 1.0;
	sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 100.0;
	sc.effects |= CS_FX_SUN;
	cs_scene_deck_light(&sc, 1);
	double tau = 64.0 * (4034.0 - 1850.0) / 3200.0, want = 100.0 / (0.9 + 0.6 * 0.15 * tau);
	double got = sc.deck.sun_top[0][1] + sc.deck.dif_top[0][1];
	printf("  the light on the lower layer's top: %.2f klux, under optical depth %.1f %.2f "
	       "(%+.0f %%); on the deck's top %.1f\n", got, tau, want, 100.0 * (got / want - 1.0),
	       sc.deck.sun_top[1][1] + sc.deck.dif_top[1][1]);
	CHECK_NEAR(got, want, 0.1 * want);
	CHECK_NEAR(sc.deck.sun_top[1][1] + sc.deck.dif_top[1][1], 100.0, 1e-9);
}

/* The light in a column of rain or snow (cs_rain_column) against the
 * adding-doubling solution of an isotropic slab over Lambertian ground lit
 * by diffuse light (tests/reference/rain-column.txt, rain_column.py: the
 * solver of slab-table.txt, the ground added exactly), drops' albedo 0.9
 * and 1, optical depths 0.3 to 4, ground albedo 0 to 0.14: the column's
 * albedo within 0.03 (measured at most 0.023), the light down on the
 * ground within 5 % (3.3 %), the mean radiance at 1/8, 1/2 and 7/8 of the
 * depth within 12 % (10.3 %, near the ground of a thin column).  The
 * hemispheric mean's coefficients (gamma1 = 2 - w, gamma2 = w) left the
 * ground 36 % short under depth 4; single scattering's rule, (1 + a) / 2
 * at every depth, was 2.4 times the mean near the ground under 1.6. */
static void rain_column_matches_adding_doubling(void)
{
	char path[4096], line[512];
	FILE *f = fopen(t_top_path(path, sizeof path, "tests/reference/rain-column.txt"), "r");
	CHECK(f != NULL);
	if (f == NULL)
		return;
	int rows = 0;
	double worst[3] = {0.0, 0.0, 0.0};
	while (fgets(line, sizeof line, f)) {
		double w, tau, a, albedo, down, m[3];
		if (line[0] == '#' || sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf", &w, &tau, &a,
					     &albedo, &down, &m[0], &m[1], &m[2]) != 8)
			continue;
		/* the row's albedo in each colour in turn, the others far off
		 * it: each colour its own */
		for (int c = 0; c < 3; c++) {
			double g[3] = {0.9, 0.5, 0.0}, mean[3], got_down[3];
			g[c] = a;
			cs_rain_column(w, tau, 0.0, g, mean, got_down);
			CHECK_NEAR(2.0 * mean[c] - 1.0, albedo, 0.03);
			CHECK_NEAR(got_down[c], down, 0.05 * down);
			worst[0] = fmax(worst[0], fabs(2.0 * mean[c] - 1.0 - albedo));
			worst[1] = fmax(worst[1], fabs(got_down[c] / down - 1.0));
			const double depth[3] = {0.125, 0.5, 0.875};
			for (int k = 0; k < 3; k++) {
				double d[3];
				cs_rain_column(w, tau, depth[k] * tau, g, mean, d);
				CHECK_NEAR(mean[c], m[k], 0.12 * m[k]);
				worst[2] = fmax(worst[2], fabs(mean[c] / m[k] - 1.0));
			}
		}
		rows++;
	}
	fclose(f);
	printf("  %d rows: albedo off by at most %.3f, the ground's light %.1f %%, the mean "
	       "radiance %.1f %%\n",
	       rows, worst[0], 100.0 * worst[1], 100.0 * worst[2]);
	CHECK(rows == 30);
	/* no rain: the ground's albedo, all of the light down */
	double g[3] = {0.1, 0.14, 0.07}, mean[3], down[3];
	cs_rain_column(0.9, 0.0, 0.0, g, mean, down);
	for (int c = 0; c < 3; c++) {
		CHECK_NEAR(2.0 * mean[c] - 1.0, g[c], 1e-12);
		CHECK_NEAR(down[c], 1.0, 1e-12);
	}
	/* a column of any depth, however deep (a fuzzer's rain), over any
	 * ground (a snowfield's noise takes its albedo past 1), keeps its
	 * light finite: no inf / inf, no pole of the denominator */
	const double deep[] = {2.0, 3.25, 50.0, 1e3, 1e300, INFINITY, NAN};
	const double bright[3] = {1.41, 2.0, NAN};
	for (size_t i = 0; i < sizeof deep / sizeof deep[0]; i++)
		for (int w = 0; w < 2; w++)
			for (int b = 0; b < 2; b++) {
				cs_rain_column(w ? 1.0 : 0.9, deep[i], 1.0, b ? bright : g, mean, down);
				for (int c = 0; c < 3; c++)
					CHECK(mean[c] >= 0.0 && mean[c] <= 1.0 && down[c] >= 0.0 &&
					      down[c] <= 1.0);
			}
}

/* A deck of optical depth 64 from 800 to 4000 m (cs_rain_shaft 1
 * everywhere) over a ground of albedo 0.2, wet (0.7), raining 2 /km from
 * its base, the sun el_rad up in the north, its beam's illuminance sun
 * and the sky's radiance sky (klux, kcd/m^2), with the sky's light, the
 * ground and the rain, and the effects more; its deck's light built. */
static void rain_slab(struct cs_scene *sc, double el_rad, const double sun[3], const double sky[3],
		      unsigned more)
{
	slab_scene(sc, 64.0 / 3200.0, 0.0, 800.0, 4000.0);
	sc->layers[0].extinction_per_m = 64.0 / 3200.0; /* cs_rain_shaft: 1 */
	sc->sun_dir = v3(0.0, cos(el_rad), sin(el_rad));
	memcpy(sc->sun_illuminance, sun, 3 * sizeof sun[0]);
	memcpy(sc->ambient_up, sky, 3 * sizeof sky[0]);
	for (int c = 0; c < 3; c++)
		sc->ground_albedo[c] = 0.2;
	sc->ground_wet = 0.7;
	sc->rain_layer = 0, sc->rain_top_m = 800.0, sc->rain_extinction_per_m = 2e-3;
	sc->precip_albedo = 0.9;
	sc->effects |= CS_FX_SKY | CS_FX_GROUND | CS_FX_RAIN | more;
	cs_scene_deck_light(sc, 1);
}

/* Rain under a uniform overcast (optical depth 64, the sun 30 deg up, the
 * sky's light too, over ground of albedo 0.2 made 0.7 times darker by the
 * wet), 2e-3 /m from the ground to the base at 800 m (depth 1.6): the
 * drops scatter isotropically, so far along a level ray through rain
 * everywhere the radiance is the drops' albedo times the mean radiance
 * around them.  At 100 m, 7/8 of the rain's depth under its top, that
 * mean is 0.2339 of the light coming down at the top (adding-doubling:
 * tests/reference/rain-column.txt, the row of albedo 0.9, depth 1.6 and
 * ground 0.14), and the light at the top is the published
 * transmittance's (overcast_ground_sees_the_transmitted_light's closed
 * form, not the renderer's), the cloud over a floor of the rain's and the
 * ground's albedo together (0.4311, the same row): within 12 %.  With
 * single scattering's rule, (1 + 0.2 x 0.7) / 2 of the light under the
 * deck over the ground alone, the rain was 1.65 times this; lit by all of
 * that light, 1.75 times that, and the real hour of rain of the meteoblue
 * capture 4.0 times the path tracer's picture. */
static void rain_scatters_the_light_around_it(void)
{
	static struct cs_scene sc;
	double e = 30.0 * CS_PI / 180.0;
	double sun[3] = {80.0, 65.0, 42.0}, sky[3] = {7.0, 9.5, 14.5}; /* klux, kcd/m^2 */
	rain_slab(&sc, e, sun, sky, CS_FX_SUN);
	CHECK(cs_rain_shaft(&sc, 3000.0, -2000.0) == 1.0);
	struct cs_render_settings s = plain(64, 16);
	struct cs_ray_result r;
	trace(&sc, &s, v3(0.0, 0.0, 100.0), v3(1.0, 0.0, 0.0), &r);
	for (int c = 0; c < 3; c++) {
		/* the light under the deck, as overcast_ground_sees_the_transmitted_light */
		double below = 0.15 * ((1.0 + 2.0 * sin(e)) / 3.0 * sun[c] * sin(e) +
				       7.0 / 9.0 * CS_PI * sky[c]) / CS_PI /
			       (1.0 - 0.4310508 * (1.0 - 0.15 * 7.0 / 9.0));
		double want = 0.9 * 0.2338526 * below;
		printf("  channel %d: the rain's radiance %.4f, isotropic scattering's %.4f (%+.0f %%)\n",
		       c, r.rgb[c], want, 100.0 * (r.rgb[c] / want - 1.0));
		CHECK_NEAR(r.rgb[c], want, 0.12 * want);
	}
}

/* Under rain with the ground's field of two planes (cs_ground_sky_field:
 * the light at the rain's top, T, and the ground's, G, whose rays crossed
 * the rain), here made by hand, uniform: the drops next to the ground
 * take the ground's light, of mean radiance (1 + a) / 2 G over a ground
 * of albedo a (the two-stream column's mean at the ground, (1 + a) / 2 of
 * the light coming down), whatever the column says comes down from T:
 * with G twice T times the column's transmittance, a ray along the
 * ground through 2 /km of rain (saturated in 2 km; it rises 0.3 m) sees
 * 0.9 (1 + a) / 2 G within 3 % (the column alone, half that).  The
 * ground takes G itself (not T through the column), and the light over
 * a point halfway up the column is halfway from G to T. */
static void rain_near_the_ground_takes_the_ground_planes_light(void)
{
	static struct cs_scene sc;
	const double sun[3] = {80.0, 65.0, 42.0}, sky[3] = {7.0, 9.5, 14.5};
	rain_slab(&sc, 30.0 * CS_PI / 180.0, sun, sky, 0u); /* (no sun's beam) */
	CHECK(sc.deck.on);
	/* the field: T, and G twice what the column lets down from it */
	const double a = 0.2 * 0.7, T[3] = {2.0, 2.5, 3.5};
	double mean[3], down[3], G[3];
	const double alb[3] = {a, a, a};
	cs_rain_column(0.9, 2e-3 * 800.0, 2e-3 * 800.0, alb, mean, down);
	static float v[2 * 2 * 2 * 3];
	for (int k = 0; k < 4; k++)
		for (int c = 0; c < 3; c++) {
			G[c] = 2.0 * down[c] * T[c];
			v[3 * k + c] = (float)G[c];
			v[12 + 3 * k + c] = (float)T[c];
		}
	sc.ground_field = (struct cs_ground_field){
		.rgb = v, .n = 2, .planes = 2, .x0_m = -1e6, .y0_m = -1e6, .step_m = 2e6,
		.fade_m = 1e6, .mean = {G[0], G[1], G[2]}, .top_mean = {T[0], T[1], T[2]}};
	struct cs_render_settings s = plain(64, 16);
	struct cs_ray_result r;
	trace(&sc, &s, v3(0.0, 0.0, 2.0), v3(1.0, 0.0, 0.0), &r);
	for (int c = 0; c < 3; c++) {
		double want = 0.9 * 0.5 * (1.0 + a) * G[c];
		printf("  channel %d: the rain's radiance %.4f, the ground plane's %.4f (%+.1f %%)\n",
		       c, r.rgb[c], want, 100.0 * (r.rgb[c] / want - 1.0));
		CHECK_NEAR(r.rgb[c], want, 0.03 * want);
	}
	/* the ground takes G (its albedo times it), not T through the
	 * column; halfway up the column the light is halfway to T */
	struct cs_render_stats st = {0};
	cs_v3 p = v3(0.0, 0.0, 0.0), n;
	double rgb[3], ground_alb[3], half[3];
	cs_ground_surface(&sc, p, 0, &n, ground_alb);
	cs_ground_light(&sc, &s, p, v3(1.0, 0.0, -0.1), 0, &st, rgb);
	cs_ground_sky(&sc, v3(0.0, 0.0, 400.0), half);
	for (int c = 0; c < 3; c++) {
		CHECK_NEAR(rgb[c], ground_alb[c] * G[c], 1e-6 * G[c]);
		CHECK_NEAR(half[c], 0.5 * (G[c] + T[c]), 1e-6 * T[c]);
	}
}

/* Koschmieder: in fog of visibility V a black object at distance V keeps
 * about 2 % of its contrast against the fog's own light along the same
 * line of sight (exp(-3.912)): its radiance is 98 % of that light.  The
 * camera stands 2 m up in fog 300 m deep; the ray meets black ground 200
 * m away, 0.01 down.  The fog's light is not the same in every direction
 * (over a dark ground more of it travels down than up: cs_fog_source), so
 * the contrast is against the fog's light toward the eye along that ray
 * (at 1.5 m, the middle of the fog light the ray gathers), not against
 * the horizon just above it; a ray 0.01 up sees that light and keeps
 * nothing of the sky behind its 30 km of fog. */
static void black_object_at_the_visibility_keeps_two_percent_contrast(void)
{
	static struct cs_scene sc;
	memset(&sc, 0, sizeof sc);
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	double e = 30.0 * CS_PI / 180.0;
	sc.sun_dir = v3(0.0, cos(e), sin(e));
	cs_sky_init(&sc.sky, sc.sun_dir, 3.0);
	memcpy(sc.sun_illuminance, sc.sky.sun_illuminance, sizeof sc.sun_illuminance);
	memcpy(sc.ambient_up, sc.sky.ambient_up, sizeof sc.ambient_up);
	sc.effects = CS_FX_SUN | CS_FX_SKY | CS_FX_GROUND | CS_FX_HAZE | CS_FX_FOG;
	double V = 200.0;
	sc.fog_beta_per_m = 3.912 / V;
	sc.fog_top_m = 300.0;
	sc.haze_scale_height_m = 1200.0;
	sc.albedo = 0.99999; /* the droplets' (cs_scene_build's) */
	sc.g_forward = 0.9, sc.g_back = -0.3, sc.w_forward = 0.96;
	CHECK(cs_scene_fog_light(&sc, 1) == CS_OK);
	struct cs_render_settings s = plain(8, 4);
	struct cs_ray_result obj, bg;
	cs_v3 o = v3(0.0, 0.0, 2.0);
	trace(&sc, &s, o, v3(sqrt(1.0 - 1e-4), 0.0, -0.01), &obj);
	trace(&sc, &s, o, v3(sqrt(1.0 - 1e-4), 0.0, 0.01), &bg);
	CHECK_NEAR(obj.depth_m, V, 0.5);
	double along[3], above[3];
	cs_fog_source(&sc, 1.5, 0.01, 0.0, along);
	cs_fog_source(&sc, 2.5, -0.01, 0.0, above);
	for (int k = 0; k < 3; k++) {
		double contrast = 1.0 - obj.rgb[k] / along[k];
		CHECK_NEAR(contrast, 0.02, 0.003);
		CHECK_NEAR(bg.rgb[k], above[k], 0.01 * above[k]);
	}
	/* fog is grey: it takes the colour of the light, not the sky's blue */
	CHECK(bg.rgb[2] / bg.rgb[0] < sc.ambient_up[2] / sc.ambient_up[0]);
}

/* A state with visibility below 1 km makes fog whose extinction at the
 * ground, with the haze of the air above it, is 3.912 / visibility. */
static void fog_extinction_at_the_ground_is_koschmieder(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.visibility_m = 250.0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(sc.effects & CS_FX_FOG);
	double haze = sc.haze_beta0_per_m * exp(-wx.site.alt_m / sc.haze_scale_height_m);
	CHECK_NEAR(sc.fog_beta_per_m + haze, 3.912 / 250.0, 1e-9);
	CHECK(sc.fog_top_m > wx.site.alt_m);
	wx.visibility_m = 20000.0;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(!(sc.effects & CS_FX_FOG) && sc.fog_beta_per_m == 0.0);
}

/* Rain's extinction is that of Marshall-Palmer drops (1948), N(D) = 8000
 * exp(-4.1 R^-0.21 D) per m^3 per mm, each blocking twice its cross
 * section (large drops): integrated here numerically over D.  Snow's
 * follows the visibility classes of FMH-1: about 1 km at 1 mm/h, 0.4 km at
 * 2.5 mm/h (3.912 / visibility). */
static void rain_and_snow_extinction_follow_published_relations(void)
{
	for (double R = 0.5; R <= 50.0; R *= 4.0) {
		double L = 4.1 * pow(R, -0.21), sum = 0.0, dD = 0.001;
		for (double D = dD / 2; D < 20.0; D += dD)
			sum += 8000.0 * exp(-L * D) * 2.0 * (CS_PI / 4.0) * D * D * 1e-6 * dD;
		CHECK_NEAR(cs_rain_extinction(R), sum, 1e-3 * sum);
	}
	CHECK_NEAR(3.912 / cs_snow_extinction(1.0), 1000.0, 100.0);
	CHECK_NEAR(3.912 / cs_snow_extinction(2.5), 400.0, 40.0);
	CHECK(cs_rain_extinction(0.0) == 0.0 && cs_snow_extinction(0.0) == 0.0);
}

/* Rain and snow are simulated only when the state has precipitation, snow
 * when the provider's snow fraction says so; the wet ground is darker. */
static void precipitation_only_when_it_rains_or_snows(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.layers[0].genus = CS_NIMBOSTRATUS;
	wx.layers[0].coverage = 0.9;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(!(sc.effects & (CS_FX_RAIN | CS_FX_SNOW)) && sc.ground_wet == 1.0);
	wx.precipitation_mm_h = 2.0;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK((sc.effects & CS_FX_RAIN) && !(sc.effects & CS_FX_SNOW) && sc.ground_wet < 1.0);
	CHECK_NEAR(sc.rain_extinction_per_m, cs_rain_extinction(2.0 / 0.9), 1e-12);
	wx.snow_fraction = 1.0;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(!(sc.effects & CS_FX_RAIN) && (sc.effects & CS_FX_SNOW));
	CHECK_NEAR(sc.rain_extinction_per_m, cs_snow_extinction(2.0 / 0.9), 1e-12);
}

/* Snow alone is seen: a precipitation that is all snow (no CS_FX_RAIN)
 * is marched as rain of the same extinction and albedo is, and a view
 * through it is not the view without it.  Until 2026-12-05 only rain put
 * the shafts on the ray (all-snow hours rendered no snowfall). */
static void snow_alone_is_marched_as_rain_is(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.layers[0].genus = CS_NIMBOSTRATUS;
	wx.layers[0].coverage = 0.9;
	wx.precipitation_mm_h = 2.0, wx.snow_fraction = 1.0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK((sc.effects & CS_FX_SNOW) && !(sc.effects & CS_FX_RAIN));
	struct cs_render_settings s;
	cs_render_quality("medium", &s);
	struct cs_render_stats st;
	struct cs_ray_result snow, rain, none;
	/* from 300 m up to the ground 2 km away (a shaft over it) */
	cs_v3 o = v3(0.0, 0.0, wx.site.alt_m + 300.0), d = v3_norm(v3(1.0, 0.0, -0.15));
	cs_render_ray(&sc, &s, o, d, 0.5, &st, &snow);
	sc.effects ^= CS_FX_SNOW | CS_FX_RAIN;
	cs_render_ray(&sc, &s, o, d, 0.5, &st, &rain);
	sc.effects &= ~(unsigned)CS_FX_RAIN;
	cs_render_ray(&sc, &s, o, d, 0.5, &st, &none);
	double ys = cs_luminance(snow.rgb[0], snow.rgb[1], snow.rgb[2]);
	double yr = cs_luminance(rain.rgb[0], rain.rgb[1], rain.rgb[2]);
	double yn = cs_luminance(none.rgb[0], none.rgb[1], none.rgb[2]);
	printf("  luminance through 2 mm/h: all snow %.4g, as rain %.4g, none %.4g\n", ys, yr, yn);
	CHECK_NEAR(ys, yr, 1e-12 * yr);
	CHECK(fabs(ys - yn) > 0.01 * yn);
	/* and the path tracer: the same 64 paths (keys) through each */
	struct cs_reference_settings rs = {64, 1, 0};
	double y[3];
	for (int m = 0; m < 3; m++) {
		sc.effects &= ~(unsigned)(CS_FX_RAIN | CS_FX_SNOW);
		sc.effects |= m == 0 ? CS_FX_SNOW : m == 1 ? CS_FX_RAIN : 0u;
		double sum = 0.0;
		for (int k = 0; k < rs.spp; k++) {
			double L[3], depth;
			int hit;
			cs_reference_path(&sc, &rs, o, d, 1000u + (uint64_t)k, &st, L, &hit, &depth);
			sum += cs_luminance(L[0], L[1], L[2]);
		}
		y[m] = sum / rs.spp;
	}
	printf("  the path tracer, 64 paths: all snow %.4g, as rain %.4g, none %.4g\n", y[0], y[1],
	       y[2]);
	CHECK_NEAR(y[0], y[1], 1e-12 * y[1]);
	CHECK(fabs(y[0] - y[2]) > 0.1 * y[2]);
}

/* A thin cirrostratus in front of the sun shows the 22-degree halo: the
 * minimum deviation of a 60-degree ice prism, 2 asin(n sin 30) - 60, at
 * n = 1.3079 (red, 650 nm) and 1.3148 (blue, 450 nm): red inside, blue
 * outside, brighter than the sky 3 degrees in or out. */
static void thin_cirrostratus_shows_the_22_degree_halo(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 0.5 / 1500.0, 0.0, 7500.0, 9000.0);
	sc.layers[0].genus = CS_CIRROSTRATUS;
	sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 100.0;
	sc.effects |= CS_FX_SUN | CS_FX_HALO;
	struct cs_render_settings s = plain(64, 8);
	double best[3] = {0, 0, 0}, at[3] = {0, 0, 0}, L[3][3];
	for (double a = 18.0; a <= 26.0; a += 0.05) {
		double r = a * CS_PI / 180.0;
		struct cs_ray_result res;
		trace(&sc, &s, v3(0, 0, 0), v3(sin(r), 0.0, cos(r)), &res);
		for (int k = 0; k < 3; k++)
			if (res.rgb[k] > best[k])
				best[k] = res.rgb[k], at[k] = a;
		int i = fabs(a - 18.9) < 0.01 ? 0 : fabs(a - 21.9) < 0.01 ? 1 : fabs(a - 24.9) < 0.01 ? 2 : -1;
		for (int k = 0; k < 3 && i >= 0; k++)
			L[i][k] = res.rgb[k];
	}
	double red = 2.0 * asin(1.3079 * 0.5) * 180.0 / CS_PI - 60.0;
	double blue = 2.0 * asin(1.3148 * 0.5) * 180.0 / CS_PI - 60.0;
	CHECK_NEAR(at[0], red, 0.3);
	CHECK_NEAR(at[2], blue, 0.3);
	CHECK(at[0] < at[2]);
	for (int k = 0; k < 3; k++)
		CHECK(L[1][k] > 1.2 * L[0][k] && L[1][k] > 1.2 * L[2][k]);
	/* without the halo effect the same sky has no ring */
	sc.effects &= ~(unsigned)CS_FX_HALO;
	struct cs_ray_result in, ring;
	trace(&sc, &s, v3(0, 0, 0), v3(sin(18.9 * CS_PI / 180), 0, cos(18.9 * CS_PI / 180)), &in);
	trace(&sc, &s, v3(0, 0, 0), v3(sin(21.9 * CS_PI / 180), 0, cos(21.9 * CS_PI / 180)), &ring);
	CHECK(ring.rgb[1] < in.rgb[1]);
}

/* Crepuscular rays: the haze in a cloud's shadow is lit by the sky only.
 * An opaque disc of cloud 2000-2100 m up, 2 km in radius over the camera,
 * with the sun 45 degrees high in the east, shades a horizontal ray 2 m up
 * looking west from 0 to 4.098 km (a point at x sees the sun through the
 * disc while x + 1998 <= 2000 and x + 2098 >= -2000), so the haze light
 * it gathers falls short of the same ray without the cloud by the sun's
 * part times 1 - exp(-b 4098) (b the haze extinction there). */
static void cloud_shadows_darken_the_haze(void)
{
	static struct cs_scene sc;
	slab_scene(&sc, 1.0, 0.0, 2000.0, 2100.0);
	sc.layers[0].homog_radius_m = 2000.0;
	double e = 45.0 * CS_PI / 180.0;
	sc.sun_dir = v3(cos(e), 0.0, sin(e));
	cs_sky_init(&sc.sky, sc.sun_dir, 3.0);
	memcpy(sc.sun_illuminance, sc.sky.sun_illuminance, sizeof sc.sun_illuminance);
	memcpy(sc.ambient_up, sc.sky.ambient_up, sizeof sc.ambient_up);
	sc.effects |= CS_FX_SUN | CS_FX_SKY | CS_FX_HAZE | CS_FX_SHAFTS;
	sc.haze_scale_height_m = 1200.0;
	sc.haze_beta0_per_m = 3.912 / 8000.0;
	struct cs_render_settings s = plain(16, 8);
	s.haze_steps = 2000; /* 10 m steps: the shadow's edges sharp */
	struct cs_ray_result clear, shaded;
	cs_v3 west = v3(-1.0, 0.0, 0.0);
	trace(&sc, &s, v3(0.0, 0.0, 2.0), west, &shaded);
	sc.nlayers = 0;
	trace(&sc, &s, v3(0.0, 0.0, 2.0), west, &clear);
	sc.nlayers = 1;
	/* the sun's part of the haze light: the clear sky looking 1 degree up
	 * (what a plane-parallel haze scatters toward the eye) less the
	 * dome's cosine mean, where that is positive: here in red only, the
	 * sky toward the horizon being redder than the dome */
	double b = sc.haze_beta0_per_m * exp(-2.0 / 1200.0);
	double band = 1.0 - exp(-b * 4098.0);
	double up = sin(CS_PI / 180.0), rgb[3];
	cs_sky_radiance(&sc.sky, v3(-cos(asin(up)), 0.0, up), rgb);
	for (int k = 0; k < 3; k++) {
		double sun = rgb[k] > sc.ambient_up[k] ? rgb[k] - sc.ambient_up[k] : 0.0;
		CHECK_NEAR(shaded.rgb[k], clear.rgb[k] - sun * band, 0.02 * clear.rgb[k]);
	}
	/* without the effect the band is not there */
	sc.effects &= ~(unsigned)CS_FX_SHAFTS;
	struct cs_ray_result flat;
	trace(&sc, &s, v3(0.0, 0.0, 2.0), west, &flat);
	CHECK(flat.rgb[0] > shaded.rgb[0] * 1.1);
}

/* The night: by day no Moon and no stars; at a full moon high over Bern
 * (2024-10-17 23:00 UTC) the Moon is the key light and the horizontal
 * illuminance on the ground under a clear sky is that of full moonlight,
 * 0.05 to 0.3 lux (RADIATION-NOTES: 0.1-0.3 lux with the Moon high); at a
 * new moon only the stars are out. */
static void moon_and_stars_only_at_night(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nlayers = 0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	CHECK(!(sc.effects & (CS_FX_MOON | CS_FX_STARS)));
	double t;
	CHECK(cs_time_parse("2024-10-17T23:00:00Z", &t) == CS_OK);
	CHECK(cs_scene_build(&sc, &wx, t, &noise) == CS_OK);
	CHECK((sc.effects & CS_FX_MOON) && !(sc.effects & CS_FX_SUN) && (sc.effects & CS_FX_STARS));
	double y_sun = 0.2126 * sc.sun_illuminance[0] + 0.7152 * sc.sun_illuminance[1] +
		       0.0722 * sc.sun_illuminance[2];
	double y_sky = 0.2126 * sc.ambient_up[0] + 0.7152 * sc.ambient_up[1] +
		       0.0722 * sc.ambient_up[2];
	double lux = 1000.0 * (y_sun * sc.sun_dir.z + CS_PI * y_sky);
	CHECK(lux > 0.05 && lux < 0.3);
	CHECK(cs_time_parse("2024-10-02T23:00:00Z", &t) == CS_OK);
	CHECK(cs_scene_build(&sc, &wx, t, &noise) == CS_OK);
	CHECK(!(sc.effects & (CS_FX_MOON | CS_FX_SUN)) && (sc.effects & CS_FX_STARS));
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

/* The thunderstorm of wxinterp(1)'s example (cumulonimbus 0.6, 8 mm/h of
 * convective rain, visibility 4 km) has no speckles: no pixel darker than
 * a quarter of the median of its 8 neighbours.  The integrator before the
 * haze was integrated along the ray drew 34 such pixels at this size and
 * quality (the haze's blend darkened the light in front of far cloud
 * edges). */
static void thunderstorm_has_no_speckles(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.layers[0].genus = CS_CUMULONIMBUS;
	wx.layers[0].coverage = 0.6;
	wx.layers[0].base_m = 1540, wx.layers[0].top_m = 11540;
	wx.precipitation_mm_h = 8, wx.convective_mm_h = 8, wx.visibility_m = 4000;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	enum { W = 320, H = 180 };
	struct cs_camera cam;
	CHECK(cs_camera_init(&cam, &sc, v3(0, 0, wx.site.alt_m + 2), wx.site.lat_deg, 160, 8, 70,
			     W, H) == CS_OK);
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	static float px[W * H * 5];
	struct cs_render_stats st;
	CHECK(cs_render_image(&sc, &cam, &s, 0, NULL, NULL, px, &st) == CS_OK);
	int speckles = 0;
	for (int j = 1; j < H - 1; j++)
		for (int i = 1; i < W - 1; i++) {
			double y[8], c = 0.0;
			int k = 0;
			for (int dj = -1; dj <= 1; dj++)
				for (int di = -1; di <= 1; di++) {
					const float *p = px + ((size_t)(j + dj) * W + i + di) * 5;
					double l = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
					if (di || dj)
						y[k++] = l;
					else
						c = l;
				}
			qsort(y, 8, sizeof y[0], cmp_double);
			speckles += c < 0.25 * 0.5 * (y[3] + y[4]);
		}
	CHECK(speckles == 0);
}

/* An independent solution for a conservative plane-parallel slab: a Monte
 * Carlo random walk of photons entering at cosine mu0 from straight down
 * (optical depth measured from the top), Henyey-Greenstein scattering of
 * asymmetry g.  Fills the total transmittance and reflectance. */
static void slab_monte_carlo_mu(double tau, double g, double mu0, int n, double *T, double *R)
{
	unsigned st = 12345;
	int down = 0, up = 0;
	for (int k = 0; k < n; k++) {
		double z = 0.0, mu = mu0; /* mu: cosine from straight down */
		for (int guard = 0; guard < 1000000; guard++) {
			z += -log(1.0 - t_uniform(&st, 0.0, 1.0)) * mu;
			if (z >= tau) { down++; break; }
			if (z <= 0.0) { up++; break; }
			double u = t_uniform(&st, 0.0, 1.0), c;
			double f = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
			c = (1.0 + g * g - f * f) / (2.0 * g); /* HG inversion */
			double phi = t_uniform(&st, 0.0, 2.0 * CS_PI);
			double sm = sqrt(fmax(0.0, 1.0 - mu * mu)), sc = sqrt(fmax(0.0, 1.0 - c * c));
			mu = mu * c + sm * sc * cos(phi);
			mu = mu > 1.0 ? 1.0 : mu < -1.0 ? -1.0 : mu;
		}
	}
	*T = (double)down / n, *R = (double)up / n;
}

static void slab_monte_carlo(double tau, double g, int n, double *T, double *R)
{
	slab_monte_carlo_mu(tau, g, 1.0, n, T, R);
}

/* The deck's transmittance against the Monte Carlo slab at optical depths
 * 1 to 100 (g = 0.85, water droplets), for an overhead sun and one 30 deg
 * up (mu0 0.5, where the old similarity form, blind to the sun's
 * elevation, was 40 % too bright at tau 10): within 10 %; the table is
 * printed. */
static void deck_transmittance_matches_a_monte_carlo_slab(void)
{
	static const double taus[] = {1, 2, 4, 8, 16, 32, 64, 100}, mus[] = {1.0, 0.5};
	for (size_t m = 0; m < 2; m++)
		for (size_t k = 0; k < sizeof taus / sizeof taus[0]; k++) {
			double T, R, ours = cs_slab_beam_transmittance(taus[k], mus[m]);
			slab_monte_carlo_mu(taus[k], 0.85, mus[m], taus[k] > 30 ? 3000 : 6000, &T, &R);
			printf("  mu0 %.1f tau %5.1f: Monte Carlo T %.3f R %.3f, deck T %.3f (%+.0f %%)\n",
			       mus[m], taus[k], T, R, ours, 100.0 * (ours - T) / T);
			CHECK_NEAR(ours, T, 0.1 * T);
			CHECK_NEAR(T + R, 1.0, 1e-12);
		}
}

/* The renderer's reflectance of the same slabs, seen straight down with the
 * sun at the zenith, as pi L / E: what the light march with its
 * multiple-scattering octaves gives against the Monte Carlo's R.  Printed:
 * the octaves hold for thin clouds (within 20 % at tau = 4) and saturate
 * near 0.2 for thick ones, where the slab reflects 0.56 (tau 16) to 0.85
 * (tau 64): thick cloud tops seen from above are too dark, a known limit
 * of the octave approximation. */
static void renderer_reflectance_against_monte_carlo(void)
{
	static const double taus[] = {1, 4, 16, 64};
	for (size_t k = 0; k < sizeof taus / sizeof taus[0]; k++) {
		static struct cs_scene sc;
		slab_scene(&sc, taus[k] / 1000.0, 0.0, 2000.0, 3000.0);
		sc.sun_illuminance[0] = sc.sun_illuminance[1] = sc.sun_illuminance[2] = 100.0;
		sc.effects |= CS_FX_SUN;
		struct cs_render_settings s;
		cs_render_quality("reference", &s);
		s.ambient = 0, s.jitter = 0.0;
		struct cs_ray_result r;
		trace(&sc, &s, v3(0.0, 0.0, 6000.0), v3(0.0, 0.0, -1.0), &r);
		double T, R, ours = CS_PI * r.rgb[1] / 100.0;
		slab_monte_carlo(taus[k], 0.85, 4000, &T, &R);
		printf("  tau %4.0f: Monte Carlo R %.3f, renderer pi L/E %.3f (%+.0f %%)\n", taus[k], R,
		       ours, 100.0 * (ours - R) / R);
		CHECK(ours > 0.0 && ours < 1.0);
		if (taus[k] == 4)
			CHECK_NEAR(ours, R, 0.2 * R);
	}
}

/* The diffuse irradiance never takes in the sun's disc: with the sun just
 * above one of the hemisphere's sample directions (the case that once
 * nudged a ray into the disc, 2e5 W/m^2), over a sweep of elevations at a
 * sample's azimuth, a clear sky's DHI stays that of a sky (< 500 W/m^2)
 * and varies smoothly. */
static void diffuse_irradiance_never_sees_the_sun_disc(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nlayers = 0;
	static struct cs_scene sc;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, &noise) == CS_OK);
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	double phi = CS_PI / 24.0, last = -1.0;
	for (double el = 55.0; el <= 80.0; el += 0.05) {
		double e = el * CS_PI / 180.0;
		sc.sun_dir = v3(cos(e) * cos(phi), cos(e) * sin(phi), sin(e));
		cs_sky_init(&sc.sky, sc.sun_dir, 3.0);
		struct cs_irradiance irr;
		struct cs_render_stats st = {0};
		cs_irradiance_at(&sc, &s, v3(0.0, 0.0, wx.site.alt_m + 2.0), &irr, &st);
		CHECK(irr.dhi_w_m2 > 0.0 && irr.dhi_w_m2 < 500.0);
		if (last > 0.0)
			CHECK(fabs(irr.dhi_w_m2 - last) < 0.05 * last);
		last = irr.dhi_w_m2;
	}
}

/* Under a clear sky the sky's radiance already holds the haze of the path:
 * a ray into the open sky through haze (and through a cloud's shafts
 * machinery with nothing to shade) returns exactly the sky model's radiance,
 * in every channel, whether the horizon there is brighter or darker than
 * the dome's mean. */
static void clear_sky_rays_are_the_sky_model(void)
{
	static struct cs_scene sc;
	memset(&sc, 0, sizeof sc);
	sc.earth_radius_m = CS_EARTH_RADIUS_M;
	double e = 20.0 * CS_PI / 180.0;
	sc.sun_dir = v3(cos(e), 0.0, sin(e));
	cs_sky_init(&sc.sky, sc.sun_dir, 3.0);
	memcpy(sc.sun_illuminance, sc.sky.sun_illuminance, sizeof sc.sun_illuminance);
	memcpy(sc.ambient_up, sc.sky.ambient_up, sizeof sc.ambient_up);
	sc.effects = CS_FX_SUN | CS_FX_SKY | CS_FX_HAZE | CS_FX_SHAFTS;
	sc.haze_scale_height_m = 1200.0;
	sc.haze_beta0_per_m = 3.912 / 8000.0;
	struct cs_render_settings s = plain(8, 4);
	s.haze_steps = 16;
	for (int a = 0; a < 12; a++) {
		double az = a * CS_PI / 6.0, el = (a % 3) * 0.02;
		cs_v3 d = v3(cos(el) * cos(az), cos(el) * sin(az), sin(el));
		struct cs_ray_result r;
		trace(&sc, &s, v3(0.0, 0.0, 2.0), d, &r);
		double sky[3], disk[3];
		cs_sky_radiance(&sc.sky, d, sky);
		cs_sky_sun_disk(&sc.sky, d, disk);
		for (int k = 0; k < 3; k++)
			CHECK_NEAR(r.rgb[k], sky[k] + disk[k], 1e-9 * (sky[k] + disk[k]));
	}
}

/* Watts from lumens: Littlefair's (1988) measured luminous efficacies of
 * daylight at Garston, the beam 70 lm/W at 10 deg sun elevation and 95 at
 * 60, diffuse light 144 lm/W under a clear sky and 115 under overcast. */
static void luminous_efficacies_are_littlefairs(void)
{
	CHECK_NEAR(cs_beam_efficacy_lm_w(10.0), 70.0, 0.5);
	CHECK_NEAR(cs_beam_efficacy_lm_w(60.0), 95.0, 0.5);
	CHECK(cs_beam_efficacy_lm_w(35.0) > 70.0 && cs_beam_efficacy_lm_w(35.0) < 95.0);
	CHECK_NEAR(cs_diffuse_efficacy_lm_w(1.0), 144.0, 0.5);
	CHECK_NEAR(cs_diffuse_efficacy_lm_w(0.0), 115.0, 0.5);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(slab_transmittance_is_beer_lambert),
	CASE(light_cache_agrees_with_a_fine_march),
	CASE(thick_slab_transmits_like_one_over_tau),
	CASE(luminous_efficacies_are_littlefairs),
	CASE(clear_sky_rays_are_the_sky_model),
	CASE(diffuse_irradiance_never_sees_the_sun_disc),
	CASE(deck_transmittance_matches_a_monte_carlo_slab),
	CASE(renderer_reflectance_against_monte_carlo),
	CASE(thunderstorm_has_no_speckles),
	CASE(moon_and_stars_only_at_night),
	CASE(cloud_shadows_darken_the_haze),
	CASE(thin_cirrostratus_shows_the_22_degree_halo),
	CASE(rain_and_snow_extinction_follow_published_relations),
	CASE(precipitation_only_when_it_rains_or_snows),
	CASE(snow_alone_is_marched_as_rain_is),
	CASE(black_object_at_the_visibility_keeps_two_percent_contrast),
	CASE(fog_extinction_at_the_ground_is_koschmieder),
	CASE(escape_function_is_chandrasekhars),
	CASE(face_sky_share_is_the_view_factor),
	CASE(fog_under_a_deck_adds_no_sunlight),
	CASE(deep_overcast_base_dims_like_one_over_tau),
	CASE(a_thin_veil_is_as_bright_as_the_adding_doubling_slab),
	CASE(fields_change_hands_without_a_step),
	CASE(rain_column_matches_adding_doubling),
	CASE(rain_scatters_the_light_around_it),
	CASE(rain_near_the_ground_takes_the_ground_planes_light),
	CASE(a_cloud_reaching_into_a_deck_is_lit_through_it),
	CASE(light_march_toward_any_sun_is_beer_lambert),
	CASE(a_far_tower_shadows_the_ground_under_a_low_sun),
	CASE(a_far_towers_shadow_at_the_presets_light_steps),
	CASE(overcast_ground_sees_the_transmitted_light),
	CASE(slab_single_scattering_matches_closed_form),
	CASE(adaptive_march_refines_dense_steps),
	CASE(cone_light_march_sees_beside_the_path),
	CASE(source_every_other_sample_is_the_mean_of_its_neighbours),
	CASE(doubling_steps_halves_the_error),
	CASE(phase_hg_is_normalised),
	CASE(clear_sky_has_no_alpha_and_costs_nothing),
	CASE(absent_effects_cost_nothing),
	CASE(more_coverage_gives_more_cloud),
	CASE(output_is_identical_for_any_thread_count),
	CASE(hard_rays_stay_finite),
	CASE(random_scenes_render_finite_pixels),
	CASE(higher_clouds_shade_lower_ones),
	CASE(cloud_shadow_is_displaced_along_the_sun),
	CASE(terrain_is_the_ground_where_it_is),
	CASE(quality_presets_exist_and_rise),
};

int main(void)
{
	if (cs_volume_new(&noise, 32, 32) != CS_OK ||
	    cs_volume_bake(&noise, 0, NULL, NULL) != CS_OK)
		return 1;
	T_RUN_TABLE(t_cases);
	cs_volume_free(&noise);
	TEST_EXIT();
}
