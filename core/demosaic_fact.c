/* Colour-polarization demosaicking with colour and polarization factorised ("pan-fact").
 *
 * On the IMX250MYR (polarcam/mosaic.h) every 2×2 colour block holds the four analysers, and
 * each (colour k, analyser a) channel is sampled once per 4×4 period (green twice). Where colour
 * and polarization are separable, channel (k, a) is I_{k,a} = M_a · h_{a,k}, M_a the radiance
 * seen through analyser a summed over the colours and h_{a,k} = I_{k,a} / Σ_k' I_{k',a} the
 * chromaticity seen through analyser a (Σ_k h_{a,k} = 1). h carries the hue, and with it the
 * colour-dependent part of the polarization (a glossy coloured surface: its white specular
 * reflection polarized, its coloured diffuse one not); M the luminance texture and the common
 * polarization, on a monochrome 2×2 analyser mosaic (spacing 2 per analyser, denser than the
 * colour channels' 4). pan-fact estimates h with a direction-aware step and M with a one-pass
 * ratio step:
 *
 *  1. Block sums b = the sum of each 2×2 colour block's four samples: a half-resolution Bayer
 *     mosaic of (about) 2·S0 per colour, the polarization cancelled where it is smooth over the
 *     block.
 *  2. Four one-sided chromaticity candidates at every pixel p from b on the lattices of the block
 *     centres (spacing 4 per colour, half-integer positions): for d = W, E, N, S the normalised
 *     tent T(dx)·T(dy), T(t) = 4 − |t|, over colour k's centres within |dx|, |dy| < 4 on d's side
 *     of p (W: dx < 0, E: dx > 0, N: dy < 0, S: dy > 0), B^d_k; c^d_k = B^d_k / Σ_k' B^d_k'.
 *  3. Their homogeneity per 2×2 colour block, as Hirakawa & Parks judge directional
 *     interpolations by the colour variation of their results ("Adaptive homogeneity-directed
 *     demosaicing algorithm", IEEE TIP 14(3) 2005, Sec. III): H_d = Σ_k the total variation of
 *     c^d_k over the 4×4 pixels around the block (its 2×2 and one pixel on each side; horizontal
 *     and vertical differences inside the window, c clamped at the image's borders); for the
 *     centred candidate C, H_C = the mean of the four (Round 10b's (3c): C's own chromaticity
 *     is not needed). Weights w_d = 1/(H_d + 10⁻⁹)², as the gradient-based threshold-free
 *     method blends its directional estimates (Pekkucuksen & Altunbasak, ICIP 2010, Sec. 2).
 *  4. Per channel (k, a) the five tents, T = (4 − |dx|)(4 − |dy|) over its samples within ±3
 *     pixels (C all, W dx ≤ 0, E dx ≥ 0, N dy ≤ 0, S dy ≥ 0, each normalised over its taps), of
 *     ratios to pan-ratio's pseudo-panchromatic image, ρ = max(v, 0) / max(P0, δ_h),
 *     P0 = raw ∗ (f5 ⊗ f5), f5 = [1 2 2 2 1]/8 (Mihoubi et al., IEEE TCI 3(4) 2017; the
 *     luminance gradient removed before interpolating, as Cok's smooth-hue transition does),
 *     blended with the block's w_d: R_{k,a} = Σ_d w_d R^d_{k,a} / Σ_d w_d; then
 *     h_{a,k} = R_{k,a} / Σ_k' R_{k',a} (each R floored at 10⁻⁴). δ_h = 10⁻⁴ of full scale
 *     only guards a zero PPI: an offset added to both sides, as pan-ratio's δ, pulls dark hues
 *     towards grey, and m = v/h does not undo that (δ_h = 1 % lost 2.7-4.5 dB S0 on the smooth
 *     colours, 10⁻⁴ broke the exactness on uniform colours by up to 16 DN; Round 11b).
 *  5. The hue-normalised mosaic m(p) = v(p) / h_{a(p),k(p)}(p): M's samples.
 *  6. The polarization step on m, pan-ratio's ratio step at spacing 2: the guide
 *     P = m ∗ (f ⊗ f), f = [1 2 1]/4 (each analyser 1/4 wherever it is centred, as the
 *     pseudo-panchromatic image of Mihoubi et al., IEEE TCI 3(4) 2017), ρ = (m + δ)/(P + δ),
 *     R_a = the tent (2 − |dx|)(2 − |dy|) of analyser a's ρ over the 3×3 window, and
 *     M_a = (m + δ)·R_a/R_own − δ, the own analyser m itself (smooth-hue transition, Cok, US
 *     patent 4,642,678, 1987); δ = 1 % of M's full scale 3·fs.
 *  7. O_{k,a}(p) = M_a(p)·h_{a,k}(p); the pixel's own channel keeps its sample (M_own·h_own = v).
 *
 * A uniform colour and polarization is reproduced exactly (every tent of a constant is the
 * constant), so is a grey linear ramp under a uniform polarization as δ → 0 (the
 * ratios to P0 are constant, h = 1/3 everywhere, m = 3v, and the ratio step's guide weighs the
 * analysers at ±1 alike). The alternatives measured (the hue from
 * the block sums alone, bilinear and Hamilton-Adams Bayer steps at half resolution, ratios to a
 * luminance, smoothed corrections, per-pixel homogeneity, the monochrome ratio methods for step
 * 6) are in docs/demosaicking.md, Round 11b.
 *
 * Borders: the raw is extended by mirroring inside each analyser's half-resolution sub-image
 * (x → (x mod 2) + 2·mirror(x div 2)), which keeps every pixel's 4×4 phase; m by the
 * whole-sample mirror (keeps the analyser).
 *
 * Support: a candidate reads block sums whose pixels lie within ±4, the block's window adds ±2,
 * the tents of step 4 read ratios within ±3, each P0's ±2: h at q reads the raw within ±6; the
 * ratio step reads m within ±2: ±8 (7 reached on random data, tests/test_front_door.c), ±10
 * through the sub-image mirror. This double reference defines the method; the float fast path
 * (pc_dm_pan_fact_fast, demosaic_pan.c) computes the same in another order (tolerance in
 * tests/test_demosaic.c; docs/demosaicking.md, Round 12). */
