/* polarcam/capture.h - a source recorded (what `polarcam capture` does): frames from any URI
 * into a recording (polarcam/recording.h), optionally each through the live Stokes stream
 * (polarcam/stream.h) with the last frame's S0, DoLP, AoLP and pictures in DIR/processed/.
 *
 * Every file is written atomically: when the camera disappears, the stream times out or the
 * caller stops it, the recording keeps every frame written so far and meta.json says
 * complete = false and why.
 */
#ifndef POLARCAM_CAPTURE_H
#define POLARCAM_CAPTURE_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/progress.h"
#include "polarcam/stream.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_capture_opts {
	pc_stream_request stream; /* the source and how to open it */
	uint64_t frames;          /* frames to record */
	const char *dir;          /* the recording */
	bool overwrite;           /* record over an existing recording */
	bool process;             /* every frame through the Stokes stream */
	const char *method;       /* demosaicking method for process; NULL: the mosaic's default
				     (pc_process_method) */
	int timeout_ms;           /* longest wait for a frame */
	pc_progress progress;     /* phase "capture", frames; non-zero stops the recording
				     (PC_ECANCELED, "interrupted after N of M frames") */
	pc_stream_levels levels;  /* black level (recorded in meta.json extra.sensor.offset_dn
				     when known), saturation, calibration for process
				     (polarcam/stream.h; pc_stream_levels_default()) */
} pc_capture_opts;

typedef struct pc_capture_report {
	uint64_t frames;   /* frames recorded */
	int error;         /* 0 when every frame was recorded, else why the recording ended (PC_E*) */
	char message[512]; /* what ended it */
	char *json;        /* {source, dir, frames, requested, seconds, fps, format, stats,
			      process (with process: method, frames, mean_ms, max_ms, last_mean_dolp,
			      width, height), error}: compact text, malloc'd */
} pc_capture_report;

/* Records. A negative return means nothing was recorded (the method, the source or the
 * recording directory was refused; the detail says which); 0 means the recording exists, whole
 * or ended early as rep->error says. Free rep with pc_capture_report_free in both cases. */
PC_API int pc_capture(const pc_capture_opts *opts, pc_capture_report *rep);
PC_API void pc_capture_report_free(pc_capture_report *rep);

#ifdef __cplusplus
}
#endif
#endif
