/* moon.h - where the Moon is and how much of it is lit: the Astronomical
 * Almanac's low-precision lunar formulae (a few terms of the series Meeus
 * gives in full in Astronomical Algorithms ch. 47; about 0.3 deg in
 * longitude, 0.2 deg in latitude), topocentric parallax, and the
 * illuminated fraction from the phase angle (Meeus ch. 48). */
#ifndef CS_MOON_H
#define CS_MOON_H

#include "core/vec.h"

struct cs_moon {
	double longitude_deg;      /* geocentric ecliptic, of date */
	double latitude_deg;
	double distance_km;        /* Earth's centre to the Moon's */
	double right_ascension_deg, declination_deg;
	double azimuth_deg;        /* topocentric, from north clockwise */
	double elevation_deg;      /* topocentric, geometric (no refraction) */
	double phase_angle_deg;    /* Sun-Moon-Earth angle: 0 full, 180 new */
	double illuminated_fraction; /* 0 new .. 1 full */
	double illuminance_lux;    /* on a plane facing it, above the
				      atmosphere: 0.267 lux full at mean distance,
				      by Allen's phase law */
};

/* The Moon for a UTC time (seconds since 1970) at a place (degrees, east
 * positive).  CS_EINVAL for non-finite input or a latitude outside
 * -90..90. */
int cs_moon_position(double unix_s, double lat_deg, double lon_deg, struct cs_moon *out);

/* Unit vector toward the Moon in the local east-north-up frame. */
cs_v3 cs_moon_direction_enu(const struct cs_moon *m);

#endif
