/* polarcam bench colour: colour-polarization demosaicking, per scene and worst scene against
 * bayer-first, and its time against the monochrome bilinear in the same run.
 *
 * There is no colour-polarization ground truth in the data (docs/evaluation.md), so colour
 * scenes are made from the monochrome ground truth: I_{k,c}(x, y) = g_k(x, y)·I_c(x, y), the
 * IMX250MYR mosaic of it in 16-bit containers, and each colour's four channels scored with the
 * frozen protocol (polarcam/eval.h), the three colours' metrics averaged. Two colourings:
 *   smooth   slowly varying gains per colour (the colour track of polarcam bench demosaic);
 *   patches  piecewise-constant hues on 37×29-pixel patches (eight colours, gains 0.08..1):
 *            hue edges that do not follow the scene's intensity edges, where a method that
 *            assumes colour ratios vary slowly is wrong. */
#include <glob.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/frame.h"
#include "polarcam/io.h"
#include "polarcam/parallel.h"
#include "polarcam/sim.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { TRACK_SMOOTH, TRACK_PATCHES, NTRACKS };
static const char *const track_name[NTRACKS] = {"smooth", "patches"};

static double gain(int track, unsigned k, uint32_t x, uint32_t y)
{
	if (track == TRACK_SMOOTH) {
		const double kx[3] = {97, 131, 173}, ky[3] = {151, 89, 113},
		             base[3] = {0.55, 0.7, 0.4};
		return base[k] + 0.3 * sin(2 * M_PI * x / kx[k] + k) * cos(2 * M_PI * y / ky[k]);
	}
	static const double pal[8][3] = {{1.0, 0.35, 0.1}, {0.2, 0.9, 0.25}, {0.15, 0.3, 1.0},
	                                 {0.9, 0.85, 0.2}, {0.8, 0.2, 0.75}, {0.25, 0.8, 0.9},
	                                 {0.6, 0.6, 0.6},  {0.08, 0.12, 0.1}};
	uint32_t px = x / 37, py = y / 29;
	uint32_t hsh = (px * 73856093u) ^ (py * 19349663u);
	hsh ^= hsh >> 13;
	hsh *= 0x5bd1e995u;
	hsh ^= hsh >> 15;
	return pal[hsh & 7][k];
}

/* The colour raw of truth t under a colouring, 16-bit containers (full scale 65535), and the
 * three colours' truths (value / 65535 of the rounded raw-scale values). */
static int make_case(const pc_eval_truth *t, int track, pc_view *raw, pc_eval_truth tk[3])
{
	pc_mosaic m = pc_mosaic_imx250myr();
	uint32_t w = t->width, h = t->height;
	size_t n = (size_t)w * h;
	int rc = pc_view_alloc(raw, PC_FMT_MONO16, w, h, 0);
	for (int k = 0; k < 3; k++) {
		tk[k] = *t;
		tk[k].full_scale = 65535; /* the raw's container */
		for (int c = 0; c < 4; c++)
			tk[k].ch[c] = rc ? NULL : malloc(sizeof(double) * n);
	}
	for (int k = 0; k < 3 && !rc; k++)
		for (int c = 0; c < 4; c++)
			if (!tk[k].ch[c])
				rc = pc_error(PC_ENOMEM, "colour case %ux%u", w, h);
	if (rc)
		return rc;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			for (unsigned k = 0; k < 3; k++) {
				double g = gain(track, k, x, y);
				for (int c = 0; c < 4; c++)
					tk[k].ch[c][i] =
					    (double)lround(g * t->ch[c][i] * 65535) / 65535;
			}
			unsigned k = pc_mosaic_color(&m, x, y) - PC_CFA_R;
			PC_ROW(raw, uint16_t, y)
			[x] = (uint16_t)lround(tk[k].ch[pc_mosaic_channel(&m, x, y)][i] * 65535);
		}
	return 0;
}

static void free_case(pc_view *raw, pc_eval_truth tk[3])
{
	pc_view_free(raw);
	for (int k = 0; k < 3; k++)
		for (int c = 0; c < 4; c++)
			free(tk[k].ch[c]);
}

