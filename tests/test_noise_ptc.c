/* ratio-nr's noise model: the frame's photon-transfer line (pc_dm_noise_ptc,
 * core/demosaic_noise.h; docs/demosaicking.md, Round 40), against values obtained independently
 * of the estimator.
 *
 * 1. The slope against the temporal noise of two frames. The simulator's frames N = 0 and 1
 *    carry independent temporal noise (shot, read, dark current) and the same fixed pattern
 *    (PRNU, DSNU, analyser errors: keyed by the pixel alone), so d = f₀ − f₁ is temporal noise
 *    only and the scene cancels exactly. Its variance at level L is 2·σ²(L); the line fitted
 *    by least squares to mean(d²)/2 over 16 level groups of all pixels gives the temporal
 *    slope a_t, which must be the sensor's system gain K = K₀·10^(gain/20) within 10 % (the
 *    truth is what the preset declares). The estimate from f₀ alone must lie within [0.75,
 *    1.3]·a_t (measured 0.81–1.08): the fit's scatter from its 8192 blocks (largest on the
 *    dark frame at 24 dB, 0.81, whose levels span little of the line while the read noise
 *    dominates), above by what the fixed pattern adds to one frame's spatial variance (PRNU
 *    0.7 % adds (0.007·L)², DSNU 1.5 e⁻, both part of the noise a demosaicker sees) and by the
 *    chart's remaining texture. The chart (scenes/stress/chart.json) through the IMX250MZR
 *    preset with a black level of 64 DN, so that no sample clips at zero, at two exposures
 *    and 0, 12 and 24 dB of gain (the mean level held: the exposure divided by the gain).
 * 2. A noise-free render (the chart through the ideal sensor) gives exactly 0, and ratio-nr
 *    is then ratio bit for bit (its guide is not shrunk), fast path and reference. At a tenth
 *    of the chart's exposure (25 µs), where no sample clips: where clipping splits the
 *    analysers ratio-nr's first guide is the binomial, not ratio's (Round 46; the chart's
 *    glints at 250 µs), which test_demosaic's test_ratio_nr_clipped covers.
 * 3. The model is the front door's: a given noise gain equal to the estimate gives the same
 *    outputs bit for bit, the reported gain (noise_gain_used) is the estimate, the same on the
 *    fast path and the reference, and pc_demosaic_noise_gain returns it.
 * 4. One level only (a flat field): the slope falls back to the line through the origin.
 * 5. Frames with nothing to fit (black, saturated, a black/saturated checker, too small) give 0
 *    and ratio-nr's outputs stay finite. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"
#include "polarcam/sim.h"

#define BLACK 64.0

static char src_dir[2048];

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static double at(const pc_view *v, uint32_t x, uint32_t y)
{
	return PC_ROW(v, uint16_t, y)[x];
}

static char *slurp(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	fseek(f, 0, SEEK_END);
	long n = ftell(f);
	fseek(f, 0, SEEK_SET);
	char *s = malloc((size_t)n + 64);
	if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
		free(s);
		s = NULL;
	}
	if (s)
		s[n] = 0;
	fclose(f);
	return s;
}

/* The chart's scene through preset (with the black level for imx250mzr) */
static pc_sim *chart_sim(const char *preset)
{
	char path[4200], dir[4096];
	snprintf(dir, sizeof dir, "%s/scenes/stress", src_dir);
	snprintf(path, sizeof path, "%s/chart.json", dir);
	char *text = slurp(path);
	CHECK(text != NULL);
	if (!text)
		return NULL;
	const char *key = "\"preset\": \"ideal\"";
	char *p = strstr(text, key);
	CHECK(p != NULL);
	if (!p) {
		free(text);
		return NULL;
	}
	char with[256];
	if (!strcmp(preset, "ideal"))
		snprintf(with, sizeof with, "%s", key);
	else
		snprintf(with, sizeof with, "\"preset\": \"%s\", \"offset_dn\": %g", preset, BLACK);
	size_t n = strlen(text) + strlen(with) + 1;
	char *t = malloc(n);
	snprintf(t, n, "%.*s%s%s", (int)(p - text), text, with, p + strlen(key));
	free(text);
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	pc_sim_options so = pc_sim_options_default();
	int rc = pc_scene_parse(t, "chart.json", dir, &scene);
	free(t);
	if (!rc)
		rc = pc_sim_new(scene, &so, &sim);
	pc_scene_free(scene);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		fprintf(stderr, "chart (%s): %s\n", preset, pc_error_detail());
	return rc ? NULL : sim;
}

