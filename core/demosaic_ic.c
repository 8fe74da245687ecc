/* Fast float paths of bicubic, PPID, RI, EARI, ratio, ratio-nr and ratio-ri (demosaic_ic.h; the
 * references are in demosaic_ref.c).
 *
 * Every intermediate image of a method (coarse and refined PPI, guide, guided-filter
 * coefficients, tentative estimates, residuals, the first EARI pass) is produced row by row
 * on demand through small per-thread row caches ("rcache"): asking a cache for row y computes
 * it from the rows it needs in other caches, so a row band streams through all stages while
 * the working set stays a few dozen rows in cache, and row bands run on threads
 * (pc_parallel_rows) recomputing only their few halo rows. Rows are padded on both sides with
 * mirrored values (the same whole-sample mirror as the references), rows above and below the
 * image are mirrored rows. The guided filter's statistics are summed in double, as in the
 * reference: G² and G·R sums in float lose the small variances (measured on a random texture:
 * 4e-4 of full scale off the double reference with float sums, 2e-7 with double sums). */
#include "demosaic_ic.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cpu_internal.h"
#include "parallel_internal.h"
#include "demosaic_anchors.h"
#include "demosaic_plan.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

/* IEEE arithmetic as written in every instance (clang would fuse multiply-adds where the
 * target has FMA; GCC does not contract in ISO C mode), but for KFMA(a, b, c) = a·b + c, fused
 * in the instances with FMA (AVX2, AVX-512) and written out in the baseline one: the ratio
 * kernels' products and sums (ratio-nr 0.93 of its time, docs/demosaicking.md, Round 32). The
 * instances then differ by rounding; each is held to the double reference (tests/
 * test_demosaic.c, also in black regions, where DoLP magnifies rounding). */
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

typedef struct pc_ic_kernels {
	void (*cubic4_rows)(float *restrict, const float *restrict, const float *restrict,
	                    const float *restrict, const float *restrict, long, long);
	void (*cubic_h)(float *restrict, float *restrict, const float *restrict, long);
	void (*tent_add)(float *restrict const[4], const float *const[4], const float *restrict,
	                 const float *restrict, const float *restrict, long);
	void (*ppi_coarse)(float *restrict, const float *restrict, const float *restrict,
	                   const float *restrict, long, long);
	void (*ppi_refine)(float *restrict, const float *const[5], const float *const[3], float,
	                   long, long);
	void (*sub)(float *restrict, const float *restrict, const float *restrict, long, long);
	void (*eari_guide)(float *restrict, const float *const[5], int, int, float, long, long);
	void (*gf_vsum)(double *restrict, const float *, const float *, int, double, long, long,
	                long);
	void (*gf_ab2)(float *restrict, float *restrict, float *restrict, float *restrict,
	               const double *, int, double, float, long, long);
	void (*acc)(float *restrict, const float *restrict, const float *restrict, long, long);
	void (*gf_t)(float *restrict, const float *restrict, const float *restrict,
	             const float *restrict, float, long);
	void (*resid)(float *restrict, const float *restrict, const float *restrict,
	              const float *restrict, long);
	void (*mean4)(float *restrict, const float *, const float *, const float *, const float *,
	              long);
	void (*ratio_q)(float *restrict, const float *restrict, const float *restrict, float, long,
	                long);
	void (*ratio_mean)(float *restrict, const float *restrict, const float *restrict,
	                   const float *restrict, const float *restrict, const float *restrict,
	                   const float *restrict, const float *restrict, float, float, long);
	void (*ratio_out)(float *restrict const[4], const float *restrict, const float *restrict,
	                  const float *restrict, const float *restrict, const float *restrict,
	                  const float *restrict, const float *restrict, const float *const[5],
	                  float, float, long);
	void (*ratio_ri_blend)(float *restrict const[4], const float *const[4],
	                       const float *restrict, const float *restrict, float, long);
	void (*ratio_mean_nr)(float *restrict, const float *restrict, const float *restrict,
	                      const float *restrict, const float *restrict, const float *restrict,
	                      const float *restrict, const float *restrict, float, float, float,
	                      long);
	void (*ratio_out_nr)(float *restrict const[4], const float *restrict, const float *restrict,
	                     const float *restrict, const float *restrict, const float *restrict,
	                     const float *restrict, const float *restrict, const float *const[5],
	                     float, float, float, long);
	int (*any_ge)(const float *restrict, long, float);
	void (*sat_split)(float *restrict, const float *restrict, const float *restrict,
	                  const float *restrict, const float *restrict, float, long);
} pc_ic_kernels;

/* Clang's load PRE turns a row kernel's neighbour loads (v[x-1], v[x], v[x+1]) into
 * recurrences across iterations that its vectoriser (LLVM 14) refuses ("value that could not
 * be identified as reduction is used outside the loop"); an offset the optimiser cannot see
 * through (an empty asm on a register holding 1 or 2) keeps them plain loads, and the loops
 * vectorise. GCC vectorises the loops as written, so the offsets stay constants there. */
#ifdef __clang__
#define PC_OPAQUE(v) __asm__("" : "+r"(v))
#else
#define PC_OPAQUE(v) ((void)0)
#endif

/* The guided filter's window radius is fixed at compile time (PC_GF_R) so that its window
 * sums unroll and vectorise; the parameter tables must agree. */
