/* tests/test_calib.c - calib/: dark, flat and analyser calibration recover the simulator's own
 * per-pixel sensor parameters (scenes/calib, preset imx250mzr_nonuniform, full noise); the
 * calibrated pipeline meets the accuracy of docs/calibration.md on DoLP-0.5 stimuli not used
 * for calibration; self-calibration finds the angles; the file round-trips and bad input is
 * refused; ECM recovers a known generator and analyser. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/optics.h"
#include "polarcam/sim.h"

#define DEG (M_PI / 180)
enum {
	RX = 2304,
	RY = 1856,
	RW = 64,
	RH = 64
}; /* the test scene: a smooth, strongly polarized part of the ground */

typedef struct simstack {
	pc_sim *sim;
	pc_sim_info info;
	char name[256];
	uint64_t first; /* first frame number: stacks share the seed (the camera) and differ here */
	pc_calib_stack s;
	bool have_ctl; /* ctl instead of the scene's exposure and gain */
	pc_sim_controls ctl;
} simstack;

static int sim_get(void *user, size_t i, pc_view *out)
{
	simstack *ss = user;
	int rc = pc_view_alloc(out, ss->info.format, ss->info.width, ss->info.height, 64);
	if (!rc &&
	    (rc = pc_sim_frame(ss->sim, ss->first + i, ss->have_ctl ? &ss->ctl : NULL, out, NULL)))
		pc_view_free(out);
	return rc;
}

static const char *srcdir(void)
{
	const char *d = getenv("PC_SOURCE_DIR");
	return d ? d : ".";
}

/* A sim of scenes/calib/NAME.json over the test ROI; n frames from frame number 100000·series;
 * angle/dolp for stimuli. */
static int open_stack(simstack *ss, const char *name, size_t n, double angle, double dolp,
                      uint64_t series)
{
	memset(ss, 0, sizeof *ss);
	char path[1024];
	snprintf(path, sizeof path, "%s/scenes/calib/%s.json", srcdir(), name);
	pc_scene *sc;
	int rc = pc_scene_load(path, &sc);
	if (rc)
		return rc;
	pc_sim_options o = pc_sim_options_default();
	o.seed = 7; /* one camera: the fixed pattern is keyed by the seed */
	ss->first = series * 100000;
	o.roi_x = RX;
	o.roi_y = RY;
	o.roi_width = RW;
	o.roi_height = RH;
	rc = pc_sim_new(sc, &o, &ss->sim);
	pc_scene_free(sc);
	if (rc)
		return rc;
	pc_sim_get_info(ss->sim, &ss->info);
	snprintf(ss->name, sizeof ss->name, "%s", name);
	pc_calib_stack *s = &ss->s;
	s->name = ss->name;
	s->geo.width = ss->info.width;
	s->geo.height = ss->info.height;
	s->geo.offset_x = ss->info.offset_x;
	s->geo.offset_y = ss->info.offset_y;
	s->geo.sensor_width = ss->info.sensor_width;
	s->geo.sensor_height = ss->info.sensor_height;
	s->geo.bits = ss->info.bits;
	s->geo.mosaic = ss->info.mosaic;
	s->n = n;
	s->get = sim_get;
	s->user = ss;
	s->exposure_us = ss->info.exposure_us;
	s->gain_db = ss->info.gain_db;
	s->angle_deg = angle;
	s->dolp = dolp;
	return 0;
}

static void close_stack(simstack *ss)
{
	pc_sim_free(ss->sim);
	ss->sim = NULL;
}

/* noise-free mean DN of pixel p */
static double mean_dn(simstack *ss, size_t p)
{
	double v = NAN;
	if (!pc_sim_is_prepared(ss->sim, 0))
		pc_sim_prepare(ss->sim, 0, NULL, NULL, NULL, NULL);
	pc_sim_mean_dn(ss->sim, 0, NULL, (uint32_t)(p % RW), (uint32_t)(p / RW), &v);
	return v;
}

/* the average of n frames as a float view */
static int average(simstack *ss, size_t n, uint64_t first, pc_view *out)
{
	int rc = pc_view_alloc(out, PC_FMT_FLOAT32, RW, RH, 64);
	if (rc)
		return rc;
	float *acc = calloc(RW * RH, sizeof *acc), *row = malloc(RW * RH * sizeof *row);
	for (size_t i = 0; i < n; i++) {
		pc_view v;
		if ((rc = sim_get(ss, first + i, &v)))
			break;
		pc_view_to_f32(&v, row, RW * sizeof(float));
		pc_view_free(&v);
		for (size_t p = 0; p < RW * RH; p++)
			acc[p] += row[p] / (float)n;
	}
	for (uint32_t y = 0; y < RH; y++)
		memcpy((char *)out->data + y * out->stride, acc + (size_t)y * RW,
		       RW * sizeof(float));
	free(acc);
	free(row);
	return rc;
}

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static double aolp_err_deg(double a, double b)
{
	return remainder(a - b, M_PI) / DEG;
}

/* DoLP/AoLP RMS errors over the interior of a stimulus (dolp 0.5 at angle) */
static void stokes_errors(pc_calib *cal, const pc_view *avg, double angle, double *e_dolp,
                          double *e_aolp, double *w_dolp)
{
	float *buf = malloc(5 * RW * RH * sizeof *buf);
	pc_stokes_out out = {0};
	pc_fplane *pl[5] = {&out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp};
	for (int k = 0; k < 5; k++) {
		pl[k]->data = buf + (size_t)k * RW * RH;
		pl[k]->row_stride = RW;
		pl[k]->pixel_stride = 1;
	}
	int rc = pc_calib_stokes(cal, avg, NULL, PC_DM_BILINEAR, 1, &out, NULL, NULL);
	CHECK_EQ_INT(rc, 0);
	double sd = 0, sa = 0, wd = 0;
	size_t n = 0;
	for (uint32_t y = 2; y < RH - 2; y++)
		for (uint32_t x = 2; x < RW - 2; x++) {
			size_t p = (size_t)y * RW + x;
			double d = out.dolp.data[p] - 0.5,
			       a = aolp_err_deg(out.aolp.data[p], angle * DEG);
			sd += d * d;
			sa += a * a;
			wd = fmax(wd, fabs(d));
			n++;
		}
	*e_dolp = sqrt(sd / (double)n);
	*e_aolp = sqrt(sa / (double)n);
	if (w_dolp)
		*w_dolp = wd;
	free(buf);
}

