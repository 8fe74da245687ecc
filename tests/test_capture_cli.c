/* polarcam capture as a user runs it (the built CLI, no network):
 *   - sim: frames recorded with the same naming and bit depth as polarcam render, equal to it
 *   - --process writes DoLP that matches the superpixel formula computed here from the raw
 *     values (S0 = ΣI/2, S1 = I0 − I90, S2 = I45 − I135: stokes.h / physics.md)
 *   - a camera that disappears (sim disconnect_after) ends with exit 1, a clear message and
 *     the frames so far intact (meta.json complete=false with the error)
 *   - a recording that ends early (file:) and bad arguments give clear errors, exit 1/2
 *   - an existing recording is never overwritten without --overwrite */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "check.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"

static const char *polarcam;
static char tmp[64], scene[512];
static char out[8192];

/* Runs polarcam with a shell-quoted argument string; captures stdout+stderr into out. */
static int run(const char *args)
{
	char cmd[2048];
	snprintf(cmd, sizeof cmd, "'%s' %s 2>&1", polarcam, args);
	FILE *p = popen(cmd, "r");
	if (!p)
		return -1;
	size_t n = fread(out, 1, sizeof out - 1, p);
	out[n] = '\0';
	int st = pclose(p);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void test_render_identical(void)
{
	char a[1500];
	snprintf(a, sizeof a, "render '%s' -o '%s/r' -n 2 -s 11 --no-truth", scene, tmp);
	CHECK_EQ_INT(run(a), 0);
	snprintf(a, sizeof a,
	         "capture 'sim:%s?seed=11&fps=0' -n 2 -o '%s/c' --process --method "
	         "superpixel-half",
	         scene, tmp);
	CHECK_EQ_INT(run(a), 0);
	CHECK(strstr(out, "\"frames\":2") != NULL);
	/* the same file names, the same PNG bytes */
	for (int k = 0; k < 2; k++) {
		char p1[128], p2[128];
		snprintf(p1, sizeof p1, "%s/r/raw_%06d.png", tmp, k);
		snprintf(p2, sizeof p2, "%s/c/raw_%06d.png", tmp, k);
		pc_view v1, v2;
		unsigned b1 = 0, b2 = 0;
		CHECK_EQ_INT(pc_image_read(p1, NULL, &v1, &b1), 0);
		CHECK_EQ_INT(pc_image_read(p2, NULL, &v2, &b2), 0);
		CHECK_EQ_INT(b1, b2);
		CHECK_EQ_INT(v1.width, v2.width);
		size_t diff = 0;
		for (uint32_t y = 0; y < v1.height && v1.width == v2.width; y++)
			diff += memcmp(PC_ROW(&v1, uint8_t, y), PC_ROW(&v2, uint8_t, y),
			               (size_t)v1.width * 2) != 0;
		CHECK_EQ_INT(diff, 0);
		if (k == 1) {
			/* DoLP of the last frame against the superpixel formula */
			char pn[128];
			snprintf(pn, sizeof pn, "%s/c/processed/dolp.npy", tmp);
			pc_array d;
			CHECK_EQ_INT(pc_npy_read(pn, &d), 0);
			CHECK_EQ_INT(d.ndim, 2);
			CHECK_EQ_INT(d.shape[1], v2.width / 2);
			unsigned bad = 0, checked = 0;
			for (uint32_t j = 0; j + 1 < v2.height && d.data; j += 14)
				for (uint32_t i = 0; i + 1 < v2.width; i += 18) {
					/* IMX250MZR block [90 45; 135 0] at even positions */
					double i90 = PC_ROW(&v2, uint16_t, j)[i];
					double i45 = PC_ROW(&v2, uint16_t, j)[i + 1];
					double i135 = PC_ROW(&v2, uint16_t, j + 1)[i];
					double i0 = PC_ROW(&v2, uint16_t, j + 1)[i + 1];
					double s0 = (i0 + i45 + i90 + i135) / 2, s1 = i0 - i90,
					       s2 = i45 - i135;
					double want =
					    s0 > 0 ? fmin(1.0, sqrt(s1 * s1 + s2 * s2) / s0) : 0;
					double got =
					    ((float *)d.data)[(j / 2) * d.shape[1] + i / 2];
					bad += fabs(got - want) > 1e-5;
					checked++;
				}
			CHECK(checked > 100);
			CHECK_EQ_INT(bad, 0);
			pc_array_free(&d);
			snprintf(pn, sizeof pn, "%s/c/processed/aolp.png", tmp);
			FILE *fp = fopen(pn, "rb");
			CHECK(fp != NULL);
			if (fp)
				fclose(fp);
		}
		pc_view_free(&v1);
		pc_view_free(&v2);
	}
	/* never over an existing recording */
	snprintf(a, sizeof a, "capture 'sim:%s?fps=0' -n 1 -o '%s/c'", scene, tmp);
	CHECK(run(a) != 0);
	CHECK(strstr(out, "already holds a recording") != NULL);
}

static void test_disconnect(void)
{
	char a[1500], dir[128];
	snprintf(dir, sizeof dir, "%s/lost", tmp);
	snprintf(a, sizeof a, "capture 'sim:%s?fps=0&disconnect_after=3' -n 10 -o '%s'", scene,
	         dir);
	CHECK_EQ_INT(run(a), 1);
	CHECK(strstr(out, "disappeared after 3 of 10 frames") != NULL);
	CHECK(strstr(out, "intact") != NULL);
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (r) {
		CHECK(!pc_recording_is_complete(r));
		CHECK_EQ_INT(pc_recording_count(r), 3);
		pc_view v;
		for (size_t k = 0; k < 3; k++) {
			CHECK_EQ_INT(pc_recording_read(r, k, &v), 0);
			pc_view_free(&v);
		}
		pc_recording_free(r);
	}
	/* a recording replayed past its end */
	snprintf(a, sizeof a, "capture 'file:%s' -n 5 -o '%s/replay'", dir, tmp);
	CHECK_EQ_INT(run(a), 1);
	CHECK(strstr(out, "ended after 3 of 5 frames") != NULL);
}

static void test_bad_arguments(void)
{
	char a[1500];
	CHECK_EQ_INT(run("capture"), 2);
	snprintf(a, sizeof a, "capture 'sim:%s' -n 0 -o '%s/x'", scene, tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK(strstr(out, "-n") != NULL);
	snprintf(a, sizeof a, "capture 'sim:%s' -n 2 -o '%s/x' --roi 1,2,3", scene, tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK(strstr(out, "--roi") != NULL);
	snprintf(a, sizeof a, "capture 'sim:%s?bogus=1' -n 2 -o '%s/x'", scene, tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK(strstr(out, "bogus") != NULL);
	snprintf(a, sizeof a, "capture 'sim:%s' -n 2 -o '%s/x' --exposure -5", scene, tmp);
	CHECK_EQ_INT(run(a), 2);
	snprintf(a, sizeof a, "capture 'sim:%s' -n 2 -o '%s/x' --format Mono8", scene, tmp);
	CHECK_EQ_INT(run(a), 2); /* a 12-bit sensor cannot deliver Mono8 without losing bits */
	CHECK(strstr(out, "adjust") != NULL);
	snprintf(a, sizeof a, "capture 'nosuch:x' -n 2 -o '%s/x'", tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK_EQ_INT(run("capture --help"), 0);
	CHECK(strstr(out, "raw_NNNNNN.png") != NULL);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	const char *src = getenv("PC_SOURCE_DIR");
	if (!polarcam || !src)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	snprintf(scene, sizeof scene, "%s/scenes/ideal_small.json", src);
	snprintf(tmp, sizeof tmp, "/tmp/pc_capcli_XXXXXX");
	if (!mkdtemp(tmp))
		SKIP("no temporary directory");
	test_render_identical();
	test_disconnect();
	test_bad_arguments();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_capture_cli");
}
