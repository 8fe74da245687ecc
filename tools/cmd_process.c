/* polarcam process: raw mosaic -> Stokes, DoLP, AoLP and pictures. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/stokes.h"
#include "raw_cli.h"

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam process RAW -o DIR [--method NAME] [--layout L]\n"
		"\n"
		"Runs the pipeline (demosaicking, Stokes, DoLP, AoLP) on a raw mosaic and writes into\n"
		"DIR (created if missing):\n"
		"  stokes.npy     float32 (H, W, 3): S0, S1, S2 in the raw's units\n"
		"                 S0 = (I0+I45+I90+I135)/2, S1 = I0 - I90, S2 = I45 - I135\n"
		"  dolp.npy       float32 (H, W): sqrt(S1^2+S2^2)/S0 clipped to [0, 1] (0 where S0 <= 0)\n"
		"  aolp.npy       float32 (H, W): 0.5 atan2(S2, S1) in radians, in [0, pi), from the\n"
		"                 image x axis, counter-clockwise as seen by the viewer\n"
		"  s0.png, dolp.png          grey pictures with colour bars\n"
		"  aolp.png, aolp_sat.png    AoLP as hue, DoLP as value / saturation, with 2-D keys\n"
		"  meta.json      input, layout, bit depth, method, timings\n"
		"Colour-polarization layouts use the colour average of each analyser image. Every file\n"
		"is written atomically, and only after the whole computation succeeded.\n"
		"\n"
		"  -o, --output DIR    output directory\n"
		"  --picture-width N   downscale the PNG pictures to at most N pixels wide for display\n"
		"                      (default 1224; 0 = full resolution, slower to write)\n"
		"  --mask-s0 T         low-signal mask: in dolp.png, aolp.png and aolp_sat.png, pixels\n"
		"                      with S0 < T (raw units; e.g. a few noise sigmas) are a dark grey\n"
		"                      hatch, stated in the title and legend. Default: 1%% of the S0\n"
		"                      99.9th percentile; 0 = no mask. The .npy files are never masked.\n"
		"%s"
		"  -h, --help          this help\n"
		"\n"
		"Exit status: 0 success, 1 failure, 2 bad arguments or bad input.\n",
		cli_raw_help);
}

static int write_in(const char *dir, const char *name, const float *data, unsigned ndim,
		    const size_t *shape)
{
	char path[4096];
	if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, name) >= sizeof path)
		return pc_error(PC_EINVAL, "%s: path too long", dir);
	return pc_npy_write(path, data, PC_DT_F32, ndim, shape);
}

int cmd_process(int argc, char **argv)
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
			int rc = i + 1 < argc ? cli_parse_long("--picture-width", argv[i + 1], 0,
								  30000, &pic_width)
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
				rc = pc_error(PC_ERANGE, "--mask-s0 %s: expected a threshold >= 0 "
							 "(0: no mask)", argv[i + 1]);
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
	pc_view raw;
	unsigned bits;
	if ((st = cli_raw_read(&o, &raw, &bits)))
		return st;
	uint32_t w, h;
	pc_demosaic_out_size(o.dm, raw.width, raw.height, &w, &h);
	size_t n = (size_t)w * h;
	float *stokes = malloc(sizeof(float) * n * 3), *dolp = malloc(sizeof(float) * n),
	      *aolp = malloc(sizeof(float) * n);
	if (!stokes || !dolp || !aolp) {
		free(stokes);
		free(dolp);
		free(aolp);
		pc_view_free(&raw);
		return cli_error(CLI_EXIT_FAILURE, "out of memory for %ux%u Stokes images", w, h);
	}
	pc_stokes_out so = { { stokes, (size_t)w * 3, 3 }, { stokes + 1, (size_t)w * 3, 3 },
			     { stokes + 2, (size_t)w * 3, 3 }, { dolp, w, 1 }, { aolp, w, 1 } };
	pc_demosaic_opts opts = { o.threads, o.reference, 0 };
	double t0 = cli_now();
	int rc = pc_stokes_from_raw(&raw, &o.mosaic, o.dm, &opts, &so);
	double t_pipe = cli_now() - t0;
	uint32_t rw = raw.width, rh = raw.height;
	pc_view_free(&raw);
	if (rc) {
		st = cli_fail(rc, o.path);
		goto out;
	}
	if ((rc = pc_mkdir_p(o.out))) {
		st = cli_fail(rc, NULL);
		goto out;
	}
	size_t s3[3] = { h, w, 3 }, s2[2] = { h, w };
	if ((rc = write_in(o.out, "stokes.npy", stokes, 3, s3)) ||
	    (rc = write_in(o.out, "dolp.npy", dolp, 2, s2)) ||
	    (rc = write_in(o.out, "aolp.npy", aolp, 2, s2)) ||
	    (rc = pc_pictures_write_opts(o.out, &so, w, h,
					 &(pc_pictures_opts){ NULL, (uint32_t)pic_width,
							      !mask_given ? 0
							      : mask_s0 > 0 ? mask_s0
									    : -1 }))) {
		st = cli_fail(rc, NULL);
		goto out;
	}
	char layout[64], path[4096];
	pc_mosaic_format(&o.mosaic, layout, sizeof layout);
	json_t *j = json_object();
	json_object_set_new(j, "input", json_string(o.path));
	json_object_set_new(j, "width", json_integer(rw));
	json_object_set_new(j, "height", json_integer(rh));
	json_object_set_new(j, "bits", json_integer(bits));
	json_object_set_new(j, "layout", json_string(layout));
	json_object_set_new(j, "method", json_string(pc_demosaic_method_get(o.dm)->name));
	json_object_set_new(j, "reference", json_boolean(o.reference));
	json_object_set_new(j, "pipeline_seconds", cli_json_real(t_pipe));
	json_object_set_new(j, "aolp_convention",
			    json_string("radians in [0, pi), from the image x axis, "
					"counter-clockwise as seen by the viewer"));
	json_t *files = json_array();
	const char *names[] = { "stokes.npy", "dolp.npy", "aolp.npy", "s0.png",
				"dolp.png",   "aolp.png", "aolp_sat.png" };
	for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
		json_array_append_new(files, json_string(names[k]));
	json_object_set_new(j, "files", files);
	char *txt = json_dumps(j, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	snprintf(path, sizeof path, "%s/meta.json", o.out);
	rc = txt ? pc_write_file_atomic(path, txt, strlen(txt)) : pc_error(PC_ENOMEM, "meta.json");
	free(txt);
	if (rc) {
		json_decref(j);
		st = cli_fail(rc, NULL);
		goto out;
	}
	json_object_set_new(j, "output", json_string(o.out));
	cli_print_json(j);
	st = CLI_EXIT_OK;
out:
	free(stokes);
	free(dolp);
	free(aolp);
	return st;
}
