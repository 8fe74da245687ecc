#include "polarcam/io.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "polarcam/error.h"

/* libpng's error callback: keep the message, longjmp back to the caller. */
typedef struct png_ctx {
	char msg[256];
} png_ctx;

static void png_err(png_structp png, png_const_charp msg)
{
	png_ctx *c = png_get_error_ptr(png);
	snprintf(c->msg, sizeof c->msg, "%s", msg);
	png_longjmp(png, 1);
}

static void png_warn(png_structp png, png_const_charp msg)
{
	(void)png;
	(void)msg;
}

static int pc_png_write_rows_(const char *path, uint32_t w, uint32_t h, int bit_depth,
                              int color_type, int sbit, const uint8_t *const *rows)
{
	pc_atomic_file af;
	int rc = pc_atomic_open(&af, path);
	if (rc)
		return rc;
	png_ctx ctx = {{0}};
	png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &ctx, png_err, png_warn);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	if (!png || !info) {
		png_destroy_write_struct(&png, &info);
		pc_atomic_abort(&af);
		return pc_error(PC_ENOMEM, "%s: cannot create PNG writer", path);
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_write_struct(&png, &info);
		pc_atomic_abort(&af);
		return pc_error(PC_EIO, "%s: PNG write failed: %s", path, ctx.msg);
	}
	png_init_io(png, af.fp);
	/* Raw frames are written often and large: favour speed over size. */
	png_set_compression_level(png, 1);
	png_set_filter(png, 0, PNG_FILTER_SUB);
	png_set_IHDR(png, info, w, h, bit_depth, color_type, PNG_INTERLACE_NONE,
	             PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
	if (sbit > 0 && sbit < bit_depth) {
		png_color_8 sb;
		memset(&sb, 0, sizeof sb);
		sb.gray = (png_byte)sbit;
		png_set_sBIT(png, info, &sb);
	}
	png_write_info(png, info);
	if (bit_depth == 16)
		png_set_swap(png); /* our rows are little-endian uint16, PNG is big-endian */
	for (uint32_t y = 0; y < h; y++)
		png_write_row(png, rows[y]);
	png_write_end(png, info);
	png_destroy_write_struct(&png, &info);
	return pc_atomic_commit(&af);
}

int pc_png_write(const char *path, const pc_view *v)
{
	int rc = pc_view_check(v);
	if (rc)
		return pc_error_prefix(rc, "%s: ", path);
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (fi->is_float)
		return pc_error(PC_EFORMAT, "%s: PNG cannot hold float32 data (use .npy or TIFF)",
		                path);
	const uint8_t **rows = malloc(sizeof *rows * v->height);
	if (!rows)
		return pc_error(PC_ENOMEM, "%s", path);
	pc_view tmp = {0};
	const pc_view *src = v;
	if (fi->packing != PC_PACK_NONE) {
		rc = pc_view_alloc(&tmp, PC_FMT_MONO16, v->width, v->height, 1);
		if (!rc)
			rc = pc_view_to_u16(v, tmp.data, tmp.stride);
		if (rc) {
			pc_view_free(&tmp);
			free(rows);
			return pc_error_prefix(rc, "%s: ", path);
		}
		src = &tmp;
	}
	for (uint32_t y = 0; y < v->height; y++)
		rows[y] = PC_ROW(src, const uint8_t, y);
	int depth = fi->bits <= 8 ? 8 : 16;
	rc = pc_png_write_rows_(path, v->width, v->height, depth, PNG_COLOR_TYPE_GRAY,
	                        (int)fi->bits, rows);
	free(rows);
	pc_view_free(&tmp);
	return rc;
}

int pc_png_write_rgb8(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height,
                      size_t stride)
{
	if (!rgb || width == 0 || height == 0 || stride < (size_t)width * 3)
		return pc_error(PC_EINVAL, "%s: bad RGB image geometry %ux%u stride %zu", path,
		                width, height, stride);
	const uint8_t **rows = malloc(sizeof *rows * height);
	if (!rows)
		return pc_error(PC_ENOMEM, "%s", path);
	for (uint32_t y = 0; y < height; y++)
		rows[y] = rgb + (size_t)y * stride;
	int rc = pc_png_write_rows_(path, width, height, 8, PNG_COLOR_TYPE_RGB, 0, rows);
	free(rows);
	return rc;
}

