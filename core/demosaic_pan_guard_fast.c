/* pan-guard's float fast path (docs/demosaicking.md, "Round 15 fast path: pan-guard"): the
 * definition is pc_dm_pan_guard_ref_with's (demosaic_pan_guard.c, its comment states it); the
 * same steps in float, on whole-frame buffers:
 *
 *  1. the base I_p straight into the output planes (pan-adapt's or pan-side's fast path, with
 *     its base, AVX2 and AVX-512 instances), the conservative estimate I_b into twelve scratch
 *     planes (bayer-first's one-pass fast path, pc_dm_bayer_first: docs Round 15d);
 *  2. the mirror-extended raw E, P̃ = max(P0, 0) + δ (pan-ratio's 5×5 PPI, separable: on
 *     integer raws every partial sum is an integer below 2^24, so exact) and the ratio
 *     ρ = (max(E, 0) + δ)/P̃ on the extended grid;
 *  3. per 2×2 block the leave-one-out errors e_b, e_p, their window sums over the colour's own
 *     blocks (red and blue on one block lattice, green on two, the diagonal one with 2r
 *     blocks a side), and the weight w = 1/(1 + ((E_p + F)/(E_b + F))^γ) — the reference's
 *     (E_b + F)^γ/((E_b + F)^γ + (E_p + F)^γ) rearranged so that no power overflows a float;
 *  4. per pixel and colour the tent-interpolated W_k and the blend, in place in the outputs.
 *
 * Rows of blocks and of pixels run in bands on threads (pc_parallel_rows). */
#include "demosaic_pan.h"

#include <math.h>
#include <stddef.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_color.h"
#include "demosaic_fast.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

typedef struct guard_fast {
	uint32_t w, h;
	int XB, M, W; /* blocks' margin; the extended grid [−M, w + M) × [−M, h + M), row W */
	int NBX, NBY; /* blocks: (i, j) has its corner at (2i − XB, 2j − XB) */
	unsigned kc[4][4]; /* colour (0 R, 1 G, 2 B) at column phase u, row phase v: kc[v][u] */
	float delta, fl;   /* δ; the floor F = (floor·FS)² */
	int r, mode;
	double gamma;
	int gi;                /* γ as an integer when it is one (powers by squaring), else 0 */
	float force;           /* < 0: the weights computed */
	const float *img;      /* the raw minus black, w × h */
	float *ext, *pt, *rho; /* E, P̃, ρ on the extended grid */
	float *eb, *ep, *wb;   /* per block */
	float *hb[2], *hp[2];  /* per block: the window sums along the rows, by lattice */
	const float *ib;       /* I_b: twelve w × h planes, np apart */
	size_t np;
	atomic_int err;       /* a band's scratch not allocated */
	const pc_fplane *out; /* I_p in, the result out */
} guard_fast;

/* max(v, 0) for the finite values here */
#define GF_MAX0(v) ((v) > 0 ? (v) : 0.0f)

static size_t gf_idx(const guard_fast *g, int x, int y)
{
	return (size_t)(y + g->M) * (size_t)g->W + (size_t)(x + g->M);
}

static unsigned gf_colour(const guard_fast *g, int x, int y)
{
	return g->kc[y & 3][x & 3];
}

/* E on rows [y0, y1) of the extended grid (in grid rows, 0 = row −M): the raw at the
 * pc_mirror4 positions (the phase kept) */
static void gf_ext_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	guard_fast *g = ctx;
	for (uint32_t j = y0; j < y1; j++) {
		const int y = (int)j - g->M;
		const float *src = g->img + (size_t)pc_mirror4(y, (int)g->h) * g->w;
		float *d = g->ext + (size_t)j * (size_t)g->W;
		for (int x = -g->M; x < (int)g->w + g->M; x++)
			d[x + g->M] = src[pc_mirror4(x, (int)g->w)];
	}
}

/* P̃ and ρ on grid rows [y0, y1) inside the grid's two-sample border (P0 = Σ m_i m_j E / 64,
 * m = [1 2 2 2 1]: the vertical sums, kept in the row of ρ until P̃ is done, then the horizontal
 * ones) */
