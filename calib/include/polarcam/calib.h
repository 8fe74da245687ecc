/* polarcam/calib.h - calibration of division-of-focal-plane polarization cameras and of Mueller
 * imaging setups (docs/calibration.md: procedure, file format, measured accuracy).
 *
 * Measurement model of a raw pixel p (physics.md §6, EMVA 1288 linear model):
 *     raw_p = dark_p + g_p · (a_p · S)              (DN)
 * with dark_p the per-pixel offset (black level + DSNU + dark current), g_p the per-pixel gain
 * (PRNU, micro-lens and transmission non-uniformity, as measured with unpolarized light) and
 * a_p = (a0, a1, a2) the pixel's analysis vector for the linear Stokes vector S = (S0, S1, S2)
 * (ideal: ½(1, cos 2θ_c, sin 2θ_c)). Calibration measures dark_p (dark frames), g_p (flat
 * frames of uniform unpolarized light at ≥ 2 levels) and a_p (frames of a uniform linearly
 * polarized field at K ≥ 3 analyser angles); the pipeline then computes
 *     I_p = (raw_p − dark_p) / g_p,  demosaic,  S = W⁺ · I
 * where W is the 4×3 analysis matrix of an output pixel (the four channels' analysis vectors,
 * demosaicked like the image: exact for linear methods on smooth scenes) and W⁺ = (WᵀW)⁻¹Wᵀ
 * its pseudo-inverse (core/include/polarcam/stokes.h, pc_analyser_pinv).
 *
 * ECM: the eigenvalue calibration method (Compain, Poirier & Drévillon, Appl. Opt. 38(16)
 * 3490, 1999) recovers the generator matrix W (4 × n_psg) and the analyser matrix A
 * (4·n_psa × 4) of a Mueller imaging setup from its intensity matrices B_i = A·M_i·W of
 * reference samples: air (M_0 = I), a polarizer at two orientations and a retarder.
 *
 * Layer: depends on core (and io for the file). Every fit is in double. No printing.
 */
#ifndef POLARCAM_CALIB_H
#define POLARCAM_CALIB_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"
#include "polarcam/process.h"
#include "polarcam/stokes.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the calibration file (calib_version.npy). Readers refuse newer versions. */
#define PC_CALIB_FILE_VERSION 1
#define PC_CALIB_MAX_STATES   64

/* What a calibration applies to: frames must match it exactly (pc_calib_check). */
typedef struct pc_calib_geometry {
	uint32_t width, height;               /* frame size (the ROI) */
	uint32_t offset_x, offset_y;          /* ROI origin on the sensor */
	uint32_t sensor_width, sensor_height; /* 0 = unknown */
	unsigned bits;                        /* ADC bit depth */
	pc_mosaic mosaic;                     /* mosaic phase at pixel (0, 0) of the frames */
} pc_calib_geometry;

/* What a calibration holds. Maps are C-order float32 of the frame size; NULL = absent. */
enum pc_calib_parts {
	PC_CAL_DARK = 1u << 0,     /* dark, dark_noise */
	PC_CAL_FLAT = 1u << 1,     /* gain */
	PC_CAL_ANALYSER = 1u << 2, /* analysis, pinv_sp */
	PC_CAL_ECM = 1u << 3,      /* ecm_A, ecm_W */
};

