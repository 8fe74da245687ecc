/* The lens blur (effect "blur", sim/blur.c) against a slow reference: the scene rendered without
 * the effect, then convolved here in two dimensions at once with the normalised Gaussian
 * exp(−(dx² + dy²)/(2σ²)) over the (2R + 1)² square, R = ⌈4σ⌉, the image mirrored at the
 * sensor's edges (reflect-101) — the library blurs along rows and then columns, with its own
 * weights. Checked:
 *  - Stokes and Mueller truth in double (pc_sim_truth_rows), monochrome and colour, a sharp
 *    scene (a sphere and a plane under a point light, the physics core's pBRDF), σ 0.5, 1.3, 2.5
 *    and 8 (the kernel wider than the 48 × 32 sensor: the mirror folds more than once);
 *  - the float truth that pc_sim_prepare writes, to float rounding;
 *  - a region of interest equals the same crop of the full sensor, bit for bit: raw frames with
 *    the IMX250MZR preset (noise, crosstalk's one-pixel halo), Stokes truth; and a band of
 *    rows from pc_sim_truth_rows equals the same rows of the whole;
 *  - the blur moves radiance between pixels and creates none: the image's total changes by
 *    less than the radiance of the border band that the edges' mirror redistributes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/sim.h"

#define W 48
#define H 32

#define SCENE_FMT                                                                                  \
	"{\"camera\": {\"position\": [0, -4, 2], \"look_at\": [0, 0, 0.6], \"focal_length_mm\": "  \
	"8},"                                                                                      \
	" \"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 100%s},"                      \
	" \"materials\": {\"m\": {\"n\": 1.5, \"k\": 0.2, \"sigma\": 0.1}, \"g\": {\"n\": 1.9,"    \
	" \"sigma\": 0.3}},"                                                                       \
	" \"lights\": [{\"type\": \"point\", \"position\": [1, -1, 4], \"intensity_w_sr\": 100}]," \
	" \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0.6], \"radius\": 0.6,"            \
	" \"material\": \"m\"}, {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1],"    \
	" \"material\": \"g\"}],"                                                                  \
	" \"effects\": {\"mueller\": true%s}}"

static pc_sim *make(const char *sensor_extra, const char *fx_extra, uint32_t roi_x, uint32_t roi_y,
                    uint32_t roi_w, uint32_t roi_h)
{
	char text[4096];
	snprintf(text, sizeof text, SCENE_FMT, sensor_extra, fx_extra);
	pc_scene *s = NULL;
	if (pc_scene_parse(text, "test", ".", &s)) {
		fprintf(stderr, "scene: %s\n", pc_error_detail());
		return NULL;
	}
	pc_sim_options o = pc_sim_options_default();
	o.roi_x = roi_x;
	o.roi_y = roi_y;
	o.roi_width = roi_w;
	o.roi_height = roi_h;
	pc_sim *sim = NULL;
	if (pc_sim_new(s, &o, &sim))
		fprintf(stderr, "sim: %s\n", pc_error_detail());
	pc_scene_free(s);
	return sim;
}

static int mirror(int i, int n)
{
	int p = 2 * n - 2;
	i %= p;
	if (i < 0)
		i += p;
	return i < n ? i : p - i;
}

/* The slow reference: q values per pixel (nch channels × 4 Stokes or × 16 Mueller). */
static void blur_ref(const double *in, double *out, int q, double sigma)
{
	int R = (int)ceil(4 * sigma);
	double sum = 0;
	for (int dy = -R; dy <= R; dy++)
		for (int dx = -R; dx <= R; dx++)
			sum += exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double *o = out + ((size_t)y * W + x) * q;
			for (int k = 0; k < q; k++)
				o[k] = 0;
			for (int dy = -R; dy <= R; dy++)
				for (int dx = -R; dx <= R; dx++) {
					double w =
					    exp(-(dx * dx + dy * dy) / (2 * sigma * sigma)) / sum;
					const double *s =
					    in +
					    ((size_t)mirror(y + dy, H) * W + mirror(x + dx, W)) * q;
					for (int k = 0; k < q; k++)
						o[k] += w * s[k];
				}
		}
}

