/* Stokes, DoLP and AoLP: the float AoLP kernel against double atan2, the AoLP convention from
 * Malus' law, DoLP clipping and S0 <= 0, the analyser-matrix least squares (ideal analysers
 * give the plain formulas; a perturbed analyser is inverted exactly), the fused bilinear
 * pipeline against demosaic-then-Stokes in double, and false-colour pictures. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/picture.h"
#include "polarcam/stokes.h"

static double aolp_ref(double s1, double s2)
{
	double a = 0.5 * atan2(s2, s1);
	return a < 0 ? a + M_PI : a;
}

static void test_aolp_kernel(void)
{
	double worst = 0;
	int in_range = 1;
	for (int i = 0; i < 200000; i++) {
		double t = 2 * M_PI * i / 200000.0;
		float r = (float)(0.1 + (i % 97) * 10.0);
		float s1 = (float)(r * cos(t)), s2 = (float)(r * sin(t));
		float a = pc_aolp_f(s1, s2);
		double d = fabs(a - aolp_ref(s1, s2));
		d = fmin(d, M_PI - d); /* 0 and π are the same orientation */
		worst = d > worst ? d : worst;
		in_range &= a >= 0 && a < (float)M_PI;
	}
	CHECK(worst <= 3e-7);
	if (worst > 3e-7)
		fprintf(stderr, "  AoLP kernel worst error %g rad\n", worst);
	CHECK(in_range);
	/* exact special cases */
	CHECK_NEAR(pc_aolp_f(1, 0), 0, 0);
	CHECK_NEAR(pc_aolp_f(0, 1), M_PI / 4, 2e-7);
	CHECK_NEAR(pc_aolp_f(-1, 0), M_PI / 2, 2e-7);
	CHECK_NEAR(pc_aolp_f(0, -1), 3 * M_PI / 4, 3e-7);
	CHECK_NEAR(pc_aolp_f(0, 0), 0, 0);
	float tiny = pc_aolp_f(1, -1e-30f); /* just below 0: wraps to just below π, or 0 */
	CHECK(tiny >= 0 && tiny < (float)M_PI);
}

/* Light linearly polarized at θ (from the x axis, counter-clockwise as seen by the viewer) with
 * degree p: I_c = S0/2 (1 + p cos 2(θ − θ_c)). The pipeline must return AoLP θ and DoLP p. */
static void test_convention(void)
{
	for (int k = 0; k < 36; k++) {
		double th = k * M_PI / 36, p = 0.3 + 0.01 * k, s0 = 2.0;
		float I[4];
		for (int c = 0; c < 4; c++)
			I[c] = (float)(s0 / 2 * (1 + p * cos(2 * (th - c * M_PI / 4))));
		pc_fplane in[4];
		for (int c = 0; c < 4; c++)
			in[c] = (pc_fplane){&I[c], 1, 1};
		float o[5];
		pc_stokes_out so = {
		    {&o[0], 1, 1}, {&o[1], 1, 1}, {&o[2], 1, 1}, {&o[3], 1, 1}, {&o[4], 1, 1}};
		CHECK_EQ_INT(pc_stokes_from_channels(in, 1, 1, NULL, &so), 0);
		CHECK_NEAR(o[0], s0, 1e-6);
		CHECK_NEAR(o[1], s0 * p * cos(2 * th), 1e-6);
		CHECK_NEAR(o[2], s0 * p * sin(2 * th), 1e-6);
		CHECK_NEAR(o[3], p, 1e-6);
		double d = fabs(o[4] - th);
		CHECK(fmin(d, M_PI - d) < 1e-6);
	}
	/* DoLP clipped to 1 and 0 where S0 <= 0 (frozen protocol) */
	float I[4] = {1, 0, -1, 0};      /* S0 = 0 */
	float J[4] = {2, 0.5f, 0, 0.5f}; /* S0 = 1.5, |S| = 2 */
	pc_fplane in[4], jn[4];
	for (int c = 0; c < 4; c++) {
		in[c] = (pc_fplane){&I[c], 1, 1};
		jn[c] = (pc_fplane){&J[c], 1, 1};
	}
	float d;
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.dolp = (pc_fplane){&d, 1, 1};
	CHECK_EQ_INT(pc_stokes_from_channels(in, 1, 1, NULL, &so), 0);
	CHECK_NEAR(d, 0, 0);
	CHECK_EQ_INT(pc_stokes_from_channels(jn, 1, 1, NULL, &so), 0);
	CHECK_NEAR(d, 1, 0);
	pc_stokes_out none;
	memset(&none, 0, sizeof none);
	CHECK_EQ_INT(pc_stokes_from_channels(in, 1, 1, NULL, &none), PC_EINVAL);
}

