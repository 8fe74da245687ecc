/* polarcam devices: list cameras of every built-in backend, diagnose USB3 Vision devices, and
 * run the frame-source compliance test against any URI. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/source.h"
#include "polarcam/usb3v.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam devices [--gige] [--json]\n"
	    "       polarcam devices --check URI [--fault KIND] [--frames N] [--finite] "
	    "[--json]\n\n"
	    "Lists the frame-source backends of this build and the cameras each finds: Aravis\n"
	    "(USB3 Vision; GigE Vision with --gige), V4L2 nodes, libcamera cameras (when built),\n"
	    "and USB3 Vision devices seen through libusb, with a diagnosis when one cannot be "
	    "used\n"
	    "(permissions / udev rule, usbfs memory limit, not on a SuperSpeed port).\n\n"
	    "  --gige         also discover GigE Vision cameras. Discovery broadcasts on every\n"
	    "                 network interface, so it is never done unless asked for.\n"
	    "  --json         one JSON line per backend and device instead of a table\n"
	    "  --check URI    run the frame-source compliance test against URI (see\n"
	    "                 devices/include/polarcam/compliance.h); exit 1 if a check fails\n"
	    "  --fault KIND   with --check: the URI injects a fault (drop, timeout, disconnect,\n"
	    "                 corrupt) that must surface as the documented error\n"
	    "  --frames N     with --check: frames to stream (default 8)\n"
	    "  --finite       with --check: the source may end before N frames (file: without "
	    "loop)\n"
	    "Exit status: 0 success, 1 a listing or a check failed, 2 bad arguments, 77 the\n"
	    "--check URI's backend is not built in or its device is absent.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam devices\n"
	    "  polarcam devices --gige --json\n"
	    "  polarcam devices --check 'sim:default?drop_every=5' --fault drop\n");
}

typedef struct list_ctx {
	bool json;
	unsigned count;
	const char *backend;
} list_ctx;

static int print_device(void *ctx, const pc_device_entry *d)
{
	list_ctx *c = ctx;
	c->count++;
	if (c->json) {
		json_t *j = json_object();
		json_object_set_new(j, "backend", json_string(c->backend));
		json_object_set_new(j, "uri", json_string(d->uri));
		json_object_set_new(j, "vendor", json_string(d->vendor));
		json_object_set_new(j, "model", json_string(d->model));
		json_object_set_new(j, "serial", json_string(d->serial));
		json_object_set_new(j, "transport", json_string(d->transport));
		json_object_set_new(j, "address", json_string(d->address));
		json_object_set_new(j, "usable", json_boolean(d->usable));
		json_object_set_new(j, "note", json_string(d->note));
		if (d->formats_total) {
			json_t *fa = json_array();
			char buf[sizeof d->formats];
			snprintf(buf, sizeof buf, "%s", d->formats);
			for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
				json_array_append_new(fa, json_string(tok));
			json_object_set_new(j, "formats", fa);
			json_object_set_new(j, "formats_total", json_integer(d->formats_total));
		}
		cli_print_json(j);
	} else {
		printf("  %-40s %-12s %s %s %s%s%s\n", d->uri, d->transport, d->vendor, d->model,
		       d->address, d->note[0] ? "\n      " : "", d->note);
		if (d->formats_total)
			printf("      formats polarcam reads: %s (%u formats offered in all)\n",
			       d->formats[0] ? d->formats : "none", d->formats_total);
		if (!d->usable)
			printf("      -> not usable as it is\n");
	}
	return 0;
}

static void log_check(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	bool json = *(bool *)ctx;
	static const char *const names[] = {"PASS", "FAIL", "SKIP"};
	if (json) {
		json_t *j = json_object();
		json_object_set_new(j, "result", json_string(names[r]));
		json_object_set_new(j, "check", json_string(check));
		json_object_set_new(j, "detail", json_string(detail));
		cli_print_json(j);
	} else {
		printf("%s  %s%s%s\n", names[r], check, detail[0] ? ": " : "", detail);
	}
}

static int run_check(const char *uri, int fault, long frames, bool finite, bool json)
{
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.frames = (unsigned)frames;
	o.expect_fault = (pc_fault_kind)fault;
	o.finite = finite;
	o.log = log_check;
	o.log_ctx = &json;
	pc_compliance_result res;
	int rc = pc_source_compliance(uri, &o, &res);
	pc_devices_shutdown();
	if (rc)
		return cli_fail(rc, "opening the source");
	if (json) {
		json_t *j = json_object();
		json_object_set_new(j, "uri", json_string(uri));
		json_object_set_new(j, "passed", json_integer(res.passed));
		json_object_set_new(j, "failed", json_integer(res.failed));
		json_object_set_new(j, "skipped", json_integer(res.skipped));
		json_object_set_new(j, "first_failure",
		                    res.failed ? json_string(res.first_failure) : json_null());
		cli_print_json(j);
	} else {
		printf("%s: %u passed, %u failed, %u skipped\n", uri, res.passed, res.failed,
		       res.skipped);
	}
	return res.failed ? CLI_EXIT_FAILURE : CLI_EXIT_OK;
}

int cli_cmd_devices(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	bool json = false, gige = false, finite = false;
	const char *check = NULL;
	int fault = PC_FAULT_NONE;
	long frames = 8;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (!strcmp(a, "--json")) {
			json = true;
		} else if (!strcmp(a, "--gige")) {
			gige = true;
		} else if (!strcmp(a, "--finite")) {
			finite = true;
		} else if (!strcmp(a, "--check") || !strcmp(a, "--fault") ||
		           !strcmp(a, "--frames")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
				                 a);
			const char *v = argv[++i];
			if (!strcmp(a, "--check")) {
				check = v;
			} else if (!strcmp(a, "--fault")) {
				fault = pc_fault_parse(v);
				if (fault < 0)
					return cli_error(CLI_EXIT_USAGE,
					                 "--fault '%s': expected drop, "
					                 "timeout, disconnect or corrupt",
					                 v);
			} else {
				int rc = cli_parse_long(a, v, 1, 100000, &frames);
				if (rc)
					return cli_fail(rc, "arguments");
			}
		} else {
			return cli_error(CLI_EXIT_USAGE, "unknown argument '%s' (see --help)", a);
		}
	}
	if (cli_parse_only())
		return CLI_EXIT_OK;
	if (check)
		return run_check(check, fault, frames, finite, json);
	if (fault != PC_FAULT_NONE || finite)
		return cli_error(CLI_EXIT_USAGE, "--fault and --finite go with --check URI");

	int status = CLI_EXIT_OK;
	for (unsigned i = 0; pc_source_backend_get(i); i++) {
		const pc_source_backend *b = pc_source_backend_get(i);
		if (json) {
			json_t *j = json_object();
			json_object_set_new(j, "backend", json_string(b->scheme));
			json_object_set_new(j, "built", json_boolean(b->ops != NULL));
			json_object_set_new(j, "summary", json_string(b->summary));
			json_object_set_new(j, "uri", json_string(b->uri_help));
			json_object_set_new(j, "missing",
			                    b->ops ? json_null() : json_string(b->missing));
			cli_print_json(j);
		} else {
			printf("%-10s %s\n           %s\n", b->scheme,
			       b->ops ? b->summary : "(not built)",
			       b->ops ? b->uri_help : b->missing);
		}
		if (!b->ops || !b->enumerate)
			continue;
		list_ctx c = {json, 0, b->scheme};
		int rc = b->enumerate(gige ? PC_ENUM_NETWORK : 0, print_device, &c);
		if (rc) {
			cli_warn("%s: listing devices failed: %s", b->scheme, pc_error_detail());
			status = CLI_EXIT_FAILURE;
		} else if (!json && c.count == 0) {
			printf("           no devices%s\n", !strcmp(b->scheme, "aravis") && !gige
			                                        ? " (GigE Vision: add --gige)"
			                                        : "");
		}
	}
	list_ctx c = {json, 0, "usb3vision"};
	if (!json)
		printf("usb3vision USB3 Vision devices (libusb, class 0x%02X subclass 0x%02X)\n",
		       PC_USB3V_CLASS, PC_USB3V_SUBCLASS);
	int rc = pc_usb3v_list(print_device, &c);
	if (rc) {
		cli_warn("USB3 Vision: %s", pc_error_detail());
	} else if (!json && c.count == 0) {
		long mb = pc_usbfs_memory_mb();
		if (mb < 0)
			printf("           no devices (usbfs memory limit unknown: no usbcore "
			       "module)\n");
		else
			printf("           no devices (usbfs memory limit %ld MB%s)\n", mb,
			       mb < PC_USBFS_MIN_MB
			           ? ", too small for streaming: see a device's note"
			           : "");
	}
	pc_devices_shutdown();
	return status;
}
