#include "core/err.h"
#include "noise/noise.h"
#include "test.h"

/* Values printed by Ken Perlin's reference ImprovedNoise.java (2002),
 * compiled and run unchanged; the first is the well-known
 * noise(3.14, 42, 7) = 0.13691995878400012. */
static const double perlin_ref[][4] = {
	{3.14, 42.0, 7.0, 0.13691995878400012},
	{0.5, 0.5, 0.5, -0.25},
	{1.25, 2.5, 3.75, -0.038363456726074220},
	{-0.3, 0.7, -1.9, 0.43756943182041597},
	{-12.34, -5.67, -8.9, -0.44827855758591550},
	{100.1, -200.2, 300.3, -0.52308448906691230},
	{0.1, 0.2, 0.3, 0.35122924878110723},
	{-255.7, 0.33, 17.01, -0.023460330343180583},
	{7.77, -3.33, 0.999, 0.13419143617270318},
};

static void perlin_matches_ken_perlin_reference(void)
{
	for (size_t i = 0; i < sizeof perlin_ref / sizeof perlin_ref[0]; i++) {
		const double *r = perlin_ref[i];
		CHECK_NEAR(cs_perlin3(r[0], r[1], r[2]), r[3], 1e-6);
	}
}

static void perlin_is_zero_on_the_lattice(void)
{
	static const int per[3] = {5, 0, 7};
	for (int i = -3; i <= 3; i++) {
		CHECK(cs_perlin3(i, 2 * i, -i) == 0.0);
		CHECK(cs_perlin3p(i, 2 * i, -i, per, 9) == 0.0);
	}
}

/* f(x + k*p) == f(x) for negative and large k, on each axis. */
static void perlin_periodic_at_negative_and_large_coordinates(void)
{
	static const int per[3] = {3, 4, 5};
	unsigned st = 1;
	for (int i = 0; i < 2000; i++) {
		double x = t_uniform(&st, -10, 10), y = t_uniform(&st, -10, 10),
		       z = t_uniform(&st, -10, 10);
		double v = cs_perlin3p(x, y, z, per, 42);
		CHECK_NEAR(cs_perlin3p(x - 3 * 7, y, z, per, 42), v, 1e-9);
		CHECK_NEAR(cs_perlin3p(x, y + 4 * 1000, z, per, 42), v, 1e-9);
		CHECK_NEAR(cs_perlin3p(x, y, z - 5 * 200000, per, 42), v, 1e-8);
		CHECK_NEAR(cs_perlin3p(x + 3 * 1000000, y - 4 * 1000000,
				       z + 5 * 1000000, per, 42), v, 1e-7);
	}
}

/* Documented range: |n| <= 1.04 (measured 1.013), and the range is used. */
static void perlin_range_is_about_unit(void)
{
	static const int per[3] = {0, 0, 0};
	unsigned st = 2;
	double lo = 0, hi = 0;
	for (int i = 0; i < 400000; i++) {
		double x = t_uniform(&st, -50, 50), y = t_uniform(&st, -50, 50),
		       z = t_uniform(&st, -50, 50);
		double a = cs_perlin3(x, y, z), b = cs_perlin3p(x, y, z, per, 3);
		lo = fmin(lo, fmin(a, b));
		hi = fmax(hi, fmax(a, b));
	}
	CHECK(lo >= -1.04 && hi <= 1.04);
	CHECK(lo < -0.9 && hi > 0.9);
}

static void perlin_seed_changes_the_field(void)
{
	static const int per[3] = {8, 8, 8};
	int differ = 0;
	for (int i = 0; i < 100; i++)
		differ += cs_perlin3p(i * 0.37, i * 0.11, 0.5, per, 1) !=
			  cs_perlin3p(i * 0.37, i * 0.11, 0.5, per, 2);
	CHECK(differ > 90);
}

/* Brute force: the distance to every feature point of a small periodic
 * domain, in each of its 27 neighbouring periodic images, against the fast
 * search, at many random queries (negative and far ones included). */
