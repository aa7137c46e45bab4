/* DEM reprojection with GDAL (see reproject.h): GDAL opens the DEMs,
 * GDALWarp (the gdalwarp application API) mosaics, reprojects, crops and
 * resamples them in memory. */
#include "terrain/reproject.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/vec.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_STDIN_BYTES ((size_t)1 << 32)

static const char *const resamplers[] = {
	"near", "bilinear", "cubic", "cubicspline", "lanczos", "average", "rms",
	"mode", "max", "min", "med", "q1", "q3", "sum", NULL,
};

int cs_reproject_resampling_known(const char *name)
{
	for (int i = 0; resamplers[i]; i++)
		if (strcmp(name, resamplers[i]) == 0)
			return 1;
	return 0;
}

/* ---- GDAL's messages -------------------------------------------------- */

struct gdal_log {
	int failed;
	char failure[512]; /* the first CE_Failure message of the step */
	char warning[2048]; /* every distinct CE_Warning message, and our own
			       notices, one a line */
	const char *input;  /* the input being opened, to name in warnings */
};

/* Adds a line to the warnings, once (GDAL repeats itself per block). */
static void add_warning(struct gdal_log *g, const char *line)
{
	size_t n = strlen(g->warning), k = strlen(line);
	for (const char *at = g->warning; (at = strstr(at, line)) != NULL; at++)
		if ((at == g->warning || at[-1] == '\n') && (at[k] == '\n' || at[k] == '\0'))
			return;
	snprintf(g->warning + n, sizeof g->warning - n, "%s%s", n ? "\n" : "", line);
}

static void copy_msg(char *dst, size_t size, const char *msg)
{
	snprintf(dst, size, "%s", msg ? msg : "");
	for (char *p = dst; *p; p++)
		if (*p == '\n' || *p == '\r')
			*p = ' ';
	for (size_t n = strlen(dst); n > 0 && dst[n - 1] == ' '; n--)
		dst[n - 1] = '\0';
}

static void CPL_STDCALL on_gdal_error(CPLErr cls, CPLErrorNum no, const char *msg)
{
	(void)no;
	struct gdal_log *g = CPLGetErrorHandlerUserData();
	if (cls >= CE_Failure) {
		if (!g->failed)
			copy_msg(g->failure, sizeof g->failure, msg);
		g->failed = 1;
	} else if (cls == CE_Warning) {
		char line[800], named[1000];
		copy_msg(line, sizeof line, msg);
		/* GDAL seldom names the file: with several inputs, say which */
		if (g->input && strstr(line, g->input) == NULL)
			snprintf(named, sizeof named, "%s: %s", g->input, line);
		else
			snprintf(named, sizeof named, "%s", line);
		add_warning(g, named);
	}
}

/* Forgets earlier messages: before a step whose failure is judged alone. */
static void log_reset(struct gdal_log *g)
{
	g->failed = 0;
	g->failure[0] = '\0';
}

static pthread_once_t gdal_once = PTHREAD_ONCE_INIT;

static void register_drivers(void)
{
	GDALAllRegister();
}

/* ---- one run's state -------------------------------------------------- */

struct cs_reproject {
	struct cs_reproject_opts opts;
	const struct cs_reproject_opts *o; /* = &opts */
	struct gdal_log log;
	GDALDatasetH *src;         /* what the warps read: band 1 of each input */
	GDALDatasetH *whole;       /* the input of a src[i] that has more bands, or NULL */
	int nsrc;
	char mem_dir[96];          /* /vsimem folder of this run */
	char stdin_path[384];      /* "-" opened from here */
	unsigned char *stdin_buf;
	OGRSpatialReferenceH s_srs, t_srs, b_srs, wgs84; /* owned */
	char *s_wkt, *t_wkt;       /* CPLFree */
	double te[4];
	int have_te;
	const char *te_srs;        /* user's string for -te_srs, or NULL */
	char source[1024], driver[128], src_nodata[64];
	double gt[6];
	char tif_path[160];          /* the encoded GeoTIFF, or "" */
	char *pam;                 /* GDAL_PAM_ENABLED outside our calls */
	char *dted;                /* DTED_VERIFY_CHECKSUM outside our calls */
	size_t in_bytes;           /* the inputs' sizes, all together */
};

/* The failure message after a GDAL step, as a CS_EDATA error. */
static int gdal_fail(struct cs_reproject *r, const char *what)
{
	return cs_error(CS_EDATA, "%s: %s", what,
			r->log.failure[0] ? r->log.failure : "GDAL failed without a message");
}

/* A CRS from any form OSRSetFromUserInput takes, in x=east, y=north order. */
static int parse_srs(struct cs_reproject *r, const char *opt, const char *text,
		     OGRSpatialReferenceH *out)
{
	log_reset(&r->log);
	OGRSpatialReferenceH h = OSRNewSpatialReference(NULL);
	if (h == NULL || OSRSetFromUserInput(h, text) != OGRERR_NONE) {
		if (h)
			OSRDestroySpatialReference(h);
		return cs_error(CS_EINVAL, "%s: '%s' is not a coordinate reference system GDAL knows%s%s",
				opt, text, r->log.failure[0] ? ": " : "", r->log.failure);
	}
	OSRSetAxisMappingStrategy(h, OAMS_TRADITIONAL_GIS_ORDER);
	*out = h;
	return CS_OK;
}

static int is_metric_projected(OGRSpatialReferenceH h)
{
	return OSRIsProjected(h) && fabs(OSRGetLinearUnits(h, NULL) - 1.0) < 1e-9;
}

