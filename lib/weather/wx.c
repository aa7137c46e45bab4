#include "weather/wx.h"
#include "weather/provider.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/fmt.h"
#include "core/json.h"
#include "core/time.h"

#include <cjson/cJSON.h>

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_FILE_BYTES ((size_t)16 << 20)

static const char *const genus_names[CS_GENUS_COUNT] = {
	"cirrus", "cirrocumulus", "cirrostratus", "altocumulus", "altostratus",
	"nimbostratus", "stratocumulus", "stratus", "cumulus", "cumulonimbus",
};

const char *cs_genus_name(enum cs_genus g)
{
	return (unsigned)g < CS_GENUS_COUNT ? genus_names[g] : "unknown";
}

int cs_genus_from_name(const char *name)
{
	for (int g = 0; name != NULL && g < CS_GENUS_COUNT; g++)
		if (strcasecmp(name, genus_names[g]) == 0)
			return g;
	return -1;
}

void cs_wx_default(struct cs_wx *wx)
{
	static const struct cs_wx_layer fair[2] = {
		{CS_CUMULUS, 0.35, 1500, 2700},
		{CS_CIRRUS, 0.2, 9000, 9600},
	};
	memset(wx, 0, sizeof *wx);
	wx->time_utc = cs_days_from_civil(2021, 6, 14) * 86400.0 + 14 * 3600.0;
	snprintf(wx->site.name, sizeof wx->site.name, "Bern");
	wx->site.lat_deg = 46.95;
	wx->site.lon_deg = 7.44;
	wx->site.alt_m = 540;
	wx->nlayers = 2;
	memcpy(wx->layers, fair, sizeof fair);
	wx->wind_speed_m_s = 4;
	wx->wind_from_deg = 250;
	wx->visibility_m = 30000;
	wx->temperature_c = NAN;
}

/* A number member of a struct: its JSON key, default and range. */
struct field {
	const char *key;
	size_t off;
	int required;
	double def, lo, hi;
};

