#include "apps/wxinterp_run.h"

#include "apps/wxsummary.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/json.h"
#include "core/time.h"
#include "weather/transition.h"
#include "weather/wxset.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void cs_wxinterp_defaults(struct cs_wxinterp_opts *o)
{
	memset(o, 0, sizeof *o);
	o->step_s = 3600;
	o->max_gap_s = CS_WXINTERP_DEFAULT_GAP_S;
	o->fade_s = CS_WX_FADE_S;
	o->output = "-";
}

static const char *label(const char *path)
{
	return strcmp(path, "-") == 0 ? "standard input" : path;
}


/* ---- the program ---------------------------------------------------------- */

/* The caller's cancel flag (a signal handler's), checked between states. */
static int canceled(const struct cs_wxinterp_opts *o)
{
	if (o->cancel != NULL && *o->cancel)
		return cs_error(CS_ECANCELED, "interrupted: no output written");
	return CS_OK;
}

struct run {
	const struct cs_wxinterp_opts *o;
	struct cs_wxinterp_result *res;
	struct cs_series main;
	char main_label[256];
	struct cs_wx_site site;
	struct cs_series far[CS_WX_MAX_FAR];
	struct cs_wx_site far_site[CS_WX_MAX_FAR];
	struct cs_drift drift;                /* of the main series' wind */
};

static void note(const struct cs_wxinterp_opts *o, int level, const char *fmt,
		 ...) __attribute__((format(printf, 3, 4)));

static void note(const struct cs_wxinterp_opts *o, int level, const char *fmt,
		 ...)
{
	if (o->note == NULL)
		return;
	char msg[1024];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	o->note(o->note_user, level, msg);
}

/* The site of a series: name from the option, the provider's, or its
 * coordinates ("46.950N 7.440E": a file's name says nothing of the place). */
static void site_of(const struct cs_series *s, const char *path,
		    const char *name, struct cs_wx_site *site)
{
	(void)path;
	memset(site, 0, sizeof *site);
	if (name == NULL && s->name[0] != '\0')
		name = s->name;
	if (name != NULL)
		snprintf(site->name, sizeof site->name, "%s", name);
	else
		snprintf(site->name, sizeof site->name, "%.3f%c %.3f%c", fabs(s->lat_deg),
			 s->lat_deg < 0 ? 'S' : 'N', fabs(s->lon_deg), s->lon_deg < 0 ? 'W' : 'E');
	site->lat_deg = s->lat_deg;
	site->lon_deg = s->lon_deg;
	site->alt_m = s->alt_m;
}

static void describe(const struct cs_wxinterp_opts *o, const char *path,
		     const struct cs_series *s)
{
	char r[80];
	cs_series_range(s, r, sizeof r);
	note(o, 2, "%s: %s, %d hours, %s (UTC offset %+g h), site \"%s\" "
	     "%.4f %.4f %.0f m", label(path), s->provider ==
	     CS_PROVIDER_METEOBLUE ? "meteoblue" : "Open-Meteo", s->n, r,
	     s->utc_offset_s / 3600, s->name, s->lat_deg, s->lon_deg, s->alt_m);
	if (s->note[0] != '\0')
		note(o, 2, "%s: %s", label(path), s->note);
}

static int read_inputs(struct run *r)
{
	const struct cs_wxinterp_opts *o = r->o;
	CS_TRY(cs_series_read(o->inputs[0], &r->main));
	describe(o, o->inputs[0], &r->main);
	snprintf(r->main_label, sizeof r->main_label, "%s%s",
		 label(o->inputs[0]), o->ninputs > 1 ? " (merged)" : "");
	for (int i = 1; i < o->ninputs; i++) {
		struct cs_series b;
		double km;
		CS_TRY(cs_series_read(o->inputs[i], &b));
		describe(o, o->inputs[i], &b);
		int rc = cs_series_merge(&r->main, &b, &km);
		cs_series_free(&b);
		if (rc != CS_OK)
			return cs_error(rc, "%s: %s", label(o->inputs[i]),
					cs_errmsg());
		if (km > 1)
			note(o, 1, "%s is %.1f km from %s; using the position "
			     "of %s", label(o->inputs[i]), km,
			     label(o->inputs[0]), label(o->inputs[0]));
	}
	site_of(&r->main, o->inputs[0], o->site_name, &r->site);
	if (o->have_alt)
		r->site.alt_m = o->alt_m;
	for (int i = 0; i < o->nfar; i++) {
		CS_TRY(cs_series_read(o->far[i], &r->far[i]));
		describe(o, o->far[i], &r->far[i]);
		site_of(&r->far[i], o->far[i], o->far_name[i], &r->far_site[i]);
	}
	return cs_drift_new(&r->drift, &r->main, o->max_gap_s);
}

