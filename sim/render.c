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
#include <math.h>
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

/* The physics core as the BRDF (the default). */
static int eval_pbrdf(void *user, unsigned material, unsigned ch, const double k_i[3],
		      const double k_r[3], const double s_i[3], const double s_r[3], double f[4][4])
{
	const pc_sim *sim = user;
	return pc_pbrdf_eval_vec(sim->pbrdf[material * sim->nch + ch], k_i, k_r, s_i, s_r, f);
}

static inline void to_local(pc_v3 a, pc_v3 t1, pc_v3 t2, pc_v3 n, double out[3])
{
	out[0] = v3_dot(a, t1);
	out[1] = v3_dot(a, t2);
	out[2] = v3_dot(a, n);
}

/* Radiance along the camera ray dir (unit, from the camera) for channel ch, PSG state g.
 * One body, instantiated per effect combination below: the branches on the const flags are
 * resolved at compile time. */
static inline void shade_body(const pc_sim *sim, unsigned ch, unsigned g, pc_v3 dir, double S[4],
			      double M[4][4], const bool cast_shadows, const bool circular)
{
	const pc_scene *sc = sim->scene;
	S[0] = S[1] = S[2] = 0;
	S[3] = circular ? 0 : NAN;
	if (M)
		memset(M, 0, 16 * sizeof(double));
	pc_hit hit;
	pc_v3 o = sim->scene->camera.position;
	if (!pc_scene_intersect(sc, o, dir, 0, INFINITY, &hit)) {
		S[0] = sc->background[ch];
		return;
	}
	pc_v3 x = v3_madd(o, dir, hit.t);
	pc_v3 kr = v3_neg(dir);
	/* two-sided surfaces: the normals face the viewer */
	pc_v3 n = hit.n, ng = hit.ng;
	if (v3_dot(ng, kr) < 0) {
		ng = v3_neg(ng);
		n = v3_neg(n);
	}
	pc_v3 t1 = v3_any_perp(n), t2 = v3_cross(n, t1);
	pc_v3 sr = v3_perp_unit(sc->camera.right, kr, sc->camera.up);
	double kr_l[3], sr_l[3];
	to_local(kr, t1, t2, n, kr_l);
	to_local(sr, t1, t2, n, sr_l);
	const pc_sim_object *ob = &sc->objects[hit.object];
	double eps = 1e-7 * (1 + fmax(fabs(x.x), fmax(fabs(x.y), fabs(x.z))));
	pc_v3 xo = v3_madd(x, ng, eps);
	for (unsigned li = 0; li < sc->n_lights; li++) {
		const pc_sim_light *l = &sc->lights[li];
		pc_v3 d, sl;
		double dist;
		double w = pc_light_frame(l, x, &d, &sl, &dist) * l->power[ch];
		pc_v3 ki = v3_neg(d);
		double cos_i = v3_dot(ki, n);
		if (!(cos_i > 0) || !(w > 0))
			continue;
		if (cast_shadows && pc_scene_occluded(sc, xo, ki, 0, dist * (1 - 1e-9)))
			continue;
		double ki_l[3], si_l[3], f[4][4];
		to_local(ki, t1, t2, n, ki_l);
		to_local(sl, t1, t2, n, si_l);
		if (sim->brdf.eval(sim->brdf.user, ob->material, ch, ki_l, kr_l, si_l, sr_l, f))
			continue; /* the evaluator rejected the geometry: no contribution */
		w *= cos_i;
		const double *Sl = l->stokes[g % l->n_states];
		if (circular) {
			for (int i = 0; i < 4; i++)
				S[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] + f[i][2] * Sl[2] +
					     f[i][3] * Sl[3]);
		} else {
			for (int i = 0; i < 3; i++) /* lights are linear here: S_l[3] = 0 */
				S[i] += w * (f[i][0] * Sl[0] + f[i][1] * Sl[1] + f[i][2] * Sl[2]);
		}
		if (M)
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					M[i][j] += w * f[i][j];
	}
}

static void shade_lin(const pc_sim *s, unsigned ch, unsigned g, pc_v3 d, double S[4], double M[4][4])
{
	shade_body(s, ch, g, d, S, M, false, false);
}
static void shade_lin_sh(const pc_sim *s, unsigned ch, unsigned g, pc_v3 d, double S[4], double M[4][4])
{
	shade_body(s, ch, g, d, S, M, true, false);
}
static void shade_circ(const pc_sim *s, unsigned ch, unsigned g, pc_v3 d, double S[4], double M[4][4])
{
	shade_body(s, ch, g, d, S, M, false, true);
}
static void shade_circ_sh(const pc_sim *s, unsigned ch, unsigned g, pc_v3 d, double S[4], double M[4][4])
{
	shade_body(s, ch, g, d, S, M, true, true);
}

/* Camera ray through sensor position (px, py) in pixels (pixel centres at integer + 0.5):
 * pinhole with the virtual image in front of the lens, image x = camera right, image rows go
 * down. */
static inline pc_v3 camera_ray(const pc_sim *sim, double px, double py)
{
	const pc_sim_camera *c = &sim->scene->camera;
	double u = (px - sim->cx) * sim->pitch_m, v = (py - sim->cy) * sim->pitch_m;
	pc_v3 d = v3_add(v3_scale(c->forward, sim->focal_m), v3_scale(c->right, u));
	return v3_unit(v3_madd(d, c->up, -v));
}

void pc_render_pixel(const pc_sim *sim, uint32_t sx, uint32_t sy, unsigned ch, unsigned g,
		     double S[4], double M[4][4])
{
	if (sim->ss <= 1) {
		sim->shade(sim, ch, g, camera_ray(sim, sx + 0.5, sy + 0.5), S, M);
		return;
	}
	/* n×n stratified (regular) samples over the pixel footprint, averaged: Stokes vectors in
	 * one frame add (incoherent superposition). The s-axis differs between sub-rays by
	 * < 1e-3 rad over a pixel, below the model's accuracy; each sub-ray uses its own. */
	double acc[4] = { 0, 0, 0, 0 }, macc[4][4];
	if (M)
		memset(macc, 0, sizeof macc);
	double Ss[4], Ms[4][4];
	for (unsigned j = 0; j < sim->ss; j++)
		for (unsigned i = 0; i < sim->ss; i++) {
			pc_v3 d = camera_ray(sim, sx + 0.5 + sim->ss_off[i], sy + 0.5 + sim->ss_off[j]);
			sim->shade(sim, ch, g, d, Ss, M ? Ms : NULL);
			for (int k = 0; k < 4; k++)
				acc[k] += Ss[k];
			if (M)
				for (int a = 0; a < 4; a++)
					for (int b = 0; b < 4; b++)
						macc[a][b] += Ms[a][b];
		}
	double inv = 1.0 / (sim->ss * sim->ss);
	for (int k = 0; k < 4; k++)
		S[k] = acc[k] * inv;
	if (M)
		for (int a = 0; a < 4; a++)
			for (int b = 0; b < 4; b++)
				M[a][b] = macc[a][b] * inv;
}

void pc_render_setup(pc_sim *sim)
{
	const pc_scene *sc = sim->scene;
	bool sh = sim->fx & PC_FX_CAST_SHADOWS;
	sim->shade = sim->circular ? (sh ? shade_circ_sh : shade_circ) : (sh ? shade_lin_sh : shade_lin);
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
}
