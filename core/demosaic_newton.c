/* The Newton-polynomial method of Li, Zhao, Pan and Kong, "Demosaicking DoFP images using
 * Newton's polynomial interpolation and polarization difference model", Opt. Express 27(2)
 * 1376-1391 (2019), in double precision (the reference; no fast path yet). Only the paper's
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

#include "demosaic_anchors.h"
#include "polarcam/error.h"

#define NEWTON_TAU 5.8
#define NEWTON_EPS 1e-15

typedef struct dimg {
	double *p;
	int w, h;
} dimg;

static double at(const dimg *r, int x, int y)
{
	return r->p[(size_t)pc_mirror(y, r->h) * r->w + pc_mirror(x, r->w)];
}

/* N_u(p) of the file comment: t the target's image (read at odd steps), r the raw (even). */
static double newton(const dimg *t, const dimg *r, int x, int y, int ux, int uy)
{
	return 7.0 / 16 * (at(t, x - ux, y - uy) + at(t, x + ux, y + uy)) +
	       1.0 / 16 * (at(t, x - 3 * ux, y - 3 * uy) + at(t, x + 3 * ux, y + 3 * uy)) -
	       0.25 * (at(r, x - 2 * ux, y - 2 * uy) - 2 * at(r, x, y) + at(r, x + 2 * ux, y + 2 * uy));
}

/* d_k: the gradient along u */
static double grad(const dimg *r, int x, int y, int ux, int uy)
{
	return fabs(at(r, x - ux, y - uy) - at(r, x + ux, y + uy)) +
	       fabs(2 * at(r, x, y) - at(r, x - 2 * ux, y - 2 * uy) - at(r, x + 2 * ux, y + 2 * uy));
}

/* φ of an estimate image e against the raw over p's 3×3 same-channel neighbourhood */
static double phi(const dimg *e, const dimg *r, int x, int y)
{
	double s = 0;
	for (int b = -2; b <= 2; b += 2)
		for (int a = -2; a <= 2; a += 2)
			s += fabs(at(e, x + a, y + b) - at(r, x + a, y + b));
	return s;
}

/* The edge classifier and fusion: e1 along (u1), e2 along (u2). */
static double fuse(const dimg *e1, const dimg *e2, const dimg *r, int x, int y, int u1x, int u1y,
                   int u2x, int u2y, double eps)
{
	double p1 = phi(e1, r, x, y), p2 = phi(e2, r, x, y);
	double v1 = at(e1, x, y), v2 = at(e2, x, y);
	if (p1 > NEWTON_TAU * p2)
		return v2;
	if (p2 > NEWTON_TAU * p1)
		return v1;
	double w1 = 1 / (grad(r, x, y, u1x, u1y) + eps), w2 = 1 / (grad(r, x, y, u2x, u2y) + eps);
	return (w1 * v1 + w2 * v2) / (w1 + w2);
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
	dimg r = {(double *)img, w, h}, E[4], Y1 = {buf + 4 * n, w, h}, Y2 = {buf + 5 * n, w, h},
	     X2 = {buf + 6 * n, w, h}, V2 = {buf + 7 * n, w, h};
	for (int c = 0; c < 4; c++)
		E[c] = (dimg){buf + (size_t)c * n, w, h};
#define CH(x, y) ((unsigned)m->channel[(y) & 1][(x) & 1])
#define SET(im, x, y, v) ((im).p[(size_t)(y) * w + (x)] = (v))
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
				o[c] = at(&E[c], x, y);
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
