/* march.h - internal to lib/render: the per-sample pieces the integrator's
 * files share.  Every function here is CS_HD: plain structs in, numbers
 * out, no I/O, allocation or globals, so one source serves a CPU and a GPU
 * build (core/hd.h). */
#ifndef CS_MARCH_H
#define CS_MARCH_H

#include "core/hd.h"
#include "render/render.h"

/* The parts of [0, tmax] of the ray o + t d inside the shell
 * r_in < |p - centre| < r_out: 0, 1 or 2 intervals. */
CS_HD int cs_shell_intervals(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
			     double r_in, double r_out, double tmax,
			     double iv[2][2]);

/* Sum of the extinction (1/m) of the layers in mask at p (altitude alt);
 * *dominant gets the layer with the most of it (untouched where none). */
CS_HD double cs_extinction_at(const struct cs_scene *sc, unsigned mask, cs_v3 p,
			      double alt, int *dominant);

/* Points the march hands to the density at once (cs_cloud_extinction_n):
 * on a CPU, so that their lookups overlap; a GPU thread takes them one at
 * a time (arrays indexed at run time would leave its registers). */
#ifdef __CUDA_ARCH__
#define CS_MARCH_BATCH 1
#else
#define CS_MARCH_BATCH 8
#endif

/* cs_extinction_at for n <= CS_MARCH_BATCH points (x[i], y[i], alt[i]):
 * sigma[i], and dominant[i] as cs_extinction_at leaves it from 0. */
CS_HD void cs_extinction_at_n(const struct cs_scene *sc, unsigned mask, int n, const double *x,
			      const double *y, const double *alt, double *sigma, int *dominant);

/* Optical depth of the clouds from p toward the sun (light_march.c). */
CS_HD double cs_light_depth(const struct cs_scene *sc,
			    const struct cs_render_settings *s, cs_v3 p,
			    unsigned mask, struct cs_render_stats *st);
/* The same, and into *tau_over its part through the layers in over (one
 * bit a layer). */
CS_HD double cs_light_depth_over(const struct cs_scene *sc, const struct cs_render_settings *s,
				 cs_v3 p, unsigned mask, unsigned over, double *tau_over,
				 struct cs_render_stats *st);

/* The optical depth of layer l from the point (x, y) at altitude alt_m up
 * to its top along the rays of its volume lc (struct cs_light_cache:
 * toward the sun, or up the vertical column): trilinear, the columns
 * wrapped by the field's periods; below the layer the whole layer along
 * the ray through the point, above it 0. */
CS_HD double cs_cached_depth(const struct cs_cloud_layer *l, const struct cs_light_cache *lc,
			     double x, double y, double alt_m);

/* Optical depth of layer li alone from p along the unit vector dir
 * (light_steps samples over the path through it, spaced as
 * cs_light_depth's). */
double cs_layer_depth(const struct cs_scene *sc, const struct cs_render_settings *s, int li,
		      cs_v3 p, cs_v3 dir, struct cs_render_stats *st);

/* Optical depth of the cloud of layer li that p is in, from p along the
 * unit vector dir up to the first sample without cloud (light_steps
 * samples over the path through the layer, spaced as cs_light_depth's):
 * a heap's depth behind a point, which its light fields read
 * (cs_deck_tilt_source). */
CS_HD double cs_heap_depth(const struct cs_scene *sc, const struct cs_render_settings *s, int li,
			   cs_v3 p, cs_v3 dir, struct cs_render_stats *st);

/* Aerial perspective (haze.c): the radiance the haze scatters toward the
 * eye along d under a clear sky and, of it, the sun's part (which the
 * clouds' shadows take away); the haze optical depth over distance t from
 * altitude h0 with vertical direction component dz. */
CS_HD void cs_haze_light(const struct cs_scene *sc, cs_v3 d, double clear[3], double sun[3]);
CS_HD double cs_haze_depth(const struct cs_scene *sc, double h0, double dz,
			   double t);
/* Fog optical depth over distance t (flat Earth): the part of the path
 * below the fog's top, times its extinction. */
CS_HD double cs_fog_depth(const struct cs_scene *sc, double h0, double dz,
			  double t);

/* The fog's light (haze.c, from sc->fog, bilinear): the scattered light
 * it sends toward the eye at altitude alt_m along a direction of travel
 * with vertical component up_out whose horizontal part makes an angle of
 * cosine cos_phi with the sun beam's (kcd/m^2; the sun's beam scattered
 * once is not in it), and the scattered light coming down on a
 * horizontal plane there (klux). */
CS_HD void cs_fog_source(const struct cs_scene *sc, double alt_m, double up_out, double cos_phi,
			 double out[3]);
/* The same for a light field f at height fraction h in [0, 1] of its
 * layer (of optical depth from the bottom: 1 at the top). */
CS_HD void cs_field_source(const struct cs_fog_field *f, double h, double up_out, double cos_phi,
			   double out[3]);
/* The same in a layer of the deck d whose light fields are d->field[fi],
 * at a point of its column with optical depth tau_above over it and
 * tau_below under it (haze.c). */
CS_HD void cs_deck_field_source(const struct cs_deck *d, int fi, double tau_above,
				double tau_below, double up_out, double cos_phi, double out[3]);
