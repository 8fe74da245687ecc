/* TIFF through libtiff: single-channel 8/16-bit unsigned and 32-bit float images (raw mosaics,
 * ground truth), and multi-channel interleaved arrays (float outputs such as Stokes images).
 *
 * libtiff reports problems through handlers; TIFFOpenExt's per-file handlers (libtiff >= 4.5)
 * collect the first message into the caller's context, so concurrent reads do not share state
 * and nothing is printed behind the caller's back. Writers go through pc_atomic_* via
 * TIFFClientOpenExt on the temporary file's FILE*. */
#include "polarcam/io.h"

#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <tiffio.h>

#include "io_internal.h"
#include "polarcam/error.h"
#include "polarcam/limits.h"

typedef struct tiff_ctx {
	char msg[256];
	uint64_t file_size; /* of the file being read (UINT64_MAX: unknown) */
} tiff_ctx;

/* fmt is libtiff's printf format for ap: the attribute lets the compiler check that use. */
#if defined(__GNUC__)
__attribute__((format(printf, 4, 0)))
#endif
static int
tiff_on_error(TIFF *t, void *ud, const char *module, const char *fmt, va_list ap)
{
	(void)t;
	(void)module;
	tiff_ctx *c = ud;
	if (c && !c->msg[0])
		vsnprintf(c->msg, sizeof c->msg, fmt, ap);
	return 1; /* handled: libtiff must not print */
}

static int tiff_on_warning(TIFF *t, void *ud, const char *module, const char *fmt, va_list ap)
{
	(void)t;
	(void)ud;
	(void)module;
	(void)fmt;
	(void)ap;
	return 1;
}

static TIFFOpenOptions *tiff_options(tiff_ctx *c)
{
	TIFFOpenOptions *o = TIFFOpenOptionsAlloc();
	if (!o)
		return NULL;
	TIFFOpenOptionsSetErrorHandlerExtR(o, tiff_on_error, c);
	TIFFOpenOptionsSetWarningHandlerExtR(o, tiff_on_warning, c);
	/* libtiff's own allocations (directories, strip tables, codec buffers) stay within the
	 * byte limit too (polarcam/limits.h) */
	uint64_t lim = pc_limit_get(PC_LIMIT_BYTES);
	TIFFOpenOptionsSetMaxSingleMemAlloc(o,
	                                    lim > (uint64_t)INT64_MAX ? INT64_MAX : (tmsize_t)lim);
	return o;
}

/* The most a codec can expand its input (bytes out per byte in), to check a file's length
 * against its header before allocating: 0 when unknown (no check). Deflate: 1032:1 (RFC 1951:
 * a 258-byte match in two 1-bit codes); PackBits: 128 bytes from a 2-byte run; LZW (TIFF 6.0
 * §13): a code of at least 9 bits stands for at most 4094 − 258 bytes between table resets. */
static uint64_t tiff_max_ratio(uint16_t compression)
{
	switch (compression) {
	case COMPRESSION_NONE:
		return 1;
	case COMPRESSION_ADOBE_DEFLATE:
	case COMPRESSION_DEFLATE:
		return 1032;
	case COMPRESSION_PACKBITS:
		return 64;
	case COMPRESSION_LZW:
		return 3836 * 8 / 9 + 1;
	default:
		return 0;
	}
}

typedef struct tiff_info {
	uint32_t width, height;
	uint16_t spp, bps, sample_format;
	pc_dtype dtype;
} tiff_info;

/* Opens path for reading and validates what polarcam can hold: unsigned 8/16-bit or IEEE
 * 32-bit float samples, chunky (interleaved) when there are several samples per pixel. */
