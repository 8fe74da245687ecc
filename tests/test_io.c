/* Files: round trips of every format polarcam reads and writes (TIFF 8/16/float32 and
 * multi-channel, .npy, PNG with sBIT, grey BMP, raw with explicit geometry in every packing),
 * and bad input: truncated files, wrong bit depth, out-of-range values, NaN, non-images. Every
 * failure must name the file and leave no output behind. */
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <tiffio.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/io.h"
#include "polarcam/stokes.h"

static char dir[64];

static const char *tmp(const char *name)
{
	static char buf[8][160];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

static int count_files(void)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)))
		if (e->d_name[0] != '.' || (e->d_name[1] && e->d_name[1] != '.'))
			n++;
	closedir(d);
	return n;
}

static uint32_t rng = 2463534242u;
static uint32_t next(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 17;
	rng ^= rng << 5;
	return rng;
}

static void truncate_file(const char *path, long keep)
{
	CHECK_EQ_INT(truncate(path, keep), 0);
}

/* Same pixels, whatever the strides. */
static int views_equal(const pc_view *a, const pc_view *b)
{
	if (a->width != b->width || a->height != b->height)
		return 0;
	const pc_format_info *fa = pc_format_info_get(a->format);
	for (uint32_t y = 0; y < a->height; y++)
		if (memcmp(PC_ROW(a, uint8_t, y), PC_ROW(b, uint8_t, y),
		           (size_t)a->width * fa->group_bytes / fa->group_pixels))
			return 0;
	return 1;
}

