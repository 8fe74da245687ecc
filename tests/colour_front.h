/* Shared by the colour method tests (test_pan_adapt, test_pan_guard): a colour method through the
 * front door, its double reference against its default (fast) path on a small random texture.
 * Include after check.h, polarcam/demosaic.h and xorshift.h (it draws from the test's stream). */
#ifndef PC_TESTS_COLOUR_FRONT_H
#define PC_TESTS_COLOUR_FRONT_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/demosaic.h"
#include "polarcam/mosaic.h"

/* method md on a W × H 12-bit IMX250MYR raw of 600..1400 DN (uniform): CHECKs that both calls
 * succeed and that max |default − reference| <= 1e-5 of the 12-bit full scale (the fast paths'
 * tolerance), prints it, and returns it (-1 when a call failed) */
static double colour_front_check(pc_demosaic_method md, uint32_t W, uint32_t H)
{
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)(600 + 800 * urand());
	size_t n = (size_t)W * H * 12;
	float *ab = malloc(sizeof(float) * n), *bb = malloc(sizeof(float) * n);
	pc_fplane a[12], b[12];
	pc_fplanes_separate(ab, W, H, 12, a);
	pc_fplanes_separate(bb, W, H, 12, b);
	pc_mosaic m = pc_mosaic_imx250myr();
	pc_demosaic_opts ref = {0, true, 0};
	int ra = pc_demosaic(&raw, &m, md, &ref, a), rb = pc_demosaic(&raw, &m, md, NULL, b);
	CHECK_EQ_INT(ra, 0);
	CHECK_EQ_INT(rb, 0);
	double worst = -1;
	if (ra == 0 && rb == 0) {
		worst = 0;
		for (size_t i = 0; i < n; i++)
			worst = fmax(worst, fabs(ab[i] - bb[i]));
		printf("  front door %ux%u: max |default - reference| %.3g DN\n", W, H, worst);
		CHECK(worst <= 1e-5 * 4095);
	}
	free(ab);
	free(bb);
	pc_view_free(&raw);
	return worst;
}

/* method md (reference) on the smallest frame, 8 × 8 (the block grids and their windows mostly
 * mirrored): CHECKs that every output is finite and, on this mid-level texture, inside (0, full
 * scale) */
static void colour_tiny_check(pc_demosaic_method md)
{
	pc_mosaic m = pc_mosaic_imx250myr();
	pc_demosaic_opts ref = {0, true, 0};
	pc_view tiny;
	CHECK_EQ_INT(pc_view_alloc(&tiny, PC_FMT_MONO16, 8, 8, 0), 0);
	for (uint32_t y = 0; y < 8; y++)
		for (uint32_t x = 0; x < 8; x++)
			PC_ROW(&tiny, uint16_t, y)[x] = (uint16_t)(600 + 800 * urand());
	pc_fplane t[12];
	float *tb = malloc(sizeof(float) * 8 * 8 * 12);
	pc_fplanes_separate(tb, 8, 8, 12, t);
	CHECK_EQ_INT(pc_demosaic(&tiny, &m, md, &ref, t), 0);
	int finite = 1;
	for (size_t i = 0; i < 8 * 8 * 12; i++)
		finite &= isfinite(tb[i]) && tb[i] > 0 && tb[i] < 4095;
	CHECK(finite);
	free(tb);
	pc_view_free(&tiny);
}

/* a method with PC_DMF_NOISE_GAIN through pc_demosaic_run (o set up for it, o.noise_gain
 * ignored): on the reference and on the fast path, the gain g the method would estimate, given,
 * reproduces the default bit for bit, and 10·g changes the outputs (not vacuous); the gain the
 * run reports (noise_gain_used) is g bit for bit by default and 10·g as given; then a given
 * gain of 3.5 on the fast path within 1e-5 of the 12-bit full scale of the reference with it.
 * a, b: two sets of twelve planes over ab, bb (W × H each). */
static void colour_gain_check(const pc_view *raw, pc_pipeline_opts o, double g, const pc_fplane *a,
                              const float *ab, const pc_fplane *b, const float *bb)
{
	const size_t n = (size_t)raw->width * raw->height * 12;
	for (int ref = 0; ref < 2; ref++) {
		double used = -1, used0;
		o.reference = ref;
		o.noise_gain = 0;
		o.noise_gain_used = &used;
		CHECK_EQ_INT(pc_demosaic_run(raw, &o, a, NULL), 0);
		CHECK(memcmp(&used, &g, sizeof g) == 0); /* the estimate, bit for bit */
		used0 = used;
		o.noise_gain_used = NULL;
		o.noise_gain = g;
		CHECK_EQ_INT(pc_demosaic_run(raw, &o, b, NULL), 0);
		CHECK(memcmp(ab, bb, sizeof(float) * n) == 0);
		o.noise_gain = 10 * g;
		o.noise_gain_used = &used;
		CHECK_EQ_INT(pc_demosaic_run(raw, &o, b, NULL), 0);
		CHECK(used == 10 * g); /* a given gain, reported as given */
		o.noise_gain_used = NULL;
		printf("  reported gain (%s): %.17g by default (pc_demosaic_noise_gain's %.17g), "
		       "%.17g when %.17g is given\n",
		       ref ? "reference" : "fast path", used0, g, used, 10 * g);
		double d = 0;
		for (size_t i = 0; i < n; i++)
			d = fmax(d, fabs(ab[i] - bb[i]));
		printf("  given gain (%s): the estimate %.4f given = default bit for bit; 10x it "
		       "moves outputs by up to %.3g DN\n",
		       ref ? "reference" : "fast path", g, d);
		CHECK(d > 0);
	}
	o.noise_gain = 3.5;
	o.reference = true;
	CHECK_EQ_INT(pc_demosaic_run(raw, &o, a, NULL), 0);
	o.reference = false;
	CHECK_EQ_INT(pc_demosaic_run(raw, &o, b, NULL), 0);
	double worst = 0;
	for (size_t i = 0; i < n; i++)
		worst = fmax(worst, fabs(ab[i] - bb[i]));
	printf("  given gain 3.5: max |fast - reference| %.3g DN\n", worst);
	CHECK(worst <= 1e-5 * 4095);
}

#endif
