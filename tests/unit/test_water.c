/* Open water (render/water.h, cs_water_light) against Fresnel's closed
 * form, and the GMT palette (io/cpt.h) against known colours. */
#include "test.h"

#include "core/err.h"
#include "core/time.h"
#include "io/cpt.h"
#include "render/march.h"
#include "render/scene.h"
#include "render/water.h"

#include <stdlib.h>

/* Fresnel's equations for unpolarised light from air (n = 1) into a
 * medium of index n at incidence cos_i (Hecht, Optics, 4.34 and 4.40):
 * the mean of the s and p reflectances. */
static double fresnel_exact(double cos_i, double n)
{
	double sin_t = sqrt(1.0 - cos_i * cos_i) / n;
	double cos_t = sqrt(1.0 - sin_t * sin_t);
	double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
	double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
	return 0.5 * (rs * rs + rp * rp);
}

static void fresnel_matches_the_closed_form(void)
{
	/* normal incidence: ((n-1)/(n+1))^2, 2.04 % for water */
	CHECK_NEAR(cs_water_fresnel(1.0), fresnel_exact(1.0, 1.333), 1e-6);
	CHECK_NEAR(cs_water_fresnel(1.0), 0.0204, 0.0001);
	for (int deg = 0; deg <= 89; deg++) {
		double c = cos(deg * CS_PI / 180.0);
		CHECK_NEAR(cs_water_fresnel(c), fresnel_exact(c, 1.333), 1e-9);
	}
	CHECK_NEAR(cs_water_fresnel(0.0), 1.0, 1e-9);
	/* Brewster's angle (53.1 deg) has the p reflectance 0: R = rs^2 / 2 */
	double cb = cos(atan(1.333));
	double sb = sin(acos(cb)) / 1.333, ct = sqrt(1 - sb * sb);
	double rs = (cb - 1.333 * ct) / (cb + 1.333 * ct);
	CHECK_NEAR(cs_water_fresnel(cb), rs * rs / 2, 1e-9);
}

/* Level water's reflectance for diffuse light, which the rain over it
 * sees under it (CS_WATER_DIFFUSE_ALBEDO): Fresnel's reflectance over the
 * hemisphere weighted by cos, 2 int_0^1 F(mu) mu dmu, by the midpoint
 * rule on Hecht's equations (0.0664; 6.6 % is the value the ocean-optics
 * texts give for a uniform sky over a flat sea).  Within 0.002: a
 * constant 20 % off (0.053 or 0.080) fails, as does the normal
 * incidence's 0.0204. */
static void diffuse_albedo_is_fresnel_over_the_hemisphere(void)
{
	enum { N = 20000 };
	double sum = 0.0;
	for (int i = 0; i < N; i++) {
		double mu = (i + 0.5) / N;
		sum += 2.0 * fresnel_exact(mu, 1.333) * mu / N;
	}
	printf("  hemispheric Fresnel reflectance of water: %.5f (the constant %.3f)\n", sum,
	       CS_WATER_DIFFUSE_ALBEDO);
	CHECK_NEAR(sum, 0.0664, 0.0002);
	CHECK_NEAR(CS_WATER_DIFFUSE_ALBEDO, sum, 0.002);
}

/* A scene over flat ground at sea level with the sky but no key light
 * (the sun's glint away): water reflects F times the sky in the mirror
 * direction, plus the water body's faint light. */
static void water_reflects_the_sky_by_fresnel(void)
{
	struct cs_wx wx;
	struct cs_scene *sc = malloc(sizeof *sc);
	cs_wx_default(&wx);
	wx.nlayers = 0;
	CHECK(cs_scene_build(sc, &wx, wx.time_utc, NULL) == CS_OK);
	sc->effects &= ~(unsigned)(CS_FX_KEY | CS_FX_DECK);
	sc->deck.on = 0;
	struct cs_render_settings s;
	cs_render_quality("low", &s);
	struct cs_render_stats st = {0};
	const double angles[] = {0.0, 45.0, 75.0, 85.0};
	for (int a = 0; a < 4; a++) {
		double th = angles[a] * CS_PI / 180.0;
		cs_v3 d = v3(sin(th), 0.0, -cos(th)); /* looking down at th from the vertical */
		cs_v3 r = v3(sin(th), 0.0, cos(th));  /* its mirror image */
		double rgb[3], sky[3];
		cs_water_light(sc, &s, v3(0, 0, 0), d, 0, &st, rgb);
		cs_scene_sky(sc, r, sky);
		double F = fresnel_exact(cos(th), 1.333);
		const double body[3] = {CS_WATER_BODY_R, CS_WATER_BODY_G, CS_WATER_BODY_B};
		for (int k = 0; k < 3; k++) {
			double up = body[k] * sc->ambient_up[k];
			double refl = (rgb[k] - (1.0 - F) * up) / sky[k];
			printf("  %2.0f deg: channel %d reflectance %.4f, Fresnel %.4f\n",
			       angles[a], k, refl, F);
			CHECK_NEAR(refl, F, 1e-6);
		}
	}
	free(sc);
}

