/* polarcam process: raw mosaics -> Stokes, DoLP, AoLP and pictures (polarcam/process.h; a
 * recording: polarcam/process_recording.h). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/process.h"
#include "polarcam/process_recording.h"
#include "raw_cli.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam process RAW -o DIR [options]\n"
	    "       polarcam process RAW... | RECORDING_DIR -o DIR [--stack] [options]\n"
	    "       (options among them: --method NAME --layout L --black-level DN\n"
	    "        --saturation DN|none --calibration FILE)\n"
	    "\n"
	    "Runs the pipeline (demosaicking, Stokes, DoLP, AoLP) on raw mosaics and writes into\n"
	    "DIR (docs/outputs.md):\n"
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
	    "With --minmax (polanalyser's Imin/Imax; S0 = Imin + Imax, the total intensity):\n"
	    "  imin.npy, imax.npy        float32 (H, W): (S0 -+ sqrt(S1^2+S2^2))/2, and pictures\n"
	    "With --split (unpolarized diffuse + fully polarized specular light):\n"
	    "  diffuse.npy, specular.npy float32 (H, W): 2 Imin and Imax - Imin, and pictures\n"
	    "  (opt-in: 8 bytes a pixel more each, 40 MB a 5 MP frame; not clipped, so noise\n"
	    "  makes Imin < 0 in dark pixels)\n"
	    "Several RAW files, or a recording folder (render, capture: its frames in order), "
	    "give\n"
	    "one set per frame, stokes_NNNNNN.npy, dolp_NNNNNN.npy, aolp_NNNNNN.npy and, when a\n"
	    "level is checked, valid_NNNNNN.npy (NNNNNN: the recording's frame number, else the\n"
	    "position in the list), or with --stack one array per quantity: stokes.npy (N, H, W,\n"
	    "3), dolp.npy, aolp.npy (N, H, W) and valid.npy (N, H, W); pictures of the first "
	    "frame\n"
	    "(s0_000000.png, ...) unless --pictures-every says otherwise. A recording's black\n"
	    "level (meta.json) is used as for one of its frames.\n"
	    "Colour-polarization layouts: stokes.npy and the pictures above are of the colour\n"
	    "average of each analyser image; also stokes_rgb.npy (H, W, 3, 3): S0..S2 of R, G, B\n"
	    "(not with --stack), s0_rgb.png and dolp_rgb.png (R, G, B of one picture). DIR is\n"
	    "written as a whole: made beside DIR and renamed into place once every file is "
	    "written;\n"
	    "an existing DIR is refused unless --overwrite, which replaces it as a whole.\n"
	    "\n"
	    "  -o, --output DIR    output folder\n"
	    "  --overwrite         replace DIR when it exists\n"
	    "  --stack             several frames: one (N, ...) array per quantity\n"
	    "  --minmax            also imin.npy, imax.npy (+ pictures on the S0 scale)\n"
	    "  --split             also diffuse.npy, specular.npy (+ pictures on the S0 scale)\n"
	    "  --pictures-every K  several frames: pictures of frames 0, K, 2K, ... (default: the\n"
	    "                      first frame only)\n"
	    "  --no-pictures       no PNG pictures\n"
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
	    "  --dolp-max V|auto   DoLP range of dolp.png (and the DoLP at full colour in the "
	    "AoLP\n"
	    "                      pictures): 0..V (0 < V <= 1; default 1), or auto: 0 to the\n"
	    "                      unmasked pixels' 99th percentile, rounded up to 0.05. The "
	    "range\n"
	    "                      is printed on the key.\n"
	    "  --json              print meta.json's content as one JSON line on stdout\n"
	    "%s"
	    "  -h, --help          this help\n"
	    "\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or bad input, or DIR exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam process rec/raw_000000.png -o out/ --minmax --split\n"
	    "  polarcam process rec/ -o frames/ --stack --method ratio --json\n"
	    "  polarcam process raw.bin --width 2448 --height 2048 --format Mono12p -o out/ "
	    "--overwrite\n",
	    cli_raw_help);
}

/* process's own options (the rest are the shared raw options) */
typedef struct proc_args {
	long pic_width, pictures_every;
	double mask_s0, dolp_hi;
	bool stack, pictures, overwrite, json, minmax, split;
} proc_args;

/* Takes process's options out of argv into a, the others into args. */
static int parse_own(int argc, char **argv, proc_args *a, char **args, int *nargs)
{
	*nargs = 0;
	for (int i = 0; i < argc; i++) {
		const char *o = argv[i];
		int rc = 0;
		if (!strcmp(o, "--picture-width") || !strcmp(o, "--mask-s0") ||
		    !strcmp(o, "--pictures-every") || !strcmp(o, "--dolp-max")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 o);
			const char *v = argv[++i];
			if (!strcmp(o, "--picture-width"))
				rc = cli_parse_long(o, v, 0, 30000, &a->pic_width);
			else if (!strcmp(o, "--pictures-every"))
				rc = cli_parse_long(o, v, 1, 999999, &a->pictures_every);
			else
				rc = cli_parse_picture_opt(o, v, &a->mask_s0, &a->dolp_hi);
			if (rc)
				return cli_fail(rc, NULL);
		} else if (!strcmp(o, "--stack")) {
			a->stack = true;
		} else if (!strcmp(o, "--minmax")) {
			a->minmax = true;
		} else if (!strcmp(o, "--split")) {
			a->split = true;
		} else if (!strcmp(o, "--no-pictures")) {
			a->pictures = false;
		} else if (!strcmp(o, "--overwrite")) {
			a->overwrite = true;
		} else if (!strcmp(o, "--json")) {
			a->json = true;
		} else {
			args[(*nargs)++] = argv[i];
		}
	}
	return 0;
}