#define F(type, member, req, def, lo, hi) \
	{#member, offsetof(type, member), req, def, lo, hi}
#define COUNT(a) (sizeof (a) / sizeof *(a))

static const struct field site_fields[] = {
	F(struct cs_wx_site, lat_deg, 1, 0, -90, 90),
	F(struct cs_wx_site, lon_deg, 1, 0, -180, 180),
	F(struct cs_wx_site, alt_m, 0, 0, -500, 9000),
};
static const struct field layer_fields[] = {
	F(struct cs_wx_layer, coverage, 1, 0, 0, 1),
	F(struct cs_wx_layer, base_m, 1, 0, -500, 20000),
	F(struct cs_wx_layer, top_m, 1, 0, -500, 20000),
};
static const struct field wx_fields[] = {
	F(struct cs_wx, precipitation_mm_h, 0, 0, 0, 500),
	F(struct cs_wx, convective_mm_h, 0, 0, 0, 500),
	F(struct cs_wx, visibility_m, 0, 30000, 1, 1e6),
	F(struct cs_wx, fog_probability, 0, 0, 0, 1),
	F(struct cs_wx, snow_fraction, 0, 0, 0, 1),
};
/* "observed": the radiation keys all three or none; the cover alone. */
static const struct field radiation_fields[] = {
	F(struct cs_wx_observed, ghi_w_m2, 1, 0, 0, 2000),
	F(struct cs_wx_observed, dni_w_m2, 1, 0, 0, 2000),
	F(struct cs_wx_observed, dhi_w_m2, 1, 0, 0, 2000),
};
static const struct field cover_fields[] = {
	F(struct cs_wx_observed, total_cloud_cover, 1, 0, 0, 1),
};
/* Optional: NaN (unknown) when absent or null, and then not written. */
#define TEMP_LO -100.0
#define TEMP_HI 70.0
/* Required only inside a "wind" object (a speed without a direction is no
 * wind); no object at all is calm. */
static const struct field wind_fields[] = {
	{"speed_m_s", offsetof(struct cs_wx, wind_speed_m_s), 1, 0, 0, 100},
	{"from_deg", offsetof(struct cs_wx, wind_from_deg), 1, 0, 0, 360},
};
/* "drift" (cloudwx/2, optional): all members required inside it. */
static const struct field drift_fields[] = {
	F(struct cs_wx_drift, east_m, 1, 0, -CS_WX_MAX_DRIFT_M, CS_WX_MAX_DRIFT_M),
	F(struct cs_wx_drift, north_m, 1, 0, -CS_WX_MAX_DRIFT_M, CS_WX_MAX_DRIFT_M),
	F(struct cs_wx_drift, axis_deg, 1, 0, 0, 360),
};
static const struct field far_fields[] = {
	F(struct cs_wx_far, precipitation_mm_h, 0, 0, 0, 500),
	F(struct cs_wx_far, visibility_m, 0, 30000, 1, 1e6),
};

/* ---- validation: ranges of the struct ---------------------------------- */

/* Written as !(in range) so that NaN fails too. */
static int check(const char *pre, const char *key, double v, double lo,
		 double hi)
{
	if (v >= lo && v <= hi)
		return CS_OK;
	return cs_error(CS_EDATA, "%s%s: %s is outside %s..%s", pre, key,
			cs_num(v).s, cs_num(lo).s, cs_num(hi).s);
}

static int check_fields(const char *pre, const struct field *f, size_t n,
			const void *base)
{
	for (size_t i = 0; i < n; i++)
		CS_TRY(check(pre, f[i].key,
			  *(const double *)((const char *)base + f[i].off),
			  f[i].lo, f[i].hi));
	return CS_OK;
}

static int check_site(const char *pre, const struct cs_wx_site *s)
{
	if (memchr(s->name, '\0', sizeof s->name) == NULL)
		return cs_error(CS_EDATA, "%sname: not terminated", pre);
	return check_fields(pre, site_fields, COUNT(site_fields), s);
}

static int check_layers(const char *pre, int n, const struct cs_wx_layer *l)
{
	if (n < 0 || n > CS_WX_MAX_LAYERS)
		return cs_error(CS_EDATA, "%slayers: %d layers, at most %d",
				pre, n, CS_WX_MAX_LAYERS);
	for (int i = 0; i < n; i++) {
		char p[48];
		snprintf(p, sizeof p, "%slayers[%d].", pre, i);
		if ((unsigned)l[i].genus >= CS_GENUS_COUNT)
			return cs_error(CS_EDATA, "%sgenus: %d is not a genus", p,
					(int)l[i].genus);
		CS_TRY(check_fields(p, layer_fields, COUNT(layer_fields), &l[i]));
		/* thinner than 10 m is no cloud a renderer can march */
		if (!(l[i].top_m >= l[i].base_m + 10))
			return cs_error(CS_EDATA, "%stop_m: %s is not at least "
					"10 m above base_m %s", p,
					cs_num(l[i].top_m).s, cs_num(l[i].base_m).s);
	}
	return CS_OK;
}

int cs_wx_validate(const struct cs_wx *wx)
{
	if (wx == NULL)
		return cs_error(CS_EINVAL, "cs_wx_validate: no state");
	/* four-digit years, so that the time reads back (cs_time_parse) */
	if (!(wx->time_utc >= cs_days_from_civil(0, 1, 1) * 86400.0 &&
	      wx->time_utc < cs_days_from_civil(10000, 1, 1) * 86400.0))
		return cs_error(CS_EDATA, "time_utc: %s s is outside years "
				"0000..9999", cs_num(wx->time_utc).s);
	CS_TRY(check_site("site.", &wx->site));
	CS_TRY(check_layers("", wx->nlayers, wx->layers));
	CS_TRY(check_fields("", wx_fields, COUNT(wx_fields), wx));
	CS_TRY(check("", "convective_mm_h", wx->convective_mm_h, 0,
		  wx->precipitation_mm_h));
	if (!isnan(wx->temperature_c))
		CS_TRY(check("", "temperature_c", wx->temperature_c, TEMP_LO,
			  TEMP_HI));
	if (wx->observed.has_radiation)
		CS_TRY(check_fields("observed.", radiation_fields,
				 COUNT(radiation_fields), &wx->observed));
	if (wx->observed.has_cloud_cover)
		CS_TRY(check_fields("observed.", cover_fields, COUNT(cover_fields),
				 &wx->observed));
	CS_TRY(check_fields("wind.", wind_fields, COUNT(wind_fields), wx));
	if (wx->drift.known) {
		CS_TRY(check_fields("drift.", drift_fields, COUNT(drift_fields),
				 &wx->drift));
		if (!(wx->drift.since_utc >= cs_days_from_civil(0, 1, 1) * 86400.0 &&
		      wx->drift.since_utc < cs_days_from_civil(10000, 1, 1) * 86400.0))
			return cs_error(CS_EDATA, "drift.since_utc: %s s is outside "
					"years 0000..9999", cs_num(wx->drift.since_utc).s);
	}
	if (wx->nfar < 0 || wx->nfar > CS_WX_MAX_FAR)
		return cs_error(CS_EDATA, "far: %d sites, at most %d", wx->nfar,
				CS_WX_MAX_FAR);
	for (int i = 0; i < wx->nfar; i++) {
		char p[32], ps[40];
		snprintf(p, sizeof p, "far[%d].", i);
		snprintf(ps, sizeof ps, "far[%d].site.", i);
		CS_TRY(check_site(ps, &wx->far[i].site));
		CS_TRY(check_layers(p, wx->far[i].nlayers, wx->far[i].layers));
		CS_TRY(check_fields(p, far_fields, COUNT(far_fields), &wx->far[i]));
	}
	return CS_OK;
}

/* ---- parsing: types and presence --------------------------------------- */

/* The member key of obj, *out = NULL if absent.  Absent and required, or
 * present with another type than kind (a cJSON type bit), is an error. */
static int get(const cJSON *obj, const char *pre, const char *key, int kind,
	       int required, const cJSON **out)
{
	const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
	*out = NULL;
	if (it == NULL)
		return required ? cs_error(CS_EDATA, "%s%s: missing (required)",
					   pre, key) : CS_OK;
	if ((it->type & 0xff) != kind)
		return cs_error(CS_EDATA, "%s%s: expected %s", pre, key,
				kind == cJSON_Number ? "a number" :
				kind == cJSON_String ? "a string" :
				kind == cJSON_Array ? "an array" : "an object");
	*out = it;
	return CS_OK;
}

/* Sets the fields of base from obj, or to their defaults where absent;
 * obj NULL (an optional object left out) gives every default. */
static int parse_fields(const cJSON *obj, const char *pre,
			const struct field *f, size_t n, void *base)
{
	for (size_t i = 0; i < n; i++) {
		const cJSON *it;
		CS_TRY(get(obj, pre, f[i].key, cJSON_Number,
			f[i].required && obj != NULL, &it));
		if (it != NULL && !isfinite(it->valuedouble))
			return cs_error(CS_EDATA, "%s%s: expected a finite "
					"number", pre, f[i].key);
		*(double *)((char *)base + f[i].off) =
			it != NULL ? it->valuedouble : f[i].def;
	}
	return CS_OK;
}

/* The member "site" of obj. */
static int parse_site(const cJSON *obj, const char *pre, struct cs_wx_site *s)
{
	const cJSON *site, *name;
	char p[40];
	snprintf(p, sizeof p, "%ssite.", pre);
	CS_TRY(get(obj, pre, "site", cJSON_Object, 1, &site));
	CS_TRY(get(site, p, "name", cJSON_String, 0, &name));
	if (name != NULL && strlen(name->valuestring) >= sizeof s->name)
		return cs_error(CS_EDATA, "%sname: longer than %zu bytes", p,
				sizeof s->name - 1);
	snprintf(s->name, sizeof s->name, "%s", name ? name->valuestring : "");
	return parse_fields(site, p, site_fields, COUNT(site_fields), s);
}

static int unknown_genus(const char *pre, const char *name)
{
	char list[160] = "";
	for (int g = 0; g < CS_GENUS_COUNT; g++)
		snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
			 g ? ", " : "", genus_names[g]);
	return cs_error(CS_EDATA, "%sgenus: unknown genus \"%.40s\" (expected "
			"one of %s)", pre, name, list);
}

