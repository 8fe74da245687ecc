/* sim/geometry.c - ray intersection with planes, spheres, boxes and triangle meshes (BVH). */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "polarcam/error.h"
#include "geometry_inline.h"
#include "scene_impl.h"

struct pc_bvh_node {
	pc_v3 bmin, bmax;
	uint32_t first; /* leaf: first index into tri_order; inner: index of the right child */
	uint16_t count; /* leaf: number of triangles; 0 for inner nodes (left child = next node) */
	uint16_t axis;
};

/* Slab test (Kay & Kajiya 1986) with precomputed inverse direction. */
static inline bool aabb_hit(pc_v3 bmin, pc_v3 bmax, pc_v3 o, pc_v3 inv, double tmin, double tmax)
{
	double t0 = (bmin.x - o.x) * inv.x, t1 = (bmax.x - o.x) * inv.x;
	if (t0 > t1) {
		double t = t0;
		t0 = t1;
		t1 = t;
	}
	if (t0 > tmin)
		tmin = t0;
	if (t1 < tmax)
		tmax = t1;
	t0 = (bmin.y - o.y) * inv.y;
	t1 = (bmax.y - o.y) * inv.y;
	if (t0 > t1) {
		double t = t0;
		t0 = t1;
		t1 = t;
	}
	if (t0 > tmin)
		tmin = t0;
	if (t1 < tmax)
		tmax = t1;
	t0 = (bmin.z - o.z) * inv.z;
	t1 = (bmax.z - o.z) * inv.z;
	if (t0 > t1) {
		double t = t0;
		t0 = t1;
		t1 = t;
	}
	if (t0 > tmin)
		tmin = t0;
	if (t1 < tmax)
		tmax = t1;
	return tmin <= tmax;
}

static bool hit_sphere(const pc_sim_object *s, pc_v3 o, pc_v3 d, double tmin, double tmax,
                       double *t, pc_v3 *n)
{
	pc_v3 oc = v3_sub(o, s->center);
	double tt;
	if (!pc_sphere_hit_oc(oc, s->radius, v3_dot(oc, oc) - s->radius * s->radius, d, tmin, tmax,
	                      &tt))
		return false;
	*t = tt;
	*n = pc_sphere_normal(s, o, d, tt);
	return true;
}

static bool hit_plane(const pc_sim_object *p, pc_v3 o, pc_v3 d, double tmin, double tmax, double *t)
{
	double tt;
	if (!pc_plane_hit_num(v3_dot(v3_sub(p->p, o), p->n), v3_dot(d, p->n), tmin, tmax, &tt) ||
	    !pc_plane_within(p, o, d, tt))
		return false;
	*t = tt;
	return true;
}

static bool hit_box(const pc_sim_object *b, pc_v3 o, pc_v3 d, double tmin, double tmax, double *t,
                    pc_v3 *n)
{
	pc_v3 ol = m3_apply_t(&b->rot, v3_sub(o, b->center)), dl = m3_apply_t(&b->rot, d);
	double lo[3] = {-b->half.x, -b->half.y, -b->half.z},
	       hi[3] = {b->half.x, b->half.y, b->half.z};
	double oo[3] = {ol.x, ol.y, ol.z}, dd[3] = {dl.x, dl.y, dl.z};
	double t0 = -INFINITY, t1 = INFINITY;
	int ax0 = -1, ax1 = -1;
	double sg0 = 0, sg1 = 0;
	for (int i = 0; i < 3; i++) {
		if (dd[i] == 0) {
			if (oo[i] < lo[i] || oo[i] > hi[i])
				return false;
			continue;
		}
		double a = (lo[i] - oo[i]) / dd[i], c = (hi[i] - oo[i]) / dd[i];
		double sa = -1, sc = 1;
		if (a > c) {
			double x = a;
			a = c;
			c = x;
			sa = 1;
			sc = -1;
		}
		if (a > t0) {
			t0 = a;
			ax0 = i;
			sg0 = sa;
		}
		if (c < t1) {
			t1 = c;
			ax1 = i;
			sg1 = sc;
		}
	}
	if (t0 > t1)
		return false;
	double tt;
	int ax;
	double sg;
	if (t0 > tmin && t0 < tmax) {
		tt = t0;
		ax = ax0;
		sg = sg0;
	} else if (t1 > tmin && t1 < tmax) {
		tt = t1;
		ax = ax1;
		sg = sg1;
	} else {
		return false;
	}
	if (ax < 0)
		return false;
	pc_v3 nl = v3(ax == 0 ? sg : 0, ax == 1 ? sg : 0, ax == 2 ? sg : 0);
	*t = tt;
	*n = m3_apply(&b->rot, nl);
	return true;
}

