/* frame.c - a whole frame: bands of rows as tasks of the CPU pool, one ray
 * per pixel with its jitter from the pixel's hash, statistics gathered per
 * task and summed per worker (no counters shared between threads). */
#include "render/render.h"
#include "render/cpu/kernel.h"

#include "core/err.h"

#include <stdalign.h>
#include <stdlib.h>
#include <string.h>

enum { ROWS_PER_TASK = 4 };

/* A worker's statistics, on a cache line of its own. */
struct worker_stats {
	alignas(64) struct cs_render_stats s;
};

struct frame_job {
	cs_kernel_rows_fn *rows;
	const struct cs_scene *sc;
	const struct cs_camera *cam;
	const struct cs_render_settings *s;
	float *out;
	struct worker_stats stats[CS_POOL_MAX_THREADS];
};

static void stats_add(struct cs_render_stats *a, const struct cs_render_stats *b)
{
	a->pixels += b->pixels;
	a->density_samples += b->density_samples;
	a->light_samples += b->light_samples;
	a->rays_terminated_early += b->rays_terminated_early;
	a->layer_crossings += b->layer_crossings;
	a->terrain_cells += b->terrain_cells;
}

static void render_rows(void *user, int task, int worker)
{
	struct frame_job *job = user;
	const struct cs_camera *cam = job->cam;
	struct cs_render_stats st = {0};
	int r0 = task * ROWS_PER_TASK;
	int r1 = r0 + ROWS_PER_TASK < cam->height ? r0 + ROWS_PER_TASK : cam->height;
	job->rows(job->sc, cam, job->s, r0, r1, &st, job->out);
	stats_add(&job->stats[worker].s, &st);
}

/* The builds of cpu/kernel.c, best last (the same bits, each faster on a
 * CPU that has its instructions). */
static const struct kernel {
	const char *name; /* CLOUDSCAPE_KERNEL's word */
	cs_kernel_rows_fn *rows;
	cs_kernel_extinction_fn *extinction;
} kernels[] = {
	{"base", cs_kernel_rows_base, cs_kernel_extinction_base},
	{"avx2", cs_kernel_rows_avx2, cs_kernel_extinction_avx2},
	{"avx512", cs_kernel_rows_avx512, cs_kernel_extinction_avx512},
};
enum { NKERNELS = sizeof kernels / sizeof kernels[0] };

/* Whether this CPU has kernel k's instructions. */
static int cpu_has(int k)
{
#if defined(__x86_64__) && defined(__GNUC__)
	switch (k) { /* kernels[k]; the builtin takes a literal */
	case 0:
		return 1;
	case 1:
		return __builtin_cpu_supports("avx2");
	case 2: /* x86-64-v4 by its parts: clang 14 knows no level names */
		return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
		       __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
		       __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
		       __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
		       __builtin_cpu_supports("avx512vl");
	default:
		return 0;
	}
#else
	return k == 0;
#endif
}

/* The build to run: the best this CPU has, or, with CLOUDSCAPE_KERNEL
 * naming one, that one where the CPU has it (else the best it has below
 * it). */
static const struct kernel *kernel(void)
{
	const char *want = getenv("CLOUDSCAPE_KERNEL");
	int top = NKERNELS - 1;
	for (int k = 0; want != NULL && k < NKERNELS; k++)
		if (strcmp(want, kernels[k].name) == 0)
			top = k;
	while (top > 0 && !cpu_has(top))
		top--;
	return &kernels[top];
}

const char *cs_render_kernel_name(void)
{
	return kernel()->name;
}

void cs_render_extinction(const struct cs_cloud_layer *l, const struct cs_volume *noise, int n,
			  const double *xyz, double *out)
{
	kernel()->extinction(l, noise, n, xyz, out);
}

int cs_render_image(const struct cs_scene *sc, const struct cs_camera *cam,
		    const struct cs_render_settings *s, int nthreads,
		    cs_progress_fn progress, void *user, float *out,
		    struct cs_render_stats *stats)
{
	int rc = cs_render_settings_check(s);
	if (rc != CS_OK)
		return rc;
	/* aligned as its cache-line members ask (calloc promises less) */
	size_t size = (sizeof(struct frame_job) + 63) / 64 * 64;
	struct frame_job *job = aligned_alloc(64, size);
	if (job == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	/* the light caches, the towers' light and the ground's dome: built
	 * on a copy of the scene, for this frame (cs_frame_scene) */
	struct cs_scene *cached;
	uint64_t cache_evaluations;
	int ground_lit;
	rc = cs_frame_scene(sc, cam, s, nthreads, &cached, &cache_evaluations, &ground_lit);
	if (rc != CS_OK) {
		free(job);
		return rc;
	}
	if (cached != NULL)
		sc = cached;
	*job = (struct frame_job){.rows = kernel()->rows, .sc = sc, .cam = cam, .s = s, .out = out};
	int tasks = (cam->height + ROWS_PER_TASK - 1) / ROWS_PER_TASK, workers = 0;
	rc = cs_pool_run(tasks, nthreads, render_rows, job, progress, user, &workers);
	memset(stats, 0, sizeof *stats);
	for (int i = 0; i < workers; i++)
		stats_add(stats, &job->stats[i].s);
	stats->light_samples += cache_evaluations;
	stats->ground_lit = ground_lit;
	if (cached != NULL) {
		stats->cache_cells = cache_evaluations;
		stats->cache_volumes = cs_light_cache_volumes(cached);
		cs_frame_scene_free(cached);
	}
	free(job);
	if (rc == CS_ECANCELED)
		return cs_error(CS_ECANCELED, "rendering cancelled");
	return rc;
}
