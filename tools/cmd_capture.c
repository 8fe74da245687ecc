/* polarcam capture: record frames from a source URI as a recording directory. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/io.h"
#include "polarcam/process.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"
#include "raw_cli.h"
#include "source_cli.h"

static volatile sig_atomic_t capture_stop;

static void on_signal(int sig)
{
	(void)sig;
	capture_stop = 1;
}

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam capture URI -n N -o DIR [options]\n\n"
	    "Records N frames from a frame source as DIR/raw_NNNNNN.png (8-bit, or 16-bit with "
	    "the\n"
	    "significant bits in sBIT: the same naming and bit depth as `polarcam render`) and\n"
	    "DIR/meta.json (format, mosaic, per-frame sequence/timestamp/exposure/gain/status,\n"
	    "stream statistics). Every file is written atomically: if the camera disappears or "
	    "the\n"
	    "command is interrupted, the command fails with a clear error and everything recorded\n"
	    "so far stays intact (meta.json says complete=false and why).\n\n"
	    "  URI                 sim:SCENE, file:DIR, aravis:ID, v4l2:/dev/videoN, libcamera:ID\n"
	    "  -n N                frames to record (1..999999)\n"
	    "  -o DIR              output directory (refused if it already holds a recording)\n"
	    "  --overwrite         record into a directory that already holds a recording\n"
	    "  --process           run every frame through the pipeline (demosaic -> Stokes) as "
	    "it\n"
	    "                      arrives; DIR/processed/ gets S0, DoLP, AoLP (.npy, float32) "
	    "and\n"
	    "                      pictures of the last frame; meta.json the per-frame timings\n"
	    "  --method M          demosaicking method for --process (default bilinear; for\n"
	    "                      colour-polarization frames bayer-first, the colour methods\n"
	    "                      being bayer-first and bayer-eari); S0, DoLP and AoLP of colour\n"
	    "                      frames are those of the colour average (R + G + B)/3\n"
	    "%s"
	    "\nPrints one JSON line: frames recorded, format, statistics, error (if any).\n"
	    "Exit status: 0 all frames recorded, 1 device/stream failure, 2 bad arguments.\n",
	    cli_stream_args_help());
}

int cmd_capture(int argc, char **argv)
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
	for (int i = 1; i < argc; i++) {
		int rc = cli_stream_args_parse(&sa, argc, argv, &i);
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
			else if ((rc = cli_parse_long("-n", argv[++i], 1, 999999, &n)))
				return cli_fail(rc, "arguments");
		} else if (!strcmp(a, "--overwrite")) {
			overwrite = true;
		} else if (!strcmp(a, "--process")) {
			process = true;
		} else if (!strcmp(a, "--method")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE,
				                    "--method needs a value (see --help)");
			method = argv[++i];
		} else if (a[0] == '-') {
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", a);
		} else if (!sa.uri) {
			sa.uri = a;
		} else {
			return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (see --help)",
			                    a);
		}
	}
	if (!sa.uri)
		return cli_error(CLI_EXIT_USAGE, "missing the source URI (see --help)");
	if (!n)
		return cli_error(CLI_EXIT_USAGE, "missing -n N (frames to record)");
	if (!dir)
		return cli_error(CLI_EXIT_USAGE, "missing -o DIR (output directory)");
	pc_live lv;
	memset(&lv, 0, sizeof lv);
	if (method) { /* a misspelt name is refused before the camera is opened */
		int mrc = pc_demosaic_method_from_name(method, &lv.method);
		if (mrc)
			return cli_fail(mrc, "--method");
	}

	pc_source *s = NULL;
	int rc = pc_stream_open(&sa, &s);
	if (rc) {
		pc_devices_shutdown();
		return cli_fail(rc, "opening the source");
	}
	pc_source_format f;
	pc_source_get_format(s, &f);
	if (process && f.polarized) {
		/* a method for the other kind of mosaic is refused before anything is recorded */
		rc = pc_process_method(method, &f.mosaic, &lv.method);
		if (rc) {
			pc_source_close(s);
			pc_devices_shutdown();
			return cli_fail(rc, NULL);
		}
		method = pc_demosaic_method_get(lv.method)->name;
	}
	pc_recording_desc d;
	memset(&d, 0, sizeof d);
	d.source = sa.uri;
	d.format = f.format;
	d.device_format = f.format_name;
	d.width = f.width;
	d.height = f.height;
	d.offset_x = f.offset_x;
	d.offset_y = f.offset_y;
	d.sensor_width = f.sensor_width;
	d.sensor_height = f.sensor_height;
	d.polarized = f.polarized;
	d.mosaic = f.mosaic;
	pc_recording *rec = NULL;
	rc = pc_recording_create(&rec, dir, &d, overwrite);
	if (rc) {
		pc_source_close(s);
		pc_devices_shutdown();
		return cli_fail(rc, "creating the recording");
	}

	struct sigaction sig;
	memset(&sig, 0, sizeof sig);
	sig.sa_handler = on_signal;
	sigaction(SIGINT, &sig, NULL);
	sigaction(SIGTERM, &sig, NULL);

	cli_progress prog;
	cli_progress_begin(&prog, "capture", (uint64_t)n);
	char err[512] = "";
	int err_rc = 0;
	long got = 0;
	rc = pc_source_start(s);
	if (rc) {
		err_rc = rc;
		snprintf(err, sizeof err, "starting the stream: %s", pc_error_detail());
	}
	double t0 = cli_now(), proc_sum = 0, proc_max = 0, dolp_last = 0;
	if (process && !f.polarized) {
		err_rc = PC_EFORMAT;
		snprintf(err, sizeof err,
		         "--process: the source's frames carry no polarizer mosaic");
	}
	while (!err_rc && got < n) {
		if (capture_stop) {
			err_rc = PC_ECANCELED;
			snprintf(err, sizeof err, "interrupted after %ld of %ld frames", got, n);
			break;
		}
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(s, sa.timeout_ms, &b);
		if (rc) {
			err_rc = rc;
			if (rc == PC_EDISCONNECTED)
				snprintf(err, sizeof err,
				         "the camera disappeared after %ld of %ld frames: %s", got,
				         n, pc_error_detail());
			else if (rc == PC_ETIMEDOUT)
				snprintf(err, sizeof err,
				         "no frame within %d ms after %ld of %ld frames: %s",
				         sa.timeout_ms, got, n, pc_error_detail());
			else if (rc == PC_EEND)
				snprintf(err, sizeof err,
				         "the source ended after %ld of %ld frames", got, n);
			else
				snprintf(err, sizeof err, "frame %ld: %s", got, pc_error_detail());
			break;
		}
		rc = pc_recording_add(rec, &b->frame);
		if (!rc && process) {
			rc = pc_live_process(&lv, &b->frame);
			proc_sum += lv.process_s;
			if (lv.process_s > proc_max)
				proc_max = lv.process_s;
		}
		int rc2 = pc_source_requeue(s, b);
		if (rc || rc2) {
			err_rc = rc ? rc : rc2;
			snprintf(err, sizeof err, "%s frame %ld: %s", rc ? "writing" : "requeueing",
			         got, pc_error_detail());
			break;
		}
		got++;
		cli_progress_update(&prog, (uint64_t)got);
	}
	double dt = cli_now() - t0;
	cli_progress_end(&prog);
	json_t *pj = NULL;
	if (process && got > 0 && lv.planes) {
		/* the last frame's Stokes images and pictures */
		char pdir[1100], path[1200];
		snprintf(pdir, sizeof pdir, "%s/processed", dir);
		int prc = pc_mkdir_p(pdir);
		static const char *const names[3] = {"s0", "dolp", "aolp"};
		size_t shape[2] = {lv.h, lv.w};
		for (int k = 0; !prc && k < 3; k++) {
			snprintf(path, sizeof path, "%s/%s.npy", pdir, names[k]);
			prc = pc_npy_write(path, lv.planes + (size_t)k * lv.w * lv.h, PC_DT_F32, 2,
			                   shape);
		}
		if (!prc)
			prc = pc_pictures_write(pdir, &lv.out, lv.w, lv.h, "capture");
		double sum = 0;
		for (size_t i = 0; i < (size_t)lv.w * lv.h; i++)
			sum += lv.out.dolp.data[i];
		dolp_last = sum / ((double)lv.w * lv.h);
		if (prc && !err_rc) {
			err_rc = prc;
			snprintf(err, sizeof err, "writing the processed pictures: %s",
			         pc_error_detail());
		}
		pj = json_object();
		json_object_set_new(pj, "method", json_string(method));
		json_object_set_new(pj, "frames", json_integer(got));
		json_object_set_new(pj, "mean_ms", cli_json_real(1e3 * proc_sum / (double)got));
		json_object_set_new(pj, "max_ms", cli_json_real(1e3 * proc_max));
		json_object_set_new(pj, "last_mean_dolp", cli_json_real(dolp_last));
		json_object_set_new(pj, "width", json_integer(lv.w));
		json_object_set_new(pj, "height", json_integer(lv.h));
		char *ptext = json_dumps(pj, JSON_COMPACT);
		if (ptext) {
			char wrapped[1200];
			snprintf(wrapped, sizeof wrapped, "{\"process\":%s}", ptext);
			pc_recording_set_json(rec, "extra", wrapped);
		}
		free(ptext);
	}
	if (pc_source_get_state(s) == PC_SOURCE_STREAMING ||
	    pc_source_get_state(s) == PC_SOURCE_FAILED)
		pc_source_stop(s);
	pc_source_stats st;
	pc_source_get_stats(s, &st);
	json_t *sj = cli_json_source_stats(&st);
	char *stext = json_dumps(sj, JSON_COMPACT);
	if (stext)
		pc_recording_set_json(rec, "stats", stext);
	free(stext);
	rc = pc_recording_finish(rec, err_rc ? err : NULL);
	if (rc && !err_rc) {
		err_rc = rc;
		snprintf(err, sizeof err, "writing meta.json: %s", pc_error_detail());
	}
	json_t *j = json_object();
	json_object_set_new(j, "source", json_string(sa.uri));
	json_object_set_new(j, "dir", json_string(dir));
	json_object_set_new(j, "frames", json_integer(got));
	json_object_set_new(j, "requested", json_integer(n));
	json_object_set_new(j, "seconds", cli_json_real(dt));
	json_object_set_new(j, "fps", cli_json_real(dt > 0 ? got / dt : 0));
	json_object_set_new(j, "format", cli_json_source_format(&f));
	json_object_set_new(j, "stats", sj);
	if (pj)
		json_object_set_new(j, "process", pj);
	json_object_set_new(j, "error", err_rc ? json_string(err) : json_null());
	cli_print_json(j);
	pc_recording_free(rec);
	pc_live_free(&lv);
	pc_source_close(s);
	pc_devices_shutdown();
	if (err_rc)
		return cli_error(cli_status(err_rc),
		                    "%s (the %ld frames recorded are intact in %s)", err, got, dir);
	return CLI_EXIT_OK;
}
