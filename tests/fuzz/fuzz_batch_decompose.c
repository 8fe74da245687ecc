/* libFuzzer harness: `polarcam decompose --batch` lines of 16 numbers. Property oracle: the
 * decomposition of any finite matrix returns 0; with the Cloude filter (the CLI default) D and
 * Δ are in [0, 1] wherever defined and R in [0, π]; a matrix that passes the realisability check
 * decomposes without filtering to D ≤ 1 (+rounding); the vector map kernel gives the same bits
 * as the scalar code. */
#include <math.h>

#include "fuzz_batch.h"
#include "polarcam/decompose.h"
#include "polarcam/optics.h"

static bool same(double a, double b)
{
	return (isnan(a) && isnan(b)) || memcmp(&a, &b, sizeof a) == 0;
}

static void fuzz_batch_line(const double *v, const uint8_t *data, size_t size)
{
	(void)data;
	(void)size;
	double M[4][4];
	memcpy(M, v, sizeof M);
	pc_lu_chipman lc;
	FUZZ_ASSERT(pc_lu_chipman_decompose(M, PC_LC_FILTER, &lc) == 0, "%s", pc_error_detail());
	if (!(lc.flags & PC_LC_ZERO_M00)) {
		FUZZ_ASSERT(lc.D >= 0 && lc.D <= 1, "D = %.17g", lc.D);
		if (!(lc.flags & (PC_LC_D_SINGULAR | PC_LC_ZERO_M00))) {
			FUZZ_ASSERT(lc.Delta >= 0 && lc.Delta <= 1, "Delta = %.17g", lc.Delta);
			FUZZ_ASSERT(lc.R >= 0 && lc.R <= M_PI + 1e-12, "R = %.17g", lc.R);
		}
	}
	if (lc.physical && !(lc.flags & PC_LC_ZERO_M00)) {
		pc_lu_chipman u;
		pc_lu_chipman_decompose(M, 0, &u);
		FUZZ_ASSERT(u.D <= 1 + 1e-6, "physical matrix with D = %.17g", u.D);
	}
	for (unsigned opt = 0; opt <= PC_LC_FILTER; opt += PC_LC_FILTER) {
		pc_lu_chipman s;
		pc_lu_chipman_decompose(M, opt | PC_LC_NO_FACTORS, &s);
		double D, R, Delta;
		unsigned flags;
		pc_lc_map mo;
		memset(&mo, 0, sizeof mo);
		mo.D = &D;
		mo.R = &R;
		mo.Delta = &Delta;
		mo.flags = &flags;
		FUZZ_ASSERT(pc_lu_chipman_map(&M[0][0], 1, opt, &mo) == 0, "map");
		FUZZ_ASSERT(same(D, s.D) && same(R, s.R) && same(Delta, s.Delta) &&
		                flags == s.flags,
		            "map %g %g %g %#x, scalar %g %g %g %#x", D, R, Delta, flags, s.D, s.R,
		            s.Delta, s.flags);
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const names[16] = {"m00", "m01", "m02", "m03", "m10", "m11",
	                                      "m12", "m13", "m20", "m21", "m22", "m23",
	                                      "m30", "m31", "m32", "m33"};
	fuzz_batch(data, size, names, 16);
	return 0;
}
