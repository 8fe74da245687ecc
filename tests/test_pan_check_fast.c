/* pan-check's float fast path (core/demosaic_pan_check_fast.c on pan-guard's,
 * core/demosaic_pan_guard_fast.c; docs/demosaicking.md "Round 18a: pan-check's fast path")
 * against its double reference pc_dm_pan_check_ref_with (core/demosaic_pan_check.c), at every
 * instruction set the machine has:
 *  - every output within TOL = 1e-5 of full scale of the reference (0.04 DN at 12 bits;
 *    pan-guard's fast path's tolerance, on the same float-against-double error sums through
 *    the exponent γ = 8, which multiplies a relative rounding difference of the sums by up to
 *    γ/4 in a weight; Round 18a gives the measured worst, 3.3e-6), on inputs: a smooth coloured
 * polarized scene, a texture, a hue grating finer than the red and blue lattices' Nyquist period,
 * the smooth scene with noise, dim at 1/64, clipping at full scale, dark patches next to bright
 * ones, and a uniform noisy field; sizes 8 × 8, 10 × 14, 34 × 20, 64 × 48 and 150 × 36 (borders,
 * sizes not a multiple of the period 4, small frames; the front door refuses odd sizes); four
 * mosaic phases, with the method's parameters; its variants (no gate, no noise term, r = 0 and
 * 2, γ = 2.5) on every input at 34 × 20 and 40 × 300 and two phases (each reference is
 * computed once and every instruction set's fast path compared with it);
 *  - the check is not idle: on the grating the reference moves some output by more than 1 %
 *    of full scale away from its base, and its gate is on;
 *  - three threads give one thread's outputs bit for bit (one band, or five at 40 × 300),
 *    interleaved outputs the planar ones;
 *  - forced weights 1 give pan-side's fast path bit for bit (six sizes, one and three
 *    threads, a frame of two of pan-side's column strips);
 *  - the front door runs the fast path (its outputs bit for bit). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_pan.h"
#include "../core/demosaic_pan_check.h"
#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x18ac4ec0fa57ull
#include "xorshift.h"

#include "colour_truth.h"

#define FS  4095.0
#define TOL 1e-5
#define NK  8

/* channel (k, c) at (x, y) of input kind 0 smooth, 1 texture, 2 hue grating, 3 noisy, 4 dim,
 * 5 clipping, 6 dark patches next to bright, 7 uniform noisy field */
static double scene(int kind, unsigned k, unsigned c, double x, double y)
{
	switch (kind) {
	case 1:
		return (700 + 500 * sin(0.45 * x + 0.2 * k) * cos(0.37 * y - 0.3 * k) +
		        300 * sin(0.11 * (x + y))) *
		       pol(c);
	case 2: {
		const double s = 0.5 + 0.5 * cos(2 * M_PI * x / 6);
		const double lv[3] = {300 + 1800 * s, 300 + 1800 * (1 - s), 250};
		return lv[k] * pol(c);
	}
	case 5:
		return (2500 + 2500 * sin(0.21 * x + 0.5 * k) * cos(0.17 * y)) * pol(c);
	case 6: {
		const int dark = ((int)(x / 7) + (int)(y / 5)) & 1;
		return (dark ? 12 + 3 * k : 3600 - 400 * k) * pol(c);
	}
	case 7:
		return 1200 * pol(c);
	default: {
		const double l = (900 + 400 * sin(0.05 * x + 0.3 * k) * cos(0.04 * y + 0.2 * k)) *
		                 (1 + 0.3 * k) * pol(c);
		return kind == 4 ? l / 64 : l;
	}
	}
}

static void make_raw_kind(int kind, const pc_mosaic *m, uint32_t w, uint32_t h, double *img,
                          float *imgf)
{
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			unsigned k = pc_mosaic_color(m, x, y) - PC_CFA_R,
			         c = pc_mosaic_channel(m, x, y);
			double v = scene(kind, k, c, x, y);
			if (kind == 3 || kind == 7)
				v += (kind == 3 ? 23 : 30) * nrand();
			v = fmin(fmax(round(v), 0), FS);
			img[(size_t)y * w + x] = v;
			imgf[(size_t)y * w + x] = (float)v;
		}
}

static double fget(const pc_fplane *p, uint32_t x, uint32_t y)
{
	return p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
}

