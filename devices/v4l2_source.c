/* The `v4l2:` frame source: a V4L2 capture node behind the frame-source ops (polarcam/source.h),
 * on top of the node layer in v4l2.c (polarcam/v4l2.h).
 *
 *   v4l2:/dev/videoN[?input=I&dv=WxH@FPS&mosaic=LAYOUT|none&gain_db_step=DB]
 *
 * input         selects a capture input (VIDIOC_S_INPUT) before anything else
 * dv            sets VESA CVT reduced-blanking v2 timings WxH at FPS on that input (HDMI
 *               receivers; vivid's loopback)
 * mosaic        the polarizer layout of the sensor ("90,45,135,0", the default Sony IMX250MZR
 *               order, see pc_mosaic_parse), or "none" for a sensor without one: V4L2 does not
 *               report it
 * gain_db_step  dB per unit of the driver's gain control (V4L2 gain units are driver-specific;
 *               without this option gain_db is not offered)
 *
 * Sensor size: the DV timings of the input when it has them, else the largest frame size the
 * driver enumerates for the format, else the size at open. Requests beyond it are adjusted to
 * it. ROI offsets are not offered (V4L2 cropping is driver-specific): a request with an offset
 * is adjusted to (0, 0). Strides: the driver's bytesperline is honoured and a larger one may be
 * requested (drivers that support padding, vivid does, give it).
 *
 * Sequence numbers: V4L2's are 32-bit; they are extended to 64 bits across wraps. A driver that
 * repeats or reorders a number (vivid does when it lags) gets the next free one so that
 * delivered numbers strictly increase; gaps count as dropped frames in the statistics.
 * Timestamps: the driver's CLOCK_MONOTONIC buffer time; the dequeue time when the driver's
 * timestamps are not monotonic.
 */
#include "polarcam/source.h"

#include <errno.h>
#include <linux/videodev2.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "backend_util.h"
#include "backends.h"
#include "polarcam/error.h"
#include "polarcam/v4l2.h"

typedef struct v4l2_src {
	pc_v4l2 *dev;
	uint32_t sensor_w, sensor_h;
	bool polarized;
	pc_mosaic mosaic;
	double gain_db_step; /* 0: gain_db not offered */
	pc_buffer **bufs;
	unsigned nbufs;
	/* sequence extension */
	bool have_last;
	uint32_t last_raw;
	uint64_t last_drv; /* driver number, extended */
	uint64_t last_out; /* number delivered */
	/* control values for frame metadata (0 = unknown) */
	double exposure_us, gain_db;
} v4l2_src;

static v4l2_src *priv(pc_source *s)
{
	return pc_source_priv(s);
}

/* ---- helpers ---- */

static uint32_t fourcc_from_string(const char *name)
{
	char b[4] = {' ', ' ', ' ', ' '};
	size_t n = strlen(name);
	if (n == 0 || n > 4)
		return 0;
	memcpy(b, name, n);
	return PC_FOURCC(b[0], b[1], b[2], b[3]);
}

static bool offered(const uint32_t *list, size_t n, uint32_t f)
{
	for (size_t i = 0; i < n; i++)
		if (list[i] == f)
			return true;
	return false;
}

/* The readable formats the node offers, in driver order. */
static int readable_formats(v4l2_src *v, uint32_t *out, size_t cap, size_t *n)
{
	uint32_t all[128];
	size_t total = 0;
	int rc = pc_v4l2_enum_formats(v->dev, all, 128, &total);
	if (rc)
		return rc;
	size_t k = 0;
	for (size_t i = 0; i < total && i < 128; i++)
		if (pc_format_from_v4l2(all[i]) != PC_FMT_INVALID && k < cap)
			out[k++] = all[i];
	*n = k;
	return 0;
}