/* Both ends of the requested times inside every series. */
static int covered(const struct run *r, double t0, double t1)
{
	const struct cs_wxinterp_opts *o = r->o;
	for (int i = -1; i < o->nfar; i++) {
		const struct cs_series *s = i < 0 ? &r->main : &r->far[i];
		const char *name = i < 0 ? r->main_label : label(o->far[i]);
		double bad = t0 < s->time_utc[0] ? t0 :
			     t1 > s->time_utc[s->n - 1] ? t1 : NAN;
		if (!isnan(bad)) {
			char range[80];
			cs_series_range(s, range, sizeof range);
			return cs_error(CS_EDATA, "%s is outside the data: %s "
					"covers %s", cs_time_text(bad).s, name, range);
		}
	}
	return CS_OK;
}

static void explain(const struct cs_wxinterp_opts *o, const struct cs_wx *wx,
		    const struct cs_wx_obs *ob)
{
	enum cs_wx_rule rules[3];
	static const char *const etage[3] = {"low", "mid", "high"};
	const double cover[3] = {ob->low, ob->mid, ob->high};
	char msg[1200];
	size_t k = 0;
	cs_wx_rules(ob, rules);
	k += (size_t)snprintf(msg, sizeof msg, "%s: sun %.1f deg, rain %g mm/h "
			      "(convective %g, snow fraction %g)",
			      cs_time_text(wx->time_utc).s, ob->sun_elevation_deg,
			      ob->precipitation_mm_h, ob->convective_mm_h,
			      ob->snow_fraction);
	for (int e = 0; e < 3 && k < sizeof msg; e++)
		k += (size_t)snprintf(msg + k, sizeof msg - k, "; %s %g%%: %s",
				      etage[e], cover[e] * 100,
				      cs_wx_rule_text(rules[e]));
	if (ob->visibility_default && k < sizeof msg)
		snprintf(msg + k, sizeof msg - k, "; visibility at Open-Meteo's "
			 "~24 km ceiling, a model default: unknown, %g m used",
			 CS_WX_DEFAULT_VIS_M);
	note(o, 2, "%s", msg);
}

/* Fills one far site (layers, rain, visibility) at time t. */
static int far_state(const struct run *r, int i, double t, struct cs_wx_far *f)
{
	struct cs_wx_obs ob;
	int rc = cs_series_obs(&r->far[i], t, r->o->max_gap_s, &ob);
	if (rc != CS_OK)
		return cs_error(rc, "%s: %s", label(r->o->far[i]), cs_errmsg());
	f->site = r->far_site[i];
	rc = cs_series_layers(&r->far[i], t, r->o->max_gap_s, r->o->fade_s, f->site.alt_m,
			      f->layers, &f->nlayers);
	if (rc != CS_OK)
		return cs_error(rc, "%s: %s", label(r->o->far[i]), cs_errmsg());
	f->precipitation_mm_h = ob.precipitation_mm_h;
	f->visibility_m = isnan(ob.visibility_m) ? CS_WX_DEFAULT_VIS_M :
			  ob.visibility_m < 1 ? 1 : ob.visibility_m;
	return CS_OK;
}

/* The state at time t, before the --set edits. */
static int derive(const struct run *r, double t, struct cs_wx *wx,
		  struct cs_wx_obs *obs)
{
	struct cs_wx_obs ob;
	memset(wx, 0, sizeof *wx);
	int rc = cs_series_obs(&r->main, t, r->o->max_gap_s, &ob);
	if (rc != CS_OK)
		return cs_error(rc, "%s: %s", r->main_label, cs_errmsg());
	wx->time_utc = t;
	wx->site = r->site;
	rc = cs_series_layers(&r->main, t, r->o->max_gap_s, r->o->fade_s, wx->site.alt_m,
			      wx->layers, &wx->nlayers);
	if (rc != CS_OK)
		return cs_error(rc, "%s: %s", r->main_label, cs_errmsg());
	wx->precipitation_mm_h = ob.precipitation_mm_h;
	wx->convective_mm_h = ob.convective_mm_h;
	wx->wind_speed_m_s = ob.wind_speed_m_s;
	wx->wind_from_deg = ob.wind_from_deg;
	wx->visibility_m = isnan(ob.visibility_m) ? CS_WX_DEFAULT_VIS_M :
			   ob.visibility_m < 1 ? 1 : ob.visibility_m;
	wx->fog_probability = isnan(ob.fog_probability) ? 0 :
			      ob.fog_probability;
	wx->snow_fraction = ob.snow_fraction;
	wx->temperature_c = ob.temperature_c;
	wx->observed = ob.observed;
	wx->drift.known = 1;
	wx->drift.since_utc = r->drift.since_utc;
	wx->drift.axis_deg = r->drift.axis_deg;
	CS_TRY(cs_drift_at(&r->drift, &r->main, t, &wx->drift.east_m,
			   &wx->drift.north_m));
	explain(r->o, wx, &ob);
	wx->nfar = r->o->nfar;
	for (int i = 0; i < r->o->nfar; i++)
		CS_TRY(far_state(r, i, t, &wx->far[i]));
	if (obs != NULL)
		*obs = ob;
	return CS_OK;
}

