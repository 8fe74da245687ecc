/* A source recorded, optionally through the Stokes stream (polarcam/capture.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/capture.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/process.h"
#include "polarcam/recording.h"

typedef struct capture {
	const pc_capture_opts *o;
	pc_source *src;
	pc_source_format f;
	pc_outdir od; /* the recording is made in od.tmp and put in place at the end */
	pc_recording *rec;
	pc_stokes_stream *live;
	const char *method; /* name, with process */
	double seconds, proc_sum, proc_max;
	uint64_t kept;      /* frames whose Stokes images were written */
	bool last_kept;     /* the last processed frame's were */
	pc_capture_report *rep;
} capture;

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The first reason the recording ended; later ones are dropped. */
static void fail(capture *c, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
static void fail(capture *c, int code, const char *fmt, ...)
{
	if (c->rep->error)
		return;
	c->rep->error = code;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(c->rep->message, sizeof c->rep->message, fmt, ap);
	va_end(ap);
}

/* The source, the method and the recording: nothing recorded when one of them is refused. */
static int open_all(capture *c)
{
	const pc_capture_opts *o = c->o;
	pc_demosaic_method m = PC_DM_BILINEAR;
	int rc = o->method ? pc_demosaic_method_from_name(o->method, &m) : 0;
	if (rc) /* a misspelt name is refused before the camera is opened */
		return pc_error_prefix(rc, "--method: ");
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
	if (o->process && (rc = pc_stokes_stream_new(m, &c->live)))
		return rc;
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
	if ((rc = pc_recording_create(&c->rec, c->od.tmp, &d, false)))
		return pc_error_prefix(rc, "creating the recording: ");
	return 0;
}

/* Files of the last processed frame (number n) in DIR/processed/. */
static int keep(capture *c, uint64_t n, unsigned files)
{
	uint32_t w, h;
	const pc_stokes_out *so = pc_stokes_stream_planes(c->live, &w, &h);
	char pdir[4200];
	snprintf(pdir, sizeof pdir, "%s/processed", c->od.tmp);
	pc_stokes_folder_opts fo = { .files = files,
				     .pictures = { .title_prefix = "capture" },
				     .numbered = true,
				     .number = n };
	int rc = pc_stokes_folder_write(pdir, so, w, h, &fo);
	if (!rc && (files & PC_SF_DOLP)) {
		c->kept++;
		c->last_kept = true;
	}
	return rc;
}

/* Dequeue → record (→ Stokes) → requeue, until the frames are in or something ends it. */
static void record(capture *c)
{
	const pc_capture_opts *o = c->o;
	uint64_t got = 0, n = o->frames;
	int stop = 0;
	int src = pc_source_start(c->src);
	if (src)
		fail(c, src, "starting the stream: %s", pc_error_detail());
	double t0 = now_s();
	if (o->process && !c->f.polarized)
		fail(c, PC_EFORMAT, "--process: the source's frames carry no polarizer mosaic");
	while (!c->rep->error && got < n) {
		if (stop) {
			fail(c, PC_ECANCELED, "interrupted after %llu of %llu frames",
			     (unsigned long long)got, (unsigned long long)n);
			break;
		}
		pc_buffer *b = NULL;
		int rc = pc_source_dequeue(c->src, o->timeout_ms, &b);
		if (rc == PC_EDISCONNECTED)
			fail(c, rc, "the camera disappeared after %llu of %llu frames: %s",
			     (unsigned long long)got, (unsigned long long)n, pc_error_detail());
		else if (rc == PC_ETIMEDOUT)
			fail(c, rc, "no frame within %d ms after %llu of %llu frames: %s",
			     o->timeout_ms, (unsigned long long)got, (unsigned long long)n,
			     pc_error_detail());
		else if (rc == PC_EEND)
			fail(c, rc, "the source ended after %llu of %llu frames",
			     (unsigned long long)got, (unsigned long long)n);
		else if (rc)
			fail(c, rc, "frame %llu: %s", (unsigned long long)got, pc_error_detail());
		if (rc)
			break;
		rc = pc_recording_add(c->rec, &b->frame);
		if (!rc && o->process) {
			rc = pc_stokes_stream_process(c->live, &b->frame);
			double s = pc_stokes_stream_seconds(c->live);
			c->proc_sum += s;
			if (s > c->proc_max)
				c->proc_max = s;
			c->last_kept = false;
			if (!rc && o->keep_every && got % o->keep_every == 0)
				rc = keep(c, got, PC_SF_S0 | PC_SF_DOLP | PC_SF_AOLP);
		}
		int rc2 = pc_source_requeue(c->src, b);
		if (rc || rc2) {
			fail(c, rc ? rc : rc2, "%s frame %llu: %s", rc ? "writing" : "requeueing",
			     (unsigned long long)got, pc_error_detail());
			break;
		}
		got++;
		stop = pc_progress_report(&o->progress, "capture", got, n);
	}
	c->seconds = now_s() - t0;
	c->rep->frames = got;
}

/* The last frame's Stokes images (when not kept already) and pictures in DIR/processed/, and
 * the "process" report. */
static json_t *processed(capture *c)
{
	uint32_t w, h;
	const pc_stokes_out *so = pc_stokes_stream_planes(c->live, &w, &h);
	uint64_t got = c->rep->frames;
	if (!so || got == 0)
		return NULL;
	unsigned files = PC_SF_PICTURES | (c->last_kept ? 0 : PC_SF_S0 | PC_SF_DOLP | PC_SF_AOLP);
	int rc = keep(c, got - 1, files);
	if (rc)
		fail(c, rc, "writing the processed frames: %s", pc_error_detail());
	double sum = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		sum += so->dolp.data[i];
	json_t *pj = json_object();
	json_object_set_new(pj, "method", json_string(c->method));
	json_object_set_new(pj, "frames", json_integer((json_int_t)got));
	json_object_set_new(pj, "kept", json_integer((json_int_t)c->kept));
	json_object_set_new(pj, "keep_every", json_integer((json_int_t)c->o->keep_every));
	json_object_set_new(pj, "mean_ms", pc_json_real(1e3 * c->proc_sum / (double)got));
	json_object_set_new(pj, "max_ms", pc_json_real(1e3 * c->proc_max));
	json_object_set_new(pj, "last_mean_dolp", pc_json_real(sum / ((double)w * h)));
	json_object_set_new(pj, "width", json_integer(w));
	json_object_set_new(pj, "height", json_integer(h));
	json_t *extra = json_object();
	json_object_set(extra, "process", pj);
	char *t = pc_json_text(extra);
	if (t)
		pc_recording_set_json(c->rec, "extra", t);
	free(t);
	json_decref(extra);
	return pj;
}

/* Statistics into meta.json, the recording finished, the report. */
static void finish(capture *c, json_t *pj)
{
	const pc_capture_opts *o = c->o;
	pc_source_state s = pc_source_get_state(c->src);
	if (s == PC_SOURCE_STREAMING || s == PC_SOURCE_FAILED)
		pc_source_stop(c->src);
	pc_source_stats st;
	pc_source_get_stats(c->src, &st);
	char *stats = pc_source_stats_json(&st), *fmt = pc_source_format_json(&c->f);
	if (stats)
		pc_recording_set_json(c->rec, "stats", stats);
	int rc = pc_recording_finish(c->rec, c->rep->error ? c->rep->message : NULL);
	if (rc)
		fail(c, rc, "writing meta.json: %s", pc_error_detail());
	const uint64_t got = c->rep->frames;
	const double dt = c->seconds;
	json_t *j = json_object();
	json_object_set_new(j, "source", json_string(o->stream.uri));
	json_object_set_new(j, "dir", json_string(o->dir));
	json_object_set_new(j, "frames", json_integer((json_int_t)got));
	json_object_set_new(j, "requested", json_integer((json_int_t)o->frames));
	json_object_set_new(j, "seconds", pc_json_real(dt));
	json_object_set_new(j, "fps", pc_json_real(dt > 0 ? (double)got / dt : 0));
	json_object_set_new(j, "format", fmt ? json_loads(fmt, 0, NULL) : json_null());
	json_object_set_new(j, "stats", stats ? json_loads(stats, 0, NULL) : json_null());
	if (pj)
		json_object_set(j, "process", pj);
	json_object_set_new(j, "error",
			    c->rep->error ? json_string(c->rep->message) : json_null());
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
