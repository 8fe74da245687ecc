/* sim/render.c - per-pixel ray casting: camera ray → nearest surface → for each light the pBRDF
 * Mueller matrix in consistent Stokes frames → Stokes radiance in the image-plane frame.
 *
 * Stokes frames (physics.md §1: for a beam travelling along d, (s, p, d) is right-handed,
 * p = d × s):
 *   light beam:   d = propagation from the light, s = the light's reference (default unit(d × ẑ),
 *                 i.e. s-polarized with respect to the horizontal ground; world x when d ∥ ẑ);
 *   towards the camera: d = k_r (from the surface to the camera), s = camera x ("right")
 *                 projected perpendicular to k_r, so p = k_r × s ≈ camera up. S1 > 0 is
 *                 polarization along image x, AoLP counter-clockwise from image x as seen by the
 *                 viewer of the image (image up = decreasing row index).
 * pc_pbrdf_eval_vec takes exactly these s-vectors (expressed in the surface's local frame), so
 * no rotation matrices are composed here: the physics core rotates from the given frames into
 * the facet frames itself (physics.md §2, T_in/T_out).
 *
 * Radiometry: L_r = f · S_light · E · cosθ_i (f in sr⁻¹, E the irradiance of the beam at normal
 * incidence in W/m²), summed over lights (BRDF definition; Nicodemus et al., NBS Monograph 160,
 * 1977). Point lights: E = I/r² (inverse-square law).
 */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "polarcam/error.h"
#include "sim_impl.h"

static void light_frame_compute(const pc_sim_light *l, pc_v3 *d, pc_v3 *s)
{
	pc_v3 dflt = v3_cross(*d, v3(0, 0, 1));
	double l2 = v3_len(dflt);
	dflt = l2 > 1e-9 ? v3_scale(dflt, 1 / l2) : v3_perp_unit(v3(1, 0, 0), *d, v3(0, 1, 0));
	*s = l->has_reference ? v3_perp_unit(l->reference, *d, dflt) : dflt;
}

void pc_light_prepare(pc_sim_light *l)
{
	if (l->type == PC_LIGHT_DIRECTIONAL) {
		l->frame_d = v3_neg(l->direction);
		light_frame_compute(l, &l->frame_d, &l->frame_s);
	}
}

double pc_light_frame(const pc_sim_light *l, pc_v3 x, pc_v3 *d, pc_v3 *s, double *dist)
{
	double factor;
	if (l->type == PC_LIGHT_DIRECTIONAL) {
		/* constant over the scene: computed once by pc_light_prepare */
		*d = l->frame_d;
		*s = l->frame_s;
		*dist = INFINITY;
		return 1;
	} else {
		pc_v3 v = v3_sub(x, l->position);
		double r = v3_len(v);
		*d = r > 0 ? v3_scale(v, 1 / r) : v3(0, 0, -1);
		*dist = r;
		factor = r > 0 ? 1 / (r * r) : 0;
	}
	light_frame_compute(l, d, s);
	return factor;
}

/* The physics core as the BRDF (the default; shading calls it directly). */
static int eval_pbrdf(void *user, unsigned material, unsigned ch, const double k_i[3],
                      const double k_r[3], const double s_i[3], const double s_r[3], double f[4][4])
{
	const pc_sim *sim = user;
	return pc_pbrdf_eval_vec(sim->pbrdf[material * sim->nch + ch], k_i, k_r, s_i, s_r, f);
}

/* ---- camera rays and primary-ray culling ----
 *
 * Camera ray through sensor position (px, py) in pixels (pixel centres at integer + 0.5):
 * pinhole with the virtual image in front of the lens, image x = camera right, image rows go
 * down: D = f·forward + u·right − v·up, u = (px − cx)·pitch, v = (py − cy)·pitch, d = D/|D|.
 *
 * Culling: D(u) = A + u·right with A = f·forward − v·up ⟂ right. The line through the camera
 * centre o along D meets a sphere (c, r) only if |oc × D|² ≤ r²|D|² (oc = c − o), i.e.
 *   (C − β²)u² − 2αβu + (C|A|² − α²) ≤ 0,  C = |oc|² − r², α = oc·A, β = oc·right,
 * a quadratic in u whose root interval bounds the pixel columns of one sensor row that can see
 * the object's bounding sphere. The radius is inflated (relative 1e-6) and the column range
 * widened by two pixels, so rounding never culls a ray that the exact test would hit; where
 * the quadratic is not convex (the camera near or inside the sphere), or its terms overflow
 * (objects ~1e90 away: a fuzzing finding), nothing is culled. The
 * per-pixel intersection tests themselves are unchanged, so culling changes no result. */

static inline pc_v3 row_base(const pc_sim *sim, double py)
{
	const pc_sim_camera *c = &sim->scene->camera;
	double v = (py - sim->cy) * sim->pitch_m;
	return v3_madd(v3_scale(c->forward, sim->focal_m), c->up, -v);
}

