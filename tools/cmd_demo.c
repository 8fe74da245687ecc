/* polarcam demo: the main job. Renders the default scene through the sensor model, runs the
 * raw frame through the pipeline (several demosaicking methods), compares the estimates with
 * the ground truth, does Mueller imaging of the same scene from a PSG × PSA frame sequence, and
 * writes pictures and a report. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/sim.h"
#include "polarcam/stokes.h"
#include "sim_cli.h"

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam demo [-o DIR] [options]\n"
		"\n"
		"The main job, on the built-in default scene (the seed paper's black and green paints on\n"
		"spheres and a ground plane, IMX250MZR-class sensor, 2448x2048):\n"
		"  1. renders the ground truth and one raw frame through the sensor model;\n"
		"  2. runs the raw frame through the pipeline (demosaicking -> Stokes -> DoLP/AoLP) with\n"
		"     several methods, timing each, and scores them against the truth;\n"
		"  3. renders a Mueller-imaging sequence of the same scene (tetrahedral generator x\n"
		"     quarter-wave analyser, 8 frames, at 612x512 with the same field of view),\n"
		"     reconstructs per-pixel Mueller matrices and compares the Lu-Chipman D, R, Delta\n"
		"     maps with the truth;\n"
		"  4. writes pictures, .npy arrays and report.md / report.json into DIR.\n"
		"\n"
		"options:\n"
		"  -o, --output DIR    output directory (default polarcam-demo)\n"
		"  --scene FILE        another scene instead of the default\n"
		"  -s, --seed S        noise seed (default 1)\n"
		"  --methods LIST      demosaicking methods to compare (default\n"
		"                      superpixel,bilinear,bicubic,ppid,eari,ratio)\n"
		"  --no-mueller        skip step 3\n"
		"  -t, --threads N     threads\n"
		"Exit status: 0 success, 1 failure, 2 bad arguments.\n");
}

/* ---- small image statistics ---- */

typedef struct accuracy {
	char method[32];
	double seconds;
	double s0_rel_rms, dolp_bias, dolp_rms, aolp_err_deg, aolp_median_deg;
	long pixels, aolp_pixels;
} accuracy;

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

