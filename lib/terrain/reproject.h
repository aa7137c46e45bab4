/* reproject.h - DEM reprojection with GDAL: opens any DEM GDAL reads (files
 * or standard input), works out the coordinate reference systems (the
 * source's, a metric target: --t-srs, the source's own if projected in
 * metres, else the UTM zone of the centre), and warps, mosaics, crops and
 * resamples the inputs in memory (GDALWarp, the gdalwarp application API)
 * into a north-up grid of heights in metres.  Also georeferences the grid
 * (corners in WGS84) and encodes it as a GeoTIFF.
 *
 * GDAL reports problems through CPLError, and some calls return success
 * after logging one, so every call here pushes a thread-local error handler
 * and treats any CE_Failure it saw as the failure of the step.  Call every
 * function of one handle from the same thread. */
#ifndef CS_REPROJECT_H
#define CS_REPROJECT_H

#include "terrain/terrain.h"
#include "noise/volume.h" /* cs_progress_fn */

#include <stddef.h>

/* Most samples in a warped grid. */
#define CS_REPROJECT_MAX_SAMPLES ((long)1 << 28) /* 16384^2 */
/* A projected CRS whose point scale at the data's centre is further than
 * this from 1 is not taken as metric: its metres are not true metres
 * (Web Mercator: 1/cos(latitude)).  UTM's is 0.1 % within its zone. */
#define CS_REPROJECT_MAX_SCALE_ERROR 0.01

struct cs_reproject_opts {
	const char **inputs;      /* DEM files, "-" = standard input (once) */
	int ninputs;
	const char *stdin_name;   /* name "-" is opened under */
	const char *s_srs, *t_srs;/* any form GDAL accepts, or NULL */
	int have_center;
	double center_lat, center_lon, radius_km;  /* square crop */
	int have_bounds;
	double bounds[4];         /* xmin, ymin, xmax, ymax */
	const char *bounds_srs;   /* CRS of bounds; NULL: the target CRS */
	double res_m;             /* > 0: pixel size */
	int size_long;            /* > 0: samples along the longer side */
	int size_w, size_h;       /* > 0: exactly these samples */
	int size_unity;           /* square 2^n+1, 33..4097 */
	const char *resampling;   /* NULL: bilinear, average when shrinking > 2x */
	int have_src_nodata;
	int src_nodata_none;      /* ignore the files' nodata */
	double src_nodata;
	cs_progress_fn progress;  /* of the warp, or NULL */
	void *progress_user;
};

/* One reprojection's GDAL state: the open inputs and the chosen CRSs. */
struct cs_reproject;

/* Whether name is one of gdalwarp's resampling methods ("bilinear", ...). */
int cs_reproject_resampling_known(const char *name);

/* Parses the CRS options, opens the inputs and chooses the target CRS and
 * the crop.  A bad CRS option is CS_EINVAL; an unreadable input, or one
 * without georeferencing or (without s_srs) a CRS, CS_EDATA.  *out is
 * allocated even on failure (free it with cs_reproject_free). */
int cs_reproject_open(const struct cs_reproject_opts *o, struct cs_reproject **out);

/* Warps to the target grid: t->h (malloc'ed, NaN = void), t->width,
 * t->height.  resampling gets the method used.  A grid over
 * CS_REPROJECT_MAX_SAMPLES is CS_EINVAL. */
int cs_reproject_warp(struct cs_reproject *rp, struct cs_terrain *t,
		      char *resampling, size_t size);

/* Georeferences the warped grid in t: origin, pixel size, EPSG code,
 * crs_wkt (malloc'ed), corners and centre in WGS84. */
int cs_reproject_georeference(struct cs_reproject *rp, struct cs_terrain *t);

/* t as a DEFLATE Float32 GeoTIFF in memory; NaN marked as nodata when
 * nan_nodata.  *bytes stay valid until the next call or cs_reproject_free. */
int cs_reproject_geotiff(struct cs_reproject *rp, const struct cs_terrain *t,
			 int nan_nodata, const void **bytes, size_t *len);

/* A water mask (any raster GDAL reads, e.g. a lake polygon rasterised with
 * gdal_rasterize) on the grid of t (after cs_reproject_warp): water[i] 1
 * where the mask's first band is non-zero and not nodata, else 0 (also
 * outside the mask).  Nearest-neighbour; a mask without a CRS is taken to
 * be in the heightfield's.  Unreadable: CS_EDATA. */
int cs_reproject_water_mask(struct cs_reproject *rp, const char *path,
			    const struct cs_terrain *t, float *water);

/* The inputs as the sidecar names them: "a.tif, b.tif", the drivers
 * ("GTiff,AAIGrid"), the source nodata ("-32767", "none"). */
const char *cs_reproject_source(const struct cs_reproject *rp);
const char *cs_reproject_driver(const struct cs_reproject *rp);
const char *cs_reproject_src_nodata(const struct cs_reproject *rp);
/* GDAL's warnings (each once, naming the input being opened when GDAL
 * did not) and ours (a source CRS whose metres are not true metres), one
 * a line, or "". */
const char *cs_reproject_warning(const struct cs_reproject *rp);
/* "GDAL 3.6.2" style release name of the GDAL in use. */
const char *cs_reproject_gdal_version(void);

void cs_reproject_free(struct cs_reproject *rp);

#endif
