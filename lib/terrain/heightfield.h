/* hfield.h - a heightfield placed in the world, and rays against it.
 *
 * Grid coordinates (col, row) are an affine function of the world's
 * horizontal coordinates (x east, y north): col = a0 + a1 x + a2 y,
 * row = b0 + b1 x + b2 y; sample (i, j) sits at col = i, row = j.  The
 * surface is the bilinear interpolation of the samples, as altitude above
 * the spherical Earth.  Intersection is exact: a two-level maximum
 * structure skips 16 x 16 blocks whose highest sample the ray clears, a
 * grid walk visits every cell the ray crosses, and in a cell the bilinear
 * patch along the ray is a quadratic whose first root is solved for, then
 * refined by bisection on the true (curved) altitude.  Nothing is stepped
 * over, so thin ridges cannot be tunnelled through. */
#ifndef CS_HFIELD_H
#define CS_HFIELD_H

#include "core/hd.h"

#include "core/vec.h"

struct cs_hfield {
	int w, h;                /* samples */
	const float *z;          /* heights, m, row-major, row 0 first (not owned) */
	double a[3], b[3];       /* world (x, y) -> (col, row) */
	double ia[3], ib[3];     /* (col, row) -> world (x, y) */
	double earth_radius_m;
	double min_m, max_m;
	int bw, bh;              /* blocks of 16 x 16 cells */
	float *block_max;        /* owned */
};

/* Sets up a heightfield over heights z (w x h, at least 2 x 2) with the
 * placement (col, row) = (a0 + a1 x + a2 y, b0 + b1 x + b2 y).  0 or an
 * error (singular placement, out of memory). */
int cs_hfield_init(struct cs_hfield *f, const float *z, int w, int h,
		   const double a[3], const double b[3], double earth_radius_m);
void cs_hfield_free(struct cs_hfield *f);

/* Fits the placement from world positions of three grid points
 * (col, row) -> (x, y), e.g. three corners placed with cs_geo_to_world(). */
int cs_hfield_place(const double col[3], const double row[3], const double x[3],
		    const double y[3], double a[3], double b[3]);

/* Height of the surface under world (x, y), and whether (x, y) is over the
 * grid (0 outside: the height is then that of the nearest edge). */
CS_HD int cs_hfield_height(const struct cs_hfield *f, double x, double y, double *h);

/* Unit surface normal (in world axes, with "up" = +z at the origin; the
 * caller tilts it for the sphere if it cares). */
CS_HD cs_v3 cs_hfield_normal(const struct cs_hfield *f, double x, double y);

/* First hit of the ray o + t d (d unit) with the surface for t in
 * [0, tmax]: 1 and *t, or 0.  Counts the cells visited in *cells. */
CS_HD int cs_hfield_intersect(const struct cs_hfield *f, cs_v3 o, cs_v3 d, double tmax,
			double *t, unsigned long *cells);

/* Altitude of world point p above the spherical Earth. */
CS_HD double cs_hfield_altitude(const struct cs_hfield *f, cs_v3 p);

#endif
