/* sim/scene.c - scene files (docs/scene-format.md): parsing and validation with errors that name
 * the file, the JSON line (syntax) or the field path (values), and what was expected. */
#include "polarcam/sim.h"

#include <jansson.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "polarcam/mosaic.h"
#include "polarcam/optics.h"
#include "json.h"
#include "scene_impl.h"

#define DEG (3.14159265358979323846 / 180.0)

/* ---- parse context and error helpers ---- */

typedef struct pctx {
	pc_json_src js; /* file name, PC_EINVAL */
	const char *base_dir;
	pc_scene *scene;
	bool colour;
} pctx;

typedef struct {
	const char *name;
	int value;
} pc_scene_keyword;

/* Optional string field that must be one of the keywords (NULL-terminated table). *out is the
 * keyword's value, or -1 when the field is absent; `expected` lists them for the error. */
static int get_enum(const pctx *c, json_t *obj, const char *path, const char *key,
                    const pc_scene_keyword *words, const char *expected, int *out)
{
	const char *s = NULL;
	int rc = pc_json_get_str(&c->js, obj, path, key, PC_JSON_OPTIONAL, &s);
	*out = -1;
	if (rc || !s)
		return rc;
	for (const pc_scene_keyword *w = words; w->name; w++)
		if (!strcmp(s, w->name)) {
			*out = w->value;
			return 0;
		}
	char p[256];
	pc_json_path(p, sizeof p, path, key);
	return pc_json_error(&c->js, p, "'%s': expected %s", s, expected);
}

static int get_v3(const pctx *c, json_t *obj, const char *path, const char *key, int required,
                  pc_v3 *out)
{
	double a[3];
	if (!json_object_get(obj, key)) {
		if (required) {
			char p[256];
			pc_json_path(p, sizeof p, path, key);
			return pc_json_error(&c->js, p, "missing (required; [x, y, z])");
		}
		return 0;
	}
	int rc = pc_json_get_nums(&c->js, obj, path, key, required, a, 3);
	if (rc)
		return rc;
	*out = v3(a[0], a[1], a[2]);
	return 0;
}

static int get_unit_v3(const pctx *c, json_t *obj, const char *path, const char *key, int required,
                       pc_v3 *out)
{
	pc_v3 v = *out;
	int rc = get_v3(c, obj, path, key, required, &v);
	if (rc)
		return rc;
	if (!json_object_get(obj, key))
		return 0;
	if (!(v3_len(v) > 1e-12)) {
		char p[256];
		pc_json_path(p, sizeof p, path, key);
		return pc_json_error(&c->js, p, "must be a non-zero vector");
	}
	*out = v3_unit(v);
	return 0;
}

/* A number, or an array of 3 numbers (R, G, B), each in [lo, hi]. */
static int get_num_rgb(const pctx *c, json_t *obj, const char *path, const char *key, int required,
                       double lo, bool lo_open, double hi, double out[3])
{
	char p[256];
	pc_json_path(p, sizeof p, path, key);
	json_t *v = json_object_get(obj, key);
	if (!v) {
		if (required)
			return pc_json_error(&c->js, p, "missing (required)");
		return 0;
	}
	if (json_is_array(v)) {
		double a[3];
		int rc = pc_json_get_nums(&c->js, obj, path, key, PC_JSON_REQUIRED, a, 3);
		if (rc)
			return rc;
		for (int i = 0; i < 3; i++) {
			if (lo_open ? !(a[i] > lo) : !(a[i] >= lo)) {
				char q[288];
				pc_json_path_index(q, sizeof q, p, (size_t)i);
				return pc_json_error(&c->js, q, "= %g: must be %s %g", a[i],
				                     lo_open ? ">" : "≥", lo);
			}
			if (a[i] > hi) {
				char q[288];
				pc_json_path_index(q, sizeof q, p, (size_t)i);
				return pc_json_error(&c->js, q, "= %g: must be ≤ %g", a[i], hi);
			}
			out[i] = a[i];
		}
		return 0;
	}
	double x;
	int rc = pc_json_get_num(&c->js, obj, path, key, PC_JSON_REQUIRED, lo, lo_open, hi, &x);
	if (rc)
		return rc;
	out[0] = out[1] = out[2] = x;
	return 0;
}

/* ---- polarization states ---- */

static int parse_retarder(const pctx *c, json_t *v, const char *path, double m[4][4])
{
	static const char *const keys[] = {"angle_deg", "retardance_deg", NULL};
	int rc;
	if ((rc = pc_json_need_object(&c->js, v, path)) ||
	    (rc = pc_json_check_keys(&c->js, v, path, keys)))
		return rc;
	double a = 0, d = 0;
	if ((rc = pc_json_get_num(&c->js, v, path, "angle_deg", PC_JSON_REQUIRED, -360, false, 360,
	                          &a)) ||
	    (rc = pc_json_get_num(&c->js, v, path, "retardance_deg", PC_JSON_REQUIRED, 0, false,
	                          360, &d)))
		return rc;
	pc_retarder_mueller(a * DEG, d * DEG, m);
	return 0;
}

/* "unpolarized" | {"linear_deg": a, "dop": p} | {"circular": ±1, "dop": p} | {"stokes": [s1,s2,s3]}
 * | {"polarizer_deg": p, "retarder": {...}} → normalized Stokes (S0 = 1). */
