/* pan-lean (core/demosaic_pan.c, docs/demosaicking.md Rounds 21 and 24): its double reference
 * against independent values.
 *  - A uniform colour and polarization is exact, with and without noise gain (every ratio and
 *    every tent is then the truth, whatever the weights).
 *  - The noise limit: with g → ∞ (1e16) the side factors are flat and the level is the block
 *    window's mean (of the 3 × 3 blocks' levels, Round 27), so every output but the own sample
 *    is that mean times the normalised 2D tent (4 − |dx|)(4 − |dy|) of the channel's ratios in
 *    the 7 × 7 window, less δ (computed here from the definition: P0's filter, the ratios, the
 *    window). With g = 0 the outputs are far from it on the same texture (not vacuous).
 *  - Green bars on magenta (period 4.5 px, 10°; the bars alias on the red and blue lattices and
 *    P0 barely sees them), noise-free: red's and blue's errors at most 0.85× pan-side's (whose
 *    ratio step carries the own sample's green detail into them; measured 0.76–0.78×) and
 *    within 1 % of bayer-first's (measured +0.3 to +0.6 %: the plain tents' level).
 *  - A flat colour field with noise of variance g·(L + F) (given g = 2): every colour's error
 *    at most 0.8× pan-side's (measured 0.58–0.73×) and within 1 % of bayer-first's (measured
 *    red −2.8 %, green −3.9 %, blue −2.7 %; with Round 24's 6 × 6 pixel window −2.7, −4.7 and
 *    −2.7 %): the shrunk level and the cored own sample keep the tents' averaging.
 *  - The front door finds it by name and runs the reference and the float fast path
 *    (pan_band's fifth mode in demosaic_pan.c) within 1e-5 of full scale of each other
 * (test_demosaic's test_pan_fast runs it on four scenes, sixteen phases and four sizes); a given
 * noise gain behaves as for the other noise-gain methods (colour_gain_check); on an 8 × 8 frame
 * every output is finite; a negative or non-finite noise gain is refused. Checked by mutation
 * (2026-12-05, Round 24): the level's shrinkage removed (P_s = P̃) fails 10 of 102 checks, the
 * own colour's coring removed (c_s = 0) fails 8. */
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

/* P0 at (x, y) (interior): the separable filter (1, 2, 2, 2, 1)/8 in x and y of the raw
 * (core/demosaic_pan.c, ppi0) */
static double p0_at(const double *img, uint32_t w, int x, int y)
{
	static const double k[5] = {1, 2, 2, 2, 1};
	double s = 0;
	for (int j = -2; j <= 2; j++)
		for (int i = -2; i <= 2; i++)
			s += k[i + 2] * k[j + 2] * img[(size_t)(y + j) * w + (size_t)(x + i)];
	return s / 64;
}

/* the limit g → ∞ of pan-lean's output of channel q at (x, y) (interior), from its definition
 * directly: flat side factors, so R_q is the normalised 2D tent (4 − |dx|)(4 − |dy|) over the
 * channel's ratios ρ = (max(x, 0) + δ)/(max(P0, 0) + δ) within ±3; λ = s = 0, so the level is
 * the mean m of P̃ = max(P0, 0) + δ at the even corners of the 3 × 3 blocks centred on the
 * pixel's 2 × 2 block (b + (2i, 2j), i, j ∈ {−1, 0, 1}); the output m·R_q − δ */
static double noise_limit(const double *img, const pc_mosaic *m, uint32_t w, double delta,
                          unsigned q, int x, int y)
{
	double s = 0, t = 0;
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			if (chan_of(m, (uint32_t)(x + dx), (uint32_t)(y + dy)) != q)
				continue;
			const double wt = (4 - abs(dx)) * (4 - abs(dy)),
			             v = img[(size_t)(y + dy) * w + (size_t)(x + dx)];
			s += wt * (fmax(v, 0) + delta) /
			     (fmax(p0_at(img, w, x + dx, y + dy), 0) + delta);
			t += wt;
		}
	double lv = 0;
	for (int j = -2; j <= 2; j += 2)
		for (int i = -2; i <= 2; i += 2)
			lv += fmax(p0_at(img, w, (x & ~1) + i, (y & ~1) + j), 0) + delta;
	return lv / 9 * s / t - delta;
}

static void test_noise_limit(void)
{
	const uint32_t W = 48, H = 40;
	const size_t np = (size_t)W * H, n = np * 12;
	const double delta = 0.01 * 4095;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * np), *truth = malloc(sizeof(double) * n);
	pc_fplane o[12];
	float *ob = alloc_planes(W, H, o);
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		make_raw(f_grey, &m, W, H, img, truth);
		double dlim[2] = {0, 0};
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
						const double t = noise_limit(img, &m, W, delta, q,
						                             (int)x, (int)y);
						dlim[gi] = fmax(dlim[gi], fabs(ob[q * np + i] - t));
					}
				}
		}
		printf(
		    "  grey texture, phase %2u: max |out - the noise limit| %.3g DN with g = 1e16 "
		    "(%.3g with g = 0)\n",
		    ph, dlim[1], dlim[0]);
		CHECK(dlim[1] < 1e-3);
		CHECK(dlim[0] > 10);
	}
	free(ob);
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
