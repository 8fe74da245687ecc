/* pan-guard (docs/demosaicking.md, Round 15): a pan method with a detail guard.
 *
 * The pan methods (demosaic_pan.c) give every channel p's own detail through its ratio to the
 * pseudo-panchromatic image P0. Where the ratio of a colour to P0 is not smooth at the colour
 * lattice's scale — hue rings finer than the red and blue lattices' Nyquist period of 8 pixels,
 * colour gratings whose bars barely show in P0 (Round 13c), noise (Round 13d) — that detail has
 * the wrong size or sign, and the method loses to bayer-first's plain interpolation. pan-guard
 * measures, on each colour's own samples, which of the two models predicts them better nearby,
 * and blends the two estimates by that:
 *
 *  1. The base estimate I_p: pan-adapt's (pc_dm_pan_adapt_ref_with, with the noise gain
 *     params.g when given, Round 15b) or pan-side's (params.base), and
 *     the conservative estimate I_b: bayer-first's (pc_dm_color_split_ref, then mono bilinear,
 *     pc_dm_ref: pc_dm_bayer_first_ref), both double references, twelve float planes each.
 *  2. A leave-one-out check per 2×2 block B (corner (x & ~1, y & ~1), one colour k: red and
 *     blue one block per 4×4 period, green two), on the mirror-extended raw (pc_mirror4, which
 *     keeps the phase). Its neighbour blocks n of the same colour: red and blue the four at
 *     (±4, 0), (0, ±4), green the four at (±2, ±2). For each of the block's four samples
 *     s = B + o (o in {0, 1}²; its analyser) with P̃ = max(P0, 0) + δ (P0 pan-ratio's 5×5 PPI,
 *     δ = 1 % of full scale):
 *
 *       conservative  x_b = mean_n raw(s + n),
 *       pan           x_p = P̃(s) · mean_n [(max(raw(s + n), 0) + δ) / P̃(s + n)] − δ,
 *
 *     the ratio model's prediction of the sample from its neighbours' ratios (pan-ratio's,
 *     demosaic_pan.c, with the own block left out), and e_b(B) = Σ_o (raw(s) − x_b)², e_p(B)
 *     = Σ_o (raw(s) − x_p)². P̃(s) contains the sample itself (weight 1/16): the pan
 *     prediction sees 1/16 of what it predicts, as the method's output does.
 *  3. Window sums over the blocks B' of the same colour with |B' − B| ≤ 4r on both axes:
 *     E_b(B) = Σ e_b(B'), E_p(B) = Σ e_p(B') (red and blue (2r + 1)² blocks, green about
 *     twice as many).
 *  4. The block's weight of the pan estimate, a combination of two forecasts by their past
 *     errors (Bates & Granger, "The combination of forecasts", Operational Research Quarterly
 *     20(4) 1969: weight σ_b²/(σ_b² + σ_p²) for uncorrelated errors), sharpened by an exponent
 *     γ (derived here, Round 15): with F = (f·FS)² a floor,
 *
 *       w(B) = (E_b + F)^γ / ((E_b + F)^γ + (E_p + F)^γ)   in [0, 1].
 *
 *  5. Per pixel p and colour k the weights of k's blocks interpolated by pan-ratio's normalised
 *     tent on the block centres c_B = B + (1/2, 1/2): W_k(p) = Σ_B T(c_B − p) w(B) / Σ_B T,
 *     T(d) = (4 − |d_x|)(4 − |d_y|) over |d_x|, |d_y| < 4 (both green lattices summed).
 *  6. I_q(p) = W_k(p)·I_p,q(p) + (1 − W_k(p))·I_b,q(p) for the four analysers q of colour k
 *     (one weight per colour; mode 0, the method's). Mode 1 (tried, not chosen) blends only
 *     the colour's analyser mean s = Σ_c I_c / 4 and keeps the base's modulation:
 *     I_q = I_p,q + (1 − W_k)·(s_b − s_p)·(max(I_p,q, 0) + δ)/(max(s_p, 0) + δ). W = 1 gives the
 *     base bit for bit in both (1·I_p + 0·I_b; (1 − 1)·… = 0).
 *
 * Not in the method (pan-hue's, Round 17a): params.unshrink = c_u > 0 blends each colour's own
 * outputs of the base towards pan-adapt without its shrinkage (guard_unshrink states it).
 *
 * The method: base pan-adapt, r = 1, γ = 8, F from 10⁻⁴ of full scale, mode 0, bayer-first as
 * the conservative estimate (cons 0; cons 1, every channel's plain tents on its own samples,
 * tried, not chosen), picked on the development sets by the rule of Round 15.
 * Every constant is in demosaic_pan.h (PC_DM_PAN_GUARD_*). */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_color.h"
