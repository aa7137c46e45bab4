/* texfetch.cu - the GPU's ceiling for the noise lookups cloudrender makes
 * through the texture unit (render_cuda.cu's cs_volume_sample4): one thread
 * a pixel of a 1920x1080 frame, each taking STEPS coherent steps of half a
 * voxel through a wrapped 128^3 RGBA16F texture with trilinear filtering
 * and normalized coordinates, as the renderer's texture is.  Prints the
 * fetches a second (the best of REPEATS launches, timed by CUDA events),
 * the ceiling cloudrender(1) GPU compares the kernel's own fetch rate with.
 *
 * make check-gpu builds it (build-cuda/bench/texfetch) and gpu-check runs
 * it; by hand: nvcc -O3 -arch=sm_90 bench/texfetch.cu -o texfetch.  Never
 * by make check: CI has no GPU. */
#include <cuda_fp16.h>
#include <cuda_runtime.h>
#include <stdio.h>
#include <stdlib.h>

enum { N = 128, W = 1920, H = 1080, STEPS = 256, REPEATS = 10 };

#define CHECK(call)                                                                         \
	do {                                                                                \
		cudaError_t e_ = (call);                                                    \
		if (e_ != cudaSuccess) {                                                    \
			fprintf(stderr, "texfetch: %s: %s\n", #call, cudaGetErrorString(e_)); \
			exit(1);                                                            \
		}                                                                           \
	} while (0)

__global__ void march(cudaTextureObject_t tex, float *out)
{
	int i = blockIdx.x * blockDim.x + threadIdx.x, j = blockIdx.y * blockDim.y + threadIdx.y;
	if (i >= W || j >= H)
		return;
	/* a ray through the volume: neighbouring pixels start a voxel apart */
	float u = (float)i / N, v = (float)j / N, w = 0.25f, step = 0.5f / N;
	float sum = 0.0f;
	for (int k = 0; k < STEPS; k++) {
		float4 q = tex3D<float4>(tex, u, v, w);
		sum += q.x + q.y + q.z + q.w;
		u += 0.3f * step, v += 0.2f * step, w += step;
	}
	out[(size_t)j * W + i] = sum;
}

int main(void)
{
	size_t n = (size_t)N * N * N * 4;
	__half *hv = (__half *)malloc(n * sizeof *hv);
	if (hv == NULL)
		return 1;
	unsigned x = 12345u; /* random voxels: no cache line is all alike */
	for (size_t k = 0; k < n; k++) {
		x = x * 1664525u + 1013904223u;
		hv[k] = __float2half((float)(x >> 8) / 16777216.0f);
	}
	cudaChannelFormatDesc fd = cudaCreateChannelDescHalf4();
	cudaExtent ext = make_cudaExtent(N, N, N);
	cudaArray_t arr;
	CHECK(cudaMalloc3DArray(&arr, &fd, ext));
	cudaMemcpy3DParms cp = {};
	cp.srcPtr = make_cudaPitchedPtr(hv, N * 4 * sizeof *hv, N, N);
	cp.dstArray = arr;
	cp.extent = ext;
	cp.kind = cudaMemcpyHostToDevice;
	CHECK(cudaMemcpy3D(&cp));
	cudaResourceDesc rd = {};
	rd.resType = cudaResourceTypeArray;
	rd.res.array.array = arr;
	cudaTextureDesc td = {};
	td.addressMode[0] = td.addressMode[1] = td.addressMode[2] = cudaAddressModeWrap;
	td.filterMode = cudaFilterModeLinear;
	td.readMode = cudaReadModeElementType;
	td.normalizedCoords = 1;
	cudaTextureObject_t tex;
	CHECK(cudaCreateTextureObject(&tex, &rd, &td, NULL));
	float *out;
	CHECK(cudaMalloc((void **)&out, (size_t)W * H * sizeof *out));
	dim3 block(16, 8), grid((W + 15) / 16, (H + 7) / 8);
	cudaEvent_t e0, e1;
	CHECK(cudaEventCreate(&e0));
	CHECK(cudaEventCreate(&e1));
	march<<<grid, block>>>(tex, out); /* warm-up */
	CHECK(cudaGetLastError());
	float best = 1e30f;
	for (int r = 0; r < REPEATS; r++) {
		CHECK(cudaEventRecord(e0));
		march<<<grid, block>>>(tex, out);
		CHECK(cudaEventRecord(e1));
		CHECK(cudaEventSynchronize(e1));
		float ms;
		CHECK(cudaEventElapsedTime(&ms, e0, e1));
		best = ms < best ? ms : best;
	}
	double fetches = (double)W * H * STEPS;
	printf("texfetch: %dx%d threads, %d fetches each, 128^3 RGBA16F, trilinear, wrapped: "
	       "%.3f ms, %.1f G fetches/s\n",
	       W, H, STEPS, best, fetches / (best * 1e-3) / 1e9);
	return 0;
}
