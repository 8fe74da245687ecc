/* polarcam bench calib: what analyser-calibration accuracy costs. For K polarizer angles
 * (evenly over 180°) × F frames per angle, the residual DoLP and AoLP errors of DoLP-0.5
 * stimuli at 4 other AoLPs (64 frames averaged, bilinear) after dark + flat + analyser
 * calibration of the imx250mzr_nonuniform preset, and the acquisition time of the sweep at the
 * sensor's frame rate plus a stated time per polarizer rotation. No timing is measured: the
 * acquisition time is computed. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"
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

/* RMS DoLP and AoLP errors of the averaged stimulus over the interior */
static int errors(pc_calib *cal, bstack *t, size_t frames, double angle, double *ed, double *ea)
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
	pc_stokes_out out = { 0 };
	pc_fplane *pl[5] = { &out.s0, &out.s1, &out.s2, &out.dolp, &out.aolp };
	for (int k = 0; k < 5; k++) {
		pl[k]->data = buf + (size_t)k * np;
		pl[k]->row_stride = W;
		pl[k]->pixel_stride = 1;
	}
	if (!rc)
		rc = pc_calib_stokes(cal, &avg, NULL, PC_DM_BILINEAR, 0, &out, NULL, NULL);
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

int pc_bench_calib(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	static const struct option opts[] = { { "size", required_argument, NULL, 's' },
					      { "rotation-s", required_argument, NULL, 'r' },
					      { "json", no_argument, NULL, 'J' },
					      { "help", no_argument, NULL, 'h' },
					      { NULL, 0, NULL, 0 } };
	long size = 64;
	double rot_s = 2;
	bool json = false;
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
		case 'h':
			printf("usage: polarcam bench calib [--size N] [--rotation-s S] [--json]\n\n"
			       "Analyser calibration of the imx250mzr_nonuniform preset (N x N ROI, default\n"
			       "64; dark and flat: 32 frames each) with K polarizer angles x F frames per\n"
			       "angle: residual DoLP and AoLP RMS errors on DoLP-0.5 stimuli at 10, 55, 100\n"
			       "and 145 deg (64 frames averaged), and the sweep's acquisition time: K*F\n"
			       "frames at the sensor's 30 fps plus S seconds per polarizer rotation\n"
			       "(default 2, a manual or motorised rotation mount).\n");
			return PC_BENCH_OK;
		default:
			return host->error(PC_BENCH_USAGE, "bad option '%s' (see --help)", argv[optind - 1]);
		}
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	const uint32_t S = (uint32_t)size;
	bstack dk, fl, fh;
	pc_calib dark, flat;
	if ((rc = bopen(&dk, 0, NULL, S, 32, 1000000, NAN, NAN)) ||
	    (rc = bopen(&fl, 0.55, NULL, S, 32, 2000000, NAN, NAN)) ||
	    (rc = bopen(&fh, 1.25, NULL, S, 32, 3000000, NAN, NAN)))
		return host->fail(rc, "bench calib");
	if ((rc = pc_calib_dark(&dk.s, NULL, &dark)))
		return host->fail(rc, "dark");
	pc_calib_stack lv[2] = { fl.s, fh.s };
	if ((rc = pc_calib_flat(lv, 2, &dark, NULL, &flat)))
		return host->fail(rc, "flat");
	static const double tang[4] = { 10, 55, 100, 145 };
	bstack ts[4];
	for (int k = 0; k < 4; k++) {
		char psa[128];
		snprintf(psa, sizeof psa, "{\"diattenuator\": {\"angle_deg\": %g, \"diattenuation\": 0.5}}",
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
		if ((rc = errors(&base, &ts[k], 64, tang[k], &ed, &ea)))
			return host->fail(rc, "uncalibrated");
		ud += ed * ed / 4;
		ua += ea * ea / 4;
	}
	static const unsigned Ks[] = { 3, 4, 6, 8, 12, 16 }, Fs[] = { 1, 4, 16, 64 };
	json_t *rows = json_array();
	if (!json)
		printf("analyser calibration, %ux%u ROI, imx250mzr_nonuniform, DoLP-0.5 test stimuli\n"
		       "uncalibrated (black level only): DoLP RMS %.5f, AoLP RMS %.3f deg\n\n"
		       "%3s %4s %7s %10s %11s %12s\n", S, S, sqrt(ud), sqrt(ua), "K", "F", "frames",
		       "time (s)", "DoLP RMS", "AoLP RMS deg");
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
				if ((rc = errors(&cal, &ts[k], 64, tang[k], &ed, &ea)))
					return host->fail(rc, "calibrated");
				cd += ed * ed / 4;
				ca += ea * ea / 4;
			}
			pc_calib_free(&cal);
			double tsec = K * F / 30.0 + K * rot_s;
			if (json) {
				json_t *r = json_object();
				json_object_set_new(r, "angles", json_integer(K));
				json_object_set_new(r, "frames_per_angle", json_integer(F));
				json_object_set_new(r, "acquisition_s", json_real(tsec));
				json_object_set_new(r, "dolp_rms", json_real(sqrt(cd)));
				json_object_set_new(r, "aolp_rms_deg", json_real(sqrt(ca)));
				json_array_append_new(rows, r);
			} else {
				printf("%3u %4u %7u %10.1f %11.5f %12.4f\n", K, F, K * F, tsec, sqrt(cd),
				       sqrt(ca));
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
