/* geo.h - the spherical Earth of the whole toolchain (R = 6371 km) and
 * distances on it. */
#ifndef CS_GEO_H
#define CS_GEO_H

/* The Earth's mean radius, m (IUGG; the sphere of design notes). */
#define CS_EARTH_RADIUS_M 6371000.0

/* Great-circle distance in metres between two WGS84 positions (degrees),
 * on the sphere of CS_EARTH_RADIUS_M (haversine: accurate for small and
 * large separations alike, antipodes included). */
double cs_great_circle_m(double lat1_deg, double lon1_deg, double lat2_deg,
			 double lon2_deg);

/* Where an eye must look to see a target, on a sphere of radius_m: the
 * azimuth (degrees from true north, clockwise, 0..360) and the elevation
 * (degrees above the eye's horizon, -90..90, the Earth's curvature
 * included) of the straight line from the eye to the target (WGS84
 * degrees, metres above the sphere).  0, or -1 when they coincide within
 * a micrometre (no direction; azimuth and elevation are left alone). */
int cs_look_at(double radius_m, double eye_lat_deg, double eye_lon_deg, double eye_alt_m,
	       double lat_deg, double lon_deg, double alt_m, double *azimuth_deg,
	       double *elevation_deg);

#endif
