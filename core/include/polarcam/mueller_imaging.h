/* polarcam/mueller_imaging.h - per-pixel Mueller matrices from frame sequences of a division-of-
 * focal-plane camera under known polarization states (physics.md §7).
 *
 * Measurement model. Frame j is taken with generator (PSG) state g and analyser (PSA) state a,
 * j = g + n_psg·a (generator fastest, as the simulator orders them). Mosaic channel c (0°, 45°,
 * 90°, 135°) of that frame reads
 *     I_{j,c} = r_{a,c} · M · s_g,   r_{a,c} = w_c · P_a   (1×4),
 * with w_c the channel's analyser row (ideal: ½(1, cos2θ_c, sin2θ_c, 0)), P_a the PSA element's
 * Mueller matrix and s_g the generated Stokes vector. Stacking the 4·n_psa rows r_{a,c} into A
 * and the generator vectors as the columns of G gives the intensity matrix I = A·M·G, i.e.
 * vec(I) = W·vec(M) with W = A ⊗ Gᵀ (row-major vec). The least-squares solution is
 *     M = A⁺ · I · G⁺,
 * which equals W⁺·vec(I) because (A ⊗ Gᵀ)⁺ = A⁺ ⊗ (Gᵀ)⁺, and cond(W) = cond(A)·cond(G)
 * (Horn & Johnson, Topics in Matrix Analysis, 1991, §4.2). With independent noise of variance
 * σ² on every intensity the covariance of vec(M) is σ²·(WᵀW)⁻¹ = σ²·(AᵀA)⁻¹ ⊗ (GGᵀ)⁻¹, so
 * element (k, l) of M has standard deviation σ·sqrt([(AᵀA)⁻¹]_kk·[(GGᵀ)⁻¹]_ll): the noise gain.
 *
 * Rank. A DoFP camera alone (no retarder in the PSA) does not see S3: A has rank 3, and linear
 * generator states give G rank 3. Then only the 3×3 linear block (rows/columns 0..2) is
 * determined; the other elements are reported as NaN and the condition numbers are those of
 * the determined parts.
 */
#ifndef POLARCAM_MUELLER_IMAGING_H
#define POLARCAM_MUELLER_IMAGING_H

#include <stdint.h>

#include <stdbool.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_MUELLER_MAX_STATES 64

typedef struct pc_mueller_system {
	unsigned n_psg, n_psa;
	double A[4 * PC_MUELLER_MAX_STATES][4];  /* analyser rows r_{a,c}, row 4a + c */
	double G[4][PC_MUELLER_MAX_STATES];      /* generator Stokes vectors as columns */
	double Ap[4][4 * PC_MUELLER_MAX_STATES]; /* A⁺ */
	double Gp[PC_MUELLER_MAX_STATES][4];     /* G⁺ */
	unsigned rank_A, rank_G;                 /* 3 or 4 */
	double cond_A, cond_G, cond_W;           /* 2-norm condition numbers (determined part) */
	double noise_gain[4][4];                 /* σ(M_kl)/σ(I); NaN where undetermined */
	unsigned determined;                     /* bit 4k + l: element (k, l) is determined */
} pc_mueller_system;

/* Builds the system from n_psg generator Stokes vectors, n_psa PSA Mueller matrices (NULL with
 * n_psa = 1 means no PSA element) and the four channel analyser rows (NULL: ideal). Errors:
 * counts out of range, non-finite input, rank below 3 (PC_ENUMERIC, naming A or G). */
PC_API int pc_mueller_system_init(pc_mueller_system *s, unsigned n_psg, const double (*psg)[4],
                                  unsigned n_psa, const double (*psa)[4][4],
                                  const double (*analyser)[4]);

/* The scalar double reference: M from the n_psg·n_psa·4 intensities of one pixel,
 * I[(g + n_psg·a)·4 + c]. Undetermined elements are NaN. */
PC_API void pc_mueller_solve(const pc_mueller_system *s, const double *I, double M[4][4]);

/* Adds frame j's contribution to per-pixel Mueller matrices: M is float (H, W, 4, 4), zeroed
 * by the caller before the first frame; ch[c] are the frame's four analyser images (channel c
 * at 45°·c, e.g. from pc_demosaic). After every frame of the sequence has been added, M holds
 * A⁺·I·G⁺ (undetermined elements stay 0: pc_mueller_finish marks them NaN). Accumulation in
 * float: relative error ≤ ~1e-6 against pc_mueller_solve (tested), far below shot noise. Runs
 * row bands on pc_parallel threads (threads 0 = default). */
PC_API int pc_mueller_accumulate(const pc_mueller_system *s, unsigned frame, const pc_fplane ch[4],
                                 uint32_t width, uint32_t height, int threads, float *M);

/* Marks the undetermined elements of every pixel NaN. */
PC_API void pc_mueller_finish(const pc_mueller_system *s, uint32_t width, uint32_t height,
                              float *M);

