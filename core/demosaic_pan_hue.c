/* pan-hue (docs/demosaicking.md, Round 16): pan-guard with a cross-colour gate for red and blue.
 *
 * pan-guard (demosaic_pan_guard.c) blends pan-adapt towards bayer-first per colour where a
 * leave-one-out check on the colour's own samples finds the ratio model worse. Red and blue
 * are sampled once per 4×4 period: a hue pattern near that period (green against magenta bars,
 * red against cyan checks, halftone screens) aliases on their lattice, their own samples look
 * smooth there, and the check cannot tell the ratio model from plain averaging. But the ratio
 * step gives red and blue, at the green pixels (half of all), green's own sample times a smooth
 * ratio: where green's ratio to the guide P̃ is not smooth — hue detail that P0 does not carry
 * — that error goes into red and blue whatever their own lattice shows. Green is sampled twice
 * as densely, so its ratio residual sees such patterns down to a 4-pixel period. The gate
 * compares the two (derived here, docs/demosaicking.md Round 16):
 *
 *  0. (Round 17a) pan-guard's base is pan-adapt with its shrinkage undone, for each colour's own
 *     outputs, where the colour's ratio residual exceeds c_u times its expected noise
 *     (pc_dm_pan_guard_params.unshrink, c_u = PC_DM_PAN_HUE_UNSHRINK; demosaic_pan_guard.c,
 *     guard_unshrink): pan-adapt's shrinkage, driven by P̃'s variance, smooths away hue detail
 *     that P0 does not carry (dim green bars on magenta), which no later step can restore.
 *  1. pan-guard's output O and, from its reference (pc_dm_pan_guard_ref_parts), bayer-first's I_b
 *     (pc_dm_bayer_first_ref with PC_DM_BILINEAR) and its blocks (pc_dm_pan_guard_blocks): per
 * 2×2 block its leave-one-out errors e_b (plain), e_p (ratio model) and mean level mu of max(raw,
 * 0) + δ.
 *  2. For each red or blue block B (colour k), over the blocks within ±4r pixels on both axes:
 *     the mean ε_G of green's residual max(e_p − β·(e_b − e_p), 0) (the part of green's detail
 *     the ratio model does not explain, Round 19b; β = 0.75 since Round 19e, before it e_p
 *     itself) and its mean level m_G, the mean ε_k of k's own e_b and its
 *     mean level m_k. Green's ratio residual carried into k by the ratio step (the step
 *     multiplies green's sample by the ratio of k to green, about m_k/m_G):
 *
 *       X = κ·max(ε_G − c·5·g·m_G, 0)·(m_k/m_G)²,   Y = ε_k + F   (F = (f·FS)², pan-guard's
 *       floor),
 *
 *     where 5·g·m_G is the expected noise part of ε_G (four samples, each with a flat field's
 *     leave-one-out residual 1.25 σ², σ² = g·(level + δ) the noise model of pan-adapt,
 *     demosaic_noise.h; g the given noise gain or the frame's estimate) and c its weight:
 *     without it green's noise, scaled into a brighter red or blue, would read as hue detail.
 *     and the gate D(B) = X^γ/(X^γ + Y^γ) = 1/(1 + (Y/X)^γ), 0 where X = 0: the share of the
 *     two errors as pan-guard's weight (Bates & Granger, "The combination of forecasts",
 *     Operational Research Quarterly 20(4) 1969, sharpened by γ as in Round 15). Green's
 *     blocks have D = 0 (green is not gated: its own check sees its detail).
 *  3. Per pixel D_k(p) for k red and blue: pan-guard's tent over k's blocks
 *     (pc_dm_pan_guard_tent), and I_q = (1 − D_k)·O_q + D_k·I_b,q for k's four analysers;
 *     green's channels are O's. D = 0 gives pan-guard bit for bit, D = 1 bayer-first's.
 *
 * Where green's residual is small against red's and blue's own (smooth hue, luminance detail
 * that P̃ follows) the gate is ≈ 0 and the method is pan-guard. It does not tell hue detail
 * from fine luminance detail that P0's 5×5 filter removes (its response is 0 at a 4-pixel
 * period): there it falls back too. The constants are PC_DM_PAN_HUE_* (demosaic_pan.h),
 * chosen on the development sets by Round 16's rule. */
