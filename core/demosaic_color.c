/* Colour-polarization demosaicking (Sony IMX250MYR: each 2×2 polarizer block under one colour
 * of a Bayer pattern, 4×4 period; polarcam/mosaic.h draws it).
 *
 * Both methods demosaic colour first, at the analysers' own half resolution, then polarization:
 *
 *  1. For analyser c at (cx, cy) of the 2×2 polarizer block, the sub-image
 *     A_c(i, j) = raw(cx + 2i, cy + 2j) holds one pixel of every polarizer block, so its
 *     colours follow the blocks' Bayer pattern: A_c is an ordinary Bayer mosaic at half
 *     resolution (whatever the crop phase). Bilinear Bayer demosaicking of A_c (a sample of
 *     colour k keeps its value; elsewhere the normalised tent (2−|dx|)(2−|dy|) over the
 *     colour's samples of the 3×3 sub-image neighbourhood) gives R, G and B of analyser c at
 *     its own pixels. Borders mirror inside the sub-image
 *     (whole-sample), which keeps the Bayer parity, hence the colour.
 *  2. For each colour k, the full-resolution image M_k(x, y) = colour k of analyser ch(x, y) at
 *     its own pixel is a monochrome polarizer mosaic; a monochrome method demosaics it into
 *     I_{k,c} for the four analysers: bilinear for "bayer-first" (the colour-first baseline of
 *     Morimatsu et al. 2020), EARI for "bayer-eari".
 *
 * This file holds step 1 (demosaic_color.h): in double for the reference, in float on row bands
 * for the fast path. The front door runs step 2 through the monochrome paths of the method
 * table (the reference or the fast kernel of the method's second step). */
#include "demosaic_color.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"

pc_mosaic pc_dm_color_mono(const pc_mosaic *m)
{
	pc_mosaic r;
	memset(&r, 0, sizeof r);
	r.period = 2;
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			r.channel[y][x] = m->channel[y & 1][x & 1];
	return r;
}

/* Step 1 for one sub-image row j of analyser c: colour k at sub-pixel (i, j) from the raw. The
 * accessor reads raw(cx + 2i, cy + 2j) with i, j mirrored in the sub-image. Generic over the
 * sample type through the get() callback (double reference or float fast path). */
typedef double (*rawget_fn)(const void *img, uint32_t w, int x, int y);

static double get_f64(const void *img, uint32_t w, int x, int y)
{
	return ((const double *)img)[(size_t)y * w + x];
}

static double bayer_tent(const void *img, rawget_fn get, const pc_mosaic *m, uint32_t w, uint32_t h,
                         unsigned cx, unsigned cy, int i, int j, unsigned colour)
{
	int sw = (int)(w / 2), sh = (int)(h / 2);
	/* a sample of the colour keeps its value (for G the tent would also average the four
	 * diagonal G samples of the quincunx) */
	if (pc_mosaic_color(m, cx + 2 * (uint32_t)i, cy + 2 * (uint32_t)j) == colour)
		return get(img, w, (int)cx + 2 * i, (int)cy + 2 * j);
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

/* Reference: rows [j0, j1) of the sub-images (full-resolution rows cy + 2j). */
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
					double v = bayer_tent(cj->img, cj->get, cj->m, cj->w, cj->h,
					                      cx, cy, (int)i, (int)j, PC_CFA_R + k);
					if (cj->dbl)
						((double *)cj->mk[k])[at] = v;
					else
						((float *)cj->mk[k])[at] = (float)v;
				}
			}
	}
}

/* Fast step 1, float. In a Bayer sub-image every colour k at a sub-pixel is one of: the pixel
 * itself, the mean of the horizontal pair, of the vertical pair, of the four diagonals, or of
 * the four plus-neighbours (G at R and B) — the normalised tent's five cases. The case depends
 * only on the sub-pixel's parities, so it is looked up once per row and column parity; the
 * mirrored neighbour columns are precomputed. */
enum { BK_SELF, BK_H, BK_V, BK_DIAG, BK_PLUS };

