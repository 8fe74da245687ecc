/* Internal to core: pc_parallel_rows' tapered walk with a chosen smallest band. Not a public
 * header. */
#ifndef POLARCAM_PARALLEL_INTERNAL_H
#define POLARCAM_PARALLEL_INTERNAL_H

#include <stdint.h>

#include "polarcam/parallel.h"

/* pc_parallel_rows' tapered bands (band_rows 0), each at least min_rows rows instead of
 * max(8, height/(32·threads)): for kernels that recompute halo rows at every band's start */
void pc_parallel_rows_tapered(uint32_t height, uint32_t min_rows, int threads, pc_rows_fn fn,
                              void *ctx);

#endif
