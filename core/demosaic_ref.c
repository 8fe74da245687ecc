/* The demosaicking ladder's scalar references, in double precision: the specification every
 * fast kernel is tested against. Written for clarity, not speed: per pixel, per channel, with
 * explicit neighbourhoods and mirrored indices.
 *
 * Monochrome mosaic, e.g. Sony IMX250MZR (channel c at (x mod 2, y mod 2)):
 *
 *        x-1   x   x+1
 *   y-1   D    V    D        same (S): the pixel itself
 *   y     H    S    H        H: horizontal pair, V: vertical pair, D: the four diagonals
 *   y+1   D    V    D
 *
 * Each of the four analysers sits at exactly one of S, H, V, D around any pixel, so a 3×3
 * window interpolates every channel. Borders: whole-sample mirror (pc_mirror), which keeps the
 * parity of every index and so the analyser at every mirrored position.
 */
#include "demosaic_ref.h"

#include "demosaic_anchors.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static int rimg_new(pc_dimg *r, int w, int h)
{
	r->w = w;
	r->h = h;
	r->p = calloc((size_t)w * h, sizeof(double));
	return r->p ? 0 : pc_error(PC_ENOMEM, "reference: %dx%d image", w, h);
}

static void rimg_free(pc_dimg *r)
{
	free(r->p);
	r->p = NULL;
}

static double *px(pc_dimg *r, int x, int y)
{
	return &r->p[(size_t)y * r->w + x];
}

static void put(const pc_fplane *o, int x, int y, double v)
{
	o->data[(size_t)y * o->row_stride + (size_t)x * o->pixel_stride] = (float)v;
}

static void ref_bilinear(const pc_dimg *r, const pc_mosaic *m, const pc_fplane *out)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++)
			for (unsigned c = 0; c < 4; c++)
				put(&out[c], x, y, pc_dm_tent(r, m, c, x, y));
}

/* The 2×2 block at even coordinates holds each analyser once. */
static double block_value(const pc_dimg *r, const pc_mosaic *m, unsigned c, int bx, int by)
{
	for (int dy = 0; dy < 2; dy++)
		for (int dx = 0; dx < 2; dx++)
			if (pc_dm_ch(m, bx + dx, by + dy) == c)
				return pc_dimg_at(r, bx + dx, by + dy);
	return 0; /* unreachable for a checked mosaic */
}

static void ref_superpixel(const pc_dimg *r, const pc_mosaic *m, int half, const pc_fplane *out)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			if (half && ((x | y) & 1))
				continue;
			for (unsigned c = 0; c < 4; c++) {
				double v = block_value(r, m, c, x & ~1, y & ~1);
				if (half)
					put(&out[c], x / 2, y / 2, v);
				else
					put(&out[c], x, y, v);
			}
		}
}

/* Keys' cubic convolution kernel with a = -1/2 (R. Keys, IEEE TASSP 29(6) 1981, eq. 15). */
static double keys(double t)
{
	const double a = -0.5;
	t = fabs(t);
	if (t <= 1)
		return (a + 2) * t * t * t - (a + 3) * t * t + 1;
	if (t < 2)
		return a * t * t * t - 5 * a * t * t + 8 * a * t - 4 * a;
	return 0;
}

/* Channel c's samples lie on a lattice of spacing 2; the kernel is evaluated in lattice units,
 * so offsets of 1 and 3 pixels weigh keys(0.5) = 9/16 and keys(1.5) = -1/16. */
static void ref_bicubic(const pc_dimg *r, const pc_mosaic *m, const pc_fplane *out)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++)
			for (unsigned c = 0; c < 4; c++) {
				double s = 0;
				for (int dy = -3; dy <= 3; dy++)
					for (int dx = -3; dx <= 3; dx++)
						if (pc_dm_ch(m, x + dx, y + dy) == c)
							s += keys(dx / 2.0) * keys(dy / 2.0) *
							     pc_dimg_at(r, x + dx, y + dy);
				put(&out[c], x, y, s);
			}
}

/* ---- inter-channel methods ---- */

/* PPID step 1 (Mihoubi et al. 2017, eq. 24 adapted to the 2×2 PFA): the pseudo-panchromatic
 * image as the raw filtered by M = [1 2 1; 2 4 2; 1 2 1]/16, which weighs each analyser by 1/4. */
