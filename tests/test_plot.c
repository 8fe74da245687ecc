/* Plots: a known line lands where the axis mapping says, legends and colour bars render, and
 * a failed write leaves no file behind. */
#include <cairo.h>
#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/plot.h"

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

int main(void)
{
	test_dolp_auto();
	char dir[64];
	CHECK(pc_test_tmpdir(dir, sizeof dir, "pc_test_plot") != NULL);
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
