#include "polarcam/mueller_imaging.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/parallel.h"

/* Pseudo-inverse pieces of an n×4 matrix X (rows) through XᵀX = V·diag(e)·Vᵀ: the Moore–Penrose
 * inverse X⁺ = V·diag(1/e_i, for e_i above the rank threshold)·Vᵀ·Xᵀ (Golub & Van Loan §5.5.2).
 * Returns the rank and the condition number of the determined part; inv_gram = (XᵀX)⁺ and the
 * mask of determined coordinates (unit vectors inside the range). */
static unsigned pinv_setup(const double *X, size_t ld, unsigned n, double inv_gram[4][4],
                           double *cond, unsigned *mask)
{
	static const double zero[4][4];
	double S[4][4] = {{0}}, e[4], V[4][4];
	for (unsigned r = 0; r < n; r++)
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				S[i][j] += X[r * ld + (size_t)i] * X[r * ld + (size_t)j];
	/* real symmetric: the Hermitian solver with a zero imaginary part (V comes out real) */
	double Vi[4][4];
	pc_hermitian4_eig(S, zero, e, V, Vi);
	double emax = fmax(fmax(e[0], e[1]), fmax(e[2], e[3]));
	double emin = INFINITY;
	unsigned rank = 0;
	bool keep[4];
	for (int i = 0; i < 4; i++) {
		keep[i] = e[i] > 1e-12 * emax;
		if (keep[i]) {
			rank++;
			emin = fmin(emin, e[i]);
		}
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double s = 0;
			for (int k = 0; k < 4; k++)
				if (keep[k])
					s += V[i][k] * V[j][k] / e[k];
			inv_gram[i][j] = s;
		}
	*cond = rank ? sqrt(emax / emin) : INFINITY;
	/* coordinate i is determined when the unit vector e_i lies in the kept eigenspace */
	*mask = 0;
	for (int i = 0; i < 4; i++) {
		double proj = 0;
		for (int k = 0; k < 4; k++)
			if (keep[k])
				proj += V[i][k] * V[i][k];
		if (proj > 1 - 1e-9)
			*mask |= 1u << i;
	}
	return rank;
}

int pc_mueller_system_init(pc_mueller_system *s, unsigned n_psg, const double (*psg)[4],
                           unsigned n_psa, const double (*psa)[4][4], const double (*analyser)[4])
{
	memset(s, 0, sizeof *s);
	if (n_psg < 1 || n_psg > PC_MUELLER_MAX_STATES || n_psa < 1 ||
	    n_psa > PC_MUELLER_MAX_STATES)
		return pc_error(PC_EINVAL,
		                "%u generator and %u analyser states: each must be in [1, %d]",
		                n_psg, n_psa, PC_MUELLER_MAX_STATES);
	if (!psg)
		return pc_error(PC_EINVAL, "generator states missing");
	if (!psa && n_psa != 1)
		return pc_error(PC_EINVAL, "%u analyser states but no analyser matrices", n_psa);
	s->n_psg = n_psg;
	s->n_psa = n_psa;
	double ideal[4][4];
	for (int c = 0; c < 4; c++) {
		double th = c * 0.78539816339744830962; /* 45°·c */
		ideal[c][0] = 0.5;
		ideal[c][1] = 0.5 * cos(2 * th);
		ideal[c][2] = 0.5 * sin(2 * th);
		ideal[c][3] = 0;
	}
	const double(*w)[4] = analyser ? analyser : (const double(*)[4])ideal;
	for (unsigned g = 0; g < n_psg; g++)
		for (int i = 0; i < 4; i++) {
			if (!isfinite(psg[g][i]))
				return pc_error(PC_EINVAL,
				                "generator state %u: non-finite Stokes element %d",
				                g, i);
			s->G[i][g] = psg[g][i];
		}
	for (unsigned a = 0; a < n_psa; a++)
		for (int c = 0; c < 4; c++)
			for (int j = 0; j < 4; j++) {
				double v = 0;
				for (int k = 0; k < 4; k++) {
					double p = psa ? psa[a][k][j] : (k == j);
					if (!isfinite(p) || !isfinite(w[c][k]))
						return pc_error(PC_EINVAL,
						                "analyser state %u: non-finite "
						                "element",
						                a);
					v += w[c][k] * p;
				}
				s->A[4 * a + (unsigned)c][j] = v;
			}
	double iA[4][4], iG[4][4];
	unsigned mA, mG;
	/* G⁺ from the rows of Gᵀ */
	double Gt[PC_MUELLER_MAX_STATES][4];
	for (unsigned g = 0; g < n_psg; g++)
		for (int i = 0; i < 4; i++)
			Gt[g][i] = s->G[i][g];
	s->rank_A = pinv_setup(&s->A[0][0], 4, 4 * n_psa, iA, &s->cond_A, &mA);
	s->rank_G = pinv_setup(&Gt[0][0], 4, n_psg, iG, &s->cond_G, &mG);
	if (s->rank_A < 3)
		return pc_error(PC_ENUMERIC,
		                "the analyser states have rank %u: at least 3 needed "
		                "(the 4 mosaic channels alone give 3)",
		                s->rank_A);
	if (s->rank_G < 3)
		return pc_error(PC_ENUMERIC,
		                "the %u generator states have rank %u: at least 3 "
		                "linearly independent Stokes vectors are needed",
		                n_psg, s->rank_G);
	s->cond_W = s->cond_A * s->cond_G;
	/* A⁺ = (AᵀA)⁺Aᵀ (4 × 4n_psa); G⁺ = Gᵀ(GGᵀ)⁺ (n_psg × 4) */
	for (int i = 0; i < 4; i++)
		for (unsigned r = 0; r < 4 * n_psa; r++) {
			double v = 0;
			for (int k = 0; k < 4; k++)
				v += iA[i][k] * s->A[r][k];
			s->Ap[i][r] = v;
		}
	for (unsigned g = 0; g < n_psg; g++)
		for (int l = 0; l < 4; l++) {
			double v = 0;
			for (int k = 0; k < 4; k++)
				v += Gt[g][k] * iG[k][l];
			s->Gp[g][l] = v;
		}
	s->determined = 0;
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++) {
			bool det = (mA >> k & 1) && (mG >> l & 1);
			if (det)
				s->determined |= 1u << (4 * k + l);
			s->noise_gain[k][l] = det ? sqrt(iA[k][k] * iG[l][l]) : NAN;
		}
	return 0;
}

