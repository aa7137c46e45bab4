/* terrain.h - a metric heightfield and where it lies on the Earth.
 *
 * Written by terrainprep (an EXR of heights plus a JSON sidecar, see
 * man 1 terrainprep), read by cloudrender.  Row 0 is the north edge
 * (north-up); column 0 the west edge.  Heights in metres above the source's
 * vertical datum (sea level for the DEMs we use).  This module needs no
 * GDAL: everything a renderer needs is in the two files. */
#ifndef CS_TERRAIN_H
#define CS_TERRAIN_H

#include <stddef.h>

#define CS_TERRAIN_FORMAT 1 /* the sidecar's "cloudscape_terrain" version */

struct cs_terrain {
	int width, height;        /* samples */
	float *h;                 /* width * height heights, m; no NaN (voids filled) */
	double origin_x, origin_y;/* CRS coordinates of the outer upper-left corner */
	double pixel_x_m, pixel_y_m; /* pixel size, m (both positive) */
	double min_m, max_m;      /* height range */
	int epsg;                 /* EPSG code of the CRS, or 0 if none */
	char *crs_wkt;            /* WKT2 of the CRS (owned) */
	/* WGS84 latitude/longitude (degrees) of the pixel centres of the four
	 * corners - upper-left, upper-right, lower-right, lower-left - and of
	 * the grid's centre: enough for a renderer without GDAL to place the
	 * grid on the sphere (an affine fit is good to metres over ~100 km). */
	double corner_lat[4], corner_lon[4];
	double center_lat, center_lon;
	/* Water (optional): NULL, or width * height values, 1 where the sample
	 * is open water (a lake, the sea), 0 on land; stored as channel "W"
	 * of the EXR and "water" in the sidecar.  Files without it read with
	 * water NULL. */
	float *water;
	double water_level_m;     /* --water-level that made it, NaN if none */
	char water_source[256];   /* the mask file it came from, or "" */
	/* From the sidecar, for terrainprep --info (not needed to render). */
	long voids;               /* void samples the source had; -1 unknown */
	char nodata_policy[160];  /* e.g. "fill=nearest; source nodata -32767" */
};

/* How the data file next to the sidecar is encoded. */
enum cs_terrain_format {
	CS_TERRAIN_EXR,  /* OpenEXR, one 32-bit float channel "Y", metres */
	CS_TERRAIN_R16,  /* raw 16-bit little-endian: h = offset + v * scale */
	CS_TERRAIN_TIF,  /* Float32 GeoTIFF, encoded by the caller */
};

/* What the sidecar records beyond the grid itself (strings may be NULL). */
struct cs_terrain_meta {
	enum cs_terrain_format format;
	const char *source;        /* input file(s) */
	const char *driver;        /* GDAL driver(s) that read them */
	const char *nodata_policy; /* e.g. "fill=nearest" */
	long voids;                /* void samples found (and filled, unless
				    * the policy is "fill=none") */
	const char *resampling;    /* e.g. "bilinear" */
	const char *generator;     /* e.g. "terrainprep 0.1.0 (GDAL 3.6.2)" */
	int r16_south_up;          /* R16: rows from the south edge */
	const void *bytes;         /* TIF: the encoded file */
	size_t nbytes;
};

/* The sidecar's path for a data file: its extension replaced by ".json"
 * (appended if it has none).  Fails if that is the data file itself or
 * does not fit in size bytes. */
int cs_terrain_sidecar_path(const char *path, char *out, size_t size);

/* Reads a heightfield: the EXR (channel "Y", 32-bit float, and "W", the
 * water, when the sidecar has a "water" object) and its sidecar
 * (cs_terrain_sidecar_path); validates both and their agreement.
 * "-" is not accepted (two files are needed).  Voids (NaN, from
 * terrainprep --fill none) are an error. */
int cs_terrain_read(const char *exr_path, struct cs_terrain *t);
/* The same from memory: the EXR's bytes and the sidecar's text, with the
 * names messages give them. */
int cs_terrain_read_mem(const void *exr, size_t exr_len, const char *exr_name,
			const char *json, size_t json_len,
			const char *json_name, struct cs_terrain *t);

/* Writes the EXR and the sidecar atomically (each via temporary + rename).
 * source and driver describe where the data came from; nodata_policy is
 * e.g. "fill=nearest".  t->min_m/max_m must be set. */
int cs_terrain_write(const char *exr_path, const struct cs_terrain *t,
		     const char *source, const char *driver,
		     const char *nodata_policy);

/* The number of water samples (0 without water). */
long cs_terrain_water_count(const struct cs_terrain *t);

/* The same for any format: writes the data file (in m->format) and the
 * sidecar; the sidecar is prepared first and committed last, so a failure
 * leaves neither new file.  NaN voids are allowed in EXR and TIF only (the
 * reader refuses them).  R16 maps min..max to 0..65535 and records the
 * scale and offset.  Water (t->water) is stored in EXR files only
 * (CS_EINVAL for the others). */
int cs_terrain_write_as(const char *path, const struct cs_terrain *t,
			const struct cs_terrain_meta *m);

struct cs_outset;

/* cs_terrain_write_as() into a set of outputs (core/fileio.h): the data
 * file and its sidecar are written to temporaries of set, which its
 * cs_outset_commit() places with the run's other outputs. */
int cs_terrain_write_into(struct cs_outset *set, const char *path,
			  const struct cs_terrain *t, const struct cs_terrain_meta *m);

void cs_terrain_free(struct cs_terrain *t);

/* Bilinear height at fractional sample coordinates (col, row), clamped to
 * the grid's edge. */
double cs_terrain_height(const struct cs_terrain *t, double col, double row);

#endif
