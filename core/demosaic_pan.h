/* Internal to core: the colour-polarization method guided by a pseudo-panchromatic image
 * (demosaic_pan.c): all sixteen samples of a 4×4 period share one scene. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_PAN_H
#define POLARCAM_DEMOSAIC_PAN_H

#include "demosaic_common.h"

/* The double reference: img the raw minus black (C order, w × h, w and h even, >= 8); out the
 * twelve planes (channel 4·k + c); fs the signal's full scale. */
int pc_dm_pan_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                  const pc_fplane *out);

/* pan-guided's double reference and fast path (the same arguments). */
int pc_dm_pan_guided_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out);
int pc_dm_pan_guided_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out);

/* pan-chroma's double reference and fast path (the same arguments). */
int pc_dm_pan_chroma_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out);
int pc_dm_pan_chroma_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out);

/* pan-side's double reference and fast path (the same arguments). */
int pc_dm_pan_side_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out);
int pc_dm_pan_side_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out);
/* ... and the same with the own channel's interpolated ratio R_own(p) = num_own/den_own of every
 * pixel written to rown[y·w + x] (when rown is not NULL; pan-split, Round 17b) */
int pc_dm_pan_side_ref_own(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           const pc_fplane *out, double *rown);

/* pan-lean (docs/demosaicking.md, Rounds 21 and 24): pan-side's tents without range weights,
 * side factors aware of noise, fine hue texture and luminance steps, a level shrunk towards its
 * window mean within the noise; demosaic_pan.c states the formulas. The constants were picked
 * on the development sets by Round 17's margin (Round 21: margin >= 0 at μ 0.0625 and 0.125,
 * κ_t 1 and 1.5; -0.002 at μ 0.25. Round 24: c_p and r_p, margin +0.004 at r_p 2 to 5 with
 * c_p from 0.75 to 3 and with windows per pixel or per 2 × 2 block, ties broken by the next
 * smallest term; the block's 6 × 6 window for the fast path's cost and rows; then c_s 4 over 1
 * and 2 by that term, -0.019 at 8. Round 27: the window's statistics from the 3 × 3 blocks'
 * levels instead of its 36 pixels, for the fast path's cost; the plus of five blocks lost
 * -0.01). */
#define PC_DM_PAN_LEAN_MU 0.125 /* μ: the side distance's relative luminance step */
#define PC_DM_PAN_LEAN_KN 4.0   /* κ_n: ε's hue noise term */
#define PC_DM_PAN_LEAN_KT 1.0   /* κ_t: ε's texture term, times the smaller side distance */
#define PC_DM_PAN_LEAN_CS 4.0   /* c_s: the own colour's level cored against one sample's noise */
#define PC_DM_PAN_LEAN_CP 1.5   /* c_p: the level's shrinkage, times one sample's noise */
/* pan-lean's double reference (the frame's noise gain estimated by pc_dm_noise_gain_d), and the
 * same with a given noise gain g >= 0 (raw units; PC_EINVAL otherwise) */
int pc_dm_pan_lean_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out);
int pc_dm_pan_lean_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         double g, const pc_fplane *out);
/* pan-lean's float fast path (pan_band in demosaic_pan.c): the frame's noise gain estimated by
 * pc_dm_noise_gain_in_mt, or given (g >= 0) */
int pc_dm_pan_lean_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out);
int pc_dm_pan_lean_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, double g, const pc_fplane *out);

/* pan-adapt (docs/demosaicking.md, Round 14): pan-side with a range scale relative to the local
 * signal and the ratio step's level shrunk towards its local mean where the frame's noise
 * (demosaic_noise.h) is of the order of the local variation. Every parameter of the definition
 * is one of these constants; demosaic_pan.c states the formulas. k_e and c were chosen on the
 * development sets by a rule written down before the sweep (Round 14; Rounds 13c and 13d
 * measured 0.115 and 8 for each change alone). */
#define PC_DM_PAN_ADAPT_EFS 0.0  /* e's fixed part, fraction of full scale (pan-side: 0.04) */
#define PC_DM_PAN_ADAPT_KE  0.13 /* k_e: e's part relative to the window mean μ_e of P̃ */
#define PC_DM_PAN_ADAPT_RE  2    /* μ_e's window radius: (2·2 + 1)² */
#define PC_DM_PAN_ADAPT_C   4.0  /* c: the shrinkage's noise multiple */
#define PC_DM_PAN_ADAPT_R   2    /* the shrinkage window's radius: (2·2 + 1)² */
#define PC_DM_PAN_ADAPT_DFS 0.01 /* δ, fraction of full scale (every pan method's) */

