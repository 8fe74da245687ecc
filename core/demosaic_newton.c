/* The Newton-polynomial method of Li, Zhao, Pan and Kong, "Demosaicking DoFP images using
 * Newton's polynomial interpolation and polarization difference model", Opt. Express 27(2)
 * 1376-1391 (2019), in double precision: the reference, and a fast path (below). Only the paper's
 * abstract was reachable here; the formulas are those of the authors' MATLAB release
 * (`Newton_Polynomial_Interpolation.m`, read for its formulas, not copied), whose comments
 * name the paper's equations and cases: its stage one is "Eqs. (14)-(17), simplified", its
 * cases are the paper's Fig. 6(a) (the diagonal neighbour's channel), 6(b) (the horizontal
 * one's) and 6(c) (the vertical one's).
 *
 * The interpolator (Eqs. (14)-(17) as simplified in the release): along a direction u (x, y,
 * or a diagonal), where the samples at odd steps p ± u, p ± 3u belong to the target channel t
 * and those at even steps p, p ± 2u to p's own channel,
 *
 *   N_u(p) = 7/16 (t(p − u) + t(p + u)) + 1/16 (t(p − 3u) + t(p + 3u))
 *            − 1/4 (I(p − 2u) − 2 I(p) + I(p + 2u)),
 *
 * a Newton-polynomial estimate of t in the polarization-difference domain: the target's taps
 * sum to 1 and the own channel's correction to 0, so a constant difference between channels
 * (uniform polarization) passes unchanged, and the symmetric taps reproduce every polynomial
 * of degree ≤ 3 along u (Σ taps·k² = 2 = the correction's, odd moments vanish): exact on
 * cubic intensity with constant per-channel offsets (tested).
 *
 * Stage one, at every pixel p: its own channel is I(p); the horizontal neighbour's channel
 * N_x(p), the vertical neighbour's N_y(p); the diagonal neighbour's (Fig. 6(a)) from the two
 * diagonal estimates Y1 = N_(1,1)(p), Y2 = N_(1,−1)(p) by the edge classifier and fusion:
 *
 *   φ_k(p) = Σ_{a,b ∈ {−2,0,2}} |Y_k(p + (a, b)) − I(p + (a, b))|  (the estimated polarization
 *            difference along direction k over the 3×3 same-channel neighbourhood);
 *   φ1 > τ φ2: Y2;  φ2 > τ φ1: Y1;  else (w1 Y1 + w2 Y2)/(w1 + w2), w_k = 1/(d_k + ε),
 *   d_k = |I(p − u_k) − I(p + u_k)| + |2 I(p) − I(p − 2u_k) − I(p + 2u_k)|,
 *
 * τ = 5.8 (the release's value) and ε = 10⁻¹⁵ of full scale (the release's 10⁻¹⁵, which only
 * keeps the weights finite). The ratio tests are written as products, so that φ1 = φ2 = 0
 * (a flat neighbourhood, where the release divides 0 by 0) takes the weighted branch.
 *
 * Stage two (Fig. 6(b), 6(c)): the horizontal neighbour's channel t_h gets a second estimate
 * across, X2 = N_y(p) on the stage-one estimates of t_h at p ± y, p ± 3y (diagonal estimates
 * there) with p's own samples at p, p ± 2y, and the stage-one X1 = N_x(p); the same
 * classifier on X1, X2 and fusion with the horizontal (X1) and vertical (X2) gradients d_h,
 * d_v. The vertical neighbour's channel alike with the directions swapped. The diagonal
 * neighbour's channel keeps its stage-one value.
 *
 * Borders: every intermediate image is read with the library's whole-sample mirror
 * (docs/demosaicking.md), which keeps each index's parity and so its channel; the release
 * leaves a 3-pixel border uninterpolated. Support: ±10 (stage one ±3, its diagonal
 * classifier ±5; stage two reads stage one at ±3 across and its classifier that at ±2:
 * 3 + 5 + 2). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

#define NEWTON_TAU 5.8
#define NEWTON_EPS 1e-15

/* N_u(p) of the file comment: t the target's image (read at odd steps), r the raw (even). */
static double newton(const pc_dimg *t, const pc_dimg *r, int x, int y, int ux, int uy)
{
	return 7.0 / 16 * (pc_dimg_at(t, x - ux, y - uy) + pc_dimg_at(t, x + ux, y + uy)) +
	       1.0 / 16 *
	           (pc_dimg_at(t, x - 3 * ux, y - 3 * uy) + pc_dimg_at(t, x + 3 * ux, y + 3 * uy)) -
	       0.25 * (pc_dimg_at(r, x - 2 * ux, y - 2 * uy) - 2 * pc_dimg_at(r, x, y) +
	               pc_dimg_at(r, x + 2 * ux, y + 2 * uy));
}

