/* sim/obj.c - Wavefront OBJ triangle meshes: v, vn and f records (polygons fan-triangulated,
 * negative indices relative); everything else (vt, g, o, s, usemtl, mtllib, l, p) is ignored.
 * Errors name the file and line. */
#include <errno.h>
#include <limits.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "scene_impl.h"

#define OBJ_MAX_ELEMS (1u << 26)

typedef struct grow {
	void *p;
	size_t n, cap, elem;
} grow;

static int grow_push(grow *g, const void *x)
{
	if (g->n == g->cap) {
		size_t nc = g->cap ? g->cap * 2 : 256;
		void *np = realloc(g->p, nc * g->elem);
		if (!np)
			return -1;
		g->p = np;
		g->cap = nc;
	}
	memcpy((char *)g->p + g->n * g->elem, x, g->elem);
	g->n++;
	return 0;
}

void pc_mesh_free(pc_mesh *m)
{
	if (!m)
		return;
	free(m->v);
	free(m->vn);
	free(m->tri);
	free(m->tri_n);
	free(m->nodes);
	free(m->tri_order);
	free(m);
}

/* An OBJ index: optional '-', decimal digits; *end after it. 0 and *out, or -1. */
static int parse_index(const char *p, long *out, const char **end)
{
	const char *q = p;
	bool neg = *q == '-';
	if (neg)
		q++;
	if (*q < '0' || *q > '9')
		return -1;
	long v = 0;
	for (; *q >= '0' && *q <= '9'; q++) {
		if (v > (LONG_MAX - 9) / 10)
			return -1;
		v = v * 10 + (*q - '0');
	}
	*out = neg ? -v : v;
	*end = q;
	return 0;
}

/* Parses "a", "a/b", "a/b/c" or "a//c" (nothing else in the token); returns 0 and the 0-based
 * vertex/normal indices (normal −1 when absent). */
static int parse_face_vertex(const char *tok, size_t nv, size_t nn, long *vi, long *ni,
                             const char **why)
{
	const char *p;
	long v, t, n = 0;
	if (parse_index(tok, &v, &p)) {
		*why = "not an integer vertex index";
		return -1;
	}
	if (*p == '/') {
		p++;
		if (*p != '/' && parse_index(p, &t, &p)) { /* texture index: checked, unused */
			*why = "not an integer texture index after '/'";
			return -1;
		}
		if (*p == '/') {
			p++;
			if (parse_index(p, &n, &p)) {
				*why = "not an integer normal index after the second '/'";
				return -1;
			}
			if (n == 0) {
				*why = "normal index 0 (OBJ indices start at 1)";
				return -1;
			}
		}
	}
	if (*p) {
		*why =
		    "unexpected characters after the indices (expected v, v/vt, v/vt/vn or v//vn)";
		return -1;
	}
	if (v < 0 && (size_t)(-v) <= nv)
		v = (long)nv + v + 1;
	if (v < 1 || (size_t)v > nv) {
		*why = "vertex index out of range";
		return -1;
	}
	*vi = v - 1;
	if (n) {
		if (n < 0 && (size_t)(-n) <= nn)
			n = (long)nn + n + 1;
		if (n < 1 || (size_t)n > nn) {
			*why = "normal index out of range";
			return -1;
		}
		*ni = n - 1;
	} else {
		*ni = -1;
	}
	return 0;
}

