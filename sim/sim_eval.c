/* Evaluation cases from scenes: the stress suite of docs/demosaicking.md renders a scene with
 * ground truth and scores demosaicking against it under the frozen protocol (polarcam/eval.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/sim.h"

/* The evaluation case of a sensor with nc colour channels (1 or 3): t[k] colour k's truth. */
static int eval_case(pc_sim *sim, unsigned nc, pc_eval_truth *t, pc_view *raw)
{
	for (unsigned k = 0; k < nc; k++)
		memset(&t[k], 0, sizeof t[k]);
	memset(raw, 0, sizeof *raw);
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	if (info.colour_channels != nc)
		return pc_error(PC_ENOTSUP,
		                nc == 1 ? "evaluation case: the scene's sensor is a colour sensor "
		                          "(pc_sim_eval_colour_case scores it)"
		                        : "evaluation case: the scene's sensor is monochrome "
		                          "(pc_sim_eval_case scores it)");
	if (info.width % 2 || info.height % 2 || info.width < 2 * PC_EVAL_BORDER + 2 ||
	    info.height < 2 * PC_EVAL_BORDER + 2)
		return pc_error(PC_EINVAL,
		                "evaluation case: frame %ux%u: even sizes of at least "
		                "%dx%d are needed",
		                info.width, info.height, 2 * PC_EVAL_BORDER + 2,
		                2 * PC_EVAL_BORDER + 2);
	pc_sensor_figures fig;
	pc_sim_get_sensor(sim, &fig);
	const uint32_t w = info.width, h = info.height;
	const size_t n = (size_t)w * h;
	float *st = malloc(sizeof(float) * n * 4 * nc);
	if (!st)
		return pc_error(PC_ENOMEM, "evaluation case: truth Stokes of %ux%u", w, h);
	int rc = pc_sim_prepare(sim, 0, st, NULL, NULL, NULL);
	if (!rc)
		rc = pc_view_alloc(raw, info.format, w, h, 0);
	if (!rc)
		rc = pc_sim_frame(sim, 0, NULL, raw, NULL);
	for (unsigned k = 0; k < nc && !rc; k++)
		for (int c = 0; c < 4 && !rc; c++)
			if (!(t[k].ch[c] = malloc(sizeof(double) * n)))
				rc = pc_error(PC_ENOMEM, "evaluation case: truth of %ux%u", w, h);
	if (rc) {
		free(st);
		for (unsigned k = 0; k < nc; k++)
			pc_eval_truth_free(&t[k]);
		pc_view_free(raw);
		return rc;
	}
	/* The truth is what ideal analysers at 0/45/90/135° would read without noise, in DN:
	 * offset + k·(S0 + S1·cos 2θ + S2·sin 2θ)/2 with k = pc_sim_dn_per_radiance of the colour
	 * channel (physics.md §6, the sensor chain's mean), clipped to the ADC range as a
	 * ground-truth capture would be; normalised by the ADC's full scale 2^bits − 1 (the
	 * protocol's step 1). A colour sensor's truth Stokes are (H, W, 3, 4): colour k of pixel
	 * i at st[4·(3·i + k)]. */
	const double fs = (double)((1u << info.bits) - 1u);
	static const double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
	for (unsigned k = 0; k < nc; k++) {
		const double kd = pc_sim_dn_per_radiance(sim, NULL, k);
		for (size_t i = 0; i < n; i++) {
			const float *s = st + 4 * (nc * i + k);
			for (int c = 0; c < 4; c++) {
				double v = fig.offset_dn +
				           kd * 0.5 * (s[0] + cs[c][0] * s[1] + cs[c][1] * s[2]);
				t[k].ch[c][i] = fmin(fmax(v, 0), fs) / fs;
			}
		}
		t[k].width = w;
		t[k].height = h;
		t[k].full_scale = fs;
		t[k].format = info.bits <= 8 ? PC_FMT_MONO8 : PC_FMT_MONO16;
	}
	free(st);
	return 0;
}

int pc_sim_eval_case(pc_sim *sim, pc_eval_truth *t, pc_view *raw)
{
	return eval_case(sim, 1, t, raw);
}

int pc_sim_eval_colour_case(pc_sim *sim, pc_eval_truth t[3], pc_view *raw)
{
	return eval_case(sim, 3, t, raw);
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int is_scene_file(const char *path)
{
	size_t n = strlen(path);
	return n > 5 && !strcmp(path + n - 5, ".json");
}

/* One evaluation case: a truth directory (mosaicked with the Sony layout) or a scene (rendered
 * with its sensor); *nc the colour channels (3: t[0..2] the colours' truths). */
static int load_case(const char *path, int threads, pc_eval_truth t[3], unsigned *nc, pc_view *raw,
                     pc_mosaic *m)
{
	memset(raw, 0, sizeof *raw);
	*nc = 1;
	if (!is_scene_file(path)) {
		int rc = pc_truth_load(path, &t[0]);
		if (rc)
			return rc;
		*m = pc_mosaic_imx250mzr();
		rc = pc_eval_mosaic(&t[0], m, raw);
		if (rc)
			pc_eval_truth_free(&t[0]);
		return rc;
	}
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	int rc = pc_scene_load(path, &scene);
	pc_sim_options so = pc_sim_options_default();
	so.threads = threads;
	if (!rc)
		rc = pc_sim_new(scene, &so, &sim);
	pc_scene_free(scene);
	if (!rc) {
		pc_sim_info info;
		pc_sim_get_info(sim, &info);
		*m = info.mosaic;
		*nc = info.colour_channels == 3 ? 3 : 1;
		rc = eval_case(sim, *nc, t, raw);
	}
	pc_sim_free(sim);
	return rc;
}

int pc_sim_eval_cases(const char *const *paths, size_t n, const pc_demosaic_method *methods,
                      size_t nmeth, const pc_demosaic_opts *opts, int threads,
                      const pc_progress *progress, pc_eval_result *res)
{
	size_t nres = 0;
	for (size_t d = 0; d < n; d++) {
		pc_eval_truth t[3];
		pc_view raw;
		pc_mosaic mo;
		unsigned nc;
		int rc = load_case(paths[d], threads, t, &nc, &raw, &mo);
		if (rc)
			return pc_error_prefix(rc, "%s: ", paths[d]);
		pc_eval_pattern pat;
		rc = pc_eval_truth_pattern(&t[0], &pat);
		for (size_t k = 0; k < nmeth && !rc; k++) {
			pc_eval_result *r = &res[nres];
			r->truth_pattern = pat;
			r->scene = paths[d];
			pc_truth_dataset(paths[d], r->dataset, sizeof r->dataset);
			r->method = methods[k];
			double t0 = now_s();
			rc = nc == 3
			         ? pc_eval_method_raw_colour(t, &raw, &mo, methods[k], opts, &r->m)
			         : pc_eval_method_raw(&t[0], &raw, &mo, methods[k], opts, &r->m);
			r->seconds = now_s() - t0;
			if (!rc) {
				nres++;
				pc_progress_report(progress, "eval", nres, n * nmeth);
			}
		}
		for (unsigned k = 0; k < nc; k++)
			pc_eval_truth_free(&t[k]);
		pc_view_free(&raw);
		if (rc)
			return pc_error_prefix(rc, "%s: ", paths[d]);
	}
	return 0;
}
