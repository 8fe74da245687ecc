/* core/decompose_internal.h - thresholds shared by the scalar Lu–Chipman decomposition
 * (decompose.c) and its vectorised map kernel (decompose_map.c); private to core. */
#ifndef POLARCAM_CORE_DECOMPOSE_INTERNAL_H
#define POLARCAM_CORE_DECOMPOSE_INTERNAL_H

#define PC_LC_D_MAX         (1 - 1e-6) /* physics.md §4: flag D ≥ 1 − 1e-6 */
#define PC_LC_NONUNIQUE_DET 1e-6       /* |det m'| ≤ 1e-6 (λ₁/3)³: retarder not unique */

#endif
