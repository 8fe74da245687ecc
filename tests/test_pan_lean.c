/* pan-lean (core/demosaic_pan.c, docs/demosaicking.md Round 21): its double reference against
 * independent values.
 *  - A uniform colour and polarization is exact, with and without noise gain (every ratio and
 *    every tent is then the truth, whatever the weights).
 *  - The noise limit: with g → ∞ (1e16) the side factors are flat and every blend picks the plain
 *    tents, so every output but the own sample is the normalised 2D tent (4 − |dx|)(4 − |dy|)
 *    over the channel's samples in the 7 × 7 window (computed here directly), and red and blue
 *    are bayer-first's (its double reference; Round 17). With g = 0 the outputs are far from the
 *    tents on the same texture (not vacuous).
 *  - Green bars on magenta (period 4.5 px, 10°; the bars alias on the red and blue lattices and
 *    P0 barely sees them), noise-free: red's and blue's errors at most 0.85× pan-side's (whose
 *    ratio step carries the own sample's green detail into them; measured 0.76–0.78×) and
 *    within 1 % of bayer-first's (measured +0.3 to +0.6 %: the plain tents' level).
 *  - A flat colour field with noise of variance g·(L + F) (given g = 2): every colour's error
 *    at most 0.8× pan-side's (measured 0.57–0.75×) and within 1 % of bayer-first's (measured
 *    red +0.4 %, blue +0.2 %, green −4.9 %): the blends keep the tents' averaging.
 *  - The front door finds it by name and runs the reference and the float fast path
 *    (pan_band's fifth mode in demosaic_pan.c) within 1e-5 of full scale of each other
 * (test_demosaic's test_pan_fast runs it on four scenes, sixteen phases and four sizes); a given
 * noise gain behaves as for the other noise-gain methods (colour_gain_check); on an 8 × 8 frame
 * every output is finite; a negative or non-finite noise gain is refused. Checked by mutation
 * (2026-12-05): the own sample's level for every colour (pan-side's ratio step) fails 19 of 86
 * checks (the bars and the noisy field); the blend towards the plain tents removed (a = 1) fails 12
 * (the noise limit and the noisy field). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_color.h"
#include "../core/demosaic_noise.h"
#include "../core/demosaic_pan.h"
#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x5eed21ea0ull
#include "xorshift.h"

#include "colour_front.h"
#include "colour_truth.h"

static unsigned chan_of(const pc_mosaic *m, uint32_t x, uint32_t y)
{
	return 4 * (pc_mosaic_color(m, x, y) - PC_CFA_R) + pc_mosaic_channel(m, x, y);
}

static void test_uniform(void)
{
	const uint32_t W = 40, H = 36;
	const size_t n = (size_t)W * H * 12;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *truth = malloc(sizeof(double) * n);
	pc_fplane o[12];
	float *ob = alloc_planes(W, H, o);
	for (unsigned ph = 0; ph < 16; ph += 5)
		for (int gi = 0; gi < 2; gi++) {
			pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
			make_raw(f_uniform, &m, W, H, img, truth);
			CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, W, H, &m, 4095, gi ? 5.0 : 0.0, o),
			             0);
			double e = max_rel_error(ob, truth, n);
			printf("  uniform, phase %2u, g %g: max relative error %.3g\n", ph,
			       gi ? 5.0 : 0.0, e);
			CHECK(e < 1e-6);
		}
	free(ob);
	free(img);
	free(truth);
}

/* the normalised 2D tent over channel q's samples within ±3 of (x, y) (interior) */
static double plain_tent(const double *img, const pc_mosaic *m, uint32_t w, unsigned q, int x,
                         int y)
{
	double s = 0, t = 0;
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			if (chan_of(m, (uint32_t)(x + dx), (uint32_t)(y + dy)) != q)
				continue;
			double wt = (4 - abs(dx)) * (4 - abs(dy));
			s += wt * img[(size_t)(y + dy) * w + (size_t)(x + dx)];
			t += wt;
		}
	return s / t;
}

static void test_noise_limit(void)
{
	const uint32_t W = 48, H = 40;
	const size_t np = (size_t)W * H, n = np * 12;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * np), *truth = malloc(sizeof(double) * n);
	pc_fplane o[12], b[12];
	float *ob = alloc_planes(W, H, o), *bb = alloc_planes(W, H, b);
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		make_raw(f_grey, &m, W, H, img, truth);
		CHECK_EQ_INT(pc_dm_bayer_first_ref(img, W, H, &m, PC_DM_BILINEAR, 4095, b), 0);
		double dtent[2] = {0, 0}, dbf = 0;
		for (int gi = 0; gi < 2; gi++) {
			CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, W, H, &m, 4095, gi ? 1e16 : 0, o),
			             0);
			for (uint32_t y = 8; y < H - 8; y++)
				for (uint32_t x = 8; x < W - 8; x++) {
					const unsigned own = chan_of(&m, x, y);
					const size_t i = (size_t)y * W + x;
					for (unsigned q = 0; q < 12; q++) {
						if (q == own)
							continue;
						const double t =
						    plain_tent(img, &m, W, q, (int)x, (int)y);
						dtent[gi] =
						    fmax(dtent[gi], fabs(ob[q * np + i] - t));
						if (gi && q / 4 != 1)
							dbf = fmax(dbf, fabs(ob[q * np + i] -
							                     bb[q * np + i]));
					}
				}
		}
		printf("  grey texture, phase %2u: max |out - plain tents| %.3g DN with g = 1e16 "
		       "(%.3g with g = 0); red and blue against bayer-first's %.3g DN\n",
		       ph, dtent[1], dtent[0], dbf);
		CHECK(dtent[1] < 1e-3);
		CHECK(dbf < 1e-3);
		CHECK(dtent[0] > 10);
	}
	free(ob);
	free(bb);
	free(img);
	free(truth);
}

