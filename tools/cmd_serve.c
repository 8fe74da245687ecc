/* polarcam serve: the simulator as a GigE Vision camera (polarcam/gige_server.h). */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/io.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam serve [SCENE] [--address ADDR] [--seed S] [options]\n\n"
	    "Serves simulated polarization frames as a GigE Vision camera (Aravis's in-process\n"
	    "GigE Vision camera with polarcam's image callback). Any GigE Vision client can "
	    "stream\n"
	    "from it; polarcam's own client is `polarcam capture aravis:ADDR ...`. Frames are\n"
	    "rendered ahead; every acquisition starts at frame 0 of the scene, so the frames "
	    "equal\n"
	    "`polarcam render SCENE --seed S` bit for bit. A monochrome sensor (IMX250MZR layout) "
	    "is\n"
	    "served with Mono* and LUCID's PolarizeMono* formats (model polarcam-sim), a colour-\n"
	    "polarization one (IMX250MYR, e.g. scenes/colour.json) with FLIR's BayerRGPolarized8/\n"
	    "10p/12p/16 (model polarcam-sim-colour); clients take the mosaic from the model name, "
	    "so\n"
	    "other layouts are refused.\n\n"
	    "  SCENE               a scene file or 'default' (the built-in scene)\n"
	    "  --address ADDR      interface address to serve on (default 127.0.0.1)\n"
	    "  --seed S            noise seed of the simulator (default 0, as render)\n"
	    "  --source URI        serve frames of any source instead (e.g. file:DIR?loop=1)\n"
	    "  --serial SN         serial number (default POLARCAM0001)\n"
	    "  --fps F             initial frame rate (default 25; clients may change it)\n"
	    "  --ahead N           frames rendered ahead (default 4)\n"
	    "  --cycle K           render frames 0..K-1 once and repeat them (transport "
	    "benchmarks)\n"
	    "  --lost-packets R    fault injection: drop this fraction of stream packets\n"
	    "  --duration SEC      stop after SEC seconds (default: until SIGINT/SIGTERM)\n"
	    "  --genicam FILE      also write the camera's GenICam XML to FILE (an existing FILE\n"
	    "                      is refused unless --overwrite)\n"
	    "  --overwrite         replace FILE\n"
	    "  --json              accepted: the output is always JSON lines\n\n"
	    "SIGINT/SIGTERM stop the camera cleanly (also while the cycle is being rendered) and\n"
	    "print the statistics; exit status 0 then, 1 when the frame source failed.\n"
	    "On start it prints one JSON line {\"serving\": ...} on stdout; at the end one with "
	    "the\n"
	    "statistics. Camera discovery answers go to the interface's network: in tests run it\n"
	    "inside `unshare -n` with only loopback up.\n"
	    "Exit status: 0 stopped by SIGINT/SIGTERM or --duration, 1 failure, 2 bad arguments,\n"
	    "77 built without Aravis.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam serve scenes/mesh.json --seed 3\n"
	    "  polarcam serve --source 'file:rec/?loop=1' --fps 10 --duration 60\n"
	    "  polarcam serve --address 127.0.0.1 --genicam camera.xml --overwrite\n");
}

/* the camera until a signal or the duration, and its statistics */
static int run(const pc_gige_server_options *op, const char *genicam, double duration)
{
	pc_gige_server_options o = *op;
	const char *uri = o.source_uri;
	pc_gige_server *srv = NULL;
	/* a signal during the start (rendering the cycle) ends it cleanly too */
	cli_catch_signals();
	cli_progress bar = {0};
	o.progress = (pc_progress){cli_progress_stoppable, &bar};
	int rc = pc_gige_server_start(&srv, &o);
	cli_progress_end(&bar);
	if (rc) {
		pc_devices_shutdown();
		if (rc == PC_ECANCELED)
			return cli_error(CLI_EXIT_FAILURE, "interrupted while starting: %s",
			                 pc_error_detail());
		return cli_fail(rc, "serve");
	}
	if (genicam) {
		const char *xml = pc_gige_server_genicam(srv);
		if (pc_write_file_atomic(genicam, xml, strlen(xml)))
			cli_warn("cannot write %s: %s", genicam, pc_error_detail());
	}
	pc_gige_server_stats st;
	pc_gige_server_get_stats(srv, &st);
	json_t *j = json_object();
	json_t *sv = json_object();
	json_object_set_new(sv, "address", json_string(o.address ? o.address : "127.0.0.1"));
	json_object_set_new(sv, "serial", json_string(o.serial ? o.serial : "POLARCAM0001"));
	json_object_set_new(sv, "source", json_string(uri));
	json_object_set_new(sv, "width", json_integer(st.sensor_width));
	json_object_set_new(sv, "height", json_integer(st.sensor_height));
	json_object_set_new(sv, "bits", json_integer(st.bits));
	json_object_set_new(sv, "model", json_string(st.model));
	json_object_set_new(sv, "mosaic", json_string(st.mosaic));
	json_object_set_new(sv, "black_level", json_real(st.black_level));
	json_object_set_new(j, "serving", sv);
	cli_print_json(j);
	fflush(stdout);

	double t0 = cli_now();
	char msg[256] = "";
	int err = 0;
	while (!cli_stop_requested && (duration <= 0 || cli_now() - t0 < duration)) {
		struct timespec ts = {0, 20000000};
		nanosleep(&ts, NULL);
		if ((err = pc_gige_server_error(srv, msg, sizeof msg)))
			break;
	}
	pc_gige_server_get_stats(srv, &st);
	pc_gige_server_stop(srv);
	pc_devices_shutdown();
	j = json_object();
	json_object_set_new(j, "served", json_integer((json_int_t)st.served));
	json_object_set_new(j, "late", json_integer((json_int_t)st.late));
	json_object_set_new(j, "rendered", json_integer((json_int_t)st.rendered));
	json_object_set_new(j, "acquisitions", json_integer((json_int_t)st.acquisitions));
	json_object_set_new(j, "seconds", cli_json_real(cli_now() - t0));
	if (err)
		json_object_set_new(j, "error", json_string(msg));
	cli_print_json(j);
	if (err)
		return cli_error(cli_status(err), "the frame source failed: %s", msg);
	return CLI_EXIT_OK;
}