typedef struct pc_calib {
	unsigned parts;   /* PC_CAL_* bits present */
	char camera[128]; /* camera model / source description */
	pc_calib_geometry geo;
	double black_level; /* DN: mean dark offset (or the declared black level) */
	double saturation;  /* DN: samples at or above it are not trusted */
	/* The system gain K in DN per e⁻ at the flat frames' settings (EMVA 1288's photon
	 * transfer: the slope of the frames' mean temporal variance against their mean level
	 * above dark, over the flat levels; pc_calib_flat with ≥ 2 frames a level); 0 unknown.
	 * The noise gain of the noise-aware demosaicking methods (pc_pipeline_opts.noise_gain,
	 * --noise-gain) at those settings. */
	double system_gain;
	/* The analog gain of those flats in dB (their frames' gain_db), NAN unknown. A frame
	 * whose own gain g is known (pc_frame_meta.gain_db) has the system gain
	 * system_gain·10^((g − system_gain_db)/20) (EMVA 1288: K scales with the analog gain's
	 * amplitude); pc_calib_apply uses that. */
	double system_gain_db;
	/* The analog gain of the dark frames in dB (their gain_db), NAN unknown. Above the black
	 * level the dark map is electrons times the system gain (EMVA 1288: the DSNU and the
	 * dark current), so at another known gain g it is black_level + (dark −
	 * black_level)·10^((g − dark_gain_db)/20) (pc_calib_dark_scale): pc_calib_apply and the
	 * flat, analyser and ECM steps subtract it so. */
	double dark_gain_db;
	float *dark;       /* (H, W) per-pixel offset, DN */
	float *dark_noise; /* (H, W) temporal σ of one frame, DN */
	float *gain;       /* (H, W) relative gain, mean 1 over valid pixels */
	float *analysis;   /* (H, W, 3) analysis vectors (a0, a1, a2), after dark and gain */
	float *residual;   /* (H, W) RMS residual of the analyser fit, DN (K > 3) */
	float *pinv_sp;    /* (3, 4, H/2, W/2) pseudo-inverses per 2×2 super-pixel */
	uint8_t *valid;    /* (H, W) 1 = trusted pixel, 0 = dead, hot, saturated, unfit */
	/* ECM (global over the field): generator W (4 × n_psg) and analyser A (4·n_psa × 4) in
	 * the frame order of polarcam mueller (generator fastest). */
	unsigned n_psg, n_psa;
	double ecm_W[4][PC_CALIB_MAX_STATES];
	double ecm_A[4 * PC_CALIB_MAX_STATES][4];
	char *provenance; /* JSON object text (malloc'd): inputs, options, residuals */
	/* cache of the per-pixel pseudo-inverses for one demosaicking method (pc_calib_pinv) */
	float *pinv_px;
	int pinv_method;
	/* 1/gain, computed once (pc_calib_prepare or the first pc_calib_apply) */
	float *apply_ig;
	/* the analysis vectors in 16 bits for the fused bilinear pipeline (apply_vec.q =
	 * apply_q; pc_calib_prepare or the first bilinear pc_calib_apply) */
	int16_t *apply_q;
	/* the distrusted samples (valid = 0) listed for it (apply_vec.distrust_row, _x) */
	uint32_t *apply_dis;
	pc_compact_calib apply_vec;
} pc_calib;

PC_API void pc_calib_init(pc_calib *cal);
PC_API void pc_calib_free(pc_calib *cal);
/* Deep copy (maps, provenance; not the cache). */
PC_API int pc_calib_copy(pc_calib *dst, const pc_calib *src);

/* One recording of one stimulus: n frames of the geometry, read on demand. */
typedef int (*pc_calib_frame_fn)(void *user, size_t i, pc_view *out);
typedef struct pc_calib_stack {
	const char *name; /* for messages (the recording's path) */
	pc_calib_geometry geo;
	size_t n;              /* frames */
	pc_calib_frame_fn get; /* frame i into an owned view (freed by the library) */
	void *user;
	double exposure_us; /* flat levels: the exposure (or any level measure), NAN unknown */
	double gain_db;   /* the frames' analog gain (dB), NAN unknown: the flat levels share it */
	double angle_deg; /* analyser stimulus: polarizer angle (AoLP), NAN unknown */
	double dolp;      /* analyser stimulus: its DoLP (1 for a good polarizer) */
} pc_calib_stack;

/* Progress: called with work done out of total from the calling thread (may be NULL). */
typedef void (*pc_calib_progress_fn)(void *user, uint64_t done, uint64_t total);

typedef struct pc_calib_opts {
	double saturation;         /* DN; 0 = 2^bits − 1 */
	double max_saturated_frac; /* refuse a stimulus with more saturated pixels than this
	                              (default 1e-4 when 0); fewer are marked invalid */
	bool unknown_angles;       /* analyser: self-calibration, the angles are estimated */
	unsigned iterations;       /* unknown angles: alternating iterations (0 = 50) */
	pc_calib_progress_fn progress;
	void *progress_user;
} pc_calib_opts;