static int tiff_open_read(const char *path, tiff_ctx *c, TIFF **out, tiff_info *info)
{
	*out = NULL;
	FILE *probe = fopen(path, "rb");
	if (!probe)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path,
		                strerror(errno));
	c->file_size = pc_io_file_size(probe);
	fclose(probe);
	TIFFOpenOptions *o = tiff_options(c);
	if (!o)
		return pc_error(PC_ENOMEM, "%s: cannot create TIFF reader", path);
	TIFF *t = TIFFOpenExt(path, "r", o);
	TIFFOpenOptionsFree(o);
	if (!t)
		return pc_error(PC_EFORMAT, "%s: not a readable TIFF file: %s", path,
		                c->msg[0] ? c->msg : "libtiff could not open it");
	uint32_t w = 0, h = 0;
	uint16_t spp = 1, bps = 1, sfmt = SAMPLEFORMAT_UINT, photo = PHOTOMETRIC_MINISBLACK;
	uint16_t planar = PLANARCONFIG_CONTIG;
	int rc = 0;
	if (!TIFFGetField(t, TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(t, TIFFTAG_IMAGELENGTH, &h)) {
		rc = pc_error(PC_EFORMAT, "%s: TIFF without image width/length", path);
		goto fail;
	}
	TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLESPERPIXEL, &spp);
	TIFFGetFieldDefaulted(t, TIFFTAG_BITSPERSAMPLE, &bps);
	TIFFGetFieldDefaulted(t, TIFFTAG_SAMPLEFORMAT, &sfmt);
	TIFFGetFieldDefaulted(t, TIFFTAG_PLANARCONFIG, &planar);
	if (!TIFFGetField(t, TIFFTAG_PHOTOMETRIC, &photo))
		photo = PHOTOMETRIC_MINISBLACK;
	if (w == 0 || h == 0) {
		rc = pc_error(PC_EFORMAT, "%s: TIFF of size %ux%u: expected a non-empty image",
		              path, w, h);
		goto fail;
	}
	if (spp < 1 || spp > 16) {
		rc = pc_error(PC_EFORMAT, "%s: %u samples per pixel: not supported", path, spp);
		goto fail;
	}
	if (spp > 1 && planar != PLANARCONFIG_CONTIG) {
		rc = pc_error(PC_EFORMAT, "%s: planar (separate) TIFF samples are not supported",
		              path);
		goto fail;
	}
	/* A colour map makes the samples indices into it (a palette image), whatever the
	 * photometric tag says or when it is missing (libtiff then guesses min-is-black). */
	uint16_t *cmap[3];
	if (TIFFGetField(t, TIFFTAG_COLORMAP, &cmap[0], &cmap[1], &cmap[2]))
		photo = PHOTOMETRIC_PALETTE;
	if (photo != PHOTOMETRIC_MINISBLACK && !(photo == PHOTOMETRIC_RGB && spp >= 3)) {
		static const char *const names[] = {
		    "min-is-white", "min-is-black",     "RGB",  "palette",
		    "mask",         "separated (CMYK)", "YCbCr"};
		rc = pc_error(PC_EFORMAT,
		              "%s: TIFF photometric interpretation %u (%s): expected "
		              "min-is-black grey data%s",
		              path, photo, photo < 7 ? names[photo] : "other",
		              spp >= 3 ? " or RGB" : "");
		goto fail;
	}
	if (sfmt == SAMPLEFORMAT_UINT && (bps == 8 || bps == 16)) {
		info->dtype = bps == 8 ? PC_DT_U8 : PC_DT_U16;
	} else if (sfmt == SAMPLEFORMAT_IEEEFP && bps == 32) {
		info->dtype = PC_DT_F32;
	} else {
		const char *kind = sfmt == SAMPLEFORMAT_UINT     ? "unsigned"
		                   : sfmt == SAMPLEFORMAT_INT    ? "signed"
		                   : sfmt == SAMPLEFORMAT_IEEEFP ? "float"
		                                                 : "other";
		rc = pc_error(PC_EFORMAT,
		              "%s: TIFF with %u-bit %s samples: expected 8- or 16-bit "
		              "unsigned or 32-bit float",
		              path, bps, kind);
		goto fail;
	}
	/* Before allocating from the header's sizes: the limits, then the file's length, which must
	 * hold the strips or tiles (their byte counts times the codec's largest expansion must
	 * cover the image; every strip must lie inside the file). */
	{
		const uint64_t bytes = (uint64_t)w * h * spp * (bps / 8);
		if ((rc = pc_io_check_image(path, w, h, bytes)))
			goto fail;
		uint16_t comp = COMPRESSION_NONE;
		TIFFGetFieldDefaulted(t, TIFFTAG_COMPRESSION, &comp);
		const uint64_t ratio = tiff_max_ratio(comp);
		const uint64_t fsize = c->file_size;
		const uint32_t n = TIFFIsTiled(t) ? TIFFNumberOfTiles(t) : TIFFNumberOfStrips(t);
		uint64_t stored = 0;
		for (uint32_t i = 0; i < n; i++) {
			int err = 0;
			uint64_t off = TIFFGetStrileOffsetWithErr(t, i, &err);
			uint64_t cnt = err ? 0 : TIFFGetStrileByteCountWithErr(t, i, &err);
			if (err || (fsize != UINT64_MAX && (off > fsize || cnt > fsize - off))) {
				rc = pc_error(PC_EFORMAT,
				              "%s: truncated: TIFF %s %u lies beyond the "
				              "end of the file",
				              path, TIFFIsTiled(t) ? "tile" : "strip", i);
				goto fail;
			}
			stored += cnt;
		}
		if (ratio && stored < (bytes + ratio - 1) / ratio) {
			rc = pc_error(
			    PC_EFORMAT,
			    "%s: truncated: a %ux%u TIFF of %u x %u-bit samples "
			    "needs %llu bytes, its %s hold %llu",
			    path, w, h, spp, bps, (unsigned long long)((bytes + ratio - 1) / ratio),
			    TIFFIsTiled(t) ? "tiles" : "strips", (unsigned long long)stored);
			goto fail;
		}
	}
	info->width = w;
	info->height = h;
	info->spp = spp;
	info->bps = bps;
	info->sample_format = sfmt;
	*out = t;
	return 0;
