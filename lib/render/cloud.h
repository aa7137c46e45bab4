/* cloud.h - cloud genera and the density field of a cloud layer.
 *
 * A layer is a spherical shell between two altitudes.  Its density is the
 * noise volume's base shape (channel R) scaled by the genus height profile,
 * thresholded by coverage, eroded by the detail channels (G, B, A) and
 * moved by the wind; it is multiplied by the genus extinction to give an
 * extinction coefficient in 1/m. */
#ifndef CS_CLOUD_H
#define CS_CLOUD_H

#include "core/hd.h"

#include "core/vec.h"
#include "noise/volume.h"
#include "weather/wx.h"

#define CS_BLEND_LEVELS 16
#define CS_CLOUD_BOUND_MAX 64 /* cells of the coverage bound along a tile's side */

/* The look of a genus (see man 1 cloudrender, GENERA). */
struct cs_genus_preset {
	double extinction_per_m;  /* at density 1 */
	double tile_m;            /* horizontal size of one base-noise tile */
	double tile_z_m;          /* vertical size of one base-noise tile */
	double detail_tile_m;     /* size of one detail-noise tile */
	double erosion;           /* 0..1: how much detail eats the edges */
	double stretch;           /* >= 1: elongation along the wind (streaks) */
	double ramp[4];           /* height profile: 0 below ramp[0], rising to 1
				     at ramp[1], 1 until ramp[2], 0 at ramp[3]
				     (fractions of the layer's thickness) */
	double anvil;             /* 0..1: spreading of the top (cumulonimbus) */
	double edge;              /* 0..1: width of the density ramp above the
				     coverage threshold (small = sharp edges) */
	double tau_in;            /* > 0: the mean vertical optical depth of the
				     layer where it has cloud, which the
				     extinction is scaled to reach (the sheets:
				     how much light they let through); 0: the
				     extinction as it is (the heaps and veils of
				     fair weather, tuned by their look) */
};

const struct cs_genus_preset *cs_genus_preset(enum cs_genus g);

enum cs_layer_kind {
	CS_LAYER_CLOUD,       /* noise clouds, as described above */
	CS_LAYER_HOMOGENEOUS, /* extinction a + b * (relative height), within
				 homog_radius_m of (homog_x, homog_y) if that
				 is > 0: analytic cases for tests */
};

/* A layer ready to be sampled.  Plain data: the per-sample code reads it and
 * the noise volume only. */
struct cs_cloud_layer {
	enum cs_layer_kind kind;
	enum cs_genus genus;
	double base_m, top_m;     /* altitude above sea level */
	double coverage;          /* 0..1 */
	double threshold;         /* base-shape value below which there is no cloud
				     (calibrated from the coverage) */
	double extinction_per_m;
	double inv_tile, inv_tile_z, inv_detail; /* 1 / tile sizes, 1/m */
	double stretch, erosion, anvil, edge;
	double ramp[4];
	/* derived by cs_cloud_layer_init: 1 / the ramps' widths (0 where a
	 * ramp has none), and the tiles' reciprocals along the wind, stretched */
	double ramp_inv[2], inv_tile_along, inv_detail_along;
	double wind_x, wind_y;    /* unit vector of the field's along axis (east,
				     north): the way the wind blows */
	double offset_along_m;    /* how far the wind has carried the clouds along
				     and across that axis, reduced modulo the */
	double offset_across_m;   /* field's periods (small for a float build) */
	/* Near and far weather: the layer belongs to the near site (site -1)
	 * or to far site `site`; with far sites its coverage is scaled, point
	 * by point, by its site's weight (see cs_cloud_site_weight). */
	int site, nfar;
	double far_ux[CS_WX_MAX_FAR], far_uy[CS_WX_MAX_FAR]; /* far position / |position|^2 */
	double thr_table[CS_BLEND_LEVELS + 1]; /* threshold at coverage * k / CS_BLEND_LEVELS */
	/* An upper bound of the base shape (noise channel R) over the layer,
	 * so that the many samples in clear air need no noise lookup: cell
	 * (i, j) of a bound_n x bound_n grid over the base tile holds the
	 * largest voxel, rounded up to 1/255, that the trilinear lookup of a
	 * point in it between bound_w0 and bound_w1 (in tiles) reads.  A point
	 * whose bound times the height profile is at most the threshold has
	 * no cloud: cs_cloud_extinction then returns 0 without a lookup, the
	 * same 0 the lookup gives.  bound_n 0: no bound. */
	int bound_n, bound_shift;  /* cells a side; log2 of the voxels a cell */
	double bound_w0, bound_w1;
	unsigned char bound[CS_CLOUD_BOUND_MAX * CS_CLOUD_BOUND_MAX];
	double homog_a, homog_b;  /* CS_LAYER_HOMOGENEOUS only */
	double homog_radius_m, homog_x, homog_y;
};

