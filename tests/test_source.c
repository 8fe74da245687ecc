/* The frame-source wrappers, checked against a tiny model backend written here: the state
 * machine refuses calls in the wrong state, a missing op is PC_ENOTSUP, URI options are parsed
 * and unknown ones refused, negotiation answers are checked, frames that break the negotiated
 * format or go backwards in sequence/time are refused, sequence gaps count as dropped, stop
 * returns every buffer, a disconnect moves the source to FAILED; a black level declared only
 * once frames flow reaches the live pipeline's levels (pc_stokes_stream_update_black). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/source.h"
#include "polarcam/stream.h"

/* Model backend: a 4x2 Mono8 sensor; frames carry sequence numbers from a script. */
typedef struct model {
	pc_buffer *queue[8];
	unsigned n_queued;
	uint64_t seq[16]; /* sequence of the k-th frame */
	unsigned n_frames, next;
	int fail_at;       /* dequeue number that reports PC_EDISCONNECTED, -1 = never */
	int bad_stride_at; /* dequeue number that returns a wrong stride */
	double exposure_us;
	bool backwards_ts_at2;
	unsigned black_from; /* m_info_late: declares 37.5 DN once frame black_from was dequeued */
	unsigned n_info;     /* m_info_late: times asked */
} model;

static int m_open(pc_source *s, const char *arg)
{
	if (strcmp(arg, "cam0"))
		return pc_error(PC_ENOENT, "no model camera '%s'", arg);
	model *m = calloc(1, sizeof *m);
	if (!m)
		return PC_ENOMEM;
	m->fail_at = -1;
	m->bad_stride_at = -1;
	m->exposure_us = 1000;
	uint64_t skip = 0;
	int rc = pc_source_option_u64(s, "skip", 0, 3, &skip);
	if (rc) {
		free(m);
		return rc;
	}
	for (unsigned i = 0; i < 16; i++)
		m->seq[i] = i + (i >= 3 ? skip : 0); /* a gap of `skip` after frame 2 */
	m->n_frames = 16;
	pc_source_set_priv(s, m);
	return 0;
}

static void m_close(pc_source *s)
{
	free(pc_source_priv(s));
}

static int m_try(pc_source *s, pc_source_format *f, pc_format_verdict *v)
{
	(void)s;
	pc_source_format want = *f;
	*v = PC_FORMAT_VALID;
	if (f->format != PC_FMT_INVALID && f->format != PC_FMT_MONO8)
		*v = PC_FORMAT_ADJUSTED;
	f->format = PC_FMT_MONO8;
	f->format_name[0] = '\0';
	if (f->offset_x >= 4 || f->offset_y >= 2) {
		*v = PC_FORMAT_INVALID;
		return pc_error(PC_OK, "offset outside the 4x2 sensor");
	}
	if (f->offset_x % 2) { /* ROI origins on even columns only */
		f->offset_x &= ~1u;
		*v = PC_FORMAT_ADJUSTED;
	}
	if (!f->width || f->width > 4 - f->offset_x) {
		if (f->width)
			*v = PC_FORMAT_ADJUSTED;
		f->width = 4 - f->offset_x;
	}
	if (!f->height || f->height > 2 - f->offset_y) {
		if (f->height)
			*v = PC_FORMAT_ADJUSTED;
		f->height = 2 - f->offset_y;
	}
	if (want.stride && want.stride < f->width) {
		f->stride = 0;
		*v = PC_FORMAT_ADJUSTED;
	}
	f->frame_bytes = 0;
	f->sensor_width = 4;
	f->sensor_height = 2;
	f->polarized = true;
	pc_mosaic m = pc_mosaic_imx250mzr();
	return pc_source_format_complete(f, &m);
}

static int m_set(pc_source *s, const pc_source_format *f)
{
	(void)s;
	(void)f;
	return 0;
}

static int m_cquery(pc_source *s, pc_control_id id, pc_control_info *ci)
{
	(void)s;
	if (id != PC_CTRL_EXPOSURE_US)
		return pc_error(PC_ENOTSUP, "model: only exposure");
	*ci = (pc_control_info){10, 1e6, 10, 1000, false};
	return 0;
}

static int m_cget(pc_source *s, pc_control_id id, double *v)
{
	(void)id;
	*v = ((model *)pc_source_priv(s))->exposure_us;
	return 0;
}

