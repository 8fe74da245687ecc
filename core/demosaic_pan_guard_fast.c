/* pan-guard's float fast path (docs/demosaicking.md, "Round 15 fast path: pan-guard" and
 * Round 16b): the definition is pc_dm_pan_guard_ref_with's (demosaic_pan_guard.c, its comment
 * states it); the same steps in float:
 *
 *  1. the base I_p straight into the output planes (pan-adapt's or pan-side's fast path, with
 *     its base, AVX2 and AVX-512 instances), over the whole frame;
 *  2. then, per band of output rows on a thread, a pipeline of rings that runs ahead of the
 *     output row:
 *     - the mirror-extended raw E (grid rows, one raw row converted each);
 *     - P̃ = max(P0, 0) + δ (pan-ratio's 5×5 PPI, separable: on integer raws every partial
 *       sum is an integer below 2^24, so exact) and the ratio ρ = (max(E, 0) + δ)/P̃;
 *     - per block row the leave-one-out errors e_b, e_p of its 2×2 blocks and their window
 *       sums along the row over the colour's own blocks (red and blue on one block lattice,
 *       green on two, the diagonal one with 2r blocks a side);
 *     - per block row the window sums down the rows and the weight w = 1/(1 + ((E_p + F)/
 *       (E_b + F))^γ) — the reference's (E_b + F)^γ/((E_b + F)^γ + (E_p + F)^γ) rearranged
 *       so that no power overflows a float;
 *     - per output row the conservative estimate I_b (bayer-first's one-pass rows,
 *       pc_dm_bayer_first_band_rows: docs Round 15d), the tent-interpolated W_k and the
 *       blend, in place in the outputs.
 *     A row of a ring is computed once per band (the band's first rows also compute the rows
 *     above it that they need), by the same float operations in the same order as the whole-
 *     frame version of Round 15 fast path, so the outputs do not depend on the bands (threads
 *     1 and 3 bit for bit). The row kernels are demosaic_pan_guard_kern.inc's, one instance
 *     per instruction-set level.
 *
 * The extended grid: columns and rows [−M, w + M) and [−M, h + M) (grid index x + M); blocks
 * (i, j) with corners (2i − XB, 2j − XB), i.e. grid column 2i + 8 and grid row 2j + 8. */
#include "demosaic_pan.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_color.h"
#include "demosaic_fast.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "simd.h"

/* pan-check's tents of one colour's four channels, as their lattices' row sums (channel c's
 * a[k·c + i], k the terms per channel) with their weights (c, likewise) and 1/Σ T (s[c]), for
 * the blends that compute them in their pass (gk_mix2t, gk_gmix) */
typedef struct gk_tsrc {
	const float *a[16];
	float c[16];
	float s[4];
} gk_tsrc;

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_pan_guard_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_pan_guard_kern.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "demosaic_pan_guard_kern.inc"
#include "simd_instance_end.h"
#endif

/* one instruction-set level's kernels */
typedef struct gk_fns {
	void (*ppi)(const float *, const float *, const float *, const float *, const float *, long,
	            float, float *, float *, float *);
	void (*sq)(const float *, const float *, const float *, const float *, const float *,
	           const float *, const float *, const float *, const float *, const float *,
	           const float *, long, long, const float *, const float *, float, float *,
	           float *);
	void (*blocks)(const float *, const float *, const float *, const float *, long, long,
	               float *, float *);
	void (*hsum)(const float *, long, int, int, float *);
	void (*add)(float *, const float *, const float *, long);
	void (*acc)(float *, const float *, long);
	void (*weight)(const float *, const float *, const float *, const float *, long,
	               const float *, const float *, float, int, float, float *, float *, float *);
	void (*vtent)(const float *, const float *, float, float, long, float *);
	void (*htent)(const float *, long, long, float *, float *);
	void (*wsel1)(const float *, const float *, const float *, const float *, long, float,
	              float *);
	void (*wsel2)(const float *, const float *, const float *, const float *, const float *,
	              const float *, long, float, float *);
	void (*mix0)(float *, float *, float *, float *, const float *, const float *,
	             const float *, const float *, const float *, long);
	void (*mix2)(float *, float *, float *, float *, const float *, const float *,
	             const float *, const float *, const float *, const float *, long);
	void (*fac1)(const float *, const float *, const float *, const float *, const float *,
	             const float *, const float *, const float *, const float *, float, float *,
	             long);
	void (*mix1)(float *, const float *, float, long);
	void (*trow)(const float *, long, float *, float *, float *, float *, float *);
	void (*tcomb)(const float *, const float *, const float *, const float *, float, float,
	              float, float, float, long, float *);
	void (*tcomb2)(const float *, const float *, float, float, float, long, float *);
	void (*gmod)(const float *, const float *, const float *, const float *, const float *,
	             long, float *, float *, float *, float *);
	void (*cmu)(const float *, const float *, long, long, float, float, float, const float *,
	            const float *, float, const float *, float *, float *, float *, float *);
	void (*gsel)(const float *, const float *, const float *, const float *, const float *,
	             long, long, int, float *, float *, float *);
	void (*gate)(const float *, const float *, const float *, const float *, const float *,
	             long, long, const double *, int, float *, double *, double *, float *);
	void (*mix2t)(float *, float *, float *, float *, const gk_tsrc *, const float *,
	              const float *, long);
	void (*gmix)(float *, float *, float *, float *, const float *, const gk_tsrc *,
	             const float *, long);
	void (*vtent2)(const float *, const float *, const float *, const float *, float, float,
	               long, float *, float *);
	void (*htent2)(const float *, const float *, long, long, float *, float *, float *,
	               float *);
	void (*wsel1x2)(const float *, const float *, const float *, const float *, const float *,
	                const float *, long, float, float *, float *);
} gk_fns;

#define GK_FNS(s)                                                                                  \
	{                                                                                          \
		gk_ppi_##s, gk_sq_##s, gk_blocks_##s, gk_hsum_##s, gk_add_##s, gk_acc_##s,         \
		    gk_weight_##s, gk_vtent_##s, gk_htent_##s, gk_wsel1_##s, gk_wsel2_##s,         \
		    gk_mix0_##s, gk_mix2_##s, gk_fac1_##s, gk_mix1_##s, gk_trow_##s, gk_tcomb_##s, \
		    gk_tcomb2_##s, gk_gmod_##s, gk_cmu_##s, gk_gsel_##s, gk_gate_##s,              \
		    gk_mix2t_##s, gk_gmix_##s, gk_vtent2_##s, gk_htent2_##s, gk_wsel1x2_##s        \
	}

#ifdef PC_CPU_X86
static const gk_fns gk_base = GK_FNS(base), gk_avx2 = GK_FNS(avx2), gk_avx512 = GK_FNS(avx512);
#else
/* other processors have the generic instance only */
static const gk_fns gk_base = GK_FNS(base);
#define gk_avx2   gk_base
#define gk_avx512 gk_base
#endif

