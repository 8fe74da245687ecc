/* polarcam/demosaic.h - the demosaicking ladder: from a raw polarizer mosaic to four full-
 * resolution analyser images I0, I45, I90, I135 (twelve, R/G/B × four angles, for
 * colour-polarization sensors).
 *
 * Every method has a plain scalar reference, computed in double, which is its specification
 * (pc_demosaic with opts.reference), and a fast float version (fused passes, vectorisable
 * loops, row bands on OpenMP threads) that the tests hold to the reference within the
 * tolerance stated in docs/demosaicking.md. Outputs keep the raw's units (a 12-bit frame gives
 * values in 0..4095), are never clamped, and never contain NaN or infinity.
 *
 * Borders: whole-sample mirror (pixel -1 reads pixel 1, pixel W reads pixel W-2), which keeps
 * the 2×2 analyser parity of every pixel. Colour-polarization methods mirror inside each
 * analyser's half-resolution Bayer sub-image, which keeps both the analyser and the colour.
 *
 * Channels: analyser c = 0..3 is 0°, 45°, 90°, 135° (polarcam/mosaic.h). Colour mosaics give
 * channel 4·k + c for colour k = 0 (R), 1 (G), 2 (B).
 */
#ifndef POLARCAM_DEMOSAIC_H
#define POLARCAM_DEMOSAIC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_DEMOSAIC_MAX_CHANNELS 12

/* One float output image: pixel (x, y) at data[y·row_stride + x·pixel_stride] (strides counted
 * in floats, not bytes). pixel_stride 1 is a plane; 4 with data = base + c is an interleaved
 * (H, W, 4) array. */
typedef struct pc_fplane {
	float *data;
	size_t row_stride;
	size_t pixel_stride;
} pc_fplane;

typedef enum pc_demosaic_method {
	PC_DM_SUPERPIXEL_HALF = 0, /* one output pixel per 2×2 block: (W/2, H/2) */
	PC_DM_SUPERPIXEL,          /* the same values replicated over each 2×2 block */
	PC_DM_BILINEAR,            /* per-channel bilinear (tent) interpolation */
	PC_DM_BICUBIC,             /* per-channel separable cubic convolution (Keys, a = -1/2) */
	PC_DM_PPID,                /* pseudo-panchromatic image difference (Mihoubi et al.) */
	PC_DM_RI,                  /* guided-filter residual interpolation (Kiku et al., Ahmed et al.) */
	PC_DM_EARI,                /* edge-aware residual interpolation (Morimatsu et al.) */
	PC_DM_BAYER_FIRST,         /* colour only: Bayer bilinear per analyser, then analysers */
	PC_DM_BAYER_EARI,          /* colour only: Bayer bilinear per analyser, then EARI per colour */
	PC_DM_RATIO,               /* edge-aware guide + ratio interpolation, two passes (ours) */
	PC_DM_EARI_MLRI,           /* EARI as its authors define it: their guide + MLRI (anchor) */
	PC_DM_EARI_ROBUST,         /* eari-mlri + the overshoot limiter (ours; recommended) */
	PC_DM_PCDP,                /* polarization channel difference prior (Wu et al. 2021; anchor) */
	PC_DM_IGRI2,               /* iterative guided residual interpolation 2 (Morimatsu 2021; anchor) */
	PC_DM_COUNT
} pc_demosaic_method;

enum pc_demosaic_flags {
	PC_DMF_MONO = 1u << 0,    /* works on monochrome polarizer mosaics */
	PC_DMF_COLOR = 1u << 1,   /* works on colour-polarization mosaics */
	PC_DMF_HALF_RES = 1u << 2 /* output is (W/2, H/2) */
};

typedef struct pc_demosaic_method_info {
	pc_demosaic_method method;
	const char *name;     /* command-line name: "bilinear", "ri", ... */
	const char *accuracy; /* one line on accuracy */
	const char *cost;     /* one line on cost */
	const char *source;   /* the publication it follows */
	unsigned flags;       /* pc_demosaic_flags */
} pc_demosaic_method_info;

/* Table entry of a method, NULL for out-of-range values. */
const pc_demosaic_method_info *pc_demosaic_method_get(pc_demosaic_method m);

/* Method by command-line name. PC_EINVAL listing the valid names when unknown. */
int pc_demosaic_method_from_name(const char *name, pc_demosaic_method *m);

/* Number of output channels for a mosaic: 4 (monochrome) or 12 (colour). */
unsigned pc_demosaic_channels(const pc_mosaic *m);

/* Output size of a method for a raw of width × height. */
void pc_demosaic_out_size(pc_demosaic_method m, uint32_t width, uint32_t height, uint32_t *ow,
			  uint32_t *oh);

typedef struct pc_demosaic_opts {
	int threads;      /* 0: pc_parallel default; 1: the caller's thread only */
	bool reference;   /* run the scalar double-precision reference instead of the fast path */
	double full_scale;/* the raw's full-scale value for edge-aware weights; 0: from the
			   * format (2^bits - 1), or 1.0 for float32 raws */
} pc_demosaic_opts;

/* Demosaics raw (any integer pc_pixfmt, packed or not, or finite float32) with mosaic m into
 * pc_demosaic_channels(m) output images of pc_demosaic_out_size(). opts may be NULL.
 * Errors (PC_EINVAL with a detail message): invalid view or mosaic, odd or too small sizes
 * (at least 4×4, even; colour: at least 8×8), a method that does not support the mosaic kind,
 * missing output planes, NaN or infinite float input (PC_ERANGE naming the pixel). */
int pc_demosaic(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
		const pc_demosaic_opts *opts, const pc_fplane *out);

/* Bilinear into 16-bit planes, for live paths that keep integers (display, recording, 16-bit
 * outputs like OpenCV's): out[c] is the plane of analyser c (row stride out_stride bytes), each
 * value round(bilinear · 2^frac_bits) with halves rounded up. frac_bits = 2 is exact (bilinear
 * values are multiples of 1/4); frac_bits = 0 rounds to whole raw units. raw must be a 16-bit
 * container format (Mono10/12/14/16) and bits + frac_bits <= 16 (PC_ERANGE otherwise), with
 * the same sizes and mosaics as pc_demosaic. Equal to pc_demosaic's bilinear scaled and rounded
 * (tested). */
int pc_demosaic_bilinear_u16(const pc_view *raw, const pc_mosaic *m, unsigned frac_bits,
			     int threads, uint16_t *const out[4], size_t out_stride);

/* Fills planes[0..channels) for an interleaved C-order (height, width, channels) float buffer. */
void pc_fplanes_interleaved(float *base, uint32_t width, unsigned channels, pc_fplane *planes);

/* Fills planes[0..channels) for channels consecutive width × height planes (channel-major). */
void pc_fplanes_separate(float *base, uint32_t width, uint32_t height, unsigned channels,
			 pc_fplane *planes);

#ifdef __cplusplus
}
#endif
#endif
