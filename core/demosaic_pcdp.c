/* PCDP, polarization channel difference prior (Wu, Zhao, Li, et al., "Fast and accurate
 * polarization demosaicking based on polarization channel difference prior", Opt. Express
 * 29(14) 2021). The paper's text was not reachable for this implementation; the formulas
 * follow the method's published description as restated in the documentation of a public
 * course project that implements it (docs/demosaicking.md, "Anchors"):
 *
 *   Ĩ_j = bilinear interpolation of channel j ([1 2 1; 2 4 2; 1 2 1]/4 on the zero-filled
 *         samples, our tent);
 *   Δ^{i,j} = bilinear interpolation of channel i's samples of (raw − Ĩ_j), the difference
 *         of channel i to channel j, which varies less across edges than either channel
 *         (the "prior"), and most for orthogonal channels;
 *   I_i = Σ_{j ≠ i} w_ij (Ĩ_j + Δ^{i,j}), w = √2/(2 + √2) for the orthogonal channel,
 *         1/(2 + √2) for the other two (Σ_j w_ij = 1).
 *
 * Since the tent is linear and the weights sum to 1, I_i = G_i + tent_i(raw − G_i) with the
 * guide G_i = Σ_j w_ij Ĩ_j: residual interpolation with a guide made of the other channels'
 * bilinear estimates. The reference evaluates the published form literally, the fast path
 * the identity (equal within float rounding, tested). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

static double pcdp_weight(unsigned i, unsigned j)
{
	return (i ^ j) == 2 ? M_SQRT2 / (2 + M_SQRT2) : 1 / (2 + M_SQRT2);
}

static unsigned chan(const pc_mosaic *m, int x, int y)
{
	return m->channel[y & 1][x & 1];
}

/* tent of channel c's samples of f(x, y) around (x, y) */
static double tent_of(const pc_dimg *r, const pc_mosaic *m, unsigned c, int x, int y,
                      double (*f)(const pc_dimg *, const pc_mosaic *, unsigned, int, int),
                      unsigned j)
{
	double s = 0, ws = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++)
			if (chan(m, x + dx, y + dy) == c) {
				double wt = (2 - abs(dx)) * (2 - abs(dy));
				s += wt * f(r, m, j, x + dx, y + dy);
				ws += wt;
			}
	return s / ws;
}

static double raw_at(const pc_dimg *r, const pc_mosaic *m, unsigned j, int x, int y)
{
	(void)m;
	(void)j;
	return pc_dimg_at(r, x, y);
}

/* Ĩ_j at (x, y) */
static double bil(const pc_dimg *r, const pc_mosaic *m, unsigned j, int x, int y)
{
	return tent_of(r, m, j, x, y, raw_at, 0);
}

/* raw − Ĩ_j at (x, y) (read at channel i's samples only) */
static double diff_j(const pc_dimg *r, const pc_mosaic *m, unsigned j, int x, int y)
{
	return pc_dimg_at(r, x, y) - bil(r, m, j, x, y);
}

int pc_dm_ref_pcdp(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                   const pc_fplane *out)
{
	if (m->period != 2)
		return pc_error(PC_ENOTSUP, "pcdp: monochrome mosaics only");
	pc_dimg r = {(double *)img, (int)width, (int)height};
	for (int y = 0; y < r.h; y++)
		for (int x = 0; x < r.w; x++)
			for (unsigned i = 0; i < 4; i++) {
				double v = 0;
				for (unsigned j = 0; j < 4; j++) {
					if (j == i)
						continue;
					double d = tent_of(&r, m, i, x, y, diff_j, j);
					v += pcdp_weight(i, j) * (bil(&r, m, j, x, y) + d);
				}
				out[i].data[(size_t)y * out[i].row_stride +
				            (size_t)x * out[i].pixel_stride] = (float)v;
			}
	return 0;
}

/* ---- fast path: I_i = G_i + tent_i(raw − G_i), G_i = Σ_j w_ij Ĩ_j ---- */

#define PAD 2
typedef struct fjob {
	const pc_dm_input *in;
	const pc_mosaic *m;
	long w, h, s;
	float *R, *B[4], *Rs; /* padded raw, bilinear planes, residual of the current channel */
	unsigned i;
	int stage;
	const pc_fplane *out;
} fjob;

#define AT(p, x, y) ((p)[((long)(y) + PAD) * j->s + (long)(x) + PAD])

static void pad_plane(const fjob *j, float *p, long y0, long y1)
{
	for (long y = y0; y < y1; y++)
		for (int k = 1; k <= PAD; k++) {
			AT(p, -k, y) = AT(p, pc_mirror(-k, (int)j->w), y);
			AT(p, j->w - 1 + k, y) = AT(p, pc_mirror((int)j->w - 1 + k, (int)j->w), y);
		}
}

