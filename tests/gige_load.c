/* GigE Vision capture of 2448x2048 frames when the writer cannot keep up with the camera (issue
 * 13: with the CPU busy, `capture aravis:127.0.0.1 -n 10` from `serve` recorded an incomplete
 * frame - the buffer pool ran dry while frames were written as PNG - exited 0 and said
 * complete). `polarcam serve` and `polarcam capture` run as separate processes inside a private
 * network namespace (tests/netns.sh); a writer slowed on purpose (--write-delay-ms) stands for
 * the busy machine. The camera serves the default scene pre-rendered (--cycle 3), so frame k of
 * an acquisition is simulator frame k mod 3, regenerated here from (seed, frame) as checksums
 * (tests/sim_frames.h): every check compares with that or with frame counts.
 *   - the repro: 10 frames, each whole and the simulator's, complete, exit 0; the writer was
 *     behind (queue peak >= 2) and lost nothing
 *   - a queue too small for that writer: frames lost and said so (exit 1, complete=false), the
 *     recorded sequence's gaps = frames lost + skipped + dropped by the transport
 *   - packets lost on purpose (serve --lost-packets): skip records only whole frames and counts
 *     the others as the source's failed frames; keep and fail tell the truth in the exit status
 *     and meta.json
 *   - SIGTERM to capture: the frames acquired are written, complete=false
 *   - SIGINT to serve: clean exit with its statistics; SIGTERM while it renders its cycle ends
 *     the start cleanly (exit 1, "interrupted while starting") */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "gige_peer.h"
#include "polarcam/gige_server.h"
#include "sim_frames.h"

static const char *polarcam;
static char base[64];
static sf_frames frames; /* sim:default?seed=2, frames 0..2 */
enum { CYCLE = 3 };

static pid_t start_serve(const char *lost, int *fd)
{
	char errp[160];
	snprintf(errp, sizeof errp, "%s/serve.err", base);
	char *args[] = {"default",    "--seed", "2",  "--cycle",
	                "3",          "--fps",  "10", lost ? "--lost-packets" : NULL,
	                (char *)lost, NULL};
	return serve_start(polarcam, args, errp, fd, NULL, 0);
}

/* polarcam capture aravis:127.0.0.1 -n N -o DIR EXTRA...: its exit status and JSON line. */
static int capture(const char *dir, const char *n, char *const extra[], json_t **rep)
{
	char errp[200];
	snprintf(errp, sizeof errp, "%s.err", dir);
	char *argv[32] = {(char *)polarcam,
	                  "capture",
	                  "aravis:127.0.0.1?packet_size=65000",
	                  "-n",
	                  (char *)n,
	                  "-o",
	                  (char *)dir,
	                  "--timeout-ms",
	                  "20000",
	                  "--json",
	                  NULL};
	int k = 10;
	for (int i = 0; extra && extra[i] && k < 31; i++)
		argv[k++] = extra[i];
	argv[k] = NULL;
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	if (pid < 0)
		return -1;
	static char out[1 << 16];
	wait_line(fd, "\n", EXIT_MS * 5, out, sizeof out);
	int st = pc_child_wait(pid, EXIT_MS * 5, NULL);
	close(fd);
	*rep = json_loads(out, JSON_DISABLE_EOF_CHECK, NULL);
	if (!*rep)
		fprintf(stderr, "capture %s: no report (exit %d)\n", dir, st);
	return st;
}

static json_int_t geti(json_t *o, const char *a, const char *b)
{
	json_t *x = json_object_get(o, a);
	return json_integer_value(b ? json_object_get(x, b) : x);
}

typedef struct rec_check {
	size_t frames, whole, flagged, bad;
	uint64_t seq_span; /* last - first + 1 */
} rec_check;

/* Every recorded frame: a whole one equals simulator frame (sequence - first + k) mod CYCLE,
 * with one k for the whole recording (the camera's first frames may have been skipped, so the
 * first recorded frame need not be the cycle's first: k is found from the first whole frame). */
static rec_check check_recording(const char *dir)
{
	rec_check c = {0};
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (!r)
		return c;
	c.frames = pc_recording_count(r);
	uint64_t s0 = c.frames ? pc_recording_get_frame(r, 0)->sequence : 0;
	int k = -1;
	for (size_t i = 0; i < c.frames; i++) {
		const pc_recording_frame *f = pc_recording_get_frame(r, i);
		c.seq_span = f->sequence - s0 + 1;
		if (f->status) {
			c.flagged++;
			continue;
		}
		pc_view v;
		if (pc_recording_read(r, i, &v)) {
			c.bad++;
			continue;
		}
		uint64_t sum = sf_checksum(&v);
		for (int j = 0; k < 0 && j < CYCLE; j++)
			if (sum == frames.sum[(f->sequence - s0 + (uint64_t)j) % CYCLE])
				k = j;
		if (k >= 0 && sum == frames.sum[(f->sequence - s0 + (uint64_t)k) % CYCLE])
			c.whole++;
		else
			c.bad++;
		pc_view_free(&v);
	}
	pc_recording_free(r);
	return c;
}

