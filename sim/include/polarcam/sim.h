/* polarcam/sim.h - the scene simulator: scenes → per-pixel Stokes/Mueller ground truth →
 * sensor model (polarizer mosaic, analyser non-idealities, EMVA 1288 noise) → raw frames.
 *
 * Contract used by devices/ (the `sim:` source, `serve`) and tools/: functions and fields may be
 * added, not removed or changed.
 *
 * Typical use:
 *
 *     pc_scene *scene;  pc_sim *sim;  pc_sim_info info;
 *     pc_scene_load("scenes/spheres.json", &scene);   // or pc_scene_load_default(&scene)
 *     pc_sim_options opt = pc_sim_options_default();  opt.seed = 42;
 *     pc_sim_new(scene, &opt, &sim);                   // the sim keeps its own copy of the scene
 *     pc_sim_get_info(sim, &info);                     // size, pixel format, mosaic, states
 *     pc_view v;  pc_view_alloc(&v, info.format, info.width, info.height, 64);
 *     pc_frame_meta meta;
 *     pc_sim_frame(sim, 0, NULL, &v, &meta);           // raw frame 0, any frame N on demand
 *
 * Determinism: raw frame N is a pure function of (scene, options, controls, N). Its noise comes
 * from a counter-based generator (Philox4x32-10) keyed by (seed, N, pixel position on the full
 * sensor), so any frame, any row band and any ROI is reproducible in any thread order; fixed
 * pattern noise (PRNU, DSNU, per-pixel analyser errors) is keyed by (seed, pixel) alone.
 *
 * Frame sequences: when a scene declares polarization-state sequences (a PSG on a light and/or a
 * PSA retarder in front of the camera, for Mueller imaging), frame N is taken under PSG state
 * N mod n_psg and PSA state (N / n_psg) mod n_psa; info.n_states = n_psg·n_psa.
 *
 * Image-plane Stokes frame (physics.md §1): S1 > 0 means polarized along the image x axis
 * (columns, increasing to the right), S2 > 0 along the diagonal between +x and image "up"
 * (decreasing row index); AoLP is measured from the image x axis counter-clockwise as seen by
 * someone looking at the image, in [0, π). For an off-axis pixel the reference axis is the
 * camera's x axis projected perpendicular to the pixel's ray.
 */
#ifndef POLARCAM_SIM_H
#define POLARCAM_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/eval.h"
#include "polarcam/frame.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Scenes (docs/scene-format.md). A scene is immutable once loaded.
 */
typedef struct pc_scene pc_scene;

/* Loads and validates a scene file. OBJ meshes are resolved relative to the file's directory.
 * Errors name the file and the line (JSON syntax) or the field path and what was expected:
 * "scenes/x.json: objects[2].material.sigma = -1: must be > 0". */
PC_API int pc_scene_load(const char *path, pc_scene **out);

/* The same from text; name is used in messages, base_dir resolves OBJ paths (NULL = "."). */
PC_API int pc_scene_parse(const char *text, const char *name, const char *base_dir, pc_scene **out);

/* The built-in default scene: the seed paper's black paint (ñ = 1.46 − 1.28i, σ = 0.2) and
 * green paint (1.47 − 0.47i, σ = 0.1) on spheres and a ground plane under a directional light,
 * IMX250MZR-class sensor, 2448×2048. */
PC_API int pc_scene_load_default(pc_scene **out);
/* Its JSON text (static storage). */
PC_API const char *pc_scene_default_text(void);

PC_API void pc_scene_free(pc_scene *scene);

/* The scene's name, and the scene document as parsed (compact JSON, malloc'd; the caller frees
 * it), for meta.json. The resolved sensor figures are in pc_sim_get_sensor(). */
PC_API const char *pc_scene_name(const pc_scene *scene);
PC_API char *pc_scene_to_json(const pc_scene *scene);

/* ---------------------------------------------------------------------------------------------
 * Effects. Every effect is opt-in (declared by the scene; sensor presets declare theirs) and the
 * render and sensor pipelines are assembled from the set once, in pc_sim_new: work for an effect
 * not asked for is never done.
 */