typedef struct pc_dm_pan_adapt_params {
	double e_fs; /* PC_DM_PAN_ADAPT_EFS */
	double ke;   /* PC_DM_PAN_ADAPT_KE */
	int re;      /* PC_DM_PAN_ADAPT_RE, 0..5 */
	double c;    /* PC_DM_PAN_ADAPT_C, >= 0 */
	int r;       /* PC_DM_PAN_ADAPT_R, 0..8 */
	double d_fs; /* PC_DM_PAN_ADAPT_DFS, > 0 */
	double g;    /* the noise gain (raw units, demosaic_noise.h); < 0: estimated from the frame
	              * (pc_dm_noise_gain_d), the method's choice */
} pc_dm_pan_adapt_params;

/* The method's parameters: the constants above, g estimated */
pc_dm_pan_adapt_params pc_dm_pan_adapt_defaults(void);

/* pan-adapt's double reference (pc_dm_pan_adapt_defaults), and the same with other parameters
 * (tests: g given, pan-side's e, δ → 0); PC_EINVAL for parameters out of range */
int pc_dm_pan_adapt_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out);
int pc_dm_pan_adapt_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_adapt_params *p, const pc_fplane *out);
/* ... and the own channel's interpolated ratio R_own(p) into rown (as pc_dm_pan_side_ref_own) */
int pc_dm_pan_adapt_ref_own(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                            double fs, const pc_dm_pan_adapt_params *p, const pc_fplane *out,
                            double *rown);
int pc_dm_pan_adapt_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out);
/* pan-adapt's reference and fast path with the noise gain g (raw units; < 0: estimated, as
 * pc_dm_pan_adapt_ref and pc_dm_pan_adapt_fast) */
int pc_dm_pan_adapt_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                          double g, const pc_fplane *out);
int pc_dm_pan_adapt_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           pc_cpu_level level, double g, const pc_fplane *out);

/* pan-guard (docs/demosaicking.md, Round 15): a base pan estimate (pan-adapt's or pan-side's)
 * blended per colour with bayer-first's where a leave-one-out check on the colour's own
 * samples finds the pan ratio model locally less predictive than plain interpolation
 * (demosaic_pan_guard.c states the formulas). Every constant of the definition is one of
 * these. */
/* the base estimate: 1 pan-adapt, 0 pan-side */
#define PC_DM_PAN_GUARD_BASE 1
/* the error window's radius r in lattice steps (4 pixels) */
#define PC_DM_PAN_GUARD_R 1
/* γ, the weights' exponent */
#define PC_DM_PAN_GUARD_GAMMA 8.0
/* the error sums' floor F = (floor·FS)² */
#define PC_DM_PAN_GUARD_FLOOR 1e-4
/* the blend: 0 every channel (the method), 1 each colour's analyser mean with the base's
 * analyser modulation kept */
#define PC_DM_PAN_GUARD_MODE 0
/* the conservative estimate: 0 bayer-first's (the method), 1 every channel's plain tents on its
 * own samples */
#define PC_DM_PAN_GUARD_CONS 0
/* c_u: > 0 blends the base towards its unshrunk form (pan-adapt with g = 0) where a colour's
 * ratio residual exceeds c_u times its expected noise (0: pan-guard; Round 17a) */
#define PC_DM_PAN_GUARD_UNSHRINK 0.0

typedef struct pc_dm_pan_guard_params {
	int base;        /* PC_DM_PAN_GUARD_BASE */
	int r;           /* PC_DM_PAN_GUARD_R, 0..4 */
	double gamma;    /* PC_DM_PAN_GUARD_GAMMA, > 0 */
	double floor;    /* PC_DM_PAN_GUARD_FLOOR, >= 0 */
	int mode;        /* PC_DM_PAN_GUARD_MODE, 0 or 1 */
	int cons;        /* PC_DM_PAN_GUARD_CONS, 0 or 1 */
	double force;    /* < 0: the weights computed (the method); in [0, 1]: every weight set to
	                  * it (tests: 1 is the base, 0 bayer-first) */
	double g;        /* the base pan-adapt's noise gain (raw units, demosaic_noise.h; as
	                  * pc_dm_pan_adapt_params.g); < 0: estimated from the frame (the default);
	                  * base 0 (pan-side) uses none */
	double unshrink; /* PC_DM_PAN_GUARD_UNSHRINK, >= 0; the reference only (fast path: 0) */
} pc_dm_pan_guard_params;

