/* polarcam/source.h - the one frame-source API.
 *
 * Every camera, the simulator and recordings are frame sources named by a URI:
 *
 *   sim:SCENE[?opts]          the simulator (SCENE = a scene file or "default"), paced, can
 *                             misbehave on demand (dropped frames, timeouts, disconnect, padded
 *                             strides, odd ROI offsets)
 *   file:DIR                  a recording (raw_NNNNNN.png + metadata, as render/capture write)
 *   aravis:ID                 GigE Vision / USB3 Vision through Aravis (ID = device id, serial
 *                             or IP address)
 *   v4l2:/dev/videoN          a V4L2 capture node (mmap streaming)
 *   libcamera:ID              a libcamera camera
 *
 * Backend options follow '?' as key=value pairs separated by '&' ("sim:default?fps=30&seed=2");
 * an option a backend does not know is an error naming it.
 *
 * Life of a source (state machine, checked by the public wrappers on every call; a call in the
 * wrong state fails with PC_ESTATE and says which state it needs):
 *
 *      pc_source_open ──► OPEN ◄──────────────┐  try/set format, controls
 *                          │ buffers_alloc     │ buffers_free
 *                          ▼                   │
 *                        READY ────────────────┘  format fixed, controls
 *                          │ start   ▲ stop
 *                          ▼         │
 *                       STREAMING ───┘            dequeue / requeue, live controls
 *                          │ device lost (PC_EDISCONNECTED from any call)
 *                          ▼
 *                        FAILED                   stop, stats, buffers_free, close only
 *
 * Buffers: the application chooses how many buffers a source fills (pc_source_buffers_alloc)
 * and owns the pool, as in Aravis's ArvStream: a dequeued buffer belongs to the application
 * until it requeues it; every other buffer is queued to the source. A backend may provide the
 * memory (V4L2 mmap) but never the pool semantics. pc_source_stop returns every queued buffer
 * to the pool; they are filled again after the next start.
 *
 * Frames arrive as pc_frame: a view into the buffer memory, metadata (sequence strictly
 * increasing, timestamp_ns non-decreasing, both checked by the wrapper) and the polarizer mosaic
 * already shifted for the ROI origin (and for ReverseX/Y where the camera has them).
 *
 * Threads: a source is used from one thread at a time. The library starts no threads of its own
 * for sim: and file:; camera backends run their transport's threads (Aravis's stream thread).
 */
#ifndef POLARCAM_SOURCE_H
#define POLARCAM_SOURCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/format.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_source pc_source;

typedef enum pc_source_state {
	PC_SOURCE_OPEN = 0,  /* opened; format negotiable; no buffers */
	PC_SOURCE_READY,     /* buffers allocated; format fixed */
	PC_SOURCE_STREAMING, /* started: dequeue / requeue */
	PC_SOURCE_FAILED,    /* the device is gone or broke: stop, stats, buffers_free, close */
	PC_SOURCE_CLOSED     /* only seen by backends during close */
} pc_source_state;

PC_API const char *pc_source_state_name(pc_source_state s);

/* ---- format negotiation (libcamera's Valid / Adjusted / Invalid) ---- */

typedef enum pc_format_verdict {
	PC_FORMAT_VALID = 0, /* the request is possible exactly as asked */
	PC_FORMAT_ADJUSTED,  /* possible after changes, written back into the request */
	PC_FORMAT_INVALID    /* nothing close is possible; the detail message says why */
} pc_format_verdict;

PC_API const char *pc_format_verdict_name(pc_format_verdict v);

/* What a source delivers. In a request, zero fields mean "the source's choice" (format
 * PC_FMT_INVALID, width/height 0 = the whole sensor from the offset, stride 0 = the source's
 * natural stride) and filling them in does not count as an adjustment. An all-zero request
 * asks for the source's default format, which may have an ROI of its own. */
