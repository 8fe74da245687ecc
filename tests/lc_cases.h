/* tests/lc_cases.h - random Mueller matrices built from known Lu–Chipman factors
 * M = m00 · M_Δ M_R M_D (physics.md §3; paper eqs. 14–16), shared by test_decompose.c and
 * test_decompose_map.c: the round-trip set with its degenerate kinds (pure diattenuators,
 * pure retarders, isotropic depolarisers, two equal eigenvalues, det m' < 0, D → 1, R at 0 and
 * π). Static functions: each test program has its own copy and its own random stream. */
#ifndef POLARCAM_TESTS_LC_CASES_H
#define POLARCAM_TESTS_LC_CASES_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "polarcam/optics.h"

static uint64_t rng = 0x853c49e6748fea9bull;
static double urand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}
static double nrand(void) /* standard normal (Box–Muller) */
{
	double u = urand() + 1e-300, v = urand();
	return sqrt(-2 * log(u)) * cos(2 * PC_PI * v);
}
static void unit3(double v[3])
{
	do {
		v[0] = nrand();
		v[1] = nrand();
		v[2] = nrand();
	} while (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] < 1e-6);
	double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	for (int i = 0; i < 3; i++)
		v[i] /= n;
}

/* Rodrigues: rotation by θ about n. Its (m[1][2] − m[2][1], …) = −2 sinθ n, so the Lu–Chipman
 * axis of physics.md §3 is −n. */
static void rodrigues(const double n[3], double th, double R[3][3])
{
	double c = cos(th), s = sin(th), C = 1 - c;
	double K[3][3] = {{0, -n[2], n[1]}, {n[2], 0, -n[0]}, {-n[1], n[0], 0}};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			R[i][j] = (i == j ? c : 0) + s * K[i][j] + C * n[i] * n[j];
}

static void random_rotation(double R[3][3])
{
	double n[3];
	unit3(n);
	rodrigues(n, PC_PI * urand(), R);
}

/* the factors of physics.md §3 / paper eqs. 14–16 */
static void make_MD(const double Dv[3], double M[4][4])
{
	double D = sqrt(Dv[0] * Dv[0] + Dv[1] * Dv[1] + Dv[2] * Dv[2]);
	double s = D < 1 ? sqrt((1 - D) * (1 + D)) : 0; /* D > 1: a non-physical test input */
	memset(M, 0, 16 * sizeof(double));
	M[0][0] = 1;
	for (int i = 0; i < 3; i++) {
		M[0][i + 1] = M[i + 1][0] = Dv[i];
		for (int j = 0; j < 3; j++)
			M[i + 1][j + 1] =
			    (i == j ? s : 0) + (D > 0 ? (1 - s) * Dv[i] * Dv[j] / (D * D) : 0);
	}
}

static void make_MR(const double R3[3][3], double M[4][4])
{
	memset(M, 0, 16 * sizeof(double));
	M[0][0] = 1;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			M[i + 1][j + 1] = R3[i][j];
}

static void make_MDelta(const double P[3], const double lam[3], const double U[3][3],
                        double M[4][4])
{
	memset(M, 0, 16 * sizeof(double));
	M[0][0] = 1;
	for (int i = 0; i < 3; i++) {
		M[i + 1][0] = P[i];
		for (int j = 0; j < 3; j++)
			M[i + 1][j + 1] = U[i][0] * lam[0] * U[j][0] + U[i][1] * lam[1] * U[j][1] +
			                  U[i][2] * lam[2] * U[j][2];
	}
}

enum lc_kind {
	LC_GENERAL,
	LC_PURE_DIATT,
	LC_PURE_RET,
	LC_ISO_DEPOL,
	LC_TWO_EQUAL,
	LC_DET_NEG,
	LC_D_NEAR1,
	LC_R_EDGES,
	LC_NKINDS
};

typedef struct lc_case {
	double M[4][4];                        /* m00 · M_Δ M_R M_D */
	double MD[4][4], MR[4][4], MDel[4][4]; /* the known factors */
	double Dv[3], lam[3], ax[3];           /* D⃗, eigenvalues of m_Δ, Lu–Chipman axis */
	double R, m00;
} lc_case;

static void lc_make_case(enum lc_kind kind, lc_case *c)
{
	double n[3], R3[3][3], U[3][3], P[3] = {0, 0, 0};
	double *Dv = c->Dv, *lam = c->lam, *ax = c->ax;
	for (int i = 0; i < 3; i++) {
		Dv[i] = 0;
		lam[i] = 1;
	}
	unit3(n);
	double Dmag = 0.95 * urand();
	if (kind == LC_D_NEAR1)
		Dmag = urand() < 0.5 ? 0.99999 : 1 - 2e-6;
	if (kind != LC_PURE_RET)
		for (int i = 0; i < 3; i++)
			Dv[i] = Dmag * n[i];
	unit3(ax);
	double Rtrue = PC_PI * urand();
	if (kind == LC_R_EDGES) {
		const double edges[] = {0, 1e-9, 1e-5, PC_PI - 1e-5, PC_PI - 1e-9, PC_PI};
		Rtrue = edges[(int)(urand() * 6) % 6];
	}
	if (kind == LC_PURE_DIATT)
		Rtrue = 0;
	double nn[3] = {-ax[0], -ax[1], -ax[2]}; /* Lu–Chipman axis = −Rodrigues axis */
	rodrigues(nn, Rtrue, R3);
	random_rotation(U);
	if (kind == LC_GENERAL || kind == LC_DET_NEG || kind == LC_D_NEAR1 || kind == LC_R_EDGES) {
		for (int i = 0; i < 3; i++)
			lam[i] = 0.05 + 0.95 * urand();
		double pm = urand() * 0.3 * (1 - fmax(lam[0], fmax(lam[1], lam[2])));
		double pv[3];
		unit3(pv);
		for (int i = 0; i < 3; i++)
			P[i] = pm * pv[i];
	} else if (kind == LC_ISO_DEPOL) {
		lam[0] = lam[1] = lam[2] = 0.05 + 0.9 * urand();
	} else if (kind == LC_TWO_EQUAL) {
		lam[0] = lam[1] = 0.1 + 0.9 * urand();
		lam[2] = 0.1 + 0.9 * urand();
	}
	if (kind == LC_DET_NEG)
		for (int i = 0; i < 3; i++)
			lam[i] = -lam[i];
	make_MD(Dv, c->MD);
	make_MR(R3, c->MR);
	make_MDelta(P, lam, U, c->MDel);
	pc_mueller_mul(c->MDel, c->MR, c->M);
	pc_mueller_mul(c->M, c->MD, c->M);
	double m00 = exp(6 * urand() - 3);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			c->M[i][j] *= m00;
	c->R = Rtrue;
	c->m00 = m00;
}

#endif
