/* Opening a source as asked, and the live source → Stokes stream (polarcam/stream.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/stream.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "black_watch.h"
#include "json.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"

void pc_stream_request_init(pc_stream_request *r)
{
	memset(r, 0, sizeof *r);
	r->exposure_us = r->gain_db = r->fps = -1;
	r->buffers = 8;
}

static int set_control(pc_source *s, pc_control_id id, double v)
{
	if (v < 0)
		return 0;
	double got;
	int rc = pc_source_control_set(s, id, v, &got);
	if (rc)
		return pc_error_prefix(rc, "--%s: ", pc_control_name(id));
	return 0;
}

/* Format and ROI as requested, or an error showing what the source would do instead. */
static int negotiate(pc_source *s, const pc_stream_request *a)
{
	pc_source_format f;
	pc_source_get_format(s, &f);
	pc_source_format req;
	memset(&req, 0, sizeof req);
	req.format = f.format;
	snprintf(req.format_name, sizeof req.format_name, "%s", f.format_name);
	if (a->format) {
		if (strlen(a->format) >= sizeof req.format_name)
			return pc_error(PC_EINVAL, "--format '%s': name too long", a->format);
		req.format = PC_FMT_INVALID;
		snprintf(req.format_name, sizeof req.format_name, "%s", a->format);
	}
	if (a->roi_set) {
		req.offset_x = a->roi[0];
		req.offset_y = a->roi[1];
		req.width = a->roi[2];
		req.height = a->roi[3];
	} else {
		req.offset_x = f.offset_x;
		req.offset_y = f.offset_y;
	}
	pc_source_format got = req;
	pc_format_verdict v;
	int rc = pc_source_try_format(s, &got, &v);
	if (!rc && v == PC_FORMAT_INVALID)
		rc = pc_error_prefix(PC_EINVAL, "%s: the source cannot deliver this: ", a->uri);
	if (!rc && v == PC_FORMAT_ADJUSTED)
		rc = pc_error(PC_EINVAL,
		              "%s: the source would adjust the request to %s ROI %u,%u,%u,%u; ask "
		              "for that explicitly",
		              a->uri, got.format_name, got.offset_x, got.offset_y, got.width,
		              got.height);
	if (!rc)
		rc = pc_source_set_format(s, &got);
	return rc;
}

int pc_stream_open(const pc_stream_request *a, pc_source **out)
{
	*out = NULL;
	pc_source *s = NULL;
	int rc = pc_source_open(&s, a->uri);
	if (rc)
		return rc;
	if (a->format || a->roi_set)
		rc = negotiate(s, a);
	if (!rc)
		rc = set_control(s, PC_CTRL_EXPOSURE_US, a->exposure_us);
	if (!rc)
		rc = set_control(s, PC_CTRL_GAIN_DB, a->gain_db);
	if (!rc)
		rc = set_control(s, PC_CTRL_FRAME_RATE_HZ, a->fps);
	if (!rc)
		rc = pc_source_buffers_alloc(s, a->buffers);
	if (rc) {
		pc_source_close(s);
		return rc;
	}
	*out = s;
	return 0;
}

char *pc_source_format_json(const pc_source_format *f)
{
	json_t *j = json_object();
	json_object_set_new(j, "format", json_string(f->format_name));
	json_object_set_new(j, "storage", json_string(pc_format_info_get(f->format)->name));
	json_object_set_new(j, "width", json_integer(f->width));
	json_object_set_new(j, "height", json_integer(f->height));
	json_object_set_new(j, "offset_x", json_integer(f->offset_x));
	json_object_set_new(j, "offset_y", json_integer(f->offset_y));
	json_object_set_new(j, "stride", json_integer((json_int_t)f->stride));
	json_object_set_new(j, "sensor_width", json_integer(f->sensor_width));
	json_object_set_new(j, "sensor_height", json_integer(f->sensor_height));
	json_object_set_new(j, "polarized", json_boolean(f->polarized));
	if (f->polarized) {
		char m[48];
		pc_mosaic_format(&f->mosaic, m, sizeof m);
		json_object_set_new(j, "mosaic", json_string(m));
	}
	char *t = pc_json_text(j);
	json_decref(j);
	return t;
}

char *pc_source_stats_json(const pc_source_stats *st)
{
	json_t *j = json_object();
	json_object_set_new(j, "completed", json_integer((json_int_t)st->completed));
	json_object_set_new(j, "failed", json_integer((json_int_t)st->failed));
	json_object_set_new(j, "dropped", json_integer((json_int_t)st->dropped));
	json_object_set_new(j, "timeouts", json_integer((json_int_t)st->timeouts));
	json_object_set_new(j, "underruns", json_integer((json_int_t)st->underruns));
	json_object_set_new(j, "transport_failures",
	                    json_integer((json_int_t)st->transport_failures));
	if (st->has_packets) {
		json_object_set_new(j, "missing_packets",
		                    json_integer((json_int_t)st->missing_packets));
		json_object_set_new(j, "resent_packets",
		                    json_integer((json_int_t)st->resent_packets));
	} else {
		json_object_set_new(j, "missing_packets", json_null());
		json_object_set_new(j, "resent_packets", json_null());
	}
	json_object_set_new(j, "bytes", json_integer((json_int_t)st->bytes));
	char *t = pc_json_text(j);
	json_decref(j);
	return t;
}

