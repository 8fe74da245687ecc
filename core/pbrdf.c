/* The corrected microfacet polarized BRDF (docs/physics.md §2, hard cases §4, ρ^s quadrature §5).
 *
 * Conventions (physics.md §1): k_i points from the surface towards the source, k_r towards the
 * viewer, +z is the macro normal; propagation directions d_i = −k_i, d_r = k_r; s-vectors
 * s = unit(d × N), p = d × s. ñ = n − ik. σ is the rms slope per axis. f is in sr⁻¹.
 */
#include "polarcam/pbrdf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/optics.h"

#define PC_RHO_MAX_ORDER 1024

struct pc_pbrdf {
	pc_material m;
	unsigned flags;
	double eps_re, eps_im; /* ñ² */
	double inv_2s2;        /* 1/(2σ²) */
	double norm;           /* 1/(8πσ²), physics.md §2 corrected P_D */
	int ntab;              /* nodes of the cosθ_i table (0: none) */
	double *gl_x, *gl_w; /* Gauss–Legendre nodes/weights of order m.rho_order on [−1, 1] */
	double *tab;         /* y(cosθ_i) at ntab uniform nodes on [0, 1] */
	                     /* storage follows */
};

/* ---------------------------------------------------------------------------------------- */
/* small vector helpers */

static inline void pc_cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double pc_dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Gauss–Legendre nodes and weights of order N on [−1, 1]: Newton iteration on P_N from the
 * usual cosine initial guesses, P_N and P_{N−1} by the three-term recurrence. */
static void pc_legendre(int N, double z, double *pn, double *dpn)
{
	double p0 = 1, p1 = z;
	for (int l = 2; l <= N; l++) {
		double p2 = ((2 * l - 1) * z * p1 - (l - 1) * p0) / l;
		p0 = p1;
		p1 = p2;
	}
	*pn = p1;
	*dpn = N * (z * p1 - p0) / (z * z - 1);
}

static void pc_gauss_legendre(int N, double *x, double *w)
{
	for (int i = 0; i < (N + 1) / 2; i++) {
		double z = cos(PC_PI * (i + 0.75) / (N + 0.5)), pn, dp;
		for (int it = 0; it < 100; it++) {
			pc_legendre(N, z, &pn, &dp);
			double dz = pn / dp;
			z -= dz;
			if (fabs(dz) <= 1e-16)
				break;
		}
		pc_legendre(N, z, &pn, &dp);
		x[i] = -z;
		x[N - 1 - i] = z;
		w[i] = w[N - 1 - i] = 2 / ((1 - z * z) * dp * dp);
	}
	if (N % 2)
		x[N / 2] = 0;
}

/* Facet Fresnel parameters (a, b, c, s) at local incidence β (physics.md §2). */
static inline void pc_facet_abcs(const pc_pbrdf *p, double cos_b, double sin2_b, double abcs[4])
{
	pc_fresnel r;
	pc_fresnel_eval(p->m.n, p->m.k, cos_b, sin2_b, &r);
	pc_fresnel_abcs(&r, abcs);
}

/* The same as abcs·2^e2, for a matrix that scales them: r_s and r_p are accurate down to any
 * size (docs/physics-notes.md, "Fresnel far from |ñ| = 1"), but their products a, b, c, s fall
 * below the normal range where |r| < 2^-511 (ñ within about 1e-154 of 1), and a subnormal keeps
 * only its absolute precision 2^-1074: a = 2.5e-321 (k = 1e-160 at normal incidence) has four
 * significant digits, and a narrow lobe (K = 4e16 at σ = 1e-9) carried the error into a normal
 * result, f00 1.1e-5 off. Where a < 2^-1000 the products are formed again on the coefficients
 * scaled by 2^-e (exact; max |r| brought into [0.5, 1)), and the caller applies 2^e2 = 2^(2e)
 * after its own factor; elsewhere e2 = 0 and the values are pc_facet_abcs's, at the cost of one
 * comparison (this is the renderer's inner loop). */
