/* pan-guard (core/demosaic_pan_guard.c, docs/demosaicking.md Round 15): its guard against
 * independent values.
 *  - Forced weights: every weight 1 gives the base (pan-adapt's double reference) bit for bit in
 *    both modes; every weight 0 bayer-first's double reference through the front door bit for
 *    bit in mode 0, and in mode 1 bayer-first's analyser means (within 1e-5 relative) with the
 *    base's modulation (v + δ)/(s + δ) (within 1e-5).
 *  - The blend is convex: on a random texture (where the two estimates differ almost
 *    everywhere) every colour's analyser mean lies between the two estimates', within the float
 *    rounding of the blend (weights outside [0, 1] or not finite would leave that interval).
 *  - Where the two estimates coincide (a uniform colour and polarization: both exact) the output
 *    equals them.
 *  - A grey, hue-free texture (smooth, periods 11–23 px, uniform polarization) where the ratio
 *    model holds: the guard keeps the base (effective weight, the least-squares W of
 *    out − I_b on I_p − I_b, at least 0.8 for every colour) and its error stays within 10 % of
 *    the base's, below bayer-first's.
 *  - A hue grating below the red and blue lattices' Nyquist period (red/lime stripes of period
 *    6 px, high P0 contrast: Round 13c's `curved` case) against its known truth, where the base
 *    is worse than bayer-first: the guard moves red towards bayer-first (effective weight at
 *    most 0.75; measured 0.51–0.59, since the leave-one-out errors of both models are large
 *    there and differ by little), and for every colour its error is at most the base's (so at
 *    most the worse of the two estimates').
 *  - The front door runs it (reference and default path, while the fast path is the
 *    reference) and finds it by name; on an 8 × 8 frame every output is finite.
 *  - A given noise gain (pc_pipeline_opts.noise_gain, docs/demosaicking.md Round 15b) reaches
 *    the base: with forced weights 1 and g given the output is pan-adapt's reference with that
 *    g, bit for bit, and another g changes it; through the front door the default (estimated)
 *    equals the estimate given explicitly (pc_demosaic_noise_gain's value) bit for bit, on the
 *    reference and the fast path, 10× the estimate changes the outputs, and the fast path with
 *    a given gain is within 1e-5 of full scale of the reference with it; a g that is not finite
 *    is refused; the method carries the flag PC_DMF_NOISE_GAIN. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_pan.h"
#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x5eed15a8a2dull
#include "xorshift.h"

#include "colour_front.h"
#include "colour_truth.h"

/* red/lime stripes along x, period 6 px (3 + 3) */
static double f_grating(unsigned k, unsigned c, double x, double y)
{
	(void)y;
	static const double red[3] = {1.0, 0.2, 0.1}, lime[3] = {0.2, 1.0, 0.1};
	int ph = ((int)x % 6) < 3;
	return 2000 * (ph ? red[k] : lime[k]) * pol(c);
}

/* error and effective weight per colour, on the colour's analyser mean (S0/2: what the guard
 * blends in both modes) over the interior (B from the borders) */
typedef struct colour_stats {
	double rms_out[3], rms_p[3], rms_b[3], weff[3];
} colour_stats;

static double amean(const float *v, unsigned k, size_t i, size_t n)
{
	double s = 0;
	for (unsigned c = 0; c < 4; c++)
		s += v[(size_t)(4 * k + c) * n + i];
	return s / 4;
}

static double amean_d(const double *v, unsigned k, size_t i, size_t n)
{
	double s = 0;
	for (unsigned c = 0; c < 4; c++)
		s += v[(size_t)(4 * k + c) * n + i];
	return s / 4;
}

static colour_stats stats(const float *out, const float *ip, const float *ib, const double *truth,
                          uint32_t w, uint32_t h, uint32_t B)
{
	colour_stats s;
	const size_t np = (size_t)w * h;
	for (unsigned k = 0; k < 3; k++) {
		double eo = 0, ep = 0, eb = 0, num = 0, den = 0, n = 0;
		for (uint32_t y = B; y < h - B; y++)
			for (uint32_t x = B; x < w - B; x++) {
				size_t i = (size_t)y * w + x;
				double t = amean_d(truth, k, i, np), o = amean(out, k, i, np),
				       vp = amean(ip, k, i, np), vb = amean(ib, k, i, np);
				eo += (o - t) * (o - t);
				ep += (vp - t) * (vp - t);
				eb += (vb - t) * (vb - t);
				num += (o - vb) * (vp - vb);
				den += (vp - vb) * (vp - vb);
				n++;
			}
		s.rms_out[k] = sqrt(eo / n);
		s.rms_p[k] = sqrt(ep / n);
		s.rms_b[k] = sqrt(eb / n);
		s.weff[k] = den > 0 ? num / den : 1;
	}
	return s;
}

