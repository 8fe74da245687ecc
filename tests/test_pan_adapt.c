/* pan-adapt (core/demosaic_pan.c, docs/demosaicking.md Round 14): its new parts against
 * independent values.
 *  - The noise gain g (core/demosaic_noise.h) against the known gain of simulated noise: flat
 *    frames with Gaussian noise of variance g0·(L + F) per colour level L, and a grey frame of
 *    Poisson electrons times K (variance K·L, so the estimate is K·L/(L + F)). Frames of
 *    2048 × 1600, whose grid is every 9th sample (independent residuals, n ≈ 40 000): the
 *    relative standard error of the median of n χ²₁ values is 2.33/√n (1.2 %); tolerance four
 *    of them. A frame whose every 2×2 polarizer block has its own random Stokes vector (DoLP
 *    up to 1): the block estimate (Round 19) must find the noise's gain where the period
 *    estimate reads the texture as noise. And the selection against a sort of the same values
 *    (both estimates' formulas computed here, g their minimum), on a frame small enough that
 *    every interior sample is on the grid.
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
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x5eed14ada97ull
#include "xorshift.h"

#include "colour_front.h"

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

static size_t grid_sorted(const double *img, uint32_t w, uint32_t h, double fs, double *t);

/* The block estimate of demosaic_noise.h computed here from its formula on a double image of
 * the IMX250MYR layout ([90 45; 135 0] blocks from (0, 0)): every s-th 2×2 block, s the smallest
 * odd stride leaving at most PC_DM_NG_POINTS blocks; its median over m₁ (a sort, not the
 * library's selection) */
static double block_gain(const double *img, uint32_t w, uint32_t h, double fs)
{
	const double F4 = 4 * PC_DM_NG_FLOOR * fs;
	const uint32_t bw = w / 2, bh = h / 2;
	uint32_t s = 1;
	while ((size_t)((bw + s - 1) / s) * ((bh + s - 1) / s) > PC_DM_NG_POINTS)
		s += 2;
	double *t = malloc(sizeof(double) * (size_t)bw * bh);
	size_t n = 0;
	for (uint32_t by = 0; by < bh; by += s)
		for (uint32_t bx = 0; bx < bw; bx += s) {
			const double *r0 = img + (size_t)(2 * by) * w + 2 * bx, *r1 = r0 + w;
			/* r0: 90°, 45°; r1: 135°, 0°; in raster order, as the library sums */
			double r = r0[0] - r0[1] - r1[0] + r1[1];
			double l =
			    F4 + fmax(r0[0], 0) + fmax(r0[1], 0) + fmax(r1[0], 0) + fmax(r1[1], 0);
			t[n++] = r * r / l;
		}
	qsort(t, n, sizeof(double), cmp_d);
	const double g = t[n / 2] / PC_DM_NG_CHI1;
	free(t);
	return g;
}

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

	/* (3) texture the period estimate reads as noise: every 2×2 polarizer block its own Stokes
	 * vector (S0 uniform in 100..1500 DN, DoLP in 0..1, AoLP in 0..180°), its four samples
	 * Malus's I_θ = (S0 + S1 cos 2θ + S2 sin 2θ)/2 plus noise of variance g0·(I_θ + F). The
	 * block estimate (I0 + I90 − I45 − I135 cancels any Stokes vector) must find g0; the period
	 * estimate (grid_sorted) must not, or the check proves nothing. At the four phases of the
	 * colour blocks' origin (the mosaic shifted by (1, 0), (0, 1), (1, 1)): a block grid
	 * started at the wrong origin would mix two blocks' Stokes vectors and fail. Blocks on the
	 * grid: every 5th of about 1024 × 800, n = 205 · 160. */
	const uint32_t NBX = W / 2 + 1, NBY = H / 2 + 1;
	double *st = malloc(sizeof(double) * 3 * NBX * NBY);
	for (unsigned ph = 0; ph < 6; ph += ph == 1 ? 3 : 1) { /* 0, 1, 4, 5 */
		const pc_mosaic mp = pc_mosaic_shift(&m, ph % 4, ph / 4);
		unsigned ox = 0, oy = 0;
		CHECK_EQ_INT(pc_mosaic_color_origin(&mp, &ox, &oy), 0);
		for (size_t b = 0; b < (size_t)NBX * NBY; b++) {
			double s0 = 100 + 1400 * urand(), dolp = urand(), a = M_PI * urand();
			st[3 * b] = s0;
			st[3 * b + 1] = s0 * dolp * cos(2 * a);
			st[3 * b + 2] = s0 * dolp * sin(2 * a);
		}
		for (uint32_t y = 0; y < H; y++)
			for (uint32_t x = 0; x < W; x++) {
				/* the block of (x, y): blocks start at ox + 2i, oy + 2j (a partial
				 * one before them) */
				const size_t b =
				    (size_t)((y + 2 - oy) / 2) * NBX + (x + 2 - ox) / 2;
				const double th = 45.0 * pc_mosaic_channel(&mp, x, y) * M_PI / 180;
				const double l = (st[3 * b] + st[3 * b + 1] * cos(2 * th) +
				                  st[3 * b + 2] * sin(2 * th)) /
				                 2;
				img[(size_t)y * W + x] = l + sqrt(g0 * (l + F)) * nrand();
			}
		CHECK_EQ_INT(pc_dm_noise_gain_d(img, W, H, &mp, fs, &g), 0);
		double *tp = malloc(sizeof(double) * PC_DM_NG_POINTS);
		const size_t np = grid_sorted(img, W, H, fs, tp);
		const double gper = tp[np / 2] / (1.25 * PC_DM_NG_CHI1),
		             seb = 2.33 / sqrt(205.0 * 160.0);
		free(tp);
		printf(
		    "  noise gain, a random Stokes vector per block (blocks from %u,%u): %.5f "
		    "against %.5f (%+.2f %%, tolerance %.1f %%); the period estimate alone %.2f\n",
		    ox, oy, g, g0, 100 * (g / g0 - 1), 400 * seb, gper);
		CHECK(fabs(g / g0 - 1) <= 4 * seb);
		CHECK(gper > 10 * g0);
	}
	free(st);
	free(img);

	/* (4) the selection against a sort, every interior sample on the grid */
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
	const double gp = t[nt / 2] / (1.25 * PC_DM_NG_CHI1), gb = block_gain(small, w, h, fs);
	printf("  selection on a 64 x 48 frame: period %.9g, block %.9g, g %.9g\n", gp, gb, g);
	CHECK(g == fmin(gp, gb));
	/* no interior sample: 0 */
	CHECK_EQ_INT(pc_dm_noise_gain_d(small, 8, 8, &m, fs, &g), 0);
	CHECK(g == 0);
	free(small);
	free(t);
}

