#include "polarcam/plot.h"

#include <assert.h>
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "polarcam/error.h"
#include "polarcam/io.h"

typedef struct plot_series {
	char *label;
	double *x, *y;
	size_t n;
	pc_plot_style style;
} plot_series;

typedef struct plot_label {
	double x, y;
	char *text;
} plot_label;

struct pc_plot {
	char *title, *xlabel, *ylabel;
	plot_series *series;
	size_t nseries;
	plot_label *labels;
	size_t nlabels;
	bool fixed_x, fixed_y, log_x, log_y;
	double xmin, xmax, ymin, ymax;
};

/* Tableau-10-like palette, distinguishable and print-friendly. */
static const double palette[][3] = {
    {0.12, 0.47, 0.71}, {1.00, 0.50, 0.05}, {0.17, 0.63, 0.17}, {0.84, 0.15, 0.16},
    {0.58, 0.40, 0.74}, {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76}, {0.50, 0.50, 0.50},
    {0.74, 0.74, 0.13}, {0.09, 0.75, 0.81},
};
#define PALETTE_N (sizeof palette / sizeof palette[0])

static char *dup_or_null(const char *s)
{
	if (!s)
		return NULL;
	size_t n = strlen(s) + 1;
	char *d = malloc(n);
	if (d)
		memcpy(d, s, n);
	return d;
}

pc_plot *pc_plot_new(const char *title, const char *xlabel, const char *ylabel)
{
	pc_plot *p = calloc(1, sizeof *p);
	if (!p)
		return NULL;
	p->title = dup_or_null(title);
	p->xlabel = dup_or_null(xlabel);
	p->ylabel = dup_or_null(ylabel);
	return p;
}

void pc_plot_free(pc_plot *p)
{
	if (!p)
		return;
	for (size_t i = 0; i < p->nseries; i++) {
		free(p->series[i].label);
		free(p->series[i].x);
		free(p->series[i].y);
	}
	for (size_t i = 0; i < p->nlabels; i++)
		free(p->labels[i].text);
	free(p->series);
	free(p->labels);
	free(p->title);
	free(p->xlabel);
	free(p->ylabel);
	free(p);
}

void pc_plot_set_xrange(pc_plot *p, double min, double max)
{
	p->fixed_x = true;
	p->xmin = min;
	p->xmax = max;
}

void pc_plot_set_yrange(pc_plot *p, double min, double max)
{
	p->fixed_y = true;
	p->ymin = min;
	p->ymax = max;
}

void pc_plot_set_log(pc_plot *p, bool log_x, bool log_y)
{
	p->log_x = log_x;
	p->log_y = log_y;
}

int pc_plot_add_series(pc_plot *p, const char *label, const double *x, const double *y, size_t n,
                       pc_plot_style style)
{
	if (!p || (!x && n) || (!y && n))
		return pc_error(PC_EINVAL, "plot series: missing data");
	plot_series *s = realloc(p->series, (p->nseries + 1) * sizeof *s);
	if (!s)
		return pc_error(PC_ENOMEM, "plot series");
	p->series = s;
	plot_series *t = &s[p->nseries];
	memset(t, 0, sizeof *t);
	t->label = dup_or_null(label);
	t->x = malloc((n ? n : 1) * sizeof(double));
	t->y = malloc((n ? n : 1) * sizeof(double));
	if (!t->x || !t->y || (label && !t->label)) {
		free(t->x);
		free(t->y);
		free(t->label);
		return pc_error(PC_ENOMEM, "plot series");
	}
	if (n) {
		memcpy(t->x, x, n * sizeof(double));
		memcpy(t->y, y, n * sizeof(double));
	}
	t->n = n;
	t->style = style;
	p->nseries++;
	return 0;
}

int pc_plot_add_label(pc_plot *p, double x, double y, const char *text)
{
	plot_label *l = realloc(p->labels, (p->nlabels + 1) * sizeof *l);
	if (!l)
		return pc_error(PC_ENOMEM, "plot label");
	p->labels = l;
	l[p->nlabels].x = x;
	l[p->nlabels].y = y;
	l[p->nlabels].text = dup_or_null(text ? text : "");
	if (!l[p->nlabels].text)
		return pc_error(PC_ENOMEM, "plot label");
	p->nlabels++;
	return 0;
}

