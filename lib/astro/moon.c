#include "astro/moon.h"

#include "astro/sun.h"
#include "core/err.h"
#include "core/time.h"

#include <math.h>

#define RAD (CS_PI / 180.0)

static double sind(double d) { return sin(d * RAD); }
static double cosd(double d) { return cos(d * RAD); }

static double wrap360(double d)
{
	d = fmod(d, 360.0);
	return d < 0.0 ? d + 360.0 : d;
}

/* Geocentric ecliptic longitude, latitude (deg) and horizontal parallax
 * (deg) for T Julian centuries from J2000 (Astronomical Almanac, low
 * precision formulae for the Moon). */
static void ecliptic(double T, double *lon, double *lat, double *par)
{
	*lon = wrap360(218.32 + 481267.881 * T + 6.29 * sind(135.0 + 477198.87 * T) -
		       1.27 * sind(259.3 - 413335.36 * T) + 0.66 * sind(235.7 + 890534.22 * T) +
		       0.21 * sind(269.9 + 954397.74 * T) - 0.19 * sind(357.5 + 35999.05 * T) -
		       0.11 * sind(186.5 + 966404.03 * T));
	*lat = 5.13 * sind(93.3 + 483202.02 * T) + 0.28 * sind(228.2 + 960400.89 * T) -
	       0.28 * sind(318.3 + 6003.15 * T) - 0.17 * sind(217.6 - 407332.21 * T);
	*par = 0.9508 + 0.0518 * cosd(135.0 + 477198.87 * T) + 0.0095 * cosd(259.3 - 413335.36 * T) +
	       0.0078 * cosd(235.7 + 890534.22 * T) + 0.0028 * cosd(269.9 + 954397.74 * T);
}

int cs_moon_position(double unix_s, double lat_deg, double lon_deg, struct cs_moon *out)
{
	if (!isfinite(unix_s) || !isfinite(lon_deg) || !(lat_deg >= -90.0 && lat_deg <= 90.0))
		return cs_error(CS_EINVAL, "moon position needs a finite time and place");
	double jd = cs_julian_day(unix_s), d = jd - 2451545.0, T = d / 36525.0;
	double lam, bet, par;
	ecliptic(T, &lam, &bet, &par);
	out->longitude_deg = lam, out->latitude_deg = bet;
	out->distance_km = 6378.14 / sind(par);
	double eps = 23.439 - 0.0000004 * d;
	double ra = atan2(sind(lam) * cosd(eps) - tan(bet * RAD) * sind(eps), cosd(lam)) / RAD;
	double dec = asin(sind(bet) * cosd(eps) + cosd(bet) * sind(eps) * sind(lam)) / RAD;
	out->right_ascension_deg = wrap360(ra), out->declination_deg = dec;
	/* hour angle from the mean sidereal time (Meeus 12.4) */
	double gmst = wrap360(280.46061837 + 360.98564736629 * d);
	double H = gmst + lon_deg - ra;
	double alt = asin(sind(lat_deg) * sind(dec) + cosd(lat_deg) * cosd(dec) * cosd(H)) / RAD;
	double az = atan2(-sind(H), tan(dec * RAD) * cosd(lat_deg) - sind(lat_deg) * cosd(H)) / RAD;
	out->azimuth_deg = wrap360(az);
	out->elevation_deg = alt - par * cosd(alt); /* seen from the surface */
	/* the phase angle from the elongation from the sun (Meeus 48.2-48.3) */
	struct cs_sun sun;
	int rc = cs_sun_position(unix_s, lat_deg, lon_deg, &sun);
	if (rc != CS_OK)
		return rc;
	double psi = acos(cosd(bet) * cosd(lam - sun.apparent_longitude_deg));
	double r = sun.distance_au * 149597870.7;
	double i = atan2(r * sin(psi), out->distance_km - r * cos(psi)) / RAD;
	out->phase_angle_deg = i;
	out->illuminated_fraction = (1.0 + cosd(i)) / 2.0;
	/* Allen's phase law: magnitude -12.73 + 0.026 |i| + 4e-9 i^4 at mean
	 * distance; a magnitude m gives 10^(-0.4 (m + 14.18)) lux */
	double m = -12.73 + 0.026 * fabs(i) + 4e-9 * i * i * i * i;
	double scale = 384400.0 / out->distance_km;
	out->illuminance_lux = pow(10.0, -0.4 * (m + 14.18)) * scale * scale;
	return CS_OK;
}

cs_v3 cs_moon_direction_enu(const struct cs_moon *m)
{
	double el = m->elevation_deg * RAD, az = m->azimuth_deg * RAD;
	return v3(cos(el) * sin(az), cos(el) * cos(az), sin(el));
}
