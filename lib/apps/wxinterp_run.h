/* wxinterp.h - the wxinterp program as a library call: provider files in,
 * weather states (cloudwx/2, man 5 cloudwx) out, one per requested time.
 * Its parts - merging files and interpolating in time (weather/series.h),
 * the genus rules (genus_rules.h), play-mode edits (wxset.h) - are
 * callable alone. */
#ifndef CS_WXINTERP_H
#define CS_WXINTERP_H

#include "weather/provider.h"
#include "weather/series.h"
#include "weather/wx.h"
#include "weather/genus_rules.h"
#include "weather/transition.h"

#include <signal.h>

#define CS_WXINTERP_MAX_INPUTS 32
#define CS_WXINTERP_MAX_SETS 64
#define CS_WXINTERP_MAX_STATES 1000000
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
	double fade_s;                        /* a genus change fades over this
						 window (default CS_WX_FADE_S;
						 0: at once; transition.h) */
	const char *sets[CS_WXINTERP_MAX_SETS]; /* "PATH=VALUE" (wxset.h) */
	int nsets;
	const char *site_name;                /* or NULL: from the file */
	int have_alt;
	double alt_m;                         /* ground height override */
	int template_state;                   /* the default state, no inputs */
	int pretty;                           /* indented JSON (one state) */
	int summary;                          /* 1: a table per time (wxsummary.h)
						 instead of states; 2: per UTC day */
	int summary_json;                     /* the summary as JSON Lines */
	const char *output;                   /* path or "-" (default) */
	int no_clobber;                       /* never replace an existing file */
	cs_note_fn note;
	void *note_user;
	/* Set (to nonzero, by the caller's signal handler) to stop: the run
	 * returns CS_ECANCELED before the next state and leaves no output. */
	const volatile sig_atomic_t *cancel;
};

/* What a run produced. */
struct cs_wxinterp_result {
	long nstates;                         /* states written */
};

void cs_wxinterp_defaults(struct cs_wxinterp_opts *o);

/* Reads the inputs, writes the states (atomically).  CS_EINVAL for bad
 * options or --set edits, CS_EDATA for bad or insufficient data, CS_EIO,
 * CS_ECANCELED when *o->cancel was set (nothing written). */
int cs_wxinterp_run(const struct cs_wxinterp_opts *o, struct cs_wxinterp_result *res);

#endif
