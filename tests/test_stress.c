/* The demosaicking stress suite (scenes/stress, docs/demosaicking.md): each scene's evaluation
 * case (pc_sim_eval_case) against the simulator's own sensor path, and the scenes are what
 * they claim to be (dark and bright patches with saturated glints, DoLP near 1 at every AoLP,
 * polarization texture, three exposures), and the held-out scenes of scenes/heldout likewise.
 * Needs the source tree (PC_SOURCE_DIR). */
#include <dirent.h>
#include <math.h>
#include <nettle/sha2.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/sim.h"

static char src_dir[2048];

typedef struct scase {
	pc_eval_truth t;
	pc_view raw;
	pc_sim_info info;
	pc_sensor_figures fig;
} scase;

/* The suite a scene is loaded from (scenes/stress or scenes/heldout) and its frame size. */
static const char *suite = "stress";
static uint32_t suite_w = 512, suite_h = 384;

static int load(const char *name, uint32_t roi_w, uint32_t roi_h, scase *c)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/scenes/%s/%s", src_dir, suite, name);
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	int rc = pc_scene_load(path, &scene);
	pc_sim_options so = pc_sim_options_default();
	so.roi_width = roi_w;
	so.roi_height = roi_h;
	if (roi_w) { /* a central region (even offsets keep the mosaic phase) */
		so.roi_x = (suite_w - roi_w) / 4 * 2;
		so.roi_y = (suite_h - roi_h) / 4 * 2;
	}
	if (!rc)
		rc = pc_sim_new(scene, &so, &sim);
	pc_scene_free(scene);
	if (!rc) {
		pc_sim_get_info(sim, &c->info);
		pc_sim_get_sensor(sim, &c->fig);
		rc = pc_sim_eval_case(sim, &c->t, &c->raw);
	}
	pc_sim_free(sim);
	if (rc)
		fprintf(stderr, "%s: %s\n", path, pc_error_detail());
	return rc;
}

static void unload(scase *c)
{
	pc_eval_truth_free(&c->t);
	pc_view_free(&c->raw);
}

static double raw_at(const pc_view *v, uint32_t x, uint32_t y)
{
	return PC_ROW(v, const uint16_t, y)[x];
}

/* Noise-free scenes with the ideal sensor: the raw frame the sensor model makes is the truth
 * (our formula for ideal analysers) at each pixel's analyser, rounded: within half a DN plus
 * float rounding. */
static void test_ideal_raw_is_truth(const char *name)
{
	scase c;
	if (load(name, 128, 96, &c)) {
		CHECK(0);
		return;
	}
	double fs = c.t.full_scale, worst = 0;
	CHECK_NEAR(fs, 4095, 0);
	for (uint32_t y = 0; y < c.t.height; y++)
		for (uint32_t x = 0; x < c.t.width; x++) {
			unsigned ch = pc_mosaic_channel(&c.info.mosaic, x, y);
			double d =
			    fabs(raw_at(&c.raw, x, y) - c.t.ch[ch][(size_t)y * c.t.width + x] * fs);
			worst = fmax(worst, d);
		}
	printf("%s: ideal sensor, worst |raw - truth| = %.4f DN\n", name, worst);
	CHECK(worst <= 0.5 + 1e-3);
	unload(&c);
}

/* scenes/stress/optics: the scene of the same name seen through the lens's PSF (σ 0.7 px), the
 * rest unchanged: over the central region its truth keeps the mean radiance (the blur moves
 * light and makes none; clipping at full scale, after the blur, lets saturated bars spread a
 * few per cent more) and loses most of its energy at the highest frequencies (the squared
 * second differences along rows and columns: a Gaussian of σ 0.7 px passes exp(−4π²σ²f²)
 * of the amplitude at f cycles/pixel, 0.08 at Nyquist). */
static void test_optics(const char *name)
{
	scase a, b;
	suite = "stress";
	int ra = load(name, 128, 96, &a);
	suite = "stress/optics";
	int rb = load(name, 128, 96, &b);
	suite = "stress";
	CHECK(!ra && !rb);
	if (ra || rb) {
		if (!ra)
			unload(&a);
		if (!rb)
			unload(&b);
		return;
	}
	CHECK(b.info.effects & PC_FX_BLUR);
	CHECK(!(a.info.effects & PC_FX_BLUR));
	CHECK_EQ_INT(b.info.effects & ~PC_FX_BLUR, a.info.effects);
	double ma = 0, mb = 0, ea = 0, eb = 0;
	const uint32_t w = a.t.width, h = a.t.height;
	for (int ch = 0; ch < 4; ch++)
		for (uint32_t y = 8; y + 8 < h; y++)
			for (uint32_t x = 8; x + 8 < w; x++) {
				size_t i = (size_t)y * w + x;
				const double *p = a.t.ch[ch], *q = b.t.ch[ch];
				ma += p[i];
				mb += q[i];
				double ha = p[i - 1] - 2 * p[i] + p[i + 1],
				       va = p[i - w] - 2 * p[i] + p[i + w];
				double hb = q[i - 1] - 2 * q[i] + q[i + 1],
				       vb = q[i - w] - 2 * q[i] + q[i + w];
				ea += ha * ha + va * va;
				eb += hb * hb + vb * vb;
			}
	printf("optics/%s: mean truth %.4f of the sharp scene's, second-difference energy %.3f\n",
	       name, mb / ma, eb / ea);
	CHECK(fabs(mb / ma - 1) < 0.1);
	CHECK(eb < 0.6 * ea); /* measured 0.11 (star) to 0.51 (chart: mostly smooth patches) */
	unload(&a);
	unload(&b);
}