static inline void pc_facet_abcs_e(const pc_pbrdf *p, double cos_b, double sin2_b, double abcs[4],
                                   int *e2)
{
	pc_fresnel r;
	pc_fresnel_eval(p->m.n, p->m.k, cos_b, sin2_b, &r);
	pc_fresnel_abcs(&r, abcs);
	*e2 = 0;
	if (!(abcs[0] < 0x1p-1000)) /* a = (|r_s|² + |r_p|²)/2 bounds every product */
		return;
	const double m =
	    fmax(fmax(fabs(r.rs_re), fabs(r.rs_im)), fmax(fabs(r.rp_re), fabs(r.rp_im)));
	if (!(m > 0))
		return;
	int e;
	(void)frexp(m, &e);
	r.rs_re = ldexp(r.rs_re, -e);
	r.rs_im = ldexp(r.rs_im, -e);
	r.rp_re = ldexp(r.rp_re, -e);
	r.rp_im = ldexp(r.rp_im, -e);
	pc_fresnel_abcs(&r, abcs);
	*e2 = 2 * e;
}

/* ---------------------------------------------------------------------------------------- */
/* ρ^s by slope-space quadrature (physics.md §5).
 *
 * ρ^s(θ_i) = ∫ f00^s cosθ_r dω_r. With dω_r = 4 cosβ dω_h and f00^s = P_D G F/(cosθ_N cosθ_i
 * cosθ_r) (eqs. 2, 3 corrected, 9, 11): ρ^s = ∫ P_D dω_h · 4 cosβ G F/(cosθ_N cosθ_i), and in slope
 * space P_D dω_h = e^{−u} du dφ_h/(8π), u = tan²θ_N/(2σ²). With v = 1 − e^{−u} the measure is
 * dv dφ_h/(8π) on v ∈ [0, v*(φ_h)], where the horizon cosθ_r > 0 is exactly
 * tanθ_N < t*(φ_h) = (sinθ_i cosφ_h + sqrt(sin²θ_i cos²φ_h + cos²θ_i))/cosθ_i.
 * Gauss–Legendre in v, midpoint in φ_h ∈ [0, π], doubled by symmetry:
 *   ρ^s = 1/(8N) Σ_j v*_j Σ_k w_k g(v_k, φ_j),  g = 4 cosβ G F/(cosθ_N cosθ_i).
 * At grazing incidence v*(φ_h) drops from ≈ 1 to ≈ 0 within |cosφ_h| ≲ cosθ_i/σ of φ_h = 90°,
 * which uniform φ_h nodes resolve slowly (quad:16 was off by up to 1e-2 at θ_i = 85–89°,
 * σ ≥ 0.2). The midpoint nodes are therefore placed in ψ with φ_h = ψ + (α/2) sin 2ψ,
 * dφ_h = (1 + α cos 2ψ) dψ, α = clamp(1 − cosθ_i/σ, 0, 0.9): a smooth change of variable that
 * maps the period onto itself (φ_h(ψ + π) = φ_h(ψ) + π, odd in ψ), so the integrand stays even
 * and periodic and the midpoint rule keeps its spectral convergence, with the node density at
 * 90° raised by 1/(1 − α) ≤ 10. α = 0 (the plain rule) wherever cosθ_i ≥ σ. Measured against an
 * order-1024 rule: docs/physics-notes.md.
 * Returned: y = ρ^s with shadowing, y = ρ^s cosθ_i without (finite at grazing). */
