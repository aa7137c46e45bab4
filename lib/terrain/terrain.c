/* The heightfield files (see man 1 terrainprep, "SIDECAR"): an EXR (or raw
 * 16-bit, or GeoTIFF) of heights and a JSON sidecar with the georeference.
 * No GDAL here, so that a renderer can read terrain without it. */
#include "terrain/terrain.h"

#include "core/err.h"
#include "io/exr.h"
#include "core/fileio.h"
#include "core/fmt.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define MAX_DATA_BYTES ((size_t)1 << 32)    /* 4 GiB: larger is not ours */
#define MAX_SIDECAR_BYTES ((size_t)1 << 24) /* 16 MiB of JSON */

static const char *const corner_keys[4] = {"upper_left", "upper_right",
					   "lower_right", "lower_left"};

int cs_terrain_sidecar_path(const char *path, char *out, size_t size)
{
	const char *slash = strrchr(path, '/');
	const char *base = slash ? slash + 1 : path;
	const char *dot = strrchr(base, '.');
	size_t stem = dot && dot != base ? (size_t)(dot - path) : strlen(path);
	if (base[0] == '\0')
		return cs_error(CS_EINVAL, "'%s' is not a file name", path);
	if (stem + 6 > size)
		return cs_error(CS_EINVAL, "file name too long: %s", path);
	memcpy(out, path, stem);
	strcpy(out + stem, ".json");
	if (strcmp(out, path) == 0)
		return cs_error(CS_EINVAL,
				"%s: a heightfield cannot be named .json (that is its sidecar's name)",
				path);
	return CS_OK;
}

void cs_terrain_free(struct cs_terrain *t)
{
	free(t->h);
	free(t->crs_wkt);
	free(t->water);
	t->h = NULL;
	t->crs_wkt = NULL;
	t->water = NULL;
}

long cs_terrain_water_count(const struct cs_terrain *t)
{
	long n = 0;
	if (t->water != NULL)
		for (size_t i = 0; i < (size_t)t->width * t->height; i++)
			n += t->water[i] >= 0.5f;
	return n;
}

double cs_terrain_height(const struct cs_terrain *t, double col, double row)
{
	double cmax = t->width - 1, rmax = t->height - 1;
	col = col > 0.0 ? (col < cmax ? col : cmax) : 0.0; /* NaN -> 0 */
	row = row > 0.0 ? (row < rmax ? row : rmax) : 0.0;
	int c0 = (int)col, r0 = (int)row;
	int c1 = c0 < t->width - 1 ? c0 + 1 : c0;
	int r1 = r0 < t->height - 1 ? r0 + 1 : r0;
	double fx = col - c0, fy = row - r0;
	const float *a = t->h + (size_t)r0 * t->width, *b = t->h + (size_t)r1 * t->width;
	double top = a[c0] + (a[c1] - a[c0]) * fx;
	double bot = b[c0] + (b[c1] - b[c0]) * fx;
	return top + (bot - top) * fy;
}

/* ---- writing ---------------------------------------------------------- */

/* The writers below rely on cJSON ignoring additions to a NULL object: an
 * allocation failure leaves a key out, which the reader then reports. */

/* A number written with the fewest digits that read back exactly (cJSON's
 * own printing may drop the last bit), or null if not finite. */
static void add_num(cJSON *o, const char *key, double v)
{
	if (isfinite(v))
		cJSON_AddRawToObject(o, key, cs_num(v).s);
	else
		cJSON_AddNullToObject(o, key);
}

static void add_str(cJSON *o, const char *key, const char *s)
{
	if (s != NULL)
		cJSON_AddStringToObject(o, key, s);
	else
		cJSON_AddNullToObject(o, key);
}

/* parent.key = {k1: v1, k2: v2} */
static void add_pair(cJSON *parent, const char *key, const char *k1, double v1,
		     const char *k2, double v2)
{
	cJSON *o = cJSON_AddObjectToObject(parent, key);
	add_num(o, k1, v1);
	add_num(o, k2, v2);
}

static const char *format_name(enum cs_terrain_format f)
{
	return f == CS_TERRAIN_R16 ? "r16" : f == CS_TERRAIN_TIF ? "tif" : "exr";
}

