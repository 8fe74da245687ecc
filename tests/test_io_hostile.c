/* Hostile files against the readers (issue 13): every one fails with an error naming the file,
 * before anything of the header's size is allocated, and no reader touches memory it does not
 * own (the ASan build runs this too). Covered: a float64 .npy value beyond float32 (the message
 * used to read the freed array), .npy headers declaring (10^7, 10^7) or shapes that overflow,
 * headerless raw geometry beyond the file (a stride of 2^64 − 1), PNG headers beyond the pixel
 * limit and a decompression bomb within it, TIFF palette images (with and without the
 * photometric tag), tiled YCbCr with 2×2 subsampling through pc_tiff_read_array (it read past the
 * tile buffer), TIFF strips beyond the end of the file, BMP headers claiming 2^20 × 2^20, float
 * raws at ±3.4e38, the limits' environment variables, and atomic writes of a legal 254-byte
 * name (the temporary name used to exceed NAME_MAX). */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "check.h"
#include "hostile.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/io.h"
#include "polarcam/limits.h"

static char dir[64];

static const char *tmp(const char *name)
{
	static char buf[8][400];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

static int count_entries(void)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)))
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
			n++;
	closedir(d);
	return n;
}

/* The read fails with `code`, its detail names the file and holds `what`. */
static void expect_fail(const char *path, const pc_raw_geometry *g, int code, const char *what)
{
	pc_view v;
	int rc = pc_image_read(path, g, &v, NULL);
	const char *d = pc_error_detail();
	const char *base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
	bool ok = rc == code && strstr(d, base) && (!what || strstr(d, what));
	CHECK(ok);
	if (!ok)
		fprintf(stderr, "  %s: rc %d (want %d): %s\n", base, rc, code, d);
	if (!rc)
		pc_view_free(&v);
}

static void test_npy(void)
{
	/* float64 beyond float32 in a small and a 600×600 file: an error naming the pixel and its
	 * value (read before the array is freed) */
	for (int big = 0; big < 2; big++) {
		size_t n = big ? 600 * 600 : 16;
		double *d = malloc(n * sizeof *d);
		for (size_t i = 0; i < n; i++)
			d[i] = 1;
		d[n / 2 + 3] = 1e39;
		char dict[96];
		snprintf(dict, sizeof dict,
		         "{'descr': '<f8', 'fortran_order': False, 'shape': (%d, %d), }",
		         big ? 600 : 4, big ? 600 : 4);
		CHECK_EQ_INT(hostile_npy(tmp("f64.npy"), dict, d, n * sizeof *d), 0);
		expect_fail(tmp("f64.npy"), NULL, PC_ERANGE, "1e+39");
		free(d);
	}
	/* (10^7, 10^7) u2 with no data: refused as truncated (input error), nothing allocated: the
	 * address-space limit below makes a 200 TB malloc attempt fail loudly */
	CHECK_EQ_INT(
	    hostile_npy(tmp("huge.npy"),
	                "{'descr': '<u2', 'fortran_order': False, 'shape': (10000000, 10000000), }",
	                NULL, 0),
	    0);
	expect_fail(tmp("huge.npy"), NULL, PC_EFORMAT, "truncated");
	/* shapes whose byte count overflows 64 bits, negative and malformed dimensions */
	static const char *const bad[] = {
	    "{'descr': '<f8', 'fortran_order': False, 'shape': (4294967296, 4294967296), }",
	    "{'descr': '<f8', 'fortran_order': False, 'shape': (99999999999999999999, 2), }",
	    "{'descr': '<u2', 'fortran_order': False, 'shape': (-1, 4), }",
	    "{'descr': '<u2', 'fortran_order': False, 'shape': (4, 4 }",
	    "{'descr': '<u2', 'fortran_order': False, 'shape': (4; 4), }",
	};
	for (int i = 0; i < 5; i++) {
		uint16_t px[16] = {0};
		CHECK_EQ_INT(hostile_npy(tmp("shape.npy"), bad[i], px, sizeof px), 0);
		expect_fail(tmp("shape.npy"), NULL, PC_EFORMAT, NULL);
	}
	/* within the file but beyond the pixel limit: PC_ERANGE naming the variable */
	{
		uint8_t *px = calloc(1, 10000);
		CHECK_EQ_INT(
		    hostile_npy(tmp("lim.npy"),
		                "{'descr': '|u1', 'fortran_order': False, 'shape': (100, 100), }",
		                px, 10000),
		    0);
		free(px);
		setenv("POLARCAM_MAX_PIXELS", "9999", 1);
		expect_fail(tmp("lim.npy"), NULL, PC_ERANGE, "POLARCAM_MAX_PIXELS");
		setenv("POLARCAM_MAX_PIXELS", "10k", 1);
		pc_view v;
		CHECK_EQ_INT(pc_image_read(tmp("lim.npy"), NULL, &v, NULL), 0);
		pc_view_free(&v);
		setenv("POLARCAM_MAX_PIXELS", "lots", 1);
		expect_fail(tmp("lim.npy"), NULL, PC_EINVAL, "POLARCAM_MAX_PIXELS='lots'");
		unsetenv("POLARCAM_MAX_PIXELS");
		setenv("POLARCAM_MAX_BYTES", "9Ki", 1);
		expect_fail(tmp("lim.npy"), NULL, PC_ERANGE, "POLARCAM_MAX_BYTES");
		unsetenv("POLARCAM_MAX_BYTES");
	}
}

