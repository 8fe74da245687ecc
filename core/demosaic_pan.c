/* Colour-polarization demosaicking guided by a pseudo-panchromatic image ("pan-ratio").
 *
 * On a colour-polarization sensor (Sony IMX250MYR, polarcam/mosaic.h) each of the twelve
 * (colour k, analyser c) channels is sampled once per 4×4 period (green: twice), so a
 * channel-by-channel interpolation works on a lattice of spacing 4. But all sixteen samples of
 * a period see one scene. As for multispectral filter arrays, whose 4×4 periods hold sixteen
 * bands (Mihoubi, Losson, Mathon, Macaire, "Multispectral demosaicing using pseudo-panchromatic
 * image", IEEE TCI 3(4) 2017, Sec. III), the mean of the period's samples around a pixel is a
 * full-resolution pseudo-panchromatic image (PPI)
 *
 *   P0 = raw ∗ (m ⊗ m),  m = [1 2 2 2 1]/8,
 *
 * which weighs each of the sixteen positions of the period 1/16 wherever it is centred. Each
 * channel is then interpolated as a ratio to the guide rather than as a value — the smooth-hue
 * transition of Cok (US patent 4,642,678, 1987), which colour and polarization both obey where
 * they change slowly (a channel is the scene's radiance times a slowly varying colour and
 * polarization factor) — with an offset δ that makes it a difference in the dark, as in our
 * monochrome `ratio` method (docs/demosaicking.md):
 *
 *   ρ(q)   = (max(raw(q), 0) + δ) / (max(P0(q), 0) + δ)          at every sample q,
 *   R_kc(p) = Σ_q T(p − q) ρ(q) / Σ_q T(p − q)                    over channel kc's samples q,
 *   I_kc(p) = (max(raw(p), 0) + δ) · R_kc(p) / R_own(p) − δ       (kc ≠ own, the channel at p),
 *   I_own(p) = raw(p),
 *
 * T the bilinear tent of the channel's lattice, T(d) = (4 − |dx|)(4 − |dy|) for |dx|, |dy| < 4
 * (green's two lattices, offset by (2, 2) within the analyser's sub-image... in pixels (2, −2),
 * are both summed). R_kc / R_own is the ratio between two channels, smooth where hue and
 * polarization are; the detail of every channel at p comes from p's own sample, at full
 * resolution. δ = 1 % of full scale.
 *
 * Borders: the raw is extended by mirroring inside each analyser's half-resolution sub-image
 * (x → (x mod 2) + 2·mirror(x div 2)), which keeps every pixel's 4×4 phase, hence its colour
 * and analyser; P0 and ρ are computed on the extended raw.
 *
 * Support: R reads ρ at lattice points within ±3 pixels (the tent's zero at ±4), ρ reads P0's
 * ±2: an output pixel depends on the raw within ±5 (mirrored). */
#include "demosaic_pan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "simd.h"

/* the per-row arguments of the output row kernel (demosaic_pan_kern.inc) */
typedef struct pan_orow_args {
	const float *vrow[12][4];
	float vw[12][4];
	int nv[12];
	const float *sel[4]; /* 0/1 lane patterns of column phase u (16 lanes) */
	unsigned own[4];     /* the own channel at column phase u */
} pan_orow_args;

/* pan-guided's: the terms' tent weights vt, their rows' index vdy in p0row (rows y-3 .. y+3) */
typedef struct pan_gorow_args {
	const float *vrow[12][4];
	float vt[12][4];
	int vdy[12][4];
	int nv[12];
	const float *sel[4];
	unsigned own[4];
	const float *p0row[7];
} pan_gorow_args;

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_pan_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_pan_kern.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "demosaic_pan_kern.inc"
#include "simd_instance_end.h"
#endif

#define PAN_DELTA 0.01 /* δ, fraction of full scale */
#define PAN_E     0.01 /* pan-guided's e, fraction of full scale */

/* The sub-image mirror: x of the raw extended beyond [0, n) (n even) keeping x mod 4. */
static inline int mirror4(int x, int n)
{
	int px = x & 1;
	return px + 2 * pc_mirror((x - px) / 2, n / 2);
}

