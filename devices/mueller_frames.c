/* Mueller imaging of frame sequences from recordings, files and sources
 * (polarcam/mueller_frames.h). */
#include "polarcam/mueller_frames.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/states.h"

/* Frame j into an owned view (or a view of the source's buffer, released by done). */
typedef int (*frame_fn)(void *ctx, size_t j, pc_view *v);
typedef void (*done_fn)(void *ctx, pc_view *v);

/* The states and the mosaic of a request: st from states_path unless given; layout: the
 * request's, the states file's, the frames' own (fallback, may be NULL), else IMX250MZR. */
static int setup(const pc_mueller_request *rq, const pc_sim_states *given,
                 const pc_mosaic *fallback, pc_sim_states *st, pc_mosaic *m, pc_mueller_used *u)
{
	char layout[64] = "";
	int rc = 0;
	if (given)
		*st = *given;
	else if (!rq->states_path)
		return pc_error(PC_EINVAL, "--states FILE is required with frame files");
	else if ((rc = pc_states_read(rq->states_path, st, layout, sizeof layout)))
		return rc;
	const char *lay = rq->layout ? rq->layout : *layout ? layout : NULL;
	if (lay) {
		if ((rc = pc_mosaic_parse(lay, m)))
			return pc_error_prefix(rc, "layout: ");
	} else {
		*m = fallback ? *fallback : pc_mosaic_imx250mzr();
	}
	pc_mosaic_format(m, u->layout, sizeof u->layout);
	return 0;
}

/* The frames-given check (as many frames as one cycle of the states at least), then the run. */
static int run(const pc_sim_states *st, const pc_mosaic *m, const pc_mueller_request *rq,
               double black, size_t given, const char *what, frame_fn get, done_fn done, void *ctx,
               pc_mueller_result *res, pc_mueller_used *u)
{
	memset(res, 0, sizeof *res);
	const size_t nframes = (size_t)st->n_psg * st->n_psa;
	u->black_level = black;
	u->frames_given = given;
	u->frames_used = nframes;
	if (given < nframes)
		return pc_error(PC_EINVAL,
		                "%s describes %zu frames (%u PSG x %u PSA states) but %zu "
		                "frame%s given",
		                what, nframes, st->n_psg, st->n_psa, given,
		                given == 1 ? " was" : "s were");
	pc_mueller_system sys;
	int rc = pc_mueller_system_init(&sys, st->n_psg, st->psg, st->n_psa, st->psa, st->analyser);
	if (rc)
		return rc;
	pc_mueller_run_opts o = rq->run;
	o.black_level = black;
	pc_mueller_run *r = NULL;
	if ((rc = pc_mueller_run_new(&sys, m, &o, &r)))
		return rc;
	for (size_t j = 0; j < nframes && !rc; j++) {
		pc_view v = {0};
		if ((rc = get(ctx, j, &v)))
			break;
		rc = pc_mueller_run_add(r, (unsigned)j, &v);
		done(ctx, &v);
		if (!rc && pc_progress_report(&rq->progress, "mueller", j + 1, nframes))
			rc = pc_error(PC_ECANCELED,
			              "Mueller imaging: stopped after %zu of %zu frames", j + 1,
			              nframes);
	}
	if (!rc)
		rc = pc_mueller_run_finish(r, res);
	pc_mueller_run_free(r);
	return rc;
}

static void view_free(void *ctx, pc_view *v)
{
	(void)ctx;
	pc_view_free(v);
}

static int recording_frame(void *ctx, size_t j, pc_view *v)
{
	return pc_recording_read(ctx, j, v);
}

