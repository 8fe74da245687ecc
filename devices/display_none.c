/* Without OpenCV: no window; resizing by nearest neighbour so that view --screenshot works. */
#include "polarcam/display.h"
#include "polarcam/error.h"

#include <string.h>

bool pc_display_available(void)
{
	return false;
}

int pc_display_open(pc_display **out, const char *title)
{
	(void)title;
	*out = NULL;
	return pc_error(PC_EUNAVAIL, "no live window in this build: OpenCV (Debian: "
	                             "libopencv-highgui-dev) was not found at configure time");
}

int pc_display_show(pc_display *d, const uint8_t *rgb, uint32_t width, uint32_t height,
                    size_t stride, const char *overlay)
{
	(void)d, (void)rgb, (void)width, (void)height, (void)stride, (void)overlay;
	return pc_error(PC_EUNAVAIL, "no live window in this build");
}

void pc_display_close(pc_display *d)
{
	(void)d;
}

int pc_display_resize_rgb8(const uint8_t *src, uint32_t sw, uint32_t sh, size_t sstride,
                           uint8_t *dst, uint32_t dw, uint32_t dh, size_t dstride)
{
	if (!src || !dst || !sw || !sh || !dw || !dh)
		return pc_error(PC_EINVAL, "resize: bad image");
	for (uint32_t y = 0; y < dh; y++)
		for (uint32_t x = 0; x < dw; x++)
			memcpy(dst + (size_t)y * dstride + 3 * (size_t)x,
			       src + (size_t)(y * (uint64_t)sh / dh) * sstride +
			           3 * (size_t)(x * (uint64_t)sw / dw),
			       3);
	return 0;
}
