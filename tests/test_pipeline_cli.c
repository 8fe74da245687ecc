/* The pipeline's commands as users run them ($POLARCAM): demosaic, process and eval outputs
 * against the library, --list and --help, and bad input: exit status 2, a message naming the
 * file, and no output left behind. Synthetic files in a temporary directory. */
#include <cairo.h>
#include <dirent.h>
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/folders.h"
#include "polarcam/io.h"
#include "polarcam/picture.h"
#include "polarcam/stokes.h"

static char dir[64];
static const char *exe;

static const char *tmp(const char *name)
{
	static char buf[8][200];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

/* Runs "$POLARCAM args" with stdout to out.txt and stderr to err.txt; returns the exit status. */
static int run(const char *args)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd, "%s %s >%s 2>%s", exe, args, tmp("out.txt"), tmp("err.txt"));
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int file_contains(const char *path, const char *what)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return 0;
	static char buf[1 << 16]; /* demosaic --list is over 10 kB */
	size_t n = fread(buf, 1, sizeof buf - 1, fp);
	fclose(fp);
	buf[n] = '\0';
	return strstr(buf, what) != NULL;
}

static int exists(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0;
}

/* a 12-bit mosaic of a polarized scene */
static void make_raw(pc_view *v, uint32_t w, uint32_t h)
{
	pc_view_alloc(v, PC_FMT_MONO12, w, h, 0);
	pc_mosaic m = pc_mosaic_imx250mzr();
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			unsigned c = pc_mosaic_channel(&m, x, y);
			double s0 = 2000 + 1000 * sin(0.2 * x) * cos(0.15 * y);
			double a = 0.3 + 0.01 * x;
			PC_ROW(v, uint16_t, y)
			[x] = (uint16_t)lround(s0 / 2 * (1 + 0.4 * cos(2 * (a - c * M_PI / 4))));
		}
}

static void test_demosaic_cmd(void)
{
	CHECK_EQ_INT(run("demosaic --help"), 0);
	CHECK(file_contains(tmp("out.txt"), "usage: polarcam demosaic"));
	CHECK_EQ_INT(run("demosaic --list"), 0);
	for (int k = 0; k < PC_DM_COUNT; k++)
		CHECK(file_contains(tmp("out.txt"),
		                    pc_demosaic_method_get((pc_demosaic_method)k)->name));
	CHECK_EQ_INT(run("demosaic --list --json"), 0);

	pc_view raw;
	make_raw(&raw, 32, 24);
	CHECK_EQ_INT(pc_png_write(tmp("raw.png"), &raw), 0);
	char args[512];
	snprintf(args, sizeof args, "demosaic %s --method eari -o %s", tmp("raw.png"),
	         tmp("d.npy"));
	CHECK_EQ_INT(run(args), 0);
	pc_array a;
	CHECK_EQ_INT(pc_npy_read(tmp("d.npy"), &a), 0);
	CHECK(a.ndim == 3 && a.shape[0] == 24 && a.shape[1] == 32 && a.shape[2] == 4 &&
	      a.dtype == PC_DT_F32);
	float *want = malloc(sizeof(float) * 32 * 24 * 4);
	pc_fplane p[4];
	pc_fplanes_interleaved(want, 32, 4, p);
	pc_mosaic m = pc_mosaic_imx250mzr();
	CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_EARI, NULL, p), 0);
	CHECK(memcmp(want, a.data, sizeof(float) * 32 * 24 * 4) == 0);
	pc_array_free(&a);
	free(want);
	/* float TIFF output (another stem: d.npy's mask d_valid.npy would be d.tif's too, and an
	 * existing mask is refused like the output itself) */
	snprintf(args, sizeof args, "demosaic %s -o %s", tmp("raw.png"), tmp("dt.tif"));
	CHECK_EQ_INT(run(args), 0);
	CHECK_EQ_INT(pc_tiff_read_array(tmp("dt.tif"), &a), 0);
	CHECK(a.ndim == 3 && a.shape[2] == 4);
	pc_array_free(&a);
	/* a headerless raw with explicit geometry (Mono12p) */
	pc_view packed;
	CHECK_EQ_INT(pc_view_alloc(&packed, PC_FMT_MONO12P, 32, 24, 1), 0);
	CHECK_EQ_INT(pc_view_from_u16(raw.data, raw.stride, &packed), 0);
	CHECK_EQ_INT(pc_write_file_atomic(tmp("raw.bin"), packed.data, packed.stride * 24), 0);
	snprintf(args, sizeof args,
	         "demosaic %s --width 32 --height 24 --format PolarizeMono12p -o %s",
	         tmp("raw.bin"), tmp("p.npy"));
	CHECK_EQ_INT(run(args), 0);
	pc_view_free(&packed);
	pc_view_free(&raw);
}

