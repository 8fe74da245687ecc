/* polarcam/family.h - scene families: a generator spec (JSON, docs/dataset.md) of distributions
 * over materials, shapes, placements, lights and their polarization, camera poses, sensors,
 * exposures and effects, from which sample i is drawn as a complete scene in the scene format
 * (docs/scene-format.md) and rendered with its ground truth.
 *
 * Determinism: sample i is a pure function of (spec, seed, i). Its random draws come from the
 * counter-based generator of the simulator (Philox4x32-10 keyed by the seed, the sample index
 * in the counter), so samples are independent of each other, of the order they are made in and
 * of the thread count. The scene written for a sample re-renders alone (`polarcam render
 * scene.json --seed S`) to the same raw frames and truth, bit for bit.
 *
 *     pc_family *f;
 *     pc_family_load("scenes/dataset/demosaic.json", &f);
 *     pc_family_sample s;
 *     pc_family_render(f, 7, 123, 0, &s);      // seed 7, sample 123, all threads
 *     ... s.scene_json, s.frames[0], s.truth_stokes ...
 *     pc_family_sample_free(&s);
 *     pc_family_free(f);
 */
#ifndef POLARCAM_FAMILY_H
#define POLARCAM_FAMILY_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/export.h"
#include "polarcam/frame.h"
#include "polarcam/sim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_family pc_family;

/* Loads and validates a family spec; errors name the file and the field path and say what was
 * expected ("demosaic.json: lights.count: {"int": [lo, hi]} needs 0 <= lo <= hi <= 64").
 * Mesh files are resolved relative to the spec's directory. */
PC_API int pc_family_load(const char *path, pc_family **out);
/* The same from text; name is used in messages, base_dir resolves mesh files (NULL = "."). */
PC_API int pc_family_parse(const char *text, const char *name, const char *base_dir,
                           pc_family **out);
PC_API void pc_family_free(pc_family *f);

/* Replaces the spec's resolution (multiples of the mosaic period of every sensor preset the
 * spec may draw). */
PC_API int pc_family_set_resolution(pc_family *f, uint32_t width, uint32_t height);
PC_API const char *pc_family_name(const pc_family *f);
PC_API void pc_family_resolution(const pc_family *f, uint32_t *width, uint32_t *height);
/* The spec as used (with the resolution override), canonical compact JSON (malloc'd): two
 * families with the same text make the same samples. */
PC_API char *pc_family_to_json(const pc_family *f);

/* Mesh files the spec may draw: the path as resolved for reading and the name a dataset stores
 * it under (DIR/meshes/NAME; sample scenes refer to "../../meshes/NAME"). */
PC_API unsigned pc_family_mesh_count(const pc_family *f);
PC_API void pc_family_mesh(const pc_family *f, unsigned i, const char **path, const char **name);

typedef enum pc_family_truth { PC_TRUTH_NONE, PC_TRUTH_F32, PC_TRUTH_F16 } pc_family_truth;

/* One rendered sample. */
typedef struct pc_family_sample {
	uint64_t index;
	uint64_t sim_seed; /* the simulator's noise seed of this sample (< 2^63) */
	char *scene_json;  /* the complete scene (scene format, exposure chosen), with mesh
	                    * files as "../../meshes/NAME": DIR/samples/NNNNNN/scene.json */
	pc_sim_info info;  /* size, format, mosaic, bits, effects */
	unsigned n_frames;
	pc_view *frames;           /* n_frames raw frames 0..n−1 in the natural format */
	pc_frame_meta *frame_meta; /* theirs, as pc_sim_frame reports it */
	char *sim_json;            /* pc_sim_describe_json of the simulator (without the scene),
	                            * with the chosen exposure: what `polarcam render` writes under
	                            * meta.json's "extra" */
	pc_family_truth truth;     /* what the spec asks to store */
	float *truth_stokes;       /* (H, W, 4) or (H, W, 3, 4) float32 radiance, or NULL */
	double exposure_us;        /* as in scene_json */
	double dn_per_radiance;    /* mean DN per unit radiance of unpolarized light (green/mono) */
	double saturated_fraction; /* of frame 0's pixels at full scale */
	double median_dn, p99_dn;  /* of frame 0 */
} pc_family_sample;

/* Draws sample `index` of the family under `seed` and renders it: scene → simulator (threads,
 * 0 = all) → truth → exposure (the spec's auto-exposure sets the chosen percentile of the mean
 * signal to the chosen fraction of full scale) → frames. */
PC_API int pc_family_render(const pc_family *f, uint64_t seed, uint64_t index, int threads,
                            pc_family_sample *out);
/* Only the scene document of sample index (mesh files as the spec names them, resolved against
 * its directory) and its simulator seed, before the exposure is chosen (tests, previews). */
PC_API int pc_family_scene(const pc_family *f, uint64_t seed, uint64_t index, char **scene_json,
                           uint64_t *sim_seed);
PC_API void pc_family_sample_free(pc_family_sample *s);

#ifdef __cplusplus
}
#endif

#endif
