/* pan-guard's fast path in row bands (core/demosaic_pan_guard_fast.c, docs/demosaicking.md
 * Round 16b) where test_pan_guard_fast's frames (at most 48 rows) fit in one band:
 *  - frames of 150 to 300 rows, so that three threads run four or five bands of at least 64
 *    rows, each starting its rings part-way down the frame: three threads give one thread's
 *    outputs bit for bit (one band), and both are within 1e-5 of full scale of the double
 *    reference pc_dm_pan_guard_ref_with, for r = 0, 1, 2 and both modes, on a texture and on
 *    a hue grating where the guard moves outputs away from its base by over 1 % of full scale
 *    (else the comparison would test the base only);
 *  - bayer-first's row-range entry (pc_dm_bayer_first_band_rows, demosaic_color.h) on
 *    consecutive ranges of uneven length, the ranges' first rows at the frame's border rows and
 *    inside it, equals the whole-frame pass pc_dm_bayer_first bit for bit, at every
 *    instruction set the machine has. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_color.h"
#include "../core/demosaic_pan.h"
#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 0x5b2e91c3d7ull
#include "xorshift.h"

#include "colour_truth.h"

#define FS 4095.0

/* channel (k, c) at (x, y): kind 0 a texture, 1 red/lime stripes of period 6 px (the colour
 * lattices alias, P0 sees them: the guard moves away from the base) */
static double scene(int kind, unsigned k, unsigned c, double x, double y)
{
	if (kind == 0)
		return (700 + 500 * sin(0.45 * x + 0.2 * k) * cos(0.37 * y - 0.3 * k) +
		        300 * sin(0.11 * (x + y))) *
		       pol(c);
	const double s = 0.5 + 0.5 * cos(2 * M_PI * (x + 0.3 * y) / 6);
	const double lv[3] = {300 + 1800 * s, 300 + 1800 * (1 - s), 250};
	return lv[k] * pol(c);
}

static void test_bands(pc_cpu_level level)
{
	static const int sizes[2][2] = {{40, 300}, {96, 150}};
	/* r, mode */
	static const int sets[4][2] = {{1, 0}, {0, 0}, {2, 0}, {1, 1}};
	const pc_mosaic base = pc_mosaic_imx250myr();
	double worst = 0, moved = 0;
	int same = 1;
	for (int z = 0; z < 2; z++) {
		const uint32_t W = (uint32_t)sizes[z][0], H = (uint32_t)sizes[z][1];
		const pc_mosaic m = pc_mosaic_shift(&base, (unsigned)z, (unsigned)(3 * z));
		double *img = malloc(sizeof(double) * W * H);
		float *imgf = malloc(sizeof(float) * W * H);
		pc_fplane r[12], f[12], t3[12], b[12];
		float *rb = alloc_planes(W, H, r), *fb = alloc_planes(W, H, f),
		      *tb = alloc_planes(W, H, t3), *bb = alloc_planes(W, H, b);
		for (int kind = 0; kind < 2; kind++) {
			for (uint32_t y = 0; y < H; y++)
				for (uint32_t x = 0; x < W; x++) {
					unsigned k = pc_mosaic_color(&m, x, y) - PC_CFA_R,
					         c = pc_mosaic_channel(&m, x, y);
					double v = scene(kind, k, c, x, y) + 10 * nrand();
					v = fmin(fmax(round(v), 0), FS);
					img[(size_t)y * W + x] = v;
					imgf[(size_t)y * W + x] = (float)v;
				}
			const pc_dm_input in = pc_dm_input_f32(imgf, W, H);
			for (int s = 0; s < 4; s++) {
				pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
				p.r = sets[s][0];
				p.mode = sets[s][1];
				CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, FS, &p, r), 0);
				CHECK_EQ_INT(
				    pc_dm_pan_guard_fast_with(&in, &m, FS, 1, level, &p, f), 0);
				CHECK_EQ_INT(
				    pc_dm_pan_guard_fast_with(&in, &m, FS, 3, level, &p, t3), 0);
				pc_dm_pan_guard_params pb = p;
				pb.force = 1;
				CHECK_EQ_INT(pc_dm_pan_guard_ref_with(img, W, H, &m, FS, &pb, b),
				             0);
				for (unsigned q = 0; q < 12; q++)
					for (size_t i = 0; i < (size_t)W * H; i++) {
						worst = fmax(
						    worst, fabs(f[q].data[i] - r[q].data[i]) / FS);
						same &= f[q].data[i] == t3[q].data[i];
						if (kind == 1)
							moved = fmax(
							    moved,
							    fabs(r[q].data[i] - b[q].data[i]) / FS);
					}
			}
		}
		free(img);
		free(imgf);
		free(rb);
		free(fb);
		free(tb);
		free(bb);
	}
	printf("  %s: bands of 64+ rows: max |fast - reference| %.3g of full scale, threads 3 = "
	       "threads 1 %s; the guard moves the grating's outputs by up to %.3g of full scale\n",
	       pc_cpu_level_name(level), worst, same ? "bit for bit" : "NOT bit for bit", moved);
	CHECK(same);
	CHECK(moved > 0.01);
	CHECK(worst <= 1e-5);
}

static void test_bayer_first_rows(pc_cpu_level level)
{
	static const int sizes[3][2] = {{8, 8}, {12, 10}, {66, 50}};
	const pc_mosaic base = pc_mosaic_imx250myr();
	int same = 1;
	for (int z = 0; z < 3; z++) {
		const uint32_t W = (uint32_t)sizes[z][0], H = (uint32_t)sizes[z][1];
		float *img = malloc(sizeof(float) * W * H);
		for (size_t i = 0; i < (size_t)W * H; i++)
			img[i] = (float)urand();
		pc_fplane a[12], rows[12];
		float *ab = alloc_planes(W, H, a), *rbuf = malloc(sizeof(float) * W * 12 * 7);
		for (unsigned ph = 0; ph < 16; ph += 3) {
			const pc_mosaic m = pc_mosaic_shift(&base, ph % 4, ph / 4);
			const pc_dm_input in = pc_dm_input_f32(img, W, H);
			CHECK_EQ_INT(pc_dm_bayer_first(&in, &m, 1, level, a), 0);
			pc_dm_bf_band *bd = pc_dm_bayer_first_band_new(&in, &m, level);
			CHECK(bd != NULL);
			if (!bd)
				continue;
			/* ranges of 1, 2, 3, .., 7 rows, then again */
			for (uint32_t y0 = 0, n = 1; y0 < H; y0 += n, n = n % 7 + 1) {
				const uint32_t y1 = y0 + n < H ? y0 + n : H;
				for (unsigned q = 0; q < 12; q++)
					rows[q] = (pc_fplane){rbuf + (size_t)q * W * 7, W, 1};
				pc_dm_bayer_first_band_rows(bd, y0, y1, rows);
				for (unsigned q = 0; q < 12; q++)
					for (uint32_t y = y0; y < y1; y++)
						same &= memcmp(rows[q].data + (size_t)(y - y0) * W,
						               a[q].data + (size_t)y * W,
						               sizeof(float) * W) == 0;
			}
			pc_dm_bayer_first_band_free(bd);
		}
		free(img);
		free(ab);
		free(rbuf);
	}
	printf("  %s: bayer-first's row ranges = the whole-frame pass %s\n",
	       pc_cpu_level_name(level), same ? "bit for bit" : "NOT bit for bit");
	CHECK(same);
}

int main(void)
{
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		test_bands((pc_cpu_level)l);
		test_bayer_first_rows((pc_cpu_level)l);
	}
	return pc_test_finish("test_pan_guard_bands");
}