/* The values of the grid of demosaic_noise.h, computed here from the formula on a double image,
 * sorted: the median g of that image must be t[n/2]/(1.25·m₁) */
static size_t grid_sorted(const double *img, uint32_t w, uint32_t h, double fs, double *t)
{
	const uint32_t p = 4;
	uint32_t s = 1;
	while ((size_t)((w - 2 * p + s - 1) / s) * ((h - 2 * p + s - 1) / s) > PC_DM_NG_POINTS)
		s += 2;
	size_t n = 0;
	for (uint32_t y = p; y < h - p; y += s)
		for (uint32_t x = p; x < w - p; x += s) {
			double nb = (img[(size_t)y * w + x - p] + img[(size_t)y * w + x + p] +
			             img[(size_t)(y - p) * w + x] + img[(size_t)(y + p) * w + x]) /
			            4,
			       r = img[(size_t)y * w + x] - nb;
			t[n++] = r * r / (fmax(nb, 0) + PC_DM_NG_FLOOR * fs);
		}
	qsort(t, n, sizeof(double), cmp_d);
	return n;
}

/* Round 16a: the selection (a radix selection on the values' bit patterns, then the three-way
 * one) against a sort on full grids of 2448 × 2048 frames (n = 61 517): distinct values, values
 * with many ties (integer levels 0..3: thousands of equal t) and a flat frame (every t = 0).
 * And the fast path's threaded grid (pc_dm_noise_gain_in_mt, rows straight from 8-bit, 16-bit
 * and float inputs, a black level) equal to the reference's g bit for bit at 1, 2 and 3
 * threads and every instruction-set level, on two frame sizes. */
