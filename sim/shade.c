/* sim/shade.c - shading of camera rays in batches (render.c sets up the frames and culling;
 * the conventions and the radiometry are described there).
 *
 * A batch of up to NB rays goes through stages, each a loop over the rays: camera directions;
 * the nearest hit (spheres and planes in vectorised loops, other objects per ray); the surface
 * frames; per light its direction, the shadow tests and the local vectors; finally, per ray and
 * light, the pBRDF and the Stokes sum. The loops are independent across rays, so they pipeline
 * and vectorise (built without errno for sqrt; shade_stages.inc is compiled once per
 * instruction-set level of polarcam/cpu.h and chosen at run time); every value is computed with the
 * operations of the per-ray formulas of geometry_inline.h and vec.h in the same order, so the
 * result does not depend on the batch size or the instruction set (IEEE arithmetic, no FMA
 * contraction in ISO C builds). */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "polarcam/cpu.h"
#include "polarcam/pbrdf.h"
#include "sim_impl.h"

#define NB 64

/* IEEE arithmetic as written, whatever the instance (clang would otherwise fuse multiply-adds
 * where the target has FMA) */
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

typedef struct batch {
	unsigned n;
	int32_t col[NB]; /* pixel column (culling) */
	double px[NB];   /* sensor x of the ray (pixel + 0.5 + sub-pixel offset) */
	double dx[NB], dy[NB], dz[NB];
	double t[NB];
	int64_t obj[NB]; /* −1: no hit (64-bit lanes like the doubles: the loops vectorise) */
	double nx[NB], ny[NB], nz[NB]; /* shading normal, then flipped towards the viewer */
	double gx[NB], gy[NB], gz[NB]; /* geometric normal as the object has it */
	double fx[NB], fy[NB], fz[NB]; /* geometric normal towards the viewer */
	double xx[NB], xy[NB], xz[NB]; /* hit point */
	double ox[NB], oy[NB], oz[NB]; /* shadow-ray origin */
	double t1x[NB], t1y[NB], t1z[NB], t2x[NB], t2y[NB], t2z[NB];
	double kr[3][NB], sr[3][NB]; /* k_r and s_r in the local frame */
	/* the current light */
	double lx[NB], ly[NB], lz[NB]; /* propagation d */
	double sx[NB], sy[NB], sz[NB]; /* its s-axis */
	double dist[NB], factor[NB], cosi[NB];
	double ki[3][NB], si[3][NB];
	int64_t skip[NB], lit[NB];
} batch;

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
	plane_c c = {p->n.x, p->n.y, p->n.z, p->p.x, p->p.y,    p->p.z,    p->u.x,       p->u.y,
	             p->u.z, p->v.x, p->v.y, p->v.z, p->half_u, p->half_v, p->half_u > 0};
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

/* ---- stages (shade_stages.inc), one instance per instruction-set level ---- */

typedef struct shade_stages {
	void (*rays)(const pc_sim *sim, pc_v3 A, batch *b);
	void (*primary)(const pc_sim *sim, const int32_t *lo, const int32_t *hi, batch *b);
	void (*surface)(const pc_sim *sim, batch *b);
	void (*light)(const pc_sim *sim, bool cast_shadows, batch *b);
} shade_stages;

#define KFN(name) name##_baseline
#define KATTR
#include "shade_stages.inc"
#undef KFN
#undef KATTR
#if defined(__x86_64__) && defined(__GNUC__)
#define KFN(name) name##_avx2
#define KATTR     __attribute__((target("avx2")))
#include "shade_stages.inc"
#undef KFN
#undef KATTR
#define KFN(name) name##_avx512
#define KATTR     __attribute__((target("avx512f")))
#include "shade_stages.inc"
#undef KFN
#undef KATTR
#endif

static const shade_stages *stages_now(void)
{
	switch (pc_cpu_active()) {
#if defined(__x86_64__) && defined(__GNUC__)
	case PC_CPU_AVX512:
		return &stages_avx512;
	case PC_CPU_AVX2:
		return &stages_avx2;
#endif
	default:
		return &stages_baseline;
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
	const shade_stages *st = stages_now();
	st->rays(sim, A, b);
	st->primary(sim, lo, hi, b);
	st->surface(sim, b);
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
				factor = pc_light_frame(l, v3(b->xx[r], b->xy[r], b->xz[r]), &d, &s,
				                        &dist);
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
		st->light(sim, shadows, b);
		const double *Sl = l->stokes[g % l->n_states];
		for (unsigned r = 0; r < b->n; r++) {
			if (!b->lit[r])
				continue;
			const pc_sim_object *ob = &sc->objects[b->obj[r]];
			const double kil[3] = {b->ki[0][r], b->ki[1][r], b->ki[2][r]};
			const double sil[3] = {b->si[0][r], b->si[1][r], b->si[2][r]};
			const double krl[3] = {b->kr[0][r], b->kr[1][r], b->kr[2][r]};
			const double srl[3] = {b->sr[0][r], b->sr[1][r], b->sr[2][r]};
			for (unsigned k = 0; k < nout; k++) {
				unsigned ch = chan ? chan[r] : k;
				double w = b->factor[r] * l->power[ch];
				if (!(w > 0))
					continue;
				double f[4][4];
				if (sim->pbrdf) {
					if (pc_pbrdf_eval_vec(
					        sim->pbrdf[ob->material * sim->nch + ch], kil, krl,
					        sil, srl, f))
						continue;
				} else if (sim->brdf.eval(sim->brdf.user, ob->material, ch, kil,
				                          krl, sil, srl, f)) {
					continue; /* the evaluator rejected the geometry: no
					             contribution */
				}
				w *= b->cosi[r];
				double *Sk = S + ((size_t)r * nout + k) * 4;
				if (circular) {
					for (int i = 0; i < 4; i++)
						Sk[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] +
						              f[i][2] * Sl[2] + f[i][3] * Sl[3]);
				} else {
					for (int i = 0; i < 3;
					     i++) /* lights are linear here: S_l[3] = 0 */
						Sk[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] +
						              f[i][2] * Sl[2]);
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
			shade_batch(sim, rr->lo[0], rr->hi[0], rr->base[0], chan ? chan + i0 : NULL,
			            g, &b, S + (size_t)i0 * nout * 4,
			            M ? M + (size_t)i0 * nout * 16 : NULL);
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
			shade_batch(sim, rr->lo[j], rr->hi[j], rr->base[j], chan ? cb : NULL, g, &b,
			            Sa, Mo ? Ma : NULL);
			for (unsigned p = 0; p < np; p++)
				for (unsigned i = 0; i < ss; i++) {
					unsigned r = p * ss + i;
					for (unsigned k = 0; k < nout * 4; k++)
						So[p * nout * 4 + k] += Sa[r * nout * 4 + k];
					if (Mo)
						for (unsigned k = 0; k < nout * 16; k++)
							Mo[p * nout * 16 + k] +=
							    Ma[r * nout * 16 + k];
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
