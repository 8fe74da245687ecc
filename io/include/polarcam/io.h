/* polarcam/io.h - files: PNG, TIFF, NumPy .npy, raw with explicit geometry; atomic writes.
 *
 * Every writer writes to a temporary file in the destination's directory and renames it into
 * place on success, so a failure never leaves a half-written file behind. Every reader
 * validates what it reads; errors name the file and the problem.
 */
#ifndef POLARCAM_IO_H
#define POLARCAM_IO_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "polarcam/eval.h"
#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- atomic files ---- */
typedef struct pc_atomic_file {
	FILE *fp;
	char *path;     /* final path */
	char *tmp_path; /* temporary path in the same directory */
} pc_atomic_file;

PC_API int pc_atomic_open(pc_atomic_file *af, const char *path);
/* Flushes, fsyncs, closes and renames into place. On failure the temporary file is removed. */
PC_API int pc_atomic_commit(pc_atomic_file *af);
/* Closes and removes the temporary file. Safe to call after a failed commit or twice. */
PC_API void pc_atomic_abort(pc_atomic_file *af);

/* Writes size bytes atomically. */
PC_API int pc_write_file_atomic(const char *path, const void *data, size_t size);

/* Removes what killed writers left in dir: the temporary files of pc_atomic_open
 * (".NAME.tmpXXXXXX") whose lock no process holds any more (a writer holds an flock on its
 * temporary file until it is renamed or removed; the kernel drops it when the writer dies).
 * Files a live process is writing, in this process or another, are left alone. *removed (may
 * be NULL) counts the files removed. A directory that does not exist holds nothing: 0. */
PC_API int pc_atomic_sweep(const char *dir, unsigned *removed);

/* ---- outputs: the one rule, and folders written as a set ----
 *
 * Every pipeline that writes an output (a file or a folder) follows one rule: an output that
 * exists and is not empty is refused (PC_EEXIST, the detail naming it) unless the caller asks
 * for PC_OUT_OVERWRITE. An empty file or folder, or a missing one, is simply written (missing
 * parent folders are created).
 *
 * A folder is written as a set: pc_outdir_begin makes a temporary sibling folder
 * ".NAME.tmp-HOST-PID-XXXXXX" beside it, the caller writes every file into od->tmp, and
 * pc_outdir_commit puts the whole folder in place with one rename. With PC_OUT_OVERWRITE an
 * existing folder is swapped out in the same step (renameat2 RENAME_EXCHANGE, or two renames
 * where the file system lacks it) and removed only once the new one is in place. The folder at
 * PATH is therefore always the old one or the new one, whole: no file of an older run survives
 * a new one, and a failure (a full disk, an error, an interruption) leaves the old folder as it
 * was, with pc_outdir_abort removing the temporary one. A run killed outright leaves its
 * temporary folder; the next pc_outdir_begin for the same PATH on the same host removes those
 * whose process is gone.
 *
 * Overwriting is refused, even with PC_OUT_OVERWRITE, for what polarcam cannot have written
 * and would delete with it: a folder holding none of meta.json, report.json, mueller.json,
 * figures.md or demosaic.json (the description every polarcam output folder carries; `bench
 * demosaic` writes the last), a symbolic link, a file
 * where a folder is expected (and the reverse), and the current directory or a folder that
 * contains it. */
#define PC_OUT_OVERWRITE 1u

/* The rule alone, checked without writing anything (to refuse before long work): 0 when path
 * may be written as a folder (folder true) or a file. */
PC_API int pc_output_check(const char *path, unsigned flags, bool folder);

typedef struct pc_outdir {
	char *path; /* the folder asked for */
	char *tmp;  /* the temporary sibling folder to write into */
	unsigned flags;
} pc_outdir;

/* Checks the rule (pc_output_check) and creates od->tmp. */
PC_API int pc_outdir_begin(pc_outdir *od, const char *path, unsigned flags);
/* Puts od->tmp in place at od->path (replacing the old folder when one was allowed) and frees
 * od. On failure the old folder is untouched and the temporary one removed. */
PC_API int pc_outdir_commit(pc_outdir *od);
/* Removes the temporary folder and frees od. Safe after a failed commit, twice, or on a zeroed
 * pc_outdir. */
PC_API void pc_outdir_abort(pc_outdir *od);

