/* Residual interpolation as its authors define it, in double precision (references):
 *
 *  - MLRI, minimized-Laplacian residual interpolation (Kiku, Monno, Tanaka, Okutomi, "Beyond
 *    color difference: residual interpolation for color image demosaicking", IEEE TIP 25(3)
 *    2016; for polarization: Morimatsu, Monno, Tanaka, Okutomi, ICIP 2020, arXiv:2007.14292,
 *    and their MATLAB release): per channel c, in every (2R+1)² window (R = 5), the slope
 *    a = Σ L_G·L_I / (Σ L_G² + ε) over channel c's samples, L the Laplacian with spacing 2
 *    (4·v(p) − v(p ± 2x) − v(p ± 2y), same-channel pixels only), and b = mean(I) − a·mean(G)
 *    over the samples; each window's fit error σ² = mean over the samples of (a·G + b − I)²;
 *    at p, ā and b̄ are the averages of a and b over the windows covering p weighted by
 *    1/max(σ², 0.01·FS²); tentative T = clip(ā·G + b̄, 0, FS); I_c = T + tent(raw − T).
 *  - the authors' edge-aware guide (ibid., Sec. 2): four directional intensity estimates
 *    X_n, X_s, X_w, X_e (the raw averaged over the two rows above / below, or the two columns
 *    left / right, of p with weights 1/8, 1/4, 1/8 across: a 2×3 window holds every analyser
 *    with weight 1/4), each weighted by 1/(ε + w_d), w_d the mean of D_d over the 3×5 half
 *    window towards d, D_n(p) = |h(p − y) − h(p)| with h(q) = v(q) − (v(q − x) + v(q + x))/2
 *    the horizontal second difference: for uniform polarization h alternates between
 *    I_a − I_b and I_c − I_d of the two rows, and (I0 + I90) = (I45 + I135) makes D_n vanish
 *    whatever the DoLP — the detector is not fooled by polarization.
 *
 * ε is the authors' machine epsilon on [0, 1] data (scaled by full scale here). Borders: the
 * library's whole-sample mirror (the release replicates edge pixels; the protocol's 15-pixel
 * border hides the difference). The release's box sums shrink at the image border; ours
 * mirror, so every window has (2R+1)² pixels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "polarcam/error.h"

#define MLRI_R      5
#define MACHINE_EPS 2.220446049250313e-16

/* dst(p) = Σ over the (2R+1)² window around p of src (mirrored), by running sums in double,
 * separable. Each pass also counts the window's nonzero entries and gives exactly 0 where there
 * are none: a running sum keeps the rounding of the values that left its window, and in a black
 * region the slope a = Σ L_G·L_I/(Σ L_G² + ε) of two such residues, far below ε's scale or not,
 * decides the output and hence its DoLP (Round 38, docs/demosaicking.md). A sum over zeros is 0
 * by definition, so this changes no value but the residues. */
static void box(const pc_dimg *src, int R, pc_dimg *dst, double *tmp)
{
	int w = src->w, h = src->h;
	for (int y = 0; y < h; y++) { /* horizontal */
		double s = 0;
		long nz = 0;
		for (int dx = -R; dx <= R; dx++) {
			s += pc_dimg_at(src, dx, y);
			nz += pc_dimg_at(src, dx, y) != 0;
		}
		for (int x = 0; x < w; x++) {
			tmp[(size_t)y * w + x] = nz ? s : 0;
			double a = pc_dimg_at(src, x + R + 1, y), b = pc_dimg_at(src, x - R, y);
			s += a - b;
			nz += (a != 0) - (b != 0);
		}
	}
	pc_dimg t = {tmp, w, h};
	for (int x = 0; x < w; x++) { /* vertical */
		double s = 0;
		long nz = 0;
		for (int dy = -R; dy <= R; dy++) {
			s += pc_dimg_at(&t, x, dy);
			nz += pc_dimg_at(&t, x, dy) != 0;
		}
		for (int y = 0; y < h; y++) {
			dst->p[(size_t)y * w + x] = nz ? s : 0;
			double a = pc_dimg_at(&t, x, y + R + 1), b = pc_dimg_at(&t, x, y - R);
			s += a - b;
			nz += (a != 0) - (b != 0);
		}
	}
}

