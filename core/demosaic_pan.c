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
#include "demosaic_pan_check.h"
#include "demosaic_pan_kargs.h"

#include <assert.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_fact.h"
#include "demosaic_noise.h"
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

/* pan-dir's, for one row. Its first stage: eight groups (a colour on one row phase t: red 0, 1,
 * green 2..5, blue 6, 7, each in t's order), each with its column-pair rows (hp, lp: the pair the
 * colour covers on row t) at the lattice rows at or above the row (n) and at or below it (s: the
 * same row when the row is a lattice row), the vertical fraction b = e/4 (gb, e the rows from
 * n's), green's weights in N and S (ggn, ggs); every per-row weight is a 16-lane row (one load).
 * The output row: the sixteen lattices by position L = 4t + s, each with its hold rows (nrow,
 * srow; read at x + 3 for E: nrowe, srowe, the same rows but pan-fact's green, weighed for W and
 * E), its rows' interpolations (lnrow, lsrow) and channel lq; per row phase t the weights
 * u1 = 1 − b, u2 = b of red and blue and u1, u2 halved for green (cu), green's weights in N and
 * S (cg), full: the lattice rows are not on the output row (e ≠ 0); red's or blue's two lattices
 * of t (rl); the green groups G = 0, 1: the row phases G and G + 2 (gt), each green channel's
 * lattice on either (gl); per channel the lanes where it is the own channel (osel: the column
 * phase's 0/1 pattern, or zeros); the ratio rows y (r0), y − 2 (rn), y + 2 (rs), the green
 * pixels' lanes gsel. */
typedef struct pan_dlat_args {
	const float *hpn[8], *hps[8], *lpn[8], *lps[8];
	float gb[8][16], ggn[4][16], ggs[4][16];
	const float *nrow[16], *srow[16], *nrowe[16], *srowe[16], *lnrow[16], *lsrow[16];
	float cu[4][4], cg[4][2];
	int full[4], rl[4][2], gt[2][2], gl[2][2][2], lq[16];
	const float *osel[12];
	const float *r0, *rn, *rs, *gsel;
	const float *base; /* the lattice sums' start: a row read at x & bmask (pan_dorow) */
	long bmask;
} pan_dlat_args;

/* pan_dorow runs its six passes (four red-or-blue row phases, two green groups) on strips of
 * this many columns (a multiple of 16), so that the blend weights and the raw row, which every
 * pass reads, stay in L1 (Round 12c) */
#define PAN_DSTRIP 512

/* pan-fact's step 2 for one row (fact_chroma): the block columns' vertical interpolations u (red
 * or blue) and g (green); W's and E's lane weights (colour, near/far column); N's and S's rows
 * (red's, blue's, green's two) and green's weights */
typedef struct fact_cargs {
	const float *u, *g;
	float cw[3][2][16], ce[3][2][16];
	const float *nr, *nb, *ng[2], *sr, *sb, *sg[2];
	float ngw[2], sgw[2];
} fact_cargs;

/* pan-fact's output row (fact_orow): the ratio rows r2 above, at and below it, pd, m, the twelve
 * blended ratio rows rq (the hue); the own channel per column phase u (own, sel); per analyser
 * which of (m, H, V, D) it is on even and odd columns (mx) */
typedef struct fact_oargs {
	const float *ru, *r0, *rd, *pd, *m, *rq[12];
	const float *sel[4];
	unsigned own[4];
	int mx[4][2];
} fact_oargs;

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

typedef struct pan_ref {
	const double *img;
	int w, h;
	double delta;
	const pc_mosaic *m;
	double e; /* pan-guided's range scale */
} pan_ref;

static double ext(const pan_ref *r, int x, int y)
{
	return r->img[(size_t)pc_mirror4(y, r->h) * r->w + pc_mirror4(x, r->w)];
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

/* Channel 4·k + c (colour k, analyser c) of mosaic position (px, py) */
static unsigned pan_q(const pc_mosaic *m, unsigned px, unsigned py)
{
	return 4 * (pc_mosaic_color(m, px, py) - PC_CFA_R) + pc_mosaic_channel(m, px, py);
}

/* channel 4·k + c of the extended raw at (x, y): the mirror keeps the phase */
static unsigned chan(const pan_ref *r, int x, int y)
{
	uint32_t xm = (uint32_t)pc_mirror4(x, r->w), ym = (uint32_t)pc_mirror4(y, r->h);
	return pan_q(r->m, xm, ym);
}

/* The references' twelve values at (x, y): the pixel's own sample kept, every other channel q
 * its sample times the interpolated ratio of q to the own channel (num, den: each channel's
 * weighted ratio sum and its weight). */
static void pan_values(const pan_ref *r, int x, int y, const double num[12], const double den[12],
                       double o[12])
{
	unsigned own = chan(r, x, y);
	double v = r->img[(size_t)y * (size_t)r->w + (size_t)x];
	double scale = (fmax(v, 0) + r->delta) * den[own] / num[own];
	for (unsigned q = 0; q < 12; q++)
		o[q] = q == own ? v : scale * num[q] / den[q] - r->delta;
}

/* ... stored into out */
static void put_pixel(const pan_ref *r, int x, int y, const double num[12], const double den[12],
                      const pc_fplane *out)
{
	double o[12];
	pan_values(r, x, y, num, den, o);
	for (unsigned q = 0; q < 12; q++) {
		const pc_fplane *p = &out[q];
		p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride] = (float)o[q];
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

/* pan-chroma: pan-guided whose range distance also sees hue. A colour edge where the PPI
 * stays level (red beside a green of the same brightness) is invisible to P0, and pan-guided
 * mixes the two sides' ratios there. The colour layer modulates the scene's chrominance
 * onto the mosaic: demodulating the raw by the colours' signs, with the same 5×5 filter as P0,
 * gives full-resolution chrominance images, as the luminance-chrominance demosaickers read the
 * Bayer CFA (Alleysson, Süsstrunk, Hérault, "Linear demosaicing inspired by the human visual
 * system", IEEE TIP 14(4) 2005, Sec. II; Dubois, IEEE SPL 12(12) 2005):
 *
 *   C1 = (χ1·raw) ∗ (m ⊗ m),  χ1 = +1 on red, −1 on blue, 0 on green   (red − blue),
 *   C2 = (χ2·raw) ∗ (m ⊗ m),  χ2 = +1 on green, −1 on red and blue      (green − magenta).
 *
 * As in P0 each of the sixteen period positions weighs 1/16 wherever the filter is centred, so
 * on a uniform patch C1 = (4R − 4B)/16 and C2 = (8G − 4R − 4B)/16 (R, G, B its colours' samples
 * summed over the analysers: polarization cancels) whatever the phase. The range distance of
 * pan-guided's weights becomes the L1 distance in (P0, C1, C2),
 *
 *   D(p, q) = |P0(q) − P0(p)| + β·(|C1(q) − C1(p)| + |C2(q) − C2(p)|),  β = 1/2,
 *
 * the joint-bilateral weights of a colour guide (Kopf et al., SIGGRAPH 2007, with an L1 colour
 * distance; Tomasi & Manduchi, ICCV 1998), with pan-guided's form otherwise and its range scale
 * e = 2 % of full scale. β and e: the chrominance images also respond to fine luminance texture
 * (its aliases at the colour layer's frequencies), where they cost smoothing. Chosen on the
 * development scenes (bench colour DATA_DIR --reference, 9 scenes, gains over bayer-first S0 /
 * DoLP dB, smooth colours; hue patches): β = 2, 1, 1/2, 1/4 at e = 1 %: +3.75/+1.32, +3.99/+1.43,
 * +4.17/+1.50, +4.27/+1.54; +0.70/+0.97, +0.73/+1.04, +0.73/+1.08, +0.70/+1.08; β = 1/2 at
 * e = 2 %: +4.41/+1.62; +0.67/+1.15 (pan-guided: +4.36/+1.57; +0.38/+0.96). Also tried: the
 * chrominance of the ratios ρ instead of the raw (hue without the luminance texture), scaled
 * by P0(p): +4.03/+1.46; +0.69/+1.05 — no better. The reference computes every image on the
 * mirror-extended raw, PAN_CX pixels beyond each border; C1 and C2 are stored times β. */
#define PAN_CX 8
#define PAN_CB 0.5  /* β */
#define PAN_CE 0.02 /* pan-chroma's e, fraction of full scale */

typedef struct chroma_ref {
	int w, h, W;                /* the extended images: (w + 2X) × (h + 2X), row W */
	double *p0, *c1, *c2, *rho; /* at (x, y): [(y + X)·W + x + X] */
} chroma_ref;

static size_t cidx(const chroma_ref *c, int x, int y)
{
	return (size_t)(y + PAN_CX) * (size_t)c->W + (size_t)(x + PAN_CX);
}

static double cdist(const chroma_ref *c, int x0, int y0, int x1, int y1)
{
	size_t i = cidx(c, x0, y0), j = cidx(c, x1, y1);
	return fabs(c->p0[j] - c->p0[i]) + fabs(c->c1[j] - c->c1[i]) + fabs(c->c2[j] - c->c2[i]);
}

/* pan-chroma's guide images P0, β·C1, β·C2 and ρ − sub on the extended raw (c's buffers
 * allocated); sub 0 or 1 (pan-lean's ρ − 1), formed as (num − sub·den)/den as pan_ratio does: ρ
 * itself with 0, exactly 0 with 1 where num = den (a black window) */
static void chroma_images(const pan_ref *r, chroma_ref *c, double sub)
{
	static const double mk[5] = {1, 2, 2, 2, 1};
	for (int y = -PAN_CX; y < c->h + PAN_CX; y++)
		for (int x = -PAN_CX; x < c->w + PAN_CX; x++) {
			double p0 = 0, c1 = 0, c2 = 0;
			for (int j = -2; j <= 2; j++)
				for (int i = -2; i <= 2; i++) {
					double v =
					    mk[i + 2] * mk[j + 2] * ext(r, x + i, y + j) / 64;
					unsigned k = chan(r, x + i, y + j) / 4; /* 0 R, 1 G, 2 B */
					p0 += v;
					c1 += k == 0 ? v : k == 2 ? -v : 0;
					c2 += k == 1 ? v : -v;
				}
			size_t i = cidx(c, x, y);
			c->p0[i] = p0;
			c->c1[i] = PAN_CB * c1;
			c->c2[i] = PAN_CB * c2;
			const double num = fmax(ext(r, x, y), 0) + r->delta,
			             den = fmax(p0, 0) + r->delta;
			c->rho[i] = (num - sub * den) / den;
		}
}

/* pan-chroma's weighted ratio sums at (x, y) over the taps dx in [dx0, dx1], dy in [dy0, dy1]
 * (the full tents: [-3, 3] both; a one-sided candidate of pan-dir restricts one range); with
 * r->e = 0 the tents are plain (pan-ratio's, as pan-dir uses them) */
static void chroma_sums(const pan_ref *r, const chroma_ref *c, int x, int y, int dx0, int dx1,
                        int dy0, int dy1, double num[12], double den[12])
{
	for (unsigned q = 0; q < 12; q++)
		num[q] = den[q] = 0;
	for (int dy = dy0; dy <= dy1; dy++) {
		double wv = 4 - abs(dy);
		if (r->e > 0) /* pan-chroma's range weight; pan-dir's tents are plain */
			wv /= r->e + cdist(c, x, y, x, y + dy);
		for (int s = 0; s < 4; s++) {
			/* row y + dy's taps of column phase s: H_s (pan-guided's) */
			double hn = 0, hd = 0;
			for (int d = dx0; d <= dx1; d++) {
				if ((((x + d) % 4) + 4) % 4 != s)
					continue;
				double wh = 4 - abs(d);
				if (r->e > 0)
					wh /= r->e + cdist(c, x, y + dy, x + d, y + dy);
				hn += wh * c->rho[cidx(c, x + d, y + dy)];
				hd += wh;
			}
			if (hd == 0)
				continue; /* no tap of phase s in the restricted range */
			int xs = x - (((x - s) % 4) + 4) % 4;
			unsigned q = chan(r, xs, y + dy);
			num[q] += wv * hn / hd;
			den[q] += wv;
		}
	}
}

static int chroma_alloc(chroma_ref *c, uint32_t w, uint32_t h, const char *what)
{
	*c = (chroma_ref){(int)w, (int)h, (int)w + 2 * PAN_CX, NULL, NULL, NULL, NULL};
	const size_t n = (size_t)c->W * (size_t)(c->h + 2 * PAN_CX);
	double *buf = malloc(sizeof(double) * n * 4);
	if (!buf)
		return pc_error(PC_ENOMEM, "%s reference: images of %ux%u", what, w, h);
	c->p0 = buf;
	c->c1 = buf + n;
	c->c2 = buf + 2 * n;
	c->rho = buf + 3 * n;
	return 0;
}

/* The chroma images of r's raw, allocated (free c->p0) and filled: pan-chroma's, pan-side's,
 * pan-adapt's and pan-dir's first step. what names the method in the error message. */
static int chroma_prepare(const pan_ref *r, chroma_ref *c, const char *what, double sub)
{
	int rc = chroma_alloc(c, (uint32_t)r->w, (uint32_t)r->h, what);
	if (!rc)
		chroma_images(r, c, sub);
	return rc;
}

int pc_dm_pan_chroma_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out)
{
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, PAN_CE * fs};
	chroma_ref c;
	int rc = chroma_prepare(&r, &c, "pan-chroma", 0);
	if (rc)
		return rc;
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++) {
			double num[12], den[12];
			chroma_sums(&r, &c, x, y, -3, 3, -3, 3, num, den);
			put_pixel(&r, x, y, num, den, out);
		}
	free(c.p0);
	return 0;
}

/* pan-side: pan-guided with one-sided factors from a hue measure (Round 13; the definition
 * measured in Round 12d). pan-guided's tents mix the two sides' ratios at a hue edge that the
 * PPI does not see (docs/demosaicking.md, Round 7); pan-dir's one-sided candidates (Round 8)
 * avoid that at twice the budget. Here each side of a pixel's tents is weighed by how far the
 * hue on that side is from the pixel's own, a soft side choice at the cost of a few
 * multiplies per tap. The hue is pan-chroma's chrominance (C1, C2, β folded in) over the PPI,
 * chromaticity without the luminance texture,
 *
 *   u = (C1, C2)/(max(P0, 0) + δ),
 *
 * taken at block rate: at the even corner (x & ~1, y & ~1) of each 2×2 analyser block (one
 * colour), one hue and one set of factors per block. Side distances D_W = ‖u(B − (2, 0)) −
 * u(B)‖₁, D_E, D_N, D_S likewise (±2 pixels, the neighbouring blocks B of one axis), side
 * weights a_d = (ε + D_d)^−2 (GBTF's inverse-square weights, Pekkucuksen & Altunbasak, ICIP
 * 2010), normalised per axis:
 *
 *   f_W = 2·a_W/(a_W + a_E),  f_E = 2·a_E/(a_W + a_E)   (equal sides: 1, 1, pan-guided),
 *   f_N, f_S likewise.
 *
 * Along a row y' the taps at d < 0 weigh pan-guided's (4 − |d|)/(e + |ΔP0|) times f_W, d > 0
 * times f_E, the factors of the tap row's block at (x, y') (so the pass stays separable); down
 * the column the lattice rows above y times f_N, below times f_S (the factors of (x, y)'s
 * block). ε = 0.1 (hue units), pan-guided's range scale e widened to 4 % of full scale (the
 * factors on their own pick sides by aliasing on fine gratings; a wider e undoes that):
 * Round 12d's sweep of ε, e, the exponent and pixel against block rate. */
#define PAN_SE   0.04 /* pan-side's e, fraction of full scale */
#define PAN_SEPS 0.1  /* ε of the side weights, hue units */
#define PAN_SST  2    /* the side distances' step: the neighbouring blocks */

/* the hue component k (0: C1, 1: C2) of (x, y)'s block */
static double side_u(const chroma_ref *c, double delta, int x, int y, int k)
{
	size_t i = cidx(c, x & ~1, y & ~1);
	return (k ? c->c2[i] : c->c1[i]) / (fmax(c->p0[i], 0) + delta);
}

/* D: the hue's L1 distance between (x + dx, y + dy)'s block and (x, y)'s */
static double side_d(const chroma_ref *c, double delta, int x, int y, int dx, int dy)
{
	return fabs(side_u(c, delta, x + dx, y + dy, 0) - side_u(c, delta, x, y, 0)) +
	       fabs(side_u(c, delta, x + dx, y + dy, 1) - side_u(c, delta, x, y, 1));
}

/* pan-lean's block terms (below): g the frame's noise gain and F its floor (raw units) */
typedef struct lean_side {
	double g, F;
} lean_side;

/* pan-lean's D: pan-side's plus μ times the blocks' relative P̃ step */
static double lean_d(const chroma_ref *c, double delta, int x, int y, int dx, int dy)
{
	const double pa = fmax(c->p0[cidx(c, (x + dx) & ~1, (y + dy) & ~1)], 0) + delta,
	             pb = fmax(c->p0[cidx(c, x & ~1, y & ~1)], 0) + delta;
	return side_d(c, delta, x, y, dx, dy) + PC_DM_PAN_LEAN_MU * fabs(pa - pb) / fmin(pa, pb);
}

/* pan-lean's ε at (x, y)'s block: pan-side's plus κ_n times the hue's noise, σ(P̃)/P̃ with
 * σ² = g·(max(P0, 0) + F) */
static double lean_eps(const chroma_ref *c, double delta, const lean_side *ls, int x, int y)
{
	const double p = fmax(c->p0[cidx(c, x & ~1, y & ~1)], 0);
	return PAN_SEPS + PC_DM_PAN_LEAN_KN * sqrt(ls->g * (p + ls->F)) / (p + delta);
}

/* the factors f[0] (W or N, distance d0) and f[1] (E or S, distance d1) */
static void side_f(double d0, double d1, double eps, double f[2])
{
	double a0 = 1 / ((eps + d0) * (eps + d0)), a1 = 1 / ((eps + d1) * (eps + d1));
	f[0] = 2 * a0 / (a0 + a1);
	f[1] = 2 * a1 / (a0 + a1);
}