static void ppi_coarse(const pc_dimg *r, pc_dimg *p0)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			double s = 0;
			for (int dy = -1; dy <= 1; dy++)
				for (int dx = -1; dx <= 1; dx++)
					s += (2 - abs(dx)) * (2 - abs(dy)) *
					     pc_dimg_at(r, x + dx, y + dy);
			*px(p0, x, y) = s / 16;
		}
}

/* PPID step 2 (ibid. eqs. 25-28, adapted): at p, the difference "PPI minus raw" is smooth
 * within a channel, so it is taken from the eight same-channel neighbours q = p + 2d and
 * averaged with edge-aware weights γ_d = 1 / (ε + G_d), where
 *   G_d = |raw(p + 2d) − raw(p)| + |raw(p + d) − raw(p − d)|
 * sums two same-channel differences along direction d and ε = full_scale / 255:
 *   PPI(p) = raw(p) + Σ_d γ_d (PPI0(q_d) − raw(q_d)) / Σ_d γ_d. */
static void ppi_refine(const pc_dimg *r, const pc_dimg *p0, double eps, pc_dimg *p)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			double num = 0, den = 0, c = pc_dimg_at(r, x, y);
			for (int dy = -1; dy <= 1; dy++)
				for (int dx = -1; dx <= 1; dx++) {
					if (!dx && !dy)
						continue;
					double g = fabs(pc_dimg_at(r, x + 2 * dx, y + 2 * dy) - c) +
					           fabs(pc_dimg_at(r, x + dx, y + dy) -
					                pc_dimg_at(r, x - dx, y - dy));
					double gam = 1.0 / (eps + g);
					num += gam * (pc_dimg_at(p0, x + 2 * dx, y + 2 * dy) -
					              pc_dimg_at(r, x + 2 * dx, y + 2 * dy));
					den += gam;
				}
			*px(p, x, y) = c + num / den;
		}
}

/* PPID step 3 (ibid. eqs. 30-31, 34): I_c = PPI + tent-interpolated (raw − PPI) of channel c. */
static int ref_ppid(const pc_dimg *r, const pc_mosaic *m, double fs, const pc_fplane *out)
{
	pc_dimg p0 = {0}, p = {0}, d = {0};
	int rc = rimg_new(&p0, r->w, r->h);
	if (!rc)
		rc = rimg_new(&p, r->w, r->h);
	if (!rc)
		rc = rimg_new(&d, r->w, r->h);
	if (rc) {
		rimg_free(&p0);
		rimg_free(&p);
		return rc;
	}
	ppi_coarse(r, &p0);
	ppi_refine(r, &p0, fs / 255.0, &p);
	for (size_t i = 0; i < (size_t)r->w * r->h; i++)
		d.p[i] = r->p[i] - p.p[i];
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++)
			for (unsigned c = 0; c < 4; c++)
				put(&out[c], x, y, *px(&p, x, y) + pc_dm_tent(&d, m, c, x, y));
	rimg_free(&p0);
	rimg_free(&p);
	rimg_free(&d);
	return 0;
}

/* Edge-aware intensity guide for EARI (after Morimatsu et al. 2020, whose key idea is a guide
 * built from the relation S0 = I_c + I_c⊥ of orthogonal analysers, 0°/90° and 45°/135°; the
 * detector below is ours). Around any pixel p of channel c, the orthogonal channel c⊥ occupies
 * exactly one of the neighbour sets H, V, D of the figure at the top, and the other orthogonal
 * couple occupies the other two. Estimates of S0 at p:
 *   e_axis = raw(p) + mean of c⊥ along one axis of its set (one axis for H or V, the two
 *            diagonals for D), one estimate per axis;
 *   e_other = mean(first set of the other couple) + mean(second set)  (centred on p).
 * Each e_axis weighs 1/(ε + g_axis) with the axis gradient
 *   g = |raw(p+o) − raw(p−o)| + |raw(p+2o) − raw(p)| + |raw(p−2o) − raw(p)|,
 * so the estimate along an edge wins over one across it; e_other weighs 1/(ε + mean g over the
 * four axes). The guide is half the weighted mean (S0/2, the mean analyser intensity, on the
 * scale of every I_c). ε = 0.1 × full scale keeps the weighting mild: sharper weights
 * (1/(ε+g)² or smaller ε) scored lower on both test datasets. */
