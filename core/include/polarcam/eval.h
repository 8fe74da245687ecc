/* polarcam/eval.h - the frozen demosaicking evaluation protocol (docs/evaluation.md, the one
 * the field's public evaluation code uses, Tokyo Tech / Lapray):
 *
 *  1. the four analyser images as float64, normalised to [0, 1] by the container's full scale
 *     (16-bit containers: 65535, even for 12-bit data; 8-bit: 255; float data as is);
 *  2. cropped to even height and width and mosaicked with the Sony layout [90 45; 135 0];
 *  3. demosaicked to I0, I45, I90, I135;
 *  4. S0 = (I0+I45+I90+I135)/2, S1 = I0 − I90, S2 = I45 − I135,
 *     DoLP = sqrt(S1² + S2²)/S0 clipped to [0, 1], AoLP = ½·atan2(S2, S1);
 *  5. a 15-pixel border excluded; PSNR (peak 1) of: the mean over the four I channels of their
 *     PSNRs, S0/2, (S1+1)/2, (S2+1)/2, DoLP; AoLP RMSE in degrees with the difference wrapped
 *     to [0°, 90°], and the same weighted by the ground-truth DoLP;
 *  6. per dataset, never pooled, with the time per 2448×2048 frame beside it (bench).
 * Core does no I/O: callers load the images (io) and pass views.
 */
#ifndef POLARCAM_EVAL_H
#define POLARCAM_EVAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_EVAL_BORDER 15

/* Ground truth after protocol steps 1-2. */
typedef struct pc_eval_truth {
	double *ch[4]; /* I0, I45, I90, I135 normalised to [0, 1], width × height, C order */
	uint32_t width, height;
	double full_scale; /* the container's full scale the values were divided by */
	pc_pixfmt format;  /* the container format (Mono8, Mono16 or Float32) */
} pc_eval_truth;

typedef struct pc_eval_metrics {
	double psnr_i;       /* mean of the four I channels' PSNRs (dB) */
	double psnr_i_ch[4]; /* each channel's PSNR */
	double psnr_s0;      /* of S0/2 */
	double psnr_s1;      /* of (S1+1)/2 */
	double psnr_s2;      /* of (S2+1)/2 */
	double psnr_dolp;
	double aolp_rmse_deg;  /* wrapped to [0°, 90°] */
	double aolp_wrmse_deg; /* weighted by the ground-truth DoLP */
} pc_eval_metrics;

/* Steps 1-2 from four analyser images in the order I0, I45, I90, I135 (same size; Mono8,
 * 16-bit containers or Float32, all the same container). Odd sizes lose their last row or
 * column. Errors name the image (0°, 45°, ...) and the problem. */
PC_API int pc_eval_truth_from_views(const pc_view views[4], pc_eval_truth *t);
PC_API void pc_eval_truth_free(pc_eval_truth *t);

/* The raw mosaic of the truth with layout m, in the truth's container (values × full scale,
 * exact). Owned view: free with pc_view_free. */
PC_API int pc_eval_mosaic(const pc_eval_truth *t, const pc_mosaic *m, pc_view *raw);

/* Steps 4-5: scores four demosaicked channels (in the raw's units; divided by est_scale to
 * normalise) against the truth. Images must be at least 2·PC_EVAL_BORDER + 1 in each size. */
PC_API int pc_eval_score(const pc_eval_truth *t, const pc_fplane est[4], double est_scale,
                         pc_eval_metrics *out);

/* Steps 2-5 for one method: mosaic with the Sony layout, demosaic (opts may be NULL), score.
 * Half-resolution methods are scored after replication to full size (each 2×2 block takes its
 * super-pixel's values). */
PC_API int pc_eval_method(const pc_eval_truth *t, pc_demosaic_method method,
                          const pc_demosaic_opts *opts, pc_eval_metrics *out);

/* Steps 3-5 on a given raw frame with mosaic m (a camera's or the simulator's frame of the
 * scene the truth describes, noise and all), raw and truth of one size; full scale and
 * normalisation as pc_eval_method. */
PC_API int pc_eval_method_raw(const pc_eval_truth *t, const pc_view *raw, const pc_mosaic *m,
                              pc_demosaic_method method, const pc_demosaic_opts *opts,
                              pc_eval_metrics *out);

/* Steps 3-5 on a colour-polarization raw frame (m with a colour layer, e.g.
 * pc_mosaic_imx250myr): demosaicked into the twelve (colour, analyser) planes of a colour
 * method, each colour's four scored against its truth t[k] (k = R, G, B; one size, one full
 * scale), out the mean of the three colours' metrics (zeros on an error). Full scale and
 * normalisation as pc_eval_method_raw: opts->full_scale when > 0, else the truths', for the
 * demosaicking; the truths' for the scores. */
