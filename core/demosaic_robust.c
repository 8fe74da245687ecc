/* The overshoot limiter of the robust rungs (docs/demosaicking.md, "Robustness"): every
 * interpolated sample of channel c at pixel p is held inside the range of channel c's own
 * measurements in the 5×5 window around p (mirrored borders, as every method):
 *     I_c(p) ← min(max(I_c(p), min_W raw_c), max_W raw_c).
 * Inter-channel methods extrapolate from a guide; where the guide's model does not hold (a
 * bright object on black, a saturated glint, polarization texture) they ring, and in the dark
 * the ringing becomes false polarization (the DoLP of small numbers). Bilinear never leaves
 * that range. Min, max and clamp are exact in float, and the limiter runs on the float outputs
 * of both the fast paths and the double references (rounded to float first), so the two stay
 * as close to each other after it as before. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"

#include "cpu_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

/* The limiter's scratch (pc_dm_limiter_init): a ring of five rows' ranges, each row's four
 * (An, Ax, Bn, Bx) interleaved in blocks of 16 columns, range k of column x at PC_DM_LIM_AT(x) +
 * 16·k of its 4·LIM_W16(w) floats, so that combine_clamp's fourteen range reads a column come from
 * five rows instead of fourteen separate ones (docs/demosaicking.md, Round 29); then combine's
 * eight rows of w and the column parities. */
#define LIM_W16(w) (((w) + 15) / 16 * 16)

/* the x & 1 row (floats, the clamp kernels' blend) after the ranges and combine's rows */
static float *lim_par(const pc_dm_limiter *l)
{
	return l->mem + (size_t)LIM_W16(l->w) * 20 + (size_t)l->w * 8;
}

int pc_dm_limited(pc_demosaic_method method)
{
	return method == PC_DM_BICUBIC || method == PC_DM_PPID || method == PC_DM_RI ||
	       method == PC_DM_EARI || method == PC_DM_RATIO || method == PC_DM_EARI_ROBUST ||
	       method == PC_DM_RATIO_RI || method == PC_DM_RATIO_NR || method == PC_DM_RATIO_NR3;
}

int pc_dm_limiter_init(pc_dm_limiter *l, long w, pc_cpu_level level)
{
	l->w = w;
	l->level = level;
	l->mem = pc_dm_alloc(sizeof(float) * ((size_t)LIM_W16(w) * 5 * 4 + (size_t)w * (8 + 1)));
	for (int k = 0; k < 5; k++)
		l->key[k] = LONG_MIN;
	if (!l->mem)
		return -1;
	float *par = lim_par(l);
	for (long x = 0; x < w; x++)
		par[x] = (float)(x & 1);
	return 0;
}

void pc_dm_limiter_free(pc_dm_limiter *l)
{
	pc_dm_free(l->mem);
	l->mem = NULL;
}

typedef struct lim_kernels {
	void (*ranges)(const float *restrict, float *restrict, long);
	void (*combine)(const float *const[5], float *restrict, long);
	void (*clamp)(float *restrict, const float *, const float *, const float *, const float *,
	              const float *, long, int, long);
	void (*combine_clamp)(const float *const[5], float *restrict, float *restrict,
	                      float *restrict, float *restrict, const float *, long);
} lim_kernels;

#define KFN(name) name##_base
#define KATTR
#include "demosaic_robust_kern.inc"
#undef KFN
#undef KATTR
#ifdef PC_CPU_X86
#define KFN(name) name##_avx2
#define KATTR     __attribute__((target("avx2")))
#include "demosaic_robust_kern.inc"
#undef KFN
#undef KATTR
/* AVX-512: 16 lanes (GCC prefers 256-bit vectors unless told, as in demosaic_ic.c) */
#define KFN(name) name##_avx512
#ifdef __clang__
#define KATTR __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw"), min_vector_width(512)))
#else
#define KATTR __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,prefer-vector-width=512")))
#endif
#include "demosaic_robust_kern.inc"
#undef KFN
#undef KATTR
#endif

/* The instance for a CPU level (polarcam/cpu.h). */
static const lim_kernels *lim_k(pc_cpu_level level)
{
	static const lim_kernels base = {ranges_base, combine_base, clamp_base, combine_clamp_base};
#ifdef PC_CPU_X86
	static const lim_kernels avx2 = {ranges_avx2, combine_avx2, clamp_avx2, combine_clamp_avx2};
	static const lim_kernels avx512 = {ranges_avx512, combine_avx512, clamp_avx512,
	                                   combine_clamp_avx512};
	if (level >= PC_CPU_AVX512)
		return &avx512;
	if (level >= PC_CPU_AVX2)
		return &avx2;
#else
	(void)level;
#endif
	return &base;
}

/* Row vrow's horizontal ranges, cached in a ring of five rows. */
static const float *row_ranges(pc_dm_limiter *l, const float *r, long vrow)
{
	long slot = ((vrow % 5) + 5) % 5;
	float *m4 = l->mem + (size_t)LIM_W16(l->w) * 4 * (size_t)slot;
	if (l->key[slot] == vrow)
		return m4;
	const long w = l->w;
	lim_k(l->level)->ranges(r, m4, w);
	l->key[slot] = vrow;
	return m4;
}