static int sensor_size(v4l2_src *v, uint32_t fourcc, uint32_t *w, uint32_t *h)
{
	pc_dv_timings t;
	if (pc_v4l2_get_dv_timings(v->dev, &t) == 0 && t.width && t.height) {
		*w = t.width;
		*h = t.height;
		return 0;
	}
	pc_v4l2_size_range r;
	if (pc_v4l2_frame_sizes(v->dev, fourcc, &r) == 0 && r.max_width && r.max_height) {
		*w = r.max_width;
		*h = r.max_height;
		return 0;
	}
	pc_v4l2_format g;
	int rc = pc_v4l2_get_format(v->dev, &g);
	if (rc)
		return rc;
	*w = g.width;
	*h = g.height;
	return 0;
}

/* "2448x2048@30" */
static int parse_dv(const char *s, uint32_t *w, uint32_t *h, double *fps)
{
	unsigned a, b;
	double f;
	char tail;
	if (sscanf(s, "%ux%u@%lf%c", &a, &b, &f, &tail) != 3 || !a || !b || !(f > 0.0))
		return pc_error(PC_EINVAL,
		                "URI option dv=%s: expected WIDTHxHEIGHT@FPS such as "
		                "2448x2048@30",
		                s);
	*w = a;
	*h = b;
	*fps = f;
	return 0;
}

/* ---- ops ---- */

static void v_close(pc_source *s)
{
	v4l2_src *v = priv(s);
	if (!v)
		return;
	pc_v4l2_close(v->dev);
	free(v);
	pc_source_set_priv(s, NULL);
}

static int v_open(pc_source *s, const char *arg)
{
	char path[256];
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "v4l2: device missing: expected v4l2:/dev/videoN");
	if (strspn(arg, "0123456789") == strlen(arg))
		snprintf(path, sizeof path, "/dev/video%s", arg); /* v4l2:0 = /dev/video0 */
	else
		snprintf(path, sizeof path, "%s", arg);
	v4l2_src *v = calloc(1, sizeof *v);
	if (!v)
		return pc_error(PC_ENOMEM, "v4l2 source");
	pc_source_set_priv(s, v);
	v->polarized = true;
	v->mosaic = pc_mosaic_imx250mzr();

	uint64_t input = 0;
	bool have_input = pc_source_option(s, "input") != NULL;
	int rc = pc_source_option_u64(s, "input", 0, 255, &input);
	const char *mos = pc_source_option(s, "mosaic");
	if (!rc && mos) {
		if (!strcmp(mos, "none")) {
			v->polarized = false;
			memset(&v->mosaic, 0, sizeof v->mosaic);
		} else {
			rc = pc_mosaic_parse(mos, &v->mosaic);
			if (rc)
				rc = pc_error_prefix(rc, "URI option mosaic=%s: ", mos);
		}
	}
	if (!rc)
		rc = pc_source_option_double(s, "gain_db_step", 1e-6, 100.0, &v->gain_db_step);
	const char *dv = pc_source_option(s, "dv");
	uint32_t dw = 0, dh = 0;
	double dfps = 0;
	if (!rc && dv)
		rc = parse_dv(dv, &dw, &dh, &dfps);
	if (!rc)
		rc = pc_v4l2_open(path, PC_V4L2_CAPTURE, &v->dev);
	if (!rc && have_input)
		rc = pc_v4l2_select_io(v->dev, (unsigned)input);
	if (!rc && dv) {
		pc_dv_timings t;
		rc = pc_dv_timings_cvt_rb2(dw, dh, dfps, &t);
		if (!rc)
			rc = pc_v4l2_set_dv_timings(v->dev, &t);
	}
	if (!rc) {
		pc_v4l2_format g;
		rc = pc_v4l2_get_format(v->dev, &g);
		if (!rc)
			rc = sensor_size(v, g.fourcc, &v->sensor_w, &v->sensor_h);
	}
	if (rc) {
		v_close(s);
		return rc;
	}
	return 0;
}