static void test_raw(void)
{
	uint8_t b[100];
	for (int i = 0; i < 100; i++)
		b[i] = (uint8_t)i;
	CHECK_EQ_INT(hostile_write(tmp("r.bin"), b, sizeof b), 0);
	/* a stride of 2^64 − 1 used to wrap the seek and read garbage */
	pc_raw_geometry g = {4, 4, PC_FMT_MONO8, 10, SIZE_MAX};
	expect_fail(tmp("r.bin"), &g, PC_EFORMAT, "beyond any file");
	pc_raw_geometry g2 = {4, 4, PC_FMT_MONO8, SIZE_MAX - 2, 0};
	expect_fail(tmp("r.bin"), &g2, PC_EFORMAT, NULL);
	pc_raw_geometry g3 = {4, 4, PC_FMT_MONO8, 90, 0}; /* needs 106 bytes */
	expect_fail(tmp("r.bin"), &g3, PC_EFORMAT, "106");
	pc_raw_geometry g4 = {4, 4, PC_FMT_MONO8, 84, 0}; /* exactly fits */
	pc_view v;
	CHECK_EQ_INT(pc_image_read(tmp("r.bin"), &g4, &v, NULL), 0);
	CHECK_EQ_INT(PC_ROW(&v, uint8_t, 3)[3], 99);
	pc_view_free(&v);
	pc_raw_geometry g5 = {4, 3, PC_FMT_MONO8, 0, 40}; /* rows 40 bytes apart: 84 bytes */
	CHECK_EQ_INT(pc_image_read(tmp("r.bin"), &g5, &v, NULL), 0);
	CHECK_EQ_INT(PC_ROW(&v, uint8_t, 2)[1], 81);
	pc_view_free(&v);
	/* a Mono12 raw (LSB-aligned in 16 bits) holding 55245: the container holds it, the
	 * format's 12 bits do not (found by fuzz_raw: pc_view_check_bits took 12 for the capacity)
	 */
	uint16_t m12[16];
	for (int i = 0; i < 16; i++)
		m12[i] = (uint16_t)(i * 200);
	m12[13] = 55245;
	CHECK_EQ_INT(hostile_write(tmp("m12.bin"), m12, sizeof m12), 0);
	pc_raw_geometry gm = {4, 4, PC_FMT_MONO12, 0, 0};
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("m12.bin"), &gm, 0, &v, NULL), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "m12.bin") && strstr(pc_error_detail(), "55245"));
	/* a headerless geometry of 2^30 × 2^30 within nothing: refused before allocating */
	pc_raw_geometry g6 = {1u << 30, 1u << 30, PC_FMT_MONO8, 0, 0};
	expect_fail(tmp("r.bin"), &g6, PC_EFORMAT, "truncated");
}

static void test_png(void)
{
	/* headers claiming 100000 × 100000 and (the bomb) 20000 × 20000 in a few bytes:
	 * the default limit refuses both before decoding */
	CHECK_EQ_INT(hostile_png(tmp("claim.png"), 100000, 100000, 16, 0), 0);
	expect_fail(tmp("claim.png"), NULL, PC_ERANGE, "POLARCAM_MAX_PIXELS");
	CHECK_EQ_INT(hostile_png(tmp("claim2.png"), 20000, 20000, 8, 0), 0);
	expect_fail(tmp("claim2.png"), NULL, PC_ERANGE, "400000000 pixels");
	/* within the limit but too short for its rows even at deflate's best ratio */
	CHECK_EQ_INT(hostile_png(tmp("short.png"), 9000, 9000, 16, 0), 0);
	expect_fail(tmp("short.png"), NULL, PC_EFORMAT, "truncated");
	/* a real decompression bomb (2000 × 2000 zeros, ~4 kB): refused under a lowered limit,
	 * decoded exactly under the default */
	CHECK_EQ_INT(hostile_png(tmp("bomb.png"), 2000, 2000, 8, 2000), 0);
	setenv("POLARCAM_MAX_PIXELS", "1M", 1);
	expect_fail(tmp("bomb.png"), NULL, PC_ERANGE, "4000000 pixels");
	unsetenv("POLARCAM_MAX_PIXELS");
	pc_view v;
	CHECK_EQ_INT(pc_image_read(tmp("bomb.png"), NULL, &v, NULL), 0);
	CHECK(v.width == 2000 && v.height == 2000);
	pc_view_free(&v);
}

