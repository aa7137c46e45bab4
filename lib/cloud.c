#include "cloud.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Extinction of cloud: liquid water clouds have 10..100 droplets per cm^3,
 * giving 0.01..0.1 /m in the visible (mean free paths of 10..100 m); ice
 * clouds are 10..100 times thinner.  Tile sizes set the size of cells: a
 * base tile holds 4 lattice cells of the default noise recipe.  The base
 * tile is tall (tile_z several times the layer) so that the base shape is
 * nearly a 2D coverage map through the layer: coverage is then the
 * fraction of the sky covered, and the height profile rounds the tops. */
static const struct cs_genus_preset presets[CS_GENUS_COUNT] = {
	[CS_CIRRUS] = {0.005, 20000, 60000, 2500, 0.45, 6.0,
		       {0.0, 0.3, 0.5, 1.0}, 0.0, 0.4, 8000, 10000},
	[CS_CIRROCUMULUS] = {0.004, 4000, 30000, 800, 0.35, 1.2,
			     {0.0, 0.3, 0.7, 1.0}, 0.0, 0.3, 7000, 7600},
	[CS_CIRROSTRATUS] = {0.0008, 40000, 80000, 6000, 0.15, 2.0,
			     {0.0, 0.15, 0.85, 1.0}, 0.0, 0.8, 7500, 9000},
	[CS_ALTOCUMULUS] = {0.02, 6000, 30000, 1200, 0.35, 1.3,
			    {0.0, 0.25, 0.6, 1.0}, 0.0, 0.2, 3000, 3800},
	[CS_ALTOSTRATUS] = {0.006, 30000, 60000, 5000, 0.1, 1.5,
			    {0.0, 0.1, 0.9, 1.0}, 0.0, 0.7, 3000, 5000},
	[CS_NIMBOSTRATUS] = {0.025, 30000, 60000, 4000, 0.08, 1.2,
			     {0.0, 0.05, 0.85, 1.0}, 0.0, 0.5, 800, 4000},
	[CS_STRATOCUMULUS] = {0.03, 9000, 30000, 1500, 0.25, 1.3,
			      {0.0, 0.2, 0.65, 1.0}, 0.0, 0.25, 800, 1500},
	[CS_STRATUS] = {0.02, 30000, 60000, 3000, 0.08, 1.2,
			{0.0, 0.1, 0.9, 1.0}, 0.0, 0.6, 300, 800},
	[CS_CUMULUS] = {0.05, 8000, 20000, 1500, 0.35, 1.0,
			{0.0, 0.06, 0.45, 1.0}, 0.0, 0.12, 1500, 2700},
	[CS_CUMULONIMBUS] = {0.07, 20000, 40000, 2500, 0.25, 1.0,
			     {0.0, 0.03, 0.8, 1.0}, 0.8, 0.12, 1000, 11000},
};

const struct cs_genus_preset *cs_genus_preset(enum cs_genus g)
{
	return (unsigned)g < CS_GENUS_COUNT ? &presets[g] : &presets[CS_CUMULUS];
}

static int cmp_float(const void *a, const void *b)
{
	float x = *(const float *)a, y = *(const float *)b;
	return (x > y) - (x < y);
}

void cs_noise_stats_compute(const struct cs_volume *v, struct cs_noise_stats *st)
{
	size_t n = (size_t)v->nx * v->ny * v->nz;
	/* a fixed stride subsample: at most 2^18 values, deterministic */
	size_t stride = n > (1u << 18) ? n / (1u << 18) : 1;
	size_t m = (n + stride - 1) / stride;
	float *vals = malloc(m * sizeof *vals);
	if (vals == NULL) { /* degrade to the nominal range */
		for (int i = 0; i <= CS_QUANTILES; i++)
			st->q[i] = (float)i / CS_QUANTILES;
		return;
	}
	for (size_t i = 0; i < m; i++)
		vals[i] = v->data[i * stride * 4];
	qsort(vals, m, sizeof *vals, cmp_float);
	for (int i = 0; i <= CS_QUANTILES; i++)
		st->q[i] = vals[(size_t)((double)i / CS_QUANTILES * (double)(m - 1) + 0.5)];
	free(vals);
}

static double quantile(const struct cs_noise_stats *st, double u)
{
	double x = u * CS_QUANTILES;
	int i = (int)x;
	if (i >= CS_QUANTILES)
		return st->q[CS_QUANTILES];
	if (i < 0)
		return st->q[0];
	return st->q[i] + (x - i) * (st->q[i + 1] - st->q[i]);
}

