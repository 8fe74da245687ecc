/* polarcam/v4l2.h - Video4Linux2 video nodes.
 *
 * The low-level layer under the `v4l2:/dev/videoN` frame source: one open video node used in
 * one direction (capture or output), single-planar memory-mapped streaming, format negotiation
 * that honours the driver's bytesperline, controls found by id or by name, inputs/outputs and
 * DV timings (what HDMI receivers and vivid's loopback need), and the node listing behind
 * `polarcam devices`. Pixel formats come from the one table in core/format.c
 * (pc_format_from_v4l2); nothing here computes a stride on its own.
 *
 * Every call returns 0 or a negative PC_E* code with a detail message naming the node and the
 * ioctl. A node that goes away (ENODEV) gives PC_EDISCONNECTED; EINTR is retried.
 * This header does not include <linux/videodev2.h>: its types are polarcam's own.
 */
#ifndef POLARCAM_V4L2_H
#define POLARCAM_V4L2_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/format.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_v4l2 pc_v4l2;

typedef enum pc_v4l2_dir {
	PC_V4L2_CAPTURE = 1,
	PC_V4L2_OUTPUT = 2,
} pc_v4l2_dir;

/* What VIDIOC_QUERYCAP says about a node (device_caps when the driver reports them). */
typedef struct pc_v4l2_info {
	char path[256];
	char driver[17];
	char card[33];
	char bus_info[33];
	uint32_t version;     /* KERNEL_VERSION-style a.b.c */
	uint32_t device_caps; /* V4L2_CAP_* of this node */
	bool capture;         /* single-planar video capture */
	bool output;          /* single-planar video output */
	bool capture_mplane;  /* multi-planar video capture (streamed with one-plane formats) */
	bool output_mplane;   /* multi-planar video output */
	bool multiplanar;     /* capture_mplane || output_mplane */
	bool metadata;        /* metadata capture or output */
	bool streaming;       /* V4L2_CAP_STREAMING */
	bool readwrite;       /* V4L2_CAP_READWRITE */
} pc_v4l2_info;

/* Opens path for one direction, through the single-planar API when the node has it, else the
 * multi-planar one (formats with one plane only: every format of the table). Fails with
 * PC_ENOTSUP (naming what the node offers) when the node cannot stream in that direction, PC_ENOENT
 * when it does not exist, PC_EPERM when it cannot be opened for lack of permission. */
PC_API int pc_v4l2_open(const char *path, pc_v4l2_dir dir, pc_v4l2 **out);
/* Stops streaming if needed, unmaps the buffers and closes the node. NULL is fine. */
PC_API void pc_v4l2_close(pc_v4l2 *dev);
PC_API const pc_v4l2_info *pc_v4l2_get_info(const pc_v4l2 *dev);

/* ---- formats ---- */

/* Pixel formats the node offers in its direction (VIDIOC_ENUM_FMT), in driver order.
 * Writes at most cap fourccs; *count receives the total. */
PC_API int pc_v4l2_enum_formats(pc_v4l2 *dev, uint32_t *fourccs, size_t cap, size_t *count);

typedef struct pc_v4l2_format {
	uint32_t fourcc;
	pc_pixfmt format; /* pc_format_from_v4l2(fourcc); PC_FMT_INVALID when polarcam has none */
	uint32_t width, height;
	size_t bytesperline; /* the driver's stride, >= the table's row bytes */
	size_t sizeimage;    /* bytes of one buffer's image */
} pc_v4l2_format;

/* Frame size range for a fourcc (VIDIOC_ENUM_FRAMESIZES). Discrete sizes report the smallest
 * and largest with step 0. PC_ENOTSUP when the driver does not enumerate sizes. */
typedef struct pc_v4l2_size_range {
	uint32_t min_width, max_width, step_width;
	uint32_t min_height, max_height, step_height;
	bool discrete;
} pc_v4l2_size_range;
PC_API int pc_v4l2_frame_sizes(pc_v4l2 *dev, uint32_t fourcc, pc_v4l2_size_range *out);

/* What the driver would make of (fourcc, width, height, bytesperline): VIDIOC_TRY_FMT, no state
 * change. bytesperline 0 lets the driver choose; a larger value asks for padded rows (drivers
 * may ignore it). The answer may differ from the request: compare to tell valid from adjusted.
 * Progressive frames only: a driver that insists on fields gives PC_ENOTSUP. */
PC_API int pc_v4l2_try_format(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                              size_t bytesperline, pc_v4l2_format *got);
/* VIDIOC_S_FMT. Fails with PC_EFORMAT when the driver answers with a fourcc polarcam cannot
 * read or a bytesperline/sizeimage too small for the table's row size (corrupt answer). */