static void gf_ppi_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	guard_fast *g = ctx;
	const int W = g->W;
	const uint32_t ny = g->h + 2 * (uint32_t)g->M;
	for (uint32_t j = y0; j < y1; j++) {
		if (j < 2 || j + 2 >= ny)
			continue;
		const float *e[5];
		for (int k = 0; k < 5; k++)
			e[k] = g->ext + (size_t)(j + (uint32_t)k - 2) * (size_t)W;
		float *pt = g->pt + (size_t)j * (size_t)W, *vs = g->rho + (size_t)j * (size_t)W;
		for (int x = 0; x < W; x++)
			vs[x] = (e[0][x] + e[4][x]) + 2.0f * ((e[1][x] + e[2][x]) + e[3][x]);
		for (int x = 2; x < W - 2; x++) {
			float p0 =
			    ((vs[x - 2] + vs[x + 2]) + 2.0f * ((vs[x - 1] + vs[x]) + vs[x + 1])) *
			    (1.0f / 64);
			pt[x] = GF_MAX0(p0) + g->delta;
		}
		for (int x = 2; x < W - 2; x++)
			vs[x] = (GF_MAX0(e[2][x]) + g->delta) / pt[x];
	}
}

/* the leave-one-out errors of block rows [j0, j1) */
static void gf_err_rows(void *ctx, uint32_t j0, uint32_t j1)
{
	guard_fast *g = ctx;
	const ptrdiff_t W = g->W;
	/* the neighbours' offsets in the extended grid: red and blue (±4, 0), (0, ±4); green
	 * (±2, ±2), in the reference's order */
	const ptrdiff_t nrb[4] = {-4, 4, -4 * W, 4 * W},
	                ngr[4] = {-2 - 2 * W, 2 - 2 * W, -2 + 2 * W, 2 + 2 * W};
	for (uint32_t j = j0; j < j1; j++)
		for (int i = 0; i < g->NBX; i++) {
			const int bx = 2 * i - g->XB, by = 2 * (int)j - g->XB;
			const ptrdiff_t *nb = gf_colour(g, bx, by) == 1 ? ngr : nrb;
			const size_t a0 = gf_idx(g, bx, by);
			float sb = 0, sp = 0;
			for (int o = 0; o < 4; o++) {
				const size_t a =
				    a0 + (size_t)(o & 1) + (size_t)(o >> 1) * (size_t)W;
				const float *e = g->ext + a, *rh = g->rho + a;
				const float mb = ((e[nb[0]] + e[nb[1]]) + e[nb[2]]) + e[nb[3]],
				            mr = ((rh[nb[0]] + rh[nb[1]]) + rh[nb[2]]) + rh[nb[3]];
				const float v = e[0], xb = mb * 0.25f,
				            xp = g->pt[a] * (mr * 0.25f) - g->delta;
				sb += (v - xb) * (v - xb);
				sp += (v - xp) * (v - xp);
			}
			g->eb[(size_t)j * (size_t)g->NBX + (size_t)i] = sb;
			g->ep[(size_t)j * (size_t)g->NBX + (size_t)i] = sp;
		}
}

/* t^γ: by squaring for an integer γ, else powf */
static float gf_pow(const guard_fast *g, float t)
{
	if (!g->gi)
		return powf(t, (float)g->gamma);
	float r = 1, b = t;
	for (int e = g->gi; e; e >>= 1) {
		if (e & 1)
			r *= b;
		b *= b;
	}
	return r;
}

/* the window sums along block rows [j0, j1): over the offsets |di| <= 2r of even parity (the
 * own lattice: hb[0], hp[0]) and of odd parity (green's diagonal one: hb[1], hp[1]), clipped at
 * the block grid's edge as the reference's */
static void gf_hsum_rows(void *ctx, uint32_t j0, uint32_t j1)
{
	guard_fast *g = ctx;
	const int rb = 2 * g->r, nx = g->NBX;
	for (uint32_t j = j0; j < j1; j++) {
		const size_t o = (size_t)j * (size_t)nx;
		const float *eb = g->eb + o, *ep = g->ep + o;
		for (int i = 0; i < nx; i++)
			for (int l = 0; l < 2; l++) {
				float sb = 0, sp = 0;
				for (int ii = i - rb + l; ii <= i + rb - l; ii += 2) {
					if (ii < 0 || ii >= nx)
						continue;
					sb += eb[ii];
					sp += ep[ii];
				}
				g->hb[l][o + (size_t)i] = sb;
				g->hp[l][o + (size_t)i] = sp;
			}
	}
}

/* the window sums down block rows [j0, j1) (the own lattice from hb[0], hp[0] at even row
 * offsets; for green the diagonal lattice's from hb[1], hp[1] at odd ones, |dj| <= 2r − 1) and
 * the weights */
