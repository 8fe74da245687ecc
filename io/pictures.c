/* The standard pictures of a polarization image, as PNGs with titles and colour bars. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/picture.h"
#include "polarcam/plot.h"
#include "polarcam/stokes.h"

static int write_one(const char *dir, const char *name, const char *suffix, const uint8_t *rgb,
                     uint32_t w, uint32_t h, const char *title, const pc_colorbar *bar,
                     const pc_legend_note *note, uint32_t max_width)
{
	char path[4096];
	if ((size_t)snprintf(path, sizeof path, "%s/%s%s.png", dir, name, suffix ? suffix : "") >=
	    sizeof path)
		return pc_error(PC_EINVAL, "%s: directory path too long", dir);
	return pc_image_write_png_ex(path, rgb, w, h, (size_t)w * 3, title, bar, note, max_width);
}

double pc_pictures_dolp_auto(const float *dolp, const float *s0, size_t n, double mask)
{
	/* 99th percentile from a histogram of 2000 bins over [0, 1] (values above 1 in the last):
	 * the largest value in the percentile's bin, at most 0.0005 above the percentile and a
	 * value of the data (so that DoLP 0.9 everywhere gives 0.9, not the bin's edge) */
	enum { NB = 2000 };
	static const double q = 0.99, step = 0.05;
	size_t *hist = calloc(NB, sizeof *hist), used = 0;
	float *top_of = calloc(NB, sizeof *top_of);
	if (!hist || !top_of || !dolp)
		goto none;
	const bool masked = s0 && isfinite(mask) && mask > 0;
	for (size_t i = 0; i < n; i++) {
		float d = dolp[i];
		if (!isfinite(d) || (masked && !(s0[i] >= mask)))
			continue;
		long b = d <= 0 ? 0 : d >= 1 ? NB - 1 : (long)((double)d * NB);
		if (b >= NB)
			b = NB - 1;
		if (!hist[b]++ || d > top_of[b])
			top_of[b] = d;
		used++;
	}
	if (!used)
		goto none;
	size_t want = (size_t)ceil(q * (double)used), acc = 0;
	long b = 0;
	for (; b < NB - 1; b++)
		if ((acc += hist[b]) >= want)
			break;
	double top = top_of[b], hi = ceil(top / step - 1e-9) * step;
	free(hist);
	free(top_of);
	return hi < step ? step : hi > 1 ? 1 : hi;
none:
	free(hist);
	free(top_of);
	return 1;
}

int pc_pictures_write(const char *dir, const pc_stokes_out *st, uint32_t width, uint32_t height,
                      const char *title_prefix)
{
	pc_pictures_opts o = {title_prefix, 0, 0, NULL, 0, 0};
	return pc_pictures_write_opts(dir, st, width, height, &o);
}

int pc_pictures_write_opts(const char *dir, const pc_stokes_out *st, uint32_t width,
                           uint32_t height, const pc_pictures_opts *opts)
{
	return pc_pictures_write_valid(dir, st, width, height, opts, NULL);
}

/* S0's picture scale: 0 to its 99.9th percentile (a few specular pixels must not darken the
 * rest), or to the scale given (pictures to compare). Every picture of S0's units uses it. */
static float s0_scale(const pc_stokes_out *st, uint32_t width, uint32_t height, double s0_hi)
{
	float hi = s0_hi > 0 ? (float)s0_hi : pc_picture_quantile(&st->s0, width, height, 0.999);
	return hi > 0 ? hi : 1;
}

/* Invalid pixels (saturated, dead or distrusted samples), marked by a pink checker over every
 * picture and counted in its legend: their count, and the legend's "invalid N %" into note. */
static size_t invalid_count(const pc_validity *valid, uint32_t width, uint32_t height,
                            char note[80])
{
	const uint8_t *vm = valid && valid->mask ? valid->mask : NULL;
	size_t n_bad = 0;
	for (uint32_t y = 0; vm && y < height; y++)
		for (uint32_t x = 0; x < width; x++)
			n_bad += !vm[(size_t)y * valid->row_stride + x];
	snprintf(note, 80, "invalid %.2g%%", 100.0 * (double)n_bad / ((double)width * height));
	return n_bad;
}

/* White columns between two panels of a live window (a key's label and the next image apart). */
#define PANEL_GAP 12

/* Where the pictures of a Stokes image go: files (write_one) or the panels of a live window.
 * put() receives each picture with its file name, its title (long, for files, and short, for
 * panels), colour bar and legend notes; kinds: bits PIC_* of the pictures wanted. */
