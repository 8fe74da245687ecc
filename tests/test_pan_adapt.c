/* pan-adapt (core/demosaic_pan.c, docs/demosaicking.md Round 14): its new parts against
 * independent values.
 *  - The noise gain g (core/demosaic_noise.h) against the known gain of simulated noise: flat
 *    frames with Gaussian noise of variance g0·(L + F) per colour level L, and a grey frame of
 *    Poisson electrons times K (variance K·L, so the estimate is K·L/(L + F)). Frames of
 *    2048 × 1600, whose grid is every 9th sample (independent residuals, n ≈ 40 000): the
 *    relative standard error of the median of n χ²₁ values is 2.33/√n (1.2 %); tolerance four
 *    of them. And the selection against a sort of the same values, computed here from the
 *    formula, on a frame small enough that every interior sample is on the grid.
 *  - The shrinkage's limits: g = 0 (and c = 0) give pan-side's ratio step exactly, and with
 *    pan-side's fixed range scale pan-side itself, bit for bit (pc_dm_pan_side_ref, a separate
 *    implementation); on a flat noisy grey field the outputs stay unbiased (mean within 3 DN of
 *    the level) while the S0 noise falls with c, and at λ → 0 (c = 10¹²) it matches Round 13d's
 *    prediction from the linearised weights (S0 variance 0.463/0.248/0.463 σ² for R/G/B) within
 *    15 % (about three standard errors of a variance over the field's ~10⁴ correlated pixels).
 *  - A grey linear ramp under a uniform polarization exact as δ → 0 (full scale 10⁻⁶): the ratios
 *    are constant, the ratio step's level is the PPI, and the PPI's window mean equals it on a
 *    linear ramp, so the shrinkage (any g) returns it; within 10⁻⁶ relative, 12 pixels in.
 *  - Scale invariance of the relative range scale: with δ → 0 and g scaled with the raw, raw × s
 *    gives outputs × s (within 10⁻⁶ relative: the float outputs' rounding); pan-side's fixed e
 *    under the same scaling moves them by more than 10⁻³ (the check is not vacuous). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_noise.h"
#include "../core/demosaic_pan.h"
#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x5eed14ada97ull
#include "xorshift.h"

static float *alloc_planes(uint32_t w, uint32_t h, pc_fplane *p)
{
	float *buf = malloc(sizeof(float) * (size_t)w * h * 12);
	pc_fplanes_separate(buf, w, h, 12, p);
	return buf;
}

static double fget(const pc_fplane *p, uint32_t x, uint32_t y)
{
	return p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
}

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* ---- the noise gain ---- */

static void test_noise_gain(void)
{
	const uint32_t W = 2048, H = 1600;
	const double fs = 4095, F = PC_DM_NG_FLOOR * fs;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	/* (1) Gaussian, colour levels R/G/B 300/600/200 DN, variance g0·(L + F) */
	const double lev[3] = {300, 600, 200}, g0 = 0.9;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			unsigned k = pc_mosaic_color(&m, x, y) - PC_CFA_R;
			img[(size_t)y * W + x] = lev[k] + sqrt(g0 * (lev[k] + F)) * nrand();
		}
	double g = 0;
	CHECK_EQ_INT(pc_dm_noise_gain_d(img, W, H, &m, fs, &g), 0);
	/* the grid: s = 9, ((2048 − 8)/9 rounded up)·((1600 − 8)/9 rounded up) */
	const double n = 227.0 * 177.0, se = 2.33 / sqrt(n);
	printf("  noise gain, Gaussian colour field: %.5f against %.5f (%+.2f %%, tolerance %.1f "
	       "%%)\n",
	       g, g0, 100 * (g / g0 - 1), 400 * se);
	CHECK(fabs(g / g0 - 1) <= 4 * se);
	/* (2) Poisson: grey, λ = 500 electrons, K = 4 DN per electron, by inversion of the CDF */
	const double lam = 500, K = 4;
	const int kmax = 800;
	double *cdf = malloc(sizeof(double) * (kmax + 1)), pk = exp(-lam), acc = 0;
	for (int k = 0; k <= kmax; k++) {
		acc += pk;
		cdf[k] = acc;
		pk *= lam / (k + 1);
	}
	for (size_t i = 0; i < (size_t)W * H; i++) {
		double u = urand() * acc;
		int lo = 0, hi = kmax;
		while (lo < hi) {
			int mid = (lo + hi) / 2;
			if (cdf[mid] < u)
				lo = mid + 1;
			else
				hi = mid;
		}
		img[i] = K * lo;
	}
	free(cdf);
	CHECK_EQ_INT(pc_dm_noise_gain_d(img, W, H, &m, fs, &g), 0);
	const double want = K * K * lam / (K * lam + F);
	printf("  noise gain, Poisson grey field: %.5f against K·L/(L + F) = %.5f (%+.2f %%)\n", g,
	       want, 100 * (g / want - 1));
	CHECK(fabs(g / want - 1) <= 4 * se);
	free(img);

	/* (3) the selection against a sort, every interior sample on the grid */
	const uint32_t w = 64, h = 48;
	double *small = malloc(sizeof(double) * w * h), *t = malloc(sizeof(double) * w * h);
	for (size_t i = 0; i < (size_t)w * h; i++)
		small[i] = 800 + 400 * urand();
	size_t nt = 0;
	for (uint32_t y = 4; y < h - 4; y++)
		for (uint32_t x = 4; x < w - 4; x++) {
			double nb = (small[y * w + x - 4] + small[y * w + x + 4] +
			             small[(y - 4) * w + x] + small[(y + 4) * w + x]) /
			            4,
			       r = small[y * w + x] - nb;
			t[nt++] = r * r / (fmax(nb, 0) + F);
		}
	qsort(t, nt, sizeof(double), cmp_d);
	CHECK_EQ_INT(pc_dm_noise_gain_d(small, w, h, &m, fs, &g), 0);
	CHECK(g == t[nt / 2] / (1.25 * PC_DM_NG_CHI1));
	/* no interior sample: 0 */
	CHECK_EQ_INT(pc_dm_noise_gain_d(small, 8, 8, &m, fs, &g), 0);
	CHECK(g == 0);
	free(small);
	free(t);
}

