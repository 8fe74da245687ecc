/* polarcam eval [TRUTH_DIR|SCENE.json]... [--stress DIR] [--data DIR] [--method NAME|all]:
 * score demosaicking methods against ground truth with the frozen protocol (polarcam/eval.h);
 * the evaluation is one library call (pc_sim_eval_cases), the gains pc_eval_dataset_gain. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/io.h"
#include "polarcam/sim.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam eval [TRUTH_DIR|SCENE.json]... [--stress DIR] [--data DIR]\n"
	    "                     [--method NAME|all] [--json PATH|- [--overwrite]] [--reference]\n"
	    "\n"
	    "Scores demosaicking methods against ground truth with the frozen protocol of\n"
	    "docs/evaluation.md: the four analyser images normalised by their container's\n"
	    "full scale, cropped to even size, mosaicked with the Sony layout [90 45; 135 0],\n"
	    "demosaicked, and compared outside a 15-pixel border: PSNR (dB, peak 1) of the four\n"
	    "I channels (mean), S0/2, (S1+1)/2, (S2+1)/2 and DoLP; AoLP RMSE in degrees (wrapped\n"
	    "to [0, 90]) and its DoLP-weighted version.\n"
	    "\n"
	    "Each TRUTH_DIR holds the analyser images 0, 45, 90 and 135 (.tif/.tiff, .png, .bmp "
	    "or\n"
	    ".npy). A SCENE.json (docs/scene-format.md; the stress suite in scenes/stress) is\n"
	    "rendered with ground truth: its raw frame 0 (with the sensor's noise and analyser\n"
	    "errors when the scene declares them) is scored against the noise-free ideal-analyser\n"
	    "images, normalised by the ADC's full scale. Results are per scene and, per dataset "
	    "(the\n"
	    "directory above the scenes), the mean over its scenes; datasets are never pooled.\n"
	    "Bilinear is always run as the baseline: per dataset and method, the mean gain over\n"
	    "bilinear in S0 and DoLP and the worst scene's (with its name) are reported.\n"
	    "Colour-polarization methods (--method colour, or one by name) need scenes with a\n"
	    "colour sensor (the colour stress suite: scenes/stress/colour): each colour's four\n"
	    "analyser images are scored against its own truth and the three colours' metrics\n"
	    "averaged; bayer-first is then the baseline.\n"
	    "\n"
	    "options:\n"
	    "  --stress DIR       add every DIR/*.json scene (the stress suite: scenes/stress)\n"
	    "  --data DIR         add every public-dataset scene DIR/gt/*/* (skipped with a note\n"
	    "                     when DIR/gt is absent); default $POLARCAM_DATA when set\n"
	    "  --method NAME|all|colour  a method of `polarcam demosaic --list` (default all:\n"
	    "                     every method for monochrome mosaics; colour: every colour\n"
	    "                     method)\n"
	    "  --json -|PATH      print the results as one JSON line on stdout instead of the\n"
	    "                     table (-), or also write them as JSON to PATH (atomically;\n"
	    "                     an existing PATH is refused unless --overwrite)\n"
	    "  --reference        run the double-precision reference implementations (slow)\n"
	    "  -h, --help         this help\n"
	    "\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or unreadable truth.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam eval data/gt/lapray-nir/* --method all\n"
	    "  polarcam eval data/gt/lapray-nir/* --method ratio --json -\n"
	    "  polarcam eval data/gt/*/* --json results.json --overwrite\n");
}

static json_t *metrics_json(const pc_eval_metrics *m)
{
	json_t *o = json_object();
	json_object_set_new(o, "psnr_i", cli_json_real(m->psnr_i));
	json_object_set_new(o, "psnr_i_channels", cli_json_vec(m->psnr_i_ch, 4));
	json_object_set_new(o, "psnr_s0", cli_json_real(m->psnr_s0));
	json_object_set_new(o, "psnr_s1", cli_json_real(m->psnr_s1));
	json_object_set_new(o, "psnr_s2", cli_json_real(m->psnr_s2));
	json_object_set_new(o, "psnr_dolp", cli_json_real(m->psnr_dolp));
	json_object_set_new(o, "aolp_rmse_deg", cli_json_real(m->aolp_rmse_deg));
	json_object_set_new(o, "aolp_wrmse_deg", cli_json_real(m->aolp_wrmse_deg));
	return o;
}

static void table_row(FILE *tf, const char *label, pc_demosaic_method method,
                      const pc_eval_metrics *m)
{
	fprintf(tf, "%-28.28s %-10s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", label,
	        pc_demosaic_method_get(method)->name, m->psnr_i, m->psnr_s0, m->psnr_s1, m->psnr_s2,
	        m->psnr_dolp, m->aolp_rmse_deg, m->aolp_wrmse_deg);
}

