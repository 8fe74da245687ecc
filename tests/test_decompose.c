/* Lu–Chipman decomposition (physics.md §3, §4) against (1) the known factors of random products
 * M = m00 · M_Δ M_R M_D (12 000 round trips, including degenerate spectra, D → 1, det < 0, R at 0
 * and π), and (2) a slow, obviously correct reference written here: the 4×4 product with the
 * analytic M_D⁻¹ and a one-sided Jacobi SVD of m', all in long double, on noisy non-physical
 * and random matrices. Cloude filtering is checked by its projection property. */
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "lc_cases.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"

/* ---------------------------------------------------------------------------------------- */
/* slow reference in long double */

typedef long double ld;

typedef struct ref_lc {
	ld D, R, Delta;
	ld mR[3][3];
	bool singular;
} ref_lc;

static ld det3l(ld a[3][3])
{
	return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
	       a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
	       a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

static void ref_decompose(const double Min[4][4], ref_lc *r)
{
	ld m[4][4];
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			m[i][j] = (ld)Min[i][j] / (ld)Min[0][0];
	ld D = sqrtl(m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[0][3] * m[0][3]);
	r->D = D;
	r->singular = D >= 1 - 1e-6L;
	if (r->singular)
		return;
	/* M_D⁻¹ = [[1, −Dᵀ], [−D, m_D]]/(1 − D²) as a full 4×4, then M' = m M_D⁻¹ */
	ld s = sqrtl(1 - D * D), Mi[4][4], Mp[4][4];
	Mi[0][0] = 1;
	for (int i = 0; i < 3; i++) {
		Mi[0][i + 1] = Mi[i + 1][0] = -m[0][i + 1];
		for (int j = 0; j < 3; j++)
			Mi[i + 1][j + 1] =
			    (i == j ? s : 0) +
			    (D > 0 ? (1 - s) * m[0][i + 1] * m[0][j + 1] / (D * D) : 0);
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			ld acc = 0;
			for (int k = 0; k < 4; k++)
				acc += m[i][k] * Mi[k][j];
			Mp[i][j] = acc / (1 - D * D);
		}
	/* one-sided Jacobi SVD of m' = A: rotate columns until orthogonal, A V = U Σ */
	ld A[3][3], V[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			A[i][j] = Mp[i + 1][j + 1];
	ld detA = det3l(A);
	for (int sweep = 0; sweep < 100; sweep++) {
		ld off = 0;
		for (int p = 0; p < 3; p++)
			for (int q = p + 1; q < 3; q++) {
				ld al = 0, be = 0, ga = 0;
				for (int k = 0; k < 3; k++) {
					al += A[k][p] * A[k][p];
					be += A[k][q] * A[k][q];
					ga += A[k][p] * A[k][q];
				}
				if (ga == 0)
					continue;
				off = fmaxl(off, fabsl(ga) / sqrtl(al * be));
				ld ze = (be - al) / (2 * ga);
				ld t = (ze >= 0 ? 1 : -1) / (fabsl(ze) + sqrtl(1 + ze * ze));
				ld c = 1 / sqrtl(1 + t * t), sn = c * t;
				for (int k = 0; k < 3; k++) {
					ld x = A[k][p], y = A[k][q];
					A[k][p] = c * x - sn * y;
					A[k][q] = sn * x + c * y;
					x = V[k][p];
					y = V[k][q];
					V[k][p] = c * x - sn * y;
					V[k][q] = sn * x + c * y;
				}
			}
		if (off < 1e-30L)
			break;
	}
	ld sum = 0, U[3][3];
	for (int j = 0; j < 3; j++) {
		ld n = sqrtl(A[0][j] * A[0][j] + A[1][j] * A[1][j] + A[2][j] * A[2][j]);
		sum += n;
		for (int k = 0; k < 3; k++)
			U[k][j] = A[k][j] / n;
	}
	/* sign rule: det m' < 0 → m_R = −UVᵀ (physics.md §3) */
	ld sg = detA < 0 ? -1 : 1;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			r->mR[i][j] =
			    sg * (U[i][0] * V[j][0] + U[i][1] * V[j][1] + U[i][2] * V[j][2]);
	r->Delta = 1 - sum / 3;
	/* R = atan2(½‖a‖, (tr m_R − 1)/2) (physics.md §3) */
	ld a0 = r->mR[1][2] - r->mR[2][1], a1 = r->mR[2][0] - r->mR[0][2],
	   a2 = r->mR[0][1] - r->mR[1][0];
	r->R = atan2l(0.5L * sqrtl(a0 * a0 + a1 * a1 + a2 * a2),
	              (r->mR[0][0] + r->mR[1][1] + r->mR[2][2] - 1) / 2);
}

/* ---------------------------------------------------------------------------------------- */

typedef struct stats {
	const char *name;
	double dD, dR, dDelta, dAxis, dRecomp, dFactors;
	int n;
} stats;

static void report(const stats *s)
{
	printf("%-28s n=%5d  |dD| %.1e  |dR| %.1e  |dDelta| %.1e  axis %.1e  recomposition %.1e  "
	       "factors %.1e\n",
	       s->name, s->n, s->dD, s->dR, s->dDelta, s->dAxis, s->dRecomp, s->dFactors);
}

/* One round trip from known factors. Stated tolerances (tol_scale = 1, measured worst ~1e-15):
 * D 1e-13, R and Δ 1e-12, axis 1e-10 (R in (1e-4, π − 1e-4)), recomposition 1e-13 relative to
 * M00, each factor matrix 1e-12; all × 1e4 for D = 0.99999 and 1 − 2e-6, where the analytic
 * M_D⁻¹ amplifies rounding by 1/(1 − D²) ≤ 2.5e5 (measured: R 6e-11, axis 3e-9). */
static void round_trip(enum lc_kind kind, stats *st, double tol_scale)
{
	lc_case c;
	lc_make_case(kind, &c);
	double(*M)[4] = c.M, (*MD)[4] = c.MD, (*MR)[4] = c.MR, (*MDel)[4] = c.MDel;
	const double *Dv = c.Dv, *lam = c.lam, *ax = c.ax;
	const double Rtrue = c.R, m00 = c.m00;
	pc_lu_chipman lc, fast;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, PC_LC_NO_FACTORS, &fast), 0);
	st->n++;
	double Dt = sqrt(Dv[0] * Dv[0] + Dv[1] * Dv[1] + Dv[2] * Dv[2]);
	double Deltat = 1 - fabs(lam[0] + lam[1] + lam[2]) / 3;
	double eD = fabs(lc.D - Dt), eR = fabs(lc.R - Rtrue), eDel = fabs(lc.Delta - Deltat);
	CHECK_NEAR(lc.m00, m00, 1e-15 * m00);
	CHECK_NEAR(lc.D, Dt, 1e-13);
	CHECK(!(lc.flags & PC_LC_D_SINGULAR));
	CHECK_NEAR(lc.R, Rtrue, 1e-12 * tol_scale);
	CHECK_NEAR(lc.Delta, Deltat, 1e-12 * tol_scale);
	/* the fast path gives the same numbers */
	CHECK_NEAR(fast.R, lc.R, 1e-14 * tol_scale);
	CHECK_NEAR(fast.Delta, lc.Delta, 1e-14);
	CHECK_EQ_INT(fast.flags & ~PC_LC_NONPHYSICAL, lc.flags & ~PC_LC_NONPHYSICAL);
	double eAx = 0;
	if (Rtrue > 1e-4 && Rtrue < PC_PI - 1e-4) {
		for (int i = 0; i < 3; i++)
			eAx = fmax(eAx, fabs(lc.R_axis[i] - ax[i]));
		CHECK_NEAR(eAx, 0, 1e-10 * tol_scale);
	} else if (Rtrue >= PC_PI - 1e-4) { /* axis defined up to sign at π */
		double d = fabs(lc.R_axis[0] * ax[0] + lc.R_axis[1] * ax[1] + lc.R_axis[2] * ax[2]);
		eAx = fabs(d - 1);
		CHECK_NEAR(d, 1, 1e-10 * tol_scale);
	}
	/* recomposition and the factors themselves */
	double Mr[4][4], eRec = 0, eFac = 0;
	pc_mueller_mul(lc.M_Delta, lc.M_R, Mr);
	pc_mueller_mul(Mr, lc.M_D, Mr);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			eRec = fmax(eRec, fabs(Mr[i][j] * lc.m00 - M[i][j]) / m00);
			eFac = fmax(eFac, fabs(lc.M_D[i][j] - MD[i][j]));
			eFac = fmax(eFac, fabs(lc.M_R[i][j] - MR[i][j]));
			eFac = fmax(eFac, fabs(lc.M_Delta[i][j] - MDel[i][j]));
		}
	CHECK_NEAR(eRec, 0, 1e-13 * tol_scale);
	if (Rtrue > 1e-12 || kind != LC_R_EDGES)
		CHECK_NEAR(eFac, 0, 1e-12 * tol_scale);
	st->dD = fmax(st->dD, eD);
	st->dR = fmax(st->dR, eR);
	st->dDelta = fmax(st->dDelta, eDel);
	st->dAxis = fmax(st->dAxis, eAx);
	st->dRecomp = fmax(st->dRecomp, eRec);
	st->dFactors = fmax(st->dFactors, eFac);
}

