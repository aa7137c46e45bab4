/* render_cuda.cu - the renderer on a CUDA GPU (render/device.h): the same
 * integrator as the CPU's, compiled from the same C sources by nvcc.
 *
 * One translation unit (a unity build) includes the C files whose CS_HD
 * functions a ray calls, inside extern "C" so that what they call outside
 * (cs_error...) is the C library's; the Makefile keeps only this file's
 * interface global in the object (objcopy -G), so its host copies of those
 * functions never meet the C objects' at link time.  The kernel runs one
 * thread a pixel through cs_render_pixel (pixel.h), the function the CPU
 * pool calls.  The scene is copied to device memory once (layers, sky and
 * deck tables by value; the noise volume, the terrain's heights, block
 * maxima, colour, water and palette as arrays) and rendered as often as
 * asked.  Arithmetic is cs_real as in the C build (double) but for the
 * exponential and logarithm family, which the device takes in single
 * precision (below): the images differ from the CPU's by that, by the
 * order of floating-point operations the compilers choose (fused
 * multiply-adds), by CUDA's maths against libm, and by the noise's detail,
 * which the texture unit interpolates (below).  The noise lookup is the
 * other device-only piece: volume.c's, with its index arithmetic made
 * cheap for a GPU, or the texture (below). */
/* Compiled once with every effect (the host's code and the kernel "all"),
 * and once for each kernel of kernels.h with -DCS_CUDA_KERNEL=name
 * (its kernel and launch alone: CS_CUDA_KERNEL_ONLY). */
#define CS_CUDA_CAT_(a, b) a##b
#define CS_CUDA_CAT(a, b) CS_CUDA_CAT_(a, b)
#ifdef CS_CUDA_KERNEL
#define CS_CUDA_KERNEL_ONLY 1
#define CS_FX_BUILT CS_CUDA_CAT(CS_CUDA_FX_, CS_CUDA_KERNEL)
#else
#define CS_CUDA_KERNEL all
#endif

#include <ctype.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <cuda_runtime.h>

