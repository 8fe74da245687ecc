/* tests/test_calib_process.c - black level, saturation and calibration through `polarcam process`
 * and `polarcam demosaic` (issue 11 item 1), against the simulator's truth:
 *   - a recording with a black level: process takes it from meta.json and the DoLP is the
 *     truth's; without it the DoLP is low by exactly the factor S0 / (S0 + 2·black) that the
 *     formulas of docs/physics.md give;
 *   - saturated samples: valid.npy is exactly the 3×3 (bilinear support) dilation of the raw
 *     samples at full scale, computed here from the raw; the statistics leave them out; their
 *     DoLP is far from the truth while the valid pixels' is not;
 *   - a calibration from `polarcam calibrate` (imx250mzr_nonuniform preset): the calibrated
 *     process is closer to the truth than the uncalibrated one;
 *   - bad calibration input (another ROI, another size, a colour mosaic, a corrupt file, a black
 *     level given twice): a non-zero exit status and nothing written;
 *   - capture --process and view: the simulator's declared black level, the calibration
 *     applied (the stimulus's DoLP), a mismatch refused before anything is recorded;
 *   - the calibration's system gain (flats at 0 dB) as ratio-nr's noise gain at +12 dB of
 *     analog gain, live and through a recording: the preset's K at +12 dB within 5 %; a
 *     recording whose frames change gain refused by calibrate;
 *   - mueller: a pixel saturated in any frame is in valid.npy, values unchanged. */
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/io.h"
#include "run_cli.h"

static char tmp[64];

static bool exists(const char *p)
{
	struct stat st;
	return stat(p, &st) == 0;
}

static const char *P(const char *name)
{
	static char buf[8][1024];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
	return buf[k];
}

/* a float32 .npy of n elements (NULL on any mismatch) */
static float *load_f32(const char *path, size_t n, pc_array *a)
{
	if (pc_npy_read(path, a) || a->dtype != PC_DT_F32 || pc_array_count(a) != n) {
		fprintf(stderr, "%s: not float32 of %zu elements\n", path, n);
		return NULL;
	}
	return a->data;
}

static double meta_number(const char *dir, const char *key, const char *sub)
{
	char path[1200];
	snprintf(path, sizeof path, "%s/meta.json", dir);
	json_t *j = json_load_file(path, 0, NULL);
	json_t *v = j ? json_object_get(j, key) : NULL;
	if (v && sub)
		v = json_object_get(v, sub);
	double r = json_is_number(v) ? json_number_value(v) : NAN;
	json_decref(j);
	return r;
}

/* The truth: the simulator's Stokes image (H, W, 4) of the light reaching the sensor, or for
 * the uniform stimuli seen through a PSA element (whose truth_stokes.npy is the light before
 * it) the stimulus's own DoLP and AoLP. */
typedef struct truth {
	const float *t;
	double dolp, aolp;
} truth;

static double truth_dolp(const truth *tr, size_t p)
{
	const float *t = tr->t;
	return t ? hypot(t[4 * p + 1], t[4 * p + 2]) / t[4 * p] : tr->dolp;
}

static double truth_aolp(const truth *tr, size_t p)
{
	const float *t = tr->t;
	return t ? 0.5 * atan2(t[4 * p + 2], t[4 * p + 1]) : tr->aolp;
}

/* Mean and RMS of (dolp − truth) over the pixels at least 2 from the border (where mask is NULL
 * or mask[p] == want). */
typedef struct err_stats {
	double mean, rms, aolp_rms_deg;
	size_t n;
} err_stats;

static err_stats compare(const float *dolp, const float *aolp, const truth *tr, uint32_t w,
                         uint32_t h, const uint8_t *mask, int want)
{
	double s = 0, ss = 0, sa = 0;
	size_t n = 0;
	for (uint32_t y = 2; y + 2 < h; y++)
		for (uint32_t x = 2; x + 2 < w; x++) {
			size_t p = (size_t)y * w + x;
			if (mask && mask[p] != want)
				continue;
			double e = dolp[p] - truth_dolp(tr, p);
			s += e;
			ss += e * e;
			if (aolp) {
				double ea =
				    remainder(aolp[p] - truth_aolp(tr, p), M_PI) * 180 / M_PI;
				sa += ea * ea;
			}
			n++;
		}
	err_stats r = {n ? s / (double)n : NAN, n ? sqrt(ss / (double)n) : NAN,
	               n ? sqrt(sa / (double)n) : NAN, n};
	return r;
}

