#include "render/cloud.h"
#include "render/render.h"
#include "weather/genus_rules.h"
#include "test.h"
#include "core/vec.h"
#include "noise/volume.h"

#include <stdlib.h>

static struct cs_volume noise;

static void layer(struct cs_cloud_layer *l, enum cs_genus g, double cov,
		  double speed, double from_deg, double t)
{
	struct cs_wx_layer wl = {g, cov, 1500, 2700};
	cs_cloud_layer_init(l, &wl, &noise, speed, from_deg, 540, t);
}

/* Clouds at time t + dt are the clouds at time t carried by the wind:
 * density(x + v dt, t + dt) = density(x, t), with v the 10-m wind scaled by
 * the documented power law to the layer's mid-height. */
static void wind_moves_clouds_consistently_in_time(void)
{
	static const double froms[] = {0, 90, 250, 333};
	double speed = 7.0, dt = 600.0;
	double factor = pow((2100.0 - 540.0) / 10.0, 1.0 / 7.0);
	for (size_t k = 0; k < 4; k++) {
		struct cs_cloud_layer a, b;
		double t = 6.6e8; /* 2021, in seconds since 2000 */
		layer(&a, CS_CUMULUS, 0.5, speed, froms[k], t);
		layer(&b, CS_CUMULUS, 0.5, speed, froms[k], t + dt);
		double f = froms[k] * CS_PI / 180;
		double vx = -sin(f) * speed * factor, vy = -cos(f) * speed * factor;
		unsigned st = 3;
		int nonzero = 0;
		for (int i = 0; i < 2000; i++) {
			double x = t_uniform(&st, -20000, 20000), y = t_uniform(&st, -20000, 20000);
			double z = t_uniform(&st, 1500, 2700);
			double da = cs_cloud_extinction(&a, &noise, x, y, z);
			double db = cs_cloud_extinction(&b, &noise, x + vx * dt, y + vy * dt, z);
			CHECK_NEAR(db, da, 1e-3 * a.extinction_per_m);
			nonzero += da > 0;
		}
		CHECK(nonzero > 100); /* the comparison saw clouds, not only sky */
	}
}

static long gcd(long a, long b)
{
	return b == 0 ? a : gcd(b, a % b);
}

/* The wind offset is kept small (reduced modulo the field's period along
 * the wind, for a float port), and the reduction is by a true period: the
 * field equals the one with the whole offset, wind x the documented power
 * law x time, computed here.  A period off by any factor shows. */
static void wind_offset_is_reduced_by_a_true_period(void)
{
	static const enum cs_genus gs[] = {CS_CUMULUS, CS_CIRRUS, CS_STRATOCUMULUS,
					   CS_ALTOSTRATUS};
	double speed = 9.0, t = 1.796e9; /* 2026, seconds since 1970 */
	double factor = pow((2100.0 - 540.0) / 10.0, 1.0 / 7.0);
	for (size_t k = 0; k < sizeof gs / sizeof gs[0]; k++) {
		const struct cs_genus_preset *p = cs_genus_preset(gs[k]);
		long a = (long)p->tile_m, b = (long)p->detail_tile_m;
		double period = p->stretch * (double)(a / gcd(a, b) * b);
		struct cs_cloud_layer l, m;
		layer(&l, gs[k], 0.5, speed, 250, t);
		CHECK(fabs(l.offset_along_m) < period);
		m = l;
		m.offset_along_m = speed * factor * t;
		unsigned st = 5;
		int nonzero = 0;
		for (int i = 0; i < 1000; i++) {
			double x = t_uniform(&st, -3e4, 3e4), y = t_uniform(&st, -3e4, 3e4);
			double z = t_uniform(&st, 1500, 2700);
			double dl = cs_cloud_extinction(&l, &noise, x, y, z);
			CHECK_NEAR(cs_cloud_extinction(&m, &noise, x, y, z), dl,
				   1e-3 * l.extinction_per_m);
			nonzero += dl > 0.0;
		}
		CHECK(nonzero > 50);
	}
}

