/* The 4×4 from the 3×3 linear block (physics.md §7, docs/physics-notes.md "Rebuilding the 4×4
 * from the 3×3"): the sign facts the convention rests on, checked on the Fresnel coefficients
 * alone; round trips on pBRDF matrices of the physics core (the truth is the core's 4×4, which
 * the rebuild never sees) over many geometries, materials, σ, frames, with and without the
 * diffuse term; the hard cases; noisy and foreign 3×3 blocks (flagged); Lu–Chipman D, R, Δ of
 * the rebuilt matrix against those of the true one, and their independence of the sign. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

#define PC_TEST_SEED 0x9E3779B97F4A7C15ull
#include "xorshift.h"

#define DEG (M_PI / 180)

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static void block3(const double M[4][4], double N[3][3])
{
	for (int k = 0; k < 3; k++)
		for (int l = 0; l < 3; l++)
			N[k][l] = M[k][l];
}

/* max |X_kl − Y_kl| / Y00 over all 16 elements */
static double mdiff(const double X[4][4], const double Y[4][4])
{
	double m = 0;
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++)
			m = fmax(m, fabs(X[k][l] - Y[k][l]));
	return m / Y[0][0];
}

/* 1. The sign facts, from the Fresnel coefficients only: |r_p| ≤ |r_s| (so b ≥ 0) and
 * Im(r_s r_p*) ≤ 0 for k ≥ 0 (< 0 for k > 0, 0 < β < 90°), and Abelès' relation
 * r_p = r_s (r_s − cos2β)/(1 − r_s cos2β) that the proof in physics-notes uses. */
static void test_sign_facts(void)
{
	int neg = 0, cases = 0;
	double worst_abeles = 0, max_s_dielectric = 0;
	for (int i = 0; i < 40000; i++) {
		double n = exp(log(0.05) + urand() * log(10 / 0.05));
		double k = i % 4 == 0 ? 0 : exp(log(1e-3) + urand() * log(20 / 1e-3));
		double beta = (0.01 + 89.98 * urand()) * DEG;
		pc_fresnel f;
		pc_fresnel_angle(n, k, beta, &f);
		double rs2 = f.rs_re * f.rs_re + f.rs_im * f.rs_im;
		double rp2 = f.rp_re * f.rp_re + f.rp_im * f.rp_im;
		double s = f.rs_im * f.rp_re - f.rs_re * f.rp_im; /* Im(r_s conj(r_p)) */
		CHECK(rp2 <= rs2 * (1 + 1e-12));
		cases++;
		if (k > 0) {
			neg += s < 0;
			CHECK(s < 0);
		} else {
			CHECK(s <= 1e-15);
			if (n >= 1)
				max_s_dielectric = fmax(max_s_dielectric, fabs(s));
		}
		/* Abelès: r_p (1 − r_s c) = r_s (r_s − c), c = cos 2β */
		double c = cos(2 * beta);
		double lre = f.rp_re * (1 - c * f.rs_re) + f.rp_im * c * f.rs_im;
		double lim = f.rp_im * (1 - c * f.rs_re) - f.rp_re * c * f.rs_im;
		double rre = f.rs_re * (f.rs_re - c) - f.rs_im * f.rs_im;
		double rim = f.rs_im * (f.rs_re - c) + f.rs_re * f.rs_im;
		worst_abeles = fmax(worst_abeles, hypot(lre - rre, lim - rim));
	}
	CHECK(worst_abeles < 1e-13);
	CHECK(max_s_dielectric < 1e-15);
	printf("sign facts: %d cases, Im(r_s r_p*) < 0 in all %d with k > 0; Abeles relation to "
	       "%.1e; |s| for k = 0, n >= 1 at most %.1e\n",
	       cases, neg, worst_abeles, max_s_dielectric);
}

typedef struct mat_case {
	double n, k, sigma;
	pc_diffuse diffuse;
} mat_case;

