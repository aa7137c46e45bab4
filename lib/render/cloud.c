#include "render/cloud.h"
#include "weather/genus_rules.h"

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
	double e = factor * east_m, n = factor * north_m;
	/* the offsets in the field's axes, reduced by its periods there */
	l->offset_along_m = reduce_period(e * l->wind_x + n * l->wind_y, wind_period_m(p));
	l->offset_across_m = reduce_period(-e * l->wind_y + n * l->wind_x, across_period_m(p));
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

/* The extinction at coordinates along and across the wind (already moved
 * by it), at altitude alt_m and relative height h in [0, 1]. */
CS_HD static double extinction_aw(const struct cs_cloud_layer *l,
			    const struct cs_volume *noise, double along,
			    double across, double alt_m, double h, double thr)
{
	double u = along * l->inv_tile_along, v = across * l->inv_tile;
	double w = alt_m * l->inv_tile_z;

	double prof = profile(l->ramp, l->ramp_inv, h);
	/* an anvil spreads the top fifth: the threshold drops there */
	if (l->anvil > 0.0 && h > 0.78)
		thr -= l->anvil * 0.3 * smooth01((h - 0.78) / 0.1) * (1.0 - thr);
	if (l->bound_n > 0 && w >= l->bound_w0 && w <= l->bound_w1 && fabs(u) < 0x1p30 &&
	    fabs(v) < 0x1p30) {
		/* the cell of the voxel the lookup's trilinear starts at */
		long i = floor_long(u * noise->nx - 0.5) >> l->bound_shift;
		long j = floor_long(v * noise->ny - 0.5) >> l->bound_shift;
		unsigned m = (unsigned)l->bound_n - 1u;
		double b = l->bound[((unsigned long)j & m) * (unsigned)l->bound_n + ((unsigned long)i & m)];
		if (b < 255.0 && b * (1.0 / 255.0) * prof <= thr)
			return 0.0;
	}
	double shape = cs_volume_sample(noise, 0, u, v, w) * prof;
	if (shape <= thr)
		return 0.0;
	/* d = (shape - thr) / (1 - thr): 0 at the edge, 1 at the core.
	 * Erosion by the detail fBm carves the edge into billows: the cloud's
	 * surface is where d equals the local erosion e, not where d is 0,
	 * and the density (d - e) / (1 - e) then rises over a band of width
	 * edge: narrow for sharp-edged heaps, wide for veils.  One division,
	 * and none where the erosion leaves nothing. */
	float g[4];
	cs_volume_sample4(noise, along * l->inv_detail_along, across * l->inv_detail,
			  alt_m * l->inv_detail, g);
	double detail = 0.625 * g[1] + 0.25 * g[2] + 0.125 * g[3];
	double e = l->erosion * detail;
	double num = (shape - thr) - e * (1.0 - thr);
	if (num <= 0.0)
		return 0.0;
	double d = num / ((1.0 - thr) * (1.0 - e + 1e-9) * l->edge);
	d = d < 1.0 ? d : 1.0;
	return d * l->extinction_per_m;
}

CS_HD double cs_cloud_extinction(const struct cs_cloud_layer *l,
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
	double thr = l->threshold;
	if (l->nfar > 0) { /* blended with other sites: the coverage here */
		double w = cs_cloud_site_weight(l, x, y) * CS_BLEND_LEVELS;
		if (w <= 0.0)
			return 0.0;
		int k = (int)w;
		thr = k >= CS_BLEND_LEVELS ? l->thr_table[CS_BLEND_LEVELS]
					   : l->thr_table[k] + (w - k) * (l->thr_table[k + 1] - l->thr_table[k]);
	}
	/* coordinates along and across the wind, moved by it */
	double along = x * l->wind_x + y * l->wind_y - l->offset_along_m;
	double across = -x * l->wind_y + y * l->wind_x - l->offset_across_m;
	return extinction_aw(l, noise, along, across, alt_m, h, thr);
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

CS_HD double cs_cloud_column(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			     double x, double y, double z0_m, double z1_m, int steps)
{
	double dz = (z1_m - z0_m) / steps, tau = 0.0;
	if (!(dz > 0.0))
		return 0.0;
	for (int k = 0; k < steps; k++)
		tau += cs_cloud_extinction(l, noise, x, y, z0_m + (k + 0.5) * dz) * dz;
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