/* Every bad input: exit 2, the file named, no output. */
static void test_bad_input(void)
{
	char args[512];
	pc_view raw;
	/* odd size */
	make_raw(&raw, 31, 24);
	CHECK_EQ_INT(pc_png_write(tmp("odd.png"), &raw), 0);
	pc_view_free(&raw);
	snprintf(args, sizeof args, "demosaic %s -o %s", tmp("odd.png"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "odd.png") && file_contains(tmp("err.txt"), "even"));
	CHECK(!exists(tmp("x.npy")));
	/* 12-bit data with a value above 4095 */
	uint16_t px[4][4] = {{1, 2, 3, 4}, {5, 6, 7, 8}, {9, 10, 4096, 12}, {1, 2, 3, 4}};
	pc_view big = {px, 4, 4, sizeof px[0], PC_FMT_MONO16};
	size_t s2[2] = {4, 4};
	CHECK_EQ_INT(pc_npy_write(tmp("big.npy"), px, PC_DT_U16, 2, s2), 0);
	(void)big;
	snprintf(args, sizeof args, "process %s --bits 12 -o %s", tmp("big.npy"), tmp("outdir"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "big.npy") && file_contains(tmp("err.txt"), "4096"));
	CHECK(!exists(tmp("outdir")));
	/* wrong bit depth: 8-bit data declared 12-bit */
	uint8_t p8[4][4] = {{0}};
	CHECK_EQ_INT(pc_npy_write(tmp("b8.npy"), p8, PC_DT_U8, 2, s2), 0);
	snprintf(args, sizeof args, "demosaic %s --bits 12 -o %s", tmp("b8.npy"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "bit depth"));
	/* NaN */
	float pf[4][4] = {{0}};
	pf[1][2] = NAN;
	CHECK_EQ_INT(pc_npy_write(tmp("nan.npy"), pf, PC_DT_F32, 2, s2), 0);
	snprintf(args, sizeof args, "demosaic %s -o %s", tmp("nan.npy"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "NaN"));
	/* truncated files */
	make_raw(&raw, 32, 24);
	CHECK_EQ_INT(pc_tiff_write(tmp("t.tif"), &raw), 0);
	pc_view_free(&raw);
	CHECK_EQ_INT(truncate(tmp("t.tif"), 300), 0);
	snprintf(args, sizeof args, "demosaic %s -o %s", tmp("t.tif"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "t.tif"));
	snprintf(args, sizeof args, "demosaic %s --width 32 --height 24 --format Mono16 -o %s",
	         tmp("t.tif"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "truncated"));
	/* layouts that are not permutations of 0/45/90/135 */
	snprintf(args, sizeof args, "demosaic %s --layout 90,45,135,45 -o %s", tmp("odd.png"),
	         tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "permutation"));
	snprintf(args, sizeof args, "demosaic %s --layout 90,45,13 -o %s", tmp("odd.png"),
	         tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	/* unknown method, unknown option, missing file, no output */
	snprintf(args, sizeof args, "demosaic %s --method magic -o %s", tmp("odd.png"),
	         tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "bilinear"));
	CHECK_EQ_INT(run("demosaic --frobnicate"), 2);
	snprintf(args, sizeof args, "demosaic %s -o %s", tmp("missing.png"), tmp("x.npy"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "missing.png"));
	snprintf(args, sizeof args, "demosaic %s", tmp("odd.png"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(!exists(tmp("x.npy")));
}

static void test_process_cmd(void)
{
	CHECK_EQ_INT(run("process --help"), 0);
	pc_view raw;
	make_raw(&raw, 40, 32);
	CHECK_EQ_INT(pc_png_write(tmp("p.png"), &raw), 0);
	char args[512];
	snprintf(args, sizeof args, "process %s -o %s --method ppid", tmp("p.png"), tmp("proc"));
	CHECK_EQ_INT(run(args), 0);
	const char *files[] = {"stokes.npy", "dolp.npy", "aolp.npy",     "s0.png",
	                       "dolp.png",   "aolp.png", "aolp_sat.png", "meta.json"};
	for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
		char name[64];
		snprintf(name, sizeof name, "proc/%s", files[k]);
		CHECK(exists(tmp(name)));
	}
	pc_array st, dl, al;
	CHECK_EQ_INT(pc_npy_read(tmp("proc/stokes.npy"), &st), 0);
	CHECK_EQ_INT(pc_npy_read(tmp("proc/dolp.npy"), &dl), 0);
	CHECK_EQ_INT(pc_npy_read(tmp("proc/aolp.npy"), &al), 0);
	CHECK(st.ndim == 3 && st.shape[0] == 32 && st.shape[1] == 40 && st.shape[2] == 3);
	CHECK(dl.ndim == 2 && al.ndim == 2);
	/* the files agree with the library's pipeline */
	float *s = malloc(sizeof(float) * 40 * 32 * 3);
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.s0 = (pc_fplane){s, 120, 3};
	so.s1 = (pc_fplane){s + 1, 120, 3};
	so.s2 = (pc_fplane){s + 2, 120, 3};
	pc_mosaic m = pc_mosaic_imx250mzr();
	CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, PC_DM_PPID, NULL, &so), 0);
	CHECK(memcmp(s, st.data, sizeof(float) * 40 * 32 * 3) == 0);
	const float *a = al.data, *d = dl.data;
	int ok = 1;
	for (int i = 0; i < 40 * 32; i++)
		ok &= a[i] >= 0 && a[i] < (float)M_PI && d[i] >= 0 && d[i] <= 1;
	CHECK(ok);
	free(s);
	pc_array_free(&st);
	pc_array_free(&dl);
	pc_array_free(&al);
	/* the low-signal mask threshold: a number >= 0, else exit 2 and nothing written */
	snprintf(args, sizeof args, "process %s -o %s --mask-s0 500", tmp("p.png"), tmp("procm"));
	CHECK_EQ_INT(run(args), 0);
	CHECK(exists(tmp("procm/dolp.png")));
	snprintf(args, sizeof args, "process %s -o %s --mask-s0 -3", tmp("p.png"), tmp("procn"));
	CHECK_EQ_INT(run(args), 2);
	snprintf(args, sizeof args, "process %s -o %s --mask-s0 nan", tmp("p.png"), tmp("procn"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(!exists(tmp("procn")));
	pc_view_free(&raw);
}

/* Pixels of a PNG picture (title, key and legend included) whose colour match() accepts; -1 when
 * the file is not a readable PNG. */
static long count_pixels(const char *path, bool (*match)(unsigned r, unsigned g, unsigned b))
{
	cairo_surface_t *s = cairo_image_surface_create_from_png(path);
	if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(s);
		return -1;
	}
	cairo_surface_flush(s);
	const unsigned char *d = cairo_image_surface_get_data(s);
	int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
	int stride = cairo_image_surface_get_stride(s);
	long n = 0;
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			uint32_t px;
			memcpy(&px, d + (size_t)y * stride + (size_t)x * 4, 4);
			n += match((px >> 16) & 255, (px >> 8) & 255, px & 255);
		}
	cairo_surface_destroy(s);
	return n;
}

