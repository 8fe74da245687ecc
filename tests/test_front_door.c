/* The front door's options (pc_pipeline_opts, pc_demosaic_run, pc_stokes_run), each against an
 * independently computed answer, at every CPU instance the machine runs:
 *  - supports: each method's reference, perturbed at single raw samples, changes only output
 *    pixels inside the support this test states (and reaches its edge);
 *  - validity mask: exactly the pixels whose support touches a saturated or dead sample,
 *    computed here by a slow loop from those supports, for every method, every path (fast,
 *    reference, fused Stokes, row-cache Stokes, two-step Stokes), packed, 8-bit and float raws;
 *  - black level: a synthetic frame with an offset, computed here from Malus' law, gives the
 *    truth's DoLP and AoLP (and the bias it removes is there without it);
 *  - calibrated analysers: per-super-pixel, per-pixel, one-matrix and other grids through every
 *    path against S = P·I in double on the reference channels (tolerances below); the exact
 *    ideal matrix gives the uncalibrated outputs bit for bit; on a frame made with perturbed
 *    analysers the calibrated DoLP/AoLP are the truth's where the uncalibrated ones are not;
 *  - bad options: each refused with PC_EINVAL. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/stokes.h"

static uint32_t rng_state = 2024;
static double urand(void)
{
	rng_state = rng_state * 1664525u + 1013904223u;
	return (rng_state >> 8) / 16777216.0;
}

/* Whole-sample mirror (reflect-101), written here again: -1 -> 1, n -> n-2. */
static int mir(int i, int n)
{
	while (i < 0 || i >= n)
		i = i < 0 ? -i : 2 * (n - 1) - i;
	return i;
}

static double fget(const pc_fplane *p, uint32_t x, uint32_t y)
{
	return p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
}

static pc_mosaic mosaic_for(pc_demosaic_method m)
{
	return pc_demosaic_method_get(m)->flags & PC_DMF_COLOR ? pc_mosaic_imx250myr()
	                                                       : pc_mosaic_imx250mzr();
}

/* ---- supports ----
 * The raw samples each output pixel depends on, stated from the methods' definitions
 * (docs/demosaicking.md): output (x, y) reads rows mirror(ay + lo .. ay + hi) and columns
 * mirror(ax + lo .. ax + hi) with ax = x·scale rounded down to a multiple of block. */
typedef struct support {
	pc_demosaic_method m;
	int lo, hi, block, scale;
	int slack; /* 0: the stated support is exact (reached); else an upper bound whose reach on
	            * random data is at least hi - slack */
} support;

static const support supports[] = {
    {PC_DM_SUPERPIXEL_HALF, 0, 1, 2, 2, 0}, /* its 2×2 block */
    {PC_DM_SUPERPIXEL, 0, 1, 2, 1, 0},      /* the block the pixel lies in */
    {PC_DM_BILINEAR, -1, 1, 1, 1, 0},       /* 3×3 tents */
    {PC_DM_BICUBIC, -3, 3, 1, 1, 0},        /* Keys' taps at ±1, ±3 */
    {PC_DM_PPID, -4, 4, 1, 1, 0},           /* PPI (±1, refined ±2) + 3×3 tent */
    {PC_DM_RI, -8, 8, 1, 1, 0},             /* PPI ±3, two ±2 windows, tent ±1 */
    {PC_DM_EARI, -7, 7, 1, 1, 0},           /* guide ±2, two ±2 windows, tent ±1 */
    {PC_DM_BAYER_FIRST, -3, 3, 1, 1, 0},    /* Bayer sub-image 3×3 (±2), tent ±1 */
    {PC_DM_BAYER_EARI, -9, 9, 1, 1, 0},     /* ±2, then EARI's ±7 */
    {PC_DM_RATIO, -4, 4, 1, 1, 0},          /* guide ±2, tent ±1, second pass's guide */
    {PC_DM_EARI_MLRI, -16, 16, 1, 1, 0},    /* guide ±3, Laplacian ±2, two ±5 windows, tent */
    {PC_DM_EARI_ROBUST, -16, 16, 1, 1, 0},  /* the same; the limiter's ±2 inside */
    {PC_DM_PCDP, -2, 2, 1, 1, 0},           /* bilinear ±1, then the tent of the differences */
    {PC_DM_IGRI2, -40, 40, 1, 1, 6},        /* a bound: three stages of about ±13 */
    {PC_DM_NEWTON, -10, 10, 1, 1, 4},       /* a bound: ±6 through the values, ±10 only
                                             * through the edge classifier's branch */
    {PC_DM_RATIO_RI, -9, 9, 1, 1, 0},       /* ratio ±4, two ±2 windows of its mean, tent */
    {PC_DM_RATIO_NR, -4, 4, 1, 1, 0},       /* ratio's; the 3×3 guide statistics inside */
    {PC_DM_RATIO_NR3, -4, 4, 1, 1, 0},      /* binomial ±1, then three 3×3 passes */
    {PC_DM_PAN_RATIO, -7, 7, 1, 1, 2},      /* ±5 inside; ±7 through the sub-image mirror */
    {PC_DM_PAN_GUIDED, -7, 7, 1, 1, 2},     /* the same (its weights read the PPI's ±5) */
    {PC_DM_PAN_CHROMA, -7, 7, 1, 1, 2},     /* the same (C1 and C2 read as the PPI) */
    {PC_DM_PAN_DIR, -8, 8, 1, 1, 2},        /* pan-ratio's, ±1 through the 3×3 window */
    {PC_DM_PAN_FACT, -10, 10, 1, 1, 3}, /* ±8 inside (demosaic_fact.c; 7 reached), ±10 the mirror */
    {PC_DM_PAN_SIDE, -8, 8, 1, 1, 2},   /* ±6 inside (demosaic_plan.c), ±8 the mirror */
};
#define N_SUP (sizeof supports / sizeof supports[0])