static int v_get_info(pc_source *s, pc_source_info *info)
{
	v4l2_src *v = priv(s);
	const pc_v4l2_info *in = pc_v4l2_get_info(v->dev);
	snprintf(info->vendor, sizeof info->vendor, "%s", in->driver);
	snprintf(info->model, sizeof info->model, "%s", in->card);
	snprintf(info->serial, sizeof info->serial, "%s", in->bus_info);
	snprintf(info->driver, sizeof info->driver, "%s", in->driver);
	info->sensor_width = v->sensor_w;
	info->sensor_height = v->sensor_h;
	info->polarized = v->polarized;
	if (v->polarized)
		info->mosaic = v->mosaic;
	return 0;
}

static int v_try_format(pc_source *s, pc_source_format *fmt, pc_format_verdict *verdict)
{
	v4l2_src *v = priv(s);
	const char *path = pc_v4l2_get_info(v->dev)->path;
	pc_source_format req = *fmt;
	bool adjusted = false;
	*verdict = PC_FORMAT_INVALID;

	uint32_t have[64];
	size_t nhave = 0;
	int rc = readable_formats(v, have, 64, &nhave);
	if (rc)
		return rc;
	if (nhave == 0) {
		pc_error(PC_EFORMAT,
		         "%s offers no raw monochrome format polarcam reads (GREY, Y10, "
		         "Y12, Y14, Y16, Y10P, Y12P, ...)",
		         path);
		return 0;
	}

	/* 1. the pixel format */
	uint32_t fourcc = 0;
	if (req.format_name[0]) {
		/* a fourcc the node offers ("Y16"), else a polarcam / GenICam name, vendors'
		 * polarized names included ("Mono12", "PolarizeMono12"): the storage layout
		 * decides; else a fourcc the node lacks (substituted below) */
		uint32_t as_fourcc = fourcc_from_string(req.format_name);
		pc_pixfmt byname = pc_format_from_name(req.format_name);
		bool pol, col;
		if (byname == PC_FMT_INVALID &&
		    pc_format_from_genicam(req.format_name, &byname, &pol, &col) != 0)
			byname = PC_FMT_INVALID;
		const pc_format_info *fi = pc_format_info_get(byname);
		if (offered(have, nhave, as_fourcc))
			fourcc = as_fourcc;
		else if (fi && fi->v4l2_fourcc)
			fourcc = fi->v4l2_fourcc;
		else
			fourcc = as_fourcc;
		if (!fourcc) {
			pc_error(PC_EINVAL,
			         "format name '%s': neither a V4L2 fourcc nor a polarcam "
			         "format with one",
			         req.format_name);
			return 0;
		}
	}
	if (req.format != PC_FMT_INVALID) {
		uint32_t f4 = pc_format_info_get(req.format)->v4l2_fourcc;
		if (fourcc && f4 != fourcc) {
			pc_error(PC_EINVAL, "format %s and format name '%s' disagree",
			         pc_format_info_get(req.format)->name, req.format_name);
			return 0;
		}
		if (f4)
			fourcc = f4;
		else
			adjusted = true; /* V4L2 has no such layout: substitute below */
	}
	if (!fourcc && !adjusted) {
		pc_v4l2_format g;
		if (pc_v4l2_get_format(v->dev, &g) == 0 && offered(have, nhave, g.fourcc))
			fourcc = g.fourcc; /* the node's current choice */
		else
			fourcc = have[0];
	}
	if (!offered(have, nhave, fourcc)) {
		/* substitute: a readable format with the same bit depth, else the deepest one */
		unsigned want_bits =
		    req.format != PC_FMT_INVALID
		        ? pc_format_info_get(req.format)->bits
		        : (pc_format_from_v4l2(fourcc) != PC_FMT_INVALID
		               ? pc_format_info_get(pc_format_from_v4l2(fourcc))->bits
		               : 0);
		uint32_t best = 0;
		unsigned best_bits = 0;
		for (size_t i = 0; i < nhave; i++) {
			unsigned b = pc_format_info_get(pc_format_from_v4l2(have[i]))->bits;
			if (b == want_bits) {
				best = have[i];
				break;
			}
			if (b > best_bits) {
				best = have[i];
				best_bits = b;
			}
		}
		fourcc = best;
		adjusted = true;
	}

	/* 2. the size: the whole sensor unless asked; no ROI offsets */
	uint32_t sw = v->sensor_w, sh = v->sensor_h;
	if (req.offset_x || req.offset_y)
		adjusted = true;
	uint32_t w = req.width ? req.width : sw, h = req.height ? req.height : sh;
	if (w > sw) {
		w = sw;
		adjusted = true;
	}
	if (h > sh) {
		h = sh;
		adjusted = true;
	}

	/* 3. what the driver makes of it */
	pc_v4l2_format g;
	rc = pc_v4l2_try_format(v->dev, fourcc, w, h, req.stride, &g);
	if (rc == PC_EINVAL) {
		return 0; /* the driver refused outright: invalid, detail set */
	}
	if (rc)
		return rc;
	if (g.format == PC_FMT_INVALID) {
		char b[5];
		pc_error(PC_EFORMAT,
		         "%s: the driver answers '%s' %ux%u, which polarcam cannot read", path,
		         pc_fourcc_str(g.fourcc, b), g.width, g.height);
		return 0;
	}
	if (g.fourcc != fourcc || g.width != w || g.height != h)
		adjusted = adjusted || req.width || req.height || g.fourcc != fourcc ||
		           req.format != PC_FMT_INVALID || req.format_name[0];
	if (g.width > sw || g.height > sh) {
		/* the driver scales up beyond the sensor: not a raw mosaic any more */
		pc_error(PC_EFORMAT, "%s: the driver answers %ux%u for a %ux%u sensor", path,
		         g.width, g.height, sw, sh);
		return 0;
	}
	if (req.stride && g.bytesperline != req.stride)
		adjusted = true;
	size_t row;
	if (pc_format_row_bytes(g.format, g.width, &row) || g.bytesperline < row ||
	    g.sizeimage < g.bytesperline * (g.height - 1) + row) {
		pc_error(PC_EFORMAT,
		         "%s: the driver answers bytesperline %zu / sizeimage %zu for %ux%u", path,
		         g.bytesperline, g.sizeimage, g.width, g.height);
		return 0;
	}

	memset(fmt, 0, sizeof *fmt);
	fmt->format = g.format;
	if (!adjusted && req.format_name[0])
		snprintf(fmt->format_name, sizeof fmt->format_name, "%s", req.format_name);
	else
		pc_fourcc_str(g.fourcc, fmt->format_name);
	fmt->width = g.width;
	fmt->height = g.height;
	fmt->stride = g.bytesperline;
	fmt->frame_bytes = g.sizeimage;
	fmt->polarized = v->polarized;
	fmt->sensor_width = sw;
	fmt->sensor_height = sh;
	rc = pc_source_format_complete(fmt, v->polarized ? &v->mosaic : NULL);
	if (rc)
		return rc;
	*verdict = adjusted ? PC_FORMAT_ADJUSTED : PC_FORMAT_VALID;
	return 0;
}