typedef struct pc_source_format {
	pc_pixfmt format;            /* storage format of the pixels */
	char format_name[48];        /* the device's own name ("PolarizeMono12p", "Y16 ", "Mono8");
	                                in a request: ask for a device format by name ("" = any) */
	uint32_t width, height;      /* ROI size in pixels */
	uint32_t offset_x, offset_y; /* ROI origin on the full sensor */
	size_t stride;               /* bytes between rows (>= the format's row bytes) */
	/* outputs only (ignored in a request): */
	size_t frame_bytes; /* bytes a buffer must hold: stride * (height - 1) + row bytes
	                       at least; backends may ask for more (trailers) */
	bool polarized;     /* the pixels lie under a polarizer mosaic */
	pc_mosaic mosaic;   /* mosaic phase of pixel (0,0) of the ROI */
	uint32_t sensor_width, sensor_height; /* full sensor */
} pc_source_format;

/* ---- controls ---- */

typedef enum pc_control_id {
	PC_CTRL_EXPOSURE_US = 0,
	PC_CTRL_GAIN_DB,
	PC_CTRL_FRAME_RATE_HZ,
	PC_CTRL_COUNT
} pc_control_id;

PC_API const char *
pc_control_name(pc_control_id id); /* "exposure_us", "gain_db", "frame_rate_hz" */

typedef struct pc_control_info {
	double min, max; /* inclusive range */
	double step;     /* 0 = continuous */
	double def;      /* default */
	bool live;       /* may change while streaming */
} pc_control_info;

/* ---- statistics ---- */

typedef struct pc_source_stats {
	/* counted by the wrappers, the same for every source: */
	uint64_t completed; /* frames dequeued with status PC_FRAME_OK (or only SIMULATED) */
	uint64_t failed;    /* frames dequeued flagged INCOMPLETE or CORRUPT */
	uint64_t dropped;   /* frames the source produced but never delivered: gaps in sequence */
	uint64_t timeouts;  /* dequeue calls that timed out */
	/* reported by the backend where its transport knows them: */
	uint64_t underruns;          /* frames lost because no buffer was queued */
	uint64_t transport_failures; /* frames the transport discarded before delivery */
	bool has_packets;            /* packet counters below are meaningful (GigE Vision) */
	uint64_t missing_packets;
	uint64_t resent_packets;
	uint64_t bytes; /* payload bytes of completed frames */
} pc_source_stats;

/* ---- what a source is ---- */

typedef struct pc_source_info {
	char scheme[16]; /* "sim", "aravis", ... */
	char id[128];    /* what follows the scheme in the URI (without options) */
	char vendor[64], model[64], serial[64];
	char driver[64]; /* backend / transport ("aravis-gv", "vivid", "polarcam-sim") */
	uint32_t sensor_width, sensor_height;
	bool polarized;     /* has a polarizer mosaic (from the profile table or the device) */
	pc_mosaic mosaic;   /* full-sensor mosaic (phase at sensor pixel 0,0) */
	double black_level; /* DN the source declares (the simulator's sensor offset, a recording's
	                       meta.json); 0: not declared (cameras: give --black-level) */
	bool black_level_late; /* the level comes with the frames (a libcamera camera's
	                          SensorBlackLevels metadata): 0 until frames flow, so capture
	                          and view ask again after the first frames */
} pc_source_info;

/* ---- buffers ---- */

typedef enum pc_buffer_state {
	PC_BUFFER_QUEUED = 0, /* the source's to fill (while streaming) or waiting for start */
	PC_BUFFER_DEQUEUED    /* the application's, frame valid until requeued */
} pc_buffer_state;

typedef struct pc_buffer {
	pc_frame frame;        /* filled when dequeued; view.data points into data */
	void *data;            /* memory of the buffer (owned by the pool or by the backend) */
	size_t size;           /* bytes */
	unsigned index;        /* position in the pool, 0..count-1 */
	void *user;            /* free for the application */
	void *backend;         /* backend's per-buffer state (an ArvBuffer, a V4L2 index...) */
	pc_buffer_state state; /* maintained by the wrappers; read only */
} pc_buffer;

/* ---- the public API ---- */

/* Opens a source by URI. Errors: PC_EINVAL (malformed URI, unknown option), PC_EUNAVAIL (scheme
 * known but not built in, the detail says which package is missing; or no such device for a
 * device backend, one with an enumerate function), PC_ENOENT (no such scene / directory),
 * others from the backend. */
PC_API int pc_source_open(pc_source **out, const char *uri);
/* Stops if streaming, frees the buffers and closes. NULL is fine. */
PC_API void pc_source_close(pc_source *s);

PC_API pc_source_state pc_source_get_state(const pc_source *s);
PC_API int pc_source_get_info(pc_source *s, pc_source_info *info);

