/* sim/shade.c - shading of camera rays in batches (render.c sets up the frames and culling;
 * the conventions and the radiometry are described there).
 *
 * A batch of up to NB rays goes through stages, each a loop over the rays: camera directions;
 * the nearest hit (spheres and planes in vectorised loops, other objects per ray); the surface
 * frames; per light its direction, the shadow tests and the local vectors; finally, per ray and
 * light, the pBRDF and the Stokes sum. The loops are independent across rays, so they pipeline
 * and vectorise (built without errno for sqrt, with AVX2 and AVX-512 clones chosen at run
 * time); every value is computed with the operations of the per-ray formulas of
 * geometry_inline.h and vec.h in the same order, so the result does not depend on the batch
 * size or the instruction set (IEEE arithmetic, no FMA contraction in ISO C builds). */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "polarcam/pbrdf.h"
#include "sim_impl.h"

#define NB 64

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define STAGE __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define STAGE
#endif

typedef struct batch {
	unsigned n;
	int32_t col[NB];  /* pixel column (culling) */
	double px[NB];    /* sensor x of the ray (pixel + 0.5 + sub-pixel offset) */
	double dx[NB], dy[NB], dz[NB];
	double t[NB];
	int64_t obj[NB];  /* −1: no hit (64-bit lanes like the doubles: the loops vectorise) */
	double nx[NB], ny[NB], nz[NB]; /* shading normal, then flipped towards the viewer */
	double gx[NB], gy[NB], gz[NB]; /* geometric normal as the object has it */
	double fx[NB], fy[NB], fz[NB]; /* geometric normal towards the viewer */
	double xx[NB], xy[NB], xz[NB]; /* hit point */
	double ox[NB], oy[NB], oz[NB]; /* shadow-ray origin */
	double t1x[NB], t1y[NB], t1z[NB], t2x[NB], t2y[NB], t2z[NB];
	double kr[3][NB], sr[3][NB];   /* k_r and s_r in the local frame */
	/* the current light */
	double lx[NB], ly[NB], lz[NB]; /* propagation d */
	double sx[NB], sy[NB], sz[NB]; /* its s-axis */
	double dist[NB], factor[NB], cosi[NB];
	double ki[3][NB], si[3][NB];
	int64_t skip[NB], lit[NB];
} batch;

/* ---- stages ---- */

/* Camera rays: d = unit(A + u·right), u = (px − cx)·pitch. */
STAGE static void stage_rays(const pc_sim *sim, pc_v3 A, batch *b)
{
	const pc_v3 R = sim->scene->camera.right;
	const double cx = sim->cx, pitch = sim->pitch_m;
#pragma omp simd
	for (unsigned r = 0; r < b->n; r++) {
		double u = (b->px[r] - cx) * pitch;
		double x = A.x + R.x * u, y = A.y + R.y * u, z = A.z + R.z * u;
		double l = sqrt(x * x + y * y + z * z);
		double inv = 1.0 / l;
		int ok = l > 0;
		b->dx[r] = ok ? x * inv : x;
		b->dy[r] = ok ? y * inv : y;
		b->dz[r] = ok ? z * inv : z;
	}
}

/* pc_sphere_hit_oc's arithmetic without branches: *t and whether it is a hit in (0, tmax). */
static inline int64_t sphere_t(double ocx, double ocy, double ocz, double rad, double c, double dx,
			    double dy, double dz, double tmax, double *t)
{
	double b = ocx * dx + ocy * dy + ocz * dz;
	double hx = ocx + dx * -b, hy = ocy + dy * -b, hz = ocz + dz * -b;
	double disc = rad * rad - (hx * hx + hy * hy + hz * hz);
	double sq = sqrt(disc > 0 ? disc : 0);
	double qm = -b - sq, qp = -b + sq;
	double q = b > 0 ? qm : qp;
	double cq = c / (q != 0 ? q : 1);
	double t0 = q, t1 = q != 0 ? cq : q;
	double lo = t0 > t1 ? t1 : t0, hi = t0 > t1 ? t0 : t1;
	double tt = lo > 0 ? lo : hi;
	*t = tt;
	return (int64_t)((((c > 0) & (b > 0)) == 0) & (disc >= 0) & (tt > 0) & (tt < tmax));
}

/* A plane's data as loop invariants. */
typedef struct plane_c {
	double nx, ny, nz, px, py, pz, ux, uy, uz, vx, vy, vz, hu, hv;
	int finite;
} plane_c;

