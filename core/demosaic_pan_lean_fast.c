/* pan-lean's float fast path (docs/demosaicking.md, Round 21; the definition and every formula:
 * pc_dm_pan_lean_ref_g in demosaic_pan.c, constants in demosaic_pan.h). A first, plain form:
 * whole-frame planes for the mirror-extended raw, P0 and the ratios ρ, the block quantities
 * (hue, P̃, the four side factors) at block rate in double, then per row band the horizontal
 * tents of ρ and of the raw for every column phase (rows y − 3 .. y + 3 of each chunk of output
 * rows) and the output rows. Written for the compiler to vectorise (every inner loop runs over
 * x with per-row constant channel maps, the row loops compiled once per instruction-set level:
 * demosaic_pan_lean_kern.inc). Correct against the reference (tests/test_demosaic.c,
 * test_pan_fast) but not yet the budget's form: its whole-frame planes (about 120 MB of fresh
 * pages a call) and its block pass in double make it far slower than pan-side's fast path
 * (docs/demosaicking.md, Round 21: the plan for a band form like pan_band's).
 *
 * The channel of a tent term depends only on the tap row's phase and the column phase s: the
 * tap of column phase s on row y′ is the lattice position (x − ((x − s) mod 4), y′), whose
 * channel is the mosaic's at (s, y′) mod 4 (the sub-image mirror keeps phases). So per output
 * row each (dy, s) adds to one fixed channel, for every x. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_common.h"
#include "demosaic_noise.h"
#include "demosaic_pan.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "simd.h"

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_pan_lean_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_pan_lean_kern.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "demosaic_pan_lean_kern.inc"
#include "simd_instance_end.h"
#endif

/* one instance's loops */
typedef struct lf_kern {
	void (*tents)(const float *, const float *, const float *, const float *, int, long,
	              float *, float *);
	void (*acc)(float *, float *, const float *, const float *, const float *, float, long);
	void (*norm)(float *, float *, const float *, const float *, float, float, float, long);
	void (*levels)(const float *const[12], const float *const[12], const float *, const float *,
	               float, float, float, long, float *, float *);
	void (*out)(const float *, const float *, const float *, const float *, const float *,
	            const float *, const float *, float, float, float, long, float *);
} lf_kern;

#define LF_KERN(sfx)                                                                               \
	(lf_kern)                                                                                  \
	{                                                                                          \
		lf_tents_##sfx, lf_acc_##sfx, lf_norm_##sfx, lf_levels_##sfx, lf_out_##sfx         \
	}

static lf_kern lf_kernels(pc_cpu_level level)
{
#ifdef PC_CPU_X86
	if (level >= PC_CPU_AVX512)
		return LF_KERN(avx512);
	if (level >= PC_CPU_AVX2)
		return LF_KERN(avx2);
#else
	(void)level;
#endif
	return LF_KERN(base);
}

#define LF_X     8  /* the extended planes' margin: the raw's reach (support ±8) */
#define LF_CHUNK 32 /* output rows per chunk of a band */

typedef struct lf_job {
	const pc_dm_input *in;
	uint32_t w, h;
	int ew, eh;    /* extended planes: (w + 2X) × (h + 2X) */
	float *e, *p0; /* extended raw (minus black) and P0 */
	float *rho;    /* ρ on the extended grid */
	int bw, bh;    /* block grid of the extended planes: corners at even extended x, y */
	float *fw, *fe, *fn, *fs; /* per block: the side factors W, E, N, S */
	double delta, g, F;
	unsigned q4[4][4]; /* channel at (x mod 4, y mod 4) */
	const pc_fplane *out;
	lf_kern K;
	int err;
} lf_job;

static size_t eidx(const lf_job *j, int x, int y)
{
	return (size_t)(y + LF_X) * (size_t)j->ew + (size_t)(x + LF_X);
}

