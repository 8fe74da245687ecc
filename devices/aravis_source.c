/* aravis: source - GigE Vision and USB3 Vision cameras through Aravis 0.8.
 *
 *   aravis:ID[?packet_size=N&reverse_x=1&reverse_y=1&mosaic=90,45,135,0&realtime=0]
 *
 * ID is what arv_camera_new accepts: an IP address (opened directly, no discovery broadcast),
 * a device id or a serial number (found through Aravis's discovery: run that inside a network
 * namespace in tests). packet_size sets the GigE Vision packet size in bytes (default: Aravis's
 * automatic negotiation, which picks only 1400 bytes on loopback).
 *
 * Pixel formats are identified by their GenICam enumeration NAME (pc_camera_format_get),
 * never by value: Aravis 0.8 knows no polarized formats and vendors' codes collide with Aravis's
 * custom codes. A format carries the polarizer mosaic when its name says so (PolarizeMono12,
 * Polarized8, the colour BayerRGPolarized8...) or when the camera profile table lists it for
 * this vendor/model (Basler's polarized models use plain Mono names). Each format has its own
 * sensor mosaic (a colour-polarization name gives the IMX250MYR-style 4x4 layout); the mosaic of
 * the ROI is that sensor mosaic, mirrored for ReverseX/ReverseY (pc_mosaic_flip) and shifted by
 * the ROI offset (pc_mosaic_shift).
 *
 * Frame ids: GigE Vision 1.x block ids are 16 bits and wrap (skipping 0 on real cameras); they
 * are unwrapped into a 64-bit sequence so that gaps still count as dropped frames.
 * A camera that stops answering (control lost, or a register read failing after a dequeue
 * timeout) is PC_EDISCONNECTED.
 *
 * Aravis's stream thread receives the packets; when it waits for a CPU longer than the socket
 * buffer lasts (net.core.rmem_max, 4 MiB by default: 13 ms of a 2448x2048 stream at 30 fps),
 * packets are lost and frames arrive incomplete. So the thread asks for real-time scheduling
 * (SCHED_FIFO priority 10, as Aravis's own tools do), else for nice -10, else keeps what it has
 * (both need privileges: CAP_SYS_NICE, or RLIMIT_RTPRIO / RLIMIT_NICE); realtime=0 leaves it
 * alone. It only waits for packets, so it never holds a CPU for long. */
#include "polarcam/camera_profile.h"
#include "polarcam/error.h"
#include "polarcam/source.h"

#include <arv.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "backend_util.h"
#include "backends.h"

typedef struct arv_fmt {
	char name[48];
	pc_pixfmt fmt;
	bool polarized;
	pc_mosaic sensor_mosaic; /* at sensor pixel (0,0), unflipped (polarized formats) */
	int64_t code;            /* to recognise frames: only ever compared, never interpreted */
} arv_fmt;

typedef struct arv_src {
	ArvCamera *cam;
	ArvDevice *dev;
	ArvStream *stream;
	gulong lost_handler;
	gint lost; /* atomic: set by the control-lost signal */
	char vendor[64], model[64], serial[64], device_id[128];
	const pc_camera_profile *profile;
	pc_mosaic user_mosaic; /* the URI's mosaic= (at sensor pixel (0,0), unflipped) */
	bool user_mosaic_set;
	int sensor_w, sensor_h;
	int x_inc, y_inc, w_inc, h_inc, w_min, h_min;
	bool has_reverse_x, has_reverse_y;
	bool reverse_x, reverse_y;
	uint64_t packet_size; /* 0 = auto */
	bool realtime;        /* the stream thread asks for real-time scheduling */
	arv_fmt *fmts;
	unsigned n_fmts;
	int64_t cur_code;
	/* frame id unwrapping */
	bool have_id, seen_zero, wide_ids;
	uint64_t last_id, seq;
	uint64_t last_ts;
	/* statistics of finished streams */
	pc_source_stats done;
	/* the exposure and gain the frames report: read at start and after each control set
	 * (NAN: the camera has no such control); a camera's own auto-exposure or auto-gain is not
	 * followed */
	double meta_exposure_us, meta_gain_db;
} arv_src;

static int gerr(int code, GError **err, const char *what)
{
	int rc = pc_error(code, "aravis: %s: %s", what, *err ? (*err)->message : "failed");
	g_clear_error(err);
	return rc;
}

static void on_control_lost(ArvDevice *dev, gpointer user)
{
	(void)dev;
	arv_src *a = user;
	g_atomic_int_set(&a->lost, 1);
}

/* The mosaic at pixel (0,0) of the full, possibly mirrored, readout in format e. */
static pc_mosaic readout_mosaic(const arv_src *a, const arv_fmt *e)
{
	return pc_mosaic_flip(&e->sensor_mosaic, a->reverse_x, a->reverse_y, (uint32_t)a->sensor_w,
	                      (uint32_t)a->sensor_h);
}