#include "demosaic_noise.h"
#include "demosaic_pan.h"
#include "polarcam/error.h"

pc_dm_pan_guard_params pc_dm_pan_guard_defaults(void)
{
	pc_dm_pan_guard_params p = {PC_DM_PAN_GUARD_BASE,
	                            PC_DM_PAN_GUARD_R,
	                            PC_DM_PAN_GUARD_GAMMA,
	                            PC_DM_PAN_GUARD_FLOOR,
	                            PC_DM_PAN_GUARD_MODE,
	                            PC_DM_PAN_GUARD_CONS,
	                            -1.0,
	                            -1.0,
	                            PC_DM_PAN_GUARD_UNSHRINK};
	return p;
}

int pc_dm_pan_guard_check(const pc_dm_pan_guard_params *p)
{
	if ((p->base != 0 && p->base != 1) || p->r < 0 || p->r > 4 || !(p->gamma > 0) ||
	    !(p->floor >= 0) || (p->mode != 0 && p->mode != 1) || (p->cons != 0 && p->cons != 1) ||
	    !(p->force <= 1) || !isfinite(p->force) || !isfinite(p->g) || !(p->unshrink >= 0) ||
	    !isfinite(p->unshrink))
		return pc_error(PC_EINVAL, "pan-guard: parameters out of range");
	return 0;
}

typedef struct guard_ext {
	int w, h, M, W;   /* the extended images: [−M, w + M) × [−M, h + M), row W */
	double *raw, *pt; /* the mirrored raw and P̃ = max(P0, 0) + δ */
} guard_ext;

static size_t gidx(const guard_ext *g, int x, int y)
{
	return (size_t)(y + g->M) * (size_t)g->W + (size_t)(x + g->M);
}

/* the cheap conservative estimate: every channel q by pan-ratio's normalised tents on its own
 * samples' values, I_q(p) = Σ T(d)·raw(p + d) / Σ T(d) over the samples of q at d in [−3, 3]²,
 * T(d) = (4 − |d_x|)(4 − |d_y|) (green's two lattices summed), on the mirror-extended raw */
void pc_dm_pan_guard_tents(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                           const pc_fplane *out)
{
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			double num[12] = {0}, den[12] = {0};
			for (int dy = -3; dy <= 3; dy++)
				for (int dx = -3; dx <= 3; dx++) {
					uint32_t xm = (uint32_t)pc_mirror4(x + dx, (int)w),
					         ym = (uint32_t)pc_mirror4(y + dy, (int)h);
					unsigned q = 4 * (pc_mosaic_color(m, xm, ym) - PC_CFA_R) +
					             pc_mosaic_channel(m, xm, ym);
					double t = (4 - abs(dx)) * (4 - abs(dy));
					num[q] += t * img[(size_t)ym * w + xm];
					den[q] += t;
				}
			for (unsigned q = 0; q < 12; q++)
				out[q].data[(size_t)y * out[q].row_stride +
				            (size_t)x * out[q].pixel_stride] =
				    (float)(num[q] / den[q]);
		}
}

