#include "weather/provider.h"

#include "core/err.h"
#include "core/fmt.h"
#include "core/json.h"
#include "core/time.h"

#include <cjson/cJSON.h>

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ---- the variables and their units -------------------------------------- */

enum unit_kind { U_NONE, U_PERCENT, U_PRECIP, U_SPEED, U_DEGREE, U_LENGTH, U_TEMP,
		 U_SNOW, U_IRRADIANCE };

/* The unit of each kind after parsing, for messages. */
static const char *const si_unit[] = {"", "%", "mm", "m/s", "deg", "m", "C", "cm", "W/m2"};

/* A unit as each provider spells it: value in cloudscape units =
 * value * scale + offset. */
struct unit {
	const char *mb, *om;
	double scale, offset;
};

static const struct unit unit_table[][5] = {
	[U_NONE] = {{NULL, NULL, 1, 0}},
	[U_PERCENT] = {{"percent", "%", 1, 0}, {NULL, NULL, 0, 0}},
	[U_PRECIP] = {{"mm", "mm", 1, 0}, {"inch", "inch", 25.4, 0}, {NULL, NULL, 0, 0}},
	[U_SPEED] = {{"ms-1", "m/s", 1, 0}, {"kmh", "km/h", 1 / 3.6, 0},
		     {"mph", "mph", 0.44704, 0}, {"kn", "kn", 1852.0 / 3600, 0},
		     {NULL, NULL, 0, 0}},
	[U_DEGREE] = {{"degree", "\xc2\xb0", 1, 0}, {NULL, NULL, 0, 0}},
	[U_LENGTH] = {{"m", "m", 1, 0}, {"ft", "ft", 0.3048, 0}, {NULL, NULL, 0, 0}},
	[U_TEMP] = {{"C", "\xc2\xb0""C", 1, 0}, {"F", "\xc2\xb0""F", 5.0 / 9, -160.0 / 9},
		    {NULL, NULL, 0, 0}},
	/* snow depth: Open-Meteo's snowfall is in cm (inch with
	 * precipitation_unit=inch); meteoblue sends none */
	[U_SNOW] = {{"cm", "cm", 1, 0}, {"inch", "inch", 2.54, 0}, {NULL, NULL, 0, 0}},
	[U_IRRADIANCE] = {{"Wm-2", "W/m\xc2\xb2", 1, 0}, {NULL, NULL, 0, 0}},
};

/* The hourly arrays cloudscape reads or range-checks.  mb: meteoblue's
 * data_1h key; om, om_old: Open-Meteo's current and legacy spelling;
 * cat: meteoblue's units category; var: the series variable, or -1 for a
 * key that is only checked; lo..hi: the valid range in cloudscape units. */
struct key {
	const char *mb, *om, *om_old, *cat;
	int var;
	enum unit_kind unit;
	double lo, hi;
	int required;
};