static const mat_case mats[] = {
    {1.5, 0, 0.2, PC_DIFFUSE_FRESNEL},     {1.5, 0, 0.05, PC_DIFFUSE_NONE},
    {1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL}, /* black paint (physics.md §8) */
    {1.47, 0.47, 0.1, PC_DIFFUSE_FRESNEL}, /* green paint */
    {1.46, 1.28, 0.4, PC_DIFFUSE_NONE},    {1.2, 7.0, 0.1, PC_DIFFUSE_FRESNEL},
    {0.2, 3.3, 0.3, PC_DIFFUSE_GEOMETRIC}, {2.5, 0.01, 0.15, PC_DIFFUSE_FRESNEL},
    {0.8, 0, 0.2, PC_DIFFUSE_FRESNEL},     {4.0, 3.0, 0.02, PC_DIFFUSE_NONE},
};
enum { NMAT = sizeof mats / sizeof mats[0] };

static pc_pbrdf *make(const mat_case *m)
{
	pc_material mt = {m->n, m->k, m->sigma, m->diffuse, PC_SHADOW_TS, PC_RHO_QUAD, 0};
	pc_pbrdf *p = NULL;
	if (pc_pbrdf_new(&mt, &p))
		abort();
	return p;
}

/* a unit vector ⟂ k at a random angle */
static void random_s(const double k[3], double s[3])
{
	double a[3] = {nrand(), nrand(), nrand()}, d = a[0] * k[0] + a[1] * k[1] + a[2] * k[2];
	for (int i = 0; i < 3; i++)
		a[i] -= d * k[i];
	double m = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
	for (int i = 0; i < 3; i++)
		s[i] = a[i] / m;
}

/* decompose both and compare; returns the worst of |ΔD|, |ΔR|, |ΔΔ| */
static double lc_diff(const double X[4][4], const double T[4][4], int *singular)
{
	pc_lu_chipman a, b;
	CHECK_EQ_INT(pc_lu_chipman_decompose(X, 0, &a), 0);
	CHECK_EQ_INT(pc_lu_chipman_decompose(T, 0, &b), 0);
	if ((a.flags | b.flags) & (PC_LC_D_SINGULAR | PC_LC_ZERO_M00)) {
		(*singular)++;
		return fabs(a.D - b.D);
	}
	double e = fmax(fabs(a.D - b.D), fabs(a.Delta - b.Delta));
	/* R is compared where it means something: m' not (nearly) singular and a polarised part
	 * of at least 1e-3 of M00 — where the specular lobe is ~1e-30 of the diffuse term R is
	 * the retardance of rounding noise; near D = 1 the 1/(1 − D²) of M_D⁻¹ amplifies the
	 * ~1e-8 error of S (sqrt of rounding) */
	if ((a.flags | b.flags) & PC_LC_R_NONUNIQUE || b.Delta > 1 - 1e-3 || b.D > 1 - 1e-3)
		return e;
	return fmax(e, fabs(a.R - b.R));
}