void pc_dm_limit_ranges(pc_dm_limiter *l, const float *const r[5], uint32_t y, const float *rr[5])
{
	for (int i = 0; i < 5; i++)
		rr[i] = row_ranges(l, r[i], (long)y - 2 + i);
}

void pc_dm_limit_row(pc_dm_limiter *l, const pc_mosaic *m, const float *const r[5], uint32_t y,
                     float *const o[4], size_t pixel_stride)
{
	const long w = l->w;
	const lim_kernels *k = lim_k(l->level);
	const float *rr[5];
	pc_dm_limit_ranges(l, r, y, rr);
	if (pixel_stride == 1) {
		/* planar rows: one fused pass (the channels measured in row y's parity, then those
		 * of the other rows, each pair by column parity) */
		unsigned py = y & 1;
		k->combine_clamp(rr, o[pc_dm_ch(m, 0, py)], o[pc_dm_ch(m, 1, py)],
		                 o[pc_dm_ch(m, 0, py ^ 1)], o[pc_dm_ch(m, 1, py ^ 1)], lim_par(l),
		                 w);
		return;
	}
	/* the ranges of rows of y's parity (y−2, y, y+2) and of the other (y±1), for the A and
	 * B column sets */
	float *v = l->mem + (size_t)LIM_W16(w) * 20;
	k->combine(rr, v, w);
	for (unsigned py = 0; py < 2; py++)
		for (unsigned px = 0; px < 2; px++) {
			unsigned c = pc_dm_ch(m, px, py);
			int same_row = ((y ^ py) & 1) == 0;
			const float *sn = v + (same_row ? 2 : 6) * w,
			            *sx = v + (same_row ? 3 : 7) * w;
			const float *an = v + (same_row ? 0 : 4) * w,
			            *ax = v + (same_row ? 1 : 5) * w;
			if (pixel_stride == 1) {
				k->clamp(o[c], sn, sx, an, ax, v + 8 * w, (long)px, same_row, w);
				continue;
			}
			for (long x = 0; x < w; x++) {
				int own_col = ((x ^ (long)px) & 1) == 0;
				if (same_row && own_col)
					continue;
				float lo = own_col ? sn[x] : an[x], hi = own_col ? sx[x] : ax[x];
				float *p = o[c] + (size_t)x * pixel_stride;
				*p = pc_dm_mn(pc_dm_mx(*p, lo), hi);
			}
		}
}

typedef struct limit_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	pc_cpu_level level;
	int err;
} limit_job;

static void limit_band(void *ctx, uint32_t y0, uint32_t y1)
{
	limit_job *j = ctx;
	const pc_dm_input *in = j->in;
	const long w = in->width;
	const int h = (int)in->height;
	const size_t L = (size_t)w + 8;
	float *mem = malloc(sizeof(float) * L * 5);
	pc_dm_limiter lim;
	if (!mem || pc_dm_limiter_init(&lim, w, j->level)) {
		free(mem);
		j->err = 1;
		return;
	}
	long have[5] = {LONG_MIN, LONG_MIN, LONG_MIN, LONG_MIN, LONG_MIN};
	for (uint32_t y = y0; y < y1; y++) {
		const float *r[5];
		for (int k = 0; k < 5; k++) {
			long vrow = (long)y + k - 2, slot = ((vrow % 5) + 5) % 5;
			float *row = mem + L * (size_t)slot + 4;
			if (have[slot] != vrow) {
				pc_dm_row_to_float(in, (uint32_t)pc_mirror((int)vrow, h), row);
				row[-2] = row[pc_mirror(-2, (int)w)];
				row[w + 1] = row[pc_mirror((int)w + 1, (int)w)];
				have[slot] = vrow;
			}
			r[k] = row;
		}
		float *o[4];
		for (int c = 0; c < 4; c++)
			o[c] = j->out[c].data + (size_t)y * j->out[c].row_stride;
		/* one pixel stride for all four planes in every layout the library makes */
		pc_dm_limit_row(&lim, j->m, r, y, o, j->out[0].pixel_stride);
	}
	pc_dm_limiter_free(&lim);
	free(mem);
}

int pc_dm_range_limit(const pc_dm_input *in, const pc_mosaic *m, int threads, pc_cpu_level level,
                      const pc_fplane *out)
{
	for (int c = 1; c < 4; c++)
		if (out[c].pixel_stride != out[0].pixel_stride)
			return pc_error(PC_EINVAL, "output channels with different pixel strides");
	limit_job j = {in, m, out, level, 0};
	pc_parallel_rows(in->height, 32, threads, limit_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "range limiter: row scratch") : 0;
}

int pc_dm_range_limit_ref(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                          const pc_fplane *out)
{
	size_t n = (size_t)width * height;
	float *f = malloc(n * sizeof(float));
	if (!f)
		return pc_error(PC_ENOMEM, "range limiter: %ux%u input", width, height);
	for (size_t i = 0; i < n; i++)
		f[i] = (float)img[i];
	pc_dm_input in = pc_dm_input_f32(f, width, height);
	int rc = pc_dm_range_limit(&in, m, 1, PC_CPU_BASELINE, out);
	free(f);
	return rc;
}
