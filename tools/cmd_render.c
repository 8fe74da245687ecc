/* polarcam render: a scene → raw mosaic frames (a recording, devices/recording.h) + ground truth. */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/sim.h"
#include "sim_cli.h"

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam render [SCENE] -o DIR [options]\n"
		"\n"
		"Renders SCENE (a scene file, docs/scene-format.md; the built-in default scene when\n"
		"omitted or \"default\") through the sensor model into DIR:\n"
		"  raw_NNNNNN.png      raw mosaic frames at the sensor's bit depth (16-bit PNG + sBIT\n"
		"                      above 8 bits), numbered by frame: frame N is reproducible alone\n"
		"  truth_stokes.npy    float32 (H, W, 4): S0..S3 radiance in W/(m^2 sr) in the image-\n"
		"                      plane frame (S1 > 0 along image x, AoLP counter-clockwise from x\n"
		"                      as the image is viewed); (H, W, 3, 4) for colour sensors; S3 is\n"
		"                      NaN unless the scene declares the \"circular\" effect. With a\n"
		"                      PSG sequence: truth_stokes_psgNN.npy per generator state\n"
		"  truth_mueller.npy   float32 (H, W, 4, 4) when the scene declares \"mueller\"\n"
		"  states.json         the polarization-state sequence, for polarcam mueller --states\n"
		"  meta.json           frames, format and mosaic (the recording), plus scene, sensor,\n"
		"                      seed, effects, timings and peak memory under \"extra\"\n"
		"\n"
		"options:\n"
		"  -o, --output DIR    output directory (created if missing)\n"
		"  -n, --frames N      number of frames (default 1, or one cycle of the scene's states)\n"
		"      --first N       number of the first frame (default 0)\n"
		"  -s, --seed S        noise seed (default 0)\n"
		"      --roi X,Y,W,H   render only this region of the sensor (bit-identical to a crop)\n"
		"      --no-truth      do not write truth_*.npy\n"
		"  -t, --threads N     threads (default: all cores)\n"
		"      --overwrite     replace a recording already in DIR\n"
		"      --json          print a summary as one JSON line on stdout\n"
		"  -h, --help          this help\n"
		"\n"
		"Progress goes to stderr when it is a terminal (POLARCAM_PROGRESS=1 forces it).\n"
		"Exit status: 0 success, 1 failure, 2 bad arguments or scene.\n");
}

static int parse_roi(const char *arg, pc_sim_options *o)
{
	unsigned long v[4];
	const char *p = arg;
	for (int i = 0; i < 4; i++) {
		char *end;
		errno = 0;
		if (*p == '-' || *p == '+')
			return pc_error(PC_EINVAL, "--roi '%s': expected X,Y,W,H (non-negative integers)", arg);
		v[i] = strtoul(p, &end, 10);
		if (end == p || errno || v[i] > 65535 || (i < 3 && *end != ',') || (i == 3 && *end))
			return pc_error(PC_EINVAL, "--roi '%s': expected X,Y,W,H (non-negative integers)", arg);
		p = end + 1;
	}
	if (v[2] == 0 || v[3] == 0)
		return pc_error(PC_EINVAL, "--roi '%s': width and height must be positive", arg);
	o->roi_x = (uint32_t)v[0];
	o->roi_y = (uint32_t)v[1];
	o->roi_width = (uint32_t)v[2];
	o->roi_height = (uint32_t)v[3];
	return 0;
}