/* the factors f[0] (W or N) and f[1] (E or S) of the blocks (x, y) ∓ (dx, dy) against (x, y)'s
 * block: pan-side's, or pan-lean's with ls */
static void side_pair(const pan_ref *r, const chroma_ref *c, const lean_side *ls, int x, int y,
                      int dx, int dy, double f[2])
{
	if (!ls) {
		side_f(side_d(c, r->delta, x, y, -dx, -dy), side_d(c, r->delta, x, y, dx, dy),
		       PAN_SEPS, f);
		return;
	}
	const double d0 = lean_d(c, r->delta, x, y, -dx, -dy),
	             d1 = lean_d(c, r->delta, x, y, dx, dy);
	side_f(d0, d1, lean_eps(c, r->delta, ls, x, y) + PC_DM_PAN_LEAN_KT * fmin(d0, d1), f);
}

/* pan-side's sums at (x, y) (above): num_q, den_q of every channel's tents, with the side
 * factors and the range scales ev (the vertical weights, centre (x, y)) and eh[dy + 3] (the
 * horizontal weights of tap row y + dy). pan-side passes its e everywhere, pan-adapt its
 * relative scale (below). With ls (pan-lean) the tents carry the side factors alone (no range
 * weights: ev and eh unused) and the factors are pan-lean's. */
static void side_sums(const pan_ref *r, const chroma_ref *c, const lean_side *ls, int x, int y,
                      double ev, const double eh[7], double num[12], double den[12])
{
	double p0 = c->p0[cidx(c, x, y)], fv[2];
	for (unsigned q = 0; q < 12; q++)
		num[q] = den[q] = 0;
	side_pair(r, c, ls, x, y, 0, PAN_SST, fv);
	for (int dy = -3; dy <= 3; dy++) {
		double p0r = c->p0[cidx(c, x, y + dy)], fh[2];
		double wv = ls ? 4 - abs(dy) : (4 - abs(dy)) / (ev + fabs(p0r - p0));
		wv *= dy < 0 ? fv[0] : dy > 0 ? fv[1] : 1;
		side_pair(r, c, ls, x, y + dy, PAN_SST, 0, fh);
		for (int s = 0; s < 4; s++) {
			/* row y + dy's taps of column phase s: H_s */
			double hn = 0, hd = 0;
			for (int d = -3; d <= 3; d++) {
				if ((((x + d) % 4) + 4) % 4 != s)
					continue;
				double wh =
				    ls ? 4 - abs(d)
				       : (4 - abs(d)) / (eh[dy + 3] +
				                         fabs(c->p0[cidx(c, x + d, y + dy)] - p0r));
				wh *= d < 0 ? fh[0] : d > 0 ? fh[1] : 1;
				hn += wh * c->rho[cidx(c, x + d, y + dy)];
				hd += wh;
			}
			int xc = x - (((x - s) % 4) + 4) % 4;
			unsigned q = chan(r, xc, y + dy);
			num[q] += wv * hn / hd;
			den[q] += wv;
		}
	}
}

int pc_dm_pan_side_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out)
{
	return pc_dm_pan_side_ref_own(img, w, h, m, fs, out, NULL);
}

int pc_dm_pan_side_ref_own(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           const pc_fplane *out, double *rown)
{
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, PAN_SE * fs};
	chroma_ref c;
	int rc = chroma_prepare(&r, &c, "pan-side", 0);
	if (rc)
		return rc;
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++) {
			double num[12], den[12];
			const double eh[7] = {r.e, r.e, r.e, r.e, r.e, r.e, r.e};
			side_sums(&r, &c, NULL, x, y, r.e, eh, num, den);
			put_pixel(&r, x, y, num, den, out);
			if (rown) {
				unsigned own = chan(&r, x, y);
				rown[(size_t)y * w + (size_t)x] = num[own] / den[own];
			}
		}
	free(c.p0);
	return 0;
}

/* pan-lean's window (step 3 below): the mean *mu and population variance *var of P̃ − δ =
 * max(P0, 0) at the even corners of the 3 × 3 blocks centred on (x, y)'s 2 × 2 block (without
 * δ: a window of black blocks has mean and variance exactly 0) */
static void lean_window(const chroma_ref *c, int x, int y, double *mu, double *var)
{
	double v[9], s = 0, d = 0;
	for (int k = 0; k < 9; k++) {
		v[k] =
		    fmax(c->p0[cidx(c, (x & ~1) + 2 * (k % 3 - 1), (y & ~1) + 2 * (k / 3 - 1))], 0);
		s += v[k];
	}
	*mu = s / 9;
	for (int k = 0; k < 9; k++)
		d += (v[k] - *mu) * (v[k] - *mu);
	*var = d / 9;
}

/* pan-lean (docs/demosaicking.md, Rounds 21 and 24): pan-side's tents without their range
 * weights, the side factors made aware of noise, fine hue texture and luminance steps, and a
 * level shrunk towards its window mean where the window's variation is within the noise. With
 * P̃ = max(P0, 0) + δ, g the frame's noise gain (demosaic_noise.h: variance g·(L + F)) and every
 * constant in demosaic_pan.h:
 *
 *  1. Side distances D = ‖u(B′) − u(B)‖₁ + μ·|P̃(B′) − P̃(B)|/min(P̃(B′), P̃(B)) (pan-side's hue
 *     distance plus a relative luminance step, both at the blocks' corners), factors
 *     f = 2a/(a_0 + a_1), a = (ε_B + D)⁻², with ε_B = ε + κ_n·√(g·(max(P0(B), 0) + F))/P̃(B) +
 *     κ_t·min(D_0, D_1): the hue's noise at the block (its scale σ/P̃) and, where the hue
 *     differs on both sides (texture finer than the blocks, where the factors would pick a
 *     side by aliasing), the smaller distance flatten the factors; a one-sided edge keeps them.
 *  2. Tents (4 − |d|)·f along the rows and (4 − |dy|)·f down the columns (pan-side's with
 *     e → ∞), giving each channel's ratio R_q = num_q/den_q.
 *  3. The level: P̃'s mean m and (population) variance v over the levels of the 3 × 3 blocks
 *     centred on the pixel's 2 × 2 block, each block's P̃ at its even corner (the nine values
 *     P̃(b + (2i, 2j)), i, j ∈ {−1, 0, 1}, b the pixel's block's even corner: the block levels
 *     the side distances of step 1 already use; one window a block), and P_s = m + λ·(P̃ − m),
 *     λ = v/(v + c_p·g·(m + F)) (0/0 → 1), P̃ the pixel's own: the guided filter's
 *     shrinkage (He, Sun, Tang, TPAMI 35(6) 2013, eq. 7) with a regulariser of the order of one
 *     sample's noise, as pan-adapt's (Round 14); where the window's variation is within the
 *     noise, the smooth mean, so that the level's own noise does not go into every output.
 *  4. The own colour's level L = (max(x_p, 0) + δ)/R_own cored against its noise around P_s:
 *     L_o = P_s + s·(L − P_s), s = d²/(d² + c_s·σ_L²), d = L − P_s, σ_L² = g·(max(x_p, 0) +
 *     F)/R_own² (a Wiener-type factor of one sample; 0/0 → 1); the other colours' level is P_s
 *     (no detail of the own sample's colour goes into them: Round 20 (e)).
 *  5. I_q = level·R_q − δ; the own channel keeps the sample.
 *
 * Computed on the ratios less 1, ρ' = ρ − 1 = ((max(x, 0) + δ) − P̃)/P̃, the levels less δ
 * (P̃ − δ, the window's m − δ, P_s − δ, L_o − δ) and R'_q = R_q − 1 (the tents of ρ'), I_q =
 * (level − δ) + level·R'_q: the same values, and in a window of black samples (every ρ' 0,
 * every level δ) every output exactly 0, whatever the side factors and g. The direct form gave
 * there residues of the rounding (±7e-15 DN in this reference, ±1.4e-6 DN in the float path
 * with g > 0, where the factors are not exactly 1), whose DoLP is anything up to 1: a scene
 * with black regions lost up to 2.7 dB of DoLP by them (docs/demosaicking.md, Round 42).
 *
 * With g = 0 steps 3 and 4 are identities (λ = s = 1): P_s = P̃, L_o = L. With g → ∞ the
 * factors are flat (the tents (4 − |d|)(4 − |dy|)) and every output but the own sample is
 * m·R_q − δ. Round 21's definition had no step 3 and blended each output towards the same
 * tents of the raw where their difference was within the noise (eleven blends and a second set
 * of sums a pixel); Round 24 replaced that by step 3, one shrinkage a pixel, whose statistics
 * Round 27 took from the nine block levels instead of all 36 pixels of the blocks (the same
 * window, a quarter of the samples: the fast path's separate pass over six P0 rows becomes one
 * over three block-level rows). */
int pc_dm_pan_lean_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         double g, const pc_fplane *out)
{
	if (!(g >= 0) || !isfinite(g))
		return pc_error(PC_EINVAL, "pan-lean: noise gain %g, expected finite and >= 0", g);
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, 0};
	chroma_ref c;
	/* the ratios less 1 (the definition's last comment) */
	int rc = chroma_prepare(&r, &c, "pan-lean", 1);
	if (rc)
		return rc;
	const double F = PC_DM_NG_FLOOR * fs;
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++) {
			double num[12], den[12];
			const lean_side ls = {g, F};
			side_sums(&r, &c, &ls, x, y, 0, NULL, num, den);
			const unsigned own = chan(&r, x, y);
			const double v = img[(size_t)y * w + (size_t)x], vp = fmax(v, 0);
			const double pt = fmax(c.p0[cidx(&c, x, y)], 0); /* P̃ − δ */
			double mu, wv;
			lean_window(&c, x, y, &mu, &wv);
			const double nv = PC_DM_PAN_LEAN_CP * g * (mu + r.delta + F);
			/* P_s − δ and P_s */
			const double ps = mu + (wv + nv > 0 ? wv / (wv + nv) : 1) * (pt - mu),
			             pd = ps + r.delta;
			const double rn = num[own] / den[own],
			             ro = 1 / (1 + rn); /* R_own − 1, 1/R_own */
			/* d = L − P_s = ((max(v, 0) + δ) − P_s·R_own)/R_own */
			const double d = (vp - ps - pd * rn) * ro;
			const double vl = PC_DM_PAN_LEAN_CS * g * (vp + F) * ro * ro;
			const double lo = ps + (d * d + vl > 0 ? d * d / (d * d + vl) : 1) * d;
			for (unsigned q = 0; q < 12; q++) {
				const int same = q / 4 == own / 4;
				const double o =
				    q == own ? v
				             : (same ? lo : ps) +
				                   (same ? lo + r.delta : pd) * num[q] / den[q];
				const pc_fplane *pl = &out[q];
				pl->data[(size_t)y * pl->row_stride +
				         (size_t)x * pl->pixel_stride] = (float)o;
			}
		}
	free(c.p0);
	return 0;
}

int pc_dm_pan_lean_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out)
{
	double g = 0;
	int rc = pc_dm_noise_gain_d(img, w, h, m, fs, &g);
	return rc ? rc : pc_dm_pan_lean_ref_g(img, w, h, m, fs, fmax(g, 0), out);
}

/* pan-adapt: pan-side with two changes (docs/demosaicking.md, Rounds 13c, 13d and 14), with
 * P̃ = max(P0, 0) + δ on the extended images and every constant in demosaic_pan.h.
 *
 * (1) A range scale relative to the local signal. pan-side's e (4 % of full scale) flattens the
 * P0 weights in dim scenes and makes the result depend on the exposure (Round 13c). Here the
 * range weights centred at c use
 *
 *   e(c) = e_fs·FS + k_e·μ_e(c),  μ_e(c) = the mean of P̃ over the (2r_e + 1)² window at c,
 *
 * (e_fs = 0, k_e = 0.13, r_e = 2): the vertical weights of (x, y) the centre (x, y), the
 * horizontal ones of row y' the tap row's centre (x, y'), so the pass stays separable. The
 * weights (4 − |d|)/(e(c) + |ΔP0|) are normalised per centre, so this is a range kernel on the
 * relative difference |ΔP0|/μ_e: the bilateral filter on log intensity to first order (Durand &
 * Dorsey, SIGGRAPH 2002, Sec. 3), with δ the floor in the dark; scaling the raw by s scales
 * every output by s (δ and e_fs aside).
 *
 * (2) The ratio step's level shrunk where the noise is of the order of the local variation.
 * pan-ratio's and pan-side's ratio step gives every output of a green pixel half of its own
 * sample's noise, which the analysers add coherently in S0 (Round 13d). As ratio-nr shrinks its
 * guide (demosaic_ref.c, shrunk_guide: the guided filter's shrinkage, He, Sun, Tang, TPAMI
 * 35(6) 2013, eq. 7, with a signal-dependent regulariser), the level L that multiplies every
 * ratio is pulled towards the window mean μ of P̃:
 *
 *   L = (max(raw(p), 0) + δ)·den_own/num_own   (pan-side's x̃_p / R_own(p)),
 *   μ, v = the mean and (population) variance of P̃ over the (2r + 1)² window at p,
 *   λ = v / (v + c·(14/64)²·g·μ),   L' = μ + λ·(L − μ),
 *   I_q(p) = L'·num_q/den_q − δ   for all twelve q, the own channel's too,
 *
 * (c = 4, r = 2; (14/64)² the sum of the P0 filter's squared weights, so c·(14/64)²·g·μ is c
 * times P0's noise variance at level μ; g the frame's noise gain, pc_dm_noise_gain_d). λ = 1
 * where v + c·(14/64)²·g·μ = 0. Where c·g = 0 the step is pan-side's (pan_values: the own
 * sample kept), the limit λ → 1 up to rounding and negative samples. */
static double adapt_mean(const chroma_ref *c, double delta, int x, int y, int r)
{
	double s = 0;
	for (int j = -r; j <= r; j++)
		for (int i = -r; i <= r; i++)
			s += fmax(c->p0[cidx(c, x + i, y + j)], 0) + delta;
	return s / ((2 * r + 1) * (2 * r + 1));
}

static double adapt_var(const chroma_ref *c, double delta, int x, int y, int r, double mu)
{
	double s = 0;
	for (int j = -r; j <= r; j++)
		for (int i = -r; i <= r; i++) {
			double d = fmax(c->p0[cidx(c, x + i, y + j)], 0) + delta - mu;
			s += d * d;
		}
	return s / ((2 * r + 1) * (2 * r + 1));
}

pc_dm_pan_adapt_params pc_dm_pan_adapt_defaults(void)
{
	pc_dm_pan_adapt_params p = {PC_DM_PAN_ADAPT_EFS,
	                            PC_DM_PAN_ADAPT_KE,
	                            PC_DM_PAN_ADAPT_RE,
	                            PC_DM_PAN_ADAPT_C,
	                            PC_DM_PAN_ADAPT_R,
	                            PC_DM_PAN_ADAPT_DFS,
	                            -1};
	return p;
}

int pc_dm_pan_adapt_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_adapt_params *p, const pc_fplane *out)
{
	return pc_dm_pan_adapt_ref_own(img, w, h, m, fs, p, out, NULL);
}

int pc_dm_pan_adapt_ref_own(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                            double fs, const pc_dm_pan_adapt_params *p, const pc_fplane *out,
                            double *rown)
{
	if (!(p->e_fs >= 0) || !(p->ke >= 0) || !(p->e_fs + p->ke > 0) || p->re < 0 ||
	    p->re > PAN_CX - 3 || !(p->c >= 0) || p->r < 0 || p->r > PAN_CX || !(p->d_fs > 0) ||
	    !isfinite(p->g))
		return pc_error(PC_EINVAL, "pan-adapt: parameters out of range");
	pan_ref r = {img, (int)w, (int)h, p->d_fs * fs, m, 0};
	double g = p->g;
	if (g < 0) {
		int rc = pc_dm_noise_gain_d(img, w, h, m, fs, &g);
		if (rc)
			return rc;
	}
	const double kn = p->c * (14.0 / 64) * (14.0 / 64) * g; /* the noise term over μ */
	chroma_ref c;
	int rc = chroma_prepare(&r, &c, "pan-adapt", 0);
	if (rc)
		return rc;
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++) {
			double num[12], den[12], eh[7];
			double ev = p->e_fs * fs + p->ke * adapt_mean(&c, r.delta, x, y, p->re);
			for (int dy = -3; dy <= 3; dy++)
				eh[dy + 3] = p->e_fs * fs +
				             p->ke * adapt_mean(&c, r.delta, x, y + dy, p->re);
			side_sums(&r, &c, NULL, x, y, ev, eh, num, den);
			if (rown) {
				unsigned own = chan(&r, x, y);
				rown[(size_t)y * w + (size_t)x] = num[own] / den[own];
			}
			if (!(kn > 0)) {
				put_pixel(&r, x, y, num, den, out);
				continue;
			}
			unsigned own = chan(&r, x, y);
			double v = img[(size_t)y * w + (size_t)x];
			double lv = (fmax(v, 0) + r.delta) * den[own] / num[own];
			double mu = adapt_mean(&c, r.delta, x, y, p->r);
			double var = adapt_var(&c, r.delta, x, y, p->r, mu);
			double lam = var + kn * mu > 0 ? var / (var + kn * mu) : 1;
			double ls = mu + lam * (lv - mu);
			for (unsigned q = 0; q < 12; q++)
				out[q].data[(size_t)y * out[q].row_stride +
				            (size_t)x * out[q].pixel_stride] =
				    (float)(ls * num[q] / den[q] - r.delta);
		}
	free(c.p0);
	return 0;
}

int pc_dm_pan_adapt_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out)
{
	pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
	return pc_dm_pan_adapt_ref_with(img, w, h, m, fs, &p, out);
}

int pc_dm_pan_adapt_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                          double g, const pc_fplane *out)
{
	pc_dm_pan_adapt_params p = pc_dm_pan_adapt_defaults();
	p.g = g;
	return pc_dm_pan_adapt_ref_with(img, w, h, m, fs, &p, out);
}

