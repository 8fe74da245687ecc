#include "polarcam/format.h"

#include <stdint.h>
#include <string.h>

#include "polarcam/error.h"

/* GenICam PFNC values: "GenICam Pixel Format Naming Convention 2.x", pixel format value table.
 * V4L2 fourccs: linux/videodev2.h (V4L2_PIX_FMT_GREY, Y10, Y12, Y14, Y16, Y10P, Y12P, Y14P,
 * Y10BPACK); packed layouts: the kernel's pixfmt-y10p/y12p/y14p/y10b pages, GigE Vision 2.0
 * (Mono10Packed, Mono12Packed), PFNC 2.x (Mono10p/12p/14p). */
static const pc_format_info pc_formats[PC_FMT_COUNT] = {
    [PC_FMT_MONO8] = {PC_FMT_MONO8, "Mono8", 8, 1, 1, PC_PACK_NONE, false,
                      PC_FOURCC('G', 'R', 'E', 'Y'), 0x01080001u},
    [PC_FMT_MONO10] = {PC_FMT_MONO10, "Mono10", 10, 1, 2, PC_PACK_NONE, false,
                       PC_FOURCC('Y', '1', '0', ' '), 0x01100003u},
    [PC_FMT_MONO12] = {PC_FMT_MONO12, "Mono12", 12, 1, 2, PC_PACK_NONE, false,
                       PC_FOURCC('Y', '1', '2', ' '), 0x01100005u},
    [PC_FMT_MONO14] = {PC_FMT_MONO14, "Mono14", 14, 1, 2, PC_PACK_NONE, false,
                       PC_FOURCC('Y', '1', '4', ' '), 0x01100025u},
    [PC_FMT_MONO16] = {PC_FMT_MONO16, "Mono16", 16, 1, 2, PC_PACK_NONE, false,
                       PC_FOURCC('Y', '1', '6', ' '), 0x01100007u},
    [PC_FMT_MONO10P] = {PC_FMT_MONO10P, "Mono10p", 10, 4, 5, PC_PACK_PFNC_LSB, false, 0,
                        0x010A0046u},
    [PC_FMT_MONO12P] = {PC_FMT_MONO12P, "Mono12p", 12, 2, 3, PC_PACK_PFNC_LSB, false, 0,
                        0x010C0047u},
    [PC_FMT_MONO12PACKED] = {PC_FMT_MONO12PACKED, "Mono12Packed", 12, 2, 3, PC_PACK_GVSP12, false,
                             0, 0x010C0006u},
    [PC_FMT_Y10P] = {PC_FMT_Y10P, "Y10P", 10, 4, 5, PC_PACK_MIPI, false,
                     PC_FOURCC('Y', '1', '0', 'P'), 0},
    [PC_FMT_Y12P] = {PC_FMT_Y12P, "Y12P", 12, 2, 3, PC_PACK_MIPI, false,
                     PC_FOURCC('Y', '1', '2', 'P'), 0},
    [PC_FMT_FLOAT32] = {PC_FMT_FLOAT32, "Float32", 32, 1, 4, PC_PACK_NONE, true, 0, 0},
    [PC_FMT_MONO14P] = {PC_FMT_MONO14P, "Mono14p", 14, 4, 7, PC_PACK_PFNC_LSB, false, 0,
                        0x010E0104u},
    [PC_FMT_MONO10PACKED] = {PC_FMT_MONO10PACKED, "Mono10Packed", 10, 2, 3, PC_PACK_GVSP10, false,
                             0, 0x010C0004u},
    [PC_FMT_Y10BPACK] = {PC_FMT_Y10BPACK, "Y10BPACK", 10, 4, 5, PC_PACK_MSB, false,
                         PC_FOURCC('Y', '1', '0', 'B'), 0},
    [PC_FMT_Y14P] = {PC_FMT_Y14P, "Y14P", 14, 4, 7, PC_PACK_MIPI, false,
                     PC_FOURCC('Y', '1', '4', 'P'), 0},
};

const pc_format_info *pc_format_info_get(pc_pixfmt fmt)
{
	if ((int)fmt <= (int)PC_FMT_INVALID || (int)fmt >= (int)PC_FMT_COUNT)
		return NULL;
	return &pc_formats[fmt];
}

int pc_format_row_bytes(pc_pixfmt fmt, uint32_t width, size_t *row_bytes)
{
	const pc_format_info *fi = pc_format_info_get(fmt);
	if (!fi)
		return pc_error(PC_EINVAL, "pixel format %d: not a known format", (int)fmt);
	if (width == 0)
		return pc_error(PC_EINVAL, "width 0: expected at least 1 pixel");
	if (width % fi->group_pixels)
		return pc_error(PC_EINVAL,
		                "width %u: %s packs %u pixels per group, width must be a multiple",
		                width, fi->name, fi->group_pixels);
	uint64_t n = (uint64_t)(width / fi->group_pixels) * fi->group_bytes;
	if (n > SIZE_MAX / 2)
		return pc_error(PC_EOVERFLOW, "width %u: row size overflows", width);
	*row_bytes = (size_t)n;
	return 0;
}

pc_pixfmt pc_format_from_name(const char *name)
{
	if (!name)
		return PC_FMT_INVALID;
	for (int f = PC_FMT_INVALID + 1; f < PC_FMT_COUNT; f++)
		if (strcmp(pc_formats[f].name, name) == 0)
			return (pc_pixfmt)f;
	return PC_FMT_INVALID;
}