static int m_cset(pc_source *s, pc_control_id id, double v, double *applied)
{
	(void)id;
	model *m = pc_source_priv(s);
	m->exposure_us = 10 * (double)(long)(v / 10 + 0.5);
	*applied = m->exposure_us;
	return 0;
}

static int m_queue(pc_source *s, pc_buffer *b)
{
	model *m = pc_source_priv(s);
	if (m->n_queued == 8)
		return pc_error(PC_EIO, "model queue full");
	m->queue[m->n_queued++] = b;
	return 0;
}

static int m_start(pc_source *s)
{
	(void)s;
	return 0;
}

static int m_dequeue(pc_source *s, int timeout_ms, pc_buffer **out)
{
	(void)timeout_ms;
	model *m = pc_source_priv(s);
	if (m->fail_at >= 0 && m->next == (unsigned)m->fail_at)
		return pc_error(PC_EDISCONNECTED, "model camera unplugged");
	if (!m->n_queued || m->next >= m->n_frames)
		return pc_error(PC_ETIMEDOUT, "model: no frame");
	pc_buffer *b = m->queue[0];
	memmove(m->queue, m->queue + 1, --m->n_queued * sizeof m->queue[0]);
	const pc_source_format *f = pc_source_current_format(s);
	b->frame.view = (pc_view){b->data, f->width, f->height, f->stride, f->format};
	if ((int)m->next == m->bad_stride_at)
		b->frame.view.stride = f->stride + 1;
	b->frame.meta = (pc_frame_meta){0};
	b->frame.meta.sequence = m->seq[m->next];
	b->frame.meta.timestamp_ns = 1000 * (m->seq[m->next] + 1);
	if (m->backwards_ts_at2 && m->next == 2)
		b->frame.meta.timestamp_ns = 1;
	m->next++;
	*out = b;
	return 0;
}

static int m_stop(pc_source *s)
{
	((model *)pc_source_priv(s))->n_queued = 0;
	return 0;
}

static const char *const m_options[] = {"skip", NULL};

static const pc_source_ops model_ops = {
    .open = m_open,
    .close = m_close,
    .try_format = m_try,
    .set_format = m_set,
    .control_query = m_cquery,
    .control_get = m_cget,
    .control_set = m_cset,
    .queue = m_queue,
    .start = m_start,
    .dequeue = m_dequeue,
    .stop = m_stop,
    .options = m_options,
};

/* Only open: everything else must be PC_ENOTSUP from the wrappers. */
static const pc_source_ops bare_ops = {.open = m_open, .close = m_close};

static void test_registry_and_uris(void)
{
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, "nosuch:x"), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "unknown scheme") != NULL);
	CHECK_EQ_INT(pc_source_open(&s, "no-colon"), PC_EINVAL);
	CHECK_EQ_INT(pc_source_open(&s, ""), PC_EINVAL);
	CHECK(s == NULL);
	const char *schemes[] = {"sim", "file", "aravis", "v4l2", "libcamera"};
	for (unsigned i = 0; i < 5; i++) {
		const pc_source_backend *b = pc_source_backend_find(schemes[i]);
		CHECK(b != NULL);
		if (b && !b->ops)
			CHECK(b->missing != NULL && b->missing[0]);
	}
	CHECK(pc_source_backend_get(5) == NULL);
	/* a known scheme that is not built says why */
	for (unsigned i = 0; pc_source_backend_get(i); i++) {
		const pc_source_backend *b = pc_source_backend_get(i);
		if (!b->ops) {
			char uri[64];
			snprintf(uri, sizeof uri, "%s:x", b->scheme);
			CHECK_EQ_INT(pc_source_open(&s, uri), PC_EUNAVAIL);
			CHECK(strstr(pc_error_detail(), "not built") != NULL);
		}
	}
	/* options */
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?bogus=1"), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "bogus") && strstr(pc_error_detail(), "skip"));
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?skip=9"), PC_EINVAL);
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?skip=1&skip=2"), PC_EINVAL);
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?skip=x"), PC_EINVAL);
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?&"), PC_EINVAL);
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam9"), PC_ENOENT);
	CHECK(s == NULL);
}