/* rows kept per ring: E and P̃, ρ span at most 12 and 10 rows around a block row (its
 * samples' neighbours ±4, P̃'s ±2 more); the output rows' tents read 4 block rows */
enum { GF_RE = 16, GF_RW = 8 };

typedef struct guard_fast {
	const pc_dm_input *in;
	const pc_mosaic *m;
	pc_cpu_level level;
	const gk_fns *k;
	uint32_t w, h;
	int XB, M, W;      /* blocks' margin; the grid's margin and row length */
	int NBX, NBY;      /* blocks */
	int RH;            /* rows of the window-sum ring, a power of two >= 4r + 1 */
	unsigned kc[4][4]; /* colour (0 R, 1 G, 2 B) at column phase u, row phase v: kc[v][u] */
	float delta, fl;   /* δ; the floor F = (floor·FS)² */
	int r, mode;
	float gamma;
	int gi;      /* γ as an integer when it is one (powers by squaring), else 0 */
	float force; /* < 0: the weights computed */
	/* pan-check's additions (pc_dm_pan_guard_fast_run's chk; NULL: none) */
	const pc_dm_guard_check *chk;
	float nk[3]; /* the noise term per block colour */
	int gate;    /* pan-hue's gate on */
	/* the tents: channel q's lattices (u, v), q at column phase u and row phase v, in raster
	 * order (at most two kept: gf_tent_src's 2·nql[q] terms) */
	unsigned char ql[12][2][2], nql[12];
	float tinv[12]; /* 1 / Σ T of channel q (1/16 red and blue, 1/32 green) */
	int32_t *xmap;  /* grid column → raw column (pc_mirror4) */
	float *qf, *nf; /* column x's block-column phase ((x + 1) >> 1) & 1, and 1 minus it */
	/* the kernels' lane choices as rows of 0 and 1 (gf_pat): per grid column x (px) and per
	 * block column i (pi), each 0, 1, the parity ((x >> 1) & 1, i & 1) and 1 minus it */
	const float *px[4], *pi[4];
	atomic_int err;       /* a band's scratch not allocated */
	const pc_fplane *out; /* I_p in, the result out */
} guard_fast;

/* One band's rings and rows. Ring rows are keyed by grid row (E, P̃, ρ) or block row (the
 * rest) modulo the ring's size; *_next is the next row each stage computes. */
typedef struct gf_band {
	float *mem;
	float *e, *pt, *rho;       /* GF_RE rows of W (E's with pc_dm_row_to_float's ±1 columns) */
	float *vs, *qb[2], *qp[2]; /* W: vertical sums; squared errors of a block row's two rows */
	float *eb, *ep;            /* one block row's errors, 2r zeros either side */
	float *hs[4];              /* RH rows each: window sums along the rows, hb0 hp0 hb1 hp1 */
	float *sb[4], *q, *t;      /* window sums down (own lattice b p, both lattices b p); pow */
	float *wb;                 /* GF_RW rows of weights */
	float *A[2], *P[4], *wr[3], *fr; /* the tents; W_k per colour; mode 1's factor */
	float *ib;                       /* I_b: 12 rows of w */
	int e_next, r_next, h_next, w_next;
	int e_first; /* E's first grid row in this band */
	pc_dm_bf_band *bf;
	/* pan-check's (cmem): the blocks' e_b, e_p (before the noise term), mu (RH block rows
	 * each), the gates (GF_RW block rows), D_k of red and blue and 1 − D_k; the tents' raw rows
	 * (keyed by raw row, 4 mirrored columns either side: tr) tent-summed along the
	 * rows per column phase (th: GF_RT raw rows of four, keyed by raw row) and the twelve tent
	 * rows; tr one raw row and gk_trow's rows of each phase's samples (4⌈w/4⌉ + 8 floats, at
	 * most gf_up(w + 8)) */
	float *cmem;
	float *ce, *cp, *cm, *gt, *cs[5], *dr[2], *om, *th, *tr, *tn;
	float *AD[2], *PD[4]; /* D_k's tents, as A and P */
	float *gd;            /* gk_gsel's five rows of n + 2, then gk_gate's four */
	double *gq;           /* gk_gate's q and t */
	float *gr;            /* gk_gate's gates */
	int t_next;
} gf_band;

enum { GF_RT = 8 };

static size_t gf_up(size_t n)
{
	return (n + 15) / 16 * 16;
}

static int gf_band_init(gf_band *b, const guard_fast *g)
{
	memset(b, 0, sizeof *b);
	const size_t W = gf_up((size_t)g->W), nxp = gf_up((size_t)g->NBX + 4 * (size_t)g->r + 8),
	             wp = gf_up((size_t)g->w + 8);
	const size_t total = 3 * GF_RE * W + 5 * W + 2 * nxp +
	                     (4 * (size_t)g->RH + 4 + 2 + GF_RW + 2) * nxp + (4 + 3 + 1 + 12) * wp;
	b->mem = pc_dm_alloc(sizeof(float) * total);
	b->bf = pc_dm_bayer_first_band_new(g->in, g->m, g->level);
	if (!b->mem || !b->bf) {
		pc_dm_free(b->mem);
		pc_dm_bayer_first_band_free(b->bf);
		return -1;
	}
	memset(b->mem, 0, sizeof(float) * total);
	float *p = b->mem;
	b->e = p;
	p += GF_RE * W;
	b->pt = p;
	p += GF_RE * W;
	b->rho = p;
	p += GF_RE * W;
	b->vs = p;
	p += W;
	for (int i = 0; i < 2; i++) {
		b->qb[i] = p;
		p += W;
		b->qp[i] = p;
		p += W;
	}
	/* the errors' rows with 2r zeros before block 0 (and after the last) */
	b->eb = p + 2 * g->r + 1;
	p += nxp;
	b->ep = p + 2 * g->r + 1;
	p += nxp;
	for (int i = 0; i < 4; i++) {
		b->hs[i] = p;
		p += (size_t)g->RH * nxp;
	}
	for (int i = 0; i < 4; i++) {
		b->sb[i] = p;
		p += nxp;
	}
	b->q = p;
	p += nxp;
	b->t = p;
	p += nxp;
	b->wb = p;
	p += GF_RW * nxp;
	for (int i = 0; i < 2; i++) {
		b->A[i] = p;
		p += nxp;
	}
	for (int i = 0; i < 4; i++) {
		b->P[i] = p;
		p += wp;
	}
	for (int i = 0; i < 3; i++) {
		b->wr[i] = p;
		p += wp;
	}
	b->fr = p;
	p += wp;
	b->ib = p;
	if (!g->chk)
		return 0;
	const size_t wt = gf_up((size_t)g->w + 8);
	const size_t ctot = (3 * (size_t)g->RH + GF_RW + 5 + 5 + 3 + 2) * nxp + (3 + 4) * wp +
	                    (4 * GF_RT + 2) * wt + 12 * wp;
	b->cmem = pc_dm_alloc(sizeof(float) * ctot);
	if (!b->cmem) {
		pc_dm_free(b->mem);
		pc_dm_bayer_first_band_free(b->bf);
		return -1;
	}
	memset(b->cmem, 0, sizeof(float) * ctot);
	p = b->cmem;
	b->ce = p;
	p += (size_t)g->RH * nxp;
	b->cp = p;
	p += (size_t)g->RH * nxp;
	b->cm = p;
	p += (size_t)g->RH * nxp;
	b->gt = p;
	p += GF_RW * nxp;
	for (int i = 0; i < 5; i++) {
		b->cs[i] = p;
		p += nxp;
	}
	b->gd = p;
	p += 5 * nxp;
	b->gq = (double *)(void *)p; /* q, t: nxp/2 doubles each (nxp a multiple of 16) */
	p += 2 * nxp;
	b->gr = p;
	p += nxp;
	for (int i = 0; i < 2; i++) {
		b->dr[i] = p;
		p += wp;
	}
	b->om = p;
	p += wp;
	for (int i = 0; i < 2; i++) {
		b->AD[i] = p;
		p += nxp;
	}
	for (int i = 0; i < 4; i++) {
		b->PD[i] = p;
		p += wp;
	}
	b->th = p;
	p += 4 * GF_RT * wt;
	b->tr = p;
	p += 2 * wt;
	b->tn = p;
	return 0;
}