void pc_mueller_solve(const pc_mueller_system *s, const double *I, double M[4][4])
{
	const unsigned R = 4 * s->n_psa;
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++) {
			if (!(s->determined >> (4 * k + l) & 1)) {
				M[k][l] = NAN;
				continue;
			}
			double v = 0;
			for (unsigned g = 0; g < s->n_psg; g++) {
				double t = 0;
				for (unsigned r = 0; r < R; r++) {
					unsigned a = r / 4, c = r % 4;
					t += s->Ap[k][r] * I[(g + s->n_psg * a) * 4 + c];
				}
				v += t * s->Gp[g][l];
			}
			M[k][l] = v;
		}
}

typedef struct acc_ctx {
	const pc_fplane *ch;
	uint32_t width;
	float *M;
	float coef[4][16]; /* [c][4k + l]: Ap[k][4a + c]·Gp[g][l] for this frame */
} acc_ctx;

static void acc_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	const acc_ctx *a = ctx;
	for (uint32_t y = y0; y < y1; y++) {
		const float *p[4];
		for (int c = 0; c < 4; c++)
			p[c] = a->ch[c].data + (size_t)y * a->ch[c].row_stride;
		float *m = a->M + (size_t)y * a->width * 16;
		for (uint32_t x = 0; x < a->width; x++, m += 16) {
			float I0 = p[0][(size_t)x * a->ch[0].pixel_stride];
			float I1 = p[1][(size_t)x * a->ch[1].pixel_stride];
			float I2 = p[2][(size_t)x * a->ch[2].pixel_stride];
			float I3 = p[3][(size_t)x * a->ch[3].pixel_stride];
			for (int kl = 0; kl < 16; kl++)
				m[kl] += a->coef[0][kl] * I0 + a->coef[1][kl] * I1 +
				         a->coef[2][kl] * I2 + a->coef[3][kl] * I3;
		}
	}
}

int pc_mueller_accumulate(const pc_mueller_system *s, unsigned frame, const pc_fplane ch[4],
                          uint32_t width, uint32_t height, int threads, float *M)
{
	if (frame >= s->n_psg * s->n_psa)
		return pc_error(PC_EINVAL, "frame %u: the sequence has %u frames", frame,
		                s->n_psg * s->n_psa);
	for (int c = 0; c < 4; c++)
		if (!ch[c].data)
			return pc_error(PC_EINVAL, "frame %u: analyser image %d missing", frame, c);
	if (!M || width == 0 || height == 0)
		return pc_error(PC_EINVAL, "empty Mueller image");
	unsigned g = frame % s->n_psg, a = frame / s->n_psg;
	acc_ctx ctx = {ch, width, M, {{0}}};
	for (int c = 0; c < 4; c++)
		for (int k = 0; k < 4; k++)
			for (int l = 0; l < 4; l++)
				ctx.coef[c][4 * k + l] =
				    (s->determined >> (4 * k + l) & 1)
				        ? (float)(s->Ap[k][4 * a + (unsigned)c] * s->Gp[g][l])
				        : 0.0f;
	pc_parallel_rows(height, 0, threads, acc_rows, &ctx);
	return 0;
}

void pc_mueller_finish(const pc_mueller_system *s, uint32_t width, uint32_t height, float *M)
{
	if (s->determined == 0xFFFFu)
		return;
	for (size_t i = 0; i < (size_t)width * height; i++)
		for (int kl = 0; kl < 16; kl++)
			if (!(s->determined >> kl & 1))
				M[16 * i + (size_t)kl] = NAN;
}

