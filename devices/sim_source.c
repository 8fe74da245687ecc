/* sim: source - the simulator as a camera.
 *
 *   sim:SCENE[?seed=S&fps=F&first=N&threads=T&<faults>]
 *
 * SCENE is a scene file (docs/scene-format.md) or "default". Frame k of a stream is simulator
 * frame first + k (plus the frames skipped by drop faults): a pure function of (scene, seed,
 * ROI, controls, frame number), so `sim:SCENE?seed=S` delivers exactly what `polarcam render
 * SCENE --seed S` writes. Frames are paced at fps (default: the scene's frame rate; 0 = as fast
 * as they render) from the stream start: frame k is due at start + k / fps, never after an
 * accumulated sleep. Timestamps are the simulator's (frame number / the scene's frame rate).
 *
 * Negotiation: any ROI (odd offsets shift the mosaic; ROI frames are bit-identical crops of
 * full frames), any integer pixel format with at least the sensor's bits (packed ones too),
 * any stride holding a row. Controls: exposure_us and gain_db per frame (live, no re-render),
 * frame_rate_hz (live).
 *
 * Misbehaviour on demand, for testing applications and the compliance test:
 *   drop_every=K        every K-th frame is never delivered (a sequence gap: "dropped")
 *   timeout_every=K     every K-th frame stalls: that dequeue answers PC_ETIMEDOUT after its
 *                       full timeout, the frame comes with the next call
 *   corrupt_every=K     every K-th frame arrives flagged PC_FRAME_INCOMPLETE with its last row
 *                       zeroed (as a frame with lost packets)
 *   disconnect_after=N  after N delivered frames the camera is gone (PC_EDISCONNECTED)
 *   stride_pad=B        the natural stride is the row plus B bytes (padded strides)
 *   roi=X,Y,W,H         the default format is this ROI (odd offsets shift the mosaic) */
#include "polarcam/error.h"
#include "polarcam/sim.h"
#include "polarcam/source.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "backend_util.h"
#include "backends.h"

typedef struct sim_src {
	pc_scene *scene;
	char scene_name[48];
	pc_sim *sim;      /* for the current ROI and format */
	pc_sim_info full; /* the full sensor in its natural format */
	pc_sim_options opt;
	uint32_t cur_roi[4];
	pc_pixfmt cur_fmt;
	pc_sim_controls ctl;
	double fps;
	uint64_t first;
	uint64_t drop_every, timeout_every, corrupt_every, disconnect_after, stride_pad;
	uint32_t def_roi[4];
	bool def_roi_set;
	/* stream */
	pc_bfifo q;
	pc_pacer pacer;
	uint64_t k; /* slots since start (each slot is one simulator frame number) */
	uint64_t delivered;
	bool stalled; /* the current slot already answered one timeout */
} sim_src;

static int parse_roi(const char *v, uint32_t r[4])
{
	unsigned long a[4];
	char tail;
	if (!v || sscanf(v, "%lu,%lu,%lu,%lu%c", &a[0], &a[1], &a[2], &a[3], &tail) != 4 ||
	    strchr(v, '-') || a[2] == 0 || a[3] == 0 || a[0] > 1u << 20 || a[1] > 1u << 20 ||
	    a[2] > 1u << 20 || a[3] > 1u << 20)
		return pc_error(PC_EINVAL, "URI option roi=%s: expected X,Y,W,H with W, H >= 1",
		                v ? v : "");
	for (int i = 0; i < 4; i++)
		r[i] = (uint32_t)a[i];
	return 0;
}

static void s_close(pc_source *s);

