/* io/json.h - internal to the library (not installed; jansson types): reading JSON documents
 * with errors that name the file and the field path, and the small builders every writer of JSON
 * in the library shares. One module for every jansson user: scene files (sim/scene.c),
 * recordings' meta.json and states.json (devices), the output folders (io, devices).
 *
 * Messages read "FILE: PATH: what was wrong" or "FILE: PATH = VALUE: what it must be", with PATH
 * the field's path in the document ("objects[2].material.sigma", "frames[3].sequence", "psa[1]").
 */
#ifndef POLARCAM_IO_JSON_H
#define POLARCAM_IO_JSON_H

#include <jansson.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The document being read: its name in messages, and the error code a bad value gets (PC_EINVAL
 * for documents a user writes, such as scene files; PC_EFORMAT for files polarcam writes). */
typedef struct pc_json_src {
	const char *file;
	int code;
} pc_json_src;

enum { PC_JSON_OPTIONAL = 0, PC_JSON_REQUIRED = 1 };

/* Sets the error detail "FILE: PATH: MESSAGE" ("FILE: PATH = ..." when MESSAGE starts with "= ",
 * "FILE: MESSAGE" for an empty PATH) and returns src->code. */
int pc_json_error(const pc_json_src *src, const char *path, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* "an object", "an array", "a string", "a number", "a boolean", "null" (for messages). */
const char *pc_json_kind(const json_t *v);

/* PATH.KEY and PATH[I] into dst (paths only appear in messages: a long one is cut short). */
void pc_json_path(char *dst, size_t size, const char *path, const char *key);
void pc_json_path_index(char *dst, size_t size, const char *path, size_t i);

/* Fails unless v is an object. */
int pc_json_need_object(const pc_json_src *src, const json_t *v, const char *path);
/* Unknown fields are errors (a typo must not silently become a default): every key of obj must
 * be in allowed (NULL-terminated); the message lists them. */
int pc_json_check_keys(const pc_json_src *src, json_t *obj, const char *path,
                       const char *const *allowed);

/* Typed fields of obj. Absent: an error when required, else 0 with *out untouched. */
/* A finite number in [lo, hi] (open at lo when lo_open; hi = INFINITY for none). */
int pc_json_get_num(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, double lo, bool lo_open, double hi, double *out);
/* An integer in [lo, hi]. */
int pc_json_get_int(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, long lo, long hi, long *out);
/* A non-negative integer up to max. */
int pc_json_get_u64(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, uint64_t max, uint64_t *out);
int pc_json_get_bool(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                     int required, bool *out);
/* A string (valid while the document lives). */
int pc_json_get_str(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                    int required, const char **out);
/* An array of exactly n finite numbers. */
int pc_json_get_nums(const pc_json_src *src, json_t *obj, const char *path, const char *key,
                     int required, double *out, size_t n);
/* The same for a value already in hand (an array element); path names it. */
int pc_json_nums(const pc_json_src *src, const json_t *v, const char *path, double *out, size_t n);

/* Reads and parses a file (duplicate keys refused): PC_ENOENT when it cannot be opened,
 * PC_EFORMAT "FILE: line L: ..." for bad JSON or (when need_object) a document that is not an
 * object. */
int pc_json_load(const char *path, bool need_object, json_t **out);

/* Builders. Non-finite numbers become null. */
json_t *pc_json_real(double v);
json_t *pc_json_vec(const double *v, unsigned n);
json_t *pc_json_matrix4(const double m[4][4]);

/* Compact text of v (17 significant digits), malloc'd; NULL (detail set) when out of memory. */
char *pc_json_text(const json_t *v);

#endif
