#include "weather/series.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/geo.h"
#include "core/time.h"
#include "astro/sun.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FILE_BYTES ((size_t)64 << 20)

static const char *label(const char *path)
{
	return strcmp(path, "-") == 0 ? "standard input" : path;
}

int cs_series_read(const char *path, struct cs_series *s)
{
	unsigned char *data;
	size_t len;
	memset(s, 0, sizeof *s);
	int rc = cs_read_all(path, MAX_FILE_BYTES, &data, &len);
	if (rc != CS_OK)
		return rc;
	rc = cs_provider_parse((const char *)data, len, label(path), s);
	free(data);
	return rc;
}

void cs_series_range(const struct cs_series *s, char *buf, size_t size)
{
	char a[32], b[32];
	if (s->n <= 0) {
		snprintf(buf, size, "no hours");
		return;
	}
	cs_time_format(s->time_utc[0], a, sizeof a);
	cs_time_format(s->time_utc[s->n - 1], b, sizeof b);
	snprintf(buf, size, "%s to %s", a, b);
}

/* ---- merging -------------------------------------------------------------- */

int cs_series_merge(struct cs_series *a, const struct cs_series *b,
		    double *dist_km)
{
	double d = cs_great_circle_m(a->lat_deg, a->lon_deg, b->lat_deg,
				     b->lon_deg) / 1000.0;
	if (dist_km != NULL)
		*dist_km = d;
	if (!(fabs(a->lat_deg - b->lat_deg) <= CS_SERIES_MERGE_DEG &&
	      fabs(a->lon_deg - b->lon_deg) <= CS_SERIES_MERGE_DEG))
		return cs_error(CS_EDATA, "its site (%.4f, %.4f) is %.1f km "
				"from the first file's (%.4f, %.4f): not the same "
				"site (a distant site is given with --far)",
				b->lat_deg, b->lon_deg, d, a->lat_deg, a->lon_deg);
	if (a->n <= 0 || b->n <= 0)
		return cs_error(CS_EDATA, "no hours to merge");
	double shift = fmod(b->time_utc[0] - a->time_utc[0], 3600.0);
	if (shift != 0)
		return cs_error(CS_EDATA, "its hours fall %.0f min off the first "
				"file's hours", fabs(shift) / 60);
	double t0 = fmin(a->time_utc[0], b->time_utc[0]);
	double t1 = fmax(a->time_utc[a->n - 1], b->time_utc[b->n - 1]);
	double hours = (t1 - t0) / 3600 + 1;
	if (hours > CS_SERIES_MAX_HOURS)
		return cs_error(CS_EDATA, "together the files span %.0f hours, "
				"more than %d", hours, CS_SERIES_MAX_HOURS);
	int n = (int)hours;
	int ia = (int)((a->time_utc[0] - t0) / 3600);
	int ib = (int)((b->time_utc[0] - t0) / 3600);
	struct cs_series m = *a;
	m.n = n;
	m.time_utc = malloc((size_t)n * sizeof *m.time_utc);
	int fail = m.time_utc == NULL;
	for (int k = 0; k < CS_VAR_COUNT; k++) {
		m.v[k] = NULL;
		if (fail || (a->v[k] == NULL && b->v[k] == NULL))
			continue;
		if ((m.v[k] = malloc((size_t)n * sizeof *m.v[k])) == NULL) {
			fail = 1;
			continue;
		}
		for (int i = 0; i < n; i++)
			m.v[k][i] = NAN;
		for (int i = 0; a->v[k] && i < a->n; i++)
			m.v[k][ia + i] = a->v[k][i];
		for (int i = 0; b->v[k] && i < b->n; i++)
			if (!isnan(b->v[k][i]))
				m.v[k][ib + i] = b->v[k][i];
		if (m.key[k][0] == '\0')
			memcpy(m.key[k], b->key[k], sizeof m.key[k]);
		if (m.note[0] == '\0')
			memcpy(m.note, b->note, sizeof m.note);
	}
	if (fail) {
		cs_series_free(&m);
		return cs_error(CS_ENOMEM, "out of memory merging");
	}
	for (int i = 0; i < n; i++)
		m.time_utc[i] = t0 + 3600.0 * i;
	cs_series_free(a);
	*a = m;
	return CS_OK;
}

/* ---- interpolation -------------------------------------------------------- */