typedef struct pan_ref {
	const double *img;
	int w, h;
	double delta;
	const pc_mosaic *m;
	double e; /* pan-guided's range scale */
} pan_ref;

static double ext(const pan_ref *r, int x, int y)
{
	return r->img[(size_t)mirror4(y, r->h) * r->w + mirror4(x, r->w)];
}

static double ppi0(const pan_ref *r, int x, int y)
{
	static const double m[5] = {1, 2, 2, 2, 1};
	double s = 0;
	for (int j = -2; j <= 2; j++)
		for (int i = -2; i <= 2; i++)
			s += m[i + 2] * m[j + 2] * ext(r, x + i, y + j);
	return s / 64;
}

static double ratio_at(const pan_ref *r, int x, int y)
{
	return (fmax(ext(r, x, y), 0) + r->delta) / (fmax(ppi0(r, x, y), 0) + r->delta);
}

/* channel 4·k + c of the extended raw at (x, y): the mirror keeps the phase */
static unsigned chan(const pan_ref *r, int x, int y)
{
	uint32_t xm = (uint32_t)mirror4(x, r->w), ym = (uint32_t)mirror4(y, r->h);
	return 4 * (pc_mosaic_color(r->m, xm, ym) - PC_CFA_R) + pc_mosaic_channel(r->m, xm, ym);
}

/* Both references' output at (x, y): the pixel's own sample kept, every other channel q its
 * sample times the interpolated ratio of q to the own channel (num, den: each channel's
 * weighted ratio sum and its weight). */
static void put_pixel(const pan_ref *r, int x, int y, const double num[12], const double den[12],
                      const pc_fplane *out)
{
	unsigned own = chan(r, x, y);
	double v = r->img[(size_t)y * (size_t)r->w + (size_t)x];
	double scale = (fmax(v, 0) + r->delta) * den[own] / num[own];
	for (unsigned q = 0; q < 12; q++) {
		double o = q == own ? v : scale * num[q] / den[q] - r->delta;
		const pc_fplane *p = &out[q];
		p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride] = (float)o;
	}
}

int pc_dm_pan_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                  const pc_fplane *out)
{
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, 0};
	for (int y = 0; y < r.h; y++)
		for (int x = 0; x < r.w; x++) {
			double num[12] = {0}, den[12] = {0};
			for (int dy = -3; dy <= 3; dy++)
				for (int dx = -3; dx <= 3; dx++) {
					double t = (4 - abs(dx)) * (4 - abs(dy));
					unsigned q = chan(&r, x + dx, y + dy);
					num[q] += t * ratio_at(&r, x + dx, y + dy);
					den[q] += t;
				}
			put_pixel(&r, x, y, num, den, out);
		}
	return 0;
}

/* pan-guided: pan-ratio with joint-bilateral tents (Tomasi & Manduchi, ICCV 1998; Kopf et al.,
 * SIGGRAPH 2007), separable as the tents are: along a row, the ratios of a column phase s at
 * x + d weigh (4 − |d|)/(e + |P0(x + d, y') − P0(x, y')|) (normalised per phase), giving
 * H_s(x, y'); down a column, a channel's lattice rows y' weigh (4 − |y' − y|)/(e + |P0(x, y') −
 * P0(x, y)|) (normalised over the channel's rows, both lattices for green); e = 1 % of full
 * scale. Near a hue or intensity edge the samples across it, whose ratio belongs to the other
 * surface, weigh little. */
static double guided_h(const pan_ref *r, int x, int y, int s)
{
	double p0 = ppi0(r, x, y), num = 0, den = 0;
	for (int d = -3; d <= 3; d++) {
		if ((((x + d) % 4) + 4) % 4 != s)
			continue;
		double wgt = (4 - abs(d)) / (r->e + fabs(ppi0(r, x + d, y) - p0));
		num += wgt * ratio_at(r, x + d, y);
		den += wgt;
	}
	return num / den;
}