/* d_k: the gradient along u */
static double grad(const pc_dimg *r, int x, int y, int ux, int uy)
{
	return fabs(pc_dimg_at(r, x - ux, y - uy) - pc_dimg_at(r, x + ux, y + uy)) +
	       fabs(2 * pc_dimg_at(r, x, y) - pc_dimg_at(r, x - 2 * ux, y - 2 * uy) -
	            pc_dimg_at(r, x + 2 * ux, y + 2 * uy));
}

/* φ of an estimate image e against the raw over p's 3×3 same-channel neighbourhood */
static double phi(const pc_dimg *e, const pc_dimg *r, int x, int y)
{
	double s = 0;
	for (int b = -2; b <= 2; b += 2)
		for (int a = -2; a <= 2; a += 2)
			s += fabs(pc_dimg_at(e, x + a, y + b) - pc_dimg_at(r, x + a, y + b));
	return s;
}

/* The edge classifier and fusion rule of the file comment, over the values: estimates v1, v2
 * with their misfits p1, p2 (φ) and gradients g1, g2 (d) along their directions. One rule for
 * the reference and the fast path, so the two agree by construction. */
static inline double newton_fuse(double v1, double v2, double p1, double p2, double g1, double g2,
                                 double eps)
{
	if (p1 > NEWTON_TAU * p2)
		return v2;
	if (p2 > NEWTON_TAU * p1)
		return v1;
	double w1 = 1 / (g1 + eps), w2 = 1 / (g2 + eps);
	return (w1 * v1 + w2 * v2) / (w1 + w2);
}

/* The fusion at (x, y): e1 along (u1), e2 along (u2). */
static double fuse(const pc_dimg *e1, const pc_dimg *e2, const pc_dimg *r, int x, int y, int u1x,
                   int u1y, int u2x, int u2y, double eps)
{
	return newton_fuse(pc_dimg_at(e1, x, y), pc_dimg_at(e2, x, y), phi(e1, r, x, y),
	                   phi(e2, r, x, y), grad(r, x, y, u1x, u1y), grad(r, x, y, u2x, u2y), eps);
}

int pc_dm_ref_newton(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                     double full_scale, const pc_fplane *out)
{
	if (m->period != 2)
		return pc_error(PC_ENOTSUP, "newton: monochrome mosaics only");
	const int w = (int)width, h = (int)height;
	const size_t n = (size_t)w * h;
	const double eps = NEWTON_EPS * (full_scale > 0 ? full_scale : 1);
	/* E[c]: stage-one estimate of channel c at every pixel; Y1, Y2 the diagonal estimates;
	 * X2, V2 stage two's second estimates of the horizontal / vertical neighbours' channels */
	double *buf = malloc(sizeof(double) * n * 8);
	if (!buf)
		return pc_error(PC_ENOMEM, "newton reference: %ux%u images", width, height);
	pc_dimg r = {(double *)img, w, h}, E[4], Y1 = {buf + 4 * n, w, h}, Y2 = {buf + 5 * n, w, h},
	        X2 = {buf + 6 * n, w, h}, V2 = {buf + 7 * n, w, h};
	for (int c = 0; c < 4; c++)
		E[c] = (pc_dimg){buf + (size_t)c * n, w, h};
#define CH(x, y)         ((unsigned)m->channel[(y)&1][(x)&1])
#define SET(im, x, y, v) ((im).p[(size_t)(y)*w + (x)] = (v))
	/* stage one: own, horizontal, vertical channels; the diagonal estimates */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			SET(E[CH(x, y)], x, y, img[(size_t)y * w + x]);
			SET(E[CH(x + 1, y)], x, y, newton(&r, &r, x, y, 1, 0));
			SET(E[CH(x, y + 1)], x, y, newton(&r, &r, x, y, 0, 1));
			SET(Y1, x, y, newton(&r, &r, x, y, 1, 1));
			SET(Y2, x, y, newton(&r, &r, x, y, 1, -1));
		}
	/* Fig. 6(a): the diagonal neighbour's channel */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++)
			SET(E[CH(x + 1, y + 1)], x, y, fuse(&Y1, &Y2, &r, x, y, 1, 1, 1, -1, eps));
	/* stage two's second estimates, across: X2 of the horizontal neighbour's channel along
	 * y, V2 of the vertical neighbour's along x, on stage one's estimates of that channel */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			SET(X2, x, y, newton(&E[CH(x + 1, y)], &r, x, y, 0, 1));
			SET(V2, x, y, newton(&E[CH(x, y + 1)], &r, x, y, 1, 0));
		}
	/* Fig. 6(b), 6(c): fused into the outputs (stage one's images stay intact for φ) */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			const unsigned th = CH(x + 1, y), tv = CH(x, y + 1);
			double o[4];
			for (unsigned c = 0; c < 4; c++)
				o[c] = pc_dimg_at(&E[c], x, y);
			o[th] = fuse(&E[th], &X2, &r, x, y, 1, 0, 0, 1, eps);
			o[tv] = fuse(&E[tv], &V2, &r, x, y, 0, 1, 1, 0, eps);
			for (unsigned c = 0; c < 4; c++)
				out[c].data[(size_t)y * out[c].row_stride +
				            (size_t)x * out[c].pixel_stride] = (float)o[c];
		}