/* The samples of the dark frames avg (at gain_db, NAN unknown) after cal's correction: each
 * pixel's own channel of a bilinear demosaic through pc_calib_apply (dark-only calibrations:
 * the float dark map), or with stokes the S0 of the calibrated bilinear pipeline (the compact
 * calibration); their mean and RMS over the interior */
static void dark_residual(pc_calib *cal, const pc_view *avg, double gain_db, bool stokes,
                          double *mean, double *rms)
{
	float *buf = malloc(5 * RW * RH * sizeof *buf);
	const float *v = buf;
	if (stokes) {
		pc_stokes_out out = {0};
		pc_fplane *pl[5] = {&out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp};
		for (int k = 0; k < 5; k++)
			*pl[k] = (pc_fplane){buf + (size_t)k * RW * RH, RW, 1};
		CHECK_EQ_INT(pc_calib_stokes_gain(cal, avg, NULL, PC_DM_BILINEAR, 1, 0, gain_db,
		                                  &out, NULL, NULL, NULL),
		             0);
	} else {
		pc_fplane ch[4];
		for (int k = 0; k < 4; k++)
			ch[k] = (pc_fplane){buf + (size_t)k * RW * RH, RW, 1};
		pc_frame f;
		memset(&f, 0, sizeof f);
		f.view = *avg;
		f.meta.exposure_us = NAN;
		f.meta.gain_db = gain_db;
		f.mosaic = cal->geo.mosaic;
		f.meta.offset_x = cal->geo.offset_x;
		f.meta.offset_y = cal->geo.offset_y;
		pc_pipeline_opts po = pc_pipeline_defaults();
		po.method = PC_DM_BILINEAR;
		po.mosaic = cal->geo.mosaic;
		po.threads = 1;
		CHECK_EQ_INT(pc_calib_apply(cal, &f, 0, &po, NULL, ch, NULL), 0);
		float *own = buf + 4 * (size_t)RW * RH;
		for (size_t p = 0; p < RW * RH; p++)
			own[p] =
			    buf[pc_mosaic_channel(&cal->geo.mosaic, p % RW, p / RW) * RW * RH + p];
		v = own;
	}
	double s = 0, s2 = 0, n = 0;
	for (uint32_t y = 2; y < RH - 2; y++)
		for (uint32_t x = 2; x < RW - 2; x++) {
			const double a = v[(size_t)y * RW + x];
			s += a;
			s2 += a * a;
			n++;
		}
	*mean = s / n;
	*rms = sqrt(s2 / n);
	free(buf);
}

static double expected_mean_d(void)
{
	/* E[(ER − 1)/(ER + 1)] for ER = 200·exp(0.35 z), z ~ N(0, 1) (the preset, sensor.c) */
	double s = 0, w = 0;
	for (double z = -8; z <= 8; z += 0.001) {
		double er = 200 * exp(0.35 * z), g = exp(-z * z / 2);
		s += g * (er - 1) / (er + 1);
		w += g;
	}
	return s / w;
}

