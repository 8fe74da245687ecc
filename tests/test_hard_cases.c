/* Hard cases of the physics core stay finite at their mathematical limits (issue 13; derivations
 * in docs/physics-notes.md, "Extreme inputs"): Fresnel coefficients for |ñ| from 1e-300 to 1e100
 * against a long-double evaluation of physics.md §2's formulas (whose range, 1e±4932, holds every
 * intermediate), the pBRDF in the perfect-conductor limit (|ñ| → ∞: K·diag(1, 1, −1, −1)), the
 * ñ → 0 limit (r_s = e^{2iβ}, r_p = −1), a lobe of σ = 1e-20 hit exactly at Δφ = 180°
 * (K = 1/(8πσ² cos²θ) times the Fresnel matrix), the refusal below PC_PBRDF_SIGMA_MIN, finite
 * output over random extreme materials and directions, Lu–Chipman of physical matrices scaled
 * from 1e-323 to 1e308 (identity, ideal polarizer: the same D, R, Δ as unscaled) and of a matrix
 * whose normalised m33 is subnormal (Δ = 1 − m33/3), exact degree trigonometry. */
#include <complex.h>
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "lc_map_check.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double urand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}

static bool finite16(const double f[4][4])
{
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			if (!isfinite(f[i][j]))
				return false;
	return true;
}

/* physics.md §2 in long double complex: w = sqrt(ñ² − sin²β) on Re w ≥ 0, Im w ≤ 0. */
static void fresnel_ref(long double n, long double k, long double c, long double s2,
                        long double complex *rs, long double complex *rp)
{
	long double complex nt = n - k * I;
	long double complex eps = nt * nt;
	long double complex w = csqrtl(eps - s2);
	if (cimagl(w) > 0) /* principal root of a real negative argument with +0 imaginary part */
		w = conjl(w);
	*rs = (c - w) / (c + w);
	*rp = (eps * c - w) / (eps * c + w);
}

static void test_fresnel_extreme(void)
{
	static const double ns[] = {1e-300, 1e-200, 1e-100, 1e-20,  0x1p-61, 0x1p-59, 0.1,
	                            1.0,    1.5,    0x1p59, 0x1p61, 1e20,    1e90,    1e100};
	static const double ks[] = {0, 1e-200, 1e-50, 0.5, 1e50, 1e90, 1e100};
	static const double betas[] = {0, 1e-200, 1e-100, 1e-10, 0.3, 1.0, 1.5707963267};
	double worst = 0;
	int n_cases = 0;
	for (size_t a = 0; a < sizeof ns / sizeof ns[0]; a++)
		for (size_t b = 0; b < sizeof ks / sizeof ks[0]; b++)
			for (size_t g = 0; g < sizeof betas / sizeof betas[0] + 1; g++) {
				double c, s2;
				if (g < sizeof betas / sizeof betas[0]) {
					c = cos(betas[g]);
					s2 = sin(betas[g]) * sin(betas[g]);
				} else { /* exactly grazing */
					c = 0;
					s2 = 1;
				}
				pc_fresnel r;
				pc_fresnel_eval(ns[a], ks[b], c, s2, &r);
				long double complex rs, rp;
				fresnel_ref(ns[a], ks[b], c, s2, &rs, &rp);
				/* at the critical angle of a lossless n < 1 (sinβ = n) r_p jumps
				 * from +1 to −1 within a relative change of 1e-16 of the inputs,
				 * and at grazing with n = 1 both are 0/0: only finite values with
				 * |r| <= 1 */
				const double nn = ns[a], sb = sqrt(s2);
				if (fabs((nn - 1) * (nn + 1) - ks[b] * ks[b]) + 2 * nn * ks[b] <
				    0x1p-10)
					continue; /* ñ near 1: test_fresnel_near_one */
				if ((ks[b] == 0 && fabs(nn - sb) <= 1e-6 * fmax(nn, sb)) ||
				    (c == 0 && nn == 1 && ks[b] == 0)) {
					CHECK(hypot(r.rs_re, r.rs_im) <= 1 + 1e-12 &&
					      hypot(r.rp_re, r.rp_im) <= 1 + 1e-12);
					continue;
				}
				double e = fmax(fmax(fabs(r.rs_re - (double)creall(rs)),
				                     fabs(r.rs_im - (double)cimagl(rs))),
				                fmax(fabs(r.rp_re - (double)creall(rp)),
				                     fabs(r.rp_im - (double)cimagl(rp))));
				bool ok = isfinite(r.rs_re) && isfinite(r.rs_im) &&
				          isfinite(r.rp_re) && isfinite(r.rp_im) && e <= 1e-12;
				CHECK(ok);
				if (!ok)
					fprintf(stderr,
					        "  n=%g k=%g cos=%g: rs=(%g,%g) rp=(%g,%g), "
					        "reference rs=(%Lg,%Lg) rp=(%Lg,%Lg)\n",
					        ns[a], ks[b], c, r.rs_re, r.rs_im, r.rp_re, r.rp_im,
					        creall(rs), cimagl(rs), creall(rp), cimagl(rp));
				if (isfinite(e))
					worst = fmax(worst, e);
				n_cases++;
			}
	printf("Fresnel at extreme indices: %d cases, worst difference from long double %.2g\n",
	       n_cases, worst);
}

