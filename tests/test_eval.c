/* The evaluation protocol: metrics against hand-computed values, the AoLP wrap, the 15-pixel
 * border, normalisation by the container, and our bilinear against an independent convolution
 * formulation (zero-filled sparse channels filtered by [1 2 1; 2 4 2; 1 2 1]/4 with
 * reflect-101 borders, as the field's public evaluation code does it with OpenCV); the truth's
 * shared pixel-level pattern (pc_eval_truth_pattern) against its analytic values on synthetic
 * truths: a share ρ of white variation common to the four images gives corr ρ, RMS √(8/9)·σ,
 * and one pixel apart −ρ/6 before the selection of flat pixels (the 3×3 mean's overlap: cov
 * −4/27·σ², var 8/9·σ²). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"

#define PC_TEST_SEED 0x5eed41ull
#include "xorshift.h"

enum { W = 40, H = 36 };

static void make_truth(pc_eval_truth *t, double base[4])
{
	memset(t, 0, sizeof *t);
	t->width = W;
	t->height = H;
	t->full_scale = 65535;
	t->format = PC_FMT_MONO16;
	for (int c = 0; c < 4; c++) {
		t->ch[c] = malloc(sizeof(double) * W * H);
		for (int i = 0; i < W * H; i++)
			t->ch[c][i] = base[c];
	}
}

static void test_hand_values(void)
{
	/* truth: unpolarized 0.4 in every channel (S0 = 0.8, DoLP 0) */
	double base[4] = {0.4, 0.4, 0.4, 0.4};
	pc_eval_truth t;
	make_truth(&t, base);
	/* estimate: I0 off by +0.01 everywhere, others exact */
	float *e = malloc(sizeof(float) * W * H * 4);
	pc_fplane est[4];
	pc_fplanes_separate(e, W, H, 4, est);
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < W * H; i++)
			est[c].data[i] = (float)((base[c] + (c == 0 ? 0.01 : 0)) * 1000);
	pc_eval_metrics m;
	CHECK_EQ_INT(pc_eval_score(&t, est, 1000, &m), 0);
	/* I0 MSE = 1e-4 -> 40 dB; the others are exact (float rounding of 400/1000 aside) */
	CHECK_NEAR(m.psnr_i_ch[0], 40, 1e-4);
	CHECK(m.psnr_i_ch[1] > 120);
	/* S0 error 0.005, so S0/2 error 0.0025 -> 52.04 dB; (S1+1)/2 error 0.005 -> 46.02 dB;
	 * S2 exact */
	CHECK_NEAR(m.psnr_s0, 20 * log10(1 / 0.0025), 1e-3);
	CHECK_NEAR(m.psnr_s1, 20 * log10(1 / 0.005), 1e-3);
	CHECK(m.psnr_s2 > 120);
	/* DoLP: |S1|/S0 = 0.01/0.805 against 0 */
	CHECK_NEAR(m.psnr_dolp, -20 * log10(0.01 / 0.805), 1e-3);
	/* AoLP: truth atan2(0, 0) = 0, estimate ½ atan2(0, 0.01) = 0 -> 0 error */
	CHECK_NEAR(m.aolp_rmse_deg, 0, 1e-9);
	CHECK_NEAR(m.aolp_wrmse_deg, 0, 0); /* all weights (truth DoLP) are zero */
	pc_eval_truth_free(&t);

	/* AoLP wrap: truth AoLP 1° (DoLP 0.5), estimate 179° -> 2° error, not 178° */
	double th = M_PI / 180, es = 179 * M_PI / 180;
	for (int c = 0; c < 4; c++)
		base[c] = 0.25 * (1 + 0.5 * cos(2 * (th - c * M_PI / 4)));
	make_truth(&t, base);
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < W * H; i++)
			est[c].data[i] = (float)(0.25 * (1 + 0.5 * cos(2 * (es - c * M_PI / 4))));
	CHECK_EQ_INT(pc_eval_score(&t, est, 1, &m), 0);
	CHECK_NEAR(m.aolp_rmse_deg, 2, 1e-4);
	CHECK_NEAR(m.aolp_wrmse_deg, 2, 1e-4);
	/* errors inside the 15-pixel border do not count */
	for (int c = 0; c < 4; c++)
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				int inner = x >= 15 && x < W - 15 && y >= 15 && y < H - 15;
				est[c].data[y * W + x] = inner ? (float)t.ch[c][y * W + x] : 7.0f;
			}
	CHECK_EQ_INT(pc_eval_score(&t, est, 1, &m), 0);
	CHECK(m.psnr_i > 120 && m.aolp_rmse_deg < 1e-3);
	pc_eval_truth_free(&t);
	free(e);
}