static void pad_rows(const fjob *j, float *p)
{
	for (int k = 1; k <= PAD; k++) {
		memcpy(&AT(p, -PAD, -k), &AT(p, -PAD, pc_mirror(-k, (int)j->h)),
		       sizeof(float) * (size_t)j->s);
		memcpy(&AT(p, -PAD, j->h - 1 + k),
		       &AT(p, -PAD, pc_mirror((int)j->h - 1 + k, (int)j->h)),
		       sizeof(float) * (size_t)j->s);
	}
}

/* tent of channel c's samples of plane p at (x, y): the pixel, a horizontal or vertical
 * pair, or the four diagonals */
static inline float tentf(const fjob *j, const float *p, unsigned c, long x, long y)
{
	unsigned cx = (unsigned)(x & 1), cy = (unsigned)(y & 1);
	const pc_mosaic *m = j->m;
	if (m->channel[cy][cx] == c)
		return AT(p, x, y);
	if (m->channel[cy][cx ^ 1] == c)
		return 0.5f * (AT(p, x - 1, y) + AT(p, x + 1, y));
	if (m->channel[cy ^ 1][cx] == c)
		return 0.5f * (AT(p, x, y - 1) + AT(p, x, y + 1));
	return 0.25f * ((AT(p, x - 1, y - 1) + AT(p, x + 1, y - 1)) +
	                (AT(p, x - 1, y + 1) + AT(p, x + 1, y + 1)));
}

static void fband(void *ctx, uint32_t y0u, uint32_t y1u)
{
	fjob *j = ctx;
	long y0 = y0u, y1 = y1u, w = j->w;
	if (j->stage == 0) {
		for (long y = y0; y < y1; y++)
			pc_dm_row_to_float(j->in, (uint32_t)y, &AT(j->R, 0, y));
		pad_plane(j, j->R, y0, y1);
	} else if (j->stage == 1) {
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++)
				for (unsigned c = 0; c < 4; c++)
					AT(j->B[c], x, y) = tentf(j, j->R, c, x, y);
	} else if (j->stage == 2) { /* residual raw − G_i at channel i's samples (all pixels) */
		unsigned i = j->i;
		float wt[4];
		for (unsigned c = 0; c < 4; c++)
			wt[c] = c == i ? 0.0f : (float)pcdp_weight(i, c);
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				float g = wt[0] * AT(j->B[0], x, y) + wt[1] * AT(j->B[1], x, y) +
				          wt[2] * AT(j->B[2], x, y) + wt[3] * AT(j->B[3], x, y);
				AT(j->Rs, x, y) = AT(j->R, x, y) - g;
			}
		pad_plane(j, j->Rs, y0, y1);
	} else {
		unsigned i = j->i;
		float wt[4];
		for (unsigned c = 0; c < 4; c++)
			wt[c] = c == i ? 0.0f : (float)pcdp_weight(i, c);
		const pc_fplane *o = &j->out[i];
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				float g = wt[0] * AT(j->B[0], x, y) + wt[1] * AT(j->B[1], x, y) +
				          wt[2] * AT(j->B[2], x, y) + wt[3] * AT(j->B[3], x, y);
				o->data[(size_t)y * o->row_stride + (size_t)x * o->pixel_stride] =
				    g + tentf(j, j->Rs, i, x, y);
			}
	}
}

static int pcdp_fast(const pc_dm_input *in, const pc_mosaic *m, int threads, const pc_fplane *out)
{
	if (m->period != 2 || in->width < 4 || in->height < 4)
		return PC_ENOTSUP;
	fjob j;
	memset(&j, 0, sizeof j);
	j.in = in;
	j.m = m;
	j.w = in->width;
	j.h = in->height;
	j.s = j.w + 2 * PAD;
	j.out = out;
	size_t ps = (size_t)j.s * (size_t)(j.h + 2 * PAD);
	float *mem = pc_dm_alloc(sizeof(float) * ps * 6);
	if (!mem)
		return pc_error(PC_ENOMEM, "pcdp: %ldx%ld planes", j.w, j.h);
	j.R = mem;
	for (int c = 0; c < 4; c++)
		j.B[c] = mem + ps * (size_t)(1 + c);
	j.Rs = mem + ps * 5;
	fjob *jp = &j;
	j.stage = 0;
	pc_parallel_rows((uint32_t)j.h, 0, threads, fband, jp);
	pad_rows(&j, j.R);
	j.stage = 1;
	pc_parallel_rows((uint32_t)j.h, 0, threads, fband, jp);
	for (unsigned i = 0; i < 4; i++) {
		j.i = i;
		j.stage = 2;
		pc_parallel_rows((uint32_t)j.h, 0, threads, fband, jp);
		pad_rows(&j, j.Rs);
		j.stage = 3;
		pc_parallel_rows((uint32_t)j.h, 0, threads, fband, jp);
	}
	pc_dm_free(mem);
	return 0;
}

int pc_dm_pcdp_fast(const pc_dm_call *call, const pc_fplane *out)
{
	int rc = pcdp_fast(call->in, call->m, call->threads, out);
	return rc == PC_ENOTSUP ? pc_dm_ref_of_call(call, out) : rc;
}
