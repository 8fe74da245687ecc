/* Flat-field noise propagation of the colour methods (docs/demosaicking.md, Round 13d): the
 * variance of every output channel, of S0 and of S1 + S2 per colour, as multiples of one raw
 * sample's variance σ², predicted from each output's linear weights and measured on the fast
 * paths (and on pan-side's double reference) for bayer-first, pan-ratio and pan-side, on a grey
 * and a coloured flat field. Synthetic data only.
 *
 * Prediction. Each output at a pixel p is written as a weighted sum of the raw's noise n_j
 * (white, variance σ²), its variance σ²·Σ c_j². The weights are built here from the methods'
 * definitions (the formulas of Round 13d), not by running any of the library's code: the
 * library supplies only the mosaic's layout (which colour and analyser a pixel samples). So an
 * error in an implementation's weights — the own sample's above all, where the methods differ —
 * shows as a mismatch instead of being copied into the prediction, as it would be by feeding
 * unit impulses through the double reference.
 *   bayer-first (core/demosaic_color.c) is linear: step 1, Bayer bilinear on each analyser's
 *   sub-image (same-colour samples at (±2, 0), (0, ±2) weight 2, at (±2, ±2) weight 1,
 *   normalised; the own colour taken as it is), then step 2, the monochrome bilinear of that
 *   analyser (same-analyser samples at (±1, 0), (0, ±1) weight 2, at (±1, ±1) weight 1,
 *   normalised) — the two compose into one weight vector per output.
 *   pan-ratio (core/demosaic_pan.c) outputs at p, own channel o, I_k + δ = x̃_p·R_k/R_o with
 *   R_k = Σ_q t_kq·ρ_q its normalised tents (T = (4 − |dx|)(4 − |dy|) on channel k's lattice
 *   within ±3), ρ_q = x̃_q/P̃_q, P0 the 5 × 5 filter m⊗m, m = (1 2 2 2 1)/8, x̃ = x + δ,
 *   δ = 1 % of full scale; I_o = x_p. Linearised about the flat field's means μ̃ = μ + δ:
 *     dI_k(p) = μ̃_k·[n_p/μ̃_o + Σ_q t_kq(n_q/μ̃_k − dP0_q/P̃) − Σ_q t_oq(n_q/μ̃_o − dP0_q/P̃)].
 *   pan-side equals pan-ratio to first order on a flat field (its range weights are uniform and
 *   its side factors 1 where the noise is small against e and ε: Round 13d).
 * The linearisation drops terms of relative size (σ/μ̃)² (products of two relative
 * fluctuations): it holds for σ small against the level + δ. Here σ = 5 DN against μ̃ ≥ 241 DN,
 * (σ/μ̃)² ≤ 4.3·10⁻⁴; LIN_TOL allows ten times that for the pan methods (0 for the linear
 * bayer-first).
 *
 * Measurement and its statistical error. Over the N pixels at least MARGIN from the borders
 * (all sixteen phases, equally often), the variance about each phase's own mean. Outputs whose
 * supports overlap are correlated, so the estimate's standard error is computed from the same
 * weights: for Gaussian noise Var(Σ_i y_i²/N) = (2σ⁴/N²)·Σ_{i,j} Cov(y_i, y_j)² (Isserlis), the
 * covariances Σ_n c_i(n)·c_j(n) over every neighbour j within ±2·RAD. The noise is Gaussian
 * (xorshift.h, fixed seed) on a float raw, so nothing is rounded and its variance is σ². On the
 * FAST_SIZE² fields (N = 2016²) the relative standard errors are 0.13–0.31 % (printed; a
 * channel of bayer-first interpolates one sample in sixteen, so about N/16 of its outputs are
 * independent: √(2·16/N) = 0.28 %); the check is |measured/predicted − 1| <= 5 standard errors
 * (+ LIN_TOL for the pan methods), 0.65–1.6 % (+ 0.43 %), against the effects the test is for:
 * the own sample's weight is where the methods part (Round 13d: S0 variance 2.5 times
 * bayer-first's), and moving 5 % of that weight in pan-ratio's multiplier to the same channel's
 * samples at ±4 pixels lowered its S0 variance by 8–10 % (checked by a local change, reverted).
 * pan-side's double reference runs on REF_SIZE² (N = 224², 81 times fewer pixels: standard
 * errors 1.2–2.7 %, nine times larger). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#define PC_TEST_SEED 14u
#include "xorshift.h"

#define RAD    5 /* the weights' reach: pan's tents ±3 plus P0's ±2 (bayer-first ±3) */
#define SW     (2 * RAD + 1)
#define MARGIN 16 /* from the borders: full support for every method */
#define FS     4095.0
#define SIGMA  5.0
#define NLIN   21 /* per colour: 4 channels, S0, S1, S2 */
/* ten times the largest (σ/μ̃)² of the fields below, (5/241)² */
#define LIN_TOL   4.3e-3
#define NSE       5.0
#define FAST_SIZE 2048
#define REF_SIZE  256