/* Derives (or takes the template), edits, validates and writes one state. */
static int one_state(struct run *r, double t, struct cs_outfile *of)
{
	const struct cs_wxinterp_opts *o = r->o;
	struct cs_wx wx;
	if (o->template_state) {
		cs_wx_default(&wx);
		wx.time_utc = t;
		if (o->site_name != NULL)
			snprintf(wx.site.name, sizeof wx.site.name, "%s",
				 o->site_name);
		if (o->have_alt)
			wx.site.alt_m = o->alt_m;
	} else {
		CS_TRY(derive(r, t, &wx, NULL));
		if (cs_wx_validate(&wx) != CS_OK)
			return cs_error(CS_EDATA, "%s: the state at %s is invalid: "
					"%s", r->main_label, cs_time_text(t).s,
					cs_errmsg());
	}
	for (int i = 0; i < o->nsets; i++)
		CS_TRY(cs_wx_set(&wx, o->sets[i]));
	if (o->nsets > 0 && cs_wx_validate(&wx) != CS_OK)
		return cs_error(CS_EINVAL, "after --set: %s", cs_errmsg());
	char *json = NULL, *pretty = NULL;
	CS_TRY(cs_wx_to_json(&wx, &json));
	int rc = CS_OK;
	if (o->pretty)
		rc = cs_json_pretty(json, &pretty);
	if (rc == CS_OK && pretty == NULL) {
		size_t n = strlen(json);
		json[n] = '\n'; /* over the terminator: written by length */
		rc = cs_outfile_write(of, json, n + 1);
	} else if (rc == CS_OK) {
		rc = cs_outfile_write(of, pretty, strlen(pretty));
	}
	free(json);
	free(pretty);
	r->res->nstates++;
	return rc;
}