#define PC_GF_R 2
_Static_assert(PC_RATIO_PASSES == 2, "the ratio method's row caches are written for two passes");
_Static_assert(PC_RATIO_NR3_PASSES == 3, "ratio-nr3's row caches are written for three passes");
_Static_assert(PC_GF_R == 2, "the kernels' window sums are written for radius 2");
#define KFN(name) name##_base
#define KATTR
#define KFMA(a, b, c) ((a) * (b) + (c))
#include "demosaic_ic_kern.inc"
#undef KFN
#undef KATTR
#undef KFMA

#ifdef PC_CPU_X86
#define KFN(name)     name##_avx2
#define KATTR         __attribute__((target("avx2,fma")))
#define KFMA(a, b, c) fmaf((a), (b), (c))
#include "demosaic_ic_kern.inc"
#undef KFN
#undef KATTR
#undef KFMA
/* AVX-512: 16 float or 8 double lanes and 32 registers for the guided filter's sums (GCC
 * prefers 256-bit vectors unless told; clang's generic tuning uses 512-bit ones) */
#define KFN(name) name##_avx512
#ifdef __clang__
#define KATTR                                                                                      \
	__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,fma"), min_vector_width(512)))
#else
#define KATTR                                                                                      \
	__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,fma,prefer-vector-width=512")))
#endif
#define KFMA(a, b, c) fmaf((a), (b), (c))
#include "demosaic_ic_kern.inc"
#undef KFN
#undef KATTR
#undef KFMA
#endif

static const pc_ic_kernels *kernels(pc_cpu_level level)
{
#ifdef PC_CPU_X86
	switch (level) {
	case PC_CPU_AVX512:
		return &kernels_avx512;
	case PC_CPU_AVX2:
		return &kernels_avx2;
	default:
		break;
	}
#endif
	(void)level;
	return &kernels_base;
}

/* ---- row caches ---- */
typedef struct rcache rcache;
typedef void (*rc_fill_fn)(rcache *c, int y, float *const *rows);

#define RC_MAX_K      24
#define RC_MAX_PLANES 8

struct rcache {
	int k, planes, pad, h;
	long w;
	size_t pitch;
	float *buf;
	int key[RC_MAX_K];
	float *rows[RC_MAX_K][RC_MAX_PLANES];
	rc_fill_fn fill;
	void *ctx;
	pc_dm_pf *pf; /* the band's raw-row prefetch, stepped at each access (NULL: none) */
};

/* raw-row lines prefetched at each rc_get (the band's cursor, fill_raw): a 2448-column 16-bit
 * row is 77 lines, and an output row makes 10 (bicubic) to 45 (ratio-ri) rc_get calls, 28 for
 * ratio and ratio-nr (counted at 2448 × 2048) */
#define RC_PF_LINES 8

static int rc_init(rcache *c, int k, int planes, int pad, long w, int h, rc_fill_fn fill, void *ctx)
{
	memset(c, 0, sizeof *c);
	c->k = k;
	c->planes = planes;
	c->pad = pad;
	c->w = w;
	c->h = h;
	c->fill = fill;
	c->ctx = ctx;
	c->pitch = ((size_t)w + 2 * (size_t)pad + 15) / 16 * 16;
	c->buf = pc_dm_alloc(c->pitch * (size_t)k * planes * sizeof(float));
	if (!c->buf)
		return -1;
	for (int i = 0; i < k; i++) {
		c->key[i] = -1;
		for (int p = 0; p < planes; p++)
			c->rows[i][p] = c->buf + ((size_t)i * planes + p) * c->pitch + pad;
	}
	return 0;
}

static void rc_free(rcache *c)
{
	pc_dm_free(c->buf);
	c->buf = NULL;
}

/* Mirrors row[0..w) into its padding: row[-i] = row[i], row[w-1+i] = row[w-1-i]. */
static void pad_row(float *row, long w, int pad)
{
	for (int i = 1; i <= pad; i++) {
		row[-i] = row[pc_mirror(-i, (int)w)];
		row[w - 1 + i] = row[pc_mirror((int)w - 1 + i, (int)w)];
	}
}

/* The plane rows of image row y (mirrored into [0, h)), computed if needed. */
static float *const *rc_get(rcache *c, int y)
{
	if (c->pf)
		pc_dm_pf_step(c->pf, RC_PF_LINES);
	int sy = pc_mirror(y, c->h);
	int victim = 0;
	for (int i = 0; i < c->k; i++) {
		if (c->key[i] == sy)
			return c->rows[i];
		if (c->key[i] < c->key[victim])
			victim = i;
	}
	c->key[victim] = sy;
	c->fill(c, sy, c->rows[victim]);
	for (int p = 0; p < c->planes; p++)
		pad_row(c->rows[victim][p], c->w, c->pad);
	return c->rows[victim];
}

/* One guided-filter stage (a residual-interpolation pass): its coefficient and tentative-
 * estimate caches and its own scratch, so that nested stages never share sums. Window sums run:
 * moving from row k to k+1 subtracts the row leaving the window and adds the one entering it
 * (statistics in double; the box sums of a and b in float, recomputed from scratch every
 * PC_GF_RESET rows to bound rounding drift). */