/* the invalid mark's pink */
static bool is_invalid_pink(unsigned r, unsigned g, unsigned b)
{
	return r == PC_PICTURE_INVALID_R && g == PC_PICTURE_INVALID_G && b == PC_PICTURE_INVALID_B;
}

static long count_invalid_pink(const char *path)
{
	return count_pixels(path, is_invalid_pink);
}

/* process --minmax --split: Imin, Imax, diffuse, specular against a double computation from
 * the written stokes.npy; their pictures mark the saturated pixels as s0.png does; --stack
 * gives the same planes as one file at a time. */
static void test_process_minmax(void)
{
	enum { W = 40, H = 32 };
	pc_view raw;
	make_raw(&raw, W, H);
	for (uint32_t y = 4; y < 10; y++) /* a saturated patch */
		for (uint32_t x = 6; x < 14; x++)
			PC_ROW(&raw, uint16_t, y)[x] = 4095;
	CHECK_EQ_INT(pc_png_write(tmp("mm.png"), &raw), 0);
	char args[1024];
	snprintf(args, sizeof args, "process %s -o %s --minmax --split --picture-width 0",
	         tmp("mm.png"), tmp("mm"));
	CHECK_EQ_INT(run(args), 0);
	pc_array st, v, q[4];
	static const char *names[4] = {"imin", "imax", "diffuse", "specular"};
	CHECK_EQ_INT(pc_npy_read(tmp("mm/stokes.npy"), &st), 0);
	CHECK_EQ_INT(pc_npy_read(tmp("mm/valid.npy"), &v), 0);
	for (int k = 0; k < 4; k++) {
		char name[64];
		snprintf(name, sizeof name, "mm/%s.npy", names[k]);
		CHECK_EQ_INT(pc_npy_read(tmp(name), &q[k]), 0);
		CHECK(q[k].ndim == 2 && q[k].shape[0] == H && q[k].shape[1] == W);
	}
	const float *s = st.data;
	double worst = 0;
	long n_bad = 0;
	for (int i = 0; i < W * H; i++) {
		double s0 = s[3 * i], p = sqrt((double)s[3 * i + 1] * s[3 * i + 1] +
		                               (double)s[3 * i + 2] * s[3 * i + 2]);
		double want[4] = {(s0 - p) / 2, (s0 + p) / 2, s0 - p, p};
		for (int k = 0; k < 4; k++)
			worst =
			    fmax(worst, fabs(((const float *)q[k].data)[i] - want[k]) / (s0 + p));
		n_bad += !((const uint8_t *)v.data)[i];
	}
	CHECK(worst <= 1e-6);
	CHECK(n_bad > 0);
	/* the saturated pixels in every picture, as in s0.png: half of each is pink (checker) */
	long pink_s0 = count_invalid_pink(tmp("mm/s0.png"));
	CHECK(pink_s0 >= n_bad / 2);
	for (int k = 0; k < 4; k++) {
		char name[64];
		snprintf(name, sizeof name, "mm/%s.png", names[k]);
		CHECK_EQ_INT(count_invalid_pink(tmp(name)), pink_s0);
	}
	/* no level checked: nothing pink */
	snprintf(args, sizeof args, "process %s -o %s --minmax --saturation none", tmp("mm.png"),
	         tmp("mm0"));
	CHECK_EQ_INT(run(args), 0);
	CHECK_EQ_INT(count_invalid_pink(tmp("mm0/imin.png")), 0);
	CHECK(!exists(tmp("mm0/diffuse.npy")));
	/* --stack: (N, H, W) planes, frame 1 equal to the single file's */
	snprintf(args, sizeof args, "process %s %s -o %s --stack --split --no-pictures",
	         tmp("p.png"), tmp("mm.png"), tmp("mms"));
	CHECK_EQ_INT(run(args), 0);
	pc_array sd;
	CHECK_EQ_INT(pc_npy_read(tmp("mms/diffuse.npy"), &sd), 0);
	CHECK(sd.ndim == 3 && sd.shape[0] == 2 && sd.shape[1] == H && sd.shape[2] == W);
	if (sd.ndim == 3 && sd.shape[0] == 2)
		CHECK(memcmp((const float *)sd.data + W * H, q[2].data, sizeof(float) * W * H) ==
		      0);
	CHECK(!exists(tmp("mms/imin.npy")));
	CHECK(file_contains(tmp("mms/meta.json"), "\"specular.npy\""));
	pc_array_free(&sd);
	pc_array_free(&st);
	pc_array_free(&v);
	for (int k = 0; k < 4; k++)
		pc_array_free(&q[k]);
	pc_view_free(&raw);
}

