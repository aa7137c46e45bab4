#include "render/cloud.h"
#include "weather/genus_rules.h"

#if defined(__AVX2__) && !defined(__CUDA_ARCH__)
#include <immintrin.h>
#endif

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Extinction of cloud: liquid water clouds have 10..100 droplets per cm^3,
 * giving 0.01..0.1 /m in the visible (mean free paths of 10..100 m); ice
 * clouds are 10..100 times thinner.  Tile sizes set the size of cells: a
 * base tile holds 4 lattice cells of the default noise recipe.  The base
 * tile is tall (tile_z several times the layer) so that the base shape is
 * nearly a 2D coverage map through the layer: coverage is then the
 * fraction of the sky covered, and the height profile rounds the tops.
 * The sheets that decide how much light reaches the ground are scaled to
 * the typical optical depth of their ISCCP class (Rossow & Schiffer 1999:
 * medium 3.6-23 for altostratus and stratocumulus, thick > 23 for
 * nimbostratus and stratus). */
static const struct cs_genus_preset presets[CS_GENUS_COUNT] = {
	[CS_CIRRUS] = {0.005, 20000, 60000, 2500, 0.45, 6.0,
		       {0.0, 0.3, 0.5, 1.0}, 0.0, 0.4, 0},
	[CS_CIRROCUMULUS] = {0.004, 4000, 30000, 800, 0.35, 1.2,
			     {0.0, 0.3, 0.7, 1.0}, 0.0, 0.3, 0},
	[CS_CIRROSTRATUS] = {0.0008, 40000, 80000, 6000, 0.15, 2.0,
			     {0.0, 0.15, 0.85, 1.0}, 0.0, 0.8, 0},
	[CS_ALTOCUMULUS] = {0.02, 6000, 30000, 1200, 0.35, 1.3,
			    {0.0, 0.25, 0.6, 1.0}, 0.0, 0.2, 0},
	[CS_ALTOSTRATUS] = {0.006, 30000, 60000, 5000, 0.1, 1.5,
			    {0.0, 0.1, 0.9, 1.0}, 0.0, 0.7, 12},
	[CS_NIMBOSTRATUS] = {0.025, 30000, 60000, 4000, 0.08, 1.2,
			     {0.0, 0.05, 0.85, 1.0}, 0.0, 0.5, 40},
	[CS_STRATOCUMULUS] = {0.03, 9000, 30000, 1500, 0.25, 1.3,
			      {0.0, 0.2, 0.65, 1.0}, 0.0, 0.25, 10},
	[CS_STRATUS] = {0.02, 30000, 60000, 3000, 0.08, 1.2,
			{0.0, 0.1, 0.9, 1.0}, 0.0, 0.6, 30},
	[CS_CUMULUS] = {0.05, 8000, 20000, 1500, 0.35, 1.0,
			{0.0, 0.06, 0.45, 1.0}, 0.0, 0.12, 0},
	[CS_CUMULONIMBUS] = {0.07, 40000, 80000, 4000, 0.15, 1.0,
			     {0.0, 0.03, 0.92, 1.0}, 0.35, 0.1, 0},
};

const struct cs_genus_preset *cs_genus_preset(enum cs_genus g)
{
	return (unsigned)g < CS_GENUS_COUNT ? &presets[g] : &presets[CS_CUMULUS];
}

static void calibrate(struct cs_cloud_layer *l, const struct cs_volume *noise);
static void build_bound(struct cs_cloud_layer *l, const struct cs_volume *noise);

/* The period of a genus's field across the wind, m: the least common
 * multiple of the base and detail tiles, or 0 when a tile is not a whole
 * number of metres (then the offset is not reduced). */
static double across_period_m(const struct cs_genus_preset *p)
{
	double a = p->tile_m, b = p->detail_tile_m;
	if (a != floor(a) || b != floor(b) || a < 1.0 || b < 1.0 || a > 1e9 || b > 1e9)
		return 0.0;
	long x = (long)a, y = (long)b;
	while (y != 0) {
		long r = x % y;
		x = y;
		y = r;
	}
	return a / (double)x * b;
}

/* The period along the wind: the one across, stretched. */
static double wind_period_m(const struct cs_genus_preset *p)
{
	return p->stretch * across_period_m(p);
}

int cs_cloud_periods(const struct cs_cloud_layer *l, double *along_m, double *across_m)
{
	const struct cs_genus_preset *p = cs_genus_preset(l->genus);
	double across = across_period_m(p);
	/* the layer's tiles must be its genus's (a test may set its own) */
	if (l->kind != CS_LAYER_CLOUD || !(across > 0.0) || l->inv_tile != 1.0 / p->tile_m ||
	    l->inv_detail != 1.0 / p->detail_tile_m || l->stretch != p->stretch)
		return 0;
	*across_m = across;
	*along_m = wind_period_m(p);
	return 1;
}

double cs_cloud_aloft_factor(double height_m)
{
	double factor = pow(fmax(height_m, 10.0) / 10.0, 1.0 / 7.0);
	return factor > 3.0 ? 3.0 : factor;
}

/* v reduced modulo period (when there is one); a non-finite v is 0. */
static double reduce_period(double v, double period)
{
	v = isfinite(v) ? v : 0.0;
	return period > 0.0 ? fmod(v, period) : v;
}

void cs_cloud_layer_init(struct cs_cloud_layer *l, const struct cs_wx_layer *wl,
			 const struct cs_volume *noise, double wind_speed_m_s,
			 double wind_from_deg, double ground_alt_m, double time_s)
{
	const struct cs_genus_preset *p = cs_genus_preset(wl->genus);
	memset(l, 0, sizeof *l);
	l->kind = CS_LAYER_CLOUD;
	l->site = -1;
	l->genus = wl->genus;
	l->base_m = wl->base_m;
	l->top_m = wl->top_m;
	l->coverage = wl->coverage;
	l->extinction_per_m = p->extinction_per_m;
	l->inv_tile = 1.0 / p->tile_m;
	l->inv_tile_z = 1.0 / p->tile_z_m;
	l->inv_detail = 1.0 / p->detail_tile_m;
	l->stretch = p->stretch;
	l->erosion = p->erosion;
	l->anvil = p->anvil;
	l->edge = p->edge;
	memcpy(l->ramp, p->ramp, sizeof l->ramp);
	l->ramp_inv[0] = p->ramp[1] > p->ramp[0] ? 1.0 / (p->ramp[1] - p->ramp[0]) : 0.0;
	l->ramp_inv[1] = p->ramp[3] > p->ramp[2] ? 1.0 / (p->ramp[3] - p->ramp[2]) : 0.0;
	l->inv_tile_along = l->inv_tile / l->stretch;
	l->inv_detail_along = l->inv_detail / l->stretch;

	double from = wind_from_deg * (CS_PI / 180.0);
	l->wind_x = -sin(from); /* blowing toward the opposite direction */
	l->wind_y = -cos(from);
	double factor = cs_cloud_aloft_factor(0.5 * (wl->base_m + wl->top_m) - ground_alt_m);
	/* Reduced modulo the field's period along the wind, the least common
	 * multiple of the base and detail tiles (whole metres), stretched: the
	 * field is the same, and the coordinates the per-sample code sees stay
	 * small, so a float build keeps its precision on any date. */
	l->offset_along_m = reduce_period(wind_speed_m_s * factor * time_s, wind_period_m(p));
	l->offset_across_m = 0.0;
	build_bound(l, noise);
	calibrate(l, noise);
}