/* The noisy scenes (IMX250MZR preset): the raw's mean over lit unsaturated pixels matches the
 * truth's within the analyser non-idealities (ER 300, 1 % transmission, 1 % crosstalk: a
 * few per cent), and the exposure is what the name says (the brightest tenth's level). */
static void test_noisy(const char *name, double lo, double hi)
{
	scase c;
	if (load(name, 0, 0, &c)) {
		CHECK(0);
		return;
	}
	double fs = c.t.full_scale, sr = 0, st = 0, peak = 0;
	for (uint32_t y = 0; y < c.t.height; y++)
		for (uint32_t x = 0; x < c.t.width; x++) {
			unsigned ch = pc_mosaic_channel(&c.info.mosaic, x, y);
			double tv = c.t.ch[ch][(size_t)y * c.t.width + x] * fs;
			if (tv >= fs - 1)
				continue;
			sr += raw_at(&c.raw, x, y);
			st += tv;
		}
	/* the 90th percentile of the truth's mean intensity: the bright patches' level */
	size_t n = (size_t)c.t.width * c.t.height;
	double *v = malloc(sizeof(double) * n);
	for (size_t i = 0; i < n; i++)
		v[i] = 0.25 * (c.t.ch[0][i] + c.t.ch[1][i] + c.t.ch[2][i] + c.t.ch[3][i]);
	/* partial selection by counting is enough here: histogram in 1/4096 bins */
	size_t hist[4097] = {0};
	for (size_t i = 0; i < n; i++)
		hist[(size_t)lround(fmin(v[i], 1.0) * 4096)]++;
	size_t acc = 0;
	for (int b = 4096; b >= 0; b--) {
		acc += hist[b];
		if (acc >= n / 10) {
			peak = b / 4096.0;
			break;
		}
	}
	free(v);
	printf("%s: raw/truth mean %.4f, bright level %.4f of full scale\n", name, sr / st, peak);
	CHECK_NEAR(sr / st, 1.0, 0.03);
	CHECK(peak >= lo && peak <= hi);
	unload(&c);
}

/* The chart: dark patches (< 2 % of full scale) beside bright ones (> 40 %) and saturated
 * glints, each on at least 5 % (glints 0.5 %) of the frame. */
static void test_chart(void)
{
	scase c;
	if (load("chart.json", 0, 0, &c)) {
		CHECK(0);
		return;
	}
	size_t n = (size_t)c.t.width * c.t.height, dark = 0, bright = 0, sat = 0;
	for (size_t i = 0; i < n; i++) {
		double m = 0.25 * (c.t.ch[0][i] + c.t.ch[1][i] + c.t.ch[2][i] + c.t.ch[3][i]);
		dark += m < 0.02;
		bright += m > 0.4;
		sat += c.t.ch[0][i] >= 1 || c.t.ch[1][i] >= 1 || c.t.ch[2][i] >= 1 ||
		       c.t.ch[3][i] >= 1;
	}
	printf("chart: %.1f %% dark, %.1f %% bright, %.1f %% saturated\n", 100.0 * dark / n,
	       100.0 * bright / n, 100.0 * sat / n);
	CHECK(dark > n / 20 && bright > n / 20 && sat > n / 200);
	unload(&c);
}

/* Pixels (unsaturated, S0 above 1 % of full scale) with DoLP above dmin in each of the eight
 * 22.5° AoLP bins. */
static void dolp_bins(const scase *c, double dmin, size_t bins[8])
{
	size_t n = (size_t)c->t.width * c->t.height;
	for (int b = 0; b < 8; b++)
		bins[b] = 0;
	for (size_t i = 0; i < n; i++) {
		double I[4] = {c->t.ch[0][i], c->t.ch[1][i], c->t.ch[2][i], c->t.ch[3][i]};
		if (I[0] >= 1 || I[1] >= 1 || I[2] >= 1 || I[3] >= 1)
			continue;
		double s0 = 0.5 * (I[0] + I[1] + I[2] + I[3]), s1 = I[0] - I[2], s2 = I[1] - I[3];
		if (s0 < 0.01 || sqrt(s1 * s1 + s2 * s2) / s0 < dmin)
			continue;
		double a = 0.5 * atan2(s2, s1);
		if (a < 0)
			a += M_PI;
		bins[(int)(a / (M_PI / 8)) & 7]++;
	}
}

/* Glossy spheres: DoLP > 0.8 somewhere in each of the eight 22.5° AoLP bins, on unsaturated
 * pixels. */
static void test_gloss(void)
{
	scase c;
	if (load("gloss.json", 0, 0, &c)) {
		CHECK(0);
		return;
	}
	size_t bins[8];
	dolp_bins(&c, 0.8, bins);
	for (int b = 0; b < 8; b++) {
		printf("gloss: DoLP > 0.8 at AoLP %5.1f-%5.1f deg: %zu pixels\n", 22.5 * b,
		       22.5 * (b + 1), bins[b]);
		CHECK(bins[b] >= 10);
	}
	unload(&c);
}