static char *export_wkt(OGRSpatialReferenceH h)
{
	const char *const opts[] = {"FORMAT=WKT2_2019", NULL};
	char *wkt = NULL;
	if (OSRExportToWktEx(h, &wkt, opts) != OGRERR_NONE) {
		CPLFree(wkt);
		return NULL;
	}
	return wkt;
}

/* UTM zone of a point as an EPSG code (WGS84 / UTM), with the Norway and
 * Svalbard exceptions, and UPS beyond UTM's latitudes. */
static int utm_epsg(double lat, double lon)
{
	if (lat > 84.0)
		return 32661;
	if (lat < -80.0)
		return 32761;
	lon = isfinite(lon) ? lon - 360.0 * floor((lon + 180.0) / 360.0) : 0.0;
	int zone = (int)floor((lon + 180.0) / 6.0) + 1;
	zone = zone < 1 ? 1 : zone > 60 ? 60 : zone;
	if (lat >= 56.0 && lat < 64.0 && lon >= 3.0 && lon < 12.0)
		zone = 32;
	if (lat >= 72.0 && lon >= 0.0 && lon < 42.0)
		zone = lon < 9.0 ? 31 : lon < 21.0 ? 33 : lon < 33.0 ? 35 : 37;
	return (lat >= 0.0 ? 32600 : 32700) + zone;
}

/* Transforms n points in place from one CRS to another. */
static int transform(struct cs_reproject *r, OGRSpatialReferenceH from,
		     OGRSpatialReferenceH to, int n, double *x, double *y)
{
	log_reset(&r->log);
	OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(from, to);
	int ok = ct != NULL && OCTTransform(ct, n, x, y, NULL) && !r->log.failed;
	if (ct)
		OCTDestroyCoordinateTransformation(ct);
	return ok ? CS_OK : gdal_fail(r, "coordinate transformation");
}

/* ---- inputs ----------------------------------------------------------- */

static int open_stdin(struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	size_t len = 0;
	int rc = cs_read_all("-", MAX_STDIN_BYTES, &r->stdin_buf, &len);
	if (rc != CS_OK)
		return rc;
	snprintf(r->stdin_path, sizeof r->stdin_path, "%s/%s", r->mem_dir, o->stdin_name);
	VSILFILE *f = VSIFileFromMemBuffer(r->stdin_path, r->stdin_buf, len, FALSE);
	if (f == NULL)
		return gdal_fail(r, "standard input");
	VSIFCloseL(f);
	return CS_OK;
}

static void append(char *dst, size_t size, const char *sep, const char *s)
{
	size_t n = strlen(dst);
	snprintf(dst + n, size - n, "%s%s", n ? sep : "", s);
}

/* GDAL names the file in most messages: show the user's name for it, and
 * add it only where GDAL did not. */
static int open_error(struct cs_reproject *r, const char *path, const char *label)
{
	char msg[sizeof r->log.failure + 64] = "";
	const char *m = r->log.failure[0] ? r->log.failure : "not a raster GDAL reads";
	const char *at = strstr(m, path);
	if (at == NULL)
		return cs_error(CS_EDATA, "cannot read %s: %s", label, m);
	snprintf(msg, sizeof msg, "%.*s%s%s", (int)(at - m), m, label, at + strlen(path));
	return cs_error(CS_EDATA, "%s", msg);
}

/* Whether the grid's corners lie within 1e9 units of the origin of its
 * CRS (the Earth is 4e7 m round, 1.3e8 ft): far beyond, PROJ's inverse
 * projections can run for minutes (an origin at 1e54 m hung gdalinfo). */
static int sane_extent(const double gt[6], int w, int h)
{
	for (int k = 0; k < 4; k++) {
		double c = (k & 1) ? w : 0, r = (k & 2) ? h : 0;
		double x = gt[0] + c * gt[1] + r * gt[2], y = gt[3] + c * gt[4] + r * gt[5];
		if (!(fabs(x) <= 1e9 && fabs(y) <= 1e9))
			return 0;
	}
	return 1;
}

/* The size of a file GDAL opens (files and /vsimem alike), or 0. */
static size_t file_bytes(const char *path)
{
	VSILFILE *f = VSIFOpenL(path, "rb");
	size_t n = 0;
	if (f != NULL && VSIFSeekL(f, 0, SEEK_END) == 0)
		n = (size_t)VSIFTellL(f);
	if (f != NULL)
		VSIFCloseL(f);
	return n;
}

/* DTED stores a checksum per elevation profile: read the whole file once
 * with DTED_VERIFY_CHECKSUM (set in enter()), so that a damaged tile is
 * an error naming it, not a warp failure naming none of a mosaic's. */
static int verify_checksums(struct cs_reproject *r, GDALDatasetH ds, const char *label)
{
	if (strcmp(GDALGetDriverShortName(GDALGetDatasetDriver(ds)), "DTED") != 0 ||
	    GDALGetRasterCount(ds) < 1)
		return CS_OK;
	log_reset(&r->log);
	GDALRasterBandH b = GDALGetRasterBand(ds, 1);
	(void)GDALChecksumImage(b, 0, 0, GDALGetRasterXSize(ds), GDALGetRasterYSize(ds));
	if (r->log.failed)
		return cs_error(CS_EDATA, "%s is damaged: %s", label, r->log.failure);
	return CS_OK;
}

/* GDAL utility arguments, one at a time (CSLAddString) */
static char **add(char **av, const char *a)
{
	return CSLAddString(av, a);
}

static char **addnum(char **av, double v)
{
	char buf[64];
	snprintf(buf, sizeof buf, "%.17g", v);
	return CSLAddString(av, buf);
}

