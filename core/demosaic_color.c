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
 * table (the reference or the fast kernel of the method's second step), except for
 * bayer-first's fast path: both steps at once, their composed weights applied to the raw
 * (pc_dm_bayer_first, below). */
#include "demosaic_color.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_ref.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "simd.h"

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

int pc_dm_bayer_first_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                          pc_demosaic_method second, double fs, const pc_fplane *out)
{
	const size_t n = (size_t)w * h;
	double *buf = malloc(sizeof(double) * n * 3);
	if (!buf)
		return pc_error(PC_ENOMEM, "colour reference: images of %ux%u", w, h);
	double *md[3] = {buf, buf + n, buf + 2 * n};
	pc_dm_color_split_ref(img, w, h, m, md);
	const pc_mosaic mono = pc_dm_color_mono(m);
	int rc = 0;
	for (unsigned k = 0; k < 3 && !rc; k++)
		rc = pc_dm_ref(md[k], w, h, &mono, second, fs, 0, out + 4 * k);
	free(buf);
	return rc;
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

/* ---- bayer-first in one pass ----
 *
 * Away from the borders bayer-first is linear and shift-invariant on each (colour k, analyser c)
 * lattice of the raw (derived in docs/demosaicking.md, Round 15d): with
 *     T2 = [1/2 1 1/2] and T4 = [1/4 1/2 3/4 1 3/4 1/2 1/4] (offsets -1..1 and -3..3),
 * and s_{k,c} the raw masked to the samples of colour k and analyser c,
 *     R, B:  out_{k,c} = (T4 ⊗ T4) ⊛ s_{k,c}
 *     G:     out_{G,c} = ½ (T4 ⊗ T2 + T2 ⊗ T4) ⊛ s_{G,c}      (x ⊗ y)
 * (step 1's Bayer tent is [1/2 0 1 0 1/2]⊗[..] on R/B and δ + ¼ plus at distance 2 on G; step
 * 2's tent is T2 ⊗ T2; their composition). The kernel runs it as a vertical pass over the rows
 * of one analyser row parity cy, masked by colour, giving one row V that holds both analysers
 * of that parity (column parity = analyser's), then a horizontal pass split by the parity of
 * the offset: the even taps read the analyser of the output's column, the odd ones the other.
 * Output pixels within 3 of a border (where the two mirrors of the definition differ from a
 * shift-invariant filter) are computed by the composition itself, in double. */

/* The band's raw rows minus black, as floats: a ring of 8 rows keyed by row & 7 (an output
 * row reads the rows within ±3 of it, mirrored into the frame, never more than 7 distinct). */
typedef struct bf_ring {
	float *row[8];
	int32_t have[8];
} bf_ring;

static double get_ring(const void *img, uint32_t w, int x, int y)
{
	(void)w;
	const bf_ring *r = img;
	return r->row[y & 7][x];
}

/* M_k (step 1) at the rows mirror(y - 1), y, mirror(y + 1) and the columns xx in [x0, x1) into
 * mk[(dy + 1) * 3 + k][xx], each mirror as the reference applies it, in double. */
static void bf_mrows(const bf_ring *img, uint32_t w, uint32_t h, const pc_mosaic *m, int y,
                     uint32_t x0, uint32_t x1, double *const mk[9])
{
	for (int dy = -1; dy <= 1; dy++) {
		int yy = pc_mirror(y + dy, (int)h);
		for (uint32_t xx = x0; xx < x1; xx++) {
			unsigned ch = pc_mosaic_channel(m, xx, (uint32_t)yy), cx, cy;
			pc_mosaic_channel_pos(m, ch, &cx, &cy);
			for (unsigned k = 0; k < 3; k++)
				mk[(dy + 1) * 3 + k][xx] = bayer_tent(
				    img, get_ring, m, w, h, cx, cy, ((int)xx - (int)cx) / 2,
				    (yy - (int)cy) / 2, PC_CFA_R + k);
		}
	}
}

/* The 12 outputs of pixel (x, y) by the definition: step 2's tent (its mirror on the full
 * resolution grid) over the M_k rows of bf_mrows. */
static void bf_pixel(double *const mk[9], uint32_t w, const pc_mosaic *m, int x, int y,
                     double o[12])
{
	for (unsigned c = 0; c < 4; c++) {
		double s[3] = {0, 0, 0}, ws = 0;
		for (int dy = -1; dy <= 1; dy++)
			for (int dx = -1; dx <= 1; dx++) {
				/* the parity of x + dx is that of its mirror */
				if (pc_mosaic_channel(m, (uint32_t)(x + dx) & 3u,
				                      (uint32_t)(y + dy) & 3u) != c)
					continue;
				double wt = (2 - abs(dx)) * (2 - abs(dy));
				int xx = pc_mirror(x + dx, (int)w);
				for (unsigned k = 0; k < 3; k++)
					s[k] += wt * mk[(dy + 1) * 3 + k][xx];
				ws += wt;
			}
		for (unsigned k = 0; k < 3; k++)
			o[4 * k + c] = s[k] / ws;
	}
}

typedef struct bf_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	uint32_t w, h;
	const float *cmask; /* [k][y mod 4][x]: 1 where the raw's colour is k, else 0 */
	const pc_fplane *out;
	pc_cpu_level level;
	int fail;
} bf_job;

