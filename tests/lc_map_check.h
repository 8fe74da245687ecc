/* tests/lc_map_check.h - the Lu–Chipman map kernel against the scalar path on one matrix:
 * pc_lu_chipman_map (the vector kernel, which hands extreme magnitudes to the scalar code) must
 * give the bits of pc_lu_chipman_decompose with PC_LC_NO_FACTORS for D, R, Δ and the flags, a
 * NaN matching a NaN. Shared by test_hard_cases.c and the fuzz harnesses (fuzz/fuzz_lu_chipman.h);
 * each caller asserts in its own way. */
#ifndef POLARCAM_TESTS_LC_MAP_CHECK_H
#define POLARCAM_TESTS_LC_MAP_CHECK_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "polarcam/decompose.h"

static inline bool lc_same_bits(double a, double b)
{
	return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

typedef struct {
	int map_status;  /* pc_lu_chipman_map's return value (0: success) */
	bool same;       /* D, R, Δ and flags equal bit for bit */
	pc_lu_chipman s; /* the scalar path's result */
	double D, R, Delta;
	unsigned flags; /* the map kernel's results */
} lc_map_check;

/* opt: 0 or PC_LC_FILTER */
static inline lc_map_check lc_map_vs_scalar(const double M[4][4], unsigned opt)
{
	lc_map_check c;
	memset(&c, 0, sizeof c);
	pc_lu_chipman_decompose(M, opt | PC_LC_NO_FACTORS, &c.s);
	pc_lc_map mo;
	memset(&mo, 0, sizeof mo);
	mo.D = &c.D;
	mo.R = &c.R;
	mo.Delta = &c.Delta;
	mo.flags = &c.flags;
	c.map_status = pc_lu_chipman_map(&M[0][0], 1, opt & PC_LC_FILTER, &mo);
	c.same = c.map_status == 0 && lc_same_bits(c.D, c.s.D) && lc_same_bits(c.R, c.s.R) &&
	         lc_same_bits(c.Delta, c.s.Delta) && c.flags == c.s.flags;
	return c;
}

#endif
