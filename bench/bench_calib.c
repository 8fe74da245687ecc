/* polarcam bench calib: what analyser-calibration accuracy costs. For K polarizer angles
 * (evenly over 180°) × F frames per angle, the residual DoLP and AoLP errors of DoLP-0.5
 * stimuli at 4 other AoLPs (64 frames averaged, bilinear) after dark + flat + analyser
 * calibration of the imx250mzr_nonuniform preset, and the acquisition time of the sweep at the
 * sensor's frame rate plus a stated time per polarizer rotation. No timing is measured: the
 * acquisition time is computed. */
#include <getopt.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "polarcam/sim.h"

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

#define DEG (M_PI / 180)

/* the scenes/calib stimuli, built here so that the benchmark runs from any directory */
static const char *const scene_fmt =
    "{\"camera\": {\"position\": [0, 0, 1], \"direction\": [0, 1, 0], \"focal_length_mm\": 50},"
    " \"materials\": {\"unused\": {\"n\": 1.5, \"sigma\": 0.2}},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], \"irradiance_w_m2\": 1}],"
    " \"background\": %g, \"effects\": {\"circular\": true},"
    " \"sensor\": {\"preset\": \"imx250mzr_nonuniform\", \"offset_dn\": 60, \"exposure_us\": 10000"
    "%s}}";

typedef struct bstack {
	pc_sim *sim;
	pc_sim_info info;
	uint64_t first;
	char name[64];
	pc_calib_stack s;
} bstack;

static int bget(void *user, size_t i, pc_view *out)
{
	bstack *b = user;
	int rc = pc_view_alloc(out, b->info.format, b->info.width, b->info.height, 64);
	if (!rc && (rc = pc_sim_frame(b->sim, b->first + i, NULL, out, NULL)))
		pc_view_free(out);
	return rc;
}

static int bopen(bstack *b, double bg, const char *psa, uint32_t size, size_t n, uint64_t first,
                 double angle, double dolp)
{
	memset(b, 0, sizeof *b);
	char text[1024], extra[256] = "";
	if (psa)
		snprintf(extra, sizeof extra, ", \"psa\": [%s]", psa);
	snprintf(text, sizeof text, scene_fmt, bg, extra);
	pc_scene *sc;
	int rc = pc_scene_parse(text, "bench-calib", NULL, &sc);
	if (rc)
		return rc;
	pc_sim_options o = pc_sim_options_default();
	o.seed = 7;
	o.roi_x = 1000;
	o.roi_y = 800;
	o.roi_width = o.roi_height = size;
	rc = pc_sim_new(sc, &o, &b->sim);
	pc_scene_free(sc);
	if (rc)
		return rc;
	pc_sim_get_info(b->sim, &b->info);
	b->first = first;
	snprintf(b->name, sizeof b->name, "stimulus %.1f", angle);
	pc_calib_stack *s = &b->s;
	s->name = b->name;
	s->geo.width = b->info.width;
	s->geo.height = b->info.height;
	s->geo.offset_x = b->info.offset_x;
	s->geo.offset_y = b->info.offset_y;
	s->geo.sensor_width = b->info.sensor_width;
	s->geo.sensor_height = b->info.sensor_height;
	s->geo.bits = b->info.bits;
	s->geo.mosaic = b->info.mosaic;
	s->n = n;
	s->get = bget;
	s->user = b;
	s->exposure_us = b->info.exposure_us;
	s->angle_deg = angle;
	s->dolp = dolp;
	return 0;
}

/* One W⁺ per 2×2 super-pixel for the bilinear pipeline: the mean of the block's four
 * per-pixel W⁺ (pc_calib_pinv), as a W/2 × H/2 grid (12 floats per block, 12 bytes per pixel
 * instead of 48). */
static int block_pinv(pc_calib *cal, float **out)
{
	pc_analyser_pinv pp;
	int rc = pc_calib_pinv(cal, PC_DM_BILINEAR, 0, &pp);
	if (rc)
		return rc;
	const uint32_t W = pp.grid_w, H = pp.grid_h, gw = W / 2, gh = H / 2;
	const size_t np = (size_t)W * H, nb = (size_t)gw * gh;
	float *b = malloc(12 * nb * sizeof *b);
	if (!b)
		return PC_ENOMEM;
	for (size_t e = 0; e < 12; e++)
		for (uint32_t by = 0; by < gh; by++)
			for (uint32_t bx = 0; bx < gw; bx++) {
				const float *m = pp.m + e * np + (size_t)2 * by * W + 2 * bx;
				b[e * nb + (size_t)by * gw + bx] =
				    0.25f * ((m[0] + m[1]) + (m[W] + m[W + 1]));
			}
	*out = b;
	return 0;
}