static int load_formats(arv_src *a)
{
	GError *err = NULL;
	guint n = 0;
	const char **names = arv_camera_dup_available_pixel_formats_as_strings(a->cam, &n, &err);
	if (err)
		return gerr(PC_EIO, &err, "listing pixel formats");
	gint64 *codes = arv_camera_dup_available_pixel_formats(a->cam, &n, &err);
	if (err) {
		g_free(names);
		return gerr(PC_EIO, &err, "listing pixel formats");
	}
	a->fmts = calloc(n ? n : 1, sizeof *a->fmts);
	if (!a->fmts) {
		g_free(names);
		g_free(codes);
		return pc_error(PC_ENOMEM, "aravis: pixel formats");
	}
	for (guint i = 0; i < n; i++) {
		pc_camera_format cf;
		if (!names[i] ||
		    pc_camera_format_get(a->profile, names[i],
		                         a->user_mosaic_set ? &a->user_mosaic : NULL, &cf) != 0) {
			pc_error_clear();
			continue; /* RGB, Bayer, processed polarization formats: not raw mosaics */
		}
		arv_fmt *e = &a->fmts[a->n_fmts++];
		snprintf(e->name, sizeof e->name, "%s", names[i]);
		e->fmt = cf.format;
		e->polarized = cf.polarized;
		e->sensor_mosaic = cf.sensor_mosaic;
		e->code = codes[i];
	}
	g_free(names);
	g_free(codes);
	if (a->n_fmts == 0)
		return pc_error(PC_EFORMAT,
		                "aravis: %s %s offers no raw monochrome, polarized or "
		                "colour-polarized pixel format polarcam can read",
		                a->vendor, a->model);
	return 0;
}

static void a_close(pc_source *s);

static int a_open(pc_source *s, const char *arg)
{
	if (!*arg)
		return pc_error(PC_EINVAL,
		                "aravis: expected a device id, serial number or IP address "
		                "(aravis:ID)");
	arv_src *a = calloc(1, sizeof *a);
	if (!a)
		return pc_error(PC_ENOMEM, "aravis source");
	bool rx = false, ry = false;
	a->realtime = true;
	int rc = pc_source_option_u64(s, "packet_size", 576, 65500, &a->packet_size);
	if (!rc)
		rc = pc_source_option_bool(s, "realtime", &a->realtime);
	if (!rc)
		rc = pc_source_option_bool(s, "reverse_x", &rx);
	if (!rc)
		rc = pc_source_option_bool(s, "reverse_y", &ry);
	const char *mosaic = pc_source_option(s, "mosaic");
	if (!rc && mosaic) {
		rc = pc_mosaic_parse(mosaic, &a->user_mosaic);
		if (rc)
			rc = pc_error_prefix(PC_EINVAL, "URI option mosaic: ");
		a->user_mosaic_set = true;
	}
	if (rc) {
		free(a);
		return rc;
	}
	GError *err = NULL;
	a->cam = arv_camera_new(arg, &err);
	if (!a->cam) {
		rc = pc_error(PC_ENOENT, "aravis: no camera '%s': %s", arg,
		              err ? err->message : "not found");
		g_clear_error(&err);
		free(a);
		return rc;
	}
	pc_source_set_priv(s, a);
	a->dev = arv_camera_get_device(a->cam);
	a->lost_handler = g_signal_connect(a->dev, "control-lost", G_CALLBACK(on_control_lost), a);
	/* Aravis's string getters return storage the next call may reuse: copy each at once */
	const char *t = arv_camera_get_vendor_name(a->cam, NULL);
	snprintf(a->vendor, sizeof a->vendor, "%s", t ? t : "");
	t = arv_camera_get_model_name(a->cam, NULL);
	snprintf(a->model, sizeof a->model, "%s", t ? t : "");
	t = arv_camera_get_device_serial_number(a->cam, NULL);
	snprintf(a->serial, sizeof a->serial, "%s", t ? t : "");
	t = arv_camera_get_device_id(a->cam, NULL);
	snprintf(a->device_id, sizeof a->device_id, "%s", t ? t : arg);
	a->profile = pc_camera_profile_find(a->vendor, a->model);
	arv_camera_get_sensor_size(a->cam, &a->sensor_w, &a->sensor_h, &err);
	if (!rc && err)
		rc = gerr(PC_EIO, &err, "reading the sensor size");
	if (!rc && (a->sensor_w <= 0 || a->sensor_h <= 0 || a->sensor_w > 1 << 16 ||
	            a->sensor_h > 1 << 16))
		rc = pc_error(PC_EIO, "aravis: %s reports a %dx%d sensor", a->device_id,
		              a->sensor_w, a->sensor_h);
	if (!rc) {
		bool offsets = arv_camera_is_region_offset_available(a->cam, NULL);
		a->x_inc = offsets ? arv_camera_get_x_offset_increment(a->cam, NULL) : 0;
		a->y_inc = offsets ? arv_camera_get_y_offset_increment(a->cam, NULL) : 0;
		a->w_inc = arv_camera_get_width_increment(a->cam, NULL);
		a->h_inc = arv_camera_get_height_increment(a->cam, NULL);
		int mx;
		arv_camera_get_width_bounds(a->cam, &a->w_min, &mx, NULL);
		arv_camera_get_height_bounds(a->cam, &a->h_min, &mx, NULL);
		if (a->w_inc < 1)
			a->w_inc = 1;
		if (a->h_inc < 1)
			a->h_inc = 1;
		if (a->w_min < 1)
			a->w_min = 1;
		if (a->h_min < 1)
			a->h_min = 1;
		a->has_reverse_x = arv_camera_is_feature_available(a->cam, "ReverseX", NULL);
		a->has_reverse_y = arv_camera_is_feature_available(a->cam, "ReverseY", NULL);
		if ((rx && !a->has_reverse_x) || (ry && !a->has_reverse_y))
			rc = pc_error(PC_ENOTSUP, "aravis: %s %s has no %s feature", a->vendor,
			              a->model, rx && !a->has_reverse_x ? "ReverseX" : "ReverseY");
	}
	if (!rc && a->has_reverse_x) {
		if (pc_source_option(s, "reverse_x"))
			arv_camera_set_boolean(a->cam, "ReverseX", rx, &err);
		a->reverse_x = !err && arv_camera_get_boolean(a->cam, "ReverseX", &err);
		if (err)
			rc = gerr(PC_EIO, &err, "ReverseX");
	}
	if (!rc && a->has_reverse_y) {
		if (pc_source_option(s, "reverse_y"))
			arv_camera_set_boolean(a->cam, "ReverseY", ry, &err);
		a->reverse_y = !err && arv_camera_get_boolean(a->cam, "ReverseY", &err);
		if (err)
			rc = gerr(PC_EIO, &err, "ReverseY");
	}
	if (!rc)
		rc = load_formats(a);
	if (!rc && arv_camera_is_gv_device(a->cam)) {
		if (a->packet_size)
			arv_camera_gv_set_packet_size(a->cam, (gint)a->packet_size, &err);
		else
			arv_camera_gv_auto_packet_size(a->cam, &err);
		if (err)
			rc = gerr(PC_EIO, &err, "setting the packet size");
	}
	if (!rc)
		a->cur_code = arv_camera_get_pixel_format(a->cam, NULL);
	if (rc) { /* the wrapper does not call close after a failed open */
		a_close(s);
		pc_source_set_priv(s, NULL);
	}
	return rc;
}