#define PC_GF_RESET 16
typedef struct gf_stage {
	rcache ab, t;
	rcache *guide;
	double *vs; /* 2 row parities × (G, R, G², GR) × vs_stride, index -r.. */
	long vs_stride;
	int vs_k, vs_age;
	float *sab; /* 8 planes (a_c, b_c) of running vertical sums, index -r.. */
	size_t sab_pitch;
	int sab_y, sab_age;
} gf_stage;

/* ---- per-band state of all methods ---- */
typedef struct ic_band {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_ic_kernels *k;
	float eps_ppi, eps_guide;
	int rad;
	double eps2;
	rcache raw, p0, ppi, guide, out1, guide2;
	rcache rq1, rg2, rq2; /* ratio method: first ratio, second guide, second ratio */
	rcache rg3, rq3;      /* ratio-nr3: third guide, third ratio */
	int three;            /* ratio-nr3: three passes from the binomial guide */
	float delta, eps_ratio;
	rcache rout; /* ratio-ri: the ratio method's four channels (its guide: guide2) */
	float dark;  /* ratio-ri: the blend's dark level */
	float shot;  /* ratio-nr: the guide's noise variance k·μ (the frame's noise gain) */
	float sat;   /* ratio-nr: a clipped sample's value, the raw's full scale less the black
	              * level as the conversion computes it (saturated_binomial_row) */
	unsigned char *rowsat; /* ratio-nr: per image row, whether it holds a clipped sample */
	int nr;                /* ratio-nr (else ratio) */
	gf_stage s1, s2; /* residual-interpolation passes; s1 guided by the PPI (RI) or the EARI
	                  * guide, s2 by the mean of s1's channels (two-pass variants) */
	int passes;
	float *tmp; /* scratch rows */
	/* the raw row after the last one converted, prefetched a few lines at each rc_get of any
	 * cache (pc_dm_pf; docs/demosaicking.md, Round 36) */
	pc_dm_pf pf;
} ic_band;

static void fill_raw(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	pc_dm_pf_finish(&b->pf); /* what the accesses since the last conversion left */
	pc_dm_row_convert(b->in, (uint32_t)y, rows[0]);
	if (b->rowsat) /* ratio-nr: whether the row holds a clipped sample */
		b->rowsat[y] = (unsigned char)b->k->any_ge(rows[0], c->w, b->sat);
	pc_dm_pf_row(&b->pf, b->in, (uint32_t)y + 1);
}

static void fill_p0(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	const float *a = rc_get(&b->raw, y - 1)[0], *m = rc_get(&b->raw, y)[0],
	            *d = rc_get(&b->raw, y + 1)[0];
	b->k->ppi_coarse(rows[0], a, m, d, 0, c->w);
}

static void fill_ppi(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	const float *r[5], *q[3];
	/* other caches first: their fills may evict raw rows (pointers would dangle) */
	for (int i = 0; i < 3; i++)
		q[i] = rc_get(&b->p0, y - 2 + 2 * i)[0];
	for (int i = 0; i < 5; i++)
		r[i] = rc_get(&b->raw, y - 2 + i)[0];
	b->k->ppi_refine(rows[0], r, q, b->eps_ppi, 0, c->w);
}

/* where the orthogonal analyser of the pixel at column parity px of row y sits */
static int ortho_kind(const pc_mosaic *m, int px, int y)
{
	unsigned cp = pc_dm_ch(m, (unsigned)px, (unsigned)y) ^ 2u;
	if (pc_dm_ch(m, (unsigned)px + 1, (unsigned)y + 1) == cp)
		return 0;
	if (pc_dm_ch(m, (unsigned)px + 1, (unsigned)y) == cp)
		return 1;
	return 2;
}

/* ratio-nr's guide row g where clipping splits the analysers (demosaic_ref.c,
 * saturated_binomial): the binomial wherever the 3 × 3 neighbourhood holds an analyser all of
 * whose samples are >= b->sat beside one with none. In a 2 × 2 mosaic the neighbourhood's four
 * analysers are the pixel's own (1 sample), the row's (x ± 1), the column's (y ± 1) and the
 * diagonals' (4). Rows without a clipped sample among the three (nearly all) cost nothing more:
 * each raw row is scanned once as it is converted (fill_raw, b->rowsat). r: the raw rows
 * y − 1, y, y + 1, which the guide's fill has in hand. The binomial goes to b->tmp (scratch that
 * only PPID's output uses). */
static void saturated_binomial_row(ic_band *b, int y, const float *const r[3], float *g)
{
	const int h = b->raw.h;
	if (!b->rowsat[pc_mirror(y - 1, h)] && !b->rowsat[pc_mirror(y, h)] &&
	    !b->rowsat[pc_mirror(y + 1, h)])
		return;
	b->k->ppi_coarse(b->tmp, r[0], r[1], r[2], 0, b->raw.w);
	b->k->sat_split(g, b->tmp, r[0], r[1], r[2], b->sat, b->raw.w);
}

static void fill_eari_guide(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	const float *r[5];
	for (int i = 0; i < 5; i++)
		r[i] = rc_get(&b->raw, y - 2 + i)[0];
	b->k->eari_guide(rows[0], r, ortho_kind(b->m, 0, y), ortho_kind(b->m, 1, y), b->eps_guide,
	                 0, c->w);
	if (b->rowsat) /* ratio-nr */
		saturated_binomial_row(b, y, r + 1, rows[0]);
}

