#include "core/err.h"
#include "core/pool.h"
#include "test.h"

#include <pthread.h>
#include <stdatomic.h>
#include <time.h>

enum { NTASKS = 500 };

struct job {
	atomic_int runs[NTASKS];
	atomic_int calls;      /* progress reports */
	atomic_int asked;      /* progress has been called */
	double first, last;    /* the first and last fractions reported */
	int cancel_at;         /* progress asks to stop at this call (0: never) */
	int block_first;       /* task 0 waits until progress has been called */
};

static void task(void *user, int t, int worker)
{
	struct job *j = user;
	(void)worker;
	if (j->block_first) { /* task 0 until progress is asked, the others 1 ms */
		struct timespec ts = {0, 1000 * 1000};
		if (t > 0)
			nanosleep(&ts, NULL);
		else
			while (!atomic_load(&j->asked))
				nanosleep(&ts, NULL);
	}
	atomic_fetch_add(&j->runs[t], 1);
}

static int progress(void *user, double fraction)
{
	struct job *j = user;
	int n = atomic_fetch_add(&j->calls, 1) + 1;
	if (n == 1)
		j->first = fraction;
	j->last = fraction;
	atomic_store(&j->asked, 1);
	return j->cancel_at > 0 && n >= j->cancel_at;
}

static void job_init(struct job *j)
{
	for (int t = 0; t < NTASKS; t++)
		atomic_init(&j->runs[t], 0);
	atomic_init(&j->calls, 0);
	atomic_init(&j->asked, 0);
	j->first = j->last = -1.0;
	j->cancel_at = 0;
	j->block_first = 0;
}

/* Every task runs exactly once, for any thread count, with and without
 * progress; progress reports 1 last, and nworkers is the threads asked
 * for (at most the tasks and CS_POOL_MAX_THREADS). */
static void pool_runs_every_task_once(void)
{
	static struct job j;
	const int threads[] = {1, 2, 3, 8, 300, 600};
	for (int k = 0; k < 6; k++)
		for (int with = 0; with < 2; with++) {
			job_init(&j);
			int workers = 0;
			CHECK(cs_pool_run(NTASKS, threads[k], task, &j, with ? progress : NULL, &j,
					  &workers) == CS_OK);
			int once = 0;
			for (int t = 0; t < NTASKS; t++)
				once += atomic_load(&j.runs[t]) == 1;
			CHECK(once == NTASKS);
			int want = threads[k] < CS_POOL_MAX_THREADS ? threads[k] : CS_POOL_MAX_THREADS;
			CHECK(workers == want);
			if (with) {
				CHECK(j.first >= 0.0 && j.first <= 1.0);
				CHECK(j.last == 1.0);
			} else
				CHECK(atomic_load(&j.calls) == 0);
		}
}

/* Progress that asks to stop on its first call, before the one worker
 * has started or while it is on task 0: the run says cancelled, and only
 * the tasks of 1 ms the worker took while progress was returning start
 * after it (all 500 when the pool ignores the request: half a second). */
static void pool_cancel_starts_no_new_task(void)
{
	static struct job j;
	job_init(&j);
	j.cancel_at = 1;
	j.block_first = 1;
	CHECK(cs_pool_run(NTASKS, 1, task, &j, progress, &j, NULL) == CS_ECANCELED);
	CHECK_STR_CONTAINS(cs_errmsg(), "cancelled");
	int ran = 0;
	for (int t = 0; t < NTASKS; t++)
		ran += atomic_load(&j.runs[t]);
	CHECK(ran < NTASKS / 2);
	CHECK(atomic_load(&j.calls) == 1); /* not asked again once cancelled */
}

/* One worker and no progress: the tasks run on the calling thread, in
 * order (no thread to start for a pool of one); with progress (which the
 * calling thread reports) on another. */
struct where {
	pthread_t caller;
	int on_caller;
	atomic_int elsewhere;
	int next, in_order;
};

static void where_task(void *user, int t, int worker)
{
	struct where *w = user;
	(void)worker;
	if (pthread_equal(pthread_self(), w->caller))
		w->on_caller++;
	else
		atomic_fetch_add(&w->elsewhere, 1);
	if (t != w->next++)
		w->in_order = 0;
}

static int no_stop(void *user, double fraction)
{
	(void)user, (void)fraction;
	return 0;
}

static void pool_of_one_runs_on_the_calling_thread(void)
{
	struct where w = {pthread_self(), 0, 0, 0, 1};
	int workers = 0;
	CHECK(cs_pool_run(50, 1, where_task, &w, NULL, NULL, &workers) == CS_OK);
	CHECK(w.on_caller == 50 && atomic_load(&w.elsewhere) == 0 && w.in_order && workers == 1);
	w = (struct where){pthread_self(), 0, 0, 0, 1};
	CHECK(cs_pool_run(50, 1, where_task, &w, no_stop, NULL, NULL) == CS_OK);
	CHECK(w.on_caller == 0 && atomic_load(&w.elsewhere) == 50);
}

/* The cases, in the order they run: their number is the plan. */
static const struct t_case t_cases[] = {
	CASE(pool_runs_every_task_once),
	CASE(pool_cancel_starts_no_new_task),
	CASE(pool_of_one_runs_on_the_calling_thread),
};

int main(void)
{
	T_RUN_TABLE(t_cases);
	TEST_EXIT();
}