static int anchor(const support *s, int x)
{
	return x * s->scale / s->block * s->block;
}

/* Whether output coordinate x (of an axis of n raw samples) reads raw coordinate sx. */
static int reads(const support *s, int n, int x, int sx)
{
	for (int d = s->lo; d <= s->hi; d++)
		if (mir(anchor(s, x) + d, n) == sx)
			return 1;
	return 0;
}

static void fill_random(pc_view *v, double lo, double hi)
{
	for (uint32_t y = 0; y < v->height; y++)
		for (uint32_t x = 0; x < v->width; x++)
			PC_ROW(v, uint16_t, y)[x] = (uint16_t)(lo + (hi - lo) * urand());
}

/* The reference of a method on raw into nch planes of the output size (buf owns them). */
static float *reference_of(const pc_view *raw, pc_demosaic_method m, pc_fplane *pl, uint32_t *ow,
                           uint32_t *oh)
{
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = m;
	o.mosaic = mosaic_for(m);
	o.reference = true;
	pc_demosaic_out_size(m, raw->width, raw->height, ow, oh);
	unsigned nch = pc_demosaic_channels(&o.mosaic);
	float *buf = malloc(sizeof(float) * (size_t)*ow * *oh * nch);
	pc_fplanes_separate(buf, *ow, *oh, nch, pl);
	CHECK_EQ_INT(pc_demosaic_run(raw, &o, pl, NULL), 0);
	return buf;
}

static void test_supports(void)
{
	for (size_t k = 0; k < N_SUP; k++) {
		const support *s = &supports[k];
		/* large enough that an interior sample's change can reach the stated edge */
		const uint32_t W = s->hi > 16 ? (uint32_t)(2 * s->hi + 8) : 40, H = W;
		const int n = (int)W;
		/* interior samples of both parities, corners, edges */
		const int pos[][2] = {{n / 2 - 1, n / 2}, {n / 2, n / 2 + 1}, {0, 0},    {1, 0},
		                      {n - 1, n - 2},     {2, n - 1},         {n - 2, 1}};
		pc_view raw;
		CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO16, W, H, 0), 0);
		fill_random(&raw, 600, 1400);
		pc_fplane a[12], b[12];
		uint32_t ow, oh;
		float *ba = reference_of(&raw, s->m, a, &ow, &oh);
		pc_mosaic mm = mosaic_for(s->m);
		unsigned nch = pc_demosaic_channels(&mm);
		int outside = 0, reach = 0;
		for (size_t p = 0; p < sizeof pos / sizeof pos[0]; p++) {
			const int sx = pos[p][0], sy = pos[p][1];
			uint16_t keep = PC_ROW(&raw, uint16_t, sy)[sx];
			PC_ROW(&raw, uint16_t, sy)[sx] = (uint16_t)(keep + 2500);
			float *bb = reference_of(&raw, s->m, b, &ow, &oh);
			PC_ROW(&raw, uint16_t, sy)[sx] = keep;
			for (uint32_t y = 0; y < oh; y++)
				for (uint32_t x = 0; x < ow; x++) {
					int changed = 0;
					for (unsigned c = 0; c < nch; c++)
						changed |= fget(&a[c], x, y) != fget(&b[c], x, y);
					if (!changed)
						continue;
					if (!(reads(s, (int)W, (int)x, sx) &&
					      reads(s, (int)H, (int)y, sy)))
						outside++;
					/* the interior samples: how far the change reaches */
					if (p < 2 && s->block == 1) {
						int d = abs((int)x - sx) > abs((int)y - sy)
						            ? abs((int)x - sx)
						            : abs((int)y - sy);
						reach = d > reach ? d : reach;
					}
				}
			free(bb);
		}
		const int reach_ok =
		    s->slack ? reach >= s->hi - s->slack && reach <= s->hi : reach == s->hi;
		if (outside || (s->block == 1 && !reach_ok))
			fprintf(stderr,
			        "  %s: %d changed pixels outside the stated support; reach %d, "
			        "stated %d\n",
			        pc_demosaic_method_get(s->m)->name, outside, reach, s->hi);
		CHECK(outside == 0);
		if (s->block == 1)
			CHECK(reach_ok);
		printf("  %-16s support %d..%d: changes reach %d, none outside\n",
		       pc_demosaic_method_get(s->m)->name, s->lo, s->hi, reach);
		free(ba);
		pc_view_free(&raw);
	}
}

/* ---- validity masks ---- */

/* The slow mask: 1 where no sample the support reads is flagged. Returns the 0 count. */
static size_t slow_mask(const support *s, const uint8_t *flag, uint32_t W, uint32_t H, uint32_t ow,
                        uint32_t oh, uint8_t *mask)
{
	size_t bad = 0;
	for (uint32_t y = 0; y < oh; y++)
		for (uint32_t x = 0; x < ow; x++) {
			int ok = 1;
			for (int dy = s->lo; dy <= s->hi && ok; dy++)
				for (int dx = s->lo; dx <= s->hi && ok; dx++) {
					int sx = mir(anchor(s, (int)x) + dx, (int)W);
					int sy = mir(anchor(s, (int)y) + dy, (int)H);
					ok = !flag[(size_t)sy * W + sx];
				}
			mask[(size_t)y * ow + x] = (uint8_t)ok;
			bad += !ok;
		}
	return bad;
}