static inline plane_c plane_of(const pc_sim_object *p)
{
	plane_c c = { p->n.x, p->n.y, p->n.z, p->p.x, p->p.y, p->p.z, p->u.x, p->u.y, p->u.z,
		      p->v.x, p->v.y, p->v.z, p->half_u, p->half_v, p->half_u > 0 };
	return c;
}

/* pc_plane_hit_num and pc_plane_within without branches. */
static inline int64_t plane_t(plane_c p, double num, double ox, double oy, double oz, double dx,
			      double dy, double dz, double tmax, double *t)
{
	double den = dx * p.nx + dy * p.ny + dz * p.nz;
	double tt = num / (den != 0 ? den : 1);
	int hit = (den != 0) & (tt > 0) & (tt < tmax);
	double rx = (ox + dx * tt) - p.px, ry = (oy + dy * tt) - p.py, rz = (oz + dz * tt) - p.pz;
	int out = (fabs(rx * p.ux + ry * p.uy + rz * p.uz) > p.hu) |
		  (fabs(rx * p.vx + ry * p.vy + rz * p.vz) > p.hv);
	*t = tt;
	return (int64_t)(hit & ((p.finite == 0) | (out == 0))); /* infinite planes: no rectangle */
}

/* Nearest hits of the batch's camera rays (the camera centre is their origin). */
STAGE static void stage_primary(const pc_sim *sim, const int32_t *lo, const int32_t *hi, batch *b)
{
	const pc_scene *sc = sim->scene;
	const pc_v3 o = sc->camera.position;
	const unsigned n = b->n;
	for (unsigned r = 0; r < n; r++) {
		b->t[r] = INFINITY;
		b->obj[r] = -1;
	}
	const int32_t cmin = b->col[0], cmax = b->col[n - 1];
	for (unsigned i = 0; i < sc->n_objects; i++) {
		const pc_sim_object *ob = &sc->objects[i];
		int32_t l = INT32_MIN, h = INT32_MAX;
		if (i < sim->n_cull) {
			l = lo[i];
			h = hi[i];
			if (h < cmin || l > cmax)
				continue; /* no ray of the batch reaches the bounding sphere */
		}
		if (i < PC_CULL_MAX && ob->type == PC_OBJ_SPHERE) {
			const pc_v3 oc = sim->prim_oc[i], c = ob->center;
			const double C = sim->prim_c[i], rad = ob->radius, inv_r = 1.0 / rad;
#pragma omp simd
			for (unsigned r = 0; r < n; r++) {
				double tt;
				int64_t hit = sphere_t(oc.x, oc.y, oc.z, rad, C, b->dx[r], b->dy[r], b->dz[r],
						    b->t[r], &tt) &
					   (b->col[r] >= l) & (b->col[r] <= h);
				/* pc_sphere_normal */
				double nx = ((o.x + b->dx[r] * tt) - c.x) * inv_r;
				double ny = ((o.y + b->dy[r] * tt) - c.y) * inv_r;
				double nz = ((o.z + b->dz[r] * tt) - c.z) * inv_r;
				b->t[r] = hit ? tt : b->t[r];
				b->obj[r] = hit ? (int64_t)i : b->obj[r];
				b->nx[r] = hit ? nx : b->nx[r];
				b->ny[r] = hit ? ny : b->ny[r];
				b->nz[r] = hit ? nz : b->nz[r];
				b->gx[r] = hit ? nx : b->gx[r];
				b->gy[r] = hit ? ny : b->gy[r];
				b->gz[r] = hit ? nz : b->gz[r];
			}
		} else if (i < PC_CULL_MAX && ob->type == PC_OBJ_PLANE) {
			const double num = sim->prim_num[i];
			const pc_v3 pn = ob->n;
			const plane_c pc = plane_of(ob);
#pragma omp simd
			for (unsigned r = 0; r < n; r++) {
				double tt;
				int64_t hit = plane_t(pc, num, o.x, o.y, o.z, b->dx[r], b->dy[r], b->dz[r], b->t[r],
						   &tt) &
					   (b->col[r] >= l) & (b->col[r] <= h);
				b->t[r] = hit ? tt : b->t[r];
				b->obj[r] = hit ? (int64_t)i : b->obj[r];
				b->nx[r] = hit ? pn.x : b->nx[r];
				b->ny[r] = hit ? pn.y : b->ny[r];
				b->nz[r] = hit ? pn.z : b->nz[r];
				b->gx[r] = hit ? pn.x : b->gx[r];
				b->gy[r] = hit ? pn.y : b->gy[r];
				b->gz[r] = hit ? pn.z : b->gz[r];
			}
		} else {
			for (unsigned r = 0; r < n; r++) {
				if (b->col[r] < l || b->col[r] > h)
					continue;
				double tt;
				pc_v3 nn, ng;
				if (pc_object_hit(ob, o, v3(b->dx[r], b->dy[r], b->dz[r]), 0, b->t[r], false, &tt,
						  &nn, &ng)) {
					b->t[r] = tt;
					b->obj[r] = (int64_t)i;
					b->nx[r] = nn.x;
					b->ny[r] = nn.y;
					b->nz[r] = nn.z;
					b->gx[r] = ng.x;
					b->gy[r] = ng.y;
					b->gz[r] = ng.z;
				}
			}
		}
	}
}

