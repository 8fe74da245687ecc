/* polarcam/viewer.h - the live window (what `polarcam view` does): a source's frames through
 * the Stokes stream (polarcam/stream.h), S0 | DoLP | AoLP side by side in a window
 * (polarcam/display.h), with the keys and masks of the files' pictures (pc_pictures_panels,
 * polarcam/io.h) and the frame rate; keys q or Esc quit, s writes view_NNNN.png.
 */
#ifndef POLARCAM_VIEWER_H
#define POLARCAM_VIEWER_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/progress.h"
#include "polarcam/stream.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_viewer_opts {
	pc_stream_request stream; /* the source */
	const char *method;       /* demosaicking method; NULL: the mosaic's default */
	bool window;              /* show a window; without one (headless), frames and screenshot
	                             say what to do */
	uint32_t width;           /* width of the three panels on screen */
	uint64_t frames;          /* stop after this many frames; 0: until q, Esc or stopped */
	const char *screenshot;   /* the last picture shown, as PNG (NULL: none); a name not
	                             ending in .png is refused (PC_EINVAL) */
	int timeout_ms;           /* longest wait for a frame */
	pc_progress progress;     /* phase "view", frames shown; non-zero stops */
	pc_stream_levels levels;  /* black level, saturation (invalid pixels marked), calibration
	                             (polarcam/stream.h; pc_stream_levels_default()) */
	double mask_s0;           /* the panels' low-signal hatch where S0 < mask_s0 (raw units;
	                             0: 1 % of the S0 scale, < 0: none), as pc_pictures_opts */
	double dolp_hi;           /* the panels' DoLP range 0..dolp_hi (0: 0..1, < 0: automatic) */
} pc_viewer_opts;

typedef struct pc_viewer_report {
	uint64_t frames; /* frames shown */
	int error;       /* 0, or what ended the stream early (PC_E*) */
	char message[512];
	unsigned screenshots_failed; /* 's' screenshots that could not be written */
	char warning[256];           /* "" or what the caller should hear (no black level) */
	char *json; /* {source, frames, fps, process_ms, window, black_level, saturation_level,
	               calibration, last_invalid_pixels, warnings [the warning, when there is
	               one], error}: compact, malloc'd */
} pc_viewer_report;

/* Runs the window. A negative return means nothing was shown (method, window or source
 * refused); 0 means it ran, until the end or as rep->error says. Free rep with
 * pc_viewer_report_free. */
PC_API int pc_viewer_run(const pc_viewer_opts *opts, pc_viewer_report *rep);
PC_API void pc_viewer_report_free(pc_viewer_report *rep);

#ifdef __cplusplus
}
#endif
#endif