/* Compares a library mask (row stride `stride`) with the slow one. */
static int same_mask(const uint8_t *lib, size_t stride, const uint8_t *want, uint32_t ow,
                     uint32_t oh)
{
	for (uint32_t y = 0; y < oh; y++)
		if (memcmp(lib + (size_t)y * stride, want + (size_t)y * ow, ow))
			return 0;
	return 1;
}

/* A raw of format fmt (Mono12, Mono12p, Mono8 or Float32) with ~0.15 % saturated and
 * ~0.1 % dead samples, more on the first row (borders); flag[] marks them. */
static void flagged_raw(pc_pixfmt fmt, uint32_t W, uint32_t H, pc_view *raw, uint8_t *flag,
                        double *sat, double *dead)
{
	double full = fmt == PC_FMT_MONO8 ? 255 : fmt == PC_FMT_FLOAT32 ? 1.0 : 4095;
	*sat = full;
	*dead = fmt == PC_FMT_FLOAT32 ? 0.001 : 0.5;
	uint16_t *u = malloc(sizeof(uint16_t) * W * H);
	float *f = malloc(sizeof(float) * W * H);
	for (uint32_t i = 0; i < W * H; i++) {
		double r = urand(), v = 0.1 + 0.8 * urand();
		int s = r < 0.0015 || (i < W && r < 0.05), d = !s && r > 0.999;
		v = s ? 1.0 : d ? 0.0 : v;
		flag[i] = (uint8_t)(s || d);
		u[i] = (uint16_t)lround(v * full);
		f[i] = (float)v;
	}
	CHECK_EQ_INT(pc_view_alloc(raw, fmt, W, H, 0), 0);
	if (fmt == PC_FMT_FLOAT32)
		for (uint32_t y = 0; y < H; y++)
			memcpy(PC_ROW(raw, float, y), f + (size_t)y * W, W * sizeof(float));
	else
		CHECK_EQ_INT(pc_view_from_u16(u, W * sizeof(uint16_t), raw), 0);
	free(u);
	free(f);
}

static void test_masks(void)
{
	const pc_pixfmt fmts[] = {PC_FMT_MONO12, PC_FMT_MONO12P, PC_FMT_MONO8, PC_FMT_FLOAT32};
	const uint32_t W = 98, H = 64;
	const size_t gotsz = (size_t)(W + 3) * H;
	/* its own seed: the flagged frames must not change with the number of supports tested
	 * before (a frame whose flags cover every ±16 window tests nothing for eari-mlri) */
	rng_state = 7;
	uint8_t *flag = malloc(W * H), *want = malloc(W * H), *got = malloc(gotsz);
	for (size_t f = 0; f < sizeof fmts / sizeof fmts[0]; f++)
		for (size_t k = 0; k < N_SUP; k++) {
			const support *s = &supports[k];
			/* igri2's ±40 covers this frame: its mask is all invalid, which still
			 * checks that the mask code takes an 81-row support (it refused one above
			 * 71 rows with PC_ENOMEM, so polarcam demosaic --method igri2 failed) */
			pc_view raw;
			double sat, dead;
			flagged_raw(fmts[f], W, H, &raw, flag, &sat, &dead);
			pc_pipeline_opts o = pc_pipeline_defaults();
			o.method = s->m;
			o.mosaic = mosaic_for(s->m);
			o.saturation_level = sat;
			o.dead_level = dead;
			uint32_t ow, oh;
			pc_demosaic_out_size(s->m, W, H, &ow, &oh);
			size_t nbad = slow_mask(s, flag, W, H, ow, oh, want);
			/* some pixels valid, some not (igri2's support spans the frame: all not) */
			CHECK(nbad > 0 && (nbad < (size_t)ow * oh || 2 * s->hi + 1 > (int)H));
			unsigned nch = pc_demosaic_channels(&o.mosaic);
			float *buf = malloc(sizeof(float) * ow * oh * 12);
			pc_fplane pl[12];
			pc_fplanes_separate(buf, ow, oh, nch, pl);
			/* demosaic, fast and reference; a padded mask stride */
			for (int ref = 0; ref < 2; ref++) {
				o.reference = ref;
				memset(got, 7, gotsz);
				pc_validity v = {got, ow + 3, 0};
				CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, &v), 0);
				CHECK(same_mask(got, ow + 3, want, ow, oh));
				CHECK_EQ_INT(v.n_invalid, nbad);
			}
			o.reference = false;
			/* Stokes: planar outputs (fused or row-cache paths) and interleaved ones
			 * (two-step), and the count alone */
			pc_stokes_out so;
			memset(&so, 0, sizeof so);
			so.s0 = (pc_fplane){buf, ow, 1};
			so.dolp = (pc_fplane){buf + (size_t)ow * oh, ow, 1};
			pc_validity v = {got, ow, 0};
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, &v), 0);
			CHECK(same_mask(got, ow, want, ow, oh));
			CHECK_EQ_INT(v.n_invalid, nbad);
			so.s0 = (pc_fplane){buf, (size_t)ow * 2, 2};
			so.dolp = (pc_fplane){buf + 1, (size_t)ow * 2, 2};
			pc_validity vc = {NULL, 0, 12345};
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, &vc), 0);
			CHECK_EQ_INT(vc.n_invalid, nbad);
			/* no levels: everything valid */
			o.saturation_level = o.dead_level = 0;
			memset(got, 0, W * H);
			pc_validity vn = {got, ow, 99};
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, &vn), 0);
			CHECK_EQ_INT(vn.n_invalid, 0);
			int all = 1;
			for (size_t i = 0; i < (size_t)ow * oh; i++)
				all &= got[i] == 1;
			CHECK(all);
			free(buf);
			pc_view_free(&raw);
		}
	free(flag);
	free(want);
	free(got);
}