int cli_cmd_serve(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	const char *scene = NULL, *source = NULL, *genicam = NULL;
	pc_gige_server_options o = {0};
	uint64_t seed = 0;
	double duration = 0;
	bool overwrite = false;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const char *v = i + 1 < argc ? argv[i + 1] : NULL;
		int rc = 0;
		long l;
		if (!strcmp(a, "--overwrite") || !strcmp(a, "--json")) {
			overwrite |= !strcmp(a, "--overwrite");
			continue;
		}
		if (a[0] != '-') {
			if (scene)
				return cli_error(CLI_EXIT_USAGE,
				                 "more than one scene given ('%s', '%s')", scene,
				                 a);
			scene = a;
			continue;
		}
		static const char *const known[] = {
		    "--address", "--seed",         "--source",   "--serial",  "--fps", "--ahead",
		    "--cycle",   "--lost-packets", "--duration", "--genicam", NULL};
		bool is_known = false;
		for (const char *const *k = known; *k; k++)
			is_known |= !strcmp(a, *k);
		if (!is_known)
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)", a);
		if (!v)
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)", a);
		if (!strcmp(a, "--address"))
			o.address = v;
		else if (!strcmp(a, "--seed"))
			rc = cli_parse_u64(a, v, &seed);
		else if (!strcmp(a, "--source"))
			source = v;
		else if (!strcmp(a, "--serial"))
			o.serial = v;
		else if (!strcmp(a, "--fps"))
			rc = cli_parse_double(a, v, &o.frame_rate_hz);
		else if (!strcmp(a, "--ahead") && !(rc = cli_parse_long(a, v, 1, 60, &l)))
			o.ahead = (unsigned)l;
		else if (!strcmp(a, "--cycle") && !(rc = cli_parse_long(a, v, 1, 256, &l)))
			o.cycle = (unsigned)l;
		else if (!strcmp(a, "--lost-packets"))
			rc = cli_parse_double(a, v, &o.lost_packet_ratio);
		else if (!strcmp(a, "--duration"))
			rc = cli_parse_double(a, v, &duration);
		else if (!strcmp(a, "--genicam"))
			genicam = v;
		if (rc)
			return cli_fail(rc, "arguments");
		i++;
	}
	if (source && scene)
		return cli_error(CLI_EXIT_USAGE, "give a SCENE or --source, not both");
	if (o.frame_rate_hz < 0 || o.frame_rate_hz > 1000)
		return cli_error(CLI_EXIT_USAGE, "--fps %g: expected (0, 1000]", o.frame_rate_hz);
	if (duration < 0)
		return cli_error(CLI_EXIT_USAGE, "--duration %g: expected >= 0", duration);
	char uri[1200];
	if (source) {
		snprintf(uri, sizeof uri, "%s", source);
	} else {
		const char *sc = scene ? scene : "default";
		if (strchr(sc, '?') || strchr(sc, '&'))
			return cli_error(CLI_EXIT_USAGE,
			                 "scene '%s': '?' and '&' are not allowed in a "
			                 "scene path",
			                 sc);
		snprintf(uri, sizeof uri, "sim:%s?seed=%llu", sc, (unsigned long long)seed);
	}
	o.source_uri = uri;
	int rc = genicam ? pc_output_check(genicam, overwrite ? PC_OUT_OVERWRITE : 0, false) : 0;
	if (rc)
		return cli_fail(rc, NULL);
	if (cli_parse_only())
		return CLI_EXIT_OK;
	return run(&o, genicam, duration);
}
