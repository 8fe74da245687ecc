/* pan-check (docs/demosaicking.md, Round 17): a guarded colour method built for the 5x budget.
 *
 * pan-guard (demosaic_pan_guard.c, Round 15) and pan-hue (demosaic_pan_hue.c, Round 16) fall
 * back towards bayer-first where the pan ratio model fails, but their base (pan-adapt) and
 * fallback (bayer-first) cost 21x and more of the mono bilinear. pan-check keeps their checks
 * and swaps both for estimates one band pass can compute:
 *
 *  1. The base I_p: pan-side's (pc_dm_pan_side_ref, base 0) or pan-guided's (base 1); the
 *     conservative estimate I_b (cons 5, the method's): red and blue every channel's normalised
 *     tents on its own samples' values (pc_dm_pan_guard_tents, pan-guard's "cons 1"), which
 *     equal bayer-first's away from the borders (Round 17: bayer-first's second, step-2
 *     bilinear reproduces its first step's step-4 bilinear); green's analyser mean
 *     bayer-first's (its colour step's M_G, the mean of the four same-analyser greens at ±2 px,
 *     then mono bilinear; pc_dm_bayer_first_ref) and its modulation, each green channel less
 *     the four's mean, the tents'. cons 4: bayer-first's green; cons 1: the tents' green;
 *     diagnostics: cons 0 bayer-first, cons 2 and 3 the 2×2 blocks' mean raw by pan-guard's
 *     tent with the base's modulation scaled to it (2) or the tents' modulation added (3).
 *  2. pan-guard's leave-one-out errors per 2×2 block (pc_dm_pan_guard_blocks: e_b plain, e_p
 *     ratio model, mu the mean level max(raw, 0) + δ) and their window sums E_b, E_p over the
 *     same colour's blocks within ±4r pixels.
 *  3. A noise term (derived here, Round 17): the leave-one-out errors carry the same noise
 *     (raw(s) against a mean of four neighbours in both, ≈ 1.25 σ² a sample), but the outputs do
 *     not: the pan ratio step gives channel q at pixel x the pixel's own sample times a smooth
 *     ratio, I_q = (S_o + δ)·R_q/R_o − δ (Round 13's edge bound), so one sample's noise, σ²,
 *     while the tents average about two to four samples (≈ 0.3–0.6 σ²). The base's error sum
 *     gets c_k·Σ 4σ²(B′) over the window's blocks, σ² = g·mu (pan-adapt's noise model,
 *     demosaic_noise.h; g the given noise gain or the frame's estimate, pc_dm_noise_gain_d),
 *     c_k per colour (Round 18): c_G for green's blocks, c_RB for red's and blue's, whose
 *     lattices are four times sparser.
 *  4. The block weight of the base, pan-guard's w(B) = (E_b + F)^γ / ((E_b + F)^γ + (E_p' + F)^γ)
 *     (Bates & Granger, Operational Research Quarterly 20(4) 1969, sharpened by γ, Round 15),
 *     per pixel and colour W_k by pan-guard's tent (pc_dm_pan_guard_tent), and
 *     O_q = W_k·I_p,q + (1 − W_k)·I_b,q.
 *  5. For red and blue, pan-hue's cross-colour gate D(B) (pc_dm_pan_hue_gates with κ, its q =
 *     0.25 quantile, its noise term c = 1, r and γ as step 2 and 4), tent-interpolated to D_k,
 *     and I_q = (1 − D_k)·O_q + D_k·I_b,q (towards the tents, not bayer-first). κ = 0: no gate.
 *     Green's residual in the gate is max(e_p − β·(e_b − e_p), 0), β = 0.75 (Round 19b): the
 *     part of green's detail that the ratio model against P̃ leaves, less β times the part it
 *     explains, so that luminance detail P̃ partly follows (periods from about 5.5 px) does
 *     not read as hue detail (Round 17e's gate, β = 0, doubled red's and blue's error on grey
 *     bars at 8 px; Round 19a).
 *
 * Every constant is PC_DM_PAN_CHECK_* (demosaic_pan_check.h). */
#include "demosaic_pan_check.h"

#include <math.h>
#include <stdlib.h>

#include "demosaic_color.h"
#include "demosaic_noise.h"
#include "demosaic_pan.h"
#include "polarcam/error.h"

