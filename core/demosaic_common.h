/* Internal to core's demosaic → Stokes pipeline: the helpers every kernel shares (the lowest
 * tier; it calls no kernel). Input preparation (a raw view as 8-bit, 16-bit or float rows, the
 * black level recorded), row conversion to padded float rows, scratch allocation, the 3-row
 * ring of the one-pass kernels, streaming (non-temporal) stores, the mirror rule and the
 * methods' parameters. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_COMMON_H
#define POLARCAM_DEMOSAIC_COMMON_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include "polarcam/cpu.h"
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

/* A double-precision image (the references' intermediate planes): w × h samples in C order,
 * read with the whole-sample mirror by pc_dimg_at. */
typedef struct pc_dimg {
	double *p;
	int w, h;
} pc_dimg;

/* The sub-image mirror: x of the raw extended beyond [0, n) (n even) keeping x mod 4 (the colour
 * mosaic's 4×4 period): the 2×2 blocks mirrored whole (pc_mirror on block indices). */
static inline int pc_mirror4(int x, int n)
{
	int px = x & 1;
	return px + 2 * pc_mirror((x - px) / 2, n / 2);
}

/* Sample (x, y) of r, both indices mirrored (pc_mirror) into the image. */
static inline double pc_dimg_at(const pc_dimg *r, int x, int y)
{
	return r->p[(size_t)pc_mirror(y, r->h) * r->w + pc_mirror(x, r->w)];
}

/* Analyser channel at row parity py (0/1) and column parity px of a monochrome mosaic. */
static inline unsigned pc_dm_ch(const pc_mosaic *m, unsigned px, unsigned py)
{
	return m->channel[py & 1][px & 1];
}

/* Normalised tent (bilinear) interpolation of the samples of channel c of v at (x, y): the
 * weights (2-|dx|)(2-|dy|) over the channel's pixels in the 3×3 window, divided by their sum
 * (4 at the pixel itself; 2+2 for a horizontal or vertical pair; 1+1+1+1 for diagonals). The
 * double references' bilinear step (demosaic_ref.c, demosaic_mlri.c). Negative x, y keep
 * their parity through the unsigned conversion (two's complement). */
static inline double pc_dm_tent(const pc_dimg *v, const pc_mosaic *m, unsigned c, int x, int y)
{
	double s = 0, ws = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++)
			if (pc_dm_ch(m, x + dx, y + dy) == c) {
				double w = (2 - abs(dx)) * (2 - abs(dy));
				s += w * pc_dimg_at(v, x + dx, y + dy);
				ws += w;
			}
	return s / ws;
}

/* ---- the prepared input ---- */

/* The raw as a kernel reads it: a plane of 8-bit, 16-bit or float samples (raw units) and the
 * black level that row conversion subtracts. */
typedef enum pc_dm_type { PC_DMT_U8, PC_DMT_U16, PC_DMT_F32 } pc_dm_type;

/* A sample's bytes in a row of type t */
static inline size_t pc_dm_type_bytes(pc_dm_type t)
{
	return t == PC_DMT_U8 ? 1 : t == PC_DMT_U16 ? 2 : 4;
}

typedef struct pc_dm_input {
	const uint8_t *data;
	size_t stride; /* bytes */
	pc_dm_type type;
	uint32_t width, height;
	float black;    /* subtracted from every sample by the float row conversions */
	double black_d; /* the same, subtracted in double by pc_dm_input_to_double */
	/* per-pixel correction of pc_dm_row_to_float only (pc_pipeline_opts.dark, gain_inv):
	 * (sample − dark[x])·gain_inv[x] on row y of width-stride maps; NULL: none */
	const float *dark, *gain_inv;
	/* with dark and dark_scale ≠ 0, 1: dark[x] taken as dark_offset + dark_scale·dark[x]
	 * (pc_pipeline_opts.dark_scale, dark_pivot: dark_offset = pivot·(1 − scale)) */
	float dark_scale, dark_offset;
} pc_dm_input;

/* in's per-pixel correction from opts (dark, gain_inv, and the dark map's scale about its pivot:
 * dark_offset = dark_pivot·(1 − dark_scale)) */
void pc_dm_input_dark(pc_dm_input *in, const pc_pipeline_opts *opts);

/* Prepares a (validated) raw view: integer and float planes are used in place (float checked
 * for NaN and infinity, PC_ERANGE naming the pixel); packed formats are unpacked into *owned
 * (free with pc_dm_free). */
int pc_dm_prepare_input(const pc_view *raw, double black, pc_dm_input *in, void **owned);

