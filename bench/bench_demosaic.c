/* polarcam bench demosaic: what accuracy costs in time.
 *
 * Accuracy: the frozen protocol (polarcam/eval.h) on every ground-truth dataset under
 * DATA_DIR/gt (mean over each dataset's scenes and each scene with the worst against
 * bilinear, datasets never pooled), for every selected monochrome method, with bilinear as the
 * same-run baseline and our bilinear against the double-precision reference bilinear. Time:
 * per 2448×2048 frame of 12-bit data in 16-bit containers (tiled from a Lapray scene when the
 * data is there), median of repeated runs on warm, pre-faulted buffers, for every selected
 * method (reference-only methods, left out unless asked for, in one run), the full bilinear
 * pipeline (demosaic + Stokes + DoLP + AoLP, float32) and its memory floor (its own bytes streamed
 * with its store kind), a copy of bilinear's input and output bytes and, when OpenCV is built in,
 * OpenCV's bilinear 16-bit Bayer demosaicking of the same frame — all measured in the same run, so
 * that the ratios hold even when the machine is shared. */
#include <glob.h>
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "polarcam/cpu.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/io.h"
#include "polarcam/parallel.h"
#include "polarcam/plot.h"
#include "polarcam/sim.h"
#include "polarcam/stokes.h"
#include "polarcam/version.h"

#ifdef PC_HAVE_OPENCV
int pc_bench_opencv_bayer16(const uint16_t *src, size_t src_stride, uint16_t *dst,
                            size_t dst_stride, int width, int height, int threads, char *err,
                            size_t err_size);
const char *pc_bench_opencv_version(void);
#endif

enum { FW = 2448, FH = 2048 };

typedef struct timing {
	double median_ms, min_ms, cpu_ms; /* wall median and minimum, CPU-time median */
} timing;

static timing summarize(double *t, int n)
{
	qsort(t, (size_t)n, sizeof *t, bench_cmp_double);
	timing r = {1e3 * (n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2])), 1e3 * t[0], NAN};
	return r;
}

/* ---- the timing frame ---- */
static int make_frame(const char *data_dir, pc_view *raw, char *what, size_t what_size)
{
	int rc = pc_view_alloc(raw, PC_FMT_MONO12, FW, FH, 0);
	if (rc)
		return rc;
	pc_eval_truth t;
	char scene[4096];
	snprintf(scene, sizeof scene, "%s/gt/lapray-nir/fabrics", data_dir ? data_dir : "");
	if (data_dir && pc_truth_load(scene, &t) == 0) {
		pc_mosaic m = pc_mosaic_imx250mzr();
		for (uint32_t y = 0; y < FH; y++)
			for (uint32_t x = 0; x < FW; x++) {
				/* tile with the scene's mosaic phase kept (even tile sizes) */
				uint32_t sx = x % t.width, sy = y % t.height;
				double v =
				    t.ch[pc_mosaic_channel(&m, x, y)][(size_t)sy * t.width + sx];
				PC_ROW(raw, uint16_t, y)[x] = (uint16_t)lround(v * 4095.0);
			}
		pc_eval_truth_free(&t);
		snprintf(what, what_size, "Lapray fabrics mosaic tiled to %dx%d, 12-bit", FW, FH);
		return 0;
	}
	uint32_t r = 12345;
	for (uint32_t y = 0; y < FH; y++)
		for (uint32_t x = 0; x < FW; x++) {
			r = r * 1664525u + 1013904223u;
			double v = 2000 + 1500 * sin(0.01 * x) * cos(0.013 * y) + (double)(r >> 27);
			PC_ROW(raw, uint16_t, y)[x] = (uint16_t)v;
		}
	snprintf(what, what_size, "synthetic %dx%d 12-bit frame (no data found)", FW, FH);
	return 0;
}

/* ---- memory copy baseline: bilinear's input and output bytes ---- */
typedef struct copy_job {
	uint8_t *dst;
	const uint8_t *src;
	size_t row;
} copy_job;

static void copy_band(void *ctx, uint32_t y0, uint32_t y1)
{
	copy_job *j = ctx;
	memcpy(j->dst + (size_t)y0 * j->row, j->src + (size_t)y0 * j->row,
	       (size_t)(y1 - y0) * j->row);
}

/* ---- calibrated analysers for the calibrated pipeline's timing ---- */
typedef struct pc_bench_pinv {
	float *m;
	pc_analyser_pinv pv;
} pc_bench_pinv;

/* gw × gh cells of perturbed analyser matrices (a fixed pattern) and their pseudo-inverses;
 * m stays NULL when memory or the inversion fails (the row is then left out). */
static void bench_make_pinv(pc_bench_pinv *b, uint32_t gw, uint32_t gh)
{
	size_t n = (size_t)gw * gh;
	float *w = malloc(sizeof(float) * 12 * n), *p = malloc(sizeof(float) * 12 * n);
	uint32_t r = 12345;
	for (size_t k = 0; w && p && k < n; k++)
		for (int c = 0; c < 4; c++) {
			double u[3];
			for (int i = 0; i < 3; i++) {
				r = r * 1664525u + 1013904223u;
				u[i] = (r >> 8) / 16777216.0;
			}
			double t = (45.0 * c + 2 * (u[0] - 0.5)) * M_PI / 180;
			double e = 0.93 + 0.06 * u[1], g = 0.9 + 0.2 * u[2];
			w[12 * k + 3 * c] = (float)(0.5 * g);
			w[12 * k + 3 * c + 1] = (float)(0.5 * g * e * cos(2 * t));
			w[12 * k + 3 * c + 2] = (float)(0.5 * g * e * sin(2 * t));
		}
	if (w && p && pc_stokes_pinv(w, n, p) == 0) {
		b->m = p;
		b->pv = (pc_analyser_pinv){p, gw, gh};
	} else {
		free(p);
	}
	free(w);
}

/* ---- the full pipeline's memory floor: its own bytes, its store kind ---- */
/* Reads the 16-bit raw and writes five float planes (S0, S1, S2, DoLP, AoLP's places) with the
 * pipeline's store kind (pc_stokes_streams): the time the pipeline could not beat if its
 * arithmetic were free. The values are the raw converted to float (no other arithmetic). With
 * non-temporal stores each plane's 64 bytes go out back to back, as in the pipeline. */
typedef struct floor_job {
	const pc_view *raw;
	float *o[5];
	size_t ostride; /* floats */
	int nt;
} floor_job;

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define PC_BENCH_X86 1
__attribute__((target("avx2"))) static void floor_rows_avx2(const floor_job *j, uint32_t y0,
                                                            uint32_t y1)
{
	for (uint32_t y = y0; y < y1; y++) {
		const uint16_t *r = PC_ROW(j->raw, const uint16_t, y);
		size_t off = (size_t)y * j->ostride;
		uint32_t x = 0, w = j->raw->width;
		for (; x + 16 <= w; x += 16) {
			__m256 a = _mm256_cvtepi32_ps(
			    _mm256_cvtepu16_epi32(_mm_loadu_si128((const __m128i *)(r + x))));
			__m256 b = _mm256_cvtepi32_ps(
			    _mm256_cvtepu16_epi32(_mm_loadu_si128((const __m128i *)(r + x + 8))));
			for (int p = 0; p < 5; p++) {
				if (j->nt) {
					_mm256_stream_ps(j->o[p] + off + x, a);
					_mm256_stream_ps(j->o[p] + off + x + 8, b);
				} else {
					_mm256_storeu_ps(j->o[p] + off + x, a);
					_mm256_storeu_ps(j->o[p] + off + x + 8, b);
				}
			}
		}
		for (; x < w; x++)
			for (int p = 0; p < 5; p++)
				j->o[p][off + x] = r[x];
	}
	if (j->nt)
		_mm_sfence();
}
#endif

static void floor_band(void *ctx, uint32_t y0, uint32_t y1)
{
	const floor_job *j = ctx;
#ifdef PC_BENCH_X86
	if (pc_cpu_active() >= PC_CPU_AVX2) {
		floor_rows_avx2(j, y0, y1);
		return;
	}
#endif
	for (uint32_t y = y0; y < y1; y++) {
		const uint16_t *r = PC_ROW(j->raw, const uint16_t, y);
		for (int p = 0; p < 5; p++) {
			float *d = j->o[p] + (size_t)y * j->ostride;
			for (uint32_t x = 0; x < j->raw->width; x++)
				d[x] = r[x];
		}
	}
}

/* ---- results ---- */
typedef struct method_row {
	pc_demosaic_method m;
	timing t;
	int colour;
	int skip; /* not selected (--methods, or reference only without --all-methods) */
	int once; /* reference only: timed in one run, outside the round robin */
	int n_ds; /* datasets scored */
	pc_eval_metrics acc[4]; /* per dataset */
	char ds_name[4][64];
} method_row;

/* Colour track (synthetic, ours): no colour-polarization ground truth ships with the data, so
 * each Lapray NIR scene is coloured with smooth, different gain fields per colour,
 * I_{k,c}(x, y) = g_k(x, y)·I_c(x, y), mosaicked with IMX250MYR in 16-bit containers, and each
 * colour's four channels are scored with the protocol's metrics; the three colours' metrics are
 * averaged. */
static double colour_gain(unsigned k, uint32_t x, uint32_t y)
{
	const double kx[3] = {97, 131, 173}, ky[3] = {151, 89, 113}, base[3] = {0.55, 0.7, 0.4};
	return base[k] + 0.3 * sin(2 * M_PI * x / kx[k] + k) * cos(2 * M_PI * y / ky[k]);
}

