/* polarcam/folders.h - the output folders of the pipelines: what `polarcam process`, `capture
 * --process`, `mueller` and `demo` write, laid out in one place. Every file is written
 * atomically; the folder is created when missing.
 *
 * A Stokes folder (pc_stokes_folder_write) holds, as asked (frame N of a series: the same names
 * with _NNNNNN before the extension, NNNNNN the frame number in six or more digits):
 *   stokes.npy     float32 (H, W, 3): S0, S1, S2
 *   s0.npy         float32 (H, W): S0
 *   dolp.npy       float32 (H, W): DoLP in [0, 1]
 *   aolp.npy       float32 (H, W): AoLP in radians, [0, π) (polarcam/stokes.h's convention)
 *   valid.npy      uint8 (H, W): 1 valid, 0 where the value depends on a saturated, dead or
 *                  distrusted sample (pc_stokes_folder_write_valid with a mask)
 *   imin.npy, imax.npy          float32 (H, W): Imin, Imax (pc_stokes_minmax, polarcam/stokes.h)
 *   diffuse.npy, specular.npy   float32 (H, W): 2·Imin, Imax − Imin
 *   s0.png, dolp.png, aolp.png, aolp_sat.png   the pictures of pc_pictures_write_opts (invalid
 *                  pixels marked, pc_pictures_write_valid), and imin.png, imax.png, diffuse.png,
 *                  specular.png for the planes asked for (pc_pictures_write_minmax)
 *
 * A Mueller folder (pc_mueller_folder_write) holds:
 *   mueller.npy    float32 (H, W, 4, 4) (unless left out)
 *   D, R, Delta    .npy (H, W) float32 and .png (grey, with a colour bar; NaN magenta; R.png
 *                  hatched where Δ > PC_MUELLER_R_MASK_DELTA)
 *   rebuild_residual.npy/.png   when the circular entries were rebuilt
 *   valid.npy      uint8 (H, W) when levels were checked: 0 where a frame's sample was
 *                  saturated or dead (marked in the D, R, Delta pictures)
 *   mueller.json   condition numbers, noise gains, pixel counts (see pc_mueller_folder_write)
 *
 * The figures folder (pc_figures_write) holds figNN.csv (x and one column per curve, then the
 * same curves under the printed normalisation), figNN.png and figures.md (each claim, whether it
 * reproduces, with the numbers).
 */
#ifndef POLARCAM_FOLDERS_H
#define POLARCAM_FOLDERS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/figures.h"
#include "polarcam/io.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/progress.h"
#include "polarcam/stokes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- one map: NAME.npy and NAME.png ---- */

/* Writes a float (H, W) map as DIR/NAME.npy and a grey picture DIR/NAME.png, linear from lo to
 * hi, titled title, with a colour bar labelled label; non-finite values are drawn magenta and
 * their share noted under the bar. */
PC_API int pc_map_write(const char *dir, const char *name, const float *map, uint32_t width,
                        uint32_t height, double lo, double hi, const char *title,
                        const char *label);

/* Marks drawn over a map's picture (pc_map_write_marked); zeroed: none. */
typedef struct pc_map_marks {
	const uint8_t *valid;   /* (H, W) 1 valid; 0s are painted with the invalid checker */
	const float *hatch_map; /* (H, W): where hatch_map > hatch_above the picture shows */
	double hatch_above;     /* the dark grey hatch of pc_picture_mask_low (NaN: magenta) */
	const char *hatch_text; /* the hatch's legend text, e.g. "Delta > 0.5: R undefined" */
} pc_map_marks;

/* pc_map_write with marks (NULL: none): the .npy is never masked, the picture is. */
PC_API int pc_map_write_marked(const char *dir, const char *name, const float *map, uint32_t width,
                               uint32_t height, double lo, double hi, const char *title,
                               const char *label, const pc_map_marks *marks);

/* Retardance is undefined where the light is depolarized: the polar decomposition reads the
 * retarder from m' = m_Δ·m_R (docs/physics.md §3), whose singular values are the depolarizer's
 * (1 − Δ on average, eq. 18), so noise in m' reaches R divided by about 1 − Δ, and at Δ = 1
 * nothing of m_R is left. R pictures (Mueller folders, the demo) hatch the pixels with Δ above
 * this, where R's noise gain passes twice a non-depolarizing pixel's; the demo compares R with
 * its truth below the same bound. */
#define PC_MUELLER_R_MASK_DELTA 0.5

/* ---- Stokes folders ---- */

enum pc_stokes_folder_files {
	PC_SF_STOKES = 1u << 0,   /* stokes.npy (H, W, 3) */
	PC_SF_S0 = 1u << 1,       /* s0.npy */
	PC_SF_DOLP = 1u << 2,     /* dolp.npy */
	PC_SF_AOLP = 1u << 3,     /* aolp.npy */
	PC_SF_PICTURES = 1u << 4, /* s0.png, dolp.png, aolp.png, aolp_sat.png */
	PC_SF_MINMAX = 1u << 5,   /* imin.npy, imax.npy (and imin.png, imax.png with pictures) */
	PC_SF_SPLIT = 1u << 6,    /* diffuse.npy, specular.npy (and their .png with pictures) */
};