/* pan-dir: pan-ratio's colour step made direction-aware. Near a hue edge pan-ratio's centred
 * tents mix the two sides' ratios up to ±3 pixels away; on a lattice of spacing 4 a directional
 * interpolation is a one-sided one. Five candidate interpolations R^d of every channel's ratio:
 *
 *   C  pan-ratio's (the tents over dx, dy in [-3, 3]),
 *   W  the taps dx in [-3, 0] only: along a row each channel's nearest lattice sample at or left
 *      of x, the vertical tent as in C; E dx in [0, 3];
 *   N  the lattice rows dy in [-3, 0] only, the horizontal tents as in C; S dy in [0, 3]
 *
 * (per column phase along a row, and per channel down a column, the weights are normalised over
 * the taps kept). The one-sided candidates are judged by the homogeneity of their own result, as
 * Hirakawa & Parks judge their horizontal and vertical interpolations ("Adaptive
 * homogeneity-directed demosaicing algorithm", IEEE TIP 14(3) 2005, Sec. III: the result's colour
 * variation over a small neighbourhood): here the chromaticity of the candidate's interpolated
 * ratios,
 *
 *   c_k^d = ρ̄_k^d / (ρ̄_R^d + ρ̄_G^d + ρ̄_B^d),  ρ̄_k^d = Σ_a R^d_{4k+a}(p)   (colour k's four
 *           analysers: the hue the step interpolates, without the luminance, which comes from
 *           each pixel's own sample, and without the polarization, which the sum cancels),
 *
 * and its total variation inside the 3×3 window around p,
 *
 *   H_d(p) = Σ_k [ Σ_{|j|≤1} Σ_{i=0,1} |c_k^d(x+i, y+j) − c_k^d(x+i−1, y+j)|
 *                + Σ_{|i|≤1} Σ_{j=0,1} |c_k^d(x+i, y+j) − c_k^d(x+i, y+j−1)| ],
 *
 * c clamped at the image's borders (a difference across a border is 0), d = W, E, N, S. C is,
 * per lattice, the distance-weighted mean of W and E and of N and S (the tent is linear
 * interpolation between the two nearest lattice samples), and its homogeneity is taken as the
 * mean of theirs, H_C = (H_W + H_E + H_N + H_S)/4, so its chromaticity is not computed. The
 * candidates' ratios are blended with weights 1/(H_d + 10⁻⁹)², as the gradient-based
 * threshold-free method blends its directional colour-difference estimates before the one
 * reconstruction step (Pekkucuksen & Altunbasak, "Gradient based threshold free color filter array
 * interpolation", ICIP 2010, Sec. 2; the ratios play the colour differences' part, Cok 1987):
 *
 *   R̃_q = Σ_d w_d R_q^d / Σ_d w_d,   then pan-ratio's ratio step on R̃ (pan_values):
 *   I_q(p) = (max(raw(p), 0) + δ)·R̃_q / R̃_own − δ,  I_own(p) = raw(p).
 *
 * A clearly more homogeneous direction wins, equal ones average, which keeps C's averaging on
 * smooth colours; the 10⁻⁹ only guards an exactly uniform patch. On red and blue pixels this
 * equals blending the five candidates' outputs (every candidate's own ratio is ρ(p): the own
 * lattice has no other sample within ±3), on green ones it differs; the blend then folds into
 * the tents' weights, one weighted sum per channel.
 *
 * Round 8's pan-dir (pan-chroma's range-weighted tents as the base, the homogeneity the
 * variation of ln S_k of each candidate's outputs, luminance removed, over 3×3 then summed over
 * 3×3 again) was more accurate at hue edges and several times pan-chroma's cost; Round 9's
 * blended the five candidates' outputs and judged C by its own chromaticity. The choices and
 * what they gave on the three sets are in docs/demosaicking.md, Rounds 9, 10b and 11.
 *
 * Support: a candidate reads pan-ratio's ±5 (±7 through the sub-image mirror), H adds ±1. */
#define PAN_ND 5

static void dir_range(int d, int *dx0, int *dx1, int *dy0, int *dy1)
{
	*dx0 = d == 2 ? 0 : -3;
	*dx1 = d == 1 ? 0 : 3;
	*dy0 = d == 4 ? 0 : -3;
	*dy1 = d == 3 ? 0 : 3;
}

static int clampi(int i, int n)
{
	return i < 0 ? 0 : i >= n ? n - 1 : i;
}

int pc_dm_pan_dir_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      const pc_fplane *out)
{
	pan_ref r = {img, (int)w, (int)h, PAN_DELTA * fs, m, 0}; /* e = 0: plain tents */
	chroma_ref c;
	int rc = chroma_prepare(&r, &c, "pan-dir", 0); /* ρ on the extended raw (guides unused) */
	if (rc)
		return rc;
	const size_t np = (size_t)w * h;
	double *cs = malloc(sizeof(double) * np * (PAN_ND - 1) * 3); /* c_k^d, d = W, E, N, S */
	if (!cs) {
		free(c.p0);
		return pc_error(PC_ENOMEM, "pan-dir reference: candidates of %ux%u", w, h);
	}
#define PAN_CS(x, y, d) (cs + (((size_t)(y)*w + (size_t)(x)) * (PAN_ND - 1) + (size_t)((d)-1)) * 3)
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++)
			for (int d = 1; d < PAN_ND; d++) {
				int dx0, dx1, dy0, dy1;
				double num[12], den[12], rb[3] = {0, 0, 0};
				dir_range(d, &dx0, &dx1, &dy0, &dy1);
				chroma_sums(&r, &c, x, y, dx0, dx1, dy0, dy1, num, den);
				for (int k = 0; k < 3; k++)
					for (int a = 0; a < 4; a++)
						rb[k] += num[4 * k + a] / den[4 * k + a];
				for (int k = 0; k < 3; k++)
					PAN_CS(x, y, d)[k] = rb[k] / (rb[0] + rb[1] + rb[2]);
			}
	for (int y = 0; y < c.h; y++)
		for (int x = 0; x < c.w; x++) {
			double hv[PAN_ND] = {0}, rt[12] = {0}, one[12], o[12], ws = 0;
			for (int d = 1; d < PAN_ND; d++) {
				for (int j = -1; j <= 1; j++)
					for (int i = -1; i <= 1; i++) {
						int xq = clampi(x + i, c.w),
						    yq = clampi(y + j, c.h);
						const double *p = PAN_CS(xq, yq, d);
						const double *pl =
						    PAN_CS(clampi(x + i - 1, c.w), yq, d);
						const double *pu =
						    PAN_CS(xq, clampi(y + j - 1, c.h), d);
						for (int k = 0; k < 3; k++) {
							hv[d] += i > -1 ? fabs(p[k] - pl[k]) : 0;
							hv[d] += j > -1 ? fabs(p[k] - pu[k]) : 0;
						}
					}
				hv[0] += hv[d] / 4;
			}
			for (int d = 0; d < PAN_ND; d++) {
				int dx0, dx1, dy0, dy1;
				double num[12], den[12];
				dir_range(d, &dx0, &dx1, &dy0, &dy1);
				chroma_sums(&r, &c, x, y, dx0, dx1, dy0, dy1, num, den);
				double wd = 1 / ((hv[d] + 1e-9) * (hv[d] + 1e-9));
				for (unsigned q = 0; q < 12; q++)
					rt[q] += wd * num[q] / den[q];
				ws += wd;
			}
			for (unsigned q = 0; q < 12; q++) {
				rt[q] /= ws;
				one[q] = 1;
			}
			pan_values(&r, x, y, rt, one, o);
			for (unsigned q = 0; q < 12; q++)
				out[q].data[(size_t)y * out[q].row_stride +
				            (size_t)x * out[q].pixel_stride] = (float)o[q];
		}
#undef PAN_CS
	free(cs);
	free(c.p0);
	return 0;
}

/* ---- the fast path ----
 *
 * Per thread, a band of output rows, in column strips (pan_band). Every (extended) source row yy
 * gets its ratio row ρ (columns [-16, n + 16), n the strip rounded up to whole 16-float vectors,
 * from the vertical sums of the five raw rows pc_mirror4(yy - 2 .. yy + 2) on [-32, n + 32): the
 * neighbouring strips' columns, the column mirror outside the frame; then the horizontal half of
 * the filter) and from it the four horizontal tents h_s (s the column phase of the
 * channel), kept in a ring of 8 rows: output row y reads rows y - 3 .. y + 3. An output row sums
 * each channel's vertical tent over its lattice rows (two terms, four for green's two lattices),
 * then scales by the pixel's own ratio. Whole vectors of planar outputs are stored in place
 * (streaming stores where pc_dm_stream_wanted says so, as the other kernels); the last partial
 * vector, and interleaved outputs, go through a row buffer. */
#define PAN_PADR  32 /* raw and sum rows: columns [-32, w + 32) */
#define PAN_AROWS 25 /* pan-adapt's rows beyond pan-side's (pan_band) */
#define PAN_LROWS 11 /* pan-lean's: the blocks' level (4), 2 × 2 m and λ, e0 (2), D (1) */
#ifndef PAN_STRIPW
/* pan_band's strips: at most about this many columns. Round 17c's 1024 (three strips at 2448
 * columns, each strip's scratch in a core's L2) cut L2 read misses by 59 % but measured no wall
 * time near idle on the AVX-512 dev machine (pan-guided 8 % slower, pan-adapt unchanged:
 * docs/demosaicking.md, Round 17d), so frames up to 4096 columns take one strip, as before,
 * and wider ones are split to bound the scratch. */
#define PAN_STRIPW 4096
#endif
_Static_assert(PAN_STRIPW >= 192, "pan_band: strips of at least 64 columns");

typedef struct pan_job {
	const pc_dm_input *in;
	uint32_t w, h;
	const pc_mosaic *m;
	float delta;
	pc_cpu_level level;
	const pc_fplane *out;
	int err;
	int guided; /* 1 pan-guided, 2 pan-chroma, 3 pan-side, 4 pan-adapt, 5 pan-lean */
	float e;    /* its range scale (pan-adapt: the factor of the window mean) */
	int nt;     /* streaming stores into the planes (pc_dm_stream_wanted) */
	float kn;   /* pan-adapt: the noise term's factor c·(14/64)²·g */
	float e0;   /* pan-adapt: its range scale's fixed part e_fs·FS */
	double g;   /* pan-lean: the frame's noise gain */
	float F;    /* pan-lean: the noise floor PC_DM_NG_FLOOR·FS */
	int ntil;   /* an interleaved output streamed (pc_dm_stream_wanted_il) */
} pan_job;

/* 0/1 lane patterns (period 4, 16 lanes), the tent weights of pan_hrows; pan-chroma's
 * horizontal chrominance taps ha[i][lane] = m_i·a(lane + i − 2) and the row signs b of the
 * column and row phases (+1 on red's columns and rows: the colour layer is a Bayer pattern of
 * 2×2 analyser blocks, so χ1 = (a + b)/2 and χ2 = −a·b, the signs of the reference) */
typedef struct pan_tables {
	float sel[4][16];
	float wt[4][7][16];
	float ha[5][16];
	float b[4];
	float same[4][3]
	          [16]; /* pan-lean: row phase t, colour k: 1 where the pixel is of colour k */
} pan_tables;

static void pan_tables_init(pan_tables *t, const pc_mosaic *m)
{
	memset(t, 0, sizeof *t);
	float a[4];
	for (unsigned u = 0; u < 4; u++) {
		a[u] = t->b[u] = -1;
		for (unsigned v = 0; v < 4; v++) {
			if (pc_mosaic_color(m, u, v) == PC_CFA_R)
				a[u] = 1;
			if (pc_mosaic_color(m, v, u) == PC_CFA_R)
				t->b[u] = 1;
		}
	}
	static const float mk[5] = {1, 2, 2, 2, 1};
	for (int l = 0; l < 16; l++)
		for (int i = 0; i < 5; i++)
			t->ha[i][l] = mk[i] * a[(l + i + 2) & 3];
	for (unsigned ty = 0; ty < 4; ty++)
		for (int l = 0; l < 16; l++)
			t->same[ty][pc_mosaic_color(m, (unsigned)l & 3, ty) - PC_CFA_R][l] = 1;
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
                             float lo, float sub, float *rho, float *p0out);
typedef void (*pan_ghrows_fn)(const float *rho, const float *p0, long n, const float wt[4][7][16],
                              float e, float *const h[4]);
typedef void (*pan_gorow_fn)(const pan_gorow_args *a, const float *raw, long n, float delta,
                             float e, float *const out[12], int nt);
typedef void (*pan_hrows_fn)(const float *rho, long n, const float wt[4][7][16], float *const h[4]);
typedef void (*pan_orow_fn)(const pan_orow_args *a, const float *raw, long n, float delta,
                            float *const out[12], int nt);
typedef void (*pan_vsumw_fn)(const float *const r[5], const float w[5], long n, float *sum);
typedef void (*pan_cratio_fn)(const float *vs, const float *vsb, const float *raw, long x0, long n,
                              float delta, float sub, const float ha[5][16], float *rho,
                              float *p0out, float *c1out, float *c2out);
typedef void (*pan_cghrows_fn)(const float *rho, const float *p0, const float *c1, const float *c2,
                               long n, const float wt[4][7][16], float e, float *const h[4]);
typedef void (*pan_sghrows_fn)(const float *rho, const float *p0, const float *fw, const float *fe,
                               long n, const float wt[4][7][16], float e, float *const h[4]);
typedef void (*pan_shue_fn)(const float *p0, const float *c1, const float *c2, long x0, long n,
                            float delta, float *u1, float *u2, float *pt);
typedef void (*pan_sfac_fn)(const float *const u[2], const float *const um[2],
                            const float *const up[2], long n, float eps, float *f0, float *f1);

typedef void (*pan_lfach_fn)(const float *const u[3], long n, const pan_lpar *lp, float *f0,
                             float *f1, float *eo);
typedef void (*pan_lfacv_fn)(const float *const u[3], const float *const un[3],
                             const float *const us[3], const float *e0, float *dps, int have,
                             long n, const pan_lpar *lp, float *f0, float *f1);
typedef void (*pan_lhrows_fn)(const float *rho, const float *fw, const float *fe, long n,
                              const float wt[4][7][16], float *const h[4]);
typedef void (*pan_lwin_fn)(const float *const p[3], long n, float cp, float F, float delta,
                            float *mo, float *lo);

typedef void (*pan_atents_fn)(const float *const p[5], const float *rho, const float *fw,
                              const float *fe, long n, float delta, const float wt[4][7][16],
                              float ke, float e0, float *mu, float *var, float *const h[4]);
typedef void (*pan_agorow_fn)(const pan_gorow_args *a, const float *raw, long n, float delta,
                              float *const out[12], int nt);

typedef void (*pan_dwrows_fn)(const float *rho, long x0, long n, const float tw[4][4][16],
                              float *const hw[4]);
typedef void (*pan_dprows_fn)(float *const hw[4], long n, const float fa[4][16], unsigned o,
                              float *const li[4], float *const hp[2], float *const lp[2]);
typedef void (*pan_dchroma_fn)(const pan_dlat_args *a, long n, float *const c[4][2]);
typedef void (*pan_dvar_fn)(const float *const c[2], const float *const p[2], long x0, long n,
                            float *dh, float *dv);
typedef void (*pan_dbox_fn)(const float *dh, const float *dv, long n, float *bh, float *ba);
typedef void (*pan_dgam_fn)(const pan_dlat_args *a, const float *const hb[4][3], const float *raw,
                            long x0, long x1, float delta, float *const g[5], float *bs);
typedef void (*pan_dratio_fn)(const float *vs, const float *raw, long x0, long n, float delta,
                              float *rho, float *rho1);
typedef void (*pan_dorow_fn)(const pan_dlat_args *a, const float *const g[5], const float *raw,
                             long x0, long x1, float *const out[12], long xo, int nt);
typedef void (*fact_gwrows_fn)(const float *const hw[2], const float *const ww[2],
                               const float *const we[2], long n, float *const gw[2],
                               float *const ge[2]);
typedef void (*fact_bsum_fn)(const float *r0, const float *r1, const float par[16], long x0, long n,
                             float *bd);
typedef void (*fact_taps_fn)(const float *const in[4], const int off[4], const float w[2][4][16],
                             long x0, long n, float *const out[2]);
typedef void (*fact_chroma_fn)(const fact_cargs *a, long n, float eps, float *const c[4][2]);
typedef void (*fact_box_fn)(const float *dh, const float *dv, long x0, long n, float *bh,
                            float *be);
typedef void (*fact_gam_fn)(const float *const hb[4][4], const float par[16], long n,
                            float *const g[5]);
typedef void (*fact_m_fn)(const float *const rq[12], const float *raw, const float *const sel[4],
                          const unsigned own[4], long n, float *m);
typedef void (*fact_ppi2_fn)(const float *mu, const float *m0, const float *md, float delta, long n,
                             float *r2, float *pd);
typedef void (*fact_orow_fn)(const fact_oargs *a, const float *raw, long x0, long x1, float delta,
                             float *const out[12], long xo, int nt);

typedef struct pan_kern {
	pan_vsum_fn vsum;
	pan_ratio_fn ratio;
	pan_hrows_fn hrows;
	pan_orow_fn orow;
	pan_ghrows_fn ghrows;
	pan_gorow_fn gorow;
	pan_vsumw_fn vsumw;
	pan_cratio_fn cratio;
	pan_cghrows_fn cghrows;
	pan_gorow_fn cgorow;
	pan_sghrows_fn sghrows;
	pan_gorow_fn sgorow;
	pan_shue_fn shue;
	pan_sfac_fn sfac;
	pan_dwrows_fn dwrows;
	pan_dprows_fn dprows;
	pan_dchroma_fn dchroma;
	pan_dvar_fn dvar;
	pan_dbox_fn dbox;
	pan_dgam_fn dgam;
	pan_dorow_fn dorow;
	fact_gwrows_fn gwrows;
	fact_bsum_fn bsum;
	fact_taps_fn taps;
	fact_chroma_fn chroma;
	fact_box_fn box;
	fact_gam_fn gam;
	fact_m_fn fm;
	fact_ppi2_fn ppi2;
	fact_orow_fn forow;
	pan_lfach_fn lfach;
	pan_lfacv_fn lfacv;
	pan_lhrows_fn lhrows;
	pan_gorow_fn lgorow;
	pan_lwin_fn lwin;
	pan_shue_fn lshue;
	pan_dratio_fn dratio;
} pan_kern;