/* The same from the deck's tilted columns (struct cs_deck's tilt): the
 * sun's diffuse light at a point of a tower whose heap has optical depth
 * tau_sun between it and the sun and tau_away behind it, the plane-parallel
 * field of a slab of depth tau_sun + tau_away facing the sun read at the
 * point's level, toward a direction of travel whose cosine with the way
 * to the sun is to_sun (haze.c). */
CS_HD void cs_deck_tilt_source(const struct cs_deck *d, double tau_sun, double tau_away,
			       double to_sun, double out[3]);
CS_HD void cs_fog_down(const struct cs_scene *sc, double alt_m, double out[3]);

/* The sun's beam through the fog from above down to altitude alt_m (flat
 * Earth): 1 above the fog, exp(-beta (top - alt) / sin(elevation)) in it
 * (haze.c). */
CS_HD double cs_fog_sun_transmittance(const struct cs_scene *sc, double alt_m);

/* Radiance leaving the ground at p toward the eye, which looks along d
 * (ground.c): flat ground or, when on_terrain, the heightfield with its
 * normal, colour (drape, palette or land cover), horizon occlusion and
 * self-shadow, or its water (Fresnel sky reflection, sun glint, the dark
 * water body); cloud shadows when the scene has them. */
CS_HD void cs_ground_light(const struct cs_scene *sc,
			   const struct cs_render_settings *s, cs_v3 p, cs_v3 d,
			   int on_terrain, struct cs_render_stats *st,
			   double rgb[3]);

/* The ground along the ray o + t d: the terrain inside its grid, the flat
 * ground sphere outside it; the distance, or INFINITY when the ray meets
 * neither (integrator.c). */
CS_HD double cs_find_ground(const struct cs_scene *sc, cs_v3 o, cs_v3 d,
			    int *on_terrain, struct cs_render_stats *st);

/* How much it rains at (x, y): 1 under the raining layer's cells, 0
 * between them, soft at their edges; read just above the layer's base
 * (integrator.c). */
CS_HD double cs_rain_shaft(const struct cs_scene *sc, double x, double y);

/* The diffuse light in a column of rain or snow of optical depth tau_m
 * (its extinction times its height) over ground of albedo a, lit at its
 * top by diffuse light of irradiance F0 and scattering isotropically with
 * albedo w: the two-stream solution (Eddington's coefficients, Meador &
 * Weaver 1980 table 1), the light sent back and forth between the drops
 * and the ground counted; for each colour's ground albedo a[c] (the
 * drops are grey).  mean: the mean radiance over the sphere at
 * optical depth tau_above under the top, (F_up + F_down) / 2, over F0 /
 * pi (the drops scatter w times it); *down: the irradiance down on the
 * ground over F0 (integrator.c).  Without rain (tau_m 0) (1 + a) / 2 and
 * 1; the column's albedo (F_up / F_down at its top) is 2 mean - 1 there.
 * w and a are taken in [0, 1].
 * Against adding-doubling (tests/reference/rain-column.txt, w 0.9 and 1,
 * tau 0.3 to 4, a 0 to 0.14) down is within 3.3 % and the albedo within
 * 0.023 (the hemispheric mean's coefficients: down 36 % low at tau 4). */
CS_HD void cs_rain_column(double w, double tau_m, double tau_above, const double a[3],
			  double mean[3], double down[3]);

/* The diffuse light on the ground at p under clouds (deck.on; ground.c),
 * the radiance of a cosine-weighted mean, kcd/m^2, which lights the haze
 * over p too (integrator.c): the frame's field where it has one
 * (sc->ground_field: bilinear between its points, fading to their mean
 * beyond them; where it rains or snows its ground plane, whose rays
 * crossed the precipitation, taken linearly in p's height toward its top
 * plane at the precipitation's top), else the one value of the frame
 * (deck.sky_ground; under rain the ground then takes what comes down
 * through the column, cs_rain_column). */
CS_HD void cs_ground_sky(const struct cs_scene *sc, cs_v3 p, double rgb[3]);
/* The same at the top of the rain's or snow's column over p, which lights
 * it (march_rain): the field's top plane, else deck.sky_ground. */
CS_HD void cs_rain_top_sky(const struct cs_scene *sc, cs_v3 p, double rgb[3]);
/* The field's ground plane under p where it has one (rain or snow): 1,
 * else 0 (rgb untouched). */
CS_HD int cs_rain_ground_sky(const struct cs_scene *sc, cs_v3 p, double rgb[3]);
/* The height of altitude alt_m in the rain's or snow's column: 0 on the
 * flat ground (or under it) to 1 at the precipitation's top (or over it;
 * 0 where the column has no height). */
CS_HD double cs_rain_height(const struct cs_scene *sc, double alt_m);

/* The ground's surface at p (ground.c): its unit normal and its albedo
 * (land cover, terrain colour, wetness). */
CS_HD void cs_ground_surface(const struct cs_scene *sc, cs_v3 p, int on_terrain,
			     cs_v3 *normal, double albedo[3]);

/* Radiance leaving open water at p toward the eye looking along d: the sky
 * in the mirror direction times Fresnel's reflectance (Schlick, n 1.333),
 * the sun's glint on the wind's ripples (sc->water_mss), the dark water
 * body; shadowed by the terrain (on_terrain) and the clouds. */
CS_HD void cs_water_light(const struct cs_scene *sc, const struct cs_render_settings *s,
			  cs_v3 p, cs_v3 d, int on_terrain, struct cs_render_stats *st,
			  double rgb[3]);

#endif