static void eari_guide(const pc_dimg *r, const pc_mosaic *m, double eps, pc_dimg *g)
{
	/* neighbour sets: H = ±(1,0), V = ±(0,1), D = ±(1,1) and ±(1,-1) */
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			unsigned cp = pc_dm_ch(m, x, y) ^ 2u;
			double c0 = pc_dimg_at(r, x, y);
			double mh = 0.5 * (pc_dimg_at(r, x - 1, y) + pc_dimg_at(r, x + 1, y));
			double mv = 0.5 * (pc_dimg_at(r, x, y - 1) + pc_dimg_at(r, x, y + 1));
			double md =
			    0.25 * (pc_dimg_at(r, x - 1, y - 1) + pc_dimg_at(r, x + 1, y + 1) +
			            pc_dimg_at(r, x + 1, y - 1) + pc_dimg_at(r, x - 1, y + 1));
			/* gradients along the four axes */
			double gax[4];
			static const int ax[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
			for (int k = 0; k < 4; k++) {
				int ox = ax[k][0], oy = ax[k][1];
				gax[k] = fabs(pc_dimg_at(r, x + ox, y + oy) -
				              pc_dimg_at(r, x - ox, y - oy)) +
				         fabs(pc_dimg_at(r, x + 2 * ox, y + 2 * oy) - c0) +
				         fabs(pc_dimg_at(r, x - 2 * ox, y - 2 * oy) - c0);
			}
			double num = 0, den = 0, gmean = 0.25 * (gax[0] + gax[1] + gax[2] + gax[3]);
			double other;
			if (pc_dm_ch(m, x + 1, y + 1) ==
			    cp) { /* orthogonal analyser on the diagonals */
				for (int k = 2; k < 4; k++) {
					int ox = ax[k][0], oy = ax[k][1];
					double e = c0 + 0.5 * (pc_dimg_at(r, x + ox, y + oy) +
					                       pc_dimg_at(r, x - ox, y - oy));
					double wgt = 1.0 / (eps + gax[k]);
					num += wgt * e;
					den += wgt;
				}
				other = mh + mv;
			} else if (pc_dm_ch(m, x + 1, y) == cp) { /* ... on the horizontal pair */
				double wgt = 1.0 / (eps + gax[0]);
				num += wgt * (c0 + mh);
				den += wgt;
				other = mv + md;
			} else { /* ... on the vertical pair */
				double wgt = 1.0 / (eps + gax[1]);
				num += wgt * (c0 + mv);
				den += wgt;
				other = mh + md;
			}
			double wo = 1.0 / (eps + gmean);
			num += wo * other;
			den += wo;
			*px(g, x, y) = 0.5 * num / den;
		}
}

/* Guided filter of He, Sun, Tang (ECCV 2010 / TPAMI 2013, eqs. 7-8) restricted to the samples
 * of channel c (Kiku et al. 2013's residual interpolation): in every (2r+1)² window ω_k, the
 * least-squares fit I_c ≈ a_k·G + b_k over the channel's samples, regularised by eps2:
 *   a_k = cov_k(G, I) / (var_k(G) + eps2),  b_k = mean_k(I) − a_k·mean_k(G);
 * then the tentative image T = mean_ω(a)·G + mean_ω(b). The residual raw − T at the samples is
 * tent-interpolated and added back: I_c = T + tent(raw − T). */
static int ref_ri_channel(const pc_dimg *r, const pc_dimg *g, const pc_mosaic *m, unsigned c,
                          int rad, double eps2, pc_dimg *a, pc_dimg *b, pc_dimg *t,
                          const pc_fplane *out)
{
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			double n = 0, sg = 0, si = 0, sgg = 0, sgi = 0;
			for (int dy = -rad; dy <= rad; dy++)
				for (int dx = -rad; dx <= rad; dx++) {
					if (pc_dm_ch(m, x + dx, y + dy) != c)
						continue;
					double gv = pc_dimg_at(g, x + dx, y + dy),
					       iv = pc_dimg_at(r, x + dx, y + dy);
					n++;
					sg += gv;
					si += iv;
					sgg += gv * gv;
					sgi += gv * iv;
				}
			double mg = sg / n, mi = si / n;
			double var = sgg / n - mg * mg, cov = sgi / n - mg * mi;
			double ak = cov / (var + eps2);
			*px(a, x, y) = ak;
			*px(b, x, y) = mi - ak * mg;
		}
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			double sa = 0, sb = 0;
			for (int dy = -rad; dy <= rad; dy++)
				for (int dx = -rad; dx <= rad; dx++) {
					sa += pc_dimg_at(a, x + dx, y + dy);
					sb += pc_dimg_at(b, x + dx, y + dy);
				}
			double n = (2 * rad + 1) * (2 * rad + 1);
			*px(t, x, y) = sa / n * *px((pc_dimg *)g, x, y) + sb / n;
		}
	/* residual at the samples (the tent reads only channel c's pixels) */
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++)
			*px(a, x, y) = *px((pc_dimg *)r, x, y) - *px(t, x, y);
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++)
			put(&out[c], x, y, *px(t, x, y) + pc_dm_tent(a, m, c, x, y));
	return 0;
}