int pc_mueller_from_recording(const char *dir, const pc_mueller_request *rq, pc_mueller_result *res,
                              pc_mueller_used *used)
{
	memset(res, 0, sizeof *res);
	pc_mueller_used u;
	memset(&u, 0, sizeof u);
	pc_recording *r = NULL;
	int rc = pc_recording_open(&r, dir);
	if (rc)
		return pc_error_prefix(rc, "%s: ", dir);
	char states[4096];
	pc_mueller_request q = *rq;
	if (!q.states_path) {
		if ((size_t)snprintf(states, sizeof states, "%s/states.json", dir) >=
		    sizeof states) {
			pc_recording_free(r);
			return pc_error(PC_EINVAL, "%s: path too long", dir);
		}
		if (access(states, F_OK) != 0) {
			pc_recording_free(r);
			return pc_error(PC_ENOENT,
			                "%s: no states.json: the frames were not recorded "
			                "under a sequence of polarization states (render writes "
			                "it for scenes with \"states\"); give them with --states "
			                "FILE",
			                dir);
		}
		q.states_path = states;
	}
	pc_sim_states st;
	pc_mosaic m;
	rc = setup(&q, NULL, NULL, &st, &m, &u);
	if (!rc) {
		double black =
		    isnan(rq->run.black_level) ? pc_recording_black_level(r) : rq->run.black_level;
		rc = run(&st, &m, &q, black, pc_recording_count(r), q.states_path, recording_frame,
		         view_free, r, res, &u);
	}
	pc_recording_free(r);
	if (used)
		*used = u;
	return rc;
}

static int file_frame(void *ctx, size_t j, pc_view *v)
{
	const char *const *files = ctx;
	return pc_image_read_mosaic(files[j], NULL, 0, v, NULL);
}

int pc_mueller_from_files(const char *const *files, size_t n, const pc_mueller_request *rq,
                          pc_mueller_result *res, pc_mueller_used *used)
{
	memset(res, 0, sizeof *res);
	pc_mueller_used u;
	memset(&u, 0, sizeof u);
	pc_sim_states st;
	pc_mosaic m;
	int rc = setup(rq, NULL, NULL, &st, &m, &u);
	if (!rc) {
		double black = isnan(rq->run.black_level) ? 0 : rq->run.black_level;
		rc = run(&st, &m, rq, black, n, rq->states_path, file_frame, view_free,
		         (void *)files, res, &u);
	}
	if (used)
		*used = u;
	return rc;
}

typedef struct source_ctx {
	pc_source *src;
	int timeout_ms;
	pc_buffer *buf;
	uint64_t first_seq;
} source_ctx;

static int source_frame(void *ctx, size_t j, pc_view *v)
{
	source_ctx *c = ctx;
	int rc = pc_source_dequeue(c->src, c->timeout_ms, &c->buf);
	if (rc)
		return pc_error_prefix(rc, "frame %zu: ", j);
	if (j == 0)
		c->first_seq = c->buf->frame.meta.sequence;
	if (c->buf->frame.meta.sequence != c->first_seq + j) {
		rc = pc_error(PC_EIO,
		              "frame %zu has sequence %llu, %llu expected: a frame was lost "
		              "and the states' order is broken",
		              j, (unsigned long long)c->buf->frame.meta.sequence,
		              (unsigned long long)(c->first_seq + j));
		pc_source_requeue(c->src, c->buf);
		c->buf = NULL;
		return rc;
	}
	*v = c->buf->frame.view;
	return 0;
}

static void source_done(void *ctx, pc_view *v)
{
	source_ctx *c = ctx;
	(void)v;
	if (c->buf)
		pc_source_requeue(c->src, c->buf);
	c->buf = NULL;
}

int pc_mueller_from_source(pc_source *src, const pc_sim_states *st, int timeout_ms,
                           const pc_mueller_request *rq, pc_mueller_result *res,
                           pc_mueller_used *used)
{
	memset(res, 0, sizeof *res);
	pc_mueller_used u;
	memset(&u, 0, sizeof u);
	if (!src || !st)
		return pc_error(PC_EINVAL, "Mueller imaging: source or states missing");
	pc_source_format f;
	int rc = pc_source_get_format(src, &f);
	if (!rc && !f.polarized)
		rc = pc_error(PC_EFORMAT, "the source's frames carry no polarizer mosaic");
	pc_sim_states s;
	pc_mosaic m;
	if (!rc)
		rc = setup(rq, st, &f.mosaic, &s, &m, &u);
	if (!rc) {
		source_ctx c = {src, timeout_ms, NULL, 0};
		double black = isnan(rq->run.black_level) ? 0 : rq->run.black_level;
		size_t n = (size_t)s.n_psg * s.n_psa;
		rc =
		    run(&s, &m, rq, black, n, "the states", source_frame, source_done, &c, res, &u);
	}
	if (used)
		*used = u;
	return rc;
}