/* process on a colour-polarization raw (IMX250MYR, RGGB:90,45,135,0) of one uniform state per
 * colour, worked out by hand (I(θ) = S0/2·(1 + p·cos 2(θ − φ)), docs/physics.md §1):
 * R unpolarized S0 2000; G S0 3000, DoLP 0.5 at 0°; B S0 1000, DoLP 0.2 at 90°. Every raw value
 * is an integer, so each colour's analyser images are constant and demosaicking keeps them:
 * stokes_rgb.npy holds (2000, 0, 0), (3000, 1500, 0), (1000, −200, 0); stokes.npy their mean;
 * s0_rgb.png (one scale, 3000 at the top) is (170, 255, 85) and dolp_rgb.png on 0..1 is
 * (0, 128, 51), both to within 1 of the rounding. */
static bool is_s0_rgb(unsigned r, unsigned g, unsigned b)
{
	return abs((int)r - 170) <= 1 && g >= 254 && abs((int)b - 85) <= 1;
}

static bool is_dolp_rgb(unsigned r, unsigned g, unsigned b)
{
	return r <= 1 && abs((int)g - 128) <= 1 && abs((int)b - 51) <= 1;
}

static void test_process_colour(void)
{
	enum { W = 48, H = 40 };
	pc_view raw;
	pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0);
	pc_mosaic m = pc_mosaic_imx250myr();
	static const double s0[4] = {0, 2000, 3000, 1000}, p[4] = {0, 0, 0.5, 0.2},
	                    phi[4] = {0, 0, 0, M_PI / 2}; /* by pc_cfa_color */
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			unsigned c = pc_mosaic_channel(&m, x, y), k = pc_mosaic_color(&m, x, y);
			double th = c * M_PI / 4;
			PC_ROW(&raw, uint16_t, y)
			[x] = (uint16_t)lround(s0[k] / 2 * (1 + p[k] * cos(2 * (th - phi[k]))));
		}
	CHECK_EQ_INT(pc_png_write(tmp("col.png"), &raw), 0);
	char args[1024];
	snprintf(args, sizeof args,
	         "process %s --layout RGGB:90,45,135,0 -o %s --picture-width 0 --json",
	         tmp("col.png"), tmp("col"));
	CHECK_EQ_INT(run(args), 0);
	CHECK(file_contains(tmp("out.txt"), "\"stokes_rgb.npy\"") &&
	      file_contains(tmp("out.txt"), "\"dolp_rgb.png\""));
	pc_array rgb, st;
	CHECK_EQ_INT(pc_npy_read(tmp("col/stokes_rgb.npy"), &rgb), 0);
	CHECK_EQ_INT(pc_npy_read(tmp("col/stokes.npy"), &st), 0);
	CHECK(rgb.ndim == 4 && rgb.shape[0] == H && rgb.shape[1] == W && rgb.shape[2] == 3 &&
	      rgb.shape[3] == 3);
	const double want[3][3] = {{2000, 0, 0}, {3000, 1500, 0}, {1000, -200, 0}};
	double worst = 0, worst_mean = 0;
	for (int i = 0; rgb.ndim == 4 && i < W * H; i++)
		for (int k = 0; k < 3; k++) {
			double mean = 0;
			for (int c = 0; c < 3; c++) {
				double v = ((const float *)rgb.data)[9 * i + 3 * c + k];
				worst = fmax(worst, fabs(v - want[c][k]));
				mean += v / 3;
			}
			worst_mean =
			    fmax(worst_mean, fabs(mean - ((const float *)st.data)[3 * i + k]));
		}
	printf("colour: stokes_rgb worst |error| %.3g DN, mean over colours vs stokes.npy %.3g\n",
	       worst, worst_mean);
	CHECK(worst <= 1e-3);
	CHECK(worst_mean <= 1e-3);
	/* the pictures: every image pixel the colour worked out above */
	long n_s0 = count_pixels(tmp("col/s0_rgb.png"), is_s0_rgb),
	     n_dolp = count_pixels(tmp("col/dolp_rgb.png"), is_dolp_rgb);
	printf("colour: %ld and %ld of %d pixels the expected colour\n", n_s0, n_dolp, W * H);
	CHECK(n_s0 >= W * H && n_s0 < W * H + 50);
	CHECK(n_dolp >= W * H && n_dolp < W * H + 50);
	pc_array_free(&rgb);
	pc_array_free(&st);
	/* a monochrome raw has no colour outputs */
	CHECK(!exists(tmp("mm/stokes_rgb.npy")) && !exists(tmp("mm/s0_rgb.png")));
	pc_view_free(&raw);
}