/* ñ near 1: r_s and r_p go to 0 with t = ñ² − 1, and must keep their relative precision, not an
 * absolute 1e-17 of rounding (physics-notes.md, "ñ near 1"), and |r| <= 1 (n = 1 − 2^-14 at
 * cosβ = 2^-8 is beyond its critical angle: |r| = 1). References: where |t| <= 5e-10 cos²β the
 * first order in t of physics.md §2's formulas (w = cosβ·sqrt(1 + t/cos²β) ≈ cosβ + t/(2cosβ)):
 * r_s = −t/(4cos²β), r_p = t·cos 2β/(4cos²β), relative error O(t/cos²β); elsewhere (|t| >=
 * 1.2e-7 cos²β in this set) the formulas in long double, whose cancellation costs about 1e-19
 * absolute against |r| >= 3e-8. Tolerance 1e-9 of |r| (the larger of the two). test_fresnel_extreme
 * leaves these ñ out: its long-double reference and absolute tolerance cannot see an error of 1e-17
 * in an r of 1e-180. */
static void test_fresnel_near_one(void)
{
	static const double nk[][2] = {{1, 1e-160},      {1, 1e-20},      {1 + 0x1p-40, 0},
	                               {1 - 0x1p-40, 0}, {1, 1e-8},       {1 + 1e-8, 1e-8},
	                               {1.0001, 1e-5},   {1 - 0x1p-14, 0}};
	/* cosines whose cos² + sin² is exactly 1 in double, so that the references see the same β
	 * as the code (a pair off by an ulp moves w by about that ulp, more than |t| here) */
	static const double cosines[] = {1, 0.75, 0.5, 0.25, 0.0625, 0x1p-8};
	double worst = 0;
	for (size_t a = 0; a < sizeof nk / sizeof nk[0]; a++)
		for (size_t g = 0; g < sizeof cosines / sizeof cosines[0]; g++) {
			const double n = nk[a][0], k = nk[a][1], c = cosines[g], s2 = 1 - c * c;
			pc_fresnel r;
			pc_fresnel_eval(n, k, c, s2, &r);
			/* t = ñ² − 1 exactly enough: (n − 1)(n + 1) − k² − 2ink */
			const long double tr = (long double)(n - 1) * ((long double)n + 1) -
			                       (long double)k * k,
			                  ti = -2.0L * n * k;
			long double complex t = tr + ti * I, rs, rp;
			if (cabsl(t) <= 5e-10L * c * c) {
				const long double cc = (long double)c * c;
				rs = -t / (4 * cc);
				rp = t * (cc - (long double)s2) / (4 * cc);
			} else {
				fresnel_ref(n, k, c, s2, &rs, &rp);
			}
			const double scale = (double)fmaxl(cabsl(rs), cabsl(rp));
			const double e = fmax(fmax(fabs(r.rs_re - (double)creall(rs)),
			                           fabs(r.rs_im - (double)cimagl(rs))),
			                      fmax(fabs(r.rp_re - (double)creall(rp)),
			                           fabs(r.rp_im - (double)cimagl(rp)))) /
			                 scale;
			const bool ok = scale > 0 && e <= 1e-9 &&
			                hypot(r.rs_re, r.rs_im) <= 1 + 1e-12 &&
			                hypot(r.rp_re, r.rp_im) <= 1 + 1e-12;
			CHECK(ok);
			if (!ok)
				fprintf(stderr,
				        "  n=%.17g k=%g cos=%g: rs=(%g,%g) rp=(%g,%g), reference "
				        "rs=(%Lg,%Lg) rp=(%Lg,%Lg)\n",
				        n, k, c, r.rs_re, r.rs_im, r.rp_re, r.rp_im, creall(rs),
				        cimagl(rs), creall(rp), cimagl(rp));
			worst = fmax(worst, e);
		}
	/* total reflection for lossless n just below 1, with the angle as callers give it (cos β
	 * and sin²β rounded apart): |r| = 1 beyond the critical angle, <= 1 before it (fuzz_physics
	 * found |r| > 1 + 1e-12 at n = 0.99995475313645543, β = 1.5647082477664753) */
	static const double nl[] = {0.99995475313645543, 1 - 0x1p-14, 1 - 1e-6, 1 - 1e-9};
	double worst_tir = 0;
	int n_tir = 0;
	for (size_t a = 0; a < sizeof nl / sizeof nl[0]; a++) {
		const double bc = asin(nl[a]);
		for (int i = -200; i < 400; i++) {
			const double beta =
			    i < 0 ? bc * (1 + i * 1e-4) : bc + (PC_PI / 2 - bc) * i / 400;
			pc_fresnel r;
			pc_fresnel_eval(nl[a], 0, cos(beta), sin(beta) * sin(beta), &r);
			const double ms = hypot(r.rs_re, r.rs_im), mp = hypot(r.rp_re, r.rp_im);
			bool ok = ms <= 1 + 1e-12 && mp <= 1 + 1e-12;
			if (sin(beta) > nl[a] * (1 + 1e-12)) { /* beyond the critical angle */
				ok = ok && fabs(ms - 1) <= 1e-12 && fabs(mp - 1) <= 1e-12;
				worst_tir = fmax(worst_tir, fmax(fabs(ms - 1), fabs(mp - 1)));
				n_tir++;
			}
			CHECK(ok);
			if (!ok)
				fprintf(stderr, "  n=%.17g beta=%.17g: |rs|=%.17g |rp|=%.17g\n",
				        nl[a], beta, ms, mp);
		}
	}
	printf("Fresnel near n~ = 1: worst relative difference %.2g; total reflection: %d angles, "
	       "|r| within %.2g of 1\n",
	       worst, n_tir, worst_tir);
}

