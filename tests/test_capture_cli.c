/* polarcam capture as a user runs it (the built CLI, no network):
 *   - sim: frames recorded with the same naming and bit depth as polarcam render, equal to it
 *   - --process writes DoLP that matches the superpixel formula computed here from the raw
 *     values (S0 = ΣI/2, S1 = I0 − I90, S2 = I45 − I135: stokes.h / physics.md)
 *   - a camera that disappears (sim disconnect_after) ends with exit 1, a clear message and
 *     the frames so far kept (meta.json complete=false with the error)
 *   - a recording that ends early (file:) and bad arguments give clear errors, exit 1/2
 *   - an existing recording is never overwritten without --overwrite (exit 2)
 *   - --process keeps every frame's S0, DoLP, AoLP (processed/dolp_NNNNNN.npy), or those
 *     --keep-every chooses and the last
 *   - a colour-polarization scene (IMX250MYR): capture == render, --process runs bayer-first
 *     on the recorded mosaic (mean S0 against the colour-average formula computed here from
 *     the raw values and the layout drawn by hand; `polarcam process` of a recorded frame takes
 *     the layout from meta.json and gives the same images), a monochrome method is refused
 *     before anything is written */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

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
	         "superpixel-half --json",
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
			snprintf(pn, sizeof pn, "%s/c/processed/dolp_000001.npy", tmp);
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
			snprintf(pn, sizeof pn, "%s/c/processed/aolp_000001.png", tmp);
			FILE *fp = fopen(pn, "rb");
			CHECK(fp != NULL);
			if (fp)
				fclose(fp);
		}
		pc_view_free(&v1);
		pc_view_free(&v2);
	}
	/* every frame's DoLP was kept (--keep-every 1, the default) */
	char p0[128];
	snprintf(p0, sizeof p0, "%s/c/processed/dolp_000000.npy", tmp);
	pc_array d0;
	CHECK_EQ_INT(pc_npy_read(p0, &d0), 0);
	pc_array_free(&d0);
	/* never over an existing recording */
	snprintf(a, sizeof a, "capture 'sim:%s?fps=0' -n 1 -o '%s/c'", scene, tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK(strstr(out, "exists and is not empty") != NULL);
	/* --keep-every 2 over 3 frames keeps frames 0 and 2 (the last) */
	snprintf(
	    a, sizeof a,
	    "capture 'sim:%s?seed=11&fps=0' -n 3 -o '%s/c' --process --keep-every 2 --overwrite",
	    scene, tmp);
	CHECK_EQ_INT(run(a), 0);
	for (int k = 0; k < 3; k++) {
		snprintf(p0, sizeof p0, "%s/c/processed/dolp_%06d.npy", tmp, k);
		CHECK_EQ_INT(access(p0, F_OK) == 0, k != 1);
	}
}

