/* kernel.c - the CPU's per-pixel work as one translation unit (a unity
 * build, as the GPU's cuda/render_cuda.cu is): it includes the C files
 * whose CS_HD functions a ray calls, so that the compiler sees the whole
 * path of a sample at once and inlines across what are separate files
 * elsewhere (the lookup, the density, the light march, the step).
 *
 * The Makefile compiles it three times, as CS_KERNEL = cs_kernel_rows_base
 * for any x86-64, as cs_kernel_rows_avx2 with -mavx2 and as
 * cs_kernel_rows_avx512 with -march=x86-64-v4 (the density eight points
 * at a time, cloud.c's extinction8, with AVX-512's 32 vector registers:
 * on a 2-core AMD EPYC 215 against 145 million density evaluations a
 * second, renders 12 % faster than the AVX2 build),
 * all -O3 and -ffp-contract=off: no fused multiply-adds and no
 * reassociation, so they give the same bits as each other and as the
 * library's own objects (test_cloud and tests/tools/device.sh compare
 * them).  Only CS_KERNEL stays global in each object (objcopy -G): the
 * copies of the included functions never meet the library's at link
 * time.  frame.c chooses at run time.  The
 * second function, CS_KERNEL_EXTINCTION, is the density alone, for the
 * benchmark of density evaluations (cs_render_extinction). */
#include "render/cpu/kernel.h"
#include "render/pixel.h"

#include "io/cpt.c"
#include "noise/volume.c"
#include "render/camera.c"
#include "render/cloud.c"
#include "render/deck.c"
#include "render/ground.c"
#include "render/haze.c"
#include "render/integrator.c"
#include "render/light_march.c"
#include "render/night.c"
#include "render/sky.c"
#include "render/water.c"
#include "terrain/heightfield.c"

#if !defined(CS_KERNEL) || !defined(CS_KERNEL_EXTINCTION)
#error "CS_KERNEL and CS_KERNEL_EXTINCTION name the functions this build of kernel.c defines"
#endif

void CS_KERNEL(const struct cs_scene *sc, const struct cs_camera *cam,
	       const struct cs_render_settings *s, int r0, int r1, struct cs_render_stats *st,
	       float *out)
{
	for (int j = r0; j < r1; j++)
		for (int i = 0; i < cam->width; i++)
			cs_render_pixel(sc, cam, s, i, j, st, out + ((size_t)j * cam->width + i) * 5);
}

enum { CHUNK = 64 };

void CS_KERNEL_EXTINCTION(const struct cs_cloud_layer *l, const struct cs_volume *noise, int n,
			  const double *xyz, double *out)
{
	for (int i0 = 0; i0 < n; i0 += CHUNK) {
		int m = n - i0 < CHUNK ? n - i0 : CHUNK;
		double x[CHUNK], y[CHUNK], z[CHUNK];
		for (int i = 0; i < m; i++)
			x[i] = xyz[3 * (i0 + i)], y[i] = xyz[3 * (i0 + i) + 1], z[i] = xyz[3 * (i0 + i) + 2];
		cs_cloud_extinction_n(l, noise, m, x, y, z, out + i0);
	}
}
