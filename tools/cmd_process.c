/* polarcam process: raw mosaic -> Stokes, DoLP, AoLP and pictures (polarcam/process.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/process.h"
#include "raw_cli.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam process RAW -o DIR [--method NAME] [--layout L] [--black-level DN]\n"
	    "                        [--saturation DN|none] [--calibration FILE]\n"
	    "\n"
	    "Runs the pipeline (demosaicking, Stokes, DoLP, AoLP) on a raw mosaic and writes into\n"
	    "DIR (created if missing):\n"
	    "  stokes.npy     float32 (H, W, 3): S0, S1, S2 in the raw's units\n"
	    "                 S0 = (I0+I45+I90+I135)/2, S1 = I0 - I90, S2 = I45 - I135\n"
	    "  dolp.npy       float32 (H, W): sqrt(S1^2+S2^2)/S0 clipped to [0, 1] (0 where S0 <= "
	    "0)\n"
	    "  valid.npy      uint8 (H, W): 0 where the value depends on a saturated or dead\n"
	    "                 sample (or one the calibration distrusts), else 1; their count is\n"
	    "                 invalid_pixels in meta.json, and the pictures mark them\n"
	    "  aolp.npy       float32 (H, W): 0.5 atan2(S2, S1) in radians, in [0, pi), from the\n"
	    "                 image x axis, counter-clockwise as seen by the viewer\n"
	    "  s0.png, dolp.png          grey pictures with colour bars\n"
	    "  aolp.png, aolp_sat.png    AoLP as hue, DoLP as value / saturation, with 2-D keys\n"
	    "  meta.json      input, layout, bit depth, method, levels, invalid_pixels, timings\n"
	    "Colour-polarization layouts use the colour average of each analyser image. Every "
	    "file\n"
	    "is written atomically, and only after the whole computation succeeded.\n"
	    "\n"
	    "  -o, --output DIR    output directory\n"
	    "  --picture-width N   downscale the PNG pictures to at most N pixels wide for "
	    "display\n"
	    "                      (default 1224; 0 = full resolution, slower to write)\n"
	    "  --mask-s0 T         low-signal mask: in dolp.png, aolp.png and aolp_sat.png, "
	    "pixels\n"
	    "                      with S0 < T (raw units; e.g. a few noise sigmas) are a dark "
	    "grey\n"
	    "                      hatch, stated in the title and legend. Default: 1%% of the S0\n"
	    "                      99.9th percentile; 0 = no mask. The .npy files are never "
	    "masked.\n"
	    "%s"
	    "  -h, --help          this help\n"
	    "\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or bad input.\n",
	    cli_raw_help);
}

int cli_cmd_process(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	/* --picture-width is process's own; the rest are the shared raw options */
	long pic_width = 1224;
	double mask_s0 = 0; /* 0: the library default */
	int mask_given = 0;
	char **args = calloc((size_t)argc + 1, sizeof *args);
	int nargs = 0;
	if (!args)
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	for (int i = 0; i < argc; i++) {
		if (!strcmp(argv[i], "--picture-width")) {
			int rc = i + 1 < argc
			             ? cli_parse_long("--picture-width", argv[i + 1], 0, 30000,
			                              &pic_width)
			             : pc_error(PC_EINVAL, "--picture-width needs a value");
			if (rc) {
				free(args);
				return cli_fail(rc, NULL);
			}
			i++;
			continue;
		}
		if (!strcmp(argv[i], "--mask-s0")) {
			int rc = i + 1 < argc ? cli_parse_double("--mask-s0", argv[i + 1], &mask_s0)
			                      : pc_error(PC_EINVAL, "--mask-s0 needs a value");
			if (!rc && !(mask_s0 >= 0))
				rc = pc_error(PC_ERANGE,
				              "--mask-s0 %s: expected a threshold >= 0 "
				              "(0: no mask)",
				              argv[i + 1]);
			if (rc) {
				free(args);
				return cli_fail(rc, NULL);
			}
			mask_given = 1;
			i++;
			continue;
		}
		args[nargs++] = argv[i];
	}
	cli_raw o;
	int st = cli_raw_parse(nargs, args, &o, NULL);
	free(args);
	if (st)
		return st;
	if (!o.path) {
		usage(stderr);
		return cli_error(CLI_EXIT_USAGE, "no RAW file given");
	}
	if (!o.out)
		return cli_error(CLI_EXIT_USAGE, "no output directory given (-o DIR)");
	pc_raw_input in = cli_raw_input(&o);
	pc_process_opts po = cli_raw_process(&o);
	pc_calib cal;
	pc_raw_stage stage;
	if ((st = cli_raw_calibration(&o, &cal, &stage, &po)))
		return st;
	pc_stokes_folder_opts fo = {PC_SF_STOKES | PC_SF_DOLP | PC_SF_AOLP | PC_SF_PICTURES,
	                            {NULL, (uint32_t)pic_width,
	                             !mask_given   ? 0
	                             : mask_s0 > 0 ? mask_s0
	                                           : -1}};
	char *meta = NULL;
	int rc = pc_process_file(&in, &po, o.out, &fo, &meta);
	pc_calib_free(&cal);
	if (rc)
		return cli_fail(rc, NULL);
	json_t *j = json_loads(meta, 0, NULL);
	free(meta);
	json_object_set_new(j, "output", json_string(o.out));
	json_object_set_new(j, "black_level_from", json_string(o.black_from));
	cli_print_json(j);
	return CLI_EXIT_OK;
}