static void test_tiff(void)
{
	const pc_pixfmt fmts[] = {PC_FMT_MONO8, PC_FMT_MONO16, PC_FMT_FLOAT32};
	for (size_t i = 0; i < 3; i++) {
		pc_view v, back;
		CHECK_EQ_INT(pc_view_alloc(&v, fmts[i], 13, 7, 64), 0); /* padded stride */
		for (uint32_t y = 0; y < 7; y++)
			for (uint32_t x = 0; x < 13; x++) {
				uint32_t r = next();
				if (fmts[i] == PC_FMT_MONO8)
					PC_ROW(&v, uint8_t, y)[x] = (uint8_t)r;
				else if (fmts[i] == PC_FMT_MONO16)
					PC_ROW(&v, uint16_t, y)[x] = (uint16_t)r;
				else
					PC_ROW(&v, float, y)[x] = (float)((int32_t)r) * 1e-7f;
			}
		const char *p = tmp("a.tif");
		CHECK_EQ_INT(pc_tiff_write(p, &v), 0);
		unsigned sb = 0;
		CHECK_EQ_INT(pc_image_read(p, NULL, &back, &sb), 0);
		CHECK(back.format == fmts[i]);
		CHECK_EQ_INT(sb, fmts[i] == PC_FMT_MONO8 ? 8 : fmts[i] == PC_FMT_MONO16 ? 16 : 32);
		CHECK(views_equal(&v, &back));
		pc_view_free(&back);
		/* truncated: a clear error naming the file */
		truncate_file(p, 200);
		CHECK(pc_image_read(p, NULL, &back, NULL) != 0);
		CHECK(strstr(pc_error_detail(), "a.tif") != NULL);
		CHECK(back.data == NULL);
		pc_view_free(&v);
	}
	/* a packed 12-bit view is written as 16-bit with the same values */
	uint16_t vals[2][4] = {{1, 4095, 17, 300}, {2048, 0, 5, 4000}};
	pc_view packed, back;
	CHECK_EQ_INT(pc_view_alloc(&packed, PC_FMT_MONO12P, 4, 2, 1), 0);
	CHECK_EQ_INT(pc_view_from_u16(&vals[0][0], sizeof vals[0], &packed), 0);
	CHECK_EQ_INT(pc_tiff_write(tmp("p.tif"), &packed), 0);
	CHECK_EQ_INT(pc_image_read(tmp("p.tif"), NULL, &back, NULL), 0);
	CHECK(back.format == PC_FMT_MONO16);
	CHECK_EQ_INT(PC_ROW(&back, uint16_t, 1)[3], 4000);
	CHECK_EQ_INT(PC_ROW(&back, uint16_t, 0)[1], 4095);
	pc_view_free(&back);
	pc_view_free(&packed);

	/* multi-channel float array */
	float arr[3][5][4];
	for (int y = 0; y < 3; y++)
		for (int x = 0; x < 5; x++)
			for (int c = 0; c < 4; c++)
				arr[y][x][c] = (float)(y * 100 + x * 10 + c) + 0.25f;
	CHECK_EQ_INT(pc_tiff_write_array(tmp("m.tif"), arr, PC_DT_F32, 3, 5, 4), 0);
	pc_array a;
	CHECK_EQ_INT(pc_tiff_read_array(tmp("m.tif"), &a), 0);
	CHECK_EQ_INT(a.ndim, 3);
	CHECK(a.shape[0] == 3 && a.shape[1] == 5 && a.shape[2] == 4 && a.dtype == PC_DT_F32);
	CHECK(memcmp(a.data, arr, sizeof arr) == 0);
	pc_array_free(&a);
	/* a 4-channel TIFF is not a single-channel raw */
	CHECK_EQ_INT(pc_image_read(tmp("m.tif"), NULL, &back, NULL), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "4 samples per pixel") != NULL);

	/* signed 16-bit samples: unsupported, said clearly */
	TIFF *t = TIFFOpen(tmp("s.tif"), "w");
	CHECK(t != NULL);
	int16_t srow[4] = {-1, 2, 3, 4};
	TIFFSetField(t, TIFFTAG_IMAGEWIDTH, 4u);
	TIFFSetField(t, TIFFTAG_IMAGELENGTH, 1u);
	TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
	TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 16);
	TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_INT);
	TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
	TIFFWriteScanline(t, srow, 0, 0);
	TIFFClose(t);
	CHECK_EQ_INT(pc_image_read(tmp("s.tif"), NULL, &back, NULL), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "signed") != NULL);
	/* float TIFF with NaN */
	float fnan[2][2] = {{1, 2}, {NAN, 4}};
	CHECK_EQ_INT(pc_tiff_write_array(tmp("n.tif"), fnan, PC_DT_F32, 2, 2, 1), 0);
	CHECK_EQ_INT(pc_image_read(tmp("n.tif"), NULL, &back, NULL), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "n.tif") && strstr(pc_error_detail(), "(0,1) is NaN"));
	/* not a TIFF at all */
	CHECK_EQ_INT(pc_write_file_atomic(tmp("x.tif"), "hello", 5), 0);
	CHECK_EQ_INT(pc_image_read(tmp("x.tif"), NULL, &back, NULL), PC_EFORMAT);
	CHECK_EQ_INT(pc_image_read(tmp("missing.tif"), NULL, &back, NULL), PC_ENOENT);
	/* a writer that fails leaves nothing behind */
	int before = count_files();
	CHECK(pc_tiff_write_array(tmp("nodir/m.tif"), arr, PC_DT_F32, 3, 5, 4) != 0);
	CHECK_EQ_INT(count_files(), before);
}