/* Guided-filter coefficients of row k for the four channels: planes 0..3 = a_c, 4..7 = b_c. */
static void fill_ab_stage(ic_band *b, gf_stage *st, int k, float *const *rows)
{
	long w = st->ab.w, r = b->rad;
	double *vs = st->vs + r; /* index -r .. w+r-1 */
	if (st->vs_k != INT_MIN && k == st->vs_k + 1 && st->vs_age < PC_GF_RESET) {
		int out = k - (int)r - 1, in = k + (int)r;
		const float *g = rc_get(st->guide, out)[0], *rr = rc_get(&b->raw, out)[0];
		b->k->gf_vsum(vs, g, rr, out & 1, -1.0, -r, w + r, st->vs_stride);
		g = rc_get(st->guide, in)[0];
		rr = rc_get(&b->raw, in)[0];
		b->k->gf_vsum(vs, g, rr, in & 1, 1.0, -r, w + r, st->vs_stride);
		st->vs_age++;
	} else {
		memset(st->vs, 0, sizeof(double) * 8 * (size_t)st->vs_stride);
		for (int yy = k - (int)r; yy <= k + (int)r; yy++) {
			const float *g = rc_get(st->guide, yy)[0], *rr = rc_get(&b->raw, yy)[0];
			b->k->gf_vsum(vs, g, rr, yy & 1, 1.0, -r, w + r, st->vs_stride);
		}
		st->vs_age = 0;
	}
	st->vs_k = k;
	int ny[2] = {0, 0};
	for (int yy = k - (int)r; yy <= k + (int)r; yy++)
		ny[yy & 1]++;
	for (int py = 0; py < 2; py++) {
		unsigned ce = pc_dm_ch(b->m, 0, (unsigned)py), co = pc_dm_ch(b->m, 1, (unsigned)py);
		b->k->gf_ab2(rows[ce], rows[4 + ce], rows[co], rows[4 + co], vs, py, ny[py],
		             (float)b->eps2, w, st->vs_stride);
	}
}

static void fill_ab1(rcache *c, int k, float *const *rows)
{
	ic_band *b = c->ctx;
	fill_ab_stage(b, &b->s1, k, rows);
}

static void fill_ab2(rcache *c, int k, float *const *rows)
{
	ic_band *b = c->ctx;
	fill_ab_stage(b, &b->s2, k, rows);
}

/* Tentative estimates of row y (planes 0..3 = T_c) and the residual (plane 4). */
static void fill_t_stage(ic_band *b, gf_stage *st, int y, float *const *rows)
{
	long w = st->t.w, r = b->rad;
	float *sab[8];
	for (int p = 0; p < 8; p++)
		sab[p] = st->sab + (size_t)p * st->sab_pitch + r;
	if (st->sab_y != INT_MIN && y == st->sab_y + 1 && st->sab_age < PC_GF_RESET) {
		float *const *in = rc_get(&st->ab, y + (int)r);
		float *const *out = rc_get(&st->ab, y - (int)r - 1);
		for (int p = 0; p < 8; p++)
			b->k->acc(sab[p], in[p], out[p], -r, w + r);
		st->sab_age++;
	} else {
		for (int p = 0; p < 8; p++)
			memset(sab[p] - r, 0, sizeof(float) * ((size_t)w + 2 * r));
		for (int yy = y - (int)r; yy <= y + (int)r; yy++) {
			float *const *abr = rc_get(&st->ab, yy);
			for (int p = 0; p < 8; p++)
				b->k->acc(sab[p], abr[p], NULL, -r, w + r);
		}
		st->sab_age = 0;
	}
	st->sab_y = y;
	const float *g = rc_get(st->guide, y)[0];
	float inv_n = 1.0f / (float)((2 * r + 1) * (2 * r + 1));
	for (unsigned c4 = 0; c4 < 4; c4++)
		b->k->gf_t(rows[c4], sab[c4], sab[4 + c4], g, inv_n, w);
	const float *raw = rc_get(&b->raw, y)[0];
	b->k->resid(rows[4], raw, rows[pc_dm_ch(b->m, 0, (unsigned)y)],
	            rows[pc_dm_ch(b->m, 1, (unsigned)y)], w);
}

static void fill_t1(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	fill_t_stage(b, &b->s1, y, rows);
}

static void fill_t2(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	fill_t_stage(b, &b->s2, y, rows);
}

/* I_c = T_c + tent_c(E) for row y of a residual-interpolation stage into o[channel]. */
static void ri_output(ic_band *b, rcache *t, int y, float *const o[4])
{
	unsigned slot[4] = {pc_dm_ch(b->m, 0, (unsigned)y), pc_dm_ch(b->m, 1, (unsigned)y),
	                    pc_dm_ch(b->m, 0, (unsigned)y + 1), pc_dm_ch(b->m, 1, (unsigned)y + 1)};
	float *const *tm = rc_get(t, y - 1), *const *t0 = rc_get(t, y),
	             *const *tp = rc_get(t, y + 1);
	float *os[4];
	const float *ts[4];
	for (int k = 0; k < 4; k++) {
		os[k] = o[slot[k]];
		ts[k] = t0[slot[k]];
	}
	b->k->tent_add(os, ts, tm[4], t0[4], tp[4], t->w);
}

static void fill_out1(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ri_output(b, &b->s1.t, y, rows);
}

