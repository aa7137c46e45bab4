/* series.h - a provider's hourly series in time: reading a file, merging
 * files of one site, the value of a variable at any time (linear, nulls
 * bridged), and the observations the genus rules take. */
#ifndef CS_SERIES_H
#define CS_SERIES_H

#include "weather/genus_rules.h"
#include "weather/provider.h"

#include <stddef.h>

#define CS_SERIES_MAX_HOURS 200000 /* span of merged inputs (22 years) */
#define CS_SERIES_MERGE_DEG 0.1    /* files this close are one site */

/* Reads and parses a provider file ("-" = standard input); messages start
 * with the file name. */
int cs_series_read(const char *path, struct cs_series *s);

/* Merges b into a (the union of their hours on one hourly grid, NaN where
 * neither has a value; where both have a value b's wins, as later files
 * win in gdal_merge).  The sites must lie within CS_SERIES_MERGE_DEG of
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

/* The drift of the air over a series: the integral of the 10-m wind
 * vector (the way it blows toward, speed and direction interpolated as
 * cs_series_value does) from the series' first hour, tabled at each hour
 * (east[i], north[i] at time_utc[i], m).  Each hour is integrated by an
 * 8-point Gauss-Legendre rule; an hour whose wind has no value (a gap
 * longer than max_gap_s) adds nothing.  axis_deg: the compass bearing the
 * mean of the hourly wind vectors blows toward (0 if it is calm). */
struct cs_drift {
	int n;
	double *east, *north;
	double since_utc;
	double axis_deg;
	double max_gap_s;
};

/* Tables the drift of s (allocates; cs_drift_free releases). */
int cs_drift_new(struct cs_drift *d, const struct cs_series *s,
		 double max_gap_s);
void cs_drift_free(struct cs_drift *d);

/* The drift at time t inside the series, m: the table's value at the hour
 * before t plus the integral from that hour to t (the same rule on the
 * shorter interval), so that it is continuous in t and the same for t
 * whatever other times are asked. */
int cs_drift_at(const struct cs_drift *d, const struct cs_series *s, double t,
		double *east_m, double *north_m);

/* "2024-10-06T00:00:00Z to 2024-10-14T00:00:00Z" (the hours covered). */
void cs_series_range(const struct cs_series *s, char *buf, size_t size);

#endif