/* ---- axes ---- */

/* "Nice numbers" tick step for a range (Heckbert, Graphics Gems I, 1990). */
static double nice_step(double range, int target_ticks)
{
	double raw = range / target_ticks;
	double mag = pow(10, floor(log10(raw)));
	double f = raw / mag;
	double nf = f < 1.5 ? 1 : f < 3 ? 2 : f < 7 ? 5 : 10;
	return nf * mag;
}

typedef struct axis {
	double min, max; /* in plotted units (log10 for log axes) */
	bool log;
	double step; /* tick step in plotted units */
} axis;

static void axis_auto(axis *a, double dmin, double dmax, bool fixed, double fmin, double fmax,
                      bool log_axis)
{
	a->log = log_axis;
	if (fixed) {
		dmin = fmin;
		dmax = fmax;
	}
	if (log_axis) {
		dmin = dmin > 0 ? log10(dmin) : 0;
		dmax = dmax > 0 ? log10(dmax) : 1;
	}
	if (!isfinite(dmin) || !isfinite(dmax)) {
		dmin = 0;
		dmax = 1;
	}
	if (dmax <= dmin) {
		double c = dmin, h = fabs(c) > 0 ? fabs(c) * 0.1 : 1;
		dmin = c - h;
		dmax = c + h;
	}
	if (log_axis) {
		a->step = ceil((dmax - dmin) / 8);
		if (a->step < 1)
			a->step = 1;
		if (!fixed) {
			dmin = floor(dmin);
			dmax = ceil(dmax);
		}
	} else {
		a->step = nice_step(dmax - dmin, 6);
		if (!fixed) {
			dmin = floor(dmin / a->step + 1e-9) * a->step;
			dmax = ceil(dmax / a->step - 1e-9) * a->step;
		}
	}
	a->min = dmin;
	a->max = dmax;
}

static double axis_value(const axis *a, double v)
{
	return a->log ? (v > 0 ? log10(v) : NAN) : v;
}

static void format_tick(const axis *a, double t, char *buf, size_t n)
{
	if (a->log) {
		double v = pow(10, t);
		if (t >= -3 && t <= 4)
			snprintf(buf, n, "%g", v);
		else
			snprintf(buf, n, "1e%d", (int)lround(t));
		return;
	}
	if (fabs(t) < a->step * 1e-9)
		t = 0;
	snprintf(buf, n, "%g", t);
}

/* ---- output ---- */

static cairo_status_t write_cb(void *closure, const unsigned char *data, unsigned int length)
{
	FILE *fp = closure;
	return fwrite(data, 1, length, fp) == length ? CAIRO_STATUS_SUCCESS
	                                             : CAIRO_STATUS_WRITE_ERROR;
}

static int surface_to_png(cairo_surface_t *s, const char *path)
{
	pc_atomic_file af;
	int rc = pc_atomic_open(&af, path);
	if (rc)
		return rc;
	cairo_status_t st = cairo_surface_write_to_png_stream(s, write_cb, af.fp);
	if (st != CAIRO_STATUS_SUCCESS) {
		pc_atomic_abort(&af);
		return pc_error(PC_EIO, "%s: PNG encoding failed: %s", path,
		                cairo_status_to_string(st));
	}
	return pc_atomic_commit(&af);
}

static void text_at(cairo_t *cr, double x, double y, const char *s, double ax, double ay)
{
	cairo_text_extents_t e;
	cairo_text_extents(cr, s, &e);
	cairo_move_to(cr, x - ax * e.width - e.x_bearing, y - ay * e.height - e.y_bearing);
	cairo_show_text(cr, s);
}

