/* A small deterministic random stream for tests: Marsaglia's xorshift64 (J. Stat. Softw. 8(14),
 * 2003, shifts 13, 7, 17), uniform in (0, 1) from the top 53 bits, normal by Box–Muller.
 * Define PC_TEST_SEED (a non-zero uint64_t constant) before including; one stream per test. */
#ifndef PC_TESTS_XORSHIFT_H
#define PC_TESTS_XORSHIFT_H

#include <math.h>
#include <stdint.h>

#ifndef PC_TEST_SEED
#error "define PC_TEST_SEED before including xorshift.h"
#endif

static uint64_t rs = PC_TEST_SEED;

static double urand(void)
{
	rs ^= rs << 13;
	rs ^= rs >> 7;
	rs ^= rs << 17;
	return ((double)(rs >> 11) + 0.5) / 9007199254740992.0;
}

static double nrand(void)
{
	return sqrt(-2 * log(urand())) * cos(2 * M_PI * urand());
}

#endif