/* Hit points, normals towards the viewer, the local frame (t1 = v3_any_perp(n), t2 = n × t1),
 * k_r and s_r (camera x projected ⟂ k_r) in it, and the shadow-ray origins. */
STAGE static void stage_surface(const pc_sim *sim, batch *b)
{
	const pc_sim_camera *cam = &sim->scene->camera;
	const pc_v3 o = cam->position, R = cam->right, U = cam->up;
#pragma omp simd
	for (unsigned r = 0; r < b->n; r++) {
		double dx = b->dx[r], dy = b->dy[r], dz = b->dz[r], t = b->t[r];
		double x = o.x + dx * t, y = o.y + dy * t, z = o.z + dz * t;
		double kx = -dx, ky = -dy, kz = -dz;
		double nx = b->nx[r], ny = b->ny[r], nz = b->nz[r];
		double gx = b->gx[r], gy = b->gy[r], gz = b->gz[r];
		int flip = gx * kx + gy * ky + gz * kz < 0;
		gx = flip ? -gx : gx;
		gy = flip ? -gy : gy;
		gz = flip ? -gz : gz;
		nx = flip ? -nx : nx;
		ny = flip ? -ny : ny;
		nz = flip ? -nz : nz;
		/* v3_any_perp */
		double ax = fabs(nx) < 0.6 ? 1 : 0;
		double ay = fabs(nx) < 0.6 ? 0 : fabs(ny) < 0.6 ? 1 : 0;
		double az = fabs(nx) < 0.6 ? 0 : fabs(ny) < 0.6 ? 0 : 1;
		double an = ax * nx + ay * ny + az * nz;
		double px = ax + nx * -an, py = ay + ny * -an, pz = az + nz * -an;
		double pl = sqrt(px * px + py * py + pz * pz);
		double pinv = 1.0 / pl;
		int pok = pl > 0;
		double t1x = pok ? px * pinv : px, t1y = pok ? py * pinv : py, t1z = pok ? pz * pinv : pz;
		/* v3_cross(n, t1) */
		double t2x = ny * t1z - nz * t1y, t2y = nz * t1x - nx * t1z, t2z = nx * t1y - ny * t1x;
		/* s_r: camera right ⟂ k_r (perp_unit of a unit vector, fallback camera up) */
		double rk = R.x * kx + R.y * ky + R.z * kz;
		double qx = R.x + kx * -rk, qy = R.y + ky * -rk, qz = R.z + kz * -rk;
		double ql = sqrt(qx * qx + qy * qy + qz * qz);
		double qinv = 1.0 / ql;
		int qok = (ql < 1e-9) == 0;
		double srx = qok ? qx * qinv : U.x, sry = qok ? qy * qinv : U.y, srz = qok ? qz * qinv : U.z;
		b->kr[0][r] = kx * t1x + ky * t1y + kz * t1z;
		b->kr[1][r] = kx * t2x + ky * t2y + kz * t2z;
		b->kr[2][r] = kx * nx + ky * ny + kz * nz;
		b->sr[0][r] = srx * t1x + sry * t1y + srz * t1z;
		b->sr[1][r] = srx * t2x + sry * t2y + srz * t2z;
		b->sr[2][r] = srx * nx + sry * ny + srz * nz;
		double m = fabs(x) > fabs(y) ? fabs(x) : fabs(y);
		m = m > fabs(z) ? m : fabs(z);
		double eps = 1e-7 * (1 + m);
		b->xx[r] = x;
		b->xy[r] = y;
		b->xz[r] = z;
		b->ox[r] = x + gx * eps;
		b->oy[r] = y + gy * eps;
		b->oz[r] = z + gz * eps;
		b->fx[r] = gx;
		b->fy[r] = gy;
		b->fz[r] = gz;
		b->nx[r] = nx;
		b->ny[r] = ny;
		b->nz[r] = nz;
		b->t1x[r] = t1x;
		b->t1y[r] = t1y;
		b->t1z[r] = t1z;
		b->t2x[r] = t2x;
		b->t2y[r] = t2y;
		b->t2z[r] = t2z;
	}
}

