/* polarcam/process.h - raw mosaic files through the pipeline: what `polarcam demosaic` and
 * `polarcam process` do, as library calls.
 *
 *   raw file ──pc_raw_read──► view ──pc_demosaic──► analyser images ──► OUT.npy / OUT.tif
 *                                  └─pc_stokes_from_raw─► S0, S1, S2, DoLP, AoLP ──► Stokes folder
 *                                                                     (polarcam/folders.h)
 */
#ifndef POLARCAM_PROCESS_H
#define POLARCAM_PROCESS_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/folders.h"
#include "polarcam/io.h"
#include "polarcam/mosaic.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A raw mosaic file and how to read it. */
typedef struct pc_raw_input {
	const char *path;
	const pc_raw_geometry *geometry; /* a headerless file's geometry; NULL: a file with one */
	unsigned bits;                   /* significant bits; 0: what the file declares */
	const pc_frame_meta *meta; /* the frame's metadata (a recording's exposure and analog gain:
	                            * a calibration's noise gain follows the gain); NULL: unknown */
} pc_raw_input;

/* Reads and validates a raw mosaic (pc_image_read_mosaic: bit depth, every value, NaN) into an
 * owned view, and checks it holds whole 2×2 analyser blocks (even width and height, at least 4);
 * bits (may be NULL) receives the bit depth. Errors name the file. */
PC_API int pc_raw_read(const pc_raw_input *in, pc_view *raw, unsigned *bits);

/* The demosaicking method for frames with mosaic m: the one named (NULL: bilinear for
 * monochrome mosaics, bayer-first for colour-polarization ones). PC_EINVAL (the detail names
 * --method, the mosaic and the methods that would work) for an unknown name or a method for the
 * other kind of mosaic. */
PC_API int pc_process_method(const char *name, const pc_mosaic *m, pc_demosaic_method *out);

/* A stage run in place of the front door (pc_stokes_run / pc_demosaic_run): a calibration,
 * made by pc_calib_stage (polarcam/calib.h) from a `polarcam calibrate` file. run computes the
 * Stokes outputs st, or when st is NULL the analyser images ch, of frame f (its view, its ROI
 * origin in meta.offset_x/y, its mosaic; bits the raw's bit depth) with o's method, threads,
 * reference, saturation and dead levels (o->black_level is 0: the stage has its own), and fills
 * valid (which may be NULL). It refuses frames that do not match it, naming the mismatch. */
typedef struct pc_raw_stage {
	int (*run)(void *user, const pc_frame *f, unsigned bits, const pc_pipeline_opts *o,
	           const pc_stokes_out *st, const pc_fplane *ch, pc_validity *valid);
	void *user;
	const char *name;        /* for meta.json ("calibration") */
	double saturation_level; /* the stage's default saturation level (raw units; 0: none) */
	double noise_gain; /* the noise gain the stage applies when none is given (a calibration's
	                    * system gain, pc_calib.system_gain; 0: none) */
} pc_raw_stage;

/* How a raw file is processed. */
typedef struct pc_process_opts {
	pc_mosaic mosaic;
	pc_demosaic_method method;
	pc_demosaic_opts demosaic; /* threads, reference */
	bool overwrite;            /* replace an existing output (polarcam/io.h's rule) */
	/* the raw's levels (pc_pipeline_opts, polarcam/demosaic.h), raw units */
	double black_level;        /* subtracted from every sample; 0: none */
	double saturation_level;   /* samples >= it are saturated; 0: the stage's level, else the
	                            * raw's full scale (2^bits − 1 for integer raws, none for float32
	                            * ones); < 0: not checked */
	double dead_level;         /* samples <= it are dead; 0: not checked */
	uint32_t roi_x, roi_y;     /* the frame's ROI origin on the sensor (for stage checks) */
	const pc_raw_stage *stage; /* NULL: the front door with the levels above */
	double noise_gain;         /* pc_pipeline_opts.noise_gain (0: the stage's, else estimated
	                            * from each frame) */
} pc_process_opts;

/* The saturation level that pc_process_file and pc_demosaic_file check for o and a raw of the
 * given format and bit depth (0: none). */
PC_API double pc_process_saturation(const pc_process_opts *o, pc_pixfmt format, unsigned bits);

