/* polarcam/format.h - the one pixel-format table.
 *
 * Every stride, size, V4L2 fourcc and GenICam (PFNC) name comes from here; backends never
 * compute them on their own. Unpacked integer formats hold their significant bits LSB-aligned
 * in little-endian 16-bit containers (Mono10/12/14/16), as GenICam and V4L2 Y10/Y12/Y16 do.
 */
#ifndef POLARCAM_FORMAT_H
#define POLARCAM_FORMAT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_pixfmt {
	PC_FMT_INVALID = 0,
	PC_FMT_MONO8,
	PC_FMT_MONO10, /* 10 bits LSB-aligned in uint16 */
	PC_FMT_MONO12, /* 12 bits LSB-aligned in uint16 */
	PC_FMT_MONO14, /* 14 bits LSB-aligned in uint16 */
	PC_FMT_MONO16,
	PC_FMT_MONO10P,      /* GenICam PFNC Mono10p: LSB-first bit stream, 4 px in 5 bytes */
	PC_FMT_MONO12P,      /* GenICam PFNC Mono12p: LSB-first bit stream, 2 px in 3 bytes */
	PC_FMT_MONO12PACKED, /* GigE Vision Mono12Packed: [a11..4][b3..0|a3..0][b11..4] */
	PC_FMT_Y10P,         /* V4L2 'Y10P' (MIPI CSI-2 RAW10): 4 high bytes, then 2-bit lows */
	PC_FMT_Y12P,         /* V4L2 'Y12P' (MIPI CSI-2 RAW12): 2 high bytes, then 4-bit lows */
	PC_FMT_FLOAT32,      /* one native-endian float plane */
	PC_FMT_MONO14P,      /* GenICam PFNC Mono14p: LSB-first bit stream, 4 px in 7 bytes */
	PC_FMT_MONO10PACKED, /* GigE Vision Mono10Packed: [a9..2][00 b1..0 00 a1..0][b9..2] */
	PC_FMT_Y10BPACK,     /* V4L2 'Y10B': MSB-first bit stream, 4 px in 5 bytes */
	PC_FMT_Y14P,         /* V4L2 'Y14P' (MIPI CSI-2 RAW14): 4 high bytes, then 6-bit lows */
	PC_FMT_COUNT
} pc_pixfmt;

typedef enum pc_packing {
	PC_PACK_NONE = 0, /* one pixel per 1, 2 or 4 bytes */
	PC_PACK_PFNC_LSB, /* PFNC "p" formats: contiguous LSB-first bit stream */
	PC_PACK_GVSP12,   /* GigE Vision Mono12Packed */
	PC_PACK_MIPI,     /* MIPI CSI-2 / V4L2 packed RAW10/RAW12/RAW14 */
	PC_PACK_GVSP10,   /* GigE Vision Mono10Packed */
	PC_PACK_MSB       /* MSB-first contiguous bit stream (V4L2 Y10BPACK) */
} pc_packing;

typedef struct pc_format_info {
	pc_pixfmt fmt;
	const char *name;      /* polarcam's name, equal to the standard GenICam name */
	unsigned bits;         /* significant bits per pixel (32 for float) */
	unsigned group_pixels; /* pixels per packing group (1 when unpacked) */
	unsigned group_bytes;  /* bytes per packing group */
	pc_packing packing;
	bool is_float;
	uint32_t v4l2_fourcc; /* 0 when V4L2 has no such format */
	uint32_t pfnc_code;   /* GenICam PFNC value of the standard name, 0 if none */
} pc_format_info;

/* Table entry of a format, or NULL for PC_FMT_INVALID / out-of-range values. */
PC_API const pc_format_info *pc_format_info_get(pc_pixfmt fmt);

/* Minimum bytes of one row of width pixels. Fails (PC_EINVAL) when width is not a multiple of
 * the packing group or the size overflows. */
PC_API int pc_format_row_bytes(pc_pixfmt fmt, uint32_t width, size_t *row_bytes);

/* Format by polarcam/GenICam name, case-sensitive ("Mono12", "Mono12p"). PC_FMT_INVALID if none. */
PC_API pc_pixfmt pc_format_from_name(const char *name);

/* Format by V4L2 fourcc. PC_FMT_INVALID if none. */
PC_API pc_pixfmt pc_format_from_v4l2(uint32_t fourcc);

/* A GenICam PixelFormat enumeration entry name as cameras report it, including vendors'
 * polarized raw names (LUCID PolarizeMono8/12/12p/12Packed/16, FLIR Polarized8/10p/12p/16,
 * colour BayerRGPolarized8/…). Identify formats by name, never by value: vendor codes collide
 * with Aravis's custom codes (0x81100007 is LUCID PolarizeMono16 and Aravis CUSTOM_BAYER_RG_16).
 * On success *fmt is the storage format, *polarized tells whether the name declares a
 * polarizer mosaic and *colour whether it declares a colour filter array on top of it.
 * Returns PC_ENOTSUP for names polarcam cannot process (processed formats such as
 * PolarizedStokes_* or RGB), PC_EINVAL for unknown names. */
PC_API int pc_format_from_genicam(const char *name, pc_pixfmt *fmt, bool *polarized, bool *colour);

/* One GenICam PixelFormat enumeration entry polarcam can take raw mosaics from. */
typedef struct pc_genicam_format {
	const char *name;   /* as the camera's GenICam description spells it */
	pc_pixfmt fmt;      /* storage format of the payload */
	bool polarized;     /* the name declares a polarizer mosaic */
	bool colour;        /* ... with a Bayer colour filter on top (IMX250MYR) */
	uint32_t code;      /* the value cameras use (PFNC or the vendor's custom value), 0 if
	                     * unknown; never identify a format by this value alone */
	const char *vendor; /* "PFNC", "LUCID", "FLIR" */
} pc_genicam_format;

/* The table of GenICam names polarcam accepts (standard mono names and vendors' polarized raw
 * names); *count receives its length. For cameras' GenICam descriptions and listings. */
PC_API const pc_genicam_format *pc_genicam_formats(size_t *count);

/* V4L2 fourcc as a printable 4-character string in buf (at least 5 bytes). */
PC_API const char *pc_fourcc_str(uint32_t fourcc, char buf[5]);

#define PC_FOURCC(a, b, c, d)                                                                      \
	((uint32_t)(a) | ((uint32_t)(b) << 8) | ((uint32_t)(c) << 16) | ((uint32_t)(d) << 24))

#ifdef __cplusplus
}
#endif
#endif
