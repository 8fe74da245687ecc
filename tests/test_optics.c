/* Optics: Fresnel against an independent complex-library implementation and analytic limits;
 * Jones → Mueller against Stokes vectors computed from fields by their definitions; the facet
 * fast path against the general route; coherency matrix and Cloude filter on matrices whose
 * spectra are known in closed form; pc_atan2 against libm. */
#include <complex.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "polarcam/optics.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double urand(void) /* [0, 1) */
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}

/* Independent Fresnel: libm csqrt, then the branch Im w ≤ 0 (physics.md §2). */
static void ref_fresnel(double n, double k, double beta, double complex *rs, double complex *rp)
{
	double complex eps = (n - I * k) * (n - I * k);
	double c = cos(beta), s = sin(beta);
	double complex w = csqrt(eps - s * s);
	if (cimag(w) > 0)
		w = -w;
	if (creal(w) < 0)
		w = -w;
	*rs = (c - w) / (c + w);
	*rp = (eps * c - w) / (eps * c + w);
}

static void test_fresnel(void)
{
	double max_err = 0, max_abs = 0;
	for (int t = 0; t < 20000; t++) {
		double n = 0.05 + 10 * urand(), k = t % 3 == 0 ? 0 : 30 * urand() * urand();
		double beta = urand() * 0.5 * PC_PI * 0.9999;
		pc_fresnel r;
		pc_fresnel_angle(n, k, beta, &r);
		double complex rs, rp;
		ref_fresnel(n, k, beta, &rs, &rp);
		double e =
		    fmax(cabs(rs - (r.rs_re + I * r.rs_im)), cabs(rp - (r.rp_re + I * r.rp_im)));
		if (e > max_err)
			max_err = e;
		double a = fmax(hypot(r.rs_re, r.rs_im), hypot(r.rp_re, r.rp_im));
		if (a > max_abs)
			max_abs = a;
	}
	CHECK_NEAR(max_err, 0, 1e-13);
	/* the wrong branch gives |r| > 1 for metals */
	CHECK(max_abs <= 1 + 1e-14);

	/* normal incidence: r_p = −r_s = (ñ − 1)/(ñ + 1) (Born & Wolf form, physics.md §1) */
	pc_fresnel r;
	pc_fresnel_angle(1.46, 1.28, 0, &r);
	double complex nt = 1.46 - 1.28 * I, expect = (1 - nt) / (1 + nt);
	CHECK_NEAR(r.rs_re, creal(expect), 1e-15);
	CHECK_NEAR(r.rs_im, cimag(expect), 1e-15);
	CHECK_NEAR(r.rp_re, -creal(expect), 1e-15);
	CHECK_NEAR(r.rp_im, -cimag(expect), 1e-15);

	/* Brewster angle of a dielectric: r_p = 0; the s reflectance there is ((n²−1)/(n²+1))² */
	pc_fresnel_angle(1.5, 0, atan(1.5), &r);
	CHECK_NEAR(hypot(r.rp_re, r.rp_im), 0, 1e-15);
	CHECK_NEAR(r.rs_re * r.rs_re + r.rs_im * r.rs_im, pow((2.25 - 1) / (2.25 + 1), 2), 1e-15);

	/* perfect conductor: r_s → −1, r_p → +1 at any β < 90°, deviations O(1/(|ñ| cosβ)) */
	for (int i = 0; i < 5; i++) {
		double beta = i * 0.35, tol = 4e-9 / cos(beta);
		pc_fresnel_angle(1, 1e9, beta, &r);
		CHECK_NEAR(r.rs_re, -1, tol);
		CHECK_NEAR(r.rp_re, 1, tol);
		CHECK_NEAR(r.rs_im, 0, tol);
		CHECK_NEAR(r.rp_im, 0, tol);
	}
	/* n → 0 metal-like (silver in the visible, ñ ≈ 0.05 − 4.3i): |r| close to but below 1 */
	pc_fresnel_angle(0.05, 4.3, 0.7, &r);
	CHECK(hypot(r.rs_re, r.rs_im) < 1 && hypot(r.rs_re, r.rs_im) > 0.98);
	/* total internal reflection from below (n < 1, k = 0, beyond the critical angle): |r| = 1
	 */
	pc_fresnel_angle(0.6, 0, 1.2, &r);
	CHECK_NEAR(hypot(r.rs_re, r.rs_im), 1, 1e-14);
	CHECK_NEAR(hypot(r.rp_re, r.rp_im), 1, 1e-14);
	/* grazing: both → −1 for a dielectric */
	pc_fresnel_eval(1.5, 0, 0, 1, &r);
	CHECK_NEAR(r.rs_re, -1, 1e-15);
	CHECK_NEAR(r.rp_re, -1, 1e-15);
	CHECK_NEAR(pc_fresnel_reflectance(1.5, 0, 0), 0.04, 1e-15);
}

