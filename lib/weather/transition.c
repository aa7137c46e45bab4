#include "weather/transition.h"

#include "core/err.h"
#include "weather/genus_rules.h"
#include "weather/series.h"

#include <math.h>
#include <string.h>

/* The cases of an étage: the rules, and thick fog (L2 with visibility
 * under 1 km: coverage 1) apart from thin fog, so that fog thickening
 * fades too. */
enum { CASE_FOG_THICK = CS_RULE_COUNT, NCASES };
enum { BISECTIONS = 12 };        /* 60 s / 2^12 = 15 ms */
enum { MAX_GRID = (int)(CS_WX_FADE_MAX_S / CS_WX_FADE_GRID_S) + 3 };

struct cases {
	int c[3]; /* low, mid, high */
};

static struct cases cases_of(const struct cs_wx_obs *o)
{
	struct cases k;
	enum cs_wx_rule r[3];
	cs_wx_rules(o, r);
	for (int e = 0; e < 3; e++)
		k.c[e] = (int)r[e];
	if (r[0] == CS_RULE_L2_FOG && o->visibility_m < CS_WX_FOG_VIS_M)
		k.c[0] = CASE_FOG_THICK;
	return k;
}

/* The cases at time tau (clamped into the data); fallback where the
 * observation there fails (a gap too long to bridge). */
static struct cases cases_at(const struct cs_series *s, double tau, double gap,
			     const struct cases *fallback)
{
	struct cs_wx_obs o;
	double t0 = s->time_utc[0], t1 = s->time_utc[s->n - 1];
	tau = tau < t0 ? t0 : tau > t1 ? t1 : tau;
	if (cs_series_obs(s, tau, gap, &o) != CS_OK)
		return *fallback;
	return cases_of(&o);
}

/* The time in (a, b) where étage e's case stops being ca (bisection). */
static double switch_time(const struct cs_series *s, double a, double b, double gap,
			  int e, int ca, const struct cases *fallback)
{
	for (int i = 0; i < BISECTIONS; i++) {
		double m = 0.5 * (a + b);
		if (cases_at(s, m, gap, fallback).c[e] == ca)
			a = m;
		else
			b = m;
	}
	return 0.5 * (a + b);
}

/* The layer a case makes of observation o, or 0. */
static int case_layer(const struct cs_wx_obs *o, int c, double ground,
		      struct cs_wx_layer *l)
{
	struct cs_wx_obs v = *o;
	if (c == CASE_FOG_THICK || c == CS_RULE_L2_FOG) {
		/* the fog's coverage by its case, whatever visibility is now */
		v.visibility_m = c == CASE_FOG_THICK ? 0.0 : NAN;
		c = CS_RULE_L2_FOG;
	}
	return cs_wx_rule_layer(&v, (enum cs_wx_rule)c, ground, l);
}

/* Which layer a case is: fog is a stratus of its own (on the ground). */
static int layer_key(int c, enum cs_genus g)
{
	return c == CASE_FOG_THICK || c == CS_RULE_L2_FOG ? CS_GENUS_COUNT : (int)g;
}

int cs_series_layers(const struct cs_series *s, double t, double max_gap_s,
		     double fade_s, double ground_alt_m, struct cs_wx_layer *layers,
		     int *nlayers)
{
	struct cs_wx_obs o;
	*nlayers = 0;
	if (!(fade_s >= 0.0 && fade_s <= CS_WX_FADE_MAX_S))
		return cs_error(CS_EINVAL, "a fade of %g s is outside 0..%g s",
				fade_s, CS_WX_FADE_MAX_S);
	CS_TRY(cs_series_obs(s, t, max_gap_s, &o));
	if (fade_s == 0.0) {
		cs_wx_layers(&o, ground_alt_m, layers, nlayers, NULL);
		return CS_OK;
	}
	struct cases here = cases_of(&o), grid[MAX_GRID];
	double w[3][NCASES];
	memset(w, 0, sizeof w);
	/* the fraction of the window each case holds, read on a grid of whole
	 * minutes so that a change is found at the same instant whatever t is */
	const double g = CS_WX_FADE_GRID_S;
	double a = t - 0.5 * fade_s, b = t + 0.5 * fade_s;
	double k0 = floor(a / g);
	int n = (int)(ceil(b / g) - k0) + 1;
	n = n > MAX_GRID ? MAX_GRID : n;
	for (int i = 0; i < n; i++)
		grid[i] = cases_at(s, (k0 + i) * g, max_gap_s, &here);
	for (int i = 0; i + 1 < n; i++) {
		double ga = (k0 + i) * g, gb = ga + g;
		double lo = fmax(ga, a), hi = fmin(gb, b);
		if (!(hi > lo))
			continue;
		for (int e = 0; e < 3; e++) {
			int ca = grid[i].c[e], cb = grid[i + 1].c[e];
			if (ca == cb) {
				w[e][ca] += hi - lo;
				continue;
			}
			double sw = switch_time(s, ga, gb, max_gap_s, e, ca, &here);
			w[e][ca] += fmax(0.0, fmin(hi, sw) - lo);
			w[e][cb] += fmax(0.0, hi - fmax(lo, sw));
		}
	}
	/* each étage's layers, low to high, a case's coverage times its weight */
	struct cs_wx_layer out[3 * NCASES];
	int key[3 * NCASES], m = 0;
	for (int e = 0; e < 3; e++) {
		int first = m;
		for (int c = 0; c < NCASES; c++) {
			struct cs_wx_layer l;
			double f = w[e][c] / (b - a);
			if (!(f > 0.0) || !case_layer(&o, c, ground_alt_m, &l))
				continue;
			int k = layer_key(c, l.genus), j = first;
			while (j < m && key[j] != k)
				j++;
			if (j == m) {
				out[m] = l;
				out[m].coverage = 0.0;
				key[m++] = k;
			}
			out[j].coverage += f * l.coverage;
		}
	}
	/* the faintest left out when there are more than a state holds */
	for (int i = 0; i < m; i++) {
		if (out[i].coverage > 1.0)
			out[i].coverage = 1.0;
		if (!(out[i].coverage >= 0.0005))
			continue;
		int brighter = 0;
		for (int j = 0; j < m; j++)
			brighter += out[j].coverage >= 0.0005 &&
				    (out[j].coverage > out[i].coverage ||
				     (out[j].coverage == out[i].coverage && j < i));
		if (brighter < CS_WX_MAX_LAYERS)
			layers[(*nlayers)++] = out[i];
	}
	return CS_OK;
}
