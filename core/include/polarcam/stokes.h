/* polarcam/stokes.h - linear Stokes images, DoLP and AoLP from analyser images or raw mosaics.
 *
 * Formulas (ideal analysers at 0°, 45°, 90°, 135°; the frozen evaluation protocol,
 * docs/evaluation.md, step 4):
 *   S0 = (I0 + I45 + I90 + I135) / 2,  S1 = I0 − I90,  S2 = I45 − I135,
 *   DoLP = sqrt(S1² + S2²) / S0, clipped to [0, 1] (0 where S0 <= 0),
 *   AoLP = ½·atan2(S2, S1) in radians, mapped to [0, π).
 * AoLP convention: measured from the image x axis (pixel columns, left to right),
 * counter-clockwise as seen by the viewer looking at the image (towards the top of the image,
 * since image rows run downwards), in [0, π): 0 is horizontal polarization, π/2 vertical, π/4
 * the direction from the bottom-left to the top-right corner. The analyser angles of
 * polarcam/mosaic.h use the same convention. Vendor SDKs differ (some use [−π/2, π/2) or a
 * clockwise angle); convert with aolp' = π − aolp for a clockwise convention.
 *
 * Calibrated cameras: each analyser c responds I_c = W_c · (S0, S1, S2) with a 4×3 analyser
 * matrix W (ideal: W_c = ½·(1, cos 2θ_c, sin 2θ_c)). Least squares gives S = W⁺·I with the
 * 3×4 pseudo-inverse W⁺ = (WᵀW)⁻¹Wᵀ, computed once per calibration (pc_stokes_pinv) and
 * applied per pixel: by the front door (pc_stokes_run with pc_pipeline_opts.pinv, in every
 * path, the fused fast ones included), or to analyser images (pc_stokes_from_channels).
 * S_i = (W⁺_i0·I0 + W⁺_i1·I1) + (W⁺_i2·I2 + W⁺_i3·I3): the ideal W⁺ gives the formulas above.
 */
#ifndef POLARCAM_STOKES_H
#define POLARCAM_STOKES_H

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

/* Outputs; a NULL data pointer means "not wanted". Strides in floats (see pc_fplane). */
typedef struct pc_stokes_out {
	pc_fplane s0, s1, s2, dolp, aolp;
} pc_stokes_out;

/* Per-pixel (or per-region) analyser pseudo-inverses: a grid_w × grid_h grid of 3×4 matrices,
 * stored as twelve planes, C order (3, 4, grid_h, grid_w): element (i, c) of cell (gx, gy) -
 * Stokes component i, analyser c - is m[((4·i + c)·grid_h + gy)·grid_w + gx]. Output pixel
 * (x, y) of a W × H image uses cell (x·grid_w / W, y·grid_h / H) (integer division). A 1×1
 * grid is one matrix for the whole image, a W × H grid one per pixel, a W/2 × H/2 grid one per
 * 2×2 super-pixel; these three run in the vectorised kernels, other grids in a scalar one.
 * The elements must be finite (pc_stokes_pinv makes them; the kernels do not check). */
typedef struct pc_analyser_pinv {
	const float *m;
	uint32_t grid_w, grid_h;
} pc_analyser_pinv;

