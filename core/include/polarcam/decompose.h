/* polarcam/decompose.h - Lu–Chipman polar decomposition M = M_Δ M_R M_D (physics.md §3, §4).
 *
 * Contract used by sim/ and tools/: fields and functions may be added, not removed or changed.
 */
#ifndef POLARCAM_DECOMPOSE_H
#define POLARCAM_DECOMPOSE_H

#include <stdbool.h>

#ifdef __cplusplus
extern "C" {
#endif

enum pc_lc_flags {
	PC_LC_D_SINGULAR = 1u << 0, /* D ≥ 1 − 1e-6: R and Δ undefined (NaN), M_D not inverted */
	PC_LC_R_NONUNIQUE = 1u << 1, /* smallest singular value of m' ≈ 0: retarder not unique */
	PC_LC_NONPHYSICAL = 1u << 2, /* input failed the coherency-matrix realisability check */
	PC_LC_FILTERED = 1u << 3,    /* input was Cloude-filtered before decomposing */
	PC_LC_CLAMPED = 1u << 4,     /* D or Δ clamped into [0, 1] after filtering */
	PC_LC_ZERO_M00 = 1u << 5,    /* M00 ≤ 0: nothing to decompose */
};

enum pc_lc_options {
	PC_LC_FILTER = 1u << 0,     /* Cloude-filter non-physical input (default in the CLI) */
	PC_LC_NO_FACTORS = 1u << 1, /* skip M_D, M_R, M_Δ and physicality check (fast maps) */
};

typedef struct pc_lu_chipman {
	double m00; /* M00 of the input; the factors are of M/M00 */
	double D;   /* diattenuation, |D⃗| */
	double D_vec[3];
	double R;         /* retardance in radians, [0, π] */
	double R_axis[3]; /* unit retardance axis (a1, a2, a3): linear part a1,a2, circular a3 */
	double R_linear, R_circular; /* linear retardance and optical rotation (radians) */
	double Delta;                /* depolarization 1 − |tr m_Δ|/3 (paper eq. 18) */
	double depol_index; /* Gil–Bernabeu depolarization index of the (filtered) input */
	double M_D[4][4], M_R[4][4], M_Delta[4][4];
	bool physical;  /* input passed the realisability check */
	bool filtered;  /* Cloude filtering changed the input */
	unsigned flags; /* pc_lc_flags */
} pc_lu_chipman;

/* Decomposes M. Returns 0 (flags say what is undefined), PC_EINVAL for non-finite input.
 * Undefined quantities are NaN (R, Δ, axis, M_R, M_Δ when PC_LC_D_SINGULAR; everything but m00
 * when PC_LC_ZERO_M00; R_axis when R = 0). With PC_LC_NO_FACTORS the three factor matrices are
 * not written and `physical` is false unless PC_LC_FILTER asked for the check. Conventions and
 * tolerances: docs/physics-notes.md. */
int pc_lu_chipman_decompose(const double M[4][4], unsigned options, pc_lu_chipman *out);

#ifdef __cplusplus
}
#endif
#endif