static int parse_pol(const pctx *c, json_t *v, const char *path, double S[4])
{
	int rc;
	if (json_is_string(v)) {
		if (!strcmp(json_string_value(v), "unpolarized") ||
		    !strcmp(json_string_value(v), "unpolarised")) {
			S[0] = 1;
			S[1] = S[2] = S[3] = 0;
			return 0;
		}
		return pc_json_error(&c->js, path,
		                     "'%s': expected \"unpolarized\" or an object (linear_deg, "
		                     "circular, stokes or polarizer_deg)",
		                     json_string_value(v));
	}
	static const char *const keys[] = {"linear_deg", "circular", "stokes", "polarizer_deg",
	                                   "retarder",   "dop",      NULL};
	if ((rc = pc_json_need_object(&c->js, v, path)) ||
	    (rc = pc_json_check_keys(&c->js, v, path, keys)))
		return rc;
	int kinds = !!json_object_get(v, "linear_deg") + !!json_object_get(v, "circular") +
	            !!json_object_get(v, "stokes") + !!json_object_get(v, "polarizer_deg");
	if (kinds != 1)
		return pc_json_error(
		    &c->js, path,
		    "give exactly one of linear_deg, circular, stokes, polarizer_deg");
	double dop = 1;
	if ((rc = pc_json_get_num(&c->js, v, path, "dop", PC_JSON_OPTIONAL, 0, false, 1, &dop)))
		return rc;
	S[0] = 1;
	S[1] = S[2] = S[3] = 0;
	if (json_object_get(v, "linear_deg")) {
		double a;
		if ((rc = pc_json_get_num(&c->js, v, path, "linear_deg", PC_JSON_REQUIRED, -360,
		                          false, 360, &a)))
			return rc;
		S[1] = dop * cos(2 * a * DEG);
		S[2] = dop * sin(2 * a * DEG);
	} else if (json_object_get(v, "circular")) {
		long h;
		if ((rc =
		         pc_json_get_int(&c->js, v, path, "circular", PC_JSON_REQUIRED, -1, 1, &h)))
			return rc;
		if (h == 0)
			return pc_json_error(&c->js, path,
			                     "circular = 0: must be +1 (S3 > 0) or -1 (S3 < 0)");
		S[3] = dop * (double)h;
	} else if (json_object_get(v, "stokes")) {
		double s[3];
		if ((rc = pc_json_get_nums(&c->js, v, path, "stokes", PC_JSON_REQUIRED, s, 3)))
			return rc;
		double p = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
		if (p > 1 + 1e-12) {
			char q[256];
			pc_json_path(q, sizeof q, path, "stokes");
			return pc_json_error(
			    &c->js, q,
			    "degree of polarization %g > 1 (normalized [S1, S2, S3] "
			    "with S0 = 1)",
			    p);
		}
		for (int i = 0; i < 3; i++)
			S[i + 1] = dop * s[i];
	} else {
		double a;
		if ((rc = pc_json_get_num(&c->js, v, path, "polarizer_deg", PC_JSON_REQUIRED, -360,
		                          false, 360, &a)))
			return rc;
		double in[4] = {1, dop * cos(2 * a * DEG), dop * sin(2 * a * DEG), 0};
		json_t *r = json_object_get(v, "retarder");
		if (r) {
			double m[4][4];
			char q[256];
			pc_json_path(q, sizeof q, path, "retarder");
			if ((rc = parse_retarder(c, r, q, m)))
				return rc;
			for (int i = 0; i < 4; i++)
				S[i] = m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2] +
				       m[i][3] * in[3];
		} else {
			memcpy(S, in, sizeof in);
		}
	}
	if (json_object_get(v, "retarder") && !json_object_get(v, "polarizer_deg"))
		return pc_json_error(&c->js, path,
		                     "retarder needs polarizer_deg (the polarizer in front of it)");
	return 0;
}

/* ---- sections ---- */

static int parse_camera(const pctx *c, json_t *v, pc_sim_camera *cam)
{
	static const char *const keys[] = {"focal_length_mm", "f_number",  "position",
	                                   "look_at",         "direction", "up",
	                                   "principal_point", NULL};
	const char *P = "camera";
	int rc;
	if ((rc = pc_json_need_object(&c->js, v, P)) ||
	    (rc = pc_json_check_keys(&c->js, v, P, keys)))
		return rc;
	cam->focal_length_mm = 12;
	cam->f_number = 4;
	pc_v3 pos = v3(0, -5, 2), up = v3(0, 0, 1), fwd = v3(0, 1, 0), at = pos;
	if ((rc = pc_json_get_num(&c->js, v, P, "focal_length_mm", PC_JSON_OPTIONAL, 0, true, 1e5,
	                          &cam->focal_length_mm)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "f_number", PC_JSON_OPTIONAL, 0.3, false, 1000,
	                          &cam->f_number)) ||
	    (rc = get_v3(c, v, P, "position", PC_JSON_REQUIRED, &pos)) ||
	    (rc = get_unit_v3(c, v, P, "up", PC_JSON_OPTIONAL, &up)))
		return rc;
	bool has_at = json_object_get(v, "look_at"), has_dir = json_object_get(v, "direction");
	if (has_at == has_dir)
		return pc_json_error(&c->js, P,
		                     "give exactly one of look_at ([x, y, z] point) or direction");
	if (has_at) {
		if ((rc = get_v3(c, v, P, "look_at", PC_JSON_REQUIRED, &at)))
			return rc;
		if (!(v3_len(v3_sub(at, pos)) > 1e-12))
			return pc_json_error(&c->js, "camera.look_at", "equals camera.position");
		fwd = v3_unit(v3_sub(at, pos));
	} else if ((rc = get_unit_v3(c, v, P, "direction", PC_JSON_REQUIRED, &fwd))) {
		return rc;
	}
	pc_v3 right = v3_cross(fwd, up);
	if (v3_len(right) < 1e-9)
		return pc_json_error(&c->js, "camera.up", "is parallel to the viewing direction");
	cam->position = pos;
	cam->forward = fwd;
	cam->right = v3_unit(right);
	cam->up =
	    v3_cross(cam->right, fwd); /* right × up = −forward: (right, up, −fwd) right-handed */
	cam->principal_x = cam->principal_y = NAN;
	if (json_object_get(v, "principal_point")) {
		double pp[2];
		if ((rc = pc_json_get_nums(&c->js, v, P, "principal_point", PC_JSON_REQUIRED, pp,
		                           2)))
			return rc;
		cam->principal_x = pp[0];
		cam->principal_y = pp[1];
	}
	return 0;
}

static int parse_material(const pctx *c, json_t *v, const char *path, const char *name,
                          pc_sim_material *m)
{
	static const char *const keys[] = {"n",         "k",   "sigma",     "diffuse",
	                                   "shadowing", "rho", "rho_order", NULL};
	int rc;
	if ((rc = pc_json_need_object(&c->js, v, path)) ||
	    (rc = pc_json_check_keys(&c->js, v, path, keys)))
		return rc;
	if (strlen(name) >= sizeof m->name)
		return pc_json_error(&c->js, path, "material name longer than %zu characters",
		                     sizeof m->name - 1);
	snprintf(m->name, sizeof m->name, "%s", name);
	double n[3] = {0}, k[3] = {0, 0, 0}, sigma = 0;
	if ((rc = get_num_rgb(c, v, path, "n", PC_JSON_REQUIRED, 0, true, 100, n)) ||
	    (rc = get_num_rgb(c, v, path, "k", PC_JSON_OPTIONAL, 0, false, 100, k)) ||
	    (rc = pc_json_get_num(&c->js, v, path, "sigma", PC_JSON_REQUIRED, 0, true, 10, &sigma)))
		return rc;
	pc_diffuse diffuse = PC_DIFFUSE_FRESNEL;
	pc_shadowing shadow = PC_SHADOW_TS;
	pc_rho_mode rho = PC_RHO_TABLE;
	long order = 0;
	static const pc_scene_keyword diffuses[] = {{"fresnel", PC_DIFFUSE_FRESNEL},
	                                            {"geometric", PC_DIFFUSE_GEOMETRIC},
	                                            {"none", PC_DIFFUSE_NONE},
	                                            {NULL, 0}};
	static const pc_scene_keyword shadowings[] = {
	    {"ts", PC_SHADOW_TS}, {"none", PC_SHADOW_NONE}, {NULL, 0}};
	static const pc_scene_keyword rhos[] = {
	    {"table", PC_RHO_TABLE}, {"quad", PC_RHO_QUAD}, {NULL, 0}};
	int e;
	if ((rc = get_enum(c, v, path, "diffuse", diffuses, "fresnel, geometric or none", &e)))
		return rc;
	diffuse = e < 0 ? diffuse : (pc_diffuse)e;
	if ((rc = get_enum(c, v, path, "shadowing", shadowings, "ts (Torrance-Sparrow) or none",
	                   &e)))
		return rc;
	shadow = e < 0 ? shadow : (pc_shadowing)e;
	if ((rc = get_enum(c, v, path, "rho", rhos, "table or quad", &e)))
		return rc;
	rho = e < 0 ? rho : (pc_rho_mode)e;
	if ((rc = pc_json_get_int(&c->js, v, path, "rho_order", PC_JSON_OPTIONAL, 2, 256, &order)))
		return rc;
	/* The global switches (effects.diffuse / effects.shadowing) win over the material. */
	if (!(c->scene->effects & PC_FX_DIFFUSE))
		diffuse = PC_DIFFUSE_NONE;
	if (!(c->scene->effects & PC_FX_SHADOWING))
		shadow = PC_SHADOW_NONE;
	for (int ch = 0; ch < PC_SIM_MAX_CH; ch++) {
		/* monochrome sensors use the green value of an RGB triple */
		int src = c->colour ? ch : 1;
		m->m[ch].n = n[src];
		m->m[ch].k = k[src];
		m->m[ch].sigma = sigma;
		m->m[ch].diffuse = diffuse;
		m->m[ch].shadowing = shadow;
		m->m[ch].rho_mode = rho;
		m->m[ch].rho_order = (int)order;
	}
	return 0;
}

