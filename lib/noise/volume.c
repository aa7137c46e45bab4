#include "noise/volume.h"

#include "core/err.h"
#include "core/hash.h"
#include "noise/noise.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char chan_names[4] = {'R', 'G', 'B', 'A'};

void cs_noise_recipe_default(struct cs_noise_recipe *r)
{
	static const struct cs_noise_recipe def = {
		.seed = 0,
		.freq = {4, 4, 8, 16},
		.octaves = {4, 3, 3, 3},
		.worley_octaves = 3,
		.gain = 0.5,
	};
	*r = def;
}

int cs_noise_recipe_check(const struct cs_noise_recipe *r)
{
	if (r->seed > 2147483647u)
		return cs_error(CS_EINVAL, "seed must be 0..2147483647");
	for (int c = 0; c < 4; c++) {
		if (r->freq[c] < 1 || r->freq[c] > 256)
			return cs_error(CS_EINVAL,
					"frequency of channel %c must be 1..256 cells, not %d",
					chan_names[c], r->freq[c]);
		if (r->octaves[c] < 1 || r->octaves[c] > 12)
			return cs_error(CS_EINVAL,
					"octaves of channel %c must be 1..12, not %d",
					chan_names[c], r->octaves[c]);
	}
	if (r->worley_octaves < 1 || r->worley_octaves > 12)
		return cs_error(CS_EINVAL, "Worley octaves of channel R must be 1..12, not %d",
				r->worley_octaves);
	if (!(r->gain > 0.0 && r->gain <= 1.0))
		return cs_error(CS_EINVAL, "gain must be in (0, 1], not %g", r->gain);
	return CS_OK;
}

int cs_noise_recipe_format(const struct cs_noise_recipe *r, char *buf,
			   size_t size)
{
	/* the shortest of %.15g and %.17g that reads back exactly */
	char gain[32];
	snprintf(gain, sizeof gain, "%.15g", r->gain);
	if (strtod(gain, NULL) != r->gain)
		snprintf(gain, sizeof gain, "%.17g", r->gain);
	return snprintf(buf, size,
			"R=perlin-worley:%d:%d:%d;G=worley-fbm:%d:%d;"
			"B=worley-fbm:%d:%d;A=worley-fbm:%d:%d;gain=%s",
			r->freq[0], r->octaves[0], r->worley_octaves, r->freq[1],
			r->octaves[1], r->freq[2], r->octaves[2], r->freq[3],
			r->octaves[3], gain);
}

int cs_noise_recipe_parse(const char *s, struct cs_noise_recipe *r)
{
	struct cs_noise_recipe t = *r;
	int used = 0;
	int n = sscanf(s,
		       "R=perlin-worley:%d:%d:%d;G=worley-fbm:%d:%d;"
		       "B=worley-fbm:%d:%d;A=worley-fbm:%d:%d;gain=%lf%n",
		       &t.freq[0], &t.octaves[0], &t.worley_octaves, &t.freq[1],
		       &t.octaves[1], &t.freq[2], &t.octaves[2], &t.freq[3],
		       &t.octaves[3], &t.gain, &used);
	if (n != 10 || s[used] != '\0')
		return cs_error(CS_EDATA, "unrecognised noise recipe \"%.200s\"", s);
	int rc = cs_noise_recipe_check(&t);
	if (rc != CS_OK)
		return cs_error(CS_EDATA, "bad noise recipe: %s", cs_errmsg());
	*r = t;
	return CS_OK;
}

void cs_noise_period(const struct cs_noise_recipe *r, int c, int nx, int nz,
		     int period[3])
{
	int f = r->freq[c];
	long pz = lround((double)f * nz / nx);
	period[0] = period[1] = f;
	period[2] = pz < 1 ? 1 : (int)pz;
}