/* A camera calibration in compact form for the fused bilinear pipeline. The model of
 * polarcam/calib.h: after dark and gain the sample reads a·(S0, S1, S2) with its analysis
 * vector a = (a0, a1, a2); here each sample's equation is divided by its a0 (a0 > 0, the
 * analyser's transmission for unpolarized light), so that per raw sample the compact form
 * holds its normalised vector (1, v1, v2) = a/a0 and optionally its dark offset and its
 * inverse gain with 1/a0 folded in, 16 bits each. Each map is a fixed-point offset from a base:
 * width × height int16 (the raw's size), row y at map + y·stride (one stride for all, in
 * elements: planes, or the maps' rows interleaved so that the pipeline reads them as one
 * stream). For the sample at (x, y), whose analyser is channel c = mosaic.channel[y & 1][x & 1]
 * of the pipeline's mosaic, i = y·stride + x:
 *   v_k      = v_base[c][k] + v_scale[k]·v_q[k][i]       (k = 0, 1: a1/a0, a2/a0)
 *   dark     = dark_base + dark_scale·dark_q[i]          (dark_q NULL: dark_base alone)
 *   gain_inv = gain_base + gain_scale·gain_q[i]          (gain_q NULL: none, and then
 *                                                          gain_base, gain_scale must be 0:
 *                                                          PC_EINVAL; 1/(gain·a0))
 * in float (one fused multiply-add each). With pc_pipeline_opts.compact, pc_stokes_run
 * corrects every sample I = (raw − dark)·gain_inv as it reads the raw (with dark_q and gain_q
 * NULL and dark_base 0: opts' black level, dark and gain_inv maps as usual; else they must be
 * 0 and NULL), and solves per output pixel the least squares over its 3×3 samples weighted by
 * the bilinear interpolation's weights K (own sample 1, edge neighbours ½, corners ¼; mirrored
 * borders): S = M⁻¹b, M = Σ K_s u_s u_sᵀ, b = Σ K_s u_s I_s with u = (1, v1, v2), in float,
 * in the one pass that reads the raw: 6 to 8 bytes of calibration per pixel instead of the 56
 * of float maps and a per-pixel pc_analyser_pinv, and nothing per output pixel to prepare. M
 * and b are separable [1 2 1] sums of per-sample products; the symmetric M is inverted by its
 * cofactors (Cramer's rule), as in the double reference of tests/test_calib_fused.c
 * (tolerance there). Exact on uniform fields; with ideal analysers (v_q NULL, v_base the
 * ideal (cos 2θ_c, sin 2θ_c), gain_inv 2 = 1/a0: a gain map of zeros, gain_base 2, gain_scale
 * 0) and no dark map it is the uncalibrated estimator (results within 1e-6 relative; measured
 * bit for bit). The other calibrated paths
 * (pc_analyser_pinv) interpolate the analysis vectors per channel and solve S = (WᵀW)⁻¹WᵀI: the
 * same on uniform fields, slightly different on texture (docs/calibration.md). Bilinear,
 * monochrome mosaics, the fast path only (PC_ENOTSUP otherwise). The caller guarantees that M
 * is well conditioned at every output pixel (pc_calib checks it once per calibration; the
 * kernel does not). The samples to distrust (flagged in the validity as saturated ones are)
 * may come as a list instead of pc_pipeline_opts.trusted, so that a frame reads no trust map:
 * row y's distrusted samples are at columns distrust_x[distrust_row[y] .. distrust_row[y + 1])
 * (height + 1 offsets; NULL: none listed). */
typedef struct pc_compact_calib {
	uint32_t width, height;
	size_t stride;         /* elements between rows, every map */
	const int16_t *v_q[2]; /* NULL: v_base alone */
	float v_base[4][2], v_scale[2];
	const int16_t *dark_q, *gain_q;
	float dark_base, dark_scale, gain_base, gain_scale;
	const uint32_t *distrust_row, *distrust_x;
} pc_compact_calib;

/* The ideal analyser matrix: W[c] = ½·(1, cos 2θ_c, sin 2θ_c), θ_c = 45°·c. */
PC_API void pc_stokes_ideal_analyser(double w[4][3]);

/* The smallest reciprocal condition number the Stokes solves accept (pc_mat3_inverse). */
#define PC_RCOND_MIN 1e-10

/* Inverse of a 3×3 matrix by its cofactors over the determinant (Cramer's rule; the normal
 * equations of every Stokes solve here), guarded by the reciprocal 1-norm condition number
 * |det A| / (‖A‖₁·‖adj A‖₁) (= 1 / (‖A‖₁·‖A⁻¹‖₁)): returns that number, 0 when A is singular
 * or not finite; inv = A⁻¹ when it returns at least PC_RCOND_MIN (inv may be NULL: the check
 * alone). */
PC_API double pc_mat3_inverse(const double a[3][3], double inv[3][3]);

/* 3×4 pseudo-inverse (WᵀW)⁻¹Wᵀ of a 4×3 analyser matrix, in double. PC_ENUMERIC when W is
 * rank-deficient (reciprocal condition number of WᵀW below PC_RCOND_MIN, pc_mat3_inverse). */
PC_API int pc_stokes_pinv1(const double w[4][3], double pinv[3][4]);

/* Pseudo-inverses of n analyser matrices (n × 4 × 3 floats, C order) into the twelve planes of
 * a pc_analyser_pinv of n cells (12 × n floats: element (i, c) of matrix k at pinv[(4i + c)·n +
 * k]). Fails with PC_ENUMERIC naming the first singular matrix. */
PC_API int pc_stokes_pinv(const float *w, size_t n, float *pinv);

/* Stokes, DoLP and AoLP of width × height pixels from four analyser images (I0, I45, I90,
 * I135). pinv NULL: the ideal formulas above; otherwise the least-squares pseudo-inverses. */
PC_API int pc_stokes_from_channels(const pc_fplane in[4], uint32_t width, uint32_t height,
                                   const pc_analyser_pinv *pinv, const pc_stokes_out *out);