static double lerp(double a, double b, double f, int angle)
{
	if (!angle)
		return a + f * (b - a);
	/* the short way round: d in [-180, 180) */
	double d = fmod(b - a + 540.0, 360.0) - 180.0;
	double v = fmod(a + f * d + 360.0, 360.0);
	return v >= 360.0 ? 0.0 : v;
}


int cs_series_value(const struct cs_series *s, enum cs_wxvar k, double t,
		    double max_gap_s, double *out)
{
	if ((unsigned)k >= CS_VAR_COUNT || s->v[k] == NULL)
		return cs_error(CS_EDATA, "no %s in the data",
				cs_wxvar_name(k));
	const char *name = cs_wxvar_name(k), *key = s->key[k];
	int n = s->n;
	if (n <= 0 || !(t >= s->time_utc[0] && t <= s->time_utc[n - 1])) {
		char r[80];
		cs_series_range(s, r, sizeof r);
		return cs_error(CS_EDATA, "%s is outside the data (%s)",
				cs_time_text(t).s, r);
	}
	const double *v = s->v[k];
	int angle = k == CS_VAR_WIND_FROM;
	int i = (int)floor((t - s->time_utc[0]) / 3600.0);
	if (i > n - 1)
		i = n - 1;
	double f = (t - s->time_utc[i]) / 3600.0;
	if (f == 0 && !isnan(v[i])) {
		*out = v[i];
		return CS_OK;
	}
	if (f > 0 && i + 1 < n && !isnan(v[i]) && !isnan(v[i + 1])) {
		*out = lerp(v[i], v[i + 1], f, angle);
		return CS_OK;
	}
	/* a null: the nearest valid hours at or before t and after it */
	int ja = i, jb = f > 0 || isnan(v[i]) ? i + 1 : i;
	while (ja >= 0 && isnan(v[ja]))
		ja--;
	while (jb < n && isnan(v[jb]))
		jb++;
	if (ja < 0 && jb >= n)
		return cs_error(CS_EDATA, "%s (%s) is null at every hour", name,
				key);
	if (ja < 0)
		return cs_error(CS_EDATA, "%s (%s) has no value at %s: it is "
				"null from the start of the data to %s, with no "
				"valid hour before", name, key, cs_time_text(t).s,
				cs_time_text(s->time_utc[jb - 1]).s);
	if (jb >= n)
		return cs_error(CS_EDATA, "%s (%s) has no value at %s: it is "
				"null from %s to the end of the data, with no "
				"valid hour after", name, key, cs_time_text(t).s,
				cs_time_text(s->time_utc[ja + 1]).s);
	double ta = s->time_utc[ja], tb = s->time_utc[jb];
	if (tb - ta > max_gap_s)
		return cs_error(CS_EDATA, "%s (%s) has no value at %s: the "
				"nearest valid hours, %s and %s, are %g h apart "
				"(at most %g h are bridged: --max-gap)", name,
				key, cs_time_text(t).s, cs_time_text(ta).s, cs_time_text(tb).s,
				(tb - ta) / 3600, max_gap_s / 3600);
	*out = lerp(v[ja], v[jb], (t - ta) / (tb - ta), angle);
	return CS_OK;
}

/* An optional variable: NaN when the file lacks it. */
static int optional(const struct cs_series *s, enum cs_wxvar k, double t,
		    double gap, double *out)
{
	*out = NAN;
	return s->v[k] == NULL ? CS_OK : cs_series_value(s, k, t, gap, out);
}

/* The fraction of the precipitation falling as snow at t: the provider's
 * (meteoblue snowfraction), else from Open-Meteo's snowfall when it
 * precipitates, else by the temperature rule, else none. */
static double snow_fraction(const struct cs_series *s, double t, double gap,
			    const struct cs_wx_obs *o)
{
	double f = NAN, cm = NAN;
	if (s->v[CS_VAR_SNOW_FRACTION] != NULL &&
	    cs_series_value(s, CS_VAR_SNOW_FRACTION, t, gap, &f) == CS_OK)
		return f < 0 ? 0 : f > 1 ? 1 : f;
	if (s->v[CS_VAR_SNOWFALL] != NULL &&
	    cs_series_value(s, CS_VAR_SNOWFALL, t, gap, &cm) == CS_OK)
		f = cs_snow_fraction_of(cm, o->precipitation_mm_h);
	if (isnan(f))
		f = cs_snow_fraction_rule(o->temperature_c);
	return isnan(f) ? 0 : f;
}