/* The temporal slope a_t of frames f0 and f1 (above black): the least-squares line through
 * mean(d²)/2 over 16 groups of equal counts by level, every pixel neither of whose samples
 * clipped */
static double temporal_slope(const pc_view *f0, const pc_view *f1)
{
	const uint32_t w = f0->width, h = f0->height;
	double *lv = malloc(sizeof(double) * 2 * w * h);
	size_t n = 0;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			double a = at(f0, x, y), b = at(f1, x, y);
			if (a <= 0 || b <= 0 || a >= 4095 || b >= 4095)
				continue;
			lv[2 * n] = (a + b) / 2 - BLACK;
			lv[2 * n + 1] = (a - b) * (a - b) / 2;
			n++;
		}
	/* sort the pairs by level (qsort on pairs of doubles, keyed by the first) */
	qsort(lv, n, 2 * sizeof(double), cmp_d);
	double sx = 0, sy = 0, sxx = 0, sxy = 0;
	const int G = 16;
	for (int g = 0; g < G; g++) {
		size_t i0 = n * (size_t)g / G, i1 = n * (size_t)(g + 1) / G;
		double m = 0, v = 0;
		for (size_t i = i0; i < i1; i++) {
			m += lv[2 * i];
			v += lv[2 * i + 1];
		}
		m /= (double)(i1 - i0);
		v /= (double)(i1 - i0);
		sx += m;
		sy += v;
		sxx += m * m;
		sxy += m * v;
	}
	free(lv);
	return (G * sxy - sx * sy) / (G * sxx - sx * sx);
}

static pc_pipeline_opts nr_opts(const pc_sim_info *info, double black)
{
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_RATIO_NR;
	o.mosaic = info->mosaic;
	o.black_level = black;
	return o;
}

/* 1. one exposure and gain */
static void slope_case(pc_sim *sim, double exposure_us, double gain_db)
{
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	pc_sim_controls ctl = {exposure_us, gain_db};
	pc_view f[2] = {{0}, {0}};
	int rc = 0;
	for (int k = 0; k < 2 && !rc; k++)
		if (!(rc = pc_view_alloc(&f[k], info.format, info.width, info.height, 0)))
			rc = pc_sim_frame(sim, (uint64_t)k, &ctl, &f[k], NULL);
	CHECK_EQ_INT(rc, 0);
	if (!rc) {
		const double K = 0.39 * pow(10, gain_db / 20), at_ = temporal_slope(&f[0], &f[1]);
		pc_pipeline_opts o = nr_opts(&info, BLACK);
		double g = -1;
		CHECK_EQ_INT(pc_demosaic_noise_gain(&f[0], &o, &g), 0);
		printf(
		    "  exposure %.4g us, gain %2.0f dB: K %.4f DN, temporal slope %.4f (%.3f K), "
		    "estimate %.4f (%.3f of the temporal)\n",
		    exposure_us, gain_db, K, at_, at_ / K, g, g / at_);
		CHECK(fabs(at_ / K - 1) < 0.10);
		CHECK(g >= 0.75 * at_ && g <= 1.3 * at_);
	}
	pc_view_free(&f[0]);
	pc_view_free(&f[1]);
}

/* 2 and 3 on one frame (exposure ctl, NULL: the scene's): ratio-nr against ratio (noise-free)
 * or against its given gain */