/* Stokes vector of a field by the definitions of physics.md §1 (not through A). */
static void stokes_of(double complex Es, double complex Ep, double S[4])
{
	S[0] = creal(Es * conj(Es) + Ep * conj(Ep));
	S[1] = creal(Es * conj(Es) - Ep * conj(Ep));
	S[2] = 2 * creal(Es * conj(Ep));
	S[3] = 2 * cimag(conj(Es) * Ep);
}

static void rand_jones(double complex J[2][2], double Jr[2][2], double Ji[2][2])
{
	for (int i = 0; i < 2; i++)
		for (int j = 0; j < 2; j++) {
			Jr[i][j] = 2 * urand() - 1;
			Ji[i][j] = 2 * urand() - 1;
			J[i][j] = Jr[i][j] + I * Ji[i][j];
		}
}

static void test_jones_mueller(void)
{
	double worst = 0;
	for (int t = 0; t < 2000; t++) {
		double complex J[2][2];
		double Jr[2][2], Ji[2][2], M[4][4];
		rand_jones(J, Jr, Ji);
		pc_jones_to_mueller(Jr, Ji, M);
		double complex Es = (2 * urand() - 1) + I * (2 * urand() - 1);
		double complex Ep = (2 * urand() - 1) + I * (2 * urand() - 1);
		double S[4], Sout[4], Sm[4];
		stokes_of(Es, Ep, S);
		stokes_of(J[0][0] * Es + J[0][1] * Ep, J[1][0] * Es + J[1][1] * Ep, Sout);
		pc_mueller_apply(M, S, Sm);
		for (int i = 0; i < 4; i++)
			worst = fmax(worst, fabs(Sm[i] - Sout[i]));
	}
	CHECK_NEAR(worst, 0, 1e-13);

	/* quarter-wave retarder diag(1, i): S2 → S3 → −S2 (by hand from the definitions) */
	double Jr[2][2] = {{1, 0}, {0, 0}}, Ji[2][2] = {{0, 0}, {0, 1}}, M[4][4];
	pc_jones_to_mueller(Jr, Ji, M);
	CHECK_NEAR(M[3][2], 1, 1e-15);
	CHECK_NEAR(M[2][3], -1, 1e-15);
	CHECK_NEAR(M[2][2], 0, 1e-15);
	/* s-polariser diag(1, 0): ½[[1,1],[1,1]] block */
	double Pr[2][2] = {{1, 0}, {0, 0}}, Pi[2][2] = {{0, 0}, {0, 0}};
	pc_jones_to_mueller(Pr, Pi, M);
	CHECK_NEAR(M[0][0], 0.5, 1e-15);
	CHECK_NEAR(M[0][1], 0.5, 1e-15);
	CHECK_NEAR(M[1][1], 0.5, 1e-15);
	CHECK_NEAR(M[2][2], 0, 1e-15);

	/* R_M(θ) is the Mueller matrix of the Jones frame rotation [[c, s], [−s, c]] */
	for (int t = 0; t < 20; t++) {
		double th = (urand() - 0.5) * 7, R[4][4], G[4][4];
		double Rr[2][2] = {{cos(th), sin(th)}, {-sin(th), cos(th)}};
		double Ri[2][2] = {{0, 0}, {0, 0}};
		pc_jones_to_mueller(Rr, Ri, G);
		pc_mueller_rotator(th, R);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(R[i][j], G[i][j], 1e-14);
	}

	/* facet fast path = general route for T_out · diag(r_s, r_p) · T_in */
	worst = 0;
	for (int t = 0; t < 2000; t++) {
		double n = 0.1 + 5 * urand(), k = 5 * urand(), beta = 1.5 * urand();
		double a1 = (urand() - 0.5) * 7, a2 = (urand() - 0.5) * 7;
		pc_fresnel r;
		pc_fresnel_angle(n, k, beta, &r);
		double complex rs = r.rs_re + I * r.rs_im, rp = r.rp_re + I * r.rp_im;
		double c1 = cos(a1), s1 = sin(a1), c2 = cos(a2), s2 = sin(a2);
		/* J = [[c2, s2], [−s2, c2]] diag(rs, rp) [[c1, s1], [−s1, c1]] */
		double complex J[2][2] = {
		    {c2 * rs * c1 - s2 * rp * s1, c2 * rs * s1 + s2 * rp * c1},
		    {-s2 * rs * c1 - c2 * rp * s1, -s2 * rs * s1 + c2 * rp * c1},
		};
		double Jr2[2][2], Ji2[2][2], G[4][4], F[4][4], abcs[4];
		for (int i = 0; i < 2; i++)
			for (int j = 0; j < 2; j++) {
				Jr2[i][j] = creal(J[i][j]);
				Ji2[i][j] = cimag(J[i][j]);
			}
		pc_jones_to_mueller(Jr2, Ji2, G);
		pc_fresnel_abcs(&r, abcs);
		pc_mueller_facet(abcs, cos(2 * a1), sin(2 * a1), cos(2 * a2), sin(2 * a2), F);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				worst = fmax(worst, fabs(F[i][j] - G[i][j]));
	}
	CHECK_NEAR(worst, 0, 1e-14);
}

