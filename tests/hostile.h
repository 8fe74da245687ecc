/* tests/hostile.h - hostile and malformed input files, written byte by byte so that a test does
 * not depend on the writers it tests: .npy with any header text, PNG with any IHDR (chunk CRCs
 * computed here), BMP headers, TIFFs through libtiff then patched. Header-only; each helper
 * returns 0 on success. */
#ifndef POLARCAM_TESTS_HOSTILE_H
#define POLARCAM_TESTS_HOSTILE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>
#include <zlib.h>

static int hostile_write(const char *path, const void *data, size_t n)
{
	FILE *fp = fopen(path, "wb");
	if (!fp)
		return -1;
	int rc = (n && fwrite(data, 1, n, fp) != n) ? -1 : 0;
	if (fclose(fp))
		rc = -1;
	return rc;
}

/* .npy 1.0 with the dictionary text as given (padded to 64 bytes), then n data bytes. */
static int hostile_npy(const char *path, const char *dict, const void *data, size_t n)
{
	size_t hl = strlen(dict), total = 10 + hl + 1, pad = (total + 63) / 64 * 64 - total;
	size_t hlen = hl + pad + 1, size = 10 + hlen + n;
	uint8_t *b = malloc(size);
	if (!b)
		return -1;
	memcpy(b, "\x93NUMPY\x01\x00", 8);
	b[8] = (uint8_t)(hlen & 0xff);
	b[9] = (uint8_t)(hlen >> 8);
	memcpy(b + 10, dict, hl);
	memset(b + 10 + hl, ' ', pad);
	b[10 + hl + pad] = '\n';
	if (n)
		memcpy(b + 10 + hlen, data, n);
	int rc = hostile_write(path, b, size);
	free(b);
	return rc;
}

static void hostile_be32(uint8_t *p, uint32_t v)
{
	p[0] = (uint8_t)(v >> 24);
	p[1] = (uint8_t)(v >> 16);
	p[2] = (uint8_t)(v >> 8);
	p[3] = (uint8_t)v;
}

static void hostile_le32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

/* Appends a PNG chunk (length, type, data, CRC over type and data) at *o. */
static void hostile_png_chunk(uint8_t *b, size_t *o, const char *type, const void *data, uint32_t n)
{
	hostile_be32(b + *o, n);
	memcpy(b + *o + 4, type, 4);
	if (n)
		memcpy(b + *o + 8, data, n);
	uint32_t crc = (uint32_t)crc32(0, b + *o + 4, 4 + n);
	hostile_be32(b + *o + 8 + n, crc);
	*o += 12 + n;
}

/* A grey PNG whose IHDR declares w × h at `depth` bits and whose IDAT holds `rows` rows of
 * zeros at compression level 9 (rows = 0: an empty IDAT; rows = h: the whole image, which
 * deflates at nearly 1032:1: a decompression bomb for large w × h). */
static int hostile_png(const char *path, uint32_t w, uint32_t h, int depth, uint32_t rows)
{
	size_t rowb = 1 + ((size_t)w * (size_t)depth + 7) / 8, raw = rowb * rows;
	uLong bound = compressBound((uLong)raw);
	uint8_t *z = malloc(bound + 1), *zero = calloc(1, raw + 1);
	uint8_t *b = malloc(bound + 128);
	if (!z || !zero || !b) {
		free(z);
		free(zero);
		free(b);
		return -1;
	}
	uLongf zn = bound;
	int rc = compress2(z, &zn, zero, (uLong)raw, 9) == Z_OK ? 0 : -1;
	size_t o = 0;
	memcpy(b, "\x89PNG\r\n\x1a\n", 8);
	o = 8;
	uint8_t ihdr[13];
	hostile_be32(ihdr, w);
	hostile_be32(ihdr + 4, h);
	ihdr[8] = (uint8_t)depth;
	ihdr[9] = 0; /* grey */
	ihdr[10] = ihdr[11] = ihdr[12] = 0;
	hostile_png_chunk(b, &o, "IHDR", ihdr, 13);
	hostile_png_chunk(b, &o, "IDAT", z, (uint32_t)zn);
	hostile_png_chunk(b, &o, "IEND", NULL, 0);
	if (!rc)
		rc = hostile_write(path, b, o);
	free(z);
	free(zero);
	free(b);
	return rc;
}