static void test_pinv(void)
{
	double w[4][3], p[3][4];
	pc_stokes_ideal_analyser(w);
	CHECK_EQ_INT(pc_stokes_pinv1(w, p), 0);
	/* the ideal pseudo-inverse is S0 = ½ΣI, S1 = I0 − I90, S2 = I45 − I135 */
	const double want[3][4] = {{0.5, 0.5, 0.5, 0.5}, {1, 0, -1, 0}, {0, 1, 0, -1}};
	for (int i = 0; i < 3; i++)
		for (int c = 0; c < 4; c++)
			CHECK_NEAR(p[i][c], want[i][c], 1e-12);
	/* a non-ideal analyser (extinction, orientation errors, gains): W⁺W = identity */
	const double ang[4] = {1.5, 44.0, 91.0, 134.0}, ext[4] = {0.98, 0.95, 0.97, 0.99};
	for (int c = 0; c < 4; c++) {
		double t = ang[c] * M_PI / 180;
		w[c][0] = 0.5 * (1.0 + 0.02 * c);
		w[c][1] = 0.5 * ext[c] * cos(2 * t);
		w[c][2] = 0.5 * ext[c] * sin(2 * t);
	}
	CHECK_EQ_INT(pc_stokes_pinv1(w, p), 0);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			double s = 0;
			for (int c = 0; c < 4; c++)
				s += p[i][c] * w[c][j];
			CHECK_NEAR(s, i == j, 1e-12);
		}
	/* used per pixel: a 1×1 grid applies it everywhere and recovers S exactly */
	float wf[12], pf[12];
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < 3; i++)
			wf[3 * c + i] = (float)w[c][i];
	CHECK_EQ_INT(pc_stokes_pinv(wf, 1, pf), 0);
	const double S[3] = {3.0, 0.4, -0.7};
	float I[4];
	for (int c = 0; c < 4; c++)
		I[c] = (float)(wf[3 * c] * S[0] + wf[3 * c + 1] * S[1] + wf[3 * c + 2] * S[2]);
	pc_fplane in[4];
	for (int c = 0; c < 4; c++)
		in[c] = (pc_fplane){&I[c], 1, 1};
	float o[3];
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.s0 = (pc_fplane){&o[0], 1, 1};
	so.s1 = (pc_fplane){&o[1], 1, 1};
	so.s2 = (pc_fplane){&o[2], 1, 1};
	pc_analyser_pinv grid = {pf, 1, 1};
	CHECK_EQ_INT(pc_stokes_from_channels(in, 1, 1, &grid, &so), 0);
	for (int i = 0; i < 3; i++)
		CHECK_NEAR(o[i], S[i], 2e-6);
	/* rank-deficient: two analysers at the same angle and the others equal too */
	for (int c = 0; c < 4; c++) {
		w[c][0] = 0.5;
		w[c][1] = 0.5 * (c & 1);
		w[c][2] = 0;
	}
	CHECK_EQ_INT(pc_stokes_pinv1(w, p), PC_ENUMERIC);
}

/* The fused bilinear pipeline equals demosaic + Stokes computed in double. Tolerances: S0, S1,
 * S2 within 1e-6 of full scale (float sums of integers; in fact exact), DoLP within 2e-6, AoLP
 * within 1e-6 rad where |(S1, S2)| exceeds 1/4095 of full scale (the angle of a smaller vector
 * is dominated by the 12-bit rounding). Sizes cover the kernel's 16-pixel loop, its 8-pixel
 * step and the scalar tail; widths that are multiples of 16 give aligned rows, which take the
 * non-temporal stores (main() lowers the size threshold to 0), 1296×1296 over several row
 * bands; 8-bit and float32 raws (the latter scaled to 1e-25 and 1e+25, which the
 * fast reciprocal must not be used for) take the other input paths. */
typedef struct fused_case {
	uint32_t w, h;
	pc_pixfmt fmt;
	double scale; /* float32 raws: values × scale */
} fused_case;

