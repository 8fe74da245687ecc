/* The Lu–Chipman properties both decomposition harnesses check (fuzz_batch_decompose.c on the
 * CLI's batch lines, fuzz_physics.c on matrices of every scale): for any finite matrix the
 * filtered decomposition returns 0 with D, Δ in [0, 1] and R in [0, π] wherever they are
 * defined, and the vector map kernel (pc_lu_chipman_map) gives the scalar code's bits, with
 * and without the Cloude filter. Needs fuzz.h's FUZZ_ASSERT. */
#ifndef PC_FUZZ_LU_CHIPMAN_H
#define PC_FUZZ_LU_CHIPMAN_H

#include <math.h>
#include <string.h>

#include "polarcam/decompose.h"
#include "polarcam/error.h"

#include "../lc_map_check.h"

/* The filtered decomposition of M, its ranges checked; returned for further checks. */
static inline pc_lu_chipman fuzz_lc_ranges(const double M[4][4])
{
	pc_lu_chipman lc;
	FUZZ_ASSERT(pc_lu_chipman_decompose(M, PC_LC_FILTER, &lc) == 0, "%s", pc_error_detail());
	if (!(lc.flags & PC_LC_ZERO_M00)) {
		FUZZ_ASSERT(lc.D >= 0 && lc.D <= 1, "D = %.17g", lc.D);
		if (!(lc.flags & PC_LC_D_SINGULAR)) {
			FUZZ_ASSERT(lc.Delta >= 0 && lc.Delta <= 1, "Delta = %.17g", lc.Delta);
			FUZZ_ASSERT(lc.R >= 0 && lc.R <= M_PI + 1e-12, "R = %.17g", lc.R);
		}
	}
	return lc;
}

/* The map kernel against the scalar path (PC_LC_NO_FACTORS), unfiltered and filtered. */
static inline void fuzz_lc_map_vs_scalar(const double M[4][4])
{
	for (unsigned opt = 0; opt <= PC_LC_FILTER; opt += PC_LC_FILTER) {
		const lc_map_check c = lc_map_vs_scalar(M, opt);
		FUZZ_ASSERT(c.map_status == 0, "map");
		FUZZ_ASSERT(c.same, "map %g %g %g %#x, scalar %g %g %g %#x", c.D, c.R, c.Delta,
		            c.flags, c.s.D, c.s.R, c.s.Delta, c.s.flags);
	}
}

#endif