static int parse_states(const pctx *c, json_t *arr, const char *path, unsigned *n, double S[][4])
{
	if (!json_is_array(arr) || json_array_size(arr) == 0)
		return pc_json_error(&c->js, path,
		                     "expected a non-empty array of polarization states");
	if (json_array_size(arr) > PC_SIM_MAX_STATES)
		return pc_json_error(&c->js, path, "%zu states: at most %d", json_array_size(arr),
		                     PC_SIM_MAX_STATES);
	for (size_t i = 0; i < json_array_size(arr); i++) {
		char p[256];
		pc_json_path_index(p, sizeof p, path, i);
		int rc = parse_pol(c, json_array_get(arr, i), p, S[i]);
		if (rc)
			return rc;
	}
	*n = (unsigned)json_array_size(arr);
	return 0;
}

static int parse_light(const pctx *c, json_t *v, const char *path, pc_sim_light *l)
{
	static const char *const keys[] = {"type",
	                                   "direction",
	                                   "position",
	                                   "irradiance_w_m2",
	                                   "intensity_w_sr",
	                                   "polarization",
	                                   "reference",
	                                   "states",
	                                   NULL};
	int rc;
	if ((rc = pc_json_need_object(&c->js, v, path)) ||
	    (rc = pc_json_check_keys(&c->js, v, path, keys)))
		return rc;
	const char *type = NULL;
	if ((rc = pc_json_get_str(&c->js, v, path, "type", PC_JSON_REQUIRED, &type)))
		return rc;
	char p[256];
	if (!strcmp(type, "directional")) {
		l->type = PC_LIGHT_DIRECTIONAL;
		if ((rc = get_unit_v3(c, v, path, "direction", PC_JSON_REQUIRED, &l->direction)) ||
		    (rc = get_num_rgb(c, v, path, "irradiance_w_m2", PC_JSON_REQUIRED, 0, false,
		                      1e12, l->power)))
			return rc;
		if (json_object_get(v, "position") || json_object_get(v, "intensity_w_sr"))
			return pc_json_error(
			    &c->js, path,
			    "a directional light has direction and irradiance_w_m2 "
			    "(position and intensity_w_sr are for point lights)");
	} else if (!strcmp(type, "point")) {
		l->type = PC_LIGHT_POINT;
		if ((rc = get_v3(c, v, path, "position", PC_JSON_REQUIRED, &l->position)) ||
		    (rc = get_num_rgb(c, v, path, "intensity_w_sr", PC_JSON_REQUIRED, 0, false,
		                      1e15, l->power)))
			return rc;
		if (json_object_get(v, "direction") || json_object_get(v, "irradiance_w_m2"))
			return pc_json_error(
			    &c->js, path,
			    "a point light has position and intensity_w_sr "
			    "(direction and irradiance_w_m2 are for directional lights)");
	} else {
		pc_json_path(p, sizeof p, path, "type");
		return pc_json_error(&c->js, p, "'%s': expected directional or point", type);
	}
	/* monochrome sensors use the green value of an RGB triple, as for materials and the
	 * background (the shader reads power[0] of a monochrome frame) */
	if (!c->colour)
		l->power[0] = l->power[2] = l->power[1];
	if (json_object_get(v, "reference")) {
		if ((rc = get_unit_v3(c, v, path, "reference", PC_JSON_REQUIRED, &l->reference)))
			return rc;
		l->has_reference = true;
	}
	json_t *pol = json_object_get(v, "polarization");
	json_t *states = json_object_get(v, "states");
	if (pol && states)
		return pc_json_error(
		    &c->js, path, "give polarization (one state) or states (a sequence), not both");
	l->n_states = 1;
	l->stokes[0][0] = 1;
	if (pol) {
		pc_json_path(p, sizeof p, path, "polarization");
		if ((rc = parse_pol(c, pol, p, l->stokes[0])))
			return rc;
	} else if (states) {
		pc_json_path(p, sizeof p, path, "states");
		if ((rc = parse_states(c, states, p, &l->n_states, l->stokes)))
			return rc;
	}
	if (!(c->scene->effects & PC_FX_CIRCULAR))
		for (unsigned i = 0; i < l->n_states; i++)
			if (fabs(l->stokes[i][3]) > 1e-12) {
				pc_json_path(p, sizeof p, path, pol ? "polarization" : "states");
				return pc_json_error(&c->js, p,
				                     "has a circular component (S3 = %g): declare "
				                     "\"circular\": true in effects",
				                     l->stokes[i][3]);
			}
	return 0;
}

