/* polarcam view: a live window of S0, DoLP and AoLP false colour with the frame rate
 * (polarcam/viewer.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/io.h"
#include "polarcam/viewer.h"
#include "source_cli.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam view URI [options]\n\n"
	    "Shows a live window (OpenCV highgui) of S0 (grey), DoLP (grey) and AoLP (false\n"
	    "colour: hue = angle, brightness = DoLP), side by side at the frames' aspect ratio,\n"
	    "with the keys and masks of process's pictures (docs/pictures.md) and the frame\n"
	    "rate. Keys: q or Esc quits, s writes a screenshot (view_NNNN.png).\n\n"
	    "  URI                 sim:SCENE, file:DIR, aravis:ID, v4l2:/dev/videoN, libcamera:ID\n"
	    "  --method M          demosaicking method (default bilinear, bayer-first for colour-\n"
	    "                      polarization frames; superpixel is faster)\n"
	    "  --width PX          window width for the three panels with their keys (default\n"
	    "                      1500, at least 480)\n"
	    "  --mask-s0 T         low-signal hatch over DoLP and AoLP where S0 < T (raw\n"
	    "                      units); default 1%% of the S0 scale's top; 0: none\n"
	    "  --dolp-max V|auto   DoLP range 0..V (default 1), or auto: the 99th percentile\n"
	    "                      of each frame's unmasked DoLP, rounded up to 0.05\n"
	    "  --frames N          stop after N frames (default: until q)\n"
	    "  --screenshot FILE   write the last picture shown to FILE.png (PNG only: another\n"
	    "                      name is refused); with --frames and no display this runs\n"
	    "                      headless. An existing FILE is refused\n"
	    "                      unless --overwrite\n"
	    "  --overwrite         replace FILE\n"
	    "  --json              print one JSON line at the end on stdout: frames, display and\n"
	    "                      processing rates, levels, the last frame's invalid pixels\n"
	    "%s"
	    "levels (invalid pixels are drawn as a pink checker):\n"
	    "%s"
	    "\nExit status: 0 success, 1 failure, 2 bad arguments or FILE exists, 77 no display,\n"
	    "no live window in this build, backend not built in or device absent.\n"
	    "\nexamples:\n"
	    "  polarcam view 'sim:default?fps=5'\n"
	    "  polarcam view 'file:rec/?loop=1&fps=10' --method superpixel --width 1200\n"
	    "  polarcam view sim:default --frames 3 --screenshot view.png --overwrite --json\n",
	    cli_stream_args_help(), cli_levels_help());
}

/* the window and its report */
static int run(pc_viewer_opts *o, bool json)
{
	cli_catch_signals();
	o->progress = (pc_progress){cli_progress_stoppable, NULL};
	pc_viewer_report rep;
	int rc = pc_viewer_run(o, &rep);
	pc_devices_shutdown();
	if (rc) {
		pc_viewer_report_free(&rep);
		return cli_fail(rc, NULL);
	}
	if (rep.screenshots_failed)
		cli_warn("%u screenshots could not be written", rep.screenshots_failed);
	if (rep.warning[0])
		cli_warn("%s", rep.warning);
	if (json)
		cli_print_json(json_loads(rep.json, 0, NULL));
	int status = rep.error ? cli_error(cli_status(rep.error), "%s", rep.message) : CLI_EXIT_OK;
	pc_viewer_report_free(&rep);
	return status;
}

int cli_cmd_view(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	cli_stream_args sa;
	cli_stream_args_init(&sa);
	const char *shot = NULL, *method = NULL; /* NULL: the mosaic's default */
	long frames = 0, width = 1500;
	double mask_s0 = 0, dolp_hi = 0;
	bool overwrite = false, json = false;
	pc_stream_levels lv = pc_stream_levels_default();
	for (int i = 1; i < argc; i++) {
		int rc = cli_stream_args_parse(&sa, argc, argv, &i);
		if (rc == 0)
			rc = cli_levels_parse(&lv, argc, argv, &i);
		if (rc < 0)
			return cli_fail(rc, "arguments");
		if (rc > 0)
			continue;
		const char *a = argv[i];
		if (!strcmp(a, "--method") || !strcmp(a, "--width") || !strcmp(a, "--frames") ||
		    !strcmp(a, "--screenshot") || !strcmp(a, "--mask-s0") ||
		    !strcmp(a, "--dolp-max")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			const char *v = argv[++i];
			if (!strcmp(a, "--method"))
				method = v;
			else if (!strcmp(a, "--screenshot"))
				shot = v;
			else if (!strcmp(a, "--mask-s0") || !strcmp(a, "--dolp-max")) {
				if ((rc = cli_parse_picture_opt(a, v, &mask_s0, &dolp_hi)))
					return cli_fail(rc, "arguments");
			} else if ((rc = cli_parse_long(
			                a, v,
			                !strcmp(a, "--width") ? PC_PICTURES_PANELS_MIN_WIDTH : 1,
			                !strcmp(a, "--width") ? 16384 : 100000000,
			                !strcmp(a, "--width") ? &width : &frames)))
				return cli_fail(rc, "arguments");
		} else if (!strcmp(a, "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(a, "--json")) {
			json = true;
		} else if (a[0] == '-') {
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", a);
		} else if (!sa.req.uri) {
			sa.req.uri = a;
		} else {
			return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s'", a);
		}
	}
	if (!sa.req.uri)
		return cli_error(CLI_EXIT_USAGE, "missing the source URI (see --help)");
	int rc = shot ? pc_output_check(shot, overwrite ? PC_OUT_OVERWRITE : 0, false) : 0;
	if (rc)
		return cli_fail(rc, NULL);
	if (cli_parse_only())
		return CLI_EXIT_OK;
	bool headless = shot && frames > 0 && !getenv("DISPLAY");
	pc_viewer_opts o = {
	    sa.req,        method,       !headless, (uint32_t)width, (uint64_t)frames, shot,
	    sa.timeout_ms, {NULL, NULL}, lv,        mask_s0,         dolp_hi};
	return run(&o, json);
}