/* pan-lean (noise gain g), pan-side and bayer-first on img: colours 0, kstep, ... (< 3): each
 * colour's rms error over the interior, pan-lean's below side_bound times pan-side's and within
 * 1 % of bayer-first's */
static void against_side_bf(const char *what, const double *img, const double *truth,
                            const pc_mosaic *m, uint32_t W, uint32_t H, double g, unsigned kstep,
                            double side_bound)
{
	pc_fplane l[12], s[12], b[12];
	float *lb = alloc_planes(W, H, l), *sb = alloc_planes(W, H, s), *bb = alloc_planes(W, H, b);
	CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, W, H, m, 4095, g, l), 0);
	CHECK_EQ_INT(pc_dm_pan_side_ref(img, W, H, m, 4095, s), 0);
	CHECK_EQ_INT(pc_dm_bayer_first_ref(img, W, H, m, PC_DM_BILINEAR, 4095, b), 0);
	static const char *const name[3] = {"red", "green", "blue"};
	for (unsigned k = 0; k < 3; k += kstep) {
		double el = rms_colour(lb, truth, k, W, H, 8),
		       es = rms_colour(sb, truth, k, W, H, 8),
		       eb = rms_colour(bb, truth, k, W, H, 8);
		printf("  %s, %s: rms error pan-lean %.2f, pan-side %.2f, bayer-first %.2f DN\n",
		       what, name[k], el, es, eb);
		CHECK(el < side_bound * es);
		CHECK(el < 1.01 * eb);
	}
	free(lb);
	free(sb);
	free(bb);
}

static void test_hue_pair(void)
{
	const uint32_t W = 96, H = 80;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *truth = malloc(sizeof(double) * W * H * 12);
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		make_raw(f_gm, &m, W, H, img, truth);
		char what[64];
		snprintf(what, sizeof what, "green/magenta bars, phase %2u", ph);
		against_side_bf(what, img, truth, &m, W, H, 0, 2, 0.85);
	}
	free(img);
	free(truth);
}

static void test_noisy_flat(void)
{
	const uint32_t W = 96, H = 80;
	const double g = 2.0, F = PC_DM_NG_FLOOR * 4095;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *truth = malloc(sizeof(double) * W * H * 12);
	make_raw(f_uniform, &m, W, H, img, truth);
	for (size_t i = 0; i < (size_t)W * H; i++)
		img[i] += sqrt(g * (img[i] + F)) * nrand();
	against_side_bf("flat noisy field (g 2)", img, truth, &m, W, H, g, 1, 0.8);
	free(img);
	free(truth);
}

static void test_front(void)
{
	pc_demosaic_method md;
	CHECK_EQ_INT(pc_demosaic_method_from_name("pan-lean", &md), 0);
	CHECK(md == PC_DM_PAN_LEAN);
	CHECK(pc_demosaic_method_get(PC_DM_PAN_LEAN)->flags & PC_DMF_NOISE_GAIN);
	colour_front_check(PC_DM_PAN_LEAN, 34, 20);
	/* a given noise gain: the estimate given reproduces the default bit for bit on both paths,
	 * 10x it moves the outputs, the reported gain; the fast path with a given gain against the
	 * reference with it */
	const uint32_t W = 66, H = 50;
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++) {
		uint16_t *row = PC_ROW(&raw, uint16_t, y);
		for (uint32_t x = 0; x < W; x++)
			row[x] = (uint16_t)(700 + 300 * sin(x / 9.0) + 40 * nrand());
	}
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = PC_DM_PAN_LEAN;
	po.mosaic = pc_mosaic_imx250myr();
	po.full_scale = 4095;
	double g = -1;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &po, &g), 0);
	CHECK(g > 0);
	pc_fplane a[12], b[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
	colour_gain_check(&raw, po, g, a, ab, b, bb);
	free(ab);
	free(bb);
	pc_view_free(&raw);
	colour_tiny_check(PC_DM_PAN_LEAN);
	const pc_mosaic m = pc_mosaic_imx250myr();
	double img[64];
	for (int i = 0; i < 64; i++)
		img[i] = 1000;
	pc_fplane o[12];
	float *ob = alloc_planes(8, 8, o);
	CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, 8, 8, &m, 4095, -1, o), PC_EINVAL);
	CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, 8, 8, &m, 4095, NAN, o), PC_EINVAL);
	CHECK_EQ_INT(pc_dm_pan_lean_ref_g(img, 8, 8, &m, 4095, INFINITY, o), PC_EINVAL);
	free(ob);
}

int main(void)
{
	(void)colour_gain_check;  /* colour_front.h's, for the methods with a noise gain */
	(void)colour_front_check; /* ... and for those with a fast path */
	test_uniform();
	test_noise_limit();
	test_hue_pair();
	test_noisy_flat();
	test_front();
	return pc_test_finish("test_pan_lean");
}