static void fill_guide2(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	float *const *o = rc_get(&b->out1, y);
	b->k->mean4(rows[0], o[0], o[1], o[2], o[3], c->w);
}

/* ---- ratio method ---- */
/* q = (raw + δ)/(guide + δ) of row y, the guide from cache gc (a pass's ratios) */
static void ratio_q_row(ic_band *b, rcache *gc, int y, float *row, long w)
{
	const float *g = rc_get(gc, y)[0];
	const float *r = rc_get(&b->raw, y)[0];
	b->k->ratio_q(row, r, g, b->delta, 0, w);
}

/* The next pass's guide of row y: the mean of the four channels of the pass whose ratios and
 * guide are in the caches q and gd (ratio-nr: its noise-aware multiplier) */
static void ratio_mean_row(ic_band *b, rcache *q, rcache *gd, int y, float *row, long w)
{
	/* other caches first: their fills may evict rows (pointers would dangle) */
	const float *qa = rc_get(q, y - 1)[0], *qb = rc_get(q, y)[0], *qc = rc_get(q, y + 1)[0];
	const float *ga = rc_get(gd, y - 1)[0], *g = rc_get(gd, y)[0], *gc = rc_get(gd, y + 1)[0];
	const float *r = rc_get(&b->raw, y)[0];
	if (b->nr)
		b->k->ratio_mean_nr(row, r, ga, g, gc, qa, qb, qc, b->delta, b->eps_ratio, b->shot,
		                    w);
	else
		b->k->ratio_mean(row, r, ga, g, gc, qa, qb, qc, b->delta, b->eps_ratio, w);
}

/* the first pass's ratios, the second pass's guide and ratios; ratio-nr3's third pass */
static void fill_rq1(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ratio_q_row(b, &b->guide, y, rows[0], c->w);
}

static void fill_rg2(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ratio_mean_row(b, &b->rq1, &b->guide, y, rows[0], c->w);
}

static void fill_rq2(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ratio_q_row(b, &b->rg2, y, rows[0], c->w);
}

static void fill_rg3(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ratio_mean_row(b, &b->rq2, &b->rg2, y, rows[0], c->w);
}

static void fill_rq3(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	ratio_q_row(b, &b->rg3, y, rows[0], c->w);
}

/* The ratio method's row y into o; mm: the limiter's ranges of rows y−2..y+2
 * (pc_dm_limit_ranges), applied as the row is written, or NULL. */
static void ratio_output(ic_band *b, int y, float *const o[4], const float *const mm[5])
{
	unsigned slot[4] = {pc_dm_ch(b->m, 0, (unsigned)y), pc_dm_ch(b->m, 1, (unsigned)y),
	                    pc_dm_ch(b->m, 0, (unsigned)y + 1), pc_dm_ch(b->m, 1, (unsigned)y + 1)};
	/* the last pass's ratios and guide: the second's, ratio-nr3's third */
	rcache *rq = b->three ? &b->rq3 : &b->rq2, *rg = b->three ? &b->rg3 : &b->rg2;
	const float *qa = rc_get(rq, y - 1)[0], *qb = rc_get(rq, y)[0], *qc = rc_get(rq, y + 1)[0];
	const float *ga = rc_get(rg, y - 1)[0], *g = rc_get(rg, y)[0], *gc = rc_get(rg, y + 1)[0];
	const float *r = rc_get(&b->raw, y)[0];
	float *os[4];
	for (int k = 0; k < 4; k++)
		os[k] = o[slot[k]];
	if (b->nr)
		b->k->ratio_out_nr(os, r, ga, g, gc, qa, qb, qc, mm, b->delta, b->eps_ratio,
		                   b->shot, b->raw.w);
	else
		b->k->ratio_out(os, r, ga, g, gc, qa, qb, qc, mm, b->delta, b->eps_ratio, b->raw.w);
}

/* ---- ratio-ri: ratio, then one residual-interpolation pass guided by its mean ---- */
static void fill_rout(rcache *c, int y, float *const *rows)
{
	ratio_output(c->ctx, y, rows, NULL);
}

static void fill_rguide(rcache *c, int y, float *const *rows)
{
	ic_band *b = c->ctx;
	float *const *o = rc_get(&b->rout, y);
	b->k->mean4(rows[0], o[0], o[1], o[2], o[3], c->w);
}

/* I_c = w·RI_c + (1 − w)·R_c, w = G⁺²/(G⁺² + d²), on row y (o holds RI; the reference is
 * ref_ratio_ri); every pixel's own channel keeps its sample. */
static void ratio_ri_blend(ic_band *b, int y, float *const o[4])
{
	unsigned slot[4] = {pc_dm_ch(b->m, 0, (unsigned)y), pc_dm_ch(b->m, 1, (unsigned)y),
	                    pc_dm_ch(b->m, 0, (unsigned)y + 1), pc_dm_ch(b->m, 1, (unsigned)y + 1)};
	const float *g = rc_get(&b->guide2, y)[0];
	float *const *r = rc_get(&b->rout, y);
	const float *raw = rc_get(&b->raw, y)[0];
	float *os[4];
	const float *rs[4];
	for (int k = 0; k < 4; k++) {
		os[k] = o[slot[k]];
		rs[k] = r[slot[k]];
	}
	b->k->ratio_ri_blend(os, rs, raw, g, b->dark * b->dark, b->raw.w);
}