static void test_round_trips(void)
{
	static const char *names[LC_NKINDS] = {"general",
	                                       "pure diattenuator",
	                                       "pure retarder",
	                                       "isotropic depolariser",
	                                       "two equal eigenvalues",
	                                       "det m' < 0",
	                                       "D = 0.99999, 1 - 2e-6",
	                                       "R at 0 and pi"};
	int total = 0;
	for (int k = 0; k < LC_NKINDS; k++) {
		stats st = {names[k], 0, 0, 0, 0, 0, 0, 0};
		int n = k == LC_GENERAL ? 5000 : 1000;
		/* near D = 1 the analytic M_D⁻¹ amplifies rounding by 1/(1 − D²) ≈ 2.5e5 */
		double scale = k == LC_D_NEAR1 ? 1e4 : 1;
		for (int t = 0; t < n; t++)
			round_trip((enum lc_kind)k, &st, scale);
		report(&st);
		total += st.n;
	}
	CHECK(total >= 10000);
}

/* D = 0.999999 sits on the flag threshold D ≥ 1 − 1e-6: whichever side rounding puts it, the
 * result is either recovered or flagged with NaN, never garbage. D ≥ 1 is always flagged. */
static void test_d_singular(void)
{
	const double Ds[] = {0.999999, 0.9999995, 1.0, 1.0000001};
	for (size_t c = 0; c < sizeof Ds / sizeof Ds[0]; c++) {
		for (int t = 0; t < 200; t++) {
			double n[3], Dv[3], R3[3][3], MD[4][4], MR[4][4], M[4][4];
			unit3(n);
			for (int i = 0; i < 3; i++)
				Dv[i] = Ds[c] * n[i];
			make_MD(Dv, MD);
			if (Ds[c] > 1) /* a non-physical first row on an otherwise valid matrix */
				for (int i = 0; i < 3; i++)
					MD[0][i + 1] = Dv[i];
			double Rt = 0.3 + 2.5 * urand(), ax[3], nn[3];
			unit3(ax);
			for (int i = 0; i < 3; i++)
				nn[i] = -ax[i];
			rodrigues(nn, Rt, R3);
			make_MR(R3, MR);
			pc_mueller_mul(MR, MD, M);
			pc_lu_chipman lc;
			CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
			CHECK_NEAR(lc.D, Ds[c], 1e-12);
			if (lc.flags & PC_LC_D_SINGULAR) {
				CHECK(isnan(lc.R) && isnan(lc.Delta) && isnan(lc.R_axis[0]));
				CHECK(isnan(lc.M_R[1][1]) && isnan(lc.M_Delta[1][1]));
				CHECK(isfinite(lc.M_D[1][1]));
			} else {
				CHECK(Ds[c] < 1 - 1e-7);
				CHECK_NEAR(lc.R, Rt, 1e-6);
				CHECK_NEAR(lc.Delta, 0, 1e-6);
			}
			if (Ds[c] >= 0.9999995)
				CHECK(lc.flags & PC_LC_D_SINGULAR);
		}
	}
}