int pc_plot_write_png(const pc_plot *p, const char *path, int width, int height)
{
	if (!p || width < 200 || height < 150 || width > 10000 || height > 10000)
		return pc_error(PC_EINVAL, "%s: plot size %dx%d outside 200x150 .. 10000x10000",
		                path, width, height);
	double dxmin = INFINITY, dxmax = -INFINITY, dymin = INFINITY, dymax = -INFINITY;
	for (size_t i = 0; i < p->nseries; i++)
		for (size_t k = 0; k < p->series[i].n; k++) {
			double x = p->series[i].x[k], y = p->series[i].y[k];
			if (!isfinite(x) || !isfinite(y) || (p->log_x && x <= 0) ||
			    (p->log_y && y <= 0))
				continue;
			dxmin = fmin(dxmin, x);
			dxmax = fmax(dxmax, x);
			dymin = fmin(dymin, y);
			dymax = fmax(dymax, y);
		}
	axis ax, ay;
	axis_auto(&ax, dxmin, dxmax, p->fixed_x, p->xmin, p->xmax, p->log_x);
	axis_auto(&ay, dymin, dymax, p->fixed_y, p->ymin, p->ymax, p->log_y);

	cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
	cairo_t *cr = cairo_create(s);
	cairo_set_source_rgb(cr, 1, 1, 1);
	cairo_paint(cr);
	cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
	                       CAIRO_FONT_WEIGHT_NORMAL);
	double fs = height / 40.0 < 11 ? 11 : height / 40.0;
	cairo_set_font_size(cr, fs);

	double left = fs * 5.5, right = fs * 1.5, top = fs * 3, bottom = fs * 4;
	double pw = width - left - right, ph = height - top - bottom;
