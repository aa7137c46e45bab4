#include "terrain/heightfield.h"

#include "core/err.h"
#include "core/sphere.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { BLOCK = 16 };

int cs_hfield_place(const double col[3], const double row[3], const double x[3],
		    const double y[3], double a[3], double b[3])
{
	/* [1 x y] [p0 p1 p2]^T = value, three points: Cramer's rule */
	double det = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
	if (!(fabs(det) > 1e-9))
		return cs_error(CS_EINVAL, "terrain placement: the reference points are collinear");
	const double *val[2] = {col, row};
	double *out[2] = {a, b};
	for (int k = 0; k < 2; k++) {
		const double *v = val[k];
		double p1 = ((v[1] - v[0]) * (y[2] - y[0]) - (v[2] - v[0]) * (y[1] - y[0])) / det;
		double p2 = ((x[1] - x[0]) * (v[2] - v[0]) - (x[2] - x[0]) * (v[1] - v[0])) / det;
		out[k][1] = p1;
		out[k][2] = p2;
		out[k][0] = v[0] - p1 * x[0] - p2 * y[0];
	}
	return CS_OK;
}

int cs_hfield_init(struct cs_hfield *f, const float *z, int w, int h,
		   const double a[3], const double b[3], double earth_radius_m)
{
	memset(f, 0, sizeof *f);
	if (w < 2 || h < 2)
		return cs_error(CS_EINVAL, "a heightfield needs at least 2 x 2 samples");
	double det = a[1] * b[2] - a[2] * b[1];
	if (!(fabs(det) > 1e-15))
		return cs_error(CS_EINVAL, "terrain placement is singular");
	f->w = w, f->h = h, f->z = z;
	memcpy(f->a, a, sizeof f->a);
	memcpy(f->b, b, sizeof f->b);
	f->ia[1] = b[2] / det, f->ia[2] = -a[2] / det;
	f->ib[1] = -b[1] / det, f->ib[2] = a[1] / det;
	f->ia[0] = -(f->ia[1] * a[0] + f->ia[2] * b[0]);
	f->ib[0] = -(f->ib[1] * a[0] + f->ib[2] * b[0]);
	f->earth_radius_m = earth_radius_m;
	f->bw = (w - 2) / BLOCK + 1;
	f->bh = (h - 2) / BLOCK + 1;
	f->block_max = (float *)malloc((size_t)f->bw * f->bh * sizeof *f->block_max);
	if (f->block_max == NULL)
		return cs_error(CS_ENOMEM, "out of memory for the terrain");
	f->min_m = INFINITY, f->max_m = -INFINITY;
	for (int j = 0; j < h; j++)
		for (int i = 0; i < w; i++) {
			double v = z[(size_t)j * w + i];
			f->min_m = v < f->min_m ? v : f->min_m;
			f->max_m = v > f->max_m ? v : f->max_m;
		}
	for (int J = 0; J < f->bh; J++)
		for (int I = 0; I < f->bw; I++) {
			float m = -INFINITY;
			int i1 = (I + 1) * BLOCK < w - 1 ? (I + 1) * BLOCK : w - 1;
			int j1 = (J + 1) * BLOCK < h - 1 ? (J + 1) * BLOCK : h - 1;
			for (int j = J * BLOCK; j <= j1; j++)
				for (int i = I * BLOCK; i <= i1; i++)
					m = z[(size_t)j * w + i] > m ? z[(size_t)j * w + i] : m;
			f->block_max[(size_t)J * f->bw + I] = m;
		}
	return CS_OK;
}

void cs_hfield_free(struct cs_hfield *f)
{
	free(f->block_max);
	f->block_max = NULL;
}

CS_HD static inline double Z(const struct cs_hfield *f, int i, int j)
{
	return f->z[(size_t)j * f->w + i];
}

/* Cell (i, j) and the position (u, v) inside it, clamped to the grid. */
CS_HD static inline void locate(const struct cs_hfield *f, double col, double row,
			  int *i, int *j, double *u, double *v)
{
	col = col < 0.0 ? 0.0 : col > f->w - 1 ? f->w - 1 : col;
	row = row < 0.0 ? 0.0 : row > f->h - 1 ? f->h - 1 : row;
	int ci = (int)col, rj = (int)row;
	ci = ci > f->w - 2 ? f->w - 2 : ci;
	rj = rj > f->h - 2 ? f->h - 2 : rj;
	*i = ci, *j = rj, *u = col - ci, *v = row - rj;
}

