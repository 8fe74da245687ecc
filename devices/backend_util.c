#include "backend_util.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "polarcam/error.h"

void pc_bfifo_clear(pc_bfifo *q)
{
	memset(q, 0, sizeof *q);
}

int pc_bfifo_push(pc_bfifo *q, pc_buffer *b)
{
	if (q->count == 64)
		return pc_error(PC_EOVERFLOW, "buffer queue full (64)");
	q->b[(q->head + q->count) % 64] = b;
	q->count++;
	return 0;
}

pc_buffer *pc_bfifo_pop(pc_bfifo *q)
{
	if (!q->count)
		return NULL;
	pc_buffer *b = q->b[q->head];
	q->head = (q->head + 1) % 64;
	q->count--;
	return b;
}

uint64_t pc_clock_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

void pc_sleep_until_ns(uint64_t t_ns)
{
	struct timespec ts = {(time_t)(t_ns / 1000000000u), (long)(t_ns % 1000000000u)};
	while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL) == EINTR)
		;
}

void pc_pacer_start(pc_pacer *p, double rate_hz, uint64_t now_ns, uint64_t k)
{
	p->t0_ns = now_ns;
	p->k0 = k;
	p->period_ns = rate_hz > 0 ? 1e9 / rate_hz : 0;
}

void pc_pacer_set_rate(pc_pacer *p, double rate_hz, uint64_t k)
{
	uint64_t t = pc_pacer_due_ns(p, k);
	pc_pacer_start(p, rate_hz, t, k);
}

uint64_t pc_pacer_due_ns(const pc_pacer *p, uint64_t k)
{
	if (k <= p->k0)
		return p->t0_ns;
	/* a rate of 1e-300 Hz or a huge k puts the frame beyond 2^64 ns: never due (the float to
	 * integer conversion would be undefined) */
	const double d = (double)(k - p->k0) * p->period_ns + 0.5;
	if (!(d < 0x1p64) || (uint64_t)d > UINT64_MAX - p->t0_ns)
		return UINT64_MAX;
	return p->t0_ns + (uint64_t)d;
}

int pc_copy_roi(const pc_view *src, uint32_t x0, uint32_t y0, pc_view *dst, uint16_t *tmp)
{
	pc_view c;
	int rc = pc_view_crop(src, x0, y0, dst->width, dst->height, &c);
	if (rc)
		return rc;
	if (c.format == dst->format) {
		size_t row;
		rc = pc_format_row_bytes(dst->format, dst->width, &row);
		if (rc)
			return rc;
		for (uint32_t y = 0; y < dst->height; y++)
			memcpy(PC_ROW(dst, uint8_t, y), PC_ROW(&c, const uint8_t, y), row);
		return 0;
	}
	size_t ts = (size_t)dst->width * 2;
	rc = pc_view_to_u16(&c, tmp, ts);
	if (!rc)
		rc = pc_view_from_u16(tmp, ts, dst);
	return rc;
}

int pc_negotiate_flexible(pc_source_format *f, pc_pixfmt native, uint32_t sw, uint32_t sh,
                          bool polarized, const pc_mosaic *m, pc_format_verdict *verdict)
{
	const pc_source_format req = *f;
	bool adjusted = false;
	*verdict = PC_FORMAT_VALID;
	const pc_format_info *ni = pc_format_info_get(native);
	pc_pixfmt fmt = req.format;
	if (req.format_name[0] && fmt == PC_FMT_INVALID) {
		bool pol = false, col = false;
		if (pc_format_from_genicam(req.format_name, &fmt, &pol, &col) != 0) {
			pc_error_clear();
			fmt = pc_format_from_name(req.format_name);
		}
		if (fmt == PC_FMT_INVALID)
			adjusted = true;
	}
	const pc_format_info *fi = pc_format_info_get(fmt);
	if (fmt == PC_FMT_INVALID) {
		fmt = native;
	} else if (fi->is_float || fi->bits < ni->bits) {
		fmt = native;
		adjusted = true;
	}
	fi = pc_format_info_get(fmt);
	f->format = fmt;
	snprintf(f->format_name, sizeof f->format_name, "%s", fi->name);
	if (req.format_name[0] && strcmp(req.format_name, fi->name) != 0) {
		/* a vendor name for the same storage is fine: keep the name asked for */
		pc_pixfmt vf;
		bool pol = false, col = false;
		if (pc_format_from_genicam(req.format_name, &vf, &pol, &col) == 0 && vf == fmt)
			snprintf(f->format_name, sizeof f->format_name, "%s", req.format_name);
		else
			pc_error_clear();
	}
	if (req.offset_x >= sw || req.offset_y >= sh) {
		*verdict = PC_FORMAT_INVALID;
		return pc_error(PC_OK, "ROI origin (%u,%u) outside the %ux%u sensor", req.offset_x,
		                req.offset_y, sw, sh);
	}
	f->offset_x = req.offset_x;
	f->offset_y = req.offset_y;
	uint32_t maxw = sw - req.offset_x, maxh = sh - req.offset_y;
	f->width = req.width ? req.width : maxw;
	f->height = req.height ? req.height : maxh;
	if (f->width > maxw) {
		f->width = maxw;
		adjusted = true;
	}
	if (f->height > maxh) {
		f->height = maxh;
		adjusted = true;
	}
	if (f->width % fi->group_pixels) {
		f->width -= f->width % fi->group_pixels;
		adjusted = true;
		if (f->width == 0) {
			*verdict = PC_FORMAT_INVALID;
			return pc_error(PC_OK, "%s needs widths that are multiples of %u pixels",
			                fi->name, fi->group_pixels);
		}
	}
	size_t row;
	int rc = pc_format_row_bytes(fmt, f->width, &row);
	if (rc)
		return rc;
	f->stride = req.stride;
	if (f->stride && f->stride < row) {
		f->stride = row;
		adjusted = true;
	}
	if (f->stride > (size_t)1 << 30) {
		f->stride = row;
		adjusted = true;
	}
	f->frame_bytes = 0;
	f->sensor_width = sw;
	f->sensor_height = sh;
	f->polarized = polarized;
	if (!m)
		memset(&f->mosaic, 0, sizeof f->mosaic);
	rc = pc_source_format_complete(f, m);
	if (rc)
		return rc;
	if (adjusted)
		*verdict = PC_FORMAT_ADJUSTED;
	return 0;
}
