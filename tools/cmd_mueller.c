/* polarcam mueller: raw frames under known PSG/PSA states → per-pixel Mueller matrices
 * (core/mueller_imaging) → Lu–Chipman D, R, Δ maps (core/decompose) as .npy and pictures. */
#include <dirent.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/decompose.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/parallel.h"
#include "polarcam/recording.h"
#include "sim_cli.h"

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam mueller FRAMES... --states FILE -o DIR [options]\n"
		"       polarcam mueller RECORDING_DIR -o DIR [options]\n"
		"\n"
		"Per-pixel Mueller matrices from raw mosaic frames taken under known polarization\n"
		"states (physics.md section 7): frame j was taken with generator state j mod n_psg and\n"
		"analyser state j / n_psg, as listed in FILE (states.json, written by polarcam render\n"
		"for scenes with state sequences). Least squares M = A+ I G+ per pixel, then Lu-Chipman\n"
		"diattenuation D, retardance R (radians) and depolarization Delta.\n"
		"\n"
		"FRAMES are raw mosaics (PNG, TIFF, .npy) in sequence order, or one recording directory\n"
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
		"  -o, --output DIR    output directory\n"
		"  --method NAME       demosaicking method (default bilinear; 'superpixel' halves the\n"
		"                      resolution and is the fastest; polarcam demosaic --list)\n"
		"  --black-level DN    subtracted from every raw value (default: the recording's sensor\n"
		"                      offset, else 0)\n"
		"  --layout L          mosaic layout (default: the states file's, else 90,45,135,0)\n"
		"  --no-mueller        do not write mueller.npy (it is 64 bytes per pixel)\n"
		"  --rebuild-circular convention|+|-|off\n"
		"                      linear-only (3x3) systems: rebuild the circular entries for\n"
		"                      the pBRDF family (one specular Jones matrix + a depolariser on\n"
		"                      M00, physics.md sections 2 and 7) so that D, R and Delta exist.\n"
		"                      M03 = M30 = 0 and M33 follow from the 3x3; M13, M23, M31, M32\n"
		"                      up to the sign of s = Im(r_s r_p*). 'convention' (default):\n"
		"                      s <= 0, what every material n - ik with k >= 0 gives under\n"
		"                      polarcam's conventions; '+'/'-' force a sign; 'off' leaves them\n"
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
		"Exit status: 0 success, 1 failure, 2 bad arguments or input.\n");
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* Raw frame files of a recording directory, sorted; also its black level when meta.json has
 * the simulator's sensor description. */
static int list_recording(const char *dir, char ***files, size_t *n, double *black)
{
	pc_recording *r = NULL;
	int rc = pc_recording_open(&r, dir);
	if (rc)
		return rc;
	size_t cnt = pc_recording_count(r);
	char **f = calloc(cnt ? cnt : 1, sizeof *f);
	if (!f) {
		pc_recording_free(r);
		return pc_error(PC_ENOMEM, "%s", dir);
	}
	for (size_t i = 0; i < cnt; i++) {
		char p[4096];
		if ((rc = pc_path_join(p, sizeof p, dir, pc_recording_get_frame(r, i)->file)) ||
		    !(f[i] = strdup(p))) {
			for (size_t k = 0; k < i; k++)
				free(f[k]);
			free(f);
			pc_recording_free(r);
			return rc ? rc : pc_error(PC_ENOMEM, "%s", dir);
		}
	}
	pc_recording_free(r);
	qsort(f, cnt, sizeof *f, cmp_str);
	*files = f;
	*n = cnt;
	/* black level from meta.json "extra.sensor.offset_dn" (polarcam render) */
	char mp[4096];
	if (!pc_path_join(mp, sizeof mp, dir, "meta.json")) {
		json_t *m = json_load_file(mp, 0, NULL);
		json_t *off = json_object_get(json_object_get(json_object_get(m, "extra"), "sensor"),
					      "offset_dn");
		if (json_is_number(off))
			*black = json_number_value(off);
		json_decref(m);
	}
	return 0;
}

typedef struct lc_counts {
	long singular, nonphysical, bad;
} lc_counts;

struct file_src {
	char **files;
};

static int file_get(void *user, size_t j, pc_view *out)
{
	struct file_src *f = user;
	return pc_image_read_mosaic(f->files[j], NULL, 0, out, NULL);
}

