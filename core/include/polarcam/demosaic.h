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

#include "polarcam/export.h"
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
	PC_DM_RI,          /* guided-filter residual interpolation (Kiku et al., Ahmed et al.) */
	PC_DM_EARI,        /* edge-aware residual interpolation (Morimatsu et al.) */
	PC_DM_BAYER_FIRST, /* colour only: Bayer bilinear per analyser, then analysers */
	PC_DM_BAYER_EARI,  /* colour only: Bayer bilinear per analyser, then EARI per colour */
	PC_DM_RATIO,       /* edge-aware guide + ratio interpolation, two passes (ours) */
	PC_DM_EARI_MLRI,   /* EARI as its authors define it: their guide + MLRI (anchor) */
	PC_DM_EARI_ROBUST, /* eari-mlri + the overshoot limiter (ours; recommended) */
	PC_DM_PCDP,        /* polarization channel difference prior (Wu et al. 2021; anchor) */
	PC_DM_IGRI2,       /* iterative guided residual interpolation 2 (Morimatsu 2021; anchor) */
	PC_DM_NEWTON,      /* Newton's polynomial, polarization differences (Li 2019; anchor) */
	PC_DM_RATIO_RI,    /* ratio, then guided-filter residual interpolation (ours) */
	PC_DM_RATIO_NR,    /* ratio with a shot-noise-aware guide level (ours) */
	PC_DM_PAN_RATIO,   /* colour only: ratios to a pseudo-panchromatic guide (ours) */
	PC_DM_PAN_GUIDED,  /* colour only: pan-ratio with guide-weighted (bilateral) tents */
	PC_DM_PAN_CHROMA,  /* colour only: pan-guided whose guide also sees hue (ours) */
	PC_DM_PAN_DIR,     /* colour only: pan-ratio with homogeneity-weighted one-sided
	                    * candidates (ours) */
	PC_DM_PAN_FACT,    /* colour only: hue from half-resolution block sums, polarization
	                    * on the hue-normalised mosaic (ours) */
	PC_DM_PAN_SIDE,    /* colour only: pan-guided with one-sided factors from the blocks'
	                    * hue (ours) */
	PC_DM_PAN_ADAPT,   /* colour only: pan-side with a signal-relative range scale and a
	                    * noise-aware ratio step (ours) */
	PC_DM_PAN_GUARD,   /* colour only: pan-adapt blended towards bayer-first where a
	                    * leave-one-out check finds the ratio model locally worse (ours) */
	PC_DM_PAN_HUE,     /* colour only: pan-guard whose red and blue also fall back where
	                    * green's ratio residual shows hue detail (ours) */
	PC_DM_PAN_CHECK,   /* colour only: pan-side blended towards own-lattice tents by a
	                    * leave-one-out check, for the 5x budget (ours) */
	PC_DM_PAN_SPLIT,   /* colour only: a pan estimate whose ratio step carries green's detail
	                    * into red and blue (and theirs into green) only as far as the local
	                    * luminance outweighs the green-magenta chrominance (ours) */
	PC_DM_PAN_LEAN,    /* colour only: plain pan tents with noise- and texture-aware side
	                    * factors, each output blended towards the plain tents within the
	                    * noise (ours) */
	PC_DM_RATIO_NR3,   /* ratio-nr from a binomial guide in three passes (ours) */
	PC_DM_COUNT
} pc_demosaic_method;