static int ref_ri(const pc_dimg *r, const pc_mosaic *m, double fs, int edge_aware,
                  const pc_fplane *out)
{
	pc_dimg p0 = {0}, g = {0}, a = {0}, b = {0}, t = {0};
	int rc = rimg_new(&p0, r->w, r->h);
	if (!rc)
		rc = rimg_new(&g, r->w, r->h);
	if (!rc)
		rc = rimg_new(&a, r->w, r->h);
	if (!rc)
		rc = rimg_new(&b, r->w, r->h);
	if (!rc)
		rc = rimg_new(&t, r->w, r->h);
	if (!rc) {
		const pc_ri_params *pr = edge_aware ? &pc_eari_params : &pc_ri_params_default;
		if (edge_aware) {
			eari_guide(r, m, pr->guide_eps * fs, &g);
		} else {
			ppi_coarse(r, &p0);
			ppi_refine(r, &p0, fs / 255.0, &g);
		}
		double e = pr->eps * fs;
		for (int it = 0; it < pr->passes && !rc; it++) {
			if (it) /* refine the guide: the mean analyser intensity S0/2 of the last
			           pass */
				for (int y = 0; y < r->h; y++)
					for (int x = 0; x < r->w; x++) {
						double s = 0;
						for (int c = 0; c < 4; c++)
							s += out[c].data[(size_t)y *
							                     out[c].row_stride +
							                 (size_t)x *
							                     out[c].pixel_stride];
						*px(&g, x, y) = s / 4;
					}
			for (unsigned c = 0; c < 4 && !rc; c++)
				rc =
				    ref_ri_channel(r, &g, m, c, pr->radius, e * e, &a, &b, &t, out);
		}
	}
	rimg_free(&p0);
	rimg_free(&g);
	rimg_free(&a);
	rimg_free(&b);
	rimg_free(&t);
	return rc;
}

/* Ratio interpolation with an edge-aware guide (ours; docs/demosaicking.md). With G the EARI
 * guide (S0/2 estimated from orthogonal analysers, eari_guide) and den = max(G, 0) + δ
 * (δ = full scale / 65536 keeps the ratio finite in the dark), the ratio q = raw/den at every
 * sample is tent-interpolated per channel and multiplied back: I_c = den·tent_c(q), and every
 * pixel keeps its own measurement. This is smooth-hue-transition (Cok 1987) in polarization:
 * I_c/S0 = (1 + DoLP·cos 2(AoLP − θ_c))/2 varies slowly where the intensity has edges. A
 * second pass repeats it with the mean of the first pass's four channels as the guide. */
/* The guided tent of the ratio method: channel c's neighbours of (x, y) in the 3×3 window
 * (the tent's sets: the horizontal pair, the vertical pair or the four diagonals, each with
 * equal tent weights) averaged with weights 1/(e + |g(neighbour) − g(x, y)|), g the pass's
 * guide: across an edge of the guide the far side's ratio, which belongs to another surface,
 * counts little (a joint-bilateral range weight on the guide; Tomasi & Manduchi, ICCV 1998;
 * Kopf et al., SIGGRAPH 2007). */
static double guided_tent(const pc_dimg *v, const pc_dimg *g, const pc_mosaic *m, unsigned c, int x,
                          int y, double e)
{
	double s = 0, ws = 0, g0 = pc_dimg_at(g, x, y);
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++)
			if (pc_dm_ch(m, x + dx, y + dy) == c) {
				double w = 1.0 / (e + fabs(pc_dimg_at(g, x + dx, y + dy) - g0));
				s += w * pc_dimg_at(v, x + dx, y + dy);
				ws += w;
			}
	return s / ws;
}