/* The member "layers" of obj. */
static int parse_layers(const cJSON *obj, const char *pre, int *n,
			struct cs_wx_layer *layers)
{
	const cJSON *arr, *el, *genus;
	CS_TRY(get(obj, pre, "layers", cJSON_Array, 1, &arr));
	if (cJSON_GetArraySize(arr) > CS_WX_MAX_LAYERS)
		return cs_error(CS_EDATA, "%slayers: %d layers, at most %d", pre,
				cJSON_GetArraySize(arr), CS_WX_MAX_LAYERS);
	*n = 0;
	cJSON_ArrayForEach(el, arr) {
		char p[48];
		snprintf(p, sizeof p, "%slayers[%d]", pre, *n);
		if (!cJSON_IsObject(el))
			return cs_error(CS_EDATA, "%s: expected an object", p);
		strcat(p, ".");
		CS_TRY(get(el, p, "genus", cJSON_String, 1, &genus));
		int g = cs_genus_from_name(genus->valuestring);
		if (g < 0)
			return unknown_genus(p, genus->valuestring);
		layers[*n].genus = (enum cs_genus)g;
		CS_TRY(parse_fields(el, p, layer_fields, COUNT(layer_fields),
				 &layers[(*n)++]));
	}
	return CS_OK;
}

static int parse_far(const cJSON *root, struct cs_wx *wx)
{
	const cJSON *arr, *el;
	CS_TRY(get(root, "", "far", cJSON_Array, 0, &arr));
	if (cJSON_GetArraySize(arr) > CS_WX_MAX_FAR)
		return cs_error(CS_EDATA, "far: %d sites, at most %d",
				cJSON_GetArraySize(arr), CS_WX_MAX_FAR);
	cJSON_ArrayForEach(el, arr) {
		struct cs_wx_far *f = &wx->far[wx->nfar];
		char p[32];
		snprintf(p, sizeof p, "far[%d]", wx->nfar++);
		if (!cJSON_IsObject(el))
			return cs_error(CS_EDATA, "%s: expected an object", p);
		strcat(p, ".");
		CS_TRY(parse_site(el, p, &f->site));
		CS_TRY(parse_layers(el, p, &f->nlayers, f->layers));
		CS_TRY(parse_fields(el, p, far_fields, COUNT(far_fields), f));
	}
	return CS_OK;
}