static double conv_bilinear(const double *img, const pc_mosaic *m, unsigned c, int x, int y)
{
	/* zero-filled sparse channel, reflect-101 borders, kernel [1 2 1; 2 4 2; 1 2 1]/4 */
	static const double k[3][3] = {{1, 2, 1}, {2, 4, 2}, {1, 2, 1}};
	double s = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++) {
			int xx = x + dx, yy = y + dy;
			xx = xx < 0 ? -xx : xx >= W ? 2 * W - 2 - xx : xx;
			yy = yy < 0 ? -yy : yy >= H ? 2 * H - 2 - yy : yy;
			if (pc_mosaic_channel(m, (uint32_t)xx, (uint32_t)yy) == c)
				s += k[dy + 1][dx + 1] * img[yy * W + xx];
		}
	return s / 4;
}

static void test_bilinear_protocol(void)
{
	/* a textured, polarized truth in a 16-bit container */
	pc_view v[4];
	uint32_t r = 7;
	for (int c = 0; c < 4; c++)
		CHECK_EQ_INT(pc_view_alloc(&v[c], PC_FMT_MONO16, W + 1, H + 1, 0),
		             0); /* odd: cropped */
	for (int y = 0; y <= H; y++)
		for (int x = 0; x <= W; x++) {
			r = r * 1664525u + 1013904223u;
			double s0 =
			    20000 + 20000 * ((r >> 8) & 1023) / 1023.0 * (0.5 + 0.5 * sin(x * 0.7));
			double p = 0.3 + 0.2 * cos(y * 0.3), a = 0.05 * x + 0.02 * y;
			for (int c = 0; c < 4; c++)
				PC_ROW(&v[c], uint16_t, y)
			[x] = (uint16_t)lround(s0 / 2 * (1 + p * cos(2 * (a - c * M_PI / 4))));
		}
	pc_eval_truth t;
	CHECK_EQ_INT(pc_eval_truth_from_views(v, &t), 0);
	CHECK(t.width == W && t.height == H && t.full_scale == 65535);
	CHECK_NEAR(t.ch[1][3 * W + 5], PC_ROW(&v[1], uint16_t, 3)[5] / 65535.0, 1e-15);
	pc_eval_metrics ours, ref;
	CHECK_EQ_INT(pc_eval_method(&t, PC_DM_BILINEAR, NULL, &ours), 0);
	/* the convolution formulation, scored by the same metric code */
	pc_mosaic m = pc_mosaic_imx250mzr();
	double *mos = malloc(sizeof(double) * W * H);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			mos[y * W + x] =
			    t.ch[pc_mosaic_channel(&m, (uint32_t)x, (uint32_t)y)][y * W + x];
	float *e = malloc(sizeof(float) * W * H * 4);
	pc_fplane est[4];
	pc_fplanes_separate(e, W, H, 4, est);
	for (unsigned c = 0; c < 4; c++)
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++)
				est[c].data[y * W + x] = (float)conv_bilinear(mos, &m, c, x, y);
	CHECK_EQ_INT(pc_eval_score(&t, est, 1, &ref), 0);
	CHECK_NEAR(ours.psnr_i, ref.psnr_i, 0.05);
	CHECK_NEAR(ours.psnr_s0, ref.psnr_s0, 0.05);
	CHECK_NEAR(ours.psnr_dolp, ref.psnr_dolp, 0.05);
	CHECK_NEAR(ours.aolp_rmse_deg, ref.aolp_rmse_deg, 0.01);
	/* every method scores, and the reference scores like the fast path */
	for (int k = 0; k < PC_DM_COUNT; k++) {
		const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
		if (!(mi->flags & PC_DMF_MONO))
			continue;
		pc_eval_metrics a, b;
		pc_demosaic_opts ro = {0, true, 0};
		CHECK_EQ_INT(pc_eval_method(&t, (pc_demosaic_method)k, NULL, &a), 0);
		CHECK_EQ_INT(pc_eval_method(&t, (pc_demosaic_method)k, &ro, &b), 0);
		CHECK_NEAR(a.psnr_s0, b.psnr_s0, 0.01);
		CHECK(isfinite(a.psnr_dolp) && a.psnr_dolp > 10);
	}
	free(mos);
	free(e);
	pc_eval_truth_free(&t);
	/* bad truths: different sizes, different containers, too small */
	pc_view bad[4] = {v[0], v[1], v[2], v[3]};
	bad[2].width = W - 1;
	CHECK_EQ_INT(pc_eval_truth_from_views(bad, &t), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "90 deg") != NULL);
	bad[2] = v[2];
	bad[3].format = PC_FMT_MONO8;
	CHECK_EQ_INT(pc_eval_truth_from_views(bad, &t), PC_EINVAL);
	bad[3] = v[3];
	for (int c = 0; c < 4; c++)
		bad[c].width = 20;
	CHECK_EQ_INT(pc_eval_truth_from_views(bad, &t), PC_EINVAL);
	for (int c = 0; c < 4; c++)
		pc_view_free(&v[c]);
}