static void gf_band_fini(gf_band *b)
{
	pc_dm_free(b->cmem);
	pc_dm_free(b->mem);
	pc_dm_bayer_first_band_free(b->bf);
}

static size_t gf_nxp(const guard_fast *g)
{
	return gf_up((size_t)g->NBX + 4 * (size_t)g->r + 8);
}

static float *gf_ring(float *base, int row, int size, size_t pitch)
{
	return base + (size_t)(row & (size - 1)) * pitch;
}

#define GF_E(b, g, gy)   gf_ring((b)->e, (gy), GF_RE, gf_up((size_t)(g)->W))
#define GF_PT(b, g, gy)  gf_ring((b)->pt, (gy), GF_RE, gf_up((size_t)(g)->W))
#define GF_RHO(b, g, gy) gf_ring((b)->rho, (gy), GF_RE, gf_up((size_t)(g)->W))

/* the rows of 0 and 1 of the lane choice c = g0 ^ (parity & (g0 ^ g1)) (*c) and of 1 − c (*n),
 * from rows (g->px or g->pi) */
static void gf_pat(const float *const rows[4], int g0, int g1, const float **c, const float **n)
{
	const int a = g0 == g1 ? g0 : g0 ? 3 : 2, b = g0 == g1 ? 1 - g0 : g0 ? 2 : 3;
	*c = rows[a];
	*n = rows[b];
}

/* E's grid rows up to gy: the raw at the pc_mirror4 positions (the phase kept) */
static void gf_ext_to(const guard_fast *g, gf_band *b, int gy)
{
	const int W = g->W, M = g->M, wi = (int)g->w, we = 2 * (wi / 2);
	for (; b->e_next <= gy; b->e_next++) {
		const int y = b->e_next - M;
		float *d = GF_E(b, g, b->e_next);
		pc_dm_row_to_float(g->in, (uint32_t)pc_mirror4(y, (int)g->h), d + M);
		/* the columns [0, 2⌊w/2⌋) are their own mirror, and every mirror falls in them */
		for (int x = 0; x < M; x++)
			d[x] = d[M + g->xmap[x]];
		for (int x = M + we; x < W; x++)
			d[x] = d[M + g->xmap[x]];
	}
}

/* P̃ and ρ up to grid row gy */
static void gf_ppi_to(const guard_fast *g, gf_band *b, int gy)
{
	for (; b->r_next <= gy; b->r_next++) {
		const int j = b->r_next;
		gf_ext_to(g, b, j + 2);
		g->k->ppi(GF_E(b, g, j - 2), GF_E(b, g, j - 1), GF_E(b, g, j), GF_E(b, g, j + 1),
		          GF_E(b, g, j + 2), g->W, g->delta, b->vs, GF_PT(b, g, j),
		          GF_RHO(b, g, j));
	}
}

/* pan-check: the colour of block (i, j) (the blocks' corners are a multiple of 4 from the
 * frame's, XB = 4 + 4r) */
static unsigned gf_col(const guard_fast *g, int i, int j)
{
	return g->kc[(2 * j - g->XB) & 3][(2 * i - g->XB) & 3];
}

/* pan-check: block row jb's e_b, e_p and mu = mean of max(raw, 0) + δ over the block's samples
 * (grid rows gy, gy + 1) into the rings, then the noise term n_k·mu added to e_p */
static void gf_check_blocks(const guard_fast *g, gf_band *b, int jb, int gy)
{
	const size_t nxp = gf_nxp(g);
	const int nx = g->NBX;
	const float *e0 = GF_E(b, g, gy), *e1 = GF_E(b, g, gy + 1), d = g->delta;
	float *ce = gf_ring(b->ce, jb, g->RH, nxp), *cp = gf_ring(b->cp, jb, g->RH, nxp),
	      *cm = gf_ring(b->cm, jb, g->RH, nxp);
	g->k->cmu(e0, e1, 8, nx, d, g->nk[gf_col(g, 0, jb)], g->nk[gf_col(g, 1, jb)], g->pi[2],
	          g->pi[3], (float)g->chk->beta, b->eb, b->ep, ce, cp, cm);
}

/* pan-check: s = the sum of the n rows r[0..n) in their order (n = 0: zeros) */
static void gf_colsum(const guard_fast *g, float *s, const float *const *r, int n)
{
	const int nx = g->NBX;
	if (n == 0) {
		memset(s, 0, sizeof(float) * (size_t)nx);
	} else if (n == 1) {
		memcpy(s, r[0], sizeof(float) * (size_t)nx);
	} else {
		g->k->add(s, r[0], r[1], nx);
		for (int t = 2; t < n; t++)
			g->k->acc(s, r[t], nx);
	}
}

/* pan-check: pan-hue's gate of block row j's red and blue blocks (pc_dm_pan_hue_gates' formulas
 * on the float blocks, the ratios and the power in double) into the gate ring; green's 0. The
 * blocks' colours are a Bayer pattern (gf_run checks): around a red or blue block its own colour
 * is at even offsets (di, dj), green where di + dj is odd, the other colour (which the gate does
 * not read) at both odd. The window's sums of mu and e_b come from column sums over the window's
 * even rows (cs[0] mu, cs[1] e_b) and odd rows (cs[2] mu). The q-quantile needs the order
 * statistics lo and lo + 1 of green's residuals max(e_p − c·5g·m_G, 0)·rel², a nondecreasing
 * function of e_p: they are those of the e_p, kept by a bounded insertion, then mapped. */
