/* polarcam/limits.h - size limits for untrusted input, with defaults a user can change.
 *
 * A file header, a scene or a mesh can ask for any size; the readers and the simulator check
 * these limits before they decode or allocate anything, so that a 400-byte header claiming
 * 100000 × 100000 pixels fails at once with a message instead of allocating gigabytes.
 *
 * Each limit has a default, an environment variable that replaces it for the process, and
 * pc_limit_set() for programs. Values are positive integers, optionally with a suffix: k, M, G,
 * T (powers of 1000) or Ki, Mi, Gi, Ti (powers of 1024), e.g. POLARCAM_MAX_PIXELS=400M.
 *
 *   limit               environment variable        default
 *   PC_LIMIT_PIXELS     POLARCAM_MAX_PIXELS         100 M pixels (20× a 5 MP IMX250MZR frame)
 *   PC_LIMIT_BYTES      POLARCAM_MAX_BYTES          4 GiB for one decoded image or array
 *   PC_LIMIT_TRIANGLES  POLARCAM_MAX_TRIANGLES      16 Mi triangles in one mesh
 *   PC_LIMIT_MEMORY     POLARCAM_MAX_MEMORY         0 = the memory available (MemAvailable)
 *   PC_LIMIT_FRAMES     POLARCAM_MAX_FRAMES         999999 frames in one recording (its file
 *                                                   names raw_NNNNNN.png hold no more)
 *
 * Thread safety: pc_limit_get/pc_limit_check may be called from any thread; pc_limit_set is
 * for start-up (not synchronised with readers running at the same time).
 */
#ifndef POLARCAM_LIMITS_H
#define POLARCAM_LIMITS_H

#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_limit {
	PC_LIMIT_PIXELS = 0, /* pixels (width × height) of one image: files, scene resolution */
	PC_LIMIT_BYTES,      /* bytes one reader allocates for one decoded image or array */
	PC_LIMIT_TRIANGLES,  /* triangles of one mesh (OBJ) */
	PC_LIMIT_MEMORY,     /* bytes a render may hold (0: the memory the system has available) */
	PC_LIMIT_FRAMES,     /* frames of one recording: render -n, capture -n, meta.json */
	PC_LIMIT_COUNT
} pc_limit;

#define PC_LIMIT_PIXELS_DEFAULT    100000000ull
#define PC_LIMIT_BYTES_DEFAULT     (4ull << 30)
#define PC_LIMIT_TRIANGLES_DEFAULT (16ull << 20)
#define PC_LIMIT_MEMORY_DEFAULT    0ull
#define PC_LIMIT_FRAMES_DEFAULT    999999ull

/* The value in force: pc_limit_set's, else the environment variable's, else the default. An
 * environment variable that does not parse is ignored here; pc_limit_check reports it. */
PC_API uint64_t pc_limit_get(pc_limit which);

/* Replaces the limit for this process (0 restores the environment variable or default).
 * PC_EINVAL for an unknown limit. */
PC_API int pc_limit_set(pc_limit which, uint64_t value);

/* The environment variable of a limit ("POLARCAM_MAX_PIXELS"), NULL for an unknown one. */
PC_API const char *pc_limit_env(pc_limit which);

/* 0 when value <= the limit. Otherwise PC_ERANGE with a detail such as
 * "<what>: 400000000 pixels exceed the limit of 100000000 (set POLARCAM_MAX_PIXELS to allow
 * more)"; PC_EINVAL naming the variable when its text is not a valid size. PC_LIMIT_MEMORY with
 * value 0 means "no limit set": it always passes here (callers compare with what is
 * available). */
PC_API int pc_limit_check(pc_limit which, uint64_t value, const char *what);

/* Parses a size as the environment variables take it ("400M", "4Gi", "12345"): 0 and *out,
 * or PC_EINVAL. */
PC_API int pc_limit_parse(const char *text, uint64_t *out);

#ifdef __cplusplus
}
#endif
#endif