static int colour_track(const pc_eval_truth *t, pc_demosaic_method meth,
                        const pc_demosaic_opts *opts, pc_eval_metrics *mean)
{
	pc_mosaic m = pc_mosaic_imx250myr();
	uint32_t w = t->width, h = t->height;
	size_t n = (size_t)w * h;
	pc_view raw;
	int rc = pc_view_alloc(&raw, PC_FMT_MONO16, w, h, 0);
	if (rc)
		return rc;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			unsigned k = pc_mosaic_color(&m, x, y) - PC_CFA_R;
			double v = colour_gain(k, x, y) *
			           t->ch[pc_mosaic_channel(&m, x, y)][(size_t)y * w + x];
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)lround(v * 65535);
		}
	float *buf = malloc(sizeof(float) * n * 12);
	pc_eval_truth tk = *t;
	for (int c = 0; c < 4; c++)
		tk.ch[c] = malloc(sizeof(double) * n);
	rc =
	    buf && tk.ch[0] && tk.ch[1] && tk.ch[2] && tk.ch[3] ? 0 : pc_error(PC_ENOMEM, "colour");
	pc_fplane o[12];
	if (!rc) {
		pc_fplanes_separate(buf, w, h, 12, o);
		pc_demosaic_opts op = *opts;
		op.full_scale = 65535;
		rc = pc_demosaic(&raw, &m, meth, &op, o);
	}
	memset(mean, 0, sizeof *mean);
	for (unsigned k = 0; k < 3 && !rc; k++) {
		for (int c = 0; c < 4; c++)
			for (uint32_t y = 0; y < h; y++)
				for (uint32_t x = 0; x < w; x++)
					tk.ch[c][(size_t)y * w + x] =
					    lround(colour_gain(k, x, y) *
					           t->ch[c][(size_t)y * w + x] * 65535) /
					    65535.0;
		pc_eval_metrics mk;
		rc = pc_eval_score(&tk, &o[4 * k], 65535, &mk);
		for (size_t q = 0; q < sizeof mk / sizeof(double); q++)
			(&mean->psnr_i)[q] += (&mk.psnr_i)[q] / 3;
	}
	for (int c = 0; c < 4; c++)
		free(tk.ch[c]);
	free(buf);
	pc_view_free(&raw);
	return rc;
}

/* Noisy track: the simulator's default scene (pBRDF objects, EMVA 1288 noise as the scene
 * declares), one raw frame against the noise-free truth Stokes it renders. Estimates are taken
 * above the black level and scaled to radiance (pc_sim_dn_per_radiance); outside a 15-pixel
 * border, on pixels lit to at least 5 % of the truth's peak S0 and without a saturated raw
 * pixel in their 5×5 neighbourhood (the scene has a black background and specular highlights):
 * S0 PSNR with the truth's peak, DoLP RMSE and the truth-DoLP-weighted AoLP RMSE. */
typedef struct noisy_row {
	double psnr_s0, dolp_rmse, waolp_deg, fraction;
} noisy_row;

static int noisy_track(const pc_demosaic_method *meths, size_t nm, int threads, noisy_row *res,
                       char *what, size_t what_size)
{
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	int rc = pc_scene_load_default(&scene);
	pc_sim_options so = pc_sim_options_default();
	so.threads = threads;
	if (!rc)
		rc = pc_sim_new(scene, &so, &sim);
	pc_scene_free(scene);
	if (rc)
		return rc;
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	if (info.colour_channels != 1 || info.width % 2 || info.height % 2) {
		pc_sim_free(sim);
		return pc_error(PC_ENOTSUP, "default scene: not a monochrome even-sized sensor");
	}
	pc_sensor_figures fig;
	pc_sim_get_sensor(sim, &fig);
	uint32_t w = info.width, h = info.height;
	size_t n = (size_t)w * h;
	float *truth = malloc(sizeof(float) * n * 4), *ch = malloc(sizeof(float) * n * 4);
	pc_view raw = {0};
	rc = truth && ch ? pc_view_alloc(&raw, info.format, w, h, 0) : pc_error(PC_ENOMEM, "noisy");
	if (!rc)
		rc = pc_sim_prepare(sim, 0, truth, NULL, NULL, NULL);
	if (!rc)
		rc = pc_sim_frame(sim, 0, NULL, &raw, NULL);
	double k = pc_sim_dn_per_radiance(sim, NULL, 0);
	snprintf(what, what_size, "simulator default scene %ux%u, %u-bit, effects 0x%x, seed %llu",
	         w, h, info.bits, info.effects, (unsigned long long)info.seed);
	double peak = 0;
	for (size_t i = 0; i < n && !rc; i++)
		peak = fmax(peak, truth[4 * i]);
	/* the evaluation mask: lit, unsaturated neighbourhood */
	uint8_t *mask = rc ? NULL : calloc(n, 1);
	uint16_t *u = rc ? NULL : malloc(sizeof(uint16_t) * n);
	if (!rc && (!mask || !u))
		rc = pc_error(PC_ENOMEM, "noisy mask");
	if (!rc)
		rc = pc_view_to_u16(&raw, u, (size_t)w * 2);
	uint32_t maxcode = (1u << info.bits) - 1u;
	for (uint32_t y = 2; y + 2 < h && !rc; y++)
		for (uint32_t x = 2; x + 2 < w; x++) {
			int ok = truth[4 * ((size_t)y * w + x)] >= 0.05 * peak;
			for (int dy = -2; dy <= 2 && ok; dy++)
				for (int dx = -2; dx <= 2; dx++)
					ok &= u[(size_t)(y + dy) * w + x + dx] < maxcode;
			mask[(size_t)y * w + x] = (uint8_t)ok;
		}
	free(u);
	for (size_t q = 0; q < nm && !rc; q++) {
		pc_fplane pl[4];
		pc_fplanes_separate(ch, w, h, 4, pl);
		pc_demosaic_opts o = {threads, false, 0};
		rc = pc_demosaic(&raw, &info.mosaic, meths[q], &o, pl);
		double se = 0, de = 0, a2 = 0, ws = 0, cnt = 0;
		for (uint32_t y = PC_EVAL_BORDER; y + PC_EVAL_BORDER < h && !rc; y++)
			for (uint32_t x = PC_EVAL_BORDER; x + PC_EVAL_BORDER < w; x++) {
				size_t i = (size_t)y * w + x;
				if (!mask[i])
					continue;
				double I[4];
				for (int c = 0; c < 4; c++)
					I[c] = (pl[c].data[i] - fig.offset_dn) / k;
				double s0 = 0.5 * (I[0] + I[1] + I[2] + I[3]), s1 = I[0] - I[2],
				       s2 = I[1] - I[3];
				double d = s0 > 0 ? fmin(sqrt(s1 * s1 + s2 * s2) / s0, 1) : 0;
				const float *t = truth + 4 * i;
				double td =
				    t[0] > 0
				        ? fmin(sqrt((double)t[1] * t[1] + (double)t[2] * t[2]) /
				                   t[0],
				               1)
				        : 0;
				double ad = fabs(0.5 * atan2(s2, s1) - 0.5 * atan2(t[2], t[1])) *
				            180 / M_PI;
				ad = fmod(ad, 180.0);
				if (ad > 90)
					ad = 180 - ad;
				se += (s0 - t[0]) * (s0 - t[0]);
				de += (d - td) * (d - td);
				a2 += td * ad * ad;
				ws += td;
				cnt++;
			}
		if (!rc) {
			res[q].psnr_s0 = 10 * log10(peak * peak * cnt / se);
			res[q].dolp_rmse = sqrt(de / cnt);
			res[q].waolp_deg = ws > 0 ? sqrt(a2 / ws) : 0;
			res[q].fraction = cnt / (double)n;
		}
	}
	free(mask);
	pc_view_free(&raw);
	free(truth);
	free(ch);
	pc_sim_free(sim);
	return rc;
}

/* The per-scene table of a dataset: res[s·stride + k] is method ms[k] on scene s (a result
 * whose dataset is not `dataset` is missing); per scene each method's S0 / DoLP PSNR gain over
 * bilinear (ms[bi]) and bilinear's own PSNRs, then the mean and the worst scene
 * (pc_eval_dataset_gain). Returns the JSON {scenes, gain_over_bilinear}. */
