/* Reading and writing JSON with errors that name the file and the field path (json.h). */
#include "json.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

int pc_json_error(const pc_json_src *src, const char *path, const char *fmt, ...)
{
	char msg[512];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	/* "camera.f_number = -1: must be > 0" or "camera.up: is parallel to ..." */
	const char *sep = !*path ? "" : !strncmp(msg, "= ", 2) ? " " : ": ";
	return pc_error(src->code, "%s: %s%s%s", src->file, path, sep, msg);
}

const char *pc_json_kind(const json_t *v)
{
	if (!v) /* a member that is not there (json_typeof reads through the pointer) */
		return "nothing (the member is missing)";
	switch (json_typeof(v)) {
	case JSON_OBJECT:
		return "an object";
	case JSON_ARRAY:
		return "an array";
	case JSON_STRING:
		return "a string";
	case JSON_INTEGER:
	case JSON_REAL:
		return "a number";
	case JSON_TRUE:
	case JSON_FALSE:
		return "a boolean";
	default:
		return "null";
	}
}

void pc_json_path(char *dst, size_t size, const char *path, const char *key)
{
	if (snprintf(dst, size, "%s%s%s", path, *path ? "." : "", key) >= (int)size)
		dst[size - 1] = '\0';
}

void pc_json_path_index(char *dst, size_t size, const char *path, size_t i)
{
	if (snprintf(dst, size, "%s[%zu]", path, i) >= (int)size)
		dst[size - 1] = '\0';
}

int pc_json_need_object(const pc_json_src *src, const json_t *v, const char *path)
{
	if (!json_is_object(v))
		return pc_json_error(src, path, "expected an object, got %s", pc_json_kind(v));
	return 0;
}

int pc_json_check_keys(const pc_json_src *src, json_t *obj, const char *path,
                       const char *const *allowed)
{
	const char *key;
	json_t *val;
	json_object_foreach(obj, key, val)
	{
		bool ok = false;
		for (const char *const *a = allowed; *a; a++)
			if (!strcmp(key, *a))
				ok = true;
		if (!ok) {
			char list[512] = "";
			for (const char *const *a = allowed; *a; a++) {
				strncat(list, *a, sizeof list - strlen(list) - 1);
				if (a[1])
					strncat(list, ", ", sizeof list - strlen(list) - 1);
			}
			char p[256];
			pc_json_path(p, sizeof p, path, key);
			return pc_json_error(src, p, "unknown field (expected one of: %s)", list);
		}
	}
	return 0;
}

/* The field, or NULL: *rc is then 0 (optional) or the "missing" error. p receives its path. */
static json_t *field(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                     int required, char *p, size_t psize, int *rc)
{
	pc_json_path(p, psize, path, key);
	json_t *v = json_object_get(obj, key);
	*rc = !v && required ? pc_json_error(src, p, "missing (required)") : 0;
	return v;
}

int pc_json_get_num(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, double lo, bool lo_open, double hi, double *out)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	if (!json_is_number(v))
		return pc_json_error(src, p, "expected a number, got %s", pc_json_kind(v));
	double x = json_number_value(v);
	if (!isfinite(x))
		return pc_json_error(src, p, "expected a finite number");
	if (lo_open ? !(x > lo) : !(x >= lo)) {
		if (hi < INFINITY)
			return pc_json_error(src, p, "= %g: must be in %s%g, %g]", x,
			                     lo_open ? "(" : "[", lo, hi);
		return pc_json_error(src, p, "= %g: must be %s %g", x, lo_open ? ">" : "≥", lo);
	}
	if (x > hi)
		return pc_json_error(src, p, "= %g: must be in %s%g, %g]", x, lo_open ? "(" : "[",
		                     lo, hi);
	*out = x;
	return 0;
}

int pc_json_get_int(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, long lo, long hi, long *out)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	if (!json_is_integer(v))
		return pc_json_error(src, p, "expected an integer, got %s", pc_json_kind(v));
	json_int_t x = json_integer_value(v);
	if (x < lo || x > hi)
		return pc_json_error(src, p, "= %lld: must be an integer in [%ld, %ld]",
		                     (long long)x, lo, hi);
	*out = (long)x;
	return 0;
}

int pc_json_get_u64(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, uint64_t max, uint64_t *out)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	if (!json_is_integer(v) || json_integer_value(v) < 0 ||
	    (uint64_t)json_integer_value(v) > max)
		return pc_json_error(src, p, "expected an integer in [0, %llu]",
		                     (unsigned long long)max);
	*out = (uint64_t)json_integer_value(v);
	return 0;
}

int pc_json_get_bool(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                     int required, bool *out)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	if (!json_is_boolean(v))
		return pc_json_error(src, p, "expected true or false, got %s", pc_json_kind(v));
	*out = json_is_true(v);
	return 0;
}

int pc_json_get_str(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, const char **out)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	if (!json_is_string(v))
		return pc_json_error(src, p, "expected a string, got %s", pc_json_kind(v));
	*out = json_string_value(v);
	return 0;
}

int pc_json_nums(const pc_json_src *src, const json_t *v, const char *path, double *out, size_t n)
{
	if (!json_is_array(v) || json_array_size(v) != n)
		return pc_json_error(src, path, "expected an array of %zu numbers, got %s%s", n,
		                     pc_json_kind(v), json_is_array(v) ? " of another length" : "");
	for (size_t i = 0; i < n; i++) {
		json_t *e = json_array_get(v, i);
		if (!json_is_number(e) || !isfinite(json_number_value(e))) {
			char q[288];
			pc_json_path_index(q, sizeof q, path, i);
			return pc_json_error(src, q, "expected a finite number, got %s",
			                     pc_json_kind(e));
		}
		out[i] = json_number_value(e);
	}
	return 0;
}

int pc_json_get_nums(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                     int required, double *out, size_t n)
{
	char p[256];
	int rc;
	json_t *v = field(src, obj, path, key, required, p, sizeof p, &rc);
	if (!v)
		return rc;
	return pc_json_nums(src, v, p, out, n);
}

int pc_json_load(const char *path, bool need_object, json_t **out)
{
	*out = NULL;
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(PC_ENOENT, "%s: cannot open: %s", path, strerror(errno));
	json_error_t je;
	json_t *d = json_loadf(fp, JSON_REJECT_DUPLICATES, &je);
	fclose(fp);
	if (!d)
		return pc_error(PC_EFORMAT, "%s: line %d: %s", path, je.line, je.text);
	if (need_object && !json_is_object(d)) {
		json_decref(d);
		return pc_error(PC_EFORMAT, "%s: expected a JSON object", path);
	}
	*out = d;
	return 0;
}

json_t *pc_json_real(double v)
{
	return isfinite(v) ? json_real(v) : json_null();
}

json_t *pc_json_vec(const double *v, unsigned n)
{
	json_t *a = json_array();
	for (unsigned i = 0; i < n; i++)
		json_array_append_new(a, pc_json_real(v[i]));
	return a;
}

json_t *pc_json_matrix4(const double m[4][4])
{
	json_t *a = json_array();
	for (int i = 0; i < 4; i++)
		json_array_append_new(a, pc_json_vec(m[i], 4));
	return a;
}

char *pc_json_text(const json_t *v)
{
	char *t = json_dumps(v, JSON_COMPACT | JSON_REAL_PRECISION(17));
	if (!t)
		pc_error(PC_ENOMEM, "JSON text");
	return t;
}