/* A dataset of more than one band as a virtual one of its first: the
 * warps create and write every band of what they read, and a header
 * claiming 60000 bands would cost minutes for the one band we use.
 * *one is ds itself when it has one band; else a VRT that needs ds open
 * until it is closed. */
static int first_band(struct cs_reproject *r, GDALDatasetH ds, const char *label,
		      GDALDatasetH *one)
{
	*one = ds;
	if (GDALGetRasterCount(ds) <= 1)
		return CS_OK;
	char **av = add(add(add(add(NULL, "-of"), "VRT"), "-b"), "1");
	GDALTranslateOptions *to = GDALTranslateOptionsNew(av, NULL);
	CSLDestroy(av);
	if (to == NULL)
		return gdal_fail(r, "translate options");
	log_reset(&r->log);
	*one = GDALTranslate("", ds, to, NULL);
	GDALTranslateOptionsFree(to);
	if (*one == NULL || r->log.failed) {
		if (*one)
			GDALClose(*one);
		*one = NULL;
		return cs_error(CS_EDATA, "%s: taking its first band: %s", label,
				r->log.failure[0] ? r->log.failure : "GDAL failed");
	}
	return CS_OK;
}

static int open_inputs(struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	r->src = calloc((size_t)o->ninputs, sizeof *r->src);
	r->whole = calloc((size_t)o->ninputs, sizeof *r->whole);
	if (r->src == NULL || r->whole == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (int i = 0; i < o->ninputs; i++) {
		const char *in = o->inputs[i];
		int is_stdin = strcmp(in, "-") == 0;
		if (is_stdin) {
			int rc = open_stdin(r);
			if (rc != CS_OK)
				return rc;
		}
		const char *path = is_stdin ? r->stdin_path : in;
		const char *label = is_stdin ? "standard input" : in;
		log_reset(&r->log);
		r->log.input = label;
		GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY |
					     GDAL_OF_VERBOSE_ERROR, NULL, NULL, NULL);
		if (ds == NULL || r->log.failed) {
			if (ds)
				GDALClose(ds);
			return open_error(r, path, label);
		}
		r->src[r->nsrc++] = ds;
		r->in_bytes += file_bytes(path);
		int rc = verify_checksums(r, ds, label);
		if (rc != CS_OK)
			return rc;
		double gt[6];
		if (GDALGetRasterCount(ds) < 1)
			return cs_error(CS_EDATA, "%s has no raster band", label);
		GDALDatasetH one = NULL;
		rc = first_band(r, ds, label, &one);
		if (rc != CS_OK)
			return rc;
		if (one != ds) {
			r->whole[r->nsrc - 1] = ds;
			r->src[r->nsrc - 1] = one;
		}
		int have_gt = GDALGetGeoTransform(ds, gt) == CE_None;
		if (!have_gt && GDALGetGCPCount(ds) == 0)
			return cs_error(CS_EDATA, "%s has no georeferencing (no geotransform, no GCPs)",
					label);
		if (have_gt && !sane_extent(gt, GDALGetRasterXSize(ds), GDALGetRasterYSize(ds)))
			return cs_error(CS_EDATA, "%s: its georeferencing is off the Earth (origin %g, %g; "
					"pixel %g x %g): a corrupt header", label, gt[0], gt[3],
					gt[1], gt[5]);
		log_reset(&r->log);
		if (o->s_srs == NULL && GDALGetSpatialRef(ds) == NULL &&
		    GDALGetGCPSpatialRef(ds) == NULL)
			return cs_error(CS_EDATA,
					"%s has no coordinate reference system (nothing in the file, no .prj): "
					"name it with --s-srs, e.g. --s-srs EPSG:2056",
					label);
		char name[300];
		snprintf(name, sizeof name, is_stdin ? "%s (standard input)" : "%s",
			 is_stdin ? o->stdin_name : in);
		append(r->source, sizeof r->source, ", ", name);
		const char *drv = GDALGetDriverShortName(GDALGetDatasetDriver(ds));
		if (strstr(r->driver, drv) == NULL)
			append(r->driver, sizeof r->driver, ",", drv);
	}
	if (o->have_src_nodata && o->src_nodata_none) {
		snprintf(r->src_nodata, sizeof r->src_nodata, "none (ignored)");
	} else if (o->have_src_nodata) {
		snprintf(r->src_nodata, sizeof r->src_nodata, "%.17g", o->src_nodata);
	} else {
		int ok = 0;
		double v = GDALGetRasterNoDataValue(GDALGetRasterBand(r->src[0], 1), &ok);
		snprintf(r->src_nodata, sizeof r->src_nodata, ok ? "%.17g" : "none", v);
	}
	return CS_OK;
}

