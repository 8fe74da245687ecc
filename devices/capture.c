/* A source recorded, optionally through the Stokes stream (polarcam/capture.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/capture.h"

#include <math.h>
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
	pc_recording *rec;
	pc_stokes_stream *live;
	const char *method; /* name, with process */
	double black;       /* DN: given, or what the source declares; 0: unknown */
	double seconds, proc_sum, proc_max;
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

/* The source, the method and the recording: nothing recorded when one of them is refused. */
static int open_all(capture *c)
{
	const pc_capture_opts *o = c->o;
	pc_demosaic_method m = PC_DM_BILINEAR;
	int rc = o->method ? pc_demosaic_method_from_name(o->method, &m) : 0;
	if (rc) /* a misspelt name is refused before the camera is opened */
		return pc_error_prefix(rc, "--method: ");
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
		return pc_error(PC_EINVAL, "--calibration applies to --process (the recording keeps "
					   "the raw frames)");
	if (o->process && ((rc = pc_stokes_stream_new(m, &c->live)) ||
			   (rc = pc_stokes_stream_set_levels(c->live, &o->levels, c->src))))
		return rc;
	/* the black level, for whoever processes the recording later */
	pc_source_info info;
	c->black = isnan(o->levels.black_level) ? 0 : o->levels.black_level;
	if (isnan(o->levels.black_level) && pc_source_get_info(c->src, &info) == 0)
		c->black = info.black_level;
	pc_error_clear();
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
	if ((rc = pc_recording_create(&c->rec, o->dir, &d, o->overwrite)))
		return pc_error_prefix(rc, "creating the recording: ");
	set_extra(c, NULL);
	return 0;
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

/* The last frame's Stokes images and pictures in DIR/processed/, and the "process" report. */
static json_t *processed(capture *c)
{
	uint32_t w, h;
	const pc_stokes_out *so = pc_stokes_stream_planes(c->live, &w, &h);
	uint64_t got = c->rep->frames;
	if (!so || got == 0)
		return NULL;
	char pdir[1100];
	snprintf(pdir, sizeof pdir, "%s/processed", c->o->dir);
	pc_stokes_folder_opts fo = { PC_SF_S0 | PC_SF_DOLP | PC_SF_AOLP | PC_SF_PICTURES,
				     { "capture", 0, 0 } };
	const pc_validity *valid = pc_stokes_stream_validity(c->live);
	int rc = pc_stokes_folder_write_valid(pdir, so, w, h, &fo, valid);
	if (rc)
		fail(c, rc, "writing the processed pictures: %s", pc_error_detail());
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
	json_object_set_new(pj, "last_invalid_pixels", json_integer((json_int_t)valid->n_invalid));
	json_object_set_new(pj, "method", json_string(c->method));
	json_object_set_new(pj, "frames", json_integer((json_int_t)got));
	json_object_set_new(pj, "mean_ms", pc_json_real(1e3 * c->proc_sum / (double)got));
	json_object_set_new(pj, "max_ms", pc_json_real(1e3 * c->proc_max));
	json_object_set_new(pj, "last_mean_dolp", nv > 0 ? pc_json_real(sum / nv) : json_null());
	json_object_set_new(pj, "width", json_integer(w));
	json_object_set_new(pj, "height", json_integer(h));
	set_extra(c, pj);
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
	capture c = { o, NULL, { 0 }, NULL, NULL, NULL, 0, 0, 0, 0, rep };
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
	return rc;
}

void pc_capture_report_free(pc_capture_report *rep)
{
	free(rep->json);
	rep->json = NULL;
}