/* block index of pixel (x, y)'s block (x, y in frame coordinates, may be negative) */
static size_t bidx(const lf_job *j, int x, int y)
{
	return (size_t)((y + LF_X) >> 1) * (size_t)j->bw + (size_t)((x + LF_X) >> 1);
}

/* extended raw rows [y0, y1) (frame rows − X .. h + X mapped to band rows) */
static void lf_extend(void *ctx, uint32_t r0, uint32_t r1)
{
	lf_job *j = ctx;
	float *buf = malloc(sizeof(float) * (j->w + 2)), *row = buf + 1; /* row[-1], row[w] too */
	if (!buf) {
		j->err = 1;
		return;
	}
	for (uint32_t r = r0; r < r1; r++) {
		const int y = (int)r - LF_X;
		pc_dm_row_to_float(j->in, (uint32_t)pc_mirror4(y, (int)j->h), row);
		float *d = j->e + eidx(j, 0, y);
		memcpy(d, row, sizeof(float) * j->w);
		for (int x = 1; x <= LF_X; x++) { /* the margins, mirrored */
			d[-x] = row[pc_mirror4(-x, (int)j->w)];
			d[(int)j->w - 1 + x] = row[pc_mirror4((int)j->w - 1 + x, (int)j->w)];
		}
	}
	free(buf);
}

/* P0 = raw ∗ (m ⊗ m)/64, m = [1 2 2 2 1], and ρ, on extended rows [r0, r1) within ±6 */
static void lf_p0(void *ctx, uint32_t r0, uint32_t r1)
{
	lf_job *j = ctx;
	const int lo = -LF_X + 2, hi = (int)j->w + LF_X - 2;
	const float dl = (float)j->delta;
	for (uint32_t r = r0; r < r1; r++) {
		const int y = (int)r - LF_X + 2;
		float *p = j->p0 + eidx(j, 0, y), *rh = j->rho + eidx(j, 0, y);
		const float *a = j->e + eidx(j, 0, y - 2), *b = j->e + eidx(j, 0, y - 1),
		            *c = j->e + eidx(j, 0, y), *d = j->e + eidx(j, 0, y + 1),
		            *f = j->e + eidx(j, 0, y + 2);
		for (int x = lo; x < hi; x++) {
			float v[5];
			for (int i = 0; i < 5; i++) {
				const int xx = x + i - 2;
				v[i] = a[xx] + f[xx] + 2 * (b[xx] + c[xx] + d[xx]);
			}
			p[x] = (v[0] + v[4] + 2 * (v[1] + v[2] + v[3])) * (1.0f / 64);
			rh[x] = ((c[x] > 0 ? c[x] : 0.0f) + dl) / ((p[x] > 0 ? p[x] : 0.0f) + dl);
		}
	}
}

/* the block quantities of block rows [r0, r1): hue u and P̃ at the corners (double), then the
 * factors need the neighbours ±1 block: computed by lf_factors */
typedef struct lf_blk {
	double u1, u2, pt;
} lf_blk;

typedef struct lf_bjob {
	lf_job *j;
	lf_blk *b;
} lf_bjob;

static void lf_blocks(void *ctx, uint32_t r0, uint32_t r1)
{
	lf_bjob *bj = ctx;
	lf_job *j = bj->j;
	static const double mk[5] = {1, 2, 2, 2, 1};
	for (uint32_t br = r0; br < r1; br++) {
		const int y = 2 * (int)br - LF_X;
		if (y < -LF_X + 2 || y >= (int)j->h + LF_X - 2)
			continue;
		for (int bc = 0; bc < j->bw; bc++) {
			const int x = 2 * bc - LF_X;
			if (x < -LF_X + 2 || x >= (int)j->w + LF_X - 2)
				continue;
			double p0 = 0, c1 = 0, c2 = 0;
			for (int jj = -2; jj <= 2; jj++)
				for (int ii = -2; ii <= 2; ii++) {
					double v = mk[ii + 2] * mk[jj + 2] *
					           j->e[eidx(j, x + ii, y + jj)] / 64;
					unsigned k = j->q4[(x + ii) & 3][(y + jj) & 3] / 4;
					p0 += v;
					c1 += k == 0 ? v : k == 2 ? -v : 0;
					c2 += k == 1 ? v : -v;
				}
			lf_blk *o = &bj->b[(size_t)br * (size_t)j->bw + (size_t)bc];
			const double pt = fmax(p0, 0) + j->delta;
			o->pt = pt;
			o->u1 = PC_DM_PAN_CB * c1 / pt;
			o->u2 = PC_DM_PAN_CB * c2 / pt;
		}
	}
}

