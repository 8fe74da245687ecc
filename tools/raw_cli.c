#include "raw_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "polarcam/error.h"
#include "polarcam/process.h"
#include "polarcam/recording.h"

const char cli_raw_help[] =
    "input:\n"
    "  RAW                 the raw mosaic: .png (8/16-bit grey; sBIT gives the bit depth),\n"
    "                      .tif/.tiff (8/16-bit or float32), .npy (2-D u1, <u2, <f4, <f8),\n"
    "                      .bmp (8-bit grey), or a headerless file with --width/--height/\n"
    "                      --format\n"
    "  --width W --height H --format NAME [--offset BYTES] [--stride BYTES]\n"
    "                      geometry of a headerless raw file; NAME is a pixel format (Mono8,\n"
    "                      Mono10/12/14/16, Mono10p/12p/14p, Mono10Packed, Mono12Packed,\n"
    "                      Y10P, Y12P, Y14P, Y10BPACK, Float32) or a camera's GenICam name\n"
    "                      (PolarizeMono12p, Polarized16, BayerRGPolarized8, ...)\n"
    "  --bits N            significant bits of the data (default: what the file declares);\n"
    "                      values above 2^N - 1 are an error, never clamped\n"
    "  --layout L          mosaic layout [BAYER:]A,B,C,D[@DX,DY], the analyser angles of the\n"
    "                      top-left 2x2 block row by row (RGGB:90,45,135,0 or imx250myr for\n"
    "                      the colour sensor; @DX,DY for a crop at an odd offset). Default:\n"
    "                      the mosaic in meta.json when RAW is a frame of a polarcam recording\n"
    "                      (render, capture), else 90,45,135,0 = Sony IMX250MZR\n"
    "  --method NAME       demosaicking method (polarcam demosaic --list; default bilinear,\n"
    "                      bayer-first for colour-polarization layouts)\n"
    "levels (raw units, before the black level; docs/calibration.md):\n"
    "  --black-level DN    subtracted from every raw value before demosaicking. Default: the\n"
    "                      recording's (meta.json extra.sensor.offset_dn, written by render\n"
    "                      and by capture of a source that declares it) when RAW is one of\n"
    "                      its frames, else 0. Values below it stay negative (never clamped)\n"
    "  --saturation DN|none  samples >= DN are saturated: every output pixel whose value\n"
    "                      depends on one is flagged invalid (valid.npy, the count in the\n"
    "                      JSON, a pink checker in the pictures). Default: the raw's full\n"
    "                      scale 2^bits - 1 (none for float32 raws); 'none': not checked\n"
    "  --dead-level DN     samples <= DN are dead and flagged likewise (default: not checked)\n"
    "  --calibration FILE  apply a `polarcam calibrate` file: per-pixel dark and gain, the\n"
    "                      calibrated analysers, its distrusted pixels flagged. The frame must\n"
    "                      match it (size, ROI, mosaic, bit depth); the dark map replaces\n"
    "                      --black-level. Default saturation: the file's\n"
    "  --noise-gain DN_PER_E  the noise gain of noise-aware methods (noise_gain true in\n"
    "                      demosaic --list --json): the sensor's variance per unit signal\n"
    "                      in raw units, i.e. the system gain K (DN per electron, EMVA 1288\n"
    "                      photon transfer) at the settings in use, in the raw's units (x16\n"
    "                      for a 12-bit raw stored shifted in 16 bits). Default: estimated\n"
    "                      from each frame: for ratio-nr the slope of the photon-transfer\n"
    "                      line fitted to weakly textured blocks by level; for the colour\n"
    "                      methods the median residuals of the polarizer blocks and of\n"
    "                      samples one period apart, the smaller (texture finer than a\n"
    "                      block still inflates it). With --calibration: the system gain\n"
    "                      its flats measured, when it has one. The JSON says which\n"
    "                      (noise_gain, noise_gain_from). Refused with other methods\n"
    "  --threads N         threads (default: all cores)\n"
    "  --reference         run the double-precision reference implementation (slow)\n";

static int need(int argc, char **argv, int i)
{
	if (i + 1 >= argc) {
		cli_error(CLI_EXIT_USAGE, "option %s needs a value", argv[i]);
		return 0;
	}
	return 1;
}

void cli_raw_free(cli_raw *o)
{
	free(o->paths);
	o->paths = NULL;
	o->npaths = 0;
}