/* ---- black level ---- */

/* A uniform field (S0, DoLP p, AoLP th) over an offset `black`, Malus' law, rounded to 12 bits:
 * I_c = black + S0/2·(1 + p cos 2(th − θ_c)). */
static void offset_frame(const pc_mosaic *m, uint32_t W, uint32_t H, double black, double s0,
                         double p, double th, pc_view *raw)
{
	CHECK_EQ_INT(pc_view_alloc(raw, PC_FMT_MONO12, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			unsigned c = pc_mosaic_channel(m, x, y);
			double v = black + s0 / 2 * (1 + p * cos(2 * (th - M_PI / 4 * c)));
			PC_ROW(raw, uint16_t, y)[x] = (uint16_t)lround(v);
		}
}

static void test_black_level(void)
{
	const uint32_t W = 48, H = 40;
	const double black = 240, s0 = 1200, p = 0.4, th = 30 * M_PI / 180;
	const pc_demosaic_method meths[] = {PC_DM_SUPERPIXEL_HALF,
	                                    PC_DM_BILINEAR,
	                                    PC_DM_BICUBIC,
	                                    PC_DM_PPID,
	                                    PC_DM_RI,
	                                    PC_DM_EARI,
	                                    PC_DM_RATIO,
	                                    PC_DM_RATIO_NR,
	                                    PC_DM_RATIO_NR3,
	                                    PC_DM_RATIO_RI,
	                                    PC_DM_BAYER_FIRST,
	                                    PC_DM_BAYER_EARI};
	for (size_t k = 0; k < sizeof meths / sizeof meths[0]; k++) {
		pc_pipeline_opts o = pc_pipeline_defaults();
		o.method = meths[k];
		o.mosaic = mosaic_for(meths[k]);
		pc_view raw;
		offset_frame(&o.mosaic, W, H, black, s0, p, th, &raw);
		uint32_t ow, oh;
		pc_demosaic_out_size(o.method, W, H, &ow, &oh);
		float *buf = malloc(sizeof(float) * ow * oh * 3);
		pc_stokes_out so;
		memset(&so, 0, sizeof so);
		so.s0 = (pc_fplane){buf, ow, 1};
		so.dolp = (pc_fplane){buf + (size_t)ow * oh, ow, 1};
		so.aolp = (pc_fplane){buf + 2 * (size_t)ow * oh, ow, 1};
		double e_with = 0, e_s0 = 0, e_aolp = 0, bias = 1;
		for (int with = 0; with < 2; with++) {
			o.black_level = with ? black : 0;
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), 0);
			for (size_t i = 0; i < (size_t)ow * oh; i++) {
				double d = fabs(buf[(size_t)ow * oh + i] - p);
				if (with) {
					e_with = fmax(e_with, d);
					e_s0 = fmax(e_s0, fabs(buf[i] - s0));
					double a = fabs(buf[2 * (size_t)ow * oh + i] - th);
					e_aolp = fmax(e_aolp, fmin(a, M_PI - a));
				} else {
					bias = fmin(bias, d);
				}
			}
		}
		/* 12-bit rounding of I (±0.5) moves DoLP by at most ~2·0.5/S0 = 8e-4 and S0 by 1 */
		if (e_with > 1e-3 || e_s0 > 1.0 || bias < 0.1)
			fprintf(stderr,
			        "  %s: DoLP error %g with the black level (S0 %g, AoLP %g rad), "
			        "%g without\n",
			        pc_demosaic_method_get(o.method)->name, e_with, e_s0, e_aolp, bias);
		CHECK(e_with <= 1e-3);
		CHECK(e_s0 <= 1.0);
		CHECK(e_aolp <= 1e-3);
		/* without it DoLP is p·S0/(S0 + 2·black) = 0.286, everywhere */
		CHECK(bias >= 0.1);
		free(buf);
		pc_view_free(&raw);
	}
	/* fast and reference agree with a fractional black level too (values below it negative,
	 * not clamped) */
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0), 0);
	fill_random(&raw, 0, 900);
	for (int m = 0; m < PC_DM_COUNT; m++) {
		pc_pipeline_opts o = pc_pipeline_defaults();
		o.method = (pc_demosaic_method)m;
		o.mosaic = mosaic_for(o.method);
		o.black_level = 100.5;
		uint32_t ow, oh;
		pc_demosaic_out_size(o.method, W, H, &ow, &oh);
		unsigned nch = pc_demosaic_channels(&o.mosaic);
		float *fb = malloc(sizeof(float) * ow * oh * nch),
		      *rb = malloc(sizeof(float) * ow * oh * nch);
		pc_fplane f[12], r[12];
		pc_fplanes_separate(fb, ow, oh, nch, f);
		pc_fplanes_separate(rb, ow, oh, nch, r);
		CHECK_EQ_INT(pc_demosaic_run(&raw, &o, f, NULL), 0);
		o.reference = true;
		CHECK_EQ_INT(pc_demosaic_run(&raw, &o, r, NULL), 0);
		double worst = 0;
		int negative = 0;
		for (size_t i = 0; i < (size_t)ow * oh * nch; i++) {
			/* pan-fact: relative to the value where it exceeds full scale (its hue
			 * floor 10⁻⁴ lets m = v/h reach 1.6·10⁶ DN on this noise around the black
			 * level; 0.375 DN off there, 2.3·10⁻⁷ of the value) */
			double scale = o.method == PC_DM_PAN_FACT ? fmax(1, fabs(rb[i]) / 4095) : 1;
			worst = fmax(worst, fabs(fb[i] - rb[i]) / scale);
			negative |= fb[i] < 0;
		}
		CHECK(negative);
		/* the fast paths' tolerance (docs/demosaicking.md): 1e-5 of full scale (pan-fact's
		 * blend: 1e-4) */
		const double tol = o.method == PC_DM_PAN_FACT ? 1e-4 : 1e-5;
		if (!(worst <= tol * 4095))
			fprintf(stderr,
			        "  %s: max |fast - reference| %.3g with a black level of 100.5\n",
			        pc_demosaic_method_get(o.method)->name, worst);
		CHECK(worst <= tol * 4095);
		free(fb);
		free(rb);
	}
	pc_view_free(&raw);
}

