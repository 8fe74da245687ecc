/* polarcam/optics.h - Fresnel, Jones and Mueller calculus, Stokes helpers, coherency matrix.
 *
 * Conventions (docs/physics.md §1, repeated in docs/physics-notes.md):
 * - ñ = n − ik with k ≥ 0 (time dependence e^{+iωt}); Fresnel coefficients in the Born & Wolf
 *   form, so r_p = −r_s at normal incidence and a mirror is R·diag(1, 1, −1, −1).
 * - A field is E = (E_s, E_p) in a right-handed frame (s, p, d) with p = d × s.
 * - Stokes S = A (E ⊗ E*), A = [[1,0,0,1],[1,0,0,−1],[0,1,1,0],[0,i,−i,0]]:
 *   S1 = |E_s|² − |E_p|², S2 = 2 Re(E_s E_p*), S3 = 2 Im(E_s* E_p)  (SCATMECH has −S3).
 * - AoLP is measured from s towards p, in [0, π); all angles in radians.
 * Complex numbers cross this header as (re, im) pairs so that it compiles as C and C++.
 */
#ifndef POLARCAM_OPTICS_H
#define POLARCAM_OPTICS_H

#include <stdbool.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_PI 3.14159265358979323846

/* Complex Fresnel reflection coefficients r_s, r_p. */
typedef struct pc_fresnel {
	double rs_re, rs_im;
	double rp_re, rp_im;
} pc_fresnel;

/* Fresnel reflection at local incidence β from a medium of index 1 onto ñ = n − ik
 * (physics.md §2): w = sqrt(ñ² − sin²β) on the branch Re w ≥ 0, Im w ≤ 0, enforced explicitly,
 * r_s = (cosβ − w)/(cosβ + w), r_p = (ñ² cosβ − w)/(ñ² cosβ + w). cos_beta ≥ 0 and
 * sin2_beta = sin²β are passed separately so that callers can supply both without cancellation.
 * Caller guarantees n > 0, k ≥ 0, finite. */
PC_API void pc_fresnel_eval(double n, double k, double cos_beta, double sin2_beta, pc_fresnel *out);

/* The same for an angle β in [0, π/2]. */
PC_API void pc_fresnel_angle(double n, double k, double beta, pc_fresnel *out);

/* Facet Mueller parameters of J = diag(r_s, r_p) (physics.md §2): abcs = (a, b, c, s) with
 * a = (|r_s|² + |r_p|²)/2, b = (|r_s|² − |r_p|²)/2, c = Re(r_s r_p*), s = Im(r_s r_p*), so that
 * M_F = [[a, b, 0, 0], [b, a, 0, 0], [0, 0, c, s], [0, 0, −s, c]]. */
PC_API void pc_fresnel_abcs(const pc_fresnel *r, double abcs[4]);

/* Unpolarised reflectance F = (R_s + R_p)/2 = a. */
PC_API double pc_fresnel_reflectance(double n, double k, double beta);

/* General Jones → Mueller: M = A (J ⊗ J*) A⁻¹ (physics.md §2), J given as real and imaginary
 * parts. The slow general route; pc_mueller_facet() is the fast one for diag(r_s, r_p). */
PC_API void pc_jones_to_mueller(const double J_re[2][2], const double J_im[2][2], double M[4][4]);

/* R_M(θ) = [[1,0,0,0],[0,cos2θ,sin2θ,0],[0,−sin2θ,cos2θ,0],[0,0,0,1]]: the Mueller matrix of the
 * Jones frame rotation [[cosθ, sinθ], [−sinθ, cosθ]] (physics.md §2). */
PC_API void pc_mueller_rotator(double theta, double M[4][4]);

/* Mueller matrix of a linear retarder with fast axis at angle_rad (from the x (s) axis towards
 * y (p); in the image-plane frame: from the image x axis, counter-clockwise) and retardance
 * delta_rad, in the Stokes convention above (physics.md §1): a quarter-wave plate at 45° turns
 * S1 = +1 into S3 = +1. */
PC_API void pc_retarder_mueller(double angle_rad, double delta_rad, double m[4][4]);

/* Linear diattenuator along angle_rad (same convention) with diattenuation D in [0, 1]: principal
 * intensity transmittances p = (1 + D)/2 and q = (1 − D)/2 (Goldstein, Polarized Light, 2nd ed.,
 * 2003, §5.2: M = R(−θ)·M₀·R(θ), M₀ = ½[[p+q, p−q, 0, 0], [p−q, p+q, 0, 0], [0, 0, 2√(pq), 0],
 * [0, 0, 0, 2√(pq)]]). p + q = 1: unpolarized light keeps half its power, like an ideal polarizer
 * (D = 1), and D is the DoLP it gives unpolarized light. */
PC_API void pc_diattenuator_mueller(double angle_rad, double D, double m[4][4]);

/* R_M(θ_out) · M_F(a, b, c, s) · R_M(θ_in), given cos 2θ and sin 2θ of both rotations: the
 * facet Mueller matrix carried to the macro frames without a complex Kronecker product. */
PC_API void pc_mueller_facet(const double abcs[4], double c2_in, double s2_in, double c2_out,
                             double s2_out, double M[4][4]);

PC_API void pc_mueller_mul(const double A[4][4], const double B[4][4], double C[4][4]);
PC_API void pc_mueller_apply(const double M[4][4], const double S[4], double out[4]);

