#include "polarcam/io.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static int has_suffix(const char *s, const char *suf)
{
	size_t n = strlen(s), m = strlen(suf);
	if (n < m)
		return 0;
	for (size_t i = 0; i < m; i++) {
		char c = s[n - m + i];
		if (c >= 'A' && c <= 'Z')
			c = (char)(c - 'A' + 'a');
		if (c != suf[i])
			return 0;
	}
	return 1;
}

static int read_npy_image(const char *path, pc_view *out, unsigned *sbits)
{
	pc_array a;
	int rc = pc_npy_read(path, &a);
	if (rc)
		return rc;
	if (a.ndim != 2) {
		pc_array_free(&a);
		return pc_error(PC_EFORMAT, "%s: a %u-D array; a raw mosaic is 2-D (H, W)", path, a.ndim);
	}
	pc_pixfmt fmt = a.dtype == PC_DT_U8 ? PC_FMT_MONO8 : a.dtype == PC_DT_U16 ? PC_FMT_MONO16
										 : PC_FMT_FLOAT32;
	if (a.shape[0] == 0 || a.shape[1] == 0 || a.shape[0] > UINT32_MAX || a.shape[1] > UINT32_MAX) {
		pc_array_free(&a);
		return pc_error(PC_EFORMAT, "%s: array shape (%zu, %zu) is not an image", path, a.shape[0],
				a.shape[1]);
	}
	rc = pc_view_alloc(out, fmt, (uint32_t)a.shape[1], (uint32_t)a.shape[0], 1);
	if (rc) {
		pc_array_free(&a);
		return pc_error_prefix(rc, "%s: ", path);
	}
	size_t w = a.shape[1];
	for (uint32_t y = 0; y < out->height; y++) {
		uint8_t *dst = PC_ROW(out, uint8_t, y);
		if (a.dtype == PC_DT_F64) {
			const double *s = (const double *)a.data + (size_t)y * w;
			float *d = (float *)dst;
			for (size_t x = 0; x < w; x++) {
				if (isfinite(s[x]) && fabs(s[x]) > FLT_MAX) {
					pc_array_free(&a);
					pc_view_free(out);
					return pc_error(PC_ERANGE, "%s: pixel (%zu,%u) = %g does not fit "
								   "float32", path, x, y, s[x]);
				}
				d[x] = (float)s[x];
			}
		} else {
			size_t bpp = a.dtype == PC_DT_U8 ? 1 : a.dtype == PC_DT_U16 ? 2 : 4;
			memcpy(dst, (const uint8_t *)a.data + (size_t)y * w * bpp, w * bpp);
		}
	}
	pc_array_free(&a);
	if (fmt == PC_FMT_FLOAT32) {
		rc = pc_view_check_bits(out, 32);
		if (rc) {
			pc_view_free(out);
			return pc_error_prefix(rc, "%s: ", path);
		}
	}
	if (sbits)
		*sbits = fmt == PC_FMT_MONO8 ? 8 : fmt == PC_FMT_MONO16 ? 16 : 32;
	return 0;
}

static int read_raw(const char *path, const pc_raw_geometry *g, pc_view *out, unsigned *sbits)
{
	const pc_format_info *fi = pc_format_info_get(g->format);
	if (!fi)
		return pc_error(PC_EINVAL, "%s: raw geometry has no valid pixel format", path);
	size_t row;
	int rc = pc_format_row_bytes(g->format, g->width, &row);
	if (rc)
		return pc_error_prefix(rc, "%s: ", path);
	if (g->height == 0)
		return pc_error(PC_EINVAL, "%s: raw height 0", path);
	size_t stride = g->stride ? g->stride : row;
	if (stride < row)
		return pc_error(PC_EINVAL, "%s: raw stride %zu below the row size %zu", path, stride, row);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path, strerror(errno));
	rc = pc_view_alloc(out, g->format, g->width, g->height, 1);
	if (rc) {
		fclose(fp);
		return pc_error_prefix(rc, "%s: ", path);
	}
	if (fseek(fp, (long)g->offset, SEEK_SET) != 0) {
		rc = pc_error(PC_EFORMAT, "%s: cannot seek to offset %zu", path, g->offset);
		goto fail;
	}
	for (uint32_t y = 0; y < g->height; y++) {
		if (fread(PC_ROW(out, uint8_t, y), 1, row, fp) != row) {
			rc = pc_error(PC_EFORMAT, "%s: truncated at row %u of %u (%ux%u %s, offset %zu)",
				      path, y, g->height, g->width, g->height, fi->name, g->offset);
			goto fail;
		}
		if (stride > row && y + 1 < g->height && fseek(fp, (long)(stride - row), SEEK_CUR)) {
			rc = pc_error(PC_EFORMAT, "%s: truncated in row padding", path);
			goto fail;
		}
	}
	fclose(fp);
	if (sbits)
		*sbits = fi->bits;
	return 0;