int cmd_render(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {
		{ "output", required_argument, NULL, 'o' }, { "frames", required_argument, NULL, 'n' },
		{ "first", required_argument, NULL, 'F' },  { "seed", required_argument, NULL, 's' },
		{ "roi", required_argument, NULL, 'R' },    { "no-truth", no_argument, NULL, 'T' },
		{ "threads", required_argument, NULL, 't' }, { "overwrite", no_argument, NULL, 'W' },
		{ "json", no_argument, NULL, 'J' },         { NULL, 0, NULL, 0 }
	};
	const char *out = NULL;
	long frames = -1, threads = 0;
	uint64_t first = 0, seed = 0;
	bool truth = true, overwrite = false, json = false;
	pc_sim_options o = pc_sim_options_default();
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":o:n:s:t:", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			out = optarg;
			break;
		case 'n':
			if ((rc = cli_parse_long("--frames", optarg, 1, 1000000, &frames)))
				return cli_fail(rc, NULL);
			break;
		case 'F':
			if ((rc = cli_parse_u64("--first", optarg, &first)))
				return cli_fail(rc, NULL);
			break;
		case 's':
			if ((rc = cli_parse_u64("--seed", optarg, &seed)))
				return cli_fail(rc, NULL);
			break;
		case 'R':
			if ((rc = parse_roi(optarg, &o)))
				return cli_fail(rc, NULL);
			break;
		case 'T':
			truth = false;
			break;
		case 't':
			if ((rc = cli_parse_long("--threads", optarg, 1, 1024, &threads)))
				return cli_fail(rc, NULL);
			break;
		case 'W':
			overwrite = true;
			break;
		case 'J':
			json = true;
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)", argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
		}
	}
	if (optind < argc - 1)
		return cli_error(CLI_EXIT_USAGE, "one scene at most, got '%s' and '%s'", argv[optind],
				    argv[optind + 1]);
	if (!out)
		return cli_error(CLI_EXIT_USAGE, "-o DIR is required (see --help)");
	const char *scene_path = optind < argc ? argv[optind] : NULL;
	if (scene_path && !strcmp(scene_path, "default"))
		scene_path = NULL;

	double t0 = cli_now();
	pc_scene *scene = NULL;
	rc = scene_path ? pc_scene_load(scene_path, &scene) : pc_scene_load_default(&scene);
	if (rc)
		return cli_fail(rc, NULL);
	o.seed = seed;
	o.threads = (int)threads;
	pc_sim *sim = NULL;
	if ((rc = pc_sim_new(scene, &o, &sim))) {
		pc_scene_free(scene);
		return cli_fail(rc, scene_path ? scene_path : "default scene");
	}
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	if (frames < 0)
		frames = in.n_states;
	const size_t npix = (size_t)in.width * in.height, C = in.colour_channels;
	const bool mueller = truth && (in.effects & PC_FX_MUELLER);
	float *ts = NULL, *tm = NULL;
	pc_recording *rec = NULL;
	pc_view view = { 0 };
	json_t *extra = NULL;
	char errbuf[512] = "";
	int status = CLI_EXIT_OK;
	if ((rc = pc_mkdir_p(out))) {
		status = cli_fail(rc, out);
		goto done;
	}
	/* the recording first: refuse an occupied directory before any work */
	char source[1024];
	snprintf(source, sizeof source, "sim:%s?seed=%llu", scene_path ? scene_path : "default",
		 (unsigned long long)seed);
	pc_recording_desc desc = { source, in.format, NULL, in.width, in.height, in.offset_x,
				   in.offset_y, in.sensor_width, in.sensor_height, true, in.mosaic };
	if ((rc = pc_recording_create(&rec, out, &desc, overwrite))) {
		status = rc == PC_EBUSY ? cli_error(CLI_EXIT_USAGE, "%s: %s (use --overwrite)", out,
						       pc_error_detail())
					: cli_fail(rc, out);
		goto done;
	}
	if (truth) {
		ts = malloc(npix * C * 4 * sizeof *ts);
		tm = mueller ? malloc(npix * C * 16 * sizeof *tm) : NULL;
		if (!ts || (mueller && !tm)) {
			status = cli_error(CLI_EXIT_FAILURE, "out of memory for the ground truth of %ux%u",
					      in.width, in.height);
			goto done;
		}
	}
	/* render: each PSG state the frames use, once (with its truth) */
	double t_prep = cli_now();
	unsigned n_psg_used = (uint64_t)frames < in.n_psg ? (unsigned)frames : in.n_psg;
	cli_progress bar;
	/* rows per prepared state: H, or H + 2 (halo) + H (mixing) with crosstalk */
	const uint64_t prep_rows = (in.effects & PC_FX_CROSSTALK) ? 2 * (uint64_t)in.height + 2 : in.height;
	cli_progress_begin(&bar, "render", (uint64_t)n_psg_used * prep_rows);
	pc_sim_progress_adapter ad = { &bar, 0 };
	for (unsigned k = 0; k < n_psg_used; k++) {
		unsigned g = (unsigned)((first + k) % in.n_psg);
		ad.base = (uint64_t)k * prep_rows;
		if ((rc = pc_sim_prepare(sim, g, ts, k == 0 ? tm : NULL, pc_sim_progress_cb, &ad))) {
			cli_progress_end(&bar);
			status = cli_fail(rc, "render");
			goto done;
		}
		if (truth) {
			char path[4096];
			size_t shape[4] = { in.height, in.width, C == 3 ? 3 : 4, 4 };
			if (in.n_psg > 1)
				snprintf(path, sizeof path, "%s/truth_stokes_psg%02u.npy", out, g);
			else
				snprintf(path, sizeof path, "%s/truth_stokes.npy", out);
			if ((rc = pc_npy_write(path, ts, PC_DT_F32, C == 3 ? 4 : 3, shape))) {
				cli_progress_end(&bar);
				status = cli_fail(rc, path);
				goto done;
			}
			if (k == 0 && tm) {
				snprintf(path, sizeof path, "%s/truth_mueller.npy", out);
				size_t ms[5] = { in.height, in.width, 3, 4, 4 };
				if (C == 1) {
					ms[2] = 4;
					ms[3] = 4;
				}
				if ((rc = pc_npy_write(path, tm, PC_DT_F32, C == 3 ? 5 : 4, ms))) {
					cli_progress_end(&bar);
					status = cli_fail(rc, path);
					goto done;
				}
			}
		}
	}
	free(tm);
	tm = NULL;
	cli_progress_end(&bar);
	t_prep = cli_now() - t_prep;

	if ((rc = pc_view_alloc(&view, in.format, in.width, in.height, 64))) {
		status = cli_fail(rc, "frame buffer");
		goto done;
	}
	double t_frames = 0, t_write = 0;
	cli_progress_begin(&bar, "frames", (uint64_t)frames);
	for (long i = 0; i < frames; i++) {
		pc_frame fr;
		double ta = cli_now();
		rc = pc_sim_frame(sim, first + (uint64_t)i, NULL, &view, &fr.meta);
		double tb = cli_now();
		t_frames += tb - ta;
		if (rc) {
			snprintf(errbuf, sizeof errbuf, "frame %llu: %s",
				 (unsigned long long)(first + (uint64_t)i), pc_error_detail());
			cli_progress_end(&bar);
			status = cli_fail(rc, "frame");
			goto done;
		}
		fr.view = view;
		fr.mosaic = in.mosaic;
		if ((rc = pc_recording_add(rec, &fr))) {
			snprintf(errbuf, sizeof errbuf, "%s", pc_error_detail());
			cli_progress_end(&bar);
			status = cli_fail(rc, out);
			goto done;
		}
		t_write += cli_now() - tb;
		cli_progress_update(&bar, (uint64_t)i + 1);
	}
	cli_progress_end(&bar);
	if (in.n_states > 1) {
		json_t *st = pc_sim_states_json(sim);
		char *txt = json_dumps(st, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
		json_decref(st);
		char path[4096];
		snprintf(path, sizeof path, "%s/states.json", out);
		rc = txt ? pc_write_file_atomic(path, txt, strlen(txt)) : PC_ENOMEM;
		free(txt);
		if (rc) {
			status = cli_fail(rc, path);
			goto done;
		}
	}
	extra = pc_sim_describe(sim, scene);
	json_t *tj = json_object();
	json_object_set_new(tj, "render_s", json_real(t_prep));
	json_object_set_new(tj, "frames_s", json_real(t_frames));
	json_object_set_new(tj, "per_frame_s", json_real(t_frames / (double)frames));
	json_object_set_new(tj, "write_s", json_real(t_write));
	json_object_set_new(tj, "total_s", json_real(cli_now() - t0));
	json_object_set_new(tj, "peak_rss_mib", cli_json_real(pc_peak_rss_mib()));
	json_object_set_new(extra, "timings", tj);
	json_object_set_new(extra, "first_frame", json_integer((json_int_t)first));
	char *et = json_dumps(extra, JSON_COMPACT | JSON_REAL_PRECISION(17));
	rc = et ? pc_recording_set_json(rec, "extra", et) : PC_ENOMEM;
	free(et);
	if (rc) {
		status = cli_fail(rc, "meta.json");
		goto done;
	}
	if ((rc = pc_recording_finish(rec, NULL))) {
		status = cli_fail(rc, out);
		goto done;
	}
	if (json) {
		json_t *sum = json_object();
		json_object_set_new(sum, "output", json_string(out));
		json_object_set_new(sum, "frames", json_integer(frames));
		json_object_set_new(sum, "width", json_integer(in.width));
		json_object_set_new(sum, "height", json_integer(in.height));
		json_object_set(sum, "timings", tj);
		cli_print_json(sum);
	}
done:
	if (rec) {
		if (status != CLI_EXIT_OK)
			pc_recording_finish(rec, *errbuf ? errbuf : "render failed");
		pc_recording_free(rec);
	}
	json_decref(extra);
	pc_view_free(&view);
	free(ts);
	free(tm);
	pc_sim_free(sim);
	pc_scene_free(scene);
	return status;
}
