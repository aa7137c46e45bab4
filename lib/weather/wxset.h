/* wxset.h - "play mode": edit fields of a weather state by path, as in
 * wxinterp --set PATH=VALUE.  The paths are those of man 5 cloudwx (and of
 * its error messages), with short aliases:
 *
 *   time_utc                     ISO 8601 time with zone
 *   precipitation_mm_h | precipitation, convective_mm_h | convective,
 *   visibility_m | visibility, fog_probability | fog,
 *   snow_fraction | snow, temperature_c | temperature (=none: unknown)
 *   site.name, site.lat_deg | lat, site.lon_deg | lon, site.alt_m | alt
 *   wind.speed_m_s | speed, wind.from_deg | from
 *   layers[N].genus|coverage|base_m|base|top_m|top   an existing layer
 *   layers[N]=GENUS      that genus, at its typical altitudes (N = the
 *                        number of layers appends one of coverage 0.5)
 *   layers[N]=none       removes layer N (later ones move down)
 *   layer.low|mid|high[.FIELD]   the layer of that étage, as layers[N];
 *                        setting a field of a missing one adds it first
 *                        (stratocumulus, altocumulus or cirrus, coverage
 *                        0.5); =none removes it if there is one
 *   far[N].site.FIELD, far[N].precipitation_mm_h, far[N].visibility_m,
 *   far[N].layers[M]..., far[N].layer.ETAGE...    a far site's
 *
 * A genus change moves the layer to the genus's typical altitudes
 * (cs_genus_place): set base and top after the genus.  Ranges are not
 * checked here: validate the state after all edits (cs_wx_validate). */
#ifndef CS_WXSET_H
#define CS_WXSET_H

#include "weather/wx.h"

/* Applies one "PATH=VALUE".  CS_EINVAL with a message that starts with the
 * assignment for an unknown path, an unreadable value, or a layer or far
 * site the state does not have; *wx may then be partly edited. */
int cs_wx_set(struct cs_wx *wx, const char *assignment);

/* Checks the syntax of an assignment without a state (what does not
 * depend on the state: path, number, genus, time). */
int cs_wx_set_check(const char *assignment);

#endif