typedef double stencil[SW][SW]; /* weight of the raw sample at p + (dx, dy): [dy + RAD][dx + RAD] */

static pc_mosaic lay;
/* colour 0..2 (R, G, B) and analyser 0..3 at (x, y), x and y may be negative */
static unsigned col(int x, int y)
{
	return (unsigned)(pc_mosaic_color(&lay, (uint32_t)(x + 64), (uint32_t)(y + 64)) - PC_CFA_R);
}
static unsigned ana(int x, int y)
{
	return pc_mosaic_channel(&lay, (uint32_t)(x + 64), (uint32_t)(y + 64));
}
static unsigned chan(int x, int y)
{
	return 4 * col(x, y) + ana(x, y);
}

/* bayer-first's weights of output (k, c) at (px, py) (relative offsets into s) */
static void bf_weights(int px, int py, unsigned k, unsigned c, stencil s)
{
	memset(s, 0, sizeof(stencil));
	double sw = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++)
			if (ana(px + dx, py + dy) == c)
				sw += (2 - abs(dx)) * (2 - abs(dy));
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++) {
			if (ana(px + dx, py + dy) != c)
				continue;
			double w2 = (2 - abs(dx)) * (2 - abs(dy)) / sw;
			int qx = px + dx, qy = py + dy;
			if (col(qx, qy) == k) {
				s[dy + RAD][dx + RAD] += w2;
				continue;
			}
			double s1 = 0;
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++)
					if (col(qx + 2 * i, qy + 2 * j) == k)
						s1 += (2 - abs(i)) * (2 - abs(j));
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++)
					if (col(qx + 2 * i, qy + 2 * j) == k)
						s[dy + 2 * j + RAD][dx + 2 * i + RAD] +=
						    w2 * (2 - abs(i)) * (2 - abs(j)) / s1;
		}
}

/* d ln R_k at (px, py) times f, added to s: Σ_q t_kq (n_q/mt_k − dP0_q/P̃) */
static void pan_dlnr(int px, int py, unsigned k, double mtk, double pt, double f, stencil s)
{
	static const double m[5] = {1, 2, 2, 2, 1};
	double st = 0;
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++)
			if (chan(px + dx, py + dy) == k)
				st += (4 - abs(dx)) * (4 - abs(dy));
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			if (chan(px + dx, py + dy) != k)
				continue;
			double t = f * (4 - abs(dx)) * (4 - abs(dy)) / st;
			s[dy + RAD][dx + RAD] += t / mtk;
			for (int j = -2; j <= 2; j++)
				for (int i = -2; i <= 2; i++)
					s[dy + j + RAD][dx + i + RAD] -=
					    t * m[i + 2] * m[j + 2] / 64 / pt;
		}
}

/* pan-ratio's linearised weights of output k at (px, py), colour means mu[3] */
static void pan_weights(int px, int py, unsigned k, const double mu[3], stencil s)
{
	memset(s, 0, sizeof(stencil));
	unsigned o = chan(px, py);
	if (k == o) {
		s[RAD][RAD] = 1;
		return;
	}
	double delta = 0.01 * FS, pt = delta;
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			pt += mu[col(x, y)] / 16;
	double mk = mu[k / 4] + delta, mo = mu[o / 4] + delta;
	s[RAD][RAD] += mk / mo;
	pan_dlnr(px, py, k, mk, pt, mk, s);
	pan_dlnr(px, py, o, mo, pt, -mk, s);
}

