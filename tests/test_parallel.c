/* The row-band walker (polarcam/parallel.h): every row in exactly one band, bands of fixed
 * band_rows as asked, and the tapered bands of band_rows 0 as the header states them (each
 * 1/(threads + 1) of the rows left, at least max(8, height/(32·threads)), the same boundaries
 * whatever thread claims them), checked against a serial model of that rule, for heights from
 * 0 to a 5-megapixel frame's and 1 to 5 threads; and the same walk with a chosen smallest band
 * (pc_parallel_rows_tapered, core's own: the row-cache demosaickers take 64 rows). */
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../core/parallel_internal.h"
#include "check.h"
#include "polarcam/parallel.h"

#define MAXH 2100

typedef struct walk {
	_Atomic int cover[MAXH];  /* how many bands covered each row */
	_Atomic int start[MAXH];  /* 1 where a band starts */
	_Atomic int length[MAXH]; /* the band's length at its start */
	_Atomic int bad;          /* a band outside [0, height) or empty */
	uint32_t height;
} walk;

static void record(void *ctx, uint32_t y0, uint32_t y1)
{
	walk *w = ctx;
	if (y1 <= y0 || y1 > w->height) {
		atomic_fetch_add(&w->bad, 1);
		return;
	}
	atomic_fetch_add(&w->start[y0], 1);
	atomic_store(&w->length[y0], (int)(y1 - y0));
	for (uint32_t y = y0; y < y1; y++)
		atomic_fetch_add(&w->cover[y], 1);
}

/* pc_parallel_rows(height, band_rows, ...), or with min_rows > 0 the tapered walk with that
 * smallest band */
static walk *run_min(uint32_t height, uint32_t band_rows, uint32_t min_rows, int threads)
{
	walk *w = calloc(1, sizeof *w);
	if (!w)
		abort();
	w->height = height;
	if (min_rows)
		pc_parallel_rows_tapered(height, min_rows, threads, record, w);
	else
		pc_parallel_rows(height, band_rows, threads, record, w);
	return w;
}

static walk *run(uint32_t height, uint32_t band_rows, int threads)
{
	return run_min(height, band_rows, 0, threads);
}

static void check_cover(const walk *w, const char *what, uint32_t height, int threads)
{
	int once = 1;
	for (uint32_t y = 0; y < height; y++)
		once &= atomic_load(&w->cover[y]) == 1;
	if (!once)
		fprintf(stderr, "%s: height %u, %d threads: a row not covered exactly once\n", what,
		        height, threads);
	CHECK(once);
	CHECK_EQ_INT(atomic_load(&w->bad), 0);
}

int main(void)
{
	const uint32_t heights[] = {0, 1, 7, 8, 9, 31, 64, 100, 255, 1000, 2047, 2048, 2100};
	const int nh = (int)(sizeof heights / sizeof heights[0]);
	/* fixed bands: every band band_rows long but the last */
	for (int k = 0; k < nh; k++)
		for (int t = 1; t <= 4; t++) {
			const uint32_t h = heights[k], b = 16;
			walk *w = run(h, b, t);
			check_cover(w, "fixed bands", h, t);
			if (t > 1)
				for (uint32_t y = 0; y < h; y++)
					if (atomic_load(&w->start[y])) {
						CHECK_EQ_INT(y % b, 0);
						CHECK_EQ_INT(atomic_load(&w->length[y]),
						             y + b < h ? b : h - y);
					}
			free(w);
		}
	/* tapered bands: the header's rule, modelled serially; then with smallest bands of 64 and
	 * 1 rows (m = 1, 2) */
	for (int m = 0; m < 3; m++)
		for (int k = 0; k < nh; k++)
			for (int t = 1; t <= 5; t++) {
				const uint32_t h = heights[k];
				walk *w = run_min(h, 0, m == 1 ? 64 : m == 2 ? 1 : 0, t);
				check_cover(w, "tapered bands", h, t);
				uint32_t min = h / (32u * (uint32_t)t);
				if (min < 8)
					min = 8;
				if (m)
					min = m == 1 ? 64 : 1;
				if (t == 1 || h <= min) {
					/* one band, in the caller's thread */
					if (h)
						CHECK_EQ_INT(atomic_load(&w->length[0]), h);
					free(w);
					continue;
				}
				uint32_t at = 0, nb = 0;
				while (at < h) {
					uint32_t n = (h - at) / (uint32_t)(t + 1);
					n = n < min ? min : n;
					n = n > h - at ? h - at : n;
					CHECK_EQ_INT(atomic_load(&w->start[at]), 1);
					CHECK_EQ_INT(atomic_load(&w->length[at]), n);
					at += n;
					nb++;
				}
				/* bands taper: a 5-megapixel frame's 2048 rows on two threads in 11
				 * bands, the first 682 rows, the last ones 32 or fewer */
				if (h == 2048 && t == 2 && m == 0) {
					CHECK_EQ_INT(nb, 11);
					CHECK_EQ_INT(atomic_load(&w->length[0]), 682);
				}
				if (h == 2048 && t == 2 &&
				    m == 1) /* 682 455 303 202 135 90 64 64 53 */
					CHECK_EQ_INT(nb, 9);
				free(w);
			}
	return pc_test_finish("test_parallel");
}