static double pc_rho_quad_y(const pc_pbrdf *p, double sigma, double ci, double si, int N,
                            const double *x, const double *w)
{
	const double inv_2s2 = 1 / (2 * sigma * sigma);
	const bool fresnel = p->m.diffuse == PC_DIFFUSE_FRESNEL;
	const bool ts = p->m.shadowing == PC_SHADOW_TS;
	double alpha = 1 - ci / sigma;
	alpha = alpha < 0 ? 0 : alpha > 0.9 ? 0.9 : alpha;
	double sum = 0;
	for (int j = 0; j < N; j++) {
		double psi = (j + 0.5) * PC_PI / N;
		double phi = psi, jac = 1;
		if (alpha > 0) {
			phi = psi + 0.5 * alpha * sin(2 * psi);
			jac = 1 + alpha * cos(2 * psi);
		}
		double cp = cos(phi);
		double b = si * cp, R = sqrt(b * b + ci * ci);
		double tstar;
		if (ci <= 0)
			tstar = b > 0 ? INFINITY : 0;
		else /* the positive root of ci t² − 2 b t − ci, without cancellation */
			tstar = b >= 0 ? (b + R) / ci : ci / (R - b);
		double ustar = tstar * tstar * inv_2s2;
		double vstar = ustar > 745 ? 1.0 : -expm1(-ustar);
		if (!(vstar > 0))
			continue;
		double inner = 0;
		for (int k = 0; k < N; k++) {
			double v = 0.5 * vstar * (x[k] + 1);
			double u = -log1p(-v);
			double t = sqrt(u / inv_2s2);
			double q = 1 / sqrt(1 + t * t);     /* cosθ_N */
			double cb = (t * cp * si + ci) * q; /* cosβ = k_i·ĥ */
			double cr = 2 * cb * q - ci; /* cosθ_r = k_r·z, k_r = 2(k_i·ĥ)ĥ − k_i */
			if (!(cr > 0) || !(cb > 0))
				continue; /* rounding at the horizon */
			double F = 1;
			if (fresnel) {
				double abcs[4];
				pc_facet_abcs(p, cb, (1 - cb) * (1 + cb), abcs);
				F = abcs[0];
			}
			double g;
			if (ts) {
				/* G/cosθ_i with G = min(1, 2cosθ_N min(cosθ_i, cosθ_r)/cosβ)
				 * (physics.md §2), arranged so that cosθ_i = 0 never divides. */
				double G_ci;
				if (ci <= cr)
					G_ci = 2 * q * ci < cb ? 2 * q / cb : 1 / ci;
				else {
					double G = 2 * q * cr / cb;
					G_ci = (G < 1 ? G : 1) / ci;
				}
				g = 4 * cb * F * G_ci / q;
			} else {
				g = 4 * cb * F / q; /* times cosθ_i: y = ρ^s cosθ_i */
			}
			inner += w[k] * g;
		}
		sum += jac * vstar * inner;
	}
	return sum / (8.0 * N);
}

/* Cubic Lagrange interpolation on uniform nodes y[0..n−1] over [0, 1] (n ≥ 4), one-sided
 * stencils at the ends. */
static inline double pc_interp_cubic(const double *y, int n, double x)
{
	double pos = x * (n - 1);
	int i = (int)pos;
	if (i < 1)
		i = 1;
	if (i > n - 3)
		i = n - 3;
	double t = pos - i;
	double tm = t + 1, t1 = t - 1, t2 = t - 2;
	double wm = -t * t1 * t2 * (1.0 / 6), w0 = tm * t1 * t2 * 0.5;
	double w1 = -tm * t * t2 * 0.5, w2 = tm * t * t1 * (1.0 / 6);
	return wm * y[i - 1] + w0 * y[i] + w1 * y[i + 1] + w2 * y[i + 2];
}

/* Weights of the 4-point Lagrange stencil at fractional position t from node 0 (t in [0, 3]). */
static void pc_lagrange4(double t, double wts[4])
{
	double t0 = t, t1 = t - 1, t2 = t - 2, t3 = t - 3;
	wts[0] = -t1 * t2 * t3 / 6;
	wts[1] = t0 * t2 * t3 / 2;
	wts[2] = -t0 * t1 * t3 / 2;
	wts[3] = t0 * t1 * t2 / 6;
}

static double pc_mirror_rho(const pc_pbrdf *p, double ci)
{
	/* σ → 0: the lobe is a delta at ĥ = z, β = θ_i, G = 1: ρ^s = F(θ_i) (Fresnel-weighted) or
	 * 1 (geometric) (physics.md §2 invariant, §4). */
	if (p->m.diffuse != PC_DIFFUSE_FRESNEL)
		return 1;
	double abcs[4];
	pc_facet_abcs(p, ci, (1 - ci) * (1 + ci), abcs);
	return abcs[0];
}

/* ---------------------------------------------------------------------------------------- */

