/* render.h - the integrator: rays through spherical cloud shells, light
 * marched toward the sun, tiles on all cores.
 *
 * World frame: east-north-up at sea level below the scene origin, metres;
 * the Earth is a sphere centred at (0, 0, -earth_radius_m).  Radiance is in
 * kcd/m^2 per linear-sRGB channel (see sky.h). */
#ifndef CS_RENDER_H
#define CS_RENDER_H

#include "render/cloud.h"
#include "terrain/heightfield.h"
#include "render/sky.h"
#include "core/geo.h" /* CS_EARTH_RADIUS_M */
#include "core/vec.h"

#include <stdint.h>

#define CS_SCENE_MAX_LAYERS 24 /* near layers and those of the far sites */
#define CS_SKY_DEPTH_M 1e10 /* Z of a ray that meets neither cloud nor ground */

struct cs_render_settings {
	int steps;             /* view samples across a layer's thickness */
	int max_steps;         /* most samples in one crossing of a layer */
	int light_steps;       /* samples toward the sun */
	int ms_octaves;        /* 1: single scattering; 2..4: + multiple-scattering octaves */
	int ambient;           /* sky light on the clouds: 1 on, 0 off */
	double jitter;         /* 0: step midpoints; 1: a per-pixel random offset */
	uint32_t seed;         /* for the jitter hash */
	double min_transmittance; /* a ray stops when it sees less than this */
};

/* The named presets: "low", "medium", "high", "reference".  0 or CS_EINVAL. */
int cs_render_quality(const char *name, struct cs_render_settings *s);
/* Validates settings ranges; 0 or CS_EINVAL naming the field. */
int cs_render_settings_check(const struct cs_render_settings *s);

/* What a scene simulates (cs_scene.effects). */
enum {
	CS_FX_SUN = 1,           /* direct sunlight (sun above the horizon) */
	CS_FX_SKY = 2,           /* sky background and sky light */
	CS_FX_CLOUDS = 4,        /* at least one layer with coverage */
	CS_FX_GROUND = 8,        /* ground shading */
	CS_FX_HAZE = 16,         /* aerial perspective from visibility */
	CS_FX_RAIN = 32,         /* rain below raining layers */
	CS_FX_CLOUD_SHADOWS = 64, /* clouds shadowing the ground */
	CS_FX_TERRAIN = 128      /* a heightfield instead of flat ground */
};

struct cs_scene {
	double earth_radius_m;
	double ground_alt_m;          /* flat ground: the sphere at this altitude */
	double ground_albedo[3];
	const struct cs_hfield *terrain; /* or NULL: flat ground everywhere;
					    else flat ground only outside it */
	const uint8_t *terrain_color; /* sRGB 8-bit RGB over the terrain grid, or NULL */
	int terrain_color_w, terrain_color_h;
	int nlayers;
	struct cs_cloud_layer layers[CS_SCENE_MAX_LAYERS];
	const struct cs_volume *noise;
	cs_v3 sun_dir;                /* unit, toward the sun */
	double sun_illuminance[3];    /* irradiance on a plane facing the sun */
	double ambient_up[3];         /* sky radiance (cosine mean) from above */
	double ambient_down[3];       /* from below (ground light) */
	struct cs_sky sky;            /* used when effects has CS_FX_SKY */
	double haze_beta0_per_m;      /* aerosol extinction at sea level */
	double haze_scale_height_m;
	double rain_extinction_per_m; /* grey extinction of falling rain */
	double rain_top_m;            /* rain falls from here to the ground */
	double albedo;                /* single-scattering albedo of cloud */
	double g_forward, g_back, w_forward; /* two-lobe Henyey-Greenstein */
	unsigned effects;
};

/* Henyey-Greenstein phase function (1/sr) for the cosine of the angle
 * between the light's and the view's directions of travel. */
double cs_phase_hg(double cos_theta, double g);

struct cs_render_stats {
	uint64_t pixels, density_samples, light_samples, rays_terminated_early,
		layer_crossings, terrain_cells;
};

/* Transmittance of the clouds from p toward the sun (1 without clouds or
 * sun): what makes cloud shadows on the ground. */
double cs_render_sun_transmittance(const struct cs_scene *sc,
				   const struct cs_render_settings *s, cs_v3 p,
				   struct cs_render_stats *st);

struct cs_ray_result {
	double rgb[3];          /* radiance toward the eye */
	double transmittance;   /* through the clouds only (1 = clear) */
	double depth_m;         /* first cloud or ground hit, or CS_SKY_DEPTH_M */
};

/* Radiance along one ray from origin o in unit direction d.  jitter_u in
 * [0, 1) offsets the samples (0.5 = midpoints).  Never NaN or Inf. */
void cs_render_ray(const struct cs_scene *sc, const struct cs_render_settings *s,
		   cs_v3 o, cs_v3 d, double jitter_u, struct cs_render_stats *st,
		   struct cs_ray_result *out);

struct cs_camera {
	int width, height;      /* pixels */
	cs_v3 pos;              /* world position */
	cs_v3 fwd, right, up;   /* orthonormal: view direction, image right, image up */
	double tan_half_fov;    /* horizontal */
};

/* A camera at world position pos looking at azimuth (deg from north,
 * clockwise) and elevation (deg) in the local frame at pos, with a
 * horizontal field of view in degrees.  origin_lat_deg fixes the direction
 * of north.  0 or CS_EINVAL. */
int cs_camera_init(struct cs_camera *c, const struct cs_scene *sc, cs_v3 pos,
		   double origin_lat_deg, double azimuth_deg, double elevation_deg,
		   double fov_deg, int width, int height);

/* The world ray through the centre of pixel (i, j), j = 0 at the top. */
cs_v3 cs_camera_ray(const struct cs_camera *c, int i, int j);

/* Renders the image into out: 5 floats per pixel (R, G, B, alpha, Z), rows
 * top to bottom.  Deterministic for any nthreads (<= 0: all processors). */
int cs_render_image(const struct cs_scene *sc, const struct cs_camera *cam,
		    const struct cs_render_settings *s, int nthreads,
		    cs_progress_fn progress, void *user, float *out,
		    struct cs_render_stats *stats);

/* Altitude above sea level of a world point. */
double cs_scene_altitude(const struct cs_scene *sc, cs_v3 p);

#endif
