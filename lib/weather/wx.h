/* wx.h - the weather state: what the sky is like at one minute.
 *
 * Written by wxinterp, read by cloudrender; JSON schema "cloudwx/2" (read:
 * also "cloudwx/1", which has no drift), documented in man 5 cloudwx.
 * Altitudes are metres above mean sea level, times UTC. */
#ifndef CS_WX_H
#define CS_WX_H

#include <stddef.h>

#define CS_WX_SCHEMA "cloudwx/2"    /* what writers write */
#define CS_WX_SCHEMA_V1 "cloudwx/1" /* still read: no drift */
#define CS_WX_MAX_DRIFT_M 1e11      /* |east_m|, |north_m| of a drift */
#define CS_WX_MAX_LAYERS 8
#define CS_WX_MAX_FAR 4

/* The ten WMO cloud genera. */
enum cs_genus {
	CS_CIRRUS,
	CS_CIRROCUMULUS,
	CS_CIRROSTRATUS,
	CS_ALTOCUMULUS,
	CS_ALTOSTRATUS,
	CS_NIMBOSTRATUS,
	CS_STRATOCUMULUS,
	CS_STRATUS,
	CS_CUMULUS,
	CS_CUMULONIMBUS,
	CS_GENUS_COUNT
};

/* "cirrus", "cirrocumulus", ... (lower case, as in the JSON). */
const char *cs_genus_name(enum cs_genus g);
/* The genus of a name (case-insensitive), or -1. */
int cs_genus_from_name(const char *name);

struct cs_wx_layer {
	enum cs_genus genus;
	double coverage;  /* fraction of the sky, 0..1 */
	double base_m;    /* cloud base, m above sea level */
	double top_m;     /* cloud top, m above sea level, > base_m */
};

struct cs_wx_site {
	char name[64];
	double lat_deg, lon_deg; /* WGS84 */
	double alt_m;            /* ground height, m above sea level */
};

/* Weather at a distant site, blended in by distance along the view. */
struct cs_wx_far {
	struct cs_wx_site site;
	int nlayers;
	struct cs_wx_layer layers[CS_WX_MAX_LAYERS];
	double precipitation_mm_h;
	double visibility_m;
};

/* What the provider says about the light and the sky, for comparing a
 * render with; the DNI also fits the sheets' optical depth
 * (render/beam_fit.c: cloudrender --cloud-depth), the rest is
 * never used to render.  Instant values at the state's
 * time, W/m2; GHI = DNI cos(zenith) + DHI.  The has_ flags say which the
 * provider had ("observed" in the JSON, written only with them). */
struct cs_wx_observed {
	int has_radiation;        /* ghi, dni and dhi known */
	double ghi_w_m2;          /* global horizontal irradiance, 0..2000 */
	double dni_w_m2;          /* direct normal irradiance, 0..2000 */
	double dhi_w_m2;          /* diffuse horizontal irradiance, 0..2000 */
	int has_cloud_cover;
	double total_cloud_cover; /* the provider's total cover, 0..1 */
};

/* How far the wind has carried the air since a reference time: the
 * integral of the 10-m wind vector (the way it blows toward) over time,
 * which moves the clouds continuously from one state of a series to the
 * next (see wxinterp(1), ADVECTION).  known 0: a state without one (a
 * cloudwx/1 file, the built-in state); the renderer then moves the clouds
 * by the state's wind times the time since 2000-01-01, as before. */
struct cs_wx_drift {
	int known;
	double since_utc;   /* the reference time, s since 1970 */
	double east_m;      /* displacement toward the east since then, m */
	double north_m;     /* displacement toward the north, m */
	double axis_deg;    /* compass bearing the clouds' streaks lie along
			       (the way the data's mean wind blows), 0..360;
			       the same for every state of a series */
};