CS_HD int cs_hfield_height(const struct cs_hfield *f, double x, double y, double *h)
{
	double col = f->a[0] + f->a[1] * x + f->a[2] * y;
	double row = f->b[0] + f->b[1] * x + f->b[2] * y;
	int inside = col >= 0.0 && col <= f->w - 1 && row >= 0.0 && row <= f->h - 1;
	int i, j;
	double u, v;
	locate(f, col, row, &i, &j, &u, &v);
	double z0 = Z(f, i, j) + u * (Z(f, i + 1, j) - Z(f, i, j));
	double z1 = Z(f, i, j + 1) + u * (Z(f, i + 1, j + 1) - Z(f, i, j + 1));
	*h = z0 + v * (z1 - z0);
	return inside;
}

CS_HD cs_v3 cs_hfield_normal(const struct cs_hfield *f, double x, double y)
{
	double col = f->a[0] + f->a[1] * x + f->a[2] * y;
	double row = f->b[0] + f->b[1] * x + f->b[2] * y;
	int i, j;
	double u, v;
	locate(f, col, row, &i, &j, &u, &v);
	double dcol = (1 - v) * (Z(f, i + 1, j) - Z(f, i, j)) +
		      v * (Z(f, i + 1, j + 1) - Z(f, i, j + 1));
	double drow = (1 - u) * (Z(f, i, j + 1) - Z(f, i, j)) +
		      u * (Z(f, i + 1, j + 1) - Z(f, i + 1, j));
	double hx = dcol * f->a[1] + drow * f->b[1];
	double hy = dcol * f->a[2] + drow * f->b[2];
	return v3_norm(v3(-hx, -hy, 1.0));
}

CS_HD double cs_hfield_altitude(const struct cs_hfield *f, cs_v3 p)
{
	return cs_altitude(p, f->earth_radius_m);
}

/* Height of the surface minus the altitude, along the ray: > 0 above. */
CS_HD static double gap(const struct cs_hfield *f, cs_v3 o, cs_v3 d, double t)
{
	cs_v3 p = v3_mad(o, d, t);
	double h;
	cs_hfield_height(f, p.x, p.y, &h);
	return cs_hfield_altitude(f, p) - h;
}

/* The part [t0, t1] of the ray where lo <= g(t) <= hi along one grid axis
 * whose coordinate is g(t) = g0 + gd t. */
CS_HD static int slab(double g0, double gd, double lo, double hi, double *t0, double *t1)
{
	if (gd == 0.0)
		return g0 >= lo && g0 <= hi;
	double a = (lo - g0) / gd, b = (hi - g0) / gd;
	if (a > b) {
		double s = a;
		a = b;
		b = s;
	}
	*t0 = a > *t0 ? a : *t0;
	*t1 = b < *t1 ? b : *t1;
	return *t0 <= *t1;
}

/* A lower bound of the ray's altitude over [t0, t1]: the altitude is a
 * convex function of t, so it lies above its tangent at t0. */
CS_HD static double alt_lower_bound(const struct cs_hfield *f, cs_v3 o, cs_v3 d,
			      double t0, double t1)
{
	cs_v3 p = v3_mad(o, d, t0);
	cs_v3 q = v3(p.x, p.y, p.z + f->earth_radius_m);
	double slope = v3_dot(d, q) / v3_len(q);
	double a0 = cs_altitude(p, f->earth_radius_m);
	double a1 = a0 + slope * (t1 - t0);
	return a0 < a1 ? a0 : a1;
}

/* First root in [0, len] of q0 + q1 s + q2 s^2, or -1. */
CS_HD static double first_root(double q0, double q1, double q2, double len)
{
	if (q0 <= 0.0)
		return 0.0;
	double best = -1.0;
	if (fabs(q2) < 1e-14 * (fabs(q1) + 1e-300)) {
		if (q1 < 0.0)
			best = -q0 / q1;
	} else {
		double disc = q1 * q1 - 4.0 * q2 * q0;
		if (disc >= 0.0) {
			double sq = sqrt(disc);
			double q = -0.5 * (q1 + (q1 >= 0.0 ? sq : -sq));
			double r0 = q / q2, r1 = q != 0.0 ? q0 / q : -1.0;
			if (r0 > r1) {
				double s = r0;
				r0 = r1;
				r1 = s;
			}
			best = r0 >= 0.0 ? r0 : r1;
		}
	}
	return best >= 0.0 && best <= len ? best : -1.0;
}

