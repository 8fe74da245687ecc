/* Colour-polarization demosaicking with colour and polarization factorised ("pan-fact").
 *
 * EXPLORATION DRAFT: variants through environment switches, to be fixed to one definition.
 */
#include "demosaic_fact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_color.h"
#include "demosaic_ref.h"
#include "polarcam/error.h"

#define FACT_PAD 16   /* the extension of the raw, a multiple of 4 (keeps every pixel's phase) */
#define FACT_EPS 1e-4 /* the floor of a colour's block sum, fraction of the block full scale */

static int env_int(const char *name, int dflt)
{
	const char *s = getenv(name);
	return s && *s ? atoi(s) : dflt;
}

/* The sub-image mirror: x of the raw extended beyond [0, n) (n even) keeping x mod 4. */
static inline int mirror4(int x, int n)
{
	int px = x & 1;
	return px + 2 * pc_mirror((x - px) / 2, n / 2);
}

typedef struct fact_blocks {
	double *b;     /* block sums, nbx × nby */
	unsigned char *col; /* their colour 0 (R), 1 (G), 2 (B) */
	int nbx, nby;
	int x0, y0; /* extended coordinates of block (0, 0)'s top-left pixel */
} fact_blocks;

static double bat(const fact_blocks *B, const double *p, int i, int j)
{
	return p[(size_t)pc_mirror(j, B->nby) * B->nbx + pc_mirror(i, B->nbx)];
}

static int cat(const fact_blocks *B, int i, int j)
{
	return B->col[(size_t)pc_mirror(j, B->nby) * B->nbx + pc_mirror(i, B->nbx)];
}

/* Bilinear Bayer demosaicking of the block sums: at each block the mean of the nearest blocks
 * of each colour, weighed by the tent (2 − |di|)(2 − |dj|) over the 3×3 blocks. */
static void bayer_bilinear(const fact_blocks *B, double *rgb[3])
{
	for (int j = 0; j < B->nby; j++)
		for (int i = 0; i < B->nbx; i++) {
			double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
			for (int dj = -1; dj <= 1; dj++)
				for (int di = -1; di <= 1; di++) {
					double t = (2 - abs(di)) * (2 - abs(dj));
					int c = cat(B, i + di, j + dj);
					num[c] += t * bat(B, B->b, i + di, j + dj);
					den[c] += t;
				}
			for (int c = 0; c < 3; c++)
				rgb[c][(size_t)j * B->nbx + i] = num[c] / den[c];
		}
}

/* Hamilton-Adams: green at red and blue blocks from the direction of the smaller gradient
 * (green difference plus the own colour's second difference), with the own colour's Laplacian
 * correction; then red and blue as colour differences to green interpolated bilinearly (mode 1)
 * or as ratios to green (mode 2). Hamilton & Adams, US patent 5,629,734 (1997). */
static void bayer_ha(const fact_blocks *B, double *rgb[3], int ratio, double eps)
{
	const int nbx = B->nbx, nby = B->nby;
	double *g = rgb[1];
	for (int j = 0; j < nby; j++)
		for (int i = 0; i < nbx; i++) {
			double x = bat(B, B->b, i, j);
			if (cat(B, i, j) == 1) {
				g[(size_t)j * nbx + i] = x;
				continue;
			}
			double gl = bat(B, B->b, i - 1, j), gr = bat(B, B->b, i + 1, j);
			double gu = bat(B, B->b, i, j - 1), gd = bat(B, B->b, i, j + 1);
			double lh = 2 * x - bat(B, B->b, i - 2, j) - bat(B, B->b, i + 2, j);
			double lv = 2 * x - bat(B, B->b, i, j - 2) - bat(B, B->b, i, j + 2);
			double dh = fabs(gl - gr) + fabs(lh), dv = fabs(gu - gd) + fabs(lv);
			double eh = (gl + gr) / 2 + lh / 4, ev = (gu + gd) / 2 + lv / 4;
			g[(size_t)j * nbx + i] = dh < dv ? eh : dv < dh ? ev : (eh + ev) / 2;
		}
	/* the differences (or ratios) to green at the red and blue blocks */
	double *d = malloc(sizeof *d * (size_t)nbx * nby);
	for (int j = 0; j < nby; j++)
		for (int i = 0; i < nbx; i++) {
			size_t o = (size_t)j * nbx + i;
			double x = B->b[o];
			d[o] = ratio ? (fmax(x, 0) + eps) / (fmax(g[o], 0) + eps) : x - g[o];
		}
	for (int c = 0; c < 3; c += 2)
		for (int j = 0; j < nby; j++)
			for (int i = 0; i < nbx; i++) {
				double num = 0, den = 0;
				for (int dj = -1; dj <= 1; dj++)
					for (int di = -1; di <= 1; di++) {
						if (cat(B, i + di, j + dj) != c)
							continue;
						double t = (2 - abs(di)) * (2 - abs(dj));
						num += t * bat(B, d, i + di, j + dj);
						den += t;
					}
				size_t o = (size_t)j * nbx + i;
				double r = num / den;
				rgb[c][o] = ratio ? r * (fmax(g[o], 0) + eps) - eps : r + g[o];
			}
	free(d);
}