enum { PIC_S0 = 1, PIC_DOLP = 2, PIC_AOLP = 4, PIC_AOLP_SAT = 8 };
typedef struct pic_sink {
	int (*put)(struct pic_sink *k, int index, const char *name, const uint8_t *rgb,
	           const char *title, const char *short_title, const pc_colorbar *bar,
	           const pc_legend_note *note);
	unsigned kinds;
	/* files */
	const char *dir;
	const pc_pictures_opts *o;
	uint32_t w, h;
	/* panels */
	uint8_t *out;
	uint32_t out_w, out_h, image_w, x, y;
	struct pc_pictures_live *ws; /* the buffers drawn in (draw_set, put_panel) */
} pic_sink;

/* The buffers of the live window's panels, kept from one frame to the next. */
struct pc_pictures_live {
	uint8_t *rgb; /* one full-size picture, RGB8 */
	size_t rgb_n;
	uint32_t *xrgb; /* cairo's copy of it */
	size_t xrgb_n;
	uint32_t *xout; /* cairo's drawing of one panel */
	size_t xout_n;
	float *dd; /* the automatic DoLP range's copies of DoLP and S0 */
	size_t dd_n;
	uint8_t *out; /* the panels */
	size_t out_n;
};

/* *buf holds at least n bytes afterwards (its contents are not kept); NULL when out of
 * memory. Buffers only grow: a smaller frame reuses a larger buffer. */
static void *ws_get(void *buf_p, size_t *have, size_t n)
{
	void **buf = buf_p;
	if (*buf && *have >= n)
		return *buf;
	free(*buf);
	*buf = malloc(n ? n : 1);
	*have = *buf ? n : 0;
	return *buf;
}

static int put_file(pic_sink *k, int index, const char *name, const uint8_t *rgb, const char *title,
                    const char *short_title, const pc_colorbar *bar, const pc_legend_note *note)
{
	(void)index, (void)short_title;
	return write_one(k->dir, name, k->o->suffix, rgb, k->w, k->h, title, bar, note,
	                 k->o->max_width);
}

static int put_panel(pic_sink *k, int index, const char *name, const uint8_t *rgb,
                     const char *title, const char *short_title, const pc_colorbar *bar,
                     const pc_legend_note *note)
{
	(void)index, (void)name, (void)title;
	uint32_t pw, ph;
	pc_image_annotated_size(k->w, k->h, k->image_w, true, bar, &pw, &ph);
	if (k->x >= k->out_w || k->x + pw > k->out_w || k->y + ph > k->out_h)
		return pc_error(PC_EINVAL, "panels: %ux%u panel beyond the %ux%u picture", pw, ph,
		                k->out_w, k->out_h);
	uint32_t *xout = ws_get(&k->ws->xout, &k->ws->xout_n, (size_t)pw * ph * sizeof(uint32_t));
	if (!xout)
		return pc_error(PC_ENOMEM, "panels: %ux%u panel", pw, ph);
	int rc = pc_image_render_rgb8_xrgb(
	    rgb, k->w, k->h, (size_t)k->w * 3, short_title, bar, note, k->image_w,
	    k->out + (size_t)k->y * k->out_w * 3 + 3 * k->x, k->out_w - k->x, k->out_h - k->y,
	    (size_t)k->out_w * 3, k->ws->xrgb, xout);
	k->x += pw + PANEL_GAP;
	return rc;
}

/* The S0, DoLP and AoLP pictures (with the keys, ranges, masks and notes described in
 * polarcam/io.h) handed to sink one by one, drawn in sink->ws's buffers (the live window's,
 * kept from frame to frame, or a fresh set). */
