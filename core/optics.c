/* Fresnel, Jones → Mueller, Stokes helpers, coherency matrix and Cloude filter.
 * Formulas: docs/physics.md §1 (conventions), §2 (Fresnel, Jones → Mueller), §4 (Cloude filter). */
#include "polarcam/optics.h"

#include "optics_inline.h"

#include <complex.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* F(ρ) = (1 − ρ)/(1 + ρ) for ρ = (zr + i zi)·2^E with (zr, zi) finite: r_s = F(w/cosβ),
 * r_p = F(w/(ñ² cosβ)) (physics.md §2 divided through). The exponent is kept apart so that ρ
 * may lie far outside the double range: for |ρ| > 2^30, F(ρ) = −F(1/ρ) with 1/ρ formed from the
 * reduced mantissa, and ldexp underflows gracefully towards the limits F(0) = 1, F(∞) = −1. */
static void pc_fresnel_F(double zr, double zi, int E, double *fr, double *fi)
{
	double m = fmax(fabs(zr), fabs(zi));
	if (m == 0) { /* ρ = 0 */
		*fr = 1;
		*fi = 0;
		return;
	}
	int em;
	frexp(m, &em);
	zr = ldexp(zr, -em);
	zi = ldexp(zi, -em);
	E += em;
	double sign = 1;
	if (E > 30) { /* ρ → 1/ρ = conj(z)/|z|²·2^−E, F(ρ) = −F(1/ρ) */
		double d = zr * zr + zi * zi; /* in [0.25, 2] */
		zr = ldexp(zr / d, -E);
		zi = ldexp(-zi / d, -E);
		sign = -1;
	} else {
		zr = ldexp(zr, E);
		zi = ldexp(zi, E);
	}
	/* (1 − z)/(1 + z), |z| ≤ 2^31: no overflow in |1 + z|² */
	double nr = 1 - zr, ni = -zi, dr = 1 + zr, di = zi;
	double inv = 1.0 / (dr * dr + di * di);
	*fr = sign * (nr * dr + ni * di) * inv;
	*fi = sign * (ni * dr - nr * di) * inv;
}

/* pc_fresnel_eval for ñ far from 1 (|ñ| outside [2^−60, 2^60]), where ñ², ñ⁴ and the squared
 * moduli of the direct formulas leave the double range (n = 1e100, k = 1e90: overflow; n =
 * 1e-200: ñ² underflows and r_p becomes 0/0 at normal incidence). Everything is scaled by 2^−e
 * with 2^e ≈ max(n, k, sinβ), so that what matters relative to the largest term is kept:
 * w = 2^e w', r_s = F(2^e w'/cosβ), r_p = F(2^−e w'/(ñ'² cosβ)), F as above. The limits come out
 * exactly: a perfect conductor (|ñ| → ∞: r_s → −1, r_p → +1) and ñ → 0 (w → −i sinβ:
 * r_s → e^{2iβ}, r_p → −1). Tested against a long-double evaluation of the direct formulas. */