/* Pattern scenes: the pattern carries polarization texture (DoLP differs by > 0.4 between
 * neighbours somewhere) inside a central region. */
static void test_texture(const char *name)
{
	scase c;
	if (load(name, 256, 192, &c)) {
		CHECK(0);
		return;
	}
	size_t n = 0;
	uint32_t w = c.t.width;
	for (uint32_t y = 0; y < c.t.height; y++)
		for (uint32_t x = 0; x + 2 < w; x++) {
			double d[2];
			for (int k = 0; k < 2; k++) {
				size_t i = (size_t)y * w + x + 2 * k;
				double I[4] = {c.t.ch[0][i], c.t.ch[1][i], c.t.ch[2][i],
				               c.t.ch[3][i]};
				double s0 = 0.5 * (I[0] + I[1] + I[2] + I[3]), s1 = I[0] - I[2],
				       s2 = I[1] - I[3];
				d[k] = s0 > 0 ? sqrt(s1 * s1 + s2 * s2) / s0 : 0;
			}
			n += fabs(d[0] - d[1]) > 0.4;
		}
	printf("%s: %zu pixel pairs 2 px apart differ by > 0.4 in DoLP\n", name, n);
	CHECK(n >= 100);
	unload(&c);
}

/* Held-out glints: a dark frame (most pixels below 2 % of full scale) with clipped glints. */
static void test_heldout_glints(void)
{
	scase c;
	if (load("glints.json", 0, 0, &c)) {
		CHECK(0);
		return;
	}
	size_t n = (size_t)c.t.width * c.t.height, dark = 0, sat = 0;
	for (size_t i = 0; i < n; i++) {
		double m = 0.25 * (c.t.ch[0][i] + c.t.ch[1][i] + c.t.ch[2][i] + c.t.ch[3][i]);
		dark += m < 0.02;
		sat += c.t.ch[0][i] >= 1 || c.t.ch[1][i] >= 1 || c.t.ch[2][i] >= 1 ||
		       c.t.ch[3][i] >= 1;
	}
	printf("heldout glints: %.1f %% dark, %.2f %% saturated\n", 100.0 * dark / n,
	       100.0 * sat / n);
	CHECK(dark > n * 7 / 10 && sat > n / 2000);
	unload(&c);
}

/* Held-out facets: DoLP > 0.45 in at least seven of the eight AoLP bins. */
static void test_heldout_facets(void)
{
	scase c;
	if (load("facets.json", 0, 0, &c)) {
		CHECK(0);
		return;
	}
	size_t bins[8];
	int full = 0;
	dolp_bins(&c, 0.45, bins);
	for (int b = 0; b < 8; b++) {
		printf("heldout facets: DoLP > 0.45 at AoLP %5.1f-%5.1f deg: %zu pixels\n",
		       22.5 * b, 22.5 * (b + 1), bins[b]);
		full += bins[b] >= 10;
	}
	CHECK(full >= 7);
	unload(&c);
}

/* pc_eval_method_raw on the Sony mosaic of a truth is pc_eval_method. */
static void test_method_raw(void)
{
	scase c;
	if (load("star.json", 96, 64, &c)) {
		CHECK(0);
		return;
	}
	pc_mosaic m = pc_mosaic_imx250mzr();
	pc_view raw;
	CHECK(pc_eval_mosaic(&c.t, &m, &raw) == 0);
	pc_eval_metrics a, b;
	CHECK(pc_eval_method(&c.t, PC_DM_EARI, NULL, &a) == 0);
	CHECK(pc_eval_method_raw(&c.t, &raw, &m, PC_DM_EARI, NULL, &b) == 0);
	CHECK(memcmp(&a, &b, sizeof a) == 0);
	pc_view_free(&raw);
	unload(&c);
}

/* A simulator of scenes/stress/DIR/NAME rendering the region w × h at (x, y); NULL (checked,
 * reported) when the scene does not load. */
static pc_sim *roi_sim(const char *dir, const char *name, uint32_t w, uint32_t h, uint32_t x,
                       uint32_t y)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/scenes/stress/%s/%s", src_dir, dir, name);
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	pc_sim_options so = pc_sim_options_default();
	so.roi_width = w;
	so.roi_height = h;
	so.roi_x = x;
	so.roi_y = y;
	int rc = pc_scene_load(path, &scene);
	if (!rc)
		rc = pc_sim_new(scene, &so, &sim);
	pc_scene_free(scene);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		fprintf(stderr, "%s: %s\n", path, pc_error_detail());
	return rc ? NULL : sim;
}

/* The colour suite (scenes/stress/colour): with the ideal sensor each pixel's raw value is its
 * own colour's truth at its analyser (pc_sim_eval_colour_case, each colour scaled by its own DN
 * per radiance), within half a DN; the monochrome case refuses the colour sensor and the colour
 * case a monochrome one; and the scene is what it claims: hue edges (neighbouring pixels 4
 * apart whose colour ratios R/G or B/G differ by more than a factor 2) on at least 2.5 % of the
 * frame (5 % and 14.5 % measured, patches and text), or DoLP above 0.8 in every colour (gloss,
 * 0.92-0.94). The colour methods score on it. */
