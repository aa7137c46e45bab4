#include "core/time.h"

#include "core/err.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Howard Hinnant's days_from_civil: exact for the proleptic Gregorian
 * calendar, without any table or time zone database. */
long cs_days_from_civil(long y, int m, int d)
{
	y -= m <= 2;
	long era = (y >= 0 ? y : y - 399) / 400;
	long yoe = y - era * 400;
	long doy = (153L * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
	long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
	return era * 146097 + doe - 719468;
}

static void civil_from_days(long z, long *y, int *m, int *d)
{
	z += 719468;
	long era = (z >= 0 ? z : z - 146096) / 146097;
	long doe = z - era * 146097;
	long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
	long doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
	long mp = (5 * doy + 2) / 153;
	*d = (int)(doy - (153 * mp + 2) / 5 + 1);
	*m = (int)(mp < 10 ? mp + 3 : mp - 9);
	*y = yoe + era * 400 + (*m <= 2);
}

static int days_in_month(long y, int m)
{
	static const int dm[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
	int leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
	return m == 2 ? 28 + leap : dm[m - 1];
}

/* Reads exactly n digits. */
static int digits(const char **p, int n, int *out)
{
	int v = 0;
	for (int i = 0; i < n; i++) {
		if (!isdigit((unsigned char)(*p)[i]))
			return -1;
		v = v * 10 + ((*p)[i] - '0');
	}
	*p += n;
	*out = v;
	return 0;
}

int cs_time_parse(const char *s, double *unix_s)
{
	const char *p = s;
	int y, mo, d, h, mi, sec = 0;
	double frac = 0.0;
#define BAD(why) return cs_error(CS_EINVAL, "'%.64s' is not an ISO 8601 UTC time (%s)", s, why)
	if (digits(&p, 4, &y) || *p++ != '-' || digits(&p, 2, &mo) || *p++ != '-' ||
	    digits(&p, 2, &d))
		BAD("expected YYYY-MM-DD");
	if (*p != 'T' && *p != 't' && *p != ' ')
		BAD("expected T and a time of day");
	p++;
	if (digits(&p, 2, &h) || *p++ != ':' || digits(&p, 2, &mi))
		BAD("expected hh:mm");
	if (*p == ':') {
		p++;
		if (digits(&p, 2, &sec))
			BAD("expected hh:mm:ss");
		if (*p == '.' || *p == ',') {
			const char *q = ++p;
			double scale = 0.1;
			while (isdigit((unsigned char)*p)) {
				frac += (*p - '0') * scale;
				scale *= 0.1;
				p++;
			}
			if (p == q)
				BAD("expected digits after the decimal point");
		}
	}
	if (mo < 1 || mo > 12 || d < 1 || d > days_in_month(y, mo))
		BAD("no such date");
	if (h > 23 || mi > 59 || sec > 60)
		BAD("no such time of day");
	long offset_s = 0;
	if (*p == 'Z' || *p == 'z') {
		p++;
	} else if (*p == '+' || *p == '-') {
		int sign = *p++ == '-' ? -1 : 1, oh, om = 0;
		if (digits(&p, 2, &oh))
			BAD("expected a zone offset +hh:mm");
		if (*p == ':')
			p++;
		if (isdigit((unsigned char)*p) && digits(&p, 2, &om))
			BAD("expected a zone offset +hh:mm");
		if (oh > 18 || om > 59)
			BAD("zone offset out of range");
		offset_s = sign * (oh * 3600L + om * 60L);
	} else if (*p == '\0') {
		BAD("no time zone: add Z for UTC or an offset such as +02:00");
	}
	if (*p != '\0')
		BAD("unexpected text at the end");
#undef BAD
	*unix_s = (double)cs_days_from_civil(y, mo, d) * 86400.0 + h * 3600.0 +
		  mi * 60.0 + sec + frac - (double)offset_s;
	return CS_OK;
}

void cs_time_format(double unix_s, char *buf, size_t size)
{
	double fl = floor(unix_s);
	long days = (long)floor(fl / 86400.0);
	long rem = (long)(fl - days * 86400.0);
	long y;
	int m, d;
	civil_from_days(days, &y, &m, &d);
	snprintf(buf, size, "%04ld-%02d-%02dT%02ld:%02ld:%02ldZ", y, m, d,
		 rem / 3600, rem / 60 % 60, rem % 60);
}

struct cs_time_text cs_time_text(double unix_s)
{
	struct cs_time_text t;
	double whole = floor(unix_s);
	long ms = isfinite(unix_s) ? lround((unix_s - whole) * 1000.0) : 0;
	if (ms == 1000)
		whole += 1.0, ms = 0;
	cs_time_format(whole, t.s, sizeof t.s);
	size_t n = strlen(t.s);
	if (ms > 0 && n >= 1 && n + 5 <= sizeof t.s) {
		/* "...:00.5Z": a message must not round 22:00:00.5 to 22:00:00 */
		char frac[24];
		snprintf(frac, sizeof frac, ".%03ld", ms);
		for (size_t k = strlen(frac); k > 2 && frac[k - 1] == '0'; k--)
			frac[k - 1] = '\0';
		snprintf(t.s + n - 1, sizeof t.s - (n - 1), "%sZ", frac);
	}
	return t;
}

double cs_julian_day(double unix_s)
{
	return unix_s / 86400.0 + 2440587.5;
}

int cs_duration_parse(const char *s, double *seconds)
{
	char *end;
	errno = 0;
	double v = strtod(s, &end);
	double unit = 1;
	if (end != s && end[0] != '\0' && end[1] == '\0')
		unit = end[0] == 's' ? 1 : end[0] == 'm' ? 60 : end[0] == 'h' ?
		       3600 : end[0] == 'd' ? 86400 : 0;
	else if (end == s || end[0] != '\0')
		unit = 0;
	if (unit == 0 || s[0] == '-' || s[0] == '+' || errno == ERANGE ||
	    !(v * unit > 0) || !isfinite(v * unit))
		return cs_error(CS_EINVAL, "'%s' is not a duration (a positive "
				"number with s, m, h or d, e.g. 10m)", s);
	*seconds = v * unit;
	return CS_OK;
}