/* An uncompressed 8-bit grey-palette BMP header declaring w × h (top-down when h < 0), followed
 * by `data_bytes` bytes of pixel data. */
static int hostile_bmp(const char *path, int32_t w, int32_t h, size_t data_bytes)
{
	size_t size = 14 + 40 + 1024 + data_bytes;
	uint8_t *b = calloc(1, size);
	if (!b)
		return -1;
	b[0] = 'B';
	b[1] = 'M';
	hostile_le32(b + 2, (uint32_t)size);
	hostile_le32(b + 10, 14 + 40 + 1024);
	hostile_le32(b + 14, 40);
	hostile_le32(b + 18, (uint32_t)w);
	hostile_le32(b + 22, (uint32_t)h);
	b[26] = 1;
	b[28] = 8;
	for (int i = 0; i < 256; i++)
		b[54 + 4 * i] = b[55 + 4 * i] = b[56 + 4 * i] = (uint8_t)i;
	int rc = hostile_write(path, b, size);
	free(b);
	return rc;
}

enum hostile_tiff_kind {
	HOSTILE_TIFF_GREY8,           /* a valid 8-bit grey w × h strip TIFF (zeros) */
	HOSTILE_TIFF_PALETTE,         /* 8-bit palette (photometric 3 and a colour map) */
	HOSTILE_TIFF_PALETTE_NOPHOTO, /* the same with the photometric tag renamed away */
	HOSTILE_TIFF_YCBCR_TILED,     /* 16 × 16 tiles of YCbCr 2×2-subsampled samples */
	HOSTILE_TIFF_SIGNED16,        /* 16-bit signed samples */
};

/* Renames the first IFD entry with tag `from` to `to` (little-endian classic TIFF). */
static int hostile_tiff_retag(const char *path, uint16_t from, uint16_t to)
{
	FILE *fp = fopen(path, "r+b");
	if (!fp)
		return -1;
	uint8_t h[8];
	int rc = -1;
	if (fread(h, 1, 8, fp) == 8 && h[0] == 'I') {
		long off = (long)(h[4] | h[5] << 8 | h[6] << 16 | (uint32_t)h[7] << 24);
		uint8_t nb[2];
		if (!fseek(fp, off, SEEK_SET) && fread(nb, 1, 2, fp) == 2) {
			unsigned n = nb[0] | nb[1] << 8;
			for (unsigned i = 0; i < n && rc; i++) {
				uint8_t e[12];
				if (fseek(fp, off + 2 + 12 * (long)i, SEEK_SET) ||
				    fread(e, 1, 12, fp) != 12)
					break;
				if ((e[0] | e[1] << 8) == from) {
					e[0] = (uint8_t)to;
					e[1] = (uint8_t)(to >> 8);
					if (!fseek(fp, off + 2 + 12 * (long)i, SEEK_SET) &&
					    fwrite(e, 1, 2, fp) == 2)
						rc = 0;
				}
			}
		}
	}
	if (fclose(fp))
		rc = -1;
	return rc;
}