static pc_pbrdf *make(double n, double k, double sigma, pc_diffuse d)
{
	pc_material m = {n, k, sigma, d, PC_SHADOW_TS, PC_RHO_QUAD, 0};
	pc_pbrdf *p = NULL;
	if (pc_pbrdf_new(&m, &p)) {
		fprintf(stderr, "pc_pbrdf_new(n=%g, k=%g, sigma=%g): %s\n", n, k, sigma,
		        pc_error_detail());
		exit(1);
	}
	return p;
}

/* f ≈ K·M_F(a, b, c, s) in the in-plane specular geometry θ_i = θ_r = θ, Δφ = 180° (the frames
 * coincide with the facet's there, so no rotation enters; physics.md §2's reference matrix at
 * 30° has exactly this form), with K = 1/(8πσ² cos²θ): cos θ_N = 1, G = 1, P_D = 1/(8πσ²). */
static void check_specular(const char *what, double n, double k, double sigma, double theta_deg,
                           double a, double b, double c, double s)
{
	pc_pbrdf *p = make(n, k, sigma, PC_DIFFUSE_NONE);
	double f[4][4];
	CHECK_EQ_INT(pc_pbrdf_eval_deg(p, theta_deg, theta_deg, 180, f), 0);
	double ct = cos(theta_deg * PC_PI / 180);
	if (theta_deg == 0)
		ct = 1;
	double K = 1 / (8 * PC_PI * sigma * sigma * ct * ct);
	const double want[4][4] = {{K * a, K * b, 0, 0},
	                           {K * b, K * a, 0, 0},
	                           {0, 0, K * c, K * s},
	                           {0, 0, -K * s, K * c}};
	bool ok = finite16(f);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			if (!(fabs(f[i][j] - want[i][j]) <= 1e-12 * K))
				ok = false;
	CHECK(ok);
	if (!ok) {
		fprintf(stderr, "  %s (n=%g k=%g sigma=%g theta=%g): got / want\n", what, n, k,
		        sigma, theta_deg);
		for (int i = 0; i < 4; i++)
			fprintf(stderr,
			        "   %13.6e %13.6e %13.6e %13.6e | %13.6e %13.6e %13.6e %13.6e\n",
			        f[i][0], f[i][1], f[i][2], f[i][3], want[i][0], want[i][1],
			        want[i][2], want[i][3]);
	}
	pc_pbrdf_free(p);
}