/* Dark: N ≥ 2 dark frames → per-pixel offset (mean) and temporal noise (σ). Pixels whose
 * offset is more than 8 robust σ above the median (hot) are invalid. out is (re)initialised
 * and holds only the dark part. */
PC_API int pc_calib_dark(const pc_calib_stack *s, const pc_calib_opts *o, pc_calib *out);

/* Flat: n_levels ≥ 2 stacks of uniform unpolarized light at different levels → per-pixel
 * gain: the slope of the pixel's mean against the level's mean over the pixels of its analyser
 * channel (least squares through the levels, so any residual offset cancels), normalised to mean
 * 1 over valid pixels. base (may be NULL) supplies the dark; out gets base's parts + the gain.
 * With ≥ 2 frames in every level also system_gain: the least-squares slope of the level's mean
 * per-pixel temporal variance (sample variance over its frames) against its mean level above
 * dark, over the trusted pixels (EMVA Standard 1288, the photon-transfer method; the intercept
 * takes the dark noise), 0 when that slope is not positive; system_gain_db is the levels' gain_db.
 * Levels at different known gains are refused (PC_EINVAL: the photon transfer varies the
 * exposure at one gain). */
PC_API int pc_calib_flat(const pc_calib_stack *levels, size_t n_levels, const pc_calib *base,
                         const pc_calib_opts *o, pc_calib *out);

/* Analyser: K stimuli of a uniform linearly polarized field, stimulus k with Stokes
 * s_k = s0·(1, P_k cos 2θ_k, P_k sin 2θ_k) of equal intensity s0 (a polarizer turned in front
 * of a stable unpolarized source). Known angles (K ≥ 3, spanning cos 2θ and sin 2θ): per pixel
 * the linear least squares a_p = argmin Σ_k (I_pk − s_k·a_p)², I_pk the pixel's dark- and
 * gain-corrected mean. Unknown angles (K ≥ 4): alternating least squares between a_p and the
 * θ_k, the free rotation fixed by a zero mean orientation error over the sensor (docs/
 * calibration.md). Scale: s0 makes the mean a0 over valid pixels ½ (so S0 keeps the units of
 * the uncalibrated (I0 + I45 + I90 + I135)/2). Errors: K too small, angles not spanning
 * (PC_ENUMERIC, "singular fit"), saturated stimuli, size mismatches. angles_out (may be NULL)
 * receives the K angles used (estimated ones in unknown-angles mode). */
PC_API int pc_calib_analyser(const pc_calib_stack *stim, size_t K, const pc_calib *base,
                             const pc_calib_opts *o, pc_calib *out, double *angles_out);

/* ---- ECM (Compain, Poirier & Drévillon 1999) ---- */

/* Reference samples in the order air, polarizer at 0° (defines the angle origin), polarizer
 * near 90°, retarder. B[i] is the (4·n_psa) × n_psg intensity matrix of sample i, row
 * 4a + c, column g (B[i][(4a + c)·n_psg + g]). */
typedef struct pc_ecm_result {
	double W[4][PC_CALIB_MAX_STATES];        /* generator, scaled so that mean W[0][g] = 1 */
	double A[4 * PC_CALIB_MAX_STATES][4];    /* analyser */
	double tau[4], psi_deg[4], delta_deg[4]; /* samples' parameters from the eigenvalues */
	double theta_deg[4];       /* samples' orientations (0 for the first polarizer) */
	double lambda16, lambda15; /* smallest eigenvalues of K (their ratio: quality) */
	double residual;           /* ‖A M_i W − B_i‖_F / ‖B_i‖_F, worst over samples */
} pc_ecm_result;

/* Solves ECM. n_psg must be 4, n_psa ≥ 1. theta_guess_deg (may be NULL) are the nominal
 * orientations of samples 2 and 3 (default 90° and 30°); they are refined by minimising the
 * smallest eigenvalue of K within ±20°. PC_ENUMERIC when B_air is singular or K's null space
 * is not one-dimensional. */
PC_API int pc_ecm_solve(const double *const B[4], unsigned n_psg, unsigned n_psa,
                        const double theta_guess_deg[2], pc_ecm_result *r);