/* The calibrated bilinear pipeline with the analysers from grid instead of the calibration's
 * own (pc_calib_apply's correction: the dark map and the inverse gains; no flags). */
static int stokes_with_pinv(pc_calib *cal, const pc_view *raw, const pc_analyser_pinv *grid,
                            const pc_stokes_out *out)
{
	int rc = pc_calib_prepare(cal, PC_DM_BILINEAR, 0); /* the inverse gains */
	if (rc)
		return rc;
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.mosaic = cal->geo.mosaic;
	po.dark = cal->dark;
	po.gain_inv = cal->apply_ig;
	po.black_level = cal->dark ? 0 : cal->black_level;
	po.pinv = grid;
	return pc_stokes_run(raw, &po, out, NULL);
}

/* RMS DoLP and AoLP errors of the averaged stimulus over the interior */
/* (grid: the analysers from it, stokes_with_pinv; NULL: the calibration's, pc_calib_stokes) */
static int errors(pc_calib *cal, const pc_analyser_pinv *grid, bstack *t, size_t frames,
                  double angle, double *ed, double *ea)
{
	const uint32_t W = t->info.width, H = t->info.height;
	const size_t np = (size_t)W * H;
	pc_view avg;
	int rc = pc_view_alloc(&avg, PC_FMT_FLOAT32, W, H, 64);
	float *acc = calloc(np, sizeof *acc), *row = malloc(np * sizeof *row);
	float *buf = malloc(5 * np * sizeof *buf);
	if (rc || !acc || !row || !buf) {
		free(acc);
		free(row);
		free(buf);
		pc_view_free(&avg);
		return rc ? rc : PC_ENOMEM;
	}
	for (size_t i = 0; i < frames && !rc; i++) {
		pc_view v;
		if ((rc = bget(t, i, &v)))
			break;
		rc = pc_view_to_f32(&v, row, W * sizeof(float));
		pc_view_free(&v);
		for (size_t p = 0; p < np; p++)
			acc[p] += row[p] / (float)frames;
	}
	for (uint32_t y = 0; y < H; y++)
		memcpy((char *)avg.data + y * avg.stride, acc + (size_t)y * W, W * sizeof(float));
	pc_stokes_out out = {0};
	pc_fplane *pl[5] = {&out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp};
	for (int k = 0; k < 5; k++) {
		pl[k]->data = buf + (size_t)k * np;
		pl[k]->row_stride = W;
		pl[k]->pixel_stride = 1;
	}
	if (!rc)
		rc = grid ? stokes_with_pinv(cal, &avg, grid, &out)
		          : pc_calib_stokes(cal, &avg, NULL, PC_DM_BILINEAR, 0, &out, NULL, NULL);
	double sd = 0, sa = 0;
	size_t n = 0;
	for (uint32_t y = 2; !rc && y + 2 < H; y++)
		for (uint32_t x = 2; x + 2 < W; x++) {
			size_t p = (size_t)y * W + x;
			double d = out.dolp.data[p] - 0.5;
			double a = remainder(out.aolp.data[p] - angle * DEG, M_PI) / DEG;
			sd += d * d;
			sa += a * a;
			n++;
		}
	*ed = n ? sqrt(sd / (double)n) : NAN;
	*ea = n ? sqrt(sa / (double)n) : NAN;
	free(acc);
	free(row);
	free(buf);
	pc_view_free(&avg);
	return rc;
}

/* ---- --speed: the calibrated pipeline against the uncalibrated one, same run ---- */

/* A synthetic full-sensor calibration (dark 60 DN ± 2, gain 1 ± 2 %, analysers with ±1°
 * orientation and extinction 0.93 to 0.99, one pixel in 10^4 distrusted) and a 12-bit frame
 * (values 200 to 3000, one sample in 10^4 at full scale): the timing does not depend on the
 * values, the validity work does on their flags. */
