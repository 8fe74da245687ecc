/* polarcam/parallel.h - the one row-band walker.
 *
 * Kernels are written as row-band workers fn(ctx, y0, y1). pc_parallel_rows() runs them over
 * [0, height) in bands, on OpenMP threads when built with OpenMP, in the caller's thread
 * otherwise. The library never starts threads of its own beyond this.
 */
#ifndef POLARCAM_PARALLEL_H
#define POLARCAM_PARALLEL_H

#include <stdint.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef void (*pc_rows_fn)(void *ctx, uint32_t y0, uint32_t y1);

/* Runs fn over rows [0, height) in bands of band_rows, with at most threads threads (0:
 * pc_parallel_max_threads()). band_rows 0: tapered bands, each 1/(threads + 1) of the rows
 * left and at least max(8, height/(32·threads)) rows, handed out in order as threads come free
 * (large bands first, small ones last, so that the threads finish together); the band
 * boundaries depend only on height and threads. */
PC_API void pc_parallel_rows(uint32_t height, uint32_t band_rows, int threads, pc_rows_fn fn,
                             void *ctx);

/* The threads pc_parallel_rows uses by default: OpenMP's maximum (OMP_NUM_THREADS), 1 without
 * OpenMP. */
PC_API int pc_parallel_max_threads(void);

#ifdef __cplusplus
}
#endif
#endif