static void test_stokes(void)
{
	double S[4];
	for (int i = 0; i < 36; i++) {
		double a = i * PC_PI / 36;
		pc_stokes_linear(2, a, S);
		CHECK_NEAR(pc_stokes_aolp_rad(S), a, 1e-14);
		CHECK_NEAR(pc_stokes_dolp(S), 1, 1e-15);
		CHECK_NEAR(pc_stokes_dop(S), 1, 1e-15);
		CHECK_NEAR(pc_stokes_docp(S), 0, 1e-15);
	}
	/* AoLP range [0, π): −10° maps to 170°; exactly 180° maps to 0 */
	pc_stokes_linear(1, -10 * PC_PI / 180, S);
	CHECK_NEAR(pc_stokes_aolp_rad(S), 170 * PC_PI / 180, 1e-14);
	double S180[4] = {1, 1, -0.0, 0};
	CHECK(pc_stokes_aolp_rad(S180) >= 0 && pc_stokes_aolp_rad(S180) < PC_PI);
	double Sc[4] = {2, 0, 0, -1};
	CHECK_NEAR(pc_stokes_docp(Sc), -0.5, 0);
	CHECK_NEAR(pc_stokes_dop(Sc), 0.5, 0);
	double S0[4] = {0, 0, 0, 0};
	CHECK_NEAR(pc_stokes_dop(S0), 0, 0);
}

static void diag4(double a, double b, double c, double d, double M[4][4])
{
	memset(M, 0, 16 * sizeof(double));
	M[0][0] = a;
	M[1][1] = b;
	M[2][2] = c;
	M[3][3] = d;
}

