/* polarcam demosaic: raw polarizer mosaic -> analyser images (H, W, 4) float32. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/demosaic.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "raw_cli.h"

static void usage(FILE *fp)
{
	fprintf(fp,
		"usage: polarcam demosaic --list [--json]\n"
		"       polarcam demosaic RAW --method NAME [--layout L] -o OUT.npy|OUT.tif\n"
		"\n"
		"Demosaics a raw polarizer mosaic into full-resolution analyser images. OUT is\n"
		"float32 of shape (H, W, 4) with channels I0, I45, I90, I135 (angles from the image\n"
		"x axis, counter-clockwise as seen by the viewer), in the raw's units (a 12-bit raw\n"
		"gives 0..4095). Colour-polarization layouts give (H, W, 12): R0 R45 R90 R135 G0 ...\n"
		"B135. superpixel-half gives (H/2, W/2, ...). .npy is NumPy format; .tif/.tiff is a\n"
		"float32 TIFF with one sample per channel. Outputs are written atomically; on any\n"
		"error nothing is written.\n"
		"\n"
		"  --list              the methods, one line each on accuracy and cost\n"
		"  -o, --output OUT    the output file (.npy, .tif or .tiff)\n"
		"%s"
		"  -h, --help          this help\n"
		"\n"
		"Prints one JSON line (output, shape, method, layout, bits, seconds). Exit status: 0\n"
		"success, 1 failure, 2 bad arguments or bad input (odd size, truncated file, values\n"
		"above the bit depth, NaN, bad layout).\n",
		pc_raw_cli_help);
}

static int list_methods(int json)
{
	json_t *arr = json ? json_array() : NULL;
	for (int k = 0; k < PC_DM_COUNT; k++) {
		const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)k);
		const char *kind = (mi->flags & PC_DMF_MONO) && (mi->flags & PC_DMF_COLOR) ? "mono+colour"
				   : (mi->flags & PC_DMF_COLOR)			     ? "colour"
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
			json_array_append_new(arr, o);
		} else {
			printf("%-16s [%s]\n    accuracy: %s\n    cost:     %s\n    after:    %s\n",
			       mi->name, kind, mi->accuracy, mi->cost, mi->source);
		}
	}
	if (json)
		pc_cli_print_json(arr);
	else
		printf("(accuracy: gains over bilinear in S0/DoLP PSNR, dB, under the frozen protocol:\n"
		       " mean over each dataset's scenes and, in brackets, its worst scene; datasets:\n"
		       " Lapray NIR (7 scenes), Zhang (2), and the stress suite scenes/stress (8,\n"
		       " rendered, polarcam eval --stress); times: polarcam bench demosaic, 2448x2048\n"
		       " 12-bit frames; run it for this machine's figures. No method here needs\n"
		       " denoising to beat bilinear on the noisy stress scenes.)\n");
	return PC_EXIT_OK;
}

static int has_suffix(const char *s, const char *suf)
{
	size_t n = strlen(s), m = strlen(suf);
	return n >= m && !strcmp(s + n - m, suf);
}

int cmd_demosaic(int argc, char **argv)
{
	if (pc_cli_wants_help(argc, argv)) {
		usage(stdout);
		return PC_EXIT_OK;
	}
	for (int i = 1; i < argc; i++)
		if (!strcmp(argv[i], "--list")) {
			int json = 0;
			for (int k = 1; k < argc; k++)
				if (!strcmp(argv[k], "--json"))
					json = 1;
				else if (strcmp(argv[k], "--list"))
					return pc_cli_error(PC_EXIT_USAGE, "--list takes only --json");
			return list_methods(json);
		}
	pc_raw_cli o;
	int st = pc_raw_cli_parse(argc, argv, &o, NULL);
	if (st)
		return st;
	if (!o.path) {
		usage(stderr);
		return pc_cli_error(PC_EXIT_USAGE, "no RAW file given");
	}
	if (!o.out)
		return pc_cli_error(PC_EXIT_USAGE, "no output given (-o OUT.npy or OUT.tif)");
	int tiff = has_suffix(o.out, ".tif") || has_suffix(o.out, ".tiff") ||
		   has_suffix(o.out, ".TIF") || has_suffix(o.out, ".TIFF");
	if (!tiff && !has_suffix(o.out, ".npy") && !has_suffix(o.out, ".NPY"))
		return pc_cli_error(PC_EXIT_USAGE, "-o %s: the output is .npy or .tif/.tiff (float32)",
				    o.out);
	pc_view raw;
	unsigned bits;
	if ((st = pc_raw_cli_read(&o, &raw, &bits)))
		return st;
	uint32_t ow, oh;
	pc_demosaic_out_size(o.dm, raw.width, raw.height, &ow, &oh);
	unsigned nch = pc_demosaic_channels(&o.mosaic);
	float *buf = malloc(sizeof(float) * ow * oh * nch);
	if (!buf) {
		pc_view_free(&raw);
		return pc_cli_error(PC_EXIT_FAILURE, "out of memory for %ux%ux%u floats", oh, ow, nch);
	}
	pc_fplane planes[PC_DEMOSAIC_MAX_CHANNELS];
	pc_fplanes_interleaved(buf, ow, nch, planes);
	pc_demosaic_opts opts = { o.threads, o.reference, 0 };
	double t0 = pc_cli_now();
	int rc = pc_demosaic(&raw, &o.mosaic, o.dm, &opts, planes);
	double secs = pc_cli_now() - t0;
	pc_view_free(&raw);
	if (rc) {
		free(buf);
		return pc_cli_fail(rc, o.path);
	}
	size_t shape[3] = { oh, ow, nch };
	rc = tiff ? pc_tiff_write_array(o.out, buf, PC_DT_F32, oh, ow, nch)
		  : pc_npy_write(o.out, buf, PC_DT_F32, 3, shape);
	free(buf);
	if (rc)
		return pc_cli_fail(rc, NULL);
	char layout[64];
	pc_mosaic_format(&o.mosaic, layout, sizeof layout);
	json_t *j = json_object();
	json_object_set_new(j, "output", json_string(o.out));
	json_t *js = json_array();
	for (int k = 0; k < 3; k++)
		json_array_append_new(js, json_integer((json_int_t)shape[k]));
	json_object_set_new(j, "shape", js);
	json_object_set_new(j, "method", json_string(pc_demosaic_method_get(o.dm)->name));
	json_object_set_new(j, "layout", json_string(layout));
	json_object_set_new(j, "bits", json_integer(bits));
	json_object_set_new(j, "seconds", pc_json_real(secs));
	pc_cli_print_json(j);
	return PC_EXIT_OK;
}