static int speed_setup(uint32_t W, uint32_t H, pc_calib *cal, pc_view *raw)
{
	const size_t np = (size_t)W * H;
	pc_calib_init(cal);
	cal->geo = (pc_calib_geometry){W, H, 0, 0, W, H, 12, pc_mosaic_imx250mzr()};
	cal->black_level = 60;
	cal->saturation = 4095;
	cal->parts = PC_CAL_DARK | PC_CAL_FLAT | PC_CAL_ANALYSER;
	cal->dark = malloc(np * sizeof(float));
	cal->gain = malloc(np * sizeof(float));
	cal->analysis = malloc(3 * np * sizeof(float));
	cal->pinv_sp = malloc(3 * np * sizeof(float)); /* (3, 4, H/2, W/2): not used by bilinear */
	cal->valid = malloc(np);
	int rc = pc_view_alloc(raw, PC_FMT_MONO12, W, H, 64);
	if (rc || !cal->dark || !cal->gain || !cal->analysis || !cal->pinv_sp || !cal->valid) {
		if (!rc)
			pc_view_free(raw);
		pc_calib_free(cal);
		return rc ? rc : PC_ENOMEM;
	}
	uint64_t st = 0x9e3779b97f4a7c15ull;
	for (uint32_t y = 0; y < H; y++) {
		uint16_t *r = PC_ROW(raw, uint16_t, y);
		for (uint32_t x = 0; x < W; x++) {
			size_t p = (size_t)y * W + x;
			st = st * 6364136223846793005ull + 1442695040888963407ull;
			double u = (double)(st >> 11) / 9007199254740992.0;
			double v = (double)((st >> 7) & 0xffff) / 65536.0;
			unsigned c = pc_mosaic_channel(&cal->geo.mosaic, x, y);
			double th = c * M_PI / 4 + (u - 0.5) * 2 * DEG, ex = 0.93 + 0.06 * v;
			cal->dark[p] = (float)(60 + 4 * (u - 0.5));
			cal->gain[p] = (float)(1 + 0.04 * (v - 0.5));
			cal->analysis[3 * p] = 0.5f;
			cal->analysis[3 * p + 1] = (float)(0.5 * ex * cos(2 * th));
			cal->analysis[3 * p + 2] = (float)(0.5 * ex * sin(2 * th));
			cal->valid[p] = (st >> 40) % 10000 != 0;
			r[x] = (st >> 24) % 10000 == 0 ? 4095 : (uint16_t)(200 + 2800 * u);
		}
	}
	for (size_t k = 0; k < 3 * np; k++)
		cal->pinv_sp[k] = 0;
	return 0;
}

/* The --speed setup: speed_setup's calibration and frame, 64-byte-aligned planar outputs and a
 * mask, the frame, and the options of the two pipelines: po the calibrated one (bilinear, the
 * saturation check), pu the uncalibrated one as `polarcam process` runs it (po plus the black
 * level). */
typedef struct speed_case {
	pc_calib cal;
	pc_view raw;
	float *planes;
	uint8_t *mask;
	pc_stokes_out out;
	pc_frame f;
	pc_pipeline_opts po, pu;
} speed_case;

static void speed_close(speed_case *s)
{
	free(s->planes);
	free(s->mask);
	pc_view_free(&s->raw);
	pc_calib_free(&s->cal);
}

static int speed_open(speed_case *s, uint32_t w, uint32_t h, int threads)
{
	memset(s, 0, sizeof *s);
	int rc = speed_setup(w, h, &s->cal, &s->raw);
	if (rc)
		return rc;
	const size_t np = (size_t)w * h;
	s->mask = malloc(np);
	if (posix_memalign((void **)&s->planes, 64, 5 * np * sizeof(float)) || !s->mask) {
		s->planes = NULL; /* unspecified on failure */
		speed_close(s);
		return PC_ENOMEM;
	}
	pc_fplane *pl[5] = {&s->out.s0, &s->out.s1, &s->out.s2, &s->out.dolp, &s->out.aolp};
	for (int k = 0; k < 5; k++)
		*pl[k] = (pc_fplane){s->planes + (size_t)k * np, w, 1};
	s->f.view = s->raw;
	s->f.mosaic = s->cal.geo.mosaic;
	s->po = pc_pipeline_defaults();
	s->po.threads = threads;
	s->po.method = PC_DM_BILINEAR;
	s->po.mosaic = s->cal.geo.mosaic;
	s->po.saturation_level = 4095;
	s->pu = s->po;
	s->pu.black_level = 60;
	return 0;
}