unsigned pc_dm_pan_guard_colour(const pc_mosaic *m, int x, int y, int w, int h)
{
	return (
	    unsigned)(pc_mosaic_color(m, (uint32_t)pc_mirror4(x, w), (uint32_t)pc_mirror4(y, h)) -
	              PC_CFA_R);
}

void pc_dm_pan_guard_blocks_free(pc_dm_guard_blocks *b)
{
	free(b->eb);
	free(b->col);
	b->eb = b->ep = b->mu = NULL;
	b->col = NULL;
}

int pc_dm_pan_guard_blocks(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           int XB, pc_dm_guard_blocks *b)
{
	const double delta = PC_DM_PAN_ADAPT_DFS * fs;
	/* blocks B with corners in [−XB, w + XB) (pan-guard: the tents of every pixel, B within
	 * −4 .. +3, and their windows ±4r); samples and P̃ ±5 further (neighbours ±4, offsets +1) */
	const int M = XB + 6;
	guard_ext g = {(int)w, (int)h, M, (int)w + 2 * M, NULL, NULL};
	const size_t ne = (size_t)g.W * (size_t)((int)h + 2 * M);
	const int NBX = ((int)w + 2 * XB) / 2, NBY = ((int)h + 2 * XB) / 2;
	const size_t nb = (size_t)NBX * (size_t)NBY;
	double *ebuf = malloc(sizeof(double) * (2 * ne));
	double *bbuf = malloc(sizeof(double) * (3 * nb));
	unsigned char *cbuf = malloc(nb);
	if (!ebuf || !bbuf || !cbuf) {
		free(ebuf);
		free(bbuf);
		free(cbuf);
		return pc_error(PC_ENOMEM, "pan-guard reference: images of %ux%u", w, h);
	}
	*b = (pc_dm_guard_blocks){XB, NBX, NBY, bbuf, bbuf + nb, bbuf + 2 * nb, cbuf};
	g.raw = ebuf;
	g.pt = ebuf + ne;
	double *eb = b->eb, *ep = b->ep, *mu = b->mu;
	static const double mk[5] = {1, 2, 2, 2, 1};
	for (int y = -M; y < (int)h + M; y++)
		for (int x = -M; x < (int)w + M; x++)
			g.raw[gidx(&g, x, y)] =
			    img[(size_t)pc_mirror4(y, (int)h) * w + (size_t)pc_mirror4(x, (int)w)];
	for (int y = -M; y < (int)h + M; y++)
		for (int x = -M; x < (int)w + M; x++) {
			double s = 0;
			for (int j = -2; j <= 2; j++)
				for (int i = -2; i <= 2; i++)
					s += mk[i + 2] * mk[j + 2] *
					     img[(size_t)pc_mirror4(y + j, (int)h) * w +
					         (size_t)pc_mirror4(x + i, (int)w)];
			g.pt[gidx(&g, x, y)] = fmax(s / 64, 0) + delta;
		}
	/* 2. the leave-one-out errors per block */
	static const int nrb[4][2] = {{-4, 0}, {4, 0}, {0, -4}, {0, 4}},
	                 ngr[4][2] = {{-2, -2}, {2, -2}, {-2, 2}, {2, 2}};
	for (int j = 0; j < NBY; j++)
		for (int i = 0; i < NBX; i++) {
			const int bx = 2 * i - XB, by = 2 * j - XB;
			const unsigned k = pc_dm_pan_guard_colour(m, bx, by, (int)w, (int)h);
			b->col[(size_t)j * NBX + i] = (unsigned char)k;
			const int(*nbr)[2] = k == 1 ? ngr : nrb;
			double sumb = 0, sump = 0, sumv = 0;
			for (int o = 0; o < 4; o++) {
				const int sx = bx + (o & 1), sy = by + (o >> 1);
				double mb = 0, mr = 0;
				for (int t = 0; t < 4; t++) {
					size_t a = gidx(&g, sx + nbr[t][0], sy + nbr[t][1]);
					mb += g.raw[a];
					mr += (fmax(g.raw[a], 0) + delta) / g.pt[a];
				}
				size_t a = gidx(&g, sx, sy);
				double xb = mb / 4, xp = g.pt[a] * (mr / 4) - delta;
				sumb += (g.raw[a] - xb) * (g.raw[a] - xb);
				sump += (g.raw[a] - xp) * (g.raw[a] - xp);
				sumv += fmax(g.raw[a], 0) + delta;
			}
			eb[(size_t)j * NBX + i] = sumb;
			ep[(size_t)j * NBX + i] = sump;
			mu[(size_t)j * NBX + i] = sumv / 4;
		}
	free(ebuf);
	return 0;
}