static void test_notsup(void)
{
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open_ops(&s, &bare_ops, "bare", "cam0"), 0);
	pc_source_format f = {0};
	pc_format_verdict v;
	double d;
	pc_control_info ci;
	CHECK_EQ_INT(pc_source_try_format(s, &f, &v), PC_ENOTSUP);
	CHECK_EQ_INT(pc_source_set_format(s, &f), PC_ENOTSUP);
	CHECK_EQ_INT(pc_source_control_get(s, PC_CTRL_GAIN_DB, &d), PC_ENOTSUP);
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_GAIN_DB, 1, NULL), PC_ENOTSUP);
	CHECK_EQ_INT(pc_source_control_query(s, PC_CTRL_GAIN_DB, &ci), PC_ENOTSUP);
	/* no format: no buffers */
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 2), PC_ESTATE);
	pc_source_stats st;
	CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
	pc_source_close(s);
}

static void test_negotiation(pc_source *s)
{
	pc_source_format f;
	CHECK_EQ_INT(pc_source_get_format(s, &f), 0);
	CHECK_EQ_INT(f.width, 4);
	CHECK_EQ_INT(f.height, 2);
	CHECK_EQ_INT(f.frame_bytes, 8);
	pc_format_verdict v;
	pc_source_format r = {0};
	r.width = 2;
	r.offset_x = 2;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	/* the ROI at x=2 keeps the IMX250MZR phase; at y=1 it shifts by one row */
	CHECK_EQ_INT(r.mosaic.channel[0][0], 2);
	r = (pc_source_format){0};
	r.offset_y = 1;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	CHECK_EQ_INT(r.mosaic.channel[0][0], 3); /* 135° */
	r = (pc_source_format){0};
	r.offset_x = 1;
	r.format = PC_FMT_MONO16;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_ADJUSTED);
	CHECK_EQ_INT(r.offset_x, 0);
	CHECK_EQ_INT(r.format, PC_FMT_MONO8);
	/* set_format refuses anything not exactly valid and changes nothing */
	pc_source_format req = {0};
	req.offset_x = 1;
	CHECK_EQ_INT(pc_source_set_format(s, &req), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "try_format") != NULL);
	CHECK_EQ_INT(pc_source_get_format(s, &f), 0);
	CHECK_EQ_INT(f.width, 4);
	r = (pc_source_format){0};
	r.offset_x = 7;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_INVALID);
	CHECK_EQ_INT(pc_source_set_format(s, &r), PC_EFORMAT);
	r = (pc_source_format){0};
	r.format = (pc_pixfmt)999;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), PC_EINVAL);
	/* a padded stride is honoured */
	r = (pc_source_format){0};
	r.stride = 16;
	CHECK_EQ_INT(pc_source_try_format(s, &r, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	CHECK_EQ_INT(pc_source_set_format(s, &r), 0);
	CHECK_EQ_INT(pc_source_get_format(s, &f), 0);
	CHECK_EQ_INT(f.stride, 16);
	CHECK_EQ_INT(f.frame_bytes, 16 + 4);
}

static void test_controls(pc_source *s)
{
	double d = 0;
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_EXPOSURE_US, 5, NULL), PC_ERANGE);
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_EXPOSURE_US, 1e7, NULL), PC_ERANGE);
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_EXPOSURE_US, NAN, NULL), PC_ERANGE);
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_EXPOSURE_US, 1234, &d), 0);
	CHECK_EQ_INT(d, 1230);
	CHECK_EQ_INT(pc_source_control_get(s, PC_CTRL_EXPOSURE_US, &d), 0);
	CHECK_EQ_INT(d, 1230);
	CHECK_EQ_INT(pc_source_control_get(s, (pc_control_id)17, &d), PC_EINVAL);
}