static int parse_object(const pctx *c, json_t *v, const char *path, pc_sim_object *o)
{
	static const char *const keys[] = {
	    "type",   "material",     "point", "normal",   "size",  "u_axis", "center",
	    "radius", "rotation_deg", "file",  "position", "scale", "smooth", NULL};
	int rc;
	if ((rc = pc_json_need_object(&c->js, v, path)) ||
	    (rc = pc_json_check_keys(&c->js, v, path, keys)))
		return rc;
	const char *type = NULL, *mat = NULL;
	if ((rc = pc_json_get_str(&c->js, v, path, "type", PC_JSON_REQUIRED, &type)) ||
	    (rc = pc_json_get_str(&c->js, v, path, "material", PC_JSON_REQUIRED, &mat)))
		return rc;
	char p[256];
	bool found = false;
	for (unsigned i = 0; i < c->scene->n_materials; i++)
		if (!strcmp(c->scene->materials[i].name, mat)) {
			o->material = i;
			found = true;
		}
	if (!found) {
		pc_json_path(p, sizeof p, path, "material");
		return pc_json_error(&c->js, p, "'%s' is not defined in materials", mat);
	}
	/* which fields each type takes */
	static const struct {
		const char *type;
		const char *fields;
	} allowed[] = {{"plane", " point normal size u_axis "},
	               {"sphere", " center radius "},
	               {"box", " center size rotation_deg "},
	               {"mesh", " file position scale rotation_deg smooth "}};
	int ti = -1;
	for (int i = 0; i < 4; i++)
		if (!strcmp(type, allowed[i].type))
			ti = i;
	if (ti < 0) {
		pc_json_path(p, sizeof p, path, "type");
		return pc_json_error(&c->js, p, "'%s': expected plane, sphere, box or mesh", type);
	}
	const char *key;
	json_t *val;
	json_object_foreach(v, key, val)
	{
		if (!strcmp(key, "type") || !strcmp(key, "material"))
			continue;
		char pat[40];
		snprintf(pat, sizeof pat, " %s ", key);
		if (!strstr(allowed[ti].fields, pat)) {
			pc_json_path(p, sizeof p, path, key);
			return pc_json_error(&c->js, p, "not a field of a %s (its fields:%s)", type,
			                     allowed[ti].fields);
		}
	}
	double rot_deg[3] = {0, 0, 0};
	switch (ti) {
	case 0: { /* plane */
		o->type = PC_OBJ_PLANE;
		o->n = v3(0, 0, 1);
		if ((rc = get_v3(c, v, path, "point", PC_JSON_REQUIRED, &o->p)) ||
		    (rc = get_unit_v3(c, v, path, "normal", PC_JSON_REQUIRED, &o->n)))
			return rc;
		o->u = v3_any_perp(o->n);
		if (json_object_get(v, "u_axis")) {
			pc_v3 u = o->u;
			if ((rc = get_v3(c, v, path, "u_axis", PC_JSON_REQUIRED, &u)))
				return rc;
			o->u = v3_perp_unit(u, o->n, v3(0, 0, 0));
			if (v3_len(o->u) == 0) {
				pc_json_path(p, sizeof p, path, "u_axis");
				return pc_json_error(&c->js, p, "is parallel to the normal");
			}
		}
		o->v = v3_cross(o->n, o->u);
		if (json_object_get(v, "size")) {
			double sz[2];
			if ((rc = pc_json_get_nums(&c->js, v, path, "size", PC_JSON_REQUIRED, sz,
			                           2)))
				return rc;
			if (!(sz[0] > 0 && sz[1] > 0)) {
				pc_json_path(p, sizeof p, path, "size");
				return pc_json_error(
				    &c->js, p,
				    "must be two positive lengths [along u_axis, along "
				    "normal × u_axis] (omit it for an infinite plane)");
			}
			o->half_u = sz[0] / 2;
			o->half_v = sz[1] / 2;
		}
		break;
	}
	case 1: /* sphere */
		o->type = PC_OBJ_SPHERE;
		if ((rc = get_v3(c, v, path, "center", PC_JSON_REQUIRED, &o->center)) ||
		    (rc = pc_json_get_num(&c->js, v, path, "radius", PC_JSON_REQUIRED, 0, true,
		                          INFINITY, &o->radius)))
			return rc;
		break;
	case 2: { /* box */
		o->type = PC_OBJ_BOX;
		double sz[3];
		if ((rc = get_v3(c, v, path, "center", PC_JSON_REQUIRED, &o->center)) ||
		    (rc = pc_json_get_nums(&c->js, v, path, "size", PC_JSON_REQUIRED, sz, 3)) ||
		    (rc = pc_json_get_nums(&c->js, v, path, "rotation_deg", PC_JSON_OPTIONAL,
		                           rot_deg, 3)))
			return rc;
		if (!(sz[0] > 0 && sz[1] > 0 && sz[2] > 0)) {
			pc_json_path(p, sizeof p, path, "size");
			return pc_json_error(&c->js, p, "must be three positive edge lengths");
		}
		o->half = v3(sz[0] / 2, sz[1] / 2, sz[2] / 2);
		o->rot = m3_from_euler_deg(rot_deg);
		break;
	}
	default: { /* mesh */
		o->type = PC_OBJ_MESH;
		const char *file = NULL;
		pc_v3 pos = v3(0, 0, 0), scale = v3(1, 1, 1);
		bool smooth = true;
		if ((rc = pc_json_get_str(&c->js, v, path, "file", PC_JSON_REQUIRED, &file)) ||
		    (rc = get_v3(c, v, path, "position", PC_JSON_OPTIONAL, &pos)) ||
		    (rc = pc_json_get_nums(&c->js, v, path, "rotation_deg", PC_JSON_OPTIONAL,
		                           rot_deg, 3)) ||
		    (rc = pc_json_get_bool(&c->js, v, path, "smooth", PC_JSON_OPTIONAL, &smooth)))
			return rc;
		json_t *sc = json_object_get(v, "scale");
		if (sc && json_is_number(sc)) {
			double s;
			if ((rc = pc_json_get_num(&c->js, v, path, "scale", PC_JSON_REQUIRED, 0,
			                          true, INFINITY, &s)))
				return rc;
			scale = v3(s, s, s);
		} else if (sc) {
			if ((rc = get_v3(c, v, path, "scale", PC_JSON_REQUIRED, &scale)))
				return rc;
			if (!(scale.x > 0 && scale.y > 0 && scale.z > 0)) {
				pc_json_path(p, sizeof p, path, "scale");
				return pc_json_error(&c->js, p, "must be positive");
			}
		}
		char full[4096];
		if (file[0] == '/' || !c->base_dir)
			snprintf(full, sizeof full, "%s", file);
		else
			snprintf(full, sizeof full, "%s/%s", c->base_dir, file);
		pc_m3 rot = m3_from_euler_deg(rot_deg);
		rc = pc_obj_load(full, &rot, scale, pos, smooth, &o->mesh);
		if (rc) {
			pc_json_path(p, sizeof p, path, "file");
			return pc_error_prefix(rc, "%s: %s: ", c->js.file, p);
		}
		if ((rc = pc_bvh_build(o->mesh)))
			return rc;
		break;
	}
	}
	return 0;
}

/* ---- effects ---- */

static const char *const pc_fx_names[PC_FX_COUNT_] = {
    "diffuse",      "shadowing", "cast_shadows", "supersampling",    "circular",
    "mueller",      "noise",     "prnu_dsnu",    "extinction_ratio", "orientation_error",
    "transmission", "crosstalk", "blur",
};

const char *pc_sim_effect_name(unsigned effect_bit)
{
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (effect_bit == 1u << i)
			return pc_fx_names[i];
	return NULL;
}

unsigned pc_sim_effect_from_name(const char *name)
{
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (!strcmp(name, pc_fx_names[i]))
			return 1u << i;
	return 0;
}

