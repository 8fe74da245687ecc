/* sim/family.c - scene families (polarcam/family.h, docs/dataset.md): a spec of distributions,
 * sample i drawn as a scene document, rendered with its truth and an exposure chosen from its own
 * signal. */
#include "polarcam/family.h"

#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/sim.h"
#include "rng.h"
#include "sim_impl.h"

#define DEG        (3.14159265358979323846 / 180.0)
#define MAX_MESHES 64

struct pc_family {
	json_t *spec; /* validated, with the resolution override */
	char *source; /* file name for messages */
	char *base_dir;
	char name[128];
	uint32_t width, height;
	unsigned n_mesh;
	char *mesh_spec[MAX_MESHES], *mesh_path[MAX_MESHES], *mesh_name[MAX_MESHES];
};

/* ---- validation: every error names the spec and the field path ---- */

typedef struct vctx {
	const char *src;
} vctx;

static int verr(const vctx *v, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int verr(const vctx *v, const char *path, const char *fmt, ...)
{
	char msg[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	return pc_error(PC_EINVAL, "%s: %s: %s", v->src, path, msg);
}

static const char *dist_keys[] = {"uniform", "log_uniform", "int", "choice", NULL};

/* A distribution object: exactly one of dist_keys (+ "weights" with "choice"). */
static const char *dist_kind(const json_t *j)
{
	if (!json_is_object(j))
		return NULL;
	for (int i = 0; dist_keys[i]; i++)
		if (json_object_get(j, dist_keys[i]))
			return dist_keys[i];
	return NULL;
}

static int check_weights(const vctx *v, const char *path, const json_t *d, size_t n)
{
	const json_t *w = json_object_get(d, "weights");
	size_t allowed = w ? 2 : 1;
	if (json_object_size(d) != allowed)
		return verr(v, path,
		            "a distribution object has one of \"uniform\", \"log_uniform\", "
		            "\"int\", \"choice\" (with optional \"weights\") and nothing else");
	if (!w)
		return 0;
	if (!json_is_array(w) || json_array_size(w) != n)
		return verr(v, path,
		            "\"weights\" must be an array of %zu positive numbers (one per "
		            "choice)",
		            n);
	double sum = 0;
	for (size_t i = 0; i < n; i++) {
		double x = json_number_value(json_array_get(w, i));
		if (!json_is_number(json_array_get(w, i)) || !(x >= 0) || !isfinite(x))
			return verr(v, path, "weights[%zu] must be a finite number >= 0", i);
		sum += x;
	}
	if (!(sum > 0))
		return verr(v, path, "the weights must not all be 0");
	return 0;
}

/* Numbers: x | [lo, hi] | {"uniform": [lo, hi]} | {"log_uniform": [lo, hi]} |
 * {"int": [lo, hi]} | {"choice": [x, ...], "weights": [...]}; every value in [min, max]. */
static int check_num(const vctx *v, const char *path, const json_t *j, double min, double max)
{
	if (!j)
		return verr(v, path, "missing");
	if (json_is_number(j)) {
		double x = json_number_value(j);
		if (!(x >= min && x <= max))
			return verr(v, path, "%g is outside [%g, %g]", x, min, max);
		return 0;
	}
	const json_t *r = j;
	const char *k = dist_kind(j);
	if (k && !strcmp(k, "choice")) {
		const json_t *c = json_object_get(j, "choice");
		if (!json_is_array(c) || !json_array_size(c))
			return verr(v, path, "\"choice\" must be a non-empty array of numbers");
		for (size_t i = 0; i < json_array_size(c); i++) {
			const json_t *e = json_array_get(c, i);
			if (!json_is_number(e) ||
			    !(json_number_value(e) >= min && json_number_value(e) <= max))
				return verr(v, path, "choice[%zu] must be a number in [%g, %g]", i,
				            min, max);
		}
		return check_weights(v, path, j, json_array_size(c));
	}
	if (k) {
		int rc = check_weights(v, path, j, 0);
		if (rc)
			return rc;
		r = json_object_get(j, k);
	}
	if (!json_is_array(r) || json_array_size(r) != 2 || !json_is_number(json_array_get(r, 0)) ||
	    !json_is_number(json_array_get(r, 1)))
		return verr(v, path,
		            "expected a number, [lo, hi] (uniform), {\"uniform\": [lo, hi]}, "
		            "{\"log_uniform\": [lo, hi]}, {\"int\": [lo, hi]} or "
		            "{\"choice\": [...], \"weights\": [...]}");
	double lo = json_number_value(json_array_get(r, 0)),
	       hi = json_number_value(json_array_get(r, 1));
	if (!(lo <= hi) || !(lo >= min) || !(hi <= max))
		return verr(v, path, "[%g, %g] needs %g <= lo <= hi <= %g", lo, hi, min, max);
	if (k && !strcmp(k, "log_uniform") && !(lo > 0))
		return verr(v, path, "log_uniform needs lo > 0");
	if (k && !strcmp(k, "int") && (lo != floor(lo) || hi != floor(hi)))
		return verr(v, path, "int needs integer bounds");
	return 0;
}

/* Any JSON value, or {"choice": [...], "weights": [...]} of values; each value checked by fn. */
typedef int (*value_check)(const vctx *v, const char *path, const json_t *j);
static int check_any(const vctx *v, const char *path, const json_t *j, value_check fn)
{
	if (!j)
		return verr(v, path, "missing");
	const char *k = dist_kind(j);
	if (k && strcmp(k, "choice"))
		return verr(v, path,
		            "only {\"choice\": [...], \"weights\": [...]} draws a non-number");
	if (k) {
		const json_t *c = json_object_get(j, "choice");
		if (!json_is_array(c) || !json_array_size(c))
			return verr(v, path, "\"choice\" must be a non-empty array");
		for (size_t i = 0; i < json_array_size(c); i++) {
			char p[256];
			int len = snprintf(p, sizeof p, "%s.choice[%zu]", path, i);
			if (len < 0 || (size_t)len >= sizeof p)
				return verr(v, path,
				            "nested too deeply (the field's path is too long)");
			int rc = fn(v, p, json_array_get(c, i));
			if (rc)
				return rc;
		}
		return check_weights(v, path, j, json_array_size(c));
	}
	return fn(v, path, j);
}

static int check_bool(const vctx *v, const char *path, const json_t *j)
{
	return json_is_boolean(j) ? 0 : verr(v, path, "expected true or false");
}

static int check_effect_value(const vctx *v, const char *path, const json_t *j)
{
	const bool blur = strstr(path, "blur") != NULL;
	/* every effect takes false; "blur" takes a sigma, not true (the scene parser refuses it) */
	if (json_is_boolean(j) && !(blur && json_is_true(j)))
		return 0;
	if (strstr(path, "supersampling") && json_is_integer(j) && json_integer_value(j) >= 1 &&
	    json_integer_value(j) <= 16)
		return 0;
	if (blur && json_is_number(j) && json_number_value(j) >= PC_BLUR_SIGMA_MIN &&
	    json_number_value(j) <= PC_BLUR_SIGMA_MAX)
		return 0;
	if (blur)
		return verr(v, path,
		            "expected the point-spread function's sigma in pixels (a number in "
		            "[%g, %g]) or false",
		            PC_BLUR_SIGMA_MIN, PC_BLUR_SIGMA_MAX);
	return verr(v, path,
	            strstr(path, "supersampling") ? "expected true, false or an integer 1..16"
	                                          : "expected true or false");
}

static int check_preset(const vctx *v, const char *path, const json_t *j)
{
	if (json_is_string(j))
		for (const char *const *p = pc_sensor_preset_names(); *p; p++)
			if (!strcmp(*p, json_string_value(j)))
				return 0;
	char list[256] = "";
	for (const char *const *p = pc_sensor_preset_names(); *p; p++)
		snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", *list ? ", " : "",
		         *p);
	return verr(v, path, "expected a sensor preset name (%s)", list);
}

static int check_diffuse(const vctx *v, const char *path, const json_t *j)
{
	const char *s = json_string_value(j);
	if (s && (!strcmp(s, "fresnel") || !strcmp(s, "geometric") || !strcmp(s, "none")))
		return 0;
	return verr(v, path, "expected \"fresnel\", \"geometric\" or \"none\"");
}

static int check_light_type(const vctx *v, const char *path, const json_t *j)
{
	const char *s = json_string_value(j);
	if (s && (!strcmp(s, "directional") || !strcmp(s, "point")))
		return 0;
	return verr(v, path, "expected \"directional\" or \"point\"");
}

static int check_string(const vctx *v, const char *path, const json_t *j)
{
	return json_is_string(j) && *json_string_value(j) ? 0
	                                                  : verr(v, path, "expected a file name");
}

/* Only the listed keys. */
static int check_keys(const vctx *v, const char *path, const json_t *o, const char *const *keys)
{
	if (!json_is_object(o))
		return verr(v, path, "expected an object");
	const char *k;
	json_t *val;
	json_object_foreach((json_t *)o, k, val)
	{
		bool ok = false;
		for (int i = 0; keys[i]; i++)
			ok |= !strcmp(k, keys[i]);
		if (!ok) {
			char list[512] = "";
			for (int i = 0; keys[i]; i++)
				snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
				         i ? ", " : "", keys[i]);
			return verr(v, path, "unknown field \"%s\" (expected one of: %s)", k, list);
		}
	}
	return 0;
}