/* WGS84 centre of the inputs' union (pixel corners and centres). */
static int source_center(struct cs_reproject *r, double *lat, double *lon)
{
	log_reset(&r->log);
	double lat0 = INFINITY, lat1 = -INFINITY, lon0 = INFINITY, lon1 = -INFINITY;
	char *wgs_wkt = export_wkt(r->wgs84);
	for (int i = 0; i < r->nsrc && wgs_wkt; i++) {
		char **to = CSLSetNameValue(NULL, "DST_SRS", wgs_wkt);
		if (r->s_wkt)
			to = CSLSetNameValue(to, "SRC_SRS", r->s_wkt);
		void *tr = GDALCreateGenImgProjTransformer2(r->src[i], NULL, to);
		CSLDestroy(to);
		if (tr == NULL)
			break;
		double w = GDALGetRasterXSize(r->src[i]), h = GDALGetRasterYSize(r->src[i]);
		double x[5] = {0, w, w, 0, w / 2}, y[5] = {0, 0, h, h, h / 2}, z[5] = {0};
		int ok[5] = {0};
		GDALGenImgProjTransform(tr, FALSE, 5, x, y, z, ok);
		GDALDestroyGenImgProjTransformer(tr);
		for (int k = 0; k < 5; k++)
			if (ok[k]) {
				lon0 = fmin(lon0, x[k]);
				lon1 = fmax(lon1, x[k]);
				lat0 = fmin(lat0, y[k]);
				lat1 = fmax(lat1, y[k]);
			}
	}
	CPLFree(wgs_wkt);
	if (!(lat0 <= lat1) || r->log.failed)
		return gdal_fail(r, "cannot place the input on the Earth");
	*lat = 0.5 * (lat0 + lat1);
	*lon = 0.5 * (lon0 + lon1);
	if (!(fabs(*lat) <= 90.0 && fabs(*lon) <= 540.0))
		return cs_error(CS_EDATA, "cannot place the input on the Earth: its "
				"georeferencing puts the centre at %g, %g", *lat, *lon);
	return CS_OK;
}

/* The point scale of a projected CRS at (lat, lon), WGS84 degrees: its
 * metres per true metre east and north, from points 1e-4 degree away
 * (true lengths on the WGS84 ellipsoid: the meridian radius M and the
 * prime vertical N).  1 within 0.1 % for UTM in its zone; 1/cos(lat) for
 * Web Mercator (EPSG:3857).  0 when it cannot be computed. */
static double crs_scale(struct cs_reproject *r, OGRSpatialReferenceH crs,
			double lat, double lon)
{
	const double a = 6378137.0, e2 = 0.00669437999014, d = 1e-4;
	double phi = lat * CS_PI / 180.0, w = 1.0 - e2 * sin(phi) * sin(phi);
	double m = a * (1.0 - e2) / pow(w, 1.5), n = a / sqrt(w);
	double x[3] = {lon, lon + d, lon}, y[3] = {lat, lat, lat + d};
	if (fabs(lat) > 89.0 || transform(r, r->wgs84, crs, 3, x, y) != CS_OK)
		return 0.0;
	double ke = hypot(x[1] - x[0], y[1] - y[0]) / (n * cos(phi) * d * CS_PI / 180.0);
	double kn = hypot(x[2] - x[0], y[2] - y[0]) / (m * d * CS_PI / 180.0);
	double k = 0.5 * (ke + kn);
	return isfinite(k) && k > 0.0 ? k : 0.0;
}

/* "EPSG:3857" or the CRS's name, for messages. */
static void crs_label(OGRSpatialReferenceH h, char *buf, size_t size)
{
	const char *auth = OSRGetAuthorityName(h, NULL), *code = OSRGetAuthorityCode(h, NULL);
	const char *name = OSRGetName(h);
	if (auth && code)
		snprintf(buf, size, "%s:%s (%s)", auth, code, name ? name : "unnamed");
	else
		snprintf(buf, size, "%s", name ? name : "the input's CRS");
}

/* The target CRS: --t-srs; else the input's own if projected in true
 * metres (scale within CS_REPROJECT_MAX_SCALE_ERROR of 1 at the centre);
 * else the UTM zone of the centre (of the crop, or of the inputs). */
static int choose_target(struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	int rc;
	if (r->t_srs) /* --t-srs, parsed with the other options */
		return CS_OK;
	OGRSpatialReferenceH own = r->s_srs ? r->s_srs : GDALGetSpatialRef(r->src[0]);
	if (own == NULL)
		own = GDALGetGCPSpatialRef(r->src[0]);
	double lat, lon, k = 1.0;
	if (own && is_metric_projected(own)) {
		OGRSpatialReferenceH c = OSRClone(own);
		OSRSetAxisMappingStrategy(c, OAMS_TRADITIONAL_GIS_ORDER);
		if (source_center(r, &lat, &lon) == CS_OK)
			k = crs_scale(r, c, lat, lon);
		if (k == 0.0 || fabs(k - 1.0) <= CS_REPROJECT_MAX_SCALE_ERROR) {
			r->t_srs = c;
			return CS_OK;
		}
		/* metres that are not true metres (Web Mercator): the renderer
		 * takes pixel sizes as lengths, so go to the local UTM zone */
		char label[200], msg[400];
		crs_label(c, label, sizeof label);
		OSRDestroySpatialReference(c);
		snprintf(msg, sizeof msg, "%s is not in true metres here: one of its metres is "
			 "%.3f m at the centre (%.2f, %.2f; scale %.4f), so the result is "
			 "reprojected to the local UTM zone (--t-srs keeps a CRS of your choice)",
			 label, 1.0 / k, lat, lon, k);
		add_warning(&r->log, msg);
	}
	if (o->have_center) {
		lat = o->center_lat;
		lon = o->center_lon;
	} else if (r->b_srs) {
		lon = 0.5 * (o->bounds[0] + o->bounds[2]);
		lat = 0.5 * (o->bounds[1] + o->bounds[3]);
		if ((rc = transform(r, r->b_srs, r->wgs84, 1, &lon, &lat)) != CS_OK)
			return rc;
	} else if ((rc = source_center(r, &lat, &lon)) != CS_OK) {
		return rc;
	}
	r->t_srs = OSRNewSpatialReference(NULL);
	if (OSRImportFromEPSG(r->t_srs, utm_epsg(lat, lon)) != OGRERR_NONE)
		return gdal_fail(r, "UTM");
	OSRSetAxisMappingStrategy(r->t_srs, OAMS_TRADITIONAL_GIS_ORDER);
	return CS_OK;
}

