/* pan-split (docs/demosaicking.md, Round 17b): the own sample's detail split into a luminance part
 * and a green–magenta part before the ratio step carries it into the other colours.
 *
 * The pan methods (demosaic_pan.c) give every channel q at a pixel p the pixel's own sample times
 * a smooth ratio between q and the own channel o:
 *
 *   I_q(p) + δ = (raw(p) + δ)·R_q(p)/R_o(p) = P̃(p)·R_q(p)·D(p),   D(p) = ρ(p)/R_o(p),
 *
 * ρ = (max(raw, 0) + δ)/P̃ the sample's ratio to the guide P̃ = max(P0, 0) + δ. D is the own
 * sample's detail: the part of it that the guide and the smooth ratio do not explain. On red and
 * blue pixels the own channel has no other sample within the tents' ±3 (its lattice has spacing 4),
 * so R_o(p) = ρ(p) and D = 1; on green pixels the own channel's four diagonal neighbours at (±2,
 * ±2) share the tent, and D is green's detail against them. Every q receives it with green's sign.
 * Where that detail is luminance the other colours share it; where it is green against magenta
 * (hue detail at a period near 4 pixels, to which P0's 5×5 filter responds 0) red and blue move
 * the other way, and the ratio step puts the wrong detail into them (Round 16).
 *
 * The colour layer of a 2×2-block Bayer is a luminance–chrominance modulation (Alleysson,
 * Süsstrunk, Hérault, "Linear demosaicing inspired by the human visual system", IEEE TIP 14(4)
 * 2005, Sec. II; Dubois, "Frequency-domain methods for demosaicking of Bayer-sampled color
 * images", IEEE SPL 12(12) 2005): with s(x) = +1, +1, −1, −1 (period 4, phased so that green
 * blocks have s(x)·s(y) = +1),
 *
 *   raw = Y + s(x)s(y)·C2 + ((s(y) − s(x))/2)·C1 + (the analysers' modulation),
 *   Y = (R + 2G + B)/4,  C2 = (2G − R − B)/4,  C1 = (R − B)/2,
 *
 * so a colour's sample is G = Y + C2, R = Y − C2 + C1, B = Y − C2 − C1. P0 (the 5×5 filter m⊗m,
 * m = [1 2 2 2 1]/8) is the luminance estimate; pan-chroma's demodulated image (χ2 = s(x)s(y) = +1
 * on green, −1 on red and blue; demosaic_pan.c)
 *
 *   Ĉ2 = (χ2·raw) ∗ (m⊗m)
 *
 * the green–magenta chrominance. The analysers' modulation (frequencies with a component 1/2)
 * leaves both (m's response at 1/2 and, after the modulation by χ2, at 1/4 is 0).
 *
 * Derived here: the detail of green and of magenta in one place are h_G = h_Y + h_C and h_M =
 * h_Y − h_C (h_Y, h_C the parts of Y and C2 that the smooth ratio does not follow). If they are
 * uncorrelated with variances σ_Y², σ_C², the least-squares estimate of magenta's detail from
 * green's (and of green's from magenta's) is t·h with
 *
 *   t = Cov(h_M, h_G)/Var(h_G) = (σ_Y² − σ_C²)/(σ_Y² + σ_C²)
 *
 * (t = 1 for pure luminance detail, the pan methods' transfer; −1 for pure green–magenta detail;
 * 0 in noise alone, whose variance P0 and Ĉ2 share: the filters' squared weights are the same).
 * The variances of the detail are not observable (it is finer than both filters); they are
 * taken from the guides' own finest variation, assuming the same luminance-to-chrominance balance
 * at the finer scales. With hp(v)(p) = v(p) − ¼Σ v(p + (±2, ±2)) (the diagonal step of green's
 * lattice; zero on linear ramps, so shading and a hue edge's plateaus do not count),
 *
 *   S_Y(p) = Σ_W hp(P0)²,  S_C(p) = Σ_W hp(Ĉ2)²   over the (2r + 1)² window W at p,
 *   t(p) = max(t_lo, (S_Y − κ·S_C)/(S_Y + κ·S_C))   (1 where S_Y + κ·S_C = 0),
 *
 * κ the chrominance weight (1 in the model), t_lo the lowest transfer (−1 the model's, 0 "green–
 * magenta detail not carried"). The output, on the base's (pan-side's or pan-adapt's reference,
 * O, with its own channel's interpolated ratio R_o):
 *
 *   I_q(p) = (O_q(p) + δ)·(1 + t(p)·(D(p) − 1))/D(p) − δ   for q of the other χ2 class (green vs
 *            red and blue) than the own channel, O_q(p) for the others,
 *
 * with D(p) = (the base's level)/(R_o(p)·P̃(p)): pan-side's level is max(raw(p), 0) + δ (D =
 * ρ(p)/R_o(p)), pan-adapt's its shrunk level O_o(p) + δ. D is then exactly the detail the base
 * carries (O_q + δ = P̃·R_q·D), and t = 1 gives the base (up to rounding); on pan-side's red and
 * blue pixels D = 1 and nothing changes; a uniform colour and polarization has D = 1 everywhere
 * and is exact as the base is. The images are computed on the raw mirrored inside the analyser
 * sub-images (pc_mirror4, as the base's).
 *
 * On pan-adapt (the method's base) the level is shrunk towards its window mean on every pixel, so
 * D ≠ 1 also on red and blue pixels, where it is the shrinkage's smoothing rather than green's
 * detail; the transfer is applied on green pixels only (gonly = 1; Round 17b's form C), and red
 * and blue pixels keep the base's outputs, as they keep pan-side's by D = 1.
 *
 * Two switches keep Round 17b's first form, measured and not chosen: dmode 0 takes D from the
 * plain tents of the own channel's ratios (pan-ratio's, T(d) = (4 − |dx|)(4 − |dy|) over its
 * samples within ±3) instead of the base's R_o; hp 0 takes S_Y and S_C as the variation about
 * the window's mean, Σ_W (v − v̄_W)², instead of the high-pass.
 *
 * Support: the base's, and the window's high-passes at ±(r + 2), their P0 and Ĉ2 the raw's ±2 from
 * there (±(r + 4)); dmode 0's tents ratios at ±3 (P0 ±5).
 */