static json_t *gain_table(FILE *tf, const pc_eval_result *res, size_t ns, size_t stride,
                          const pc_demosaic_method *ms, size_t nm, size_t bi, const char *dataset)
{
	fprintf(tf, "%-16s", "scene");
	for (size_t k = 0; k < nm; k++)
		if (k != bi)
			fprintf(tf, " %15.15s", pc_demosaic_method_get(ms[k])->name);
	fprintf(tf, " %15s\n", "bilinear S0/DoLP");
	json_t *root = json_object();
	json_t *jsc = json_array();
	for (size_t s = 0; s < ns; s++) {
		const pc_eval_result *br = &res[s * stride + bi];
		const char *b = br->scene ? strrchr(br->scene, '/') : NULL;
		b = b ? b + 1 : br->scene ? br->scene : "?";
		const pc_eval_metrics *bm = &br->m;
		if (strcmp(br->dataset, dataset) != 0)
			continue; /* not scored */
		fprintf(tf, "%-16.16s", b);
		json_t *js = json_object();
		json_object_set_new(js, "scene", json_string(b));
		for (size_t k = 0; k < nm; k++) {
			const pc_eval_result *r = &res[s * stride + k];
			const pc_eval_metrics *m = &r->m;
			if (strcmp(r->dataset, dataset) != 0) {
				if (k != bi)
					fprintf(tf, " %15s", "-");
				continue;
			}
			if (k != bi)
				fprintf(tf, " %+7.2f/%+7.2f", m->psnr_s0 - bm->psnr_s0,
				        m->psnr_dolp - bm->psnr_dolp);
			json_t *jm = json_object();
			json_object_set_new(jm, "psnr_s0", bench_json_real(m->psnr_s0));
			json_object_set_new(jm, "psnr_dolp", bench_json_real(m->psnr_dolp));
			json_object_set_new(jm, "aolp_wrmse_deg",
			                    bench_json_real(m->aolp_wrmse_deg));
			json_object_set_new(js, pc_demosaic_method_get(ms[k])->name, jm);
		}
		fprintf(tf, " %7.2f/%7.2f\n", bm->psnr_s0, bm->psnr_dolp);
		json_array_append_new(jsc, js);
	}
	json_t *jsum = json_object();
	pc_eval_gain gains[PC_DM_COUNT];
	for (size_t k = 0; k < nm; k++)
		pc_eval_dataset_gain(res, ns * stride, dataset, ms[k], PC_DM_BILINEAR, &gains[k]);
	for (int row = 0; row < 2; row++) {
		fprintf(tf, "%-16s", row ? "worst scene" : "mean");
		for (size_t k = 0; k < nm; k++) {
			if (k == bi)
				continue;
			double a = row ? gains[k].s0_worst : gains[k].s0_mean;
			double d = row ? gains[k].dolp_worst : gains[k].dolp_mean;
			fprintf(tf, " %+7.2f/%+7.2f", a, d);
			const char *name = pc_demosaic_method_get(ms[k])->name;
			json_t *jm = json_object_get(jsum, name);
			if (!jm) {
				jm = json_object();
				json_object_set_new(jsum, name, jm);
			}
			json_object_set_new(jm, row ? "s0_worst_gain_db" : "s0_mean_gain_db",
			                    bench_json_real(a));
			json_object_set_new(jm, row ? "dolp_worst_gain_db" : "dolp_mean_gain_db",
			                    bench_json_real(d));
			if (row) {
				const char *w[2] = {gains[k].s0_worst_scene,
				                    gains[k].dolp_worst_scene};
				for (int q = 0; q < 2; q++) {
					const char *bn = w[q] ? strrchr(w[q], '/') : NULL;
					bn = bn ? bn + 1 : w[q];
					json_object_set_new(
					    jm, q ? "dolp_worst_scene" : "s0_worst_scene",
					    bn ? json_string(bn) : json_null());
				}
			}
		}
		fprintf(tf, "\n");
	}
	json_object_set_new(root, "scenes", jsc);
	json_object_set_new(root, "gain_over_bilinear", jsum);
	return root;
}

/* Stress track: the stress suite's scenes (scenes/stress) rendered with ground truth and
 * scored by the library (pc_sim_eval_cases), the selected monochrome full-resolution methods
 * on each, gains over bilinear per scene, their mean and the worst scene
 * (pc_eval_dataset_gain). Returns the JSON (NULL on failure). */
static json_t *stress_track(const char *dir, const pc_demosaic_method *ms, size_t nm, int threads,
                            FILE *tf)
{
	char pat[4096];
	snprintf(pat, sizeof pat, "%s/*.json", dir);
	glob_t g;
	if (glob(pat, 0, NULL, &g)) {
		fprintf(tf, "stress track: no scenes in %s\n", dir);
		return NULL;
	}
	size_t bi = 0;
	for (size_t k = 0; k < nm; k++)
		if (ms[k] == PC_DM_BILINEAR)
			bi = k;
	size_t ns = g.gl_pathc;
	pc_eval_result *res = calloc(ns * nm, sizeof *res);
	if (!res) {
		globfree(&g);
		return NULL;
	}
	pc_demosaic_opts o = {threads, false, 0};
	int rc = pc_sim_eval_cases((const char *const *)g.gl_pathv, ns, ms, nm, &o, threads,
	                           &host->progress, res);
	host->progress_end(host->progress.user);
	if (rc) {
		host->fail(rc, "stress track");
		free(res);
		globfree(&g);
		return NULL;
	}
	fprintf(tf, "\nstress track (%s, %zu scenes): gain over bilinear in S0 / DoLP PSNR, dB\n",
	        dir, ns);
	json_t *root = gain_table(tf, res, ns, nm, ms, nm, bi, res[0].dataset);
	json_object_set_new(root, "dir", json_string(dir));
	free(res);
	globfree(&g);
	return root;
}

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam bench demosaic [DATA_DIR] [--stress DIR] [-o DIR [--overwrite]] "
	    "[--reps N]\n"
	    "                               [--threads N] [--methods A,B,...] [--all-methods]\n"
	    "                               [--quick] [--json]\n"
	    "\n"
	    "What demosaicking accuracy costs in time. Accuracy follows the frozen protocol on\n"
	    "every dataset in DATA_DIR/gt (default $POLARCAM_DATA; skipped with a message when\n"
	    "neither is given; layout and datasets: docs/evaluation.md): S0 and DoLP PSNR and the "
	    "DoLP-weighted AoLP RMSE, per dataset (mean of\n"
	    "its scenes, and per scene with the worst scene), bilinear as the baseline, and our\n"
	    "bilinear against a straightforward\n"
	    "double-precision reference bilinear. Time: per 2448x2048 frame of 12-bit data in\n"
	    "16-bit containers, median of N runs (default 7; 3 with --quick) on warm buffers, for\n"
	    "every method (\"x bil\": the multiple of bilinear's time in the same run, same\n"
	    "output buffers, same pc_demosaic call); the full bilinear pipeline (demosaic + Stokes "
	    "+ DoLP + AoLP, float32),\n"
	    "also with calibrated analysers (perturbed 3x4 pseudo-inverses per 2x2 super-pixel,\n"
	    "and per pixel; calibrated / uncalibrated is the ratio to read) and with a black\n"
	    "level, saturation and dead levels and the validity mask; the pipeline's\n"
	    "memory floor (read its input, write its 5 float planes with the store kind the\n"
	    "pipeline uses on this machine) and pipeline / floor; a memory copy of bilinear's\n"
	    "input and output bytes; OpenCV's bilinear 16-bit Bayer demosaicking of the same\n"
	    "frame when OpenCV is built in. All in one run: read the ratios, absolute times move\n"
	    "with the machine's load (reported). Each time is given as wall-clock and as process\n"
	    "CPU time (all threads), which does not count waiting for cores that other work\n"
	    "holds.\n"
	    "\n"
	    "Stress track: every scene of the stress suite (--stress DIR, default\n"
	    "$POLARCAM_STRESS or ./scenes/stress; skipped when absent) rendered with ground truth\n"
	    "(polarcam eval SCENE.json): per scene, each monochrome method's S0 and DoLP PSNR "
	    "gain\n"
	    "over bilinear, their mean and the worst scene.\n"
	    "\n"
	    "Noisy track (not with --quick): the simulator's default scene with its sensor noise,\n"
	    "one raw frame scored against the noise-free truth it renders (S0 PSNR, DoLP RMSE,\n"
	    "DoLP-weighted AoLP RMSE).\n"
	    "\n"
	    "Methods: all but the reference-only ones (igri2: double precision, hundreds of\n"
	    "times bilinear) by default; --all-methods adds them, --methods LIST runs only the\n"
	    "listed ones (comma-separated names of polarcam demosaic --list; bilinear always\n"
	    "runs as the baseline). Reference-only methods are timed in one run (marked 1),\n"
	    "the others by the median of the round robin.\n"
	    "\n"
	    "Writes DIR/demosaic.json, DIR/pareto_s0.png and DIR/pareto_dolp.png (default DIR:\n"
	    "bench-demosaic; made beside DIR and renamed into place at the end, an existing DIR\n"
	    "refused unless --overwrite) and prints a table; --json prints the JSON on stdout\n"
	    "instead.\n");
}