static void fused_one(const fused_case *fc)
{
	const uint32_t W = fc->w, H = fc->h;
	const size_t n = (size_t)W * H;
	pc_mosaic m = pc_mosaic_imx250mzr();
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, fc->fmt, W, H, 0), 0);
	double fs = fc->fmt == PC_FMT_MONO8 ? 255 : 4095;
	uint32_t r = 99 + W;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			r = r * 1664525u + 1013904223u;
			uint32_t v = (r >> 9) & 4095;
			if (fc->fmt == PC_FMT_MONO8)
				PC_ROW(&raw, uint8_t, y)[x] = (uint8_t)(v >> 4);
			else if (fc->fmt == PC_FMT_FLOAT32)
				PC_ROW(&raw, float, y)[x] = (float)(v * fc->scale);
			else
				PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)v;
		}
	if (fc->fmt == PC_FMT_FLOAT32)
		fs = 4095 * fc->scale;
	/* 64-byte aligned planes with 64-byte aligned rows when W is a multiple of 16 */
	size_t pl_floats = (n + 15) / 16 * 16;
	float *buf = aligned_alloc(64, sizeof(float) * pl_floats * 5);
	pc_stokes_out so;
	pc_fplane *pl[5] = {&so.s0, &so.s1, &so.s2, &so.dolp, &so.aolp};
	for (int k = 0; k < 5; k++)
		*pl[k] = (pc_fplane){buf + (size_t)k * pl_floats, W, 1};
	CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, PC_DM_BILINEAR, NULL, &so), 0);
	float *ch = malloc(sizeof(float) * n * 4);
	pc_fplane c4[4];
	pc_fplanes_separate(ch, W, H, 4, c4);
	pc_demosaic_opts ref = {0, true, 0};
	CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_BILINEAR, &ref, c4), 0);
	double ws = 0, wd = 0, wa = 0;
	int in_range = 1;
	for (size_t i = 0; i < n; i++) {
		double I0 = ch[i], I1 = ch[n + i], I2 = ch[2 * n + i], I3 = ch[3 * n + i];
		double s0 = (I0 + I1 + I2 + I3) / 2, s1 = I0 - I2, s2 = I1 - I3;
		double nn = sqrt(s1 * s1 + s2 * s2), dl = s0 > 0 ? fmin(nn / s0, 1) : 0;
		const float *o0 = pl[0]->data, *o1 = pl[1]->data, *o2 = pl[2]->data;
		double e = fabs(o0[i] - s0) + fabs(o1[i] - s1) + fabs(o2[i] - s2);
		ws = fmax(ws, e / fs);
		wd = fmax(wd, fabs(pl[3]->data[i] - dl));
		float a = pl[4]->data[i];
		in_range &= a >= 0 && a < (float)M_PI;
		if (nn > fs / 4095) {
			double d = fabs(a - aolp_ref(s1, s2));
			wa = fmax(wa, fmin(d, M_PI - d));
		}
	}
	CHECK(ws <= 1e-6);
	CHECK(wd <= 2e-6);
	CHECK(wa <= 1e-6);
	CHECK(in_range);
	if (ws > 1e-6 || wd > 2e-6 || wa > 1e-6)
		fprintf(stderr, "  fused %ux%u %s: S %g of full scale, DoLP %g, AoLP %g\n", W, H,
		        pc_format_info_get(fc->fmt)->name, ws, wd, wa);
	/* interleaved (H, W, 3) Stokes and a threads=1 run give the same numbers */
	float *il = malloc(sizeof(float) * n * 3);
	pc_stokes_out si;
	memset(&si, 0, sizeof si);
	si.s0 = (pc_fplane){il, 3 * W, 3};
	si.s1 = (pc_fplane){il + 1, 3 * W, 3};
	si.s2 = (pc_fplane){il + 2, 3 * W, 3};
	pc_demosaic_opts one = {1, false, 0};
	CHECK(!pc_stokes_streams(&si, W, H)); /* interleaved: ordinary stores */
	CHECK(!pc_stokes_streams(NULL, W, H));
	CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, PC_DM_BILINEAR, &one, &si), 0);
	int same = 1;
	for (size_t i = 0; i < n; i++)
		same &= il[3 * i] == pl[0]->data[i] && il[3 * i + 1] == pl[1]->data[i] &&
		        il[3 * i + 2] == pl[2]->data[i];
	CHECK(same);
	/* DoLP and AoLP alone (no Stokes planes wanted) are the same numbers */
	pc_stokes_out da;
	memset(&da, 0, sizeof da);
	da.dolp = (pc_fplane){il, W, 1};
	da.aolp = (pc_fplane){il + n, W, 1};
	CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, PC_DM_BILINEAR, NULL, &da), 0);
	same = 1;
	for (size_t i = 0; i < n; i++)
		same &= il[i] == pl[3]->data[i] && il[n + i] == pl[4]->data[i];
	CHECK(same);
	free(il);
	free(ch);
	free(buf);
	pc_view_free(&raw);
}