/* Puts the format on the device and checks the driver kept it. */
static int apply_format(v4l2_src *v, const pc_source_format *fmt)
{
	uint32_t fourcc = pc_format_info_get(fmt->format)->v4l2_fourcc;
	pc_v4l2_format g;
	int rc = pc_v4l2_set_format(v->dev, fourcc, fmt->width, fmt->height, fmt->stride, &g);
	if (rc)
		return rc;
	if (g.fourcc != fourcc || g.width != fmt->width || g.height != fmt->height ||
	    g.bytesperline != fmt->stride) {
		char a[5], b[5];
		return pc_error(PC_EIO,
		                "%s: asked for %s %ux%u bytesperline %zu, the driver set %s "
		                "%ux%u bytesperline %zu",
		                pc_v4l2_get_info(v->dev)->path, pc_fourcc_str(fourcc, a),
		                fmt->width, fmt->height, fmt->stride, pc_fourcc_str(g.fourcc, b),
		                g.width, g.height, g.bytesperline);
	}
	return 0;
}

static int v_set_format(pc_source *s, const pc_source_format *fmt)
{
	return apply_format(priv(s), fmt);
}

/* ---- controls ---- */

static int query_exposure(v4l2_src *v, pc_v4l2_ctrl *c)
{
	int rc = pc_v4l2_ctrl_query(v->dev, PC_V4L2_CID_EXPOSURE_ABSOLUTE, c);
	if (rc == PC_ENOENT)
		return pc_error(PC_ENOTSUP,
		                "%s: no absolute exposure control "
		                "(V4L2_CID_EXPOSURE_ABSOLUTE, in 100 us units); the "
		                "driver-specific V4L2_CID_EXPOSURE has no defined unit",
		                pc_v4l2_get_info(v->dev)->path);
	return rc;
}