static int write_text(const char *path, const char *text)
{
	FILE *f = fopen(path, "w");
	if (!f)
		return -1;
	fputs(text, f);
	return fclose(f);
}

/* A uniform partially polarized field (DoLP 0.5 at AoLP 55°) or the default scene's objects,
 * the IMX250MZR's noise, PRNU and DSNU, ideal analysers, black level 100 DN. */
static const char *const scene_uniform =
    "{\"polarcam_scene\": 1, \"name\": \"offset test\","
    " \"camera\": {\"position\": [0, 0, 1], \"direction\": [0, 1, 0], \"focal_length_mm\": 50},"
    " \"materials\": {\"unused\": {\"n\": 1.5, \"sigma\": 0.2}},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], \"irradiance_w_m2\": 1}],"
    " \"background\": 1.7,"
    " \"effects\": {\"extinction_ratio\": false, \"orientation_error\": false,"
    "   \"transmission\": false, \"crosstalk\": false},"
    " \"sensor\": {\"preset\": \"imx250mzr\", \"offset_dn\": 100, \"exposure_us\": 5000,"
    "   \"psa\": [{\"diattenuator\": {\"angle_deg\": 55, \"diattenuation\": 0.5}}]}}";

static const char *const scene_bright =
    "{\"polarcam_scene\": 1, \"name\": \"highlights\","
    " \"camera\": {\"position\": [0, -7.5, 3.0], \"look_at\": [0, 0.3, 0.7],"
    "   \"up\": [0, 0, 1], \"focal_length_mm\": 12, \"f_number\": 4},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [-0.55, -0.45, 0.70],"
    "   \"irradiance_w_m2\": 300, \"polarization\": \"unpolarized\"}],"
    " \"materials\": {\"black_paint\": {\"n\": 1.46, \"k\": 1.28, \"sigma\": 0.2},"
    "   \"green_paint\": {\"n\": 1.47, \"k\": 0.47, \"sigma\": 0.1}},"
    " \"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1],"
    "   \"material\": \"green_paint\"},"
    "   {\"type\": \"sphere\", \"center\": [-1.4, 0.4, 1.0], \"radius\": 1.0,"
    "   \"material\": \"black_paint\"}],"
    " \"effects\": {\"diffuse\": true, \"shadowing\": true, \"extinction_ratio\": false,"
    "   \"orientation_error\": false, \"transmission\": false, \"crosstalk\": false},"
    " \"sensor\": {\"preset\": \"imx250mzr\", \"offset_dn\": 100, \"exposure_us\": %s}}";