static void test_coherency(void)
{
	/* pure (Jones) matrices: H = vec(J) vec(J)^†: rank 1, eigenvalues (0, 0, 0, tr H) */
	for (int t = 0; t < 200; t++) {
		double complex J[2][2];
		double Jr[2][2], Ji[2][2], M[4][4], Hr[4][4], Hi[4][4], ev[4];
		rand_jones(J, Jr, Ji);
		pc_jones_to_mueller(Jr, Ji, M);
		pc_mueller_coherency(M, Hr, Hi);
		double tr = Hr[0][0] + Hr[1][1] + Hr[2][2] + Hr[3][3];
		double vj = 0;
		for (int i = 0; i < 4; i++)
			vj += Jr[i / 2][i % 2] * Jr[i / 2][i % 2] +
			      Ji[i / 2][i % 2] * Ji[i / 2][i % 2];
		CHECK_NEAR(tr, vj, 1e-13);          /* |vec J|² */
		CHECK_NEAR(tr, 2 * M[0][0], 1e-13); /* tr H = 2 M00 */
		pc_hermitian4_eigvals(Hr, Hi, ev);
		CHECK_NEAR(ev[3], tr, 1e-12 * tr);
		CHECK_NEAR(ev[0], 0, 1e-12 * tr);
		CHECK_NEAR(ev[2], 0, 1e-12 * tr);
		double back[4][4];
		pc_coherency_to_mueller(Hr, Hi, back);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(back[i][j], M[i][j], 1e-13);
		CHECK(pc_mueller_min_coherency_eig(M) >= -PC_PHYS_TOL);
	}
	/* diagonal Mueller matrices: eigenvalues of H/tr H are (m0 ± m1 ± m2 ± m3)/(4 m0) with an
	 * even number of minus signs among m1..m3 (closed form) */
	double M[4][4], F[4][4];
	diag4(1, 1, 1, -1, M); /* not realisable: (1 − 1 − 1 − 1)/4 = −1/2 */
	CHECK_NEAR(pc_mueller_min_coherency_eig(M), -0.5, 1e-14);
	bool changed = false;
	pc_mueller_cloude_filter(M, F, &changed);
	CHECK(changed);
	/* clipping the −1/2 component leaves ½(I + diag(1,1,−1,−1) + diag(1,−1,1,−1)) */
	double expect[4] = {1.5, 0.5, 0.5, -0.5};
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			CHECK_NEAR(F[i][j], i == j ? expect[i] : 0, 1e-13);
	CHECK(pc_mueller_min_coherency_eig(F) >= -1e-14);
	diag4(1, 0.3, -0.2, 0.1, M); /* (1 ± …)/4 all positive: physical, unchanged */
	CHECK_NEAR(pc_mueller_min_coherency_eig(M), (1 - 0.3 + (-0.2) - 0.1) / 4, 1e-14);
	pc_mueller_cloude_filter(M, F, &changed);
	CHECK(!changed);
	CHECK(memcmp(F, M, sizeof M) == 0);
	/* the filter and the eigenvalues scale with M (power-of-two prescaling inside): the same
	 * non-realisable matrix at 1e-200 … 1e200 */
	const double scales[] = {1e-200, 1e-30, 3.7, 1e30, 1e200};
	for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
		double sc = scales[k];
		diag4(sc, sc, sc, -sc, M);
		CHECK_NEAR(pc_mueller_min_coherency_eig(M), -0.5, 1e-14);
		pc_mueller_cloude_filter(M, F, &changed);
		CHECK(changed);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(F[i][j] / sc, i == j ? expect[i] : 0, 1e-13);
	}
	/* known spectra: H = V diag(λ) Vᴴ, V a random unitary, λ with mixed signs and spread */
	double worst_ev = 0;
	for (int t = 0; t < 300; t++) {
		double complex V[4][4];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				V[i][j] = (urand() - 0.5) + I * (urand() - 0.5);
		for (int j = 0; j < 4; j++) { /* Gram–Schmidt on the columns */
			for (int q = 0; q < j; q++) {
				double complex d = 0;
				for (int i = 0; i < 4; i++)
					d += conj(V[i][q]) * V[i][j];
				for (int i = 0; i < 4; i++)
					V[i][j] -= d * V[i][q];
			}
			double nr = 0;
			for (int i = 0; i < 4; i++)
				nr += creal(V[i][j] * conj(V[i][j]));
			for (int i = 0; i < 4; i++)
				V[i][j] /= sqrt(nr);
		}
		double lam[4], sc = pow(10, 40 * urand() - 20), Hr[4][4], Hi[4][4], ev[4];
		for (int i = 0; i < 4; i++)
			lam[i] = sc * (2 * urand() - 0.6) * (t % 3 == 0 && i ? 1e-9 : 1);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				double complex h = 0;
				for (int q = 0; q < 4; q++)
					h += V[i][q] * lam[q] * conj(V[j][q]);
				Hr[i][j] = creal(h);
				Hi[i][j] = cimag(h);
			}
		pc_hermitian4_eigvals(Hr, Hi, ev);
		double ls[4] = {lam[0], lam[1], lam[2], lam[3]}, lmax = 0;
		for (int i = 0; i < 4; i++) /* sort ascending */
			for (int j = i + 1; j < 4; j++)
				if (ls[j] < ls[i]) {
					double x = ls[i];
					ls[i] = ls[j];
					ls[j] = x;
				}
		for (int i = 0; i < 4; i++)
			lmax = fmax(lmax, fabs(ls[i]));
		for (int i = 0; i < 4; i++) {
			CHECK_NEAR(ev[i], ls[i], 1e-14 * lmax);
			worst_ev = fmax(worst_ev, fabs(ev[i] - ls[i]) / lmax);
		}
	}
	printf("Hermitian 4x4 eigenvalues (known spectra, scales 1e-20..1e20): worst %.1e of "
	       "max|lambda|\n",
	       worst_ev);
	/* convex combinations of pure matrices are realisable */
	for (int t = 0; t < 100; t++) {
		double S[4][4] = {{0}};
		for (int c = 0; c < 3; c++) {
			double complex J[2][2];
			double Jr[2][2], Ji[2][2], P[4][4], w = urand();
			rand_jones(J, Jr, Ji);
			pc_jones_to_mueller(Jr, Ji, P);
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					S[i][j] += w * P[i][j];
		}
		CHECK(pc_mueller_min_coherency_eig(S) >= -1e-13);
	}
	/* depolarisation index: 1 for pure, 0 for the ideal depolariser */
	diag4(2, 2, -2, 2, M);
	CHECK_NEAR(pc_mueller_depol_index(M), 1, 1e-15);
	diag4(3, 0, 0, 0, M);
	CHECK_NEAR(pc_mueller_depol_index(M), 0, 0);
	diag4(1, 0.5, 0.5, 0.5, M);
	CHECK_NEAR(pc_mueller_depol_index(M), 0.5, 1e-15);
}

