#include "weather/wxset.h"

#include "core/err.h"
#include "core/time.h"
#include "weather/genus_rules.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum ftype { T_NUM, T_OPTNUM, T_TEXT, T_TIME, T_GENUS };

/* A field: its names (canonical first) and where it lives. */
struct fdef {
	const char *name, *alias;
	enum ftype type;
	size_t off;
};

#define WX(m) offsetof(struct cs_wx, m)
#define SITE(m) offsetof(struct cs_wx_site, m)
#define LAYER(m) offsetof(struct cs_wx_layer, m)
#define FAR(m) offsetof(struct cs_wx_far, m)

static const struct fdef top_fields[] = {
	{"time_utc", NULL, T_TIME, WX(time_utc)},
	{"precipitation_mm_h", "precipitation", T_NUM, WX(precipitation_mm_h)},
	{"convective_mm_h", "convective", T_NUM, WX(convective_mm_h)},
	{"visibility_m", "visibility", T_NUM, WX(visibility_m)},
	{"fog_probability", "fog", T_NUM, WX(fog_probability)},
	{"snow_fraction", "snow", T_NUM, WX(snow_fraction)},
	{"temperature_c", "temperature", T_OPTNUM, WX(temperature_c)},
	{NULL, NULL, T_NUM, 0},
};
static const struct fdef wind_fields[] = {
	{"speed_m_s", "speed", T_NUM, WX(wind_speed_m_s)},
	{"from_deg", "from", T_NUM, WX(wind_from_deg)},
	{NULL, NULL, T_NUM, 0},
};
static const struct fdef far_fields[] = {
	{"precipitation_mm_h", "precipitation", T_NUM, FAR(precipitation_mm_h)},
	{"visibility_m", "visibility", T_NUM, FAR(visibility_m)},
	{NULL, NULL, T_NUM, 0},
};
static const struct fdef site_fields[] = {
	{"name", NULL, T_TEXT, SITE(name)},
	{"lat_deg", "lat", T_NUM, SITE(lat_deg)},
	{"lon_deg", "lon", T_NUM, SITE(lon_deg)},
	{"alt_m", "alt", T_NUM, SITE(alt_m)},
	{NULL, NULL, T_NUM, 0},
};
static const struct fdef layer_fields[] = {
	{"genus", NULL, T_GENUS, LAYER(genus)},
	{"coverage", NULL, T_NUM, LAYER(coverage)},
	{"base_m", "base", T_NUM, LAYER(base_m)},
	{"top_m", "top", T_NUM, LAYER(top_m)},
	{NULL, NULL, T_NUM, 0},
};

static const char *const etages[3] = {"low", "mid", "high"};
static const enum cs_genus etage_default[3] = {CS_STRATOCUMULUS,
					       CS_ALTOCUMULUS, CS_CIRRUS};

/* A parsed assignment. */
struct assign {
	char text[96];            /* the assignment, for messages */
	int far;                  /* -1: the site itself, else far[far] */
	const struct fdef *field; /* NULL: a whole layer (=GENUS or =none) */
	enum { K_TOP, K_WIND, K_FAR, K_SITE, K_LAYER } kind;
	int layer;                /* layers[layer], or -1 */
	int etage;                /* layer.<etage>, or -1 */
	const char *value;
	double num;
	int genus;                /* -1: none */
};

