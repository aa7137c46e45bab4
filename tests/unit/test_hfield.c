#include "core/err.h"
#include "terrain/heightfield.h"
#include "test.h"

#include <stdlib.h>

#define R_EARTH 6371000.0

/* A grid of w x h samples, spacing dx metres, north-up, its upper-left
 * sample at world (x0, y0): col = (x - x0) / dx, row = (y0 - y) / dx. */
static void place(double x0, double y0, double dx, double a[3], double b[3])
{
	a[0] = -x0 / dx, a[1] = 1 / dx, a[2] = 0;
	b[0] = y0 / dx, b[1] = 0, b[2] = -1 / dx;
}

/* Brute force: fine steps along the ray, first sign change, bisection.
 * Also returns the smallest gap seen, to leave out tangent rays that no
 * fixed step can decide. */
static int brute(const struct cs_hfield *f, cs_v3 o, cs_v3 d, double tmax,
		 double step, double *t_hit, double *min_gap)
{
	double prev_t = 0, prev = INFINITY;
	*min_gap = INFINITY;
	for (double t = 0; t <= tmax; t += step) {
		cs_v3 p = v3_mad(o, d, t);
		double h;
		if (!cs_hfield_height(f, p.x, p.y, &h)) {
			prev = INFINITY;
			prev_t = t;
			continue;
		}
		double g = cs_hfield_altitude(f, p) - h;
		*min_gap = fmin(*min_gap, fabs(g));
		if (g <= 0) {
			if (!isfinite(prev)) {
				/* entered the grid below its surface: the hit is
				 * the grid's edge, found by bisection */
				double lo = prev_t, hi = t;
				for (int k = 0; k < 60; k++) {
					double mid = 0.5 * (lo + hi), hh;
					cs_v3 q = v3_mad(o, d, mid);
					if (cs_hfield_height(f, q.x, q.y, &hh))
						hi = mid;
					else
						lo = mid;
				}
				*t_hit = hi;
				return 1;
			}
			double lo = prev_t, hi = t;
			for (int k = 0; k < 60; k++) {
				double mid = 0.5 * (lo + hi);
				cs_v3 q = v3_mad(o, d, mid);
				double hh;
				cs_hfield_height(f, q.x, q.y, &hh);
				if (cs_hfield_altitude(f, q) - hh > 0)
					lo = mid;
				else
					hi = mid;
			}
			*t_hit = hi;
			return 1;
		}
		prev = g;
		prev_t = t;
	}
	return 0;
}

static void flat_ground_is_hit_exactly(void)
{
	enum { W = 65 };
	static float z[W * W];
	for (int i = 0; i < W * W; i++)
		z[i] = 500.0f;
	double a[3], b[3];
	place(-3200, 3200, 100, a, b);
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, W, a, b, R_EARTH) == CS_OK);
	double t;
	CHECK(cs_hfield_intersect(&f, v3(0, 0, 1000), v3(0, 0, -1), 1e6, &t, NULL));
	CHECK_NEAR(t, 500.0, 1e-6);
	/* slanted: the hit lies on the sphere of radius R + 500 */
	cs_v3 d = v3_norm(v3(0.3, 0.2, -0.4));
	CHECK(cs_hfield_intersect(&f, v3(0, 0, 1000), d, 1e6, &t, NULL));
	CHECK_NEAR(cs_hfield_altitude(&f, v3_mad(v3(0, 0, 1000), d, t)), 500.0, 1e-6);
	/* upward and outward rays miss */
	CHECK(!cs_hfield_intersect(&f, v3(0, 0, 1000), v3(0, 0, 1), 1e6, &t, NULL));
	CHECK(!cs_hfield_intersect(&f, v3(0, 0, 1000), v3(1, 0, 0), 1e6, &t, NULL));
	cs_hfield_free(&f);
}

/* A ridge one sample wide, 300 m high, on flat 0 m ground: rays at grazing
 * angles toward it never pass through, and agree with brute force. */
static void grazing_rays_never_tunnel_through_a_thin_ridge(void)
{
	enum { W = 101 };
	static float z[W * W];
	for (int j = 0; j < W; j++)
		for (int i = 0; i < W; i++)
			z[j * W + i] = i == 60 ? 300.0f : 0.0f;
	double a[3], b[3];
	place(-1000, 1000, 20, a, b); /* 2 km square, ridge along x = 200 m */
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, W, a, b, R_EARTH) == CS_OK);
	unsigned st = 8;
	int compared = 0, bad = 0, hits = 0;
	for (int n = 0; n < 400; n++) {
		cs_v3 o = v3(t_uniform(&st, -990, -200), t_uniform(&st, -900, 900),
			     t_uniform(&st, 250, 320));
		double az = t_uniform(&st, -1.2, 1.2); /* roughly toward +x */
		double el = t_uniform(&st, -0.06, 0.02);
		cs_v3 d = v3_norm(v3(cos(az) * cos(el), sin(az) * cos(el), sin(el)));
		double te, tb, gmin;
		int he = cs_hfield_intersect(&f, o, d, 5000, &te, NULL);
		int hb = brute(&f, o, d, 5000, 0.05, &tb, &gmin);
		if (gmin < 0.05)
			continue; /* tangent: undecidable by fixed steps */
		compared++;
		hits += hb;
		if (he != hb || (he && fabs(te - tb) > 1e-3)) {
			if (bad++ < 5)
				printf("  ray %d: exact %d t=%.4f, brute %d t=%.4f\n", n, he, te, hb, tb);
		}
	}
	CHECK(bad == 0);
	CHECK(compared > 300 && hits > 50 && hits < compared);
	cs_hfield_free(&f);
}

