/* tests/sim_stand_in.h - test-only BRDFs for the simulator tests (never shipped): closed-form
 * answers that do not involve the physics core.
 *
 *  - brdf_lambert: an ideal Lambertian depolarizer of albedo 1, f = (1/π)·e0·e0ᵀ;
 *  - brdf_projector: the outgoing field is the incident field projected perpendicular to k_r:
 *    real Jones matrix J = [[s_r·s_i, s_r·p_i], [p_r·s_i, p_r·p_i]] (p = d × s), divided by π.
 *    Its Mueller matrix M = A(J⊗J*)A⁻¹ (physics.md §1's A) written out for real
 *    J = [[a, b], [c, d]]; test_sim_render.c checks it against the complex Kronecker product. */
#ifndef POLARCAM_TESTS_SIM_STAND_IN_H
#define POLARCAM_TESTS_SIM_STAND_IN_H

#include <math.h>
#include <string.h>

static inline void stand_in_real_jones_mueller(double a, double b, double c, double d,
                                               double M[4][4])
{
	const double m[4][4] = {
	    {(a * a + b * b + c * c + d * d) / 2, (a * a - b * b + c * c - d * d) / 2,
	     a * b + c * d, 0},
	    {(a * a + b * b - c * c - d * d) / 2, (a * a - b * b - c * c + d * d) / 2,
	     a * b - c * d, 0},
	    {a * c + b * d, a * c - b * d, a * d + b * c, 0},
	    {0, 0, 0, a * d - b * c},
	};
	memcpy(M, m, sizeof m);
}

static inline int brdf_lambert(void *u, unsigned m, unsigned ch, const double ki[3],
                               const double kr[3], const double si[3], const double sr[3],
                               double f[4][4])
{
	(void)u;
	(void)m;
	(void)ch;
	(void)si;
	(void)sr;
	memset(f, 0, 16 * sizeof(double));
	if (ki[2] > 0 && kr[2] > 0)
		f[0][0] = 1 / M_PI;
	return 0;
}

static inline int brdf_projector(void *u, unsigned m, unsigned ch, const double ki[3],
                                 const double kr[3], const double si[3], const double sr[3],
                                 double f[4][4])
{
	(void)u;
	(void)m;
	(void)ch;
	const double di[3] = {-ki[0], -ki[1], -ki[2]};
	const double pi_[3] = {di[1] * si[2] - di[2] * si[1], di[2] * si[0] - di[0] * si[2],
	                       di[0] * si[1] - di[1] * si[0]};
	const double pr[3] = {kr[1] * sr[2] - kr[2] * sr[1], kr[2] * sr[0] - kr[0] * sr[2],
	                      kr[0] * sr[1] - kr[1] * sr[0]};
#define SI_DOT(x, y) ((x)[0] * (y)[0] + (x)[1] * (y)[1] + (x)[2] * (y)[2])
	stand_in_real_jones_mueller(SI_DOT(sr, si), SI_DOT(sr, pi_), SI_DOT(pr, si),
	                            SI_DOT(pr, pi_), f);
#undef SI_DOT
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			f[i][j] /= M_PI;
	return 0;
}

#endif