int cs_volume_new(struct cs_volume *v, int nx, int nz)
{
	memset(v, 0, sizeof *v);
	if (nx < 1 || nx > CS_VOLUME_MAX_DIM || nz < 1 || nz > CS_VOLUME_MAX_DIM)
		return cs_error(CS_EINVAL, "volume size %dx%dx%d out of range 1..%d",
				nx, nx, nz, CS_VOLUME_MAX_DIM);
	size_t n = (size_t)nx * (size_t)nx * (size_t)nz * 4u;
	v->data = (float *)calloc(n, sizeof(float));
	if (v->data == NULL)
		return cs_error(CS_ENOMEM, "out of memory for a %dx%dx%d volume",
				nx, nx, nz);
	v->nx = v->ny = nx;
	v->nz = nz;
	cs_noise_recipe_default(&v->recipe);
	return CS_OK;
}

void cs_volume_free(struct cs_volume *v)
{
	free(v->data);
	memset(v, 0, sizeof *v);
}

/* One octave of one channel's lattice: tabulated where it is small enough
 * (cs_lattice_lut), else looked up directly; the same value either way. */
struct octave {
	int period[3];
	uint32_t seed;
	int worley, tabulated;
	struct cs_lattice_lut lut;
};

/* The inverted Worley noise of noise.c's fbm3p: 1 - min(F1, 1). */
static inline double inverted(double f1)
{
	return 1.0 - (f1 < 1.0 ? f1 : 1.0);
}

/* cs_perlin_worley3p()'s mix of the Perlin fBm pf and the Worley fBm wf. */
static inline float perlin_worley(double pf, double wf)
{
	pf = pf < -1.0 ? -1.0 : pf > 1.0 ? 1.0 : pf;
	double pp = 0.5 + 0.5 * pf;
	pp = pp < 0.0 ? 0.0 : pp > 1.0 ? 1.0 : pp;
	return (float)((pp - wf + 1.0) / (2.0 - wf));
}

static double octave_noise(const struct octave *o, struct cs_worley_cache *wc,
			   double x, double y, double z)
{
	if (o->worley)
		return inverted(o->tabulated ? cs_worley3p_lut(&o->lut, wc, x, y, z)
					     : cs_worley3p(x, y, z, o->period, o->seed));
	return o->tabulated ? cs_perlin3p_lut(&o->lut, x, y, z)
			    : cs_perlin3p(x, y, z, o->period, o->seed);
}

/* The fractal sum of noise.c's fbm3p over the octaves o[0..n-1], term by
 * term as it does it, so the bits are the same. */
static double fbm(const struct octave *o, struct cs_worley_cache *wc, int n, double gain,
		  double x, double y, double z)
{
	double sum = 0.0, norm = 0.0, amp = 1.0;
	long freq = 1;
	for (int i = 0; i < n; i++) {
		double fx = x * (double)freq, fy = y * (double)freq, fz = z * (double)freq;
		sum += amp * octave_noise(&o[i], wc ? &wc[i] : NULL, fx, fy, fz);
		norm += amp;
		amp *= gain;
		freq *= 2; /* the recipe's lacunarity */
	}
	return sum / norm;
}

enum { MAX_OCT = 12 };
struct bake_job {
	struct cs_volume *v;
	int period[4][3];
	/* channel c's octaves: [c][0] the Worley fBm, [0][1] R's Perlin fBm */
	struct octave oct[4][2][MAX_OCT];
};

/* Sets up n octaves of a channel from base period p and seed (seed + i
 * for octave i, period p 2^i: noise.c's fbm3p). */
static void octaves_init(struct octave *o, int n, const int p[3], uint32_t seed, int worley)
{
	for (int i = 0; i < n; i++) {
		memset(&o[i], 0, sizeof o[i]);
		for (int a = 0; a < 3; a++)
			o[i].period[a] = (int)(p[a] * (1L << i));
		o[i].seed = seed + (uint32_t)i;
		o[i].worley = worley;
		o[i].tabulated = cs_lattice_lut_new(&o[i].lut, o[i].period, o[i].seed, worley) == CS_OK;
	}
}

/* One voxel's four channels.  Voxel centres sit at (i + 0.5) / n of the
 * period so that no channel is sampled exactly on its lattice.  What
 * cs_perlin_worley3p() and cs_worley_fbm3p() give, from the tables. */