#define PC_FX_SENSOR_MASK                                                                          \
	(PC_FX_NOISE | PC_FX_PRNU_DSNU | PC_FX_EXTINCTION | PC_FX_ORIENTATION |                    \
	 PC_FX_TRANSMISSION | PC_FX_CROSSTALK)

static int parse_effects(const pctx *c, json_t *v, unsigned preset_fx, unsigned *fx, unsigned *ss,
                         double *blur)
{
	const char *P = "effects";
	*fx = preset_fx & PC_FX_SENSOR_MASK;
	*ss = 1;
	*blur = 0;
	if (!v)
		return 0;
	int rc = pc_json_need_object(&c->js, v, P);
	if (rc)
		return rc;
	const char *key;
	json_t *val;
	json_object_foreach(v, key, val)
	{
		char p[256];
		pc_json_path(p, sizeof p, P, key);
		unsigned bit = pc_sim_effect_from_name(key);
		if (!bit) {
			char list[512] = "";
			for (unsigned i = 0; i < PC_FX_COUNT_; i++) {
				strncat(list, pc_fx_names[i], sizeof list - strlen(list) - 1);
				if (i + 1 < PC_FX_COUNT_)
					strncat(list, ", ", sizeof list - strlen(list) - 1);
			}
			return pc_json_error(&c->js, p, "unknown effect (expected one of: %s)",
			                     list);
		}
		if (bit == PC_FX_SUPERSAMPLING && json_is_integer(val)) {
			json_int_t n = json_integer_value(val);
			if (n < 1 || n > 16)
				return pc_json_error(
				    &c->js, p, "= %lld: samples per pixel side must be in [1, 16]",
				    (long long)n);
			*ss = (unsigned)n;
			if (n > 1)
				*fx |= bit;
			else
				*fx &= ~bit;
			continue;
		}
		if (bit == PC_FX_BLUR) {
			/* the PSF's σ in pixels, or false */
			if (json_is_false(val)) {
				*fx &= ~bit;
				continue;
			}
			if (!json_is_number(val))
				return pc_json_error(
				    &c->js, p,
				    "expected the point-spread function's sigma in "
				    "pixels (a number in [%g, %g]) or false, got %s",
				    PC_BLUR_SIGMA_MIN, PC_BLUR_SIGMA_MAX, pc_json_kind(val));
			double sg = json_number_value(val);
			if (!(sg >= PC_BLUR_SIGMA_MIN && sg <= PC_BLUR_SIGMA_MAX))
				return pc_json_error(
				    &c->js, p,
				    "= %g: the point-spread function's sigma must be in "
				    "[%g, %g] pixels",
				    sg, PC_BLUR_SIGMA_MIN, PC_BLUR_SIGMA_MAX);
			*blur = sg;
			*fx |= bit;
			continue;
		}
		if (!json_is_boolean(val))
			return pc_json_error(
			    &c->js, p, "expected true or false%s, got %s",
			    bit == PC_FX_SUPERSAMPLING ? " or samples per pixel side (1-16)" : "",
			    pc_json_kind(val));
		if (json_is_true(val)) {
			*fx |= bit;
			if (bit == PC_FX_SUPERSAMPLING)
				*ss = 2;
		} else {
			*fx &= ~bit;
		}
	}
	return 0;
}

/* ---- sensor ---- */

static int parse_sensor(const pctx *c, json_t *v, pc_sensor_figures *f)
{
	static const char *const keys[] = {"preset",
	                                   "resolution",
	                                   "pixel_pitch_um",
	                                   "bits",
	                                   "qe",
	                                   "wavelength_nm",
	                                   "full_well_e",
	                                   "read_noise_e",
	                                   "dark_current_e_s",
	                                   "dsnu_e",
	                                   "prnu",
	                                   "gain_dn_per_e",
	                                   "offset_dn",
	                                   "extinction_ratio",
	                                   "extinction_ratio_sigma",
	                                   "orientation_sigma_deg",
	                                   "orientation_offset_deg",
	                                   "transmission_sigma",
	                                   "transmission",
	                                   "crosstalk",
	                                   "exposure_us",
	                                   "gain_db",
	                                   "frame_rate_hz",
	                                   "layout",
	                                   "psa",
	                                   NULL};
	const char *P = "sensor";
	int rc;
	const char *preset = "ideal";
	if (v) {
		if ((rc = pc_json_need_object(&c->js, v, P)) ||
		    (rc = pc_json_check_keys(&c->js, v, P, keys)) ||
		    (rc = pc_json_get_str(&c->js, v, P, "preset", PC_JSON_OPTIONAL, &preset)))
			return rc;
	}
	if (pc_sensor_preset(preset, f)) {
		const char *const *names = pc_sensor_preset_names();
		char list[256] = "";
		for (; *names; names++) {
			strncat(list, *names, sizeof list - strlen(list) - 1);
			if (names[1])
				strncat(list, ", ", sizeof list - strlen(list) - 1);
		}
		return pc_json_error(&c->js, "sensor.preset", "'%s': expected one of %s", preset,
		                     list);
	}
	if (!v)
		return 0;
	double res[2] = {f->width, f->height};
	long bits = f->bits;
	if ((rc = pc_json_get_nums(&c->js, v, P, "resolution", PC_JSON_OPTIONAL, res, 2)))
		return rc;
	if (res[0] != floor(res[0]) || res[1] != floor(res[1]) || res[0] < 2 || res[1] < 2 ||
	    res[0] > 65535 || res[1] > 65535 || fmod(res[0], f->mosaic.period) != 0 ||
	    fmod(res[1], f->mosaic.period) != 0)
		return pc_json_error(&c->js, "sensor.resolution",
		                     "[%g, %g]: expected two integers in [2, 65535], "
		                     "multiples of the mosaic period %u",
		                     res[0], res[1], f->mosaic.period);
	{
		/* the frame, its per-state caches and the truth are all this size: the same pixel
		 * limit as an image file (polarcam/limits.h), checked before anything is allocated
		 */
		char what[600];
		snprintf(what, sizeof what, "%s: sensor.resolution [%g, %g]", c->js.file, res[0],
		         res[1]);
		if ((rc = pc_limit_check(PC_LIMIT_PIXELS, (uint64_t)(res[0] * res[1]), what)))
			return rc;
	}
	f->width = (uint32_t)res[0];
	f->height = (uint32_t)res[1];
	if ((rc = pc_json_get_num(&c->js, v, P, "pixel_pitch_um", PC_JSON_OPTIONAL, 0, true, 1000,
	                          &f->pixel_pitch_um)) ||
	    (rc = pc_json_get_int(&c->js, v, P, "bits", PC_JSON_OPTIONAL, 8, 16, &bits)))
		return rc;
	if (bits != 8 && bits != 10 && bits != 12 && bits != 16)
		return pc_json_error(&c->js, "sensor.bits", "= %ld: expected 8, 10, 12 or 16",
		                     bits);
	f->bits = (unsigned)bits;
	if ((rc = get_num_rgb(c, v, P, "qe", PC_JSON_OPTIONAL, 0, true, 1, f->qe)) ||
	    (rc = get_num_rgb(c, v, P, "wavelength_nm", PC_JSON_OPTIONAL, 100, false, 20000,
	                      f->wavelength_nm)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "full_well_e", PC_JSON_OPTIONAL, 1, false, 1e9,
	                          &f->full_well_e)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "read_noise_e", PC_JSON_OPTIONAL, 0, false, 1e6,
	                          &f->read_noise_e)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "dark_current_e_s", PC_JSON_OPTIONAL, 0, false, 1e9,
	                          &f->dark_current_e_s)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "dsnu_e", PC_JSON_OPTIONAL, 0, false, 1e6,
	                          &f->dsnu_e)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "prnu", PC_JSON_OPTIONAL, 0, false, 0.5,
	                          &f->prnu)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "gain_dn_per_e", PC_JSON_OPTIONAL, 0, true, 1e6,
	                          &f->gain_dn_per_e)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "offset_dn", PC_JSON_OPTIONAL, 0, false, 65535,
	                          &f->offset_dn)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "extinction_ratio", PC_JSON_OPTIONAL, 1, true,
	                          INFINITY, &f->extinction_ratio)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "extinction_ratio_sigma", PC_JSON_OPTIONAL, 0,
	                          false, 2, &f->extinction_ratio_sigma)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "orientation_sigma_deg", PC_JSON_OPTIONAL, 0, false,
	                          45, &f->orientation_sigma_deg)) ||
	    (rc = pc_json_get_nums(&c->js, v, P, "orientation_offset_deg", PC_JSON_OPTIONAL,
	                           f->orientation_offset_deg, 4)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "transmission_sigma", PC_JSON_OPTIONAL, 0, false,
	                          0.5, &f->transmission_sigma)) ||
	    (rc = pc_json_get_nums(&c->js, v, P, "transmission", PC_JSON_OPTIONAL, f->transmission,
	                           4)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "crosstalk", PC_JSON_OPTIONAL, 0, false, 0.2,
	                          &f->crosstalk)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "exposure_us", PC_JSON_OPTIONAL, 0, true, 1e9,
	                          &f->exposure_us)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "gain_db", PC_JSON_OPTIONAL, 0, false, 60,
	                          &f->gain_db)) ||
	    (rc = pc_json_get_num(&c->js, v, P, "frame_rate_hz", PC_JSON_OPTIONAL, 0, true, 1e6,
	                          &f->frame_rate_hz)))
		return rc;
	for (int i = 0; i < 4; i++) {
		if (fabs(f->orientation_offset_deg[i]) > 45)
			return pc_json_error(&c->js, "sensor.orientation_offset_deg",
			                     "[%d] = %g: must be within "
			                     "±45°",
			                     i, f->orientation_offset_deg[i]);
		if (!(f->transmission[i] > 0 && f->transmission[i] <= 2))
			return pc_json_error(&c->js, "sensor.transmission",
			                     "[%d] = %g: must be in (0, 2]", i, f->transmission[i]);
	}
	const char *layout = NULL;
	if ((rc = pc_json_get_str(&c->js, v, P, "layout", PC_JSON_OPTIONAL, &layout)))
		return rc;
	if (layout) {
		/* "90,45,135,0" (monochrome), "RGGB:90,45,135,0" (colour), optional "@dx,dy" phase
		 */
		if ((rc = pc_mosaic_parse(layout, &f->mosaic)))
			return pc_error_prefix(rc, "%s: sensor.layout: ", c->js.file);
		if (f->width % f->mosaic.period || f->height % f->mosaic.period)
			return pc_json_error(&c->js, "sensor.layout",
			                     "period %u does not divide the resolution "
			                     "%ux%u",
			                     f->mosaic.period, f->width, f->height);
	}
	return 0;
}