/* One-sided chromaticity candidates at every pixel from the block sums on the lattices of the
 * block centres (spacing 4 per colour, half-integer offsets): d = 0 C (all the colour's centres
 * within ±4), 1 W (centres left of x), 2 E (right), 3 N (above), 4 S (below), each the
 * normalised tent T(dx)·T(dy), T(d) = 4 − |d|; then h^d_k = C^d_k / Σ C^d. X, Y extended. */
#define FACT_ND 5
static void cand_at(const fact_blocks *B, int X, int Y, double eps, double hc[FACT_ND][3])
{
	double num[FACT_ND][3] = {{0}}, den[FACT_ND][3] = {{0}};
	int ib = (X - B->x0) >> 1, jb = (Y - B->y0) >> 1;
	for (int j = jb - 2; j <= jb + 2; j++)
		for (int i = ib - 2; i <= ib + 2; i++) {
			double dx = B->x0 + 2 * i + 0.5 - X, dy = B->y0 + 2 * j + 0.5 - Y;
			if (fabs(dx) > 4 || fabs(dy) > 4)
				continue;
			double t = (4 - fabs(dx)) * (4 - fabs(dy)), v = bat(B, B->b, i, j);
			int c = cat(B, i, j);
			int in[FACT_ND] = {1, dx < 0, dx > 0, dy < 0, dy > 0};
			for (int d = 0; d < FACT_ND; d++)
				if (in[d]) {
					num[d][c] += t * v;
					den[d][c] += t;
				}
		}
	for (int d = 0; d < FACT_ND; d++) {
		double s = 0, cc[3];
		for (int c = 0; c < 3; c++)
			s += cc[c] = fmax(num[d][c] / den[d][c], eps);
		for (int c = 0; c < 3; c++)
			hc[d][c] = cc[c] / s;
	}
}

static int clampi(int i, int n)
{
	return i < 0 ? 0 : i >= n ? n - 1 : i;
}

/* The candidates blended by the homogeneity of their chromaticity (pan-dir's H_d: the total
 * variation inside the 3×3 window, weights 1/(H_d + 10⁻⁹)²). hp: three planes w × h. */
typedef struct fact_raw {
	const double *img;
	int w, h;
	const pc_mosaic *m;
	int rho;
	double delta;
} fact_raw;

/* pan-ratio's pseudo-panchromatic image (demosaic_pan.c): raw ∗ (m ⊗ m), m = [1 2 2 2 1]/8 */
static double ppi0(const fact_raw *r, int x, int y)
{
	static const double f[5] = {1, 2, 2, 2, 1};
	double s = 0;
	for (int j = -2; j <= 2; j++)
		for (int i = -2; i <= 2; i++)
			s += f[i + 2] * f[j + 2] *
			     r->img[(size_t)mirror4(y + j, r->h) * r->w + mirror4(x + i, r->w)];
	return s / 64;
}

/* Per analyser a, colour k: the one-sided tents over channel (k, a)'s raw samples within ±3
 * (T = (4 − |dx|)(4 − |dy|), W dx ≤ 0, E dx ≥ 0, N dy ≤ 0, S dy ≥ 0), their chromaticity per
 * analyser, blended with the weights wd. x, y unextended. ha[a][k]. */
