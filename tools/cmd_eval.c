/* polarcam eval TRUTH_DIR... [--method NAME|all]: score demosaicking methods against ground
 * truth with the frozen protocol (polarcam/eval.h). */
#include <dirent.h>
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
	fprintf(fp,
		"usage: polarcam eval [TRUTH_DIR|SCENE.json]... [--stress DIR] [--data DIR]\n"
		"                     [--method NAME|all] [--json PATH|-] [--reference]\n"
		"\n"
		"Scores demosaicking methods against ground truth with the frozen protocol of\n"
		"../shared/data/README.md: the four analyser images normalised by their container's\n"
		"full scale, cropped to even size, mosaicked with the Sony layout [90 45; 135 0],\n"
		"demosaicked, and compared outside a 15-pixel border: PSNR (dB, peak 1) of the four\n"
		"I channels (mean), S0/2, (S1+1)/2, (S2+1)/2 and DoLP; AoLP RMSE in degrees (wrapped\n"
		"to [0, 90]) and its DoLP-weighted version.\n"
		"\n"
		"Each TRUTH_DIR holds the analyser images 0, 45, 90 and 135 (.tif/.tiff, .png, .bmp or\n"
		".npy). A SCENE.json (docs/scene-format.md; the stress suite in scenes/stress) is\n"
		"rendered with ground truth: its raw frame 0 (with the sensor's noise and analyser\n"
		"errors when the scene declares them) is scored against the noise-free ideal-analyser\n"
		"images, normalised by the ADC's full scale. Results are per scene and, per dataset (the\n"
		"directory above the scenes), the mean over its scenes; datasets are never pooled.\n"
		"Bilinear is always run as the baseline: per dataset and method, the mean gain over\n"
		"bilinear in S0 and DoLP and the worst scene's (with its name) are reported.\n"
		"\n"
		"options:\n"
		"  --stress DIR       add every DIR/*.json scene (the stress suite: scenes/stress)\n"
		"  --data DIR         add every public-dataset scene DIR/gt/*/* (skipped with a note\n"
		"                     when DIR/gt is absent); default $POLARCAM_DATA when set\n"
		"  --method NAME|all  a method of `polarcam demosaic --list` (default: all methods\n"
		"                     for monochrome mosaics)\n"
		"  --json PATH|-      also write the results as JSON to PATH (atomically), or print\n"
		"                     JSON on stdout instead of the table with -\n"
		"  --reference        run the double-precision reference implementations (slow)\n"
		"  -h, --help         this help\n"
		"\n"
		"Exit status: 0 success, 1 failure, 2 bad arguments or unreadable truth.\n");
}

typedef struct result {
	const char *scene;   /* TRUTH_DIR as given */
	char dataset[256];
	pc_demosaic_method method;
	pc_eval_metrics m;
	double seconds;
} result;

static json_t *metrics_json(const pc_eval_metrics *m)
{
	json_t *o = json_object();
	json_object_set_new(o, "psnr_i", pc_json_real(m->psnr_i));
	json_object_set_new(o, "psnr_i_channels", pc_json_vec(m->psnr_i_ch, 4));
	json_object_set_new(o, "psnr_s0", pc_json_real(m->psnr_s0));
	json_object_set_new(o, "psnr_s1", pc_json_real(m->psnr_s1));
	json_object_set_new(o, "psnr_s2", pc_json_real(m->psnr_s2));
	json_object_set_new(o, "psnr_dolp", pc_json_real(m->psnr_dolp));
	json_object_set_new(o, "aolp_rmse_deg", pc_json_real(m->aolp_rmse_deg));
	json_object_set_new(o, "aolp_wrmse_deg", pc_json_real(m->aolp_wrmse_deg));
	return o;
}

static void mean_metrics(const result *r, size_t n, const char *dataset, pc_demosaic_method meth,
			 pc_eval_metrics *out, int *count)
{
	memset(out, 0, sizeof *out);
	*count = 0;
	for (size_t i = 0; i < n; i++) {
		if (r[i].method != meth || strcmp(r[i].dataset, dataset))
			continue;
		const double *s = &r[i].m.psnr_i;
		double *d = &out->psnr_i;
		for (size_t k = 0; k < sizeof *out / sizeof(double); k++)
			d[k] += s[k];
		(*count)++;
	}
	if (*count)
		for (size_t k = 0; k < sizeof *out / sizeof(double); k++)
			(&out->psnr_i)[k] /= *count;
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

/* Appends the paths matching a glob pattern (the stress scenes, the datasets scenes). */
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
		l[(*n)++] = strdup(g.gl_pathv[i]);
	globfree(&g);
	return 0;
}