void cs_cloud_layer_init(struct cs_cloud_layer *l, const struct cs_wx_layer *wl,
			 const struct cs_noise_stats *st, double wind_speed_m_s,
			 double wind_from_deg, double ground_alt_m, double time_s)
{
	const struct cs_genus_preset *p = cs_genus_preset(wl->genus);
	memset(l, 0, sizeof *l);
	l->kind = CS_LAYER_CLOUD;
	l->genus = wl->genus;
	l->base_m = wl->base_m;
	l->top_m = wl->top_m;
	l->coverage = wl->coverage;
	/* Coverage c puts the threshold at the (1 - c) quantile of the base
	 * shape, so c is the fraction of the layer's core that is cloud.  At
	 * c = 0 the threshold is the maximum: no cloud at all. */
	l->threshold = quantile(st, 1.0 - wl->coverage);
	if (wl->coverage <= 0.0)
		l->threshold = 2.0; /* above any value: not even the maximum voxel */
	l->extinction_per_m = p->extinction_per_m;
	l->inv_tile = 1.0 / p->tile_m;
	l->inv_tile_z = 1.0 / p->tile_z_m;
	l->inv_detail = 1.0 / p->detail_tile_m;
	l->stretch = p->stretch;
	l->erosion = p->erosion;
	l->anvil = p->anvil;
	l->edge = p->edge;
	memcpy(l->ramp, p->ramp, sizeof l->ramp);

	double from = wind_from_deg * (CS_PI / 180.0);
	l->wind_x = -sin(from); /* blowing toward the opposite direction */
	l->wind_y = -cos(from);
	double mid = 0.5 * (wl->base_m + wl->top_m) - ground_alt_m;
	double factor = pow(fmax(mid, 10.0) / 10.0, 1.0 / 7.0);
	factor = factor > 3.0 ? 3.0 : factor;
	/* The noise tiles, so the distance travelled only matters modulo the
	 * (stretched) tile: reducing it here keeps coordinates small and exact
	 * for any date. */
	double along_tile = p->tile_m * p->stretch;
	double travelled = fmod(wind_speed_m_s * factor * time_s, along_tile);
	l->offset_along_m = isfinite(travelled) ? travelled : 0.0;
	l->offset_across_m = 0.0;
}

static inline double smooth01(double x)
{
	x = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
	return x * x * (3.0 - 2.0 * x);
}

/* The genus height profile: a smooth trapezoid over the relative height. */
static inline double profile(const double r[4], double h)
{
	double up = r[1] > r[0] ? smooth01((h - r[0]) / (r[1] - r[0])) : 1.0;
	double down = r[3] > r[2] ? 1.0 - smooth01((h - r[2]) / (r[3] - r[2])) : 1.0;
	return up * down;
}

double cs_cloud_extinction(const struct cs_cloud_layer *l,
			   const struct cs_volume *noise, double x, double y,
			   double alt_m)
{
	double h = (alt_m - l->base_m) / (l->top_m - l->base_m);
	if (!(h >= 0.0 && h <= 1.0))
		return 0.0;
	if (l->kind == CS_LAYER_HOMOGENEOUS)
		return fmax(0.0, l->homog_a + l->homog_b * h);

	/* coordinates along and across the wind, moved by it */
	double along = x * l->wind_x + y * l->wind_y - l->offset_along_m;
	double across = -x * l->wind_y + y * l->wind_x - l->offset_across_m;
	double u = along / l->stretch * l->inv_tile, v = across * l->inv_tile;
	double w = alt_m * l->inv_tile_z;

	double shape = cs_volume_sample(noise, 0, u, v, w) * profile(l->ramp, h);
	/* an anvil spreads the top: the threshold drops toward the top */
	double thr = l->threshold;
	if (l->anvil > 0.0 && h > 0.6)
		thr -= l->anvil * 0.35 * smooth01((h - 0.6) / 0.3) * (1.0 - thr);
	if (shape <= thr)
		return 0.0;
	double d = (shape - thr) / (1.0 - thr); /* 0 at the edge, 1 at the core */

	/* Erosion by the detail fBm carves the edge into billows: the cloud's
	 * surface is where d equals the local erosion, not where d is 0. */
	double du = along / l->stretch * l->inv_detail, dv = across * l->inv_detail;
	double dw = alt_m * l->inv_detail;
	float g[4];
	cs_volume_sample4(noise, du, dv, dw, g);
	double detail = 0.625 * g[1] + 0.25 * g[2] + 0.125 * g[3];
	double e = l->erosion * detail;
	d = (d - e) / (1.0 - e + 1e-9);
	if (d <= 0.0)
		return 0.0;
	/* then the density rises over a band of width edge: narrow for
	 * sharp-edged heaps, wide for veils */
	d /= l->edge;
	d = d < 1.0 ? d : 1.0;
	return d * l->extinction_per_m;
}
