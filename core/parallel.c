#include "polarcam/parallel.h"

#include "parallel_internal.h"

#ifdef _OPENMP
#include <omp.h>
#include <stdatomic.h>
#endif

int pc_parallel_max_threads(void)
{
#ifdef _OPENMP
	return omp_get_max_threads();
#else
	return 1;
#endif
}

#ifdef _OPENMP
/* Hands out the next band of a tapered walk over [0, height): a 1/(threads + 1) share of the
 * rows left, at least min_rows; 0 rows when none are left. The boundaries depend only on
 * height, threads and min_rows (each claim takes the next one in order), not on which thread
 * claims. */
static uint32_t next_band(_Atomic uint32_t *next, uint32_t height, uint32_t min_rows, int threads,
                          uint32_t *y0)
{
	uint32_t at = atomic_load(next), n;
	do {
		if (at >= height)
			return 0;
		const uint32_t left = height - at;
		n = left / (uint32_t)(threads + 1);
		if (n < min_rows)
			n = min_rows;
		if (n > left)
			n = left;
	} while (!atomic_compare_exchange_weak(next, &at, at + n));
	*y0 = at;
	return n;
}
#endif

void pc_parallel_rows_tapered(uint32_t height, uint32_t min_rows, int threads, pc_rows_fn fn,
                              void *ctx)
{
	if (height == 0)
		return;
	if (threads <= 0)
		threads = pc_parallel_max_threads();
	if (min_rows < 1)
		min_rows = 1;
	if (threads == 1 || height <= min_rows) {
		fn(ctx, 0, height);
		return;
	}
#ifdef _OPENMP
	_Atomic uint32_t next = 0;
#pragma omp parallel num_threads(threads)
	{
		uint32_t y0 = 0, n;
		while ((n = next_band(&next, height, min_rows, threads, &y0)) > 0)
			fn(ctx, y0, y0 + n);
	}
#else
	fn(ctx, 0, height);
#endif
}

void pc_parallel_rows(uint32_t height, uint32_t band_rows, int threads, pc_rows_fn fn, void *ctx)
{
	if (height == 0)
		return;
	if (threads <= 0)
		threads = pc_parallel_max_threads();
	if (threads == 1) {
		fn(ctx, 0, height);
		return;
	}
#ifdef _OPENMP
	if (band_rows == 0) {
		/* Tapered bands: large ones first (little per-band overhead), ever smaller ones at
		 * the end, so that the threads finish together. Eight fixed bands of 2048 / 8 rows
		 * on two threads left one thread idle for about half a band at the end of each
		 * frame on a shared machine (docs/demosaicking.md, Round 25: pan-lean 6-10 % and
		 * the mono bilinear 2-6 % faster with these). */
		uint32_t min_rows = height / (uint32_t)(32 * threads);
		pc_parallel_rows_tapered(height, min_rows < 8 ? 8 : min_rows, threads, fn, ctx);
		return;
	}
	long nbands = (long)((height + band_rows - 1) / band_rows);
	if (nbands == 1) {
		fn(ctx, 0, height);
		return;
	}
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
	for (long b = 0; b < nbands; b++) {
		uint32_t y0 = (uint32_t)b * band_rows;
		uint32_t y1 = y0 + band_rows < height ? y0 + band_rows : height;
		fn(ctx, y0, y1);
	}
#else
	(void)band_rows;
	fn(ctx, 0, height);
#endif
}