/* A truth of PW × PH (the measure's analytic values: docs/evaluation.md): a ramp times each
 * analyser's Malus factor (DoLP 0.4 at 30°; a ramp's high-pass is exactly 0) plus white variation:
 * sc·f common to the four images and sn·n_c of each its own. */
enum { PW = 200, PH = 180 };
static void pattern_truth(pc_eval_truth *t, double sc, double sn)
{
	memset(t, 0, sizeof *t);
	t->width = PW;
	t->height = PH;
	t->full_scale = 65535;
	t->format = PC_FMT_MONO16;
	double *f = malloc(sizeof(double) * PW * PH);
	for (int i = 0; i < PW * PH; i++)
		f[i] = nrand();
	for (int c = 0; c < 4; c++) {
		t->ch[c] = malloc(sizeof(double) * PW * PH);
		const double m = 0.5 * (1 + 0.4 * cos(2 * (c * M_PI / 4 - M_PI / 6)));
		for (int y = 0; y < PH; y++)
			for (int x = 0; x < PW; x++) {
				const int i = y * PW + x;
				t->ch[c][i] =
				    m * (0.2 + 0.001 * x + 0.0005 * y) + sc * f[i] + sn * nrand();
			}
	}
	free(f);
}

static void test_pattern(void)
{
	const double s = 0.002;
	struct {
		double sc, sn, rho;
	} cases[] = {{s, 0, 1}, {s, s, 0.5}, {0, s, 0}, {s, s / 2, 0.8}};
	for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
		pc_eval_truth t;
		pattern_truth(&t, cases[k].sc, cases[k].sn);
		pc_eval_pattern p;
		CHECK_EQ_INT(pc_eval_truth_pattern(&t, &p), 0);
		const double rho = cases[k].rho,
		             sd = sqrt(8.0 / 9 *
		                       (cases[k].sc * cases[k].sc + cases[k].sn * cases[k].sn));
		printf("pattern: share %.2f -> corr %.4f (want %.4f), one pixel apart %.4f (want "
		       "%.4f), RMS %.6f (want %.6f), %zu pixels\n",
		       rho, p.corr, rho, p.corr_shift, -rho / 6, p.std, sd, p.pixels);
		CHECK_NEAR(p.corr, rho, 0.04);
		/* −ρ/6 without the selection of the flattest pixels, which deepens it (their
		 * gradient shares samples with e one pixel apart): measured −0.21ρ */
		CHECK(p.corr_shift <= -rho / 8 + 0.03 && p.corr_shift >= -rho / 4 - 0.03);
		CHECK_REL(p.std, sd, 0.08);
		CHECK_EQ_INT(p.pixels, (size_t)(0.3 * (PW - 31) * (PH - 30)) + 1);
		pc_eval_truth_free(&t);
	}
	/* no variation: NaN; too small: NaN, not an error */
	pc_eval_truth t;
	pattern_truth(&t, 0, 0);
	pc_eval_pattern p;
	CHECK_EQ_INT(pc_eval_truth_pattern(&t, &p), 0);
	CHECK(isnan(p.corr) && isnan(p.corr_shift) && p.std < 1e-12);
	pc_eval_truth_free(&t);
	double base[4] = {0.1, 0.2, 0.3, 0.4};
	make_truth(&t, base); /* 40 x 36: constant */
	CHECK_EQ_INT(pc_eval_truth_pattern(&t, &p), 0);
	CHECK(isnan(p.corr) && p.pixels > 0);
	t.height = 32; /* under 2 borders + 4 */
	CHECK_EQ_INT(pc_eval_truth_pattern(&t, &p), 0);
	CHECK(isnan(p.corr) && isnan(p.std) && p.pixels == 0);
	pc_eval_truth_free(&t);
}

int main(void)
{
	test_pattern();
	test_hand_values();
	test_bilinear_protocol();
	return pc_test_finish("test_eval");
}