/* "temperature_c": a number, or absent or null (unknown: NaN). */
static int parse_temperature(const cJSON *root, struct cs_wx *wx)
{
	const cJSON *it = cJSON_GetObjectItemCaseSensitive(root, "temperature_c");
	wx->temperature_c = NAN;
	if (it == NULL || cJSON_IsNull(it))
		return CS_OK;
	if (!cJSON_IsNumber(it) || !isfinite(it->valuedouble))
		return cs_error(CS_EDATA, "temperature_c: expected a finite number "
				"or null");
	wx->temperature_c = it->valuedouble;
	return CS_OK;
}

/* "observed" (optional): ghi_w_m2, dni_w_m2 and dhi_w_m2 together, and
 * total_cloud_cover, each group optional. */
static int parse_observed(const cJSON *root, struct cs_wx_observed *ob)
{
	const cJSON *obj;
	static const char *const rad[3] = {"ghi_w_m2", "dni_w_m2", "dhi_w_m2"};
	memset(ob, 0, sizeof *ob);
	CS_TRY(get(root, "", "observed", cJSON_Object, 0, &obj));
	if (obj == NULL)
		return CS_OK;
	for (int i = 0; i < 3; i++)
		ob->has_radiation |= cJSON_HasObjectItem(obj, rad[i]);
	if (ob->has_radiation)
		CS_TRY(parse_fields(obj, "observed.", radiation_fields,
				 COUNT(radiation_fields), ob));
	ob->has_cloud_cover = cJSON_HasObjectItem(obj, "total_cloud_cover");
	if (ob->has_cloud_cover)
		CS_TRY(parse_fields(obj, "observed.", cover_fields,
				 COUNT(cover_fields), ob));
	return CS_OK;
}

