/* A source recorded, optionally through the Stokes stream (polarcam/capture.h).
 *
 *   calling thread:  dequeue ─► policy for damaged frames ─► copy into the queue ─► requeue
 *                                                                  │ (frame_queue.h)
 *   writer thread:                         pc_recording_add (─► Stokes) ◄──┘
 */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/capture.h"

#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "black_watch.h"
#include "frame_queue.h"
#include "json.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/process.h"
#include "polarcam/recording.h"

#define GIB (1024.0 * 1024.0 * 1024.0)

typedef struct capture {
	const pc_capture_opts *o;
	pc_source *src;
	pc_source_format f;
	pc_outdir od; /* the recording is made in od.tmp and put in place at the end */
	pc_recording *rec;
	pc_stokes_stream *live;
	const char *method; /* name, with process */
	double black;       /* DN: given, or what the source declares; 0: unknown */
	black_watch bw;     /* none given or declared at the start: ask after the first frames */
	double seconds, proc_sum, proc_max;
	uint64_t kept;  /* frames whose Stokes images were written (writer thread) */
	bool last_kept; /* the last processed frame's were */
	pc_capture_report *rep;
	frame_queue q;
	bool q_ready;
	pthread_mutex_t lock; /* rep->error / message, werr */
	int werr;             /* the writer's failure: acquisition stops */
	uint64_t proc_n;      /* frames processed (writer thread) */
} capture;

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char *const policy_names[] = {"skip", "keep", "fail"};

const char *pc_incomplete_policy_name(pc_incomplete_policy p)
{
	return (unsigned)p < 3 ? policy_names[p] : NULL;
}

/* meta.json's extra: the sensor's black level when known, the process report */
static void set_extra(capture *c, json_t *process)
{
	json_t *extra = json_object();
	if (c->black > 0)
		json_object_set_new(extra, "sensor", json_pack("{s:f}", "offset_dn", c->black));
	if (process)
		json_object_set(extra, "process", process);
	char *t = json_object_size(extra) ? pc_json_text(extra) : NULL;
	if (t)
		pc_recording_set_json(c->rec, "extra", t);
	free(t);
	json_decref(extra);
}

int pc_incomplete_policy_from_name(const char *name, pc_incomplete_policy *out)
{
	for (unsigned i = 0; name && i < 3; i++)
		if (!strcmp(name, policy_names[i])) {
			*out = (pc_incomplete_policy)i;
			return 0;
		}
	return pc_error(PC_EINVAL, "incomplete frames '%s': expected skip, keep or fail",
	                name ? name : "");
}