/* The command with a writer slower than the camera (400 ms per frame plus the PNG
 * itself, the camera at 10 fps). */
static void test_repro(void)
{
	char dir[160];
	snprintf(dir, sizeof dir, "%s/repro", base);
	char *extra[] = {"--write-delay-ms", "400", NULL};
	json_t *rep = NULL;
	int st = capture(dir, "10", extra, &rep);
	CHECK_EQ_INT(st, 0);
	CHECK(json_is_true(json_object_get(rep, "complete")));
	CHECK_EQ_INT(geti(rep, "frames", NULL), 10);
	CHECK_EQ_INT(geti(rep, "queue", "lost"), 0);
	CHECK(geti(rep, "queue", "peak") >= 2); /* frames waited in the queue, not in the camera */
	/* damaged frames (packets lost to the load) were skipped and counted, never recorded */
	CHECK_EQ_INT(geti(rep, "incomplete", "skipped"), geti(rep, "stats", "failed"));
	rec_check c = check_recording(dir);
	CHECK_EQ_INT(c.frames, 10);
	CHECK_EQ_INT(c.whole, 10);
	CHECK_EQ_INT(c.bad, 0);
	printf("repro: 10 whole frames, writer %.0f ms/frame, a frame every %.0f ms, queue peak "
	       "%lld, underruns %lld, missing packets %lld, damaged frames skipped %lld\n",
	       json_number_value(json_object_get(json_object_get(rep, "queue"), "write_ms_mean")),
	       json_number_value(json_object_get(json_object_get(rep, "queue"), "period_ms")),
	       (long long)geti(rep, "queue", "peak"), (long long)geti(rep, "stats", "underruns"),
	       (long long)geti(rep, "stats", "missing_packets"),
	       (long long)geti(rep, "incomplete", "skipped"));
	json_decref(rep);
}

/* Three frames of memory for that writer: frames lost, and the capture says so. */
static void test_queue_full(void)
{
	char dir[160];
	snprintf(dir, sizeof dir, "%s/full", base);
	char *extra[] = {"--write-delay-ms", "400", "--queue-mb", "30", "--store", "raw", NULL};
	json_t *rep = NULL;
	CHECK_EQ_INT(capture(dir, "10", extra, &rep), 1);
	CHECK(json_is_false(json_object_get(rep, "complete")));
	json_int_t lost = geti(rep, "queue", "lost");
	CHECK(lost > 0);
	rec_check c = check_recording(dir);
	CHECK_EQ_INT(c.frames, 10);
	CHECK_EQ_INT(c.bad, 0);
	/* every camera frame number between the first and the last recorded is accounted for */
	CHECK_EQ_INT((json_int_t)c.seq_span - 10,
	             lost + geti(rep, "incomplete", "skipped") + geti(rep, "stats", "dropped"));
	printf("queue full: %lld frames lost, said so (exit 1, complete=false)\n", (long long)lost);
	json_decref(rep);
}

/* Packets dropped by the camera on purpose: policies. */
static void test_lost_packets(void)
{
	int fd;
	pid_t srv = start_serve("0.004", &fd);
	CHECK(srv > 0);
	if (srv <= 0)
		return;
	static const char *const policy[] = {"skip", "keep", "fail"};
	for (int p = 0; p < 3; p++) {
		char dir[160];
		snprintf(dir, sizeof dir, "%s/lossy_%s", base, policy[p]);
		char *extra[] = {"--incomplete", (char *)policy[p], "--store", "raw", NULL};
		json_t *rep = NULL;
		int st = capture(dir, "4", extra, &rep);
		if (!rep && p == 2) {
			/* the first frame came damaged: no frame, so nothing is put in place */
			CHECK_EQ_INT(st, 1);
			CHECK(access(dir, F_OK) != 0);
			printf("lost packets, fail: exit 1 at the first frame, nothing written\n");
			continue;
		}
		rec_check c = check_recording(dir);
		json_int_t failed = geti(rep, "stats", "failed");
		CHECK_EQ_INT(c.bad, 0);
		CHECK_EQ_INT(c.whole + c.flagged, c.frames);
		/* the exit status, complete and the counts say the same thing */
		CHECK_EQ_INT(st == 0, json_is_true(json_object_get(rep, "complete")));
		if (p == 0) {
			CHECK_EQ_INT(c.flagged, 0);
			CHECK_EQ_INT(geti(rep, "incomplete", "skipped"), failed);
			if (st == 0)
				CHECK_EQ_INT(c.whole, 4);
		} else if (p == 1) {
			CHECK_EQ_INT(c.flagged, geti(rep, "incomplete", "kept"));
			CHECK_EQ_INT(st == 0, c.flagged == 0);
		} else {
			CHECK_EQ_INT(c.flagged, 0);
			CHECK_EQ_INT(st == 0, failed == 0);
		}
		printf("lost packets, %s: exit %d, %zu recorded (%zu flagged), %lld damaged frames "
		       "from the camera\n",
		       policy[p], st, c.frames, c.flagged, (long long)failed);
		json_decref(rep);
	}
	CHECK_EQ_INT(stop_server(srv, fd), 0);
}