/* The method's parameters: the constants above, g estimated */
pc_dm_pan_guard_params pc_dm_pan_guard_defaults(void);

/* PC_EINVAL (set) for parameters out of range, else 0: the reference's and the fast path's check */
int pc_dm_pan_guard_check(const pc_dm_pan_guard_params *p);

/* pan-guard's double reference (pc_dm_pan_guard_defaults) and the same with other parameters;
 * PC_EINVAL for parameters out of range. The float fast path: demosaic_pan_guard_fast.c. */
int pc_dm_pan_guard_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out);
int pc_dm_pan_guard_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_guard_params *p, const pc_fplane *out);
int pc_dm_pan_guard_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                         pc_cpu_level level, const pc_fplane *out);
/* the fast path with other parameters (tests) */
int pc_dm_pan_guard_fast_with(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                              pc_cpu_level level, const pc_dm_pan_guard_params *p,
                              const pc_fplane *out);
/* the method with a given noise gain g for its base (the front door's pc_dm_pan_fns ref_g,
 * fast_g) */
int pc_dm_pan_guard_ref_g(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                          double g, const pc_fplane *out);
int pc_dm_pan_guard_fast_g(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           pc_cpu_level level, double g, const pc_fplane *out);

/* pan-check's additions to pan-guard's fast path (its fast path, demosaic_pan_check_fast.c,
 * sets them; demosaic_pan_check.c states the formulas): the noise term n_k = c_k·4g added per
 * block of colour k times its mean level mu to e_p (the window sums then carry c_k·4g·Σ mu);
 * pan-hue's gate with κ > 0, its q, its noise weight c_h and g (0 κ: no gate); cons5 1: the
 * conservative estimate pan-check's cons 5 (bayer-first's green analyser mean with the tents'
 * modulation, the tents' red and blue), else bayer-first's. */
typedef struct pc_dm_guard_check {
	double noise[3]; /* n_k per block colour k (0 R, 1 G, 2 B) */
	double kappa, quant, hnoise, g;
	int cons5;
	double beta; /* the gate's β (pc_dm_pan_hue_params.beta) */
} pc_dm_guard_check;

/* pan-guard's fast path with p's base (0: pan-side), r, γ, floor, mode and force, and pan-check's
 * additions chk (NULL: pan-guard's fast path itself) */
int pc_dm_pan_guard_fast_run(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                             pc_cpu_level level, const pc_dm_pan_guard_params *p,
                             const pc_dm_guard_check *chk, const pc_fplane *out);

/* pan-guard's parts that pan-hue (demosaic_pan_hue.c) builds on, all double, on the
 * mirror-extended raw (demosaic_pan_guard.c states the formulas). The blocks: 2×2 blocks of one
 * colour with corners (2i − XB, 2j − XB), i < NBX, j < NBY; per block the leave-one-out errors
 * e_b (plain) and e_p (ratio model) of its four samples and mu, the mean of max(raw, 0) + δ over
 * them. */
typedef struct pc_dm_guard_blocks {
	int XB, NBX, NBY;
	double *eb, *ep, *mu; /* NBX·NBY each, row j at j·NBX (one allocation, at eb) */
	unsigned char *col;   /* NBX·NBY: each block's colour (pc_dm_pan_guard_colour) */
} pc_dm_guard_blocks;
/* the blocks with corners in [−XB, w + XB) (XB even, ≥ 4); PC_ENOMEM */
int pc_dm_pan_guard_blocks(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           int XB, pc_dm_guard_blocks *b);
void pc_dm_pan_guard_blocks_free(pc_dm_guard_blocks *b);
/* colour 0 R, 1 G, 2 B of the extended position (x, y) (mirrored into the frame) */
unsigned pc_dm_pan_guard_colour(const pc_mosaic *m, int x, int y, int w, int h);
/* pan-guard's reference with the parts it computed on the way, for a method built on it:
 * bayer-first's reference (twelve float planes, plane q at ib + q·w·h, whatever p->cons) and
 * the blocks, with corners in [−XB, w + XB) for XB = max(4 + 4·p->r, xb) (xb even; the blocks'
 * values do not depend on XB). The output is pc_dm_pan_guard_ref_with's bit for bit. Free the
 * parts with pc_dm_pan_guard_parts_free (also after an error); parts NULL: none kept. */
typedef struct pc_dm_guard_parts {
	float *ib;
	pc_dm_guard_blocks bl;
} pc_dm_guard_parts;
int pc_dm_pan_guard_ref_parts(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                              double fs, const pc_dm_pan_guard_params *p, int xb,
                              const pc_fplane *out, pc_dm_guard_parts *parts);
