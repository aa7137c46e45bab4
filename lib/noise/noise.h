/* noise.h - gradient and cellular noise, plain and periodic ("seamless").
 *
 * Coordinates are in lattice cells.  A period is given per axis in cells; a
 * period of 0 means "not periodic" on that axis.  Periodic noise satisfies
 * f(x + k*px, y, z) == f(x, y, z) for every integer k, negative included. */
#ifndef CS_NOISE_H
#define CS_NOISE_H

#include <stddef.h>
#include <stdint.h>

/* Ken Perlin's Improved Noise (SIGGRAPH 2002): quintic fade, 12 gradient
 * directions, his permutation table.  Reproduces his Java reference
 * ImprovedNoise.noise(x, y, z) to rounding.  Range: a little wider than
 * [-1, 1]: the largest |n| measured over 2*10^7 random points is 1.0130;
 * tests/unit/test_noise.c asserts |n| <= 1.04.  Non-finite input gives 0. */
double cs_perlin3(double x, double y, double z);

/* Improved Perlin noise with gradients chosen by cs_hash3i() of the wrapped
 * lattice point and seed instead of the fixed table, so it can be seeded and
 * made periodic with any period.  Same range as cs_perlin3(). */
double cs_perlin3p(double x, double y, double z, const int period[3],
		   uint32_t seed);

/* Worley (cellular) noise F1: the distance, in cells, from (x,y,z) to the
 * nearest feature point, with one feature point per cell placed by
 * cs_hash3i().  Exact: the nearest point is always found.  Range
 * [0, sqrt(3)). */
double cs_worley3p(double x, double y, double z, const int period[3],
		   uint32_t seed);

/* The feature point of lattice cell (cx,cy,cz) (wrapped by the period), as
 * an offset in [0,1)^3 from the cell's lower corner. */
void cs_worley_feature(int cx, int cy, int cz, const int period[3],
		       uint32_t seed, double out[3]);

/* Fractal sum over octaves: octave i has frequency lacunarity^i and amplitude
 * gain^i.  The lacunarity is an integer so that every octave stays periodic
 * (octave i has period period*lacunarity^i).  Each octave uses its own seed
 * (seed + i) so octaves do not correlate. */
struct cs_fbm {
	int octaves;    /* 1..16 */
	int lacunarity; /* >= 2 */
	double gain;    /* (0, 1] */
};

/* Perlin fBm divided by the sum of the amplitudes and clamped to [-1, 1]
 * (the clamp acts only at the rare points where the base noise exceeds 1). */
double cs_perlin_fbm3p(double x, double y, double z, const int period[3],
		       uint32_t seed, const struct cs_fbm *fbm);

/* Inverted Worley fBm: sum of gain^i * (1 - min(F1_i, 1)) divided by the sum
 * of the amplitudes.  Range [0, 1]; 1 at feature points ("puffs"). */
double cs_worley_fbm3p(double x, double y, double z, const int period[3],
		       uint32_t seed, const struct cs_fbm *fbm);

/* The Perlin-Worley base shape of real-time cloud renderers (Schneider,
 * "The real-time volumetric cloudscapes of Horizon Zero Dawn", 2015):
 * Perlin fBm mapped to P in [0,1], dilated by the inverted Worley fBm W:
 * remap(P, W - 1, 1, 0, 1) = (P - W + 1) / (2 - W).  Range [0, 1].
 * Both parts share the period and seed; the Worley part uses seed ^ 0x5bd1e995. */
double cs_perlin_worley3p(double x, double y, double z, const int period[3],
			  uint32_t seed, const struct cs_fbm *perlin,
			  const struct cs_fbm *worley);

/* The lattice of one periodic octave as tables, for baking: every cell's
 * Worley feature point or Perlin gradient hash computed once instead of at
 * every lookup.  The _lut functions return exactly (bit for bit) what
 * cs_worley3p() and cs_perlin3p() return for the same period and seed. */
struct cs_lattice_lut {
	int period[3];   /* cells per axis, each >= 1 */
	uint32_t seed;
	double *feat;    /* Worley: the cells' x, then y, then z coordinates,
			  * x fastest; or NULL */
	long cells;      /* cells in all */
	uint8_t *grad;   /* Perlin: gradient hash & 15 per cell; or NULL */
};
/* The largest lattice tabulated (cells); larger ones are left to the direct
 * functions. */
#define CS_LATTICE_LUT_MAX_CELLS (1L << 21)

/* Tabulates the lattice of period (each >= 1) and seed, for Worley
 * (worley != 0) or Perlin noise.  0, CS_EINVAL (too large) or CS_ENOMEM. */
int cs_lattice_lut_new(struct cs_lattice_lut *t, const int period[3], uint32_t seed,
		       int worley);
void cs_lattice_lut_free(struct cs_lattice_lut *t);
/* The 27 feature points around the last cell looked up (neighbouring
 * lookups mostly share it); key[0] = -1 (no cell)
 * before the first use.  One per table and thread. */
struct cs_worley_cache {
	int key[3];
	double c[3][28]; /* per axis: cell offset + feature coordinate */
};
double cs_worley3p_lut(const struct cs_lattice_lut *t, struct cs_worley_cache *cache,
		       double x, double y, double z);
double cs_perlin3p_lut(const struct cs_lattice_lut *t, double x, double y, double z);

/* The same at the n points (x[i], y, z) of a row (any x; runs of points
 * in one cell, as a row of voxels gives, are fastest), into f1[] or
 * out[], which must not overlap x[]: what cs_worley3p_lut() and
 * cs_perlin3p_lut() return at each, bit for bit (with the library's
 * -ffp-contract=off: no fused multiply-adds).  A cs_worley_row is one
 * table's state for rows, one per table and thread: what rows of the same
 * cells share.  cs_worley_row_init() gives 0 or CS_ENOMEM;
 * cs_worley_row_free() releases it (any number of times). */
struct cs_worley_row {
	const struct cs_lattice_lut *t; /* the table it is for */
	double *buf;                    /* 3 x 9 rows of period[0] + 3 columns */
	int Y, Z;                       /* the cells of the last row; Y = -1: none */
	double fz;                      /* and its position inside cell Z */
};
int cs_worley_row_init(struct cs_worley_row *r, const struct cs_lattice_lut *t);
void cs_worley_row_free(struct cs_worley_row *r);
void cs_worley_row_lut(struct cs_worley_row *r, double y, double z, const double *x, int n,
		       double *f1);
void cs_perlin_row_lut(const struct cs_lattice_lut *t, double y, double z, const double *x,
		       int n, double *out);

/* Validates an fBm description; 0 or CS_EINVAL with a message. */
int cs_fbm_check(const struct cs_fbm *fbm);

#endif
