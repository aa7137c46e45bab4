/* test_haze.c - the air's extinction as the scene builds it from the
 * weather's visibility V, against Koschmieder (1924): a black object at
 * the visibility keeps 2 % of its contrast, so along the ground the
 * extinction is 3.912 / V; the aerosol thins with height over a 1.2 km
 * scale height (scene.c, man cloudrender); fog below 1 km visibility fills
 * a layer from the ground up.  The optical depths cs_haze_depth and
 * cs_fog_depth give along rays are checked against a midpoint quadrature
 * of that extinction written here, and against the geometry of the fog's
 * top. */
#include "core/err.h"
#include "render/march.h"
#include "render/render.h"
#include "render/scene.h"
#include "test.h"
#include "weather/wx.h"

static struct cs_scene sc;

/* the extinction at altitude h written from the definitions above (no fog) */
static double beta(double V, double site_m, double h)
{
	return 3.912 / V * exp(-(h - site_m) / 1200.0);
}

static double quad(double V, double site_m, double h0, double dz, double t)
{
	const int n = 20000;
	double s = 0.0;
	for (int i = 0; i < n; i++)
		s += beta(V, site_m, h0 + dz * (i + 0.5) * t / n) * t / n;
	return s;
}

static void haze_is_koschmieder_at_the_ground_and_thins_with_height(void)
{
	static const double vis[] = {2000, 5000, 10000, 30000, 80000};
	for (size_t k = 0; k < sizeof vis / sizeof vis[0]; k++) {
		struct cs_wx wx;
		cs_wx_default(&wx);
		wx.nlayers = 0;
		wx.visibility_m = vis[k];
		CHECK(cs_scene_build(&sc, &wx, wx.time_utc, NULL) == CS_OK);
		double a = wx.site.alt_m;
		/* along the ground over V: exp(-3.912), 2 % */
		double tau = cs_haze_depth(&sc, a, 0.0, vis[k]) + cs_fog_depth(&sc, a, 0.0, vis[k]);
		CHECK_NEAR(exp(-tau), 0.02, 0.0005);
		/* slanted rays up and down, near and far */
		static const double rays[][3] = {{0, 0.1, 5000},  {0, 0.5, 20000}, {1000, 0.02, 30000},
						 {3000, -0.3, 9000}, {200, 1.0, 8000}, {5000, -0.05, 40000}};
		for (size_t r = 0; r < sizeof rays / sizeof rays[0]; r++) {
			double h0 = a + rays[r][0], dz = rays[r][1], t = rays[r][2];
			double want = quad(vis[k], a, h0, dz, t);
			double got = cs_haze_depth(&sc, h0, dz, t);
			if (!(fabs(got - want) <= 1e-3 * want)) {
				printf("  V %g ray %zu: depth %.6g, expected %.6g\n", vis[k], r, got, want);
				t_case_failed = 1;
			}
		}
	}
}

static void fog_fills_the_layer_from_the_ground_to_its_top(void)
{
	struct cs_wx wx;
	cs_wx_default(&wx);
	wx.nlayers = 0;
	wx.visibility_m = 300.0;
	CHECK(cs_scene_build(&sc, &wx, wx.time_utc, NULL) == CS_OK);
	CHECK(sc.effects & CS_FX_FOG);
	double a = wx.site.alt_m, top = sc.fog_top_m, b = sc.fog_beta_per_m;
	CHECK(top > a);
	/* in the fog, along the ground over V: with the haze, 2 % left */
	double tau = cs_fog_depth(&sc, a + 1, 0.0, 300.0) + cs_haze_depth(&sc, a + 1, 0.0, 300.0);
	CHECK_NEAR(exp(-tau), 0.02, 0.001);
	/* from 100 m above the top down at 30 deg (dz = -0.5): the top is
	 * crossed after 200 m; 500 m of path leaves 300 m in the fog */
	CHECK_NEAR(cs_fog_depth(&sc, top + 100, -0.5, 500.0), b * 300.0, 1e-9 * b * 300.0);
	/* from 100 m below the top up at 30 deg: 200 m in the fog, then out */
	CHECK_NEAR(cs_fog_depth(&sc, top - 100, 0.5, 500.0), b * 200.0, 1e-9 * b * 200.0);
	/* above it, level or up: none */
	CHECK(cs_fog_depth(&sc, top + 10, 0.0, 1000.0) == 0.0);
	CHECK(cs_fog_depth(&sc, top + 10, 0.3, 1000.0) == 0.0);
	/* inside, any direction down: all of the path */
	CHECK_NEAR(cs_fog_depth(&sc, top - 10, -0.2, 100.0), b * 100.0, 1e-9 * b * 100.0);
}

static const struct t_case t_cases[] = {
	CASE(haze_is_koschmieder_at_the_ground_and_thins_with_height),
	CASE(fog_fills_the_layer_from_the_ground_to_its_top),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