/* The sheets have the optical depth of their ISCCP class (Rossow &
 * Schiffer 1999; typical values inside the classes: altostratus and
 * stratocumulus medium 3.6-23, nimbostratus and stratus thick > 23): the
 * mean vertical optical depth of the cloudy columns, integrated here on
 * random columns, is 12, 10, 40 and 30 at any coverage. */
static void sheets_have_their_isccp_optical_depth(void)
{
	static const struct {
		enum cs_genus g;
		double base, top, tau;
	} cases[] = {{CS_ALTOSTRATUS, 3000, 5000, 12}, {CS_STRATOCUMULUS, 1340, 2040, 10},
		     {CS_NIMBOSTRATUS, 1340, 4540, 40}, {CS_STRATUS, 840, 1340, 30}};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
		for (double cov = 0.5; cov <= 1.0; cov += 0.45) {
			struct cs_cloud_layer l;
			struct cs_wx_layer wl = {cases[k].g, cov, cases[k].base, cases[k].top};
			cs_cloud_layer_init(&l, &wl, &noise, 5.0, 200.0, 540.0, 1e8);
			unsigned st = 11;
			double sum = 0.0, dz = (wl.top_m - wl.base_m) / 64;
			int cloudy = 0;
			for (int i = 0; i < 600; i++) {
				double x = t_uniform(&st, -1e5, 1e5), y = t_uniform(&st, -1e5, 1e5), tau = 0;
				for (int j = 0; j < 64; j++)
					tau += cs_cloud_extinction(&l, &noise, x, y,
								   wl.base_m + (j + 0.5) * dz) * dz;
				if (tau > 0.0)
					sum += tau, cloudy++;
			}
			CHECK(cloudy > 100);
			CHECK_NEAR(sum / cloudy, cases[k].tau, 0.1 * cases[k].tau);
		}
}

static void coverage_zero_is_no_cloud_anywhere(void)
{
	struct cs_cloud_layer l;
	for (int g = 0; g < CS_GENUS_COUNT; g++) {
		layer(&l, (enum cs_genus)g, 0.0, 5, 200, 0);
		unsigned st = 4;
		int any = 0;
		for (int i = 0; i < 5000; i++)
			any += cs_cloud_extinction(&l, &noise, t_uniform(&st, -5e4, 5e4),
						   t_uniform(&st, -5e4, 5e4),
						   t_uniform(&st, 1500, 2700)) != 0.0;
		CHECK(any == 0);
	}
}

/* Coverage is what is drawn: the fraction of a horizontal cut through the
 * layer's core that is cloud equals the coverage (within sampling error)
 * for every genus, and rises with it. */
static void covered_fraction_follows_coverage(void)
{
	for (int g = 0; g < CS_GENUS_COUNT; g++) {
		const struct cs_genus_preset *p = cs_genus_preset((enum cs_genus)g);
		double prev = -1;
		for (double c = 0.1; c <= 0.95; c += 0.2) {
			struct cs_cloud_layer l;
			layer(&l, (enum cs_genus)g, c, 0, 0, 0);
			double h = 0.5 * (p->ramp[1] + p->ramp[2]);
			unsigned st = 5;
			int in = 0, n = 20000;
			for (int i = 0; i < n; i++)
				in += cs_cloud_extinction(&l, &noise, t_uniform(&st, -1e5, 1e5),
							  t_uniform(&st, -1e5, 1e5),
							  1500 + h * 1200) > 0;
			double frac = (double)in / n;
			if (fabs(frac - c) > 0.05)
				printf("  %s coverage %.1f: covered fraction %.3f\n",
				       cs_genus_name((enum cs_genus)g), c, frac);
			CHECK_NEAR(frac, c, 0.05);
			CHECK(frac > prev);
			prev = frac;
		}
	}
}