/* The provider's radiation and total cover at t, where the file has them
 * and they interpolate (an observation that is missing is left out, not
 * an error: it is for comparing only). */
static void observed(const struct cs_series *s, double t, double gap,
		     struct cs_wx_observed *ob)
{
	memset(ob, 0, sizeof *ob);
	ob->has_radiation =
		s->v[CS_VAR_GHI] && s->v[CS_VAR_DNI] && s->v[CS_VAR_DHI] &&
		cs_series_value(s, CS_VAR_GHI, t, gap, &ob->ghi_w_m2) == CS_OK &&
		cs_series_value(s, CS_VAR_DNI, t, gap, &ob->dni_w_m2) == CS_OK &&
		cs_series_value(s, CS_VAR_DHI, t, gap, &ob->dhi_w_m2) == CS_OK;
	if (!ob->has_radiation)
		ob->ghi_w_m2 = ob->dni_w_m2 = ob->dhi_w_m2 = 0;
	ob->has_cloud_cover = s->v[CS_VAR_CLOUD_TOTAL] &&
		cs_series_value(s, CS_VAR_CLOUD_TOTAL, t, gap,
				&ob->total_cloud_cover) == CS_OK;
	ob->total_cloud_cover = ob->has_cloud_cover ?
		ob->total_cloud_cover / 100 : 0;
}

int cs_series_obs(const struct cs_series *s, double t, double gap,
		  struct cs_wx_obs *o)
{
	double fog;
	CS_TRY(cs_series_value(s, CS_VAR_CLOUD_LOW, t, gap, &o->low));
	CS_TRY(cs_series_value(s, CS_VAR_CLOUD_MID, t, gap, &o->mid));
	CS_TRY(cs_series_value(s, CS_VAR_CLOUD_HIGH, t, gap, &o->high));
	CS_TRY(cs_series_value(s, CS_VAR_PRECIP, t, gap, &o->precipitation_mm_h));
	CS_TRY(optional(s, CS_VAR_CONV_PRECIP, t, gap, &o->convective_mm_h));
	CS_TRY(cs_series_value(s, CS_VAR_WIND_SPEED, t, gap, &o->wind_speed_m_s));
	CS_TRY(cs_series_value(s, CS_VAR_WIND_FROM, t, gap, &o->wind_from_deg));
	CS_TRY(optional(s, CS_VAR_VISIBILITY, t, gap, &o->visibility_m));
	CS_TRY(optional(s, CS_VAR_FOG_PROBABILITY, t, gap, &fog));
	CS_TRY(optional(s, CS_VAR_TEMPERATURE, t, gap, &o->temperature_c));
	CS_TRY(optional(s, CS_VAR_HUMIDITY, t, gap, &o->humidity_pct));
	o->low /= 100;
	o->mid /= 100;
	o->high /= 100;
	o->fog_probability = fog / 100;
	/* no convective part given: none (the state's default) */
	if (isnan(o->convective_mm_h))
		o->convective_mm_h = 0;
	if (o->convective_mm_h > o->precipitation_mm_h)
		o->convective_mm_h = o->precipitation_mm_h;
	/* Open-Meteo: visibility at its ~24 km ceiling is a model default
	 * (unknown); low cover at an elevated site counts pressure levels
	 * below the ground (RADIATION-NOTES.md, "Data quirks") */
	int om = s->provider == CS_PROVIDER_OPENMETEO;
	o->visibility_default = om && o->visibility_m >= CS_WX_OM_VIS_CAP_LO &&
				o->visibility_m <= CS_WX_OM_VIS_CAP_HI;
	if (o->visibility_default)
		o->visibility_m = NAN;
	o->low_below_ground = om && s->alt_m >= CS_WX_OM_ELEVATED_M;
	o->snow_fraction = snow_fraction(s, t, gap, o);
	observed(s, t, gap, &o->observed);
	struct cs_sun sun;
	o->sun_elevation_deg = cs_sun_position(t, s->lat_deg, s->lon_deg, &sun)
			       == CS_OK ? sun.elevation_deg : NAN;
	return CS_OK;
}