/* A float plane as an input (no copy): the colour methods' intermediate images. */
pc_dm_input pc_dm_input_f32(const float *data, uint32_t width, uint32_t height);

/* Row y minus the black level (or the dark map, times the inverse gains, when the input has
 * them) as floats at dst[0..w), mirrored one pixel on each side:
 * dst[-1] = row[1], dst[w] = row[w-2] (dst must have room for both). */
void pc_dm_row_to_float(const pc_dm_input *in, uint32_t y, float *dst);

/* pc_dm_row_to_float without its prefetch of row y + 1: for callers that fetch the raw's rows
 * ahead themselves (pc_dm_pf, pan-lean's output row) */
void pc_dm_row_convert(const pc_dm_input *in, uint32_t y, float *dst);

/* A raw row's prefetch spread over the work between two row conversions (docs/demosaicking.md,
 * Round 36): pc_dm_row_to_float's prefetch of the whole next row at once issues about 80 misses
 * to memory in a burst, and the core waits for them (a raw frame is read from memory once);
 * issued a few lines at a time between the kernels' passes, they complete while the kernels
 * work. pc_dm_pf_row aims the cursor at the first 64-byte line of row y (nothing past the last
 * row), pc_dm_pf_step issues up to n more of the row's lines, pc_dm_pf_finish the rest; each
 * returns the lines it issued. */
typedef struct pc_dm_pf {
	uintptr_t cur, end; /* addresses: cur may lie before the raw's buffer (its first line) */
} pc_dm_pf;

void pc_dm_pf_row(pc_dm_pf *pf, const pc_dm_input *in, uint32_t y);
unsigned pc_dm_pf_step(pc_dm_pf *pf, unsigned n);
unsigned pc_dm_pf_finish(pc_dm_pf *pf);

/* The whole raw minus the black level as floats (row stride w; the colour methods' input) or
 * doubles (the references' input), C order, through pc_view_to_f32 (integer samples above the
 * format's bit depth: PC_ERANGE naming the pixel). Free with free(). */
int pc_dm_raw_to_float(const pc_view *raw, double black, float **out);
int pc_dm_raw_to_double(const pc_view *raw, double black, double **out);

/* min and max by comparison (the overshoot limiter's, demosaic_robust.c and the ratio kernels
 * that apply it as they write): inputs are finite (the raw and the methods' outputs), and
 * unlike fminf/fmaxf (library calls without -ffinite-math-only) these vectorise */
static inline float pc_dm_mn(float a, float b)
{
	return a < b ? a : b;
}

static inline float pc_dm_mx(float a, float b)
{
	return a > b ? a : b;
}

/* Sample (x, y) in raw units, before the black level (validity checks). */
static inline float pc_dm_sample(const pc_dm_input *in, uint32_t x, uint32_t y)
{
	const uint8_t *row = in->data + (size_t)y * in->stride;
	switch (in->type) {
	case PC_DMT_U8:
		return row[x];
	case PC_DMT_U16:
		return ((const uint16_t *)(const void *)row)[x];
	default:
		return ((const float *)(const void *)row)[x];
	}
}

/* channels consecutive width × height planes (pc_fplanes_separate) */
void pc_dm_planes_separate(float *base, uint32_t width, uint32_t height, unsigned channels,
                           pc_fplane *planes);

/* ---- scratch memory (64-byte aligned; NULL on failure) ----
 * Freed blocks of up to 4 MB are kept in a small pool (up to 32 MB) and handed out again to a
 * request of the same size (demosaic_common.c); pc_dm_pool_enabled: whether this build and
 * process pool (not under AddressSanitizer, nor with POLARCAM_SCRATCH_POOL=0);
 * pc_dm_pool_release frees the pooled blocks; pc_dm_pool_bytes: the bytes it holds. */
void *pc_dm_alloc(size_t bytes);
void pc_dm_free(void *p);
int pc_dm_pool_enabled(void);
void pc_dm_pool_release(void);
size_t pc_dm_pool_bytes(void); /* what the pool holds (tests) */

/* ---- the 3-row ring of padded float rows y-1, y, y+1 (one-pass kernels) ---- */
typedef struct pc_dm_ring {
	float *buf;
	size_t pitch; /* floats per padded row */
	float *row[3];
	int32_t have[3]; /* which mirrored source row each slot holds */
} pc_dm_ring;

int pc_dm_ring_init(pc_dm_ring *r, uint32_t w);
/* The padded row for source row y (mirrored), converting it if not already in the ring; bands
 * walk downwards. */