static int pc_build_table(pc_pbrdf *p)
{
	const pc_material *m = &p->m;
	if (m->diffuse == PC_DIFFUSE_NONE || (p->flags & PC_PBRDF_MIRROR))
		return 0;
	if (m->rho_mode == PC_RHO_QUAD) {
		for (int a = 0; a < p->ntab; a++) {
			double x = (double)a / (p->ntab - 1), c = x * x;
			double s = sqrt((1 - c) * (1 + c));
			p->tab[a] =
			    pc_rho_quad_y(p, m->sigma, c, s, m->rho_order, p->gl_x, p->gl_w);
		}
		return 0;
	}
	/* PC_RHO_TABLE: the 64 (cosθ_i) × 32 (log σ) grid of physics.md §5 with bicubic (tensor
	 * product cubic Lagrange) interpolation. Only the four log σ columns the material's σ
	 * needs are computed; interpolating them in log σ gives the 64 cosθ_i values that the
	 * cubic in cosθ_i then interpolates: identical to evaluating the full table. */
	const double l0 = log(PC_RHO_TABLE_SIGMA_MIN);
	const double dl = (log(PC_RHO_TABLE_SIGMA_MAX) - l0) / (PC_RHO_TABLE_NSIGMA - 1);
	double pos = (log(m->sigma) - l0) / dl;
	int b0 = (int)floor(pos) - 1;
	if (b0 < 0)
		b0 = 0;
	if (b0 > PC_RHO_TABLE_NSIGMA - 4)
		b0 = PC_RHO_TABLE_NSIGMA - 4;
	double wts[4];
	pc_lagrange4(pos - b0, wts);
	for (int a = 0; a < p->ntab; a++) {
		double c = (double)a / (p->ntab - 1);
		double s = sqrt((1 - c) * (1 + c));
		double v = 0;
		for (int l = 0; l < 4; l++) {
			double sg = exp(l0 + (b0 + l) * dl);
			v += wts[l] * pc_rho_quad_y(p, sg, c, s, m->rho_order, p->gl_x, p->gl_w);
		}
		p->tab[a] = v;
	}
	return 0;
}

int pc_pbrdf_new(const pc_material *m, pc_pbrdf **out)
{
	if (!out)
		return pc_error(PC_EINVAL, "pc_pbrdf_new: out is NULL");
	*out = NULL;
	if (!m)
		return pc_error(PC_EINVAL, "pc_pbrdf_new: material is NULL");
	if (!isfinite(m->n) || !(m->n > 0))
		return pc_error(PC_EINVAL, "n = %g: must be a finite number > 0", m->n);
	if (!isfinite(m->k) || !(m->k >= 0))
		return pc_error(PC_EINVAL, "k = %g: must be a finite number >= 0 (n~ = n - ik)",
		                m->k);
	if (m->n > 1e100 || m->k > 1e100)
		return pc_error(PC_ERANGE, "n = %g, k = %g: must be below 1e100", m->n, m->k);
	if (!isfinite(m->sigma) || !(m->sigma > 0))
		return pc_error(PC_EINVAL, "sigma = %g: must be a finite rms slope > 0", m->sigma);
	if (m->sigma < PC_PBRDF_SIGMA_MIN) {
		/* all the digits when the short form would print the bound itself */
		char sg[32];
		snprintf(sg, sizeof sg, "%g", m->sigma);
		if (strtod(sg, NULL) >= PC_PBRDF_SIGMA_MIN)
			snprintf(sg, sizeof sg, "%.17g", m->sigma);
		return pc_error(PC_ERANGE,
		                "sigma = %s: below %g, where the specular peak 1/(8 pi sigma^2) "
		                "leaves the double range (docs/physics-notes.md, hard cases); for "
		                "an ideal mirror use pc_pbrdf_mirror",
		                sg, PC_PBRDF_SIGMA_MIN);
	}
	if (m->sigma > 1e3)
		return pc_error(PC_ERANGE, "sigma = %g: must be at most 1000", m->sigma);
	if ((unsigned)m->diffuse > PC_DIFFUSE_NONE)
		return pc_error(PC_EINVAL, "diffuse = %d: not a pc_diffuse value", (int)m->diffuse);
	if ((unsigned)m->shadowing > PC_SHADOW_NONE)
		return pc_error(PC_EINVAL, "shadowing = %d: not a pc_shadowing value",
		                (int)m->shadowing);
	if ((unsigned)m->rho_mode > PC_RHO_TABLE)
		return pc_error(PC_EINVAL, "rho_mode = %d: not a pc_rho_mode value",
		                (int)m->rho_mode);
	if (m->rho_order != 0 && (m->rho_order < 2 || m->rho_order > PC_RHO_MAX_ORDER))
		return pc_error(PC_EINVAL, "rho_order = %d: must be 0 (default 16) or in [2, %d]",
		                m->rho_order, PC_RHO_MAX_ORDER);
	bool mirror = m->sigma < PC_PBRDF_SIGMA_MIRROR;
	if (m->rho_mode == PC_RHO_TABLE && !mirror && m->diffuse != PC_DIFFUSE_NONE &&
	    m->sigma > PC_RHO_TABLE_SIGMA_MAX)
		return pc_error(PC_ERANGE,
		                "sigma = %g: outside the rho table's range [%g, %g]; use the "
		                "quadrature mode",
		                m->sigma, PC_RHO_TABLE_SIGMA_MIN, PC_RHO_TABLE_SIGMA_MAX);

	int order = m->rho_order ? m->rho_order : 16;
	int ntab = 0;
	if (m->diffuse != PC_DIFFUSE_NONE && !mirror)
		ntab = m->rho_mode == PC_RHO_TABLE ? PC_RHO_TABLE_NCOS : PC_PBRDF_RHO_NODES;
	size_t bytes = sizeof(pc_pbrdf) + (2 * (size_t)order + (size_t)ntab) * sizeof(double);
	pc_pbrdf *p = calloc(1, bytes);
	if (!p)
		return pc_error(PC_ENOMEM, "pc_pbrdf_new: %zu bytes", bytes);
	p->m = *m;
	p->m.rho_order = order;
	p->flags = (mirror ? PC_PBRDF_MIRROR : 0u) |
	           (m->sigma > PC_PBRDF_SIGMA_VALID_MAX ? PC_PBRDF_OUTSIDE_VALIDITY : 0u);
	p->eps_re = m->n * m->n - m->k * m->k;
	p->eps_im = -2 * m->n * m->k;
	p->inv_2s2 = 1 / (2 * m->sigma * m->sigma);
	p->norm = 1 / (8 * PC_PI * m->sigma * m->sigma);
	p->gl_x = (double *)(p + 1);
	p->gl_w = p->gl_x + order;
	p->tab = p->gl_w + order;
	p->ntab = ntab;
	pc_gauss_legendre(order, p->gl_x, p->gl_w);
	int rc = pc_build_table(p);
	if (rc) {
		free(p);
		return rc;
	}
	*out = p;
	return 0;
}

