/* Internal to core/stokes.c and core/demosaic_fast.c: the float arctangent used for AoLP. */
#ifndef POLARCAM_STOKES_INTERNAL_H
#define POLARCAM_STOKES_INTERNAL_H

/* atan(t) ≈ t·P(t²) on [0, 1], P of degree 7 fitted by least squares at 2000 Chebyshev nodes
 * (our own fit; evaluated in float its maximum error is 1.3e-7 rad, asserted against double
 * atan2 in tests/test_stokes.c). */
#define PC_ATAN_C0 0.999999437f
#define PC_ATAN_C1 -0.333301089f
#define PC_ATAN_C2 0.199485329f
#define PC_ATAN_C3 -0.13915916f
#define PC_ATAN_C4 0.0965653358f
#define PC_ATAN_C5 -0.0560667876f
#define PC_ATAN_C6 0.0219490069f
#define PC_ATAN_C7 -0.00407394544f

#define PC_PIF 3.14159265358979323846f
#define PC_PI_2F 1.57079632679489661923f

#include <math.h>

/* DoLP = min(|(s1, s2)| / s0, 1), 0 where s0 <= 0, with |(s1, s2)| = max·√(1 + (min/max)²)
 * (no overflow or underflow of s1² + s2², as in the vector kernels). */
static inline float pc_dolp_f(float s0, float s1, float s2)
{
	float ax = fabsf(s1), ay = fabsf(s2);
	float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
	if (!(s0 > 0) || !(mx > 0))
		return 0.0f;
	float t = mn / mx, q = mx * sqrtf(1.0f + t * t) / s0;
	return q < 1.0f ? q : 1.0f;
}

#endif