/* ratio-nr's guide level at (x, y) (ours; docs/demosaicking.md): the guide g shrunk towards
 * its 3×3 mean μ where its 3×3 variance v is of the order of shot noise, as a guided filter
 * shrinks its slope (He, Sun, Tang, TPAMI 2013, eq. 7, with a signal-dependent regulariser):
 * g' = μ + λ·(g − μ), λ = v / (v + k·μ⁺), k the frame's noise gain (the variance of Poisson
 * noise is proportional to the signal; pc_dm_call.noise_gain, Round 40). Written with the
 * differences d_i = g_i − g(x, y): g' = g + (1 − λ)·mean(d), v = mean(d²) − mean(d)²; λ = 1 where v
 * + k·μ⁺ = 0. */
static double shrunk_guide(const pc_dimg *g, int x, int y, double k)
{
	double g0 = pc_dimg_at(g, x, y), sd = 0, sdd = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++) {
			double d = pc_dimg_at(g, x + dx, y + dy) - g0;
			sd += d;
			sdd += d * d;
		}
	double md = sd / 9, v = fmax(sdd / 9 - md * md, 0), kmu = k * fmax(g0 + md, 0);
	double t = v + kmu;
	return t > 0 ? g0 + kmu / t * md : g0;
}

/* ratio-nr's guide where clipping splits the analysers (ours; docs/demosaicking.md, Round 46):
 * at every pixel whose 3 × 3 neighbourhood holds an analyser all of whose samples there are
 * saturated (>= fs, the raw's full scale less the black level) beside one none of whose samples
 * are, the EARI guide g is replaced by the raw's 3 × 3 binomial (ppi_coarse). The EARI guide
 * sums a pixel's sample and its orthogonal neighbours' (S0 = I_c + I_c⊥, eari_guide); where
 * clipping cuts some analysers and not others (a polarized highlight) the sum falls short of S0
 * by an amount that depends on which pair the pixel belongs to, so the guide takes the mosaic's
 * period and the ratios r/g carry it into the other channels (−1.1 dB S0 against bilinear on
 * such a scene without noise). The binomial weighs the four analysers alike at every pixel.
 * Where every analyser is clipped, or each only in part (the edge of a glint), the sums stay
 * comparable and the EARI guide keeps its edges. */
static int saturated_binomial(const pc_dimg *r, const pc_mosaic *m, double fs, pc_dimg *g)
{
	pc_dimg b = {0};
	for (int y = 0; y < r->h; y++)
		for (int x = 0; x < r->w; x++) {
			int n[4] = {0}, ns[4] = {0};
			for (int dy = -1; dy <= 1; dy++)
				for (int dx = -1; dx <= 1; dx++) {
					unsigned c = pc_dm_ch(m, x + dx, y + dy);
					n[c]++;
					ns[c] += pc_dimg_at(r, x + dx, y + dy) >= fs;
				}
			bool all = false, none = false;
			for (int c = 0; c < 4; c++) {
				all |= n[c] > 0 && ns[c] == n[c];
				none |= n[c] > 0 && ns[c] == 0;
			}
			if (!(all && none))
				continue;
			if (!b.p) { /* the binomial, once, at the first such neighbourhood */
				int rc = rimg_new(&b, r->w, r->h);
				if (rc)
					return rc;
				ppi_coarse(r, &b);
			}
			*px(g, x, y) = pc_dimg_at(&b, x, y);
		}
	rimg_free(&b);
	return 0;
}

/* The ratio method's passes into out; *gfin (allocated here, freed by the caller) gets the
 * mean of the last pass's four channels, the guide a further pass would use. nr: ratio-nr with
 * the noise gain k (the multiplier of each pass is the shrunk guide, shrunk_guide). ratio and
 * ratio-nr: two passes from the EARI guide; ratio-nr3 (binomial): three from the raw's 3×3
 * binomial ([1 2 1]ᵀ[1 2 1]/16, ppi_coarse: each analyser 1/4 around every pixel, the mean of
 * the four channels' tents; docs/demosaicking.md, Round 43b). */