/* "drift" (optional, cloudwx/2): since_utc, east_m, north_m, axis_deg. */
static int parse_drift(const cJSON *root, struct cs_wx_drift *d)
{
	const cJSON *obj, *since;
	memset(d, 0, sizeof *d);
	CS_TRY(get(root, "", "drift", cJSON_Object, 0, &obj));
	if (obj == NULL)
		return CS_OK;
	CS_TRY(get(obj, "drift.", "since_utc", cJSON_String, 1, &since));
	if (cs_time_parse(since->valuestring, &d->since_utc) != CS_OK)
		return cs_error(CS_EDATA, "drift.since_utc: %s", cs_errmsg());
	CS_TRY(parse_fields(obj, "drift.", drift_fields, COUNT(drift_fields), d));
	d->known = 1;
	return CS_OK;
}

/* Fills *wx from the parsed document; the ranges are checked after. */
static int parse_root(const cJSON *root, struct cs_wx *wx)
{
	const cJSON *it;
	if (!cJSON_IsObject(root))
		return cs_error(CS_EDATA, "expected a JSON object");
	CS_TRY(get(root, "", "schema", cJSON_String, 1, &it));
	int v1 = strcmp(it->valuestring, CS_WX_SCHEMA_V1) == 0;
	if (!v1 && strcmp(it->valuestring, CS_WX_SCHEMA) != 0)
		return cs_error(CS_EDATA, "schema: unsupported version \"%.40s\" "
				"(this program reads \"%s\" and \"%s\")",
				it->valuestring, CS_WX_SCHEMA, CS_WX_SCHEMA_V1);
	CS_TRY(get(root, "", "time_utc", cJSON_String, 1, &it));
	if (cs_time_parse(it->valuestring, &wx->time_utc) != CS_OK)
		return cs_error(CS_EDATA, "time_utc: %s", cs_errmsg());
	CS_TRY(parse_site(root, "", &wx->site));
	CS_TRY(parse_layers(root, "", &wx->nlayers, wx->layers));
	CS_TRY(parse_fields(root, "", wx_fields, COUNT(wx_fields), wx));
	CS_TRY(parse_temperature(root, wx));
	CS_TRY(parse_observed(root, &wx->observed));
	CS_TRY(get(root, "", "wind", cJSON_Object, 0, &it));
	CS_TRY(parse_fields(it, "wind.", wind_fields, COUNT(wind_fields), wx));
	/* a cloudwx/1 state has no drift (an unknown key there is ignored) */
	if (!v1)
		CS_TRY(parse_drift(root, &wx->drift));
	wx->nfar = 0;
	return parse_far(root, wx);
}

/* "what at byte offset N near "excerpt"" (cs_json_near). */
static int syntax_error(const char *what, const char *s, size_t len, size_t at)
{
	size_t from, to;
	cs_json_near(s, len, at, &from, &to);
	return cs_error(CS_EDATA, "%s at byte offset %zu near \"%.*s\"%s", what,
			at, (int)(to - from), s + from,
			at + 1 >= len ? " (end of input)" : "");
}

/* The state whose JSON starts at json[at] (past any blank): lines: JSON
 * Lines, so text after the object's line is ignored, and *next (when not
 * NULL) is where the text after that line starts. */
static int parse_object(const char *json, size_t len, size_t at, struct cs_wx *wx,
			int lines, size_t *next)
{
	const char *end = NULL;
	/* return_parse_end, not cJSON_GetErrorPtr(): that one is a global */
	cJSON *root = cJSON_ParseWithLengthOpts(json + at, len - at, &end, 0);
	if (root == NULL)
		return syntax_error("malformed JSON", json, len,
				    end ? (size_t)(end - json) : at);
	at = (size_t)(end - json);
	while (at < len && strchr(lines ? " \t\r" : " \t\r\n", json[at]))
		at++;
	if (at < len && !(lines && json[at] == '\n')) {
		cJSON_Delete(root);
		return syntax_error("unexpected text after the JSON object",
				    json, len, at);
	}
	if (next != NULL)
		*next = at < len ? at + 1 : len;
	struct cs_wx w;
	memset(&w, 0, sizeof w);
	int rc = parse_root(root, &w);
	int no_schema = cJSON_IsObject(root) &&
			cJSON_GetObjectItemCaseSensitive(root, "schema") == NULL;
	cJSON_Delete(root);
	if (rc != CS_OK && no_schema) {
		/* a provider's file where a state belongs: say what it is */
		char why[512];
		enum cs_provider p;
		snprintf(why, sizeof why, "%s", cs_errmsg());
		if (cs_provider_detect(json, len, &p) == CS_OK)
			return cs_error(CS_EDATA, "this is %s response (hourly weather), "
					"not a cloudwx weather state: make a state from "
					"it with wxinterp --at TIME FILE",
					p == CS_PROVIDER_METEOBLUE ? "a meteoblue" : "an Open-Meteo");
		return cs_error(rc, "%s", why);
	}
	if (rc == CS_OK)
		rc = cs_wx_validate(&w);
	if (rc == CS_OK)
		*wx = w;
	return rc;
}

