#include "noise/noise.h"

#include "core/err.h"
#include "core/hash.h"

#include <math.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

/* Perlin's permutation table from his reference ImprovedNoise.java. */
static const uint8_t perm[256] = {
	151, 160, 137, 91,  90,  15,  131, 13,  201, 95,  96,  53,  194, 233, 7,
	225, 140, 36,  103, 30,  69,  142, 8,   99,  37,  240, 21,  10,  23,  190,
	6,   148, 247, 120, 234, 75,  0,   26,  197, 62,  94,  252, 219, 203, 117,
	35,  11,  32,  57,  177, 33,  88,  237, 149, 56,  87,  174, 20,  125, 136,
	171, 168, 68,  175, 74,  165, 71,  134, 139, 48,  27,  166, 77,  146, 158,
	231, 83,  111, 229, 122, 60,  211, 133, 230, 220, 105, 92,  41,  55,  46,
	245, 40,  244, 102, 143, 54,  65,  25,  63,  161, 1,   216, 80,  73,  209,
	76,  132, 187, 208, 89,  18,  169, 200, 196, 135, 130, 116, 188, 159, 86,
	164, 100, 109, 198, 173, 186, 3,   64,  52,  217, 226, 250, 124, 123, 5,
	202, 38,  147, 118, 126, 255, 82,  85,  212, 207, 206, 59,  227, 47,  16,
	58,  17,  182, 189, 28,  42,  223, 183, 170, 213, 119, 248, 152, 2,   44,
	154, 163, 70,  221, 153, 101, 155, 167, 43,  172, 9,   129, 22,  39,  253,
	19,  98,  108, 110, 79,  113, 224, 232, 178, 185, 112, 104, 218, 246, 97,
	228, 251, 34,  242, 193, 238, 210, 144, 12,  191, 179, 162, 241, 81,  51,
	145, 235, 249, 14,  239, 107, 49,  192, 214, 31,  181, 199, 106, 157, 184,
	84,  204, 176, 115, 121, 50,  45,  127, 4,   150, 254, 138, 236, 205, 93,
	222, 114, 67,  29,  24,  72,  243, 141, 128, 195, 78,  66,  215, 61,  156,
	180,
};

static inline int P(int i)
{
	return perm[i & 255];
}