static void test_npy(void)
{
	float arr[3][2][4];
	for (int i = 0; i < 24; i++)
		(&arr[0][0][0])[i] = (float)i * 0.5f - 3.0f;
	size_t shape[3] = {3, 2, 4};
	CHECK_EQ_INT(pc_npy_write(tmp("a.npy"), arr, PC_DT_F32, 3, shape), 0);
	pc_array a;
	CHECK_EQ_INT(pc_npy_read(tmp("a.npy"), &a), 0);
	CHECK(a.ndim == 3 && a.shape[0] == 3 && a.shape[1] == 2 && a.shape[2] == 4);
	CHECK(memcmp(a.data, arr, sizeof arr) == 0);
	pc_array_free(&a);
	/* header layout per the NumPy format spec: data starts at a multiple of 64 */
	FILE *fp = fopen(tmp("a.npy"), "rb");
	unsigned char pre[10];
	CHECK_EQ_INT(fread(pre, 1, 10, fp), 10);
	fclose(fp);
	CHECK_EQ_INT((10 + (pre[8] | pre[9] << 8)) % 64, 0);

	uint16_t img[2][3] = {{1, 2, 3}, {4000, 5, 6}};
	size_t s2[2] = {2, 3};
	CHECK_EQ_INT(pc_npy_write(tmp("u.npy"), img, PC_DT_U16, 2, s2), 0);
	pc_view v;
	unsigned bits;
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("u.npy"), NULL, 12, &v, &bits), 0);
	CHECK(v.format == PC_FMT_MONO12 && bits == 12);
	CHECK_EQ_INT(PC_ROW(&v, uint16_t, 1)[0], 4000);
	pc_view_free(&v);
	img[1][2] = 4096; /* 12-bit data above 4095 */
	CHECK_EQ_INT(pc_npy_write(tmp("u.npy"), img, PC_DT_U16, 2, s2), 0);
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("u.npy"), NULL, 12, &v, &bits), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "u.npy") && strstr(pc_error_detail(), "(2,1) = 4096"));
	CHECK(v.data == NULL);
	/* NaN in float input */
	float fimg[2][2] = {{1, INFINITY}, {3, 4}};
	CHECK_EQ_INT(pc_npy_write(tmp("f.npy"), fimg, PC_DT_F32, 2, (size_t[]){2, 2}), 0);
	CHECK_EQ_INT(pc_image_read(tmp("f.npy"), NULL, &v, NULL), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "f.npy") && strstr(pc_error_detail(), "infinite"));
	/* truncated data */
	CHECK_EQ_INT(pc_npy_write(tmp("a.npy"), arr, PC_DT_F32, 3, shape), 0);
	truncate_file(tmp("a.npy"), 128 + 20);
	CHECK_EQ_INT(pc_npy_read(tmp("a.npy"), &a), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "truncated") != NULL);
	/* a 3-D array is not a raw mosaic */
	CHECK_EQ_INT(pc_npy_write(tmp("a.npy"), arr, PC_DT_F32, 3, shape), 0);
	CHECK_EQ_INT(pc_image_read(tmp("a.npy"), NULL, &v, NULL), PC_EFORMAT);
}

static void test_png(void)
{
	pc_view v, back;
	CHECK_EQ_INT(pc_view_alloc(&v, PC_FMT_MONO12, 9, 5, 0), 0);
	for (uint32_t y = 0; y < 5; y++)
		for (uint32_t x = 0; x < 9; x++)
			PC_ROW(&v, uint16_t, y)[x] = (uint16_t)(next() & 4095);
	CHECK_EQ_INT(pc_png_write(tmp("r.png"), &v), 0);
	unsigned bits;
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("r.png"), NULL, 0, &back, &bits), 0);
	CHECK_EQ_INT(bits, 12); /* from sBIT */
	CHECK(back.format == PC_FMT_MONO12);
	CHECK(views_equal(&v, &back));
	pc_view_free(&back);
	/* wrong bit depth: a 12-bit file is not 8-bit data, nor is 8-bit data 12-bit */
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("r.png"), NULL, 8, &back, &bits), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "wrong bit depth") != NULL);
	pc_view v8;
	CHECK_EQ_INT(pc_view_alloc(&v8, PC_FMT_MONO8, 4, 2, 0), 0);
	memset(v8.data, 7, v8.stride * 2);
	CHECK_EQ_INT(pc_png_write(tmp("e.png"), &v8), 0);
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("e.png"), NULL, 12, &back, &bits), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "e.png") != NULL);
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("e.png"), NULL, 0, &back, &bits), 0);
	CHECK(bits == 8 && back.format == PC_FMT_MONO8);
	pc_view_free(&back);
	pc_view_free(&v8);
	/* truncated PNG */
	truncate_file(tmp("r.png"), 60);
	CHECK_EQ_INT(pc_image_read(tmp("r.png"), NULL, &back, NULL), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "r.png") != NULL);
	pc_view_free(&v);
	CHECK_EQ_INT(pc_image_read(tmp("r.gif"), NULL, &back, NULL), PC_EFORMAT);
}