static void analyser_chroma(const fact_raw *r, int x, int y, const double wd[FACT_ND], double eps,
                            double ha[4][3])
{
	double num[FACT_ND][12] = {{0}}, den[FACT_ND][12] = {{0}};
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			int xm = mirror4(x + dx, r->w), ym = mirror4(y + dy, r->h);
			unsigned q = 4 * (pc_mosaic_color(r->m, (uint32_t)xm, (uint32_t)ym) - PC_CFA_R) +
			             pc_mosaic_channel(r->m, (uint32_t)xm, (uint32_t)ym);
			double t = (4 - abs(dx)) * (4 - abs(dy)), v = r->img[(size_t)ym * r->w + xm];
			if (r->rho)
				v = (fmax(v, 0) + r->delta) / (fmax(ppi0(r, x + dx, y + dy), 0) + r->delta);
			int in[FACT_ND] = {1, dx <= 0, dx >= 0, dy <= 0, dy >= 0};
			for (int d = 0; d < FACT_ND; d++)
				if (in[d]) {
					num[d][q] += t * v;
					den[d][q] += t;
				}
		}
	double ws = 0;
	memset(ha, 0, sizeof(double) * 12);
	if (env_int("FACT_BLENDC", 0)) {
		double cb[12] = {0};
		for (int d = 0; d < FACT_ND; d++) {
			ws += wd[d];
			for (int q = 0; q < 12; q++)
				cb[q] += wd[d] * num[d][q] / den[d][q];
		}
		for (int a = 0; a < 4; a++) {
			double s = 0, cc[3];
			for (int k = 0; k < 3; k++)
				s += cc[k] = fmax(cb[4 * k + a] / ws, eps);
			for (int k = 0; k < 3; k++)
				ha[a][k] = cc[k] / s;
		}
		return;
	}
	for (int d = 0; d < FACT_ND; d++) {
		ws += wd[d];
		for (int a = 0; a < 4; a++) {
			double s = 0, cc[3];
			for (int k = 0; k < 3; k++)
				s += cc[k] = fmax(num[d][4 * k + a] / den[d][4 * k + a], eps);
			for (int k = 0; k < 3; k++)
				ha[a][k] += wd[d] * cc[k] / s;
		}
	}
	for (int a = 0; a < 4; a++)
		for (int k = 0; k < 3; k++)
			ha[a][k] /= ws;
}

static int dir_chroma(const fact_blocks *B, int w, int h, double eps, int hcmean, double *hp,
                      const fact_raw *raw, double *hpa)
{
	const size_t n = (size_t)w * h;
	const int wblock = env_int("FACT_WBLOCK", 0);
	double *cs = malloc(sizeof *cs * n * FACT_ND * 3);
	if (!cs)
		return pc_error(PC_ENOMEM, "pan-fact reference: candidates of %dx%d", w, h);
#define CS(x, y, d) (cs + (((size_t)(y)*w + (size_t)(x)) * FACT_ND + (size_t)(d)) * 3)
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++)
			cand_at(B, x + FACT_PAD, y + FACT_PAD, eps, (double(*)[3])CS(x, y, 0));
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double hv[FACT_ND], o[3] = {0, 0, 0}, ws = 0;
			int xa = x - 1, xb = x + 1, ya = y - 1, yb = y + 1;
			if (wblock) { /* the 4×4 window around the pixel's 2×2 block */
				xa = x - ((x + FACT_PAD - B->x0) & 1) - 1;
				ya = y - ((y + FACT_PAD - B->y0) & 1) - 1;
				xb = xa + 3;
				yb = ya + 3;
			}
			for (int d = 0; d < FACT_ND; d++) {
				hv[d] = 0;
				for (int yy = ya; yy <= yb; yy++)
					for (int xx = xa; xx <= xb; xx++) {
						int xq = clampi(xx, w), yq = clampi(yy, h);
						const double *p = CS(xq, yq, d);
						const double *pl = CS(clampi(xx - 1, w), yq, d);
						const double *pu = CS(xq, clampi(yy - 1, h), d);
						for (int k = 0; k < 3; k++) {
							hv[d] += xx > xa ? fabs(p[k] - pl[k]) : 0;
							hv[d] += yy > ya ? fabs(p[k] - pu[k]) : 0;
						}
					}
			}
			if (hcmean)
				hv[0] = (hv[1] + hv[2] + hv[3] + hv[4]) / 4;
			if (hpa) {
				double wds[FACT_ND], ha[4][3];
				for (int d = 0; d < FACT_ND; d++)
					wds[d] = 1 / ((hv[d] + 1e-9) * (hv[d] + 1e-9));
				analyser_chroma(raw, x, y, wds, eps, ha);
				for (int a = 0; a < 4; a++)
					for (int k = 0; k < 3; k++)
						hpa[(size_t)(3 * a + k) * n + (size_t)y * w + x] = ha[a][k];
			}
			for (int d = 0; d < FACT_ND; d++) {
				double wd = 1 / ((hv[d] + 1e-9) * (hv[d] + 1e-9));
				for (int k = 0; k < 3; k++)
					o[k] += wd * CS(x, y, d)[k];
				ws += wd;
			}
			for (int k = 0; k < 3; k++)
				hp[(size_t)k * n + (size_t)y * w + x] = o[k] / ws;
		}