static inline double fade(double t)
{
	return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

static inline double lerp(double t, double a, double b)
{
	return a + t * (b - a);
}

/* Dot product with one of the 12 cube-edge directions (16 cases, four
 * repeated), exactly as in Perlin 2002, section 4. */
static inline double grad(int hash, double x, double y, double z)
{
	int h = hash & 15;
	double u = h < 8 ? x : y;
	double v = h < 4 ? y : (h == 12 || h == 14) ? x : z;
	return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

/* The interpolation shared by both variants: (x,y,z) is the position inside
 * the cell, h[] the gradient hashes of its corners, bit 0 = +x, 1 = +y,
 * 2 = +z. */
static double perlin_cell(double x, double y, double z, const int h[8])
{
	double u = fade(x), v = fade(y), w = fade(z);
	double x1 = x - 1.0, y1 = y - 1.0, z1 = z - 1.0;
	return lerp(w,
		    lerp(v, lerp(u, grad(h[0], x, y, z), grad(h[1], x1, y, z)),
			 lerp(u, grad(h[2], x, y1, z), grad(h[3], x1, y1, z))),
		    lerp(v, lerp(u, grad(h[4], x, y, z1), grad(h[5], x1, y, z1)),
			 lerp(u, grad(h[6], x, y1, z1),
			      grad(h[7], x1, y1, z1))));
}

double cs_perlin3(double x, double y, double z)
{
	if (!isfinite(x) || !isfinite(y) || !isfinite(z))
		return 0.0;
	double fx = floor(x), fy = floor(y), fz = floor(z);
	/* The table repeats every 256 cells, so reducing first keeps the int
	 * conversion defined for any finite coordinate. */
	int X = (int)(fx - 256.0 * floor(fx / 256.0)) & 255;
	int Y = (int)(fy - 256.0 * floor(fy / 256.0)) & 255;
	int Z = (int)(fz - 256.0 * floor(fz / 256.0)) & 255;
	int A = P(X) + Y, AA = P(A) + Z, AB = P(A + 1) + Z;
	int B = P(X + 1) + Y, BA = P(B) + Z, BB = P(B + 1) + Z;
	int h[8] = {P(AA),     P(BA),     P(AB),     P(BB),
		    P(AA + 1), P(BA + 1), P(AB + 1), P(BB + 1)};
	return perlin_cell(x - fx, y - fy, z - fz, h);
}

/* Splits a coordinate into a lattice index and the position inside the cell.
 * Periodic axes are reduced into [0, period) first (a true modulo, correct
 * for negative and huge coordinates); other axes are clamped to a range
 * where the conversion to int is defined. */
static inline int split(double x, int period, double *frac)
{
	if (period > 0 && x >= 0.0 && x < period * 0.999) {
		/* already in range (a baked voxel's coordinate): the reduction
		 * below would subtract period * 0, without its division */
		double f = floor(x);
		*frac = x - f;
		return (int)f;
	}
	if (period > 0) {
		x -= (double)period * floor(x / (double)period);
		if (!(x >= 0.0 && x <= (double)period)) /* was NaN or infinite */
			x = 0.0;
	} else if (!(fabs(x) < 1e9)) {
		x = x > 0 ? 1e9 : -1e9; /* also maps NaN to -1e9 */
	}
	double f = floor(x);
	*frac = x - f;
	int i = (int)f;
	if (period > 0 && i >= period) /* x just below period rounded up */
		i -= period;
	return i;
}

static inline int wrap(int i, int period)
{
	if (period <= 0)
		return i;
	int m = i % period;
	return m < 0 ? m + period : m;
}

double cs_perlin3p(double x, double y, double z, const int period[3],
		   uint32_t seed)
{
	double fx, fy, fz;
	int X = split(x, period[0], &fx);
	int Y = split(y, period[1], &fy);
	int Z = split(z, period[2], &fz);
	int h[8];
	for (int c = 0; c < 8; c++) {
		int cx = wrap(X + (c & 1), period[0]);
		int cy = wrap(Y + ((c >> 1) & 1), period[1]);
		int cz = wrap(Z + ((c >> 2) & 1), period[2]);
		h[c] = (int)(cs_hash3i(cx, cy, cz, seed) & 15u);
	}
	return perlin_cell(fx, fy, fz, h);
}

void cs_worley_feature(int cx, int cy, int cz, const int period[3],
		       uint32_t seed, double out[3])
{
	uint32_t h = cs_hash3i(wrap(cx, period[0]), wrap(cy, period[1]),
			       wrap(cz, period[2]), seed);
	out[0] = cs_hash_unit(h);
	out[1] = cs_hash_unit(cs_hash_u32(h ^ 0x68bc21ebu));
	out[2] = cs_hash_unit(cs_hash_u32(h ^ 0x02e5be93u));
}

/* Squared distance from the query (fx,fy,fz inside cell X,Y,Z) to the
 * feature point of the cell at offset (dx,dy,dz). */
static inline double feature_d2(int X, int Y, int Z, int dx, int dy, int dz,
				double fx, double fy, double fz,
				const int period[3], uint32_t seed)
{
	double p[3];
	cs_worley_feature(X + dx, Y + dy, Z + dz, period, seed, p);
	double ex = dx + p[0] - fx, ey = dy + p[1] - fy, ez = dz + p[2] - fz;
	return ex * ex + ey * ey + ez * ez;
}

/* Lower bound of the squared distance from position f in [0,1) to the cell
 * at offset d along one axis. */
static inline double gap2(int d, double f)
{
	double g = d > 0 ? d - f : d < 0 ? f - (d + 1) : 0.0;
	return g * g;
}

double cs_worley3p(double x, double y, double z, const int period[3],
		   uint32_t seed)
{
	double fx, fy, fz;
	int X = split(x, period[0], &fx);
	int Y = split(y, period[1], &fy);
	int Z = split(z, period[2], &fz);

	/* Why this is exact: the feature point of the query's own cell is
	 * closer than sqrt(3).  A cell at offset k along some axis is at least
	 * |k| - 1 cells away, so a cell with |k| >= 3 is at least 2 > sqrt(3)
	 * away and can never win.  Offsets -2..2 are therefore enough; cells
	 * whose nearest face is farther than the best point so far are
	 * skipped, which is what keeps this fast. */
	double best = feature_d2(X, Y, Z, 0, 0, 0, fx, fy, fz, period, seed);
	for (int r = 1; r <= 2; r++) {
		/* every cell of the outer shell is at least 1 away */
		if (r == 2 && best <= 1.0)
			break;
		for (int dz = -r; dz <= r; dz++) {
			double gz = gap2(dz, fz);
			if (gz >= best)
				continue;
			for (int dy = -r; dy <= r; dy++) {
				double gy = gz + gap2(dy, fy);
				if (gy >= best)
					continue;
				for (int dx = -r; dx <= r; dx++) {
					/* only the shell at Chebyshev radius r */
					if (dx > -r && dx < r && dy > -r &&
					    dy < r && dz > -r && dz < r)
						continue;
					if (gy + gap2(dx, fx) >= best)
						continue;
					double d2 = feature_d2(X, Y, Z, dx, dy,
							       dz, fx, fy, fz,
							       period, seed);
					if (d2 < best)
						best = d2;
				}
			}
		}
	}
	return sqrt(best);
}

enum basis { PERLIN, INVERTED_WORLEY };

/* The fractal sum shared by both bases: octave i at frequency
 * lacunarity^i (and period times that), amplitude gain^i, seed + i,
 * divided by the sum of the amplitudes. */
static double fbm3p(enum basis basis, double x, double y, double z,
		    const int period[3], uint32_t seed, const struct cs_fbm *fbm)
{
	double sum = 0.0, norm = 0.0, amp = 1.0;
	long freq = 1;
	for (int i = 0; i < fbm->octaves; i++) {
		int p[3];
		for (int a = 0; a < 3; a++)
			p[a] = period[a] > 0 ? (int)(period[a] * freq) : 0;
		double fx = x * (double)freq, fy = y * (double)freq, fz = z * (double)freq;
		double n;
		if (basis == PERLIN) {
			n = cs_perlin3p(fx, fy, fz, p, seed + (uint32_t)i);
		} else {
			double f1 = cs_worley3p(fx, fy, fz, p, seed + (uint32_t)i);
			n = 1.0 - (f1 < 1.0 ? f1 : 1.0);
		}
		sum += amp * n;
		norm += amp;
		amp *= fbm->gain;
		freq *= fbm->lacunarity;
	}
	return sum / norm;
}

double cs_perlin_fbm3p(double x, double y, double z, const int period[3],
		       uint32_t seed, const struct cs_fbm *fbm)
{
	/* Improved Perlin noise slightly exceeds [-1, 1] at rare points (see
	 * noise.h); the clamp makes the documented range exact. */
	double v = fbm3p(PERLIN, x, y, z, period, seed, fbm);
	return v < -1.0 ? -1.0 : v > 1.0 ? 1.0 : v;
}

double cs_worley_fbm3p(double x, double y, double z, const int period[3],
		       uint32_t seed, const struct cs_fbm *fbm)
{
	return fbm3p(INVERTED_WORLEY, x, y, z, period, seed, fbm);
}

double cs_perlin_worley3p(double x, double y, double z, const int period[3],
			  uint32_t seed, const struct cs_fbm *perlin,
			  const struct cs_fbm *worley)
{
	double p = 0.5 + 0.5 * cs_perlin_fbm3p(x, y, z, period, seed, perlin);
	p = p < 0.0 ? 0.0 : p > 1.0 ? 1.0 : p;
	double w = cs_worley_fbm3p(x, y, z, period, seed ^ 0x5bd1e995u, worley);
	return (p - w + 1.0) / (2.0 - w);
}

int cs_lattice_lut_new(struct cs_lattice_lut *t, const int period[3], uint32_t seed,
		       int worley)
{
	memset(t, 0, sizeof *t);
	long n = 1;
	for (int a = 0; a < 3; a++) {
		if (period[a] < 1 || period[a] > CS_LATTICE_LUT_MAX_CELLS)
			return cs_error(CS_EINVAL, "lattice period %d out of range", period[a]);
		n *= period[a];
		if (n > CS_LATTICE_LUT_MAX_CELLS)
			return cs_error(CS_EINVAL, "lattice of more than %ld cells",
					(long)CS_LATTICE_LUT_MAX_CELLS);
		t->period[a] = period[a];
	}
	t->seed = seed;
	t->cells = n;
	if (worley)
		t->feat = malloc((size_t)n * 3 * sizeof *t->feat);
	else
		t->grad = malloc((size_t)n);
	if (t->feat == NULL && t->grad == NULL)
		return cs_error(CS_ENOMEM, "out of memory for a noise table");
	size_t i = 0;
	for (int z = 0; z < period[2]; z++)
		for (int y = 0; y < period[1]; y++)
			for (int x = 0; x < period[0]; x++, i++) {
				if (worley) {
					double p[3];
					cs_worley_feature(x, y, z, period, seed, p);
					for (int a = 0; a < 3; a++)
						t->feat[(size_t)a * (size_t)n + i] = p[a];
				}
				else
					t->grad[i] = (uint8_t)(cs_hash3i(x, y, z, seed) & 15u);
			}
	return CS_OK;
}

void cs_lattice_lut_free(struct cs_lattice_lut *t)
{
	free(t->feat);
	free(t->grad);
	memset(t, 0, sizeof *t);
}

/* Cell index i - 1, i, i + 1 wrapped into [0, n) (i already is). */
static inline void neighbours(int i, int n, int out[3])
{
	out[0] = i > 0 ? i - 1 : n - 1;
	out[1] = i;
	out[2] = i + 1 < n ? i + 1 : 0;
}

/* Gathers the feature points of the 27 cells around (X, Y, Z), as the
 * offsets dx + p[0] etc. that cs_worley3p()'s feature_d2 forms. */
static void worley_gather(const struct cs_lattice_lut *t, int X, int Y, int Z,
			  struct cs_worley_cache *w)
{
	const int *period = t->period;
	int xs[3], ys[3], zs[3];
	neighbours(X, period[0], xs);
	neighbours(Y, period[1], ys);
	neighbours(Z, period[2], zs);
	int k = 0;
	for (int dz = -1; dz <= 1; dz++)
		for (int dy = -1; dy <= 1; dy++) {
			size_t row = ((size_t)zs[dz + 1] * period[1] + (size_t)ys[dy + 1]) * period[0];
			for (int dx = -1; dx <= 1; dx++, k++) {
				const double *p = t->feat + row + xs[dx + 1];
				w->c[0][k] = dx + p[0];
				w->c[1][k] = dy + p[t->cells];
				w->c[2][k] = dz + p[2 * t->cells];
			}
		}
	w->key[0] = X, w->key[1] = Y, w->key[2] = Z;
}

/* The least squared distance from (fx, fy, fz) to the 27 gathered
 * points: the same squared distances, computed the same way
 * ((ex^2 + ey^2) + ez^2), give the same minimum in whatever order it is
 * taken. */
static double nearest27_base(const struct cs_worley_cache *w, double fx, double fy, double fz)
{
	const double *cx = w->c[0], *cy = w->c[1], *cz = w->c[2];
	double best;
	int k = 0;
#if defined(__SSE2__)
	__m128d vx = _mm_set1_pd(fx), vy = _mm_set1_pd(fy), vz = _mm_set1_pd(fz);
	__m128d b0 = _mm_set1_pd(INFINITY), b1 = b0;
	for (; k + 4 <= 27; k += 4) {
		__m128d ex = _mm_sub_pd(_mm_loadu_pd(cx + k), vx);
		__m128d ey = _mm_sub_pd(_mm_loadu_pd(cy + k), vy);
		__m128d ez = _mm_sub_pd(_mm_loadu_pd(cz + k), vz);
		__m128d d = _mm_add_pd(_mm_add_pd(_mm_mul_pd(ex, ex), _mm_mul_pd(ey, ey)),
				       _mm_mul_pd(ez, ez));
		b0 = _mm_min_pd(d, b0);
		ex = _mm_sub_pd(_mm_loadu_pd(cx + k + 2), vx);
		ey = _mm_sub_pd(_mm_loadu_pd(cy + k + 2), vy);
		ez = _mm_sub_pd(_mm_loadu_pd(cz + k + 2), vz);
		d = _mm_add_pd(_mm_add_pd(_mm_mul_pd(ex, ex), _mm_mul_pd(ey, ey)),
			       _mm_mul_pd(ez, ez));
		b1 = _mm_min_pd(d, b1);
	}
	b0 = _mm_min_pd(b0, b1);
	b0 = _mm_min_sd(b0, _mm_unpackhi_pd(b0, b0));
	best = _mm_cvtsd_f64(b0);
#else
	best = INFINITY;
#endif
	for (; k < 27; k++) {
		double ex = cx[k] - fx, ey = cy[k] - fy, ez = cz[k] - fz;
		double d2 = ex * ex + ey * ey + ez * ez;
		best = d2 < best ? d2 : best;
	}
	return best;
}

/* AVX2 paths (GCC's function targets; a CPU without AVX2, another
 * compiler or architecture takes the plain C, with the same results). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define NOISE_AVX2 1
#else
#define NOISE_AVX2 0
#endif

#if NOISE_AVX2
#include <immintrin.h>
/* The least of four lanes. */
__attribute__((target("avx2"))) static inline double min4(__m256d v)
{
	__m128d h = _mm_min_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
	return _mm_cvtsd_f64(_mm_min_sd(h, _mm_unpackhi_pd(h, h)));
}

/* The same, four points at a time with AVX2 (no FMA: the same roundings),
 * on a CPU that has it. */
__attribute__((target("avx2"))) static double nearest27_avx2(const struct cs_worley_cache *w,
							     double fx, double fy, double fz)
{
	const double *cx = w->c[0], *cy = w->c[1], *cz = w->c[2];
	__m256d vx = _mm256_set1_pd(fx), vy = _mm256_set1_pd(fy), vz = _mm256_set1_pd(fz);
	__m256d b0 = _mm256_set1_pd(INFINITY), b1 = b0;
	int k = 0;
	for (; k + 8 <= 27; k += 8) {
		__m256d ex = _mm256_sub_pd(_mm256_loadu_pd(cx + k), vx);
		__m256d ey = _mm256_sub_pd(_mm256_loadu_pd(cy + k), vy);
		__m256d ez = _mm256_sub_pd(_mm256_loadu_pd(cz + k), vz);
		__m256d d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)),
					  _mm256_mul_pd(ez, ez));
		b0 = _mm256_min_pd(d, b0);
		ex = _mm256_sub_pd(_mm256_loadu_pd(cx + k + 4), vx);
		ey = _mm256_sub_pd(_mm256_loadu_pd(cy + k + 4), vy);
		ez = _mm256_sub_pd(_mm256_loadu_pd(cz + k + 4), vz);
		d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex), _mm256_mul_pd(ey, ey)),
				  _mm256_mul_pd(ez, ez));
		b1 = _mm256_min_pd(d, b1);
	}
	double best = min4(_mm256_min_pd(b0, b1));
	for (; k < 27; k++) {
		double ex = cx[k] - fx, ey = cy[k] - fy, ez = cz[k] - fz;
		double d2 = ex * ex + ey * ey + ez * ez;
		best = d2 < best ? d2 : best;
	}
	return best;
}

