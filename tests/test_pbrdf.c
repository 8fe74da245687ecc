/* The corrected pBRDF (physics.md §2, §4, §5) against independent values: the reference matrices
 * of physics.md §2, a slow reference written here from the equations (angles and acos instead
 * of vectors, libm csqrt Fresnel, Jones → Mueller from Stokes vectors of propagated fields),
 * a brute-force hemispherical integral of ρ^s, analytic limits, frame covariance, and every hard
 * case of physics.md §4. */
#include <complex.h>
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

#define DEG (PC_PI / 180)

static uint64_t rng = 0x2545f4914f6cdd1dull;
static double urand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}

static pc_pbrdf *make(double n, double k, double sigma, pc_diffuse d, pc_shadowing s, int order)
{
	pc_material m = {n, k, sigma, d, s, PC_RHO_QUAD, order};
	pc_pbrdf *p = NULL;
	int rc = pc_pbrdf_new(&m, &p);
	if (rc) {
		fprintf(stderr, "pc_pbrdf_new: %s\n", pc_error_detail());
		exit(1);
	}
	return p;
}

static double maxabs(const double f[4][4])
{
	double m = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			m = fmax(m, fabs(f[i][j]));
	return m;
}

static bool all_finite(const double f[4][4])
{
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			if (!isfinite(f[i][j]))
				return false;
	return true;
}

/* ---------------------------------------------------------------------------------------- */
/* slow reference */

static void cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void stokes_of(double complex Es, double complex Ep, double S[4])
{
	S[0] = creal(Es * conj(Es) + Ep * conj(Ep));
	S[1] = creal(Es * conj(Es) - Ep * conj(Ep));
	S[2] = 2 * creal(Es * conj(Ep));
	S[3] = 2 * cimag(conj(Es) * Ep);
}

/* Mueller matrix of a Jones matrix from four pure input states:
 * s → (1,1,0,0), p → (1,−1,0,0), 45° → (1,0,1,0), (1, i)/√2 → (1,0,0,1). */
static void ref_mueller(const double complex J[2][2], double M[4][4])
{
	const double r = sqrt(0.5);
	const double complex in[4][2] = {{1, 0}, {0, 1}, {r, r}, {r, r * I}};
	double o[4][4];
	for (int k = 0; k < 4; k++)
		stokes_of(J[0][0] * in[k][0] + J[0][1] * in[k][1],
		          J[1][0] * in[k][0] + J[1][1] * in[k][1], o[k]);
	for (int i = 0; i < 4; i++) {
		double c0 = 0.5 * (o[0][i] + o[1][i]);
		M[i][0] = c0;
		M[i][1] = 0.5 * (o[0][i] - o[1][i]);
		M[i][2] = o[2][i] - c0;
		M[i][3] = o[3][i] - c0;
	}
}

/* f from the equations with angles: cos2β = k_i·k_r (eq. 4), θ_N = acos(ĥ_z), P_D literally. */
static void ref_pbrdf(double n, double k, double sigma, bool ts, double rho, double ti, double tr,
                      double dphi, double f[4][4])
{
	double ki[3] = {sin(ti), 0, cos(ti)};
	double kr[3] = {sin(tr) * cos(dphi), sin(tr) * sin(dphi), cos(tr)};
	double si[3] = {0, 1, 0}, sr[3] = {sin(dphi), -cos(dphi), 0};
	double di[3] = {-ki[0], -ki[1], -ki[2]}, pi[3], pr[3];
	cross(di, si, pi);
	cross(kr, sr, pr);
	double beta = 0.5 * acos(fmin(1, fmax(-1, dot(ki, kr))));
	double h[3] = {ki[0] + kr[0], ki[1] + kr[1], ki[2] + kr[2]}, hl = sqrt(dot(h, h));
	for (int i = 0; i < 3; i++)
		h[i] /= hl;
	double thN = acos(h[2]);
	double complex eps = (n - I * k) * (n - I * k), w = csqrt(eps - sin(beta) * sin(beta));
	if (cimag(w) > 0)
		w = -w;
	double complex rs = (cos(beta) - w) / (cos(beta) + w);
	double complex rp = (eps * cos(beta) - w) / (eps * cos(beta) + w);
	double sF[3];
	cross(di, h, sF);
	double l = sqrt(dot(sF, sF));
	if (l < 1e-12)
		memcpy(sF, si, sizeof sF);
	else
		for (int i = 0; i < 3; i++)
			sF[i] /= l;
	double pFi[3], pFr[3];
	cross(di, sF, pFi);
	cross(kr, sF, pFr);
	double Tin[2][2] = {{dot(sF, si), dot(sF, pi)}, {dot(pFi, si), dot(pFi, pi)}};
	double Tout[2][2] = {{dot(sr, sF), dot(sr, pFr)}, {dot(pr, sF), dot(pr, pFr)}};
	double complex J[2][2];
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 2; b++)
			J[a][b] = Tout[a][0] * rs * Tin[0][b] + Tout[a][1] * rp * Tin[1][b];
	double M[4][4];
	ref_mueller(J, M);
	double cN = cos(thN), tN = tan(thN);
	double PD = exp(-tN * tN / (2 * sigma * sigma)) / (8 * PC_PI * sigma * sigma * pow(cN, 3));
	double G = 1;
	if (ts)
		G = fmin(1, fmin(2 * cN * cos(tr) / cos(beta), 2 * cN * cos(ti) / cos(beta)));
	double K = PD * G / (cN * cos(ti) * cos(tr));
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			f[i][j] = K * M[i][j];
	if (rho >= 0)
		f[0][0] += (1 - rho) / PC_PI * M[0][0];
}