/* One instance's kernels, in pan_kern's order (S: base, avx2, avx512). */
#define PAN_KERN(S)                                                                                \
	(pan_kern)                                                                                 \
	{                                                                                          \
		pan_vsum_##S, pan_ratio_##S, pan_hrows_##S, pan_orow_##S, pan_ghrows_##S,          \
		    pan_gorow_##S, pan_vsumw_##S, pan_cratio_##S, pan_cghrows_##S, pan_cgorow_##S, \
		    pan_sghrows_##S, pan_sgorow_##S, pan_shue_##S, pan_sfac_##S, pan_dwrows_##S,   \
		    pan_dprows_##S, pan_dchroma_##S, pan_dvar_##S, pan_dbox_##S, pan_dgam_##S,     \
		    pan_dorow_##S, fact_gwrows_##S, fact_bsum_##S, fact_taps_##S, fact_chroma_##S, \
		    fact_box_##S, fact_gam_##S, fact_m_##S, fact_ppi2_##S, fact_orow_##S,          \
		    pan_lfach_##S, pan_lfacv_##S, pan_lhrows_##S, pan_lgorow_##S, pan_lwin_##S,    \
		    pan_lshue_##S, pan_dratio_##S                                                  \
	}

static pan_kern pan_kernels(pc_cpu_level level)
{
#ifdef PC_CPU_X86
	if (level >= PC_CPU_AVX512)
		return PAN_KERN(avx512);
	if (level >= PC_CPU_AVX2)
		return PAN_KERN(avx2);
#else
	(void)level;
#endif
	return PAN_KERN(base);
}

/* pan-adapt's own kernels (pan-side's are pan_kern's) */
typedef struct pan_akern {
	pan_atents_fn atents;
	pan_agorow_fn agorow;
} pan_akern;

static pan_akern pan_akernels(pc_cpu_level level)
{
#ifdef PC_CPU_X86
	if (level >= PC_CPU_AVX512)
		return (pan_akern){pan_atents_avx512, pan_agorow_avx512};
	if (level >= PC_CPU_AVX2)
		return (pan_akern){pan_atents_avx2, pan_agorow_avx2};
#else
	(void)level;
#endif
	return (pan_akern){pan_atents_base, pan_agorow_base};
}

/* A direct-mapped cache of 16 converted raw rows (minus black), slot = row mod 16: the five
 * rows of a ratio row are distinct rows less than 16 apart (mirrored ones too), so fetching
 * them one after the other never evicts one of them. */