static void test_colour(const char *dir, const char *name, int gloss)
{
	pc_sim *sim = roi_sim(dir, name, 256, 192, 128, 96);
	if (!sim)
		return;
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	pc_eval_truth t[3], t1;
	pc_view raw, raw1;
	CHECK_EQ_INT(pc_sim_eval_case(sim, &t1, &raw1), PC_ENOTSUP);
	CHECK_EQ_INT(pc_sim_eval_colour_case(sim, t, &raw), 0);
	pc_sim_free(sim);
	const uint32_t w = t[0].width, h = t[0].height;
	const double fs = t[0].full_scale;
	double worst = 0, dmax[3] = {0};
	size_t edges = 0, n = 0;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			unsigned c = pc_mosaic_channel(&info.mosaic, x, y);
			unsigned k = pc_mosaic_color(&info.mosaic, x, y) - PC_CFA_R;
			worst = fmax(worst, fabs(raw_at(&raw, x, y) - t[k].ch[c][i] * fs));
			double s0[3], dolp[3];
			for (int q = 0; q < 3; q++) {
				const double *I[4] = {t[q].ch[0], t[q].ch[1], t[q].ch[2],
				                      t[q].ch[3]};
				s0[q] = 0.5 * (I[0][i] + I[1][i] + I[2][i] + I[3][i]);
				double s1 = I[0][i] - I[2][i], s2 = I[1][i] - I[3][i];
				dolp[q] = s0[q] > 0.02 ? sqrt(s1 * s1 + s2 * s2) / s0[q] : 0;
				dmax[q] = fmax(dmax[q], dolp[q]);
			}
			if (x + 4 < w) {
				size_t j = i + 4;
				double a[2], b[2];
				for (int q = 0; q < 2; q++) {
					const int kq = q ? 2 : 0;
					double gi = t[1].ch[0][i] + t[1].ch[2][i] + 1e-3,
					       gj = t[1].ch[0][j] + t[1].ch[2][j] + 1e-3;
					a[q] = (t[kq].ch[0][i] + t[kq].ch[2][i] + 1e-3) / gi;
					b[q] = (t[kq].ch[0][j] + t[kq].ch[2][j] + 1e-3) / gj;
				}
				edges += fabs(log(a[0] / b[0])) > log(2) ||
				         fabs(log(a[1] / b[1])) > log(2);
			}
			n++;
		}
	printf("%s: colour, ideal sensor, worst |raw - truth| = %.4f DN; hue edges on %.1f %% of "
	       "the pixels; DoLP max R %.2f G %.2f B %.2f\n",
	       name, worst, 100.0 * (double)edges / (double)n, dmax[0], dmax[1], dmax[2]);
	CHECK(worst <= 0.5 + 1e-3);
	if (gloss)
		CHECK(dmax[0] > 0.8 && dmax[1] > 0.8 && dmax[2] > 0.8);
	else
		CHECK(edges >= n / 40);
	/* the colour methods score it; bayer-first and pan-chroma differ */
	pc_eval_metrics mb, mc;
	CHECK_EQ_INT(pc_eval_method_raw_colour(t, &raw, &info.mosaic, PC_DM_BAYER_FIRST, NULL, &mb),
	             0);
	CHECK_EQ_INT(pc_eval_method_raw_colour(t, &raw, &info.mosaic, PC_DM_PAN_CHROMA, NULL, &mc),
	             0);
	CHECK(mb.psnr_s0 > 10 && mc.psnr_s0 > 10 && mb.psnr_s0 != mc.psnr_s0);
	/* a monochrome method is refused, naming it */
	CHECK_EQ_INT(pc_eval_method_raw_colour(t, &raw, &info.mosaic, PC_DM_BILINEAR, NULL, &mb),
	             PC_EINVAL);
	for (int k = 0; k < 3; k++)
		pc_eval_truth_free(&t[k]);
	pc_view_free(&raw);
	/* and the colour case refuses a monochrome sensor */
	char path[4096];
	snprintf(path, sizeof path, "%s/scenes/stress/chart.json", src_dir);
	pc_scene *scene = NULL;
	CHECK_EQ_INT(pc_scene_load(path, &scene), 0);
	pc_sim_options so = pc_sim_options_default();
	so.roi_width = so.roi_height = 64;
	CHECK_EQ_INT(pc_sim_new(scene, &so, &sim), 0);
	pc_scene_free(scene);
	CHECK_EQ_INT(pc_sim_eval_colour_case(sim, t, &raw), PC_ENOTSUP);
	pc_sim_free(sim);
}