/* The raw rows y−2..y+2 the limiter reads (valid until the next fill of another cache). */
static void raw_window(ic_band *b, int y, const float *r[5])
{
	for (int k = 0; k < 5; k++)
		r[k] = rc_get(&b->raw, y - 2 + k)[0];
}

/* ---- drivers ---- */
typedef struct ic_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	pc_demosaic_method method;
	double fs;
	pc_cpu_level level;
	const pc_fplane *out;
	const pc_dm_row_sink *sink; /* rows handed on instead of written to out */
	int planar, nt, err;
	int ntil;          /* an interleaved output streamed (pc_dm_stream_wanted_il) */
	double noise_gain; /* ratio-nr's noise gain (pc_dm_call) */
} ic_job;

/* The band's row caches (every one, initialised or not) into all */
#define BAND_NCACHES 16
static void band_caches(ic_band *b, rcache *all[BAND_NCACHES])
{
	rcache *const c[BAND_NCACHES] = {
	    &b->raw,   &b->p0,   &b->ppi, &b->guide, &b->out1, &b->guide2, &b->s1.ab, &b->s1.t,
	    &b->s2.ab, &b->s2.t, &b->rq1, &b->rg2,   &b->rq2,  &b->rout,   &b->rg3,   &b->rq3};
	memcpy(all, c, sizeof c);
}

static void free_band(ic_band *b)
{
	rcache *all[BAND_NCACHES];
	band_caches(b, all);
	for (size_t i = 0; i < BAND_NCACHES; i++)
		rc_free(all[i]);
	gf_stage *st[2] = {&b->s1, &b->s2};
	for (int i = 0; i < 2; i++) {
		pc_dm_free(st[i]->vs);
		pc_dm_free(st[i]->sab);
	}
	pc_dm_free(b->tmp);
	free(b->rowsat);
}