/* Where the first state of json starts, after checking for NUL bytes and
 * an empty text. */
static int text_start(const char *json, size_t len, size_t *at)
{
	const char *nul = memchr(json, '\0', len);
	if (nul != NULL)
		return cs_error(CS_EDATA, "NUL byte at byte offset %zu",
				(size_t)(nul - json));
	*at = 0;
	while (*at < len && strchr(" \t\r\n", json[*at]))
		(*at)++;
	if (*at == len)
		return cs_error(CS_EDATA, "empty input: no JSON object");
	return CS_OK;
}

static int parse_text(const char *json, size_t len, struct cs_wx *wx,
		      int lines)
{
	if (json == NULL || wx == NULL)
		return cs_error(CS_EINVAL, "cs_wx_parse: no input or no state");
	size_t at;
	CS_TRY(text_start(json, len, &at));
	return parse_object(json, len, at, wx, lines, NULL);
}

int cs_wx_parse(const char *json, size_t len, struct cs_wx *wx)
{
	return parse_text(json, len, wx, 0);
}

int cs_wx_parse_lines(const char *json, size_t len, struct cs_wx *wx)
{
	return parse_text(json, len, wx, 1);
}

int cs_wx_read(const char *path, struct cs_wx *wx)
{
	unsigned char *data;
	size_t len;
	if (path == NULL || wx == NULL)
		return cs_error(CS_EINVAL, "cs_wx_read: no path or no state");
	int rc = cs_read_all(path, MAX_FILE_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	rc = parse_text((const char *)data, len, wx, 1);
	free(data);
	if (rc != CS_OK)
		rc = cs_error(rc, "%s: %s",
			      strcmp(path, "-") == 0 ? "standard input" : path,
			      cs_errmsg());
	return rc;
}

/* ---- series ------------------------------------------------------------- */

/* The line of byte at (1 for the first). */
static long line_of(const char *text, size_t at)
{
	long line = 1;
	for (size_t i = 0; i < at; i++)
		line += text[i] == '\n';
	return line;
}

/* Takes text (malloc'ed, len bytes) into s and finds every state in it. */
static int series_scan(struct cs_wx_series *s, char *text, size_t len, const char *name)
{
	memset(s, 0, sizeof *s);
	s->text = text;
	s->len = len;
	size_t at, cap = 0;
	int rc = text_start(text, len, &at);
	struct cs_wx w;
	while (rc == CS_OK && at < len) {
		if (s->n == CS_WX_SERIES_MAX) {
			rc = cs_error(CS_EDATA, "more than %d states", CS_WX_SERIES_MAX);
			break;
		}
		if ((size_t)s->n == cap) {
			size_t *ns = realloc(s->start, (cap = cap ? 2 * cap : 64) * sizeof *ns);
			if (ns == NULL) {
				rc = cs_error(CS_ENOMEM, "out of memory reading the states");
				break;
			}
			s->start = ns;
		}
		s->start[s->n] = at;
		size_t next;
		rc = parse_object(text, len, at, &w, 1, &next);
		if (rc != CS_OK) { /* the first state's error is a single state's */
			if (s->n > 0)
				rc = cs_error(rc, "state %d (line %ld): %s", s->n + 1,
					      line_of(text, at), cs_errmsg());
			break;
		}
		s->n++;
		at = next;
		while (at < len && strchr(" \t\r\n", text[at]))
			at++;
	}
	if (rc != CS_OK) {
		rc = cs_error(rc, "%s: %s", name, cs_errmsg());
		cs_wx_series_free(s);
	}
	return rc;
}

int cs_wx_series_parse(const char *json, size_t len, struct cs_wx_series *s)
{
	if (json == NULL || s == NULL)
		return cs_error(CS_EINVAL, "cs_wx_series_parse: no input or no series");
	char *copy = malloc(len ? len : 1);
	if (copy == NULL)
		return cs_error(CS_ENOMEM, "out of memory reading the states");
	memcpy(copy, json, len);
	return series_scan(s, copy, len, "input");
}

int cs_wx_series_read(const char *path, struct cs_wx_series *s)
{
	unsigned char *data;
	size_t len;
	if (path == NULL || s == NULL)
		return cs_error(CS_EINVAL, "cs_wx_series_read: no path or no series");
	memset(s, 0, sizeof *s);
	int rc = cs_read_all(path, CS_WX_SERIES_MAX_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	return series_scan(s, (char *)data, len,
			   strcmp(path, "-") == 0 ? "standard input" : path);
}

int cs_wx_series_get(const struct cs_wx_series *s, int i, struct cs_wx *wx)
{
	if (s == NULL || wx == NULL || i < 0 || i >= s->n)
		return cs_error(CS_EINVAL, "cs_wx_series_get: no state %d", i + 1);
	return parse_object(s->text, s->len, s->start[i], wx, 1, NULL);
}

void cs_wx_series_free(struct cs_wx_series *s)
{
	free(s->text);
	free(s->start);
	memset(s, 0, sizeof *s);
}

/* ---- writing ------------------------------------------------------------ */

/* The precision each quantity is written with: what it means, not the
 * arithmetic's 17 digits (see cloudwx(5)).  A state read back and written
 * again gives the same bytes. */
#define DEG(v) cs_num_round((v), 6).s   /* degrees of lat/lon: 0.11 m */
#define M(v) cs_num_round((v), 0).s     /* heights and distances: 1 m */
#define FRAC(v) cs_num_round((v), 3).s  /* fractions 0..1: 0.1 % */
#define MM_H(v) cs_num_round((v), 3).s  /* mm/h: drizzle stays above 0 */
#define M_S(v) cs_num_round((v), 2).s   /* wind, m/s */
#define AZ(v) cs_num_round((v), 1).s    /* directions, degrees */
#define TEMP(v) cs_num_round((v), 2).s  /* degrees Celsius, as providers give */
#define W_M2(v) cs_num_round((v), 2).s  /* irradiance, W/m^2, as providers give */
#define DRIFT(v) cs_num_round((v), 2).s /* drift, m: 1 cm, so a frame a second
					   apart moves by what its wind says */

static void put_site(FILE *f, const struct cs_wx_site *s)
{
	fputs("\"site\":{\"name\":\"", f);
	for (const unsigned char *c = (const unsigned char *)s->name; *c; c++)
		if (*c == '"' || *c == '\\')
			fprintf(f, "\\%c", *c);
		else if (*c < 0x20)
			fprintf(f, "\\u%04x", *c);
		else
			fputc(*c, f);
	fprintf(f, "\",\"lat_deg\":%s,\"lon_deg\":%s,\"alt_m\":%s}",
		DEG(s->lat_deg), DEG(s->lon_deg), M(s->alt_m));
}

static void put_layers(FILE *f, int n, const struct cs_wx_layer *l)
{
	fputs(",\"layers\":[", f);
	/* a layer is at least 10 m thick, and rounding both ends to 1 m
	 * keeps it so (rounding is monotonic and 10 is even) */
	for (int i = 0; i < n; i++)
		fprintf(f, "%s{\"genus\":\"%s\",\"coverage\":%s,\"base_m\":%s,"
			"\"top_m\":%s}", i ? "," : "", cs_genus_name(l[i].genus),
			FRAC(l[i].coverage), M(l[i].base_m), M(l[i].top_m));
	fputc(']', f);
}

/* "observed", only with what the provider had. */
static void put_observed(FILE *f, const struct cs_wx_observed *ob)
{
	if (!ob->has_radiation && !ob->has_cloud_cover)
		return;
	fputs(",\"observed\":{", f);
	if (ob->has_radiation)
		fprintf(f, "\"ghi_w_m2\":%s,\"dni_w_m2\":%s,\"dhi_w_m2\":%s",
			W_M2(ob->ghi_w_m2), W_M2(ob->dni_w_m2), W_M2(ob->dhi_w_m2));
	if (ob->has_cloud_cover)
		fprintf(f, "%s\"total_cloud_cover\":%s",
			ob->has_radiation ? "," : "",
			FRAC(ob->total_cloud_cover));
	fputc('}', f);
}

int cs_wx_to_json(const struct cs_wx *wx, char **json)
{
	if (json == NULL)
		return cs_error(CS_EINVAL, "cs_wx_to_json: nowhere to put it");
	*json = NULL;
	int rc = cs_wx_validate(wx);
	if (rc != CS_OK)
		return rc;
	char t[40], *buf = NULL;
	size_t size;
	FILE *f = open_memstream(&buf, &size);
	if (f == NULL)
		return cs_error(CS_ENOMEM, "out of memory writing the state");
	cs_time_format(wx->time_utc, t, sizeof t);
	fprintf(f, "{\"schema\":\"%s\",\"time_utc\":\"%s\",", CS_WX_SCHEMA, t);
	put_site(f, &wx->site);
	put_layers(f, wx->nlayers, wx->layers);
	fprintf(f, ",\"precipitation_mm_h\":%s,\"convective_mm_h\":%s,"
		"\"wind\":{\"speed_m_s\":%s,\"from_deg\":%s},\"visibility_m\":%s,"
		"\"fog_probability\":%s", MM_H(wx->precipitation_mm_h),
		MM_H(wx->convective_mm_h), M_S(wx->wind_speed_m_s),
		AZ(wx->wind_from_deg), M(wx->visibility_m), FRAC(wx->fog_probability));
	fprintf(f, ",\"snow_fraction\":%s", FRAC(wx->snow_fraction));
	if (!isnan(wx->temperature_c))
		fprintf(f, ",\"temperature_c\":%s", TEMP(wx->temperature_c));
	put_observed(f, &wx->observed);
	if (wx->drift.known) {
		char since[40];
		cs_time_format(wx->drift.since_utc, since, sizeof since);
		fprintf(f, ",\"drift\":{\"since_utc\":\"%s\",\"east_m\":%s,"
			"\"north_m\":%s,", since, DRIFT(wx->drift.east_m),
			DRIFT(wx->drift.north_m));
		fprintf(f, "\"axis_deg\":%s}", AZ(wx->drift.axis_deg));
	}
	for (int i = 0; i < wx->nfar; i++) {
		fputs(i ? ",{" : ",\"far\":[{", f);
		put_site(f, &wx->far[i].site);
		put_layers(f, wx->far[i].nlayers, wx->far[i].layers);
		fprintf(f, ",\"precipitation_mm_h\":%s,\"visibility_m\":%s}%s",
			MM_H(wx->far[i].precipitation_mm_h), M(wx->far[i].visibility_m),
			i == wx->nfar - 1 ? "]" : "");
	}
	fputc('}', f);
	int bad = ferror(f);
	if (fclose(f) != 0 || bad) {
		free(buf);
		return cs_error(CS_ENOMEM, "out of memory writing the state");
	}
	*json = buf;
	return CS_OK;
}

/* ---- drift in time ------------------------------------------------------- */

void cs_wx_drift_at(const struct cs_wx *wx, double t, double *east_m,
		    double *north_m)
{
	double e = 0.0, n = 0.0; /* east_m may be wx's own member */
	if (wx->drift.known) {
		double from = wx->wind_from_deg * (3.14159265358979323846 / 180.0);
		double dt = t - wx->time_utc;
		/* the wind blows toward the opposite of where it comes from */
		e = wx->drift.east_m - sin(from) * wx->wind_speed_m_s * dt;
		n = wx->drift.north_m - cos(from) * wx->wind_speed_m_s * dt;
	}
	*east_m = e;
	*north_m = n;
}

void cs_wx_retime(struct cs_wx *wx, double t)
{
	cs_wx_drift_at(wx, t, &wx->drift.east_m, &wx->drift.north_m);
	/* the provider's instant values were the old time's: at another sun
	 * they would misstate the light (and the renderer fits its sheets to
	 * the DNI) */
	if (t != wx->time_utc)
		wx->observed.has_radiation = 0, wx->observed.has_cloud_cover = 0;
	wx->time_utc = t;
}