static int s_open(pc_source *s, const char *arg)
{
	if (!*arg)
		return pc_error(PC_EINVAL, "sim: expected a scene file or 'default' (sim:SCENE)");
	sim_src *m = calloc(1, sizeof *m);
	if (!m)
		return pc_error(PC_ENOMEM, "sim source");
	pc_source_set_priv(s, m);
	m->opt = pc_sim_options_default();
	m->opt.seed = 0;
	uint64_t threads = 0;
	double fps = -1;
	int rc = pc_source_option_u64(s, "seed", 0, UINT64_MAX, &m->opt.seed);
	if (!rc)
		rc = pc_source_option_double(s, "fps", 0, 100000, &fps);
	if (!rc)
		rc = pc_source_option_u64(s, "first", 0, UINT64_MAX / 4, &m->first);
	if (!rc)
		rc = pc_source_option_u64(s, "threads", 0, 1024, &threads);
	if (!rc)
		rc = pc_source_option_u64(s, "drop_every", 2, UINT32_MAX, &m->drop_every);
	if (!rc)
		rc = pc_source_option_u64(s, "timeout_every", 2, UINT32_MAX, &m->timeout_every);
	if (!rc)
		rc = pc_source_option_u64(s, "corrupt_every", 1, UINT32_MAX, &m->corrupt_every);
	if (!rc)
		rc = pc_source_option_u64(s, "disconnect_after", 0, UINT64_MAX / 4,
		                          &m->disconnect_after);
	if (!rc)
		rc = pc_source_option_u64(s, "stride_pad", 0, 1u << 20, &m->stride_pad);
	const char *roi = pc_source_option(s, "roi");
	if (!rc && roi) {
		rc = parse_roi(roi, m->def_roi);
		m->def_roi_set = !rc;
	}
	m->opt.threads = (int)threads;
	if (!rc)
		rc = !strcmp(arg, "default") ? pc_scene_load_default(&m->scene)
		                             : pc_scene_load(arg, &m->scene);
	if (!rc)
		rc = pc_sim_new(m->scene, &m->opt, &m->sim);
	if (rc) {
		s_close(s);
		pc_source_set_priv(s, NULL);
		return rc;
	}
	snprintf(m->scene_name, sizeof m->scene_name, "%s",
	         pc_scene_name(m->scene) ? pc_scene_name(m->scene) : arg);
	pc_sim_get_info(m->sim, &m->full);
	m->cur_fmt = m->full.format;
	m->cur_roi[2] = m->full.width;
	m->cur_roi[3] = m->full.height;
	m->ctl.exposure_us = m->full.exposure_us;
	m->ctl.gain_db = m->full.gain_db;
	m->fps = fps >= 0 ? fps : m->full.frame_rate_hz;
	if (!pc_source_option(s, "disconnect_after"))
		m->disconnect_after = UINT64_MAX; /* never */
	if (m->def_roi_set &&
	    (m->def_roi[0] >= m->full.sensor_width || m->def_roi[1] >= m->full.sensor_height ||
	     m->def_roi[2] > m->full.sensor_width - m->def_roi[0] ||
	     m->def_roi[3] > m->full.sensor_height - m->def_roi[1])) {
		rc = pc_error(PC_EINVAL, "URI option roi=%s: outside the %ux%u sensor", roi,
		              m->full.sensor_width, m->full.sensor_height);
		s_close(s);
		pc_source_set_priv(s, NULL);
	}
	return rc;
}

static void s_close(pc_source *s)
{
	sim_src *m = pc_source_priv(s);
	if (!m)
		return;
	pc_sim_free(m->sim);
	pc_scene_free(m->scene);
	free(m);
}

static int s_info(pc_source *s, pc_source_info *info)
{
	sim_src *m = pc_source_priv(s);
	snprintf(info->vendor, sizeof info->vendor, "polarcam");
	snprintf(info->model, sizeof info->model, "simulator: %s", m->scene_name);
	snprintf(info->serial, sizeof info->serial, "seed %llu", (unsigned long long)m->opt.seed);
	snprintf(info->driver, sizeof info->driver, "polarcam-sim");
	info->sensor_width = m->full.sensor_width;
	info->sensor_height = m->full.sensor_height;
	info->polarized = true;
	/* the full sensor's mosaic: the natural-format info is for the full sensor */
	info->mosaic = m->full.mosaic;
	pc_sensor_figures fig;
	pc_sim_get_sensor(m->sim, &fig);
	info->black_level = fig.offset_dn;
	return 0;
}

