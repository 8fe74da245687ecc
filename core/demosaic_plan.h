/* Internal to core: the one table of demosaicking methods and the one validation of a call
 * (demosaic_plan.c), shared by the two front doors, pc_demosaic_run (demosaic.c) and
 * pc_stokes_run (stokes.c). A plan is a validated raw and pipeline options with everything
 * resolved once (sizes, full scale, CPU level, the prepared input); the table says which
 * kernel runs each stage. Not a public header.
 *
 * Adding a method: a row in pc_dm_methods (demosaic_plan.c) with its public description, its
 * support (the raw samples an output depends on: checked against the reference by
 * perturbation in tests/test_demosaic.c), its monochrome reference in pc_dm_ref (or, for a
 * colour method, the monochrome method of its second step), and where it has them its fast
 * kernel and its row-sink kernel (the fused Stokes pipeline). */
#ifndef POLARCAM_DEMOSAIC_PLAN_H
#define POLARCAM_DEMOSAIC_PLAN_H

#include <stdbool.h>

#include "demosaic_common.h"
#include "polarcam/demosaic.h"
#include "validity.h"

typedef struct pc_dm_method_def {
	pc_demosaic_method_info info;
	pc_dm_support support;
	/* monochrome: the fast float kernel into channel planes (NULL: the double reference,
	 * converted to float, is the implementation) */
	int (*fast)(const pc_dm_call *call, const pc_fplane *out);
	/* monochrome: the kernel that hands finished rows to a sink (the fused Stokes pipeline;
	 * planar Stokes outputs); NULL: none */
	int (*rows)(const pc_dm_call *call, const pc_dm_row_sink *sink);
	/* monochrome: the fused bilinear demosaic + Stokes kernel computes this method */
	bool fused_bilinear;
	/* colour: the monochrome method of step 2 (demosaic_color.h) */
	pc_demosaic_method second;
	/* monochrome row-cache kernels (pc_dm_ic): ordinary stores straight into planar outputs
	 * even where large outputs stream (pc_dm_stream_wanted); measured faster for ratio and
	 * ratio-nr (docs/demosaicking.md). Interleaved outputs stream all the same
	 * (pc_dm_stream_wanted_il: ratio-nr 0.85 of the time, Round 33). */
	bool plain_stores;
} pc_dm_method_def;

/* The table row of a method, NULL for values out of range. */
const pc_dm_method_def *pc_dm_method_def_get(pc_demosaic_method m);

typedef struct pc_dm_plan {
	const pc_view *raw;
	const pc_dm_method_def *def;
	pc_pipeline_opts opts;
	bool colour;
	uint32_t ow, oh;    /* output size */
	unsigned nch;       /* output channels: 4 or 12 */
	double full_scale;  /* the signal's: the raw's full scale minus the black level */
	pc_cpu_level level; /* read once per call */
	pc_dm_input in;     /* prepared on first use (pc_dm_plan_input) */
	void *owned;
	bool prepared;
	double noise_gain; /* ratio-nr's noise gain (pc_dm_plan_noise) */
	bool noise_set;
} pc_dm_plan;

/* The pipeline options of the older entry points (pc_demosaic, pc_stokes_from_raw): method,
 * mosaic m (NULL: an invalid one, refused by pc_dm_plan_begin), and threads, reference and
 * full scale from opts (may be NULL); everything else as pc_pipeline_defaults(). */
pc_pipeline_opts pc_dm_opts_legacy(const pc_mosaic *m, pc_demosaic_method method,
                                   const pc_demosaic_opts *opts);

/* Validates the raw and the options (everything but the outputs and opts->pinv, which the
 * front doors check) and resolves them. Errors: PC_EINVAL (or PC_ERANGE) with a detail message
 * naming the field. Nothing to free on error. */
int pc_dm_plan_begin(const pc_view *raw, const pc_pipeline_opts *opts, pc_dm_plan *p);
void pc_dm_plan_end(pc_dm_plan *p);

/* The prepared input (unpacked, float checked), made on the first call. */
int pc_dm_plan_input(pc_dm_plan *p, const pc_dm_input **in);

/* The plan's raw corrected per pixel (opts.dark, opts.gain_inv) as a float image (*img, free
 * with free(); *view over it) and the options that process it as the plan would the raw: no
 * correction, no black level, no level checks (the validity comes from the raw's plan), the
 * same signal full scale. */
int pc_dm_plan_corrected(pc_dm_plan *p, float **img, pc_view *view, pc_pipeline_opts *o);

/* The noise model of a monochrome method flagged PC_DMF_NOISE_GAIN (ratio-nr), once per plan:
 * σ² = g·L for a given noise gain g (opts.noise_gain > 0), else the frame's photon-transfer
 * line (demosaic_noise.h, pc_dm_noise_ptc) on img (the raw minus black in double, the
 * reference's input) or, img NULL, on the prepared input: the same values. Nothing for the other
 * methods. */
int pc_dm_plan_noise(pc_dm_plan *p, const double *img);

/* After a successful run: the noise gain used (the model's slope) into opts.noise_gain_used,
 * when the plan has a noise model and the caller asked for it. */
void pc_dm_plan_noise_report(const pc_dm_plan *p);

/* The kernel call of a monochrome plan (after pc_dm_plan_input and pc_dm_plan_noise). */
pc_dm_call pc_dm_plan_call(const pc_dm_plan *p);

/* Demosaics into the plan's channel planes (checked by the caller): the reference, the fast
 * kernel, or for colour mosaics step 1 then step 2 through the table. */
int pc_dm_plan_demosaic(pc_dm_plan *p, const pc_fplane *out);

/* Checks a validity output for the plan's output size (PC_EINVAL naming the field). */
int pc_dm_plan_check_validity(const pc_dm_plan *p, const pc_validity *v);

/* Fills the validity output (mask and count) from the raw and the method's support. */
int pc_dm_plan_validity(pc_dm_plan *p, pc_validity *v);
/* A compact calibration's list of distrusted samples (distrust_row/distrust_x, both or
 * neither) for a width × height raw: the sizes match, the row offsets never decrease and
 * every column is inside the raw. 0 or PC_EINVAL naming the fault. */
int pc_dm_check_distrust(const struct pc_compact_calib *v, uint32_t width, uint32_t height);

#endif