static void bf_put(const pc_fplane *out, uint32_t x, uint32_t y, const double o[12])
{
	for (unsigned p = 0; p < 12; p++)
		out[p].data[(size_t)y * out[p].row_stride + (size_t)x * out[p].pixel_stride] =
		    (float)o[p];
}

/* One interior output row (y at least 3 from the top and bottom) of columns [xa, xb): the
 * kernel instances (demosaic_bf_kern.inc, one per instruction-set level) of the vertical and
 * horizontal passes. */
typedef struct bf_row {
	const float *const *raw; /* ring rows by row & 7 */
	const float *cmask;
	uint32_t w, xa, xb;
	unsigned cxy[4][2];
	float *v[2][4], *eo[2], *pe, *po;
	float *dst[12]; /* the 12 output rows of this y (planes or, strided, scratch) */
} bf_row;

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_bf_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_bf_kern.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "demosaic_bf_kern.inc"
#include "simd_instance_end.h"
#else
/* other processors have the generic instance only (pc_cpu_active() is PC_CPU_BASELINE there) */
#define bf_interior_avx512 bf_interior_base
#define bf_interior_avx2   bf_interior_base
#define bf_gmask_avx512    bf_gmask_base
#define bf_gmask_avx2      bf_gmask_base
#define bf_gmean_avx512    bf_gmean_base
#define bf_gmean_avx2      bf_gmean_base
#endif

/* One band's buffers: the raw ring, the vertical rows, scratch rows for strided outputs, the
 * double M_k rows of the border pixels; kept across consecutive row ranges (the ring too). */
struct pc_dm_bf_band {
	bf_job j;
	float *cmask_own; /* pc_dm_bayer_first_band_new's masks, else NULL */
	float *buf;
	double *mbuf, *mk[9];
	bf_ring ring;
	float *tmp[12];
	bf_row row;
	float *grow[8]; /* pc_dm_bayer_first_band_gmean's raw rows masked to green, by row & 7 */
	int32_t ghave[8];
	int32_t mgr[4]; /* its M_G rows in mk[row & 3] (bf_mg_row), -1: none */
	/* rows lent by pc_dm_bayer_first_band_put_row (NULL: none): the ring holds only their
	 * BF_EDGE columns at either end, the rest read from the caller's row by the same _gmean
	 * call */
	const float *lent[8];
	int mgfull[4]; /* ... for every column, else the border ones */
};