static void a_close(pc_source *s)
{
	arv_src *a = pc_source_priv(s);
	if (!a)
		return;
	if (a->stream)
		g_object_unref(a->stream);
	if (a->lost_handler)
		g_signal_handler_disconnect(a->dev, a->lost_handler);
	if (a->cam)
		g_object_unref(a->cam);
	free(a->fmts);
	free(a);
}

/* The camera's current format among those listed (codes are unique within one camera's
 * enumeration; only the names were interpreted). */
static const arv_fmt *find_fmt_code(const arv_src *a, int64_t code)
{
	for (unsigned i = 0; i < a->n_fmts; i++)
		if (a->fmts[i].code == code)
			return &a->fmts[i];
	return NULL;
}

/* The camera's black level in DN of the delivered samples, read when asked (it may be
 * changed on the camera): GenICam SFNC BlackLevel (Analog Control; Float, or Integer on some
 * cameras), for the BlackLevelSelector the camera is set to. Unit "%": percent of the full
 * scale of the delivered samples; otherwise DN at the sensor's AdcBitDepth (SFNC, Image Format
 * Control: BitsN) when the camera has it - a format of fewer bits carries the top bits, so the
 * level shrinks by 2^(AdcBitDepth − bits) - else DN as delivered. 0 when the camera has no
 * BlackLevel or reports a negative one (docs/calibration.md, "Black level"). */
static double camera_black_level(arv_src *a, const arv_fmt *e)
{
	ArvGcNode *node = arv_device_get_feature(a->dev, "BlackLevel");
	GError *err = NULL;
	double v = 0;
	const char *unit = NULL;
	if (node && ARV_IS_GC_FLOAT(node)) {
		v = arv_gc_float_get_value(ARV_GC_FLOAT(node), &err);
		unit = arv_gc_float_get_unit(ARV_GC_FLOAT(node));
	} else if (node && ARV_IS_GC_INTEGER(node)) {
		v = (double)arv_gc_integer_get_value(ARV_GC_INTEGER(node), &err);
		unit = arv_gc_integer_get_unit(ARV_GC_INTEGER(node));
	} else {
		return 0;
	}
	if (err || !(v > 0) || !isfinite(v)) {
		g_clear_error(&err);
		return 0;
	}
	unsigned bits = e ? pc_format_info_get(e->fmt)->bits : 0, adc = 0;
	ArvGcNode *an = arv_device_get_feature(a->dev, "AdcBitDepth");
	if (an && ARV_IS_GC_ENUMERATION(an)) {
		const char *s = arv_gc_enumeration_get_string_value(ARV_GC_ENUMERATION(an), &err);
		unsigned n = 0;
		if (!err && s && sscanf(s, "Bits%u", &n) == 1 && n >= 1 && n <= 32)
			adc = n;
		g_clear_error(&err);
	}
	unsigned eff = adc && (!bits || adc < bits) ? adc : bits; /* the samples' real bits */
	if (unit && !strcmp(unit, "%"))
		return eff ? v / 100 * (ldexp(1, (int)eff) - 1) : 0;
	if (adc && bits && bits < adc)
		v = ldexp(v, (int)bits - (int)adc);
	return v;
}

