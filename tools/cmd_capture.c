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
	    "stream statistics). Frames go from the camera into a queue at once (sized from the\n"
	    "frame rate and the measured writing speed, within --queue-mb) and are written by a\n"
	    "thread of their own, so a slow disk never starves the camera of buffers. Every file\n"
	    "is written atomically: if the camera disappears or the command is interrupted\n"
	    "(SIGINT/SIGTERM: the frames already acquired are written; a second signal quits at\n"
	    "once), the command fails with a clear error and everything recorded so far stays\n"
	    "intact (meta.json says complete=false and why). complete=true means: every frame\n"
	    "asked for is in, whole, and none was lost on the way to the disk.\n\n"
	    "  URI                 sim:SCENE, file:DIR, aravis:ID, v4l2:/dev/videoN, libcamera:ID\n"
	    "  -n N                frames to record (1..999999)\n"
	    "  -o DIR              output directory (refused if it already holds a recording)\n"
	    "  --overwrite         record into a directory that already holds a recording\n"
	    "  --process           run every frame through the pipeline (demosaic -> Stokes) as "
	    "it\n"
	    "                      arrives; DIR/processed/ gets S0, DoLP, AoLP (.npy, float32) "
	    "and\n"
	    "                      valid.npy (uint8, 0 = depends on a saturated sample) and\n"
	    "                      pictures of the last frame; meta.json the per-frame timings\n"
	    "  --incomplete P      frames that arrive damaged (lost packets): skip (default: not\n"
	    "                      recorded, counted, the next one taken), keep (recorded and\n"
	    "                      flagged; the recording is then not complete) or fail (stop)\n"
	    "  --store S           frame files: png (default), npy or raw (headerless; the\n"
	    "                      fastest to write); all read by file:DIR sources\n"
	    "  --queue-mb MB       memory for frames waiting to be written (default: half the\n"
	    "                      available memory, at most 4096)\n"
	    "  --write-delay-ms MS testing: the writer waits MS after each frame (a slow disk)\n"
	    "  --method M          demosaicking method for --process (default bilinear; for\n"
	    "                      colour-polarization frames bayer-first, the colour methods\n"
	    "                      being bayer-first and bayer-eari); S0, DoLP and AoLP of colour\n"
	    "                      frames are those of the colour average (R + G + B)/3\n"
	    "%s"
	    "levels (--process; the black level is also written to meta.json for later):\n"
	    "%s"
	    "\nPrints one JSON line: frames recorded, complete, format, statistics, incomplete\n"
	    "frames skipped/kept, the queue (peak, lost, writing ms per frame), error (if any);\n"
	    "with --process the levels used and the last frame's invalid pixel count.\n"
	    "Exit status: 0 complete, 1 not complete (device/stream failure, interrupted, frames\n"
	    "lost or kept damaged), 2 bad arguments.\n",
	    cli_stream_args_help(), cli_levels_help());
}

/* the recording and its report */
static int run(pc_capture_opts *o)
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
	cli_print_json(json_loads(rep.json, 0, NULL));
	int status = CLI_EXIT_OK;
	if (rep.error)
		status = cli_error(cli_status(rep.error),
		                   "%s (the %llu frames recorded are intact in %s)", rep.message,
		                   (unsigned long long)rep.frames, o->dir);
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
	long n = 0;
	bool overwrite = false, process = false;
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
		if (!strcmp(a, "-n") || !strcmp(a, "-o")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			if (!strcmp(a, "-o"))
				dir = argv[++i];
			else if ((rc = cli_parse_long("-n", argv[++i], 1, 999999, &n)) ||
			         (rc = pc_limit_check(PC_LIMIT_FRAMES, (uint64_t)n, "-n")))
				return cli_fail(rc, "arguments");
		} else if (!strcmp(a, "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(a, "--process")) {
			process = true;
		} else if (!strcmp(a, "--method") || !strcmp(a, "--incomplete") ||
		           !strcmp(a, "--store") || !strcmp(a, "--queue-mb") ||
		           !strcmp(a, "--write-delay-ms")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			const char *v = argv[++i];
			if (!strcmp(a, "--method"))
				method = v;
			else if (!strcmp(a, "--incomplete"))
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
		return cli_error(CLI_EXIT_USAGE, "missing -o DIR (output directory)");
	pc_capture_opts o = {sa.req,
	                     (uint64_t)n,
	                     dir,
	                     overwrite,
	                     process,
	                     method,
	                     sa.timeout_ms,
	                     {NULL, NULL},
	                     incomplete,
	                     store,
	                     (uint64_t)queue_mb << 20,
	                     write_delay_ms,
	                     lv};
	return run(&o);
}
