/* places.h - the one table of named places (weather sites, whose ground
 * height a forecast is asked for) and the viewpoints that stand on them. */
#ifndef CS_PLACES_H
#define CS_PLACES_H

/* A named place: WGS84 degrees; the ground (for hills the summit) in
 * metres above sea level. */
struct cs_place {
	const char *name;
	double lat_deg, lon_deg, alt_m;
	const char *description;
};

/* The built-in places (Bern and the places seen from its hills). */
const struct cs_place *cs_places(int *count);
/* The place of that name (case-insensitive), or NULL. */
const struct cs_place *cs_place_find(const char *name);

/* A named viewpoint: a camera eye_m above a place's ground (a tower's
 * platform), looking along azimuth and elevation (degrees). */
struct cs_view {
	const char *name;          /* as --view takes it (any case) */
	const struct cs_place *place;
	double eye_m;
	double azimuth_deg, elevation_deg, fov_deg;
	const char *description;
};

/* The built-in viewpoints, and the one with a name (case-insensitive;
 * NULL if none). */
const struct cs_view *cs_views(int *count);
const struct cs_view *cs_view_find(const char *name);

/* The camera's height above sea level, m: the place's ground plus eye_m. */
double cs_view_alt_m(const struct cs_view *v);

#endif