/* Patches the first IFD entry with tag `tag` (SHORT or LONG, value in the entry) to v. */
static int hostile_tiff_set(const char *path, uint16_t tag, uint32_t v)
{
	FILE *fp = fopen(path, "r+b");
	if (!fp)
		return -1;
	uint8_t h[8];
	int rc = -1;
	if (fread(h, 1, 8, fp) == 8 && h[0] == 'I') {
		long off = (long)(h[4] | h[5] << 8 | h[6] << 16 | (uint32_t)h[7] << 24);
		uint8_t nb[2];
		if (!fseek(fp, off, SEEK_SET) && fread(nb, 1, 2, fp) == 2) {
			unsigned n = nb[0] | nb[1] << 8;
			for (unsigned i = 0; i < n && rc; i++) {
				uint8_t e[12];
				if (fseek(fp, off + 2 + 12 * (long)i, SEEK_SET) ||
				    fread(e, 1, 12, fp) != 12)
					break;
				if ((e[0] | e[1] << 8) != tag)
					continue;
				unsigned type = e[2] | e[3] << 8;
				if (type == 3) { /* SHORT */
					e[8] = (uint8_t)v;
					e[9] = (uint8_t)(v >> 8);
				} else {
					hostile_le32(e + 8, v);
				}
				if (!fseek(fp, off + 2 + 12 * (long)i, SEEK_SET) &&
				    fwrite(e, 1, 12, fp) == 12)
					rc = 0;
			}
		}
	}
	if (fclose(fp))
		rc = -1;
	return rc;
}

static int hostile_tiff(const char *path, enum hostile_tiff_kind kind, uint32_t w, uint32_t h)
{
	TIFF *t = TIFFOpen(path, "w");
	if (!t)
		return -1;
	TIFFSetField(t, TIFFTAG_IMAGEWIDTH, w);
	TIFFSetField(t, TIFFTAG_IMAGELENGTH, h);
	TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
	int rc = 0;
	if (kind == HOSTILE_TIFF_YCBCR_TILED) {
		TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
		TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 3);
		TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_YCBCR);
		TIFFSetField(t, TIFFTAG_YCBCRSUBSAMPLING, 2, 2);
		TIFFSetField(t, TIFFTAG_TILEWIDTH, 16);
		TIFFSetField(t, TIFFTAG_TILELENGTH, 16);
		tmsize_t ts = TIFFTileSize(t);
		uint8_t *tile = calloc(1, (size_t)ts);
		for (uint32_t y = 0; y < h && tile; y += 16)
			for (uint32_t x = 0; x < w; x += 16)
				if (TIFFWriteTile(t, tile, x, y, 0, 0) < 0)
					rc = -1;
		free(tile);
	} else {
		int signed16 = kind == HOSTILE_TIFF_SIGNED16;
		TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, signed16 ? 16 : 8);
		TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
		TIFFSetField(t, TIFFTAG_SAMPLEFORMAT,
		             signed16 ? SAMPLEFORMAT_INT : SAMPLEFORMAT_UINT);
		TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, h);
		if (kind == HOSTILE_TIFF_PALETTE || kind == HOSTILE_TIFF_PALETTE_NOPHOTO) {
			static uint16_t cm[3][256];
			for (int i = 0; i < 256; i++) {
				cm[0][i] = (uint16_t)(65535 - 256 * i);
				cm[1][i] = (uint16_t)(256 * i);
				cm[2][i] = 0;
			}
			TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_PALETTE);
			TIFFSetField(t, TIFFTAG_COLORMAP, cm[0], cm[1], cm[2]);
		} else {
			TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
		}
		uint8_t *row = calloc(1, (size_t)w * 2 + 1);
		for (uint32_t y = 0; y < h && row; y++) {
			for (uint32_t x = 0; x < w && !signed16; x++)
				row[x] = (uint8_t)(x + y);
			if (TIFFWriteScanline(t, row, y, 0) < 0)
				rc = -1;
		}
		free(row);
	}
	TIFFClose(t);
	if (!rc && kind == HOSTILE_TIFF_PALETTE_NOPHOTO) /* Photometric → Thresholding (263) */
		rc = hostile_tiff_retag(path, TIFFTAG_PHOTOMETRIC, TIFFTAG_THRESHHOLDING);
	return rc;
}

#endif
