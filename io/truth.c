/* Ground-truth directories for the evaluation protocol, and methods scored on them. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/io.h"

static const char *const exts[] = {".tif", ".tiff", ".png", ".bmp", ".npy",
                                   ".TIF", ".TIFF", ".PNG", ".BMP"};

int pc_truth_load(const char *dir, pc_eval_truth *t)
{
	static const char *names[4] = {"0", "45", "90", "135"};
	memset(t, 0, sizeof *t);
	struct stat st;
	if (!dir || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
		return pc_error(PC_ENOENT, "%s: not a directory", dir ? dir : "");
	pc_view v[4];
	memset(v, 0, sizeof v);
	int rc = 0;
	for (int c = 0; c < 4 && !rc; c++) {
		char path[4096];
		int found = 0;
		for (size_t e = 0; e < sizeof exts / sizeof exts[0] && !found; e++) {
			snprintf(path, sizeof path, "%s/%s%s", dir, names[c], exts[e]);
			found = stat(path, &st) == 0 && S_ISREG(st.st_mode);
		}
		if (!found) {
			rc = pc_error(PC_ENOENT,
			              "%s: no analyser image '%s' (expected %s.tif, .png, "
			              ".bmp or .npy)",
			              dir, names[c], names[c]);
			break;
		}
		rc = pc_image_read(path, NULL, &v[c], NULL);
	}
	if (!rc) {
		rc = pc_eval_truth_from_views(v, t);
		if (rc)
			pc_error_prefix(rc, "%s: ", dir);
	}
	for (int c = 0; c < 4; c++)
		pc_view_free(&v[c]);
	return rc;
}

void pc_truth_dataset(const char *dir, char *buf, size_t size)
{
	size_t n = strlen(dir);
	while (n > 1 && dir[n - 1] == '/')
		n--;
	size_t end = n;
	while (end > 0 && dir[end - 1] != '/')
		end--; /* end: start of the scene name */
	if (end == 0) {
		snprintf(buf, size, ".");
		return;
	}
	size_t pe = end - 1; /* the slash before the scene */
	while (pe > 0 && dir[pe - 1] == '/')
		pe--;
	size_t ps = pe;
	while (ps > 0 && dir[ps - 1] != '/')
		ps--;
	if (pe == ps)
		snprintf(buf, size, "%s", pe == 0 ? "/" : ".");
	else
		snprintf(buf, size, "%.*s", (int)(pe - ps), dir + ps);
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int pc_eval_dirs(const char *const *dirs, size_t ndirs, const pc_demosaic_method *methods,
                 size_t nmeth, const pc_demosaic_opts *opts, const pc_progress *progress,
                 pc_eval_result *res)
{
	size_t nres = 0;
	for (size_t d = 0; d < ndirs; d++) {
		pc_eval_truth t;
		int rc = pc_truth_load(dirs[d], &t);
		if (rc) /* the detail names the directory */
			return rc;
		pc_eval_pattern pat;
		if ((rc = pc_eval_truth_pattern(&t, &pat))) {
			pc_eval_truth_free(&t);
			return pc_error_prefix(rc, "%s: ", dirs[d]);
		}
		for (size_t k = 0; k < nmeth; k++) {
			pc_eval_result *r = &res[nres];
			r->truth_pattern = pat;
			r->scene = dirs[d];
			pc_truth_dataset(dirs[d], r->dataset, sizeof r->dataset);
			r->method = methods[k];
			double t0 = now_s();
			rc = pc_eval_method(&t, methods[k], opts, &r->m);
			r->seconds = now_s() - t0;
			if (rc) {
				pc_eval_truth_free(&t);
				return pc_error_prefix(rc, "%s: ", dirs[d]);
			}
			nres++;
			pc_progress_report(progress, "eval", nres, ndirs * nmeth);
		}
		pc_eval_truth_free(&t);
	}
	return 0;
}

int pc_eval_dataset_mean(const pc_eval_result *r, size_t n, const char *dataset,
                         pc_demosaic_method meth, pc_eval_metrics *out)
{
	memset(out, 0, sizeof *out);
	int count = 0;
	for (size_t i = 0; i < n; i++) {
		if (r[i].method != meth || strcmp(r[i].dataset, dataset))
			continue;
		const double *s = &r[i].m.psnr_i;
		double *d = &out->psnr_i;
		for (size_t k = 0; k < sizeof *out / sizeof(double); k++)
			d[k] += s[k];
		count++;
	}
	if (count)
		for (size_t k = 0; k < sizeof *out / sizeof(double); k++)
			(&out->psnr_i)[k] /= count;
	return count;
}

int pc_eval_dataset_gain(const pc_eval_result *r, size_t n, const char *dataset,
                         pc_demosaic_method meth, pc_demosaic_method base, pc_eval_gain *g)
{
	memset(g, 0, sizeof *g);
	g->s0_worst = g->dolp_worst = INFINITY;
	int cnt = 0;
	for (size_t i = 0; i < n; i++) {
		if (r[i].method != meth || strcmp(r[i].dataset, dataset))
			continue;
		for (size_t j = 0; j < n; j++) {
			if (r[j].method != base || strcmp(r[j].scene, r[i].scene))
				continue;
			double ds = r[i].m.psnr_s0 - r[j].m.psnr_s0;
			double dd = r[i].m.psnr_dolp - r[j].m.psnr_dolp;
			g->s0_mean += ds;
			g->dolp_mean += dd;
			if (ds < g->s0_worst) {
				g->s0_worst = ds;
				g->s0_worst_scene = r[i].scene;
			}
			if (dd < g->dolp_worst) {
				g->dolp_worst = dd;
				g->dolp_worst_scene = r[i].scene;
			}
			cnt++;
			break;
		}
	}
	if (!cnt) {
		g->s0_worst = g->dolp_worst = NAN;
		return 0;
	}
	g->s0_mean /= cnt;
	g->dolp_mean /= cnt;
	return cnt;
}
