/* file: source - replays a recording directory (polarcam/recording.h).
 *
 *   file:DIR[?loop=1&fps=F]
 *
 * The "sensor" is the recorded frame: ROI offsets are relative to it and shift its mosaic.
 * Frames keep their recorded sequence numbers and timestamps (a loop continues both); with
 * fps (or the frame_rate_hz control) they are paced from the stream start, else delivered as
 * fast as they are read. After the last frame dequeue answers PC_EEND. */
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

#include <stdlib.h>
#include <string.h>

#include "backend_util.h"
#include "backends.h"

typedef struct file_src {
	pc_recording *rec;
	const pc_recording_desc *desc;
	bool loop;
	double fps;
	pc_bfifo q;
	pc_pacer pacer;
	uint64_t k;                 /* frames delivered since start */
	uint64_t seq_span, ts_span; /* sequence and time added per loop */
	uint16_t *tmp;
} file_src;

static int f_open(pc_source *s, const char *arg)
{
	if (!*arg)
		return pc_error(PC_EINVAL, "file: expected a recording directory (file:DIR)");
	file_src *f = calloc(1, sizeof *f);
	if (!f)
		return pc_error(PC_ENOMEM, "file source");
	int rc = pc_source_option_bool(s, "loop", &f->loop);
	if (!rc)
		rc = pc_source_option_double(s, "fps", 0, 100000, &f->fps);
	if (!rc)
		rc = pc_recording_open(&f->rec, arg);
	if (!rc && pc_recording_count(f->rec) == 0)
		rc = pc_error(PC_EFORMAT, "%s: the recording holds no frames", arg);
	if (rc) {
		pc_recording_free(f->rec);
		free(f);
		return rc;
	}
	f->desc = pc_recording_get_desc(f->rec);
	size_t n = pc_recording_count(f->rec);
	const pc_recording_frame *first = pc_recording_get_frame(f->rec, 0);
	const pc_recording_frame *last = pc_recording_get_frame(f->rec, n - 1);
	f->seq_span = last->sequence - first->sequence + 1;
	uint64_t dt = n > 1 ? (last->timestamp_ns - first->timestamp_ns) / (n - 1) : 0;
	if (dt == 0) {
		/* one frame, or all at one time: the nominal period (within 2^62 ns, so that the
		 * float conversion is defined for any fps > 0) */
		const double per = f->fps > 0 ? 1e9 / f->fps : 1e6;
		dt = per < 0x1p62 ? (uint64_t)per : (uint64_t)1 << 62;
	}
	f->ts_span = last->timestamp_ns - first->timestamp_ns + dt;
	pc_source_set_priv(s, f);
	return 0;
}

static void f_close(pc_source *s)
{
	file_src *f = pc_source_priv(s);
	pc_recording_free(f->rec);
	free(f->tmp);
	free(f);
}

static int f_info(pc_source *s, pc_source_info *info)
{
	file_src *f = pc_source_priv(s);
	snprintf(info->vendor, sizeof info->vendor, "polarcam");
	snprintf(info->model, sizeof info->model, "recording");
	snprintf(info->driver, sizeof info->driver, "polarcam-file");
	snprintf(info->serial, sizeof info->serial, "%s",
	         f->desc->source ? f->desc->source : "(unknown source)");
	info->mosaic = f->desc->mosaic;
	info->black_level = pc_recording_black_level(f->rec);
	return 0;
}

static int f_try(pc_source *s, pc_source_format *fmt, pc_format_verdict *v)
{
	file_src *f = pc_source_priv(s);
	const pc_recording_desc *d = f->desc;
	return pc_negotiate_flexible(fmt, d->format, d->width, d->height, d->polarized,
	                             d->mosaic.period ? &d->mosaic : NULL, v);
}

static int f_set(pc_source *s, const pc_source_format *fmt)
{
	(void)fmt;
	file_src *f = pc_source_priv(s);
	free(f->tmp);
	f->tmp = NULL; /* sized for the new format on first use */
	return 0;
}

static int f_cquery(pc_source *s, pc_control_id id, pc_control_info *ci)
{
	(void)s;
	if (id != PC_CTRL_FRAME_RATE_HZ)
		return pc_error(PC_ENOTSUP, "file: %s is recorded, not a control",
		                pc_control_name(id));
	*ci = (pc_control_info){0, 100000, 0, 0, true};
	return 0;
}