enum { NB = 14 };

/* MLRI of channel c of raw r with guide g into out (planes[NB] are scratch images). */
static void mlri_channel(const pc_dimg *r, const pc_dimg *g, const pc_mosaic *m, unsigned c,
                         double fs, pc_dimg *s, double *tmp, const pc_fplane *out)
{
	const int w = r->w, h = r->h;
	const size_t n = (size_t)w * h;
	const double eps = MACHINE_EPS * fs * fs;
	pc_dimg *M = &s[0], *LGLI = &s[1], *LG2 = &s[2], *G = &s[3], *I = &s[4], *G2 = &s[5],
	        *I2 = &s[6], *GI = &s[7], *A = &s[8], *B = &s[9], *W = &s[10], *T = &s[11],
	        *X = &s[12], *Y = &s[13];
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			int on = pc_dm_ch(m, x, y) == c;
			double gv = pc_dimg_at(g, x, y), iv = pc_dimg_at(r, x, y);
			double lg = 4 * gv - pc_dimg_at(g, x - 2, y) - pc_dimg_at(g, x + 2, y) -
			            pc_dimg_at(g, x, y - 2) - pc_dimg_at(g, x, y + 2);
			double li = 4 * iv - pc_dimg_at(r, x - 2, y) - pc_dimg_at(r, x + 2, y) -
			            pc_dimg_at(r, x, y - 2) - pc_dimg_at(r, x, y + 2);
			M->p[i] = on;
			LGLI->p[i] = on ? lg * li : 0;
			LG2->p[i] = on ? lg * lg : 0;
			G->p[i] = on ? gv : 0;
			I->p[i] = on ? iv : 0;
			G2->p[i] = on ? gv * gv : 0;
			I2->p[i] = on ? iv * iv : 0;
			GI->p[i] = on ? gv * iv : 0;
		}
	pc_dimg *in[8] = {M, LGLI, LG2, G, I, G2, I2, GI};
	for (int k = 0; k < 8; k++) {
		box(in[k], MLRI_R, X, tmp);
		memcpy(in[k]->p, X->p, n * sizeof(double));
	}
	for (size_t i = 0; i < n; i++) {
		double N = M->p[i] > 0 ? M->p[i] : 1;
		double a = (LGLI->p[i] / N) / (LG2->p[i] / N + eps);
		double b = I->p[i] / N - a * G->p[i] / N;
		double d2 = (G2->p[i] * a * a + b * b * M->p[i] + I2->p[i] + 2 * a * b * G->p[i] -
		             2 * b * I->p[i] - 2 * a * GI->p[i]) /
		            N;
		double wt = 1.0 / fmax(d2 / (fs * fs), 0.01);
		A->p[i] = a * wt;
		B->p[i] = b * wt;
		W->p[i] = wt;
	}
	box(A, MLRI_R, X, tmp);
	memcpy(A->p, X->p, n * sizeof(double));
	box(B, MLRI_R, X, tmp);
	memcpy(B->p, X->p, n * sizeof(double));
	box(W, MLRI_R, X, tmp);
	for (size_t i = 0; i < n; i++) {
		double ws = fmax(X->p[i], 0.01);
		double t = A->p[i] / ws * g->p[i] + B->p[i] / ws;
		T->p[i] = fmin(fmax(t, 0), fs);
	}
	for (int y = 0; y < h; y++) /* the residual at the samples */
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			Y->p[i] = r->p[i] - T->p[i];
		}
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			double v = T->p[i] + pc_dm_tent(Y, m, c, x, y);
			out[c]
			    .data[(size_t)y * out[c].row_stride + (size_t)x * out[c].pixel_stride] =
			    (float)v;
		}
}