static int check_vec3(const vctx *v, const char *path, const json_t *j, double min, double max)
{
	if (!json_is_array(j) || json_array_size(j) != 3)
		return verr(v, path, "expected [x, y, z], each a number distribution");
	for (int i = 0; i < 3; i++) {
		char p[256];
		snprintf(p, sizeof p, "%s[%d]", path, i);
		int rc = check_num(v, p, json_array_get(j, (size_t)i), min, max);
		if (rc)
			return rc;
	}
	return 0;
}

/* Optional field: checked when present. */
#define OPT_NUM(obj, key, path, lo, hi)                                                            \
	do {                                                                                       \
		const json_t *x_ = json_object_get((obj), (key));                                  \
		char p_[256];                                                                      \
		snprintf(p_, sizeof p_, "%s.%s", (path), (key));                                   \
		if (x_ && (rc = check_num(v, p_, x_, (lo), (hi))))                                 \
			return rc;                                                                 \
	} while (0)

static int check_weighted_list(const vctx *v, const char *path, const json_t *a)
{
	if (!json_is_array(a) || !json_array_size(a))
		return verr(v, path, "expected a non-empty array");
	for (size_t i = 0; i < json_array_size(a); i++) {
		const json_t *w = json_object_get(json_array_get(a, i), "weight");
		if (w && (!json_is_number(w) || !(json_number_value(w) > 0)))
			return verr(v, path, "[%zu].weight must be a number > 0", i);
	}
	return 0;
}

static int check_material(const vctx *v, const char *path, const json_t *m)
{
	static const char *const keys[] = {"weight", "kind", "n", "k", "sigma", "diffuse", NULL};
	int rc = check_keys(v, path, m, keys);
	if (rc)
		return rc;
	const json_t *kind = json_object_get(m, "kind");
	if (kind && (!json_is_string(kind) || (strcmp(json_string_value(kind), "dielectric") &&
	                                       strcmp(json_string_value(kind), "metal"))))
		return verr(v, path, "kind must be \"dielectric\" or \"metal\"");
	char p[256];
	snprintf(p, sizeof p, "%s.n", path);
	if ((rc = check_num(v, p, json_object_get(m, "n"), 1e-3, 20)))
		return rc;
	snprintf(p, sizeof p, "%s.sigma", path);
	if ((rc = check_num(v, p, json_object_get(m, "sigma"), 1e-3, 10)))
		return rc;
	OPT_NUM(m, "k", path, 0, 50);
	const json_t *d = json_object_get(m, "diffuse");
	snprintf(p, sizeof p, "%s.diffuse", path);
	if (d && (rc = check_any(v, p, d, check_diffuse)))
		return rc;
	return 0;
}

static int check_shape(const vctx *v, const char *path, const json_t *s)
{
	static const char *const keys[] = {"weight", "type",  "radius", "size", "rotation_deg",
	                                   "file",   "scale", "smooth", NULL};
	int rc = check_keys(v, path, s, keys);
	if (rc)
		return rc;
	const char *t = json_string_value(json_object_get(s, "type"));
	char p[256];
	if (!t || (strcmp(t, "sphere") && strcmp(t, "box") && strcmp(t, "mesh")))
		return verr(v, path, "type must be \"sphere\", \"box\" or \"mesh\"");
	if (!strcmp(t, "sphere")) {
		snprintf(p, sizeof p, "%s.radius", path);
		if ((rc = check_num(v, p, json_object_get(s, "radius"), 1e-4, 1e4)))
			return rc;
	} else if (!strcmp(t, "box")) {
		snprintf(p, sizeof p, "%s.size", path);
		const json_t *sz = json_object_get(s, "size");
		if (json_is_array(sz) && json_array_size(sz) == 3)
			rc = check_vec3(v, p, sz, 1e-4, 1e4);
		else
			rc = check_num(v, p, sz, 1e-4, 1e4);
		if (rc)
			return rc;
	} else {
		snprintf(p, sizeof p, "%s.file", path);
		if ((rc = check_any(v, p, json_object_get(s, "file"), check_string)))
			return rc;
		OPT_NUM(s, "scale", path, 1e-6, 1e6);
		const json_t *sm = json_object_get(s, "smooth");
		snprintf(p, sizeof p, "%s.smooth", path);
		if (sm && (rc = check_any(v, p, sm, check_bool)))
			return rc;
	}
	if (strcmp(t, "sphere") && json_object_get(s, "rotation_deg")) {
		snprintf(p, sizeof p, "%s.rotation_deg", path);
		if ((rc = check_vec3(v, p, json_object_get(s, "rotation_deg"), -3600, 3600)))
			return rc;
	}
	if (strcmp(t, "mesh") && (json_object_get(s, "file") || json_object_get(s, "scale") ||
	                          json_object_get(s, "smooth")))
		return verr(v, path, "file, scale and smooth are for meshes");
	if (strcmp(t, "sphere") == 0 &&
	    (json_object_get(s, "size") || json_object_get(s, "rotation_deg")))
		return verr(v, path, "a sphere has a radius (no size or rotation)");
	if (strcmp(t, "box") == 0 && json_object_get(s, "radius"))
		return verr(v, path, "a box has a size (no radius)");
	return 0;
}

static const char *const effect_names[] = {
    "diffuse", "shadowing", "cast_shadows",     "supersampling",     "circular",     "mueller",
    "noise",   "prnu_dsnu", "extinction_ratio", "orientation_error", "transmission", "crosstalk",
    "blur",    NULL};

/* An effects object: each effect a value or a choice of values. */
static int check_effects(const vctx *v, const char *path, const json_t *fx)
{
	int rc = check_keys(v, path, fx, effect_names);
	if (rc)
		return rc;
	const char *k;
	json_t *val;
	json_object_foreach((json_t *)fx, k, val)
	{
		char p[320];
		snprintf(p, sizeof p, "%s.%s", path, k);
		if ((rc = check_any(v, p, val, check_effect_value)))
			return rc;
	}
	return 0;
}