typedef struct pan_rows {
	float *slot[16]; /* each readable from -1 to w (pc_dm_row_to_float's mirror) */
	int32_t tag[16];
	/* pan_band's strips (pan_row_strip): slot column 0 is the frame's column xs, columns
	 * [gl, gh) of the frame are converted, and slot[pad_dst[i]] = slot[pad_src[i]] fill the
	 * columns outside the frame by the sub-image mirror */
	uint32_t xs, gl, gh;
	int npad;
	int pad_dst[3 * PAN_PADR], pad_src[3 * PAN_PADR];
	/* pan_row_strip: 1 when the caller fetches the raw's rows ahead itself (pan-lean's output
	 * row), so the conversion does not prefetch the next row too (pc_dm_row_convert) */
	int own_pf;
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

/* pan_band's row y in its strip (rc's xs, gl, gh and pads): the frame's columns [gl, gh)
 * converted as pc_dm_row_to_float converts them (the same operation on each sample, so the same
 * values as the whole row's), the columns outside the frame mirrored (pc_mirror4) from those;
 * readable on [-PAN_PADR, n + PAN_PADR), n the strip's columns computed. The conversion's own
 * mirror writes one column either side of [gl, gh), which may be another slot's: kept. */
static const float *pan_row_strip(pan_rows *c, const pc_dm_input *in, int y)
{
	int k = y & 15;
	if (c->tag[k] != y) {
		float *d = c->slot[k];
		pc_dm_input sub = *in;
		sub.data += (size_t)c->gl * pc_dm_type_bytes(in->type);
		sub.width = c->gh - c->gl;
		float *dl = d + ((long)c->gl - (long)c->xs), *lo = dl - 1, *hi = dl + sub.width;
		const float keep_lo = *lo, keep_hi = *hi;
		if (c->own_pf)
			pc_dm_row_convert(&sub, (uint32_t)y, dl);
		else
			pc_dm_row_to_float(&sub, (uint32_t)y, dl);
		*lo = keep_lo;
		*hi = keep_hi;
		for (int i = 0; i < c->npad; i++)
			d[c->pad_dst[i]] = d[c->pad_src[i]];
		c->tag[k] = y;
	}
	return c->slot[k];
}

/* How a row computed on columns [0, w) is extended to [-PAN_PADR, n + PAN_PADR): the sub-image
 * mirror (pc_mirror4, the raw's), the whole-sample mirror (pc_mirror, pan-fact's m and step 6's
 * ratios) or the edge samples repeated (the clamped chromaticities). */
typedef enum pan_pad { PAN_PAD_SUB, PAN_PAD_MIRROR, PAN_PAD_CLAMP } pan_pad;

static int pan_pad_src(int x, int iw, pan_pad how)
{
	return how == PAN_PAD_SUB      ? pc_mirror4(x, iw)
	       : how == PAN_PAD_MIRROR ? pc_mirror(x, iw)
	       : x < 0                 ? 0
	                               : iw - 1;
}

static void pan_pad_row(float *d, int iw, long n, pan_pad how)
{
	for (int x = -PAN_PADR; x < 0; x++)
		d[x] = d[pan_pad_src(x, iw, how)];
	for (int x = iw; x < (int)n + PAN_PADR; x++)
		d[x] = d[pan_pad_src(x, iw, how)];
}

/* The vertical sums vs of the PPI filter for the extended source row yy (from the five raw rows
 * pc_mirror4(yy - 2 .. yy + 2)), pan-chroma's signed ones vsb (if not NULL), and the raw row rawp,
 * each padded by the column mirror to [-PAN_PADR, n + PAN_PADR); src: 5 × 16 floats of scratch
 * (the last partial vectors, readable to n) */
static void pan_src_sums(const pan_job *j, const pan_kern *K, const pan_tables *t, pan_rows *rc,
                         int yy, float *src, float *vs, float *vsb, float *rawp, long n, long nmain)
{
	const int iw = (int)j->w, ih = (int)j->h;
	const float *r[5], *rt[5];
	for (int k = 0; k < 5; k++) {
		r[k] = pan_row(rc, j->in, pc_mirror4(yy + k - 2, ih));
		float *d = src + (size_t)k * 16;
		memcpy(d, r[k] + nmain, (size_t)(iw - nmain) * sizeof *d);
		rt[k] = d;
	}
	K->vsum(r, nmain, vs);
	if (nmain < n)
		K->vsum(rt, 16, vs + nmain);
	if (vsb) {
		/* m times the signs b of the five source rows */
		static const float mk[5] = {1, 2, 2, 2, 1};
		float wb[5];
		for (int k = 0; k < 5; k++)
			wb[k] = mk[k] * t->b[(yy + k - 2) & 3];
		K->vsumw(r, wb, nmain, vsb);
		if (nmain < n)
			K->vsumw(rt, wb, 16, vsb + nmain);
	}
	memcpy(rawp, r[2], (size_t)iw * sizeof *rawp);
	pan_pad_row(vs, iw, n, PAN_PAD_SUB);
	pan_pad_row(rawp, iw, n, PAN_PAD_SUB);
	if (vsb)
		pan_pad_row(vsb, iw, n, PAN_PAD_SUB);
}

/* pan_band's pan_src_sums on its strip's padded raw rows (pan_row_strip): vs and vsb on
 * [-PAN_PADR, n + PAN_PADR) straight from them (the sums are per column, so a mirrored column's
 * sum is its source column's, as pan_src_sums' padding makes it); returns the raw row yy
 * (readable there too) */
static const float *pan_ssums(const pan_job *j, const pan_kern *K, const pan_tables *t,
                              pan_rows *rc, int yy, float *vs, float *vsb, long n)
{
	const int ih = (int)j->h;
	const float *r[5];
	for (int k = 0; k < 5; k++)
		r[k] = pan_row_strip(rc, j->in, pc_mirror4(yy + k - 2, ih)) - PAN_PADR;
	K->vsum(r, n + 2 * PAN_PADR, vs - PAN_PADR);
	if (vsb) {
		/* m times the signs b of the five source rows */
		static const float mk[5] = {1, 2, 2, 2, 1};
		float wb[5];
		for (int k = 0; k < 5; k++)
			wb[k] = mk[k] * t->b[(yy + k - 2) & 3];
		K->vsumw(r, wb, n + 2 * PAN_PADR, vsb - PAN_PADR);
	}
	return r[2] + PAN_PADR;
}

/* Each channel's lattice rows around output row y, in the order the kernels sum them: for
 * every period position (px, py) of channel q, its sample row at or above y (e = (y − py) mod 4
 * rows up, the tent's vertical weight 4 − e) and, when e ≠ 0, the one four rows below (weight
 * e); slot: the row's place in an 8-row ring ((row) & 7), dy: its offset from y. */
typedef struct pan_lattice {
	int n[12];
	unsigned px[12][4];
	int slot[12][4], dy[12][4];
	float wt[12][4];
} pan_lattice;

/* the lattice of row phase t around row y: its row at or above y is e = (y − t) mod 4 rows up
 * (yn), the one at or below y is ys (the same row when e = 0, else yn + 4) */
static void lattice_rows(int y, unsigned t, int *e, int *yn, int *ys)
{
	*e = (y - (int)t) & 3;
	*yn = y - *e;
	*ys = *e ? *yn + 4 : *yn;
}

static void pan_lattice_rows(const pc_mosaic *m, int y, pan_lattice *l)
{
	memset(l->n, 0, sizeof l->n);
	for (unsigned py = 0; py < 4; py++)
		for (unsigned px = 0; px < 4; px++) {
			unsigned q = pan_q(m, px, py);
			int e, ya, yb;
			lattice_rows(y, py, &e, &ya, &yb);
			for (int k = 0; k < (e ? 2 : 1); k++) {
				int i = l->n[q]++, yr = k ? yb : ya;
				l->px[q][i] = px;
				l->slot[q][i] = yr & 7;
				l->dy[q][i] = yr - y;
				l->wt[q][i] = (float)(k ? e : 4 - e);
			}
		}
}

/* pan_gorow_ph's slots for row phase ty (its comment in demosaic_pan_kern.inc) from the
 * lattice: a->prow, a->sq, a->osel and a->ph, or a->ph = -1 (pan_gorow_in) for a lattice of
 * another structure */
static void pan_gorow_slots(const pan_lattice *l, const pan_tables *t, uint32_t ty,
                            pan_gorow_args *a)
{
	const int f02 = ty < 2 ? 0 : 2, f13 = ty == 1 || ty == 2 ? 1 : 3;
	int ns[4] = {0}, ng[2] = {0};
	a->ph = -1;
	for (int q = 0; q < 12; q++) {
		/* the channel's positions: their e and first term */
		int pe[2], pi[2], np = 0;
		for (int i = 0; i < l->n[q];) {
			const int e = -l->dy[q][i];
			if (np == 2 || e < 0 || e > 3 ||
			    (e && (i + 1 >= l->n[q] || l->px[q][i + 1] != l->px[q][i] ||
			           l->dy[q][i + 1] != 4 - e)))
				return;
			pe[np] = e;
			pi[np++] = i;
			i += e ? 2 : 1;
		}
		int s;
		if (np == 1) {
			if (ns[pe[0]] == 2)
				return;
			s = 2 * pe[0] + ns[pe[0]]++;
		} else {
			const int k = pe[0] & 1;
			if (np != 2 || pe[1] != (pe[0] ^ 2) || pe[0] != (k ? f13 : f02) ||
			    ng[k] == 2)
				return;
			s = 8 + 2 * k + ng[k]++;
		}
		for (int i = 0; i < l->n[q]; i++)
			a->prow[s][i] = a->vrow[q][i];
		a->sq[s] = (unsigned)q;
		if (s < 2 || s == 8)
			a->osel[s < 2 ? s : 2] = t->sel[l->px[q][pi[pe[0] == 0 ? 0 : 1]]];
	}
	a->ph = (f02 == 0) | (f13 == 1) << 1;
}

/* pan-guided's output row y: the terms of every channel, then the kernel (whole vectors into
 * planar outputs, the rest through the row buffer o), then the own measurements. */
/* The arguments pan_gorow and pan_agorow_row share for output row y: the lattice's term rows in
 * the tents hr, their weights and offsets, the selections, the own channels and (slots: not for
 * pan-chroma) pan_gorow_ph's slots, else pan_gorow_in's 16-lane tent weights. */
static void pan_gorow_prep(const pan_job *j, const pan_tables *t, float *hr[8][4], uint32_t y,
                           int slots, pan_gorow_args *a)
{
	const uint32_t ty = y & 3;
	pan_lattice l;
	pan_lattice_rows(j->m, (int)y, &l);
	for (int q = 0; q < 12; q++)
		for (int i = 0; i < l.n[q]; i++) {
			a->vrow[q][i] = hr[l.slot[q][i]][l.px[q][i]];
			a->vt[q][i] = l.wt[q][i];
			a->vdy[q][i] = 3 + l.dy[q][i];
		}
	memcpy(a->nv, l.n, sizeof a->nv);
	a->tstep = j->guided == 5 ? PAN_LTS : 1;
	for (unsigned u = 0; u < 4; u++) {
		a->sel[u] = t->sel[u];
		a->own[u] = pan_q(j->m, u, ty);
	}
	if (slots)
		pan_gorow_slots(&l, t, ty, a);
	else
		a->ph = -1;
	if (a->ph < 0) /* pan_gorow_in's tent weights */
		for (int q = 0; q < 12; q++)
			for (int i = 0; i < l.n[q]; i++)
				for (int k = 0; k < 16; k++)
					a->vtl[q][i][k] = l.wt[q][i];
}

/* Every row pointer of a that is set moved on by dx columns (the row's last partial vector) */
static void pan_gorow_shift(pan_gorow_args *a, long dx)
{
	assert(dx % 16 == 0); /* pan-lean's interleaved tents move by whole column blocks */
	const long tx = dx * a->tstep;
	for (int q = 0; q < 12; q++)
		for (int i = 0; i < 4; i++) {
			if (i < a->nv[q])
				a->vrow[q][i] += tx;
			if (a->prow[q][i])
				a->prow[q][i] += tx;
		}
	for (int k = 0; k < 7; k++) {
		if (a->p0row[k])
			a->p0row[k] += dx;
		if (a->c1row[k])
			a->c1row[k] += dx;
		if (a->c2row[k])
			a->c2row[k] += dx;
	}
	const float **rows[9] = {&a->fn,   &a->fs,   &a->mu,  &a->var, &a->lmu,
	                         &a->llam, &a->lrho, &a->lfw, &a->lfe};
	for (int k = 0; k < 9; k++)
		if (*rows[k])
			*rows[k] += dx;
	if (a->lh)
		a->lh += tx;
}

/* A column strip of pan_band: frame columns [xs, xs + w), n of them computed (whole vectors),
 * nmain the whole vectors inside the strip */
typedef struct pan_strip {
	uint32_t xs, w;
	long n, nmain;
} pan_strip;

/* Output row y, columns [x0, w), of the twelve planes from the row buffers: o[q][i] is column
 * x0 + i (pan_band's and pan_dir_band's last partial vector, and interleaved outputs). */
static void pan_put_row(const pan_job *j, uint32_t y, float *const o[12], uint32_t x0, uint32_t w)
{
	const float *src[12];
	for (int q = 0; q < 12; q++)
		src[q] = o[q];
	pc_dm_put_rows(j->out, 12, y, src, x0, w, j->level, j->ntil);
}

/* Which of the twelve output rows d pan-lean's output row streams (bit q: plane q; the others go
 * through the cache): at most PAN_NT_SAME of the rows that start at the same 64-byte line of a
 * 4 KB page. Twelve streams at one page offset, as in twelve consecutive planes of a frame of a
 * whole number of pages (2448 × 2048 floats is 4896 pages), cost pan-lean 10–20 % of its time
 * against planes at distinct offsets; eight of them streamed and four stored through the cache
 * take back about a third of that (docs/demosaicking.md, Round 31). */
#define PAN_NT_SAME 8
static unsigned pan_nt_mask(float *const d[12])
{
	unsigned mask = 0;
	unsigned char same[64] = {0};
	for (int q = 0; q < 12; q++)
		if (same[((uintptr_t)d[q] >> 6) & 63]++ < PAN_NT_SAME)
			mask |= 1u << q;
	return mask;
}

/* pan-lean's tents that its output row makes itself (pan_gorow): those of the row's last source
 * row, from its ratio row rho and the W and E factors fw, fe */
typedef struct pan_lfuse {
	const float *rho, *fw, *fe;
} pan_lfuse;

/* Output row y's arguments in cache[y mod 16] (pan_band_strip: every ring's length divides 16,
 * the lattice's period is 4, so rows 16 apart take the same ones): *fresh = 1 when they are made
 * here (zeroed, the N and S factors fv, pan_gorow_prep's part; the caller adds the rest), 0 when
 * the slot holds them already. */
static pan_gorow_args *pan_args_at(const pan_job *j, const pan_tables *t, float *hr[8][4],
                                   const float *const fv[2], uint32_t y, int slots,
                                   pan_gorow_args *cache, unsigned char *cached, int *fresh)
{
	pan_gorow_args *a = &cache[y & 15];
	*fresh = !cached[y & 15];
	if (*fresh) {
		memset(a, 0, sizeof *a);
		a->fn = fv[0];
		a->fs = fv[1];
		pan_gorow_prep(j, t, hr, y, slots, a);
		cached[y & 15] = 1;
	}
	return a;
}

static void pan_gorow(const pan_job *j, const pan_kern *K, const pan_tables *t, float *hr[8][4],
                      float *const lw[2][2], float *const gr[3][8], const float *const fv[2],
                      const float *raw, uint32_t y, const pan_strip *st, pan_gorow_args *cache,
                      unsigned char *cached, int planar, float *rawp, float *const o[12],
                      const pan_lfuse *lf)
{
	const uint32_t w = st->w, xs = st->xs;
	const long n = st->n, nmain = st->nmain;
	int fresh;
	const int lean = j->guided == 5;
	pan_gorow_args *ap = pan_args_at(j, t, hr, fv, y, j->guided != 2, cache, cached, &fresh);
	for (int k = 0; fresh && k < 7; k++) {
		ap->p0row[k] = gr[0][((int)y + k - 3) & 7];
		ap->c1row[k] = gr[1][((int)y + k - 3) & 7];
		ap->c2row[k] = gr[2][((int)y + k - 3) & 7];
	}
	if (fresh && lean) {
		for (unsigned q = 0; q < 12; q++)
			ap->csame[q] = t->same[y & 3][q / 4];
		ap->lmu = lw[(y >> 1) & 1][0];
		ap->llam = lw[(y >> 1) & 1][1];
		ap->lcs = (float)(PC_DM_PAN_LEAN_CS * j->g);
		ap->lF = j->F;
		ap->lrho = lf->rho;
		ap->lfw = lf->fw;
		ap->lfe = lf->fe;
		ap->lwt = t->wt;
		ap->lh = hr[(y + 3) & 7][0];
	}
	if (lean) {
		/* the output row prefetches the raw row that the next output row's first new source
		 * row (y + 4) converts first, its pan_ssums reading y + 2 .. y + 6: a raw frame is
		 * read from memory once, and its conversion otherwise waits on it (4–5 % of
		 * pan-lean's time, docs/demosaicking.md, Round 28) */
		const uint32_t yp = y + 6 < j->h ? y + 6 : j->h - 1;
		const size_t bpp = pc_dm_type_bytes(j->in->type);
		ap->pf = j->in->data + (size_t)yp * j->in->stride + (size_t)xs * bpp;
		ap->pfb = (long)bpp;
	}
	const pan_gorow_fn kern = lean             ? K->lgorow
	                          : j->guided == 3 ? K->sgorow
	                          : j->guided == 2 ? K->cgorow
	                                           : K->gorow;
	float *d[12];
	if (planar) {
		for (int q = 0; q < 12; q++)
			d[q] = j->out[q].data + (size_t)y * j->out[q].row_stride + xs;
		kern(ap, raw, nmain, j->delta, j->e, d,
		     lean && j->nt ? (int)pan_nt_mask(d) : j->nt);
		if (nmain < n) {
			pan_gorow_args a = *ap;
			memcpy(rawp, raw + nmain, (size_t)((long)w - nmain) * sizeof *rawp);
			pan_gorow_shift(&a, nmain);
			kern(&a, rawp, 16, j->delta, j->e, o, 0);
			for (int q = 0; q < 12; q++)
				memcpy(d[q] + nmain, o[q],
				       (size_t)((long)w - nmain) * sizeof *o[q]);
		}
		return;
	}
	memcpy(rawp, raw, w * sizeof *rawp);
	kern(ap, rawp, n, j->delta, j->e, o, 0);
	pan_put_row(j, y, o, xs, xs + w);
}

/* pan-adapt's output row y: pan_gorow's terms and P0 rows (p0r: a ring of 16, the window
 * statistics reading two rows further down than pan-side), the N and S factors fv, the row's
 * window mean mu and variance var; the kernel pan_agorow, whole vectors into planar outputs, the
 * rest through the row buffer o. */
static void pan_agorow_row(const pan_job *j, const pan_akern *A, const pan_tables *t,
                           float *hr[8][4], float *const p0r[16], const float *const fv[2],
                           const float *mu, const float *var, const float *raw, uint32_t y,
                           const pan_strip *st, pan_gorow_args *cache, unsigned char *cached,
                           int planar, float *rawp, float *const o[12])
{
	const uint32_t w = st->w, xs = st->xs;
	const long n = st->n, nmain = st->nmain;
	int fresh;
	pan_gorow_args *ap = pan_args_at(j, t, hr, fv, y, 1, cache, cached, &fresh);
	if (fresh) {
		ap->mu = mu;
		ap->var = var;
		ap->ke = j->e;
		ap->e0 = j->e0;
		ap->kn = j->kn;
		for (int k = 0; k < 7; k++)
			ap->p0row[k] = p0r[((int)y + k - 3) & 15];
	}
	if (!planar) {
		memcpy(rawp, raw, w * sizeof *rawp);
		A->agorow(ap, rawp, n, j->delta, o, 0);
		pan_put_row(j, y, o, xs, xs + w);
		return;
	}
	float *d[12];
	for (int q = 0; q < 12; q++)
		d[q] = j->out[q].data + (size_t)y * j->out[q].row_stride + xs;
	A->agorow(ap, raw, nmain, j->delta, d, j->nt);
	if (nmain == n)
		return;
	pan_gorow_args a = *ap;
	memcpy(rawp, raw + nmain, (size_t)((long)w - nmain) * sizeof *rawp);
	pan_gorow_shift(&a, nmain);
	A->agorow(&a, rawp, 16, j->delta, o, 0);
	pan_put_row(j, y, o, xs + (uint32_t)nmain, xs + w);
}

/* pan_band's rows y0..y1 on the strip st, in the scratch buf (nrows rows of pitch floats,
 * zeroed here) */
static void pan_band_strip(const pan_job *j, const pan_tables *t, uint32_t y0, uint32_t y1,
                           const pan_strip *st, float *buf, size_t pitch, size_t nrows,
                           pan_gorow_args *cache)
{
	/* the output row's arguments are the same for rows 16 apart (every ring's length divides
	 * 16, the lattice's period 4), so they are made once per y mod 16 and strip */
	unsigned char cached[16] = {0};
	const uint32_t w = st->w, xs = st->xs;
	const int iw = (int)w;
	const long n = st->n, nmain = st->nmain;
	const int adapt = j->guided == 4;
	memset(buf, 0, sizeof(float) * pitch * nrows);
	const pan_kern K = pan_kernels(j->level);
	const pan_akern A = pan_akernels(j->level);
	int planar = 1;
	for (int q = 0; q < 12; q++)
		planar &= j->out[q].pixel_stride == 1;
	float *vs = buf + PAN_PADR, *rawp = vs + pitch, *rho = rawp + pitch;
	float *hbase = rho + pitch, *obase = hbase + 32 * pitch, *src = obase + 12 * pitch;
	float *hr[8][4], *o[12];
	/* ring slot k's four tents: rows of their own, or pan-lean's one row of PAN_LTS·pitch
	 * floats, tent s from its column block's 16·s (PAN_LTI) */
	for (int k = 0; k < 8; k++)
		for (int s = 0; s < 4; s++)
			hr[k][s] = j->guided == 5 ? hbase + (size_t)(4 * k) * pitch + 16 * (size_t)s
			                          : hbase + (size_t)(4 * k + s) * pitch;
	for (int q = 0; q < 12; q++)
		o[q] = obase + (size_t)q * pitch;
	pan_rows rc;
	for (int k = 0; k < 16; k++) {
		rc.slot[k] = src + (size_t)(5 + k) * pitch;
		rc.tag[k] = -1;
	}
	/* the strip's raw rows: the frame's columns [xs − PAN_PADR, xs + n + PAN_PADR) inside it
	 * converted, the others mirrored from them */
	rc.xs = xs;
	/* pan-lean's output row prefetches the raw row its next source row converts, a line at a
	 * time (pan_gorow's a->pf); a burst of the whole row at its conversion waited on memory
	 * (docs/demosaicking.md, Round 36) */
	rc.own_pf = j->guided == 5;
	rc.gl = xs > PAN_PADR ? xs - PAN_PADR : 0;
	rc.gh = xs + (uint32_t)n + PAN_PADR < j->w ? xs + (uint32_t)n + PAN_PADR : j->w;
	rc.npad = 0;
	for (long x = -PAN_PADR; x < n + PAN_PADR; x++) {
		const long g = (long)xs + x;
		if (g >= 0 && g < (long)j->w)
			continue;
		assert(rc.npad < 3 * PAN_PADR);
		rc.pad_dst[rc.npad] = (int)x;
		rc.pad_src[rc.npad++] = pc_mirror4((int)g, (int)j->w) - (int)xs;
	}
	float *gr[3][8]; /* pan-guided: the PPI rows of the ring; pan-chroma: and C1's, C2's */
	for (int g = 0; g < 3; g++)
		for (int k = 0; k < 8; k++)
			gr[g][k] = src + (size_t)(21 + 8 * g + k) * pitch;
	float *vsb = src + (size_t)45 * pitch;
	/* pan-side: the block hue (u1, u2) of the last four even source rows Y in hu[(Y & 7) >> 1],
	 * pan_cratio's chrominance rows ck, the factors W and E of the current block row (fh), N
	 * and S of the last two block rows Y in fv[(Y & 3) >> 1] */
	const int lean = j->guided == 5;
	const int side = j->guided == 3 || adapt || lean;
	const float eps = (float)PAN_SEPS;
	float *hu[4][2], *ck[2] = {gr[2][0], gr[2][1]}, *fh[2] = {gr[2][2], gr[2][3]},
	                 *fv[2][2] = {{gr[2][4], gr[2][5]}, {gr[2][6], gr[2][7]}};
	for (int k = 0; k < 4; k++)
		for (int c = 0; c < 2; c++)
			hu[k][c] = gr[1][2 * k + c];
	/* pan-adapt: its source rows run look = 2 rows ahead of its tents (the window statistics
	 * of row r read P0 down to r + 2), so P0 is kept in a ring of 16 (p0r), ρ in a ring of 4,
	 * the W/E factors of two block rows (fhr[(Y & 2) >> 1]), the N/S ones of four (fvr[(Y &
	 * 7) >> 1]); the rows' window means and variances (mur, varr) in rings of 4 */
	const int look = adapt ? 2 : 0;
	float *p0r[16], *rhor[4], *fhr[2][2], *fvr[4][2], *mur[4], *varr[4];
	if (adapt) {
		float *ab = src + (size_t)46 * pitch;
		for (int k = 0; k < 16; k++)
			p0r[k] = k < 8 ? gr[0][k] : ab + (size_t)(k - 8) * pitch;
		for (int k = 0; k < 4; k++) {
			rhor[k] = k ? ab + (size_t)(7 + k) * pitch : rho;
			fvr[k][0] = k < 2 ? fv[k][0] : ab + (size_t)(7 + 2 * k) * pitch;
			fvr[k][1] = k < 2 ? fv[k][1] : ab + (size_t)(8 + 2 * k) * pitch;
			mur[k] = ab + (size_t)(15 + k) * pitch;
			varr[k] = ab + (size_t)(19 + k) * pitch;
		}
		fhr[0][0] = fh[0];
		fhr[0][1] = fh[1];
		fhr[1][0] = ab + (size_t)23 * pitch;
		fhr[1][1] = ab + (size_t)24 * pitch;
	}
	/* pan-lean: the blocks' level pt of the last four even source rows in hp[(Y & 7) >> 1], the
	 * block windows' mean and λ of block row B (pan_lwin, made once source row B + 3 is, from
	 * the block levels of rows B − 2, B, B + 2) in lw[(B >> 1) & 1] (output row y reads block
	 * row y & ~1; the next one is made after it is done), its block terms lp; pan_lfach's e0
	 * of the last two block rows B (le[(B >> 1) & 1]), pan_lfacv's D to the S neighbours of the
	 * last block row (ld) */
	float *hp[4] = {NULL}, *lw[2][2] = {{NULL}}, *le[2] = {NULL}, *ld = NULL;
	pan_lpar lp = {0};
	if (lean) {
		float *lb = src + (size_t)46 * pitch;
		for (int k = 0; k < 4; k++)
			hp[k] = lb + (size_t)k * pitch;
		for (int k = 0; k < 2; k++)
			for (int s = 0; s < 2; s++)
				lw[k][s] = lb + (size_t)(4 + 2 * k + s) * pitch;
		le[0] = lb + (size_t)8 * pitch;
		le[1] = lb + (size_t)9 * pitch;
		ld = lb + (size_t)10 * pitch;
		lp = (pan_lpar){eps,
		                (float)(PC_DM_PAN_LEAN_KN * sqrt(j->g)),
		                (float)PC_DM_PAN_LEAN_KT,
		                (float)PC_DM_PAN_LEAN_MU,
		                j->delta,
		                j->F,
		                (float)(PC_DM_PAN_LEAN_CP * j->g)};
	}
	/* source rows computed: up to have; pan-side's first one even (a block's top row) */
	int have = side ? (((int)y0 - 3 - look) & ~1) - 1 : (int)y0 - 4;
	const int first = have + 1;
	for (uint32_t y = y0; y < y1; y++) {
		for (int yy = have < (int)y - 4 - look ? (int)y - 4 - look : have + 1;
		     yy <= (int)y + 3 + look; yy++) {
			/* ratio row of the extended source row yy, and its four tents */
			const int hue = side && !(yy & 1);
			const float *rs =
			    pan_ssums(j, &K, t, &rc, yy, vs, j->guided == 2 || hue ? vsb : NULL, n);
			if (side) {
				float *p0 = adapt ? p0r[yy & 15] : gr[0][yy & 7],
				      *rh = adapt ? rhor[yy & 3] : rho;
				if (hue) {
					/* the row's block hue, its W and E factors, and the N and S
					 * ones of the block row two above (whose S neighbour this
					 * is) */
					float *const *u = hu[(yy & 7) >> 1];
					float *const *fw = adapt ? fhr[(yy & 2) >> 1] : fh;
					K.cratio(vs, vsb, rs, -16, n + 32, j->delta, (float)lean,
					         t->ha, rh, p0, ck[0], ck[1]);
					float *pc = lean ? hp[(yy & 7) >> 1] : NULL;
					(lean ? K.lshue : K.shue)(p0, ck[0], ck[1], -16, n + 32,
					                          j->delta, u[0], u[1], pc);
					const float *uc[3] = {u[0], u[1], pc},
					            *uw[3] = {u[0] - PAN_SST, u[1] - PAN_SST},
					            *ue[3] = {u[0] + PAN_SST, u[1] + PAN_SST};
					if (lean)
						K.lfach(uc, n, &lp, fw[0], fw[1],
						        le[(yy >> 1) & 1]);
					else
						K.sfac(uc, uw, ue, n, eps, fw[0], fw[1]);
					if (yy - 2 * PAN_SST >= first) {
						const int ib = ((yy - PAN_SST) & 7) >> 1,
						          ia = ((yy - 2 * PAN_SST) & 7) >> 1;
						const float *ub[3] = {hu[ib][0], hu[ib][1], hp[ib]},
						            *ua[3] = {hu[ia][0], hu[ia][1], hp[ia]};
						float *const *f =
						    adapt ? fvr[((yy - PAN_SST) & 7) >> 1]
						          : fv[((yy - PAN_SST) & 3) >> 1];
						/* pan-lean's D_m: its last call's D_p, if any */
						if (lean)
							K.lfacv(ub, ua, uc,
							        le[((yy - PAN_SST) >> 1) & 1], ld,
							        yy - PAN_SST - 2 * PAN_SST >= first,
							        n, &lp, f[0], f[1]);
						else
							K.sfac(ub, ua, uc, n, eps, f[0], f[1]);
					}
				} else {
					K.ratio(vs, rs, -16, n + 32, j->delta, 0, (float)lean, rh,
					        p0);
				}
				if (lean) {
					/* the output row y makes the tents of its last source
					 * row y + 3 itself (pan_gorow) */
					if (yy != (int)y + 3)
						K.lhrows(rho, fh[0], fh[1], n, t->wt, hr[yy & 7]);
					if ((yy & 1) && yy - 5 >= first) {
						const float *pw[3];
						for (int k = 0; k < 3; k++)
							pw[k] = hp[((yy - 5 + 2 * k) & 7) >> 1];
						float *const *l = lw[((yy - 3) >> 1) & 1];
						K.lwin(pw, n, lp.cp, j->F, j->delta, l[0], l[1]);
					}
				} else if (!adapt) {
					K.sghrows(rho, p0, fh[0], fh[1], n, t->wt, j->e,
					          hr[yy & 7]);
				} else if (yy - 2 * look >= first) {
					/* row r's window statistics, then its tents */
					const int r = yy - look;
					const float *pr[5];
					for (int k = 0; k < 5; k++)
						pr[k] = p0r[(r + k - 2) & 15];
					float *const *fr = fhr[(r & 2) >> 1];
					A.atents(pr, rhor[r & 3], fr[0], fr[1], n, j->delta, t->wt,
					         j->e, j->e0, mur[r & 3], varr[r & 3], hr[r & 7]);
				}
			} else if (j->guided == 2) {
				float *p0 = gr[0][yy & 7], *c1 = gr[1][yy & 7], *c2 = gr[2][yy & 7];
				K.cratio(vs, vsb, rs, -16, n + 32, j->delta, 0, t->ha, rho, p0, c1,
				         c2);
				K.cghrows(rho, p0, c1, c2, n, t->wt, j->e, hr[yy & 7]);
			} else if (j->guided) {
				float *p0 = gr[0][yy & 7];
				K.ratio(vs, rs, -16, n + 32, j->delta, 0, 0, rho, p0);
				K.ghrows(rho, p0, n, t->wt, j->e, hr[yy & 7]);
			} else {
				K.ratio(vs, rs, -16, n + 32, j->delta, 0, 0, rho, NULL);
				K.hrows(rho, n, t->wt, hr[yy & 7]);
			}
		}
		have = (int)y + 3 + look;
		if (adapt) {
			const float *fy[2] = {fvr[(y & 6) >> 1][0], fvr[(y & 6) >> 1][1]};
			pan_agorow_row(j, &A, t, hr, p0r, fy, mur[y & 3], varr[y & 3],
			               pan_row_strip(&rc, j->in, (int)y), y, st, cache, cached,
			               planar, rawp, o);
			continue;
		}
		if (j->guided) {
			const float *fy[2] = {fv[(y & 2) >> 1][0], fv[(y & 2) >> 1][1]};
			const pan_lfuse lf = {rho, fh[0], fh[1]};
			pan_gorow(j, &K, t, hr, lw, gr, fy, pan_row_strip(&rc, j->in, (int)y), y,
			          st, cache, cached, planar, rawp, o, &lf);
			continue;
		}
		/* channel q's lattice rows around y, with the tent's vertical weights */
		pan_orow_args a;
		memset(&a, 0, sizeof a);
		const uint32_t ty = y & 3;
		pan_lattice l;
		pan_lattice_rows(j->m, (int)y, &l);
		for (int q = 0; q < 12; q++)
			for (int i = 0; i < l.n[q]; i++) {
				a.vrow[q][i] = hr[l.slot[q][i]][l.px[q][i]];
				a.vw[q][i] = l.wt[q][i];
			}
		memcpy(a.nv, l.n, sizeof a.nv);
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
			a.own[u] = pan_q(j->m, u, ty);
		}
		const float *raw = pan_row_strip(&rc, j->in, (int)y);
		if (planar) {
			/* whole vectors straight into the planes, the rest through the row buffer
			 */
			float *d[12];
			for (int q = 0; q < 12; q++)
				d[q] = j->out[q].data + (size_t)y * j->out[q].row_stride + xs;
			K.orow(&a, raw, nmain, j->delta, d, j->nt);
			if (nmain < n) {
				memcpy(rawp, raw + nmain, (size_t)(iw - nmain) * sizeof *rawp);
				for (int q = 0; q < 12; q++)
					for (int i = 0; i < a.nv[q]; i++)
						a.vrow[q][i] += nmain;
				K.orow(&a, rawp, 16, j->delta, o, 0);
				pan_put_row(j, y, o, xs + (uint32_t)nmain, xs + w);
			}
			continue;
		}
		memcpy(rawp, raw, w * sizeof *rawp);
		K.orow(&a, rawp, n, j->delta, o, 0);
		pan_put_row(j, y, o, xs, xs + w);
	}
}