static int is_scene_file(const char *path)
{
	size_t n = strlen(path);
	return n > 5 && !strcmp(path + n - 5, ".json");
}

/* One evaluation case: a truth directory (mosaicked with the Sony layout) or a scene (rendered
 * with its sensor). */
static int load_case(const char *path, pc_eval_truth *t, pc_view *raw, pc_mosaic *m)
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


typedef struct gain {
	double s0_mean, dolp_mean, s0_worst, dolp_worst;
	const char *s0_worst_scene, *dolp_worst_scene;
} gain;

/* Per-scene gains of meth over bilinear on one dataset: mean and worst (lowest). Non-zero when
 * no scene has both. */
static int gain_vs_bilinear(const result *r, size_t n, const char *dataset,
			    pc_demosaic_method meth, gain *g)
{
	memset(g, 0, sizeof *g);
	g->s0_worst = g->dolp_worst = INFINITY;
	int cnt = 0;
	for (size_t i = 0; i < n; i++) {
		if (r[i].method != meth || strcmp(r[i].dataset, dataset))
			continue;
		for (size_t j = 0; j < n; j++) {
			if (r[j].method != PC_DM_BILINEAR || r[j].scene != r[i].scene)
				continue;
			double ds = r[i].m.psnr_s0 - r[j].m.psnr_s0;
			double dd = r[i].m.psnr_dolp - r[j].m.psnr_dolp;
			g->s0_mean += ds;
			g->dolp_mean += dd;
			if (ds < g->s0_worst) {
				g->s0_worst = ds;
				g->s0_worst_scene = base_name(r[i].scene);
			}
			if (dd < g->dolp_worst) {
				g->dolp_worst = dd;
				g->dolp_worst_scene = base_name(r[i].scene);
			}
			cnt++;
		}
	}
	if (!cnt)
		return -1;
	g->s0_mean /= cnt;
	g->dolp_mean /= cnt;
	return 0;
}