static const char *base_name(const char *path)
{
	const char *sc = strrchr(path, '/');
	while (sc && !sc[1] && sc > path) { /* trailing slash */
		const char *p = sc - 1;
		while (p > path && *p != '/')
			p--;
		sc = *p == '/' ? p : NULL;
	}
	return sc ? sc + 1 : path;
}

/* The table (per scene, then the mean of each dataset and method, then the gains over
 * the baseline, bilinear or bayer-first, with the worst scene); returns the means and gains as
 * JSON. */
static json_t *report(FILE *tf, const pc_eval_result *res, size_t nres, pc_demosaic_method base)
{
	const char *bname = pc_demosaic_method_get(base)->name;
	fprintf(tf, "%-28s %-10s %8s %8s %8s %8s %8s %8s %8s\n", "scene", "method", "I", "S0", "S1",
	        "S2", "DoLP", "AoLP", "wAoLP");
	fprintf(tf, "%-28s %-10s %8s %8s %8s %8s %8s %8s %8s\n", "", "", "dB", "dB", "dB", "dB",
	        "dB", "deg", "deg");
	for (size_t i = 0; i < nres; i++) {
		table_row(tf, base_name(res[i].scene), res[i].method, &res[i].m);
	}
	json_t *jd = json_array();
	for (size_t i = 0; i < nres; i++) {
		int seen = 0;
		for (size_t j = 0; j < i; j++)
			seen |= !strcmp(res[j].dataset, res[i].dataset) &&
			        res[j].method == res[i].method;
		if (seen)
			continue;
		pc_eval_metrics mm;
		int cnt = pc_eval_dataset_mean(res, nres, res[i].dataset, res[i].method, &mm);
		char label[300];
		snprintf(label, sizeof label, "%s (mean of %d)", res[i].dataset, cnt);
		table_row(tf, label, res[i].method, &mm);
		json_t *o = metrics_json(&mm);
		json_object_set_new(o, "dataset", json_string(res[i].dataset));
		json_object_set_new(o, "method",
		                    json_string(pc_demosaic_method_get(res[i].method)->name));
		json_object_set_new(o, "scenes", json_integer(cnt));
		pc_eval_gain g;
		if (pc_eval_dataset_gain(res, nres, res[i].dataset, res[i].method, base, &g)) {
			json_t *gj = json_object();
			json_object_set_new(gj, "s0_mean", cli_json_real(g.s0_mean));
			json_object_set_new(gj, "dolp_mean", cli_json_real(g.dolp_mean));
			json_object_set_new(gj, "s0_worst", cli_json_real(g.s0_worst));
			json_object_set_new(gj, "s0_worst_scene",
			                    json_string(base_name(g.s0_worst_scene)));
			json_object_set_new(gj, "dolp_worst", cli_json_real(g.dolp_worst));
			json_object_set_new(gj, "dolp_worst_scene",
			                    json_string(base_name(g.dolp_worst_scene)));
			json_object_set_new(o,
			                    base == PC_DM_BILINEAR ? "gain_over_bilinear_db"
			                                           : "gain_over_bayer_first_db",
			                    gj);
		}
		json_array_append_new(jd, o);
	}
	fprintf(tf, "\ngain over %s (dB), per dataset: mean, and the worst scene\n", bname);
	fprintf(tf, "%-20s %-12s %8s %8s %8s %-20s %8s %-20s\n", "dataset", "method", "S0", "DoLP",
	        "worst S0", "(scene)", "worstDoLP", "(scene)");
	for (size_t i = 0; i < nres; i++) {
		int seen = 0;
		for (size_t j = 0; j < i; j++)
			seen |= !strcmp(res[j].dataset, res[i].dataset) &&
			        res[j].method == res[i].method;
		pc_eval_gain g;
		if (seen || res[i].method == base ||
		    !pc_eval_dataset_gain(res, nres, res[i].dataset, res[i].method, base, &g))
			continue;
		fprintf(tf, "%-20.20s %-12s %+8.3f %+8.3f %+8.3f %-20.20s %+8.3f %-20.20s\n",
		        res[i].dataset, pc_demosaic_method_get(res[i].method)->name, g.s0_mean,
		        g.dolp_mean, g.s0_worst, base_name(g.s0_worst_scene), g.dolp_worst,
		        base_name(g.dolp_worst_scene));
	}
	/* what the truths hold: a pixel-level pattern shared by their analyser images rewards
	 * methods that copy a pixel's own sample into its other channels (polarcam/eval.h) */
	fprintf(tf,
	        "\ntruth: pixel-level pattern shared by the four analyser images (flattest 30 %%; "
	        "corr at the same pixel, one pixel apart; RMS, %% of full scale). A raw\n"
	        "mosaicked from a truth with a shared pattern rewards methods that copy a pixel's "
	        "sample into its other channels (docs/evaluation.md)\n");
	for (size_t i = 0; i < nres; i++) {
		int seen = 0;
		for (size_t j = 0; j < i; j++)
			seen |= res[j].scene == res[i].scene || !strcmp(res[j].scene, res[i].scene);
		if (seen)
			continue;
		const pc_eval_pattern *tp = &res[i].truth_pattern;
		fprintf(tf, "%-28.28s corr %+6.3f  %+6.3f  RMS %.4f %%%s\n",
		        base_name(res[i].scene), tp->corr, tp->corr_shift, 100 * tp->std,
		        tp->corr - fmax(tp->corr_shift, 0) > 0.5 ? "  (shared)" : "");
	}
	return jd;
}