static int setup_band(ic_band *b, const ic_job *j)
{
	memset(b, 0, sizeof *b);
	b->in = j->in;
	b->m = j->m;
	b->k = kernels(j->level);
	long w = j->in->width;
	int h = (int)j->in->height;
	/* ratio-ri reads raw rows y−2 (the limiter) to y+9 (the ratio rows under its guide) */
	int fail = rc_init(&b->raw, j->method == PC_DM_RATIO_RI ? 16 : 12, 1, 3, w, h, fill_raw, b);
	b->tmp = pc_dm_alloc(sizeof(float) * 4 * ((size_t)w + 64));
	fail |= !b->tmp;
	switch (j->method) {
	case PC_DM_BICUBIC:
		break;
	case PC_DM_RATIO:
	case PC_DM_RATIO_NR:
	case PC_DM_RATIO_NR3:
	case PC_DM_RATIO_RI:
		/* the guide reads raw rows y±2 (ratio-nr3's binomial y±1), each ratio pass 2 rows
		 * y±1 around it: an output row reads the last pass's rows y±1, which read the pass
		 * before's y±2, ... (ratio-nr3: the first ratio rows y±3, the guide y±4) */
		if (j->method == PC_DM_RATIO_NR || j->method == PC_DM_RATIO_NR3) {
			b->nr = 1;
			b->shot = (float)j->noise_gain;
			if (j->method == PC_DM_RATIO_NR) { /* its guide where clipping splits */
				b->sat = (float)(j->fs + j->in->black_d) - j->in->black;
				b->rowsat = calloc((size_t)h, 1);
				fail |= !b->rowsat;
			}
		}
		b->three = j->method == PC_DM_RATIO_NR3;
		b->eps_guide = (float)(pc_eari_params.guide_eps * j->fs);
		b->delta = (float)(PC_RATIO_OFFSET * j->fs);
		b->eps_ratio = (float)(PC_RATIO_GUIDE_EPS * j->fs);
		fail |= rc_init(&b->guide, 8, 1, 1, w, h, b->three ? fill_p0 : fill_eari_guide, b);
		fail |= rc_init(&b->rq1, b->three ? 8 : 6, 1, 1, w, h, fill_rq1, b);
		fail |= rc_init(&b->rg2, 6, 1, 1, w, h, fill_rg2, b);
		fail |= rc_init(&b->rq2, b->three ? 6 : 4, 1, 1, w, h, fill_rq2, b);
		if (b->three) {
			fail |= rc_init(&b->rg3, 4, 1, 1, w, h, fill_rg3, b);
			fail |= rc_init(&b->rq3, 4, 1, 1, w, h, fill_rq3, b);
		}
		if (j->method != PC_DM_RATIO_RI)
			break;
		{
			/* then one guided-filter stage (as EARI's) on the ratio's mean: T rows y±1
			 * read coefficients y±3, which read the guide y±5 */
			const int kk = 2 * PC_GF_R + 4;
			gf_stage *st = &b->s1;
			b->rad = PC_GF_R;
			b->eps2 = (PC_RATIO_RI_EPS * j->fs) * (PC_RATIO_RI_EPS * j->fs);
			b->dark = (float)(PC_RATIO_RI_DARK * j->fs);
			b->passes = 1;
			fail |= rc_init(&b->rout, kk + 6, 4, 0, w, h, fill_rout, b);
			fail |= rc_init(&b->guide2, kk + 4, 1, 3, w, h, fill_rguide, b);
			st->guide = &b->guide2;
			st->vs_stride = w + 2 * PC_GF_R + 8;
			st->vs = pc_dm_alloc(sizeof(double) * 8 * (size_t)st->vs_stride);
			st->sab_pitch = (size_t)w + 2 * PC_GF_R + 16;
			st->sab = pc_dm_alloc(sizeof(float) * 8 * st->sab_pitch);
			st->vs_k = st->sab_y = INT_MIN;
			fail |= !st->vs || !st->sab;
			fail |= rc_init(&st->ab, kk, 8, PC_GF_R, w, h, fill_ab1, b);
			fail |= rc_init(&st->t, 5, 5, 1, w, h, fill_t1, b);
		}
		break;
	case PC_DM_PPID:
	case PC_DM_RI:
	case PC_DM_EARI: {
		const pc_ri_params *pr =
		    j->method == PC_DM_EARI ? &pc_eari_params : &pc_ri_params_default;
		b->eps_ppi = (float)(j->fs / 255.0);
		b->eps_guide = (float)(pr->guide_eps * j->fs);
		if (pr->radius != PC_GF_R)
			return -1;
		b->rad = pr->radius;
		b->eps2 = (pr->eps * j->fs) * (pr->eps * j->fs);
		int kk = 2 * pr->radius + 4;
		if (j->method != PC_DM_EARI) {
			fail |= rc_init(&b->p0, 8, 1, 3, w, h, fill_p0, b);
			fail |= rc_init(&b->ppi, kk + 4, 1, 3, w, h, fill_ppi, b);
		}
		if (j->method == PC_DM_PPID)
			break;
		if (j->method == PC_DM_EARI)
			fail |= rc_init(&b->guide, kk + 4, 1, 3, w, h, fill_eari_guide, b);
		b->passes = pr->passes;
		b->s1.guide = j->method == PC_DM_EARI ? &b->guide : &b->ppi;
		b->s2.guide = &b->guide2;
		gf_stage *st[2] = {&b->s1, &b->s2};
		rc_fill_fn fab[2] = {fill_ab1, fill_ab2}, ft[2] = {fill_t1, fill_t2};
		for (int i = 0; i < pr->passes && i < 2; i++) {
			st[i]->vs_stride = w + 2 * pr->radius + 8;
			st[i]->vs = pc_dm_alloc(sizeof(double) * 8 * (size_t)st[i]->vs_stride);
			st[i]->sab_pitch = (size_t)w + 2 * pr->radius + 16;
			st[i]->sab = pc_dm_alloc(sizeof(float) * 8 * st[i]->sab_pitch);
			st[i]->vs_k = st[i]->sab_y = INT_MIN;
			fail |= !st[i]->vs || !st[i]->sab;
			fail |= rc_init(&st[i]->ab, kk, 8, pr->radius, w, h, fab[i], b);
			fail |= rc_init(&st[i]->t, 5, 5, 1, w, h, ft[i], b);
		}
		if (pr->passes > 1) {
			fail |= rc_init(&b->out1, kk + 4, 4, 0, w, h, fill_out1, b);
			fail |= rc_init(&b->guide2, kk + 4, 1, 3, w, h, fill_guide2, b);
		}
		break;
	}
	default:
		break;
	}
	rcache *all[BAND_NCACHES];
	band_caches(b, all);
	for (size_t i = 0; i < BAND_NCACHES; i++)
		all[i]->pf = &b->pf;
	return fail ? -1 : 0;
}