static void test_streaming(void)
{
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0?skip=2"), 0);
	if (!s)
		return;
	CHECK_EQ_INT(pc_source_get_state(s), PC_SOURCE_OPEN);
	test_negotiation(s);
	test_controls(s);
	pc_buffer *b = NULL;
	CHECK_EQ_INT(pc_source_start(s), PC_ESTATE);
	CHECK_EQ_INT(pc_source_dequeue(s, 0, &b), PC_ESTATE);
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 0), PC_EINVAL);
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 65), PC_EINVAL);
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 3), 0);
	CHECK_EQ_INT(pc_source_get_state(s), PC_SOURCE_READY);
	pc_source_format f = {0};
	pc_format_verdict v;
	CHECK_EQ_INT(pc_source_try_format(s, &f, &v), PC_ESTATE); /* format fixed */
	CHECK_EQ_INT(pc_source_start(s), 0);
	CHECK_EQ_INT(pc_source_start(s), PC_ESTATE);
	/* exposure is not live on the model */
	CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_EXPOSURE_US, 100, NULL), PC_ESTATE);

	pc_buffer *held[3];
	for (int i = 0; i < 3; i++) {
		CHECK_EQ_INT(pc_source_dequeue(s, 10, &held[i]), 0);
		if (!held[i])
			return;
		CHECK_EQ_INT(held[i]->frame.meta.sequence, (unsigned)i);
		CHECK_EQ_INT(held[i]->state, PC_BUFFER_DEQUEUED);
		CHECK_EQ_INT(held[i]->frame.mosaic.channel[0][0], 2);
	}
	/* all three held: nothing queued, the model times out */
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), PC_ETIMEDOUT);
	CHECK_EQ_INT(pc_source_requeue(s, held[1]), 0);
	CHECK_EQ_INT(pc_source_requeue(s, held[1]), PC_EINVAL); /* twice */
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), 0);
	CHECK_EQ_INT(b->frame.meta.sequence, 5); /* 3 + skip 2 */
	pc_source_stats st;
	CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
	CHECK_EQ_INT(st.completed, 4);
	CHECK_EQ_INT(st.dropped, 2);
	CHECK_EQ_INT(st.timeouts, 1);
	/* buffers_free needs READY and every buffer back */
	CHECK_EQ_INT(pc_source_buffers_free(s), PC_ESTATE);
	CHECK_EQ_INT(pc_source_stop(s), 0);
	CHECK_EQ_INT(pc_source_get_state(s), PC_SOURCE_READY);
	CHECK_EQ_INT(pc_source_buffers_free(s), PC_EBUSY);
	CHECK_EQ_INT(pc_source_requeue(s, held[0]), 0);
	CHECK_EQ_INT(pc_source_requeue(s, held[2]), 0);
	CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	/* restart: all three buffers are handed out again */
	CHECK_EQ_INT(pc_source_start(s), 0);
	((model *)pc_source_priv(s))->bad_stride_at = 6;
	for (int i = 0; i < 2; i++)
		CHECK_EQ_INT(pc_source_dequeue(s, 10, &held[i]), 0);
	/* a frame whose stride breaks the negotiated format never reaches the application */
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), PC_EIO);
	CHECK(b == NULL);
	CHECK(strstr(pc_error_detail(), "stride") != NULL);
	/* the refused buffer went back to the source */
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), 0);
	CHECK(b != NULL);
	/* unplugged */
	((model *)pc_source_priv(s))->fail_at = 8;
	CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), PC_EDISCONNECTED);
	CHECK_EQ_INT(pc_source_get_state(s), PC_SOURCE_FAILED);
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), PC_EDISCONNECTED);
	CHECK_EQ_INT(pc_source_start(s), PC_ESTATE);
	CHECK_EQ_INT(pc_source_stop(s), 0);
	CHECK_EQ_INT(pc_source_get_state(s), PC_SOURCE_FAILED);
	CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
	CHECK_EQ_INT(st.failed, 1);
	pc_source_close(s); /* with two buffers still held: close frees everything */
}

static void test_backwards_time(void)
{
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open_ops(&s, &model_ops, "model", "cam0"), 0);
	if (!s)
		return;
	((model *)pc_source_priv(s))->backwards_ts_at2 = true;
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 4), 0);
	CHECK_EQ_INT(pc_source_start(s), 0);
	pc_buffer *b;
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), 0);
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), 0);
	CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), PC_EIO);
	CHECK(strstr(pc_error_detail(), "timestamp") != NULL);
	pc_source_close(s); /* closes a streaming source */
}

/* A camera that reports its black level with its frames, as a libcamera camera does with the
 * metadata SensorBlackLevels, and whose pipeline attaches it only from frame black_from: none
 * before, 37.5 DN from then on. */
static int m_info_late(pc_source *s, pc_source_info *info)
{
	model *m = pc_source_priv(s);
	m->n_info++;
	info->black_level = m->next > m->black_from ? 37.5 : 0;
	info->black_level_late = true;
	return 0;
}