PC_API int pc_eval_method_raw_colour(const pc_eval_truth t[3], const pc_view *raw,
                                     const pc_mosaic *m, pc_demosaic_method method,
                                     const pc_demosaic_opts *opts, pc_eval_metrics *out);

/* ---- what the truth itself holds: a pixel-level pattern its analyser images share ----
 *
 * Ground truth captured through a rotating polarizer (division of time: one sensor takes the
 * four analyser images in turn, as in the public datasets) carries the sensor's per-pixel fixed
 * pattern (PRNU, DSNU) in all four images alike, while a division-of-focal-plane camera's
 * pattern belongs to each sample alone. A demosaicker that copies a pixel's own deviation into
 * the pixel's other analyser channels is rewarded by such a truth and penalised by a noisy
 * DoFP frame scored against a noise-free truth (docs/evaluation.md, docs/demosaicking.md
 * Round 41). The measure: each image's high-pass e_c = I_c − (its 3×3 mean), over the flattest
 * 30 % of the pixels inside the border (the smallest central-difference gradients of the mean
 * image, so that the scene's edges stay out); corr the mean over the six pairs of analyser
 * images of the correlation of e at the same pixel; corr_shift the same with the second image
 * one pixel to the right (a spatially white shared pattern gives a small negative value there:
 * −corr/6 from the 3×3 mean's overlap, about −corr/5 with the selection; texture correlates at
 * both); std the RMS of e over the four images, in full-scale units. For a share ρ of shared
 * white pattern in otherwise independent white variation, corr = ρ. NaN when the images vary
 * by less than 1e-9 of full scale (RMS) there or the truth is smaller
 * than 2·PC_EVAL_BORDER + 4 in a size; errors: out of memory. */
typedef struct pc_eval_pattern {
	double corr, corr_shift, std;
	size_t pixels; /* the pixels measured */
} pc_eval_pattern;

PC_API int pc_eval_truth_pattern(const pc_eval_truth *t, pc_eval_pattern *out);

/* ---- Stokes estimates against the simulator's ground truth (polarcam demo) ----
 *
 * Unlike the frozen protocol above (analyser images normalised to [0, 1]), these score the
 * pipeline's S0, DoLP and AoLP of a raw frame in DN against the truth radiance converted to DN,
 * over the pixels that are neither dark nor saturated. */

typedef struct pc_eval_stokes_metrics {
	double s0_rel_rms;   /* RMS of (S0 − T0)/T0 */
	double dolp_bias;    /* mean of DoLP − truth DoLP */
	double dolp_rms;     /* RMS of DoLP − truth DoLP */
	double aolp_err_deg; /* mean AoLP difference (wrapped to [0°, 90°]) weighted by the truth
	                        DoLP, over pixels with truth DoLP > 0.05 */
	double aolp_median_deg; /* its median over the same pixels (unweighted) */
	long pixels;            /* pixels scored */
	long aolp_pixels;       /* of them with truth DoLP > 0.05 */
} pc_eval_stokes_metrics;

/* S0 (times scale), DoLP and AoLP planes of n truth Stokes vectors (n × 4 floats: S0..S3), in
 * double through pc_stokes_dolp (then clipped to 1) and pc_stokes_aolp_rad (polarcam/optics.h). */
PC_API void pc_eval_truth_planes(const float *truth_stokes, size_t n, double scale, float *s0,
                                 float *dolp, float *aolp);

/* Scores estimate planes (W × H, contiguous) against truth planes in the same units. Scored
 * pixels: truth S0 above 2 % of full_scale, brightest analyser (S0·(1 + DoLP)/2) below 95 % of
 * it. NaN metrics when no pixel qualifies. */
PC_API int pc_eval_stokes(const float *s0, const float *dolp, const float *aolp, const float *t_s0,
                          const float *t_dolp, const float *t_aolp, uint32_t width, uint32_t height,
                          double full_scale, pc_eval_stokes_metrics *out);

/* Median |est − truth| over the n pixels whose weight exceeds wmin and whose values are finite
 * (angle_pi: differences of angles in [0, π], folded to [0, π/2]); *used (may be NULL) counts
 * them. NaN when none. */
PC_API double pc_eval_median_abs_err(const float *est, const float *truth, const float *weight,
                                     size_t n, double wmin, bool angle_pi, long *used);

#ifdef __cplusplus
}
#endif
#endif
