/* sim/geometry_inline.h - the ray tests the renderer inlines (internal to sim/); geometry.c
 * uses the same functions, so inlined and called tests give identical results. */
#ifndef POLARCAM_SIM_GEOMETRY_INLINE_H
#define POLARCAM_SIM_GEOMETRY_INLINE_H

#include <math.h>
#include <stdbool.h>

#include "scene_impl.h"

/* Ray o + t·d (|d| = 1) against the sphere of radius r, oc = o − centre, c = |oc|² − r²:
 * the nearest t in (tmin, tmax). The discriminant is computed from the distance of the centre
 * to the ray (r² − |h|², h ⟂ d), which does not cancel for distant spheres (Haines et al.,
 * "Precision improvements for ray/sphere intersection", Ray Tracing Gems, 2019, ch. 7). */
static inline bool pc_sphere_hit_oc(pc_v3 oc, double r, double c, pc_v3 d, double tmin, double tmax,
                                    double *t)
{
	double b = v3_dot(oc, d);
	if (c > 0 && b > 0 && tmin >= 0)
		return false; /* outside and moving away: both roots negative */
	pc_v3 h = v3_madd(oc, d, -b);
	double disc = r * r - v3_dot(h, h);
	if (disc < 0)
		return false;
	double sq = sqrt(disc);
	double q = b > 0 ? -b - sq : -b + sq;
	double t0 = q, t1 = q != 0 ? c / q : q;
	if (t0 > t1) {
		double tt = t0;
		t0 = t1;
		t1 = tt;
	}
	double tt = t0 > tmin ? t0 : t1;
	if (!(tt > tmin && tt < tmax))
		return false;
	*t = tt;
	return true;
}

/* Outward unit normal of sphere s at o + t·d. */
static inline pc_v3 pc_sphere_normal(const pc_sim_object *s, pc_v3 o, pc_v3 d, double t)
{
	return v3_scale(v3_sub(v3_madd(o, d, t), s->center), 1.0 / s->radius);
}

/* Plane (p − o)·n = num, d·n = den: t = num/den in (tmin, tmax). */
static inline bool pc_plane_hit_num(double num, double den, double tmin, double tmax, double *t)
{
	if (den == 0)
		return false;
	double tt = num / den;
	if (!(tt > tmin && tt < tmax))
		return false;
	*t = tt;
	return true;
}

/* Whether o + t·d lies on a finite plane's rectangle (always for an infinite plane). */
static inline bool pc_plane_within(const pc_sim_object *p, pc_v3 o, pc_v3 d, double t)
{
	if (!(p->half_u > 0))
		return true;
	pc_v3 r = v3_sub(v3_madd(o, d, t), p->p);
	return !(fabs(v3_dot(r, p->u)) > p->half_u || fabs(v3_dot(r, p->v)) > p->half_v);
}

#endif