/* The crop as gdalwarp's -te (in the target CRS, or in --bounds-srs). */
static int choose_extent(struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	if (o->have_center) {
		double x = o->center_lon, y = o->center_lat, d = o->radius_km * 1000.0;
		int rc = transform(r, r->wgs84, r->t_srs, 1, &x, &y);
		if (rc != CS_OK)
			return rc;
		r->te[0] = x - d;
		r->te[1] = y - d;
		r->te[2] = x + d;
		r->te[3] = y + d;
		r->have_te = 1;
	} else if (o->have_bounds) {
		memcpy(r->te, o->bounds, sizeof r->te);
		r->te_srs = o->bounds_srs;
		r->have_te = 1;
	}
	return CS_OK;
}

/* ---- warping ---------------------------------------------------------- */

/* gdalwarp options shared by the planning and the real warp. */
static char **common_args(const struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	char **av = add(add(NULL, "-t_srs"), r->t_wkt);
	if (r->s_wkt)
		av = add(add(av, "-s_srs"), r->s_wkt);
	if (r->have_te) {
		av = add(av, "-te");
		for (int k = 0; k < 4; k++)
			av = addnum(av, r->te[k]);
		if (r->te_srs)
			av = add(add(av, "-te_srs"), r->te_srs);
	}
	if (o->have_src_nodata && o->src_nodata_none)
		av = add(add(av, "-srcnodata"), "None");
	else if (o->have_src_nodata)
		av = addnum(add(av, "-srcnodata"), o->src_nodata);
	return av;
}

static int CPL_STDCALL on_progress(double f, const char *msg, void *user)
{
	(void)msg;
	const struct cs_reproject_opts *o = user;
	return o->progress(o->progress_user, f) == 0;
}

/* Runs GDALWarp with av (consumed) on n sources into an unnamed dataset. */
static int warp(struct cs_reproject *r, char **av, GDALDatasetH *src, int n, int report,
		GDALDatasetH *out)
{
	GDALWarpAppOptions *wo = GDALWarpAppOptionsNew(av, NULL);
	CSLDestroy(av);
	if (wo == NULL)
		return gdal_fail(r, "warp options");
	if (report && r->o->progress)
		GDALWarpAppOptionsSetProgress(wo, on_progress, &r->opts);
	int usage = 0;
	log_reset(&r->log);
	*out = GDALWarp("", NULL, n, src, wo, &usage);
	GDALWarpAppOptionsFree(wo);
	if (*out == NULL || r->log.failed) {
		if (*out)
			GDALClose(*out);
		*out = NULL;
		return gdal_fail(r, "warp");
	}
	return CS_OK;
}

/* The natural grid (about the inputs' own resolution) as gdalwarp chooses
 * it: the union of each source's suggested extent at the finest of their
 * resolutions (a VRT warp looks at one source).  ext: width and height in
 * target units; res: the pixel size. */
static int natural_grid(struct cs_reproject *r, double ext[2], double *res)
{
	double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
	*res = INFINITY;
	for (int i = 0; i < r->nsrc; i++) {
		GDALDatasetH vrt = NULL;
		int rc = warp(r, add(add(common_args(r), "-of"), "VRT"), &r->src[i], 1, 0, &vrt);
		if (rc != CS_OK)
			return rc;
		double g[6];
		GDALGetGeoTransform(vrt, g);
		x0 = fmin(x0, g[0]);
		x1 = fmax(x1, g[0] + GDALGetRasterXSize(vrt) * g[1]);
		y1 = fmax(y1, g[3]);
		y0 = fmin(y0, g[3] + GDALGetRasterYSize(vrt) * g[5]);
		*res = fmin(*res, fmin(g[1], -g[5]));
		GDALClose(vrt);
	}
	ext[0] = x1 - x0;
	ext[1] = y1 - y0;
	return CS_OK;
}

/* Adds the size options (-tr or -ts) to *av and the resampling (-r) the
 * grid calls for; want: the samples that will result. */
