/* core/decompose_internal.h - thresholds shared by the scalar Lu–Chipman decomposition
 * (decompose.c) and its vectorised map kernel (decompose_map.c); private to core. */
#ifndef POLARCAM_CORE_DECOMPOSE_INTERNAL_H
#define POLARCAM_CORE_DECOMPOSE_INTERNAL_H

#define PC_LC_D_MAX         (1 - 1e-6) /* physics.md §4: flag D ≥ 1 − 1e-6 */
#define PC_LC_NONUNIQUE_DET 1e-6       /* |det m'| ≤ 1e-6 (λ₁/3)³: retarder not unique */

#include <math.h>

/* Matrices with max|M_ij| outside [2^−256, 2^256] are scaled by 2^−e first (e from frexp of
 * the maximum; 0: leave alone). The map kernel sends such matrices to the scalar code. */
#define PC_LC_SCALE_LO 0x1p-256
#define PC_LC_SCALE_HI 0x1p256

static inline int pc_lc_scale_exp(const double M[4][4])
{
	double mx = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			mx = fmax(mx, fabs(M[i][j]));
	if (!(mx > 0) || (mx >= PC_LC_SCALE_LO && mx <= PC_LC_SCALE_HI) || !isfinite(mx))
		return 0;
	int e;
	frexp(mx, &e);
	return e;
}

#endif