int bench_calib_pair(uint32_t w, uint32_t h, int reps, int threads, double med_ms[2],
                     double min_ms[2])
{
	speed_case s;
	int rc = speed_open(&s, w, h, threads);
	if (rc)
		return rc;
	double *t = reps > 0 ? malloc(2 * (size_t)reps * sizeof *t) : NULL;
	pc_validity v = {s.mask, w, 0};
	if (!t)
		rc = PC_ENOMEM;
	else /* prepared once */
		rc = pc_calib_apply(&s.cal, &s.f, 12, &s.po, &s.out, NULL, &v);
	for (int r = 0; r < reps && !rc; r++)
		for (int k = 0; k < 2 && !rc; k++) { /* interleaved */
			v = (pc_validity){s.mask, w, 0};
			double t0 = bench_now();
			rc = k ? pc_calib_apply(&s.cal, &s.f, 12, &s.po, &s.out, NULL, &v)
			       : pc_stokes_run(&s.raw, &s.pu, &s.out, &v);
			t[(size_t)k * (size_t)reps + (size_t)r] = bench_now() - t0;
		}
	for (int k = 0; k < 2 && !rc; k++) {
		double *tk = t + (size_t)k * (size_t)reps;
		qsort(tk, (size_t)reps, sizeof *tk, bench_cmp_double);
		min_ms[k] = 1e3 * tk[0];
		med_ms[k] = 1e3 * tk[reps / 2];
	}
	free(t);
	speed_close(&s);
	return rc;
}