/* runs the guard, its base (weights forced to 1) and bayer-first (forced to 0) */
static void run3(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, float *out,
                 float *ip, float *ib)
{
	pc_fplane a[12], b[12], c[12];
	pc_fplanes_separate(out, w, h, 12, a);
	pc_fplanes_separate(ip, w, h, 12, b);
	pc_fplanes_separate(ib, w, h, 12, c);
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, w, h, m, 4095, &p, a), 0);
	p.force = 1;
	CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, w, h, m, 4095, &p, b), 0);
	p.force = 0;
	p.mode = 0;
	CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, w, h, m, 4095, &p, c), 0);
}

/* forced weights: the base and bayer-first bit for bit */
static void test_forced(void)
{
	const uint32_t W = 48, H = 40;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	pc_fplane a[12], b[12], c[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b), *cb = alloc_planes(W, H, c);
	const size_t bytes = sizeof(float) * W * H * 12;
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		for (uint32_t y = 0; y < H; y++)
			for (uint32_t x = 0; x < W; x++) {
				uint16_t v = (uint16_t)(300 + 3000 * urand());
				PC_ROW(&raw, uint16_t, y)[x] = v;
				img[y * W + x] = v;
			}
		pc_demosaic_opts ref = {0, true, 0};
		CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_BAYER_FIRST, &ref, c), 0);
		for (int mode = 0; mode < 2; mode++) {
			pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
			p.mode = mode;
			p.force = 1;
			CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, 4095, &p, a), 0);
			if (PC_DM_PAN_GUARD_BASE)
				CHECK_EQ_INT(pc_dm_pan_adapt_ref(img, W, H, &m, 4095, b), 0);
			else
				CHECK_EQ_INT(pc_dm_pan_side_ref(img, W, H, &m, 4095, b), 0);
			CHECK(memcmp(ab, bb, bytes) == 0);
			p.force = 0;
			CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, 4095, &p, a), 0);
			if (mode == 0) { /* bayer-first */
				CHECK(memcmp(ab, cb, bytes) == 0);
				continue;
			}
			/* mode 1: bayer-first's analyser means with the base's modulation */
			double dm = 0, dr = 0, dl = PC_DM_PAN_ADAPT_DFS * 4095;
			const size_t np = (size_t)W * H;
			for (unsigned k = 0; k < 3; k++)
				for (size_t i = 0; i < np; i++) {
					double so = amean(ab, k, i, np), sb = amean(cb, k, i, np),
					       sp = amean(bb, k, i, np);
					dm = fmax(dm, fabs(so - sb) / sb);
					for (unsigned ca = 0; ca < 4; ca++) {
						size_t j = (size_t)(4 * k + ca) * np + i;
						dr = fmax(dr, fabs((ab[j] + dl) / (so + dl) -
						                   (bb[j] + dl) / (sp + dl)));
					}
				}
			printf(
			    "  mode 1, weights 0, phase %2u: analyser means vs bayer-first's %.2g "
			    "relative, modulation vs the base's %.2g\n",
			    ph, dm, dr);
			CHECK(dm <= 1e-5);
			CHECK(dr <= 1e-5);
		}
	}
	free(ab);
	free(bb);
	free(cb);
	free(img);
	pc_view_free(&raw);
}

/* convexity on a random texture, and equality where both estimates are exact */
static void test_convex(void)
{
	const uint32_t W = 64, H = 48;
	const size_t n = (size_t)W * H * 12;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *truth = malloc(sizeof(double) * n);
	float *out = malloc(sizeof(float) * n), *ip = malloc(sizeof(float) * n),
	      *ib = malloc(sizeof(float) * n);
	for (size_t i = 0; i < (size_t)W * H; i++)
		img[i] = fmax(1800 + 700 * nrand(), 0);
	run3(img, W, H, &m, out, ip, ib);
	size_t outside = 0, differ = 0;
	const size_t np = (size_t)W * H;
	for (unsigned k = 0; k < 3; k++)
		for (size_t i = 0; i < np; i++) {
			double vp = amean(ip, k, i, np), vb = amean(ib, k, i, np),
			       vo = amean(out, k, i, np);
			double lo = fmin(vp, vb), hi = fmax(vp, vb), tol = 1e-6 * (fabs(hi) + 1);
			outside += !(vo >= lo - tol && vo <= hi + tol);
			differ += hi - lo > 1;
		}
	printf("  random texture: %zu of %zu analyser means where the estimates differ by > 1 DN, "
	       "%zu outside them\n",
	       differ, 3 * np, outside);
	CHECK(differ > 3 * np / 2);
	CHECK(outside == 0);
	/* uniform colour and polarization: both estimates exact, so the output */
	make_raw(f_uniform, &m, W, H, img, truth);
	run3(img, W, H, &m, out, ip, ib);
	const double worst = max_rel_error(out, truth, n);
	printf("  uniform colour and polarization: max relative error %.2g\n", worst);
	CHECK(worst <= 1e-6);
	free(img);
	free(truth);
	free(out);
	free(ip);
	free(ib);
}

