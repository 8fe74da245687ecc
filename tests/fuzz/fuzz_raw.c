/* libFuzzer harness: headerless raw files with explicit geometry (pc_image_read with a
 * pc_raw_geometry, as demosaic/process --width --height --format --offset --stride). The first
 * 24 bytes are the geometry — width and height (u16 each, or 2^30 when 0xffff), a pixel format
 * (index into the table), offset and stride (u64 little-endian, the extremes included: the
 * stride of 2^64 − 1 that used to wrap) — the rest is the file. On success the view must have
 * exactly the geometry's size and format; pc_image_read_mosaic's values must fit the depth it
 * reports (a Mono12 raw holding 55245 was accepted: pc_view_check_bits took the name's 12 bits
 * for the 16-bit container's capacity). */
#include "fuzz_image.h"

static uint64_t le64(const uint8_t *p)
{
	uint64_t v = 0;
	for (int i = 7; i >= 0; i--)
		v = v << 8 | p[i];
	return v;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 24)
		return 0;
	pc_raw_geometry g;
	unsigned w = data[0] | data[1] << 8, h = data[2] | data[3] << 8;
	g.width = w == 0xffff ? 1u << 30 : w;
	g.height = h == 0xffff ? 1u << 30 : h;
	/* formats: every entry of the table, by index (PC_FMT_INVALID and beyond included) */
	g.format = (pc_pixfmt)(data[4] % (PC_FMT_COUNT + 2));
	g.offset = (size_t)le64(data + 8);
	g.stride = (size_t)le64(data + 16);
	if (data[5] & 1) /* mostly sane offsets and strides, so that reads get to the data */
		g.offset %= 64;
	if (data[5] & 2)
		g.stride = g.stride % 4096;
	const char *p = fuzz_file("in.raw", data + 24, size - 24);
	pc_view v;
	if (pc_image_read(p, &g, &v, NULL) == 0) {
		fuzz_check_view(&v, p);
		FUZZ_ASSERT(v.width == g.width && v.height == g.height && v.format == g.format,
		            "%ux%u", v.width, v.height);
		pc_view_free(&v);
	}
	fuzz_read_image(p, &g, data[6] % 17);
	return 0;
}