/* ---- 4×4 from the 3×3 linear block (physics.md §7; derivation in docs/physics-notes.md,
 * "Rebuilding the 4×4 from the 3×3") ----
 *
 * Model of the linear block, with u = (cos α, sin α), v = (−sin α, cos α), w = (cos γ, sin γ),
 * z = (−sin γ, cos γ) (u, v the columns of R_M(θ_o)'s 2×2 block, w, z the rows of R_M(θ_i)'s):
 *     N00 = A + d,  (N10, N20) = B·u,  (N01, N02) = B·w,  L = (N_kl)_{k,l=1,2} = A·u wᵀ + C·v zᵀ.
 * Split L into its conformal and anti-conformal parts, as complex numbers
 *     z_c = (L11 + L22)/2 − i(L12 − L21)/2 = ρ_c e^{i(α−γ)},  ρ_c = (A + C)/2,
 *     z_a = (L11 − L22)/2 + i(L12 + L21)/2 = ρ_a e^{i(α+γ)},  ρ_a = (A − C)/2,
 * (1-based L indices) and write the first column and row as c = B e^{iα}, r = B e^{iγ}. Then
 * ‖N − N_model‖²_F = (N00 − A − d)² + |c − B e^{iα}|² + |r − B e^{iγ}|²
 *                   + 2|z_c − ρ_c e^{i(α−γ)}|² + 2|z_a − ρ_a e^{i(α+γ)}|²,
 * and A² − B² − C² = 4ρ_cρ_a − B² = S². */

static double cmag(double re, double im)
{
	return hypot(re, im);
}

/* Projections of the four complex numbers x_j = cz[j] (c, r, z_c, z_a) on their model phases
 * e^{iα}, e^{iγ}, e^{i(α−γ)}, e^{i(α+γ)}: p_j = Re(x_j e^{−iθ_j}), q_j = Im(x_j e^{−iθ_j}). The
 * last two phases are products of the first two, so one sine and cosine per angle suffice. */
static void rb_project(const double cz[4][2], double al, double ga, double p[4], double q[4])
{
	const double ca = cos(al), sa = sin(al), cg = cos(ga), sg = sin(ga);
	const double e[4][2] = {{ca, sa},
	                        {cg, sg},
	                        {ca * cg + sa * sg, sa * cg - ca * sg},
	                        {ca * cg - sa * sg, sa * cg + ca * sg}};
	for (int j = 0; j < 4; j++) {
		p[j] = cz[j][0] * e[j][0] + cz[j][1] * e[j][1];
		q[j] = cz[j][1] * e[j][0] - cz[j][0] * e[j][1];
	}
}

/* The profiled least-squares objective of the rebuild: for fixed angles the best magnitudes are
 * the projections, B = (p1 + p2)/2, ρ_c = p3, ρ_a = p4, and ‖N − N_model‖² = const − G with
 * G = (p1 + p2)²/2 + 2p3² + 2p4². Returns G and its gradient and Hessian in (α, γ)
 * (∂p_j/∂θ_j = q_j, ∂q_j/∂θ_j = −p_j). */
static double rb_objective(const double cz[4][2], double al, double ga, double grad[2],
                           double hess[3])
{
	double p[4], q[4];
	rb_project(cz, al, ga, p, q);
	double b = p[0] + p[1];
	grad[0] = b * q[0] + 4 * p[2] * q[2] + 4 * p[3] * q[3];
	grad[1] = b * q[1] - 4 * p[2] * q[2] + 4 * p[3] * q[3];
	double t3 = 4 * (q[2] * q[2] - p[2] * p[2]), t4 = 4 * (q[3] * q[3] - p[3] * p[3]);
	hess[0] = q[0] * q[0] - b * p[0] + t3 + t4; /* ∂²/∂α² */
	hess[1] = q[0] * q[1] - t3 + t4;            /* ∂²/∂α∂γ */
	hess[2] = q[1] * q[1] - b * p[1] + t3 + t4; /* ∂²/∂γ² */
	return 0.5 * b * b + 2 * (p[2] * p[2] + p[3] * p[3]);
}

/* Branch (α + fa·π, γ + fg·π): the projections change sign as e^{iα} → −e^{iα} and
 * e^{iγ} → −e^{iγ} do. */
static void rb_flip(const double p[4], int fa, int fg, double pf[4])
{
	double sa = fa ? -1 : 1, sg = fg ? -1 : 1;
	pf[0] = sa * p[0];
	pf[1] = sg * p[1];
	pf[2] = sa * sg * p[2];
	pf[3] = sa * sg * p[3];
}

/* Misfit ‖N − N_model‖² (without N00) of a branch with the magnitudes constrained to ≥ 0:
 * Σ w_j |x_j − m_j e^{iθ_j}|² = Σ w_j (|x_j|² − 2 m_j p_j + m_j²), w = (1, 1, 2, 2). */
static double rb_misfit(const double cz[4][2], const double p[4])
{
	const double b = fmax(0, 0.5 * (p[0] + p[1]));
	const double m[4] = {b, b, fmax(0, p[2]), fmax(0, p[3])};
	double f = 0;
	for (int j = 0; j < 4; j++)
		f += (j < 2 ? 1 : 2) *
		     (cz[j][0] * cz[j][0] + cz[j][1] * cz[j][1] - 2 * m[j] * p[j] + m[j] * m[j]);
	return fmax(0, f);
}