static void front_door_case(pc_sim *sim, const pc_sim_controls *ctl, int noise_free)
{
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	pc_view raw = {0};
	int rc = pc_view_alloc(&raw, info.format, info.width, info.height, 0);
	if (!rc)
		rc = pc_sim_frame(sim, 0, ctl, &raw, NULL);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		return;
	const uint32_t w = raw.width, h = raw.height;
	if (noise_free) { /* the premise: no clipped sample (PC_FMT_MONO12 in uint16) */
		long clipped = 0;
		for (uint32_t y = 0; y < h; y++)
			for (uint32_t x = 0; x < w; x++)
				clipped += PC_ROW(&raw, uint16_t, y)[x] >= 4095;
		CHECK(raw.format == PC_FMT_MONO12);
		CHECK(clipped == 0);
	}
	const double black = noise_free ? 0 : BLACK;
	const size_t n = (size_t)w * h * 4;
	float *a = malloc(sizeof(float) * n), *b = malloc(sizeof(float) * n);
	pc_fplane pa[4], pb[4];
	pc_fplanes_interleaved(a, w, 4, pa);
	pc_fplanes_interleaved(b, w, 4, pb);
	for (int reference = 0; reference < 2; reference++) {
		pc_pipeline_opts o = nr_opts(&info, black);
		o.reference = reference;
		double used = -1, est = -1;
		o.noise_gain_used = &used;
		CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pa, NULL), 0);
		CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &est), 0);
		CHECK(used == est);
		pc_pipeline_opts q = o;
		q.noise_gain_used = NULL;
		if (noise_free) {
			CHECK(est == 0);
			q.method = PC_DM_RATIO;
		} else {
			CHECK(est > 0.1);
			q.noise_gain = est;
		}
		CHECK_EQ_INT(pc_demosaic_run(&raw, &q, pb, NULL), 0);
		CHECK(memcmp(a, b, sizeof(float) * n) == 0);
		printf("  %s, %s: noise gain %.17g DN; ratio-nr %s bit for bit\n",
		       noise_free ? "ideal sensor" : "IMX250MZR",
		       reference ? "reference" : "fast path", used,
		       noise_free ? "equals ratio" : "with the estimate given equals the default");
		static double fast_used = -1;
		if (!noise_free && !reference)
			fast_used = used;
		if (!noise_free && reference)
			CHECK(used == fast_used); /* the same model on both paths */
	}
	free(a);
	free(b);
	pc_view_free(&raw);
}

/* 4. A flat field (one level: the fit cannot separate slope and offset) of 400 DN above a black
 * level of 64, with Gaussian noise of variance 0.39·400 + 40 DN² (a shot and a read part): the
 * slope must not be 0 (b alone would fit one level best) but that of the line through the
 * origin, var/L = 0.49 DN, within 10 % */
static void flat_case(void)
{
	const uint32_t W = 512, H = 384;
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, W, H, 0), 0);
	const double L = 400, var = 0.39 * L + 40;
	uint64_t r = 12345;
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			double u[2];
			for (int k = 0; k < 2; k++) {
				r = r * 6364136223846793005ull + 1442695040888963407ull;
				u[k] = ((double)(r >> 11) + 0.5) / 9007199254740992.0;
			}
			double z = sqrt(-2 * log(u[0])) * cos(2 * M_PI * u[1]);
			PC_ROW(&raw, uint16_t, y)[x] = (uint16_t)lround(BLACK + L + sqrt(var) * z);
		}
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_RATIO_NR;
	o.mosaic = pc_mosaic_imx250mzr();
	o.black_level = BLACK;
	double g = -1;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &g), 0);
	printf("4. a flat field at %g DN, variance %g DN^2: slope %.4f DN (var/L %.4f)\n", L, var,
	       g, var / L);
	CHECK(fabs(g / (var / L) - 1) < 0.10);
	/* the same frame as float32 in units of full scale (full scale 1): the same slope in those
	 * units (the samples' float rounding apart) */
	pc_view fr;
	CHECK_EQ_INT(pc_view_alloc(&fr, PC_FMT_FLOAT32, W, H, 0), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++)
			PC_ROW(&fr, float, y)[x] = (float)(PC_ROW(&raw, uint16_t, y)[x] / 4095.0);
	o.black_level = BLACK / 4095;
	o.full_scale = 1;
	double gf = -1;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&fr, &o, &gf), 0);
	printf("   as float32 in units of full scale: %.6g (x 4095 = %.4f DN)\n", gf, gf * 4095);
	CHECK(fabs(gf * 4095 / g - 1) < 1e-3);
	pc_view_free(&fr);
	pc_view_free(&raw);
}