#include "demosaic_fact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_color.h"
#include "polarcam/error.h"

#define FACT_PAD 16 /* the block grid's extension of the raw: a multiple of 4 */
#define FACT_ND  5  /* candidates C, W, E, N, S */

static int clampi(int i, int n)
{
	return i < 0 ? 0 : i >= n ? n - 1 : i;
}

typedef struct fact_ref {
	const double *img;
	int w, h;
	const pc_mosaic *m;
	double eps, dh;     /* the block sums' floor; δ_h */
	double *b;          /* block sums, nbx × nby */
	unsigned char *col; /* their colour 0 (R), 1 (G), 2 (B) */
	int nbx, nby;
	int x0, y0; /* block (0, 0)'s top-left pixel in the extended raw (x + FACT_PAD) */
} fact_ref;

static double raw_at(const fact_ref *r, int x, int y)
{
	return r->img[(size_t)pc_mirror4(y, r->h) * (size_t)r->w + (size_t)pc_mirror4(x, r->w)];
}

static double ppi0(const fact_ref *r, int x, int y)
{
	static const double f[5] = {1, 2, 2, 2, 1};
	double s = 0;
	for (int j = -2; j <= 2; j++)
		for (int i = -2; i <= 2; i++)
			s += f[i + 2] * f[j + 2] * raw_at(r, x + i, y + j);
	return s / 64;
}

/* Step 2 at pixel (x, y): c[d − 1][k] for d = W, E, N, S. */
static void block_chroma(const fact_ref *r, int x, int y, double c[4][3])
{
	double num[4][3] = {{0}}, den[4][3] = {{0}};
	const int X = x + FACT_PAD, Y = y + FACT_PAD;
	const int ib = (X - r->x0) >> 1, jb = (Y - r->y0) >> 1;
	for (int j = jb - 2; j <= jb + 2; j++)
		for (int i = ib - 2; i <= ib + 2; i++) {
			double dx = r->x0 + 2 * i + 0.5 - X, dy = r->y0 + 2 * j + 0.5 - Y;
			if (fabs(dx) > 4 || fabs(dy) > 4)
				continue;
			size_t o = (size_t)pc_mirror(j, r->nby) * (size_t)r->nbx +
			           (size_t)pc_mirror(i, r->nbx);
			double t = (4 - fabs(dx)) * (4 - fabs(dy));
			int k = r->col[o];
			const int in[4] = {dx<0, dx> 0, dy<0, dy> 0};
			for (int d = 0; d < 4; d++)
				if (in[d]) {
					num[d][k] += t * r->b[o];
					den[d][k] += t;
				}
		}
	for (int d = 0; d < 4; d++) {
		double s = 0, v[3];
		for (int k = 0; k < 3; k++)
			s += v[k] = fmax(num[d][k] / den[d][k], r->eps);
		for (int k = 0; k < 3; k++)
			c[d][k] = v[k] / s;
	}
}