pc_pixfmt pc_format_from_v4l2(uint32_t fourcc)
{
	if (fourcc == 0)
		return PC_FMT_INVALID;
	for (int f = PC_FMT_INVALID + 1; f < PC_FMT_COUNT; f++)
		if (pc_formats[f].v4l2_fourcc == fourcc)
			return (pc_pixfmt)f;
	return PC_FMT_INVALID;
}

/* GenICam names polarcam takes raw mosaics from. Standard names and values: PFNC 2.x; vendors'
 * polarized raw names: docs/hardware.md (LUCID Arena GenICam descriptions and LUCID's PFNC
 * header with its custom values, FLIR Spinnaker's Polarized* and BayerRGPolarized* entries, whose
 * values live in each camera's XML). Vendor values collide with Aravis's custom ones: match names
 * only. */
static const pc_genicam_format pc_genicam_table[] = {
    {"Mono8", PC_FMT_MONO8, false, false, 0x01080001u, "PFNC"},
    {"Mono10", PC_FMT_MONO10, false, false, 0x01100003u, "PFNC"},
    {"Mono10p", PC_FMT_MONO10P, false, false, 0x010A0046u, "PFNC"},
    {"Mono10Packed", PC_FMT_MONO10PACKED, false, false, 0x010C0004u, "PFNC"},
    {"Mono12", PC_FMT_MONO12, false, false, 0x01100005u, "PFNC"},
    {"Mono12p", PC_FMT_MONO12P, false, false, 0x010C0047u, "PFNC"},
    {"Mono12Packed", PC_FMT_MONO12PACKED, false, false, 0x010C0006u, "PFNC"},
    {"Mono14", PC_FMT_MONO14, false, false, 0x01100025u, "PFNC"},
    {"Mono14p", PC_FMT_MONO14P, false, false, 0x010E0104u, "PFNC"},
    {"Mono16", PC_FMT_MONO16, false, false, 0x01100007u, "PFNC"},
    {"PolarizeMono8", PC_FMT_MONO8, true, false, 0x81080001u, "LUCID"},
    {"PolarizeMono12", PC_FMT_MONO12, true, false, 0x81100008u, "LUCID"},
    {"PolarizeMono12p", PC_FMT_MONO12P, true, false, 0x810C0047u, "LUCID"},
    {"PolarizeMono12Packed", PC_FMT_MONO12PACKED, true, false, 0x810C0006u, "LUCID"},
    {"PolarizeMono16", PC_FMT_MONO16, true, false, 0x81100007u, "LUCID"},
    {"Polarized8", PC_FMT_MONO8, true, false, 0, "FLIR"},
    {"Polarized10p", PC_FMT_MONO10P, true, false, 0, "FLIR"},
    {"Polarized12p", PC_FMT_MONO12P, true, false, 0, "FLIR"},
    {"Polarized16", PC_FMT_MONO16, true, false, 0, "FLIR"},
    {"BayerRGPolarized8", PC_FMT_MONO8, true, true, 0, "FLIR"},
    {"BayerRGPolarized10p", PC_FMT_MONO10P, true, true, 0, "FLIR"},
    {"BayerRGPolarized12p", PC_FMT_MONO12P, true, true, 0, "FLIR"},
    {"BayerRGPolarized16", PC_FMT_MONO16, true, true, 0, "FLIR"},
};

const pc_genicam_format *pc_genicam_formats(size_t *count)
{
	if (count)
		*count = sizeof pc_genicam_table / sizeof pc_genicam_table[0];
	return pc_genicam_table;
}

int pc_format_from_genicam(const char *name, pc_pixfmt *fmt, bool *polarized, bool *colour)
{
	if (!name)
		return pc_error(PC_EINVAL, "pixel format name missing");
	for (size_t i = 0; i < sizeof pc_genicam_table / sizeof pc_genicam_table[0]; i++) {
		if (strcmp(pc_genicam_table[i].name, name) == 0) {
			*fmt = pc_genicam_table[i].fmt;
			*polarized = pc_genicam_table[i].polarized;
			*colour = pc_genicam_table[i].colour;
			return 0;
		}
	}
	if (strncmp(name, "Polarized", 9) == 0 || strncmp(name, "Polarize", 8) == 0)
		return pc_error(PC_ENOTSUP,
		                "pixel format '%s': a processed polarization format, "
		                "polarcam needs the raw mosaic",
		                name);
	if (strncmp(name, "Bayer", 5) == 0 || strncmp(name, "RGB", 3) == 0 ||
	    strncmp(name, "BGR", 3) == 0 || strncmp(name, "YUV", 3) == 0 ||
	    strncmp(name, "YCbCr", 5) == 0)
		return pc_error(PC_ENOTSUP,
		                "pixel format '%s': a colour format without a polarizer "
		                "mosaic; polarcam needs a polarized raw format",
		                name);
	return pc_error(PC_EINVAL,
	                "pixel format '%s': not a raw monochrome or polarized format "
	                "polarcam knows",
	                name);
}

const char *pc_fourcc_str(uint32_t fourcc, char buf[5])
{
	for (int i = 0; i < 4; i++) {
		char c = (char)((fourcc >> (8 * i)) & 0xff);
		buf[i] = (c >= 32 && c < 127) ? c : '?';
	}
	buf[4] = '\0';
	return buf;
}