/* Rough random terrain: every ray agrees with brute force. */
static void random_terrain_agrees_with_brute_force(void)
{
	enum { W = 70, H = 50 };
	static float z[W * H];
	unsigned st = 9;
	for (int i = 0; i < W * H; i++)
		z[i] = (float)t_uniform(&st, 0, 200);
	double a[3], b[3];
	/* a rotated, anisotropic placement: grid axes not aligned with x, y */
	double col[3] = {0, W - 1, 0}, row[3] = {0, 0, H - 1};
	double x[3] = {-500, 800, -300}, y[3] = {400, 600, -900};
	CHECK(cs_hfield_place(col, row, x, y, a, b) == CS_OK);
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, H, a, b, R_EARTH) == CS_OK);
	int bad = 0, compared = 0, hits = 0;
	for (int n = 0; n < 500; n++) {
		cs_v3 o = v3(t_uniform(&st, -600, 900), t_uniform(&st, -900, 700),
			     t_uniform(&st, 210, 400));
		double az = t_uniform(&st, 0, 2 * CS_PI), el = t_uniform(&st, -0.8, 0.05);
		cs_v3 d = v3(cos(az) * cos(el), sin(az) * cos(el), sin(el));
		double te, tb, gmin;
		int he = cs_hfield_intersect(&f, o, d, 4000, &te, NULL);
		int hb = brute(&f, o, d, 4000, 0.05, &tb, &gmin);
		if (gmin < 0.05)
			continue;
		compared++;
		hits += hb;
		if (he != hb || (he && fabs(te - tb) > 1e-3)) {
			if (bad++ < 5)
				printf("  ray %d: exact %d t=%.4f, brute %d t=%.4f\n", n, he, te, hb, tb);
		}
	}
	printf("  compared %d rays, %d hits\n", compared, hits);
	CHECK(bad == 0 && compared > 300 && hits > 80);
	cs_hfield_free(&f);
}

static void placement_maps_grid_to_world_and_back(void)
{
	double col[3] = {0, 99, 0}, row[3] = {0, 0, 49};
	double x[3] = {10, 1000, 20}, y[3] = {500, 530, -10};
	double a[3], b[3];
	CHECK(cs_hfield_place(col, row, x, y, a, b) == CS_OK);
	for (int k = 0; k < 3; k++) {
		CHECK_NEAR(a[0] + a[1] * x[k] + a[2] * y[k], col[k], 1e-9);
		CHECK_NEAR(b[0] + b[1] * x[k] + b[2] * y[k], row[k], 1e-9);
	}
	double xs[3] = {0, 1, 2}, ys[3] = {0, 1, 2};
	CHECK(cs_hfield_place(col, row, xs, ys, a, b) == CS_EINVAL);
}

static void normal_of_a_tilted_plane(void)
{
	enum { W = 20 };
	static float z[W * W];
	double a[3], b[3];
	place(0, 0, 10, a, b);
	for (int j = 0; j < W; j++)
		for (int i = 0; i < W; i++)
			z[j * W + i] = (float)(0.5 * i * 10); /* rises 0.5 m per m eastward */
	struct cs_hfield f;
	CHECK(cs_hfield_init(&f, z, W, W, a, b, R_EARTH) == CS_OK);
	cs_v3 n = cs_hfield_normal(&f, 55, -77);
	cs_v3 want = v3_norm(v3(-0.5, 0, 1));
	CHECK_NEAR(n.x, want.x, 1e-9);
	CHECK_NEAR(n.y, want.y, 1e-9);
	CHECK_NEAR(n.z, want.z, 1e-9);
	double h;
	CHECK(cs_hfield_height(&f, 55, -77, &h) == 1);
	CHECK_NEAR(h, 27.5, 1e-9);
	CHECK(cs_hfield_height(&f, -5, 10, &h) == 0);
	cs_hfield_free(&f);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(flat_ground_is_hit_exactly),
	CASE(grazing_rays_never_tunnel_through_a_thin_ridge),
	CASE(random_terrain_agrees_with_brute_force),
	CASE(placement_maps_grid_to_world_and_back),
	CASE(normal_of_a_tilted_plane),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
