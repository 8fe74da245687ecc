/* Signals and kills during `polarcam capture` and `polarcam render` (the built CLI, as a user
 * runs it; sim: sources, no network). What each recording must hold is known independently:
 * the frames a sim: source regenerates from (seed, frame number), as checksums
 * (tests/sim_frames.h), and the number of frames the command says it recorded.
 *   - SIGTERM during a capture whose writer is slower than the camera: exit 1, the frames
 *     already acquired are written (the queue drains), meta.json says complete=false,
 *     "interrupted after N of M frames", lists every frame on disk, has the statistics
 *   - SIGINT during a capture --process, and during a render (frames, then the timings)
 *   - a second signal while the first one's clean-up runs ends the process at once, files whole
 *   - SIGKILL at random moments of capture (PNG and raw stores, --process) and render: every
 *     file under a final name is whole and holds the frame its name or meta.json says; what
 *     is left is recognisable (".NAME.tmpXXXXXX") and the next run in the directory removes
 *     it, but not a temporary file that a live writer holds */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "children.h"
#include "sim_frames.h"

#define PC_TEST_SEED 0x5eed1337u
#include "xorshift.h"

enum { WAIT_MS = 120000 };

static const char *polarcam;
static char tmp[64], scene[600];
static sf_frames frames5; /* seed 5: capture */
static sf_frames frames4; /* seed 4: render */

static void sleep_ms(double ms)
{
	struct timespec ts = {(time_t)(ms / 1e3), (long)(fmod(ms, 1e3) * 1e6)};
	while (nanosleep(&ts, &ts) && errno == EINTR)
		;
}

/* Waits until path exists (polling; the command's own pace decides). */
static bool wait_file(const char *path, int timeout_ms)
{
	for (int t = 0; t < timeout_ms; t += 20) {
		if (access(path, F_OK) == 0)
			return true;
		sleep_ms(20);
	}
	return false;
}

/* Starts polarcam ARGS with stdout to DIR.out (a file beside the directory). */
static pid_t start(char *const args[], const char *out_path)
{
	char *argv[40];
	int n = 0;
	argv[n++] = (char *)polarcam;
	for (int i = 0; args[i] && n < 39; i++)
		argv[n++] = args[i];
	argv[n] = NULL;
	int fd = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	char err[700];
	snprintf(err, sizeof err, "%s.err", out_path);
	pid_t pid = pc_child_spawn(argv, fd, err);
	if (fd >= 0)
		close(fd);
	return pid;
}

static char *slurp(const char *path)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return strdup("");
	static char buf[65536];
	size_t n = fread(buf, 1, sizeof buf - 1, fp);
	buf[n] = '\0';
	fclose(fp);
	return strdup(buf);
}

static json_t *meta_of(const char *dir)
{
	char p[700];
	snprintf(p, sizeof p, "%s/meta.json", dir);
	return json_load_file(p, 0, NULL);
}

/* The directory's frame files (raw_*) on disk. */
static unsigned count_frames(const char *dir)
{
	DIR *d = opendir(dir);
	unsigned n = 0;
	struct dirent *de;
	while (d && (de = readdir(d)))
		n += !strncmp(de->d_name, "raw_", 4);
	if (d)
		closedir(d);
	return n;
}

/* A capture whose writer (200 ms per frame) is slower than the camera (25 fps), stopped by
 * SIGTERM: every frame acquired is written before it exits. */