static void worley_f1_equals_bruteforce(void)
{
	static const int per[3] = {3, 4, 2};
	unsigned st = 3;
	int bad = 0;
	for (int q = 0; q < 20000; q++) {
		double x = t_uniform(&st, -7, 7), y = t_uniform(&st, -9, 9),
		       z = t_uniform(&st, -5, 5);
		if (q % 10 == 0) {
			x += 3 * 1000;
			z -= 2 * 50000;
		}
		/* reduce the query into the base period as a true modulo */
		double rx = x - 3 * floor(x / 3), ry = y - 4 * floor(y / 4),
		       rz = z - 2 * floor(z / 2);
		double best = INFINITY;
		for (int cz = 0; cz < per[2]; cz++)
			for (int cy = 0; cy < per[1]; cy++)
				for (int cx = 0; cx < per[0]; cx++) {
					double p[3];
					cs_worley_feature(cx, cy, cz, per, 11, p);
					for (int k = -1; k <= 1; k++)
						for (int j = -1; j <= 1; j++)
							for (int i = -1; i <= 1; i++) {
								double dx = cx + p[0] + i * per[0] - rx;
								double dy = cy + p[1] + j * per[1] - ry;
								double dz = cz + p[2] + k * per[2] - rz;
								best = fmin(best, dx * dx + dy * dy + dz * dz);
							}
				}
		double fast = cs_worley3p(x, y, z, per, 11);
		if (fabs(fast - sqrt(best)) > 1e-9) {
			if (bad++ < 5)
				printf("  query (%g,%g,%g): fast %.12f brute %.12f\n",
				       x, y, z, fast, sqrt(best));
		}
	}
	CHECK(bad == 0);
}

/* Non-periodic F1 against a brute force over the 7^3 nearest cells. */
static void worley_f1_unbounded_equals_bruteforce(void)
{
	static const int per[3] = {0, 0, 0};
	unsigned st = 4;
	int bad = 0;
	for (int q = 0; q < 5000; q++) {
		double x = t_uniform(&st, -100, 100), y = t_uniform(&st, -100, 100),
		       z = t_uniform(&st, -100, 100);
		int X = (int)floor(x), Y = (int)floor(y), Z = (int)floor(z);
		double best = INFINITY;
		for (int k = -3; k <= 3; k++)
			for (int j = -3; j <= 3; j++)
				for (int i = -3; i <= 3; i++) {
					double p[3];
					cs_worley_feature(X + i, Y + j, Z + k, per, 5, p);
					double dx = X + i + p[0] - x, dy = Y + j + p[1] - y,
					       dz = Z + k + p[2] - z;
					best = fmin(best, dx * dx + dy * dy + dz * dz);
				}
		bad += fabs(cs_worley3p(x, y, z, per, 5) - sqrt(best)) > 1e-9;
	}
	CHECK(bad == 0);
}

static void worley_periodic_at_negative_and_large_coordinates(void)
{
	static const int per[3] = {5, 2, 7};
	unsigned st = 6;
	for (int i = 0; i < 2000; i++) {
		double x = t_uniform(&st, -10, 10), y = t_uniform(&st, -10, 10),
		       z = t_uniform(&st, -10, 10);
		double v = cs_worley3p(x, y, z, per, 8);
		CHECK_NEAR(cs_worley3p(x - 5 * 3, y, z, per, 8), v, 1e-9);
		CHECK_NEAR(cs_worley3p(x, y + 2 * 1000001, z, per, 8), v, 1e-8);
		CHECK_NEAR(cs_worley3p(x, y, z - 7 * 300000, per, 8), v, 1e-8);
	}
}

static void worley_is_zero_at_its_feature_points(void)
{
	static const int per[3] = {4, 4, 4};
	for (int c = 0; c < 20; c++) {
		double p[3];
		cs_worley_feature(c % 4, c / 4 % 4, -c, per, 2, p);
		CHECK_NEAR(cs_worley3p(c % 4 + p[0], c / 4 % 4 + p[1], -c + p[2],
				       per, 2), 0.0, 1e-12);
	}
}

/* fBm is normalised by the sum of amplitudes: one octave is the base noise,
 * and the documented ranges hold (and are used) for several settings. */
static void fbm_one_octave_is_the_base_noise(void)
{
	static const int per[3] = {4, 4, 4};
	struct cs_fbm one = {1, 2, 0.5};
	for (int i = 0; i < 50; i++) {
		double x = i * 0.173, y = i * 0.311, z = -i * 0.057;
		CHECK(cs_perlin_fbm3p(x, y, z, per, 3, &one) ==
		      cs_perlin3p(x, y, z, per, 3));
		double f1 = cs_worley3p(x, y, z, per, 3);
		CHECK_NEAR(cs_worley_fbm3p(x, y, z, per, 3, &one),
			   1.0 - fmin(f1, 1.0), 1e-15);
	}
}