static double nearest27(const struct cs_worley_cache *w, double fx, double fy, double fz)
{
	/* the same result either way: any x86-64 runs this binary */
	return __builtin_cpu_supports("avx2") ? nearest27_avx2(w, fx, fy, fz)
					      : nearest27_base(w, fx, fy, fz);
}
#else
static double nearest27(const struct cs_worley_cache *w, double fx, double fy, double fz)
{
	return nearest27_base(w, fx, fy, fz);
}
#endif

double cs_worley3p_lut(const struct cs_lattice_lut *t, struct cs_worley_cache *w,
		       double x, double y, double z)
{
	const int *period = t->period;
	double fx, fy, fz;
	int X = split(x, period[0], &fx);
	int Y = split(y, period[1], &fy);
	int Z = split(z, period[2], &fz);
	if (w->key[0] != X || w->key[1] != Y || w->key[2] != Z)
		worley_gather(t, X, Y, Z, w);
	/* the 27 cells around: cs_worley3p() searches them (skipping only
	 * cells that cannot be nearer) and goes further only when the nearest
	 * point among them is farther than 1 cell; the same squared distances,
	 * computed the same way ((ex^2 + ey^2) + ez^2), give the same minimum,
	 * in whatever order it is taken */
	double best = nearest27(w, fx, fy, fz);
	if (best > 1.0)
		return cs_worley3p(x, y, z, period, t->seed);
	return sqrt(best);
}


