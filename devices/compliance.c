/* The frame-source compliance test (what it checks: polarcam/compliance.h). */
#include "polarcam/compliance.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/source.h"

typedef struct ctx {
	const pc_compliance_options *opt;
	pc_compliance_result *res;
} ctx;

static const char *const fault_names[] = {"none", "drop", "timeout", "disconnect", "corrupt"};

const char *pc_fault_name(pc_fault_kind k)
{
	return (unsigned)k < 5 ? fault_names[k] : "?";
}

int pc_fault_parse(const char *name)
{
	if (!name)
		return PC_FAULT_NONE;
	for (int i = 0; i < 5; i++)
		if (!strcmp(name, fault_names[i]))
			return i;
	return -1;
}

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static bool
report(ctx *c, bool ok, const char *check, const char *fmt, ...)
{
	char detail[256] = "";
	if (fmt) {
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(detail, sizeof detail, fmt, ap);
		va_end(ap);
	}
	if (ok) {
		c->res->passed++;
	} else {
		if (!c->res->failed) {
			/* A long message keeps its start and says it was cut. */
			char *ff = c->res->first_failure;
			size_t cap = sizeof c->res->first_failure;
			if (snprintf(ff, cap, "%s: %s", check, detail) >= (int)cap)
				memcpy(ff + cap - 4, "...", 4);
		}
		c->res->failed++;
	}
	if (c->opt->log)
		c->opt->log(c->opt->log_ctx, ok ? PC_CHECK_PASS : PC_CHECK_FAIL, check, detail);
	return ok;
}

static void skip(ctx *c, const char *check, const char *why)
{
	c->res->skipped++;
	if (c->opt->log)
		c->opt->log(c->opt->log_ctx, PC_CHECK_SKIP, check, why);
}

/* rc as "PC_EINVAL (detail)" */
static const char *rcs(int rc)
{
	static _Thread_local char buf[300];
	snprintf(buf, sizeof buf, "%s%s%s%s", pc_errname(rc), rc ? " (" : "",
	         rc ? pc_error_detail() : "", rc ? ")" : "");
	return buf;
}

static bool same_geometry(const pc_source_format *a, const pc_source_format *b)
{
	return a->format == b->format && a->width == b->width && a->height == b->height &&
	       a->offset_x == b->offset_x && a->offset_y == b->offset_y && a->stride == b->stride;
}

static bool format_consistent(const pc_source_format *f, char *why, size_t n)
{
	size_t row;
	if (!pc_format_info_get(f->format)) {
		snprintf(why, n, "pixel format %d unknown", (int)f->format);
		return false;
	}
	if (pc_format_row_bytes(f->format, f->width, &row) || f->height == 0) {
		snprintf(why, n, "size %ux%u impossible for %s", f->width, f->height,
		         f->format_name);
		return false;
	}
	if (f->stride < row || f->frame_bytes < f->stride * (f->height - 1) + row) {
		snprintf(why, n, "stride %zu / frame_bytes %zu too small for %u x %zu-byte rows",
		         f->stride, f->frame_bytes, f->height, row);
		return false;
	}
	if (f->sensor_width && (f->offset_x + f->width > f->sensor_width ||
	                        f->offset_y + f->height > f->sensor_height)) {
		snprintf(why, n, "ROI %ux%u at (%u,%u) exceeds the %ux%u sensor", f->width,
		         f->height, f->offset_x, f->offset_y, f->sensor_width, f->sensor_height);
		return false;
	}
	return true;
}

static void check_states_open(ctx *c, pc_source *s)
{
	pc_buffer *b = NULL;
	int rc = pc_source_start(s);
	report(c, rc == PC_ESTATE, "state: start without buffers", "%s", rcs(rc));
	rc = pc_source_dequeue(s, 0, &b);
	report(c, rc == PC_ESTATE && !b, "state: dequeue while OPEN", "%s", rcs(rc));
	rc = pc_source_stop(s);
	report(c, rc == PC_ESTATE, "state: stop while OPEN", "%s", rcs(rc));
	rc = pc_source_requeue(s, NULL);
	report(c, rc == PC_EINVAL, "args: requeue(NULL)", "%s", rcs(rc));
	rc = pc_source_buffers_free(s);
	report(c, rc == PC_ESTATE, "state: buffers_free while OPEN", "%s", rcs(rc));
	rc = pc_source_buffers_alloc(s, 0);
	report(c, rc == PC_EINVAL, "args: buffers_alloc(0)", "%s", rcs(rc));
}