void pc_dm_pan_guard_tent(const pc_dm_guard_blocks *b, const double *v, const pc_mosaic *m, int w,
                          int h, int x, int y, double num[3], double den[3])
{
	for (unsigned k = 0; k < 3; k++)
		num[k] = den[k] = 0;
	for (int by = (y - 4 + 1) & ~1; by <= y + 3; by += 2)
		for (int bx = (x - 4 + 1) & ~1; bx <= x + 3; bx += 2) {
			const int dx2 = 2 * (bx - x) + 1, dy2 = 2 * (by - y) + 1;
			if (abs(dx2) >= 8 || abs(dy2) >= 8)
				continue;
			const double t = (8 - abs(dx2)) * (8 - abs(dy2));
			const unsigned k = pc_dm_pan_guard_colour(m, bx, by, w, h);
			num[k] += t * v[(size_t)((by + b->XB) / 2) * b->NBX + (bx + b->XB) / 2];
			den[k] += t;
		}
}

void pc_dm_pan_guard_parts_free(pc_dm_guard_parts *parts)
{
	free(parts->ib);
	parts->ib = NULL;
	pc_dm_pan_guard_blocks_free(&parts->bl);
}

void pc_dm_pan_guard_window(const pc_dm_guard_blocks *b, int i, int j, int rb, double s[3])
{
	const int NBX = b->NBX, NBY = b->NBY;
	const unsigned k = b->col[(size_t)j * NBX + i];
	s[0] = s[1] = s[2] = 0;
	for (int jj = j - rb; jj <= j + rb; jj++)
		for (int ii = i - rb; ii <= i + rb; ii++) {
			const size_t a = (size_t)jj * NBX + ii;
			if (ii < 0 || jj < 0 || ii >= NBX || jj >= NBY || b->col[a] != k)
				continue;
			s[0] += b->eb[a];
			s[1] += b->ep[a];
			s[2] += b->mu[a];
		}
}

/* Round 17a: the base's shrinkage undone where a colour's detail is not noise. pan-adapt's ratio
 * step shrinks the level towards its window mean where the guide P̃ varies little against its
 * noise (Round 14); hue detail that P0 does not carry (green bars on magenta) is shrunk away with
 * the noise. Per block B of colour k, over k's blocks within ±4r: X = max(E_p − c_u·N, 0), N =
 * 5·g·Σ mu the ratio residual's expected noise part (pan-hue's step 1), u(B) = X/(X + N), the
 * share of the residual that is signal (a Wiener gain, derived here); at pixel p of colour k,
 * U_k(p) by the tent and I_p,q = U_k·I_u,q + (1 − U_k)·I_p,q for k's four analysers q only (the
 * level is k's own sample; the other colours keep the shrunk one, which guards them from k's noise
 * and k's hue detail), I_u pan-adapt with g = 0 (pan-side's ratio step). u is 1
 * where N = 0 and X > 0; 0 where X = 0. The blocks' weight buffer ub (NBX·NBY) is scratch. */