static void pareto_plot(const char *path, const method_row *rows, size_t n, int ds, int dolp,
                        double bil_ms)
{
	char title[256];
	snprintf(title, sizeof title, "Demosaicking: %s PSNR vs time (%s, 2448x2048 frame)",
	         dolp ? "DoLP" : "S0", rows[0].ds_name[ds]);
	pc_plot *p = pc_plot_new(title, "time per frame (ms, log scale)",
	                         dolp ? "DoLP PSNR (dB)" : "S0 PSNR (dB)");
	if (!p)
		return;
	pc_plot_set_log(p, true, false);
	/* the points, and the Pareto front (no method both faster and more accurate) */
	double fx[16], fy[16];
	size_t nf = 0;
	for (size_t i = 0; i < n; i++) {
		if (rows[i].colour || rows[i].n_ds <= ds)
			continue;
		double x = rows[i].t.median_ms;
		double y = dolp ? rows[i].acc[ds].psnr_dolp : rows[i].acc[ds].psnr_s0;
		pc_plot_add_series(p, NULL, &x, &y, 1, PC_PLOT_POINTS);
		pc_plot_add_label(p, x, y, pc_demosaic_method_get(rows[i].m)->name);
		int dominated = 0;
		for (size_t k = 0; k < n; k++) {
			if (k == i || rows[k].colour || rows[k].n_ds <= ds)
				continue;
			double xk = rows[k].t.median_ms;
			double yk = dolp ? rows[k].acc[ds].psnr_dolp : rows[k].acc[ds].psnr_s0;
			if (xk <= x && yk >= y && (xk < x || yk > y))
				dominated = 1;
		}
		if (!dominated && nf < 16) {
			fx[nf] = x;
			fy[nf] = y;
			nf++;
		}
	}
	for (size_t a = 0; a < nf; a++) /* sort the front by time */
		for (size_t b = a + 1; b < nf; b++)
			if (fx[b] < fx[a]) {
				double tx = fx[a], ty = fy[a];
				fx[a] = fx[b], fy[a] = fy[b];
				fx[b] = tx, fy[b] = ty;
			}
	pc_plot_add_series(p, "Pareto front", fx, fy, nf, PC_PLOT_DASHED);
	double bx[2] = {bil_ms * 5, bil_ms * 5}, by[2];
	by[0] = 1e9, by[1] = -1e9;
	for (size_t i = 0; i < n; i++)
		if (!rows[i].colour && rows[i].n_ds > ds) {
			double y = dolp ? rows[i].acc[ds].psnr_dolp : rows[i].acc[ds].psnr_s0;
			by[0] = fmin(by[0], y);
			by[1] = fmax(by[1], y);
		}
	pc_plot_add_series(p, "5 x bilinear's time", bx, by, 2, PC_PLOT_DASHED);
	int rc = pc_plot_write_png(p, path, 900, 600);
	if (rc)
		host->fail(rc, path);
	pc_plot_free(p);
}

int pc_bench_demosaic(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	const char *data_dir = NULL, *out_dir = "bench-demosaic", *stress_dir = NULL;
	long reps = 7, threads = 0;
	bool json_out = false, quick = false, overwrite = false, all_methods = false;
	const char *method_list = NULL;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
			usage(stdout);
			return PC_BENCH_OK;
		} else if (!strcmp(argv[i], "-o") && i + 1 < argc) {
			out_dir = argv[++i];
		} else if (!strcmp(argv[i], "--reps") && i + 1 < argc) {
			int rc = host->parse_long("--reps", argv[++i], 1, 1000, &reps);
			if (rc)
				return host->fail(rc, NULL);
		} else if (!strcmp(argv[i], "--threads") && i + 1 < argc) {
			int rc = host->parse_long("--threads", argv[++i], 1, 1024, &threads);
			if (rc)
				return host->fail(rc, NULL);
		} else if (!strcmp(argv[i], "--stress") && i + 1 < argc) {
			stress_dir = argv[++i];
		} else if (!strcmp(argv[i], "--json")) {
			json_out = true;
		} else if (!strcmp(argv[i], "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(argv[i], "--all-methods")) {
			all_methods = true;
		} else if (!strcmp(argv[i], "--methods") && i + 1 < argc) {
			method_list = argv[++i];
		} else if (!strcmp(argv[i], "--quick")) {
			quick = true;
			reps = 3;
		} else if (argv[i][0] == '-') {
			return host->error(PC_BENCH_USAGE,
			                   "unknown option '%s' (polarcam bench demosaic "
			                   "--help)",
			                   argv[i]);
		} else {
			data_dir = argv[i];
		}
	}
	struct stat sb;
	const char *data_from = "DATA_DIR";
	if (!data_dir && getenv("POLARCAM_DATA") && *getenv("POLARCAM_DATA")) {
		data_dir = getenv("POLARCAM_DATA");
		data_from = "POLARCAM_DATA";
	}
	if (!stress_dir && getenv("POLARCAM_STRESS") && *getenv("POLARCAM_STRESS"))
		stress_dir = getenv("POLARCAM_STRESS");
	if (!stress_dir && stat("scenes/stress", &sb) == 0 && S_ISDIR(sb.st_mode))
		stress_dir = "scenes/stress";
	if (data_dir && !(stat(data_dir, &sb) == 0 && S_ISDIR(sb.st_mode)))
		return host->error(PC_BENCH_USAGE, "%s %s: not a directory", data_from, data_dir);
	/* an occupied output folder is refused before the measurements */
	int orc = pc_output_check(out_dir, overwrite ? PC_OUT_OVERWRITE : 0, true);
	if (orc)
		return host->fail(orc, NULL);
	if (host->parse_only)
		return PC_BENCH_OK;
	FILE *tf = json_out ? stderr : stdout;
	int nthreads = threads ? (int)threads : pc_parallel_max_threads();
	char load0[128], load1[128];
	bench_loadavg(load0, sizeof load0);
	fprintf(tf,
	        "polarcam bench demosaic: %d thread(s), %s kernels built by %s, median of %ld "
	        "runs; load average at start: %s\n",
	        nthreads, pc_cpu_level_name(pc_cpu_active()), pc_build_compiler(), reps, load0);

	/* ---------------- time ---------------- */
	pc_view raw;
	char frame_what[160];
	int rc = make_frame(data_dir, &raw, frame_what, sizeof frame_what);
	if (rc)
		return host->fail(rc, "frame");
	fprintf(tf, "frame: %s\n\n", frame_what);
	size_t plane = (size_t)FW * FH;
	float *obuf = aligned_alloc(64, plane * 12 * sizeof(float));
	double *ts = malloc(sizeof(double) * (size_t)reps);
	if (!obuf || !ts) {
		pc_view_free(&raw);
		free(obuf);
		free(ts);
		return host->error(PC_BENCH_FAILURE, "out of memory");
	}
	memset(obuf, 0, plane * 12 * sizeof(float)); /* pre-fault */
	pc_fplane planes[12];
	pc_fplanes_separate(obuf, FW, FH, 12, planes);
	/* the same twelve planes 64 bytes apart in their 4 KB pages (docs/api.md's layout): the
	 * table's consecutive planes are a whole number of pages each, so their rows start at one
	 * page offset, which costs the twelve-plane colour methods (docs/demosaicking.md, Rounds
	 * 31 and 36); timed for the bilinear and pan-lean */
	float *sbuf = aligned_alloc(64, (plane + 16) * 12 * sizeof(float));
	pc_fplane splanes[12];
	if (sbuf) {
		memset(sbuf, 0, (plane + 16) * 12 * sizeof(float));
		for (int c = 0; c < 12; c++)
			splanes[c] = (pc_fplane){sbuf + (size_t)c * (plane + 16), FW, 1};
	}
	pc_demosaic_opts opts = {(int)threads, false, 0};
	method_row rows[PC_DM_COUNT];
	size_t nrows = 0;
	pc_mosaic mono = pc_mosaic_imx250mzr(), colour = pc_mosaic_imx250myr();
	bool listed[PC_DM_COUNT] = {false};
	if (method_list) {
		char buf[1024];
		snprintf(buf, sizeof buf, "%s", method_list);
		for (char *sv, *tok = strtok_r(buf, ",", &sv); tok;
		     tok = strtok_r(NULL, ",", &sv)) {
			pc_demosaic_method mm;
			if ((rc = pc_demosaic_method_from_name(tok, &mm))) {
				pc_view_free(&raw);
				free(obuf);
				free(sbuf);
				free(ts);
				return host->error(PC_BENCH_USAGE, "--methods: %s",
				                   pc_error_detail());
			}
			listed[mm] = true;
		}
	}
	char skipped[512] = "";
	for (int k = 0; k < PC_DM_COUNT; k++) {
		method_row *r = &rows[nrows++];
		memset(r, 0, sizeof *r);
		r->m = (pc_demosaic_method)k;
		unsigned fl = pc_demosaic_method_get(r->m)->flags;
		r->colour = !(fl & PC_DMF_MONO);
		r->once = (fl & PC_DMF_REFERENCE_ONLY) != 0;
		/* bilinear is the baseline of every ratio; a list names the others, else
		 * everything but the reference-only methods unless --all-methods */
		r->skip =
		    r->m != PC_DM_BILINEAR && (method_list ? !listed[k] : r->once && !all_methods);
		if (r->skip && r->once && !method_list) {
			size_t l = strlen(skipped);
			snprintf(skipped + l, sizeof skipped - l, "%s%s", l ? ", " : "",
			         pc_demosaic_method_get(r->m)->name);
		}
	}
	if (*skipped)
		fprintf(tf,
		        "left out (reference only, hundreds of times bilinear; --all-methods or "
		        "--methods to include, timed in one run): %s\n\n",
		        skipped);
	/* the other timed jobs: the two pipelines, the copy, OpenCV */
	enum {
		J_PIPE_BIL = PC_DM_COUNT,
		J_PIPE_EARI,
		J_PIPE_RATIO,
		J_PIPE_CAL,    /* bilinear pipeline, per-super-pixel analyser pseudo-inverses */
		J_PIPE_CALPX,  /* ... per-pixel ones */
		J_PIPE_LEVELS, /* bilinear pipeline + black level + saturation/dead validity mask */
		J_COPY,
		J_OPENCV,
		J_BIL16,
		J_FLOOR,
		J_BIL_SPREAD,  /* bilinear into planes 64 bytes apart in their pages */
		J_LEAN_SPREAD, /* pan-lean into them (when timed) */
		J_N
	};
	const bool time_spread = sbuf && !rows[PC_DM_PAN_LEAN].skip && !rows[PC_DM_PAN_LEAN].once;
	/* bilinear into 16-bit planes (exact, 2 fraction bits), the like-for-like of OpenCV */
	uint16_t *b16 = aligned_alloc(64, plane * 4 * sizeof(uint16_t));
	uint16_t *b16p[4];
	if (b16) {
		memset(b16, 0, plane * 4 * sizeof(uint16_t));
		for (int c = 0; c < 4; c++)
			b16p[c] = b16 + (size_t)c * plane;
	}
	pc_stokes_out so = {planes[0], planes[1], planes[2], planes[3], planes[4]};
	/* calibrated analysers: perturbed analyser matrices (orientations ±1°, extinction 0.93 to
	 * 0.99, gains 0.9 to 1.1, a fixed pattern) per 2×2 super-pixel and per pixel, as a
	 * calibration would give them (pc_stokes_pinv) */
	pc_bench_pinv cal_sp = {0}, cal_px = {0};
	bench_make_pinv(&cal_sp, FW / 2, FH / 2);
	bench_make_pinv(&cal_px, FW, FH);
	pc_pipeline_opts cal_o = pc_pipeline_defaults();
	cal_o.threads = (int)threads;
	pc_pipeline_opts lev_o = cal_o;
	lev_o.black_level = 64;
	lev_o.saturation_level = 4095;
	lev_o.dead_level = 0.5;
	uint8_t *vmask = aligned_alloc(64, plane);
	if (vmask)
		memset(vmask, 0, plane);
	uint64_t lev_invalid = 0;
	/* the pipeline's floor: the same planes, the same store kind */
	floor_job fj = {
	    &raw,
	    {planes[0].data, planes[1].data, planes[2].data, planes[3].data, planes[4].data},
	    planes[0].row_stride,
	    pc_stokes_streams(&so, FW, FH)};
	size_t floor_bytes = plane * 2 + plane * 4 * 5;
	size_t bytes = plane * 2 + plane * 16; /* bilinear's 10 MB input and 80 MB output */
	uint8_t *csrc = aligned_alloc(64, bytes), *cdst = aligned_alloc(64, bytes);
	copy_job cj = {cdst, csrc, bytes / FH};
	if (csrc && cdst) {
		memset(csrc, 1, bytes);
		memset(cdst, 2, bytes);
	}
	char cv_note[160] = "OpenCV not built in";
	int have_cv = 0;
	uint16_t *bgr = NULL;