static int score(const pc_view *raw, const pc_eval_truth tk[3], pc_demosaic_method meth,
                 int threads, bool reference, pc_eval_metrics *mean)
{
	pc_mosaic m = pc_mosaic_imx250myr();
	pc_demosaic_opts op = {threads, reference, 65535};
	return pc_eval_method_raw_colour(tk, raw, &m, meth, &op, mean);
}

#define MAXSC 64

/* The per-scene table of gains over bayer-first (method bf of ms), S0 / DoLP PSNR, its mean
 * and worst scene; returns the scenes' JSON. */
static json_t *gain_table(char *const *sn, size_t ns, double (*s0)[PC_DM_COUNT],
                          double (*dl)[PC_DM_COUNT], const pc_demosaic_method *ms, size_t nm,
                          size_t bf)
{
	printf("gain over bayer-first in S0 / DoLP PSNR, dB (%zu scenes)\n%-26s %15s", ns, "scene",
	       "bayer-first");
	for (size_t q = 0; q < nm; q++)
		if (q != bf)
			printf(" %15s", pc_demosaic_method_get(ms[q])->name);
	printf("\n");
	double mean_s[PC_DM_COUNT] = {0}, mean_d[PC_DM_COUNT] = {0};
	double worst_s[PC_DM_COUNT], worst_d[PC_DM_COUNT];
	size_t ws[PC_DM_COUNT] = {0}, wd[PC_DM_COUNT] = {0};
	json_t *jt = json_array();
	for (size_t q = 0; q < nm; q++)
		worst_s[q] = worst_d[q] = INFINITY;
	for (size_t s = 0; s < ns; s++) {
		printf("%-26s %7.2f/%7.2f", sn[s], s0[s][bf], dl[s][bf]);
		json_t *js = json_object();
		json_object_set_new(js, "scene", json_string(sn[s]));
		for (size_t q = 0; q < nm; q++) {
			double gs = s0[s][q] - s0[s][bf], gd = dl[s][q] - dl[s][bf];
			mean_s[q] += gs / (double)ns;
			mean_d[q] += gd / (double)ns;
			if (gs < worst_s[q])
				worst_s[q] = gs, ws[q] = s;
			if (gd < worst_d[q])
				worst_d[q] = gd, wd[q] = s;
			json_t *jm = json_object();
			json_object_set_new(jm, "s0_db", bench_json_real(s0[s][q]));
			json_object_set_new(jm, "dolp_db", bench_json_real(dl[s][q]));
			json_object_set_new(js, pc_demosaic_method_get(ms[q])->name, jm);
			if (q != bf)
				printf(" %+7.2f/%+7.2f", gs, gd);
		}
		json_array_append_new(jt, js);
		printf("\n");
	}
	printf("%-26s %15s", "mean", "");
	for (size_t q = 0; q < nm; q++)
		if (q != bf)
			printf(" %+7.2f/%+7.2f", mean_s[q], mean_d[q]);
	printf("\n%-26s %15s", "worst scene", "");
	for (size_t q = 0; q < nm; q++)
		if (q != bf)
			printf(" %+7.2f/%+7.2f", worst_s[q], worst_d[q]);
	printf("\n");
	for (size_t q = 0; q < nm; q++)
		if (q != bf)
			printf("  %s: worst S0 %s, worst DoLP %s\n",
			       pc_demosaic_method_get(ms[q])->name, sn[ws[q]], sn[wd[q]]);
	printf("\n");
	return jt;
}

/* The colour stress suite (scenes/stress/colour): every .json scene of the directory rendered
 * with its colour sensor and per-colour ground truth and scored by the library (pc_sim_eval_cases);
 * per scene the gains over bayer-first. Returns the scenes' JSON, NULL when skipped. */