/* ---- arrays (.npy) ---- */
/* PC_DT_F16 (IEEE binary16 bits in uint16_t) is written, not read. */
typedef enum pc_dtype { PC_DT_U8 = 1, PC_DT_U16, PC_DT_F32, PC_DT_F64, PC_DT_F16 } pc_dtype;
/* float32 → binary16 bits, round to nearest even (overflow → ±inf, NaN kept). */
PC_API void pc_f32_to_f16(const float *in, uint16_t *out, size_t n);

typedef struct pc_array {
	void *data; /* C order, owned */
	pc_dtype dtype;
	unsigned ndim; /* 1..4 */
	size_t shape[4];
} pc_array;

PC_API size_t pc_array_count(const pc_array *a);
PC_API void pc_array_free(pc_array *a);

/* Writes a C-order array as NumPy format 1.0 (little-endian). */
PC_API int pc_npy_write(const char *path, const void *data, pc_dtype dtype, unsigned ndim,
                        const size_t *shape);
/* A .npy written piece by piece (a stack of frames as they are computed): open with the whole
 * array's shape, write its bytes in C order in any number of pieces, commit (atomic, like every
 * writer; PC_ESTATE when fewer bytes than the shape holds were written). A failed write
 * aborts the stream. */
typedef struct pc_npy_stream {
	pc_atomic_file af;
	size_t bytes, written;
} pc_npy_stream;
PC_API int pc_npy_stream_open(pc_npy_stream *s, const char *path, pc_dtype dtype, unsigned ndim,
                              const size_t *shape);
PC_API int pc_npy_stream_write(pc_npy_stream *s, const void *data, size_t bytes);
PC_API int pc_npy_stream_commit(pc_npy_stream *s);
PC_API void pc_npy_stream_abort(pc_npy_stream *s);

/* Reads .npy (u1, <u2, <f4, <f8; C order; format 1.0/2.0). */
PC_API int pc_npy_read(const char *path, pc_array *out);

/* ---- images ---- */
/* PNG of a Mono8 view (8-bit) or any 9..16-bit integer view (16-bit PNG; the sBIT chunk records
 * the significant bits). Grey only. */
PC_API int pc_png_write(const char *path, const pc_view *v);
/* Headerless raw file of an integer view (atomic): rows one after the other without padding,
 * each pixel in the view's container - 1 byte for 8-bit formats, 2 bytes little-endian with the
 * value LSB-aligned for unpacked 9..16-bit formats, the packed bytes as they are for packed
 * ones. pc_image_read reads it back with the geometry {width, height, format, 0, 0}. */
PC_API int pc_raw_write(const char *path, const pc_view *v);
/* 8-bit RGB PNG from interleaved rows (pictures, plots). */
PC_API int pc_png_write_rgb8(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height,
                             size_t stride);

/* Raw geometry for headerless files: width, height, format, offset into the file, stride
 * (0 = tight). */
typedef struct pc_raw_geometry {
	uint32_t width, height;
	pc_pixfmt format;
	size_t offset;
	size_t stride;
} pc_raw_geometry;

/* Reads a single-channel image: PNG 8/16-bit, TIFF 8/16-bit or float32, .npy 2-D (u1, u2, f4,
 * f8), 8-bit grey BMP, or a raw file when geometry is given (non-NULL). *out is an owned view
 * (Mono8, Mono16 or Float32; raw files keep their format); *significant_bits is the bit depth
 * the file declares (PNG sBIT, TIFF BitsPerSample, 32 for float) and may be NULL. Float images
 * holding NaN or infinity are rejected (PC_ERANGE naming the file and the pixel). */
PC_API int pc_image_read(const char *path, const pc_raw_geometry *geometry, pc_view *out,
                         unsigned *significant_bits);

/* Reads a raw mosaic for processing: pc_image_read, then the bit depth. bits = 0 takes the
 * depth the file declares (PNG sBIT, TIFF/npy container); otherwise the file's container must
 * fit it (8 needs 8-bit data, 9..16 needs 16-bit data: "wrong bit depth" otherwise). Every pixel
 * must fit the depth (PC_ERANGE naming file and pixel: 12-bit data holding 4096 is corrupt).
 * Integer views come back as Mono8/Mono10/12/14/16 matching the depth; *bits_out (may be NULL)
 * receives it (32 for float). */
PC_API int pc_image_read_mosaic(const char *path, const pc_raw_geometry *geometry, unsigned bits,
                                pc_view *out, unsigned *bits_out);