/* --json PATH|-: every result and the dataset means */
static int write_json(const char *json_path, const pc_eval_result *res, size_t nres, bool reference,
                      json_t *jd)
{
	json_t *root = json_object();
	json_t *js = json_array();
	for (size_t i = 0; i < nres; i++) {
		json_t *o = metrics_json(&res[i].m);
		json_object_set_new(o, "scene", json_string(res[i].scene));
		json_object_set_new(o, "dataset", json_string(res[i].dataset));
		json_object_set_new(o, "method",
		                    json_string(pc_demosaic_method_get(res[i].method)->name));
		json_object_set_new(o, "seconds", cli_json_real(res[i].seconds));
		const pc_eval_pattern *tp = &res[i].truth_pattern;
		json_t *pj = json_object();
		json_object_set_new(pj, "corr", cli_json_real(tp->corr));
		json_object_set_new(pj, "corr_shift", cli_json_real(tp->corr_shift));
		json_object_set_new(pj, "std", cli_json_real(tp->std));
		json_object_set_new(pj, "pixels", json_integer((json_int_t)tp->pixels));
		json_object_set_new(o, "truth_pattern", pj);
		json_array_append_new(js, o);
	}
	json_object_set_new(root, "protocol",
	                    json_string("polarcam frozen protocol: "
	                                "docs/evaluation.md"));
	json_object_set_new(root, "reference", json_boolean(reference));
	json_object_set_new(root, "scenes", js);
	json_object_set_new(root, "datasets", jd);
	if (!strcmp(json_path, "-")) {
		cli_print_json(root);
		return CLI_EXIT_OK;
	}
	char *s = json_dumps(root, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	int rc = s ? pc_write_file_atomic(json_path, s, strlen(s)) : pc_error(PC_ENOMEM, "JSON");
	free(s);
	json_decref(root);
	return rc ? cli_fail(rc, json_path) : CLI_EXIT_OK;
}

/* the methods of --method NAME|all|colour, the baseline among them (*base): bilinear, or
 * bayer-first for colour-polarization methods (scored on colour scenes) */
static int methods_of(const char *arg, pc_demosaic_method *methods, size_t *n,
                      pc_demosaic_method *base)
{
	*n = 0;
	const bool colour = !strcmp(arg, "colour");
	*base = colour ? PC_DM_BAYER_FIRST : PC_DM_BILINEAR;
	if (colour || !strcmp(arg, "all")) {
		for (int k = 0; k < PC_DM_COUNT; k++) {
			const pc_demosaic_method_info *mi =
			    pc_demosaic_method_get((pc_demosaic_method)k);
			bool want =
			    colour
			        ? (mi->flags & PC_DMF_COLOR) &&
			              !(mi->flags & PC_DMF_REFERENCE_ONLY) && k != PC_DM_BAYER_FIRST
			        : (mi->flags & PC_DMF_MONO) && !(mi->flags & PC_DMF_HALF_RES);
			if (want)
				methods[(*n)++] = (pc_demosaic_method)k;
		}
		if (colour)
			methods[(*n)++] = PC_DM_BAYER_FIRST;
		return CLI_EXIT_OK;
	}
	int rc = pc_demosaic_method_from_name(arg, &methods[0]);
	if (rc)
		return cli_fail(rc, "--method");
	*n = 1;
	*base = pc_demosaic_method_get(methods[0])->flags & PC_DMF_MONO ? PC_DM_BILINEAR
	                                                                : PC_DM_BAYER_FIRST;
	if (methods[0] != *base) /* the baseline, always */
		methods[(*n)++] = *base;
	return CLI_EXIT_OK;
}

/* the evaluation and its report */
static int run(const char *const *dirs, size_t ndirs, const char *method_arg, const char *json_path,
               bool reference)
{
	pc_demosaic_method methods[PC_DM_COUNT];
	size_t nmeth;
	pc_demosaic_method base;
	int status = methods_of(method_arg, methods, &nmeth, &base);
	if (status)
		return status;
	pc_eval_result *res = calloc(ndirs * nmeth, sizeof *res);
	if (!res)
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	cli_progress bar = {0};
	pc_demosaic_opts o = {0, reference, 0};
	int rc = pc_sim_eval_cases(dirs, ndirs, methods, nmeth, &o, 0,
	                           &(pc_progress){cli_progress_fn, &bar}, res);
	cli_progress_end(&bar);
	if (rc) {
		free(res);
		return cli_fail(rc, NULL);
	}
	size_t nres = ndirs * nmeth;
	json_t *jd =
	    report(json_path && !strcmp(json_path, "-") ? stderr : stdout, res, nres, base);
	if (json_path)
		status = write_json(json_path, res, nres, reference, jd);
	else
		json_decref(jd);
	free(res);
	return status;
}

/* Appends the paths matching a glob pattern (the stress scenes, the datasets' scenes), in
 * order; -1 without memory. */
static int add_glob(const char *pattern, char ***list, size_t *n)
{
	glob_t g;
	int r = glob(pattern, 0, NULL, &g);
	if (r == GLOB_NOMATCH)
		return 0;
	if (r)
		return -1;
	char **l = realloc(*list, sizeof *l * (*n + g.gl_pathc));
	if (!l) {
		globfree(&g);
		return -1;
	}
	*list = l;
	for (size_t i = 0; i < g.gl_pathc; i++)
		if ((l[*n] = strdup(g.gl_pathv[i])))
			(*n)++;
	globfree(&g);
	return 0;
}

int cli_cmd_eval(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	const char *method_arg = "all", *json_path = NULL, *data_dir = getenv("POLARCAM_DATA");
	bool reference = false, data_given = false, overwrite = false;
	char **dirs = NULL;
	size_t ndirs = 0;
	int status = CLI_EXIT_OK;
	for (int i = 1; i < argc && status == CLI_EXIT_OK; i++) {
		if (!strcmp(argv[i], "--method") && i + 1 < argc) {
			method_arg = argv[++i];
		} else if (!strcmp(argv[i], "--json") && i + 1 < argc) {
			json_path = argv[++i];
		} else if (!strcmp(argv[i], "--reference")) {
			reference = true;
		} else if (!strcmp(argv[i], "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(argv[i], "--stress") && i + 1 < argc) {
			char pat[4096];
			snprintf(pat, sizeof pat, "%s/*.json", argv[++i]);
			size_t before = ndirs;
			if (add_glob(pat, &dirs, &ndirs))
				status = cli_error(CLI_EXIT_FAILURE, "--stress %s: out of memory",
				                   argv[i]);
			else if (ndirs == before)
				status = cli_error(CLI_EXIT_USAGE,
				                   "--stress %s: no scene files (*.json) "
				                   "there",
				                   argv[i]);
		} else if (!strcmp(argv[i], "--data") && i + 1 < argc) {
			data_dir = argv[++i];
			data_given = true;
		} else if (argv[i][0] == '-' && argv[i][1]) {
			status = cli_error(CLI_EXIT_USAGE,
			                   "unknown or incomplete option '%s' (see "
			                   "polarcam eval --help)",
			                   argv[i]);
		} else {
			char **l = realloc(dirs, sizeof *l * (ndirs + 1));
			if (!l || !(l[ndirs] = strdup(argv[i]))) {
				if (l)
					dirs = l;
				status = cli_error(CLI_EXIT_FAILURE, "out of memory");
				break;
			}
			dirs = l;
			ndirs++;
		}
	}
	if (status == CLI_EXIT_OK && data_dir && *data_dir) {
		char pat[4096];
		snprintf(pat, sizeof pat, "%s/gt/*/*", data_dir);
		size_t before = ndirs;
		if (add_glob(pat, &dirs, &ndirs))
			status = cli_error(CLI_EXIT_FAILURE, "out of memory");
		else if (ndirs == before)
			cli_warn("%s/gt: no public-dataset scenes there; %s", data_dir,
			         data_given ? "none added" : "skipped ($POLARCAM_DATA)");
	}
	if (status == CLI_EXIT_OK && !ndirs) {
		usage(stderr);
		status = cli_error(CLI_EXIT_USAGE, "no TRUTH_DIR or SCENE.json given");
	} else if (status == CLI_EXIT_OK && json_path && strcmp(json_path, "-")) {
		int rc = pc_output_check(json_path, overwrite ? PC_OUT_OVERWRITE : 0, false);
		if (rc)
			status = cli_fail(rc, NULL);
	}
	if (status == CLI_EXIT_OK && cli_parse_only()) {
		for (size_t d = 0; d < ndirs; d++)
			free(dirs[d]);
		free(dirs);
		return CLI_EXIT_OK;
	}
	if (status == CLI_EXIT_OK)
		status = run((const char *const *)dirs, ndirs, method_arg, json_path, reference);
	for (size_t d = 0; d < ndirs; d++)
		free(dirs[d]);
	free(dirs);
	return status;
}
