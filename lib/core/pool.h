/* pool.h - the CPU pool: one parallel loop over independent tasks, used by
 * the noise bake (a task per z slice) and the renderer (a task per band of
 * rows).
 *
 * Tasks are handed out in order from an atomic counter to nthreads workers;
 * the calling thread reports progress meanwhile.  Results depend only on
 * what each task writes, never on which worker ran it, so output is the
 * same for any thread count. */
#ifndef CS_POOL_H
#define CS_POOL_H

#define CS_POOL_MAX_THREADS 256

/* Progress (0..1) of long work; returns nonzero to cancel it. */
typedef int (*cs_progress_fn)(void *user, double fraction);

/* One task: task in 0..ntasks-1, worker in 0..nthreads-1 (a worker index
 * for per-thread scratch or statistics). */
typedef void (*cs_task_fn)(void *user, int task, int worker);

/* Runs fn for every task on nthreads workers (<= 0: one per processor;
 * at most ntasks and CS_POOL_MAX_THREADS).  *nworkers (may be NULL) gets
 * the number of worker indices used.  progress may be NULL; when it asks
 * to stop, no new task starts and CS_ECANCELED is returned.  With one
 * worker and no progress the tasks run on the calling thread.  CS_OK. */
int cs_pool_run(int ntasks, int nthreads, cs_task_fn fn, void *user,
		cs_progress_fn progress, void *progress_user, int *nworkers);

/* The number of processors online (at least 1). */
int cs_pool_cpus(void);

#endif