/* ---- the shrinkage's limits ---- */

static void random_raw(double *img, uint32_t w, uint32_t h)
{
	for (size_t i = 0; i < (size_t)w * h; i++)
		img[i] = 600 + 800 * urand();
}

static void test_limits(void)
{
	const uint32_t W = 48, H = 40;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	pc_fplane a[12], b[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
	const size_t bytes = sizeof(float) * W * H * 12;
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		random_raw(img, W, H);
		pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
		/* pan-side's fixed e, g = 0: pan-side */
		p.e_fs = 0.04;
		p.ke = 0;
		p.g = 0;
		CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 4095, &p, a), 0);
		CHECK_EQ_INT(pc_dm_pan_side_ref(img, W, H, &m, 4095, b), 0);
		CHECK(memcmp(ab, bb, bytes) == 0);
		/* the relative e: g = 0 and c = 0 (g given) alike, the own sample kept */
		p = pc_dm_pan_adapt_defaults();
		p.g = 0;
		CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 4095, &p, a), 0);
		p.g = 5;
		p.c = 0;
		CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 4095, &p, b), 0);
		CHECK(memcmp(ab, bb, bytes) == 0);
		int keeps = 1;
		for (uint32_t y = 0; y < H; y++)
			for (uint32_t x = 0; x < W; x++) {
				unsigned q = 4 * (pc_mosaic_color(&m, x, y) - PC_CFA_R) +
				             pc_mosaic_channel(&m, x, y);
				keeps &= fget(&a[q], x, y) == (float)img[y * W + x];
			}
		CHECK(keeps);
	}
	free(ab);
	free(bb);
	free(img);

	/* a flat noisy grey field: unbiased, and the S0 noise falls with c */
	const uint32_t N = 128, B = 12;
	const double level = 1000, sigma = 20;
	pc_mosaic m = base;
	img = malloc(sizeof(double) * N * N);
	for (size_t i = 0; i < (size_t)N * N; i++)
		img[i] = level + sigma * nrand();
	ab = alloc_planes(N, N, a);
	const double cs[3] = {0, PC_DM_PAN_ADAPT_C, 1e12};
	double var[3][3], pred[3] = {0.463, 0.248, 0.463};
	for (int ci = 0; ci < 3; ci++) {
		pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
		p.c = cs[ci];
		CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, N, N, &m, 4095, &p, a), 0);
		double worst_bias = 0;
		for (unsigned q = 0; q < 12; q++) {
			double s = 0;
			for (uint32_t y = B; y < N - B; y++)
				for (uint32_t x = B; x < N - B; x++)
					s += fget(&a[q], x, y);
			worst_bias =
			    fmax(worst_bias, fabs(s / ((N - 2 * B) * (N - 2 * B)) - level));
		}
		for (int k = 0; k < 3; k++) {
			double s = 0, ss = 0, n = 0;
			for (uint32_t y = B; y < N - B; y++)
				for (uint32_t x = B; x < N - B; x++) {
					double s0 = 0;
					for (unsigned c = 0; c < 4; c++)
						s0 += fget(&a[4 * k + c], x, y) / 2;
					s += s0;
					ss += s0 * s0;
					n++;
				}
			var[ci][k] = (ss / n - (s / n) * (s / n)) / (sigma * sigma);
		}
		printf("  flat grey field, c = %g: S0 variance R/G/B %.3f/%.3f/%.3f sigma^2, "
		       "largest |mean - level| %.3f DN\n",
		       cs[ci], var[ci][0], var[ci][1], var[ci][2], worst_bias);
		CHECK(worst_bias <= 3);
	}
	for (int k = 0; k < 3; k++) {
		CHECK(var[1][k] < var[0][k]);
		CHECK(var[2][k] < var[1][k]);
		CHECK(fabs(var[2][k] / pred[k] - 1) <= 0.15);
	}
	free(ab);
	free(img);
}