/* ---------------------------------------------------------------------------------------- */

static void test_reference_values(void)
{
	/* physics.md §2 reference 1: ñ = 1.5, σ = 0.2, θ_i = θ_r = 30°, Δφ = 180° */
	pc_pbrdf *p = make(1.5, 0, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 64);
	double f[4][4];
	CHECK_EQ_INT(pc_pbrdf_eval(p, 30 * DEG, 30 * DEG, 180 * DEG, f), 0);
	CHECK_REL(f[0][0], 6.772339e-02, 1e-6);
	CHECK_REL(f[0][1], 2.158337e-02, 1e-6);
	CHECK_REL(f[1][0], 2.158337e-02, 1e-6);
	CHECK_REL(f[1][1], 5.507109e-02, 1e-6);
	CHECK_REL(f[2][2], -5.066541e-02, 1e-6);
	CHECK_REL(f[3][3], -5.066541e-02, 1e-6);
	const int zero1[][2] = {{0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 0},
	                        {2, 1}, {2, 3}, {3, 0}, {3, 1}, {3, 2}};
	for (size_t z = 0; z < sizeof zero1 / sizeof zero1[0]; z++)
		CHECK_NEAR(f[zero1[z][0]][zero1[z][1]], 0, 1e-14);
	pc_lu_chipman lc;
	CHECK_EQ_INT(pc_lu_chipman_decompose(f, 0, &lc), 0);
	CHECK_NEAR(lc.D, 0.318699, 6e-7);
	CHECK_NEAR(lc.R, PC_PI, 1e-9);
	CHECK_NEAR(lc.Delta, 0.209795, 6e-7);
	CHECK(lc.physical);
	pc_pbrdf_free(p);

	/* reference 2: ñ = 1.46 − 1.28i, σ = 0.2, θ_i = 40°, θ_r = 55°, Δφ = 150° */
	p = make(1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 64);
	CHECK_EQ_INT(pc_pbrdf_eval(p, 40 * DEG, 55 * DEG, 150 * DEG, f), 0);
	CHECK_REL(f[0][0], 2.728093e-01, 1e-6);
	CHECK_REL(f[0][1], 6.506253e-02, 1e-6);
	CHECK_REL(f[0][2], 7.318776e-02, 1e-6);
	CHECK_NEAR(f[0][3], 0, 1e-14);
	CHECK_REL(f[1][0], 7.769040e-02, 1e-6);
	CHECK_REL(f[2][0], 5.961360e-02, 1e-6);
	CHECK_NEAR(f[3][0], 0, 1e-14);
	CHECK_REL(f[3][3], -1.590317e-01, 1e-6);
	CHECK_REL(f[2][3], -7.800504e-02, 1e-6);
	CHECK_EQ_INT(pc_lu_chipman_decompose(f, 0, &lc), 0);
	CHECK_NEAR(lc.D, 0.358955, 6e-7);
	CHECK_NEAR(lc.R, 2.590406, 6e-7);
	CHECK_NEAR(lc.Delta, 0.263739, 6e-7);
	pc_pbrdf_free(p);
}