struct cs_wx {
	double time_utc;               /* seconds since 1970-01-01T00:00Z */
	struct cs_wx_site site;
	int nlayers;
	struct cs_wx_layer layers[CS_WX_MAX_LAYERS];
	double precipitation_mm_h;     /* total, >= 0 */
	double convective_mm_h;        /* convective part, 0..total */
	double wind_speed_m_s;         /* >= 0 */
	double wind_from_deg;          /* direction the wind blows from, 0..360 */
	double visibility_m;           /* > 0 */
	double fog_probability;        /* 0..1 */
	double snow_fraction;          /* 0..1, the fraction of the
					  precipitation that falls as snow */
	double temperature_c;          /* 2 m air temperature, -100..70;
					  NaN: unknown (no JSON key) */
	struct cs_wx_observed observed;
	struct cs_wx_drift drift;
	int nfar;
	struct cs_wx_far far[CS_WX_MAX_FAR];
};

/* The built-in fair-weather state: Bern (46.95N 7.44E, 540 m),
 * 2021-06-14T14:00Z, cumulus 0.35 from 1500 to 2700 m, cirrus 0.2 from
 * 9000 to 9600 m, wind 4 m/s from 250 deg, visibility 30 km, no rain, no
 * snow, temperature unknown (NaN). */
void cs_wx_default(struct cs_wx *wx);

/* Parses and validates one JSON object of schema cloudwx/2 or cloudwx/1.  Errors name
 * the field, e.g. "layers[1].coverage: 1.5 is outside 0..1".  Unknown keys
 * are ignored; *wx is left untouched on error. */
int cs_wx_parse(const char *json, size_t len, struct cs_wx *wx);
/* The same for JSON Lines text: the first non-empty line's state (what
 * cs_wx_read() does with a file's bytes). */
int cs_wx_parse_lines(const char *json, size_t len, struct cs_wx *wx);

/* Reads a state from a file ("-" = stdin) of at most 16 MiB.  A JSON Lines
 * file gives its first non-empty line; the lines after it are not read.
 * Error messages start with the file name ("standard input" for "-"). */
int cs_wx_read(const char *path, struct cs_wx *wx);

/* A series of states: a JSON Lines file (one state a line, blank lines
 * allowed), or states each spread over lines (wxinterp --pretty) one
 * after the other.  Held as text: every state is checked when the series
 * is read, and parsed again when asked for. */
#define CS_WX_SERIES_MAX 10000000
#define CS_WX_SERIES_MAX_BYTES ((size_t)1 << 30)
struct cs_wx_series {
	char *text;
	size_t len;
	size_t *start;    /* where state i starts in text */
	int n;            /* states, >= 1 */
};

/* Reads every state of a file ("-" = stdin) of at most
 * CS_WX_SERIES_MAX_BYTES.  Errors name the file, and the state after the
 * first: "day.jsonl: state 3 (line 3): layers[0].coverage: 1.5 is outside
 * 0..1" (as cs_wx_read() words the first state's errors).  Free with
 * cs_wx_series_free() (nothing to free after an error). */
int cs_wx_series_read(const char *path, struct cs_wx_series *s);
/* The same from len bytes in memory (copied); messages say "input". */
int cs_wx_series_parse(const char *json, size_t len, struct cs_wx_series *s);
/* State i (0 for the first) of a series. */
int cs_wx_series_get(const struct cs_wx_series *s, int i, struct cs_wx *wx);
void cs_wx_series_free(struct cs_wx_series *s);

/* Checks ranges and consistency (what cs_wx_parse() checks after parsing). */
int cs_wx_validate(const struct cs_wx *wx);

/* The state as one line of JSON (no newline); malloc'ed for the caller.
 * Numbers read back exactly; time_utc is written in whole seconds.  A state
 * that cs_wx_validate() rejects is not written (*json = NULL). */
int cs_wx_to_json(const struct cs_wx *wx, char **json);

/* Moves the state to time t (UTC s): a known drift is carried on by the
 * state's own wind over t - time_utc, so that a state rendered at another
 * time shows its clouds where its wind takes them.  The observed values,
 * the old time's, are dropped (unless t is the state's time). */
void cs_wx_retime(struct cs_wx *wx, double t);

/* The drift of a state at time t (UTC s), m: the state's drift carried on
 * by its wind over t - time_utc (see cs_wx_retime); 0, 0 without one. */
void cs_wx_drift_at(const struct cs_wx *wx, double t, double *east_m,
		    double *north_m);

#endif
