/* libFuzzer harness: `polarcam decompose --batch` lines of 16 numbers. Property oracle: the
 * decomposition of any finite matrix returns 0; with the Cloude filter (the CLI default) D and
 * Δ are in [0, 1] wherever defined and R in [0, π]; a matrix that passes the realisability check
 * decomposes without filtering to D ≤ 1 (+rounding); the vector map kernel gives the same bits
 * as the scalar code. */
#include <math.h>

#include "fuzz_batch.h"
#include "fuzz_lu_chipman.h"
#include "polarcam/decompose.h"
#include "polarcam/optics.h"

static void fuzz_batch_line(const double *v, const uint8_t *data, size_t size)
{
	(void)data;
	(void)size;
	double M[4][4];
	memcpy(M, v, sizeof M);
	pc_lu_chipman lc = fuzz_lc_ranges(M);
	if (lc.physical && !(lc.flags & PC_LC_ZERO_M00)) {
		pc_lu_chipman u;
		pc_lu_chipman_decompose(M, 0, &u);
		FUZZ_ASSERT(u.D <= 1 + 1e-6, "physical matrix with D = %.17g", u.D);
	}
	fuzz_lc_map_vs_scalar(M);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const names[16] = {"m00", "m01", "m02", "m03", "m10", "m11",
	                                      "m12", "m13", "m20", "m21", "m22", "m23",
	                                      "m30", "m31", "m32", "m33"};
	fuzz_batch(data, size, names, 16);
	return 0;
}
