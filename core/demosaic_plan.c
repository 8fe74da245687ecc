/* The method table and the one validation of the demosaic → Stokes front doors
 * (demosaic_plan.h): every method's description, support and kernels in one row; a call
 * validated and resolved once into a plan; the demosaicking paths (reference, fast, colour). */
#include "demosaic_plan.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "demosaic_color.h"
#include "demosaic_fast.h"
#include "demosaic_ic.h"
#include "demosaic_noise.h"
#include "demosaic_fact.h"
#include "demosaic_pan.h"
#include "demosaic_pan_check.h"
#include "polarcam/stokes.h"
#include "demosaic_ref.h"
#include "polarcam/error.h"
#include "polarcam/format.h"

/* Supports { lo, hi, block, scale } (validity.h): the raw samples each output pixel depends on,
 * from the methods' neighbourhoods composed stage by stage (demosaic_ref.c): bilinear 3×3;
 * bicubic ±3 (Keys' four taps at ±1, ±3); PPID ±4 (coarse PPI ±1, refined ±2 around it, then a
 * 3×3 tent of the differences); RI ±8 (PPI guide ±3, coefficients over a ±2 window of it, their
 * means over another ±2, the residual's 3×3 tent); EARI ±7 (its guide is ±2); ratio ±4 (guide
 * ±2, 3×3 tent, the second pass's guide the first pass's mean); bayer-first ±3 (the analyser
 * sub-image's 3×3 is ±2, then a 3×3 tent); bayer-eari ±9 (±2, then EARI). tests/test_demosaic.c
 * perturbs single samples of the references and checks that nothing outside changes. */
/* eari-mlri, eari-robust ±16 (guide ±3, the Laplacians ±2, the slope fit over ±5 windows,
 * the weighted average of the coefficients over another ±5, the residual's tent ±1; the
 * limiter's ±2 lies inside); pcdp ±2 (the bilinear estimates ±1, then the tent of the
 * differences); igri2 ±40, a bound: three stages of about ±13 each (the green step: MLRI
 * on ±2 Laplacians in ±3 windows, their ±3 averages, the directional residual, 5-tap
 * Gaussians and 3×3 gradient sums; a step of the 45°-rotated grid moves one pixel in x and
 * y), measured reach 35-40 on random data (tests/test_front_door.c); newton ±10 (stage one
 * ±3, its diagonal classifier over ±2 of that; stage two reads stage one at ±3 across and
 * classifies over ±2: 3 + 5 + 2). */
/* The prefix of each monochrome method's figures on the unseen set (Round 43) */
#define PC_UNSEEN                                                                                  \
	"; unseen (scenes/stress/mono-sealed: the sealed colour sets' 74 scenes through the "      \
	"monochrome sensor) "
/* The prefix of each monochrome method's figures on 60 random scenes of the dataset family
 * (Round 45) */
#define PC_FAMILY                                                                                  \
	"; 60 random scenes of the dataset family (scenes/dataset/demosaic.json, seed 20261207, "  \
	"640x512, IMX250MZR at 0-12 dB; scenes/stress/gen_family.py) "
#define MLRI_LO   -16
#define MLRI_HI   16
#define PCDP_LO   -2
#define PCDP_HI   2
#define IGRI_LO   -40
#define IGRI_HI   40
#define NEWTON_LO -10
#define NEWTON_HI 10
/* ratio-ri ±9: the ratio's ±4 under its mean, the guide, read over ±2 for the coefficients and
 * their means over another ±2, then the residual's tent ±1 (the limiter's ±2 lies inside). */
#define RATIO_RI_LO -9
#define RATIO_RI_HI 9
/* pan-fact ±10, a bound: ±8 inside (demosaic_fact.c; 7 reached on random data), the sub-image
 * mirror's two more. pan-ratio and pan-guided ±7, a bound: ±5 away from the borders (the ratios at
 * lattice points within ±3, the tent's zero at ±4, each reading the pseudo-panchromatic image's ±2;
 * demosaic_pan.c); its mirror inside the analyser sub-images reads up to 7 samples in from a border
 * where the whole-sample mirror of the supports reads 5 */
#define PAN_LO -7
#define PAN_HI 7
/* pan-side ±8, a bound: pan-guided's ±5, and its row factors at the block row of y ± 3 (y − 4 ..
 * y + 3) read the hue's rows ±2 from there, C1 and C2 the raw's ±2 from those (±6 inside, the
 * mirror's two more) */
/* pan-adapt ±9, a bound, for a given noise gain: pan-side's, and the range scale of the tap
 * rows y ± 3 reads the PPI's window ±2 rows further (y ± 5), the raw's ±2 from there (±7
 * inside, the mirror's two more); the shrinkage's window (±2 of the PPI) lies inside. Through
 * the frame's noise gain (demosaic_noise.h) every output depends a little on the whole frame. */
#define PAN_ADAPT_LO -9
#define PAN_ADAPT_HI 9
/* pan-guard ±16, for a given noise gain: a pixel's weights read the blocks with corners within
 * −4 .. +3 of it, their error windows the blocks ±4r (r = 1) further, each block's check the
 * samples ±4 (+1) around it and P̃ the raw's ±2 (±14 inside, the mirror's two more); its base
 * pan-adapt's ±9 lies inside */
#define PAN_GUARD_LO -16
#define PAN_GUARD_HI 16
/* pan-hue ±16 (r = 1), for a given noise gain: pan-guard's, and its gates' blocks as
 * pan-guard's weights' (tents −4 .. +3, windows ±4r, the checks' samples ±4 (+1), P̃ ±2) */
#define PAN_HUE_LO (-12 - 4 * PC_DM_PAN_HUE_R)
#define PAN_HUE_HI (12 + 4 * PC_DM_PAN_HUE_R)
/* pan-check ±(12 + 4r): pan-guard's weights and pan-hue's gates on the same blocks (tents
 * −4 .. +3, windows ±4r, the checks' samples ±4 (+1), P̃ ±2); its base pan-side's ±8 and the
 * own-lattice tents' ±3 (±5 with the mirror) lie inside */
#define PAN_CHECK_LO (-12 - 4 * PC_DM_PAN_CHECK_R)
#define PAN_CHECK_HI (12 + 4 * PC_DM_PAN_CHECK_R)
/* pan-split: its base's (pan-side ±8, pan-adapt ±9), and its window's high-passes at ±r, their P0
 * and Ĉ2 at ±(r + 2), the raw's ±2 from there (±(r + 4) inside), with the sub-image mirror's two
 * more: ±(r + 6) */
#define PAN_SPLIT_HI (PC_DM_PAN_SPLIT_R + 6 > 9 ? PC_DM_PAN_SPLIT_R + 6 : 9)
#define PAN_SPLIT_LO (-PAN_SPLIT_HI)
/* pan-lean ±8, for a given noise gain: pan-side's (its side factors read the same blocks, their
 * P̃ at the blocks' corners inside the hue's support; the level's window reads P0 at the 3 × 3
 * blocks' corners, within ±3, the raw at ±5) */
