/* Without OpenCV: no window (view draws and saves its pictures without one). */
#include "polarcam/display.h"
#include "polarcam/error.h"

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