enum pc_sim_effect {
	PC_FX_DIFFUSE = 1u << 0,       /* the pBRDF diffuse term (physics.md §2 eqs. 8–12) */
	PC_FX_SHADOWING = 1u << 1,     /* Torrance–Sparrow shadowing/masking G */
	PC_FX_CAST_SHADOWS = 1u << 2,  /* occlusion of lights by objects (shadow rays) */
	PC_FX_SUPERSAMPLING = 1u << 3, /* n×n samples over each pixel's footprint */
	PC_FX_CIRCULAR = 1u << 4,      /* carry S3 (circular polarization) */
	PC_FX_MUELLER = 1u << 5,       /* per-pixel 4×4 Mueller ground truth */
	PC_FX_NOISE = 1u << 6,         /* photon shot noise, dark current, read noise */
	PC_FX_PRNU_DSNU = 1u << 7,     /* fixed-pattern gain (PRNU) and offset (DSNU) */
	PC_FX_EXTINCTION = 1u << 8,    /* finite analyser extinction ratio */
	PC_FX_ORIENTATION = 1u << 9,   /* analyser orientation errors */
	PC_FX_TRANSMISSION = 1u << 10, /* analyser transmission mismatch */
	PC_FX_CROSSTALK = 1u << 11,    /* optical/electrical crosstalk from the 4 neighbours */
	PC_FX_BLUR = 1u << 12,         /* the lens's point-spread function: a Gaussian of σ px */
	PC_FX_COUNT_ = 13
};

/* The PSF σ (pixels) a scene's "blur" may declare: below the minimum a sampled Gaussian no
 * longer stands for a continuous one; the kernel reaches ⌈4σ⌉ pixels. */
#define PC_BLUR_SIGMA_MIN 0.5
#define PC_BLUR_SIGMA_MAX 8.0

/* "diffuse", "shadowing", "cast_shadows", ... (the names of the scene file); NULL if unknown. */
PC_API const char *pc_sim_effect_name(unsigned effect_bit);
/* The bit for a name, 0 if unknown. */
PC_API unsigned pc_sim_effect_from_name(const char *name);
/* The effect set a scene declares (PC_FX_* bits). */
PC_API unsigned pc_scene_effects(const pc_scene *scene);

/* ---------------------------------------------------------------------------------------------
 * The simulator.
 */
typedef struct pc_sim pc_sim;

/* Optional BRDF override (tests, user models). eval returns the Mueller BRDF in sr⁻¹ with the
 * exact contract of pc_pbrdf_eval_vec (core/include/polarcam/pbrdf.h): unit vectors in a local
 * frame whose +z is the surface normal; k_i towards the source, k_r towards the viewer; s_i, s_r
 * the s-vectors of the incident and outgoing Stokes frames (p = d × s, d the propagation
 * direction). material_index is the scene's material number, channel the colour channel (0 for
 * monochrome sensors; 0/1/2 = R/G/B). */
typedef struct pc_sim_brdf {
	int (*eval)(void *user, unsigned material_index, unsigned channel, const double k_i[3],
	            const double k_r[3], const double s_i[3], const double s_r[3], double f[4][4]);
	void *user;
} pc_sim_brdf;

typedef struct pc_sim_options {
	uint64_t seed; /* noise seed (frames and fixed pattern) */
	int threads;   /* 0 = pc_parallel default */
	/* Region of interest on the full sensor (all zero = full sensor). The mosaic phase and the
	 * noise follow the absolute sensor position, so a ROI frame equals the same crop of a
	 * full frame bit for bit. */
	uint32_t roi_x, roi_y, roi_width, roi_height;
	/* Output pixel format; PC_FMT_INVALID = the sensor's natural format (Mono8, Mono10, Mono12
	 * or Mono16 for 8/10/12/16 bits). Any integer format with at least the sensor's bits is
	 * accepted (values stay LSB-aligned), including packed Mono10p/12p, Mono12Packed,
	 * Y10P/Y12P. */
	pc_pixfmt format;
	const pc_sim_brdf *brdf; /* NULL = the physics core's pBRDF (pc_pbrdf_eval_vec) */
} pc_sim_options;

PC_API pc_sim_options pc_sim_options_default(void);

/* Builds the simulator: validates the options against the scene, prepares materials (pBRDF
 * tables), lights, geometry (mesh BVHs), the sensor's fixed patterns and the pipelines. Does
 * not render yet (see pc_sim_prepare). The sim keeps what it needs of the scene; the scene
 * may be freed afterwards. */