static int guard_unshrink(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                          const pc_dm_pan_guard_params *p, pc_dm_pan_adapt_params pa,
                          const pc_dm_guard_blocks *bl, const pc_fplane *ip, double *ub)
{
	const size_t n = (size_t)w * h;
	float *ubuf = malloc(sizeof(float) * n * 12);
	if (!ubuf)
		return pc_error(PC_ENOMEM, "pan-guard reference: images of %ux%u", w, h);
	pc_fplane iu[12];
	for (unsigned q = 0; q < 12; q++)
		iu[q] = (pc_fplane){ubuf + q * n, w, 1};
	const double g = fmax(pa.g, 0);
	pa.g = 0;
	int rc = pc_dm_pan_adapt_ref_with(img, w, h, m, fs, &pa, iu);
	if (rc) {
		free(ubuf);
		return rc;
	}
	const int NBX = bl->NBX, NBY = bl->NBY, rb = 2 * p->r;
	for (int j = 0; j < NBY; j++)
		for (int i = 0; i < NBX; i++) {
			double sw[3];
			pc_dm_pan_guard_window(bl, i, j, rb, sw);
			const double nn = 5 * g * sw[2], x = fmax(sw[1] - p->unshrink * nn, 0);
			ub[(size_t)j * NBX + i] = x > 0 ? x / (x + nn) : 0;
		}
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			double num[3], den[3];
			pc_dm_pan_guard_tent(bl, ub, m, (int)w, (int)h, x, y, num, den);
			const size_t a = (size_t)y * w + (size_t)x;
			/* the own colour's outputs only: the level is the own sample's */
			const unsigned k = pc_dm_pan_guard_colour(m, x, y, (int)w, (int)h);
			const double u = num[k] / den[k];
			for (unsigned q = 4 * k; q < 4 * k + 4; q++)
				ip[q].data[a] = (float)(u * (double)iu[q].data[a] +
				                        (1 - u) * (double)ip[q].data[a]);
		}
	free(ubuf);
	return 0;
}

