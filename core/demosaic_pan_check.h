/* Internal to core: pan-check (docs/demosaicking.md, Round 17), a guarded colour method meant
 * for the 5x time budget: a cheap pan base blended towards a conservative estimate that one band
 * pass could compute (bayer-first's green analyser mean with the own-lattice tents' modulation,
 * the tents' red and blue) by pan-guard's leave-one-out block check with a noise term, and red
 * and blue by pan-hue's cross-colour gate. demosaic_pan_check.c states the formulas; the float
 * fast path: demosaic_pan_check_fast.c (Round 18a). Not a public header. */
#ifndef POLARCAM_DEMOSAIC_PAN_CHECK_H
#define POLARCAM_DEMOSAIC_PAN_CHECK_H

#include "demosaic_common.h"

/* Every constant of the definition (chosen by Round 17's rule on the development sets). */
/* the base: 0 pan-side, 1 pan-guided */
#define PC_DM_PAN_CHECK_BASE 0
/* the conservative estimate: 5 green's analyser mean bayer-first's and its modulation the
 * own-lattice tents', red and blue the tents' (the method's); 4 bayer-first's green, the tents'
 * red and blue (bayer-first itself away from the borders); 1 every channel's tents; diagnostics:
 * 0 bayer-first's, 2 and 3 the 2×2 blocks' mean with the base's (2) or the tents' (3)
 * modulation */
#define PC_DM_PAN_CHECK_CONS 5
/* the error window's radius r in lattice steps (4 pixels) */
#define PC_DM_PAN_CHECK_R 1
/* γ, the weights' exponent */
#define PC_DM_PAN_CHECK_GAMMA 8.0
/* the error sums' floor F = (floor·FS)² (pan-guard's) */
#define PC_DM_PAN_CHECK_FLOOR 1e-4
/* c, the base's expected excess output noise per sample, in σ² = g·(level + δ), added to its
 * error sum: c_RB for red's and blue's blocks, c_G for green's (Round 18: per colour; the base's
 * red and blue carry a sample from a lattice four times sparser than green's) */
#define PC_DM_PAN_CHECK_NOISE       8.0
#define PC_DM_PAN_CHECK_NOISE_GREEN 1.0
/* κ, pan-hue's cross-colour gate's weight (0: no gate) */
#define PC_DM_PAN_CHECK_KAPPA 16.0
/* β of the gate's green residual (pc_dm_pan_hue_params.beta; Round 19b): green's residual in
 * the gate is max(e_p − β·(e_b − e_p), 0), e_b and e_p its block's plain and ratio-model
 * leave-one-out errors: the part of green's detail that the ratio model against P̃ does not
 * explain, less β times the part it does. Luminance detail that P̃'s 5×5 filter passes in part
 * (periods from about 5.5 px) is explained in part (e_p < e_b) and drops out; hue detail P0 does
 * not see is not (e_p ≈ e_b) and stays. pan-hue takes the same β (Round 19e; until then 0,
 * Round 16's gate on e_p itself, which fired on hue-free texture at the (1, 1) block phases) */
#define PC_DM_PAN_CHECK_BETA 0.75

typedef struct pc_dm_pan_check_params {
	int base;     /* PC_DM_PAN_CHECK_BASE, 0 or 1 */
	int cons;     /* PC_DM_PAN_CHECK_CONS, 0..5 */
	int r;        /* PC_DM_PAN_CHECK_R, 0..4 */
	double gamma; /* PC_DM_PAN_CHECK_GAMMA, > 0 */
	double floor; /* PC_DM_PAN_CHECK_FLOOR, >= 0 */
	double noise; /* PC_DM_PAN_CHECK_NOISE, >= 0: c_RB */
	double kappa; /* PC_DM_PAN_CHECK_KAPPA, >= 0 */
	double force; /* < 0: the weights computed (the method); in [0, 1]: every block weight of
	               * the base set to it and no gate (tests: 1 the base, 0 the conservative) */
	double g;     /* the noise gain (raw units, demosaic_noise.h); < 0: estimated from the
	               * frame (the default) */
	double noise_green; /* PC_DM_PAN_CHECK_NOISE_GREEN, >= 0: c_G */
	double beta;        /* PC_DM_PAN_CHECK_BETA, >= 0 */
} pc_dm_pan_check_params;

pc_dm_pan_check_params pc_dm_pan_check_defaults(void);
/* PC_EINVAL (set) for parameters out of range, else 0: the reference's and the fast path's check */
int pc_dm_pan_check_check(const pc_dm_pan_check_params *p);

/* pan-check's double reference (defaults) and the same with other parameters; PC_EINVAL for
 * parameters out of range */
int pc_dm_pan_check_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out);
int pc_dm_pan_check_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_check_params *p, const pc_fplane *out);
/* the float fast path (defaults; pc_dm_pan_check_ref's within the tolerance of
 * tests/test_pan_check_fast.c) and the same with other parameters: PC_ENOTSUP unless base 0 and
 * cons 5 */
int pc_dm_pan_check_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out);
int pc_dm_pan_check_fast_with(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                              pc_cpu_level level, const pc_dm_pan_check_params *p,
                              const pc_fplane *out);

#endif
