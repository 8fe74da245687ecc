/* Lu–Chipman polar decomposition M = M_Δ M_R M_D (docs/physics.md §3, hard cases §4; paper
 * eqs. 13–20; Lu & Chipman, JOSA A 13(5) 1106, 1996).
 *
 * The polar factor of the 3×3 block m' is computed without an SVD: the rotation Q closest to
 * B = ±m' (sign chosen so that det B ≥ 0, the Lu–Chipman sign rule) maximises tr(Qᵀ B) and is
 * the rotation of the unit quaternion q that maximises qᵀ K q, K the traceless symmetric 4×4
 * matrix built linearly from B (Davenport's q-method; Horn, JOSA A 4(4) 629, 1987). The largest
 * eigenvalue of K is λ₁ = σ₁ + σ₂ + σ₃ (singular values of B) = |tr m_Δ|, found by Newton's method
 * on the characteristic quartic λ⁴ − 2‖B‖²λ² − 8 det(B) λ + 2‖BᵀB‖² − ‖B‖⁴ started above the
 * largest root, and q is a column of adj(K − λ₁I). This equals the SVD route of physics.md §3
 * (m_R = UVᵀ, m_Δ = UΣUᵀ, both negated when det m' < 0): tests compare it with a long-double
 * Jacobi SVD. Retardance R = 2·atan2(|q_v|, |q_w|), exact near 0 and π (physics.md §3).
 */
#include "polarcam/decompose.h"

#include <math.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "decompose_internal.h"
#include "optics_inline.h"

