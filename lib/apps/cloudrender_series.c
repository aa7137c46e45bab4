/* cloudrender over a series of weather states: the frames' names, the
 * slice, the frames already there, and one frame after the other over what
 * they share (cloudrender_session.h). */
#include "apps/cloudrender_run.h"
#include "apps/cloudrender_session.h"

#include "core/err.h"
#include "core/fileio.h"
#include "core/framename.h"
#include "core/pool.h"
#include "render/scene.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The weather: every state of the file, or the built-in one. */
struct states {
	struct cs_wx_series series;
	int from_file;
	int n;
};

/* State i; with --cloud-depth genus without the forecast's radiation,
 * which the scene would fit its sheets to (cs_scene_fit_beam) and nothing
 * else in a render reads. */
static int get_state(const struct states *st, const struct cs_cloudrender_opts *o, int i,
		     struct cs_wx *wx)
{
	if (!st->from_file) {
		cs_wx_default(wx);
		return CS_OK;
	}
	int rc = cs_wx_series_get(&st->series, i, wx);
	if (o->cloud_depth_genus)
		wx->observed.has_radiation = 0;
	return rc;
}

/* The options every frame shares, checked against the series: the
 * patterns, what a single frame allows, the slice.  [*first, *last) are
 * the indices of the states the slice renders. */
static int check_patterns(const struct cs_cloudrender_opts *o)
{
	for (int i = 0; i < o->noutputs; i++)
		if (cs_framename_check(o->outputs[i]) < 0)
			return cs_error(CS_EINVAL, "-o %s", cs_errmsg());
	if (o->start_number < 0)
		return cs_error(CS_EINVAL, "the start number %lld is negative", o->start_number);
	/* the first frame's places now, before any input is read */
	long long first = o->frames_from >= 0 ? o->frames_from : o->start_number;
	char names[CS_RENDER_MAX_OUTPUTS][4096];
	const char *p[CS_RENDER_MAX_OUTPUTS];
	for (int i = 0; i < o->noutputs && i < CS_RENDER_MAX_OUTPUTS; i++) {
		CS_TRY(cs_framename_format(o->outputs[i], first, names[i], sizeof names[i]));
		p[i] = names[i];
	}
	return cs_outset_check(p, o->noutputs < CS_RENDER_MAX_OUTPUTS ? o->noutputs
								       : CS_RENDER_MAX_OUTPUTS,
			       o->no_clobber && !o->skip_existing ? CS_OUT_NO_CLOBBER : 0);
}

static int plan(const struct cs_cloudrender_opts *o, int n, int *first, int *last)
{
	long long lo = o->start_number, hi = o->start_number + n; /* the series' numbers */
	long long from = o->frames_from >= 0 ? o->frames_from : lo;
	long long to = o->frames_to >= 0 ? o->frames_to : hi;
	if (to > hi)
		to = hi; /* a slice past the end ends with the series */
	if (from < lo || from >= to)
		return cs_error(CS_EINVAL, "frames %lld:%lld select none of the series' %d "
				"state%s (frames %lld:%lld)", from,
				o->frames_to >= 0 ? o->frames_to : hi, n, n == 1 ? "" : "s",
				lo, hi);
	*first = (int)(from - lo), *last = (int)(to - lo);
	int frames = *last - *first;
	if (frames > 1 && o->have_time)
		return cs_error(CS_EINVAL, "--time sets the time of one state: the series has "
				"%d states (each frame takes its state's time)", n);
	for (int i = 0; frames > 1 && i < o->noutputs; i++)
		if (strcmp(o->outputs[i], "-") == 0)
			return cs_error(CS_EINVAL, "-o -: standard output takes one frame, and "
					"there are %d: name the frames with a number, e.g. "
					"-o frames/%%05d.png", frames);
	if (frames > 1)
		for (int i = 0; i < o->noutputs; i++)
			if (cs_framename_check(o->outputs[i]) == 0)
				return cs_error(CS_EINVAL, "-o %s: %d frames need a frame number "
						"in the name, e.g. -o frames/%%05d.png (%%%% for "
						"a literal percent)", o->outputs[i], frames);
	return CS_OK;
}

/* The names of frame number; with skip_existing only those not there. */
static int frame_names(const struct cs_cloudrender_opts *o, long long number,
		       struct cs_cloudrender_frame *f, enum cs_out_format *formats)
{
	f->noutputs = 0;
	for (int i = 0; i < o->noutputs; i++) {
		char *name = f->outputs[f->noutputs];
		CS_TRY(cs_framename_format(o->outputs[i], number, name, sizeof f->outputs[0]));
		struct stat st;
		if (o->skip_existing && strcmp(name, "-") != 0 && stat(name, &st) == 0)
			continue;
		formats[f->noutputs++] = o->formats[i];
	}
	return CS_OK;
}