#undef CH
#undef SET
	free(buf);
	return 0;
}

/* ---- the fast path: the same arithmetic in double (so the classifier's branches match the
 * reference's), without the per-read mirror: every intermediate image is computed on the
 * frame and then padded by NP mirrored samples (the widest read of any stage is ±3), which is
 * what the reference's mirrored reads of it see; row bands on threads. Equal to the reference
 * up to the order of nothing: the same expressions in the same order (tested within 1e-9 of
 * full scale, tests/test_demosaic.c). ---- */

#define NP 3
typedef struct njob {
	const pc_dm_input *in;
	const pc_mosaic *m;
	long w, h, s;
	double *R, *E[4], *A, *B; /* A, B: Y1, Y2 in stages 1-2, then X2, V2 */
	double eps;
	int stage;
	const pc_fplane *out;
} njob;

#define PA(p, x, y) ((p)[((long)(y) + NP) * j->s + (long)(x) + NP])
#define NCH(x, y)   ((unsigned)j->m->channel[(y)&1][(x)&1])

static void npad_cols(const njob *j, double *p, long y0, long y1)
{
	for (long y = y0; y < y1; y++)
		for (int k = 1; k <= NP; k++) {
			PA(p, -k, y) = PA(p, pc_mirror(-k, (int)j->w), y);
			PA(p, j->w - 1 + k, y) = PA(p, pc_mirror((int)j->w - 1 + k, (int)j->w), y);
		}
}

static void npad_rows(const njob *j, double *p)
{
	for (int k = 1; k <= NP; k++) {
		memcpy(&PA(p, -NP, -k), &PA(p, -NP, pc_mirror(-k, (int)j->h)),
		       sizeof(double) * (size_t)j->s);
		memcpy(&PA(p, -NP, j->h - 1 + k),
		       &PA(p, -NP, pc_mirror((int)j->h - 1 + k, (int)j->h)),
		       sizeof(double) * (size_t)j->s);
	}
}

static inline double fnewton(const njob *j, const double *t, long x, long y, int ux, int uy)
{
	const double *r = j->R;
	return 7.0 / 16 * (PA(t, x - ux, y - uy) + PA(t, x + ux, y + uy)) +
	       1.0 / 16 * (PA(t, x - 3 * ux, y - 3 * uy) + PA(t, x + 3 * ux, y + 3 * uy)) -
	       0.25 * (PA(r, x - 2 * ux, y - 2 * uy) - 2 * PA(r, x, y) +
	               PA(r, x + 2 * ux, y + 2 * uy));
}

static inline double fgrad(const njob *j, long x, long y, int ux, int uy)
{
	const double *r = j->R;
	return fabs(PA(r, x - ux, y - uy) - PA(r, x + ux, y + uy)) +
	       fabs(2 * PA(r, x, y) - PA(r, x - 2 * ux, y - 2 * uy) -
	            PA(r, x + 2 * ux, y + 2 * uy));
}

static inline double fphi(const njob *j, const double *e, long x, long y)
{
	const double *r = j->R;
	double s = 0;
	for (int b = -2; b <= 2; b += 2)
		for (int a = -2; a <= 2; a += 2)
			s += fabs(PA(e, x + a, y + b) - PA(r, x + a, y + b));
	return s;
}

