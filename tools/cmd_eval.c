/* polarcam eval TRUTH_DIR... [--method NAME|all]: score demosaicking methods against ground
 * truth with the frozen protocol (polarcam/eval.h). */
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

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam eval TRUTH_DIR... [--method NAME|all] [--json PATH|-] [--reference]\n"
		"\n"
		"Scores demosaicking methods against ground truth with the frozen protocol of\n"
		"docs/evaluation.md: the four analyser images normalised by their container's\n"
		"full scale, cropped to even size, mosaicked with the Sony layout [90 45; 135 0],\n"
		"demosaicked, and compared outside a 15-pixel border: PSNR (dB, peak 1) of the four\n"
		"I channels (mean), S0/2, (S1+1)/2, (S2+1)/2 and DoLP; AoLP RMSE in degrees (wrapped\n"
		"to [0, 90]) and its DoLP-weighted version.\n"
		"\n"
		"Each TRUTH_DIR holds the analyser images 0, 45, 90 and 135 (.tif/.tiff, .png, .bmp or\n"
		".npy). Results are per scene and, per dataset (the directory above the scenes), the\n"
		"mean over its scenes; datasets are never pooled.\n"
		"\n"
		"options:\n"
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

int cmd_eval(int argc, char **argv)
{
	if (pc_cli_wants_help(argc, argv)) {
		usage(stdout);
		return PC_EXIT_OK;
	}
	const char *method_arg = "all", *json_path = NULL;
	bool reference = false;
	const char **dirs = calloc((size_t)argc, sizeof *dirs);
	size_t ndirs = 0;
	if (!dirs)
		return pc_cli_error(PC_EXIT_FAILURE, "out of memory");
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--method") && i + 1 < argc) {
			method_arg = argv[++i];
		} else if (!strcmp(argv[i], "--json") && i + 1 < argc) {
			json_path = argv[++i];
		} else if (!strcmp(argv[i], "--reference")) {
			reference = true;
		} else if (argv[i][0] == '-' && argv[i][1]) {
			free(dirs);
			return pc_cli_error(PC_EXIT_USAGE, "unknown or incomplete option '%s' (see "
							   "polarcam eval --help)", argv[i]);
		} else {
			dirs[ndirs++] = argv[i];
		}
	}
	if (!ndirs) {
		free(dirs);
		usage(stderr);
		return pc_cli_error(PC_EXIT_USAGE, "no TRUTH_DIR given");
	}
	pc_demosaic_method methods[PC_DM_COUNT];
	size_t nmeth = 0;
	if (!strcmp(method_arg, "all")) {
		for (int k = 0; k < PC_DM_COUNT; k++) {
			const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
			if ((mi->flags & PC_DMF_MONO) && !(mi->flags & PC_DMF_HALF_RES))
				methods[nmeth++] = (pc_demosaic_method)k;
		}
	} else {
		int rc = pc_demosaic_method_from_name(method_arg, &methods[0]);
		if (rc) {
			free(dirs);
			return pc_cli_fail(rc, "--method");
		}
		if (!(pc_demosaic_method_get(methods[0])->flags & PC_DMF_MONO)) {
			free(dirs);
			return pc_cli_error(PC_EXIT_USAGE, "--method %s: the protocol mosaics with the "
							   "monochrome Sony layout; this method needs a "
							   "colour-polarization mosaic", method_arg);
		}
		nmeth = 1;
	}
	result *res = calloc(ndirs * nmeth, sizeof *res);
	size_t nres = 0;
	int status = PC_EXIT_OK;
	pc_progress prog;
	pc_progress_begin(&prog, "eval", ndirs * nmeth);
	for (size_t d = 0; d < ndirs && status == PC_EXIT_OK; d++) {
		pc_eval_truth t;
		int rc = pc_truth_load(dirs[d], &t);
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
			rc = pc_eval_method(&t, methods[k], &o, &r->m);
			r->seconds = pc_cli_now() - t0;
			if (rc) {
				status = pc_cli_fail(rc, dirs[d]);
				break;
			}
			nres++;
			pc_progress_update(&prog, nres);
		}
		pc_eval_truth_free(&t);
	}
	pc_progress_end(&prog);
	if (status != PC_EXIT_OK) {
		free(res);
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
		const char *sc = strrchr(res[i].scene, '/');
		sc = sc && sc[1] ? sc + 1 : res[i].scene;
		fprintf(tf, "%-28.28s %-10s %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f %8.3f\n", sc,
			pc_demosaic_method_get(res[i].method)->name, m->psnr_i, m->psnr_s0, m->psnr_s1,
			m->psnr_s2, m->psnr_dolp, m->aolp_rmse_deg, m->aolp_wrmse_deg);
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
		json_array_append_new(jd, o);
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
								  "docs/evaluation.md"));
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
	free(dirs);
	return status;
}