static void bake_voxel(const struct bake_job *job, struct cs_worley_cache wc[4][MAX_OCT],
		       int x, int y, int z, float out[4])
{
	const struct cs_volume *v = job->v;
	const struct cs_noise_recipe *r = &v->recipe;
	double u = (x + 0.5) / v->nx, w = (y + 0.5) / v->ny, t = (z + 0.5) / v->nz;
	for (int c = 0; c < 4; c++) {
		const int *p = job->period[c];
		double px = u * p[0], py = w * p[1], pz = t * p[2];
		if (c == 0) {
			double pf = fbm(job->oct[0][1], NULL, r->octaves[0], r->gain, px, py, pz);
			double wf = fbm(job->oct[0][0], wc[0], r->worley_octaves, r->gain, px, py, pz);
			out[c] = perlin_worley(pf, wf);
		} else {
			out[c] = (float)fbm(job->oct[c][0], wc[c], r->octaves[c], r->gain, px, py, pz);
		}
	}
}

/* One octave of a channel along a row of voxels: ox[] the row's
 * coordinates in the octave's lattice, (oy, oz) their shared ones. */
static void octave_row(const struct octave *o, struct cs_worley_cache *wc, struct cs_worley_row *wr,
		       const double *ox, int n, double oy, double oz, double *val)
{
	if (!o->tabulated) {
		for (int i = 0; i < n; i++)
			val[i] = octave_noise(o, wc, ox[i], oy, oz);
		return;
	}
	if (!o->worley) {
		cs_perlin_row_lut(&o->lut, oy, oz, ox, n, val);
		return;
	}
	cs_worley_row_lut(wr, oy, oz, ox, n, val);
	for (int i = 0; i < n; i++)
		val[i] = inverted(val[i]);
}

/* fbm() along a row: px[] the row's coordinates in the base lattice, (py,
 * pz) their shared ones; the same sums, term by term, into sum[]. */
static void fbm_row(const struct octave *o, struct cs_worley_cache *wc, struct cs_worley_row *wr,
		    int noct, double gain, const double *px, int n, double py, double pz,
		    double *ox, double *val, double *sum)
{
	double norm = 0.0, amp = 1.0;
	long freq = 1;
	for (int i = 0; i < n; i++)
		sum[i] = 0.0;
	for (int k = 0; k < noct; k++) {
		for (int i = 0; i < n; i++)
			ox[i] = px[i] * (double)freq;
		octave_row(&o[k], wc ? &wc[k] : NULL, wr ? &wr[k] : NULL, ox, n, py * (double)freq,
			   pz * (double)freq, val);
		for (int i = 0; i < n; i++)
			sum[i] += amp * val[i];
		norm += amp;
		amp *= gain;
		freq *= 2;
	}
	for (int i = 0; i < n; i++)
		sum[i] /= norm;
}

/* Row y of slice z, as bake_voxel() bakes each voxel of it.  buf: 5 nx
 * doubles; wr: each Worley table's row state. */
static void bake_row(const struct bake_job *job, struct cs_worley_cache wc[4][MAX_OCT],
		     struct cs_worley_row wr[4][MAX_OCT], double *buf, int y, int z)
{
	const struct cs_volume *v = job->v;
	const struct cs_noise_recipe *r = &v->recipe;
	int n = v->nx;
	double *px = buf, *ox = px + n, *val = ox + n, *sum = val + n, *wsum = sum + n;
	double w = (y + 0.5) / v->ny, t = (z + 0.5) / v->nz;
	float *out = v->data + ((size_t)z * v->ny + y) * (size_t)n * 4;
	for (int c = 0; c < 4; c++) {
		const int *p = job->period[c];
		for (int i = 0; i < n; i++)
			px[i] = (i + 0.5) / n * p[0];
		double py = w * p[1], pz = t * p[2];
		if (c == 0) {
			fbm_row(job->oct[0][1], NULL, NULL, r->octaves[0], r->gain, px, n, py, pz,
				ox, val, sum);
			fbm_row(job->oct[0][0], wc[0], wr[0], r->worley_octaves, r->gain, px, n,
				py, pz, ox, val, wsum);
			for (int i = 0; i < n; i++)
				out[4 * i] = perlin_worley(sum[i], wsum[i]);
		} else {
			fbm_row(job->oct[c][0], wc[c], wr[c], r->octaves[c], r->gain, px, n, py,
				pz, ox, val, sum);
			for (int i = 0; i < n; i++)
				out[4 * i + c] = (float)sum[i];
		}
	}
}