static void fbm_ranges_hold(void)
{
	static const int per[3] = {4, 4, 4};
	static const struct cs_fbm set[] = {{1, 2, 0.5}, {4, 2, 0.5}, {6, 3, 0.7},
					    {3, 2, 1.0}};
	for (size_t s = 0; s < sizeof set / sizeof set[0]; s++) {
		unsigned st = 7 + (unsigned)s;
		double plo = 1, phi = -1, wlo = 1, whi = 0, pwlo = 1, pwhi = 0;
		for (int i = 0; i < 40000; i++) {
			double x = t_uniform(&st, -8, 8), y = t_uniform(&st, -8, 8),
			       z = t_uniform(&st, -8, 8);
			double p = cs_perlin_fbm3p(x, y, z, per, 1, &set[s]);
			double w = cs_worley_fbm3p(x, y, z, per, 1, &set[s]);
			double pw = cs_perlin_worley3p(x, y, z, per, 1, &set[s], &set[s]);
			plo = fmin(plo, p), phi = fmax(phi, p);
			wlo = fmin(wlo, w), whi = fmax(whi, w);
			pwlo = fmin(pwlo, pw), pwhi = fmax(pwhi, pw);
		}
		CHECK(plo >= -1.0 && phi <= 1.0 && phi - plo > 0.6);
		CHECK(wlo >= 0.0 && whi <= 1.0 && whi - wlo > 0.5);
		CHECK(pwlo >= 0.0 && pwhi <= 1.0 && pwhi - pwlo > 0.3);
	}
}

static void fbm_is_periodic(void)
{
	static const int per[3] = {2, 3, 4};
	struct cs_fbm f = {5, 2, 0.5};
	unsigned st = 9;
	for (int i = 0; i < 500; i++) {
		double x = t_uniform(&st, -4, 4), y = t_uniform(&st, -4, 4),
		       z = t_uniform(&st, -4, 4);
		CHECK_NEAR(cs_perlin_fbm3p(x + 2, y - 3, z + 8, per, 5, &f),
			   cs_perlin_fbm3p(x, y, z, per, 5, &f), 1e-9);
		CHECK_NEAR(cs_perlin_worley3p(x - 20, y + 30, z - 4, per, 5, &f, &f),
			   cs_perlin_worley3p(x, y, z, per, 5, &f, &f), 1e-9);
	}
}

static void fbm_check_rejects_bad_settings(void)
{
	struct cs_fbm ok = {4, 2, 0.5}, o0 = {0, 2, 0.5}, l1 = {4, 1, 0.5},
		      g0 = {4, 2, 0.0}, gn = {4, 2, NAN};
	CHECK(cs_fbm_check(&ok) == CS_OK);
	CHECK(cs_fbm_check(&o0) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "octaves");
	CHECK(cs_fbm_check(&l1) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "lacunarity");
	CHECK(cs_fbm_check(&g0) == CS_EINVAL);
	CHECK(cs_fbm_check(&gn) == CS_EINVAL);
	CHECK_STR_CONTAINS(cs_errmsg(), "gain");
}

/* Non-finite or huge coordinates give a finite value (under UBSan: no
 * undefined conversion), never a crash. */
static void noise_survives_nonfinite_and_huge_input(void)
{
	static const int per[3] = {4, 0, 4};
	double v[] = {NAN, INFINITY, -INFINITY, 1e300, -1e300, 3e9, -3e9};
	for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
		CHECK(isfinite(cs_perlin3p(v[i], v[i], v[i], per, 1)));
		CHECK(isfinite(cs_worley3p(v[i], v[i], 0.5, per, 1)));
		CHECK(isfinite(cs_perlin3(v[i], 0.5, -v[i])));
	}
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(perlin_matches_ken_perlin_reference),
	CASE(perlin_is_zero_on_the_lattice),
	CASE(perlin_periodic_at_negative_and_large_coordinates),
	CASE(perlin_range_is_about_unit),
	CASE(perlin_seed_changes_the_field),
	CASE(worley_f1_equals_bruteforce),
	CASE(worley_f1_unbounded_equals_bruteforce),
	CASE(worley_periodic_at_negative_and_large_coordinates),
	CASE(worley_is_zero_at_its_feature_points),
	CASE(fbm_one_octave_is_the_base_noise),
	CASE(fbm_ranges_hold),
	CASE(fbm_is_periodic),
	CASE(fbm_check_rejects_bad_settings),
	CASE(noise_survives_nonfinite_and_huge_input),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