/* The front door of the pipeline: demosaic raw (black level subtracted), then Stokes/DoLP/AoLP
 * through ideal analysers or, with opts->pinv, calibrated ones - without full-size
 * intermediate images where the method allows (bilinear is fused into one pass, the row-cache
 * methods hand rows from cache; planar outputs), and the validity of every output pixel
 * (polarcam/demosaic.h; valid may be NULL). Colour-polarization mosaics use the colour average
 * (R + G + B)/3 of each analyser image. Output size is pc_demosaic_out_size(method, ...);
 * opts->reference runs the double-precision demosaicking reference, then the Stokes kernels of
 * pc_stokes_from_channels. Errors as pc_demosaic_run (opts->pinv allowed), plus missing outputs
 * and a pinv grid that is empty or larger than the output. */
PC_API int pc_stokes_run(const pc_view *raw, const pc_pipeline_opts *opts, const pc_stokes_out *out,
                         pc_validity *valid);

/* pc_stokes_run of a colour-polarization raw (opts->mosaic of period 4, ideal analysers: no
 * pinv, no compact calibration) that also gives each colour's Stokes: rgb[c], c = 0, 1, 2 for
 * R, G, B (any plane may be NULL), from that colour's four analyser images of the same
 * demosaicking (the twelve images are made once). out is their mean over the colours, exactly
 * what pc_stokes_run gives (it averages the analyser images, and S is linear in them). */
PC_API int pc_stokes_run_colour(const pc_view *raw, const pc_pipeline_opts *opts,
                                const pc_stokes_out *out, const pc_stokes_out rgb[3],
                                pc_validity *valid);

/* pc_stokes_run with method, mosaic m, and opts' threads, reference and full scale (opts may
 * be NULL): ideal analysers, no black level, no validity. */
PC_API int pc_stokes_from_raw(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
                              const pc_demosaic_opts *opts, const pc_stokes_out *out);

/* Whether pc_stokes_run with PC_DM_BILINEAR (or a row-cache method) writes these width ×
 * height outputs with non-temporal (cache-bypassing) stores on this machine: AVX2, planar
 * 64-byte aligned outputs with 64-byte aligned rows, at least 32 MB of them, and not on AMD
 * processors without AVX-512 (Zen 3 and earlier), where ordinary stores measured faster
 * (docs/demosaicking.md);
 * POLARCAM_NT_MIN_BYTES overrides the size threshold. For benchmarks that compare the
 * pipeline with a memory floor written the same way. */
PC_API bool pc_stokes_streams(const pc_stokes_out *out, uint32_t width, uint32_t height);

/* AoLP = ½·atan2(s2, s1) mapped to [0, π), the float kernel used by the fast paths
 * (maximum error 3e-7 rad against double, tested). */
PC_API float pc_aolp_f(float s1, float s2);

/* ---- Imin, Imax and the diffuse/specular split (the outputs polanalyser users know) ----
 *
 * With S0 the total intensity (S0 = I0 + I90 = Imax + Imin, as above and docs/physics.md §2),
 * an ideal linear analyser turned through θ sees I(θ) = ½·(S0 + S1·cos 2θ + S2·sin 2θ), whose
 * extremes are (docs/physics-notes.md, "Imin, Imax and the diffuse/specular split"):
 *   Imin = ½·(S0 − √(S1² + S2²)),  Imax = ½·(S0 + √(S1² + S2²)),
 * and, for unpolarized diffuse light under fully polarized specular light (Wolff & Boult 1991,
 * "Constraining object features using a polarization reflectance model", IEEE PAMI 13(7)):
 *   diffuse = 2·Imin,  specular = Imax − Imin = √(S1² + S2²),  diffuse + specular = S0.
 * polanalyser's cvtStokesToImin/Imax give the same Imin and Imax; its cvtStokesToSpecular the
 * same specular; its cvtStokesToDiffuse returns Imin (half of this diffuse) in recent versions
 * and 2·Imin in early ones. Nothing is clipped: where noise makes √(S1² + S2²) > S0 (an
 * estimated DoLP above 1, dark pixels), Imin and diffuse are negative; NaN stays NaN. */
typedef struct pc_minmax_out {
	pc_fplane imin, imax, diffuse, specular; /* a NULL data pointer: not wanted */
} pc_minmax_out;

/* The double-precision reference of one pixel: out = {Imin, Imax, diffuse, specular}. */
PC_API void pc_stokes_minmax1(double s0, double s1, double s2, double out[4]);

/* The float kernel over width × height pixels of S0, S1, S2 planes (strides in floats). Each
 * output is within 2⁻²² · (|S0| + √(S1² + S2²)) of pc_stokes_minmax1 (tested). PC_EINVAL for a
 * missing input, no output asked for or strides too small. */
PC_API int pc_stokes_minmax(const pc_fplane *s0, const pc_fplane *s1, const pc_fplane *s2,
                            uint32_t width, uint32_t height, const pc_minmax_out *out);

#ifdef __cplusplus
}
#endif
#endif