static json_t *stress_track(const pc_bench_host *host, const char *dir,
                            const pc_demosaic_method *ms, size_t nm, size_t bf, int threads,
                            bool reference)
{
	char pat[4096];
	snprintf(pat, sizeof pat, "%s/*.json", dir);
	glob_t g;
	if (glob(pat, 0, NULL, &g)) {
		printf("colour stress suite: no scenes in %s: skipped\n\n", dir);
		return NULL;
	}
	size_t ns = g.gl_pathc < MAXSC ? g.gl_pathc : MAXSC;
	pc_eval_result *res = calloc(ns * nm, sizeof *res);
	double(*s0)[PC_DM_COUNT] = calloc(ns, sizeof *s0),
	(*dl)[PC_DM_COUNT] = calloc(ns, sizeof *dl);
	char **sn = calloc(ns, sizeof *sn);
	pc_demosaic_opts o = {threads, reference, 0};
	int rc = res && s0 && dl && sn ? pc_sim_eval_cases((const char *const *)g.gl_pathv, ns, ms,
	                                                   nm, &o, threads, &host->progress, res)
	                               : pc_error(PC_ENOMEM, "colour stress suite");
	host->progress_end(host->progress.user);
	json_t *jt = NULL;
	if (rc) {
		host->warn("colour stress suite: %s", pc_error_detail());
	} else {
		for (size_t d = 0; d < ns; d++) {
			const char *b = strrchr(g.gl_pathv[d], '/');
			sn[d] = (char *)(b ? b + 1 : g.gl_pathv[d]);
			for (size_t q = 0; q < nm; q++) {
				s0[d][q] = res[d * nm + q].m.psnr_s0;
				dl[d][q] = res[d * nm + q].m.psnr_dolp;
			}
		}
		printf("colour stress suite (%s): ", dir);
		jt = gain_table(sn, ns, s0, dl, ms, nm, bf);
	}
	free(res);
	free(s0);
	free(dl);
	free(sn);
	globfree(&g);
	return jt;
}