static void density_is_zero_outside_the_layer_and_finite_inside(void)
{
	struct cs_cloud_layer l;
	layer(&l, CS_CUMULONIMBUS, 0.9, 30, 10, 1e9);
	CHECK(cs_cloud_extinction(&l, &noise, 0, 0, 1499.9) == 0.0);
	CHECK(cs_cloud_extinction(&l, &noise, 0, 0, 2700.1) == 0.0);
	CHECK(cs_cloud_extinction(&l, &noise, 0, 0, NAN) == 0.0);
	unsigned st = 6;
	for (int i = 0; i < 5000; i++) {
		double e = cs_cloud_extinction(&l, &noise, t_uniform(&st, -1e7, 1e7),
					       t_uniform(&st, -1e7, 1e7), t_uniform(&st, 1500, 2700));
		CHECK(isfinite(e) && e >= 0 && e <= l.extinction_per_m);
	}
}

static double fraction_near(const struct cs_cloud_layer *l, double cx, double cy)
{
	unsigned st = 10;
	int in = 0, n = 4000;
	for (int i = 0; i < n; i++)
		in += cs_cloud_extinction(l, &noise, cx + t_uniform(&st, -9000, 9000),
					  cy + t_uniform(&st, -9000, 9000),
					  1500 + 0.425 * 1200) > 0;
	return (double)in / n;
}

/* Near and far weather blend by distance along the line between the sites:
 * the near layer's coverage holds at the near site and fades to nothing at
 * the far site, the far layer's the other way round. */
static void near_and_far_weather_blend_along_the_line(void)
{
	/* the far site 300 km north, so that the weight hardly changes over the
	 * 18 km squares (two tiles) sampled below */
	double fx[1] = {0}, fy[1] = {300000};
	struct cs_cloud_layer nl, fl;
	layer(&nl, CS_STRATOCUMULUS, 0.9, 0, 0, 0);
	layer(&fl, CS_STRATOCUMULUS, 0.3, 0, 0, 0);
	cs_cloud_layer_blend(&nl, &noise, -1, 1, fx, fy);
	cs_cloud_layer_blend(&fl, &noise, 0, 1, fx, fy);
	CHECK_NEAR(cs_cloud_site_weight(&nl, 0, 0), 1.0, 1e-12);
	CHECK_NEAR(cs_cloud_site_weight(&fl, 0, 0), 0.0, 1e-12);
	CHECK_NEAR(cs_cloud_site_weight(&nl, 5000, 150000), 0.5, 1e-12);
	CHECK_NEAR(cs_cloud_site_weight(&fl, -7000, 450000), 1.0, 1e-12);
	CHECK_NEAR(cs_cloud_site_weight(&nl, 0, -9000), 1.0, 1e-12);
	/* covered fractions along the line (sampled across a strip) */
	double n0 = fraction_near(&nl, 0, -20000), n1 = fraction_near(&nl, 0, 150000),
	       n2 = fraction_near(&nl, 0, 400000);
	double f0 = fraction_near(&fl, 0, -20000), f2 = fraction_near(&fl, 0, 400000);
	printf("  near layer: %.3f behind, %.3f half-way, %.3f beyond the far site\n", n0, n1, n2);
	CHECK(fabs(n0 - 0.9) < 0.06 && fabs(n1 - 0.45) < 0.06 && n2 == 0.0);
	CHECK(f0 == 0.0 && fabs(f2 - 0.3) < 0.06);
}

static void every_genus_has_a_name_and_a_preset(void)
{
	for (int g = 0; g < CS_GENUS_COUNT; g++) {
		const struct cs_genus_preset *p = cs_genus_preset((enum cs_genus)g);
		CHECK(p->extinction_per_m > 0 && p->tile_m > 0 && p->edge > 0);
		double base, top;
		cs_genus_place((enum cs_genus)g, 540.0, &base, &top);
		CHECK(base < top);
		CHECK(cs_genus_from_name(cs_genus_name((enum cs_genus)g)) == g);
	}
}

/* The coverage bound (cs_cloud_layer.bound) only saves lookups: every
 * genus at three coverages, on a 32^3 volume (a cell a voxel) and a
 * 128 x 128 x 8 one (a cell two voxels wide, a w range that wraps), gives
 * at random points in its layer exactly the extinction it gives with the
 * bound switched off (bound_n 0): a cell bounding too little (a voxel
 * left out, the wrong cell) shows.  That the comparison reaches the bound:
 * with every cell's bound set to 0 the cloudy points go clear. */