static void test_capture_sigterm(void)
{
	char dir[200], out[220], uri[800], probe[260];
	snprintf(dir, sizeof dir, "%s/term", tmp);
	snprintf(out, sizeof out, "%s/term.out", tmp);
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=25", scene);
	snprintf(probe, sizeof probe, "%s/raw_000002.png", dir);
	char *args[] = {"capture", uri, "-n", "100000", "-o", dir, "--write-delay-ms", "200", NULL};
	pid_t pid = start(args, out);
	CHECK(pid > 0);
	CHECK(wait_file(probe, WAIT_MS));
	unsigned on_disk_at_signal = count_frames(dir);
	int st = pc_child_stop(pid, SIGTERM, WAIT_MS);
	CHECK_EQ_INT(st, 1);
	char *o = slurp(out);
	json_t *rep = json_loads(o, 0, NULL);
	CHECK(rep != NULL);
	json_int_t reported = json_integer_value(json_object_get(rep, "frames"));
	const char *err = json_string_value(json_object_get(rep, "error"));
	unsigned long long acquired = 0, asked = 0;
	CHECK(err && sscanf(err, "interrupted after %llu of %llu frames", &acquired, &asked) == 2);
	CHECK_EQ_INT(asked, 100000);
	CHECK_EQ_INT(reported, (json_int_t)acquired); /* every frame acquired was written */
	CHECK(json_is_false(json_object_get(rep, "complete")));
	json_t *q = json_object_get(rep, "queue");
	CHECK(json_integer_value(json_object_get(q, "peak")) >= 2); /* frames were waiting */
	CHECK_EQ_INT(json_integer_value(json_object_get(q, "lost")), 0);
	printf("SIGTERM: %u frames on disk at the signal, %lld acquired and written by the exit "
	       "(queue peak %lld)\n",
	       on_disk_at_signal, (long long)reported,
	       (long long)json_integer_value(json_object_get(q, "peak")));
	/* meta.json: complete=false, why, the statistics, every frame on disk listed */
	json_t *m = meta_of(dir);
	CHECK(m != NULL);
	CHECK(json_is_false(json_object_get(m, "complete")));
	const char *merr = json_string_value(json_object_get(m, "error"));
	CHECK(merr && strstr(merr, "interrupted after") != NULL);
	CHECK_EQ_INT(json_array_size(json_object_get(m, "frames")), reported);
	CHECK(json_integer_value(json_object_get(json_object_get(m, "stats"), "completed")) >=
	      reported);
	json_t *mq =
	    json_object_get(json_object_get(json_object_get(m, "extra"), "capture"), "queue");
	CHECK_EQ_INT(json_integer_value(json_object_get(mq, "written")), reported);
	CHECK_EQ_INT(count_frames(dir), reported);
	sf_dir_report r;
	memset(&r, 0, sizeof r);
	sf_check_dir(dir, &frames5, &r);
	CHECK_EQ_INT(r.bad, 0);
	CHECK_EQ_INT(r.leftovers, 0);
	CHECK_EQ_INT(r.listed, reported);
	json_decref(m);
	json_decref(rep);
	free(o);
}

/* SIGINT during a capture --process: the processed pictures of the last frame come too. */
static void test_capture_sigint_process(void)
{
	char dir[200], out[220], uri[800], probe[260];
	snprintf(dir, sizeof dir, "%s/int", tmp);
	snprintf(out, sizeof out, "%s/int.out", tmp);
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=20", scene);
	snprintf(probe, sizeof probe, "%s/raw_000001.png", dir);
	char *args[] = {"capture", uri, "-n", "100000", "-o", dir, "--process", NULL};
	pid_t pid = start(args, out);
	CHECK(wait_file(probe, WAIT_MS));
	CHECK_EQ_INT(pc_child_stop(pid, SIGINT, WAIT_MS), 1);
	json_t *m = meta_of(dir);
	CHECK(m && json_is_false(json_object_get(m, "complete")));
	json_t *pj = json_object_get(json_object_get(m, "extra"), "process");
	CHECK_EQ_INT(json_integer_value(json_object_get(pj, "frames")),
	             json_array_size(json_object_get(m, "frames")));
	char p[300];
	snprintf(p, sizeof p, "%s/processed/dolp.npy", dir);
	pc_array a;
	CHECK_EQ_INT(pc_npy_read(p, &a), 0);
	if (a.data)
		pc_array_free(&a);
	sf_dir_report r;
	memset(&r, 0, sizeof r);
	sf_check_dir(dir, &frames5, &r);
	CHECK_EQ_INT(r.bad, 0);
	CHECK(r.listed >= 2);
	json_decref(m);
}