static int a_info(pc_source *s, pc_source_info *info)
{
	arv_src *a = pc_source_priv(s);
	snprintf(info->vendor, sizeof info->vendor, "%s", a->vendor);
	snprintf(info->model, sizeof info->model, "%s", a->model);
	snprintf(info->serial, sizeof info->serial, "%s", a->serial);
	snprintf(info->driver, sizeof info->driver, "aravis-%s",
	         arv_camera_is_gv_device(a->cam)   ? "gv"
	         : arv_camera_is_uv_device(a->cam) ? "uv"
	                                           : "other");
	info->sensor_width = (uint32_t)a->sensor_w;
	info->sensor_height = (uint32_t)a->sensor_h;
	const arv_fmt *e = find_fmt_code(a, a->cur_code);
	for (unsigned i = 0; i < a->n_fmts && !e; i++)
		if (a->fmts[i].polarized)
			e = &a->fmts[i];
	if (e && e->polarized)
		info->mosaic = readout_mosaic(a, e);
	info->black_level = camera_black_level(a, find_fmt_code(a, a->cur_code));
	return 0;
}

static uint32_t round_down(uint32_t v, int inc)
{
	return inc > 1 ? v - v % (uint32_t)inc : v;
}

static int a_try(pc_source *s, pc_source_format *f, pc_format_verdict *v)
{
	arv_src *a = pc_source_priv(s);
	const pc_source_format req = *f;
	bool adj = false;
	const arv_fmt *e = NULL;
	if (req.format_name[0]) {
		for (unsigned i = 0; i < a->n_fmts && !e; i++)
			if (!strcmp(a->fmts[i].name, req.format_name))
				e = &a->fmts[i];
		adj = !e;
	} else if (req.format != PC_FMT_INVALID) {
		for (unsigned pass = 0; pass < 2 && !e; pass++) /* polarized names first */
			for (unsigned i = 0; i < a->n_fmts && !e; i++)
				if (a->fmts[i].fmt == req.format &&
				    a->fmts[i].polarized == (pass == 0))
					e = &a->fmts[i];
		adj = !e;
	}
	if (!e)
		e = find_fmt_code(a, a->cur_code);
	for (unsigned i = 0; i < a->n_fmts && !e; i++)
		if (a->fmts[i].polarized)
			e = &a->fmts[i];
	if (!e)
		e = &a->fmts[0];
	const pc_format_info *fi = pc_format_info_get(e->fmt);
	f->format = e->fmt;
	snprintf(f->format_name, sizeof f->format_name, "%s", e->name);

	uint32_t sw = (uint32_t)a->sensor_w, sh = (uint32_t)a->sensor_h;
	if (req.offset_x >= sw || req.offset_y >= sh) {
		*v = PC_FORMAT_INVALID;
		return pc_error(PC_OK, "aravis: ROI origin (%u,%u) outside the %ux%u sensor",
		                req.offset_x, req.offset_y, sw, sh);
	}
	f->offset_x = a->x_inc ? round_down(req.offset_x, a->x_inc) : 0;
	f->offset_y = a->y_inc ? round_down(req.offset_y, a->y_inc) : 0;
	adj = adj || f->offset_x != req.offset_x || f->offset_y != req.offset_y;
	uint32_t maxw = sw - f->offset_x, maxh = sh - f->offset_y;
	uint32_t w = req.width ? req.width : maxw, h = req.height ? req.height : maxh;
	if (w > maxw)
		w = maxw;
	if (h > maxh)
		h = maxh;
	/* width: the camera's increment and the packing group of the format */
	unsigned winc = (unsigned)a->w_inc;
	while (winc % fi->group_pixels)
		winc += (unsigned)a->w_inc;
	w = round_down(w, (int)winc);
	h = round_down(h, a->h_inc);
	if (w < (uint32_t)a->w_min || h < (uint32_t)a->h_min || w == 0 || h == 0) {
		*v = PC_FORMAT_INVALID;
		return pc_error(PC_OK, "aravis: ROI %ux%u below the camera's minimum %dx%d", w, h,
		                a->w_min, a->h_min);
	}
	adj = adj || (req.width && w != req.width) || (req.height && h != req.height);
	f->width = w;
	f->height = h;
	size_t row;
	int rc = pc_format_row_bytes(f->format, w, &row);
	if (rc)
		return rc;
	if (req.stride && req.stride != row)
		adj = true; /* GigE Vision / USB3 Vision payloads are tightly packed */
	f->stride = row;
	f->frame_bytes = 0;
	f->sensor_width = sw;
	f->sensor_height = sh;
	f->polarized = e->polarized;
	pc_mosaic rm = readout_mosaic(a, e);
	if (!e->polarized)
		memset(&f->mosaic, 0, sizeof f->mosaic);
	rc = pc_source_format_complete(f, e->polarized ? &rm : NULL);
	if (rc)
		return rc;
	*v = adj ? PC_FORMAT_ADJUSTED : PC_FORMAT_VALID;
	return 0;
}