/* The authors' edge-aware guide (header comment). */
static void ea_guide(const pc_dimg *r, double fs, pc_dimg *g, pc_dimg *D)
{
	const int w = r->w, h = r->h;
	const double eps = MACHINE_EPS * fs;
	/* D[0..3] = D_n, D_s, D_w, D_e per pixel (four images in D[0..3]) */
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
#define HD(xx, yy)                                                                                 \
	(pc_dimg_at(r, xx, yy) - 0.5 * (pc_dimg_at(r, (xx)-1, yy) + pc_dimg_at(r, (xx) + 1, yy)))
#define VD(xx, yy)                                                                                 \
	(pc_dimg_at(r, xx, yy) - 0.5 * (pc_dimg_at(r, xx, (yy)-1) + pc_dimg_at(r, xx, (yy) + 1)))
			D[0].p[i] = fabs(HD(x, y - 1) - HD(x, y));
			D[1].p[i] = fabs(HD(x, y + 1) - HD(x, y));
			D[2].p[i] = fabs(VD(x - 1, y) - VD(x, y));
			D[3].p[i] = fabs(VD(x + 1, y) - VD(x, y));
#undef HD
#undef VD
		}
	static const double k[3] = {0.125, 0.25, 0.125};
	for (int y = 0; y < h; y++)
		for (int x = 0; x < w; x++) {
			double X[4] = {0, 0, 0, 0}, wd[4] = {0, 0, 0, 0};
			for (int t = -1; t <= 1; t++) {
				X[0] += k[t + 1] *
				        (pc_dimg_at(r, x + t, y - 1) + pc_dimg_at(r, x + t, y));
				X[1] += k[t + 1] *
				        (pc_dimg_at(r, x + t, y) + pc_dimg_at(r, x + t, y + 1));
				X[2] += k[t + 1] *
				        (pc_dimg_at(r, x - 1, y + t) + pc_dimg_at(r, x, y + t));
				X[3] += k[t + 1] *
				        (pc_dimg_at(r, x, y + t) + pc_dimg_at(r, x + 1, y + t));
			}
			for (int a = -2; a <= 2; a++)
				for (int b = 0; b <= 2; b++) {
					wd[0] += pc_dimg_at(&D[0], x + a, y - b);
					wd[1] += pc_dimg_at(&D[1], x + a, y + b);
					wd[2] += pc_dimg_at(&D[2], x - b, y + a);
					wd[3] += pc_dimg_at(&D[3], x + b, y + a);
				}
			double num = 0, den = 0;
			for (int d = 0; d < 4; d++) {
				double W = 1.0 / (wd[d] / 15 + eps);
				num += W * X[d];
				den += W;
			}
			g->p[(size_t)y * w + x] = num / (den + eps);
		}
}

int pc_dm_ref_mlri(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                   pc_demosaic_method method, double full_scale, const pc_fplane *out)
{
	if (m->period != 2)
		return pc_error(PC_ENOTSUP, "%s: monochrome mosaics only",
		                pc_demosaic_method_get(method)->name);
	const int w = (int)width, h = (int)height;
	const size_t n = (size_t)w * h;
	pc_dimg r = {(double *)img, w, h};
	double *mem = malloc(sizeof(double) * n * (NB + 2));
	if (!mem)
		return pc_error(PC_ENOMEM, "%s reference: %dx%d images",
		                pc_demosaic_method_get(method)->name, w, h);
	pc_dimg s[NB];
	for (int k = 0; k < NB; k++)
		s[k] = (pc_dimg){mem + n * (size_t)k, w, h};
	pc_dimg g = {mem + n * NB, w, h};
	double *tmp = mem + n * (NB + 1);
	ea_guide(&r, full_scale, &g, s);
	for (unsigned c = 0; c < 4; c++)
		mlri_channel(&r, &g, m, c, full_scale, s, tmp, out);
	free(mem);
	return 0;
}

int pc_dm_mlri_ri(const double *img, const double *guide, uint32_t width, uint32_t height,
                  const pc_mosaic *m, double full_scale, const pc_fplane *out)
{
	const int w = (int)width, h = (int)height;
	const size_t n = (size_t)w * h;
	pc_dimg r = {(double *)img, w, h}, g = {(double *)guide, w, h};
	double *mem = malloc(sizeof(double) * n * (NB + 1));
	if (!mem)
		return -1;
	pc_dimg s[NB];
	for (int k = 0; k < NB; k++)
		s[k] = (pc_dimg){mem + n * (size_t)k, w, h};
	for (unsigned c = 0; c < 4; c++)
		mlri_channel(&r, &g, m, c, full_scale, s, mem + n * NB, out);
	free(mem);
	return 0;
}