static inline double ffuse(const njob *j, const double *e1, const double *e2, long x, long y,
                           int u1x, int u1y, int u2x, int u2y)
{
	return newton_fuse(PA(e1, x, y), PA(e2, x, y), fphi(j, e1, x, y), fphi(j, e2, x, y),
	                   fgrad(j, x, y, u1x, u1y), fgrad(j, x, y, u2x, u2y), j->eps);
}

static void nband(void *ctx, uint32_t y0u, uint32_t y1u)
{
	njob *j = ctx;
	const long y0 = y0u, y1 = y1u, w = j->w;
	switch (j->stage) {
	case 0:
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++)
				PA(j->R, x, y) =
				    (double)pc_dm_sample(j->in, (uint32_t)x, (uint32_t)y) -
				    j->in->black_d;
		npad_cols(j, j->R, y0, y1);
		break;
	case 1: /* stage one: own, horizontal, vertical; the diagonal estimates */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				PA(j->E[NCH(x, y)], x, y) = PA(j->R, x, y);
				PA(j->E[NCH(x + 1, y)], x, y) = fnewton(j, j->R, x, y, 1, 0);
				PA(j->E[NCH(x, y + 1)], x, y) = fnewton(j, j->R, x, y, 0, 1);
				PA(j->A, x, y) = fnewton(j, j->R, x, y, 1, 1);
				PA(j->B, x, y) = fnewton(j, j->R, x, y, 1, -1);
			}
		npad_cols(j, j->A, y0, y1);
		npad_cols(j, j->B, y0, y1);
		break;
	case 2: /* Fig. 6(a) */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++)
				PA(j->E[NCH(x + 1, y + 1)], x, y) =
				    ffuse(j, j->A, j->B, x, y, 1, 1, 1, -1);
		for (unsigned c = 0; c < 4; c++)
			npad_cols(j, j->E[c], y0, y1);
		break;
	case 3: /* stage two's second estimates, across */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				PA(j->A, x, y) = fnewton(j, j->E[NCH(x + 1, y)], x, y, 0, 1);
				PA(j->B, x, y) = fnewton(j, j->E[NCH(x, y + 1)], x, y, 1, 0);
			}
		npad_cols(j, j->A, y0, y1);
		npad_cols(j, j->B, y0, y1);
		break;
	default: /* Fig. 6(b), 6(c), into the outputs */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				const unsigned th = NCH(x + 1, y), tv = NCH(x, y + 1);
				double o[4];
				for (unsigned c = 0; c < 4; c++)
					o[c] = PA(j->E[c], x, y);
				o[th] = ffuse(j, j->E[th], j->A, x, y, 1, 0, 0, 1);
				o[tv] = ffuse(j, j->E[tv], j->B, x, y, 0, 1, 1, 0);
				for (unsigned c = 0; c < 4; c++)
					j->out[c].data[(size_t)y * j->out[c].row_stride +
					               (size_t)x * j->out[c].pixel_stride] =
					    (float)o[c];
			}
		break;
	}
}

int pc_dm_newton_fast(const pc_dm_call *call, const pc_fplane *out)
{
	const pc_dm_input *in = call->in;
	if (call->m->period != 2 || in->width < 2 * NP || in->height < 2 * NP)
		return pc_dm_ref_of_call(call, out);
	njob j;
	memset(&j, 0, sizeof j);
	j.in = in;
	j.m = call->m;
	j.w = in->width;
	j.h = in->height;
	j.s = j.w + 2 * NP;
	j.eps = NEWTON_EPS * (call->full_scale > 0 ? call->full_scale : 1);
	j.out = out;
	const size_t ps = (size_t)j.s * (size_t)(j.h + 2 * NP);
	double *mem = pc_dm_alloc(sizeof(double) * ps * 7);
	if (!mem)
		return pc_error(PC_ENOMEM, "newton: %ldx%ld planes", j.w, j.h);
	j.R = mem;
	for (int c = 0; c < 4; c++)
		j.E[c] = mem + ps * (size_t)(1 + c);
	j.A = mem + ps * 5;
	j.B = mem + ps * 6;
	for (j.stage = 0; j.stage <= 4; j.stage++) {
		pc_parallel_rows((uint32_t)j.h, 0, call->threads, nband, &j);
		if (j.stage == 0)
			npad_rows(&j, j.R);
		if (j.stage == 1 || j.stage == 3) {
			npad_rows(&j, j.A);
			npad_rows(&j, j.B);
		}
		if (j.stage == 2)
			for (int c = 0; c < 4; c++)
				npad_rows(&j, j.E[c]);
	}
	pc_dm_free(mem);
	return 0;
}