#include <math.h>
#include <stdlib.h>

#include "demosaic_pan.h"
#include "polarcam/error.h"

#define SPLIT_X                                                                                    \
	12 /* the extended images' margin: P0 and Ĉ2 computed to ±10, the high-passes of the     \
	    * window (r <= 8) read them at ±(r + 2) */

pc_dm_pan_split_params pc_dm_pan_split_defaults(void)
{
	pc_dm_pan_split_params p = {PC_DM_PAN_SPLIT_BASE,
	                            PC_DM_PAN_SPLIT_KAPPA,
	                            PC_DM_PAN_SPLIT_R,
	                            PC_DM_PAN_SPLIT_TLO,
	                            2.0,
	                            -1.0,
	                            PC_DM_PAN_SPLIT_DMODE,
	                            PC_DM_PAN_SPLIT_HP,
	                            PC_DM_PAN_SPLIT_GONLY};
	return p;
}

typedef struct split_img {
	int w, h, W;
	double *p0, *c2, *rho;
	unsigned char *cls; /* the channel 4·k + c of every extended pixel */
} split_img;

static size_t sidx(const split_img *s, int x, int y)
{
	return (size_t)(y + SPLIT_X) * (size_t)s->W + (size_t)(x + SPLIT_X);
}

static double sext(const double *img, int w, int h, int x, int y)
{
	return img[(size_t)pc_mirror4(y, h) * (size_t)w + (size_t)pc_mirror4(x, w)];
}

static unsigned schan(const pc_mosaic *m, int w, int h, int x, int y)
{
	uint32_t xm = (uint32_t)pc_mirror4(x, w), ym = (uint32_t)pc_mirror4(y, h);
	return 4 * (unsigned)(pc_mosaic_color(m, xm, ym) - PC_CFA_R) + pc_mosaic_channel(m, xm, ym);
}