double cs_perlin3p_lut(const struct cs_lattice_lut *t, double x, double y, double z)
{
	const int *period = t->period;
	double fx, fy, fz;
	int X = split(x, period[0], &fx);
	int Y = split(y, period[1], &fy);
	int Z = split(z, period[2], &fz);
	int x1 = X + 1 < period[0] ? X + 1 : 0, y1 = Y + 1 < period[1] ? Y + 1 : 0;
	int z1 = Z + 1 < period[2] ? Z + 1 : 0;
	size_t sy = (size_t)period[0], sz = sy * (size_t)period[1];
	const uint8_t *g = t->grad;
	int h[8] = {g[Z * sz + Y * sy + X],   g[Z * sz + Y * sy + x1],
		    g[Z * sz + y1 * sy + X],  g[Z * sz + y1 * sy + x1],
		    g[z1 * sz + Y * sy + X],  g[z1 * sz + Y * sy + x1],
		    g[z1 * sz + y1 * sy + X], g[z1 * sz + y1 * sy + x1]};
	return perlin_cell(fx, fy, fz, h);
}

#if NOISE_AVX2
/* Whether points x[i + 1 .. i + 3] lie in cell X of a lattice of period
 * P, as x[i] does, with their positions in it into fx[1 .. 3]. */
static inline int same_cell4(const double *x, int i, int P, int X, double fx[4])
{
	int same = 1;
	for (int l = 1; l < 4; l++)
		same &= split(x[i + l], P, &fx[l]) == X;
	return same;
}
#endif

