/* polarcam mueller: raw frames under known PSG/PSA states → per-pixel Mueller matrices
 * (core/mueller_imaging) → Lu–Chipman D, R, Δ maps (core/decompose) as .npy and pictures. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/folders.h"
#include "polarcam/mueller_frames.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam mueller FRAMES... --states FILE -o DIR [options]\n"
	    "       polarcam mueller RECORDING_DIR -o DIR [options]\n"
	    "\n"
	    "Per-pixel Mueller matrices from raw mosaic frames taken under known polarization\n"
	    "states (physics.md section 7): frame j was taken with generator state j mod n_psg "
	    "and\n"
	    "analyser state j / n_psg, as listed in FILE (states.json, written by polarcam render\n"
	    "for scenes with state sequences). Least squares M = A+ I G+ per pixel, then "
	    "Lu-Chipman\n"
	    "diattenuation D, retardance R (radians) and depolarization Delta.\n"
	    "\n"
	    "FRAMES are raw mosaics (PNG, TIFF, .npy) in sequence order, or one recording "
	    "directory\n"
	    "(polarcam render/capture output: its frames, its states.json and its black level).\n"
	    "\n"
	    "Writes into DIR: mueller.npy (H, W, 4, 4) float32 in the raw's units (undetermined\n"
	    "elements NaN; for linear-only systems the rebuilt circular entries, see below);\n"
	    "D.npy, R.npy, Delta.npy (H, W) float32 (NaN where undefined: D near 1, a pixel the\n"
	    "rebuild rejects, or a rank-3 system with --rebuild-circular off); D.png, R.png,\n"
	    "Delta.png; rebuild_residual.npy/.png (linear-only systems); mueller.json (condition\n"
	    "numbers of A, G and W = A (x) G, the noise gain per element, counts of flagged\n"
	    "pixels).\n"
	    "\n"
	    "options:\n"
	    "  --states FILE       the states file (default: RECORDING_DIR/states.json)\n"
	    "  -o, --output DIR    output folder, made beside DIR and renamed into place when\n"
	    "                      complete (refused when it exists, unless --overwrite)\n"
	    "  --overwrite         replace DIR as a whole when it exists\n"
	    "  --method NAME       demosaicking method (default bilinear; 'superpixel' halves the\n"
	    "                      resolution and is the fastest; polarcam demosaic --list)\n"
	    "  --black-level DN    subtracted from every raw value (default: the recording's "
	    "sensor\n"
	    "                      offset, else 0)\n"
	    "  --saturation DN|none  a pixel whose demosaicking support holds a sample >= DN in\n"
	    "                      any frame is invalid: valid.npy (uint8), pixels_invalid in\n"
	    "                      mueller.json, a pink checker in the pictures; its values are\n"
	    "                      computed as for any pixel. Default: the frames' full scale\n"
	    "                      (2^bits - 1); 'none': not checked\n"
	    "  --dead-level DN     likewise for samples <= DN (default: not checked)\n"
	    "  --layout L          mosaic layout (default: the states file's, else 90,45,135,0)\n"
	    "  --no-mueller        do not write mueller.npy (it is 64 bytes per pixel)\n"
	    "  --rebuild-circular convention|+|-|off\n"
	    "                      linear-only (3x3) systems: rebuild the circular entries for\n"
	    "                      the pBRDF family (one specular Jones matrix + a depolariser on\n"
	    "                      M00, physics.md sections 2 and 7) so that D, R and Delta "
	    "exist.\n"
	    "                      M03 = M30 = 0 and M33 follow from the 3x3; M13, M23, M31, M32\n"
	    "                      up to the sign of s = Im(r_s r_p*). 'convention' (default):\n"
	    "                      s <= 0, what every material n - ik with k >= 0 gives under\n"
	    "                      polarcam's conventions; '+'/'-' force a sign; 'off' leaves "
	    "them\n"
	    "                      NaN with NaN maps. D, R and Delta do not depend on the sign;\n"
	    "                      the sign shows in mueller.npy and the retardance axis only.\n"
	    "                      Pixels whose 3x3 is not of the family (residual above\n"
	    "                      --rebuild-tol) get NaN there and in the maps; see\n"
	    "                      rebuild_residual.npy and docs/physics-notes.md\n"
	    "  --rebuild-tol X     largest accepted residual ||N - N_fit|| / M00 of the 3x3 fit\n"
	    "                      (also bounds how far from realisable it may be). Default 0.05:\n"
	    "                      7x the median, 2.5x the 99th percentile of the residual that\n"
	    "                      the IMX250MZR preset's noise gives on scenes/linear_psg.json\n"
	    "                      (docs/status/sim.md); lower it for cleaner data\n"
	    "  -t, --threads N     threads\n"
	    "  --json              print mueller.json's content as one line on stdout\n"
	    "Files and fields: docs/outputs.md.\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or input, or DIR exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam mueller seq/ -o mueller/\n"
	    "  polarcam mueller f0.png f1.png f2.png f3.png --states states.json -o m/ "
	    "--no-mueller\n"
	    "  polarcam mueller seq/ -o m/ --method superpixel --rebuild-circular off --json\n");
}

/* frames → Mueller image → folder, and the report */
static int run(int nargs, char **args, const char *states_path, const char *layout, const char *out,
               const pc_mueller_run_opts *ro, bool write_m, bool overwrite, bool json)
{
	struct stat sb;
	if (nargs == 1 && stat(args[0], &sb) != 0)
		return cli_error(CLI_EXIT_USAGE, "%s: no such file or recording folder", args[0]);
	/* an occupied output is refused before the work */
	int rc = pc_output_check(out, overwrite ? PC_OUT_OVERWRITE : 0, true);
	if (rc)
		return cli_fail(rc, NULL);
	bool is_dir = nargs == 1 && S_ISDIR(sb.st_mode);
	cli_progress bar = {0};
	pc_mueller_request rq = {states_path, layout, *ro, {cli_progress_fn, &bar}};
	pc_mueller_result res;
	pc_mueller_used used;
	rc = is_dir ? pc_mueller_from_recording(args[0], &rq, &res, &used)
	            : pc_mueller_from_files((const char *const *)args, (size_t)nargs, &rq, &res,
	                                    &used);
	cli_progress_end(&bar);
	if (rc)
		return cli_fail(rc, NULL);
	if (used.frames_given > used.frames_used)
		cli_warn("%zu frames given, using the first %zu (one cycle of the states)",
		         used.frames_given, used.frames_used);
	pc_mueller_folder_opts fo = {!write_m,         pc_demosaic_method_get(ro->method)->name,
	                             used.black_level, ro->rebuild.tol,
	                             ro->rebuild.sign, overwrite};
	char *text = NULL;
	rc = pc_mueller_folder_write(out, &res, &fo, &text);
	const pc_mueller_system *sys = &res.sys;
	if (!rc && (sys->rank_A < 4 || sys->rank_G < 4) && !res.rebuilt)
		cli_warn("rank-%u analyser / rank-%u generator: only the 3x3 linear block is "
		         "determined; D/R/Delta maps are NaN (--rebuild-circular)",
		         sys->rank_A, sys->rank_G);
	else if (!rc && res.rebuilt)
		cli_warn("rank-%u analyser / rank-%u generator: circular entries rebuilt for the "
		         "pBRDF family (sign: %s); %ld of %zu pixels rejected (residual or "
		         "realisability above --rebuild-tol %g)",
		         sys->rank_A, sys->rank_G, pc_rebuild_sign_name(ro->rebuild.sign),
		         res.rb_rejected, (size_t)res.width * res.height, ro->rebuild.tol);
	pc_mueller_result_free(&res);
	if (rc) {
		free(text);
		return cli_fail(rc, NULL);
	}
	if (json)
		cli_print_json(json_loads(text, 0, NULL));
	else
		cli_info("wrote %s", out);
	free(text);
	return CLI_EXIT_OK;
}

