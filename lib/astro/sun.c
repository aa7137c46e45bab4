#include "astro/sun.h"

#include "core/err.h"
#include "core/time.h"

#include <math.h>

/* Equation numbers are those of Meeus, Astronomical Algorithms, 2nd ed.
 * (1998); the coefficients are the ones NOAA's solar calculator
 * (NOAA_Solar_Calculations_day.xls) uses, so results match it to rounding. */

#define RAD (3.14159265358979323846 / 180.0)

/* Reduces an angle to [0, 360); never returns 360 for a tiny negative. */
static double wrap360(double a)
{
	a = fmod(a, 360.0);
	if (a < 0.0)
		a += 360.0;
	return a >= 360.0 ? 0.0 : a;
}

/* Refraction in degrees for a geometric elevation e in degrees: the
 * piecewise fit (in arc seconds) of NOAA's solar calculator, for standard
 * pressure and temperature; it agrees with Bennett's formula (Meeus ch. 16)
 * to well under an arc minute above the horizon.  Zero above 85 degrees,
 * where the true value is below 5".  No branch divides by tan(0). */
static double refraction_deg(double e)
{
	if (e > 85.0)
		return 0.0;
	double t = tan(e * RAD), r;
	if (e > 5.0)
		r = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / (t * t * t * t * t);
	else if (e > -0.575)
		r = 1735.0 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
	else
		r = -20.772 / t;
	return r / 3600.0;
}

int cs_sun_position(double unix_s, double lat_deg, double lon_deg, struct cs_sun *out)
{
	if (!out || !isfinite(unix_s) || !isfinite(lat_deg) || !isfinite(lon_deg))
		return cs_error(CS_EINVAL, "sun position: time and place must be finite numbers");
	if (lat_deg < -90.0 || lat_deg > 90.0)
		return cs_error(CS_EINVAL, "sun position: latitude %g is outside -90..90", lat_deg);

	/* Julian centuries from J2000.0 (25.1).  Meeus wants TT; we take TT = UT.
	 * Delta T (~14 s in 1800, ~69 s in 2020, a few minutes by 2200 at most)
	 * moves the sun along the ecliptic by 0.041 degrees a day, so by under
	 * 0.001 degrees today; the hour angle below uses UT, as it must. */
	double T = (cs_julian_day(unix_s) - 2451545.0) / 36525.0;

	double L0 = wrap360(280.46646 + T * (36000.76983 + T * 0.0003032)); /* 25.2 */
	double M = 357.52911 + T * (35999.05029 - T * 0.0001537);          /* 25.3 */
	double e = 0.016708634 - T * (0.000042037 + T * 0.0000001267);     /* 25.4 */
	double m = M * RAD;
	/* equation of the centre C (ch. 25, after 25.4) */
	double C = sin(m) * (1.914602 - T * (0.004817 + T * 0.000014)) +
		   sin(2.0 * m) * (0.019993 - T * 0.000101) + sin(3.0 * m) * 0.000289;
	double true_lon = L0 + C, v = (M + C) * RAD; /* true longitude, anomaly */
	double R = 1.000001018 * (1.0 - e * e) / (1.0 + e * cos(v)); /* 25.5 */

	/* apparent longitude: nutation and aberration through Omega (ch. 25) */
	double omega = (125.04 - 1934.136 * T) * RAD;
	double lambda = (true_lon - 0.00569 - 0.00478 * sin(omega)) * RAD;
	/* mean obliquity (22.2), corrected for nutation (25.8) */
	double eps0 = 23.0 + (26.0 + (21.448 - T * (46.8150 + T * (0.00059 - T * 0.001813))) / 60.0) / 60.0;
	double eps = (eps0 + 0.00256 * cos(omega)) * RAD;
	double ra = atan2(cos(eps) * sin(lambda), cos(lambda)); /* 25.6 */
	double s = sin(eps) * sin(lambda);                       /* 25.7 */
	double dec = asin(s < -1.0 ? -1.0 : s > 1.0 ? 1.0 : s);

	/* equation of time (28.3, Smart 1956), in radians of hour angle */
	double y = tan(eps / 2.0), l2 = 2.0 * L0 * RAD;
	y *= y;
	double E = y * sin(l2) - 2.0 * e * sin(m) + 4.0 * e * y * sin(m) * cos(l2) -
		   0.5 * y * y * sin(2.0 * l2) - 1.25 * e * e * sin(2.0 * m);

	/* true solar time = UTC + equation of time + 4 min per degree east; the
	 * hour angle is 0 at true noon, positive in the afternoon.  Degrees
	 * below: 240 s of clock time per degree. */
	double day_s = unix_s - 86400.0 * floor(unix_s / 86400.0);
	double ha = wrap360(day_s / 240.0 + E / RAD + lon_deg) - 180.0;

	/* Horizontal coordinates (13.5, 13.6) written as east/north/up
	 * components and taken with atan2: no acos near the zenith or at the
	 * poles, and atan2 stays finite (if arbitrary) when the sun is exactly
	 * overhead and the azimuth has no meaning. */
	double phi = lat_deg * RAD, H = ha * RAD;
	double east = -cos(dec) * sin(H);
	double north = cos(phi) * sin(dec) - sin(phi) * cos(dec) * cos(H);
	double up = sin(phi) * sin(dec) + cos(phi) * cos(dec) * cos(H);
	double el = atan2(up, hypot(east, north)) / RAD;

	out->azimuth_deg = wrap360(atan2(east, north) / RAD);
	out->elevation_deg = el;
	out->apparent_elevation_deg = el + refraction_deg(el);
	out->declination_deg = dec / RAD;
	out->right_ascension_deg = wrap360(ra / RAD);
	out->apparent_longitude_deg = wrap360(lambda / RAD);
	out->equation_of_time_min = 4.0 * E / RAD;
	out->distance_au = R;
	return 0;
}

cs_v3 cs_sun_direction_enu(const struct cs_sun *s)
{
	double el = s->apparent_elevation_deg * RAD, az = s->azimuth_deg * RAD;
	return v3(cos(el) * sin(az), cos(el) * cos(az), sin(el));
}