static void test_fused(void)
{
	const fused_case cases[] = {
	    {46, 34, PC_FMT_MONO12, 1}, /* 16 + 16 + 8 + 6: every loop of the kernel */
	    {64, 8, PC_FMT_MONO12, 1},  /* whole 16-pixel blocks only */
	    {4, 4, PC_FMT_MONO12, 1},   /* the smallest frame: scalar only */
	    {30, 6, PC_FMT_MONO8, 1},
	    {40, 12, PC_FMT_FLOAT32, 1e-25},
	    {40, 12, PC_FMT_FLOAT32, 1e25},
	    {1296, 1296, PC_FMT_MONO12, 1}, /* non-temporal stores */
	};
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
		fused_one(&cases[i]);
}

/* The row-cache methods' fused pipeline (demosaic rows turned into Stokes rows in cache) gives
 * exactly the numbers of demosaicking into full images and then Stokes, for every such method,
 * with planar outputs (fused) and interleaved ones (the two-step path). */
static void test_fused_ic(void)
{
	const uint32_t W = 70, H = 150; /* several row bands */
	pc_mosaic base = pc_mosaic_imx250mzr();
	pc_mosaic m = pc_mosaic_shift(&base, 1, 0);
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			PC_ROW(&raw, uint16_t, y)
	[x] = (uint16_t)(2000 + 1200 * sin(0.3 * x) * cos(0.21 * y) + 37 * ((x * 7 + y * 3) % 11));
	size_t n = (size_t)W * H;
	float *a = malloc(sizeof(float) * n * 5), *b = malloc(sizeof(float) * n * 5),
	      *ch = malloc(sizeof(float) * n * 4);
	const pc_demosaic_method meths[] = {PC_DM_BICUBIC,  PC_DM_PPID,     PC_DM_RI,
	                                    PC_DM_EARI,     PC_DM_RATIO,    PC_DM_RATIO_NR,
	                                    PC_DM_RATIO_RI, PC_DM_RATIO_NR3};
	for (size_t k = 0; k < sizeof meths / sizeof meths[0]; k++) {
		pc_stokes_out sa, sb;
		pc_fplane *pa[5] = {&sa.s0, &sa.s1, &sa.s2, &sa.dolp, &sa.aolp};
		pc_fplane *pb[5] = {&sb.s0, &sb.s1, &sb.s2, &sb.dolp, &sb.aolp};
		for (int q = 0; q < 5; q++) {
			*pa[q] = (pc_fplane){a + (size_t)q * n, W, 1};
			*pb[q] = (pc_fplane){b + q, (size_t)W * 5, 5}; /* interleaved (H, W, 5) */
		}
		CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, meths[k], NULL, &sa), 0);
		CHECK_EQ_INT(pc_stokes_from_raw(&raw, &m, meths[k], NULL, &sb), 0);
		pc_fplane c4[4];
		pc_fplanes_separate(ch, W, H, 4, c4);
		CHECK_EQ_INT(pc_demosaic(&raw, &m, meths[k], NULL, c4), 0);
		pc_stokes_out sc;
		float *c5 = malloc(sizeof(float) * n * 5);
		pc_fplane *pc5[5] = {&sc.s0, &sc.s1, &sc.s2, &sc.dolp, &sc.aolp};
		for (int q = 0; q < 5; q++)
			*pc5[q] = (pc_fplane){c5 + (size_t)q * n, W, 1};
		CHECK_EQ_INT(pc_stokes_from_channels(c4, W, H, NULL, &sc), 0);
		/* planar: the same kernels, bit for bit; interleaved: S bit for bit, DoLP and AoLP
		 * through the scalar formulas (without fused multiply-adds) within 1e-6 */
		int same = 1;
		double worst = 0;
		for (int q = 0; q < 5; q++)
			for (size_t i = 0; i < n; i++) {
				float want = c5[(size_t)q * n + i], il = b[5 * i + (size_t)q];
				same &= a[(size_t)q * n + i] == want;
				if (q < 3)
					same &= il == want;
				else {
					double d = fabs((double)il - want);
					if (q == 4)
						d = fmin(d, M_PI - d);
					worst = fmax(worst, d);
				}
			}
		if (!same || worst > 1e-6)
			fprintf(stderr,
			        "  fused %s differs from demosaic + Stokes (DoLP/AoLP by %g)\n",
			        pc_demosaic_method_get(meths[k])->name, worst);
		CHECK(same);
		CHECK(worst <= 1e-6);
		free(c5);
	}
	free(a);
	free(b);
	free(ch);
	pc_view_free(&raw);
}

