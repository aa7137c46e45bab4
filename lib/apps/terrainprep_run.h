/* terrainprep.h - the terrainprep program as a library call: any DEM GDAL
 * reads -> a metric, north-up heightfield (see terrain.h).  The GDAL part
 * (opening, CRSs, warping) is terrain/reproject.h; this is the flow. */
#ifndef CS_TERRAINPREP_H
#define CS_TERRAINPREP_H

#include "terrain/terrain.h"
#include "terrain/reproject.h"

#define CS_TERRAINPREP_MAX_INPUTS 4096
#define CS_TERRAINPREP_MAX_SAMPLES CS_REPROJECT_MAX_SAMPLES
/* format: chosen from the output's extension (.exr, .r16/.raw, .tif/.tiff;
 * EXR for a name without one; any other extension is an error) */
#define CS_TERRAINPREP_FORMAT_AUTO (-1)

enum cs_fill { CS_FILL_NEAREST, CS_FILL_NONE, CS_FILL_VALUE };

struct cs_terrainprep_opts {
	const char **inputs;      /* DEM files, "-" = standard input (once) */
	int ninputs;
	const char *stdin_name;   /* name "-" is opened under (drivers such as
				   * SRTMHGT take georeferencing from it) */
	const char *output;       /* data file; the sidecar goes beside it */
	int format;               /* enum cs_terrain_format, or ..._FORMAT_AUTO */
	const char *s_srs, *t_srs;/* any form GDAL accepts (EPSG:n, WKT, PROJ) */
	int have_center;
	double center_lat, center_lon, radius_km;  /* square crop */
	int have_bounds;
	double bounds[4];         /* xmin, ymin, xmax, ymax */
	const char *bounds_srs;   /* CRS of bounds; NULL: the target CRS */
	double res_m;             /* > 0: pixel size */
	int size_long;            /* > 0: samples along the longer side */
	int size_w, size_h;       /* > 0: exactly these samples */
	int size_unity;           /* square 2^n+1, 33..4097 (Unity terrain) */
	const char *resampling;   /* NULL: bilinear, average when shrinking > 2x */
	int have_src_nodata;
	int src_nodata_none;      /* ignore the file's nodata */
	double src_nodata;
	enum cs_fill fill;
	double fill_value;
	double max_void_fraction; /* more voids than this is an error */
	int r16_south_up;
	const char *hillshade;    /* PNG path, or NULL */
	int no_clobber;           /* never replace an existing file */
	double azimuth_deg, altitude_deg, z_factor, scale;
	int have_water_level;
	double water_level_m;     /* samples at or below this height are water */
	const char *water_mask;   /* raster GDAL reads: non-zero is water */
	cs_progress_fn progress;
	void *progress_user;
};

/* What a run produced. */
struct cs_terrainprep_result {
	struct cs_terrain terrain; /* freed by cs_terrainprep_result_free() */
	enum cs_terrain_format format; /* of the data file written */
	long voids;                /* void samples found */
	char resampling_used[16];
	char warning[2048];        /* GDAL's warnings and ours, one a line, or "" */
};

/* Defaults: format from the output's name, fill nearest, 50% voids
 * allowed, stdin name "stdin",
 * hillshade sun at azimuth 315, altitude 45, z-factor 1, scale 1. */
void cs_terrainprep_defaults(struct cs_terrainprep_opts *o);

/* Reads, mosaics, reprojects, crops, resamples, fills and writes.  Option
 * mistakes (a bad CRS, crop or size) return CS_EINVAL; the data's
 * problems (unreadable input, no CRS without s_srs, too many voids)
 * CS_EDATA; the system's CS_EIO. */
int cs_terrainprep_run(const struct cs_terrainprep_opts *o,
		       struct cs_terrainprep_result *r);
void cs_terrainprep_result_free(struct cs_terrainprep_result *r);

/* terrainprep --info: a heightfield (EXR and sidecar) described in the
 * --info style (core/info.h): size, CRS, pixel size in CRS units and on
 * the ground (great-circle distance along the grid's edges over the
 * samples between them), the WGS84 bounds of the outer edges, min/max/mean
 * height, the voids the source had and how they were filled, the water.
 * *text is malloc'ed for the caller. */
int cs_terrainprep_info(const char *path, int json, char **text);

/* The format a name means: "exr", "r16" or "raw", "tif" or "tiff" (any
 * case); CS_EINVAL for any other. */
int cs_terrainprep_format(const char *name, enum cs_terrain_format *f);

#endif