/* The library against the slow reference over random geometries, materials and frames. */
static void test_against_reference(void)
{
	double worst = 0;
	for (int t = 0; t < 3000; t++) {
		static double n, k, sigma;
		static bool ts;
		static pc_pbrdf *p;
		if (t % 30 == 0) { /* a new material every 30 geometries */
			int u = t / 30;
			n = 0.2 + 3 * urand();
			k = u % 2 ? 0 : 4 * urand();
			sigma = 0.03 + 0.6 * urand();
			ts = u % 3 != 0;
			pc_pbrdf_free(p);
			p = make(n, k, sigma, u % 4 == 0 ? PC_DIFFUSE_NONE : PC_DIFFUSE_FRESNEL,
			         ts ? PC_SHADOW_TS : PC_SHADOW_NONE, 8);
		}
		double ti = 85 * DEG * urand(), tr = 85 * DEG * urand(), dphi = 2 * PC_PI * urand();
		if (t % 10 == 0)
			dphi = PC_PI; /* exactly in-plane */
		double f[4][4], g[4][4];
		pc_pbrdf_eval(p, ti, tr, dphi, f);
		double rho = pc_pbrdf_material(p)->diffuse == PC_DIFFUSE_NONE
		                 ? -1
		                 : pc_pbrdf_rho_s_fast(p, cos(ti));
		if (rho > 1)
			rho = 1; /* the library gives no negative diffuse term */
		ref_pbrdf(n, k, sigma, ts, rho, ti, tr, dphi, g);
		double scale = maxabs(g);
		if (scale < 1e-250)
			continue;
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				worst = fmax(worst, fabs(f[i][j] - g[i][j]) / scale);
		if (t == 2999)
			pc_pbrdf_free(p);
	}
	/* the reference's acos-based θ_N and β lose ~1e-8 relative near θ_N = 0 and β = 0 */
	CHECK_NEAR(worst, 0, 1e-7);
	printf("pbrdf vs slow reference: worst relative difference %.2e\n", worst);
}

/* Caller frames rotated by α_i about k_i and α_r about k_r: f' = R_M(α_r) f R_M(−α_i). */
static void test_frame_covariance(void)
{
	pc_pbrdf *p = make(1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 16);
	double worst = 0;
	for (int t = 0; t < 500; t++) {
		double ti = 80 * DEG * urand(), tr = 80 * DEG * urand(), dphi = 2 * PC_PI * urand();
		if (t % 5 == 0) {
			tr = ti; /* exact backscatter: the s_F fallback */
			dphi = 0;
		}
		double ai = 7 * urand(), ar = 7 * urand();
		double ki[3] = {sin(ti), 0, cos(ti)};
		double kr[3] = {sin(tr) * cos(dphi), sin(tr) * sin(dphi), cos(tr)};
		double si[3] = {0, 1, 0}, sr[3] = {sin(dphi), -cos(dphi), 0};
		double di[3] = {-ki[0], -ki[1], -ki[2]}, pi[3], pr[3];
		cross(di, si, pi);
		cross(kr, sr, pr);
		double si2[3], sr2[3];
		for (int i = 0; i < 3; i++) {
			si2[i] = cos(ai) * si[i] + sin(ai) * pi[i];
			sr2[i] = cos(ar) * sr[i] + sin(ar) * pr[i];
		}
		double f[4][4], f2[4][4], Ri[4][4], Rr[4][4], e[4][4];
		pc_pbrdf_eval_vec(p, ki, kr, si, sr, f);
		pc_pbrdf_eval_vec(p, ki, kr, si2, sr2, f2);
		pc_mueller_rotator(-ai, Ri);
		pc_mueller_rotator(ar, Rr);
		pc_mueller_mul(Rr, f, e);
		pc_mueller_mul(e, Ri, e);
		double scale = maxabs(f);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				worst = fmax(worst, fabs(e[i][j] - f2[i][j]) / scale);
	}
	CHECK_NEAR(worst, 0, 1e-13);
	pc_pbrdf_free(p);
}