/* the Cholesky realisability test against the eigenvalue route, near the boundary too */
static void test_is_physical(void)
{
	int agree = 0, n = 0, nonphys = 0;
	for (int t = 0; t < 3000; t++) {
		double M[4][4] = {{0}};
		/* a convex sum of pure matrices, plus noise of varying size */
		for (int c = 0; c < 3; c++) {
			double complex J[2][2];
			double Jr[2][2], Ji[2][2], P[4][4], w = urand();
			rand_jones(J, Jr, Ji);
			pc_jones_to_mueller(Jr, Ji, P);
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					M[i][j] += w * P[i][j];
		}
		double noise = t % 3 == 0 ? 0 : pow(10, -8 * urand()) * M[0][0];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				M[i][j] += noise * (urand() - 0.5);
		double e = pc_mueller_min_coherency_eig(M);
		if (fabs(e + PC_PHYS_TOL) < 1e-12)
			continue; /* too close to the threshold to call */
		bool ref = e >= -PC_PHYS_TOL, got = pc_mueller_is_physical(M, PC_PHYS_TOL);
		agree += ref == got;
		nonphys += !ref;
		n++;
	}
	CHECK_EQ_INT(agree, n);
	CHECK(nonphys > 300 && nonphys < n - 300);
	double M[4][4];
	diag4(1, 1, 1, -1, M);
	CHECK(!pc_mueller_is_physical(M, PC_PHYS_TOL));
	diag4(1, 1, -1, -1, M); /* a mirror: pure, rank-1 H, on the boundary but physical */
	CHECK(pc_mueller_is_physical(M, PC_PHYS_TOL));
	diag4(0, 0, 0, 0, M);
	CHECK(!pc_mueller_is_physical(M, PC_PHYS_TOL));
}

static void test_atan2(void)
{
	double worst = 0;
	for (int t = 0; t < 200000; t++) {
		double y = (2 * urand() - 1) * pow(10, 6 * urand() - 3);
		double x = (2 * urand() - 1) * pow(10, 6 * urand() - 3);
		if (t % 7 == 0)
			x = fabs(y) * (1 + 1e-9 * (urand() - 0.5)); /* near the diagonal */
		double a = atan2(y, x), b = pc_atan2(y, x);
		double ulp = nextafter(fabs(a), INFINITY) - fabs(a);
		worst = fmax(worst, fabs(a - b) / ulp);
	}
	CHECK(worst <= 4); /* in ulps of libm's result */
	CHECK_NEAR(pc_atan2(0, 0), 0, 0);
	CHECK_NEAR(pc_atan2(0, -1), PC_PI, 0);
	CHECK_NEAR(pc_atan2(-0.0, -1), -PC_PI, 0);
	CHECK_NEAR(pc_atan2(1, 0), PC_PI / 2, 0);
	CHECK_NEAR(pc_atan2(-1, 0), -PC_PI / 2, 0);
	CHECK_NEAR(pc_atan2(1, 1), PC_PI / 4, 2e-16);
	CHECK(isnan(pc_atan2(NAN, 1)));
	printf("pc_atan2: worst %.2f ulp of libm over 2e5 random arguments\n", worst);
	fflush(stdout);
}

int main(void)
{
	test_fresnel();
	test_jones_mueller();
	test_stokes();
	test_coherency();
	test_is_physical();
	test_atan2();
	return pc_test_finish("test_optics");
}
