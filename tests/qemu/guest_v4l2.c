/* guest_v4l2.c - the V4L2 checks that run inside the QEMU guest against the real vivid driver.
 *
 * Started by tests/qemu/run-guest.sh as the guest's only program after vivid was loaded with
 * n_devs=1 node_types=0x101 (a capture and an output node). Prints one line per check:
 * "PASS name: what was seen", "FAIL name: why", "SKIP name: why"; exits 0 only when every check
 * passed. The checks run in one boot, in an order that leaves the destructive ones (fatal error,
 * disconnect) for last.
 */
#define _DEFAULT_SOURCE
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>

#include "guest_common.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/frame.h"
#include "polarcam/v4l2.h"

static char cap_path[256], out_path[256];

/* ---- the checks ---- */

static void check_list(void)
{
	pc_v4l2_node *nodes = NULL;
	size_t n = 0;
	int rc = pc_v4l2_list("/dev", &nodes, &n);
	if (rc) {
		gt_fail("list", "pc_v4l2_list: %s", pc_error_detail());
		return;
	}
	for (size_t i = 0; i < n; i++) {
		const pc_v4l2_node *d = &nodes[i];
		gt_info("node %s: driver=%s card='%s' bus=%s capture=%d output=%d formats=%zu%s%s",
			d->info.path, d->info.driver, d->info.card, d->info.bus_info, d->info.capture,
			d->info.output, d->nformats, d->error ? " error: " : "",
			d->error ? d->error_detail : "");
		if (strcmp(d->info.driver, "vivid") != 0 || d->error)
			continue;
		if (d->info.capture && !cap_path[0])
			snprintf(cap_path, sizeof cap_path, "%s", d->info.path);
		if (d->info.output && !out_path[0])
			snprintf(out_path, sizeof out_path, "%s", d->info.path);
	}
	free(nodes);
	if (cap_path[0] && out_path[0])
		gt_pass("list", "%zu nodes; vivid capture %s, output %s", n, cap_path, out_path);
	else
		gt_fail("list", "no vivid capture+output pair among %zu nodes", n);
}

static void check_formats(void)
{
	pc_v4l2 *dev;
	if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev)) {
		gt_fail("formats", "%s", pc_error_detail());
		return;
	}
	uint32_t f[128];
	size_t n = 0;
	if (pc_v4l2_enum_formats(dev, f, 128, &n)) {
		gt_fail("formats", "%s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	const char *want[] = { "GREY", "Y10 ", "Y12 ", "Y16 " };
	int found = 0, readable = 0;
	char list[1024] = "", b[5];
	for (size_t i = 0; i < n && i < 128; i++) {
		if (pc_format_from_v4l2(f[i]) != PC_FMT_INVALID) {
			readable++;
			strncat(list, " ", sizeof list - strlen(list) - 1);
			strncat(list, pc_fourcc_str(f[i], b), sizeof list - strlen(list) - 1);
		}
		for (int k = 0; k < 4; k++)
			if (f[i] == PC_FOURCC(want[k][0], want[k][1], want[k][2], want[k][3]))
				found++;
	}
	if (found == 4)
		gt_pass("formats", "%zu capture formats, polarcam reads%s", n, list);
	else
		gt_fail("formats", "only %d of GREY/Y10/Y12/Y16 among %zu formats", found, n);
	pc_v4l2_close(dev);
}

int main(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	setvbuf(stdout, NULL, _IONBF, 0);
	gt_info("guest: polarcam V4L2 checks against vivid");
	check_list();
	if (!cap_path[0])
		return gt_finish();
	check_formats();
	return gt_finish();
}