/* The current format (valid in every state but CLOSED). */
PC_API int pc_source_get_format(pc_source *s, pc_source_format *fmt);
/* Checks a request without applying it: *fmt is completed or adjusted in place and *verdict
 * says which. Returns 0 whenever a verdict was reached (also PC_FORMAT_INVALID, with a detail
 * message), a negative error for bad arguments, wrong state or a failing device. OPEN only. */
PC_API int pc_source_try_format(pc_source *s, pc_source_format *fmt, pc_format_verdict *verdict);
/* Applies a format. The request must be exactly valid (negotiate with try_format first); an
 * adjustable request fails with PC_EFORMAT and changes nothing. OPEN only. */
PC_API int pc_source_set_format(pc_source *s, const pc_source_format *fmt);

PC_API int pc_source_control_query(pc_source *s, pc_control_id id, pc_control_info *info);
PC_API int pc_source_control_get(pc_source *s, pc_control_id id, double *value);
/* Sets a control. Outside [min, max] is PC_ERANGE (never clamped silently); the value applied
 * after rounding to the device's step is written to *applied (may be NULL). While streaming
 * only live controls may change (else PC_ESTATE). */
PC_API int pc_source_control_set(pc_source *s, pc_control_id id, double value, double *applied);

/* Creates the pool of count buffers (1..64) for the current format: OPEN -> READY. */
PC_API int pc_source_buffers_alloc(pc_source *s, unsigned count);
/* Frees the pool (every buffer must have been requeued): READY/FAILED -> OPEN. */
PC_API int pc_source_buffers_free(pc_source *s);
PC_API unsigned pc_source_buffer_count(const pc_source *s);

/* READY -> STREAMING: every queued buffer is handed to the source. */
PC_API int pc_source_start(pc_source *s);
/* Pops the next filled buffer, waiting at most timeout_ms (< 0: forever). PC_ETIMEDOUT when
 * nothing came, PC_EDISCONNECTED when the device is gone (the source is then FAILED); a
 * frame the transport delivered damaged is returned (0) with INCOMPLETE/CORRUPT status flags.
 * The wrapper validates every frame against the negotiated format (PC_EIO otherwise). */
PC_API int pc_source_dequeue(pc_source *s, int timeout_ms, pc_buffer **buf);
/* Pushes a dequeued buffer back into the pool (to the source when streaming). */
PC_API int pc_source_requeue(pc_source *s, pc_buffer *buf);
/* STREAMING/FAILED -> READY (FAILED stays FAILED): every buffer the application does not
 * hold is back in the pool when it returns. */
PC_API int pc_source_stop(pc_source *s);

PC_API int pc_source_get_stats(pc_source *s, pc_source_stats *st);

/* ---- the registry ---- */

/* Devices a backend finds (for `polarcam devices`). */
typedef struct pc_device_entry {
	char uri[256]; /* openable URI ("aravis:PolSim-SIM0001") */
	char vendor[64], model[64], serial[64];
	char transport[32]; /* "GigE Vision", "USB3 Vision", "V4L2", "libcamera" */
	char address[64];   /* IP address, bus path or device node */
	char note[256];     /* diagnosis when the device is not usable, else "" */
	bool usable;
	char formats[256];      /* pixel formats offered that polarcam reads, space-separated
	                           ("GREY Y10 Y12 Y16"), "" when the backend does not list them */
	unsigned formats_total; /* formats the device offers in all (0 = not listed) */
} pc_device_entry;

typedef int (*pc_device_fn)(void *ctx, const pc_device_entry *dev);

/* pc_source_backend.enumerate flags */
enum { PC_ENUM_NETWORK = 1u << 0 };

typedef struct pc_source_ops pc_source_ops;

typedef struct pc_source_backend {
	const char *scheme;       /* "sim" */
	const char *summary;      /* one line for --help */
	const char *uri_help;     /* "sim:SCENE[?fps=F&seed=S&...]" and the options */
	const pc_source_ops *ops; /* NULL when not built in */
	const char *missing;      /* why not built in ("Aravis was not found at configure time") */
	/* Lists devices (may be NULL). Network discovery (GigE Vision broadcasts on every
	 * interface) only with PC_ENUM_NETWORK in flags: callers ask for it explicitly, tests run
	 * it in a network namespace. Returns 0 or an error; fn returning non-zero stops. */
	int (*enumerate)(unsigned flags, pc_device_fn fn, void *ctx);
} pc_source_backend;