/* ---- the grey ramp ---- */

static void test_ramp(void)
{
	const uint32_t W = 64, H = 48, B = 12;
	const pc_mosaic base = pc_mosaic_imx250myr();
	const double pr = 0.55, tr = 0.6;
	double *img = malloc(sizeof(double) * W * H), worst = 0;
	pc_fplane a[12];
	float *ab = alloc_planes(W, H, a);
	for (unsigned ph = 0; ph < 16; ph++) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		for (uint32_t y = 0; y < H; y++)
			for (uint32_t x = 0; x < W; x++) {
				unsigned c = pc_mosaic_channel(&m, x, y);
				img[y * W + x] = 0.8 * (700 + 13 * x + 9 * y) *
				                 (1 + pr * cos(2 * (c * M_PI / 4 - tr)));
			}
		for (int gi = 0; gi < 2; gi++) {
			pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
			p.g = gi ? 1e3 : -1; /* estimated (≈ 0 on the ramp), or a large one */
			CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 1e-6, &p, a), 0);
			for (unsigned q = 0; q < 12; q++)
				for (uint32_t y = B; y < H - B; y++)
					for (uint32_t x = B; x < W - B; x++) {
						double want =
						    0.8 * (700 + 13 * x + 9 * y) *
						    (1 + pr * cos(2 * (q % 4 * M_PI / 4 - tr)));
						worst = fmax(worst,
						             fabs(fget(&a[q], x, y) - want) / want);
					}
		}
	}
	printf(
	    "  grey ramp (delta -> 0), 16 phases, g estimated and 1e3: max relative error %.2g\n",
	    worst);
	CHECK(worst <= 1e-6);
	free(ab);
	free(img);
}

/* ---- scale invariance of the relative range scale ---- */

static double scaled_dev(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                         pc_dm_pan_adapt_params p, double s)
{
	double *sc = malloc(sizeof(double) * w * h), dev = 0;
	for (size_t i = 0; i < (size_t)w * h; i++)
		sc[i] = s * img[i];
	pc_fplane a[12], b[12];
	float *ab = alloc_planes(w, h, a), *bb = alloc_planes(w, h, b);
	CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, w, h, m, 4095, &p, a), 0);
	p.g *= s;
	CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(sc, w, h, m, 4095, &p, b), 0);
	for (size_t i = 0; i < (size_t)w * h * 12; i++)
		dev = fmax(dev, fabs(bb[i] - s * ab[i]) / fabs(s * ab[i]));
	free(ab);
	free(bb);
	free(sc);
	return dev;
}

static void test_scale(void)
{
	const uint32_t W = 48, H = 40;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	/* a texture with edges: random levels on 3×5 blocks, and a little noise */
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			img[y * W + x] = 0;
	for (uint32_t by = 0; by < H; by += 5)
		for (uint32_t bx = 0; bx < W; bx += 3) {
			double v = 200 + 3000 * urand();
			for (uint32_t y = by; y < by + 5 && y < H; y++)
				for (uint32_t x = bx; x < bx + 3 && x < W; x++)
					img[y * W + x] = v * (0.95 + 0.1 * urand());
		}
	const double s = 1.0 / 16;
	pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
	p.d_fs = 1e-12;
	p.g = 0.5;
	double dev = scaled_dev(img, W, H, &base, p, s);
	p.e_fs = 0.04;
	p.ke = 0;
	double dev_side = scaled_dev(img, W, H, &base, p, s);
	printf("  raw x 1/16 (delta -> 0, g x 1/16): outputs x 1/16 within %.2g relative "
	       "(pan-side's fixed e: %.2g)\n",
	       dev, dev_side);
	CHECK(dev <= 1e-6);
	CHECK(dev_side > 1e-3);
	free(img);
}

/* pan-adapt through the front door: reference and default path on a small frame */
static void test_front(void)
{
	const uint32_t W = 34, H = 20;
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)(600 + 800 * urand());
	pc_fplane a[12], b[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
	pc_mosaic m = pc_mosaic_imx250myr();
	pc_demosaic_opts ref = {0, true, 0};
	CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_PAN_ADAPT, &ref, a), 0);
	CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_PAN_ADAPT, NULL, b), 0);
	double worst = 0;
	for (size_t i = 0; i < (size_t)W * H * 12; i++)
		worst = fmax(worst, fabs(ab[i] - bb[i]));
	printf("  front door 34x20: max |default - reference| %.3g DN\n", worst);
	CHECK(worst <= 1e-5 * 4095);
	pc_demosaic_method md;
	CHECK_EQ_INT(pc_demosaic_method_from_name("pan-adapt", &md), 0);
	CHECK(md == PC_DM_PAN_ADAPT);
	free(ab);
	free(bb);
	pc_view_free(&raw);
}

int main(void)
{
	test_noise_gain();
	test_limits();
	test_ramp();
	test_scale();
	test_front();
	return pc_test_finish("test_pan_adapt");
}