/* 2. Round trips: rebuild each pBRDF matrix from its 3×3 and compare with the true 4×4. */
static void test_pbrdf_round_trips(void)
{
	double worst = 0, worst_lc = 0, worst_sign = 0, worst_res = 0;
	int n = 0, zero = 0, singular = 0, szero = 0, undefined = 0;
	for (int mi = 0; mi < NMAT; mi++) {
		pc_pbrdf *p = make(&mats[mi]);
		for (int i = 0; i < 1500; i++) {
			double f[4][4];
			if (i % 3 == 0) {
				/* macro frames */
				double ti = 89 * DEG * urand(), tr = 89 * DEG * urand();
				double dp = 2 * M_PI * urand();
				CHECK_EQ_INT(pc_pbrdf_eval(p, ti, tr, dp, f), 0);
			} else {
				/* any frames: random directions above the horizon, random s-vectors
				 */
				double ti = acos(0.02 + 0.98 * urand()),
				       tr = acos(0.02 + 0.98 * urand());
				double pi = 2 * M_PI * urand(), pr = 2 * M_PI * urand();
				if (i % 3 ==
				    2) /* near the specular direction, where S is largest */
					pr = pi + M_PI + 0.3 * nrand(), tr = ti + 0.2 * nrand();
				tr = fmin(fmax(tr, 0), 89.5 * DEG);
				double ki[3] = {sin(ti) * cos(pi), sin(ti) * sin(pi), cos(ti)};
				double kr[3] = {sin(tr) * cos(pr), sin(tr) * sin(pr), cos(tr)};
				double si[3], sr[3];
				random_s(ki, si);
				random_s(kr, sr);
				CHECK_EQ_INT(pc_pbrdf_eval_vec(p, ki, kr, si, sr, f), 0);
			}
			if (!(f[0][0] > 0)) {
				zero++;
				continue;
			}
			double N[3][3], M[4][4], Mp[4][4];
			pc_rebuild_info in;
			block3(f, N);
			CHECK_EQ_INT(
			    pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 1e-9, M, &in),
			    0);
			CHECK_EQ_INT(in.flags & PC_RB_REJECTED, 0);
			szero += (in.flags & PC_RB_S_ZERO) != 0;
			double e = mdiff(M, f);
			if (in.flags & PC_RB_SIGN_UNDEFINED) {
				/* only total reflection (k = 0, n < 1, sinβ > n) has |r_s| = |r_p|,
				 * i.e. B = 0 with S ≠ 0: the 3×3 then cannot tell which of the two
				 * matrices M(±S) it came from; the rebuild returns one of them */
				CHECK(mats[mi].k == 0 && mats[mi].n < 1);
				double Q[4][4];
				for (int k = 0; k < 4; k++)
					for (int l = 0; l < 4; l++)
						Q[k][l] = ((k == 3) != (l == 3) ? -1 : 1) * M[k][l];
				e = fmin(e, mdiff(Q, f));
				undefined++;
			}
			if (e > 2e-7)
				fprintf(stderr,
				        "material %d case %d: rebuilt differs by %.3g (flags %#x, "
				        "residual %.3g, S %.3g)\n",
				        mi, i, e, in.flags, in.residual, in.S / f[0][0]);
			worst = fmax(worst, e);
			worst_res = fmax(worst_res, in.residual);
			CHECK(in.d >= -1e-12 * f[0][0]);
			worst_lc = fmax(worst_lc, lc_diff(M, f, &singular));
			/* the other sign: the same D, R, Δ (M(−S) = Q M(S) Q, Q = diag(1, 1, 1,
			 * −1)) */
			CHECK_EQ_INT(
			    pc_mueller_rebuild_from_linear(N, PC_REBUILD_PLUS, 1e-9, Mp, NULL), 0);
			for (int k = 0; k < 4; k++)
				for (int l = 0; l < 4; l++)
					CHECK_NEAR(Mp[k][l],
					           ((k == 3) != (l == 3) ? -1 : 1) * M[k][l],
					           1e-15 * f[0][0]);
			int dummy = 0;
			worst_sign = fmax(worst_sign, lc_diff(Mp, M, &dummy));
			n++;
		}
		pc_pbrdf_free(p);
	}
	/* stated tolerance: 2e-7 of M00 (|S| = sqrt(A² − B² − C²) turns rounding of order 1e-16
	 * into 1e-8 where S ≈ 0, e.g. dielectrics) */
	CHECK(worst <= 2e-7);
	/* ~1e-12 where the angles are nearly degenerate (near-normal facet incidence: B and
	 * A + C → 0 flatten the objective); ~1e-15 elsewhere */
	CHECK(worst_res <= 1e-11);
	/* D and Δ to rounding; R to 2e-5 (measured 7e-6): at R ≈ π or 0 the true S is 0 and the
	 * rebuilt |S| = sqrt(A² − B² − C²) carries the square root of rounding */
	CHECK(worst_lc <= 2e-5);
	CHECK(worst_sign <= 1e-12);
	printf("pbrdf round trips: %d matrices (%d below the horizon skipped, %d with S = 0, %d "
	       "total reflection with B = 0 (sign undefined), %d D-singular), worst |M_rebuilt - "
	       "M_true|/M00 = %.2e, residual %.1e, worst D/R/Delta "
	       "difference %.2e, plus vs minus sign %.1e\n",
	       n, zero, szero, undefined, singular, worst, worst_res, worst_lc, worst_sign);
}