int pc_dm_pan_guided_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out)
{
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, PAN_E * fs};
	for (int y = 0; y < r.h; y++)
		for (int x = 0; x < r.w; x++) {
			double num[12] = {0}, den[12] = {0}, p0 = ppi0(&r, x, y);
			/* every (column phase, row) of the 7 rows around y: its channel's lattice
			 * row */
			for (int dy = -3; dy <= 3; dy++) {
				double wv = (4 - abs(dy)) / (r.e + fabs(ppi0(&r, x, y + dy) - p0));
				for (int s = 0; s < 4; s++) {
					/* the channel of phase s on row y + dy */
					int xs = x - (((x - s) % 4) + 4) % 4;
					unsigned q = chan(&r, xs, y + dy);
					num[q] += wv * guided_h(&r, x, y + dy, s);
					den[q] += wv;
				}
			}
			put_pixel(&r, x, y, num, den, out);
		}
	return 0;
}

/* ---- the fast path ----
 *
 * Per thread, a band of output rows. Every (extended) source row yy gets its ratio row ρ
 * (columns [-16, n + 16), n the row rounded up to whole 16-float vectors, from the vertical sums of
 * the five raw rows mirror4(yy - 2 .. yy + 2), padded by the column mirror, then the horizontal
 * half of the filter) and from it the four horizontal tents h_s (s the column phase of the
 * channel), kept in a ring of 8 rows: output row y reads rows y - 3 .. y + 3. An output row sums
 * each channel's vertical tent over its lattice rows (two terms, four for green's two lattices),
 * then scales by the pixel's own ratio. Whole vectors of planar outputs are stored in place
 * (streaming stores where pc_dm_stream_wanted says so, as the other kernels); the last partial
 * vector, and interleaved outputs, go through a row buffer. */
#define PAN_PADR 32 /* raw and sum rows: columns [-32, w + 32) */

typedef struct pan_job {
	const pc_dm_input *in;
	uint32_t w, h;
	const pc_mosaic *m;
	float delta;
	pc_cpu_level level;
	const pc_fplane *out;
	int err;
	int guided; /* pan-guided */
	float e;    /* its range scale */
	int nt;     /* streaming stores into the planes (pc_dm_stream_wanted) */
} pan_job;

/* 0/1 lane patterns (period 4, 16 lanes) and the tent weights of pan_hrows */
typedef struct pan_tables {
	float sel[4][16];
	float wt[4][7][16];
} pan_tables;

static void pan_tables_init(pan_tables *t)
{
	memset(t, 0, sizeof *t);
	for (int l = 0; l < 16; l++) {
		int u = l & 3;
		t->sel[u][l] = 1;
		for (int s = 0; s < 4; s++)
			for (int d = -3; d <= 3; d++)
				if (((u + d) & 3) == s)
					t->wt[s][d + 3][l] = (float)(4 - abs(d));
	}
}

typedef void (*pan_vsum_fn)(const float *const r[5], long n, float *sum);
typedef void (*pan_ratio_fn)(const float *vs, const float *raw, long x0, long n, float delta,
                             float *rho, float *p0out);
typedef void (*pan_ghrows_fn)(const float *rho, const float *p0, long n, const float wt[4][7][16],
                              float e, float *const h[4]);
typedef void (*pan_gorow_fn)(const pan_gorow_args *a, const float *raw, long n, float delta,
                             float e, float *const out[12], int nt);
typedef void (*pan_hrows_fn)(const float *rho, long n, const float wt[4][7][16], float *const h[4]);
typedef void (*pan_orow_fn)(const pan_orow_args *a, const float *raw, long n, float delta,
                            float *const out[12], int nt);

typedef struct pan_kern {
	pan_vsum_fn vsum;
	pan_ratio_fn ratio;
	pan_hrows_fn hrows;
	pan_orow_fn orow;
	pan_ghrows_fn ghrows;
	pan_gorow_fn gorow;
} pan_kern;

static pan_kern pan_kernels(pc_cpu_level level)
{
#ifdef PC_CPU_X86
	if (level >= PC_CPU_AVX512)
		return (pan_kern){pan_vsum_avx512, pan_ratio_avx512,  pan_hrows_avx512,
		                  pan_orow_avx512, pan_ghrows_avx512, pan_gorow_avx512};
	if (level >= PC_CPU_AVX2)
		return (pan_kern){pan_vsum_avx2, pan_ratio_avx2,  pan_hrows_avx2,
		                  pan_orow_avx2, pan_ghrows_avx2, pan_gorow_avx2};
#else
	(void)level;
#endif
	return (pan_kern){pan_vsum_base, pan_ratio_base,  pan_hrows_base,
	                  pan_orow_base, pan_ghrows_base, pan_gorow_base};
}