static int validate(const vctx *v, const json_t *s)
{
	static const char *const top[] = {
	    "polarcam_family", "name",   "resolution", "frames", "truth",      "sensor",  "camera",
	    "materials",       "ground", "objects",    "lights", "background", "effects", NULL};
	int rc = check_keys(v, "(top level)", s, top);
	if (rc)
		return rc;
	const json_t *ver = json_object_get(s, "polarcam_family");
	if (!json_is_integer(ver) || json_integer_value(ver) != 1)
		return verr(v, "polarcam_family", "must be 1 (the spec format version)");
	const json_t *nm = json_object_get(s, "name");
	if (nm && (!json_is_string(nm) || strlen(json_string_value(nm)) >= 100))
		return verr(v, "name", "expected a string of at most 99 characters");
	const json_t *res = json_object_get(s, "resolution");
	if (!json_is_array(res) || json_array_size(res) != 2 ||
	    !json_is_integer(json_array_get(res, 0)) || !json_is_integer(json_array_get(res, 1)) ||
	    json_integer_value(json_array_get(res, 0)) < 4 ||
	    json_integer_value(json_array_get(res, 1)) < 4 ||
	    json_integer_value(json_array_get(res, 0)) > 16384 ||
	    json_integer_value(json_array_get(res, 1)) > 16384)
		return verr(v, "resolution", "expected [width, height], integers in 4..16384");
	const json_t *fr = json_object_get(s, "frames");
	if (fr &&
	    (!json_is_integer(fr) || json_integer_value(fr) < 1 || json_integer_value(fr) > 64))
		return verr(v, "frames", "expected an integer 1..64");
	const char *tr = json_string_value(json_object_get(s, "truth"));
	if (json_object_get(s, "truth") &&
	    (!tr || (strcmp(tr, "float32") && strcmp(tr, "float16") && strcmp(tr, "none"))))
		return verr(v, "truth", "expected \"float32\", \"float16\" or \"none\"");
	/* sensor */
	const json_t *sen = json_object_get(s, "sensor");
	if (sen) {
		static const char *const keys[] = {"preset", "pixel_pitch_um", "gain_db",
		                                   "exposure", NULL};
		if ((rc = check_keys(v, "sensor", sen, keys)))
			return rc;
		const json_t *pr = json_object_get(sen, "preset");
		if (pr && (rc = check_any(v, "sensor.preset", pr, check_preset)))
			return rc;
		OPT_NUM(sen, "pixel_pitch_um", "sensor", 0.1, 100);
		OPT_NUM(sen, "gain_db", "sensor", 0, 48);
		const json_t *ex = json_object_get(sen, "exposure");
		if (ex) {
			static const char *const ek[] = {
			    "us",     "auto_percentile", "auto_level",         "min_us",
			    "max_us", "auto_min_median", "auto_max_saturated", NULL};
			if ((rc = check_keys(v, "sensor.exposure", ex, ek)))
				return rc;
			bool us = json_object_get(ex, "us"), au = json_object_get(ex, "auto_level");
			if (us == au)
				return verr(v, "sensor.exposure",
				            "expected either \"us\" (a distribution of "
				            "exposures) or \"auto_level\" (auto-exposure)");
			OPT_NUM(ex, "us", "sensor.exposure", 1, 1e7);
			OPT_NUM(ex, "auto_level", "sensor.exposure", 1e-3, 1);
			const char *const af[] = {"auto_min_median", "auto_max_saturated"};
			for (int i = 0; i < 2; i++) {
				const json_t *x = json_object_get(ex, af[i]);
				if (x && (!json_is_number(x) || !(json_number_value(x) >= 0 &&
				                                  json_number_value(x) <= 1)))
					return verr(v, "sensor.exposure",
					            "%s: expected a number in [0, 1]", af[i]);
				if (x && us)
					return verr(v, "sensor.exposure",
					            "%s belongs to the auto-exposure", af[i]);
			}
			const json_t *p = json_object_get(ex, "auto_percentile");
			if (p && (!json_is_number(p) ||
			          !(json_number_value(p) > 0 && json_number_value(p) <= 100)))
				return verr(v, "sensor.exposure.auto_percentile",
				            "expected a number in (0, 100]");
			const json_t *mn = json_object_get(ex, "min_us"),
			             *mx = json_object_get(ex, "max_us");
			double lo = mn ? json_number_value(mn) : 1,
			       hi = mx ? json_number_value(mx) : 1e6;
			if ((mn && !json_is_number(mn)) || (mx && !json_is_number(mx)) ||
			    !(lo >= 1) || !(hi >= lo) || !(hi <= 1e7))
				return verr(v, "sensor.exposure",
				            "min_us and max_us: numbers with 1 <= min_us "
				            "<= max_us <= 1e7");
		}
	}
	/* camera */
	const json_t *cam = json_object_get(s, "camera");
	{
		static const char *const keys[] = {"distance", "azimuth_deg", "elevation_deg",
		                                   "roll_deg", "target",      "fov_deg",
		                                   "f_number", NULL};
		if ((rc = check_keys(v, "camera", cam, keys)))
			return rc;
		if ((rc = check_num(v, "camera.distance", json_object_get(cam, "distance"), 1e-3,
		                    1e6)))
			return rc;
		OPT_NUM(cam, "azimuth_deg", "camera", -3600, 3600);
		OPT_NUM(cam, "elevation_deg", "camera", -89, 89);
		OPT_NUM(cam, "roll_deg", "camera", -180, 180);
		OPT_NUM(cam, "fov_deg", "camera", 1, 150);
		OPT_NUM(cam, "f_number", "camera", 0.5, 64);
		const json_t *t = json_object_get(cam, "target");
		if (t && (rc = check_vec3(v, "camera.target", t, -1e6, 1e6)))
			return rc;
	}
	/* materials */
	const json_t *mats = json_object_get(s, "materials");
	if ((rc = check_weighted_list(v, "materials", mats)))
		return rc;
	for (size_t i = 0; i < json_array_size(mats); i++) {
		char p[64];
		snprintf(p, sizeof p, "materials[%zu]", i);
		if ((rc = check_material(v, p, json_array_get(mats, i))))
			return rc;
	}
	/* ground */
	const json_t *gr = json_object_get(s, "ground");
	if (gr) {
		static const char *const keys[] = {"probability", "size", "materials", NULL};
		if ((rc = check_keys(v, "ground", gr, keys)))
			return rc;
		const json_t *gm = json_object_get(gr, "materials");
		if (gm) {
			if ((rc = check_weighted_list(v, "ground.materials", gm)))
				return rc;
			for (size_t i = 0; i < json_array_size(gm); i++) {
				char p[64];
				snprintf(p, sizeof p, "ground.materials[%zu]", i);
				if ((rc = check_material(v, p, json_array_get(gm, i))))
					return rc;
			}
		}
		const json_t *pp = json_object_get(gr, "probability");
		if (pp && (!json_is_number(pp) ||
		           !(json_number_value(pp) >= 0 && json_number_value(pp) <= 1)))
			return verr(v, "ground.probability", "expected a number in [0, 1]");
		OPT_NUM(gr, "size", "ground", 0, 1e6);
	}
	/* objects */
	const json_t *obj = json_object_get(s, "objects");
	if (obj) {
		static const char *const keys[] = {"count", "region", "rest_on_ground", "shapes",
		                                   NULL};
		if ((rc = check_keys(v, "objects", obj, keys)))
			return rc;
		if ((rc = check_num(v, "objects.count", json_object_get(obj, "count"), 0, 256)))
			return rc;
		if ((rc = check_vec3(v, "objects.region", json_object_get(obj, "region"), -1e6,
		                     1e6)))
			return rc;
		const json_t *rg = json_object_get(obj, "rest_on_ground");
		if (rg && !json_is_boolean(rg))
			return verr(v, "objects.rest_on_ground", "expected true or false");
		const json_t *sh = json_object_get(obj, "shapes");
		if ((rc = check_weighted_list(v, "objects.shapes", sh)))
			return rc;
		for (size_t i = 0; i < json_array_size(sh); i++) {
			char p[64];
			snprintf(p, sizeof p, "objects.shapes[%zu]", i);
			if ((rc = check_shape(v, p, json_array_get(sh, i))))
				return rc;
		}
	}
	/* lights */
	const json_t *li = json_object_get(s, "lights");
	{
		static const char *const keys[] = {"count",
		                                   "type",
		                                   "azimuth_deg",
		                                   "elevation_deg",
		                                   "irradiance_w_m2",
		                                   "distance",
		                                   "polarization",
		                                   "dop",
		                                   NULL};
		if ((rc = check_keys(v, "lights", li, keys)))
			return rc;
		if ((rc = check_num(v, "lights.count", json_object_get(li, "count"), 1, 64)))
			return rc;
		const json_t *ty = json_object_get(li, "type");
		if (ty && (rc = check_any(v, "lights.type", ty, check_light_type)))
			return rc;
		OPT_NUM(li, "azimuth_deg", "lights", -3600, 3600);
		OPT_NUM(li, "elevation_deg", "lights", -90, 90);
		if ((rc = check_num(v, "lights.irradiance_w_m2",
		                    json_object_get(li, "irradiance_w_m2"), 0, 1e9)))
			return rc;
		OPT_NUM(li, "distance", "lights", 1e-3, 1e6);
		OPT_NUM(li, "dop", "lights", 0, 1);
		const json_t *po = json_object_get(li, "polarization");
		if (po) {
			static const char *const pk[] = {"unpolarized", "linear", "circular",
			                                 "elliptical", NULL};
			if ((rc = check_keys(v, "lights.polarization", po, pk)))
				return rc;
			double sum = 0;
			const char *k;
			json_t *w;
			json_object_foreach((json_t *)po, k, w)
			{
				if (!json_is_number(w) || !(json_number_value(w) >= 0))
					return verr(v, "lights.polarization",
					            "weight of \"%s\" must be a "
					            "number >= 0",
					            k);
				sum += json_number_value(w);
			}
			if (!(sum > 0))
				return verr(v, "lights.polarization",
				            "the weights must not all be 0");
		}
	}
	if (json_object_get(s, "background") &&
	    (rc = check_num(v, "background", json_object_get(s, "background"), 0, 1e9)))
		return rc;
	const json_t *fx = json_object_get(s, "effects");
	if (fx && dist_kind(fx)) /* effect sets: {"choice": [{...}, {...}], "weights": [...]} */
		return check_any(v, "effects", fx, check_effects);
	if (fx)
		return check_effects(v, "effects", fx);
	return 0;
}