/* The sidecar's text (malloc'ed), or NULL when out of memory. */
static char *sidecar_json(const char *path, const struct cs_terrain *t,
			  const struct cs_terrain_meta *m, double scale,
			  double offset)
{
	cJSON *root = cJSON_CreateObject();
	add_num(root, "cloudscape_terrain", CS_TERRAIN_FORMAT);
	add_str(root, "generator", m->generator);
	cJSON *o = cJSON_AddObjectToObject(root, "data");
	const char *slash = strrchr(path, '/');
	add_str(o, "file", slash ? slash + 1 : path);
	add_str(o, "format", format_name(m->format));
	add_str(o, "type", m->format == CS_TERRAIN_R16 ? "uint16le" : "float32");
	if (m->format == CS_TERRAIN_R16) {
		add_num(o, "scale", scale);
		add_num(o, "offset", offset);
	} else if (m->format == CS_TERRAIN_EXR) {
		add_str(o, "channel", "Y");
	}
	add_num(root, "width", t->width);
	add_num(root, "height", t->height);
	add_str(root, "row_order",
		m->format == CS_TERRAIN_R16 && m->r16_south_up ? "south-up" : "north-up");
	o = cJSON_AddObjectToObject(root, "crs");
	add_num(o, "epsg", t->epsg > 0 ? t->epsg : NAN); /* null if none */
	add_str(o, "wkt", t->crs_wkt ? t->crs_wkt : "");
	add_pair(root, "origin", "x", t->origin_x, "y", t->origin_y);
	add_pair(root, "pixel_size_m", "x", t->pixel_x_m, "y", t->pixel_y_m);
	o = cJSON_AddObjectToObject(root, "extent");
	add_num(o, "xmin", t->origin_x);
	add_num(o, "ymin", t->origin_y - t->height * t->pixel_y_m);
	add_num(o, "xmax", t->origin_x + t->width * t->pixel_x_m);
	add_num(o, "ymax", t->origin_y);
	add_pair(root, "height_m", "min", t->min_m, "max", t->max_m);
	o = cJSON_AddObjectToObject(root, "nodata");
	add_str(o, "policy", m->nodata_policy);
	add_num(o, "voids", (double)m->voids);
	add_str(root, "resampling", m->resampling);
	o = cJSON_AddObjectToObject(root, "source");
	add_str(o, "file", m->source);
	add_str(o, "driver", m->driver);
	o = cJSON_AddObjectToObject(root, "wgs84");
	for (int c = 0; c < 4; c++)
		add_pair(o, corner_keys[c], "lat", t->corner_lat[c], "lon", t->corner_lon[c]);
	add_pair(o, "center", "lat", t->center_lat, "lon", t->center_lon);
	if (t->water != NULL) {
		o = cJSON_AddObjectToObject(root, "water");
		add_str(o, "channel", "W");
		add_num(o, "samples", (double)cs_terrain_water_count(t));
		add_num(o, "level_m", t->water_level_m); /* null if none */
		add_str(o, "mask", t->water_source[0] ? t->water_source : NULL);
	}
	char *text = root ? cJSON_Print(root) : NULL;
	cJSON_Delete(root);
	return text;
}