/* Rows: the points (x[i], y, z) of one row of voxels share y and z, so
 * they share the 9 rows of cells (dy, dz) around their own and each of
 * those cells' squared distances along y and along z.  Those are
 * computed once a row, per column of cells; a query then adds only its
 * x part.  Every squared distance is formed as cs_worley3p() forms it,
 * ((ex^2 + ey^2) + ez^2) with ex = (dx + px) - fx (dx + px is exact: a
 * feature coordinate has 24 bits), so every minimum is its, bit for bit. */

int cs_worley_row_init(struct cs_worley_row *r, const struct cs_lattice_lut *t)
{
	r->t = t;
	r->Y = -1;
	r->buf = (double *)malloc(3 * 9 * ((size_t)t->period[0] + 3) * sizeof *r->buf);
	return r->buf != NULL ? CS_OK : cs_error(CS_ENOMEM, "out of memory for a noise row");
}

void cs_worley_row_free(struct cs_worley_row *r)
{
	free(r->buf);
	r->buf = NULL;
}

/* The candidates of cell X: of the 27 points around it, those that can be
 * the nearest to some point of the cell.  A point's squared distance is
 * at least its y and z part (s = ey^2 + ez^2, rounded: the sum is
 * monotonic in each term, and so is rounding), and the own column's
 * point j is at most (max(px, 1 - px)^2 + ey^2) + ez^2 away from every
 * point of the cell (|ex| <= max(px, 1 - px) as fx runs over [0, 1)).  A
 * point whose s exceeds the least such bound is never the nearest; the
 * one that gives the bound is kept (its s is at most its bound).  The
 * list is padded to a multiple of 4 with points at infinity. */
struct row_cands {
	int n, kept; /* padded, and before the padding */
	double c[32], a[32], b[32];
};