/* Mueller matrix of a linear diattenuating retarder with transmission axis at θ: principal
 * intensity transmittances p = 2τcos²ψ and q = 2τsin²ψ and retardance δ (the ECM sample model,
 * Compain et al. 1999 eq. 9, rotated: M = R(−θ)·M₀·R(θ)). */
PC_API void pc_ecm_sample_mueller(double tau, double psi_rad, double delta_rad, double theta_rad,
                                  double M[4][4]);

/* ECM from recordings: each sample's stack holds n_psg·n_psa frames (or whole multiples:
 * cycles are averaged); the intensity matrix is the mean over the valid pixels of each
 * analyser channel, after base's dark (or black level). The result goes into out (base's
 * parts + PC_CAL_ECM). */
PC_API int pc_calib_ecm(const pc_calib_stack samples[4], unsigned n_psg, unsigned n_psa,
                        const double theta_guess_deg[2], const pc_calib *base,
                        const pc_calib_opts *o, pc_calib *out, pc_ecm_result *res);

/* ---- applying a calibration ---- */

/* 0 when frames of geometry g can be processed with cal; otherwise PC_EINVAL naming the
 * mismatch ("frame 640x480 at ROI (0,0), calibration 612x512 at (0,0): size differs"). */
PC_API int pc_calib_check(const pc_calib *cal, const pc_calib_geometry *g);

/* The corrected raw: out[p] = (raw_p − dark_p)/g_p (or raw − black_level without a dark; the
 * dark map as it is, at its own gain dark_gain_db: a raw view carries no gain),
 * float (H, W) with row stride width; valid_out (may be NULL) gets 0 where the pixel is invalid
 * in the calibration or the sample is at or above the saturation level. Returns the number of
 * invalid pixels through n_invalid (may be NULL). */
PC_API int pc_calib_correct(const pc_calib *cal, const pc_view *raw, float *out, uint8_t *valid_out,
                            size_t *n_invalid);

/* Per-output-pixel pseudo-inverses for a demosaicking method into cal's cache: superpixel
 * methods use pinv_sp; the others demosaic the analysis-vector maps with the method. *pinv
 * points into the cache (valid until cal changes or is freed). */
PC_API int pc_calib_pinv(pc_calib *cal, pc_demosaic_method method, int threads,
                         pc_analyser_pinv *pinv);

/* The calibrated pipeline: check, correct, demosaic, Stokes with the calibrated analysers
 * (pc_calib_apply with the calibration's saturation level). out as pc_stokes_from_raw (size
 * pc_demosaic_out_size); valid_out (may be NULL, size of the output) is 1 where every sample
 * the pixel depends on is trusted. */
PC_API int pc_calib_stokes(pc_calib *cal, const pc_view *raw, const pc_calib_geometry *g,
                           pc_demosaic_method method, int threads, const pc_stokes_out *out,
                           uint8_t *valid_out, size_t *n_invalid);

/* The calibration as a pipeline stage, what `polarcam process/demosaic/capture --process/view
 * --calibration F` run: checks that frame f matches the calibration (size, ROI origin
 * f->meta.offset_x/y, mosaic, bit depth when both are known; a colour-polarization frame is
 * refused), corrects every sample I = (raw − dark)·(1/gain) (the calibration's black level
 * without a dark map; the dark map's part above the black level scaled to the frame's analog
 * gain when it and cal->dark_gain_db are known: pc_calib_dark_scale), then through the core's front
 * door demosaics (ch, when st is NULL) or computes Stokes with the calibrated analysers
 * (pc_calib_pinv; the fused fast paths). A sample is flagged when the calibration distrusts its
 * pixel (valid map), when it is at or above o->saturation_level (> 0; cal->saturation is the
 * calibration's own) or at or below o->dead_level (> 0); valid (may be NULL) gets the output pixels
 * whose method support holds a flagged sample (pc_validity_run), the same rule as the uncalibrated
 * pipeline. o->black_level must be 0 (the dark map is the black level), o->pinv, o->dark and
 * o->gain_inv NULL. The noise-aware methods' noise gain is o->noise_gain when given, else
 * cal->system_gain when known, scaled to the frame's analog gain when both gains are known
 * (f->meta.gain_db and cal->system_gain_db: pc_calib_noise_gain), else estimated from the frame.
 * The correction is fused into the core's pipeline (pc_pipeline_opts.dark, gain_inv): the fused
 * bilinear Stokes pass reads the raw once; a dark map at the frame's gain is scaled there too
 * (pc_pipeline_opts.dark_scale; the compact calibration of bilinear: its base and scale).
 * Per-call memory only; the once-per-calibration
 * parts are made on the first call (pc_calib_prepare), after which calls only read cal (they
 * include, for bilinear, the valid map as a list of the distrusted samples: a map changed after
 * that needs pc_calib_unprepare, then the next call prepares anew). */