int pc_bench_colour(const pc_bench_host *host, int argc, char **argv)
{
	if (bench_wants_help(argc, argv)) {
		printf(
		    "usage: polarcam bench colour [DATA_DIR] [--stress DIR] [--reps N] [--threads "
		    "N]\n"
		    "                             [--methods A,B] [--reference] [--no-time] "
		    "[--json]\n\n"
		    "Colour-polarization methods (IMX250MYR) on colourised ground truth: every "
		    "scene of\nDATA_DIR/gt (default $POLARCAM_DATA) under two colourings, "
		    "'smooth' (slowly varying\ngains) and 'patches' (piecewise-constant hues, "
		    "edges unrelated to the scene's);\nper scene the S0 and DoLP PSNR gain "
		    "over bayer-first, the mean and the worst scene.\nThe colour stress suite: "
		    "every scene of --stress DIR (default $POLARCAM_STRESS_COLOUR or\n"
		    "./scenes/stress/colour; skipped when absent) rendered with per-colour ground "
		    "truth,\nthe same gains.\nTime per 2448x2048 "
		    "frame (median of N round-robin runs, default 5) as a multiple of\nthe "
		    "monochrome bilinear's in the same run, wall and process CPU time.\n--methods "
		    "names the colour methods to run (bayer-first always runs);\n--reference "
		    "scores the double-precision references; "
		    "--no-time skips the timing.\n");
		return PC_BENCH_OK;
	}
	const char *data = getenv("POLARCAM_DATA");
	long reps = 5, threads = 0;
	bool json = false, reference = false, notime = false;
	const char *only = NULL, *stress = getenv("POLARCAM_STRESS_COLOUR");
	if (!stress)
		stress = "scenes/stress/colour";
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
			if (host->parse_long("--reps", argv[++i], 1, 1000, &reps))
				return host->fail(PC_EINVAL, "--reps");
		} else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
			if (host->parse_long("--threads", argv[++i], 0, 1024, &threads))
				return host->fail(PC_EINVAL, "--threads");
		} else if (!strcmp(argv[i], "--json")) {
			json = true;
		} else if (!strcmp(argv[i], "--stress") && i + 1 < argc) {
			stress = argv[++i];
		} else if (!strcmp(argv[i], "--methods") && i + 1 < argc) {
			only = argv[++i];
		} else if (!strcmp(argv[i], "--reference")) {
			reference = true;
		} else if (!strcmp(argv[i], "--no-time")) {
			notime = true;
		} else if (argv[i][0] != '-') {
			data = argv[i];
		} else {
			return host->error(PC_BENCH_USAGE, "bench colour: unknown option '%s'",
			                   argv[i]);
		}
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	pc_demosaic_method ms[PC_DM_COUNT];
	size_t nm = 0, bf = 0;
	for (int k = 0; k < PC_DM_COUNT; k++) {
		const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
		size_t len = strlen(mi->name);
		const char *hit = only ? strstr(only, mi->name) : NULL;
		bool listed =
		    hit && (hit == only || hit[-1] == ',') && (hit[len] == ',' || hit[len] == 0);
		if ((mi->flags & PC_DMF_COLOR) &&
		    (!(mi->flags & PC_DMF_REFERENCE_ONLY) || listed) &&
		    (!only || listed || k == PC_DM_BAYER_FIRST)) {
			if (k == PC_DM_BAYER_FIRST)
				bf = nm;
			ms[nm++] = (pc_demosaic_method)k;
		}
	}
	json_t *root = json_object(), *jtracks = json_object();
	/* ---- accuracy ---- */
	if (data) {
		static const char *const datasets[] = {"lapray-nir", "zhang"};
		/* each scene read once, scored under both colourings */
		static double s0[NTRACKS][MAXSC][PC_DM_COUNT], dl[NTRACKS][MAXSC][PC_DM_COUNT];
		char *sn[MAXSC];
		size_t ns = 0;
		for (size_t d = 0; d < 2; d++) {
			char dpath[4096];
			snprintf(dpath, sizeof dpath, "%s/gt/%s", data, datasets[d]);
			char **names = NULL;
			size_t nn = bench_list_dir(dpath, &names);
			for (size_t s = 0; s < nn; s++) {
				char sp[8192];
				snprintf(sp, sizeof sp, "%s/%s", dpath, names[s]);
				pc_eval_truth t;
				int rc = ns < MAXSC ? pc_truth_load(sp, &t) : PC_ENOMEM;
				if (rc) {
					host->warn("%s: %s", sp, pc_error_detail());
					continue;
				}
				for (int tr = 0; tr < NTRACKS && !rc; tr++) {
					pc_view raw;
					pc_eval_truth tk[3];
					rc = make_case(&t, tr, &raw, tk);
					for (size_t q = 0; q < nm && !rc; q++) {
						pc_eval_metrics mm = {0};
						rc = score(&raw, tk, ms[q], (int)threads, reference,
						           &mm);
						s0[tr][ns][q] = mm.psnr_s0;
						dl[tr][ns][q] = mm.psnr_dolp;
					}
					free_case(&raw, tk);
				}
				pc_eval_truth_free(&t);
				if (rc) {
					host->warn("%s: %s", sp, pc_error_detail());
					continue;
				}
				size_t len = strlen(datasets[d]) + strlen(names[s]) + 2;
				sn[ns] = malloc(len);
				if (sn[ns])
					snprintf(sn[ns], len, "%s/%s", datasets[d], names[s]);
				if (sn[ns])
					ns++;
			}
			for (size_t s = 0; s < nn; s++)
				free(names[s]);
			free(names);
		}
		for (int tr = 0; tr < NTRACKS && ns; tr++) {
			printf("colouring '%s': ", track_name[tr]);
			json_t *jt = gain_table(sn, ns, s0[tr], dl[tr], ms, nm, bf);
			json_object_set_new(jtracks, track_name[tr], jt);
		}
		for (size_t s = 0; s < ns; s++)
			free(sn[s]);
	} else {
		printf("no data directory (DATA_DIR or POLARCAM_DATA): accuracy skipped\n\n");
	}
	json_t *jst = stress_track(host, stress, ms, nm, bf, (int)threads, reference);
	if (jst)
		json_object_set_new(jtracks, "stress", jst);
	json_object_set_new(root, "colourings", jtracks);
	if (notime) {
		if (json)
			host->print_json(root);
		else
			json_decref(root);
		return PC_BENCH_OK;
	}
	/* ---- time: a 2448x2048 frame, round robin, monochrome bilinear as the baseline ---- */
	const uint32_t FW = 2448, FH = 2048;
	pc_view raw;
	int rc = pc_view_alloc(&raw, PC_FMT_MONO12, FW, FH, 0);
	float *buf = rc ? NULL : malloc(sizeof(float) * (size_t)FW * FH * 12);
	if (rc || !buf) {
		pc_view_free(&raw);
		return host->fail(rc ? rc : PC_ENOMEM, "bench colour: frame");
	}
	uint32_t st = 12345;
	for (uint32_t y = 0; y < FH; y++)
		for (uint32_t x = 0; x < FW; x++) {
			st = st * 1664525u + 1013904223u;
			double v = 1800 + 1200 * sin(x * 0.013) * cos(y * 0.021) + (st >> 24) * 2.0;
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)v;
		}
	pc_fplane o[12];
	pc_fplanes_separate(buf, FW, FH, 12, o);
	pc_mosaic mono = pc_mosaic_imx250mzr(), col = pc_mosaic_imx250myr();
	pc_demosaic_method tm[PC_DM_COUNT + 1];
	size_t nt = 0;
	tm[nt++] = PC_DM_BILINEAR;
	for (size_t q = 0; q < nm; q++)
		tm[nt++] = ms[q];
	double *wall = calloc(nt * (size_t)reps, sizeof *wall);
	double *cpu = calloc(nt * (size_t)reps, sizeof *cpu);
	pc_demosaic_opts op = {(int)threads, false, 0};
	for (size_t q = 0; q < nt && wall && cpu && !rc; q++) /* warm-up */
		rc = pc_demosaic(&raw, q ? &col : &mono, tm[q], &op, o);
	for (long r = 0; r < reps && wall && cpu && !rc; r++)
		for (size_t q = 0; q < nt && !rc; q++) {
			double t0 = bench_now(), c0 = bench_cpu_s();
			rc = pc_demosaic(&raw, q ? &col : &mono, tm[q], &op, o);
			wall[q * (size_t)reps + (size_t)r] = 1e3 * (bench_now() - t0);
			cpu[q * (size_t)reps + (size_t)r] = 1e3 * (bench_cpu_s() - c0);
		}
	if (rc || !wall || !cpu) {
		free(wall);
		free(cpu);
		free(buf);
		pc_view_free(&raw);
		return host->fail(rc ? rc : PC_ENOMEM, "bench colour: timing");
	}
	char lavg[128];
	bench_loadavg(lavg, sizeof lavg);
	printf("time per %ux%u frame, %d thread(s), median of %ld round-robin runs "
	       "(/proc/loadavg at the end: %s)\n%-16s %9s %7s %9s %7s\n",
	       FW, FH, threads ? (int)threads : pc_parallel_max_threads(), reps, lavg, "method",
	       "wall ms", "x bil", "cpu ms", "x bil");
	double bw = 0, bc = 0;
	json_t *jtime = json_array();
	for (size_t q = 0; q < nt; q++) {
		qsort(wall + q * (size_t)reps, (size_t)reps, sizeof *wall, bench_cmp_double);
		qsort(cpu + q * (size_t)reps, (size_t)reps, sizeof *cpu, bench_cmp_double);
		double mw = wall[q * (size_t)reps + (size_t)reps / 2],
		       mc = cpu[q * (size_t)reps + (size_t)reps / 2];
		if (q == 0)
			bw = mw, bc = mc;
		const char *name = pc_demosaic_method_get(tm[q])->name;
		printf("%-16s %9.2f %7.2f %9.2f %7.2f\n", q ? name : "bilinear (mono)", mw, mw / bw,
		       mc, mc / bc);
		json_t *j = json_object();
		json_object_set_new(j, "method", json_string(name));
		json_object_set_new(j, "wall_ms", json_real(mw));
		json_object_set_new(j, "cpu_ms", json_real(mc));
		json_object_set_new(j, "x_bilinear_wall", json_real(mw / bw));
		json_object_set_new(j, "x_bilinear_cpu", json_real(mc / bc));
		json_array_append_new(jtime, j);
	}
	json_object_set_new(root, "time", jtime);
	if (json)
		host->print_json(root);
	else
		json_decref(root);
	free(wall);
	free(cpu);
	free(buf);
	pc_view_free(&raw);
	return PC_BENCH_OK;
}