/* A sealed colour set (scenes/stress/colour-sealed, colour-sealed2, ..., READMEs there):
 * every scene loads and renders, a central 128×96 region of it. No demosaicking method is run on
 * these scenes here (they are sealed: the first evaluation of a method on them is reported as
 * is). With the ideal sensor (noisy NULL) the raw frame is each pixel's own colour's truth at
 * its analyser within half a DN (the truth is clipped at full scale as the raw is); through the
 * imx250myr preset (noisy names the gain) the frame is noisy (rms raw − truth above 8 DN) and
 * not dark (median of the region 4-30 % of full scale). Measured: colour-sealed's *_g12
 * (+12 dB) 24 and 35 DN, medians 5.2 % and 9.4 %; colour-sealed2's portrait_g6 (+6 dB) and
 * street_g18 (+18 dB), colour-sealed3's livingroom_g12 (+12 dB) and carpark_g9 (+9 dB) and
 * colour-sealed4's mosaic_g21 (+21 dB) and conveyor_g15 (+15 dB), colour-sealed5's bricks_g3
 * (+3 dB) and cobbles_g27 (+27 dB), colour-sealed6's bicycle_g8 (+8 dB) and workshop_g20
 * (+20 dB) in their READMEs; colour-sealed7's court_g5 (+5 dB) 32.5 DN, median 15.6 % and
 * pews_g23 (+23 dB) 49.3 DN, median 6.7 %; colour-sealed8's bakery_g2 (+2 dB) 29.2 DN, median
 * 7.4 % and bus_g14 (+14 dB) 29.2 DN, median 8.2 %; colour-sealed9's huts_g4 (+4 dB) 34.4 DN,
 * median 15.7 % and jeweller_g17 (+17 dB) 35.9 DN, median 7.3 %; colour-sealed10's
 * playground_g7 (+7 dB) 27.0 DN, median 9.4 % and umbrellas_g22 (+22 dB) 55.1 DN, median
 * 10.1 %; colour-sealed11's archery_g10 (+10 dB) 38.7 DN, median 14.6 % and pooltable_g19
 * (+19 dB) 76.7 DN, median 26.8 %; colour-sealed12's campsite_g11 (+11 dB) 44.6 DN, median
 * 22.7 % and bowling_g16 (+16 dB) 56.6 DN, median 17.7 %. Every scene is exposed in all three
 * colours (each colour's brightest analyser value in the region above 5 % of full scale).
 * test_sealed_region takes a smaller central w×h region: test_sealed renders the ideal scenes'
 * central 64×48 (CI time: the dense meshes cost more per pixel) and the noisy ones' 128×96 (the
 * median check needs the larger region on colour-sealed4's mosaic_g21). Of a used set (main's
 * sealed_sets[]) only the first noisy scene is rendered. */
static void test_sealed_region(const char *dir, const char *name, const char *noisy, uint32_t w0,
                               uint32_t h0)
{
	pc_sim *sim = roi_sim(dir, name, w0, h0, 256 - w0 / 2, 192 - h0 / 2);
	if (!sim)
		return;
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	pc_eval_truth t[3];
	pc_view raw;
	int rc = pc_sim_eval_colour_case(sim, t, &raw);
	pc_sim_free(sim);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		return;
	const uint32_t w = t[0].width, h = t[0].height;
	const double fs = t[0].full_scale;
	double worst = 0, ss = 0, cmax[3] = {0};
	size_t n = 0, hist[4097] = {0};
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			size_t i = (size_t)y * w + x;
			unsigned c = pc_mosaic_channel(&info.mosaic, x, y);
			unsigned k = pc_mosaic_color(&info.mosaic, x, y) - PC_CFA_R;
			double r = raw_at(&raw, x, y), d = r - t[k].ch[c][i] * fs;
			worst = fmax(worst, fabs(d));
			ss += d * d;
			cmax[k] = fmax(cmax[k], t[k].ch[c][i]);
			hist[(size_t)fmin(4096, fmax(0, r / fs * 4096))]++;
			n++;
		}
	size_t acc = 0, med = 0;
	while (med < 4096 && (acc += hist[med]) < n / 2)
		med++;
	const double rms = sqrt(ss / (double)n), median = (double)med / 4096;
	printf("%s/%s: %s; |raw - truth| worst %.2f DN, rms %.2f DN; median %.3f of full scale; "
	       "brightest R %.2f G %.2f B %.2f\n",
	       dir, name, noisy ? noisy : "ideal sensor", worst, rms, median, cmax[0], cmax[1],
	       cmax[2]);
	if (noisy)
		CHECK(rms > 8 && median > 0.04 && median < 0.3);
	else
		CHECK(worst <= 0.5 + 1e-3);
	CHECK(cmax[0] > 0.05 && cmax[1] > 0.05 && cmax[2] > 0.05);
	for (int k = 0; k < 3; k++)
		pc_eval_truth_free(&t[k]);
	pc_view_free(&raw);
}

static void test_sealed(const char *dir, const char *name, const char *noisy)
{
	if (noisy)
		test_sealed_region(dir, name, noisy, 128, 96);
	else
		test_sealed_region(dir, name, noisy, 64, 48);
}

/* The seal of a sealed set, without git: its list (`sha256sum` output, relative to the source
 * directory: scenes/stress/DIR/SHA256SUMS, written when the set was sealed, or, for
 * colour-sealed, sealed before it had one, tests/data/colour-sealed.SHA256SUMS, written later
 * from the files of its seal commit 695381e) lists every file of the directory but the README and
 * SHA256SUMS with its SHA-256; each listed file still has that hash (computed here with nettle,
 * not with the sha256sum that wrote the list) and no other file has been added. */
