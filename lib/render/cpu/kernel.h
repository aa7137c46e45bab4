/* kernel.h - internal to lib/render: the frame's per-pixel loop as frame.c
 * calls it, compiled twice from cpu/kernel.c (see there). */
#ifndef CS_KERNEL_H
#define CS_KERNEL_H

#include "render/render.h"

/* Renders rows r0..r1-1 of cam's image into out (5 floats a pixel, rows
 * of cam->width), adding to *st: cs_render_pixel for each pixel. */
typedef void cs_kernel_rows_fn(const struct cs_scene *sc, const struct cs_camera *cam,
			       const struct cs_render_settings *s, int r0, int r1,
			       struct cs_render_stats *st, float *out);

/* out[i] = cs_cloud_extinction(l, noise, xyz[3i], xyz[3i+1], xyz[3i+2])
 * for i < n, as the kernel's own copy computes it (make bench's density
 * figure is of the code that renders). */
typedef void cs_kernel_extinction_fn(const struct cs_cloud_layer *l,
				     const struct cs_volume *noise, int n, const double *xyz,
				     double *out);

/* Baseline x86-64 (any 64-bit CPU), AVX2, and x86-64-v4 (AVX-512): the
 * same bits. */
cs_kernel_rows_fn cs_kernel_rows_base, cs_kernel_rows_avx2, cs_kernel_rows_avx512;
cs_kernel_extinction_fn cs_kernel_extinction_base, cs_kernel_extinction_avx2,
	cs_kernel_extinction_avx512;

#endif
