/* Internal to core: the robust rungs and the field's anchors of the demosaicking ladder - the
 * overshoot limiter (demosaic_robust.c), eari-mlri / eari-robust (references in
 * demosaic_mlri.c, fast path in demosaic_mlri_fast.c), PCDP (demosaic_pcdp.c), IGRI2
 * (demosaic_igri.c) and Newton (demosaic_newton.c). Their rows in the method table are in
 * demosaic_plan.c. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_ANCHORS_H
#define POLARCAM_DEMOSAIC_ANCHORS_H

#include "demosaic_common.h"

/* The ratio method's offset as a fraction of full scale: ratios (raw + δ)/(guide + δ), so that
 * in the dark, where the guide is of the order of the noise, the method turns into difference
 * (residual) interpolation instead of dividing small numbers (docs/demosaicking.md, the sweep:
 * 1/65536 of full scale lost 0.3 dB S0 against bilinear on the darkest noisy stress scene,
 * 1 % gains 0.7 dB there and costs at most 0.05 dB on the public scenes). */
#define PC_RATIO_OFFSET 0.01

/* The ratio method's guided tent (demosaic_ref.c, guided_tent): the offset e of its weights
 * 1/(e + |Δguide|) as a fraction of full scale. Sweep on the stress suite / Lapray / Zhang
 * (mean S0 gain over bilinear, dB; the plain tent: +2.21 / +3.19 / +4.42): 0.003: +4.06 /
 * +3.22 / +4.55; 0.01: +3.92 / +3.29 / +4.58; 0.03: +3.68 / +3.30 / +4.56; 0.1: +3.26 /
 * +3.28 / +4.51 (docs/demosaicking.md). */
#define PC_RATIO_GUIDE_EPS 0.01

/* ratio-ri (demosaic_ref.c, ref_ratio_ri): the guided filter's regulariser (PC_RATIO_RI_EPS·FS)²
 * on the ratio method's mean as guide, and the dark level d = PC_RATIO_RI_DARK·FS of the blend
 * weight G²/(G² + d²) between the filter's and the ratio method's estimates. Sweep, double
 * references (mean S0 / DoLP gain over bilinear on stress / Lapray / Zhang, dB; the worst
 * scene's DoLP): regulariser 0.001: +4.33/+1.48, +3.28/+1.88, +4.86/+4.35 (gloss -0.36);
 * 0.003: +4.46/+1.43, +3.48/+1.97, +4.55/+4.21 (gloss -0.36); 0.01: +4.37/+1.34,
 * +3.60/+1.92, +3.74/+3.72 (gloss -0.34), all without the blend; with d = 0.003 / 0.01 /
 * 0.03 at 0.003 the worst DoLP (gloss) is +0.21 / +0.26 / +0.35 and Lapray's S0 +3.48 /
 * +3.48 / +3.48; 0.005 with d = 0.01: +4.51/+1.82, +3.58/+1.98, +4.25/+4.06 (gloss +0.26).
 * Radius 1 lost on all three (+2.76, +2.85, +2.77 S0), radius 3 lost on Lapray (+3.38) and
 * a second filter pass gained nothing (+3.51 Lapray at 0.003, Zhang -0.1). */
#define PC_RATIO_RI_EPS 0.005
/* ratio-nr (demosaic_ref.c, shrunk_guide): the shot-noise coefficient k of the guide's
 * variance model k·G. Since Round 40 (docs/demosaicking.md) k is the frame's noise gain: given
 * (pc_pipeline_opts.noise_gain), or the slope of the photon-transfer line fitted to the frame
 * (demosaic_noise.h, pc_dm_noise_ptc). Before, it was the constant 5e-5 of full scale, the
 * Poisson variance of a sensor with a full well of 20 000 e⁻ at any gain (the IMX250MZR's is
 * ~10 500 e⁻ at unity gain: 1e-4); at +24 dB it took the noise for 1/30 of what it was (the chart
 * at its low exposure −2.03 dB S0 against bilinear, now −0.14). That constant's sweep, double
 * references (mean
 * S0 / DoLP gain over bilinear on stress / Lapray / Zhang, dB; ratio: +3.92/+1.69,
 * +3.29/+1.80, +4.58/+4.21): final pass only, 1e-4: +4.10/+1.63, +3.51/+1.92, +3.68/+4.08;
 * 5e-5: +4.08/+1.65, +3.52/+1.91, +3.91/+4.12; both passes, 1e-4: +4.15/+1.55, +3.52/+1.96,
 * +3.43/+3.91; 5e-5: +4.13/+1.58, +3.56/+1.95, +3.66/+3.98 (chosen: the better Lapray mean and
 * worst scene); a constant regulariser (v/(v + (0.003·FS)²), final pass) +4.07/+1.48,
 * +3.48/+1.92, +4.16/+4.15 with gloss DoLP +0.06. */
#define PC_RATIO_RI_DARK 0.01

/* ---- the overshoot limiter (demosaic_robust.c) ----
 * Every interpolated sample of channel c clamped to the range of channel c's raw samples in
 * the 5×5 window around it; own samples untouched. pc_dm_limited: the methods it belongs to.
 * pc_dm_range_limit: monochrome mosaics, out the full-resolution planes of the input's size
 * (one pixel stride for all four). Row by row: a pc_dm_limiter per thread (init: 0 or -1
 * without memory), then for rows in increasing order pc_dm_limit_row with r[k] the raw's row
 * y−2+k as floats padded by two mirrored samples on each side (the row ranges are cached by
 * row index), o[c] channel c's row. */