static int bf_band_init(pc_dm_bf_band *b, const bf_job *j)
{
	memset(b, 0, sizeof *b);
	b->j = *j;
	const uint32_t w = j->w;
	const size_t pitch = (size_t)w + 2;
	/* 8 raw rows, 8 vertical rows (4 per row parity), 12 output rows for strided planes, 4
	 * more; 8 green rows */
	b->buf = malloc(sizeof(float) * pitch * (8 + 8 + 12 + 4 + 8));
	b->mbuf = malloc(sizeof(double) * 9 * (size_t)w);
	if (!b->buf || !b->mbuf) {
		free(b->buf);
		free(b->mbuf);
		return -1;
	}
	float *buf = b->buf;
	for (unsigned i = 0; i < 9; i++)
		b->mk[i] = b->mbuf + (size_t)i * w;
	for (unsigned i = 0; i < 8; i++) {
		b->ring.row[i] = buf + i * pitch + 1;
		b->ring.have[i] = -1;
		b->row.v[i / 4][i & 3] = buf + (8 + i) * pitch;
		b->grow[i] = buf + (32 + i) * pitch;
		b->ghave[i] = -1;
	}
	for (unsigned i = 0; i < 4; i++)
		b->mgr[i] = -1;
	for (unsigned i = 0; i < 12; i++)
		b->tmp[i] = buf + (16 + i) * pitch;
	/* e and o of one colour; the parity rows */
	float *pe = buf + 30 * pitch, *po = buf + 31 * pitch;
	for (uint32_t x = 0; x < w; x++) {
		pe[x] = x & 1 ? 0.0f : 1.0f;
		po[x] = x & 1 ? 1.0f : 0.0f;
	}
	b->row.raw = (const float *const *)b->ring.row;
	b->row.cmask = j->cmask;
	b->row.w = w;
	b->row.xa = 3; /* the interior columns [xa, xb) */
	b->row.xb = w - 3;
	b->row.eo[0] = buf + 28 * pitch;
	b->row.eo[1] = buf + 29 * pitch;
	b->row.pe = pe;
	b->row.po = po;
	for (unsigned c = 0; c < 4; c++)
		pc_mosaic_channel_pos(j->m, c, &b->row.cxy[c][0], &b->row.cxy[c][1]);
	return 0;
}

static void bf_band_fini(pc_dm_bf_band *b)
{
	free(b->buf);
	free(b->mbuf);
	free(b->cmask_own);
}

/* Output rows [y0, y1) into out, whose row y - oy holds row y. */
/* the raw rows y − 3 .. y + 3 (within the frame) into the band's ring, each converted once;
 * full: every row of the ring whole (a border row's M_G reads rows beyond y − 3 that the ring
 * still holds), the rows lent with their end columns only converted again */
static void bf_ring_load(pc_dm_bf_band *b, uint32_t y, int full)
{
	const uint32_t h = b->j.h;
	const int lo = (int)y - 3 < 0 ? 0 : (int)y - 3, hi = y + 3 < h ? (int)y + 3 : (int)h - 1;
	for (int i = 0; full && i < 8; i++)
		if (b->lent[i]) {
			pc_dm_row_to_float(b->j.in, (uint32_t)b->ring.have[i], b->ring.row[i]);
			b->lent[i] = NULL;
		}
	for (int r = lo; r <= hi; r++)
		if (b->ring.have[r & 7] != r) {
			pc_dm_row_to_float(b->j.in, (uint32_t)r, b->ring.row[r & 7]);
			b->ring.have[r & 7] = r;
			b->lent[r & 7] = NULL;
		}
}

static void bf_band_rows(pc_dm_bf_band *b, uint32_t y0, uint32_t y1, const pc_fplane *out,
                         uint32_t oy)
{
	const bf_job *j = &b->j;
	const uint32_t w = j->w, h = j->h;
	bf_ring *ring = &b->ring;
	bf_row *row = &b->row;
	const int strided = !pc_dm_planes_planar(out, 12);
	const uint32_t xa = row->xa, xb = row->xb;
	for (unsigned i = 0; i < 4; i++) /* mk is overwritten below */
		b->mgr[i] = -1;
	for (uint32_t y = y0; y < y1; y++) {
		bf_ring_load(b, y, 1);
		const uint32_t oyy = y - oy;
		double o12[12];
		if (y < 3 || y + 3 >= h) {
			bf_mrows(ring, w, h, j->m, (int)y, 0, w, b->mk);
			for (uint32_t x = 0; x < w; x++) {
				bf_pixel(b->mk, w, j->m, (int)x, (int)y, o12);
				bf_put(out, x, oyy, o12);
			}
			continue;
		}
		for (unsigned p = 0; p < 12; p++)
			row->dst[p] =
			    strided ? b->tmp[p] : out[p].data + (size_t)oyy * out[p].row_stride;
		if (j->level >= PC_CPU_AVX512)
			bf_interior_avx512(row, y);
		else if (j->level >= PC_CPU_AVX2)
			bf_interior_avx2(row, y);
		else
			bf_interior_base(row, y);
		if (strided)
			for (unsigned p = 0; p < 12; p++) {
				float *d = out[p].data + (size_t)oyy * out[p].row_stride;
				for (uint32_t x = xa; x < xb; x++)
					d[x * out[p].pixel_stride] = b->tmp[p][x];
			}
		/* the border columns: M_k at columns 0..3 and w - 4..w - 1 */
		bf_mrows(ring, w, h, j->m, (int)y, 0, 4, b->mk);
		bf_mrows(ring, w, h, j->m, (int)y, w - 4, w, b->mk);
		for (uint32_t x = 0; x < w; x++) {
			if (x == xa)
				x = xb;
			bf_pixel(b->mk, w, j->m, (int)x, (int)y, o12);
			bf_put(out, x, oyy, o12);
		}
	}
}

