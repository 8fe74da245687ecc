/* Grey BMP reading (some public polarization datasets ship 8-bit BMPs). Supported: the Windows
 * BITMAPINFOHEADER family (header size >= 40), uncompressed (BI_RGB), 8-bit with a grey palette
 * or 24/32-bit with equal R, G, B; bottom-up or top-down rows padded to 4 bytes. Layout: the
 * "BMP file format" description of BITMAPFILEHEADER / BITMAPINFOHEADER (Microsoft docs). */
#include "polarcam/io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "polarcam/error.h"

static uint32_t le32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint16_t le16(const uint8_t *p)
{
	return (uint16_t)(p[0] | p[1] << 8);
}

int pc_bmp_read(const char *path, pc_view *out)
{
	memset(out, 0, sizeof *out);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path,
		                strerror(errno));
	uint8_t h[54];
	uint8_t *row = NULL;
	int rc = 0;
	if (fread(h, 1, sizeof h, fp) != sizeof h || h[0] != 'B' || h[1] != 'M') {
		rc = pc_error(PC_EFORMAT, "%s: not a BMP file (bad or truncated header)", path);
		goto out;
	}
	uint32_t data_off = le32(h + 10), hsize = le32(h + 14);
	int32_t w = (int32_t)le32(h + 18), hh = (int32_t)le32(h + 22);
	uint16_t planes = le16(h + 26), bpp = le16(h + 28);
	uint32_t compression = le32(h + 30), ncolors = le32(h + 46);
	if (hsize < 40 || planes != 1) {
		rc = pc_error(PC_EFORMAT, "%s: unsupported BMP header (size %u, planes %u)", path,
		              hsize, planes);
		goto out;
	}
	if (compression != 0) {
		rc = pc_error(PC_EFORMAT, "%s: compressed BMP (method %u) not supported", path,
		              compression);
		goto out;
	}
	if (bpp != 8 && bpp != 24 && bpp != 32) {
		rc = pc_error(PC_EFORMAT, "%s: %u-bit BMP: expected 8-bit grey or 24/32-bit", path,
		              bpp);
		goto out;
	}
	if (w <= 0 || hh == 0 || hh == INT32_MIN || w > 1 << 20 || hh > 1 << 20 ||
	    hh < -(1 << 20)) {
		rc = pc_error(PC_EFORMAT, "%s: BMP size %dx%d is not a valid image", path, w, hh);
		goto out;
	}
	int top_down = hh < 0;
	uint32_t height = (uint32_t)(top_down ? -hh : hh), width = (uint32_t)w;
	uint8_t lut[256];
	if (bpp == 8) {
		if (ncolors == 0 || ncolors > 256)
			ncolors = 256;
		uint8_t pal[256 * 4];
		if (fseek(fp, 14 + (long)hsize, SEEK_SET) != 0 ||
		    fread(pal, 4, ncolors, fp) != ncolors) {
			rc = pc_error(PC_EFORMAT, "%s: truncated BMP palette", path);
			goto out;
		}
		memset(lut, 0, sizeof lut);
		for (uint32_t i = 0; i < ncolors; i++) {
			if (pal[4 * i] != pal[4 * i + 1] || pal[4 * i] != pal[4 * i + 2]) {
				rc = pc_error(PC_EFORMAT,
				              "%s: colour palette entry %u: a raw mosaic or "
				              "analyser image is grey",
				              path, i);
				goto out;
			}
			lut[i] = pal[4 * i];
		}
	}
	size_t row_bytes = ((size_t)width * bpp / 8 + 3) / 4 * 4;
	/* before allocating from the header: the limits, and the file must hold every row */
	if ((rc = pc_io_check_image(path, width, height, (uint64_t)width * height)))
		goto out;
	const uint64_t fsize = pc_io_file_size(fp);
	if (fsize != UINT64_MAX &&
	    (data_off > fsize || (uint64_t)row_bytes * height > fsize - data_off)) {
		rc = pc_error(PC_EFORMAT,
		              "%s: truncated BMP: %u rows of %zu bytes from offset %u need "
		              "%llu bytes, the file has %llu",
		              path, height, row_bytes, data_off,
		              (unsigned long long)data_off + (uint64_t)row_bytes * height,
		              (unsigned long long)fsize);
		goto out;
	}
	row = malloc(row_bytes);
	if (!row) {
		rc = pc_error(PC_ENOMEM, "%s", path);
		goto out;
	}
	rc = pc_view_alloc(out, PC_FMT_MONO8, width, height, 1);
	if (rc) {
		pc_error_prefix(rc, "%s: ", path);
		goto out;
	}
	if (fseek(fp, (long)data_off, SEEK_SET) != 0) {
		rc = pc_error(PC_EFORMAT, "%s: BMP pixel data offset %u beyond the file", path,
		              data_off);
		goto out;
	}
	for (uint32_t i = 0; i < height; i++) {
		if (fread(row, 1, row_bytes, fp) != row_bytes) {
			rc = pc_error(PC_EFORMAT, "%s: truncated BMP: row %u of %u missing", path,
			              i, height);
			goto out;
		}
		uint32_t y = top_down ? i : height - 1 - i;
		uint8_t *d = PC_ROW(out, uint8_t, y);
		if (bpp == 8) {
			for (uint32_t x = 0; x < width; x++)
				d[x] = lut[row[x]];
			continue;
		}
		unsigned step = bpp / 8;
		for (uint32_t x = 0; x < width; x++) {
			const uint8_t *p = row + (size_t)x * step;
			if (p[0] != p[1] || p[0] != p[2]) {
				rc = pc_error(PC_EFORMAT,
				              "%s: colour pixel (%u,%u): a raw mosaic or "
				              "analyser image is grey",
				              path, x, y);
				goto out;
			}
			d[x] = p[0];
		}
	}
out:
	free(row);
	fclose(fp);
	if (rc)
		pc_view_free(out);
	return rc;
}
