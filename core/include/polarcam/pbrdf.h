/* polarcam/pbrdf.h - the corrected microfacet polarized BRDF (physics.md §2).
 *
 * Contract used by sim/ and tools/: fields and functions may be added, not removed or changed.
 * Conventions (physics.md §1): k_i points from the surface towards the source, k_r towards the
 * viewer; Δφ = 180° is the forward (specular) plane; ñ = n − ik; σ is the rms slope per axis.
 * The Mueller matrix f maps the incident Stokes vector (frame s_i, p_i = d_i × s_i with
 * d_i = −k_i) to the scattered radiance Stokes vector (frame s_r, p_r = d_r × s_r, d_r = k_r),
 * in sr⁻¹.
 */
#ifndef POLARCAM_PBRDF_H
#define POLARCAM_PBRDF_H

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_diffuse {
	PC_DIFFUSE_FRESNEL = 0, /* ρ^s with the Fresnel factor (paper eq. 11 as written), default */
	PC_DIFFUSE_GEOMETRIC,   /* ρ^s with the Fresnel factor set to 1 in eq. 9 */
	PC_DIFFUSE_NONE         /* specular part only */
} pc_diffuse;

typedef enum pc_shadowing {
	PC_SHADOW_TS = 0, /* Torrance–Sparrow V-groove, Cook–Torrance closed form (default) */
	PC_SHADOW_NONE
} pc_shadowing;

typedef enum pc_rho_mode {
	PC_RHO_QUAD = 0, /* slope-space Gauss–Legendre quadrature of order rho_order per call */
	PC_RHO_TABLE     /* tabulated (cosθ_i × log σ, bicubic), built once */
} pc_rho_mode;

typedef struct pc_material {
	double n, k;  /* ñ = n − ik, n > 0, k ≥ 0 */
	double sigma; /* rms facet slope per axis, > 0 */
	pc_diffuse diffuse;
	pc_shadowing shadowing;
	pc_rho_mode rho_mode;
	int rho_order; /* quadrature order N (N×N rule) for PC_RHO_QUAD; 0 = default (16) */
} pc_material;

/* A material prepared for evaluation (ρ^s tables and Fresnel constants). Immutable after
 * creation: safe to evaluate from many threads. */
typedef struct pc_pbrdf pc_pbrdf;

/* Validates m (errors name the field: "sigma = -1: must be > 0") and prepares it. Cheap
 * enough to call once per material of a scene. */
PC_API int pc_pbrdf_new(const pc_material *m, pc_pbrdf **out);
PC_API void pc_pbrdf_free(pc_pbrdf *p);

/* f in sr⁻¹ for macro angles in radians (θ_i, θ_r in [0, π/2], Δφ any), in the macro frames of
 * physics.md §1. */
PC_API int pc_pbrdf_eval(const pc_pbrdf *p, double theta_i, double theta_r, double dphi,
                         double f[4][4]);

/* The same with the three angles in degrees, their sines and cosines exact at multiples of 90°
 * (pc_sincos_deg): the exact specular direction Δφ = 180°, θ_i = θ_r is hit exactly, which
 * matters for narrow lobes (σ = 1e-20 has a lobe 1e-20 rad wide; sin(π) in radians is 1e-16). */
PC_API int pc_pbrdf_eval_deg(const pc_pbrdf *p, double theta_i_deg, double theta_r_deg,
                             double dphi_deg, double f[4][4]);

/* The same from unit vectors in a local frame whose +z is the macro surface normal: k_i, k_r as
 * above; s_i ⟂ k_i and s_r ⟂ k_r are unit s-vectors of the caller's Stokes frames (any
 * orientation; physics.md §2 with s_Mi, s_Mr replaced by them). Returns an all-zero matrix
 * (and 0) below the horizon. */
PC_API int pc_pbrdf_eval_vec(const pc_pbrdf *p, const double k_i[3], const double k_r[3],
                             const double s_i[3], const double s_r[3], double f[4][4]);

/* ρ^s(θ_i) of this material (physics.md §2 eq. 11; §5 quadrature or table). In PC_RHO_QUAD
 * mode this is the direct N×N slope-space quadrature (slow: ~N² integrand evaluations); in
 * PC_RHO_TABLE mode the bicubic table value; for σ < PC_PBRDF_SIGMA_MIRROR the mirror limit
 * (Fresnel reflectance F(θ_i) for PC_DIFFUSE_FRESNEL, 1 for PC_DIFFUSE_GEOMETRIC). With
 * PC_SHADOW_NONE ρ^s grows like 1/cosθ_i and is +inf at θ_i = 90°. NaN for PC_DIFFUSE_NONE. */