void pc_dm_pan_guard_parts_free(pc_dm_guard_parts *parts);
/* the tent sums at pixel (x, y) of per-block values v (pan-guard's step 5): num[k] = Σ T·v(B),
 * den[k] = Σ T over colour k's blocks B with centres within ±4 (T = (4 − |d_x|)(4 − |d_y|)) */
void pc_dm_pan_guard_tent(const pc_dm_guard_blocks *b, const double *v, const pc_mosaic *m, int w,
                          int h, int x, int y, double num[3], double den[3]);
/* pan-guard's step 2 window of block (i, j): the sums of e_b, e_p and mu over the same colour's
 * blocks within ±rb block steps (inside the block set), into s[0], s[1], s[2] */
void pc_dm_pan_guard_window(const pc_dm_guard_blocks *b, int i, int j, int rb, double s[3]);
/* the cheap conservative estimate (cons 1): every channel q by pan-ratio's normalised tents on its
 * own samples' values, on the mirror-extended raw (twelve float planes) */
void pc_dm_pan_guard_tents(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                           const pc_fplane *out);

/* pan-hue (docs/demosaicking.md, Round 16): pan-guard with a cross-colour gate for red and
 * blue, whose lattices (one block per 4×4 period) cannot see hue detail near their own period:
 * where green's ratio-model residual, carried into red or blue by the ratio step, outweighs that
 * colour's own plain-interpolation residual nearby, red and blue move further towards
 * bayer-first (demosaic_pan_hue.c states the formulas). Every constant of the definition is one
 * of these. */
/* κ, the weight of green's residual against the colour's own */
#define PC_DM_PAN_HUE_KAPPA 16.0
/* the gate's window radius in lattice steps (4 pixels) */
#define PC_DM_PAN_HUE_R 1
/* the gate's exponent */
#define PC_DM_PAN_HUE_GAMMA 8.0
/* c, the weight of green's expected noise residual subtracted from its residual */
#define PC_DM_PAN_HUE_NOISE 1.0
/* q, the quantile of green's block residuals in the window (0.5: the median) */
#define PC_DM_PAN_HUE_QUANT 0.25
/* 1: green is gated too, by red's and blue's ratio residuals; 0: red and blue only */
#define PC_DM_PAN_HUE_GREEN 0
/* c_u of pan-hue's guard (pc_dm_pan_guard_params.unshrink, Round 17a): its base's shrinkage
 * undone, for each colour's own outputs, where the colour's ratio residual exceeds c_u times
 * its expected noise */
#define PC_DM_PAN_HUE_UNSHRINK 0.25
/* the largest window radius r */
#define PC_DM_PAN_HUE_RMAX 4

typedef struct pc_dm_pan_hue_params {
	pc_dm_pan_guard_params guard; /* pan-guard's (pc_dm_pan_guard_defaults) */
	double kappa;                 /* PC_DM_PAN_HUE_KAPPA, >= 0 (0: pan-guard bit for bit) */
	int r;                        /* PC_DM_PAN_HUE_R, 0..4 */
	double gamma;                 /* PC_DM_PAN_HUE_GAMMA, > 0 */
	double noise;                 /* PC_DM_PAN_HUE_NOISE, >= 0 (0: no noise term) */
	double quant;                 /* PC_DM_PAN_HUE_QUANT, in [0, 1] */
	int green;                    /* PC_DM_PAN_HUE_GREEN, 0 or 1 */
	double force;                 /* < 0: the gate computed (the method); in [0, 1]: every
	                               * red and blue gate set to it (tests: 0 is pan-guard, 1
	                               * bayer-first's red and blue) */
	double beta;                  /* >= 0; pan-hue's default pan-check's PC_DM_PAN_CHECK_BETA
	                               * (demosaic_pan_check.h, Round 19e) */
} pc_dm_pan_hue_params;

pc_dm_pan_hue_params pc_dm_pan_hue_defaults(void);
/* pan-hue's double reference (pc_dm_pan_hue_defaults) and the same with other parameters;
 * PC_EINVAL for parameters out of range. No fast path. */
int pc_dm_pan_hue_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      const pc_fplane *out);
int pc_dm_pan_hue_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                           const pc_dm_pan_hue_params *p, const pc_fplane *out);
/* pan-hue's step 2 on pan-guard's blocks b: the gate D(B) of every block (0 for green unless
 * p->green) with the noise gain g >= 0 (pan-check reuses it, demosaic_pan_check.c) */