static void test_seal(const char *dir, const char *sums)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/%s", src_dir, sums);
	FILE *list = fopen(path, "r");
	CHECK(list != NULL);
	if (!list) {
		fprintf(stderr, "%s: cannot open\n", path);
		return;
	}
	char line[1024], names[128][256];
	size_t n = 0, broken = 0;
	while (fgets(line, sizeof line, list)) {
		char want[65], name[256];
		if (sscanf(line, "%64s %255s", want, name) != 2 || strlen(want) != 64) {
			CHECK(0);
			fprintf(stderr, "%s: malformed line: %s", sums, line);
			broken++;
			continue;
		}
		snprintf(path, sizeof path, "%s/scenes/stress/%s/%s", src_dir, dir, name);
		FILE *f = fopen(path, "rb");
		CHECK(f != NULL);
		if (!f) {
			fprintf(stderr, "%s: listed in %s, cannot open\n", path, sums);
			broken++;
			continue;
		}
		struct sha256_ctx ctx;
		sha256_init(&ctx);
		uint8_t buf[65536], digest[SHA256_DIGEST_SIZE];
		size_t k;
		while ((k = fread(buf, 1, sizeof buf, f)) > 0)
			sha256_update(&ctx, k, buf);
		fclose(f);
		sha256_digest(&ctx, sizeof digest, digest);
		char got[65];
		for (int i = 0; i < SHA256_DIGEST_SIZE; i++)
			snprintf(got + 2 * i, 3, "%02x", digest[i]);
		if (strcmp(got, want)) {
			CHECK(0);
			fprintf(stderr, "%s: SHA-256 %s, sealed as %s: the seal is broken\n", path,
			        got, want);
			broken++;
		}
		if (n == sizeof names / sizeof *names) {
			CHECK(0);
			fprintf(stderr, "%s: more files than this test holds (%zu)\n", sums, n);
			break;
		}
		snprintf(names[n++], sizeof *names, "%s", name);
	}
	fclose(list);
	CHECK(n > 0);
	/* no file added since */
	snprintf(path, sizeof path, "%s/scenes/stress/%s", src_dir, dir);
	DIR *d = opendir(path);
	CHECK(d != NULL);
	size_t files = 0;
	for (struct dirent *e; d && (e = readdir(d));) {
		if (e->d_name[0] == '.' || !strcmp(e->d_name, "README.md") ||
		    !strcmp(e->d_name, "SHA256SUMS"))
			continue;
		int listed = 0;
		for (size_t i = 0; i < n; i++)
			listed |= !strcmp(names[i], e->d_name);
		if (!listed) {
			CHECK(0);
			fprintf(stderr, "%s/%s: not in %s (added after the seal)\n", path,
			        e->d_name, sums);
			broken++;
		}
		files++;
	}
	if (d)
		closedir(d);
	printf("%s: seal %s, %zu files of %zu listed checked\n", dir, broken ? "BROKEN" : "holds",
	       files, n);
	CHECK(files == n);
}

/* scenes/stress/mono-sealed (its README; gen_mono.py): SET-NAME.json is colour-SET/NAME.json
 * through the monochrome sensor, its exposure times 0.30/0.38, so its truth is the colour
 * scene's green truth. A central 32×32 region of both is rendered: the copy's mosaic has no
 * colour layer, and its ideal-analyser images equal the green ones to 1e-6 of full scale (the
 * exposure is written to 6 decimals of a µs), noisy copies (imx250mzr against imx250myr,
 * whose green photons are counted at 530 nm, not 525) within 2 % where above 1 % of full scale
 * (measured below), and a noisy copy's raw is noisy (rms raw − truth above 8 DN, as
 * test_sealed's). Mesh loading dominates the time under the sanitizers: one ideal scene of each
 * set and three noisy ones are checked. */