/* The sun's glint conserves energy: a flat-ish sea under an overhead sun
 * returns about R0 of the beam (integrating the glint's radiance times the
 * cosine over the view hemisphere). */
static void glint_returns_fresnel_of_the_beam(void)
{
	const double mss = 0.02;
	double sum = 0.0;
	const int N = 400;
	for (int i = 0; i < N; i++) {        /* view zenith 0..90 */
		double tv = (i + 0.5) / N * CS_PI / 2;
		for (int j = 0; j < 2 * N; j++) { /* azimuth */
			double ph = (j + 0.5) / (2 * N) * 2 * CS_PI;
			cs_v3 v = v3(sin(tv) * cos(ph), sin(tv) * sin(ph), cos(tv));
			cs_v3 l = v3(0, 0, 1);
			cs_v3 h = v3_norm(v3_add(v, l));
			double g = cs_water_glint(v.z, l.z, h.z, v3_dot(v, h), mss);
			sum += g * v.z * sin(tv) * (CS_PI / 2 / N) * (2 * CS_PI / (2 * N));
		}
	}
	printf("  glint albedo (overhead sun, mss %.2f): %.5f, R0 %.5f\n", mss, sum,
	       fresnel_exact(1.0, 1.333));
	CHECK_NEAR(sum, fresnel_exact(1.0, 1.333), 0.002);
	/* Cox & Munk's slope variance at 10 m/s */
	CHECK_NEAR(cs_water_slope_variance(10.0), 0.0542, 1e-9);
}

static const char gray_cpt[] =
	"# a palette as makecpt writes it\n"
	"# COLOR_MODEL = RGB\n"
	"0\t0/0/0\t500\t128/128/128\n"
	"500\t128/128/128\t1000\t255/255/255 U\n"
	"B\t0/0/255\n"
	"F\t255/0/0\n"
	"N\t127\n";

static void cpt_maps_heights_to_colours(void)
{
	struct cs_cpt *p = malloc(sizeof *p);
	double c[3];
	CHECK(cs_cpt_parse(gray_cpt, p) == CS_OK);
	CHECK(p->n == 2);
	cs_cpt_color(p, 250, c); /* half-way through the first slice */
	CHECK_NEAR(c[0], 64, 1e-9); CHECK_NEAR(c[1], 64, 1e-9); CHECK_NEAR(c[2], 64, 1e-9);
	cs_cpt_color(p, 0, c);
	CHECK_NEAR(c[0], 0, 1e-9);
	cs_cpt_color(p, 500, c); /* the boundary: the second slice's start */
	CHECK_NEAR(c[1], 128, 1e-9);
	cs_cpt_color(p, 900, c); /* 128 + 0.8 (255 - 128) */
	CHECK_NEAR(c[2], 229.6, 1e-4);
	cs_cpt_color(p, -10, c); /* below: B */
	CHECK(c[0] == 0 && c[1] == 0 && c[2] == 255);
	cs_cpt_color(p, 4000, c); /* above: F */
	CHECK(c[0] == 255 && c[1] == 0 && c[2] == 0);
	cs_cpt_color(p, NAN, c); /* N, a grey */
	CHECK(c[0] == 127 && c[1] == 127 && c[2] == 127);
	/* the older format: r g b as three columns, no B/F: the ends */
	CHECK(cs_cpt_parse("-100 0 0 255 0 0 255 255\n0 0 128 0 3000 255 255 255\n", p) == CS_OK);
	cs_cpt_color(p, -50, c);
	CHECK_NEAR(c[1], 127.5, 1e-9);
	cs_cpt_color(p, 1500, c);
	CHECK_NEAR(c[0], 127.5, 1e-9); CHECK_NEAR(c[1], 191.5, 1e-9);
	cs_cpt_color(p, -500, c);
	CHECK(c[0] == 0 && c[1] == 0 && c[2] == 255);
	cs_cpt_color(p, 9000, c);
	CHECK(c[0] == 255 && c[1] == 255 && c[2] == 255);
	free(p);
}

static void cpt_errors_name_the_line(void)
{
	struct cs_cpt *p = malloc(sizeof *p);
	CHECK(cs_cpt_parse("0 0/0/0 10 1/1/1\n5 0/0/0 20 1/1/1\n", p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "line 2: slices must ascend");
	CHECK(cs_cpt_parse("0 0/0/0 10 300/0/0\n", p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "line 1:");
	CHECK(cs_cpt_parse("# COLOR_MODEL = HSV\n0 0-1-1 10 100-1-1\n", p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "RGB");
	CHECK(cs_cpt_parse("10 0 0 0 5 1 1 1\n", p) == CS_EDATA);
	CHECK_STR_CONTAINS(cs_errmsg(), "not above");
	CHECK(cs_cpt_parse("# nothing\n", p) == CS_EDATA);
	free(p);
}

static const struct t_case t_cases[] = {
	CASE(fresnel_matches_the_closed_form),
	CASE(diffuse_albedo_is_fresnel_over_the_hemisphere),
	CASE(water_reflects_the_sky_by_fresnel),
	CASE(glint_returns_fresnel_of_the_beam),
	CASE(cpt_maps_heights_to_colours),
	CASE(cpt_errors_name_the_line),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