/* ---- The 4×4 from the 3×3 linear block for the pBRDF family (physics.md §7) ----
 *
 * Family: M = R_M(θ_o)·[K·M_F(a, b, c, s) + d·e₀e₀ᵀ]·R_M(θ_i) (physics.md §2: one pure
 * specular Jones matrix diag(r_s, r_p) carried into the image frames plus the diffuse term on
 * M00), with A = Ka, B = Kb, C = Kc, S = Ks. Its 3×3 linear block N determines A, B, C, d and
 * the two frame angles (6 parameters from 9 numbers: 3 consistency conditions); the circular
 * entries follow: M03 = M30 = 0, M33 = C, (M13, M23) = S·v, (M31, M32) = −S·z with v, z the
 * second column of R_M(θ_o) and second row of R_M(θ_i), and |S| = sqrt(A² − B² − C²) (the
 * Jones matrix is pure: a² = b² + c² + s²). Only the sign of S is not determined; for
 * ñ = n − ik with k ≥ 0 (e^{+iωt}, physics.md §1) S ≤ 0 in the frames where B ≥ 0, which is
 * the "convention". Lu–Chipman D, R, Δ do not depend on the sign. Derivation, estimator and
 * tolerances: docs/physics-notes.md, "Rebuilding the 4×4 from the 3×3". */

typedef enum pc_rebuild_sign {
	PC_REBUILD_OFF = 0,    /* do not rebuild (maps: the circular entries stay NaN) */
	PC_REBUILD_CONVENTION, /* S ≤ 0: what Fresnel gives for k ≥ 0 (the same as MINUS) */
	PC_REBUILD_PLUS,       /* S ≥ 0 */
	PC_REBUILD_MINUS,      /* S ≤ 0 */
} pc_rebuild_sign;

enum pc_rebuild_flags {
	PC_RB_ZERO = 1u << 0,         /* N00 ≤ 0: nothing to rebuild (rejected) */
	PC_RB_INCONSISTENT = 1u << 1, /* residual > tol: N is not of the family (rejected) */
	PC_RB_NONPHYSICAL = 1u << 2, /* sqrt(B² + C²) − A > tol·N00 or d < −tol·N00 (rejected) */
	PC_RB_CLAMPED = 1u << 3, /* A² − B² − C² < 0 within tol: S set to 0 */
	PC_RB_S_ZERO = 1u << 4,  /* |S| ≤ tol·N00: the sign does not matter (k = 0, β = 0) */
	PC_RB_SIGN_UNDEFINED = 1u << 5, /* B ≤ tol·N00 < |S|: no diattenuation axis to fix the
	                                   frame of S (a linear retarder, not a pBRDF with k ≥ 0):
	                                   the circular entries are one of the two valid choices */
};
#define PC_RB_REJECTED (PC_RB_ZERO | PC_RB_INCONSISTENT | PC_RB_NONPHYSICAL)

typedef struct pc_rebuild_info {
	double A, B, C, S, d; /* fitted family parameters (S with the chosen sign) */
	double alpha, gamma;  /* polar angles of u = (M10, M20)/B and w = (M01, M02)/B:
	                         α = −2θ_o, γ = 2θ_i (mod π when B = 0) */
	double residual;      /* ‖N − N_fit‖_F / N00 over the 9 elements */
	double excess;        /* (sqrt(B² + C²) − A) / N00: > 0 means not realisable */
	unsigned flags;       /* pc_rebuild_flags */
} pc_rebuild_info;

/* The scalar double reference. N is the 3×3 linear block (rows/columns 0..2 of M); M receives
 * N in its linear block and the rebuilt M03, M13, M23, M30, M31, M32, M33, or NaN there when
 * the input is rejected (PC_RB_REJECTED). tol (relative to N00, ≥ 0) bounds the residual and
 * the realisability excesses. info may be NULL. Returns 0, or PC_EINVAL for non-finite input,
 * a negative or non-finite tol, or sign PC_REBUILD_OFF. */
PC_API int pc_mueller_rebuild_from_linear(const double N[3][3], pc_rebuild_sign sign, double tol,
                                          double M[4][4], pc_rebuild_info *info);

/* Parses "convention", "+", "-", "off" (also "plus", "minus"); PC_EINVAL otherwise. */
PC_API int pc_rebuild_sign_from_name(const char *name, pc_rebuild_sign *out);
PC_API const char *pc_rebuild_sign_name(pc_rebuild_sign sign);

/* ---- Lu–Chipman maps of a Mueller image ---- */

/* Rebuilding the circular entries of rank-3 (linear) systems (physics.md §7,
 * pc_mueller_rebuild_from_linear): sign PC_REBUILD_OFF leaves them NaN. */
