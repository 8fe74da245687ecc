/* IGRI2, the second iterative-guided residual interpolation of Morimatsu, Monno, Tanaka and
 * Okutomi (IEEE Sensors J. 21(24) 2021), as their MATLAB release defines it (`IGRI2.m`, read
 * for its formulas), in double precision (the reference; no fast path yet):
 *
 *  1. The analysers of one diagonal lattice (i + j even: 90° and 0° in the Sony layout; odd:
 *     45° and 135°) form, rotated by 45°, a square grid on which the two analysers make a
 *     checkerboard. On each rotated grid, Bayer residual interpolation of the "green"
 *     checkerboard (Kiku et al., IEEE TIP 25(3) 2016, green step: directional MLRI tentative
 *     estimates in 7×7 windows, horizontal and vertical colour differences, combined by
 *     inverse squared gradient weights with one-sided Gaussian (σ = 1) smoothing) fills each
 *     of the two analysers on the whole lattice.
 *  2. On the full grid, each analyser's lattice values with the other lattice's S0/2
 *     estimate ((I45 + I135)/2 or (I0 + I90)/2) in the other places is a Bayer-like image;
 *     the same green step fills the analyser everywhere.
 *  3. The mean of the four as guide, MLRI residual interpolation (11×11, as eari-mlri) of
 *     each channel from its raw samples.
 *
 * Grids of steps 1-2 extend their borders by replication and the rotated grid is zero
 * outside the image, as in the release; step 3 mirrors (demosaic_mlri.c). Values are
 * normalised to [0, 1] inside (the release's constants 1e-2 and the clip to [0, 1] are
 * on that scale). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "polarcam/error.h"

#define MACHINE_EPS 2.220446049250313e-16

typedef struct grid {
	double *p;
	int h, w; /* rows, columns */
} grid;

static int grid_new(grid *g, int h, int w)
{
	g->h = h;
	g->w = w;
	g->p = calloc((size_t)h * w, sizeof(double));
	return g->p ? 0 : -1;
}

static double rep(const grid *g, int i, int j)
{
	i = i < 0 ? 0 : i >= g->h ? g->h - 1 : i;
	j = j < 0 ? 0 : j >= g->w ? g->w - 1 : j;
	return g->p[(size_t)i * g->w + j];
}

#define G(g, i, j) ((g)->p[(size_t)(i) * (g)->w + (j)])

/* correlation with a 1-D kernel k[-r..r] along rows (dir 0: horizontal) or columns, replicate */
static void filt1(const grid *s, grid *d, const double *k, int r, int dir)
{
	for (int i = 0; i < s->h; i++)
		for (int j = 0; j < s->w; j++) {
			double v = 0;
			for (int t = -r; t <= r; t++)
				v += k[t + r] * (dir == 0 ? rep(s, i, j + t) : rep(s, i + t, j));
			G(d, i, j) = v;
		}
}

/* box sum over rows i-v..i+v, columns j-h..j+h, truncated at the border (the release's
 * cumulative-sum box filter), by prefix sums */
static void boxs(const grid *s, grid *d, int h, int v)
{
	int H = s->h, W = s->w;
	double *pre = malloc(sizeof(double) * (size_t)((H > W ? H : W) + 1));
	double *tmp = malloc(sizeof(double) * (size_t)H * W);
	if (!pre || !tmp) { /* callers check nothing here: fall back to the direct sum */
		free(pre);
		free(tmp);
		for (int i = 0; i < H; i++)
			for (int j = 0; j < W; j++) {
				double t = 0;
				for (int a = i - v; a <= i + v; a++)
					for (int b = j - h; b <= j + h; b++)
						if (a >= 0 && a < H && b >= 0 && b < W)
							t += G(s, a, b);
				G(d, i, j) = t;
			}
		return;
	}
	for (int i = 0; i < H; i++) {
		pre[0] = 0;
		for (int j = 0; j < W; j++)
			pre[j + 1] = pre[j] + G(s, i, j);
		for (int j = 0; j < W; j++) {
			int a = j - h < 0 ? 0 : j - h, b = j + h >= W ? W - 1 : j + h;
			tmp[(size_t)i * W + j] = pre[b + 1] - pre[a];
		}
	}
	for (int j = 0; j < W; j++) {
		pre[0] = 0;
		for (int i = 0; i < H; i++)
			pre[i + 1] = pre[i] + tmp[(size_t)i * W + j];
		for (int i = 0; i < H; i++) {
			int a = i - v < 0 ? 0 : i - v, b = i + v >= H ? H - 1 : i + v;
			G(d, i, j) = pre[b + 1] - pre[a];
		}
	}
	free(pre);
	free(tmp);
}

