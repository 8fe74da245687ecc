#include "polarcam/frame.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

int pc_view_check(const pc_view *v)
{
	if (!v)
		return pc_error(PC_EINVAL, "view missing");
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (!fi)
		return pc_error(PC_EINVAL, "view format %d: not a known pixel format",
		                (int)v->format);
	if (v->width == 0 || v->height == 0)
		return pc_error(PC_EINVAL, "view size %ux%u: width and height must be > 0",
		                v->width, v->height);
	if (!v->data)
		return pc_error(PC_EINVAL, "view data pointer is NULL");
	size_t row;
	int rc = pc_format_row_bytes(v->format, v->width, &row);
	if (rc)
		return rc;
	if (v->stride < row)
		return pc_error(PC_EINVAL, "view stride %zu bytes: a %u-pixel %s row needs %zu",
		                v->stride, v->width, fi->name, row);
	if (v->stride > SIZE_MAX / v->height)
		return pc_error(PC_EOVERFLOW, "view %ux%u stride %zu: size overflows", v->width,
		                v->height, v->stride);
	return 0;
}

int pc_view_alloc(pc_view *v, pc_pixfmt fmt, uint32_t width, uint32_t height, size_t stride_align)
{
	memset(v, 0, sizeof *v);
	size_t row;
	int rc = pc_format_row_bytes(fmt, width, &row);
	if (rc)
		return rc;
	if (height == 0)
		return pc_error(PC_EINVAL, "height 0: expected at least 1 row");
	if (stride_align == 0)
		stride_align = 64;
	size_t stride = (row + stride_align - 1) / stride_align * stride_align;
	if (stride > SIZE_MAX / height - 64)
		return pc_error(PC_EOVERFLOW, "image %ux%u: size overflows", width, height);
	size_t bytes = stride * height;
	void *p = aligned_alloc(64, (bytes + 63) / 64 * 64);
	if (!p)
		return pc_error(PC_ENOMEM, "image %ux%u: cannot allocate %zu bytes", width, height,
		                bytes);
	v->data = p;
	v->width = width;
	v->height = height;
	v->stride = stride;
	v->format = fmt;
	return 0;
}

void pc_view_free(pc_view *v)
{
	if (!v)
		return;
	free(v->data);
	v->data = NULL;
}

int pc_view_crop(const pc_view *v, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h, pc_view *out)
{
	int rc = pc_view_check(v);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (fi->packing != PC_PACK_NONE && (x0 % fi->group_pixels || w % fi->group_pixels))
		return pc_error(PC_ENOTSUP,
		                "crop of packed format %s at x = %u, width %u: a packed "
		                "crop must start and end on %u-pixel groups (unpack first)",
		                fi->name, x0, w, fi->group_pixels);
	if (w == 0 || h == 0 || x0 > v->width || y0 > v->height || w > v->width - x0 ||
	    h > v->height - y0)
		return pc_error(PC_ERANGE, "crop %ux%u at (%u,%u) does not fit in %ux%u", w, h, x0,
		                y0, v->width, v->height);
	*out = *v;
	out->data = (uint8_t *)v->data + (size_t)y0 * v->stride +
	            (size_t)(x0 / fi->group_pixels) * fi->group_bytes;
	out->width = w;
	out->height = h;
	return 0;
}

void *pc_view_row_checked(const pc_view *v, uint32_t y, const char *file, int line)
{
	if (y >= v->height) {
		fprintf(stderr, "%s:%d: row %u outside a view of height %u\n", file, line, y,
		        v->height);
		abort();
	}
	return pc_view_row_unchecked(v, y);
}

