/* polarcam/display.h - a live window for `polarcam view` (OpenCV highgui behind one small C++
 * file, devices/display_opencv.cpp). Without OpenCV every call answers PC_ENOTSUP.
 *
 * Images are caller-owned RGB8 rows (no copy on the C side; OpenCV wraps the pointer). */
#ifndef POLARCAM_DISPLAY_H
#define POLARCAM_DISPLAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_display pc_display;

/* True when this build can open windows (OpenCV highgui found at configure time). */
PC_API bool pc_display_available(void);

/* Opens a window titled title. PC_ENOTSUP without OpenCV, PC_EIO when no display can be
 * opened (no $DISPLAY / X server). */
PC_API int pc_display_open(pc_display **out, const char *title);

/* Shows an RGB8 image with an overlay line of black text at the top-left, in its first 30 rows
 * (may be NULL), and waits briefly for a key. Returns the key code (>= 0), -1 when no key was
 * pressed, or a negative PC_E* code (PC_ECANCELED when the window was closed). */
PC_API int pc_display_show(pc_display *d, const uint8_t *rgb, uint32_t width, uint32_t height,
                           size_t stride, const char *overlay);

PC_API void pc_display_close(pc_display *d);

#ifdef __cplusplus
}
#endif
#endif