static void test_pbrdf_limits(void)
{
	/* perfect conductor: r_s = −1, r_p = +1 → (a, b, c, s) = (1, 0, −1, 0) */
	for (int t = 0; t < 3; t++) {
		double th = t == 0 ? 0 : t == 1 ? 30 : 70;
		check_specular("k = 1e90", 1.5, 1e90, 0.2, th, 1, 0, -1, 0);
		check_specular("n = 1e100", 1e100, 0, 0.2, th, 1, 0, -1, 0);
		check_specular("k = 1e100", 1e100, 1e100, 0.2, th, 1, 0, -1, 0);
		/* ñ → 0: r_s = e^{2iβ}, r_p = −1 (β = θ): a = 1, b = 0, c = −cos 2β, s = −sin 2β */
		double b2 = 2 * th * PC_PI / 180;
		check_specular("n = 1e-200", 1e-200, 0, 0.2, th, 1, 0, -cos(b2), -sin(b2));
	}
	/* a lobe of σ = 1e-20 at exactly the specular direction: the Fresnel matrix at β = θ times
	 * K = 1/(8πσ² cos²θ) ≈ 4e38, not 0 */
	for (int t = 0; t < 3; t++) {
		double th = t == 0 ? 0 : t == 1 ? 30 : 60;
		double beta = th * PC_PI / 180;
		long double complex rs, rp;
		fresnel_ref(1.5, 0, cosl(beta), sinl(beta) * sinl(beta), &rs, &rp);
		double Rs = (double)(creall(rs) * creall(rs) + cimagl(rs) * cimagl(rs));
		double Rp = (double)(creall(rp) * creall(rp) + cimagl(rp) * cimagl(rp));
		long double complex x = rs * conjl(rp);
		check_specular("sigma = 1e-20", 1.5, 0, 1e-20, th, 0.5 * (Rs + Rp), 0.5 * (Rs - Rp),
		               (double)creall(x), (double)cimagl(x));
	}
	/* ñ = 1 − 1e-160 i at normal incidence: r_s = −r_p = ik/(2 − ik), a = k²/(4 + k²)
	 * = 2.5e-321 is subnormal (four significant digits), but under a lobe of σ = 1e-9 (K =
	 * 4e16) the matrix K·a·diag(1, 1, −1, −1) is normal and must be exact to rounding (it
	 * was 1.1e-5 off before pc_facet_abcs_e): K·a computed here on k·2^530 */
	{
		const double k = 1e-160, sigma = 1e-9;
		const double ks = ldexp(k, 530);
		const double Ka = ldexp(ks * ks / (4 + k * k) / (8 * PC_PI * sigma * sigma), -1060);
		pc_pbrdf *p = make(1, k, sigma, PC_DIFFUSE_NONE);
		double f[4][4];
		CHECK_EQ_INT(pc_pbrdf_eval_deg(p, 0, 0, 180, f), 0);
		double e = 0;
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				e = fmax(e, fabs(f[i][j] - (i == j ? (i < 2 ? Ka : -Ka) : 0)));
		printf(
		    "pBRDF with subnormal Fresnel products: f00 %.17g, want %.17g, worst %.2g of "
		    "it\n",
		    f[0][0], Ka, e / Ka);
		CHECK(Ka > DBL_MIN && e <= 1e-13 * Ka);
		pc_pbrdf_free(p);
	}
	/* the smallest σ accepted is finite at its peak; below it a refusal naming sigma */
	check_specular("sigma = SIGMA_MIN", 1.5, 0, PC_PBRDF_SIGMA_MIN, 0, 0.04, 0, -0.04, 0);
	const double tiny[] = {1e-160, 1e-320, PC_PBRDF_SIGMA_MIN / 2};
	for (int i = 0; i < 3; i++) {
		pc_material m = {1.5, 0, tiny[i], PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0};
		pc_pbrdf *p = NULL;
		CHECK_EQ_INT(pc_pbrdf_new(&m, &p), PC_ERANGE);
		CHECK(p == NULL);
		CHECK(strstr(pc_error_detail(), "sigma") != NULL);
	}
}