static void test_invariants(void)
{
	double f[4][4];
	pc_lu_chipman lc;
	/* D ≡ DoP for every geometry (physics.md §2) */
	double worst = 0;
	for (int t = 0; t < 100; t++) {
		pc_pbrdf *p = make(0.3 + 2 * urand(), 3 * urand(), 0.05 + 0.5 * urand(),
		                   (pc_diffuse)(t % 3), PC_SHADOW_TS, 4);
		for (int g = 0; g < 20; g++) {
			pc_pbrdf_eval(p, 88 * DEG * urand(), 88 * DEG * urand(),
			              2 * PC_PI * urand(), f);
			if (!(f[0][0] > 0))
				continue;
			/* eq. 21, on the normalised column so that 1e-231 entries do not underflow
			 */
			double p1 = f[1][0] / f[0][0], p2 = f[2][0] / f[0][0],
			       p3 = f[3][0] / f[0][0];
			double dop = sqrt(p1 * p1 + p2 * p2 + p3 * p3);
			pc_lu_chipman_decompose(f, PC_LC_NO_FACTORS, &lc);
			worst = fmax(worst, fabs(lc.D - dop));
		}
		pc_pbrdf_free(p);
	}
	CHECK_NEAR(worst, 0, 1e-13);

	/* in-plane retardance R = |arg(r_s/r_p)| at β = (θ_i + θ_r)/2 (Δφ = 180°) or |θ_i − θ_r|/2
	 * (Δφ = 0), for every σ; specular-only DoP = |R_s − R_p|/(R_s + R_p) */
	for (int t = 0; t < 300; t++) {
		double n = 0.5 + 2 * urand(), k = t % 2 ? 0 : 3 * urand(),
		       sigma = 0.05 + 0.6 * urand();
		double ti = 80 * DEG * urand(), tr = 80 * DEG * urand();
		bool fwd = t % 3 != 0;
		double beta = fwd ? 0.5 * (ti + tr) : 0.5 * fabs(ti - tr);
		double complex eps = (n - I * k) * (n - I * k),
		               w = csqrt(eps - sin(beta) * sin(beta));
		if (cimag(w) > 0)
			w = -w;
		double complex rs = (cos(beta) - w) / (cos(beta) + w);
		double complex rp = (eps * cos(beta) - w) / (eps * cos(beta) + w);
		double Rs = creal(rs * conj(rs)), Rp = creal(rp * conj(rp));
		pc_pbrdf *p = make(n, k, sigma, PC_DIFFUSE_NONE, PC_SHADOW_TS, 4);
		pc_pbrdf_eval(p, ti, tr, fwd ? PC_PI : 0, f);
		pc_pbrdf_free(p);
		if (!(f[0][0] > 1e-200))
			continue;
		pc_lu_chipman_decompose(f, PC_LC_NO_FACTORS, &lc);
		if (lc.flags & PC_LC_D_SINGULAR)
			continue;
		CHECK_NEAR(lc.R, fabs(carg(rs / rp)), 1e-9);
		CHECK_NEAR(lc.D, fabs(Rs - Rp) / (Rs + Rp), 1e-12);
	}

	/* normal incidence on the facet (exact backscatter): M/M00 = diag(1, 1, −1, −1) */
	for (int t = 0; t < 20; t++) {
		pc_pbrdf *p = make(0.3 + 2 * urand(), 3 * urand(), 0.1 + 0.3 * urand(),
		                   PC_DIFFUSE_NONE, PC_SHADOW_TS, 8);
		double th = 70 * DEG * urand();
		pc_pbrdf_eval(p, th, th, 0, f);
		pc_pbrdf_free(p);
		const double d[4] = {1, 1, -1, -1};
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(f[i][j] / f[0][0], i == j ? d[i] : 0, 1e-14);
	}
	/* realisability of the model's matrices (coherency matrix PSD) */
	for (int t = 0; t < 20; t++) {
		pc_pbrdf *p = make(0.3 + 2 * urand(), 3 * urand(), 0.05 + 0.5 * urand(),
		                   (pc_diffuse)(t % 3), PC_SHADOW_TS, 4);
		for (int g = 0; g < 10; g++) {
			pc_pbrdf_eval(p, 85 * DEG * urand(), 85 * DEG * urand(),
			              2 * PC_PI * urand(), f);
			if (f[0][0] > 1e-200)
				CHECK(pc_mueller_min_coherency_eig(f) >= -1e-12);
		}
		pc_pbrdf_free(p);
	}
}

/* ρ^s: slope-space quadrature vs a brute-force midpoint integral over the outgoing hemisphere
 * of the evaluated f00 (paper eq. 9); σ → 0 limit; the mirror switch; the eval table. */
static double brute_rho(const pc_pbrdf *p_none, double ti, int n)
{
	double sum = 0, f[4][4];
	for (int a = 0; a < n; a++) {
		double tr = (a + 0.5) * (0.5 * PC_PI) / n;
		double w = cos(tr) * sin(tr) * (0.5 * PC_PI / n) * (PC_PI / n) * 2;
		for (int b = 0; b < n; b++) {
			double ph = (b + 0.5) * PC_PI / n;
			pc_pbrdf_eval(p_none, ti, tr, ph, f);
			sum += f[0][0] * w;
		}
	}
	return sum;
}