PC_API int pc_v4l2_set_format(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                              size_t bytesperline, pc_v4l2_format *got);
/* VIDIOC_G_FMT. */
PC_API int pc_v4l2_get_format(pc_v4l2 *dev, pc_v4l2_format *got);

/* ---- inputs, outputs, DV timings ---- */

/* VIDIOC_S_INPUT on capture nodes, VIDIOC_S_OUTPUT on output nodes. */
PC_API int pc_v4l2_select_io(pc_v4l2 *dev, unsigned index);

/* BT.656/1120 digital video timings, the fields of struct v4l2_bt_timings that matter. */
typedef struct pc_dv_timings {
	uint32_t width, height;
	bool interlaced;
	bool hsync_pos, vsync_pos; /* sync polarities */
	uint64_t pixelclock_hz;
	uint32_t hfrontporch, hsync, hbackporch;
	uint32_t vfrontporch, vsync, vbackporch;
	bool cvt, reduced_blanking; /* standard and flag */
} pc_dv_timings;

/* VESA Coordinated Video Timings 1.2, reduced blanking version 2, progressive: the timings of
 * width x height at refresh_hz. Pure computation (no device). */
PC_API int pc_dv_timings_cvt_rb2(uint32_t width, uint32_t height, double refresh_hz,
                                 pc_dv_timings *out);
/* Frame rate the timings produce: pixelclock / (total width * total height). */
PC_API double pc_dv_timings_fps(const pc_dv_timings *t);

/* VIDIOC_S_DV_TIMINGS, then VIDIOC_G_DV_TIMINGS to check that the node took them (a receiver
 * can accept and silently keep others: PC_EINVAL naming both sizes). */
PC_API int pc_v4l2_set_dv_timings(pc_v4l2 *dev, const pc_dv_timings *t);
PC_API int pc_v4l2_get_dv_timings(pc_v4l2 *dev, pc_dv_timings *t);

/* ---- controls ---- */

typedef enum pc_v4l2_ctrl_type {
	PC_V4L2_CTRL_INTEGER = 1,
	PC_V4L2_CTRL_BOOLEAN,
	PC_V4L2_CTRL_MENU,
	PC_V4L2_CTRL_INTEGER64,
	PC_V4L2_CTRL_BUTTON,
	PC_V4L2_CTRL_OTHER,
} pc_v4l2_ctrl_type;

typedef struct pc_v4l2_ctrl {
	uint32_t id;
	char name[32];
	pc_v4l2_ctrl_type type;
	int64_t minimum, maximum, step, default_value;
	bool read_only, inactive;
} pc_v4l2_ctrl;

/* PC_ENOENT when the node has no such control. */
PC_API int pc_v4l2_ctrl_query(pc_v4l2 *dev, uint32_t id, pc_v4l2_ctrl *out);
/* Finds a control by its name, ignoring case ("Loop Video"). */
PC_API int pc_v4l2_ctrl_find(pc_v4l2 *dev, const char *name, pc_v4l2_ctrl *out);
/* Sets a control; a value outside [minimum, maximum] or off the step grid is PC_ERANGE naming
 * the control and its range, never clamped. */
PC_API int pc_v4l2_ctrl_set(pc_v4l2 *dev, uint32_t id, int64_t value);
PC_API int pc_v4l2_ctrl_get(pc_v4l2 *dev, uint32_t id, int64_t *value);

/* Well-known control ids (values of linux/v4l2-controls.h) for callers without kernel headers. */
#define PC_V4L2_CID_GAIN              0x00980913u
#define PC_V4L2_CID_EXPOSURE          0x00980911u
#define PC_V4L2_CID_EXPOSURE_AUTO     0x009a0901u
#define PC_V4L2_CID_EXPOSURE_ABSOLUTE 0x009a0902u /* units of 100 us */
#define PC_V4L2_CID_ANALOGUE_GAIN     0x009e0903u

/* Frame rates the node offers for (fourcc, width, height) (VIDIOC_ENUM_FRAMEINTERVALS).
 * Discrete sets report their smallest and largest rate and, as step, the largest gap between
 * neighbouring rates (the worst rounding a request can see). PC_ENOTSUP when not enumerated. */
typedef struct pc_v4l2_rate_range {
	double min_fps, max_fps, step_fps;
	bool discrete;
	unsigned count; /* discrete rates */
} pc_v4l2_rate_range;
PC_API int pc_v4l2_frame_rates(pc_v4l2 *dev, uint32_t fourcc, uint32_t width, uint32_t height,
                               pc_v4l2_rate_range *out);