fail:
	TIFFClose(t);
	return rc;
}

/* Reads all pixels into dst (tight rows of row_bytes), from strips or tiles. */
static int tiff_read_pixels(TIFF *t, tiff_ctx *c, const char *path, const tiff_info *info,
                            uint8_t *dst, size_t row_bytes)
{
	if (!TIFFIsTiled(t)) {
		if ((size_t)TIFFScanlineSize(t) != row_bytes)
			return pc_error(PC_EFORMAT, "%s: TIFF scanline size %lld, expected %zu",
			                path, (long long)TIFFScanlineSize(t), row_bytes);
		for (uint32_t y = 0; y < info->height; y++)
			if (TIFFReadScanline(t, dst + (size_t)y * row_bytes, y, 0) < 0)
				return pc_error(PC_EFORMAT,
				                "%s: TIFF row %u of %u unreadable "
				                "(truncated?): %s",
				                path, y, info->height,
				                c->msg[0] ? c->msg : "read error");
		return 0;
	}
	uint32_t tw = 0, th = 0;
	TIFFGetField(t, TIFFTAG_TILEWIDTH, &tw);
	TIFFGetField(t, TIFFTAG_TILELENGTH, &th);
	tmsize_t tsize = TIFFTileSize(t);
	size_t px = row_bytes / info->width;
	/* the copy below reads th rows of tw·px bytes from each tile: the decoded tile must hold
	 * exactly that (subsampled YCbCr tiles, for one, are smaller) */
	if (tw == 0 || th == 0 || tsize <= 0 || (uint64_t)tw * th * px != (uint64_t)tsize)
		return pc_error(PC_EFORMAT,
		                "%s: TIFF with invalid tiles (%ux%u, %lld bytes each for "
		                "%zu bytes per pixel)",
		                path, tw, th, (long long)tsize, px);
	/* the tile buffer comes from the header too: no larger than the image (rounded up to the
	 * 16-pixel tile grain of TIFF 6.0 §15) */
	const uint64_t img =
	    ((uint64_t)info->width + 15) / 16 * 16 * (((uint64_t)info->height + 15) / 16 * 16);
	if ((uint64_t)tw * th > img)
		return pc_error(PC_EFORMAT, "%s: TIFF tiles of %ux%u for a %ux%u image", path, tw,
		                th, info->width, info->height);
	uint8_t *tile = malloc((size_t)tsize);
	if (!tile)
		return pc_error(PC_ENOMEM, "%s: tile buffer of %lld bytes", path, (long long)tsize);
	for (uint32_t ty = 0; ty < info->height; ty += th)
		for (uint32_t tx = 0; tx < info->width; tx += tw) {
			if (TIFFReadTile(t, tile, tx, ty, 0, 0) < 0) {
				free(tile);
				return pc_error(PC_EFORMAT,
				                "%s: TIFF tile at (%u,%u) unreadable "
				                "(truncated?): %s",
				                path, tx, ty, c->msg[0] ? c->msg : "read error");
			}
			uint32_t cw = info->width - tx < tw ? info->width - tx : tw;
			uint32_t ch = info->height - ty < th ? info->height - ty : th;
			for (uint32_t y = 0; y < ch; y++)
				memcpy(dst + (size_t)(ty + y) * row_bytes + (size_t)tx * px,
				       tile + (size_t)y * tw * px, (size_t)cw * px);
		}
	free(tile);
	return 0;
}

static size_t dtype_bytes(pc_dtype t)
{
	return t == PC_DT_U8 ? 1 : t == PC_DT_U16 ? 2 : t == PC_DT_F32 ? 4 : 8;
}