/* A band of output rows y0..y1, in column strips of at most about PAN_STRIPW columns (whole
 * vectors; docs/demosaicking.md, Round 17c): each strip computes its source rows on its own
 * columns and a halo (the rows' pads read the neighbouring strips' columns, mirrored only at
 * the frame's edges), so every value is the whole row's, in a scratch a strip wide that stays
 * in a core's L2. Inputs with dark or gain maps take one strip (pan_row_strip converts a
 * column range through a sub-view, which the maps' indexing does not follow). */
static void pan_band(void *ctx, uint32_t y0, uint32_t y1)
{
	pan_job *j = ctx;
	const uint32_t w = j->w;
	const long nfull = ((long)w + 15) / 16 * 16; /* columns computed: whole vectors */
	long ns = (nfull + PAN_STRIPW - 1) / PAN_STRIPW;
	if (j->in->dark || j->in->gain_inv || ns < 1)
		ns = 1;
	/* strip k: columns [xs_k, xs_{k+1}), xs_k = 16·round(k·nfull/(16·ns)) (each at least 64
	 * wide when ns > 1: the pads' mirror sources stay in the first and last strips' columns) */
	long nmax = 0;
	for (long k = 0; k < ns; k++) {
		const long a = k * nfull / ns / 16 * 16, b = (k + 1) * nfull / ns / 16 * 16;
		nmax = b - a > nmax ? b - a : nmax;
	}
	const size_t pitch = (size_t)nmax + 2 * PAN_PADR;
	pan_tables *t = pc_dm_alloc(sizeof *t);
	pan_gorow_args *cache = pc_dm_alloc(16 * sizeof *cache);
	/* scratch: vertical sums and the raw row (padded), the ratio row, 8 × 4 tent rows, 12
	 * output rows, 5 rows unused, 16 cached raw rows, 8 PPI rows (pan-guided), 8 + 8
	 * chrominance rows and a weighted vertical sum (pan-chroma; pan-side keeps its hue,
	 * chrominance and factor rows in the latter 16); pan-adapt PAN_AROWS more, pan-lean
	 * PAN_LROWS */
	const int adapt = j->guided == 4;
	const size_t nrows = 52 + 16 + 8 + 17 +
	                     (adapt            ? PAN_AROWS
	                      : j->guided == 5 ? PAN_LROWS
	                                       : 0);
	float *buf = pc_dm_alloc(sizeof(float) * pitch * nrows);
	if (!t || !buf || !cache) {
		pc_dm_free(t);
		pc_dm_free(buf);
		pc_dm_free(cache);
		j->err = 1;
		return;
	}
	pan_tables_init(t, j->m);
	for (long k = 0; k < ns; k++) {
		const long a = k * nfull / ns / 16 * 16,
		           b = k + 1 < ns ? (k + 1) * nfull / ns / 16 * 16 : (long)w;
		pan_strip st = {(uint32_t)a, (uint32_t)(b - a), (b - a + 15) / 16 * 16,
		                (b - a) / 16 * 16};
		pan_band_strip(j, t, y0, y1, &st, buf, pitch, nrows, cache);
	}
	if (j->nt || j->ntil)
		pc_dm_sfence();
	pc_dm_free(t);
	pc_dm_free(buf);
	pc_dm_free(cache);
}

/* The fast paths of pan-ratio, pan-guided (guided 1), pan-chroma (2), pan-side (3), pan-adapt (4)
 * and pan-lean (5), g the frame's noise gain for the last two: one fused pass on row bands;
 * guided 1–4 add the range weights of scale e. */
static int pan_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out, int guided, double g)
{
	/* pan-adapt's noise term's factor */
	const double kn = guided == 4 ? PC_DM_PAN_ADAPT_C * (14.0 / 64) * (14.0 / 64) * g : 0;
	const uint32_t w = in->width, h = in->height;
	pan_job j = {in,
	             w,
	             h,
	             m,
	             (float)((guided == 4 ? PC_DM_PAN_ADAPT_DFS : PAN_DELTA) * fs),
	             level,
	             out,
	             0,
	             guided,
	             guided == 4   ? (float)PC_DM_PAN_ADAPT_KE
	             : guided == 3 ? (float)(PAN_SE * fs)
	             : guided == 2 ? (float)(PAN_CE * fs)
	             : guided      ? (float)(PAN_E * fs)
	                           : 0,
	             pc_dm_stream_wanted(out, 12, w, h, level),
	             (float)kn,
	             (float)(PC_DM_PAN_ADAPT_EFS * fs),
	             g,
	             (float)(PC_DM_NG_FLOOR * fs),
	             pc_dm_stream_wanted_il(out, 12, w, h, level)};
	pc_parallel_rows(h, 0, threads, pan_band, &j);
	if (j.err)
		return pc_error(PC_ENOMEM, "%s: row buffers for width %u",
		                guided == 5   ? "pan-lean"
		                : guided == 4 ? "pan-adapt"
		                : guided == 3 ? "pan-side"
		                : guided == 2 ? "pan-chroma"
		                : guided      ? "pan-guided"
		                              : "pan-ratio",
		                w);
	return 0;
}

/* ---- pan-dir's fast path ----
 *
 * The same source rows as pan-ratio's (ratio rows ρ, kept in a ring of 8 beside rows of
 * ρ' = ρ − 1 (pan_dratio), with, for each column phase s, the hold row of s of ρ': pan_dwrows,
 * and the row's linear interpolation between its samples of phase s: pan_dprows; ρ' keeps the
 * black exact, pan_dgam). A tent of half-width 4 on a lattice of spacing 4 is linear
 * interpolation between the two nearest lattice samples (one where the pixel is on the
 * lattice), so each lattice's five candidates at a pixel are functions of its four corner
 * samples and its two rows' interpolations: C bilinear, W and E along the west and east
 * columns, N and S the north and south rows' interpolations, the fractions set by the pixel's
 * phase. Two stages per output row y: first row y + 1 (clamped to the image) gets the one-sided
 * candidates' chromaticities (two rows kept, for the vertical differences), their variation
 * rows and boxes (a ring of 4 rows per candidate); then row y's blend weights (pan_dgam, from
 * the boxes of rows y - 1 .. y + 1) and its outputs, each lattice's term a weighted sum of its
 * samples with coefficients per row phase (pan_dorow). */
typedef struct pan_dtables {
	float tw[4][4][16]; /* hold rows' lane patterns: (lane − s) mod 4 = k */
	float fa[4][16];    /* ((lane − s) mod 4)/4 */
	float gsel[4][16];  /* row phase t: 1 on green pixels */
	float zero[16];
	unsigned ox; /* the colour blocks' column origin */
} pan_dtables;

static void pan_dtables_init(pan_dtables *t, const pc_mosaic *m)
{
	memset(t, 0, sizeof *t);
	unsigned oy;
	(void)pc_mosaic_color_origin(m, &t->ox, &oy); /* a colour mosaic: blocks of 2×2 */
	for (int l = 0; l < 16; l++) {
		int u = l & 3;
		for (int s = 0; s < 4; s++) {
			t->tw[s][(u - s) & 3][l] = 1;
			t->fa[s][l] = (float)((u - s) & 3) / 4;
			t->gsel[s][l] = pc_mosaic_color(m, (unsigned)u, (unsigned)s) == PC_CFA_G;
		}
	}
}

/* pan-dir's and pan-fact's band scratch: the tables and nrows rows of pitch floats, zeroed; NULL
 * (and j->err set) when memory runs out */
static float *pan_dband_scratch(pan_job *j, size_t nrows, size_t pitch, pan_tables **t,
                                pan_dtables **dt)
{
	*t = pc_dm_alloc(sizeof **t);
	*dt = pc_dm_alloc(sizeof **dt);
	float *buf = pc_dm_alloc(sizeof(float) * pitch * nrows);
	if (!*t || !*dt || !buf) {
		pc_dm_free(*t);
		pc_dm_free(*dt);
		pc_dm_free(buf);
		j->err = 1;
		return NULL;
	}
	memset(buf, 0, sizeof(float) * pitch * nrows);
	pan_tables_init(*t, j->m);
	pan_dtables_init(*dt, j->m);
	return buf;
}

/* ... and its end: the fence after streaming stores, the scratch freed */
static void pan_dband_end(const pan_job *j, pan_tables *t, pan_dtables *dt, float *buf)
{
	if (j->nt || j->ntil)
		pc_dm_sfence();
	pc_dm_free(t);
	pc_dm_free(dt);
	pc_dm_free(buf);
}

static void fill16(float v[16], float f)
{
	for (int l = 0; l < 16; l++)
		v[l] = f;
}

/* green's weights in N and S of its lattice at row phase t (the other at t + 2): each lattice
 * row's vertical tent, 4 − e above, e below (4 on the row itself), normalised over the two */
static void dgreen_weights(int Y, unsigned t, float *gn, float *gs)
{
	int e0, e1, yn, ys;
	lattice_rows(Y, t, &e0, &yn, &ys);
	lattice_rows(Y, (t + 2) & 3, &e1, &yn, &ys);
	const float n0 = (float)(4 - e0), n1 = (float)(4 - e1), s0 = (float)(e0 ? e0 : 4),
	            s1 = (float)(e1 ? e1 : 4);
	*gn = n0 / (n0 + n1);
	*gs = s0 / (s0 + s1);
}

/* row Y's first-stage groups (pan_dlat_args) from the ring's column-pair rows hp, lp[slot][p] */
static void pan_dstage_args(const pan_job *j, const pan_dtables *dt, float *const hp[8][2],
                            float *const lp[8][2], int Y, pan_dlat_args *a)
{
	int ng[3] = {0, 2, 6};
	for (unsigned t = 0; t < 4; t++)
		for (unsigned k = 0; k < 3; k++) {
			/* colour k's pair on row phase t, if any */
			unsigned s = 0;
			while (s < 4 && pc_mosaic_color(j->m, s, t) != PC_CFA_R + k)
				s++;
			if (s == 4)
				continue;
			const unsigned pp = ((s - dt->ox) & 3) >> 1;
			const int g = ng[k]++;
			int e, yn, ys;
			lattice_rows(Y, t, &e, &yn, &ys);
			a->hpn[g] = hp[yn & 7][pp];
			a->hps[g] = hp[ys & 7][pp];
			a->lpn[g] = lp[yn & 7][pp];
			a->lps[g] = lp[ys & 7][pp];
			fill16(a->gb[g], (float)e / 4);
			if (k == 1) {
				float gn, gs;
				dgreen_weights(Y, t, &gn, &gs);
				fill16(a->ggn[g - 2], gn);
				fill16(a->ggs[g - 2], gs);
			}
		}
}

/* the output row Y's lattices, groups and rows (pan_dlat_args) from the ring's hold rows
 * hw[slot][s], their interpolations li[slot][s] and ratio rows rr[slot] */
static void pan_dout_args(const pan_job *j, const pan_tables *t, const pan_dtables *dt,
                          float *const hw[8][4], float *const li[8][4], float *const rr[8], int Y,
                          pan_dlat_args *a)
{
	for (int q = 0; q < 12; q++)
		a->osel[q] = dt->zero;
	for (unsigned u = 0; u < 4; u++)
		a->osel[pan_q(j->m, u, (unsigned)Y & 3)] = t->sel[u];
	for (unsigned ty = 0; ty < 4; ty++) {
		int e, yn, ys, nrb = 0, ng = 0;
		lattice_rows(Y, ty, &e, &yn, &ys);
		const float b = (float)e / 4;
		float gn, gs;
		dgreen_weights(Y, ty, &gn, &gs);
		a->full[ty] = e != 0;
		a->cu[ty][0] = 1 - b;
		a->cu[ty][1] = b;
		a->cu[ty][2] = (1 - b) / 2;
		a->cu[ty][3] = b / 2;
		a->cg[ty][0] = gn;
		a->cg[ty][1] = gs;
		for (unsigned s = 0; s < 4; s++) {
			const int L = 4 * (int)ty + (int)s;
			a->nrow[L] = a->nrowe[L] = hw[yn & 7][s];
			a->srow[L] = a->srowe[L] = hw[ys & 7][s];
			a->lnrow[L] = li[yn & 7][s];
			a->lsrow[L] = li[ys & 7][s];
			a->lq[L] = (int)pan_q(j->m, s, ty);
			if (pc_mosaic_color(j->m, s, ty) != PC_CFA_G)
				a->rl[ty][nrb++] = L;
			else if (ty < 2) {
				/* a green channel: its other lattice at (s + 2, t + 2) */
				a->gl[ty][ng][0] = L;
				a->gl[ty][ng++][1] = 4 * ((int)ty + 2) + (int)((s + 2) & 3);
			}
		}
	}
	for (int G = 0; G < 2; G++) {
		a->gt[G][0] = G;
		a->gt[G][1] = G + 2;
	}
	a->gsel = dt->gsel[Y & 3];
	a->r0 = rr[Y & 7];
	a->rn = rr[(Y - 2) & 7];
	a->rs = rr[(Y + 2) & 7];
	a->base = dt->zero; /* pan-fact's; pan_dir_band sets pan_dgam's row */
	a->bmask = 0;
}

/* one variation of pan_dvar at x (vert: against the row above p, else against column x − 1) */
static float pan_dvar1(const float *const c[2], const float *const p[2], int x, int vert)
{
	float r = c[0][x] - (vert ? p[0][x] : c[0][x - 1]),
	      g = c[1][x] - (vert ? p[1][x] : c[1][x - 1]);
	return (fabsf(r) + fabsf(g)) + fabsf(r + g);
}

/* E's boxes (pan_dbox's bh, ba) of a row from W's (bhw, baw): E's chromaticity is W's three
 * columns on (pan_dchroma), so are its variations and boxes wherever neither reads a clamped
 * column, x in [1, iw − 5]; at x = 0 and x ≥ iw − 4 they are computed from E's chromaticities c
 * (clamped at the borders) and the row above's p, in pan_dvar's and pan_dbox's order. */
static void pan_dbox_e(const float *const c[2], const float *const p[2], const float *bhw,
                       const float *baw, int iw, long n, float *bh, float *ba)
{
	for (long x = 0; x < n; x++) {
		bh[x] = bhw[x + 3];
		ba[x] = baw[x + 3];
	}
	for (int x = 0; x < iw; x = x ? x + 1 : (iw - 4 > 1 ? iw - 4 : 1)) {
		float h = pan_dvar1(c, p, x, 0) + pan_dvar1(c, p, x + 1, 0);
		bh[x] = h;
		ba[x] = h + ((pan_dvar1(c, p, x - 1, 1) + pan_dvar1(c, p, x, 1)) +
		             pan_dvar1(c, p, x + 1, 1));
	}
}