/* A direct-mapped cache of 16 converted raw rows (minus black), slot = row mod 16: the five
 * rows of a ratio row are distinct rows less than 16 apart (mirrored ones too), so fetching
 * them one after the other never evicts one of them. */
typedef struct pan_rows {
	float *slot[16]; /* each readable from -1 to w (pc_dm_row_to_float's mirror) */
	int32_t tag[16];
} pan_rows;

static const float *pan_row(pan_rows *c, const pc_dm_input *in, int y)
{
	int k = y & 15;
	if (c->tag[k] != y) {
		pc_dm_row_to_float(in, (uint32_t)y, c->slot[k]);
		c->tag[k] = y;
	}
	return c->slot[k];
}

/* pan-guided's output row y: the terms of every channel, then the kernel (whole vectors into
 * planar outputs, the rest through the row buffer o), then the own measurements. */
static void pan_gorow(const pan_job *j, const pan_kern *K, const pan_tables *t, float *hr[8][4],
                      float *p0r[8], const float *raw, uint32_t y, int planar, long n, long nmain,
                      float *rawp, float *const o[12])
{
	pan_gorow_args a;
	memset(&a, 0, sizeof a);
	const uint32_t w = j->w, ty = y & 3;
	for (unsigned py = 0; py < 4; py++)
		for (unsigned px = 0; px < 4; px++) {
			unsigned q = 4 * (pc_mosaic_color(j->m, px, py) - PC_CFA_R) +
			             pc_mosaic_channel(j->m, px, py);
			int e = (int)((y - py) & 3), ya = (int)y - e;
			a.vrow[q][a.nv[q]] = hr[ya & 7][px];
			a.vt[q][a.nv[q]] = (float)(4 - e);
			a.vdy[q][a.nv[q]++] = 3 - e;
			if (e) {
				a.vrow[q][a.nv[q]] = hr[(ya + 4) & 7][px];
				a.vt[q][a.nv[q]] = (float)e;
				a.vdy[q][a.nv[q]++] = 7 - e;
			}
		}
	for (int k = 0; k < 7; k++)
		a.p0row[k] = p0r[((int)y + k - 3) & 7];
	for (unsigned u = 0; u < 4; u++) {
		a.sel[u] = t->sel[u];
		a.own[u] =
		    4 * (pc_mosaic_color(j->m, u, ty) - PC_CFA_R) + pc_mosaic_channel(j->m, u, ty);
	}
	float *d[12];
	if (planar) {
		for (int q = 0; q < 12; q++)
			d[q] = j->out[q].data + (size_t)y * j->out[q].row_stride;
		K->gorow(&a, raw, nmain, j->delta, j->e, d, j->nt);
		if (nmain < n) {
			memcpy(rawp, raw + nmain, (size_t)((long)w - nmain) * sizeof *rawp);
			for (int q = 0; q < 12; q++)
				for (int i = 0; i < a.nv[q]; i++)
					a.vrow[q][i] += nmain;
			for (int k = 0; k < 7; k++)
				a.p0row[k] += nmain;
			K->gorow(&a, rawp, 16, j->delta, j->e, o, 0);
			for (int q = 0; q < 12; q++)
				memcpy(d[q] + nmain, o[q],
				       (size_t)((long)w - nmain) * sizeof *o[q]);
		}
		return;
	}
	memcpy(rawp, raw, w * sizeof *rawp);
	K->gorow(&a, rawp, n, j->delta, j->e, o, 0);
	for (int q = 0; q < 12; q++) {
		const pc_fplane *p = &j->out[q];
		float *dq = p->data + (size_t)y * p->row_stride;
		for (uint32_t x = 0; x < w; x++)
			dq[(size_t)x * p->pixel_stride] = o[q][x];
	}
}