static void test_black_declared_late(void)
{
	static pc_source_ops late;
	late = model_ops;
	late.get_info = m_info_late;
	/* no level given: 0 for the frames before the one that declares, the camera's from it on,
	 * when it declares within PC_STREAM_BLACK_FRAMES frames (the 8th: index 7), never after
	 * (index 8: 0 throughout, and no more asking); given 5 DN: 5 whatever the camera says; a
	 * source that does not declare its level with its frames (black_level_late false, here
	 * one without get_info): not asked again, and no warning (as the simulator, files and
	 * GenICam cameras, which declare theirs at once or never) */
	const struct {
		const pc_source_ops *ops;
		unsigned from;
		double given;
		int taken_at; /* frame index at which the level is taken, -1: never */
		bool missed;
		unsigned asked; /* get_info calls after set_levels' one */
	} cases[] = {{&late, 3, NAN, 3, false, 4},
	             {&late, 7, NAN, 7, false, 8},
	             {&late, 8, NAN, -1, true, PC_STREAM_BLACK_FRAMES},
	             {&late, 3, 5, -1, false, 0},
	             {&model_ops, 0, NAN, -1, false, 0}};
	CHECK_EQ_INT(PC_STREAM_BLACK_FRAMES, 8);
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		pc_source *s = NULL;
		pc_stokes_stream *ss = NULL;
		CHECK_EQ_INT(pc_source_open_ops(&s, cases[k].ops, "late", "cam0"), 0);
		CHECK_EQ_INT(pc_stokes_stream_new(PC_DM_BILINEAR, &ss), 0);
		if (!s || !ss)
			return;
		model *m = pc_source_priv(s);
		m->black_from = cases[k].from;
		pc_stream_levels lv = pc_stream_levels_default();
		lv.black_level = cases[k].given;
		CHECK_EQ_INT(pc_stokes_stream_set_levels(ss, &lv, s), 0);
		const unsigned asked0 = m->n_info;
		const double none = isnan(cases[k].given) ? 0 : cases[k].given;
		double black = -1;
		pc_stokes_stream_levels_used(ss, &black, NULL, NULL);
		CHECK_NEAR(black, none, 0);
		CHECK_EQ_INT(pc_source_buffers_alloc(s, 2), 0);
		CHECK_EQ_INT(pc_source_start(s), 0);
		for (int i = 0; i < 12; i++) {
			pc_buffer *b = NULL;
			CHECK_EQ_INT(pc_source_dequeue(s, 10, &b), 0);
			if (!b)
				return;
			/* the level this frame is processed with */
			int taken = pc_stokes_stream_update_black(ss, s);
			pc_stokes_stream_levels_used(ss, &black, NULL, NULL);
			const int t = cases[k].taken_at;
			CHECK_EQ_INT(taken, i == t);
			CHECK_NEAR(black, t >= 0 && i >= t ? 37.5 : none, 0);
			CHECK_EQ_INT(pc_source_requeue(s, b), 0);
		}
		printf("black level: given %g, declared from frame %u: taken at frame %d\n",
		       cases[k].given, cases[k].from, cases[k].taken_at);
		CHECK_EQ_INT(m->n_info - asked0, cases[k].asked); /* no asking after the window */
		CHECK_EQ_INT(pc_stokes_stream_black_missed(ss), cases[k].missed);
		pc_stokes_stream_free(ss);
		pc_source_close(s);
	}
	/* a level handed over with the frame (pc_capture's writer): taken once, only when open */
	pc_stokes_stream *ss = NULL;
	CHECK_EQ_INT(pc_stokes_stream_new(PC_DM_BILINEAR, &ss), 0);
	if (!ss)
		return;
	pc_stream_levels lv = pc_stream_levels_default();
	CHECK_EQ_INT(pc_stokes_stream_set_levels(ss, &lv, NULL), 0);
	double black = -1;
	CHECK_EQ_INT(pc_stokes_stream_take_black(ss, 0), 0);
	CHECK_EQ_INT(pc_stokes_stream_take_black(ss, NAN), 0);
	CHECK_EQ_INT(pc_stokes_stream_take_black(ss, 20), 1);
	CHECK_EQ_INT(pc_stokes_stream_take_black(ss, 30), 0);
	pc_stokes_stream_levels_used(ss, &black, NULL, NULL);
	CHECK_NEAR(black, 20, 0);
	CHECK(!pc_stokes_stream_black_missed(ss));
	lv.black_level = 5;
	CHECK_EQ_INT(pc_stokes_stream_set_levels(ss, &lv, NULL), 0);
	CHECK_EQ_INT(pc_stokes_stream_take_black(ss, 20), 0);
	pc_stokes_stream_levels_used(ss, &black, NULL, NULL);
	CHECK_NEAR(black, 5, 0);
	pc_stokes_stream_free(ss);
}

int main(void)
{
	test_registry_and_uris();
	test_notsup();
	test_streaming();
	test_backwards_time();
	test_black_declared_late();
	return pc_test_finish("test_source");
}
