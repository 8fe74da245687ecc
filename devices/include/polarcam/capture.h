/* polarcam/capture.h - a source recorded (what `polarcam capture` does): frames from any URI
 * into a recording (polarcam/recording.h), optionally each through the live Stokes stream
 * (polarcam/stream.h) with S0, DoLP, AoLP of every frame (or of a chosen subset) and pictures
 * of the last one in DIR/processed/ (names: polarcam/folders.h, numbered by frame).
 *
 * The recording is an output folder written as a set (polarcam/io.h, pc_outdir): it is made
 * beside DIR and put in place at the end, replacing an older one only with overwrite. When the
 * camera disappears, the stream times out or the caller stops it, the recording keeps every
 * frame written so far and meta.json says complete = false and why; with no frame at all,
 * nothing is put in place.
 */
#ifndef POLARCAM_CAPTURE_H
#define POLARCAM_CAPTURE_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/progress.h"
#include "polarcam/stream.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_capture_opts {
	pc_stream_request stream; /* the source and how to open it */
	uint64_t frames;          /* frames to record */
	const char *dir;          /* the recording */
	bool overwrite;           /* replace an existing output folder (polarcam/io.h's rule) */
	bool process;             /* every frame through the Stokes stream */
	const char *method;       /* demosaicking method for process; NULL: the mosaic's default
				     (pc_process_method) */
	uint64_t keep_every;      /* with process: DIR/processed/ keeps s0_NNNNNN.npy,
				     dolp_NNNNNN.npy, aolp_NNNNNN.npy of the frames at positions
				     0, k, 2k, ... and of the last; 0: of the last frame only */
	int timeout_ms;           /* longest wait for a frame */
	pc_progress progress;     /* phase "capture", frames; non-zero stops the recording
				     (PC_ECANCELED, "interrupted after N of M frames") */
} pc_capture_opts;

typedef struct pc_capture_report {
	uint64_t frames;   /* frames recorded */
	int error;         /* 0 when every frame was recorded, else why the recording ended (PC_E*) */
	char message[512]; /* what ended it */
	char *json;        /* {source, dir, frames, requested, seconds, fps, format, stats,
			      process (with process: method, frames, kept, keep_every, mean_ms,
			      max_ms, last_mean_dolp, width, height), error}: compact text,
			      malloc'd */
} pc_capture_report;

/* Records. A negative return means nothing was put in place (the method, the source or the
 * output folder was refused, or no frame came; the detail says which); 0 means the recording
 * exists, whole or ended early as rep->error says. Free rep with pc_capture_report_free in both
 * cases. */
int pc_capture(const pc_capture_opts *opts, pc_capture_report *rep);
void pc_capture_report_free(pc_capture_report *rep);

#ifdef __cplusplus
}
#endif
#endif
