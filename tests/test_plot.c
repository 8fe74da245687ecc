/* Plots: a known line lands where the axis mapping says, legends and colour bars render, and
 * a failed write leaves no file behind. */
#include <cairo.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/io.h"
#include "polarcam/picture.h"
#include "polarcam/plot.h"
#include "polarcam/stokes.h"

static int count_files(const char *dir)
{
	DIR *d = opendir(dir);
	int n = 0;
	struct dirent *e;
	while (d && (e = readdir(d)))
		if (e->d_name[0] != '.' || strstr(e->d_name, ".tmp"))
			n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
	if (d)
		closedir(d);
	return n;
}

static void grey(double t, double s, uint8_t rgb[3], void *ctx)
{
	(void)s;
	(void)ctx;
	rgb[0] = rgb[1] = rgb[2] = (uint8_t)(255 * t);
}

/* The automatic DoLP range against the percentile worked out by hand: N values spread evenly
 * over [0, 0.3) put their 99th percentile at 0.297, rounded up to 0.30; the same number of
 * pixels at DoLP 0.9 under the mask threshold leave it there, and count without the mask. */
static void test_dolp_auto(void)
{
	enum { N = 10000 };
	float *d = malloc(2 * N * sizeof *d), *s = malloc(2 * N * sizeof *s);
	for (int i = 0; i < N; i++) {
		d[i] = 0.3f * (float)i / N;
		s[i] = 1000;
		d[N + i] = 0.9f; /* dark pixels: noise */
		s[N + i] = 5;
	}
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, N, 10), 0.30, 1e-12);
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, 2 * N, 10), 0.30, 1e-12);
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, 2 * N, 0), 0.90, 1e-12); /* no mask */
	/* the floor and the ceiling: all zero gives 0.05, values above 1 give 1 */
	for (int i = 0; i < N; i++)
		d[i] = 0;
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, N, 0), 0.05, 1e-12);
	for (int i = 0; i < N; i++)
		d[i] = 1.5f;
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, N, 0), 1.0, 1e-12);
	/* nothing usable (every pixel masked or not finite): the full range */
	CHECK_NEAR(pc_pictures_dolp_auto(d, s, N, 1e9), 1.0, 1e-12);
	free(d);
	free(s);
}

/* The live window's panels (pc_pictures_panels) on a synthetic 160 × 100 Stokes image: S0 2000
 * (grey 128 on the S0 scale 0..4000), DoLP 0.5, AoLP 45°; a band of rows 10..19 at S0 = 5
 * (under the 1 % mask of 40: hatched in DoLP and AoLP); 8 × 8 invalid blocks at the top-left
 * and bottom-right corners. */
enum { PW = 160, PH = 100 };
static float p_s0[PW * PH], p_dolp[PW * PH], p_aolp[PW * PH];
static uint8_t p_valid[PW * PH];

static void panels_input(pc_stokes_out *st, pc_validity *v)
{
	for (int y = 0; y < PH; y++)
		for (int x = 0; x < PW; x++) {
			int i = y * PW + x;
			p_s0[i] = y >= 10 && y < 20 ? 5.0f : 2000.0f;
			p_dolp[i] = 0.5f;
			p_aolp[i] = (float)(M_PI / 4);
			p_valid[i] = !((x < 8 && y < 8) || (x >= PW - 8 && y >= PH - 8));
		}
	memset(st, 0, sizeof *st);
	st->s0 = (pc_fplane){p_s0, PW, 1};
	st->dolp = (pc_fplane){p_dolp, PW, 1};
	st->aolp = (pc_fplane){p_aolp, PW, 1};
	*v = (pc_validity){p_valid, PW, 16 * 8};
}

static const uint8_t *px_at(const uint8_t *rgb, uint32_t w, uint32_t x, uint32_t y)
{
	return rgb + ((size_t)y * w + x) * 3;
}

static bool near_rgb(const uint8_t *p, int r, int g, int b)
{
	return abs(p[0] - r) <= 1 && abs(p[1] - g) <= 1 && abs(p[2] - b) <= 1;
}