#undef CS
	free(cs);
	int sm = env_int("FACT_EPSSM", 0);
	if (hpa && sm) {
		/* ε = h^(a)_k / h_k smoothed per plane, then h^(a)_k = h_k·ε normalised */
		static const double f1[5] = {0, 1, 2, 1, 0}, f2[5] = {1, 2, 2, 2, 1};
		const double *f = sm == 1 ? f1 : f2;
		const double fn = sm == 1 ? 16 : 64;
		double *e = malloc(sizeof *e * 12 * n), *t = malloc(sizeof *t * n);
		for (int a = 0; a < 4; a++)
			for (int k = 0; k < 3; k++) {
				double *ep = e + (size_t)(3 * a + k) * n;
				for (size_t o = 0; o < n; o++)
					ep[o] = hpa[(size_t)(3 * a + k) * n + o] / hp[(size_t)k * n + o];
				pc_dimg ei = {ep, w, h};
				for (int y = 0; y < h; y++)
					for (int x = 0; x < w; x++) {
						double acc = 0;
						for (int j = -2; j <= 2; j++)
							for (int i = -2; i <= 2; i++)
								acc += f[i + 2] * f[j + 2] * pc_dimg_at(&ei, x + i, y + j);
						t[(size_t)y * w + x] = acc / fn;
					}
				memcpy(ep, t, sizeof *t * n);
			}
		for (int a = 0; a < 4; a++)
			for (size_t o = 0; o < n; o++) {
				double hv[3], su = 0;
				for (int k = 0; k < 3; k++)
					su += hv[k] = hp[(size_t)k * n + o] * e[(size_t)(3 * a + k) * n + o];
				for (int k = 0; k < 3; k++)
					hpa[(size_t)(3 * a + k) * n + o] = hv[k] / su;
			}
		free(e);
		free(t);
	}
	return 0;
}

/* The one-pass ratio step on a monochrome 2×2 mosaic v (w × h): the guide
 * P = v ∗ (f ⊗ f), f = [1 2 1]/4 (each analyser 1/4 wherever centred), ρ = (v + δ)/(P + δ) at
 * every sample, R_a = the tent (2 − |dx|)(2 − |dy|) of analyser a's ρ over the 3×3 window,
 * M_a = (v + δ)·R_a/R_own − δ, the own analyser v itself (pan-ratio's step at spacing 2). */
static int mono_ratio1(const double *v, int w, int h, const pc_mosaic *mono, double delta,
                       float *mk)
{
	const size_t n = (size_t)w * h;
	double *rho = malloc(sizeof *rho * n);
	if (!rho)
		return pc_error(PC_ENOMEM, "pan-fact reference: %dx%d", w, h);
	pc_dimg vi = {(double *)v, w, h};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double pp = 0;
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++)
					pp += (2 - abs(i)) * (2 - abs(j)) * pc_dimg_at(&vi, x + i, y + j);
			rho[(size_t)y * w + x] = (fmax(v[(size_t)y * w + x], 0) + delta) /
			                         (fmax(pp / 16, 0) + delta);
		}
	pc_dimg ri = {rho, w, h};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double num[4] = {0}, den[4] = {0};
			for (int j = -1; j <= 1; j++)
				for (int i = -1; i <= 1; i++) {
					double t = (2 - abs(i)) * (2 - abs(j));
					unsigned a = pc_dm_ch(mono, (unsigned)(x + i) & 1u, (unsigned)(y + j) & 1u);
					num[a] += t * pc_dimg_at(&ri, x + i, y + j);
					den[a] += t;
				}
			size_t o = (size_t)y * w + x;
			unsigned own = pc_dm_ch(mono, (unsigned)x & 1u, (unsigned)y & 1u);
			double sc = (fmax(v[o], 0) + delta) * den[own] / num[own];
			for (unsigned a = 0; a < 4; a++)
				mk[(size_t)a * n + o] =
				    (float)(a == own ? v[o] : sc * num[a] / den[a] - delta);
		}
	free(rho);
	return 0;
}