static int ratio_passes(const pc_dimg *r, const pc_mosaic *m, double fs, bool nr, double k,
                        bool binomial, const pc_fplane *out, pc_dimg *gfin)
{
	pc_dimg g = {0}, q = {0}, gn = {0};
	int rc = rimg_new(&g, r->w, r->h);
	if (!rc)
		rc = rimg_new(&q, r->w, r->h);
	if (!rc)
		rc = rimg_new(&gn, r->w, r->h);
	if (rc) {
		rimg_free(&g);
		rimg_free(&q);
		return rc;
	}
	/* ratio-nr3: the raw's 3×3 binomial, PPID's coarse pseudo-panchromatic image */
	if (binomial)
		ppi_coarse(r, &g);
	else
		eari_guide(r, m, pc_eari_params.guide_eps * fs, &g);
	if (nr && !binomial) {
		rc = saturated_binomial(r, m, fs, &g);
		if (rc) {
			rimg_free(&g);
			rimg_free(&q);
			rimg_free(&gn);
			return rc;
		}
	}
	const double delta = PC_RATIO_OFFSET * fs, e = PC_RATIO_GUIDE_EPS * fs;
	const int passes = binomial ? PC_RATIO_NR3_PASSES : PC_RATIO_PASSES;
	for (int pass = 0; pass < passes; pass++) {
		for (int y = 0; y < r->h; y++)
			for (int x = 0; x < r->w; x++)
				*px(&q, x, y) = (pc_dimg_at(r, x, y) + delta) /
				                (fmax(pc_dimg_at(&g, x, y), 0) + delta);
		for (int y = 0; y < r->h; y++)
			for (int x = 0; x < r->w; x++) {
				double gx = nr ? shrunk_guide(&g, x, y, k) : pc_dimg_at(&g, x, y);
				double den = fmax(gx, 0) + delta, sum = 0;
				for (unsigned c = 0; c < 4; c++) {
					double v =
					    c == pc_dm_ch(m, x, y)
					        ? pc_dimg_at(r, x, y)
					        : den * guided_tent(&q, &g, m, c, x, y, e) - delta;
					put(&out[c], x, y, v);
					sum += v;
				}
				*px(&gn, x, y) = sum / 4; /* the next pass's guide */
			}
		pc_dimg t = g;
		g = gn;
		gn = t;
	}
	rimg_free(&q);
	rimg_free(&gn);
	*gfin = g;
	return 0;
}

static int ref_ratio(const pc_dimg *r, const pc_mosaic *m, double fs, bool nr, double k,
                     bool binomial, const pc_fplane *out)
{
	pc_dimg g = {0};
	int rc = ratio_passes(r, m, fs, nr, k, binomial, out, &g);
	rimg_free(&g);
	return rc;
}

/* ratio-ri (ours; docs/demosaicking.md): the ratio method R_c, then one residual-interpolation
 * pass (Kiku et al., ICIP 2013: the guided filter of He, Sun, Tang, TPAMI 2013, over each
 * channel's samples, ref_ri_channel) guided by G = the mean of R's four channels, radius 2,
 * regulariser (PC_RATIO_RI_EPS·FS)²: the local linear model I_c ≈ a·G + b holds the ratio
 * model (b = 0) and the difference model (a = 1) as special cases. Where the guide is dark
 * the fit rings across the edges of bright objects (false DoLP of small numbers), so the two
 * are blended by the guide's level against the noise floor d = PC_RATIO_RI_DARK·FS:
 * I_c = w·RI_c + (1 − w)·R_c, w = G⁺²/(G⁺² + d²), G⁺ = max(G, 0). Own samples stay (both
 * keep them). */