#include <math.h>
#include <stdlib.h>

#include "demosaic_noise.h"
#include "demosaic_pan.h"
#include "demosaic_pan_check.h"
#include "polarcam/error.h"

pc_dm_pan_hue_params pc_dm_pan_hue_defaults(void)
{
	pc_dm_pan_guard_params guard = pc_dm_pan_guard_defaults();
	guard.unshrink = PC_DM_PAN_HUE_UNSHRINK;
	pc_dm_pan_hue_params p = {guard,
	                          PC_DM_PAN_HUE_KAPPA,
	                          PC_DM_PAN_HUE_R,
	                          PC_DM_PAN_HUE_GAMMA,
	                          PC_DM_PAN_HUE_NOISE,
	                          PC_DM_PAN_HUE_QUANT,
	                          PC_DM_PAN_HUE_GREEN,
	                          -1.0,
	                          PC_DM_PAN_CHECK_BETA};
	return p;
}

static int hue_check(const pc_dm_pan_hue_params *p)
{
	int rc = pc_dm_pan_guard_check(&p->guard);
	if (rc)
		return rc;
	if (!(p->kappa >= 0) || !isfinite(p->kappa) || p->r < 0 || p->r > PC_DM_PAN_HUE_RMAX ||
	    !(p->gamma > 0) || !isfinite(p->gamma) || !(p->noise >= 0) || !isfinite(p->noise) ||
	    !(p->quant >= 0 && p->quant <= 1) || (p->green != 0 && p->green != 1) ||
	    !(p->force <= 1) || !isfinite(p->force) || !(p->beta >= 0) || !isfinite(p->beta))
		return pc_error(PC_EINVAL, "pan-hue: parameters out of range");
	return 0;
}

/* step 2: the gate D(B) of every block (0 for green) */
void pc_dm_pan_hue_gates(const pc_dm_guard_blocks *b, const pc_dm_pan_hue_params *p, double fs,
                         double g, double *gate)
{
	const int rb = 2 * p->r; /* in block steps */
	const double fl = (p->guard.floor * fs) * (p->guard.floor * fs);
	for (int j = 0; j < b->NBY; j++)
		for (int i = 0; i < b->NBX; i++) {
			const size_t at = (size_t)j * b->NBX + i;
			const unsigned k = b->col[at];
			gate[at] = 0;
			if (k == 1 && !p->green)
				continue;
			/* pass 1: the window's blocks (index and colour), each colour's mean level,
			 * k's own plain residual */
			enum { NW = (4 * PC_DM_PAN_HUE_RMAX + 1) * (4 * PC_DM_PAN_HUE_RMAX + 1) };
			size_t wa[NW];
			unsigned wc[NW];
			int nw = 0;
			double msum[3] = {0, 0, 0}, ek = 0;
			int cnt[3] = {0, 0, 0};
			for (int jj = j - rb; jj <= j + rb; jj++)
				for (int ii = i - rb; ii <= i + rb; ii++) {
					if (ii < 0 || jj < 0 || ii >= b->NBX || jj >= b->NBY)
						continue;
					const size_t a = (size_t)jj * b->NBX + ii;
					const unsigned c = b->col[a];
					wa[nw] = a;
					wc[nw++] = c;
					msum[c] += b->mu[a];
					cnt[c]++;
					if (c == k)
						ek += b->eb[a];
				}
			if (!cnt[k])
				continue;
			const double mk = msum[k] / cnt[k];
			/* pass 2: the other colours' ratio residuals in excess of their expected
			 * noise (4 samples × 1.25 σ², a flat field's leave-one-out residual, σ² =
			 * g·mu), scaled into k's level, sorted */
			double v[NW];
			int nv = 0;
			for (int u = 0; u < nw; u++) {
				const size_t a = wa[u];
				const unsigned c = wc[u];
				if (c == k || (k != 1 && c != 1))
					continue;
				const double mc = msum[c] / cnt[c], rel = mk / mc;
				/* β = 0: e_p itself (finite and ≥ 0, so ep − 0·(…) and fmax keep
				 * it) */
				const double ev =
				    fmax(b->ep[a] - p->beta * (b->eb[a] - b->ep[a]), 0);
				const double e = fmax(ev - p->noise * 5 * g * mc, 0) * rel * rel;
				int t = nv++;
				while (t > 0 && v[t - 1] > e) {
					v[t] = v[t - 1];
					t--;
				}
				v[t] = e;
			}
			if (!nv)
				continue;
			/* their q-quantile (linear between order statistics) */
			const double pos = p->quant * (nv - 1);
			const int lo = (int)pos;
			const double vq =
			    lo + 1 < nv ? v[lo] + (pos - lo) * (v[lo + 1] - v[lo]) : v[lo];
			const double x = p->kappa * vq, y = ek / cnt[k] + fl;
			gate[at] = x > 0 ? 1 / (1 + pow(y / x, p->gamma)) : 0;
		}
}