static int a_set(pc_source *s, const pc_source_format *f)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	arv_camera_set_pixel_format_from_string(a->cam, f->format_name, &err);
	if (err)
		return gerr(PC_EIO, &err, "setting the pixel format");
	arv_camera_set_region(a->cam, (gint)f->offset_x, (gint)f->offset_y, (gint)f->width,
	                      (gint)f->height, &err);
	if (err)
		return gerr(PC_EIO, &err, "setting the region");
	gint x, y, w, h;
	arv_camera_get_region(a->cam, &x, &y, &w, &h, &err);
	if (err)
		return gerr(PC_EIO, &err, "reading the region back");
	const char *name = arv_camera_get_pixel_format_as_string(a->cam, &err);
	if (err)
		return gerr(PC_EIO, &err, "reading the pixel format back");
	if ((uint32_t)x != f->offset_x || (uint32_t)y != f->offset_y || (uint32_t)w != f->width ||
	    (uint32_t)h != f->height || !name || strcmp(name, f->format_name))
		return pc_error(PC_EIO,
		                "aravis: the camera kept %s %dx%d at (%d,%d) instead of %s "
		                "%ux%u at (%u,%u)",
		                name ? name : "?", w, h, x, y, f->format_name, f->width, f->height,
		                f->offset_x, f->offset_y);
	guint payload = arv_camera_get_payload(a->cam, &err);
	if (err)
		return gerr(PC_EIO, &err, "reading the payload size");
	if (payload > f->frame_bytes)
		return pc_error(PC_EFORMAT,
		                "aravis: the camera sends %u bytes per frame, a %s %ux%u "
		                "image is %zu (chunk data enabled?)",
		                payload, f->format_name, f->width, f->height, f->frame_bytes);
	a->cur_code = arv_camera_get_pixel_format(a->cam, NULL);
	return 0;
}

/* ---- controls ---- */

static int a_cquery(pc_source *s, pc_control_id id, pc_control_info *ci)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	memset(ci, 0, sizeof *ci);
	ci->live = true;
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		if (!arv_camera_is_exposure_time_available(a->cam, NULL))
			return pc_error(PC_ENOTSUP, "aravis: no exposure time control");
		arv_camera_get_exposure_time_bounds(a->cam, &ci->min, &ci->max, &err);
		break;
	case PC_CTRL_GAIN_DB:
		if (!arv_camera_is_gain_available(a->cam, NULL))
			return pc_error(PC_ENOTSUP, "aravis: no gain control");
		arv_camera_get_gain_bounds(a->cam, &ci->min, &ci->max, &err);
		break;
	case PC_CTRL_FRAME_RATE_HZ:
		if (!arv_camera_is_frame_rate_available(a->cam, NULL))
			return pc_error(PC_ENOTSUP, "aravis: no frame rate control");
		arv_camera_get_frame_rate_bounds(a->cam, &ci->min, &ci->max, &err);
		break;
	default:
		return pc_error(PC_ENOTSUP, "aravis: unknown control");
	}
	if (err)
		return gerr(PC_EIO, &err, pc_control_name(id));
	ci->def = ci->min; /* cameras do not publish defaults through GenICam */
	return 0;
}

static int a_cget(pc_source *s, pc_control_id id, double *val)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		*val = arv_camera_get_exposure_time(a->cam, &err);
		break;
	case PC_CTRL_GAIN_DB:
		*val = arv_camera_get_gain(a->cam, &err);
		break;
	case PC_CTRL_FRAME_RATE_HZ:
		*val = arv_camera_get_frame_rate(a->cam, &err);
		break;
	default:
		return pc_error(PC_ENOTSUP, "aravis: unknown control");
	}
	return err ? gerr(PC_EIO, &err, pc_control_name(id)) : 0;
}

/* Whether the camera sets the exposure or the gain itself (GenICam SFNC ExposureAuto,
 * GainAuto: Continuous, or Once while it runs): a value read then is stale by the next frame.
 * A camera without the feature, or one that does not answer, has it off. */
