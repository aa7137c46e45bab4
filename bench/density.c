/* density - density evaluations per second: cs_cloud_extinction (the
 * per-sample work of every march) as the renderer's per-pixel code runs
 * it (cs_render_extinction: the kernel build this CPU runs, the same
 * bits), in batches of 1024 points (making the points is timed too), at
 * points along view rays of the
 * default scene (built-in weather, the noise baked in memory as
 * cloudrender bakes it, 64^3), inside its cloud layers, on N threads (0:
 * all processors), for make bench.
 *
 *   density [THREADS [SECONDS]]
 *
 * prints one line: threads, evaluations, seconds, evaluations per second,
 * and the share of points with cloud (a check that the points are the
 * renderer's kind of points, mostly clear sky). */
#include "core/hash.h"
#include "core/pool.h"
#include "noise/volume.h"
#include "render/render.h"
#include "render/scene.h"
#include "weather/wx.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { TASKS = 256, PER_TASK = 1 << 16, CHUNK = 1024 };

struct job {
	const struct cs_scene *sc;
	double sink[CS_POOL_MAX_THREADS];
	long cloudy[CS_POOL_MAX_THREADS];
};

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* One task: 2^16 points inside one layer (the task's), along a line
 * climbing through it in steps of 25 m (a medium-quality view step) from
 * a random direction: every evaluation is one a march makes, inside the
 * layer's shell. */
static void task(void *user, int t, int worker)
{
	struct job *j = user;
	const struct cs_scene *sc = j->sc;
	const struct cs_cloud_layer *l = &sc->layers[t % sc->nlayers];
	uint32_t h = cs_hash_u32((uint32_t)t * 2654435761u + 1u);
	double az = cs_hash_unit(h) * 6.283185307179586;
	double dx = cos(az), dy = sin(az), th = l->top_m - l->base_m;
	double sum = 0.0;
	long cloudy = 0;
	static _Thread_local double xyz[3 * CHUNK], out[CHUNK];
	for (int k0 = 0; k0 < PER_TASK; k0 += CHUNK) {
		for (int i = 0; i < CHUNK; i++) {
			int k = k0 + i;
			double s = 25.0 * k, f = (k % 512 + 0.5) / 512.0;
			xyz[3 * i] = dx * s, xyz[3 * i + 1] = dy * s, xyz[3 * i + 2] = l->base_m + f * th;
		}
		cs_render_extinction(l, sc->noise, CHUNK, xyz, out);
		for (int i = 0; i < CHUNK; i++) {
			sum += out[i];
			cloudy += out[i] > 0.0;
		}
	}
	j->sink[worker] += sum;
	j->cloudy[worker] += cloudy;
}

int main(int argc, char **argv)
{
	int threads = argc > 1 ? atoi(argv[1]) : 0;
	double seconds = argc > 2 ? atof(argv[2]) : 2.0;
	struct cs_wx wx;
	cs_wx_default(&wx);
	struct cs_volume noise;
	if (cs_volume_new(&noise, 64, 64) != 0 || cs_volume_bake(&noise, 0, NULL, NULL) != 0)
		return 1;
	struct cs_scene *sc = calloc(1, sizeof *sc);
	if (sc == NULL || cs_scene_build(sc, &wx, wx.time_utc, &noise) != 0)
		return 1;
	struct job *j = calloc(1, sizeof *j);
	j->sc = sc;
	long evals = 0;
	int workers = 0;
	double t0 = now_s(), t;
	do {
		cs_pool_run(TASKS, threads, task, j, NULL, NULL, &workers);
		evals += (long)TASKS * PER_TASK;
		t = now_s() - t0;
	} while (t < seconds);
	long cloudy = 0;
	double sink = 0.0;
	for (int i = 0; i < CS_POOL_MAX_THREADS; i++)
		cloudy += j->cloudy[i], sink += j->sink[i];
	printf("density threads=%d evaluations=%ld seconds=%.3f evaluations_per_s=%.0f "
	       "cloudy=%.3f checksum=%.6g\n",
	       workers, evals, t, evals / t, (double)cloudy / evals, sink);
	free(j);
	free(sc);
	cs_volume_free(&noise);
	return 0;
}