/* The backends, built in or not, in a fixed order; NULL after the last. */
PC_API const pc_source_backend *pc_source_backend_get(unsigned index);
PC_API const pc_source_backend *pc_source_backend_find(const char *scheme);

/* ---- writing a backend (used by devices/ and by tests that model broken backends) ----
 *
 * The wrappers check state and arguments, then call these. A NULL op means the operation is
 * not supported: the wrapper returns PC_ENOTSUP without calling anything. Ops return 0 or a
 * negative PC_E* code with a detail message; PC_EDISCONNECTED from any op moves the source to
 * FAILED. */
struct pc_source_ops {
	/* arg: the URI after "scheme:" without options; read options with pc_source_option*. */
	int (*open)(pc_source *s, const char *arg);
	void (*close)(pc_source *s);
	int (*get_info)(pc_source *s, pc_source_info *info);
	/* Complete or adjust *fmt (all output fields filled) and give a verdict. */
	int (*try_format)(pc_source *s, pc_source_format *fmt, pc_format_verdict *verdict);
	/* Apply a format try_format found valid. */
	int (*set_format)(pc_source *s, const pc_source_format *fmt);
	int (*control_query)(pc_source *s, pc_control_id id, pc_control_info *info);
	int (*control_get)(pc_source *s, pc_control_id id, double *value);
	int (*control_set)(pc_source *s, pc_control_id id, double value, double *applied);
	/* Optional: provide memory for the pool (set data/size of each buffer, may fail); without
	 * it the wrapper allocates frame_bytes per buffer (64-byte aligned). */
	int (*buffers_alloc)(pc_source *s, pc_buffer **bufs, unsigned count);
	void (*buffers_free)(pc_source *s, pc_buffer **bufs, unsigned count);
	/* Hand one buffer to the source (before start and on requeue while streaming). */
	int (*queue)(pc_source *s, pc_buffer *buf);
	int (*start)(pc_source *s);
	/* Return a filled buffer that was queued to the backend: frame.view (format, size, stride
	 * of the negotiated format, data inside the buffer), frame.meta sequence/timestamp/
	 * exposure/gain/status. The wrapper sets frame.mosaic and the ROI offsets. */
	int (*dequeue)(pc_source *s, int timeout_ms, pc_buffer **buf);
	/* Stop streaming and forget every queued buffer. Must not fail to release buffers. */
	int (*stop)(pc_source *s);
	/* Fill the backend's counters (underruns, transport_failures, packets). */
	int (*get_stats)(pc_source *s, pc_source_stats *st);
	const char *const *options; /* option names the backend accepts, NULL-terminated */
};

/* Opens a source with explicit ops (as the registry does for a scheme). */
PC_API int pc_source_open_ops(pc_source **out, const pc_source_ops *ops, const char *scheme,
                              const char *arg_with_options);

/* Backend helpers. */
PC_API void *pc_source_priv(pc_source *s);
PC_API void pc_source_set_priv(pc_source *s, void *priv);
/* The current (applied) format, for backends. */
PC_API const pc_source_format *pc_source_current_format(const pc_source *s);
/* An option's value as given, or NULL when absent. Marks it as read. */
PC_API const char *pc_source_option(pc_source *s, const char *key);
/* Typed options: 0 and *out untouched when absent; PC_EINVAL naming the URI option when
 * malformed or outside [min, max]. */
PC_API int pc_source_option_double(pc_source *s, const char *key, double min, double max,
                                   double *out);
PC_API int pc_source_option_u64(pc_source *s, const char *key, uint64_t min, uint64_t max,
                                uint64_t *out);
PC_API int pc_source_option_bool(pc_source *s, const char *key, bool *out);

/* Fills the output fields of a request from the format table: frame_bytes from stride and
 * height, the mosaic shifted by the ROI offset from the full-sensor mosaic. Checks that stride
 * holds a row. For backends. */
PC_API int pc_source_format_complete(pc_source_format *fmt, const pc_mosaic *sensor_mosaic);

#ifdef __cplusplus
}
#endif
#endif