/* ---- 1: the recording's black level ---- */
static void black_level(void)
{
	CHECK_EQ_INT(write_text(P("uniform.json"), scene_uniform), 0);
	CHECK_EQ_INT(run_cli("render", P("uniform.json"), "-o", P("ru"), "--roi", "1000,800,64,64",
	                     "-n", "1", NULL),
	             0);
	CHECK_EQ_INT(run_cli("process", P("ru/raw_000000.png"), "-o", P("pu"), NULL), 0);
	CHECK_EQ_INT(
	    run_cli("process", P("ru/raw_000000.png"), "-o", P("pu0"), "--black-level", "0", NULL),
	    0);
	CHECK_EQ_INT(run_cli("process", P("ru/raw_000000.png"), "-o", P("pu100"), "--black-level",
	                     "100", NULL),
	             0);
	CHECK_NEAR(meta_number(P("pu"), "black_level", NULL), 100, 0);
	pc_array ad, ad0, ad100, as;
	const size_t n = 64 * 64;
	const truth tr = {NULL, 0.5, 55 * M_PI / 180};
	const float *d = load_f32(P("pu/dolp.npy"), n, &ad);
	const float *d0 = load_f32(P("pu0/dolp.npy"), n, &ad0);
	const float *d100 = load_f32(P("pu100/dolp.npy"), n, &ad100);
	const float *s = load_f32(P("pu/stokes.npy"), 3 * n, &as);
	CHECK(d && d0 && d100 && s);
	if (d && d0 && d100 && s) {
		err_stats e = compare(d, NULL, &tr, 64, 64, NULL, 1);
		err_stats e0 = compare(d0, NULL, &tr, 64, 64, NULL, 1);
		/* the truth's DoLP, 0.5: the mean error is noise (Rice bias ~ σ²/(2·DoLP·S0²),
		 * 1e-4 here) */
		printf("black level from meta.json: DoLP error mean %+.5f rms %.5f; ignored: mean "
		       "%+.5f rms %.5f\n",
		       e.mean, e.rms, e0.mean, e0.rms);
		CHECK(fabs(e.mean) < 0.002);
		/* ignoring it: DoLP·S0/(S0 + 2·black) with S0 the offset-corrected mean */
		double s0 = 0;
		for (size_t p = 0; p < n; p++)
			s0 += s[3 * p] / (double)n;
		double want = 0.5 * s0 / (s0 + 2 * 100);
		printf("S0 %.1f DN: predicted DoLP without the black level %.5f, measured %.5f\n",
		       s0, want, 0.5 + e0.mean);
		CHECK_NEAR(0.5 + e0.mean, want, 0.002);
		CHECK(e0.mean < -0.03);
		/* --black-level 100 is the recording's own */
		CHECK(memcmp(d, d100, n * sizeof *d) == 0);
	}
	pc_array_free(&ad);
	pc_array_free(&ad0);
	pc_array_free(&ad100);
	pc_array_free(&as);

	/* demosaic: bilinear weights sum to 1, so the channels are the plain ones minus 100 */
	CHECK_EQ_INT(run_cli("demosaic", P("ru/raw_000000.png"), "-o", P("dm.npy"), NULL), 0);
	CHECK_EQ_INT(run_cli("demosaic", P("ru/raw_000000.png"), "-o", P("dm0.npy"),
	                     "--black-level", "0", NULL),
	             0);
	CHECK(exists(P("dm_valid.npy")));
	pc_array a1, a0;
	const float *c1 = load_f32(P("dm.npy"), 4 * n, &a1),
	            *c0 = load_f32(P("dm0.npy"), 4 * n, &a0);
	CHECK(c1 && c0);
	double worst = 0;
	for (size_t i = 0; c1 && c0 && i < 4 * n; i++)
		worst = fmax(worst, fabs(c0[i] - 100 - c1[i]));
	CHECK(c1 && c0 && worst < 1e-3);
	pc_array_free(&a1);
	pc_array_free(&a0);
}

/* The expected bilinear validity: a pixel is invalid when its 3×3 neighbourhood (mirrored at
 * the borders: -1 reads 1, W reads W-2) holds a sample >= sat; ANDed into want. Returns the
 * number of such samples. */
static size_t sat_mask(const pc_view *raw, unsigned sat, uint8_t *want)
{
	const int W = (int)raw->width, H = (int)raw->height;
	size_t n_sat = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			bool ok = true;
			for (int dy = -1; dy <= 1; dy++)
				for (int dx = -1; dx <= 1; dx++) {
					int yy = y + dy, xx = x + dx;
					yy = yy < 0 ? -yy : yy >= H ? 2 * H - 2 - yy : yy;
					xx = xx < 0 ? -xx : xx >= W ? 2 * W - 2 - xx : xx;
					ok &= PC_ROW(raw, const uint16_t, (uint32_t)yy)[xx] < sat;
				}
			want[(size_t)y * (size_t)W + (size_t)x] &= ok;
			n_sat += PC_ROW(raw, const uint16_t, (uint32_t)y)[x] >= sat;
		}
	return n_sat;
}