void pc_pbrdf_free(pc_pbrdf *p)
{
	free(p);
}

unsigned pc_pbrdf_flags(const pc_pbrdf *p)
{
	return p->flags;
}

const pc_material *pc_pbrdf_material(const pc_pbrdf *p)
{
	return &p->m;
}

double pc_pbrdf_rho_s_fast(const pc_pbrdf *p, double ci)
{
	if (p->m.diffuse == PC_DIFFUSE_NONE)
		return NAN;
	if (p->flags & PC_PBRDF_MIRROR)
		return pc_mirror_rho(p, ci);
	double y = pc_interp_cubic(p->tab, p->ntab, p->m.rho_mode == PC_RHO_TABLE ? ci : sqrt(ci));
	if (p->m.shadowing == PC_SHADOW_NONE)
		return ci > 0 ? y / ci : INFINITY;
	return y;
}

double pc_pbrdf_rho_s_quad(const pc_pbrdf *p, double theta_i, int order)
{
	if (order < 1 || order > PC_RHO_MAX_ORDER || p->m.diffuse == PC_DIFFUSE_NONE)
		return NAN;
	double x[PC_RHO_MAX_ORDER], w[PC_RHO_MAX_ORDER];
	pc_gauss_legendre(order, x, w);
	double ci = cos(theta_i), si = sin(theta_i);
	if (ci < 0)
		ci = 0;
	double y = pc_rho_quad_y(p, p->m.sigma, ci, si, order, x, w);
	if (p->m.shadowing == PC_SHADOW_NONE)
		return ci > 0 ? y / ci : INFINITY;
	return y;
}

double pc_pbrdf_rho_s(const pc_pbrdf *p, double theta_i)
{
	if (p->m.diffuse == PC_DIFFUSE_NONE)
		return NAN;
	double ci = cos(theta_i), si = sin(theta_i);
	if (ci < 0)
		ci = 0;
	if (p->flags & PC_PBRDF_MIRROR)
		return pc_mirror_rho(p, ci);
	if (p->m.rho_mode == PC_RHO_TABLE)
		return pc_pbrdf_rho_s_fast(p, ci);
	double y = pc_rho_quad_y(p, p->m.sigma, ci, si, p->m.rho_order, p->gl_x, p->gl_w);
	if (p->m.shadowing == PC_SHADOW_NONE)
		return ci > 0 ? y / ci : INFINITY;
	return y;
}

/* ---------------------------------------------------------------------------------------- */
/* Evaluation (physics.md §2, vector form; hard cases §4). */