/* The 21 linear outputs (per colour: the 4 channels, S0 = ΣI/2, S1 = I0 − I2, S2 = I1 − I3)
 * at the 16 phases of (x mod 4, y mod 4) */
typedef struct weights {
	stencil w[16][NLIN];
} weights;

static void build(weights *wt, int pan, const double mu[3])
{
	for (int ph = 0; ph < 16; ph++) {
		stencil ch[12];
		for (unsigned q = 0; q < 12; q++) {
			if (pan)
				pan_weights(ph % 4, ph / 4, q, mu, ch[q]);
			else
				bf_weights(ph % 4, ph / 4, q / 4, q % 4, ch[q]);
		}
		for (unsigned k = 0; k < 3; k++) {
			stencil *l = &wt->w[ph][7 * k];
			for (int i = 0; i < SW * SW; i++) {
				double a[4];
				for (int c = 0; c < 4; c++)
					a[c] = (&ch[4 * k + c][0][0])[i];
				for (int c = 0; c < 4; c++)
					(&l[c][0][0])[i] = a[c];
				(&l[4][0][0])[i] = (a[0] + a[1] + a[2] + a[3]) / 2;
				(&l[5][0][0])[i] = a[0] - a[2];
				(&l[6][0][0])[i] = a[1] - a[3];
			}
		}
	}
}

/* The 18 checked quantities: 12 channel variances, then S0 and S1 + S2 per colour; each the
 * sum of the variances of lin[q][0..nl) */
static int qlin(int q, int lin[2])
{
	if (q < 12) {
		lin[0] = 7 * (q / 4) + q % 4;
		return 1;
	}
	int k = (q - 12) / 2;
	if ((q - 12) % 2 == 0) {
		lin[0] = 7 * k + 4;
		return 1;
	}
	lin[0] = 7 * k + 5;
	lin[1] = 7 * k + 6;
	return 2;
}

static double dot_shift(const stencil a, const stencil b, int dx, int dy)
{
	/* Σ_n a(n)·b(n − d): b belongs to the pixel at p + d */
	double s = 0;
	for (int y = -RAD; y <= RAD; y++) {
		int yb = y - dy;
		if (yb < -RAD || yb > RAD)
			continue;
		for (int x = -RAD; x <= RAD; x++) {
			int xb = x - dx;
			if (xb >= -RAD && xb <= RAD)
				s += a[y + RAD][x + RAD] * b[yb + RAD][xb + RAD];
		}
	}
	return s;
}

/* predicted variance per σ² of quantity q, and its estimate's relative standard error over n
 * pixels */
static void predict(const weights *wt, int q, double n, double *var, double *rse)
{
	int lin[2], nl = qlin(q, lin);
	double v = 0, c2 = 0;
	for (int ph = 0; ph < 16; ph++) {
		for (int a = 0; a < nl; a++)
			v += dot_shift(wt->w[ph][lin[a]], wt->w[ph][lin[a]], 0, 0) / 16;
		for (int dy = -2 * RAD; dy <= 2 * RAD; dy++)
			for (int dx = -2 * RAD; dx <= 2 * RAD; dx++) {
				int pj = ((ph % 4 + dx + 64) % 4) + 4 * ((ph / 4 + dy + 64) % 4);
				for (int a = 0; a < nl; a++)
					for (int b = 0; b < nl; b++) {
						double c = dot_shift(wt->w[ph][lin[a]],
						                     wt->w[pj][lin[b]], dx, dy);
						c2 += c * c / 16;
					}
			}
	}
	*var = v;
	*rse = sqrt(2 * c2 / n) / v;
}