/* TIFF of a Mono8, 9..16-bit (stored as 16-bit) or Float32 view. */
PC_API int pc_tiff_write(const char *path, const pc_view *v);
/* TIFF of a C-order (height, width, channels) array of u8, u16 or f32 samples (interleaved;
 * channels 1..16; extra samples are marked "unspecified"). */
PC_API int pc_tiff_write_array(const char *path, const void *data, pc_dtype dtype, uint32_t height,
                               uint32_t width, unsigned channels);
/* Reads a single-channel TIFF (8/16-bit unsigned, 32-bit float) into an owned view. */
PC_API int pc_tiff_read(const char *path, pc_view *out, unsigned *significant_bits);
/* Reads a TIFF as an array: (H, W) or (H, W, C) of u8, u16 or f32. */
PC_API int pc_tiff_read_array(const char *path, pc_array *out);

/* Reads a grey PNG (1..16-bit; 1/2/4-bit expanded to 8) into an owned Mono8 or Mono16 view. */
PC_API int pc_png_read(const char *path, pc_view *out, unsigned *significant_bits);
/* Reads an uncompressed grey BMP (8-bit grey palette, or 24/32-bit with R = G = B) as Mono8. */
PC_API int pc_bmp_read(const char *path, pc_view *out);

/* Writes the standard pictures of a Stokes image into dir, each with a title and a colour bar:
 * s0.png (grey, 0 to the 99.9th percentile), dolp.png (grey, 0..1), aolp.png (hue = AoLP,
 * value = DoLP) and aolp_sat.png (hue = AoLP, saturation = DoLP). st needs s0, dolp and aolp.
 * Files are written atomically. Titles read "PREFIX: S0 (total intensity)" etc.
 *
 * Low-signal mask: where S0 is below a threshold, DoLP and AoLP are noise (their noise grows
 * like σ/S0), so dolp.png, aolp.png and aolp_sat.png paint those pixels with a dark grey hatch
 * (pc_picture_mask_low), say so in the title ("hatched: S0 < T, low signal") and show the hatch
 * under the colour bar. The threshold is opts->mask_s0 in S0 units (raw units) when > 0;
 * 0 (and pc_pictures_write) uses PC_PICTURES_MASK_DEFAULT_REL of the S0 99.9th percentile
 * (the top of the S0 picture's scale); < 0 disables the mask. Callers that know their sensor's
 * noise can pass a few σ of S0 instead.
 *
 * Scales for comparing pictures: s0_hi > 0 fixes the top of the S0 scale (pictures of a truth
 * and of estimates then share one scale); 0 takes the image's own 99.9th percentile (the mask
 * default follows the scale's top either way). dolp_hi sets the DoLP range 0..dolp_hi of
 * dolp.png and the DoLP shown at full value/saturation in the AoLP pictures: > 0 that value
 * (at most 1), 0 the full range 0..1, < 0 automatic: the 99th percentile of DoLP over the
 * unmasked pixels rounded up to a multiple of 0.05 (typical scenes' DoLP stays far below 1 and
 * looks black on 0..1). The range used is printed on the key ("DoLP 0..0.35, auto"). AoLP keys
 * have ticks at 0, 45, 90, 135, 180°. */
#define PC_PICTURES_MASK_DEFAULT_REL 0.01
typedef struct pc_pictures_opts {
	const char *title_prefix; /* NULL: none */
	uint32_t max_width;       /* downscale for display to at most this width; 0: full size */
	double mask_s0;           /* low-signal mask threshold (see above) */
	const char *suffix;       /* added to the file names before .png ("_000012"); NULL: none */
	double s0_hi;             /* top of the S0 scale; 0: the image's 99.9th percentile */
	double dolp_hi;           /* DoLP range 0..dolp_hi; 0: 0..1; < 0: automatic */
} pc_pictures_opts;

/* The automatic DoLP range of pc_pictures_opts (dolp_hi < 0): the 99th percentile of the finite
 * DoLP values where S0 >= mask (all pixels when mask is not finite or <= 0), rounded up to a
 * multiple of 0.05, at least 0.05 and at most 1. */
PC_API double pc_pictures_dolp_auto(const float *dolp, const float *s0, size_t n, double mask);

struct pc_stokes_out;
/* opts may be NULL (no prefix, full size, default mask). */
PC_API int pc_pictures_write_opts(const char *dir, const struct pc_stokes_out *st, uint32_t width,
                                  uint32_t height, const pc_pictures_opts *opts);