static void pc_fresnel_eval_scaled(double n, double k, double cos_beta, double sin2_beta,
                                   pc_fresnel *out)
{
	double sb = sqrt(sin2_beta);
	double mx = fmax(fmax(n, k), sb);
	int e;
	frexp(mx, &e);
	const double ns = ldexp(n, -e), ks = ldexp(k, -e), s2s = ldexp(sb, -e);
	/* ñ'² and w' = sqrt(ñ'² − s'²) on the branch Re w ≥ 0, Im w ≤ 0, as in pc_fresnel_eval */
	const double er = (ns - ks) * (ns + ks), ei = -2.0 * ns * ks;
	const double A = er - s2s * s2s, B = ei;
	const double mod = hypot(A, B);
	double wr, wi;
	if (A >= 0) {
		wr = sqrt(0.5 * (mod + A));
		wi = wr > 0 ? B / (2.0 * wr) : 0.0;
	} else {
		wi = -sqrt(0.5 * (mod - A));
		wr = B / (2.0 * wi);
	}
	const double c = cos_beta;
	if (!(c > 0)) { /* grazing: ρ_s = ρ_p = ∞ */
		out->rs_re = out->rp_re = -1;
		out->rs_im = out->rp_im = 0;
		return;
	}
	int ec;
	const double cm = frexp(c, &ec); /* c = cm·2^ec, cm in [0.5, 1) */
	/* ρ_s = w/c = (w'/cm)·2^(e − ec) */
	pc_fresnel_F(wr / cm, wi / cm, e - ec, &out->rs_re, &out->rs_im);
	/* ρ_p = w/(ñ² c) = w'/(ñ'² cm)·2^(−e − ec) */
	const double pr = er * cm, pi = ei * cm;
	const double pm = fmax(fabs(pr), fabs(pi));
	if (pm == 0) { /* ñ'² underflowed: ρ_p = ∞ */
		out->rp_re = -1;
		out->rp_im = 0;
		return;
	}
	int ep;
	frexp(pm, &ep);
	const double qr = ldexp(pr, -ep), qi = ldexp(pi, -ep); /* max |q| in [0.5, 1) */
	const double qd = qr * qr + qi * qi;
	pc_fresnel_F((wr * qr + wi * qi) / qd, (wi * qr - wr * qi) / qd, -e - ec - ep, &out->rp_re,
	             &out->rp_im);
}

void pc_fresnel_eval(double n, double k, double cos_beta, double sin2_beta, pc_fresnel *out)
{
	const double mx = n > k ? n : k;
	if (!(mx >= 0x1p-60 && mx <= 0x1p60)) {
		pc_fresnel_eval_scaled(n, k, cos_beta, sin2_beta, out);
		return;
	}
	/* ñ² = (n − ik)² = n² − k² − 2ink (physics.md §1: ñ = n − ik, k ≥ 0). */
	double er = n * n - k * k, ei = -2.0 * n * k;
	/* w = sqrt(ñ² − sin²β) on the branch Re w ≥ 0, Im w ≤ 0 (physics.md §2), computed without
	 * cancellation: the larger of |Re w|, |Im w| from the half-modulus formula, the other from
	 * Re w · Im w = B/2. */
	double A = er - sin2_beta, B = ei; /* B ≤ 0 */
	double mod = sqrt(A * A + B * B);
	double wr, wi;
	if (A >= 0) {
		wr = sqrt(0.5 * (mod + A));
		wi = wr > 0 ? B / (2.0 * wr) : 0.0;
	} else {
		wi = -sqrt(0.5 * (mod - A)); /* Im w ≤ 0: evanescent wave decays for e^{+iωt} */
		wr = B / (2.0 * wi);         /* B ≤ 0, wi < 0 → Re w ≥ 0 */
	}
	double c = cos_beta;
	/* r_s = (cosβ − w)/(cosβ + w) */
	double nr = c - wr, ni = -wi, dr = c + wr, di = wi;
	double d2 = dr * dr + di * di;
	/* r_p = (ñ² cosβ − w)/(ñ² cosβ + w) */
	double ec_r = er * c, ec_i = ei * c;
	double pnr = ec_r - wr, pni = ec_i - wi, pdr = ec_r + wr, pdi = ec_i + wi;
	double p2 = pdr * pdr + pdi * pdi;
	if (!(d2 >= 0x1p-900 && p2 >= 0x1p-900)) {
		/* cosβ + w → 0 only near grazing with ñ ≈ 1 (or at the critical angle): the squared
		 * moduli would underflow */
		pc_fresnel_eval_scaled(n, k, cos_beta, sin2_beta, out);
		return;
	}
	/* ñ near 1 against the angle, |t| < 2^-10 cos²β with t = ñ² − 1 (docs/physics-notes.md,
	 * "ñ near 1"). There w = sqrt(cos²β + t) ≈ cosβ and ñ² cosβ ≈ w, so both numerators above
	 * cancel, losing as many bits as ñ² is close to 1 (ñ = 1 − 1e-20 i at β = 0.3 gave
	 * |r_s| ≈ 1e-17 of rounding instead of 5.5e-21). Multiplied through by their conjugates,
	 * with cos²β + sin²β = 1:
	 *   cosβ − w = −t/(cosβ + w),   ñ² cosβ − w = t·(ñ² cos²β − sin²β)/(ñ² cosβ + w),
	 * t = (n − 1)(n + 1) − k² − 2ink (n − 1 exact there), so r keeps t's relative precision
	 * and |r| < 2^-10; the second factor of r_p is its Brewster zero. Nearer the critical angle
	 * and beyond it w is not near cosβ, the direct form does not cancel, and it keeps |r| = 1
	 * of total reflection exactly, which the identity form, rounded against t, did not
	 * (|r| = 1 + 1.2e-12 at n = 0.99995, sinβ = 0.99998: fuzz_physics). */
	const double tr = (n - 1) * (n + 1) - k * k, ti = ei;
	if (fabs(tr) + fabs(ti) < 0x1p-10 * c * c) {
		nr = -(tr * dr + ti * di) / d2; /* −t / (c + w) = −t·conj(c + w)/|c + w|² */
		ni = -(ti * dr - tr * di) / d2;
		const double ur = er * c * c - sin2_beta, ui = ei * c * c; /* ñ² c² − sin²β */
		const double vr = tr * ur - ti * ui, vi = tr * ui + ti * ur; /* t·(ñ² c² − sin²β) */
		pnr = (vr * pdr + vi * pdi) / p2;
		pni = (vi * pdr - vr * pdi) / p2;
	}
	double inv = 1.0 / d2;
	out->rs_re = (nr * dr + ni * di) * inv;
	out->rs_im = (ni * dr - nr * di) * inv;
	inv = 1.0 / p2;
	out->rp_re = (pnr * pdr + pni * pdi) * inv;
	out->rp_im = (pni * pdr - pnr * pdi) * inv;
}