static void bake_slice(void *user, int z, int worker)
{
	(void)worker;
	const struct bake_job *job = (const struct bake_job *)user;
	struct cs_volume *v = job->v;
	struct cs_worley_cache wc[4][MAX_OCT];
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < MAX_OCT; i++)
			wc[c][i].key[0] = -1; /* no cell yet */
	struct cs_worley_row wr[4][MAX_OCT] = {0};
	int ok = 1;
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < MAX_OCT; i++) {
			const struct octave *o = &job->oct[c][0][i];
			if (o->tabulated && o->worley)
				ok &= cs_worley_row_init(&wr[c][i], &o->lut) == CS_OK;
		}
	double *buf = (double *)malloc(5 * (size_t)v->nx * sizeof *buf);
	if (buf != NULL && ok)
		for (int y = 0; y < v->ny; y++)
			bake_row(job, wc, wr, buf, y, z);
	free(buf);
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < MAX_OCT; i++)
			cs_worley_row_free(&wr[c][i]);
	if (buf != NULL && ok)
		return;
	/* no memory for the rows: voxel by voxel, the same values */
	for (int y = 0; y < v->ny; y++)
		for (int x = 0; x < v->nx; x++)
			bake_voxel(job, wc, x, y, z,
				   v->data + (((size_t)z * v->ny + y) * v->nx + x) * 4);
}