PC_API int pc_sim_new(const pc_scene *scene, const pc_sim_options *opt, pc_sim **out);
PC_API void pc_sim_free(pc_sim *sim);

typedef struct pc_sim_info {
	uint32_t width, height;               /* output frame size (the ROI) */
	uint32_t sensor_width, sensor_height; /* the full sensor */
	uint32_t offset_x, offset_y;          /* ROI origin */
	pc_pixfmt format;                     /* output format */
	unsigned bits;                        /* sensor ADC bit depth: 8, 10, 12 or 16 */
	pc_mosaic mosaic;                     /* of the output frame (shifted for the ROI) */
	unsigned colour_channels;             /* 1 (IMX250MZR-like) or 3 (IMX250MYR-like, RGB) */
	double exposure_us, gain_db;          /* the scene's defaults */
	double frame_rate_hz;                 /* the scene's nominal frame rate (timestamps) */
	unsigned n_psg, n_psa, n_states;      /* polarization-state sequence lengths (1 = static) */
	unsigned effects;                     /* PC_FX_* bits in force */
	uint64_t seed;
} pc_sim_info;

PC_API void pc_sim_get_info(const pc_sim *sim, pc_sim_info *info);

/* Bytes a render with this simulator holds at its peak (an estimate, within ~10 %): the
 * per-state electron-rate caches (4 bytes per pixel and state), the DSNU image, the crosstalk
 * halos while a state is prepared, per-thread row buffers, one frame, and with truth the
 * ground-truth buffers a render writes (4 floats per pixel and colour channel, 16 more with the
 * "mueller" effect). pc_sim_new allocates none of this; it is all allocated on demand. */
PC_API uint64_t pc_sim_memory_bytes(const pc_sim *sim, bool truth);

/* The memory a render may use: POLARCAM_MAX_MEMORY (polarcam/limits.h) when set, else the least
 * of MemAvailable (/proc/meminfo), the cgroup's memory.max − memory.current and RLIMIT_AS /
 * RLIMIT_DATA; UINT64_MAX when none of these can be read. *source (may be NULL) names where the
 * figure came from. */
PC_API uint64_t pc_sim_memory_available(const char **source);

/* 0 when pc_sim_memory_bytes(sim, truth) fits pc_sim_memory_available(); otherwise PC_ENOMEM
 * with a detail giving both figures, their source, the resolution and the number of states, and
 * what to change (--roi, sensor.resolution, POLARCAM_MAX_MEMORY). Call before rendering. */
PC_API int pc_sim_check_memory(const pc_sim *sim, bool truth);

/* Per-frame controls (what a camera lets a user change while streaming). Changing them needs no
 * re-rendering: the rendered signal is cached per second of exposure. */
typedef struct pc_sim_controls {
	double exposure_us; /* > 0 */
	double gain_db;     /* analog gain, ≥ 0: system gain K = K0·10^(gain_db/20) */
} pc_sim_controls;

/* Renders (once) and caches the noise-free signal of a state: the per-pixel electron rate after
 * optics, analyser, crosstalk, QE and PRNU. Costs the ray casting; frames afterwards cost only
 * the sensor chain. Optionally returns the ground truth of the ROI at the same time (may be
 * NULL): truth_stokes as float32 (H, W, C, 4) with C = colour_channels, radiance in
 * W·m⁻²·sr⁻¹ in the image-plane frame; truth_mueller as float32 (H, W, C, 4, 4) (only with
 * PC_FX_MUELLER, else PC_ENOTSUP), the Mueller matrix from the lights' Stokes frames to the
 * image-plane frame, summed over lights, in W·m⁻²·sr⁻¹ per unit normalized Stokes input.
 * Not thread-safe against other calls on the same sim. progress (may be NULL) is called with
 * rows done out of the total from the calling thread. */
typedef void (*pc_sim_progress_fn)(void *user, uint64_t done, uint64_t total);
PC_API int pc_sim_prepare(pc_sim *sim, unsigned state, float *truth_stokes, float *truth_mueller,
                          pc_sim_progress_fn progress, void *progress_user);

/* True when state's signal is cached. */
PC_API bool pc_sim_is_prepared(const pc_sim *sim, unsigned state);

