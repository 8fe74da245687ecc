/* polarcam/capture.h - a source recorded (what `polarcam capture` does): frames from any URI
 * into a recording (polarcam/recording.h), optionally each through the live Stokes stream
 * (polarcam/stream.h) with S0, DoLP, AoLP of every frame (or of a chosen subset) and pictures
 * of the last one in DIR/processed/ (names: polarcam/folders.h, numbered by frame).
 *
 * The recording is an output folder written as a set (polarcam/io.h, pc_outdir): it is made
 * beside DIR and put in place at the end, replacing an older one only with overwrite.
 *
 * Acquisition and writing are decoupled: the calling thread dequeues each frame, copies it into
 * a bounded queue and gives the buffer back to the source at once; a writer thread of the
 * capture's own writes (and processes) the queued frames. The queue is sized from the frame
 * period and the writer's measured time per frame, within a memory budget (devices/
 * frame_queue.h); a frame that finds it full is lost, counted, and the recording is then not
 * complete. A camera therefore never runs out of buffers because the disk is slow.
 *
 * Frames the source delivers damaged (PC_FRAME_INCOMPLETE or CORRUPT: lost packets) follow the
 * incomplete policy: skip (default: not recorded, counted, the next frame taken; more than
 * frames + 10 of them ends the capture), keep (recorded with their status in meta.json; the
 * recording is then not complete) or fail (the capture ends at the first one).
 *
 * The recording is complete (meta.json "complete": true, rep->error 0) exactly when it holds
 * every frame asked for, each whole, and no frame was lost between the source and the disk.
 * Every file is written atomically: when the camera disappears, the stream times out or the
 * caller stops it (progress), the frames already acquired are written, the recording keeps
 * every frame and meta.json says complete = false and why, with the statistics; with no frame
 * at all, nothing is put in place.
 *
 * Threads: one writer thread per call, joined before pc_capture returns; the progress callback
 * is called from the calling thread only.
 */
#ifndef POLARCAM_CAPTURE_H
#define POLARCAM_CAPTURE_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/progress.h"
#include "polarcam/recording.h"
#include "polarcam/stream.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What happens to a frame the source delivered damaged. */
typedef enum pc_incomplete_policy {
	PC_INCOMPLETE_SKIP = 0, /* not recorded, counted; the next frame is taken */
	PC_INCOMPLETE_KEEP,     /* recorded, flagged "incomplete" in meta.json; not complete */
	PC_INCOMPLETE_FAIL      /* the capture ends (PC_EIO) */
} pc_incomplete_policy;

/* "skip", "keep", "fail"; NULL for anything else. */
PC_API const char *pc_incomplete_policy_name(pc_incomplete_policy p);
/* PC_EINVAL naming the choices for an unknown name. */
PC_API int pc_incomplete_policy_from_name(const char *name, pc_incomplete_policy *out);

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
	pc_progress progress;     /* phase "capture" (frames acquired of those asked), then
	                             "writing" (frames written of those acquired) while the queue
	                             drains; non-zero during "capture" stops the acquisition
	                             (PC_ECANCELED, "interrupted after N of M frames"); the frames
	                             acquired are written all the same */
	pc_incomplete_policy incomplete;
	pc_recording_store store; /* how frames are stored (PNG by default) */
	uint64_t queue_bytes;     /* memory for queued frames; 0: half the available memory, at
	                             most 4 GiB (at least two frames in any case) */
	double write_delay_ms;    /* testing: the writer waits this long after each frame, as a
	                             slow disk would (0: none) */
	pc_stream_levels levels;  /* black level (recorded in meta.json extra.sensor.offset_dn
	                             when known), saturation, calibration for process
	                             (polarcam/stream.h; pc_stream_levels_default()) */
} pc_capture_opts;

typedef struct pc_capture_report {
	uint64_t frames;   /* frames recorded */
	bool complete;     /* what meta.json says: every frame asked for is in, whole */
	uint64_t skipped;  /* incomplete frames not recorded (policy skip) */
	uint64_t kept;     /* incomplete frames recorded (policy keep) */
	uint64_t lost;     /* frames lost because the queue was full */
	int error;         /* 0 when the recording is complete, else why not (PC_E*): PC_ECANCELED
	                      stopped, PC_EIO damaged frames kept or refused, PC_EOVERFLOW frames
	                      lost, or the source's or writer's error */
	char message[512]; /* what ended it */
	char warning[256]; /* "" or what the caller should hear (no black level: see levels) */
	char *json;        /* {source, dir, store, frames, requested, complete, seconds, fps,
	                      format, stats, incomplete {policy, skipped, kept}, queue {frame_bytes,
	                      limit, capacity, needed_max, peak, lost, written, write_ms_mean,
	                      write_ms_max, period_ms}, process (with process: method, frames, kept,
	                      keep_every, mean_ms, max_ms, last_mean_dolp, width, height), warnings [the
	                      warning, when there is one], error}:
	                      compact text, malloc'd */
} pc_capture_report;

/* Records. A negative return means nothing was put in place (the method, the source or the
 * output folder was refused, or no frame came; the detail says which); 0 means the recording
 * exists, whole or ended early as rep->error says. Free rep with pc_capture_report_free in both
 * cases. */
PC_API int pc_capture(const pc_capture_opts *opts, pc_capture_report *rep);
PC_API void pc_capture_report_free(pc_capture_report *rep);

#ifdef __cplusplus
}
#endif
#endif