/* The frames to render, checked before the first one is: every name's
 * place (cs_outset_check), the frames all there counted out. */
static int check_frames(const struct cs_cloudrender_opts *o, int first, int last,
			int *count)
{
	struct cs_cloudrender_frame *f = malloc(sizeof *f);
	if (f == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	enum cs_out_format formats[CS_RENDER_MAX_OUTPUTS];
	int rc = CS_OK;
	*count = 0;
	for (int i = first; i < last && rc == CS_OK; i++) {
		rc = frame_names(o, o->start_number + i, f, formats);
		if (rc != CS_OK || f->noutputs == 0)
			continue;
		const char *names[CS_RENDER_MAX_OUTPUTS];
		for (int k = 0; k < f->noutputs; k++)
			names[k] = f->outputs[k];
		rc = cs_outset_check(names, f->noutputs, o->no_clobber ? CS_OUT_NO_CLOBBER : 0);
		++*count;
	}
	free(f);
	return rc;
}

/* A series of more than one state keeps the camera still: the default
 * view (no --view, no --look) is the first state's, whatever the slice. */
static int hold_look(struct cs_cr_session *s, const struct states *st,
		     struct cs_cloudrender_opts *fo, struct cs_cloudrender_result *r,
		     char *why, size_t why_size)
{
	why[0] = '\0';
	if (st->n < 2 || fo->have_look || fo->view)
		return CS_OK;
	CS_TRY(get_state(st, fo, 0, &r->wx));
	CS_TRY(cs_cr_session_look(s, fo, r));
	fo->have_look = 1;
	fo->look_az_deg = r->look_az_deg, fo->look_el_deg = r->look_el_deg;
	snprintf(why, why_size, "the series' first state's %.130s", r->look_why);
	return CS_OK;
}

/* The progress of one frame as a part of the run's. */
struct run_progress {
	cs_progress_fn fn;
	void *user;
	double done, count;
	const volatile sig_atomic_t *cancel;
};

static int run_progress(void *user, double fraction)
{
	struct run_progress *p = user;
	if (p->cancel && *p->cancel)
		return 1; /* the render stops: CS_ECANCELED */
	return p->fn ? p->fn(p->user, (p->done + fraction) / p->count) : 0;
}

/* The ready callback of a held look: the reason said first. */
struct held_ready {
	const struct cs_cloudrender_opts *o;
	struct cs_cloudrender_result *r;
	const char *why;
};

static void held_ready(void *user, const struct cs_cloudrender_result *r)
{
	struct held_ready *h = user;
	(void)r;
	snprintf(h->r->look_why, sizeof h->r->look_why, "%s", h->why);
	h->o->ready(h->o->ready_user, h->r);
}

static void tell(const struct cs_cloudrender_opts *o, struct cs_cloudrender_frame *f,
		 enum cs_frame_stage stage, const struct cs_cloudrender_result *r)
{
	f->stage = stage;
	if (o->frame)
		o->frame(o->frame_user, f, r);
}

/* A rendered frame whose outputs are written on a thread of its own while
 * the next frames render (a series on several threads): its own copy of
 * the pixels, the options with its names, and what describes it (its
 * scene too, for its report: the session's is the next frame's by then). */
struct write_slot {
	pthread_t th;
	int busy;              /* a thread was started (join it) */
	atomic_int done;       /* the frame's outputs are written, or failed */
	struct cs_cloudrender_opts o;
	struct cs_cloudrender_result r;
	struct cs_scene *scene;
	struct cs_cloudrender_frame f;
	const char *names[CS_RENDER_MAX_OUTPUTS];
	float *px;
	double t0, t1;         /* the frame's start, its outputs' end */
	int rc;
	char msg[1024];
};

static void *write_slot_run(void *user)
{
	struct write_slot *w = user;
	w->rc = cs_cr_write(&w->o, &w->r, w->px);
	if (w->rc != CS_OK)
		snprintf(w->msg, sizeof w->msg, "%s", cs_errmsg());
	w->t1 = now_s();
	atomic_store(&w->done, 1);
	return NULL;
}

/* The ring of nslots frames being written: pending of them, the oldest
 * pending before next. */
struct writers {
	struct write_slot *slot;
	int nslots, next, pending;
	int threads; /* each writer's (an EXR's compression), the run's shared */
};

/* The writers of a series of count frames: half the threads' frames at
 * once, at most 8, and no more than 512 MB of frames held beyond the
 * first; none (one thread, one frame, or no memory for the ring): each
 * frame is written before the next one renders. */
static void writers_init(struct writers *wr, const struct cs_cloudrender_opts *o, int count)
{
	*wr = (struct writers){0};
	int threads = o->threads > 0 ? o->threads : cs_pool_cpus();
	double bytes = 5.0 * sizeof(float) * (double)o->width * (double)o->height;
	int k = threads / 2 < 8 ? threads / 2 : 8;
	while (k > 1 && k * bytes > 512e6)
		k--;
	if (count < 2 || k < 1 || (wr->slot = calloc((size_t)k, sizeof *wr->slot)) == NULL)
		return;
	wr->nslots = k;
	wr->threads = threads / k > 1 ? threads / k : 1;
}

/* The run's error for frame f that failed with rc and message why: the
 * frame named when the series has several states. */
static int frame_error(int rc, const struct cs_cloudrender_frame *f, const char *why)
{
	return f->states > 1 ? cs_error(rc, "frame %lld (state %d): %s", f->number, f->index + 1, why)
			     : cs_error(rc, "%s", why);
}

/* Hands frame f, rendered into px as r describes it, to the next slot's
 * thread (its names those of f); written here, now, where no thread can
 * start.  The slot must be free. */
static int write_begin(struct writers *wr, const struct cs_cloudrender_opts *fo,
		       const struct cs_cloudrender_result *r, const struct cs_cloudrender_frame *f,
		       const float *px, double t0)
{
	struct write_slot *w = &wr->slot[wr->next];
	size_t n = (size_t)fo->width * fo->height * 5;
	if (w->px == NULL && (w->px = malloc(n * sizeof *w->px)) == NULL)
		return cs_error(CS_ENOMEM, "frame %lld: out of memory for its outputs", f->number);
	memcpy(w->px, px, n * sizeof *px);
	w->o = *fo, w->r = *r, w->f = *f, w->t0 = t0, w->rc = CS_OK, w->msg[0] = '\0';
	if (r->scene != NULL && (w->scene != NULL || (w->scene = malloc(sizeof *w->scene)) != NULL))
		memcpy(w->scene, r->scene, sizeof *w->scene);
	w->r.scene = r->scene != NULL ? w->scene : NULL; /* (out of memory: no layers in --stats) */
	for (int k = 0; k < w->f.noutputs; k++)
		w->names[k] = w->f.outputs[k];
	memcpy(w->o.outputs, w->names, sizeof w->names);
	w->o.progress = NULL; /* the run's bar belongs to the frames rendering */
	w->o.threads = wr->threads;
	atomic_store(&w->done, 0);
	w->busy = pthread_create(&w->th, NULL, write_slot_run, w) == 0;
	if (!w->busy)
		write_slot_run(w);
	wr->next = (wr->next + 1) % wr->nslots;
	wr->pending++;
	return CS_OK;
}

/* Reports the oldest frame being written, once written (CS_FRAME_DONE
 * with its own result), or says that it failed; with wait 0 only if it
 * already is (1: reported, 0: not yet, or an error). */
static int write_end(struct writers *wr, const struct cs_cloudrender_opts *o, int wait,
		     int *rc)
{
	*rc = CS_OK;
	if (wr->pending == 0)
		return 0;
	struct write_slot *w = &wr->slot[(wr->next - wr->pending + wr->nslots) % wr->nslots];
	if (!wait && !atomic_load(&w->done))
		return 0;
	if (w->busy)
		pthread_join(w->th, NULL);
	w->busy = 0;
	wr->pending--;
	w->f.wall_s = w->t1 - w->t0;
	if (w->rc != CS_OK) {
		*rc = frame_error(w->rc, &w->f, w->msg);
		return 0;
	}
	tell(o, &w->f, CS_FRAME_DONE, &w->r);
	return 1;
}

/* Reports the frames written so far, in order (wait: every one, waiting
 * for them); the first failure stops it. */
static int write_report(struct writers *wr, const struct cs_cloudrender_opts *o, int wait)
{
	int rc = CS_OK;
	while (write_end(wr, o, wait, &rc))
		;
	return rc;
}

/* Every frame of [first, last) in turn. */
static int run_frames(struct cs_cr_session *s, const struct cs_cloudrender_opts *o,
		      const struct states *st, int first, int last, int count,
		      struct cs_cloudrender_result *r)
{
	struct cs_cloudrender_opts fo = *o;
	char held[sizeof r->look_why] = "";
	if (count > 0)
		CS_TRY(hold_look(s, st, &fo, r, held, sizeof held));
	struct run_progress prog = {o->progress, o->progress_user, 0.0, count > 0 ? count : 1,
				    o->cancel};
	fo.progress = run_progress;
	fo.progress_user = &prog;
	struct held_ready hr = {o, r, held};
	if (held[0] && o->ready) {
		fo.ready = held_ready;
		fo.ready_user = &hr;
	}
	struct cs_cloudrender_frame *f = malloc(sizeof *f);
	if (f == NULL)
		return cs_error(CS_ENOMEM, "out of memory");
	/* with several threads, each frame is written while the next ones
	 * render, nslots at once, reported in order */
	struct writers wr;
	writers_init(&wr, o, count);
	const char *names[CS_RENDER_MAX_OUTPUTS];
	int rc = CS_OK;
	for (int i = first; i < last && rc == CS_OK; i++) {
		if (o->cancel && *o->cancel) {
			rc = cs_error(CS_ECANCELED, "interrupted before frame %lld",
				      o->start_number + i);
			break;
		}
		memset(f, 0, sizeof *f);
		f->index = i, f->number = o->start_number + i, f->states = st->n;
		f->count = count;
		rc = frame_names(o, f->number, f, fo.formats);
		if (rc != CS_OK)
			break;
		if (f->noutputs == 0) { /* after the frames before it */
			if ((rc = write_report(&wr, o, 1)) != CS_OK)
				break;
			tell(o, f, CS_FRAME_SKIPPED, r);
			continue;
		}
		/* the frames written meanwhile, and a failure, as soon as seen */
		if ((rc = write_report(&wr, o, 0)) != CS_OK)
			break;
		for (int k = 0; k < f->noutputs; k++)
			names[k] = f->outputs[k];
		memcpy(fo.outputs, names, sizeof names);
		fo.noutputs = f->noutputs;
		f->nth = (int)prog.done + 1;
		if ((rc = get_state(st, o, i, &r->wx)) != CS_OK)
			break;
		if (o->have_time)
			cs_wx_retime(&r->wx, o->time_utc); /* the drift goes with the time */
		if (prog.done > 0.0)
			r->t_noise_s = 0.0; /* made once: the first frame's cost */
		tell(o, f, CS_FRAME_START, r);
		double t0 = now_s();
		float *px = NULL;
		rc = wr.nslots > 0 ? cs_cr_session_render(s, &fo, r, &px)
				   : cs_cr_session_frame(s, &fo, r);
		if (rc == CS_OK && held[0])
			snprintf(r->look_why, sizeof r->look_why, "%s", held);
		if (rc == CS_OK && wr.nslots > 0) {
			if (wr.pending == wr.nslots) /* a slot for it: the oldest frame done */
				write_end(&wr, o, 1, &rc);
			if (rc == CS_OK)
				rc = write_begin(&wr, &fo, r, f, px, t0);
			prog.done += 1.0;
			continue;
		}
		f->wall_s = now_s() - t0;
		if (rc == CS_OK)
			tell(o, f, CS_FRAME_DONE, r);
		else if (st->n > 1)
			rc = frame_error(rc, f, cs_errmsg());
		prog.done += 1.0;
	}
	/* the frames still being written, in order; the first failure is the
	 * run's (its message kept), the last frame's write its result's */
	char *why = rc != CS_OK ? strdup(cs_errmsg()) : NULL;
	const struct write_slot *newest = wr.pending > 0
						? &wr.slot[(wr.next - 1 + wr.nslots) % wr.nslots]
						: NULL;
	while (wr.pending > 0) {
		int wrc;
		write_end(&wr, o, 1, &wrc);
		if (rc == CS_OK && wrc != CS_OK)
			rc = wrc, why = strdup(cs_errmsg());
	}
	if (rc == CS_OK && newest != NULL) {
		r->t_write_s = newest->r.t_write_s;
		r->exposure_ev = newest->r.exposure_ev;
	}
	if (rc != CS_OK && why != NULL)
		cs_error(rc, "%s", why);
	free(why);
	for (int k = 0; k < wr.nslots; k++) {
		free(wr.slot[k].px);
		free(wr.slot[k].scene);
	}
	free(wr.slot);
	free(f);
	return rc;
}

int cs_cloudrender_run(const struct cs_cloudrender_opts *o, struct cs_cloudrender_result *r)
{
	memset(r, 0, sizeof *r);
	struct cs_cr_session *s = NULL;
	struct states st;
	memset(&st, 0, sizeof st);
	st.n = 1;
	int first = 0, last = 1, count = 0;
	int rc = cs_cr_session_open(o, r, &s);
	if (rc == CS_OK)
		rc = check_patterns(o); /* before any file */
	if (rc == CS_OK && o->wx_path) {
		rc = cs_wx_series_read(o->wx_path, &st.series);
		st.from_file = rc == CS_OK;
		st.n = st.series.n;
	}
	if (rc == CS_OK)
		rc = plan(o, st.n, &first, &last);
	if (rc == CS_OK)
		rc = check_frames(o, first, last, &count);
	if (rc == CS_OK && count > 0)
		rc = cs_cr_session_load(s, o, r);
	if (rc == CS_OK)
		rc = run_frames(s, o, &st, first, last, count, r);
	cs_cr_session_close(s, r);
	if (st.from_file)
		cs_wx_series_free(&st.series);
	return rc;
}