static int check_opts(const struct cs_wxinterp_opts *o)
{
	int stdin_uses = 0;
	for (int i = 0; i < o->ninputs; i++)
		stdin_uses += strcmp(o->inputs[i], "-") == 0;
	for (int i = 0; i < o->nfar; i++)
		stdin_uses += strcmp(o->far[i], "-") == 0;
	if (stdin_uses > 1)
		return cs_error(CS_EINVAL, "standard input ('-') can be read "
				"only once");
	if (o->template_state && (o->ninputs > 0 || o->nfar > 0))
		return cs_error(CS_EINVAL, "--template takes no input files");
	if (!o->template_state && o->ninputs == 0)
		return cs_error(CS_EINVAL, "no input: give a provider file "
				"('-' for standard input) or --template");
	if (o->ninputs > CS_WXINTERP_MAX_INPUTS || o->nfar > CS_WX_MAX_FAR ||
	    o->nsets > CS_WXINTERP_MAX_SETS || o->ninputs < 0 || o->nfar < 0)
		return cs_error(CS_EINVAL, "too many inputs, far sites or edits");
	if (o->have_at && (o->have_from || o->have_to))
		return cs_error(CS_EINVAL, "--at gives one time; --from and --to "
				"a series: not both");
	if (o->template_state && o->have_from != o->have_to)
		return cs_error(CS_EINVAL, "--template: a series needs both "
				"--from and --to");
	if (!(o->step_s >= 1) || !(o->max_gap_s >= 3600))
		return cs_error(CS_EINVAL, "the step must be at least 1 s and "
				"--max-gap at least 1 h");
	if (!(o->fade_s >= 0 && o->fade_s <= CS_WX_FADE_MAX_S))
		return cs_error(CS_EINVAL, "--fade: outside 0..6h");
	if (o->summary && (o->template_state || o->nsets > 0 || o->pretty))
		return cs_error(CS_EINVAL, "--summary describes provider files: "
				"not with --template, --set or --pretty");
	if (o->summary == 2 && (o->step_s != 3600 || o->have_at))
		return cs_error(CS_EINVAL, "--daily sums the hours of each day: "
				"no --step or --at with it");
	if (o->summary_json && !o->summary)
		return cs_error(CS_EINVAL, "--json goes with --summary");
	if (o->have_alt && !(o->alt_m >= -500 && o->alt_m <= 9000))
		return cs_error(CS_EINVAL, "--alt: outside -500..9000 m");
	for (int i = 0; i < o->nsets; i++)
		CS_TRY(cs_wx_set_check(o->sets[i]));
	return cs_outfile_check(o->output, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
}

/* --summary: the state and observation at each time, as a table. */
static int summary(struct run *r, double t0, long count)
{
	const struct cs_wxinterp_opts *o = r->o;
	struct cs_wxsum_row *rows = calloc((size_t)count, sizeof *rows);
	if (rows == NULL)
		return cs_error(CS_ENOMEM, "out of memory (%ld times)", count);
	int rc = CS_OK;
	for (long k = 0; rc == CS_OK && k < count; k++) {
		double t = t0 + (double)k * o->step_s;
		if ((rc = canceled(o)) != CS_OK)
			break;
		rc = derive(r, t, &rows[k].wx, &rows[k].ob);
		if (rc == CS_OK && cs_wx_validate(&rows[k].wx) != CS_OK)
			rc = cs_error(CS_EDATA, "%s: the state at %s is invalid: %s",
				      r->main_label, cs_time_text(t).s, cs_errmsg());
	}
	struct cs_outfile of;
	if (rc == CS_OK && (rc = cs_outfile_open(&of, o->output)) == CS_OK) {
		rc = cs_wxsum_write(rows, count, o->step_s, o->summary == 2,
				    o->summary_json, &of);
		if (rc == CS_OK)
			rc = cs_outfile_commit(&of);
		cs_outfile_abort(&of);
	}
	if (rc == CS_OK)
		r->res->nstates = count;
	free(rows);
	return rc;
}

static int run_times(struct run *r)
{
	const struct cs_wxinterp_opts *o = r->o;
	double t0, t1;
	if (o->have_at) {
		t0 = t1 = o->at_utc;
	} else if (o->template_state && !o->have_from) {
		struct cs_wx d;
		cs_wx_default(&d);
		t0 = t1 = d.time_utc;
	} else {
		t0 = o->have_from ? o->from_utc : r->main.time_utc[0];
		t1 = o->have_to ? o->to_utc : r->main.time_utc[r->main.n - 1];
	}
	if (t1 < t0)
		return cs_error(CS_EINVAL, "the series ends (%s) before it starts "
				"(%s)", cs_time_text(t1).s, cs_time_text(t0).s);
	double count = floor((t1 - t0) / o->step_s + 1e-9) + 1;
	if (count > CS_WXINTERP_MAX_STATES)
		return cs_error(CS_EINVAL, "%.0f states from %s to %s every %g s: "
				"more than %d", count, cs_time_text(t0).s, cs_time_text(t1).s,
				o->step_s, CS_WXINTERP_MAX_STATES);
	if (o->pretty && count > 1)
		return cs_error(CS_EINVAL, "--pretty writes one state, not a "
				"series of %.0f (JSON Lines)", count);
	if (!o->template_state)
		CS_TRY(covered(r, t0, t1));
	if (o->summary)
		return summary(r, t0, (long)count);
	struct cs_outfile of;
	CS_TRY(cs_outfile_open_flags(&of, o->output, o->no_clobber ? CS_OUT_NO_CLOBBER : 0));
	int rc = CS_OK;
	for (long k = 0; rc == CS_OK && k < (long)count; k++)
		if ((rc = canceled(o)) == CS_OK)
			rc = one_state(r, t0 + (double)k * o->step_s, &of);
	if (rc == CS_OK)
		rc = cs_outfile_commit(&of);
	cs_outfile_abort(&of);
	return rc;
}

int cs_wxinterp_run(const struct cs_wxinterp_opts *o, struct cs_wxinterp_result *res)
{
	if (o == NULL || res == NULL)
		return cs_error(CS_EINVAL, "cs_wxinterp_run: no options");
	res->nstates = 0;
	CS_TRY(check_opts(o));
	struct run *r = calloc(1, sizeof *r);
	if (r == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	r->o = o;
	r->res = res;
	int rc = o->template_state ? CS_OK : read_inputs(r);
	if (rc == CS_OK)
		rc = run_times(r);
	cs_series_free(&r->main);
	cs_drift_free(&r->drift);
	for (int i = 0; i < CS_WX_MAX_FAR; i++)
		cs_series_free(&r->far[i]);
	free(r);
	return rc;
}