fail:
	fclose(fp);
	pc_view_free(out);
	return rc;
}

int pc_image_read(const char *path, const pc_raw_geometry *geometry, pc_view *out,
		  unsigned *significant_bits)
{
	memset(out, 0, sizeof *out);
	if (!path || !*path)
		return pc_error(PC_EINVAL, "input path is empty");
	if (geometry)
		return read_raw(path, geometry, out, significant_bits);
	if (has_suffix(path, ".npy"))
		return read_npy_image(path, out, significant_bits);
	if (has_suffix(path, ".tif") || has_suffix(path, ".tiff"))
		return pc_tiff_read(path, out, significant_bits);
	if (has_suffix(path, ".png"))
		return pc_png_read(path, out, significant_bits);
	if (has_suffix(path, ".bmp")) {
		if (significant_bits)
			*significant_bits = 8;
		return pc_bmp_read(path, out);
	}
	return pc_error(PC_EFORMAT, "%s: unknown file type (expected .png, .tif/.tiff, .npy, .bmp, "
				    "or a raw file with its geometry)", path);
}

int pc_image_read_mosaic(const char *path, const pc_raw_geometry *geometry, unsigned bits,
			 pc_view *out, unsigned *bits_out)
{
	unsigned declared = 0;
	int rc = pc_image_read(path, geometry, out, &declared);
	if (rc)
		return rc;
	const pc_format_info *fi = pc_format_info_get(out->format);
	if (fi->is_float) {
		if (bits && bits != 32) {
			pc_view_free(out);
			return pc_error(PC_EFORMAT, "%s: holds float32 data, not %u-bit integers (wrong "
						    "bit depth)", path, bits);
		}
		if (bits_out)
			*bits_out = 32;
		return 0; /* finiteness was checked by the reader */
	}
	unsigned container = fi->bits;
	if (bits == 0)
		bits = declared && declared <= container ? declared : container;
	if (bits < 1 || bits > 16 || (bits <= 8) != (container <= 8) || bits > container) {
		/* what the file holds: its declared depth (PNG sBIT, TIFF BitsPerSample) in samples
		 * of its container */
		unsigned cont = container <= 8 ? 8 : 16;
		unsigned held = declared && declared <= container ? declared : container;
		pc_view_free(out);
		return pc_error(PC_EFORMAT, "%s: holds %u-bit data in %u-bit samples, not %u-bit "
					    "data (wrong bit depth: 1..8-bit data comes in 8-bit "
					    "samples, 9..16-bit data in 16-bit samples)", path, held,
				cont, bits);
	}
	rc = pc_view_check_bits(out, bits);
	if (rc) {
		pc_view_free(out);
		if (container == 16 && bits < 16)
			return pc_error_prefix(rc, "%s: %u-bit data expected (polarcam keeps values "
						   "LSB-aligned; for data scaled to the full 16 bits pass "
						   "16 bits): ", path, bits);
		return pc_error_prefix(rc, "%s: ", path);
	}
	if (fi->packing == PC_PACK_NONE && container == 16) {
		/* Relabel: the values fit, so the LSB-aligned container format says the depth. */
		out->format = bits == 10 ? PC_FMT_MONO10
			      : bits == 12 ? PC_FMT_MONO12
			      : bits == 14 ? PC_FMT_MONO14
					   : PC_FMT_MONO16; /* other depths: *bits_out tells */
	}
	if (bits_out)
		*bits_out = bits;
	return 0;
}