static double det3(const double a[3][3])
{
	return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
	       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
	       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

/* Rotation closest to B (det B ≥ 0 assumed): quaternion q = (w, x, y, z) with w ≥ 0 and
 * λ₁ = σ₁ + σ₂ + σ₃. Returns false when q is not determined (λ₁ not a simple eigenvalue). */
static bool pc_closest_rotation(const double B[3][3], double det, double q[4], double *lambda1)
{
	/* F = ‖B‖²_F = Σσ², G = ‖BᵀB‖²_F = Σσ⁴ from the entries of BᵀB */
	const double b00 = B[0][0] * B[0][0] + B[1][0] * B[1][0] + B[2][0] * B[2][0];
	const double b11 = B[0][1] * B[0][1] + B[1][1] * B[1][1] + B[2][1] * B[2][1];
	const double b22 = B[0][2] * B[0][2] + B[1][2] * B[1][2] + B[2][2] * B[2][2];
	const double b01 = B[0][0] * B[0][1] + B[1][0] * B[1][1] + B[2][0] * B[2][1];
	const double b02 = B[0][0] * B[0][2] + B[1][0] * B[1][2] + B[2][0] * B[2][2];
	const double b12 = B[0][1] * B[0][2] + B[1][1] * B[1][2] + B[2][1] * B[2][2];
	const double F = b00 + b11 + b22;
	const double G =
	    b00 * b00 + b11 * b11 + b22 * b22 + 2 * (b01 * b01 + b02 * b02 + b12 * b12);
	const double c2 = -2 * F, c1 = -8 * det, c0 = 2 * G - F * F;
	/* Newton from λ₀ = sqrt(3F) ≥ σ₁ + σ₂ + σ₃ (Cauchy–Schwarz): monotone for a real-rooted
	 * polynomial started above its largest root. */
	double lam = sqrt(3 * F), prev = lam;
	const double stop = 4e-16 * lam;
	for (int it = 0; it < 200 && lam > 0; it++) {
		double l2 = lam * lam;
		double p = (l2 + c2) * l2 + c1 * lam + c0;
		double dp = (4 * l2 + 2 * c2) * lam + c1;
		if (!(p > 0) || !(dp > 0))
			break;
		double step = p / dp;
		lam -= step;
		/* Stop at a step of one ulp, or earlier once convergence is visibly quadratic: the
		 * next error is then ≈ step³/prev² < 1e-16·λ (step ≤ 1e-8·λ and step ≤ 1e-4·prev).
		 */
		if (step <= stop || (step <= 1e-8 * lam && step <= 1e-4 * prev))
			break;
		prev = step;
	}
	*lambda1 = lam;
	/* K − λ₁I, K from tr(Qᵀ B) = qᵀ K q with Q(q) the active rotation matrix of q. */
	const double kwx = B[2][1] - B[1][2], kwy = B[0][2] - B[2][0], kwz = B[1][0] - B[0][1];
	const double kxy = B[0][1] + B[1][0], kxz = B[0][2] + B[2][0], kyz = B[1][2] + B[2][1];
	const double A[4][4] = {
	    {B[0][0] + B[1][1] + B[2][2] - lam, kwx, kwy, kwz},
	    {kwx, B[0][0] - B[1][1] - B[2][2] - lam, kxy, kxz},
	    {kwy, kxy, -B[0][0] + B[1][1] - B[2][2] - lam, kyz},
	    {kwz, kxz, kyz, -B[0][0] - B[1][1] + B[2][2] - lam},
	};
	/* adj(A) = c q qᵀ for a simple eigenvalue: take the row of the cofactor matrix with the
	 * largest diagonal cofactor (all have one sign). Cofactors by Laplace expansion over the
	 * 2×2 minors of rows (0, 1) (S_ij) and rows (2, 3) (C_ij): removing row r leaves a 3×3
	 * whose determinant expands along its remaining row of the other pair. */
	const double S01 = A[0][0] * A[1][1] - A[0][1] * A[1][0],
	             S02 = A[0][0] * A[1][2] - A[0][2] * A[1][0],
	             S03 = A[0][0] * A[1][3] - A[0][3] * A[1][0],
	             S12 = A[0][1] * A[1][2] - A[0][2] * A[1][1],
	             S13 = A[0][1] * A[1][3] - A[0][3] * A[1][1],
	             S23 = A[0][2] * A[1][3] - A[0][3] * A[1][2];
	const double C01 = A[2][0] * A[3][1] - A[2][1] * A[3][0],
	             C02 = A[2][0] * A[3][2] - A[2][2] * A[3][0],
	             C03 = A[2][0] * A[3][3] - A[2][3] * A[3][0],
	             C12 = A[2][1] * A[3][2] - A[2][2] * A[3][1],
	             C13 = A[2][1] * A[3][3] - A[2][3] * A[3][1],
	             C23 = A[2][2] * A[3][3] - A[2][3] * A[3][2];
	double diag[4] = {
	    A[1][1] * C23 - A[1][2] * C13 + A[1][3] * C12,
	    A[0][0] * C23 - A[0][2] * C03 + A[0][3] * C02,
	    A[3][0] * S13 - A[3][1] * S03 + A[3][3] * S01,
	    A[2][0] * S12 - A[2][1] * S02 + A[2][2] * S01,
	};
	int jb = 0;
	for (int j = 1; j < 4; j++)
		if (fabs(diag[j]) > fabs(diag[jb]))
			jb = j;
	if (!(fabs(diag[jb]) > 0)) {
		q[0] = 1;
		q[1] = q[2] = q[3] = 0;
		return false;
	}
	/* row jb of the cofactor matrix: (−1)^{jb+c} d_c with d_c the 3×3 minor expansion */
	const double *r = A[jb == 0 ? 1 : jb == 1 ? 0 : jb == 2 ? 3 : 2];
	double X01, X02, X03, X12, X13, X23;
	if (jb < 2) {
		X01 = C01, X02 = C02, X03 = C03, X12 = C12, X13 = C13, X23 = C23;
	} else {
		X01 = S01, X02 = S02, X03 = S03, X12 = S12, X13 = S13, X23 = S23;
	}
	double sg = (jb & 1) ? -1 : 1;
	q[0] = sg * (r[1] * X23 - r[2] * X13 + r[3] * X12);
	q[1] = -sg * (r[0] * X23 - r[2] * X03 + r[3] * X02);
	q[2] = sg * (r[0] * X13 - r[1] * X03 + r[3] * X01);
	q[3] = -sg * (r[0] * X12 - r[1] * X02 + r[2] * X01);
	/* left unnormalised (R, the axis, δ and ψ are ratios; the caller normalises when it builds
	 * m_R); only the sign is fixed: w ≥ 0 */
	if (q[0] < 0)
		for (int i = 0; i < 4; i++)
			q[i] = -q[i];
	return q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] > 0;
}