static double lf_d(const lf_blk *a, const lf_blk *b)
{
	return fabs(a->u1 - b->u1) + fabs(a->u2 - b->u2) +
	       PC_DM_PAN_LEAN_MU * fabs(a->pt - b->pt) / fmin(a->pt, b->pt);
}

static void lf_pair(double d0, double d1, double eps, float *f0, float *f1)
{
	const double e = eps + PC_DM_PAN_LEAN_KT * fmin(d0, d1);
	const double a0 = 1 / ((e + d0) * (e + d0)), a1 = 1 / ((e + d1) * (e + d1));
	*f0 = (float)(2 * a0 / (a0 + a1));
	*f1 = (float)(2 * a1 / (a0 + a1));
}

static void lf_factors(void *ctx, uint32_t r0, uint32_t r1)
{
	lf_bjob *bj = ctx;
	lf_job *j = bj->j;
	for (uint32_t br = r0; br < r1; br++) {
		const int y = 2 * (int)br - LF_X;
		if (y < -LF_X + 4 || y >= (int)j->h + LF_X - 4)
			continue;
		for (int bc = 2; bc < j->bw - 2; bc++) {
			const int x = 2 * bc - LF_X;
			if (x < -LF_X + 4 || x >= (int)j->w + LF_X - 4)
				continue;
			const size_t i = (size_t)br * (size_t)j->bw + (size_t)bc;
			const lf_blk *c = &bj->b[i];
			const double p = c->pt - j->delta;
			const double eps =
			    PC_DM_PAN_SEPS + PC_DM_PAN_LEAN_KN * sqrt(j->g * (p + j->F)) / c->pt;
			lf_pair(lf_d(c, &bj->b[i - 1]), lf_d(c, &bj->b[i + 1]), eps, &j->fw[i],
			        &j->fe[i]);
			lf_pair(lf_d(c, &bj->b[i - (size_t)j->bw]),
			        lf_d(c, &bj->b[i + (size_t)j->bw]), eps, &j->fn[i], &j->fs[i]);
		}
	}
}

/* the horizontal tents of extended row y for the four column phases: hr[s][x] (ρ) and
 * hx[s][x] (the raw), x in [0, w); fwr, fer scratch rows for the factors per column */
static void lf_hrow(const lf_job *j, int y, float *const hr[4], float *const hx[4], float *fwr,
                    float *fer)
{
	const long w = (long)j->w;
	const float *rh = j->rho + eidx(j, 0, y), *ev = j->e + eidx(j, 0, y);
	const float *fw = j->fw + bidx(j, 0, y), *fe = j->fe + bidx(j, 0, y);
	for (long x = 0; x < w; x++) {
		fwr[x] = fw[x >> 1];
		fer[x] = fe[x >> 1];
	}
	for (int s = 0; s < 4; s++)
		j->K.tents(rh, ev, fwr, fer, s, w, hr[s], hx[s]);
}

/* Output rows [y0, y1) (one band): per chunk of LF_CHUNK rows the tents of its rows ± 3, then
 * per output row each channel's sums R_q and A_q (its (dy, s) terms fixed per row), the levels
 * and the twelve outputs. */
