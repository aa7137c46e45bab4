/* The tabulated lattices of noisebake against the direct noise functions
 * (noise.c's cs_worley3p and cs_perlin3p, which hash every lookup): the
 * same value, bit for bit, for every period shape a recipe can make. */
#include "core/hash.h"
#include "noise/noise.h"
#include "test.h"

#include <math.h>
#include <string.h>

static const int periods[][3] = {
	{1, 1, 1}, {2, 2, 1}, {3, 3, 2}, {4, 4, 4}, {5, 5, 3}, {8, 8, 8}, {16, 16, 5}, {64, 64, 64},
};

static double coord(uint32_t *k, double span)
{
	return span * cs_hash_unit(cs_hash_u32((*k)++ * 0x9e3779b9u + 7u));
}

/* Points inside the period (the baker's), outside it, negative and huge,
 * and on cell corners. */
static void point(uint32_t *k, const int p[3], int i, double xyz[3])
{
	for (int a = 0; a < 3; a++) {
		double x = coord(k, p[a]);
		if (i % 5 == 1)
			x = x * 7.0 - 3.0 * p[a];
		else if (i % 5 == 2)
			x = -x - 1e7;
		else if (i % 5 == 3)
			x = (double)(int)x; /* on the lattice */
		xyz[a] = x;
	}
}

static void worley_lut_equals_direct(void)
{
	uint32_t k = 1;
	long n = 0, far = 0;
	for (size_t j = 0; j < sizeof periods / sizeof periods[0]; j++) {
		struct cs_lattice_lut t;
		uint32_t seed = 1234u + (uint32_t)j;
		CHECK(cs_lattice_lut_new(&t, periods[j], seed, 1) == 0);
		struct cs_worley_cache w;
		w.key[0] = -1;
		for (int i = 0; i < 20000; i++) {
			double q[3];
			point(&k, periods[j], i, q);
			double a = cs_worley3p_lut(&t, &w, q[0], q[1], q[2]);
			double b = cs_worley3p(q[0], q[1], q[2], periods[j], seed);
			CHECK(memcmp(&a, &b, sizeof a) == 0);
			far += b > 1.0;
			n++;
		}
		cs_lattice_lut_free(&t);
	}
	/* the search past the 27 nearest cells was exercised too */
	printf("  %ld points, %ld with the nearest feature farther than a cell\n", n, far);
	CHECK(far > 0);
}

static void perlin_lut_equals_direct(void)
{
	uint32_t k = 5;
	for (size_t j = 0; j < sizeof periods / sizeof periods[0]; j++) {
		struct cs_lattice_lut t;
		uint32_t seed = 77u + (uint32_t)j;
		CHECK(cs_lattice_lut_new(&t, periods[j], seed, 0) == 0);
		for (int i = 0; i < 20000; i++) {
			double q[3];
			point(&k, periods[j], i, q);
			double a = cs_perlin3p_lut(&t, q[0], q[1], q[2]);
			double b = cs_perlin3p(q[0], q[1], q[2], periods[j], seed);
			CHECK(memcmp(&a, &b, sizeof a) == 0);
		}
		cs_lattice_lut_free(&t);
	}
}

/* A row's x coordinates: voxel centres across the period (runs in one
 * cell, n / period of them: the candidate and the direct paths), then
 * points anywhere, out of order, negative, huge and on the lattice. */
static void row_x(uint32_t *k, const int p[3], int n, int kind, double *x)
{
	for (int i = 0; i < n; i++) {
		if (kind == 0) {
			x[i] = (i + 0.5) / n * p[0];
		} else {
			double q[3];
			point(k, p, i, q);
			x[i] = q[0];
		}
	}
}

/* Row y, z of the point set: the baker's (inside the period) or any. */
static void row_yz(uint32_t *k, const int p[3], int r, double *y, double *z)
{
	double q[3];
	point(k, p, r % 2 == 0 ? 0 : r, q);
	*y = q[1], *z = q[2];
}

static void worley_rows_equal_direct(void)
{
	uint32_t k = 3;
	long n = 0, far = 0;
	enum { N = 256 };
	double x[N], f1[N];
	for (size_t j = 0; j < sizeof periods / sizeof periods[0]; j++) {
		struct cs_lattice_lut t;
		uint32_t seed = 4321u + (uint32_t)j;
		CHECK(cs_lattice_lut_new(&t, periods[j], seed, 1) == 0);
		struct cs_worley_row wr;
		CHECK(cs_worley_row_init(&wr, &t) == 0);
		for (int r = 0; r < 60; r++) {
			/* 256 points: 8 or more a cell up to a period of 32;
			 * 5 points: fewer */
			int m = r % 3 == 2 ? 5 : N;
			double y0, z;
			row_yz(&k, periods[j], r, &y0, &z);
			row_x(&k, periods[j], m, r % 3 == 1, x);
			/* then two more rows in the same row of cells, as the
			 * rows of a slice come (what the rows keep between them) */
			double ys[3] = {y0, floor(y0) + 0.3125, floor(y0) + 0.8125};
			for (int q = 0; q < 3; q++) {
				cs_worley_row_lut(&wr, ys[q], z, x, m, f1);
				for (int i = 0; i < m; i++) {
					double b = cs_worley3p(x[i], ys[q], z, periods[j], seed);
					CHECK(memcmp(&f1[i], &b, sizeof b) == 0);
					far += b > 1.0;
					n++;
				}
			}
		}
		cs_worley_row_free(&wr);
		cs_lattice_lut_free(&t);
	}
	printf("  %ld points in rows, %ld with the nearest feature farther than a cell\n", n, far);
	CHECK(far > 0);
}

static void perlin_rows_equal_direct(void)
{
	uint32_t k = 9;
	enum { N = 256 };
	double x[N], v[N];
	for (size_t j = 0; j < sizeof periods / sizeof periods[0]; j++) {
		struct cs_lattice_lut t;
		uint32_t seed = 99u + (uint32_t)j;
		CHECK(cs_lattice_lut_new(&t, periods[j], seed, 0) == 0);
		for (int r = 0; r < 60; r++) {
			int m = r % 3 == 2 ? 7 : N;
			double y, z;
			row_yz(&k, periods[j], r, &y, &z);
			row_x(&k, periods[j], m, r % 3 == 1, x);
			cs_perlin_row_lut(&t, y, z, x, m, v);
			for (int i = 0; i < m; i++) {
				double b = cs_perlin3p(x[i], y, z, periods[j], seed);
				CHECK(memcmp(&v[i], &b, sizeof b) == 0);
			}
		}
		cs_lattice_lut_free(&t);
	}
}

static void oversized_lattice_is_refused(void)
{
	struct cs_lattice_lut t;
	int big[3] = {256, 256, 256};
	CHECK(cs_lattice_lut_new(&t, big, 0, 1) != 0);
	CHECK(t.feat == NULL && t.grad == NULL);
}

static const struct t_case t_cases[] = {
	CASE(worley_lut_equals_direct),
	CASE(perlin_lut_equals_direct),
	CASE(worley_rows_equal_direct),
	CASE(perlin_rows_equal_direct),
	CASE(oversized_lattice_is_refused),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