/* ---- sampling ---- */

enum { PC_RNG_FAMILY = 32 };

typedef struct draw {
	pc_rng r;
} draw;

static double uni(draw *d)
{
	return pc_rng_uniform(&d->r);
}

static size_t pick_weighted(draw *d, const json_t *weights, size_t n)
{
	double u = uni(d);
	if (!weights)
		return (size_t)fmin(floor(u * (double)n), (double)(n - 1));
	double sum = 0;
	for (size_t i = 0; i < n; i++)
		sum += json_number_value(json_array_get(weights, i));
	double acc = 0;
	for (size_t i = 0; i < n; i++) {
		acc += json_number_value(json_array_get(weights, i));
		if (u * sum < acc)
			return i;
	}
	return n - 1;
}

/* A draw of a validated number distribution; absent: def. One uniform per draw (two for none:
 * constants draw nothing), so every field's draw count is fixed by the spec. */
static double num(draw *d, const json_t *j, double def)
{
	if (!j)
		return def;
	if (json_is_number(j))
		return json_number_value(j);
	const char *k = dist_kind(j);
	if (k && !strcmp(k, "choice")) {
		const json_t *c = json_object_get(j, "choice");
		return json_number_value(json_array_get(
		    c, pick_weighted(d, json_object_get(j, "weights"), json_array_size(c))));
	}
	const json_t *r = k ? json_object_get(j, k) : j;
	double lo = json_number_value(json_array_get(r, 0)),
	       hi = json_number_value(json_array_get(r, 1));
	double u = uni(d);
	if (k && !strcmp(k, "log_uniform"))
		return lo * exp(u * log(hi / lo));
	if (k && !strcmp(k, "int"))
		return fmin(lo + floor(u * (hi - lo + 1)), hi);
	return lo + u * (hi - lo);
}

static const json_t *any(draw *d, const json_t *j)
{
	const char *k = dist_kind(j);
	if (!k)
		return j;
	const json_t *c = json_object_get(j, "choice");
	return json_array_get(c,
	                      pick_weighted(d, json_object_get(j, "weights"), json_array_size(c)));
}

static const json_t *pick_list(draw *d, const json_t *a)
{
	size_t n = json_array_size(a);
	double sum = 0, u = uni(d), acc = 0;
	for (size_t i = 0; i < n; i++) {
		const json_t *w = json_object_get(json_array_get(a, i), "weight");
		sum += w ? json_number_value(w) : 1;
	}
	for (size_t i = 0; i < n; i++) {
		const json_t *w = json_object_get(json_array_get(a, i), "weight");
		acc += w ? json_number_value(w) : 1;
		if (u * sum < acc)
			return json_array_get(a, i);
	}
	return json_array_get(a, n - 1);
}

static json_t *vec3(double x, double y, double z)
{
	return json_pack("[f, f, f]", x, y, z);
}

static void v3_num(draw *d, const json_t *j, double def, double out[3])
{
	for (int i = 0; i < 3; i++)
		out[i] = num(d, j ? json_array_get(j, (size_t)i) : NULL, def);
}

static json_t *sample_material(draw *d, const json_t *cls)
{
	json_t *m = json_object();
	json_object_set_new(m, "n", json_real(num(d, json_object_get(cls, "n"), 1.5)));
	json_object_set_new(m, "k", json_real(num(d, json_object_get(cls, "k"), 0)));
	json_object_set_new(m, "sigma", json_real(num(d, json_object_get(cls, "sigma"), 0.2)));
	const json_t *df = json_object_get(cls, "diffuse");
	if (df)
		json_object_set(m, "diffuse", (json_t *)any(d, df));
	return m;
}

static int mesh_index(const pc_family *f, const char *file)
{
	for (unsigned i = 0; i < f->n_mesh; i++)
		if (!strcmp(f->mesh_spec[i], file))
			return (int)i;
	return -1;
}

static const char *base_name(const char *p)
{
	const char *s = strrchr(p, '/');
	return s ? s + 1 : p;
}

/* Builds the scene document of sample index. dataset_paths: mesh files as "../../meshes/NAME"
 * (else as the spec names them). */
