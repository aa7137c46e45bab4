/* wxinterp.h - the wxinterp program as a library call: provider files in,
 * weather states (cloudwx/1, man 5 cloudwx) out, one per requested time.
 * Its parts - merging files, interpolating in time, the genus rules
 * (wxrules.h), play-mode edits (wxset.h) - are callable alone. */
#ifndef CS_WXINTERP_H
#define CS_WXINTERP_H

#include "weather/provider.h"
#include "weather/wx.h"
#include "weather/genus_rules.h"

#define CS_WXINTERP_MAX_INPUTS 32
#define CS_WXINTERP_MAX_SETS 64
#define CS_WXINTERP_MAX_STATES 1000000
#define CS_WXINTERP_MAX_HOURS 200000      /* span of merged inputs (22 years) */
#define CS_WXINTERP_MERGE_DEG 0.1         /* files this close are one site */
#define CS_WXINTERP_DEFAULT_GAP_S 10800.0 /* nulls bridged over 3 h */

/* Messages for the user: level 1 a warning, 2 a verbose note. */
typedef void (*cs_note_fn)(void *user, int level, const char *msg);

struct cs_wxinterp_opts {
	const char *inputs[CS_WXINTERP_MAX_INPUTS]; /* provider files, "-" stdin */
	int ninputs;
	const char *far[CS_WX_MAX_FAR];       /* far-site provider files */
	const char *far_name[CS_WX_MAX_FAR];  /* or NULL */
	int nfar;
	int have_at, have_from, have_to;
	double at_utc, from_utc, to_utc;      /* seconds since 1970 */
	double step_s;                        /* series step (default 3600) */
	double max_gap_s;                     /* null bridging (default 3 h) */
	const char *sets[CS_WXINTERP_MAX_SETS]; /* "PATH=VALUE" (wxset.h) */
	int nsets;
	const char *site_name;                /* or NULL: from the file */
	int have_alt;
	double alt_m;                         /* ground height override */
	int template_state;                   /* the default state, no inputs */
	int pretty;                           /* indented JSON (one state) */
	const char *output;                   /* path or "-" (default) */
	cs_note_fn note;
	void *note_user;
};

/* What a run produced. */
struct cs_wxinterp_result {
	long nstates;                         /* states written */
};

void cs_wxinterp_defaults(struct cs_wxinterp_opts *o);

/* Reads the inputs, writes the states (atomically).  CS_EINVAL for bad
 * options or --set edits, CS_EDATA for bad or insufficient data, CS_EIO. */
int cs_wxinterp_run(const struct cs_wxinterp_opts *o, struct cs_wxinterp_result *res);

/* Reads and parses a provider file ("-" = standard input); messages start
 * with the file name. */
int cs_series_read(const char *path, struct cs_series *s);

/* Merges b into a (the union of their hours on one hourly grid, NaN where
 * neither has a value; where both have a value b's wins, as later files
 * win in gdal_merge).  The sites must lie within CS_WXINTERP_MERGE_DEG of
 * each other; a keeps its position, name and offset.  Variables that only
 * one file has are missing (NaN) over the other's hours.  On error a is
 * unchanged.  *dist_km (may be NULL) says how far apart the sites are. */
int cs_series_merge(struct cs_series *a, const struct cs_series *b,
		    double *dist_km);

/* The value of variable k at time t (UTC s): linear between the bracketing
 * hours; the wind direction on the circle (350 -> 10 passes 0).  A missing
 * value (null) is bridged by the nearest valid hours on either side when
 * they are at most max_gap_s apart; else, or outside the hours, or when
 * the file lacks k, CS_EDATA naming the variable, the time and why. */
int cs_series_value(const struct cs_series *s, enum cs_wxvar k, double t,
		    double max_gap_s, double *out);

/* Every variable the rules use, at time t; the sun from the position. */
int cs_series_obs(const struct cs_series *s, double t, double max_gap_s,
		  struct cs_wx_obs *o);

/* "2024-10-06T00:00:00Z to 2024-10-14T00:00:00Z" (the hours covered). */
void cs_series_range(const struct cs_series *s, char *buf, size_t size);

/* A duration "90", "90s", "10m", "1.5h", "2d" in seconds (> 0). */
int cs_duration_parse(const char *s, double *seconds);

/* The same JSON indented: two spaces a level, an object or array with no
 * object or array inside on one line.  *out malloc'ed for the caller. */
int cs_json_pretty(const char *json, char **out);

#endif