static void bf_band(void *ctx, uint32_t y0, uint32_t y1)
{
	bf_job *j = ctx;
	pc_dm_bf_band b;
	if (bf_band_init(&b, j)) {
		j->fail = 1;
		return;
	}
	bf_band_rows(&b, y0, y1, j->out, 0);
	bf_band_fini(&b);
}

/* 1 where the raw's colour is k, else 0: [k][y mod 4][x] */
static float *bf_masks(const pc_mosaic *m, uint32_t w)
{
	float *cmask = malloc(sizeof(float) * 12 * (size_t)w);
	if (!cmask)
		return NULL;
	for (unsigned k = 0; k < 3; k++)
		for (uint32_t r = 0; r < 4; r++)
			for (uint32_t x = 0; x < w; x++)
				cmask[((size_t)k * 4 + r) * w + x] =
				    pc_mosaic_color(m, x, r) == PC_CFA_R + k ? 1.0f : 0.0f;
	return cmask;
}

pc_dm_bf_band *pc_dm_bayer_first_band_new(const pc_dm_input *in, const pc_mosaic *m,
                                          pc_cpu_level level)
{
	pc_dm_bf_band *b = malloc(sizeof *b);
	float *cmask = bf_masks(m, in->width);
	bf_job j = {in, m, in->width, in->height, cmask, NULL, level, 0};
	if (!b || !cmask || bf_band_init(b, &j)) {
		free(b);
		free(cmask);
		return NULL;
	}
	b->cmask_own = cmask;
	return b;
}

void pc_dm_bayer_first_band_rows(pc_dm_bf_band *b, uint32_t y0, uint32_t y1, const pc_fplane *out)
{
	bf_band_rows(b, y0, y1, out, y0);
}

/* bayer-first's green at the border pixels for pc_dm_bayer_first_band_gmean, by the definition:
 * M_G (step 1, bf_mrows's) of frame row yy, kept in mk[yy & 3] for every column (full) or for
 * the border pixels' columns 0..3 and w − 4..w − 1 */
static const double *bf_mg_row(pc_dm_bf_band *b, int yy, int full)
{
	const bf_job *j = &b->j;
	const uint32_t w = j->w;
	double *r = b->mk[yy & 3];
	if (b->mgr[yy & 3] == yy && (b->mgfull[yy & 3] || !full))
		return r;
	for (uint32_t xx = 0; xx < w; xx++) {
		if (!full && xx == 4 && w > 8)
			xx = w - 4;
		unsigned ch = pc_mosaic_channel(j->m, xx, (uint32_t)yy), cx, cy;
		pc_mosaic_channel_pos(j->m, ch, &cx, &cy);
		r[xx] = bayer_tent(&b->ring, get_ring, j->m, w, j->h, cx, cy,
		                   ((int)xx - (int)cx) / 2, (yy - (int)cy) / 2, PC_CFA_G);
	}
	b->mgr[yy & 3] = yy;
	b->mgfull[yy & 3] = full;
	return r;
}

/* ... and the mean of the four analysers' step 2 at (x, y), rows r[0..2] = M_G at mirror(y − 1),
 * y, mirror(y + 1): each of the 3×3 neighbours belongs to one analyser, whose tent's weights
 * (2 − |dx|)(2 − |dy|) sum to 4, so the mean is their sum over 16. On integer raws M_G is a
 * multiple of 1/4 and every sum is exact: bf_pixel's four values, rounded to float, then their
 * mean (exact too) give the same float. */
static float bf_gpix(const double *const r[3], uint32_t w, int x)
{
	double s = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++)
			s += (double)((2 - abs(dx)) * (2 - abs(dy))) *
			     r[dy + 1][pc_mirror(x + dx, (int)w)];
	return (float)(s / 16);
}