static const struct key keys[] = {
	{"totalcloudcover", "cloud_cover", "cloudcover", "cloudcover",
	 CS_VAR_CLOUD_TOTAL, U_PERCENT, 0, 100, 0},
	{"lowclouds", "cloud_cover_low", "cloudcover_low", "cloudcover",
	 CS_VAR_CLOUD_LOW, U_PERCENT, 0, 100, 1},
	{"midclouds", "cloud_cover_mid", "cloudcover_mid", "cloudcover",
	 CS_VAR_CLOUD_MID, U_PERCENT, 0, 100, 1},
	{"highclouds", "cloud_cover_high", "cloudcover_high", "cloudcover",
	 CS_VAR_CLOUD_HIGH, U_PERCENT, 0, 100, 1},
	{"precipitation", "precipitation", NULL, "precipitation",
	 CS_VAR_PRECIP, U_PRECIP, 0, 500, 1},
	{"convective_precipitation", "showers", NULL, "precipitation",
	 CS_VAR_CONV_PRECIP, U_PRECIP, 0, 500, 0},
	{"windspeed", "wind_speed_10m", "windspeed_10m", "windspeed",
	 CS_VAR_WIND_SPEED, U_SPEED, 0, 100, 1},
	{"winddirection", "wind_direction_10m", "winddirection_10m",
	 "winddirection", CS_VAR_WIND_FROM, U_DEGREE, 0, 360, 1},
	{"visibility", "visibility", NULL, "visibility", CS_VAR_VISIBILITY,
	 U_LENGTH, 0, 1e6, 0},
	{"fog_probability", NULL, NULL, "probability", CS_VAR_FOG_PROBABILITY,
	 U_PERCENT, 0, 100, 0},
	{"relativehumidity", "relative_humidity_2m", "relativehumidity_2m",
	 "relativehumidity", CS_VAR_HUMIDITY, U_PERCENT, 0, 100, 0},
	{"temperature", "temperature_2m", NULL, "temperature",
	 CS_VAR_TEMPERATURE, U_TEMP, -100, 70, 0},
	{"isdaylight", "is_day", NULL, NULL, CS_VAR_IS_DAY, U_NONE, 0, 1, 0},
	{"pictocode", NULL, NULL, NULL, -1, U_NONE, 1, 35, 0},
	{NULL, "weather_code", "weathercode", NULL, -1, U_NONE, 0, 99, 0},
	{"sunshinetime", NULL, NULL, NULL, -1, U_NONE, 0, 60, 0},
	{"snowfraction", NULL, NULL, NULL, CS_VAR_SNOW_FRACTION, U_NONE, 0, 1, 0},
	{NULL, "snowfall", NULL, NULL, CS_VAR_SNOWFALL, U_SNOW, 0, 500, 0},
	/* the values at the hour (_instant), not meteoblue's _backwards or
	 * Open-Meteo's plain names, which are means over the preceding hour */
	{"ghi_instant", "shortwave_radiation_instant", NULL, "radiation",
	 CS_VAR_GHI, U_IRRADIANCE, 0, 2000, 0},
	{"dni_instant", "direct_normal_irradiance_instant", NULL, "radiation",
	 CS_VAR_DNI, U_IRRADIANCE, 0, 2000, 0},
	{"dif_instant", "diffuse_radiation_instant", NULL, "radiation",
	 CS_VAR_DHI, U_IRRADIANCE, 0, 2000, 0},
	{"precipitation_probability", "precipitation_probability", NULL, NULL,
	 -1, U_NONE, 0, 100, 0},
	{"uvindex", NULL, NULL, NULL, -1, U_NONE, 0, 25, 0},
};
#define NKEYS (sizeof keys / sizeof *keys)

static const char *const var_names[CS_VAR_COUNT] = {
	"total cloud cover", "low cloud cover", "mid cloud cover",
	"high cloud cover", "precipitation", "convective precipitation",
	"wind speed", "wind direction", "visibility", "fog probability",
	"relative humidity", "temperature", "daylight flag", "snow fraction",
	"snowfall", "global horizontal irradiance", "direct normal irradiance",
	"diffuse horizontal irradiance",
};

const char *cs_wxvar_name(enum cs_wxvar k)
{
	return (unsigned)k < CS_VAR_COUNT ? var_names[k] : "unknown variable";
}

/* ---- problems ------------------------------------------------------------ */