/* P0, Ĉ2, ρ and the channels on the extended raw (the header's formulas) */
static void split_images(const double *img, int w, int h, const pc_mosaic *m, double delta,
                         split_img *s)
{
	static const double mk[5] = {1, 2, 2, 2, 1};
	for (int y = -SPLIT_X; y < h + SPLIT_X; y++)
		for (int x = -SPLIT_X; x < w + SPLIT_X; x++)
			s->cls[sidx(s, x, y)] = (unsigned char)schan(m, w, h, x, y);
	for (int y = -SPLIT_X + 2; y < h + SPLIT_X - 2; y++)
		for (int x = -SPLIT_X + 2; x < w + SPLIT_X - 2; x++) {
			double p0 = 0, c2 = 0;
			for (int j = -2; j <= 2; j++)
				for (int i = -2; i <= 2; i++) {
					double v = mk[i + 2] * mk[j + 2] *
					           sext(img, w, h, x + i, y + j) / 64;
					p0 += v;
					c2 += s->cls[sidx(s, x + i, y + j)] / 4 == 1 ? v : -v;
				}
			size_t a = sidx(s, x, y);
			s->p0[a] = p0;
			s->c2[a] = c2;
			s->rho[a] =
			    (fmax(sext(img, w, h, x, y), 0) + delta) / (fmax(p0, 0) + delta);
		}
}

/* the diagonal lattice step's high-pass of v at (x, y): v − the mean of v at (±2, ±2) */
static double split_hp(const split_img *s, const double *v, int x, int y)
{
	return v[sidx(s, x, y)] - (v[sidx(s, x - 2, y - 2)] + v[sidx(s, x + 2, y - 2)] +
	                           v[sidx(s, x - 2, y + 2)] + v[sidx(s, x + 2, y + 2)]) /
	                              4;
}

/* hp 0: Σ_W (v − v̄_W)²; hp 1: Σ_W hp(v)², over the (2r + 1)² window at (x, y) */
static double split_var(const split_img *s, const double *v, int x, int y, int r, int hp)
{
	if (hp) {
		double sq = 0;
		for (int j = -r; j <= r; j++)
			for (int i = -r; i <= r; i++) {
				double a = split_hp(s, v, x + i, y + j);
				sq += a * a;
			}
		return sq;
	}
	double sum = 0, sq = 0;
	for (int j = -r; j <= r; j++)
		for (int i = -r; i <= r; i++) {
			double a = v[sidx(s, x + i, y + j)];
			sum += a;
			sq += a * a;
		}
	const double n = (double)((2 * r + 1) * (2 * r + 1));
	return fmax(sq - sum * sum / n, 0);
}

/* the transfer t(p) (the header's formula) */
static double split_t(const split_img *s, int x, int y, const pc_dm_pan_split_params *p)
{
	if (p->force >= -1 && p->force <= 1)
		return p->force;
	double sy = split_var(s, s->p0, x, y, p->r, p->hp),
	       sc = p->kappa * split_var(s, s->c2, x, y, p->r, p->hp);
	double t = sy + sc > 0 ? (sy - sc) / (sy + sc) : 1;
	return fmax(p->tlo, t);
}

/* D(p) = ρ(p)/ρ̂(p), ρ̂ the plain tents of the own channel's ratios */
static double split_d(const split_img *s, int x, int y)
{
	const unsigned o = s->cls[sidx(s, x, y)];
	double num = 0, den = 0;
	for (int dy = -3; dy <= 3; dy++)
		for (int dx = -3; dx <= 3; dx++) {
			size_t a = sidx(s, x + dx, y + dy);
			if (s->cls[a] != o)
				continue;
			double t = (4 - abs(dx)) * (4 - abs(dy));
			num += t * s->rho[a];
			den += t;
		}
	return s->rho[sidx(s, x, y)] * den / num;
}