void cs_cloud_layer_drift(struct cs_cloud_layer *l, double east_m, double north_m,
			  double axis_deg, double ground_alt_m)
{
	const struct cs_genus_preset *p = cs_genus_preset(l->genus);
	double base, top, axis = axis_deg * (CS_PI / 180.0);
	cs_genus_place(l->genus, ground_alt_m, &base, &top);
	double factor = cs_cloud_aloft_factor(0.5 * (base + top) - ground_alt_m);
	l->wind_x = sin(axis); /* a compass bearing: east is its sine */
	l->wind_y = cos(axis);
	double along, across;
	/* the offsets in the field's axes, reduced by its periods there */
	cs_cloud_en_to_axes(l, factor * east_m, factor * north_m, &along, &across);
	l->offset_along_m = reduce_period(along, wind_period_m(p));
	l->offset_across_m = reduce_period(across, across_period_m(p));
}

CS_HD static inline double smooth01(double x)
{
	x = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
	return x * x * (3.0 - 2.0 * x);
}

/* The genus height profile: a smooth trapezoid over the relative height,
 * with the reciprocals of its ramps' widths (0: no ramp). */
CS_HD static inline double profile(const double r[4], const double inv[2], double h)
{
	double up = inv[0] > 0.0 ? smooth01((h - r[0]) * inv[0]) : 1.0;
	double down = inv[1] > 0.0 ? 1.0 - smooth01((h - r[2]) * inv[1]) : 1.0;
	return up * down;
}

/* floor(x) as a long, |x| < 2^62 (the callers see to it): without a call
 * into libm, which baseline x86-64 code makes for floor. */
CS_HD static inline long floor_long(double x)
{
	long i = (long)x;
	return i - (x < (double)i);
}

/* A point of a layer on its way through the density (extinction_aw):
 * its coordinates in base-noise tiles, its height profile and threshold,
 * and what the detail lookup takes. */
struct ext_point {
	double u, v, w, prof, thr;
	double along, across, alt_m;
};

/* The first part of the density at coordinates along and across the wind
 * (already moved by it), at altitude alt_m and relative height h in
 * [0, 1]: the base shape's lookup coordinates, the profile, the threshold
 * (an anvil lowers it), and the coverage bound's verdict: 0 when the
 * point has no cloud without a lookup, else 1 with *pt filled. */
CS_HD static inline int ext_prepare(const struct cs_cloud_layer *l, const struct cs_volume *noise,
				    double along, double across, double alt_m, double h,
				    double thr, struct ext_point *pt)
{
	double u = along * l->inv_tile_along, v = across * l->inv_tile;
	double w = alt_m * l->inv_tile_z;

	double prof = profile(l->ramp, l->ramp_inv, h);
	/* an anvil spreads the top fifth: the threshold drops there */
	if (l->anvil > 0.0 && h > 0.78)
		thr -= l->anvil * 0.3 * smooth01((h - 0.78) / 0.1) * (1.0 - thr);
	*pt = (struct ext_point){u, v, w, prof, thr, along, across, alt_m};
	if (l->bound_n > 0 && w >= l->bound_w0 && w <= l->bound_w1 && fabs(u) < 0x1p30 &&
	    fabs(v) < 0x1p30) {
		/* the cell of the voxel the lookup's trilinear starts at */
		long i = floor_long(u * noise->nx - 0.5) >> l->bound_shift;
		long j = floor_long(v * noise->ny - 0.5) >> l->bound_shift;
		unsigned m = (unsigned)l->bound_n - 1u;
		double b = l->bound[((unsigned long)j & m) * (unsigned)l->bound_n + ((unsigned long)i & m)];
		if (b < 255.0 && b * (1.0 / 255.0) * prof <= thr)
			return 0;
	}
	return 1;
}

/* The base shape at a prepared point (the noise's channel R times the
 * profile). */
CS_HD static inline double ext_shape(const struct cs_volume *noise, const struct ext_point *pt)
{
	return cs_volume_sample(noise, 0, pt->u, pt->v, pt->w) * pt->prof;
}

/* The extinction at a prepared point whose shape is above its threshold.
 * d = (shape - thr) / (1 - thr): 0 at the edge, 1 at the core.  Erosion
 * by the detail fBm carves the edge into billows: the cloud's surface is
 * where d equals the local erosion e, not where d is 0, and the density
 * (d - e) / (1 - e) then rises over a band of width edge: narrow for
 * sharp-edged heaps, wide for veils.  One division, and none where the
 * erosion leaves nothing. */
CS_HD static inline double ext_finish(const struct cs_cloud_layer *l, const struct cs_volume *noise,
				      const struct ext_point *pt, double shape)
{
	double thr = pt->thr;
	float g[4];
	cs_volume_sample4(noise, pt->along * l->inv_detail_along, pt->across * l->inv_detail,
			  pt->alt_m * l->inv_detail, g);
	double detail = 0.625 * g[1] + 0.25 * g[2] + 0.125 * g[3];
	double e = l->erosion * detail;
	double num = (shape - thr) - e * (1.0 - thr);
	if (num <= 0.0)
		return 0.0;
	double d = num / ((1.0 - thr) * (1.0 - e + 1e-9) * l->edge);
	d = d < 1.0 ? d : 1.0;
	return d * l->extinction_per_m;
}

/* The extinction at coordinates along and across the wind (already moved
 * by it), at altitude alt_m and relative height h in [0, 1]. */
CS_HD static double extinction_aw(const struct cs_cloud_layer *l,
			    const struct cs_volume *noise, double along,
			    double across, double alt_m, double h, double thr)
{
	struct ext_point pt;
	if (!ext_prepare(l, noise, along, across, alt_m, h, thr, &pt))
		return 0.0;
	double shape = ext_shape(noise, &pt);
	if (shape <= pt.thr)
		return 0.0;
	return ext_finish(l, noise, &pt, shape);
}

/* The threshold of layer l at (x, y) into *thr: 0 where its site has no
 * weight (no cloud there), else 1. */
CS_HD static inline int site_threshold(const struct cs_cloud_layer *l, double x, double y,
				       double *thr)
{
	*thr = l->threshold;
	if (l->nfar > 0) { /* blended with other sites: the coverage here */
		double w = cs_cloud_site_weight(l, x, y) * CS_BLEND_LEVELS;
		if (w <= 0.0)
			return 0;
		int k = (int)w;
		*thr = k >= CS_BLEND_LEVELS ? l->thr_table[CS_BLEND_LEVELS]
					    : l->thr_table[k] + (w - k) * (l->thr_table[k + 1] - l->thr_table[k]);
	}
	return 1;
}

CS_HD CS_SHARED double cs_cloud_extinction(const struct cs_cloud_layer *l,
			   const struct cs_volume *noise, double x, double y,
			   double alt_m)
{
	double h = (alt_m - l->base_m) / (l->top_m - l->base_m);
	if (!(h >= 0.0 && h <= 1.0))
		return 0.0;
	if (l->kind == CS_LAYER_HOMOGENEOUS) {
		double dx = x - l->homog_x, dy = y - l->homog_y;
		if (l->homog_radius_m > 0.0 &&
		    dx * dx + dy * dy > l->homog_radius_m * l->homog_radius_m)
			return 0.0;
		return fmax(0.0, l->homog_a + l->homog_b * h);
	}
	double thr;
	if (!site_threshold(l, x, y, &thr))
		return 0.0;
	/* coordinates along and across the wind, moved by it */
	double along, across;
	cs_cloud_en_to_axes(l, x, y, &along, &across);
	return extinction_aw(l, noise, along - l->offset_along_m, across - l->offset_across_m, alt_m,
			     h, thr);
}