#ifdef PC_HAVE_OPENCV
	bgr = aligned_alloc(64, plane * 3 * sizeof(uint16_t));
	if (bgr) {
		memset(bgr, 0, plane * 3 * sizeof(uint16_t));
		char err[160] = "";
		if (pc_bench_opencv_bayer16(raw.data, raw.stride, bgr, (size_t)FW * 6, FW, FH,
		                            nthreads, err, sizeof err) == 0) {
			have_cv = 1;
			snprintf(cv_note, sizeof cv_note,
			         "OpenCV %s cvtColor(COLOR_BayerBG2BGR), 16-bit, %d thread(s)",
			         pc_bench_opencv_version(), nthreads);
		} else {
			snprintf(cv_note, sizeof cv_note, "%s", err);
		}
	}
#endif
	/* Round robin: every repetition runs every job once, so that load changes on the shared
	 * machine hit all of them alike; the first round is a warm-up. */
	double *tj = malloc(sizeof(double) * J_N * (size_t)reps);
	double *cj_t = malloc(sizeof(double) * J_N * (size_t)reps);
	if (!tj || !cj_t) {
		free(tj);
		free(cj_t);
		pc_view_free(&raw);
		free(obuf);
		free(sbuf);
		free(ts);
		return host->error(PC_BENCH_FAILURE, "out of memory");
	}
	pc_progress_report(&host->progress, "timing", 0, (uint64_t)reps + 1);
	for (long rep = -1; rep < reps; rep++) {
		for (int j = 0; j < J_N; j++) {
			if (j < PC_DM_COUNT && (rows[j].skip || rows[j].once))
				continue;
			double t0 = bench_now(), c0 = bench_cpu_s();
			if (j < PC_DM_COUNT) {
				const pc_mosaic *m = rows[j].colour ? &colour : &mono;
				rc = pc_demosaic(&raw, m, rows[j].m, &opts, planes);
				if (rc) {
					host->progress_end(host->progress.user);
					return host->fail(rc,
					                  pc_demosaic_method_get(rows[j].m)->name);
				}
			} else if (j == J_PIPE_BIL || j == J_PIPE_EARI || j == J_PIPE_RATIO) {
				pc_stokes_from_raw(&raw, &mono,
				                   j == J_PIPE_BIL    ? PC_DM_BILINEAR
				                   : j == J_PIPE_EARI ? PC_DM_EARI
				                                      : PC_DM_RATIO,
				                   &opts, &so);
			} else if (j == J_PIPE_CAL || j == J_PIPE_CALPX) {
				pc_bench_pinv *c = j == J_PIPE_CAL ? &cal_sp : &cal_px;
				cal_o.pinv = c->m ? &c->pv : NULL;
				if (c->m)
					pc_stokes_run(&raw, &cal_o, &so, NULL);
			} else if (j == J_PIPE_LEVELS) {
				pc_validity v = {vmask, FW, 0};
				if (vmask)
					pc_stokes_run(&raw, &lev_o, &so, &v);
				lev_invalid = v.n_invalid;
			} else if (j == J_BIL16) {
				if (b16)
					pc_demosaic_bilinear_u16(&raw, &mono, 2, (int)threads, b16p,
					                         (size_t)FW * 2);
			} else if (j == J_FLOOR) {
				pc_parallel_rows(FH, 0, (int)threads, floor_band, &fj);
			} else if (j == J_BIL_SPREAD || j == J_LEAN_SPREAD) {
				if (time_spread &&
				    (rc = pc_demosaic(&raw, j == J_BIL_SPREAD ? &mono : &colour,
				                      j == J_BIL_SPREAD ? PC_DM_BILINEAR
				                                        : PC_DM_PAN_LEAN,
				                      &opts, splanes))) {
					host->progress_end(host->progress.user);
					return host->fail(rc, "planes 64 bytes apart");
				}
			} else if (j == J_COPY) {
				if (csrc && cdst)
					pc_parallel_rows(FH, 0, (int)threads, copy_band, &cj);
			} else if (have_cv) {
#ifdef PC_HAVE_OPENCV
				char err[160];
				pc_bench_opencv_bayer16(raw.data, raw.stride, bgr, (size_t)FW * 6,
				                        FW, FH, nthreads, err, sizeof err);
#endif
			}
			double dt = bench_now() - t0, dc = bench_cpu_s() - c0;
			if (rep >= 0) {
				tj[(size_t)j * (size_t)reps + (size_t)rep] = dt;
				cj_t[(size_t)j * (size_t)reps + (size_t)rep] = dc;
			}
		}
		pc_progress_report(&host->progress, "timing", (uint64_t)(rep + 2),
		                   (uint64_t)reps + 1);
	}
	host->progress_end(host->progress.user);
	/* reference-only methods: one run each on the warm output buffers, same call */
	for (int j = 0; j < PC_DM_COUNT; j++) {
		if (rows[j].skip || !rows[j].once)
			continue;
		pc_progress_report(&host->progress, pc_demosaic_method_get(rows[j].m)->name, 0, 1);
		double t0 = bench_now(), c0 = bench_cpu_s();
		rc = pc_demosaic(&raw, &mono, rows[j].m, &opts, planes);
		double dt = bench_now() - t0, dc = bench_cpu_s() - c0;
		host->progress_end(host->progress.user);
		if (rc)
			return host->fail(rc, pc_demosaic_method_get(rows[j].m)->name);
		rows[j].t = (timing){1e3 * dt, 1e3 * dt, 1e3 * dc};
	}
	timing tall[J_N];
	for (int j = 0; j < J_N; j++) {
		if (j < PC_DM_COUNT && (rows[j].skip || rows[j].once))
			continue;
		tall[j] = summarize(tj + (size_t)j * (size_t)reps, (int)reps);
		tall[j].cpu_ms = summarize(cj_t + (size_t)j * (size_t)reps, (int)reps).median_ms;
	}
	for (int k = 0; k < PC_DM_COUNT; k++)
		if (!rows[k].skip && !rows[k].once)
			rows[k].t = tall[k];
	timing t_pipe[3] = {tall[J_PIPE_BIL], tall[J_PIPE_EARI], tall[J_PIPE_RATIO]};
	timing t_cal = tall[J_PIPE_CAL], t_calpx = tall[J_PIPE_CALPX], t_lev = tall[J_PIPE_LEVELS];
	int have_cal = cal_sp.m != NULL, have_calpx = cal_px.m != NULL;
	/* the calibrated pipeline as `--calibration` runs it (pc_calib_apply, the compact
	 * calibration) against the uncalibrated one with levels and mask, same frame, interleaved
	 * (bench calib --speed's synthetic calibration; the goal's measure) */
	double cmp_med[2] = {0}, cmp_min[2] = {0};
	int have_cmp = bench_calib_pair(FW, FH, (int)reps, (int)threads, cmp_med, cmp_min) == 0;
	pc_error_clear();
	free(cal_sp.m);
	free(cal_px.m);
	free(vmask);
	timing t_copy = tall[J_COPY];
	timing t_b16 = tall[J_BIL16];
	timing t_floor = tall[J_FLOOR];
	timing t_sbil = tall[J_BIL_SPREAD], t_slean = tall[J_LEAN_SPREAD];
	free(sbuf);
	free(b16);
	timing t_cv = {NAN, NAN, NAN};
	if (have_cv)
		t_cv = tall[J_OPENCV];
	free(tj);
	free(cj_t);
	free(csrc);
	free(cdst);
	free(bgr);
	pc_view_free(&raw);
	free(obuf);
	free(ts);

	/* ---------------- accuracy ---------------- */
	double ref_gap[3] = {NAN, NAN, NAN}; /* our bilinear − reference bilinear: I, S0, DoLP */
	int have_acc = 0;
	/* per dataset, per scene: res[s·nrows + i] is row i on scene s (method PC_DM_COUNT where
	 * missing); the scenes' names */
	const char *datasets[] = {"lapray-nir", "zhang"};
	pc_eval_result *dres[2] = {NULL, NULL};
	char **dnames[2] = {NULL, NULL};
	size_t dns[2] = {0, 0}, dnn[2] = {0, 0};
	if (data_dir) {
		char gt[2048];
		if ((size_t)snprintf(gt, sizeof gt, "%s/gt", data_dir) >= sizeof gt)
			return host->error(PC_BENCH_USAGE, "%s: path too long", data_dir);
		for (int d = 0; d < 2; d++) {
			char dpath[3072];
			snprintf(dpath, sizeof dpath, "%.2047s/%s", gt, datasets[d]);
			/* scenes: the sub-directories, in name order */
			char **names = NULL;
			size_t nscenes = bench_list_dir(dpath, &names);
			if (!nscenes) {
				free(names);
				continue;
			}
			have_acc = 1;
			dres[d] = calloc(nscenes * nrows, sizeof *dres[d]);
			for (size_t q = 0; dres[d] && q < nscenes * nrows; q++) {
				dres[d][q].method = PC_DM_COUNT;
				dres[d][q].scene = "";
			}
			pc_progress_report(&host->progress, datasets[d], 0, nscenes);
			int scored = 0;
			pc_eval_metrics refbil = {0}, fastbil = {0};
			for (size_t s = 0; s < nscenes; s++) {
				char spath[4096];
				snprintf(spath, sizeof spath, "%.3071s/%.1000s", dpath, names[s]);
				pc_eval_truth t;
				if (pc_truth_load(spath, &t) != 0) {
					host->warn("%s", pc_error_detail());
					continue;
				}
				for (size_t i = 0; i < nrows; i++) {
					if (rows[i].skip)
						continue;
					if (rows[i].colour) {
						/* the synthetic colour track, on the Lapray scenes
						 */
						pc_eval_metrics cm;
						if (d != 0 ||
						    colour_track(&t, rows[i].m, &opts, &cm) != 0)
							continue;
						if (scored == 0) {
							memset(&rows[i].acc[0], 0,
							       sizeof rows[i].acc[0]);
							snprintf(rows[i].ds_name[0],
							         sizeof rows[i].ds_name[0],
							         "colourised %s", datasets[d]);
						}
						for (size_t q = 0; q < sizeof cm / sizeof(double);
						     q++)
							(&rows[i].acc[0].psnr_i)[q] +=
							    (&cm.psnr_i)[q];
						continue;
					}
					pc_eval_metrics mm;
					if (pc_eval_method(&t, rows[i].m, &opts, &mm) != 0)
						continue;
					if (dres[d]) {
						pc_eval_result *er = &dres[d][s * nrows + i];
						er->scene = names[s];
						snprintf(er->dataset, sizeof er->dataset, "%s",
						         datasets[d]);
						er->method = rows[i].m;
						er->m = mm;
						dns[d] = s + 1;
					}
					int di = rows[i].n_ds;
					if (scored == 0) {
						memset(&rows[i].acc[di], 0, sizeof rows[i].acc[di]);
						snprintf(rows[i].ds_name[di],
						         sizeof rows[i].ds_name[di], "%s",
						         datasets[d]);
					}
					double *a = &rows[i].acc[di].psnr_i;
					const double *b = &mm.psnr_i;
					for (size_t q = 0; q < sizeof mm / sizeof(double); q++)
						a[q] += b[q];
					if (rows[i].m == PC_DM_BILINEAR) {
						pc_demosaic_opts ro = {(int)threads, true, 0};
						pc_eval_metrics rm;
						if (pc_eval_method(&t, PC_DM_BILINEAR, &ro, &rm) ==
						    0) {
							for (size_t q = 0;
							     q < sizeof mm / sizeof(double); q++) {
								(&refbil.psnr_i)[q] +=
								    (&rm.psnr_i)[q];
								(&fastbil.psnr_i)[q] += b[q];
							}
						}
					}
				}
				scored++;
				pc_eval_truth_free(&t);
				pc_progress_report(&host->progress, datasets[d], s + 1, nscenes);
				if (quick && scored >= 2)
					break;
			}
			host->progress_end(host->progress.user);
			dnames[d] = names; /* freed with dres after the report */
			dnn[d] = nscenes;
			for (size_t i = 0; i < nrows && scored; i++) {
				if (rows[i].colour && d != 0)
					continue;
				double *a = &rows[i].acc[rows[i].n_ds].psnr_i;
				for (size_t q = 0; q < sizeof(pc_eval_metrics) / sizeof(double);
				     q++)
					a[q] /= scored;
				rows[i].n_ds++;
			}
			if (d == 0 && scored) {
				ref_gap[0] = (fastbil.psnr_i - refbil.psnr_i) / scored;
				ref_gap[1] = (fastbil.psnr_s0 - refbil.psnr_s0) / scored;
				ref_gap[2] = (fastbil.psnr_dolp - refbil.psnr_dolp) / scored;
			}
		}
	} else {
		fprintf(tf, "no data directory (DATA_DIR or POLARCAM_DATA; docs/evaluation.md): "
		            "accuracy skipped, time only\n\n");
	}
	/* ---------------- noisy track ---------------- */
	pc_demosaic_method nmeth[PC_DM_COUNT];
	size_t nn = 0;
	for (size_t i = 0; i < nrows; i++)
		if (!rows[i].colour && !rows[i].skip &&
		    !(pc_demosaic_method_get(rows[i].m)->flags & PC_DMF_HALF_RES))
			nmeth[nn++] = rows[i].m;
	noisy_row noisy[PC_DM_COUNT];
	char noisy_what[200] = "";
	int have_noisy = 0;
	if (!quick) {
		int nr = noisy_track(nmeth, nn, (int)threads, noisy, noisy_what, sizeof noisy_what);
		if (nr)
			host->warn("noisy track skipped: %s", pc_error_detail());
		else
			have_noisy = 1;
	}
	bench_loadavg(load1, sizeof load1);

	/* ---------------- report ---------------- */
	double bil = 0, bil_cpu = 0, bil_min = 0;
	for (size_t i = 0; i < nrows; i++)
		if (rows[i].m == PC_DM_BILINEAR) {
			bil = rows[i].t.median_ms;
			bil_cpu = rows[i].t.cpu_ms;
			bil_min = rows[i].t.min_ms;
		}
	const method_row *brow = NULL;
	json_t *json_dataset_scenes = NULL;
	for (size_t i = 0; i < nrows; i++)
		if (rows[i].m == PC_DM_BILINEAR)
			brow = &rows[i];
	fprintf(tf, "%-16s %9s %7s %8s %7s %8s %7s", "method", "ms/frame", "x bil", "best ms",
	        "x bil", "cpu ms", "x bil");
	for (int d = 0; have_acc && brow && d < brow->n_ds; d++)
		fprintf(tf, " | %-10.10s %7s %7s %7s %7s", brow->ds_name[d], "S0 dB", "dS0",
		        "DoLP dB", "dDoLP");
	fprintf(tf, " | %s\n", have_acc ? "wAoLP deg" : "");
	for (size_t i = 0; i < nrows; i++) {
		const method_row *r = &rows[i];
		if (r->skip)
			continue;
		fprintf(tf, "%-15s%s %9.2f %7.2f %8.2f %7.2f %8.2f %7.2f",
		        pc_demosaic_method_get(r->m)->name, r->once ? "1" : " ", r->t.median_ms,
		        r->t.median_ms / bil, r->t.min_ms, r->t.min_ms / bil_min, r->t.cpu_ms,
		        r->t.cpu_ms / bil_cpu);
		for (int d = 0; have_acc && brow && d < brow->n_ds; d++) {
			if (r->colour && r->n_ds && d == 0) {
				/* colour rows: against bayer-first, on the colourised track */
				const method_row *bf = NULL;
				for (size_t q = 0; q < nrows; q++)
					if (rows[q].m == PC_DM_BAYER_FIRST && !rows[q].skip)
						bf = &rows[q];
				if (!bf)
					bf = r; /* the baseline was not selected: deltas 0 */
				fprintf(tf, " | %-10s %7.3f %+7.3f %7.3f %+7.3f", "colour*",
				        r->acc[0].psnr_s0, r->acc[0].psnr_s0 - bf->acc[0].psnr_s0,
				        r->acc[0].psnr_dolp,
				        r->acc[0].psnr_dolp - bf->acc[0].psnr_dolp);
			} else if (r->n_ds > d && !r->colour)
				fprintf(tf, " | %-10s %7.3f %+7.3f %7.3f %+7.3f", "",
				        r->acc[d].psnr_s0, r->acc[d].psnr_s0 - brow->acc[d].psnr_s0,
				        r->acc[d].psnr_dolp,
				        r->acc[d].psnr_dolp - brow->acc[d].psnr_dolp);
			else
				fprintf(tf, " | %-10s %7s %7s %7s %7s", "", "colour", "", "", "");
		}
		if (have_acc && r->n_ds)
			fprintf(tf, " | %.3f", r->acc[0].aolp_wrmse_deg);
		fprintf(tf, "\n");
	}
	if (have_acc)
		for (int d = 0; d < 2; d++) {
			if (!dns[d] || !dres[d])
				continue;
			fprintf(tf, "\n%s per scene: gain over bilinear in S0 / DoLP PSNR, dB\n",
			        datasets[d]);
			/* columns: the selected monochrome rows */
			pc_demosaic_method ms[PC_DM_COUNT];
			size_t col[PC_DM_COUNT], nc = 0, bi = 0;
			for (size_t i = 0; i < nrows; i++)
				if (!rows[i].skip && !rows[i].colour) {
					if (rows[i].m == PC_DM_BILINEAR)
						bi = nc;
					col[nc] = i;
					ms[nc++] = rows[i].m;
				}
			pc_eval_result *cr = malloc(sizeof *cr * dns[d] * (nc ? nc : 1));
			if (!cr)
				continue;
			for (size_t q = 0; q < dns[d]; q++)
				for (size_t c = 0; c < nc; c++)
					cr[q * nc + c] = dres[d][q * nrows + col[c]];
			json_t *jd = gain_table(tf, cr, dns[d], nc, ms, nc, bi, datasets[d]);
			free(cr);
			if (!json_dataset_scenes)
				json_dataset_scenes = json_object();
			json_object_set_new(json_dataset_scenes, datasets[d], jd);
		}
	if (have_noisy) {
		fprintf(tf,
		        "\nnoisy track: %s; %.0f %% of the pixels scored (lit, unsaturated)\n"
		        "%-16s %9s %10s %10s\n",
		        noisy_what, 100 * noisy[0].fraction, "method", "S0 dB", "DoLP RMSE",
		        "wAoLP deg");
		for (size_t q = 0; q < nn; q++)
			fprintf(tf, "%-16s %9.3f %10.4f %10.3f\n",
			        pc_demosaic_method_get(nmeth[q])->name, noisy[q].psnr_s0,
			        noisy[q].dolp_rmse, noisy[q].waolp_deg);
	}
	fprintf(tf,
	        "\n* colour rows: synthetic colour track (Lapray NIR scenes with smooth per-colour "
	        "gains, IMX250MYR mosaic), deltas against bayer-first\n");
	fprintf(tf,
	        "full pipeline (demosaic + S0,S1,S2,DoLP,AoLP float32), median / best wall "
	        "(cpu): bilinear %.2f / %.2f ms (cpu %.2f ms; %.2f x bilinear demosaic), eari "
	        "%.2f / %.2f ms (cpu %.2f ms), ratio %.2f / %.2f ms (cpu %.2f ms)\n",
	        t_pipe[0].median_ms, t_pipe[0].min_ms, t_pipe[0].cpu_ms, t_pipe[0].median_ms / bil,
	        t_pipe[1].median_ms, t_pipe[1].min_ms, t_pipe[1].cpu_ms, t_pipe[2].median_ms,
	        t_pipe[2].min_ms, t_pipe[2].cpu_ms);
	if (have_cmp)
		fprintf(
		    tf,
		    "calibrated bilinear pipeline as --calibration runs it (pc_calib_apply: "
		    "16-bit dark, gain and analysis vectors per pixel, weighted least squares, "
		    "mask): %.2f / %.2f ms against %.2f / %.2f ms uncalibrated with black level, "
		    "saturation and mask, same frame; calibrated / uncalibrated = %.2f (best "
		    "%.2f; goal <= 1.5)\n",
		    cmp_med[1], cmp_min[1], cmp_med[0], cmp_min[0], cmp_med[1] / cmp_med[0],
		    cmp_min[1] / cmp_min[0]);
	if (have_cal)
		fprintf(tf,
		        "calibrated bilinear pipeline (one 3x4 analyser pseudo-inverse per 2x2 "
		        "super-pixel, %.0f MB of them; an experiment, not accurate enough: "
		        "docs/calibration.md): %.2f / %.2f ms (cpu %.2f ms); / uncalibrated = %.2f "
		        "(best %.2f)\n",
		        1e-6 * (double)plane * 12, t_cal.median_ms, t_cal.min_ms, t_cal.cpu_ms,
		        t_cal.median_ms / t_pipe[0].median_ms, t_cal.min_ms / t_pipe[0].min_ms);
	if (have_calpx)
		fprintf(
		    tf,
		    "calibrated bilinear pipeline, one matrix per pixel (%.0f MB of them): %.2f "
		    "/ %.2f ms (cpu %.2f ms); / uncalibrated = %.2f (best %.2f)\n",
		    1e-6 * (double)plane * 48, t_calpx.median_ms, t_calpx.min_ms, t_calpx.cpu_ms,
		    t_calpx.median_ms / t_pipe[0].median_ms, t_calpx.min_ms / t_pipe[0].min_ms);
	fprintf(tf,
	        "bilinear pipeline with black level, saturation and dead levels and the "
	        "validity mask (%llu pixels flagged): %.2f / %.2f ms (cpu %.2f ms); / plain = %.2f "
	        "(best %.2f)\n",
	        (unsigned long long)lev_invalid, t_lev.median_ms, t_lev.min_ms, t_lev.cpu_ms,
	        t_lev.median_ms / t_pipe[0].median_ms, t_lev.min_ms / t_pipe[0].min_ms);
	fprintf(tf,
	        "full pipeline's memory floor (read the %.1f MB raw, write 5 float32 planes, "
	        "%.1f MB in all, %s stores like the pipeline): %.2f ms (best %.2f, cpu %.2f ms); "
	        "pipeline / floor = %.2f (best %.2f)\n",
	        1e-6 * (double)(plane * 2), 1e-6 * (double)floor_bytes,
	        fj.nt ? "non-temporal" : "ordinary", t_floor.median_ms, t_floor.min_ms,
	        t_floor.cpu_ms, t_pipe[0].median_ms / t_floor.median_ms,
	        t_pipe[0].min_ms / t_floor.min_ms);
	fprintf(tf,
	        "memory copy of bilinear's %zu MB of input+output: %.2f ms (best %.2f, cpu %.2f "
	        "ms); bilinear / copy = %.2f (best %.2f)\n",
	        bytes >> 20, t_copy.median_ms, t_copy.min_ms, t_copy.cpu_ms, bil / t_copy.median_ms,
	        bil_min / t_copy.min_ms);
	fprintf(tf, "bilinear into 16-bit planes (exact, x4; 40 MB out): %.2f ms (cpu %.2f ms)\n",
	        t_b16.median_ms, t_b16.cpu_ms);
	if (time_spread)
		fprintf(
		    tf,
		    "planes 64 bytes apart in their pages (docs/api.md; the table's are "
		    "consecutive, each a whole number of pages): bilinear %.2f ms, pan-lean %.2f "
		    "ms = %.2f x bilinear (the table's: %.2f)\n",
		    t_sbil.median_ms, t_slean.median_ms, t_slean.median_ms / t_sbil.median_ms,
		    rows[PC_DM_PAN_LEAN].t.median_ms / bil);
	if (isfinite(t_cv.median_ms))
		fprintf(tf,
		        "%s: %.2f ms (cpu %.2f ms); bilinear / OpenCV = %.2f (cpu %.2f); 16-bit "
		        "bilinear / OpenCV = %.2f (cpu %.2f)\n",
		        cv_note, t_cv.median_ms, t_cv.cpu_ms, bil / t_cv.median_ms,
		        bil_cpu / t_cv.cpu_ms, t_b16.median_ms / t_cv.median_ms,
		        t_b16.cpu_ms / t_cv.cpu_ms);
	else
		fprintf(tf, "OpenCV comparison: %s\n", cv_note);
	if (have_acc)
		fprintf(tf,
		        "our bilinear - double reference bilinear (lapray-nir): I %+.2e dB, S0 "
		        "%+.2e dB, DoLP %+.2e dB\n",
		        ref_gap[0], ref_gap[1], ref_gap[2]);
	fprintf(tf, "load average at end: %s\n", load1);

	json_t *root = json_object();
	json_object_set_new(root, "threads", json_integer(nthreads));
	json_object_set_new(root, "reps", json_integer(reps));
	json_object_set_new(root, "frame", json_string(frame_what));
	json_object_set_new(root, "load_start", json_string(load0));
	json_object_set_new(root, "load_end", json_string(load1));
	json_t *jm = json_array();
	for (size_t i = 0; i < nrows; i++) {
		const method_row *r = &rows[i];
		if (r->skip)
			continue;
		json_t *o = json_object();
		json_object_set_new(o, "method", json_string(pc_demosaic_method_get(r->m)->name));
		json_object_set_new(o, "timed_runs", json_integer(r->once ? 1 : reps));
		json_object_set_new(o, "colour", json_boolean(r->colour));
		json_object_set_new(o, "ms_median", bench_json_real(r->t.median_ms));
		json_object_set_new(o, "ms_best", bench_json_real(r->t.min_ms));
		json_object_set_new(o, "ms_min", bench_json_real(r->t.min_ms));
		json_object_set_new(o, "cpu_ms_median", bench_json_real(r->t.cpu_ms));
		json_object_set_new(o, "x_bilinear", bench_json_real(r->t.median_ms / bil));
		json_t *ja = json_object();
		for (int d = 0; d < r->n_ds; d++) {
			const pc_eval_metrics *a = &r->acc[d];
			json_t *jd = json_object();
			json_object_set_new(jd, "psnr_i", bench_json_real(a->psnr_i));
			json_object_set_new(jd, "psnr_s0", bench_json_real(a->psnr_s0));
			json_object_set_new(jd, "psnr_s1", bench_json_real(a->psnr_s1));
			json_object_set_new(jd, "psnr_s2", bench_json_real(a->psnr_s2));
			json_object_set_new(jd, "psnr_dolp", bench_json_real(a->psnr_dolp));
			json_object_set_new(jd, "aolp_rmse_deg", bench_json_real(a->aolp_rmse_deg));
			json_object_set_new(jd, "aolp_wrmse_deg",
			                    bench_json_real(a->aolp_wrmse_deg));
			if (brow && brow->n_ds > d) {
				json_object_set_new(
				    jd, "d_psnr_s0",
				    bench_json_real(a->psnr_s0 - brow->acc[d].psnr_s0));
				json_object_set_new(
				    jd, "d_psnr_dolp",
				    bench_json_real(a->psnr_dolp - brow->acc[d].psnr_dolp));
			}
			json_object_set_new(ja, r->ds_name[d], jd);
		}
		json_object_set_new(o, "accuracy", ja);
		json_array_append_new(jm, o);
	}
	json_object_set_new(root, "methods", jm);
	if (json_dataset_scenes)
		json_object_set_new(root, "datasets_per_scene", json_dataset_scenes);
	for (int d = 0; d < 2; d++) {
		for (size_t q = 0; dnames[d] && q < dnn[d]; q++)
			free(dnames[d][q]);
		free(dnames[d]);
		free(dres[d]);
	}
	if (have_noisy) {
		json_t *jn = json_array();
		for (size_t q = 0; q < nn; q++)
			json_array_append_new(jn, json_pack("{s:s, s:f, s:f, s:f}", "method",
			                                    pc_demosaic_method_get(nmeth[q])->name,
			                                    "psnr_s0", noisy[q].psnr_s0,
			                                    "dolp_rmse", noisy[q].dolp_rmse,
			                                    "aolp_wrmse_deg", noisy[q].waolp_deg));
		json_object_set_new(root, "noisy_track", jn);
		json_object_set_new(root, "noisy_track_input", json_string(noisy_what));
	}
	json_object_set_new(root, "pipeline_bilinear_ms", bench_json_real(t_pipe[0].median_ms));
	json_object_set_new(root, "pipeline_bilinear_cpu_ms", bench_json_real(t_pipe[0].cpu_ms));
	json_object_set_new(root, "copy_cpu_ms", bench_json_real(t_copy.cpu_ms));
	json_object_set_new(root, "pipeline_floor_ms", bench_json_real(t_floor.median_ms));
	json_object_set_new(root, "pipeline_floor_best_ms", bench_json_real(t_floor.min_ms));
	json_object_set_new(root, "pipeline_floor_cpu_ms", bench_json_real(t_floor.cpu_ms));
	json_object_set_new(root, "pipeline_floor_bytes", json_integer((json_int_t)floor_bytes));
	json_object_set_new(root, "pipeline_floor_stores",
	                    json_string(fj.nt ? "non-temporal" : "ordinary"));
	json_object_set_new(root, "pipeline_bilinear_over_floor",
	                    bench_json_real(t_pipe[0].median_ms / t_floor.median_ms));
	json_object_set_new(root, "pipeline_bilinear_over_floor_best",
	                    bench_json_real(t_pipe[0].min_ms / t_floor.min_ms));
	json_object_set_new(root, "bilinear_u16_ms", bench_json_real(t_b16.median_ms));
	json_object_set_new(root, "bilinear_u16_cpu_ms", bench_json_real(t_b16.cpu_ms));
	if (time_spread) {
		json_t *sp = json_object();
		json_object_set_new(sp, "bilinear_ms", bench_json_real(t_sbil.median_ms));
		json_object_set_new(sp, "pan_lean_ms", bench_json_real(t_slean.median_ms));
		json_object_set_new(sp, "pan_lean_x_bilinear",
		                    bench_json_real(t_slean.median_ms / t_sbil.median_ms));
		json_object_set_new(root, "planes_64_bytes_apart", sp);
	}
	json_object_set_new(root, "bilinear_u16_over_opencv",
	                    bench_json_real(t_b16.median_ms / t_cv.median_ms));
	json_object_set_new(root, "opencv_cpu_ms", bench_json_real(t_cv.cpu_ms));
	json_object_set_new(root, "pipeline_eari_ms", bench_json_real(t_pipe[1].median_ms));
	json_object_set_new(root, "pipeline_bilinear_calibrated_ms",
	                    have_cal ? bench_json_real(t_cal.median_ms) : json_null());
	json_object_set_new(root, "calib_apply_ms",
	                    have_cmp ? bench_json_real(cmp_med[1]) : json_null());
	json_object_set_new(root, "calib_apply_uncalibrated_ms",
	                    have_cmp ? bench_json_real(cmp_med[0]) : json_null());
	json_object_set_new(root, "calib_apply_over_uncalibrated",
	                    have_cmp ? bench_json_real(cmp_med[1] / cmp_med[0]) : json_null());
	json_object_set_new(root, "pipeline_bilinear_calibrated_per_pixel_ms",
	                    have_calpx ? bench_json_real(t_calpx.median_ms) : json_null());
	json_object_set_new(root, "pipeline_bilinear_levels_mask_ms",
	                    bench_json_real(t_lev.median_ms));
	json_object_set_new(root, "cpu_level", json_string(pc_cpu_level_name(pc_cpu_active())));
	json_object_set_new(root, "compiler", json_string(pc_build_compiler()));
	json_object_set_new(root, "pipeline_ratio_ms", bench_json_real(t_pipe[2].median_ms));
	json_object_set_new(root, "pipeline_bilinear_best_ms", bench_json_real(t_pipe[0].min_ms));
	json_object_set_new(root, "pipeline_eari_best_ms", bench_json_real(t_pipe[1].min_ms));
	json_object_set_new(root, "pipeline_ratio_best_ms", bench_json_real(t_pipe[2].min_ms));
	json_object_set_new(root, "copy_best_ms", bench_json_real(t_copy.min_ms));
	json_object_set_new(root, "copy_ms", bench_json_real(t_copy.median_ms));
	json_object_set_new(root, "copy_bytes", json_integer((json_int_t)bytes));
	json_object_set_new(root, "bilinear_over_copy", bench_json_real(bil / t_copy.median_ms));
	json_object_set_new(root, "opencv_ms", bench_json_real(t_cv.median_ms));
	json_object_set_new(root, "opencv", json_string(cv_note));
	json_object_set_new(root, "bilinear_over_opencv", bench_json_real(bil / t_cv.median_ms));
	json_t *jg = json_object();
	json_object_set_new(jg, "psnr_i", bench_json_real(ref_gap[0]));
	json_object_set_new(jg, "psnr_s0", bench_json_real(ref_gap[1]));
	json_object_set_new(jg, "psnr_dolp", bench_json_real(ref_gap[2]));
	json_object_set_new(root, "bilinear_minus_reference_db", jg);

	if (stress_dir) {
		json_t *jst = stress_track(stress_dir, nmeth, nn, (int)threads, tf);
		if (jst)
			json_object_set_new(root, "stress_track", jst);
	} else {
		fprintf(tf, "\nstress track skipped: no --stress DIR, $POLARCAM_STRESS or "
		            "./scenes/stress\n");
	}
	int status = PC_BENCH_OK;
	pc_outdir od;
	if ((rc = pc_outdir_begin(&od, out_dir, overwrite ? PC_OUT_OVERWRITE : 0))) {
		status = host->fail(rc, NULL);
	} else {
		char path[4096];
		snprintf(path, sizeof path, "%s/demosaic.json", od.tmp);
		char *txt = json_dumps(root, JSON_INDENT(1) | JSON_REAL_PRECISION(10));
		if (!txt || (rc = pc_write_file_atomic(path, txt, strlen(txt))))
			status = host->fail(rc ? rc : PC_ENOMEM, path);
		free(txt);
		if (have_acc && brow) {
			snprintf(path, sizeof path, "%s/pareto_s0.png", od.tmp);
			pareto_plot(path, rows, nrows, 0, 0, bil);
			snprintf(path, sizeof path, "%s/pareto_dolp.png", od.tmp);
			pareto_plot(path, rows, nrows, 0, 1, bil);
		}
		if (status == PC_BENCH_OK && (rc = pc_outdir_commit(&od)))
			status = host->fail(rc, NULL);
		pc_outdir_abort(&od);
		fprintf(tf, "wrote %s/demosaic.json%s\n", out_dir,
		        have_acc ? ", pareto_s0.png, pareto_dolp.png" : "");
	}
	if (json_out)
		host->print_json(root);
	else
		json_decref(root);
	return status;
}