/* Random materials and directions over the whole accepted range: every element finite, and the
 * matrix realisable (its coherency matrix positive semi-definite), the property the pBRDF
 * promises (physics.md §2: a weighted sum of pure Jones matrices and a depolariser). */
static void test_pbrdf_finite_sweep(void)
{
	int bad = 0, nonphys = 0, n = 0;
	for (int it = 0; it < 400; it++) {
		double nn = exp(log(1e-300) + urand() * (log(1e100) - log(1e-300)));
		double kk =
		    urand() < 0.3 ? 0 : exp(log(1e-300) + urand() * (log(1e100) - log(1e-300)));
		double sg =
		    exp(log(PC_PBRDF_SIGMA_MIN) + urand() * (log(1e3) - log(PC_PBRDF_SIGMA_MIN)));
		pc_diffuse d = (pc_diffuse)(it % 3);
		pc_material m = {nn,          kk, sg, d, it & 4 ? PC_SHADOW_NONE : PC_SHADOW_TS,
		                 PC_RHO_QUAD, 4};
		pc_pbrdf *p = NULL;
		if (pc_pbrdf_new(&m, &p)) {
			bad++;
			fprintf(stderr, "  pc_pbrdf_new(%g, %g, %g): %s\n", nn, kk, sg,
			        pc_error_detail());
			continue;
		}
		for (int g = 0; g < 20; g++) {
			/* directions: exact specular, backscatter, normal, grazing, random */
			static const double special[][3] = {{0, 0, 0},
			                                    {0, 0, 180},
			                                    {30, 30, 180},
			                                    {30, 30, 0},
			                                    {89.9999, 89.9999, 180},
			                                    {90, 45, 180},
			                                    {45, 90, 0},
			                                    {89, 1, 90}};
			double ti, tr, ph;
			if (g < 8) {
				ti = special[g][0];
				tr = special[g][1];
				ph = special[g][2];
			} else {
				ti = 90 * urand();
				tr = 90 * urand();
				ph = 360 * urand();
			}
			double f[4][4];
			pc_pbrdf_eval_deg(p, ti, tr, ph, f);
			n++;
			if (!finite16(f)) {
				bad++;
				fprintf(stderr,
				        "  not finite: n=%g k=%g sigma=%g at (%g, %g, %g)\n", nn,
				        kk, sg, ti, tr, ph);
			} else if (f[0][0] > 0 && !pc_mueller_is_physical(f, 1e-9)) {
				nonphys++;
				fprintf(stderr,
				        "  not physical: n=%g k=%g sigma=%g at (%g, %g, %g)\n", nn,
				        kk, sg, ti, tr, ph);
			}
		}
		pc_pbrdf_free(p);
	}
	CHECK_EQ_INT(bad, 0);
	CHECK_EQ_INT(nonphys, 0);
	printf("pBRDF over extreme materials: %d evaluations, %d not finite, %d not physical\n", n,
	       bad, nonphys);
}