/* Negotiates; returns the format to stream with (a padded stride when possible). */
static pc_source_format check_negotiation(ctx *c, pc_source *s, const pc_mosaic *sensor_mosaic)
{
	char why[200];
	pc_source_format cur, f;
	pc_format_verdict v;
	int rc = pc_source_get_format(s, &cur);
	report(c, rc == 0 && format_consistent(&cur, why, sizeof why),
	       "format: current is consistent", "%s", rc ? rcs(rc) : why);

	f = cur;
	rc = pc_source_try_format(s, &f, &v);
	report(c, rc == 0 && v == PC_FORMAT_VALID && same_geometry(&f, &cur),
	       "negotiate: the current format is valid", "%s verdict %s", rcs(rc),
	       pc_format_verdict_name(v));

	memset(&f, 0, sizeof f);
	rc = pc_source_try_format(s, &f, &v);
	report(c, rc == 0 && v == PC_FORMAT_VALID && format_consistent(&f, why, sizeof why),
	       "negotiate: an empty request is completed, not adjusted", "%s verdict %s", rcs(rc),
	       pc_format_verdict_name(v));

	/* too large */
	f = cur;
	f.offset_x = f.offset_y = 0;
	f.width = cur.sensor_width + 1000;
	f.height = cur.sensor_height + 1000;
	rc = pc_source_try_format(s, &f, &v);
	bool ok = rc == 0 && v != PC_FORMAT_VALID;
	if (ok && v == PC_FORMAT_ADJUSTED) {
		ok = format_consistent(&f, why, sizeof why);
		pc_source_format again = f;
		pc_format_verdict v2;
		int rc2 = pc_source_try_format(s, &again, &v2);
		report(c, rc2 == 0 && v2 == PC_FORMAT_VALID && same_geometry(&again, &f),
		       "negotiate: an adjusted answer is valid when asked again", "%s verdict %s",
		       rcs(rc2), pc_format_verdict_name(v2));
	}
	report(c, ok, "negotiate: a size beyond the sensor is never valid", "%s verdict %s",
	       rcs(rc), pc_format_verdict_name(v));

	/* offset outside */
	f = cur;
	f.offset_x = cur.sensor_width + 8;
	f.width = 0;
	rc = pc_source_try_format(s, &f, &v);
	report(c, rc == 0 && v != PC_FORMAT_VALID,
	       "negotiate: an offset outside the sensor is "
	       "never valid",
	       "%s verdict %s", rcs(rc), pc_format_verdict_name(v));

	/* too small stride */
	size_t row = 0;
	(void)pc_format_row_bytes(cur.format, cur.width, &row);
	f = cur;
	f.stride = row > 1 ? row - 1 : 0;
	if (row > 1) {
		rc = pc_source_try_format(s, &f, &v);
		report(c,
		       rc == 0 && v != PC_FORMAT_VALID &&
		           (v == PC_FORMAT_INVALID || f.stride >= row),
		       "negotiate: a stride shorter than a row is never valid",
		       "%s verdict %s stride %zu", rcs(rc), pc_format_verdict_name(v), f.stride);
	}

	/* set_format refuses an adjustable request and keeps the format */
	f = cur;
	f.width = cur.sensor_width + 1000;
	rc = pc_source_set_format(s, &f);
	pc_source_format after;
	pc_source_get_format(s, &after);
	report(c, rc != 0 && same_geometry(&after, &cur),
	       "negotiate: set_format refuses a request that needs adjusting", "%s", rcs(rc));

	/* an ROI at an odd offset shifts the mosaic phase; a colour-polarization mosaic repeats
	 * every 4 pixels, so an offset of 2 mod 4 must move its colours too (a shift reduced
	 * mod 2 passes at (1,1)) */
	const uint32_t offsets[2][2] = {{1, 1}, {3, 2}};
	unsigned n_offsets = sensor_mosaic->period == 4 ? 2 : 1;
	for (unsigned i = 0; i < n_offsets; i++) {
		if (!cur.polarized || cur.sensor_width < 8 || cur.sensor_height < 8) {
			skip(c, "negotiate: ROI mosaic phase",
			     "not a polarized source or a tiny sensor");
			break;
		}
		f = cur;
		f.offset_x = offsets[i][0];
		f.offset_y = offsets[i][1];
		f.width = cur.sensor_width / 2;
		f.height = cur.sensor_height / 2;
		f.stride = 0;
		rc = pc_source_try_format(s, &f, &v);
		if (rc == 0 && v != PC_FORMAT_INVALID) {
			pc_mosaic want = pc_mosaic_shift(sensor_mosaic, f.offset_x, f.offset_y);
			report(c, pc_mosaic_equal(&f.mosaic, &want),
			       "negotiate: the ROI's mosaic is the sensor's shifted by the offset",
			       "ROI at (%u,%u) %s", f.offset_x, f.offset_y,
			       pc_format_verdict_name(v));
		} else {
			skip(c, "negotiate: ROI mosaic phase", "the source offers no ROI");
			break;
		}
	}

	/* every integer format: a consistent answer */
	unsigned n_valid = 0;
	for (int pf = PC_FMT_INVALID + 1; pf < PC_FMT_COUNT; pf++) {
		const pc_format_info *fi = pc_format_info_get((pc_pixfmt)pf);
		if (fi->is_float)
			continue;
		f = cur;
		f.format = (pc_pixfmt)pf;
		f.format_name[0] = '\0';
		f.stride = 0;
		f.width = cur.width - cur.width % 4; /* fits every packing group */
		rc = pc_source_try_format(s, &f, &v);
		char name[64];
		snprintf(name, sizeof name, "negotiate: %s answered consistently", fi->name);
		if (rc == 0 && v == PC_FORMAT_VALID)
			n_valid++;
		report(c,
		       rc == 0 && (v == PC_FORMAT_INVALID ||
		                   (format_consistent(&f, why, sizeof why) &&
		                    (v != PC_FORMAT_VALID || f.format == (pc_pixfmt)pf))),
		       name, "%s verdict %s -> %s", rcs(rc), pc_format_verdict_name(v),
		       pc_format_info_get(f.format) ? pc_format_info_get(f.format)->name : "?");
	}
	report(c, n_valid >= 1, "negotiate: at least one pixel format is valid", "%u valid",
	       n_valid);

	/* the format to stream with: the current one, with a padded stride when accepted */
	f = cur;
	f.stride = (row + 64 + 63) / 64 * 64 + 8; /* padded, not a multiple of 64 */
	rc = pc_source_try_format(s, &f, &v);
	if (rc == 0 && v == PC_FORMAT_VALID) {
		rc = pc_source_set_format(s, &f);
		report(c, rc == 0, "negotiate: a padded stride is applied", "%s stride %zu",
		       rcs(rc), f.stride);
	} else {
		skip(c, "negotiate: padded stride", "the source does not offer padded strides");
		f = cur;
	}
	pc_source_get_format(s, &f);
	return f;
}