static int query_gain(v4l2_src *v, pc_v4l2_ctrl *c)
{
	if (v->gain_db_step <= 0)
		return pc_error(PC_ENOTSUP,
		                "%s: V4L2 gain has driver-specific units, not dB; give the "
		                "scale with the URI option gain_db_step=DB (dB per unit)",
		                pc_v4l2_get_info(v->dev)->path);
	int rc = pc_v4l2_ctrl_query(v->dev, PC_V4L2_CID_GAIN, c);
	if (rc == PC_ENOENT)
		rc = pc_v4l2_ctrl_query(v->dev, PC_V4L2_CID_ANALOGUE_GAIN, c);
	if (rc == PC_ENOENT)
		return pc_error(PC_ENOTSUP,
		                "%s: no gain control (V4L2_CID_GAIN or "
		                "V4L2_CID_ANALOGUE_GAIN)",
		                pc_v4l2_get_info(v->dev)->path);
	return rc;
}

static int v_control_query(pc_source *s, pc_control_id id, pc_control_info *info)
{
	v4l2_src *v = priv(s);
	pc_v4l2_ctrl c;
	int rc;
	memset(info, 0, sizeof *info);
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		rc = query_exposure(v, &c);
		if (rc)
			return rc;
		info->min = 100.0 * (double)c.minimum;
		info->max = 100.0 * (double)c.maximum;
		info->step = 100.0 * (double)(c.step > 0 ? c.step : 1);
		info->def = 100.0 * (double)c.default_value;
		info->live = true;
		return 0;
	case PC_CTRL_GAIN_DB:
		rc = query_gain(v, &c);
		if (rc)
			return rc;
		info->min = v->gain_db_step * (double)c.minimum;
		info->max = v->gain_db_step * (double)c.maximum;
		info->step = v->gain_db_step * (double)(c.step > 0 ? c.step : 1);
		info->def = v->gain_db_step * (double)c.default_value;
		info->live = true;
		return 0;
	case PC_CTRL_FRAME_RATE_HZ: {
		double cur;
		rc = pc_v4l2_get_frame_rate(v->dev, &cur);
		if (rc)
			return rc;
		const pc_source_format *f = pc_source_current_format(s);
		pc_v4l2_rate_range r;
		rc = pc_v4l2_frame_rates(v->dev, pc_format_info_get(f->format)->v4l2_fourcc,
		                         f->width, f->height, &r);
		if (rc)
			return rc;
		info->min = r.min_fps;
		info->max = r.max_fps;
		info->step = r.step_fps; /* discrete rates: the largest gap (worst rounding) */
		info->def = cur < r.min_fps ? r.min_fps : cur > r.max_fps ? r.max_fps : cur;
		info->live = false;
		return 0;
	}
	case PC_CTRL_COUNT:
		break;
	}
	return pc_error(PC_EINVAL, "control %d unknown", (int)id);
}

static int v_control_get(pc_source *s, pc_control_id id, double *value)
{
	v4l2_src *v = priv(s);
	pc_v4l2_ctrl c;
	int64_t raw;
	int rc;
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		rc = query_exposure(v, &c);
		if (!rc)
			rc = pc_v4l2_ctrl_get(v->dev, c.id, &raw);
		if (!rc)
			*value = 100.0 * (double)raw;
		return rc;
	case PC_CTRL_GAIN_DB:
		rc = query_gain(v, &c);
		if (!rc)
			rc = pc_v4l2_ctrl_get(v->dev, c.id, &raw);
		if (!rc)
			*value = v->gain_db_step * (double)raw;
		return rc;
	case PC_CTRL_FRAME_RATE_HZ:
		return pc_v4l2_get_frame_rate(v->dev, value);
	case PC_CTRL_COUNT:
		break;
	}
	return pc_error(PC_EINVAL, "control %d unknown", (int)id);
}