/* the low-signal hatch's two greys */
static bool is_hatch_grey(unsigned r, unsigned g, unsigned b)
{
	return r == g && g == b && (r == PC_PICTURE_MASK_RGB0 || r == PC_PICTURE_MASK_RGB1);
}

/* Pixels of a PNG picture in the low-signal hatch's two greys. */
static long count_hatch(const char *path)
{
	return count_pixels(path, is_hatch_grey);
}

/* A retardance map hatched where its Δ is above PC_MUELLER_R_MASK_DELTA: every such pixel is
 * drawn in the hatch's greys (R = π: white, so no other pixel of the map is), the .npy stays
 * unmasked; without the Δ map nothing is. */
static void test_map_hatch(void)
{
	enum { W = 48, H = 40 };
	float r[W * H], delta[W * H];
	long want = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			r[y * W + x] = (float)M_PI;
			delta[y * W + x] = x < 20 ? 0.9f : 0.1f;
			want += x < 20;
		}
	pc_map_marks mk = {NULL, delta, PC_MUELLER_R_MASK_DELTA, "Delta > 0.5: R undefined"};
	CHECK_EQ_INT(pc_map_write_marked(dir, "Rh", r, W, H, 0, M_PI, "R", "R (rad)", &mk), 0);
	long n = count_hatch(tmp("Rh.png"));
	CHECK(n >= want && n <= want + 2000); /* the map's pixels, and the legend's swatch */
	pc_array a;
	CHECK_EQ_INT(pc_npy_read(tmp("Rh.npy"), &a), 0);
	CHECK(a.ndim == 2 && memcmp(a.data, r, sizeof r) == 0);
	pc_array_free(&a);
	CHECK_EQ_INT(pc_map_write_marked(dir, "R0", r, W, H, 0, M_PI, "R", "R (rad)", NULL), 0);
	/* (a few pixels of the key's grey ramp and antialiased text share the greys) */
	CHECK(count_hatch(tmp("R0.png")) < want / 20);
}