void pc_fresnel_angle(double n, double k, double beta, pc_fresnel *out)
{
	double s = sin(beta);
	pc_fresnel_eval(n, k, cos(beta), s * s, out);
}

void pc_fresnel_abcs(const pc_fresnel *r, double abcs[4])
{
	/* physics.md §2, Jones → Mueller for J = diag(r_s, r_p). */
	double Rs = r->rs_re * r->rs_re + r->rs_im * r->rs_im;
	double Rp = r->rp_re * r->rp_re + r->rp_im * r->rp_im;
	abcs[0] = 0.5 * (Rs + Rp);
	abcs[1] = 0.5 * (Rs - Rp);
	abcs[2] = r->rs_re * r->rp_re + r->rs_im * r->rp_im; /* Re(r_s r_p*) */
	abcs[3] = r->rs_im * r->rp_re - r->rs_re * r->rp_im; /* Im(r_s r_p*) */
}

double pc_fresnel_reflectance(double n, double k, double beta)
{
	pc_fresnel r;
	double abcs[4];
	pc_fresnel_angle(n, k, beta, &r);
	pc_fresnel_abcs(&r, abcs);
	return abcs[0];
}

/* A and A⁻¹ of physics.md §1: S = A (E ⊗ E*). A⁻¹ = ½[[1,1,0,0],[0,0,1,−i],[0,0,1,i],[1,−1,0,0]].
 */
static void pc_stokes_A(double complex A[4][4], double complex Ai[4][4])
{
	static const double complex a[4][4] = {
	    {1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0}, {0, I, -I, 0}};
	static const double complex ai[4][4] = {
	    {0.5, 0.5, 0, 0}, {0, 0, 0.5, -0.5 * I}, {0, 0, 0.5, 0.5 * I}, {0.5, -0.5, 0, 0}};
	memcpy(A, a, sizeof a);
	memcpy(Ai, ai, sizeof ai);
}

static void pc_cmul4(const double complex X[4][4], const double complex Y[4][4],
                     double complex Z[4][4])
{
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double complex s = 0;
			for (int l = 0; l < 4; l++)
				s += X[i][l] * Y[l][j];
			Z[i][j] = s;
		}
}

