/* polarcam/decompose.h - Lu–Chipman polar decomposition M = M_Δ M_R M_D (physics.md §3, §4).
 *
 * Contract used by sim/ and tools/: fields and functions may be added, not removed or changed.
 */
#ifndef POLARCAM_DECOMPOSE_H
#define POLARCAM_DECOMPOSE_H

#include <stdbool.h>
#include <stddef.h>

#include "polarcam/export.h"

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
	PC_LC_NONFINITE = 1u << 6,   /* pc_lu_chipman_map only: an element is NaN or ±∞ (the
	                                scalar call returns PC_EINVAL); every output NaN */
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
PC_API int pc_lu_chipman_decompose(const double M[4][4], unsigned options, pc_lu_chipman *out);

/* Outputs of pc_lu_chipman_map as structure of arrays, n entries each. A NULL pointer is not
 * written, and the work only it needs is skipped (R_axis, R_linear, R_circular cost two
 * arctangents and four divisions per matrix). */
typedef struct pc_lc_map {
	double *D, *D_vec[3];
	double *R, *R_axis[3], *R_linear, *R_circular;
	double *Delta, *depol_index;
	unsigned *flags; /* pc_lc_flags */
} pc_lc_map;

/* Instruction set of the map kernel; AUTO follows pc_cpu_active() (polarcam/cpu.h: the widest
 * this CPU has, capped by the environment variable POLARCAM_CPU): AVX-512, AVX2, else PORTABLE
 * (the scalar reference matrix by matrix). */
typedef enum pc_lc_isa {
	PC_LC_ISA_AUTO = 0,
	PC_LC_ISA_PORTABLE,
	PC_LC_ISA_AVX2,
	PC_LC_ISA_AVX512,
} pc_lc_isa;

/* Decomposes n matrices M + 16·i (row-major 4×4, contiguous) into D, R, Δ maps, vectorised
 * across matrices. Entry i equals, bit for bit, the field of pc_lu_chipman_decompose(M_i,
 * options | PC_LC_NO_FACTORS) (NaN where that is NaN; flags equal); `options` may hold
 * PC_LC_FILTER and PC_LC_NO_FACTORS (implied) only. A matrix with a non-finite element gets
 * NaN everywhere and PC_LC_NONFINITE (the scalar call returns PC_EINVAL for it). Matrices the
 * realisability check rejects under PC_LC_FILTER go through the scalar path (Cloude filter).
 * Single-threaded and reentrant: callers split large maps across threads. Returns 0, or
 * PC_EINVAL for NULL pointers with n > 0 or unknown option bits. */
PC_API int pc_lu_chipman_map(const double *M, size_t n, unsigned options, const pc_lc_map *out);

/* The same with an explicit instruction set; PC_ENOTSUP when this CPU or build lacks it. */
PC_API int pc_lu_chipman_map_isa(const double *M, size_t n, unsigned options, const pc_lc_map *out,
                                 pc_lc_isa isa);

/* Name of the instruction set AUTO uses here ("avx512", "avx2", "scalar"). */
PC_API const char *pc_lu_chipman_map_isa_name(void);

#ifdef __cplusplus
}
#endif
#endif