static void row_cands(const double *C, const double *A, const double *B,
		      size_t w, int X, struct row_cands *k)
{
	double ub = INFINITY;
	for (int j = 0; j < 9; j++) {
		size_t o = (size_t)j * w + (size_t)X + 1;
		double c = C[o], m = c > 1.0 - c ? c : 1.0 - c;
		double u = (m * m + A[o]) + B[o];
		ub = u < ub ? u : ub;
	}
	int n = 0;
	for (int dx = -1; dx <= 1; dx++)
		for (int j = 0; j < 9; j++) {
			/* written whether kept or not (no branch to mispredict):
			 * a point left out is overwritten by the next */
			size_t o = (size_t)j * w + (size_t)(X + 1 + dx);
			k->c[n] = dx + C[o], k->a[n] = A[o], k->b[n] = B[o];
			n += A[o] + B[o] <= ub;
		}
	k->kept = n;
	for (; n & 3; n++)
		k->c[n] = INFINITY, k->a[n] = 0.0, k->b[n] = 0.0;
	k->n = n;
}

static double row_nearest_base(const struct row_cands *k, double fx)
{
	double best = INFINITY;
	for (int i = 0; i < k->n; i++) {
		double ex = k->c[i] - fx;
		double d2 = (ex * ex + k->a[i]) + k->b[i];
		best = d2 < best ? d2 : best;
	}
	return best;
}

/* All 27 points around cell X, straight from the row's columns. */
static double row_direct_base(const double *C, const double *A, const double *B, size_t w,
			      int X, double fx)
{
	double best = INFINITY;
	for (int j = 0; j < 9; j++)
		for (int dx = -1; dx <= 1; dx++) {
			size_t o = (size_t)j * w + (size_t)(X + 1 + dx);
			double ex = (dx + C[o]) - fx;
			double d2 = (ex * ex + A[o]) + B[o];
			best = d2 < best ? d2 : best;
		}
	return best;
}

#if NOISE_AVX2
/* The same, the columns X - 1 .. X + 2 as four lanes, the fourth moved
 * to infinity. */
__attribute__((target("avx2"))) static double row_direct_avx2(const double *C, const double *A,
							      const double *B, size_t w, int X,
							      double fx)
{
	__m256d vx = _mm256_set1_pd(fx), best = _mm256_set1_pd(INFINITY);
	__m256d dx = _mm256_setr_pd(-1.0, 0.0, 1.0, INFINITY);
	for (int j = 0; j < 9; j++) {
		size_t o = (size_t)j * w + (size_t)X;
		__m256d ex = _mm256_sub_pd(_mm256_add_pd(dx, _mm256_loadu_pd(C + o)), vx);
		__m256d d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex),
							_mm256_loadu_pd(A + o)),
					  _mm256_loadu_pd(B + o));
		best = _mm256_min_pd(d, best);
	}
	return min4(best);
}

__attribute__((target("avx2"))) static double row_nearest_avx2(const struct row_cands *k, double fx)
{
	__m256d vx = _mm256_set1_pd(fx), best = _mm256_set1_pd(INFINITY);
	for (int i = 0; i < k->n; i += 4) {
		__m256d ex = _mm256_sub_pd(_mm256_loadu_pd(k->c + i), vx);
		__m256d d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex),
							_mm256_loadu_pd(k->a + i)),
					  _mm256_loadu_pd(k->b + i));
		best = _mm256_min_pd(d, best);
	}
	return min4(best);
}
/* The least squared distances of four points of the cell (lanes) to its
 * candidates, into out[]. */
__attribute__((target("avx2"))) static void row_nearest4_avx2(const struct row_cands *k,
							       const double *fx, double *out)
{
	__m256d vx = _mm256_loadu_pd(fx), best = _mm256_set1_pd(INFINITY);
	for (int i = 0; i < k->kept; i++) {
		__m256d ex = _mm256_sub_pd(_mm256_broadcast_sd(k->c + i), vx);
		__m256d d = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(ex, ex),
							_mm256_broadcast_sd(k->a + i)),
					  _mm256_broadcast_sd(k->b + i));
		best = _mm256_min_pd(d, best);
	}
	_mm256_storeu_pd(out, best);
}
#define ROW_NEAREST(k, fx) (avx2 ? row_nearest_avx2(k, fx) : row_nearest_base(k, fx))
#define ROW_DIRECT(C, A, B, w, X, fx)                                                        \
	(avx2 ? row_direct_avx2(C, A, B, w, X, fx) : row_direct_base(C, A, B, w, X, fx))
#else
#define ROW_NEAREST(k, fx) row_nearest_base(k, fx)
#define ROW_DIRECT(C, A, B, w, X, fx) row_direct_base(C, A, B, w, X, fx)
#endif