#if defined(__AVX2__) && !defined(__CUDA_ARCH__)
/* Four points at a time with AVX2, for the kernel build that has it:
 * every operation of ext_prepare and ext_shape, lane by lane, in the same
 * order and rounding (no fused multiply-adds: -ffp-contract=off), so each
 * lane has the bits of the scalar code.  The points whose base shape is
 * above the threshold are finished one by one (ext_finish). */

/* The low 32 bits of the integers in f (whole numbers below 2^51 in
 * size): f + 1.5 2^52 is exact and holds 2^51 + f in its fraction, whose
 * low bits are f's, two's complement. */
static inline __m128i low32(__m256d f)
{
	__m256i b = _mm256_castpd_si256(_mm256_add_pd(f, _mm256_set1_pd(0x1.8p52)));
	b = _mm256_permutevar8x32_epi32(b, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6));
	return _mm256_castsi256_si128(b);
}

/* smooth01 lane by lane */
static inline __m256d smooth01_4(__m256d x)
{
	__m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
	x = _mm256_blendv_pd(x, zero, _mm256_cmp_pd(x, zero, _CMP_LT_OQ));
	x = _mm256_blendv_pd(x, one, _mm256_cmp_pd(x, one, _CMP_GT_OQ));
	return _mm256_mul_pd(_mm256_mul_pd(x, x),
			     _mm256_sub_pd(_mm256_set1_pd(3.0), _mm256_mul_pd(_mm256_set1_pd(2.0), x)));
}

/* The eight voxels around lanes' voxel coordinates g (u nx - 0.5 ...)
 * and the trilinear weights, as volume.c's corners() (power-of-two sizes,
 * at most 2^31 floats): float offsets of channel 0, by bit 0 = +x, 1 =
 * +y, 2 = +z. */
struct corners4 {
	__m128i off[8];
	__m128 tx, ty, tz;
};

static inline void corners4(const struct cs_volume *v, __m256d gx, __m256d gy, __m256d gz,
			    struct corners4 *c)
{
	__m256d fx = _mm256_floor_pd(gx), fy = _mm256_floor_pd(gy), fz = _mm256_floor_pd(gz);
	c->tx = _mm256_cvtpd_ps(_mm256_sub_pd(gx, fx));
	c->ty = _mm256_cvtpd_ps(_mm256_sub_pd(gy, fy));
	c->tz = _mm256_cvtpd_ps(_mm256_sub_pd(gz, fz));
	__m128i mx = _mm_set1_epi32(v->nx - 1), my = _mm_set1_epi32(v->ny - 1),
		mz = _mm_set1_epi32(v->nz - 1), one = _mm_set1_epi32(1);
	__m128i x0 = _mm_and_si128(low32(fx), mx), x1 = _mm_and_si128(_mm_add_epi32(x0, one), mx);
	__m128i y0 = _mm_and_si128(low32(fy), my), y1 = _mm_and_si128(_mm_add_epi32(y0, one), my);
	__m128i z0 = _mm_and_si128(low32(fz), mz), z1 = _mm_and_si128(_mm_add_epi32(z0, one), mz);
	__m128i sy = _mm_set1_epi32(v->nx), sz = _mm_set1_epi32(v->nx * v->ny);
	y0 = _mm_mullo_epi32(y0, sy), y1 = _mm_mullo_epi32(y1, sy);
	z0 = _mm_mullo_epi32(z0, sz), z1 = _mm_mullo_epi32(z1, sz);
	__m128i zy[4] = {_mm_add_epi32(z0, y0), _mm_add_epi32(z0, y1), _mm_add_epi32(z1, y0),
			 _mm_add_epi32(z1, y1)};
	for (int k = 0; k < 8; k++)
		c->off[k] = _mm_slli_epi32(_mm_add_epi32(zy[k >> 1], k & 1 ? x1 : x0), 2);
}

/* volume.c's trilinear() of the eight corner values q, lane by lane */
static inline __m128 lerp3_4(const __m128 q[8], const struct corners4 *c)
{
	__m128 c00 = _mm_add_ps(q[0], _mm_mul_ps(c->tx, _mm_sub_ps(q[1], q[0])));
	__m128 c10 = _mm_add_ps(q[2], _mm_mul_ps(c->tx, _mm_sub_ps(q[3], q[2])));
	__m128 c01 = _mm_add_ps(q[4], _mm_mul_ps(c->tx, _mm_sub_ps(q[5], q[4])));
	__m128 c11 = _mm_add_ps(q[6], _mm_mul_ps(c->tx, _mm_sub_ps(q[7], q[6])));
	__m128 c0 = _mm_add_ps(c00, _mm_mul_ps(c->ty, _mm_sub_ps(c10, c00)));
	__m128 c1 = _mm_add_ps(c01, _mm_mul_ps(c->ty, _mm_sub_ps(c11, c01)));
	return _mm_add_ps(c0, _mm_mul_ps(c->tz, _mm_sub_ps(c1, c0)));
}

/* volume.c's trilinear() of channel 0 (the base shape) at the lanes'
 * corners */
static inline __m128 trilinear4_r(const struct cs_volume *v, const struct corners4 *c)
{
	const float *d = v->data;
	__m128 q[8];
	for (int k = 0; k < 8; k++) {
		int o[4];
		_mm_storeu_si128((__m128i *)o, c->off[k]);
		q[k] = _mm_setr_ps(d[o[0]], d[o[1]], d[o[2]], d[o[3]]);
	}
	return lerp3_4(q, c);
}

/* volume.c's trilinear() of channels 1, 2 and 3 (the detail) at the
 * lanes' corners: each voxel's four channels in one load, turned into
 * channels across lanes (fewer loads than a gather a channel) */
static inline void trilinear4_gba(const struct cs_volume *v, const struct corners4 *c,
				  __m128 g[3])
{
	const float *d = v->data;
	__m128 q[3][8];
	for (int k = 0; k < 8; k++) {
		int o[4];
		_mm_storeu_si128((__m128i *)o, c->off[k]);
		__m128 r0 = _mm_loadu_ps(d + o[0]), r1 = _mm_loadu_ps(d + o[1]);
		__m128 r2 = _mm_loadu_ps(d + o[2]), r3 = _mm_loadu_ps(d + o[3]);
		_MM_TRANSPOSE4_PS(r0, r1, r2, r3);
		q[0][k] = r1, q[1][k] = r2, q[2][k] = r3;
	}
	for (int ch = 0; ch < 3; ch++)
		g[ch] = lerp3_4(q[ch], c);
}

/* A mask of the lanes whose three coordinates are below 2^40 in size
 * (volume.c's reduce: beyond, its fmod) */
static inline int small4(__m256d u, __m256d v, __m256d w)
{
	__m256d big = _mm256_set1_pd(0x1p40), sign = _mm256_set1_pd(-0.0);
	__m256d in = _mm256_and_pd(_mm256_cmp_pd(_mm256_andnot_pd(sign, u), big, _CMP_LT_OQ),
				   _mm256_cmp_pd(_mm256_andnot_pd(sign, v), big, _CMP_LT_OQ));
	in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_andnot_pd(sign, w), big, _CMP_LT_OQ));
	return _mm256_movemask_pd(in);
}