static int fail(const struct assign *a, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

static int fail(const struct assign *a, const char *fmt, ...)
{
	char why[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(why, sizeof why, fmt, ap);
	va_end(ap);
	return cs_error(CS_EINVAL, "%s: %s", a->text, why);
}

/* Reads "[N]" at *p (N in 0..max-1). */
static int index_at(const char **p, int max, int *n)
{
	const char *s = *p;
	if (*s++ != '[' || !isdigit((unsigned char)*s))
		return -1;
	long v = 0;
	while (isdigit((unsigned char)*s) && v < 1000)
		v = v * 10 + (*s++ - '0');
	if (*s++ != ']' || v >= max)
		return -1;
	*n = (int)v;
	*p = s;
	return 0;
}

static const struct fdef *find_field(const struct fdef *f, const char *name)
{
	for (; f->name != NULL; f++)
		if (strcmp(name, f->name) == 0 ||
		    (f->alias != NULL && strcmp(name, f->alias) == 0))
			return f;
	return NULL;
}

static int bad_path(const struct assign *a)
{
	return fail(a, "%s", "unknown path (expected e.g. layer.low.coverage, "
		    "layers[0].genus, precipitation, wind.speed, visibility, "
		    "fog, snow, temperature, site.name, far[0].visibility; "
		    "see wxinterp(1))");
}

/* The layer part of a path: "layers[N][.F]" or "layer.ETAGE[.F]". */
static int parse_layer(struct assign *a, const char *p)
{
	a->kind = K_LAYER;
	if (strncmp(p, "layers", 6) == 0) {
		p += 6;
		if (index_at(&p, CS_WX_MAX_LAYERS, &a->layer) != 0)
			return fail(a, "expected layers[N] with N in 0..%d",
				    CS_WX_MAX_LAYERS - 1);
	} else {
		p += 6; /* "layer." */
		for (int e = 0; e < 3; e++) {
			size_t n = strlen(etages[e]);
			if (strncmp(p, etages[e], n) == 0 &&
			    (p[n] == '\0' || p[n] == '.')) {
				a->etage = e;
				p += n;
			}
		}
		if (a->etage < 0)
			return fail(a, "%s", "expected layer.low, layer.mid or "
				    "layer.high");
	}
	if (*p == '\0')
		return CS_OK;
	if (*p != '.' || (a->field = find_field(layer_fields, p + 1)) == NULL)
		return fail(a, "%s", "a layer has the fields genus, coverage, "
			    "base_m and top_m");
	return CS_OK;
}

static int parse_path(struct assign *a, const char *p)
{
	if (strncmp(p, "far", 3) == 0 && p[3] == '[') {
		p += 3;
		if (index_at(&p, CS_WX_MAX_FAR, &a->far) != 0 || *p++ != '.')
			return fail(a, "expected far[N]. with N in 0..%d",
				    CS_WX_MAX_FAR - 1);
	}
	if (strncmp(p, "site.", 5) == 0) {
		a->kind = K_SITE;
		a->field = find_field(site_fields, p + 5);
	} else if (strncmp(p, "wind.", 5) == 0 && a->far < 0) {
		a->kind = K_WIND;
		a->field = find_field(wind_fields, p + 5);
	} else if (strncmp(p, "layers[", 7) == 0 || strncmp(p, "layer.", 6) == 0) {
		return parse_layer(a, p);
	} else {
		a->kind = a->far < 0 ? K_TOP : K_FAR;
		a->field = find_field(a->far < 0 ? top_fields : far_fields, p);
	}
	return a->field == NULL ? bad_path(a) : CS_OK;
}

static int parse_value(struct assign *a)
{
	const char *v = a->value;
	enum ftype t = a->field ? a->field->type : T_GENUS;
	if (t == T_OPTNUM && strcmp(v, "none") == 0) {
		a->num = NAN; /* unknown */
	} else if (t == T_NUM || t == T_OPTNUM) {
		char *end;
		errno = 0;
		a->num = strtod(v, &end);
		if (v[0] == '\0' || isspace((unsigned char)v[0]) || *end != '\0' ||
		    errno == ERANGE || !isfinite(a->num))
			return fail(a, "'%s' is not a number", v);
	} else if (t == T_TIME) {
		if (cs_time_parse(v, &a->num) != CS_OK)
			return fail(a, "%s", cs_errmsg());
	} else if (t == T_TEXT) {
		if (strlen(v) >= sizeof ((struct cs_wx_site *)0)->name)
			return fail(a, "%s", "a name has at most 63 bytes");
	} else if (strcmp(v, "none") != 0 || a->field != NULL) {
		a->genus = cs_genus_from_name(v);
		if (a->genus < 0)
			return fail(a, "unknown genus '%s' (expected cirrus, "
				    "cirrocumulus, cirrostratus, altocumulus, "
				    "altostratus, nimbostratus, stratocumulus, "
				    "stratus, cumulus, cumulonimbus or none)", v);
		if (a->etage >= 0 && cs_genus_etage(a->genus) != a->etage)
			return fail(a, "that genus is not of the %s étage",
				    etages[a->etage]);
	}
	return CS_OK;
}

static int parse(const char *text, struct assign *a)
{
	memset(a, 0, sizeof *a);
	a->far = a->layer = a->etage = a->genus = -1;
	snprintf(a->text, sizeof a->text, "%s", text ? text : "");
	const char *eq = text ? strchr(text, '=') : NULL;
	if (eq == NULL || eq == text)
		return fail(a, "%s", "expected PATH=VALUE");
	char path[96];
	if ((size_t)(eq - text) >= sizeof path)
		return bad_path(a);
	memcpy(path, text, (size_t)(eq - text));
	path[eq - text] = '\0';
	a->value = eq + 1;
	int rc = parse_path(a, path);
	return rc != CS_OK ? rc : parse_value(a);
}

int cs_wx_set_check(const char *assignment)
{
	struct assign a;
	return parse(assignment, &a);
}

/* The layers, count and ground of the site or far site being edited. */
struct target {
	struct cs_wx_site *site;
	struct cs_wx_layer *layers;
	int *n;
};

static void place(struct cs_wx_layer *l, enum cs_genus g, double ground)
{
	l->genus = g;
	cs_genus_place(g, ground, &l->base_m, &l->top_m);
}

/* The index of the layer a path names, adding one where the path says so;
 * -1 with *removed when a layer was removed. */
static int layer_of(struct assign *a, struct target *t, int *idx)
{
	int n = *t->n, i = a->layer, whole = a->field == NULL;
	if (a->etage >= 0) {
		for (i = 0; i < n; i++)
			if (cs_genus_etage(t->layers[i].genus) == a->etage)
				break;
	}
	if (whole && a->genus < 0) { /* =none */
		if (i < n) {
			memmove(&t->layers[i], &t->layers[i + 1],
				(size_t)(n - i - 1) * sizeof *t->layers);
			(*t->n)--;
		} else if (a->etage < 0) {
			return fail(a, "no layer %d (the state has %d)", i, n);
		}
		*idx = -1;
		return CS_OK;
	}
	if (i == n && (whole || a->etage >= 0)) { /* a new layer */
		if (n == CS_WX_MAX_LAYERS)
			return fail(a, "%s", "the state already has 8 layers");
		t->layers[i].coverage = 0.5;
		place(&t->layers[i], a->etage >= 0 && a->genus < 0 ?
		      etage_default[a->etage] : (enum cs_genus)a->genus,
		      t->site->alt_m);
		(*t->n)++;
	} else if (i >= n) {
		return fail(a, "no layer %d (the state has %d; layers[%d]=GENUS "
			    "adds one)", i, n, n);
	}
	*idx = i;
	return CS_OK;
}

/* Layers come low to high (man 1 wxinterp): by base, stably. */
static void sort_layers(struct cs_wx_layer *l, int n)
{
	for (int i = 1; i < n; i++)
		for (int j = i; j > 0 && l[j].base_m < l[j - 1].base_m; j--) {
			struct cs_wx_layer tmp = l[j];
			l[j] = l[j - 1];
			l[j - 1] = tmp;
		}
}

int cs_wx_set(struct cs_wx *wx, const char *assignment)
{
	struct assign a;
	int rc = parse(assignment, &a);
	if (rc != CS_OK)
		return rc;
	if (wx == NULL)
		return cs_error(CS_EINVAL, "cs_wx_set: no state");
	struct target t = {&wx->site, wx->layers, &wx->nlayers};
	char *base = (char *)wx;
	if (a.far >= 0) {
		if (a.far >= wx->nfar) {
			return fail(&a, "no far site %d (the state has %d; "
				    "--far adds one)", a.far, wx->nfar);
		}
		struct cs_wx_far *f = &wx->far[a.far];
		t = (struct target){&f->site, f->layers, &f->nlayers};
		base = (char *)f;
	}
	if (a.kind == K_SITE)
		base = (char *)t.site;
	if (a.kind == K_LAYER) {
		int i = -1;
		rc = layer_of(&a, &t, &i);
		if (rc != CS_OK || i < 0)
			return rc;
		if (a.field == NULL || a.field->type == T_GENUS) {
			place(&t.layers[i], (enum cs_genus)a.genus, t.site->alt_m);
			sort_layers(t.layers, *t.n);
			return CS_OK;
		}
		base = (char *)&t.layers[i];
	}
	if (a.field->type == T_TEXT)
		snprintf(base + a.field->off, sizeof t.site->name, "%s", a.value);
	else if (a.field->type == T_TIME)
		cs_wx_retime(wx, a.num); /* the drift goes with the time */
	else
		*(double *)(base + a.field->off) = a.num;
	if (a.kind == K_LAYER)
		sort_layers(t.layers, *t.n);
	return CS_OK;
}