static void gf_gate_row(const guard_fast *g, gf_band *b, int j)
{
	const size_t nxp = gf_nxp(g);
	const int rb = 2 * g->r, nx = g->NBX, ny = g->NBY;
	const pc_dm_guard_check *c = g->chk;
	float *out = gf_ring(b->gt, j, GF_RW, nxp);
	enum { NW = (4 * PC_DM_PAN_HUE_RMAX + 1) * (4 * PC_DM_PAN_HUE_RMAX + 1) };
	const float *cp[4 * PC_DM_PAN_HUE_RMAX + 1];
	float *sm = b->cs[0], *se = b->cs[1], *so = b->cs[2];
	const int j0 = j - rb > 0 ? j - rb : 0, j1 = j + rb < ny - 1 ? j + rb : ny - 1;
	/* the column sums in row order (the first row's values kept, x + 0 = x for these sums
	 * of non-negative values), by the add and acc kernels */
	const float *rm[2][4 * PC_DM_PAN_HUE_RMAX + 1], *re[4 * PC_DM_PAN_HUE_RMAX + 1];
	int nro = 0, nre = 0;
	for (int jj = j0; jj <= j1; jj++) {
		const float *m = gf_ring(b->cm, jj, g->RH, nxp);
		cp[jj - j0] = gf_ring(b->cp, jj, g->RH, nxp);
		if ((jj - j) & 1) {
			rm[1][nro++] = m;
			continue;
		}
		rm[0][nre] = m;
		re[nre++] = gf_ring(b->ce, jj, g->RH, nxp);
	}
	gf_colsum(g, sm, rm[0], nre);
	gf_colsum(g, se, re, nre);
	gf_colsum(g, so, rm[1], nro);
	const double thr0 = c->hnoise * 5 * c->g;
	const int c0 = gf_col(g, 0, j) != 1 ? 0 : 1; /* the parity of the row's red or blue */
	/* r = 1 with the window inside the grid: the blocks i in [2, nx − 3] by gk_gsel (their
	 * order statistics in cs[3], cs[4], indexed by (i − iv0)/2) and gk_gate */
	const int lo12 = (int)(c->quant * 11), vec = rb == 2 && j >= 2 && j + 2 < ny && lo12 <= 2;
	const int iv0 = c0 + 2 > 2 ? c0 + 2 : 2,
	          nvk = vec && nx - 3 >= iv0 ? (nx - 3 - iv0) / 2 + 1 : 0;
	/* green: no gate; its blocks iv0 + 2k + 1 beside gk_gate's are zeroed with them below */
	for (int i = 1 - c0; i < nx; i += 2) {
		if (nvk && i == iv0 + 1) {
			i = iv0 + 2 * nvk - 1;
			continue;
		}
		out[i] = 0;
	}
	if (nvk) {
		g->k->gsel(cp[0], cp[1], cp[2], cp[3], cp[4], iv0, nvk, lo12, b->gd, b->cs[3],
		           b->cs[4]);
		/* and the rest of their gate (the loop below's, in the same order): nk and ng as
		 * it counts them (the window's three columns of each lattice) */
		const int nk = 3 * nre, ng = 3 * ((j1 - j0 + 1) - nre) + 2 * nre;
		const double pos = c->quant * (ng - 1);
		const double pr[7] = {nk, ng, pos - (int)pos, thr0, c->kappa, g->fl, g->gamma};
		const size_t nq = nxp / 2;
		g->k->gate(sm, se, so, b->cs[3], b->cs[4], iv0, nvk, pr, g->gi, b->gd, b->gq,
		           b->gq + nq, b->gr);
		float *restrict o = out + iv0;
		const float *restrict gr = b->gr;
		for (int k = 0; k < nvk; k++) {
			o[2 * k] = gr[k];
			o[2 * k + 1] = 0;
		}
	}
	for (int i = c0; i < nx; i += 2) {
		if (nvk && i == iv0) { /* gk_gate's: i = iv0 + 2k, k < nvk */
			i = iv0 + 2 * (nvk - 1);
			continue;
		}
		out[i] = 0;
		const int i0 = i - rb > 0 ? i - rb : 0, i1 = i + rb < nx - 1 ? i + rb : nx - 1;
		const int se0 = i0 + ((i0 - i) & 1), so0 = i0 + !((i0 - i) & 1);
		double mk = 0, mg = 0, ek = 0;
		int nk = 0, ng = 0;
		for (int ii = se0; ii <= i1; ii += 2) {
			mk += sm[ii];
			ek += se[ii];
			mg += so[ii];
			nk += nre;
			ng += (j1 - j0 + 1) - nre;
		}
		for (int ii = so0; ii <= i1; ii += 2) {
			mg += sm[ii];
			ng += nre;
		}
		if (!ng)
			continue;
		/* green's e_p: odd rows at even di, even rows at odd di; the lo + 2 smallest */
		const double pos = c->quant * (ng - 1);
		const int lo = (int)pos, nkeep = lo + 2 < ng ? lo + 2 : ng;
		float v[NW];
		int nv = 0;
		for (int jj = j0; jj <= j1; jj++) {
			const float *p = cp[jj - j0];
			for (int ii = ((jj - j) & 1) ? se0 : so0; ii <= i1; ii += 2) {
				const float e = p[ii];
				if (nv == nkeep && !(e < v[nv - 1]))
					continue;
				int t = nv < nkeep ? nv++ : nv - 1;
				while (t > 0 && v[t - 1] > e) {
					v[t] = v[t - 1];
					t--;
				}
				v[t] = e;
			}
		}
		mk /= nk;
		mg /= ng;
		const double rel = mk / mg, thr = thr0 * mg;
		const double a = (double)v[lo] - thr, qa = a > 0 ? a : 0;
		double vq = qa;
		if (lo + 1 < ng) {
			const double bq = (double)v[lo + 1] - thr;
			vq = qa + (pos - lo) * ((bq > 0 ? bq : 0) - qa);
		}
		vq *= rel * rel;
		const double x = c->kappa * vq, y = ek / nk + g->fl;
		if (!(x > 0))
			continue;
		double t = 1, q = y / x;
		if (g->gi)
			for (int e = g->gi; e; e >>= 1) {
				if (e & 1)
					t *= q;
				q *= q;
			}
		else
			t = pow(q, (double)g->gamma);
		out[i] = (float)(1 / (1 + t));
	}
}

/* the window sums along the block rows up to j: the errors of the row's blocks (its two sample
 * rows' squared errors, then per block), then their sums over the offsets |di| <= 2r of even
 * parity (the own lattice: hs[0], hs[1]) and of odd parity (green's diagonal one: hs[2],
 * hs[3]) */