static void cull_range(const pc_sim *sim, pc_v3 A, unsigned i, int32_t *lo, int32_t *hi)
{
	const pc_sim_camera *cam = &sim->scene->camera;
	const int32_t full_lo = INT32_MIN / 2, full_hi = INT32_MAX / 2;
	*lo = full_lo;
	*hi = full_hi;
	if (!sim->cull_r[i] || !(sim->cull_r[i] < INFINITY))
		return; /* unbounded */
	double r = sim->cull_r[i] * (1 + 1e-6);
	pc_v3 oc = v3_sub(sim->cull_c[i], cam->position);
	double oc2 = v3_dot(oc, oc);
	double C = oc2 - r * r;
	if (!(C > 1e-6 * oc2))
		return; /* camera at or inside the bounding sphere */
	double al = v3_dot(oc, A), be = v3_dot(oc, cam->right), A2 = v3_dot(A, A);
	double a2 = C - be * be;
	if (!(a2 > 1e-6 * C))
		return; /* not a bounded interval in u: keep the whole row */
	double hb = al * be, c0 = C * A2 - al * al;
	double hb2 = hb * hb, ac = a2 * c0;
	if (!isfinite(hb2) || !isfinite(ac))
		return; /* overflow (an object ~1e90 away): keep the whole row */
	double disc = hb2 - ac;
	if (disc < 0) {
		*lo = 1;
		*hi = 0; /* this row never sees the object */
		return;
	}
	double sq = sqrt(disc);
	double u0 = (hb - sq) / a2, u1 = (hb + sq) / a2;
	double x0 = u0 / sim->pitch_m + sim->cx - 0.5, x1 = u1 / sim->pitch_m + sim->cx - 0.5;
	if (!isfinite(x0) || !isfinite(x1))
		return; /* keep the whole row: culling only saves work */
	double l = floor(x0) - 2, h = ceil(x1) + 2;
	*lo = l < full_lo ? full_lo : l > full_hi ? full_hi : (int32_t)l;
	*hi = h < full_lo ? full_lo : h > full_hi ? full_hi : (int32_t)h;
}

void pc_render_row_begin(const pc_sim *sim, uint32_t sy, pc_render_row *rr)
{
	rr->sy = sy;
	rr->nsub = sim->ss <= 1 ? 1 : sim->ss;
	unsigned nc = sim->n_cull;
	for (unsigned j = 0; j < rr->nsub; j++) {
		double py = sy + 0.5 + (sim->ss <= 1 ? 0 : sim->ss_off[j]);
		rr->base[j] = row_base(sim, py);
		for (unsigned i = 0; i < nc; i++)
			cull_range(sim, rr->base[j], i, &rr->lo[j][i], &rr->hi[j][i]);
	}
}

void pc_render_setup(pc_sim *sim)
{
	const pc_scene *sc = sim->scene;
	if (!sim->opt.brdf) {
		sim->brdf.eval = eval_pbrdf;
		sim->brdf.user = sim;
	} else {
		sim->brdf = *sim->opt.brdf;
	}
	sim->pitch_m = sim->fig.pixel_pitch_um * 1e-6;
	sim->focal_m = sc->camera.focal_length_mm * 1e-3;
	sim->cx = isnan(sc->camera.principal_x) ? sim->fig.width / 2.0 : sc->camera.principal_x;
	sim->cy = isnan(sc->camera.principal_y) ? sim->fig.height / 2.0 : sc->camera.principal_y;
	sim->ss = (sim->fx & PC_FX_SUPERSAMPLING) ? sc->supersampling : 1;
	for (unsigned i = 0; i < sim->ss && i < 16; i++)
		sim->ss_off[i] = (i + 0.5) / sim->ss - 0.5;
	/* per-camera terms of the primary-ray tests (primary_hit) */
	for (unsigned i = 0; i < sc->n_objects && i < PC_CULL_MAX; i++) {
		const pc_sim_object *ob = &sc->objects[i];
		sim->prim_oc[i] = v3_sub(sc->camera.position, ob->center);
		sim->prim_c[i] = v3_dot(sim->prim_oc[i], sim->prim_oc[i]) - ob->radius * ob->radius;
		sim->prim_num[i] = v3_dot(v3_sub(ob->p, sc->camera.position), ob->n);
	}
	/* bounding spheres of the first PC_CULL_MAX objects (radius 0: not culled) */
	sim->n_cull = sc->n_objects < PC_CULL_MAX ? sc->n_objects : PC_CULL_MAX;
	for (unsigned i = 0; i < sim->n_cull; i++) {
		sim->cull_r[i] = 0;
		pc_v3 c;
		double r;
		if (pc_object_bsphere(&sc->objects[i], &c, &r) && r > 0 && isfinite(r) &&
		    isfinite(c.x) && isfinite(c.y) && isfinite(c.z)) {
			sim->cull_c[i] = c;
			sim->cull_r[i] = r;
		}
	}
}