/* Frame interval as a rate (VIDIOC_G_PARM / S_PARM). PC_ENOTSUP when the node has no
 * V4L2_CAP_TIMEPERFRAME. set stores what the driver chose in *actual_fps (may be NULL). */
PC_API int pc_v4l2_get_frame_rate(pc_v4l2 *dev, double *fps);
PC_API int pc_v4l2_set_frame_rate(pc_v4l2 *dev, double fps, double *actual_fps);

/* ---- streaming (memory-mapped buffers) ---- */

typedef struct pc_v4l2_buffer {
	unsigned index;
	void *data;            /* the mapping; valid until stream_stop */
	size_t length;         /* bytes mapped */
	size_t bytesused;      /* bytes of image data the driver filled */
	uint32_t sequence;     /* the driver's 32-bit sequence number */
	uint64_t timestamp_ns; /* buffer timestamp (CLOCK_MONOTONIC for most drivers) */
	bool error;            /* V4L2_BUF_FLAG_ERROR: the data may be corrupt */
	bool timestamp_monotonic;
} pc_v4l2_buffer;

/* Step by step (what the frame source does):
 *   buffers_alloc -> queue each -> stream_on -> dequeue/queue ... -> stream_off -> buffers_free
 * buffers_alloc reads the node's format (G_FMT, checked against the format table), requests
 * count mmap buffers and maps them; *granted (may be NULL) receives what the driver gave,
 * which can differ from count. stream_off returns every buffer to the application (none is
 * queued afterwards). buffers_free unmaps and releases them (stream_off first). */
PC_API int pc_v4l2_buffers_alloc(pc_v4l2 *dev, unsigned count, unsigned *granted);
PC_API int pc_v4l2_buffer_memory(const pc_v4l2 *dev, unsigned index, void **data, size_t *length);
PC_API int pc_v4l2_stream_on(pc_v4l2 *dev);
PC_API int pc_v4l2_stream_off(pc_v4l2 *dev);
PC_API int pc_v4l2_buffers_free(pc_v4l2 *dev);

/* All at once: buffers_alloc(nbuf), on capture nodes queue every buffer (output nodes hand
 * out buffers with pc_v4l2_output_acquire()), stream_on. */
PC_API int pc_v4l2_stream_start(pc_v4l2 *dev, unsigned nbuf);
PC_API unsigned pc_v4l2_buffer_count(const pc_v4l2 *dev);

/* Waits up to timeout_ms (negative: forever) for a filled capture buffer (or, on output nodes,
 * a consumed one) and dequeues it. PC_ETIMEDOUT, PC_EDISCONNECTED, PC_EIO. With no buffer
 * queued nothing can arrive: it waits out the timeout and answers PC_ETIMEDOUT (PC_ESTATE when
 * the timeout is infinite). */
PC_API int pc_v4l2_dequeue(pc_v4l2 *dev, int timeout_ms, pc_v4l2_buffer *buf);
/* Gives a buffer to the driver (before stream_on or while streaming). On output nodes bytesused
 * is the image size to send (0 = the format's sizeimage); capture nodes ignore it. */
PC_API int pc_v4l2_queue(pc_v4l2 *dev, unsigned index, size_t bytesused);
/* Output nodes: a buffer the application may fill, either one never queued yet or one the
 * driver has consumed (waiting up to timeout_ms). */
PC_API int pc_v4l2_output_acquire(pc_v4l2 *dev, int timeout_ms, pc_v4l2_buffer *buf);
/* stream_off + buffers_free. Safe to call when not streaming. */
PC_API int pc_v4l2_stream_stop(pc_v4l2 *dev);

/* ---- listing ---- */

#define PC_V4L2_LIST_MAX_FORMATS 64
typedef struct pc_v4l2_node {
	pc_v4l2_info info; /* info.path is set even when the node could not be opened */
	int error;         /* 0, or why the node could not be queried */
	char error_detail[256];
	uint32_t fourccs[PC_V4L2_LIST_MAX_FORMATS]; /* capture (or else output) formats */
	size_t nformats;                            /* entries in fourccs */
	size_t nformats_total; /* formats the node offers (may exceed the array) */
} pc_v4l2_node;

/* Lists the video nodes dev_dir/videoN (dev_dir NULL = "/dev"), sorted by N. Nodes that cannot
 * be opened are listed with error set, not skipped. *nodes is malloc'd (free()). An absent
 * dev_dir or no nodes gives 0 and *count = 0. */
PC_API int pc_v4l2_list(const char *dev_dir, pc_v4l2_node **nodes, size_t *count);

#ifdef __cplusplus
}
#endif
#endif