/* Unpacks one row of n pixels to uint16. Layouts: see format.h. */
static void unpack_row(pc_pixfmt fmt, const uint8_t *s, uint16_t *d, uint32_t n)
{
	uint32_t x;
	switch (fmt) {
	case PC_FMT_MONO8:
		for (x = 0; x < n; x++)
			d[x] = s[x];
		break;
	case PC_FMT_MONO10:
	case PC_FMT_MONO12:
	case PC_FMT_MONO14:
	case PC_FMT_MONO16:
		for (x = 0; x < n; x++)
			d[x] = (uint16_t)(s[2 * x] | (s[2 * x + 1] << 8));
		break;
	case PC_FMT_MONO10P: /* LSB-first stream, 4 px in 5 bytes */
		for (x = 0; x < n; x += 4, s += 5) {
			uint64_t b = (uint64_t)s[0] | (uint64_t)s[1] << 8 | (uint64_t)s[2] << 16 |
			             (uint64_t)s[3] << 24 | (uint64_t)s[4] << 32;
			for (int k = 0; k < 4; k++)
				d[x + k] = (uint16_t)((b >> (10 * k)) & 0x3ff);
		}
		break;
	case PC_FMT_MONO12P: /* LSB-first stream, 2 px in 3 bytes */
		for (x = 0; x < n; x += 2, s += 3) {
			d[x] = (uint16_t)(s[0] | ((s[1] & 0x0f) << 8));
			d[x + 1] = (uint16_t)((s[1] >> 4) | (s[2] << 4));
		}
		break;
	case PC_FMT_MONO12PACKED: /* GVSP: [a11..4][b3..0 a3..0][b11..4] */
		for (x = 0; x < n; x += 2, s += 3) {
			d[x] = (uint16_t)((s[0] << 4) | (s[1] & 0x0f));
			d[x + 1] = (uint16_t)((s[2] << 4) | (s[1] >> 4));
		}
		break;
	case PC_FMT_Y10P: /* MIPI RAW10: 4 high bytes, then lows of p0..p3 in bits 0-1, 2-3, ... */
		for (x = 0; x < n; x += 4, s += 5)
			for (int k = 0; k < 4; k++)
				d[x + k] = (uint16_t)((s[k] << 2) | ((s[4] >> (2 * k)) & 3));
		break;
	case PC_FMT_Y12P: /* MIPI RAW12: 2 high bytes, then lows of p0 (bits 0-3), p1 (4-7) */
		for (x = 0; x < n; x += 2, s += 3) {
			d[x] = (uint16_t)((s[0] << 4) | (s[2] & 0x0f));
			d[x + 1] = (uint16_t)((s[1] << 4) | (s[2] >> 4));
		}
		break;
	case PC_FMT_MONO14P: /* LSB-first stream, 4 px in 7 bytes */
		for (x = 0; x < n; x += 4, s += 7) {
			uint64_t b = 0;
			for (int k = 0; k < 7; k++)
				b |= (uint64_t)s[k] << (8 * k);
			for (int k = 0; k < 4; k++)
				d[x + k] = (uint16_t)((b >> (14 * k)) & 0x3fff);
		}
		break;
	case PC_FMT_MONO10PACKED: /* GVSP: [a9..2][.. b1..0 .. a1..0][b9..2] */
		for (x = 0; x < n; x += 2, s += 3) {
			d[x] = (uint16_t)((s[0] << 2) | (s[1] & 3));
			d[x + 1] = (uint16_t)((s[2] << 2) | ((s[1] >> 4) & 3));
		}
		break;
	case PC_FMT_Y10BPACK: /* MSB-first stream, 4 px in 5 bytes */
		for (x = 0; x < n; x += 4, s += 5) {
			uint64_t b = 0;
			for (int k = 0; k < 5; k++)
				b = (b << 8) | s[k];
			for (int k = 0; k < 4; k++)
				d[x + k] = (uint16_t)((b >> (30 - 10 * k)) & 0x3ff);
		}
		break;
	case PC_FMT_Y14P: /* MIPI RAW14: 4 high bytes, then the 6-bit lows as an LSB-first stream */
		for (x = 0; x < n; x += 4, s += 7) {
			uint32_t lo = (uint32_t)s[4] | (uint32_t)s[5] << 8 | (uint32_t)s[6] << 16;
			for (int k = 0; k < 4; k++)
				d[x + k] = (uint16_t)((s[k] << 6) | ((lo >> (6 * k)) & 0x3f));
		}
		break;
	default:
		break;
	}
}

