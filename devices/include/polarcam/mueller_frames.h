/* polarcam/mueller_frames.h - Mueller imaging of frame sequences where they are: a recording,
 * raw files, or a frame source streaming them (what `polarcam mueller` does).
 *
 *   frames ──pc_mueller_run_add (demosaic, − black, accumulate)──► pc_mueller_run_finish
 *          ──► M = A⁺·I·G⁺ per pixel, Lu–Chipman D, R, Δ (polarcam/mueller_imaging.h)
 *
 * The states come from a states.json (polarcam/states.h) or, for a source, from the caller.
 * Write the result with pc_mueller_folder_write (polarcam/folders.h).
 */
#ifndef POLARCAM_MUELLER_FRAMES_H
#define POLARCAM_MUELLER_FRAMES_H

#include <stddef.h>

#include "polarcam/export.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/progress.h"
#include "polarcam/sim.h"
#include "polarcam/source.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_mueller_request {
	const char *states_path; /* states.json; NULL: RECORDING/states.json (recordings only) */
	const char *layout;      /* the frames' mosaic; NULL: the states file's, else IMX250MZR */
	pc_mueller_run_opts run; /* method, threads, rebuild; run.black_level NaN: the
	                            recording's black level (pc_recording_black_level), else 0 */
	pc_progress progress;    /* phase "mueller", frames */
} pc_mueller_request;

/* What a call used. */
typedef struct pc_mueller_used {
	double black_level;
	size_t frames_given; /* frames available (a recording's, the files given) */
	size_t frames_used;  /* one cycle of the states: the first n_psg·n_psa */
	char layout[64];     /* the mosaic */
} pc_mueller_used;

/* The frames of a recording directory, in recording order. */
PC_API int pc_mueller_from_recording(const char *dir, const pc_mueller_request *rq,
                                     pc_mueller_result *res, pc_mueller_used *used);

/* Raw mosaic files (PNG, TIFF, .npy, BMP: pc_image_read_mosaic) in sequence order;
 * rq->states_path is required. */
PC_API int pc_mueller_from_files(const char *const *files, size_t n, const pc_mueller_request *rq,
                                 pc_mueller_result *res, pc_mueller_used *used);

/* n_psg·n_psa frames dequeued from a streaming source (frame j is the j-th dequeued: a gap in
 * the sequence numbers is an error, PC_EIO, since a lost frame breaks the states' order), under
 * the states st. The mosaic is the frames' own unless rq->layout is given. */
PC_API int pc_mueller_from_source(pc_source *src, const pc_sim_states *st, int timeout_ms,
                                  const pc_mueller_request *rq, pc_mueller_result *res,
                                  pc_mueller_used *used);

#ifdef __cplusplus
}
#endif
#endif