int pc_dm_pan_hue_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           const pc_dm_pan_hue_params *p, const pc_fplane *out)
{
	int rc = hue_check(p);
	if (rc)
		return rc;
	/* pan-guard's output, with its bayer-first estimate and blocks (reach ±4r for the gates) */
	pc_dm_guard_parts parts;
	rc = pc_dm_pan_guard_ref_parts(img, w, h, m, fs, &p->guard, 4 + 4 * p->r, out, &parts);
	const pc_dm_guard_blocks *bl = &parts.bl;
	double *gate = NULL;
	if (!rc) {
		gate = malloc(sizeof(double) * (size_t)bl->NBX * (size_t)bl->NBY);
		if (!gate)
			rc = pc_error(PC_ENOMEM, "pan-hue reference: images of %ux%u", w, h);
	}
	/* the noise gain: the given one, or the frame's estimate (pan-adapt's, demosaic_noise.h) */
	double g = p->guard.g;
	if (!rc && g < 0 && p->noise > 0)
		rc = pc_dm_noise_gain_d(img, w, h, m, fs, &g);
	if (rc) {
		free(gate);
		pc_dm_pan_guard_parts_free(&parts);
		return rc;
	}
	pc_dm_pan_hue_gates(bl, p, fs, fmax(g, 0), gate);
	/* step 3: red (k 0) and blue (k 2) towards bayer-first by their gates */
	const size_t n = (size_t)w * h;
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			double num[3], den[3];
			pc_dm_pan_guard_tent(bl, gate, m, (int)w, (int)h, x, y, num, den);
			const size_t a = (size_t)y * w + (size_t)x;
			for (unsigned k = 0; k < 3; k++) {
				if (k == 1 && !p->green)
					continue;
				const double d = p->force >= 0 ? p->force : num[k] / den[k];
				for (unsigned c = 0; c < 4; c++) {
					const unsigned q = 4 * k + c;
					float *o = out[q].data + (size_t)y * out[q].row_stride +
					           (size_t)x * out[q].pixel_stride;
					*o = (float)((1 - d) * (double)*o +
					             d * (double)parts.ib[q * n + a]);
				}
			}
		}
	free(gate);
	pc_dm_pan_guard_parts_free(&parts);
	return 0;
}

int pc_dm_pan_hue_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      const pc_fplane *out)
{
	pc_dm_pan_hue_params p = pc_dm_pan_hue_defaults();
	return pc_dm_pan_hue_ref_with(img, w, h, m, fs, &p, out);
}
