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

#include "polarcam/demosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_MUELLER_MAX_STATES 64

typedef struct pc_mueller_system {
	unsigned n_psg, n_psa;
	double A[4 * PC_MUELLER_MAX_STATES][4]; /* analyser rows r_{a,c}, row 4a + c */
	double G[4][PC_MUELLER_MAX_STATES];     /* generator Stokes vectors as columns */
	double Ap[4][4 * PC_MUELLER_MAX_STATES]; /* A⁺ */
	double Gp[PC_MUELLER_MAX_STATES][4];     /* G⁺ */
	unsigned rank_A, rank_G;                  /* 3 or 4 */
	double cond_A, cond_G, cond_W;            /* 2-norm condition numbers (determined part) */
	double noise_gain[4][4];                  /* σ(M_kl)/σ(I); NaN where undetermined */
	unsigned determined;                      /* bit 4k + l: element (k, l) is determined */
} pc_mueller_system;

/* Builds the system from n_psg generator Stokes vectors, n_psa PSA Mueller matrices (NULL with
 * n_psa = 1 means no PSA element) and the four channel analyser rows (NULL: ideal). Errors:
 * counts out of range, non-finite input, rank below 3 (PC_ENUMERIC, naming A or G). */
int pc_mueller_system_init(pc_mueller_system *s, unsigned n_psg, const double (*psg)[4],
			   unsigned n_psa, const double (*psa)[4][4], const double (*analyser)[4]);

/* The scalar double reference: M from the n_psg·n_psa·4 intensities of one pixel,
 * I[(g + n_psg·a)·4 + c]. Undetermined elements are NaN. */
void pc_mueller_solve(const pc_mueller_system *s, const double *I, double M[4][4]);

/* Adds frame j's contribution to per-pixel Mueller matrices: M is float (H, W, 4, 4), zeroed
 * by the caller before the first frame; ch[c] are the frame's four analyser images (channel c
 * at 45°·c, e.g. from pc_demosaic). After every frame of the sequence has been added, M holds
 * A⁺·I·G⁺ (undetermined elements stay 0: pc_mueller_finish marks them NaN). Accumulation in
 * float: relative error ≤ ~1e-6 against pc_mueller_solve (tested), far below shot noise. Runs
 * row bands on pc_parallel threads (threads 0 = default). */
int pc_mueller_accumulate(const pc_mueller_system *s, unsigned frame, const pc_fplane ch[4],
			  uint32_t width, uint32_t height, int threads, float *M);

/* Marks the undetermined elements of every pixel NaN. */
void pc_mueller_finish(const pc_mueller_system *s, uint32_t width, uint32_t height, float *M);

#ifdef __cplusplus
}
#endif
#endif