static void lf_out_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	lf_job *j = ctx;
	const size_t w = j->w;
	const size_t rowsz = 8 * w;
	/* scratch rows: R_q, A_q (24), fN, fS, two factor rows, pt, lo, an output row; then the
	 * own-channel and own-colour indicator rows of the four row phases (2 × 4 × 12) */
	float *hb = malloc(sizeof(float) * (LF_CHUNK + 6) * rowsz),
	      *sc = malloc(sizeof(float) * (31 + 96) * w);
	if (!hb || !sc) {
		j->err = 1;
		free(hb);
		free(sc);
		return;
	}
	const float dl = (float)j->delta, gF = (float)j->F;
	const float cgs = (float)(PC_DM_PAN_LEAN_CS * j->g),
	            cga = (float)(PC_DM_PAN_LEAN_CA * j->g);
	float *R[12], *A[12], *fnr = sc + 24 * w, *fsr = sc + 25 * w, *t0 = sc + 26 * w,
	                      *t1 = sc + 27 * w, *pt = sc + 28 * w, *lo = sc + 29 * w,
	                      *orow = sc + 30 * w;
	const float *sel[4][12], *same[4][12];
	for (int q = 0; q < 12; q++) {
		R[q] = sc + (size_t)q * w;
		A[q] = sc + (size_t)(12 + q) * w;
	}
	for (int yp = 0; yp < 4; yp++)
		for (unsigned q = 0; q < 12; q++) {
			float *a = sc + (31 + (size_t)(24 * yp) + q) * w, *b = a + 12 * w;
			for (size_t x = 0; x < w; x++) {
				const unsigned ow = j->q4[x & 3][yp];
				a[x] = ow == q ? 1.0f : 0.0f;
				b[x] = ow / 4 == q / 4 ? 1.0f : 0.0f;
			}
			sel[yp][q] = a;
			same[yp][q] = b;
		}
	for (uint32_t c0 = y0; c0 < y1; c0 += LF_CHUNK) {
		const uint32_t c1 = c0 + LF_CHUNK < y1 ? c0 + LF_CHUNK : y1;
		for (int yy = (int)c0 - 3; yy < (int)c1 + 3; yy++) {
			float *base = hb + (size_t)(yy - ((int)c0 - 3)) * rowsz, *hr[4], *hx[4];
			for (int s = 0; s < 4; s++) {
				hr[s] = base + (size_t)s * w;
				hx[s] = base + (size_t)(4 + s) * w;
			}
			lf_hrow(j, yy, hr, hx, t0, t1);
		}
		for (uint32_t y = c0; y < c1; y++) {
			const float *fn = j->fn + bidx(j, 0, (int)y),
			            *fs = j->fs + bidx(j, 0, (int)y);
			for (size_t x = 0; x < w; x++) {
				fnr[x] = fn[x >> 1];
				fsr[x] = fs[x >> 1];
			}
			memset(sc, 0, sizeof(float) * 24 * w);
			for (int q = 0; q < 12; q++) {
				float cn = 0, cc = 0, cs = 0; /* the tents' weights per side */
				for (int dy = -3; dy <= 3; dy++)
					for (int s = 0; s < 4; s++) {
						const int yy = (int)y + dy;
						if (j->q4[s][yy & 3] != (unsigned)q)
							continue;
						const float tw = (float)(4 - abs(dy));
						const float *hr =
						    hb + (size_t)(yy - ((int)c0 - 3)) * rowsz +
						    (size_t)s * w;
						*(dy < 0 ? &cn : dy > 0 ? &cs : &cc) += tw;
						j->K.acc(R[q], A[q], hr, hr + 4 * w,
						         dy < 0   ? fnr
						         : dy > 0 ? fsr
						                  : NULL,
						         tw, (long)w);
					}
				j->K.norm(R[q], A[q], fnr, fsr, cn, cc, cs, (long)w);
			}
			const float *ev = j->e + eidx(j, 0, (int)y),
			            *p0 = j->p0 + eidx(j, 0, (int)y);
			const int yp = (int)(y & 3);
			j->K.levels((const float *const *)R, sel[yp], ev, p0, dl, cgs, gF, (long)w,
			            pt, lo);
			for (unsigned q = 0; q < 12; q++) {
				const pc_fplane *pl = &j->out[q];
				float *dst = pl->data + (size_t)y * pl->row_stride;
				const int direct = pl->pixel_stride == 1;
				j->K.out(R[q], A[q], sel[yp][q], same[yp][q], ev, pt, lo, dl, cga,
				         gF, (long)w, direct ? dst : orow);
				if (!direct)
					for (size_t x = 0; x < w; x++)
						dst[x * pl->pixel_stride] = orow[x];
			}
		}
	}
	free(hb);
	free(sc);
}