/* The release's MLRI guided filter (guidedfilter_MLRI_wei.m): guide gd, target r, masks,
 * Laplacians lg (of the masked guide) and lr (of the target), window (2v+1) × (2h+1). */
static int mlri(const grid *gd, const grid *r, const grid *mask, const grid *lg, const grid *lr,
                int h, int v, double eps, grid *q)
{
	int H = gd->h, W = gd->w;
	size_t n = (size_t)H * W;
	grid t[10];
	for (int k = 0; k < 10; k++)
		if (grid_new(&t[k], H, W)) {
			for (int z = 0; z < k; z++)
				free(t[z].p);
			return -1;
		}
	grid *N = &t[0], *Ip = &t[1], *II = &t[2], *mG = &t[3], *mR = &t[4], *A = &t[5], *B = &t[6],
	     *X = &t[7], *Y = &t[8], *Z = &t[9];
	/* products at the masked samples */
	for (size_t i = 0; i < n; i++) {
		X->p[i] = lg->p[i] * lr->p[i] * mask->p[i];
		Y->p[i] = lg->p[i] * lg->p[i] * mask->p[i];
	}
	boxs(mask, N, h, v);
	boxs(X, Ip, h, v);
	boxs(Y, II, h, v);
	for (size_t i = 0; i < n; i++) {
		X->p[i] = gd->p[i] * mask->p[i];
		Y->p[i] = r->p[i] * mask->p[i];
	}
	boxs(X, mG, h, v);
	boxs(Y, mR, h, v);
	for (size_t i = 0; i < n; i++) {
		double Nn = N->p[i] == 0 ? 1 : N->p[i];
		double a = (Ip->p[i] / Nn) / (II->p[i] / Nn + eps);
		A->p[i] = a;
		B->p[i] = mR->p[i] / Nn - a * mG->p[i] / Nn;
	}
	/* fit error per window: Σ over the samples of (a·G + b − R)² / N */
	for (size_t i = 0; i < n; i++) {
		X->p[i] = gd->p[i] * gd->p[i] * mask->p[i];
		Y->p[i] = r->p[i] * r->p[i] * mask->p[i];
		Z->p[i] = r->p[i] * gd->p[i] * mask->p[i];
	}
	grid sGG = {NULL, 0, 0}, sRR = {NULL, 0, 0}, sRG = {NULL, 0, 0};
	if (grid_new(&sGG, H, W) || grid_new(&sRR, H, W) || grid_new(&sRG, H, W)) {
		free(sGG.p);
		free(sRR.p);
		free(sRG.p);
		for (int k = 0; k < 10; k++)
			free(t[k].p);
		return -1;
	}
	boxs(X, &sGG, h, v);
	boxs(Y, &sRR, h, v);
	boxs(Z, &sRG, h, v);
	for (size_t i = 0; i < n; i++) {
		double Nn = N->p[i] == 0 ? 1 : N->p[i], a = A->p[i], b = B->p[i];
		double d2 = (sGG.p[i] * a * a + b * b * N->p[i] + sRR.p[i] + 2 * a * b * mG->p[i] -
		             2 * b * mR->p[i] - 2 * a * sRG.p[i]) /
		            Nn;
		double wt = 1.0 / (d2 < 0.01 ? 0.01 : d2);
		X->p[i] = wt;
		Y->p[i] = a * wt;
		Z->p[i] = b * wt;
	}
	boxs(X, &sGG, h, v);
	boxs(Y, &sRR, h, v);
	boxs(Z, &sRG, h, v);
	for (size_t i = 0; i < n; i++) {
		double ws = sGG.p[i] < 0.01 ? 0.01 : sGG.p[i];
		q->p[i] = sRR.p[i] / ws * gd->p[i] + sRG.p[i] / ws;
	}
	free(sGG.p);
	free(sRR.p);
	free(sRG.p);
	for (int k = 0; k < 10; k++)
		free(t[k].p);
	return 0;
}

static double clip01(double v)
{
	return v < 0 ? 0 : v > 1 ? 1 : v;
}

/* The green step of Bayer residual interpolation (the release's green_interpolation.m) on
 * grid raw whose "green" sites are those with (i + j) % 2 == gpar and whose red sites are
 * the other sites of rows with i % 2 == rrow (blue: the others). Writes the full green. */