static void rebuild_check(const char *what, const pc_pbrdf *p, double ti, double tr, double dp,
                          unsigned want_flags, double tol)
{
	double f[4][4], N[3][3], M[4][4];
	pc_rebuild_info in;
	CHECK_EQ_INT(pc_pbrdf_eval(p, ti * DEG, tr * DEG, dp * DEG, f), 0);
	block3(f, N);
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 1e-9, M, &in), 0);
	CHECK_EQ_INT(in.flags, want_flags);
	double e = mdiff(M, f);
	CHECK(e <= tol);
	printf("  %-44s flags %#x, |dM|/M00 = %.1e, S/M00 = %+.3e, M33/M00 = %+.4f\n", what,
	       in.flags, e, in.S / f[0][0], M[3][3] / f[0][0]);
}

/* 3. Hard cases. */
static void test_hard_cases(void)
{
	printf("hard cases:\n");
	mat_case glass = {1.5, 0, 0.2, PC_DIFFUSE_FRESNEL},
	         glass_s = {1.5, 0, 0.2, PC_DIFFUSE_NONE};
	mat_case paint = {1.46, 1.28, 0.2, PC_DIFFUSE_NONE},
	         sharp = {1.46, 1.28, 0.02, PC_DIFFUSE_FRESNEL};
	pc_pbrdf *g = make(&glass), *gs = make(&glass_s), *pt = make(&paint), *sh = make(&sharp);
	double brewster = atan(1.5) / DEG;
	rebuild_check("dielectric below Brewster (40/40/180)", g, 40, 40, 180, PC_RB_S_ZERO, 2e-7);
	rebuild_check("dielectric above Brewster (70/70/180)", g, 70, 70, 180, PC_RB_S_ZERO, 2e-7);
	rebuild_check("dielectric at Brewster, no diffuse", gs, brewster, brewster, 180,
	              PC_RB_S_ZERO, 2e-7);
	rebuild_check("dielectric out of plane (40/55/150)", g, 40, 55, 150, PC_RB_S_ZERO, 2e-7);
	rebuild_check("normal incidence, backscatter (0/0)", pt, 0, 0, 0, PC_RB_S_ZERO, 1e-12);
	rebuild_check("backscatter at 50/50/0", pt, 50, 50, 0, PC_RB_S_ZERO, 1e-12);
	rebuild_check("paint (40/55/150), physics.md reference", pt, 40, 55, 150, 0, 1e-12);
	rebuild_check("grazing specular (89.5/89.5/180)", pt, 89.5, 89.5, 180, 0, 1e-9);
	rebuild_check("grazing off-plane (85/87/172)", pt, 85, 87, 172, 0, 1e-9);
	/* specular part exactly zero (tan²θ_N/(2σ²) > 700): only the diffuse term */
	double f[4][4], N[3][3], M[4][4];
	pc_rebuild_info in;
	CHECK_EQ_INT(pc_pbrdf_eval(sh, 60 * DEG, 60 * DEG, 0, f), 0);
	CHECK(f[0][0] > 0 && f[0][1] == 0 && f[1][1] == 0);
	rebuild_check("zero specular part (sigma 0.02, 60/60/0)", sh, 60, 60, 0, PC_RB_S_ZERO, 0);
	/* below the horizon: M00 = 0, nothing to rebuild */
	CHECK_EQ_INT(pc_pbrdf_eval(pt, 30 * DEG, 95 * DEG, 0, f), 0);
	block3(f, N);
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 1e-9, M, &in), 0);
	CHECK_EQ_INT(in.flags, PC_RB_ZERO);
	CHECK(isnan(M[3][3]) && isnan(M[1][3]) && M[0][0] == 0);
	pc_pbrdf_free(g);
	pc_pbrdf_free(gs);
	pc_pbrdf_free(pt);
	pc_pbrdf_free(sh);
}