/* The raw value nearest to value/scale on the control's grid. */
static int64_t to_grid(const pc_v4l2_ctrl *c, double value, double scale)
{
	double step = (double)(c->step > 0 ? c->step : 1);
	double k = llround((value / scale - (double)c->minimum) / step);
	double raw = (double)c->minimum + k * step;
	if (raw > (double)c->maximum)
		raw -= step;
	if (raw < (double)c->minimum)
		raw = (double)c->minimum;
	return (int64_t)raw;
}

/* Turns an automatic mode off (value `manual`) when the driver has it and it is not already. */
static int manual_mode(v4l2_src *v, uint32_t auto_id, int64_t manual)
{
	pc_v4l2_ctrl a;
	int64_t cur;
	if (pc_v4l2_ctrl_query(v->dev, auto_id, &a) != 0 || a.read_only)
		return 0;
	if (pc_v4l2_ctrl_get(v->dev, auto_id, &cur) == 0 && cur == manual)
		return 0;
	return pc_v4l2_ctrl_set(v->dev, auto_id, manual);
}

static int v_control_set(pc_source *s, pc_control_id id, double value, double *applied)
{
	v4l2_src *v = priv(s);
	pc_v4l2_ctrl c;
	int rc;
	int64_t raw;
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		rc = query_exposure(v, &c);
		if (!rc)
			rc = manual_mode(v, V4L2_CID_EXPOSURE_AUTO, V4L2_EXPOSURE_MANUAL);
		raw = to_grid(&c, value, 100.0);
		if (!rc)
			rc = pc_v4l2_ctrl_set(v->dev, c.id, raw);
		if (!rc) {
			*applied = 100.0 * (double)raw;
			v->exposure_us = *applied;
		}
		return rc;
	case PC_CTRL_GAIN_DB:
		rc = query_gain(v, &c);
		if (!rc)
			rc = manual_mode(v, V4L2_CID_AUTOGAIN, 0);
		raw = to_grid(&c, value, v->gain_db_step);
		if (!rc)
			rc = pc_v4l2_ctrl_set(v->dev, c.id, raw);
		if (!rc) {
			*applied = v->gain_db_step * (double)raw;
			v->gain_db = *applied;
		}
		return rc;
	case PC_CTRL_FRAME_RATE_HZ:
		return pc_v4l2_set_frame_rate(v->dev, value, applied);
	case PC_CTRL_COUNT:
		break;
	}
	return pc_error(PC_EINVAL, "control %d unknown", (int)id);
}

/* ---- buffers and streaming ---- */

static int v_buffers_alloc(pc_source *s, pc_buffer **bufs, unsigned count)
{
	v4l2_src *v = priv(s);
	const char *path = pc_v4l2_get_info(v->dev)->path;
	/* the negotiated format, even if the node was changed behind our back since */
	int rc = apply_format(v, pc_source_current_format(s));
	if (rc)
		return rc;
	unsigned granted = 0;
	rc = pc_v4l2_buffers_alloc(v->dev, count, &granted);
	if (rc)
		return rc;
	if (granted != count) {
		pc_v4l2_buffers_free(v->dev);
		if (granted > count)
			return pc_error(PC_EINVAL,
			                "%s: the driver needs at least %u buffers (asked for %u)",
			                path, granted, count);
		return pc_error(PC_ENOMEM, "%s: the driver granted %u of %u buffers", path, granted,
		                count);
	}
	for (unsigned i = 0; i < count; i++) {
		rc = pc_v4l2_buffer_memory(v->dev, i, &bufs[i]->data, &bufs[i]->size);
		if (rc) {
			pc_v4l2_buffers_free(v->dev);
			return rc;
		}
		bufs[i]->backend = NULL;
	}
	v->bufs = bufs;
	v->nbufs = count;
	return 0;
}