static int green_step(const grid *raw, int gpar, int rrow, grid *green)
{
	const int H = raw->h, W = raw->w;
	const size_t n = (size_t)H * W;
	enum { NT = 30 };
	grid t[NT];
	for (int k = 0; k < NT; k++)
		if (grid_new(&t[k], H, W)) {
			for (int z = 0; z < k; z++)
				free(t[z].p);
			return -1;
		}
	grid *mR = &t[0], *mG = &t[1], *mB = &t[2], *mGr = &t[3], *mGb = &t[4], *R = &t[5],
	     *Gc = &t[6], *Bc = &t[7], *rh = &t[8], *rv = &t[9];
	for (int i = 0; i < H; i++)
		for (int j = 0; j < W; j++) {
			size_t k = (size_t)i * W + j;
			int g = ((i + j) & 1) == gpar, rr = (i & 1) == rrow;
			mG->p[k] = g;
			mR->p[k] = !g && rr;
			mB->p[k] = !g && !rr;
			mGr->p[k] = g && rr;
			mGb->p[k] = g && !rr;
			R->p[k] = raw->p[k] * mR->p[k];
			Gc->p[k] = raw->p[k] * mG->p[k];
			Bc->p[k] = raw->p[k] * mB->p[k];
		}
	static const double kh[3] = {0.5, 0, 0.5};
	filt1(raw, rh, kh, 1, 0);
	filt1(raw, rv, kh, 1, 1);
	grid *dh = &t[10], *dv = &t[11];
	static const double F[5] = {-1, 0, 2, 0, -1};
	for (int dir = 0; dir < 2 && 1; dir++) {
		const grid *rd = dir == 0 ? rh : rv;
		/* guides: green filled at R and B sites; red filled at the green sites of red rows
		 * (horizontal) or of blue rows (vertical: their vertical neighbours are red) */
		grid *gg = &t[12], *gr = &t[13], *gb = &t[14];
		const grid *mGR = dir == 0 ? mGr : mGb, *mGB = dir == 0 ? mGb : mGr;
		for (size_t k = 0; k < n; k++) {
			gg->p[k] = Gc->p[k] + rd->p[k] * (mR->p[k] + mB->p[k]);
			gr->p[k] = R->p[k] + rd->p[k] * mGR->p[k];
			gb->p[k] = Bc->p[k] + rd->p[k] * mGB->p[k];
		}
		grid *la = &t[15], *lb = &t[16], *tmp = &t[17];
		grid *tR = &t[18], *tGr = &t[19], *tB = &t[20], *tGb = &t[21];
		const double eps = MACHINE_EPS;
		/* R from the green guide at R sites */
		filt1(R, la, F, 2, dir);
		for (size_t k = 0; k < n; k++)
			tmp->p[k] = gg->p[k] * mR->p[k];
		filt1(tmp, lb, F, 2, dir);
		if (mlri(gg, R, mR, lb, la, 3, 3, eps, tR))
			goto fail;
		/* G at GR sites from the red guide */
		for (size_t k = 0; k < n; k++)
			tmp->p[k] = Gc->p[k] * mGR->p[k];
		filt1(tmp, la, F, 2, dir);
		grid *tmp2 = &t[22];
		for (size_t k = 0; k < n; k++)
			tmp2->p[k] = gr->p[k] * mGR->p[k];
		filt1(tmp2, lb, F, 2, dir);
		if (mlri(gr, tmp, mGR, lb, la, 3, 3, eps, tGr))
			goto fail;
		/* B from the green guide at B sites */
		filt1(Bc, la, F, 2, dir);
		for (size_t k = 0; k < n; k++)
			tmp->p[k] = gg->p[k] * mB->p[k];
		filt1(tmp, lb, F, 2, dir);
		if (mlri(gg, Bc, mB, lb, la, 3, 3, eps, tB))
			goto fail;
		/* G at GB sites from the blue guide */
		for (size_t k = 0; k < n; k++)
			tmp->p[k] = Gc->p[k] * mGB->p[k];
		filt1(tmp, la, F, 2, dir);
		for (size_t k = 0; k < n; k++)
			tmp2->p[k] = gb->p[k] * mGB->p[k];
		filt1(tmp2, lb, F, 2, dir);
		if (mlri(gb, tmp, mGB, lb, la, 3, 3, eps, tGb))
			goto fail;
		/* residuals at the own sites, linearly interpolated along the direction */
		grid *rs[4] = {&t[23], &t[24], &t[25], &t[26]}, *ri[4] = {&t[27], &t[28], la, lb};
		for (size_t k = 0; k < n; k++) {
			rs[0]->p[k] = (raw->p[k] - tGr->p[k]) * mGR->p[k];
			rs[1]->p[k] = (raw->p[k] - tGb->p[k]) * mGB->p[k];
			rs[2]->p[k] = (raw->p[k] - tR->p[k]) * mR->p[k];
			rs[3]->p[k] = (raw->p[k] - tB->p[k]) * mB->p[k];
		}
		for (int q = 0; q < 4; q++)
			filt1(rs[q], ri[q], kh, 1, dir);
		grid *d = dir == 0 ? dh : dv;
		for (size_t k = 0; k < n; k++) {
			/* estimates: G at R sites (from GR residuals: the sites next to red along
			 * the direction), G at B sites, R at GR sites, B at GB sites */
			double Gr = (tGr->p[k] + ri[0]->p[k]) * mR->p[k];
			double Gb = (tGb->p[k] + ri[1]->p[k]) * mB->p[k];
			double Rg = (tR->p[k] + ri[2]->p[k]) * mGR->p[k];
			double Bg = (tB->p[k] + ri[3]->p[k]) * mGB->p[k];
			d->p[k] = Gc->p[k] + Gr + Gb - R->p[k] - Bc->p[k] - Rg - Bg;
		}
	}
	{
		/* combine the directional colour differences */
		static const double kd[3] = {1, 0, -1};
		grid *gh = &t[12], *gv = &t[13], *wh = &t[14], *wv = &t[15];
		filt1(dh, gh, kd, 1, 0);
		filt1(dv, gv, kd, 1, 1);
		for (size_t k = 0; k < n; k++) {
			gh->p[k] = fabs(gh->p[k]);
			gv->p[k] = fabs(gv->p[k]);
		}
		static const double k3[3] = {1, 1, 1};
		grid *tmp = &t[16];
		filt1(gh, tmp, k3, 1, 0);
		filt1(tmp, wh, k3, 1, 1);
		filt1(gv, tmp, k3, 1, 0);
		filt1(tmp, wv, k3, 1, 1);
		/* one-sided Gaussian (σ = 1) of 5 taps: centre and 4 towards the side */
		double gk[9], s = 0;
		for (int q = 0; q < 9; q++)
			s += gk[q] = exp(-0.5 * (q - 4) * (q - 4));
		for (int q = 0; q < 9; q++)
			gk[q] /= s;
		double ke[9], kw[9], se = 0, sw = 0;
		for (int q = 0; q < 9; q++) {
			ke[q] = q >= 4 ? gk[q] : 0;
			kw[q] = q <= 4 ? gk[q] : 0;
			se += ke[q];
			sw += kw[q];
		}
		for (int q = 0; q < 9; q++) {
			ke[q] /= se;
			kw[q] /= sw;
		}
		grid *dn = &t[17], *ds = &t[18], *dw = &t[19], *de = &t[20];
		filt1(dv, dn, kw, 4, 1);
		filt1(dv, ds, ke, 4, 1);
		filt1(dh, dw, kw, 4, 0);
		filt1(dh, de, ke, 4, 0);
		for (int i = 0; i < H; i++)
			for (int j = 0; j < W; j++) {
				size_t k = (size_t)i * W + j;
				double Ww = 1 / (pow(rep(wh, i, j - 1), 2) + 1e-2);
				double We = 1 / (pow(rep(wh, i, j + 1), 2) + 1e-2);
				double Wn = 1 / (pow(rep(wv, i - 1, j), 2) + 1e-2);
				double Ws = 1 / (pow(rep(wv, i + 1, j), 2) + 1e-2);
				double dif = (Wn * dn->p[k] + Ws * ds->p[k] + Ww * dw->p[k] +
				              We * de->p[k]) /
				             (Ww + We + Wn + Ws);
				green->p[k] = mG->p[k] ? raw->p[k] : dif + raw->p[k];
			}
	}
	for (int k = 0; k < NT; k++)
		free(t[k].p);
	return 0;
fail:
	for (int k = 0; k < NT; k++)
		free(t[k].p);
	return -1;
}