static void ic_band_run(void *ctx, uint32_t y0, uint32_t y1)
{
	ic_job *j = ctx;
	ic_band b;
	long w = j->in->width;
	float *rowbuf = NULL;
	if (setup_band(&b, j) || !(rowbuf = pc_dm_alloc(sizeof(float) * 5 * ((size_t)w + 16)))) {
		free_band(&b);
		pc_dm_free(rowbuf);
		j->err = 1;
		return;
	}
	pc_dm_limiter limiter = {0, {0}, NULL, PC_CPU_BASELINE}, *lim = NULL;
	if (pc_dm_limited(j->method) && pc_dm_limiter_init(&limiter, w, j->level) == 0)
		lim = &limiter;
	if (pc_dm_limited(j->method) && !lim) {
		free_band(&b);
		pc_dm_free(rowbuf);
		j->err = 1;
		return;
	}
	float *vrow = rowbuf + 3; /* one padded row (pad 3) for the bicubic */
	float *obuf = rowbuf + (size_t)w + 16;
	for (uint32_t y = y0; y < y1; y++) {
		float *o[4];
		/* rows go straight into planar outputs, or through obuf (in cache) into strided
		 * outputs or, with non-temporal stores, into large aligned planes */
		for (unsigned c = 0; c < 4; c++)
			o[c] = j->planar && !j->nt && !j->sink
			           ? j->out[c].data + (size_t)y * j->out[c].row_stride
			           : obuf + (size_t)c * (size_t)w;
		int yy = (int)y;
		int limited = 0; /* the method's kernel applied the limiter as it wrote the row */
		switch (j->method) {
		case PC_DM_BICUBIC: {
			unsigned e0 = pc_dm_ch(j->m, 0, y), e1 = pc_dm_ch(j->m, 1, y);
			unsigned f0 = pc_dm_ch(j->m, 0, y + 1), f1 = pc_dm_ch(j->m, 1, y + 1);
			const float *self = rc_get(&b.raw, yy)[0];
			b.k->cubic_h(o[e0], o[e1], self, w);
			b.k->cubic4_rows(vrow, rc_get(&b.raw, yy - 3)[0], rc_get(&b.raw, yy - 1)[0],
			                 rc_get(&b.raw, yy + 1)[0], rc_get(&b.raw, yy + 3)[0], -3,
			                 w + 3);
			b.k->cubic_h(o[f0], o[f1], vrow, w);
			break;
		}
		case PC_DM_PPID: {
			/* D = raw − PPI on rows y-1..y+1, then I_c = PPI + tent_c(D) */
			float *d[3];
			for (int i = 0; i < 3; i++) {
				d[i] = b.tmp + (size_t)i * ((size_t)w + 16) + 2;
				const float *p = rc_get(&b.ppi, yy - 1 + i)[0];
				const float *raw = rc_get(&b.raw, yy - 1 + i)[0];
				b.k->sub(d[i], raw, p, -1, w + 1);
			}
			const float *p = rc_get(&b.ppi, yy)[0];
			unsigned slot[4] = {pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
			                    pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1)};
			float *os[4];
			const float *ts[4] = {p, p, p, p};
			for (int k = 0; k < 4; k++)
				os[k] = o[slot[k]];
			b.k->tent_add(os, ts, d[0], d[1], d[2], w);
			break;
		}
		case PC_DM_RI:
		case PC_DM_EARI:
			ri_output(&b, b.passes > 1 ? &b.s2.t : &b.s1.t, yy, o);
			break;
		case PC_DM_RATIO:
		case PC_DM_RATIO_NR:
		case PC_DM_RATIO_NR3: {
			/* limited as the row is written (ratio_out_blk), not by limit_row below */
			const float *r[5], *mm[5];
			raw_window(&b, yy, r);
			pc_dm_limit_ranges(lim, r, y, mm);
			ratio_output(&b, yy, o, mm);
			limited = 1;
			break;
		}
		case PC_DM_RATIO_RI:
			ri_output(&b, &b.s1.t, yy, o);
			ratio_ri_blend(&b, yy, o);
			break;
		default:
			break;
		}
		if (lim && !limited) {
			/* the overshoot limiter (demosaic_robust.c) on the finished row */
			const float *r[5];
			raw_window(&b, yy, r);
			pc_dm_limit_row(lim, j->m, r, y, o, 1);
		}
		if (j->sink) {
			const float *ch[4] = {o[0], o[1], o[2], o[3]};
			j->sink->row(j->sink->ctx, y, ch);
		} else if (j->nt) {
			float *dst[4];
			const float *src[4] = {o[0], o[1], o[2], o[3]};
			for (unsigned c = 0; c < 4; c++)
				dst[c] = j->out[c].data + (size_t)y * j->out[c].row_stride;
			pc_dm_stream_rows(dst, src, 4, (uint32_t)w, j->level);
		} else if (!j->planar) {
			const float *src[4] = {o[0], o[1], o[2], o[3]};
			pc_dm_put_rows(j->out, 4, y, src, 0, (uint32_t)w, j->level, j->ntil);
		}
	}
	if (j->ntil)
		pc_dm_sfence();
	free_band(&b);
	pc_dm_free(rowbuf);
	if (lim)
		pc_dm_limiter_free(lim);
}

/* Tapered row bands (pc_parallel_rows') of at least 64 rows, which keeps the recomputed halo
 * rows a small fraction. Two fixed bands a thread left one thread waiting whenever the host
 * slowed the other: on a noisy host `ratio-nr` 0.93-0.99 of the time per call (its median
 * 3-10 % lower), `ratio` 0.92, `eari` 0.96; the best call of each up to 2 % (`ratio` 7 %) slower
 * (docs/demosaicking.md, Round 33). */
static void run(ic_job *j, int threads)
{
	pc_parallel_rows_tapered(j->in->height, 64, threads, ic_band_run, j);
}

int pc_dm_ic(const pc_dm_call *call, const pc_fplane *out)
{
	ic_job j = {
	    call->in, call->m, call->method,    call->full_scale, call->level, out, NULL, 1, 0,
	    0,        0,       call->noise_gain};
	j.planar = pc_dm_planes_planar(out, 4);
	/* the method table says which methods keep ordinary stores (plain_stores) */
	const pc_dm_method_def *def = pc_dm_method_def_get(call->method);
	j.nt = j.planar && !(def && def->plain_stores) &&
	       pc_dm_stream_wanted(out, 4, call->in->width, call->in->height, call->level);
	j.ntil = pc_dm_stream_wanted_il(out, 4, call->in->width, call->in->height, call->level);
	run(&j, call->threads);
	return j.err ? pc_error(PC_ENOMEM, "row caches of %u-pixel rows", call->in->width) : 0;
}

int pc_dm_ic_rows(const pc_dm_call *call, const pc_dm_row_sink *sink)
{
	ic_job j = {
	    call->in, call->m, call->method,    call->full_scale, call->level, NULL, sink, 0, 0,
	    0,        0,       call->noise_gain};
	run(&j, call->threads);
	return j.err ? pc_error(PC_ENOMEM, "row caches of %u-pixel rows", call->in->width) : 0;
}