/* against the long-double reference on noisy, non-physical and arbitrary matrices */
static void test_against_reference(void)
{
	double wD = 0, wR = 0, wDel = 0;
	int nonphys = 0, n = 0;
	for (int t = 0; t < 4000; t++) {
		double Dv[3], nv[3], R3[3][3], U[3][3], lam[3], P[3] = {0, 0, 0};
		unit3(nv);
		double Dm = 0.8 * urand();
		for (int i = 0; i < 3; i++)
			Dv[i] = Dm * nv[i];
		random_rotation(R3);
		random_rotation(U);
		for (int i = 0; i < 3; i++)
			lam[i] = 0.1 + 0.9 * urand();
		double MD[4][4], MR[4][4], MDel[4][4], M[4][4];
		make_MD(Dv, MD);
		make_MR(R3, MR);
		make_MDelta(P, lam, U, MDel);
		pc_mueller_mul(MDel, MR, M);
		pc_mueller_mul(M, MD, M);
		double noise = t % 4 == 0 ? 0.3 : 0.05 * urand();
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				M[i][j] += noise * nrand();
		if (t % 10 == 0) /* arbitrary matrices */
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					M[i][j] = i + j ? nrand() * 0.4 : 1;
		if (!(M[0][0] > 0.2))
			continue;
		ref_lc r = {0};
		ref_decompose(M, &r);
		pc_lu_chipman lc;
		CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
		nonphys += !lc.physical;
		CHECK_NEAR(lc.D, (double)r.D, 1e-14);
		CHECK_EQ_INT(!!(lc.flags & PC_LC_D_SINGULAR), r.singular);
		if (r.singular) {
			CHECK(isnan(lc.R) && isnan(lc.Delta));
			continue;
		}
		n++;
		/* conditioning: rounding in m' is amplified by 1/(1 − D²) and, for R, by
		 * 1/σ_min-type gaps; skip matrices the reference itself calls near-singular */
		double cond = 1 / ((1 - lc.D) * (1 + lc.D));
		if (lc.flags & PC_LC_R_NONUNIQUE)
			continue;
		double eD = fabs(lc.D - (double)r.D), eR = fabs(lc.R - (double)r.R),
		       eDel = fabs(lc.Delta - (double)r.Delta);
		CHECK_NEAR(lc.R, (double)r.R, 1e-12 * cond);
		CHECK_NEAR(lc.Delta, (double)r.Delta, 1e-12 * cond);
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				CHECK_NEAR(lc.M_R[i + 1][j + 1], (double)r.mR[i][j], 1e-12 * cond);
		wD = fmax(wD, eD);
		wR = fmax(wR, eR / cond);
		wDel = fmax(wDel, eDel / cond);
	}
	printf("vs long-double Jacobi SVD: %d matrices (%d non-physical): |dD| %.1e, "
	       "|dR|(1-D^2) %.1e, |dDelta|(1-D^2) %.1e\n",
	       n, nonphys, wD, wR, wDel);
	CHECK(nonphys > 500); /* the noisy set really is non-physical */
}