static void pack_row(pc_pixfmt fmt, const uint16_t *s, uint8_t *d, uint32_t n)
{
	uint32_t x;
	switch (fmt) {
	case PC_FMT_MONO8:
		for (x = 0; x < n; x++)
			d[x] = (uint8_t)s[x];
		break;
	case PC_FMT_MONO10:
	case PC_FMT_MONO12:
	case PC_FMT_MONO14:
	case PC_FMT_MONO16:
		for (x = 0; x < n; x++) {
			d[2 * x] = (uint8_t)(s[x] & 0xff);
			d[2 * x + 1] = (uint8_t)(s[x] >> 8);
		}
		break;
	case PC_FMT_MONO10P:
		for (x = 0; x < n; x += 4, d += 5) {
			uint64_t b = 0;
			for (int k = 0; k < 4; k++)
				b |= (uint64_t)(s[x + k] & 0x3ff) << (10 * k);
			for (int k = 0; k < 5; k++)
				d[k] = (uint8_t)(b >> (8 * k));
		}
		break;
	case PC_FMT_MONO12P:
		for (x = 0; x < n; x += 2, d += 3) {
			d[0] = (uint8_t)(s[x] & 0xff);
			d[1] = (uint8_t)((s[x] >> 8) | ((s[x + 1] & 0x0f) << 4));
			d[2] = (uint8_t)(s[x + 1] >> 4);
		}
		break;
	case PC_FMT_MONO12PACKED:
		for (x = 0; x < n; x += 2, d += 3) {
			d[0] = (uint8_t)(s[x] >> 4);
			d[1] = (uint8_t)((s[x] & 0x0f) | ((s[x + 1] & 0x0f) << 4));
			d[2] = (uint8_t)(s[x + 1] >> 4);
		}
		break;
	case PC_FMT_Y10P:
		for (x = 0; x < n; x += 4, d += 5) {
			d[4] = 0;
			for (int k = 0; k < 4; k++) {
				d[k] = (uint8_t)(s[x + k] >> 2);
				d[4] |= (uint8_t)((s[x + k] & 3) << (2 * k));
			}
		}
		break;
	case PC_FMT_Y12P:
		for (x = 0; x < n; x += 2, d += 3) {
			d[0] = (uint8_t)(s[x] >> 4);
			d[1] = (uint8_t)(s[x + 1] >> 4);
			d[2] = (uint8_t)((s[x] & 0x0f) | ((s[x + 1] & 0x0f) << 4));
		}
		break;
	case PC_FMT_MONO14P:
		for (x = 0; x < n; x += 4, d += 7) {
			uint64_t b = 0;
			for (int k = 0; k < 4; k++)
				b |= (uint64_t)(s[x + k] & 0x3fff) << (14 * k);
			for (int k = 0; k < 7; k++)
				d[k] = (uint8_t)(b >> (8 * k));
		}
		break;
	case PC_FMT_MONO10PACKED:
		for (x = 0; x < n; x += 2, d += 3) {
			d[0] = (uint8_t)(s[x] >> 2);
			d[1] = (uint8_t)((s[x] & 3) | ((s[x + 1] & 3) << 4));
			d[2] = (uint8_t)(s[x + 1] >> 2);
		}
		break;
	case PC_FMT_Y10BPACK:
		for (x = 0; x < n; x += 4, d += 5) {
			uint64_t b = 0;
			for (int k = 0; k < 4; k++)
				b = (b << 10) | (s[x + k] & 0x3ff);
			for (int k = 0; k < 5; k++)
				d[k] = (uint8_t)(b >> (32 - 8 * k));
		}
		break;
	case PC_FMT_Y14P:
		for (x = 0; x < n; x += 4, d += 7) {
			uint32_t lo = 0;
			for (int k = 0; k < 4; k++) {
				d[k] = (uint8_t)(s[x + k] >> 6);
				lo |= (uint32_t)(s[x + k] & 0x3f) << (6 * k);
			}
			d[4] = (uint8_t)lo;
			d[5] = (uint8_t)(lo >> 8);
			d[6] = (uint8_t)(lo >> 16);
		}
		break;
	default:
		break;
	}
}