#define PAN_LEAN_LO -8
#define PAN_LEAN_HI 8
static const pc_dm_method_def pc_dm_methods[PC_DM_COUNT] = {
    [PC_DM_SUPERPIXEL_HALF] =
        {{PC_DM_SUPERPIXEL_HALF, "superpixel-half",
          "no interpolation error, half resolution; 2x2 IFoV misregistration "
          "shows as false DoLP on edges; not scored (the protocol is at "
          "full size: superpixel's figures are its full-size version)",
          "cheapest: one read of the raw, a quarter-size output; 0.64-1.11x bilinear's "
          "time (Round 44c)",
          "the 2x2 super-pixel of DoFP sensors (e.g. Ratliff et al. 2009)",
          PC_DMF_MONO | PC_DMF_HALF_RES},
         {0, 1, 2, 2},
         pc_dm_superpixel_half,
         NULL,
         false,
         PC_DM_SUPERPIXEL_HALF,
         false},
    [PC_DM_SUPERPIXEL] =
        {{PC_DM_SUPERPIXEL, "superpixel",
          "full-size output of the 2x2 super-pixel values; blocky, lowest "
          "accuracy; mean (worst): Lapray -7.74/-7.12 (-9.33/-9.35), Zhang "
          "-6.24/-6.39 (-6.61/-6.81), stress -3.36/-1.92 (-4.28/-4.75)"
          "; held-out (scenes/heldout, 12) -2.81/-1.61 (-5.53/-3.40); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) -5.67/-3.33 (-7.16/-5.94)" PC_UNSEEN
          "-2.75/-1.85 (-5.32/-4.39), through a lens -5.45/-3.56 (-8.45/-7.66)" PC_FAMILY
          "-4.16/-0.25 (-10.26/-2.56)",
          "memory-bound, like a copy: 1.04-1.13x bilinear's time (its rows streamed like "
          "the bilinear's; 2.1-3.3x before, docs/demosaicking.md, Round 44c)",
          "the 2x2 super-pixel replicated over its block", PC_DMF_MONO},
         {0, 1, 2, 1},
         pc_dm_superpixel,
         NULL,
         false,
         PC_DM_SUPERPIXEL,
         false},
    [PC_DM_BILINEAR] =
        {{PC_DM_BILINEAR, "bilinear",
          "the baseline every gain below is measured against: per-channel tent "
          "interpolation, false DoLP on edges (Lapray NIR: S0 48.7 dB, DoLP 36.0 dB; "
          "worst scene S0 44.1 dB (fabrics), DoLP 31.2 dB (macbeth_classic))",
          "memory-bound: 3x3 neighbourhood, one pass",
          "Gao & Gruev, Opt. Express 19(27) 2011, bilinear DoFP interpolation", PC_DMF_MONO},
         {-1, 1, 1, 1},
         pc_dm_bilinear,
         NULL,
         true,
         PC_DM_BILINEAR,
         false},
    [PC_DM_BICUBIC] =
        {{PC_DM_BICUBIC, "bicubic",
          "sharper than bilinear, per channel, overshoot limited; S0/DoLP dB over "
          "bilinear, mean (worst scene): Lapray +1.72/+0.82 (+0.46/+0.00), Zhang "
          "+1.10/+1.17 (+0.78/+0.98), stress +0.18/-0.17 (+0.01/-0.83)"
          "; held-out (scenes/heldout, 12) +0.32/-0.28 (-0.16/-0.93); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +1.17/+0.77 (+0.39/-0.34)" PC_UNSEEN
          "+0.19/-0.09 (-0.26/-0.70), through a lens +1.34/+1.42 (+0.46/-0.46)" PC_FAMILY
          "+0.34/-0.10 (-0.74/-0.75)",
          "7x7 neighbourhood, separable; 2.0-3.3x bilinear's time (Round 44d: four runs, AVX-512, "
          "2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "Keys cubic convolution (a = -1/2) per channel, as in Gao & Gruev 2011", PC_DMF_MONO},
         {-3, 3, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_BICUBIC,
         false},
    [PC_DM_PPID] =
        {{PC_DM_PPID, "ppid",
          "inter-channel: differences to an edge-aware pseudo-panchromatic image, "
          "overshoot limited; mean (worst): Lapray -0.02/-0.20 (-3.19/-1.44), Zhang "
          "+4.71/+3.11 (+4.71/+2.79), stress +3.57/+1.64 (+0.39/-0.13); noisy stress "
          "low exposure +0.43/+1.57 (-3.98/+0.04: needs denoising in low light)"
          "; held-out (scenes/heldout, 12) +4.33/+1.76 (+0.80/+0.04); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +3.02/+2.38 (-3.36/-1.25)" PC_UNSEEN
          "+4.61/+1.80 (+0.59/+0.38), through a lens +4.40/+2.86 (-2.28/-0.68)" PC_FAMILY
          "+1.49/+1.63 (-5.98/-0.86)",
          "5x5 neighbourhood, three fused passes; 3.6-6.1x bilinear's time (Round 44d: four runs, "
          "AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "Mihoubi, Losson, Mathon, Macaire, IEEE TCI 3(4) 2017; for PFAs: Mihoubi, "
          "Lapray, Bigue, Sensors 18(11) 3688, 2018",
          PC_DMF_MONO},
         {-4, 4, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_PPID,
         false},
    [PC_DM_RI] =
        {{PC_DM_RI, "ri",
          "inter-channel: guided-filter tentative estimates plus interpolated "
          "residuals, overshoot limited; mean (worst): Lapray +1.21/+1.08 "
          "(-0.52/+0.16), Zhang +3.78/+3.01 (+3.24/+2.97), stress +3.88/+1.11 "
          "(+1.32/-0.29)"
          "; held-out (scenes/heldout, 12) +4.71/+1.23 (+0.58/-0.08); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +4.58/+1.78 (+0.66/-1.83)" PC_UNSEEN
          "+4.77/+1.63 (+1.17/+0.18), through a lens +4.79/+2.87 (-0.84/+0.11)" PC_FAMILY
          "+2.86/+0.11 (-4.11/-0.08)",
          "guided filters (5x5 windows) per channel; 9-16x bilinear's time (Round 44d: four runs, "
          "AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "Kiku, Monno, Tanaka, Okutomi, ICIP 2013; for DoFP: Ahmed, Zhao, Gruev, "
          "Zhang, Bermak, Opt. Express 25(9) 2017",
          PC_DMF_MONO},
         {-8, 8, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_RI,
         false},
    [PC_DM_EARI] = {{PC_DM_EARI, "eari",
                     "inter-channel: residual interpolation guided by an edge-aware "
                     "intensity image (our detector), overshoot limited; mean (worst): Lapray "
                     "+3.37/+1.90 (+1.32/+0.34), Zhang +3.46/+3.32 (+2.79/+3.01), stress "
                     "+2.88/+1.04 (+1.51/-0.14); noisy stress high/mid/low exposure worst S0/DoLP "
                     "+1.97/-0.01, +1.32/-0.03, +0.05/-0.06 (no denoising needed)"
                     "; held-out (scenes/heldout, 12) +4.03/+1.10 (+0.77/-0.06); through a lens "
                     "(scenes/stress/optics, PSF sigma 0.7 px) +5.04/+2.42 (+1.87/+0.05)" PC_UNSEEN
                     "+2.98/+1.11 (+1.05/+0.12), through a lens +4.68/+2.90 (+1.09/+0.10)" PC_FAMILY
                     "+1.95/+0.09 (-3.66/-0.07)",
                     "8.5-14x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; "
                     "the multiple swings with the bilinear's 1.6-3.0 ms); like ri plus an "
                     "edge-aware guide pass; 9.5-14.6x bilinear's time "
                     "over twenty runs (median 12.5x; AVX-512, 2026-12-06, Round 30)",
                     "Morimatsu, Monno, Tanaka, Okutomi, ICIP 2020 (arXiv:2007.14292)",
                     PC_DMF_MONO},
                    {-7, 7, 1, 1},
                    pc_dm_ic,
                    pc_dm_ic_rows,
                    false,
                    PC_DM_EARI,
                    false},
    [PC_DM_BAYER_FIRST] = {{PC_DM_BAYER_FIRST, "bayer-first",
                            "colour-polarization: bilinear Bayer demosaicking of each analyser "
                            "sub-image, then bilinear up-sampling of the analysers; the colour "
                            "baseline, which the colour methods' gains are measured against; "
                            "its own S0/DoLP PSNR (bench colour), mean (worst scene): smooth "
                            "colours (9) 45.41/33.76 dB (40.44 fabrics/27.64 macbeth_classic), "
                            "hue patches (9) 32.26/18.84 (28.26/17.78 fabrics), colour stress "
                            "suite (5) 30.25/19.11 (18.82/17.48 gratings), noisy copies (4) "
                            "41.00/10.07 (37.95 gratings_g24/8.40 patches_g24), hue-pair scenes "
                            "(5) 23.03/13.21 (16.22 gm_bars/10.72 gm_bars_g18); synthetic "
                            "colour track S0 44.7, DoLP 32.4 (docs/demosaicking.md, Round 20)",
                            "one pass, the two bilinear steps' weights composed; 10x bilinear's "
                            "instructions (callgrind, 2448x2048, AVX2, Round 15d; the two-step "
                            "path it replaced 20x); 8.4-14.8x the mono bilinear's time at AVX-512 "
                            "against its faster kernel (Rounds 44b, 44d), 9.3-11.4x before it near "
                            "idle "
                            "(Rounds 15e, 16d, 17d; the old path 19.8-26.1x)",
                            "the colour-first baseline of colour-polarization demosaicking "
                            "(Morimatsu et al. 2020, Sec. 3.2)",
                            PC_DMF_COLOR},
                           {-3, 3, 1, 1},
                           NULL,
                           NULL,
                           false,
                           PC_DM_BILINEAR,
                           false},
    [PC_DM_BAYER_EARI] =
        {{PC_DM_BAYER_EARI, "bayer-eari",
          "colour-polarization: bilinear Bayer demosaicking of each analyser "
          "sub-image, then EARI across the analysers of each colour; better "
          "polarization than bayer-first; over bayer-first, synthetic colour "
          "track mean +0.65/+0.76; held-out colour scenes "
          "(scenes/stress/colour-holdout, 9) +0.44/+0.71 (worst +0.22/+0.28): "
          "the one colour method with no held-out scene losing; hue-pair dev set "
          "(scenes/stress/colour-hue, 5, Round 16) +0.26/+0.63 (worst +0.23/+0.40)",
          "bayer-first's colour step plus three EARI runs; 90-155x bilinear's time (Round 44d: "
          "four runs, AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "colour-first as Morimatsu et al. 2020, with the polarization step of "
          "their EARI",
          PC_DMF_COLOR},
         {-9, 9, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_EARI,
         false},
    [PC_DM_RATIO] =
        {{PC_DM_RATIO, "ratio",
          "inter-channel: our EARI guide, channels as guide x ratio (raw + 1 % FS)/"
          "(guide + 1 % FS) interpolated by a guide-weighted tent, twice, overshoot "
          "limited; mean (worst): Lapray +3.29/+1.80 (+0.62/-0.02), Zhang +4.58/+4.21 "
          "(+4.02/+4.17), stress +3.92/+1.69 (+1.77/+0.31); noisy stress (IMX250MZR) "
          "high/mid/low exposure +4.23/+1.64, +3.52/+1.42, +1.99/+1.24 (worst S0 +2.25, "
          "+1.22, -1.56: needs denoising in low light, brightest tenth ~1 % of full scale); "
          "ratio-nr keeps its speed and holds in low light"
          "; held-out (scenes/heldout, 12) +4.59/+1.69 (+2.36/+0.37); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +5.48/+3.12 (-0.59/+0.70)" PC_UNSEEN
          "+3.88/+2.32 (+0.72/+0.75), through a lens +5.91/+4.97 (+0.43/+0.84)" PC_FAMILY
          "+2.23/+0.76 (-4.26/+0.24)",
          "the guide pass plus two ratio passes (3x3 guided tents); 3.1-5.7x bilinear's time "
          "(Round 44d: four runs, AVX-512, 2 threads; the multiple swings with the bilinear's "
          "1.6-3.0 ms)",
          "ours: the guide of Morimatsu et al. ICIP 2020 with smooth-hue-transition "
          "(ratio) interpolation, Cok, US patent 4,642,678 (1987), iterated; "
          "joint-bilateral weights (Kopf et al., SIGGRAPH 2007)",
          PC_DMF_MONO},
         {-4, 4, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_RATIO,
         true},
    [PC_DM_EARI_MLRI] =
        {{PC_DM_EARI_MLRI, "eari-mlri",
          "anchor: EARI as its authors define it (their polarization-invariant "
          "edge-aware guide, minimized-Laplacian RI in 11x11 windows); mean "
          "(worst): Lapray +3.60/+1.74 (+0.91/-0.20), Zhang +3.96/+4.07 "
          "(+3.14/+3.75), stress +5.24/+1.78 (+1.20/+0.44); held-out "
          "(scenes/heldout, 12) +4.38/+1.57 (+2.68/+0.05); through a lens (scenes/stress/optics, "
          "PSF sigma 0.7 px) +6.17/+3.09 (-1.41/-0.29) (before Round 38's exact "
          "box sums of zeros: stress DoLP +1.09, worst -4.58 on gloss's black)" PC_UNSEEN
          "+4.16/+1.43 (+0.83/+0.06), through a lens +6.51/+2.86 (-0.16/-1.63)" PC_FAMILY
          "+2.04/+0.83 (-5.10/-0.39)",
          "multi-pass float path, ~22 planes; 530-860x bilinear's time (Round 44d: four runs, "
          "AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms) (not within "
          "budget)",
          "Morimatsu, Monno, Tanaka, Okutomi, ICIP 2020 (arXiv:2007.14292) and their "
          "release; MLRI: Kiku et al., IEEE TIP 25(3) 2016",
          PC_DMF_MONO},
         {MLRI_LO, MLRI_HI, 1, 1},
         pc_dm_mlri_fast,
         NULL,
         false,
         PC_DM_EARI_MLRI,
         false},
    [PC_DM_EARI_ROBUST] =
        {{PC_DM_EARI_ROBUST, "eari-robust",
          "inter-channel: eari-mlri with the overshoot limiter (no ringing into "
          "the dark); the most accurate, no scene below -0.3 dB; mean (worst): "
          "Lapray +3.51/+1.78 (+1.01/-0.12), Zhang +3.69/+3.74 (+3.03/+3.51), "
          "stress +5.35/+2.29 (+1.87/+0.59); noisy stress low exposure +2.12/+1.28 "
          "(-2.09/+0.49: needs denoising in low light)"
          "; held-out (scenes/heldout, 12) +4.36/+1.73 (+1.78/+0.21); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +6.05/+3.14 (-0.93/+0.51)" PC_UNSEEN
          "+3.93/+2.02 (+0.89/+0.46), through a lens +5.92/+3.17 (+0.26/+0.60)" PC_FAMILY
          "+2.43/+0.51 (-4.50/+0.07)",
          "eari-mlri's cost plus one 5x5 min/max pass: 520-840x bilinear's time (Round 44d: four "
          "runs, AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms) (not "
          "within the 5x budget)",
          "ours: Morimatsu et al. ICIP 2020's guide and Kiku et al. TIP 2016's "
          "MLRI, held to each channel's local sample range",
          PC_DMF_MONO},
         {MLRI_LO, MLRI_HI, 1, 1},
         pc_dm_mlri_fast,
         NULL,
         false,
         PC_DM_EARI_ROBUST,
         false},
    [PC_DM_PCDP] =
        {{PC_DM_PCDP, "pcdp",
          "anchor: residual interpolation with the other channels' bilinear "
          "estimates as guide, the orthogonal one weighted sqrt(2); mean (worst): "
          "Lapray +3.01/+0.78 (+0.97/-0.54), Zhang +3.88/+4.01 (+3.08/+3.78), stress "
          "+2.58/+0.76 (+1.32/-0.89)"
          "; held-out (scenes/heldout, 12) +2.30/+1.35 (+1.35/-0.07); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +4.08/+2.25 (-0.32/+0.95)" PC_UNSEEN
          "+2.47/+1.00 (+0.92/-1.75), through a lens +4.73/+2.42 (+0.31/-3.08)" PC_FAMILY
          "+1.05/+1.27 (-3.27/-0.28)",
          "four bilinear planes plus four residual tents; 94-150x bilinear's time (Round 44d: four "
          "runs, AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "Wu et al., Opt. Express 29(14) 2021 (polarization channel difference prior)",
          PC_DMF_MONO},
         {PCDP_LO, PCDP_HI, 1, 1},
         pc_dm_pcdp_fast,
         NULL,
         false,
         PC_DM_PCDP,
         false},
    [PC_DM_IGRI2] = {{PC_DM_IGRI2, "igri2",
                      "anchor: residual interpolation on the rotated diagonal lattices, then "
                      "across them, then MLRI with the mean as guide; mean (worst): Lapray "
                      "+2.91/+1.41 (-0.50/-0.72), Zhang +5.80/+4.47 (+5.24/+4.45), stress "
                      "+5.72/+0.93 (+0.81/-0.93); held-out (scenes/heldout, 12) "
                      "+5.20/+1.23 (+1.74/+0.11); through a lens (scenes/stress/optics, PSF sigma "
                      "0.7 px) +5.97/+2.66 (-2.63/-1.40) (before Round 38's exact box sums of "
                      "zeros in its MLRI step: stress DoLP -0.13, worst -7.74 on gloss's "
                      "black)" PC_UNSEEN "+5.74/+1.25 (+0.84/-0.46), through a lens "
                      "+7.65/+3.06 (-1.29/-3.22)" PC_FAMILY "+2.51/+1.17 (-6.25/-0.61)",
                      "the double reference (no fast path yet): hundreds of times bilinear",
                      "Morimatsu, Monno, Tanaka, Okutomi, IEEE Sensors J. 21(24) 2021 (IGRI2) and "
                      "their release",
                      PC_DMF_MONO | PC_DMF_REFERENCE_ONLY},
                     {IGRI_LO, IGRI_HI, 1, 1},
                     NULL,
                     NULL,
                     false,
                     PC_DM_IGRI2,
                     false},
    [PC_DM_NEWTON] =
        {{PC_DM_NEWTON, "newton",
          "anchor: Newton-polynomial interpolation of polarization differences, "
          "horizontal / vertical / diagonal estimates fused by an edge classifier; "
          "mean (worst): Lapray +2.13/-0.32 (-0.44/-2.91), Zhang +5.88/+3.62 "
          "(+5.28/+3.26), stress +4.63/+0.92 (+1.14/-1.13)"
          "; held-out (scenes/heldout, 12) +5.10/+1.14 (+4.03/-1.36); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +5.04/+1.91 (-1.70/-0.33)" PC_UNSEEN
          "+4.96/+0.88 (+0.77/-1.99), through a lens +6.12/+1.17 (-1.12/-5.76)" PC_FAMILY
          "+2.16/+1.64 (-4.85/-0.41)",
          "five passes in double over padded planes, on threads; 210-370x bilinear's time (Round "
          "44d: four runs, AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms)",
          "Li, Zhao, Pan, Kong, Opt. Express 27(2) 1376, 2019, and their release", PC_DMF_MONO},
         {NEWTON_LO, NEWTON_HI, 1, 1},
         pc_dm_newton_fast,
         NULL,
         false,
         PC_DM_NEWTON,
         false},
    [PC_DM_RATIO_RI] =
        {{PC_DM_RATIO_RI, "ratio-ri",
          "inter-channel: the ratio method, then one guided-filter residual "
          "interpolation (5x5) with its mean as guide, blended back into the ratio "
          "estimate where the guide is dark (below ~1 % FS), overshoot limited; mean "
          "(worst): Lapray +3.58/+1.98 (+1.14/+0.33), Zhang +4.25/+4.06 "
          "(+3.46/+3.86), stress +4.51/+1.82 (+2.36/+0.26); noisy stress low exposure "
          "+2.35/+1.09 (-0.90/+0.58: needs denoising in low light)"
          "; held-out (scenes/heldout, 12) +5.61/+1.85 (+2.49/+0.36); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +7.14/+3.42 (+0.76/+0.76)" PC_UNSEEN
          "+4.60/+2.31 (+1.41/+0.77), through a lens +6.66/+5.00 (+0.99/+0.82)" PC_FAMILY
          "+3.13/+0.72 (-4.13/+0.17)",
          "ratio plus one guided-filter stage; 11-20x bilinear's time (Round 44d: four runs, "
          "AVX-512, 2 threads; the multiple swings with the bilinear's 1.6-3.0 ms) (not within the "
          "5x budget)",
          "ours: ratio (above) with the residual interpolation of Kiku et al. ICIP "
          "2013 (guided filter: He, Sun, Tang, TPAMI 2013)",
          PC_DMF_MONO},
         {RATIO_RI_LO, RATIO_RI_HI, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_RATIO_RI,
         false},
    [PC_DM_RATIO_NR] =
        {{PC_DM_RATIO_NR, "ratio-nr",
          "inter-channel: ratio with a noise-aware multiplier (the guide shrunk "
          "towards its 3x3 mean where its variance is of the order of the frame's "
          "noise: the noise gain given, or the slope of the photon-transfer line "
          "fitted to the frame; where clipping splits the analysers, the binomial "
          "guide instead of EARI's, Round 46), overshoot limited; mean (worst): Lapray "
          "+3.54/+1.94 (+1.34/+0.24), Zhang +3.83/+4.02 (+3.02/+3.87), stress "
          "+4.23/+1.60 (+2.49/+0.31); noisy stress (IMX250MZR) high/mid/low exposure "
          "+4.39/+1.54, +3.93/+1.16, +2.79/+0.74 (worst +2.38/+0.36, +1.69/+0.07, "
          "+0.39/+0.05: no loss without denoising); at +12/+24 dB gain "
          "(scenes/stress/gain, 6) +2.27/+0.87 (-0.14/+0.48), the only method above -0.3 "
          "there; the recommended choice"
          "; held-out (scenes/heldout, 12) +4.69/+1.53 (+2.24/+0.25); through a lens "
          "(scenes/stress/optics, PSF sigma 0.7 px) +6.23/+2.96 (+1.89/+0.66)" PC_UNSEEN
          "+3.92/+2.25 (+0.90/+0.52), through a lens +6.33/+4.85 (+1.24/+0.41)" PC_FAMILY
          "+3.31/+0.34 (-1.00/+0.09): two scenes at 12 dB below -0.3 (smooth surfaces filling "
          "the frame: its channels' noise is correlated and adds up in S0), every method "
          "but ratio-nr3 (-0.93) losing more (Round 45); seed 20261208 +3.11/+0.68 "
          "(-0.56/+0.06), one scene below -0.3; seed 20261209, evaluated once after Round "
          "46's change: +3.27/+0.38 (-1.92/+0.06), two scenes below -0.3, dark and noisy "
          "(12 dB at 10 us; 0 dB at 33 us)",
          "3.2-6.8x the mono bilinear's time (Rounds 44d and 45: AVX-512, 2 threads; 4.6-5.1x "
          "in the dev host's usual regime, 6.4-6.8x in its fastest, the bilinear 1.2 ms; no "
          "cheaper definition keeps its accuracy: the binomial guide 0.86x its time, one pass "
          "0.77x, no limiter 0.81x, each losing 0.5-2 dB mean S0 on some set or 6 dB on a "
          "scene); ratio's passes with a 3x3 guide "
          "variance per pixel, the binomial guide on rows with a clipped sample near (no "
          "cost measurable without; 1.2x a frame clipped on every row, Round 46), the "
          "overshoot "
          "limiter applied as each output row is written, the frame's noise fit (8192 blocks, "
          "~0.2-0.3 ms a 5 MP frame, Round 40); 4.8-5.5x the bilinear's time at "
          "AVX-512 since the bilinear runs its faster AVX2 row kernel there (Round 44b: "
          "at the 5x budget's edge, not reliably within it); against the former "
          "bilinear kernel 3.2-4.1x bilinear's time in the "
          "shared 2-vCPU dev machine's usual regime (medians 3.4x and 3.9x over two "
          "sets of runs), 4.5-5.5x in periods when its write bandwidth doubles and the "
          "memory-bound bilinear speeds up with it (medians 5.1x: at the 5x budget's "
          "edge; AVX-512, 2026-12-06; at AVX2 5.2-6.0x in the first); on the faster "
          "host of 2026-12-07 3.2-4.2x in 31 runs at one and two threads, the "
          "fast-memory regime included (Rounds 38 and 41b): the budget's reading "
          "depends on the machine; scalar 36-52x before Round 25 vectorised it "
          "(Rounds 30-33: docs/demosaicking.md)",
          "ours: ratio (above) with a guided filter's shrinkage (He, Sun, Tang, TPAMI "
          "2013) and a Poisson noise variance from the frame (Foi et al., IEEE TIP "
          "17(10) 2008; Liu, Tanaka, Okutomi, IEEE TIP 22(12) 2013)",
          PC_DMF_MONO | PC_DMF_NOISE_GAIN},
         {-4, 4, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_RATIO_NR,
         true},
    [PC_DM_RATIO_NR3] =
        {{PC_DM_RATIO_NR3, "ratio-nr3",
          "inter-channel: ratio-nr from the raw's 3x3 binomial as the first guide, in three "
          "passes (each pass's guide the mean of the one before, carrying more of a pixel's "
          "own sample into its other channels), overshoot limited; mean (worst): Lapray "
          "+3.68/+1.89 (+1.43/+0.21), Zhang +3.84/+4.19 (+2.96/+4.03), stress +4.94/+1.81 "
          "(+1.74/+0.16); held-out (scenes/heldout, 12) +4.58/+1.58 (+2.17/+0.28); through a "
          "lens (scenes/stress/optics, PSF sigma 0.7 px) +7.21/+2.98 (+1.86/+0.05); at "
          "+12/+24 dB gain (scenes/stress/gain, 6) +3.15/+1.00 (-0.10/+0.48); mono-sealed "
          "(already used: a secondary figure) +3.99/+2.48 (+1.44/+0.55), through a lens "
          "+6.96/+4.72 (+1.82/+0.43)" PC_FAMILY "+3.42/+0.37 (-0.93/+0.12); an evaluation "
          "candidate, not recommended (over the "
          "budget; docs/demosaicking.md, Round 43b)",
          "3.5-5.8x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms); ratio-nr's passes with a third one, "
          "the binomial instead of the EARI guide: "
          "1.09-1.12x ratio-nr's time, 5.0-5.6x bilinear's in the dev machine's fast-memory "
          "regime (four runs, Round 43b), 5.0-5.7x against the faster bilinear kernel of "
          "Round 44b: over the 5x budget",
          "ours: ratio-nr (above) from PPID's pseudo-panchromatic image (Mihoubi et al., "
          "IEEE TCI 3(4) 2017) as the first guide; more passes of the ratio's mean as guide, "
          "as residual interpolation iterates (Kiku et al., IEEE TIP 25(3) 2016; Morimatsu et "
          "al., IEEE Sensors J. 21(24) 2021)",
          PC_DMF_MONO | PC_DMF_NOISE_GAIN},
         {-4, 4, 1, 1},
         pc_dm_ic,
         pc_dm_ic_rows,
         false,
         PC_DM_RATIO_NR3,
         true},
    [PC_DM_PAN_RATIO] =
        {{PC_DM_PAN_RATIO, "pan-ratio",
          "colour-polarization: every channel as its pixel's own sample times "
          "a smooth ratio between channels, the ratios to a pseudo-panchromatic "
          "guide (the mean of the 4x4 period) interpolated on each channel's "
          "lattice; over bayer-first (bench colour, 9 scenes) smooth colours "
          "mean +4.46/+1.66 (worst +2.70/+0.37), hue patches -0.53/+1.12 "
          "(worst -0.76/+0.45: loses S0 at dense hue edges); colour stress "
          "suite (5 scenes) +0.58/+0.71 (worst -0.75 patches/+0.12)"
          "; held-out colour scenes (scenes/stress/colour-holdout, 9) -1.41/+1.34 (worst "
          "-2.69/+1.07), all 9 losing S0",
          "4.9-9.0x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms); one fused pass on row bands, twelve "
          "planes; 3.8-4.5x the mono "
          "bilinear's time on a quiet machine, more where bilinear's output "
          "streams (bayer-first 8-18x)",
          "ours: the pseudo-panchromatic image of Mihoubi et al., IEEE TCI 3(4) "
          "2017, with smooth-hue-transition (ratio) interpolation, Cok, US "
          "patent 4,642,678 (1987)",
          PC_DMF_COLOR},
         {PAN_LO, PAN_HI, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_RATIO,
         false},
    [PC_DM_PAN_GUIDED] =
        {{PC_DM_PAN_GUIDED, "pan-guided",
          "colour-polarization: pan-ratio with joint-bilateral tents (lattice "
          "samples weighed down across edges of the pseudo-panchromatic "
          "guide); over bayer-first (bench "
          "colour, 9 scenes) smooth colours +4.36/+1.57 (worst +2.41/+0.35), "
          "hue patches +0.38/+0.96 (worst +0.25/+0.59); colour stress suite "
          "(5 scenes) +1.33/+0.87 (worst +0.66/-0.05, gratings)"
          "; held-out colour scenes (scenes/stress/colour-holdout, 9) -0.34/+0.51 (worst "
          "-1.88/-0.96), 5 losing",
          "3.3-4.7x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms); pan-ratio's pass with a weight per "
          "tap, its output row per row phase "
          "(Rounds 14b, 14c): 0.82-0.91x pan-ratio; 3.3-4.0x the mono bilinear's "
          "time near idle (eight runs, docs/demosaicking.md, Round 14d)",
          "ours: pan-ratio with joint-bilateral weights (Tomasi & Manduchi, "
          "ICCV 1998; Kopf et al., SIGGRAPH 2007)",
          PC_DMF_COLOR},
         {PAN_LO, PAN_HI, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_GUIDED,
         false},
    [PC_DM_PAN_CHROMA] =
        {{PC_DM_PAN_CHROMA, "pan-chroma",
          "colour-polarization: pan-guided whose range weights also see hue "
          "(chrominance images demodulated from the colour layer); over "
          "bayer-first (bench colour, 9 scenes) smooth colours +4.41/+1.62 "
          "(worst +2.46/+0.36), hue patches +0.67/+1.15 (worst +0.52/+0.66); "
          "colour stress suite (5 scenes) +1.32/+0.91 (worst +0.49/-0.02, "
          "gratings); held-out colour scenes (scenes/stress/colour-holdout, 9) +0.05/+0.83 "
          "(worst -1.61/-0.69)",
          "6.0-9.8x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms); pan-guided's pass with two more guide "
          "images: 1.1-1.4x "
          "pan-guided, 5.5-6.9x the mono bilinear's time at load 2 (over the "
          "5x budget)",
          "ours: pan-guided with a luminance-chrominance guide (Alleysson et "
          "al., IEEE TIP 14(4) 2005; Kopf et al., SIGGRAPH 2007)",
          PC_DMF_COLOR},
         {PAN_LO, PAN_HI, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_CHROMA,
         false},
    [PC_DM_PAN_DIR] =
        {{PC_DM_PAN_DIR, "pan-dir",
          "colour-polarization: pan-ratio's colour step with one-sided "
          "(directional) candidates whose ratios are blended by the homogeneity "
          "of their hue; over bayer-first (bench colour, 9 scenes) smooth colours "
          "+4.17/+1.44 (worst +2.55/+0.10), hue patches +1.65/+3.81 (worst "
          "+1.50/+2.86); colour stress suite (5 scenes) +1.70/+2.12 (worst +0.73 "
          "text/+0.65 gratings): the colour accuracy goal met on all three sets, "
          "not on the held-out colour scenes (scenes/stress/colour-holdout, 9): "
          "+0.33/+3.40 (worst -1.32/+1.59), 4 losing S0",
          "12-20x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the multiple "
          "swings with the bilinear's 1.6-3.0 ms); one fused pass on row bands, the blend folded "
          "into each row phase's "
          "lattice coefficients: about 0.8x Round 10's time, 2.6-2.9x "
          "pan-ratio's (bench demosaic --quick, 2 threads, Release, load 2-3); "
          "idle 10.5-11.4x the mono bilinear's median wall time (Round 10: 14.8-14.9x "
          "in the same runs), twice the 5x budget (docs/demosaicking.md, Round 11)",
          "ours: pan-ratio with directional candidates (Hirakawa & Parks, IEEE "
          "TIP 14(3) 2005) blended as in GBTF (Pekkucuksen & Altunbasak, ICIP "
          "2010)",
          PC_DMF_COLOR},
         {PAN_LO - 1, PAN_HI + 1, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_DIR,
         false},
    [PC_DM_PAN_FACT] = {{PC_DM_PAN_FACT, "pan-fact",
                         "colour-polarization: colour and polarization factorised, each "
                         "channel as M_a x h_ak: the hue h per analyser from one-sided tents "
                         "of ratios to the PPI blended by the homogeneity of the 2x2 blocks' "
                         "sums, M by a ratio step on the hue-normalised 2x2 mosaic; over "
                         "bayer-first (bench colour, fast path and reference alike, 9 scenes) "
                         "smooth colours "
                         "+4.56/+1.78 (worst +2.54/+0.49), hue patches +2.72/+2.85 (worst "
                         "+2.31/+2.49); colour stress suite (5 scenes) +2.17/+1.88 (worst "
                         "+0.62 text/+0.75 gratings): the colour accuracy goal met on all "
                         "three sets, not on the held-out colour scenes "
                         "(scenes/stress/colour-holdout, 9): +0.80/+1.74 (worst -0.95/+0.24), "
                         "4 losing S0",
                         "15-25x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 "
                         "threads; the multiple swings with the bilinear's 1.6-3.0 ms); one fused "
                         "pass on row bands (pan-dir's source rows and blend kernel, "
                         "m two rows ahead of the output), within 1e-4 of full scale of the "
                         "double reference and equal to it on bench colour: 1.31x pan-dir's "
                         "instructions, 1.29-1.40x its time (bench demosaic --quick, 2 threads, "
                         "Release, load 1.2), about 13-15x the mono bilinear's time idle, about "
                         "3x the 5x budget (docs/demosaicking.md, Round 12)",
                         "ours: the factorisation of Round 11b; homogeneity as Hirakawa & "
                         "Parks, IEEE TIP 14(3) 2005, blended as GBTF (Pekkucuksen & "
                         "Altunbasak, ICIP 2010); ratios to the PPI of Mihoubi et al., IEEE "
                         "TCI 3(4) 2017; smooth-hue transition, Cok 1987",
                         PC_DMF_COLOR},
                        {-10, 10, 1, 1},
                        NULL,
                        NULL,
                        false,
                        PC_DM_PAN_FACT,
                        false},
    [PC_DM_PAN_SIDE] =
        {{PC_DM_PAN_SIDE, "pan-side",
          "colour-polarization: pan-guided whose tents weigh each side of the "
          "pixel by the hue distance to it (one pair of factors per 2x2 block "
          "and axis, range scale 4 % of full scale); over bayer-first (bench "
          "colour, 9 scenes) smooth colours +4.51/+1.68 (worst +2.51/+0.40), "
          "hue patches +1.08/+2.29 (worst +0.89/+1.66); colour stress suite (5 "
          "scenes) +1.39/+1.26 (worst +0.65 gratings/+0.04 gratings): the "
          "colour accuracy goal met on all three sets, narrowly (margins <= "
          "0.05 dB, parameters chosen on them), not on the held-out colour "
          "scenes (scenes/stress/colour-holdout, 9): +0.07/+1.50 (worst "
          "-1.72/-0.11), 4 losing (docs/demosaicking.md, Round 13b); sealed "
          "set (scenes/stress/colour-sealed, 8, its first evaluation) "
          "+2.34/+1.61 (worst +1.40/+0.23), none losing (Round 14); hue-pair dev "
          "set (scenes/stress/colour-hue, 5, Round 16) -0.91/+0.50 (worst "
          "-1.27/+0.33, all 5 losing)",
          "3.9-5.8x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms); pan-guided's pass with the factors: "
          "per even row one more vertical "
          "sum, the chrominance, the blocks' hue and two factor rows; 1.22x "
          "pan-guided's instructions (callgrind, AVX2; 292 M vs 240 M per frame after "
          "Rounds 14b, 14c), 1.17-1.23x its median wall time near idle; "
          "4.0-4.9x the mono bilinear's in the same runs (eight runs; Round 17d, "
          "eight more: 4.0-4.8x), within the 5x budget (docs/demosaicking.md, "
          "Rounds 14d, 17d)",
          "ours: pan-guided with side weights as GBTF's (Pekkucuksen & "
          "Altunbasak, ICIP 2010) from pan-chroma's hue (Alleysson et al., IEEE "
          "TIP 14(4) 2005); docs/demosaicking.md, Round 13",
          PC_DMF_COLOR},
         {PAN_LO - 1, PAN_HI + 1, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_SIDE,
         false},
    [PC_DM_PAN_ADAPT] = {{PC_DM_PAN_ADAPT, "pan-adapt",
                          "colour-polarization: pan-side with a range scale relative to the "
                          "local signal (13 % of the 5x5 mean of the PPI) and the ratio "
                          "step's level shrunk towards its 5x5 mean where the frame's noise "
                          "(estimated from the frame, or given: --noise-gain) is of the order of "
                          "the local variation; "
                          "over bayer-first (bench colour --reference, 9 scenes) smooth colours "
                          "+4.53/+1.69 (worst +2.46/+0.40), hue patches +1.10/+2.20 (worst "
                          "+0.89/+1.70); colour stress suite (5 scenes) +1.38/+1.23 (worst "
                          "+0.67/+0.11 gratings); noisy copies of the stress scenes (4) "
                          "+0.95/+0.45 (worst +0.28/+0.19) (Round 19's noise gain); its two "
                          "constants chosen on these (with Round 14's); "
                          "hue-pair dev set (scenes/stress/colour-hue, 5, Round 16) -0.80/+0.53 "
                          "(worst -1.07/+0.40, all 5 losing); "
                          "held-out colour scenes (seen before, 9) +0.23/+1.53 (worst "
                          "-1.04/-0.07, 3 losing); sealed set (scenes/stress/colour-sealed, 8, "
                          "its first evaluation) +2.31/+1.36 (worst +1.04/+0.41 textile), none "
                          "losing (docs/demosaicking.md, Round 14); colour-sealed5 (6, Round 19) "
                          "+1.62/+0.86 (worst +0.80/-0.08, 1 losing DoLP: cobbles)",
                          "5.5-8.7x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 "
                          "threads; the multiple swings with the bilinear's 1.6-3.0 ms); "
                          "pan-side's fused pass with each row's 5x5 window mean and variance "
                          "of the PPI and the shrunk ratio step, within 1e-5 of full scale of "
                          "the double reference: 1.24x pan-side's instructions (callgrind, "
                          "AVX2, one thread: 349 M per frame, 5.7 M of them the noise gain, "
                          "now on the caller's threads), 13x the mono bilinear's 26.6 M; "
                          "near idle 5.2-6.8x the mono bilinear's median wall time (Rounds "
                          "16d and 17d, eight runs; 6.6-7.0x before Round 16a), over the 5x "
                          "budget (docs/demosaicking.md, Rounds 14 fast path, 16a, 16d, 17d)",
                          "ours: pan-side (docs/demosaicking.md, Round 13) with a relative "
                          "range scale (Durand & Dorsey, SIGGRAPH 2002) and ratio-nr's "
                          "shrinkage (He, Sun, Tang, TPAMI 35(6) 2013, eq. 7); noise gain "
                          "from the median residual (Donoho & Johnstone, Biometrika 81(3) "
                          "1994) under EMVA 1288's linear model",
                          PC_DMF_COLOR | PC_DMF_NOISE_GAIN},
                         {PAN_ADAPT_LO, PAN_ADAPT_HI, 1, 1},
                         NULL,
                         NULL,
                         false,
                         PC_DM_PAN_ADAPT,
                         false},
    [PC_DM_PAN_GUARD] = {{PC_DM_PAN_GUARD, "pan-guard",
                          "colour-polarization: pan-adapt blended per colour towards "
                          "bayer-first where a leave-one-out check on the colour's own samples "
                          "finds the pan ratio model locally less predictive (weights from the "
                          "two models' errors over 3x3 blocks, exponent 8); over bayer-first "
                          "(bench colour --reference, Round 19's noise gain) smooth colours (9) "
                          "+4.59/+1.71 (worst +2.42/+0.46), hue patches (9) +1.19/+1.78 (worst "
                          "+1.03/+1.49), colour stress suite (5) +1.48/+1.38 (worst "
                          "+0.60/+0.26), noisy copies (4) +0.96/+0.43 (worst +0.34/+0.26); its "
                          "constants chosen on these (with Round 14's noise gain); "
                          "hue-pair dev set (scenes/stress/colour-hue, 5, Round 16) -0.36/+0.52 "
                          "(worst -0.61/+0.35, all 5 losing); "
                          "held-out colour scenes (seen before, 9) +0.71/+1.37 (worst "
                          "-0.63/+0.37, 1 losing: gratings2); second sealed set "
                          "(scenes/stress/colour-sealed2, 7, its first evaluation) +1.07/+0.96 "
                          "(worst -0.09/+0.53, 1 losing: print) (docs/demosaicking.md, Round 15); "
                          "colour-sealed5 (6, Round 19) +1.53/+0.86 (worst +0.68/+0.04), none "
                          "losing",
                          "17-32x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 "
                          "threads; the multiple swings with the bilinear's 1.6-3.0 ms); float "
                          "fast path: pan-adapt's fast path, then per row band "
                          "bayer-first's rows, the block check and the blend (no whole-frame "
                          "scratch); 806 M instructions per 2448x2048 frame (callgrind, AVX2, "
                          "one thread), 30x mono bilinear's, of which pan-adapt and bayer-first "
                          "620 M; near idle 16.9-22.1x mono bilinear's median wall time, "
                          "38-48 ms a frame (Rounds 16d and 17d, twelve runs; 312-388x before "
                          "Round 16b): far over the 5x budget (docs/demosaicking.md, Rounds "
                          "16b, 16d, 17d)",
                          "ours (docs/demosaicking.md, Round 15): pan-adapt and bayer-first "
                          "combined by their local leave-one-out errors (Bates & Granger, "
                          "Operational Research Quarterly 20(4) 1969, sharpened); its base "
                          "pan-adapt takes a given noise gain (--noise-gain)",
                          PC_DMF_COLOR | PC_DMF_NOISE_GAIN},
                         {PAN_GUARD_LO, PAN_GUARD_HI, 1, 1},
                         NULL,
                         NULL,
                         false,
                         PC_DM_PAN_GUARD,
                         false},
    [PC_DM_PAN_HUE] = {{PC_DM_PAN_HUE, "pan-hue",
                        "colour-polarization: pan-guard whose red and blue move further "
                        "towards bayer-first where green's ratio-model residual (its lower "
                        "quartile over 3x3 lattice steps, less its expected noise), carried "
                        "into them by the ratio step, outweighs their own plain-interpolation "
                        "residual (hue detail near the colour lattice's period that P0 does not "
                        "see; green's residual less 0.75 times the part the ratio model "
                        "explains, as pan-check's), and whose base keeps each colour's own detail "
                        "where its ratio "
                        "residual exceeds a quarter of its expected noise (pan-adapt's "
                        "shrinkage undone there); over bayer-first (bench colour --reference) "
                        "smooth colours (9) +4.47/+1.71 (worst +1.95/+0.46), hue patches (9) "
                        "+1.15/+1.65 (worst +1.01/+1.41), colour stress suite (5) +1.42/+1.37 "
                        "(worst +0.44/+0.29), noisy copies (4) +0.87/+0.39 (worst +0.28/+0.25), "
                        "hue-pair scenes (scenes/stress/colour-hue, 5) +0.12/+0.58 (worst "
                        "-0.02/+0.39, 1 losing); its constants chosen on these with Round 14's "
                        "noise gain, beta taken from pan-check (docs/demosaicking.md, Rounds "
                        "16, 17a, 19 and 19e)",
                        "double reference only (pan-guard's reference with pan-adapt's twice, "
                        "bayer-first's and the gate): hundreds of times mono bilinear's time, "
                        "for evaluation only",
                        "ours (docs/demosaicking.md, Rounds 16 and 17a): pan-guard "
                        "(Round 15) with a cross-colour gate weighted as Bates & Granger "
                        "(Operational Research Quarterly 20(4) 1969), sharpened",
                        PC_DMF_COLOR | PC_DMF_REFERENCE_ONLY},
                       {PAN_HUE_LO, PAN_HUE_HI, 1, 1},
                       NULL,
                       NULL,
                       false,
                       PC_DM_PAN_HUE,
                       false},
    [PC_DM_PAN_CHECK] =
        {{PC_DM_PAN_CHECK, "pan-check",
          "colour-polarization: pan-side blended per colour towards a "
          "conservative estimate one band pass could compute (bayer-first's "
          "green level with the own-lattice tents' polarization; the tents' red "
          "and blue, which equal bayer-first's) where pan-guard's leave-one-out "
          "check, with a noise term per colour, finds the ratio model locally "
          "worse, red and blue also by pan-hue's gate on the part of green's "
          "detail the ratio model does not explain (beta 0.75, Round 19b); over "
          "bayer-first (bench colour --reference) smooth colours (9) +4.22/+1.63 "
          "(worst +1.89/+0.39), hue patches (9) +1.15/+1.95 (worst +1.01/+1.53), "
          "colour stress suite (5) +1.44/+1.45 (worst +0.44/+0.26), noisy copies "
          "(4) +0.78/+0.86 (worst +0.20/+0.68), hue-pair scenes "
          "(scenes/stress/colour-hue, 5) +0.12/+1.03 (worst +0.01/+0.84), no "
          "scene losing; its constants chosen on these (docs/demosaicking.md, "
          "Rounds 17, 18, 19 and 19b); unseen: colour-sealed6 (5, evaluated once, "
          "Round 19b) +1.49/+0.97 (worst +0.90/+0.74), none losing: the accuracy "
          "goal met; again, unchanged, on colour-sealed7 (6, evaluated once, Round "
          "19d) +1.22/+1.01 (worst +0.72/+0.70), none losing; earlier definitions on earlier "
          "sealed sets, evaluated once: "
          "colour-sealed3 +1.65/+1.37, colour-sealed4 +0.81/+0.97, colour-sealed5 "
          "+0.84/+0.95 (mean S0 short; with this definition, now used: +2.08/+1.56, "
          "+1.03/+1.01, +1.15/+1.09, none losing); held-out (9, seen) +0.72/+1.78 "
          "(worst -0.05/+0.80, 1 losing: gratings2)",
          "15-22x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the multiple "
          "swings with the bilinear's 1.6-3.0 ms); float fast path: pan-side's fast path, then per "
          "row band pan-guard's "
          "check with the noise term, pan-hue's gate per block row, bayer-first's "
          "rows and the own-lattice tents for the conservative estimate, and the "
          "blends; 681 M instructions per 2448x2048 frame (callgrind, AVX2, one "
          "thread), 26x mono bilinear's, of which pan-side 256 M, green's analyser "
          "mean 45 M, the check 88 M, the gate 32 M, the weights' tents 67 M, the "
          "conservative estimate's tents with the blends 163 M, the noise gain 12 M; "
          "16-18x its time near idle at AVX-512 (34-36 ms), 28-31x at AVX2 (45-49 "
          "ms): far over the 5x budget "
          "(docs/demosaicking.md, Rounds 18a, 18d, 19, 19b and 19c)",
          "ours (docs/demosaicking.md, Rounds 17 and 18): pan-guard's check (Bates & "
          "Granger, Operational Research Quarterly 20(4) 1969, sharpened) on "
          "estimates one band pass can compute",
          PC_DMF_COLOR},
         {PAN_CHECK_LO, PAN_CHECK_HI, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_CHECK,
         false},
    [PC_DM_PAN_SPLIT] = {{PC_DM_PAN_SPLIT, "pan-split",
                          "colour-polarization: pan-adapt whose ratio step carries green's "
                          "detail into red and blue times t = (S_Y - S_C)/(S_Y + S_C), S_Y "
                          "and S_C the local high-pass energy of the luminance P0 and of the "
                          "demodulated green-magenta chrominance (t = -1: the detail flipped); "
                          "over bayer-first (bench colour --reference) smooth colours (9) "
                          "+4.30/+1.69 (worst +2.11/+0.40), hue patches (9) +1.46/+2.27 (worst "
                          "+1.24/+1.84), colour stress suite (5) +1.45/+1.29 (worst "
                          "+0.22/+0.11), noisy copies (4) +0.88/+0.45 (worst -0.11/+0.19 "
                          "gratings_g24), hue-pair dev set (5) -0.03/+0.56 (worst -0.21/+0.40 "
                          "gm_bars_g18); its constants chosen on these (docs/demosaicking.md, "
                          "Round 17b)",
                          "double reference only (pan-adapt's reference and a per-pixel pass), "
                          "for evaluation",
                          "ours (docs/demosaicking.md, Round 17b): pan-adapt (Round 14) with a "
                          "least-squares detail transfer in the luminance-chrominance model of "
                          "the colour layer (Alleysson et al., IEEE TIP 14(4) 2005; Dubois, "
                          "IEEE SPL 12(12) 2005)",
                          PC_DMF_COLOR | PC_DMF_REFERENCE_ONLY},
                         {PAN_SPLIT_LO, PAN_SPLIT_HI, 1, 1},
                         NULL,
                         NULL,
                         false,
                         PC_DM_PAN_SPLIT,
                         false},
    [PC_DM_PAN_LEAN] =
        {{PC_DM_PAN_LEAN, "pan-lean",
          "colour-polarization: pan-side's tents without range weights, side "
          "factors flattened by the hue's noise and by texture finer than the "
          "blocks, a level shrunk towards the mean of its 3x3 blocks' levels within "
          "the noise, the own colour's detail cored; over bayer-first (bench "
          "colour --reference) smooth colours (9) +3.47/+1.72 (worst +1.70/+0.46), "
          "hue patches (9) +1.08/+2.62 (+0.96/+1.78), colour stress (5) "
          "+1.20/+1.60 (+0.32/+0.24), noisy copies (4) +0.73/+0.57 (+0.11/+0.45), "
          "hue pairs (5) +0.03/+1.00 (+0.00/+0.76); unseen, each evaluated once: "
          "colour-sealed11 (6) +1.43/+1.47 (+1.30/+0.59), and with Round 24's "
          "6x6 pixel window colour-sealed9 (6) +1.09/+1.45 (+0.63/+1.09) and "
          "colour-sealed10 (6) +1.15/+1.36 (+0.34/+0.82); since Round 42's exact "
          "zeros in the black colour-sealed12 (6) +1.34/+1.81 (+0.92/+0.48) and "
          "(used) colour-sealed4 (6) +0.84/+1.30 (+0.36/+0.99: before it, -0.87 "
          "DoLP on conveyor's black regions); no scene of any colour set losing; "
          "60 random scenes of the dataset family through the colour sensor (seed "
          "20261207, 640x512, IMX250MYR at 0-12 dB; scenes/stress/gen_family.py) "
          "+2.16/+0.66 (+0.30/+0.15), none losing; seed 20261208 +2.04/+0.93 "
          "(+0.54/+0.31), none losing; docs/demosaicking.md, Rounds 24, 27, 42, 45 and 46",
          "3.9-5.6x the mono bilinear's time (Round 44d: four runs, AVX-512, 2 threads; the "
          "multiple swings with the bilinear's 1.6-3.0 ms; 4.9-5.3x in the dev host's usual "
          "regime of Round 45); float fast path in pan-side's band "
          "form: within 2.4e-7 of full scale "
          "of the double reference; at AVX-512 4.9-5.6x the mono bilinear's time "
          "against its faster kernel (Round 44b: over the 5x budget in most runs), "
          "before it 3.8-4.2x the mono bilinear's time "
          "in the shared 2-vCPU dev machine's usual regime, 5.2-5.8x in periods when "
          "its write bandwidth doubles and the memory-bound bilinear speeds up with "
          "it (2026-12-06; Round 31: 0.93 of Round 30's time; twelve planes that "
          "start at one page offset cost it up to a fifth more, docs/api.md); at "
          "AVX2 6.0x and 8.8x in the two (bayer-first 6.9x and 9.4x), 9.5-10.0x in "
          "the generic vector build (bayer-first 6.9-7.3x: 1.4x its time, Round 34); "
          "writing the 12 planes "
          "alone takes 1.6-2.3x (docs/demosaicking.md, Rounds 23-31)",
          "ours (docs/demosaicking.md, Rounds 21, 24 and 27): pan-side (Round 13) with "
          "GBTF-style side weights (Pekkucuksen & Altunbasak, ICIP 2010), the "
          "guided filter's shrinkage (He, Sun, Tang, TPAMI 2013) and Wiener-type "
          "coring (Round 20 (e))",
          PC_DMF_COLOR | PC_DMF_NOISE_GAIN},
         {PAN_LEAN_LO, PAN_LEAN_HI, 1, 1},
         NULL,
         NULL,
         false,
         PC_DM_PAN_LEAN,
         false},
};

const pc_dm_method_def *pc_dm_method_def_get(pc_demosaic_method m)
{
	if ((int)m < 0 || (int)m >= PC_DM_COUNT)
		return NULL;
	return &pc_dm_methods[m];
}

/* ---- validation ---- */

pc_pipeline_opts pc_dm_opts_legacy(const pc_mosaic *m, pc_demosaic_method method,
                                   const pc_demosaic_opts *opts)
{
	pc_pipeline_opts o;
	memset(&o, 0, sizeof o);
	o.method = method;
	if (m)
		o.mosaic = *m; /* else period 0: pc_mosaic_check refuses it */
	if (opts) {
		o.threads = opts->threads;
		o.reference = opts->reference;
		o.full_scale = opts->full_scale;
	}
	return o;
}

static int check_level(const char *name, double v)
{
	if (!isfinite(v) || v < 0)
		return pc_error(
		    PC_EINVAL, "%s %g: expected a finite value >= 0 (raw units; 0: none)", name, v);
	return 0;
}

int pc_dm_plan_begin(const pc_view *raw, const pc_pipeline_opts *opts, pc_dm_plan *p)
{
	memset(p, 0, sizeof *p);
	if (!opts)
		return pc_error(PC_EINVAL, "pipeline options missing");
	int rc = pc_view_check(raw);
	if (rc)
		return pc_error_prefix(rc, "raw: ");
	const pc_mosaic *m = &opts->mosaic;
	rc = pc_mosaic_check(m);
	if (rc)
		return rc;
	const pc_dm_method_def *def = pc_dm_method_def_get(opts->method);
	if (!def)
		return pc_error(PC_EINVAL, "demosaicking method %d: unknown", (int)opts->method);
	const pc_demosaic_method_info *mi = &def->info;
	int colour = m->period == 4;
	if (colour && !(mi->flags & PC_DMF_COLOR)) {
		char list[512];
		pc_demosaic_method_names(PC_DMF_COLOR, list, sizeof list);
		return pc_error(PC_EINVAL,
		                "method %s works on monochrome polarizer mosaics only; "
		                "this mosaic has a colour filter (methods for it: %s)",
		                mi->name, list);
	}
	if (!colour && !(mi->flags & PC_DMF_MONO))
		return pc_error(PC_EINVAL, "method %s works on colour-polarization mosaics only",
		                mi->name);
	uint32_t minsz = colour ? 8 : 4;
	if (raw->width % 2 || raw->height % 2)
		return pc_error(PC_EINVAL,
		                "raw size %ux%u: width and height must be even (whole 2x2 "
		                "analyser blocks); crop one column or row",
		                raw->width, raw->height);
	if (raw->width < minsz || raw->height < minsz)
		return pc_error(PC_EINVAL, "raw size %ux%u: at least %ux%u pixels are needed",
		                raw->width, raw->height, minsz, minsz);
	if (raw->width > (1u << 30) || raw->height > (1u << 30))
		return pc_error(PC_EINVAL, "raw size %ux%u: too large", raw->width, raw->height);
	if ((rc = check_level("black level", opts->black_level)) ||
	    (rc = check_level("saturation level", opts->saturation_level)) ||
	    (rc = check_level("dead level", opts->dead_level)))
		return rc;
	if (!isfinite(opts->noise_gain) || opts->noise_gain < 0)
		return pc_error(
		    PC_EINVAL,
		    "noise_gain %g: expected a finite value >= 0 (the variance per unit "
		    "signal in raw units, EMVA 1288's system gain K in DN/e-; 0: "
		    "estimated from the frame)",
		    opts->noise_gain);
	if (!isfinite(opts->dark_scale) || opts->dark_scale < 0 || !isfinite(opts->dark_pivot))
		return pc_error(PC_EINVAL,
		                "dark_scale %g, dark_pivot %g: expected finite values, the scale "
		                ">= 0 (0: the dark map as it is)",
		                opts->dark_scale, opts->dark_pivot);
	if (opts->saturation_level > 0 && opts->dead_level > 0 &&
	    !(opts->dead_level < opts->saturation_level))
		return pc_error(PC_EINVAL, "dead level %g: must be below the saturation level %g",
		                opts->dead_level, opts->saturation_level);
	const pc_format_info *fi = pc_format_info_get(raw->format);
	double fs = opts->full_scale > 0 && isfinite(opts->full_scale) ? opts->full_scale
	            : fi->is_float                                     ? 1.0
	                           : (double)((1u << fi->bits) - 1u);
	if (!(opts->black_level < fs))
		return pc_error(PC_EINVAL, "black level %g: must be below the full scale %g",
		                opts->black_level, fs);
	p->raw = raw;
	p->def = def;
	p->opts = *opts;
	p->colour = colour;
	const bool half = mi->flags & PC_DMF_HALF_RES;
	p->ow = half ? raw->width / 2 : raw->width;
	p->oh = half ? raw->height / 2 : raw->height;
	p->nch = colour ? 12u : 4u;
	p->full_scale = fs - opts->black_level;
	p->level = pc_cpu_active();
	return 0;
}

void pc_dm_plan_end(pc_dm_plan *p)
{
	pc_dm_free(p->owned);
	p->owned = NULL;
	p->prepared = false;
}

int pc_dm_plan_input(pc_dm_plan *p, const pc_dm_input **in)
{
	if (!p->prepared) {
		int rc = pc_dm_prepare_input(p->raw, p->opts.black_level, &p->in, &p->owned);
		if (rc)
			return rc;
		p->prepared = true;
	}
	*in = &p->in;
	return 0;
}

int pc_dm_plan_corrected(pc_dm_plan *p, float **img, pc_view *view, pc_pipeline_opts *o)
{
	*img = NULL;
	const pc_dm_input *in0;
	int rc = pc_dm_plan_input(p, &in0);
	if (rc)
		return rc;
	pc_dm_input in = *in0;
	pc_dm_input_dark(&in, &p->opts);
	const uint32_t w = in.width, h = in.height;
	float *f = malloc((size_t)w * h * sizeof *f), *row = malloc(((size_t)w + 2) * sizeof *row);
	if (!f || !row) {
		free(f);
		free(row);
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot correct", w, h);
	}
	for (uint32_t y = 0; y < h; y++) {
		pc_dm_row_to_float(&in, y, row + 1);
		memcpy(f + (size_t)y * w, row + 1, (size_t)w * sizeof *f);
	}
	free(row);
	*img = f;
	*view = (pc_view){f, w, h, (size_t)w * sizeof *f, PC_FMT_FLOAT32};
	*o = p->opts;
	o->dark = o->gain_inv = NULL;
	o->black_level = 0;
	o->saturation_level = o->dead_level = 0;
	o->full_scale = p->full_scale;
	return 0;
}

int pc_dm_plan_noise(pc_dm_plan *p, const double *img)
{
	if (p->noise_set || p->colour || !(p->def->info.flags & PC_DMF_NOISE_GAIN))
		return 0;
	double g = p->opts.noise_gain;
	int rc = 0;
	if (!(g > 0)) {
		if (img) {
			rc = pc_dm_noise_ptc_d(img, p->raw->width, p->raw->height, &p->opts.mosaic,
			                       p->full_scale, -p->opts.black_level, &g, NULL);
		} else {
			const pc_dm_input *in;
			rc = pc_dm_plan_input(p, &in);
			if (!rc)
				rc = pc_dm_noise_ptc_in(in, &p->opts.mosaic, p->full_scale, &g,
				                        NULL);
		}
	}
	if (!rc) {
		p->noise_gain = g;
		p->noise_set = true;
	}
	return rc;
}

void pc_dm_plan_noise_report(const pc_dm_plan *p)
{
	if (p->noise_set && p->opts.noise_gain_used)
		*p->opts.noise_gain_used = p->noise_gain;
}

pc_dm_call pc_dm_plan_call(const pc_dm_plan *p)
{
	pc_dm_call c = {&p->in,          &p->opts.mosaic, p->opts.method, p->full_scale,
	                p->opts.threads, p->level,        p->noise_gain};
	return c;
}

/* ---- demosaicking paths ---- */

/* The reference of a monochrome method on a raw in double. */
static int mono_reference(pc_dm_plan *p, const double *img, const pc_mosaic *m,
                          pc_demosaic_method method, const pc_fplane *out)
{
	int rc = pc_dm_plan_noise(p, img);
	if (rc)
		return rc;
	return pc_dm_ref(img, p->raw->width, p->raw->height, m, method, p->full_scale,
	                 p->noise_gain, out);
}

/* A colour method of its own (demosaic_pan.h): the reference on the raw minus black, or the fast
 * path on the prepared input. The methods that use a noise gain (PC_DMF_NOISE_GAIN) take it
 * from here through their ref_g and fast_g: the given one (pc_pipeline_opts.noise_gain > 0), or
 * the estimate their own ref and fast would make (pc_dm_noise_gain_d on the reference's raw,
 * pc_dm_noise_gain_in_mt on the fast path's, on the plan's threads: the same value at any thread
 * count, pc_demosaic_noise_gain's), made once and stored for the caller (noise_gain_used). */
static int colour_own(pc_dm_plan *p, const pc_dm_pan_fns *fn, const pc_fplane *out)
{
	const uint32_t w = p->raw->width, h = p->raw->height;
	const bool uses_g = p->def->info.flags & PC_DMF_NOISE_GAIN;
	if (uses_g && !(fn->ref_g && fn->fast_g))
		return pc_error(PC_ENOTSUP, "%s: no path for a noise gain", p->def->info.name);
	double g = uses_g ? p->opts.noise_gain : 0;
	int rc;
	if (p->opts.reference || !fn->fast) {
		double *img = NULL;
		rc = pc_dm_raw_to_double(p->raw, p->opts.black_level, &img);
		if (!rc && uses_g && !(g > 0))
			rc = pc_dm_noise_gain_d(img, w, h, &p->opts.mosaic, p->full_scale, &g);
		if (!rc)
			rc = uses_g ? fn->ref_g(img, w, h, &p->opts.mosaic, p->full_scale, g, out)
			            : fn->ref(img, w, h, &p->opts.mosaic, p->full_scale, out);
		free(img);
	} else {
		const pc_dm_input *in;
		rc = pc_dm_plan_input(p, &in);
		if (!rc && uses_g && !(g > 0))
			rc = pc_dm_noise_gain_in_mt(in, &p->opts.mosaic, p->full_scale,
			                            p->opts.threads, &g);
		if (!rc)
			rc = uses_g ? fn->fast_g(in, &p->opts.mosaic, p->full_scale,
			                         p->opts.threads, p->level, g, out)
			            : fn->fast(in, &p->opts.mosaic, p->full_scale, p->opts.threads,
			                       p->level, out);
	}
	if (!rc && uses_g && p->opts.noise_gain_used)
		*p->opts.noise_gain_used = g;
	return rc;
}

static int colour_demosaic(pc_dm_plan *p, const pc_fplane *out)
{
	const pc_dm_pan_fns *own = pc_dm_pan_fns_get(p->opts.method);
	if (!own)
		own = pc_dm_fact_fns_get(p->opts.method);
	if (own)
		return colour_own(p, own, out);
	const uint32_t w = p->raw->width, h = p->raw->height;
	if (p->opts.method == PC_DM_BAYER_FIRST && !p->opts.reference) {
		/* the one-pass fast path (the two steps' weights composed) */
		const pc_dm_input *in;
		int rc = pc_dm_plan_input(p, &in);
		if (!rc)
			rc = pc_dm_bayer_first(in, &p->opts.mosaic, p->opts.threads, p->level, out);
		return rc;
	}
	const size_t n = (size_t)w * h;
	const pc_demosaic_method second = p->def->second;
	const pc_dm_method_def *sdef = pc_dm_method_def_get(second);
	if (p->opts.reference || !sdef->fast) {
		double *img = NULL;
		int rc = pc_dm_raw_to_double(p->raw, p->opts.black_level, &img);
		if (!rc)
			rc = pc_dm_bayer_first_ref(img, w, h, &p->opts.mosaic, second,
			                           p->full_scale, out);
		free(img);
		return rc;
	}
	const pc_mosaic mono = pc_dm_color_mono(&p->opts.mosaic);
	int rc = 0;
	float *mf[3] = {NULL, NULL, NULL}, *fin = NULL;
	for (int k = 0; k < 3 && !rc; k++)
		if (!(mf[k] = malloc(n * sizeof(float))))
			rc = pc_error(PC_ENOMEM, "colour demosaicking: %ux%u images", w, h);
	if (!rc)
		rc = pc_dm_raw_to_float(p->raw, p->opts.black_level, &fin);
	if (!rc)
		rc = pc_dm_color_split(fin, w, h, &p->opts.mosaic, p->opts.threads, mf);
	for (unsigned k = 0; k < 3 && !rc; k++) {
		pc_dm_input in = pc_dm_input_f32(mf[k], w, h);
		pc_dm_call c = {&in, &mono, second, p->full_scale, p->opts.threads, p->level, 0};
		rc = sdef->fast(&c, out + 4 * k);
	}
	for (int k = 0; k < 3; k++)
		free(mf[k]);
	free(fin);
	return rc;
}

int pc_dm_plan_demosaic(pc_dm_plan *p, const pc_fplane *out)
{
	if (p->colour)
		return colour_demosaic(p, out);
	if (!p->opts.reference && p->def->fast) {
		const pc_dm_input *in;
		int rc = pc_dm_plan_input(p, &in);
		if (!rc)
			rc = pc_dm_plan_noise(p, NULL);
		if (rc)
			return rc;
		pc_dm_call c = pc_dm_plan_call(p);
		rc = p->def->fast(&c, out);
		if (!rc)
			pc_dm_plan_noise_report(p);
		return rc;
	}
	double *img = NULL;
	int rc = pc_dm_raw_to_double(p->raw, p->opts.black_level, &img);
	if (!rc)
		rc = mono_reference(p, img, &p->opts.mosaic, p->opts.method, out);
	free(img);
	if (!rc)
		pc_dm_plan_noise_report(p);
	return rc;
}

/* ---- validity ---- */

int pc_dm_plan_check_validity(const pc_dm_plan *p, const pc_validity *v)
{
	if (v && v->mask && v->row_stride < p->ow)
		return pc_error(PC_EINVAL, "validity mask: row stride %zu bytes below the width %u",
		                v->row_stride, p->ow);
	return 0;
}

int pc_dm_check_distrust(const pc_compact_calib *v, uint32_t width, uint32_t height)
{
	if (v->distrust_row && (v->width != width || v->height != height))
		return pc_error(PC_EINVAL, "Stokes: compact calibration %ux%u for a %ux%u raw",
		                v->width, v->height, width, height);
	if (!v->distrust_row != !v->distrust_x)
		return pc_error(PC_EINVAL, "Stokes: compact calibration: distrust_row and "
		                           "distrust_x go together");
	for (uint32_t y = 0; v->distrust_row && y < v->height; y++) {
		if (v->distrust_row[y + 1] < v->distrust_row[y])
			return pc_error(PC_EINVAL,
			                "Stokes: compact calibration: distrust_row decreases at "
			                "row %u",
			                y);
		for (uint32_t i = v->distrust_row[y]; i < v->distrust_row[y + 1]; i++)
			if (v->distrust_x[i] >= v->width)
				return pc_error(PC_EINVAL,
				                "Stokes: compact calibration: distrusted sample "
				                "(%u,%u) outside the %ux%u raw",
				                v->distrust_x[i], y, v->width, v->height);
	}
	return 0;
}

int pc_dm_plan_validity(pc_dm_plan *p, pc_validity *v)
{
	const pc_dm_input *in;
	v->n_invalid = 0;
	pc_dm_levels lv = {p->opts.saturation_level, p->opts.dead_level, p->opts.trusted, NULL,
	                   NULL};
	if (p->opts.compact && p->opts.compact->distrust_row) {
		/* checked here too: pc_validity_run takes the list without pc_stokes_run's checks
		 */
		int rc = pc_dm_check_distrust(p->opts.compact, p->raw->width, p->raw->height);
		if (rc)
			return rc;
		lv.dis_row = p->opts.compact->distrust_row;
		lv.dis_x = p->opts.compact->distrust_x;
	}
	if (!(lv.saturation > 0) && !(lv.dead > 0) && !lv.trusted && !lv.dis_row && !v->mask)
		return 0;
	int rc = pc_dm_plan_input(p, &in);
	if (rc)
		return rc;
	return pc_dm_validity(in, &p->def->support, &lv, p->ow, p->oh, p->opts.threads, v->mask,
	                      v->row_stride, &v->n_invalid);
}