/* ---- calibrated analysers ---- */

/* Planes (3, 4, gh, gw) of a grid whose cell k has the pseudo-inverse of a perturbed analyser
 * matrix (angles ±1.5°, extinction 0.93..0.99, gains 0.9..1.1); ideal: the exact ideal P. */
static float *make_pinv(uint32_t gw, uint32_t gh, int ideal)
{
	size_t n = (size_t)gw * gh;
	float *w = malloc(sizeof(float) * 12 * n), *pinv = malloc(sizeof(float) * 12 * n);
	for (size_t k = 0; k < n; k++)
		for (int c = 0; c < 4; c++) {
			double t = (45.0 * c + 3 * (urand() - 0.5)) * M_PI / 180;
			double e = 0.93 + 0.06 * urand(), g = 0.9 + 0.2 * urand();
			w[12 * k + 3 * c] = (float)(0.5 * g);
			w[12 * k + 3 * c + 1] = (float)(0.5 * g * e * cos(2 * t));
			w[12 * k + 3 * c + 2] = (float)(0.5 * g * e * sin(2 * t));
		}
	if (ideal) {
		static const float P[3][4] = {
		    {0.5f, 0.5f, 0.5f, 0.5f}, {1, 0, -1, 0}, {0, 1, 0, -1}};
		for (int i = 0; i < 3; i++)
			for (int c = 0; c < 4; c++)
				for (size_t k = 0; k < n; k++)
					pinv[(size_t)(4 * i + c) * n + k] = P[i][c];
	} else {
		CHECK_EQ_INT(pc_stokes_pinv(w, n, pinv), 0);
	}
	free(w);
	return pinv;
}

/* Stokes in double of channel values I (channel order) through the matrix of output pixel
 * (x, y) of a W × H output. */
static void stokes_ref(const pc_analyser_pinv *pv, uint32_t W, uint32_t H, uint32_t x, uint32_t y,
                       const double I[4], double S[5])
{
	size_t n = (size_t)pv->grid_w * pv->grid_h;
	size_t cell = (size_t)((uint64_t)y * pv->grid_h / H) * pv->grid_w +
	              (size_t)((uint64_t)x * pv->grid_w / W);
	for (int i = 0; i < 3; i++) {
		S[i] = 0;
		for (int c = 0; c < 4; c++)
			S[i] += (double)pv->m[(size_t)(4 * i + c) * n + cell] * I[c];
	}
	double q = hypot(S[1], S[2]);
	S[3] = S[0] > 0 ? fmin(q / S[0], 1) : 0;
	double a = 0.5 * atan2(S[2], S[1]);
	S[4] = a < 0 ? a + M_PI : a;
}

typedef struct cal_case {
	pc_demosaic_method m;
	int grid; /* 0: 1×1, 1: per super-pixel (W/2 × H/2), 2: per pixel, 3: other (W/4 × H/3) */
	int interleaved;
} cal_case;

static void calibrated_one(const cal_case *cc, const pc_view *raw, double *worst)
{
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = cc->m;
	o.mosaic = mosaic_for(cc->m);
	uint32_t ow, oh;
	pc_demosaic_out_size(cc->m, raw->width, raw->height, &ow, &oh);
	uint32_t gw = cc->grid == 0 ? 1 : cc->grid == 1 ? ow / 2 : cc->grid == 2 ? ow : ow / 4;
	uint32_t gh = cc->grid == 0 ? 1 : cc->grid == 1 ? oh / 2 : cc->grid == 2 ? oh : oh / 3;
	float *pm = make_pinv(gw, gh, 0);
	pc_analyser_pinv pv = {pm, gw, gh};
	o.pinv = &pv;
	size_t n = (size_t)ow * oh;
	/* 64-byte aligned planes with aligned rows where ow allows: the streaming stores too */
	float *buf = aligned_alloc(64, sizeof(float) * ((n + 15) / 16 * 16) * 5);
	pc_stokes_out so;
	pc_fplane *pl[5] = {&so.s0, &so.s1, &so.s2, &so.dolp, &so.aolp};
	for (int q = 0; q < 5; q++)
		*pl[q] = cc->interleaved
		             ? (pc_fplane){buf + q, (size_t)ow * 5, 5}
		             : (pc_fplane){buf + (size_t)q * ((n + 15) / 16 * 16), ow, 1};
	CHECK_EQ_INT(pc_stokes_run(raw, &o, &so, NULL), 0);
	pc_fplane ch[12];
	uint32_t rw, rh;
	float *rb = reference_of(raw, cc->m, ch, &rw, &rh);
	int colour = o.mosaic.period == 4;
	for (uint32_t y = 0; y < oh; y++)
		for (uint32_t x = 0; x < ow; x++) {
			double I[4], S[5];
			for (int c = 0; c < 4; c++)
				I[c] = colour ? (fget(&ch[c], x, y) + fget(&ch[4 + c], x, y) +
				                 fget(&ch[8 + c], x, y)) /
				                    3
				              : fget(&ch[c], x, y);
			stokes_ref(&pv, ow, oh, x, y, I, S);
			for (int q = 0; q < 3; q++)
				worst[q] = fmax(worst[q], fabs(fget(pl[q], x, y) - S[q]) / 4095);
			worst[3] = fmax(worst[3], fabs(fget(pl[3], x, y) - S[3]));
			/* AoLP: an error ΔS in S1, S2 turns the angle by up to ΔS/|(S1, S2)|,
			 * so the angle error times |(S1, S2)| is held to S's tolerance */
			double a = fabs(fget(pl[4], x, y) - S[4]);
			worst[4] = fmax(worst[4], fmin(a, M_PI - a) * hypot(S[1], S[2]) / 4095);
		}
	free(rb);
	free(buf);
	free(pm);
}

