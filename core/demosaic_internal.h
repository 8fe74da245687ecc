/* Internal to core/demosaic*.c and core/stokes.c: shared helpers of the demosaicking ladder.
 * Not a public header. */
#ifndef POLARCAM_DEMOSAIC_INTERNAL_H
#define POLARCAM_DEMOSAIC_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

/* Loop vectorisation that does not depend on the -O level: OpenMP simd (ignored without OpenMP). */
#ifdef _OPENMP
#define PC_SIMD _Pragma("omp simd")
#else
#define PC_SIMD
#endif

/* Whole-sample mirror (reflect-101) of index i into [0, n): -1 -> 1, n -> n-2, periodic with
 * period 2n-2 for far-out indices. Keeps the parity of i (n >= 2), hence the 2×2 analyser. */
static inline int pc_mirror(int i, int n)
{
	if (i >= 0 && i < n)
		return i;
	if (n == 1)
		return 0;
	int p = 2 * n - 2;
	i %= p;
	if (i < 0)
		i += p;
	return i < n ? i : p - i;
}

/* The input of a fast kernel: a plane of 8-bit, 16-bit or float samples. */
typedef enum pc_dm_type { PC_DMT_U8, PC_DMT_U16, PC_DMT_F32 } pc_dm_type;

typedef struct pc_dm_input {
	const uint8_t *data;
	size_t stride; /* bytes */
	pc_dm_type type;
	uint32_t width, height;
} pc_dm_input;

/* Prepares a raw view for the fast kernels (demosaic.c): integer and float planes are used in
 * place (float checked for NaN/inf); packed formats are unpacked into *owned (free with
 * pc_dm_free). */
int pc_dm_prepare_input(const pc_view *raw, pc_dm_input *in, void **owned);

/* The raw's full scale: opts->full_scale when set, else 2^bits − 1 (1.0 for float raws). */
double pc_dm_full_scale(const pc_view *raw, const pc_demosaic_opts *opts);

/* Converts row y of the input to floats at dst[0..w) and mirrors one pixel on each side:
 * dst[-1] = row[1], dst[w] = row[w-2] (dst must have room for both). */
void pc_dm_row_to_float(const pc_dm_input *in, uint32_t y, float *dst);

/* The double-precision reference (the specification): img is the raw in double, C order,
 * width × height; full_scale as in pc_demosaic_opts (resolved, > 0). */
int pc_demosaic_ref(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
		    pc_demosaic_method method, double full_scale, const pc_fplane *out);

/* The anchors' references in their own files (demosaic_mlri.c: PC_DM_EARI_MLRI). */
int pc_demosaic_ref_mlri(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
			 pc_demosaic_method method, double full_scale, const pc_fplane *out);

/* MLRI residual interpolation of every channel of img with the given guide (demosaic_mlri.c;
 * -1 without memory), and the IGRI2 reference (demosaic_igri.c). */
int pc_dm_mlri_ri(const double *img, const double *guide, uint32_t width, uint32_t height,
		  const pc_mosaic *m, double full_scale, const pc_fplane *out);
int pc_demosaic_ref_igri2(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
			  double full_scale, const pc_fplane *out);
int pc_demosaic_ref_pcdp(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
			 const pc_fplane *out);
int pc_demosaic_fast_pcdp(const pc_dm_input *in, const pc_mosaic *m, int threads,
			  const pc_fplane *out);

/* The anchors' fast float paths (demosaic_mlri_fast.c); PC_ENOTSUP for tiny frames. */
int pc_demosaic_fast_mlri(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
			  double full_scale, int threads, const pc_fplane *out);

/* The fast float paths. Return PC_ENOTSUP when the method has none (the caller falls back to
 * the float-converted reference). */
int pc_demosaic_fast(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
		     double full_scale, int threads, const pc_fplane *out);

/* Fused bilinear + Stokes/DoLP/AoLP (monochrome mosaics), in demosaic_fast.c. */
struct pc_stokes_out;
int pc_stokes_bilinear_fused(const pc_dm_input *in, const pc_mosaic *m, int threads,
			     const struct pc_stokes_out *out);

/* Stokes from four planar analyser images (ideal analysers), vectorised; PC_ENOTSUP when an
 * input or output is not planar (pixel_stride != 1). In demosaic_fast.c. */