/* all ones in the lanes of mask, zero in the others */
static inline __m256d lanes4(int mask)
{
	return _mm256_castsi256_pd(_mm256_setr_epi64x(mask & 1 ? -1 : 0, mask & 2 ? -1 : 0,
						      mask & 4 ? -1 : 0, mask & 8 ? -1 : 0));
}

/* The lanes' prepared points (struct ext_point's values, lane by lane)
 * and base shapes, for the lanes finished one by one. */
struct lanes {
	double u[8], v[8], w[8], prof[8], thr[8], along[8], across[8], shape[8];
};

/* The lanes of slow (bit k: lane k) the scalar way: the base shape
 * looked up where the lanes did not (not in fast), then ext_finish where
 * it is above the threshold, into out[k]. */
static void finish_lanes(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			 const struct lanes *ln, unsigned slow, unsigned fast, const double *alt_m,
			 double *out)
{
	for (int k = 0; slow >> k; k++) {
		if (!(slow & (1u << k)))
			continue;
		struct ext_point pt = {ln->u[k], ln->v[k], ln->w[k], ln->prof[k],
				       ln->thr[k], ln->along[k], ln->across[k], alt_m[k]};
		double sh = (fast & (1u << k)) ? ln->shape[k] : ext_shape(noise, &pt);
		if (!(sh <= pt.thr))
			out[k] = ext_finish(l, noise, &pt, sh);
	}
}

/* Whether the lanes' fast path applies to this layer and volume at all. */
static int batch4_ok(const struct cs_cloud_layer *l, const struct cs_volume *v)
{
	int nx = v->nx, ny = v->ny, nz = v->nz;
	return l->kind == CS_LAYER_CLOUD && l->nfar == 0 && v->data != NULL &&
	       (nx & (nx - 1)) == 0 && (ny & (ny - 1)) == 0 && (nz & (nz - 1)) == 0 &&
	       (double)nx * ny * nz * 4.0 < 0x1p31;
}

/* Points i0 .. i0 + 3 of the batch: out[] for each, 0 or the density. */
static void extinction4(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			const double *x, const double *y, const double *alt_m, double *out)
{
	__m256d X = _mm256_loadu_pd(x), Y = _mm256_loadu_pd(y), A = _mm256_loadu_pd(alt_m);
	__m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
	__m256d H = _mm256_div_pd(_mm256_sub_pd(A, _mm256_set1_pd(l->base_m)),
				  _mm256_set1_pd(l->top_m - l->base_m));
	__m256d live = _mm256_and_pd(_mm256_cmp_pd(H, zero, _CMP_GE_OQ),
				     _mm256_cmp_pd(H, one, _CMP_LE_OQ));
	__m256d thr = _mm256_set1_pd(l->threshold);
	__m256d wx = _mm256_set1_pd(l->wind_x), wy = _mm256_set1_pd(l->wind_y);
	__m256d along = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(X, wx), _mm256_mul_pd(Y, wy)),
				      _mm256_set1_pd(l->offset_along_m));
	__m256d negx = _mm256_xor_pd(X, _mm256_set1_pd(-0.0));
	__m256d across = _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(negx, wy), _mm256_mul_pd(Y, wx)),
				       _mm256_set1_pd(l->offset_across_m));
	__m256d U = _mm256_mul_pd(along, _mm256_set1_pd(l->inv_tile_along));
	__m256d V = _mm256_mul_pd(across, _mm256_set1_pd(l->inv_tile));
	__m256d W = _mm256_mul_pd(A, _mm256_set1_pd(l->inv_tile_z));
	/* the profile */
	__m256d up = one, down = one;
	if (l->ramp_inv[0] > 0.0)
		up = smooth01_4(_mm256_mul_pd(_mm256_sub_pd(H, _mm256_set1_pd(l->ramp[0])),
					      _mm256_set1_pd(l->ramp_inv[0])));
	if (l->ramp_inv[1] > 0.0)
		down = _mm256_sub_pd(one, smooth01_4(_mm256_mul_pd(
						  _mm256_sub_pd(H, _mm256_set1_pd(l->ramp[2])),
						  _mm256_set1_pd(l->ramp_inv[1]))));
	__m256d prof = _mm256_mul_pd(up, down);
	if (l->anvil > 0.0) {
		__m256d s = smooth01_4(_mm256_div_pd(_mm256_sub_pd(H, _mm256_set1_pd(0.78)),
						     _mm256_set1_pd(0.1)));
		__m256d t = _mm256_sub_pd(thr, _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(l->anvil * 0.3), s),
							     _mm256_sub_pd(one, thr)));
		thr = _mm256_blendv_pd(thr, t, _mm256_cmp_pd(H, _mm256_set1_pd(0.78), _CMP_GT_OQ));
	}
	__m256d nx = _mm256_set1_pd((double)noise->nx), ny = _mm256_set1_pd((double)noise->ny);
	__m256d nz = _mm256_set1_pd((double)noise->nz), half = _mm256_set1_pd(0.5);
	__m256d gx = _mm256_sub_pd(_mm256_mul_pd(U, nx), half);
	__m256d gy = _mm256_sub_pd(_mm256_mul_pd(V, ny), half);
	if (l->bound_n > 0) {
		__m256d lim = _mm256_set1_pd(0x1p30), sign = _mm256_set1_pd(-0.0);
		__m256d in = _mm256_and_pd(_mm256_cmp_pd(W, _mm256_set1_pd(l->bound_w0), _CMP_GE_OQ),
					   _mm256_cmp_pd(W, _mm256_set1_pd(l->bound_w1), _CMP_LE_OQ));
		in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_andnot_pd(sign, U), lim, _CMP_LT_OQ));
		in = _mm256_and_pd(in, _mm256_cmp_pd(_mm256_andnot_pd(sign, V), lim, _CMP_LT_OQ));
		__m128i m = _mm_set1_epi32(l->bound_n - 1), sh = _mm_cvtsi32_si128(l->bound_shift);
		__m128i ci = _mm_and_si128(_mm_srl_epi32(low32(_mm256_floor_pd(gx)), sh), m);
		__m128i cj = _mm_and_si128(_mm_srl_epi32(low32(_mm256_floor_pd(gy)), sh), m);
		__m128i cell = _mm_add_epi32(_mm_mullo_epi32(cj, _mm_set1_epi32(l->bound_n)), ci);
		int c[4];
		_mm_storeu_si128((__m128i *)c, cell);
		__m256d b = _mm256_setr_pd(l->bound[c[0]], l->bound[c[1]], l->bound[c[2]], l->bound[c[3]]);
		__m256d empty = _mm256_and_pd(
			_mm256_cmp_pd(b, _mm256_set1_pd(255.0), _CMP_LT_OQ),
			_mm256_cmp_pd(_mm256_mul_pd(_mm256_mul_pd(b, _mm256_set1_pd(1.0 / 255.0)), prof),
				      thr, _CMP_LE_OQ));
		live = _mm256_andnot_pd(_mm256_and_pd(in, empty), live);
	}
	int lanes = _mm256_movemask_pd(live);
	_mm256_storeu_pd(out, zero);
	if (lanes == 0)
		return;
	/* the lanes in play within the lookup's own limit (the rare other
	 * lane the scalar way); lanes not in play look up voxel 0 harmlessly */
	int fast = small4(U, V, W) & lanes;
	__m256d keep = lanes4(fast);
	__m256d gz = _mm256_sub_pd(_mm256_mul_pd(W, nz), half);
	struct corners4 cb;
	corners4(noise, _mm256_and_pd(gx, keep), _mm256_and_pd(gy, keep), _mm256_and_pd(gz, keep),
		 &cb);
	__m256d shape = _mm256_mul_pd(_mm256_cvtps_pd(trilinear4_r(noise, &cb)), prof);
	/* !(shape <= thr), as the scalar code tests it: a shape that is not
	 * a number (a volume with such voxels) goes on, as there */
	int cloud = _mm256_movemask_pd(_mm256_cmp_pd(shape, thr, _CMP_NLE_UQ)) & fast;
	/* the detail where the shape is above the threshold */
	__m256d du = _mm256_mul_pd(along, _mm256_set1_pd(l->inv_detail_along));
	__m256d dv = _mm256_mul_pd(across, _mm256_set1_pd(l->inv_detail));
	__m256d dw = _mm256_mul_pd(A, _mm256_set1_pd(l->inv_detail));
	int detail = small4(du, dv, dw) & cloud;
	if (detail) {
		__m256d dk = lanes4(detail);
		__m256d hx = _mm256_and_pd(_mm256_sub_pd(_mm256_mul_pd(du, nx), half), dk);
		__m256d hy = _mm256_and_pd(_mm256_sub_pd(_mm256_mul_pd(dv, ny), half), dk);
		__m256d hz = _mm256_and_pd(_mm256_sub_pd(_mm256_mul_pd(dw, nz), half), dk);
		struct corners4 cd;
		corners4(noise, hx, hy, hz, &cd);
		__m128 gba[3];
		trilinear4_gba(noise, &cd, gba);
		__m256d g1 = _mm256_cvtps_pd(gba[0]), g2 = _mm256_cvtps_pd(gba[1]);
		__m256d g3 = _mm256_cvtps_pd(gba[2]);
		__m256d det = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(_mm256_set1_pd(0.625), g1),
							  _mm256_mul_pd(_mm256_set1_pd(0.25), g2)),
					    _mm256_mul_pd(_mm256_set1_pd(0.125), g3));
		__m256d e = _mm256_mul_pd(_mm256_set1_pd(l->erosion), det);
		__m256d omt = _mm256_sub_pd(one, thr);
		__m256d num = _mm256_sub_pd(_mm256_sub_pd(shape, thr), _mm256_mul_pd(e, omt));
		__m256d den = _mm256_mul_pd(
			_mm256_mul_pd(omt, _mm256_add_pd(_mm256_sub_pd(one, e), _mm256_set1_pd(1e-9))),
			_mm256_set1_pd(l->edge));
		__m256d d = _mm256_min_pd(_mm256_div_pd(num, den), one);
		d = _mm256_mul_pd(d, _mm256_set1_pd(l->extinction_per_m));
		/* !(num <= 0) as there; a num that is not a number gives d 1 (min_pd
		 * returns its second operand then), as the scalar d < 1 ? d : 1 */
		__m256d pos = _mm256_and_pd(_mm256_cmp_pd(num, zero, _CMP_NLE_UQ), dk);
		_mm256_storeu_pd(out, _mm256_and_pd(d, pos));
	}
	unsigned slow = (unsigned)((lanes & ~fast) | (cloud & ~detail));
	if (slow == 0)
		return;
	struct lanes ln;
	_mm256_storeu_pd(ln.u, U), _mm256_storeu_pd(ln.v, V), _mm256_storeu_pd(ln.w, W);
	_mm256_storeu_pd(ln.prof, prof), _mm256_storeu_pd(ln.thr, thr);
	_mm256_storeu_pd(ln.along, along), _mm256_storeu_pd(ln.across, across);
	_mm256_storeu_pd(ln.shape, shape);
	finish_lanes(l, noise, &ln, slow, (unsigned)fast, alt_m, out);
}
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
/* Eight points at a time with AVX-512 (the x86-64-v4 kernel build):
 * extinction4's operations on eight lanes, in the same order and
 * rounding, so each lane has the bits of the scalar code.  The corners'
 * values are loaded one by one, as extinction4's: with AVX-512 gathers
 * instead, the density benchmark ran 165 against 215 million
 * evaluations a second on a 2-core AMD EPYC, and renders gained nothing
 * over the AVX2 build. */