static void test_calibrated_vs_reference(void)
{
	const uint32_t W = 80, H = 48; /* 16-pixel blocks and a tail */
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0), 0);
	fill_random(&raw, 300, 3800);
	const cal_case cases[] = {
	    {PC_DM_BILINEAR, 0, 0},
	    {PC_DM_BILINEAR, 1, 0},
	    {PC_DM_BILINEAR, 2, 0},
	    {PC_DM_BILINEAR, 3, 0},
	    {PC_DM_BILINEAR, 1, 1},
	    {PC_DM_RATIO, 1, 0},
	    {PC_DM_RATIO, 2, 0},
	    {PC_DM_RATIO, 1, 1},
	    {PC_DM_RATIO_NR, 1, 0},
	    {PC_DM_RATIO_NR3, 1, 0},
	    {PC_DM_RATIO_RI, 2, 0},
	    {PC_DM_EARI, 0, 0},
	    {PC_DM_BICUBIC, 1, 0},
	    {PC_DM_PPID, 2, 0},
	    {PC_DM_RI, 1, 0},
	    {PC_DM_SUPERPIXEL, 1, 0},
	    {PC_DM_SUPERPIXEL_HALF, 1, 0},
	    {PC_DM_SUPERPIXEL_HALF, 2, 1},
	    {PC_DM_BAYER_FIRST, 1, 0},
	};
	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		double worst[5] = {0};
		calibrated_one(&cases[k], &raw, worst);
		/* Tolerances against S = P·I in double on the reference channels: the float
		 * products and sums (two roundings of terms up to |P|·4095, |P| < 1.3) give 1e-6
		 * of full scale where the fast channels equal the reference (bilinear,
		 * super-pixels: exact sums); the inter-channel methods add their own tolerance,
		 * 1e-5 of full scale per channel, times Σ|P_ic| <= 3. DoLP follows with S0 >= 300:
		 * 2e-6 and 1e-4; AoLP (rad) times |(S1, S2)| as S, plus the arctangent's 3e-7. */
		int exact_ch = cases[k].m == PC_DM_BILINEAR || cases[k].m == PC_DM_SUPERPIXEL ||
		               cases[k].m == PC_DM_SUPERPIXEL_HALF;
		double ts = exact_ch ? 1e-6 : 3e-5, td = exact_ch ? 2e-6 : 1e-4, ta = ts + 3e-7;
		int ok = worst[0] <= ts && worst[1] <= ts && worst[2] <= ts && worst[3] <= td &&
		         worst[4] <= ta;
		if (!ok || k == 0)
			fprintf(
			    ok ? stdout : stderr,
			    "  calibrated %s grid %d%s: S %.2g %.2g %.2g of full scale, DoLP %.2g, "
			    "AoLP·|(S1, S2)| %.2g of full scale\n",
			    pc_demosaic_method_get(cases[k].m)->name, cases[k].grid,
			    cases[k].interleaved ? " interleaved" : "", worst[0], worst[1],
			    worst[2], worst[3], worst[4]);
		CHECK(ok);
	}
	pc_view_free(&raw);
	/* colour: a colour raw through bayer-first with a per-super-pixel grid */
	pc_view craw;
	CHECK_EQ_INT(pc_view_alloc(&craw, PC_FMT_MONO12, W, H, 0), 0);
	fill_random(&craw, 300, 3800);
	double worst[5] = {0};
	cal_case cc = {PC_DM_BAYER_EARI, 1, 0};
	calibrated_one(&cc, &craw, worst);
	CHECK(worst[0] <= 3e-5 && worst[1] <= 3e-5 && worst[2] <= 3e-5 && worst[3] <= 1e-4);
	pc_view_free(&craw);
}

/* The exact ideal matrix, in every grid kind, gives the uncalibrated outputs bit for bit on
 * the vectorised paths (fused bilinear, row-cache methods, two-step planar); the scalar kernel
 * of other grids equals them in S and within 1e-6 in DoLP/AoLP. */