/* 4. Matrices outside the family, noisy blocks, bad arguments. */
static void test_outside_family(void)
{
	double N[3][3], M[4][4];
	pc_rebuild_info in;
	/* a linear retarder (δ = 60° at 20°): in the family with B = 0, so S has no frame */
	{
		double th = 20 * DEG, dl = 60 * DEG, c = cos(4 * th), s = sin(4 * th), cd = cos(dl);
		double T[4][4] = {{1, 0, 0, 0},
		                  {0, (1 + cd) / 2 + (1 - cd) / 2 * c, (1 - cd) / 2 * s, 0},
		                  {0, (1 - cd) / 2 * s, (1 + cd) / 2 - (1 - cd) / 2 * c, 0},
		                  {0, 0, 0, cd}};
		/* the (k,3) entries of a linear retarder at θ: ±sinδ (sin2θ, −cos2θ) */
		T[1][3] = -sin(dl) * sin(2 * th);
		T[2][3] = sin(dl) * cos(2 * th);
		T[3][1] = -T[1][3];
		T[3][2] = -T[2][3];
		block3(T, N);
		CHECK_EQ_INT(pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 1e-9, M, &in),
		             0);
		CHECK_EQ_INT(in.flags, PC_RB_SIGN_UNDEFINED);
		double Q[4][4]; /* the other valid choice */
		for (int k = 0; k < 4; k++)
			for (int l = 0; l < 4; l++)
				Q[k][l] = ((k == 3) != (l == 3) ? -1 : 1) * T[k][l];
		CHECK(fmin(mdiff(M, T), mdiff(M, Q)) < 1e-14);
		int sing = 0;
		CHECK(lc_diff(M, T, &sing) < 1e-13);
	}
	/* not realisable: B² + C² > A² */
	double bad[3][3] = {{1, 0.6, 0}, {0.6, 0.9, 0}, {0, 0, 0.9}};
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(bad, PC_REBUILD_CONVENTION, 1e-3, M, &in), 0);
	CHECK(in.flags & PC_RB_NONPHYSICAL);
	CHECK(isnan(M[3][3]));
	/* diffuse part negative: A > N00 */
	double negd[3][3] = {{1, 0, 0}, {0, 1.2, 0}, {0, 0, 1.2}};
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(negd, PC_REBUILD_CONVENTION, 1e-3, M, &in), 0);
	CHECK(in.flags & PC_RB_NONPHYSICAL);
	/* arguments */
	double nanb[3][3] = {{1, 0, 0}, {0, NAN, 0}, {0, 0, 1}};
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(nanb, PC_REBUILD_CONVENTION, 1e-3, M, NULL),
	             PC_EINVAL);
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(negd, PC_REBUILD_CONVENTION, -1, M, NULL),
	             PC_EINVAL);
	CHECK_EQ_INT(pc_mueller_rebuild_from_linear(negd, PC_REBUILD_OFF, 1e-3, M, NULL),
	             PC_EINVAL);
	pc_rebuild_sign sg;
	CHECK_EQ_INT(pc_rebuild_sign_from_name("convention", &sg), 0);
	CHECK_EQ_INT(sg, PC_REBUILD_CONVENTION);
	CHECK_EQ_INT(pc_rebuild_sign_from_name("-", &sg), 0);
	CHECK_EQ_INT(sg, PC_REBUILD_MINUS);
	CHECK_EQ_INT(pc_rebuild_sign_from_name("off", &sg), 0);
	CHECK_EQ_INT(sg, PC_REBUILD_OFF);
	CHECK_EQ_INT(pc_rebuild_sign_from_name("positive", &sg), PC_EINVAL);

	/* sums of two pBRDF matrices (two lights, or two facets in one pixel) and general
	 * retarder·diattenuator·depolariser products are not of the family: most are flagged */
	mat_case paint = {1.46, 1.28, 0.2, PC_DIFFUSE_NONE};
	pc_pbrdf *p = make(&paint);
	int flagged = 0, total = 0;
	for (int i = 0; i < 2000; i++) {
		double f1[4][4], f2[4][4], S[4][4];
		double ti = 60 * DEG * urand(), tr = 60 * DEG * urand();
		pc_pbrdf_eval(p, ti, tr, M_PI + 0.5 * nrand(), f1);
		pc_pbrdf_eval(p, 60 * DEG * urand(), tr, M_PI + 0.5 * nrand(), f2);
		double w = f1[0][0] / f2[0][0];
		for (int k = 0; k < 4; k++)
			for (int l = 0; l < 4; l++)
				S[k][l] = f1[k][l] + w * f2[k][l]; /* equal weights */
		block3(S, N);
		if (pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 1e-3, M, &in))
			continue;
		total++;
		flagged += (in.flags & PC_RB_REJECTED) != 0;
	}
	printf("sums of two pBRDF matrices of equal M00: %d of %d flagged at tol 1e-3\n", flagged,
	       total);
	CHECK(flagged >= 0.9 * total);
	pc_pbrdf_free(p);
}