/* From a start (α, γ): Newton steps on the profiled objective, then the branch (α and γ are
 * known modulo π from G) with the smallest constrained misfit, which it returns. */
static double rb_refine(const double cz[4][2], double a0, double g0, double *al, double *ga)
{
	/* α and γ of a start may be known modulo π only: begin on the branch whose projections
	 * B, ρ_c, ρ_a are largest (all ≥ 0 for a member of the family); G is not invariant
	 * under a flip of α or γ alone */
	double p[4], q[4], pf[4], best_score = -INFINITY;
	int ba = 0, bg = 0;
	rb_project(cz, a0, g0, p, q);
	for (int fa = 0; fa < 2; fa++)
		for (int fg = 0; fg < 2; fg++) {
			rb_flip(p, fa, fg, pf);
			double score = pf[0] + pf[1] + 2 * (pf[2] + pf[3]);
			if (score > best_score) {
				best_score = score;
				ba = fa;
				bg = fg;
			}
		}
	double a = a0 + ba * PC_PI, g = g0 + bg * PC_PI, gr[2], h[3];
	double G0 = rb_objective(cz, a, g, gr, h);
	for (int it = 0; it < 20; it++) {
		double det = h[0] * h[2] - h[1] * h[1];
		if (!(h[0] < 0 && det > 1e-24)) /* not in a maximum's basin, or a degenerate one */
			break;
		double da = -(h[2] * gr[0] - h[1] * gr[1]) / det;
		double dg = -(h[0] * gr[1] - h[1] * gr[0]) / det;
		double step = 1, G1 = -INFINITY, gr1[2], h1[3];
		for (int k = 0; k < 8; k++, step *= 0.5) {
			G1 = rb_objective(cz, a + step * da, g + step * dg, gr1, h1);
			if (G1 >= G0)
				break;
		}
		if (!(G1 >= G0))
			break;
		a += step * da;
		g += step * dg;
		G0 = G1;
		memcpy(gr, gr1, sizeof gr);
		memcpy(h, h1, sizeof h);
		if (fabs(step * da) + fabs(step * dg) < 1e-13)
			break;
	}
	double best = INFINITY;
	rb_project(cz, a, g, p, q);
	ba = bg = 0;
	for (int fa = 0; fa < 2; fa++)
		for (int fg = 0; fg < 2; fg++) {
			rb_flip(p, fa, fg, pf);
			double f = rb_misfit(cz, pf);
			if (f < best) {
				best = f;
				ba = fa;
				bg = fg;
			}
		}
	*al = remainder(a + ba * PC_PI, 2 * PC_PI);
	*ga = remainder(g + bg * PC_PI, 2 * PC_PI);
	return best;
}

