/* polarcam/demo.h - the main job (`polarcam demo`): a scene rendered through the sensor model,
 * one raw frame run through the pipeline with several demosaicking methods and scored against
 * the ground truth (polarcam/eval.h), Mueller imaging of the same scene from a tetrahedral
 * generator × quarter-wave analyser sequence compared with the truth's Lu–Chipman maps, and
 * pictures and a report.
 *
 * Writes into the output directory: raw_000000.png + meta.json (a recording), truth_stokes.npy,
 * truth/ (pictures), pipeline_<method>/ (pictures of bilinear and of the last method),
 * stokes.npy (the bilinear estimate, (H, W, 3) in DN), mueller/ (D, R, Delta and truth_* .npy and
 * .png, mueller.npy, truth_mueller.npy), report.json and report.md.
 */
#ifndef POLARCAM_DEMO_H
#define POLARCAM_DEMO_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/demosaic.h"
#include "polarcam/export.h"
#include "polarcam/progress.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_demo_opts {
	const char *scene_path;            /* NULL: the built-in default scene */
	uint64_t seed;                     /* noise seed */
	const pc_demosaic_method *methods; /* compared methods (half-resolution ones run as their
	                                      full-resolution variant) */
	unsigned n_methods;
	bool mueller;         /* run the Mueller-imaging step */
	bool overwrite;       /* replace an existing output folder (polarcam/io.h's rule) */
	int threads;          /* 0: all */
	pc_progress progress; /* phases "render", "mueller render", "mueller frames" */
} pc_demo_opts;

typedef struct pc_demo pc_demo;

typedef struct pc_demo_info {
	const char *scene_name;
	uint32_t width, height;
	unsigned effects; /* PC_FX_* */
} pc_demo_info;

/* Loads the scene and builds the simulator (monochrome sensors only: PC_EINVAL otherwise). */
PC_API int pc_demo_new(const pc_demo_opts *opts, pc_demo **out);
PC_API void pc_demo_get_info(const pc_demo *demo, pc_demo_info *info);
/* Runs the job into out_dir, an output folder written as a set (polarcam/io.h, pc_outdir:
 * refused when it exists unless opts->overwrite, put in place only when complete). report_md
 * (may be NULL) receives report.md's text (malloc'd), also when writing it failed. */
PC_API int pc_demo_run(pc_demo *demo, const char *out_dir, char **report_md);
PC_API void pc_demo_free(pc_demo *demo);

#ifdef __cplusplus
}
#endif
#endif