int cli_cmd_mueller(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {{"states", required_argument, NULL, 'S'},
	                                     {"output", required_argument, NULL, 'o'},
	                                     {"method", required_argument, NULL, 'm'},
	                                     {"black-level", required_argument, NULL, 'B'},
	                                     {"layout", required_argument, NULL, 'L'},
	                                     {"no-mueller", no_argument, NULL, 'N'},
	                                     {"threads", required_argument, NULL, 't'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {"rebuild-circular", required_argument, NULL, 'C'},
	                                     {"rebuild-tol", required_argument, NULL, 'T'},
	                                     {"overwrite", no_argument, NULL, 'W'},
	                                     {"saturation", required_argument, NULL, 'X'},
	                                     {"dead-level", required_argument, NULL, 'D'},
	                                     {NULL, 0, NULL, 0}};
	const char *states_path = NULL, *out = NULL, *method_name = "bilinear", *layout_arg = NULL;
	double black = NAN, sat = 0, dead = 0;
	long threads = 0;
	bool write_m = true, json = false, overwrite = false;
	pc_rebuild_opts rb = {PC_REBUILD_CONVENTION, 0.05};
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":o:t:", opts, NULL)) != -1) {
		switch (c) {
		case 'S':
			states_path = optarg;
			break;
		case 'o':
			out = optarg;
			break;
		case 'm':
			method_name = optarg;
			break;
		case 'B':
			if ((rc = cli_parse_double("--black-level", optarg, &black)))
				return cli_fail(rc, NULL);
			if (black < 0)
				return cli_error(CLI_EXIT_USAGE, "--black-level %g: must be ≥ 0",
				                 black);
			break;
		case 'X':
		case 'D':
			if (c == 'X' && !strcmp(optarg, "none")) {
				sat = -1;
				break;
			}
			if ((rc = cli_parse_double(c == 'X' ? "--saturation" : "--dead-level",
			                           optarg, c == 'X' ? &sat : &dead)))
				return cli_fail(rc, NULL);
			if (!((c == 'X' ? sat : dead) > 0))
				return cli_error(CLI_EXIT_USAGE, "%s %s: expected a level > 0 DN",
				                 c == 'X' ? "--saturation" : "--dead-level",
				                 optarg);
			break;
		case 'L':
			layout_arg = optarg;
			break;
		case 'N':
			write_m = false;
			break;
		case 't':
			if ((rc = cli_parse_long("--threads", optarg, 1, 1024, &threads)))
				return cli_fail(rc, NULL);
			break;
		case 'J':
			json = true;
			break;
		case 'W':
			overwrite = true;
			break;
		case 'C':
			if ((rc = pc_rebuild_sign_from_name(optarg, &rb.sign)))
				return cli_fail(rc, "--rebuild-circular");
			break;
		case 'T':
			if ((rc = cli_parse_double("--rebuild-tol", optarg, &rb.tol)))
				return cli_fail(rc, NULL);
			if (!(rb.tol >= 0) || !isfinite(rb.tol))
				return cli_error(CLI_EXIT_USAGE,
				                 "--rebuild-tol %g: must be finite and ≥ 0",
				                 rb.tol);
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
			                 argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)",
			                 argv[optind - 1]);
		}
	}
	if (!out)
		return cli_error(CLI_EXIT_USAGE, "-o DIR is required (see --help)");
	if (optind >= argc)
		return cli_error(CLI_EXIT_USAGE, "no frames given (see --help)");
	pc_demosaic_method method;
	if ((rc = pc_demosaic_method_from_name(method_name, &method)))
		return cli_fail(rc, "--method");
	if (!strcmp(method_name, "superpixel"))
		method = PC_DM_SUPERPIXEL_HALF;
	if (cli_parse_only())
		return CLI_EXIT_OK;
	return run(argc - optind, argv + optind, states_path, layout_arg, out,
	           &(pc_mueller_run_opts){method, black, (int)threads, rb, sat, dead}, write_m,
	           overwrite, json);
}