/* Möller & Trumbore, "Fast, minimum storage ray/triangle intersection", J. Graphics Tools
 * 2(1):21–28, 1997. Returns t and barycentrics (u, v). */
static inline bool hit_tri(pc_v3 o, pc_v3 d, pc_v3 a, pc_v3 b, pc_v3 c, double tmin, double tmax,
                           double *t, double *u, double *v)
{
	pc_v3 e1 = v3_sub(b, a), e2 = v3_sub(c, a);
	pc_v3 p = v3_cross(d, e2);
	double det = v3_dot(e1, p);
	if (det == 0 || !isfinite(det))
		return false;
	double inv = 1.0 / det;
	pc_v3 s = v3_sub(o, a);
	double uu = v3_dot(s, p) * inv;
	if (uu < 0 || uu > 1)
		return false;
	pc_v3 q = v3_cross(s, e1);
	double vv = v3_dot(d, q) * inv;
	if (vv < 0 || uu + vv > 1)
		return false;
	double tt = v3_dot(e2, q) * inv;
	if (!(tt > tmin && tt < tmax))
		return false;
	*t = tt;
	*u = uu;
	*v = vv;
	return true;
}

static bool hit_mesh(const pc_mesh *m, pc_v3 o, pc_v3 d, double tmin, double tmax, bool any,
                     double *t, pc_v3 *n, pc_v3 *ng)
{
	pc_v3 inv = v3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
	uint32_t stack[64];
	int sp = 0;
	stack[sp++] = 0;
	bool found = false;
	uint32_t best = 0;
	double bu = 0, bv = 0;
	while (sp) {
		const struct pc_bvh_node *nd = &m->nodes[stack[--sp]];
		if (!aabb_hit(nd->bmin, nd->bmax, o, inv, tmin, tmax))
			continue;
		if (nd->count) {
			for (uint32_t i = 0; i < nd->count; i++) {
				uint32_t tri = m->tri_order[nd->first + i];
				const uint32_t *ix = &m->tri[3 * tri];
				double tt, u, v;
				if (hit_tri(o, d, m->v[ix[0]], m->v[ix[1]], m->v[ix[2]], tmin, tmax,
				            &tt, &u, &v)) {
					if (any)
						return true;
					tmax = tt;
					best = tri;
					bu = u;
					bv = v;
					found = true;
				}
			}
		} else {
			uint32_t self = (uint32_t)(nd - m->nodes);
			/* visit the child on the ray's side first */
			uint32_t l = self + 1, r = nd->first;
			if (v3_get(d, nd->axis) < 0) {
				uint32_t x = l;
				l = r;
				r = x;
			}
			if (sp + 2 > 64)
				continue; /* depth is bounded by the builder; never reached */
			stack[sp++] = r;
			stack[sp++] = l;
		}
	}
	if (!found)
		return false;
	const uint32_t *ix = &m->tri[3 * best];
	pc_v3 g =
	    v3_unit(v3_cross(v3_sub(m->v[ix[1]], m->v[ix[0]]), v3_sub(m->v[ix[2]], m->v[ix[0]])));
	*t = tmax;
	*ng = g;
	if (m->vn) {
		const uint32_t *jn = &m->tri_n[3 * best];
		pc_v3 s =
		    v3_add(v3_add(v3_scale(m->vn[jn[0]], 1 - bu - bv), v3_scale(m->vn[jn[1]], bu)),
		           v3_scale(m->vn[jn[2]], bv));
		double l = v3_len(s);
		*n = l > 1e-12 ? v3_scale(s, 1 / l) : g;
		/* keep the shading normal on the geometric normal's side */
		if (v3_dot(*n, g) < 0)
			*n = v3_neg(*n);
	} else {
		*n = g;
	}
	return true;
}

bool pc_object_hit(const pc_sim_object *ob, pc_v3 o, pc_v3 d, double tmin, double tmax, bool any,
                   double *t, pc_v3 *n, pc_v3 *ng)
{
	switch (ob->type) {
	case PC_OBJ_PLANE:
		if (!hit_plane(ob, o, d, tmin, tmax, t))
			return false;
		*n = *ng = ob->n;
		return true;
	case PC_OBJ_SPHERE:
		if (!hit_sphere(ob, o, d, tmin, tmax, t, n))
			return false;
		*ng = *n;
		return true;
	case PC_OBJ_BOX:
		if (!hit_box(ob, o, d, tmin, tmax, t, n))
			return false;
		*ng = *n;
		return true;
	case PC_OBJ_MESH:
		return hit_mesh(ob->mesh, o, d, tmin, tmax, any, t, n, ng);
	default:
		return false;
	}
}