/* One element in front of the camera (a PSA state): "none", {"retarder": {...}},
 * {"polarizer_deg": α}, {"diattenuator": {"angle_deg", "diattenuation"}}, {"mueller": [[4×4]]}
 * or {"chain": [element, ...]} (light passes the first element first). */
static int parse_element(const pctx *c, json_t *e, const char *p, double m[4][4], int depth)
{
	memset(m, 0, sizeof(double) * 16);
	if (json_is_string(e) && !strcmp(json_string_value(e), "none")) {
		for (int k = 0; k < 4; k++)
			m[k][k] = 1;
		return 0;
	}
	static const char *const keys[] = {"retarder",     "mueller", "polarizer_deg",
	                                   "diattenuator", "chain",   NULL};
	int rc;
	if ((rc = pc_json_need_object(&c->js, e, p)) ||
	    (rc = pc_json_check_keys(&c->js, e, p, keys)))
		return rc;
	json_t *r = json_object_get(e, "retarder"), *mm = json_object_get(e, "mueller");
	json_t *pol = json_object_get(e, "polarizer_deg"), *di = json_object_get(e, "diattenuator");
	json_t *ch = json_object_get(e, "chain");
	if (!!r + !!mm + !!pol + !!di + !!ch != 1)
		return pc_json_error(&c->js, p,
		                     "give exactly one of retarder, polarizer_deg, diattenuator, "
		                     "mueller or chain");
	char q[288];
	if (r) {
		pc_json_path(q, sizeof q, p, "retarder");
		return parse_retarder(c, r, q, m);
	}
	if (pol) {
		double a = 0;
		if ((rc = pc_json_get_num(&c->js, e, p, "polarizer_deg", PC_JSON_REQUIRED, -360,
		                          false, 360, &a)))
			return rc;
		pc_diattenuator_mueller(a * DEG, 1, m);
		return 0;
	}
	if (di) {
		static const char *const dkeys[] = {"angle_deg", "diattenuation", NULL};
		pc_json_path(q, sizeof q, p, "diattenuator");
		double a = 0, D = 0;
		if ((rc = pc_json_need_object(&c->js, di, q)) ||
		    (rc = pc_json_check_keys(&c->js, di, q, dkeys)) ||
		    (rc = pc_json_get_num(&c->js, di, q, "angle_deg", PC_JSON_REQUIRED, -360, false,
		                          360, &a)) ||
		    (rc = pc_json_get_num(&c->js, di, q, "diattenuation", PC_JSON_REQUIRED, 0,
		                          false, 1, &D)))
			return rc;
		pc_diattenuator_mueller(a * DEG, D, m);
		return 0;
	}
	if (ch) {
		pc_json_path(q, sizeof q, p, "chain");
		if (!json_is_array(ch) || json_array_size(ch) == 0 || json_array_size(ch) > 16)
			return pc_json_error(&c->js, q, "expected an array of 1 to 16 elements");
		if (depth > 4)
			return pc_json_error(&c->js, q, "chains nested deeper than 4");
		double acc[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
		for (size_t i = 0; i < json_array_size(ch); i++) {
			char qi[300];
			pc_json_path_index(qi, sizeof qi, q, i);
			double el[4][4], t[4][4];
			if ((rc = parse_element(c, json_array_get(ch, i), qi, el, depth + 1)))
				return rc;
			pc_mueller_mul(el, acc, t); /* the later element acts after the earlier */
			memcpy(acc, t, sizeof acc);
		}
		memcpy(m, acc, sizeof acc);
		return 0;
	}
	pc_json_path(q, sizeof q, p, "mueller");
	if (!json_is_array(mm) || json_array_size(mm) != 4)
		return pc_json_error(&c->js, q, "expected 4 rows of 4 numbers");
	for (int row = 0; row < 4; row++) {
		char qr[300];
		pc_json_path_index(qr, sizeof qr, q, (size_t)row);
		json_t *rr = json_array_get(mm, (size_t)row);
		if (!json_is_array(rr) || json_array_size(rr) != 4)
			return pc_json_error(&c->js, qr, "expected 4 numbers");
		for (int col = 0; col < 4; col++) {
			json_t *x = json_array_get(rr, (size_t)col);
			if (!json_is_number(x) || !isfinite(json_number_value(x)))
				return pc_json_error(&c->js, qr, "[%d]: expected a finite number",
				                     col);
			m[row][col] = json_number_value(x);
		}
	}
	return 0;
}

static int parse_psa(const pctx *c, json_t *v, pc_scene *s)
{
	const char *P = "sensor.psa";
	if (!json_is_array(v) || json_array_size(v) == 0)
		return pc_json_error(
		    &c->js, P,
		    "expected a non-empty array of analyser states (\"none\", "
		    "{\"retarder\": {...}}, {\"polarizer_deg\": a}, {\"diattenuator\": "
		    "{...}}, {\"mueller\": [[4×4]]} or {\"chain\": [...]})");
	if (json_array_size(v) > PC_SIM_MAX_STATES)
		return pc_json_error(&c->js, P, "at most %d states", PC_SIM_MAX_STATES);
	for (size_t i = 0; i < json_array_size(v); i++) {
		char p[256];
		pc_json_path_index(p, sizeof p, P, i);
		int rc = parse_element(c, json_array_get(v, i), p, s->psa[i], 0);
		if (rc)
			return rc;
	}
	s->n_psa = (unsigned)json_array_size(v);
	s->psa_declared = true;
	return 0;
}

/* ---- the document ---- */

static void scene_destroy(pc_scene *s)
{
	if (!s)
		return;
	for (unsigned i = 0; i < s->n_objects; i++)
		if (s->objects[i].mesh)
			pc_mesh_free(s->objects[i].mesh);
	free(s->objects);
	free(s->lights);
	free(s->materials);
	free(s->name);
	free(s->source);
	free(s->json_text);
	free(s);
}

void pc_scene_ref(pc_scene *s)
{
	atomic_fetch_add_explicit((_Atomic int *)&s->refcount, 1, memory_order_relaxed);
}

void pc_scene_free(pc_scene *s)
{
	if (!s)
		return;
	if (atomic_fetch_sub_explicit((_Atomic int *)&s->refcount, 1, memory_order_acq_rel) == 1)
		scene_destroy(s);
}

static void object_bounds(pc_sim_object *o)
{
	const double inf = INFINITY;
	switch (o->type) {
	case PC_OBJ_SPHERE:
		o->bmin = v3_sub(o->center, v3(o->radius, o->radius, o->radius));
		o->bmax = v3_add(o->center, v3(o->radius, o->radius, o->radius));
		break;
	case PC_OBJ_BOX: {
		/* world extent of the rotated box: |R|ᵀ·half per axis (rot maps local→world) */
		pc_v3 e;
		double h[3] = {o->half.x, o->half.y, o->half.z};
		double ext[3];
		for (int i = 0; i < 3; i++)
			ext[i] = fabs(o->rot.m[i][0]) * h[0] + fabs(o->rot.m[i][1]) * h[1] +
			         fabs(o->rot.m[i][2]) * h[2];
		e = v3(ext[0], ext[1], ext[2]);
		o->bmin = v3_sub(o->center, e);
		o->bmax = v3_add(o->center, e);
		break;
	}
	case PC_OBJ_PLANE:
		if (o->half_u > 0) {
			pc_v3 a = v3_scale(o->u, o->half_u), b = v3_scale(o->v, o->half_v);
			pc_v3 e =
			    v3(fabs(a.x) + fabs(b.x), fabs(a.y) + fabs(b.y), fabs(a.z) + fabs(b.z));
			o->bmin = v3_sub(o->p, e);
			o->bmax = v3_add(o->p, e);
		} else {
			o->bmin = v3(-inf, -inf, -inf);
			o->bmax = v3(inf, inf, inf);
		}
		break;
	default:
		break; /* meshes: set by the BVH builder */
	}
}

int pc_scene_parse(const char *text, const char *name, const char *base_dir, pc_scene **out)
{
	*out = NULL;
	if (!text)
		return pc_error(PC_EINVAL, "scene text is NULL");
	if (!name)
		name = "<scene>";
	json_error_t jerr;
	json_t *doc = json_loads(text, JSON_REJECT_DUPLICATES, &jerr);
	if (!doc)
		return pc_error(PC_EFORMAT, "%s: line %d, column %d: %s", name, jerr.line,
		                jerr.column, jerr.text);
	pc_scene *s = calloc(1, sizeof *s);
	if (!s) {
		json_decref(doc);
		return pc_error(PC_ENOMEM, "%s: scene", name);
	}
	s->refcount = 1;
	pctx c = {{name, PC_EINVAL}, base_dir ? base_dir : ".", s, false};
	int rc = 0;
	static const char *const keys[] = {"polarcam_scene", "name",    "camera",  "lights",
	                                   "materials",      "objects", "effects", "sensor",
	                                   "background",     NULL};
	if ((rc = pc_json_need_object(&c.js, doc, "")) ||
	    (rc = pc_json_check_keys(&c.js, doc, "", keys)))
		goto fail;
	long version = 1;
	if ((rc = pc_json_get_int(&c.js, doc, "", "polarcam_scene", PC_JSON_OPTIONAL, 1, 1,
	                          &version)))
		goto fail;
	const char *sname = NULL;
	if ((rc = pc_json_get_str(&c.js, doc, "", "name", PC_JSON_OPTIONAL, &sname)))
		goto fail;
	s->name = strdup(sname ? sname : name);
	s->source = strdup(name);
	s->json_text = json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(17));
	if (!s->name || !s->source || !s->json_text) {
		rc = pc_error(PC_ENOMEM, "%s: scene", name);
		goto fail;
	}
	/* the sensor first: its preset declares sensor effects and whether it is colour */
	if ((rc = parse_sensor(&c, json_object_get(doc, "sensor"), &s->sensor)))
		goto fail;
	c.colour = s->sensor.mosaic.period == 4;
	if ((rc = parse_effects(&c, json_object_get(doc, "effects"), s->sensor.effects, &s->effects,
	                        &s->supersampling, &s->blur_sigma)))
		goto fail;
	s->sensor.effects = s->effects & PC_FX_SENSOR_MASK;
	json_t *psa = json_object_get(json_object_get(doc, "sensor"), "psa");
	s->n_psa = 1;
	for (int k = 0; k < 4; k++)
		s->psa[0][k][k] = 1;
	if (psa) {
		if ((rc = parse_psa(&c, psa, s)))
			goto fail;
		if (!(s->effects & PC_FX_CIRCULAR))
			for (unsigned i = 0; i < s->n_psa; i++)
				for (int k = 0; k < 3; k++) /* M33 alone couples nothing */
					if (fabs(s->psa[i][3][k]) > 1e-12 ||
					    fabs(s->psa[i][k][3]) > 1e-12) {
						rc = pc_json_error(
						    &c.js, "sensor.psa",
						    "state %u couples circular "
						    "polarization: declare \"circular\": true "
						    "in effects",
						    i);
						goto fail;
					}
	}
	double bg[3] = {0, 0, 0};
	if ((rc = get_num_rgb(&c, doc, "", "background", PC_JSON_OPTIONAL, 0, false, 1e12, bg)))
		goto fail;
	for (int i = 0; i < 3; i++)
		s->background[i] = c.colour ? bg[i] : bg[1];

	json_t *cam = json_object_get(doc, "camera");
	if (!cam) {
		rc = pc_json_error(&c.js, "camera", "missing (required)");
		goto fail;
	}
	if ((rc = parse_camera(&c, cam, &s->camera)))
		goto fail;

	json_t *mats = json_object_get(doc, "materials");
	if (!mats || !json_is_object(mats) || json_object_size(mats) == 0) {
		rc = pc_json_error(&c.js, "materials",
		                   mats ? "expected an object of named materials, got %s"
		                        : "missing (required): an object of named materials%s",
		                   mats ? pc_json_kind(mats) : "");
		goto fail;
	}
	s->materials = calloc(json_object_size(mats), sizeof *s->materials);
	if (!s->materials) {
		rc = pc_error(PC_ENOMEM, "%s: materials", name);
		goto fail;
	}
	{
		const char *key;
		json_t *val;
		json_object_foreach(mats, key, val)
		{
			char p[256];
			pc_json_path(p, sizeof p, "materials", key);
			if ((rc = parse_material(&c, val, p, key, &s->materials[s->n_materials])))
				goto fail;
			s->n_materials++;
		}
	}

	json_t *lights = json_object_get(doc, "lights");
	if (!lights || !json_is_array(lights) || json_array_size(lights) == 0) {
		rc = pc_json_error(&c.js, "lights", "expected a non-empty array of lights");
		goto fail;
	}
	s->lights = calloc(json_array_size(lights), sizeof *s->lights);
	if (!s->lights) {
		rc = pc_error(PC_ENOMEM, "%s: lights", name);
		goto fail;
	}
	unsigned n_psg = 1;
	for (size_t i = 0; i < json_array_size(lights); i++) {
		char p[64];
		pc_json_path_index(p, sizeof p, "lights", i);
		if ((rc = parse_light(&c, json_array_get(lights, i), p, &s->lights[i])))
			goto fail;
		pc_light_prepare(&s->lights[i]);
		s->n_lights++;
		unsigned n = s->lights[i].n_states;
		if (n > 1) {
			if (n_psg > 1 && n != n_psg) {
				rc = pc_json_error(
				    &c.js, p,
				    "states: %u states, but another light has %u (lights "
				    "with sequences must have equally many)",
				    n, n_psg);
				goto fail;
			}
			n_psg = n;
		}
	}
	if ((uint64_t)n_psg * s->n_psa > 4096) {
		rc = pc_json_error(&c.js, "sensor.psa",
		                   "%u PSG × %u PSA states: at most 4096 frames per cycle", n_psg,
		                   s->n_psa);
		goto fail;
	}

	json_t *objs = json_object_get(doc, "objects");
	json_t *no_objects = NULL;
	if (!objs)
		objs = no_objects =
		    json_array(); /* optional: an empty scene shows the background */
	if (!objs || !json_is_array(objs)) {
		json_decref(no_objects);
		rc = pc_json_error(&c.js, "objects", "expected an array of objects");
		goto fail;
	}
	s->objects = calloc(json_array_size(objs) + 1, sizeof *s->objects);
	if (!s->objects) {
		json_decref(no_objects);
		rc = pc_error(PC_ENOMEM, "%s: objects", name);
		goto fail;
	}
	for (size_t i = 0; i < json_array_size(objs); i++) {
		char p[64];
		pc_json_path_index(p, sizeof p, "objects", i);
		if ((rc = parse_object(&c, json_array_get(objs, i), p, &s->objects[i]))) {
			json_decref(no_objects);
			goto fail;
		}
		object_bounds(&s->objects[i]);
		s->n_objects++;
	}
	json_decref(no_objects);
	json_decref(doc);
	*out = s;
	return 0;
fail:
	json_decref(doc);
	scene_destroy(s);
	return rc;
}