static json_t *build_scene(const pc_family *f, uint64_t seed, uint64_t index, bool dataset_paths,
                           uint64_t *sim_seed, double *exposure_us)
{
	const json_t *s = f->spec;
	draw d;
	pc_rng_init(&d.r, seed, PC_RNG_FAMILY, (uint32_t)(index & 0xFFFFu),
	            (uint32_t)(index >> 16 & 0xFFFFu), index >> 32);
	/* 63 bits: JSON integers are signed */
	uint64_t hi = pc_rng_u32(&d.r); /* two statements: C leaves the order within one open */
	uint64_t lo = pc_rng_u32(&d.r);
	*sim_seed = (hi << 32 | lo) & 0x7FFFFFFFFFFFFFFFull;
	json_t *sc = json_object();
	char nm[200];
	snprintf(nm, sizeof nm, "%s #%llu (seed %llu)", f->name, (unsigned long long)index,
	         (unsigned long long)seed);
	json_object_set_new(sc, "polarcam_scene", json_integer(1));
	json_object_set_new(sc, "name", json_string(nm));
	/* sensor */
	const json_t *sen = json_object_get(s, "sensor");
	json_t *sensor = json_object();
	const json_t *preset = json_object_get(sen, "preset");
	json_object_set_new(sensor, "preset",
	                    json_string(preset ? json_string_value(any(&d, preset)) : "imx250mzr"));
	json_object_set_new(sensor, "resolution",
	                    json_pack("[i, i]", (int)f->width, (int)f->height));
	double pitch = num(&d, json_object_get(sen, "pixel_pitch_um"), 3.45);
	json_object_set_new(sensor, "pixel_pitch_um", json_real(pitch));
	json_object_set_new(sensor, "gain_db",
	                    json_real(num(&d, json_object_get(sen, "gain_db"), 0)));
	const json_t *ex = json_object_get(sen, "exposure");
	*exposure_us = num(&d, ex ? json_object_get(ex, "us") : NULL, 1000);
	json_object_set_new(sensor, "exposure_us", json_real(*exposure_us));
	json_object_set_new(sc, "sensor", sensor);
	/* camera */
	const json_t *cam = json_object_get(s, "camera");
	double tgt[3];
	v3_num(&d, json_object_get(cam, "target"), 0, tgt);
	double dist = num(&d, json_object_get(cam, "distance"), 5);
	double az = num(&d, json_object_get(cam, "azimuth_deg"), 0) * DEG;
	double el = num(&d, json_object_get(cam, "elevation_deg"), 30) * DEG;
	double roll = num(&d, json_object_get(cam, "roll_deg"), 0) * DEG;
	double fov = num(&d, json_object_get(cam, "fov_deg"), 40) * DEG;
	double fnum = num(&d, json_object_get(cam, "f_number"), 4);
	double pos[3] = {tgt[0] + dist * cos(el) * cos(az), tgt[1] + dist * cos(el) * sin(az),
	                 tgt[2] + dist * sin(el)};
	/* roll: the up vector turned about the view direction */
	double fw[3] = {tgt[0] - pos[0], tgt[1] - pos[1], tgt[2] - pos[2]};
	double fl = sqrt(fw[0] * fw[0] + fw[1] * fw[1] + fw[2] * fw[2]);
	for (int i = 0; i < 3; i++)
		fw[i] /= fl;
	double rt[3] = {fw[1], -fw[0], 0}; /* forward × z */
	double rl = sqrt(rt[0] * rt[0] + rt[1] * rt[1]);
	rt[0] /= rl;
	rt[1] /= rl;
	double u0[3] = {rt[1] * fw[2] - rt[2] * fw[1], rt[2] * fw[0] - rt[0] * fw[2],
	                rt[0] * fw[1] - rt[1] * fw[0]}; /* right × forward */
	double up[3];
	for (int i = 0; i < 3; i++)
		up[i] = cos(roll) * u0[i] + sin(roll) * rt[i];
	double width_m = f->width * pitch * 1e-6;
	double focal_mm = width_m / (2 * tan(fov / 2)) * 1e3;
	json_t *camera = json_object();
	json_object_set_new(camera, "position", vec3(pos[0], pos[1], pos[2]));
	json_object_set_new(camera, "look_at", vec3(tgt[0], tgt[1], tgt[2]));
	json_object_set_new(camera, "up", vec3(up[0], up[1], up[2]));
	json_object_set_new(camera, "focal_length_mm", json_real(focal_mm));
	json_object_set_new(camera, "f_number", json_real(fnum));
	json_object_set_new(sc, "camera", camera);
	/* lights */
	const json_t *li = json_object_get(s, "lights");
	json_t *lights = json_array();
	bool circular = false;
	int nl = (int)num(&d, json_object_get(li, "count"), 1);
	for (int i = 0; i < nl; i++) {
		json_t *l = json_object();
		const json_t *ty = json_object_get(li, "type");
		const char *type = ty ? json_string_value(any(&d, ty)) : "directional";
		double laz = num(&d, json_object_get(li, "azimuth_deg"), 0) * DEG;
		double lel = num(&d, json_object_get(li, "elevation_deg"), 45) * DEG;
		double irr = num(&d, json_object_get(li, "irradiance_w_m2"), 100);
		double ldist = num(&d, json_object_get(li, "distance"), 5);
		double dir[3] = {cos(lel) * cos(laz), cos(lel) * sin(laz), sin(lel)};
		json_object_set_new(l, "type", json_string(type));
		if (!strcmp(type, "point")) {
			json_object_set_new(l, "position",
			                    vec3(tgt[0] + ldist * dir[0], tgt[1] + ldist * dir[1],
			                         tgt[2] + ldist * dir[2]));
			json_object_set_new(l, "intensity_w_sr", json_real(irr * ldist * ldist));
		} else {
			json_object_set_new(l, "direction", vec3(dir[0], dir[1], dir[2]));
			json_object_set_new(l, "irradiance_w_m2", json_real(irr));
		}
		/* polarization: a kind by weight, then its state */
		const json_t *po = json_object_get(li, "polarization");
		static const char *const kinds[] = {"unpolarized", "linear", "circular",
		                                    "elliptical"};
		double w[4], sum = 0;
		for (int k = 0; k < 4; k++) {
			const json_t *x = po ? json_object_get(po, kinds[k]) : NULL;
			w[k] = po ? (x ? json_number_value(x) : 0) : (k == 0);
			sum += w[k];
		}
		double u = uni(&d) * sum, acc = 0;
		int kind = 3;
		for (int k = 0; k < 4; k++) {
			acc += w[k];
			if (u < acc) {
				kind = k;
				break;
			}
		}
		double dop = num(&d, json_object_get(li, "dop"), 1);
		double a1 = uni(&d), a2 = uni(&d);
		json_t *st = NULL;
		if (kind == 1) {
			st = json_pack("{s:f, s:f}", "linear_deg", 180 * a1, "dop", dop);
		} else if (kind == 2) {
			st = json_pack("{s:i, s:f}", "circular", a1 < 0.5 ? -1 : 1, "dop", dop);
			circular = true;
		} else if (kind == 3) {
			/* uniform on the Poincaré sphere: S3 = 2·a1 − 1, azimuth 2π·a2 */
			double s3 = 2 * a1 - 1, c = sqrt(fmax(0, 1 - s3 * s3)), ph = 2 * M_PI * a2;
			st = json_pack("{s:[f, f, f], s:f}", "stokes", c * cos(ph), c * sin(ph), s3,
			               "dop", dop);
			circular = true;
		}
		if (st)
			json_object_set_new(l, "polarization", st);
		json_array_append_new(lights, l);
	}
	json_object_set_new(sc, "lights", lights);
	/* materials and objects: each object (and the ground) its own material */
	const json_t *mats = json_object_get(s, "materials");
	json_t *materials = json_object(), *objects = json_array();
	const json_t *gr = json_object_get(s, "ground");
	double gp = gr && json_object_get(gr, "probability")
	                ? json_number_value(json_object_get(gr, "probability"))
	                : 1;
	bool ground = gr && uni(&d) < gp;
	if (ground) {
		const json_t *gm = json_object_get(gr, "materials");
		json_object_set_new(materials, "ground",
		                    sample_material(&d, pick_list(&d, gm ? gm : mats)));
		json_t *o = json_pack("{s:s, s:[f,f,f], s:[f,f,f], s:s}", "type", "plane", "point",
		                      0.0, 0.0, 0.0, "normal", 0.0, 0.0, 1.0, "material", "ground");
		double size = num(&d, json_object_get(gr, "size"), 0);
		if (size > 0)
			json_object_set_new(o, "size", json_pack("[f, f]", size, size));
		json_array_append_new(objects, o);
	}
	const json_t *ob = json_object_get(s, "objects");
	int no = ob ? (int)num(&d, json_object_get(ob, "count"), 0) : 0;
	bool rest = ob && json_is_true(json_object_get(ob, "rest_on_ground"));
	double placed[256][4];
	int nplaced = 0;
	for (int i = 0; i < no; i++) {
		char mname[32];
		snprintf(mname, sizeof mname, "m%d", i);
		json_object_set_new(materials, mname, sample_material(&d, pick_list(&d, mats)));
		const json_t *sh = pick_list(&d, json_object_get(ob, "shapes"));
		const char *type = json_string_value(json_object_get(sh, "type"));
		json_t *o = json_object();
		json_object_set_new(o, "type", json_string(type));
		json_object_set_new(o, "material", json_string(mname));
		double bound = 0, lift = 0, rot[3] = {0, 0, 0};
		if (!strcmp(type, "sphere")) {
			double r = num(&d, json_object_get(sh, "radius"), 0.5);
			json_object_set_new(o, "radius", json_real(r));
			bound = lift = r;
		} else if (!strcmp(type, "box")) {
			const json_t *sz = json_object_get(sh, "size");
			double e[3];
			if (json_is_array(sz) && json_array_size(sz) == 3) {
				v3_num(&d, sz, 1, e);
			} else {
				e[0] = num(&d, sz, 1);
				e[1] = num(&d, sz, 1);
				e[2] = num(&d, sz, 1);
			}
			json_object_set_new(o, "size", vec3(e[0], e[1], e[2]));
			v3_num(&d, json_object_get(sh, "rotation_deg"), 0, rot);
			if (rest)
				rot[0] = rot[1] = 0; /* resting on a face: yaw only */
			json_object_set_new(o, "rotation_deg", vec3(rot[0], rot[1], rot[2]));
			bound = 0.5 * sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
			lift = 0.5 * e[2];
		} else {
			const char *file = json_string_value(any(&d, json_object_get(sh, "file")));
			int mi = mesh_index(f, file);
			json_object_set_new(o, "file", json_string(file));
			if (dataset_paths) {
				char p[300];
				snprintf(p, sizeof p, "../../meshes/%s", f->mesh_name[mi]);
				json_object_set_new(o, "file", json_string(p));
			}
			double scale = num(&d, json_object_get(sh, "scale"), 1);
			json_object_set_new(o, "scale", json_real(scale));
			v3_num(&d, json_object_get(sh, "rotation_deg"), 0, rot);
			json_object_set_new(o, "rotation_deg", vec3(rot[0], rot[1], rot[2]));
			const json_t *sm = json_object_get(sh, "smooth");
			if (sm)
				json_object_set(o, "smooth", (json_t *)any(&d, sm));
			bound = scale; /* OBJ models are expected to fit the unit sphere
			                  (docs/dataset.md) */
			lift = 0;
		}
		/* placement: up to 16 tries for a centre whose bounding sphere keeps clear of the
		 * objects placed before; the last try is kept */
		double c[3] = {0, 0, 0};
		for (int t = 0; t < 16; t++) {
			v3_num(&d, json_object_get(ob, "region"), 0, c);
			if (rest && lift > 0)
				c[2] = lift;
			bool clear = true;
			for (int k = 0; k < nplaced && clear; k++) {
				double dx = c[0] - placed[k][0], dy = c[1] - placed[k][1],
				       dz = c[2] - placed[k][2];
				clear = dx * dx + dy * dy + dz * dz >=
				        (bound + placed[k][3]) * (bound + placed[k][3]);
			}
			if (clear)
				break;
		}
		if (nplaced < 256) {
			placed[nplaced][0] = c[0];
			placed[nplaced][1] = c[1];
			placed[nplaced][2] = c[2];
			placed[nplaced][3] = bound;
			nplaced++;
		}
		json_object_set_new(o, !strcmp(type, "mesh") ? "position" : "center",
		                    vec3(c[0], c[1], c[2]));
		json_array_append_new(objects, o);
	}
	json_object_set_new(sc, "materials", materials);
	json_object_set_new(sc, "objects", objects);
	json_object_set_new(sc, "background",
	                    json_real(num(&d, json_object_get(s, "background"), 0)));
	/* effects */
	json_t *effects = json_object();
	const json_t *fx = json_object_get(s, "effects");
	if (fx && dist_kind(fx))
		fx = any(&d, fx); /* one of the effect sets, then its effects' draws */
	for (int i = 0; effect_names[i]; i++) {
		const json_t *e = fx ? json_object_get(fx, effect_names[i]) : NULL;
		if (e)
			json_object_set(effects, effect_names[i], (json_t *)any(&d, e));
	}
	if (circular)
		json_object_set_new(effects, "circular", json_true()); /* the lights need S3 */
	json_object_set_new(sc, "effects", effects);
	return sc;
}