/* CPU time of the whole process (every thread), seconds */
static double cpu_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int bench_speed(uint32_t W, uint32_t H, int reps, int threads, bool json, const char *only)
{
	speed_case sc;
	int rc = speed_open(&sc, W, H, threads);
	if (rc)
		return host->fail(rc, "bench calib --speed");
	pc_calib *cal = &sc.cal;
	const pc_view raw = sc.raw;
	uint8_t *mask = sc.mask;
	pc_stokes_out out = sc.out;
	pc_frame f = sc.f;
	pc_pipeline_opts po = sc.po, pu = sc.pu;
	enum { IDEAL, IDEAL_NOMASK, CAL, CAL_NOMASK, CAL_PINV, CAL_SP, NCASE };
	static const char *const name[NCASE] = {"ideal",           "ideal_no_mask",
	                                        "calibrated",      "calibrated_no_mask",
	                                        "calibrated_pinv", "calibrated_2x2"};
	int one = -1; /* --only: one case (for perf stat) */
	for (int k = 0; only && k < NCASE; k++)
		if (!strcmp(only, name[k]))
			one = k;
	if (only && one < 0) {
		speed_close(&sc);
		return host->error(PC_BENCH_USAGE,
		                   "--only %s: expected ideal, ideal_no_mask, "
		                   "calibrated, calibrated_no_mask, calibrated_pinv or "
		                   "calibrated_2x2",
		                   only);
	}
	/* the alternatives, the fused pipeline with the calibration's dark and 1/gain and no flags:
	 * the float per-pixel W⁺ (pc_calib_pinv, 48 bytes per pixel: the path before the 16-bit
	 * analysis vectors), and one W⁺ per 2×2 super-pixel (block_pinv; fast, not accurate
	 * enough) */
	float *bp = NULL;
	pc_pipeline_opts ps = po, pp = po;
	pc_analyser_pinv pxgrid = {0};
	double *t = calloc(2 * (size_t)NCASE * (size_t)reps, sizeof *t), best[NCASE], med[NCASE];
	double cbest[NCASE], cmed[NCASE];
	uint64_t inval[NCASE] = {0};
	if (!t) {
		rc = PC_ENOMEM;
		goto out;
	}
	/* warm-up: what is computed once per calibration (the 16-bit analysis vectors) */
	pc_validity v = {mask, W, 0};
	double t0 = bench_now();
	if ((rc = pc_calib_apply(cal, &f, 12, &po, &out, NULL, &v)))
		goto out;
	double prep = bench_now() - t0;
	/* (with --only, the cases that need them) */
	const bool want_px = one < 0 || one == CAL_PINV || one == CAL_SP;
	t0 = bench_now();
	if (want_px && (rc = pc_calib_pinv(cal, PC_DM_BILINEAR, 0, &pxgrid)))
		goto out;
	double prep_pinv = bench_now() - t0;
	if (want_px && (rc = block_pinv(cal, &bp)))
		goto out;
	pc_analyser_pinv bgrid = {bp, W / 2, H / 2};
	ps.dark = pp.dark = cal->dark;
	ps.gain_inv = pp.gain_inv = cal->apply_ig;
	ps.pinv = &bgrid;
	pp.pinv = &pxgrid;
	for (int r = 0; r < reps; r++)
		for (int k = 0; k < NCASE; k++) { /* interleaved: load drifts hit every case */
			if (one >= 0 && k != one)
				continue;
			v = (pc_validity){mask, W, 0};
			pc_validity *vp = k == IDEAL || k == CAL || k == CAL_SP ? &v : NULL;
			t0 = bench_now();
			double c0 = cpu_now();
			rc = k <= IDEAL_NOMASK ? pc_stokes_run(&raw, &pu, &out, vp)
			     : k == CAL_SP     ? pc_stokes_run(&raw, &ps, &out, vp)
			     : k == CAL_PINV   ? pc_stokes_run(&raw, &pp, &out, NULL)
			                       : pc_calib_apply(cal, &f, 12, &po, &out, NULL, vp);
			t[(size_t)k * (size_t)reps + (size_t)r] = bench_now() - t0;
			t[(size_t)(NCASE + k) * (size_t)reps + (size_t)r] = cpu_now() - c0;
			if (rc)
				goto out;
			inval[k] = v.n_invalid;
		}
	for (int k = 0; k < NCASE; k++) {
		double *tk = t + (size_t)k * (size_t)reps;
		qsort(tk, (size_t)reps, sizeof *tk, bench_cmp_double);
		best[k] = tk[0];
		med[k] = tk[reps / 2];
		tk = t + (size_t)(NCASE + k) * (size_t)reps;
		qsort(tk, (size_t)reps, sizeof *tk, bench_cmp_double);
		cbest[k] = tk[0];
		cmed[k] = tk[reps / 2];
	}
	double load[3];
	bench_loadavg_values(load);
	if (json) {
		json_t *j = json_object();
		json_object_set_new(j, "width", json_integer(W));
		json_object_set_new(j, "height", json_integer(H));
		json_object_set_new(j, "repetitions", json_integer(reps));
		json_object_set_new(j, "load_1min", bench_json_real(load[0]));
		json_object_set_new(j, "prepare_ms", bench_json_real(1e3 * prep));
		json_object_set_new(j, "pinv_prepare_ms", bench_json_real(1e3 * prep_pinv));
		for (int k = 0; k < NCASE; k++) {
			char key[64];
			snprintf(key, sizeof key, "%s_ms_min", name[k]);
			json_object_set_new(j, key, bench_json_real(1e3 * best[k]));
			snprintf(key, sizeof key, "%s_ms_median", name[k]);
			json_object_set_new(j, key, bench_json_real(1e3 * med[k]));
			snprintf(key, sizeof key, "%s_cpu_ms_min", name[k]);
			json_object_set_new(j, key, bench_json_real(1e3 * cbest[k]));
			snprintf(key, sizeof key, "%s_cpu_ms_median", name[k]);
			json_object_set_new(j, key, bench_json_real(1e3 * cmed[k]));
		}
		json_object_set_new(j, "ratio_min", bench_json_real(best[CAL] / best[IDEAL]));
		json_object_set_new(j, "ratio_median", bench_json_real(med[CAL] / med[IDEAL]));
		json_object_set_new(j, "ratio_no_mask_median",
		                    bench_json_real(med[CAL_NOMASK] / med[IDEAL_NOMASK]));
		json_object_set_new(j, "cpu_ratio_no_mask_min",
		                    bench_json_real(cbest[CAL_NOMASK] / cbest[IDEAL_NOMASK]));
		json_object_set_new(j, "cpu_ratio_pinv_no_mask_min",
		                    bench_json_real(cbest[CAL_PINV] / cbest[IDEAL_NOMASK]));
		json_object_set_new(j, "ratio_pinv_no_mask_median",
		                    bench_json_real(med[CAL_PINV] / med[IDEAL_NOMASK]));
		json_object_set_new(j, "ratio_2x2_median",
		                    bench_json_real(med[CAL_SP] / med[IDEAL]));
		json_object_set_new(j, "ratio_2x2_min",
		                    bench_json_real(best[CAL_SP] / best[IDEAL]));
		host->print_json(j);
	} else {
		printf("bilinear Stokes pipeline, %ux%u Mono12, planar S0 S1 S2 DoLP AoLP, %d "
		       "threads, "
		       "%d repetitions interleaved (load %.2f %.2f %.2f)\n",
		       W, H, threads > 0 ? threads : pc_parallel_max_threads(), reps, load[0],
		       load[1], load[2]);
		printf("  prepared once: 16-bit analysis vectors (first call, checked) %.1f ms; "
		       "float per-pixel W+ (calibrated_pinv) %.1f ms\n",
		       1e3 * prep, 1e3 * prep_pinv);
		for (int k = 0; k < NCASE; k++)
			printf(
			    "  %-20s min %7.2f ms  median %7.2f ms  (cpu min %7.2f, median %7.2f "
			    "ms)  invalid %llu\n",
			    name[k], 1e3 * best[k], 1e3 * med[k], 1e3 * cbest[k], 1e3 * cmed[k],
			    (unsigned long long)inval[k]);
		printf("calibrated / ideal (black level, saturation check, mask): %.2f (min %.2f); "
		       "goal <= 1.5\nwithout the mask: %.2f (min %.2f)\n",
		       med[CAL] / med[IDEAL], best[CAL] / best[IDEAL],
		       med[CAL_NOMASK] / med[IDEAL_NOMASK], best[CAL_NOMASK] / best[IDEAL_NOMASK]);
		printf(
		    "float per-pixel W+ (the previous path) / ideal, without the mask: %.2f (min "
		    "%.2f)\n",
		    med[CAL_PINV] / med[IDEAL_NOMASK], best[CAL_PINV] / best[IDEAL_NOMASK]);
		printf("one W+ per 2x2 super-pixel (experiment) / ideal: %.2f (min %.2f)\n",
		       med[CAL_SP] / med[IDEAL], best[CAL_SP] / best[IDEAL]);
		printf("cpu time, min, without the mask: calibrated / ideal %.2f, previous path / "
		       "ideal %.2f\n",
		       cbest[CAL_NOMASK] / cbest[IDEAL_NOMASK],
		       cbest[CAL_PINV] / cbest[IDEAL_NOMASK]);
	}
out:
	free(bp);
	free(t);
	speed_close(&sc);
	return rc ? host->fail(rc, "bench calib --speed") : PC_BENCH_OK;
}

