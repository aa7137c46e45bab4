/* time.h - UTC times: ISO 8601 in and out, seconds since 1970 inside. */
#ifndef CS_TIME_H
#define CS_TIME_H

#include <stddef.h>

/* Parses an ISO 8601 date-time with a zone: "2021-06-14T16:45Z",
 * "2021-06-14T16:45:30Z", "2021-06-14T16:45:30.5+02:00", "...-0130"; a
 * space may replace the T.  A time without a zone is an error (it would be
 * ambiguous).  *unix_s is seconds since 1970-01-01T00:00:00Z, UTC. */
int cs_time_parse(const char *s, double *unix_s);

/* Formats as "2021-06-14T16:45:00Z" (whole seconds, rounded down). */
void cs_time_format(double unix_s, char *buf, size_t size);

/* Days since 1970-01-01 of a proleptic Gregorian date (any year). */
long cs_days_from_civil(long y, int m, int d);

/* Julian Day of a UTC time (JD 2440587.5 at the Unix epoch). */
double cs_julian_day(double unix_s);

/* A UTC time as ISO 8601 text for messages: cs_time_text(t).s; whole
 * seconds as cs_time_format writes them, a fraction to the millisecond
 * when there is one ("2021-06-14T22:00:00.5Z"). */
struct cs_time_text {
	char s[32];
};
struct cs_time_text cs_time_text(double unix_s);

/* A duration "90", "90s", "10m", "1.5h", "2d" in seconds (> 0). */
int cs_duration_parse(const char *s, double *seconds);

#endif