/* 5. Hard frames: no blocks to fit (all black, all saturated, smaller than one row group, a
 * single noisy level on too few blocks) give 0, not NaN, and ratio-nr still runs; a checker of
 * black and full scale (every block clipped) likewise */
static void hard_case(const char *what, uint32_t w, uint32_t h, int kind)
{
	pc_view raw;
	CHECK_EQ_INT(pc_view_alloc(&raw, PC_FMT_MONO12, w, h, 0), 0);
	uint32_t r = 7;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			r = r * 1664525u + 1013904223u;
			uint16_t v = kind == 0   ? 0
			             : kind == 1 ? 4095
			             : kind == 2 ? (uint16_t)(((x + y) & 1) ? 4095 : 0)
			                         : (uint16_t)(1000 + (r >> 27));
			PC_ROW(&raw, uint16_t, y)[x] = v;
		}
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = PC_DM_RATIO_NR;
	o.mosaic = pc_mosaic_imx250mzr();
	double g = -1;
	CHECK_EQ_INT(pc_demosaic_noise_gain(&raw, &o, &g), 0);
	float *buf = malloc(sizeof(float) * 4 * w * h);
	pc_fplane pl[4];
	pc_fplanes_interleaved(buf, w, 4, pl);
	CHECK_EQ_INT(pc_demosaic_run(&raw, &o, pl, NULL), 0);
	int finite = 1;
	for (size_t i = 0; i < (size_t)4 * w * h; i++)
		finite &= isfinite(buf[i]);
	printf("5. %s (%ux%u): noise gain %g, outputs finite %d\n", what, w, h, g, finite);
	CHECK(kind == 3 ? g >= 0 : g == 0);
	CHECK(finite);
	free(buf);
	pc_view_free(&raw);
}

int main(void)
{
	const char *src = getenv("PC_SOURCE_DIR");
	if (!src)
		SKIP("PC_SOURCE_DIR not set: the stress scenes (scenes/stress) are not reachable");
	snprintf(src_dir, sizeof src_dir, "%s", src);
	pc_sim *sim = chart_sim("imx250mzr");
	if (sim) {
		printf("1. the estimated slope against two frames' temporal noise (the chart, "
		       "black level %g DN):\n",
		       BLACK);
		const double exposure[2] = {120, 16}, gain[3] = {0, 12, 24};
		for (int e = 0; e < 2; e++)
			for (int g = 0; g < 3; g++)
				slope_case(sim, exposure[e] / pow(10, gain[g] / 20), gain[g]);
		printf("3. the front door's model:\n");
		front_door_case(sim, NULL, 0);
		pc_sim_free(sim);
	}
	flat_case();
	hard_case("all black", 64, 48, 0);
	hard_case("all saturated", 64, 48, 1);
	hard_case("black and saturated checker", 64, 48, 2);
	hard_case("noisy, 4 rows", 64, 4, 3);
	hard_case("noisy, 8x8", 8, 8, 3);
	sim = chart_sim("ideal");
	if (sim) {
		printf("2. a noise-free frame (25 us, nothing clipped):\n");
		const pc_sim_controls dim = {25, 0};
		front_door_case(sim, &dim, 1);
		pc_sim_free(sim);
	}
	return pc_test_finish("test_noise_ptc");
}