const float *pc_dm_ring_get(pc_dm_ring *r, const pc_dm_input *in, int y);
void pc_dm_ring_free(pc_dm_ring *r);

/* ---- streaming (non-temporal) stores ---- */

/* Output bytes from which non-temporal stores pay: 32 MB, never on AMD processors without
 * AVX-512 (Zen 3 and earlier: measured slower there, docs/demosaicking.md);
 * POLARCAM_NT_MIN_BYTES overrides it (read once). */
size_t pc_dm_nt_min_bytes(void);

/* Whether n planes are planar (pixel_stride 1), present, 64-byte aligned with 64-byte aligned
 * rows (whole cache lines; the AVX-512 streaming stores need it). */
int pc_dm_planes_aligned(const pc_fplane *p, unsigned n);

/* Whether every one of the n planes has pixel stride 1 (rows of contiguous floats) */
int pc_dm_planes_planar(const pc_fplane *p, unsigned n);

/* Whether n planes of w × h floats are worth streaming at this CPU level (aligned, large,
 * AVX2 present). */
int pc_dm_stream_wanted(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h, pc_cpu_level level);

/* The same for one interleaved (H, W, n) array (n = 4 or 12; 64-byte aligned, rows of whole
 * cache lines), which pc_dm_put_rows writes: whether its stores stream */
int pc_dm_stream_wanted_il(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h,
                           pc_cpu_level level);

/* Copies n rows of w floats with non-temporal stores (dst rows 64-byte aligned), one row after
 * the other so that every store sequence fills whole cache lines; then a store fence. For
 * kernels that compute a row in cache and then write it out; PC_ENOTSUP below AVX2, where the
 * caller keeps ordinary stores. */
int pc_dm_stream_rows(float *const dst[], const float *const src[], unsigned n, uint32_t w,
                      pc_cpu_level level);

/* Row y of n output planes (n ≤ 12) from row buffers: src[c][i] is plane c's column x0 + i, for
 * columns [x0, w). Each plane by its row and pixel strides; when the n planes are one interleaved
 * (H, W, n) array (pixel stride n, plane c at the first plane's data + c, n = 4 or 12, the Python
 * module's and the CLI's layout), pixel by pixel, each pixel's n values side by side, with lane
 * transposes at AVX-512 and AVX2 (docs/demosaicking.md, Round 31), streamed when nt
 * (pc_dm_stream_wanted_il; the caller ends its rows with pc_dm_sfence) and the row's first
 * pixel starts a cache line. */
void pc_dm_put_rows(const pc_fplane *out, unsigned n, uint32_t y, const float *const src[],
                    uint32_t x0, uint32_t w, pc_cpu_level level, int nt);

/* The store fence that ends a sequence of non-temporal stores (nothing off x86-64). */
void pc_dm_sfence(void);

/* ---- one kernel call: the prepared input and what the front door resolved ---- */
typedef struct pc_dm_call {
	const pc_dm_input *in;
	const pc_mosaic *m; /* a monochrome mosaic */
	pc_demosaic_method method;
	double full_scale; /* the signal's full scale: the raw's minus the black level */
	int threads;       /* 0: pc_parallel default */
	pc_cpu_level level;
	/* ratio-nr's noise gain k (its guide's variance model k·L, raw units): the plan's, given or
	 * fitted to the frame once (pc_dm_plan_noise); the other methods ignore it */
	double noise_gain;
} pc_dm_call;

/* ---- row sinks: a kernel that produces whole demosaicked rows hands them on ---- */
typedef struct pc_dm_row_sink {
	/* row y of the four analyser channels (channel order), w floats each, in cache */
	void (*row)(void *ctx, uint32_t y, const float *const ch[4]);
	void *ctx;
} pc_dm_row_sink;

/* ---- the methods' parameters (shared by the references and the fast paths) ---- */

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

static const pc_ri_params pc_ri_params_default = {2, 0.01, 1, 0};
static const pc_ri_params pc_eari_params = {2, 0.003, 1, 0.1};

/* Passes of the ratio method (PC_DM_RATIO): the second uses the first's mean as its guide
 * (Lapray NIR: +0.25 dB S0; Zhang: +1.0 dB S0, +0.8 dB DoLP over a single pass). */
#define PC_RATIO_PASSES 2
/* ratio-nr3: three passes from the binomial guide (docs/demosaicking.md, Round 43b) */
#define PC_RATIO_NR3_PASSES 3

#endif