static bool a_auto(arv_src *a, pc_control_id id)
{
	GError *err = NULL;
	ArvAuto m = ARV_AUTO_OFF;
	if (id == PC_CTRL_GAIN_DB && arv_camera_is_gain_auto_available(a->cam, NULL))
		m = arv_camera_get_gain_auto(a->cam, &err);
	else if (id == PC_CTRL_EXPOSURE_US && arv_camera_is_exposure_auto_available(a->cam, NULL))
		m = arv_camera_get_exposure_time_auto(a->cam, &err);
	if (err) {
		g_clear_error(&err);
		return false;
	}
	return m != ARV_AUTO_OFF;
}

static int a_cset(pc_source *s, pc_control_id id, double val, double *applied)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	/* a value asked for is a fixed one: the camera's own adjustment of it is turned off
	 * first (otherwise it would overwrite the value, or refuse it) */
	if (id == PC_CTRL_GAIN_DB && a_auto(a, id))
		arv_camera_set_gain_auto(a->cam, ARV_AUTO_OFF, &err);
	else if (id == PC_CTRL_EXPOSURE_US && a_auto(a, id))
		arv_camera_set_exposure_time_auto(a->cam, ARV_AUTO_OFF, &err);
	if (err)
		return gerr(PC_EIO, &err, "turning the camera's automatic adjustment off");
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		arv_camera_set_exposure_time(a->cam, val, &err);
		break;
	case PC_CTRL_GAIN_DB:
		arv_camera_set_gain(a->cam, val, &err);
		break;
	case PC_CTRL_FRAME_RATE_HZ:
		arv_camera_set_frame_rate(a->cam, val, &err);
		break;
	default:
		return pc_error(PC_ENOTSUP, "aravis: unknown control");
	}
	if (err)
		return gerr(PC_EIO, &err, pc_control_name(id));
	int rc = a_cget(s, id, applied);
	if (!rc && id == PC_CTRL_EXPOSURE_US)
		a->meta_exposure_us = *applied;
	if (!rc && id == PC_CTRL_GAIN_DB)
		a->meta_gain_db = *applied;
	return rc;
}

/* what the frames will report: the camera's exposure and gain now (NAN where it has none, and
 * where the camera adjusts it itself: the value would be stale, and a stale gain would scale a
 * calibration's noise gain and dark map wrongly) */
static void read_meta_controls(pc_source *s)
{
	arv_src *a = pc_source_priv(s);
	double v;
	a->meta_exposure_us = a->meta_gain_db = NAN;
	if (arv_camera_is_exposure_time_available(a->cam, NULL) &&
	    !a_auto(a, PC_CTRL_EXPOSURE_US) && a_cget(s, PC_CTRL_EXPOSURE_US, &v) == 0 &&
	    isfinite(v))
		a->meta_exposure_us = v;
	if (arv_camera_is_gain_available(a->cam, NULL) && !a_auto(a, PC_CTRL_GAIN_DB) &&
	    a_cget(s, PC_CTRL_GAIN_DB, &v) == 0 && isfinite(v))
		a->meta_gain_db = v;
	pc_error_clear();
}

/* ---- streaming ---- */

static void collect_stats(arv_src *a, pc_source_stats *st)
{
	memset(st, 0, sizeof *st);
	if (!a->stream)
		return;
	guint64 completed = 0, failures = 0, underruns = 0;
	arv_stream_get_statistics(a->stream, &completed, &failures, &underruns);
	st->underruns = underruns;
	if (ARV_IS_GV_STREAM(a->stream)) {
		st->has_packets = true;
		st->missing_packets =
		    arv_stream_get_info_uint64_by_name(a->stream, "n_missing_packets");
		st->resent_packets =
		    arv_stream_get_info_uint64_by_name(a->stream, "n_resent_packets");
		st->transport_failures =
		    arv_stream_get_info_uint64_by_name(a->stream, "n_size_mismatch_errors");
	}
}

/* Aravis calls this in its stream thread; at its start the thread asks for priority. */
static void stream_cb(void *user, ArvStreamCallbackType type, ArvBuffer *buffer)
{
	(void)buffer;
	const arv_src *a = user;
	if (type != ARV_STREAM_CALLBACK_TYPE_INIT || !a->realtime)
		return;
	struct sched_param sp;
	memset(&sp, 0, sizeof sp);
	sp.sched_priority = 10;
	if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0)
		return;
	id_t tid = (id_t)syscall(SYS_gettid);
	errno = 0;
	int nice_now = getpriority(PRIO_PROCESS, tid);
	if (errno == 0 && nice_now > -10)
		(void)setpriority(PRIO_PROCESS, tid, -10); /* may be refused: normal priority */
}

static int a_queue(pc_source *s, pc_buffer *b)
{
	arv_src *a = pc_source_priv(s);
	if (!a->stream) {
		GError *err = NULL;
		a->stream = arv_camera_create_stream(a->cam, stream_cb, a, &err);
		if (!a->stream)
			return gerr(g_atomic_int_get(&a->lost) ? PC_EDISCONNECTED : PC_EIO, &err,
			            "creating the stream");
	}
	ArvBuffer *ab = arv_buffer_new_full(b->size, b->data, b, NULL);
	if (!ab)
		return pc_error(PC_ENOMEM, "aravis: buffer");
	arv_stream_push_buffer(a->stream, ab);
	return 0;
}

