/* pan-guard's float fast path (core/demosaic_pan_guard_fast.c, docs/demosaicking.md "Round 15
 * fast path: pan-guard") against its double reference pc_dm_pan_guard_ref_with (guard17's,
 * core/demosaic_pan_guard.c), at every instruction set the machine has:
 *  - every output within 1e-5 of full scale of the reference, on five inputs (a smooth coloured
 *    polarized scene, a texture, a hue grating finer than the red and blue lattices' Nyquist
 *    period where the guard moves away from the base, the smooth scene with noise, and dim at
 *    1/64 of its level), three sizes, four mosaic phases, and parameter sets covering both
 *    bases, both modes, r = 0..2 and γ = 1, 4, 8 and a non-integer γ (cons 0: the fast
 *    path has only bayer-first as its conservative estimate, and refuses cons 1);
 *  - the guard is not idle on those inputs: on the grating the reference moves some output by
 *    more than 1 % of full scale away from its base (else the comparison would test the base
 *    only);
 *  - three threads give one thread's outputs bit for bit, interleaved outputs the planar ones;
 *  - forced weights 1 give the base's fast path bit for bit, also with a given noise gain g
 *    (pan-adapt's fast path with that g; another g changes it), and with a given g the fast
 *    path is within 1e-5 of full scale of the reference with it (Round 15b's gain, given to
 *    the base). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_pan.h"
#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x9a4df0a517ull
#include "xorshift.h"

#include "colour_truth.h"

#define FS 4095.0

/* channel (k, c) at (x, y) of input kind 0 smooth, 1 texture, 2 hue grating, 3 noisy, 4 dim */
static double scene(int kind, unsigned k, unsigned c, double x, double y)
{
	switch (kind) {
	case 1:
		return (700 + 500 * sin(0.45 * x + 0.2 * k) * cos(0.37 * y - 0.3 * k) +
		        300 * sin(0.11 * (x + y))) *
		       pol(c);
	case 2: /* red/lime stripes of period 6 px: P0 sees them, the colour lattices alias */
	{
		const double s = 0.5 + 0.5 * cos(2 * M_PI * x / 6);
		const double lv[3] = {300 + 1800 * s, 300 + 1800 * (1 - s), 250};
		return lv[k] * pol(c);
	}
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
			if (kind == 3) /* Gaussian, σ = 23 DN (test_pan_fast's noisy input's) */
				v += 23 * nrand();
			v = fmin(fmax(round(v), 0), FS);
			img[(size_t)y * w + x] = v;
			imgf[(size_t)y * w + x] = (float)v;
		}
}

static double fget(const pc_fplane *p, uint32_t x, uint32_t y)
{
	return p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
}