bool pc_object_bsphere(const pc_sim_object *ob, pc_v3 *c, double *r)
{
	pc_v3 lo, hi;
	switch (ob->type) {
	case PC_OBJ_SPHERE:
		*c = ob->center;
		*r = ob->radius;
		return true;
	case PC_OBJ_PLANE:
		if (!(ob->half_u > 0))
			return false; /* infinite */
		*c = ob->p;
		*r = sqrt(ob->half_u * ob->half_u + ob->half_v * ob->half_v);
		return true;
	case PC_OBJ_BOX:
		*c = ob->center;
		*r = v3_len(ob->half);
		return true;
	case PC_OBJ_MESH:
		if (!ob->mesh || !ob->mesh->n_nodes)
			return false;
		lo = ob->mesh->nodes[0].bmin;
		hi = ob->mesh->nodes[0].bmax;
		*c = v3_scale(v3_add(lo, hi), 0.5);
		*r = 0.5 * v3_len(v3_sub(hi, lo));
		return isfinite(*r);
	default:
		return false;
	}
}

bool pc_scene_intersect_cull(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax,
                             int32_t x, const pc_cull *cull, pc_hit *hit)
{
	bool found = false;
	for (unsigned i = 0; i < s->n_objects; i++) {
		if (i < cull->n && (x < cull->lo[i] || x > cull->hi[i]))
			continue; /* the ray cannot reach the object's bounding sphere */
		double t;
		pc_v3 n, ng;
		if (pc_object_hit(&s->objects[i], o, d, tmin, tmax, false, &t, &n, &ng)) {
			tmax = t;
			hit->t = t;
			hit->n = n;
			hit->ng = ng;
			hit->object = i;
			found = true;
		}
	}
	return found;
}

bool pc_scene_occluded_skip(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax,
                            unsigned skip)
{
	for (unsigned i = 0; i < s->n_objects; i++) {
		double t;
		pc_v3 n, ng;
		if (i != skip && pc_object_hit(&s->objects[i], o, d, tmin, tmax, true, &t, &n, &ng))
			return true;
	}
	return false;
}

bool pc_object_convex(const pc_sim_object *ob)
{
	return ob->type == PC_OBJ_PLANE || ob->type == PC_OBJ_SPHERE || ob->type == PC_OBJ_BOX;
}

bool pc_scene_intersect(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax, pc_hit *hit)
{
	bool found = false;
	for (unsigned i = 0; i < s->n_objects; i++) {
		double t;
		pc_v3 n, ng;
		if (pc_object_hit(&s->objects[i], o, d, tmin, tmax, false, &t, &n, &ng)) {
			tmax = t;
			hit->t = t;
			hit->n = n;
			hit->ng = ng;
			hit->object = i;
			found = true;
		}
	}
	return found;
}

bool pc_scene_occluded(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax)
{
	for (unsigned i = 0; i < s->n_objects; i++) {
		double t;
		pc_v3 n, ng;
		if (pc_object_hit(&s->objects[i], o, d, tmin, tmax, true, &t, &n, &ng))
			return true;
	}
	return false;
}

/* ---- BVH build: midpoint split on the longest centroid axis, object median when the midpoint
 * does not separate (Wald, "On fast construction of SAH-based bounding volume hierarchies",
 * 2007, describes the trade-offs; midpoint/median is enough for scene meshes here). ---- */

typedef struct bvh_build {
	pc_mesh *m;
	pc_v3 *centroid;
	unsigned n_nodes, cap;
	int max_depth;
} bvh_build;

static void tri_bounds(const pc_mesh *m, uint32_t tri, pc_v3 *lo, pc_v3 *hi)
{
	const uint32_t *ix = &m->tri[3 * tri];
	*lo = v3_min(v3_min(m->v[ix[0]], m->v[ix[1]]), m->v[ix[2]]);
	*hi = v3_max(v3_max(m->v[ix[0]], m->v[ix[1]]), m->v[ix[2]]);
}

/* Partition tri_order[a, b) so that the k-th smallest centroid along axis is at position k
 * (quickselect, Hoare partition). */