int pc_family_scene(const pc_family *f, uint64_t seed, uint64_t index, char **scene_json,
                    uint64_t *sim_seed)
{
	double e;
	json_t *sc = build_scene(f, seed, index, false, sim_seed, &e);
	*scene_json =
	    json_dumps(sc, JSON_INDENT(1) | JSON_REAL_PRECISION(17) | JSON_PRESERVE_ORDER);
	json_decref(sc);
	return *scene_json ? 0 : pc_error(PC_ENOMEM, "scene text");
}

/* ---- load ---- */

void pc_family_free(pc_family *f)
{
	if (!f)
		return;
	json_decref(f->spec);
	free(f->source);
	free(f->base_dir);
	for (unsigned i = 0; i < f->n_mesh; i++) {
		free(f->mesh_spec[i]);
		free(f->mesh_path[i]);
		free(f->mesh_name[i]);
	}
	free(f);
}

static int add_mesh(pc_family *f, const vctx *v, const char *file)
{
	if (mesh_index(f, file) >= 0)
		return 0;
	if (f->n_mesh >= MAX_MESHES)
		return verr(v, "objects.shapes", "more than %d mesh files", MAX_MESHES);
	const char *bn = base_name(file);
	for (unsigned i = 0; i < f->n_mesh; i++)
		if (!strcmp(f->mesh_name[i], bn))
			return verr(v, "objects.shapes",
			            "two mesh files named %s (a dataset stores meshes "
			            "by file name)",
			            bn);
	char path[4096];
	if (file[0] == '/')
		snprintf(path, sizeof path, "%s", file);
	else
		snprintf(path, sizeof path, "%s/%s", f->base_dir, file);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return verr(v, "objects.shapes", "mesh file %s: cannot be opened", path);
	fclose(fp);
	f->mesh_spec[f->n_mesh] = strdup(file);
	f->mesh_path[f->n_mesh] = strdup(path);
	f->mesh_name[f->n_mesh] = strdup(bn);
	if (!f->mesh_spec[f->n_mesh] || !f->mesh_path[f->n_mesh] || !f->mesh_name[f->n_mesh]) {
		f->n_mesh++; /* freed with the family */
		return pc_error(PC_ENOMEM, "mesh names");
	}
	f->n_mesh++;
	return 0;
}