int pc_stokes_planar_fast(const pc_fplane in[4], uint32_t width, uint32_t height,
			  const struct pc_stokes_out *out);

/* Analyser channel at row parity py (0/1) and column parity px of a monochrome mosaic. */
static inline unsigned pc_dm_ch(const pc_mosaic *m, unsigned px, unsigned py)
{
	return m->channel[py & 1][px & 1];
}

/* Residual interpolation parameters: the guided filter's window radius in pixels, the square
 * root of its regulariser as a fraction of full scale, the number of passes (each pass after
 * the first uses the mean of the previous pass's four channels as its guide), and for EARI the
 * guide's edge-weight offset as a fraction of full scale. Chosen on the Lapray NIR and Zhang
 * scenes together (docs/demosaicking.md has the sweep). */
typedef struct pc_ri_params {
	int radius;
	double eps;
	int passes;
	double guide_eps;
} pc_ri_params;

static const pc_ri_params pc_ri_params_default = { 2, 0.01, 1, 0 };
static const pc_ri_params pc_eari_params = { 2, 0.003, 1, 0.1 };

/* Passes of the ratio method (PC_DM_RATIO): the second uses the first's mean as its guide
 * (Lapray NIR: +0.25 dB S0; Zhang: +1.0 dB S0, +0.8 dB DoLP over a single pass). */
#define PC_RATIO_PASSES 2

/* The ratio method's offset as a fraction of full scale: ratios (raw + δ)/(guide + δ), so that
 * in the dark, where the guide is of the order of the noise, the method turns into difference
 * (residual) interpolation instead of dividing small numbers (docs/demosaicking.md, the sweep:
 * 1/65536 of full scale lost 0.3 dB S0 against bilinear on the darkest noisy stress scene,
 * 1 % gains 0.7 dB there and costs at most 0.05 dB on the public scenes). */
#define PC_RATIO_OFFSET 0.01

/* Non-temporal output (demosaic_fast.c): whether n planes of w × h floats are worth streaming
 * (aligned, planar, large, AVX2 present), and the copy of finished rows into them. */
int pc_dm_stream_wanted(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h);
int pc_dm_stream_rows(float *const dst[], const float *const src[], unsigned n, uint32_t w);

/* The row-cache methods' fused pipeline (demosaic_ic.c): demosaic in row bands and turn each
 * finished row into Stokes/DoLP/AoLP (pc_dm_stokes_row, demosaic_fast.c) without full-size
 * channel images. Outputs must be planar (pixel_stride 1); PC_ENOTSUP for methods or mosaics
 * without a row-cache path. */
int pc_stokes_ic_fused(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
		       double full_scale, int threads, const struct pc_stokes_out *out);
void pc_dm_stokes_row(const float *const ch[4], uint32_t w, uint32_t y,
		      const struct pc_stokes_out *out, int nt);
int pc_dm_stokes_stream_wanted(const struct pc_stokes_out *out, uint32_t w, uint32_t h);

/* The overshoot limiter (demosaic_robust.c): every interpolated sample of channel c clamped to
 * the range of channel c's raw samples in the 5×5 window around it; own samples untouched.
 * pc_dm_limited: the methods it belongs to. pc_dm_range_limit: monochrome mosaics, out the
 * full-resolution planes of the raw's size (one pixel stride for all four). Row by row: a
 * pc_dm_limiter per thread (init: 0 or -1 without memory), then for rows in increasing order
 * pc_dm_limit_row with r[k] the raw's row y−2+k as floats padded by two mirrored samples on
 * each side (the row ranges are cached by row index), o[c] channel c's row. */
typedef struct pc_dm_limiter {
	long w;
	long key[5];
	float *mem;
} pc_dm_limiter;
int pc_dm_limited(pc_demosaic_method method);
int pc_dm_range_limit(const pc_view *raw, const pc_mosaic *m, int threads, const pc_fplane *out);
int pc_dm_limiter_init(pc_dm_limiter *l, long w);
void pc_dm_limiter_free(pc_dm_limiter *l);
void pc_dm_limit_row(pc_dm_limiter *l, const pc_mosaic *m, const float *const r[5], uint32_t y,
		     float *const o[4], size_t pixel_stride);

/* Scratch memory helpers (64-byte aligned; NULL on failure). */
void *pc_dm_alloc(size_t bytes);
void pc_dm_free(void *p);

#endif