static inline __m256i low32_8(__m512d f)
{
	return _mm512_cvtepi64_epi32(_mm512_castpd_si512(_mm512_add_pd(f, _mm512_set1_pd(0x1.8p52))));
}

static inline __m512d smooth01_8(__m512d x)
{
	__m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
	x = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(x, zero, _CMP_LT_OQ), x, zero);
	x = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(x, one, _CMP_GT_OQ), x, one);
	return _mm512_mul_pd(_mm512_mul_pd(x, x),
			     _mm512_sub_pd(_mm512_set1_pd(3.0), _mm512_mul_pd(_mm512_set1_pd(2.0), x)));
}

static inline __mmask8 small8(__m512d u, __m512d v, __m512d w)
{
	__m512d big = _mm512_set1_pd(0x1p40);
	return _mm512_cmp_pd_mask(_mm512_abs_pd(u), big, _CMP_LT_OQ) &
	       _mm512_cmp_pd_mask(_mm512_abs_pd(v), big, _CMP_LT_OQ) &
	       _mm512_cmp_pd_mask(_mm512_abs_pd(w), big, _CMP_LT_OQ);
}

struct corners8 {
	__m256i off[8];
	__m256 tx, ty, tz;
};

static inline void corners8(const struct cs_volume *v, __m512d gx, __m512d gy, __m512d gz,
			    struct corners8 *c)
{
	__m512d fx = _mm512_floor_pd(gx), fy = _mm512_floor_pd(gy), fz = _mm512_floor_pd(gz);
	c->tx = _mm512_cvtpd_ps(_mm512_sub_pd(gx, fx));
	c->ty = _mm512_cvtpd_ps(_mm512_sub_pd(gy, fy));
	c->tz = _mm512_cvtpd_ps(_mm512_sub_pd(gz, fz));
	__m256i mx = _mm256_set1_epi32(v->nx - 1), my = _mm256_set1_epi32(v->ny - 1),
		mz = _mm256_set1_epi32(v->nz - 1), one = _mm256_set1_epi32(1);
	__m256i x0 = _mm256_and_si256(low32_8(fx), mx);
	__m256i x1 = _mm256_and_si256(_mm256_add_epi32(x0, one), mx);
	__m256i y0 = _mm256_and_si256(low32_8(fy), my);
	__m256i y1 = _mm256_and_si256(_mm256_add_epi32(y0, one), my);
	__m256i z0 = _mm256_and_si256(low32_8(fz), mz);
	__m256i z1 = _mm256_and_si256(_mm256_add_epi32(z0, one), mz);
	__m256i sy = _mm256_set1_epi32(v->nx), sz = _mm256_set1_epi32(v->nx * v->ny);
	y0 = _mm256_mullo_epi32(y0, sy), y1 = _mm256_mullo_epi32(y1, sy);
	z0 = _mm256_mullo_epi32(z0, sz), z1 = _mm256_mullo_epi32(z1, sz);
	__m256i zy[4] = {_mm256_add_epi32(z0, y0), _mm256_add_epi32(z0, y1),
			 _mm256_add_epi32(z1, y0), _mm256_add_epi32(z1, y1)};
	for (int k = 0; k < 8; k++)
		c->off[k] = _mm256_slli_epi32(_mm256_add_epi32(zy[k >> 1], k & 1 ? x1 : x0), 2);
}