extern "C" {
#include "core/err.h"
#include "core/half.h"
#include "render/cuda/kernels.h"
#include "render/device.h"
#include "render/pixel.h"

#include "io/cpt.c"
/* volume.c's samplers under other names: the device's own follow */
#define cs_volume_sample cs_volume_sample_host
#define cs_volume_sample4 cs_volume_sample4_host
#include "noise/volume.c"
#undef cs_volume_sample
#undef cs_volume_sample4

/* The noise volume's samplers (noise/volume.h) as the device runs them:
 * the same lookup as volume.c's (voxel centres at (i + 0.5) / n, every
 * axis wrapped, trilinear in float with the same weights, the same
 * numbers), with the wrap done by a mask on a 64-bit integer (the sizes
 * are powers of two; any other size by %) instead of volume.c's
 * divisions, which a GPU emulates in long instruction sequences.  The
 * host copies are volume.c's.  The floats are read as they are: the
 * volume stored as halves (exact for noisebake's volumes) measured 4 %
 * slower on an H200 (1080p low 60.8 against 63.0 frames/s, medium 30.3
 * against 31.5): the kernel is not bound by the bytes it reads. */
/* The noise as a 3D texture of halves (RGBA16F), wrapped, filtered
 * trilinearly by the texture unit: one fetch a lookup instead of eight
 * loads, for the detail (cs_volume_sample4).  Voxel centres sit at
 * (i + 0.5) / n in normalized coordinates, as in volume.c; the unit's
 * weights are 8-bit fractions (CUDA's texture filtering), coarser than the
 * CPU's float weights.  The detail only erodes the edges (times the
 * genus's erosion, at most 0.35), and the renders stay within 8e-7 relMSE
 * of the CPU's; the base shape through the texture, whose value is the
 * density itself near the threshold, left the cumulonimbus 8.3e-4 off
 * (1080p low and medium 87 and 60 frames/s on an H200 with both, 70.5
 * and 48.6 with the detail alone, 53.1 and 36.2 with neither).  Halves
 * hold noisebake's volumes exactly.  One handle a kernel's module (each
 * compiled unit has its own): each launch sets its scene's (launch());
 * 0: the loads below.  (Halves read by the loads instead, not the texture
 * unit, were 4 % slower, above.) */
__constant__ unsigned long long dev_noise_tex;

struct dev_corners {
	unsigned off[8]; /* voxel index of each corner; bit 0 = +x, 1 = +y, 2 = +z */
	float tx, ty, tz;
};

CS_HD static inline unsigned dev_wrap(double f, int n)
{
	/* f is a whole number below 2^51 in size: |u| < 2^40, n <= 1024 */
	long long i = (long long)f;
	if ((n & (n - 1)) == 0)
		return (unsigned)(i & (n - 1));
	long long m = i % n;
	return (unsigned)(m < 0 ? m + n : m);
}

CS_HD static inline void dev_corners(const struct cs_volume *v, double u, double vv, double w,
				     struct dev_corners *c)
{
	/* beyond 2^40 (never in a scene: the wind offsets are reduced) the
	 * fraction, exact there, instead of volume.c's fmod, whose long
	 * inline expansion six lookups made a third of the density's code */
	u = fabs(u) < 0x1p40 ? u : u - floor(u);
	vv = fabs(vv) < 0x1p40 ? vv : vv - floor(vv);
	w = fabs(w) < 0x1p40 ? w : w - floor(w);
	double gx = u * v->nx - 0.5, gy = vv * v->ny - 0.5, gz = w * v->nz - 0.5;
	double fx = floor(gx), fy = floor(gy), fz = floor(gz);
	c->tx = (float)(gx - fx), c->ty = (float)(gy - fy), c->tz = (float)(gz - fz);
	unsigned x0 = dev_wrap(fx, v->nx), y0 = dev_wrap(fy, v->ny), z0 = dev_wrap(fz, v->nz);
	unsigned x1 = x0 + 1 == (unsigned)v->nx ? 0 : x0 + 1;
	unsigned y1 = y0 + 1 == (unsigned)v->ny ? 0 : y0 + 1;
	unsigned z1 = z0 + 1 == (unsigned)v->nz ? 0 : z0 + 1;
	unsigned xs[2] = {x0, x1}, ys[2] = {y0 * v->nx, y1 * v->nx},
		 zs[2] = {z0 * v->nx * v->ny, z1 * v->nx * v->ny};
	for (int k = 0; k < 8; k++)
		c->off[k] = zs[k >> 2] + ys[(k >> 1) & 1] + xs[k & 1];
}

CS_HD static inline float dev_lerp3(const float d[8], const struct dev_corners *c)
{
	float c00 = d[0] + c->tx * (d[1] - d[0]);
	float c10 = d[2] + c->tx * (d[3] - d[2]);
	float c01 = d[4] + c->tx * (d[5] - d[4]);
	float c11 = d[6] + c->tx * (d[7] - d[6]);
	float c0 = c00 + c->ty * (c10 - c00);
	float c1 = c01 + c->ty * (c11 - c01);
	return c0 + c->tz * (c1 - c0);
}

CS_HD void cs_volume_sample4(const struct cs_volume *v, double u, double vv, double w,
			     float out[4])
{
#ifdef __CUDA_ARCH__
	if (!isfinite(u) || !isfinite(vv) || !isfinite(w)) {
		out[0] = out[1] = out[2] = out[3] = 0.0f;
		return;
	}
	if (dev_noise_tex != 0) {
		float4 q = tex3D<float4>((cudaTextureObject_t)dev_noise_tex, (float)(u - floor(u)),
					 (float)(vv - floor(vv)), (float)(w - floor(w)));
		out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
		return;
	}
	struct dev_corners c;
	dev_corners(v, u, vv, w, &c);
	const float4 *d4 = (const float4 *)v->data;
	float r[8], g[8], b[8], a[8];
	for (int k = 0; k < 8; k++) {
		float4 q = __ldg(d4 + c.off[k]);
		r[k] = q.x, g[k] = q.y, b[k] = q.z, a[k] = q.w;
	}
	out[0] = dev_lerp3(r, &c);
	out[1] = dev_lerp3(g, &c);
	out[2] = dev_lerp3(b, &c);
	out[3] = dev_lerp3(a, &c);
#else
	cs_volume_sample4_host(v, u, vv, w, out);
#endif
}

CS_HD float cs_volume_sample(const struct cs_volume *v, int channel, double u, double vv,
			     double w)
{
#ifdef __CUDA_ARCH__
	if (!isfinite(u) || !isfinite(vv) || !isfinite(w))
		return 0.0f;
	struct dev_corners c;
	dev_corners(v, u, vv, w, &c);
	const float *d = v->data + (channel & 3);
	float q[8];
	for (int k = 0; k < 8; k++)
		q[k] = __ldg(d + (size_t)c.off[k] * 4);
	return dev_lerp3(q, &c);
#else
	return cs_volume_sample_host(v, channel, u, vv, w);
#endif
}

/* The exponential and logarithm family in single precision on the device
 * (the march's transmittances, steps and phase): a GPU's double exp and
 * log are long instruction sequences; the float ones err by about 1e-7
 * relative, far inside the 1e-4 relMSE the renders must agree to (the
 * largest on the hard scenes 1.1e-10).  On an H200, 1080p low and medium
 * 49.9 -> 53.1 and 33.8 -> 36.2 frames/s; the fast intrinsics (__expf,
 * __logf, __powf) gave 4 % more, kept out for their larger error at large
 * arguments.  The host copies keep libm's double functions. */
#ifdef __CUDA_ARCH__
#define CS_DEV_F1(name, fname) \
	CS_HD static inline double cs_dev_##name(double x) { return (double)fname((float)x); }
#else
#define CS_DEV_F1(name, fname) \
	CS_HD static inline double cs_dev_##name(double x) { return ::name(x); }
#endif
CS_DEV_F1(exp, expf)
CS_DEV_F1(expm1, expm1f)
CS_DEV_F1(log, logf)
CS_DEV_F1(log1p, log1pf)
CS_HD static inline double cs_dev_pow(double x, double y)
{
#ifdef __CUDA_ARCH__
	return (double)powf((float)x, (float)y);
#else
	return ::pow(x, y);
#endif
}
#define exp(x) cs_dev_exp(x)
#define expm1(x) cs_dev_expm1(x)
#define log(x) cs_dev_log(x)
#define log1p(x) cs_dev_log1p(x)
#define pow(x, y) cs_dev_pow(x, y)

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
#undef exp
#undef expm1
#undef log
#undef log1p
#undef pow
/* the reference integrator, in the unit of every effect only: its own
 * free paths and Russian roulette in double precision, as on the CPU
 * (a float logarithm of 1 - u would end a free path at 1 - u below
 * 2^-24 as if nothing were there); what it calls of the files above
 * takes their single-precision exponentials */
#ifndef CS_CUDA_KERNEL_ONLY
#include "render/reference.c"
#endif
}