static void test_mono_sealed(const char *set, const char *name, int noisy)
{
	char copy[256];
	snprintf(copy, sizeof copy, "%s-%s", set + strlen("colour-"), name);
	pc_sim *ms = roi_sim("mono-sealed", copy, 32, 32, 240, 176);
	pc_sim *cs = roi_sim(set, name, 32, 32, 240, 176);
	if (!ms || !cs) {
		pc_sim_free(ms);
		pc_sim_free(cs);
		return;
	}
	pc_sim_info mi, ci;
	pc_sim_get_info(ms, &mi);
	pc_sim_get_info(cs, &ci);
	const pc_mosaic mzr = pc_mosaic_imx250mzr(), myr = pc_mosaic_imx250myr();
	CHECK(pc_mosaic_equal(&mi.mosaic, &mzr) && pc_mosaic_equal(&ci.mosaic, &myr));
	pc_eval_truth t1, t[3];
	pc_view r1, r3;
	int rc = pc_sim_eval_case(ms, &t1, &r1);
	CHECK_EQ_INT(rc, 0);
	if (rc)
		fprintf(stderr, "%s: %s\n", copy, pc_error_detail());
	int rc3 = pc_sim_eval_colour_case(cs, t, &r3);
	CHECK_EQ_INT(rc3, 0);
	pc_sim_free(ms);
	pc_sim_free(cs);
	if (rc || rc3) {
		if (!rc) {
			pc_eval_truth_free(&t1);
			pc_view_free(&r1);
		}
		return;
	}
	CHECK(t1.width == t[1].width && t1.height == t[1].height);
	const size_t n = (size_t)t1.width * t1.height;
	double worst_abs = 0, worst_rel = 0, gmax = 0, ss = 0;
	for (unsigned c = 0; c < 4; c++)
		for (size_t i = 0; i < n; i++) {
			double a = t1.ch[c][i], g = t[1].ch[c][i];
			worst_abs = fmax(worst_abs, fabs(a - g));
			if (g > 0.01)
				worst_rel = fmax(worst_rel, fabs(a / g - 1));
			gmax = fmax(gmax, g);
		}
	for (uint32_t y = 0; y < t1.height; y++)
		for (uint32_t x = 0; x < t1.width; x++) {
			size_t i = (size_t)y * t1.width + x;
			double d = raw_at(&r1, x, y) -
			           t1.ch[pc_mosaic_channel(&mi.mosaic, x, y)][i] * t1.full_scale;
			ss += d * d;
		}
	const double rms = sqrt(ss / (double)n);
	printf("mono-sealed/%s: truth against %s/%s's green: worst %.2e of full scale, %.2f %% "
	       "relative; brightest %.2f; |raw - truth| rms %.2f DN\n",
	       copy, set, name, worst_abs, 100 * worst_rel, gmax, rms);
	CHECK(gmax > 0.02);
	if (noisy)
		CHECK(worst_rel <= 0.02 && rms > 8);
	else
		CHECK(worst_abs <= 1e-6);
	pc_eval_truth_free(&t1);
	for (int k = 0; k < 3; k++)
		pc_eval_truth_free(&t[k]);
	pc_view_free(&r1);
	pc_view_free(&r3);
}

/* The sealed colour sets (scenes/stress/colour-sealed*): the list of their seal, their ideal
 * scenes and their noisy ones with the gain each README gives. colour-sealed, sealed before it
 * had a list, keeps its list in tests/data. `used`: the set has had its one evaluation
 * (docs/demosaicking.md names the round); its scenes are then secondary figures, and the test
 * renders only its first noisy scene (the set still loads, its noise is what the README says)
 * besides checking the seal. A set not yet used has every scene rendered, so that nothing in
 * it fails on the day it is opened. (Each used set's scenes rendered in CI cost about 8 s under
 * the sanitizers: loading the dense meshes.) */
typedef struct sealed_set {
	const char *dir, *sums;
	int used;
	const char *ideal[8];
	const char *noisy[3][2];
} sealed_set;

static const sealed_set sealed_sets[] = {
    {"colour-sealed",
     "tests/data/colour-sealed.SHA256SUMS",
     1,
     {"foliage.json", "stilllife.json", "textile.json", "gradients.json", "metals.json",
      "fruit.json"},
     {{"stilllife_g12.json", "imx250myr +12 dB"}, {"foliage_g12.json", "imx250myr +12 dB"}}},
    {"colour-sealed2",
     "scenes/stress/colour-sealed2/SHA256SUMS",
     1,
     {"portrait.json", "street.json", "print.json", "rooftops.json", "water.json"},
     {{"portrait_g6.json", "imx250myr +6 dB"}, {"street_g18.json", "imx250myr +18 dB"}}},
    {"colour-sealed3",
     "scenes/stress/colour-sealed3/SHA256SUMS",
     1,
     {"cables.json", "chart.json", "carpark.json", "pcb.json"},
     {{"livingroom_g12.json", "imx250myr +12 dB"}, {"carpark_g9.json", "imx250myr +9 dB"}}},
    {"colour-sealed4",
     "scenes/stress/colour-sealed4/SHA256SUMS",
     1,
     {"mosaic.json", "meadow.json", "conveyor.json", "solar.json"},
     {{"mosaic_g21.json", "imx250myr +21 dB"}, {"conveyor_g15.json", "imx250myr +15 dB"}}},
    {"colour-sealed5",
     "scenes/stress/colour-sealed5/SHA256SUMS",
     1,
     {"spices.json", "bricks.json", "cobbles.json", "fields.json"},
     {{"bricks_g3.json", "imx250myr +3 dB"}, {"cobbles_g27.json", "imx250myr +27 dB"}}},
    {"colour-sealed6",
     "scenes/stress/colour-sealed6/SHA256SUMS",
     1,
     {"kitchen.json", "workshop.json", "bicycle.json"},
     {{"bicycle_g8.json", "imx250myr +8 dB"}, {"workshop_g20.json", "imx250myr +20 dB"}}},
    {"colour-sealed7",
     "scenes/stress/colour-sealed7/SHA256SUMS",
     1,
     {"court.json", "tackle.json", "greenhouse.json", "pews.json"},
     {{"court_g5.json", "imx250myr +5 dB"}, {"pews_g23.json", "imx250myr +23 dB"}}},
    {"colour-sealed8",
     "scenes/stress/colour-sealed8/SHA256SUMS",
     1,
     {"wool.json", "pool.json", "bus.json", "bakery.json"},
     {{"bakery_g2.json", "imx250myr +2 dB"}, {"bus_g14.json", "imx250myr +14 dB"}}},
    {"colour-sealed9",
     "scenes/stress/colour-sealed9/SHA256SUMS",
     1,
     {"huts.json", "fishmonger.json", "jeweller.json", "pencils.json"},
     {{"huts_g4.json", "imx250myr +4 dB"}, {"jeweller_g17.json", "imx250myr +17 dB"}}},
    {"colour-sealed10",
     "scenes/stress/colour-sealed10/SHA256SUMS",
     1,
     {"umbrellas.json", "trainset.json", "playground.json", "makeup.json"},
     {{"playground_g7.json", "imx250myr +7 dB"}, {"umbrellas_g22.json", "imx250myr +22 dB"}}},
    {"colour-sealed11",
     "scenes/stress/colour-sealed11/SHA256SUMS",
     1,
     {"roadworks.json", "pooltable.json", "archery.json", "boardgame.json"},
     {{"archery_g10.json", "imx250myr +10 dB"}, {"pooltable_g19.json", "imx250myr +19 dB"}}},
    {"colour-sealed12",
     "scenes/stress/colour-sealed12/SHA256SUMS",
     1,
     {"bowling.json", "labbench.json", "console.json", "campsite.json"},
     {{"campsite_g11.json", "imx250myr +11 dB"}, {"bowling_g16.json", "imx250myr +16 dB"}}},
};