static inline __m256 lerp3_8(const __m256 q[8], const struct corners8 *c)
{
	__m256 c00 = _mm256_add_ps(q[0], _mm256_mul_ps(c->tx, _mm256_sub_ps(q[1], q[0])));
	__m256 c10 = _mm256_add_ps(q[2], _mm256_mul_ps(c->tx, _mm256_sub_ps(q[3], q[2])));
	__m256 c01 = _mm256_add_ps(q[4], _mm256_mul_ps(c->tx, _mm256_sub_ps(q[5], q[4])));
	__m256 c11 = _mm256_add_ps(q[6], _mm256_mul_ps(c->tx, _mm256_sub_ps(q[7], q[6])));
	__m256 c0 = _mm256_add_ps(c00, _mm256_mul_ps(c->ty, _mm256_sub_ps(c10, c00)));
	__m256 c1 = _mm256_add_ps(c01, _mm256_mul_ps(c->ty, _mm256_sub_ps(c11, c01)));
	return _mm256_add_ps(c0, _mm256_mul_ps(c->tz, _mm256_sub_ps(c1, c0)));
}

/* volume.c's trilinear() of channel 0 (the base shape) at the lanes'
 * corners */
static inline __m256 trilinear8_r(const struct cs_volume *v, const struct corners8 *c)
{
	const float *d = v->data;
	__m256 q[8];
	for (int k = 0; k < 8; k++) {
		int o[8];
		_mm256_storeu_si256((__m256i *)o, c->off[k]);
		q[k] = _mm256_setr_ps(d[o[0]], d[o[1]], d[o[2]], d[o[3]], d[o[4]], d[o[5]], d[o[6]],
				      d[o[7]]);
	}
	return lerp3_8(q, c);
}

/* trilinear8 of channels 1, 2 and 3 (the detail): each voxel's four
 * channels in one load, turned into channels across lanes */
static inline void trilinear8_gba(const struct cs_volume *v, const struct corners8 *c,
				  __m256 g[3])
{
	const float *d = v->data;
	__m256 q[3][8];
	for (int k = 0; k < 8; k++) {
		int o[8];
		_mm256_storeu_si256((__m256i *)o, c->off[k]);
		__m128 r0 = _mm_loadu_ps(d + o[0]), r1 = _mm_loadu_ps(d + o[1]);
		__m128 r2 = _mm_loadu_ps(d + o[2]), r3 = _mm_loadu_ps(d + o[3]);
		__m128 r4 = _mm_loadu_ps(d + o[4]), r5 = _mm_loadu_ps(d + o[5]);
		__m128 r6 = _mm_loadu_ps(d + o[6]), r7 = _mm_loadu_ps(d + o[7]);
		_MM_TRANSPOSE4_PS(r0, r1, r2, r3);
		_MM_TRANSPOSE4_PS(r4, r5, r6, r7);
		q[0][k] = _mm256_set_m128(r5, r1);
		q[1][k] = _mm256_set_m128(r6, r2);
		q[2][k] = _mm256_set_m128(r7, r3);
	}
	for (int ch = 0; ch < 3; ch++)
		g[ch] = lerp3_8(q[ch], c);
}

