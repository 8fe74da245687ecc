/* The live window (polarcam/viewer.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/viewer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "json.h"
#include "polarcam/display.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/process.h"

typedef struct viewer {
	const pc_viewer_opts *o;
	pc_display *win;
	pc_source *src;
	pc_stokes_stream *live;
	const char *method;
	pc_pictures_live *pics; /* the panels' buffers, kept from frame to frame */
	const uint8_t *small;   /* the picture on screen (pics's) */
	uint32_t dw, dh;
	double fps, t_last, proc_total;
	long shots;
	pc_viewer_report *rep;
} viewer;

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int fail(viewer *v, int code, const char *what)
{
	v->rep->error = code;
	snprintf(v->rep->message, sizeof v->rep->message, "%s%s", what, pc_error_detail());
	return code;
}

static int open_all(viewer *v)
{
	pc_demosaic_method m = PC_DM_BILINEAR;
	int rc = v->o->method ? pc_demosaic_method_from_name(v->o->method, &m) : 0;
	if (rc)
		return pc_error_prefix(rc, "--method: ");
	/* screenshots are PNG: a name promising another format is refused, not filled with PNG */
	const char *shot = v->o->screenshot;
	size_t len = shot ? strlen(shot) : 0;
	if (shot && (len < 5 || strcasecmp(shot + len - 4, ".png")))
		return pc_error(
		    PC_EINVAL, "%s: screenshots are written as PNG only: name the file .png", shot);
	if (v->o->width < PC_PICTURES_PANELS_MIN_WIDTH)
		return pc_error(PC_EINVAL, "--width %u: the three panels with their keys need %u",
		                v->o->width, PC_PICTURES_PANELS_MIN_WIDTH);
	if (v->o->window && (rc = pc_display_open(&v->win, "polarcam view")))
		return pc_error_prefix(rc, "opening the window: ");
	if ((rc = pc_stream_open(&v->o->stream, &v->src)))
		return pc_error_prefix(rc, "opening the source: ");
	pc_source_format f;
	pc_source_get_format(v->src, &f);
	if ((rc = pc_process_method(v->o->method, &f.mosaic, &m)))
		return rc;
	v->method = pc_demosaic_method_get(m)->name;
	if ((rc = pc_stokes_stream_new(m, &v->live)) || (rc = pc_pictures_live_new(&v->pics)))
		return rc;
	return pc_stokes_stream_set_levels(v->live, &v->o->levels, v->src);
}

/* The status line's height above the panels (the window's overlay text goes there). */
#define STATUS_ROWS 30

/* One frame on screen: 1 to go on, 0 when the user quit, < 0 on an error. */
static int show(viewer *v, uint64_t seq)
{
	uint32_t w, h;
	const pc_stokes_out *st = pc_stokes_stream_planes(v->live, &w, &h);
	if (!st)
		return fail(v, pc_error(PC_ESTATE, "Stokes stream: no frame processed yet"), "");
	/* the pictures of the files (keys, DoLP range, low-signal hatch, invalid mark) as panels
	 * at the frames' aspect ratio */
	pc_pictures_opts po = {NULL, 0, v->o->mask_s0, NULL, 0, v->o->dolp_hi};
	const uint8_t *pic = NULL;
	uint32_t ph = 0;
	int rc = pc_pictures_live_draw(v->pics, st, w, h, &po, pc_stokes_stream_validity(v->live),
	                               v->o->width, STATUS_ROWS, &pic, &ph);
	v->small = NULL; /* the last picture is gone with a failed draw */
	if (rc)
		return fail(v, rc, "");
	v->small = pic;
	v->dw = v->o->width;
	v->dh = ph;
	v->rep->frames++;
	double t = now_s();
	if (v->rep->frames > 1)
		v->fps = v->fps > 0 ? 0.9 * v->fps + 0.1 / (t - v->t_last) : 1.0 / (t - v->t_last);
	v->t_last = t;
	char overlay[160];
	snprintf(overlay, sizeof overlay, "%.1f fps   frame %llu   %s", v->fps,
	         (unsigned long long)seq, v->method);
	if (v->win) {
		int key =
		    pc_display_show(v->win, v->small, v->dw, v->dh, (size_t)v->dw * 3, overlay);
		if (key == 'q' || key == 27 || key == PC_ECANCELED)
			return 0;
		if (key < -1)
			return fail(v, key, "");
		if (key == 's') {
			char name[32];
			snprintf(name, sizeof name, "view_%04ld.png", v->shots++);
			if (pc_png_write_rgb8(name, v->small, v->dw, v->dh, (size_t)v->dw * 3))
				v->rep->screenshots_failed++;
		}
	}
	return 1;
}

