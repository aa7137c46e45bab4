/* reference.h - the reference integrator (reference.c): an unbiased Monte
 * Carlo volumetric path tracer over the same scene as cs_render_ray, with
 * full multiple scattering, the sun by next-event estimation, the sky as
 * the environment and the ground's bounce.  It is what the fast
 * integrator's error is measured against (scripts/accuracy-study). */
#ifndef CS_REFERENCE_H
#define CS_REFERENCE_H

#include "render/render.h"

#include <stdint.h>

struct cs_reference_settings {
	int spp;          /* paths per pixel */
	uint32_t seed;    /* the same seed gives the same image */
	int max_bounces;  /* 0: paths end by Russian roulette only; n: after
			     n scattering or ground events (1: single
			     scattering, for tests) */
};

/* Validates settings; 0 or CS_EINVAL naming the field. */
int cs_reference_check(const struct cs_reference_settings *s);

/* One path from o along unit d, its random numbers drawn from key: the
 * radiance it carries to the eye (kcd/m^2 per channel), whether its first
 * collision was with a cloud, and the distance of its first collision or
 * of the ground (CS_SKY_DEPTH_M when it left the scene). */
CS_HD void cs_reference_path(const struct cs_scene *sc, const struct cs_reference_settings *s,
			     cs_v3 o, cs_v3 d, uint64_t key, struct cs_render_stats *st,
			     double L[3], int *hit_cloud, double *depth_m);

/* The ground irradiance at p (a horizontal plane) from the reference's
 * light transport: the beam's transmittance by ratio tracking and the
 * diffuse light from paths cosine-distributed over the sky, paths of each,
 * in W/m^2 by the same efficacies as cs_irradiance_at; and its mean over
 * cs_irradiance_area's n x n points. */
void cs_reference_irradiance_at(const struct cs_scene *sc, const struct cs_reference_settings *s,
				cs_v3 p, int paths, struct cs_irradiance *out,
				struct cs_render_stats *st);
void cs_reference_irradiance_area(const struct cs_scene *sc, const struct cs_reference_settings *s,
				  double size_m, int n, int paths, struct cs_irradiance *out,
				  struct cs_render_stats *st);

/* One pixel's paths as they accumulate (cs_render_reference's, and the
 * GPU's, lib/render/cuda, which adds them in batches): begin, add paths
 * k0 .. k1 - 1 of pixel (i, j) (a pixel's paths in order, in one call or
 * in several), then end writes the pixel as cs_render_reference does. */
struct cs_reference_pixel {
	double sum[3];       /* the paths' radiance, kcd/m^2 */
	double mean, m2;     /* Welford's running mean and sum of squares of the luminance */
	double depth_sum;    /* of the paths whose first collision was a cloud's, m */
	double ground_depth; /* the nearest first collision of the others, m */
	int n, hits, ndepth; /* paths; of them, those that met a cloud first */
	int ok;              /* the pixel has a ray (cs_camera_ray) */
};
CS_HD void cs_reference_pixel_begin(struct cs_reference_pixel *a);
CS_HD void cs_reference_pixel_add(const struct cs_scene *sc, const struct cs_camera *cam,
				  const struct cs_reference_settings *s, int i, int j, int k0,
				  int k1, struct cs_reference_pixel *a, struct cs_render_stats *st);
CS_HD void cs_reference_pixel_end(const struct cs_reference_pixel *a, float px[5], float *var);

/* Renders spp paths through each pixel's centre into out (5 floats per
 * pixel as cs_render_image: R, G, B, alpha = the share of paths that met a
 * cloud first, Z) and, if var is not NULL, the variance of each pixel's
 * mean luminance into var (one float per pixel).  Deterministic for a
 * seed, whatever nthreads (<= 0: all processors).  progress may cancel. */
int cs_render_reference(const struct cs_scene *sc, const struct cs_camera *cam,
			const struct cs_reference_settings *s, int nthreads,
			cs_progress_fn progress, void *user, float *out, float *var,
			struct cs_render_stats *stats);

#endif