int pc_dm_pan_fact_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out)
{
	const int W = (int)w + 2 * FACT_PAD, H = (int)h + 2 * FACT_PAD;
	unsigned ox, oy;
	if (pc_mosaic_color_origin(m, &ox, &oy))
		return pc_error(PC_EINVAL, "pan-fact: the colour filter must cover 2x2 blocks");
	const int bayer = env_int("FACT_BAYER", 1);   /* 0 bilinear, 1 HA diff, 2 HA ratio */
	const int up = env_int("FACT_UP", 1);         /* 0 nearest block, 1 bilinear */
	const int mono_m = env_int("FACT_MONO", PC_DM_BILINEAR);
	const int interp_c = env_int("FACT_INTERPC", 0); /* up-sample C (1) or h (0) */
	fact_blocks B;
	B.x0 = (int)ox;
	B.y0 = (int)oy;
	B.nbx = (W - B.x0) / 2;
	B.nby = (H - B.y0) / 2;
	const size_t nb = (size_t)B.nbx * B.nby, n = (size_t)w * h;
	B.b = malloc(sizeof *B.b * nb);
	B.col = malloc(nb);
	double *rgb[3], *hb[3];
	for (int c = 0; c < 3; c++) {
		rgb[c] = malloc(sizeof **rgb * nb);
		hb[c] = malloc(sizeof **hb * nb);
	}
	double *mm = malloc(sizeof *mm * n), *hp = malloc(sizeof *hp * 3 * n);
	float *mk = malloc(sizeof *mk * 4 * n);
	double *hpa = NULL; /* per analyser a, colour k: plane 3a + k */
	int rc = 0;
	if (!B.b || !B.col || !rgb[0] || !rgb[1] || !rgb[2] || !hb[0] || !hb[1] || !hb[2] || !mm ||
	    !hp || !mk) {
		rc = pc_error(PC_ENOMEM, "pan-fact: %ux%u planes", w, h);
		goto done;
	}
	/* block sums of the extended raw */
	for (int j = 0; j < B.nby; j++)
		for (int i = 0; i < B.nbx; i++) {
			int X = B.x0 + 2 * i, Y = B.y0 + 2 * j;
			double s = 0;
			for (int v = 0; v < 2; v++)
				for (int u = 0; u < 2; u++)
					s += img[(size_t)mirror4(Y + v - FACT_PAD, (int)h) * w +
					         (size_t)mirror4(X + u - FACT_PAD, (int)w)];
			B.b[(size_t)j * B.nbx + i] = s;
			B.col[(size_t)j * B.nbx + i] =
			    (unsigned char)(pc_mosaic_color(m, (uint32_t)X, (uint32_t)Y) - PC_CFA_R);
		}
	double eps = FACT_EPS * 4 * fs;
	if (env_int("FACT_PRHO", 0))
		eps = FACT_EPS;
	if (env_int("FACT_RHO", 0)) {
		eps = FACT_EPS;
		/* ratios to the blocks' luminance: [1 2 1]⊗[1 2 1]/16 over the block sums weighs
		 * R, G, B 1/4, 1/2, 1/4 around every block */
		double *pb = malloc(sizeof *pb * nb);
		for (int j = 0; j < B.nby; j++)
			for (int i = 0; i < B.nbx; i++) {
				double s = 0;
				for (int dj = -1; dj <= 1; dj++)
					for (int di = -1; di <= 1; di++)
						s += (2 - abs(di)) * (2 - abs(dj)) *
						     bat(&B, B.b, i + di, j + dj);
				pb[(size_t)j * B.nbx + i] = s / 16;
			}
		const double dl = 0.01 * 4 * fs;
		for (size_t o = 0; o < nb; o++)
			B.b[o] = (fmax(B.b[o], 0) + dl) / (fmax(pb[o], 0) + dl);
		free(pb);
	}
	const int hdir = env_int("FACT_H", 0), perana = env_int("FACT_PERANA", 0);
	if (hdir) {
		fact_raw fr = {img, (int)w, (int)h, m, env_int("FACT_PRHO", 0), 0.01 * fs};
		if (perana && !(hpa = malloc(sizeof *hpa * 12 * n))) {
			rc = pc_error(PC_ENOMEM, "pan-fact");
			goto done;
		}
		rc = dir_chroma(&B, (int)w, (int)h, eps, hdir == 2, hp, &fr, hpa);
		if (rc)
			goto done;
	}
	if (bayer == 0)
		bayer_bilinear(&B, rgb);
	else
		bayer_ha(&B, rgb, bayer == 2, 0.01 * 4 * fs);
	for (size_t o = 0; o < nb; o++) {
		double s = 0, c3[3];
		for (int c = 0; c < 3; c++)
			s += c3[c] = fmax(rgb[c][o], eps);
		for (int c = 0; c < 3; c++)
			hb[c][o] = interp_c ? c3[c] : c3[c] / s;
	}
	/* the chromaticities at every pixel of the raw */
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			int X = x + FACT_PAD, Y = y + FACT_PAD;
			int i = (X - B.x0) / 2, j = (Y - B.y0) / 2;
			int si = (X - B.x0) % 2 ? 1 : -1, sj = (Y - B.y0) % 2 ? 1 : -1;
			double hv[3], s = 0;
			int own = pc_mosaic_color(m, (uint32_t)x, (uint32_t)y) - PC_CFA_R;
			if (hpa) {
				int a = (int)pc_mosaic_channel(m, (uint32_t)x, (uint32_t)y);
				mm[(size_t)y * w + x] = img[(size_t)y * w + x] /
				                        hpa[(size_t)(3 * a + own) * n + (size_t)y * w + x];
				continue;
			}
			if (hdir) {
				mm[(size_t)y * w + x] =
				    img[(size_t)y * w + x] / hp[(size_t)own * n + (size_t)y * w + x];
				continue;
			}
			for (int c = 0; c < 3; c++) {
				if (up == 0)
					hv[c] = bat(&B, hb[c], i, j);
				else
					hv[c] = (9 * bat(&B, hb[c], i, j) + 3 * bat(&B, hb[c], i + si, j) +
					         3 * bat(&B, hb[c], i, j + sj) +
					         bat(&B, hb[c], i + si, j + sj)) /
					        16;
				s += hv[c];
			}
			for (int c = 0; c < 3; c++)
				hp[(size_t)c * n + (size_t)y * w + x] = interp_c ? hv[c] / s : hv[c];
			mm[(size_t)y * w + x] = img[(size_t)y * w + x] / hp[(size_t)own * n + (size_t)y * w + x];
		}
	/* the monochrome polarization step on the hue-normalised mosaic */
	pc_mosaic mono = pc_dm_color_mono(m);
	pc_fplane mp[4];
	for (int k = 0; k < 4; k++) {
		mp[k].data = mk + (size_t)k * n;
		mp[k].row_stride = w;
		mp[k].pixel_stride = 1;
	}
	if (mono_m == 100)
		rc = mono_ratio1(mm, (int)w, (int)h, &mono, 0.01 * 3 * fs, mk);
	else
		rc = pc_dm_ref(mm, w, h, &mono, (pc_demosaic_method)mono_m, 3 * fs, mp);
	if (rc)
		goto done;
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			size_t o = (size_t)y * w + x;
			unsigned own = 4 * (pc_mosaic_color(m, (uint32_t)x, (uint32_t)y) - PC_CFA_R) +
			               pc_mosaic_channel(m, (uint32_t)x, (uint32_t)y);
			for (unsigned q = 0; q < 12; q++) {
				double hq = hpa ? hpa[(size_t)(3 * (q % 4) + q / 4) * n + o]
				                : hp[(size_t)(q / 4) * n + o];
				double v = q == own ? img[o] : (double)mk[(size_t)(q % 4) * n + o] * hq;
				const pc_fplane *p = &out[q];
				p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride] = (float)v;
			}
		}
done:
	free(B.b);
	free(B.col);
	for (int c = 0; c < 3; c++) {
		free(rgb[c]);
		free(hb[c]);
	}
	free(mm);
	free(hp);
	free(mk);
	free(hpa);
	return rc;
}

const pc_dm_pan_fns *pc_dm_fact_fns_get(pc_demosaic_method m)
{
	static const pc_dm_pan_fns fact = {pc_dm_pan_fact_ref, NULL};
	return m == PC_DM_PAN_FACT ? &fact : NULL;
}
