/* device.h - the renderer on a GPU: the same integrator (cs_render_ray and
 * everything it calls, the CS_HD core of core/hd.h) compiled by nvcc into
 * lib/render/cuda/render_cuda.cu, one thread a pixel.
 *
 * A build without CUDA (the default `make`; `make CUDA=1` builds it, see
 * README) links lib/render/cuda/device_none.c instead, whose functions
 * only say why there is no GPU.  The reference integrator runs on it too
 * (cs_cuda_reference). */
#ifndef CS_DEVICE_H
#define CS_DEVICE_H

#include "render/reference.h"
#include "render/render.h"

#include <stddef.h>

/* Where a frame is rendered (cs_cloudrender_opts.device). */
enum cs_device { CS_DEVICE_CPU, CS_DEVICE_CUDA };

/* 1 when a CUDA device can render (the build has CUDA and the runtime
 * finds a device), else 0 with the reason in why (n bytes): "built without
 * CUDA: ..." or "no CUDA device: ...".  A description of the device in
 * why when 1 ("NVIDIA H200, compute capability 9.0"). */
int cs_device_available(char *why, size_t n);

/* A scene uploaded to the device: the noise volume, the terrain's heights,
 * colour, water and palette, the layers and sky tables.  Uploaded once,
 * rendered as often as asked (a benchmark, a series of frames). */
struct cs_cuda_scene;

/* Uploads sc; CS_EIO with the CUDA error when the device refuses. */
int cs_cuda_scene_new(const struct cs_scene *sc, struct cs_cuda_scene **out);
/* The next frame of a series: sc's struct (layers, sky, sun, effects) sent
 * again; its noise, terrain, water and colour only where sc points at other
 * host arrays than before (the caller makes a new scene when an array it
 * keeps changed its contents). */
int cs_cuda_scene_update(struct cs_cuda_scene *d, const struct cs_scene *sc);
/* NULL is ignored. */
void cs_cuda_scene_free(struct cs_cuda_scene *d);

/* Renders the frame on the device into out (host memory, 5 floats a pixel
 * as cs_render_image writes them: R, G, B, alpha, Z) with the statistics;
 * *kernel_ms (may be NULL) gets the kernel's time by CUDA events, ms. */
int cs_cuda_render(struct cs_cuda_scene *d, const struct cs_camera *cam,
		   const struct cs_render_settings *s, float *out,
		   struct cs_render_stats *stats, double *kernel_ms);

/* Renders the frame n times without copying it back and returns the mean
 * time of one, ms, by CUDA events (the warm benchmark: the scene uploaded,
 * no PNG encoding, no copy to the host). */
int cs_cuda_bench(struct cs_cuda_scene *d, const struct cs_camera *cam,
		  const struct cs_render_settings *s, int n, double *frame_ms);

/* The reference integrator's frame on the device: cs_render_reference's
 * paths, pixels and variance (out and var as it writes them, var may be
 * NULL) from the same paths (the same keys, added in the same order), in
 * batches of paths with a progress report after each (progress may
 * cancel: CS_ECANCELED); *kernel_ms (may be NULL) the kernels' time.
 * Its images differ from the CPU's where the device's arithmetic (its
 * single-precision exponentials, fused multiply-adds, CUDA's mathematical
 * functions: render_cuda.cu) turns a path another way; the noise is read
 * by volume.c's weights, not the march's texture. */
int cs_cuda_reference(struct cs_cuda_scene *d, const struct cs_camera *cam,
		      const struct cs_reference_settings *s, cs_progress_fn progress, void *user,
		      float *out, float *var, struct cs_render_stats *stats, double *kernel_ms);

/* The name of the kernel that renders a frame of d with s: the first of
 * render/cuda/kernels.h built for all the frame needs ("plain",
 * "terrain"), else "all", every effect's (or what the environment's
 * CLOUDSCAPE_CUDA_KERNEL=all asks for). */
const char *cs_cuda_kernel_name(const struct cs_cuda_scene *d, const struct cs_render_settings *s);

#endif