static int bayer_kind(const pc_mosaic *m, unsigned cx, unsigned cy, unsigned pi, unsigned pj,
                      unsigned colour)
{
	/* colours of the 3×3 sub-neighbourhood of a sub-pixel with parities (pi, pj) */
#define COL(di, dj) pc_mosaic_color(m, cx + 2 * (pi + 2 + (di)), cy + 2 * (pj + 2 + (dj)))
	if (COL(0, 0) == colour)
		return BK_SELF;
	int h = COL(-1, 0) == colour, v = COL(0, -1) == colour;
	return h && v ? BK_PLUS : h ? BK_H : v ? BK_V : BK_DIAG;
#undef COL
}

typedef struct colf_job {
	const float *img;
	const pc_mosaic *m;
	uint32_t w, h;
	float *mk[3];
	const int32_t *xm, *xp; /* per analyser column parity: mirrored sub-columns i-1, i+1 */
} colf_job;

static void colf_band(void *ctx, uint32_t j0, uint32_t j1)
{
	colf_job *cj = ctx;
	uint32_t w = cj->w, sw = w / 2;
	int sh = (int)(cj->h / 2);
	for (unsigned c = 0; c < 4; c++) {
		unsigned cx, cy;
		pc_mosaic_channel_pos(cj->m, c, &cx, &cy);
		const int32_t *xm = cj->xm + (size_t)cx * sw, *xp = cj->xp + (size_t)cx * sw;
		for (uint32_t j = j0; j < j1; j++) {
			int jm = pc_mirror((int)j - 1, sh), jp = pc_mirror((int)j + 1, sh);
			const float *r0 = cj->img + (size_t)(cy + 2 * (uint32_t)jm) * w;
			const float *r1 = cj->img + (size_t)(cy + 2 * j) * w;
			const float *r2 = cj->img + (size_t)(cy + 2 * (uint32_t)jp) * w;
			size_t row = (size_t)(cy + 2 * j) * w;
			for (unsigned k = 0; k < 3; k++) {
				int kind[2] = {bayer_kind(cj->m, cx, cy, 0, j & 1, PC_CFA_R + k),
				               bayer_kind(cj->m, cx, cy, 1, j & 1, PC_CFA_R + k)};
				float *dst = cj->mk[k] + row;
				for (uint32_t i = 0; i < sw; i++) {
					uint32_t x = cx + 2 * i;
					int32_t a = xm[i], b = xp[i];
					float v;
					switch (kind[i & 1]) {
					case BK_SELF:
						v = r1[x];
						break;
					case BK_H:
						v = 0.5f * (r1[a] + r1[b]);
						break;
					case BK_V:
						v = 0.5f * (r0[x] + r2[x]);
						break;
					case BK_DIAG:
						v = 0.25f * ((r0[a] + r0[b]) + (r2[a] + r2[b]));
						break;
					default:
						v = 0.25f * ((r1[a] + r1[b]) + (r0[x] + r2[x]));
						break;
					}
					dst[x] = v;
				}
			}
		}
	}
}

void pc_dm_color_split_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                           double *mk[3])
{
	col_job cj = {img, get_f64, m, w, h, {mk[0], mk[1], mk[2]}, 1};
	col_band(&cj, 0, h / 2);
}

int pc_dm_color_split(const float *img, uint32_t w, uint32_t h, const pc_mosaic *m, int threads,
                      float *mk[3])
{
	/* mirrored neighbour columns (full-resolution x) of every sub-column, per parity */
	uint32_t sw = w / 2;
	int32_t *xm = malloc(sizeof(int32_t) * 2 * sw), *xp = malloc(sizeof(int32_t) * 2 * sw);
	if (!xm || !xp) {
		free(xm);
		free(xp);
		return pc_error(PC_ENOMEM, "colour demosaicking: column tables");
	}
	for (uint32_t px = 0; px < 2; px++)
		for (uint32_t i = 0; i < sw; i++) {
			xm[px * sw + i] =
			    (int32_t)(px + 2 * (uint32_t)pc_mirror((int)i - 1, (int)sw));
			xp[px * sw + i] =
			    (int32_t)(px + 2 * (uint32_t)pc_mirror((int)i + 1, (int)sw));
		}
	colf_job cj = {img, m, w, h, {mk[0], mk[1], mk[2]}, xm, xp};
	pc_parallel_rows(h / 2, 0, threads, colf_band, &cj);
	free(xm);
	free(xp);
	return 0;
}