pc_dm_pan_check_params pc_dm_pan_check_defaults(void)
{
	pc_dm_pan_check_params p = {PC_DM_PAN_CHECK_BASE,
	                            PC_DM_PAN_CHECK_CONS,
	                            PC_DM_PAN_CHECK_R,
	                            PC_DM_PAN_CHECK_GAMMA,
	                            PC_DM_PAN_CHECK_FLOOR,
	                            PC_DM_PAN_CHECK_NOISE,
	                            PC_DM_PAN_CHECK_KAPPA,
	                            -1.0,
	                            -1.0,
	                            PC_DM_PAN_CHECK_NOISE_GREEN,
	                            PC_DM_PAN_CHECK_BETA};
	return p;
}

int pc_dm_pan_check_check(const pc_dm_pan_check_params *p)
{
	if ((p->base != 0 && p->base != 1) || p->cons < 0 || p->cons > 5 || p->r < 0 ||
	    p->r > PC_DM_PAN_HUE_RMAX || !(p->gamma > 0) || !isfinite(p->gamma) ||
	    !(p->floor >= 0) || !isfinite(p->floor) || !(p->noise >= 0) || !isfinite(p->noise) ||
	    !(p->noise_green >= 0) || !isfinite(p->noise_green) || !(p->kappa >= 0) ||
	    !isfinite(p->kappa) || !(p->force <= 1) || !isfinite(p->force) || !isfinite(p->g) ||
	    !(p->beta >= 0) || !isfinite(p->beta))
		return pc_error(PC_EINVAL, "pan-check: parameters out of range");
	return 0;
}