void pc_jones_to_mueller(const double J_re[2][2], const double J_im[2][2], double M[4][4])
{
	double complex A[4][4], Ai[4][4], K[4][4], T[4][4], R[4][4];
	pc_stokes_A(A, Ai);
	/* (J ⊗ J*)_{(ab),(cd)} = J_ac J*_bd with (xy) = 2x + y: the field products E_a E_b*. */
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 2; b++)
			for (int c = 0; c < 2; c++)
				for (int d = 0; d < 2; d++) {
					double complex jac = J_re[a][c] + I * J_im[a][c];
					double complex jbd = J_re[b][d] + I * J_im[b][d];
					K[2 * a + b][2 * c + d] = jac * conj(jbd);
				}
	pc_cmul4(A, K, T);
	pc_cmul4(T, Ai, R);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			M[i][j] = creal(R[i][j]);
}

void pc_mueller_rotator(double theta, double M[4][4])
{
	double c = cos(2 * theta), s = sin(2 * theta);
	memset(M, 0, 16 * sizeof(double));
	M[0][0] = M[3][3] = 1;
	M[1][1] = M[2][2] = c;
	M[1][2] = s;
	M[2][1] = -s;
}

void pc_retarder_mueller(double angle_rad, double delta_rad, double m[4][4])
{
	/* Linear retarder, fast axis at θ from the x (s) axis towards y (p), retardance δ: the
	 * Jones matrix R(−θ)·diag(1, e^{−iδ})·R(θ) (e^{+iωt}: the slow component lags) mapped to
	 * Mueller with physics.md §1's A (S3 = 2 Im(E_s* E_p)). Worked out by hand:
	 * [[1,0,0,0],[0,c²+s²cosδ, cs(1−cosδ), −s sinδ],[0, cs(1−cosδ), s²+c²cosδ, c sinδ],
	 *  [0, s sinδ, −c sinδ, cosδ]] with c = cos2θ, s = sin2θ. Verified in tests against the
	 * Jones calculus (tests/test_sim_render.c): a quarter-wave plate at 45° turns S1 = +1 into
	 * S3 = +1 in this convention. */
	double c = cos(2 * angle_rad), s = sin(2 * angle_rad);
	double cd = cos(delta_rad), sd = sin(delta_rad);
	double r[4][4] = {{1, 0, 0, 0},
	                  {0, c * c + s * s * cd, c * s * (1 - cd), -s * sd},
	                  {0, c * s * (1 - cd), s * s + c * c * cd, c * sd},
	                  {0, s * sd, -c * sd, cd}};
	memcpy(m, r, sizeof r);
}

void pc_diattenuator_mueller(double angle_rad, double D, double m[4][4])
{
	double p = (1 + D) / 2, q = (1 - D) / 2, r = 2 * sqrt(p * q);
	double c = cos(2 * angle_rad), s = sin(2 * angle_rad);
	double t[4][4] = {{p + q, (p - q) * c, (p - q) * s, 0},
	                  {(p - q) * c, (p + q) * c * c + r * s * s, (p + q - r) * c * s, 0},
	                  {(p - q) * s, (p + q - r) * c * s, (p + q) * s * s + r * c * c, 0},
	                  {0, 0, 0, r}};
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			m[i][j] = 0.5 * t[i][j];
}

void pc_mueller_facet(const double abcs[4], double C1, double S1, double C2, double S2,
                      double M[4][4])
{
	/* R_M(θ_out) M_F R_M(θ_in) multiplied out by hand (physics.md §2): 20 products instead of
	 * two 4×4 products or a complex Kronecker product. */
	double a = abcs[0], b = abcs[1], c = abcs[2], s = abcs[3];
	double aC1 = a * C1, aS1 = a * S1, cC1 = c * C1, cS1 = c * S1;
	M[0][0] = a;
	M[0][1] = b * C1;
	M[0][2] = b * S1;
	M[0][3] = 0;
	M[1][0] = C2 * b;
	M[1][1] = C2 * aC1 - S2 * cS1;
	M[1][2] = C2 * aS1 + S2 * cC1;
	M[1][3] = S2 * s;
	M[2][0] = -S2 * b;
	M[2][1] = -S2 * aC1 - C2 * cS1;
	M[2][2] = -S2 * aS1 + C2 * cC1;
	M[2][3] = C2 * s;
	M[3][0] = 0;
	M[3][1] = s * S1;
	M[3][2] = -s * C1;
	M[3][3] = c;
}