void pc_dm_pan_hue_gates(const pc_dm_guard_blocks *b, const pc_dm_pan_hue_params *p, double fs,
                         double g, double *gate);

/* pan-dir's double reference and fast path (the same arguments). */
int pc_dm_pan_dir_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      const pc_fplane *out);
int pc_dm_pan_dir_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                       pc_cpu_level level, const pc_fplane *out);

/* The fast float path on the prepared input (raw rows converted as they are needed): row bands
 * on threads, intermediate rows in per-thread rings. PC_ENOMEM for its row buffers. */
int pc_dm_pan_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out);

/* The colour methods of this file, which the front door runs instead of a colour step and a
 * monochrome step: pc_dm_pan_fns_get gives their reference and fast path (NULL for other
 * methods). */
/* pan-split (docs/demosaicking.md, Round 17b): a base pan estimate whose ratio step carries into
 * the other χ2 class (green against red and blue) only t times the own sample's detail, t from the
 * local variation of the luminance P0 against the green–magenta chrominance Ĉ2
 * (demosaic_pan_split.c states the formulas). Every constant of the definition is one of these. */
/* the base estimate: 0 pan-side, 1 pan-adapt */
#define PC_DM_PAN_SPLIT_BASE 1
/* κ, the chrominance variation's weight */
#define PC_DM_PAN_SPLIT_KAPPA 1.0
/* the window's radius r: (2r + 1)² pixels */
#define PC_DM_PAN_SPLIT_R 4
/* t_lo, the lowest transfer */
#define PC_DM_PAN_SPLIT_TLO -1.0
/* D: 0 from the plain tents (Round 17b's form A), 1 from the base's own interpolated ratio */
#define PC_DM_PAN_SPLIT_DMODE 1
/* S_Y, S_C: 0 the variation about the window mean (form A), 1 the diagonal lattice step's
 * high-pass */
#define PC_DM_PAN_SPLIT_HP 1
/* the transfer on green pixels only (1; red and blue pixels keep the base's outputs) or on every
 * pixel (0; on pan-side's red and blue pixels D = 1 anyway) */
#define PC_DM_PAN_SPLIT_GONLY 1
#define PC_DM_PAN_SPLIT_RMAX  8

typedef struct pc_dm_pan_split_params {
	int base;     /* PC_DM_PAN_SPLIT_BASE, 0 or 1 */
	double kappa; /* PC_DM_PAN_SPLIT_KAPPA, >= 0 (0: t = 1, the base up to rounding) */
	int r;        /* PC_DM_PAN_SPLIT_R, 0..PC_DM_PAN_SPLIT_RMAX */
	double tlo;   /* PC_DM_PAN_SPLIT_TLO, in [-1, 1] */
	/* outside [-1, 1]: t computed (the method); inside: every t set to it (tests) */
	double force;
	double g;  /* base 1: pan-adapt's noise gain (< 0: estimated from the frame) */
	int dmode; /* PC_DM_PAN_SPLIT_DMODE, 0 or 1 */
	int hp;    /* PC_DM_PAN_SPLIT_HP, 0 or 1 */
	int gonly; /* PC_DM_PAN_SPLIT_GONLY, 0 or 1 */
} pc_dm_pan_split_params;

pc_dm_pan_split_params pc_dm_pan_split_defaults(void);
/* PC_EINVAL (set) for parameters out of range, else 0 */
int pc_dm_pan_split_check(const pc_dm_pan_split_params *p);
/* pan-split's double reference (pc_dm_pan_split_defaults) and the same with other parameters */
int pc_dm_pan_split_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                        const pc_fplane *out);
int pc_dm_pan_split_ref_with(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                             double fs, const pc_dm_pan_split_params *p, const pc_fplane *out);

typedef struct pc_dm_pan_fns {
	int (*ref)(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
	           const pc_fplane *out);
	int (*fast)(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
	            pc_cpu_level level, const pc_fplane *out);
	/* the methods with PC_DMF_NOISE_GAIN: the same with a given noise gain g > 0 (raw units,
	 * demosaic_noise.h; pc_pipeline_opts.noise_gain); NULL for the others */
	int (*ref_g)(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
	             double g, const pc_fplane *out);
	int (*fast_g)(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
	              pc_cpu_level level, double g, const pc_fplane *out);
} pc_dm_pan_fns;

const pc_dm_pan_fns *pc_dm_pan_fns_get(pc_demosaic_method m);

#endif