/* ---- 2: saturated samples in the mask, out of the statistics ---- */
static void saturation(void)
{
	char text[4096];
	snprintf(text, sizeof text, scene_bright, "900");
	CHECK_EQ_INT(write_text(P("bright.json"), text), 0);
	CHECK_EQ_INT(run_cli("render", P("bright.json"), "-o", P("rb"), "--roi", "600,700,96,96",
	                     "-n", "1", NULL),
	             0);
	CHECK_EQ_INT(run_cli("process", P("rb/raw_000000.png"), "-o", P("pb"), NULL), 0);
	CHECK_EQ_INT(run_cli("process", P("rb/raw_000000.png"), "-o", P("pbn"), "--saturation",
	                     "none", NULL),
	             0);
	CHECK(exists(P("pb/valid.npy")) && !exists(P("pbn/valid.npy")));
	const uint32_t W = 96, H = 96;
	const size_t n = (size_t)W * H;
	pc_view raw;
	unsigned bits = 0;
	CHECK_EQ_INT(pc_image_read_mosaic(P("rb/raw_000000.png"), NULL, 0, &raw, &bits), 0);
	CHECK_EQ_INT(bits, 12);
	uint8_t *want = malloc(n);
	memset(want, 1, n);
	size_t n_sat = sat_mask(&raw, 4095, want), n_want = 0;
	for (size_t p = 0; p < n; p++)
		n_want += !want[p];
	pc_view_free(&raw);
	pc_array av, at, ad, adn;
	bool got = pc_npy_read(P("pb/valid.npy"), &av) == 0 && av.dtype == PC_DT_U8 &&
	           av.ndim == 2 && av.shape[0] == H && av.shape[1] == W;
	CHECK(got);
	printf("saturated samples %zu, invalid pixels expected %zu, reported %.0f\n", n_sat, n_want,
	       meta_number(P("pb"), "invalid_pixels", NULL));
	/* the ROI straddles the edge of a clipped highlight */
	CHECK(n_sat > n / 10 && n_want < 3 * n / 4);
	CHECK(got && memcmp(av.data, want, n) == 0);
	CHECK_NEAR(meta_number(P("pb"), "invalid_pixels", NULL), (double)n_want, 0);
	CHECK(isnan(meta_number(P("pbn"), "invalid_pixels", NULL)));
	const float *t = load_f32(P("rb/truth_stokes.npy"), 4 * n, &at);
	const float *d = load_f32(P("pb/dolp.npy"), n, &ad);
	const float *dn = load_f32(P("pbn/dolp.npy"), n, &adn);
	CHECK(t && d && dn);
	if (got && t && d && dn) {
		/* nothing clamped: the values are those computed without the check */
		CHECK(memcmp(d, dn, n * sizeof *d) == 0);
		/* statistics: the valid pixels' mean, computed here */
		double sv = 0, sa = 0;
		size_t nv = 0;
		for (size_t p = 0; p < n; p++) {
			sa += d[p];
			if (want[p]) {
				sv += d[p];
				nv++;
			}
		}
		CHECK_NEAR(meta_number(P("pb"), "valid_statistics", "pixels"), (double)nv, 0);
		CHECK_NEAR(meta_number(P("pb"), "valid_statistics", "dolp_mean"), sv / (double)nv,
		           1e-6);
		CHECK_NEAR(meta_number(P("pbn"), "valid_statistics", "dolp_mean"), sa / (double)n,
		           1e-6);
		/* what the mask catches: DoLP near clipped samples is wrong, elsewhere right */
		const truth tr = {t, 0, 0};
		err_stats ev = compare(d, NULL, &tr, W, H, want, 1);
		err_stats ei = compare(d, NULL, &tr, W, H, want, 0);
		printf(
		    "DoLP error against the truth: valid pixels (%zu) rms %.4f, invalid (%zu) rms "
		    "%.4f\n",
		    ev.n, ev.rms, ei.n, ei.rms);
		CHECK(ei.n > 0 && ei.rms > 5 * ev.rms);
	}
	free(want);
	pc_array_free(&av);
	pc_array_free(&at);
	pc_array_free(&ad);
	pc_array_free(&adn);
}

/* ---- 3, 4: a calibration from polarcam calibrate ---- */
static int render_calib(const char *scene, const char *out, const char *roi, const char *first,
                        const char *n)
{
	char sp[1024];
	snprintf(sp, sizeof sp, "%s/scenes/calib/%s.json", getenv("PC_SOURCE_DIR"), scene);
	return run_cli("render", sp, "-o", P(out), "--roi", roi, "-n", n, "--first", first, NULL);
}

