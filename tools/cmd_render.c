/* polarcam render: a scene → raw mosaic frames (a recording) + ground truth
 * (polarcam/render_recording.h). */
#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/render_recording.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam render [SCENE] -o DIR [options]\n"
	    "\n"
	    "Renders SCENE (a scene file, docs/scene-format.md; the built-in default scene when\n"
	    "omitted or \"default\") through the sensor model into DIR:\n"
	    "  raw_NNNNNN.png      raw mosaic frames at the sensor's bit depth (16-bit PNG + sBIT\n"
	    "                      above 8 bits), numbered by frame: frame N is reproducible "
	    "alone\n"
	    "  truth_stokes.npy    float32 (H, W, 4): S0..S3 radiance in W/(m^2 sr) in the image-\n"
	    "                      plane frame (S1 > 0 along image x, AoLP counter-clockwise from "
	    "x\n"
	    "                      as the image is viewed); (H, W, 3, 4) for colour sensors; S3 "
	    "is\n"
	    "                      NaN unless the scene declares the \"circular\" effect. With a\n"
	    "                      PSG sequence: truth_stokes_psgNN.npy per generator state\n"
	    "  truth_mueller.npy   float32 (H, W, 4, 4) when the scene declares \"mueller\"\n"
	    "  states.json         the polarization-state sequence, for polarcam mueller --states\n"
	    "  meta.json           frames, format and mosaic (the recording), plus scene, sensor,\n"
	    "                      seed, effects, timings and peak memory under \"extra\"\n"
	    "\n"
	    "options:\n"
	    "  -o, --output DIR    output folder, made beside DIR and renamed into place when\n"
	    "                      complete (refused when it exists, unless --overwrite)\n"
	    "  -n, --frames N      number of frames (default 1, or one cycle of the scene's "
	    "states)\n"
	    "      --first N       number of the first frame (default 0)\n"
	    "  -s, --seed S        noise seed (default 0)\n"
	    "      --roi X,Y,W,H   render only this region of the sensor (bit-identical to a "
	    "crop)\n"
	    "      --no-truth      do not write truth_*.npy\n"
	    "  -t, --threads N     threads (default: all cores)\n"
	    "      --overwrite     replace DIR as a whole when it exists\n"
	    "      --store S       frame files: png (default), npy or raw (headerless, geometry\n"
	    "                      in meta.json); all read by file:DIR sources\n"
	    "      --json          print a summary as one JSON line on stdout\n"
	    "  -h, --help          this help\n"
	    "\n"
	    "Progress goes to stderr when it is a terminal (POLARCAM_PROGRESS=1 forces it).\n"
	    "Files and fields: docs/outputs.md.\n"
	    "SIGINT/SIGTERM stop after the frame in hand (or the scene's render): the frames "
	    "written\n"
	    "are put in place, meta.json says complete=false, \"interrupted after N of M "
	    "frames\",\n"
	    "with timings.\n"
	    "Exit status: 0 success, 1 failure or interrupted, 2 bad arguments or scene, or DIR\n"
	    "exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam render -o out/\n"
	    "  polarcam render scenes/mesh.json -o out/ --frames 10 --seed 3 --roi "
	    "100,101,512,384\n"
	    "  polarcam render scenes/mueller_tetrahedral.json -o seq/ --overwrite --json\n");
}

static int parse_roi(const char *arg, pc_sim_options *o)
{
	unsigned long v[4];
	const char *p = arg;
	for (int i = 0; i < 4; i++) {
		char *end;
		errno = 0;
		if (*p == '-' || *p == '+')
			return pc_error(
			    PC_EINVAL, "--roi '%s': expected X,Y,W,H (non-negative integers)", arg);
		v[i] = strtoul(p, &end, 10);
		if (end == p || errno || v[i] > 65535 || (i < 3 && *end != ',') || (i == 3 && *end))
			return pc_error(
			    PC_EINVAL, "--roi '%s': expected X,Y,W,H (non-negative integers)", arg);
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

/* the recording and its report */
static int run(const char *out, pc_render_opts *ro, bool json)
{
	cli_catch_signals();
	cli_progress bar = {0};
	ro->progress = (pc_progress){cli_progress_stoppable, &bar};
	pc_render_report rep;
	int rc = pc_render_recording(out, ro, &rep);
	cli_progress_end(&bar);
	if (rc == PC_ECANCELED)
		return cli_error(CLI_EXIT_FAILURE,
		                 "%s (the %llu frames written are intact in %s; meta.json says "
		                 "complete=false)",
		                 pc_error_detail(), (unsigned long long)rep.frames, out);
	if (rc)
		return cli_fail(rc, NULL);
	if (json) {
		json_t *sum = json_object();
		json_object_set_new(sum, "output", json_string(out));
		json_object_set_new(sum, "frames", json_integer((json_int_t)rep.frames));
		json_object_set_new(sum, "width", json_integer(rep.width));
		json_object_set_new(sum, "height", json_integer(rep.height));
		json_object_set_new(sum, "timings", json_loads(rep.timings, 0, NULL));
		cli_print_json(sum);
	} else {
		cli_info("wrote %llu frames (%ux%u) to %s", (unsigned long long)rep.frames,
		         rep.width, rep.height, out);
	}
	free(rep.timings);
	return CLI_EXIT_OK;
}

int cli_cmd_render(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
	                                     {"frames", required_argument, NULL, 'n'},
	                                     {"first", required_argument, NULL, 'F'},
	                                     {"seed", required_argument, NULL, 's'},
	                                     {"roi", required_argument, NULL, 'R'},
	                                     {"no-truth", no_argument, NULL, 'T'},
	                                     {"threads", required_argument, NULL, 't'},
	                                     {"overwrite", no_argument, NULL, 'W'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {"store", required_argument, NULL, 'S'},
	                                     {NULL, 0, NULL, 0}};
	const char *out = NULL;
	long frames = -1, threads = 0;
	uint64_t first = 0, seed = 0;
	bool truth = true, overwrite = false, json = false;
	pc_recording_store store = PC_STORE_PNG;
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
			if ((rc = cli_parse_u64_range("--first", optarg, 0, INT64_MAX, &first)))
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
		case 'S':
			if ((rc = pc_recording_store_from_name(optarg, &store)))
				return cli_fail(rc, "--store");
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
			                 argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)",
			                 argv[optind - 1]);
		}
	}
	if (optind < argc - 1)
		return cli_error(CLI_EXIT_USAGE, "one scene at most, got '%s' and '%s'",
		                 argv[optind], argv[optind + 1]);
	if (!out)
		return cli_error(CLI_EXIT_USAGE, "-o DIR is required (see --help)");
	const char *scene_path = optind < argc ? argv[optind] : NULL;
	if (scene_path && !strcmp(scene_path, "default"))
		scene_path = NULL;
	if (cli_parse_only())
		return CLI_EXIT_OK;
	o.seed = seed;
	o.threads = (int)threads;
	pc_render_opts ro = {scene_path, NULL,  o,         frames > 0 ? (uint64_t)frames : 0,
	                     first,      truth, overwrite, {NULL, NULL},
	                     store};
	return run(out, &ro, json);
}