/* Raw frame n into dst (format, width and height as pc_sim_get_info; any stride). controls may
 * be NULL (the scene's exposure and gain). Prepares the frame's state when needed (therefore
 * not thread-safe unless every state was prepared: then it only reads the sim, and several
 * threads may produce different frames at once). meta (may be NULL) gets sequence = n,
 * timestamp_ns = n / frame_rate, exposure, gain, PC_FRAME_SIMULATED and the ROI offset. */
PC_API int pc_sim_frame(pc_sim *sim, uint64_t n, const pc_sim_controls *controls, pc_view *dst,
                        pc_frame_meta *meta);

/* Checks that frames first .. first + count − 1 have sequence numbers and timestamps
 * (n / frame_rate_hz, in ns) that fit 64-bit signed integers, as recordings store them
 * (meta.json), and that count is within PC_LIMIT_FRAMES (polarcam/limits.h): 0, or PC_ERANGE
 * naming the largest first frame this scene's frame rate allows, or the limit.
 * pc_sim_frame fails the same way for a frame whose timestamp does not fit. */
PC_API int pc_sim_check_frames(const pc_sim *sim, uint64_t first, uint64_t count);

/* Rows [y0, y1) of frame n into dst rows [y0, y1) (dst is the whole frame's view). The state
 * must be prepared (PC_ESTATE otherwise). Const and thread-safe: bands may be produced in any
 * order and on any thread, the result is bit-identical to pc_sim_frame. */
PC_API int pc_sim_frame_rows(const pc_sim *sim, uint64_t n, const pc_sim_controls *controls,
                             pc_view *dst, uint32_t y0, uint32_t y1);

/* Ground truth in double for rows [y0, y1) of the ROI without touching any cache (tests,
 * exact comparisons): stokes (may be NULL) gets (y1−y0)·W·C·4 doubles, mueller (may be NULL,
 * needs PC_FX_MUELLER) (y1−y0)·W·C·16. Thread-safe. */
PC_API int pc_sim_truth_rows(const pc_sim *sim, unsigned state, uint32_t y0, uint32_t y1,
                             double *stokes, double *mueller);

/* The mean raw value (DN, before quantization and noise, after clipping at full well) that
 * pixel (x, y) of the ROI would have in state under controls: for photon-transfer and bias
 * tests and for calibration. The state must be prepared. */
PC_API int pc_sim_mean_dn(const pc_sim *sim, unsigned state, const pc_sim_controls *controls,
                          uint32_t x, uint32_t y, double *mean_dn);

/* The scale between a Stokes estimate in DN and the truth radiance, for colour channel ch under
 * controls (NULL: the scene's): with ideal analysers, S_est = (I0 + I45 + I90 + I135)/2 above the
 * black level (and S1 = I0 − I90, S2 = I45 − I135) equals this factor times the truth Stokes
 * radiance (before noise, clipping and quantization): K·t_exp·2η·π/(4N²)·A_pix·λ/(hc). */
PC_API double pc_sim_dn_per_radiance(const pc_sim *sim, const pc_sim_controls *controls,
                                     unsigned ch);

/* An evaluation case for the demosaicking protocol (polarcam/eval.h, docs/demosaicking.md):
 * renders state 0 and gives raw frame 0 (the sensor's whole chain: noise and analyser errors
 * as the scene declares) and its ground truth, the four ideal-analyser images
 * offset + k·(S0 + S1·cos 2θ + S2·sin 2θ)/2 without noise (k = pc_sim_dn_per_radiance),
 * clipped to [0, 2^bits − 1] and normalised by 2^bits − 1. Monochrome sensors with even sizes
 * of at least 32×32 (PC_ENOTSUP, PC_EINVAL otherwise). Free with pc_eval_truth_free and
 * pc_view_free; score with pc_eval_method_raw and the frame's mosaic (pc_sim_get_info). */
PC_API int pc_sim_eval_case(pc_sim *sim, pc_eval_truth *truth, pc_view *raw);

/* The same for a colour sensor (colour_channels 3, e.g. the imx250myr preset): truth[k] is
 * colour k's (R, G, B) four ideal-analyser images, each scaled by its own
 * pc_sim_dn_per_radiance. Score with pc_eval_method_raw_colour. */
PC_API int pc_sim_eval_colour_case(pc_sim *sim, pc_eval_truth truth[3], pc_view *raw);

