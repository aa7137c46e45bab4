#include "core/pool.h"

#include "core/err.h"

#include <pthread.h>
#include <stdatomic.h>
#include <time.h>
#include <unistd.h>

struct pool {
	cs_task_fn fn;
	void *user;
	int ntasks;
	atomic_int next, done, cancel;
	int finished;         /* workers that have returned (under lock) */
	pthread_mutex_t lock; /* with wake: the reporting thread waits for */
	pthread_cond_t wake;  /* a worker's end or its next report */
};

struct worker {
	struct pool *p;
	int index;
};

static void *work(void *arg)
{
	struct worker *w = arg;
	struct pool *p = w->p;
	while (!atomic_load(&p->cancel)) {
		int t = atomic_fetch_add(&p->next, 1);
		if (t >= p->ntasks)
			break;
		p->fn(p->user, t, w->index);
		atomic_fetch_add(&p->done, 1);
	}
	pthread_mutex_lock(&p->lock);
	p->finished++;
	pthread_cond_signal(&p->wake);
	pthread_mutex_unlock(&p->lock);
	return NULL;
}

/* The calling thread, while started workers run: progress every 20 ms
 * until they have all returned (or progress cancels), woken at once by
 * the last one (polling with a sleep rounded every run up to the next
 * 20 ms: a 96x54 image took 21 ms however few its steps). */
static void report(struct pool *p, int started, cs_progress_fn progress, void *progress_user)
{
	pthread_mutex_lock(&p->lock);
	while (p->finished < started) {
		if (!atomic_load(&p->cancel)) {
			pthread_mutex_unlock(&p->lock);
			if (progress(progress_user, (double)atomic_load(&p->done) / p->ntasks))
				atomic_store(&p->cancel, 1);
			pthread_mutex_lock(&p->lock);
		}
		struct timespec until;
		clock_gettime(CLOCK_REALTIME, &until);
		until.tv_nsec += 20 * 1000 * 1000;
		if (until.tv_nsec >= 1000 * 1000 * 1000)
			until.tv_sec++, until.tv_nsec -= 1000 * 1000 * 1000;
		while (p->finished < started &&
		       pthread_cond_timedwait(&p->wake, &p->lock, &until) == 0)
			;
	}
	pthread_mutex_unlock(&p->lock);
}

int cs_pool_cpus(void)
{
	long n = sysconf(_SC_NPROCESSORS_ONLN);
	return n > 0 ? (int)n : 1;
}

int cs_pool_run(int ntasks, int nthreads, cs_task_fn fn, void *user,
		cs_progress_fn progress, void *progress_user, int *nworkers)
{
	if (nthreads <= 0)
		nthreads = cs_pool_cpus();
	nthreads = nthreads > ntasks ? ntasks : nthreads;
	nthreads = nthreads > CS_POOL_MAX_THREADS ? CS_POOL_MAX_THREADS : nthreads;
	nthreads = nthreads < 1 ? 1 : nthreads;
	struct pool p = {.fn = fn, .user = user, .ntasks = ntasks};
	atomic_init(&p.next, 0);
	atomic_init(&p.done, 0);
	atomic_init(&p.cancel, 0);
	p.finished = 0;
	pthread_mutex_init(&p.lock, NULL);
	pthread_cond_init(&p.wake, NULL);
	pthread_t tid[CS_POOL_MAX_THREADS];
	struct worker w[CS_POOL_MAX_THREADS];
	int started = 0;
	/* one worker with no one to report progress: no thread to start */
	for (; started < nthreads && (nthreads > 1 || progress); started++) {
		w[started] = (struct worker){&p, started};
		if (pthread_create(&tid[started], NULL, work, &w[started]) != 0)
			break;
	}
	if (started == 0) { /* none asked for, or none could start: work here */
		w[0] = (struct worker){&p, 0};
		work(&w[0]);
	}
	if (progress && started > 0)
		report(&p, started, progress, progress_user);
	for (int i = 0; i < started; i++)
		pthread_join(tid[i], NULL);
	pthread_cond_destroy(&p.wake);
	pthread_mutex_destroy(&p.lock);
	if (nworkers)
		*nworkers = started > 0 ? started : 1;
	if (atomic_load(&p.cancel))
		return cs_error(CS_ECANCELED, "cancelled");
	if (progress)
		progress(progress_user, 1.0);
	return CS_OK;
}