/* Stokes helpers. For S0 ≤ 0 the degrees are 0 and the AoLP is 0. */
PC_API double pc_stokes_dop(const double S[4]);      /* sqrt(S1² + S2² + S3²)/S0 */
PC_API double pc_stokes_dolp(const double S[4]);     /* sqrt(S1² + S2²)/S0 */
PC_API double pc_stokes_docp(const double S[4]);     /* S3/S0 (signed) */
PC_API double pc_stokes_aolp_rad(const double S[4]); /* atan2(S2, S1)/2 mapped into [0, π) */
/* Stokes vector of fully linearly polarised light of intensity I at angle aolp_rad. */
PC_API void pc_stokes_linear(double intensity, double aolp_rad, double S[4]);

/* Degree of polarization of what M sends out for unpolarised input (the seed paper's eq. 21):
 * |(M10, M20, M30)| / M00, computed on the normalised column (entries off a specular lobe can be
 * ~1e-230); NaN when M00 ≤ 0. */
PC_API double pc_mueller_dop(const double M[4][4]);

/* Coherency (covariance) matrix of a Mueller matrix: with N = A⁻¹ M A, H_{(ac),(bd)} =
 * N_{(ab),(cd)} (indices (xy) = 2x + y). For M from a Jones matrix J, H = vec(J) vec(J)^† (rank 1,
 * PSD); a Mueller matrix is physically realisable iff H is positive semi-definite (Cloude 1986). tr
 * H = 2 M00. H is returned as real and imaginary parts. */
PC_API void pc_mueller_coherency(const double M[4][4], double H_re[4][4], double H_im[4][4]);
/* The inverse map (real part of A N A⁻¹). */
PC_API void pc_coherency_to_mueller(const double H_re[4][4], const double H_im[4][4],
                                    double M[4][4]);

/* The symmetric / Hermitian eigen-solver of the project (real symmetric matrices are the case
 * H_im = 0, where the eigenvectors come out real): the eigen-decomposition of a 4×4 Hermitian
 * matrix (its Hermitian part) H = V·diag(eval)·Vᴴ by cyclic complex Jacobi rotations (Golub &
 * Van Loan, Matrix Computations, 4th ed., §8.5.2, with a phase per rotation for the complex
 * case). Eigenvalues in no particular order; eigenvector k in column k of V_re + i V_im (both may
 * be NULL). */
PC_API void pc_hermitian4_eig(const double H_re[4][4], const double H_im[4][4], double eval[4],
                              double V_re[4][4], double V_im[4][4]);
/* Its eigenvalues in ascending order. */
PC_API void pc_hermitian4_eigvals(const double H_re[4][4], const double H_im[4][4], double eval[4]);

/* Realisability: smallest eigenvalue of H divided by tr H (≥ 0 for physical matrices up to
 * rounding). Returns NaN when tr H ≤ 0. */
PC_API double pc_mueller_min_coherency_eig(const double M[4][4]);

/* Default tolerance of the realisability check: physical iff min eig / tr H ≥ −PC_PHYS_TOL. */
#define PC_PHYS_TOL 1e-9

/* The same test without eigenvalues: λ_min(H) ≥ −tol·tr H by a Cholesky (LDLᴴ) factorisation of
 * H + tol·tr H·I (about 20× cheaper than pc_mueller_min_coherency_eig). False for tr H ≤ 0. */
PC_API bool pc_mueller_is_physical(const double M[4][4], double tol);

/* Cloude filter (physics.md §4): eigenvalues of H below zero are set to zero and M is rebuilt
 * (no renormalisation, so M00 may drop slightly). *changed tells whether any eigenvalue was below
 * −PC_PHYS_TOL·tr H (matrices within rounding of physical are returned unchanged). The filtered
 * entries are at most 4·max|M_ij| (|out_ij| ≤ out_00 = tr H₊/2 ≤ ‖H‖_F ≤ ‖M‖_F, H₊ the kept part),
 * so they overflow to ±inf only for input entries above DBL_MAX/4: the filtered matrix is then
 * not a double matrix (pc_lu_chipman_decompose scales first and is not affected). */
PC_API void pc_mueller_cloude_filter(const double M[4][4], double out[4][4], bool *changed);

/* Gil–Bernabeu depolarisation index sqrt(Σ M_ij² − M00²)/(√3 M00): 1 for non-depolarising,
 * 0 for the ideal depolariser. NaN for M00 ≤ 0. */
PC_API double pc_mueller_depol_index(const double M[4][4]);

/* atan2(y, x) in (−π, π] to within a few ulp, about 3× faster than glibc's here: reduction to
 * t = min/max ∈ [0, 1], then atan(t) = atan(k/8) + atan((t − k/8)/(1 + t·k/8)) with the nearest
 * k and a degree-13 Taylor series (|argument| ≤ 1/16, truncation < 1e-18 relative). Used by the
 * Lu–Chipman fast path; tested against libm. atan2(0, 0) = 0. Non-finite input gives NaN. */
PC_API double pc_atan2(double y, double x);

/* sin and cos of an angle in degrees, exact where the value is: multiples of 90° give exactly
 * 0 and ±1 (sin(π) in radians is 1.2e-16, which moves a lobe of width σ = 1e-20 off the exact
 * specular direction Δφ = 180°). The angle is reduced exactly (fmod, then the nearest multiple
 * of 90°) before one call of sin and cos on |x| ≤ 45°. Non-finite input gives NaN. */
PC_API void pc_sincos_deg(double deg, double *s, double *c);

#ifdef __cplusplus
}
#endif
#endif
