/* terrainprep as a library call: terrain/reproject.c (GDAL) opens the DEMs
 * and warps them to a metric grid; this file checks the options, fills the
 * voids and writes the heightfield (terrain.c) and the hillshade (dem.c).
 * See man 1 terrainprep. */
#include "apps/terrainprep_run.h"

#include "terrain/dem.h"
#include "core/err.h"
#include "core/geo.h"
#include "core/info.h"
#include "io/image.h"
#include "core/fileio.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#ifndef CS_VERSION
#define CS_VERSION "unknown"
#endif

void cs_terrainprep_defaults(struct cs_terrainprep_opts *o)
{
	memset(o, 0, sizeof *o);
	o->stdin_name = "stdin";
	o->format = CS_TERRAINPREP_FORMAT_AUTO;
	o->fill = CS_FILL_NEAREST;
	o->max_void_fraction = 0.5;
	o->azimuth_deg = 315.0;
	o->altitude_deg = 45.0;
	o->z_factor = 1.0;
	o->scale = 1.0;
}

void cs_terrainprep_result_free(struct cs_terrainprep_result *r)
{
	cs_terrain_free(&r->terrain);
}

int cs_terrainprep_format(const char *name, enum cs_terrain_format *f)
{
	if (strcasecmp(name, "exr") == 0)
		*f = CS_TERRAIN_EXR;
	else if (strcasecmp(name, "r16") == 0 || strcasecmp(name, "raw") == 0)
		*f = CS_TERRAIN_R16;
	else if (strcasecmp(name, "tif") == 0 || strcasecmp(name, "tiff") == 0)
		*f = CS_TERRAIN_TIF;
	else
		return cs_error(CS_EINVAL, "'%s' is not exr, r16 or tif", name);
	return CS_OK;
}

/* The data file's format: as given, else from the output's extension. */
static enum cs_terrain_format output_format(const struct cs_terrainprep_opts *o)
{
	enum cs_terrain_format f = CS_TERRAIN_EXR;
	if (o->format != CS_TERRAINPREP_FORMAT_AUTO)
		return (enum cs_terrain_format)o->format;
	const char *dot = o->output ? strrchr(o->output, '.') : NULL;
	if (dot && !strchr(dot, '/') && cs_terrainprep_format(dot + 1, &f) != CS_OK)
		f = CS_TERRAIN_EXR;
	return f;
}

/* Counts the voids (any non-finite height becomes NaN), refuses too many,
 * fills them as asked and sets the height range. */
/* The range of the heights that are not voids. */
static void height_range(struct cs_terrain *t)
{
	size_t n = (size_t)t->width * t->height;
	t->min_m = INFINITY;
	t->max_m = -INFINITY;
	for (size_t i = 0; i < n; i++)
		if (!isnan(t->h[i])) {
			t->min_m = fmin(t->min_m, t->h[i]);
			t->max_m = fmax(t->max_m, t->h[i]);
		}
}

static int handle_voids(const struct cs_terrainprep_opts *o, struct cs_terrain *t,
			long *nvoids)
{
	size_t n = (size_t)t->width * t->height, voids = 0;
	for (size_t i = 0; i < n; i++)
		if (!isfinite(t->h[i])) {
			t->h[i] = NAN;
			voids++;
		}
	*nvoids = (long)voids;
	if (voids == n)
		return cs_error(CS_EDATA,
				"no heights in the output grid: the crop lies outside the data, or all of it is nodata");
	double frac = (double)voids / (double)n;
	if (frac > o->max_void_fraction)
		return cs_error(CS_EDATA,
				"%.1f%% of the output samples are voids (nodata or outside the data), more than --max-void-fraction %g allows",
				100.0 * frac, o->max_void_fraction);
	int rc = CS_OK;
	if (voids > 0 && o->fill == CS_FILL_NEAREST)
		rc = cs_dem_fill_nearest(t->h, t->width, t->height);
	else if (voids > 0 && o->fill == CS_FILL_VALUE)
		for (size_t i = 0; i < n; i++)
			if (isnan(t->h[i]))
				t->h[i] = (float)o->fill_value;
	height_range(t);
	return rc;
}

