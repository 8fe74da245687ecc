/* polarcam/render_recording.h - a scene rendered into a recording with its ground truth (what
 * `polarcam render` does; the building block of dataset generation).
 *
 *   scene ──pc_sim_new──► simulator ──pc_sim_prepare (each generator state once, with truth)
 *         ──pc_sim_frame (frame N from (seed, N))──► pc_recording_add ──► DIR
 *
 * DIR receives raw_NNNNNN.png (.npy, .raw: opts.store) and meta.json (polarcam/recording.h; "extra"
 * holds pc_sim_describe_json plus "timings" and "first_frame"), truth_stokes.npy (H, W, 4) float32
 * — (H, W, 3, 4) for colour sensors, truth_stokes_psgNN.npy per generator state of a sequence —,
 * truth_mueller.npy (H, W, 4, 4) (or (H, W, 3, 4, 4)) when the scene declares "mueller", and
 * states.json (polarcam/states.h) for state sequences. DIR is an output folder written as a set
 * (polarcam/io.h, pc_outdir): refused (PC_EEXIST) when it exists and is not empty unless
 * overwrite, and put in place whole only when every file is written; a failure leaves nothing
 * of the new run and an older DIR as it was.
 */
#ifndef POLARCAM_RENDER_RECORDING_H
#define POLARCAM_RENDER_RECORDING_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/io.h"
#include "polarcam/progress.h"
#include "polarcam/recording.h"
#include "polarcam/sim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_render_opts {
	const char *scene_path;   /* the scene file; NULL: the built-in default scene */
	const pc_scene *scene;    /* or a scene already loaded (then scene_path only names it) */
	pc_sim_options sim;       /* seed, threads, ROI, pixel format */
	uint64_t frames;          /* frames to write; 0: one cycle of the scene's states */
	uint64_t first;           /* number of the first frame */
	bool truth;               /* write truth_*.npy */
	bool overwrite;           /* replace an existing output folder (polarcam/io.h's rule) */
	pc_progress progress;     /* phases "render" (rows of each state), "frames"; non-zero stops
	                             (PC_ECANCELED) after the state or frame in hand, the recording
	                             finished with complete = false and its timings */
	pc_recording_store store; /* how frames are stored (PNG by default) */
} pc_render_opts;

typedef struct pc_render_report {
	uint64_t frames; /* frames in the recording (also when the call failed or was stopped) */
	uint32_t width, height;
	char *timings; /* {render_s, frames_s, per_frame_s, write_s, total_s, peak_rss_mib}: JSON
	                  text, malloc'd (free it) */
} pc_render_report;

/* Ground truth as recordings and datasets store it, one .npy at path: Stokes radiance (H, W, 4)
 * — (H, W, 3, 4) for colour sensors — or, when mueller, Mueller matrices (H, W, 4, 4) — (H, W,
 * 3, 4, 4) —, in the layout pc_sim_prepare fills. dtype PC_DT_F32 writes the values as they are,
 * PC_DT_F16 rounds them to binary16 (pc_f32_to_f16). Atomic (pc_npy_write); errors name path. */
PC_API int pc_truth_write(const char *path, const pc_sim_info *in, const float *values,
                          bool mueller, pc_dtype dtype);

/* Renders into dir (created with its parents), an output folder written as a set (polarcam/io.h,
 * pc_outdir). rep may be NULL. PC_ECANCELED when the progress callback asked to stop: the frames
 * written so far are put in place, meta.json says complete = false, "interrupted after N of M
 * frames", with the timings (nothing is put in place when no frame was written). */
PC_API int pc_render_recording(const char *dir, const pc_render_opts *opts, pc_render_report *rep);

#ifdef __cplusplus
}
#endif
#endif