static void loop(viewer *v)
{
	const pc_viewer_opts *o = v->o;
	int stop = 0;
	int src = pc_source_start(v->src);
	if (src)
		fail(v, src, "starting the stream: ");
	while (!v->rep->error && !stop && (o->frames == 0 || v->rep->frames < o->frames)) {
		pc_buffer *b = NULL;
		int rc = pc_source_dequeue(v->src, o->timeout_ms, &b);
		if (rc) {
			char what[64];
			snprintf(what, sizeof what,
			         "after %llu frames: ", (unsigned long long)v->rep->frames);
			fail(v, rc, what);
			break;
		}
		/* a level the source declares only once frames flow (libcamera): asked after each
		 * of the first frames until one is declared, before the frame is processed */
		pc_stokes_stream_update_black(v->live, v->src);
		rc = pc_stokes_stream_process(v->live, &b->frame);
		uint64_t seq = b->frame.meta.sequence;
		int rc2 = pc_source_requeue(v->src, b);
		if (rc || rc2) {
			char what[64];
			snprintf(what, sizeof what,
			         "frame %llu: ", (unsigned long long)v->rep->frames);
			fail(v, rc ? rc : rc2, what);
			break;
		}
		v->proc_total += pc_stokes_stream_seconds(v->live);
		int go = show(v, seq);
		if (go <= 0)
			break;
		stop = pc_progress_report(&o->progress, "view", v->rep->frames, o->frames);
	}
}

int pc_viewer_run(const pc_viewer_opts *o, pc_viewer_report *rep)
{
	memset(rep, 0, sizeof *rep);
	viewer v = {o, NULL, NULL, NULL, NULL, NULL, NULL, 0, 0, 0, 0, 0, 0, rep};
	int rc = open_all(&v);
	if (!rc) {
		double t0 = now_s();
		v.t_last = t0;
		loop(&v);
		if (!rep->error && o->screenshot && v.small &&
		    pc_png_write_rgb8(o->screenshot, v.small, v.dw, v.dh, (size_t)v.dw * 3)) {
			char what[300];
			snprintf(what, sizeof what, "%s: ", o->screenshot);
			fail(&v, PC_EIO, what);
		}
		double dt = now_s() - t0;
		uint64_t shown = rep->frames;
		json_t *j = json_object();
		json_object_set_new(j, "source", json_string(o->stream.uri));
		json_object_set_new(j, "frames", json_integer((json_int_t)shown));
		json_object_set_new(j, "fps", pc_json_real(dt > 0 ? (double)shown / dt : 0));
		json_object_set_new(j, "process_ms",
		                    pc_json_real(shown ? 1e3 * v.proc_total / (double)shown : 0));
		json_object_set_new(j, "window", json_boolean(v.win != NULL));
		double black = 0, sat = 0;
		const char *calib = NULL;
		if (v.live)
			pc_stokes_stream_levels_used(v.live, &black, &sat, &calib);
		json_object_set_new(j, "black_level", pc_json_real(black));
		json_object_set_new(j, "saturation_level",
		                    sat > 0 ? pc_json_real(sat) : json_null());
		json_object_set_new(j, "calibration", calib ? json_string(calib) : json_null());
		const char *ng_from = NULL;
		const double ng =
		    v.live && shown ? pc_stokes_stream_noise_gain(v.live, &ng_from) : 0;
		json_object_set_new(j, "noise_gain", ng_from ? pc_json_real(ng) : json_null());
		json_object_set_new(j, "noise_gain_from",
		                    ng_from ? json_string(ng_from) : json_null());
		json_object_set_new(
		    j, "last_invalid_pixels",
		    v.live && shown
		        ? json_integer((json_int_t)pc_stokes_stream_validity(v.live)->n_invalid)
		        : json_null());
		json_t *warn = json_array();
		if (v.live && pc_stokes_stream_black_missed(v.live)) {
			snprintf(rep->warning, sizeof rep->warning,
			         "no black level given and the source declared none in the first "
			         "%llu frames: 0 DN used (give --black-level)",
			         (unsigned long long)(shown < PC_STREAM_BLACK_FRAMES
			                                  ? shown
			                                  : PC_STREAM_BLACK_FRAMES));
			json_array_append_new(warn, json_string(rep->warning));
		}
		json_object_set_new(j, "warnings", warn);
		json_object_set_new(j, "error",
		                    rep->error ? json_string(rep->message) : json_null());
		rep->json = pc_json_text(j);
		json_decref(j);
	}
	pc_pictures_live_free(v.pics);
	pc_stokes_stream_free(v.live);
	pc_source_close(v.src);
	pc_display_close(v.win);
	return rc;
}

void pc_viewer_report_free(pc_viewer_report *rep)
{
	free(rep->json);
	rep->json = NULL;
}