/* SIGINT during a render: the frames so far, complete=false, the timings. */
static void test_render_sigint(void)
{
	char dir[200], out[220], probe[260];
	snprintf(dir, sizeof dir, "%s/render", tmp);
	snprintf(out, sizeof out, "%s/render.out", tmp);
	snprintf(probe, sizeof probe, "%s/raw_000002.png", dir);
	char *args[] = {"render", scene, "-o", dir, "-n", "100000", "-s", "4", NULL};
	pid_t pid = start(args, out);
	CHECK(wait_file(probe, WAIT_MS));
	CHECK_EQ_INT(pc_child_stop(pid, SIGINT, WAIT_MS), 1);
	json_t *m = meta_of(dir);
	CHECK(m && json_is_false(json_object_get(m, "complete")));
	const char *err = m ? json_string_value(json_object_get(m, "error")) : NULL;
	unsigned long long done = 0, asked = 0;
	CHECK(err && sscanf(err, "interrupted after %llu of %llu frames", &done, &asked) == 2);
	CHECK_EQ_INT(asked, 100000);
	CHECK_EQ_INT(json_array_size(json_object_get(m, "frames")), done);
	CHECK_EQ_INT(count_frames(dir), done);
	json_t *tj = json_object_get(json_object_get(m, "extra"), "timings");
	CHECK(json_number_value(json_object_get(tj, "frames_s")) > 0);
	CHECK(json_number_value(json_object_get(tj, "per_frame_s")) > 0);
	char e[300];
	snprintf(e, sizeof e, "%s.err", out);
	char *msg = slurp(e);
	CHECK(strstr(msg, "intact") != NULL);
	free(msg);
	sf_dir_report r;
	memset(&r, 0, sizeof r);
	sf_check_dir(dir, &frames4, &r);
	CHECK_EQ_INT(r.bad, 0);
	CHECK_EQ_INT(r.listed, done);
	json_decref(m);
}

/* A second signal while the first one's clean-up (a long queue) runs: the process ends at once,
 * by the signal, and what it leaves is whole. */
static void test_second_signal(void)
{
	char dir[200], out[220], uri[800], probe[260];
	snprintf(dir, sizeof dir, "%s/twice", tmp);
	snprintf(out, sizeof out, "%s/twice.out", tmp);
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=50", scene);
	snprintf(probe, sizeof probe, "%s/raw_000000.png", dir);
	char *args[] = {"capture",          uri,    "-n", "100000", "-o", dir,
	                "--write-delay-ms", "2000", NULL};
	pid_t pid = start(args, out);
	CHECK(wait_file(probe, WAIT_MS));
	sleep_ms(500); /* a queue of frames waits for the 2 s writer */
	kill(pid, SIGTERM);
	sleep_ms(300);
	int st = pc_child_stop(pid, SIGTERM, WAIT_MS);
	CHECK_EQ_INT(st, 128 + SIGTERM);
	sf_dir_report r;
	memset(&r, 0, sizeof r);
	sf_check_dir(dir, &frames5, &r);
	CHECK_EQ_INT(r.bad, 0);
}

/* ---- SIGKILL at random moments ---- */

typedef struct kill_totals {
	unsigned rounds, files, frames, leftovers, cleaned;
} kill_totals;

/* Kills a run at a random moment: from its start (after_first false: any stage, the start up
 * included), or from its first frame on disk (after_first: while frames are written, however
 * slow the start is on a loaded machine). */
static void kill_round(char *const args[], const char *dir, const sf_frames *f, double max_ms,
                       bool after_first, char *const rerun[], kill_totals *t)
{
	char out[300], png[300], raw[300];
	snprintf(out, sizeof out, "%s.out", dir);
	snprintf(png, sizeof png, "%s/raw_000000.png", dir);
	snprintf(raw, sizeof raw, "%s/raw_000000.raw", dir);
	pid_t pid = start(args, out);
	CHECK(pid > 0);
	bool first = !after_first;
	for (int w = 0; w < WAIT_MS && !first; w += 20) {
		first = access(png, F_OK) == 0 || access(raw, F_OK) == 0;
		if (!first)
			sleep_ms(20);
	}
	CHECK(first);
	sleep_ms(urand() * max_ms);
	pc_child_stop(pid, SIGKILL, WAIT_MS);
	sf_dir_report r;
	memset(&r, 0, sizeof r);
	sf_check_dir(dir, f, &r);
	CHECK_EQ_INT(r.bad, 0);
	t->rounds++;
	t->files += r.files;
	t->frames += r.frames;
	t->leftovers += r.leftovers;
	if (!r.leftovers)
		return;
	/* the next run in the directory removes them */
	pid = start(rerun, out);
	CHECK_EQ_INT(pc_child_wait(pid, WAIT_MS, NULL), 0);
	sf_dir_report r2;
	memset(&r2, 0, sizeof r2);
	sf_check_dir(dir, f, &r2);
	CHECK_EQ_INT(r2.bad, 0);
	CHECK_EQ_INT(r2.leftovers, 0);
	t->cleaned += r.leftovers - r2.leftovers;
}