/* Largest |a − b| over the largest |b| (S3 is NaN without "circular": skipped). */
static double rel_diff(const double *a, const double *b, size_t n, int q, int skip)
{
	double d = 0, m = 0;
	for (size_t i = 0; i < n; i++) {
		if (skip >= 0 && (int)(i % (size_t)q) == skip)
			continue;
		d = fmax(d, fabs(a[i] - b[i]));
		m = fmax(m, fabs(b[i]));
	}
	return d / m;
}

static void test_against_reference(const char *sensor_extra, int nch, double sigma)
{
	char fx[64];
	snprintf(fx, sizeof fx, ", \"blur\": %g", sigma);
	pc_sim *plain = make(sensor_extra, "", 0, 0, 0, 0),
	       *blur = make(sensor_extra, fx, 0, 0, 0, 0);
	CHECK(plain && blur);
	if (!plain || !blur) {
		pc_sim_free(plain);
		pc_sim_free(blur);
		return;
	}
	const size_t n = (size_t)W * H * nch;
	double *S = malloc(n * 4 * sizeof *S), *M = malloc(n * 16 * sizeof *M);
	double *Sb = malloc(n * 4 * sizeof *Sb), *Mb = malloc(n * 16 * sizeof *Mb);
	double *Sr = malloc(n * 4 * sizeof *Sr), *Mr = malloc(n * 16 * sizeof *Mr);
	float *Sf = malloc(n * 4 * sizeof *Sf);
	CHECK(S && M && Sb && Mb && Sr && Mr && Sf);
	if (S && M && Sb && Mb && Sr && Mr && Sf) {
		CHECK_EQ_INT(pc_sim_truth_rows(plain, 0, 0, H, S, M), 0);
		CHECK_EQ_INT(pc_sim_truth_rows(blur, 0, 0, H, Sb, Mb), 0);
		blur_ref(S, Sr, nch * 4, sigma);
		blur_ref(M, Mr, nch * 16, sigma);
		/* S3 (every fourth value) is NaN without "circular" */
		double es = rel_diff(Sb, Sr, n * 4, 4, 3), em = rel_diff(Mb, Mr, n * 16, 16, -1);
		double moved = rel_diff(S, Sr, n * 4, 4, 3);
		printf(
		    "blur sigma %.1f, %d channel(s): Stokes %.2e, Mueller %.2e of the largest off "
		    "the 2-D reference; the blur itself moves the image by %.2f\n",
		    sigma, nch, es, em, moved);
		CHECK(es < 1e-12);
		CHECK(em < 1e-12);
		CHECK(moved > 0.05); /* the scene has edges: the blur does change it */
		/* the float truth pc_sim_prepare writes */
		CHECK_EQ_INT(pc_sim_prepare(blur, 0, Sf, NULL, NULL, NULL), 0);
		double ef = 0, m = 0;
		for (size_t i = 0; i < n * 4; i++)
			if (i % 4 != 3) {
				ef = fmax(ef, fabs(Sf[i] - Sr[i]));
				m = fmax(m, fabs(Sr[i]));
			}
		CHECK(ef / m < 1e-6);
		/* the total radiance in the interior: the kernel moves light between pixels but
		 * creates none (rows and columns far enough from the edges not to see the mirror)
		 */
		int R = (int)ceil(4 * sigma);
		if (2 * R + 8 < H) {
			double t0 = 0, t1 = 0, lo = 0;
			for (int y = 0; y < H; y++)
				for (int x = 0; x < W; x++)
					for (int c = 0; c < nch; c++) {
						double v = S[(((size_t)y * W + x) * nch + c) * 4];
						t0 += v;
						t1 += Sb[(((size_t)y * W + x) * nch + c) * 4];
						if (y < R || y >= H - R || x < R || x >= W - R)
							lo += v;
					}
			/* the edges' mirror redistributes at most the border band's radiance */
			CHECK(fabs(t1 - t0) <= lo);
		}
	}
	free(S);
	free(M);
	free(Sb);
	free(Mb);
	free(Sr);
	free(Mr);
	free(Sf);
	pc_sim_free(plain);
	pc_sim_free(blur);
}