/* rotated coordinates of (I, J) on its diagonal lattice (the release's deformation, 0-based) */
static void rot(int I, int J, int s1, int *r, int *c)
{
	if (((I + J) & 1) == 0) {
		*r = (I + J) / 2;
		*c = (J - I) / 2 + s1 / 2 - 1;
	} else {
		*r = (I + J - 1) / 2;
		*c = (J - I + 1) / 2 + s1 / 2 - 1;
	}
}

int pc_dm_ref_igri2(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                    double full_scale, const pc_fplane *out)
{
	if (m->period != 2)
		return pc_error(PC_ENOTSUP, "igri2: monochrome mosaics only");
	if ((m->channel[0][0] ^ m->channel[1][1]) != 2)
		return pc_error(PC_ENOTSUP,
		                "igri2: the layout must put orthogonal analysers on each "
		                "diagonal (as 90,45,135,0 does)");
	const int s1 = (int)height, s2 = (int)width;
	const size_t n = (size_t)s1 * s2;
	double *full[4] = {NULL, NULL, NULL, NULL};
	double *x = malloc(sizeof(double) * n), *guide = malloc(sizeof(double) * n);
	int rc = x && guide ? 0 : -1;
	for (int c = 0; c < 4 && !rc; c++)
		rc = (full[c] = malloc(sizeof(double) * n)) ? 0 : -1;
	int R = 0, C = 0; /* rotated grid size */
	for (int I = 0; I < s1 && !rc; I++)
		for (int J = 0; J < s2; J++) {
			x[(size_t)I * s2 + J] = img[(size_t)I * s2 + J] / full_scale;
			int r, c;
			rot(I, J, s1, &r, &c);
			if (r + 1 > R)
				R = r + 1;
			if (c + 1 > C)
				C = c + 1;
		}
	/* step 1: each diagonal lattice rotated, each of its two analysers filled on it */
	for (int L = 0; L < 2 && !rc; L++) {
		grid g, out1;
		if (grid_new(&g, R, C) || grid_new(&out1, R, C)) {
			rc = -1;
			break;
		}
		for (int I = 0; I < s1; I++)
			for (int J = 0; J < s2; J++)
				if (((I + J) & 1) == L) {
					int r, c;
					rot(I, J, s1, &r, &c);
					G(&g, r, c) = x[(size_t)I * s2 + J];
				}
		for (int k = 0; k < 2 && !rc; k++) {
			/* the analyser on this lattice at row parity k */
			int I0 = k, J0 = (L + k) & 1;
			unsigned ch = m->channel[I0][J0];
			int r0, c0;
			rot(I0, J0, s1, &r0, &c0);
			rc = green_step(&g, (r0 + c0) & 1, 0, &out1);
			for (int I = 0; I < s1 && !rc; I++)
				for (int J = 0; J < s2; J++)
					if (((I + J) & 1) == L) {
						int r, c;
						rot(I, J, s1, &r, &c);
						full[ch][(size_t)I * s2 + J] =
						    clip01(G(&out1, r, c));
					}
		}
		free(g.p);
		free(out1.p);
	}
	/* step 2: each analyser on its lattice, the other lattice's S0/2 elsewhere */
	if (!rc) {
		grid in2, out2;
		if (grid_new(&in2, s1, s2) || grid_new(&out2, s1, s2)) {
			free(in2.p);
			rc = -1;
		}
		double *st = rc ? NULL : malloc(sizeof(double) * n * 4);
		if (!rc && !st)
			rc = -1;
		for (unsigned ch = 0; ch < 4 && !rc; ch++) {
			/* lattice of ch */
			int L = -1;
			for (int I = 0; I < 2; I++)
				for (int J = 0; J < 2; J++)
					if (m->channel[I][J] == ch)
						L = (I + J) & 1;
			for (int I = 0; I < s1; I++)
				for (int J = 0; J < s2; J++) {
					size_t k = (size_t)I * s2 + J;
					if (((I + J) & 1) == L) {
						G(&in2, I, J) = full[ch][k];
					} else { /* the other lattice's two analysers, both filled
						    there */
						unsigned a = m->channel[0][(L + 1) & 1], b = a ^ 2u;
						G(&in2, I, J) = 0.5 * (full[a][k] + full[b][k]);
					}
				}
			rc = green_step(&in2, L, 0, &out2);
			for (size_t k = 0; k < n && !rc; k++)
				st[ch * n + k] = clip01(out2.p[k]);
		}
		/* step 3: MLRI of every channel with the mean of the four as guide */
		if (!rc) {
			for (size_t k = 0; k < n; k++)
				guide[k] = 0.25 *
				           (st[k] + st[n + k] + st[2 * n + k] + st[3 * n + k]) *
				           full_scale;
			rc = pc_dm_mlri_ri(img, guide, width, height, m, full_scale, out);
		}
		free(st);
		free(in2.p);
		free(out2.p);
	}
	free(x);
	free(guide);
	for (int c = 0; c < 4; c++)
		free(full[c]);
	return rc ? pc_error(PC_ENOMEM, "igri2 reference: %ux%u images", width, height) : 0;
}