int pc_bench_calib(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	static const struct option opts[] = {{"size", required_argument, NULL, 's'},
	                                     {"rotation-s", required_argument, NULL, 'r'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {"speed", no_argument, NULL, 'S'},
	                                     {"reps", required_argument, NULL, 'n'},
	                                     {"only", required_argument, NULL, 'o'},
	                                     {"threads", required_argument, NULL, 't'},
	                                     {"help", no_argument, NULL, 'h'},
	                                     {NULL, 0, NULL, 0}};
	long size = 64, reps = 10, threads = 0;
	double rot_s = 2;
	bool json = false, speed = false;
	const char *only = NULL;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":h", opts, NULL)) != -1) {
		switch (c) {
		case 's':
			if ((rc = host->parse_long("--size", optarg, 8, 1024, &size)))
				return host->fail(rc, NULL);
			size &= ~1L;
			break;
		case 'r':
			if ((rc = host->parse_double("--rotation-s", optarg, &rot_s)))
				return host->fail(rc, NULL);
			break;
		case 'J':
			json = true;
			break;
		case 'S':
			speed = true;
			break;
		case 'o':
			only = optarg;
			break;
		case 't':
			if ((rc = host->parse_long("--threads", optarg, 0, 256, &threads)))
				return host->fail(rc, NULL);
			break;
		case 'n':
			if ((rc = host->parse_long("--reps", optarg, 1, 1000, &reps)))
				return host->fail(rc, NULL);
			break;
		case 'h':
			printf(
			    "usage: polarcam bench calib [--size N] [--rotation-s S] [--json]\n"
			    "       polarcam bench calib --speed [--reps N] [--threads T] [--only "
			    "CASE] "
			    "[--json]\n\n"
			    "--speed: the calibrated bilinear pipeline (pc_calib_apply: the "
			    "compact\n"
			    "calibration - 16-bit dark, gain and analysis vectors, a weighted "
			    "least "
			    "squares over each pixel's 3x3 samples - and\n"
			    "the saturation and distrusted-pixel mask) against the uncalibrated "
			    "one\n"
			    "(pc_stokes_run with the black level and the saturation mask) on a "
			    "2448x2048\n"
			    "Mono12 frame, N repetitions each, interleaved (default 10), T threads "
			    "(default\n"
			    "0: all): wall and process CPU time, min and median, and their ratios "
			    "(goal\n"
			    "<= 1.5), with the load average. calibrated_pinv: the previous path "
			    "(float dark\n"
			    "and gain maps, float per-pixel W+; no mask); calibrated_2x2: one W+ "
			    "per 2x2\n"
			    "super-pixel (the block mean of the four per-pixel ones; an "
			    "experiment). --only\n"
			    "CASE runs one case (ideal, ideal_no_mask, calibrated, "
			    "calibrated_no_mask,\n"
			    "calibrated_pinv, calibrated_2x2), e.g. under perf stat. Without "
			    "--speed:\n"
			    "Analyser calibration of the imx250mzr_nonuniform preset (N x N ROI, "
			    "default\n"
			    "64; dark and flat: 32 frames each) with K polarizer angles x F frames "
			    "per\n"
			    "angle: residual DoLP and AoLP RMS errors on DoLP-0.5 stimuli at 10, "
			    "55, 100\n"
			    "and 145 deg (64 frames averaged), and the sweep's acquisition time: "
			    "K*F\n"
			    "frames at the sensor's 30 fps plus S seconds per polarizer rotation\n"
			    "(default 2, a manual or motorised rotation mount).\n");
			return PC_BENCH_OK;
		default:
			return host->error(PC_BENCH_USAGE, "bad option '%s' (see --help)",
			                   argv[optind - 1]);
		}
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	if (speed)
		return bench_speed(2448, 2048, (int)reps, (int)threads, json, only);
	const uint32_t S = (uint32_t)size;
	bstack dk, fl, fh;
	pc_calib dark, flat;
	if ((rc = bopen(&dk, 0, NULL, S, 32, 1000000, NAN, NAN)) ||
	    (rc = bopen(&fl, 0.55, NULL, S, 32, 2000000, NAN, NAN)) ||
	    (rc = bopen(&fh, 1.25, NULL, S, 32, 3000000, NAN, NAN)))
		return host->fail(rc, "bench calib");
	if ((rc = pc_calib_dark(&dk.s, NULL, &dark)))
		return host->fail(rc, "dark");
	pc_calib_stack lv[2] = {fl.s, fh.s};
	if ((rc = pc_calib_flat(lv, 2, &dark, NULL, &flat)))
		return host->fail(rc, "flat");
	static const double tang[4] = {10, 55, 100, 145};
	bstack ts[4];
	for (int k = 0; k < 4; k++) {
		char psa[128];
		snprintf(psa, sizeof psa,
		         "{\"diattenuator\": {\"angle_deg\": %g, \"diattenuation\": 0.5}}",
		         tang[k]);
		if ((rc = bopen(&ts[k], 1.7, psa, S, 64, 4000000 + 100000 * k, tang[k], 0.5)))
			return host->fail(rc, "test stimuli");
	}
	/* the uncalibrated baseline: black level only */
	pc_calib base;
	pc_calib_init(&base);
	base.geo = flat.geo;
	base.black_level = dark.black_level;
	base.saturation = flat.saturation;
	double ud = 0, ua = 0;
	for (int k = 0; k < 4; k++) {
		double ed, ea;
		if ((rc = errors(&base, NULL, &ts[k], 64, tang[k], &ed, &ea)))
			return host->fail(rc, "uncalibrated");
		ud += ed * ed / 4;
		ua += ea * ea / 4;
	}
	static const unsigned Ks[] = {3, 4, 6, 8, 12, 16}, Fs[] = {1, 4, 16, 64};
	json_t *rows = json_array();
	if (!json)
		printf(
		    "analyser calibration, %ux%u ROI, imx250mzr_nonuniform, DoLP-0.5 test stimuli\n"
		    "uncalibrated (black level only): DoLP RMS %.5f, AoLP RMS %.3f deg\n\n"
		    "calibrated: what the pipeline runs (16-bit analysis vectors, weighted least "
		    "squares per pixel); W+: the float per-pixel W+ (pc_calib_pinv); 2x2: one W+ "
		    "per 2x2 "
		    "block, the mean of its four\n\n"
		    "%3s %4s %7s %10s %11s %12s %11s %12s %11s %12s\n",
		    S, S, sqrt(ud), sqrt(ua), "K", "F", "frames", "time (s)", "DoLP RMS",
		    "AoLP RMS deg", "W+ DoLP", "W+ AoLP deg", "2x2 DoLP", "2x2 AoLP deg");
	for (size_t i = 0; i < sizeof Ks / sizeof Ks[0]; i++)
		for (size_t j = 0; j < sizeof Fs / sizeof Fs[0]; j++) {
			unsigned K = Ks[i], F = Fs[j];
			bstack st[16];
			pc_calib_stack stk[16];
			for (unsigned k = 0; k < K; k++) {
				double a = 180.0 * k / K;
				char psa[64];
				snprintf(psa, sizeof psa, "{\"polarizer_deg\": %.6g}", a);
				if ((rc = bopen(&st[k], 1.2, psa, S, F, 5000000 + 10000 * k, a, 1)))
					return host->fail(rc, "stimuli");
				stk[k] = st[k].s;
			}
			pc_calib cal;
			rc = pc_calib_analyser(stk, K, &flat, NULL, &cal, NULL);
			for (unsigned k = 0; k < K; k++)
				pc_sim_free(st[k].sim);
			if (rc)
				return host->fail(rc, "analyser");
			double cd = 0, ca = 0;
			for (int k = 0; k < 4; k++) {
				double ed, ea;
				if ((rc = errors(&cal, NULL, &ts[k], 64, tang[k], &ed, &ea)))
					return host->fail(rc, "calibrated");
				cd += ed * ed / 4;
				ca += ea * ea / 4;
			}
			/* the same with the float per-pixel W⁺ (pc_calib_pinv) and with one W⁺ per
			 * 2×2 super-pixel (block_pinv) */
			double pd = 0, pa = 0, bd = 0, ba = 0;
			float *bp = NULL;
			pc_analyser_pinv pp, bg;
			if ((rc = pc_calib_pinv(&cal, PC_DM_BILINEAR, 0, &pp)) ||
			    (rc = block_pinv(&cal, &bp)))
				return host->fail(rc, "per-pixel and per-super-pixel W+");
			bg = (pc_analyser_pinv){bp, pp.grid_w / 2, pp.grid_h / 2};
			for (int k = 0; k < 4 && !rc; k++) {
				double ed, ea, fd, fa;
				if ((rc = errors(&cal, &pp, &ts[k], 64, tang[k], &fd, &fa)) ||
				    (rc = errors(&cal, &bg, &ts[k], 64, tang[k], &ed, &ea)))
					break;
				pd += fd * fd / 4;
				pa += fa * fa / 4;
				bd += ed * ed / 4;
				ba += ea * ea / 4;
			}
			free(bp);
			if (rc)
				return host->fail(rc, "calibrated per pixel / super-pixel");
			pc_calib_free(&cal);
			double tsec = K * F / 30.0 + K * rot_s;
			if (json) {
				json_t *r = json_object();
				json_object_set_new(r, "angles", json_integer(K));
				json_object_set_new(r, "frames_per_angle", json_integer(F));
				json_object_set_new(r, "acquisition_s", json_real(tsec));
				json_object_set_new(r, "dolp_rms", json_real(sqrt(cd)));
				json_object_set_new(r, "aolp_rms_deg", json_real(sqrt(ca)));
				json_object_set_new(r, "pinv_dolp_rms", json_real(sqrt(pd)));
				json_object_set_new(r, "pinv_aolp_rms_deg", json_real(sqrt(pa)));
				json_object_set_new(r, "superpixel_dolp_rms", json_real(sqrt(bd)));
				json_object_set_new(r, "superpixel_aolp_rms_deg",
				                    json_real(sqrt(ba)));
				json_array_append_new(rows, r);
			} else {
				printf("%3u %4u %7u %10.1f %11.5f %12.4f %11.5f %12.4f %11.5f "
				       "%12.4f\n",
				       K, F, K * F, tsec, sqrt(cd), sqrt(ca), sqrt(pd), sqrt(pa),
				       sqrt(bd), sqrt(ba));
				fflush(stdout);
			}
		}
	if (json) {
		json_t *o = json_object();
		json_object_set_new(o, "size", json_integer(S));
		json_object_set_new(o, "uncalibrated_dolp_rms", json_real(sqrt(ud)));
		json_object_set_new(o, "uncalibrated_aolp_rms_deg", json_real(sqrt(ua)));
		json_object_set_new(o, "rows", rows);
		host->print_json(o);
	} else {
		json_decref(rows);
	}
	for (int k = 0; k < 4; k++)
		pc_sim_free(ts[k].sim);
	pc_sim_free(dk.sim);
	pc_sim_free(fl.sim);
	pc_sim_free(fh.sim);
	pc_calib_free(&dark);
	pc_calib_free(&flat);
	return PC_BENCH_OK;
}