int cmd_eval(int argc, char **argv)
{
	if (pc_cli_wants_help(argc, argv)) {
		usage(stdout);
		return PC_EXIT_OK;
	}
	const char *method_arg = "all", *json_path = NULL, *data_dir = getenv("POLARCAM_DATA");
	bool reference = false, data_given = false;
	char **dirs = NULL;
	size_t ndirs = 0;
	int status = PC_EXIT_OK;
	for (int i = 1; i < argc && status == PC_EXIT_OK; i++) {
		if (!strcmp(argv[i], "--method") && i + 1 < argc) {
			method_arg = argv[++i];
		} else if (!strcmp(argv[i], "--json") && i + 1 < argc) {
			json_path = argv[++i];
		} else if (!strcmp(argv[i], "--reference")) {
			reference = true;
		} else if (!strcmp(argv[i], "--stress") && i + 1 < argc) {
			char pat[4096];
			snprintf(pat, sizeof pat, "%s/*.json", argv[++i]);
			size_t before = ndirs;
			if (add_glob(pat, &dirs, &ndirs))
				status = pc_cli_error(PC_EXIT_FAILURE, "--stress %s: out of memory", argv[i]);
			else if (ndirs == before)
				status = pc_cli_error(PC_EXIT_USAGE, "--stress %s: no scene files (*.json) "
								     "there", argv[i]);
		} else if (!strcmp(argv[i], "--data") && i + 1 < argc) {
			data_dir = argv[++i];
			data_given = true;
		} else if (argv[i][0] == '-' && argv[i][1]) {
			status = pc_cli_error(PC_EXIT_USAGE, "unknown or incomplete option '%s' (see "
							     "polarcam eval --help)", argv[i]);
		} else {
			char **l = realloc(dirs, sizeof *l * (ndirs + 1));
			if (!l) {
				status = pc_cli_error(PC_EXIT_FAILURE, "out of memory");
				break;
			}
			dirs = l;
			dirs[ndirs++] = strdup(argv[i]);
		}
	}
	if (status == PC_EXIT_OK && data_dir && *data_dir) {
		char pat[4096];
		snprintf(pat, sizeof pat, "%s/gt/*/*", data_dir);
		size_t before = ndirs;
		if (add_glob(pat, &dirs, &ndirs))
			status = pc_cli_error(PC_EXIT_FAILURE, "out of memory");
		else if (ndirs == before)
			fprintf(stderr, "polarcam eval: %s/gt: no public-dataset scenes there; %s\n",
				data_dir, data_given ? "none added" : "skipped ($POLARCAM_DATA)");
	}
	if (status == PC_EXIT_OK && !ndirs) {
		usage(stderr);
		status = pc_cli_error(PC_EXIT_USAGE, "no TRUTH_DIR or SCENE.json given");
	}
	pc_demosaic_method methods[PC_DM_COUNT];
	size_t nmeth = 0;
	if (status == PC_EXIT_OK && !strcmp(method_arg, "all")) {
		for (int k = 0; k < PC_DM_COUNT; k++) {
			const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
			if ((mi->flags & PC_DMF_MONO) && !(mi->flags & PC_DMF_HALF_RES))
				methods[nmeth++] = (pc_demosaic_method)k;
		}
	} else if (status == PC_EXIT_OK) {
		int rc = pc_demosaic_method_from_name(method_arg, &methods[0]);
		if (rc)
			status = pc_cli_fail(rc, "--method");
		else if (!(pc_demosaic_method_get(methods[0])->flags & PC_DMF_MONO))
			status = pc_cli_error(PC_EXIT_USAGE, "--method %s: the protocol scores "
							     "monochrome polarizer mosaics; this method "
							     "needs a colour-polarization mosaic", method_arg);
		nmeth = 1;
		if (methods[0] != PC_DM_BILINEAR) /* the baseline, always */
			methods[nmeth++] = PC_DM_BILINEAR;
	}
	result *res = status == PC_EXIT_OK ? calloc(ndirs * nmeth, sizeof *res) : NULL;
	size_t nres = 0;
	if (status == PC_EXIT_OK && !res)
		status = pc_cli_error(PC_EXIT_FAILURE, "out of memory");
	pc_progress prog;
	pc_progress_begin(&prog, "eval", ndirs * nmeth);
	for (size_t d = 0; d < ndirs && status == PC_EXIT_OK; d++) {
		pc_eval_truth t;
		pc_view raw;
		pc_mosaic mo;
		int rc = load_case(dirs[d], &t, &raw, &mo);
		if (rc) {
			status = pc_cli_fail(rc, dirs[d]);
			break;
		}
		for (size_t k = 0; k < nmeth; k++) {
			result *r = &res[nres];
			r->scene = dirs[d];
			pc_truth_dataset(dirs[d], r->dataset, sizeof r->dataset);
			r->method = methods[k];
			pc_demosaic_opts o = { 0, reference, 0 };
			double t0 = pc_cli_now();
			rc = pc_eval_method_raw(&t, &raw, &mo, methods[k], &o, &r->m);
			r->seconds = pc_cli_now() - t0;
			if (rc) {
				status = pc_cli_fail(rc, dirs[d]);
				break;
			}
			nres++;
			pc_progress_update(&prog, nres);
		}
		pc_eval_truth_free(&t);
		pc_view_free(&raw);
	}
	pc_progress_end(&prog);
	if (status != PC_EXIT_OK) {
		free(res);
		for (size_t d = 0; d < ndirs; d++)
			free(dirs[d]);
		free(dirs);
		return status;
	}
	int json_stdout = json_path && !strcmp(json_path, "-");
	FILE *tf = json_stdout ? stderr : stdout;
	fprintf(tf, "%-28s %-10s %8s %8s %8s %8s %8s %8s %8s\n", "scene", "method", "I", "S0", "S1",
		"S2", "DoLP", "AoLP", "wAoLP");
	fprintf(tf, "%-28s %-10s %8s %8s %8s %8s %8s %8s %8s\n", "", "", "dB", "dB", "dB", "dB",
		"dB", "deg", "deg");
	for (size_t i = 0; i < nres; i++) {
		const pc_eval_metrics *m = &res[i].m;
		fprintf(tf, "%-28.28s %-10s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n",
			base_name(res[i].scene), pc_demosaic_method_get(res[i].method)->name,
			m->psnr_i, m->psnr_s0, m->psnr_s1, m->psnr_s2, m->psnr_dolp,
			m->aolp_rmse_deg, m->aolp_wrmse_deg);
	}
	/* per-dataset means */
	json_t *jd = json_array();
	for (size_t i = 0; i < nres; i++) {
		int seen = 0;
		for (size_t j = 0; j < i; j++)
			seen |= !strcmp(res[j].dataset, res[i].dataset) && res[j].method == res[i].method;
		if (seen)
			continue;
		pc_eval_metrics mm;
		int cnt;
		mean_metrics(res, nres, res[i].dataset, res[i].method, &mm, &cnt);
		char label[300];
		snprintf(label, sizeof label, "%s (mean of %d)", res[i].dataset, cnt);
		fprintf(tf, "%-28.28s %-10s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", label,
			pc_demosaic_method_get(res[i].method)->name, mm.psnr_i, mm.psnr_s0, mm.psnr_s1,
			mm.psnr_s2, mm.psnr_dolp, mm.aolp_rmse_deg, mm.aolp_wrmse_deg);
		json_t *o = metrics_json(&mm);
		json_object_set_new(o, "dataset", json_string(res[i].dataset));
		json_object_set_new(o, "method", json_string(pc_demosaic_method_get(res[i].method)->name));
		json_object_set_new(o, "scenes", json_integer(cnt));
		gain g;
		if (gain_vs_bilinear(res, nres, res[i].dataset, res[i].method, &g) == 0) {
			json_t *gj = json_object();
			json_object_set_new(gj, "s0_mean", pc_json_real(g.s0_mean));
			json_object_set_new(gj, "dolp_mean", pc_json_real(g.dolp_mean));
			json_object_set_new(gj, "s0_worst", pc_json_real(g.s0_worst));
			json_object_set_new(gj, "s0_worst_scene", json_string(g.s0_worst_scene));
			json_object_set_new(gj, "dolp_worst", pc_json_real(g.dolp_worst));
			json_object_set_new(gj, "dolp_worst_scene", json_string(g.dolp_worst_scene));
			json_object_set_new(o, "gain_over_bilinear_db", gj);
		}
		json_array_append_new(jd, o);
	}
	/* gains over bilinear: mean and worst scene, per dataset */
	fprintf(tf, "\ngain over bilinear (dB), per dataset: mean, and the worst scene\n");
	fprintf(tf, "%-20s %-12s %8s %8s %8s %-20s %8s %-20s\n", "dataset", "method", "S0", "DoLP",
		"worst S0", "(scene)", "worstDoLP", "(scene)");
	for (size_t i = 0; i < nres; i++) {
		int seen = 0;
		for (size_t j = 0; j < i; j++)
			seen |= !strcmp(res[j].dataset, res[i].dataset) && res[j].method == res[i].method;
		gain g;
		if (seen || res[i].method == PC_DM_BILINEAR ||
		    gain_vs_bilinear(res, nres, res[i].dataset, res[i].method, &g))
			continue;
		fprintf(tf, "%-20.20s %-12s %+8.3f %+8.3f %+8.3f %-20.20s %+8.3f %-20.20s\n",
			res[i].dataset, pc_demosaic_method_get(res[i].method)->name, g.s0_mean,
			g.dolp_mean, g.s0_worst, g.s0_worst_scene, g.dolp_worst, g.dolp_worst_scene);
	}
	if (json_path) {
		json_t *root = json_object();
		json_t *js = json_array();
		for (size_t i = 0; i < nres; i++) {
			json_t *o = metrics_json(&res[i].m);
			json_object_set_new(o, "scene", json_string(res[i].scene));
			json_object_set_new(o, "dataset", json_string(res[i].dataset));
			json_object_set_new(o, "method",
					    json_string(pc_demosaic_method_get(res[i].method)->name));
			json_object_set_new(o, "seconds", pc_json_real(res[i].seconds));
			json_array_append_new(js, o);
		}
		json_object_set_new(root, "protocol", json_string("polarcam frozen protocol: "
								  "docs/demosaicking.md"));
		json_object_set_new(root, "reference", json_boolean(reference));
		json_object_set_new(root, "scenes", js);
		json_object_set_new(root, "datasets", jd);
		if (json_stdout) {
			pc_cli_print_json(root);
		} else {
			char *s = json_dumps(root, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
			int rc = s ? pc_write_file_atomic(json_path, s, strlen(s))
				   : pc_error(PC_ENOMEM, "JSON");
			free(s);
			json_decref(root);
			if (rc)
				status = pc_cli_fail(rc, json_path);
		}
	} else {
		json_decref(jd);
	}
	free(res);
	for (size_t d = 0; d < ndirs; d++)
		free(dirs[d]);
	free(dirs);
	return status;
}
