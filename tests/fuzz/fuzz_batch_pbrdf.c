/* libFuzzer harness: `polarcam pbrdf --batch` lines "n k sigma theta_i theta_r phi". Property
 * oracle for every line the CLI would evaluate (θ in [0, 90], a material pc_pbrdf_new accepts):
 * all 16 elements finite; where f00 is a normal double, the matrix physically realisable
 * (coherency matrix PSD, physics.md §2: a sum of pure Jones matrices and a depolariser) and
 * Lu–Chipman of it giving D and Δ in [0, 1] up to rounding. The material options come from the
 * first byte (ρ^s orders kept small so that an execution stays fast). */
#include <float.h>
#include <math.h>

#include "fuzz_batch.h"
#include "polarcam/decompose.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

static void fuzz_batch_line(const double *v, const uint8_t *data, size_t size)
{
	if (!(v[3] >= 0 && v[3] <= 90 && v[4] >= 0 && v[4] <= 90))
		return; /* the CLI refuses these (check_theta) */
	unsigned o = size ? data[0] : 0;
	pc_material m = {v[0],
	                 v[1],
	                 v[2],
	                 (pc_diffuse)(o % 3),
	                 (pc_shadowing)((o >> 2) & 1),
	                 (pc_rho_mode)((o >> 3) & 1),
	                 2 + (int)((o >> 4) & 3)};
	pc_pbrdf *p = NULL;
	if (pc_pbrdf_new(&m, &p) != 0) {
		FUZZ_ASSERT(p == NULL && *pc_error_detail(), "no detail");
		return;
	}
	double f[4][4];
	pc_pbrdf_eval_deg(p, v[3], v[4], v[5], f);
	for (int i = 0; i < 16; i++)
		FUZZ_ASSERT(isfinite(f[i / 4][i % 4]),
		            "f[%d][%d] = %g for n=%g k=%g sigma=%g (%g, %g, %g)", i / 4, i % 4,
		            f[i / 4][i % 4], v[0], v[1], v[2], v[3], v[4], v[5]);
	/* realisable where the matrix holds full precision: a subnormal f00 (n = 1, k = 1.1e-159,
	 * |r|² ≈ 3e-319) keeps a few significant digits, whose rounding alone breaks the check, as
	 * fuzz_physics's Cloude filter (docs/reliability.md; finding_subnormal_pbrdf) */
	if (f[0][0] >= DBL_MIN) {
		FUZZ_ASSERT(pc_mueller_is_physical(f, 1e-9),
		            "not physical: n=%g k=%g sigma=%g (%g, %g, %g), f00 = %g", v[0], v[1],
		            v[2], v[3], v[4], v[5], f[0][0]);
		pc_lu_chipman lc;
		FUZZ_ASSERT(pc_lu_chipman_decompose(f, PC_LC_NO_FACTORS, &lc) == 0, "decompose");
		FUZZ_ASSERT(lc.D >= 0 && lc.D <= 1 + 1e-9, "D = %g", lc.D);
		if (!(lc.flags & PC_LC_D_SINGULAR))
			FUZZ_ASSERT(lc.Delta >= -1e-6 && lc.Delta <= 1 + 1e-6, "Delta = %g",
			            lc.Delta);
	}
	pc_pbrdf_free(p);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	static const char *const names[6] = {"n", "k", "sigma", "theta_i", "theta_r", "phi"};
	fuzz_batch(data, size, names, 6);
	return 0;
}