int pc_tiff_read(const char *path, pc_view *out, unsigned *significant_bits)
{
	memset(out, 0, sizeof *out);
	tiff_ctx c = {{0}, UINT64_MAX};
	TIFF *t;
	tiff_info info;
	int rc = tiff_open_read(path, &c, &t, &info);
	if (rc)
		return rc;
	if (info.spp != 1) {
		TIFFClose(t);
		return pc_error(PC_EFORMAT,
		                "%s: TIFF with %u samples per pixel: a raw mosaic or "
		                "analyser image is single-channel",
		                path, info.spp);
	}
	pc_pixfmt fmt = info.dtype == PC_DT_U8    ? PC_FMT_MONO8
	                : info.dtype == PC_DT_U16 ? PC_FMT_MONO16
	                                          : PC_FMT_FLOAT32;
	rc = pc_view_alloc(out, fmt, info.width, info.height, 1);
	if (rc) {
		TIFFClose(t);
		return pc_error_prefix(rc, "%s: ", path);
	}
	rc = tiff_read_pixels(t, &c, path, &info, out->data, out->stride);
	TIFFClose(t);
	if (!rc && fmt == PC_FMT_FLOAT32) {
		rc = pc_view_check_bits(out, 32);
		if (rc)
			pc_error_prefix(rc, "%s: ", path);
	}
	if (rc) {
		pc_view_free(out);
		return rc;
	}
	if (significant_bits)
		*significant_bits = info.bps;
	return 0;
}

int pc_tiff_read_array(const char *path, pc_array *out)
{
	memset(out, 0, sizeof *out);
	tiff_ctx c = {{0}, UINT64_MAX};
	TIFF *t;
	tiff_info info;
	int rc = tiff_open_read(path, &c, &t, &info);
	if (rc)
		return rc;
	size_t px = dtype_bytes(info.dtype) * info.spp;
	if ((size_t)info.width > SIZE_MAX / px / info.height) {
		TIFFClose(t);
		return pc_error(PC_EOVERFLOW, "%s: %ux%u TIFF too large", path, info.width,
		                info.height);
	}
	size_t row = (size_t)info.width * px;
	out->data = malloc(row * info.height);
	if (!out->data) {
		TIFFClose(t);
		return pc_error(PC_ENOMEM, "%s: %zu bytes", path, row * info.height);
	}
	rc = tiff_read_pixels(t, &c, path, &info, out->data, row);
	TIFFClose(t);
	if (rc) {
		pc_array_free(out);
		return rc;
	}
	out->dtype = info.dtype;
	out->ndim = info.spp > 1 ? 3 : 2;
	out->shape[0] = info.height;
	out->shape[1] = info.width;
	out->shape[2] = info.spp;
	return 0;
}

/* ---- writing through the atomic file's FILE* ---- */
static tmsize_t fp_read(thandle_t h, void *buf, tmsize_t n)
{
	return (tmsize_t)fread(buf, 1, (size_t)n, (FILE *)h);
}

static tmsize_t fp_write(thandle_t h, void *buf, tmsize_t n)
{
	return (tmsize_t)fwrite(buf, 1, (size_t)n, (FILE *)h);
}

static toff_t fp_seek(thandle_t h, toff_t off, int whence)
{
	FILE *fp = h;
	if (fseeko(fp, (off_t)off, whence) != 0)
		return (toff_t)-1;
	return (toff_t)ftello(fp);
}

static int fp_close(thandle_t h)
{
	(void)h; /* pc_atomic_commit closes it */
	return 0;
}

static toff_t fp_size(thandle_t h)
{
	struct stat st;
	FILE *fp = h;
	fflush(fp);
	if (fstat(fileno(fp), &st) != 0)
		return 0;
	return (toff_t)st.st_size;
}

static int fp_map(thandle_t h, void **base, toff_t *size)
{
	(void)h;
	(void)base;
	(void)size;
	return 0;
}

static void fp_unmap(thandle_t h, void *base, toff_t size)
{
	(void)h;
	(void)base;
	(void)size;
}

/* Writes height rows of width pixels × spp samples (row(y) gives each row's bytes). */
typedef const void *(*tiff_row_fn)(void *ctx, uint32_t y);

