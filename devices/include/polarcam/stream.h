/* polarcam/stream.h - a source opened the way an application asks for it, and the live
 * source → Stokes stream (what `polarcam capture --process`, `view` and `bench devices` run).
 *
 *   pc_stream_open: URI → source (polarcam/source.h) with the requested format, ROI and
 *   controls, READY with its buffers. An adjusted answer (libcamera's Adjusted) is an error that
 *   shows what the source proposes: requests are never silently changed.
 *
 *   pc_stokes_stream: each dequeued frame → pc_stokes_from_raw → S0, DoLP, AoLP planes (sized
 *   by the frames), and on demand one picture of three panels S0 | DoLP | AoLP.
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
	const char *format;               /* a device pixel format by name; NULL: the source's */
	bool roi_set;                     /* roi = x, y, width, height on the sensor */
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

typedef struct pc_stokes_stream pc_stokes_stream;

PC_API int pc_stokes_stream_new(pc_demosaic_method method, pc_stokes_stream **out);
PC_API void pc_stokes_stream_free(pc_stokes_stream *s);

/* Runs a frame (which must carry a polarizer mosaic: PC_EFORMAT otherwise) through the
 * pipeline into the stream's S0, DoLP and AoLP planes; sizes follow the frame. */
PC_API int pc_stokes_stream_process(pc_stokes_stream *s, const pc_frame *f);

/* The planes of the last frame (s1, s2 not computed) and their size. */
PC_API const pc_stokes_out *pc_stokes_stream_planes(const pc_stokes_stream *s, uint32_t *width,
					     uint32_t *height);
/* Seconds the last pc_stokes_stream_process spent in pc_stokes_from_raw. */
PC_API double pc_stokes_stream_seconds(const pc_stokes_stream *s);

/* Draws S0 (grey, 0 to the 99.9th percentile), DoLP (grey, 0..1) and AoLP (hue = AoLP,
 * value = DoLP) of the last frame side by side: *rgb is (3·width) × height RGB8 with the stride
 * 9·width bytes, owned by the stream (valid until the next process). */
PC_API int pc_stokes_stream_picture(pc_stokes_stream *s, const uint8_t **rgb);

#ifdef __cplusplus
}
#endif
#endif