/* A ROI equals the crop of the full sensor; a band of truth rows equals those rows of the whole. */
static void test_roi(void)
{
	const char *preset = ", \"preset\": \"imx250mzr\", \"exposure_us\": 20000";
	const uint32_t rx = 10, ry = 6, rw = 20, rh = 12;
	pc_sim *full = make(preset, ", \"blur\": 1.7", 0, 0, 0, 0),
	       *roi = make(preset, ", \"blur\": 1.7", rx, ry, rw, rh);
	CHECK(full && roi);
	if (!full || !roi) {
		pc_sim_free(full);
		pc_sim_free(roi);
		return;
	}
	pc_sim_info fi, ri;
	pc_sim_get_info(full, &fi);
	pc_sim_get_info(roi, &ri);
	CHECK(fi.effects & PC_FX_CROSSTALK);
	CHECK(fi.effects & PC_FX_BLUR);
	pc_view a = {0}, b = {0};
	CHECK_EQ_INT(pc_view_alloc(&a, fi.format, W, H, 0), 0);
	CHECK_EQ_INT(pc_view_alloc(&b, ri.format, rw, rh, 0), 0);
	CHECK_EQ_INT(pc_sim_frame(full, 3, NULL, &a, NULL), 0);
	CHECK_EQ_INT(pc_sim_frame(roi, 3, NULL, &b, NULL), 0);
	int same = 1;
	for (uint32_t y = 0; y < rh; y++)
		same &= !memcmp((const uint8_t *)b.data + (size_t)y * b.stride,
		                (const uint8_t *)a.data + (size_t)(ry + y) * a.stride + rx * 2,
		                (size_t)rw * 2);
	CHECK(same);
	double *St = malloc((size_t)W * H * 4 * sizeof *St),
	       *Sr = malloc((size_t)rw * rh * 4 * sizeof *Sr);
	double *Sband = malloc((size_t)W * 5 * 4 * sizeof *Sband);
	CHECK(St && Sr && Sband);
	if (St && Sr && Sband) {
		CHECK_EQ_INT(pc_sim_truth_rows(full, 0, 0, H, St, NULL), 0);
		CHECK_EQ_INT(pc_sim_truth_rows(roi, 0, 0, rh, Sr, NULL), 0);
		CHECK_EQ_INT(pc_sim_truth_rows(full, 0, 9, 14, Sband, NULL), 0);
		int same_t = 1, same_b = 1;
		for (uint32_t y = 0; y < rh; y++)
			for (uint32_t x = 0; x < rw; x++)
				for (int q = 0; q < 3; q++)
					same_t &= Sr[((size_t)y * rw + x) * 4 + q] ==
					          St[((size_t)(ry + y) * W + rx + x) * 4 + q];
		for (uint32_t y = 0; y < 5; y++)
			for (uint32_t x = 0; x < W; x++)
				for (int q = 0; q < 3; q++)
					same_b &= Sband[((size_t)y * W + x) * 4 + q] ==
					          St[((size_t)(9 + y) * W + x) * 4 + q];
		CHECK(same_t);
		CHECK(same_b);
	}
	free(St);
	free(Sr);
	free(Sband);
	pc_view_free(&a);
	pc_view_free(&b);
	pc_sim_free(full);
	pc_sim_free(roi);
}

int main(void)
{
	test_against_reference("", 1, 0.5);
	test_against_reference("", 1, 1.3);
	test_against_reference("", 1, 2.5);
	test_against_reference("", 1, 8);
	test_against_reference(", \"layout\": \"RGGB:90,45,135,0\"", 3, 1.3);
	test_roi();
	return pc_test_finish("test_sim_blur");
}