static int tiff_write_rows(const char *path, uint32_t width, uint32_t height, uint16_t spp,
                           pc_dtype dtype, tiff_row_fn row, void *ctx)
{
	pc_atomic_file af;
	int rc = pc_atomic_open(&af, path);
	if (rc)
		return rc;
	tiff_ctx c = {{0}, UINT64_MAX};
	TIFFOpenOptions *o = tiff_options(&c);
	TIFF *t = o ? TIFFClientOpenExt(path, "w", (thandle_t)af.fp, fp_read, fp_write, fp_seek,
	                                fp_close, fp_size, fp_map, fp_unmap, o)
	            : NULL;
	if (o)
		TIFFOpenOptionsFree(o);
	if (!t) {
		pc_atomic_abort(&af);
		return pc_error(PC_EIO, "%s: cannot create TIFF writer: %s", path,
		                c.msg[0] ? c.msg : "out of memory");
	}
	uint16_t bps = (uint16_t)(8 * dtype_bytes(dtype));
	TIFFSetField(t, TIFFTAG_IMAGEWIDTH, width);
	TIFFSetField(t, TIFFTAG_IMAGELENGTH, height);
	TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, spp);
	TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, bps);
	TIFFSetField(t, TIFFTAG_SAMPLEFORMAT,
	             dtype == PC_DT_F32 || dtype == PC_DT_F64 ? SAMPLEFORMAT_IEEEFP
	                                                      : SAMPLEFORMAT_UINT);
	TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
	TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
	TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_NONE);
	TIFFSetField(t, TIFFTAG_ORIENTATION, ORIENTATION_TOPLEFT);
	if (spp > 1) {
		uint16_t extra[16];
		for (int i = 0; i < 16; i++)
			extra[i] = EXTRASAMPLE_UNSPECIFIED;
		TIFFSetField(t, TIFFTAG_EXTRASAMPLES, (uint16_t)(spp - 1), extra);
	}
	TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, TIFFDefaultStripSize(t, 0));
	TIFFSetField(t, TIFFTAG_SOFTWARE, "polarcam");
	size_t row_bytes = (size_t)width * spp * dtype_bytes(dtype);
	void *buf = malloc(row_bytes);
	rc = buf ? 0 : pc_error(PC_ENOMEM, "%s: row buffer", path);
	for (uint32_t y = 0; y < height && !rc; y++) {
		memcpy(buf, row(ctx, y), row_bytes); /* libtiff may modify the row it writes */
		if (TIFFWriteScanline(t, buf, y, 0) < 0)
			rc = pc_error(PC_EIO, "%s: TIFF write failed at row %u: %s", path, y,
			              c.msg[0] ? c.msg : "write error");
	}
	free(buf);
	if (!rc && !TIFFWriteDirectory(t))
		rc = pc_error(PC_EIO, "%s: TIFF write failed: %s", path,
		              c.msg[0] ? c.msg : "cannot write the directory");
	TIFFClose(t);
	if (rc) {
		pc_atomic_abort(&af);
		return rc;
	}
	return pc_atomic_commit(&af);
}

typedef struct view_rows {
	const pc_view *v;
} view_rows;

static const void *view_row(void *ctx, uint32_t y)
{
	view_rows *r = ctx;
	return PC_ROW(r->v, const uint8_t, y);
}

int pc_tiff_write(const char *path, const pc_view *v)
{
	int rc = pc_view_check(v);
	if (rc)
		return pc_error_prefix(rc, "%s: ", path);
	const pc_format_info *fi = pc_format_info_get(v->format);
	pc_view tmp = {0};
	const pc_view *src = v;
	if (fi->packing != PC_PACK_NONE) {
		rc = pc_view_alloc(&tmp, PC_FMT_MONO16, v->width, v->height, 1);
		if (!rc)
			rc = pc_view_to_u16(v, tmp.data, tmp.stride);
		if (rc) {
			pc_view_free(&tmp);
			return pc_error_prefix(rc, "%s: ", path);
		}
		src = &tmp;
	}
	pc_dtype dt = fi->is_float ? PC_DT_F32 : fi->bits <= 8 ? PC_DT_U8 : PC_DT_U16;
	view_rows r = {src};
	rc = tiff_write_rows(path, v->width, v->height, 1, dt, view_row, &r);
	pc_view_free(&tmp);
	return rc;
}

typedef struct array_rows {
	const uint8_t *data;
	size_t row_bytes;
} array_rows;

static const void *array_row(void *ctx, uint32_t y)
{
	array_rows *r = ctx;
	return r->data + (size_t)y * r->row_bytes;
}

int pc_tiff_write_array(const char *path, const void *data, pc_dtype dtype, uint32_t height,
                        uint32_t width, unsigned channels)
{
	if (!data || width == 0 || height == 0 || channels < 1 || channels > 16)
		return pc_error(PC_EINVAL, "%s: bad TIFF array geometry %ux%ux%u", path, height,
		                width, channels);
	if (dtype != PC_DT_U8 && dtype != PC_DT_U16 && dtype != PC_DT_F32)
		return pc_error(PC_EINVAL, "%s: TIFF arrays hold u8, u16 or f32 samples", path);
	array_rows r = {data, (size_t)width * channels * dtype_bytes(dtype)};
	return tiff_write_rows(path, width, height, (uint16_t)channels, dtype, array_row, &r);
}