/* Cloude filter: the filtered matrix is realisable, at least as close to the input as the true
 * physical matrix is (projection in an isometric space), and D, Δ land in [0, 1]. */
static void test_filter(void)
{
	int filtered = 0;
	for (int t = 0; t < 1000; t++) {
		double Dv[3], nv[3], R3[3][3], U[3][3], lam[3], P[3] = {0, 0, 0};
		unit3(nv);
		double Dm = 0.98 * urand();
		for (int i = 0; i < 3; i++)
			Dv[i] = Dm * nv[i];
		random_rotation(R3);
		random_rotation(U);
		for (int i = 0; i < 3; i++)
			lam[i] = urand() * (1 - Dm * 0.5);
		double MD[4][4], MR[4][4], MDel[4][4], Mt[4][4], M[4][4];
		make_MD(Dv, MD);
		make_MR(R3, MR);
		make_MDelta(P, lam, U, MDel);
		pc_mueller_mul(MDel, MR, Mt);
		pc_mueller_mul(Mt, MD, Mt);
		if (pc_mueller_min_coherency_eig(Mt) < -PC_PHYS_TOL)
			continue; /* only physical truths */
		double noise = 0.002 + 0.1 * urand(), dist_true = 0;
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				M[i][j] = Mt[i][j] + noise * nrand();
				dist_true += (M[i][j] - Mt[i][j]) * (M[i][j] - Mt[i][j]);
			}
		double Mf[4][4];
		bool changed;
		pc_mueller_cloude_filter(M, Mf, &changed);
		double dist_f = 0;
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				dist_f += (M[i][j] - Mf[i][j]) * (M[i][j] - Mf[i][j]);
		CHECK(dist_f <= dist_true * (1 + 1e-9) + 1e-24);
		CHECK(pc_mueller_min_coherency_eig(Mf) >= -1e-12);
		pc_lu_chipman lc;
		CHECK_EQ_INT(pc_lu_chipman_decompose(M, PC_LC_FILTER, &lc), 0);
		CHECK_EQ_INT(lc.filtered, changed);
		CHECK_EQ_INT(!!(lc.flags & PC_LC_NONPHYSICAL), !lc.physical);
		filtered += lc.filtered;
		if (lc.flags & PC_LC_ZERO_M00)
			continue;
		CHECK(lc.D >= 0 && lc.D <= 1);
		if (!(lc.flags & PC_LC_D_SINGULAR))
			CHECK(lc.Delta >= 0 && lc.Delta <= 1);
	}
	CHECK(filtered > 100);
}

