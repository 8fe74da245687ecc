/* Evaluation cases from scenes: the stress suite of docs/demosaicking.md renders a scene with
 * ground truth and scores demosaicking against it under the frozen protocol (polarcam/eval.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/sim.h"

int pc_sim_eval_case(pc_sim *sim, pc_eval_truth *t, pc_view *raw)
{
	memset(t, 0, sizeof *t);
	memset(raw, 0, sizeof *raw);
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	if (info.colour_channels != 1)
		return pc_error(PC_ENOTSUP,
		                "evaluation case: the scene's sensor is a colour sensor; "
		                "the protocol scores monochrome polarizer mosaics");
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
	float *st = malloc(sizeof(float) * n * 4);
	if (!st)
		return pc_error(PC_ENOMEM, "evaluation case: truth Stokes of %ux%u", w, h);
	int rc = pc_sim_prepare(sim, 0, st, NULL, NULL, NULL);
	if (!rc)
		rc = pc_view_alloc(raw, info.format, w, h, 0);
	if (!rc)
		rc = pc_sim_frame(sim, 0, NULL, raw, NULL);
	if (!rc) {
		for (int c = 0; c < 4 && !rc; c++)
			if (!(t->ch[c] = malloc(sizeof(double) * n)))
				rc = pc_error(PC_ENOMEM, "evaluation case: truth of %ux%u", w, h);
	}
	if (rc) {
		free(st);
		pc_eval_truth_free(t);
		pc_view_free(raw);
		return rc;
	}
	/* The truth is what ideal analysers at 0/45/90/135° would read without noise, in DN:
	 * offset + k·(S0 + S1·cos 2θ + S2·sin 2θ)/2 with k = pc_sim_dn_per_radiance (physics.md
	 * §6, the sensor chain's mean), clipped to the ADC range as a ground-truth capture would
	 * be; normalised by the ADC's full scale 2^bits − 1 (the protocol's step 1). */
	const double k = pc_sim_dn_per_radiance(sim, NULL, 0);
	const double fs = (double)((1u << info.bits) - 1u);
	static const double cs[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
	for (size_t i = 0; i < n; i++) {
		const float *s = st + 4 * i;
		for (int c = 0; c < 4; c++) {
			double v =
			    fig.offset_dn + k * 0.5 * (s[0] + cs[c][0] * s[1] + cs[c][1] * s[2]);
			t->ch[c][i] = fmin(fmax(v, 0), fs) / fs;
		}
	}
	free(st);
	t->width = w;
	t->height = h;
	t->full_scale = fs;
	t->format = info.bits <= 8 ? PC_FMT_MONO8 : PC_FMT_MONO16;
	return 0;
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
 * with its sensor). */
static int load_case(const char *path, int threads, pc_eval_truth *t, pc_view *raw, pc_mosaic *m)
{
	memset(raw, 0, sizeof *raw);
	if (!is_scene_file(path)) {
		int rc = pc_truth_load(path, t);
		if (rc)
			return rc;
		*m = pc_mosaic_imx250mzr();
		rc = pc_eval_mosaic(t, m, raw);
		if (rc)
			pc_eval_truth_free(t);
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
		rc = pc_sim_eval_case(sim, t, raw);
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
		pc_eval_truth t;
		pc_view raw;
		pc_mosaic mo;
		int rc = load_case(paths[d], threads, &t, &raw, &mo);
		if (rc)
			return pc_error_prefix(rc, "%s: ", paths[d]);
		for (size_t k = 0; k < nmeth && !rc; k++) {
			pc_eval_result *r = &res[nres];
			r->scene = paths[d];
			pc_truth_dataset(paths[d], r->dataset, sizeof r->dataset);
			r->method = methods[k];
			double t0 = now_s();
			rc = pc_eval_method_raw(&t, &raw, &mo, methods[k], opts, &r->m);
			r->seconds = now_s() - t0;
			if (!rc) {
				nres++;
				pc_progress_report(progress, "eval", nres, n * nmeth);
			}
		}
		pc_eval_truth_free(&t);
		pc_view_free(&raw);
		if (rc)
			return pc_error_prefix(rc, "%s: ", paths[d]);
	}
	return 0;
}