static void pan_dir_band(void *ctx, uint32_t y0, uint32_t y1)
{
	pan_job *j = ctx;
	const uint32_t w = j->w, h = j->h;
	const int iw = (int)w, ih = (int)h;
	const long n = ((long)w + 15) / 16 * 16, nmain = (long)w / 16 * 16;
	const size_t pitch = (size_t)n + 2 * PAN_PADR;
	pan_tables *t;
	pan_dtables *dt;
	/* rows: vs, rawp, the raw row of the output; 21 of source scratch and cache; 8 × (ρ, 4
	 * hold rows, 2 + 2 column-pair rows, 4 interpolated rows); 2 × 4 × 2 chromaticities (red's,
	 * green's of W, E, N, S); dh, dv; 4 × 4 × 2 boxes (bh, ba); 5 blend weights; 12 output
	 * rows; 8 rows of ρ' (beside ρ's); the base row */
	const size_t nrows = 3 + 21 + 104 + 16 + 2 + 32 + 5 + 12 + 8 + 1;
	float *buf = pan_dband_scratch(j, nrows, pitch, &t, &dt);
	if (!buf)
		return;
	const pan_kern K = pan_kernels(j->level);
	int planar = 1;
	for (int q = 0; q < 12; q++)
		planar &= j->out[q].pixel_stride == 1;
	float *row = buf + PAN_PADR;
#define PAN_ROW(i) (row + (size_t)(i)*pitch)
	float *vs = PAN_ROW(0), *rawp = PAN_ROW(1), *rawo = PAN_ROW(2);
	float *src = PAN_ROW(3);
	pan_rows rc;
	for (int k = 0; k < 16; k++) {
		rc.slot[k] = PAN_ROW(8 + k);
		rc.tag[k] = -1;
	}
	float *rr[8], *hw[8][4], *li[8][4], *hp[8][2], *lp[8][2], *cr[2][4][2], *bh[4][4],
	    *ba[4][4], *g[5], *o[12];
	for (int k = 0; k < 8; k++) {
		rr[k] = PAN_ROW(24 + 13 * k);
		for (int s = 0; s < 4; s++) {
			hw[k][s] = PAN_ROW(25 + 13 * k + s);
			li[k][s] = PAN_ROW(29 + 13 * k + s);
		}
		for (int p = 0; p < 2; p++) {
			hp[k][p] = PAN_ROW(33 + 13 * k + p);
			lp[k][p] = PAN_ROW(35 + 13 * k + p);
		}
	}
	for (int k = 0; k < 2; k++)
		for (int d = 0; d < 4; d++)
			for (int c = 0; c < 2; c++)
				cr[k][d][c] = PAN_ROW(128 + 8 * k + 2 * d + c);
	float *dh = PAN_ROW(144), *dv = PAN_ROW(145);
	for (int k = 0; k < 4; k++)
		for (int d = 0; d < 4; d++) {
			bh[k][d] = PAN_ROW(146 + 8 * k + d);
			ba[k][d] = PAN_ROW(150 + 8 * k + d);
		}
	for (int d = 0; d < 5; d++)
		g[d] = PAN_ROW(178 + d);
	for (int q = 0; q < 12; q++)
		o[q] = PAN_ROW(183 + q);
	float *r1[8], *bs = PAN_ROW(203);
	for (int k = 0; k < 8; k++)
		r1[k] = PAN_ROW(195 + k);
#undef PAN_ROW
	int have = (int)y0 - 8;                     /* source rows computed: up to have */
	const int first = y0 > 0 ? (int)y0 - 1 : 0; /* the first row of the first stage */
	int cdone = first - 1;
	pan_dlat_args a;
	for (uint32_t y = y0; y < y1; y++) {
		const int ct = (int)y + 1 < ih ? (int)y + 1 : ih - 1;
		for (int yc = cdone + 1; yc <= ct; yc++) {
			/* the source rows yc - 3 .. yc + 3 (the ring holds yc - 4 .. yc + 3; the
			 * output row y <= yc reads y - 3 .. y + 3) */
			for (int yy = have + 1 > yc - 4 ? have + 1 : yc - 4; yy <= yc + 3; yy++) {
				pan_src_sums(j, &K, t, &rc, yy, src, vs, NULL, rawp, n, nmain);
				K.dratio(vs, rawp, -16, n + 32, j->delta, rr[yy & 7], r1[yy & 7]);
				K.dwrows(r1[yy & 7], 0, n + 16, dt->tw, hw[yy & 7]);
				K.dprows(hw[yy & 7], n, dt->fa, dt->ox, li[yy & 7], hp[yy & 7],
				         lp[yy & 7]);
			}
			if (yc + 3 > have)
				have = yc + 3;
			/* the first stage for row yc */
			pan_dstage_args(j, dt, hp, lp, yc, &a);
			float *const(*c)[2] = cr[yc & 1];
			K.dchroma(&a, n, c);
			for (int d = 0; d < 4; d++) {
				for (int k = 0; k < 2; k++)
					pan_pad_row(c[d][k], iw, n, PAN_PAD_CLAMP);
				const float *cc[2] = {c[d][0], c[d][1]};
				float *const *pp = yc == first ? c[d] : cr[(yc - 1) & 1][d];
				const float *pc[2] = {pp[0], pp[1]};
				if (d ==
				    1) { /* E's boxes: W's three columns on, but at the borders */
					pan_dbox_e(cc, pc, bh[yc & 3][0], ba[yc & 3][0], iw, n,
					           bh[yc & 3][1], ba[yc & 3][1]);
					continue;
				}
				K.dvar(cc, pc, -16, n + 32, dh, dv);
				K.dbox(dh, dv, n, bh[yc & 3][d], ba[yc & 3][d]);
			}
			cdone = yc;
		}
		/* the output row y: H_d = bh(y − 1) + ba(y) + ba(y + 1), at the last row bh(y) for
		 * the clamped row y + 1 (no vertical differences) */
		const int ym = y > 0 ? (int)y - 1 : 0;
		const float *hb[4][3];
		for (int d = 0; d < 4; d++) {
			hb[d][0] = bh[ym & 3][d];
			hb[d][1] = ba[y & 3][d];
			hb[d][2] = (int)y + 1 < ih ? ba[(y + 1) & 3][d] : bh[y & 3][d];
		}
		pan_dout_args(j, t, dt, hw, li, rr, (int)y, &a);
		memcpy(rawo, pan_row(&rc, j->in, (int)y), w * sizeof *rawo);
		K.dgam(&a, hb, rawo, 0, n, j->delta, g, bs);
		a.base = bs;
		a.bmask = ~0L;
		const float *gc[5] = {g[0], g[1], g[2], g[3], g[4]};
		float *dq[12];
		if (planar) {
			for (int q = 0; q < 12; q++)
				dq[q] = j->out[q].data + (size_t)y * j->out[q].row_stride;
			K.dorow(&a, gc, rawo, 0, nmain, dq, 0, j->nt);
			if (nmain < n) {
				K.dorow(&a, gc, rawo, nmain, n, o, nmain, 0);
				pan_put_row(j, y, o, (uint32_t)nmain, w);
			}
			continue;
		}
		K.dorow(&a, gc, rawo, 0, n, o, 0, 0);
		pan_put_row(j, y, o, 0, w);
	}
	pan_dband_end(j, t, dt, buf);
}

int pc_dm_pan_dir_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                       pc_cpu_level level, const pc_fplane *out)
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
	             0,
	             0,
	             pc_dm_stream_wanted(out, 12, w, h, level),
	             0,
	             0,
	             0,
	             0,
	             pc_dm_stream_wanted_il(out, 12, w, h, level)};
	pc_parallel_rows(h, 0, threads, pan_dir_band, &j);
	if (j.err)
		return pc_error(PC_ENOMEM, "pan-dir: row buffers for width %u", w);
	return 0;
}

int pc_dm_pan_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 0, 0);
}

int pc_dm_pan_guided_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 1, 0);
}

/* pan-side's fast path: pan-guided's (pan_band), each even source row's block hue and W/E
 * factors from pan-chroma's chrominance (pan_cratio, pan_shue, pan_sfac), the block row two
 * above it getting its N/S factors there; the factors multiply pan-guided's weights in
 * pan_sghrows and pan_sgorow. */
int pc_dm_pan_side_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 3, 0);
}

/* pan-adapt's fast path: pan-side's pass (pan_band, guided 4) with each source row's window
 * statistics two rows behind its P0, the range scale e_fs·FS + k_e·μ in the tents (both
 * pan_atents) and in the output row (pan_agorow), and the ratio step's level shrunk there; g,
 * the frame's noise gain, pc_dm_noise_gain_in's (the reference's, bit for bit). It sums 5 × 5
 * windows. */
_Static_assert(PC_DM_PAN_ADAPT_RE == 2 && PC_DM_PAN_ADAPT_R == 2,
               "pan-adapt's fast path (pan_atents) sums 5 x 5 windows");

int pc_dm_pan_adapt_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           pc_cpu_level level, double g, const pc_fplane *out)
{
	if (!isfinite(g))
		return pc_error(PC_EINVAL, "pan-adapt: noise gain %g not finite", g);
	if (g < 0) {
		int rc = pc_dm_noise_gain_in_mt(in, m, fs, threads, &g);
		if (rc)
			return rc;
	}
	return pan_run(in, m, fs, threads, level, out, 4, g);
}

int pc_dm_pan_adapt_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out)
{
	return pc_dm_pan_adapt_fast_g(in, m, fs, threads, level, -1, out);
}

/* pan-lean's fast path (docs/demosaicking.md, Rounds 22 and 29): pan-side's pass (pan_band,
 * guided 5) with pan-lean's block terms (pan_lshue: the hue and block level in compact rows;
 * pan_lfach, pan_lfacv: its side distances and ε_B), the tents of the ratios with the side
 * factors alone (pan_lhrows, interleaved tent rows) and its output row (pan_lgorow: both sums,
 * the cored level, the blends); g, the frame's noise gain, pc_dm_noise_gain_in_mt's when not
 * given. */
int pc_dm_pan_lean_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, double g, const pc_fplane *out)
{
	if (!(g >= 0) || !isfinite(g))
		return pc_error(PC_EINVAL, "pan-lean: noise gain %g, expected finite and >= 0", g);
	return pan_run(in, m, fs, threads, level, out, 5, g);
}

int pc_dm_pan_lean_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out)
{
	double g = 0;
	int rc = pc_dm_noise_gain_in_mt(in, m, fs, threads, &g);
	return rc ? rc : pc_dm_pan_lean_fast_g(in, m, fs, threads, level, fmax(g, 0), out);
}

const pc_dm_pan_fns *pc_dm_pan_fns_get(pc_demosaic_method m)
{
	static const pc_dm_pan_fns ratio = {pc_dm_pan_ref, pc_dm_pan_fast, NULL, NULL},
	                           guided = {pc_dm_pan_guided_ref, pc_dm_pan_guided_fast, NULL,
	                                     NULL},
	                           chroma = {pc_dm_pan_chroma_ref, pc_dm_pan_chroma_fast, NULL,
	                                     NULL},
	                           dir = {pc_dm_pan_dir_ref, pc_dm_pan_dir_fast, NULL, NULL},
	                           side = {pc_dm_pan_side_ref, pc_dm_pan_side_fast, NULL, NULL},
	                           adapt = {pc_dm_pan_adapt_ref, pc_dm_pan_adapt_fast,
	                                    pc_dm_pan_adapt_ref_g, pc_dm_pan_adapt_fast_g},
	                           guard = {pc_dm_pan_guard_ref, pc_dm_pan_guard_fast,
	                                    pc_dm_pan_guard_ref_g, pc_dm_pan_guard_fast_g},
	                           hue = {pc_dm_pan_hue_ref, NULL, NULL, NULL},
	                           check = {pc_dm_pan_check_ref, pc_dm_pan_check_fast, NULL, NULL},
	                           split = {pc_dm_pan_split_ref, NULL, NULL, NULL},
	                           lean = {pc_dm_pan_lean_ref, pc_dm_pan_lean_fast,
	                                   pc_dm_pan_lean_ref_g, pc_dm_pan_lean_fast_g};
	return m == PC_DM_PAN_RATIO    ? &ratio
	       : m == PC_DM_PAN_GUIDED ? &guided
	       : m == PC_DM_PAN_CHROMA ? &chroma
	       : m == PC_DM_PAN_DIR    ? &dir
	       : m == PC_DM_PAN_SIDE   ? &side
	       : m == PC_DM_PAN_ADAPT  ? &adapt
	       : m == PC_DM_PAN_GUARD  ? &guard
	       : m == PC_DM_PAN_HUE    ? &hue
	       : m == PC_DM_PAN_CHECK  ? &check
	       : m == PC_DM_PAN_SPLIT  ? &split
	       : m == PC_DM_PAN_LEAN   ? &lean
	                               : NULL;
}

int pc_dm_pan_chroma_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out)
{
	return pan_run(in, m, fs, threads, level, out, 2, 0);
}

/* ---- pan-fact's fast path ----
 *
 * pc_dm_pan_fact_ref's definition (demosaic_fact.c) on row bands, float, every intermediate a
 * row in a per-thread ring; exact in real arithmetic, reordered in float. Per (extended) source
 * row, pan-dir's: the ratio row ρ = max(v, 0)/max(P0, δ_h) (pan_ratio with δ = 0 and floor
 * δ_h), its hold rows and row interpolations per column phase (pan_dwrows, pan_dprows), and
 * for green's two column phases its hold rows weighed for W and E (fact_gwrows: a green channel's
 * one-sided tent over its two lattices weighs each lattice's hold by 4 − |dx|, normalised,
 * where pan-dir takes 1/2 each; stored times 2 so that pan-dir's halved green coefficients
 * apply). Then, in order:
 *  - per block row (its top row Y ≡ the colour blocks' row origin, mod 2), the block sums at
 *    pixel resolution (each column holds its block's sum, fact_bsum) and their horizontal
 *    interpolations of red-or-blue and of green along the row (fact_taps at x ± 1, x ± 3: a
 *    colour's two blocks within ±3.5 of x, weights (4 − |dx|)/4);
 *  - per pixel row r, the block columns' vertical interpolations (fact_taps over the four
 *    block rows within ±3.5) and the four candidates' chromaticities (fact_chroma: W and E read
 *    the near and far block column at x ∓ 1, x ∓ 3, N and S the rows' interpolations), c
 *    clamped at the borders, their variation rows (pan_dvar) and boxes (fact_box): per row the
 *    horizontal box bh and the full box be of the block whose left column is x;
 *  - per block row, the blend weights γ_d = w_d/Σ w (fact_gam: H_d the box of the window's
 *    rows Y − 1 .. Y + 2, clamped rows repeating the edge row's horizontal box);
 *  - per row yc, step 4: Σ_d γ_d R^d_q of the twelve channels by pan-dir's output kernel
 *    (pan_dorow: the blend folded into each row phase's lattice coefficients; base 0, no own
 *    channel), kept for three rows, then m = v/h_own (fact_m), m padded by the whole-sample
 *    mirror; the output row computes the hue h again from the blended ratios (four divisions),
 *    which costs less than storing twelve hue rows and reading them back;
 *  - per row, step 6's guide and ratios (fact_ppi2), the ratio step's reference scale
 *    (max(m, 0) + δ)/ρ(p) taken as max(P, 0) + δ, its equal in real arithmetic;
 *  - the output row y (fact_orow) from rows y − 1 .. y + 1 of the ratios, m of row y and its
 *    blended ratios (the hue h computed again there): step 4 runs two rows ahead of the
 *    output, the chromaticities four. */
typedef struct fact_job {
	pan_job j; /* delta: step 6's δ */
	float eps; /* step 2's floor: FACT_EPS of the block sums' full scale 4·fs */
	float dh;  /* step 4's δ_h */
} fact_job;

/* the lane patterns of one band (lane l at column phase l mod 4) */
typedef struct fact_tables {
	float par[16];              /* 1 on the right columns of the colour blocks */
	float gw[4][16], ge[4][16]; /* green's hold weights (×2) for W and E, by column phase */
	fact_cargs ca;              /* W's and E's weights (the rows set per row) */
	/* fact_taps' weights: a block row's horizontal interpolations by its top row's phase
	 * (y mod 4), the block columns' vertical ones at row r by r mod 4 */
	float bt[4][2][4][16], vt[4][2][4][16];
} fact_tables;

static int fact_col(const pc_mosaic *m, int x, int y)
{
	return (int)pc_mosaic_color(m, (unsigned)x & 3, (unsigned)y & 3) - PC_CFA_R;
}

/* the left column of the colour block holding column x */
static int fact_x0(int x, unsigned ox)
{
	return x - ((x - (int)ox) & 1);
}

/* whether colour k is on block column x0 */
static int fact_on_col(const pc_mosaic *m, int k, int x0)
{
	for (int y = 0; y < 4; y++)
		if (fact_col(m, x0, y) == k)
			return 1;
	return 0;
}

static int fact_on_row(const pc_mosaic *m, int k, int y0)
{
	for (int x = 0; x < 4; x++)
		if (fact_col(m, x, y0) == k)
			return 1;
	return 0;
}

/* a green lattice's share in the one-sided tent at distance e (0..3) from its hold: the other
 * lattice is 2 columns on, (4 − e)/((4 − e) + (4 − (e + 2) mod 4)) */
static float fact_gshare(int e)
{
	return (float)(4 - e) / (float)(8 - e - ((e + 2) & 3));
}

/* fact_blocks_to's weights for the block row with top row y: red-or-blue's (wt[0]) and green's
 * (wt[1]) two blocks within ±3.5 of x, at x ± 1, x ± 3, weights (4 − |dx|)/4 */
static const int fact_hoff[4] = {-3, -1, 1, 3};

static void fact_htaps(const pc_mosaic *m, unsigned ox, int y, float wt[2][4][16])
{
	for (int l = 0; l < 16; l++)
		for (int i = 0; i < 4; i++) {
			const int x0 = fact_x0(8 + l + fact_hoff[i], ox);
			const float w = (4 - fabsf((float)x0 + 0.5f - (float)(8 + l))) / 4;
			const int gr = fact_col(m, x0, y) == 1;
			wt[0][i][l] = gr ? 0 : w;
			wt[1][i][l] = gr ? w : 0;
		}
}

/* the top row of the first of the four block rows within ±3.5 of row r */
static int fact_vy0(int r, unsigned oy)
{
	const int y = r - 4;
	return y + ((y - (int)oy) & 1);
}

/* fact_chroma_to's weights at row r: the four block rows' vertical interpolations, red-or-blue's
 * and green's */
static void fact_vtaps(const pc_mosaic *m, unsigned ox, unsigned oy, int r, float wt[2][4][16])
{
	const int y = fact_vy0(r, oy);
	for (int i = 0; i < 4; i++) {
		const int yb = y + 2 * i;
		const float w = (4 - fabsf((float)yb + 0.5f - (float)r)) / 4;
		for (int l = 0; l < 16; l++) {
			const int gr = fact_col(m, fact_x0(8 + l, ox), yb) == 1;
			wt[0][i][l] = gr ? 0 : w;
			wt[1][i][l] = gr ? w : 0;
		}
	}
}

static void fact_tables_init(fact_tables *t, const pc_mosaic *m, unsigned ox, unsigned oy)
{
	memset(t, 0, sizeof *t);
	for (int l = 0; l < 16; l++) {
		const int x = 8 + l; /* column phase l mod 4 */
		t->par[l] = (float)((x - (int)ox) & 1);
		for (int s = 0; s < 4; s++) {
			t->gw[s][l] = 2 * fact_gshare((l - s) & 3);
			/* read at x + 3 by the pixel x: its distance (s − x) mod 4 */
			t->ge[s][l] = 2 * fact_gshare((s - (l - 3)) & 3);
		}
		for (int d = 0; d < 2; d++) {
			float wt[3][2];
			for (int f = 0; f < 2; f++) {
				const int x0 = fact_x0(x + (d ? 1 : -1) * (f ? 3 : 1), ox);
				const float dx = (float)x0 + 0.5f - (float)x;
				for (int k = 0; k < 3; k++)
					wt[k][f] = fact_on_col(m, k, x0) ? 4 - fabsf(dx) : 0;
			}
			for (int k = 0; k < 3; k++)
				for (int f = 0; f < 2; f++) {
					float *c = d ? t->ca.ce[k][f] : t->ca.cw[k][f];
					c[l] = wt[k][f] / (wt[k][0] + wt[k][1]);
				}
		}
	}
	/* rows 8 .. 11 stand for every row of their phase: the weights depend on y mod 4 (and
	 * r − y, which r mod 4 and oy fix) */
	for (int p = 0; p < 4; p++) {
		fact_htaps(m, ox, 8 + p, t->bt[p]);
		fact_vtaps(m, ox, oy, 8 + p, t->vt[p]);
	}
}