int cs_volume_bake(struct cs_volume *v, int nthreads, cs_progress_fn progress,
		   void *user)
{
	int rc = cs_noise_recipe_check(&v->recipe);
	if (rc != CS_OK)
		return rc;
	if (v->data == NULL)
		return cs_error(CS_EINVAL, "volume is not allocated");
	struct bake_job *job = (struct bake_job *)calloc(1, sizeof *job);
	if (job == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	job->v = v;
	const struct cs_noise_recipe *r = &v->recipe;
	for (int c = 0; c < 4; c++) {
		cs_noise_period(r, c, v->nx, v->nz, job->period[c]);
		/* one independent stream per channel, fixed by the recipe seed */
		uint32_t seed = cs_hash3i((int32_t)r->seed, c, 0, 0x6e6f6973u);
		if (c == 0) {
			octaves_init(job->oct[0][1], r->octaves[0], job->period[0], seed, 0);
			/* the Worley part of R: noise.c's seed ^ 0x5bd1e995 */
			octaves_init(job->oct[0][0], r->worley_octaves, job->period[0],
				     seed ^ 0x5bd1e995u, 1);
		} else {
			octaves_init(job->oct[c][0], r->octaves[c], job->period[c], seed, 1);
		}
	}
	rc = cs_pool_run(v->nz, nthreads, bake_slice, job, progress, user, NULL);
	for (int c = 0; c < 4; c++)
		for (int k = 0; k < 2; k++)
			for (int i = 0; i < MAX_OCT; i++)
				cs_lattice_lut_free(&job->oct[c][k][i].lut);
	free(job);
	if (rc == CS_ECANCELED)
		return cs_error(CS_ECANCELED, "baking cancelled");
	return rc;
}

CS_HD static inline int wrapi(long i, int n)
{
	long m = i % n;
	return (int)(m < 0 ? m + n : m);
}

/* The eight voxels around (u, v, w) and the trilinear weights: voxel
 * centres are at (i + 0.5) / n, as baked, and every axis wraps. */
struct corners {
	uint32_t off[8]; /* float offsets of the voxels' channel 0; bit 0 = +x, 1 = +y, 2 = +z */
	float tx, ty, tz;
};

/* The lattice index of voxel coordinate g (floor taken) wrapped into
 * [0, n).  Sizes are powers of two in every volume noisebake makes and
 * cloudrender bakes: then the wrap is a mask (the reduction below gives
 * the same integer, without its divisions). */
CS_HD static inline long lattice(double f, int n)
{
	if ((n & (n - 1)) == 0)
		return (long)f & (n - 1);
	/* reduce first so the conversion to long is defined for any finite input */
	return wrapi((long)(f - n * floor(f / n)), n);
}

/* u, vv, w finite and below 2^40 in magnitude (the callers see to it). */
CS_HD static inline void corners(const struct cs_volume *v, double u, double vv,
				 double w, struct corners *c)
{
	int nx = v->nx, ny = v->ny, nz = v->nz;
	double gx = u * nx - 0.5, gy = vv * ny - 0.5, gz = w * nz - 0.5;
	double fx = floor(gx), fy = floor(gy), fz = floor(gz);
	c->tx = (float)(gx - fx), c->ty = (float)(gy - fy), c->tz = (float)(gz - fz);
	long ix = lattice(fx, nx), iy = lattice(fy, ny), iz = lattice(fz, nz);
	uint32_t x0 = (uint32_t)ix, x1 = ix + 1 < nx ? (uint32_t)ix + 1 : 0;
	uint32_t sy = (uint32_t)nx, sz = (uint32_t)nx * (uint32_t)ny;
	uint32_t y0 = (uint32_t)iy * sy, y1 = (iy + 1 < ny ? (uint32_t)iy + 1 : 0) * sy;
	uint32_t z0 = (uint32_t)iz * sz, z1 = (iz + 1 < nz ? (uint32_t)iz + 1 : 0) * sz;
	c->off[0] = (z0 + y0 + x0) * 4, c->off[1] = (z0 + y0 + x1) * 4;
	c->off[2] = (z0 + y1 + x0) * 4, c->off[3] = (z0 + y1 + x1) * 4;
	c->off[4] = (z1 + y0 + x0) * 4, c->off[5] = (z1 + y0 + x1) * 4;
	c->off[6] = (z1 + y1 + x0) * 4, c->off[7] = (z1 + y1 + x1) * 4;
}

CS_HD static inline float trilinear(const float *d, const struct corners *c)
{
	const uint32_t *o = c->off;
	float c00 = d[o[0]] + c->tx * (d[o[1]] - d[o[0]]);
	float c10 = d[o[2]] + c->tx * (d[o[3]] - d[o[2]]);
	float c01 = d[o[4]] + c->tx * (d[o[5]] - d[o[4]]);
	float c11 = d[o[6]] + c->tx * (d[o[7]] - d[o[6]]);
	float c0 = c00 + c->ty * (c10 - c00);
	float c1 = c01 + c->ty * (c11 - c01);
	return c0 + c->tz * (c1 - c0);
}

/* Brings (u, vv, w) where corners() takes them: 0 when a coordinate is
 * not finite (the sample is then 0).  A coordinate of 2^40 or more has no
 * fraction left that a double can tell; fmod (exact) keeps u * nx finite
 * and the casts defined up to 1e308, while ordinary coordinates keep
 * their bits.  One test covers the usual case. */
CS_HD static inline int reduce(double *u, double *vv, double *w)
{
	if (fabs(*u) < 0x1p40 && fabs(*vv) < 0x1p40 && fabs(*w) < 0x1p40)
		return 1;
	if (!isfinite(*u) || !isfinite(*vv) || !isfinite(*w))
		return 0;
	*u = fabs(*u) < 0x1p40 ? *u : fmod(*u, 1.0);
	*vv = fabs(*vv) < 0x1p40 ? *vv : fmod(*vv, 1.0);
	*w = fabs(*w) < 0x1p40 ? *w : fmod(*w, 1.0);
	return 1;
}

CS_HD void cs_volume_sample4(const struct cs_volume *v, double u, double vv,
		       double w, float out[4])
{
	if (!reduce(&u, &vv, &w)) {
		out[0] = out[1] = out[2] = out[3] = 0.0f;
		return;
	}
	struct corners c;
	corners(v, u, vv, w, &c);
	for (int k = 0; k < 4; k++)
		out[k] = trilinear(v->data + k, &c);
}

CS_HD float cs_volume_sample(const struct cs_volume *v, int channel, double u,
		       double vv, double w)
{
	if (!reduce(&u, &vv, &w))
		return 0.0f;
	struct corners c;
	corners(v, u, vv, w, &c);
	return trilinear(v->data + (channel & 3), &c);
}

