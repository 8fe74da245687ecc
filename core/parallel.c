#include "polarcam/parallel.h"

#ifdef _OPENMP
#include <omp.h>
#endif

int pc_parallel_max_threads(void)
{
#ifdef _OPENMP
	return omp_get_max_threads();
#else
	return 1;
#endif
}

void pc_parallel_rows(uint32_t height, uint32_t band_rows, int threads, pc_rows_fn fn, void *ctx)
{
	if (height == 0)
		return;
	if (threads <= 0)
		threads = pc_parallel_max_threads();
	if (band_rows == 0) {
		/* a few bands per thread balance load without making bands too small for caches */
		band_rows = height / (uint32_t)(threads * 4);
		if (band_rows < 8)
			band_rows = 8;
	}
	long nbands = (long)((height + band_rows - 1) / band_rows);
	if (threads == 1 || nbands == 1) {
		fn(ctx, 0, height);
		return;
	}
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
	for (long b = 0; b < nbands; b++) {
		uint32_t y0 = (uint32_t)b * band_rows;
		uint32_t y1 = y0 + band_rows < height ? y0 + band_rows : height;
		fn(ctx, y0, y1);
	}
}