/* The scene as the device reads it: the pointers of sc lead to the
 * members below or to device arrays. */
struct dev_scene {
	struct cs_scene sc;
	struct cs_hfield hf;
	struct cs_volume noise;
	struct cs_cpt cpt;
};

/* The thread block, and the blocks a multiprocessor should hold at once
 * (__launch_bounds__: the registers a thread may use follow from it).
 * The kernel is bound by latency, not by a unit's throughput, and more
 * warps hide more of it: on an H200 at 1920x1080 (scripts/gpu-check's
 * benchmark) 8 blocks of 128 threads (64 registers) run low at 80.7 and
 * medium at 55.4 frames/s, against 75.1/50.6 with 10 (48 registers) and
 * 72.3/48.5 with 12 (40); blocks of 32 x 4 threads 76.1/52.6; 6 blocks
 * (80 registers) and 4 (128) were 3 and 8 % slower than 8 (measured
 * before dev_corners lost its fmod: 72.8/50.1 and 70.1/47.6 against
 * 75.7/51.8).  (Before
 * the functions a ray calls were compiled once, CS_COLD and CS_SHARED:
 * 63/31 with 8 blocks, 54/27 with 6, 48/23 with 4, 44/21 with 1, 65/32
 * and 65/33 with 10 and 12, 51/26 with 16.)  With them inlined again
 * (core/hd.h), 8 blocks still: 8.64/10.95 ms a frame, against 8.79/11.00
 * with 4 blocks, 9.01/11.35 with 5, 8.87/11.12 with 6, and 9.23/11.46
 * for blocks of 32 x 4 with 4. */
#ifndef CS_CUDA_BLOCK_W
#define CS_CUDA_BLOCK_W 16
#endif
#ifndef CS_CUDA_BLOCK_H
#define CS_CUDA_BLOCK_H 8
#endif
#ifndef CS_CUDA_MIN_BLOCKS
#define CS_CUDA_MIN_BLOCKS 8
#endif
enum { NSTATS = 6, BLOCK_W = CS_CUDA_BLOCK_W, BLOCK_H = CS_CUDA_BLOCK_H };

#ifndef CS_CUDA_KERNEL_ONLY
struct cs_cuda_scene {
	struct dev_scene *d;       /* device */
	void *arrays[5];           /* device: noise, heights, block maxima, water, colour */
	const void *src[5];        /* the host arrays they were copied from */
	float *cache[3 * CS_SCENE_MAX_LAYERS]; /* device: the layers' light caches,
						  toward the sun, the columns' and
						  the towers' diffused light */
	size_t cache_n[3 * CS_SCENE_MAX_LAYERS]; /* their sizes, bytes */
	float *field;              /* device: the ground's light (CS_GROUND_SKY_FIELD) */
	size_t field_n;            /* its size, bytes */
	unsigned long long *stats; /* device: NSTATS counters */
	float *frame;              /* device: 5 floats a pixel */
	size_t frame_px;
	cudaEvent_t ev[2];
	int have_ev;
	cudaArray_t noise_arr;     /* the noise as halves, for noise_tex */
	cudaTextureObject_t noise_tex;
	const void *noise_src;     /* the host array it was made from */
	unsigned needs;            /* what the scene needs of a kernel (scene_needs) */
	int no_sun_cache;          /* a layer has no light cache toward the sun */
	int no_column_cache;       /* under a deck, a layer has none up the column */
	int deck_layers;           /* layers under a deck: their columns are read */
	int heap_towers;           /* a layer has a towers' share only where the
				      settings light heaps as towers: the
				      towers' code then (kernel_for) */
};

static int cuda_error(cudaError_t e, const char *what)
{
	return cs_error(CS_EIO, "CUDA: %s: %s", what, cudaGetErrorString(e));
}
#endif

/* A thread's statistics into the NSTATS counters: summed per warp (every
 * thread of the block calls it), then atomically. */
__device__ static void add_stats(const struct cs_render_stats *st, unsigned long long *stats)
{
	unsigned long long v[NSTATS] = {st->pixels, st->density_samples, st->light_samples,
					st->rays_terminated_early, st->layer_crossings,
					st->terrain_cells};
	for (int k = 0; k < NSTATS; k++) {
		for (int off = 16; off > 0; off /= 2)
			v[k] += __shfl_down_sync(0xffffffffu, v[k], off);
		if ((threadIdx.x + threadIdx.y * blockDim.x) % 32 == 0 && v[k] != 0)
			atomicAdd(&stats[k], v[k]);
	}
}

/* One thread a pixel. */
__global__ void __launch_bounds__(BLOCK_W * BLOCK_H, CS_CUDA_MIN_BLOCKS)
render_kernel(const struct dev_scene *ds, struct cs_camera cam, struct cs_render_settings s,
	      float *out, unsigned long long *stats)
{
	int i = blockIdx.x * blockDim.x + threadIdx.x;
	int j = blockIdx.y * blockDim.y + threadIdx.y;
	struct cs_render_stats st;
	memset(&st, 0, sizeof st);
	if (i < cam.width && j < cam.height)
		cs_render_pixel(&ds->sc, &cam, &s, i, j, &st,
				out + ((size_t)j * cam.width + i) * 5);
	if (stats != NULL)
		add_stats(&st, stats);
}