/* Step 4 at pixel (x, y) with the weights wd: ha[a][k]. */
static void analyser_chroma(const fact_ref *r, int x, int y, const double wd[FACT_ND],
                            double ha[4][3])
{
	double num[FACT_ND][12] = {{0}}, den[FACT_ND][12] = {{0}};
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			uint32_t xm = (uint32_t)pc_mirror4(x + dx, r->w),
			         ym = (uint32_t)pc_mirror4(y + dy, r->h);
			unsigned q = 4 * (pc_mosaic_color(r->m, xm, ym) - PC_CFA_R) +
			             pc_mosaic_channel(r->m, xm, ym);
			double t = (4 - abs(dx)) * (4 - abs(dy)),
			       v = r->img[(size_t)ym * r->w + xm];
			v = fmax(v, 0) / fmax(ppi0(r, x + dx, y + dy), r->dh);
			const int in[FACT_ND] = {1, dx <= 0, dx >= 0, dy <= 0, dy >= 0};
			for (int d = 0; d < FACT_ND; d++)
				if (in[d]) {
					num[d][q] += t * v;
					den[d][q] += t;
				}
		}
	double rb[12] = {0}, ws = 0;
	for (int d = 0; d < FACT_ND; d++) {
		ws += wd[d];
		for (int q = 0; q < 12; q++)
			rb[q] += wd[d] * num[d][q] / den[d][q];
	}
	for (int a = 0; a < 4; a++) {
		double s = 0, v[3];
		for (int k = 0; k < 3; k++)
			s += v[k] = fmax(rb[4 * k + a] / ws, FACT_EPS);
		for (int k = 0; k < 3; k++)
			ha[a][k] = v[k] / s;
	}
}

/* Step 6 on m (w × h, the monochrome mosaic mono); mk the four planes M_a. */
static int ratio_step(const double *v, int w, int h, const pc_mosaic *mono, double delta,
                      double *mk)
{
	const size_t n = (size_t)w * h;
	double *rho = malloc(sizeof *rho * n);
	if (!rho)
		return pc_error(PC_ENOMEM, "pan-fact reference: %dx%d ratios", w, h);
	pc_dimg vi = {(double *)v, w, h};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double p = 0;
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++)
					p += (2 - abs(i)) * (2 - abs(j)) *
					     pc_dimg_at(&vi, x + i, y + j);
			rho[(size_t)y * w + x] =
			    (fmax(v[(size_t)y * w + x], 0) + delta) / (fmax(p / 16, 0) + delta);
		}
	pc_dimg ri = {rho, w, h};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double num[4] = {0}, den[4] = {0};
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++) {
					double t = (2 - abs(i)) * (2 - abs(j));
					unsigned a =
					    pc_dm_ch(mono, (unsigned)(x + i), (unsigned)(y + j));
					num[a] += t * pc_dimg_at(&ri, x + i, y + j);
					den[a] += t;
				}
			size_t o = (size_t)y * w + x;
			unsigned own = pc_dm_ch(mono, (unsigned)x, (unsigned)y);
			double sc = (fmax(v[o], 0) + delta) * den[own] / num[own];
			for (unsigned a = 0; a < 4; a++)
				mk[(size_t)a * n + o] =
				    a == own ? v[o] : sc * num[a] / den[a] - delta;
		}
	free(rho);
	return 0;
}