static void test_noise_select(void)
{
	const uint32_t W = 2448, H = 2048;
	const double fs = 4095;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *t = malloc(sizeof(double) * PC_DM_NG_POINTS);
	for (int kind = 0; kind < 3; kind++) {
		for (size_t i = 0; i < (size_t)W * H; i++)
			img[i] = kind == 0   ? 500 + 30 * nrand()
			         : kind == 1 ? (double)(int)(4 * urand())
			                     : 700;
		const size_t n = grid_sorted(img, W, H, fs, t);
		double g = -1;
		CHECK_EQ_INT(pc_dm_noise_gain_d(img, W, H, &m, fs, &g), 0);
		size_t ties = 0;
		for (size_t i = 0; i < n; i++)
			ties += t[i] == t[n / 2];
		printf("  selection, %s: n %zu, median %.9g (%zu equal to it), g %.9g\n",
		       kind == 0   ? "Gaussian"
		       : kind == 1 ? "levels 0..3"
		                   : "flat",
		       n, t[n / 2], ties, g);
		const double gb = block_gain(img, W, H, fs);
		CHECK(g == fmin(t[n / 2] / (1.25 * PC_DM_NG_CHI1), gb));
	}
	/* the threaded grid on the three input types, black 3.5, at every instruction-set level of
	 * this machine (the 16-bit grids' AVX-512 rows, eight points at a time: Round 28), on the
	 * full frame and on an odd one (1001 × 777: rows that end between eight-point groups), the
	 * 16-bit input once with g from the sample grid (k 1) and once over its full range with g
	 * from the block grid (k 3) */
	uint8_t *u8 = malloc((size_t)W * H);
	uint16_t *u16 = malloc(sizeof(uint16_t) * W * H);
	float *f32 = malloc(sizeof(float) * W * H);
	const pc_dm_type ty[4] = {PC_DMT_U8, PC_DMT_U16, PC_DMT_F32, PC_DMT_U16};
	const uint32_t sw[2] = {W, 1001}, sh[2] = {H, 777};
	for (int sz = 0; sz < 2; sz++)
		for (int k = 0; k < 4; k++) {
			const uint32_t w = sw[sz], h = sh[sz];
			for (size_t i = 0; i < (size_t)w * h; i++) {
				/* k 1: the samples of each 2×2 block alternately 300 apart, which
				 * the block estimate takes for signal (g from the sample grid
				 * alone) */
				const size_t x = i % w, y = i / w;
				u16[i] = k == 3 ? (uint16_t)(65535 * urand())
				                : (uint16_t)(1000 + (int)(200 * urand()) +
				                             300 * (int)((x ^ y) & 1));
				u8[i] = (uint8_t)(100 + (int)(40 * urand()));
				f32[i] = (float)(1000 + 50 * nrand());
			}
			const void *data = k == 0   ? (const void *)u8
			                   : k == 2 ? (const void *)f32
			                            : (const void *)u16;
			pc_dm_input in;
			memset(&in, 0, sizeof in);
			in.data = data;
			in.stride = w * pc_dm_type_bytes(ty[k]);
			in.type = ty[k];
			in.width = w;
			in.height = h;
			in.black = 3.5f;
			in.black_d = 3.5;
			for (size_t i = 0; i < (size_t)w * h; i++)
				img[i] = (k == 0 ? u8[i] : k == 2 ? (double)f32[i] : u16[i]) - 3.5;
			double gd = -1;
			CHECK_EQ_INT(pc_dm_noise_gain_d(img, w, h, &m, fs, &gd), 0);
			for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
				CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
				for (int th = 1; th <= 3; th++) {
					double gi = -2;
					CHECK_EQ_INT(pc_dm_noise_gain_in_mt(&in, &m, fs, th, &gi),
					             0);
					CHECK(gi == gd);
				}
			}
			pc_cpu_force(PC_CPU_LEVELS);
			printf(
			    "  threaded grid, %ux%u, input type %d%s: g %.9g (levels up to %s)\n",
			    w, h, (int)ty[k], k == 3 ? " full range" : "", gd,
			    pc_cpu_level_name(pc_cpu_supported()));
		}
	free(u8);
	free(u16);
	free(f32);
	free(img);
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
	colour_front_check(PC_DM_PAN_ADAPT, 34, 20);
	pc_demosaic_method md;
	CHECK_EQ_INT(pc_demosaic_method_from_name("pan-adapt", &md), 0);
	CHECK(md == PC_DM_PAN_ADAPT);
}