static void decompose_both(const double M[4][4], unsigned opt, pc_lu_chipman *lc, bool *same)
{
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, opt, lc), 0);
	/* the vector map kernel gives the same bits (it hands extreme magnitudes to the scalar
	 * code) */
	const lc_map_check c = lc_map_vs_scalar(M, opt);
	CHECK_EQ_INT(c.map_status, 0);
	*same = c.same;
}

static void test_decompose_scaled(void)
{
	/* identity, an ideal polarizer, a partial depolariser with diattenuation and retardance, a
	 * rotator; the first three have dyadic entries, exact at every power-of-two scale down to
	 * the subnormals */
	const double c = cos(0.7), s = sin(0.7);
	const double base[4][4][4] = {
	    {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}},
	    {{0.5, 0.5, 0, 0}, {0.5, 0.5, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}},
	    {{1, 0.25, 0, 0}, {0.25, 0.5, 0, 0}, {0, 0, 0.375, 0.125}, {0, 0, -0.125, 0.375}},
	    {{1, 0, 0, 0}, {0, c, s, 0}, {0, -s, c, 0}, {0, 0, 0, 1}},
	};
	const int dyadic[4] = {1, 1, 1, 0};
	/* powers of two are exact; 1e308 and 1e-300 are not, but stay normal (relative rounding
	 * 1e-16) */
	const double scales[] = {1,         1e308,     0x1p1000, 1e-300,
	                         0x1p-1030, 0x1p-1062, 0x1p-300, 0x1p300};
	const int subnormal[] = {0, 0, 0, 0, 1, 1, 0, 0};
	int n = 0, mismatch = 0;
	for (int b = 0; b < 4; b++) {
		pc_lu_chipman ref;
		CHECK_EQ_INT(pc_lu_chipman_decompose(base[b], PC_LC_FILTER, &ref), 0);
		for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
			if (subnormal[k] && !dyadic[b])
				continue;
			double M[4][4];
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					M[i][j] = base[b][i][j] * scales[k];
			for (unsigned opt = 0; opt < 2; opt++) {
				pc_lu_chipman lc;
				bool same;
				decompose_both(M, opt ? PC_LC_FILTER : 0, &lc, &same);
				n++;
				if (!same) {
					mismatch++;
					fprintf(stderr,
					        "  map kernel differs: base %d scale %g opt %u\n",
					        b, scales[k], opt);
				}
				bool ok = lc.physical && lc.flags == ref.flags &&
				          fabs(lc.D - ref.D) <= 1e-14 && lc.m00 == M[0][0];
				if (!(ref.flags & PC_LC_D_SINGULAR))
					ok = ok && fabs(lc.R - ref.R) <= 1e-14 &&
					     fabs(lc.Delta - ref.Delta) <= 1e-14;
				CHECK(ok);
				if (!ok)
					fprintf(stderr,
					        "  base %d scale %g: D %.17g R %.17g Delta %.17g "
					        "flags %#x physical %d; unscaled %.17g %.17g %.17g "
					        "%#x\n",
					        b, scales[k], lc.D, lc.R, lc.Delta, lc.flags,
					        lc.physical, ref.D, ref.R, ref.Delta, ref.flags);
			}
		}
	}
	CHECK_EQ_INT(mismatch, 0);
	/* analytic values: identity D = R = Δ = 0; the rotator's 3×3 block turns by 0.7 about the
	 * S3 axis: a circular retarder R = 0.7 */
	pc_lu_chipman lc;
	double M[4][4];
	memcpy(M, base[0], sizeof M);
	for (int i = 0; i < 4; i++)
		M[i][i] = 1e308;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, PC_LC_FILTER, &lc), 0);
	CHECK(lc.physical && lc.D == 0 && fabs(lc.R) <= 1e-15 && fabs(lc.Delta) <= 1e-15);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			M[i][j] = base[3][i][j] * 1e308;
	CHECK_EQ_INT(pc_lu_chipman_decompose(M, PC_LC_FILTER, &lc), 0);
	CHECK_NEAR(lc.R, 0.7, 1e-14);

	/* normalised m33 subnormal: m' = diag(x, x, δ), D = 0: λ₁ = 2x + δ, Δ = 1 − (2x + δ)/3 */
	const double xs[] = {0, 0.5};
	for (int a = 0; a < 2; a++)
		for (int e = 0; e < 2; e++) {
			double M00 = e ? 1e10 : 1;
			double Mz[4][4] = {{M00, 0, 0, 0},
			                   {0, xs[a] * M00, 0, 0},
			                   {0, 0, xs[a] * M00, 0},
			                   {0, 0, 0, 1e-310 * M00}};
			bool same;
			decompose_both(Mz, 0, &lc, &same);
			CHECK(same);
			CHECK(isfinite(lc.Delta) && isfinite(lc.R));
			CHECK_NEAR(lc.Delta, 1 - 2 * xs[a] / 3, 1e-15);
			CHECK_NEAR(lc.D, 0, 0);
		}
	printf("Lu-Chipman scaled 2^-1062..1e308: %d decompositions, map kernel mismatches %d\n", n,
	       mismatch);
}

