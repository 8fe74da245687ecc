/* polarcam/stream.h - a source opened the way an application asks for it, and the live
 * source → Stokes stream (what `polarcam capture --process`, `view` and `bench devices` run).
 *
 *   pc_stream_open: URI → source (polarcam/source.h) with the requested format, ROI and
 *   controls, READY with its buffers. An adjusted answer (libcamera's Adjusted) is an error that
 *   shows what the source proposes: requests are never silently changed.
 *
 *   pc_stokes_stream: each dequeued frame → the front door (pc_stokes_run with the black level and
 *   the saturation check; or a calibration, pc_calib_apply) → S0, DoLP, AoLP planes and the
 *   validity mask (sized by the frames), and on demand one picture of three panels
 *   S0 | DoLP | AoLP with the invalid pixels marked.
 */
#ifndef POLARCAM_STREAM_H
#define POLARCAM_STREAM_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/source.h"
#include "polarcam/stokes.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_stream_request {
	const char *uri;
	const char *format; /* a device pixel format by name; NULL: the source's */
	bool roi_set;       /* roi = x, y, width, height on the sensor */
	uint32_t roi[4];
	double exposure_us, gain_db, fps; /* < 0: leave alone */
	unsigned buffers;                 /* 1..64 */
} pc_stream_request;

/* No format, ROI or controls asked for; 8 buffers. */
PC_API void pc_stream_request_init(pc_stream_request *r);

/* Opens r->uri, negotiates the format and ROI, sets the controls, allocates the buffers: the
 * source is READY. Errors name what was refused. */
PC_API int pc_stream_open(const pc_stream_request *r, pc_source **out);

/* JSON objects (compact text, malloc'd; NULL when out of memory) of a format {format, storage,
 * width, height, offset_x, offset_y, stride, sensor_width, sensor_height, polarized, mosaic} and
 * of statistics {completed, failed, dropped, timeouts, underruns, transport_failures,
 * missing_packets, resent_packets (null without packets), bytes}, as reports and meta.json
 * carry them. */
PC_API char *pc_source_format_json(const pc_source_format *f);
PC_API char *pc_source_stats_json(const pc_source_stats *st);

/* ---- live Stokes ---- */

/* The raw's levels and calibration for a live stream (capture --process, view), as
 * pc_process_opts gives them for files (polarcam/process.h). */
typedef struct pc_stream_levels {
	double black_level;      /* DN subtracted; NAN: what the source declares
	                            (pc_source_info.black_level), else 0 */
	double saturation_level; /* DN; 0: the calibration's, else the frames' full scale
	                            (2^bits − 1); < 0: not checked */
	double dead_level;       /* DN; 0: not checked */
	const char *calibration; /* a `polarcam calibrate` file (polarcam/calib.h); NULL: none */
	double noise_gain;       /* the noise-aware methods' noise gain (PC_DMF_NOISE_GAIN, raw
	                          * units); 0: the calibration's system gain at each frame's analog
	                          * gain (pc_calib_noise_gain), else estimated from each frame */
} pc_stream_levels;

/* The defaults: black level from the source, saturation at full scale, no dead level, no
 * calibration. */
PC_API pc_stream_levels pc_stream_levels_default(void);

typedef struct pc_stokes_stream pc_stokes_stream;

PC_API int pc_stokes_stream_new(pc_demosaic_method method, pc_stokes_stream **out);
PC_API void pc_stokes_stream_free(pc_stokes_stream *s);

/* Sets the levels (lv NULL: pc_stream_levels_default) before the first frame: reads the
 * calibration file and checks it against src's format (size, ROI, mosaic, bit depth), so that
 * a mismatch is refused before anything is recorded; src (may be NULL) also gives the declared
 * black level. A black level given with a calibration is refused (the dark map is the black
 * level). */
PC_API int pc_stokes_stream_set_levels(pc_stokes_stream *s, const pc_stream_levels *lv,
                                       pc_source *src);

/* How many frames a source has to declare its black level when it declares none before the
 * first frame (pc_stokes_stream_update_black, pc_capture, pc_viewer_run). */
#define PC_STREAM_BLACK_FRAMES 8

/* After each frame is dequeued and before it is processed, on the thread that dequeues and
 * processes: when set_levels was given no black level and no calibration and src declared none
 * then, the level src declares now is taken (a `libcamera:` camera declares the level its frames
 * report, so only once frames flow, and a pipeline may attach it only from a later frame). Asks
 * src after each of the first PC_STREAM_BLACK_FRAMES frames until a level is taken, then no
 * more: frames before that one are processed with 0, that frame and the later ones with the
 * level. 1 when a level was taken now, else 0; never an error (a source that cannot say keeps
 * none). */
PC_API int pc_stokes_stream_update_black(pc_stokes_stream *s, pc_source *src);

/* A level the caller learnt after set_levels (the level a source declared late, handed with the
 * frame to the thread that processes it, as pc_capture does): taken, for the frames processed
 * from now on, when set_levels was given neither a level nor a calibration and src declared
 * none then. 1 when taken, else 0 (a level is not finite and above 0, or was not open). */
PC_API int pc_stokes_stream_take_black(pc_stokes_stream *s, double black_dn);

/* True when the stream was left to the source's black level, was asked after at least one frame
 * and none came (0 used): a caller says so (polarcam warns). */
PC_API bool pc_stokes_stream_black_missed(const pc_stokes_stream *s);

/* The last frame's validity (mask of the output size, 1 valid; n_invalid) and the black and
 * saturation levels used (0: none), the calibration file (NULL: none). */
PC_API const pc_validity *pc_stokes_stream_validity(const pc_stokes_stream *s);
PC_API void pc_stokes_stream_levels_used(const pc_stokes_stream *s, double *black,
                                         double *saturation, const char **calibration);

/* The noise gain the last frame was processed with (a method flagged PC_DMF_NOISE_GAIN; 0
 * otherwise) and where it came from (from may be NULL): "option" (pc_stream_levels.noise_gain),
 * "calibration" (its system gain), "calibration at the frame's gain" (scaled to the frame's
 * analog gain), "estimated" (from the frame), or NULL for other methods. */
PC_API double pc_stokes_stream_noise_gain(const pc_stokes_stream *s, const char **from);
/* The last frame's analog gain, the calibration's flats' (pc_calib.system_gain_db) and its dark
 * frames' (pc_calib.dark_gain_db), dB; NAN where unknown (no frame yet, no calibration, a
 * source that does not say). Each may be NULL. Where the frame's and the calibration's are
 * known, its noise gain and its dark map's part above the black level are scaled to the frame
 * (pc_calib_noise_gain, pc_calib_dark_scale). */
PC_API void pc_stokes_stream_gains(const pc_stokes_stream *s, double *frame_db,
                                   double *calibration_db, double *dark_db);

/* Runs a frame (which must carry a polarizer mosaic: PC_EFORMAT otherwise) through the
 * pipeline into the stream's S0, DoLP and AoLP planes; sizes follow the frame. */
PC_API int pc_stokes_stream_process(pc_stokes_stream *s, const pc_frame *f);

/* The planes of the last frame (s1, s2 not computed) and their size. */
PC_API const pc_stokes_out *pc_stokes_stream_planes(const pc_stokes_stream *s, uint32_t *width,
                                                    uint32_t *height);
/* Seconds the last pc_stokes_stream_process spent in pc_stokes_from_raw. */
PC_API double pc_stokes_stream_seconds(const pc_stokes_stream *s);

#ifdef __cplusplus
}
#endif
#endif
