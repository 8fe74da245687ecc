#include "source_cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "polarcam/error.h"

json_t *cli_json_source_stats(const pc_source_stats *st)
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
	return j;
}

json_t *cli_json_source_format(const pc_source_format *f)
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
	return j;
}

void cli_stream_args_init(cli_stream_args *a)
{
	memset(a, 0, sizeof *a);
	a->exposure_us = a->gain_db = a->fps = -1;
	a->buffers = 8;
	a->timeout_ms = 5000;
}

const char *cli_stream_args_help(void)
{
	return "  --format NAME       pixel format by its GenICam name (Mono12, PolarizeMono12p, "
	       "...)\n"
	       "  --roi X,Y,W,H       region of interest on the sensor (odd offsets shift the "
	       "mosaic)\n"
	       "  --exposure US       exposure time in microseconds\n"
	       "  --gain DB           gain in dB (the camera's Gain feature)\n"
	       "  --fps F             frame rate\n"
	       "  --buffers N         frames the source can fill ahead (default 8)\n"
	       "  --timeout-ms MS     longest wait for a frame (default 5000)\n";
}

int cli_stream_args_parse(cli_stream_args *a, int argc, char **argv, int *i)
{
	const char *o = argv[*i];
	static const char *const ours[] = {"--format", "--roi",     "--exposure",   "--gain",
	                                   "--fps",    "--buffers", "--timeout-ms", NULL};
	bool mine = false;
	for (const char *const *p = ours; *p; p++)
		mine |= !strcmp(o, *p);
	if (!mine)
		return 0;
	if (*i + 1 >= argc)
		return pc_error(PC_EINVAL, "%s needs a value", o);
	const char *v = argv[++*i];
	long l;
	int rc = 0;
	if (!strcmp(o, "--format")) {
		a->format = v;
	} else if (!strcmp(o, "--roi")) {
		unsigned long r[4];
		char tail;
		if (sscanf(v, "%lu,%lu,%lu,%lu%c", &r[0], &r[1], &r[2], &r[3], &tail) != 4 ||
		    strchr(v, '-') || r[0] > 1u << 20 || r[1] > 1u << 20 || r[2] < 1 ||
		    r[2] > 1u << 20 || r[3] < 1 || r[3] > 1u << 20)
			return pc_error(PC_EINVAL, "--roi '%s': expected X,Y,W,H (W, H >= 1)", v);
		for (int k = 0; k < 4; k++)
			a->roi[k] = (uint32_t)r[k];
		a->roi_set = true;
	} else if (!strcmp(o, "--exposure")) {
		rc = cli_parse_double(o, v, &a->exposure_us);
		if (!rc && a->exposure_us <= 0)
			rc = pc_error(PC_EINVAL, "--exposure %s: expected > 0", v);
	} else if (!strcmp(o, "--gain")) {
		rc = cli_parse_double(o, v, &a->gain_db);
		if (!rc && a->gain_db < 0)
			rc = pc_error(PC_EINVAL, "--gain %s: expected >= 0", v);
	} else if (!strcmp(o, "--fps")) {
		rc = cli_parse_double(o, v, &a->fps);
		if (!rc && a->fps <= 0)
			rc = pc_error(PC_EINVAL, "--fps %s: expected > 0", v);
	} else if (!strcmp(o, "--buffers")) {
		rc = cli_parse_long(o, v, 1, 64, &l);
		a->buffers = (unsigned)l;
	} else if (!strcmp(o, "--timeout-ms")) {
		rc = cli_parse_long(o, v, 1, 3600000, &l);
		a->timeout_ms = (int)l;
	}
	return rc ? rc : 1;
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

int pc_stream_open(const cli_stream_args *a, pc_source **out)
{
	*out = NULL;
	pc_source *s = NULL;
	int rc = pc_source_open(&s, a->uri);
	if (rc)
		return rc;
	if (a->format || a->roi_set) {
		pc_source_format f;
		pc_source_get_format(s, &f);
		pc_source_format req;
		memset(&req, 0, sizeof req);
		req.format = f.format;
		snprintf(req.format_name, sizeof req.format_name, "%s", f.format_name);
		if (a->format) {
			if (strlen(a->format) >= sizeof req.format_name) {
				pc_source_close(s);
				return pc_error(PC_EINVAL, "--format '%s': name too long",
				                a->format);
			}
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
		rc = pc_source_try_format(s, &got, &v);
		if (!rc && v == PC_FORMAT_INVALID)
			rc = pc_error_prefix(PC_EINVAL,
			                     "%s: the source cannot deliver this: ", a->uri);
		if (!rc && v == PC_FORMAT_ADJUSTED)
			rc = pc_error(PC_EINVAL,
			              "%s: the source would adjust the request to %s ROI "
			              "%u,%u,%u,%u; ask for that explicitly",
			              a->uri, got.format_name, got.offset_x, got.offset_y,
			              got.width, got.height);
		if (!rc)
			rc = pc_source_set_format(s, &got);
		if (rc) {
			pc_source_close(s);
			return rc;
		}
	}
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

/* ---- live processing ---- */

#include "polarcam/picture.h"

int pc_live_process(pc_live *lv, const pc_frame *f)
{
	if (f->mosaic.period != 2 && f->mosaic.period != 4)
		return pc_error(PC_EFORMAT,
		                "the frames carry no polarizer mosaic: nothing to compute "
		                "Stokes images from");
	uint32_t w, h;
	pc_demosaic_out_size(lv->method, f->view.width, f->view.height, &w, &h);
	if (w != lv->w || h != lv->h || !lv->planes) {
		free(lv->planes);
		free(lv->rgb);
		lv->w = w;
		lv->h = h;
		lv->planes = malloc((size_t)w * h * 3 * sizeof(float));
		lv->rgb = malloc((size_t)w * 3 * h * 3);
		if (!lv->planes || !lv->rgb)
			return pc_error(PC_ENOMEM, "Stokes images %ux%u", w, h);
		memset(&lv->out, 0, sizeof lv->out);
		lv->out.s0 = (pc_fplane){lv->planes, w, 1};
		lv->out.dolp = (pc_fplane){lv->planes + (size_t)w * h, w, 1};
		lv->out.aolp = (pc_fplane){lv->planes + 2 * (size_t)w * h, w, 1};
	}
	double t0 = cli_now();
	int rc = pc_stokes_from_raw(&f->view, &f->mosaic, lv->method, NULL, &lv->out);
	lv->process_s = cli_now() - t0;
	return rc;
}

int pc_live_compose(pc_live *lv)
{
	size_t stride = (size_t)lv->w * 3 * 3;
	float hi = pc_picture_quantile(&lv->out.s0, lv->w, lv->h, 0.999);
	if (!(hi > 0))
		hi = 1;
	int rc = pc_picture_grey(&lv->out.s0, lv->w, lv->h, 0, hi, lv->rgb, stride);
	if (!rc)
		rc = pc_picture_grey(&lv->out.dolp, lv->w, lv->h, 0, 1, lv->rgb + (size_t)lv->w * 3,
		                     stride);
	if (!rc)
		rc = pc_picture_aolp(&lv->out.aolp, &lv->out.dolp, lv->w, lv->h, PC_AOLP_VALUE,
		                     1.0f, lv->rgb + (size_t)lv->w * 6, stride);
	return rc;
}

void pc_live_free(pc_live *lv)
{
	free(lv->planes);
	free(lv->rgb);
	memset(lv, 0, sizeof *lv);
}