static void check_controls(ctx *c, pc_source *s)
{
	for (int id = 0; id < PC_CTRL_COUNT; id++) {
		char name[96];
		pc_control_info ci;
		int rc = pc_source_control_query(s, (pc_control_id)id, &ci);
		if (rc == PC_ENOTSUP) {
			snprintf(name, sizeof name, "control %s",
			         pc_control_name((pc_control_id)id));
			skip(c, name, "not supported");
			continue;
		}
		snprintf(name, sizeof name, "control %s: query",
		         pc_control_name((pc_control_id)id));
		if (!report(c, rc == 0 && ci.min <= ci.max && ci.def >= ci.min && ci.def <= ci.max,
		            name, "%s [%g, %g] default %g", rcs(rc), ci.min, ci.max, ci.def))
			continue;
		double val = NAN;
		rc = pc_source_control_get(s, (pc_control_id)id, &val);
		snprintf(name, sizeof name, "control %s: value in range",
		         pc_control_name((pc_control_id)id));
		report(c, rc == 0 && val >= ci.min && val <= ci.max, name, "%s value %g", rcs(rc),
		       val);
		double span = ci.max - ci.min;
		double bad = ci.max + (span > 0 ? span : 1.0) + 1.0;
		rc = pc_source_control_set(s, (pc_control_id)id, bad, NULL);
		snprintf(name, sizeof name, "control %s: out of range refused",
		         pc_control_name((pc_control_id)id));
		report(c, rc == PC_ERANGE, name, "set %g: %s", bad, rcs(rc));
		double target = ci.min + 0.5 * span, applied = NAN, back = NAN;
		rc = pc_source_control_set(s, (pc_control_id)id, target, &applied);
		if (rc == 0)
			rc = pc_source_control_get(s, (pc_control_id)id, &back);
		/* without a published step, devices still quantize (a frame period in whole
		 * microseconds): accept 0.1 % */
		double tol = ci.step > 0 ? ci.step : 1e-3 * fmax(1.0, fabs(target));
		snprintf(name, sizeof name, "control %s: set value reads back",
		         pc_control_name((pc_control_id)id));
		report(c,
		       rc == 0 && fabs(applied - target) <= tol &&
		           fabs(back - applied) <= 1e-9 * fmax(1.0, fabs(applied)),
		       name, "%s set %g applied %g read %g", rcs(rc), target, applied, back);
		/* restore the original value */
		if (isfinite(val))
			(void)pc_source_control_set(s, (pc_control_id)id, val, NULL);
	}
}