typedef struct pc_rebuild_opts {
	pc_rebuild_sign sign;
	double tol; /* residual / realisability tolerance, relative to M00 */
} pc_rebuild_opts;

/* True when the rebuild applies to a system with these determined elements: rb given and not
 * off, the 3×3 linear block determined and not the whole matrix. */
PC_API bool pc_mueller_rebuild_applies(const pc_rebuild_opts *rb, unsigned determined);

/* Lu–Chipman D, R, Δ of every pixel of a (H, W, 4, 4) Mueller image through the batched kernel
 * (pc_lu_chipman_map with PC_LC_FILTER | PC_LC_NO_FACTORS: non-physical matrices are
 * Cloude-filtered first), NaN where undefined and everywhere when determined is not the whole
 * matrix. counts (may be NULL): pixels with D ≈ 1 or M00 ≤ 0, not physical (filtered, or M00 ≤
 * 0), not decomposable (non-finite). Row bands on pc_parallel threads. */
PC_API void pc_mueller_maps(const float *M, uint32_t width, uint32_t height, unsigned determined,
                            int threads, float *D, float *R, float *Delta, long counts[3]);
/* The same, first rebuilding the circular entries in M (in place) where
 * pc_mueller_rebuild_applies: rejected pixels get NaN there and NaN maps; residual (may be NULL)
 * receives the rebuild residual / M00 per pixel; rb_counts: rejected (inconsistent or not
 * realisable; M00 ≤ 0 is not counted), sign undefined. */
PC_API void pc_mueller_maps_rebuild(float *M, uint32_t width, uint32_t height, unsigned determined,
                                    const pc_rebuild_opts *rb, int threads, float *D, float *R,
                                    float *Delta, float *residual, long counts[3],
                                    long rb_counts[2]);

/* ---- Mueller imaging of a frame sequence, frame by frame ----
 *
 * Raw mosaic frames (from any source: a recording, files, a camera, the simulator) are added in
 * sequence order; each is demosaicked, the black level subtracted and its contribution
 * accumulated; finishing gives the per-pixel Mueller image and its Lu–Chipman maps. */

typedef struct pc_mueller_run_opts {
	pc_demosaic_method method; /* the demosaicking method (its output size is the maps') */
	double black_level;        /* DN subtracted from every demosaicked value */
	int threads;               /* 0: pc_parallel default */
	pc_rebuild_opts rebuild;   /* linear-only systems; sign PC_REBUILD_OFF: no rebuild */
	double saturation_level;   /* raw DN: a pixel is invalid when, in any frame, its
	                              demosaicking support (polarcam/demosaic.h) holds a sample at
	                              or above it; 0: the frames' full scale (2^bits − 1; none for
	                              float32 frames); < 0: not checked */
	double dead_level;         /* raw DN: likewise at or below it; 0: not checked */
} pc_mueller_run_opts;

typedef struct pc_mueller_result {
	pc_mueller_system sys;
	uint32_t width, height; /* of the maps (the demosaicked size) */
	float *M;               /* (H, W, 4, 4) in the raw's units above the black level */
	float *maps;            /* D, R, Delta: three (H, W) planes */
	float *residual;        /* (H, W) rebuild residual / M00, NULL when nothing was rebuilt */
	long singular, nonphysical, bad; /* pixel counts: D ≈ 1 / Cloude-filtered / no result */
	long rb_rejected, rb_sign_undefined; /* rebuild: not of the family (M00 > 0) / sign
	                                        without a frame */
	bool rebuilt;                        /* the circular entries were rebuilt from the 3×3 */
	uint8_t *valid;          /* (H, W) 1 valid, 0 saturated/dead in some frame; NULL when no
	                            level was checked. Values are computed as for any pixel */
	long invalid;            /* its 0s */
	double saturation_level; /* checked (0: none) */
} pc_mueller_result;

typedef struct pc_mueller_run pc_mueller_run;

/* Starts a run for the system (copied) and the frames' mosaic (monochrome polarizer mosaics
 * only: PC_EINVAL naming the layout otherwise). */
PC_API int pc_mueller_run_new(const pc_mueller_system *sys, const pc_mosaic *mosaic,
                              const pc_mueller_run_opts *opts, pc_mueller_run **out);
/* Adds frame number frame (0 .. n_psg·n_psa − 1, in order: the float sums depend on it); every
 * frame must have frame 0's size. */
PC_API int pc_mueller_run_add(pc_mueller_run *run, unsigned frame, const pc_view *raw);
/* After the last frame: the Mueller image and its maps (the run hands its buffers over; free
 * them with pc_mueller_result_free). */
PC_API int pc_mueller_run_finish(pc_mueller_run *run, pc_mueller_result *res);
PC_API void pc_mueller_run_free(pc_mueller_run *run);
PC_API void pc_mueller_result_free(pc_mueller_result *res);

#ifdef __cplusplus
}
#endif
#endif
