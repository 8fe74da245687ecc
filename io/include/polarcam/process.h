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

#ifdef __cplusplus
extern "C" {
#endif

/* A raw mosaic file and how to read it. */
typedef struct pc_raw_input {
	const char *path;
	const pc_raw_geometry *geometry; /* a headerless file's geometry; NULL: a file with one */
	unsigned bits;                   /* significant bits; 0: what the file declares */
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

/* How a raw file is processed. */
typedef struct pc_process_opts {
	pc_mosaic mosaic;
	pc_demosaic_method method;
	pc_demosaic_opts demosaic; /* threads, reference */
} pc_process_opts;

/* What pc_demosaic_file did. */
typedef struct pc_demosaic_file_report {
	uint32_t width, height, channels; /* of the output array (H, W, channels) */
	unsigned bits;                    /* of the raw */
	double seconds;                   /* the demosaicking alone */
} pc_demosaic_file_report;

/* Raw file → analyser images (H, W, 4), or (H, W, 12) for colour-polarization mosaics, float32
 * in the raw's units, written to out_path: NumPy .npy, or a float32 TIFF for .tif/.tiff. rep
 * may be NULL. */
PC_API int pc_demosaic_file(const pc_raw_input *in, const pc_process_opts *o, const char *out_path,
		     pc_demosaic_file_report *rep);

/* Raw file → Stokes folder in dir (pc_stokes_folder_write with files, pictures as given) plus
 * dir/meta.json: input, width, height, bits, layout, method, reference, pipeline_seconds,
 * aolp_convention, files. meta (may be NULL) receives meta.json's content as one compact line
 * (malloc'd). Nothing is written unless the computation succeeded. */
PC_API int pc_process_file(const pc_raw_input *in, const pc_process_opts *o, const char *dir,
		    const pc_stokes_folder_opts *folder, char **meta);

#ifdef __cplusplus
}
#endif
#endif