/* ---- a given noise gain (pc_pipeline_opts.noise_gain; docs/demosaicking.md, Round 15b) ----
 *
 * A colour-polarization scene with known truth for all twelve channels: S0 = s0(x, y) times a
 * smooth colour, a smooth linear polarization, and for textured frames sinusoidal gratings
 * (periods 6 to 16 px) over the right 5/16 of the frame. Each sample gets Gaussian noise of
 * variance g0·(L + F), L its truth and F = PC_DM_NG_FLOOR·FS: the model under which the
 * estimate is unbiased (demosaic_noise.h), so that "the true g" is g0. */
#define GG_FS 4095.0

static double gg_truth(unsigned q, uint32_t x, uint32_t y, uint32_t W, int textured)
{
	const double tau = 6.283185307179586;
	double s0 = 1200 + 500 * sin(tau * x / 310.0) * cos(tau * y / 270.0);
	if (textured && x >= W - W * 5 / 16) {
		double per = 6 + (y / 64) % 6 * 2, a = 0.3 * (double)((y / 64) % 4);
		s0 = 1200 + 700 * sin(tau * (x * cos(a) + y * sin(a)) / per);
	}
	const double col[3] = {0.8 + 0.2 * sin(x / 200.0), 1.0, 0.7 + 0.2 * cos(y / 180.0)};
	const double d = 0.3 + 0.2 * sin(x / 150.0), phi = y / 300.0;
	const unsigned k = q / 4, c = q % 4;
	return s0 * col[k] * (1 + d * cos(2 * (c * tau / 8 - phi))) / 4;
}

/* a float32 raw of the scene (opts.full_scale GG_FS) with the noise above */
static float *gg_raw(uint32_t W, uint32_t H, const pc_mosaic *m, double g0, int textured,
                     pc_view *v)
{
	float *r = malloc(sizeof(float) * W * H);
	const double F = PC_DM_NG_FLOOR * GG_FS;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			unsigned q = 4 * (unsigned)(pc_mosaic_color(m, x, y) - PC_CFA_R) +
			             pc_mosaic_channel(m, x, y);
			double L = gg_truth(q, x, y, W, textured);
			r[(size_t)y * W + x] = (float)(L + sqrt(g0 * (L + F)) * nrand());
		}
	*v = (pc_view){r, W, H, (size_t)W * sizeof(float), PC_FMT_FLOAT32};
	return r;
}

/* RMS error against the truth over all twelve channels, 8 pixels in from the borders */
static double gg_rmse(const pc_fplane *p, uint32_t W, uint32_t H, int textured)
{
	double s = 0;
	size_t n = 0;
	for (uint32_t y = 8; y < H - 8; y++)
		for (uint32_t x = 8; x < W - 8; x++)
			for (unsigned q = 0; q < 12; q++) {
				double e = fget(&p[q], x, y) - gg_truth(q, x, y, W, textured);
				s += e * e;
				n++;
			}
	return sqrt(s / (double)n);
}

static double rms_diff(const float *a, const float *b, size_t n)
{
	double s = 0;
	for (size_t i = 0; i < n; i++)
		s += ((double)a[i] - b[i]) * ((double)a[i] - b[i]);
	return sqrt(s / (double)n);
}