/* Scores each method on each evaluation case into res[d·nmeth + k] (as pc_eval_dirs): a path
 * ending in .json is a scene, loaded and rendered by pc_sim_eval_case (its frame 0 with its
 * sensor, scored against the noise-free truth; the dataset is the scene's directory; a colour
 * sensor's by pc_sim_eval_colour_case and pc_eval_method_raw_colour, which need colour
 * methods), any other a truth directory (pc_truth_load, mosaicked with the Sony layout). threads:
 * the renderer's (0: default); opts as pc_eval_method (may be NULL); progress (may be NULL): phase
 * "eval", results done. Errors name the path. pc_eval_result: polarcam/io.h. */
struct pc_eval_result;
PC_API int pc_sim_eval_cases(const char *const *paths, size_t n, const pc_demosaic_method *methods,
                             size_t nmeth, const pc_demosaic_opts *opts, int threads,
                             const pc_progress *progress, struct pc_eval_result *res);

/* ---------------------------------------------------------------------------------------------
 * The sensor (physics.md §6). Figures as resolved from the preset and the scene's overrides.
 */
typedef struct pc_sensor_figures {
	char preset[32]; /* "ideal", "imx250mzr", "imx250myr", "imx250mzr_nonuniform" */
	uint32_t width, height;
	double pixel_pitch_um;
	unsigned bits;           /* ADC bits */
	double qe[3];            /* quantum efficiency for unpolarized light (R, G, B; mono: [0]) */
	double wavelength_nm[3]; /* effective wavelength of each channel */
	double full_well_e;      /* saturation capacity, electrons */
	double read_noise_e;     /* temporal dark noise σ_d, electrons */
	double dark_current_e_s; /* mean dark current µ_I, electrons per second */
	double dsnu_e;           /* DSNU σ, electrons */
	double prnu;             /* PRNU σ, relative (0.005 = 0.5 %) */
	double gain_dn_per_e;    /* system gain K0 at gain_db = 0, DN per electron */
	double offset_dn;        /* black level, DN */
	double extinction_ratio; /* ER of the micro-polarizers (the median with a spread) */
	double extinction_ratio_sigma;    /* per-pixel ER spread: σ of ln ER (log-normal, median
	                                     extinction_ratio); 0 = every pixel has extinction_ratio */
	double orientation_sigma_deg;     /* random per-pixel analyser orientation error σ */
	double orientation_offset_deg[4]; /* systematic error per channel 0/45/90/135 */
	double transmission_sigma;        /* random per-pixel relative transmission error σ */
	double transmission[4]; /* systematic relative transmission per channel (1 = nominal) */
	double crosstalk;       /* fraction of each 4-neighbour's signal received */
	double exposure_us, gain_db, frame_rate_hz;
	pc_mosaic mosaic; /* of the full sensor */
	unsigned effects; /* the sensor effects the preset/scene declares */
} pc_sensor_figures;

PC_API void pc_sim_get_sensor(const pc_sim *sim, pc_sensor_figures *fig);

/* Preset names, NULL-terminated. */
PC_API const char *const *pc_sensor_preset_names(void);

/* The simulator as a JSON object (compact text, malloc'd; NULL when out of memory): {"scene":
 * the scene document (scene may be NULL), "scene_name", "seed", "effects": [names], "sensor":
 * {preset, size, pitch, bits, layout, QE, noise figures, analyser errors, exposure...}, "roi",
 * "n_states"}. What `polarcam render` writes under meta.json's "extra". */
PC_API char *pc_sim_describe_json(const pc_sim *sim, const pc_scene *scene);

/* ---------------------------------------------------------------------------------------------
 * Polarization states of a frame sequence (Mueller imaging, physics.md §7).
 */
typedef struct pc_sim_states {
	unsigned n_psg, n_psa;
	/* Generator states: normalized Stokes vectors (S0 = 1) in each PSG light's own frame. */
	double psg[64][4];
	/* Analyser states: Mueller matrix of the element in front of the camera, image-plane frame.
	 */
	double psa[64][4][4];
	/* The ideal analyser rows of the four mosaic channels 0/45/90/135° (nominal, normalized as
	 * physics.md §6 with t = 1, d = 1: 0.5·(1, cos2θ, sin2θ, 0)). */
	double analyser[4][4];
} pc_sim_states;

PC_API void pc_sim_get_states(const pc_sim *sim, pc_sim_states *states);

#ifdef __cplusplus
}
#endif
#endif
