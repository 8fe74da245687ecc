/* polarcam/plot.h - PNG plots and annotated images for people who would rather look than read.
 *
 * Line/scatter plots (linear or log axes, legends, point labels) and images with a title and a
 * colour bar (1-D, or 2-D for keys such as AoLP hue × DoLP saturation). Rendering uses cairo;
 * files are written atomically.
 */
#ifndef POLARCAM_PLOT_H
#define POLARCAM_PLOT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_plot pc_plot;

typedef enum pc_plot_style {
	PC_PLOT_LINE = 0,    /* polyline; NaN values break the line */
	PC_PLOT_POINTS,      /* markers only */
	PC_PLOT_LINE_POINTS, /* both */
	PC_PLOT_DASHED       /* dashed polyline (references, limits) */
} pc_plot_style;

PC_API pc_plot *pc_plot_new(const char *title, const char *xlabel, const char *ylabel);
PC_API void pc_plot_free(pc_plot *p);

/* Fixed axis ranges (default: automatic from the data, padded to nice ticks). */
PC_API void pc_plot_set_xrange(pc_plot *p, double min, double max);
PC_API void pc_plot_set_yrange(pc_plot *p, double min, double max);
/* Logarithmic axes (non-positive values are skipped). */
PC_API void pc_plot_set_log(pc_plot *p, bool log_x, bool log_y);

/* Adds a series (the data are copied). Colours cycle through a fixed palette; label may be NULL
 * (no legend entry). */
PC_API int pc_plot_add_series(pc_plot *p, const char *label, const double *x, const double *y,
                              size_t n, pc_plot_style style);

/* Writes a text label next to the data point (x, y). */
PC_API int pc_plot_add_label(pc_plot *p, double x, double y, const char *text);

/* Renders to a PNG of width × height pixels (atomically). */
PC_API int pc_plot_write_png(const pc_plot *p, const char *path, int width, int height);

/* Colour key for pc_image_write_png: color(t, s) gives the colour at value fraction t ∈ [0, 1]
 * (along the bar) and, for 2-D keys, second fraction s ∈ [0, 1] (across the bar). */
typedef struct pc_colorbar {
	const char *label;   /* quantity and unit, e.g. "AoLP (deg)" */
	double vmin, vmax;   /* values at t = 0 and t = 1 */
	const char *s_label; /* 2-D keys: the quantity across the bar (e.g. "DoLP"), else NULL */
	double smin, smax;
	void (*color)(double t, double s, uint8_t rgb[3], void *ctx);
	void *ctx;
	double tick_step; /* ticks every tick_step from vmin (AoLP: 45); 0: "nice" steps */
} pc_colorbar;

/* Writes an RGB8 image with a title above it and, when bar is non-NULL, a colour bar with ticks
 * on its right. Images wider than max_width (0 = no limit) are downscaled for display. */
PC_API int pc_image_write_png(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height,
                              size_t stride, const char *title, const pc_colorbar *bar,
                              uint32_t max_width);

/* A legend entry below a colour bar: a swatch coloured by color(x, y) (pixel coordinates inside
 * the swatch, so that it can show a hatch) and a short text, e.g. "S0 < 82". */
typedef struct pc_legend_note {
	const char *text;
	void (*color)(uint32_t x, uint32_t y, uint8_t rgb[3]);
	const struct pc_legend_note *next; /* a further note below this one, or NULL */
} pc_legend_note;

/* pc_image_write_png with an optional note (NULL: none) under the colour bar. */
PC_API int pc_image_write_png_ex(const char *path, const uint8_t *rgb, uint32_t width,
                                 uint32_t height, size_t stride, const char *title,
                                 const pc_colorbar *bar, const pc_legend_note *note,
                                 uint32_t max_width);

/* The same picture drawn in memory (a live window shows it): the image drawn image_width pixels
 * wide (0: its own width; scaled up by nearest neighbour, down by a box filter), the height in
 * proportion, with the title, the colour bar and the notes, into out (RGB8, out_stride bytes
 * per row) from its top-left corner; pixels beyond the picture are left as they are.
 * pc_image_annotated_size gives the size it takes (title: whether there is one); PC_EINVAL
 * when it does not fit out_width × out_height. */
PC_API void pc_image_annotated_size(uint32_t width, uint32_t height, uint32_t image_width,
                                    bool title, const pc_colorbar *bar, uint32_t *out_width,
                                    uint32_t *out_height);
PC_API int pc_image_render_rgb8(const uint8_t *rgb, uint32_t width, uint32_t height, size_t stride,
                                const char *title, const pc_colorbar *bar,
                                const pc_legend_note *note, uint32_t image_width, uint8_t *out,
                                uint32_t out_width, uint32_t out_height, size_t out_stride);

#ifdef __cplusplus
}
#endif
#endif