static void select_k(bvh_build *B, uint32_t *idx, long a, long b, long k, int axis)
{
	while (b - a > 1) {
		double pivot = v3_get(B->centroid[idx[(a + b) / 2]], axis);
		long i = a, j = b - 1;
		while (i <= j) {
			while (v3_get(B->centroid[idx[i]], axis) < pivot)
				i++;
			while (v3_get(B->centroid[idx[j]], axis) > pivot)
				j--;
			if (i <= j) {
				uint32_t t = idx[i];
				idx[i] = idx[j];
				idx[j] = t;
				i++;
				j--;
			}
		}
		if (k <= j)
			b = j + 1;
		else if (k >= i)
			a = i;
		else
			return;
	}
}

static int bvh_node(bvh_build *B, uint32_t first, uint32_t count, int depth)
{
	if (B->n_nodes == B->cap) {
		unsigned nc = B->cap * 2;
		struct pc_bvh_node *nn = realloc(B->m->nodes, nc * sizeof *nn);
		if (!nn)
			return -1;
		B->m->nodes = nn;
		B->cap = nc;
	}
	unsigned self = B->n_nodes++;
	pc_v3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
	pc_v3 clo = lo, chi = hi;
	uint32_t *idx = B->m->tri_order;
	for (uint32_t i = first; i < first + count; i++) {
		pc_v3 a, b;
		tri_bounds(B->m, idx[i], &a, &b);
		lo = v3_min(lo, a);
		hi = v3_max(hi, b);
		clo = v3_min(clo, B->centroid[idx[i]]);
		chi = v3_max(chi, B->centroid[idx[i]]);
	}
	struct pc_bvh_node *nd = &B->m->nodes[self];
	nd->bmin = lo;
	nd->bmax = hi;
	if (count <= 4 || depth >= B->max_depth) {
		nd->first = first;
		nd->count = (uint16_t)count;
		nd->axis = 0;
		if (count > 65535)
			return -2;
		return 0;
	}
	pc_v3 ext = v3_sub(chi, clo);
	int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : ext.y >= ext.z ? 1 : 2;
	double mid = 0.5 * (v3_get(clo, axis) + v3_get(chi, axis));
	uint32_t i = first, j = first + count;
	while (i < j) {
		if (v3_get(B->centroid[idx[i]], axis) < mid) {
			i++;
		} else {
			j--;
			uint32_t t = idx[i];
			idx[i] = idx[j];
			idx[j] = t;
		}
	}
	uint32_t nl = i - first;
	if (nl == 0 || nl == count) {
		nl = count / 2;
		select_k(B, idx, first, first + count, first + nl, axis);
	}
	nd->count = 0;
	nd->axis = (uint16_t)axis;
	int rc = bvh_node(B, first, nl, depth + 1);
	if (rc)
		return rc;
	B->m->nodes[self].first = B->n_nodes; /* right child follows the left subtree */
	return bvh_node(B, first + nl, count - nl, depth + 1);
}

int pc_bvh_build(pc_mesh *m)
{
	bvh_build B = {m, NULL, 0, 64, 30};
	if (m->n_triangles == 0)
		return pc_error(PC_EFORMAT, "mesh has no triangles");
	m->tri_order = malloc(m->n_triangles * sizeof *m->tri_order);
	B.centroid = malloc(m->n_triangles * sizeof *B.centroid);
	m->nodes = malloc(B.cap * sizeof *m->nodes);
	if (!m->tri_order || !B.centroid || !m->nodes) {
		free(B.centroid);
		return pc_error(PC_ENOMEM, "mesh BVH (%u triangles)", m->n_triangles);
	}
	for (uint32_t i = 0; i < m->n_triangles; i++) {
		const uint32_t *ix = &m->tri[3 * i];
		m->tri_order[i] = i;
		B.centroid[i] =
		    v3_scale(v3_add(v3_add(m->v[ix[0]], m->v[ix[1]]), m->v[ix[2]]), 1.0 / 3);
	}
	int rc = bvh_node(&B, 0, m->n_triangles, 0);
	free(B.centroid);
	if (rc == -1)
		return pc_error(PC_ENOMEM, "mesh BVH (%u triangles)", m->n_triangles);
	if (rc == -2)
		return pc_error(PC_EFORMAT, "mesh BVH: more than 65535 triangles share one "
		                            "position (degenerate mesh)");
	m->n_nodes = B.n_nodes;
	return 0;
}