static void gf_weight_rows(void *ctx, uint32_t j0, uint32_t j1)
{
	guard_fast *g = ctx;
	const int rb = 2 * g->r, nx = g->NBX, ny = g->NBY;
	for (uint32_t ju = j0; ju < j1; ju++) {
		const int j = (int)ju;
		for (int i = 0; i < nx; i++) {
			const int green = gf_colour(g, 2 * i - g->XB, 2 * j - g->XB) == 1;
			float sb = 0, sp = 0;
			for (int l = 0; l < (green ? 2 : 1); l++)
				for (int dj = -rb + l; dj <= rb - l; dj += 2) {
					const int jj = j + dj;
					if (jj < 0 || jj >= ny)
						continue;
					const size_t a = (size_t)jj * (size_t)nx + (size_t)i;
					sb += g->hb[l][a];
					sp += g->hp[l][a];
				}
			/* (E_b + F)^γ / ((E_b + F)^γ + (E_p + F)^γ) = 1/(1 + q^γ), q = (E_p +
			 * F)/(E_b + F); 1 where both are 0 (the reference's 0/0 rule), 0 where only
			 * E_b + F is */
			const float ab = sb + g->fl, ap = sp + g->fl;
			float wgt;
			if (ab > 0)
				wgt = 1.0f / (1.0f + gf_pow(g, ap / ab));
			else
				wgt = ap > 0 ? 0.0f : 1.0f;
			g->wb[(size_t)j * (size_t)nx + (size_t)i] = wgt;
		}
	}
}

/* one colour's planar rows: mode 0's blend of one channel, d = W·d + (1 − W)·b */
static void gf_mix0(float *restrict d, const float *restrict b, const float *restrict wk,
                    uint32_t w)
{
	for (uint32_t x = 0; x < w; x++)
		d[x] = wk[x] * d[x] + (1 - wk[x]) * b[x];
}

/* mode 1's factor of the colour, f = (1 − W)·(s_b − s_p)/(max(s_p, 0) + δ), from its four
 * channels' rows p (I_p) and b (I_b) */
static void gf_fac1(const float *restrict p0, const float *restrict p1, const float *restrict p2,
                    const float *restrict p3, const float *restrict b0, const float *restrict b1,
                    const float *restrict b2, const float *restrict b3, const float *restrict wk,
                    float delta, float *restrict f, uint32_t w)
{
	for (uint32_t x = 0; x < w; x++) {
		const float s_p = (((p0[x] + p1[x]) + p2[x]) + p3[x]) * 0.25f,
		            s_b = (((b0[x] + b1[x]) + b2[x]) + b3[x]) * 0.25f;
		f[x] = (1 - wk[x]) * (s_b - s_p) / (GF_MAX0(s_p) + delta);
	}
}

/* ... and one channel's output, d = d + f·(max(d, 0) + δ) */
static void gf_mix1(float *restrict d, const float *restrict f, float delta, uint32_t w)
{
	for (uint32_t x = 0; x < w; x++)
		d[x] = d[x] + f[x] * (GF_MAX0(d[x]) + delta);
}

/* output rows [y0, y1): W_k per pixel and the blend, in place. The tent T = T_x·T_y on the
 * block centres is separable: a row's four block rows t (by = by0 + 2t) weigh T_y(t), the
 * vertical sums A_p[i] = Σ_{t ≡ p (mod 2)} T_y(t)·w(i, j_t) of the two block-row parities p, then
 * per pixel the four block columns s with T_x(s); the four parity pairs (s mod 2, p) are the
 * colour blocks' Bayer pattern (red, blue and two greens), and every pair's T sums to
 * (T_x(s) + T_x(s + 2))·(T_y(p) + T_y(p + 2)) = 8·8 (the tents {1, 5, 7, 3} or {3, 7, 5, 1}), so
 * W_k = Σ/64 (green: Σ/128). The same weights as the reference's sum over the sixteen blocks,
 * in another order. */