static void test_ideal_matrix(void)
{
	const uint32_t W = 72, H = 40;
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0), 0);
	fill_random(&raw, 0, 4095);
	const pc_demosaic_method meths[] = {PC_DM_BILINEAR, PC_DM_RATIO, PC_DM_EARI,
	                                    PC_DM_SUPERPIXEL};
	size_t n = (size_t)W * H;
	float *a = malloc(sizeof(float) * n * 5), *b = malloc(sizeof(float) * n * 5);
	for (size_t k = 0; k < sizeof meths / sizeof meths[0]; k++)
		for (int g = 0; g < 4; g++) {
			uint32_t gw = g == 0 ? 1 : g == 1 ? W / 2 : g == 2 ? W : W / 4;
			uint32_t gh = g == 0 ? 1 : g == 1 ? H / 2 : g == 2 ? H : H / 4;
			float *pm = make_pinv(gw, gh, 1);
			pc_analyser_pinv pv = {pm, gw, gh};
			pc_pipeline_opts o = pc_pipeline_defaults();
			o.method = meths[k];
			pc_stokes_out sa, sb;
			pc_fplane *pa[5] = {&sa.s0, &sa.s1, &sa.s2, &sa.dolp, &sa.aolp};
			pc_fplane *pb[5] = {&sb.s0, &sb.s1, &sb.s2, &sb.dolp, &sb.aolp};
			for (int q = 0; q < 5; q++) {
				*pa[q] = (pc_fplane){a + (size_t)q * n, W, 1};
				*pb[q] = (pc_fplane){b + (size_t)q * n, W, 1};
			}
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &sa, NULL), 0);
			o.pinv = &pv;
			CHECK_EQ_INT(pc_stokes_run(&raw, &o, &sb, NULL), 0);
			int same_s = 1;
			double dd = 0;
			for (size_t i = 0; i < 3 * n; i++)
				same_s &= a[i] == b[i];
			int same_da = 1;
			for (size_t i = 3 * n; i < 5 * n; i++) {
				same_da &= a[i] == b[i];
				double d = fabs(a[i] - b[i]);
				dd = fmax(dd, i >= 4 * n ? fmin(d, M_PI - d) : d);
			}
			if (!same_s || (g < 3 && !same_da) || dd > 1e-6)
				fprintf(
				    stderr,
				    "  ideal matrix, %s grid %d: S %s, DoLP/AoLP differ by %g\n",
				    pc_demosaic_method_get(meths[k])->name, g,
				    same_s ? "equal" : "differ", dd);
			CHECK(same_s);
			if (g < 3)
				CHECK(same_da);
			CHECK(dd <= 1e-6);
			free(pm);
		}
	free(a);
	free(b);
	pc_view_free(&raw);
	/* pc_stokes_pinv of the ideal analyser matrix is the ideal pseudo-inverse */
	double w[4][3];
	float wf[12], pf[12];
	pc_stokes_ideal_analyser(w);
	for (int c = 0; c < 4; c++)
		for (int i = 0; i < 3; i++)
			wf[3 * c + i] = (float)w[c][i];
	CHECK_EQ_INT(pc_stokes_pinv(wf, 1, pf), 0);
	static const float P[12] = {0.5f, 0.5f, 0.5f, 0.5f, 1, 0, -1, 0, 0, 1, 0, -1};
	for (int i = 0; i < 12; i++)
		CHECK_NEAR(pf[i], P[i], 1e-7);
}

/* A frame made by per-super-pixel perturbed analysers from a uniform field: the calibrated
 * pipeline gives the truth's DoLP and AoLP, the uncalibrated one does not. */
static void test_calibration_recovers_truth(void)
{
	const uint32_t W = 64, H = 48, gw = W / 2, gh = H / 2;
	const double s0 = 3000, p = 0.5, th = 70 * M_PI / 180;
	const double S[3] = {s0, s0 * p * cos(2 * th), s0 * p * sin(2 * th)};
	size_t n = (size_t)gw * gh;
	float *w = malloc(sizeof(float) * 12 * n), *pm = malloc(sizeof(float) * 12 * n);
	for (size_t k = 0; k < n; k++)
		for (int c = 0; c < 4; c++) {
			double t = (45.0 * c + 2 * (urand() - 0.5)) * M_PI / 180;
			double e = 0.9 + 0.08 * urand(), g = 0.85 + 0.3 * urand();
			w[12 * k + 3 * c] = (float)(0.5 * g);
			w[12 * k + 3 * c + 1] = (float)(0.5 * g * e * cos(2 * t));
			w[12 * k + 3 * c + 2] = (float)(0.5 * g * e * sin(2 * t));
		}
	CHECK_EQ_INT(pc_stokes_pinv(w, n, pm), 0);
	pc_mosaic m = pc_mosaic_imx250mzr();
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_FLOAT32, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			unsigned c = pc_mosaic_channel(&m, x, y);
			const float *wc = w + 12 * ((size_t)(y / 2) * gw + x / 2) + 3 * c;
			PC_ROW(&raw, float, y)
			[x] = (float)(wc[0] * S[0] + wc[1] * S[1] + wc[2] * S[2]);
		}
	pc_analyser_pinv pv = {pm, gw, gh};
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_SUPERPIXEL; /* one super-pixel's four samples: no interpolation error */
	o.full_scale = 4095;
	float *buf = malloc(sizeof(float) * W * H * 2);
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.dolp = (pc_fplane){buf, W, 1};
	so.aolp = (pc_fplane){buf + (size_t)W * H, W, 1};
	double err[2][2] = {{0}};
	for (int cal = 0; cal < 2; cal++) {
		o.pinv = cal ? &pv : NULL;
		CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), 0);
		for (size_t i = 0; i < (size_t)W * H; i++) {
			double a = fabs(buf[(size_t)W * H + i] - th);
			err[cal][0] = fmax(err[cal][0], fabs(buf[i] - p));
			err[cal][1] = fmax(err[cal][1], fmin(a, M_PI - a));
		}
	}
	printf("  perturbed analysers: DoLP error %.2g -> %.2g, AoLP %.2g -> %.2g deg\n", err[0][0],
	       err[1][0], err[0][1] * 180 / M_PI, err[1][1] * 180 / M_PI);
	CHECK(err[1][0] <= 1e-5 && err[1][1] <= 1e-5);
	CHECK(err[0][0] >= 1e-2 && err[0][1] >= 1e-3);
	free(buf);
	free(w);
	free(pm);
	pc_view_free(&raw);
}