static int size_args(struct cs_reproject *r, char ***av, const double ext[2],
		     double res, char *resampling, size_t size)
{
	const struct cs_reproject_opts *o = r->o;
	double ext_x = ext[0], ext_y = ext[1];
	double nw = round(ext_x / res), nh = round(ext_y / res);
	double want_w = nw, want_h = nh;
	if (o->res_m > 0.0) {
		*av = addnum(addnum(add(*av, "-tr"), o->res_m), o->res_m);
		want_w = ext_x / o->res_m;
		want_h = ext_y / o->res_m;
	} else if (o->size_w > 0) {
		want_w = o->size_w;
		want_h = o->size_h;
	} else if (o->size_long > 0) {
		want_w = ext_x >= ext_y ? o->size_long : fmax(1.0, round(ext_x / ext_y * o->size_long));
		want_h = ext_x >= ext_y ? fmax(1.0, round(ext_y / ext_x * o->size_long)) : o->size_long;
	} else if (o->size_unity) {
		int n = 33;
		while (n < (nw > nh ? nw : nh) && n < 4097)
			n = 2 * n - 1;
		want_w = want_h = n;
	}
	/* the grid the inputs' headers make, when no option chose one: no
	 * more samples than their bytes can hold, one bit a sample at
	 * deflate's best ratio (1032:1) */
	double can = (double)r->in_bytes * 8.0 * 1032.0;
	if (o->res_m <= 0.0 && o->size_w <= 0 && o->size_long <= 0 && !o->size_unity &&
	    want_w * want_h > can && want_w * want_h <= (double)CS_REPROJECT_MAX_SAMPLES)
		return cs_error(CS_EDATA, "%s: the header%s make%s a %.0fx%.0f grid, more "
				"samples than %zu bytes can hold (%.0f): a corrupt or hostile "
				"header (--res or --size chooses the grid)", r->source,
				r->nsrc > 1 ? "s" : "", r->nsrc > 1 ? "" : "s", want_w, want_h,
				r->in_bytes, can);
	if (want_w * want_h > (double)CS_REPROJECT_MAX_SAMPLES || want_w > 65536 ||
	    want_h > 65536)
		return cs_error(CS_EINVAL, "the grid would be %.0fx%.0f samples (at most %ld): choose a coarser --res or a smaller --size",
				want_w, want_h, CS_REPROJECT_MAX_SAMPLES);
	/* --size N: the other side follows from square pixels */
	if (o->size_long > 0)
		*av = addnum(addnum(add(*av, "-ts"), ext_x >= ext_y ? want_w : 0),
			     ext_x >= ext_y ? 0 : want_h);
	else if (o->size_w > 0 || o->size_unity)
		*av = addnum(addnum(add(*av, "-ts"), want_w), want_h);
	/* shrinking more than 2x: bilinear would skip samples, average does not */
	double shrink = fmax(ext_x / want_w, ext_y / want_h) / res;
	const char *alg = o->resampling ? o->resampling : shrink > 2.0 ? "average" : "bilinear";
	snprintf(resampling, size, "%s", alg);
	*av = add(add(*av, "-r"), alg);
	return CS_OK;
}

/* Warps in memory to the final grid and reads the heights (NaN = void). */
static int warp_heights(struct cs_reproject *r, float **h, int *w, int *hh,
			char *resampling, size_t size)
{
	double ext[2], res;
	int rc = natural_grid(r, ext, &res);
	if (rc != CS_OK)
		return rc;
	char **av = add(add(add(add(common_args(r), "-of"), "MEM"), "-ot"), "Float32");
	av = add(add(av, "-dstnodata"), "nan");
	rc = size_args(r, &av, ext, res, resampling, size);
	if (rc != CS_OK) {
		CSLDestroy(av);
		return rc;
	}
	GDALDatasetH mem = NULL;
	rc = warp(r, av, r->src, r->nsrc, 1, &mem);
	if (rc != CS_OK)
		return rc;
	*w = GDALGetRasterXSize(mem);
	*hh = GDALGetRasterYSize(mem);
	GDALGetGeoTransform(mem, r->gt);
	*h = malloc((size_t)*w * (size_t)*hh * sizeof **h);
	if (*h == NULL) {
		GDALClose(mem);
		return cs_error(CS_ENOMEM, "out of memory");
	}
	CPLErr e = GDALRasterIO(GDALGetRasterBand(mem, 1), GF_Read, 0, 0, *w, *hh,
				*h, *w, *hh, GDT_Float32, 0, 0);
	GDALClose(mem);
	if (e != CE_None || r->log.failed)
		return gdal_fail(r, "reading the warped heights");
	if (r->gt[2] != 0.0 || r->gt[4] != 0.0 || !(r->gt[1] > 0.0) || !(r->gt[5] < 0.0))
		return cs_error(CS_EDATA, "warp gave a rotated or flipped grid");
	return CS_OK;
}

/* ---- georeference, GeoTIFF ------------------------------------------ */

/* A --t-srs whose metres are not true metres here: say the true size. */
static void warn_target_scale(struct cs_reproject *r, const struct cs_terrain *t)
{
	if (r->o->t_srs == NULL)
		return;
	double k = crs_scale(r, r->t_srs, t->center_lat, t->center_lon);
	if (k == 0.0 || fabs(k - 1.0) <= CS_REPROJECT_MAX_SCALE_ERROR)
		return;
	char label[200], msg[400];
	crs_label(r->t_srs, label, sizeof label);
	snprintf(msg, sizeof msg, "--t-srs %s is not in true metres here (scale %.4f at "
		 "%.2f, %.2f): the pixels are %g x %g of its metres but about %.4g x %.4g "
		 "true metres; the sidecar records its metres", label, k, t->center_lat,
		 t->center_lon, t->pixel_x_m, t->pixel_y_m, t->pixel_x_m / k, t->pixel_y_m / k);
	add_warning(&r->log, msg);
}