#define PX(v) (left + ((v)-ax.min) / (ax.max - ax.min) * pw)
#define PY(v) (top + ph - ((v)-ay.min) / (ay.max - ay.min) * ph)

	/* grid and ticks */
	char buf[64];
	cairo_set_line_width(cr, 1);
	for (int k = 0;; k++) {
		double t = ceil(ax.min / ax.step - 1e-9) * ax.step + k * ax.step;
		if (t > ax.max + 1e-9 * ax.step || k > 100)
			break;
		double x = PX(t);
		cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
		cairo_move_to(cr, x, top);
		cairo_line_to(cr, x, top + ph);
		cairo_stroke(cr);
		cairo_set_source_rgb(cr, 0, 0, 0);
		format_tick(&ax, t, buf, sizeof buf);
		text_at(cr, x, top + ph + fs * 0.5, buf, 0.5, 0);
	}
	for (int k = 0;; k++) {
		double t = ceil(ay.min / ay.step - 1e-9) * ay.step + k * ay.step;
		if (t > ay.max + 1e-9 * ay.step || k > 100)
			break;
		double y = PY(t);
		cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
		cairo_move_to(cr, left, y);
		cairo_line_to(cr, left + pw, y);
		cairo_stroke(cr);
		cairo_set_source_rgb(cr, 0, 0, 0);
		format_tick(&ay, t, buf, sizeof buf);
		text_at(cr, left - fs * 0.4, y, buf, 1, 0.5);
	}
	cairo_set_source_rgb(cr, 0, 0, 0);
	cairo_rectangle(cr, left, top, pw, ph);
	cairo_stroke(cr);

	/* labels */
	if (p->title) {
		cairo_save(cr);
		cairo_set_font_size(cr, fs * 1.2);
		text_at(cr, left + pw / 2, fs * 0.8, p->title, 0.5, 0);
		cairo_restore(cr);
	}
	if (p->xlabel)
		text_at(cr, left + pw / 2, height - fs * 1.6, p->xlabel, 0.5, 0);
	if (p->ylabel) {
		cairo_save(cr);
		cairo_translate(cr, fs * 1.0, top + ph / 2);
		cairo_rotate(cr, -M_PI / 2);
		text_at(cr, 0, 0, p->ylabel, 0.5, 0);
		cairo_restore(cr);
	}

	/* data, clipped to the plot area */
	cairo_save(cr);
	cairo_rectangle(cr, left, top, pw, ph);
	cairo_clip(cr);
	for (size_t i = 0; i < p->nseries; i++) {
		const plot_series *se = &p->series[i];
		const double *c = palette[i % PALETTE_N];
		cairo_set_source_rgb(cr, c[0], c[1], c[2]);
		cairo_set_line_width(cr, 2);
		if (se->style == PC_PLOT_DASHED) {
			double dash[2] = {6, 4};
			cairo_set_dash(cr, dash, 2, 0);
		} else {
			cairo_set_dash(cr, NULL, 0, 0);
		}
		if (se->style != PC_PLOT_POINTS) {
			bool pen = false;
			for (size_t k = 0; k < se->n; k++) {
				double x = axis_value(&ax, se->x[k]), y = axis_value(&ay, se->y[k]);
				if (!isfinite(x) || !isfinite(y)) {
					pen = false;
					continue;
				}
				if (pen)
					cairo_line_to(cr, PX(x), PY(y));
				else
					cairo_move_to(cr, PX(x), PY(y));
				pen = true;
			}
			cairo_stroke(cr);
		}
		if (se->style == PC_PLOT_POINTS || se->style == PC_PLOT_LINE_POINTS) {
			cairo_set_dash(cr, NULL, 0, 0);
			for (size_t k = 0; k < se->n; k++) {
				double x = axis_value(&ax, se->x[k]), y = axis_value(&ay, se->y[k]);
				if (!isfinite(x) || !isfinite(y))
					continue;
				cairo_arc(cr, PX(x), PY(y), fs * 0.3, 0, 2 * M_PI);
				cairo_fill(cr);
			}
		}
	}
	cairo_set_dash(cr, NULL, 0, 0);
	cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
	cairo_set_font_size(cr, fs * 0.85);
	for (size_t i = 0; i < p->nlabels; i++) {
		double x = axis_value(&ax, p->labels[i].x), y = axis_value(&ay, p->labels[i].y);
		if (isfinite(x) && isfinite(y))
			text_at(cr, PX(x) + fs * 0.5, PY(y) - fs * 0.3, p->labels[i].text, 0, 1);
	}
	cairo_restore(cr);

	/* legend, top right inside the plot */
	size_t nleg = 0;
	double legw = 0;
	for (size_t i = 0; i < p->nseries; i++)
		if (p->series[i].label) {
			cairo_text_extents_t e;
			cairo_text_extents(cr, p->series[i].label, &e);
			legw = fmax(legw, e.x_advance);
			nleg++;
		}
	if (nleg) {
		double lh = fs * 1.4, bw = legw + fs * 3.5, bh = lh * (double)nleg + fs * 0.5;
		double bx = left + pw - bw - fs * 0.5, by = top + fs * 0.5;
		cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
		cairo_rectangle(cr, bx, by, bw, bh);
		cairo_fill_preserve(cr);
		cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
		cairo_set_line_width(cr, 1);
		cairo_stroke(cr);
		size_t row = 0;
		for (size_t i = 0; i < p->nseries; i++) {
			if (!p->series[i].label)
				continue;
			const double *c = palette[i % PALETTE_N];
			double yy = by + fs * 0.25 + lh * ((double)row + 0.5);
			cairo_set_source_rgb(cr, c[0], c[1], c[2]);
			cairo_set_line_width(cr, 2);
			if (p->series[i].style == PC_PLOT_DASHED) {
				double dash[2] = {6, 4};
				cairo_set_dash(cr, dash, 2, 0);
			}
			if (p->series[i].style == PC_PLOT_POINTS) {
				cairo_arc(cr, bx + fs * 1.5, yy, fs * 0.3, 0, 2 * M_PI);
				cairo_fill(cr);
			} else {
				cairo_move_to(cr, bx + fs * 0.5, yy);
				cairo_line_to(cr, bx + fs * 2.5, yy);
				cairo_stroke(cr);
			}
			cairo_set_dash(cr, NULL, 0, 0);
			cairo_set_source_rgb(cr, 0, 0, 0);
			text_at(cr, bx + fs * 3, yy, p->series[i].label, 0, 0.5);
			row++;
		}
	}
#undef PX
#undef PY
	cairo_destroy(cr);
	cairo_surface_flush(s);
	int rc = cairo_surface_status(s) == CAIRO_STATUS_SUCCESS
	             ? surface_to_png(s, path)
	             : pc_error(PC_ENOMEM, "%s: cannot draw the plot", path);
	cairo_surface_destroy(s);
	return rc;
}

int pc_image_write_png(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height,
                       size_t stride, const char *title, const pc_colorbar *bar, uint32_t max_width)
{
	return pc_image_write_png_ex(path, rgb, width, height, stride, title, bar, NULL, max_width);
}

/* The annotated picture's layout: the image drawn iw × ih, the font size, the title's height,
 * the colour bar's width and the whole W × H. */
typedef struct annot_layout {
	int iw, ih, top, barw, W, H;
	double fs;
} annot_layout;