static int s_try(pc_source *s, pc_source_format *f, pc_format_verdict *v)
{
	sim_src *m = pc_source_priv(s);
	bool empty = !f->width && !f->height && !f->offset_x && !f->offset_y && !f->format &&
	             !f->format_name[0] && !f->stride;
	if (empty && m->def_roi_set) {
		f->offset_x = m->def_roi[0];
		f->offset_y = m->def_roi[1];
		f->width = m->def_roi[2];
		f->height = m->def_roi[3];
	}
	bool want_stride = f->stride != 0;
	int rc = pc_negotiate_flexible(f, m->full.format, m->full.sensor_width,
	                               m->full.sensor_height, true, &m->full.mosaic, v);
	if (rc || *v == PC_FORMAT_INVALID)
		return rc;
	if (!want_stride && m->stride_pad) {
		/* the simulated camera's natural stride is padded (stride_pad) */
		f->stride += m->stride_pad;
		f->frame_bytes = 0;
		rc = pc_source_format_complete(f, &m->full.mosaic);
	}
	return rc;
}

static int s_set(pc_source *s, const pc_source_format *f)
{
	sim_src *m = pc_source_priv(s);
	if (f->offset_x == m->cur_roi[0] && f->offset_y == m->cur_roi[1] &&
	    f->width == m->cur_roi[2] && f->height == m->cur_roi[3] && f->format == m->cur_fmt)
		return 0;
	pc_sim_options o = m->opt;
	o.roi_x = f->offset_x;
	o.roi_y = f->offset_y;
	o.roi_width = f->width;
	o.roi_height = f->height;
	o.format = f->format;
	pc_sim *sim = NULL;
	int rc = pc_sim_new(m->scene, &o, &sim);
	if (rc)
		return rc;
	pc_sim_free(m->sim);
	m->sim = sim;
	m->cur_roi[0] = f->offset_x;
	m->cur_roi[1] = f->offset_y;
	m->cur_roi[2] = f->width;
	m->cur_roi[3] = f->height;
	m->cur_fmt = f->format;
	return 0;
}

static int s_cquery(pc_source *s, pc_control_id id, pc_control_info *ci)
{
	sim_src *m = pc_source_priv(s);
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		*ci = (pc_control_info){1, 1e7, 0, m->full.exposure_us, true};
		return 0;
	case PC_CTRL_GAIN_DB:
		*ci = (pc_control_info){0, 48, 0, m->full.gain_db, true};
		return 0;
	case PC_CTRL_FRAME_RATE_HZ:
		*ci = (pc_control_info){0, 10000, 0, m->full.frame_rate_hz, true};
		return 0;
	default:
		return pc_error(PC_ENOTSUP, "sim: unknown control");
	}
}

static int s_cget(pc_source *s, pc_control_id id, double *val)
{
	sim_src *m = pc_source_priv(s);
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		*val = m->ctl.exposure_us;
		return 0;
	case PC_CTRL_GAIN_DB:
		*val = m->ctl.gain_db;
		return 0;
	case PC_CTRL_FRAME_RATE_HZ:
		*val = m->fps;
		return 0;
	default:
		return pc_error(PC_ENOTSUP, "sim: unknown control");
	}
}

static int s_cset(pc_source *s, pc_control_id id, double val, double *applied)
{
	sim_src *m = pc_source_priv(s);
	switch (id) {
	case PC_CTRL_EXPOSURE_US:
		m->ctl.exposure_us = val;
		break;
	case PC_CTRL_GAIN_DB:
		m->ctl.gain_db = val;
		break;
	case PC_CTRL_FRAME_RATE_HZ:
		m->fps = val;
		pc_pacer_set_rate(&m->pacer, val, m->k);
		break;
	default:
		return pc_error(PC_ENOTSUP, "sim: unknown control");
	}
	*applied = val;
	return 0;
}

static int s_queue(pc_source *s, pc_buffer *b)
{
	return pc_bfifo_push(&((sim_src *)pc_source_priv(s))->q, b);
}

