/* scene.h - from a weather state, a place and a time to a scene: clouds,
 * sun and sky, ground, haze and rain; the named viewpoints; geographic to
 * world coordinates. */
#ifndef CS_SCENE_H
#define CS_SCENE_H

#include "render/cloud.h"
#include "render/render.h"
#include "weather/places.h" /* the named viewpoints */
#include "weather/wx.h"

/* World position (ENU at sea level under the origin, on the spherical Earth
 * of radius earth_radius_m) of a geographic point. */
cs_v3 cs_geo_to_world(double origin_lat_deg, double origin_lon_deg,
		      double earth_radius_m, double lat_deg, double lon_deg,
		      double alt_m);

/* Builds the scene for wx at time_utc (seconds since 1970): the origin is
 * the weather site; the sun is placed for that time and place; layers with
 * no coverage are left out; rain only when it rains under a raining genus;
 * haze from the visibility.  The noise must outlive the scene. */
int cs_scene_build(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
		   const struct cs_volume *noise);
/* The same, the light fields of fog and of broken or overcast layers
 * solved on nthreads of the CPU pool (<= 0: one per processor): the same
 * scene for any number. */
int cs_scene_build_threads(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
			   const struct cs_volume *noise, int nthreads);

#endif