#ifndef CS_CUDA_KERNEL_ONLY
/* The reference integrator: one thread a pixel adds its paths k0 .. k1 - 1
 * to the pixel's accumulator (reference.h), which the first batch begins
 * and the last, end, writes out as the CPU does. */
__global__ void __launch_bounds__(BLOCK_W * BLOCK_H)
reference_kernel(const struct dev_scene *ds, struct cs_camera cam,
		 struct cs_reference_settings s, int k0, int k1, int end,
		 struct cs_reference_pixel *acc, float *out, float *var, unsigned long long *stats)
{
	int i = blockIdx.x * blockDim.x + threadIdx.x;
	int j = blockIdx.y * blockDim.y + threadIdx.y;
	struct cs_render_stats st;
	memset(&st, 0, sizeof st);
	if (i < cam.width && j < cam.height) {
		size_t at = (size_t)j * cam.width + i;
		struct cs_reference_pixel a;
		if (k0 == 0)
			cs_reference_pixel_begin(&a);
		else
			a = acc[at];
		cs_reference_pixel_add(&ds->sc, &cam, &s, i, j, k0, k1, &a, &st);
		if (end)
			cs_reference_pixel_end(&a, out + at * 5, var + at);
		else
			acc[at] = a;
	}
	add_stats(&st, stats);
}
#endif

/* This unit's kernel, for the host's code: its module's texture handle
 * (each unit has its own dev_noise_tex), and n launches for cam's pixels;
 * a cudaError_t. */
extern "C" int CS_CUDA_CAT(cs_cuda_texture_, CS_CUDA_KERNEL)(unsigned long long tex)
{
	return (int)cudaMemcpyToSymbol(dev_noise_tex, &tex, sizeof tex);
}

extern "C" int CS_CUDA_CAT(cs_cuda_launch_, CS_CUDA_KERNEL)(const struct dev_scene *ds,
							     const struct cs_camera *cam,
							     const struct cs_render_settings *s,
							     float *out, unsigned long long *stats,
							     int n)
{
	dim3 block(BLOCK_W, BLOCK_H);
	dim3 grid((cam->width + BLOCK_W - 1) / BLOCK_W, (cam->height + BLOCK_H - 1) / BLOCK_H);
	for (int k = 0; k < n; k++)
		render_kernel<<<grid, block>>>(ds, *cam, *s, out, stats);
	return (int)cudaGetLastError();
}

#ifndef CS_CUDA_KERNEL_ONLY
/* The kernels: kernels.h's, then the one with every effect. */
#define CS_CUDA_DECLARE(name)                                                                  \
	extern "C" int cs_cuda_texture_##name(unsigned long long tex);                         \
	extern "C" int cs_cuda_launch_##name(const struct dev_scene *ds,                        \
					     const struct cs_camera *cam,                        \
					     const struct cs_render_settings *s, float *out,     \
					     unsigned long long *stats, int n);
CS_CUDA_KERNELS(CS_CUDA_DECLARE)
#define CS_CUDA_ENTRY(name) {#name, CS_CUDA_FX_##name, cs_cuda_texture_##name, cs_cuda_launch_##name},
static const struct kernel {
	const char *name;
	unsigned built; /* CS_FX_BUILT */
	int (*texture)(unsigned long long tex);
	int (*launch)(const struct dev_scene *ds, const struct cs_camera *cam,
		      const struct cs_render_settings *s, float *out, unsigned long long *stats,
		      int n);
} kernels[] = {CS_CUDA_KERNELS(CS_CUDA_ENTRY){"all", 0xffffffffu, cs_cuda_texture_all,
							   cs_cuda_launch_all}};
enum { NKERNELS = sizeof kernels / sizeof kernels[0] };

extern "C" int cs_device_available(char *why, size_t n)
{
	int count = 0;
	cudaError_t e = cudaGetDeviceCount(&count);
	if (e != cudaSuccess || count < 1) {
		if (n > 0)
			snprintf(why, n, "no CUDA device: %s",
				 e != cudaSuccess ? cudaGetErrorString(e) : "the runtime found none");
		return 0;
	}
	cudaDeviceProp p;
	e = cudaGetDeviceProperties(&p, 0);
	if (e != cudaSuccess) {
		if (n > 0)
			snprintf(why, n, "no CUDA device: %s", cudaGetErrorString(e));
		return 0;
	}
	if (n > 0)
		snprintf(why, n, "%.100s, compute capability %d.%d, %.0f MiB", p.name, p.major,
			 p.minor, (double)p.totalGlobalMem / (1024.0 * 1024.0));
	return 1;
}

/* Array k of the device scene holds n bytes of the host's src: copied
 * unless it already is (a series keeps its noise and terrain; only what a
 * frame changes travels again). */
static int upload(struct cs_cuda_scene *c, int k, const void *src, size_t n, const char *what)
{
	if (c->arrays[k] != NULL && c->src[k] == src)
		return CS_OK;
	cudaFree(c->arrays[k]);
	c->arrays[k] = NULL;
	c->src[k] = NULL;
	cudaError_t e = cudaMalloc(&c->arrays[k], n);
	if (e != cudaSuccess)
		return cuda_error(e, what);
	e = cudaMemcpy(c->arrays[k], src, n, cudaMemcpyHostToDevice);
	if (e != cudaSuccess)
		return cuda_error(e, what);
	c->src[k] = src;
	return CS_OK;
}

/* The noise volume as a texture of halves (dev_noise_tex), made once for
 * as long as the host's volume stays the same. */