int pc_mueller_rebuild_from_linear(const double N[3][3], pc_rebuild_sign sign, double tol,
                                   double M[4][4], pc_rebuild_info *info)
{
	pc_rebuild_info tmp;
	pc_rebuild_info *in = info ? info : &tmp;
	memset(in, 0, sizeof *in);
	if (sign != PC_REBUILD_CONVENTION && sign != PC_REBUILD_PLUS && sign != PC_REBUILD_MINUS)
		return pc_error(PC_EINVAL, "rebuild sign %d: expected convention, plus or minus",
		                (int)sign);
	if (!(tol >= 0) || !isfinite(tol))
		return pc_error(PC_EINVAL, "rebuild tolerance %g: must be finite and ≥ 0", tol);
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 3; l++)
			if (!isfinite(N[k][l]))
				return pc_error(
				    PC_EINVAL, "linear block element (%d, %d) is not finite", k, l);
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++)
			M[k][l] = k < 3 && l < 3 ? N[k][l] : NAN;
	const double m00 = N[0][0];
	if (!(m00 > 0)) {
		in->A = in->B = in->C = in->S = in->d = in->alpha = in->gamma = NAN;
		in->residual = in->excess = NAN;
		in->flags = PC_RB_ZERO;
		return 0;
	}
	/* work on n = N/N00 (pBRDF blocks off the lobe reach 1e-300: squares would underflow) */
	double n[3][3];
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 3; l++)
			n[k][l] = N[k][l] / m00;
	const double c_re = n[1][0], c_im = n[2][0], r_re = n[0][1], r_im = n[0][2];
	const double zc_re = 0.5 * (n[1][1] + n[2][2]), zc_im = -0.5 * (n[1][2] - n[2][1]);
	const double za_re = 0.5 * (n[1][1] - n[2][2]), za_im = 0.5 * (n[1][2] + n[2][1]);

	const double cz[4][2] = {{c_re, c_im}, {r_re, r_im}, {zc_re, zc_im}, {za_re, za_im}};
	/* Starting angles. (1) 2α from c² and z_c z_a, 2γ from r² and z_a z̄_c: both terms of each
	 * pair have the phase 2α (2γ) in the model, so any positive weighting is exact for members
	 * of the family; the factor 4 weights them like their shares of the Frobenius misfit
	 * (|c|² ~ B², 4|z_c z_a| ~ (A + C)(A − C)). (2) α, γ from c and r alone; (3) from z_a and
	 * z_c alone. With noise the least-squares optimum can lie in the basin of any of them
	 * (e.g. near normal incidence, where A + C and B are small), so all are refined and the
	 * best fit kept. */
	double starts[3][2];
	int nstart = 0;
	const double tiny = 1e-28; /* below this a phase is rounding noise */
	double ea_re = c_re * c_re - c_im * c_im + 4 * (zc_re * za_re - zc_im * za_im);
	double ea_im = 2 * c_re * c_im + 4 * (zc_re * za_im + zc_im * za_re);
	double eg_re = r_re * r_re - r_im * r_im + 4 * (za_re * zc_re + za_im * zc_im);
	double eg_im = 2 * r_re * r_im + 4 * (za_im * zc_re - za_re * zc_im);
	double mzc = cmag(zc_re, zc_im), mza = cmag(za_re, za_im);
	if (cmag(ea_re, ea_im) > tiny && cmag(eg_re, eg_im) > tiny) {
		starts[nstart][0] = 0.5 * atan2(ea_im, ea_re);
		starts[nstart++][1] = 0.5 * atan2(eg_im, eg_re);
	}
	if (cmag(c_re, c_im) > tiny && cmag(r_re, r_im) > tiny) {
		starts[nstart][0] = atan2(c_im, c_re);
		starts[nstart++][1] = atan2(r_im, r_re);
	}
	if (mzc > tiny && mza > tiny) {
		double ps = atan2(za_im, za_re), pd = atan2(zc_im, zc_re);
		starts[nstart][0] = 0.5 * (ps + pd);
		starts[nstart++][1] = 0.5 * (ps - pd);
	}
	if (nstart == 0) {
		/* B = 0 and ρ_c or ρ_a = 0 (normal incidence: only α + γ matters; A = C, an
		 * isotropic part: only α − γ matters) */
		double ph = mza >= mzc ? atan2(za_im, za_re) : atan2(zc_im, zc_re);
		starts[0][0] = 0.5 * ph;
		starts[0][1] = mza >= mzc ? 0.5 * ph : -0.5 * ph;
		nstart = 1;
	}
	double alpha = 0, gamma = 0, best_f = INFINITY;
	for (int st = 0; st < nstart; st++) {
		/* starts that coincide modulo π (always, for members of the family) run once */
		bool seen = false;
		for (int q = 0; q < st; q++)
			seen =
			    seen || (fabs(remainder(starts[st][0] - starts[q][0], PC_PI)) < 1e-9 &&
			             fabs(remainder(starts[st][1] - starts[q][1], PC_PI)) < 1e-9);
		if (seen)
			continue;
		double a = 0, g = 0;
		double f = rb_refine(cz, starts[st][0], starts[st][1], &a, &g);
		if (f < best_f) {
			best_f = f;
			alpha = a;
			gamma = g;
		}
	}
	const double ca = cos(alpha), sa = sin(alpha), cg = cos(gamma), sg = sin(gamma);
	const double cd = cos(alpha - gamma), sd = sin(alpha - gamma);
	const double cs = cos(alpha + gamma), ss = sin(alpha + gamma);
	/* least-squares magnitudes for these angles, constrained to ≥ 0 */
	double B = fmax(0, 0.5 * ((c_re * ca + c_im * sa) + (r_re * cg + r_im * sg)));
	double rho_c = fmax(0, zc_re * cd + zc_im * sd);
	double rho_a = fmax(0, za_re * cs + za_im * ss);
	double A = rho_c + rho_a, C = rho_c - rho_a, d = 1 - A;
	/* the misfit, entry by entry (the complex form above is the same sum) */
	double u[2] = {ca, sa}, v[2] = {-sa, ca}, w[2] = {cg, sg}, z[2] = {-sg, cg};
	double fit[3][3];
	fit[0][0] = 1;
	for (int k = 0; k < 2; k++) {
		fit[k + 1][0] = B * u[k];
		fit[0][k + 1] = B * w[k];
		for (int l = 0; l < 2; l++)
			fit[k + 1][l + 1] = A * u[k] * w[l] + C * v[k] * z[l];
	}
	double res2 = 0;
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 3; l++)
			res2 += (n[k][l] - fit[k][l]) * (n[k][l] - fit[k][l]);
	double s2 = 4 * rho_c * rho_a - B * B;
	in->A = A * m00;
	in->B = B * m00;
	in->C = C * m00;
	in->d = d * m00;
	in->alpha = alpha;
	in->gamma = gamma;
	in->residual = sqrt(res2);
	in->excess = hypot(B, C) - A;
	unsigned fl = 0;
	if (in->residual > tol)
		fl |= PC_RB_INCONSISTENT;
	if (in->excess > tol || d < -tol)
		fl |= PC_RB_NONPHYSICAL;
	/* rounding leaves |s2| ~ 1e-16 where S = 0 (dielectrics, β = 0): that is not a clamp,
	 * and S below sqrt of it (~1e-8) is zero to working accuracy */
	const double s2_round = 64 * DBL_EPSILON * fmax(1, A * A);
	if (s2 < -s2_round)
		fl |= PC_RB_CLAMPED;
	double S = sqrt(fmax(0, s2));
	if (s2 <= tol * tol + s2_round)
		fl |= PC_RB_S_ZERO;
	else if (B <= tol)
		fl |= PC_RB_SIGN_UNDEFINED;
	/* k ≥ 0 gives Im(r_s r_p*) ≤ 0 (docs/physics-notes.md): CONVENTION is MINUS */
	if (sign != PC_REBUILD_PLUS)
		S = -S;
	S *= m00;
	C *= m00;
	in->S = S;
	in->flags = fl;
	if (fl & PC_RB_REJECTED)
		return 0;
	M[0][3] = M[3][0] = 0;
	M[3][3] = C;
	for (int k = 0; k < 2; k++) {
		M[k + 1][3] = S * v[k];
		M[3][k + 1] = -S * z[k];
	}
	return 0;
}