/* the library call for what was given: one file, several, or a recording folder */
static int run_with(const cli_raw *o, const proc_args *a, pc_process_opts po, char **meta)
{
	pc_stokes_folder_opts fo = {
	    .files = PC_SF_STOKES | PC_SF_DOLP | PC_SF_AOLP | (a->pictures ? PC_SF_PICTURES : 0) |
	             (a->minmax ? PC_SF_MINMAX : 0) | (a->split ? PC_SF_SPLIT : 0),
	    .pictures = {
	        .max_width = (uint32_t)a->pic_width, .mask_s0 = a->mask_s0, .dolp_hi = a->dolp_hi}};
	struct stat sb;
	bool folder = o->npaths == 1 && stat(o->path, &sb) == 0 && S_ISDIR(sb.st_mode);
	if (o->npaths == 1 && !folder && !a->stack) {
		pc_raw_input in = cli_raw_input(o);
		return pc_process_file(&in, &po, o->out, &fo, meta);
	}
	cli_progress bar = {0};
	pc_process_batch b = {NULL,
	                      0,
	                      NULL,
	                      a->stack,
	                      a->pictures_every ? (uint64_t)a->pictures_every : UINT64_MAX,
	                      {cli_progress_stoppable, &bar}};
	cli_catch_signals();
	int rc;
	if (folder) {
		rc = pc_process_recording(o->path, &b, &po, o->out, &fo, meta);
	} else {
		pc_raw_input *in = calloc(o->npaths, sizeof *in);
		if (!in)
			return pc_error(PC_ENOMEM, "inputs");
		for (size_t k = 0; k < o->npaths; k++) {
			in[k] = cli_raw_input(o);
			in[k].path = o->paths[k];
		}
		b.inputs = in;
		b.count = o->npaths;
		rc = pc_process_files(&b, &po, o->out, &fo, meta);
		free(in);
	}
	cli_progress_end(&bar);
	return rc;
}

/* run_with the calibration, when one is given, as the stage */
static int run(const cli_raw *o, const proc_args *a, char **meta, int *status)
{
	pc_process_opts po = cli_raw_process(o);
	po.overwrite = a->overwrite;
	pc_calib cal;
	pc_raw_stage stage;
	if ((*status = cli_raw_calibration(o, &cal, &stage, &po)))
		return 0;
	int rc = run_with(o, a, po, meta);
	pc_calib_free(&cal);
	return rc;
}

int cli_cmd_process(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	proc_args a = {1224, 0, 0, 0, false, true, false, false, false, false};
	char **args = calloc((size_t)argc + 1, sizeof *args);
	int nargs = 0;
	if (!args)
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	cli_raw o;
	memset(&o, 0, sizeof o);
	int st = parse_own(argc, argv, &a, args, &nargs);
	if (!st)
		st = cli_raw_parse(nargs, args, &o, NULL, true);
	free(args);
	if (st) {
		cli_raw_free(&o);
		return st;
	}
	if (!o.path) {
		usage(stderr);
		st = cli_error(CLI_EXIT_USAGE, "no RAW file given");
	} else if (!o.out) {
		st = cli_error(CLI_EXIT_USAGE, "no output folder given (-o DIR)");
	} else if (o.npaths > 1 && o.have_geometry == false) {
		struct stat sb;
		for (size_t k = 0; k < o.npaths && !st; k++)
			if (stat(o.paths[k], &sb) == 0 && S_ISDIR(sb.st_mode))
				st = cli_error(CLI_EXIT_USAGE,
				               "%s: a recording folder is processed "
				               "alone, not with other inputs",
				               o.paths[k]);
	}
	if (st || cli_parse_only()) {
		cli_raw_free(&o);
		return st;
	}
	char *meta = NULL;
	int rc = run(&o, &a, &meta, &st);
	if (st) {
		cli_raw_free(&o);
		return st;
	}
	if (rc) {
		cli_raw_free(&o);
		return cli_fail(rc, NULL);
	}
	if (a.json) {
		json_t *j = json_loads(meta, 0, NULL);
		json_object_set_new(j, "output", json_string(o.out));
		json_object_set_new(j, "black_level_from", json_string(o.black_from));
		cli_print_json(j);
	} else {
		cli_info("wrote %s", o.out);
	}
	free(meta);
	cli_raw_free(&o);
	return CLI_EXIT_OK;
}
