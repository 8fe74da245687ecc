/* polarcam/picture.h - false-colour pictures of polarization images, for people who would
 * rather look than read. Pure computation into caller-owned RGB8 buffers (files are written by
 * io: pc_pictures_write in polarcam/io.h).
 *
 *   S0, DoLP: grey, linear between lo and hi (clipped for display only).
 *   AoLP: hue = AoLP (0 red, 60° yellow-green... the full hue circle over [0, π), so 0 and π
 *   meet), and DoLP/dolp_max as the HSV value (unpolarized regions dark) or the saturation
 *   (unpolarized regions white).
 * The *_key functions give the colour of a legend position, for colour bars.
 */
#ifndef POLARCAM_PICTURE_H
#define POLARCAM_PICTURE_H

#include <stddef.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_aolp_style {
	PC_AOLP_VALUE = 0,  /* hue = AoLP, value = DoLP, saturation 1 */
	PC_AOLP_SATURATION, /* hue = AoLP, saturation = DoLP, value 1 */
	PC_AOLP_HUE_ONLY    /* hue = AoLP at full saturation and value */
} pc_aolp_style;

/* Grey picture of a float image, linear from lo (black) to hi (white). Non-finite values are
 * drawn magenta so that they cannot hide. */
PC_API int pc_picture_grey(const pc_fplane *in, uint32_t width, uint32_t height, float lo, float hi,
                           uint8_t *rgb, size_t rgb_stride);

/* AoLP false colour; dolp may be NULL for PC_AOLP_HUE_ONLY. dolp_max (> 0) is the DoLP shown
 * at full value/saturation. */
PC_API int pc_picture_aolp(const pc_fplane *aolp, const pc_fplane *dolp, uint32_t width,
                           uint32_t height, pc_aolp_style style, float dolp_max, uint8_t *rgb,
                           size_t rgb_stride);

/* The q-quantile (0..1) of the finite values of an image (histogram-based, 4096 bins between
 * the minimum and maximum; exact to 1/4096 of the range). For display ranges. */
PC_API float pc_picture_quantile(const pc_fplane *in, uint32_t width, uint32_t height, double q);

/* Low-signal mask: where S0 is below threshold (or not finite), DoLP and AoLP are dominated by
 * noise (their noise grows like σ/S0; the simulator's cast shadows show as white DoLP speckle),
 * so pictures of them paint those pixels with a dark grey hatch (diagonal stripes of
 * PC_PICTURE_MASK_RGB0 and PC_PICTURE_MASK_RGB1, 8 pixels per period) that no DoLP grey or
 * AoLP colour looks like. Returns the number of pixels painted. */
#define PC_PICTURE_MASK_RGB0 52
#define PC_PICTURE_MASK_RGB1 84
PC_API size_t pc_picture_mask_low(const pc_fplane *s0, uint32_t width, uint32_t height,
                                  float threshold, uint8_t *rgb, size_t rgb_stride);
/* The mask's colour at pixel (x, y) (for legends). */
PC_API void pc_picture_mask_rgb(uint32_t x, uint32_t y, uint8_t rgb[3]);

/* Invalid pixels (a validity mask of polarcam/demosaic.h: 0 where the value depends on a
 * saturated or dead sample, or on one the calibration distrusts) are painted with a checker of
 * PC_PICTURE_INVALID_RGB and black, 2 pixels per square (4 per period, so it survives a
 * display downscale of 2), drawn over everything, the low-signal hatch included: no grey, hue
 * or the hatch looks like it. valid: row stride valid_stride bytes; NULL paints nothing.
 * Returns the number of pixels painted. */
#define PC_PICTURE_INVALID_R 255
#define PC_PICTURE_INVALID_G 0
#define PC_PICTURE_INVALID_B 160
PC_API size_t pc_picture_mask_invalid(const uint8_t *valid, size_t valid_stride, uint32_t width,
                                      uint32_t height, uint8_t *rgb, size_t rgb_stride);
/* The invalid mark's colour at pixel (x, y) (for legends). */
PC_API void pc_picture_invalid_rgb(uint32_t x, uint32_t y, uint8_t rgb[3]);

/* HSV (h in [0, 1) of the circle, s, v in [0, 1]) to RGB8. */
PC_API void pc_hsv_to_rgb8(double h, double s, double v, uint8_t rgb[3]);

/* Legend colours: t along the bar (0..1), s across it (2-D keys). ctx: pointer to a
 * pc_aolp_style for pc_picture_aolp_key; unused for pc_picture_grey_key. */
PC_API void pc_picture_grey_key(double t, double s, uint8_t rgb[3], void *ctx);
PC_API void pc_picture_aolp_key(double t, double s, uint8_t rgb[3], void *ctx);

#ifdef __cplusplus
}
#endif
#endif