/* For the light in b->l*, b->s*, b->dist: cos θ_i, which rays it reaches (cos θ_i > 0, not
 * shadowed: a ray leaving a plane, or a convex solid outwards, cannot meet it again), and k_i,
 * s_i in the local frame. */
STAGE static void stage_light(const pc_sim *sim, bool cast_shadows, batch *b)
{
	const pc_scene *sc = sim->scene;
	const unsigned n = b->n;
#pragma omp simd
	for (unsigned r = 0; r < n; r++) {
		double kx = -b->lx[r], ky = -b->ly[r], kz = -b->lz[r];
		double c = kx * b->nx[r] + ky * b->ny[r] + kz * b->nz[r];
		b->cosi[r] = c;
		b->lit[r] = (b->obj[r] >= 0) & (c > 0);
		b->ki[0][r] = kx * b->t1x[r] + ky * b->t1y[r] + kz * b->t1z[r];
		b->ki[1][r] = kx * b->t2x[r] + ky * b->t2y[r] + kz * b->t2z[r];
		b->ki[2][r] = kx * b->nx[r] + ky * b->ny[r] + kz * b->nz[r];
		b->si[0][r] = b->sx[r] * b->t1x[r] + b->sy[r] * b->t1y[r] + b->sz[r] * b->t1z[r];
		b->si[1][r] = b->sx[r] * b->t2x[r] + b->sy[r] * b->t2y[r] + b->sz[r] * b->t2z[r];
		b->si[2][r] = b->sx[r] * b->nx[r] + b->sy[r] * b->ny[r] + b->sz[r] * b->nz[r];
	}
	if (!cast_shadows)
		return;
	for (unsigned r = 0; r < n; r++) {
		int64_t i = b->obj[r];
		bool skip = false;
		if (i >= 0 && pc_object_convex(&sc->objects[i]))
			skip = sc->objects[i].type == PC_OBJ_PLANE ||
			       -b->lx[r] * b->gx[r] + -b->ly[r] * b->gy[r] + -b->lz[r] * b->gz[r] > 0;
		b->skip[r] = skip;
	}
	for (unsigned i = 0; i < sc->n_objects; i++) {
		const pc_sim_object *ob = &sc->objects[i];
		if (ob->type == PC_OBJ_SPHERE) {
			const pc_v3 c = ob->center;
			const double rad = ob->radius;
#pragma omp simd
			for (unsigned r = 0; r < n; r++) {
				double ocx = b->ox[r] - c.x, ocy = b->oy[r] - c.y, ocz = b->oz[r] - c.z;
				double C = (ocx * ocx + ocy * ocy + ocz * ocz) - rad * rad;
				double tt;
				int64_t hit = sphere_t(ocx, ocy, ocz, rad, C, -b->lx[r], -b->ly[r], -b->lz[r],
						    b->dist[r] * (1 - 1e-9), &tt);
				int64_t self = b->skip[r] & (b->obj[r] == (int64_t)i);
				b->lit[r] = b->lit[r] & ((hit & (self == 0)) == 0);
			}
		} else if (ob->type == PC_OBJ_PLANE) {
			const double pnx = ob->n.x, pny = ob->n.y, pnz = ob->n.z;
			const double ppx = ob->p.x, ppy = ob->p.y, ppz = ob->p.z;
			const plane_c pc = plane_of(ob);
#pragma omp simd
			for (unsigned r = 0; r < n; r++) {
				double num = (ppx - b->ox[r]) * pnx + (ppy - b->oy[r]) * pny + (ppz - b->oz[r]) * pnz;
				double tt;
				int64_t hit = plane_t(pc, num, b->ox[r], b->oy[r], b->oz[r], -b->lx[r], -b->ly[r],
						   -b->lz[r], b->dist[r] * (1 - 1e-9), &tt);
				int64_t self = b->skip[r] & (b->obj[r] == (int64_t)i);
				b->lit[r] = b->lit[r] & ((hit & (self == 0)) == 0);
			}
		} else {
			for (unsigned r = 0; r < n; r++) {
				if (!b->lit[r] || (b->skip[r] && b->obj[r] == (int64_t)i))
					continue;
				double tt;
				pc_v3 nn, ng;
				if (pc_object_hit(ob, v3(b->ox[r], b->oy[r], b->oz[r]),
						  v3(-b->lx[r], -b->ly[r], -b->lz[r]), 0, b->dist[r] * (1 - 1e-9), true,
						  &tt, &nn, &ng))
					b->lit[r] = 0;
			}
		}
	}
}

