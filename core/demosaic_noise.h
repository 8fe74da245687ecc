/* Internal to core: a frame's noise gain for the noise-aware colour methods (pan-adapt,
 * pan-guard, pan-hue, pan-check; docs/demosaicking.md, Rounds 14 and 19). Shared by its double
 * reference and its fast path, which call it unchanged, so that both use the identical g. Not a
 * public header.
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
 * minority of the samples and hardly the median. Texture at the period's own scale (grass,
 * tesserae, fabric) moves most of them, and that estimate then reads texture as noise
 * (docs/demosaicking.md, Round 18f: 264.6 DN on a noise-free render).
 *
 * So a second estimate cancels the scene instead of differencing it over P (Round 19). The four
 * analysers of a 2×2 polarizer block (one colour) see nearly one Stokes vector, and for any
 * Stokes vector the ideal analysers' intensities satisfy I₀ + I₉₀ = I₄₅ + I₁₃₅ = S₀ (Malus's law,
 * I_θ = (S₀ + S₁ cos 2θ + S₂ sin 2θ)/2; Goldstein, Polarized Light, 3rd ed. 2011, Ch. 5). The
 * block residual
 *
 *   u(b) = (I₀ + I₉₀ − I₄₅ − I₁₃₅)² / (Σ max(Iᵢ, 0) + 4F)
 *
 * is then noise alone plus what the Stokes vector changes within the block: for the Sony layout
 * [90 45; 135 0] the 0°/90° and 45°/135° pairs are the two diagonals, whose means agree on any
 * linear ramp of S₀, so only curvature of S₀ and first differences of S₁, S₂ across one pixel
 * remain. The noise part has variance g·(ΣLᵢ + 4F) and does not correlate with the sum in the
 * denominator (the signs cancel), so median u / m₁ estimates g. Blocks: the 2×2 polarizer blocks
 * (from the colour origin of a colour mosaic, from (0, 0) of a monochrome one; the four samples
 * summed in raster order, the floor first in the denominator), every s-th
 * block in each direction, s the smallest odd integer leaving at most PC_DM_NG_POINTS.
 *
 * Texture can only raise either estimate (a residual r = n + d with a fixed detail d and noise n
 * symmetric about 0 has |r| stochastically larger than |n|), so g = min(g_period, g_block): on a
 * flat noisy field both estimate g (the minimum is biased low by less than their 0.9 % standard
 * error), and on texture the less fooled one counts. Noise-free smooth frames give g ≈ 0.
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

/* ---- the photon-transfer line of a frame (ratio-nr's noise model; docs/demosaicking.md,
 * Round 40) ----
 *
 * EMVA Standard 1288's sensor model makes the temporal variance of a sample linear in its mean
 * level L above black: σ²(L) = a·L + b, a the system gain K (raw units per electron), b the
 * read noise and quantisation (K²·σ_d² + σ_q²). The fit here estimates both from one frame, after
 * Foi, Trimeche, Katkovnik, Egiazarian, "Practical Poissonian-Gaussian noise modeling and fitting
 * for single-image raw-data", IEEE TIP 17(10) 2008 (local estimates of level and variance on
 * smooth parts of the image, grouped by level, a straight line fitted to them), with Liu,
 * Tanaka, Okutomi's selection of weakly textured patches by their gradients ("Single-image noise
 * level estimation for blind denoising", IEEE TIP 22(12) 2013):
 *
 * - Blocks: the 2×2 blocks of same-channel samples one mosaic period P apart, A at (x, y),
 *   B (x + P, y), C (x, y + P), D (x + P, y + P), tiling each of the P² sub-images. Read in
 *   row groups (rows 2P·k .. 2P·k + 2P − 1 hold one block row of every phase): every sx-th
 *   block along the rows (sx the smallest odd ≥ 3 leaving at most PC_DM_PTC_BLOCKS/16 a group)
 *   in every sy-th group (sy leaving at most PC_DM_PTC_BLOCKS). Whole rows are read, once:
 *   strided single samples would read a cache line each, from every part of the frame. A block
 *   with a sample at or below lo (the raw's zero: clipped) or at or above fs (saturated) is left
 *   out. Its Haar coefficients are orthonormal: the level μ = (A + B + C + D)/4, the detail
 *   d = (A − B − C + D)/2, the gradients h = (A − B + C − D)/2, v = (A + B − C − D)/2. On
 *   independent noise of variance σ² the three are independent N(0, σ²); a ramp moves h and v
 *   only, texture all three.
 * - Levels: PC_DM_PTC_BINS groups of about equal counts by μ (a histogram of √(μ/fs) in 4096
 *   cells; a cell is never split).
 * - A group's variance: s² = median(d²)/m₁ (m₁ the median of χ²₁), then up to eight times
 *   s² = mean(d²)/c over the blocks with h² + v² ≤ 9.2103·s² (χ²₂'s 99 % point: weak texture)
 *   and d² ≤ 9·s² (c = 0.97334, the variance of N(0, 1) given |x| ≤ 3), until it changes by less
 *   than 1e-3 of itself or fewer than 16 blocks remain. Texture only raises d², so the selection
 *   converges from above.
 * - The line: a, b ≥ 0 minimising Σ n_k·(a·μ_k + b − s²_k)²/(s²_k + ε)² over the groups (n_k
 *   the blocks selected, the weights those of a variance estimate; ε 1e-6 of the largest s²),
 *   the unconstrained least squares when both come out ≥ 0, else the better of a alone and b
 *   alone. When the slope is not determined (b > 0 and a not above twice its standard error,
 *   √(2·Σw/det) for these weights: the frame's levels span too little of the line to separate
 *   the two, or texture raises every group alike), a is the slope of the line through the
 *   origin fitted to the same groups: the one-parameter model σ² = a·L that ratio-nr uses
 *   (without it the fit reports little or no signal-dependent noise in a frame full of it: the
 *   stress suite's text at its low exposure, a flat field; Round 40).
 *
 * a and b in raw units (DN per DN, DN²), each 0 below 1e-12 of full scale (of its square for
 * b: the fit's rounding on a noise-free frame); 0 and 0 for a noise-free frame, a frame too
 * small for two groups of 64 blocks, or one whose blocks are all clipped. The scatter of the
 * slope is about ±10 % where the frame's levels span the line well and up to −20 % on a dark
 * frame at high gain, where the offset b dominates (test_noise_ptc); ratio-nr's results move
 * little with a factor of 2 in it (docs/demosaicking.md, Round 40). Deterministic: the same samples
 * give the same a and b whatever the thread count or instruction set. */
#define PC_DM_PTC_BLOCKS 8192
#define PC_DM_PTC_BINS   16

/* Row y of an image minus the black level, in double, into dst[0..w) */
typedef void (*pc_dm_row_fn)(const void *ctx, uint32_t y, double *dst);

/* b may be NULL (ratio-nr uses a alone) */
int pc_dm_noise_ptc(pc_dm_row_fn row, const void *ctx, uint32_t w, uint32_t h, const pc_mosaic *m,
                    double fs, double lo, double *a, double *b);

/* The same on the references' input (raw minus black in double, C order; lo = −black) */
int pc_dm_noise_ptc_d(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      double lo, double *a, double *b);

/* The same on the fast paths' prepared input (no dark or gain maps), the samples as
 * pc_dm_noise_ptc_d reads them from pc_dm_raw_to_double's image: the same a and b */
int pc_dm_noise_ptc_in(const pc_dm_input *in, const pc_mosaic *m, double fs, double *a, double *b);

#endif