PC_API double pc_pbrdf_rho_s(const pc_pbrdf *p, double theta_i);

/* Additions (physics area). */

/* Below this σ the material is treated as a mirror for ρ^s (physics.md §4): the slope-space
 * integrand is a delta-like lobe and ρ^s equals its σ → 0 limit to 2e-4. The pointwise BRDF is
 * still the formula (a very narrow lobe); renderers may prefer pc_pbrdf_mirror(). */
#define PC_PBRDF_SIGMA_MIRROR 0.01
/* Smallest σ pc_pbrdf_new accepts: the specular peak 1/(8πσ²)·G/(cos⁴θ_N cosθ_i cosθ_r) must
 * stay within the double range for every direction above PC_PBRDF_COS_HORIZON (derivation:
 * docs/physics-notes.md, hard cases). Smaller σ is refused (PC_ERANGE); it is a mirror
 * (pc_pbrdf_mirror). */
#define PC_PBRDF_SIGMA_MIN 1e-50
/* Directions with cosθ ≤ this count as at the horizon (all-zero matrix): without shadowing
 * K ∝ 1/(cosθ_i cosθ_r) would overflow closer to it. */
#define PC_PBRDF_COS_HORIZON 1e-60
/* Above this σ the single-scattering V-groove model loses energy: outside its validity. */
#define PC_PBRDF_SIGMA_VALID_MAX 0.5
/* σ range of the PC_RHO_TABLE grid (32 log-spaced nodes) and its cosθ_i nodes. */
#define PC_RHO_TABLE_SIGMA_MIN 0.01
#define PC_RHO_TABLE_SIGMA_MAX 1.0
#define PC_RHO_TABLE_NSIGMA    32
#define PC_RHO_TABLE_NCOS      64

enum pc_pbrdf_flags {
	PC_PBRDF_MIRROR = 1u << 0,           /* σ < PC_PBRDF_SIGMA_MIRROR: mirror model for ρ^s */
	PC_PBRDF_OUTSIDE_VALIDITY = 1u << 1, /* σ > PC_PBRDF_SIGMA_VALID_MAX: warn the user */
};

/* pc_pbrdf_flags of a prepared material. */
PC_API unsigned pc_pbrdf_flags(const pc_pbrdf *p);

/* The material as validated (rho_order resolved to the order actually used). */
PC_API const pc_material *pc_pbrdf_material(const pc_pbrdf *p);

/* ρ^s(θ_i) as pc_pbrdf_eval uses it: a per-material table in cosθ_i (PC_PBRDF_RHO_NODES nodes,
 * cubic interpolation) built at creation from the material's rule, so that evaluation costs a
 * few ns. Its difference from pc_pbrdf_rho_s() is the interpolation error, stated in
 * docs/physics-notes.md and tested. Argument: cosθ_i in [0, 1]. */
PC_API double pc_pbrdf_rho_s_fast(const pc_pbrdf *p, double cos_theta_i);
#define PC_PBRDF_RHO_NODES 257

/* ρ^s(θ_i) by the N×N slope-space rule of physics.md §5 for any order N ≥ 1 (allocates nothing
 * for N ≤ 1024; larger N returns NaN), ignoring the material's rho_mode and the mirror switch.
 * For tests and the accuracy-vs-cost benchmark. */
PC_API double pc_pbrdf_rho_s_quad(const pc_pbrdf *p, double theta_i, int order);

/* Mueller reflectance matrix (dimensionless) of the ideal mirror reflection of this material
 * (the σ → 0 limit of the specular lobe) for light arriving from k_i, leaving along
 * k_r = (−k_ix, −k_iy, k_iz), with the caller's s-vectors s_i ⟂ k_i, s_r ⟂ k_r as in
 * pc_pbrdf_eval_vec. All-zero for k_iz ≤ 0. */
PC_API int pc_pbrdf_mirror(const pc_pbrdf *p, const double k_i[3], const double s_i[3],
                           const double s_r[3], double R[4][4]);

#ifdef __cplusplus
}
#endif
#endif