void pc_dm_bayer_first_band_gmean(pc_dm_bf_band *b, uint32_t y, float *out)
{
	const bf_job *j = &b->j;
	const uint32_t w = j->w, h = j->h;
	bf_ring *ring = &b->ring;
	const int lo = (int)y - 3 < 0 ? 0 : (int)y - 3, hi = y + 3 < h ? (int)y + 3 : (int)h - 1;
	const int border = y < 3 || y + 3 >= h;
	bf_ring_load(b, y, border);
	for (int r = lo; r <= hi; r++) {
		if (border || b->ghave[r & 7] == r)
			continue;
		const float *mg = j->cmask + (4 + ((uint32_t)r & 3)) * (size_t)w,
		            *src = b->lent[r & 7] ? b->lent[r & 7] : ring->row[r & 7];
		if (j->level >= PC_CPU_AVX512)
			bf_gmask_avx512(src, mg, (long)w, b->grow[r & 7]);
		else if (j->level >= PC_CPU_AVX2)
			bf_gmask_avx2(src, mg, (long)w, b->grow[r & 7]);
		else
			bf_gmask_base(src, mg, (long)w, b->grow[r & 7]);
		b->ghave[r & 7] = r;
	}
	const double *mr[3];
	for (int dy = -1; dy <= 1; dy++)
		mr[dy + 1] = bf_mg_row(b, pc_mirror((int)y + dy, (int)h), border);
	if (border) { /* the definition */
		for (uint32_t x = 0; x < w; x++)
			out[x] = bf_gpix(mr, w, (int)x);
		return;
	}
	const float *g[7];
	for (int dy = -3; dy <= 3; dy++)
		g[dy + 3] = b->grow[((int)y + dy) & 7];
	float *v2 = b->row.v[0][0], *v4 = b->row.v[0][1];
	if (j->level >= PC_CPU_AVX512)
		bf_gmean_avx512(g, (long)w, v2, v4, out);
	else if (j->level >= PC_CPU_AVX2)
		bf_gmean_avx2(g, (long)w, v2, v4, out);
	else
		bf_gmean_base(g, (long)w, v2, v4, out);
	/* the border columns by the definition, as bf_band_rows */
	for (uint32_t x = 0; x < w; x++) {
		if (x == 3)
			x = w - 3;
		out[x] = bf_gpix(mr, w, (int)x);
	}
}

/* Lent rows keep their end columns in the ring: those bf_mg_row reads for the border pixels
 * of an interior row (bayer_tent's samples within 8 of either end at an even width, 9 at an
 * odd one) */
enum { BF_EDGE = 10 };

void pc_dm_bayer_first_band_put_row(pc_dm_bf_band *b, uint32_t y, const float *src)
{
	const uint32_t w = b->j.w;
	if (b->ring.have[y & 7] == (int32_t)y)
		return;
	float *d = b->ring.row[y & 7];
	if (w <= 2 * BF_EDGE) {
		memcpy(d, src, sizeof(float) * w);
		b->lent[y & 7] = NULL;
	} else {
		memcpy(d, src, sizeof(float) * BF_EDGE);
		memcpy(d + w - BF_EDGE, src + w - BF_EDGE, sizeof(float) * BF_EDGE);
		b->lent[y & 7] = src;
	}
	d[-1] = d[w > 1 ? 1 : 0]; /* pc_dm_row_to_float's mirror */
	d[w] = d[w > 1 ? w - 2 : 0];
	b->ring.have[y & 7] = (int32_t)y;
}

void pc_dm_bayer_first_band_free(pc_dm_bf_band *b)
{
	if (!b)
		return;
	bf_band_fini(b);
	free(b);
}

int pc_dm_bayer_first(const pc_dm_input *in, const pc_mosaic *m, int threads, pc_cpu_level level,
                      const pc_fplane *out)
{
	const uint32_t w = in->width, h = in->height;
	float *cmask = bf_masks(m, w);
	if (!cmask)
		return pc_error(PC_ENOMEM, "bayer-first: colour masks");
	bf_job j = {in, m, w, h, cmask, out, level, 0};
	pc_parallel_rows(h, 0, threads, bf_band, &j);
	free(cmask);
	return j.fail ? pc_error(PC_ENOMEM, "bayer-first: row buffers") : 0;
}