static annot_layout annot_size(uint32_t width, uint32_t height, double scale, bool title,
                               const pc_colorbar *bar)
{
	annot_layout l;
	l.iw = (int)lround(width * scale);
	l.ih = (int)lround(height * scale);
	if (l.iw < 1)
		l.iw = 1;
	if (l.ih < 1)
		l.ih = 1;
	l.fs = fmax(12, fmin(l.iw, l.ih) / 40.0);
	l.top = title ? (int)(l.fs * 2.2) : 0;
	l.barw = bar ? (int)(l.fs * (bar->s_label ? 9 : 7)) : 0;
	l.W = l.iw + l.barw + (bar ? (int)l.fs : 0);
	l.H = l.ih + l.top + (bar ? (int)l.fs : 0);
	if (l.H < l.ih + l.top + (int)(l.fs * 2))
		l.H = l.ih + l.top + (int)(l.fs * 2);
	return l;
}

/* The picture drawn at scale with its title, colour bar and notes, as a new cairo surface
 * (*out; NULL on an error, which names what). */
/* xrgb: NULL, or width × height words (stride 4·width) that hold cairo's copy of the picture;
 * xout: NULL, or the annotated picture's words (its size as pc_image_annotated_size gives it),
 * where it is drawn (both kept by the live window; otherwise cairo allocates them per call). */