void pc_mueller_mul(const double A[4][4], const double B[4][4], double C[4][4])
{
	double T[4][4];
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			T[i][j] = A[i][0] * B[0][j] + A[i][1] * B[1][j] + A[i][2] * B[2][j] +
			          A[i][3] * B[3][j];
	memcpy(C, T, sizeof T);
}

void pc_mueller_apply(const double M[4][4], const double S[4], double out[4])
{
	double t[4];
	for (int i = 0; i < 4; i++)
		t[i] = M[i][0] * S[0] + M[i][1] * S[1] + M[i][2] * S[2] + M[i][3] * S[3];
	memcpy(out, t, sizeof t);
}

double pc_stokes_dop(const double S[4])
{
	if (!(S[0] > 0))
		return 0;
	return sqrt(S[1] * S[1] + S[2] * S[2] + S[3] * S[3]) / S[0];
}

double pc_stokes_dolp(const double S[4])
{
	if (!(S[0] > 0))
		return 0;
	return hypot(S[1], S[2]) / S[0];
}

double pc_stokes_docp(const double S[4])
{
	if (!(S[0] > 0))
		return 0;
	return S[3] / S[0];
}

double pc_stokes_aolp_rad(const double S[4])
{
	if (!(S[0] > 0) || (S[1] == 0 && S[2] == 0))
		return 0;
	double a = 0.5 * atan2(S[2], S[1]); /* (−π/2, π/2] */
	if (a < 0)
		a += PC_PI;
	if (a >= PC_PI) /* rounding of a + π */
		a = 0;
	return a;
}

double pc_mueller_dop(const double M[4][4])
{
	if (!(M[0][0] > 0))
		return NAN;
	double p1 = M[1][0] / M[0][0], p2 = M[2][0] / M[0][0], p3 = M[3][0] / M[0][0];
	return sqrt(p1 * p1 + p2 * p2 + p3 * p3);
}

void pc_stokes_linear(double intensity, double aolp_rad, double S[4])
{
	S[0] = intensity;
	S[1] = intensity * cos(2 * aolp_rad);
	S[2] = intensity * sin(2 * aolp_rad);
	S[3] = 0;
}

void pc_mueller_coherency(const double M[4][4], double H_re[4][4], double H_im[4][4])
{
	/* N = A⁻¹ M A using the sparsity of A and A⁻¹ (physics.md §1):
	 * columns of T = M A: T0 = M·0 + M·1, T1 = M·2 + i M·3, T2 = M·2 − i M·3, T3 = M·0 − M·1;
	 * rows of N = A⁻¹ T: N0 = (T0· + T1·)/2, N1 = (T2· − i T3·)/2, N2 = (T2· + i T3·)/2,
	 * N3 = (T0· − T1·)/2. Then H_{(ac),(bd)} = N_{(ab),(cd)}. */
	double complex T[4][4], N[4][4];
	for (int r = 0; r < 4; r++) {
		T[r][0] = M[r][0] + M[r][1];
		T[r][1] = M[r][2] + I * M[r][3];
		T[r][2] = M[r][2] - I * M[r][3];
		T[r][3] = M[r][0] - M[r][1];
	}
	for (int c = 0; c < 4; c++) {
		N[0][c] = 0.5 * (T[0][c] + T[1][c]);
		N[1][c] = 0.5 * (T[2][c] - I * T[3][c]);
		N[2][c] = 0.5 * (T[2][c] + I * T[3][c]);
		N[3][c] = 0.5 * (T[0][c] - T[1][c]);
	}
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 2; b++)
			for (int c = 0; c < 2; c++)
				for (int d = 0; d < 2; d++) {
					double complex v = N[2 * a + b][2 * c + d];
					H_re[2 * a + c][2 * b + d] = creal(v);
					H_im[2 * a + c][2 * b + d] = cimag(v);
				}
}