/* ---- live Stokes ---- */

struct pc_stokes_stream {
	pc_demosaic_method method;
	uint32_t w, h; /* output size of the method */
	float *planes; /* s0, dolp, aolp (each w*h) */
	pc_stokes_out out;
	double process_s;    /* time of the last pc_stokes_from_raw */
	pc_stream_levels lv; /* resolved: black_level finite */
	pc_calib cal;        /* with lv.calibration */
	bool have_cal;
	uint8_t *valid; /* w × h */
	pc_validity validity;
	double sat_used;
	double ng_used;       /* the last frame's noise gain (noise-aware methods) */
	const char *ng_from;  /* and its origin (pc_stokes_stream_noise_gain) */
	double frame_gain_db; /* the last frame's analog gain (NAN unknown) */
	black_watch black;    /* no level given, none declared at set-up: ask after frames */
};

pc_stream_levels pc_stream_levels_default(void)
{
	return (pc_stream_levels){NAN, 0, 0, NULL, 0};
}

int pc_stokes_stream_set_levels(pc_stokes_stream *s, const pc_stream_levels *lv, pc_source *src)
{
	pc_stream_levels l = lv ? *lv : pc_stream_levels_default();
	if (l.calibration && !isnan(l.black_level))
		return pc_error(PC_EINVAL,
		                "--black-level and --calibration: the calibration's dark "
		                "map is the black level; give one or the other");
	if (!isnan(l.black_level) && !(l.black_level >= 0 && isfinite(l.black_level)))
		return pc_error(PC_EINVAL, "black level %g: expected a finite level >= 0 DN",
		                l.black_level);
	if (!(l.noise_gain >= 0 && isfinite(l.noise_gain)))
		return pc_error(PC_EINVAL, "noise gain %g: expected a finite gain > 0 (raw units)",
		                l.noise_gain);
	if (l.noise_gain > 0 && !(pc_demosaic_method_get(s->method)->flags & PC_DMF_NOISE_GAIN))
		return pc_error(PC_EINVAL,
		                "--noise-gain: method %s uses no noise gain (the methods that do "
		                "say noise_gain in `polarcam demosaic --list --json`)",
		                pc_demosaic_method_get(s->method)->name);
	/* only a source that declares its level with its frames is asked again */
	l.black_level = black_watch_start(&s->black, src, l.black_level, !l.calibration);
	if (s->have_cal)
		pc_calib_free(&s->cal);
	s->have_cal = false;
	if (l.calibration) {
		int rc = pc_calib_read(l.calibration, &s->cal);
		if (rc)
			return pc_error_prefix(rc, "--calibration: ");
		s->have_cal = true;
		pc_source_format f;
		if (src && pc_source_get_format(src, &f) == 0) {
			pc_calib_geometry g = {f.width,
			                       f.height,
			                       f.offset_x,
			                       f.offset_y,
			                       f.sensor_width,
			                       f.sensor_height,
			                       pc_format_info_get(f.format)->bits,
			                       f.mosaic};
			if (f.polarized && f.mosaic.period == 4)
				rc = pc_error(PC_EINVAL,
				              "the source's frames are colour-polarization: "
				              "the calibration is for a monochrome mosaic");
			else if (!f.polarized)
				rc = pc_error(PC_EFORMAT, "the source's frames carry no polarizer "
				                          "mosaic");
			else
				rc = pc_calib_check(&s->cal, &g);
			if (rc)
				return pc_error_prefix(rc, "--calibration %s: ", l.calibration);
		}
	}
	s->lv = l;
	return 0;
}

int pc_stokes_stream_update_black(pc_stokes_stream *s, pc_source *src)
{
	int taken = black_watch_frame(&s->black, src);
	if (taken)
		s->lv.black_level = s->black.level;
	return taken;
}

int pc_stokes_stream_take_black(pc_stokes_stream *s, double black_dn)
{
	if (!s->black.open || !(black_dn > 0 && isfinite(black_dn)))
		return 0;
	s->black = (black_watch){false, true, true, 1, black_dn};
	s->lv.black_level = black_dn;
	return 1;
}

bool pc_stokes_stream_black_missed(const pc_stokes_stream *s)
{
	return black_watch_missed(&s->black);
}

const pc_validity *pc_stokes_stream_validity(const pc_stokes_stream *s)
{
	return &s->validity;
}

