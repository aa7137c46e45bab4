/* frame.c - a whole frame: bands of rows as tasks of the CPU pool, one ray
 * per pixel with its jitter from the pixel's hash, statistics gathered per
 * task and summed per worker (no counters shared between threads). */
#include "render/render.h"

#include "core/err.h"
#include "core/hash.h"

#include <stdalign.h>
#include <stdlib.h>
#include <string.h>

enum { ROWS_PER_TASK = 4 };

/* A worker's statistics, on a cache line of its own. */
struct worker_stats {
	alignas(64) struct cs_render_stats s;
};

struct frame_job {
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
	for (int j = r0; j < r1; j++) {
		for (int i = 0; i < cam->width; i++) {
			double u = 0.5;
			if (job->s->jitter > 0.0) {
				uint32_t h = cs_hash3i(i, j, 0x6a697474, job->s->seed);
				u = 0.5 + job->s->jitter * (cs_hash_unit(h) - 0.5);
			}
			struct cs_ray_result r = {{0.0, 0.0, 0.0}, 1.0, CS_SKY_DEPTH_M};
			cs_v3 d;
			if (cs_camera_ray(cam, i, j, &d))
				cs_render_ray(job->sc, job->s, cam->pos, d, u, &st, &r);
			float *px = job->out + ((size_t)j * cam->width + i) * 5;
			px[0] = (float)r.rgb[0];
			px[1] = (float)r.rgb[1];
			px[2] = (float)r.rgb[2];
			px[3] = (float)(1.0 - r.transmittance);
			px[4] = (float)r.depth_m;
			st.pixels++;
		}
	}
	stats_add(&job->stats[worker].s, &st);
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
	*job = (struct frame_job){.sc = sc, .cam = cam, .s = s, .out = out};
	int tasks = (cam->height + ROWS_PER_TASK - 1) / ROWS_PER_TASK, workers = 0;
	rc = cs_pool_run(tasks, nthreads, render_rows, job, progress, user, &workers);
	memset(stats, 0, sizeof *stats);
	for (int i = 0; i < workers; i++)
		stats_add(stats, &job->stats[i].s);
	free(job);
	if (rc == CS_ECANCELED)
		return cs_error(CS_ECANCELED, "rendering cancelled");
	return rc;
}
