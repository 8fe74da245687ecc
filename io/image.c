#include "polarcam/io.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
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
		return pc_error(PC_EFORMAT, "%s: a %u-D array; a raw mosaic is 2-D (H, W)", path,
		                a.ndim);
	}
	pc_pixfmt fmt = a.dtype == PC_DT_U8    ? PC_FMT_MONO8
	                : a.dtype == PC_DT_U16 ? PC_FMT_MONO16
	                                       : PC_FMT_FLOAT32;
	if (a.shape[0] == 0 || a.shape[1] == 0 || a.shape[0] > UINT32_MAX ||
	    a.shape[1] > UINT32_MAX) {
		pc_array_free(&a);
		return pc_error(PC_EFORMAT, "%s: array shape (%zu, %zu) is not an image", path,
		                a.shape[0], a.shape[1]);
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
					/* the message first: s points into the array freed below */
					rc = pc_error(PC_ERANGE,
					              "%s: pixel (%zu,%u) = %g does not fit "
					              "float32",
					              path, x, y, s[x]);
					pc_array_free(&a);
					pc_view_free(out);
					return rc;
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
	const uint64_t stride = g->stride ? g->stride : row;
	if (stride < row)
		return pc_error(PC_EINVAL, "%s: raw stride %llu below the row size %zu", path,
		                (unsigned long long)stride, row);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path,
		                strerror(errno));
	/* The geometry must lie inside the file: offset + (height − 1)·stride + row bytes, every
	 * step checked for overflow (a stride of 2^64 − 1 must not wrap round to a small one). */
	const uint64_t fsize = pc_io_file_size(fp);
	const uint64_t h1 = (uint64_t)g->height - 1;
	uint64_t need = 0;
	bool over = (h1 && stride > (UINT64_MAX - row) / h1);
	if (!over) {
		need = h1 * stride + row;
		over = g->offset > UINT64_MAX - need || g->offset + need > (uint64_t)INT64_MAX;
	}
	if (over || (fsize != UINT64_MAX && g->offset + need > fsize)) {
		char needs[48] = "more than 2^63", have[48] = "";
		if (!over)
			snprintf(needs, sizeof needs, "%llu",
			         (unsigned long long)(g->offset + need));
		if (fsize != UINT64_MAX)
			snprintf(have, sizeof have, ", the file has %llu",
			         (unsigned long long)fsize);
		fclose(fp);
		return pc_error(PC_EFORMAT,
		                "%s: %s: a %ux%u %s raw at offset %llu with stride %llu "
		                "needs %s bytes%s",
		                path, over ? "geometry beyond any file" : "truncated", g->width,
		                g->height, fi->name, (unsigned long long)g->offset,
		                (unsigned long long)stride, needs, have);
	}
	if ((rc = pc_io_check_image(path, g->width, g->height, (uint64_t)row * g->height))) {
		fclose(fp);
		return rc;
	}
	rc = pc_view_alloc(out, g->format, g->width, g->height, 1);
	if (rc) {
		fclose(fp);
		return pc_error_prefix(rc, "%s: ", path);
	}
	for (uint32_t y = 0; y < g->height; y++) {
		const uint64_t pos = g->offset + (uint64_t)y * stride;
		if ((y == 0 || stride > row) && fseeko(fp, (off_t)pos, SEEK_SET) != 0) {
			rc = pc_error(PC_EFORMAT, "%s: cannot seek to byte %llu (row %u)", path,
			              (unsigned long long)pos, y);
			goto fail;
		}
		if (fread(PC_ROW(out, uint8_t, y), 1, row, fp) != row) {
			rc = pc_error(PC_EFORMAT,
			              "%s: truncated at row %u of %u (%ux%u %s, offset %llu)", path,
			              y, g->height, g->width, g->height, fi->name,
			              (unsigned long long)g->offset);
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
	return pc_error(PC_EFORMAT,
	                "%s: unknown file type (expected .png, .tif/.tiff, .npy, .bmp, "
	                "or a raw file with its geometry)",
	                path);
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
			return pc_error(PC_EFORMAT,
			                "%s: holds float32 data, not %u-bit integers (wrong "
			                "bit depth)",
			                path, bits);
		}
		/* finiteness was checked by the reader; the magnitude here (io_internal.h) */
		for (uint32_t y = 0; y < out->height; y++) {
			const float *r = PC_ROW(out, const float, y);
			for (uint32_t x = 0; x < out->width; x++)
				if (!(fabsf(r[x]) <= PC_RAW_FLOAT_MAX)) {
					double v = r[x];
					pc_view_free(out);
					return pc_error(PC_ERANGE,
					                "%s: pixel (%u,%u) = %g: a float raw "
					                "holds intensities relative to a full "
					                "scale of 1.0 and must stay within "
					                "+-2^24 (%.4g), where demosaicking and "
					                "Stokes in float32 cannot overflow",
					                path, x, y, v, (double)PC_RAW_FLOAT_MAX);
				}
		}
		if (bits_out)
			*bits_out = 32;
		return 0;
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
		return pc_error(PC_EFORMAT,
		                "%s: holds %u-bit data in %u-bit samples, not %u-bit "
		                "data (wrong bit depth: 1..8-bit data comes in 8-bit "
		                "samples, 9..16-bit data in 16-bit samples)",
		                path, held, cont, bits);
	}
	rc = pc_view_check_bits(out, bits);
	if (rc) {
		pc_view_free(out);
		if (container == 16 && bits < 16)
			return pc_error_prefix(
			    rc,
			    "%s: %u-bit data expected (polarcam keeps values "
			    "LSB-aligned; for data scaled to the full 16 bits pass "
			    "16 bits): ",
			    path, bits);
		return pc_error_prefix(rc, "%s: ", path);
	}
	if (fi->packing == PC_PACK_NONE && container == 16) {
		/* Relabel: the values fit, so the LSB-aligned container format says the depth. */
		out->format = bits == 10   ? PC_FMT_MONO10
		              : bits == 12 ? PC_FMT_MONO12
		              : bits == 14 ? PC_FMT_MONO14
		                           : PC_FMT_MONO16; /* other depths: *bits_out tells */
	}
	if (bits_out)
		*bits_out = bits;
	return 0;
}