static void test_tiff(void)
{
	/* palette images are colours, not grey values: with the photometric tag and without it
	 * (libtiff then guesses min-is-black; the colour map gives it away) */
	CHECK_EQ_INT(hostile_tiff(tmp("pal.tif"), HOSTILE_TIFF_PALETTE, 4, 4), 0);
	expect_fail(tmp("pal.tif"), NULL, PC_EFORMAT, "palette");
	CHECK_EQ_INT(hostile_tiff(tmp("pal2.tif"), HOSTILE_TIFF_PALETTE_NOPHOTO, 4, 4), 0);
	expect_fail(tmp("pal2.tif"), NULL, PC_EFORMAT, "palette");
	/* tiled YCbCr with 2×2 subsampling: 384-byte tiles where 768 would be copied */
	CHECK_EQ_INT(hostile_tiff(tmp("ycc.tif"), HOSTILE_TIFF_YCBCR_TILED, 16, 16), 0);
	pc_array a;
	CHECK_EQ_INT(pc_tiff_read_array(tmp("ycc.tif"), &a), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "ycc.tif") && strstr(pc_error_detail(), "YCbCr"));
	expect_fail(tmp("ycc.tif"), NULL, PC_EFORMAT, NULL);
	/* dimensions patched to 100000 × 100000: the limit */
	CHECK_EQ_INT(hostile_tiff(tmp("big.tif"), HOSTILE_TIFF_GREY8, 8, 8), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("big.tif"), TIFFTAG_IMAGEWIDTH, 100000), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("big.tif"), TIFFTAG_IMAGELENGTH, 100000), 0);
	expect_fail(tmp("big.tif"), NULL, PC_ERANGE, "POLARCAM_MAX_PIXELS");
	/* within the limit, but its one strip holds 64 bytes for 9000 × 9000 pixels */
	CHECK_EQ_INT(hostile_tiff(tmp("short.tif"), HOSTILE_TIFF_GREY8, 8, 8), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("short.tif"), TIFFTAG_IMAGEWIDTH, 9000), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("short.tif"), TIFFTAG_IMAGELENGTH, 9000), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("short.tif"), TIFFTAG_ROWSPERSTRIP, 9000), 0);
	expect_fail(tmp("short.tif"), NULL, PC_EFORMAT, NULL);
	/* a strip whose offset lies beyond the end of the file */
	CHECK_EQ_INT(hostile_tiff(tmp("off.tif"), HOSTILE_TIFF_GREY8, 8, 8), 0);
	CHECK_EQ_INT(hostile_tiff_set(tmp("off.tif"), TIFFTAG_STRIPOFFSETS, 1u << 30), 0);
	expect_fail(tmp("off.tif"), NULL, PC_EFORMAT, NULL);
	CHECK_EQ_INT(hostile_tiff(tmp("s16.tif"), HOSTILE_TIFF_SIGNED16, 4, 4), 0);
	expect_fail(tmp("s16.tif"), NULL, PC_EFORMAT, "signed");
	/* the valid one still reads */
	CHECK_EQ_INT(hostile_tiff(tmp("ok.tif"), HOSTILE_TIFF_GREY8, 8, 6), 0);
	pc_view v;
	CHECK_EQ_INT(pc_image_read(tmp("ok.tif"), NULL, &v, NULL), 0);
	CHECK(v.width == 8 && v.height == 6 && PC_ROW(&v, uint8_t, 5)[7] == 12);
	pc_view_free(&v);
}

static void test_bmp(void)
{
	CHECK_EQ_INT(hostile_bmp(tmp("huge.bmp"), 1 << 20, 1 << 20, 16), 0);
	expect_fail(tmp("huge.bmp"), NULL, PC_ERANGE, "POLARCAM_MAX_PIXELS");
	CHECK_EQ_INT(hostile_bmp(tmp("short.bmp"), 5000, -5000, 16), 0);
	expect_fail(tmp("short.bmp"), NULL, PC_EFORMAT, "truncated");
	CHECK_EQ_INT(hostile_bmp(tmp("ok.bmp"), 4, 2, 8), 0);
	pc_view v;
	CHECK_EQ_INT(pc_image_read(tmp("ok.bmp"), NULL, &v, NULL), 0);
	pc_view_free(&v);
}