static void gf_hsum_to(const guard_fast *g, gf_band *b, int j)
{
	const size_t nxp = gf_nxp(g);
	const int rb = 2 * g->r, nx = g->NBX;
	for (; b->h_next <= j; b->h_next++) {
		const int jb = b->h_next, gy = 2 * jb + 8, by = 2 * jb - g->XB;
		gf_ppi_to(g, b, gy + 5);
		/* the colour of the row's blocks at even and odd block columns (bx ≡ 0, 2 mod 4) */
		const int g0 = g->kc[by & 3][0] == 1, g1 = g->kc[by & 3][2] == 1;
		const float *gr, *nr;
		gf_pat(g->px, g0, g1, &gr, &nr);
		for (int o = 0; o < 2; o++) {
			const int sy = gy + o;
			g->k->sq(GF_E(b, g, sy), GF_E(b, g, sy - 4), GF_E(b, g, sy + 4),
			         GF_E(b, g, sy - 2), GF_E(b, g, sy + 2), GF_RHO(b, g, sy),
			         GF_RHO(b, g, sy - 4), GF_RHO(b, g, sy + 4), GF_RHO(b, g, sy - 2),
			         GF_RHO(b, g, sy + 2), GF_PT(b, g, sy), 8, 8 + 2 * (long)nx, gr, nr,
			         g->delta, b->qb[o], b->qp[o]);
		}
		g->k->blocks(b->qb[0], b->qb[1], b->qp[0], b->qp[1], 8, nx, b->eb, b->ep);
		if (g->chk)
			gf_check_blocks(g, b, jb, gy);
		for (int l = 0; l < 2; l++) {
			g->k->hsum(b->eb, nx, rb, l, gf_ring(b->hs[2 * l], jb, g->RH, nxp));
			g->k->hsum(b->ep, nx, rb, l, gf_ring(b->hs[2 * l + 1], jb, g->RH, nxp));
		}
	}
}

/* the weights of the block rows up to j: the window sums down the rows (the own lattice at even
 * row offsets |dj| <= 2r, for green also the diagonal lattice's at odd ones, |dj| <= 2r − 1),
 * clipped at the block grid's edge as the reference's */
static void gf_weight_to(const guard_fast *g, gf_band *b, int j)
{
	const size_t nxp = gf_nxp(g);
	const int rb = 2 * g->r, nx = g->NBX, ny = g->NBY;
	for (; b->w_next <= j; b->w_next++) {
		const int jw = b->w_next, by = 2 * jw - g->XB;
		gf_hsum_to(g, b, jw + rb < ny ? jw + rb : ny - 1);
		for (int l = 0; l < 2; l++) {
			/* the rows in order, the diagonal lattice's after the own one's: n of them
			 * so far; the first's sums kept in place, the second added to them */
			float *sb = b->sb[2 * l], *sp = b->sb[2 * l + 1];
			const float *fb = l ? b->sb[0] : NULL, *fp = l ? b->sb[1] : NULL;
			int n = l;
			for (int dj = -rb + l; dj <= rb - l; dj += 2) {
				const int jj = jw + dj;
				if (jj < 0 || jj >= ny)
					continue;
				const float *hb = gf_ring(b->hs[2 * l], jj, g->RH, nxp),
				            *hp = gf_ring(b->hs[2 * l + 1], jj, g->RH, nxp);
				if (n == 0) {
					fb = hb;
					fp = hp;
				} else if (n == 1) {
					g->k->add(sb, fb, hb, nx);
					g->k->add(sp, fp, hp, nx);
				} else {
					g->k->acc(sb, hb, nx);
					g->k->acc(sp, hp, nx);
				}
				n++;
			}
			if (n == 1) { /* one row (l = 0) or no diagonal one (l = 1): the first's */
				memcpy(sb, fb, sizeof(float) * (size_t)nx);
				memcpy(sp, fp, sizeof(float) * (size_t)nx);
			}
		}
		const int g0 = g->kc[by & 3][0] == 1, g1 = g->kc[by & 3][2] == 1;
		const float *gr, *nr;
		gf_pat(g->pi, g0, g1, &gr, &nr);
		g->k->weight(b->sb[0], b->sb[1], b->sb[2], b->sb[3], nx, gr, nr, g->fl, g->gi,
		             g->gamma, b->q, b->t, gf_ring(b->wb, jw, GF_RW, nxp));
		if (g->gate)
			gf_gate_row(g, b, jw);
	}
}

/* colour k's pairs 2p + s at block-column phase q = 0, 1 (si[q][0], and si[q][1] for green):
 * the colour of pair (s, p) at phase q is kc[(by0 + 2p) & 3][2(q ^ s)] */
static void gf_tent_sel(const guard_fast *g, int by0, unsigned k, int si[2][2])
{
	for (int q = 0; q < 2; q++) {
		int n = 0;
		si[q][0] = si[q][1] = 0;
		for (int p = 0; p < 2; p++)
			for (int s = 0; s < 2; s++)
				if (g->kc[(by0 + 2 * p) & 3][2 * (q ^ s)] == k && n < 2)
					si[q][n++] = 2 * p + s;
	}
}

/* W_k of output row y into b->wr[k] and, with pan-check's gate, D_k of red and blue into
 * b->dr, the gates' tents in the same passes as the weights' (gk_vtent2, gk_htent2,
 * gk_wsel1x2). The tent T = T_x·T_y on the block centres is separable: the row's four block
 * rows t (by = by0 + 2t) weigh T_y(t), the vertical sums A_p[i] = Σ_{t ≡ p (mod 2)}
 * T_y(t)·w(i, j_t) of the two block-row parities p, then per pixel the four block columns s with
 * T_x(s); the four parity pairs (s mod 2, p) are the colour blocks' Bayer pattern (red, blue and
 * two greens), and every pair's T sums to (T_x(s) + T_x(s + 2))·(T_y(p) + T_y(p + 2)) = 8·8 (the
 * tents {1, 5, 7, 3} or {3, 7, 5, 1}), so W_k = Σ/64 (green: Σ/128). The same weights as the
 * reference's sum over the sixteen blocks, in another order. */
static void gf_tent_vals(const guard_fast *g, gf_band *b, int y)
{
	const size_t nxp = gf_nxp(g);
	const long w = (long)g->w;
	const int by0 = (y - 3) & ~1, j0 = (by0 + g->XB) / 2, gate = g->gate;
	float ty[4];
	const float *wb[4], *gb[4];
	for (int t = 0; t < 4; t++) {
		ty[t] = (float)(8 - abs(2 * (by0 + 2 * t - y) + 1));
		wb[t] = gf_ring(b->wb, j0 + t, GF_RW, nxp);
		gb[t] = gate ? gf_ring(b->gt, j0 + t, GF_RW, nxp) : NULL;
	}
	for (int p = 0; p < 2; p++)
		if (gate)
			g->k->vtent2(wb[p], wb[p + 2], gb[p], gb[p + 2], ty[p], ty[p + 2], g->NBX,
			             b->A[p], b->AD[p]);
		else
			g->k->vtent(wb[p], wb[p + 2], ty[p], ty[p + 2], g->NBX, b->A[p]);
	/* P[2p + s]: the pair (block column parity s relative to i0, block row parity p) */
	const long nm = (w + 1) / 2, c = g->XB / 2 - 2;
	for (int p = 0; p < 2; p++)
		if (gate)
			g->k->htent2(b->A[p], b->AD[p], nm, c, b->P[2 * p], b->P[2 * p + 1],
			             b->PD[2 * p], b->PD[2 * p + 1]);
		else
			g->k->htent(b->A[p], nm, c, b->P[2 * p], b->P[2 * p + 1]);
	for (unsigned k = 0; k < 3; k++) {
		int si[2][2];
		gf_tent_sel(g, by0, k, si);
		if (k == 1)
			g->k->wsel2(b->P[si[0][0]], b->P[si[0][1]], b->P[si[1][0]], b->P[si[1][1]],
			            g->qf, g->nf, w, 1.0f / 128, b->wr[1]);
		else if (gate)
			g->k->wsel1x2(b->P[si[0][0]], b->P[si[1][0]], b->PD[si[0][0]],
			              b->PD[si[1][0]], g->qf, g->nf, w, 1.0f / 64, b->wr[k],
			              b->dr[k / 2]);
		else
			g->k->wsel1(b->P[si[0][0]], b->P[si[1][0]], g->qf, g->nf, w, 1.0f / 64,
			            b->wr[k]);
	}
}