int cli_raw_parse(int argc, char **argv, cli_raw *o, int *extra, bool many)
{
	memset(o, 0, sizeof *o);
	if (many && !(o->paths = calloc((size_t)argc + 1, sizeof *o->paths)))
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	o->black_level = NAN;
	int nextra = 0, have_w = 0, have_h = 0, have_f = 0;
	long v;
	int rc;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (!strcmp(a, "-o") || !strcmp(a, "--output")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			o->out = argv[++i];
		} else if (!strcmp(a, "--layout")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			o->layout = argv[++i];
		} else if (!strcmp(a, "--method")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			o->method = argv[++i];
		} else if (!strcmp(a, "--bits")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			if ((rc = cli_parse_long("--bits", argv[++i], 1, 16, &v)))
				return cli_fail(rc, NULL);
			o->bits = (unsigned)v;
		} else if (!strcmp(a, "--threads")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			if ((rc = cli_parse_long("--threads", argv[++i], 1, 1024, &v)))
				return cli_fail(rc, NULL);
			o->threads = (int)v;
		} else if (!strcmp(a, "--black-level") || !strcmp(a, "--dead-level") ||
		           !strcmp(a, "--saturation")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			const char *val = argv[++i];
			double d;
			if (a[2] == 's' && !strcmp(val, "none")) {
				o->saturation = -1;
				continue;
			}
			if ((rc = cli_parse_double(a, val, &d)))
				return cli_fail(rc, NULL);
			if (!(d >= 0) || (a[2] != 'b' && !(d > 0)))
				return cli_error(CLI_EXIT_USAGE,
				                 "%s %s: expected a level %s 0 in raw "
				                 "units%s",
				                 a, val, a[2] == 'b' ? ">=" : ">",
				                 a[2] == 's' ? " (or 'none')" : "");
			if (a[2] == 'b')
				o->black_level = d;
			else if (a[2] == 's')
				o->saturation = d;
			else
				o->dead = d;
		} else if (!strcmp(a, "--noise-gain")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			const char *val = argv[++i];
			double d;
			if ((rc = cli_parse_double(a, val, &d)))
				return cli_fail(rc, NULL);
			if (!(d > 0) || !isfinite(d))
				return cli_error(
				    CLI_EXIT_USAGE,
				    "--noise-gain %s: expected a finite gain > 0 (raw "
				    "units per unit signal: the system gain K in DN/e-)",
				    val);
			o->noise_gain = d;
		} else if (!strcmp(a, "--calibration")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			o->calibration = argv[++i];
		} else if (!strcmp(a, "--reference")) {
			o->reference = true;
		} else if (!strcmp(a, "--width") || !strcmp(a, "--height")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			if ((rc = cli_parse_long(a, argv[++i], 1, 1 << 30, &v)))
				return cli_fail(rc, NULL);
			if (a[2] == 'w') {
				o->geometry.width = (uint32_t)v;
				have_w = 1;
			} else {
				o->geometry.height = (uint32_t)v;
				have_h = 1;
			}
		} else if (!strcmp(a, "--offset") || !strcmp(a, "--stride")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			uint64_t u;
			if ((rc = cli_parse_u64(a, argv[++i], &u)))
				return cli_fail(rc, NULL);
			if (a[2] == 'o')
				o->geometry.offset = (size_t)u;
			else
				o->geometry.stride = (size_t)u;
		} else if (!strcmp(a, "--format")) {
			if (!need(argc, argv, i))
				return CLI_EXIT_USAGE;
			const char *name = argv[++i];
			pc_pixfmt f = pc_format_from_name(name);
			if (f == PC_FMT_INVALID) {
				bool pol, col;
				if (pc_format_from_genicam(name, &f, &pol, &col) != 0)
					return cli_error(CLI_EXIT_USAGE, "--format '%s': %s", name,
					                 pc_error_detail());
			}
			o->geometry.format = f;
			have_f = 1;
		} else if (a[0] == '-' && a[1]) {
			if (!extra)
				return cli_error(CLI_EXIT_USAGE,
				                 "unknown option '%s' (see polarcam %s "
				                 "--help)",
				                 a, argv[0]);
			extra[nextra++] = i;
		} else if (!o->path || many) {
			if (!o->path)
				o->path = a;
			if (many)
				o->paths[o->npaths++] = a;
		} else {
			return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (one RAW file)",
			                 a);
		}
	}
	if (extra)
		extra[nextra] = 0;
	if (have_w || have_h || have_f || o->geometry.offset || o->geometry.stride) {
		if (!(have_w && have_h && have_f))
			return cli_error(CLI_EXIT_USAGE,
			                 "a headerless raw needs --width, --height and "
			                 "--format together");
		o->have_geometry = true;
	}
	/* what the recording says about RAW when it is one of its frames; for a recording folder,
	 * what it says about its first frame holds for all (one mosaic, ROI and black level) */
	char first[4200];
	const char *probe = o->path;
	struct stat sb;
	if (o->path && !o->have_geometry && stat(o->path, &sb) == 0 && S_ISDIR(sb.st_mode)) {
		pc_recording *r = NULL;
		if (pc_recording_open(&r, o->path) == 0) {
			if (pc_recording_count(r) &&
			    snprintf(first, sizeof first, "%s/%s", o->path,
			             pc_recording_get_frame(r, 0)->file) < (int)sizeof first)
				probe = first;
			pc_recording_free(r);
		}
		pc_error_clear(); /* not a recording: the command says so when it reads it */
	}
	pc_recording_frame_meta fm;
	int info = probe && !o->have_geometry ? pc_recording_frame_info(probe, &fm) : 0;
	if (info < 0 && !o->layout)
		return cli_fail(info, NULL);
	pc_error_clear();
	bool in_rec = info > 0;
	if (in_rec) {
		o->roi_x = fm.offset_x;
		o->roi_y = fm.offset_y;
	}
	if (o->calibration && !isnan(o->black_level))
		return cli_error(CLI_EXIT_USAGE,
		                 "--black-level and --calibration: the calibration's "
		                 "dark map is the black level; give one or the other");
	o->black_from = o->calibration                 ? "calibration"
	                : !isnan(o->black_level)       ? "option"
	                : in_rec && fm.black_level > 0 ? "recording"
	                                               : "none";
	if (isnan(o->black_level))
		o->black_level = !o->calibration && in_rec ? fm.black_level : 0;
	if (o->layout) {
		if ((rc = pc_mosaic_parse(o->layout, &o->mosaic)))
			return cli_fail(rc, "--layout");
	} else if (o->path && !o->have_geometry &&
	           (rc = pc_recording_frame_mosaic(probe, &o->mosaic)) != 0) {
		if (rc < 0)
			return cli_fail(rc, NULL);
		pc_mosaic_format(&o->mosaic, o->layout_buf, sizeof o->layout_buf);
		o->layout = o->layout_buf;
	} else {
		o->layout = "90,45,135,0";
		pc_mosaic_parse(o->layout, &o->mosaic);
	}
	if ((rc = pc_process_method(o->method, &o->mosaic, &o->dm)))
		return cli_fail(rc, NULL);
	o->method = pc_demosaic_method_get(o->dm)->name;
	if (o->noise_gain > 0 && !(pc_demosaic_method_get(o->dm)->flags & PC_DMF_NOISE_GAIN)) {
		char list[512];
		pc_demosaic_method_names(PC_DMF_NOISE_GAIN, list, sizeof list);
		return cli_error(CLI_EXIT_USAGE,
		                 "--noise-gain: method %s uses no noise gain (the methods that "
		                 "do: %s)",
		                 o->method, list);
	}
	return 0;
}

pc_raw_input cli_raw_input(const cli_raw *o)
{
	return (pc_raw_input){o->path, o->have_geometry ? &o->geometry : NULL, o->bits, NULL};
}

pc_process_opts cli_raw_process(const cli_raw *o)
{
	return (pc_process_opts){.mosaic = o->mosaic,
	                         .method = o->dm,
	                         .demosaic = {o->threads, o->reference, 0},
	                         .overwrite = false,
	                         .black_level = o->black_level,
	                         .saturation_level = o->saturation,
	                         .dead_level = o->dead,
	                         .roi_x = o->roi_x,
	                         .roi_y = o->roi_y,
	                         .noise_gain = o->noise_gain};
}

int cli_raw_calibration(const cli_raw *o, pc_calib *cal, pc_raw_stage *stage, pc_process_opts *po)
{
	pc_calib_init(cal);
	if (!o->calibration)
		return 0;
	int rc = pc_calib_read(o->calibration, cal);
	if (rc)
		return cli_fail(rc, "--calibration");
	*stage = pc_calib_stage(cal, o->calibration);
	po->stage = stage;
	po->black_level = 0;
	return 0;
}