static void test_rho(void)
{
	const struct {
		double n, k, sigma, ti;
		pc_diffuse d;
	} cs[] = {{1.46, 1.28, 0.3, 40 * DEG, PC_DIFFUSE_FRESNEL},
	          {1.5, 0, 0.12, 70 * DEG, PC_DIFFUSE_GEOMETRIC},
	          {1.47, 0.47, 0.5, 10 * DEG, PC_DIFFUSE_FRESNEL}};
	for (size_t c = 0; c < sizeof cs / sizeof cs[0]; c++) {
		pc_pbrdf *pn =
		    make(cs[c].n, cs[c].k, cs[c].sigma, PC_DIFFUSE_NONE, PC_SHADOW_TS, 8);
		pc_pbrdf *pf =
		    make(cs[c].n, cs[c].k, cs[c].sigma, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 8);
		pc_pbrdf *pg =
		    make(cs[c].n, cs[c].k, cs[c].sigma, PC_DIFFUSE_GEOMETRIC, PC_SHADOW_TS, 8);
		double bf = brute_rho(pn, cs[c].ti, 500);
		CHECK_REL(pc_pbrdf_rho_s_quad(pf, cs[c].ti, 128), bf, 3e-4);
		/* geometric ρ: the same integral with F = 1, i.e. of f00/a(β); check it is larger
		 * than the Fresnel-weighted one and at most 1 */
		double rg = pc_pbrdf_rho_s_quad(pg, cs[c].ti, 128);
		CHECK(rg > bf && rg <= 1);
		pc_pbrdf_free(pn);
		pc_pbrdf_free(pf);
		pc_pbrdf_free(pg);
	}
	/* geometric ρ against brute force: integrate the facet-count only (n huge → F → 1 with
	 * the sign of r irrelevant to f00) */
	pc_pbrdf *pn = make(1, 1e12, 0.25, PC_DIFFUSE_NONE, PC_SHADOW_TS, 8);
	pc_pbrdf *pg = make(1.5, 0, 0.25, PC_DIFFUSE_GEOMETRIC, PC_SHADOW_TS, 8);
	CHECK_REL(pc_pbrdf_rho_s_quad(pg, 55 * DEG, 128), brute_rho(pn, 55 * DEG, 500), 3e-4);
	pc_pbrdf_free(pn);
	pc_pbrdf_free(pg);

	/* σ → 0: ρ^s → F(θ_i) (physics.md §2: ratio 1.0000–1.0002 at σ = 0.01 up to θ_i = 40°;
	 * beyond, the O(σ²) average of F over the lobe gives up to +4e-4 at 60° and −1.3e-3 at
	 * 80°). The approach is O(σ²): halving σ divides ratio − 1 by 4. */
	pc_pbrdf *p = make(1.5, 0, 0.01, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 64);
	pc_pbrdf *p2 = make(1.5, 0, 0.02, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 64);
	CHECK(!(pc_pbrdf_flags(p) & PC_PBRDF_MIRROR));
	for (int i = 0; i <= 8; i++) {
		double ti = i * 10 * DEG, F = pc_fresnel_reflectance(1.5, 0, ti);
		double r1 = pc_pbrdf_rho_s(p, ti) / F, r2 = pc_pbrdf_rho_s(p2, ti) / F;
		if (i <= 3)
			CHECK(r1 > 1 - 1e-7 && r1 < 1.0002);
		CHECK_NEAR(r1, 1, 1.5e-3);
		if (i >= 1 && i <= 6)
			CHECK_NEAR((r2 - 1) / (r1 - 1), 4, 0.4);
	}
	pc_pbrdf_free(p);
	pc_pbrdf_free(p2);
	/* below PC_PBRDF_SIGMA_MIRROR: the mirror model, exactly F(θ_i) (or 1 for geometric) */
	p = make(1.46, 1.28, 0.005, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 0);
	CHECK(pc_pbrdf_flags(p) & PC_PBRDF_MIRROR);
	CHECK_NEAR(pc_pbrdf_rho_s(p, 0.6), pc_fresnel_reflectance(1.46, 1.28, 0.6), 1e-15);
	CHECK_NEAR(pc_pbrdf_rho_s_fast(p, cos(0.6)), pc_fresnel_reflectance(1.46, 1.28, 0.6),
	           1e-15);
	pc_pbrdf_free(p);
	p = make(1.46, 1.28, 0.005, PC_DIFFUSE_GEOMETRIC, PC_SHADOW_TS, 0);
	CHECK_NEAR(pc_pbrdf_rho_s(p, 0.6), 1, 0);
	pc_pbrdf_free(p);

	/* the per-material eval table against the direct quadrature of the same order */
	double worst = 0;
	for (int t = 0; t < 12; t++) {
		p = make(0.3 + 2 * urand(), 2 * urand(), 0.01 + 0.7 * urand(),
		         t % 2 ? PC_DIFFUSE_FRESNEL : PC_DIFFUSE_GEOMETRIC,
		         t % 3 ? PC_SHADOW_TS : PC_SHADOW_NONE, 16);
		for (int i = 0; i < 10; i++) {
			double ti = 89.9 * DEG * urand();
			double a = pc_pbrdf_rho_s(p, ti), b = pc_pbrdf_rho_s_fast(p, cos(ti));
			worst = fmax(worst, fabs(a - b) / fmax(a, 1));
		}
		pc_pbrdf_free(p);
	}
	CHECK_NEAR(worst, 0, 3e-4);
	printf("rho_s eval table vs direct order-16 rule: worst %.2e\n", worst);

	/* grazing incidence with broad lobes, where the φ_h clustering of the rule matters:
	 * quad:16 and quad:512 against the brute-force hemisphere integral (500², measured to
	 * agree with quad:512 to ≤ 6e-5 here). Measured worst: quad:16 7e-4 (1.2e-2 for uniform
	 * φ_h nodes, the rule before the clustering), quad:32 1.3e-4. */
	double wg16 = 0, wg32 = 0;
	for (int si = 0; si < 3; si++) {
		const double sg[3] = {0.2, 0.3, 0.5};
		pc_pbrdf *gn = make(1.46, 1.28, sg[si], PC_DIFFUSE_NONE, PC_SHADOW_TS, 16);
		pc_pbrdf *gf = make(1.46, 1.28, sg[si], PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 16);
		for (int t = 0; t < 3; t++) {
			double ti = (85 + 2 * t) * DEG, bf = brute_rho(gn, ti, 500);
			CHECK_REL(pc_pbrdf_rho_s_quad(gf, ti, 512), bf, 1e-4);
			double e16 = fabs(pc_pbrdf_rho_s_quad(gf, ti, 16) / bf - 1);
			double e32 = fabs(pc_pbrdf_rho_s_quad(gf, ti, 32) / bf - 1);
			CHECK_NEAR(e16, 0, 1.5e-3);
			CHECK_NEAR(e32, 0, 3e-4);
			wg16 = fmax(wg16, e16);
			wg32 = fmax(wg32, e32);
		}
		pc_pbrdf_free(gn);
		pc_pbrdf_free(gf);
	}
	printf("rho_s at theta_i 85-89 deg, sigma 0.2-0.5 vs brute force: quad:16 %.1e, quad:32 "
	       "%.1e\n",
	       wg16, wg32);

	/* table mode (bicubic 64 × 32) against a high-order rule: ~1e-3 (physics.md §5) */
	pc_material mt = {1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_TABLE, 16};
	CHECK_EQ_INT(pc_pbrdf_new(&mt, &p), 0);
	for (int i = 0; i < 8; i++) {
		double ti = i * 11 * DEG;
		CHECK_NEAR(pc_pbrdf_rho_s(p, ti), pc_pbrdf_rho_s_quad(p, ti, 96), 2e-3);
	}
	pc_pbrdf_free(p);
	mt.sigma = 1.5;
	CHECK_EQ_INT(pc_pbrdf_new(&mt, &p), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "sigma") != NULL);
}

