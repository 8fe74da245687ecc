/* sim/vec.h - small 3-vector helpers (internal to sim/). Double precision throughout. */
#ifndef POLARCAM_SIM_VEC_H
#define POLARCAM_SIM_VEC_H

#include <math.h>

typedef struct pc_v3 {
	double x, y, z;
} pc_v3;

static inline pc_v3 v3(double x, double y, double z)
{
	pc_v3 r = {x, y, z};
	return r;
}
static inline pc_v3 v3_add(pc_v3 a, pc_v3 b)
{
	return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline pc_v3 v3_sub(pc_v3 a, pc_v3 b)
{
	return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline pc_v3 v3_scale(pc_v3 a, double s)
{
	return v3(a.x * s, a.y * s, a.z * s);
}
static inline pc_v3 v3_neg(pc_v3 a)
{
	return v3(-a.x, -a.y, -a.z);
}
static inline double v3_dot(pc_v3 a, pc_v3 b)
{
	return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline pc_v3 v3_cross(pc_v3 a, pc_v3 b)
{
	return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_len(pc_v3 a)
{
	return sqrt(v3_dot(a, a));
}
static inline pc_v3 v3_unit(pc_v3 a)
{
	double l = v3_len(a);
	return l > 0 ? v3_scale(a, 1.0 / l) : a;
}
static inline pc_v3 v3_madd(pc_v3 a, pc_v3 b, double s)
{
	return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline pc_v3 v3_min(pc_v3 a, pc_v3 b)
{
	return v3(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z);
}
static inline pc_v3 v3_max(pc_v3 a, pc_v3 b)
{
	return v3(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z);
}
static inline double v3_get(pc_v3 a, int i)
{
	return i == 0 ? a.x : i == 1 ? a.y : a.z;
}

/* Component of a perpendicular to unit n, normalised; fallback when a ∥ n. */
static inline pc_v3 v3_perp_unit(pc_v3 a, pc_v3 n, pc_v3 fallback)
{
	pc_v3 p = v3_madd(a, n, -v3_dot(a, n));
	double l = v3_len(p);
	if (l < 1e-9 * (v3_len(a) + 1e-300))
		return fallback;
	return v3_scale(p, 1.0 / l);
}

/* Any unit vector perpendicular to unit n (Frisvad-style branch on the largest component). */
static inline pc_v3 v3_any_perp(pc_v3 n)
{
	pc_v3 a = fabs(n.x) < 0.6 ? v3(1, 0, 0) : fabs(n.y) < 0.6 ? v3(0, 1, 0) : v3(0, 0, 1);
	return v3_unit(v3_madd(a, n, -v3_dot(a, n)));
}

/* 3×3 rotation (row-major), applied as R·v. */
typedef struct pc_m3 {
	double m[3][3];
} pc_m3;

static inline pc_v3 m3_apply(const pc_m3 *r, pc_v3 v)
{
	return v3(r->m[0][0] * v.x + r->m[0][1] * v.y + r->m[0][2] * v.z,
	          r->m[1][0] * v.x + r->m[1][1] * v.y + r->m[1][2] * v.z,
	          r->m[2][0] * v.x + r->m[2][1] * v.y + r->m[2][2] * v.z);
}
/* Rᵀ·v (the inverse rotation). */
static inline pc_v3 m3_apply_t(const pc_m3 *r, pc_v3 v)
{
	return v3(r->m[0][0] * v.x + r->m[1][0] * v.y + r->m[2][0] * v.z,
	          r->m[0][1] * v.x + r->m[1][1] * v.y + r->m[2][1] * v.z,
	          r->m[0][2] * v.x + r->m[1][2] * v.y + r->m[2][2] * v.z);
}

/* R = Rz(γ)·Ry(β)·Rx(α) for rotation_deg = [α, β, γ] (extrinsic x, then y, then z). */
static inline pc_m3 m3_from_euler_deg(const double deg[3])
{
	const double k = 3.14159265358979323846 / 180.0;
	double ca = cos(deg[0] * k), sa = sin(deg[0] * k);
	double cb = cos(deg[1] * k), sb = sin(deg[1] * k);
	double cg = cos(deg[2] * k), sg = sin(deg[2] * k);
	pc_m3 r = {{{cg * cb, cg * sb * sa - sg * ca, cg * sb * ca + sg * sa},
	            {sg * cb, sg * sb * sa + cg * ca, sg * sb * ca - cg * sa},
	            {-sb, cb * sa, cb * ca}}};
	return r;
}

#endif
