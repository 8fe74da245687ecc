/* The fast paths' scratch memory (demosaic_common.h, pc_dm_alloc): 64-byte aligned blocks
 * writable over the size asked plus 64 bytes; with the pool on, a freed block of up to 4 MB is
 * handed out again to a request of the same size and to one request only, blocks above 4 MB
 * and beyond the pool's 32 MB are not kept (a full pool makes room for a new size by dropping
 * older blocks), pc_dm_pool_release empties it; with
 * POLARCAM_SCRATCH_POOL=0 (ctest runs this program a second time so) or under
 * AddressSanitizer nothing is kept. Threads allocating and freeing blocks of a few sizes at
 * once never share a block: each fills its blocks with its own pattern and checks it before
 * freeing. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "../core/demosaic_common.h"
#include "check.h"

/* CHECK with a message (cond is evaluated twice: pure expressions only) */
#define CHECKM(cond, ...)                                                                          \
	do {                                                                                       \
		CHECK(cond);                                                                       \
		if (!(cond)) {                                                                     \
			fprintf(stderr, "  ");                                                     \
			fprintf(stderr, __VA_ARGS__);                                              \
			fputc('\n', stderr);                                                       \
		}                                                                                  \
	} while (0)

static int aligned_and_writable(void)
{
	int bad = 0;
	const size_t sizes[] = {1, 63, 64, 65, 1000, 4096, 100000, 5u << 20};
	for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
		unsigned char *p = pc_dm_alloc(sizes[i]);
		if (!p || ((uintptr_t)p & 63)) {
			fprintf(stderr, "pc_dm_alloc(%zu): %p not 64-byte aligned\n", sizes[i],
			        (void *)p);
			bad++;
			pc_dm_free(p);
			continue;
		}
		memset(p, 0xa5, sizes[i] + 64); /* the slack the kernels may read */
		pc_dm_free(p);
	}
	pc_dm_free(NULL);
	CHECKM(pc_dm_alloc(SIZE_MAX - 10) == NULL, "a size that would wrap: NULL");
	return bad;
}

static int pooled(int on)
{
	int bad = 0;
	pc_dm_pool_release();
	CHECKM(pc_dm_pool_bytes() == 0, "pool empty after release");
	void *a = pc_dm_alloc(1000), *b = pc_dm_alloc(1000);
	CHECKM(a && b && a != b, "two live blocks are distinct");
	pc_dm_free(a);
	void *c = pc_dm_alloc(1000), *d = pc_dm_alloc(1000);
	if (on) {
		CHECKM(c == a, "a freed block is handed out again to a request of its size");
		CHECKM(d != a && d != b, "and to one request only");
	}
	CHECKM(c != b && d != c, "live blocks stay distinct");
	pc_dm_free(b);
	void *e = pc_dm_alloc(2000); /* b (1000 bytes) is pooled now, and too small */
	CHECKM(e != b && e != c && e != d, "another size gets another block");
	pc_dm_free(c);
	pc_dm_free(d);
	pc_dm_free(e);
	size_t held = pc_dm_pool_bytes();
	if (on)
		CHECKM(held >= 3 * 1000 + 2000 && held <= 4 * 1200 + 2200,
		       "the pool holds the four freed blocks (%zu bytes)", held);
	else
		CHECKM(held == 0, "nothing kept with the pool off (%zu bytes)", held);

	/* above 4 MB: not kept */
	pc_dm_pool_release();
	void *big = pc_dm_alloc(5u << 20);
	CHECKM(big != NULL, "5 MB block");
	pc_dm_free(big);
	CHECKM(pc_dm_pool_bytes() == 0, "a 5 MB block is not kept (%zu bytes)", pc_dm_pool_bytes());

	/* forty 1 MB blocks freed: at most 32 MB kept, and with the pool on, all but one MB of it
	 */
	enum { N = 40 };
	void *m[N];
	for (int i = 0; i < N; i++)
		m[i] = pc_dm_alloc(1u << 20);
	for (int i = 0; i < N; i++)
		pc_dm_free(m[i]);
	held = pc_dm_pool_bytes();
	CHECKM(held <= (size_t)32 << 20, "the pool stays within 32 MB (%zu bytes)", held);
	if (on)
		CHECKM(held > (size_t)30 << 20, "and fills it (%zu bytes)", held);
	/* a full pool still keeps a block of a new size (older blocks make room): the next request
	 * of that size takes it out (the pool's bytes drop by the block's: the size asked, 64
	 * bytes of slack) */
	void *x = pc_dm_alloc(2u << 20);
	pc_dm_free(x);
	size_t before = pc_dm_pool_bytes();
	void *y = pc_dm_alloc(2u << 20);
	if (on)
		CHECKM(y == x && before - pc_dm_pool_bytes() == (2u << 20) + 64,
		       "a full pool keeps a freed block of a new size (%zu -> %zu bytes)", before,
		       pc_dm_pool_bytes());
	pc_dm_free(y);
	CHECKM(pc_dm_pool_bytes() <= (size_t)32 << 20, "still within 32 MB (%zu bytes)",
	       pc_dm_pool_bytes());
	pc_dm_pool_release();
	CHECKM(pc_dm_pool_bytes() == 0, "pool empty after release");
	return bad;
}

/* threads allocating and freeing at once: a block given to two of them would fail a check */
static int threads_never_share(void)
{
	int bad = 0;
	const size_t sizes[] = {256, 4096, 20000, 300000};
#ifdef _OPENMP
#pragma omp parallel num_threads(4) reduction(+ : bad)
#endif
	{
		int id = 1;
#ifdef _OPENMP
		id = omp_get_thread_num() + 1;
#endif
		uint32_t rng = 2463534242u * (uint32_t)id;
		for (int it = 0; it < 4000; it++) {
			rng ^= rng << 13;
			rng ^= rng >> 17;
			rng ^= rng << 5;
			size_t n = sizes[rng % 4];
			unsigned char *p = pc_dm_alloc(n);
			if (!p) {
				bad++;
				continue;
			}
			memset(p, id, n);
			for (volatile int spin = 0; spin < (int)(rng >> 28); spin++)
				;
			for (size_t k = 0; k < n; k += 61)
				if (p[k] != (unsigned char)id) {
					bad++;
					break;
				}
			pc_dm_free(p);
		}
	}
	CHECKM(bad == 0, "threads never saw another thread's pattern in their blocks (%d)", bad);
	return 0;
}

int main(void)
{
	const char *env = getenv("POLARCAM_SCRATCH_POOL");
	int off_asked = env && strcmp(env, "0") == 0;
	int on = pc_dm_pool_enabled();
	if (off_asked)
		CHECKM(!on, "POLARCAM_SCRATCH_POOL=0 turns the pool off");
	printf("scratch pool %s\n",
	       on ? "on" : "off (AddressSanitizer or POLARCAM_SCRATCH_POOL=0)");
	int bad = aligned_and_writable();
	bad += pooled(on);
	bad += threads_never_share();
	pc_dm_pool_release();
	CHECKM(bad == 0, "%d blocks misaligned or not allocated", bad);
	return pc_test_finish("test_scratch");
}
