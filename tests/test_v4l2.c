/* test_v4l2.c - the V4L2 layer on the host, where no video device is needed: CVT timings
 * against VESA's published numbers, error paths of open/list on things that are not V4L2
 * nodes. Streaming against a real driver runs in the QEMU guest (tests/qemu, test v4l2_guest). */

#include "check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "polarcam/error.h"
#include "polarcam/v4l2.h"

static void test_cvt_published(void)
{
	/* VESA CVT 1.2 reduced blanking v2 modes as published (e.g. the VESA DMT/CVT timing
	 * tables, and display EDIDs): 1920x1080@60 = 133.320 MHz, 2000 x 1111 total;
	 * 3840x2160@60 = 522.614 MHz, 3920 x 2222 total. */
	pc_dv_timings t;
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 1080, 60.0, &t), 0);
	CHECK_EQ_INT(t.pixelclock_hz, 133320000);
	CHECK_EQ_INT(t.width + t.hfrontporch + t.hsync + t.hbackporch, 2000);
	CHECK_EQ_INT(t.height + t.vfrontporch + t.vsync + t.vbackporch, 1111);
	CHECK_EQ_INT(t.hfrontporch, 8);
	CHECK_EQ_INT(t.hsync, 32);
	CHECK_EQ_INT(t.hbackporch, 40);
	CHECK_EQ_INT(t.vsync, 8);
	CHECK_EQ_INT(t.vbackporch, 6);
	CHECK(t.hsync_pos && !t.vsync_pos && t.cvt && t.reduced_blanking && !t.interlaced);
	CHECK_NEAR(pc_dv_timings_fps(&t), 60.0, 1e-9);

	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(3840, 2160, 60.0, &t), 0);
	CHECK_EQ_INT(t.pixelclock_hz, 522614000);
	CHECK_EQ_INT(t.width + t.hfrontporch + t.hsync + t.hbackporch, 3920);
	CHECK_EQ_INT(t.height + t.vfrontporch + t.vsync + t.vbackporch, 2222);

	/* The vertical blanking is at least 460 us and at most one line more (CVT 1.2 §3.4). */
	static const double rates[] = {24.0, 30.0, 50.0, 60.0, 120.0};
	static const uint32_t sizes[][2] = {{640, 480}, {2448, 2048}, {5472, 3648}};
	for (int s = 0; s < 3; s++) {
		for (int r = 0; r < 5; r++) {
			CHECK_EQ_INT(pc_dv_timings_cvt_rb2(sizes[s][0], sizes[s][1], rates[r], &t),
			             0);
			double total_h = (double)t.width + 80.0;
			double total_v = (double)t.height + t.vfrontporch + t.vsync + t.vbackporch;
			double line_us = total_h / (double)t.pixelclock_hz * 1e6;
			double vblank_us = (total_v - t.height) * line_us;
			CHECK(t.vfrontporch >= 1);
			CHECK(vblank_us >= 460.0 * (1 - 1e-3));
			if (t.vfrontporch > 1) /* not at the 15-line minimum */
				CHECK(vblank_us <= 460.0 + 2 * line_us);
			CHECK_EQ_INT(t.pixelclock_hz % 1000, 0);
			CHECK_REL(pc_dv_timings_fps(&t), rates[r], 1e-3);
		}
	}
	/* Bad input is refused, not clamped. */
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(0, 1080, 60.0, &t), PC_EINVAL);
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 0, 60.0, &t), PC_EINVAL);
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 1080, 0.0, &t), PC_EINVAL);
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 1080, -5.0, &t), PC_EINVAL);
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 1080, 1.0 / 0.0, &t), PC_EINVAL);
	CHECK_EQ_INT(pc_dv_timings_cvt_rb2(1920, 1080, 3000.0, &t), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "refresh") != NULL);
}

static void test_open_errors(const char *dir)
{
	pc_v4l2 *dev = (pc_v4l2 *)1;
	char path[512];
	snprintf(path, sizeof path, "%s/video99", dir);
	CHECK_EQ_INT(pc_v4l2_open(path, PC_V4L2_CAPTURE, &dev), PC_ENOENT);
	CHECK(dev == NULL);
	CHECK(strstr(pc_error_detail(), "video99") != NULL);

	/* a regular file is not a device node */
	FILE *f = fopen(path, "w");
	CHECK(f != NULL);
	if (f)
		fclose(f);
	CHECK_EQ_INT(pc_v4l2_open(path, PC_V4L2_CAPTURE, &dev), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "not a character device") != NULL);

	/* a character device that is not V4L2 */
	if (access("/dev/null", R_OK | W_OK) == 0) {
		CHECK_EQ_INT(pc_v4l2_open("/dev/null", PC_V4L2_CAPTURE, &dev), PC_ENOTSUP);
		CHECK(strstr(pc_error_detail(), "not a V4L2 device") != NULL);
	}
	CHECK_EQ_INT(pc_v4l2_open("", PC_V4L2_CAPTURE, &dev), PC_EINVAL);
	CHECK_EQ_INT(pc_v4l2_open("/dev/null", (pc_v4l2_dir)7, &dev), PC_EINVAL);

	/* every call refuses a NULL device instead of crashing */
	pc_v4l2_format g;
	pc_v4l2_buffer b;
	CHECK_EQ_INT(pc_v4l2_set_format(NULL, 0, 1, 1, 0, &g), PC_EINVAL);
	CHECK_EQ_INT(pc_v4l2_dequeue(NULL, 0, &b), PC_EINVAL);
	CHECK_EQ_INT(pc_v4l2_stream_start(NULL, 4), PC_EINVAL);
	CHECK_EQ_INT(pc_v4l2_stream_stop(NULL), PC_EINVAL);
	pc_v4l2_close(NULL);
}

static void test_list(const char *dir)
{
	/* An empty or missing directory lists nothing, without error. */
	pc_v4l2_node *nodes = (pc_v4l2_node *)1;
	size_t n = 99;
	char path[512];
	snprintf(path, sizeof path, "%s/absent", dir);
	CHECK_EQ_INT(pc_v4l2_list(path, &nodes, &n), 0);
	CHECK_EQ_INT(n, 0);
	CHECK(nodes == NULL);

	/* Names that only look like nodes are ignored; nodes sort numerically; a node that is
	 * not a device is listed with its error, not skipped. */
	snprintf(path, sizeof path, "%s/dev", dir);
	CHECK_EQ_INT(mkdir(path, 0700), 0);
	const char *names[] = {"video10", "video2", "video", "videox", "video1a", "vbi0"};
	for (int i = 0; i < 6; i++) {
		char p[600];
		snprintf(p, sizeof p, "%s/%s", path, names[i]);
		FILE *f = fopen(p, "w");
		CHECK(f != NULL);
		if (f)
			fclose(f);
	}
	CHECK_EQ_INT(pc_v4l2_list(path, &nodes, &n), 0);
	CHECK_EQ_INT(n, 2);
	if (n == 2) {
		CHECK(strstr(nodes[0].info.path, "/video2") != NULL);
		CHECK(strstr(nodes[1].info.path, "/video10") != NULL);
		CHECK_EQ_INT(nodes[0].error, PC_EINVAL);
		CHECK(strstr(nodes[0].error_detail, "not a character device") != NULL);
	}
	free(nodes);
}

int main(void)
{
	char dir[64];
	if (!pc_test_tmpdir(dir, sizeof dir, "pc-test-v4l2"))
		return 1;
	test_cvt_published();
	test_open_errors(dir);
	test_list(dir);
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_v4l2");
}
