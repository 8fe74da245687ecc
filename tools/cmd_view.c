/* polarcam view: a live window of S0, DoLP and AoLP false colour with the frame rate. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/display.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/io.h"
#include "polarcam/process.h"
#include "polarcam/source.h"
#include "raw_cli.h"
#include "source_cli.h"

static volatile sig_atomic_t view_stop;

static void on_signal(int sig)
{
	(void)sig;
	view_stop = 1;
}

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam view URI [options]\n\n"
	    "Shows a live window (OpenCV highgui) of S0 (grey), DoLP (grey, 0..1) and AoLP (false\n"
	    "colour: hue = angle, brightness = DoLP), side by side, with the frame rate. Keys:\n"
	    "q or Esc quits, s writes a screenshot (view_NNNN.png).\n\n"
	    "  URI                 sim:SCENE, file:DIR, aravis:ID, v4l2:/dev/videoN, libcamera:ID\n"
	    "  --method M          demosaicking method (default bilinear, bayer-first for colour-\n"
	    "                      polarization frames; superpixel is faster)\n"
	    "  --width PX          window width for the three panels (default 1500)\n"
	    "  --frames N          stop after N frames (default: until q)\n"
	    "  --screenshot FILE   write the last picture shown to FILE (PNG); with --frames and "
	    "no\n"
	    "                      display this runs headless\n"
	    "%s"
	    "\nPrints one JSON line at the end: frames, display and processing rates.\n",
	    cli_stream_args_help());
}

int cmd_view(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	cli_stream_args sa;
	cli_stream_args_init(&sa);
	const char *shot = NULL, *method = NULL; /* NULL: the mosaic's default */
	long frames = 0, width = 1500;
	for (int i = 1; i < argc; i++) {
		int rc = cli_stream_args_parse(&sa, argc, argv, &i);
		if (rc < 0)
			return cli_fail(rc, "arguments");
		if (rc > 0)
			continue;
		const char *a = argv[i];
		if (!strcmp(a, "--method") || !strcmp(a, "--width") || !strcmp(a, "--frames") ||
		    !strcmp(a, "--screenshot")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                    a);
			const char *v = argv[++i];
			if (!strcmp(a, "--method"))
				method = v;
			else if (!strcmp(a, "--screenshot"))
				shot = v;
			else if ((rc = cli_parse_long(a, v, !strcmp(a, "--width") ? 64 : 1,
			                                 !strcmp(a, "--width") ? 16384 : 100000000,
			                                 !strcmp(a, "--width") ? &width : &frames)))
				return cli_fail(rc, "arguments");
		} else if (a[0] == '-') {
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", a);
		} else if (!sa.uri) {
			sa.uri = a;
		} else {
			return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s'", a);
		}
	}
	if (!sa.uri)
		return cli_error(CLI_EXIT_USAGE, "missing the source URI (see --help)");
	pc_live lv;
	memset(&lv, 0, sizeof lv);
	int rc = method ? pc_demosaic_method_from_name(method, &lv.method) : 0;
	if (rc)
		return cli_fail(rc, "--method");
	bool headless = shot && frames > 0 && !getenv("DISPLAY");
	pc_display *win = NULL;
	if (!headless) {
		rc = pc_display_open(&win, "polarcam view");
		if (rc)
			return cli_fail(rc, "opening the window");
	}
	pc_source *s = NULL;
	rc = pc_stream_open(&sa, &s);
	if (rc) {
		pc_display_close(win);
		pc_devices_shutdown();
		return cli_fail(rc, "opening the source");
	}
	pc_source_format f;
	pc_source_get_format(s, &f);
	rc = pc_process_method(method, &f.mosaic, &lv.method);
	if (rc) {
		pc_source_close(s);
		pc_display_close(win);
		pc_devices_shutdown();
		return cli_fail(rc, NULL);
	}
	method = pc_demosaic_method_get(lv.method)->name;
	struct sigaction sig;
	memset(&sig, 0, sizeof sig);
	sig.sa_handler = on_signal;
	sigaction(SIGINT, &sig, NULL);
	sigaction(SIGTERM, &sig, NULL);

	uint8_t *small = NULL;
	uint32_t dw = 0, dh = 0;
	long shown = 0, shots = 0;
	double t0 = cli_now(), t_last = t0, fps = 0, proc_total = 0;
	char err[512] = "";
	int err_rc = pc_source_start(s);
	if (err_rc)
		snprintf(err, sizeof err, "starting the stream: %s", pc_error_detail());
	while (!err_rc && !view_stop && (frames == 0 || shown < frames)) {
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(s, sa.timeout_ms, &b);
		if (rc) {
			err_rc = rc;
			snprintf(err, sizeof err, "after %ld frames: %s", shown, pc_error_detail());
			break;
		}
		rc = pc_live_process(&lv, &b->frame);
		if (!rc)
			rc = pc_live_compose(&lv);
		uint64_t seq = b->frame.meta.sequence;
		int rc2 = pc_source_requeue(s, b);
		if (rc || rc2) {
			err_rc = rc ? rc : rc2;
			snprintf(err, sizeof err, "frame %ld: %s", shown, pc_error_detail());
			break;
		}
		proc_total += lv.process_s;
		if (!small || dw != (uint32_t)width) {
			dw = (uint32_t)width;
			dh = (uint32_t)((uint64_t)lv.h * dw / (3u * lv.w));
			if (dh < 1)
				dh = 1;
			free(small);
			small = malloc((size_t)dw * dh * 3);
			if (!small) {
				err_rc = pc_error(PC_ENOMEM, "picture");
				snprintf(err, sizeof err, "out of memory");
				break;
			}
		}
		rc = pc_display_resize_rgb8(lv.rgb, 3 * lv.w, lv.h, (size_t)lv.w * 9, small, dw, dh,
		                            (size_t)dw * 3);
		shown++;
		double t = cli_now();
		if (shown > 1)
			fps = fps > 0 ? 0.9 * fps + 0.1 / (t - t_last) : 1.0 / (t - t_last);
		t_last = t;
		char overlay[160];
		snprintf(overlay, sizeof overlay, "S0 | DoLP | AoLP   %.1f fps   frame %llu   %s",
		         fps, (unsigned long long)seq, method);
		if (win && !rc) {
			int key = pc_display_show(win, small, dw, dh, (size_t)dw * 3, overlay);
			if (key == 'q' || key == 27 || key == PC_ECANCELED)
				break;
			if (key < -1) {
				err_rc = key;
				snprintf(err, sizeof err, "%s", pc_error_detail());
				break;
			}
			if (key == 's') {
				char name[32];
				snprintf(name, sizeof name, "view_%04ld.png", shots++);
				if (pc_png_write_rgb8(name, small, dw, dh, (size_t)dw * 3))
					cli_warn("%s: %s", name, pc_error_detail());
			}
		}
		if (rc) {
			err_rc = rc;
			snprintf(err, sizeof err, "%s", pc_error_detail());
		}
	}
	if (!err_rc && shot && small && pc_png_write_rgb8(shot, small, dw, dh, (size_t)dw * 3)) {
		err_rc = PC_EIO;
		snprintf(err, sizeof err, "%s: %s", shot, pc_error_detail());
	}
	double dt = cli_now() - t0;
	json_t *j = json_object();
	json_object_set_new(j, "source", json_string(sa.uri));
	json_object_set_new(j, "frames", json_integer(shown));
	json_object_set_new(j, "fps", cli_json_real(dt > 0 ? shown / dt : 0));
	json_object_set_new(j, "process_ms", cli_json_real(shown ? 1e3 * proc_total / shown : 0));
	json_object_set_new(j, "window", json_boolean(win != NULL));
	json_object_set_new(j, "error", err_rc ? json_string(err) : json_null());
	cli_print_json(j);
	free(small);
	pc_live_free(&lv);
	pc_source_close(s);
	pc_display_close(win);
	pc_devices_shutdown();
	if (err_rc)
		return cli_error(cli_status(err_rc), "%s", err);
	return CLI_EXIT_OK;
}