void cs_worley_row_lut(struct cs_worley_row *r, double y, double z, const double *x, int n,
		       double *f1)
{
	const struct cs_lattice_lut *t = r->t;
	const int *period = t->period;
	int P = period[0];
	/* columns -1 .. P at X + 1, and one of zeros (the direct path's fourth lane) */
	size_t w = (size_t)P + 3;
	double fy, fz;
	int Y = split(y, period[1], &fy), Z = split(z, period[2], &fz);
	int ys[3], zs[3];
	neighbours(Y, period[1], ys);
	neighbours(Z, period[2], zs);
	double *C = r->buf, *A = C + 9 * w, *B = A + 9 * w;
	/* C and B stay while the row's cells and fz do (rows of a slice in
	 * one row of cells) */
	int keep = r->Y == Y && r->Z == Z && r->fz == fz;
	r->Y = Y, r->Z = Z, r->fz = fz;
	for (int j = 0; j < 9; j++) {
		int dy = j % 3 - 1, dz = j / 3 - 1;
		size_t row = ((size_t)zs[dz + 1] * period[1] + (size_t)ys[dy + 1]) * P;
		const double *p0 = t->feat + row, *p1 = p0 + t->cells, *p2 = p1 + t->cells;
		double *c = C + j * w, *a = A + j * w, *b = B + j * w;
		/* column -1 is P - 1, column P is 0, P + 1 zeros */
		a[0] = ((dy + p1[P - 1]) - fy) * ((dy + p1[P - 1]) - fy);
		a[P + 1] = ((dy + p1[0]) - fy) * ((dy + p1[0]) - fy);
		a[P + 2] = 0.0;
		for (int i = 0; i < P; i++) {
			double e = (dy + p1[i]) - fy;
			a[i + 1] = e * e;
		}
		if (keep)
			continue;
		c[0] = p0[P - 1], c[P + 1] = p0[0], c[P + 2] = 0.0;
		b[0] = ((dz + p2[P - 1]) - fz) * ((dz + p2[P - 1]) - fz);
		b[P + 1] = ((dz + p2[0]) - fz) * ((dz + p2[0]) - fz);
		b[P + 2] = 0.0;
		for (int i = 0; i < P; i++) {
			double e = (dz + p2[i]) - fz;
			c[i + 1] = p0[i], b[i + 1] = e * e;
		}
	}
#if NOISE_AVX2
	int avx2 = __builtin_cpu_supports("avx2");
#endif
	/* fewer than 8 points a cell: the candidates would cost more than they
	 * save */
	int direct = (long)n < 8L * P;
	struct row_cands k;
	int cur = -1;
	k.n = k.kept = 0; /* (filled at the first cell) */
	for (int i = 0; i < n;) {
		double fx[4];
		int X = split(x[i], P, &fx[0]);
		if (direct) {
			f1[i++] = ROW_DIRECT(C, A, B, w, X, fx[0]);
			continue;
		}
		if (X != cur)
			row_cands(C, A, B, w, X, &k), cur = X;
#if NOISE_AVX2
		/* four points in the cell: four lanes */
		if (avx2 && i + 4 <= n && same_cell4(x, i, P, X, fx)) {
			row_nearest4_avx2(&k, fx, f1 + i);
			i += 4;
			continue;
		}
#endif
		f1[i++] = ROW_NEAREST(&k, fx[0]);
	}
	/* the square roots, two at a time (the same roots); a point whose
	 * nearest of the 27 is farther than a cell: cs_worley3p_lut()'s
	 * search beyond them */
	int i = 0;
#if defined(__SSE2__)
	for (; i + 2 <= n; i += 2) {
		__m128d b = _mm_loadu_pd(f1 + i);
		_mm_storeu_pd(f1 + i, _mm_sqrt_pd(b));
		int far = _mm_movemask_pd(_mm_cmpgt_pd(b, _mm_set1_pd(1.0)));
		for (int l = 0; far; l++, far >>= 1)
			if (far & 1)
				f1[i + l] = cs_worley3p(x[i + l], y, z, period, t->seed);
	}
#endif
	for (; i < n; i++)
		f1[i] = f1[i] > 1.0 ? cs_worley3p(x[i], y, z, period, t->seed) : sqrt(f1[i]);
}

#if NOISE_AVX2
/* grad()'s choices for each hash as bit masks: which of x, y, z are u and
 * v, and their signs.  Selecting bits and flipping the sign bit are what
 * the choices and the negations do, so the sums are the same. */
struct grad_masks {
	uint64_t ux, vx, vy, vz, su, sv;
};
#define ALL1 0xffffffffffffffffull
#define SIGN 0x8000000000000000ull
#define GRAD_MASKS(h)                                                                        \
	{(h) < 8 ? ALL1 : 0, (h) == 12 || (h) == 14 ? ALL1 : 0, (h) < 4 ? ALL1 : 0,          \
	 (h) >= 4 && (h) != 12 && (h) != 14 ? ALL1 : 0, (h) & 1 ? SIGN : 0, (h) & 2 ? SIGN : 0}
static const struct grad_masks grad_mask[16] = {
	GRAD_MASKS(0),  GRAD_MASKS(1),  GRAD_MASKS(2),  GRAD_MASKS(3),
	GRAD_MASKS(4),  GRAD_MASKS(5),  GRAD_MASKS(6),  GRAD_MASKS(7),
	GRAD_MASKS(8),  GRAD_MASKS(9),  GRAD_MASKS(10), GRAD_MASKS(11),
	GRAD_MASKS(12), GRAD_MASKS(13), GRAD_MASKS(14), GRAD_MASKS(15),
};
#undef GRAD_MASKS
#undef SIGN
#undef ALL1