int pc_scene_load(const char *path, pc_scene **out)
{
	*out = NULL;
	if (!path)
		return pc_error(PC_EINVAL, "scene path is NULL");
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO,
		                "%s: cannot open the scene file: %s", path, strerror(errno));
	char *buf = NULL;
	size_t len = 0, cap = 0;
	for (;;) {
		if (len + 4096 + 1 > cap) {
			cap = cap ? cap * 2 : 65536;
			if (cap > ((size_t)64 << 20)) {
				free(buf);
				fclose(fp);
				return pc_error(PC_EFORMAT,
				                "%s: larger than 64 MiB: not a scene file", path);
			}
			char *nb = realloc(buf, cap);
			if (!nb) {
				free(buf);
				fclose(fp);
				return pc_error(PC_ENOMEM, "%s", path);
			}
			buf = nb;
		}
		size_t got = fread(buf + len, 1, cap - len - 1, fp);
		len += got;
		if (got == 0)
			break;
	}
	int err = ferror(fp);
	fclose(fp);
	if (err) {
		free(buf);
		return pc_error(PC_EIO, "%s: read error", path);
	}
	buf[len] = '\0';
	if (strlen(buf) != len) {
		free(buf);
		return pc_error(PC_EFORMAT, "%s: contains NUL bytes: not a JSON scene file", path);
	}
	/* OBJ paths are relative to the scene file's directory */
	char *dir = strdup(path);
	if (!dir) {
		free(buf);
		return pc_error(PC_ENOMEM, "%s", path);
	}
	char *slash = strrchr(dir, '/');
	if (slash)
		*slash = '\0';
	else
		strcpy(dir, ".");
	int rc = pc_scene_parse(buf, path, dir, out);
	free(dir);
	free(buf);
	return rc;
}

const char *pc_scene_name(const pc_scene *scene)
{
	return scene->name;
}

char *pc_scene_to_json(const pc_scene *scene)
{
	return strdup(scene->json_text);
}

unsigned pc_scene_effects(const pc_scene *scene)
{
	return scene->effects;
}

int pc_scene_load_default(pc_scene **out)
{
	return pc_scene_parse(pc_scene_default_text(), "<default scene>", ".", out);
}