/* Points x[0..7]: out[] for each, 0 or the density. */
static void extinction8(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			const double *x, const double *y, const double *alt_m, double *out)
{
	__m512d X = _mm512_loadu_pd(x), Y = _mm512_loadu_pd(y), A = _mm512_loadu_pd(alt_m);
	__m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
	__m512d H = _mm512_div_pd(_mm512_sub_pd(A, _mm512_set1_pd(l->base_m)),
				  _mm512_set1_pd(l->top_m - l->base_m));
	__mmask8 live = _mm512_cmp_pd_mask(H, zero, _CMP_GE_OQ) & _mm512_cmp_pd_mask(H, one, _CMP_LE_OQ);
	__m512d thr = _mm512_set1_pd(l->threshold);
	__m512d wx = _mm512_set1_pd(l->wind_x), wy = _mm512_set1_pd(l->wind_y);
	__m512d along = _mm512_sub_pd(_mm512_add_pd(_mm512_mul_pd(X, wx), _mm512_mul_pd(Y, wy)),
				      _mm512_set1_pd(l->offset_along_m));
	__m512d negx = _mm512_xor_pd(X, _mm512_set1_pd(-0.0));
	__m512d across = _mm512_sub_pd(_mm512_add_pd(_mm512_mul_pd(negx, wy), _mm512_mul_pd(Y, wx)),
				       _mm512_set1_pd(l->offset_across_m));
	__m512d U = _mm512_mul_pd(along, _mm512_set1_pd(l->inv_tile_along));
	__m512d V = _mm512_mul_pd(across, _mm512_set1_pd(l->inv_tile));
	__m512d W = _mm512_mul_pd(A, _mm512_set1_pd(l->inv_tile_z));
	__m512d up = one, down = one;
	if (l->ramp_inv[0] > 0.0)
		up = smooth01_8(_mm512_mul_pd(_mm512_sub_pd(H, _mm512_set1_pd(l->ramp[0])),
					      _mm512_set1_pd(l->ramp_inv[0])));
	if (l->ramp_inv[1] > 0.0)
		down = _mm512_sub_pd(one, smooth01_8(_mm512_mul_pd(
						  _mm512_sub_pd(H, _mm512_set1_pd(l->ramp[2])),
						  _mm512_set1_pd(l->ramp_inv[1]))));
	__m512d prof = _mm512_mul_pd(up, down);
	if (l->anvil > 0.0) {
		__m512d s8 = smooth01_8(_mm512_div_pd(_mm512_sub_pd(H, _mm512_set1_pd(0.78)),
						      _mm512_set1_pd(0.1)));
		__m512d t = _mm512_sub_pd(thr, _mm512_mul_pd(_mm512_mul_pd(_mm512_set1_pd(l->anvil * 0.3), s8),
							     _mm512_sub_pd(one, thr)));
		thr = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(H, _mm512_set1_pd(0.78), _CMP_GT_OQ), thr, t);
	}
	__m512d nx = _mm512_set1_pd((double)noise->nx), ny = _mm512_set1_pd((double)noise->ny);
	__m512d nz = _mm512_set1_pd((double)noise->nz), half = _mm512_set1_pd(0.5);
	__m512d gx = _mm512_sub_pd(_mm512_mul_pd(U, nx), half);
	__m512d gy = _mm512_sub_pd(_mm512_mul_pd(V, ny), half);
	if (l->bound_n > 0 && live) {
		__m512d lim = _mm512_set1_pd(0x1p30);
		__mmask8 in = _mm512_cmp_pd_mask(W, _mm512_set1_pd(l->bound_w0), _CMP_GE_OQ) &
			      _mm512_cmp_pd_mask(W, _mm512_set1_pd(l->bound_w1), _CMP_LE_OQ) &
			      _mm512_cmp_pd_mask(_mm512_abs_pd(U), lim, _CMP_LT_OQ) &
			      _mm512_cmp_pd_mask(_mm512_abs_pd(V), lim, _CMP_LT_OQ);
		__m256i m = _mm256_set1_epi32(l->bound_n - 1);
		__m128i sh = _mm_cvtsi32_si128(l->bound_shift);
		__m256i ci = _mm256_and_si256(_mm256_srl_epi32(low32_8(_mm512_floor_pd(gx)), sh), m);
		__m256i cj = _mm256_and_si256(_mm256_srl_epi32(low32_8(_mm512_floor_pd(gy)), sh), m);
		__m256i cell = _mm256_add_epi32(_mm256_mullo_epi32(cj, _mm256_set1_epi32(l->bound_n)), ci);
		int c[8], bv[8];
		_mm256_storeu_si256((__m256i *)c, cell);
		for (int k = 0; k < 8; k++)
			bv[k] = l->bound[c[k]];
		__m512d b = _mm512_cvtepi32_pd(_mm256_loadu_si256((const __m256i *)bv));
		__mmask8 empty = _mm512_cmp_pd_mask(b, _mm512_set1_pd(255.0), _CMP_LT_OQ) &
				 _mm512_cmp_pd_mask(_mm512_mul_pd(_mm512_mul_pd(b, _mm512_set1_pd(1.0 / 255.0)), prof),
						    thr, _CMP_LE_OQ);
		live &= (__mmask8)~(in & empty);
	}
	_mm512_storeu_pd(out, zero);
	if (live == 0)
		return;
	__mmask8 fast = small8(U, V, W) & live;
	__m512d gz = _mm512_sub_pd(_mm512_mul_pd(W, nz), half);
	struct corners8 cb;
	corners8(noise, _mm512_maskz_mov_pd(fast, gx), _mm512_maskz_mov_pd(fast, gy),
		 _mm512_maskz_mov_pd(fast, gz), &cb);
	__m512d shape = _mm512_mul_pd(_mm512_cvtps_pd(trilinear8_r(noise, &cb)), prof);
	__mmask8 cloud = _mm512_cmp_pd_mask(shape, thr, _CMP_NLE_UQ) & fast;
	__m512d du = _mm512_mul_pd(along, _mm512_set1_pd(l->inv_detail_along));
	__m512d dv = _mm512_mul_pd(across, _mm512_set1_pd(l->inv_detail));
	__m512d dw = _mm512_mul_pd(A, _mm512_set1_pd(l->inv_detail));
	__mmask8 detail = small8(du, dv, dw) & cloud;
	if (detail) {
		__m512d hx = _mm512_maskz_mov_pd(detail, _mm512_sub_pd(_mm512_mul_pd(du, nx), half));
		__m512d hy = _mm512_maskz_mov_pd(detail, _mm512_sub_pd(_mm512_mul_pd(dv, ny), half));
		__m512d hz = _mm512_maskz_mov_pd(detail, _mm512_sub_pd(_mm512_mul_pd(dw, nz), half));
		struct corners8 cd;
		corners8(noise, hx, hy, hz, &cd);
		__m256 gba[3];
		trilinear8_gba(noise, &cd, gba);
		__m512d g1 = _mm512_cvtps_pd(gba[0]), g2 = _mm512_cvtps_pd(gba[1]);
		__m512d g3 = _mm512_cvtps_pd(gba[2]);
		__m512d det = _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(_mm512_set1_pd(0.625), g1),
							  _mm512_mul_pd(_mm512_set1_pd(0.25), g2)),
					    _mm512_mul_pd(_mm512_set1_pd(0.125), g3));
		__m512d e = _mm512_mul_pd(_mm512_set1_pd(l->erosion), det);
		__m512d omt = _mm512_sub_pd(one, thr);
		__m512d num = _mm512_sub_pd(_mm512_sub_pd(shape, thr), _mm512_mul_pd(e, omt));
		__m512d den = _mm512_mul_pd(
			_mm512_mul_pd(omt, _mm512_add_pd(_mm512_sub_pd(one, e), _mm512_set1_pd(1e-9))),
			_mm512_set1_pd(l->edge));
		__m512d d = _mm512_min_pd(_mm512_div_pd(num, den), one);
		d = _mm512_mul_pd(d, _mm512_set1_pd(l->extinction_per_m));
		__mmask8 pos = _mm512_cmp_pd_mask(num, zero, _CMP_NLE_UQ) & detail;
		_mm512_storeu_pd(out, _mm512_maskz_mov_pd(pos, d));
	}
	unsigned slow = (unsigned)((live & ~fast) | (cloud & ~detail)) & 0xffu;
	if (slow == 0)
		return;
	struct lanes ln;
	_mm512_storeu_pd(ln.u, U), _mm512_storeu_pd(ln.v, V), _mm512_storeu_pd(ln.w, W);
	_mm512_storeu_pd(ln.prof, prof), _mm512_storeu_pd(ln.thr, thr);
	_mm512_storeu_pd(ln.along, along), _mm512_storeu_pd(ln.across, across);
	_mm512_storeu_pd(ln.shape, shape);
	finish_lanes(l, noise, &ln, slow, (unsigned)fast, alt_m, out);
}
#endif
#endif

CS_HD void cs_cloud_extinction_n(const struct cs_cloud_layer *l, const struct cs_volume *noise,
				 int n, const double *x, const double *y, const double *alt_m,
				 double *out)
{
	int i = 0;
#if defined(__AVX2__) && !defined(__CUDA_ARCH__)
	if (batch4_ok(l, noise)) {
#if defined(__AVX512F__) && defined(__AVX512VL__) && defined(__AVX512DQ__)
		for (; i + 8 <= n; i += 8)
			extinction8(l, noise, x + i, y + i, alt_m + i, out + i);
#endif
		for (; i + 4 <= n; i += 4)
			extinction4(l, noise, x + i, y + i, alt_m + i, out + i);
		if (i < n) { /* the last few, with lanes outside the layer */
			double px[4] = {0.0}, py[4] = {0.0}, pa[4], po[4];
			for (int k = 0; k < 4; k++)
				pa[k] = i + k < n ? alt_m[i + k] : NAN;
			for (int k = 0; i + k < n; k++)
				px[k] = x[i + k], py[k] = y[i + k];
			extinction4(l, noise, px, py, pa, po);
			for (; i < n; i++)
				out[i] = po[i & 3];
		}
	}
#endif
	for (; i < n; i++)
		out[i] = cs_cloud_extinction(l, noise, x[i], y[i], alt_m[i]);
}

/* The coverage bound (struct cs_cloud_layer): for a power-of-two volume
 * of side nx, bound_n = min(nx, CS_CLOUD_BOUND_MAX) cells a side, each
 * k = nx / bound_n voxels wide.  A point's trilinear lookup reads voxels
 * ix and ix + 1 (wrapped), ix = floor(u nx - 0.5); its cell is ix / k, so
 * cell c's lookups read voxels c k .. c k + k.  Along w, the voxels the
 * layer's altitudes read.  Rounded up to 1/255 with a margin for the
 * float rounding of the trilinear sum; 255 where it would be above 254/255
 * (a volume of values above 1 has no bound there). */