/* The per-band state of pan-fact's fast path: rows and what they hold. */
typedef struct fact_band_st {
	const fact_job *fj;
	const pan_kern *K;
	const pan_tables *t;
	const pan_dtables *dt;
	const fact_tables *ft;
	pan_rows rc;
	unsigned ox, oy;
	long n, nmain;
	float *vs, *rawp, *src, *rho, *braw[2];
	float *hw[8][4], *li[8][4], *gw[8][2], *ge[8][2], *dummy[8];
	float *bd[8], *hrb[8], *hg[8], *u, *g;
	float *c[2][4][2], *dh, *dv, *bh[4][4], *be[4][4], *gam[5], *rq[4][12];
	float *mr[8], *r2[8], *pd[8], *o[12];
	int src_next, blk_next, c_next, c_first, hue_next, r2_next, g_y0;
} fact_band_st;

/* the raw row y (mirror4) minus black, padded by the sub-image mirror, into d */
static void fact_raw_row(fact_band_st *b, int y, float *d)
{
	const int iw = (int)b->fj->j.w;
	memcpy(d, pan_row(&b->rc, b->fj->j.in, pc_mirror4(y, (int)b->fj->j.h)),
	       (size_t)iw * sizeof *d);
	pan_pad_row(d, iw, b->n, PAN_PAD_SUB);
}

/* source rows up to yy: ρ, hold rows, interpolations, green's weighed holds */
static void fact_src_to(fact_band_st *b, int ymax)
{
	const pan_job *j = &b->fj->j;
	for (; b->src_next <= ymax; b->src_next++) {
		const int yy = b->src_next, k = yy & 7;
		pan_src_sums(j, b->K, b->t, &b->rc, yy, b->src, b->vs, NULL, b->rawp, b->n,
		             b->nmain);
		b->K->ratio(b->vs, b->rawp, -16, b->n + 32, 0, b->fj->dh, 0, b->rho, NULL);
		b->K->dwrows(b->rho, 0, b->n + 16, b->dt->tw, b->hw[k]);
		b->K->dprows(b->hw[k], b->n, b->dt->fa, b->ox, b->li[k], NULL, NULL);
		const float *h2[2], *ww[2], *we[2];
		int p = 0;
		for (int s = 0; s < 4; s++)
			if (fact_col(j->m, s, yy) == 1) {
				h2[p] = b->hw[k][s];
				ww[p] = b->ft->gw[s];
				we[p++] = b->ft->ge[s];
			}
		b->K->gwrows(h2, ww, we, b->n + 16, b->gw[k], b->ge[k]);
	}
}

static int fact_bslot(const fact_band_st *b, int y)
{
	return ((y - (int)b->oy) >> 1) & 7;
}

/* block rows (top rows) up to ymax: sums and horizontal interpolations */
static void fact_blocks_to(fact_band_st *b, int ymax)
{
	for (; b->blk_next <= ymax; b->blk_next += 2) {
		const int y = b->blk_next, k = fact_bslot(b, y);
		fact_raw_row(b, y, b->braw[0]);
		fact_raw_row(b, y + 1, b->braw[1]);
		b->K->bsum(b->braw[0], b->braw[1], b->ft->par, -24, b->n + 48, b->bd[k]);
		const float *in[4] = {b->bd[k], b->bd[k], b->bd[k], b->bd[k]};
		float *out[2] = {b->hrb[k], b->hg[k]};
		b->K->taps(in, fact_hoff, b->ft->bt[(unsigned)y & 3], 0, b->n, out);
	}
}

/* the two block rows on one side of row r (north: centres above r, else below): red's, blue's,
 * green's rows and green's weights */
static void fact_ns_rows(const fact_band_st *b, int r, int south, const float **pr,
                         const float **pb, const float *pg[2], float gw[2])
{
	const pc_mosaic *m = b->fj->j.m;
	int y = fact_vy0(south ? r + 4 : r, b->oy);
	float ws = 0;
	for (int i = 0; i < 2; i++, y += 2) {
		const int k = fact_bslot(b, y);
		if (fact_on_row(m, 0, y))
			*pr = b->hrb[k];
		else
			*pb = b->hrb[k];
		pg[i] = b->hg[k];
		gw[i] = 4 - fabsf((float)y + 0.5f - (float)r);
		ws += gw[i];
	}
	gw[0] /= ws;
	gw[1] /= ws;
}

/* chromaticity rows up to r: candidates, clamped columns, variation boxes */
static void fact_chroma_to(fact_band_st *b, int ymax)
{
	const int iw = (int)b->fj->j.w;
	for (; b->c_next <= ymax; b->c_next++) {
		const int r = b->c_next, y = fact_vy0(r, b->oy);
		fact_blocks_to(b, y + 6);
		/* the block columns' vertical interpolations at row r */
		const float *in[4];
		for (int i = 0; i < 4; i++)
			in[i] = b->bd[fact_bslot(b, y + 2 * i)];
		static const int off0[4] = {0, 0, 0, 0};
		float *ug[2] = {b->u, b->g};
		b->K->taps(in, off0, b->ft->vt[(unsigned)r & 3], -16, b->n + 32, ug);
		fact_cargs a = b->ft->ca;
		a.u = b->u;
		a.g = b->g;
		fact_ns_rows(b, r, 0, &a.nr, &a.nb, a.ng, a.ngw);
		fact_ns_rows(b, r, 1, &a.sr, &a.sb, a.sg, a.sgw);
		float *const(*c)[2] = b->c[r & 1];
		b->K->chroma(&a, b->n, b->fj->eps, c);
		for (int d = 0; d < 4; d++) {
			for (int k = 0; k < 2; k++)
				pan_pad_row(c[d][k], iw, b->n, PAN_PAD_CLAMP);
			/* the row above (itself on the first row: no vertical differences there,
			 * and on a band's first row only its horizontal box is read) */
			float *const *pp = r == b->c_first ? c[d] : b->c[(r - 1) & 1][d];
			const float *cc[2] = {c[d][0], c[d][1]}, *pc[2] = {pp[0], pp[1]};
			b->K->dvar(cc, pc, -16, b->n + 32, b->dh, b->dv);
			b->K->box(b->dh, b->dv, -16, b->n + 16, b->bh[r & 3][d], b->be[r & 3][d]);
		}
	}
}

/* the blend weights of the block row with top row y0 */
static void fact_gamma(fact_band_st *b, int y0)
{
	if (b->g_y0 == y0)
		return;
	const int ih = (int)b->fj->j.h;
	fact_chroma_to(b, y0 + 2 < ih ? y0 + 2 : ih - 1);
	const float *hb[4][4];
	for (int d = 0; d < 4; d++) {
		const int ya = y0 > 0 ? y0 - 1 : 0;
		hb[d][0] = b->bh[ya & 3][d];
		for (int i = 0; i < 3; i++) {
			const int r = y0 + i;
			hb[d][i + 1] = r < 0     ? b->bh[0][d]
			               : r >= ih ? b->bh[(ih - 1) & 3][d]
			                         : b->be[r & 3][d];
		}
	}
	b->K->gam(hb, b->ft->par, b->n, b->gam);
	b->g_y0 = y0;
}

/* hue rows up to ymax: step 4 (blend, hue) and step 5 (m) */
static void fact_hue_to(fact_band_st *b, int ymax)
{
	const pan_job *j = &b->fj->j;
	const int iw = (int)j->w;
	for (; b->hue_next <= ymax; b->hue_next++) {
		const int yc = b->hue_next;
		fact_src_to(b, yc + 3);
		fact_gamma(b, yc - ((yc - (int)b->oy) & 1));
		pan_dlat_args a;
		pan_dout_args(j, b->t, b->dt, b->hw, b->li, b->dummy, yc, &a);
		for (int q = 0; q < 12; q++)
			a.osel[q] = b->dt->zero;
		for (unsigned t = 0; t < 4; t++) {
			int e, yn, ys, p = 0;
			lattice_rows(yc, t, &e, &yn, &ys);
			for (unsigned s = 0; s < 4; s++) {
				if (fact_col(j->m, (int)s, (int)t) != 1)
					continue;
				const int L = 4 * (int)t + (int)s;
				a.nrow[L] = b->gw[yn & 7][p];
				a.srow[L] = b->gw[ys & 7][p];
				a.nrowe[L] = b->ge[yn & 7][p];
				a.srowe[L] = b->ge[ys & 7][p++];
			}
		}
		const float *gc[5] = {b->gam[0], b->gam[1], b->gam[2], b->gam[3], b->gam[4]};
		/* the raw row, read in the cache's slot (no other row fetched before its last use;
		 * the lanes past w unused) */
		const float *raw = pan_row(&b->rc, j->in, yc);
		float *const *rqo = b->rq[yc & 3];
		b->K->dorow(&a, gc, raw, 0, b->n, rqo, 0, 0);
		const float *sel[4], *rq[12];
		unsigned own[4];
		for (unsigned u = 0; u < 4; u++) {
			sel[u] = b->t->sel[u];
			own[u] = pan_q(j->m, u, (unsigned)yc & 3);
		}
		for (int q = 0; q < 12; q++)
			rq[q] = rqo[q];
		b->K->fm(rq, raw, sel, own, b->n, b->mr[yc & 7]);
		pan_pad_row(b->mr[yc & 7], iw, b->n, PAN_PAD_MIRROR);
	}
}

/* step 6's ratio rows up to ymax */
static void fact_r2_to(fact_band_st *b, int ymax)
{
	const int iw = (int)b->fj->j.w, ih = (int)b->fj->j.h;
	for (; b->r2_next <= ymax; b->r2_next++) {
		const int r = b->r2_next;
		fact_hue_to(b, r + 1 < ih ? r + 1 : ih - 1);
		b->K->ppi2(b->mr[pc_mirror(r - 1, ih) & 7], b->mr[r & 7],
		           b->mr[pc_mirror(r + 1, ih) & 7], b->fj->j.delta, b->n, b->r2[r & 7],
		           b->pd[r & 7]);
		pan_pad_row(b->r2[r & 7], iw, b->n, PAN_PAD_MIRROR);
	}
}

static void pan_fact_band(void *ctx, uint32_t y0, uint32_t y1)
{
	fact_job *fj = ctx;
	pan_job *j = &fj->j;
	const uint32_t w = j->w, h = j->h;
	const int ih = (int)h;
	const long n = ((long)w + 15) / 16 * 16, nmain = (long)w / 16 * 16;
	const size_t pitch = (size_t)n + 2 * PAN_PADR;
	pan_tables *t;
	pan_dtables *dt;
	fact_tables ft;
	/* rows: 6 of scratch (source sums, raw rows), 16 cached raw rows; 8 × (4 hold rows, 4
	 * interpolations, 2 + 2 green weighed holds); 8 × (block sums, two interpolations), u, g;
	 * 2 × 4 × 2 chromaticities, dh, dv, 4 × 4 × 2 boxes; 5 weights, 4 × 12 blended ratios;
	 * 8 × (m, r2, pd); 12 output rows; 1 unused */
	const size_t nrows = 6 + 16 + 96 + 24 + 2 + 16 + 2 + 32 + 5 + 48 + 24 + 12 + 1;
	float *buf = pan_dband_scratch(j, nrows, pitch, &t, &dt);
	if (!buf)
		return;
	const pan_kern K = pan_kernels(j->level);
	fact_band_st b;
	memset(&b, 0, sizeof b);
	b.fj = fj;
	b.K = &K;
	b.t = t;
	b.dt = dt;
	b.ft = &ft;
	b.n = n;
	b.nmain = nmain;
	(void)pc_mosaic_color_origin(j->m, &b.ox, &b.oy);
	fact_tables_init(&ft, j->m, b.ox, b.oy);
	float *row = buf + PAN_PADR;
	size_t next = 0;
#define FACT_ROW() (row + pitch * next++)
	b.vs = FACT_ROW();
	b.rawp = FACT_ROW();
	b.src = FACT_ROW();
	b.rho = FACT_ROW();
	b.braw[0] = FACT_ROW();
	b.braw[1] = FACT_ROW();
	for (int k = 0; k < 16; k++) {
		b.rc.slot[k] = FACT_ROW();
		b.rc.tag[k] = -1;
	}
	for (int k = 0; k < 8; k++) {
		for (int s = 0; s < 4; s++) {
			b.hw[k][s] = FACT_ROW();
			b.li[k][s] = FACT_ROW();
		}
		for (int p = 0; p < 2; p++) {
			b.gw[k][p] = FACT_ROW();
			b.ge[k][p] = FACT_ROW();
		}
	}
	for (int k = 0; k < 8; k++) {
		b.bd[k] = FACT_ROW();
		b.hrb[k] = FACT_ROW();
		b.hg[k] = FACT_ROW();
	}
	b.u = FACT_ROW();
	b.g = FACT_ROW();
	for (int k = 0; k < 2; k++)
		for (int d = 0; d < 4; d++)
			for (int c = 0; c < 2; c++)
				b.c[k][d][c] = FACT_ROW();
	b.dh = FACT_ROW();
	b.dv = FACT_ROW();
	for (int k = 0; k < 4; k++)
		for (int d = 0; d < 4; d++) {
			b.bh[k][d] = FACT_ROW();
			b.be[k][d] = FACT_ROW();
		}
	for (int d = 0; d < 5; d++)
		b.gam[d] = FACT_ROW();
	for (int k = 0; k < 4; k++)
		for (int q = 0; q < 12; q++)
			b.rq[k][q] = FACT_ROW();
	for (int k = 0; k < 8; k++) {
		b.mr[k] = FACT_ROW();
		b.r2[k] = FACT_ROW();
		b.pd[k] = FACT_ROW();
	}
	for (int q = 0; q < 12; q++)
		b.o[q] = FACT_ROW();
	float *unused = FACT_ROW();
	for (int k = 0; k < 8; k++)
		b.dummy[k] = unused;
#undef FACT_ROW
	/* the first rows each stage computes: the hue from two rows above the band (m's), the
	 * chromaticities from the window of its block row, the block rows and source rows those
	 * read */
	b.hue_next = y0 >= 2 ? (int)y0 - 2 : 0;
	b.r2_next = y0 >= 1 ? (int)y0 - 1 : 0;
	const int yb = b.hue_next - ((b.hue_next - (int)b.oy) & 1);
	b.c_first = b.c_next = yb > 0 ? yb - 1 : 0;
	b.blk_next = b.c_first - 4 + ((b.c_first - 4 - (int)b.oy) & 1);
	b.src_next = b.hue_next - 3;
	b.g_y0 = INT_MIN;
	int planar = 1;
	for (int q = 0; q < 12; q++)
		planar &= j->out[q].pixel_stride == 1;
	for (uint32_t y = y0; y < y1; y++) {
		const int yi = (int)y;
		fact_hue_to(&b, yi + 2 < ih ? yi + 2 : ih - 1);
		fact_r2_to(&b, yi + 1 < ih ? yi + 1 : ih - 1);
		fact_oargs a;
		a.ru = b.r2[pc_mirror(yi - 1, ih) & 7];
		a.r0 = b.r2[yi & 7];
		a.rd = b.r2[pc_mirror(yi + 1, ih) & 7];
		a.pd = b.pd[yi & 7];
		a.m = b.mr[yi & 7];
		for (int q = 0; q < 12; q++)
			a.rq[q] = b.rq[yi & 3][q];
		for (unsigned u = 0; u < 4; u++) {
			a.sel[u] = t->sel[u];
			a.own[u] = pan_q(j->m, u, y & 3);
		}
		const unsigned py = y & 1;
		for (unsigned c = 0; c < 4; c++)
			for (unsigned px = 0; px < 2; px++) {
				/* analyser c at (px ^ i, py ^ jj): own, horizontal, vertical,
				 * diagonal */
				for (int k = 0; k < 4; k++)
					if (pc_mosaic_channel(j->m, px ^ (unsigned)(k & 1),
					                      py ^ (unsigned)(k >> 1)) == c)
						a.mx[c][px] = k;
			}
		const float *raw = pan_row(&b.rc, j->in, yi); /* as in fact_hue_to */
		if (planar) {
			float *dq[12];
			for (int q = 0; q < 12; q++)
				dq[q] = j->out[q].data + (size_t)y * j->out[q].row_stride;
			K.forow(&a, raw, 0, nmain, j->delta, dq, 0, j->nt);
			if (nmain < n) {
				K.forow(&a, raw, nmain, n, j->delta, b.o, nmain, 0);
				pan_put_row(j, y, b.o, (uint32_t)nmain, w);
			}
			continue;
		}
		K.forow(&a, raw, 0, n, j->delta, b.o, 0, 0);
		pan_put_row(j, y, b.o, 0, w);
	}
	pan_dband_end(j, t, dt, buf);
}

int pc_dm_pan_fact_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out)
{
	const uint32_t w = in->width, h = in->height;
	fact_job fj = {{in, w, h, m, (float)(FACT_DELTA * 3 * fs), level, out, 0, 0, 0,
	                pc_dm_stream_wanted(out, 12, w, h, level), 0, 0, 0, 0,
	                pc_dm_stream_wanted_il(out, 12, w, h, level)},
	               (float)(FACT_EPS * 4 * fs),
	               (float)(FACT_DH * fs)};
	pc_parallel_rows(h, 0, threads, pan_fact_band, &fj);
	if (fj.j.err)
		return pc_error(PC_ENOMEM, "pan-fact: row buffers for width %u", w);
	return 0;
}