/* 5. Noise on the 9 elements: within the tolerance the rebuild is kept and close to the truth;
 * far above it is flagged. The residual of a member of the family plus white noise of σ per
 * element behaves like σ·sqrt(χ²₃) (9 numbers, 6 parameters). */
static void test_noise(void)
{
	mat_case paint = {1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL};
	pc_pbrdf *p = make(&paint);
	double sig = 1e-3, sum_r2 = 0, lce[4000];
	int nlc = 0;
	int n = 0, flagged_small = 0, flagged_big = 0, sing = 0;
	for (int i = 0; i < 4000; i++) {
		double f[4][4], N[3][3], Nb[3][3], M[4][4];
		pc_rebuild_info in;
		pc_pbrdf_eval(p, 70 * DEG * urand(), 70 * DEG * urand(), M_PI + 0.6 * nrand(), f);
		if (!(f[0][0] > 0))
			continue;
		block3(f, N);
		for (int k = 0; k < 3; k++)
			for (int l = 0; l < 3; l++) {
				Nb[k][l] = N[k][l] + 0.05 * f[0][0] * nrand();
				N[k][l] += sig * f[0][0] * nrand();
			}
		CHECK_EQ_INT(
		    pc_mueller_rebuild_from_linear(N, PC_REBUILD_CONVENTION, 10 * sig, M, &in), 0);
		n++;
		sum_r2 += in.residual * in.residual;
		if (in.flags & PC_RB_REJECTED)
			flagged_small++;
		else
			lce[nlc++] = lc_diff(M, f, &sing);
		CHECK_EQ_INT(
		    pc_mueller_rebuild_from_linear(Nb, PC_REBUILD_CONVENTION, 10 * sig, M, &in), 0);
		flagged_big += (in.flags & PC_RB_REJECTED) != 0;
	}
	double r2 = sum_r2 / n / (sig * sig);
	qsort(lce, (size_t)nlc, sizeof lce[0], cmp_double);
	double med_lc = nlc ? lce[nlc / 2] : NAN;
	printf("noise sigma = %.0e per element: mean residual^2 / sigma^2 = %.2f (chi^2_3: 3), "
	       "flagged at tol 10 sigma: %d of %d; median of the worst D/R/Delta error of the kept "
	       "ones %.4f; sigma = 0.05: %d of %d flagged\n",
	       sig, r2, flagged_small, n, med_lc, flagged_big, n);
	CHECK(med_lc < 0.01);
	CHECK(r2 > 2.4 && r2 < 4.0);
	CHECK(flagged_small <= n / 1000);
	CHECK(flagged_big >= 0.99 * n);
	pc_pbrdf_free(p);
}

int main(void)
{
	test_sign_facts();
	test_pbrdf_round_trips();
	test_hard_cases();
	test_outside_family();
	test_noise();
	return pc_test_finish("test_mueller_rebuild");
}