static int noise_texture(struct cs_cuda_scene *c, const struct cs_volume *v)
{
	if (c->noise_arr != NULL && c->noise_src == v->data)
		return CS_OK;
	if (c->noise_tex)
		cudaDestroyTextureObject(c->noise_tex);
	cudaFreeArray(c->noise_arr);
	c->noise_tex = 0, c->noise_arr = NULL, c->noise_src = NULL;
	size_t n = (size_t)v->nx * v->ny * v->nz * 4;
	uint16_t *hv = (uint16_t *)malloc(n * sizeof *hv);
	if (hv == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	for (size_t i = 0; i < n; i++)
		hv[i] = cs_float_to_half(v->data[i]);
	cudaChannelFormatDesc fd = cudaCreateChannelDescHalf4();
	cudaExtent ext = make_cudaExtent((size_t)v->nx, (size_t)v->ny, (size_t)v->nz);
	cudaError_t e = cudaMalloc3DArray(&c->noise_arr, &fd, ext);
	if (e == cudaSuccess) {
		cudaMemcpy3DParms cp;
		memset(&cp, 0, sizeof cp);
		cp.srcPtr = make_cudaPitchedPtr(hv, (size_t)v->nx * 4 * sizeof *hv, (size_t)v->nx,
						(size_t)v->ny);
		cp.dstArray = c->noise_arr;
		cp.extent = ext;
		cp.kind = cudaMemcpyHostToDevice;
		e = cudaMemcpy3D(&cp);
	}
	free(hv);
	if (e != cudaSuccess)
		return cuda_error(e, "uploading the noise texture");
	cudaResourceDesc rd;
	memset(&rd, 0, sizeof rd);
	rd.resType = cudaResourceTypeArray;
	rd.res.array.array = c->noise_arr;
	cudaTextureDesc td;
	memset(&td, 0, sizeof td);
	td.addressMode[0] = td.addressMode[1] = td.addressMode[2] = cudaAddressModeWrap;
	td.filterMode = cudaFilterModeLinear;
	td.readMode = cudaReadModeElementType;
	td.normalizedCoords = 1;
	e = cudaCreateTextureObject(&c->noise_tex, &rd, &td, NULL);
	if (e != cudaSuccess)
		return cuda_error(e, "the noise texture");
	c->noise_src = v->data;
	return CS_OK;
}

/* What of CS_FX_BUILT a frame of sc needs of a kernel, its settings aside
 * (kernel_for), into c: its effects and what the per-sample code reads
 * from its state (fog, terrain, water, towers), and the light caches it
 * lacks. */
static void scene_needs(struct cs_cuda_scene *c, const struct cs_scene *sc)
{
	unsigned need = sc->effects;
	need |= sc->fog_beta_per_m > 0.0 ? (unsigned)CS_FX_FOG : 0u;
	need |= sc->terrain ? (unsigned)CS_FX_TERRAIN : 0u;
	need |= sc->terrain && sc->terrain_water ? (unsigned)CS_FX_WATER : 0u;
	c->no_sun_cache = c->no_column_cache = c->heap_towers = 0;
	c->deck_layers = sc->deck.on && sc->nlayers > 0;
	/* the towers' share (cs_tower_share) whatever the settings, and the
	 * heaps' that only some settings take (kernel_for) */
	struct cs_render_settings off, on;
	memset(&off, 0, sizeof off);
	on = off;
	on.heap_towers = 1;
	for (int i = 0; i < sc->nlayers; i++) {
		int always = cs_tower_share(sc, &off, i) > 0.0;
		need |= always ? (unsigned)CS_BUILT_TOWERS : 0u;
		c->heap_towers |= !always && cs_tower_share(sc, &on, i) > 0.0;
		c->no_sun_cache |= sc->light_cache[i].depth == NULL;
		/* the column is read under a deck only */
		c->no_column_cache |= sc->deck.on && sc->column_cache[i].depth == NULL;
	}
	c->needs = need;
}

/* The first kernel built for all a frame of scene c with settings s
 * needs; the last, every effect's, builds all. */
static const struct kernel *kernel_for(const struct cs_cuda_scene *c,
				       const struct cs_render_settings *s)
{
	/* CLOUDSCAPE_CUDA_KERNEL=all: every effect's, to compare
	 * (cloudrender(1), ENVIRONMENT) */
	const char *force = getenv("CLOUDSCAPE_CUDA_KERNEL");
	if (force != NULL && strcmp(force, "all") == 0)
		return &kernels[NKERNELS - 1];
	unsigned need = c->needs;
	need |= s->source_every == 2 ? CS_BUILT_SOURCE_EVERY2 : 0u;
	need |= c->heap_towers && s->heap_towers ? (unsigned)CS_BUILT_TOWERS : 0u;
	/* the light marched: toward the key light (every such march is
	 * under CS_FX_IS(sc, CS_FX_KEY)) and up the column (under a deck,
	 * with the diffuse light), where the settings or a missing cache
	 * ask for it (the ground's shadows are marched in every kernel:
	 * cs_render_sun_transmittance never reads the cache) */
	int cached = CS_LIGHT_CACHED(s->light_march);
	if ((c->needs & CS_FX_KEY) && (!cached || c->no_sun_cache))
		need |= CS_BUILT_LIGHT_MARCH;
	if (s->ambient && c->deck_layers && (!cached || c->no_column_cache))
		need |= CS_BUILT_LIGHT_MARCH;
	for (int k = 0; k < NKERNELS - 1; k++)
		if ((need & ~kernels[k].built) == 0u)
			return &kernels[k];
	return &kernels[NKERNELS - 1];
}

/* Copies bytes of host floats into *dev, device memory kept from frame to
 * frame while its size (*dev_n) stays: the new memory first, so that
 * where it fails, the device's scene of the frame before keeps valid
 * memory. */
static int reupload(float **dev, size_t *dev_n, const float *host, size_t bytes, const char *what)
{
	cudaError_t e;
	if (*dev == NULL || *dev_n != bytes) {
		float *mem = NULL;
		if ((e = cudaMalloc((void **)&mem, bytes)) != cudaSuccess)
			return cs_error(CS_EIO, "CUDA: device memory for %s: %s", what,
					cudaGetErrorString(e));
		cudaFree(*dev);
		*dev = mem;
		*dev_n = bytes;
	}
	if ((e = cudaMemcpy(*dev, host, bytes, cudaMemcpyHostToDevice)) != cudaSuccess)
		return cs_error(CS_EIO, "CUDA: uploading %s: %s", what, cudaGetErrorString(e));
	return CS_OK;
}

/* The scene's struct on the device, pointing at the device arrays (each
 * uploaded once for as long as the host's array stays the same). */
static int scene_struct(struct cs_cuda_scene *c, const struct cs_scene *sc)
{
	scene_needs(c, sc);
	cudaError_t e;
	struct dev_scene *h = (struct dev_scene *)calloc(1, sizeof *h);
	if (h == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	h->sc = *sc;
	int rc = CS_OK;
	if (sc->noise) {
		const struct cs_volume *v = sc->noise;
		h->noise = *v;
		rc = upload(c, 0, v->data, (size_t)v->nx * v->ny * v->nz * 4 * sizeof(float),
			    "uploading the noise volume");
		h->noise.data = (float *)c->arrays[0];
		h->sc.noise = &c->d->noise;
		if (rc == CS_OK)
			rc = noise_texture(c, v);
	}
	if (rc == CS_OK && sc->terrain) {
		const struct cs_hfield *f = sc->terrain;
		h->hf = *f;
		rc = upload(c, 1, f->z, (size_t)f->w * f->h * sizeof(float), "uploading the terrain");
		if (rc == CS_OK)
			rc = upload(c, 2, f->block_max, (size_t)f->bw * f->bh * sizeof(float),
				    "uploading the terrain's block maxima");
		h->hf.z = (const float *)c->arrays[1];
		h->hf.block_max = (float *)c->arrays[2];
		h->sc.terrain = &c->d->hf;
		if (rc == CS_OK && sc->terrain_water) {
			rc = upload(c, 3, sc->terrain_water, (size_t)f->w * f->h * sizeof(float),
				    "uploading the terrain's water");
			h->sc.terrain_water = (const float *)c->arrays[3];
		}
	} else {
		h->sc.terrain = NULL;
		h->sc.terrain_water = NULL;
	}
	if (rc == CS_OK && sc->terrain_color) {
		rc = upload(c, 4, sc->terrain_color,
			    (size_t)sc->terrain_color_w * sc->terrain_color_h * 3,
			    "uploading the terrain's colour");
		h->sc.terrain_color = (const uint8_t *)c->arrays[4];
	}
	if (sc->terrain_cpt) {
		h->cpt = *sc->terrain_cpt;
		h->sc.terrain_cpt = &c->d->cpt;
	}
	/* the light caches (CS_LIGHT_CACHE), built on the host for this
	 * frame: copied every frame, into the same device memory while their
	 * size stays */
	for (int n = 0; rc == CS_OK && n < 3 * CS_SCENE_MAX_LAYERS; n++) {
		/* h's copy of the volume: the host's array, then the device's */
		int kind = n / CS_SCENE_MAX_LAYERS, li = n % CS_SCENE_MAX_LAYERS;
		struct cs_light_cache *lc = kind == 0   ? &h->sc.light_cache[li]
					    : kind == 1 ? &h->sc.column_cache[li]
							: &h->sc.tower_light[li];
		if (lc->depth == NULL)
			continue;
		size_t bytes = (size_t)lc->nu * lc->nv * (lc->nh + 1) * sizeof(float);
		rc = reupload(&c->cache[n], &c->cache_n[n], lc->depth, bytes, "the light cache");
		lc->depth = c->cache[n];
	}
	/* and the ground's light field, built with them */
	struct cs_ground_field *gf = &h->sc.ground_field;
	if (rc == CS_OK && gf->rgb != NULL) {
		rc = reupload(&c->field, &c->field_n, gf->rgb,
			      (size_t)(gf->planes > 1 ? gf->planes : 1) * gf->n * gf->n * 3 *
				      sizeof(float),
			      "the ground's light");
		gf->rgb = c->field;
	}
	if (rc == CS_OK && (e = cudaMemcpy(c->d, h, sizeof *h, cudaMemcpyHostToDevice)) != cudaSuccess)
		rc = cuda_error(e, "uploading the scene");
	free(h);
	return rc;
}

static int scene_upload(struct cs_cuda_scene *c, const struct cs_scene *sc)
{
	char why[256];
	if (!cs_device_available(why, sizeof why))
		return cs_error(CS_EIO, "%s", why);
	cudaError_t e = cudaMalloc((void **)&c->d, sizeof *c->d);
	if (e != cudaSuccess)
		return cuda_error(e, "device memory for the scene");
	int rc = scene_struct(c, sc);
	if (rc == CS_OK && (e = cudaMalloc((void **)&c->stats, NSTATS * sizeof *c->stats)) != cudaSuccess)
		rc = cuda_error(e, "device memory for the statistics");
	if (rc == CS_OK && (e = cudaEventCreate(&c->ev[0])) == cudaSuccess) {
		if ((e = cudaEventCreate(&c->ev[1])) == cudaSuccess)
			c->have_ev = 1;
		else
			cudaEventDestroy(c->ev[0]);
	}
	if (rc == CS_OK && e != cudaSuccess)
		rc = cuda_error(e, "creating events");
	return rc;
}

extern "C" int cs_cuda_scene_new(const struct cs_scene *sc, struct cs_cuda_scene **out)
{
	struct cs_cuda_scene *c = (struct cs_cuda_scene *)calloc(1, sizeof *c);
	*out = NULL;
	if (c == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	int rc = scene_upload(c, sc);
	if (rc != CS_OK) {
		cs_cuda_scene_free(c);
		return rc;
	}
	*out = c;
	return CS_OK;
}

extern "C" int cs_cuda_scene_update(struct cs_cuda_scene *c, const struct cs_scene *sc)
{
	return scene_struct(c, sc);
}

extern "C" void cs_cuda_scene_free(struct cs_cuda_scene *c)
{
	if (c == NULL)
		return;
	for (int k = 0; k < 5; k++)
		cudaFree(c->arrays[k]);
	for (int n = 0; n < 3 * CS_SCENE_MAX_LAYERS; n++)
		cudaFree(c->cache[n]);
	cudaFree(c->field);
	if (c->noise_tex)
		cudaDestroyTextureObject(c->noise_tex);
	cudaFreeArray(c->noise_arr);
	cudaFree(c->d);
	cudaFree(c->stats);
	cudaFree(c->frame);
	if (c->have_ev) {
		cudaEventDestroy(c->ev[0]);
		cudaEventDestroy(c->ev[1]);
	}
	free(c);
}

/* The device frame at least as large as cam's. */
static int frame_alloc(struct cs_cuda_scene *c, const struct cs_camera *cam)
{
	size_t n = (size_t)cam->width * cam->height;
	if (n <= c->frame_px)
		return CS_OK;
	cudaFree(c->frame);
	c->frame = NULL;
	c->frame_px = 0;
	cudaError_t e = cudaMalloc((void **)&c->frame, n * 5 * sizeof(float));
	if (e != cudaSuccess)
		return cuda_error(e, "device memory for the frame");
	c->frame_px = n;
	return CS_OK;
}

/* Launches the kernel n times between the two events; the mean ms. */
static int launch(struct cs_cuda_scene *c, const struct cs_camera *cam,
		  const struct cs_render_settings *s, int n, unsigned long long *stats,
		  double *ms)
{
	int rc = cs_render_settings_check(s);
	if (rc == CS_OK)
		rc = cs_render_settings_gpu_check(s);
	if (rc != CS_OK)
		return rc;
	if ((rc = frame_alloc(c, cam)) != CS_OK)
		return rc;
	/* the kernel's module's one texture handle is this scene's, set by
	 * every launch of the march (here, and cs_cuda_reference sets it to
	 * 0; both wait for their kernels to end): another scene may have
	 * set it, or destroyed its texture, since; 0 without a noise
	 * texture: the loads */
	const struct kernel *k = kernel_for(c, s);
	unsigned long long tex = (unsigned long long)c->noise_tex;
	cudaError_t e = (cudaError_t)k->texture(tex);
	if (e != cudaSuccess)
		return cuda_error(e, "the noise texture");
	cudaEventRecord(c->ev[0]);
	e = (cudaError_t)k->launch(c->d, cam, s, c->frame, stats, n);
	if (e != cudaSuccess)
		return cuda_error(e, "launching the render kernel");
	cudaEventRecord(c->ev[1]);
	if ((e = cudaEventSynchronize(c->ev[1])) != cudaSuccess)
		return cuda_error(e, "rendering");
	float t = 0.0f;
	if ((e = cudaEventElapsedTime(&t, c->ev[0], c->ev[1])) != cudaSuccess)
		return cuda_error(e, "timing the kernel");
	*ms = (double)t / n;
	return CS_OK;
}

/* The NSTATS counters (add_stats) copied back into stats' fields. */
static int stats_back(const struct cs_cuda_scene *c, struct cs_render_stats *stats)
{
	unsigned long long v[NSTATS];
	cudaError_t e = cudaMemcpy(v, c->stats, sizeof v, cudaMemcpyDeviceToHost);
	if (e != cudaSuccess)
		return cuda_error(e, "copying the statistics back");
	stats->pixels = v[0];
	stats->density_samples = v[1];
	stats->light_samples = v[2];
	stats->rays_terminated_early = v[3];
	stats->layer_crossings = v[4];
	stats->terrain_cells = v[5];
	return CS_OK;
}

extern "C" int cs_cuda_render(struct cs_cuda_scene *c, const struct cs_camera *cam,
			      const struct cs_render_settings *s, float *out,
			      struct cs_render_stats *stats, double *kernel_ms)
{
	cudaError_t e = cudaMemset(c->stats, 0, NSTATS * sizeof *c->stats);
	if (e != cudaSuccess)
		return cuda_error(e, "clearing the statistics");
	double ms = 0.0;
	int rc = launch(c, cam, s, 1, c->stats, &ms);
	if (rc != CS_OK)
		return rc;
	if (kernel_ms)
		*kernel_ms = ms;
	size_t n = (size_t)cam->width * cam->height * 5 * sizeof(float);
	if ((e = cudaMemcpy(out, c->frame, n, cudaMemcpyDeviceToHost)) != cudaSuccess)
		return cuda_error(e, "copying the frame back");
	return stats_back(c, stats);
}

/* The paths a launch of reference_kernel adds to each pixel: about 2^20
 * paths a launch (a GPU full of threads, a progress report every few),
 * at most all of them; CLOUDSCAPE_CUDA_REF_BATCH=n asks for n (the image
 * is the same: scripts/gpu-check compares 1 with the default). */
static int reference_batch(const struct cs_camera *cam, int spp)
{
	const char *env = getenv("CLOUDSCAPE_CUDA_REF_BATCH");
	size_t px = (size_t)cam->width * cam->height, b;
	if (env != NULL && atoi(env) > 0)
		b = (size_t)atoi(env);
	else
		b = ((size_t)1 << 20) / (px > 0 ? px : 1) + 1;
	return b < (size_t)spp ? (int)b : spp;
}

extern "C" int cs_cuda_reference(struct cs_cuda_scene *c, const struct cs_camera *cam,
				 const struct cs_reference_settings *s, cs_progress_fn progress,
				 void *user, float *out, float *var, struct cs_render_stats *stats,
				 double *kernel_ms)
{
	int rc = cs_reference_check(s);
	if (rc != CS_OK || (rc = frame_alloc(c, cam)) != CS_OK)
		return rc;
	/* the noise by the loads, volume.c's weights (the march's texture
	 * filters the detail with 8-bit weights): the module's handle 0 */
	cudaError_t e = (cudaError_t)cs_cuda_texture_all(0);
	if (e != cudaSuccess)
		return cuda_error(e, "the noise texture");
	size_t n = (size_t)cam->width * cam->height;
	struct cs_reference_pixel *acc = NULL;
	float *dvar = NULL;
	if ((e = cudaMalloc((void **)&acc, n * sizeof *acc)) != cudaSuccess ||
	    (e = cudaMalloc((void **)&dvar, n * sizeof *dvar)) != cudaSuccess)
		rc = cuda_error(e, "device memory for the reference's paths");
	else if ((e = cudaMemset(c->stats, 0, NSTATS * sizeof *c->stats)) != cudaSuccess)
		rc = cuda_error(e, "clearing the statistics");
	dim3 block(BLOCK_W, BLOCK_H);
	dim3 grid((cam->width + BLOCK_W - 1) / BLOCK_W, (cam->height + BLOCK_H - 1) / BLOCK_H);
	int batch = reference_batch(cam, s->spp);
	float ms = 0.0f;
	for (int k0 = 0; rc == CS_OK && k0 < s->spp; k0 += batch) {
		int k1 = k0 + batch < s->spp ? k0 + batch : s->spp;
		(void)cudaGetLastError(); /* an earlier call's error is not this launch's */
		cudaEventRecord(c->ev[0]);
		reference_kernel<<<grid, block>>>(c->d, *cam, *s, k0, k1, k1 == s->spp, acc,
						  c->frame, dvar, c->stats);
		cudaEventRecord(c->ev[1]);
		float t = 0.0f;
		if ((e = cudaGetLastError()) != cudaSuccess)
			rc = cuda_error(e, "launching the reference kernel");
		else if ((e = cudaEventSynchronize(c->ev[1])) != cudaSuccess)
			rc = cuda_error(e, "rendering the reference");
		else if ((e = cudaEventElapsedTime(&t, c->ev[0], c->ev[1])) != cudaSuccess)
			rc = cuda_error(e, "timing the kernel");
		ms += t;
		if (rc == CS_OK && progress && progress(user, (double)k1 / s->spp) != 0)
			rc = cs_error(CS_ECANCELED, "rendering cancelled");
	}
	if (rc == CS_OK && (e = cudaMemcpy(out, c->frame, n * 5 * sizeof(float),
					   cudaMemcpyDeviceToHost)) != cudaSuccess)
		rc = cuda_error(e, "copying the frame back");
	if (rc == CS_OK && var != NULL &&
	    (e = cudaMemcpy(var, dvar, n * sizeof *var, cudaMemcpyDeviceToHost)) != cudaSuccess)
		rc = cuda_error(e, "copying the variance back");
	if (rc == CS_OK) {
		memset(stats, 0, sizeof *stats);
		rc = stats_back(c, stats);
	}
	if (rc == CS_OK && kernel_ms)
		*kernel_ms = ms;
	cudaFree(acc);
	cudaFree(dvar);
	return rc;
}

extern "C" const char *cs_cuda_kernel_name(const struct cs_cuda_scene *c,
					   const struct cs_render_settings *s)
{
	return kernel_for(c, s)->name;
}

extern "C" int cs_cuda_bench(struct cs_cuda_scene *c, const struct cs_camera *cam,
			     const struct cs_render_settings *s, int n, double *frame_ms)
{
	if (n < 1)
		return cs_error(CS_EINVAL, "benchmark of %d frames: at least 1", n);
	double ms = 0.0;
	int rc = launch(c, cam, s, 1, NULL, &ms); /* warm-up */
	if (rc == CS_OK)
		rc = launch(c, cam, s, n, NULL, frame_ms);
	return rc;
}
#endif /* CS_CUDA_KERNEL_ONLY */
