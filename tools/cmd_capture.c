/* polarcam capture: record frames from a source URI as a recording directory
 * (polarcam/capture.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/capture.h"
#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "polarcam/gige_server.h"
#include "source_cli.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam capture URI -n N -o DIR [options]\n\n"
	    "Records N frames from a frame source as DIR/raw_NNNNNN.png (8-bit, or 16-bit with "
	    "the\n"
	    "significant bits in sBIT: the same naming and bit depth as `polarcam render`) and\n"
	    "DIR/meta.json (format, mosaic, per-frame sequence/timestamp/exposure/gain/status,\n"
	    "stream statistics); docs/outputs.md. Frames go from the camera into a queue at once\n"
	    "(sized from the frame rate and the measured writing speed, within --queue-mb) and "
	    "are\n"
	    "written by a thread of their own, so a slow disk never starves the camera of "
	    "buffers.\n"
	    "The recording is made beside DIR and renamed into place at the end. If the camera\n"
	    "disappears or the command is interrupted (SIGINT/SIGTERM: the frames already "
	    "acquired\n"
	    "are written; a second signal quits at once), the command fails with a clear error "
	    "and\n"
	    "everything recorded so far is kept (meta.json says complete=false and why); with no\n"
	    "frame at all nothing is written. complete=true means: every frame asked for is in,\n"
	    "whole, and none was lost on the way to the disk.\n\n"
	    "  URI                 sim:SCENE, file:DIR, aravis:ID, v4l2:/dev/videoN, libcamera:ID\n"
	    "  -n N                frames to record (1..999999)\n"
	    "  -o DIR              output folder (refused when it exists, unless --overwrite)\n"
	    "  --overwrite         replace DIR as a whole when it exists\n"
	    "  --process           run every frame through the pipeline (demosaic -> Stokes) as "
	    "it\n"
	    "                      arrives; DIR/processed/ gets s0_NNNNNN.npy, dolp_NNNNNN.npy,\n"
	    "                      aolp_NNNNNN.npy (float32, H x W) and valid_NNNNNN.npy (uint8,\n"
	    "                      0 = depends on a saturated sample) of every frame, or of those\n"
	    "                      --keep-every chooses, and pictures of the last frame\n"
	    "  --keep-every K      with --process: keep the .npy of frames 0, K, 2K, ... and of "
	    "the\n"
	    "                      last (default 1: every frame; 0: the last frame only)\n"
	    "  --incomplete P      frames that arrive damaged (lost packets): skip (default: not\n"
	    "                      recorded, counted, the next one taken), keep (recorded and\n"
	    "                      flagged; the recording is then not complete) or fail (stop)\n"
	    "  --store S           frame files: png (default), npy or raw (headerless; the\n"
	    "                      fastest to write); all read by file:DIR sources\n"
	    "  --queue-mb MB       memory for frames waiting to be written (default: half the\n"
	    "                      available memory, at most 4096)\n"
	    "  --write-delay-ms MS testing: the writer waits MS after each frame (a slow disk)\n"
	    "  --method M          demosaicking method for --process (default bilinear; for\n"
	    "                      colour-polarization frames bayer-first; demosaic --list marks\n"
	    "                      the colour methods); S0, DoLP and AoLP of colour\n"
	    "                      frames are those of the colour average (R + G + B)/3\n"
	    "  --json              print the report as one JSON line on stdout: frames recorded,\n"
	    "                      complete, format, statistics, incomplete frames skipped/kept,\n"
	    "                      the queue (peak, lost, writing ms per frame), error (if any)\n"
	    "%s"
	    "levels (--process; the black level is also written to meta.json for later):\n"
	    "%s"
	    "\nWith --json, one JSON line: frames recorded, complete, format, statistics,\n"
	    "incomplete frames skipped/kept, the queue (peak, lost, writing ms per frame), error\n"
	    "(if any); with --process the levels used and the last frame's invalid pixel count.\n"
	    "Exit status: 0 complete, 1 not complete (device/stream failure, interrupted, "
	    "frames\n"
	    "lost or kept damaged), 2 bad arguments or DIR exists, 77 backend not built in or\n"
	    "device absent.\n"
	    "\nexamples:\n"
	    "  polarcam capture 'sim:default?seed=3' -n 10 -o rec/ --process\n"
	    "  polarcam capture aravis:192.168.1.20 -n 100 -o rec/ --store raw --json\n"
	    "  polarcam capture v4l2:/dev/video0 -n 50 -o rec/ --process --keep-every 10 "
	    "--overwrite\n",
	    cli_stream_args_help(), cli_levels_help());
}

/* the recording and its report */
static int run(pc_capture_opts *o, bool json)
{
	cli_catch_signals();
	cli_progress bar = {0};
	o->progress = (pc_progress){cli_progress_stoppable, &bar};
	pc_capture_report rep;
	int rc = pc_capture(o, &rep);
	cli_progress_end(&bar);
	pc_devices_shutdown();
	if (rc) {
		pc_capture_report_free(&rep);
		return cli_fail(rc, NULL);
	}
	if (rep.warning[0])
		cli_warn("%s", rep.warning);
	if (json)
		cli_print_json(json_loads(rep.json, 0, NULL));
	int status = CLI_EXIT_OK;
	if (rep.error)
		status = cli_error(cli_status(rep.error),
		                   "%s (the %llu frames recorded are kept intact in %s)",
		                   rep.message, (unsigned long long)rep.frames, o->dir);
	else
		cli_info("recorded %llu frames in %s", (unsigned long long)rep.frames, o->dir);
	pc_capture_report_free(&rep);
	return status;
}