static int finish(pc_family *f)
{
	vctx v = {f->source};
	int rc = validate(&v, f->spec);
	if (rc)
		return rc;
	const json_t *nm = json_object_get(f->spec, "name");
	snprintf(f->name, sizeof f->name, "%s", nm ? json_string_value(nm) : "family");
	const json_t *res = json_object_get(f->spec, "resolution");
	f->width = (uint32_t)json_integer_value(json_array_get(res, 0));
	f->height = (uint32_t)json_integer_value(json_array_get(res, 1));
	/* the mesh files the shapes may draw */
	const json_t *sh = json_object_get(json_object_get(f->spec, "objects"), "shapes");
	for (size_t i = 0; i < json_array_size(sh); i++) {
		const json_t *file = json_object_get(json_array_get(sh, i), "file");
		if (!file)
			continue;
		if (dist_kind(file)) {
			const json_t *c = json_object_get(file, "choice");
			for (size_t k = 0; k < json_array_size(c); k++)
				if ((rc = add_mesh(f, &v, json_string_value(json_array_get(c, k)))))
					return rc;
		} else if ((rc = add_mesh(f, &v, json_string_value(file)))) {
			return rc;
		}
	}
	return pc_family_set_resolution(f, f->width, f->height);
}

int pc_family_parse(const char *text, const char *name, const char *base_dir, pc_family **out)
{
	*out = NULL;
	pc_family *f = calloc(1, sizeof *f);
	if (!f)
		return pc_error(PC_ENOMEM, "family");
	f->source = strdup(name ? name : "family");
	f->base_dir = strdup(base_dir && *base_dir ? base_dir : ".");
	if (!f->source || !f->base_dir) {
		pc_family_free(f);
		return pc_error(PC_ENOMEM, "family");
	}
	json_error_t je;
	f->spec = json_loads(text, JSON_REJECT_DUPLICATES, &je);
	if (!f->spec) {
		int rc = pc_error(PC_EINVAL, "%s: line %d, column %d: %s", f->source, je.line,
		                  je.column, je.text);
		pc_family_free(f);
		return rc;
	}
	int rc = finish(f);
	if (rc) {
		pc_family_free(f);
		return rc;
	}
	*out = f;
	return 0;
}

int pc_family_load(const char *path, pc_family **out)
{
	*out = NULL;
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(PC_EIO, "%s: cannot be opened", path);
	char *buf = NULL;
	size_t n = 0, cap = 0;
	for (;;) {
		if (n + 4096 + 1 > cap) {
			cap = cap ? 2 * cap : 65536;
			char *nb = cap > (64u << 20) ? NULL : realloc(buf, cap);
			if (!nb) {
				free(buf);
				fclose(fp);
				return pc_error(PC_EINVAL,
				                "%s: larger than 64 MiB or out of memory", path);
			}
			buf = nb;
		}
		size_t k = fread(buf + n, 1, 4096, fp);
		n += k;
		if (k < 4096)
			break;
	}
	fclose(fp);
	buf[n] = 0;
	char dir[4096];
	snprintf(dir, sizeof dir, "%s", path);
	char *sl = strrchr(dir, '/');
	if (sl)
		*sl = 0;
	else
		snprintf(dir, sizeof dir, ".");
	int rc = pc_family_parse(buf, path, dir, out);
	free(buf);
	return rc;
}

int pc_family_set_resolution(pc_family *f, uint32_t width, uint32_t height)
{
	if (width < 4 || height < 4 || width > 16384 || height > 16384)
		return pc_error(PC_EINVAL, "%s: resolution %ux%u: expected 4..16384 each",
		                f->source, width, height);
	/* every preset the spec may draw must tile */
	const json_t *pr = json_object_get(json_object_get(f->spec, "sensor"), "preset");
	const json_t *list = pr && dist_kind(pr) ? json_object_get(pr, "choice") : NULL;
	size_t n = list ? json_array_size(list) : 1;
	for (size_t i = 0; i < n; i++) {
		const char *name = list ? json_string_value(json_array_get(list, i))
		                   : pr ? json_string_value(pr)
		                        : "imx250mzr";
		pc_sensor_figures fig;
		if (pc_sensor_preset(name, &fig))
			return pc_error(PC_EINVAL, "%s: sensor.preset %s: unknown", f->source,
			                name);
		unsigned per = fig.mosaic.period;
		if (width % per || height % per)
			return pc_error(PC_EINVAL,
			                "%s: resolution %ux%u: the %s mosaic needs multiples of %u",
			                f->source, width, height, name, per);
	}
	f->width = width;
	f->height = height;
	json_object_set_new(f->spec, "resolution", json_pack("[i, i]", (int)width, (int)height));
	/* the first samples must be valid scenes (catches what the field checks cannot) */
	for (uint64_t i = 0; i < 4; i++) {
		char *text = NULL;
		uint64_t ss;
		int rc = pc_family_scene(f, 1, i, &text, &ss);
		pc_scene *scene = NULL;
		if (!rc)
			rc = pc_scene_parse(text, f->source, f->base_dir, &scene);
		free(text);
		pc_scene_free(scene);
		if (rc)
			return pc_error_prefix(
			    rc, "%s: sample %llu of the spec is not a valid scene: ", f->source,
			    (unsigned long long)i);
	}
	return 0;
}

const char *pc_family_name(const pc_family *f)
{
	return f->name;
}

void pc_family_resolution(const pc_family *f, uint32_t *width, uint32_t *height)
{
	*width = f->width;
	*height = f->height;
}

char *pc_family_to_json(const pc_family *f)
{
	return json_dumps(f->spec, JSON_COMPACT | JSON_SORT_KEYS | JSON_REAL_PRECISION(17));
}

unsigned pc_family_mesh_count(const pc_family *f)
{
	return f->n_mesh;
}

void pc_family_mesh(const pc_family *f, unsigned i, const char **path, const char **name)
{
	*path = i < f->n_mesh ? f->mesh_path[i] : NULL;
	*name = i < f->n_mesh ? f->mesh_name[i] : NULL;
}

/* ---- render ---- */

void pc_family_sample_free(pc_family_sample *s)
{
	if (!s)
		return;
	free(s->scene_json);
	for (unsigned i = 0; i < s->n_frames && s->frames; i++)
		pc_view_free(&s->frames[i]);
	free(s->frames);
	free(s->frame_meta);
	free(s->sim_json);
	free(s->truth_stokes);
	memset(s, 0, sizeof *s);
}

/* k-th smallest of a (n > k), partially reordering it (Hoare's selection). */
static float select_kth(float *a, size_t n, size_t k)
{
	size_t lo = 0, hi = n - 1;
	while (lo < hi) {
		float p = a[lo + (hi - lo) / 2];
		size_t i = lo, j = hi;
		while (i <= j) {
			while (a[i] < p)
				i++;
			while (a[j] > p)
				j--;
			if (i <= j) {
				float t = a[i];
				a[i] = a[j];
				a[j] = t;
				i++;
				if (j == 0)
					break;
				j--;
			}
		}
		if (k <= j)
			hi = j;
		else if (k >= i)
			lo = i;
		else
			return a[k];
	}
	return a[k];
}