/* ---- the batch ---- */

/* Shades the batch's rays for the channels chan[r] (or all channels: chan NULL) and PSG state
 * g into S[(r·nout + k)·4 + i] (nout = 1 or nch) and M[(r·nout + k)·16 + 4i + j] (may be NULL). */
static void shade_batch(const pc_sim *sim, const int32_t *lo, const int32_t *hi, pc_v3 A,
			const uint8_t *chan, unsigned g, batch *b, double *S, double *M)
{
	const pc_scene *sc = sim->scene;
	const unsigned nout = chan ? 1 : sim->nch;
	const bool circular = sim->circular, shadows = sim->fx & PC_FX_CAST_SHADOWS;
	stage_rays(sim, A, b);
	stage_primary(sim, lo, hi, b);
	stage_surface(sim, b);
	for (unsigned r = 0; r < b->n; r++)
		for (unsigned k = 0; k < nout; k++) {
			unsigned ch = chan ? chan[r] : k;
			double *Sk = S + ((size_t)r * nout + k) * 4;
			Sk[0] = b->obj[r] < 0 ? sc->background[ch] : 0;
			Sk[1] = Sk[2] = 0;
			Sk[3] = circular ? 0 : NAN;
		}
	if (M)
		memset(M, 0, (size_t)b->n * nout * 16 * sizeof(double));
	for (unsigned li = 0; li < sc->n_lights; li++) {
		const pc_sim_light *l = &sc->lights[li];
		for (unsigned r = 0; r < b->n; r++) {
			pc_v3 d, s;
			double dist, factor;
			if (l->type == PC_LIGHT_DIRECTIONAL) {
				d = l->frame_d; /* constant over the scene (pc_light_prepare) */
				s = l->frame_s;
				dist = INFINITY;
				factor = 1;
			} else {
				factor = pc_light_frame(l, v3(b->xx[r], b->xy[r], b->xz[r]), &d, &s, &dist);
			}
			b->lx[r] = d.x;
			b->ly[r] = d.y;
			b->lz[r] = d.z;
			b->sx[r] = s.x;
			b->sy[r] = s.y;
			b->sz[r] = s.z;
			b->dist[r] = dist;
			b->factor[r] = factor;
		}
		stage_light(sim, shadows, b);
		const double *Sl = l->stokes[g % l->n_states];
		for (unsigned r = 0; r < b->n; r++) {
			if (!b->lit[r])
				continue;
			const pc_sim_object *ob = &sc->objects[b->obj[r]];
			const double kil[3] = { b->ki[0][r], b->ki[1][r], b->ki[2][r] };
			const double sil[3] = { b->si[0][r], b->si[1][r], b->si[2][r] };
			const double krl[3] = { b->kr[0][r], b->kr[1][r], b->kr[2][r] };
			const double srl[3] = { b->sr[0][r], b->sr[1][r], b->sr[2][r] };
			for (unsigned k = 0; k < nout; k++) {
				unsigned ch = chan ? chan[r] : k;
				double w = b->factor[r] * l->power[ch];
				if (!(w > 0))
					continue;
				double f[4][4];
				if (sim->pbrdf) {
					if (pc_pbrdf_eval_vec(sim->pbrdf[ob->material * sim->nch + ch], kil, krl, sil,
							      srl, f))
						continue;
				} else if (sim->brdf.eval(sim->brdf.user, ob->material, ch, kil, krl, sil, srl,
							  f)) {
					continue; /* the evaluator rejected the geometry: no contribution */
				}
				w *= b->cosi[r];
				double *Sk = S + ((size_t)r * nout + k) * 4;
				if (circular) {
					for (int i = 0; i < 4; i++)
						Sk[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] + f[i][2] * Sl[2] +
							      f[i][3] * Sl[3]);
				} else {
					for (int i = 0; i < 3; i++) /* lights are linear here: S_l[3] = 0 */
						Sk[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] + f[i][2] * Sl[2]);
				}
				if (M) {
					double *Mk = M + ((size_t)r * nout + k) * 16;
					for (int i = 0; i < 4; i++)
						for (int j = 0; j < 4; j++)
							Mk[i * 4 + j] += w * f[i][j];
				}
			}
		}
	}
}