/* Sets up a layer from a weather layer: its genus preset, coverage and the
 * wind (speed at 10 m, direction it blows from) acting for time_s seconds.
 * Wind aloft is taken as the 10-m wind times (altitude above ground /
 * 10 m)^(1/7), at most 3 times it (a power-law profile).  The coverage
 * threshold is calibrated on the noise so that a fraction coverage of the
 * layer's core is cloud (about 5 ms). */
void cs_cloud_layer_init(struct cs_cloud_layer *l, const struct cs_wx_layer *wl,
			 const struct cs_volume *noise, double wind_speed_m_s,
			 double wind_from_deg, double ground_alt_m, double time_s);

/* Moves an initialised layer by a weather state's drift instead (cloudwx/2:
 * see struct cs_wx_drift): the field's along axis points to compass
 * bearing axis_deg, and the field is carried by (east_m, north_m), the
 * 10-m wind's displacement, times the wind-aloft factor of the genus's
 * typical height above the ground (cs_genus_place; the power law of
 * cs_cloud_layer_init).  The factor and the axis do not follow the
 * layer's current altitude or wind, so a state a minute later shows the
 * same clouds moved by the wind of that minute. */
void cs_cloud_layer_drift(struct cs_cloud_layer *l, double east_m, double north_m,
			  double axis_deg, double ground_alt_m);

/* The periods of layer l's density along and across the wind, m (the
 * least common multiple of its genus's base and detail tiles, stretched
 * along): 1, or 0 where it has none (tiles not whole metres, a
 * homogeneous layer, tiles not its genus's). */
int cs_cloud_periods(const struct cs_cloud_layer *l, double *along_m, double *across_m);

/* A vector of along_m and across_m on layer l's axes (along the wind and
 * across it, as cs_cloud_extinction takes them) in east and north: the
 * rotation only (the field's offsets are the caller's). */
CS_HD static inline void cs_cloud_axes_to_en(const struct cs_cloud_layer *l, double along_m,
					     double across_m, double *east_m, double *north_m)
{
	*east_m = along_m * l->wind_x - across_m * l->wind_y;
	*north_m = along_m * l->wind_y + across_m * l->wind_x;
}

/* The inverse: a vector of east_m and north_m on layer l's axes. */
CS_HD static inline void cs_cloud_en_to_axes(const struct cs_cloud_layer *l, double east_m,
					     double north_m, double *along_m, double *across_m)
{
	*along_m = east_m * l->wind_x + north_m * l->wind_y;
	*across_m = -east_m * l->wind_y + north_m * l->wind_x;
}

/* The wind-aloft factor at height_m above the ground: (height / 10 m)^(1/7),
 * at least 1 and at most 3. */
double cs_cloud_aloft_factor(double height_m);

/* Makes the layer part of a near/far blend: it belongs to site (-1 near,
 * else the far index) among nfar far sites at world positions (far_x,
 * far_y) (the near site is at the origin).  Calibrates a threshold table
 * (about 80 ms). */
void cs_cloud_layer_blend(struct cs_cloud_layer *l, const struct cs_volume *noise,
			  int site, int nfar, const double *far_x, const double *far_y);

/* The weight of the layer's site at (x, y): far site f weighs
 * w_f = clamp(projection of (x, y) on the line from the near site to f, as
 * a fraction of that line, 0, 1); the far weights are scaled to sum to at
 * most 1 and the near site has the rest.  1 without far sites. */
CS_HD double cs_cloud_site_weight(const struct cs_cloud_layer *l, double x, double y);

/* Extinction coefficient (1/m) at local position (x east, y north, metres)
 * and altitude alt_m.  Zero outside the layer.  No allocation, no state. */
CS_HD double cs_cloud_extinction(const struct cs_cloud_layer *l,
			   const struct cs_volume *noise, double x, double y,
			   double alt_m);

/* out[i] = cs_cloud_extinction(l, noise, x[i], y[i], alt_m[i]) for n
 * points, the same bits: where the code is built for AVX2 (the renderer's
 * kernel, cpu/kernel.c), four points at a time.  out must not overlap the
 * inputs. */
CS_HD void cs_cloud_extinction_n(const struct cs_cloud_layer *l, const struct cs_volume *noise,
				 int n, const double *x, const double *y, const double *alt_m,
				 double *out);

/* Vertical optical depth of layer l in the column at (x, y) from altitude
 * z0_m to z1_m: steps midpoint samples (0 when z1_m <= z0_m). */
CS_HD double cs_cloud_column(const struct cs_cloud_layer *l, const struct cs_volume *noise,
			     double x, double y, double z0_m, double z1_m, int steps);

#endif