static void put32(uint8_t *p, uint32_t v)
{
	for (int i = 0; i < 4; i++)
		p[i] = (uint8_t)(v >> (8 * i));
}

static void test_bmp(void)
{
	/* a 5x3 8-bit grey BMP written by hand: bottom-up rows padded to 8 bytes */
	uint8_t f[14 + 40 + 1024 + 3 * 8];
	memset(f, 0, sizeof f);
	f[0] = 'B';
	f[1] = 'M';
	put32(f + 2, sizeof f);
	put32(f + 10, 14 + 40 + 1024);
	put32(f + 14, 40);
	put32(f + 18, 5);
	put32(f + 22, 3);
	f[26] = 1;
	f[28] = 8;
	for (int i = 0; i < 256; i++)
		f[54 + 4 * i] = f[55 + 4 * i] = f[56 + 4 * i] = (uint8_t)i;
	for (int r = 0; r < 3; r++) /* file row r is image row 2 - r */
		for (int x = 0; x < 5; x++)
			f[14 + 40 + 1024 + 8 * r + x] = (uint8_t)(10 * (2 - r) + x);
	CHECK_EQ_INT(pc_write_file_atomic(tmp("g.bmp"), f, sizeof f), 0);
	pc_view v;
	CHECK_EQ_INT(pc_image_read(tmp("g.bmp"), NULL, &v, NULL), 0);
	CHECK(v.width == 5 && v.height == 3 && v.format == PC_FMT_MONO8);
	CHECK_EQ_INT(PC_ROW(&v, uint8_t, 0)[4], 4);
	CHECK_EQ_INT(PC_ROW(&v, uint8_t, 2)[1], 21);
	pc_view_free(&v);
	CHECK_EQ_INT(pc_write_file_atomic(tmp("t.bmp"), f, sizeof f - 5), 0);
	CHECK_EQ_INT(pc_image_read(tmp("t.bmp"), NULL, &v, NULL), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "truncated") != NULL);
	f[54 + 4 * 9] = 0xff; /* a colour palette entry */
	CHECK_EQ_INT(pc_write_file_atomic(tmp("c.bmp"), f, sizeof f), 0);
	CHECK_EQ_INT(pc_image_read(tmp("c.bmp"), NULL, &v, NULL), PC_EFORMAT);
}