/* M scaled by the power of two 2^−e that brings max|M_ij| into [0.5, 1) when it lies outside
 * [2^−256, 2^256] (e = 0 and a plain copy otherwise): the coherency matrix sums entries and the
 * filter squares them, which overflow for M ~ 1e308 and lose everything for M ~ 1e-310; the
 * quantities below are scale-invariant or scale back exactly. Returns e. */
static int pc_mueller_scaled(const double M[4][4], double S[4][4])
{
	const int e = pc_mat4_scale_exp(M);
	if (!e) {
		memcpy(S, M, 16 * sizeof(double));
		return 0;
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			S[i][j] = ldexp(M[i][j], -e);
	return e;
}

bool pc_mueller_is_physical(const double M_in[4][4], double tol)
{
	double M[4][4];
	pc_mueller_scaled(M_in, M);
	/* λ_min(H) ≥ −tol·tr H  ⇔  H + tol·tr H·I is positive definite  ⇔  its LDLᴴ factorisation
	 * has positive pivots (Hermitian Cholesky without pivoting). */
	double Hr[4][4], Hi[4][4];
	pc_mueller_coherency(M, Hr, Hi);
	double tr = Hr[0][0] + Hr[1][1] + Hr[2][2] + Hr[3][3];
	if (!(tr > 0))
		return false;
	double complex L[4][4];
	double d[4];
	const double eps = tol * tr;
	for (int j = 0; j < 4; j++) {
		double dj = Hr[j][j] + eps;
		for (int k = 0; k < j; k++)
			dj -= creal(L[j][k] * conj(L[j][k])) * d[k];
		if (!(dj > 0))
			return false;
		d[j] = dj;
		for (int i = j + 1; i < 4; i++) {
			/* H_ij = Σ_k L_ik d_k conj(L_jk); Hermitian part of H */
			double complex hij =
			    0.5 * (Hr[i][j] + Hr[j][i]) + 0.5 * I * (Hi[i][j] - Hi[j][i]);
			for (int k = 0; k < j; k++)
				hij -= L[i][k] * d[k] * conj(L[j][k]);
			L[i][j] = hij / dj;
		}
	}
	return true;
}

void pc_coherency_to_mueller(const double H_re[4][4], const double H_im[4][4], double M[4][4])
{
	double complex A[4][4], Ai[4][4], N[4][4], T[4][4], R[4][4];
	pc_stokes_A(A, Ai);
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 2; b++)
			for (int c = 0; c < 2; c++)
				for (int d = 0; d < 2; d++)
					N[2 * a + b][2 * c + d] = H_re[2 * a + c][2 * b + d] +
					                          I * H_im[2 * a + c][2 * b + d];
	pc_cmul4(A, N, T);
	pc_cmul4(T, Ai, R);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			M[i][j] = creal(R[i][j]);
}

/* Cyclic Jacobi for a 4×4 Hermitian matrix H = Hr + i Hi (in place; H becomes diagonal, V = Vr
 * + i Vi collects the eigenvectors as columns when non-NULL). Each step zeroes H_pq = |h|e^{iα}
 * with U = D R: D = diag(1, e^{−iα}) on (p, q) makes the pair real, R is the real Jacobi
 * rotation. Complex arithmetic spelt out in real and imaginary parts; |h| = sqrt(h_r² + h_i²)
 * assumes max|H_ij| near 1 (pc_herm_load scales by a power of two). */
