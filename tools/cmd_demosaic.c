/* polarcam demosaic: raw polarizer mosaic -> analyser images (H, W, 4) float32. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/process.h"
#include "raw_cli.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam demosaic --list [--json]\n"
	    "       polarcam demosaic RAW --method NAME [--layout L] -o OUT.npy|OUT.tif [--json]\n"
	    "\n"
	    "Demosaics a raw polarizer mosaic into full-resolution analyser images. OUT is\n"
	    "float32 of shape (H, W, 4) with channels I0, I45, I90, I135 (angles from the image\n"
	    "x axis, counter-clockwise as seen by the viewer), in the raw's units (a 12-bit raw\n"
	    "gives 0..4095). Colour-polarization layouts give (H, W, 12): R0 R45 R90 R135 G0 ...\n"
	    "B135. superpixel-half gives (H/2, W/2, ...). Values are above the black level. When\n"
	    "saturated (default) or dead samples are checked, OUT_valid.npy (uint8 (H, W): 0 "
	    "where\n"
	    "a value depends on one) goes beside OUT and the JSON gives invalid_pixels. .npy is\n"
	    "NumPy format; .tif/.tiff is a float32 TIFF with one sample per channel. Outputs are\n"
	    "written atomically, OUT and OUT_valid.npy as a set (both in place or neither); on\n"
	    "any error nothing is written; an existing OUT or OUT_valid.npy is refused unless\n"
	    "--overwrite.\n"
	    "\n"
	    "  --list              the methods, one line each on accuracy and cost\n"
	    "  -o, --output OUT    the output file (.npy, .tif or .tiff)\n"
	    "  --overwrite         replace OUT when it exists\n"
	    "  --json              print one JSON line (output, shape, method, layout, bits,\n"
	    "                      seconds) on stdout; with --list, the methods as JSON\n"
	    "%s"
	    "  -h, --help          this help\n"
	    "\n"
	    "JSON fields: output, shape, method, layout, bits, seconds, black_level,\n"
	    "saturation_level, calibration, valid, invalid_pixels, noise_gain and\n"
	    "noise_gain_from (\"option\", \"calibration\" or \"estimated\"; null for methods\n"
	    "without one).\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or bad input (odd size, truncated\n"
	    "file, values above the bit depth, NaN, bad layout) or OUT exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam demosaic --list\n"
	    "  polarcam demosaic rec/raw_000000.png --method eari -o i.npy\n"
	    "  polarcam demosaic raw.bin --width 2448 --height 2048 --format PolarizeMono12p "
	    "--layout 90,45,135,0 -o i.tif --json\n",
	    cli_raw_help);
}

static int list_methods(int json)
{
	json_t *arr = json ? json_array() : NULL;
	for (int k = 0; k < PC_DM_COUNT; k++) {
		const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
		const char *kind = (mi->flags & PC_DMF_MONO) && (mi->flags & PC_DMF_COLOR)
		                       ? "mono+colour"
		                   : (mi->flags & PC_DMF_COLOR) ? "colour"
		                                                : "mono";
		if (json) {
			json_t *o = json_object();
			json_object_set_new(o, "name", json_string(mi->name));
			json_object_set_new(o, "mosaics", json_string(kind));
			json_object_set_new(o, "accuracy", json_string(mi->accuracy));
			json_object_set_new(o, "cost", json_string(mi->cost));
			json_object_set_new(o, "source", json_string(mi->source));
			json_object_set_new(o, "half_resolution",
			                    json_boolean(mi->flags & PC_DMF_HALF_RES));
			json_object_set_new(o, "reference_only",
			                    json_boolean(mi->flags & PC_DMF_REFERENCE_ONLY));
			json_object_set_new(o, "noise_gain",
			                    json_boolean(mi->flags & PC_DMF_NOISE_GAIN));
			json_array_append_new(arr, o);
		} else {
			printf("%-16s [%s]\n    accuracy: %s\n    cost:     %s\n    after:    %s\n",
			       mi->name, kind, mi->accuracy, mi->cost, mi->source);
		}
	}
	if (json)
		cli_print_json(arr);
	else
		printf(
		    "(accuracy: gains over bilinear in S0/DoLP PSNR, dB, under the frozen "
		    "protocol:\n"
		    " mean over each dataset's scenes and, in brackets, its worst scene; "
		    "datasets:\n"
		    " Lapray NIR (7 scenes), Zhang (2), and the stress suite scenes/stress (8,\n"
		    " rendered, polarcam eval --stress); times: polarcam bench demosaic, "
		    "2448x2048\n"
		    " 12-bit frames; run it for this machine's figures. Noise: the stress\n"
		    " scenes through the IMX250MZR preset at three exposures\n"
		    " (scenes/stress/gen_noisy.py, docs/demosaicking.md \"Noise\"): at the\n"
		    " high and mid ones no method but superpixel and bicubic loses to bilinear;\n"
		    " in low light (brightest tenth ~1 %% of full scale) ratio, ratio-ri,\n"
		    " eari-robust, ppid and the anchors lose S0 on text (-0.9 to -4.0 dB):\n"
		    " they need denoising there; ratio-nr, eari and ri hold. Held-out: the 12\n"
		    " scenes of scenes/heldout, written before any method ran on them and never\n"
		    " used for tuning (6 ideal, 6 noisy; docs/demosaicking.md \"Held-out\n"
		    " check\"). Through a lens: the stress scenes with the simulator's\n"
		    " point-spread function, a Gaussian of 0.7 px (scenes/stress/optics; real\n"
		    " cameras blur, the other sets are pixel-sharp, docs/demosaicking.md\n"
		    " Round 39).)\n");
	return CLI_EXIT_OK;
}

int cli_cmd_demosaic(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	for (int i = 1; i < argc; i++)
		if (!strcmp(argv[i], "--list")) {
			int json = 0;
			for (int k = 1; k < argc; k++)
				if (!strcmp(argv[k], "--json"))
					json = 1;
				else if (strcmp(argv[k], "--list"))
					return cli_error(CLI_EXIT_USAGE,
					                 "--list takes only --json");
			return list_methods(json);
		}
	bool overwrite = false, json = false;
	char **args = calloc((size_t)argc + 1, sizeof *args);
	int nargs = 0;
	if (!args)
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	for (int i = 0; i < argc; i++) {
		if (!strcmp(argv[i], "--overwrite"))
			overwrite = true;
		else if (!strcmp(argv[i], "--json"))
			json = true;
		else
			args[nargs++] = argv[i];
	}
	cli_raw o;
	int st = cli_raw_parse(nargs, args, &o, NULL, false);
	free(args);
	if (st)
		return st;
	if (!o.path) {
		usage(stderr);
		return cli_error(CLI_EXIT_USAGE, "no RAW file given");
	}
	if (!o.out)
		return cli_error(CLI_EXIT_USAGE, "no output given (-o OUT.npy or OUT.tif)");
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_raw_input in = cli_raw_input(&o);
	pc_process_opts po = cli_raw_process(&o);
	po.overwrite = overwrite;
	pc_calib cal;
	pc_raw_stage stage;
	if ((st = cli_raw_calibration(&o, &cal, &stage, &po)))
		return st;
	pc_demosaic_file_report rep;
	int rc = pc_demosaic_file(&in, &po, o.out, &rep);
	pc_calib_free(&cal);
	if (rc)
		return cli_fail(rc, NULL);
	if (!json) {
		cli_info("wrote %s (%ux%ux%u float32, %s)", o.out, rep.height, rep.width,
		         rep.channels, pc_demosaic_method_get(o.dm)->name);
		return CLI_EXIT_OK;
	}
	char layout[64];
	pc_mosaic_format(&o.mosaic, layout, sizeof layout);
	json_t *j = json_object();
	json_object_set_new(j, "output", json_string(o.out));
	json_object_set_new(j, "shape",
	                    json_pack("[I, I, I]", (json_int_t)rep.height, (json_int_t)rep.width,
	                              (json_int_t)rep.channels));
	json_object_set_new(j, "method", json_string(pc_demosaic_method_get(o.dm)->name));
	json_object_set_new(j, "layout", json_string(layout));
	json_object_set_new(j, "bits", json_integer(rep.bits));
	json_object_set_new(j, "seconds", cli_json_real(rep.seconds));
	json_object_set_new(j, "black_level", cli_json_real(po.black_level));
	json_object_set_new(j, "black_level_from", json_string(o.black_from));
	json_object_set_new(j, "saturation_level",
	                    rep.saturation_level > 0 ? cli_json_real(rep.saturation_level)
	                                             : json_null());
	json_object_set_new(j, "calibration",
	                    o.calibration ? json_string(o.calibration) : json_null());
	json_object_set_new(j, "valid",
	                    *rep.valid_path ? json_string(rep.valid_path) : json_null());
	json_object_set_new(j, "invalid_pixels",
	                    *rep.valid_path ? json_integer((json_int_t)rep.n_invalid)
	                                    : json_null());
	const bool ng = pc_demosaic_method_get(o.dm)->flags & PC_DMF_NOISE_GAIN;
	json_object_set_new(j, "noise_gain", ng ? cli_json_real(rep.noise_gain) : json_null());
	json_object_set_new(j, "noise_gain_from",
	                    !ng                    ? json_null()
	                    : po.noise_gain > 0    ? json_string("option")
	                    : rep.noise_gain_given ? json_string("calibration")
	                                           : json_string("estimated"));
	cli_print_json(j);
	return CLI_EXIT_OK;
}
