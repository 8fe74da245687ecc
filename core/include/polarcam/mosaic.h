/* polarcam/mosaic.h - the polarizer mosaic as data.
 *
 * Analyser channels are numbered c = 0..3 for 0°, 45°, 90°, 135° (angle = 45°·c, measured
 * from the image x axis, counter-clockwise as seen by the viewer; physics.md §1).
 * A monochrome division-of-focal-plane sensor repeats a 2×2 block; Sony IMX250MZR's top-left
 * block is
 *
 *        x=0   x=1
 *   y=0  90°   45°
 *   y=1  135°  0°
 *
 * A colour-polarization sensor (Sony IMX250MYR) puts each 2×2 polarizer block under one colour
 * of an RGGB Bayer pattern, so the pattern repeats every 4×4 pixels:
 *
 *        x=0 1   2 3
 *   y=0  R90 R45 G90 G45
 *   y=1  R135 R0 G135 G0
 *   y=2  G90 G45 B90 B45
 *   y=3  G135 G0 B135 B0
 *
 * A crop or ROI at offset (x0, y0) shifts the phase: the pixel (x, y) of the crop is the pixel
 * (x + x0, y + y0) of the full sensor.
 */
#ifndef POLARCAM_MOSAIC_H
#define POLARCAM_MOSAIC_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_cfa_color { PC_CFA_NONE = 0, PC_CFA_R, PC_CFA_G, PC_CFA_B } pc_cfa_color;

typedef struct pc_mosaic {
	uint8_t period;        /* 2 (monochrome) or 4 (colour-polarization) */
	uint8_t channel[4][4]; /* analyser channel 0..3 at (y mod period, x mod period) */
	uint8_t color[4][4];   /* pc_cfa_color at (y mod period, x mod period) */
} pc_mosaic;

/* Sony IMX250MZR: [90 45; 135 0]. */
PC_API pc_mosaic pc_mosaic_imx250mzr(void);

/* Sony IMX250MYR: [90 45; 135 0] blocks under RGGB. */
PC_API pc_mosaic pc_mosaic_imx250myr(void);

/* Monochrome mosaic from the four angles of the 2×2 block in row-major order (top-left,
 * top-right, bottom-left, bottom-right), e.g. {90, 45, 135, 0}. PC_EINVAL unless the angles
 * are a permutation of 0, 45, 90, 135. */
PC_API int pc_mosaic_from_angles(const int angles_deg[4], pc_mosaic *out);

/* Parses a layout string [BAYER:]A,B,C,D[@DX,DY]:
 *   A,B,C,D  the analyser angles of the 2×2 block, row-major ("90,45,135,0" is IMX250MZR);
 *   BAYER:   a colour-polarization mosaic: RGGB, BGGR, GRBG or GBRG gives the colours of the
 *            four 2×2 polarizer blocks of the 4×4 period, row-major ("RGGB:90,45,135,0" is
 *            IMX250MYR);
 *   @DX,DY   the phase: pixel (0,0) of the image is pixel (DX,DY) of the pattern described
 *            (0..1, or 0..3 with a colour filter), as after a crop at an odd offset.
 * The names "imx250mzr" and "imx250myr" are accepted too. Errors name the offending token. */
PC_API int pc_mosaic_parse(const char *layout, pc_mosaic *out);

/* Writes the layout in the syntax pc_mosaic_parse reads ("90,45,135,0",
 * "RGGB:90,45,135,0@1,0"); pc_mosaic_parse of the result gives the same mosaic. */
PC_API void pc_mosaic_format(const pc_mosaic *m, char *buf, unsigned size);

/* Validates a mosaic: period 2 without colour or period 4 with whole 2×2 polarizer blocks under
 * a Bayer pattern; a 2×2 polarizer pattern holding each analyser once. PC_EINVAL otherwise. */
PC_API int pc_mosaic_check(const pc_mosaic *m);

/* Whether a and b describe the same pattern: the same period and the same analyser and colour
 * at every position of it (what pc_mosaic_channel / pc_mosaic_color read). */
PC_API bool pc_mosaic_equal(const pc_mosaic *a, const pc_mosaic *b);

/* For a colour mosaic: (*ox, *oy) in 0..1 where the 2×2 colour blocks start. PC_EINVAL (no
 * detail message) when m is monochrome or its colours are not constant on 2×2 blocks. */
PC_API int pc_mosaic_color_origin(const pc_mosaic *m, unsigned *ox, unsigned *oy);

/* The mosaic seen by a crop whose origin is (x0, y0) on this mosaic. */
PC_API pc_mosaic pc_mosaic_shift(const pc_mosaic *m, uint32_t x0, uint32_t y0);

/* The mosaic of an image flipped horizontally (ReverseX) or vertically (ReverseY) whose full
 * width/height is w/h. Flips mirror angles: an analyser at θ becomes one at 180° − θ. */
PC_API pc_mosaic pc_mosaic_flip(const pc_mosaic *m, int flip_x, int flip_y, uint32_t w, uint32_t h);

static inline unsigned pc_mosaic_channel(const pc_mosaic *m, uint32_t x, uint32_t y)
{
	return m->channel[y % m->period][x % m->period];
}

static inline pc_cfa_color pc_mosaic_color(const pc_mosaic *m, uint32_t x, uint32_t y)
{
	return (pc_cfa_color)m->color[y % m->period][x % m->period];
}

/* Position (dx, dy) in 0..1 of channel c inside a 2×2 block starting at an even position of
 * this (monochrome) mosaic. */
PC_API void pc_mosaic_channel_pos(const pc_mosaic *m, unsigned c, unsigned *dx, unsigned *dy);

#ifdef __cplusplus
}
#endif
#endif