static void test_against_reference(void)
{
	static const int sizes[3][2] = {{34, 20}, {64, 48}, {150, 36}};
	/* base, r, γ, mode */
	static const double sets[6][4] = {{1, 1, 1, 0}, {0, 0, 4, 1},   {1, 2, 8, 0},
	                                  {0, 1, 8, 0}, {1, 1, 2.5, 1}, {1, 1, 8, 1}};
	const pc_mosaic base = pc_mosaic_imx250myr();
	/* each reference once, every level held against it (CI time: the references dominate) */
	double worst[PC_CPU_LEVELS][5] = {{0}}, moved = 0;
	int same = 1;
	const int nl = (int)pc_cpu_supported() + 1;
	for (int z = 0; z < 3; z++) {
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
			for (int kind = 0; kind < 5; kind++) {
				make_raw_kind(kind, &m, W, H, img, imgf);
				const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
				for (int s = 0; s < 6; s++) {
					pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
					p.base = (int)sets[s][0];
					p.r = (int)sets[s][1];
					p.gamma = sets[s][2];
					p.mode = (int)sets[s][3];
					p.cons = 0;
					p.force = -1;
					CHECK_EQ_INT(
					    pc_dm_pan_guard_ref_with(img, W, H, &m, FS, &p, r), 0);
					if (kind == 2) {
						/* the reference's base: forced weights 1 */
						pc_dm_pan_guard_params pb = p;
						pb.force = 1;
						CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m,
						                                      FS, &pb, b),
						             0);
					}
					for (unsigned q = 0; kind == 2 && q < 12; q++)
						for (uint32_t y = 0; y < H; y++)
							for (uint32_t x = 0; x < W; x++)
								moved = fmax(
								    moved, fabs(fget(&r[q], x, y) -
								                fget(&b[q], x, y)) /
								               FS);
					for (int l = 0; l < nl; l++) {
						const pc_cpu_level level = (pc_cpu_level)l;
						CHECK_EQ_INT(pc_dm_pan_guard_fast_with(
						                 &in, &m, FS, 1, level, &p, f),
						             0);
						CHECK_EQ_INT(pc_dm_pan_guard_fast_with(
						                 &in, &m, FS, 3, level, &p, t3),
						             0);
						CHECK_EQ_INT(pc_dm_pan_guard_fast_with(
						                 &in, &m, FS, 3, level, &p, il),
						             0);
						for (unsigned q = 0; q < 12; q++)
							for (uint32_t y = 0; y < H; y++)
								for (uint32_t x = 0; x < W; x++) {
									const double v =
									    fget(&f[q], x, y);
									worst[l][kind] = fmax(
									    worst[l][kind],
									    fabs(v - fget(&r[q], x,
									                  y)) /
									        FS);
									same &=
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
	for (int l = 0; l < nl; l++) {
		printf("  %s: max |fast - reference| %.3g (smooth), %.3g (texture), %.3g (hue "
		       "grating), %.3g (noisy), %.3g (dim) of full scale\n",
		       pc_cpu_level_name((pc_cpu_level)l), worst[l][0], worst[l][1], worst[l][2],
		       worst[l][3], worst[l][4]);
		for (int k = 0; k < 5; k++)
			CHECK(worst[l][k] <= 1e-5);
	}
	printf("  the guard moves the grating's outputs by up to %.3g of full scale\n", moved);
	CHECK(same);
	CHECK(moved > 0.01);
}

/* forced weights 1: the base's fast path bit for bit (1·I_p + 0·I_b) */
static void test_forced_base(pc_cpu_level level)
{
	const uint32_t W = 64, H = 48;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	float *imgf = malloc(sizeof(float) * W * H);
	pc_fplane f[12], b[12];
	float *fb = alloc_planes(W, H, f), *bb = alloc_planes(W, H, b);
	make_raw_kind(1, &m, W, H, img, imgf);
	const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
	for (int base = 0; base < 2; base++) {
		pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
		p.base = base;
		p.force = 1;
		CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), 0);
		CHECK_EQ_INT(base ? pc_dm_pan_adapt_fast(&in, &m, FS, 1, level, b)
		                  : pc_dm_pan_side_fast(&in, &m, FS, 1, level, b),
		             0);
		int eq = 1;
		for (unsigned q = 0; q < 12; q++)
			for (uint32_t y = 0; y < H; y++)
				for (uint32_t x = 0; x < W; x++)
					eq &= fget(&f[q], x, y) == fget(&b[q], x, y);
		CHECK(eq);
	}
	/* a given noise gain reaches the base: pan-adapt's fast path with the same g */
	for (int i = 0; i < 2; i++) {
		pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
		p.force = 1;
		p.g = i ? 40.0 : 4.0;
		CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), 0);
		CHECK_EQ_INT(pc_dm_pan_adapt_fast_g(&in, &m, FS, 1, level, i ? 40.0 : 4.0, b), 0);
		int eq = 1;
		for (unsigned q = 0; q < 12; q++)
			for (uint32_t y = 0; y < H; y++)
				for (uint32_t x = 0; x < W; x++)
					eq &= fget(&f[q], x, y) == fget(&b[q], x, y);
		CHECK(eq);
		if (i) { /* not vacuous: 4's base differs from 40's */
			CHECK_EQ_INT(pc_dm_pan_adapt_fast_g(&in, &m, FS, 1, level, 4.0, b), 0);
			int ne = 0;
			for (unsigned q = 0; q < 12; q++)
				for (uint32_t y = 0; y < H; y++)
					for (uint32_t x = 0; x < W; x++)
						ne |= fget(&f[q], x, y) != fget(&b[q], x, y);
			CHECK(ne);
		}
	}
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	p.g = NAN;
	CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), PC_EINVAL);
	p = pc_dm_pan_guard_defaults();
	p.cons = 1;
	CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), PC_ENOTSUP);
	free(img);
	free(imgf);
	free(fb);
	free(bb);
}

/* a given noise gain: the fast path within 1e-5 of full scale of the reference with it, on
 * the noisy scene (kind 3), at gains around and far from its estimate; and different gains
 * give different outputs */
static void test_given_gain(pc_cpu_level level)
{
	const uint32_t W = 64, H = 48;
	const pc_mosaic m = pc_mosaic_imx250myr();
	double *img = malloc(sizeof(double) * W * H);
	float *imgf = malloc(sizeof(float) * W * H);
	pc_fplane r[12], f[12], f0[12];
	float *rb = alloc_planes(W, H, r), *fb = alloc_planes(W, H, f),
	      *f0b = alloc_planes(W, H, f0);
	make_raw_kind(3, &m, W, H, img, imgf);
	const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
	static const double gs[3] = {0.5, 4.0, 40.0};
	double worst = 0, moved = 0;
	for (int i = 0; i < 3; i++) {
		pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
		p.g = gs[i];
		CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, FS, &p, r), 0);
		CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), 0);
		if (i == 0)
			CHECK_EQ_INT(pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f0), 0);
		for (unsigned q = 0; q < 12; q++)
			for (uint32_t y = 0; y < H; y++)
				for (uint32_t x = 0; x < W; x++) {
					worst =
					    fmax(worst,
					         fabs(fget(&f[q], x, y) - fget(&r[q], x, y)) / FS);
					moved =
					    fmax(moved,
					         fabs(fget(&f[q], x, y) - fget(&f0[q], x, y)) / FS);
				}
	}
	printf("  %s, given gains 0.5, 4, 40 (noisy scene): max |fast - reference| %.3g of full "
	       "scale; the gains move outputs by up to %.3g of full scale\n",
	       pc_cpu_level_name(level), worst, moved);
	CHECK(worst <= 1e-5);
	CHECK(moved > 1e-4);
	free(img);
	free(imgf);
	free(rb);
	free(fb);
	free(f0b);
}

int main(void)
{
	test_against_reference();
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		test_forced_base((pc_cpu_level)l);
		test_given_gain((pc_cpu_level)l);
	}
	return pc_test_finish("test_pan_guard_fast");
}