int pc_dm_pan_fact_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out)
{
	unsigned ox, oy;
	if (pc_mosaic_color_origin(m, &ox, &oy))
		return pc_error(PC_EINVAL,
		                "pan-fact: the colour filter must cover whole 2x2 blocks");
	const int W = (int)w + 2 * FACT_PAD, H = (int)h + 2 * FACT_PAD;
	fact_ref r = {img,
	              (int)w,
	              (int)h,
	              m,
	              FACT_EPS * 4 * fs,
	              FACT_DH * fs,
	              NULL,
	              NULL,
	              (W - (int)ox) / 2,
	              (H - (int)oy) / 2,
	              (int)ox,
	              (int)oy};
	const size_t nb = (size_t)r.nbx * r.nby, n = (size_t)w * h;
	r.b = malloc(sizeof *r.b * nb);
	r.col = malloc(nb);
	double *cs = malloc(sizeof *cs * n * 12); /* c^d_k per pixel */
	double *hp = malloc(sizeof *hp * n * 12); /* h_{a,k}: plane 3a + k */
	double *mm = malloc(sizeof *mm * n), *mk = malloc(sizeof *mk * 4 * n);
	int rc = 0;
	if (!r.b || !r.col || !cs || !hp || !mm || !mk) {
		rc = pc_error(PC_ENOMEM, "pan-fact reference: planes of %ux%u", w, h);
		goto done;
	}
	/* step 1 */
	for (int j = 0; j < r.nby; j++)
		for (int i = 0; i < r.nbx; i++) {
			int x = r.x0 + 2 * i - FACT_PAD, y = r.y0 + 2 * j - FACT_PAD;
			size_t o = (size_t)j * r.nbx + i;
			r.b[o] = raw_at(&r, x, y) + raw_at(&r, x + 1, y) + raw_at(&r, x, y + 1) +
			         raw_at(&r, x + 1, y + 1);
			r.col[o] = (unsigned char)(pc_mosaic_color(m, (uint32_t)(r.x0 + 2 * i),
			                                           (uint32_t)(r.y0 + 2 * j)) -
			                           PC_CFA_R);
		}
		/* step 2 */
#define CS(x, y) ((double(*)[3])(cs + ((size_t)(y) * (size_t)w + (size_t)(x)) * 12))
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++)
			block_chroma(&r, x, y, CS(x, y));
	/* steps 3 to 5 */
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			const int xa = x - ((x + FACT_PAD - r.x0) & 1) - 1,
			          ya = y - ((y + FACT_PAD - r.y0) & 1) - 1;
			double hv[FACT_ND] = {0}, wd[FACT_ND], ha[4][3];
			for (int yy = ya; yy <= ya + 3; yy++)
				for (int xx = xa; xx <= xa + 3; xx++) {
					int xq = clampi(xx, (int)w), yq = clampi(yy, (int)h);
					double(*p)[3] = CS(xq, yq);
					double(*pl)[3] = CS(clampi(xx - 1, (int)w), yq);
					double(*pu)[3] = CS(xq, clampi(yy - 1, (int)h));
					for (int d = 0; d < 4; d++)
						for (int k = 0; k < 3; k++) {
							hv[d + 1] +=
							    xx > xa ? fabs(p[d][k] - pl[d][k]) : 0;
							hv[d + 1] +=
							    yy > ya ? fabs(p[d][k] - pu[d][k]) : 0;
						}
				}
			hv[0] = (hv[1] + hv[2] + hv[3] + hv[4]) / 4;
			for (int d = 0; d < FACT_ND; d++)
				wd[d] = 1 / ((hv[d] + 1e-9) * (hv[d] + 1e-9));
			analyser_chroma(&r, x, y, wd, ha);
			size_t o = (size_t)y * w + x;
			for (int a = 0; a < 4; a++)
				for (int k = 0; k < 3; k++)
					hp[(size_t)(3 * a + k) * n + o] = ha[a][k];
			int a = (int)pc_mosaic_channel(m, (uint32_t)x, (uint32_t)y),
			    k = pc_mosaic_color(m, (uint32_t)x, (uint32_t)y) - PC_CFA_R;
			mm[o] = img[o] / ha[a][k];
		}
#undef CS
	/* step 6 */
	const pc_mosaic mono = pc_dm_color_mono(m);
	rc = ratio_step(mm, (int)w, (int)h, &mono, FACT_DELTA * 3 * fs, mk);
	if (rc)
		goto done;
	/* step 7 */
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			size_t o = (size_t)y * w + x;
			unsigned own =
			    4 * (pc_mosaic_color(m, (uint32_t)x, (uint32_t)y) - PC_CFA_R) +
			    pc_mosaic_channel(m, (uint32_t)x, (uint32_t)y);
			for (unsigned q = 0; q < 12; q++) {
				unsigned k = q / 4, a = q % 4;
				double v = q == own ? img[o]
				                    : mk[(size_t)a * n + o] *
				                          hp[(size_t)(3 * a + k) * n + o];
				out[q].data[(size_t)y * out[q].row_stride +
				            (size_t)x * out[q].pixel_stride] = (float)v;
			}
		}
done:
	free(r.b);
	free(r.col);
	free(cs);
	free(hp);
	free(mm);
	free(mk);
	return rc;
}

const pc_dm_pan_fns *pc_dm_fact_fns_get(pc_demosaic_method m)
{
	static const pc_dm_pan_fns fact = {pc_dm_pan_fact_ref, pc_dm_pan_fact_fast, NULL, NULL};
	return m == PC_DM_PAN_FACT ? &fact : NULL;
}