static void test_disconnect(void)
{
	char a[1500], dir[128];
	snprintf(dir, sizeof dir, "%s/lost", tmp);
	snprintf(a, sizeof a, "capture 'sim:%s?fps=0&disconnect_after=3' -n 10 -o '%s'", scene,
	         dir);
	CHECK_EQ_INT(run(a), 1);
	CHECK(strstr(out, "disappeared after 3 of 10 frames") != NULL);
	CHECK(strstr(out, "kept") != NULL);
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

static float *npy(const char *path, size_t *n)
{
	pc_array a;
	if (pc_npy_read(path, &a) != 0 || a.dtype != PC_DT_F32)
		return NULL;
	*n = pc_array_count(&a);
	return a.data;
}

static void test_colour(const char *src)
{
	char a[1500], cs[600];
	snprintf(cs, sizeof cs, "%s/scenes/colour_small.json", src);
	snprintf(a, sizeof a, "render '%s' -o '%s/rc' -n 2 -s 11 --no-truth", cs, tmp);
	CHECK_EQ_INT(run(a), 0);
	snprintf(a, sizeof a, "capture 'sim:%s?seed=11&fps=0' -n 2 -o '%s/cc' --process --json", cs,
	         tmp);
	CHECK_EQ_INT(run(a), 0);
	CHECK(strstr(out, "\"method\":\"bayer-first\"") != NULL);
	CHECK(strstr(out, "\"mosaic\":\"RGGB:90,45,135,0\"") != NULL);
	char p1[128], p2[128];
	snprintf(p1, sizeof p1, "%s/rc/raw_000001.png", tmp);
	snprintf(p2, sizeof p2, "%s/cc/raw_000001.png", tmp);
	pc_view v1, v2;
	unsigned b1 = 0, b2 = 0;
	CHECK_EQ_INT(pc_image_read(p1, NULL, &v1, &b1), 0);
	CHECK_EQ_INT(pc_image_read(p2, NULL, &v2, &b2), 0);
	CHECK_EQ_INT(b2, 12);
	CHECK(v1.width == v2.width && v1.height == v2.height);
	size_t diff = 0;
	for (uint32_t y = 0; y < v1.height && v1.width == v2.width; y++)
		diff += memcmp(PC_ROW(&v1, uint8_t, y), PC_ROW(&v2, uint8_t, y),
		               (size_t)v1.width * 2) != 0;
	CHECK_EQ_INT(diff, 0);
	/* mean S0 = mean over pixels of (1/2) sum_c (R_c + G_c + B_c) / 3; interpolation keeps
	 * each colour-analyser class's mean (up to the borders), so it is (1/2) sum_c (1/3)
	 * sum_k mean(raw over class (k, c)) with the classes of IMX250MYR drawn by hand:
	 *   R90  R45 G90  G45
	 *   R135 R0  G135 G0
	 *   G90  G45 B90  B45
	 *   G135 G0  B135 B0 */
	static const char col[4][5] = {"RRGG", "RRGG", "GGBB", "GGBB"};
	double sum[3][4] = {{0}}, cnt[3][4] = {{0}};
	for (uint32_t y = 0; y < v2.height; y++)
		for (uint32_t x = 0; x < v2.width; x++) {
			int k = col[y & 3][x & 3] == 'R' ? 0 : col[y & 3][x & 3] == 'G' ? 1 : 2;
			int c = (y & 1) ? ((x & 1) ? 0 : 3) : ((x & 1) ? 1 : 2); /* 0,45,90,135 */
			sum[k][c] += PC_ROW(&v2, uint16_t, y)[x];
			cnt[k][c]++;
		}
	double want = 0;
	for (int k = 0; k < 3; k++)
		for (int c = 0; c < 4; c++)
			want += sum[k][c] / cnt[k][c] / 6;
	char pn[160];
	snprintf(pn, sizeof pn, "%s/cc/processed/s0_000001.npy", tmp);
	size_t n = 0, n2 = 0;
	float *s0 = npy(pn, &n);
	CHECK(s0 != NULL && n == (size_t)v2.width * v2.height);
	double mean = 0;
	for (size_t i = 0; s0 && i < n; i++)
		mean += s0[i] / (double)n;
	CHECK_REL(mean, want, 0.005); /* measured 0.05 % here */
	/* process of a recorded frame: the layout and method from the recording's meta.json */
	snprintf(a, sizeof a, "process '%s' -o '%s/pc' --json", p2, tmp);
	CHECK_EQ_INT(run(a), 0);
	CHECK(strstr(out, "\"layout\":\"RGGB:90,45,135,0\"") &&
	      strstr(out, "\"method\":\"bayer-first\""));
	snprintf(pn, sizeof pn, "%s/cc/processed/dolp_000001.npy", tmp);
	float *d1 = npy(pn, &n);
	snprintf(pn, sizeof pn, "%s/pc/dolp.npy", tmp);
	float *d2 = npy(pn, &n2);
	CHECK(d1 && d2 && n == n2);
	size_t bad = 0;
	for (size_t i = 0; d1 && d2 && i < n && n == n2; i++)
		bad += !(fabsf(d1[i] - d2[i]) <= 1e-6f);
	CHECK_EQ_INT(bad, 0);
	free(s0);
	free(d1);
	free(d2);
	pc_view_free(&v1);
	pc_view_free(&v2);
	/* a monochrome method on colour frames: exit 2, naming the methods, nothing written */
	snprintf(a, sizeof a,
	         "capture 'sim:%s?seed=11&fps=0' -n 2 -o '%s/cb' --process --method bilinear", cs,
	         tmp);
	CHECK_EQ_INT(run(a), 2);
	CHECK(strstr(out, "bayer-first") != NULL);
	snprintf(pn, sizeof pn, "%s/cb", tmp);
	FILE *fp = fopen(pn, "r");
	CHECK(fp == NULL);
	if (fp)
		fclose(fp);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	const char *src = getenv("PC_SOURCE_DIR");
	if (!polarcam || !src)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	snprintf(scene, sizeof scene, "%s/scenes/ideal_small.json", src);
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_capcli"))
		SKIP("no temporary directory");
	test_render_identical();
	test_disconnect();
	test_bad_arguments();
	test_colour(src);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_capture_cli");
}