int pc_dm_pan_split_check(const pc_dm_pan_split_params *p)
{
	if ((p->base != 0 && p->base != 1) || !(p->kappa >= 0) || !isfinite(p->kappa) || p->r < 0 ||
	    p->r > PC_DM_PAN_SPLIT_RMAX || !(p->tlo >= -1 && p->tlo <= 1) || !isfinite(p->force) ||
	    !isfinite(p->g) || (p->dmode != 0 && p->dmode != 1) || (p->hp != 0 && p->hp != 1) ||
	    (p->gonly != 0 && p->gonly != 1))
		return pc_error(PC_EINVAL, "pan-split: parameters out of range");
	return 0;
}

int pc_dm_pan_split_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_split_params *p, const pc_fplane *out)
{
	int rc = pc_dm_pan_split_check(p);
	if (rc)
		return rc;
	double *rown = malloc(sizeof(double) * (size_t)w * h);
	if (!rown)
		return pc_error(PC_ENOMEM, "pan-split reference: images of %ux%u", w, h);
	if (p->base) {
		pc_dm_pan_adapt_params pa = pc_dm_pan_adapt_defaults();
		pa.g = p->g;
		rc = pc_dm_pan_adapt_ref_own(img, w, h, m, fs, &pa, out, rown);
	} else {
		rc = pc_dm_pan_side_ref_own(img, w, h, m, fs, out, rown);
	}
	if (rc) {
		free(rown);
		return rc;
	}
	split_img s = {(int)w, (int)h, (int)w + 2 * SPLIT_X, NULL, NULL, NULL, NULL};
	const size_t n = (size_t)s.W * (size_t)(h + 2 * SPLIT_X);
	double *buf = malloc(sizeof(double) * n * 3);
	s.cls = malloc(n);
	if (!buf || !s.cls) {
		free(buf);
		free(s.cls);
		free(rown);
		return pc_error(PC_ENOMEM, "pan-split reference: images of %ux%u", w, h);
	}
	s.p0 = buf;
	s.c2 = buf + n;
	s.rho = buf + 2 * n;
	const double delta = PC_DM_PAN_ADAPT_DFS * fs; /* δ, every pan method's */
	split_images(img, (int)w, (int)h, m, delta, &s);
	for (int y = 0; y < (int)h; y++)
		for (int x = 0; x < (int)w; x++) {
			const size_t at = (size_t)y * w + (size_t)x;
			const unsigned own = s.cls[sidx(&s, x, y)], og = own / 4 == 1;
			const double pt = fmax(s.p0[sidx(&s, x, y)], 0) + delta;
			/* D: the base's own detail, (its level)/(R_own·P̃): pan-side's level is
			 * max(raw, 0) + δ, pan-adapt's its shrunk level O_own + δ */
			const double d =
			    p->dmode == 0 ? split_d(&s, x, y)
			    : p->base     ? ((double)out[own].data[(size_t)y * out[own].row_stride +
                                                               (size_t)x * out[own].pixel_stride] +
                                         delta) /
			                    (rown[at] * pt)
			              : s.rho[sidx(&s, x, y)] / rown[at];
			if (d == 1 || (p->gonly && !og))
				continue; /* no detail carried (pan-side's red and blue pixels) */
			const double t = split_t(&s, x, y, p);
			const double f = (1 + t * (d - 1)) / d;
			for (unsigned q = 0; q < 12; q++) {
				if ((q / 4 == 1) == og)
					continue; /* the same χ2 class: the base's */
				float *o = out[q].data + (size_t)y * out[q].row_stride +
				           (size_t)x * out[q].pixel_stride;
				*o = (float)(((double)*o + delta) * f - delta);
			}
		}
	free(buf);
	free(s.cls);
	free(rown);
	return 0;
}

int pc_dm_pan_split_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out)
{
	pc_dm_pan_split_params p = pc_dm_pan_split_defaults();
	return pc_dm_pan_split_ref_with(img, w, h, m, fs, &p, out);
}
