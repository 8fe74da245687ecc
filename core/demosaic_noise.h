/* Internal to core: a frame's noise gain for the noise-aware colour method pan-adapt
 * (demosaic_pan.c; docs/demosaicking.md, Round 14). Shared by its double reference and its fast
 * path, which call it unchanged, so that both use the identical g. Not a public header.
 *
 * The model is EMVA 1288's linear photon-transfer curve (EMVA Standard 1288, the sensor model:
 * σ_y² = K²·σ_d² + K·(μ_y − μ_y.dark), the temporal variance of a sample linear in its mean with
 * slope the system gain K), with the read noise folded into a floor: a sample of mean level L has
 * variance g·(L + F), F = PC_DM_NG_FLOOR of full scale. g is estimated on a fixed grid of interior
 * samples p: the residual of p against the mean of its four same-channel neighbours at ±P (P the
 * mosaic's period, so the four share p's colour and analyser),
 *
 *   r(p) = raw(p) − nb(p),  nb(p) = (raw(p ± (P, 0)) + raw(p ± (0, P)))/4,
 *   t(p) = r(p)² / (max(nb(p), 0) + F),
 *
 * on a flat field of independent samples has variance (1 + 1/4)·g·(L + F) (the four neighbours'
 * mean adds a quarter of one sample's), and r²/(1.25·g·(L + F)) is χ²₁ for Gaussian noise. So
 *
 *   g = median_p t(p) / (1.25 · m₁),  m₁ = 0.45493642 the median of χ²₁,
 *
 * a robust scale estimate in the manner of Donoho & Johnstone's median absolute detail
 * coefficient (Biometrika 81(3) 1994, Sec. 4.2): texture and edges move the residuals of a
 * minority of the samples and hardly the median. Textured frames overestimate g (their
 * residuals carry detail), noise-free smooth frames give g ≈ 0.
 *
 * The grid: the samples x = P + i·s, y = P + j·s inside [P, w − P) × [P, h − P), s the smallest
 * odd integer with ((w − 2P)/s)·((h − 2P)/s) ≤ PC_DM_NG_POINTS (s odd, so every phase of the
 * period is sampled). The median is the element of rank ⌊n/2⌋ (0-based) of the n values, found
 * by selection, not a sort. Deterministic: the same samples give the same g, whatever the
 * thread count or instruction set. The relative standard error of the median of n χ²₁ values
 * is 1/(2·f(m₁)·m₁·√n) = 2.33/√n (f the χ²₁ density, 0.4712 at m₁): 0.9 % at n = 65536. */
#ifndef POLARCAM_DEMOSAIC_NOISE_H
#define POLARCAM_DEMOSAIC_NOISE_H

#include <stdint.h>

#include "demosaic_common.h"

#define PC_DM_NG_POINTS 65536            /* the grid's largest number of samples */
#define PC_DM_NG_FLOOR  0.01             /* F, fraction of full scale (pan's δ) */
#define PC_DM_NG_CHI1   0.45493642311957 /* the median of χ²₁ */

/* Sample (x, y) minus the black level, in double, of an image behind ctx */
typedef double (*pc_dm_sample_fn)(const void *ctx, uint32_t x, uint32_t y);

/* The noise gain g (raw units: variance per unit level) of a w × h frame read through get, on
 * mosaic m, fs the full scale; 0 when the frame has no interior sample (w or h ≤ 2P). 0 or
 * PC_ENOMEM for the values' buffer (*g untouched). */
int pc_dm_noise_gain(pc_dm_sample_fn get, const void *ctx, uint32_t w, uint32_t h,
                     const pc_mosaic *m, double fs, double *g);

/* The same on the references' input (raw minus black in double, C order) */
int pc_dm_noise_gain_d(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       double *g);

/* The same on the fast paths' prepared input: samples (double)pc_dm_sample − black_d, equal to
 * pc_dm_raw_to_double's values, so the reference and the fast path get the same g. The colour
 * paths' inputs carry no dark or gain maps (the front door corrects a copy first); an input with
 * them is refused (PC_EINVAL). */
int pc_dm_noise_gain_in(const pc_dm_input *in, const pc_mosaic *m, double fs, double *g);

/* pc_dm_noise_gain_in on threads threads (pc_parallel_rows' count: 0 its default, 1 the
 * caller's): the grid's rows computed in parallel into their fixed places, so the same g bit for
 * bit whatever the count (docs/demosaicking.md, Round 16a) */
int pc_dm_noise_gain_in_mt(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           double *g);

#endif
