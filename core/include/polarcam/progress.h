/* polarcam/progress.h - progress of long library calls, as a callback (the library never
 * prints).
 *
 * A call that takes a pc_progress_fn calls it from the calling thread as work gets done: phase
 * names the step ("render", "frames", "mueller"; a call may have several, each counting from 0
 * to its own total), done and total count the step's units (rows, frames). Returning non-zero
 * asks the call to stop: it then returns PC_ECANCELED as soon as it can, leaving what it has
 * written complete and saying so (recordings: complete = false). A NULL callback is never
 * called.
 */
#ifndef POLARCAM_PROGRESS_H
#define POLARCAM_PROGRESS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef int (*pc_progress_fn)(void *user, const char *phase, uint64_t done, uint64_t total);

/* A progress callback and its user pointer, as the calls take them. */
typedef struct pc_progress {
	pc_progress_fn fn; /* NULL: no progress */
	void *user;
} pc_progress;

/* Calls p's callback when there is one: its answer, 0 otherwise (p may be NULL). */
static inline int pc_progress_report(const pc_progress *p, const char *phase, uint64_t done,
                                     uint64_t total)
{
	return p && p->fn ? p->fn(p->user, phase, done, total) : 0;
}

#ifdef __cplusplus
}
#endif
#endif
