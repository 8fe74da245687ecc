/* Colour-polarization demosaicking (Sony IMX250MYR: each 2×2 polarizer block under one colour
 * of a Bayer pattern, 4×4 period; polarcam/mosaic.h draws it).
 *
 * Both methods demosaic colour first, at the analysers' own half resolution, then polarization:
 *
 *  1. For analyser c at (cx, cy) of the 2×2 polarizer block, the sub-image
 *     A_c(i, j) = raw(cx + 2i, cy + 2j) holds one pixel of every polarizer block, so its
 *     colours follow the blocks' Bayer pattern: A_c is an ordinary Bayer mosaic at half
 *     resolution (whatever the crop phase). Bilinear Bayer demosaicking of A_c (the normalised
 *     tent (2−|dx|)(2−|dy|) over the colour's samples of the 3×3 sub-image neighbourhood) gives
 *     R, G and B of analyser c at its own pixels. Borders mirror inside the sub-image
 *     (whole-sample), which keeps the Bayer parity, hence the colour.
 *  2. For each colour k, the full-resolution image M_k(x, y) = colour k of analyser ch(x, y) at
 *     its own pixel is a monochrome polarizer mosaic; a monochrome method demosaics it into
 *     I_{k,c} for the four analysers: bilinear for "bayer-first" (the colour-first baseline of
 *     Morimatsu et al. 2020), EARI for "bayer-eari".
 *
 * The reference runs both steps in double (step 2 through the monochrome references); the fast
 * path runs step 1 in float on row bands and step 2 through the monochrome fast paths. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

/* The monochrome polarizer part of a colour mosaic. */
static pc_mosaic mono_part(const pc_mosaic *m)
{
	pc_mosaic r;
	memset(&r, 0, sizeof r);
	r.period = 2;
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			r.channel[y][x] = m->channel[y & 1][x & 1];
	return r;
}

static pc_demosaic_method second_step(pc_demosaic_method method)
{
	return method == PC_DM_BAYER_EARI ? PC_DM_EARI : PC_DM_BILINEAR;
}

/* Step 1 for one sub-image row j of analyser c: colour k at sub-pixel (i, j) from the raw. The
 * accessor reads raw(cx + 2i, cy + 2j) with i, j mirrored in the sub-image. Generic over the
 * sample type through the get() callback (double reference or float fast path). */
typedef double (*rawget_fn)(const void *img, uint32_t w, int x, int y);

static double get_f64(const void *img, uint32_t w, int x, int y)
{
	return ((const double *)img)[(size_t)y * w + x];
}

static double get_f32(const void *img, uint32_t w, int x, int y)
{
	return ((const float *)img)[(size_t)y * w + x];
}

static double bayer_tent(const void *img, rawget_fn get, const pc_mosaic *m, uint32_t w,
			 uint32_t h, unsigned cx, unsigned cy, int i, int j, unsigned colour)
{
	int sw = (int)(w / 2), sh = (int)(h / 2);
	double s = 0, ws = 0;
	for (int dj = -1; dj <= 1; dj++)
		for (int di = -1; di <= 1; di++) {
			int ii = pc_mirror(i + di, sw), jj = pc_mirror(j + dj, sh);
			int x = (int)cx + 2 * ii, y = (int)cy + 2 * jj;
			if (pc_mosaic_color(m, (uint32_t)x, (uint32_t)y) != colour)
				continue;
			double wt = (2 - abs(di)) * (2 - abs(dj));
			s += wt * get(img, w, x, y);
			ws += wt;
		}
	return s / ws;
}

typedef struct col_job {
	const void *img;
	rawget_fn get;
	const pc_mosaic *m;
	uint32_t w, h;
	void *mk[3]; /* M_k images, double or float */
	int dbl;
} col_job;

/* Rows [j0, j1) of the sub-images, i.e. full-resolution rows 2·j0 .. 2·j1. */
static void col_band(void *ctx, uint32_t j0, uint32_t j1)
{
	col_job *cj = ctx;
	for (unsigned c = 0; c < 4; c++) {
		unsigned cx, cy;
		pc_mosaic_channel_pos(cj->m, c, &cx, &cy);
		for (uint32_t j = j0; j < j1; j++)
			for (uint32_t i = 0; i < cj->w / 2; i++) {
				size_t at = (size_t)(cy + 2 * j) * cj->w + cx + 2 * i;
				for (unsigned k = 0; k < 3; k++) {
					double v = bayer_tent(cj->img, cj->get, cj->m, cj->w, cj->h, cx,
							      cy, (int)i, (int)j, PC_CFA_R + k);
					if (cj->dbl)
						((double *)cj->mk[k])[at] = v;
					else
						((float *)cj->mk[k])[at] = (float)v;
				}
			}
	}
}

int pc_demosaic_color(const pc_view *raw, const double *img_ref, const pc_mosaic *m,
		      pc_demosaic_method method, const pc_demosaic_opts *opts, double full_scale,
		      const pc_fplane *out);
int pc_demosaic_color(const pc_view *raw, const double *img_ref, const pc_mosaic *m,
		      pc_demosaic_method method, const pc_demosaic_opts *opts, double full_scale,
		      const pc_fplane *out)
{
	uint32_t w = raw->width, h = raw->height;
	size_t n = (size_t)w * h;
	int reference = img_ref != NULL;
	pc_mosaic mono = mono_part(m);
	int rc = 0;
	void *mk[3] = { NULL, NULL, NULL };
	float *fin = NULL;
	size_t esz = reference ? sizeof(double) : sizeof(float);
	for (int k = 0; k < 3; k++)
		if (!(mk[k] = malloc(n * esz)))
			rc = pc_error(PC_ENOMEM, "colour demosaicking: %ux%u images", w, h);
	if (!rc && !reference) {
		fin = malloc(n * sizeof(float));
		if (!fin)
			rc = pc_error(PC_ENOMEM, "colour demosaicking: %ux%u input", w, h);
		else
			rc = pc_view_to_f32(raw, fin, (size_t)w * sizeof(float));
		if (rc)
			pc_error_prefix(rc, "raw: ");
	}
	if (!rc) {
		col_job cj = { reference ? (const void *)img_ref : fin, reference ? get_f64 : get_f32,
			       m, w, h, { mk[0], mk[1], mk[2] }, reference };
		if (reference)
			col_band(&cj, 0, h / 2);
		else
			pc_parallel_rows(h / 2, 0, opts ? opts->threads : 0, col_band, &cj);
	}
	for (unsigned k = 0; k < 3 && !rc; k++) {
		const pc_fplane *o = out + 4 * k;
		if (reference) {
			rc = pc_demosaic_ref(mk[k], w, h, &mono, second_step(method), full_scale, o);
		} else {
			pc_view v = { mk[k], w, h, (size_t)w * sizeof(float), PC_FMT_FLOAT32 };
			pc_demosaic_opts o2 = { opts ? opts->threads : 0, false, full_scale };
			rc = pc_demosaic(&v, &mono, second_step(method), &o2, o);
		}
	}
	for (int k = 0; k < 3; k++)
		free(mk[k]);
	free(fin);
	return rc;
}
