/* polarcam/gige_server.h - the simulator (or any frame source) as a GigE Vision camera.
 *
 * Runs Aravis's in-process GigE Vision camera (ArvGvFakeCamera) on an interface address with
 * our own image callback and a GenICam description derived at run time from Aravis's built-in
 * one: its PixelFormat enumeration offers the raw formats of a polarization camera
 * (Mono8/10/12/12p/16 and LUCID's PolarizeMono8/12/12p/16 with their vendor codes; for a source
 * with a colour-polarization mosaic, FLIR's BayerRGPolarized8/10p/12p/16 only) and it has
 * ReverseX/ReverseY. Any GigE Vision client can stream from it; the vendor is "polarcam", the
 * model "polarcam-sim" or "polarcam-sim-colour", which is how clients learn the mosaic
 * (polarcam/camera_profile.h): a source whose mosaic at pixel (0,0) is not IMX250MZR's
 * (colour: IMX250MYR's) is refused with PC_ENOTSUP.
 *
 * Frames come from a frame source (normally "sim:SCENE?seed=S") rendered ahead on a producer
 * thread, so the camera keeps its frame rate while the callback only copies (crop for the ROI
 * registers, mirror for ReverseX/Y, pack into the requested pixel format). Each acquisition
 * starts again at the source's frame 0: frame k of an acquisition is source frame k, so a
 * capture is bit-identical to `polarcam render` with the same seed. If rendering falls behind,
 * the callback waits (frames are late, never replaced); `late` counts them.
 *
 * Formats narrower than the sensor's bit depth (Mono8 from a 12-bit sensor) carry the top bits
 * (value >> (bits - 8)), as cameras do.
 *
 * Threads: the server runs Aravis's camera thread and one producer thread of its own.
 * Discovery answers go to the interface's subnet: run it in a network namespace in tests.
 */
#ifndef POLARCAM_GIGE_SERVER_H
#define POLARCAM_GIGE_SERVER_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_gige_server pc_gige_server;

typedef struct pc_gige_server_options {
	const char *address;      /* interface address, default "127.0.0.1" */
	const char *serial;       /* default "POLARCAM0001" */
	const char *source_uri;   /* where frames come from, e.g. "sim:default?seed=1" (required) */
	unsigned ahead;           /* frames rendered ahead (0 = 4) */
	unsigned cycle;           /* 0: acquisition frame k = source frame k. K > 0: render source
	                             frames 0..K-1 once and repeat them (benchmarks of the transport
	                             when rendering cannot keep up) */
	double frame_rate_hz;     /* initial AcquisitionFrameRate (0 = 25) */
	double lost_packet_ratio; /* fault injection: fraction of GVSP packets not sent */
	pc_progress progress;     /* phase "cycle" (frames rendered before serving, cycle > 0);
	                             non-zero stops the start (PC_ECANCELED) */
} pc_gige_server_options;

typedef struct pc_gige_server_stats {
	uint64_t served;       /* frames handed to the camera */
	uint64_t late;         /* of those, frames the callback had to wait for */
	uint64_t acquisitions; /* acquisition starts seen */
	uint64_t rendered;     /* frames produced by the source */
	uint32_t sensor_width, sensor_height;
	unsigned bits;
	char model[32];     /* GigE Vision model name: "polarcam-sim" or "polarcam-sim-colour" */
	char mosaic[40];    /* the served mosaic at sensor pixel (0,0) (pc_mosaic_parse syntax) */
	double black_level; /* DN at `bits` served as the GenICam BlackLevel (with AdcBitDepth):
	                       what the source declares, 0: none */
} pc_gige_server_stats;

/* Starts serving. Errors: PC_ENOTSUP without Aravis, PC_EBUSY when the address cannot be
 * bound, source errors. */
PC_API int pc_gige_server_start(pc_gige_server **out, const pc_gige_server_options *opt);
PC_API void pc_gige_server_get_stats(pc_gige_server *srv, pc_gige_server_stats *st);
/* 0 while healthy; the producer's error code after a failure (the detail message is copied into
 * msg). A server whose source failed keeps answering GVCP but sends no frames. */
PC_API int pc_gige_server_error(pc_gige_server *srv, char *msg, unsigned size);
/* The GenICam XML the camera serves (owned by the server). */
PC_API const char *pc_gige_server_genicam(pc_gige_server *srv);
PC_API void pc_gige_server_stop(pc_gige_server *srv);

/* Process-wide clean-up of the camera library (Aravis's caches), for programs before exit. */
PC_API void pc_devices_shutdown(void);

#ifdef __cplusplus
}
#endif
#endif