static void test_hard_cases(void)
{
	double f[4][4], g[4][4];
	pc_pbrdf *p = make(1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 16);
	pc_pbrdf *pn = make(1.46, 1.28, 0.2, PC_DIFFUSE_NONE, PC_SHADOW_TS, 16);

	/* θ_i = 0 and θ_r = 0: finite; at θ_i = 0 a change of Δφ only rotates the incident frame:
	 * f(Δφ) = f(0) R_M(−Δφ) */
	pc_pbrdf_eval(p, 0, 0, 0, f);
	CHECK(all_finite(f) && f[0][0] > 0);
	pc_pbrdf_eval(p, 0.3, 0, 1.0, f);
	CHECK(all_finite(f) && f[0][0] > 0);
	pc_pbrdf_eval(p, 0, 35 * DEG, 0, g);
	for (int t = 0; t < 10; t++) {
		double a = 2 * PC_PI * urand(), R[4][4], e[4][4];
		pc_pbrdf_eval(p, 0, 35 * DEG, a, f);
		pc_mueller_rotator(-a, R);
		pc_mueller_mul(g, R, e);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(f[i][j], e[i][j], 1e-14 * maxabs(g));
	}
	/* continuity at θ = 0 */
	pc_pbrdf_eval(p, 1e-9, 20 * DEG, 2.0, g);
	pc_pbrdf_eval(p, 0, 20 * DEG, 2.0, f);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			CHECK_NEAR(f[i][j], g[i][j], 1e-7 * maxabs(f));

	/* β → 0 (exact backscatter) is continuous with its neighbourhood */
	pc_pbrdf_eval(pn, 37 * DEG, 37 * DEG, 0, f);
	pc_pbrdf_eval(pn, 37 * DEG, 37 * DEG + 1e-8, 1e-8, g);
	CHECK(all_finite(f));
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			CHECK_NEAR(f[i][j], g[i][j], 1e-6 * maxabs(f));

	/* exactly in-plane: no arccos domain error, continuous */
	pc_pbrdf_eval(pn, 50 * DEG, 20 * DEG, PC_PI, f);
	pc_pbrdf_eval(pn, 50 * DEG, 20 * DEG, PC_PI - 1e-9, g);
	CHECK(all_finite(f));
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			CHECK_NEAR(f[i][j], g[i][j], 1e-7 * maxabs(f));

	/* grazing: finite with G (f·cosθ_i → 0), zero below the horizon and for k_r = −k_i */
	pc_pbrdf_eval(p, PC_PI / 2, 60 * DEG, PC_PI, f);
	CHECK(all_finite(f));
	pc_pbrdf_eval(p, PC_PI / 2 - 1e-9, PC_PI / 2 - 1e-9, PC_PI, f);
	CHECK(all_finite(f));
	/* off the grazing specular direction G ∝ cosθ_i: f·cosθ_i → 0 as θ_i → 90° */
	pc_pbrdf_eval(pn, PC_PI / 2 - 1e-6, 60 * DEG, PC_PI, f);
	pc_pbrdf_eval(pn, PC_PI / 2 - 1e-3, 60 * DEG, PC_PI, g);
	CHECK(all_finite(f) && f[0][0] > 0);
	CHECK_REL(f[0][0] * sin(1e-6) / (g[0][0] * sin(1e-3)), 1e-3, 1e-2);
	pc_pbrdf_eval(p, PC_PI / 2 + 1e-3, 30 * DEG, PC_PI, f);
	CHECK_NEAR(maxabs(f), 0, 0);
	pc_pbrdf_eval(p, 30 * DEG, PC_PI / 2 + 1e-3, PC_PI, f);
	CHECK_NEAR(maxabs(f), 0, 0);
	{
		double ki[3] = {1, 0, 0}, kr[3] = {-1, 0, 0}, s[3] = {0, 1, 0}, sr[3] = {0, -1, 0};
		pc_pbrdf_eval_vec(p, ki, kr, s, sr, f);
		CHECK_NEAR(maxabs(f), 0, 0);
	}
	/* without G, K ∝ 1/cosθ_i: still finite just above the horizon */
	pc_pbrdf *p0 = make(1.5, 0, 0.3, PC_DIFFUSE_NONE, PC_SHADOW_NONE, 8);
	pc_pbrdf_eval(p0, PC_PI / 2 - 1e-12, 60 * DEG, PC_PI, f);
	CHECK(all_finite(f));
	pc_pbrdf_free(p0);

	/* cosθ_N → 0: the lobe's exponent beyond 700 gives specular 0 (no ∞·0), diffuse stays:
	 * f00 = (1 − ρ^s)/π · F(β = 0), everything else exactly 0 */
	pc_pbrdf *ps = make(1.5, 0, 0.02, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 16);
	pc_pbrdf_eval(ps, 80 * DEG, 80 * DEG, 0, f);
	double expect = (1 - pc_pbrdf_rho_s_fast(ps, cos(80 * DEG))) / PC_PI * 0.04;
	CHECK_REL(f[0][0], expect, 1e-14);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			if (i || j)
				CHECK_NEAR(f[i][j], 0, 0);
	pc_pbrdf_free(ps);

	/* σ → 0: mirror flag, finite at the exact specular direction, no NaN anywhere */
	pc_pbrdf *pm = make(1.5, 0, 1e-4, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 0);
	pc_pbrdf_eval(pm, 30 * DEG, 30 * DEG, PC_PI, f);
	/* at the specular peak θ_N = 0, G = 1: f00 = F/(8πσ² cos²θ) + (1 − F)/π · F */
	double F30 = pc_fresnel_reflectance(1.5, 0, 30 * DEG);
	CHECK(all_finite(f));
	CHECK_REL(f[0][0], F30 / (8 * PC_PI * 1e-8 * 0.75) + (1 - F30) / PC_PI * F30, 1e-12);
	pc_pbrdf_eval(pm, 30 * DEG, 31 * DEG, PC_PI, f);
	CHECK(all_finite(f));
	CHECK_NEAR(f[1][1], 0, 0);
	{
		/* the mirror matrix: R_s/R_p block of the Fresnel coefficients at θ_i */
		double ki[3] = {sin(0.5), 0, cos(0.5)}, s[3] = {0, 1, 0}, sr[3] = {0, 1, 0},
		       R[4][4];
		pc_pbrdf_mirror(pm, ki, s, sr, R);
		pc_fresnel r;
		pc_fresnel_angle(1.5, 0, 0.5, &r);
		CHECK_NEAR(R[0][0], 0.5 * (r.rs_re * r.rs_re + r.rp_re * r.rp_re), 1e-15);
		CHECK_NEAR(R[0][1], 0.5 * (r.rs_re * r.rs_re - r.rp_re * r.rp_re), 1e-15);
		CHECK_NEAR(fabs(R[2][2]), fabs(r.rs_re * r.rp_re), 1e-15);
	}
	pc_pbrdf_free(pm);

	/* σ ≳ 0.5: outside the model's validity, flagged */
	pc_pbrdf *pr = make(1.5, 0, 0.7, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 0);
	CHECK(pc_pbrdf_flags(pr) & PC_PBRDF_OUTSIDE_VALIDITY);
	pc_pbrdf_free(pr);
	pr = make(1.5, 0, 0.5, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 0);
	CHECK(!(pc_pbrdf_flags(pr) & PC_PBRDF_OUTSIDE_VALIDITY));
	pc_pbrdf_free(pr);

	/* k = 0 at Brewster: r_p = 0, D = 1 → flagged, R and Δ undefined (NaN), not garbage */
	pc_pbrdf *pb = make(1.5, 0, 0.2, PC_DIFFUSE_NONE, PC_SHADOW_TS, 0);
	pc_pbrdf_eval(pb, atan(1.5), atan(1.5), PC_PI, f);
	pc_lu_chipman lc;
	CHECK_EQ_INT(pc_lu_chipman_decompose(f, 0, &lc), 0);
	CHECK(lc.flags & PC_LC_D_SINGULAR);
	CHECK_NEAR(lc.D, 1, 1e-9);
	CHECK(isnan(lc.R) && isnan(lc.Delta));
	pc_pbrdf_free(pb);

	/* metals with large k and n → 0: the explicit branch keeps reflectance ≤ 1; the specular
	 * matrix stays realisable */
	pc_pbrdf *pk = make(0.05, 40, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, 8);
	for (int t = 0; t < 50; t++) {
		pc_pbrdf_eval(pk, 85 * DEG * urand(), 85 * DEG * urand(), 2 * PC_PI * urand(), f);
		CHECK(all_finite(f));
		pc_lu_chipman_decompose(f, PC_LC_NO_FACTORS, &lc);
		CHECK(!(lc.D > 1 + 1e-12));
	}
	pc_pbrdf_free(pk);
	pc_pbrdf_free(p);
	pc_pbrdf_free(pn);
}

