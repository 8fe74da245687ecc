/* core/decompose_internal.h - thresholds shared by the scalar Lu–Chipman decomposition
 * (decompose.c) and its vectorised map kernel (decompose_map.c); private to core. */
#ifndef POLARCAM_CORE_DECOMPOSE_INTERNAL_H
#define POLARCAM_CORE_DECOMPOSE_INTERNAL_H

#define PC_LC_D_MAX         (1 - 1e-6) /* physics.md §4: flag D ≥ 1 − 1e-6 */
#define PC_LC_NONUNIQUE_DET 1e-6       /* |det m'| ≤ 1e-6 (λ₁/3)³: retarder not unique */

#include "optics_inline.h"

/* Matrices with max|M_ij| outside [2^−256, 2^256] are scaled by 2^−e first
 * (pc_mat4_scale_exp, optics_inline.h). The map kernel sends such matrices to the scalar code. */
#define PC_LC_SCALE_LO PC_MAT4_SCALE_LO
#define PC_LC_SCALE_HI PC_MAT4_SCALE_HI

#endif