int pc_dm_pan_check_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_check_params *p, const pc_fplane *out)
{
	int rc = pc_dm_pan_check_check(p);
	if (rc)
		return rc;
	const size_t n = (size_t)w * h;
	float *planes = malloc(sizeof(float) * n * 36);
	double *wb = NULL, *gate = NULL, *bm = NULL;
	pc_dm_guard_blocks bl = {0, 0, 0, NULL, NULL, NULL, NULL};
	if (!planes)
		return pc_error(PC_ENOMEM, "pan-check reference: images of %ux%u", w, h);
	pc_fplane ip[12], ib[12];
	for (unsigned q = 0; q < 12; q++) {
		ip[q] = (pc_fplane){planes + q * n, w, 1};
		ib[q] = (pc_fplane){planes + (12 + q) * n, w, 1};
	}
	/* 1. the two estimates */
	rc = p->base ? pc_dm_pan_guided_ref(img, w, h, m, fs, ip)
	             : pc_dm_pan_side_ref(img, w, h, m, fs, ip);
	if (!rc && p->cons)
		pc_dm_pan_guard_tents(img, w, h, m, ib); /* cons 2 overwrites them below */
	if (!rc && (p->cons == 0 || p->cons >= 4)) {
		/* cons 4: bayer-first's green (its colour step's M_G, then mono bilinear), the
		 * tents' red and blue (equal to bayer-first's away from the borders) */
		pc_fplane bf[12];
		for (unsigned q = 0; q < 12; q++)
			bf[q] = (pc_fplane){planes + (24 + q) * n, w, 1};
		rc = pc_dm_bayer_first_ref(img, w, h, m, PC_DM_BILINEAR, fs, bf);
		for (unsigned q = 0; q < 12 && !rc; q++)
			if (p->cons == 0 || (p->cons == 4 && q >= 4 && q < 8))
				for (size_t a = 0; a < n; a++)
					ib[q].data[a] = bf[q].data[a];
		/* cons 5: green's analyser mean bayer-first's, its modulation the tents' */
		for (size_t a = 0; a < n && !rc && p->cons == 5; a++) {
			double mb = 0, mt = 0;
			for (unsigned c = 0; c < 4; c++) {
				mb += (double)bf[4 + c].data[a] / 4;
				mt += (double)ib[4 + c].data[a] / 4;
			}
			for (unsigned c = 0; c < 4; c++)
				ib[4 + c].data[a] = (float)(mb + ((double)ib[4 + c].data[a] - mt));
		}
	}
	/* 2. the blocks, with room for the windows ±4r around the tents' −4 .. +3 */
	if (!rc)
		rc = pc_dm_pan_guard_blocks(img, w, h, m, fs, 4 + 4 * p->r, &bl);
	if (!rc) {
		wb = malloc(sizeof(double) * (size_t)bl.NBX * (size_t)bl.NBY);
		gate = malloc(sizeof(double) * (size_t)bl.NBX * (size_t)bl.NBY);
		bm = malloc(sizeof(double) * (size_t)bl.NBX * (size_t)bl.NBY);
		if (!wb || !gate || !bm)
			rc = pc_error(PC_ENOMEM, "pan-check reference: images of %ux%u", w, h);
	}
	double g = p->g;
	if (!rc && g < 0 && (p->noise > 0 || p->noise_green > 0 || p->kappa > 0))
		rc = pc_dm_noise_gain_d(img, w, h, m, fs, &g);
	if (rc)
		goto done;
	g = fmax(g, 0);
	const int XB = bl.XB, NBX = bl.NBX, NBY = bl.NBY, rb = 2 * p->r;
	const double fl = (p->floor * fs) * (p->floor * fs);
	/* 3., 4. the window sums, the noise term, the block weights */
	for (int j = 0; j < NBY; j++)
		for (int i = 0; i < NBX; i++) {
			double sw[3];
			pc_dm_pan_guard_window(&bl, i, j, rb, sw);
			const double c =
			    bl.col[(size_t)j * NBX + i] == 1 ? p->noise_green : p->noise;
			const double ab = pow(sw[0] + fl, p->gamma),
			             ap = pow(sw[1] + c * 4 * g * sw[2] + fl, p->gamma);
			wb[(size_t)j * NBX + i] = ab + ap > 0 ? ab / (ab + ap) : 1;
		}
	if (p->cons == 2 || p->cons == 3) {
		/* each block's mean raw (its colour's analyser mean, polarization-free) */
		for (int j = 0; j < NBY; j++)
			for (int i = 0; i < NBX; i++) {
				double sm = 0;
				for (int o = 0; o < 4; o++)
					sm +=
					    img[(size_t)pc_mirror4(2 * j - XB + (o >> 1), (int)h) *
					            w +
					        (size_t)pc_mirror4(2 * i - XB + (o & 1), (int)w)];
				bm[(size_t)j * NBX + i] = sm / 4;
			}
		const double delta = PC_DM_PAN_ADAPT_DFS * fs;
		for (int y = 0; y < (int)h; y++)
			for (int x = 0; x < (int)w; x++) {
				double num[3], den[3];
				pc_dm_pan_guard_tent(&bl, bm, m, (int)w, (int)h, x, y, num, den);
				const size_t a = (size_t)y * w + (size_t)x;
				for (unsigned k = 0; k < 3; k++) {
					const double sk = num[k] / den[k];
					double sp = 0, st = 0;
					for (unsigned c = 0; c < 4; c++) {
						sp += (double)ip[4 * k + c].data[a] / 4;
						st += (double)ib[4 * k + c].data[a] / 4;
					}
					for (unsigned c = 0; c < 4; c++) {
						float *v = &ib[4 * k + c].data[a];
						const double vp = ip[4 * k + c].data[a];
						*v = p->cons == 2
						         ? (float)(sk * (fmax(vp, 0) + delta) /
						                   (fmax(sp, 0) + delta))
						         : (float)(sk + ((double)*v - st));
					}
				}
			}
	}
	/* 5. pan-hue's gate for red and blue */
	if (p->kappa > 0 && p->force < 0) {
		pc_dm_pan_hue_params hp = pc_dm_pan_hue_defaults();
		hp.guard.floor = p->floor;
		hp.kappa = p->kappa;
		hp.r = p->r;
		hp.gamma = p->gamma;
		hp.beta = p->beta;
		pc_dm_pan_hue_gates(&bl, &hp, fs, g, gate);
	} else {
		for (size_t a = 0; a < (size_t)NBX * NBY; a++)
			gate[a] = 0;
	}
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			double num[3], den[3], gn[3], gd[3];
			pc_dm_pan_guard_tent(&bl, wb, m, (int)w, (int)h, x, y, num, den);
			pc_dm_pan_guard_tent(&bl, gate, m, (int)w, (int)h, x, y, gn, gd);
			const size_t a = (size_t)y * w + (size_t)x;
			for (unsigned k = 0; k < 3; k++) {
				const double wk = p->force >= 0 ? p->force : num[k] / den[k];
				const double d = p->force >= 0 ? 0 : gn[k] / gd[k];
				for (unsigned c = 0; c < 4; c++) {
					const unsigned q = 4 * k + c;
					const double vp = ip[q].data[a], vb = ib[q].data[a];
					const double o = wk * vp + (1 - wk) * vb;
					out[q].data[(size_t)y * out[q].row_stride +
					            (size_t)x * out[q].pixel_stride] =
					    (float)((1 - d) * o + d * vb);
				}
			}
		}
done:
	free(bm);
	free(gate);
	free(wb);
	pc_dm_pan_guard_blocks_free(&bl);
	free(planes);
	return rc;
}

int pc_dm_pan_check_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out)
{
	pc_dm_pan_check_params p = pc_dm_pan_check_defaults();
	return pc_dm_pan_check_ref_with(img, w, h, m, fs, &p, out);
}