/* ---- drift ---------------------------------------------------------------- */

/* The wind vector toward which the air moves at t (m/s east, north); 0 where
 * the wind has no value. */
static void wind_vector(const struct cs_series *s, double t, double gap,
			double *ve, double *vn)
{
	double speed, from;
	*ve = *vn = 0.0;
	if (cs_series_value(s, CS_VAR_WIND_SPEED, t, gap, &speed) != CS_OK ||
	    cs_series_value(s, CS_VAR_WIND_FROM, t, gap, &from) != CS_OK)
		return;
	from *= 3.14159265358979323846 / 180.0;
	*ve = -sin(from) * speed;
	*vn = -cos(from) * speed;
}

/* The integral of the wind vector from a to b: 8-point Gauss-Legendre
 * (Abramowitz & Stegun 1964, table 25.4); exact to 1e-12 relative for the
 * speed and direction linear in time over an hour (a turn of up to 180
 * degrees). */
static void integrate(const struct cs_series *s, double a, double b, double gap,
		      double *de, double *dn)
{
	static const double x[4] = {0.183434642495649805, 0.525532409916328986,
				    0.796666477413626740, 0.960289856497536232};
	static const double w[4] = {0.362683783378361983, 0.313706645877887287,
				    0.222381034453374471, 0.101228536290376259};
	double mid = 0.5 * (a + b), half = 0.5 * (b - a), se = 0.0, sn = 0.0;
	*de = *dn = 0.0;
	if (!(half > 0.0))
		return;
	for (int k = 0; k < 4; k++)
		for (int sign = -1; sign <= 1; sign += 2) {
			double ve, vn;
			wind_vector(s, mid + sign * half * x[k], gap, &ve, &vn);
			se += w[k] * ve;
			sn += w[k] * vn;
		}
	*de = se * half;
	*dn = sn * half;
}

int cs_drift_new(struct cs_drift *d, const struct cs_series *s, double max_gap_s)
{
	memset(d, 0, sizeof *d);
	if (s->n <= 0)
		return cs_error(CS_EDATA, "no hours to drift over");
	d->east = malloc((size_t)s->n * sizeof *d->east);
	d->north = malloc((size_t)s->n * sizeof *d->north);
	if (d->east == NULL || d->north == NULL) {
		cs_drift_free(d);
		return cs_error(CS_ENOMEM, "out of memory (%d hours)", s->n);
	}
	d->n = s->n;
	d->since_utc = s->time_utc[0];
	d->max_gap_s = max_gap_s;
	d->east[0] = d->north[0] = 0.0;
	double me = 0.0, mn = 0.0;
	for (int i = 0; i < s->n; i++) {
		double ve, vn;
		wind_vector(s, s->time_utc[i], max_gap_s, &ve, &vn);
		me += ve, mn += vn;
		if (i + 1 == s->n)
			break;
		double de, dn;
		integrate(s, s->time_utc[i], s->time_utc[i + 1], max_gap_s, &de, &dn);
		d->east[i + 1] = d->east[i] + de;
		d->north[i + 1] = d->north[i] + dn;
	}
	double az = atan2(me, mn) * (180.0 / 3.14159265358979323846);
	d->axis_deg = me == 0.0 && mn == 0.0 ? 0.0 : az < 0.0 ? az + 360.0 : az;
	return CS_OK;
}

void cs_drift_free(struct cs_drift *d)
{
	free(d->east);
	free(d->north);
	memset(d, 0, sizeof *d);
}

int cs_drift_at(const struct cs_drift *d, const struct cs_series *s, double t,
		double *east_m, double *north_m)
{
	if (d->n != s->n || d->n <= 0 ||
	    !(t >= s->time_utc[0] && t <= s->time_utc[s->n - 1]))
		return cs_error(CS_EDATA, "%s is outside the data's drift",
				cs_time_text(t).s);
	int i = (int)floor((t - s->time_utc[0]) / 3600.0);
	if (i > s->n - 2)
		i = s->n - 2;
	if (i < 0) { /* a single hour */
		*east_m = *north_m = 0.0;
		return CS_OK;
	}
	double de, dn;
	integrate(s, s->time_utc[i], t, d->max_gap_s, &de, &dn);
	*east_m = d->east[i] + de;
	*north_m = d->north[i] + dn;
	return CS_OK;
}