int cli_cmd_capture(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	cli_stream_args sa;
	cli_stream_args_init(&sa);
	const char *dir = NULL;
	long n = 0, keep_every = 1;
	bool overwrite = false, process = false, json = false;
	const char *method = NULL; /* the mosaic's default */
	pc_stream_levels lv = pc_stream_levels_default();
	pc_incomplete_policy incomplete = PC_INCOMPLETE_SKIP;
	pc_recording_store store = PC_STORE_PNG;
	long queue_mb = 0;
	double write_delay_ms = 0;
	for (int i = 1; i < argc; i++) {
		int rc = cli_stream_args_parse(&sa, argc, argv, &i);
		if (rc == 0)
			rc = cli_levels_parse(&lv, argc, argv, &i);
		if (rc < 0)
			return cli_fail(rc, "arguments");
		if (rc > 0)
			continue;
		const char *a = argv[i];
		if (!strcmp(a, "-n") || !strcmp(a, "-o") || !strcmp(a, "--keep-every") ||
		    !strcmp(a, "--method")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			const char *v = argv[++i];
			if (!strcmp(a, "-o"))
				dir = v;
			else if (!strcmp(a, "--method"))
				method = v;
			else if ((rc = cli_parse_long(a, v, a[1] == 'n' ? 1 : 0, 999999,
			                              a[1] == 'n' ? &n : &keep_every)) ||
			         (a[1] == 'n' &&
			          (rc = pc_limit_check(PC_LIMIT_FRAMES, (uint64_t)n, "-n"))))
				return cli_fail(rc, "arguments");
		} else if (!strcmp(a, "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(a, "--process")) {
			process = true;
		} else if (!strcmp(a, "--json")) {
			json = true;
		} else if (!strcmp(a, "--incomplete") || !strcmp(a, "--store") ||
		           !strcmp(a, "--queue-mb") || !strcmp(a, "--write-delay-ms")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			const char *v = argv[++i];
			if (!strcmp(a, "--incomplete"))
				rc = pc_incomplete_policy_from_name(v, &incomplete);
			else if (!strcmp(a, "--store"))
				rc = pc_recording_store_from_name(v, &store);
			else if (!strcmp(a, "--queue-mb"))
				rc = cli_parse_long(a, v, 1, 1L << 30, &queue_mb);
			else if (!(rc = cli_parse_double(a, v, &write_delay_ms)) &&
			         (write_delay_ms < 0 || write_delay_ms > 3.6e6))
				return cli_error(CLI_EXIT_USAGE,
				                 "--write-delay-ms %g: expected 0..3600000",
				                 write_delay_ms);
			if (rc)
				return cli_fail(rc, a);
		} else if (a[0] == '-') {
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", a);
		} else if (!sa.req.uri) {
			sa.req.uri = a;
		} else {
			return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (see --help)",
			                 a);
		}
	}
	if (!sa.req.uri)
		return cli_error(CLI_EXIT_USAGE, "missing the source URI (see --help)");
	if (!n)
		return cli_error(CLI_EXIT_USAGE, "missing -n N (frames to record)");
	if (!dir)
		return cli_error(CLI_EXIT_USAGE, "missing -o DIR (output folder)");
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_capture_opts o = {.stream = sa.req,
	                     .frames = (uint64_t)n,
	                     .dir = dir,
	                     .overwrite = overwrite,
	                     .process = process,
	                     .method = method,
	                     .keep_every = (uint64_t)keep_every,
	                     .timeout_ms = sa.timeout_ms,
	                     .incomplete = incomplete,
	                     .store = store,
	                     .queue_bytes = (uint64_t)queue_mb << 20,
	                     .write_delay_ms = write_delay_ms,
	                     .levels = lv};
	return run(&o, json);
}