static void calibrated(void)
{
	const char *roi = "1000,800,64,64";
	CHECK_EQ_INT(render_calib("dark", "dark", roi, "0", "16"), 0);
	CHECK_EQ_INT(render_calib("flat_low", "fl", roi, "100", "16"), 0);
	CHECK_EQ_INT(render_calib("flat_high", "fh", roi, "200", "16"), 0);
	CHECK_EQ_INT(render_calib("polarizer_000", "p0", roi, "300", "16"), 0);
	CHECK_EQ_INT(render_calib("polarizer_060", "p60", roi, "400", "16"), 0);
	CHECK_EQ_INT(render_calib("polarizer_120", "p120", roi, "500", "16"), 0);
	CHECK_EQ_INT(run_cli("calibrate", "dark", P("dark"), "-o", P("d.npz"), NULL), 0);
	CHECK_EQ_INT(run_cli("calibrate", "flat", P("fl"), P("fh"), "--dark", P("d.npz"), "-o",
	                     P("f.npz"), NULL),
	             0);
	CHECK_EQ_INT(run_cli("calibrate", "analyser", P("p0"), P("p60"), P("p120"), "--flat",
	                     P("f.npz"), "-o", P("a.npz"), NULL),
	             0);
	/* a stimulus not used for calibration: DoLP 0.5 at AoLP 55° */
	CHECK_EQ_INT(render_calib("dolp50_055", "t", roi, "900", "1"), 0);
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("pt_u"), NULL), 0);
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("pt_c"), "--calibration",
	                     P("a.npz"), NULL),
	             0);
	CHECK(exists(P("pt_c/valid.npy")));
	const size_t n = 64 * 64;
	pc_array du, dc, au, ac, av;
	const truth tr = {NULL, 0.5, 55 * M_PI / 180};
	const float *u = load_f32(P("pt_u/dolp.npy"), n, &du);
	const float *c = load_f32(P("pt_c/dolp.npy"), n, &dc);
	const float *ua = load_f32(P("pt_u/aolp.npy"), n, &au);
	const float *ca = load_f32(P("pt_c/aolp.npy"), n, &ac);
	CHECK(u && c && ua && ca);
	CHECK(pc_npy_read(P("pt_c/valid.npy"), &av) == 0 && av.dtype == PC_DT_U8);
	if (u && c && ua && ca) {
		err_stats eu = compare(u, ua, &tr, 64, 64, NULL, 1);
		err_stats ec = compare(c, ca, &tr, 64, 64, av.data, 1);
		printf("one frame of DoLP 0.5 at 55 deg, imx250mzr_nonuniform: uncalibrated DoLP "
		       "error mean %+.5f rms %.5f, AoLP rms %.3f deg; calibrated (%zu valid "
		       "pixels) mean %+.5f rms %.5f, AoLP rms %.3f deg\n",
		       eu.mean, eu.rms, eu.aolp_rms_deg, ec.n, ec.mean, ec.rms, ec.aolp_rms_deg);
		CHECK(ec.n > 3 * n / 4);
		CHECK(ec.rms < 0.8 * eu.rms);
		CHECK(fabs(ec.mean) < 0.5 * fabs(eu.mean));
		CHECK(ec.aolp_rms_deg < 0.8 * eu.aolp_rms_deg);
		CHECK_NEAR(meta_number(P("pt_c"), "black_level", NULL), 0, 0);
	}
	/* the calibration's system gain (its flats' photon transfer, EMVA 1288: the preset's K of
	 * 0.39 DN/e- within 5 %) is the noise gain of ratio-nr, said so in meta.json; a given
	 * --noise-gain overrides it */
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("pt_n"), "--calibration",
	                     P("a.npz"), "--method", "ratio-nr", NULL),
	             0);
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("pt_o"), "--calibration",
	                     P("a.npz"), "--method", "ratio-nr", "--noise-gain", "1.5", NULL),
	             0);
	{
		char path[1200];
		snprintf(path, sizeof path, "%s/meta.json", P("pt_n"));
		json_t *j = json_load_file(path, 0, NULL);
		const char *from =
		    j ? json_string_value(json_object_get(j, "noise_gain_from")) : NULL;
		double k = meta_number(P("pt_n"), "noise_gain", NULL);
		printf("ratio-nr with the calibration: noise gain %.4f DN/e- from %s\n", k,
		       from ? from : "(none)");
		CHECK(from && !strcmp(from, "calibration"));
		CHECK_REL(k, 0.39, 0.05);
		json_decref(j);
		snprintf(path, sizeof path, "%s/meta.json", P("pt_o"));
		j = json_load_file(path, 0, NULL);
		from = j ? json_string_value(json_object_get(j, "noise_gain_from")) : NULL;
		CHECK(from && !strcmp(from, "option"));
		CHECK_NEAR(meta_number(P("pt_o"), "noise_gain", NULL), 1.5, 0);
		json_decref(j);
	}
	pc_array_free(&du);
	pc_array_free(&dc);
	pc_array_free(&au);
	pc_array_free(&ac);
	pc_array_free(&av);
	/* demosaic with the calibration: the mask beside it */
	CHECK_EQ_INT(run_cli("demosaic", P("t/raw_000000.png"), "-o", P("tc.npy"), "--calibration",
	                     P("a.npz"), NULL),
	             0);
	CHECK(exists(P("tc.npy")) && exists(P("tc_valid.npy")));

	/* bad calibration input: refused, nothing written */
	CHECK_EQ_INT(render_calib("dolp50_055", "moved", "1002,800,64,64", "900", "1"), 0);
	CHECK_EQ_INT(run_cli("process", P("moved/raw_000000.png"), "-o", P("bad1"), "--calibration",
	                     P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad1")));
	CHECK_EQ_INT(render_calib("dolp50_055", "small", "1000,800,64,32", "900", "1"), 0);
	CHECK_EQ_INT(run_cli("process", P("small/raw_000000.png"), "-o", P("bad2"), "--calibration",
	                     P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad2")));
	CHECK_EQ_INT(run_cli("demosaic", P("small/raw_000000.png"), "-o", P("bad2.npy"),
	                     "--calibration", P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad2.npy")) && !exists(P("bad2_valid.npy")));
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("bad3"), "--layout",
	                     "RGGB:90,45,135,0", "--calibration", P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad3")));
	CHECK_EQ_INT(write_text(P("corrupt.npz"), "PK\003\004 this is not a zip archive"), 0);
	CHECK(run_cli("process", P("t/raw_000000.png"), "-o", P("bad4"), "--calibration",
	              P("corrupt.npz"), NULL) != 0);
	CHECK(!exists(P("bad4")));
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("bad5"), "--calibration",
	                     P("a.npz"), "--black-level", "60", NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("bad5")));
	CHECK_EQ_INT(run_cli("process", P("t/raw_000000.png"), "-o", P("bad6"), "--calibration",
	                     P("missing.npz"), NULL) != 0,
	             1);
	CHECK(!exists(P("bad6")));
}

/* ---- 6: polarcam mueller: a pixel saturated in any frame is invalid ---- */
static void mueller(void)
{
	char sp[1024];
	snprintf(sp, sizeof sp, "%s/scenes/linear_psg.json", getenv("PC_SOURCE_DIR"));
	CHECK_EQ_INT(
	    run_cli("render", sp, "-o", P("lp"), "--roi", "200,200,48,48", "--no-truth", NULL), 0);
	CHECK_EQ_INT(run_cli("mueller", P("lp"), "-o", P("m_s"), "--saturation", "1500", NULL), 0);
	CHECK_EQ_INT(run_cli("mueller", P("lp"), "-o", P("m_n"), "--saturation", "none", NULL), 0);
	const size_t n = 48 * 48;
	uint8_t want[48 * 48];
	memset(want, 1, n);
	size_t frames = 0;
	for (;; frames++) {
		char f[64];
		snprintf(f, sizeof f, "lp/raw_%06zu.png", frames);
		if (!exists(P(f)))
			break;
		pc_view raw;
		unsigned bits;
		if (pc_image_read_mosaic(P(f), NULL, 0, &raw, &bits))
			break;
		sat_mask(&raw, 1500, want);
		pc_view_free(&raw);
	}
	size_t n_want = 0;
	for (size_t p = 0; p < n; p++)
		n_want += !want[p];
	char js[1200];
	snprintf(js, sizeof js, "%s/mueller.json", P("m_s"));
	json_t *j = json_load_file(js, 0, NULL);
	double got = json_number_value(json_object_get(j, "pixels_invalid"));
	json_decref(j);
	printf("mueller: %zu frames, pixels with a sample >= 1500 DN in a frame's 3x3: %zu, "
	       "reported %.0f\n",
	       frames, n_want, got);
	CHECK(frames >= 3 && n_want > 0 && n_want < n);
	CHECK_NEAR(got, (double)n_want, 0);
	pc_array av, a1, a2;
	CHECK(pc_npy_read(P("m_s/valid.npy"), &av) == 0 && av.dtype == PC_DT_U8 &&
	      pc_array_count(&av) == n && memcmp(av.data, want, n) == 0);
	CHECK(!exists(P("m_n/valid.npy")));
	/* nothing clamped: the maps are those computed without the check */
	const float *d1 = load_f32(P("m_s/D.npy"), n, &a1), *d2 = load_f32(P("m_n/D.npy"), n, &a2);
	CHECK(d1 && d2 && memcmp(d1, d2, n * sizeof *d1) == 0);
	pc_array_free(&av);
	pc_array_free(&a1);
	pc_array_free(&a2);
}

/* ---- 5: the live paths: capture --process and view ---- */
static json_t *meta_json(const char *dir)
{
	char path[1200];
	snprintf(path, sizeof path, "%s/meta.json", dir);
	return json_load_file(path, 0, NULL);
}

static double process_num(const char *dir, const char *key)
{
	json_t *j = meta_json(dir);
	double v = json_number_value(
	    json_object_get(json_object_get(json_object_get(j, "extra"), "process"), key));
	json_decref(j);
	return v;
}

static char *process_str(const char *dir, const char *key, char *buf, size_t n)
{
	json_t *j = meta_json(dir);
	const char *v = json_string_value(
	    json_object_get(json_object_get(json_object_get(j, "extra"), "process"), key));
	snprintf(buf, n, "%s", v ? v : "(none)");
	json_decref(j);
	return buf;
}

/* The flats were taken at 0 dB (the scenes' gain); frames at +12 dB have 10^(12/20) times
 * the system gain (the simulator's sensor model, EMVA 1288's K), which is what ratio-nr's noise
 * gain must follow. */
static void live_gain(const char *uri)
{
	const double k12 = 0.39 * pow(10, 12.0 / 20); /* the preset's K at +12 dB */
	char from[128];
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_g12"), "--roi",
	                     "1000,800,64,64", "--gain", "12", "--process", "--method", "ratio-nr",
	                     "--calibration", P("a.npz"), NULL),
	             0);
	double ng = process_num(P("cap_g12"), "noise_gain");
	printf("capture --gain 12 --process --method ratio-nr --calibration: noise gain %.4f "
	       "DN/e- from %s (the preset's K at +12 dB %.4f)\n",
	       ng, process_str(P("cap_g12"), "noise_gain_from", from, sizeof from), k12);
	CHECK_REL(ng, k12, 0.05);
	CHECK(!strcmp(from, "calibration at the frame's gain"));
	CHECK_NEAR(process_num(P("cap_g12"), "gain_db"), 12, 0);
	CHECK_NEAR(process_num(P("cap_g12"), "calibration_gain_db"), 0, 0);
	CHECK_NEAR(process_num(P("cap_g12"), "dark_gain_db"), 0, 0); /* the dark scaled from 0 dB */
	/* at the flats' gain: the calibration's K itself (0.39 within 5 %) */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_g0"), "--roi",
	                     "1000,800,64,64", "--process", "--method", "ratio-nr", "--calibration",
	                     P("a.npz"), NULL),
	             0);
	CHECK_REL(process_num(P("cap_g0"), "noise_gain"), 0.39, 0.05);
	CHECK_REL(ng / process_num(P("cap_g0"), "noise_gain"), pow(10, 0.6), 1e-9);
	/* a given noise gain wins; with a method that uses none it is refused */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_go"), "--roi",
	                     "1000,800,64,64", "--gain", "12", "--process", "--method", "ratio-nr",
	                     "--calibration", P("a.npz"), "--noise-gain", "2.5", NULL),
	             0);
	CHECK_NEAR(process_num(P("cap_go"), "noise_gain"), 2.5, 0);
	CHECK(!strcmp(process_str(P("cap_go"), "noise_gain_from", from, sizeof from), "option"));
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_gb"), "--roi",
	                     "1000,800,64,64", "--process", "--noise-gain", "2.5", NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("cap_gb/meta.json")));
	/* a recording at +12 dB processed later: each frame's noise gain follows its gain */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "2", "-o", P("rec_g12"), "--roi",
	                     "1000,800,64,64", "--gain", "12", NULL),
	             0);
	CHECK_EQ_INT(run_cli("process", P("rec_g12"), "-o", P("rec_g12_p"), "--method", "ratio-nr",
	                     "--calibration", P("a.npz"), NULL),
	             0);
	json_t *j = meta_json(P("rec_g12_p"));
	json_t *fr = json_object_get(j, "frames");
	CHECK(json_array_size(fr) == 2);
	for (size_t i = 0; i < json_array_size(fr); i++) {
		json_t *f = json_array_get(fr, i);
		CHECK_NEAR(json_number_value(json_object_get(f, "gain_db")), 12, 0);
		CHECK_REL(json_number_value(json_object_get(f, "noise_gain")), ng, 1e-12);
	}
	json_decref(j);
	/* a calibration recording whose gain changes between frames: refused by calibrate */
	CHECK_EQ_INT(
	    run_cli("capture", uri, "-n", "3", "-o", P("rec_mix"), "--roi", "1000,800,64,64", NULL),
	    0);
	char mp[1200];
	snprintf(mp, sizeof mp, "%s/meta.json", P("rec_mix"));
	json_t *m = json_load_file(mp, 0, NULL);
	json_object_set_new(json_array_get(json_object_get(m, "frames"), 2), "gain_db",
	                    json_real(6));
	CHECK(m && json_dump_file(m, mp, JSON_INDENT(1)) == 0);
	json_decref(m);
	CHECK_EQ_INT(run_cli("calibrate", "dark", P("rec_mix"), "-o", P("mix.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("mix.npz")));
}

static void live(void)
{
	char uri[1200];
	snprintf(uri, sizeof uri, "sim:%s/scenes/calib/dolp50_055.json?fps=0&first=900",
	         getenv("PC_SOURCE_DIR"));
	/* uncalibrated: the simulator declares its black level (60 DN) */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_u"), "--roi", "1000,800,64,64",
	                     "--process", NULL),
	             0);
	json_t *j = meta_json(P("cap_u"));
	json_t *ex = json_object_get(j, "extra");
	CHECK_NEAR(json_number_value(json_object_get(json_object_get(ex, "sensor"), "offset_dn")),
	           60, 0);
	CHECK_NEAR(
	    json_number_value(json_object_get(json_object_get(ex, "process"), "black_level")), 60,
	    0);
	CHECK(exists(P("cap_u/processed/valid_000000.npy")));
	json_decref(j);
	/* calibrated: the DoLP is the stimulus's */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_c"), "--roi", "1000,800,64,64",
	                     "--process", "--calibration", P("a.npz"), NULL),
	             0);
	j = meta_json(P("cap_c"));
	json_t *pr = json_object_get(json_object_get(j, "extra"), "process");
	double dolp = json_number_value(json_object_get(pr, "last_mean_dolp"));
	printf(
	    "capture --process --calibration: mean DoLP of the valid pixels %.5f (stimulus 0.5)\n",
	    dolp);
	CHECK_NEAR(dolp, 0.5, 0.005);
	CHECK(json_is_string(json_object_get(pr, "calibration")));
	json_decref(j);
	/* another ROI: refused before anything is recorded */
	CHECK_EQ_INT(run_cli("capture", uri, "-n", "1", "-o", P("cap_bad"), "--roi",
	                     "1002,800,64,64", "--process", "--calibration", P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("cap_bad/meta.json")) && !exists(P("cap_bad/raw_000000.png")));
	/* view, headless: the calibrated stream, and the mismatch refused */
	unsetenv("DISPLAY");
	CHECK_EQ_INT(run_cli("view", uri, "--roi", "1000,800,64,64", "--frames", "1",
	                     "--screenshot", P("view.png"), "--calibration", P("a.npz"), NULL),
	             0);
	CHECK(exists(P("view.png")));
	CHECK_EQ_INT(run_cli("view", uri, "--roi", "1000,800,64,32", "--frames", "1",
	                     "--screenshot", P("view_bad.png"), "--calibration", P("a.npz"), NULL),
	             CLI_STATUS_USAGE);
	CHECK(!exists(P("view_bad.png")));
	live_gain(uri);
}

int main(void)
{
	const char *src = getenv("PC_SOURCE_DIR");
	char probe[1024];
	snprintf(probe, sizeof probe, "%s/scenes/calib/dark.json", src ? src : ".");
	if (!src || access(probe, R_OK))
		SKIP("%s not found (PC_SOURCE_DIR unset?)", probe);
	if (!run_cli_exe())
		SKIP("POLARCAM (the built CLI) is not set or not executable: run through ctest");
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_calib_process"))
		SKIP("cannot create a temporary directory");
	black_level();
	saturation();
	calibrated();
	live();
	mueller();
	char rm[1200];
	snprintf(rm, sizeof rm, "rm -rf '%s'", tmp);
	if (!pc_test_failures && system(rm))
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_calib_process");
}