static void v_buffers_free(pc_source *s, pc_buffer **bufs, unsigned count)
{
	v4l2_src *v = priv(s);
	for (unsigned i = 0; i < count; i++) {
		bufs[i]->data = NULL;
		bufs[i]->size = 0;
	}
	pc_v4l2_stream_off(v->dev);
	pc_v4l2_buffers_free(v->dev);
	v->bufs = NULL;
	v->nbufs = 0;
}

static int v_queue(pc_source *s, pc_buffer *buf)
{
	return pc_v4l2_queue(priv(s)->dev, buf->index, 0);
}

/* Whether the driver adjusts a control itself: its automatic mode auto_id is present and at
 * none of the n values that hold the control fixed (a value read now is stale by the next
 * frame) */
static bool auto_on(v4l2_src *v, uint32_t auto_id, const int64_t *fixed, int n)
{
	pc_v4l2_ctrl a;
	int64_t cur;
	if (pc_v4l2_ctrl_query(v->dev, auto_id, &a) != 0 || pc_v4l2_ctrl_get(v->dev, auto_id, &cur))
		return false;
	for (int i = 0; i < n; i++)
		if (cur == fixed[i])
			return false;
	return true;
}

static int v_start(pc_source *s)
{
	v4l2_src *v = priv(s);
	v->have_last = false;
	double x;
	/* what the frames report: unknown (NAN) where the driver adjusts it itself (exposure: not
	 * manual nor shutter priority; gain: autogain on) */
	static const int64_t exp_fixed[2] = {V4L2_EXPOSURE_MANUAL, V4L2_EXPOSURE_SHUTTER_PRIORITY},
	                     gain_fixed[1] = {0};
	v->exposure_us = !auto_on(v, V4L2_CID_EXPOSURE_AUTO, exp_fixed, 2) &&
	                         v_control_get(s, PC_CTRL_EXPOSURE_US, &x) == 0
	                     ? x
	                     : NAN;
	v->gain_db = !auto_on(v, V4L2_CID_AUTOGAIN, gain_fixed, 1) &&
	                     v_control_get(s, PC_CTRL_GAIN_DB, &x) == 0
	                 ? x
	                 : NAN;
	pc_error_clear();
	return pc_v4l2_stream_on(v->dev);
}

/* 32-bit driver sequence -> strictly increasing 64-bit sequence (see the top of the file). */
static uint64_t next_sequence(v4l2_src *v, uint32_t raw)
{
	if (!v->have_last) {
		v->have_last = true;
		v->last_raw = raw;
		v->last_drv = raw;
		v->last_out = raw;
		return raw;
	}
	uint32_t delta = raw - v->last_raw; /* modulo 2^32 */
	uint64_t drv;
	if (delta < 0x80000000u)
		drv = v->last_drv + delta; /* forward, across a wrap too */
	else
		drv = v->last_drv >= (uint64_t)(0u - delta) ? v->last_drv - (0u - delta) : 0;
	v->last_raw = raw;
	v->last_drv = drv;
	v->last_out = drv > v->last_out ? drv : v->last_out + 1;
	return v->last_out;
}