/* cos 2θ and sin 2θ of the Jones frame rotation [[c, s], [−s, c]] with c = s_F·s, s = s_F·p
 * (T_in) or c = s·s_F, s = s·p_F (T_out). Divides by c² + s² so that slightly non-unit caller
 * vectors do not scale the result. */
static inline void pc_rot2(double c, double s, double *c2, double *s2)
{
	double n = c * c + s * s;
	double inv = n > 0 ? 1 / n : 0;
	*c2 = (c * c - s * s) * inv;
	*s2 = 2 * c * s * inv;
}

/* Specular frame rotations for the facet ĥ = h/|h| (physics.md §2): s_F = unit(d_i × ĥ), or the
 * caller's s_i when |d_i × ĥ| < 1e-12 (β ≈ 0, where M does not depend on the choice). */
static inline void pc_facet_frames(const double k_i[3], const double k_r[3], const double h[3],
                                   double hl, const double s_i[3], const double s_r[3], double *C1,
                                   double *S1, double *C2, double *S2)
{
	double d_i[3] = {-k_i[0], -k_i[1], -k_i[2]};
	double sF[3], pFr[3], p_i[3];
	pc_cross(d_i, h, sF); /* |d_i × h| = |h| sinβ */
	double l = sqrt(pc_dot(sF, sF));
	if (l < 1e-12 * hl) {
		memcpy(sF, s_i, sizeof sF);
	} else {
		double inv = 1 / l;
		sF[0] *= inv;
		sF[1] *= inv;
		sF[2] *= inv;
	}
	pc_cross(k_r, sF, pFr);  /* p_Fr = d_r × s_F */
	pc_cross(d_i, s_i, p_i); /* p_i = d_i × s_i */
	/* T_in = [[s_F·s_i, s_F·p_i], [p_Fi·s_i, p_Fi·p_i]] */
	pc_rot2(pc_dot(sF, s_i), pc_dot(sF, p_i), C1, S1);
	/* T_out = [[s_r·s_F, s_r·p_Fr], [p_r·s_F, p_r·p_Fr]] */
	pc_rot2(pc_dot(s_r, sF), pc_dot(s_r, pFr), C2, S2);
}

int pc_pbrdf_eval_vec(const pc_pbrdf *p, const double k_i[3], const double k_r[3],
                      const double s_i[3], const double s_r[3], double f[4][4])
{
	const double ci = k_i[2], cr = k_r[2];
	double h[3] = {k_i[0] + k_r[0], k_i[1] + k_r[1], k_i[2] + k_r[2]};
	double h2 = pc_dot(h, h);
	/* below or at the horizon, or k_r = −k_i (|k_i + k_r| < ε, physics.md §4): nothing.
	 * "At" includes cosθ ≤ PC_PBRDF_COS_HORIZON: without shadowing K ∝ 1/(cosθ_i cosθ_r),
	 * which would leave the double range there (angles in degrees never come that close:
	 * cos 90° is 0 exactly, the next double below 90° gives cos ≈ 2.5e-16). */
	if (!(ci > PC_PBRDF_COS_HORIZON) || !(cr > PC_PBRDF_COS_HORIZON) || !(h2 > 1e-24)) {
		memset(f, 0, 16 * sizeof(double));
		return 0;
	}
	double hl = sqrt(h2);
	double cos_b = 0.5 * hl; /* cosβ = |k_i + k_r|/2 */
	double d[3] = {k_r[0] - k_i[0], k_r[1] - k_i[1], k_r[2] - k_i[2]};
	double sin2_b = 0.25 * pc_dot(d, d); /* sin²β = |k_r − k_i|²/4, no 1 − cos² cancellation */
	double abcs[4];
	int e2;
	pc_facet_abcs_e(p, cos_b, sin2_b, abcs, &e2);

	/* Specular factor K = P_D G/(cosθ_N cosθ_i cosθ_r) with the corrected
	 * P_D = exp(−tan²θ_N/(2σ²))/(8πσ² cos³θ_N) (physics.md §2, paper eqs. 2, 3). tan²θ_N from
	 * the unnormalised h; the lobe is 0 where the exponent exceeds 700 (physics.md §4). */
	double txy = h[0] * h[0] + h[1] * h[1], hz2 = h[2] * h[2];
	double K = 0;
	if (txy <= 700 * hz2 / p->inv_2s2) {
		double u = txy / hz2 * p->inv_2s2;
		double cN = h[2] / hl;
		double cN2 = cN * cN;
		double G_cc; /* G/(cosθ_i cosθ_r), G of Torrance–Sparrow (physics.md §2) */
		if (p->m.shadowing == PC_SHADOW_TS) {
			double cmin = ci < cr ? ci : cr, cmax = ci < cr ? cr : ci;
			double g = 2 * cN * cmin / cos_b;
			G_cc = (g < 1 ? g : 1) / (cmin * cmax);
		} else {
			G_cc = 1 / (ci * cr);
		}
		K = exp(-u) * p->norm / (cN2 * cN2) * G_cc;
	}
	double C1, S1, C2, S2;
	pc_facet_frames(k_i, k_r, h, hl, s_i, s_r, &C1, &S1, &C2, &S2);
	double ks[4] = {K * abcs[0], K * abcs[1], K * abcs[2], K * abcs[3]};
	if (e2)
		for (int q = 0; q < 4; q++)
			ks[q] = ldexp(ks[q], e2);
	pc_mueller_facet(ks, C1, S1, C2, S2, f);
	/* Diffuse part (paper eqs. 8–12, physics.md §2): f_d = (1 − ρ^s(θ_i))/π times the facet's
	 * M00 = a(β), on element (0, 0). ρ^s > 1 (only without shadowing, outside the model's
	 * validity) gives no diffuse light rather than a negative BRDF. */
	if (p->m.diffuse != PC_DIFFUSE_NONE) {
		double rho = pc_pbrdf_rho_s_fast(p, ci);
		if (rho < 1)
			f[0][0] += e2 ? ldexp((1 - rho) * (1 / PC_PI) * abcs[0], e2)
			              : (1 - rho) * (1 / PC_PI) * abcs[0];
	}
	return 0;
}