void pc_stokes_stream_levels_used(const pc_stokes_stream *s, double *black, double *saturation,
                                  const char **calibration)
{
	if (black)
		*black = s->have_cal ? 0 : s->lv.black_level;
	if (saturation)
		*saturation = s->sat_used;
	if (calibration)
		*calibration = s->have_cal ? s->lv.calibration : NULL;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int pc_stokes_stream_new(pc_demosaic_method method, pc_stokes_stream **out)
{
	*out = calloc(1, sizeof **out);
	if (!*out)
		return pc_error(PC_ENOMEM, "Stokes stream");
	(*out)->method = method;
	(*out)->lv = pc_stream_levels_default();
	(*out)->lv.black_level = 0;
	return 0;
}

void pc_stokes_stream_free(pc_stokes_stream *s)
{
	if (!s)
		return;
	free(s->planes);
	free(s->valid);
	if (s->have_cal)
		pc_calib_free(&s->cal);
	free(s);
}

int pc_stokes_stream_process(pc_stokes_stream *lv, const pc_frame *f)
{
	if (f->mosaic.period != 2 && f->mosaic.period != 4)
		return pc_error(PC_EFORMAT,
		                "the frames carry no polarizer mosaic: nothing to compute "
		                "Stokes images from");
	uint32_t w, h;
	pc_demosaic_out_size(lv->method, f->view.width, f->view.height, &w, &h);
	if (w != lv->w || h != lv->h || !lv->planes) {
		free(lv->planes);
		free(lv->valid);
		lv->w = w;
		lv->h = h;
		lv->planes = malloc((size_t)w * h * 3 * sizeof(float));
		lv->valid = malloc((size_t)w * h);
		if (!lv->planes || !lv->valid) {
			free(lv->planes);
			lv->planes = NULL;
			return pc_error(PC_ENOMEM, "Stokes images %ux%u", w, h);
		}
		memset(&lv->out, 0, sizeof lv->out);
		lv->out.s0 = (pc_fplane){lv->planes, w, 1};
		lv->out.dolp = (pc_fplane){lv->planes + (size_t)w * h, w, 1};
		lv->out.aolp = (pc_fplane){lv->planes + 2 * (size_t)w * h, w, 1};
	}
	const pc_format_info *fi = pc_format_info_get(f->view.format);
	unsigned bits = fi ? fi->bits : 0;
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = lv->method;
	po.mosaic = f->mosaic;
	po.black_level = lv->have_cal ? 0 : lv->lv.black_level;
	po.saturation_level = lv->lv.saturation_level > 0         ? lv->lv.saturation_level
	                      : lv->lv.saturation_level < 0       ? 0
	                      : lv->have_cal                      ? lv->cal.saturation
	                      : fi && !fi->is_float && bits <= 16 ? (double)((1u << bits) - 1u)
	                                                          : 0;
	po.dead_level = lv->lv.dead_level;
	po.noise_gain = lv->lv.noise_gain;
	lv->ng_used = 0;
	lv->frame_gain_db = f->meta.gain_db;
	po.noise_gain_used = &lv->ng_used;
	lv->ng_from = NULL;
	if (pc_demosaic_method_get(lv->method)->flags & PC_DMF_NOISE_GAIN) {
		bool scaled = false;
		lv->ng_from =
		    lv->lv.noise_gain > 0 ? "option"
		    : lv->have_cal && pc_calib_noise_gain(&lv->cal, f->meta.gain_db, &scaled) > 0
		        ? (scaled ? "calibration at the frame's gain" : "calibration")
		        : "estimated";
	}
	lv->sat_used = po.saturation_level;
	lv->validity = (pc_validity){lv->valid, w, 0};
	double t0 = now_s();
	int rc = lv->have_cal
	             ? pc_calib_apply(&lv->cal, f, bits, &po, &lv->out, NULL, &lv->validity)
	             : pc_stokes_run(&f->view, &po, &lv->out, &lv->validity);
	lv->process_s = now_s() - t0;
	return rc;
}

void pc_stokes_stream_gains(const pc_stokes_stream *s, double *frame_db, double *calibration_db,
                            double *dark_db)
{
	if (frame_db)
		*frame_db = s->planes ? s->frame_gain_db : NAN;
	if (calibration_db)
		*calibration_db =
		    s->have_cal && s->cal.system_gain > 0 ? s->cal.system_gain_db : NAN;
	if (dark_db)
		*dark_db = s->have_cal && s->cal.dark ? s->cal.dark_gain_db : NAN;
}

double pc_stokes_stream_noise_gain(const pc_stokes_stream *s, const char **from)
{
	if (from)
		*from = s->ng_from;
	return s->ng_used;
}

const pc_stokes_out *pc_stokes_stream_planes(const pc_stokes_stream *s, uint32_t *width,
                                             uint32_t *height)
{
	if (width)
		*width = s->w;
	if (height)
		*height = s->h;
	return s->planes ? &s->out : NULL;
}

double pc_stokes_stream_seconds(const pc_stokes_stream *s)
{
	return s->process_s;
}