int pc_rebuild_sign_from_name(const char *name, pc_rebuild_sign *out)
{
	static const struct {
		const char *name;
		pc_rebuild_sign sign;
	} tab[] = {{"convention", PC_REBUILD_CONVENTION},
	           {"+", PC_REBUILD_PLUS},
	           {"plus", PC_REBUILD_PLUS},
	           {"-", PC_REBUILD_MINUS},
	           {"minus", PC_REBUILD_MINUS},
	           {"off", PC_REBUILD_OFF}};
	for (size_t i = 0; name && i < sizeof tab / sizeof tab[0]; i++)
		if (!strcmp(name, tab[i].name)) {
			*out = tab[i].sign;
			return 0;
		}
	return pc_error(PC_EINVAL, "'%s': expected convention, +, - or off",
	                name ? name : "(null)");
}

const char *pc_rebuild_sign_name(pc_rebuild_sign sign)
{
	switch (sign) {
	case PC_REBUILD_OFF:
		return "off";
	case PC_REBUILD_CONVENTION:
		return "convention";
	case PC_REBUILD_PLUS:
		return "+";
	case PC_REBUILD_MINUS:
		return "-";
	}
	return "?";
}

/* ---- Lu–Chipman maps of a Mueller image ---- */

typedef struct lc_ctx {
	const float *M;
	float *Mw; /* = M when the rebuild writes the circular entries back, else NULL */
	float *D, *R, *Delta, *residual;
	uint32_t width;
	unsigned determined;
	const pc_rebuild_opts *rb;       /* non-NULL: rebuild the circular entries from the 3×3 */
	long singular, nonphysical, bad; /* counted per band, summed under a lock-free atomic */
	long rb_rejected, rb_undefined;
} lc_ctx;

/* the 3×3 linear block: bits 4k + l, k, l < 3 */
#define PC_LINEAR_BLOCK 0x777u

bool pc_mueller_rebuild_applies(const pc_rebuild_opts *rb, unsigned determined)
{
	return rb && rb->sign != PC_REBUILD_OFF && determined != 0xFFFFu &&
	       (determined & PC_LINEAR_BLOCK) == PC_LINEAR_BLOCK;
}