static void test_pictures(void)
{
	float a[4] = {0, (float)(M_PI / 3), (float)(M_PI / 2), 3.0f};
	float d[4] = {1, 1, 0, 0.5f};
	pc_fplane ap = {a, 4, 1}, dp = {d, 4, 1};
	uint8_t rgb[12];
	CHECK_EQ_INT(pc_picture_aolp(&ap, &dp, 4, 1, PC_AOLP_VALUE, 1.0f, rgb, 12), 0);
	/* AoLP 0: red; π/3: hue 1/3 = green; DoLP 0: black */
	CHECK(rgb[0] == 255 && rgb[1] == 0 && rgb[2] == 0);
	CHECK(rgb[3] == 0 && rgb[4] == 255 && rgb[5] == 0);
	CHECK(rgb[6] == 0 && rgb[7] == 0 && rgb[8] == 0);
	CHECK_EQ_INT(pc_picture_aolp(&ap, &dp, 4, 1, PC_AOLP_SATURATION, 1.0f, rgb, 12), 0);
	CHECK(rgb[6] == 255 && rgb[7] == 255 && rgb[8] == 255); /* unpolarized: white */
	CHECK_EQ_INT(pc_picture_grey(&dp, 4, 1, 0, 1, rgb, 12), 0);
	CHECK(rgb[0] == 255 && rgb[6] == 0 && rgb[9] == 128);
	CHECK_EQ_INT(pc_picture_grey(&dp, 4, 1, 1, 1, rgb, 12), PC_EINVAL);
	CHECK_EQ_INT(pc_picture_aolp(&ap, NULL, 4, 1, PC_AOLP_VALUE, 1.0f, rgb, 12), PC_EINVAL);
	/* low-signal mask: S0 below the threshold or not finite gets the hatch, the rest is kept */
	float s0v[4] = {5, 50, NAN, 49.99f};
	pc_fplane s0p = {s0v, 4, 1};
	uint8_t img[12];
	memset(img, 200, sizeof img);
	CHECK_EQ_INT((int)pc_picture_mask_low(&s0p, 4, 1, 50, img, 12), 3);
	uint8_t hatch[3];
	int masked_ok = 1;
	for (uint32_t x = 0; x < 4; x++) {
		pc_picture_mask_rgb(x, 0, hatch);
		int is_hatch = !memcmp(img + 3 * x, hatch, 3);
		masked_ok &= x == 1 ? (img[3] == 200 && img[4] == 200 && img[5] == 200) : is_hatch;
	}
	CHECK(masked_ok);
	/* the hatch is grey and has both stripes */
	int seen0 = 0, seen1 = 0;
	for (uint32_t x = 0; x < 16; x++) {
		pc_picture_mask_rgb(x, 3, hatch);
		CHECK(hatch[0] == hatch[1] && hatch[1] == hatch[2]);
		seen0 |= hatch[0] == PC_PICTURE_MASK_RGB0;
		seen1 |= hatch[0] == PC_PICTURE_MASK_RGB1;
	}
	CHECK(seen0 && seen1);
	float q[100];
	for (int i = 0; i < 100; i++)
		q[i] = (float)i;
	pc_fplane qp = {q, 100, 1};
	CHECK_NEAR(pc_picture_quantile(&qp, 100, 1, 0.5), 50, 0.1);
}

int main(void)
{
	/* every aligned planar case streams (non-temporal stores), also on machines whose default
	 * never does (AMD); the unaligned and interleaved cases take ordinary stores */
	setenv("POLARCAM_NT_MIN_BYTES", "0", 1);
	/* every kernel instance this machine runs (polarcam/cpu.h), held to the same references */
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
		test_aolp_kernel();
		test_convention();
		test_pinv();
		test_fused();
		test_fused_ic();
		test_pictures();
		printf("  instance %s: done\n", pc_cpu_level_name((pc_cpu_level)l));
	}
	pc_cpu_force(PC_CPU_LEVELS);
	return pc_test_finish("test_stokes");
}