int pc_dm_pan_guard_ref_parts(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                              double fs, const pc_dm_pan_guard_params *p, int xb,
                              const pc_fplane *out, pc_dm_guard_parts *parts)
{
	pc_dm_guard_parts own;
	const bool keep = parts != NULL;
	if (!keep)
		parts = &own;
	*parts = (pc_dm_guard_parts){NULL, {0, 0, 0, NULL, NULL, NULL, NULL}};
	int rc = pc_dm_pan_guard_check(p);
	if (rc)
		return rc;
	const size_t n = (size_t)w * h;
	const double delta = PC_DM_PAN_ADAPT_DFS * fs;
	float *pbuf = malloc(sizeof(float) * n * 12);
	parts->ib = malloc(sizeof(float) * n * 12);
	if (!pbuf || !parts->ib) {
		free(pbuf);
		if (!keep)
			pc_dm_pan_guard_parts_free(parts);
		return pc_error(PC_ENOMEM, "pan-guard reference: images of %ux%u", w, h);
	}
	pc_fplane ip[12], ib[12];
	for (unsigned q = 0; q < 12; q++) {
		ip[q] = (pc_fplane){pbuf + q * n, w, 1};
		ib[q] = (pc_fplane){parts->ib + q * n, w, 1};
	}
	/* the base: pan-adapt with the given noise gain, or (g < 0) its own estimate, as
	 * pc_dm_pan_adapt_ref */
	pc_dm_pan_adapt_params pa = pc_dm_pan_adapt_defaults();
	pa.g = p->g;
	/* the unshrink's noise gain: the given one, or the frame's estimate, which is pan-adapt's
	 * own (pc_dm_noise_gain_d), so the base is the same either way */
	if (p->unshrink > 0 && pa.g < 0)
		rc = pc_dm_noise_gain_d(img, w, h, m, fs, &pa.g);
	if (!rc)
		rc = p->base ? pc_dm_pan_adapt_ref_with(img, w, h, m, fs, &pa, ip)
		             : pc_dm_pan_side_ref(img, w, h, m, fs, ip);
	if (!rc && p->cons == 0)
		rc = pc_dm_bayer_first_ref(img, w, h, m, PC_DM_BILINEAR, fs, ib);
	else if (!rc)
		pc_dm_pan_guard_tents(img, w, h, m, ib);
	const int XB = 4 + 4 * p->r > xb ? 4 + 4 * p->r : xb;
	if (!rc)
		rc = pc_dm_pan_guard_blocks(img, w, h, m, fs, XB, &parts->bl);
	double *wb = NULL;
	if (!rc) {
		wb = malloc(sizeof(double) * (size_t)parts->bl.NBX * (size_t)parts->bl.NBY);
		if (!wb)
			rc = pc_error(PC_ENOMEM, "pan-guard reference: images of %ux%u", w, h);
	}
	if (rc) {
		free(pbuf);
		if (!keep)
			pc_dm_pan_guard_parts_free(parts);
		return rc;
	}
	const pc_dm_guard_blocks *bl = &parts->bl;
	const int NBX = bl->NBX, NBY = bl->NBY;
	if (p->unshrink > 0 && p->base)
		rc = guard_unshrink(img, w, h, m, fs, p, pa, bl, ip, wb);
	if (rc) {
		free(wb);
		free(pbuf);
		if (!keep)
			pc_dm_pan_guard_parts_free(parts);
		return rc;
	}
	/* 3. window sums over the same colour's blocks within ±4r; 4. the block weights */
	const int rb = 2 * p->r; /* in block steps */
	const double fl = (p->floor * fs) * (p->floor * fs);
	for (int j = 0; j < NBY; j++)
		for (int i = 0; i < NBX; i++) {
			double sw[3];
			pc_dm_pan_guard_window(bl, i, j, rb, sw);
			double ab = pow(sw[0] + fl, p->gamma), ap = pow(sw[1] + fl, p->gamma);
			wb[(size_t)j * NBX + i] = ab + ap > 0 ? ab / (ab + ap) : 1;
		}
	/* 5. per pixel and colour the tent-interpolated weight; 6. the blend */
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			double num[3], den[3];
			pc_dm_pan_guard_tent(bl, wb, m, (int)w, (int)h, x, y, num, den);
			const size_t a = (size_t)y * w + (size_t)x;
			for (unsigned k = 0; k < 3; k++) {
				const double wk = p->force >= 0 ? p->force : num[k] / den[k];
				/* mode 1: the colour's analyser means s_p, s_b */
				double s_p = 0, s_b = 0;
				for (unsigned c = 0; c < 4; c++) {
					s_p += (double)ip[4 * k + c].data[a] / 4;
					s_b += (double)ib[4 * k + c].data[a] / 4;
				}
				for (unsigned c = 0; c < 4; c++) {
					const unsigned q = 4 * k + c;
					const double vp = ip[q].data[a], vb = ib[q].data[a];
					const double v = p->mode ? vp + (1 - wk) * (s_b - s_p) *
					                                    (fmax(vp, 0) + delta) /
					                                    (fmax(s_p, 0) + delta)
					                         : wk * vp + (1 - wk) * vb;
					out[q].data[(size_t)y * out[q].row_stride +
					            (size_t)x * out[q].pixel_stride] = (float)v;
				}
			}
		}
	free(wb);
	free(pbuf);
	if (!keep)
		pc_dm_pan_guard_parts_free(parts);
	else if (p->cons != 0) /* the parts promise bayer-first's: the tents replaced */
		rc = pc_dm_bayer_first_ref(img, w, h, m, PC_DM_BILINEAR, fs, ib);
	return rc;
}

int pc_dm_pan_guard_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_guard_params *p, const pc_fplane *out)
{
	return pc_dm_pan_guard_ref_parts(img, w, h, m, fs, p, 0, out, NULL);
}

int pc_dm_pan_guard_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out)
{
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	return pc_dm_pan_guard_ref_with(img, w, h, m, fs, &p, out);
}

int pc_dm_pan_guard_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                          double g, const pc_fplane *out)
{
	pc_dm_pan_guard_params p = pc_dm_pan_guard_defaults();
	p.g = g;
	return pc_dm_pan_guard_ref_with(img, w, h, m, fs, &p, out);
}