static void coverage_bound_changes_no_sample(void)
{
	struct cs_volume wide;
	CHECK(cs_volume_new(&wide, 128, 8) == 0 && cs_volume_bake(&wide, 0, NULL, NULL) == 0);
	const struct cs_volume *vols[2] = {&noise, &wide};
	static const double covs[3] = {0.2, 0.5, 0.8};
	long reached = 0, cloudy = 0, n = 0, differ = 0;
	for (int vi = 0; vi < 2; vi++)
		for (int g = 0; g < CS_GENUS_COUNT; g++)
			for (int c = 0; c < 3; c++) {
				struct cs_wx_layer wl = {(enum cs_genus)g, covs[c], 0, 0};
				cs_genus_place((enum cs_genus)g, 540.0, &wl.base_m, &wl.top_m);
				static struct cs_cloud_layer l, off, zero;
				cs_cloud_layer_init(&l, &wl, vols[vi], 6.0, 230.0, 540.0, 1e8);
				CHECK(l.bound_n == (vi == 0 ? 32 : 64) && l.bound_shift == vi);
				off = l, zero = l;
				off.bound_n = 0;
				memset(zero.bound, 0, sizeof zero.bound);
				unsigned st = 11u + (unsigned)(g * 3 + c);
				for (int i = 0; i < 4000; i++, n++) {
					double x = t_uniform(&st, -60000, 60000), y = t_uniform(&st, -60000, 60000);
					double z = t_uniform(&st, wl.base_m, wl.top_m);
					double a = cs_cloud_extinction(&l, vols[vi], x, y, z);
					double b = cs_cloud_extinction(&off, vols[vi], x, y, z);
					differ += a != b;
					cloudy += b > 0.0;
					reached += b > 0.0 &&
						   cs_cloud_extinction(&zero, vols[vi], x, y, z) == 0.0;
				}
			}
	printf("  %ld points, %ld with cloud, %ld other with the bound than without; "
	       "%ld cloudy points cleared by a zero bound\n", n, cloudy, differ, reached);
	CHECK(differ == 0);
	CHECK(cloudy > n / 10 && cloudy < n - n / 10);
	CHECK(reached > cloudy / 2);
	cs_volume_free(&wide);
}

/* Points of every genus's layer, in a volume, through the renderer's own
 * per-pixel density (cs_render_extinction) against the library's
 * cs_cloud_extinction: the number of points whose bits differ, of those
 * with cloud. */
static long kernel_differs(const struct cs_volume *v, long *cloudy)
{
	enum { N = 2003 };
	static const double odd[][3] = {
		{0x1p45, 0.0, 0.5}, {0.0, -0x1p47, 0.5}, {0x1p36, 0x1p36, 0.5}, {NAN, 0.0, 0.5},
		{INFINITY, 0.0, 0.5}, {0.0, 0.0, NAN}, {1e300, -1e300, 0.5}, {0.0, 0.0, 0.0},
		{0.0, 0.0, 1.0}, {-0x1p33, 0x1p31, 0.3},
	};
	static double xyz[3 * N], got[N];
	long differ = 0;
	/* each build of the kernel this CPU has (one that it lacks falls back
	 * to one it has, compared again) */
	static const char *const builds[] = {"avx512", "avx2", "base"};
	for (int pass = 0; pass < 3; pass++) {
		setenv("CLOUDSCAPE_KERNEL", builds[pass], 1);
		for (int g = 0; g < CS_GENUS_COUNT; g++) {
			struct cs_wx_layer wl = {(enum cs_genus)g, 0.5, 0, 0};
			cs_genus_place((enum cs_genus)g, 540.0, &wl.base_m, &wl.top_m);
			static struct cs_cloud_layer l;
			cs_cloud_layer_init(&l, &wl, v, 6.0, 230.0, 540.0, 1e8);
			unsigned st = 5u + (unsigned)g;
			for (int i = 0; i < N; i++) {
				xyz[3 * i] = t_uniform(&st, -60000, 60000);
				xyz[3 * i + 1] = t_uniform(&st, -60000, 60000);
				xyz[3 * i + 2] = t_uniform(&st, wl.base_m - 50.0, wl.top_m + 50.0);
			}
			/* the odd points, at relative heights of the layer */
			for (int k = 0; k < (int)(sizeof odd / sizeof odd[0]); k++) {
				int i = 97 * k + 13;
				xyz[3 * i] = odd[k][0], xyz[3 * i + 1] = odd[k][1];
				xyz[3 * i + 2] = wl.base_m + odd[k][2] * (wl.top_m - wl.base_m);
			}
			cs_render_extinction(&l, v, N, xyz, got);
			for (int i = 0; i < N; i++) {
				double want = cs_cloud_extinction(&l, v, xyz[3 * i], xyz[3 * i + 1],
								  xyz[3 * i + 2]);
				differ += memcmp(&want, &got[i], sizeof want) != 0;
				*cloudy += want > 0.0;
			}
		}
	}
	unsetenv("CLOUDSCAPE_KERNEL");
	return differ;
}