/* measured variance per σ² of the 18 quantities on the output planes f (w × h) */
static void measure(const pc_fplane f[12], int w, int h, double var[18])
{
	double s1[16][NLIN] = {{0}}, s2[16][NLIN] = {{0}};
	double cnt[16] = {0};
	for (int y = MARGIN; y < h - MARGIN; y++)
		for (int x = MARGIN; x < w - MARGIN; x++) {
			int ph = x % 4 + 4 * (y % 4);
			size_t i = (size_t)y * (size_t)w + (size_t)x;
			cnt[ph]++;
			for (int k = 0; k < 3; k++) {
				double a[4], l[7];
				for (int c = 0; c < 4; c++)
					l[c] = a[c] = f[4 * k + c].data[i];
				l[4] = (a[0] + a[1] + a[2] + a[3]) / 2;
				l[5] = a[0] - a[2];
				l[6] = a[1] - a[3];
				for (int j = 0; j < 7; j++) {
					s1[ph][7 * k + j] += l[j];
					s2[ph][7 * k + j] += l[j] * l[j];
				}
			}
		}
	for (int q = 0; q < 18; q++) {
		int lin[2], nl = qlin(q, lin);
		var[q] = 0;
		for (int ph = 0; ph < 16; ph++)
			for (int a = 0; a < nl; a++) {
				double m = s1[ph][lin[a]] / cnt[ph];
				var[q] += (s2[ph][lin[a]] - cnt[ph] * m * m) / (cnt[ph] - 1) / 16;
			}
		var[q] /= SIGMA * SIGMA;
	}
}

static const char *const qname[18] = {"R 0",  "R 45",    "R 90", "R 135",   "G 0",  "G 45",
                                      "G 90", "G 135",   "B 0",  "B 45",    "B 90", "B 135",
                                      "R S0", "R S1+S2", "G S0", "G S1+S2", "B S0", "B S1+S2"};

/* One method on one field: predicted against measured for all 18 quantities. */
static void check_method(pc_demosaic_method meth, int reference, const double mu[3], int size)
{
	weights *wt = malloc(sizeof *wt);
	int pan = meth != PC_DM_BAYER_FIRST;
	build(wt, pan, mu);
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_FLOAT32, (uint32_t)size, (uint32_t)size, 0), 0);
	rs = PC_TEST_SEED; /* the same noise draw for every method */
	for (int y = 0; y < size; y++)
		for (int x = 0; x < size; x++)
			PC_ROW(&raw, float, y)[x] = (float)(mu[col(x, y)] + SIGMA * nrand());
	pc_fplane f[12];
	float *buf = malloc(sizeof(float) * (size_t)size * (size_t)size * 12);
	pc_fplanes_separate(buf, (uint32_t)size, (uint32_t)size, 12, f);
	pc_demosaic_opts o = {0, reference != 0, FS};
	CHECK_EQ_INT(pc_demosaic(&raw, &lay, meth, &o, f), 0);
	double var[18], n = (double)(size - 2 * MARGIN) * (size - 2 * MARGIN);
	measure(f, size, size, var);
	printf("  %s%s, field %g/%g/%g, %d x %d: predicted / measured per sigma^2 "
	       "(relative standard error)\n",
	       pc_demosaic_method_get(meth)->name, reference ? " (reference)" : "", mu[0], mu[1],
	       mu[2], size, size);
	for (int q = 0; q < 18; q++) {
		double pv, rse;
		predict(wt, q, n, &pv, &rse);
		printf("    %-8s %.4f / %.4f (%.2f %%)%s", qname[q], pv, var[q], 100 * rse,
		       q % 3 == 2 ? "\n" : "  ");
		CHECK_REL(var[q], pv, NSE * rse + (pan ? LIN_TOL : 0));
	}
	free(buf);
	pc_view_free(&raw);
	free(wt);
}

int main(void)
{
	lay = pc_mosaic_imx250myr();
	const double grey[3] = {400, 400, 400}, colour[3] = {300, 600, 200};
	const double *field[2] = {grey, colour};
	for (int fi = 0; fi < 2; fi++) {
		check_method(PC_DM_BAYER_FIRST, 0, field[fi], FAST_SIZE);
		check_method(PC_DM_PAN_RATIO, 0, field[fi], FAST_SIZE);
		check_method(PC_DM_PAN_SIDE, 0, field[fi], FAST_SIZE);
		check_method(PC_DM_PAN_SIDE, 1, field[fi], REF_SIZE);
	}
	return pc_test_finish("test_colour_noise");
}