static void gf_blend_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	guard_fast *g = ctx;
	const uint32_t w = g->w;
	float *buf = pc_dm_alloc(sizeof(float) * (2 * (size_t)g->NBX + 4 * (size_t)w));
	if (!buf) {
		atomic_store(&g->err, 1);
		return;
	}
	float *A[2] = {buf, buf + g->NBX}, *wr[3], *fr = buf + 2 * (size_t)g->NBX + 3 * (size_t)w;
	for (int k = 0; k < 3; k++)
		wr[k] = buf + 2 * (size_t)g->NBX + (size_t)k * w;
	for (uint32_t yu = y0; yu < y1; yu++) {
		const int y = (int)yu, by0 = (y - 3) & ~1;
		if (g->force >= 0) {
			for (int k = 0; k < 3; k++)
				for (uint32_t x = 0; x < w; x++)
					wr[k][x] = g->force;
		} else {
			float ty[4];
			const float *wb[4];
			for (int t = 0; t < 4; t++) {
				ty[t] = (float)(8 - abs(2 * (by0 + 2 * t - y) + 1));
				wb[t] =
				    g->wb + (size_t)((by0 + 2 * t + g->XB) / 2) * (size_t)g->NBX;
			}
			for (int i = 0; i < g->NBX; i++) {
				A[0][i] = ty[0] * wb[0][i] + ty[2] * wb[2][i];
				A[1][i] = ty[1] * wb[1][i] + ty[3] * wb[3][i];
			}
			/* per column phase x mod 4: the colour of each pair (s mod 2, p), and 1/64
			 * or 1/128 */
			unsigned kp[4][2][2];
			float sc[3];
			for (int u = 0; u < 4; u++) {
				const int bx0 = (u - 3) & ~1;
				for (int s2 = 0; s2 < 2; s2++)
					for (int p = 0; p < 2; p++)
						kp[u][s2][p] =
						    gf_colour(g, bx0 + 2 * s2, by0 + 2 * p);
			}
			for (int k = 0; k < 3; k++)
				sc[k] = k == 1 ? 1.0f / 128 : 1.0f / 64;
			/* T_x of the four block columns from (x − 3) & ~1: x even, x odd */
			static const float txp[2][4] = {{1, 5, 7, 3}, {3, 7, 5, 1}};
			for (uint32_t x = 0; x < w; x++) {
				const int bx0 = ((int)x - 3) & ~1, i0 = (bx0 + g->XB) / 2,
				          u = (int)(x & 3);
				const float *tx = txp[x & 1];
				float num[3] = {0, 0, 0};
				for (int p = 0; p < 2; p++) {
					num[kp[u][0][p]] += tx[0] * A[p][i0] + tx[2] * A[p][i0 + 2];
					num[kp[u][1][p]] +=
					    tx[1] * A[p][i0 + 1] + tx[3] * A[p][i0 + 3];
				}
				for (int k = 0; k < 3; k++)
					wr[k][x] = num[k] * sc[k];
			}
		}
		for (unsigned k = 0; k < 3; k++) {
			float *d[4];
			const float *vbr[4];
			size_t ps[4];
			for (unsigned c = 0; c < 4; c++) {
				const pc_fplane *o = &g->out[4 * k + c];
				d[c] = o->data + (size_t)y * o->row_stride;
				ps[c] = o->pixel_stride;
				vbr[c] = g->ib + (size_t)(4 * k + c) * g->np + (size_t)y * w;
			}
			const float *wk = wr[k];
			if (ps[0] == 1 && ps[1] == 1 && ps[2] == 1 && ps[3] == 1) {
				if (g->mode) {
					gf_fac1(d[0], d[1], d[2], d[3], vbr[0], vbr[1], vbr[2],
					        vbr[3], wk, g->delta, fr, w);
					for (unsigned c = 0; c < 4; c++)
						gf_mix1(d[c], fr, g->delta, w);
				} else {
					for (unsigned c = 0; c < 4; c++)
						gf_mix0(d[c], vbr[c], wk, w);
				}
				continue;
			}
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
					                (GF_MAX0(s_p) + g->delta);
					for (unsigned c = 0; c < 4; c++)
						d[c][x * ps[c]] =
						    vp[c] + f * (GF_MAX0(vp[c]) + g->delta);
				} else {
					for (unsigned c = 0; c < 4; c++)
						d[c][x * ps[c]] =
						    wk[x] * vp[c] + (1 - wk[x]) * vb[c];
				}
			}
		}
	}
	pc_dm_free(buf);
}

/* The fast path with the definition's parameters as arguments (mode: 0 every channel
 * blended, 1 the colour's analyser mean) */