/* SIGTERM to a capture behind its writer: what was acquired is written. */
static void test_capture_sigterm(void)
{
	char dir[160], errp[200];
	snprintf(dir, sizeof dir, "%s/term", base);
	snprintf(errp, sizeof errp, "%s.err", dir);
	char *argv[] = {(char *)polarcam,
	                "capture",
	                "aravis:127.0.0.1?packet_size=65000",
	                "-n",
	                "100000",
	                "-o",
	                dir,
	                "--write-delay-ms",
	                "300",
	                "--store",
	                "raw",
	                "--json",
	                NULL};
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	/* the second frame written (in the folder's temporary sibling until the end) */
	for (int t = 0; t < 600 && !sf_out_file_exists(dir, "raw_000001.raw"); t++) {
		struct timespec ts = {0, 100000000};
		nanosleep(&ts, NULL);
	}
	kill(pid, SIGTERM);
	static char out[1 << 16];
	wait_line(fd, "\n", EXIT_MS, out, sizeof out);
	CHECK_EQ_INT(pc_child_wait(pid, EXIT_MS, NULL), 1);
	close(fd);
	json_t *rep = json_loads(out, JSON_DISABLE_EOF_CHECK, NULL);
	const char *e = json_string_value(json_object_get(rep, "error"));
	unsigned long long acquired = 0;
	CHECK(e && sscanf(e, "interrupted after %llu of", &acquired) == 1);
	CHECK_EQ_INT(geti(rep, "frames", NULL), (json_int_t)acquired);
	rec_check c = check_recording(dir);
	CHECK_EQ_INT(c.frames, acquired);
	CHECK_EQ_INT(c.whole, acquired);
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (r)
		CHECK(!pc_recording_is_complete(r));
	pc_recording_free(r);
	json_decref(rep);
}

/* SIGTERM while serve renders its cycle: the start ends cleanly and quickly. */
static void test_serve_start_signal(void)
{
	char errp[160];
	snprintf(errp, sizeof errp, "%s/serve_long.err", base);
	setenv("POLARCAM_PROGRESS", "1", 1);
	char *argv[] = {(char *)polarcam, "serve", "default", "--cycle", "200", NULL};
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	unsetenv("POLARCAM_PROGRESS");
	bool rendering = false;
	for (int t = 0; t < 3000 && !rendering; t++) {
		char *txt = NULL;
		FILE *fp = fopen(errp, "r");
		if (fp) {
			static char buf[8192];
			size_t n = fread(buf, 1, sizeof buf - 1, fp);
			buf[n] = '\0';
			txt = buf;
			fclose(fp);
		}
		rendering = txt && strstr(txt, "cycle");
		struct timespec ts = {0, 100000000};
		nanosleep(&ts, NULL);
	}
	CHECK(rendering);
	CHECK_EQ_INT(pc_child_stop(pid, SIGTERM, EXIT_MS), 1);
	close(fd);
	FILE *fp = fopen(errp, "r");
	static char buf[8192];
	size_t n = fp ? fread(buf, 1, sizeof buf - 1, fp) : 0;
	buf[n] = '\0';
	if (fp)
		fclose(fp);
	CHECK(strstr(buf, "interrupted while starting") != NULL);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	if (!polarcam)
		SKIP("POLARCAM (the built CLI) not set: run through ctest");
	snprintf(base, sizeof base, "/tmp/pc_gigeload_XXXXXX");
	if (!mkdtemp(base))
		SKIP("no temporary directory");
	if (sf_regenerate("default", 2, CYCLE, &frames)) {
		CHECK(false);
		return pc_test_finish("gige_load");
	}
	int fd;
	char ready[1024];
	char errp[160];
	snprintf(errp, sizeof errp, "%s/serve.err", base);
	char *args[] = {"default", "--seed", "2", "--cycle", "3", "--fps", "10", NULL};
	pid_t srv = serve_start(polarcam, args, errp, &fd, ready, sizeof ready);
	CHECK(srv > 0);
	if (srv > 0) {
		CHECK(strstr(ready, "\"width\":2448") && strstr(ready, "\"height\":2048"));
		test_repro();
		test_queue_full();
		test_capture_sigterm();
		/* SIGINT: a clean stop with the statistics */
		int st = pc_child_stop(srv, SIGINT, EXIT_MS);
		CHECK_EQ_INT(st, 0);
		static char tail[4096];
		wait_line(fd, "\"served\"", 2000, tail, sizeof tail);
		CHECK(strstr(tail, "\"served\"") != NULL);
		close(fd);
	}
	test_lost_packets();
	test_serve_start_signal();
	sf_free(&frames);
	pc_devices_shutdown();
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
	if (!pc_test_failures && system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", base);
	return pc_test_finish("gige_load");
}
