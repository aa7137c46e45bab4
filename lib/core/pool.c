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
	return NULL;
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
	pthread_t tid[CS_POOL_MAX_THREADS];
	struct worker w[CS_POOL_MAX_THREADS];
	int started = 0;
	for (; started < nthreads; started++) {
		w[started] = (struct worker){&p, started};
		if (pthread_create(&tid[started], NULL, work, &w[started]) != 0)
			break;
	}
	if (started == 0) { /* no thread could start: work here */
		w[0] = (struct worker){&p, 0};
		work(&w[0]);
	}
	while (progress && started > 0 && atomic_load(&p.done) < ntasks &&
	       !atomic_load(&p.cancel)) {
		if (progress(progress_user, (double)atomic_load(&p.done) / ntasks))
			atomic_store(&p.cancel, 1);
		struct timespec ts = {0, 20 * 1000 * 1000};
		nanosleep(&ts, NULL);
	}
	for (int i = 0; i < started; i++)
		pthread_join(tid[i], NULL);
	if (nworkers)
		*nworkers = started > 0 ? started : 1;
	if (atomic_load(&p.cancel))
		return cs_error(CS_ECANCELED, "cancelled");
	if (progress)
		progress(progress_user, 1.0);
	return CS_OK;
}
