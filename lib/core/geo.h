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

#endif