static void pc_jacobi_herm4(double Hr[4][4], double Hi[4][4], double Vr[4][4], double Vi[4][4])
{
	if (Vr)
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				Vr[i][j] = i == j;
				Vi[i][j] = 0;
			}
	double frob = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			frob += Hr[i][j] * Hr[i][j] + Hi[i][j] * Hi[i][j];
	for (int sweep = 0; sweep < 50; sweep++) {
		double off = 0;
		for (int p = 0; p < 4; p++)
			for (int q = p + 1; q < 4; q++)
				off += Hr[p][q] * Hr[p][q] + Hi[p][q] * Hi[p][q];
		if (off <= 1e-34 * frob || off == 0)
			break;
		for (int p = 0; p < 4; p++)
			for (int q = p + 1; q < 4; q++) {
				double hm = sqrt(Hr[p][q] * Hr[p][q] + Hi[p][q] * Hi[p][q]);
				if (hm == 0)
					continue;
				const double er = Hr[p][q] / hm, ei = Hi[p][q] / hm; /* e^{iα} */
				const double app = Hr[p][p], aqq = Hr[q][q];
				double th = (aqq - app) / (2 * hm);
				double t = fabs(th) > 1e150 ? 0.5 / th
				                            : (th >= 0 ? 1 : -1) /
				                                  (fabs(th) + sqrt(th * th + 1));
				double c = 1 / sqrt(t * t + 1), sn = t * c;
				/* H ← Uᴴ H U with U = [[c, s], [−s e^{−iα}, c e^{−iα}]] on (p, q).
				 * Outside the (p, q) block only columns p, q change through H U
				 * (rows p, q through Uᴴ H are their conjugates: H stays Hermitian);
				 * the block itself becomes diag(app − t|h|, aqq + t|h|). */
				for (int k = 0; k < 4; k++) {
					if (k == p || k == q)
						continue;
					double xr = Hr[k][p], xi = Hi[k][p];
					double yr =
					    Hr[k][q] * er + Hi[k][q] * ei; /* H_kq e^{−iα} */
					double yi = Hi[k][q] * er - Hr[k][q] * ei;
					Hr[k][p] = Hr[p][k] = c * xr - sn * yr;
					Hi[k][p] = c * xi - sn * yi;
					Hi[p][k] = -Hi[k][p];
					Hr[k][q] = Hr[q][k] = sn * xr + c * yr;
					Hi[k][q] = sn * xi + c * yi;
					Hi[q][k] = -Hi[k][q];
				}
				Hr[p][p] = app - t * hm;
				Hr[q][q] = aqq + t * hm;
				Hi[p][p] = Hi[q][q] = 0;
				Hr[p][q] = Hr[q][p] = Hi[p][q] = Hi[q][p] = 0;
				if (Vr)
					for (int k = 0; k < 4; k++) {
						double xr = Vr[k][p], xi = Vi[k][p];
						double yr = Vr[k][q] * er + Vi[k][q] * ei;
						double yi = Vi[k][q] * er - Vr[k][q] * ei;
						Vr[k][p] = c * xr - sn * yr;
						Vi[k][p] = c * xi - sn * yi;
						Vr[k][q] = sn * xr + c * yr;
						Vi[k][q] = sn * xi + c * yi;
					}
			}
	}
}

/* The Hermitian part of H_re + i H_im, times a power of two s (returned) that brings max|H_ij|
 * near 1 (exact; keeps the squares in pc_jacobi_herm4 clear of overflow and underflow). */
static double pc_herm_load(const double H_re[4][4], const double H_im[4][4], double Hr[4][4],
                           double Hi[4][4])
{
	double mx = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			Hr[i][j] = 0.5 * (H_re[i][j] + H_re[j][i]);
			Hi[i][j] = 0.5 * (H_im[i][j] - H_im[j][i]);
			mx = fmax(mx, fmax(fabs(Hr[i][j]), fabs(Hi[i][j])));
		}
	double s = 1;
	if (mx > 0 && isfinite(mx)) {
		int e;
		frexp(mx, &e);
		s = ldexp(1.0, -e);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				Hr[i][j] *= s;
				Hi[i][j] *= s;
			}
	}
	return s;
}

static int pc_cmp_double(const void *x, const void *y)
{
	double a = *(const double *)x, b = *(const double *)y;
	return (a > b) - (a < b);
}

void pc_hermitian4_eig(const double H_re[4][4], const double H_im[4][4], double eval[4],
                       double V_re[4][4], double V_im[4][4])
{
	double Hr[4][4], Hi[4][4];
	double s = pc_herm_load(H_re, H_im, Hr, Hi);
	pc_jacobi_herm4(Hr, Hi, V_re, V_im);
	for (int i = 0; i < 4; i++)
		eval[i] = Hr[i][i] / s;
}

void pc_hermitian4_eigvals(const double H_re[4][4], const double H_im[4][4], double eval[4])
{
	pc_hermitian4_eig(H_re, H_im, eval, NULL, NULL);
	qsort(eval, 4, sizeof eval[0], pc_cmp_double);
}