int main(void)
{
	const char *src = getenv("PC_SOURCE_DIR");
	if (!src)
		SKIP("PC_SOURCE_DIR not set: the stress scenes (scenes/stress) are not reachable");
	snprintf(src_dir, sizeof src_dir, "%s", src);
	static const char *ideal[] = {"chart.json", "gloss.json", "star.json", "gratings.json",
	                              "text.json"};
	for (size_t i = 0; i < sizeof ideal / sizeof *ideal; i++)
		test_ideal_raw_is_truth(ideal[i]);
	test_noisy("noise_high.json", 0.4, 0.65);
	test_noisy("noise_mid.json", 0.055, 0.085);
	test_noisy("noise_low.json", 0.01, 0.016);
	test_chart();
	test_gloss();
	test_texture("star.json");
	test_texture("gratings.json");
	test_texture("text.json");
	test_method_raw();
	/* the stress suite through a lens (scenes/stress/optics): ideal raws are their (blurred)
	 * truth, and each scene is its sharp source blurred */
	for (size_t i = 0; i < sizeof ideal / sizeof *ideal; i++) {
		suite = "stress/optics";
		test_ideal_raw_is_truth(ideal[i]);
		suite = "stress";
		test_optics(ideal[i]);
	}
	test_optics("noise_mid.json");
	test_colour("colour", "patches.json", 0);
	test_colour("colour", "text.json", 0);
	test_colour("colour", "gloss.json", 1);
	/* the hue-pair development scenes (scenes/stress/colour-hue, docs/demosaicking.md Round
	 * 16): the same checks, hue edges on at least 2.5 % of the central region */
	static const char *hue[] = {"gm_bars.json", "rc_checks.json", "halftone.json",
	                            "polar_bars.json"};
	for (size_t i = 0; i < sizeof hue / sizeof *hue; i++)
		test_colour("colour-hue", hue[i], 0);

	/* the held-out check (scenes/heldout): each scene is what its README says */
	suite = "heldout";
	suite_w = 448, suite_h = 336;
	static const char *held[] = {"metals.json", "dielectrics.json", "glints.json",
	                             "facets.json", "rings.json",       "fine.json"};
	for (size_t i = 0; i < sizeof held / sizeof *held; i++)
		test_ideal_raw_is_truth(held[i]);
	test_noisy("facets_bright.json", 0.33, 0.46);
	test_noisy("facets_dim.json", 0.05, 0.07);
	test_noisy("facets_dark.json", 0.009, 0.014);
	test_noisy("fine_bright.json", 0.33, 0.46);
	test_noisy("fine_dim.json", 0.05, 0.07);
	test_noisy("fine_dark.json", 0.009, 0.014);
	test_heldout_glints();
	test_heldout_facets();

	/* the sealed colour sets: each seal holds; every scene of a set not yet used, and a used
	 * set's first noisy scene, loads and renders; nothing is scored (test_seal, test_sealed) */
	for (size_t i = 0; i < sizeof sealed_sets / sizeof *sealed_sets; i++) {
		const sealed_set *ss = &sealed_sets[i];
		test_seal(ss->dir, ss->sums);
		if (ss->used) {
			test_sealed(ss->dir, ss->noisy[0][0], ss->noisy[0][1]);
			continue;
		}
		for (const char *const *n = ss->ideal; *n; n++)
			test_sealed(ss->dir, *n, NULL);
		for (const char *const(*n)[2] = ss->noisy; (*n)[0]; n++)
			test_sealed(ss->dir, (*n)[0], (*n)[1]);
	}
	/* their monochrome copies (scenes/stress/mono-sealed): one ideal scene of every set, the
	 * second noisy one of every fourth */
	for (size_t i = 0; i < sizeof sealed_sets / sizeof *sealed_sets; i++) {
		test_mono_sealed(sealed_sets[i].dir, sealed_sets[i].ideal[0], 0);
		if (i % 4 == 3)
			test_mono_sealed(sealed_sets[i].dir, sealed_sets[i].noisy[1][0], 1);
	}
	return pc_test_finish("test_stress");
}