static void pc_quat_to_rot(const double q[4], double Q[3][3])
{
	double w = q[0], x = q[1], y = q[2], z = q[3];
	Q[0][0] = w * w + x * x - y * y - z * z;
	Q[0][1] = 2 * (x * y - w * z);
	Q[0][2] = 2 * (x * z + w * y);
	Q[1][0] = 2 * (x * y + w * z);
	Q[1][1] = w * w - x * x + y * y - z * z;
	Q[1][2] = 2 * (y * z - w * x);
	Q[2][0] = 2 * (x * z - w * y);
	Q[2][1] = 2 * (y * z + w * x);
	Q[2][2] = w * w - x * x - y * y + z * z;
}

static void pc_fill_nan4(double M[4][4])
{
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			M[i][j] = NAN;
}

int pc_lu_chipman_decompose(const double M_in[4][4], unsigned options, pc_lu_chipman *out)
{
	if (!M_in || !out)
		return pc_error(PC_EINVAL, "pc_lu_chipman_decompose: NULL argument");
	/* one test for all 16: x·0 is NaN exactly for non-finite x */
	const double *mi = &M_in[0][0];
	double z0 = 0, z1 = 0, z2 = 0, z3 = 0; /* four chains: no 16-deep add latency */
	for (int i = 0; i < 16; i += 4) {
		z0 += mi[i] * 0.0;
		z1 += mi[i + 1] * 0.0;
		z2 += mi[i + 2] * 0.0;
		z3 += mi[i + 3] * 0.0;
	}
	if ((z0 + z1) + (z2 + z3) != 0)
		for (int i = 0; i < 16; i++)
			if (!isfinite(mi[i]))
				return pc_error(PC_EINVAL, "M[%d][%d] = %g: not a finite number",
				                i / 4, i % 4, mi[i]);
	const bool factors = !(options & PC_LC_NO_FACTORS);
	const bool filter = options & PC_LC_FILTER;
	out->m00 = M_in[0][0];
	out->D = out->R = out->R_linear = out->R_circular = out->Delta = out->depol_index = NAN;
	for (int i = 0; i < 3; i++)
		out->D_vec[i] = out->R_axis[i] = NAN;
	if (factors) { /* with PC_LC_NO_FACTORS the factor matrices are not written at all */
		pc_fill_nan4(out->M_D);
		pc_fill_nan4(out->M_R);
		pc_fill_nan4(out->M_Delta);
	}
	out->physical = false;
	out->filtered = false;
	out->flags = 0;

	double M[4][4];
	memcpy(M, M_in, sizeof M);
	if (!(M[0][0] > 0)) {
		out->flags |= PC_LC_ZERO_M00;
		return 0;
	}
	/* Far from 1 (a physical matrix times 1e308 overflows the coherency matrix's sums; M00 =
	 * 1e-310 makes 1/M00 infinite): scale by the power of two 2^−e that brings max|M_ij| into
	 * [0.5, 1). Exact, and the factors, D, R and Δ are of M/M00, so nothing else changes;
	 * inside [2^−256, 2^256] the matrix is left alone (bit-identical results, and
	 * pc_lu_chipman_map's vector kernel hands the rest to this code). */
	{
		const int e = pc_mat4_scale_exp(M_in);
		if (e)
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					M[i][j] = ldexp(M_in[i][j], -e);
	}
	if (factors || filter) {
		/* realisability: coherency matrix positive semi-definite (physics.md §4) */
		out->physical = pc_mueller_is_physical(M, PC_PHYS_TOL);
		if (!out->physical) {
			out->flags |= PC_LC_NONPHYSICAL;
			if (filter) {
				bool changed;
				pc_mueller_cloude_filter(M, M, &changed);
				out->filtered = changed;
				if (changed)
					out->flags |= PC_LC_FILTERED;
				if (!(M[0][0] > 0)) {
					out->flags |= PC_LC_ZERO_M00;
					return 0;
				}
			}
		}
	}

	/* normalise (the paper's eq. 20 assumes M00 = 1) */
	const double inv00 = 1 / M[0][0];
	double Dv[3] = {M[0][1] * inv00, M[0][2] * inv00, M[0][3] * inv00};
	double P[3] = {M[1][0] * inv00, M[2][0] * inv00, M[3][0] * inv00};
	double m3[3][3];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			m3[i][j] = M[i + 1][j + 1] * inv00;
	double D2 = Dv[0] * Dv[0] + Dv[1] * Dv[1] + Dv[2] * Dv[2];
	double D = sqrt(D2); /* eq. 20 */
	/* Gil–Bernabeu depolarisation index from the normalised matrix:
	 * sqrt((Σ m_ij² − 1)/3) */
	double s2 = D2 + P[0] * P[0] + P[1] * P[1] + P[2] * P[2];
	for (int i = 0; i < 3; i++)
		s2 += m3[i][0] * m3[i][0] + m3[i][1] * m3[i][1] + m3[i][2] * m3[i][2];
	out->depol_index = sqrt(s2 / 3);
	if (filter && D > 1) {
		/* a filtered matrix is physical: D > 1 can only be rounding */
		double s = 1 / D;
		for (int i = 0; i < 3; i++)
			Dv[i] *= s;
		D = 1;
		out->flags |= PC_LC_CLAMPED;
	}
	out->D = D;
	memcpy(out->D_vec, Dv, sizeof Dv);

	double Dh[3] = {0, 0, 0};
	if (D > 0) {
		const double iD = 1 / D;
		for (int i = 0; i < 3; i++)
			Dh[i] = Dv[i] * iD;
	}
	const double omd2 = (1 - D) * (1 + D); /* 1 − D², without cancellation near D = 1 */
	const double sq = sqrt(omd2 > 0 ? omd2 : 0);
	if (factors) {
		/* M_D = [[1, Dᵀ], [D, m_D]], m_D = sqrt(1−D²) I + (1 − sqrt(1−D²)) D̂D̂ᵀ (eq. 16) */
		memset(out->M_D, 0, sizeof out->M_D);
		out->M_D[0][0] = 1;
		for (int i = 0; i < 3; i++) {
			out->M_D[0][i + 1] = out->M_D[i + 1][0] = Dv[i];
			for (int j = 0; j < 3; j++)
				out->M_D[i + 1][j + 1] =
				    (i == j ? sq : 0) + (1 - sq) * Dh[i] * Dh[j];
		}
	}
	if (D >= PC_LC_D_MAX) {
		/* M_D is singular: R and Δ are undefined, never divided out (physics.md §4) */
		out->flags |= PC_LC_D_SINGULAR;
		return 0;
	}

	/* M' = m M_D⁻¹ with M_D⁻¹ = [[1, −Dᵀ], [−D, m_D]]/(1 − D²) (physics.md §3):
	 * m' = (m m_D − P Dᵀ)/(1 − D²) with m m_D = sq·m + (1 − sq)(m D̂) D̂ᵀ,
	 * P_Δ = (P − m D)/(1 − D²) (eq. 17). */
	const double inv = 1 / omd2;
	double mD[3], mp[3][3], PD[3];
	const double sqi = sq * inv, u = (1 - sq) * inv;
	for (int i = 0; i < 3; i++) {
		mD[i] = m3[i][0] * Dh[0] + m3[i][1] * Dh[1] + m3[i][2] * Dh[2];
		PD[i] = (P[i] - D * mD[i]) * inv;
		/* m'_ij = sq/(1−D²)·m_ij + ((1 − sq)(mD̂)_i D̂_j − P_i D_j)/(1−D²); P D = D P D̂ */
		const double gi = u * mD[i] - inv * D * P[i];
		mp[i][0] = sqi * m3[i][0] + gi * Dh[0];
		mp[i][1] = sqi * m3[i][1] + gi * Dh[1];
		mp[i][2] = sqi * m3[i][2] + gi * Dh[2];
	}

	/* Lu–Chipman sign rule: det m' < 0 → m_R = −UVᵀ, m_Δ = −UΣUᵀ; B = sign·m' has det ≥ 0 */
	double detmp = det3(mp);
	double sgn = detmp < 0 ? -1 : 1;
	const double B[3][3] = {
	    {sgn * mp[0][0], sgn * mp[0][1], sgn * mp[0][2]},
	    {sgn * mp[1][0], sgn * mp[1][1], sgn * mp[1][2]},
	    {sgn * mp[2][0], sgn * mp[2][1], sgn * mp[2][2]},
	};
	/* the polar factor does not depend on scale: outside [1e-30, 1e30] work with B scaled by a
	 * power of two near 1/max|B_ij| (exact), so that nearly fully depolarising matrices
	 * (m' ~ 1e-74 happens off the specular lobe) neither underflow (quartic terms ~ B⁸) nor
	 * lose the quaternion; inside, no division on the common path */
	double bmax = 0;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) { /* B is finite: a compare, not a call to fmax */
			const double a = fabs(B[i][j]);
			bmax = a > bmax ? a : bmax;
		}
	double q[4] = {1, 0, 0, 0}, lam1 = 0;
	bool unique = false;
	if (bmax > 0) {
		/* ldexp per element, not a multiplication by 2^−e: for a subnormal bmax (a
		 * normalised m33 of 1e-310) 2^−e itself overflows */
		int e = 0;
		if (bmax < 1e-30 || bmax > 1e30)
			frexp(bmax, &e);
		double Bn[3][3];
		memcpy(Bn, B, sizeof Bn);
		if (e) /* ldexp is a call: only on the rare rescaled path */
			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					Bn[i][j] = ldexp(B[i][j], -e);
		unique = pc_closest_rotation((const double(*)[3])Bn,
		                             fabs(det3((const double(*)[3])Bn)), q, &lam1);
		if (e)
			lam1 = ldexp(lam1, e);
	}
	if (!unique || fabs(detmp) <= PC_LC_NONUNIQUE_DET * (lam1 / 3) * (lam1 / 3) * (lam1 / 3) ||
	    !(lam1 > 0))
		out->flags |= PC_LC_R_NONUNIQUE;

	/* Δ = 1 − |tr m_Δ|/3 (eq. 18); |tr m_Δ| = σ₁ + σ₂ + σ₃ = λ₁ */
	double Delta = 1 - lam1 / 3;
	if (filter && (Delta < 0 || Delta > 1)) {
		Delta = Delta < 0 ? 0 : 1;
		out->flags |= PC_LC_CLAMPED;
	}
	out->Delta = Delta;

	/* Retardance from the quaternion: R = 2 atan2(|v|, w), w ≥ 0 (physics.md §3's atan2 form:
	 * ½‖a‖ = 2w|v|·… and (tr m_R − 1)/2 = w² − |v|²). Axis a = (m_R[1,2] − m_R[2,1], …)/‖·‖
	 * = −v/|v| (physics.md §3). Linear retardance δ and optical rotation ψ from
	 * q = q_lin ⊗ q_circ, i.e. m_R = m_LR(δ) · m_CR(ψ), m_CR rotating the plane of polarisation
	 * by +ψ (from s towards p): cos(δ/2) = sqrt(w² + z²), ψ = atan2(z, w). */
	double w = q[0], vx = q[1], vy = q[2], vz = q[3];
	double vn = sqrt(vx * vx + vy * vy + vz * vz);
	out->R = vn > 0 ? 2 * pc_atan2_q1(vn, w) : 0; /* w ≥ 0 */
	if (vn > 0) {
		out->R_axis[0] = -vx / vn;
		out->R_axis[1] = -vy / vn;
		out->R_axis[2] = -vz / vn;
	}
	double vl = sqrt(vx * vx + vy * vy);
	out->R_linear = vl > 0 ? 2 * pc_atan2_q1(vl, sqrt(w * w + vz * vz)) : 0;
	out->R_circular = vz == 0 ? 0 : vz > 0 ? pc_atan2_q1(vz, w) : -pc_atan2_q1(-vz, w);

	if (factors) {
		double Q[3][3];
		double qn = 1 / sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
		const double qu[4] = {q[0] * qn, q[1] * qn, q[2] * qn, q[3] * qn};
		pc_quat_to_rot(qu, Q);
		memset(out->M_R, 0, sizeof out->M_R);
		memset(out->M_Delta, 0, sizeof out->M_Delta);
		out->M_R[0][0] = out->M_Delta[0][0] = 1;
		/* m_Δ = m' m_Rᵀ, symmetrised (it is symmetric up to rounding) */
		double md[3][3];
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++) {
				out->M_R[i + 1][j + 1] = Q[i][j];
				md[i][j] =
				    mp[i][0] * Q[j][0] + mp[i][1] * Q[j][1] + mp[i][2] * Q[j][2];
			}
		for (int i = 0; i < 3; i++) {
			out->M_Delta[i + 1][0] = PD[i];
			for (int j = 0; j < 3; j++)
				out->M_Delta[i + 1][j + 1] = 0.5 * (md[i][j] + md[j][i]);
		}
	}
	return 0;
}