int pc_pbrdf_eval(const pc_pbrdf *p, double theta_i, double theta_r, double dphi, double f[4][4])
{
	/* Macro frames of physics.md §1 with φ_i = 0, φ_r = Δφ; defined from the azimuth so that
	 * θ = 0 needs no vanishing cross product. */
	double si = sin(theta_i), ci = cos(theta_i), sr = sin(theta_r), cr = cos(theta_r);
	double cp = cos(dphi), sp = sin(dphi);
	double k_i[3] = {si, 0, ci};
	double k_r[3] = {sr * cp, sr * sp, cr};
	double s_i[3] = {0, 1, 0};    /* s_Mi = (−sinφ_i, cosφ_i, 0) */
	double s_r[3] = {sp, -cp, 0}; /* s_Mr = (sinφ_r, −cosφ_r, 0) */
	return pc_pbrdf_eval_vec(p, k_i, k_r, s_i, s_r, f);
}

int pc_pbrdf_eval_deg(const pc_pbrdf *p, double theta_i_deg, double theta_r_deg, double dphi_deg,
                      double f[4][4])
{
	/* as pc_pbrdf_eval, with sines and cosines exact at multiples of 90° (pc_sincos_deg): at
	 * Δφ = 180° the reflected direction is exactly in the plane of incidence */
	double si, ci, sr, cr, sp, cp;
	pc_sincos_deg(theta_i_deg, &si, &ci);
	pc_sincos_deg(theta_r_deg, &sr, &cr);
	pc_sincos_deg(dphi_deg, &sp, &cp);
	double k_i[3] = {si, 0, ci};
	double k_r[3] = {sr * cp, sr * sp, cr};
	double s_i[3] = {0, 1, 0};
	double s_r[3] = {sp, -cp, 0};
	return pc_pbrdf_eval_vec(p, k_i, k_r, s_i, s_r, f);
}

int pc_pbrdf_mirror(const pc_pbrdf *p, const double k_i[3], const double s_i[3],
                    const double s_r[3], double R[4][4])
{
	double ci = k_i[2];
	if (!(ci > 0)) {
		memset(R, 0, 16 * sizeof(double));
		return 0;
	}
	double k_r[3] = {-k_i[0], -k_i[1], k_i[2]};
	double h[3] = {0, 0, 2 * ci};
	double sin2 = k_i[0] * k_i[0] + k_i[1] * k_i[1];
	double abcs[4];
	pc_facet_abcs(p, ci, sin2, abcs);
	double C1, S1, C2, S2;
	pc_facet_frames(k_i, k_r, h, 2 * ci, s_i, s_r, &C1, &S1, &C2, &S2);
	pc_mueller_facet(abcs, C1, S1, C2, S2, R);
	return 0;
}