/* W_k of output row y into b->wr[k] and, with pan-check's gate, D_k of red and blue into
 * b->dr */
static void gf_tent_row(const guard_fast *g, gf_band *b, int y)
{
	const int j0 = (((y - 3) & ~1) + g->XB) / 2;
	gf_weight_to(g, b, j0 + 3);
	gf_tent_vals(g, b, y);
}

/* raw row pc_mirror4(t, h) from E's ring, its column x at [x] for x in [−4, w + 4) (mirrored by
 * pc_mirror4 outside [0, w)), while the ring holds it (gf_tent_row runs E ahead of the output
 * rows), else NULL: E's grid row t + M. Even widths only: at an odd one E's column w − 1 is
 * pc_mirror4's, not the raw's (gf_ext_to). */
static const float *gf_e_row(const guard_fast *g, const gf_band *b, int t)
{
	const int gy = t + g->M;
	if (!(g->w & 1) && gy >= b->e_first && gy < b->e_next && gy >= b->e_next - GF_RE)
		return GF_E(b, g, gy) + g->M;
	return NULL;
}

/* channel q's tent at output row y from its lattices' row sums (gf_tents_row): the rows a[0..n)
 * weighed c[0..n), two per lattice (n = 2 red and blue, 4 green on imx250myr) */
static int gf_tent_src(const guard_fast *g, const gf_band *b, int y, unsigned q, const float *a[4],
                       float c[4])
{
	const size_t wt = gf_up((size_t)g->w + 8);
	int n = 0;
	for (unsigned l = 0; l < g->nql[q]; l++) {
		const int u = g->ql[q][l][0], v = g->ql[q][l][1], d0 = (v - y) & 3;
		a[n] = b->th + ((size_t)((y + d0) & (GF_RT - 1)) * 4 + (size_t)u) * wt;
		c[n++] = (float)(4 - d0);
		a[n] = b->th + ((size_t)((y + d0 - 4) & (GF_RT - 1)) * 4 + (size_t)u) * wt;
		c[n++] = (float)d0;
	}
	return n;
}

/* colour k's four channels' tent sources at row y into ts, n terms each */
static void gf_tent_srcs(const guard_fast *g, const gf_band *b, int y, unsigned k, int n,
                         gk_tsrc *ts)
{
	for (unsigned c = 0; c < 4; c++) {
		const float *a[4];
		float cf[4];
		const int nc = gf_tent_src(g, b, y, 4 * k + c, a, cf);
		assert(nc == n);
		(void)nc;
		for (int i = 0; i < n; i++) {
			ts->a[n * (int)c + i] = a[i];
			ts->c[n * (int)c + i] = cf[i];
		}
		ts->s[c] = g->tinv[4 * k + c];
	}
}

/* pan-check's tents of output row y (pc_dm_pan_guard_tents in float: exact sums on integer
 * raws) into b->tn, of the channels q whose bit is set in make (the others' the blends compute
 * from the row sums: gk_mix2t, gk_gmix). The tent T = (4 − |dx|)(4 − |dy|) is separable and
 * pc_mirror4 keeps the phase mod 4, so: each raw row (once, mirrored, keyed by its unmirrored
 * index) summed along the row per column phase u, h_u (gk_trow); then channel q at row y from its
 * lattices (u, v): the rows y + dy of phase v within ±3, dy = d0 and d0 − 4 with d0 = (v − y) mod
 * 4, weighing 4 − d0 and d0 (gk_tcomb), over Σ T = 16 per lattice */
static void gf_tents_row(const guard_fast *g, gf_band *b, int y, unsigned make)
{
	const int w = (int)g->w;
	const size_t wt = gf_up((size_t)w + 8), wp = gf_up((size_t)w + 8);
	for (; b->t_next <= y + 3; b->t_next++) {
		/* E's row, mirrored by pc_mirror4 as here (columns −4 .. w + 3), while E's ring
		 * keeps it; else the row converted */
		const float *d = gf_e_row(g, b, b->t_next);
		if (!d) {
			float *dc = b->tr + 4;
			pc_dm_row_to_float(g->in, (uint32_t)pc_mirror4(b->t_next, (int)g->h), dc);
			for (int x = -4; x < 0; x++)
				dc[x] = dc[pc_mirror4(x, w)];
			for (int x = w; x < w + 4; x++)
				dc[x] = dc[pc_mirror4(x, w)];
			d = dc;
		}
		float *h = b->th + (size_t)(b->t_next & (GF_RT - 1)) * 4 * wt;
		g->k->trow(d, w, b->tr + wt, h, h + wt, h + 2 * wt, h + 3 * wt);
	}
	for (unsigned q = 0; q < 12; q++) {
		if (!(make >> q & 1))
			continue;
		const float *a[4];
		float c[4];
		const int n = gf_tent_src(g, b, y, q, a, c);
		if (n == 2)
			g->k->tcomb2(a[0], a[1], c[0], c[1], g->tinv[q], w, b->tn + q * wp);
		else
			g->k->tcomb(a[0], a[1], a[2], a[3], c[0], c[1], c[2], c[3], g->tinv[q], w,
			            b->tn + q * wp);
	}
}

/* pan-check's conservative estimate of row y (cons 5): red and blue the tents' (b->tn), green
 * bayer-first's analyser mean (pc_dm_bayer_first_band_gmean, into I_b's first row: the red rows
 * are not read with cons 5) plus the tents' modulation, in b->ib's green rows; the channels
 * not in make and, with fuse_g, green's modulation left to the blends */