static void test_bad_input(void)
{
	pc_pbrdf *p = NULL;
	pc_material m = {1.5, 0, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0};
	const struct {
		double n, k, sigma;
		int order;
		const char *field;
	} bad[] = {{0, 0, 0.2, 0, "n ="},          {-1, 0, 0.2, 0, "n ="},
	           {NAN, 0, 0.2, 0, "n ="},        {1.5, -0.1, 0.2, 0, "k ="},
	           {1.5, INFINITY, 0.2, 0, "k ="}, {1.5, 0, 0, 0, "sigma"},
	           {1.5, 0, -0.1, 0, "sigma"},     {1.5, 0, NAN, 0, "sigma"},
	           {1.5, 0, 0.2, 1, "rho_order"},  {1.5, 0, 0.2, 5000, "rho_order"}};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		pc_material b = m;
		b.n = bad[i].n;
		b.k = bad[i].k;
		b.sigma = bad[i].sigma;
		b.rho_order = bad[i].order;
		CHECK_EQ_INT(pc_pbrdf_new(&b, &p), PC_EINVAL);
		CHECK(p == NULL);
		CHECK(strstr(pc_error_detail(), bad[i].field) != NULL);
	}
	pc_material b = m;
	b.diffuse = (pc_diffuse)7;
	CHECK_EQ_INT(pc_pbrdf_new(&b, &p), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "diffuse") != NULL);
	CHECK_EQ_INT(pc_pbrdf_new(NULL, &p), PC_EINVAL);
	CHECK_EQ_INT(pc_pbrdf_new(&m, &p), 0);
	CHECK(pc_pbrdf_material(p)->rho_order == 16);
	pc_pbrdf_free(p);
}

int main(void)
{
	test_reference_values();
	test_against_reference();
	test_frame_covariance();
	test_invariants();
	test_rho();
	test_hard_cases();
	test_bad_input();
	return pc_test_finish("test_pbrdf");
}