/* ---- bad options ---- */
static void test_bad_options(void)
{
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, 8, 8, 0), 0);
	fill_random(&raw, 0, 4095);
	float buf[64 * 5];
	pc_fplane pl[4];
	pc_fplanes_separate(buf, 8, 8, 4, pl);
	pc_stokes_out so;
	memset(&so, 0, sizeof so);
	so.s0 = (pc_fplane){buf, 8, 1};
	pc_pipeline_opts o = pc_pipeline_defaults();
	CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, NULL), 0);
	CHECK_EQ_INT(pc_demosaic_run(&raw, NULL, pl, NULL), PC_EINVAL);
	o.black_level = -1;
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	o.black_level = NAN;
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	o.black_level = 4095; /* at full scale */
	CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, NULL), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "black level") != NULL);
	o.black_level = 0;
	o.saturation_level = INFINITY;
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	o.saturation_level = 100;
	o.dead_level = 100;
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "dead level") != NULL);
	o.dead_level = 0;
	uint8_t mask[64];
	pc_validity v = {mask, 7, 0}; /* stride below the width */
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, &v), PC_EINVAL);
	float pm[12] = {0};
	pc_analyser_pinv pv = {pm, 1, 1};
	o.pinv = &pv;
	CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, NULL), PC_EINVAL); /* Stokes only */
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), 0);
	pv.grid_w = 9; /* wider than the output */
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	pv.grid_w = 0;
	CHECK_EQ_INT(pc_stokes_run(&raw, &o, &so, NULL), PC_EINVAL);
	pc_view_free(&raw);
}

/* Texts that name methods take them from the table: the names of the methods with a flag,
 * gathered here from pc_demosaic_method_get, are what pc_demosaic_method_names gives (cut as
 * snprintf cuts, at every size) and what the refusal of a colour mosaic by a monochrome-only
 * method names. */
static void test_method_lists(void)
{
	const unsigned flags[3] = {PC_DMF_COLOR, PC_DMF_NOISE_GAIN, 0};
	char want[1024], got[1024], cut[1024];
	for (int f = 0; f < 3; f++) {
		size_t n = 0;
		int count = 0;
		want[0] = 0;
		for (int k = 0; k < PC_DM_COUNT; k++) {
			const pc_demosaic_method_info *mi =
			    pc_demosaic_method_get((pc_demosaic_method)k);
			if ((mi->flags & flags[f]) != flags[f])
				continue;
			n += (size_t)snprintf(want + n, sizeof want - n, "%s%s", count ? ", " : "",
			                      mi->name);
			count++;
		}
		CHECK(n < sizeof want && count > 0);
		CHECK_EQ_INT((long long)pc_demosaic_method_names(flags[f], got, sizeof got),
		             (long long)n);
		CHECK(strcmp(got, want) == 0);
		printf("  methods with flags 0x%x (%d): %s\n", flags[f], count, got);
		CHECK_EQ_INT((long long)pc_demosaic_method_names(flags[f], NULL, 0), (long long)n);
		for (size_t size = 1; size <= n + 1; size++) {
			memset(cut, 'x', sizeof cut);
			CHECK_EQ_INT((long long)pc_demosaic_method_names(flags[f], cut, size),
			             (long long)n);
			CHECK(strlen(cut) == (size - 1 < n ? size - 1 : n));
			CHECK(strncmp(cut, want, strlen(cut)) == 0 && cut[size] == 'x');
		}
		CHECK(count == PC_DM_COUNT || flags[f] != 0);
		if (flags[f] != PC_DMF_COLOR)
			continue;
		/* bilinear (monochrome only) on a colour mosaic */
		pc_view raw;
		CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, 8, 8, 0), 0);
		fill_random(&raw, 0, 4095);
		float buf[64 * 12];
		pc_fplane pl[12];
		pc_fplanes_separate(buf, 8, 8, 12, pl);
		pc_pipeline_opts o = pc_pipeline_defaults();
		o.mosaic = pc_mosaic_imx250myr();
		CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, NULL), PC_EINVAL);
		char said[1100];
		snprintf(said, sizeof said, "(methods for it: %s)", want);
		CHECK(strstr(pc_error_detail(), said) != NULL);
		printf("  refusal: \"%s\"\n", pc_error_detail());
		pc_view_free(&raw);
	}
}

int main(void)
{
	/* streaming stores on the small aligned frames too (as test_stokes) */
	setenv("POLARCAM_NT_MIN_BYTES", "0", 1);
	test_supports();
	test_bad_options();
	test_method_lists();
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
		test_masks();
		test_black_level();
		test_calibrated_vs_reference();
		test_ideal_matrix();
		test_calibration_recovers_truth();
		printf("  instance %s: done\n", pc_cpu_level_name((pc_cpu_level)l));
	}
	pc_cpu_force(PC_CPU_LEVELS);
	return pc_test_finish("test_front_door");
}