static int f_cget(pc_source *s, pc_control_id id, double *val)
{
	if (id != PC_CTRL_FRAME_RATE_HZ)
		return pc_error(PC_ENOTSUP, "file: %s is recorded, not a control",
		                pc_control_name(id));
	*val = ((file_src *)pc_source_priv(s))->fps;
	return 0;
}

static int f_cset(pc_source *s, pc_control_id id, double val, double *applied)
{
	file_src *f = pc_source_priv(s);
	if (id != PC_CTRL_FRAME_RATE_HZ)
		return pc_error(PC_ENOTSUP, "file: %s is recorded, not a control",
		                pc_control_name(id));
	f->fps = val;
	pc_pacer_set_rate(&f->pacer, val, f->k);
	*applied = val;
	return 0;
}

static int f_queue(pc_source *s, pc_buffer *b)
{
	return pc_bfifo_push(&((file_src *)pc_source_priv(s))->q, b);
}

static int f_start(pc_source *s)
{
	file_src *f = pc_source_priv(s);
	f->k = 0;
	pc_pacer_start(&f->pacer, f->fps, pc_clock_ns(), 0);
	return 0;
}

static int f_stop(pc_source *s)
{
	pc_bfifo_clear(&((file_src *)pc_source_priv(s))->q);
	return 0;
}

static int f_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	file_src *f = pc_source_priv(s);
	size_t n = pc_recording_count(f->rec);
	if (!f->loop && f->k >= n)
		return pc_error(PC_EEND, "%s: all %zu frames delivered", pc_recording_dir(f->rec),
		                n);
	uint64_t now = pc_clock_ns();
	uint64_t deadline = timeout_ms < 0 ? UINT64_MAX : now + (uint64_t)timeout_ms * 1000000u;
	if (!f->q.count) {
		/* no buffer: nothing can arrive before one is requeued */
		if (timeout_ms > 0)
			pc_sleep_until_ns(deadline);
		return pc_error(PC_ETIMEDOUT, "file: no buffer queued");
	}
	uint64_t due = pc_pacer_due_ns(&f->pacer, f->k);
	if (due > deadline) {
		pc_sleep_until_ns(deadline);
		return pc_error(PC_ETIMEDOUT, "file: next frame due in %.1f ms",
		                (double)(due - now) / 1e6);
	}
	if (due > now)
		pc_sleep_until_ns(due);
	size_t i = (size_t)(f->k % n);
	uint64_t lap = f->k / n;
	pc_view src;
	int rc = pc_recording_read(f->rec, i, &src);
	if (rc)
		return rc;
	const pc_source_format *fmt = pc_source_current_format(s);
	if (!f->tmp && fmt->format != src.format &&
	    !(f->tmp = malloc((size_t)fmt->width * fmt->height * sizeof *f->tmp))) {
		pc_view_free(&src);
		return pc_error(PC_ENOMEM, "file source conversion buffer");
	}
	pc_buffer *b = pc_bfifo_pop(&f->q);
	pc_view dst = {b->data, fmt->width, fmt->height, fmt->stride, fmt->format};
	rc = pc_copy_roi(&src, fmt->offset_x, fmt->offset_y, &dst, f->tmp);
	pc_view_free(&src);
	if (rc) {
		(void)pc_bfifo_push(&f->q, b); /* the buffer stays queued */
		return rc;
	}
	const pc_recording_frame *rf = pc_recording_get_frame(f->rec, i);
	b->frame.view = dst;
	memset(&b->frame.meta, 0, sizeof b->frame.meta);
	b->frame.meta.sequence = rf->sequence + lap * f->seq_span;
	b->frame.meta.timestamp_ns = rf->timestamp_ns + lap * f->ts_span;
	b->frame.meta.exposure_us = rf->exposure_us;
	b->frame.meta.gain_db = rf->gain_db;
	b->frame.meta.status = rf->status;
	f->k++;
	*out = b;
	return 0;
}

static const char *const f_options[] = {"loop", "fps", NULL};

const pc_source_ops pc_file_source_ops = {
    .open = f_open,
    .close = f_close,
    .get_info = f_info,
    .try_format = f_try,
    .set_format = f_set,
    .control_query = f_cquery,
    .control_get = f_cget,
    .control_set = f_cset,
    .queue = f_queue,
    .start = f_start,
    .dequeue = f_dequeue,
    .stop = f_stop,
    .options = f_options,
};