static void test_given_gain(void)
{
	const pc_mosaic m = pc_mosaic_imx250myr();
	const double g0 = 2.0;
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_PAN_ADAPT;
	o.mosaic = m;
	o.full_scale = GG_FS;
	/* (1) a large smooth frame: the estimate is within four standard errors of g0, and the
	 * outputs with g0 given and with the estimate differ by at most 1 % of their error
	 * against the truth (λ moves by at most λ(1 − λ)·|ε| ≤ |ε|/4 for a relative error ε of g,
	 * a few per mille here; stated tolerance 1 %) */
	{
		const uint32_t W = 1024, H = 1024;
		pc_view v;
		float *r = gg_raw(W, H, &m, g0, 0, &v);
		double g = -1;
		CHECK_EQ_INT(pc_demosaic_noise_gain(&v, &o, &g), 0);
		/* the grid: s = 5, 204 × 204 samples */
		const double se = 2.33 / sqrt(204.0 * 204.0);
		printf("  given gain, smooth 1024x1024: estimate %.4f against g0 %.4f (%+.2f %%, "
		       "tolerance %.1f %%)\n",
		       g, g0, 100 * (g / g0 - 1), 400 * se);
		CHECK(fabs(g / g0 - 1) <= 4 * se);
		pc_fplane a[12], b[12];
		float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
		o.noise_gain = 0;
		CHECK_EQ_INT(pc_demosaic_run(&v, &o, a, NULL), 0);
		o.noise_gain = g0;
		CHECK_EQ_INT(pc_demosaic_run(&v, &o, b, NULL), 0);
		double ea = gg_rmse(a, W, H, 0), eb = gg_rmse(b, W, H, 0),
		       d = rms_diff(ab, bb, (size_t)W * H * 12);
		printf("  given gain, smooth: RMSE estimated %.4f DN, g0 given %.4f DN; RMS "
		       "difference %.4f DN (%.3f %% of the error)\n",
		       ea, eb, d, 100 * d / eb);
		CHECK(d <= 0.01 * eb);
		CHECK(d > 0); /* the estimate is not g0 exactly: the two paths ran */
		free(ab);
		free(bb);
		free(r);
	}
	/* (2) a frame with gratings: g0 given gives a lower error against the truth than g0/10
	 * (too little shrinkage: noise) and 10·g0 (too much: the gratings flattened) */
	{
		const uint32_t W = 768, H = 768;
		pc_view v;
		float *r = gg_raw(W, H, &m, g0, 1, &v);
		pc_fplane p[12];
		float *pb = alloc_planes(W, H, p);
		const double gs[4] = {0, g0, g0 / 10, 10 * g0};
		double e[4];
		for (int i = 0; i < 4; i++) {
			o.noise_gain = gs[i];
			CHECK_EQ_INT(pc_demosaic_run(&v, &o, p, NULL), 0);
			e[i] = gg_rmse(p, W, H, 1);
		}
		double g = -1;
		CHECK_EQ_INT(pc_demosaic_noise_gain(&v, &o, &g), 0);
		printf("  given gain, gratings 768x768: RMSE estimated (g %.3f) %.4f, g0 %.4f, "
		       "g0/10 %.4f, 10 g0 %.4f DN\n",
		       g, e[0], e[1], e[2], e[3]);
		CHECK(e[1] < e[2]);
		CHECK(e[1] < e[3]);
		free(pb);
		free(r);
	}
}

/* The options' edges: the default (0, estimated) is the estimate given explicitly, bit for bit,
 * on the fast path and the reference; pc_demosaic_noise_gain is the estimator's value on the raw
 * minus black (also through the per-pixel correction); the legacy entry point passes the gain;
 * invalid gains are refused naming the field. */