static void gf_cons5_row(const guard_fast *g, gf_band *b, int y, unsigned make, int fuse_g)
{
	const size_t wp = gf_up((size_t)g->w + 8);
	const int w = (int)g->w;
	gf_tents_row(g, b, y, make);
	float *bg = b->ib + 4 * wp, *mb = b->ib;
	const float *tg = b->tn + 4 * wp;
	/* the green mean's raw rows y − 3 .. y + 3 lent from E where it has them (E's row r is
	 * pc_mirror4's, row r itself except the last of an odd height) */
	for (int r = y - 3; r <= y + 3; r++) {
		const float *e = r >= 0 && pc_mirror4(r, (int)g->h) == r ? gf_e_row(g, b, r) : NULL;
		if (e)
			pc_dm_bayer_first_band_put_row(b->bf, (uint32_t)r, e);
	}
	pc_dm_bayer_first_band_gmean(b->bf, (uint32_t)y, mb);
	if (!fuse_g)
		g->k->gmod(mb, tg, tg + wp, tg + 2 * wp, tg + 3 * wp, w, bg, bg + wp, bg + 2 * wp,
		           bg + 3 * wp);
}

/* output rows [y0, y1): I_b, W_k and the blend, in place */
static void gf_band_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	guard_fast *g = ctx;
	gf_band b;
	if (gf_band_init(&b, g)) {
		atomic_store(&g->err, 1);
		return;
	}
	const uint32_t w = g->w;
	const size_t wp = gf_up((size_t)w + 8);
	/* the first block row the band's first output row reads, and what that needs */
	const int j0 = (((int)y0 - 3) & ~1) / 2 + g->XB / 2;
	b.w_next = j0;
	b.h_next = j0 - 2 * g->r > 0 ? j0 - 2 * g->r : 0;
	b.r_next = 2 * b.h_next + 8 - 4;
	b.e_next = b.r_next - 2;
	b.e_first = b.e_next;
	b.t_next = (int)y0 - 3;
	pc_fplane ibp[12];
	for (unsigned q = 0; q < 12; q++)
		ibp[q] = (pc_fplane){b.ib + q * wp, wp, 1};
	/* pan-check's cons 5 on planar outputs in mode 0: the blends compute the tents of red and
	 * blue (with the gate: gk_mix2t) and green's I_b (gk_gmix) from the tents' row sums, where
	 * every channel of the colour has the same number of lattices (two terms each for red and
	 * blue, four for green, as gk_tcomb2 and gk_tcomb) */
	const int cons5 = g->chk && g->chk->cons5, gate = g->gate && g->force < 0;
	int planar = 1;
	for (unsigned q = 0; q < 12; q++)
		planar &= g->out[q].pixel_stride == 1;
	int fuse_rb = cons5 && planar && !g->mode && gate, fuse_g = cons5 && planar && !g->mode;
	for (unsigned q = 0; cons5 && q < 12; q++) { /* gf_tent_src's terms: 2·nql[q] */
		if (q / 4 == 1)
			fuse_g &= g->nql[q] == 2;
		else
			fuse_rb &= g->nql[q] == 1;
	}
	const unsigned make = (fuse_rb ? 0x0f0u : 0xfffu) & (fuse_g ? 0xf0fu : 0xfffu);
	for (uint32_t yu = y0; yu < y1; yu++) {
		const int y = (int)yu;
		if (g->force >= 0) {
			for (int k = 0; k < 3; k++)
				for (uint32_t x = 0; x < w; x++)
					b.wr[k][x] = g->force;
		} else {
			gf_tent_row(g, &b, y);
		}
		if (cons5)
			gf_cons5_row(g, &b, y, make, fuse_g);
		else
			pc_dm_bayer_first_band_rows(b.bf, yu, yu + 1, ibp);
		for (unsigned k = 0; k < 3; k++) {
			float *d[4];
			const float *vbr[4];
			size_t ps[4];
			for (unsigned c = 0; c < 4; c++) {
				const pc_fplane *o = &g->out[4 * k + c];
				d[c] = o->data + (size_t)y * o->row_stride;
				ps[c] = o->pixel_stride;
				vbr[c] = (g->chk && g->chk->cons5 && k != 1 ? b.tn : b.ib) +
				         (size_t)(4 * k + c) * wp;
			}
			const float *wk = b.wr[k];
			/* pan-check's gate of red and blue: 1 − D_k */
			const int gk = gate && k != 1;
			if (ps[0] == 1 && ps[1] == 1 && ps[2] == 1 && ps[3] == 1) {
				if (g->mode) {
					g->k->fac1(d[0], d[1], d[2], d[3], vbr[0], vbr[1], vbr[2],
					           vbr[3], wk, g->delta, b.fr, w);
					for (unsigned c = 0; c < 4; c++)
						g->k->mix1(d[c], b.fr, g->delta, w);
				} else if (k == 1 && fuse_g) {
					gk_tsrc ts;
					gf_tent_srcs(g, &b, y, k, 4, &ts);
					g->k->gmix(d[0], d[1], d[2], d[3], b.ib, &ts, wk, w);
				} else if (gk && fuse_rb) {
					gk_tsrc ts;
					gf_tent_srcs(g, &b, y, k, 2, &ts);
					g->k->mix2t(d[0], d[1], d[2], d[3], &ts, wk, b.dr[k / 2],
					            w);
				} else if (gk) {
					g->k->mix2(d[0], d[1], d[2], d[3], vbr[0], vbr[1], vbr[2],
					           vbr[3], wk, b.dr[k / 2], w);
				} else {
					g->k->mix0(d[0], d[1], d[2], d[3], vbr[0], vbr[1], vbr[2],
					           vbr[3], wk, w);
				}
				continue;
			}
			if (gk)
				for (uint32_t x = 0; x < w; x++)
					b.om[x] = 1 - b.dr[k / 2][x];
			for (uint32_t x = 0; x < w; x++) {
				float vp[4], vb[4];
				for (unsigned c = 0; c < 4; c++) {
					vp[c] = d[c][x * ps[c]];
					vb[c] = vbr[c][x];
				}
				if (g->mode) {
					const float s_p =
					                (((vp[0] + vp[1]) + vp[2]) + vp[3]) * 0.25f,
					            s_b =
					                (((vb[0] + vb[1]) + vb[2]) + vb[3]) * 0.25f,
					            f = (1 - wk[x]) * (s_b - s_p) /
					                ((s_p > 0 ? s_p : 0.0f) + g->delta);
					for (unsigned c = 0; c < 4; c++)
						d[c][x * ps[c]] =
						    vp[c] +
						    f * ((vp[c] > 0 ? vp[c] : 0.0f) + g->delta);
				} else {
					for (unsigned c = 0; c < 4; c++) {
						float o = wk[x] * vp[c] + (1 - wk[x]) * vb[c];
						if (gk)
							o = b.om[x] * o + (1 - b.om[x]) * vb[c];
						d[c][x * ps[c]] = o;
					}
				}
			}
		}
	}
	gf_band_fini(&b);
}

/* The fast path with the definition's parameters as arguments (mode: 0 every channel
 * blended, 1 the colour's analyser mean) */
