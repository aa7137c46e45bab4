/* device_none.c - the GPU interface (render/device.h) in a build without
 * CUDA: every call says why.  CS_CUDA_WHY comes from the Makefile. */
#include "render/device.h"

#include "core/err.h"

#include <stdio.h>

#ifndef CS_CUDA_WHY
#define CS_CUDA_WHY "built without CUDA"
#endif

int cs_device_available(char *why, size_t n)
{
	if (n > 0)
		snprintf(why, n, "%s", CS_CUDA_WHY);
	return 0;
}

int cs_cuda_scene_new(const struct cs_scene *sc, struct cs_cuda_scene **out)
{
	(void)sc;
	*out = NULL;
	return cs_error(CS_EINVAL, "%s", CS_CUDA_WHY);
}

int cs_cuda_scene_update(struct cs_cuda_scene *d, const struct cs_scene *sc)
{
	(void)d, (void)sc;
	return cs_error(CS_EINVAL, "%s", CS_CUDA_WHY);
}

void cs_cuda_scene_free(struct cs_cuda_scene *d)
{
	(void)d;
}

int cs_cuda_render(struct cs_cuda_scene *d, const struct cs_camera *cam,
		   const struct cs_render_settings *s, float *out,
		   struct cs_render_stats *stats, double *kernel_ms)
{
	(void)d, (void)cam, (void)s, (void)out, (void)stats, (void)kernel_ms;
	return cs_error(CS_EINVAL, "%s", CS_CUDA_WHY);
}

const char *cs_cuda_kernel_name(const struct cs_cuda_scene *d, const struct cs_render_settings *s)
{
	(void)d, (void)s;
	return "none";
}

int cs_cuda_bench(struct cs_cuda_scene *d, const struct cs_camera *cam,
		  const struct cs_render_settings *s, int n, double *frame_ms)
{
	(void)d, (void)cam, (void)s, (void)n, (void)frame_ms;
	return cs_error(CS_EINVAL, "%s", CS_CUDA_WHY);
}

int cs_cuda_reference(struct cs_cuda_scene *d, const struct cs_camera *cam,
		      const struct cs_reference_settings *s, cs_progress_fn progress, void *user,
		      float *out, float *var, struct cs_render_stats *stats, double *kernel_ms)
{
	(void)d, (void)cam, (void)s, (void)progress, (void)user, (void)out, (void)var;
	(void)stats, (void)kernel_ms;
	return cs_error(CS_EINVAL, "%s", CS_CUDA_WHY);
}