int pc_png_read(const char *path, pc_view *out, unsigned *significant_bits)
{
	memset(out, 0, sizeof *out);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path,
		                strerror(errno));
	png_ctx ctx = {{0}};
	png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &ctx, png_err, png_warn);
	png_infop info = png ? png_create_info_struct(png) : NULL;
	uint8_t **volatile rows = NULL;
	if (!png || !info) {
		png_destroy_read_struct(&png, &info, NULL);
		fclose(fp);
		return pc_error(PC_ENOMEM, "%s: cannot create PNG reader", path);
	}
	if (setjmp(png_jmpbuf(png))) {
		png_destroy_read_struct(&png, &info, NULL);
		fclose(fp);
		free(rows);
		pc_view_free(out);
		return pc_error(PC_EFORMAT, "%s: not a valid PNG or truncated: %s", path, ctx.msg);
	}
	png_init_io(png, fp);
	/* libpng's own dimension limit (default 10^6 per side) only as a backstop: the pixel and
	 * byte limits are checked below, before anything is decoded */
	png_set_user_limits(png, 0x7fffffffu, 0x7fffffffu);
	png_read_info(png, info);
	png_uint_32 w, h;
	int depth, ctype, ilace;
	png_get_IHDR(png, info, &w, &h, &depth, &ctype, &ilace, NULL, NULL);
	if (ctype != PNG_COLOR_TYPE_GRAY) {
		png_destroy_read_struct(&png, &info, NULL);
		fclose(fp);
		return pc_error(PC_EFORMAT,
		                "%s: a colour PNG (type %d); raw mosaics are single-channel "
		                "grey",
		                path, ctype);
	}
	/* Before decoding: the limits, and the file's length. The filtered rows (a filter byte and
	 * ceil(w·depth/8) bytes each) are deflate-compressed, and deflate cannot do better than
	 * 1032:1 (a 258-byte match in two 1-bit codes, RFC 1951), so a file shorter than that
	 * fraction of them cannot hold the image its header declares. */
	{
		const uint64_t out_bytes = (uint64_t)w * h * (depth == 16 ? 2u : 1u);
		const uint64_t filtered =
		    (uint64_t)h * (1 + ((uint64_t)w * (unsigned)depth + 7) / 8);
		const uint64_t fsize = pc_io_file_size(fp);
		int lrc = pc_io_check_image(path, w, h, out_bytes);
		if (!lrc && fsize != UINT64_MAX && fsize < filtered / 1032)
			lrc = pc_error(PC_EFORMAT,
			               "%s: truncated: a %ux%u %d-bit PNG needs at least "
			               "%llu bytes even at deflate's maximum compression, "
			               "the file has %llu",
			               path, (unsigned)w, (unsigned)h, depth,
			               (unsigned long long)(filtered / 1032),
			               (unsigned long long)fsize);
		if (lrc) {
			png_destroy_read_struct(&png, &info, NULL);
			fclose(fp);
			return lrc;
		}
	}
	if (depth < 8)
		png_set_expand_gray_1_2_4_to_8(png);
	if (depth == 16)
		png_set_swap(png);
	png_read_update_info(png, info);
	unsigned sbits = depth < 8 ? 8u : (unsigned)depth;
	png_color_8p sb;
	if (png_get_sBIT(png, info, &sb) && sb->gray > 0 && sb->gray <= depth)
		sbits = sb->gray;
	int rc = pc_view_alloc(out, depth == 16 ? PC_FMT_MONO16 : PC_FMT_MONO8, w, h, 1);
	if (rc) {
		png_destroy_read_struct(&png, &info, NULL);
		fclose(fp);
		return pc_error_prefix(rc, "%s: ", path);
	}
	rows = malloc(sizeof *rows * h);
	if (!rows)
		png_error(png, "out of memory");
	for (uint32_t y = 0; y < h; y++)
		rows[y] = PC_ROW(out, uint8_t, y);
	png_read_image(png, rows);
	png_read_end(png, NULL);
	png_destroy_read_struct(&png, &info, NULL);
	free(rows);
	fclose(fp);
	if (significant_bits)
		*significant_bits = sbits;
	return 0;
}