/* Checks one dequeued frame against the format, the previous frame and its buffer. */
static bool check_frame(ctx *c, const pc_source_format *f, const pc_buffer *b, uint64_t *last_seq,
                        uint64_t *last_ts, bool *have_last, unsigned *bad)
{
	const pc_view *v = &b->frame.view;
	size_t row = 0;
	(void)pc_format_row_bytes(f->format, f->width, &row);
	bool ok = v->format == f->format && v->width == f->width && v->height == f->height &&
	          v->stride == f->stride && v->stride >= row;
	const uint8_t *lo = b->data, *p = v->data;
	ok = ok && p >= lo && (size_t)(p - lo) + f->stride * (f->height - 1) + row <= b->size;
	const pc_frame_meta *m = &b->frame.meta;
	if (*have_last)
		ok = ok && m->sequence > *last_seq && m->timestamp_ns >= *last_ts;
	ok = ok && m->offset_x == f->offset_x && m->offset_y == f->offset_y;
	if (f->polarized)
		ok = ok && pc_mosaic_equal(&b->frame.mosaic, &f->mosaic);
	if (!ok && (*bad)++ == 0)
		report(
		    c, false, "stream: frame matches the format, buffer and order",
		    "seq %llu (last %llu) ts %llu (last %llu) %ux%u stride %zu vs %ux%u stride %zu",
		    (unsigned long long)m->sequence, (unsigned long long)*last_seq,
		    (unsigned long long)m->timestamp_ns, (unsigned long long)*last_ts, v->width,
		    v->height, v->stride, f->width, f->height, f->stride);
	*have_last = true;
	*last_seq = m->sequence;
	*last_ts = m->timestamp_ns;
	return ok;
}

