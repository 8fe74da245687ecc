/* core/optics_inline.h - small inline kernels shared by core/optics.c and core/decompose.c
 * (private to core). */
#ifndef POLARCAM_CORE_OPTICS_INLINE_H
#define POLARCAM_CORE_OPTICS_INLINE_H

#include <math.h>

#include "polarcam/optics.h"

/* The exponent e that brings max|M_ij| into [0.5, 1) by a scaling with 2^−e, when that maximum
 * lies outside [PC_MAT4_SCALE_LO, PC_MAT4_SCALE_HI]; 0 (leave alone) inside, for a zero matrix
 * and for a non-finite maximum. Far from 1 a Mueller matrix's coherency sums overflow (M ~ 1e308)
 * or lose everything (M ~ 1e-310); the quantities computed from it are scale-invariant or scale
 * back exactly. A compare, not fmax(), which is a libm call on x86-64: the same result for NaN
 * (ignored) and ±inf (kept). */
#define PC_MAT4_SCALE_LO 0x1p-256
#define PC_MAT4_SCALE_HI 0x1p256
static inline int pc_mat4_scale_exp(const double M[4][4])
{
	double mx = 0;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			const double a = fabs(M[i][j]);
			mx = a > mx ? a : mx;
		}
	if (!(mx > 0) || (mx >= PC_MAT4_SCALE_LO && mx <= PC_MAT4_SCALE_HI) || !isfinite(mx))
		return 0;
	int e;
	frexp(mx, &e);
	return e;
}

/* atan2(y, x) for y, x ≥ 0, not both 0, in [0, π/2], to a few ulp (see pc_atan2 in optics.h).
 * With num = min(x, y), den = max(x, y), t = num/den ∈ [0, 1], k = round(8t): atan t = atan(k/8) +
 * atan(r), r = (num − (k/8)·den)/(den + (k/8)·num), |r| ≤ 1/16, by the Taylor series through r¹³
 * (truncation < 1e-18 relative). */
static inline double pc_atan2_q1(double y, double x)
{
	/* atan(k/8), k = 0..8, to 22 digits (computed with a 50-digit series) */
	static const double atan_k8[9] = {
	    0.0,
	    0.1243549945467614350313,
	    0.2449786631268641541720,
	    0.3587706702705722203959,
	    0.4636476090008061162142,
	    0.5585993153435624359715,
	    0.6435011087932843868028,
	    0.7188299996216245054170,
	    0.7853981633974483096156,
	};
	int swap = y > x;
	double num = swap ? x : y, den = swap ? y : x;
	double t = num / den;
	if (!(t <= 1)) /* NaN (or 0/0): never index the table with garbage */
		return NAN;
	int k = (int)(8 * t + 0.5);
	double c = k * 0.125;
	double r = (num - c * den) / (den + c * num);
	double r2 = r * r;
	/* atan r = r − r³/3 + r⁵/5 − … (Horner in r²) */
	double p = -1.0 / 13;
	p = 1.0 / 11 + r2 * p;
	p = -1.0 / 9 + r2 * p;
	p = 1.0 / 7 + r2 * p;
	p = -1.0 / 5 + r2 * p;
	p = 1.0 / 3 + r2 * p;
	double a = atan_k8[k] + (r - r * r2 * p);
	return swap ? 0.5 * PC_PI - a : a;
}

#endif
