/* sun.h - where the sun is: NOAA's solar position algorithm (Meeus,
 * Astronomical Algorithms, ch. 25 low-accuracy solar coordinates, with the
 * equation of time and NOAA's piecewise refraction fit). */
#ifndef CS_SUN_H
#define CS_SUN_H

#include "core/vec.h"

struct cs_sun {
	double azimuth_deg;        /* from true north, clockwise (east 90), 0..360 */
	double elevation_deg;      /* geometric (no refraction), -90..90 */
	double apparent_elevation_deg; /* with atmospheric refraction */
	double declination_deg;
	double right_ascension_deg; /* apparent, 0..360 */
	double apparent_longitude_deg;
	double equation_of_time_min;
	double distance_au;        /* earth-sun distance */
};

/* Sun position for a UTC time (seconds since 1970) and a place (WGS84
 * degrees, east positive). Returns CS_EINVAL for non-finite input or a
 * latitude outside -90..90. Valid for years 1800..2200. */
int cs_sun_position(double unix_s, double lat_deg, double lon_deg, struct cs_sun *out);

/* Unit vector toward the sun in the local east-north-up frame, from the
 * apparent elevation and azimuth. */
cs_v3 cs_sun_direction_enu(const struct cs_sun *s);

#endif
