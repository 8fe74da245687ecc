/* The robust rungs (docs/demosaicking.md, "Robustness"): the overshoot limiter's bound checked
 * against an independent computation of each channel's 5×5 sample range, fast paths and
 * double references alike; no false polarization in the dark beside a bright polarized object
 * (the failure the limiter fixes: eari-mlri rings there); the ratio method's offset keeps it
 * finite and within the local range on a near-black ramp with noise. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"

enum { W = 48, H = 40 };

static const pc_demosaic_method limited[] = {PC_DM_BICUBIC,  PC_DM_PPID,     PC_DM_RI,
                                             PC_DM_EARI,     PC_DM_RATIO,    PC_DM_EARI_ROBUST,
                                             PC_DM_RATIO_RI, PC_DM_RATIO_NR, PC_DM_RATIO_NR3};
#define N_LIM (sizeof limited / sizeof limited[0])

static uint64_t rng = 88172645463325252ull;
static double urand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) / 9007199254740992.0;
}

static int mirror(int i, int n)
{
	if (i < 0)
		i = -i;
	if (i >= n)
		i = 2 * n - 2 - i;
	return i;
}

/* every interpolated sample within [min, max] of its channel's raw samples in the 5×5 window
 * (a pixel's own channel is its measurement, which the limiter leaves alone: the residual
 * methods' float paths give it back to within rounding, test_demosaic checks that) */
static void check_bound(const pc_view *raw, const pc_mosaic *m, const float *buf, const char *what)
{
	int bad = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			for (unsigned c = 0; c < 4; c++) {
				if (pc_mosaic_channel(m, (uint32_t)x, (uint32_t)y) == c)
					continue;
				double lo = INFINITY, hi = -INFINITY;
				for (int dy = -2; dy <= 2; dy++)
					for (int dx = -2; dx <= 2; dx++) {
						int xx = mirror(x + dx, W), yy = mirror(y + dy, H);
						if (pc_mosaic_channel(m, (uint32_t)xx,
						                      (uint32_t)yy) != c)
							continue;
						double v = PC_ROW(raw, const uint16_t, yy)[xx];
						lo = fmin(lo, v);
						hi = fmax(hi, v);
					}
				double v = buf[(size_t)c * W * H + (size_t)y * W + x];
				if ((v < lo || v > hi) && bad < 4)
					fprintf(stderr, "  (%d,%d) ch %u: %.9g not in [%g, %g]\n",
					        x, y, c, v, lo, hi);
				bad += v < lo || v > hi;
			}
	if (bad)
		fprintf(stderr, "%s: %d samples outside their 5x5 range\n", what, bad);
	CHECK(bad == 0);
}

static void test_bound(void)
{
	pc_view raw;
	pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0);
	/* texture with hard edges: random blocks, random polarization */
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			PC_ROW(&raw, uint16_t, y)
	[x] = (uint16_t)lround(((x / 5 + y / 3) % 3 == 0 ? 2600 : 200) * (0.5 + urand()));
	float *buf = malloc(sizeof(float) * W * H * 4);
	pc_fplane p[4];
	pc_fplanes_separate(buf, W, H, 4, p);
	for (unsigned ph = 0; ph < 4; ph++) {
		pc_mosaic base = pc_mosaic_imx250mzr();
		pc_mosaic m = pc_mosaic_shift(&base, ph & 1, ph >> 1);
		for (size_t k = 0; k < N_LIM; k++)
			for (int ref = 0; ref < 2; ref++) {
				pc_demosaic_opts o = {0, ref != 0, 0};
				CHECK_EQ_INT(pc_demosaic(&raw, &m, limited[k], &o, p), 0);
				char what[96];
				snprintf(what, sizeof what, "%s%s phase %u",
				         pc_demosaic_method_get(limited[k])->name,
				         ref ? " (reference)" : "", ph);
				check_bound(&raw, &m, buf, what);
			}
	}
	free(buf);
	pc_view_free(&raw);
}

/* A bright, strongly polarized disc (DoLP 0.9) on black: every pixel further than 3 px from
 * the disc is exactly black in every channel with the limiter (its whole 5×5 window is), so
 * its DoLP is 0 as in the truth; eari-mlri, without it, rings into the black (the stress
 * suite's gloss scene), which this test also shows. */
static void test_dark_beside_bright(void)
{
	pc_view raw;
	pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0);
	pc_mosaic m = pc_mosaic_imx250mzr();
	const double th[4] = {0, M_PI / 4, M_PI / 2, 3 * M_PI / 4}, aolp = 0.4, dolp = 0.9;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double r = hypot(x - 20.3, y - 18.7);
			unsigned c = pc_mosaic_channel(&m, (uint32_t)x, (uint32_t)y);
			double s0 = r < 9 ? 7000 : 0;
			double v = 0.5 * s0 * (1 + dolp * cos(2 * (aolp - th[c])));
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)lround(fmin(v, 4095));
		}
	float *buf = malloc(sizeof(float) * W * H * 4);
	pc_fplane p[4];
	pc_fplanes_separate(buf, W, H, 4, p);
	const pc_demosaic_method ms[2] = {PC_DM_EARI_ROBUST, PC_DM_EARI_MLRI};
	for (int k = 0; k < 2; k++) {
		CHECK_EQ_INT(pc_demosaic(&raw, &m, ms[k], NULL, p), 0);
		size_t nonzero = 0, far = 0;
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				if (hypot(x - 20.3, y - 18.7) < 9 + 3 * M_SQRT2 + 1)
					continue;
				far++;
				for (int c = 0; c < 4; c++)
					nonzero += buf[(size_t)c * W * H + (size_t)y * W + x] != 0;
			}
		printf("%s: %zu of %zu far-dark channel samples non-zero\n",
		       pc_demosaic_method_get(ms[k])->name, nonzero, 4 * far);
		if (k == 0)
			CHECK(nonzero == 0);
		else
			CHECK(nonzero > 0); /* the failure the limiter exists for */
	}
	free(buf);
	pc_view_free(&raw);
}

/* ratio on a near-black noisy ramp (0..12 DN of 4095): finite, and within each channel's
 * 5×5 range (the offset ratio does not blow up small numbers). */
static void test_ratio_dark(void)
{
	pc_view raw;
	pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0);
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++)
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)lround(x / 4.0 * urand());
	float *buf = malloc(sizeof(float) * W * H * 4);
	pc_fplane p[4];
	pc_fplanes_separate(buf, W, H, 4, p);
	pc_mosaic m = pc_mosaic_imx250mzr();
	CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_RATIO, NULL, p), 0);
	int finite = 1;
	for (int i = 0; i < W * H * 4; i++)
		finite &= isfinite(buf[i]);
	CHECK(finite);
	check_bound(&raw, &m, buf, "ratio, near-black ramp");
	free(buf);
	pc_view_free(&raw);
}

int main(void)
{
	test_bound();
	test_dark_beside_bright();
	test_ratio_dark();
	return pc_test_finish("test_demosaic_robust");
}