static int gf_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                  pc_cpu_level level, int base, int r, double gamma, double floor, int mode,
                  double force, double gain, const pc_dm_guard_check *chk, const pc_fplane *out)
{
	const uint32_t w = in->width, h = in->height;
	guard_fast g;
	memset(&g, 0, sizeof g);
	atomic_init(&g.err, 0);
	g.in = in;
	g.m = m;
	g.level = level;
	g.k = level >= PC_CPU_AVX512 ? &gk_avx512 : level >= PC_CPU_AVX2 ? &gk_avx2 : &gk_base;
	g.w = w;
	g.h = h;
	g.XB = 4 + 4 * r;
	g.M = g.XB + 6 + 2; /* the samples' ±(XB + 5), P̃'s two more */
	g.W = (int)w + 2 * g.M;
	g.NBX = ((int)w + 2 * g.XB) / 2;
	g.NBY = ((int)h + 2 * g.XB) / 2;
	g.RH = 1;
	while (g.RH < 4 * r + 1)
		g.RH *= 2;
	for (unsigned v = 0; v < 4; v++)
		for (unsigned u = 0; u < 4; u++)
			g.kc[v][u] = (unsigned)(pc_mosaic_color(m, u, v) - PC_CFA_R);
	/* W_k's tents take the blocks' colours as a Bayer pattern (gf_tent_row): at each block
	 * phase one red, one blue and two green blocks among the four parity pairs */
	for (unsigned v = 0; v < 4; v += 2)
		for (unsigned u = 0; u < 4; u += 2) {
			unsigned n[3] = {0, 0, 0};
			for (unsigned p = 0; p < 4; p += 2)
				for (unsigned s = 0; s < 4; s += 2)
					n[g.kc[(v + p) & 3][(u + s) & 3]]++;
			if (n[0] != 1 || n[1] != 2 || n[2] != 1)
				return pc_error(PC_ENOTSUP, "pan-guard fast path: the colour "
				                            "blocks are not a Bayer pattern");
		}
	g.delta = (float)(PC_DM_PAN_ADAPT_DFS * fs);
	g.fl = (float)((floor * fs) * (floor * fs));
	g.r = r;
	g.mode = mode;
	g.gamma = (float)gamma;
	g.gi = gamma >= 1 && gamma <= 64 && gamma == (double)(int)gamma ? (int)gamma : 0;
	g.force = (float)force;
	g.out = out;
	g.chk = chk;
	if (chk) {
		for (unsigned k = 0; k < 3; k++)
			g.nk[k] = (float)chk->noise[k];
		g.gate = chk->kappa > 0;
		unsigned nq[12] = {0};
		for (unsigned v = 0; v < 4; v++)
			for (unsigned u = 0; u < 4; u++) {
				const unsigned q =
				    4 * (unsigned)(pc_mosaic_color(m, u, v) - PC_CFA_R) +
				    pc_mosaic_channel(m, u, v);
				nq[q]++;
				if (g.nql[q] < 2) {
					g.ql[q][g.nql[q]][0] = (unsigned char)u;
					g.ql[q][g.nql[q]++][1] = (unsigned char)v;
				}
			}
		for (unsigned q = 0; q < 12; q++)
			g.tinv[q] = nq[q] ? 1.0f / (16.0f * (float)nq[q]) : 0.0f;
	}
	g.xmap = malloc(sizeof(int32_t) * (size_t)g.W);
	const size_t wu = gf_up((size_t)w), gu = gf_up((size_t)g.W), bu = gf_up((size_t)g.NBX);
	g.qf = pc_dm_alloc(sizeof(float) * (2 * wu + 4 * gu + 4 * bu));
	if (!g.xmap || !g.qf) {
		free(g.xmap);
		pc_dm_free(g.qf);
		return pc_error(PC_ENOMEM, "pan-guard: column maps of width %u", w);
	}
	for (int x = 0; x < g.W; x++)
		g.xmap[x] = pc_mirror4(x - g.M, (int)w);
	g.nf = g.qf + wu;
	for (uint32_t x = 0; x < w; x++) {
		g.qf[x] = (float)(((x + 1) >> 1) & 1);
		g.nf[x] = 1.0f - g.qf[x];
	}
	for (int k = 0; k < 4; k++) {
		float *rx = g.nf + wu + (size_t)k * gu, *ri = g.nf + wu + 4 * gu + (size_t)k * bu;
		for (int x = 0; x < g.W; x++) {
			const float v = k < 2 ? (float)k : (float)((x >> 1) & 1);
			rx[x] = k == 3 ? 1.0f - v : v;
		}
		for (int i = 0; i < g.NBX; i++) {
			const float v = k < 2 ? (float)k : (float)(i & 1);
			ri[i] = k == 3 ? 1.0f - v : v;
		}
		g.px[k] = rx;
		g.pi[k] = ri;
	}
	/* 1. the base into the outputs (pan-adapt with the given noise gain, < 0 its own
	 * estimate) */
	int rc = base ? pc_dm_pan_adapt_fast_g(in, m, fs, threads, level, gain, out)
	              : pc_dm_pan_side_fast(in, m, fs, threads, level, out);
	/* 2. the guard in bands of at least 64 rows (each band recomputes ≈ 14 + 4r rows of its
	 * rings above its first row) */
	if (!rc) {
		const int nt = threads > 0 ? threads : pc_parallel_max_threads();
		uint32_t band = h / (uint32_t)(4 * nt);
		if (band < 64)
			band = 64;
		pc_parallel_rows(h, band, threads, gf_band_rows, &g);
		if (atomic_load(&g.err))
			rc = pc_error(PC_ENOMEM, "pan-guard: row buffers for width %u", w);
	}
	free(g.xmap);
	pc_dm_free(g.qf);
	return rc;
}

int pc_dm_pan_guard_fast_with(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                              pc_cpu_level level, const pc_dm_pan_guard_params *p,
                              const pc_fplane *out)
{
	int rc = pc_dm_pan_guard_check(p);
	if (rc)
		return rc;
	if (p->unshrink != 0)
		return pc_error(PC_ENOTSUP, "pan-guard fast path: no unshrink (the reference's)");
	if (p->cons != 0)
		return pc_error(PC_ENOTSUP, "pan-guard fast path: only bayer-first as the "
		                            "conservative estimate (cons 0)");
	return gf_run(in, m, fs, threads, level, p->base, p->r, p->gamma, p->floor, p->mode,
	              p->force, p->g, NULL, out);
}

int pc_dm_pan_guard_fast_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                             pc_cpu_level level, const pc_dm_pan_guard_params *p,
                             const pc_dm_guard_check *chk, const pc_fplane *out)
{
	return gf_run(in, m, fs, threads, level, p->base, p->r, p->gamma, p->floor, p->mode,
	              p->force, p->g, chk, out);
}

int pc_dm_pan_guard_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out)
{
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	return pc_dm_pan_guard_fast_with(in, m, fs, threads, level, &p, out);
}

int pc_dm_pan_guard_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           pc_cpu_level level, double g, const pc_fplane *out)
{
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	p.g = g;
	return pc_dm_pan_guard_fast_with(in, m, fs, threads, level, &p, out);
}