static int a_start(pc_source *s)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	a->have_id = false;
	a->last_ts = 0;
	a->seen_zero = false;
	a->wide_ids = false;
	read_meta_controls(s);
	arv_camera_start_acquisition(a->cam, &err);
	if (err)
		return gerr(g_atomic_int_get(&a->lost) ? PC_EDISCONNECTED : PC_EIO, &err,
		            "starting the acquisition");
	return 0;
}

static int a_stop(pc_source *s)
{
	arv_src *a = pc_source_priv(s);
	GError *err = NULL;
	int rc = 0;
	if (!g_atomic_int_get(&a->lost)) {
		arv_camera_stop_acquisition(a->cam, &err);
		if (err)
			rc = gerr(PC_EIO, &err, "stopping the acquisition");
	}
	if (a->stream) {
		pc_source_stats st;
		collect_stats(a, &st);
		a->done.underruns += st.underruns;
		a->done.missing_packets += st.missing_packets;
		a->done.resent_packets += st.resent_packets;
		a->done.transport_failures += st.transport_failures;
		a->done.has_packets |= st.has_packets;
		/* the stream's queued ArvBuffers only wrap our memory: dropping the stream
		 * releases every one of them */
		g_object_unref(a->stream);
		a->stream = NULL;
	}
	return rc;
}

/* 64-bit sequence from GigE Vision 1.x 16-bit block ids (0 is skipped by real cameras on
 * wrap-around; Aravis's simulator sends it). */
static uint64_t unwrap_id(arv_src *a, uint64_t id, bool damaged)
{
	if (damaged && a->have_id) {
		/* a damaged frame's id may be missing (0) or stale: unless it is exactly the next
		 * one, take it as the next frame and keep counting from there */
		uint64_t next = a->wide_ids ? a->last_id + 1 : (a->last_id + 1) & 0xffff;
		if (id != next && !(next == 0 && id == 1)) {
			a->last_id = next;
			a->seq += 1;
			return a->seq;
		}
	}
	if (id > 0xffff)
		a->wide_ids = true;
	if (!a->have_id) {
		a->have_id = true;
		a->last_id = id;
		a->seq = a->wide_ids ? id : id & 0xffff;
		if (id == 0)
			a->seen_zero = true;
		return a->seq;
	}
	uint64_t delta;
	if (a->wide_ids) {
		delta = id > a->last_id ? id - a->last_id : 1;
	} else {
		delta = (id - a->last_id) & 0xffff;
		if (id == 0)
			a->seen_zero = true;
		if (delta == 0)
			delta =
			    1; /* a repeated id: the wrapper still needs an increasing sequence */
		else if (id < a->last_id && id != 0 && !a->seen_zero && delta >= 2)
			delta--; /* wrapped past the id 0 the camera never sends */
	}
	a->last_id = id;
	a->seq += delta;
	return a->seq;
}

/* Is the camera still there? A register read costs one GVCP round trip. */
static bool camera_alive(arv_src *a)
{
	if (g_atomic_int_get(&a->lost))
		return false;
	guint32 v;
	GError *err = NULL;
	gboolean ok = arv_device_read_register(a->dev, 0x0, &v, &err);
	g_clear_error(&err);
	return ok;
}