/* the grey texture keeps the base; the sub-Nyquist hue grating moves towards bayer-first */
static void test_guard(void)
{
	const uint32_t W = 96, H = 64, B = 16;
	const size_t n = (size_t)W * H * 12;
	const pc_mosaic base = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H), *truth = malloc(sizeof(double) * n);
	float *out = malloc(sizeof(float) * n), *ip = malloc(sizeof(float) * n),
	      *ib = malloc(sizeof(float) * n);
	static const char *const cn = "RGB";
	for (unsigned ph = 0; ph < 16; ph += 5) {
		pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
		make_raw(f_grey, &m, W, H, img, truth);
		run3(img, W, H, &m, out, ip, ib);
		colour_stats s = stats(out, ip, ib, truth, W, H, B);
		for (unsigned k = 0; k < 3; k++) {
			printf(
			    "  grey texture, phase %2u, %c: rms guard %.2f, base %.2f, bayer-first "
			    "%.2f DN, effective weight %.3f\n",
			    ph, cn[k], s.rms_out[k], s.rms_p[k], s.rms_b[k], s.weff[k]);
			CHECK(s.weff[k] >= 0.8);
			CHECK(s.rms_out[k] <= 1.1 * s.rms_p[k]);
			CHECK(s.rms_out[k] < s.rms_b[k]);
		}
		make_raw(f_grating, &m, W, H, img, truth);
		run3(img, W, H, &m, out, ip, ib);
		s = stats(out, ip, ib, truth, W, H, B);
		for (unsigned k = 0; k < 3; k++) {
			printf(
			    "  red/lime grating (6 px), phase %2u, %c: rms guard %.2f, base %.2f, "
			    "bayer-first %.2f DN, effective weight %.3f\n",
			    ph, cn[k], s.rms_out[k], s.rms_p[k], s.rms_b[k], s.weff[k]);
			CHECK(s.rms_out[k] <= fmax(s.rms_p[k], s.rms_b[k]));
			CHECK(s.rms_out[k] <= s.rms_p[k]);
			if (k == 0)
				CHECK(s.weff[k] <= 0.75);
		}
	}
	free(img);
	free(truth);
	free(out);
	free(ip);
	free(ib);
}

/* pan-guard through the front door: reference and default path on a small frame */
static void test_front(void)
{
	colour_front_check(PC_DM_PAN_GUARD, 34, 20);
	colour_tiny_check(PC_DM_PAN_GUARD);
	pc_demosaic_method md;
	CHECK_EQ_INT(pc_demosaic_method_from_name("pan-guard", &md), 0);
	CHECK(md == PC_DM_PAN_GUARD);
}

/* a given noise gain: the base's, the front door's routing, bit-identical defaults */
static void test_given_gain(void)
{
	const uint32_t W = 130, H = 66;
	const pc_mosaic m = pc_mosaic_imx250myr();
	const size_t nf = sizeof(float) * W * H * 12;
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
	double *img = malloc(sizeof(double) * W * H);
	const double black = 100;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			uint16_t s = (uint16_t)(700 + 300 * sin(x / 9.0) +
			                        200 * sin(y / 2.7 + x / 3.1) + 40 * nrand());
			PC_ROW(&raw, uint16_t, y)[x] = s;
			img[(size_t)y * W + x] = s - black;
		}
	pc_fplane a[12], b[12];
	float *ab = alloc_planes(W, H, a), *bb = alloc_planes(W, H, b);
	/* (1) the base with forced weights 1: pan-adapt's reference with the same g, bit for bit
	 * (a g the estimate is not: 3.5 and 35) */
	for (int i = 0; i < 2; i++) {
		pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
		p.force = 1;
		p.g = i ? 35 : 3.5;
		CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, 4095 - black, &p, a), 0);
		pc_dm_pan_adapt_params pa = pc_dm_pan_adapt_defaults();
		pa.g = p.g;
		CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 4095 - black, &pa, b), 0);
		CHECK(memcmp(ab, bb, nf) == 0);
		if (i) { /* not vacuous: 3.5's base differs from 35's */
			pa.g = 3.5;
			CHECK_EQ_INT(pc_dm_pan_adapt_ref_with(img, W, H, &m, 4095 - black, &pa, b),
			             0);
			CHECK(memcmp(ab, bb, nf) != 0);
		}
	}
	/* a gain that is not finite: refused */
	{
		pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
		p.g = NAN;
		CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, 4095 - black, &p, a),
		             PC_EINVAL);
		p.g = INFINITY;
		CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, 4095 - black, &p, a),
		             PC_EINVAL);
	}
	/* (2) the front door */
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_PAN_GUARD;
	o.mosaic = m;
	o.black_level = black;
	o.full_scale = 4095; /* a 12-bit raw in 16 bits */
	double g = -1;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &g), 0);
	CHECK(g > 0);
	colour_gain_check(&raw, o, g, a, ab, b, bb);
	CHECK(pc_demosaic_method_get(PC_DM_PAN_GUARD)->flags & PC_DMF_NOISE_GAIN);
	free(ab);
	free(bb);
	free(img);
	pc_view_free(&raw);
}

int main(void)
{
	test_forced();
	test_convex();
	test_guard();
	test_front();
	test_given_gain();
	return pc_test_finish("test_pan_guard");
}