static int v_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	v4l2_src *v = priv(s);
	pc_v4l2_buffer b;
	int rc = pc_v4l2_dequeue(v->dev, timeout_ms, &b);
	if (rc)
		return rc;
	if (b.index >= v->nbufs)
		return pc_error(PC_EIO, "%s: buffer %u is not in the pool",
		                pc_v4l2_get_info(v->dev)->path, b.index);
	pc_buffer *pb = v->bufs[b.index];
	const pc_source_format *f = pc_source_current_format(s);
	pc_frame *fr = &pb->frame;
	fr->view.data = b.data;
	fr->view.width = f->width;
	fr->view.height = f->height;
	fr->view.stride = f->stride;
	fr->view.format = f->format;
	memset(&fr->meta, 0, sizeof fr->meta);
	fr->meta.sequence = next_sequence(v, b.sequence);
	fr->meta.timestamp_ns = b.timestamp_monotonic ? b.timestamp_ns : pc_clock_ns();
	fr->meta.exposure_us = v->exposure_us;
	fr->meta.gain_db = v->gain_db;
	size_t row = 0;
	(void)pc_format_row_bytes(f->format, f->width, &row);
	if (b.error)
		fr->meta.status |= PC_FRAME_CORRUPT;
	if (b.bytesused < f->stride * (f->height - 1) + row)
		fr->meta.status |= PC_FRAME_INCOMPLETE;
	*out = pb;
	return 0;
}

static int v_stop(pc_source *s)
{
	return pc_v4l2_stream_off(priv(s)->dev);
}

/* ---- enumeration for `polarcam devices` ---- */

int pc_v4l2_enumerate(unsigned flags, pc_device_fn fn, void *ctx)
{
	(void)flags; /* V4L2 nodes are local: no network discovery */
	pc_v4l2_node *nodes = NULL;
	size_t n = 0;
	int rc = pc_v4l2_list(NULL, &nodes, &n);
	if (rc)
		return rc;
	for (size_t i = 0; i < n && !rc; i++) {
		const pc_v4l2_node *d = &nodes[i];
		pc_device_entry e;
		memset(&e, 0, sizeof e);
		snprintf(e.uri, sizeof e.uri, "v4l2:%.240s", d->info.path);
		snprintf(e.vendor, sizeof e.vendor, "%s", d->info.driver);
		snprintf(e.model, sizeof e.model, "%s", d->info.card);
		snprintf(e.serial, sizeof e.serial, "%s", d->info.bus_info);
		snprintf(e.transport, sizeof e.transport, "V4L2");
		snprintf(e.address, sizeof e.address, "%.63s", d->info.path);
		size_t readable = 0;
		for (size_t k = 0; k < d->nformats; k++) {
			if (pc_format_from_v4l2(d->fourccs[k]) == PC_FMT_INVALID)
				continue;
			char f4[5];
			pc_fourcc_str(d->fourccs[k], f4);
			for (int c = 3; c > 0 && f4[c] == ' '; c--)
				f4[c] = '\0'; /* "Y10 " -> "Y10" */
			size_t used = strlen(e.formats);
			snprintf(e.formats + used, sizeof e.formats - used, "%s%s", used ? " " : "",
			         f4);
			readable++;
		}
		e.formats_total = (unsigned)d->nformats_total;
		if (d->error)
			snprintf(e.note, sizeof e.note, "%s", d->error_detail);
		else if (!d->info.capture && !d->info.capture_mplane)
			snprintf(e.note, sizeof e.note, "not a video capture node%s",
			         d->info.output     ? " (video output)"
			         : d->info.metadata ? " (metadata)"
			                            : "");
		else if (!d->info.streaming)
			snprintf(e.note, sizeof e.note, "no streaming I/O");
		else if (!readable)
			snprintf(e.note, sizeof e.note,
			         "offers no raw monochrome format polarcam reads "
			         "(%zu other formats)",
			         d->nformats_total);
		else
			e.usable = true;
		rc = fn(ctx, &e);
	}
	free(nodes);
	return rc > 0 ? 0 : rc;
}

static const char *const v_options[] = {"input", "dv", "mosaic", "gain_db_step", NULL};

const pc_source_ops pc_v4l2_source_ops = {
    .open = v_open,
    .close = v_close,
    .get_info = v_get_info,
    .try_format = v_try_format,
    .set_format = v_set_format,
    .control_query = v_control_query,
    .control_get = v_control_get,
    .control_set = v_control_set,
    .buffers_alloc = v_buffers_alloc,
    .buffers_free = v_buffers_free,
    .queue = v_queue,
    .start = v_start,
    .dequeue = v_dequeue,
    .stop = v_stop,
    .get_stats = NULL,
    .options = v_options,
};