static void pan_band(void *ctx, uint32_t y0, uint32_t y1)
{
	pan_job *j = ctx;
	const uint32_t w = j->w, h = j->h;
	const int iw = (int)w, ih = (int)h;
	const long n = ((long)w + 15) / 16 * 16; /* columns computed: whole vectors */
	const long nmain = (long)w / 16 * 16;    /* whole vectors inside the row */
	const size_t pitch = (size_t)n + 2 * PAN_PADR;
	pan_tables *t = pc_dm_alloc(sizeof *t);
	/* scratch: vertical sums and the raw row (padded), the ratio row, 8 × 4 tent rows, 12
	 * output rows, copies of 5 source rows' last partial vectors, 16 cached raw rows, 8 PPI
	 * rows (pan-guided) */
	float *buf = pc_dm_alloc(sizeof(float) * pitch * (52 + 16 + 8));
	if (!t || !buf) {
		pc_dm_free(t);
		pc_dm_free(buf);
		j->err = 1;
		return;
	}
	memset(buf, 0, sizeof(float) * pitch * (52 + 16 + 8));
	pan_tables_init(t);
	const pan_kern K = pan_kernels(j->level);
	int planar = 1;
	for (int q = 0; q < 12; q++)
		planar &= j->out[q].pixel_stride == 1;
	float *vs = buf + PAN_PADR, *rawp = vs + pitch, *rho = rawp + pitch;
	float *hbase = rho + pitch, *obase = hbase + 32 * pitch, *src = obase + 12 * pitch;
	float *hr[8][4], *o[12];
	for (int k = 0; k < 8; k++)
		for (int s = 0; s < 4; s++)
			hr[k][s] = hbase + (size_t)(4 * k + s) * pitch;
	for (int q = 0; q < 12; q++)
		o[q] = obase + (size_t)q * pitch;
	pan_rows rc;
	for (int k = 0; k < 16; k++) {
		rc.slot[k] = src + (size_t)(5 + k) * pitch;
		rc.tag[k] = -1;
	}
	float *p0r[8]; /* pan-guided: the PPI rows of the ring */
	for (int k = 0; k < 8; k++)
		p0r[k] = src + (size_t)(21 + k) * pitch;
	int have = (int)y0 - 4; /* source rows computed: up to have */
	for (uint32_t y = y0; y < y1; y++) {
		for (int yy = have < (int)y - 4 ? (int)y - 4 : have + 1; yy <= (int)y + 3; yy++) {
			/* ratio row of the extended source row yy, and its four tents */
			const float *r[5], *rt[5];
			for (int k = 0; k < 5; k++) {
				r[k] = pan_row(&rc, j->in, mirror4(yy + k - 2, ih));
				/* the last partial vector from a copy that is readable to n */
				float *d = src + (size_t)k * 16;
				memcpy(d, r[k] + nmain, (size_t)(iw - nmain) * sizeof *d);
				rt[k] = d;
			}
			K.vsum(r, nmain, vs);
			if (nmain < n)
				K.vsum(rt, 16, vs + nmain);
			memcpy(rawp, r[2], w * sizeof *rawp);
			for (int x = -PAN_PADR; x < 0; x++) {
				vs[x] = vs[mirror4(x, iw)];
				rawp[x] = rawp[mirror4(x, iw)];
			}
			for (int x = iw; x < (int)n + PAN_PADR; x++) {
				vs[x] = vs[mirror4(x, iw)];
				rawp[x] = rawp[mirror4(x, iw)];
			}
			if (j->guided) {
				float *p0 = p0r[yy & 7];
				K.ratio(vs, rawp, -16, n + 32, j->delta, rho, p0);
				K.ghrows(rho, p0, n, t->wt, j->e, hr[yy & 7]);
			} else {
				K.ratio(vs, rawp, -16, n + 32, j->delta, rho, NULL);
				K.hrows(rho, n, t->wt, hr[yy & 7]);
			}
		}
		have = (int)y + 3;
		if (j->guided) {
			pan_gorow(j, &K, t, hr, p0r, pan_row(&rc, j->in, (int)y), y, planar, n,
			          nmain, rawp, o);
			continue;
		}
		/* channel q's lattice rows around y, with the tent's vertical weights */
		pan_orow_args a;
		memset(&a, 0, sizeof a);
		const uint32_t ty = y & 3;
		for (unsigned py = 0; py < 4; py++)
			for (unsigned px = 0; px < 4; px++) {
				unsigned q = 4 * (pc_mosaic_color(j->m, px, py) - PC_CFA_R) +
				             pc_mosaic_channel(j->m, px, py);
				int e = (int)((y - py) & 3);
				int ya = (int)y - e;
				a.vrow[q][a.nv[q]] = hr[ya & 7][px];
				a.vw[q][a.nv[q]++] = (float)(4 - e);
				if (e) {
					a.vrow[q][a.nv[q]] = hr[(ya + 4) & 7][px];
					a.vw[q][a.nv[q]++] = (float)e;
				}
			}
		for (int q = 0; q < 12; q++) {
			/* the weights sum to 16 per lattice (4 across, 4 down) */
			int lat = 0;
			for (int i = 0; i < a.nv[q]; i++)
				lat += (int)a.vw[q][i];
			float norm = 1.0f / (float)(4 * lat);
			for (int i = 0; i < a.nv[q]; i++)
				a.vw[q][i] *= norm;
		}
		for (unsigned u = 0; u < 4; u++) {
			a.sel[u] = t->sel[u];
			a.own[u] = 4 * (pc_mosaic_color(j->m, u, ty) - PC_CFA_R) +
			           pc_mosaic_channel(j->m, u, ty);
		}
		const float *raw = pan_row(&rc, j->in, (int)y);
		if (planar) {
			/* whole vectors straight into the planes, the rest through the row buffer
			 */
			float *d[12];
			for (int q = 0; q < 12; q++)
				d[q] = j->out[q].data + (size_t)y * j->out[q].row_stride;
			K.orow(&a, raw, nmain, j->delta, d, j->nt);
			if (nmain < n) {
				memcpy(rawp, raw + nmain, (size_t)(iw - nmain) * sizeof *rawp);
				for (int q = 0; q < 12; q++)
					for (int i = 0; i < a.nv[q]; i++)
						a.vrow[q][i] += nmain;
				K.orow(&a, rawp, 16, j->delta, o, 0);
				for (int q = 0; q < 12; q++)
					memcpy(d[q] + nmain, o[q],
					       (size_t)(iw - nmain) * sizeof *o[q]);
			}
			continue;
		}
		memcpy(rawp, raw, w * sizeof *rawp);
		K.orow(&a, rawp, n, j->delta, o, 0);
		for (int q = 0; q < 12; q++) {
			const pc_fplane *p = &j->out[q];
			float *d = p->data + (size_t)y * p->row_stride;
			for (uint32_t x = 0; x < w; x++)
				d[(size_t)x * p->pixel_stride] = o[q][x];
		}
	}
	if (j->nt)
		pc_dm_sfence();
	pc_dm_free(t);
	pc_dm_free(buf);
}

/* Both fast paths: one fused pass on row bands; guided adds the range weights of scale e. */
static int pan_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out, int guided)
{
	const uint32_t w = in->width, h = in->height;
	pan_job j = {in,
	             w,
	             h,
	             m,
	             (float)(PAN_DELTA * fs),
	             level,
	             out,
	             0,
	             guided,
	             guided ? (float)(PAN_E * fs) : 0,
	             pc_dm_stream_wanted(out, 12, w, h, level)};
	pc_parallel_rows(h, 0, threads, pan_band, &j);
	if (j.err)
		return pc_error(PC_ENOMEM, "%s: row buffers for width %u",
		                guided ? "pan-guided" : "pan-ratio", w);
	return 0;
}

int pc_dm_pan_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 0);
}

int pc_dm_pan_guided_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 1);
}

const pc_dm_pan_fns *pc_dm_pan_fns_get(pc_demosaic_method m)
{
	static const pc_dm_pan_fns ratio = {pc_dm_pan_ref, pc_dm_pan_fast},
	                           guided = {pc_dm_pan_guided_ref, pc_dm_pan_guided_fast};
	return m == PC_DM_PAN_RATIO ? &ratio : m == PC_DM_PAN_GUIDED ? &guided : NULL;
}