static void test_special(void)
{
	pc_lu_chipman lc;
	double M[4][4] = {{0}};
	/* M00 ≤ 0 */
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK(lc.flags & PC_LC_ZERO_M00);
	CHECK(isnan(lc.D) && isnan(lc.R));
	/* non-finite input: an error naming the element */
	M[0][0] = 1;
	M[2][3] = NAN;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "M[2][3]") != NULL);
	M[2][3] = INFINITY;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, PC_LC_NO_FACTORS, &lc), PC_EINVAL);
	/* the ideal depolariser: Δ = 1, R not unique, depolarisation index 0 */
	memset(M, 0, sizeof M);
	M[0][0] = 2;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK_NEAR(lc.Delta, 1, 0);
	CHECK_NEAR(lc.D, 0, 0);
	CHECK(lc.flags & PC_LC_R_NONUNIQUE);
	CHECK_NEAR(lc.depol_index, 0, 0);
	CHECK(lc.physical);
	/* identity: nothing; a mirror diag(1, 1, −1, −1): R = π, Δ = 0 (physics.md §1) */
	for (int i = 0; i < 4; i++)
		M[i][i] = 1;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK_NEAR(lc.R, 0, 1e-15);
	CHECK_NEAR(lc.Delta, 0, 1e-15);
	CHECK_NEAR(lc.depol_index, 1, 1e-15);
	M[2][2] = M[3][3] = -1;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK_NEAR(lc.R, PC_PI, 1e-15);
	CHECK_NEAR(lc.Delta, 0, 1e-15);
	CHECK_NEAR(fabs(lc.R_axis[0]), 1, 1e-15);
	/* a rank-1 m' (partial polariser-like depolariser diag(1, 0.5, 0, 0)): R flagged */
	memset(M, 0, sizeof M);
	M[0][0] = 1;
	M[1][1] = 0.5;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
	CHECK(lc.flags & PC_LC_R_NONUNIQUE);
	CHECK_NEAR(lc.Delta, 1 - 0.5 / 3, 1e-7);
	CHECK(isfinite(lc.R));

	/* linear retardance δ and optical rotation ψ from Jones matrices:
	 * a rotator by ψ (plane of polarisation turned from s towards p) followed by a linear
	 * retarder δ with axis along s: m_R = m_LR(δ) m_CR(ψ) */
	for (int t = 0; t < 200; t++) {
		double psi = (urand() - 0.5) * 1.2, delta = PC_PI * 0.95 * urand(),
		       th = urand() * PC_PI;
		/* Jones: rotator C = [[cos ψ, −sin ψ], [sin ψ, cos ψ]]; linear retarder with its
		 * axis at θ: L = Rot(θ) diag(e^{iδ/2}, e^{−iδ/2}) Rot(θ)ᵀ, Rot(θ) = [[cos θ, −sin
		 * θ], [sin θ, cos θ]], i.e. L_ij = Σ_k Rot_ik d_k Rot_jk */
		double c = cos(psi), s = sin(psi), ct = cos(th), st = sin(th);
		double Jr[2][2], Ji[2][2], Lr[2][2], Li[2][2];
		const double rot[2][2] = {{ct, -st}, {st, ct}};
		const double cd = cos(delta / 2), sd = sin(delta / 2);
		for (int i = 0; i < 2; i++)
			for (int j = 0; j < 2; j++) {
				Lr[i][j] = cd * (rot[i][0] * rot[j][0] + rot[i][1] * rot[j][1]);
				Li[i][j] = sd * (rot[i][0] * rot[j][0] - rot[i][1] * rot[j][1]);
			}
		double Cr[2][2] = {{c, -s}, {s, c}};
		for (int i = 0; i < 2; i++)
			for (int j = 0; j < 2; j++) {
				Jr[i][j] = Lr[i][0] * Cr[0][j] + Lr[i][1] * Cr[1][j];
				Ji[i][j] = Li[i][0] * Cr[0][j] + Li[i][1] * Cr[1][j];
			}
		pc_jones_to_mueller(Jr, Ji, M);
		CHECK_EQ_INT(pc_lu_chipman_decompose(M, 0, &lc), 0);
		CHECK_NEAR(lc.R_linear, delta, 1e-10);
		CHECK_NEAR(lc.R_circular, psi, 1e-10);
		CHECK_NEAR(lc.Delta, 0, 1e-12);
		CHECK_NEAR(lc.D, 0, 1e-12);
		CHECK_NEAR(cos(lc.R / 2), cos(delta / 2) * cos(psi), 1e-12);
	}
}

int main(void)
{
	test_round_trips();
	test_d_singular();
	test_against_reference();
	test_filter();
	test_special();
	return pc_test_finish("test_decompose");
}