static bool is_white(const uint8_t *p)
{
	return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

/* The image's extent in a panel starting at column x0: from column x0 + 1 down from the status
 * strip (the centred title leaves it white) and along the image's middle row. */
static void image_extent(const uint8_t *rgb, uint32_t w, uint32_t h, uint32_t x0, uint32_t top,
                         uint32_t *iw, uint32_t *ih, uint32_t *y0)
{
	uint32_t y = top;
	while (y < h && is_white(px_at(rgb, w, x0 + 1, y)))
		y++;
	*y0 = y;
	while (y < h && !is_white(px_at(rgb, w, x0 + 1, y)))
		y++;
	*ih = y - *y0;
	uint32_t x = x0, ym = *y0 + *ih / 2;
	while (x < w && !is_white(px_at(rgb, w, x, ym)))
		x++;
	*iw = x - x0;
}

static void test_panels(const char *dir)
{
	pc_stokes_out st;
	pc_validity v;
	panels_input(&st, &v);
	pc_pictures_opts o = {NULL, 0, 0, NULL, 4000, 0};
	/* 816 = 3·160 + two grey keys of 7 fs + fs (fs = 12 below 480-pixel images) + the 2-D
	 * AoLP key of 9 fs + fs + two gaps of 12: the images are drawn at their own size */
	uint8_t *out = NULL;
	uint32_t oh = 0;
	CHECK_EQ_INT(pc_pictures_panels(&st, PW, PH, &o, &v, 816, 30, &out, &oh), 0);
	uint32_t iw, ih, y0;
	image_extent(out, 816, oh, 0, 30, &iw, &ih, &y0);
	printf("panels at 816: image %ux%u at row %u, picture height %u\n", iw, ih, y0, oh);
	CHECK_EQ_INT(iw, PW);
	CHECK_EQ_INT(ih, PH);
	/* each panel equals the file picture pc_pictures_write_valid writes (same key, ticks,
	 * range, masks and notes) below the titles, which differ (short on screen) */
	CHECK_EQ_INT(pc_pictures_write_valid(dir, &st, PW, PH, &o, &v), 0);
	static const char *files[3] = {"s0.png", "dolp.png", "aolp.png"};
	uint32_t x0 = 0;
	for (int k = 0; k < 3; k++) {
		char path[300];
		snprintf(path, sizeof path, "%s/%s", dir, files[k]);
		cairo_surface_t *f = cairo_image_surface_create_from_png(path);
		CHECK(cairo_surface_status(f) == CAIRO_STATUS_SUCCESS);
		const int fw = cairo_image_surface_get_width(f),
		          fh = cairo_image_surface_get_height(f);
		const unsigned char *fd = cairo_image_surface_get_data(f);
		const int fst = cairo_image_surface_get_stride(f);
		CHECK_EQ_INT((uint32_t)fh + 30, oh);
		long diff = 0;
		for (int y = 30; y < fh; y++)
			for (int x = 0; x < fw; x++) {
				uint32_t q =
				    ((const uint32_t *)(const void *)(fd + (size_t)y * fst))[x];
				const uint8_t *p =
				    px_at(out, 816, x0 + (uint32_t)x, 30 + (uint32_t)y);
				diff += p[0] != (uint8_t)(q >> 16) || p[1] != (uint8_t)(q >> 8) ||
				        p[2] != (uint8_t)q;
			}
		printf("panel %d (%s, %dx%d): %ld pixels differ from the file below the title\n", k,
		       files[k], fw, fh, diff);
		CHECK_EQ_INT(diff, 0);
		cairo_surface_destroy(f);
		x0 += (uint32_t)fw + 12;
	}
	CHECK(x0 - 12 <= 816);
	/* colours at known values, worked out from the documented maps (polarcam/picture.h):
	 * S0 2000 on 0..4000 grey 128; DoLP 0.5 on 0..1 grey 128; AoLP 45° = hue 0.25 of the
	 * circle (HSV sector 1, f = 0.5) at value 0.5: (0.25, 0.5, 0) -> (64, 128, 0) */
	const uint32_t w1 = 160 + 96 + 12, cx = 80, cy = y0 + 50, by = y0 + 15;
	CHECK(near_rgb(px_at(out, 816, cx, cy), 128, 128, 128));
	CHECK(near_rgb(px_at(out, 816, w1 + cx, cy), 128, 128, 128));
	CHECK(near_rgb(px_at(out, 816, 2 * w1 + cx, cy), 64, 128, 0));
	/* the low-signal band: S0 black, DoLP and AoLP the hatch's two greys */
	CHECK(near_rgb(px_at(out, 816, cx, by), 0, 0, 0));
	int hatch = 0;
	for (uint32_t x = 20; x < 140; x++)
		for (int k = 1; k < 3; k++) {
			const uint8_t *p = px_at(out, 816, (uint32_t)k * w1 + x, by);
			hatch += (p[0] == PC_PICTURE_MASK_RGB0 || p[0] == PC_PICTURE_MASK_RGB1) &&
			         p[1] == p[0] && p[2] == p[0];
		}
	CHECK_EQ_INT(hatch, 2 * 120);
	/* the invalid corners: the pink checker in every panel */
	for (int k = 0; k < 3; k++) {
		int pink = 0;
		for (uint32_t y = 0; y < 8; y++)
			for (uint32_t x = 0; x < 8; x++)
				pink += near_rgb(px_at(out, 816, (uint32_t)k * w1 + x, y0 + y),
				                 PC_PICTURE_INVALID_R, PC_PICTURE_INVALID_G,
				                 PC_PICTURE_INVALID_B);
		CHECK_EQ_INT(pink, 32);
	}
	free(out);

	/* the automatic DoLP range: 0.5 everywhere unmasked gives 0..0.5, so DoLP 0.5 is white
	 * and AoLP at full value: hue 0.25 -> (128, 255, 0) */
	o.dolp_hi = -1;
	CHECK_EQ_INT(pc_pictures_panels(&st, PW, PH, &o, &v, 816, 30, &out, &oh), 0);
	CHECK(near_rgb(px_at(out, 816, w1 + cx, cy), 255, 255, 255));
	CHECK(near_rgb(px_at(out, 816, 2 * w1 + cx, cy), 128, 255, 0));
	free(out);

	/* a wider window: the images scaled up at the frames' aspect ratio (1.6), to within the
	 * rounding of a pixel, and the whole picture exactly as wide as asked */
	o.dolp_hi = 0;
	CHECK_EQ_INT(pc_pictures_panels(&st, PW, PH, &o, &v, 1500, 30, &out, &oh), 0);
	image_extent(out, 1500, oh, 0, 30, &iw, &ih, &y0);
	printf("panels at 1500: image %ux%u (aspect %.4f, frames 1.6)\n", iw, ih, (double)iw / ih);
	CHECK(iw > 2 * PW);
	CHECK(fabs((double)iw / ih - 1.6) < 1.6 / ih + 1e-9);
	free(out);
	/* too narrow for the keys: refused, nothing returned */
	out = (uint8_t *)1;
	CHECK(pc_pictures_panels(&st, PW, PH, &o, &v, PC_PICTURES_PANELS_MIN_WIDTH - 1, 30, &out,
	                         &oh) == PC_EINVAL);
	CHECK(out == NULL);
}

/* The live window's drawer (pc_pictures_live_draw) keeps its buffers from frame to frame: every
 * draw must give the pixels of a fresh pc_pictures_panels (checked against the files above), so
 * that nothing of an earlier frame, size or DoLP range shows through; frames of one size reuse
 * the output buffer (the same pointer back). */
static void test_panels_live(void)
{
	pc_stokes_out a, b;
	pc_validity va, vb;
	panels_input(&a, &va);
	/* frame B: other values everywhere, no invalid pixel, no low-signal band */
	static float b_s0[PW * PH], b_dolp[PW * PH], b_aolp[PW * PH];
	for (int i = 0; i < PW * PH; i++) {
		b_s0[i] = 500.0f + (float)(i % PW) * 20.0f;
		b_dolp[i] = (float)(i / PW) / PH;
		b_aolp[i] = (float)(M_PI * (i % PW) / PW);
	}
	b = a;
	b.s0 = (pc_fplane){b_s0, PW, 1};
	b.dolp = (pc_fplane){b_dolp, PW, 1};
	b.aolp = (pc_fplane){b_aolp, PW, 1};
	vb = (pc_validity){NULL, 0, 0};
	/* frame C: the top-left 80 x 50 of A (its planes' row stride stays PW) */
	pc_validity vc = {p_valid, PW, 8 * 8};
	struct {
		const pc_stokes_out *st;
		const pc_validity *v;
		uint32_t w, h, out_w;
		double dolp_hi;
	} seq[] = {{&a, &va, PW, PH, 816, 0},  {&b, &vb, PW, PH, 816, 0},
	           {&b, &vb, PW, PH, 816, -1}, {&a, &vc, 80, 50, 816, 0},
	           {&a, &va, PW, PH, 1500, 0}, {&a, &va, PW, PH, 816, 0.25}};
	pc_pictures_live *lp = NULL;
	CHECK_EQ_INT(pc_pictures_live_new(&lp), 0);
	const uint8_t *first = NULL;
	for (size_t k = 0; lp && k < sizeof seq / sizeof seq[0]; k++) {
		pc_pictures_opts o = {NULL, 0, 0, NULL, 0, seq[k].dolp_hi};
		const uint8_t *got = NULL;
		uint8_t *want = NULL;
		uint32_t gh = 0, wh = 0;
		CHECK_EQ_INT(pc_pictures_live_draw(lp, seq[k].st, seq[k].w, seq[k].h, &o, seq[k].v,
		                                   seq[k].out_w, 30, &got, &gh),
		             0);
		CHECK_EQ_INT(pc_pictures_panels(seq[k].st, seq[k].w, seq[k].h, &o, seq[k].v,
		                                seq[k].out_w, 30, &want, &wh),
		             0);
		CHECK_EQ_INT(gh, wh);
		long diff = 0;
		for (size_t i = 0; got && want && gh == wh && i < (size_t)seq[k].out_w * gh * 3;
		     i++)
			diff += got[i] != want[i];
		printf(
		    "live panels, draw %zu (%ux%u into %u, DoLP range %g): %ld bytes differ from a "
		    "fresh drawing\n",
		    k, seq[k].w, seq[k].h, seq[k].out_w, seq[k].dolp_hi, diff);
		CHECK_EQ_INT(diff, 0);
		if (k == 0)
			first = got;
		if (k == 1 || k == 2)
			CHECK(got == first); /* the same size: the same buffer */
		free(want);
	}
	pc_pictures_live_free(lp);
	pc_pictures_live_free(NULL);
}

/* Circular polarization (pc_circular_folder_write): states built from Jones vectors
 * E = (cos a, sin a·e^{iδ}) mixed with unpolarized light (degree P), whose Stokes vector is
 * S0 (1, P cos 2a, P sin 2a cos δ, P sin 2a sin δ) (physics.md §1) and whose ellipse has
 * sin 2χ = sin 2a sin δ (Born & Wolf §1.4.2): DoCP = P |sin 2a sin δ|, χ = ½ asin(sin 2a sin δ),
 * worked out from a and δ, not from S. Column 0 is right-handed circular (χ = +45°, red), 1
 * left-handed (−45°, blue), 2 linear (white); row 7 has no light, pixel (5, 6) S3 = NaN. */
static void test_circular(const char *dir)
{
	enum { CW = 16, CH = 8 };
	static float s[4][CW * CH];
	double want_d[CW], want_e[CW];
	for (int x = 0; x < CW; x++) {
		double a = x == 0 || x == 1 ? M_PI / 4
		           : x == 2         ? 0
		                            : 0.1 + 0.09 * x,
		       d = x == 0   ? M_PI / 2
		           : x == 1 ? -M_PI / 2
		           : x == 2 ? 0
		                    : -1.3 + 0.23 * x,
		       p = x < 3 ? 1 : 0.3 + 0.04 * x;
		want_d[x] = p * fabs(sin(2 * a) * sin(d));
		want_e[x] = 0.5 * asin(sin(2 * a) * sin(d));
		for (int y = 0; y < CH; y++) {
			double s0 = y == CH - 1 ? 0 : 1000;
			s[0][y * CW + x] = (float)s0;
			s[1][y * CW + x] = (float)(s0 * p * cos(2 * a));
			s[2][y * CW + x] = (float)(s0 * p * sin(2 * a) * cos(d));
			s[3][y * CW + x] = (float)(s0 * p * sin(2 * a) * sin(d));
		}
	}
	s[3][6 * CW + 5] = NAN;
	pc_fplane pl[4];
	for (int k = 0; k < 4; k++)
		pl[k] = (pc_fplane){s[k], CW, 1};
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	CHECK_EQ_INT(pc_circular_folder_write(dir, pl, CW, CH, &o), 0);
	char path[300];
	pc_array d, e;
	snprintf(path, sizeof path, "%s/docp.npy", dir);
	CHECK_EQ_INT(pc_npy_read(path, &d), 0);
	snprintf(path, sizeof path, "%s/ellipticity.npy", dir);
	CHECK_EQ_INT(pc_npy_read(path, &e), 0);
	const float *dd = d.data, *ee = e.data;
	double worst = 0;
	for (int y = 0; y < CH - 1; y++)
		for (int x = 0; x < CW; x++) {
			if (y == 6 && x == 5)
				continue;
			worst = fmax(worst, fabs(dd[y * CW + x] - want_d[x]));
			worst = fmax(worst, fabs(ee[y * CW + x] - want_e[x]));
		}
	printf("circular: worst |error| of DoCP and ellipticity %.3g\n", worst);
	CHECK(worst < 1e-6);
	CHECK(isnan(dd[6 * CW + 5]) && isnan(ee[6 * CW + 5]));
	CHECK(dd[7 * CW + 3] == 0 && ee[7 * CW + 3] == 0); /* no light: no polarization */
	/* the pictures: image pixels below the title band (io/plot.c: 2.2 fs, fs = 12 here) */
	const int top = (int)(12 * 2.2);
	snprintf(path, sizeof path, "%s/ellipticity.png", dir);
	cairo_surface_t *f = cairo_image_surface_create_from_png(path);
	CHECK(cairo_surface_status(f) == CAIRO_STATUS_SUCCESS);
	const unsigned char *fd = cairo_image_surface_get_data(f);
	const int fst = cairo_image_surface_get_stride(f);
#define PX(xx, yy) (((const uint32_t *)(const void *)(fd + (size_t)(top + (yy)) * fst))[xx])
	CHECK_EQ_INT(PX(0, 2) & 0xffffff, 0xff0000); /* +45°: red */
	CHECK_EQ_INT(PX(1, 2) & 0xffffff, 0x0000ff); /* −45°: blue */
	CHECK_EQ_INT(PX(2, 2) & 0xffffff, 0xffffff); /* linear: white */
	CHECK_EQ_INT(PX(5, 6) & 0xffffff, 0xff00ff); /* NaN: magenta */
	cairo_surface_destroy(f);
	snprintf(path, sizeof path, "%s/docp.png", dir);
	f = cairo_image_surface_create_from_png(path);
	CHECK(cairo_surface_status(f) == CAIRO_STATUS_SUCCESS);
	fd = cairo_image_surface_get_data(f);
	CHECK_EQ_INT(PX(0, 2) & 0xffffff, 0xffffff); /* DoCP 1 on 0..1 */
	CHECK_EQ_INT(PX(2, 2) & 0xffffff, 0x000000); /* DoCP 0 */
	const unsigned g = PX(3, 2) & 0xff, want_g = (unsigned)(want_d[3] * 255 + 0.5);
	CHECK(g + 1 >= want_g && g <= want_g + 1);
	/* the dark row (S0 < 1 % of the scale) carries the hatch */
	const unsigned h = PX(8, 7) & 0xff;
	CHECK(h == PC_PICTURE_MASK_RGB0 || h == PC_PICTURE_MASK_RGB1);
#undef PX
	cairo_surface_destroy(f);
	pc_array_free(&d);
	pc_array_free(&e);
}

int main(void)
{
	test_dolp_auto();
	char dir[64];
	CHECK(pc_test_tmpdir(dir, sizeof dir, "pc_test_plot") != NULL);
	char pdir[128];
	snprintf(pdir, sizeof pdir, "%s/panels", dir);
	CHECK_EQ_INT(pc_mkdir_p(pdir), 0);
	test_panels(pdir);
	test_panels_live();
	test_circular(pdir);
	snprintf(pdir, sizeof pdir, "rm -rf '%s/panels'", dir);
	CHECK_EQ_INT(system(pdir), 0);
	char path[256];
	snprintf(path, sizeof path, "%s/line.png", dir);

	/* a vertical line at x = 0.5 on a fixed [0, 1] axis must be drawn at the centre column
	 * of the plot area: find the palette's first colour on the middle row */
	pc_plot *p = pc_plot_new("test", "x", "y");
	pc_plot_set_xrange(p, 0, 1);
	pc_plot_set_yrange(p, 0, 1);
	double x[2] = {0.5, 0.5}, y[2] = {0, 1};
	CHECK_EQ_INT(pc_plot_add_series(p, NULL, x, y, 2, PC_PLOT_LINE), 0);
	CHECK_EQ_INT(pc_plot_write_png(p, path, 800, 600), 0);
	cairo_surface_t *s = cairo_image_surface_create_from_png(path);
	CHECK(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS);
	CHECK_EQ_INT(cairo_image_surface_get_width(s), 800);
	CHECK_EQ_INT(cairo_image_surface_get_height(s), 600);
	/* the plot area spans [left, left + pw] with left = 5.5 fs, right margin 1.5 fs */
	double fs = 600 / 40.0, left = 5.5 * fs, pw = 800 - left - 1.5 * fs;
	int expect_x = (int)(left + 0.5 * pw);
	const unsigned char *data = cairo_image_surface_get_data(s);
	int stride = cairo_image_surface_get_stride(s);
	int found = -1;
	const uint32_t *row = (const uint32_t *)(const void *)(data + 300 * stride);
	for (int i = 0; i < 800; i++) {
		uint32_t px = row[i] & 0xffffff;
		unsigned r = px >> 16, g = (px >> 8) & 255, b = px & 255;
		if (b > 150 && r < 60 && g > 90 && g < 150) { /* palette[0] = (0.12, 0.47, 0.71) */
			found = i;
			break;
		}
	}
	CHECK(found >= expect_x - 2 && found <= expect_x + 2);
	cairo_surface_destroy(s);
	pc_plot_free(p);

	/* log axes, legend, labels, NaN gaps: renders without error */
	p = pc_plot_new("log", "time (ms)", "error");
	pc_plot_set_log(p, true, true);
	double lx[4] = {1, 10, NAN, 1000}, ly[4] = {1e-1, 1e-3, 1, 1e-6};
	CHECK_EQ_INT(pc_plot_add_series(p, "a", lx, ly, 4, PC_PLOT_LINE_POINTS), 0);
	CHECK_EQ_INT(pc_plot_add_series(p, "b", lx, ly, 4, PC_PLOT_DASHED), 0);
	CHECK_EQ_INT(pc_plot_add_label(p, 10, 1e-3, "knee"), 0);
	snprintf(path, sizeof path, "%s/log.png", dir);
	CHECK_EQ_INT(pc_plot_write_png(p, path, 640, 480), 0);
	pc_plot_free(p);

	/* image with a colour bar */
	uint8_t img[16 * 8 * 3];
	for (int i = 0; i < 16 * 8 * 3; i++)
		img[i] = (uint8_t)(i * 7);
	pc_colorbar bar = {"S0", 0, 1, NULL, 0, 0, grey, NULL, 0};
	snprintf(path, sizeof path, "%s/img.png", dir);
	CHECK_EQ_INT(pc_image_write_png(path, img, 16, 8, 16 * 3, "picture", &bar, 0), 0);
	s = cairo_image_surface_create_from_png(path);
	CHECK(cairo_surface_status(s) == CAIRO_STATUS_SUCCESS);
	CHECK(cairo_image_surface_get_width(s) > 16);
	cairo_surface_destroy(s);

	/* writing into a missing directory fails and leaves nothing */
	snprintf(path, sizeof path, "%s/missing/x.png", dir);
	p = pc_plot_new(NULL, NULL, NULL);
	CHECK(pc_plot_write_png(p, path, 400, 300) != 0);
	CHECK(strstr(pc_error_detail(), "missing") != NULL);
	pc_plot_free(p);
	CHECK_EQ_INT(count_files(dir), 3);

	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	CHECK_EQ_INT(system(cmd), 0);
	return pc_test_finish("test_plot");
}