double pc_mueller_min_coherency_eig(const double M_in[4][4])
{
	double M[4][4], Hr[4][4], Hi[4][4], ev[4];
	pc_mueller_scaled(M_in, M);
	pc_mueller_coherency(M, Hr, Hi);
	double tr = Hr[0][0] + Hr[1][1] + Hr[2][2] + Hr[3][3];
	if (!(tr > 0))
		return NAN;
	pc_hermitian4_eigvals(Hr, Hi, ev);
	return ev[0] / tr;
}

void pc_mueller_cloude_filter(const double M_in[4][4], double out[4][4], bool *changed)
{
	double M[4][4], Hr[4][4], Hi[4][4], Vr[4][4], Vi[4][4];
	const int e = pc_mueller_scaled(M_in, M);
	pc_mueller_coherency(M, Hr, Hi);
	double tr = Hr[0][0] + Hr[1][1] + Hr[2][2] + Hr[3][3];
	double lam[4], lmin = INFINITY;
	pc_hermitian4_eig(Hr, Hi, lam, Vr, Vi);
	for (int i = 0; i < 4; i++)
		if (lam[i] < lmin)
			lmin = lam[i];
	bool ch = !(lmin >= -PC_PHYS_TOL * fabs(tr));
	if (changed)
		*changed = ch;
	if (!ch) {
		if (out != M_in)
			memcpy(out, M_in, 16 * sizeof(double));
		return;
	}
	/* H' = Σ max(λ_k, 0) v_k v_kᴴ */
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double ar = 0, ai = 0;
			for (int k = 0; k < 4; k++)
				if (lam[k] > 0) {
					/* v_ik conj(v_jk) */
					ar += lam[k] * (Vr[i][k] * Vr[j][k] + Vi[i][k] * Vi[j][k]);
					ai += lam[k] * (Vi[i][k] * Vr[j][k] - Vr[i][k] * Vi[j][k]);
				}
			Hr[i][j] = ar;
			Hi[i][j] = ai;
		}
	pc_coherency_to_mueller(Hr, Hi, out);
	if (e)
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				out[i][j] = ldexp(out[i][j], e);
}

double pc_mueller_depol_index(const double M_in[4][4])
{
	if (!(M_in[0][0] > 0))
		return NAN;
	double M[4][4];
	pc_mueller_scaled(M_in, M);
	double s = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			s += M[i][j] * M[i][j];
	double v = (s - M[0][0] * M[0][0]) / (3 * M[0][0] * M[0][0]);
	return sqrt(v > 0 ? v : 0);
}

double pc_atan2(double y, double x)
{
	if (!isfinite(x) || !isfinite(y))
		return NAN;
	double ax = fabs(x), ay = fabs(y);
	if (ax == 0 && ay == 0)
		return signbit(x) ? (signbit(y) ? -PC_PI : PC_PI) : y;
	double a = pc_atan2_q1(ay, ax);
	if (x < 0)
		a = PC_PI - a;
	return signbit(y) ? -a : a;
}

void pc_sincos_deg(double deg, double *s, double *c)
{
	if (!isfinite(deg)) {
		*s = *c = NAN;
		return;
	}
	double r = fmod(deg, 360.0); /* exact, |r| < 360 */
	if (r < 0)
		r += 360.0; /* [0, 360]: the rounding of r + 360 keeps the angle within an ulp */
	double q = nearbyint(r / 90.0); /* 0..4 */
	double d = r - 90.0 * q;        /* exact (Sterbenz), |d| ≤ 45 */
	double x = d * (PC_PI / 180.0);
	double sd = sin(x), cd = cos(x);
	switch ((int)q & 3) {
	case 0:
		*s = sd;
		*c = cd;
		break;
	case 1:
		*s = cd;
		*c = -sd;
		break;
	case 2:
		*s = -sd;
		*c = -cd;
		break;
	default:
		*s = -cd;
		*c = sd;
		break;
	}
	if (*s == 0)
		*s = 0.0; /* no −0 */
	if (*c == 0)
		*c = 0.0;
}