static int render_annotated(const char *what, const uint8_t *rgb, uint32_t width, uint32_t height,
                            size_t stride, const char *title, const pc_colorbar *bar,
                            const pc_legend_note *note, double scale, uint32_t *xrgb,
                            uint32_t *xout, cairo_surface_t **out_s)
{
	*out_s = NULL;
	if (!rgb || width == 0 || height == 0 || stride < (size_t)width * 3 || width > 30000 ||
	    height > 30000 || !(scale > 0) || width * scale > 30000 || height * scale > 30000)
		return pc_error(PC_EINVAL, "%s: bad image geometry %ux%u stride %zu", what, width,
		                height, stride);
	const annot_layout l = annot_size(width, height, scale, title != NULL, bar);
	const int iw = l.iw, ih = l.ih, top = l.top, W = l.W;
	const double fs = l.fs;

	/* the picture itself, as a cairo surface (xRGB little-endian words) */
	/* RGB24 rows are 4·width bytes: whole 32-bit words, already aligned as cairo wants */
	assert(!xrgb ||
	       cairo_format_stride_for_width(CAIRO_FORMAT_RGB24, (int)width) == (int)width * 4);
	cairo_surface_t *img =
	    xrgb ? cairo_image_surface_create_for_data((unsigned char *)xrgb, CAIRO_FORMAT_RGB24,
	                                               (int)width, (int)height, (int)width * 4)
	         : cairo_image_surface_create(CAIRO_FORMAT_RGB24, (int)width, (int)height);
	if (cairo_surface_status(img) != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(img);
		return pc_error(PC_ENOMEM, "%s: image of %ux%u", what, width, height);
	}
	cairo_surface_flush(img);
	unsigned char *dst = cairo_image_surface_get_data(img);
	int dstride = cairo_image_surface_get_stride(img);
	for (uint32_t y = 0; y < height; y++) {
		const uint8_t *s = rgb + (size_t)y * stride;
		uint32_t *d = (uint32_t *)(void *)(dst + (size_t)y * (size_t)dstride);
		for (uint32_t x = 0; x < width; x++)
			d[x] = 0xff000000u | ((uint32_t)s[3 * x] << 16) |
			       ((uint32_t)s[3 * x + 1] << 8) | s[3 * x + 2];
	}
	cairo_surface_mark_dirty(img);

	cairo_surface_t *out = xout ? cairo_image_surface_create_for_data(
	                                  (unsigned char *)xout, CAIRO_FORMAT_RGB24, W, l.H, W * 4)
	                            : cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, l.H);
	cairo_t *cr = cairo_create(out);
	cairo_set_source_rgb(cr, 1, 1, 1);
	cairo_paint(cr);
	cairo_select_font_face(cr, "DejaVu Sans", CAIRO_FONT_SLANT_NORMAL,
	                       CAIRO_FONT_WEIGHT_NORMAL);
	cairo_set_font_size(cr, fs);
	cairo_save(cr);
	cairo_translate(cr, 0, top);
	cairo_scale(cr, scale, scale);
	cairo_set_source_surface(cr, img, 0, 0);
	cairo_pattern_set_filter(cairo_get_source(cr),
	                         scale < 1 ? CAIRO_FILTER_GOOD : CAIRO_FILTER_NEAREST);
	cairo_paint(cr);
	cairo_restore(cr);
	cairo_set_source_rgb(cr, 0, 0, 0);
	if (title)
		text_at(cr, iw / 2.0, fs * 0.6, title, 0.5, 0);
	if (bar) {
		double bx = iw + fs, by = top + fs * 0.5, bh = fmax(ih - fs * 1.5, fs * 4);
		int n_notes = 0;
		for (const pc_legend_note *q = note; q && n_notes < 4; q = q->next)
			n_notes += q->text && q->color;
		int with_note = n_notes > 0 && bh > fs * (6 + 2 * n_notes);
		if (with_note)
			bh -= fs * (1.5 + 1.5 * n_notes); /* room for the notes' swatches */
		else if (bar->s_label)
			bh -= fs * 0.5; /* room for the key's second range below the last tick */
		double bwid = bar->s_label ? fs * 3 : fs * 1.2;
		int nt = (int)bh, ns = bar->s_label ? (int)bwid : 1;
		for (int k = 0; k < nt; k++) {
			double t = 1.0 - (k + 0.5) / nt;
			for (int j = 0; j < ns; j++) {
				double sfrac = ns > 1 ? (j + 0.5) / ns : 1.0;
				uint8_t c[3] = {0, 0, 0};
				if (bar->color)
					bar->color(t, sfrac, c, bar->ctx);
				cairo_set_source_rgb(cr, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0);
				cairo_rectangle(cr, bx + (ns > 1 ? j : 0), by + k,
				                ns > 1 ? 1 : bwid, 1.2);
				cairo_fill(cr);
			}
		}
		cairo_set_source_rgb(cr, 0, 0, 0);
		cairo_set_line_width(cr, 1);
		cairo_rectangle(cr, bx, by, bwid, bh);
		cairo_stroke(cr);
		cairo_set_font_size(cr, fs * 0.8);
		double step =
		    bar->tick_step > 0 ? bar->tick_step : nice_step(bar->vmax - bar->vmin, 5);
		char buf[64];
		if (step > 0 && isfinite(step)) {
			for (int k = 0; k < 50; k++) {
				double v = ceil(bar->vmin / step - 1e-9) * step + k * step;
				if (v > bar->vmax + 1e-9 * step)
					break;
				double yy =
				    by + bh * (1 - (v - bar->vmin) / (bar->vmax - bar->vmin));
				snprintf(buf, sizeof buf, "%g", fabs(v) < step * 1e-9 ? 0.0 : v);
				cairo_move_to(cr, bx + bwid, yy);
				cairo_line_to(cr, bx + bwid + fs * 0.3, yy);
				cairo_stroke(cr);
				text_at(cr, bx + bwid + fs * 0.4, yy, buf, 0, 0.5);
			}
		}
		if (bar->label) {
			cairo_save(cr);
			cairo_translate(cr, W - fs * 0.5, by + bh / 2);
			cairo_rotate(cr, -M_PI / 2);
			text_at(cr, 0, 0, bar->label, 0.5, 0.5);
			cairo_restore(cr);
		}
		if (bar->s_label) {
			snprintf(buf, sizeof buf, "%s %g..%g", bar->s_label, bar->smin, bar->smax);
			text_at(cr, bx, by + bh + fs * 0.7, buf, 0,
			        0); /* below the last tick's label */
		}
		int k_note = 0;
		for (const pc_legend_note *q = note; with_note && q && k_note < 4; q = q->next) {
			if (!q->text || !q->color)
				continue;
			int sw = (int)(fs * 1.2), sy = (int)(by + bh + fs * (1.8 + 1.5 * k_note++));
			for (int yy = 0; yy < sw; yy++)
				for (int xx = 0; xx < sw; xx++) {
					uint8_t c[3];
					q->color((uint32_t)xx, (uint32_t)yy, c);
					cairo_set_source_rgb(cr, c[0] / 255.0, c[1] / 255.0,
					                     c[2] / 255.0);
					cairo_rectangle(cr, bx + xx, sy + yy, 1, 1);
					cairo_fill(cr);
				}
			cairo_set_source_rgb(cr, 0, 0, 0);
			cairo_rectangle(cr, bx, sy, sw, sw);
			cairo_stroke(cr);
			text_at(cr, bx + sw + fs * 0.3, sy + sw / 2.0, q->text, 0, 0.5);
		}
	}
	cairo_destroy(cr);
	cairo_surface_destroy(img);
	if (cairo_surface_status(out) != CAIRO_STATUS_SUCCESS) {
		cairo_surface_destroy(out);
		return pc_error(PC_ENOMEM, "%s: cannot draw the image", what);
	}
	cairo_surface_flush(out);
	*out_s = out;
	return 0;
}