int pc_view_to_u16(const pc_view *src, uint16_t *dst, size_t dst_stride)
{
	int rc = pc_view_check(src);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(src->format);
	if (fi->is_float)
		return pc_error(PC_EFORMAT, "float32 image: expected integer raw data");
	if (dst_stride < (size_t)src->width * 2)
		return pc_error(PC_EINVAL, "destination stride %zu: needs %zu bytes", dst_stride,
		                (size_t)src->width * 2);
	uint16_t maxv = (uint16_t)((1u << fi->bits) - 1u);
	for (uint32_t y = 0; y < src->height; y++) {
		uint16_t *d = (uint16_t *)((uint8_t *)dst + (size_t)y * dst_stride);
		unpack_row(src->format, PC_ROW(src, const uint8_t, y), d, src->width);
		if (fi->bits < 16 && fi->packing == PC_PACK_NONE && fi->bits > 8)
			for (uint32_t x = 0; x < src->width; x++)
				if (d[x] > maxv)
					return pc_error(
					    PC_ERANGE,
					    "pixel (%u,%u) = %u: above the %u-bit range "
					    "(max %u) of %s",
					    x, y, d[x], fi->bits, maxv, fi->name);
	}
	return 0;
}

int pc_view_to_f32(const pc_view *src, float *dst, size_t dst_stride)
{
	int rc = pc_view_check(src);
	if (rc)
		return rc;
	if (dst_stride < (size_t)src->width * 4)
		return pc_error(PC_EINVAL, "destination stride %zu: needs %zu bytes", dst_stride,
		                (size_t)src->width * 4);
	const pc_format_info *fi = pc_format_info_get(src->format);
	if (fi->is_float) {
		for (uint32_t y = 0; y < src->height; y++) {
			const float *s = PC_ROW(src, const float, y);
			float *d = (float *)((uint8_t *)dst + (size_t)y * dst_stride);
			for (uint32_t x = 0; x < src->width; x++) {
				if (!isfinite(s[x]))
					return pc_error(
					    PC_ERANGE,
					    "pixel (%u,%u) is %s: expected a finite value", x, y,
					    isnan(s[x]) ? "NaN" : "infinite");
				d[x] = s[x];
			}
		}
		return 0;
	}
	uint16_t *tmp = malloc((size_t)src->width * sizeof *tmp);
	if (!tmp)
		return pc_error(PC_ENOMEM, "row buffer of %u pixels", src->width);
	uint16_t maxv = (uint16_t)((1u << fi->bits) - 1u);
	for (uint32_t y = 0; y < src->height; y++) {
		unpack_row(src->format, PC_ROW(src, const uint8_t, y), tmp, src->width);
		float *d = (float *)((uint8_t *)dst + (size_t)y * dst_stride);
		for (uint32_t x = 0; x < src->width; x++) {
			if (fi->bits < 16 && tmp[x] > maxv) {
				unsigned v = tmp[x];
				free(tmp);
				return pc_error(PC_ERANGE,
				                "pixel (%u,%u) = %u: above the %u-bit range of %s",
				                x, y, v, fi->bits, fi->name);
			}
			d[x] = (float)tmp[x];
		}
	}
	free(tmp);
	return 0;
}

int pc_view_from_u16(const uint16_t *src, size_t src_stride, pc_view *dst)
{
	int rc = pc_view_check(dst);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(dst->format);
	if (fi->is_float)
		return pc_error(PC_EFORMAT, "float32 destination: expected an integer format");
	uint32_t maxv = (1u << fi->bits) - 1u;
	for (uint32_t y = 0; y < dst->height; y++) {
		const uint16_t *s =
		    (const uint16_t *)((const uint8_t *)src + (size_t)y * src_stride);
		for (uint32_t x = 0; x < dst->width; x++)
			if (s[x] > maxv)
				return pc_error(PC_ERANGE,
				                "pixel (%u,%u) = %u: above the %u-bit range of %s",
				                x, y, s[x], fi->bits, fi->name);
		pack_row(dst->format, s, PC_ROW(dst, uint8_t, y), dst->width);
	}
	return 0;
}