int cmd_mueller(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option opts[] = {
		{ "states", required_argument, NULL, 'S' },    { "output", required_argument, NULL, 'o' },
		{ "method", required_argument, NULL, 'm' },    { "black-level", required_argument, NULL, 'B' },
		{ "layout", required_argument, NULL, 'L' },    { "no-mueller", no_argument, NULL, 'N' },
		{ "threads", required_argument, NULL, 't' },   { "json", no_argument, NULL, 'J' },
		{ "rebuild-circular", required_argument, NULL, 'C' },
		{ "rebuild-tol", required_argument, NULL, 'T' },
		{ NULL, 0, NULL, 0 }
	};
	const char *states_path = NULL, *out = NULL, *method_name = "bilinear", *layout_arg = NULL;
	double black = NAN;
	long threads = 0;
	bool write_m = true, json = false;
	pc_rebuild_opts rb = { PC_REBUILD_CONVENTION, 0.05 };
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
				return cli_error(CLI_EXIT_USAGE, "--black-level %g: must be ≥ 0", black);
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
		case 'C':
			if ((rc = pc_rebuild_sign_from_name(optarg, &rb.sign)))
				return cli_fail(rc, "--rebuild-circular");
			break;
		case 'T':
			if ((rc = cli_parse_double("--rebuild-tol", optarg, &rb.tol)))
				return cli_fail(rc, NULL);
			if (!(rb.tol >= 0) || !isfinite(rb.tol))
				return cli_error(CLI_EXIT_USAGE, "--rebuild-tol %g: must be finite and ≥ 0",
						    rb.tol);
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)", argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", argv[optind - 1]);
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

	/* the frames */
	char **files = NULL;
	size_t nfiles = 0;
	char states_buf[4096];
	struct stat sb;
	bool is_dir = argc - optind == 1 && stat(argv[optind], &sb) == 0 && S_ISDIR(sb.st_mode);
	double rec_black = 0;
	if (is_dir) {
		if ((rc = list_recording(argv[optind], &files, &nfiles, &rec_black)))
			return cli_fail(rc, argv[optind]);
		if (!states_path) {
			if ((rc = pc_path_join(states_buf, sizeof states_buf, argv[optind], "states.json")))
				return cli_fail(rc, NULL);
			states_path = states_buf;
		}
	} else {
		nfiles = (size_t)(argc - optind);
		files = calloc(nfiles, sizeof *files);
		if (!files)
			return cli_error(CLI_EXIT_FAILURE, "out of memory");
		for (size_t i = 0; i < nfiles; i++)
			files[i] = strdup(argv[optind + (int)i]);
	}
	if (isnan(black))
		black = rec_black;
	int status = CLI_EXIT_OK;
	float *M = NULL, *maps = NULL, *residual = NULL;
	if (!states_path) {
		status = cli_error(CLI_EXIT_USAGE, "--states FILE is required with frame files");
		goto done;
	}
	pc_sim_states st;
	char layout[64] = "";
	if ((rc = pc_states_read(states_path, &st, layout, sizeof layout))) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	size_t nframes = (size_t)st.n_psg * st.n_psa;
	if (nfiles < nframes) {
		status = cli_error(CLI_EXIT_USAGE, "%s describes %zu frames (%u PSG x %u PSA states) "
						     "but %zu frame%s given", states_path, nframes, st.n_psg,
				      st.n_psa, nfiles, nfiles == 1 ? " was" : "s were");
		goto done;
	}
	if (nfiles > nframes)
		cli_warn("%zu frames given, using the first %zu (one cycle of the states)", nfiles,
			    nframes);
	pc_mosaic mosaic = pc_mosaic_imx250mzr();
	const char *lay = layout_arg ? layout_arg : *layout ? layout : NULL;
	if (lay && (rc = pc_mosaic_parse(lay, &mosaic))) {
		status = cli_fail(rc, "layout");
		goto done;
	}
	if (mosaic.period != 2) {
		status = cli_error(CLI_EXIT_USAGE, "colour-polarization mosaics are not supported by "
						     "polarcam mueller yet (layout %s)", lay);
		goto done;
	}
	struct file_src fs = { files };
	cli_progress bar;
	cli_progress_begin(&bar, "mueller", nframes);
	pc_mueller_result res;
	rc = pc_mueller_run(file_get, &fs, &st, &mosaic, method, black, (int)threads, &rb, &bar,
			    &res);
	cli_progress_end(&bar);
	if (rc) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	pc_mueller_system sys = res.sys;
	uint32_t ow = res.width, oh = res.height;
	size_t np = (size_t)ow * oh;
	M = res.M;
	maps = res.maps;
	residual = res.residual;
	lc_counts lc = { res.singular, res.nonphysical, res.bad };
	if ((rc = pc_mkdir_p(out))) {
		status = cli_fail(rc, out);
		goto done;
	}
	char path[4096];
	if (write_m) {
		size_t shape[4] = { oh, ow, 4, 4 };
		if ((rc = pc_path_join(path, sizeof path, out, "mueller.npy")) ||
		    (rc = pc_npy_write(path, M, PC_DT_F32, 4, shape))) {
			status = cli_fail(rc, NULL);
			goto done;
		}
	}
	if ((rc = pc_write_map(out, "D", maps, ow, oh, 0, 1, "Diattenuation D (Lu-Chipman)", "D")) ||
	    (rc = pc_write_map(out, "R", maps + np, ow, oh, 0, M_PI, "Retardance R (Lu-Chipman)",
			       "R (rad)")) ||
	    (rc = pc_write_map(out, "Delta", maps + 2 * np, ow, oh, 0, 1,
			       "Depolarization Delta (Lu-Chipman)", "Delta"))) {
		status = cli_fail(rc, out);
		goto done;
	}
	if (residual &&
	    (rc = pc_write_map(out, "rebuild_residual", residual, ow, oh, 0, 2 * rb.tol,
			       "Residual of the 3x3 fit / M00 (pBRDF family)", "residual"))) {
		status = cli_fail(rc, out);
		goto done;
	}
	json_t *js = json_object();
	json_object_set_new(js, "frames", json_integer((json_int_t)nframes));
	json_object_set_new(js, "width", json_integer(ow));
	json_object_set_new(js, "height", json_integer(oh));
	json_object_set_new(js, "method", json_string(pc_demosaic_method_get(method)->name));
	json_object_set_new(js, "black_level", json_real(black));
	json_object_set_new(js, "cond_A", cli_json_real(sys.cond_A));
	json_object_set_new(js, "cond_G", cli_json_real(sys.cond_G));
	json_object_set_new(js, "cond_W", cli_json_real(sys.cond_W));
	json_object_set_new(js, "rank_A", json_integer(sys.rank_A));
	json_object_set_new(js, "rank_G", json_integer(sys.rank_G));
	json_object_set_new(js, "noise_gain", cli_json_matrix4(sys.noise_gain));
	json_object_set_new(js, "pixels_D_singular", json_integer(lc.singular));
	json_object_set_new(js, "pixels_nonphysical_filtered", json_integer(lc.nonphysical));
	json_object_set_new(js, "pixels_undecomposable", json_integer(lc.bad));
	json_object_set_new(js, "determined", json_integer(sys.determined));
	json_object_set_new(js, "rebuild_circular",
			    json_string(res.rebuilt ? pc_rebuild_sign_name(rb.sign) : "off"));
	if (res.rebuilt) {
		json_object_set_new(js, "rebuild_tol", json_real(rb.tol));
		json_object_set_new(js, "pixels_rebuild_rejected", json_integer(res.rb_rejected));
		json_object_set_new(js, "pixels_rebuild_sign_undefined",
				    json_integer(res.rb_sign_undefined));
	}
	char *txt = json_dumps(js, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	if (!txt || (rc = pc_path_join(path, sizeof path, out, "mueller.json")) ||
	    (rc = pc_write_file_atomic(path, txt, strlen(txt)))) {
		free(txt);
		json_decref(js);
		status = cli_fail(rc ? rc : PC_ENOMEM, "mueller.json");
		goto done;
	}
	free(txt);
	if ((sys.rank_A < 4 || sys.rank_G < 4) && !res.rebuilt)
		cli_warn("rank-%u analyser / rank-%u generator: only the 3x3 linear block is "
			    "determined; D/R/Delta maps are NaN (--rebuild-circular)", sys.rank_A,
			    sys.rank_G);
	else if (res.rebuilt)
		cli_warn("rank-%u analyser / rank-%u generator: circular entries rebuilt for the "
			    "pBRDF family (sign: %s); %ld of %zu pixels rejected (residual or "
			    "realisability above --rebuild-tol %g)", sys.rank_A, sys.rank_G,
			    pc_rebuild_sign_name(rb.sign), res.rb_rejected, np, rb.tol);
	if (json)
		cli_print_json(js);
	else
		json_decref(js);
done:
	for (size_t i = 0; i < nfiles; i++)
		free(files[i]);
	free(files);
	free(M);
	free(maps);
	free(residual);
	return status;
}