static void test_given_gain_api(void)
{
	const uint32_t W = 130, H = 66;
	const pc_mosaic m = pc_mosaic_imx250myr();
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	double *img = malloc(sizeof(double) * W * H);
	const double black = 100;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			uint16_t s = (uint16_t)(700 + 300 * sin(x / 9.0) + 40 * nrand());
			PC_ROW(&raw, uint16_t, y)[x] = s;
			img[(size_t)y * W + x] = s - black;
		}
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_PAN_ADAPT;
	o.mosaic = m;
	o.black_level = black;
	o.full_scale = 4095; /* a 12-bit raw in 16 bits */
	double g = -1, gd = -2, gc = -3;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &g), 0);
	CHECK_EQ_INT(pc_dm_noise_gain_d(img, W, H, &m, 4095 - black, &gd), 0);
	printf("  pc_demosaic_noise_gain %.6f, the estimator on raw - black %.6f\n", g, gd);
	CHECK(g == gd && g > 0);
	/* through the per-pixel correction: dark = black everywhere, unit gains */
	float *dark = malloc(sizeof(float) * W * H), *gi = malloc(sizeof(float) * W * H);
	for (size_t i = 0; i < (size_t)W * H; i++) {
		dark[i] = (float)black;
		gi[i] = 1;
	}
	pc_pipeline_opts oc = o;
	oc.black_level = 0;
	oc.full_scale = 4095 - black; /* the same signal full scale */
	oc.dark = dark;
	oc.gain_inv = gi;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &oc, &gc), 0);
	CHECK(gc == g);
	/* the run through the correction reports the same estimate */
	{
		pc_fplane c[12];
		float *cb = alloc_planes(W, H, c);
		double used = -1;
		oc.noise_gain_used = &used;
		CHECK_EQ_INT(pc_demosaic_run(&raw, &oc, c, NULL), 0);
		CHECK(memcmp(&used, &gc, sizeof gc) == 0);
		/* a method without the flag leaves it as it was */
		oc.method = PC_DM_BAYER_FIRST;
		used = -1;
		CHECK_EQ_INT(pc_demosaic_run(&raw, &oc, c, NULL), 0);
		CHECK(used == -1);
		free(cb);
	}
	free(dark);
	free(gi);

	pc_fplane a[12], b[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
	const size_t nf = sizeof(float) * W * H * 12;
	colour_gain_check(&raw, o, g, a, ab, b, bb);
	o.reference = false;
	/* the legacy entry point (no black level, no noise gain there) is the estimate: the same
	 * samples minus black, the same signal full scale */
	pc_view raw0;
	CHECK_EQ_INT(pc_view_alloc(&raw0, PC_FMT_MONO16, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			PC_ROW(&raw0, uint16_t, y)
	[x] = (uint16_t)(PC_ROW(&raw, uint16_t, y)[x] - 100);
	pc_demosaic_opts lo = {0, false, 4095 - black};
	CHECK_EQ_INT(pc_demosaic(&raw0, &m, PC_DM_PAN_ADAPT, &lo, a), 0);
	o.noise_gain = 0;
	CHECK_EQ_INT(pc_demosaic_run(&raw, &o, b, NULL), 0);
	CHECK(memcmp(ab, bb, nf) == 0);
	/* invalid gains: PC_EINVAL naming the field */
	const double bad[4] = {-1, NAN, INFINITY, -INFINITY};
	for (int i = 0; i < 4; i++) {
		o.noise_gain = bad[i];
		CHECK_EQ_INT(pc_demosaic_run(&raw, &o, a, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "noise_gain") != NULL);
		CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &g), 0); /* not used there */
	}
	printf("  invalid noise gain: \"%s\"\n", pc_error_detail());
	/* the flag: pan-adapt, pan-guard (its base pan-adapt, Round 15b), pan-lean (Round 21) and
	 * the monochrome ratio-nr (Round 40: its noise model; test_noise_ptc) use a noise gain */
	for (int k = 0; k < PC_DM_COUNT; k++)
		CHECK(!(pc_demosaic_method_get((pc_demosaic_method)k)->flags & PC_DMF_NOISE_GAIN) ==
		      (k != PC_DM_PAN_ADAPT && k != PC_DM_PAN_GUARD && k != PC_DM_PAN_LEAN &&
		       k != PC_DM_RATIO_NR && k != PC_DM_RATIO_NR3));
	/* every flagged colour method has the paths that take the gain (the front door refuses
	 * one without them: it estimates the gain once and passes it) */
	for (int k = 0; k < PC_DM_COUNT; k++)
		if ((pc_demosaic_method_get((pc_demosaic_method)k)->flags & PC_DMF_NOISE_GAIN) &&
		    (pc_demosaic_method_get((pc_demosaic_method)k)->flags & PC_DMF_COLOR)) {
			const pc_dm_pan_fns *fn = pc_dm_pan_fns_get((pc_demosaic_method)k);
			CHECK(fn && fn->ref_g && fn->fast_g);
		}
	free(ab);
	free(bb);
	free(img);
	pc_view_free(&raw);
	pc_view_free(&raw0);
}

int main(void)
{
	test_noise_gain();
	test_limits();
	test_ramp();
	test_scale();
	test_front();
	colour_tiny_check(PC_DM_PAN_ADAPT); /* an 8 × 8 frame: finite, inside (0, full scale) */
	test_given_gain();
	test_given_gain_api();
	test_noise_select(); /* last: it draws from the random stream */
	return pc_test_finish("test_pan_adapt");
}