static void build_bound(struct cs_cloud_layer *l, const struct cs_volume *noise)
{
	l->bound_n = 0;
	if (noise == NULL || noise->data == NULL || noise->nx != noise->ny ||
	    (noise->nx & (noise->nx - 1)) != 0 || !(l->top_m > l->base_m))
		return;
	int nx = noise->nx, nz = noise->nz, n = nx < CS_CLOUD_BOUND_MAX ? nx : CS_CLOUD_BOUND_MAX;
	int k = nx / n, shift = 0;
	while ((1 << shift) < k)
		shift++;
	double w0 = l->base_m * l->inv_tile_z, w1 = l->top_m * l->inv_tile_z;
	double z0 = floor(w0 * nz - 0.5), z1 = floor(w1 * nz - 0.5) + 1.0;
	if (!(z1 - z0 < 4.0 * nz)) /* a layer many tiles tall: no bound worth it */
		return;
	for (int j = 0; j < n; j++)
		for (int i = 0; i < n; i++) {
			float most = 0.0f;
			int nan = 0;
			for (double z = z0; z <= z1; z++) {
				long iz = (long)(z - nz * floor(z / nz));
				for (int y = j * k; y <= j * k + k; y++)
					for (int x = i * k; x <= i * k + k; x++) {
						size_t at = (((size_t)iz * nx + (size_t)(y % nx)) * nx +
							     (size_t)(x % nx)) * 4u;
						float r = noise->data[at];
						nan |= r != r;
						most = r > most ? r : most;
					}
			}
			/* 255: above 254/255 (or not a number), no bound */
			double q = nan ? 255.0 : ceil((double)most * (1.0 + 1e-6) * 255.0);
			l->bound[j * n + i] = (unsigned char)(!(q < 255.0) ? 255.0 : q < 0.0 ? 0.0 : q);
		}
	l->bound_n = n;
	l->bound_shift = shift;
	l->bound_w0 = w0;
	l->bound_w1 = w1;
}

CS_HD CS_SHARED double cs_cloud_column(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			     double x, double y, double z0_m, double z1_m, int steps)
{
#ifdef __CUDA_ARCH__
	enum { B = 1 }; /* a GPU thread one point at a time (march.h's CS_MARCH_BATCH) */
#else
	enum { B = 8 };
#endif
	double dz = (z1_m - z0_m) / steps, tau = 0.0;
	if (!(dz > 0.0))
		return 0.0;
	double px[B], py[B], pz[B], e[B];
	for (int b = 0; b < B; b++)
		px[b] = x, py[b] = y;
	for (int k0 = 0; k0 < steps; k0 += B) {
		int m = steps - k0 < B ? steps - k0 : B;
		for (int b = 0; b < m; b++)
			pz[b] = z0_m + (k0 + b + 0.5) * dz;
		cs_cloud_extinction_n(l, noise, m, px, py, pz, e);
		for (int b = 0; b < m; b++)
			tau += e[b] * dz;
	}
	return tau;
}

/* Fraction of a grid over one whole base tile (the field's period), at the
 * middle of the profile's plateau, that is cloud. */
enum { CAL_N = 48 };
static double covered_fraction(const struct cs_cloud_layer *l,
			       const struct cs_volume *noise, double thr)
{
	double h = 0.5 * (l->ramp[1] + l->ramp[2]);
	double alt = l->base_m + h * (l->top_m - l->base_m);
	int in = 0;
	for (int j = 0; j < CAL_N; j++)
		for (int i = 0; i < CAL_N; i++)
			in += extinction_aw(l, noise, (i + 0.5) / CAL_N * l->stretch / l->inv_tile,
					    (j + 0.5) / CAL_N / l->inv_tile, alt, h, thr) > 0.0;
	return (double)in / (CAL_N * CAL_N);
}

/* Coverage c is the fraction of the layer's core that is cloud: the
 * threshold is found by bisection (the covered fraction falls as the
 * threshold rises), after erosion, so what the forecast says is what is
 * drawn.  At c = 0 the threshold is above any value: no cloud at all. */
static double calibrate_coverage(const struct cs_cloud_layer *l,
				 const struct cs_volume *noise, double coverage)
{
	if (coverage <= 0.0 || noise == NULL)
		return 2.0;
	double lo = -3.0, hi = 1.0; /* fraction(lo) ~ 1, fraction(hi) = 0 */
	for (int it = 0; it < 24; it++) {
		double mid = 0.5 * (lo + hi);
		if (covered_fraction(l, noise, mid) > coverage)
			lo = mid;
		else
			hi = mid;
	}
	return lo; /* the last threshold covering at least the coverage */
}

/* The mean vertical optical depth of the layer's cloudy columns, over a
 * grid on one base tile. */
enum { TAU_N = 24, TAU_STEPS = 24 };
static double mean_tau_in(const struct cs_cloud_layer *l, const struct cs_volume *noise)
{
	double dz = (l->top_m - l->base_m) / TAU_STEPS, sum = 0.0;
	int cloudy = 0;
	for (int j = 0; j < TAU_N; j++)
		for (int i = 0; i < TAU_N; i++) {
			double along = (i + 0.5) / TAU_N * l->stretch / l->inv_tile;
			double across = (j + 0.5) / TAU_N / l->inv_tile, tau = 0.0;
			for (int k = 0; k < TAU_STEPS; k++) {
				double h = (k + 0.5) / TAU_STEPS;
				tau += extinction_aw(l, noise, along, across,
						     l->base_m + h * (l->top_m - l->base_m), h,
						     l->threshold) * dz;
			}
			if (tau > 0.0)
				sum += tau, cloudy++;
		}
	return cloudy ? sum / cloudy : 0.0;
}

static void calibrate(struct cs_cloud_layer *l, const struct cs_volume *noise)
{
	l->threshold = calibrate_coverage(l, noise, l->coverage);
	double target = cs_genus_preset(l->genus)->tau_in;
	if (target > 0.0 && noise != NULL && l->coverage > 0.0) {
		double tau = mean_tau_in(l, noise);
		if (tau > 0.0)
			l->extinction_per_m *= target / tau;
	}
}

void cs_cloud_layer_blend(struct cs_cloud_layer *l, const struct cs_volume *noise,
			  int site, int nfar, const double *far_x, const double *far_y)
{
	l->site = site;
	l->nfar = nfar < CS_WX_MAX_FAR ? nfar : CS_WX_MAX_FAR;
	for (int f = 0; f < l->nfar; f++) {
		double d2 = far_x[f] * far_x[f] + far_y[f] * far_y[f];
		d2 = d2 > 1.0 ? d2 : 1.0;
		l->far_ux[f] = far_x[f] / d2;
		l->far_uy[f] = far_y[f] / d2;
	}
	for (int k = 0; k <= CS_BLEND_LEVELS; k++)
		l->thr_table[k] = k == CS_BLEND_LEVELS
					  ? l->threshold
					  : calibrate_coverage(l, noise, l->coverage * k / CS_BLEND_LEVELS);
}

CS_HD double cs_cloud_site_weight(const struct cs_cloud_layer *l, double x, double y)
{
	if (l->nfar <= 0)
		return 1.0;
	double w[CS_WX_MAX_FAR], sum = 0.0;
	for (int f = 0; f < l->nfar; f++) {
		double p = x * l->far_ux[f] + y * l->far_uy[f];
		w[f] = p < 0.0 ? 0.0 : p > 1.0 ? 1.0 : p;
		sum += w[f];
	}
	double scale = sum > 1.0 ? 1.0 / sum : 1.0;
	if (l->site < 0)
		return 1.0 - sum * scale;
	return w[l->site] * scale;
}