int pc_source_compliance(const char *uri, const pc_compliance_options *opt_in,
                         pc_compliance_result *res)
{
	pc_compliance_options opt = opt_in ? *opt_in : (pc_compliance_options){0};
	if (!opt.frames)
		opt.frames = 8;
	if (!opt.buffers)
		opt.buffers = 4;
	if (!opt.timeout_ms)
		opt.timeout_ms = 3000;
	if (!opt.starve_ms)
		opt.starve_ms = 300;
	if (!res)
		return pc_error(PC_EINVAL, "compliance: result missing");
	memset(res, 0, sizeof *res);
	ctx c = {&opt, res};

	pc_source *s = NULL;
	int rc = pc_source_open(&s, uri);
	if (rc)
		return rc;
	report(&c, pc_source_get_state(s) == PC_SOURCE_OPEN, "open: state OPEN", "%s",
	       pc_source_state_name(pc_source_get_state(s)));
	pc_source_info info;
	rc = pc_source_get_info(s, &info);
	report(&c, rc == 0, "info", "%s %s %s", rcs(rc), info.vendor, info.model);
	pc_mosaic sensor_mosaic = info.mosaic;
	{
		pc_source_format cur;
		pc_source_get_format(s, &cur);
		if (cur.polarized) {
			/* the current format's mosaic is the sensor's shifted by its offset */
			pc_mosaic want = pc_mosaic_shift(&info.mosaic, cur.offset_x, cur.offset_y);
			report(&c, info.polarized && pc_mosaic_equal(&cur.mosaic, &want),
			       "info: sensor mosaic agrees with the format's", "offset (%u,%u)",
			       cur.offset_x, cur.offset_y);
			int mrc = pc_mosaic_check(&info.mosaic);
			char layout[64] = "";
			if (mrc == 0)
				pc_mosaic_format(&info.mosaic, layout, sizeof layout);
			report(&c, mrc == 0, "info: the sensor mosaic is a valid layout", "%s",
			       mrc ? pc_error_detail() : layout);
			pc_error_clear();
		}
	}

	check_states_open(&c, s);
	pc_source_format f = check_negotiation(&c, s, &sensor_mosaic);
	check_controls(&c, s);

	/* ---- streaming ---- */
	rc = pc_source_buffers_alloc(s, opt.buffers);
	if (!report(&c, rc == 0 && pc_source_buffer_count(s) == opt.buffers, "buffers: allocate",
	            "%s", rcs(rc))) {
		pc_source_close(s);
		return 0;
	}
	pc_source_format tmp = f;
	pc_format_verdict v;
	rc = pc_source_try_format(s, &tmp, &v);
	report(&c, rc == PC_ESTATE, "state: negotiation refused while READY", "%s", rcs(rc));
	rc = pc_source_start(s);
	if (!report(&c, rc == 0 && pc_source_get_state(s) == PC_SOURCE_STREAMING, "stream: start",
	            "%s", rcs(rc))) {
		pc_source_close(s);
		return 0;
	}
	rc = pc_source_start(s);
	report(&c, rc == PC_ESTATE, "state: start twice", "%s", rcs(rc));

	uint64_t last_seq = 0, last_ts = 0;
	bool have_last = false, ended = false, lost = false;
	unsigned got = 0, bad = 0, timeouts = 0, tries = 0;
	int fault_rc = 0;
	unsigned want = opt.frames;
	while (got < want && tries < want * 4 + 8) {
		tries++;
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(s, opt.timeout_ms, &b);
		if (rc == PC_EEND) {
			ended = true;
			break;
		}
		if (rc == PC_ETIMEDOUT) {
			timeouts++;
			if (opt.expect_fault == PC_FAULT_TIMEOUT) {
				fault_rc = rc;
				continue;
			}
			break;
		}
		if (rc == PC_EDISCONNECTED) {
			lost = true;
			fault_rc = rc;
			break;
		}
		if (rc) {
			report(&c, false, "stream: dequeue", "%s", rcs(rc));
			break;
		}
		got++;
		check_frame(&c, &f, b, &last_seq, &last_ts, &have_last, &bad);
		rc = pc_source_requeue(s, b);
		if (rc) {
			report(&c, false, "stream: requeue", "%s", rcs(rc));
			break;
		}
	}
	if (opt.expect_fault == PC_FAULT_NONE) {
		report(&c, got == want || (ended && opt.finite && got > 0),
		       "stream: frames delivered", "%u of %u (timeouts %u, %s)", got, want,
		       timeouts,
		       ended  ? "ended"
		       : lost ? "device lost"
		              : "running");
		if (bad == 0)
			report(&c, got > 0,
			       "stream: every frame matches the format, buffer and order",
			       "%u frames, stride %zu", got, f.stride);
	}

	pc_source_stats st;
	rc = pc_source_get_stats(s, &st);
	report(
	    &c, rc == 0 && st.completed + st.failed >= got - bad && st.completed + st.failed <= got,
	    "stats: completed + failed = frames dequeued", "%s completed %llu failed %llu got %u",
	    rcs(rc), (unsigned long long)st.completed, (unsigned long long)st.failed, got);

	switch (opt.expect_fault) {
	case PC_FAULT_NONE:
		break;
	case PC_FAULT_DROP:
		report(&c, st.dropped > 0, "fault drop: sequence gaps counted as dropped",
		       "dropped %llu", (unsigned long long)st.dropped);
		break;
	case PC_FAULT_TIMEOUT:
		report(&c, fault_rc == PC_ETIMEDOUT && st.timeouts > 0,
		       "fault timeout: dequeue answers PC_ETIMEDOUT", "timeouts %llu",
		       (unsigned long long)st.timeouts);
		break;
	case PC_FAULT_CORRUPT:
		report(&c, st.failed > 0, "fault corrupt: damaged frames flagged and counted",
		       "failed %llu", (unsigned long long)st.failed);
		break;
	case PC_FAULT_DISCONNECT: {
		report(&c, lost && pc_source_get_state(s) == PC_SOURCE_FAILED,
		       "fault disconnect: PC_EDISCONNECTED and state FAILED",
		       "state %s after %u frames", pc_source_state_name(pc_source_get_state(s)),
		       got);
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(s, 10, &b);
		report(&c, rc == PC_EDISCONNECTED, "fault disconnect: later dequeues fail too",
		       "%s", rcs(rc));
		rc = pc_source_start(s);
		report(&c, rc == PC_ESTATE, "fault disconnect: cannot restart", "%s", rcs(rc));
		rc = pc_source_stop(s);
		report(&c, rc == 0, "fault disconnect: stop succeeds", "%s", rcs(rc));
		rc = pc_source_buffers_free(s);
		report(&c, rc == 0, "fault disconnect: buffers can be freed", "%s", rcs(rc));
		pc_source_close(s);
		return 0;
	}
	}
	if (lost || opt.expect_fault != PC_FAULT_NONE) {
		pc_source_close(s);
		return 0;
	}

	/* ---- buffer ownership: hold everything, nothing more arrives ---- */
	pc_buffer *held[64];
	unsigned n_held = 0;
	if (!ended) {
		for (unsigned i = 0; i < opt.buffers + 2 && n_held < 64; i++) {
			pc_buffer *b = NULL;
			rc = pc_source_dequeue(
			    s, n_held < opt.buffers ? opt.timeout_ms : opt.starve_ms, &b);
			if (rc == 0) {
				check_frame(&c, &f, b, &last_seq, &last_ts, &have_last, &bad);
				held[n_held++] = b;
			} else {
				break;
			}
		}
		if (rc == PC_EEND && opt.finite) {
			ended = true;
			skip(&c, "buffers: nothing arrives while all are held", "the source ended");
		} else {
			report(&c, n_held == opt.buffers && rc == PC_ETIMEDOUT,
			       "buffers: nothing arrives while all are held",
			       "held %u of %u, then %s", n_held, opt.buffers, rcs(rc));
		}
	}
	rc = pc_source_stop(s);
	report(&c, rc == 0 && pc_source_get_state(s) == PC_SOURCE_READY, "stream: stop", "%s",
	       rcs(rc));
	rc = pc_source_buffers_free(s);
	report(&c, n_held == 0 || rc == PC_EBUSY,
	       "buffers: free refused while the application "
	       "holds buffers",
	       "%s", rcs(rc));
	if (n_held == 0 && rc == 0) {
		/* nothing held: the pool is gone, make a new one for the restart check */
		rc = pc_source_buffers_alloc(s, opt.buffers);
	}
	for (unsigned i = 0; i < n_held; i++) {
		int r2 = pc_source_requeue(s, held[i]);
		if (r2)
			report(&c, false, "buffers: requeue after stop", "%s", rcs(r2));
	}

	/* ---- restart: stop returned every buffer, all of them are filled again ---- */
	if (!ended) {
		rc = pc_source_start(s);
		report(&c, rc == 0, "stream: restart", "%s", rcs(rc));
		unsigned refill = 0;
		have_last = false; /* sequence may restart after a stop */
		for (unsigned i = 0; rc == 0 && i < opt.buffers; i++) {
			pc_buffer *b = NULL;
			int r2 = pc_source_dequeue(s, opt.timeout_ms, &b);
			if (r2 == PC_EEND && opt.finite)
				break;
			if (r2) {
				report(&c, false, "buffers: refilled after restart",
				       "buffer %u: %s", i, rcs(r2));
				break;
			}
			check_frame(&c, &f, b, &last_seq, &last_ts, &have_last, &bad);
			held[refill++] = b;
		}
		if (refill == opt.buffers)
			report(&c, true,
			       "buffers: stop returned every buffer (all refilled after "
			       "restart)",
			       "%u buffers", refill);
		pc_source_stop(s);
		for (unsigned i = 0; i < refill; i++)
			pc_source_requeue(s, held[i]);
	}
	rc = pc_source_buffers_free(s);
	report(&c, rc == 0 && pc_source_get_state(s) == PC_SOURCE_OPEN,
	       "buffers: free when all are back", "%s", rcs(rc));
	pc_source_close(s);
	return 0;
}
