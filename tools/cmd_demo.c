/* polarcam demo: the main job (polarcam/demo.h). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/demo.h"
#include "polarcam/demosaic.h"
#include "polarcam/sim.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam demo [-o DIR] [options]\n"
	    "\n"
	    "The main job, on the built-in default scene (the seed paper's black and green paints "
	    "on\n"
	    "spheres and a ground plane, IMX250MZR-class sensor, 2448x2048):\n"
	    "  1. renders the ground truth and one raw frame through the sensor model;\n"
	    "  2. runs the raw frame through the pipeline (demosaicking -> Stokes -> DoLP/AoLP) "
	    "with\n"
	    "     several methods, timing each, and scores them against the truth;\n"
	    "  3. renders a Mueller-imaging sequence of the same scene (tetrahedral generator x\n"
	    "     quarter-wave analyser, 8 frames, at 612x512 with the same field of view),\n"
	    "     reconstructs per-pixel Mueller matrices and compares the Lu-Chipman D, R, Delta\n"
	    "     maps with the truth;\n"
	    "  4. writes pictures, .npy arrays and report.md / report.json into DIR.\n"
	    "\n"
	    "options:\n"
	    "  -o, --output DIR    output folder (default polarcam-demo), made beside DIR and\n"
	    "                      renamed into place when complete\n"
	    "  --overwrite         replace DIR as a whole when it exists\n"
	    "  --scene FILE        another scene instead of the default\n"
	    "  -s, --seed S        noise seed (default 1)\n"
	    "  --methods LIST      demosaicking methods to compare (default\n"
	    "                      superpixel,bilinear,bicubic,ppid,eari,ratio)\n"
	    "  --no-mueller        skip step 3\n"
	    "  -t, --threads N     threads\n"
	    "  --json              print report.json's content as one line on stdout (report.md\n"
	    "                      goes to stderr, as without --json)\n"
	    "\n"
	    "Files and their fields: docs/outputs.md; how to read the pictures: docs/pictures.md.\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or DIR exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam demo -o polarcam-demo\n"
	    "  polarcam demo -o demo2 --methods bilinear,ratio --no-mueller --seed 7\n"
	    "  polarcam demo --scene scenes/mesh.json -o mesh-demo --overwrite --json\n");
}

/* the job and its report */
static int run(pc_demo_opts *o, const char *out, bool json)
{
	cli_progress bar = {0};
	o->progress = (pc_progress){cli_progress_fn, &bar};
	pc_demo *demo = NULL;
	int rc = pc_demo_new(o, &demo);
	if (rc)
		return cli_fail(rc, NULL);
	pc_demo_info in;
	pc_demo_get_info(demo, &in);
	char fx[512] = "";
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (in.effects & (1u << i))
			snprintf(fx + strlen(fx), sizeof fx - strlen(fx), " %s",
			         pc_sim_effect_name(1u << i));
	cli_info("%s, %ux%u, effects:%s", in.scene_name, in.width, in.height, fx);
	char *md = NULL;
	rc = pc_demo_run(demo, out, &md);
	cli_progress_end(&bar);
	pc_demo_free(demo);
	if (md && !rc && !cli_quiet)
		fputs(md, stderr);
	free(md);
	if (rc)
		return cli_fail(rc, NULL);
	if (json) {
		char path[4096];
		snprintf(path, sizeof path, "%s/report.json", out);
		json_t *j = json_load_file(path, 0, NULL);
		if (!j)
			return cli_error(CLI_EXIT_FAILURE, "%s: cannot read it back", path);
		json_object_set_new(j, "output", json_string(out));
		cli_print_json(j);
	}
	return CLI_EXIT_OK;
}

int cli_cmd_demo(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
	                                     {"scene", required_argument, NULL, 'S'},
	                                     {"seed", required_argument, NULL, 's'},
	                                     {"methods", required_argument, NULL, 'M'},
	                                     {"no-mueller", no_argument, NULL, 'N'},
	                                     {"threads", required_argument, NULL, 't'},
	                                     {"overwrite", no_argument, NULL, 'W'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {NULL, 0, NULL, 0}};
	const char *out = "polarcam-demo", *scene_path = NULL;
	const char *methods_arg = "superpixel,bilinear,bicubic,ppid,eari,ratio";
	uint64_t seed = 1;
	long threads = 0;
	bool do_mueller = true, overwrite = false, json = false;
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
		case 'W':
			overwrite = true;
			break;
		case 'J':
			json = true;
			break;
		case 't':
			if ((rc = cli_parse_long("--threads", optarg, 1, 1024, &threads)))
				return cli_fail(rc, NULL);
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
			                 argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)",
			                 argv[optind - 1]);
		}
	}
	if (optind < argc)
		return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (see --help)",
		                 argv[optind]);
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
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_demo_opts o = {.scene_path = scene_path,
	                  .seed = seed,
	                  .methods = methods,
	                  .n_methods = nm,
	                  .mueller = do_mueller,
	                  .overwrite = overwrite,
	                  .threads = (int)threads};
	return run(&o, out, json);
}