typedef struct pc_dm_limiter {
	long w;
	long key[5];
	float *mem;
	pc_cpu_level level;
} pc_dm_limiter;
int pc_dm_limited(pc_demosaic_method method);
int pc_dm_range_limit(const pc_dm_input *in, const pc_mosaic *m, int threads, pc_cpu_level level,
                      const pc_fplane *out);
int pc_dm_limiter_init(pc_dm_limiter *l, long w, pc_cpu_level level);
void pc_dm_limiter_free(pc_dm_limiter *l);
void pc_dm_limit_row(pc_dm_limiter *l, const pc_mosaic *m, const float *const r[5], uint32_t y,
                     float *const o[4], size_t pixel_stride);
/* The ranges of rows y−2..y+2 (r as for pc_dm_limit_row, from the same ring) into rr, for a
 * kernel that clamps as it writes (ratio and ratio-nr: demosaic_ic_kern.inc) instead of
 * calling pc_dm_limit_row: row k's four ranges of column x at PC_DM_LIM_AT(x) + 16·j of
 * rr[k], j = 0..3 for An, Ax (over columns x ± 1), Bn, Bx (over x − 2, x, x + 2), in blocks
 * of 16 columns. The channel measured in the row of y's parity at the other column parity
 * lies in [min_k∈{0,2,4} An, max Ax]; those of the other parity in [min_k∈{1,3} Bn, max Bx]
 * at their own columns and [min_k∈{1,3} An, max Ax] at the others. */
#define PC_DM_LIM_AT(x) (4 * ((x) & ~15L) + ((x)&15L))
/* One column's vertical ranges from the five rows' interleaved ranges (m[k] + i, i the column's
 * PC_DM_LIM_AT index): over rows 0, 2, 4 (the output row's parity) the A and B ranges (s_*),
 * over rows 1, 3 the A and B ranges (o_*). The one definition of the order of the min and max
 * that combine, combine_clamp and ratio_out_blk share (bit-identical results). */
typedef struct pc_dm_vranges {
	float s_an, s_ax, s_bn, s_bx, o_an, o_ax, o_bn, o_bx;
} pc_dm_vranges;
static inline pc_dm_vranges pc_dm_lim_vranges(const float *m0, const float *m1, const float *m2,
                                              const float *m3, const float *m4, long i)
{
	pc_dm_vranges v;
	v.s_an = pc_dm_mn(pc_dm_mn(m0[i], m2[i]), m4[i]);
	v.s_ax = pc_dm_mx(pc_dm_mx(m0[16 + i], m2[16 + i]), m4[16 + i]);
	v.s_bn = pc_dm_mn(pc_dm_mn(m0[32 + i], m2[32 + i]), m4[32 + i]);
	v.s_bx = pc_dm_mx(pc_dm_mx(m0[48 + i], m2[48 + i]), m4[48 + i]);
	v.o_an = pc_dm_mn(m1[i], m3[i]);
	v.o_ax = pc_dm_mx(m1[16 + i], m3[16 + i]);
	v.o_bn = pc_dm_mn(m1[32 + i], m3[32 + i]);
	v.o_bx = pc_dm_mx(m1[48 + i], m3[48 + i]);
	return v;
}
void pc_dm_limit_ranges(pc_dm_limiter *l, const float *const r[5], uint32_t y, const float *rr[5]);
/* The limiter on a reference's output: img the raw minus black in double (rounded to float,
 * as the fast paths see it). */
int pc_dm_range_limit_ref(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                          const pc_fplane *out);

/* ---- the anchors' double references ----
 * img, width, height, m, full_scale as pc_dm_ref (demosaic_ref.h). */
int pc_dm_ref_mlri(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                   pc_demosaic_method method, double full_scale, const pc_fplane *out);
/* MLRI residual interpolation of every channel of img with the given guide (-1 without
 * memory). */
int pc_dm_mlri_ri(const double *img, const double *guide, uint32_t width, uint32_t height,
                  const pc_mosaic *m, double full_scale, const pc_fplane *out);
int pc_dm_ref_igri2(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                    double full_scale, const pc_fplane *out);
/* Li et al., Opt. Express 27(2) 2019 (demosaic_newton.c) */
int pc_dm_ref_newton(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                     double full_scale, const pc_fplane *out);
int pc_dm_ref_pcdp(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                   const pc_fplane *out);

/* ---- the fast float paths (method-table kernels; tiny frames fall back to the reference,
 * converted to float) ---- */
int pc_dm_mlri_fast(const pc_dm_call *call, const pc_fplane *out);
int pc_dm_pcdp_fast(const pc_dm_call *call, const pc_fplane *out);
int pc_dm_newton_fast(const pc_dm_call *call, const pc_fplane *out);

/* The reference of call's method on its input, into float planes (the fast paths' fallback
 * for frames too small for their padding). */
int pc_dm_ref_of_call(const pc_dm_call *call, const pc_fplane *out);

#endif