static void lc_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	/* chunks of a row through the batched Lu–Chipman kernel (bit-identical to
	 * pc_lu_chipman_decompose with PC_LC_FILTER | PC_LC_NO_FACTORS per pixel) */
	enum { CH = 256 };
	lc_ctx *c = ctx;
	long singular = 0, nonphys = 0, bad = 0, rejected = 0, undefined = 0;
	double Mb[16 * CH], D[CH], R[CH], De[CH];
	unsigned fl[CH];
	const pc_lc_map out = {D, {NULL, NULL, NULL}, R, {NULL, NULL, NULL}, NULL, NULL, De, NULL,
	                       fl};
	for (uint32_t y = y0; y < y1; y++)
		for (uint32_t x0 = 0; x0 < c->width; x0 += CH) {
			size_t n = c->width - x0 < CH ? c->width - x0 : CH;
			size_t i0 = (size_t)y * c->width + x0;
			if (c->determined != 0xFFFFu && !c->rb) {
				for (size_t j = 0; j < n; j++)
					c->D[i0 + j] = c->R[i0 + j] = c->Delta[i0 + j] = NAN;
				continue;
			}
			for (size_t k = 0; k < 16 * n; k++)
				Mb[k] = c->M[16 * i0 + k];
			if (c->rb) {
				/* physics.md §7: the 4×4 of the pBRDF family from its 3×3 */
				for (size_t j = 0; j < n; j++) {
					double N[3][3], R4[4][4];
					const float *m = c->M + 16 * (i0 + j);
					float *mw = c->Mw ? c->Mw + 16 * (i0 + j) : NULL;
					pc_rebuild_info in;
					for (int k = 0; k < 3; k++)
						for (int l = 0; l < 3; l++)
							N[k][l] = m[4 * k + l];
					if (pc_mueller_rebuild_from_linear(N, c->rb->sign,
					                                   c->rb->tol, R4, &in)) {
						in.flags = PC_RB_ZERO; /* non-finite input */
						in.residual = NAN;
						for (int k = 0; k < 4; k++)
							for (int l = 0; l < 4; l++)
								R4[k][l] = NAN;
					}
					if (c->residual)
						c->residual[i0 + j] = (float)in.residual;
					/* M00 ≤ 0 (background, shadow) is no rejection: nothing
					 * was there to rebuild */
					rejected += (in.flags &
					             (PC_RB_INCONSISTENT | PC_RB_NONPHYSICAL)) != 0;
					undefined += (in.flags & PC_RB_SIGN_UNDEFINED) != 0;
					for (int k = 0; k < 4; k++)
						for (int l = 0; l < 4; l++) {
							Mb[16 * j + 4 * (size_t)k + (size_t)l] =
							    R4[k][l];
							if (mw && (k == 3 || l == 3))
								mw[4 * k + l] = (float)R4[k][l];
						}
				}
			}
			if (pc_lu_chipman_map(Mb, n, PC_LC_FILTER | PC_LC_NO_FACTORS, &out)) {
				for (size_t j = 0; j < n; j++)
					c->D[i0 + j] = c->R[i0 + j] = c->Delta[i0 + j] = NAN;
				bad += (long)n;
				continue;
			}
			for (size_t j = 0; j < n; j++) {
				size_t i = i0 + j;
				if (fl[j] & PC_LC_NONFINITE) {
					c->D[i] = c->R[i] = c->Delta[i] = NAN;
					bad++;
					continue;
				}
				c->D[i] = (float)D[j];
				c->R[i] = (float)R[j];
				c->Delta[i] = (float)De[j];
				singular += (fl[j] & (PC_LC_D_SINGULAR | PC_LC_ZERO_M00)) != 0;
				/* not physical: rejected by the check, or M00 ≤ 0 (never checked)
				 */
				nonphys += (fl[j] & (PC_LC_NONPHYSICAL | PC_LC_ZERO_M00)) != 0;
			}
		}
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->singular += singular;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->nonphysical += nonphys;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->bad += bad;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->rb_rejected += rejected;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->rb_undefined += undefined;
}

void pc_mueller_maps_rebuild(float *M, uint32_t width, uint32_t height, unsigned determined,
                             const pc_rebuild_opts *rb, int threads, float *D, float *R,
                             float *Delta, float *residual, long counts[3], long rb_counts[2])
{
	bool use = pc_mueller_rebuild_applies(rb, determined);
	lc_ctx lc = {M, M, D, R, Delta, use ? residual : NULL, width, determined, use ? rb : NULL,
	             0, 0, 0, 0, 0};
	pc_parallel_rows(height, 0, threads, lc_rows, &lc);
	if (counts) {
		counts[0] = lc.singular;
		counts[1] = lc.nonphysical;
		counts[2] = lc.bad;
	}
	if (rb_counts) {
		rb_counts[0] = lc.rb_rejected;
		rb_counts[1] = lc.rb_undefined;
	}
}

void pc_mueller_maps(const float *M, uint32_t width, uint32_t height, unsigned determined,
                     int threads, float *D, float *R, float *Delta, long counts[3])
{
	lc_ctx lc = {M, NULL, D, R, Delta, NULL, width, determined, NULL, 0, 0, 0, 0, 0};
	pc_parallel_rows(height, 0, threads, lc_rows, &lc);
	if (counts) {
		counts[0] = lc.singular;
		counts[1] = lc.nonphysical;
		counts[2] = lc.bad;
	}
}

void pc_mueller_result_free(pc_mueller_result *res)
{
	free(res->M);
	free(res->maps);
	free(res->residual);
	free(res->valid);
	res->M = res->maps = res->residual = NULL;
	res->valid = NULL;
}

struct pc_mueller_run {
	pc_mueller_system sys;
	pc_mosaic mosaic;
	pc_mueller_run_opts o;
	unsigned next;         /* the frame expected next */
	uint32_t W, H, ow, oh; /* raw and demosaicked size (from frame 0) */
	float *M, *planes;
	uint8_t *valid, *fvalid; /* over all frames, of the current frame (levels checked) */
	double sat;              /* resolved from frame 0 */
	long invalid;
};

int pc_mueller_run_new(const pc_mueller_system *sys, const pc_mosaic *mosaic,
                       const pc_mueller_run_opts *opts, pc_mueller_run **out)
{
	*out = NULL;
	if (!sys || !mosaic || !opts)
		return pc_error(PC_EINVAL, "Mueller imaging: missing argument");
	if (mosaic->period != 2) {
		char lay[64];
		pc_mosaic_format(mosaic, lay, sizeof lay);
		return pc_error(PC_EINVAL,
		                "colour-polarization mosaics are not supported by Mueller "
		                "imaging yet (layout %s)",
		                lay);
	}
	pc_mueller_run *r = calloc(1, sizeof *r);
	if (!r)
		return pc_error(PC_ENOMEM, "Mueller imaging");
	r->sys = *sys;
	r->mosaic = *mosaic;
	r->o = *opts;
	*out = r;
	return 0;
}