static int gf_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                  pc_cpu_level level, int base, int r, double gamma, double floor, int mode,
                  double force, double gain, const pc_fplane *out)
{
	const uint32_t w = in->width, h = in->height;
	const size_t n = (size_t)w * h;
	guard_fast g;
	memset(&g, 0, sizeof g);
	atomic_init(&g.err, 0);
	g.w = w;
	g.h = h;
	g.XB = 4 + 4 * r;
	g.M = g.XB + 6 + 2; /* the samples' ±(XB + 5), P̃'s two more */
	g.W = (int)w + 2 * g.M;
	g.NBX = ((int)w + 2 * g.XB) / 2;
	g.NBY = ((int)h + 2 * g.XB) / 2;
	for (unsigned v = 0; v < 4; v++)
		for (unsigned u = 0; u < 4; u++)
			g.kc[v][u] = (unsigned)(pc_mosaic_color(m, u, v) - PC_CFA_R);
	g.delta = (float)(PC_DM_PAN_ADAPT_DFS * fs);
	g.fl = (float)((floor * fs) * (floor * fs));
	g.r = r;
	g.mode = mode;
	g.gamma = gamma;
	g.gi = gamma >= 1 && gamma <= 64 && gamma == (double)(int)gamma ? (int)gamma : 0;
	g.force = (float)force;
	g.out = out;
	const size_t ne = (size_t)g.W * (size_t)((int)h + 2 * g.M),
	             nb = (size_t)g.NBX * (size_t)g.NBY;
	float *img = pc_dm_alloc(sizeof(float) * (n + 2));
	/* I_b's planes 64 floats more than a plane apart: planes a multiple of 4 KiB apart would
	 * share the L1's sets, column for column */
	g.np = n + 64;
	float *ib = pc_dm_alloc(sizeof(float) * g.np * 12);
	float *eb = pc_dm_alloc(sizeof(float) * (3 * ne + 7 * nb));
	float *row = pc_dm_alloc(sizeof(float) * ((size_t)w + 2));
	int rc = 0;
	if (!img || !ib || !eb || !row) {
		rc = pc_error(PC_ENOMEM, "pan-guard: images of %ux%u", w, h);
		goto done;
	}
	for (uint32_t y = 0; y < h; y++) {
		pc_dm_row_to_float(in, y, row + 1);
		memcpy(img + (size_t)y * w, row + 1, sizeof(float) * w);
	}
	/* 1. the base into the outputs (pan-adapt with the given noise gain, < 0 its own
	 * estimate), bayer-first into ib */
	rc = base ? pc_dm_pan_adapt_fast_g(in, m, fs, threads, level, gain, out)
	          : pc_dm_pan_side_fast(in, m, fs, threads, level, out);
	pc_fplane pl[12];
	for (unsigned q = 0; q < 12; q++)
		pl[q] = (pc_fplane){ib + (size_t)q * g.np, w, 1};
	if (!rc)
		rc = pc_dm_bayer_first(in, m, threads, level, pl);
	if (rc)
		goto done;
	g.img = img;
	g.ib = ib;
	g.ext = eb;
	g.pt = eb + ne;
	g.rho = eb + 2 * ne;
	g.eb = eb + 3 * ne;
	g.ep = g.eb + nb;
	g.wb = g.ep + nb;
	for (int l = 0; l < 2; l++) {
		g.hb[l] = g.wb + (size_t)(1 + 2 * l) * nb;
		g.hp[l] = g.wb + (size_t)(2 + 2 * l) * nb;
	}
	/* 2.–4. */
	const uint32_t ny = h + 2 * (uint32_t)g.M;
	pc_parallel_rows(ny, 0, threads, gf_ext_rows, &g);
	pc_parallel_rows(ny, 0, threads, gf_ppi_rows, &g);
	pc_parallel_rows((uint32_t)g.NBY, 0, threads, gf_err_rows, &g);
	pc_parallel_rows((uint32_t)g.NBY, 0, threads, gf_hsum_rows, &g);
	pc_parallel_rows((uint32_t)g.NBY, 0, threads, gf_weight_rows, &g);
	pc_parallel_rows(h, 0, threads, gf_blend_rows, &g);
	if (atomic_load(&g.err))
		rc = pc_error(PC_ENOMEM, "pan-guard: row buffers for width %u", w);
done:
	pc_dm_free(img);
	pc_dm_free(ib);
	pc_dm_free(eb);
	pc_dm_free(row);
	return rc;
}

int pc_dm_pan_guard_fast_with(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                              pc_cpu_level level, const pc_dm_pan_guard_params *p,
                              const pc_fplane *out)
{
	int rc = pc_dm_pan_guard_check(p);
	if (rc)
		return rc;
	if (p->cons != 0)
		return pc_error(PC_ENOTSUP, "pan-guard fast path: only bayer-first as the "
		                            "conservative estimate (cons 0)");
	return gf_run(in, m, fs, threads, level, p->base, p->r, p->gamma, p->floor, p->mode,
	              p->force, p->g, out);
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