enum pc_demosaic_flags {
	PC_DMF_MONO = 1u << 0,           /* works on monochrome polarizer mosaics */
	PC_DMF_COLOR = 1u << 1,          /* works on colour-polarization mosaics */
	PC_DMF_HALF_RES = 1u << 2,       /* output is (W/2, H/2) */
	PC_DMF_REFERENCE_ONLY = 1u << 3, /* no fast path: the double-precision reference always
	                                  * runs (hundreds of times bilinear's time) */
	PC_DMF_NOISE_GAIN = 1u << 4 /* uses the frame's noise gain (pc_pipeline_opts.noise_gain:
	                             * given, or estimated from the frame) */
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
PC_API const pc_demosaic_method_info *pc_demosaic_method_get(pc_demosaic_method m);

/* The names of the methods whose flags contain all of flags (pc_demosaic_flags; 0: every
 * method), in the table's order, joined by ", ": generated from the table, so messages and help
 * that list methods stay in step with it. Written into buf as snprintf does (at most size
 * bytes, NUL-terminated when size > 0, buf may be NULL when size is 0); returns the length of
 * the whole list, so a return >= size means it was cut. */
PC_API size_t pc_demosaic_method_names(unsigned flags, char *buf, size_t size);

/* Method by command-line name. PC_EINVAL listing the valid names when unknown. */
PC_API int pc_demosaic_method_from_name(const char *name, pc_demosaic_method *m);

/* Number of output channels for a mosaic: 4 (monochrome) or 12 (colour). */
PC_API unsigned pc_demosaic_channels(const pc_mosaic *m);

/* Output size of a method for a raw of width × height. */
PC_API void pc_demosaic_out_size(pc_demosaic_method m, uint32_t width, uint32_t height,
                                 uint32_t *ow, uint32_t *oh);

typedef struct pc_demosaic_opts {
	int threads;       /* 0: pc_parallel default; 1: the caller's thread only */
	bool reference;    /* run the scalar double-precision reference instead of the fast path */
	double full_scale; /* the raw's full-scale value for edge-aware weights; 0: from the
	                    * format (2^bits - 1), or 1.0 for float32 raws */
} pc_demosaic_opts;

/* ---- the front door: raw → demosaic (→ Stokes, polarcam/stokes.h) with one options struct ----
 *
 * Black level: subtracted from every raw sample before demosaicking (so outputs are in raw
 * units above black; DoLP is unbiased by the sensor's offset). Values below the black level
 * become negative, and stay so: nothing is clamped.
 * Saturation and dead levels: an output pixel whose value depends on a raw sample >= the
 * saturation level or <= the dead level (raw units, before the black level) is flagged in the
 * validity output; its value is computed as for any other pixel. "Depends on" is the method's
 * support: the 3×3 neighbourhood for bilinear, the 2×2 super-pixel for the super-pixel
 * methods, wider boxes for the others (docs/demosaicking.md lists them), with the borders'
 * mirror applied. */

struct pc_analyser_pinv; /* polarcam/stokes.h */
struct pc_compact_calib; /* polarcam/stokes.h */

typedef struct pc_pipeline_opts {
	pc_demosaic_method method;
	pc_mosaic mosaic;        /* the raw's mosaic, phase included (pc_frame.mosaic) */
	int threads;             /* 0: pc_parallel default; 1: the caller's thread only */
	bool reference;          /* the double-precision references instead of the fast paths */
	double full_scale;       /* the raw's full scale for edge-aware weights (raw units); 0:
	                          * 2^bits − 1, or 1.0 for float32 raws. The methods use
	                          * full_scale − black_level. */
	double black_level;      /* raw units, >= 0 and below full scale; 0: none */
	double saturation_level; /* raw units; samples >= it are saturated; 0: not checked */
	double dead_level;       /* raw units; samples <= it are dead; 0: not checked (to flag
	                          * samples of 0 in an integer raw, give 0.5) */
	/* pc_stokes_run only: calibrated analysers (polarcam/stokes.h), NULL for ideal ones;
	 * pc_demosaic_run refuses it */
	const struct pc_analyser_pinv *pinv;
	/* pc_stokes_run only, bilinear fast path only: a compact calibration (the analysis
	 * vectors of the raw samples, solved per output pixel in the fused pass, and optionally
	 * 16-bit dark and gain maps; polarcam/stokes.h); NULL: none. Not together with pinv. */
	const struct pc_compact_calib *compact;
	/* Per-pixel correction before demosaicking (a calibration's dark offsets and gains,
	 * polarcam/calib.h): sample p = y·width + x becomes (raw_p − dark[p])·gain_inv[p], in
	 * float, with black_level in place of dark[p] when dark is NULL and no factor when
	 * gain_inv is NULL. Maps of width × height floats, row stride width; NULL: none. The
	 * saturation and dead levels still apply to the raw samples. The fused bilinear Stokes
	 * pipeline applies it while reading each raw row; the other paths correct a float copy of
	 * the raw first. */
	const float *dark;
	const float *gain_inv;
	/* Per raw sample trust for the validity (width × height bytes, row stride width): 0 flags
	 * the sample as a saturated one is flagged (a calibration's distrusted pixels); NULL: all
	 * trusted. */
	const uint8_t *trusted;
	/* The noise model of the methods flagged PC_DMF_NOISE_GAIN (pan-adapt, pan-guard for its
	 * base pan-adapt, pan-lean and ratio-nr; the others ignore it): the gain g of the sensor's
	 * photon-transfer curve, variance per unit signal in raw units (DN² per DN above black,
	 * i.e. DN per unit of signal: a sample of mean s DN above black has variance g·s plus the
	 * read noise). For a camera measured after EMVA Standard 1288 (its photon-transfer curve,
	 * docs/calibration.md) g is the system gain K in DN/e⁻ at the settings in use, in the raw's
	 * units (a 12-bit raw in a 16-bit container shifted left by 4 has 16·K). No read noise is
	 * given: pan-adapt's shrinkage takes the dark floor as g times its δ (docs/demosaicking.md,
	 * Round 15b); ratio-nr's guide variance model is g·L (Round 40). > 0: given; 0: estimated
	 * from each frame (pc_demosaic_noise_gain; the
	 * default). Negative, NaN or infinite: PC_EINVAL. The per-pixel correction (dark, gain_inv)
	 * does not rescale it. */
	double noise_gain;
	/* Output, optional: where a run of a method flagged PC_DMF_NOISE_GAIN (pc_demosaic_run,
	 * pc_stokes_run, pc_stokes_run_colour) stores the noise gain it used: noise_gain when
	 * given, else its estimate from the frame (pc_demosaic_noise_gain's value, bit for bit),
	 * so a caller that reports it need not estimate it again. Written on success only, and
	 * not by the other methods (start it at 0). NULL: not stored. */
	double *noise_gain_used;
	/* With dark: the map taken about a level, dark[p] → dark_pivot + dark_scale·(dark[p] −
	 * dark_pivot), in float (a calibration's dark map at another analog gain: its part above
	 * the black level scales with the gain, polarcam/calib.h pc_calib_dark_scale). dark_scale 0
	 * or 1: the map as it is. Finite, dark_scale ≥ 0; PC_EINVAL otherwise. */
	double dark_scale, dark_pivot;
} pc_pipeline_opts;

/* Bilinear on Sony's IMX250MZR mosaic, default threads, fast paths, full scale from the format,
 * no black level, no saturation or dead checks, ideal analysers, noise gain estimated. A struct
 * initialised to zero and given a method and a mosaic means the same (fields added later keep
 * 0 as "as before"). */
PC_API pc_pipeline_opts pc_pipeline_defaults(void);

/* Which output pixels are valid. mask: NULL (only the count is wanted) or the output size in
 * bytes, row stride row_stride bytes, written 1 (valid) or 0 (depends on a saturated or dead
 * sample). n_invalid: set by the call to the number of 0s (0 when no level is checked). */
typedef struct pc_validity {
	uint8_t *mask;
	size_t row_stride;
	uint64_t n_invalid;
} pc_validity;

/* Demosaics raw (any integer pc_pixfmt, packed or not, or finite float32) into
 * pc_demosaic_channels(&opts->mosaic) output images of pc_demosaic_out_size(); valid may be
 * NULL. Validates everything once, then takes the path of the method table: the reference,
 * the fast kernel, or for colour mosaics the colour step then the monochrome one.
 * Errors (PC_EINVAL with a detail message): invalid view or mosaic, odd or too small sizes
 * (at least 4×4, even; colour: at least 8×8), a method that does not support the mosaic kind,
 * missing output planes, levels that are negative, not finite, a black level at or above full
 * scale, a dead level at or above the saturation level, opts->pinv set; NaN or infinite float
 * input (PC_ERANGE naming the pixel). */
PC_API int pc_demosaic_run(const pc_view *raw, const pc_pipeline_opts *opts, const pc_fplane *out,
                           pc_validity *valid);

/* The validity output of pc_demosaic_run alone (valid required; nothing demosaicked): for a
 * pipeline that demosaics elsewhere, e.g. a calibrated one that flags its own samples (a Mono8
 * view of 0 = good, 1 = bad with saturation_level 1 gives the mask of the method's support). */
PC_API int pc_validity_run(const pc_view *raw, const pc_pipeline_opts *opts, pc_validity *valid);

/* The noise gain g (pc_pipeline_opts.noise_gain's units) that the methods flagged
 * PC_DMF_NOISE_GAIN estimate from a frame when none is given. For ratio-nr (a monochrome
 * method): the slope of the frame's photon-transfer line σ² = g·L + b, fitted to the
 * variances of weakly textured 2×2 same-channel blocks grouped by level (Foi et al., IEEE TIP
 * 17(10) 2008; Liu, Tanaka, Okutomi, IEEE TIP 22(12) 2013; docs/demosaicking.md, Round 40),
 * 0 for noise-free frames and for frames too small for two groups of 64 blocks. For the colour
 * methods (pan-adapt, pan-guard, pan-lean): the smaller of two robust
 * estimates, the median of the squared residuals of same-channel samples one mosaic period
 * apart (docs/demosaicking.md, Round 14) and the median of the squared residuals
 * I0 + I90 − I45 − I135 of the 2×2 polarizer blocks, which cancel any Stokes vector (Round 19),
 * each over a fixed grid of at most 65536 samples or blocks, on the raw minus the black level
 * after the per-pixel correction of opts (dark, gain_inv). Any mosaic. The identical value
 * pc_demosaic_run uses. Texture finer than a block still raises it (a noise-free render of
 * grass blades 1.4–2.8 px wide: 73 DN; Round 19), noise-free smooth frames give about 0; 0 for
 * frames too small to have an interior sample. On real cameras a calibrated g (EMVA 1288's K)
 * given in noise_gain is better. opts->noise_gain is not used; the raw and the other options (the
 * method must suit the mosaic) are validated as by pc_demosaic_run. */
PC_API int pc_demosaic_noise_gain(const pc_view *raw, const pc_pipeline_opts *opts, double *g);

/* pc_demosaic_run with method, mosaic m, and opts' threads, reference and full scale (opts may
 * be NULL): no black level, no validity, the noise gain estimated. (New options go to
 * pc_pipeline_opts only: callers initialise pc_demosaic_opts positionally, and a new member
 * would break their builds under -Werror=missing-field-initializers.) */
PC_API int pc_demosaic(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
                       const pc_demosaic_opts *opts, const pc_fplane *out);

/* Bilinear into 16-bit planes, for live paths that keep integers (display, recording, 16-bit
 * outputs like OpenCV's): out[c] is the plane of analyser c (row stride out_stride bytes), each
 * value round(bilinear · 2^frac_bits) with halves rounded up. frac_bits = 2 is exact (bilinear
 * values are multiples of 1/4); frac_bits = 0 rounds to whole raw units. raw must be a 16-bit
 * container format (Mono10/12/14/16) and bits + frac_bits <= 16 (PC_ERANGE otherwise), with
 * the same sizes and mosaics as pc_demosaic. Equal to pc_demosaic's bilinear scaled and rounded
 * (tested). */
PC_API int pc_demosaic_bilinear_u16(const pc_view *raw, const pc_mosaic *m, unsigned frac_bits,
                                    int threads, uint16_t *const out[4], size_t out_stride);

/* Fills planes[0..channels) for an interleaved C-order (height, width, channels) float buffer. */
PC_API void pc_fplanes_interleaved(float *base, uint32_t width, unsigned channels,
                                   pc_fplane *planes);

/* Fills planes[0..channels) for channels consecutive width × height planes (channel-major). */
PC_API void pc_fplanes_separate(float *base, uint32_t width, uint32_t height, unsigned channels,
                                pc_fplane *planes);

#ifdef __cplusplus
}
#endif
#endif