static int a_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	arv_src *a = pc_source_priv(s);
	const pc_source_format *f = pc_source_current_format(s);
	if (!a->stream)
		return pc_error(PC_EIO, "aravis: no stream");
	guint64 to_us = timeout_ms < 0 ? G_MAXUINT64 / 2 : (guint64)timeout_ms * 1000u;
	ArvBuffer *ab = arv_stream_timeout_pop_buffer(a->stream, to_us);
	if (!ab) {
		if (!camera_alive(a)) {
			g_atomic_int_set(&a->lost, 1);
			return pc_error(PC_EDISCONNECTED, "aravis: camera %s stopped answering",
			                a->device_id);
		}
		return pc_error(PC_ETIMEDOUT, "aravis: no frame from %s within %d ms", a->device_id,
		                timeout_ms);
	}
	pc_buffer *b = (pc_buffer *)arv_buffer_get_user_data(ab);
	ArvBufferStatus st = arv_buffer_get_status(ab);
	uint32_t status = 0;
	switch (st) {
	case ARV_BUFFER_STATUS_SUCCESS:
		break;
	case ARV_BUFFER_STATUS_MISSING_PACKETS:
	case ARV_BUFFER_STATUS_TIMEOUT:
	case ARV_BUFFER_STATUS_ABORTED:
		status |= PC_FRAME_INCOMPLETE;
		break;
	default:
		status |= PC_FRAME_CORRUPT;
		break;
	}
	size_t row = 0, image_bytes;
	(void)pc_format_row_bytes(f->format, f->width, &row);
	image_bytes = row * f->height;
	const void *data = b->data;
	if (st == ARV_BUFFER_STATUS_SUCCESS) {
		size_t size = 0;
		const void *img = arv_buffer_get_image_data(ab, &size);
		/* every camera datum is checked: geometry, pixel format (by the code the name was
		 * given when negotiated) and payload size */
		if ((uint32_t)arv_buffer_get_image_width(ab) != f->width ||
		    (uint32_t)arv_buffer_get_image_height(ab) != f->height ||
		    (int64_t)arv_buffer_get_image_pixel_format(ab) != a->cur_code)
			status |= PC_FRAME_CORRUPT;
		else if (!img || size < image_bytes)
			status |= PC_FRAME_INCOMPLETE;
		else if ((const uint8_t *)img != (const uint8_t *)b->data)
			status |=
			    PC_FRAME_CORRUPT; /* an image part elsewhere: not what we negotiated */
	}
	b->frame.view = (pc_view){(void *)data, f->width, f->height, f->stride, f->format};
	memset(&b->frame.meta, 0, sizeof b->frame.meta);
	b->frame.meta.sequence = unwrap_id(a, arv_buffer_get_frame_id(ab), status != 0);
	uint64_t ts = arv_buffer_get_timestamp(ab);
	if (!ts)
		ts = arv_buffer_get_system_timestamp(ab);
	/* a frame whose leader packet was lost has no timestamp: it is flagged incomplete and
	 * keeps the previous frame's time (a successful frame going back in time is refused by
	 * the wrapper as bad camera data) */
	if (status && ts < a->last_ts)
		ts = a->last_ts;
	a->last_ts = ts;
	b->frame.meta.timestamp_ns = ts;
	b->frame.meta.status = status;
	b->frame.meta.exposure_us = a->meta_exposure_us;
	b->frame.meta.gain_db = a->meta_gain_db;
	g_object_unref(ab);
	*out = b;
	return 0;
}

static int a_stats(pc_source *s, pc_source_stats *st)
{
	arv_src *a = pc_source_priv(s);
	collect_stats(a, st);
	st->underruns += a->done.underruns;
	st->missing_packets += a->done.missing_packets;
	st->resent_packets += a->done.resent_packets;
	st->transport_failures += a->done.transport_failures;
	st->has_packets |= a->done.has_packets;
	return 0;
}

int pc_aravis_enumerate(unsigned flags, pc_device_fn fn, void *ctx)
{
	/* GigE Vision discovery broadcasts on every interface: only when asked for. USB3 Vision
	 * enumeration stays local. */
	if (flags & PC_ENUM_NETWORK)
		arv_enable_interface("GigEVision");
	else
		arv_disable_interface("GigEVision");
	arv_update_device_list();
	unsigned n = arv_get_n_devices();
	for (unsigned i = 0; i < n; i++) {
		pc_device_entry e;
		memset(&e, 0, sizeof e);
		const char *id = arv_get_device_id(i), *proto = arv_get_device_protocol(i);
		snprintf(e.uri, sizeof e.uri, "aravis:%s", id ? id : "?");
		snprintf(e.vendor, sizeof e.vendor, "%s",
		         arv_get_device_vendor(i) ? arv_get_device_vendor(i) : "");
		snprintf(e.model, sizeof e.model, "%s",
		         arv_get_device_model(i) ? arv_get_device_model(i) : "");
		snprintf(e.serial, sizeof e.serial, "%s",
		         arv_get_device_serial_nbr(i) ? arv_get_device_serial_nbr(i) : "");
		snprintf(e.transport, sizeof e.transport, "%s",
		         proto && !strcmp(proto, "GigEVision")   ? "GigE Vision"
		         : proto && !strcmp(proto, "USB3Vision") ? "USB3 Vision"
		                                                 : (proto ? proto : "?"));
		snprintf(e.address, sizeof e.address, "%s",
		         arv_get_device_address(i) ? arv_get_device_address(i) : "");
		const pc_camera_profile *p = pc_camera_profile_find(e.vendor, e.model);
		snprintf(e.note, sizeof e.note, "%s", p ? p->sensor : "");
		e.usable = true;
		if (fn(ctx, &e))
			break;
	}
	return 0;
}

static const char *const a_options[] = {"packet_size", "reverse_x", "reverse_y",
                                        "mosaic",      "realtime",  NULL};

const pc_source_ops pc_aravis_source_ops = {
    .open = a_open,
    .close = a_close,
    .get_info = a_info,
    .try_format = a_try,
    .set_format = a_set,
    .control_query = a_cquery,
    .control_get = a_cget,
    .control_set = a_cset,
    .queue = a_queue,
    .start = a_start,
    .dequeue = a_dequeue,
    .stop = a_stop,
    .get_stats = a_stats,
    .options = a_options,
};