/* What pc_demosaic_file did. */
typedef struct pc_demosaic_file_report {
	uint32_t width, height, channels; /* of the output array (H, W, channels) */
	unsigned bits;                    /* of the raw */
	double seconds;                   /* the demosaicking alone */
	double saturation_level;          /* checked (0: none) */
	uint64_t n_invalid;               /* output pixels depending on a saturated/dead sample */
	char valid_path[4096];            /* the mask written ("" when no level was checked) */
	/* a method flagged PC_DMF_NOISE_GAIN (polarcam/demosaic.h): the noise gain it used (raw
	 * units), as the pipeline returns it (pc_pipeline_opts.noise_gain_used): o->noise_gain
	 * when given (noise_gain_given), else its estimate from the frame (pc_demosaic_noise_gain's
	 * value, made once); other methods: 0 and false */
	double noise_gain;
	bool noise_gain_given;
} pc_demosaic_file_report;

/* Raw file → analyser images (H, W, 4), or (H, W, 12) for colour-polarization mosaics, float32
 * in the raw's units above the black level (o->black_level, or the stage's calibration),
 * written to out_path: NumPy .npy, or a float32 TIFF for .tif/.tiff. When a saturation or dead
 * level is checked, the validity mask goes beside it as OUT_valid.npy (uint8 (H, W), 1 valid).
 * The output and its mask are one set: an existing one of them is refused (PC_EEXIST) unless
 * o->overwrite, both are written to temporaries and put in place only when both are complete.
 * rep may be NULL. */
PC_API int pc_demosaic_file(const pc_raw_input *in, const pc_process_opts *o, const char *out_path,
                            pc_demosaic_file_report *rep);

/* Raw file → Stokes folder in dir (pc_stokes_folder_write_valid with files, pictures as given;
 * valid.npy when a level is checked) plus dir/meta.json: input, width, height, bits, layout,
 * method, reference, black_level, saturation_level, dead_level, invalid_pixels, calibration,
 * pipeline_seconds, aolp_convention, files, valid_statistics (pixels, s0_mean, dolp_mean over
 * the valid pixels only). meta (may be NULL) receives meta.json's content as one compact line
 * (malloc'd). dir is an output folder written as a set (polarcam/io.h, pc_outdir): an existing
 * one is refused (PC_EEXIST) unless o->overwrite, and nothing is put in place unless every file
 * (valid.npy among them) was written. */
PC_API int pc_process_file(const pc_raw_input *in, const pc_process_opts *o, const char *dir,
                           const pc_stokes_folder_opts *folder, char **meta);

/* Several raw files through the pipeline into one Stokes folder (what `polarcam process` does
 * with several files; a recording's frames: pc_process_recording, polarcam/process_recording.h).
 * Frame k (of number numbers[k]) gives stokes_NNNNNN.npy, dolp_NNNNNN.npy, ... (the files
 * folder->files asks for, named as in polarcam/folders.h), or with stack one array per quantity
 * holding every frame in order: stokes.npy (N, H, W, 3), s0.npy, dolp.npy, aolp.npy (N, H, W).
 * Pictures (s0_NNNNNN.png, ...) of the frames at positions 0, pictures_every, 2·pictures_every,
 * ... when folder->files has PC_SF_PICTURES (0: none). Every input must have the size and bit
 * depth of the first. meta.json adds to pc_process_file's fields (input and pipeline_seconds
 * apart) frames [{input, number, pipeline_seconds, pictures}], stack, pictures_every and the
 * total pipeline_seconds, invalid_pixels summed over the frames (per frame in frames[]); "files"
 * names the per-frame files with NNNNNN. With a level checked each frame's mask is
 * valid_NNNNNN.npy, or with stack one valid.npy (N, H, W) uint8. dir is written as a
 * set (polarcam/io.h, pc_outdir), so a failure or a stop part-way leaves nothing. */
typedef struct pc_process_batch {
	const pc_raw_input *inputs;
	size_t count;
	const uint64_t *numbers; /* the frame number naming each input's outputs; NULL: 0, 1, ... */
	bool stack;              /* one array per quantity instead of files per frame */
	uint64_t pictures_every; /* see above */
	pc_progress progress;    /* phase "process", frames done; a non-zero return stops
	                            (PC_ECANCELED) */
} pc_process_batch;

PC_API int pc_process_files(const pc_process_batch *b, const pc_process_opts *o, const char *dir,
                            const pc_stokes_folder_opts *folder, char **meta);

#ifdef __cplusplus
}
#endif
#endif
