/* pan-check's float fast path (docs/demosaicking.md, "Round 18a: pan-check's fast path"): the
 * definition is pc_dm_pan_check_ref_with's (demosaic_pan_check.c states it); the same steps in
 * float on pan-guard's fast path (demosaic_pan_guard_fast.c, pc_dm_pan_guard_fast_run), which
 * pan-check's additions (pc_dm_guard_check) extend:
 *
 *  1. the base: pan-side's fast path into the outputs;
 *  2. per row band, pan-guard's rings: the blocks' leave-one-out errors, then each block's mean
 *     level mu and the noise term c_k·4g·mu added to its e_p before the window sums (the
 *     reference adds c_k·4g·Σ mu to the sum: the same in real arithmetic), the weights;
 *  3. per block row, pan-hue's gate of the red and blue blocks (in double, at block rate, on
 *     the float errors kept in rings of 4r + 1 block rows);
 *  4. per output row, the conservative estimate cons 5: bayer-first's green analyser mean alone
 *     (pc_dm_bayer_first_band_gmean, bit for bit its one-pass rows' on integer raws) and the
 *     own-lattice tents (exact sums on integer raws), the tent-interpolated W_k and D_k, and
 *     the blend O = W_k·I_p + (1 − W_k)·I_b, then red and blue (1 − D_k)·O + D_k·I_b.
 *
 * g is pc_dm_noise_gain_in_mt's, the reference's. Only the method's base (pan-side) and its
 * conservative estimate (cons 5) have a fast path; the other parameters' values all do. */
#include "demosaic_pan_check.h"

#include <math.h>

#include "demosaic_noise.h"
#include "demosaic_pan.h"
#include "polarcam/error.h"

_Static_assert(PC_DM_PAN_HUE_GREEN == 0, "pan-check's fast path gates red and blue only");

int pc_dm_pan_check_fast_with(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                              pc_cpu_level level, const pc_dm_pan_check_params *p,
                              const pc_fplane *out)
{
	int rc = pc_dm_pan_check_check(p);
	if (rc)
		return rc;
	if (p->base != 0 || p->cons != 5)
		return pc_error(PC_ENOTSUP,
		                "pan-check fast path: only base 0 (pan-side) and cons 5");
	double g = p->g;
	if (g < 0 && (p->noise > 0 || p->noise_green > 0 || p->kappa > 0)) {
		rc = pc_dm_noise_gain_in_mt(in, m, fs, threads, &g);
		if (rc)
			return rc;
	}
	g = fmax(g, 0);
	pc_dm_pan_guard_params gp = pc_dm_pan_guard_defaults();
	gp.base = 0;
	gp.r = p->r;
	gp.gamma = p->gamma;
	gp.floor = p->floor;
	gp.mode = 0;
	gp.cons = 0;
	gp.force = p->force;
	const pc_dm_pan_hue_params hp = pc_dm_pan_hue_defaults();
	const pc_dm_guard_check chk = {{p->noise * 4 * g, p->noise_green * 4 * g, p->noise * 4 * g},
	                               p->kappa,
	                               hp.quant,
	                               hp.noise,
	                               g,
	                               1,
	                               p->beta};
	return pc_dm_pan_guard_fast_run(in, m, fs, threads, level, &gp, &chk, out);
}

int pc_dm_pan_check_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out)
{
	pc_dm_pan_check_params p = pc_dm_pan_check_defaults();
	return pc_dm_pan_check_fast_with(in, m, fs, threads, level, &p, out);
}
