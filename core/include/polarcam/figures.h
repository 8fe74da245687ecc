/* polarcam/figures.h - the seed paper's Figs. 2–11 (Zhang, Wang, He, Acta Optica Sinica 38(3)
 * 0329002, 2018) under the corrected model of docs/physics.md §8, and each of the paper's claims
 * about them checked numerically (what `polarcam figures` reports; docs/figures.md).
 *
 * Parameters (physics.md §8; the paper does not give θ_r for Figs. 3–8):
 *   Fig. 2     DoP vs θ_i, θ_r = 60°, Δφ = 180°: green paint 1.47 − 0.47i, σ 0.1; black paint
 *              1.46 − 1.28i, σ 0.2
 *   Figs. 3–5  D, R, Δ vs θ_i, Δφ = 180°, θ_r = 15°, 30°, 45°, 60° (black paint)
 *   Figs. 6–8  D, R, Δ vs Δφ, θ_i = 60°, θ_r = 15°, 30°, 45°, 60° (black paint)
 *   Figs. 9–11 D, R, Δ vs θ_i, θ_r = 30°, Δφ = 180°, σ = 0.2, 0.5, 0.7
 * Every curve also comes as printed: the paper's 4πσ² normalisation (specular part × 2, diffuse
 * (1 − 2ρ^s)/π, eqs. 3, 11, 12 as printed, the rest corrected). Angles in degrees, R in radians.
 * Pure computation; io writes the CSV, the plots and figures.md (pc_figures_write).
 */
#ifndef POLARCAM_FIGURES_H
#define POLARCAM_FIGURES_H

#include <stddef.h>

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PC_FIGURE_MAX_CURVES 4
#define PC_FIGURE_MAX_POINTS 400
#define PC_FIGURE_MAX_CLAIMS 32

typedef struct pc_figure_curve {
	char label[48];
	double y[PC_FIGURE_MAX_POINTS];  /* corrected model */
	double yp[PC_FIGURE_MAX_POINTS]; /* as printed (4πσ²) */
} pc_figure_curve;

typedef struct pc_figure {
	int num;
	const char *title, *xname, *xlabel, *yname, *ylabel;
	int nx;
	double x[PC_FIGURE_MAX_POINTS];
	int nc;
	pc_figure_curve c[PC_FIGURE_MAX_CURVES];
} pc_figure;

typedef enum pc_verdict { PC_VERDICT_NO = 0, PC_VERDICT_YES, PC_VERDICT_PARTLY } pc_verdict;

/* "does not reproduce", "reproduces", "partly" */
PC_API const char *pc_verdict_name(pc_verdict v);

typedef struct pc_figure_claim {
	int figure;
	const char *text;     /* the paper's claim */
	pc_verdict corrected; /* under the corrected model */
	pc_verdict printed;   /* under the printed normalisation */
	char evidence[1024];  /* the numbers (corrected model) */
} pc_figure_claim;

/* Computes figs[2] .. figs[11] (figs[0], figs[1] unused). */
PC_API int pc_figures_compute(pc_figure figs[12]);

/* Checks the paper's claims against computed figures: fills claims (at most max) and returns
 * how many there are (PC_FIGURE_MAX_CLAIMS is enough). */
PC_API size_t pc_figures_check(const pc_figure figs[12], pc_figure_claim *claims, size_t max);

#ifdef __cplusplus
}
#endif
#endif