void pc_mueller_run_free(pc_mueller_run *run)
{
	if (!run)
		return;
	free(run->M);
	free(run->planes);
	free(run->valid);
	free(run->fvalid);
	free(run);
}

int pc_mueller_run_add(pc_mueller_run *r, unsigned frame, const pc_view *raw)
{
	const unsigned nframes = r->sys.n_psg * r->sys.n_psa;
	if (frame != r->next || frame >= nframes)
		return pc_error(PC_EINVAL,
		                "Mueller imaging: frame %u given, frame %u of %u expected", frame,
		                r->next, nframes);
	if (frame == 0) {
		r->W = raw->width;
		r->H = raw->height;
		pc_demosaic_out_size(r->o.method, r->W, r->H, &r->ow, &r->oh);
		r->M = calloc((size_t)r->ow * r->oh * 16, sizeof *r->M);
		r->planes = malloc((size_t)r->ow * r->oh * 4 * sizeof *r->planes);
		if (!r->M || !r->planes)
			return pc_error(PC_ENOMEM, "Mueller images of %ux%u", r->ow, r->oh);
		const pc_format_info *fi = pc_format_info_get(raw->format);
		r->sat = r->o.saturation_level > 0 ? r->o.saturation_level
		         : r->o.saturation_level < 0 || !fi || fi->is_float
		             ? 0
		             : (double)((1u << fi->bits) - 1u);
		if (r->sat > 0 || r->o.dead_level > 0) {
			r->valid = malloc((size_t)r->ow * r->oh);
			r->fvalid = malloc((size_t)r->ow * r->oh);
			if (!r->valid || !r->fvalid)
				return pc_error(PC_ENOMEM, "validity of %ux%u", r->ow, r->oh);
			memset(r->valid, 1, (size_t)r->ow * r->oh);
		}
	} else if (raw->width != r->W || raw->height != r->H) {
		return pc_error(PC_EINVAL, "frame %u is %ux%u, frame 0 is %ux%u", frame, raw->width,
		                raw->height, r->W, r->H);
	}
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = r->o.method;
	po.mosaic = r->mosaic;
	po.threads = r->o.threads;
	po.saturation_level = r->sat;
	po.dead_level = r->o.dead_level > 0 ? r->o.dead_level : 0;
	pc_validity fv = {r->fvalid, r->ow, 0};
	pc_fplane pl[4];
	pc_fplanes_separate(r->planes, r->ow, r->oh, 4, pl);
	int rc = pc_demosaic_run(raw, &po, pl, r->valid ? &fv : NULL);
	if (rc)
		return pc_error_prefix(rc, "frame %u: ", frame);
	for (size_t k = 0; r->valid && fv.n_invalid && k < (size_t)r->ow * r->oh; k++)
		r->valid[k] &= r->fvalid[k];
	if (r->o.black_level != 0)
		for (size_t k = 0; k < (size_t)r->ow * r->oh * 4; k++)
			r->planes[k] -= (float)r->o.black_level;
	if ((rc = pc_mueller_accumulate(&r->sys, frame, pl, r->ow, r->oh, r->o.threads, r->M)))
		return rc;
	r->next++;
	return 0;
}

int pc_mueller_run_finish(pc_mueller_run *r, pc_mueller_result *res)
{
	memset(res, 0, sizeof *res);
	const unsigned nframes = r->sys.n_psg * r->sys.n_psa;
	if (r->next != nframes)
		return pc_error(PC_EINVAL, "Mueller imaging: %u of %u frames added", r->next,
		                nframes);
	res->sys = r->sys;
	const uint32_t ow = r->ow, oh = r->oh;
	pc_mueller_finish(&r->sys, ow, oh, r->M);
	free(r->planes);
	r->planes = NULL;
	res->M = r->M;
	r->M = NULL;
	size_t np = (size_t)ow * oh;
	res->maps = malloc(np * 3 * sizeof *res->maps);
	if (!res->maps) {
		pc_mueller_result_free(res);
		return pc_error(PC_ENOMEM, "decomposition maps");
	}
	long counts[3], rbc[2] = {0, 0};
	const pc_rebuild_opts *rb = &r->o.rebuild;
	res->rebuilt = pc_mueller_rebuild_applies(rb, res->sys.determined);
	if (res->rebuilt && !(res->residual = malloc(np * sizeof *res->residual))) {
		pc_mueller_result_free(res);
		return pc_error(PC_ENOMEM, "rebuild residual map");
	}
	pc_mueller_maps_rebuild(res->M, ow, oh, res->sys.determined, rb, r->o.threads, res->maps,
	                        res->maps + np, res->maps + 2 * np, res->residual, counts, rbc);
	res->singular = counts[0];
	res->nonphysical = counts[1];
	res->bad = counts[2];
	res->rb_rejected = rbc[0];
	res->rb_sign_undefined = rbc[1];
	res->width = ow;
	res->height = oh;
	res->saturation_level = r->sat;
	res->valid = r->valid;
	r->valid = NULL;
	for (size_t k = 0; res->valid && k < np; k++)
		res->invalid += !res->valid[k];
	return 0;
}