static void problem(struct cs_problems *pr, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* Keeps the first problems, one line each (control characters, which a
 * provider's text might hold, become spaces), and counts all. */
static void problem(struct cs_problems *pr, const char *fmt, ...)
{
	int i = pr->count++;
	if (i >= (int)(sizeof pr->msg / sizeof *pr->msg))
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(pr->msg[i], sizeof pr->msg[i], fmt, ap);
	va_end(ap);
	for (char *c = pr->msg[i]; *c; c++)
		if ((unsigned char)*c < 0x20 || *c == 0x7f)
			*c = ' ';
}

static const char *type_name(const cJSON *it)
{
	switch (it->type & 0xff) {
	case cJSON_False:
	case cJSON_True: return "a boolean";
	case cJSON_NULL: return "null";
	case cJSON_Number: return "a number";
	case cJSON_String: return "a string";
	case cJSON_Array: return "an array";
	default: return "an object";
	}
}

/* A value for a message: the number as the file wrote it. */
struct txt {
	char s[48];
};

/* ---- what the document holds -------------------------------------------- */

struct doc {
	cJSON *root;
	int strict;   /* units exactly as cloudscape requests them (mbfetch) */
	enum cs_provider prov;
	const cJSON *data, *units;
	const char *data_name, *units_name;
	int n;                       /* hours (length of time) */
	double *t;                   /* n UTC times, NaN where unreadable */
	double offset_s;
	double lat, lon, alt;
	const char *site_name;
	const cJSON *arr[NKEYS];     /* each key's array, or NULL */
	const char *arr_key[NKEYS];  /* the spelling found */
	const struct unit *unit[NKEYS];
};

/* The text of an HTML page worth showing: its title, else its start. */
static void html_problem(const char *s, size_t len, struct cs_problems *pr)
{
	char text[160];
	size_t k = 0;
	const char *from = s, *to = s + (len < 120 ? len : 120);
	for (size_t i = 0; i + 7 <= len; i++)
		if (strncasecmp(s + i, "<title>", 7) == 0) {
			from = s + i + 7;
			to = from;
			while (to < s + len && to - from < 150 && *to != '<')
				to++;
			break;
		}
	for (const char *c = from; c < to && k + 1 < sizeof text; c++)
		text[k++] = isspace((unsigned char)*c) ? ' ' : *c;
	text[k] = '\0';
	problem(pr, "an HTML page, not JSON: \"%s\"", text);
}

/* Parses the text; reports empty, HTML and malformed or truncated input. */
static cJSON *parse_json(const char *json, size_t len, struct cs_problems *pr)
{
	size_t at = 0;
	while (at < len && isspace((unsigned char)json[at]))
		at++;
	if (at == len) {
		problem(pr, "empty response (%zu bytes, no JSON)", len);
		return NULL;
	}
	if (json[at] == '<') {
		html_problem(json + at, len - at, pr);
		return NULL;
	}
	const char *nul = memchr(json, '\0', len), *end = NULL;
	if (nul != NULL) {
		problem(pr, "NUL byte at byte offset %zu: not JSON text",
			(size_t)(nul - json));
		return NULL;
	}
	cJSON *root = cJSON_ParseWithLengthOpts(json, len, &end, 0);
	size_t off = end ? (size_t)(end - json) : 0;
	if (root == NULL) {
		size_t from, to;
		cs_json_near(json, len, off, &from, &to);
		if (cs_json_cut_short(json, len, off))
			problem(pr, "truncated JSON: the text ends at byte %zu "
				"before the document is complete", len);
		else
			problem(pr, "malformed JSON at byte offset %zu near "
				"\"%.*s\"", off, (int)(to - from), json + from);
		return NULL;
	}
	while (off < len && isspace((unsigned char)json[off]))
		off++;
	if (off < len) {
		problem(pr, "unexpected text after the JSON document at byte "
			"offset %zu", off);
		cJSON_Delete(root);
		return NULL;
	}
	return root;
}

/* Reports a provider's error body verbatim; returns 1 if root is one. */
static int error_body(const cJSON *root, struct cs_problems *pr)
{
	const cJSON *msg = cJSON_GetObjectItemCaseSensitive(root, "error_message");
	const cJSON *err = cJSON_GetObjectItemCaseSensitive(root, "error");
	const cJSON *reason = cJSON_GetObjectItemCaseSensitive(root, "reason");
	if (cJSON_IsString(msg)) {
		problem(pr, "provider error (error_message): %s", msg->valuestring);
		return 1;
	}
	if (cJSON_IsTrue(err)) {
		problem(pr, "provider error (reason): %s", cJSON_IsString(reason) ?
			reason->valuestring : "(no reason given)");
		return 1;
	}
	return 0;
}

static int classify(const cJSON *root, enum cs_provider *p)
{
	if (cJSON_HasObjectItem(root, "data_1h") ||
	    cJSON_HasObjectItem(root, "metadata")) {
		*p = CS_PROVIDER_METEOBLUE;
		return 1;
	}
	if (cJSON_HasObjectItem(root, "hourly") ||
	    cJSON_HasObjectItem(root, "hourly_units") ||
	    cJSON_HasObjectItem(root, "utc_offset_seconds")) {
		*p = CS_PROVIDER_OPENMETEO;
		return 1;
	}
	return 0;
}

/* The member key of obj, which must have the type kind; reports a missing
 * or mistyped member (with a hint) and gives NULL. */
static const cJSON *member(const cJSON *obj, const char *pre, const char *key,
			   int kind, const char *hint, struct cs_problems *pr)
{
	const cJSON *it = cJSON_GetObjectItemCaseSensitive(obj, key);
	if (it == NULL) {
		problem(pr, "%s%s: missing%s", pre, key, hint ? hint : "");
		return NULL;
	}
	if ((it->type & 0xff) != kind) {
		problem(pr, "%s%s: expected %s, not %s", pre, key,
			kind == cJSON_Number ? "a number" :
			kind == cJSON_String ? "a string" : "an object",
			type_name(it));
		return NULL;
	}
	return it;
}

/* A number member in lo..hi, or NaN (reported). */
static double number(const cJSON *obj, const char *pre, const char *key,
		     double lo, double hi, struct cs_problems *pr)
{
	const cJSON *it = member(obj, pre, key, cJSON_Number, NULL, pr);
	if (it == NULL)
		return NAN;
	if (!(it->valuedouble >= lo && it->valuedouble <= hi)) {
		problem(pr, "%s%s: %s is outside %s..%s", pre, key,
			cs_num(it->valuedouble).s, cs_num(lo).s, cs_num(hi).s);
		return NAN;
	}
	return it->valuedouble;
}

static void meta_meteoblue(struct doc *d, struct cs_problems *pr)
{
	const cJSON *m = member(d->root, "", "metadata", cJSON_Object, NULL, pr);
	if (m != NULL) {
		d->lat = number(m, "metadata.", "latitude", -90, 90, pr);
		d->lon = number(m, "metadata.", "longitude", -180, 180, pr);
		d->alt = number(m, "metadata.", "height", -500, 9000, pr);
		d->offset_s = number(m, "metadata.", "utc_timeoffset", -18, 18,
				     pr) * 3600.0;
		const cJSON *name = cJSON_GetObjectItemCaseSensitive(m, "name");
		if (cJSON_IsString(name))
			d->site_name = name->valuestring;
	}
	d->units = member(d->root, "", "units", cJSON_Object, NULL, pr);
	d->data = member(d->root, "", "data_1h", cJSON_Object,
			 " (request an -1h package)", pr);
	d->data_name = "data_1h";
	d->units_name = "units";
}

static void meta_openmeteo(struct doc *d, struct cs_problems *pr)
{
	d->lat = number(d->root, "", "latitude", -90, 90, pr);
	d->lon = number(d->root, "", "longitude", -180, 180, pr);
	d->alt = number(d->root, "", "elevation", -500, 9000, pr);
	d->offset_s = number(d->root, "", "utc_offset_seconds", -18 * 3600.0,
			     18 * 3600.0, pr);
	d->units = member(d->root, "", "hourly_units", cJSON_Object, NULL, pr);
	d->data = member(d->root, "", "hourly", cJSON_Object,
			 " (request &hourly=...)", pr);
	d->data_name = "hourly";
	d->units_name = "hourly_units";
}

/* One time value: "YYYY-MM-DD hh:mm" or "YYYY-MM-DDThh:mm" wall time in the
 * file's offset, or integer Unix seconds (UTC).  NaN if unreadable. */
static double time_value(const cJSON *it, double offset_s)
{
	if (cJSON_IsNumber(it))
		return it->valuedouble == floor(it->valuedouble) &&
		       fabs(it->valuedouble) < 1e12 ? it->valuedouble : NAN;
	if (!cJSON_IsString(it))
		return NAN;
	const char *s = it->valuestring;
	char buf[24];
	double t;
	if (strlen(s) != 16 || (s[10] != ' ' && s[10] != 'T'))
		return NAN;
	snprintf(buf, sizeof buf, "%.10sT%.5sZ", s, s + 11);
	if (cs_time_parse(buf, &t) != CS_OK)
		return NAN;
	return t - offset_s;
}

/* The time as the file wrote it, for messages. */
static struct txt time_text(const cJSON *it)
{
	struct txt t;
	if (cJSON_IsString(it))
		snprintf(t.s, sizeof t.s, "\"%.40s\"", it->valuestring);
	else if (cJSON_IsNumber(it))
		cs_fmt_double(t.s, sizeof t.s, it->valuedouble);
	else
		snprintf(t.s, sizeof t.s, "%s", type_name(it));
	return t;
}

static void check_times(struct doc *d, struct cs_problems *pr)
{
	char pre[16];
	snprintf(pre, sizeof pre, "%s.", d->data_name);
	const cJSON *time = cJSON_GetObjectItemCaseSensitive(d->data, "time");
	if (time == NULL || !cJSON_IsArray(time)) {
		problem(pr, "%stime: %s", pre, time ? "expected an array" : "missing");
		return;
	}
	d->n = cJSON_GetArraySize(time);
	if (d->n == 0) {
		problem(pr, "%stime: empty (no hours)", pre);
		return;
	}
	d->t = malloc((size_t)d->n * sizeof *d->t);
	if (d->t == NULL) {
		problem(pr, "out of memory");
		return;
	}
	double off = isfinite(d->offset_s) ? d->offset_s : 0.0;
	const cJSON *it, *prev = NULL;
	int i = 0;
	cJSON_ArrayForEach(it, time) {
		d->t[i] = time_value(it, off);
		if (isnan(d->t[i]))
			problem(pr, "%stime[%d]: %s is not a time (expected "
				"\"YYYY-MM-DD hh:mm\", \"YYYY-MM-DDThh:mm\" or "
				"Unix seconds)", pre, i, time_text(it).s);
		else if (i > 0 && !isnan(d->t[i - 1]) &&
			 d->t[i] - d->t[i - 1] != 3600.0) {
			double h = (d->t[i] - d->t[i - 1]) / 3600.0;
			problem(pr, "%stime[%d]: %s is %s h after time[%d] %s "
				"(expected 1 h steps%s)", pre, i,
				time_text(it).s, cs_num(h).s, i - 1,
				time_text(prev).s,
				h > 1 ? ": hours are missing" :
				h == 0 ? ": a repeated hour, as at a daylight-"
					 "saving change" :
				h < 0 ? ": time goes back" : "");
		}
		prev = it;
		i++;
	}
}

/* The unit of key k as the file states it, or NULL (reported). */
static const struct unit *find_unit(struct doc *d, size_t k, const char *key,
				    struct cs_problems *pr)
{
	const struct key *kk = &keys[k];
	const struct unit *u = unit_table[kk->unit];
	if (kk->unit == U_NONE)
		return u;
	int mb = d->prov == CS_PROVIDER_METEOBLUE;
	const char *ukey = mb ? kk->cat : key;
	const cJSON *us = cJSON_GetObjectItemCaseSensitive(d->units, ukey);
	if (!cJSON_IsString(us)) {
		problem(pr, "%s.%s: %s (the unit of %s.%s)", d->units_name, ukey,
			us ? "expected a string" : "missing", d->data_name, key);
		return NULL;
	}
	char expect[96] = "";
	/* strict: only the first unit of each kind, the one mbfetch asks for;
	 * a provider that silently ignored the request is caught here */
	for (int n = 0; u->scale != 0 && (!d->strict || n < 1); u++, n++) {
		const char *name = mb ? u->mb : u->om;
		if (strcmp(us->valuestring, name) == 0)
			return u;
		snprintf(expect + strlen(expect), sizeof expect - strlen(expect),
			 "%s\"%s\"", expect[0] ? ", " : "", name);
	}
	problem(pr, "%s.%s: unit \"%.40s\" is not %s (expected %s)", d->units_name,
		ukey, us->valuestring,
		d->strict ? "the one cloudscape requests" : "one cloudscape reads", expect);
	return NULL;
}

/* Every array as long as time; the known arrays present where required,
 * in their unit, numbers or null, in range. */
static void check_arrays(struct doc *d, struct cs_problems *pr)
{
	const char *dn = d->data_name;
	const cJSON *it;
	cJSON_ArrayForEach(it, d->data) {
		if (!cJSON_IsArray(it)) {
			problem(pr, "%s.%s: expected an array, not %s", dn,
				it->string, type_name(it));
			continue;
		}
		int m = cJSON_GetArraySize(it);
		if (d->n > 0 && m != d->n)
			problem(pr, "%s.%s: %d values but time has %d (index %d "
				"%s)", dn, it->string, m, d->n, m < d->n ? m : d->n,
				m < d->n ? "has no value" : "has no time");
	}
	int mb = d->prov == CS_PROVIDER_METEOBLUE;
	for (size_t k = 0; k < NKEYS; k++) {
		const char *names[2] = {mb ? keys[k].mb : keys[k].om,
					mb ? NULL : keys[k].om_old};
		for (int j = 0; j < 2 && d->arr[k] == NULL; j++)
			if (names[j] != NULL &&
			    (it = cJSON_GetObjectItemCaseSensitive(d->data,
								    names[j]))) {
				d->arr[k] = cJSON_IsArray(it) ? it : NULL;
				d->arr_key[k] = names[j];
			}
		if (d->arr_key[k] == NULL) {
			if (keys[k].required && names[0] != NULL)
				problem(pr, "%s.%s: missing (cloudscape needs it; "
					"request %s)", dn, names[0], mb ?
					"basic-1h and clouds-1h" :
					"it in &hourly=");
			continue;
		}
		if (d->arr[k] == NULL)
			continue;
		d->unit[k] = find_unit(d, k, d->arr_key[k], pr);
		if (d->unit[k] == NULL)
			continue;
		int i = 0;
		const struct unit *u = d->unit[k];
		cJSON_ArrayForEach(it, d->arr[k]) {
			if (cJSON_IsNumber(it)) {
				double v = it->valuedouble * u->scale + u->offset;
				if (v >= keys[k].lo && v <= keys[k].hi)
					;
				else if (u->scale == 1 && u->offset == 0)
					problem(pr, "%s.%s[%d]: %s is outside "
						"%s..%s", dn, d->arr_key[k], i,
						cs_num(it->valuedouble).s,
						cs_num(keys[k].lo).s, cs_num(keys[k].hi).s);
				else
					/* the converted value rounded: it is
					 * ours, not the file's text */
					problem(pr, "%s.%s[%d]: %s %s (%.10g %s) is "
						"outside %s..%s %s", dn,
						d->arr_key[k], i,
						cs_num(it->valuedouble).s,
						mb ? u->mb : u->om, v,
						si_unit[keys[k].unit],
						cs_num(keys[k].lo).s, cs_num(keys[k].hi).s,
						si_unit[keys[k].unit]);
			} else if (!cJSON_IsNull(it)) {
				problem(pr, "%s.%s[%d]: expected a number or null, "
					"not %s", dn, d->arr_key[k], i,
					type_name(it));
			}
			i++;
		}
	}
}

/* Fills d from the text, reporting every problem; d->root is NULL when the
 * text is no provider document at all. */
static void analyse(const char *json, size_t len, int strict, struct doc *d,
		    struct cs_problems *pr)
{
	memset(d, 0, sizeof *d);
	memset(pr, 0, sizeof *pr);
	d->strict = strict;
	d->lat = d->lon = d->alt = d->offset_s = NAN;
	if (json == NULL) {
		problem(pr, "no input");
		return;
	}
	d->root = parse_json(json, len, pr);
	if (d->root == NULL)
		return;
	if (cJSON_IsArray(d->root)) {
		problem(pr, "a list of %d responses (one per location); "
			"cloudscape reads one location per file",
			cJSON_GetArraySize(d->root));
		return;
	}
	if (!cJSON_IsObject(d->root)) {
		problem(pr, "expected a JSON object, not %s", type_name(d->root));
		return;
	}
	if (error_body(d->root, pr))
		return;
	if (!classify(d->root, &d->prov)) {
		problem(pr, "neither a meteoblue nor an Open-Meteo response "
			"(no data_1h, metadata, hourly or utc_offset_seconds)");
		return;
	}
	if (d->prov == CS_PROVIDER_METEOBLUE)
		meta_meteoblue(d, pr);
	else
		meta_openmeteo(d, pr);
	if (d->data == NULL)
		return;
	check_times(d, pr);
	if (d->units == NULL)
		return;
	check_arrays(d, pr);
}

static void doc_free(struct doc *d)
{
	cJSON_Delete(d->root);
	free(d->t);
	d->root = NULL;
	d->t = NULL;
}

/* ---- the public calls ----------------------------------------------------- */

int cs_provider_detect(const char *json, size_t len, enum cs_provider *p)
{
	struct cs_problems pr;
	memset(&pr, 0, sizeof pr);
	if (json == NULL || p == NULL)
		return cs_error(CS_EINVAL, "cs_provider_detect: no input");
	cJSON *root = parse_json(json, len, &pr);
	int ok = 0;
	if (root != NULL && cJSON_IsObject(root) && !error_body(root, &pr))
		ok = classify(root, p);
	cJSON_Delete(root);
	if (ok)
		return CS_OK;
	return cs_error(CS_EDATA, "%s", pr.count ? pr.msg[0] :
			"neither a meteoblue nor an Open-Meteo response");
}

int cs_provider_check(const char *json, size_t len, struct cs_problems *pr)
{
	struct doc d;
	analyse(json, len, 1, &d, pr);
	doc_free(&d);
	if (pr->count == 0)
		return CS_OK;
	return cs_error(CS_EDATA, "%s%s", pr->msg[0],
			pr->count > 1 ? " (and more problems)" : "");
}

void cs_series_free(struct cs_series *s)
{
	if (s == NULL)
		return;
	free(s->time_utc);
	for (int k = 0; k < CS_VAR_COUNT; k++)
		free(s->v[k]);
	memset(s, 0, sizeof *s);
}

static int fill(struct doc *d, struct cs_series *s)
{
	s->provider = d->prov;
	snprintf(s->name, sizeof s->name, "%s", d->site_name ? d->site_name : "");
	s->lat_deg = d->lat;
	s->lon_deg = d->lon;
	s->alt_m = d->alt;
	s->utc_offset_s = d->offset_s;
	s->n = d->n;
	s->time_utc = d->t;
	d->t = NULL;
	for (size_t k = 0; k < NKEYS; k++) {
		int var = keys[k].var;
		if (var < 0 || d->arr[k] == NULL || s->v[var] != NULL)
			continue;
		s->v[var] = malloc((size_t)s->n * sizeof *s->v[var]);
		if (s->v[var] == NULL)
			return cs_error(CS_ENOMEM, "out of memory");
		snprintf(s->key[var], sizeof s->key[var], "%s.%s", d->data_name,
			 d->arr_key[k]);
		const struct unit *u = d->unit[k];
		const cJSON *it;
		int i = 0;
		cJSON_ArrayForEach(it, d->arr[k])
			s->v[var][i++] = cJSON_IsNumber(it) ?
				it->valuedouble * u->scale + u->offset : NAN;
	}
	return CS_OK;
}

/* A visibility that is the same at every hour of a long file is a model's
 * default, not a measurement (Open-Meteo's sits at its ~24 km ceiling
 * wherever only one global model provides it): dropped, and said. */
static void drop_constant_visibility(struct cs_series *s)
{
	double *v = s->v[CS_VAR_VISIBILITY], first = NAN;
	int valid = 0;
	for (int i = 0; v != NULL && i < s->n; i++) {
		if (isnan(v[i]))
			continue;
		if (valid++ == 0)
			first = v[i];
		else if (v[i] != first)
			return;
	}
	if (valid < CS_CONST_VIS_HOURS)
		return;
	snprintf(s->note, sizeof s->note, "%s is %s m at all %d hours: a "
		 "model's default, not used (visibility unknown)",
		 s->key[CS_VAR_VISIBILITY], cs_num(first).s, valid);
	free(v);
	s->v[CS_VAR_VISIBILITY] = NULL;
	s->key[CS_VAR_VISIBILITY][0] = '\0';
}

int cs_provider_parse(const char *json, size_t len, const char *name,
		      struct cs_series *s)
{
	if (s == NULL)
		return cs_error(CS_EINVAL, "cs_provider_parse: no series");
	memset(s, 0, sizeof *s);
	if (name == NULL)
		name = "input";
	struct doc d;
	struct cs_problems pr;
	analyse(json, len, 0, &d, &pr);
	int rc = CS_OK;
	if (pr.count == 1)
		rc = cs_error(CS_EDATA, "%s: %s", name, pr.msg[0]);
	else if (pr.count > 1)
		rc = cs_error(CS_EDATA, "%s: %s (and %d more problem%s)", name,
			      pr.msg[0], pr.count - 1, pr.count > 2 ? "s" : "");
	else
		rc = fill(&d, s);
	if (rc == CS_OK)
		drop_constant_visibility(s);
	doc_free(&d);
	if (rc != CS_OK)
		cs_series_free(s);
	return rc;
}