static int georeference(struct cs_reproject *r, struct cs_terrain *t)
{
	const double *gt = r->gt;
	t->origin_x = gt[0];
	t->origin_y = gt[3];
	t->pixel_x_m = gt[1];
	t->pixel_y_m = -gt[5];
	const char *auth = OSRGetAuthorityName(r->t_srs, NULL);
	const char *code = OSRGetAuthorityCode(r->t_srs, NULL);
	if (auth == NULL || code == NULL) {
		/* a CRS given as WKT or PROJ string may still be an EPSG one */
		OSRAutoIdentifyEPSG(r->t_srs);
		auth = OSRGetAuthorityName(r->t_srs, NULL);
		code = OSRGetAuthorityCode(r->t_srs, NULL);
		log_reset(&r->log); /* not identified is no failure */
	}
	t->epsg = auth && code && strcmp(auth, "EPSG") == 0 ? atoi(code) : 0;
	if ((t->crs_wkt = strdup(r->t_wkt)) == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	double W = t->width, H = t->height;
	double cx[5] = {0.5, W - 0.5, W - 0.5, 0.5, W / 2}, cy[5] = {0.5, 0.5, H - 0.5, H - 0.5, H / 2};
	for (int k = 0; k < 5; k++) {
		cx[k] = gt[0] + cx[k] * gt[1];
		cy[k] = gt[3] + cy[k] * gt[5];
	}
	int rc = transform(r, r->t_srs, r->wgs84, 5, cx, cy);
	if (rc != CS_OK)
		return rc;
	for (int k = 0; k < 4; k++) {
		t->corner_lon[k] = cx[k];
		t->corner_lat[k] = cy[k];
	}
	t->center_lon = cx[4];
	t->center_lat = cy[4];
	return CS_OK;
}

/* The heightfield as a Float32 GeoTIFF in memory (bytes owned by GDAL's
 * /vsimem file at path until it is unlinked). */
static int encode_tif(struct cs_reproject *r, const struct cs_terrain *t, const char *path,
		      int nan_nodata, const void **bytes, size_t *len)
{
	GDALDriverH drv = GDALGetDriverByName("GTiff");
	if (drv == NULL)
		return cs_error(CS_EDATA, "this GDAL has no GTiff driver");
	char **co = CSLSetNameValue(NULL, "COMPRESS", "DEFLATE");
	co = CSLSetNameValue(co, "PREDICTOR", "3");
	log_reset(&r->log);
	GDALDatasetH ds = GDALCreate(drv, path, t->width, t->height, 1, GDT_Float32, co);
	CSLDestroy(co);
	if (ds == NULL)
		return gdal_fail(r, "GeoTIFF");
	GDALRasterBandH b = GDALGetRasterBand(ds, 1);
	GDALSetGeoTransform(ds, r->gt);
	GDALSetSpatialRef(ds, r->t_srs);
	GDALSetMetadataItem(ds, "AREA_OR_POINT", "Area", NULL);
	GDALSetMetadataItem(ds, "SOURCE", r->source, NULL);
	if (nan_nodata)
		GDALSetRasterNoDataValue(b, NAN);
	CPLErr e = GDALRasterIO(b, GF_Write, 0, 0, t->width, t->height, t->h,
				t->width, t->height, GDT_Float32, 0, 0);
	GDALClose(ds);
	vsi_l_offset n = 0;
	*bytes = VSIGetMemFileBuffer(path, &n, FALSE);
	*len = (size_t)n;
	if (e != CE_None || r->log.failed || *bytes == NULL)
		return gdal_fail(r, "GeoTIFF");
	return CS_OK;
}

/* ---- the calls --------------------------------------------------------- */

/* Around every call: GDAL's messages to this handle's log, no .aux.xml. */
static void enter(struct cs_reproject *r)
{
	CPLPushErrorHandlerEx(on_gdal_error, &r->log);
	pthread_once(&gdal_once, register_drivers);
	r->pam = CPLStrdup(CPLGetThreadLocalConfigOption("GDAL_PAM_ENABLED", ""));
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", "NO");
	r->dted = CPLStrdup(CPLGetThreadLocalConfigOption("DTED_VERIFY_CHECKSUM", ""));
	CPLSetThreadLocalConfigOption("DTED_VERIFY_CHECKSUM", "YES");
}

static int leave(struct cs_reproject *r, int rc)
{
	CPLSetThreadLocalConfigOption("GDAL_PAM_ENABLED", r->pam[0] ? r->pam : NULL);
	CPLSetThreadLocalConfigOption("DTED_VERIFY_CHECKSUM", r->dted[0] ? r->dted : NULL);
	CPLFree(r->pam);
	CPLFree(r->dted);
	r->pam = r->dted = NULL;
	CPLPopErrorHandler();
	return rc;
}

/* The CRS options: WGS84, --s-srs, --t-srs (metric), --bounds-srs. */
static int parse_crs_opts(struct cs_reproject *r)
{
	const struct cs_reproject_opts *o = r->o;
	int rc = CS_OK;
	r->wgs84 = OSRNewSpatialReference(NULL);
	if (OSRImportFromEPSG(r->wgs84, 4326) != OGRERR_NONE)
		rc = gdal_fail(r, "WGS84");
	OSRSetAxisMappingStrategy(r->wgs84, OAMS_TRADITIONAL_GIS_ORDER);
	if (rc == CS_OK && o->s_srs && (rc = parse_srs(r, "--s-srs", o->s_srs, &r->s_srs)) == CS_OK &&
	    (r->s_wkt = export_wkt(r->s_srs)) == NULL)
		rc = gdal_fail(r, "--s-srs");
	if (rc == CS_OK && o->t_srs && (rc = parse_srs(r, "--t-srs", o->t_srs, &r->t_srs)) == CS_OK &&
	    !is_metric_projected(r->t_srs))
		rc = cs_error(CS_EINVAL, "--t-srs: '%s' is not a projected CRS in metres", o->t_srs);
	if (rc == CS_OK && o->bounds_srs)
		rc = parse_srs(r, "--bounds-srs", o->bounds_srs, &r->b_srs);
	return rc;
}

int cs_reproject_open(const struct cs_reproject_opts *o, struct cs_reproject **out)
{
	static atomic_uint serial;
	struct cs_reproject *r = calloc(1, sizeof *r);
	*out = r;
	if (r == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	r->opts = *o;
	r->o = &r->opts;
	snprintf(r->mem_dir, sizeof r->mem_dir, "/vsimem/terrainprep-%ld-%u",
		 (long)getpid(), atomic_fetch_add(&serial, 1));
	enter(r);
	int rc = parse_crs_opts(r);
	if (rc == CS_OK)
		rc = open_inputs(r);
	r->log.input = NULL; /* named while it was read */
	if (rc == CS_OK)
		rc = choose_target(r);
	if (rc == CS_OK && (r->t_wkt = export_wkt(r->t_srs)) == NULL)
		rc = gdal_fail(r, "target CRS");
	if (rc == CS_OK)
		rc = choose_extent(r);
	return leave(r, rc);
}

int cs_reproject_warp(struct cs_reproject *rp, struct cs_terrain *t,
		      char *resampling, size_t size)
{
	enter(rp);
	return leave(rp, warp_heights(rp, &t->h, &t->width, &t->height, resampling, size));
}

int cs_reproject_georeference(struct cs_reproject *rp, struct cs_terrain *t)
{
	enter(rp);
	int rc = georeference(rp, t);
	if (rc == CS_OK)
		warn_target_scale(rp, t);
	return leave(rp, rc);
}

int cs_reproject_geotiff(struct cs_reproject *rp, const struct cs_terrain *t,
			 int nan_nodata, const void **bytes, size_t *len)
{
	enter(rp);
	if (rp->tif_path[0])
		VSIUnlink(rp->tif_path);
	snprintf(rp->tif_path, sizeof rp->tif_path, "%s/out.tif", rp->mem_dir);
	return leave(rp, encode_tif(rp, t, rp->tif_path, nan_nodata, bytes, len));
}

/* The mask warped onto the heights' grid (r->gt, w x h): nearest
 * neighbour, outside the mask and its nodata 0; water where the value is
 * not 0.  A mask without a CRS is taken to be in the target CRS. */
static int warp_mask(struct cs_reproject *r, const char *path, int w, int h, float *water)
{
	log_reset(&r->log);
	GDALDatasetH src = GDALOpenEx(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR,
				      NULL, NULL, NULL);
	if (src == NULL) {
		return cs_error(CS_EDATA, "--water-mask %s: %s", path,
				r->log.failure[0] ? r->log.failure : "GDAL cannot open it");
	}
	GDALDatasetH one = NULL; /* its first band, which is all the mask is */
	int rc = first_band(r, src, path, &one);
	if (rc != CS_OK) {
		GDALClose(src);
		return cs_error(rc, "--water-mask %s", cs_errmsg());
	}
	char **av = add(add(add(add(NULL, "-of"), "MEM"), "-ot"), "Float32");
	av = add(add(av, "-t_srs"), r->t_wkt);
	if (GDALGetSpatialRef(src) == NULL)
		av = add(add(av, "-s_srs"), r->t_wkt);
	av = add(av, "-te");
	av = addnum(av, r->gt[0]);
	av = addnum(av, r->gt[3] + h * r->gt[5]);
	av = addnum(av, r->gt[0] + w * r->gt[1]);
	av = addnum(av, r->gt[3]);
	av = addnum(addnum(add(av, "-ts"), w), h);
	av = add(add(av, "-r"), "near");
	av = add(add(av, "-dstnodata"), "0");
	GDALDatasetH mem = NULL;
	rc = warp(r, av, &one, 1, 0, &mem);
	if (one != src)
		GDALClose(one);
	GDALClose(src);
	if (rc != CS_OK)
		return cs_error(rc, "--water-mask %s: %s", path, cs_errmsg());
	CPLErr e = CE_Failure;
	if (GDALGetRasterXSize(mem) == w && GDALGetRasterYSize(mem) == h)
		e = GDALRasterIO(GDALGetRasterBand(mem, 1), GF_Read, 0, 0, w, h, water, w, h,
				 GDT_Float32, 0, 0);
	GDALClose(mem);
	if (e != CE_None || r->log.failed)
		return gdal_fail(r, "reading the warped water mask");
	for (size_t i = 0; i < (size_t)w * h; i++)
		water[i] = isfinite(water[i]) && water[i] != 0.0f ? 1.0f : 0.0f;
	return CS_OK;
}

int cs_reproject_water_mask(struct cs_reproject *rp, const char *path,
			    const struct cs_terrain *t, float *water)
{
	enter(rp);
	return leave(rp, warp_mask(rp, path, t->width, t->height, water));
}

const char *cs_reproject_source(const struct cs_reproject *rp)
{
	return rp->source;
}

const char *cs_reproject_driver(const struct cs_reproject *rp)
{
	return rp->driver;
}

const char *cs_reproject_src_nodata(const struct cs_reproject *rp)
{
	return rp->src_nodata;
}

const char *cs_reproject_warning(const struct cs_reproject *rp)
{
	return rp->log.warning;
}

const char *cs_reproject_gdal_version(void)
{
	return GDALVersionInfo("RELEASE_NAME");
}

void cs_reproject_free(struct cs_reproject *r)
{
	if (r == NULL)
		return;
	for (int i = 0; i < r->nsrc; i++) {
		GDALClose(r->src[i]);
		if (r->whole[i])
			GDALClose(r->whole[i]);
	}
	free(r->src);
	free(r->whole);
	if (r->stdin_path[0])
		VSIUnlink(r->stdin_path);
	if (r->tif_path[0])
		VSIUnlink(r->tif_path);
	free(r->stdin_buf);
	OGRSpatialReferenceH srs[4] = {r->s_srs, r->t_srs, r->b_srs, r->wgs84};
	for (int i = 0; i < 4; i++)
		if (srs[i])
			OSRDestroySpatialReference(srs[i]);
	CPLFree(r->s_wkt);
	CPLFree(r->t_wkt);
	free(r);
}