/* every configuration's reference once, then every instruction-set level's fast path against
 * it (levels 0..L, pc_cpu_supported) */
static void test_against_reference(int L)
{
	static const int sizes[6][2] = {{8, 8}, {10, 14}, {34, 20}, {64, 48}, {150, 36}, {40, 300}};
	/* variants: 0 the method, 1 no gate, 2 no noise term, 3 r = 0, 4 r = 2 and γ = 2.5 */
	enum { NV = 5, NL = PC_CPU_AVX512 + 1 };
	const pc_mosaic base = pc_mosaic_imx250myr();
	double worst[NL][NK] = {{0}}, moved = 0, gated = 0;
	int same[NL];
	for (int l = 0; l < NL; l++)
		same[l] = 1;
	for (int z = 0; z < 6; z++) {
		const uint32_t W = (uint32_t)sizes[z][0], H = (uint32_t)sizes[z][1];
		double *img = malloc(sizeof(double) * W * H);
		float *imgf = malloc(sizeof(float) * W * H);
		pc_fplane r[12], f[12], t3[12], il[12], b[12];
		float *rb = alloc_planes(W, H, r), *fb = alloc_planes(W, H, f),
		      *tb = alloc_planes(W, H, t3), *bb = alloc_planes(W, H, b),
		      *ib = malloc(sizeof(float) * W * H * 12);
		pc_fplanes_interleaved(ib, W, 12, il);
		for (unsigned ph = 0; ph < 16; ph += 5) {
			const pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
			for (int kind = 0; kind < NK; kind++) {
				make_raw_kind(kind, &m, W, H, img, imgf);
				const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
				for (int s = 0; s < NV; s++) {
					/* the variants on two sizes (one with threads' bands) at
					 * two phases; the method everywhere (CI time) */
					if (s > 0 && ((z != 2 && z != 5) || (ph != 0 && ph != 10)))
						continue;
					pc_dm_pan_check_params p = pc_dm_pan_check_defaults();
					if (s == 1)
						p.kappa = 0;
					if (s == 2)
						p.noise = p.noise_green = 0;
					if (s == 3)
						p.r = 0;
					if (s == 4) {
						p.r = 2;
						p.gamma = 2.5;
					}
					CHECK_EQ_INT(
					    pc_dm_pan_check_ref_with(img, W, H, &m, FS, &p, r), 0);
					if (kind == 2 && s <= 1) {
						/* the base (s 0) and the check without the gate
						 * (s 1): how far the reference moves from each */
						pc_dm_pan_check_params pb = p;
						if (s == 0)
							pb.kappa = 0;
						else
							pb.force = 1;
						CHECK_EQ_INT(pc_dm_pan_check_ref_with(img, W, H, &m,
						                                      FS, &pb, b),
						             0);
						for (unsigned q = 0; q < 12; q++)
							for (uint32_t y = 0; y < H; y++)
								for (uint32_t x = 0; x < W; x++) {
									const double d =
									    fabs(
									        fget(&r[q], x, y) -
									        fget(&b[q], x, y)) /
									    FS;
									if (s == 0)
										gated =
										    fmax(gated, d);
									else
										moved =
										    fmax(moved, d);
								}
					}
					for (int l = 0; l <= L; l++) {
						const pc_cpu_level level = (pc_cpu_level)l;
						CHECK_EQ_INT(pc_dm_pan_check_fast_with(
						                 &in, &m, FS, 1, level, &p, f),
						             0);
						CHECK_EQ_INT(pc_dm_pan_check_fast_with(
						                 &in, &m, FS, 3, level, &p, t3),
						             0);
						CHECK_EQ_INT(pc_dm_pan_check_fast_with(
						                 &in, &m, FS, 3, level, &p, il),
						             0);
						for (unsigned q = 0; q < 12; q++)
							for (uint32_t y = 0; y < H; y++)
								for (uint32_t x = 0; x < W; x++) {
									const double v = fget(&f[q],
									                      x, y),
									             e = fget(&r[q],
									                      x, y);
									worst[l][kind] =
									    fmax(worst[l][kind],
									         fabs(v - e) / FS);
									same[l] &=
									    v == fget(&t3[q], x,
									              y) &&
									    v == fget(&il[q], x, y);
								}
					}
				}
			}
		}
		free(img);
		free(imgf);
		free(rb);
		free(fb);
		free(tb);
		free(bb);
		free(ib);
	}
	for (int l = 0; l <= L; l++) {
		printf(
		    "  %s: max |fast - reference| of full scale: %.3g smooth, %.3g texture, %.3g "
		    "hue grating, %.3g noisy, %.3g dim, %.3g clipping, %.3g dark by bright, %.3g "
		    "uniform noisy\n",
		    pc_cpu_level_name((pc_cpu_level)l), worst[l][0], worst[l][1], worst[l][2],
		    worst[l][3], worst[l][4], worst[l][5], worst[l][6], worst[l][7]);
		CHECK(same[l]);
		for (int k = 0; k < NK; k++)
			CHECK(worst[l][k] <= TOL);
	}
	printf(
	    "  on the grating the check moves outputs by up to %.3g of full scale from the base, "
	    "the gate by up to %.3g\n",
	    moved, gated);
	CHECK(moved > 0.01);
	CHECK(gated > 0);
}