void pc_render_span(const pc_sim *sim, const pc_render_row *rr, uint32_t sx0, uint32_t n,
		    const uint8_t *chan, unsigned g, double *S, double *M)
{
	const unsigned nout = chan ? 1 : sim->nch;
	batch b;
	if (sim->ss <= 1) {
		for (uint32_t i0 = 0; i0 < n; i0 += NB) {
			b.n = n - i0 < NB ? n - i0 : NB;
			for (unsigned r = 0; r < b.n; r++) {
				b.col[r] = (int32_t)(sx0 + i0 + r);
				b.px[r] = (sx0 + i0 + r) + 0.5;
			}
			shade_batch(sim, rr->lo[0], rr->hi[0], rr->base[0], chan ? chan + i0 : NULL, g, &b,
				    S + (size_t)i0 * nout * 4, M ? M + (size_t)i0 * nout * 16 : NULL);
		}
		return;
	}
	/* n×n stratified (regular) samples over the pixel footprint, averaged: Stokes vectors in
	 * one frame add (incoherent superposition). The s-axis differs between sub-rays by
	 * < 1e-3 rad over a pixel, below the model's accuracy; each sub-ray uses its own. The sums
	 * run sub-row by sub-row, left to right, per pixel. */
	const unsigned ss = sim->ss, per = NB / ss; /* pixels per batch */
	double Sa[NB * PC_SIM_MAX_CH * 4], Ma[NB * PC_SIM_MAX_CH * 16];
	uint8_t cb[NB];
	for (uint32_t p0 = 0; p0 < n; p0 += per) {
		unsigned np = n - p0 < per ? n - p0 : per;
		double *So = S + (size_t)p0 * nout * 4, *Mo = M ? M + (size_t)p0 * nout * 16 : NULL;
		memset(So, 0, (size_t)np * nout * 4 * sizeof(double));
		if (Mo)
			memset(Mo, 0, (size_t)np * nout * 16 * sizeof(double));
		for (unsigned j = 0; j < ss; j++) {
			/* rays ordered pixel-major, sub-column-minor */
			b.n = np * ss;
			for (unsigned p = 0; p < np; p++)
				for (unsigned i = 0; i < ss; i++) {
					unsigned r = p * ss + i;
					b.col[r] = (int32_t)(sx0 + p0 + p);
					b.px[r] = (sx0 + p0 + p) + 0.5 + sim->ss_off[i];
					if (chan)
						cb[r] = chan[p0 + p];
				}
			shade_batch(sim, rr->lo[j], rr->hi[j], rr->base[j], chan ? cb : NULL, g, &b, Sa,
				    Mo ? Ma : NULL);
			for (unsigned p = 0; p < np; p++)
				for (unsigned i = 0; i < ss; i++) {
					unsigned r = p * ss + i;
					for (unsigned k = 0; k < nout * 4; k++)
						So[p * nout * 4 + k] += Sa[r * nout * 4 + k];
					if (Mo)
						for (unsigned k = 0; k < nout * 16; k++)
							Mo[p * nout * 16 + k] += Ma[r * nout * 16 + k];
				}
		}
		double inv = 1.0 / (ss * ss);
		for (unsigned k = 0; k < np * nout * 4; k++)
			So[k] *= inv;
		if (Mo)
			for (unsigned k = 0; k < np * nout * 16; k++)
				Mo[k] *= inv;
	}
}

void pc_render_pixel(const pc_sim *sim, const pc_render_row *rr, uint32_t sx, unsigned ch,
		     unsigned g, double S[4], double M[4][4])
{
	uint8_t c = (uint8_t)ch;
	pc_render_span(sim, rr, sx, 1, &c, g, S, M ? &M[0][0] : NULL);
}