static int draw_set(const pc_stokes_out *st, uint32_t width, uint32_t height,
                    const pc_pictures_opts *opts, const pc_validity *valid, pic_sink *sink)
{
	pc_pictures_live *ws = sink->ws;
	if (!st || !st->s0.data || !st->dolp.data || !st->aolp.data)
		return pc_error(PC_EINVAL, "pictures: S0, DoLP and AoLP images are needed");
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	if (!isfinite(o.mask_s0))
		return pc_error(PC_EINVAL, "pictures: mask threshold %g is not finite", o.mask_s0);
	if (!(isfinite(o.s0_hi) && o.s0_hi >= 0) || !isfinite(o.dolp_hi))
		return pc_error(PC_EINVAL,
		                "pictures: S0 scale %g / DoLP range %g: expected a finite "
		                "S0 scale >= 0 and a finite DoLP range",
		                o.s0_hi, o.dolp_hi);
	/* "truth" -> "truth: S0 ..." */
	char pre[96] = "";
	if (o.title_prefix && *o.title_prefix)
		snprintf(pre, sizeof pre, "%s: ", o.title_prefix);
	const size_t rgb_bytes = (size_t)width * height * 3;
	uint8_t *rgb = ws_get(&ws->rgb, &ws->rgb_n, rgb_bytes);
	if (!rgb)
		return pc_error(PC_ENOMEM, "pictures: %ux%u RGB buffer", width, height);
	char title[320];
	const float hi = s0_scale(st, width, height, o.s0_hi);
	float mask = o.mask_s0 > 0    ? (float)o.mask_s0
	             : o.mask_s0 == 0 ? (float)(PC_PICTURES_MASK_DEFAULT_REL * hi)
	                              : -INFINITY;
	char mask_note[64] = "", mask_title[128] = "";
	if (mask > -INFINITY) {
		snprintf(mask_note, sizeof mask_note, "S0 < %.4g", mask);
		snprintf(mask_title, sizeof mask_title, "; hatched: S0 < %.4g, low signal", mask);
	}
	/* the DoLP range: given, full, or automatic over the unmasked pixels */
	double dhi = o.dolp_hi > 0 ? fmin(o.dolp_hi, 1) : 1;
	char dlabel[64] = "DoLP";
	if (o.dolp_hi < 0) {
		const size_t dd_bytes = (size_t)width * height * 2 * sizeof(float);
		float *dd = ws_get(&ws->dd, &ws->dd_n, dd_bytes);
		if (!dd)
			return pc_error(PC_ENOMEM, "pictures: %ux%u DoLP copy", width, height);
		float *ss = dd + (size_t)width * height;
		for (uint32_t y = 0; y < height; y++)
			for (uint32_t x = 0; x < width; x++) {
				const pc_fplane *d = &st->dolp, *s = &st->s0;
				bool bad = valid && valid->mask &&
				           !valid->mask[(size_t)y * valid->row_stride + x];
				/* invalid pixels stay out of the range (NaN is skipped) */
				dd[(size_t)y * width + x] =
				    bad ? NAN : d->data[y * d->row_stride + x * d->pixel_stride];
				ss[(size_t)y * width + x] =
				    s->data[y * s->row_stride + x * s->pixel_stride];
			}
		dhi = pc_pictures_dolp_auto(dd, ss, (size_t)width * height, mask);
		snprintf(dlabel, sizeof dlabel, "DoLP (0..%.2f, auto)", dhi);
	} else if (dhi < 1) {
		snprintf(dlabel, sizeof dlabel, "DoLP (0..%.2f)", dhi);
	}
	const uint8_t *vm = valid && valid->mask ? valid->mask : NULL;
	const size_t vs = vm ? valid->row_stride : 0, rs = (size_t)width * 3;
	char bad_note[80];
	const size_t n_bad = invalid_count(valid, width, height, bad_note);
	pc_legend_note bad = {bad_note, pc_picture_invalid_rgb, NULL};
	pc_legend_note note = {mask_note, pc_picture_mask_rgb, n_bad ? &bad : NULL};
	const pc_legend_note *np = mask > -INFINITY ? &note : n_bad ? &bad : NULL;
	const pc_legend_note *nb = n_bad ? &bad : NULL;
	int rc = 0;
	if (sink->kinds & PIC_S0) {
		rc = pc_picture_grey(&st->s0, width, height, 0, hi, rgb, rs);
		pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
		pc_colorbar bar = {"S0 (raw units)",    0,    hi, NULL, 0, 0,
		                   pc_picture_grey_key, NULL, 0};
		snprintf(title, sizeof title, "%sS0 (total intensity)", pre);
		if (!rc)
			rc = sink->put(sink, 0, "s0", rgb, title, "S0 (total intensity)", &bar, nb);
	}
	if (!rc && (sink->kinds & PIC_DOLP)) {
		rc = pc_picture_grey(&st->dolp, width, height, 0, (float)dhi, rgb, rs);
		if (mask > -INFINITY)
			pc_picture_mask_low(&st->s0, width, height, mask, rgb, rs);
		pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
		pc_colorbar dbar = {dlabel, 0, dhi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
		snprintf(title, sizeof title, "%sDoLP (degree of linear polarization)%s", pre,
		         mask_title);
		if (!rc)
			rc = sink->put(sink, 1, "dolp", rgb, title, "DoLP", &dbar, np);
	}
	static const pc_aolp_style styles[2] = {PC_AOLP_VALUE, PC_AOLP_SATURATION};
	static const char *names[2] = {"aolp", "aolp_sat"};
	static const char *what[2] = {"value", "saturation"};
	static const unsigned kind[2] = {PIC_AOLP, PIC_AOLP_SAT};
	for (int k = 0; k < 2 && !rc; k++) {
		if (!(sink->kinds & kind[k]))
			continue;
		rc = pc_picture_aolp(&st->aolp, &st->dolp, width, height, styles[k], (float)dhi,
		                     rgb, rs);
		if (!rc && mask > -INFINITY)
			pc_picture_mask_low(&st->s0, width, height, mask, rgb, rs);
		if (!rc)
			pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
		pc_colorbar abar = {"AoLP (deg, from x, counter-clockwise)",
		                    0,
		                    180,
		                    "DoLP",
		                    0,
		                    dhi,
		                    pc_picture_aolp_key,
		                    (void *)&styles[k],
		                    45};
		snprintf(title, sizeof title, "%sAoLP (hue) with DoLP (%s)%s", pre, what[k],
		         mask_title);
		char short_title[64];
		snprintf(short_title, sizeof short_title, "AoLP (hue), DoLP (%s)", what[k]);
		if (!rc)
			rc = sink->put(sink, 2 + k, names[k], rgb, title, short_title, &abar, np);
	}
	return rc;
}

int pc_pictures_write_valid(const char *dir, const pc_stokes_out *st, uint32_t width,
                            uint32_t height, const pc_pictures_opts *opts, const pc_validity *valid)
{
	if (!dir)
		return pc_error(PC_EINVAL, "pictures: no folder given");
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	pic_sink k = {put_file, PIC_S0 | PIC_DOLP | PIC_AOLP | PIC_AOLP_SAT,
	              dir,      &o,
	              width,    height,
	              NULL,     0,
	              0,        0,
	              0,        0,
	              NULL};
	int rc = pc_pictures_live_new(&k.ws);
	if (!rc)
		rc = draw_set(st, width, height, &o, valid, &k);
	pc_pictures_live_free(k.ws);
	return rc;
}

/* The panels' width for an image drawn iw wide: S0, DoLP and AoLP with their bars. */
static uint32_t panels_width(uint32_t width, uint32_t height, uint32_t iw, uint32_t *ph)
{
	static const pc_colorbar grey = {"", 0, 1, NULL, 0, 0, NULL, NULL, 0},
	                         key2 = {"", 0, 1, "", 0, 1, NULL, NULL, 0};
	uint32_t w1, w2, h1, h2;
	pc_image_annotated_size(width, height, iw, true, &grey, &w1, &h1);
	pc_image_annotated_size(width, height, iw, true, &key2, &w2, &h2);
	*ph = h1 > h2 ? h1 : h2;
	return 2 * w1 + w2 + 2 * PANEL_GAP;
}

int pc_pictures_live_new(pc_pictures_live **out)
{
	*out = calloc(1, sizeof **out);
	return *out ? 0 : pc_error(PC_ENOMEM, "live pictures");
}

void pc_pictures_live_free(pc_pictures_live *p)
{
	if (!p)
		return;
	free(p->rgb);
	free(p->xrgb);
	free(p->xout);
	free(p->dd);
	free(p->out);
	free(p);
}

int pc_pictures_panels(const pc_stokes_out *st, uint32_t width, uint32_t height,
                       const pc_pictures_opts *opts, const pc_validity *valid, uint32_t out_width,
                       uint32_t top, uint8_t **out, uint32_t *out_height)
{
	*out = NULL;
	*out_height = 0;
	pc_pictures_live *p;
	int rc = pc_pictures_live_new(&p);
	const uint8_t *pic = NULL;
	if (!rc)
		rc = pc_pictures_live_draw(p, st, width, height, opts, valid, out_width, top, &pic,
		                           out_height);
	if (!rc) { /* the picture leaves with the caller */
		*out = p->out;
		p->out = NULL;
	}
	pc_pictures_live_free(p);
	return rc;
}

int pc_pictures_live_draw(pc_pictures_live *p, const pc_stokes_out *st, uint32_t width,
                          uint32_t height, const pc_pictures_opts *opts, const pc_validity *valid,
                          uint32_t out_width, uint32_t top, const uint8_t **out,
                          uint32_t *out_height)
{
	*out = NULL;
	*out_height = 0;
	if (!width || !height)
		return pc_error(PC_EINVAL, "panels: empty image %ux%u", width, height);
	if (out_width < PC_PICTURES_PANELS_MIN_WIDTH || out_width > 30000 || top > 1000)
		return pc_error(PC_EINVAL,
		                "panels: width %u: expected %u to 30000 pixels (three pictures "
		                "with their keys), a status strip of at most 1000",
		                out_width, PC_PICTURES_PANELS_MIN_WIDTH);
	/* the widest image that leaves room for the three keys; height in proportion (the
	 * frames' aspect ratio) */
	uint32_t iw = out_width / 3, ph = 0;
	for (int i = 0; i < 64 && iw > 8; i++) {
		uint32_t pw = panels_width(width, height, iw, &ph);
		if (pw <= out_width)
			break;
		uint32_t d = (pw - out_width + 2) / 3;
		iw -= d < iw - 8 ? d : iw - 8;
	}
	if (panels_width(width, height, iw, &ph) > out_width)
		return pc_error(PC_EINVAL, "panels: width %u too small for the keys", out_width);
	const uint32_t oh = top + ph;
	uint8_t *buf = ws_get(&p->out, &p->out_n, (size_t)out_width * oh * 3);
	uint32_t *xrgb = ws_get(&p->xrgb, &p->xrgb_n, (size_t)width * height * sizeof(uint32_t));
	if (!buf || !xrgb)
		return pc_error(PC_ENOMEM, "panels: %ux%u picture", out_width, oh);
	memset(buf, 255, (size_t)out_width * oh * 3);
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	pic_sink k = {put_panel, PIC_S0 | PIC_DOLP | PIC_AOLP,
	              NULL,      &o,
	              width,     height,
	              buf,       out_width,
	              oh,        iw,
	              0,         top,
	              p};
	int rc = draw_set(st, width, height, &o, valid, &k);
	if (rc)
		return rc;
	*out = buf;
	*out_height = oh;
	return 0;
}

/* The four pictures from Imin/Imax planes already computed (mo, as pc_stokes_minmax writes
 * them; the ones not drawn may be NULL). */
int pc_pictures_write_minmax_planes(const char *dir, const pc_stokes_out *st,
                                    const pc_minmax_out *mo, uint32_t width, uint32_t height,
                                    const pc_pictures_opts *opts, const pc_validity *valid,
                                    bool minmax, bool split)
{
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	if (!(isfinite(o.s0_hi) && o.s0_hi >= 0))
		return pc_error(PC_EINVAL, "pictures: S0 scale %g: expected a finite value >= 0",
		                o.s0_hi);
	uint8_t *rgb = malloc((size_t)width * height * 3);
	if (!rgb)
		return pc_error(PC_ENOMEM, "pictures: %ux%u Imin/Imax pictures", width, height);
	const float hi = s0_scale(st, width, height, o.s0_hi); /* as the S0 picture */
	const uint8_t *vm = valid && valid->mask ? valid->mask : NULL;
	const size_t vs = vm ? valid->row_stride : 0, rs = (size_t)width * 3;
	char bad_note[80];
	const size_t n_bad = invalid_count(valid, width, height, bad_note);
	pc_legend_note bad = {bad_note, pc_picture_invalid_rgb, NULL};
	char pre[96] = "";
	if (o.title_prefix && *o.title_prefix)
		snprintf(pre, sizeof pre, "%s: ", o.title_prefix);
	static const struct {
		const char *name, *title, *label;
	} pics[4] = {
	    {"imin", "Imin (minimum over analyser angles) = (S0 - |S_lin|)/2", "Imin (raw units)"},
	    {"imax", "Imax (maximum over analyser angles) = (S0 + |S_lin|)/2", "Imax (raw units)"},
	    {"diffuse", "diffuse = 2 Imin (unpolarized part)", "diffuse (raw units)"},
	    {"specular", "specular = Imax - Imin (polarized part)", "specular (raw units)"}};
	const pc_fplane *pl[4] = {&mo->imin, &mo->imax, &mo->diffuse, &mo->specular};
	int rc = 0;
	for (int k = 0; k < 4 && !rc; k++) {
		if (!(k < 2 ? minmax : split))
			continue;
		if (!pl[k]->data) {
			rc = pc_error(PC_EINVAL, "pictures: %s image not computed", pics[k].name);
			break;
		}
		rc = pc_picture_grey(pl[k], width, height, 0, hi, rgb, rs);
		pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
		pc_colorbar bar = {pics[k].label, 0, hi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
		char title[320];
		snprintf(title, sizeof title, "%s%s", pre, pics[k].title);
		if (!rc)
			rc = write_one(dir, pics[k].name, o.suffix, rgb, width, height, title, &bar,
			               n_bad ? &bad : NULL, o.max_width);
	}
	free(rgb);
	return rc;
}

int pc_pictures_write_minmax(const char *dir, const pc_stokes_out *st, uint32_t width,
                             uint32_t height, const pc_pictures_opts *opts,
                             const pc_validity *valid, bool minmax, bool split)
{
	if (!dir || !st || !st->s0.data || !st->s1.data || !st->s2.data)
		return pc_error(PC_EINVAL, "pictures: S0, S1 and S2 images are needed");
	const size_t n = (size_t)width * height;
	float *planes = malloc(sizeof(float) * n * 4);
	if (!planes)
		return pc_error(PC_ENOMEM, "pictures: %ux%u Imin/Imax images", width, height);
	pc_minmax_out mo = {{planes, width, 1},
	                    {planes + n, width, 1},
	                    {planes + 2 * n, width, 1},
	                    {planes + 3 * n, width, 1}};
	int rc = pc_stokes_minmax(&st->s0, &st->s1, &st->s2, width, height, &mo);
	if (!rc)
		rc = pc_pictures_write_minmax_planes(dir, st, &mo, width, height, opts, valid,
		                                     minmax, split);
	free(planes);
	return rc;
}

/* An RGB picture of three float planes (one per colour channel), each linear from 0 to hi,
 * non-finite values magenta as in pc_picture_grey. */
static void draw_rgb(const pc_fplane *p[3], uint32_t width, uint32_t height, float hi, uint8_t *rgb,
                     size_t rs)
{
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			uint8_t *o = rgb + (size_t)y * rs + 3 * (size_t)x;
			float v[3];
			bool bad = false;
			for (int c = 0; c < 3; c++) {
				v[c] = p[c]->data[y * p[c]->row_stride + x * p[c]->pixel_stride];
				bad |= !isfinite(v[c]);
			}
			for (int c = 0; c < 3; c++) {
				/* as pc_picture_grey: 255·t rounded half up, clipped */
				double t = (double)v[c] / hi;
				o[c] = !(t > 0) ? 0 : t >= 1 ? 255 : (uint8_t)(t * 255.0 + 0.5);
			}
			if (bad)
				o[0] = 255, o[1] = 0, o[2] = 255;
		}
}

int pc_pictures_write_colour(const char *dir, const pc_stokes_out *rgbst, uint32_t width,
                             uint32_t height, const pc_pictures_opts *opts,
                             const pc_validity *valid)
{
	if (!dir || !rgbst)
		return pc_error(PC_EINVAL, "colour pictures: no folder or no Stokes images");
	for (int c = 0; c < 3; c++)
		if (!rgbst[c].s0.data || !rgbst[c].dolp.data)
			return pc_error(PC_EINVAL, "colour pictures: S0 and DoLP of R, G and B are "
			                           "needed");
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	if (!isfinite(o.mask_s0) || !(isfinite(o.s0_hi) && o.s0_hi >= 0) || !isfinite(o.dolp_hi))
		return pc_error(PC_EINVAL,
		                "colour pictures: mask %g, S0 scale %g, DoLP range %g: "
		                "expected finite values, a scale >= 0",
		                o.mask_s0, o.s0_hi, o.dolp_hi);
	const size_t n = (size_t)width * height;
	uint8_t *rgb = malloc(n * 3);
	float *smin = malloc(n * sizeof *smin), *dd = malloc(3 * n * sizeof *dd);
	if (!rgb || !smin || !dd) {
		free(rgb);
		free(smin);
		free(dd);
		return pc_error(PC_ENOMEM, "colour pictures: %ux%u images", width, height);
	}
	/* one S0 scale for the three channels (the largest of their 99.9th percentiles), so
	 * that the colours are the sensor's: no white balance */
	float hi = (float)o.s0_hi;
	for (int c = 0; c < 3 && !(o.s0_hi > 0); c++) {
		float q = pc_picture_quantile(&rgbst[c].s0, width, height, 0.999);
		hi = q > hi ? q : hi;
	}
	if (!(hi > 0))
		hi = 1;
	const float mask = o.mask_s0 > 0    ? (float)o.mask_s0
	                   : o.mask_s0 == 0 ? (float)(PC_PICTURES_MASK_DEFAULT_REL * hi)
	                                    : -INFINITY;
	/* a colour's DoLP is noise where its own S0 is low: the hatch goes where the darkest
	 * channel is below the threshold */
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			float m = INFINITY;
			for (int c = 0; c < 3; c++) {
				const pc_fplane *s = &rgbst[c].s0;
				float v = s->data[y * s->row_stride + x * s->pixel_stride];
				m = isfinite(v) && v < m ? v : isfinite(v) ? m : -INFINITY;
			}
			smin[(size_t)y * width + x] = m;
		}
	const uint8_t *vm = valid && valid->mask ? valid->mask : NULL;
	const size_t vs = vm ? valid->row_stride : 0, rs = (size_t)width * 3;
	double dhi = o.dolp_hi > 0 ? fmin(o.dolp_hi, 1) : 1;
	char dlabel[80] = "DoLP of R, G, B";
	if (o.dolp_hi < 0) {
		/* automatic: over the three channels' unmasked, valid pixels */
		for (int c = 0; c < 3; c++)
			for (uint32_t y = 0; y < height; y++)
				for (uint32_t x = 0; x < width; x++) {
					const pc_fplane *d = &rgbst[c].dolp;
					bool bad = vm && !vm[(size_t)y * vs + x];
					dd[c * n + (size_t)y * width + x] =
					    bad || !(smin[(size_t)y * width + x] >= mask)
					        ? NAN
					        : d->data[y * d->row_stride + x * d->pixel_stride];
				}
		dhi = pc_pictures_dolp_auto(dd, NULL, 3 * n, 0);
		snprintf(dlabel, sizeof dlabel, "DoLP of R, G, B (0..%.2f, auto)", dhi);
	} else if (dhi < 1) {
		snprintf(dlabel, sizeof dlabel, "DoLP of R, G, B (0..%.2f)", dhi);
	}
	char bad_note[80], mask_note[64] = "", mask_title[128] = "", title[320], pre[96] = "";
	const size_t n_bad = invalid_count(valid, width, height, bad_note);
	pc_legend_note bad = {bad_note, pc_picture_invalid_rgb, NULL};
	pc_legend_note note = {mask_note, pc_picture_mask_rgb, n_bad ? &bad : NULL};
	if (mask > -INFINITY) {
		snprintf(mask_note, sizeof mask_note, "S0 < %.4g", mask);
		snprintf(mask_title, sizeof mask_title,
		         "; hatched: S0 of a colour < %.4g, low signal", mask);
	}
	if (o.title_prefix && *o.title_prefix)
		snprintf(pre, sizeof pre, "%s: ", o.title_prefix);
	const pc_fplane *s0p[3] = {&rgbst[0].s0, &rgbst[1].s0, &rgbst[2].s0};
	const pc_fplane *dp[3] = {&rgbst[0].dolp, &rgbst[1].dolp, &rgbst[2].dolp};
	draw_rgb(s0p, width, height, hi, rgb, rs);
	pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
	pc_colorbar bar = {
	    "S0 of each colour (raw units)", 0, hi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
	snprintf(title, sizeof title, "%sS0 in colour (R, G, B as the sensor saw them)", pre);
	int rc = write_one(dir, "s0_rgb", o.suffix, rgb, width, height, title, &bar,
	                   n_bad ? &bad : NULL, o.max_width);
	if (!rc) {
		draw_rgb(dp, width, height, (float)dhi, rgb, rs);
		pc_fplane sm = {smin, width, 1};
		if (mask > -INFINITY)
			pc_picture_mask_low(&sm, width, height, mask, rgb, rs);
		pc_picture_mask_invalid(vm, vs, width, height, rgb, rs);
		pc_colorbar dbar = {dlabel, 0, dhi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
		snprintf(title, sizeof title, "%sDoLP of each colour as R, G, B%s", pre,
		         mask_title);
		rc = write_one(dir, "dolp_rgb", o.suffix, rgb, width, height, title, &dbar,
		               mask > -INFINITY ? &note
		               : n_bad          ? &bad
		                                : NULL,
		               o.max_width);
	}
	free(rgb);
	free(smin);
	free(dd);
	return rc;
}

/* The ellipticity key: blue (−45°, S3 < 0) through white (linear) to red (+45°, S3 > 0). */
static void diverging_key(double t, double s, uint8_t rgb[3], void *ctx)
{
	(void)s, (void)ctx;
	const double v = 2 * t - 1;
	const uint8_t k = (uint8_t)(255.0 * (1 - fabs(v)) + 0.5);
	rgb[0] = v < 0 ? k : 255;
	rgb[1] = k;
	rgb[2] = v > 0 ? k : 255;
}

int pc_pictures_write_circular(const char *dir, const pc_fplane *s0, const pc_fplane *docp,
                               const pc_fplane *ellipticity, uint32_t width, uint32_t height,
                               const pc_pictures_opts *opts)
{
	if (!dir || !s0 || !docp || !ellipticity || !s0->data || !docp->data || !ellipticity->data)
		return pc_error(PC_EINVAL, "circular pictures: S0, DoCP and ellipticity needed");
	pc_pictures_opts o = {NULL, 0, 0, NULL, 0, 0};
	if (opts)
		o = *opts;
	if (!isfinite(o.mask_s0) || !(isfinite(o.s0_hi) && o.s0_hi >= 0) || !isfinite(o.dolp_hi))
		return pc_error(PC_EINVAL,
		                "circular pictures: mask %g, S0 scale %g, DoCP range %g: "
		                "expected finite values, a scale >= 0",
		                o.mask_s0, o.s0_hi, o.dolp_hi);
	const size_t n = (size_t)width * height;
	uint8_t *rgb = malloc(n * 3);
	float *dd = malloc(n * 2 * sizeof *dd);
	if (!rgb || !dd) {
		free(rgb);
		free(dd);
		return pc_error(PC_ENOMEM, "circular pictures: %ux%u images", width, height);
	}
	pc_stokes_out st = {*s0, {NULL, 0, 0}, {NULL, 0, 0}, *docp, {NULL, 0, 0}};
	const float hi = s0_scale(&st, width, height, o.s0_hi);
	const float mask = o.mask_s0 > 0    ? (float)o.mask_s0
	                   : o.mask_s0 == 0 ? (float)(PC_PICTURES_MASK_DEFAULT_REL * hi)
	                                    : -INFINITY;
	/* the DoCP range as the DoLP's (pc_pictures_opts.dolp_hi) */
	double dhi = o.dolp_hi > 0 ? fmin(o.dolp_hi, 1) : 1;
	char dlabel[64] = "DoCP";
	if (o.dolp_hi < 0) {
		for (uint32_t y = 0; y < height; y++)
			for (uint32_t x = 0; x < width; x++) {
				dd[(size_t)y * width + x] =
				    docp->data[y * docp->row_stride + x * docp->pixel_stride];
				dd[n + (size_t)y * width + x] =
				    s0->data[y * s0->row_stride + x * s0->pixel_stride];
			}
		dhi = pc_pictures_dolp_auto(dd, dd + n, n, mask);
		snprintf(dlabel, sizeof dlabel, "DoCP (0..%.2f, auto)", dhi);
	} else if (dhi < 1) {
		snprintf(dlabel, sizeof dlabel, "DoCP (0..%.2f)", dhi);
	}
	char pre[96] = "", mask_note[64] = "", mask_title[128] = "", title[320];
	if (o.title_prefix && *o.title_prefix)
		snprintf(pre, sizeof pre, "%s: ", o.title_prefix);
	if (mask > -INFINITY) {
		snprintf(mask_note, sizeof mask_note, "S0 < %.4g", mask);
		snprintf(mask_title, sizeof mask_title, "; hatched: S0 < %.4g, low signal", mask);
	}
	pc_legend_note note = {mask_note, pc_picture_mask_rgb, NULL};
	const pc_legend_note *np = mask > -INFINITY ? &note : NULL;
	const size_t rs = (size_t)width * 3;
	int rc = pc_picture_grey(docp, width, height, 0, (float)dhi, rgb, rs);
	if (!rc && mask > -INFINITY)
		pc_picture_mask_low(s0, width, height, mask, rgb, rs);
	pc_colorbar dbar = {dlabel, 0, dhi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
	snprintf(title, sizeof title, "%sDoCP |S3|/S0 (circular polarization)%s", pre, mask_title);
	if (!rc)
		rc = write_one(dir, "docp", o.suffix, rgb, width, height, title, &dbar, np,
		               o.max_width);
	if (!rc) {
		/* ellipticity angle in degrees on the diverging key, magenta where not finite */
		for (uint32_t y = 0; y < height; y++)
			for (uint32_t x = 0; x < width; x++) {
				float e = ellipticity->data[y * ellipticity->row_stride +
				                            x * ellipticity->pixel_stride];
				uint8_t *q = rgb + (size_t)y * rs + 3 * (size_t)x;
				if (!isfinite(e)) {
					q[0] = 255, q[1] = 0, q[2] = 255;
					continue;
				}
				double t = 0.5 + (double)e / (M_PI / 2);
				diverging_key(t < 0 ? 0 : t > 1 ? 1 : t, 0, q, NULL);
			}
		if (mask > -INFINITY)
			pc_picture_mask_low(s0, width, height, mask, rgb, rs);
		pc_colorbar ebar = {"ellipticity angle (deg; + : S3 > 0)",
		                    -45,
		                    45,
		                    NULL,
		                    0,
		                    0,
		                    diverging_key,
		                    NULL,
		                    15};
		snprintf(title, sizeof title, "%sellipticity (red S3 > 0, blue < 0)%s", pre,
		         mask_title);
		rc = write_one(dir, "ellipticity", o.suffix, rgb, width, height, title, &ebar, np,
		               o.max_width);
	}
	free(rgb);
	free(dd);
	return rc;
}
