/* pixel.h - internal to lib/render: one pixel of a frame, as the CPU pool
 * (frame.c) and the GPU kernel (cuda/render_cuda.cu) both render it: one
 * ray with its jitter from the pixel's hash, 5 floats out (R, G, B, alpha,
 * Z).  CS_HD, so one source serves both. */
#ifndef CS_PIXEL_H
#define CS_PIXEL_H

#include "core/hash.h"
#include "render/render.h"

CS_HD static inline void cs_render_pixel(const struct cs_scene *sc, const struct cs_camera *cam,
					 const struct cs_render_settings *s, int i, int j,
					 struct cs_render_stats *st, float px[5])
{
	double u = 0.5;
	if (s->jitter > 0.0) {
		uint32_t h = cs_hash3i(i, j, 0x6a697474, s->seed);
		u = 0.5 + s->jitter * (cs_hash_unit(h) - 0.5);
	}
	struct cs_ray_result r = {{0.0, 0.0, 0.0}, 1.0, CS_SKY_DEPTH_M};
	cs_v3 d;
	if (cs_camera_ray(cam, i, j, &d))
		cs_render_ray(sc, s, cam->pos, d, u, st, &r);
	px[0] = (float)r.rgb[0];
	px[1] = (float)r.rgb[1];
	px[2] = (float)r.rgb[2];
	px[3] = (float)(1.0 - r.transmittance);
	px[4] = (float)r.depth_m;
	st->pixels++;
}

#endif