static int s_start(pc_source *s)
{
	sim_src *m = pc_source_priv(s);
	/* the default format (never set explicitly) may be an ROI of its own */
	int rc = s_set(s, pc_source_current_format(s));
	if (rc)
		return rc;
	pc_sim_info info;
	pc_sim_get_info(m->sim, &info);
	/* render every polarization state now, so that pacing starts with frames that cost only
	 * the sensor chain */
	for (unsigned st = 0; st < (info.n_states ? info.n_states : 1); st++) {
		if (pc_sim_is_prepared(m->sim, st))
			continue;
		rc = pc_sim_prepare(m->sim, st, NULL, NULL, NULL, NULL);
		if (rc)
			return rc;
	}
	m->k = 0;
	m->delivered = 0;
	m->stalled = false;
	pc_pacer_start(&m->pacer, m->fps, pc_clock_ns(), 0);
	return 0;
}

static int s_stop(pc_source *s)
{
	pc_bfifo_clear(&((sim_src *)pc_source_priv(s))->q);
	return 0;
}

static int s_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	sim_src *m = pc_source_priv(s);
	if (m->delivered >= m->disconnect_after)
		return pc_error(PC_EDISCONNECTED,
		                "sim: simulated camera unplugged after %llu frames "
		                "(disconnect_after)",
		                (unsigned long long)m->disconnect_after);
	uint64_t now = pc_clock_ns();
	uint64_t deadline = timeout_ms < 0 ? UINT64_MAX : now + (uint64_t)timeout_ms * 1000000u;
	/* dropped frames: their slots pass without a frame */
	while (m->drop_every && (m->first + m->k) % m->drop_every == m->drop_every - 1)
		m->k++;
	if (!m->q.count) {
		if (timeout_ms > 0)
			pc_sleep_until_ns(deadline);
		return pc_error(PC_ETIMEDOUT,
		                "sim: no buffer queued (the application holds them all)");
	}
	if (m->timeout_every && !m->stalled &&
	    (m->first + m->k) % m->timeout_every == m->timeout_every - 1) {
		m->stalled = true;
		if (timeout_ms > 0)
			pc_sleep_until_ns(deadline);
		return pc_error(PC_ETIMEDOUT, "sim: frame %llu stalled (timeout_every)",
		                (unsigned long long)(m->first + m->k));
	}
	uint64_t due = pc_pacer_due_ns(&m->pacer, m->k);
	if (due > deadline) {
		pc_sleep_until_ns(deadline);
		return pc_error(PC_ETIMEDOUT, "sim: next frame due in %.1f ms",
		                (double)(due - now) / 1e6);
	}
	if (due > now)
		pc_sleep_until_ns(due);
	const pc_source_format *f = pc_source_current_format(s);
	pc_buffer *b = pc_bfifo_pop(&m->q);
	pc_view v = {b->data, f->width, f->height, f->stride, f->format};
	uint64_t n = m->first + m->k;
	pc_frame_meta meta;
	int rc = pc_sim_frame(m->sim, n, &m->ctl, &v, &meta);
	if (rc) {
		(void)pc_bfifo_push(&m->q, b);
		return rc;
	}
	if (m->corrupt_every && n % m->corrupt_every == m->corrupt_every - 1) {
		size_t row;
		(void)pc_format_row_bytes(f->format, f->width, &row);
		memset(PC_ROW(&v, uint8_t, f->height - 1), 0, row);
		meta.status |= PC_FRAME_INCOMPLETE;
	}
	b->frame.view = v;
	b->frame.meta = meta;
	m->k++;
	m->stalled = false;
	m->delivered++;
	*out = b;
	return 0;
}

static const char *const s_options[] = {"seed",
                                        "fps",
                                        "first",
                                        "threads",
                                        "drop_every",
                                        "timeout_every",
                                        "corrupt_every",
                                        "disconnect_after",
                                        "stride_pad",
                                        "roi",
                                        NULL};

const pc_source_ops pc_sim_source_ops = {
    .open = s_open,
    .close = s_close,
    .get_info = s_info,
    .try_format = s_try,
    .set_format = s_set,
    .control_query = s_cquery,
    .control_get = s_cget,
    .control_set = s_cset,
    .queue = s_queue,
    .start = s_start,
    .dequeue = s_dequeue,
    .stop = s_stop,
    .options = s_options,
};