/* The data file, its sidecar and the hillshade are written to temporaries
 * first and renamed together at the end: a failure leaves none of them. */
static int write_outputs(const struct cs_terrainprep_opts *o, struct cs_reproject *rp,
			 const struct cs_terrainprep_result *res)
{
	const struct cs_terrain *t = &res->terrain;
	struct cs_outset set;
	cs_outset_init(&set, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
	int rc = CS_OK;
	if (o->output) {
		char policy[64], generator[96];
		if (o->fill == CS_FILL_VALUE)
			snprintf(policy, sizeof policy, "fill=value=%.9g", o->fill_value);
		else
			snprintf(policy, sizeof policy, "fill=%s",
				 o->fill == CS_FILL_NONE ? "none" : "nearest");
		snprintf(generator, sizeof generator, "terrainprep %s (GDAL %s)", CS_VERSION,
			 cs_reproject_gdal_version());
		char nodata[sizeof policy + 64 + 32];
		snprintf(nodata, sizeof nodata, "%s; source nodata %s", policy,
			 cs_reproject_src_nodata(rp));
		struct cs_terrain_meta m = {
			.format = res->format, .source = cs_reproject_source(rp),
			.driver = cs_reproject_driver(rp), .nodata_policy = nodata,
			.voids = res->voids, .resampling = res->resampling_used,
			.generator = generator, .r16_south_up = o->r16_south_up,
		};
		if (res->format == CS_TERRAIN_TIF)
			rc = cs_reproject_geotiff(rp, t, res->voids > 0 && o->fill == CS_FILL_NONE,
						  &m.bytes, &m.nbytes);
		if (rc == CS_OK)
			rc = cs_terrain_write_into(&set, o->output, t, &m);
	}
	if (rc == CS_OK && o->hillshade) {
		unsigned char *px = malloc((size_t)t->width * t->height);
		struct cs_outfile *of;
		if (px == NULL)
			rc = cs_error(CS_ENOMEM, "out of memory");
		if (rc == CS_OK)
			rc = cs_outset_open(&set, o->hillshade, &of);
		if (rc == CS_OK) {
			struct cs_hillshade s = {o->azimuth_deg, o->altitude_deg, o->z_factor,
						 o->scale};
			cs_dem_hillshade(t->h, t->width, t->height, t->pixel_x_m, t->pixel_y_m,
					 &s, px);
			rc = cs_png_write_to(of, strcmp(o->hillshade, "-") == 0 ? "standard output"
									       : o->hillshade,
					     t->width, t->height, 1, px);
		}
		free(px);
	}
	if (rc == CS_OK)
		rc = cs_outset_commit(&set);
	cs_outset_abort(&set);
	return rc;
}

/* Water where the mask says so or at or below the water level. */
static int make_water(const struct cs_terrainprep_opts *o, struct cs_reproject *rp,
		      struct cs_terrain *t)
{
	t->water_level_m = o->have_water_level ? o->water_level_m : NAN;
	t->water_source[0] = '\0';
	if (!o->have_water_level && o->water_mask == NULL)
		return CS_OK;
	size_t n = (size_t)t->width * t->height;
	t->water = calloc(n, sizeof *t->water);
	if (t->water == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	if (o->water_mask) {
		const char *slash = strrchr(o->water_mask, '/');
		snprintf(t->water_source, sizeof t->water_source, "%s",
			 slash ? slash + 1 : o->water_mask);
		CS_TRY(cs_reproject_water_mask(rp, o->water_mask, t, t->water));
	}
	/* below the level the surface is the water's: level */
	if (o->have_water_level)
		for (size_t i = 0; i < n; i++)
			if (t->h[i] <= o->water_level_m) {
				t->water[i] = 1.0f;
				t->h[i] = (float)o->water_level_m;
			}
	if (o->have_water_level)
		height_range(t);
	return CS_OK;
}

/* ---- --info ------------------------------------------------------------ */

int cs_terrainprep_info(const char *path, int json, char **text)
{
	struct cs_terrain t;
	*text = NULL;
	CS_TRY(cs_terrain_read(path, &t));
	size_t n = (size_t)t.width * t.height;
	double sum = 0.0;
	for (size_t i = 0; i < n; i++)
		sum += t.h[i];
	struct cs_info in;
	cs_info_init(&in, json);
	cs_info_str(&in, "file", "file", path);
	cs_info_str(&in, "format", "format", "cloudscape heightfield (OpenEXR float32 \"Y\" + JSON sidecar)");
	const double size[2] = {t.width, t.height};
	cs_info_nums(&in, "size", "size", size, 2, 0, " x ", "samples");
	char crs[32];
	snprintf(crs, sizeof crs, t.epsg > 0 ? "EPSG:%d" : "unknown (WKT only)", t.epsg);
	cs_info_str(&in, "crs", "crs", crs);
	const double px[2] = {t.pixel_x_m, t.pixel_y_m};
	cs_info_nums(&in, "pixel_size_m", "pixel size", px, 2, 3, " x ", "m (CRS units)");
	/* true metres: great circles between the corner sample centres */
	double gx = t.width > 1 ? cs_great_circle_m(t.corner_lat[0], t.corner_lon[0],
		t.corner_lat[1], t.corner_lon[1]) / (t.width - 1) : NAN;
	double gy = t.height > 1 ? cs_great_circle_m(t.corner_lat[0], t.corner_lon[0],
		t.corner_lat[3], t.corner_lon[3]) / (t.height - 1) : NAN;
	const double ground[2] = {gx, gy};
	cs_info_nums(&in, "ground_pixel_size_m", "ground pixel size", ground, 2, 3, " x ",
		     "m (great circle along the north and west edges)");
	const double origin[2] = {t.origin_x, t.origin_y};
	cs_info_nums(&in, "origin", "origin", origin, 2, 3, ", ", "(upper-left corner, CRS)");
	/* the outer edges: the corner sample centres moved out by half a
	 * sample along the grid (affine in lat/lon over the grid) */
	double lat[4], lon[4];
	const int right[4] = {1, 0, 3, 2}, down[4] = {3, 2, 1, 0};
	for (int c = 0; c < 4; c++) {
		double sx = t.width > 1 ? 0.5 / (t.width - 1) : 0.0;
		double sy = t.height > 1 ? 0.5 / (t.height - 1) : 0.0;
		lat[c] = t.corner_lat[c] + (t.corner_lat[c] - t.corner_lat[right[c]]) * sx +
			 (t.corner_lat[c] - t.corner_lat[down[c]]) * sy;
		lon[c] = t.corner_lon[c] + (t.corner_lon[c] - t.corner_lon[right[c]]) * sx +
			 (t.corner_lon[c] - t.corner_lon[down[c]]) * sy;
	}
	double s = 90, nth = -90, w = 180, e = -180;
	for (int c = 0; c < 4; c++) {
		s = fmin(s, lat[c]);
		nth = fmax(nth, lat[c]);
		w = fmin(w, lon[c]);
		e = fmax(e, lon[c]);
	}
	cs_info_open(&in, "bounds_wgs84_deg", "bounds (WGS84, degrees)");
	cs_info_num(&in, "south", "south", s, 6, NULL);
	cs_info_num(&in, "north", "north", nth, 6, NULL);
	cs_info_num(&in, "west", "west", w, 6, NULL);
	cs_info_num(&in, "east", "east", e, 6, NULL);
	cs_info_close(&in);
	const double centre[2] = {t.center_lat, t.center_lon};
	cs_info_nums(&in, "center_wgs84_deg", "centre (WGS84)", centre, 2, 6, ", ", "deg (lat, lon)");
	cs_info_open(&in, "height_m", "height");
	cs_info_num(&in, "min", "min", t.min_m, 3, "m");
	cs_info_num(&in, "max", "max", t.max_m, 3, "m");
	cs_info_num(&in, "mean", "mean", sum / (double)n, 3, "m");
	cs_info_close(&in);
	cs_info_open(&in, "voids", "voids");
	cs_info_num(&in, "count", "count", t.voids >= 0 ? (double)t.voids : NAN, 0,
		    t.voids > 0 ? "(filled)" : NULL);
	cs_info_str(&in, "policy", "policy", t.nodata_policy[0] ? t.nodata_policy : "unknown");
	cs_info_close(&in);
	cs_info_open(&in, "water", "water");
	long nw = cs_terrain_water_count(&t);
	cs_info_num(&in, "samples", "samples", (double)nw, 0, NULL);
	cs_info_num(&in, "percent", "percent", 100.0 * (double)nw / (double)n, 2, "%");
	if (t.water != NULL) {
		cs_info_num(&in, "level_m", "level", t.water_level_m, 3, "m");
		cs_info_str(&in, "mask", "mask", t.water_source[0] ? t.water_source : "none");
	}
	cs_info_close(&in);
	cs_terrain_free(&t);
	return cs_info_finish(&in, text);
}

/* Whether name ends in ext (any case). */
static int ends_in(const char *name, const char *ext)
{
	size_t n = strlen(name), e = strlen(ext);
	return n > e && strcasecmp(name + n - e, ext) == 0;
}

/* The names of the outputs: a format the name does not say is refused
 * (a .png heightfield would be an EXR under a PNG's name), and every
 * output's place is checked before the long work. */
static int check_outputs(const struct cs_terrainprep_opts *o)
{
	if (o->output && o->format == CS_TERRAINPREP_FORMAT_AUTO) {
		const char *slash = strrchr(o->output, '/');
		const char *dot = strrchr(slash ? slash : o->output, '.');
		enum cs_terrain_format f;
		if (dot && dot[1] != '\0' && cs_terrainprep_format(dot + 1, &f) != CS_OK)
			return cs_error(CS_EINVAL, "-o %s: a heightfield is EXR, GeoTIFF or 16-bit "
					"raw: name it .exr, .tif, .tiff, .r16 or .raw (or give "
					"--format)", o->output);
	}
	if (o->hillshade && strcmp(o->hillshade, "-") != 0 && !ends_in(o->hillshade, ".png")) {
		struct stat st;
		if (stat(o->hillshade, &st) < 0 || S_ISREG(st.st_mode))
			return cs_error(CS_EINVAL, "--hillshade %s: the hillshade is a PNG: name "
					"it .png (or '-')", o->hillshade);
	}
	const char *paths[3];
	char sidecar[4096];
	int n = 0;
	if (o->output) {
		int rc = cs_terrain_sidecar_path(o->output, sidecar, sizeof sidecar);
		if (rc != CS_OK)
			return rc;
		paths[n++] = sidecar; /* the first written (as before) */
		paths[n++] = o->output;
	}
	if (o->hillshade)
		paths[n++] = o->hillshade;
	return cs_outset_check(paths, n, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
}

/* ---- the run ---------------------------------------------------------- */

static int check_opts(const struct cs_terrainprep_opts *o, enum cs_terrain_format format)
{
	int nstdin = 0;
	for (int i = 0; i < o->ninputs; i++)
		nstdin += strcmp(o->inputs[i], "-") == 0;
	if (o->ninputs < 1 || o->ninputs > CS_TERRAINPREP_MAX_INPUTS)
		return cs_error(CS_EINVAL, "give 1 to %d input DEMs", CS_TERRAINPREP_MAX_INPUTS);
	if (nstdin > 1)
		return cs_error(CS_EINVAL, "standard input ('-') can be read only once");
	if (o->output == NULL && o->hillshade == NULL)
		return cs_error(CS_EINVAL, "no output: give -o FILE and/or --hillshade FILE.png");
	char sidecar[4096];
	int rc = o->output ? cs_terrain_sidecar_path(o->output, sidecar, sizeof sidecar) : CS_OK;
	if (rc != CS_OK)
		return rc;
	if (o->stdin_name == NULL || o->stdin_name[0] == '\0' || strchr(o->stdin_name, '/') ||
	    strlen(o->stdin_name) > 200 || strcmp(o->stdin_name, ".") == 0 ||
	    strcmp(o->stdin_name, "..") == 0)
		return cs_error(CS_EINVAL, "--stdin-name: a plain file name is needed");
	int sizes = (o->res_m > 0.0) + (o->size_w > 0 || o->size_h > 0) +
		    (o->size_long > 0) + (o->size_unity != 0);
	if (sizes > 1)
		return cs_error(CS_EINVAL, "--res and --size exclude each other");
	if ((o->size_w > 0) != (o->size_h > 0))
		return cs_error(CS_EINVAL, "--size WxH needs both numbers");
	if (o->have_center && o->have_bounds)
		return cs_error(CS_EINVAL, "--center and --bounds exclude each other");
	if (o->have_center && !(o->radius_km > 0.0 && fabs(o->center_lat) <= 90.0 &&
				fabs(o->center_lon) <= 180.0))
		return cs_error(CS_EINVAL, "--center needs a latitude, a longitude and --radius above 0");
	if (o->have_bounds && !(o->bounds[0] < o->bounds[2] && o->bounds[1] < o->bounds[3]))
		return cs_error(CS_EINVAL, "--bounds: need xmin < xmax and ymin < ymax");
	if (o->bounds_srs && !o->have_bounds)
		return cs_error(CS_EINVAL, "--bounds-srs needs --bounds");
	if (!(o->max_void_fraction >= 0.0 && o->max_void_fraction <= 1.0))
		return cs_error(CS_EINVAL, "--max-void-fraction must be within 0..1");
	if (o->r16_south_up && format != CS_TERRAIN_R16)
		return cs_error(CS_EINVAL, "--flip applies to --format r16 only");
	if (format == CS_TERRAIN_R16 && o->fill == CS_FILL_NONE)
		return cs_error(CS_EINVAL, "--format r16 cannot hold voids: use --fill nearest or --fill value");
	if ((o->have_water_level || o->water_mask) && o->output && format != CS_TERRAIN_EXR)
		return cs_error(CS_EINVAL, "--water-level and --water-mask: water is stored in EXR heightfields only");
	if (o->have_water_level && !isfinite(o->water_level_m))
		return cs_error(CS_EINVAL, "--water-level: not a number");
	if (o->resampling && !cs_reproject_resampling_known(o->resampling))
		return cs_error(CS_EINVAL, "-r: unknown resampling '%s'", o->resampling);
	return check_outputs(o);
}

static void reproject_opts(const struct cs_terrainprep_opts *o, struct cs_reproject_opts *w)
{
	*w = (struct cs_reproject_opts){
		.inputs = o->inputs, .ninputs = o->ninputs, .stdin_name = o->stdin_name,
		.s_srs = o->s_srs, .t_srs = o->t_srs,
		.have_center = o->have_center, .center_lat = o->center_lat,
		.center_lon = o->center_lon, .radius_km = o->radius_km,
		.have_bounds = o->have_bounds, .bounds_srs = o->bounds_srs,
		.res_m = o->res_m, .size_long = o->size_long, .size_w = o->size_w,
		.size_h = o->size_h, .size_unity = o->size_unity, .resampling = o->resampling,
		.have_src_nodata = o->have_src_nodata, .src_nodata_none = o->src_nodata_none,
		.src_nodata = o->src_nodata, .progress = o->progress,
		.progress_user = o->progress_user,
	};
	memcpy(w->bounds, o->bounds, sizeof w->bounds);
}

int cs_terrainprep_run(const struct cs_terrainprep_opts *o, struct cs_terrainprep_result *res)
{
	memset(res, 0, sizeof *res);
	res->format = output_format(o);
	int rc = check_opts(o, res->format);
	if (rc != CS_OK)
		return rc;
	struct cs_reproject_opts wo;
	struct cs_reproject *rp = NULL;
	reproject_opts(o, &wo);
	struct cs_terrain *t = &res->terrain;
	rc = cs_reproject_open(&wo, &rp);
	if (rc == CS_OK)
		rc = cs_reproject_warp(rp, t, res->resampling_used, sizeof res->resampling_used);
	if (rc == CS_OK)
		rc = handle_voids(o, t, &res->voids);
	if (rc == CS_OK)
		rc = cs_reproject_georeference(rp, t);
	if (rc == CS_OK)
		rc = make_water(o, rp, t);
	if (rc == CS_OK)
		rc = write_outputs(o, rp, res);
	if (rc == CS_OK && o->progress)
		o->progress(o->progress_user, 1.0);
	if (rp)
		snprintf(res->warning, sizeof res->warning, "%s", cs_reproject_warning(rp));
	cs_reproject_free(rp);
	if (rc != CS_OK)
		cs_terrain_free(t);
	return rc;
}