int pc_dm_pan_lean_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, double g, const pc_fplane *out)
{
	if (!(g >= 0) || !isfinite(g))
		return pc_error(PC_EINVAL, "pan-lean: noise gain %g, expected finite and >= 0", g);
	lf_job j;
	memset(&j, 0, sizeof j);
	j.K = lf_kernels(level);
	j.in = in;
	j.w = in->width;
	j.h = in->height;
	j.ew = (int)j.w + 2 * LF_X;
	j.eh = (int)j.h + 2 * LF_X;
	j.bw = j.ew / 2;
	j.bh = j.eh / 2;
	j.delta = PC_DM_PAN_DELTA * fs;
	j.g = g;
	j.F = PC_DM_NG_FLOOR * fs;
	j.out = out;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++)
			j.q4[x][y] =
			    4 * (pc_mosaic_color(m, x, y) - PC_CFA_R) + pc_mosaic_channel(m, x, y);
	const size_t np = (size_t)j.ew * (size_t)j.eh, nb = (size_t)j.bw * (size_t)j.bh;
	j.e = malloc(sizeof(float) * np);
	j.p0 = calloc(np, sizeof(float));
	j.rho = calloc(np, sizeof(float));
	float *fb = malloc(sizeof(float) * 4 * nb);
	lf_blk *blk = calloc(nb, sizeof(lf_blk));
	int rc = 0;
	if (!j.e || !j.p0 || !j.rho || !fb || !blk)
		rc = pc_error(PC_ENOMEM, "pan-lean: planes for %ux%u", j.w, j.h);
	if (!rc) {
		for (size_t i = 0; i < 4 * nb; i++)
			fb[i] = 1;
		j.fw = fb;
		j.fe = fb + nb;
		j.fn = fb + 2 * nb;
		j.fs = fb + 3 * nb;
		pc_parallel_rows((uint32_t)j.eh, 0, threads, lf_extend, &j);
		pc_parallel_rows((uint32_t)j.eh - 4, 0, threads, lf_p0, &j);
		lf_bjob bj = {&j, blk};
		pc_parallel_rows((uint32_t)j.bh, 0, threads, lf_blocks, &bj);
		pc_parallel_rows((uint32_t)j.bh, 0, threads, lf_factors, &bj);
		int t = threads > 0 ? threads : pc_parallel_max_threads();
		uint32_t band = (j.h + (uint32_t)t - 1) / (uint32_t)t;
		pc_parallel_rows(j.h, band < 8 ? 8 : band, threads, lf_out_rows, &j);
		if (j.err)
			rc = pc_error(PC_ENOMEM, "pan-lean: row buffers for width %u", j.w);
	}
	free(j.e);
	free(j.p0);
	free(j.rho);
	free(fb);
	free(blk);
	return rc;
}

int pc_dm_pan_lean_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out)
{
	double g = 0;
	int rc = pc_dm_noise_gain_in_mt(in, m, fs, threads, &g);
	return rc ? rc : pc_dm_pan_lean_fast_g(in, m, fs, threads, level, fmax(g, 0), out);
}