int pc_view_check_bits(const pc_view *v, unsigned bits)
{
	int rc = pc_view_check(v);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (fi->is_float) {
		for (uint32_t y = 0; y < v->height; y++) {
			const float *r = PC_ROW(v, const float, y);
			for (uint32_t x = 0; x < v->width; x++)
				if (!isfinite(r[x]))
					return pc_error(PC_ERANGE,
					                "pixel (%u,%u) is %s: expected a finite "
					                "value",
					                x, y, isnan(r[x]) ? "NaN" : "infinite");
		}
		return 0;
	}
	if (bits == 0 || bits > 16)
		return pc_error(PC_EINVAL, "%u significant bits: expected 1..16", bits);
	/* what the container can hold: packed samples have exactly fi->bits, but Mono10/12/14
	 * are LSB-aligned in 16 bits and can hold more than their name says (a headerless raw
	 * read as Mono12 may carry 55245) */
	const unsigned capacity =
	    fi->packing == PC_PACK_NONE ? 8 * fi->group_bytes / fi->group_pixels : fi->bits;
	if (bits >= capacity)
		return 0; /* the container cannot hold more */
	uint32_t maxv = (1u << bits) - 1u;
	if (v->format == PC_FMT_MONO8) {
		for (uint32_t y = 0; y < v->height; y++) {
			const uint8_t *r = PC_ROW(v, const uint8_t, y);
			for (uint32_t x = 0; x < v->width; x++)
				if (r[x] > maxv)
					return pc_error(PC_ERANGE,
					                "pixel (%u,%u) = %u: above the %u-bit "
					                "range (max %u)",
					                x, y, r[x], bits, maxv);
		}
		return 0;
	}
	uint16_t *tmp = malloc((size_t)v->width * sizeof *tmp);
	if (!tmp)
		return pc_error(PC_ENOMEM, "row buffer of %u pixels", v->width);
	for (uint32_t y = 0; y < v->height; y++) {
		unpack_row(v->format, PC_ROW(v, const uint8_t, y), tmp, v->width);
		for (uint32_t x = 0; x < v->width; x++)
			if (tmp[x] > maxv) {
				unsigned val = tmp[x];
				free(tmp);
				return pc_error(PC_ERANGE,
				                "pixel (%u,%u) = %u: above the %u-bit range "
				                "(max %u)",
				                x, y, val, bits, maxv);
			}
	}
	free(tmp);
	return 0;
}

int pc_frame_crop(const pc_frame *f, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                  pc_frame *out)
{
	if (!f || !out)
		return pc_error(PC_EINVAL, "frame missing");
	pc_view v;
	int rc = pc_view_crop(&f->view, x0, y0, w, h, &v);
	if (rc)
		return rc;
	*out = *f;
	out->view = v;
	out->mosaic = pc_mosaic_shift(&f->mosaic, x0, y0);
	out->meta.offset_x = f->meta.offset_x + x0;
	out->meta.offset_y = f->meta.offset_y + y0;
	return 0;
}

int pc_view_flip(const pc_view *src, int flip_x, int flip_y, pc_view *dst)
{
	int rc = pc_view_check(src);
	if (!rc)
		rc = pc_view_check(dst);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(src->format);
	if (fi->packing != PC_PACK_NONE)
		return pc_error(PC_ENOTSUP, "flip of packed format %s: unpack first", fi->name);
	if (dst->format != src->format || dst->width != src->width || dst->height != src->height)
		return pc_error(PC_EINVAL,
		                "flip: destination %ux%u %s differs from source %ux%u %s",
		                dst->width, dst->height, pc_format_info_get(dst->format)->name,
		                src->width, src->height, fi->name);
	if (dst->data == src->data)
		return pc_error(PC_EINVAL, "flip: in-place flips are not supported");
	size_t bpp = fi->group_bytes;
	for (uint32_t y = 0; y < src->height; y++) {
		const uint8_t *s = PC_ROW(src, const uint8_t, flip_y ? src->height - 1 - y : y);
		uint8_t *d = PC_ROW(dst, uint8_t, y);
		if (!flip_x) {
			memcpy(d, s, (size_t)src->width * bpp);
			continue;
		}
		for (uint32_t x = 0; x < src->width; x++)
			memcpy(d + (size_t)x * bpp, s + (size_t)(src->width - 1 - x) * bpp, bpp);
	}
	return 0;
}
