/* transition.h - the cloud layers of a series at any time, with every
 * change of genus faded over a window instead of made at once.
 *
 * The genus rules (genus_rules.h) pick one rule per étage at each instant,
 * and a rule change is a jump: cumulus at 1186 m becomes stratocumulus at
 * 834 m the minute the sun sinks below 30 degrees.  Here each rule r of an
 * étage weighs w_r(t), the fraction of the window [t - W/2, t + W/2] during
 * which the rules pick it (a moving average of which rule holds, so each
 * weight changes by at most step / W over a step); the layer of r (genus,
 * coverage, base and top of the observation at t, cs_wx_rule_layer) enters
 * with its coverage times w_r (W = CS_WX_FADE_S unless the caller says).  Rules that make the same layer (showers and
 * fair-weather cumulus, thin and thick fog) add their weighted coverages
 * into one layer.  Away from a change (none within W/2) the layers are the
 * rules' own.  Where the data ends, the rules of its first or last hour
 * are taken to hold beyond it. */
#ifndef CS_TRANSITION_H
#define CS_TRANSITION_H

#include "weather/provider.h"
#include "weather/wx.h"

#define CS_WX_FADE_S 3600.0     /* W: a genus change fades over one hour,
				   the resolution of the data (default) */
#define CS_WX_FADE_MAX_S 21600.0 /* the longest window, 6 h */
#define CS_WX_FADE_GRID_S 60.0  /* the rules are read at whole minutes (UTC)
				   and a change between two is found by
				   bisection to 15 ms */

/* The layers at time t of series s (low to high, at most CS_WX_MAX_LAYERS,
 * those of coverage below 0.0005 left out) over ground at ground_alt_m,
 * changes faded over a window of fade_s seconds (0: none, the rules of
 * the instant, cs_wx_layers(); at most CS_WX_FADE_MAX_S).  The value at t
 * does not depend on any other time asked for.  Errors as cs_series_obs()
 * at t; CS_EINVAL for fade_s out of range. */
int cs_series_layers(const struct cs_series *s, double t, double max_gap_s,
		     double fade_s, double ground_alt_m, struct cs_wx_layer *layers,
		     int *nlayers);

#endif