/* The density the renderer's own per-pixel code computes (cpu/kernel.c,
 * -O3: the x86-64-v4 and AVX2 builds where the CPU has them, four points
 * at a time there, and the baseline build) is the library's
 * cs_cloud_extinction bit for bit: every genus, 2003 points of its layer
 * (the benchmark of density evaluations measures that copy; 2003: the last
 * three take the batch's tail), among
 * them points the four-lane code must hand to the scalar one (beyond the
 * coverage bound's 2^30 tiles, beyond the lookup's 2^40, not finite) and
 * points on the layer's base and top; in the baked 32^3 volume, and in a
 * 128 x 128 x 8 one (coverage-bound cells 2 voxels wide) of made-up
 * values with voxels that are not numbers in R and in G (the scalar code
 * carries a shape that is not a number on to the detail, and a detail
 * that is not one to a density of 1).  A kernel built with fused
 * multiply-adds differs in the last bits and fails. */
static void kernel_density_is_the_librarys(void)
{
	long cloudy = 0, differ = kernel_differs(&noise, &cloudy);
	printf("  baked 32^3: %ld points (three kernels), %ld with cloud, %ld differ\n",
	       3L * 2003 * CS_GENUS_COUNT, cloudy, differ);
	CHECK(differ == 0);
	CHECK(cloudy > 2003);
	struct cs_volume odd;
	CHECK(cs_volume_new(&odd, 128, 8) == 0);
	unsigned st = 99u;
	for (size_t i = 0; i < (size_t)128 * 128 * 8 * 4; i++)
		odd.data[i] = (float)t_uniform(&st, 0.0, 1.0);
	for (size_t i = 0; i < (size_t)128 * 128 * 8; i += 997)
		odd.data[4 * i + (i / 997) % 2] = NAN;
	long c2 = 0, d2 = kernel_differs(&odd, &c2);
	printf("  128x128x8 with NaN voxels: %ld with cloud, %ld differ\n", c2, d2);
	CHECK(d2 == 0);
	CHECK(c2 > 2003);
	cs_volume_free(&odd);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(wind_moves_clouds_consistently_in_time),
	CASE(wind_offset_is_reduced_by_a_true_period),
	CASE(sheets_have_their_isccp_optical_depth),
	CASE(coverage_zero_is_no_cloud_anywhere),
	CASE(covered_fraction_follows_coverage),
	CASE(density_is_zero_outside_the_layer_and_finite_inside),
	CASE(near_and_far_weather_blend_along_the_line),
	CASE(every_genus_has_a_name_and_a_preset),
	CASE(coverage_bound_changes_no_sample),
	CASE(kernel_density_is_the_librarys),
};

int main(void)
{
	if (cs_volume_new(&noise, 32, 32) != 0 || cs_volume_bake(&noise, 0, NULL, NULL) != 0)
		return 1;
	T_RUN_TABLE(t_cases);
	cs_volume_free(&noise);
	TEST_EXIT();
}