/* The same with a validity mask (valid may be NULL or have a NULL mask: all valid): pixels
 * whose value depends on a saturated, dead or distrusted sample are painted with the invalid
 * mark of polarcam/picture.h (pc_picture_mask_invalid) in every picture, over the low-signal
 * hatch, and their count is noted under each colour bar. */
struct pc_validity;
PC_API int pc_pictures_write_valid(const char *dir, const struct pc_stokes_out *st, uint32_t width,
                                   uint32_t height, const pc_pictures_opts *opts,
                                   const struct pc_validity *valid);
/* Pictures of Imin/Imax and of the diffuse/specular split (pc_stokes_minmax, polarcam/stokes.h)
 * of st's S0, S1, S2: imin.png and imax.png when minmax, diffuse.png and specular.png when
 * split, grey on the S0 picture's scale (opts->s0_hi, or S0's 99.9th percentile as s0.png) so
 * that they compare with s0.png and with each other, invalid pixels marked as in the others.
 * Imin/Imax are intensities, not ratios: no low-signal hatch. */
PC_API int pc_pictures_write_minmax(const char *dir, const struct pc_stokes_out *st, uint32_t width,
                                    uint32_t height, const pc_pictures_opts *opts,
                                    const struct pc_validity *valid, bool minmax, bool split);
/* The live window's picture (polarcam view): S0, DoLP and AoLP (hue, value = DoLP) side by
 * side, each with the key, ranges, masks and legend notes of pc_pictures_write_valid's files
 * (opts as there: mask_s0, s0_hi, dolp_hi; title_prefix, suffix and max_width unused) under a
 * short title. The images keep the frames' aspect ratio, drawn as wide as three fit with their
 * keys in out_width (scaled up by nearest neighbour, down by a box filter); white fills the
 * rest, and `top` white rows above them leave room for a status line. *out: malloc'd RGB8,
 * out_width × *out_height, stride 3·out_width. out_width at least
 * PC_PICTURES_PANELS_MIN_WIDTH (the three keys take about 310 pixels). */
#define PC_PICTURES_PANELS_MIN_WIDTH 480
PC_API int pc_pictures_panels(const struct pc_stokes_out *st, uint32_t width, uint32_t height,
                              const pc_pictures_opts *opts, const struct pc_validity *valid,
                              uint32_t out_width, uint32_t top, uint8_t **out,
                              uint32_t *out_height);
/* The same panels frame after frame (polarcam view): pc_pictures_live keeps the buffers of
 * pc_pictures_panels - the full-size picture, cairo's copy of it, the automatic DoLP range's
 * copies and the output - made at the first draw and again only when a larger one is needed,
 * so that drawing a stream of frames of one size allocates no frame-sized memory (only the
 * keys' small surfaces). Not for two threads at once. */
typedef struct pc_pictures_live pc_pictures_live;
PC_API int pc_pictures_live_new(pc_pictures_live **out);
PC_API void pc_pictures_live_free(pc_pictures_live *p);
/* As pc_pictures_panels, the same pixels; *out belongs to p, valid until its next draw or
 * free. */
PC_API int pc_pictures_live_draw(pc_pictures_live *p, const struct pc_stokes_out *st,
                                 uint32_t width, uint32_t height, const pc_pictures_opts *opts,
                                 const struct pc_validity *valid, uint32_t out_width, uint32_t top,
                                 const uint8_t **out, uint32_t *out_height);
/* Pictures of a colour-polarization frame's per-colour Stokes images rgb[0..2] (R, G, B; S0 and
 * DoLP needed; rgb points to 3): s0_rgb.png, the three S0 as the red, green and blue of one picture
 * on one scale (opts->s0_hi, or the largest of their 99.9th percentiles: no white balance, the
 * colours the sensor saw), and dolp_rgb.png, the three DoLP as red, green and blue on the DoLP
 * range of opts->dolp_hi (automatic: over the three channels): grey where R, G and B are equally
 * polarized, tinted towards the colours polarized more. Keys are grey (a value in all three
 * channels). The low-signal hatch covers the pixels where the darkest channel's S0 is below
 * the threshold (opts->mask_s0 as in pc_pictures_write_valid, default 1 % of the S0 scale),
 * the invalid mark the invalid pixels. AoLP has no colour picture: aolp.png of the colour
 * average (pc_stokes_run) shows it. */