int pc_obj_load(const char *path, const pc_m3 *rot, pc_v3 scale, pc_v3 translate, bool smooth,
                pc_mesh **out)
{
	*out = NULL;
	FILE *fp = fopen(path, "r");
	if (!fp)
		return pc_error(PC_ENOENT, "%s: cannot open OBJ file", path);
	grow V = {NULL, 0, 0, sizeof(pc_v3)}, N = {NULL, 0, 0, sizeof(pc_v3)};
	grow T = {NULL, 0, 0, 3 * sizeof(uint32_t)}, TN = {NULL, 0, 0, 3 * sizeof(uint32_t)};
	char line[4096];
	long lineno = 0;
	/* the mesh's size limit (polarcam/limits.h); a malformed variable is reported here */
	int rc = pc_limit_check(PC_LIMIT_TRIANGLES, 0, path);
	const uint64_t tri_max = pc_limit_get(PC_LIMIT_TRIANGLES);
	if (rc) {
		fclose(fp);
		return rc;
	}
	bool any_missing_normal = false;
	while (fgets(line, sizeof line, fp)) {
		lineno++;
		size_t len = strlen(line);
		if (len == sizeof line - 1 && line[len - 1] != '\n') {
			rc = pc_error(PC_EFORMAT, "%s: line %ld: longer than %zu characters", path,
			              lineno, sizeof line - 2);
			goto done;
		}
		char *p = line;
		while (*p == ' ' || *p == '\t')
			p++;
		if (p[0] == 'v' && (p[1] == ' ' || p[1] == '\t' ||
		                    (p[1] == 'n' && (p[2] == ' ' || p[2] == '\t')))) {
			bool is_n = p[1] == 'n';
			double a[3];
			char *q = p + (is_n ? 2 : 1);
			for (int i = 0; i < 3; i++) {
				char *end;
				a[i] = strtod(q, &end);
				if (end == q || !isfinite(a[i])) {
					rc = pc_error(PC_EFORMAT,
					              "%s: line %ld: %s record needs 3 finite "
					              "numbers",
					              path, lineno, is_n ? "vn" : "v");
					goto done;
				}
				q = end;
			}
			pc_v3 w;
			if (is_n) { /* normals: inverse-transpose of the scale, then the rotation */
				w = m3_apply(rot,
				             v3(a[0] / scale.x, a[1] / scale.y, a[2] / scale.z));
				w = v3_unit(w);
			} else {
				w = v3_add(m3_apply(rot, v3(a[0] * scale.x, a[1] * scale.y,
				                            a[2] * scale.z)),
				           translate);
			}
			/* placed in the scene, every coordinate must stay finite (a vertex at 1e300
			 * scaled by 1e10 is not), and not so large that the ray-triangle products
			 * (cubes of coordinates) overflow */
			if (!(fabs(w.x) <= 1e100 && fabs(w.y) <= 1e100 && fabs(w.z) <= 1e100)) {
				rc = pc_error(PC_EFORMAT,
				              "%s: line %ld: %s (%g, %g, %g) is beyond 1e100 "
				              "once scaled, rotated and placed",
				              path, lineno, is_n ? "normal" : "vertex", a[0], a[1],
				              a[2]);
				goto done;
			}
			if ((is_n ? N.n : V.n) >= OBJ_MAX_ELEMS) {
				rc = pc_error(PC_EFORMAT, "%s: line %ld: more than %u records",
				              path, lineno, OBJ_MAX_ELEMS);
				goto done;
			}
			if (grow_push(is_n ? &N : &V, &w)) {
				rc = pc_error(PC_ENOMEM, "%s: line %ld", path, lineno);
				goto done;
			}
		} else if (p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) {
			long vi[3], ni[3], count = 0;
			char *save = NULL;
			for (char *tok = strtok_r(p + 2, " \t\r\n", &save); tok;
			     tok = strtok_r(NULL, " \t\r\n", &save)) {
				long v, n;
				const char *why = "";
				if (parse_face_vertex(tok, V.n, N.n, &v, &n, &why)) {
					rc = pc_error(PC_EFORMAT,
					              "%s: line %ld: face vertex '%s': %s (%zu "
					              "vertices, %zu normals so far)",
					              path, lineno, tok, why, V.n, N.n);
					goto done;
				}
				if (count < 2) {
					vi[count] = v;
					ni[count] = n;
				} else {
					vi[2] = v;
					ni[2] = n;
					uint32_t t[3] = {(uint32_t)vi[0], (uint32_t)vi[1],
					                 (uint32_t)vi[2]};
					uint32_t tn[3] = {0, 0, 0};
					if (ni[0] < 0 || ni[1] < 0 || ni[2] < 0)
						any_missing_normal = true;
					else
						for (int k = 0; k < 3; k++)
							tn[k] = (uint32_t)ni[k];
					if (T.n >= OBJ_MAX_ELEMS) {
						rc = pc_error(PC_ERANGE,
						              "%s: line %ld: more than %u "
						              "triangles",
						              path, lineno, OBJ_MAX_ELEMS);
						goto done;
					}
					if (T.n + 1 > tri_max) {
						char what[4200];
						snprintf(what, sizeof what, "%s: line %ld", path,
						         lineno);
						rc = pc_limit_check(PC_LIMIT_TRIANGLES, T.n + 1,
						                    what);
						goto done;
					}
					if (grow_push(&T, t) || grow_push(&TN, tn)) {
						rc = pc_error(PC_ENOMEM, "%s: line %ld", path,
						              lineno);
						goto done;
					}
					vi[1] = vi[2]; /* fan */
					ni[1] = ni[2];
				}
				count++;
			}
			if (count < 3) {
				rc = pc_error(PC_EFORMAT,
				              "%s: line %ld: a face needs at least 3 vertices",
				              path, lineno);
				goto done;
			}
		}
	}
	if (ferror(fp)) {
		rc = pc_error(PC_EIO, "%s: read error", path);
		goto done;
	}
	if (T.n == 0) {
		rc = pc_error(PC_EFORMAT, "%s: no faces (f records) found", path);
		goto done;
	}
	pc_mesh *m = calloc(1, sizeof *m);
	if (!m) {
		rc = pc_error(PC_ENOMEM, "%s", path);
		goto done;
	}
	m->n_vertices = (unsigned)V.n;
	m->n_triangles = (unsigned)T.n;
	m->v = V.p;
	m->tri = T.p;
	V.p = T.p = NULL;
	if (smooth) {
		if (N.n && !any_missing_normal) {
			m->vn = N.p;
			m->tri_n = TN.p;
			N.p = TN.p = NULL;
		} else {
			/* area-weighted vertex normals from the faces */
			m->vn = calloc(m->n_vertices, sizeof *m->vn);
			m->tri_n = malloc(3 * sizeof(uint32_t) * m->n_triangles);
			if (!m->vn || !m->tri_n) {
				pc_mesh_free(m);
				rc = pc_error(PC_ENOMEM, "%s", path);
				goto done;
			}
			for (unsigned t = 0; t < m->n_triangles; t++) {
				const uint32_t *ix = &m->tri[3 * t];
				pc_v3 c = v3_cross(v3_sub(m->v[ix[1]], m->v[ix[0]]),
				                   v3_sub(m->v[ix[2]], m->v[ix[0]]));
				for (int k = 0; k < 3; k++) {
					m->vn[ix[k]] = v3_add(m->vn[ix[k]], c);
					m->tri_n[3 * t + k] = ix[k];
				}
			}
			for (unsigned i = 0; i < m->n_vertices; i++)
				m->vn[i] = v3_unit(m->vn[i]);
		}
	}
	*out = m;
done:
	free(V.p);
	free(N.p);
	free(T.p);
	free(TN.p);
	fclose(fp);
	return rc;
}