static void test_optics_scaled(void)
{
	/* realisability and the Cloude filter do not depend on the scale of M */
	const double M[4][4] = {
	    {1, 0.3, 0, 0}, {0.3, 1, 0, 0}, {0, 0, 0.9, 0.1}, {0, 0, -0.1, 0.9}};
	const double bad[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, -1}};
	double Fref[4][4];
	pc_mueller_cloude_filter(bad, Fref, NULL);
	const double scales[] = {1e308, 1e-310, 1e-300, 0x1p700, 1e200};
	for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
		double A[4][4], B[4][4], F[4][4];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				A[i][j] = M[i][j] * scales[k];
				B[i][j] = bad[i][j] * scales[k];
			}
		CHECK(pc_mueller_is_physical(A, 1e-9));
		CHECK(!pc_mueller_is_physical(B, 1e-9));
		bool changed = false;
		pc_mueller_cloude_filter(B, F, &changed);
		CHECK(changed);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(F[i][j] / scales[k], Fref[i][j], 1e-12);
		CHECK_NEAR(pc_mueller_depol_index(A), pc_mueller_depol_index(M), 1e-14);
		CHECK(isfinite(pc_mueller_min_coherency_eig(A)));
	}
}

static void test_sincos_deg(void)
{
	/* exact at every multiple of 90°, including large and negative angles */
	for (long q = -12; q <= 12; q++) {
		double s, c;
		pc_sincos_deg(90.0 * (double)q, &s, &c);
		long m = ((q % 4) + 4) % 4;
		CHECK(s == (m == 1 ? 1 : m == 3 ? -1 : 0));
		CHECK(c == (m == 0 ? 1 : m == 2 ? -1 : 0));
	}
	double s, c;
	pc_sincos_deg(90.0 * 1e12, &s, &c);
	CHECK(s == 0 && c == 1);
	/* elsewhere the libm value to rounding */
	for (int i = 0; i < 1000; i++) {
		double d = -720 + 1440 * urand();
		pc_sincos_deg(d, &s, &c);
		CHECK_NEAR(s, sin(d * PC_PI / 180), 4e-15);
		CHECK_NEAR(c, cos(d * PC_PI / 180), 4e-15);
	}
	pc_sincos_deg(NAN, &s, &c);
	CHECK(isnan(s) && isnan(c));
}

int main(void)
{
	test_fresnel_extreme();
	test_fresnel_near_one();
	test_pbrdf_limits();
	test_pbrdf_finite_sweep();
	test_decompose_scaled();
	test_optics_scaled();
	test_sincos_deg();
	return pc_test_finish("test_hard_cases");
}