/* The first reason the recording ended; later ones are dropped. Either thread. */
static void fail(capture *c, int code, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void fail(capture *c, int code, const char *fmt, ...)
{
	pthread_mutex_lock(&c->lock);
	if (!c->rep->error) {
		c->rep->error = code;
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(c->rep->message, sizeof c->rep->message, fmt, ap);
		va_end(ap);
	}
	pthread_mutex_unlock(&c->lock);
}

static int failed(capture *c)
{
	pthread_mutex_lock(&c->lock);
	int e = c->rep->error;
	pthread_mutex_unlock(&c->lock);
	return e;
}

/* Half the available memory, at most 4 GiB. */
static uint64_t default_queue_bytes(void)
{
	long pages = sysconf(_SC_AVPHYS_PAGES), size = sysconf(_SC_PAGESIZE);
	double avail = pages > 0 && size > 0 ? (double)pages * (double)size : GIB;
	double b = avail / 2;
	return (uint64_t)(b < 4 * GIB ? b : 4 * GIB);
}

/* The source, the method, the recording and the queue: nothing recorded when one of them is
 * refused. */
static int open_all(capture *c)
{
	const pc_capture_opts *o = c->o;
	pc_demosaic_method m = PC_DM_BILINEAR;
	int rc = o->method ? pc_demosaic_method_from_name(o->method, &m) : 0;
	if (rc) /* a misspelt name is refused before the camera is opened */
		return pc_error_prefix(rc, "--method: ");
	if (!pc_incomplete_policy_name(o->incomplete) || !pc_recording_store_name(o->store))
		return pc_error(PC_EINVAL, "capture: incomplete policy %d / store %d unknown",
		                (int)o->incomplete, (int)o->store);
	if (!(o->write_delay_ms >= 0 && o->write_delay_ms <= 3.6e6))
		return pc_error(PC_EINVAL, "capture: write delay %g ms: expected 0..3600000",
		                o->write_delay_ms);
	/* so is an occupied output folder */
	if ((rc = pc_outdir_begin(&c->od, o->dir, o->overwrite ? PC_OUT_OVERWRITE : 0)))
		return rc;
	if ((rc = pc_stream_open(&o->stream, &c->src)))
		return pc_error_prefix(rc, "opening the source: ");
	pc_source_get_format(c->src, &c->f);
	if (o->process && c->f.polarized) {
		/* a method for the other kind of mosaic is refused before anything is recorded */
		if ((rc = pc_process_method(o->method, &c->f.mosaic, &m)))
			return rc;
		c->method = pc_demosaic_method_get(m)->name;
	}
	if (!o->process && o->levels.calibration)
		return pc_error(PC_EINVAL,
		                "--calibration applies to --process (the recording keeps "
		                "the raw frames)");
	if (o->process && ((rc = pc_stokes_stream_new(m, &c->live)) ||
	                   (rc = pc_stokes_stream_set_levels(c->live, &o->levels, c->src))))
		return rc;
	/* the black level, for whoever processes the recording later */
	/* only a source that declares its level with its frames is asked again (and warned of) */
	c->black = black_watch_start(&c->bw, c->src, o->levels.black_level, true);
	size_t row = 0;
	(void)pc_format_row_bytes(c->f.format, c->f.width, &row);
	size_t frame_bytes = c->f.height ? c->f.stride * (c->f.height - 1) + row : row;
	if ((rc = fq_init(&c->q, frame_bytes,
	                  o->queue_bytes ? o->queue_bytes : default_queue_bytes())))
		return rc;
	c->q_ready = true;
	pc_recording_desc d;
	memset(&d, 0, sizeof d);
	d.source = o->stream.uri;
	d.format = c->f.format;
	d.device_format = c->f.format_name;
	d.width = c->f.width;
	d.height = c->f.height;
	d.offset_x = c->f.offset_x;
	d.offset_y = c->f.offset_y;
	d.sensor_width = c->f.sensor_width;
	d.sensor_height = c->f.sensor_height;
	d.polarized = c->f.polarized;
	d.mosaic = c->f.mosaic;
	d.store = o->store;
	if ((rc = pc_recording_create(&c->rec, c->od.tmp, &d, false)))
		return pc_error_prefix(rc, "creating the recording: ");
	set_extra(c, NULL);
	return 0;
}

/* Files of processed frame number n in DIR/processed/ (writer thread, or after it ended). */
static int keep(capture *c, uint64_t n, unsigned files)
{
	uint32_t w, h;
	const pc_stokes_out *so = pc_stokes_stream_planes(c->live, &w, &h);
	char pdir[4200];
	snprintf(pdir, sizeof pdir, "%s/processed", c->od.tmp);
	pc_stokes_folder_opts fo = {
	    .files = files, .pictures = {.title_prefix = "capture"}, .numbered = true, .number = n};
	int rc =
	    pc_stokes_folder_write_valid(pdir, so, w, h, &fo, pc_stokes_stream_validity(c->live));
	if (!rc && (files & PC_SF_DOLP)) {
		c->kept++;
		c->last_kept = true;
	}
	return rc;
}

/* ---- the writer thread ---- */

static void *writer_main(void *arg)
{
	capture *c = arg;
	const pc_capture_opts *o = c->o;
	fq_item *it;
	while ((it = fq_pop(&c->q))) {
		pthread_mutex_lock(&c->lock);
		int werr = c->werr;
		pthread_mutex_unlock(&c->lock);
		if (werr) { /* after a failed write nothing more is written */
			fq_done(&c->q, it, false, 0);
			continue;
		}
		double t0 = now_s();
		int rc = pc_recording_add(c->rec, &it->frame);
		if (!rc && o->process) {
			pc_stokes_stream_take_black(c->live, it->black_dn);
			rc = pc_stokes_stream_process(c->live, &it->frame);
			double s = pc_stokes_stream_seconds(c->live);
			c->proc_sum += s;
			c->proc_n++;
			if (s > c->proc_max)
				c->proc_max = s;
			c->last_kept = false;
			uint64_t pos = pc_recording_count(c->rec) - 1; /* this frame's position */
			if (!rc && o->keep_every && pos % o->keep_every == 0)
				rc = keep(c, pos, PC_SF_S0 | PC_SF_DOLP | PC_SF_AOLP);
		}
		if (!rc && o->write_delay_ms > 0) {
			double d = o->write_delay_ms / 1e3;
			struct timespec ts = {(time_t)d, (long)((d - (double)(time_t)d) * 1e9)};
			while (nanosleep(&ts, &ts) != 0)
				;
		}
		if (rc) {
			fail(c, rc, "%s frame %llu (sequence %llu): %s",
			     o->process ? "writing or processing" : "writing",
			     (unsigned long long)pc_recording_count(c->rec),
			     (unsigned long long)it->frame.meta.sequence, pc_error_detail());
			pthread_mutex_lock(&c->lock);
			c->werr = rc;
			pthread_mutex_unlock(&c->lock);
		}
		fq_done(&c->q, it, rc == 0, now_s() - t0);
	}
	return NULL;
}

/* ---- acquisition (the calling thread) ---- */

typedef struct acq {
	uint64_t acquired, n, skipped, kept;
	double fallback_period_s;
} acq;

/* One damaged frame by the policy: 0 to record it, 1 to take the next, -1 to stop. */
static int damaged(capture *c, acq *a, const pc_frame *fr)
{
	const char *what = fr->meta.status & PC_FRAME_CORRUPT ? "corrupt" : "incomplete";
	switch (c->o->incomplete) {
	case PC_INCOMPLETE_KEEP:
		return 0; /* counted once it is in the queue */
	case PC_INCOMPLETE_FAIL:
		fail(c, PC_EIO,
		     "frame %llu (sequence %llu) arrived %s (lost packets) and incomplete frames "
		     "end the capture (policy fail)",
		     (unsigned long long)a->acquired, (unsigned long long)fr->meta.sequence, what);
		return -1;
	default:
		a->skipped++;
		if (a->skipped > a->n + 10) {
			fail(c, PC_EIO,
			     "%llu damaged frames skipped for %llu recorded of %llu: the source "
			     "delivers too few whole frames",
			     (unsigned long long)a->skipped, (unsigned long long)a->acquired,
			     (unsigned long long)a->n);
			return -1;
		}
		return 1;
	}
}

/* Dequeue, and unless the source failed, hand the frame to the queue. 1: go on, 0: stop. */
static int acquire_one(capture *c, acq *a)
{
	const pc_capture_opts *o = c->o;
	pc_buffer *b = NULL;
	int rc = pc_source_dequeue(c->src, o->timeout_ms, &b);
	unsigned long long got = a->acquired, n = a->n;
	if (rc == PC_EDISCONNECTED)
		fail(c, rc, "the camera disappeared after %llu of %llu frames: %s", got, n,
		     pc_error_detail());
	else if (rc == PC_ETIMEDOUT)
		fail(c, rc, "no frame within %d ms after %llu of %llu frames: %s", o->timeout_ms,
		     got, n, pc_error_detail());
	else if (rc == PC_EEND)
		fail(c, rc, "the source ended after %llu of %llu frames", got, n);
	else if (rc)
		fail(c, rc, "frame %llu: %s", got, pc_error_detail());
	if (rc)
		return 0;
	fq_arrival(&c->q, now_s());
	/* a level the source declares only once frames flow (libcamera), asked here, on the
	 * thread that dequeues, and handed to the writer with the frame, which processes it and
	 * the later ones with that level */
	if (black_watch_frame(&c->bw, c->src))
		c->black = c->bw.level;
	int take = 0;
	const bool bad = b->frame.meta.status & (PC_FRAME_INCOMPLETE | PC_FRAME_CORRUPT);
	if (bad)
		take = damaged(c, a, &b->frame);
	int pushed = take == 0 ? fq_push(&c->q, &b->frame, c->black) : 1;
	if (pushed < 0) /* the slot could not be made: lost like a full queue */
		pc_error_clear();
	int rc2 = pc_source_requeue(c->src, b);
	if (rc2) {
		fail(c, rc2, "requeueing frame %llu: %s", got, pc_error_detail());
		return 0;
	}
	if (take < 0)
		return 0;
	if (take == 0 && pushed == 0) {
		a->acquired++;
		a->kept += bad;
	}
	fq_plan(&c->q, a->n - a->acquired, a->fallback_period_s);
	return 1;
}

/* Dequeue → queue → requeue until the frames are in or something ends it; then the writer
 * finishes the queue. */
static void record(capture *c)
{
	const pc_capture_opts *o = c->o;
	acq a = {0, o->frames, 0, 0, 0};
	double fps = 0;
	if (pc_source_control_get(c->src, PC_CTRL_FRAME_RATE_HZ, &fps) == 0 && fps > 0)
		a.fallback_period_s = 1 / fps;
	pc_error_clear();
	int src = pc_source_start(c->src);
	if (src)
		fail(c, src, "starting the stream: %s", pc_error_detail());
	if (o->process && !c->f.polarized)
		fail(c, PC_EFORMAT, "--process: the source's frames carry no polarizer mosaic");
	pthread_t writer;
	bool have_writer = false;
	if (!failed(c)) {
		if (pthread_create(&writer, NULL, writer_main, c) == 0)
			have_writer = true;
		else
			fail(c, PC_ENOMEM, "cannot start the writer thread");
	}
	double t0 = now_s();
	int stop = 0;
	while (!failed(c) && a.acquired < a.n) {
		if (stop) {
			fail(c, PC_ECANCELED, "interrupted after %llu of %llu frames",
			     (unsigned long long)a.acquired, (unsigned long long)a.n);
			break;
		}
		if (!acquire_one(c, &a))
			break;
		stop = pc_progress_report(&o->progress, "capture", a.acquired, a.n);
	}
	/* the camera stops sending now; what was acquired is written */
	pc_source_state s = pc_source_get_state(c->src);
	if (s == PC_SOURCE_STREAMING || s == PC_SOURCE_FAILED)
		pc_source_stop(c->src);
	fq_close(&c->q);
	fq_stats qs;
	while (have_writer && fq_pending(&c->q) > 0) {
		fq_get_stats(&c->q, &qs);
		pc_progress_report(&o->progress, "writing", qs.written, qs.pushed);
		fq_wait(&c->q, 100);
	}
	if (have_writer)
		pthread_join(writer, NULL);
	c->seconds = now_s() - t0;
	fq_get_stats(&c->q, &qs);
	c->rep->frames = pc_recording_count(c->rec);
	c->rep->skipped = a.skipped;
	c->rep->kept = a.kept;
	c->rep->lost = qs.lost;
	/* the recording is not complete when frames were lost or kept damaged */
	if (qs.lost)
		fail(c, PC_EOVERFLOW,
		     "the writer fell behind: %llu frames lost with the queue full at %zu frames "
		     "(%.0f MB; %.1f ms per frame written, one every %.1f ms arriving)",
		     (unsigned long long)qs.lost, qs.capacity,
		     (double)qs.capacity * (double)qs.frame_bytes / 1e6, 1e3 * qs.write_mean_s,
		     1e3 * qs.period_s);
	if (a.kept)
		fail(c, PC_EIO,
		     "%llu of the %llu frames recorded arrived incomplete (kept: policy keep)",
		     (unsigned long long)a.kept, (unsigned long long)c->rep->frames);
}

/* The last frame's Stokes images and pictures in DIR/processed/, and the "process" report. */
static json_t *processed(capture *c)
{
	uint32_t w, h;
	const pc_stokes_out *so = pc_stokes_stream_planes(c->live, &w, &h);
	uint64_t got = c->proc_n;
	if (!so || got == 0)
		return NULL;
	unsigned files = PC_SF_PICTURES | (c->last_kept ? 0 : PC_SF_S0 | PC_SF_DOLP | PC_SF_AOLP);
	int rc = keep(c, pc_recording_count(c->rec) - 1, files);
	if (rc)
		fail(c, rc, "writing the processed frames: %s", pc_error_detail());
	const pc_validity *valid = pc_stokes_stream_validity(c->live);
	/* the mean DoLP of the valid pixels: invalid ones depend on saturated samples */
	double sum = 0, nv = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		if (!valid->mask || valid->mask[i]) {
			sum += so->dolp.data[i];
			nv++;
		}
	double black, sat;
	const char *calib;
	pc_stokes_stream_levels_used(c->live, &black, &sat, &calib);
	json_t *pj = json_object();
	json_object_set_new(pj, "black_level", pc_json_real(black));
	json_object_set_new(pj, "saturation_level", sat > 0 ? pc_json_real(sat) : json_null());
	json_object_set_new(pj, "calibration", calib ? json_string(calib) : json_null());
	/* a noise-aware method's noise gain for the last frame, and whence */
	const char *ng_from = NULL;
	const double ng = pc_stokes_stream_noise_gain(c->live, &ng_from);
	json_object_set_new(pj, "noise_gain", ng_from ? pc_json_real(ng) : json_null());
	json_object_set_new(pj, "noise_gain_from", ng_from ? json_string(ng_from) : json_null());
	double fdb, cdb, ddb;
	pc_stokes_stream_gains(c->live, &fdb, &cdb, &ddb);
	json_object_set_new(pj, "gain_db", pc_json_real(fdb));
	json_object_set_new(pj, "calibration_gain_db", pc_json_real(cdb));
	json_object_set_new(pj, "dark_gain_db", pc_json_real(ddb));
	json_object_set_new(pj, "last_invalid_pixels", json_integer((json_int_t)valid->n_invalid));
	json_object_set_new(pj, "method", json_string(c->method));
	json_object_set_new(pj, "frames", json_integer((json_int_t)got));
	json_object_set_new(pj, "kept", json_integer((json_int_t)c->kept));
	json_object_set_new(pj, "keep_every", json_integer((json_int_t)c->o->keep_every));
	json_object_set_new(pj, "mean_ms", pc_json_real(1e3 * c->proc_sum / (double)got));
	json_object_set_new(pj, "max_ms", pc_json_real(1e3 * c->proc_max));
	json_object_set_new(pj, "last_mean_dolp", nv > 0 ? pc_json_real(sum / nv) : json_null());
	json_object_set_new(pj, "width", json_integer(w));
	json_object_set_new(pj, "height", json_integer(h));
	return pj;
}

/* {policy, skipped, kept} and the queue's figures */
static json_t *incomplete_json(const capture *c)
{
	json_t *j = json_object();
	json_object_set_new(j, "policy", json_string(pc_incomplete_policy_name(c->o->incomplete)));
	json_object_set_new(j, "skipped", json_integer((json_int_t)c->rep->skipped));
	json_object_set_new(j, "kept", json_integer((json_int_t)c->rep->kept));
	return j;
}

static json_t *queue_json(capture *c)
{
	fq_stats q;
	fq_get_stats(&c->q, &q);
	json_t *j = json_object();
	json_object_set_new(j, "frame_bytes", json_integer((json_int_t)q.frame_bytes));
	json_object_set_new(j, "limit", json_integer((json_int_t)q.limit));
	json_object_set_new(j, "capacity", json_integer((json_int_t)q.capacity));
	json_object_set_new(j, "needed_max", json_integer((json_int_t)q.needed_max));
	json_object_set_new(j, "peak", json_integer((json_int_t)q.peak));
	json_object_set_new(j, "lost", json_integer((json_int_t)q.lost));
	json_object_set_new(j, "written", json_integer((json_int_t)q.written));
	json_object_set_new(j, "write_ms_mean", pc_json_real(1e3 * q.write_mean_s));
	json_object_set_new(j, "write_ms_max", pc_json_real(1e3 * q.write_max_s));
	json_object_set_new(j, "period_ms",
	                    q.period_s > 0 ? pc_json_real(1e3 * q.period_s) : json_null());
	return j;
}

/* Statistics into meta.json, the recording finished, the report. */
static void finish(capture *c, json_t *pj)
{
	const pc_capture_opts *o = c->o;
	pc_source_stats st;
	pc_source_get_stats(c->src, &st);
	char *stats = pc_source_stats_json(&st), *fmt = pc_source_format_json(&c->f);
	if (stats)
		pc_recording_set_json(c->rec, "stats", stats);
	json_t *inc = incomplete_json(c), *qj = queue_json(c);
	json_t *extra = json_object();
	if (c->black > 0) /* the black level, for whoever processes the recording later */
		json_object_set_new(extra, "sensor", json_pack("{s:f}", "offset_dn", c->black));
	json_t *cj = json_object();
	json_object_set(cj, "incomplete", inc);
	json_object_set(cj, "queue", qj);
	json_object_set_new(cj, "seconds", pc_json_real(c->seconds));
	json_object_set_new(extra, "capture", cj);
	if (pj)
		json_object_set(extra, "process", pj);
	char *t = pc_json_text(extra);
	if (t)
		pc_recording_set_json(c->rec, "extra", t);
	free(t);
	json_decref(extra);
	int rc = pc_recording_finish(c->rec, c->rep->error ? c->rep->message : NULL);
	if (rc)
		fail(c, rc, "writing meta.json: %s", pc_error_detail());
	c->rep->complete = !c->rep->error && pc_recording_is_complete(c->rec);
	const uint64_t got = c->rep->frames;
	const double dt = c->seconds;
	json_t *j = json_object();
	json_object_set_new(j, "source", json_string(o->stream.uri));
	json_object_set_new(j, "dir", json_string(o->dir));
	json_object_set_new(j, "store", json_string(pc_recording_store_name(o->store)));
	json_object_set_new(j, "frames", json_integer((json_int_t)got));
	json_object_set_new(j, "requested", json_integer((json_int_t)o->frames));
	json_object_set_new(j, "complete", json_boolean(c->rep->complete));
	json_object_set_new(j, "seconds", pc_json_real(dt));
	json_object_set_new(j, "fps", pc_json_real(dt > 0 ? (double)got / dt : 0));
	json_object_set_new(j, "format", fmt ? json_loads(fmt, 0, NULL) : json_null());
	json_object_set_new(j, "stats", stats ? json_loads(stats, 0, NULL) : json_null());
	json_object_set_new(j, "incomplete", inc);
	json_object_set_new(j, "queue", qj);
	if (pj)
		json_object_set(j, "process", pj);
	json_t *warn = json_array();
	if (black_watch_missed(&c->bw)) {
		snprintf(
		    c->rep->warning, sizeof c->rep->warning,
		    "no black level given and the source declared none in the first %u frames: "
		    "0 DN used%s (give --black-level)",
		    c->bw.frames, o->process ? "" : ", none recorded");
		json_array_append_new(warn, json_string(c->rep->warning));
	}
	json_object_set_new(j, "warnings", warn);
	json_object_set_new(j, "error", c->rep->error ? json_string(c->rep->message) : json_null());
	c->rep->json = pc_json_text(j);
	json_decref(j);
	free(stats);
	free(fmt);
}

int pc_capture(const pc_capture_opts *o, pc_capture_report *rep)
{
	memset(rep, 0, sizeof *rep);
	capture c;
	memset(&c, 0, sizeof c);
	c.o = o;
	c.rep = rep;
	pthread_mutex_init(&c.lock, NULL);
	int rc = open_all(&c);
	if (!rc) {
		record(&c);
		json_t *pj = o->process ? processed(&c) : NULL;
		finish(&c, pj);
		json_decref(pj);
	}
	pc_recording_free(c.rec);
	pc_stokes_stream_free(c.live);
	pc_source_close(c.src);
	if (c.q_ready)
		fq_destroy(&c.q);
	pthread_mutex_destroy(&c.lock);
	/* Frames from a camera cannot be made again: a recording that ended early is kept (and
	 * replaces an older one) once it holds a frame. With none, nothing is put in place. */
	if (!rc && rep->frames == 0) {
		rc = pc_error(rep->error ? rep->error : PC_EIO, "%s: no frame recorded: %s", o->dir,
		              rep->message);
		pc_capture_report_free(rep);
	}
	if (!rc && (rc = pc_outdir_commit(&c.od)))
		pc_capture_report_free(rep);
	if (rc)
		pc_outdir_abort(&c.od);
	return rc;
}

void pc_capture_report_free(pc_capture_report *rep)
{
	free(rep->json);
	rep->json = NULL;
}
