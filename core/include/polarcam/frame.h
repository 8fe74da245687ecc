/* polarcam/frame.h - frames: a plain view plus metadata.
 *
 * A view never assumes stride == width * bytes per pixel: rows are addressed through PC_ROW,
 * bounds-checked in debug builds. A frame adds metadata and the mosaic phase of its pixels.
 */
#ifndef POLARCAM_FRAME_H
#define POLARCAM_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/format.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_view {
	void *data;
	uint32_t width, height;
	size_t stride; /* bytes between the starts of consecutive rows */
	pc_pixfmt format;
} pc_view;

enum pc_frame_status {
	PC_FRAME_OK = 0,
	PC_FRAME_INCOMPLETE = 1u << 0, /* missing packets / lines */
	PC_FRAME_CORRUPT = 1u << 1,    /* transport reported an error */
	PC_FRAME_SIMULATED = 1u << 2,  /* produced by the simulator */
};

typedef struct pc_frame_meta {
	uint64_t sequence;     /* frame number from the source, monotonic */
	uint64_t timestamp_ns; /* capture time (source clock), monotonic */
	double exposure_us;    /* µs; NAN when the source does not say */
	double gain_db;        /* analog gain, dB (20·log10 of the amplification); NAN: unknown */
	uint32_t status;       /* pc_frame_status flags */
	uint32_t offset_x, offset_y; /* ROI origin on the full sensor */
} pc_frame_meta;

typedef struct pc_frame {
	pc_view view;
	pc_frame_meta meta;
	pc_mosaic mosaic; /* already shifted for the ROI origin */
} pc_frame;

/* Validates a view: known format, non-zero size, data non-NULL, stride large enough, packed
 * widths a multiple of the packing group. Errors say which field is wrong. */
PC_API int pc_view_check(const pc_view *v);

/* Allocates an owned view (64-byte aligned rows; stride = row bytes rounded up to 64 unless
 * stride_align is 1). Free with pc_view_free. */
PC_API int pc_view_alloc(pc_view *v, pc_pixfmt fmt, uint32_t width, uint32_t height,
                         size_t stride_align);
PC_API void pc_view_free(pc_view *v);

/* A sub-view of (x0, y0, w, h) sharing the data (unpacked formats only). */
PC_API int pc_view_crop(const pc_view *v, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                        pc_view *out);

/* Unpacks any integer format to LSB-aligned uint16 rows (dst_stride in bytes). Fails with
 * PC_ERANGE naming the first pixel whose value exceeds the format's bit depth (a 12-bit frame
 * holding 4096 is corrupt data, not something to clamp). */
PC_API int pc_view_to_u16(const pc_view *src, uint16_t *dst, size_t dst_stride);

/* Converts any format to float32 rows (integers keep their values, not normalised). Float
 * input is checked for NaN and infinity (PC_ERANGE naming the pixel). */
PC_API int pc_view_to_f32(const pc_view *src, float *dst, size_t dst_stride);

/* Packs LSB-aligned uint16 rows into dst (any integer format); values above the format's
 * range give PC_ERANGE. */
PC_API int pc_view_from_u16(const uint16_t *src, size_t src_stride, pc_view *dst);

/* Checks that every pixel of an integer view fits in bits significant bits (PC_ERANGE naming the
 * first pixel above 2^bits − 1: a 12-bit frame holding 4096 is corrupt data, not something to
 * clamp), and that every pixel of a float view is finite (PC_ERANGE naming the first NaN or
 * infinity; bits is ignored for float views). */
PC_API int pc_view_check_bits(const pc_view *v, unsigned bits);

/* A frame of the (x0, y0, w, h) part of f sharing its data: the mosaic is shifted by the crop
 * offset (an odd offset changes the phase) and meta.offset_x/y advance by it. */
PC_API int pc_frame_crop(const pc_frame *f, uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                         pc_frame *out);

/* Copies src into dst (same size and unpacked format) mirrored horizontally (flip_x) and/or
 * vertically (flip_y), as a camera's ReverseX/ReverseY would deliver it. The mosaic of the
 * result is pc_mosaic_flip(mosaic, flip_x, flip_y, width, height). */
PC_API int pc_view_flip(const pc_view *src, int flip_x, int flip_y, pc_view *dst);

static inline void *pc_view_row_unchecked(const pc_view *v, uint32_t y)
{
	return (uint8_t *)v->data + (size_t)y * v->stride;
}

/* Aborts with file:line when y is outside the view (a broken internal invariant). */
PC_API void *pc_view_row_checked(const pc_view *v, uint32_t y, const char *file, int line);

#ifdef NDEBUG
#define PC_ROW(view, type, y) ((type *)pc_view_row_unchecked((view), (y)))
#else
#define PC_ROW(view, type, y) ((type *)pc_view_row_checked((view), (y), __FILE__, __LINE__))
#endif

#ifdef __cplusplus
}
#endif
#endif