int pc_family_render(const pc_family *f, uint64_t seed, uint64_t index, int threads,
                     pc_family_sample *out)
{
	memset(out, 0, sizeof *out);
	out->index = index;
	double exposure_us;
	json_t *sc = build_scene(f, seed, index, false, &out->sim_seed, &exposure_us);
	char *text = json_dumps(sc, JSON_COMPACT | JSON_REAL_PRECISION(17));
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	int rc = text ? pc_scene_parse(text, f->source, f->base_dir, &scene) : PC_ENOMEM;
	free(text);
	if (rc) {
		json_decref(sc);
		return pc_error_prefix(rc, "sample %llu: ", (unsigned long long)index);
	}
	pc_sim_options o = pc_sim_options_default();
	o.seed = out->sim_seed;
	o.threads = threads;
	rc = pc_sim_new(scene, &o, &sim);
	pc_sim_info *in = &out->info;
	const char *tr = json_string_value(json_object_get(f->spec, "truth"));
	out->truth = !tr || !strcmp(tr, "float32") ? PC_TRUTH_F32
	             : !strcmp(tr, "float16")      ? PC_TRUTH_F16
	                                           : PC_TRUTH_NONE;
	const json_t *fr = json_object_get(f->spec, "frames");
	out->n_frames = fr ? (unsigned)json_integer_value(fr) : 1;
	size_t npix = 0;
	if (!rc) {
		pc_sim_get_info(sim, in);
		npix = (size_t)in->width * in->height;
		if (out->truth != PC_TRUTH_NONE) {
			out->truth_stokes = malloc(npix * in->colour_channels * 4 * sizeof(float));
			if (!out->truth_stokes)
				rc = pc_error(PC_ENOMEM, "truth of %ux%u", in->width, in->height);
		}
	}
	if (!rc)
		rc = pc_sim_prepare(sim, 0, out->truth_stokes, NULL, NULL, NULL);
	/* exposure: the chosen percentile of the mean signal at the chosen fraction of full scale
	 */
	const json_t *ex = json_object_get(json_object_get(f->spec, "sensor"), "exposure");
	if (!rc && ex && json_object_get(ex, "auto_level")) {
		draw d; /* its own stream: the level draw does not shift the scene's draws */
		pc_rng_init(&d.r, seed, PC_RNG_FAMILY + 1, (uint32_t)(index & 0xFFFFu),
		            (uint32_t)(index >> 16 & 0xFFFFu), index >> 32);
		double level = num(&d, json_object_get(ex, "auto_level"), 0.8);
		const json_t *pp = json_object_get(ex, "auto_percentile");
		double pct = pp ? json_number_value(pp) : 99.5;
		const json_t *mn = json_object_get(ex, "min_us"),
		             *mx = json_object_get(ex, "max_us");
		double lo = mn ? json_number_value(mn) : 1, hi = mx ? json_number_value(mx) : 1e6;
		const json_t *jm = json_object_get(ex, "auto_min_median");
		const json_t *js = json_object_get(ex, "auto_max_saturated");
		double min_median = jm ? json_number_value(jm) : 0,
		       max_sat = js ? json_number_value(js) : 1;
		float *r = malloc(npix * sizeof *r);
		if (!r) {
			rc = pc_error(PC_ENOMEM, "exposure statistics");
		} else {
			/* quantiles of the electron rate (e⁻/s): mean DN = K·rate·t above the
			 * offset */
			memcpy(r, sim->rate[0], npix * sizeof *r);
			size_t kq =
			    (size_t)fmin((double)(npix - 1), floor(pct / 100 * (double)npix));
			size_t ks =
			    (size_t)fmin((double)(npix - 1), floor((1 - max_sat) * (double)npix));
			double q = select_kth(r, npix, kq);
			double qs = select_kth(r, npix, ks);
			double q50 = select_kth(r, npix, npix / 2);
			free(r);
			double K = sim->fig.gain_dn_per_e * pow(10, sim->fig.gain_db / 20);
			double room = sim->max_dn - sim->fig.offset_dn;
			/* the percentile at the level; raised until the median reaches its minimum,
			 * but never so far that more than max_sat of the pixels reach full scale */
			double t_us = q > 0 && room > 0 ? level * room / (K * q) * 1e6 : hi;
			if (min_median > 0 && q50 > 0 && K * q50 * t_us * 1e-6 < min_median * room)
				t_us = min_median * room / (K * q50) * 1e6;
			if (max_sat < 1 && qs > 0)
				t_us = fmin(t_us, room / (K * qs) * 1e6);
			/* a round number of nanoseconds: short in the scene file, exact through
			 * JSON */
			t_us = round(fmin(hi, fmax(lo, t_us)) * 1e3) / 1e3;
			exposure_us = t_us;
		}
	}
	if (!rc) {
		out->exposure_us = exposure_us;
		pc_sim_controls ctl = {exposure_us, sim->fig.gain_db};
		out->frames = calloc(out->n_frames, sizeof *out->frames);
		out->frame_meta = calloc(out->n_frames, sizeof *out->frame_meta);
		if (!out->frames || !out->frame_meta)
			rc = pc_error(PC_ENOMEM, "frames");
		for (unsigned i = 0; !rc && i < out->n_frames; i++) {
			rc = pc_view_alloc(&out->frames[i], in->format, in->width, in->height, 64);
			if (!rc)
				rc = pc_sim_frame(sim, i, &ctl, &out->frames[i],
				                  &out->frame_meta[i]);
		}
		out->dn_per_radiance =
		    pc_sim_dn_per_radiance(sim, &ctl, in->colour_channels == 3 ? 1 : 0);
	}
	if (!rc) {
		/* described as the scene file written for the sample configures it: the chosen
		 * exposure (the frames are made, nothing else reads it) */
		sim->fig.exposure_us = exposure_us;
		if (!(out->sim_json = pc_sim_describe_json(sim, NULL)))
			rc = pc_error(PC_ENOMEM, "simulator description");
	}
	if (!rc) {
		/* frame 0's statistics */
		uint16_t *v = malloc(npix * sizeof *v);
		float *fv = malloc(npix * sizeof *fv);
		if (!v || !fv) {
			rc = pc_error(PC_ENOMEM, "frame statistics");
		} else if (!(rc = pc_view_to_u16(&out->frames[0], v, in->width * sizeof *v))) {
			size_t sat = 0;
			for (size_t i = 0; i < npix; i++) {
				sat += v[i] >= sim->max_dn;
				fv[i] = v[i];
			}
			out->saturated_fraction = (double)sat / (double)npix;
			out->median_dn = select_kth(fv, npix, npix / 2);
			out->p99_dn = select_kth(fv, npix, (size_t)(0.99 * (double)(npix - 1)));
		}
		free(v);
		free(fv);
	}
	if (!rc) {
		/* the scene as written: exposure chosen, dataset mesh paths */
		uint64_t ss;
		double e2;
		json_decref(sc);
		sc = build_scene(f, seed, index, true, &ss, &e2);
		json_object_set_new(json_object_get(sc, "sensor"), "exposure_us",
		                    json_real(exposure_us));
		out->scene_json =
		    json_dumps(sc, JSON_INDENT(1) | JSON_REAL_PRECISION(17) | JSON_PRESERVE_ORDER);
		if (!out->scene_json)
			rc = pc_error(PC_ENOMEM, "scene text");
	}
	json_decref(sc);
	pc_sim_free(sim);
	pc_scene_free(scene);
	if (rc) {
		pc_family_sample_free(out);
		return pc_error_prefix(rc, "sample %llu: ", (unsigned long long)index);
	}
	return 0;
}