typedef struct pc_stokes_folder_opts {
	unsigned files;            /* PC_SF_* */
	pc_pictures_opts pictures; /* title prefix, display width, low-signal mask */
	bool numbered; /* names carry a frame number: stokes_NNNNNN.npy, s0_NNNNNN.png */
	uint64_t number;
	bool no_valid_file;   /* the mask goes elsewhere (a batch's stacked valid.npy): the pictures
	                       * still mark it, valid.npy is not written here */
	bool no_minmax_files; /* the same for imin/imax/diffuse/specular.npy (PC_SF_MINMAX,
	                       * PC_SF_SPLIT): only their pictures are written here */
	const pc_stokes_out *colour; /* a colour-polarization frame's R, G, B Stokes images (three,
	                              * pc_stokes_run_colour) or NULL: with PC_SF_STOKES
	                              * stokes_rgb.npy (H, W, 3, 3): [y, x, colour, S0..S2]; with
	                              * PC_SF_PICTURES s0_rgb.png and dolp_rgb.png
	                              * (pc_pictures_write_colour) */
} pc_stokes_folder_opts;

/* Writes the files asked for from st (planes as pc_stokes_out; stokes.npy needs s0, s1, s2,
 * the others their plane) into dir (created when missing), in the order of the table above. */
PC_API int pc_stokes_folder_write(const char *dir, const pc_stokes_out *st, uint32_t width,
                                  uint32_t height, const pc_stokes_folder_opts *opts);

/* The same with a validity mask (valid may be NULL, or its mask NULL: none): valid.npy is
 * written after the .npy files and the pictures mark the invalid pixels. */
PC_API int pc_stokes_folder_write_valid(const char *dir, const pc_stokes_out *st, uint32_t width,
                                        uint32_t height, const pc_stokes_folder_opts *opts,
                                        const pc_validity *valid);

/* ---- circular polarization (Stokes with S3) ---- */

/* From S0..S3 planes s[0..3] (a truth with the "circular" effect: docs/outputs.md): docp.npy,
 * float32 (H, W) DoCP = |S3|/S0 in [0, 1] (polanalyser's cvtStokesToDoCP; 0 where S0 <= 0),
 * and ellipticity.npy, float32 (H, W) the ellipticity angle χ = ½·atan2(S3, √(S1² + S2²)) in
 * radians in [−π/4, π/4], positive for S3 > 0 (physics.md §1's sign; 0 where S0 <= 0), NaN
 * where an input is not finite, into dir (created when missing); with pictures non-NULL
 * docp.png and ellipticity.png (pc_pictures_write_circular). */
PC_API int pc_circular_folder_write(const char *dir, const pc_fplane s[4], uint32_t width,
                                    uint32_t height, const pc_pictures_opts *pictures);

/* ---- Mueller folders ---- */

typedef struct pc_mueller_folder_opts {
	bool no_mueller;    /* leave mueller.npy out (64 bytes per pixel) */
	const char *method; /* demosaicking method name, for mueller.json */
	double black_level; /* for mueller.json */
	double rebuild_tol; /* for mueller.json and the residual picture's scale (0 .. 2·tol) */
	pc_rebuild_sign rebuild_sign;
	bool overwrite; /* replace an existing folder (polarcam/io.h's rule) */
} pc_mueller_folder_opts;

/* Writes res into dir, an output folder written as a set (polarcam/io.h, pc_outdir: refused
 * when it exists unless opts->overwrite, put in place only when complete; valid.npy with the
 * rest). mueller.json holds frames, width, height, method, black_level, cond_A, cond_G, cond_W,
 * rank_A, rank_G, noise_gain, pixels_D_singular, pixels_nonphysical_filtered,
 * pixels_undecomposable, determined, saturation_level, pixels_invalid, rebuild_circular (and
 * when rebuilt: rebuild_tol, pixels_rebuild_rejected, pixels_rebuild_sign_undefined). json (may
 * be NULL) receives its content as one compact line (malloc'd). */
PC_API int pc_mueller_folder_write(const char *dir, const pc_mueller_result *res,
                                   const pc_mueller_folder_opts *opts, char **json);

/* ---- the seed paper's figures (polarcam/figures.h) ---- */

/* Writes figs[2..11] and the claims into dir, an output folder written as a set (polarcam/io.h,
 * pc_outdir; flags: PC_OUT_OVERWRITE); progress (may be NULL): phase "figures". */
PC_API int pc_figures_write(const char *dir, unsigned flags, const pc_figure figs[12],
                            const pc_figure_claim *claims, size_t n_claims,
                            const pc_progress *progress);

#ifdef __cplusplus
}
#endif
#endif
