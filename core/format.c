#include "polarcam/format.h"

#include <stdint.h>
#include <string.h>

#include "polarcam/error.h"

/* GenICam PFNC values: "GenICam Pixel Format Naming Convention 2.x", pixel format value table.
 * V4L2 fourccs: linux/videodev2.h (V4L2_PIX_FMT_GREY, Y10, Y12, Y14, Y16, Y10P, Y12P). */
static const pc_format_info pc_formats[PC_FMT_COUNT] = {
	[PC_FMT_MONO8] = { PC_FMT_MONO8, "Mono8", 8, 1, 1, PC_PACK_NONE, false,
			   PC_FOURCC('G', 'R', 'E', 'Y'), 0x01080001u },
	[PC_FMT_MONO10] = { PC_FMT_MONO10, "Mono10", 10, 1, 2, PC_PACK_NONE, false,
			    PC_FOURCC('Y', '1', '0', ' '), 0x01100003u },
	[PC_FMT_MONO12] = { PC_FMT_MONO12, "Mono12", 12, 1, 2, PC_PACK_NONE, false,
			    PC_FOURCC('Y', '1', '2', ' '), 0x01100005u },
	[PC_FMT_MONO14] = { PC_FMT_MONO14, "Mono14", 14, 1, 2, PC_PACK_NONE, false,
			    PC_FOURCC('Y', '1', '4', ' '), 0x01100025u },
	[PC_FMT_MONO16] = { PC_FMT_MONO16, "Mono16", 16, 1, 2, PC_PACK_NONE, false,
			    PC_FOURCC('Y', '1', '6', ' '), 0x01100007u },
	[PC_FMT_MONO10P] = { PC_FMT_MONO10P, "Mono10p", 10, 4, 5, PC_PACK_PFNC_LSB, false, 0,
			     0x010A0046u },
	[PC_FMT_MONO12P] = { PC_FMT_MONO12P, "Mono12p", 12, 2, 3, PC_PACK_PFNC_LSB, false, 0,
			     0x010C0047u },
	[PC_FMT_MONO12PACKED] = { PC_FMT_MONO12PACKED, "Mono12Packed", 12, 2, 3, PC_PACK_GVSP12,
				  false, 0, 0x010C0006u },
	[PC_FMT_Y10P] = { PC_FMT_Y10P, "Y10P", 10, 4, 5, PC_PACK_MIPI, false,
			  PC_FOURCC('Y', '1', '0', 'P'), 0 },
	[PC_FMT_Y12P] = { PC_FMT_Y12P, "Y12P", 12, 2, 3, PC_PACK_MIPI, false,
			  PC_FOURCC('Y', '1', '2', 'P'), 0 },
	[PC_FMT_FLOAT32] = { PC_FMT_FLOAT32, "Float32", 32, 1, 4, PC_PACK_NONE, true, 0, 0 },
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
		return pc_error(PC_EINVAL, "width %u: %s packs %u pixels per group, width must be a multiple",
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

/* Vendors' names for raw polarizer-mosaic data (hardware.md: LUCID Arena, FLIR Spinnaker
 * GenICam descriptions). */
static const struct {
	const char *name;
	pc_pixfmt fmt;
	bool colour;
} pc_polarized_names[] = {
	{ "PolarizeMono8", PC_FMT_MONO8, false },
	{ "PolarizeMono12", PC_FMT_MONO12, false },
	{ "PolarizeMono12p", PC_FMT_MONO12P, false },
	{ "PolarizeMono12Packed", PC_FMT_MONO12PACKED, false },
	{ "PolarizeMono16", PC_FMT_MONO16, false },
	{ "Polarized8", PC_FMT_MONO8, false },
	{ "Polarized10p", PC_FMT_MONO10P, false },
	{ "Polarized12p", PC_FMT_MONO12P, false },
	{ "Polarized16", PC_FMT_MONO16, false },
	{ "BayerRGPolarized8", PC_FMT_MONO8, true },
	{ "BayerRGPolarized10p", PC_FMT_MONO10P, true },
	{ "BayerRGPolarized12p", PC_FMT_MONO12P, true },
	{ "BayerRGPolarized16", PC_FMT_MONO16, true },
};

int pc_format_from_genicam(const char *name, pc_pixfmt *fmt, bool *polarized, bool *colour)
{
	if (!name)
		return pc_error(PC_EINVAL, "pixel format name missing");
	for (size_t i = 0; i < sizeof pc_polarized_names / sizeof pc_polarized_names[0]; i++) {
		if (strcmp(pc_polarized_names[i].name, name) == 0) {
			*fmt = pc_polarized_names[i].fmt;
			*polarized = true;
			*colour = pc_polarized_names[i].colour;
			return 0;
		}
	}
	pc_pixfmt f = pc_format_from_name(name);
	if (f != PC_FMT_INVALID && f != PC_FMT_FLOAT32 && pc_formats[f].v4l2_fourcc != 0 &&
	    pc_formats[f].pfnc_code == 0)
		f = PC_FMT_INVALID; /* Y10P/Y12P are V4L2 names, not GenICam ones */
	if (f != PC_FMT_INVALID && f != PC_FMT_FLOAT32) {
		*fmt = f;
		*polarized = false;
		*colour = false;
		return 0;
	}
	if (strncmp(name, "Polarized", 9) == 0 || strncmp(name, "Polarize", 8) == 0)
		return pc_error(PC_ENOTSUP, "pixel format '%s': a processed polarization format, "
					    "polarcam needs the raw mosaic", name);
	return pc_error(PC_EINVAL, "pixel format '%s': not a raw monochrome or polarized format "
				   "polarcam knows", name);
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