int main(void)
{
	char probe[1024];
	snprintf(probe, sizeof probe, "%s/scenes/calib/dark.json", srcdir());
	if (access(probe, R_OK))
		SKIP("%s not found (PC_SOURCE_DIR unset?)", probe);

	/* ---- dark: per-pixel offset against the simulator's noise-free mean ---- */
	const size_t ND = 32, NF = 32, NA = 32;
	simstack dk;
	CHECK_EQ_INT(open_stack(&dk, "dark", ND, NAN, NAN, 1), 0);
	pc_calib dark;
	CHECK_EQ_INT(pc_calib_dark(&dk.s, NULL, &dark), 0);
	pc_sensor_figures fig;
	pc_sim_get_sensor(dk.sim, &fig);
	double K = fig.gain_dn_per_e, t = fig.exposure_us * 1e-6;
	double sig_t =
	    sqrt(K * K * (fig.read_noise_e * fig.read_noise_e + fig.dark_current_e_s * t) +
	         1.0 / 12); /* read + dark shot + quantization, DN */
	double worst = 0, noise = 0;
	for (size_t p = 0; p < RW * RH; p++) {
		worst = fmax(worst, fabs(dark.dark[p] - mean_dn(&dk, p)));
		noise += dark.dark_noise[p];
	}
	noise /= RW * RH;
	printf("dark: worst |offset - truth| %.3f DN (sigma/sqrt(N) = %.3f), mean noise %.3f DN "
	       "(model %.3f)\n",
	       worst, sig_t / sqrt((double)ND), noise, sig_t);
	CHECK(worst < 6 * sig_t / sqrt((double)ND) + 0.05);
	CHECK_REL(noise, sig_t, 0.1);
	CHECK_NEAR(dark.black_level, fig.offset_dn, 0.2);

	/* ---- the dark map at another analog gain: above the black level it is electrons (DSNU,
	 * dark current) times K, which follows the gain (EMVA 1288). Dark frames at +12 dB,
	 * averaged, corrected with the 0 dB dark map: scaled, what remains is the two
	 * averages' noise; unscaled, also the DSNU's growth, K·DSNU·(10^0.6 − 1) ---- */
	const double r12 = pow(10, 0.6);
	simstack d12;
	pc_view avg12;
	CHECK_EQ_INT(open_stack(&d12, "dark", 64, NAN, NAN, 14), 0);
	d12.have_ctl = true;
	d12.ctl = (pc_sim_controls){d12.info.exposure_us, fig.gain_db + 12};
	CHECK_EQ_INT(average(&d12, 64, 0, &avg12), 0);
	{
		CHECK_NEAR(dark.dark_gain_db, fig.gain_db, 0);
		bool sc = false;
		CHECK_REL(pc_calib_dark_scale(&dark, fig.gain_db + 12, &sc), r12, 1e-12);
		CHECK(sc);
		CHECK(pc_calib_dark_scale(&dark, NAN, &sc) == 1 && !sc);
		const double k12 = K * pow(10, (fig.gain_db + 12) / 20),
		             s12 = sqrt(k12 * k12 *
		                            (fig.read_noise_e * fig.read_noise_e +
		                             fig.dark_current_e_s * t) +
		                        1.0 / 12),
		             pred = sqrt(s12 * s12 / 64 + r12 * r12 * sig_t * sig_t / (double)ND),
		             dsnu = (k12 - K * pow(10, fig.gain_db / 20)) * fig.dsnu_e;
		double m1, q1, m0, q0;
		dark_residual(&dark, &avg12, fig.gain_db + 12, false, &m1, &q1);
		dark_residual(&dark, &avg12, NAN, false, &m0, &q0);
		printf(
		    "dark frames at +12 dB, corrected with the 0 dB dark map: scaled mean %+.3f "
		    "RMS "
		    "%.3f DN (the averages' noise %.3f); unscaled %+.3f, %.3f DN (with the DSNU's "
		    "growth %.3f)\n",
		    m1, q1, pred, m0, q0, sqrt(pred * pred + dsnu * dsnu));
		CHECK(fabs(m1) < 0.2 && q1 < 1.2 * pred);
		CHECK(q0 > 1.5 * pred && q0 > 1.5 * q1);
		/* a frame's gain that no factor can reach (10^(±8000/20) over- or underflows)
		 * is refused, naming both gains, not scaled to 0 or infinity */
		float *buf = malloc(5 * RW * RH * sizeof *buf);
		pc_stokes_out out = {0};
		pc_fplane *pl[5] = {&out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp};
		for (int k = 0; k < 5; k++)
			*pl[k] = (pc_fplane){buf + (size_t)k * RW * RH, RW, 1};
		for (int k = 0; k < 2; k++) {
			CHECK_EQ_INT(pc_calib_stokes_gain(&dark, &avg12, NULL, PC_DM_BILINEAR, 1, 0,
			                                  k ? -8000 : 8000, &out, NULL, NULL, NULL),
			             PC_EINVAL);
			CHECK(strstr(pc_error_detail(), "dark map cannot be scaled") != NULL);
		}
		printf("a frame at -8000 dB: %s\n", pc_error_detail());
		free(buf);
	}

	/* ---- flat: gain against the noise-free means ---- */
	simstack fl, fh;
	CHECK_EQ_INT(open_stack(&fl, "flat_low", NF, NAN, NAN, 2), 0);
	CHECK_EQ_INT(open_stack(&fh, "flat_high", NF, NAN, NAN, 3), 0);
	pc_calib_stack lv[2] = {fl.s, fh.s};
	pc_calib flat;
	CHECK_EQ_INT(pc_calib_flat(lv, 2, &dark, NULL, &flat), 0);
	/* the photon transfer (EMVA 1288): the flats' mean temporal variance against their mean
	 * level gives the simulator's system gain K (the temporal noise is shot, read and dark
	 * shot noise and quantisation, the last three in the intercept): within 3 % (32 frames a
	 * level over every pixel) */
	printf("flat: system gain %.4f DN/e- (the preset's K %.4f)\n", flat.system_gain,
	       K * pow(10, fig.gain_db / 20));
	CHECK_REL(flat.system_gain, K * pow(10, fig.gain_db / 20), 0.03);
	/* the flats' analog gain goes with it, and K follows a frame's gain as 10^(dB/20) */
	CHECK_NEAR(flat.system_gain_db, fig.gain_db, 0);
	{
		bool sc = true;
		CHECK(pc_calib_noise_gain(&flat, NAN, &sc) == flat.system_gain && !sc);
		CHECK_REL(pc_calib_noise_gain(&flat, fig.gain_db + 12, &sc),
		          flat.system_gain * pow(10, 0.6), 1e-12);
		CHECK(sc);
		CHECK_REL(pc_calib_noise_gain(&flat, fig.gain_db - 6, NULL),
		          flat.system_gain / pow(10, 0.3), 1e-12);
		/* measured again at +12 dB (the exposure divided by the gain, so that the levels
		 * stay): the photon transfer there agrees with the scaled K within 4 % */
		simstack gl, gh;
		CHECK_EQ_INT(open_stack(&gl, "flat_low", NF, NAN, NAN, 12), 0);
		CHECK_EQ_INT(open_stack(&gh, "flat_high", NF, NAN, NAN, 13), 0);
		gl.have_ctl = gh.have_ctl = true;
		gl.ctl = (pc_sim_controls){gl.info.exposure_us / pow(10, 0.6), fig.gain_db + 12};
		gh.ctl = (pc_sim_controls){gh.info.exposure_us / pow(10, 0.6), fig.gain_db + 12};
		gl.s.gain_db = gh.s.gain_db = fig.gain_db + 12;
		pc_calib_stack l12[2] = {gl.s, gh.s};
		pc_calib f12;
		CHECK_EQ_INT(pc_calib_flat(l12, 2, &dark, NULL, &f12), 0);
		printf("flat at +12 dB: system gain %.4f DN/e-, the 0 dB flats' K scaled %.4f, the "
		       "preset's %.4f\n",
		       f12.system_gain, pc_calib_noise_gain(&flat, fig.gain_db + 12, NULL),
		       K * pow(10, (fig.gain_db + 12) / 20));
		CHECK_REL(f12.system_gain, pc_calib_noise_gain(&flat, fig.gain_db + 12, NULL),
		          0.04);
		CHECK_NEAR(f12.system_gain_db, fig.gain_db + 12, 0);
		pc_calib_free(&f12);
		/* levels at two gains: refused, naming both */
		pc_calib_stack mix[2] = {fl.s, gh.s};
		pc_calib fm;
		CHECK_EQ_INT(pc_calib_flat(mix, 2, &dark, NULL, &fm), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "12 dB") && strstr(pc_error_detail(), "one gain"));
		/* levels whose gain puts the dark map's scale out of range: refused, naming the
		 * step and both gains */
		pc_calib_stack far[2] = {fl.s, fh.s};
		far[0].gain_db = far[1].gain_db = 8000;
		CHECK_EQ_INT(pc_calib_flat(far, 2, &dark, NULL, &fm), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "flat:") && strstr(pc_error_detail(), "8000 dB") &&
		      strstr(pc_error_detail(), "cannot be scaled"));
		/* a level of unknown gain takes the other's; none known: no gain recorded, K is
		 * not scaled */
		pc_calib_stack unk[2] = {fl.s, fh.s};
		unk[1].gain_db = NAN;
		CHECK_EQ_INT(pc_calib_flat(unk, 2, &dark, NULL, &fm), 0);
		CHECK_NEAR(fm.system_gain_db, fig.gain_db, 0);
		pc_calib_free(&fm);
		unk[0].gain_db = NAN;
		CHECK_EQ_INT(pc_calib_flat(unk, 2, &dark, NULL, &fm), 0);
		CHECK(isnan(fm.system_gain_db) && fm.system_gain == flat.system_gain);
		CHECK(pc_calib_noise_gain(&fm, 12, &sc) == fm.system_gain && !sc);
		pc_calib_free(&fm);
		close_stack(&gl);
		close_stack(&gh);
	}
	{
		double cm[2][4] = {{0}}, cn[4] = {0}, *tr = malloc(RW * RH * sizeof *tr);
		for (size_t p = 0; p < RW * RH; p++) {
			unsigned c = pc_mosaic_channel(&dk.info.mosaic, p % RW, p / RW);
			cm[0][c] += mean_dn(&fl, p) - mean_dn(&dk, p);
			cm[1][c] += mean_dn(&fh, p) - mean_dn(&dk, p);
			cn[c]++;
		}
		double s = 0;
		for (size_t p = 0; p < RW * RH; p++) {
			unsigned c = pc_mosaic_channel(&dk.info.mosaic, p % RW, p / RW);
			tr[p] =
			    (mean_dn(&fh, p) - mean_dn(&fl, p)) / ((cm[1][c] - cm[0][c]) / cn[c]);
			s += tr[p];
		}
		double e2 = 0, gsd = 0;
		for (size_t p = 0; p < RW * RH; p++) {
			double g = tr[p] / (s / (RW * RH));
			e2 += (flat.gain[p] - g) * (flat.gain[p] - g);
			gsd += (g - 1) * (g - 1);
		}
		/* the expected error from shot and read noise: σ²(DN) = K·(mean − offset) +
		 * (K·σ_read)² per frame (EMVA 1288 §2.2), for both levels, over N frames, divided
		 * by the levels' difference */
		double ml = 0, mh = 0;
		for (size_t p = 0; p < RW * RH; p++) {
			ml += mean_dn(&fl, p) - fig.offset_dn;
			mh += mean_dn(&fh, p) - fig.offset_dn;
		}
		ml /= RW * RH;
		mh /= RW * RH;
		double rn = K * fig.read_noise_e;
		double eg = sqrt((K * ml + rn * rn + K * mh + rn * rn) / (double)NF) / (mh - ml);
		printf("flat: gain RMS error %.5f (noise model %.5f; true gain spread %.4f)\n",
		       sqrt(e2 / (RW * RH)), eg, sqrt(gsd / (RW * RH)));
		CHECK(sqrt(e2 / (RW * RH)) < 1.3 * eg);
		CHECK(sqrt(gsd / (RW * RH)) > 0.01); /* the preset's non-uniformity is there */
		free(tr);
	}

	/* ---- analyser, known angles ---- */
	static const int ang[6] = {0, 30, 60, 90, 120, 150};
	simstack pst[6];
	pc_calib_stack stim[6];
	for (int k = 0; k < 6; k++) {
		char nm[64];
		snprintf(nm, sizeof nm, "polarizer_%03d", ang[k]);
		CHECK_EQ_INT(open_stack(&pst[k], nm, NA, ang[k], 1, 10 + k), 0);
		stim[k] = pst[k].s;
	}
	pc_calib cal;
	double est[6];
	CHECK_EQ_INT(pc_calib_analyser(stim, 6, &flat, NULL, &cal, est), 0);
	{
		/* the +12 dB dark frames through the calibrated bilinear pipeline, whose compact
		 * calibration holds the dark map in 16 bits: S0 (its scale and base are scaled) */
		double m1, q1, m0, q0;
		CHECK_NEAR(cal.dark_gain_db, dark.dark_gain_db, 0);
		dark_residual(&cal, &avg12, fig.gain_db + 12, true, &m1, &q1);
		dark_residual(&cal, &avg12, NAN, true, &m0, &q0);
		printf(
		    "calibrated S0 of the +12 dB dark frames: dark scaled mean %+.3f RMS %.3f DN; "
		    "unscaled %+.3f, %.3f DN\n",
		    m1, q1, m0, q0);
		CHECK(fabs(m1) < 0.3 && q0 > 1.5 * q1);
	}
	{
		/* per channel: mean orientation error = the preset's systematic offset (crosstalk
		 * from the ±45° neighbours does not turn the analyser); mean diattenuation =
		 * (1 − 4·crosstalk)·E[d] */
		double oe[4] = {0}, dd = 0, n4[4] = {0};
		for (size_t p = 0; p < RW * RH; p++) {
			unsigned c = pc_mosaic_channel(&dk.info.mosaic, p % RW, p / RW);
			const float *a = cal.analysis + 3 * p;
			oe[c] += remainder(0.5 * atan2(a[2], a[1]) / DEG - 45.0 * c, 180);
			dd += hypot(a[1], a[2]) / a[0];
			n4[c]++;
		}
		double ed = (1 - 4 * fig.crosstalk) * expected_mean_d();
		printf("analyser: mean diattenuation %.5f (model %.5f); orientation offsets",
		       dd / (RW * RH), ed);
		for (int c = 0; c < 4; c++) {
			printf(" %.3f (%.2f)", oe[c] / n4[c], fig.orientation_offset_deg[c]);
			/* random per-pixel errors average over 1024 pixels to 0.8°/32 = 0.025° */
			CHECK_NEAR(oe[c] / n4[c], fig.orientation_offset_deg[c], 0.1);
		}
		printf("\n");
		CHECK_NEAR(dd / (RW * RH), ed, 0.003);
	}

	/* ---- accuracy on stimuli not used for calibration (DoLP 0.5, 4 AoLPs, 64 frames) ---- */
	pc_calib uncal;
	pc_calib_init(&uncal);
	uncal.geo = cal.geo;
	uncal.black_level = dark.black_level;
	uncal.saturation = cal.saturation;
	static const int tang[4] = {10, 55, 100, 145};
	double wc_d = 0, wc_a = 0, wu_d = INFINITY, wu_a = INFINITY, cal_d2 = 0, cal_a2 = 0,
	       un_d2 = 0, un_a2 = 0;
	for (int k = 0; k < 4; k++) {
		char nm[64];
		snprintf(nm, sizeof nm, "dolp50_%03d", tang[k]);
		simstack ts;
		CHECK_EQ_INT(open_stack(&ts, nm, 64, tang[k], 0.5, 100 + k), 0);
		pc_view avg;
		CHECK_EQ_INT(average(&ts, 64, 0, &avg), 0);
		double cd, ca, ud, ua, cw;
		stokes_errors(&cal, &avg, tang[k], &cd, &ca, &cw);
		stokes_errors(&uncal, &avg, tang[k], &ud, &ua, NULL);
		printf(
		    "DoLP 0.5 at %3d deg: calibrated DoLP RMS %.5f (worst %.4f) AoLP RMS %.4f deg; "
		    "uncalibrated %.5f, %.4f deg\n",
		    tang[k], cd, cw, ca, ud, ua);
		cal_d2 += cd * cd / 4;
		cal_a2 += ca * ca / 4;
		un_d2 += ud * ud / 4;
		un_a2 += ua * ua / 4;
		wc_d = fmax(wc_d, cd);
		wc_a = fmax(wc_a, ca);
		wu_d = fmin(wu_d, ud);
		wu_a = fmin(wu_a, ua);
		pc_view_free(&avg);
		close_stack(&ts);
	}
	printf("all: calibrated DoLP RMS %.5f AoLP RMS %.4f deg; uncalibrated %.5f %.4f deg "
	       "(ratios %.1f, %.1f)\n",
	       sqrt(cal_d2), sqrt(cal_a2), sqrt(un_d2), sqrt(un_a2), sqrt(un_d2 / cal_d2),
	       sqrt(un_a2 / cal_a2));
	CHECK(wc_d <= 0.002);
	CHECK(wc_a <= 0.1);
	CHECK(wu_d >= 10 * wc_d);
	CHECK(wu_a >= 10 * wc_a);

	/* ---- a rendered scene not used for calibration: DoLP against the truth where the signal
	 * is high (S0 above the median), 64 frames averaged ---- */
	{
		simstack ts;
		CHECK_EQ_INT(open_stack(&ts, "test_scene", 64, NAN, NAN, 40), 0);
		float *truth = malloc(RW * RH * 4 * sizeof *truth);
		CHECK_EQ_INT(pc_sim_prepare(ts.sim, 0, truth, NULL, NULL, NULL), 0);
		pc_view avg;
		CHECK_EQ_INT(average(&ts, 64, 0, &avg), 0);
		float *buf = malloc(5 * RW * RH * sizeof *buf);
		uint8_t *valid = malloc(RW * RH);
		double e2[2] = {0, 0};
		size_t n = 0;
		for (int pass = 0; pass < 2; pass++) {
			pc_stokes_out out = {0};
			pc_fplane *pl[5] = {&out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp};
			for (int k = 0; k < 5; k++) {
				pl[k]->data = buf + (size_t)k * RW * RH;
				pl[k]->row_stride = RW;
				pl[k]->pixel_stride = 1;
			}
			CHECK_EQ_INT(pc_calib_stokes(pass ? &uncal : &cal, &avg, NULL,
			                             PC_DM_BILINEAR, 1, &out, valid, NULL),
			             0);
			double s0s[RW * RH];
			size_t m = 0;
			for (size_t p = 0; p < RW * RH; p++)
				s0s[m++] = truth[4 * p];
			qsort(s0s, m, sizeof *s0s, cmp_d);
			double med = s0s[m / 2];
			n = 0;
			for (uint32_t y = 2; y < RH - 2; y++)
				for (uint32_t x = 2; x < RW - 2; x++) {
					size_t p = (size_t)y * RW + x;
					const float *S = truth + 4 * p;
					if (!(S[0] > med) || !valid[p])
						continue;
					double d = out.dolp.data[p] - hypot(S[1], S[2]) / S[0];
					e2[pass] += d * d;
					n++;
				}
		}
		double rc_ = sqrt(e2[0] / (double)n), ru = sqrt(e2[1] / (double)n);
		printf("rendered scene (%zu high-signal pixels): DoLP RMSE calibrated %.5f, "
		       "uncalibrated "
		       "%.5f (ratio %.1f)\n",
		       n, rc_, ru, ru / rc_);
		CHECK(n > 500);
		CHECK(ru >= 5 * rc_);
		free(buf);
		free(valid);
		free(truth);
		pc_view_free(&avg);
		close_stack(&ts);
	}

	/* ---- self-calibration: the angles come back (up to the gauge: mean orientation error 0,
	 * so every angle moves by minus the mean of the channel offsets) ---- */
	{
		pc_calib_opts o = {.unknown_angles = true};
		pc_calib selfc;
		double ea[6];
		CHECK_EQ_INT(pc_calib_analyser(stim, 6, &flat, &o, &selfc, ea), 0);
		double shift = -(fig.orientation_offset_deg[0] + fig.orientation_offset_deg[1] +
		                 fig.orientation_offset_deg[2] + fig.orientation_offset_deg[3]) /
		               4;
		double w = 0;
		for (int k = 0; k < 6; k++)
			w = fmax(w, fabs(remainder(ea[k] - ang[k] - shift, 180)));
		printf("unknown angles: worst angle error %.4f deg (gauge shift %.2f)\n", w, shift);
		CHECK(w < 0.05);
		pc_calib_free(&selfc);
	}

	/* ---- the file: round trip, mismatches, corruption ---- */
	{
		char dir[64] = "", path[128];
		CHECK(pc_test_tmpdir(dir, sizeof dir, "pc_test_calib") != NULL);
		snprintf(path, sizeof path, "%s/calibration.npz", dir);
		CHECK_EQ_INT(pc_calib_write(path, &cal), 0);
		pc_calib back;
		CHECK_EQ_INT(pc_calib_read(path, &back), 0);
		CHECK_EQ_INT(back.parts, cal.parts);
		CHECK(!memcmp(back.analysis, cal.analysis, RW * RH * 12));
		CHECK(!memcmp(back.gain, cal.gain, RW * RH * 4));
		CHECK(!memcmp(back.dark, cal.dark, RW * RH * 4));
		CHECK(!memcmp(back.valid, cal.valid, RW * RH));
		CHECK(!memcmp(back.pinv_sp, cal.pinv_sp, RW * RH / 4 * 48));
		CHECK_NEAR(back.black_level, cal.black_level, 0);
		/* the system gain: kept through the analyser step and through the file, exactly */
		CHECK(cal.system_gain > 0 && cal.system_gain == flat.system_gain);
		CHECK(back.system_gain == cal.system_gain);
		CHECK(back.system_gain_db == cal.system_gain_db && isfinite(back.system_gain_db));
		CHECK(back.dark_gain_db == cal.dark_gain_db && isfinite(back.dark_gain_db));
		CHECK(pc_calib_check(&back, &cal.geo) == 0);
		pc_calib_geometry g = cal.geo;
		g.offset_x += 2;
		CHECK_EQ_INT(pc_calib_check(&back, &g), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "ROI offset differs") != NULL);
		g = cal.geo;
		g.width += 2;
		CHECK_EQ_INT(pc_calib_check(&back, &g), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "size differs") != NULL);
		g = cal.geo;
		g.bits = 10;
		CHECK_EQ_INT(pc_calib_check(&back, &g), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "bit depth") != NULL);
		pc_calib_free(&back);
		/* truncated and overwritten bytes */
		FILE *f = fopen(path, "rb");
		fseek(f, 0, SEEK_END);
		long sz = ftell(f);
		fseek(f, 0, SEEK_SET);
		char *b = malloc((size_t)sz);
		CHECK(fread(b, 1, (size_t)sz, f) == (size_t)sz);
		fclose(f);
		f = fopen(path, "wb");
		fwrite(b, 1, (size_t)sz / 2, f);
		fclose(f);
		CHECK(pc_calib_read(path, &back) < 0);
		printf("truncated file: %s\n", pc_error_detail());
		for (long i = 200; i < sz; i += 997)
			b[i] ^= 0x5a;
		f = fopen(path, "wb");
		fwrite(b, 1, (size_t)sz, f);
		fclose(f);
		CHECK(pc_calib_read(path, &back) < 0);
		printf("corrupted file: %s\n", pc_error_detail());
		free(b);
		unlink(path);
		rmdir(dir);
	}

	/* ---- bad input ---- */
	{
		pc_calib bad;
		CHECK_EQ_INT(pc_calib_analyser(stim, 2, &flat, NULL, &bad, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "at least 3") != NULL);
		pc_calib_stack sing[3] = {stim[0], stim[3], stim[0]}; /* 0, 90, 0: no sin 2θ */
		CHECK_EQ_INT(pc_calib_analyser(sing, 3, &flat, NULL, &bad, NULL), PC_ENUMERIC);
		CHECK(strstr(pc_error_detail(), "singular fit") != NULL);
		/* stimuli compared as equal intensities: one analog gain (an unknown one matches)
		 */
		pc_calib_stack gains[3] = {stim[0], stim[1], stim[2]};
		gains[0].gain_db = NAN;
		gains[2].gain_db = gains[1].gain_db + 6;
		CHECK_EQ_INT(pc_calib_analyser(gains, 3, &flat, NULL, &bad, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "analyser:") && strstr(pc_error_detail(), "6 dB") &&
		      strstr(pc_error_detail(), stim[1].name) &&
		      strstr(pc_error_detail(), "one gain"));
		pc_calib_opts o = {.saturation = 1500}; /* the stimuli reach ~2800 DN */
		CHECK_EQ_INT(pc_calib_analyser(stim, 6, &flat, &o, &bad, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "saturated") != NULL);
		pc_calib_stack one[1] = {fl.s};
		CHECK_EQ_INT(pc_calib_flat(one, 1, &dark, NULL, &bad), PC_EINVAL);
		pc_calib_stack same[2] = {fl.s, fl.s};
		CHECK_EQ_INT(pc_calib_flat(same, 2, &dark, NULL, &bad), PC_ENUMERIC);
		/* a recording of another ROI against the calibration */
		simstack other;
		CHECK_EQ_INT(open_stack(&other, "polarizer_000", 2, 0, 1, 5), 0);
		pc_calib_stack moved[3] = {stim[0], stim[1], other.s};
		moved[2].geo.offset_x += 2;
		CHECK_EQ_INT(pc_calib_analyser(moved, 3, &flat, NULL, &bad, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "ROI offset differs") != NULL);
		close_stack(&other);
	}

	/* ---- ECM on exact synthetic data: W, A and an unseen sample come back ---- */
	{
		double W[4][4], Ar[8][4], M[5][4][4];
		/* PSG: polarizer at 0 + retarder 136° at 15.9, 51.0, −52.5, −14.6 (errors of a few
		 * degrees); PSA: quarter-wave plates of 86° at 0.7° and 44.1° before the DoFP */
		static const double ra[4] = {15.9, 51.0, -52.5, -14.6};
		for (int g = 0; g < 4; g++) {
			double R[4][4], s0[4] = {1, 1, 0, 0}, s[4];
			pc_retarder_mueller(ra[g] * DEG, 136 * DEG, R);
			pc_mueller_apply(R, s0, s);
			for (int i = 0; i < 4; i++)
				W[i][g] = s[i] * (1 + 0.01 * g);
		}
		static const double pa[2] = {0.7, 44.1};
		for (int a = 0; a < 2; a++) {
			double R[4][4];
			pc_retarder_mueller(pa[a] * DEG, 86 * DEG, R);
			for (int c = 0; c < 4; c++) {
				double th = (45.0 * c + 0.3 * c) * DEG;
				double w[4] = {0.5, 0.49 * cos(2 * th), 0.49 * sin(2 * th), 0};
				for (int j = 0; j < 4; j++) {
					Ar[4 * a + c][j] = 0;
					for (int k = 0; k < 4; k++)
						Ar[4 * a + c][j] += w[k] * R[k][j];
				}
			}
		}
		memset(M[0], 0, sizeof M[0]);
		for (int i = 0; i < 4; i++)
			M[0][i][i] = 1;
		pc_ecm_sample_mueller(0.45, 0.02, 0.1, 0, M[1]);
		pc_ecm_sample_mueller(0.45, 0.02, 0.1, 88.5 * DEG, M[2]);
		pc_ecm_sample_mueller(0.9, M_PI / 4, 92 * DEG, 31 * DEG, M[3]);
		pc_ecm_sample_mueller(0.7, 0.5, 40 * DEG, 20 * DEG, M[4]); /* the unseen sample */
		double B[5][32];
		for (int i = 0; i < 5; i++)
			for (int k = 0; k < 8; k++)
				for (int g = 0; g < 4; g++) {
					double s = 0;
					for (int a = 0; a < 4; a++)
						for (int b = 0; b < 4; b++)
							s += Ar[k][a] * M[i][a][b] * W[b][g];
					B[i][k * 4 + g] = s;
				}
		const double *Bp[4] = {B[0], B[1], B[2], B[3]};
		pc_ecm_result r;
		CHECK_EQ_INT(pc_ecm_solve(Bp, 4, 2, NULL, &r), 0);
		CHECK_NEAR(r.theta_deg[2], 88.5, 1e-4);
		CHECK_NEAR(r.theta_deg[3], 31, 1e-4);
		CHECK_NEAR(r.delta_deg[3], 92, 1e-6);
		double m0 = (W[0][0] + W[0][1] + W[0][2] + W[0][3]) / 4, e = 0;
		for (int i = 0; i < 4; i++)
			for (int g = 0; g < 4; g++)
				e = fmax(e, fabs(r.W[i][g] - W[i][g] / m0));
		printf("ECM exact: generator max error %.2e, theta %.6f %.6f, lambda15/16 %.3g\n",
		       e, r.theta_deg[2], r.theta_deg[3], r.lambda15 / fmax(r.lambda16, 1e-300));
		CHECK(e < 1e-7);
		/* the unseen sample through the recovered system: M = A⁺ B W⁻¹ */
		pc_mueller_system sys;
		double psg[4][4], psa[2][4][4],
		    an[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
		for (int g = 0; g < 4; g++)
			for (int i = 0; i < 4; i++)
				psg[g][i] = r.W[i][g];
		for (int a = 0; a < 2; a++)
			for (int i = 0; i < 4; i++)
				memcpy(psa[a][i], r.A[4 * a + i], sizeof psa[a][i]);
		CHECK_EQ_INT(pc_mueller_system_init(&sys, 4, (const double(*)[4])psg, 2,
		                                    (const double(*)[4][4])psa,
		                                    (const double(*)[4])an),
		             0);
		double I[32], Mx[4][4], em = 0;
		for (int a = 0; a < 2; a++)
			for (int g = 0; g < 4; g++)
				for (int c = 0; c < 4; c++)
					I[(g + 4 * a) * 4 + c] = B[4][(4 * a + c) * 4 + g];
		pc_mueller_solve(&sys, I, Mx);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				em = fmax(em, fabs(Mx[i][j] - M[4][i][j]));
		printf("ECM exact: unseen sample max |M error| %.2e\n", em);
		CHECK(em < 1e-7);
		/* a bad reference set: air instead of the retarder (no retardance to see) */
		const double *Bs[4] = {B[0], B[1], B[2], B[0]};
		int rc = pc_ecm_solve(Bs, 4, 2, NULL, &r);
		CHECK_EQ_INT(rc, PC_ENUMERIC);
		printf("ECM degenerate references: %s\n", pc_error_detail());
	}

	/* ---- ECM on the simulator: generator/analyser errors (retardances ±5°, orientations up
	 * to 1°) in scenes/calib/ecm_*; the sample not used for calibration comes back within 2×
	 * the error of the ideal polarimeter (no errors, nominal states) ---- */
	{
		static const char *const refs[4] = {"ecm_air", "ecm_polarizer_000",
		                                    "ecm_polarizer_090", "ecm_retarder_030"};
		simstack es[4];
		pc_calib_stack estk[4];
		for (int i = 0; i < 4; i++) {
			CHECK_EQ_INT(open_stack(&es[i], refs[i], 16, NAN, NAN, 20 + i), 0);
			estk[i] = es[i].s;
		}
		pc_calib ecal;
		pc_ecm_result r;
		{ /* the samples' intensities are compared with the air's: one analog gain */
			pc_calib_stack eg[4] = {estk[0], estk[1], estk[2], estk[3]};
			eg[3].gain_db += 3;
			CHECK_EQ_INT(pc_calib_ecm(eg, 4, 2, NULL, &dark, NULL, &ecal, &r),
			             PC_EINVAL);
			CHECK(strstr(pc_error_detail(), "ECM:") &&
			      strstr(pc_error_detail(), "3 dB"));
		}
		CHECK_EQ_INT(pc_calib_ecm(estk, 4, 2, NULL, &dark, NULL, &ecal, &r), 0);
		printf(
		    "ECM sim: polarizer2 %.3f deg, retarder %.3f deg at %.3f deg, model residual "
		    "%.2e\n",
		    r.theta_deg[2], r.delta_deg[3], r.theta_deg[3], r.residual);
		CHECK_NEAR(r.theta_deg[2], 90, 0.05);
		CHECK_NEAR(r.theta_deg[3], 30, 0.05);
		CHECK_NEAR(r.delta_deg[3], 90, 0.1);
		/* truth: diattenuator D = 0.3 at 25° (p + q = 1), then a 60° retarder at 70° */
		double Dm[4][4], Rm[4][4], T[4][4];
		{
			double th = 25 * DEG, D = 0.3, pp = (1 + D) / 2, q = (1 - D) / 2,
			       rr = 2 * sqrt(pp * q);
			double c = cos(2 * th), sn = sin(2 * th);
			double tm[4][4] = {{pp + q, (pp - q) * c, (pp - q) * sn, 0},
			                   {(pp - q) * c, (pp + q) * c * c + rr * sn * sn,
			                    (pp + q - rr) * c * sn, 0},
			                   {(pp - q) * sn, (pp + q - rr) * c * sn,
			                    (pp + q) * sn * sn + rr * c * c, 0},
			                   {0, 0, 0, rr}};
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					Dm[i][j] = 0.5 * tm[i][j];
		}
		pc_retarder_mueller(70 * DEG, 60 * DEG, Rm);
		pc_mueller_mul(Rm, Dm, T);
		/* field-mean intensities of a sample → M through a system */
		double errs[2];
		for (int pass = 0; pass < 2; pass++) {
			simstack ss;
			CHECK_EQ_INT(open_stack(&ss, pass ? "ecm_sample_ideal" : "ecm_sample", 16,
			                        NAN, NAN, 30 + pass),
			             0);
			double I[32] = {0};
			float *row = malloc(RW * RH * sizeof *row);
			for (size_t j = 0; j < 16; j++) {
				pc_view v;
				CHECK_EQ_INT(sim_get(&ss, j, &v), 0);
				pc_view_to_f32(&v, row, RW * sizeof(float));
				pc_view_free(&v);
				double sum[4] = {0}, n[4] = {0};
				for (size_t p = 0; p < RW * RH; p++) {
					unsigned c =
					    pc_mosaic_channel(&ss.info.mosaic, p % RW, p / RW);
					sum[c] += row[p] - dark.dark[p];
					n[c]++;
				}
				for (int c = 0; c < 4; c++)
					I[(j % 8) * 4 + c] += sum[c] / n[c] / 2;
			}
			free(row);
			close_stack(&ss);
			pc_mueller_system sys;
			if (pass == 0) {
				double psg[4][4], psa[2][4][4],
				    an[4][4] = {
				        {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
				for (int g = 0; g < 4; g++)
					for (int i = 0; i < 4; i++)
						psg[g][i] = ecal.ecm_W[i][g];
				for (int a = 0; a < 2; a++)
					for (int i = 0; i < 4; i++)
						memcpy(psa[a][i], ecal.ecm_A[4 * a + i],
						       sizeof psa[a][i]);
				CHECK_EQ_INT(pc_mueller_system_init(&sys, 4,
				                                    (const double(*)[4])psg, 2,
				                                    (const double(*)[4][4])psa,
				                                    (const double(*)[4])an),
				             0);
			} else {
				/* the nominal polarimeter: polarizer + 132° retarder at ±15.1°,
				 * ±51.7°, quarter-wave plates at 0° and 45°, ideal DoFP rows */
				static const double ra[4] = {15.1, 51.7, -51.7, -15.1};
				double psg[4][4], psa[2][4][4];
				for (int g = 0; g < 4; g++) {
					double R[4][4], s0[4] = {1, 1, 0, 0};
					pc_retarder_mueller(ra[g] * DEG, 132 * DEG, R);
					pc_mueller_apply(R, s0, psg[g]);
				}
				pc_retarder_mueller(0, 90 * DEG, psa[0]);
				pc_retarder_mueller(45 * DEG, 90 * DEG, psa[1]);
				CHECK_EQ_INT(
				    pc_mueller_system_init(&sys, 4, (const double(*)[4])psg, 2,
				                           (const double(*)[4][4])psa, NULL),
				    0);
			}
			double M[4][4], e2 = 0;
			pc_mueller_solve(&sys, I, M);
			for (int k = 1; k < 16; k++) {
				double d = M[k / 4][k % 4] / M[0][0] - T[k / 4][k % 4] / T[0][0];
				e2 += d * d;
			}
			errs[pass] = sqrt(e2 / 15);
		}
		printf("ECM sim: sample error (RMS of M/M00) calibrated %.5f, ideal polarimeter "
		       "%.5f\n",
		       errs[0], errs[1]);
		CHECK(errs[0] <= 2 * errs[1]);
		CHECK(errs[0] < 0.01);
		pc_calib_free(&ecal);
		for (int i = 0; i < 4; i++)
			close_stack(&es[i]);
	}

	pc_calib_free(&uncal);
	pc_calib_free(&cal);
	pc_calib_free(&flat);
	pc_calib_free(&dark);
	for (int k = 0; k < 6; k++)
		close_stack(&pst[k]);
	close_stack(&fl);
	close_stack(&fh);
	close_stack(&dk);
	pc_view_free(&avg12);
	close_stack(&d12);
	return pc_test_finish("test_calib");
}
