/* tools/sim_cli.h - what the simulator commands (render, demo, mueller, bench render) share:
 * the simulator's description as JSON, the states file, progress adapters. */
#ifndef CLI_TOOLS_SIM_CLI_H
#define CLI_TOOLS_SIM_CLI_H

#include <jansson.h>

#include "cli.h"
#include "polarcam/demosaic.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/sim.h"

/* {"scene": <document>, "scene_name", "seed", "effects": [names], "sensor": {figures},
 *  "supersampling", "states": {...}} */
json_t *pc_sim_describe(const pc_sim *sim, const pc_scene *scene);

/* The effect names of a PC_FX_* set as a JSON array. */
json_t *pc_sim_effects_json(unsigned effects);

/* states.json for `polarcam mueller --states`: frame order, PSG Stokes vectors, PSA Mueller
 * matrices, the mosaic and the analyser rows (docs/scene-format.md, "Frame sequences"). */
json_t *pc_sim_states_json(const pc_sim *sim);

/* A pc_sim_progress_fn drawing a cli_progress (user = cli_progress*) with an offset. */
typedef struct pc_sim_progress_adapter {
	cli_progress *bar;
	uint64_t base;
} pc_sim_progress_adapter;
void pc_sim_progress_cb(void *user, uint64_t done, uint64_t total);

/* Peak resident set size of this process in MiB (VmHWM), or -1. */
double pc_peak_rss_mib(void);


/* Writes a float (H, W) map as DIR/NAME.npy and a grey picture DIR/NAME.png (linear from lo to
 * hi, with a title and a colour bar labelled label). */
int pc_write_map(const char *dir, const char *name, const float *map, uint32_t width,
		 uint32_t height, double lo, double hi, const char *title, const char *label);

/* Parses a states.json (pc_sim_states_json's format) into st; errors name the file and field. */
int pc_states_read(const char *path, pc_sim_states *st, char *layout, size_t layout_size);

/* sizeof-checked path join: DIR/NAME into buf (PC_EINVAL when too long). */
int pc_path_join(char *buf, size_t size, const char *dir, const char *name);

/* ---- Mueller imaging from frame sequences (polarcam mueller, polarcam demo) ---- */

/* Supplies frame j of a sequence as an owned view (the caller frees it). */
typedef int (*pc_frame_get_fn)(void *user, size_t j, pc_view *out);

/* Rebuilding the circular entries of rank-3 (linear) systems (physics.md §7,
 * pc_mueller_rebuild_from_linear): sign PC_REBUILD_OFF leaves them NaN. */
typedef struct pc_rebuild_opts {
	pc_rebuild_sign sign;
	double tol; /* residual / realisability tolerance, relative to M00 */
} pc_rebuild_opts;

typedef struct pc_mueller_result {
	pc_mueller_system sys;
	uint32_t width, height;   /* of the maps (the demosaicked size) */
	float *M;                 /* (H, W, 4, 4) in the raw's units above the black level */
	float *maps;              /* D, R, Delta: three (H, W) planes */
	float *residual;          /* (H, W) rebuild residual / M00, NULL when nothing was rebuilt */
	long singular, nonphysical, bad; /* pixel counts: D ≈ 1 / Cloude-filtered / no result */
	long rb_rejected, rb_sign_undefined; /* rebuild: not of the family (M00 > 0) / sign
	                                        without a frame */
	bool rebuilt;             /* the circular entries were rebuilt from the 3×3 */
} pc_mueller_result;

/* Frames → demosaic (method) → − black → per-pixel least squares → (rank 3 and rb given and
 * not off: the 4×4 rebuilt from the 3×3) → Lu–Chipman maps. bar may be NULL (else advanced
 * by one per frame); rb may be NULL (no rebuild). */
int pc_mueller_run(pc_frame_get_fn get, void *user, const pc_sim_states *st,
		   const pc_mosaic *mosaic, pc_demosaic_method method, double black, int threads,
		   const pc_rebuild_opts *rb, cli_progress *bar, pc_mueller_result *res);
/* Lu–Chipman D, R, Δ of every pixel of a (H, W, 4, 4) Mueller image (NaN where undefined). */
void pc_mueller_maps(const float *M, uint32_t width, uint32_t height, unsigned determined,
		     int threads, float *D, float *R, float *Delta, long counts[3]);
/* The same, first rebuilding the circular entries in M (in place) where only the 3×3 linear
 * block is determined and rb is given and not off: rejected pixels get NaN there and NaN maps;
 * residual (may be NULL) receives the rebuild residual / M00 per pixel; rb_counts: rejected
 * (inconsistent or not realisable; M00 ≤ 0 is not counted), sign undefined. */
void pc_mueller_maps_rebuild(float *M, uint32_t width, uint32_t height, unsigned determined,
			     const pc_rebuild_opts *rb, int threads, float *D, float *R,
			     float *Delta, float *residual, long counts[3], long rb_counts[2]);
void pc_mueller_result_free(pc_mueller_result *res);

#endif