static int write_r16(struct cs_outfile *of, const struct cs_terrain *t,
		     const struct cs_terrain_meta *m, double scale)
{
	size_t n = (size_t)t->width * t->height;
	uint8_t *buf = malloc(n * 2);
	if (buf == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (int y = 0; y < t->height; y++) {
		int src = m->r16_south_up ? t->height - 1 - y : y;
		for (int x = 0; x < t->width; x++) {
			double h = t->h[(size_t)src * t->width + x];
			long v = scale > 0.0 ? lrint((h - t->min_m) / scale) : 0;
			v = v < 0 ? 0 : v > 65535 ? 65535 : v;
			size_t i = ((size_t)y * t->width + x) * 2;
			buf[i] = (uint8_t)(v & 0xff);
			buf[i + 1] = (uint8_t)(v >> 8);
		}
	}
	int rc = cs_outfile_write(of, buf, n * 2);
	free(buf);
	return rc;
}

static int write_data(struct cs_outfile *of, const char *path, const struct cs_terrain *t,
		      const struct cs_terrain_meta *m, double scale)
{
	if (m->format == CS_TERRAIN_R16)
		return write_r16(of, t, m, scale);
	if (m->format == CS_TERRAIN_TIF)
		return cs_outfile_write(of, m->bytes, m->nbytes);
	const struct cs_exr_channel ch[2] = {{"Y", 1, t->h, 1}, {"W", 0, t->water, 1}};
	const struct cs_exr_attr attr = {"cloudscapeTerrain", CS_EXR_INT,
					 {CS_TERRAIN_FORMAT, 0, 0}, NULL, 0};
	return cs_exr_write_to(of, path, t->width, t->height, ch, t->water ? 2 : 1, &attr, 1, 0);
}

int cs_terrain_write_into(struct cs_outset *set, const char *path,
			  const struct cs_terrain *t, const struct cs_terrain_meta *m)
{
	char json_path[4096];
	if (strcmp(path, "-") == 0)
		return cs_error(CS_EINVAL,
				"a heightfield is two files (data and sidecar): '-' cannot name them");
	int rc = cs_terrain_sidecar_path(path, json_path, sizeof json_path);
	if (rc != CS_OK)
		return rc;
	if (t->width < 1 || t->height < 1 || t->h == NULL ||
	    !isfinite(t->min_m) || !isfinite(t->max_m) || t->min_m > t->max_m ||
	    !(t->pixel_x_m > 0.0) || !(t->pixel_y_m > 0.0))
		return cs_error(CS_EINVAL, "%s: not a valid heightfield", path);
	if (t->water != NULL && m->format != CS_TERRAIN_EXR)
		return cs_error(CS_EINVAL, "%s: water is stored in EXR heightfields only", path);
	if (m->format == CS_TERRAIN_TIF && m->bytes == NULL)
		return cs_error(CS_EINVAL, "%s: no GeoTIFF to write", path);
	double scale = (t->max_m - t->min_m) / 65535.0;
	if (m->format == CS_TERRAIN_R16)
		for (size_t i = 0; i < (size_t)t->width * t->height; i++)
			if (isnan(t->h[i]))
				return cs_error(CS_EINVAL,
						"%s: 16-bit raw cannot hold voids: fill them (--fill)",
						path);
	char *text = sidecar_json(path, t, m, scale, t->min_m);
	if (text == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	struct cs_outfile *side, *data;
	rc = cs_outset_open(set, json_path, &side);
	if (rc == CS_OK)
		rc = cs_outfile_write(side, text, strlen(text));
	if (rc == CS_OK)
		rc = cs_outfile_write(side, "\n", 1);
	free(text);
	if (rc == CS_OK)
		rc = cs_outset_open(set, path, &data);
	if (rc == CS_OK)
		rc = write_data(data, path, t, m, scale);
	return rc;
}

int cs_terrain_write_as(const char *path, const struct cs_terrain *t,
			const struct cs_terrain_meta *m)
{
	struct cs_outset set;
	cs_outset_init(&set, 0);
	int rc = cs_terrain_write_into(&set, path, t, m);
	if (rc == CS_OK)
		rc = cs_outset_commit(&set); /* no data file without its sidecar */
	cs_outset_abort(&set);
	return rc;
}

int cs_terrain_write(const char *exr_path, const struct cs_terrain *t,
		     const char *source, const char *driver,
		     const char *nodata_policy)
{
	struct cs_terrain_meta m = {.format = CS_TERRAIN_EXR, .source = source,
				    .driver = driver, .nodata_policy = nodata_policy};
	return cs_terrain_write_as(exr_path, t, &m);
}

/* ---- reading ---------------------------------------------------------- */

/* The member at a dotted key path ("a.b"), or NULL. */
static const cJSON *member(const cJSON *o, const char *path)
{
	char key[64];
	while (o != NULL && *path) {
		size_t n = strcspn(path, ".");
		if (n >= sizeof key)
			return NULL;
		memcpy(key, path, n);
		key[n] = '\0';
		o = cJSON_IsObject(o) ? cJSON_GetObjectItemCaseSensitive(o, key) : NULL;
		path += n + (path[n] == '.');
	}
	return o;
}

struct reader {
	const cJSON *root;
	const char *name;
	int rc;
};

/* A finite number at key, or records an error (only the first is kept). */
static double need_num(struct reader *r, const char *key)
{
	const cJSON *v = member(r->root, key);
	if (r->rc == CS_OK && (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)))
		r->rc = cs_error(CS_EDATA, "%s: %s is missing or not a number", r->name, key);
	return r->rc == CS_OK ? v->valuedouble : 0.0;
}

static const char *need_str(struct reader *r, const char *key)
{
	const cJSON *v = member(r->root, key);
	if (r->rc == CS_OK && !cJSON_IsString(v))
		r->rc = cs_error(CS_EDATA, "%s: %s is missing or not a string", r->name, key);
	return r->rc == CS_OK ? v->valuestring : "";
}

static void need_range(struct reader *r, const char *key, double v, double lo,
		       double hi)
{
	if (r->rc == CS_OK && !(v >= lo && v <= hi))
		r->rc = cs_error(CS_EDATA, "%s: %s = %g is outside %g..%g", r->name,
				 key, v, lo, hi);
}

static void need_latlon(struct reader *r, const char *key, double *lat, double *lon)
{
	char k[64];
	snprintf(k, sizeof k, "wgs84.%s.lat", key);
	*lat = need_num(r, k);
	need_range(r, k, *lat, -90.0, 90.0);
	snprintf(k, sizeof k, "wgs84.%s.lon", key);
	*lon = need_num(r, k);
	need_range(r, k, *lon, -180.0, 180.0);
}

static int parse_sidecar(const char *text, size_t len, const char *name,
			 struct cs_terrain *t, int *has_water)
{
	*has_water = 0;
	t->water_level_m = NAN;
	cJSON *root = cJSON_ParseWithLength(text, len);
	if (!cJSON_IsObject(root)) {
		cJSON_Delete(root);
		return cs_error(CS_EDATA, "%s: not a JSON object (corrupt sidecar?)", name);
	}
	struct reader r = {root, name, CS_OK};
	double version = need_num(&r, "cloudscape_terrain");
	if (r.rc == CS_OK && version != CS_TERRAIN_FORMAT)
		r.rc = cs_error(CS_EDATA, "%s: terrain sidecar version %g is not supported (this build reads %d)",
				name, version, CS_TERRAIN_FORMAT);
	const char *fmt = need_str(&r, "data.format");
	if (r.rc == CS_OK && strcmp(fmt, "exr") != 0)
		r.rc = cs_error(CS_EDATA, "%s: describes a \"%.20s\" file; only exr heightfields can be read",
				name, fmt);
	const char *order = need_str(&r, "row_order");
	if (r.rc == CS_OK && strcmp(order, "north-up") != 0)
		r.rc = cs_error(CS_EDATA, "%s: row_order \"%.20s\" is not north-up", name, order);
	double w = need_num(&r, "width"), h = need_num(&r, "height");
	need_range(&r, "width", w, 1, 1 << 30);
	need_range(&r, "height", h, 1, 1 << 30);
	if (r.rc == CS_OK && (w != t->width || h != t->height))
		r.rc = cs_error(CS_EDATA, "%s: says %gx%g but the heights are %dx%d",
				name, w, h, t->width, t->height);
	t->origin_x = need_num(&r, "origin.x");
	t->origin_y = need_num(&r, "origin.y");
	t->pixel_x_m = need_num(&r, "pixel_size_m.x");
	t->pixel_y_m = need_num(&r, "pixel_size_m.y");
	need_range(&r, "pixel_size_m.x", t->pixel_x_m, 1e-6, 1e7);
	need_range(&r, "pixel_size_m.y", t->pixel_y_m, 1e-6, 1e7);
	t->min_m = need_num(&r, "height_m.min");
	t->max_m = need_num(&r, "height_m.max");
	const cJSON *epsg = member(root, "crs.epsg");
	if (r.rc == CS_OK && !cJSON_IsNull(epsg)) {
		double e = need_num(&r, "crs.epsg");
		need_range(&r, "crs.epsg", e, 1, 999999);
		if (r.rc == CS_OK && e != floor(e))
			r.rc = cs_error(CS_EDATA, "%s: crs.epsg: %s is not a whole number",
					name, cs_num(e).s);
		if (r.rc == CS_OK) /* a rejected value never reaches the cast */
			t->epsg = (int)e;
	}
	const char *wkt = need_str(&r, "crs.wkt");
	for (int c = 0; c < 4; c++)
		need_latlon(&r, corner_keys[c], &t->corner_lat[c], &t->corner_lon[c]);
	need_latlon(&r, "center", &t->center_lat, &t->center_lon);
	const cJSON *voids = member(root, "nodata.voids");
	t->voids = cJSON_IsNumber(voids) ? (long)voids->valuedouble : -1;
	const cJSON *pol = member(root, "nodata.policy");
	snprintf(t->nodata_policy, sizeof t->nodata_policy, "%s",
		 cJSON_IsString(pol) ? pol->valuestring : "");
	const cJSON *water = member(root, "water");
	if (r.rc == CS_OK && water != NULL && !cJSON_IsNull(water)) {
		const char *ch = need_str(&r, "water.channel");
		if (r.rc == CS_OK && strcmp(ch, "W") != 0)
			r.rc = cs_error(CS_EDATA, "%s: water.channel \"%.20s\" is not \"W\"",
					name, ch);
		const cJSON *lv = member(root, "water.level_m");
		t->water_level_m = cJSON_IsNumber(lv) ? lv->valuedouble : NAN;
		const cJSON *mk = member(root, "water.mask");
		snprintf(t->water_source, sizeof t->water_source, "%s",
			 cJSON_IsString(mk) ? mk->valuestring : "");
		*has_water = 1;
	}
	if (r.rc == CS_OK && (t->crs_wkt = strdup(wkt)) == NULL)
		r.rc = cs_error(CS_ENOMEM, "out of memory");
	cJSON_Delete(root);
	return r.rc;
}

/* Checks the heights against the sidecar: no voids, the same range. */
static int check_heights(const struct cs_terrain *t, const char *exr_name,
			 const char *json_name)
{
	size_t n = (size_t)t->width * t->height, voids = 0;
	double lo = INFINITY, hi = -INFINITY;
	for (size_t i = 0; i < n; i++) {
		double v = t->h[i];
		if (!isfinite(v)) {
			voids++;
			continue;
		}
		lo = v < lo ? v : lo;
		hi = v > hi ? v : hi;
	}
	if (voids > 0)
		return cs_error(CS_EDATA, "%s: %zu of %zu heights are voids (NaN): make it with --fill nearest or --fill value",
				exr_name, voids, n);
	/* the sidecar's range is the data's, to float precision */
	double tol = 1e-6 * (fabs(lo) + fabs(hi) + 1.0);
	if (fabs(lo - t->min_m) > tol || fabs(hi - t->max_m) > tol)
		return cs_error(CS_EDATA, "%s: height range %g..%g disagrees with the heights (%g..%g)",
				json_name, t->min_m, t->max_m, lo, hi);
	return CS_OK;
}

int cs_terrain_read_mem(const void *exr, size_t exr_len, const char *exr_name,
			const char *json, size_t json_len,
			const char *json_name, struct cs_terrain *t)
{
	memset(t, 0, sizeof *t);
	int has_water = 0;
	int rc = cs_exr_read_float_channel(exr, exr_len, exr_name, "Y", &t->width,
					   &t->height, &t->h);
	if (rc == CS_OK)
		rc = parse_sidecar(json, json_len, json_name, t, &has_water);
	if (rc == CS_OK && has_water) {
		int ww, wh;
		rc = cs_exr_read_float_channel(exr, exr_len, exr_name, "W", &ww, &wh, &t->water);
		if (rc == CS_OK && (ww != t->width || wh != t->height))
			rc = cs_error(CS_EDATA, "%s: water is %dx%d, heights %dx%d", exr_name, ww,
				      wh, t->width, t->height);
	}
	if (rc == CS_OK)
		rc = check_heights(t, exr_name, json_name);
	if (rc != CS_OK)
		cs_terrain_free(t);
	return rc;
}

int cs_terrain_read(const char *exr_path, struct cs_terrain *t)
{
	char json_path[4096];
	unsigned char *data = NULL, *json = NULL;
	size_t len = 0, json_len = 0;
	memset(t, 0, sizeof *t);
	if (strcmp(exr_path, "-") == 0)
		return cs_error(CS_EINVAL,
				"a heightfield is two files (EXR and sidecar): give its file name, not '-'");
	int rc = cs_terrain_sidecar_path(exr_path, json_path, sizeof json_path);
	if (rc != CS_OK)
		return rc;
	rc = cs_read_all(exr_path, MAX_DATA_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	if (access(json_path, F_OK) != 0)
		rc = cs_error(CS_EDATA, "%s: its sidecar %s is missing (%s)", exr_path,
			      json_path, strerror(errno));
	else
		rc = cs_read_all(json_path, MAX_SIDECAR_BYTES, &json, &json_len);
	if (rc == CS_OK)
		rc = cs_terrain_read_mem(data, len, exr_path, (const char *)json,
					 json_len, json_path, t);
	free(data);
	free(json);
	return rc;
}