static void test_raw(void)
{
	const pc_pixfmt fmts[] = {PC_FMT_MONO8,        PC_FMT_MONO10,  PC_FMT_MONO12,
	                          PC_FMT_MONO14,       PC_FMT_MONO16,  PC_FMT_MONO10P,
	                          PC_FMT_MONO12P,      PC_FMT_MONO14P, PC_FMT_MONO12PACKED,
	                          PC_FMT_MONO10PACKED, PC_FMT_Y10P,    PC_FMT_Y12P,
	                          PC_FMT_Y14P,         PC_FMT_Y10BPACK};
	enum { W = 8, H = 4 };
	for (size_t i = 0; i < sizeof fmts / sizeof fmts[0]; i++) {
		const pc_format_info *fi = pc_format_info_get(fmts[i]);
		uint16_t src[H][W], back[H][W];
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				src[y][x] = (uint16_t)(next() & ((1u << fi->bits) - 1));
		pc_view v;
		CHECK_EQ_INT(pc_view_alloc(&v, fmts[i], W, H, 16), 0);
		CHECK_EQ_INT(pc_view_from_u16(&src[0][0], sizeof src[0], &v), 0);
		/* a file with a 7-byte header and the rows at v's (padded) stride */
		size_t bytes = 7 + v.stride * H;
		uint8_t *file = calloc(1, bytes);
		memcpy(file + 7, v.data, v.stride * H);
		CHECK_EQ_INT(pc_write_file_atomic(tmp("r.raw"), file, bytes), 0);
		pc_raw_geometry g = {W, H, fmts[i], 7, v.stride};
		pc_view r;
		unsigned sb;
		CHECK_EQ_INT(pc_image_read(tmp("r.raw"), &g, &r, &sb), 0);
		CHECK_EQ_INT(sb, fi->bits);
		CHECK(r.format == fmts[i]);
		CHECK_EQ_INT(pc_view_to_u16(&r, &back[0][0], sizeof back[0]), 0);
		CHECK(memcmp(src, back, sizeof src) == 0);
		pc_view_free(&r);
		/* truncated by one byte: an error naming the file and the row */
		CHECK_EQ_INT(pc_write_file_atomic(tmp("r.raw"), file, bytes - v.stride + 1), 0);
		CHECK_EQ_INT(pc_image_read(tmp("r.raw"), &g, &r, &sb), PC_EFORMAT);
		CHECK(strstr(pc_error_detail(), "r.raw") && strstr(pc_error_detail(), "truncated"));
		free(file);
		pc_view_free(&v);
	}
	pc_raw_geometry zero = {0, 4, PC_FMT_MONO16, 0, 0};
	pc_view r;
	CHECK_EQ_INT(pc_image_read(tmp("r.raw"), &zero, &r, NULL), PC_EINVAL);
	pc_raw_geometry odd = {6, 4, PC_FMT_MONO10P, 0, 0}; /* not a multiple of 4 pixels */
	CHECK_EQ_INT(pc_image_read(tmp("r.raw"), &odd, &r, NULL), PC_EINVAL);
}

/* The picture writer: the four PNGs, with and without the low-signal mask; a non-finite mask
 * threshold or missing planes are refused. */
static void test_pictures(void)
{
	enum { W = 24, H = 16 };
	float s0[W * H], dl[W * H], al[W * H];
	for (int i = 0; i < W * H; i++) {
		s0[i] = (float)(i % W) * 10.0f; /* dark on the left */
		dl[i] = 0.5f;
		al[i] = 1.0f;
	}
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.s0 = (pc_fplane){s0, W, 1};
	so.dolp = (pc_fplane){dl, W, 1};
	so.aolp = (pc_fplane){al, W, 1};
	CHECK_EQ_INT(pc_pictures_write(dir, &so, W, H, "truth"), 0);
	const char *names[4] = {"s0.png", "dolp.png", "aolp.png", "aolp_sat.png"};
	for (int k = 0; k < 4; k++)
		CHECK(access(tmp(names[k]), F_OK) == 0);
	pc_pictures_opts o = {.title_prefix = "m", .mask_s0 = 45.0};
	CHECK_EQ_INT(pc_pictures_write_opts(dir, &so, W, H, &o), 0);
	o.mask_s0 = -1;
	CHECK_EQ_INT(pc_pictures_write_opts(dir, &so, W, H, &o), 0);
	CHECK_EQ_INT(pc_pictures_write_opts(dir, &so, W, H, NULL), 0);
	o.mask_s0 = NAN;
	int before = count_files();
	CHECK_EQ_INT(pc_pictures_write_opts(dir, &so, W, H, &o), PC_EINVAL);
	so.dolp.data = NULL;
	CHECK_EQ_INT(pc_pictures_write_opts(dir, &so, W, H, NULL), PC_EINVAL);
	CHECK_EQ_INT(count_files(), before);
	for (int k = 0; k < 4; k++)
		unlink(tmp(names[k]));
}

int main(void)
{
	if (!pc_test_tmpdir(dir, sizeof dir, "pc_test_io"))
		SKIP("cannot create a temporary directory");
	test_tiff();
	test_npy();
	test_png();
	test_bmp();
	test_raw();
	test_pictures();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_io");
}