static double median(double *v, size_t n)
{
	if (!n)
		return NAN;
	qsort(v, n, sizeof *v, cmp_d);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* angular difference of two AoLPs in [0, π): in [0, π/2] */
static double aolp_diff(double a, double b)
{
	double d = fabs(a - b);
	return d > M_PI / 2 ? M_PI - d : d;
}

/* Scores an estimate (s0, dolp, aolp planes, W×H) against truth arrays in the same units. The
 * mask keeps pixels that are neither saturated nor in the dark (truth S0 above 2 % of full
 * scale; brightest analyser below 95 % of it). */
static void score(const float *s0, const float *dolp, const float *aolp, const float *t_s0,
		  const float *t_dolp, const float *t_aolp, uint32_t W, uint32_t H, double full,
		  accuracy *acc)
{
	double se = 0, sb = 0, sd = 0, sa = 0, sw = 0;
	long n = 0, na = 0;
	double *ad = malloc(sizeof(double) * (size_t)W * H);
	for (size_t i = 0; i < (size_t)W * H; i++) {
		double T = t_s0[i], P = t_dolp[i];
		if (!(T > 0.02 * full) || T * (1 + P) / 2 > 0.95 * full)
			continue;
		double r = (s0[i] - T) / T;
		se += r * r;
		sb += dolp[i] - P;
		sd += (dolp[i] - P) * (dolp[i] - P);
		n++;
		if (P > 0.05) {
			double d = aolp_diff(aolp[i], t_aolp[i]);
			sa += P * d;
			sw += P;
			ad[na++] = d;
		}
	}
	acc->pixels = n;
	acc->aolp_pixels = na;
	acc->s0_rel_rms = n ? sqrt(se / n) : NAN;
	acc->dolp_bias = n ? sb / n : NAN;
	acc->dolp_rms = n ? sqrt(sd / n) : NAN;
	acc->aolp_err_deg = sw > 0 ? sa / sw * 180 / M_PI : NAN;
	acc->aolp_median_deg = median(ad, (size_t)na) * 180 / M_PI;
	free(ad);
}

/* DoLP and AoLP of truth Stokes (H, W, 4) scaled to DN */
static void truth_planes(const float *ts, size_t n, double scale, float *s0, float *dolp, float *aolp)
{
	for (size_t i = 0; i < n; i++) {
		double S0 = ts[4 * i], S1 = ts[4 * i + 1], S2 = ts[4 * i + 2];
		s0[i] = (float)(S0 * scale);
		dolp[i] = S0 > 0 ? (float)fmin(1, sqrt(S1 * S1 + S2 * S2) / S0) : 0;
		double a = 0.5 * atan2(S2, S1);
		aolp[i] = (float)(a < 0 ? a + M_PI : a);
	}
}

/* ---- sim as a frame source for the Mueller step ---- */

typedef struct sim_src {
	pc_sim *sim;
	pc_sim_info in;
	uint8_t *saturated; /* per pixel: saturated in some frame */
	uint16_t full;
} sim_src;

static int sim_get(void *user, size_t j, pc_view *out)
{
	sim_src *s = user;
	int rc = pc_view_alloc(out, s->in.format, s->in.width, s->in.height, 64);
	if (rc)
		return rc;
	rc = pc_sim_frame(s->sim, j, NULL, out, NULL);
	if (rc) {
		pc_view_free(out);
		return rc;
	}
	if (s->saturated && s->in.bits > 8)
		for (uint32_t y = 0; y < out->height; y++) {
			const uint16_t *r = PC_ROW(out, uint16_t, y);
			for (uint32_t x = 0; x < out->width; x++)
				if (r[x] >= s->full)
					s->saturated[(size_t)y * out->width + x] = 1;
		}
	return 0;
}

/* The Mueller-imaging variant of a scene: 612×512 (same sensor area), the lights carry
 * the tetrahedral PSG (polarizer 0° + 132° retarder at ±15.1°, ±51.7°; physics.md §7), a
 * quarter-wave plate at 0° and 45° in front of the camera, circular + mueller effects. */
static char *mueller_variant(const char *scene_text, uint32_t w, uint32_t h, double pitch_um,
			     double exposure_us)
{
	json_t *d = json_loads(scene_text, 0, NULL);
	if (!d)
		return NULL;
	/* every light passes through the same generator states (each in its own Stokes frame), so
	 * that the reconstruction and the Mueller ground truth (summed over lights) agree */
	json_t *lights = json_object_get(d, "lights");
	size_t li;
	json_t *l;
	json_array_foreach(lights, li, l) {
		json_object_del(l, "polarization");
		json_t *st = json_array();
		const double ang[4] = { 15.1, 51.7, -51.7, -15.1 };
		for (int i = 0; i < 4; i++)
			json_array_append_new(st, json_pack("{s:f, s:{s:f, s:f}}", "polarizer_deg", 0.0,
							    "retarder", "angle_deg", ang[i],
							    "retardance_deg", 132.0));
		json_object_set_new(l, "states", st);
	}
	json_t *fx = json_object_get(d, "effects");
	if (!fx) {
		fx = json_object();
		json_object_set_new(d, "effects", fx);
	}
	json_object_set_new(fx, "circular", json_true());
	json_object_set_new(fx, "mueller", json_true());
	json_t *sen = json_object_get(d, "sensor");
	if (!sen) {
		sen = json_object();
		json_object_set_new(d, "sensor", sen);
	}
	json_object_set_new(sen, "resolution", json_pack("[i, i]", (int)w, (int)h));
	json_object_set_new(sen, "pixel_pitch_um", json_real(pitch_um));
	json_object_set_new(sen, "exposure_us", json_real(exposure_us));
	json_object_set_new(sen, "psa",
			    json_pack("[{s:{s:f, s:f}}, {s:{s:f, s:f}}]", "retarder", "angle_deg", 0.0,
				      "retardance_deg", 90.0, "retarder", "angle_deg", 45.0,
				      "retardance_deg", 90.0));
	char *txt = json_dumps(d, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(d);
	return txt;
}

static double map_median_abs_err(const float *est, const float *truth, const float *w, size_t n,
				 double wmin, bool angle_pi, long *used)
{
	double *v = malloc(sizeof(double) * n);
	size_t k = 0;
	for (size_t i = 0; i < n; i++)
		if (w[i] > wmin && isfinite(est[i]) && isfinite(truth[i])) {
			double d = fabs(est[i] - truth[i]);
			if (angle_pi && d > M_PI / 2)
				d = M_PI - d; /* retardance near π: keep the absolute difference */
			v[k++] = d;
		}
	double m = median(v, k);
	free(v);
	*used = (long)k;
	return m;
}

int cmd_demo(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {
		{ "output", required_argument, NULL, 'o' }, { "scene", required_argument, NULL, 'S' },
		{ "seed", required_argument, NULL, 's' },   { "methods", required_argument, NULL, 'M' },
		{ "no-mueller", no_argument, NULL, 'N' },   { "threads", required_argument, NULL, 't' },
		{ NULL, 0, NULL, 0 }
	};
	const char *out = "polarcam-demo", *scene_path = NULL;
	const char *methods_arg = "superpixel,bilinear,bicubic,ppid,eari,ratio";
	uint64_t seed = 1;
	long threads = 0;
	bool do_mueller = true;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":o:s:t:", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			out = optarg;
			break;
		case 'S':
			scene_path = optarg;
			break;
		case 's':
			if ((rc = cli_parse_u64("--seed", optarg, &seed)))
				return cli_fail(rc, NULL);
			break;
		case 'M':
			methods_arg = optarg;
			break;
		case 'N':
			do_mueller = false;
			break;
		case 't':
			if ((rc = cli_parse_long("--threads", optarg, 1, 1024, &threads)))
				return cli_fail(rc, NULL);
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)", argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
		}
	}
	if (optind < argc)
		return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (see --help)", argv[optind]);
	/* methods */
	pc_demosaic_method methods[PC_DM_COUNT];
	unsigned nm = 0;
	{
		char buf[256];
		snprintf(buf, sizeof buf, "%s", methods_arg);
		char *save = NULL;
		for (char *t = strtok_r(buf, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
			if (nm == PC_DM_COUNT)
				return cli_error(CLI_EXIT_USAGE, "--methods: too many");
			if ((rc = pc_demosaic_method_from_name(t, &methods[nm])))
				return cli_fail(rc, "--methods");
			if (methods[nm] == PC_DM_SUPERPIXEL_HALF)
				methods[nm] = PC_DM_SUPERPIXEL; /* full resolution, comparable */
			nm++;
		}
		if (!nm)
			return cli_error(CLI_EXIT_USAGE, "--methods: empty list");
	}
	double t_all = cli_now();
	int status = CLI_EXIT_OK;
	pc_scene *scene = NULL;
	pc_sim *sim = NULL, *msim = NULL;
	pc_scene *mscene = NULL;
	pc_recording *rec = NULL;
	pc_view raw = { 0 };
	float *ts = NULL, *tp = NULL, *ep = NULL;
	json_t *report = json_object(), *jm = json_array();
	char *mtext = NULL;
	accuracy acc[PC_DM_COUNT];
	pc_mueller_result mres = { 0 };
	float *tM = NULL, *tmaps = NULL;
	char path[4096];

	rc = scene_path ? pc_scene_load(scene_path, &scene) : pc_scene_load_default(&scene);
	if (rc) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	pc_sim_options o = pc_sim_options_default();
	o.seed = seed;
	o.threads = (int)threads;
	if ((rc = pc_sim_new(scene, &o, &sim))) {
		status = cli_fail(rc, "scene");
		goto done;
	}
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	if (in.colour_channels != 1) {
		status = cli_error(CLI_EXIT_USAGE, "the demo handles monochrome sensors; render colour "
						     "scenes with polarcam render");
		goto done;
	}
	const uint32_t W = in.width, H = in.height;
	const size_t np = (size_t)W * H;
	if ((rc = pc_mkdir_p(out))) {
		status = cli_fail(rc, out);
		goto done;
	}
	fprintf(stderr, "polarcam demo: %s, %ux%u, effects:", pc_scene_name(scene), W, H);
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (in.effects & (1u << i))
			fprintf(stderr, " %s", pc_sim_effect_name(1u << i));
	fprintf(stderr, "\n");

	/* 1. truth + raw frame 0 */
	ts = malloc(np * 4 * sizeof *ts);
	if (!ts) {
		status = cli_error(CLI_EXIT_FAILURE, "out of memory");
		goto done;
	}
	cli_progress bar;
	cli_progress_begin(&bar, "render",
			  (in.effects & PC_FX_CROSSTALK) ? 2 * (uint64_t)H + 2 : (uint64_t)H);
	pc_sim_progress_adapter ad = { &bar, 0 };
	double t0 = cli_now();
	rc = pc_sim_prepare(sim, 0, ts, NULL, pc_sim_progress_cb, &ad);
	cli_progress_end(&bar);
	double t_render = cli_now() - t0;
	if (rc) {
		status = cli_fail(rc, "render");
		goto done;
	}
	if ((rc = pc_view_alloc(&raw, in.format, W, H, 64))) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	pc_frame fr;
	t0 = cli_now();
	rc = pc_sim_frame(sim, 0, NULL, &raw, &fr.meta);
	double t_frame = cli_now() - t0;
	if (rc) {
		status = cli_fail(rc, "frame");
		goto done;
	}
	char source[1024];
	snprintf(source, sizeof source, "sim:%s?seed=%llu", scene_path ? scene_path : "default",
		 (unsigned long long)seed);
	pc_recording_desc desc = { source, in.format, NULL, W, H, in.offset_x, in.offset_y,
				   in.sensor_width, in.sensor_height, true, in.mosaic };
	fr.view = raw;
	fr.mosaic = in.mosaic;
	if ((rc = pc_recording_create(&rec, out, &desc, true)) || (rc = pc_recording_add(rec, &fr))) {
		status = cli_fail(rc, out);
		goto done;
	}
	json_t *extra = pc_sim_describe(sim, scene);
	char *et = json_dumps(extra, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_object_set_new(report, "simulation", extra);
	rc = et ? pc_recording_set_json(rec, "extra", et) : PC_ENOMEM;
	free(et);
	if (rc || (rc = pc_recording_finish(rec, NULL))) {
		status = cli_fail(rc, "meta.json");
		goto done;
	}
	size_t shp[3] = { H, W, 4 };
	if ((rc = pc_path_join(path, sizeof path, out, "truth_stokes.npy")) ||
	    (rc = pc_npy_write(path, ts, PC_DT_F32, 3, shp))) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	/* truth in DN (the pipeline's units): pictures of truth and estimate share one scale */
	const double scale = pc_sim_dn_per_radiance(sim, NULL, 0);
	const double full = (double)((1u << in.bits) - 1);
	tp = malloc(np * 3 * sizeof *tp);
	ep = malloc(np * 5 * sizeof *ep);
	if (!tp || !ep) {
		status = cli_error(CLI_EXIT_FAILURE, "out of memory");
		goto done;
	}
	float *t_s0 = tp, *t_dolp = tp + np, *t_aolp = tp + 2 * np;
	truth_planes(ts, np, scale, t_s0, t_dolp, t_aolp);
	long saturated = 0;
	for (uint32_t y = 0; y < H; y++) {
		const uint16_t *r = PC_ROW(&raw, uint16_t, y);
		for (uint32_t x = 0; x < W; x++)
			saturated += r[x] >= full;
	}
	char dir[4096];
	pc_stokes_out so = { { t_s0, W, 1 }, { NULL, 0, 0 }, { NULL, 0, 0 }, { t_dolp, W, 1 },
			     { t_aolp, W, 1 } };
	if ((rc = pc_path_join(dir, sizeof dir, out, "truth")) || (rc = pc_mkdir_p(dir)) ||
	    (rc = pc_pictures_write(dir, &so, W, H, "truth"))) {
		status = cli_fail(rc, dir);
		goto done;
	}

	/* 2. the pipeline with each method */
	float *e_s0 = ep, *e_s1 = ep + np, *e_s2 = ep + 2 * np, *e_dolp = ep + 3 * np,
	      *e_aolp = ep + 4 * np;
	unsigned best = 0;
	{
		/* one untimed bilinear run first: thread start-up and first-touch costs would
		 * otherwise land in the first method's time */
		pc_stokes_out wo = { { e_s0, W, 1 }, { e_s1, W, 1 }, { e_s2, W, 1 }, { e_dolp, W, 1 },
				     { e_aolp, W, 1 } };
		pc_demosaic_opts wopt = { (int)threads, false, 0 };
		if ((rc = pc_stokes_from_raw(&raw, &in.mosaic, PC_DM_BILINEAR, &wopt, &wo))) {
			status = cli_fail(rc, "bilinear");
			goto done;
		}
	}
	for (unsigned m = 0; m < nm; m++) {
		pc_stokes_out eo = { { e_s0, W, 1 }, { e_s1, W, 1 }, { e_s2, W, 1 }, { e_dolp, W, 1 },
				     { e_aolp, W, 1 } };
		pc_demosaic_opts dopt = { (int)threads, false, 0 };
		t0 = cli_now();
		rc = pc_stokes_from_raw(&raw, &in.mosaic, methods[m], &dopt, &eo);
		double dt = cli_now() - t0;
		if (rc) {
			status = cli_fail(rc, pc_demosaic_method_get(methods[m])->name);
			goto done;
		}
		snprintf(acc[m].method, sizeof acc[m].method, "%s",
			 pc_demosaic_method_get(methods[m])->name);
		acc[m].seconds = dt;
		score(e_s0, e_dolp, e_aolp, t_s0, t_dolp, t_aolp, W, H, full, &acc[m]);
		if (acc[m].dolp_rms < acc[best].dolp_rms)
			best = m;
		bool bilinear = methods[m] == PC_DM_BILINEAR;
		if (bilinear || m + 1 == nm) {
			char sub[96];
			if (snprintf(sub, sizeof sub, "pipeline_%.40s", acc[m].method) >= (int)sizeof sub)
				sub[sizeof sub - 1] = '\0';
			if ((rc = pc_path_join(dir, sizeof dir, out, sub)) || (rc = pc_mkdir_p(dir)) ||
			    (rc = pc_pictures_write(dir, &eo, W, H, acc[m].method))) {
				status = cli_fail(rc, dir);
				goto done;
			}
		}
		if (bilinear) {
			/* stokes.npy (H, W, 3): S0, S1, S2 in DN from the bilinear pipeline */
			float *st3 = malloc(np * 3 * sizeof *st3);
			if (!st3) {
				status = cli_error(CLI_EXIT_FAILURE, "out of memory");
				goto done;
			}
			for (size_t i = 0; i < np; i++) {
				st3[3 * i] = e_s0[i];
				st3[3 * i + 1] = e_s1[i];
				st3[3 * i + 2] = e_s2[i];
			}
			size_t s3[3] = { H, W, 3 };
			rc = pc_path_join(path, sizeof path, out, "stokes.npy");
			if (!rc)
				rc = pc_npy_write(path, st3, PC_DT_F32, 3, s3);
			free(st3);
			if (rc) {
				status = cli_fail(rc, NULL);
				goto done;
			}
		}
	}
	free(ep);
	ep = NULL;
	pc_view_free(&raw);
	free(ts);
	ts = NULL;
	free(tp);
	tp = NULL;

	/* 3. Mueller imaging of the same scene */
	double t_mueller = 0;
	long m_used[3] = { 0, 0, 0 }, m_saturated = 0;
	double m_med[3] = { NAN, NAN, NAN };
	const uint32_t mw = in.sensor_width / 4 / 2 * 2, mh = in.sensor_height / 4 / 2 * 2;
	if (do_mueller) {
		pc_sensor_figures fig;
		pc_sim_get_sensor(sim, &fig);
		char *doc = pc_scene_to_json(scene);
		/* same sensor area: 4× the pitch; 1/16 of the exposure keeps the signal per pixel */
		double ratio = (double)in.sensor_width / mw;
		mtext = doc ? mueller_variant(doc, mw, mh, fig.pixel_pitch_um * ratio,
					      fig.exposure_us / (ratio * ratio))
			    : NULL;
		free(doc);
		if (!mtext) {
			status = cli_error(CLI_EXIT_FAILURE, "cannot build the Mueller scene");
			goto done;
		}
		if ((rc = pc_scene_parse(mtext, "demo Mueller scene", ".", &mscene)) ||
		    (rc = pc_sim_new(mscene, &o, &msim))) {
			status = cli_fail(rc, "Mueller scene");
			goto done;
		}
		sim_src src = { msim, { 0 }, NULL, 0 };
		pc_sim_get_info(msim, &src.in);
		src.full = (uint16_t)((1u << src.in.bits) - 1);
		src.saturated = calloc((size_t)mw * mh, 1);
		if (!src.saturated) {
			status = cli_error(CLI_EXIT_FAILURE, "out of memory");
			goto done;
		}
		pc_sim_states st;
		pc_sim_get_states(msim, &st);
		size_t mnp = (size_t)mw * mh;
		tM = malloc(mnp * 16 * sizeof *tM);
		tmaps = malloc(mnp * 3 * sizeof *tmaps);
		if (!tM || !tmaps) {
			status = cli_error(CLI_EXIT_FAILURE, "out of memory");
			goto done;
		}
		t0 = cli_now();
		cli_progress_begin(&bar, "mueller render", src.in.n_psg);
		for (unsigned g = 0; g < src.in.n_psg; g++) {
			if ((rc = pc_sim_prepare(msim, g, NULL, g == 0 ? tM : NULL, NULL, NULL))) {
				cli_progress_end(&bar);
				status = cli_fail(rc, "Mueller render");
				goto done;
			}
			cli_progress_update(&bar, g + 1);
		}
		cli_progress_end(&bar);
		cli_progress_begin(&bar, "mueller frames", src.in.n_states);
		rc = pc_mueller_run(sim_get, &src, &st, &src.in.mosaic, PC_DM_BILINEAR, 0, (int)threads, NULL,
				    &bar, &mres);
		cli_progress_end(&bar);
		t_mueller = cli_now() - t0;
		if (rc) {
			free(src.saturated);
			status = cli_fail(rc, "Mueller imaging");
			goto done;
		}
		/* truth maps from the truth Mueller image */
		pc_mueller_maps(tM, mw, mh, 0xFFFFu, (int)threads, tmaps, tmaps + mnp, tmaps + 2 * mnp,
				NULL);
		if ((rc = pc_path_join(dir, sizeof dir, out, "mueller")) || (rc = pc_mkdir_p(dir))) {
			status = cli_fail(rc, dir);
			goto done;
		}
		const char *names[3] = { "D", "R", "Delta" }, *labels[3] = { "D", "R (rad)", "Delta" };
		const double his[3] = { 1, M_PI, 1 };
		/* compared pixels: truth signal above 100 DN per frame (S0 of a generator state) and
		 * no frame saturated (the bilinear demosaic spreads a saturated pixel to its
		 * neighbours: they are excluded too) */
		float *w = malloc(mnp * sizeof *w);
		const double mscale = pc_sim_dn_per_radiance(msim, NULL, 0), wmax = 1;
		for (size_t i = 0; i < mnp; i++) {
			uint32_t x = (uint32_t)(i % mw), y = (uint32_t)(i / mw);
			bool sat = false;
			for (int dy = -1; dy <= 1; dy++)
				for (int dx = -1; dx <= 1; dx++) {
					int64_t xx = (int64_t)x + dx, yy = (int64_t)y + dy;
					if (xx >= 0 && yy >= 0 && xx < mw && yy < mh)
						sat |= src.saturated[(size_t)yy * mw + (size_t)xx] != 0;
				}
			w[i] = !sat && tM[16 * i] * mscale > 100 ? 1.0f : 0.0f;
			m_saturated += sat;
		}
		free(src.saturated);
		for (int k = 0; k < 3; k++) {
			char nm_[32], title[96];
			snprintf(title, sizeof title, "%s from 8 simulated frames (cond %.2f)", names[k],
				 mres.sys.cond_W);
			if ((rc = pc_write_map(dir, names[k], mres.maps + (size_t)k * mnp, mw, mh, 0,
					       his[k], title, labels[k]))) {
				free(w);
				status = cli_fail(rc, dir);
				goto done;
			}
			snprintf(nm_, sizeof nm_, "truth_%s", names[k]);
			snprintf(title, sizeof title, "%s ground truth", names[k]);
			if ((rc = pc_write_map(dir, nm_, tmaps + (size_t)k * mnp, mw, mh, 0, his[k], title,
					       labels[k]))) {
				free(w);
				status = cli_fail(rc, dir);
				goto done;
			}
			/* retardance is defined where the light keeps its polarization: compare R
			 * only where the truth depolarization Δ < 0.5 */
			float *wk = w;
			float *wr = NULL;
			if (k == 1) {
				wr = malloc(mnp * sizeof *wr);
				if (wr)
					for (size_t i = 0; i < mnp; i++)
						wr[i] = tmaps[2 * mnp + i] < 0.5f ? w[i] : 0;
				wk = wr ? wr : w;
			}
			m_med[k] = map_median_abs_err(mres.maps + (size_t)k * mnp, tmaps + (size_t)k * mnp,
						      wk, mnp, 0.5 * wmax, k == 1, &m_used[k]);
			free(wr);
		}
		free(w);
		size_t ms[4] = { mh, mw, 4, 4 };
		if ((rc = pc_path_join(path, sizeof path, dir, "truth_mueller.npy")) ||
		    (rc = pc_npy_write(path, tM, PC_DT_F32, 4, ms)) ||
		    (rc = pc_path_join(path, sizeof path, dir, "mueller.npy")) ||
		    (rc = pc_npy_write(path, mres.M, PC_DT_F32, 4, ms))) {
			status = cli_fail(rc, NULL);
			goto done;
		}
	}

	/* 4. report */
	double t_total = cli_now() - t_all;
	json_t *jt = json_object();
	json_object_set_new(jt, "render_s", json_real(t_render));
	json_object_set_new(jt, "frame_s", json_real(t_frame));
	json_object_set_new(jt, "mueller_s", json_real(t_mueller));
	json_object_set_new(jt, "total_s", json_real(t_total));
	json_object_set_new(jt, "peak_rss_mib", cli_json_real(pc_peak_rss_mib()));
	json_object_set_new(report, "timings", jt);
	json_object_set_new(report, "saturated_pixels", json_integer(saturated));
	json_object_set_new(report, "dn_per_radiance", json_real(scale));
	for (unsigned m = 0; m < nm; m++) {
		json_t *e = json_object();
		json_object_set_new(e, "method", json_string(acc[m].method));
		json_object_set_new(e, "seconds", json_real(acc[m].seconds));
		json_object_set_new(e, "s0_rel_rms", cli_json_real(acc[m].s0_rel_rms));
		json_object_set_new(e, "dolp_bias", cli_json_real(acc[m].dolp_bias));
		json_object_set_new(e, "dolp_rms", cli_json_real(acc[m].dolp_rms));
		json_object_set_new(e, "aolp_weighted_err_deg", cli_json_real(acc[m].aolp_err_deg));
		json_object_set_new(e, "aolp_median_err_deg", cli_json_real(acc[m].aolp_median_deg));
		json_object_set_new(e, "pixels", json_integer(acc[m].pixels));
		json_array_append_new(jm, e);
	}
	json_object_set(report, "pipeline", jm);
	if (do_mueller) {
		json_t *mj = json_object();
		json_object_set_new(mj, "width", json_integer(mw));
		json_object_set_new(mj, "height", json_integer(mh));
		json_object_set_new(mj, "frames", json_integer(mres.sys.n_psg * mres.sys.n_psa));
		json_object_set_new(mj, "cond_A", cli_json_real(mres.sys.cond_A));
		json_object_set_new(mj, "cond_G", cli_json_real(mres.sys.cond_G));
		json_object_set_new(mj, "cond_W", cli_json_real(mres.sys.cond_W));
		json_object_set_new(mj, "median_abs_err_D", cli_json_real(m_med[0]));
		json_object_set_new(mj, "median_abs_err_R_rad", cli_json_real(m_med[1]));
		json_object_set_new(mj, "median_abs_err_Delta", cli_json_real(m_med[2]));
		json_object_set_new(mj, "pixels_compared", json_integer(m_used[0]));
		json_object_set_new(mj, "pixels_compared_R", json_integer(m_used[1]));
		json_object_set_new(mj, "pixels_nonphysical_filtered", json_integer(mres.nonphysical));
		json_object_set_new(report, "mueller", mj);
	}
	char *rj = json_dumps(report, JSON_INDENT(1) | JSON_REAL_PRECISION(10));
	if (!rj || (rc = pc_path_join(path, sizeof path, out, "report.json")) ||
	    (rc = pc_write_file_atomic(path, rj, strlen(rj)))) {
		free(rj);
		status = cli_fail(rc ? rc : PC_ENOMEM, "report.json");
		goto done;
	}
	free(rj);
	/* report.md */
	char *md = NULL;
	size_t mdlen = 0;
	FILE *mf = open_memstream(&md, &mdlen);
	if (!mf) {
		status = cli_error(CLI_EXIT_FAILURE, "out of memory");
		goto done;
	}
	fprintf(mf, "# polarcam demo\n\nScene `%s` (%ux%u), seed %llu. Effects:", pc_scene_name(scene),
		W, H, (unsigned long long)seed);
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (in.effects & (1u << i))
			fprintf(mf, " %s", pc_sim_effect_name(1u << i));
	fprintf(mf, ".\nRender %.2f s (ray casting + pBRDF, once), one noisy frame %.2f s, total %.1f s, "
		    "peak memory %.0f MiB.\n\n", t_render, t_frame, t_total, pc_peak_rss_mib());
	fprintf(mf, "## Pipeline estimates against the ground truth\n\n"
		    "Raw frame 0 (`raw_000000.png`) demosaicked and turned into Stokes/DoLP/AoLP, compared "
		    "with `truth_stokes.npy` (converted to DN: %.4g DN per W m^-2 sr^-1) over %ld pixels that "
		    "are neither dark (S0 < 2 %% of full scale) nor saturated; %ld raw pixels are saturated. "
		    "AoLP errors over pixels with truth DoLP > 0.05, weighted by DoLP.\n\n"
		    "| method | time (s) | S0 rel. RMS | DoLP bias | DoLP RMS | AoLP err (deg, weighted) | AoLP median (deg) |\n"
		    "|---|---|---|---|---|---|---|\n", scale, acc[0].pixels, saturated);
	for (unsigned m = 0; m < nm; m++)
		fprintf(mf, "| %s%s | %.3f | %.4f | %+.4f | %.4f | %.2f | %.2f |\n", acc[m].method,
			m == best ? " (best DoLP)" : "", acc[m].seconds, acc[m].s0_rel_rms,
			acc[m].dolp_bias, acc[m].dolp_rms, acc[m].aolp_err_deg, acc[m].aolp_median_deg);
	fprintf(mf, "\nThe DoLP bias is positive where the signal is low: the estimator's noise "
		    "floor (physics.md §6). Pictures: `truth/` and `pipeline_<method>/` (s0, dolp, aolp, "
		    "aolp_sat); `stokes.npy` is the bilinear estimate (H, W, 3) in DN.\n\n");
	if (do_mueller)
		fprintf(mf, "## Mueller imaging\n\nThe same scene at %ux%u (same field of view), "
			    "tetrahedral generator (polarizer + 132° retarder at ±15.1°, ±51.7°) × quarter-"
			    "wave analyser at 0°/45° in front of the DoFP: %u frames, cond(A) = %.3f, "
			    "cond(G) = %.3f, cond(W) = %.3f. Per-pixel least squares (bilinear demosaic), then "
			    "Lu–Chipman; compared with the decomposition of the Mueller ground truth over "
			    "the lit pixels (signal above 100 DN) that no frame saturates (%ld pixels are "
			    "excluded as saturated or next to a saturated one):\n\n"
			    "| map | median abs. error | pixels |\n|---|---|---|\n| D | %.4f | %ld |\n"
			    "| R (rad, where truth Delta < 0.5) | %.4f | %ld |\n| Delta | %.4f | %ld |\n\n"
			    "%ld pixels had non-physical noisy matrices (Cloude-filtered "
			    "before decomposing). Files: `mueller/` (D, R, Delta and truth_* as .npy and "
			    ".png, mueller.npy, truth_mueller.npy).\n",
			mw, mh, mres.sys.n_psg * mres.sys.n_psa, mres.sys.cond_A, mres.sys.cond_G,
			mres.sys.cond_W, m_saturated, m_med[0], m_used[0], m_med[1], m_used[1], m_med[2],
			m_used[2], mres.nonphysical);
	fclose(mf);
	rc = pc_path_join(path, sizeof path, out, "report.md");
	if (!rc)
		rc = pc_write_file_atomic(path, md, mdlen);
	fputs(md, stdout);
	free(md);
	if (rc) {
		status = cli_fail(rc, "report.md");
		goto done;
	}
done:
	if (rec)
		pc_recording_free(rec);
	pc_view_free(&raw);
	free(ts);
	free(tp);
	free(ep);
	free(tM);
	free(tmaps);
	free(mtext);
	pc_mueller_result_free(&mres);
	json_decref(jm);
	json_decref(report);
	pc_sim_free(msim);
	pc_scene_free(mscene);
	pc_sim_free(sim);
	pc_scene_free(scene);
	return status;
}