static void test_kills(void)
{
	kill_totals tc = {0}, tr = {0};
	const double max_ms = 2500; /* past the end of some runs: kills at every stage */
	for (int k = 0; k < 16; k++) {
		char dir[200], uri[800];
		snprintf(dir, sizeof dir, "%s/kill_c%02d", tmp, k);
		snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0", scene);
		const char *store = k % 2 ? "raw" : "png";
		char *args[] = {"capture", uri,           "-n",
		                "40",      "-o",          dir,
		                "--store", (char *)store, k % 4 == 3 ? "--process" : NULL,
		                NULL};
		char *rerun[] = {"capture", uri,       "-n",          "1",           "-o",
		                 dir,       "--store", (char *)store, "--overwrite", NULL};
		kill_round(args, dir, &frames5, max_ms, k % 4 >= 2, rerun, &tc);
	}
	for (int k = 0; k < 12; k++) {
		char dir[200];
		snprintf(dir, sizeof dir, "%s/kill_r%02d", tmp, k);
		char *args[] = {"render", scene, "-o", dir, "-n", "30", "-s", "4", NULL};
		char *rerun[] = {"render", scene, "-o",          dir,          "-n", "1",
		                 "-s",     "4",   "--overwrite", "--no-truth", NULL};
		kill_round(args, dir, &frames4, max_ms, k % 2, rerun, &tr);
	}
	printf("SIGKILL: capture %u kills: %u files under final names, all whole (%u frames "
	       "compared), %u temporary leftovers, %u removed by the next run; render %u kills: "
	       "%u files, %u frames, %u leftovers, %u removed\n",
	       tc.rounds, tc.files, tc.frames, tc.leftovers, tc.cleaned, tr.rounds, tr.files,
	       tr.frames, tr.leftovers, tr.cleaned);
	CHECK(tc.frames > 0 && tr.frames > 0);
}

/* Leftovers made on purpose: one unlocked (a dead writer's) is removed by the next capture,
 * one whose lock this test holds (a live writer's) is left alone. */
static void test_sweep(void)
{
	char dir[200], pdir[220], dead[300], live[300], pdead[300], uri[800];
	snprintf(dir, sizeof dir, "%s/sweep", tmp);
	snprintf(pdir, sizeof pdir, "%s/processed", dir);
	snprintf(dead, sizeof dead, "%s/.raw_000007.png.tmpAb12Cd", dir);
	snprintf(live, sizeof live, "%s/.raw_000008.png.tmpXy34Zw", dir);
	/* a run killed while processing: its leftover is removed by a capture without --process */
	snprintf(pdead, sizeof pdead, "%s/.s0_000003.png.tmpQq11Rr", pdir);
	mkdir(dir, 0755);
	mkdir(pdir, 0755);
	int fd1 = open(dead, O_WRONLY | O_CREAT, 0600);
	int fd2 = open(live, O_WRONLY | O_CREAT, 0600);
	int fd3 = open(pdead, O_WRONLY | O_CREAT, 0600);
	CHECK(fd1 >= 0 && fd2 >= 0 && fd3 >= 0);
	if (fd1 >= 0)
		close(fd1);
	if (fd3 >= 0)
		close(fd3);
	CHECK_EQ_INT(flock(fd2, LOCK_EX), 0);
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0", scene);
	char out[300];
	snprintf(out, sizeof out, "%s.out", dir);
	char *args[] = {"capture", uri, "-n", "2", "-o", dir, NULL};
	CHECK_EQ_INT(pc_child_wait(start(args, out), WAIT_MS, NULL), 0);
	CHECK(access(dead, F_OK) != 0);
	CHECK(access(pdead, F_OK) != 0);
	CHECK(access(live, F_OK) == 0);
	if (fd2 >= 0)
		close(fd2);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	const char *src = getenv("PC_SOURCE_DIR");
	if (!polarcam || !src)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	snprintf(scene, sizeof scene, "%s/scenes/ideal_small.json", src);
	snprintf(tmp, sizeof tmp, "/tmp/pc_interrupt_XXXXXX");
	if (!mkdtemp(tmp))
		SKIP("no temporary directory");
	printf("random kill moments from xorshift seed %#llx\n", (unsigned long long)PC_TEST_SEED);
	(void)nrand; /* only uniform moments are drawn */
	/* far more frames than any run here records */
	if (sf_regenerate(scene, 5, 400, &frames5) || sf_regenerate(scene, 4, 200, &frames4)) {
		CHECK(false);
		return pc_test_finish("test_interrupt");
	}
	test_sweep();
	test_capture_sigterm();
	test_capture_sigint_process();
	test_render_sigint();
	test_second_signal();
	test_kills();
	sf_free(&frames5);
	sf_free(&frames4);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (!pc_test_failures && system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_interrupt");
}
