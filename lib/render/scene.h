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

/* Where building a scene has a choice (cloudrender's options); zeroed,
 * the defaults. */
struct cs_scene_opts {
	enum cs_sky_level sky_level; /* the sky's absolute level */
};
/* cs_scene_build_threads with opts (NULL: the defaults). */
int cs_scene_build_opts(struct cs_scene *sc, const struct cs_wx *wx, double time_utc,
			const struct cs_volume *noise, int nthreads, const struct cs_scene_opts *opts);

/* The fit of the clouds' depth to the forecast's beam (cs_scene_fit_beam):
 * the points a side of its grid, the factor's bounds, the share of the
 * clear sky's beam below which the forecast has none, and the lowest sun
 * it fits under, degrees. */
#define CS_BEAM_FIT_N 24
#define CS_BEAM_FIT_K_MIN (1.0 / 64.0)
#define CS_BEAM_FIT_K_MAX 4.0
#define CS_BEAM_FIT_NONE 0.01
#define CS_BEAM_FIT_MIN_ELEVATION_DEG 10.0
/* the fit fades in over this much of the sun's elevation around that, deg */
#define CS_BEAM_FIT_RAMP_DEG 4.0
/* The sheets' optical depth scaled so that the clouds let through the
 * forecast's DNI of wx->observed (beam_fit.c; cs_scene_build calls it
 * once the layers and the sun are set, before their light): sets
 * sc->cloud_depth_scale, 1 where nothing is fitted.  CS_OK or CS_ENOMEM. */
int cs_scene_fit_beam(struct cs_scene *sc, const struct cs_wx *wx);

#endif