int pc_image_write_png_ex(const char *path, const uint8_t *rgb, uint32_t width, uint32_t height,
                          size_t stride, const char *title, const pc_colorbar *bar,
                          const pc_legend_note *note, uint32_t max_width)
{
	double scale = (max_width && width > max_width) ? (double)max_width / width : 1.0;
	cairo_surface_t *out;
	int rc = render_annotated(path, rgb, width, height, stride, title, bar, note, scale, NULL,
	                          NULL, &out);
	if (rc)
		return rc;
	rc = surface_to_png(out, path);
	cairo_surface_destroy(out);
	return rc;
}

void pc_image_annotated_size(uint32_t width, uint32_t height, uint32_t image_width, bool title,
                             const pc_colorbar *bar, uint32_t *out_width, uint32_t *out_height)
{
	annot_layout l =
	    annot_size(width, height,
	               width ? (double)(image_width ? image_width : width) / width : 1, title, bar);
	*out_width = (uint32_t)l.W;
	*out_height = (uint32_t)l.H;
}

int pc_image_render_rgb8(const uint8_t *rgb, uint32_t width, uint32_t height, size_t stride,
                         const char *title, const pc_colorbar *bar, const pc_legend_note *note,
                         uint32_t image_width, uint8_t *out, uint32_t out_width,
                         uint32_t out_height, size_t out_stride)
{
	return pc_image_render_rgb8_xrgb(rgb, width, height, stride, title, bar, note, image_width,
	                                 out, out_width, out_height, out_stride, NULL, NULL);
}

int pc_image_render_rgb8_xrgb(const uint8_t *rgb, uint32_t width, uint32_t height, size_t stride,
                              const char *title, const pc_colorbar *bar, const pc_legend_note *note,
                              uint32_t image_width, uint8_t *out, uint32_t out_width,
                              uint32_t out_height, size_t out_stride, uint32_t *xrgb,
                              uint32_t *xout)
{
	if (!out || out_stride < (size_t)out_width * 3)
		return pc_error(PC_EINVAL, "annotated picture: bad output buffer");
	cairo_surface_t *s;
	int rc = render_annotated("annotated picture", rgb, width, height, stride, title, bar, note,
	                          width ? (double)(image_width ? image_width : width) / width : 1,
	                          xrgb, xout, &s);
	if (rc)
		return rc;
	const int sw = cairo_image_surface_get_width(s), sh = cairo_image_surface_get_height(s);
	if ((uint32_t)sw > out_width || (uint32_t)sh > out_height) {
		cairo_surface_destroy(s);
		return pc_error(PC_EINVAL, "annotated picture: %dx%d does not fit the %ux%u output",
		                sw, sh, out_width, out_height);
	}
	const unsigned char *src = cairo_image_surface_get_data(s);
	const int ss = cairo_image_surface_get_stride(s);
	for (int y = 0; y < sh; y++) {
		const uint32_t *p = (const uint32_t *)(const void *)(src + (size_t)y * (size_t)ss);
		uint8_t *d = out + (size_t)y * out_stride;
		for (int x = 0; x < sw; x++) {
			d[3 * x] = (uint8_t)(p[x] >> 16);
			d[3 * x + 1] = (uint8_t)(p[x] >> 8);
			d[3 * x + 2] = (uint8_t)p[x];
		}
	}
	cairo_surface_destroy(s);
	return 0;
}
