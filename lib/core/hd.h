/* hd.h - what the per-sample code needs to compile for a CPU and a GPU from
 * one source, the way pbrt-v4 does it with PBRT_CPU_GPU.
 *
 * The hot path (noise sampling, cloud density, phase functions, the light
 * march and the integrator's step) is written as CS_HD functions over plain
 * structs: no libc I/O, no allocation, no globals, no callbacks.  Tables it
 * reads are CS_CONST, or CS_TABLE where threads read them at indices of
 * their own (constant memory serves a warp one address at a time: a
 * lookup table there is read in as many turns as the warp has indices).
 * In C the annotations are empty; a CUDA build (nvcc defines __CUDACC__)
 * makes them host+device functions, constant memory and device memory.  cs_real is the scalar of the hot path: double today, so CPU
 * renders stay bit for bit what they were; a GPU build may choose float,
 * which is why the code avoids the float traps (altitudes computed without
 * cancellation, wind offsets reduced modulo the noise period). */
#ifndef CS_HD_H
#define CS_HD_H

#if defined(__CUDACC__)
#define CS_HD __host__ __device__
#define CS_CONST __constant__
#define CS_TABLE __device__
#else
#define CS_HD
#define CS_CONST
#define CS_TABLE
#endif

/* CS_COLD marks a function a ray calls once or a few times (the sky, the
 * ground, the crossings of the layers), CS_SHARED one a cloudy sample
 * calls (the density, the light march and its shells, the diffuse light).
 * Both are empty, in C and on a GPU: nvcc inlines them into the kernel.
 * -DCS_CUDA_NOINLINE_COLD or -DCS_CUDA_NOINLINE_SHARED compile each
 * once on a GPU and call it instead, to measure the difference.  Once
 * (inlined, the kernel was 960 KB of code and its warps stalled on
 * instruction fetch 61 % of the time) called was faster; since the noise
 * lookup lost its fmod and the presets took the light cache, inlined is:
 * on an H200 at 1920x1080, 8.64 against 9.63 ms a frame at low in one
 * session, 10.95 at medium against 11.92 in another (whose low took
 * 9.49); the shared functions alone inlined 9.00 and 11.43 there
 * (cloudrender(1), GPU). */
#if defined(__CUDACC__) && defined(CS_CUDA_NOINLINE_COLD)
#define CS_COLD __noinline__
#else
#define CS_COLD
#endif
#if defined(__CUDACC__) && defined(CS_CUDA_NOINLINE_SHARED)
#define CS_SHARED __noinline__
#else
#define CS_SHARED
#endif

#ifndef CS_REAL_FLOAT
typedef double cs_real;
#else
typedef float cs_real;
#endif

#endif