PC_API int pc_calib_apply(pc_calib *cal, const pc_frame *f, unsigned bits,
                          const pc_pipeline_opts *o, const pc_stokes_out *st, const pc_fplane *ch,
                          pc_validity *valid);

/* pc_calib_stokes for noise-aware methods: noise_gain > 0 is given to them (0: the calibration's
 * system gain at the frame's analog gain gain_db, NAN unknown: pc_calib_noise_gain; else
 * estimated from the frame); noise_gain_used (may be NULL) receives the one used
 * (pc_pipeline_opts.noise_gain_used). pc_calib_stokes is this with 0 and NAN. */
PC_API int pc_calib_stokes_gain(pc_calib *cal, const pc_view *raw, const pc_calib_geometry *g,
                                pc_demosaic_method method, int threads, double noise_gain,
                                double gain_db, const pc_stokes_out *out, uint8_t *valid_out,
                                size_t *n_invalid, double *noise_gain_used);

/* Computes what pc_calib_apply needs once per calibration and demosaicking method (the inverse
 * gains; for bilinear the 16-bit analysis vectors of pc_calib_apply, for the other methods the
 * per-pixel pseudo-inverses of pc_calib_pinv), so that later calls only read cal.
 * pc_calib_prepared: whether that is done (then pc_calib_apply, pc_calib_stokes with this
 * method only read cal and may run concurrently). */
PC_API int pc_calib_prepare(pc_calib *cal, pc_demosaic_method method, int threads);
PC_API bool pc_calib_prepared(const pc_calib *cal, pc_demosaic_method method);
/* Drops what pc_calib_prepare (or a first pc_calib_apply) made: needed after a change to
 * cal's maps (valid, analysis, dark, gain), so that the next call prepares from the new ones. */
PC_API void pc_calib_unprepare(pc_calib *cal);

/* The noise gain pc_calib_apply gives the noise-aware methods for a frame at analog gain
 * gain_db (NAN unknown) when none is given: cal->system_gain·10^((gain_db −
 * cal->system_gain_db)/20) when both gains are known and finite, else cal->system_gain (0:
 * unknown). *scaled (may be NULL) says whether it was scaled. */
PC_API double pc_calib_noise_gain(const pc_calib *cal, double gain_db, bool *scaled);

/* The factor by which pc_calib_apply multiplies the dark map's part above the black level for
 * a frame at analog gain gain_db (NAN unknown): 10^((gain_db − cal->dark_gain_db)/20) when cal
 * has a dark map and both gains are known and finite, else 1. *scaled (may be NULL) says
 * whether both were known (the factor is then 1 at equal gains). The black level is the dark
 * map's mean (pc_calib.black_level), so the dark current's mean is not scaled: with the
 * exposures of a polarization camera it is a small part of a DN (docs/calibration.md). */
PC_API double pc_calib_dark_scale(const pc_calib *cal, double gain_db, bool *scaled);

/* pc_calib_apply as a pc_raw_stage (polarcam/process.h) for pc_process_file, pc_demosaic_file
 * and the live Stokes stream; name is reported in meta.json (e.g. the file's path); the stage's
 * default saturation level and noise gain are the calibration's. */
PC_API pc_raw_stage pc_calib_stage(pc_calib *cal, const char *name);

/* ---- the file (docs/calibration.md) ---- */

/* Writes cal as a NumPy .npz (a zip of .npy arrays) atomically. */
PC_API int pc_calib_write(const char *path, const pc_calib *cal);
/* Reads and validates a calibration file (every array's dtype and shape, the version, the
 * metadata); errors name the file and the member. */
PC_API int pc_calib_read(const char *path, pc_calib *cal);

#ifdef __cplusplus
}
#endif
#endif