PC_API int pc_pictures_write_colour(const char *dir, const struct pc_stokes_out *rgb,
                                    uint32_t width, uint32_t height, const pc_pictures_opts *opts,
                                    const struct pc_validity *valid);
/* Pictures of circular polarization (Stokes with S3: a simulated truth, docs/outputs.md):
 * docp.png, DoCP = |S3|/S0 grey on the range opts->dolp_hi gives the DoLP (> 0: 0..V, 0: 0..1,
 * < 0: automatic), and ellipticity.png, the ellipticity angle χ = ½·atan2(S3, √(S1² + S2²))
 * (radians in the plane, drawn in degrees) on a key from blue (−45°, S3 < 0) through white
 * (linear light) to red (+45°, S3 > 0), ticks every 15°; both with the low-signal hatch of
 * pc_pictures_write_valid (threshold opts->mask_s0, default 1 % of S0's scale opts->s0_hi or
 * its 99.9th percentile). */
PC_API int pc_pictures_write_circular(const char *dir, const pc_fplane *s0, const pc_fplane *docp,
                                      const pc_fplane *ellipticity, uint32_t width, uint32_t height,
                                      const pc_pictures_opts *opts);
/* The same with a title prefix (may be NULL) and the default mask. */
PC_API int pc_pictures_write(const char *dir, const struct pc_stokes_out *st, uint32_t width,
                             uint32_t height, const char *title_prefix);

/* Loads a ground-truth directory for the evaluation protocol (polarcam/eval.h): the analyser
 * images named 0, 45, 90 and 135 with any extension pc_image_read knows (.tif, .tiff, .png,
 * .bmp, .npy). Errors name the directory and the missing or bad file. */
struct pc_eval_truth;
PC_API int pc_truth_load(const char *dir, struct pc_eval_truth *t);
/* The dataset a truth directory belongs to: the name of its parent directory ("lapray-nir"
 * for .../gt/lapray-nir/fabrics), or "." when it has none. */
PC_API void pc_truth_dataset(const char *dir, char *buf, size_t size);

/* One method scored on one truth directory by the protocol (polarcam/eval.h). */
typedef struct pc_eval_result {
	const char *scene; /* the directory as given */
	char dataset[256]; /* pc_truth_dataset */
	pc_demosaic_method method;
	pc_eval_metrics m;
	double seconds; /* of pc_eval_method */
	/* the scene's truth: the pixel-level pattern its analyser images share
	 * (pc_eval_truth_pattern; of the red truth for colour scenes); NaN when not measured */
	pc_eval_pattern truth_pattern;
} pc_eval_result;

/* Scores each method on each truth directory (pc_truth_load, pc_eval_method; opts may be
 * NULL) into res[d·nmeth + k]; progress (may be NULL): phase "eval", results done. Errors name
 * the directory. */
PC_API int pc_eval_dirs(const char *const *dirs, size_t ndirs, const pc_demosaic_method *methods,
                        size_t nmeth, const pc_demosaic_opts *opts, const pc_progress *progress,
                        pc_eval_result *res);

/* The mean metrics of the results of one dataset and method (datasets are never pooled);
 * returns how many results it averaged. */
PC_API int pc_eval_dataset_mean(const pc_eval_result *res, size_t n, const char *dataset,
                                pc_demosaic_method method, pc_eval_metrics *out);

/* The gain of one method over a baseline on one dataset, scene by scene (the results of the
 * same scene path): the mean gain in S0 and DoLP PSNR (dB) and the worst (lowest) with its
 * scene (a pointer into res). */
typedef struct pc_eval_gain {
	double s0_mean, dolp_mean, s0_worst, dolp_worst;
	const char *s0_worst_scene, *dolp_worst_scene;
} pc_eval_gain;

/* Returns how many scenes had both results (0: none, *out zeroed with NaN worsts). */
PC_API int pc_eval_dataset_gain(const pc_eval_result *res, size_t n, const char *dataset,
                                pc_demosaic_method method, pc_demosaic_method baseline,
                                pc_eval_gain *out);

/* Creates a directory (and parents) if missing. */
PC_API int pc_mkdir_p(const char *path);

/* Peak resident set size of this process in MiB (VmHWM of /proc/self/status), or -1 where
 * the system does not say. */
PC_API double pc_peak_rss_mib(void);

#ifdef __cplusplus
}
#endif
#endif