static void test_eval_cmd(void)
{
	CHECK_EQ_INT(run("eval --help"), 0);
	/* a truth directory of four 16-bit TIFFs */
	mkdir(tmp("gt"), 0777);
	mkdir(tmp("gt/scene"), 0777);
	pc_view v[4];
	const char *names[4] = {"gt/scene/0.tif", "gt/scene/45.tif", "gt/scene/90.tif",
	                        "gt/scene/135.tif"};
	for (int c = 0; c < 4; c++) {
		pc_view_alloc(&v[c], PC_FMT_MONO16, 48, 40, 0);
		for (uint32_t y = 0; y < 40; y++)
			for (uint32_t x = 0; x < 48; x++) {
				double s0 = 30000 + 20000 * sin(0.3 * x + 0.2 * y);
				PC_ROW(&v[c], uint16_t, y)
				[x] = (uint16_t)lround(
				    s0 / 2 * (1 + 0.3 * cos(2 * (0.02 * x - c * M_PI / 4))));
			}
		CHECK_EQ_INT(pc_tiff_write(tmp(names[c]), &v[c]), 0);
	}
	char args[512];
	snprintf(args, sizeof args, "eval %s --method bilinear --json %s", tmp("gt/scene"),
	         tmp("e.json"));
	CHECK_EQ_INT(run(args), 0);
	CHECK(file_contains(tmp("out.txt"), "bilinear"));
	json_error_t je;
	json_t *root = json_load_file(tmp("e.json"), 0, &je);
	CHECK(root != NULL);
	pc_eval_truth t;
	CHECK_EQ_INT(pc_eval_truth_from_views(v, &t), 0);
	pc_eval_metrics mm;
	CHECK_EQ_INT(pc_eval_method(&t, PC_DM_BILINEAR, NULL, &mm), 0);
	json_t *sc = json_array_get(json_object_get(root, "scenes"), 0);
	CHECK_NEAR(json_real_value(json_object_get(sc, "psnr_s0")), mm.psnr_s0, 1e-9);
	CHECK_NEAR(json_real_value(json_object_get(sc, "aolp_wrmse_deg")), mm.aolp_wrmse_deg, 1e-9);
	CHECK(!strcmp(json_string_value(json_object_get(sc, "dataset")), "gt"));
	json_decref(root);
	pc_eval_truth_free(&t);
	/* every method (the default): gains over bilinear, whatever method the list ends with */
	snprintf(args, sizeof args, "eval %s --json %s", tmp("gt/scene"), tmp("all.json"));
	CHECK_EQ_INT(run(args), 0);
	CHECK(file_contains(tmp("out.txt"), "gain over bilinear"));
	CHECK(file_contains(tmp("all.json"), "gain_over_bilinear_db"));
	/* a colour method on a monochrome truth: refused, saying why (colour scenes: test_stress)
	 */
	snprintf(args, sizeof args, "eval %s --method pan-chroma", tmp("gt/scene"));
	CHECK(run(args) != 0);
	CHECK(file_contains(tmp("err.txt"), "colour-polarization"));
	/* a missing analyser image: exit 2 naming it */
	CHECK_EQ_INT(unlink(tmp("gt/scene/45.tif")), 0);
	snprintf(args, sizeof args, "eval %s", tmp("gt/scene"));
	CHECK_EQ_INT(run(args), 2);
	CHECK(file_contains(tmp("err.txt"), "'45'"));
	for (int c = 0; c < 4; c++)
		pc_view_free(&v[c]);
}

int main(void)
{
	exe = getenv("POLARCAM");
	if (!exe || !*exe)
		SKIP("POLARCAM (the built CLI) is not set; run through ctest");
	if (!pc_test_tmpdir(dir, sizeof dir, "pc_test_pcli"))
		SKIP("cannot create a temporary directory");
	setenv("POLARCAM_PROGRESS", "0", 1);
	test_demosaic_cmd();
	test_bad_input();
	test_process_cmd();
	test_process_minmax();
	test_process_colour();
	test_map_hatch();
	test_eval_cmd();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_pipeline_cli");
}