/* forced weights 1: pan-side's fast path bit for bit (1·I_p + 0·I_b, no gate), at six sizes and
 * phases, one and three threads (one band, or several at 40 × 300), and 4112 columns, where
 * pan-side's fast path takes two column strips */
static void forced_base_at(pc_cpu_level level, uint32_t W, uint32_t H, int threads, int phase)
{
	const pc_mosaic m0 = pc_mosaic_imx250myr();
	const pc_mosaic m = pc_mosaic_shift(&m0, (unsigned)phase, (unsigned)(3 * phase % 4));
	double *img = malloc(sizeof(double) * W * H);
	float *imgf = malloc(sizeof(float) * W * H);
	pc_fplane f[12], b[12];
	float *fb = alloc_planes(W, H, f), *bb = alloc_planes(W, H, b);
	make_raw_kind(1, &m, W, H, img, imgf);
	const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
	pc_dm_pan_check_params p = pc_dm_pan_check_defaults();
	p.force = 1;
	CHECK_EQ_INT(pc_dm_pan_check_fast_with(&in, &m, FS, threads, level, &p, f), 0);
	CHECK_EQ_INT(pc_dm_pan_side_fast(&in, &m, FS, 1, level, b), 0);
	int eq = 1;
	for (unsigned q = 0; q < 12; q++)
		for (uint32_t y = 0; y < H; y++)
			for (uint32_t x = 0; x < W; x++)
				eq &= fget(&f[q], x, y) == fget(&b[q], x, y);
	CHECK(eq);
	free(img);
	free(imgf);
	free(fb);
	free(bb);
}

static void test_forced_base(pc_cpu_level level)
{
	static const uint32_t sz[][2] = {{64, 48},  {10, 14},  {34, 20},
	                                 {150, 36}, {40, 300}, {4112, 8}};
	for (unsigned z = 0; z < sizeof sz / sizeof sz[0]; z++)
		for (int t = 1; t <= 3; t += 2)
			forced_base_at(level, sz[z][0], sz[z][1], t, (int)(z % 4));
	const uint32_t W = 64, H = 48;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	float *imgf = malloc(sizeof(float) * W * H);
	pc_fplane f[12];
	float *fb = alloc_planes(W, H, f);
	make_raw_kind(1, &m, W, H, img, imgf);
	const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
	pc_dm_pan_check_params p;
	/* the variants without a fast path are refused */
	p = pc_dm_pan_check_defaults();
	p.base = 1;
	CHECK_EQ_INT(pc_dm_pan_check_fast_with(&in, &m, FS, 1, level, &p, f), PC_ENOTSUP);
	p = pc_dm_pan_check_defaults();
	p.cons = 4;
	CHECK_EQ_INT(pc_dm_pan_check_fast_with(&in, &m, FS, 1, level, &p, f), PC_ENOTSUP);
	p = pc_dm_pan_check_defaults();
	p.gamma = -1;
	CHECK_EQ_INT(pc_dm_pan_check_fast_with(&in, &m, FS, 1, level, &p, f), PC_EINVAL);
	free(img);
	free(imgf);
	free(fb);
}

int main(void)
{
	test_against_reference((int)pc_cpu_supported());
	for (int l = 0; l <= (int)pc_cpu_supported(); l++)
		test_forced_base((pc_cpu_level)l);
	return pc_test_finish("test_pan_check_fast");
}