static int ref_ratio_ri(const pc_dimg *r, const pc_mosaic *m, double fs, const pc_fplane *out)
{
	const int w = r->w, h = r->h;
	pc_dimg g = {0}, a = {0}, b = {0}, t = {0};
	float *rat = malloc(sizeof(float) * 4 * (size_t)w * (size_t)h);
	if (!rat)
		return pc_error(PC_ENOMEM, "reference: %dx%d image", w, h);
	pc_fplane rp[4];
	for (int c = 0; c < 4; c++)
		rp[c] = (pc_fplane){rat + (size_t)c * w * h, (size_t)w, 1};
	int rc = ratio_passes(r, m, fs, false, 0, false, rp, &g);
	if (!rc)
		rc = rimg_new(&a, w, h);
	if (!rc)
		rc = rimg_new(&b, w, h);
	if (!rc)
		rc = rimg_new(&t, w, h);
	const double e = PC_RATIO_RI_EPS * fs, d = PC_RATIO_RI_DARK * fs;
	for (unsigned c = 0; c < 4 && !rc; c++)
		rc = ref_ri_channel(r, &g, m, c, 2, e * e, &a, &b, &t, out);
	for (int y = 0; y < h && !rc; y++)
		for (int x = 0; x < w; x++) {
			double gp = fmax(*px(&g, x, y), 0), wt = gp * gp / (gp * gp + d * d);
			for (unsigned c = 0; c < 4; c++) {
				float *o = &out[c].data[(size_t)y * out[c].row_stride +
				                        (size_t)x * out[c].pixel_stride];
				*o = c == pc_dm_ch(m, x, y)
				         ? (float)pc_dimg_at(r, x, y)
				         : (float)(wt * *o +
				                   (1 - wt) * rp[c].data[(size_t)y * w + x]);
			}
		}
	free(rat);
	rimg_free(&g);
	rimg_free(&a);
	rimg_free(&b);
	rimg_free(&t);
	return rc;
}

static int ref_method(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
                      pc_demosaic_method method, double full_scale, double noise_gain,
                      const pc_fplane *out)
{
	pc_dimg r = {(double *)img, (int)width, (int)height};
	switch (method) {
	case PC_DM_SUPERPIXEL_HALF:
		if (m->period == 4)
			break;
		ref_superpixel(&r, m, 1, out);
		return 0;
	case PC_DM_SUPERPIXEL:
		if (m->period == 4)
			break;
		ref_superpixel(&r, m, 0, out);
		return 0;
	case PC_DM_BILINEAR:
		ref_bilinear(&r, m, out);
		return 0;
	case PC_DM_BICUBIC:
		ref_bicubic(&r, m, out);
		return 0;
	case PC_DM_PPID:
		return ref_ppid(&r, m, full_scale, out);
	case PC_DM_RI:
		return ref_ri(&r, m, full_scale, 0, out);
	case PC_DM_EARI:
		return ref_ri(&r, m, full_scale, 1, out);
	case PC_DM_RATIO:
		return ref_ratio(&r, m, full_scale, false, 0, false, out);
	case PC_DM_RATIO_NR:
		return ref_ratio(&r, m, full_scale, true, noise_gain, false, out);
	case PC_DM_RATIO_NR3:
		return ref_ratio(&r, m, full_scale, true, noise_gain, true, out);
	case PC_DM_RATIO_RI:
		return ref_ratio_ri(&r, m, full_scale, out);
	case PC_DM_EARI_MLRI:
	case PC_DM_EARI_ROBUST:
		return pc_dm_ref_mlri(img, width, height, m, method, full_scale, out);
	case PC_DM_PCDP:
		return pc_dm_ref_pcdp(img, width, height, m, out);
	case PC_DM_IGRI2:
		return pc_dm_ref_igri2(img, width, height, m, full_scale, out);
	case PC_DM_NEWTON:
		return pc_dm_ref_newton(img, width, height, m, full_scale, out);
	default:
		break;
	}
	return pc_error(PC_ENOTSUP, "demosaicking method %d: no reference for this mosaic",
	                (int)method);
}

int pc_dm_ref(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
              pc_demosaic_method method, double full_scale, double noise_gain, const pc_fplane *out)
{
	int rc = ref_method(img, width, height, m, method, full_scale, noise_gain, out);
	/* the robust methods' overshoot limiter (demosaic_robust.c; the fast paths apply it row
	 * by row) */
	if (!rc && m->period == 2 && pc_dm_limited(method))
		rc = pc_dm_range_limit_ref(img, width, height, m, out);
	return rc;
}

int pc_dm_ref_of_call(const pc_dm_call *call, const pc_fplane *out)
{
	const pc_dm_input *in = call->in;
	const uint32_t w = in->width, h = in->height;
	double *img = malloc(sizeof(double) * (size_t)w * h);
	if (!img)
		return pc_error(PC_ENOMEM, "demosaicking reference: %ux%u image", w, h);
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++)
			img[(size_t)y * w + x] = (double)pc_dm_sample(in, x, y) - in->black_d;
	int rc =
	    pc_dm_ref(img, w, h, call->m, call->method, call->full_scale, call->noise_gain, out);
	free(img);
	return rc;
}