static void test_float_raw(void)
{
	/* ±3.4e38 is finite but leaves float32 no room: refused naming the pixel */
	float f[16];
	for (int i = 0; i < 16; i++)
		f[i] = (i & 1) ? 3.4e38f : 1.0f;
	CHECK_EQ_INT(hostile_npy(tmp("fmax.npy"),
	                         "{'descr': '<f4', 'fortran_order': False, "
	                         "'shape': (4, 4), }",
	                         f, sizeof f),
	             0);
	pc_view v;
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("fmax.npy"), NULL, 0, &v, NULL), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "(1,0)") && strstr(pc_error_detail(), "fmax.npy"));
	f[1] = -0x1p24f; /* the bound itself is accepted */
	for (int i = 3; i < 16; i += 2)
		f[i] = 0x1p24f;
	CHECK_EQ_INT(hostile_npy(tmp("fok.npy"),
	                         "{'descr': '<f4', 'fortran_order': False, "
	                         "'shape': (4, 4), }",
	                         f, sizeof f),
	             0);
	CHECK_EQ_INT(pc_image_read_mosaic(tmp("fok.npy"), NULL, 0, &v, NULL), 0);
	pc_view_free(&v);
}

static void test_atomic_long_name(void)
{
	/* a legal name of NAME_MAX − 1 bytes: the temporary sibling must fit too */
	char name[NAME_MAX + 2];
	for (int len = NAME_MAX - 12; len <= NAME_MAX; len++) {
		memset(name, 'a', (size_t)len);
		name[len] = '\0';
		const char *p = tmp(name);
		int before = count_entries();
		CHECK_EQ_INT(pc_write_file_atomic(p, "x", 1), 0);
		CHECK(access(p, F_OK) == 0);
		CHECK_EQ_INT(count_entries(), before + 1); /* no temporary left behind */
		unlink(p);
	}
	/* a multi-byte UTF-8 name is cut at a character boundary (the file itself is fine) */
	char u[NAME_MAX + 1];
	size_t o = 0;
	while (o + 2 <= NAME_MAX - 1) {
		u[o++] = (char)0xc3;
		u[o++] = (char)0xa9;
	}
	u[o] = '\0';
	CHECK_EQ_INT(pc_write_file_atomic(tmp(u), "y", 1), 0);
	unlink(tmp(u));
	/* over NAME_MAX: the file system's own error, naming the path */
	memset(name, 'b', NAME_MAX + 1);
	name[NAME_MAX + 1] = '\0';
	CHECK(pc_write_file_atomic(tmp(name), "x", 1) != 0);
}

static void test_limits_api(void)
{
	uint64_t v = 0;
	CHECK_EQ_INT(pc_limit_parse("400M", &v), 0);
	CHECK(v == 400000000ull);
	CHECK_EQ_INT(pc_limit_parse("4Gi", &v), 0);
	CHECK(v == 4ull << 30);
	CHECK_EQ_INT(pc_limit_parse("0", &v), PC_EINVAL);
	CHECK_EQ_INT(pc_limit_parse("-5", &v), PC_EINVAL);
	CHECK_EQ_INT(pc_limit_parse("5x", &v), PC_EINVAL);
	CHECK_EQ_INT(pc_limit_parse("99999999999T", &v), PC_EINVAL);
	CHECK(pc_limit_get(PC_LIMIT_PIXELS) == PC_LIMIT_PIXELS_DEFAULT);
	CHECK_EQ_INT(pc_limit_set(PC_LIMIT_PIXELS, 5), 0);
	CHECK_EQ_INT(pc_limit_check(PC_LIMIT_PIXELS, 6, "x"), PC_ERANGE);
	CHECK_EQ_INT(pc_limit_check(PC_LIMIT_PIXELS, 5, "x"), 0);
	CHECK_EQ_INT(pc_limit_set(PC_LIMIT_PIXELS, 0), 0);
	CHECK(pc_limit_get(PC_LIMIT_PIXELS) == PC_LIMIT_PIXELS_DEFAULT);
	CHECK_EQ_INT(pc_limit_set(PC_LIMIT_COUNT, 1), PC_EINVAL);
}

int main(void)
{
	/* an address-space limit of 8 GiB: an allocation from a hostile header would fail here
	 * (and be reported as PC_ENOMEM, not the input error the checks expect) instead of being
	 * attempted; ASan reserves its shadow memory beyond any such limit, so only without it */
#if !defined(__SANITIZE_ADDRESS__)
	struct rlimit rl = {8ull << 30, 8ull << 30};
	setrlimit(RLIMIT_AS, &rl);
#endif
	snprintf(dir, sizeof dir, "/tmp/pc_io_hostile_XXXXXX");
	if (!mkdtemp(dir))
		SKIP("cannot create a temporary directory: %s", strerror(errno));
	test_npy();
	test_raw();
	test_png();
	test_tiff();
	test_bmp();
	test_float_raw();
	test_atomic_long_name();
	test_limits_api();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_io_hostile");
}