CS_HD int cs_hfield_intersect(const struct cs_hfield *f, cs_v3 o, cs_v3 d, double tmax,
			double *t_hit, unsigned long *cells)
{
	double c0 = f->a[0] + f->a[1] * o.x + f->a[2] * o.y, cd = f->a[1] * d.x + f->a[2] * d.y;
	double r0 = f->b[0] + f->b[1] * o.x + f->b[2] * o.y, rd = f->b[1] * d.x + f->b[2] * d.y;
	double R = f->earth_radius_m;

	/* the ray's span over the grid and below the highest sample */
	double t0 = 0.0, t1 = tmax;
	if (!slab(c0, cd, 0.0, f->w - 1, &t0, &t1) || !slab(r0, rd, 0.0, f->h - 1, &t0, &t1))
		return 0;
	{
		double e0, e1;
		if (!cs_sphere_hit(o, d, R, R + f->max_m, &e0, &e1))
			return 0;
		t0 = e0 > t0 ? e0 : t0;
		t1 = e1 < t1 ? e1 : t1;
		if (!(t0 <= t1))
			return 0;
	}

	int si = cd > 0.0 ? 1 : cd < 0.0 ? -1 : 0, sj = rd > 0.0 ? 1 : rd < 0.0 ? -1 : 0;
	double t = t0;
	int ci, rj;
	double u, v;
	locate(f, c0 + cd * t, r0 + rd * t, &ci, &rj, &u, &v);
	long guard = 4L * (f->w + f->h) + 64;
	while (t <= t1 && guard-- > 0) {
		if (ci < 0 || rj < 0 || ci > f->w - 2 || rj > f->h - 2)
			return 0;
		/* a whole block the ray clears */
		int I = ci / BLOCK, J = rj / BLOCK;
		double b0 = t, b1 = t1;
		slab(c0, cd, I * BLOCK, (I + 1) * BLOCK < f->w - 1 ? (I + 1) * BLOCK : f->w - 1, &b0, &b1);
		slab(r0, rd, J * BLOCK, (J + 1) * BLOCK < f->h - 1 ? (J + 1) * BLOCK : f->h - 1, &b0, &b1);
		if (b1 > t && alt_lower_bound(f, o, d, t, b1) > f->block_max[(size_t)J * f->bw + I]) {
			/* on the block's edge: step just across it to find the cell */
			t = b1;
			ci = (int)floor(c0 + cd * t + si * 1e-9);
			rj = (int)floor(r0 + rd * t + sj * 1e-9);
			continue;
		}
		if (cells)
			(*cells)++;
		/* this cell: from t to where the ray leaves it */
		double tc = si ? ((si > 0 ? ci + 1 : ci) - c0) / cd : INFINITY;
		double tr = sj ? ((sj > 0 ? rj + 1 : rj) - r0) / rd : INFINITY;
		double te = tc < tr ? tc : tr;
		te = te < t1 ? te : t1;
		te = te > t ? te : t;
		double h00 = Z(f, ci, rj), h10 = Z(f, ci + 1, rj), h01 = Z(f, ci, rj + 1),
		       h11 = Z(f, ci + 1, rj + 1);
		double hmax = fmax(fmax(h00, h10), fmax(h01, h11));
		if (alt_lower_bound(f, o, d, t, te) <= hmax) {
			/* the bilinear patch along the ray is a quadratic in s */
			double u0 = c0 + cd * t - ci, v0 = r0 + rd * t - rj;
			double A = h10 - h00, B = h01 - h00, D = h00 - h10 - h01 + h11;
			double H0 = h00 + A * u0 + B * v0 + D * u0 * v0;
			double H1 = A * cd + B * rd + D * (u0 * rd + v0 * cd);
			double H2 = D * cd * rd;
			cs_v3 p = v3_mad(o, d, t);
			cs_v3 q = v3(p.x, p.y, p.z + R);
			double r = v3_len(q);
			double al0 = r - R, al1 = v3_dot(d, q) / r;
			double al2 = (1.0 - al1 * al1) / (2.0 * r);
			double q0 = al0 - H0, q1 = al1 - H1, q2 = al2 - H2, s;
			/* the eye stands on the surface (to rounding) and the ray
			 * leaves it: the ground is solid, so only a ray that
			 * comes back down meets it again */
			int leaving = t == 0.0 && fabs(q0) < 1e-6 && q1 > 0.0;
			if (leaving)
				s = q2 < 0.0 && -q1 / q2 <= te - t ? -q1 / q2 : -1.0;
			else
				s = first_root(q0, q1, q2, te - t);
			if (!leaving && s < 0.0 && gap(f, o, d, te) <= 0.0)
				s = te - t; /* rounding: the end is below, so a root is here */
			if (s >= 0.0) {
				/* refine on the exact gap by bisection where it brackets */
				double lo = t + s - 1e-3 * (te - t + 1.0), hi = t + s + 1e-3 * (te - t + 1.0);
				lo = lo > t ? lo : t;
				hi = hi < te ? hi : te;
				if (gap(f, o, d, lo) > 0.0 && gap(f, o, d, hi) <= 0.0) {
					for (int k = 0; k < 40; k++) {
						double mid = 0.5 * (lo + hi);
						if (gap(f, o, d, mid) > 0.0)
							lo = mid;
						else
							hi = mid;
					}
					*t_hit = hi;
				} else {
					*t_hit = t + s;
				}
				return 1;
			}
		}
		if (te >= t1)
			return 0;
		t = te;
		if (tc <= tr)
			ci += si;
		else
			rj += sj;
	}
	return 0;
}