__attribute__((target("avx2"))) static inline __m256d fade4(__m256d t)
{
	__m256d a = _mm256_mul_pd(_mm256_mul_pd(t, t), t);
	__m256d b = _mm256_sub_pd(_mm256_mul_pd(t, _mm256_set1_pd(6.0)), _mm256_set1_pd(15.0));
	return _mm256_mul_pd(a, _mm256_add_pd(_mm256_mul_pd(t, b), _mm256_set1_pd(10.0)));
}

__attribute__((target("avx2"))) static inline __m256d lerp4(__m256d t, __m256d a, __m256d b)
{
	return _mm256_add_pd(a, _mm256_mul_pd(t, _mm256_sub_pd(b, a)));
}

__attribute__((target("avx2"))) static inline __m256d grad4(const struct grad_masks *g,
							    __m256d x, __m256d y, __m256d z)
{
	__m256d u = _mm256_or_pd(_mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->ux))),
				 _mm256_andnot_pd(_mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->ux)), y));
	__m256d v = _mm256_or_pd(
		_mm256_or_pd(_mm256_and_pd(x, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->vx))),
			     _mm256_and_pd(y, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->vy)))),
		_mm256_and_pd(z, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->vz))));
	u = _mm256_xor_pd(u, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->su)));
	v = _mm256_xor_pd(v, _mm256_castsi256_pd(_mm256_set1_epi64x((long long)g->sv)));
	return _mm256_add_pd(u, v);
}

/* perlin_cell() at four points of one cell (fx[] differ, fy and fz are
 * shared), lane by lane the same operations. */
__attribute__((target("avx2"))) static void perlin_cell4(const double *fx, double fy, double fz,
							  const int h[8], double *out)
{
	const struct grad_masks *m = grad_mask;
	__m256d x = _mm256_loadu_pd(fx), y = _mm256_set1_pd(fy), z = _mm256_set1_pd(fz);
	__m256d one = _mm256_set1_pd(1.0);
	__m256d x1 = _mm256_sub_pd(x, one), y1 = _mm256_sub_pd(y, one), z1 = _mm256_sub_pd(z, one);
	__m256d u = fade4(x), v = fade4(y), w = fade4(z);
	__m256d r = lerp4(w,
			  lerp4(v, lerp4(u, grad4(&m[h[0]], x, y, z), grad4(&m[h[1]], x1, y, z)),
				lerp4(u, grad4(&m[h[2]], x, y1, z), grad4(&m[h[3]], x1, y1, z))),
			  lerp4(v, lerp4(u, grad4(&m[h[4]], x, y, z1), grad4(&m[h[5]], x1, y, z1)),
				lerp4(u, grad4(&m[h[6]], x, y1, z1), grad4(&m[h[7]], x1, y1, z1))));
	_mm256_storeu_pd(out, r);
}
#endif

void cs_perlin_row_lut(const struct cs_lattice_lut *t, double y, double z, const double *x,
		       int n, double *out)
{
	const int *period = t->period;
	double fy, fz;
	int Y = split(y, period[1], &fy), Z = split(z, period[2], &fz);
	int y1 = Y + 1 < period[1] ? Y + 1 : 0, z1 = Z + 1 < period[2] ? Z + 1 : 0;
	size_t sy = (size_t)period[0], sz = sy * (size_t)period[1];
	const uint8_t *g00 = t->grad + Z * sz + Y * sy, *g10 = t->grad + Z * sz + y1 * sy;
	const uint8_t *g01 = t->grad + z1 * sz + Y * sy, *g11 = t->grad + z1 * sz + y1 * sy;
#if NOISE_AVX2
	int avx2 = __builtin_cpu_supports("avx2");
#endif
	for (int i = 0; i < n;) {
		double fx[4];
		int X = split(x[i], period[0], &fx[0]);
		int x1 = X + 1 < period[0] ? X + 1 : 0;
		int h[8] = {g00[X], g00[x1], g10[X], g10[x1], g01[X], g01[x1], g11[X], g11[x1]};
#if NOISE_AVX2
		/* four points in one cell share its gradients: four lanes */
		if (avx2 && i + 4 <= n && same_cell4(x, i, period[0], X, fx)) {
			perlin_cell4(fx, fy, fz, h, out + i);
			i += 4;
			continue;
		}
#endif
		out[i] = perlin_cell(fx[0], fy, fz, h);
		i++;
	}
}

int cs_fbm_check(const struct cs_fbm *fbm)
{
	if (fbm->octaves < 1 || fbm->octaves > 16)
		return cs_error(CS_EINVAL, "octaves must be 1..16, not %d",
				fbm->octaves);
	if (fbm->lacunarity < 2 || fbm->lacunarity > 8)
		return cs_error(CS_EINVAL, "lacunarity must be an integer 2..8, not %d",
				fbm->lacunarity);
	if (!(fbm->gain > 0.0 && fbm->gain <= 1.0))
		return cs_error(CS_EINVAL, "gain must be in (0, 1], not %g",
				fbm->gain);
	return CS_OK;
}
