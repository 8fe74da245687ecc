/* GigE Vision end to end against a real protocol peer: `polarcam serve` (Aravis's GigE Vision
 * camera, a separate process) on 127.0.0.1 and polarcam's aravis: source, inside a private
 * network namespace (tests/netns.sh). Frames come from a recording whose pixel values this test
 * computes independently, so every check compares against arithmetic, not against the code
 * under test:
 *   - the served frames equal the recording bit for bit (PolarizeMono12), looping
 *   - ROI at an odd offset, ReverseX, Mono12p packing and Mono8 (top bits) deliver the
 *     expected pixels and the expected mosaic phase
 *   - the compliance test passes on aravis:
 *   - 16-bit GigE Vision frame ids wrap without a gap in the sequence
 *   - `polarcam capture` records frames equal to the recording, with 0 missing packets
 *   - killing the server mid-capture ends capture with a clear error and intact files
 *   - packets lost on purpose surface as failed frames (compliance fault "corrupt")
 *   - a client that stops and restarts at once (two GVCP writes apart) gets frame 0 again
 *   - the recording's black level (37.5 DN, meta.json) is served as the GenICam BlackLevel
 *     (with AdcBitDepth 12): the aravis: source reports 37.5 DN for 12-bit formats and
 *     37.5/16 for Mono8, `capture` records it in meta.json and `capture --process` subtracts it
 *   - Aravis's stream thread runs SCHED_FIFO 10 when the process may ask for it (the kernel's
 *     answer read back per thread), none does with realtime=0 */
#include <arv.h>
#include <errno.h>
#include <fcntl.h>
#include <dirent.h>
#include <math.h>
#include <poll.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "gige_peer.h"
#include "out_peek.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

enum { W = 64, H = 48, NREC = 7 };
#define BLACK 37.5 /* DN, the recording's sensor offset: exact in a float register */

static const char *polarcam;
static char base[64];
static char rec_dir[128];

/* Independent model of the recording: a 12-bit value per (frame, x, y). */
static uint16_t value(unsigned k, unsigned x, unsigned y)
{
	return (uint16_t)((k * 577u + y * 61u + x * 29u + ((x ^ y) & 5u)) & 0xfffu);
}

/* IMX250MZR [90 45; 135 0] as angles, from the datasheet, independent of pc_mosaic. */
static int imx_angle(unsigned x, unsigned y)
{
	static const int a[2][2] = {{90, 45}, {135, 0}};
	return a[y & 1][x & 1];
}

static void make_recording(void)
{
	pc_recording_desc d;
	memset(&d, 0, sizeof d);
	d.format = PC_FMT_MONO12;
	d.width = d.sensor_width = W;
	d.height = d.sensor_height = H;
	d.polarized = true;
	d.mosaic = pc_mosaic_imx250mzr();
	d.source = "gige_e2e";
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_create(&r, rec_dir, &d, false), 0);
	if (r)
		CHECK_EQ_INT(
		    pc_recording_set_json(r, "extra", "{\"sensor\": {\"offset_dn\": 37.5}}"), 0);
	pc_frame f;
	memset(&f, 0, sizeof f);
	CHECK_EQ_INT(pc_view_alloc(&f.view, PC_FMT_MONO12, W, H, 64), 0);
	for (unsigned k = 0; k < NREC && r; k++) {
		for (unsigned y = 0; y < H; y++)
			for (unsigned x = 0; x < W; x++)
				PC_ROW(&f.view, uint16_t, y)[x] = value(k, x, y);
		f.meta.sequence = k;
		f.meta.timestamp_ns = 5000000ull * k;
		CHECK_EQ_INT(pc_recording_add(r, &f), 0);
	}
	if (r)
		CHECK_EQ_INT(pc_recording_finish(r, NULL), 0);
	pc_recording_free(r);
	pc_view_free(&f.view);
}

/* ---- processes (tests/gige_peer.h) ---- */

static pid_t start_serve_args(char *const args[], int *fd)
{
	char errp[160];
	snprintf(errp, sizeof errp, "%s/serve.err", base);
	return serve_start(polarcam, args, errp, fd, NULL, 0);
}

static pid_t start_server(const char *extra1, const char *extra2, int *fd)
{
	char src[256];
	snprintf(src, sizeof src, "file:%s?loop=1", rec_dir);
	char *args[] = {"--source", src, "--fps", "200", (char *)extra1, (char *)extra2, NULL};
	return start_serve_args(args, fd);
}

/* ---- in-process client checks ---- */

static pc_source *open_cam(const char *opts, const char *fmt_name, uint32_t ox, uint32_t oy,
                           uint32_t w, uint32_t h)
{
	char uri[128];
	snprintf(uri, sizeof uri, "aravis:127.0.0.1?packet_size=1500%s", opts);
	pc_source *s = NULL;
	int rc = pc_source_open(&s, uri);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		fprintf(stderr, "open %s: %s\n", uri, pc_error_detail());
		return NULL;
	}
	pc_source_format f;
	memset(&f, 0, sizeof f);
	snprintf(f.format_name, sizeof f.format_name, "%s", fmt_name);
	f.offset_x = ox;
	f.offset_y = oy;
	f.width = w;
	f.height = h;
	pc_format_verdict v;
	CHECK_EQ_INT(pc_source_try_format(s, &f, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	rc = pc_source_set_format(s, &f);
	CHECK_EQ_INT(rc, 0);
	if (!rc)
		rc = pc_source_buffers_alloc(s, 4);
	if (!rc)
		rc = pc_source_start(s);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		fprintf(stderr, "%s: %s\n", uri, pc_error_detail());
		pc_source_close(s);
		return NULL;
	}
	return s;
}

/* Streams n frames and compares them with the model: ROI (ox, oy, w, h) of the mirrored
 * (rev_x) recording, values shifted right by `shift`. Returns frames checked. */
static unsigned stream_and_compare(pc_source *s, unsigned n, uint32_t ox, uint32_t oy, bool rev_x,
                                   unsigned shift, uint64_t *first_seq, uint64_t *last_seq)
{
	/* Frame j of an acquisition is recording frame j mod NREC; j comes from the sequence
	 * (the camera's frame ids), so a frame lost under load shows as a gap that the statistics
	 * must count, never as wrong content. */
	unsigned mism = 0, got = 0, gaps = 0, mosaic_bad = 0, damaged = 0;
	uint64_t prev = 0;
	uint16_t *u = NULL;
	for (unsigned k = 0; k < n; k++) {
		pc_buffer *b = NULL;
		int rc = pc_source_dequeue(s, FRAME_MS, &b);
		CHECK_EQ_INT(rc, 0);
		if (rc) {
			fprintf(stderr, "dequeue %u: %s\n", k, pc_error_detail());
			break;
		}
		const pc_view *v = &b->frame.view;
		uint64_t seq = b->frame.meta.sequence;
		if (k == 0)
			*first_seq = seq;
		else if (seq != prev + 1)
			gaps += (unsigned)(seq - prev - 1);
		prev = seq;
		unsigned j = (unsigned)((seq - *first_seq) % NREC);
		if (b->frame.meta.status != 0) {
			/* packets lost under load: the frame is flagged, its content is not checked
			 */
			damaged++;
			got++;
			CHECK_EQ_INT(pc_source_requeue(s, b), 0);
			continue;
		}
		if (!u)
			u = malloc((size_t)v->width * v->height * 2);
		CHECK_EQ_INT(pc_view_to_u16(v, u, (size_t)v->width * 2), 0);
		for (uint32_t y = 0; y < v->height; y++)
			for (uint32_t x = 0; x < v->width; x++) {
				unsigned sx = rev_x ? W - 1 - (ox + x) : ox + x, sy = oy + y;
				mism += u[y * v->width + x] != (value(j, sx, sy) >> shift);
			}
		/* the mosaic the frame declares, against the datasheet layout moved by hand */
		for (uint32_t y = 0; y < 2; y++)
			for (uint32_t x = 0; x < 2; x++) {
				unsigned sx = rev_x ? W - 1 - (ox + x) : ox + x, sy = oy + y;
				int a = imx_angle(sx, sy);
				if (rev_x && (a == 45 || a == 135))
					a = 180 -
					    a; /* a mirror maps an analyser at θ to 180° − θ */
				mosaic_bad += (int)b->frame.mosaic.channel[y][x] * 45 != a;
			}
		got++;
		CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	}
	free(u);
	*last_seq = prev;
	CHECK_EQ_INT(mism, 0);
	CHECK_EQ_INT(mosaic_bad, 0);
	pc_source_stats st;
	CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
	CHECK_EQ_INT(st.dropped, gaps);
	CHECK_EQ_INT(st.failed, damaged);
	CHECK(damaged * 10 <= got); /* under heavy load a few frames may lose packets, not more */
	if (gaps || damaged)
		printf("note: %u frames damaged (load)\n", damaged);
	if (gaps)
		printf("note: %u frames lost (load): underruns %llu, missing packets %llu\n", gaps,
		       (unsigned long long)st.underruns, (unsigned long long)st.missing_packets);
	return got;
}

static void test_client(void)
{
	uint64_t s0, s1;
	/* full frame, the camera's default polarized format */
	pc_source *s = open_cam("", "PolarizeMono12", 0, 0, 0, 0);
	if (s) {
		pc_source_info info;
		CHECK_EQ_INT(pc_source_get_info(s, &info), 0);
		CHECK(!strcmp(info.vendor, "polarcam"));
		CHECK(info.black_level == BLACK); /* BlackLevel at AdcBitDepth 12 = the format's */
		pc_source_format f;
		pc_source_get_format(s, &f);
		CHECK(f.polarized);
		CHECK_EQ_INT(f.width, W);
		CHECK_EQ_INT(stream_and_compare(s, 10, 0, 0, false, 0, &s0, &s1), 10);
		pc_source_stats st;
		CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
		CHECK(st.has_packets);
		pc_source_close(s);
	}
	/* ROI at an odd offset, packed Mono12p */
	s = open_cam("", "Mono12p", 3, 1, 32, 20);
	if (s) {
		CHECK_EQ_INT(stream_and_compare(s, 4, 3, 1, false, 0, &s0, &s1), 4);
		pc_source_close(s);
	}
	/* ReverseX with an ROI: mirrored pixels and mosaic */
	s = open_cam("&reverse_x=1", "PolarizeMono16", 2, 3, 40, 30);
	if (s) {
		CHECK_EQ_INT(stream_and_compare(s, 4, 2, 3, true, 0, &s0, &s1), 4);
		pc_source_close(s);
	}
	/* Mono8 from the 12-bit sensor: the top 8 bits */
	s = open_cam("&reverse_x=0", "Mono8", 0, 0, 0, 0);
	if (s) {
		pc_source_info info;
		CHECK_EQ_INT(pc_source_get_info(s, &info), 0);
		CHECK(info.black_level == BLACK / 16); /* the top 8 of 12 bits */
		CHECK_EQ_INT(stream_and_compare(s, 3, 0, 0, false, 4, &s0, &s1), 3);
		pc_source_close(s);
	}
	/* 16-bit frame ids wrap (Aravis's camera model starts near 65400): a fast stream of
	 * small frames crosses 65535 without a gap */
	s = open_cam("", "PolarizeMono12", 0, 0, 16, 8);
	if (s) {
		double fps = 0;
		CHECK_EQ_INT(pc_source_control_set(s, PC_CTRL_FRAME_RATE_HZ, 400, &fps), 0);
		unsigned got = stream_and_compare(s, 200, 0, 0, false, 0, &s0, &s1);
		CHECK_EQ_INT(got, 200);
		CHECK(s1 > 65535); /* the unwrapped sequence went past the 16-bit range */
		pc_source_stats st;
		pc_source_get_stats(s, &st);
		CHECK_EQ_INT(s1 - s0, 199 + st.dropped); /* contiguous but for counted losses */
		pc_source_close(s);
	}
}

/* ---- real-time scheduling of the stream thread ---- */

/* Threads of this process under SCHED_FIFO at priority prio (read from the kernel per thread). */
static unsigned fifo_threads(int prio)
{
	unsigned n = 0;
	DIR *d = opendir("/proc/self/task");
	if (!d)
		return 0;
	struct dirent *e;
	while ((e = readdir(d))) {
		pid_t tid = (pid_t)atoi(e->d_name);
		if (tid <= 0)
			continue;
		struct sched_param sp;
		if (sched_getscheduler(tid) == SCHED_FIFO && sched_getparam(tid, &sp) == 0 &&
		    sp.sched_priority == prio)
			n++;
	}
	closedir(d);
	return n;
}

static void *idle_thread(void *arg)
{
	return arg;
}

/* Whether this process may make a thread SCHED_FIFO 10 (CAP_SYS_NICE or RLIMIT_RTPRIO): asked
 * on a thread created for the question. */
static bool may_realtime(void)
{
	pthread_attr_t at;
	pthread_attr_init(&at);
	struct sched_param sp = {.sched_priority = 10};
	pthread_attr_setinheritsched(&at, PTHREAD_EXPLICIT_SCHED);
	pthread_attr_setschedpolicy(&at, SCHED_FIFO);
	pthread_attr_setschedparam(&at, &sp);
	pthread_t t;
	bool ok = pthread_create(&t, &at, idle_thread, NULL) == 0;
	if (ok)
		pthread_join(t, NULL);
	pthread_attr_destroy(&at);
	return ok;
}

static void test_realtime(void)
{
	uint64_t s0, s1;
	bool may = may_realtime();
	CHECK_EQ_INT(fifo_threads(10), 0);
	/* the stream thread exists once frames arrive: its first act was the request */
	pc_source *s = open_cam("", "PolarizeMono12", 0, 0, 16, 8);
	if (s) {
		CHECK_EQ_INT(stream_and_compare(s, 3, 0, 0, false, 0, &s0, &s1), 3);
		CHECK_EQ_INT(fifo_threads(10), may ? 1 : 0);
		pc_source_close(s);
	}
	CHECK_EQ_INT(fifo_threads(10), 0); /* it ended with the stream */
	s = open_cam("&realtime=0", "PolarizeMono12", 0, 0, 16, 8);
	if (s) {
		CHECK_EQ_INT(stream_and_compare(s, 3, 0, 0, false, 0, &s0, &s1), 3);
		CHECK_EQ_INT(fifo_threads(10), 0);
		pc_source_close(s);
	}
	printf("realtime: %s\n", may ? "the stream thread ran SCHED_FIFO 10"
	                             : "not permitted here: checked that no thread asked for more");
}

/* ---- a client that stops and restarts at once ---- */

/* Which recording frame a PolarizeMono12 buffer of the full sensor holds, and whether it is
 * mirrored (ReverseX); -1 when it is none of them (a damaged frame). */
static int classify(ArvBuffer *b, bool *mirrored)
{
	size_t size = 0;
	const uint8_t *d = arv_buffer_get_data(b, &size);
	if (arv_buffer_get_status(b) != ARV_BUFFER_STATUS_SUCCESS || !d ||
	    size < (size_t)W * H * 2 || arv_buffer_get_image_width(b) != W ||
	    arv_buffer_get_image_height(b) != H)
		return -1;
	for (int m = 0; m < 2; m++)
		for (unsigned j = 0; j < NREC; j++) {
			bool same = true;
			for (unsigned y = 0; y < H && same; y++)
				for (unsigned x = 0; x < W && same; x++) {
					const uint8_t *p = d + ((size_t)y * W + x) * 2;
					unsigned sx = m ? W - 1 - x : x;
					same = (unsigned)(p[0] | p[1] << 8) == value(j, sx, y);
				}
			if (same) {
				*mirrored = m;
				return (int)j;
			}
		}
	return -1;
}

/* Pops the next frame: its recording index (-1 damaged), mirrored or not; -2 on a timeout. */
static int next_frame(ArvStream *st, bool *mirrored)
{
	ArvBuffer *b = arv_stream_timeout_pop_buffer(st, (guint64)FRAME_MS * 1000);
	if (!b)
		return -2;
	int j = classify(b, mirrored);
	arv_stream_push_buffer(st, b);
	return j;
}

/* The client writes AcquisitionStop, ReverseX and AcquisitionStart back to back (Aravis's own
 * API: polarcam's aravis: source drops its stream on stop and takes longer). Frames sent before
 * the stop are not mirrored, frames after the start are: the first mirrored frame must be
 * recording frame 0 and the next ones 1, 2, as `serve` promises for every acquisition. Rounds
 * alternate the mirror. A round where a damaged frame hides the boundary is repeated. */
static void test_fast_restart(void)
{
	GError *err = NULL;
	ArvCamera *cam = arv_camera_new("127.0.0.1", &err);
	ArvStream *st = NULL;
	int rounds = 0, inconclusive = 0, bad = 0;
	gint64 gap_max_us = 0;
	if (cam) {
		ArvDevice *dev = arv_camera_get_device(cam);
		arv_camera_gv_set_packet_size(cam, 1500, &err);
		if (!err)
			arv_camera_set_region(cam, 0, 0, W, H, &err);
		if (!err)
			arv_camera_set_pixel_format_from_string(cam, "PolarizeMono12", &err);
		if (!err)
			arv_device_set_boolean_feature_value(dev, "ReverseX", FALSE, &err);
		if (!err)
			arv_camera_set_frame_rate(cam, 100, &err);
		size_t payload = err ? 0 : arv_camera_get_payload(cam, &err);
		if (!err)
			st = arv_camera_create_stream(cam, NULL, NULL, &err);
		for (int i = 0; st && i < 8; i++)
			arv_stream_push_buffer(st, arv_buffer_new(payload, NULL));
		if (!err)
			arv_camera_start_acquisition(cam, &err);
		bool mir = false;
		for (int r = 1; !err && rounds < 6 && r <= 10; r++) {
			bool old = (r - 1) & 1, now = r & 1;
			/* the acquisition runs: some frames, so the source is past frame 0 */
			int good = 0, j = 0;
			for (int n = 0; good < 3 && n < 30 && j != -2; n++)
				if ((j = next_frame(st, &mir)) >= 0 && mir == old)
					good++;
			CHECK(good == 3);
			if (good < 3)
				break;
			gint64 t0 = g_get_monotonic_time();
			arv_camera_stop_acquisition(cam, &err);
			if (!err)
				arv_device_set_boolean_feature_value(dev, "ReverseX", now, &err);
			if (!err)
				arv_camera_start_acquisition(cam, &err);
			gint64 gap = g_get_monotonic_time() - t0;
			gap_max_us = gap > gap_max_us ? gap : gap_max_us;
			/* frames still on the way from before the stop, then the new acquisition */
			int skipped = 0;
			bool damaged = false;
			while (!err && skipped < 10) {
				j = next_frame(st, &mir);
				if (j >= 0 && mir == now)
					break;
				damaged |= j == -1;
				if (j == -2)
					break;
				skipped++;
			}
			CHECK(j != -2 && skipped < 10);
			if (j < 0 || skipped >= 10)
				break;
			if (damaged) {
				inconclusive++;
				continue;
			}
			int seq[3] = {j, next_frame(st, &mir), -3};
			seq[2] = mir == now ? next_frame(st, &mir) : -3;
			if (seq[0] != 0 || seq[1] != 1 || seq[2] != 2 || mir != now) {
				bad++;
				fprintf(
				    stderr,
				    "restart %d: the new acquisition began with recording frames "
				    "%d %d %d, not 0 1 2\n",
				    r, seq[0], seq[1], seq[2]);
			}
			rounds++;
		}
		if (err)
			fprintf(stderr, "fast restart: %s\n", err->message);
		CHECK(err == NULL);
		g_clear_error(&err);
		arv_camera_stop_acquisition(cam, &err);
		g_clear_error(&err);
		arv_device_set_boolean_feature_value(dev, "ReverseX", FALSE, &err);
		g_clear_error(&err);
	} else {
		fprintf(stderr, "arv_camera_new: %s\n", err ? err->message : "?");
		g_clear_error(&err);
	}
	if (st)
		g_object_unref(st);
	if (cam)
		g_object_unref(cam);
	CHECK(cam != NULL);
	CHECK(rounds >= 6);
	CHECK_EQ_INT(bad, 0);
	printf("fast restart: %d acquisitions restarted within %.2f ms (stop, ReverseX, start), "
	       "%d began at frame 0; %d rounds repeated (a damaged frame at the boundary)\n",
	       rounds, (double)gap_max_us / 1e3, rounds - bad, inconclusive);
}

static void log_fail(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	(void)ctx;
	if (r == PC_CHECK_FAIL)
		fprintf(stderr, "compliance FAIL: %s: %s\n", check, detail);
}

static void test_compliance(pc_fault_kind fault)
{
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.log = log_fail;
	o.expect_fault = fault;
	o.frames = fault == PC_FAULT_NONE ? 8 : 40;
	o.timeout_ms = FRAME_MS;
	pc_compliance_result res;
	int rc = pc_source_compliance("aravis:127.0.0.1?packet_size=1500", &o, &res);
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(res.failed, 0);
	CHECK(res.passed >= (fault == PC_FAULT_NONE ? 40u : 10u));
}

/* ---- polarcam capture ---- */

static int run_capture_x(const char *dir, const char *n, const char *extra, char *out, size_t size,
                         pid_t *pid_out, int *fd_out)
{
	char errp[160];
	snprintf(errp, sizeof errp, "%s/capture.err", base);
	/* the camera keeps the settings of earlier clients: ask for what the model expects */
	char *argv[] = {(char *)polarcam,
	                "capture",
	                "aravis:127.0.0.1?packet_size=1500",
	                "-n",
	                (char *)n,
	                "-o",
	                (char *)dir,
	                "--timeout-ms",
	                "5000",
	                "--roi",
	                "0,0,64,48",
	                "--format",
	                "PolarizeMono12",
	                "--fps",
	                "50",
	                "--json",
	                (char *)extra,
	                NULL};
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	if (pid_out) { /* asynchronous */
		*pid_out = pid;
		*fd_out = fd;
		return 0;
	}
	if (pid < 0)
		return 127;
	wait_line(fd, "\n", EXIT_MS, out, size);
	int st = pc_child_wait(pid, EXIT_MS, NULL);
	close(fd);
	return st;
}

static int run_capture(const char *dir, const char *n, char *out, size_t size, pid_t *pid_out,
                       int *fd_out)
{
	return run_capture_x(dir, n, NULL, out, size, pid_out, fd_out);
}

/* Every frame listed in the recording is readable and equals the model. */
static size_t check_recording(const char *dir, bool want_complete)
{
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (!r)
		return 0;
	CHECK_EQ_INT(pc_recording_is_complete(r), want_complete);
	size_t n = pc_recording_count(r), bad = 0;
	uint64_t seq0 = n ? pc_recording_get_frame(r, 0)->sequence : 0;
	for (size_t k = 0; k < n; k++) {
		unsigned j = (unsigned)((pc_recording_get_frame(r, k)->sequence - seq0) % NREC);
		pc_view v;
		int rc = pc_recording_read(r, k, &v);
		CHECK_EQ_INT(rc, 0);
		if (rc)
			continue;
		for (unsigned y = 0; y < H; y++)
			for (unsigned x = 0; x < W; x++)
				bad += PC_ROW(&v, uint16_t, y)[x] != value(j, x, y);
		pc_view_free(&v);
	}
	CHECK_EQ_INT(bad, 0);
	pc_recording_free(r);
	return n;
}

static void test_capture(void)
{
	char dir[160], out[4096];
	snprintf(dir, sizeof dir, "%s/cap", base);
	int st = run_capture(dir, "9", out, sizeof out, NULL, NULL);
	CHECK_EQ_INT(st, 0);
	CHECK(strstr(out, "\"frames\":9") != NULL);
	CHECK(strstr(out, "\"missing_packets\":0") != NULL);
	CHECK(strstr(out, "\"failed\":0") != NULL);
	CHECK_EQ_INT(check_recording(dir, true), 9);
	/* the camera's black level, recorded for whoever processes the recording later */
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (r)
		CHECK(pc_recording_black_level(r) == BLACK);
	pc_recording_free(r);
	/* and subtracted by the live pipeline without being given */
	snprintf(dir, sizeof dir, "%s/cap_process", base);
	st = run_capture_x(dir, "3", "--process", out, sizeof out, NULL, NULL);
	CHECK_EQ_INT(st, 0);
	CHECK(strstr(out, "\"black_level\":37.5") != NULL);
}

static void test_kill(pid_t server, int server_fd)
{
	char dir[160], out[4096];
	snprintf(dir, sizeof dir, "%s/cap_killed", base);
	pid_t cap;
	int fd;
	run_capture(dir, "100000", out, sizeof out, &cap, &fd);
	/* let it record some frames (50 fps), then kill the camera */
	/* (written in the folder's temporary sibling until the end) */
	for (int t = 0; t < 300 && !sf_out_file_exists(dir, "raw_000007.png"); t++) {
		struct timespec ts = {0, 100000000};
		nanosleep(&ts, NULL);
	}
	pc_child_stop(server, SIGKILL, EXIT_MS);
	close(server_fd);
	wait_line(fd, "\n", EXIT_MS, out, sizeof out);
	int st = pc_child_wait(cap, EXIT_MS, NULL);
	close(fd);
	CHECK_EQ_INT(st, 1);
	CHECK(strstr(out, "disappeared") != NULL);
	char errp[160], err[2048] = "";
	snprintf(errp, sizeof errp, "%s/capture.err", base);
	FILE *fp = fopen(errp, "r");
	if (fp) {
		size_t n = fread(err, 1, sizeof err - 1, fp);
		err[n] = '\0';
		fclose(fp);
	}
	CHECK(strstr(err, "disappeared") && strstr(err, "intact"));
	size_t n = check_recording(dir, false);
	CHECK(n > 5);
	printf("killed the server after %zu recorded frames: %s", n, err);
}

/* serve SCENE --seed S, captured over GigE Vision, equals render SCENE --seed S bit for bit */
static void test_serve_equals_render(void)
{
	const char *src = getenv("PC_SOURCE_DIR");
	if (!src) {
		fprintf(stderr, "PC_SOURCE_DIR not set: skipping the render comparison\n");
		return;
	}
	char scene[512], rdir[160], cdir[160], out[4096];
	snprintf(scene, sizeof scene, "%s/scenes/ideal_small.json", src);
	snprintf(rdir, sizeof rdir, "%s/render", base);
	snprintf(cdir, sizeof cdir, "%s/cap_sim", base);
	char *rargv[] = {(char *)polarcam, "render", scene, "-o", rdir, "-n", "4", "-s", "7",
	                 "--no-truth",     NULL};
	int devnull = open("/dev/null", O_WRONLY);
	CHECK_EQ_INT(pc_child_wait(pc_child_spawn(rargv, devnull, NULL), EXIT_MS, NULL), 0);
	if (devnull >= 0)
		close(devnull);
	int fd;
	char *args[] = {scene, "--seed", "7", NULL};
	pid_t srv = start_serve_args(args, &fd);
	CHECK(srv > 0);
	if (srv <= 0)
		return;
	char errp[160];
	snprintf(errp, sizeof errp, "%s/capture.err", base);
	char *argv[] = {(char *)polarcam,
	                "capture",
	                "aravis:127.0.0.1?packet_size=65000",
	                "-n",
	                "4",
	                "-o",
	                cdir,
	                "--json",
	                NULL};
	int cfd;
	pid_t cap = spawn(argv, &cfd, errp);
	CHECK(cap > 0);
	if (cap <= 0) {
		stop_server(srv, fd);
		return;
	}
	wait_line(cfd, "\n", EXIT_MS, out, sizeof out);
	CHECK_EQ_INT(pc_child_wait(cap, EXIT_MS, NULL), 0);
	close(cfd);
	CHECK(strstr(out, "\"missing_packets\":0") != NULL);
	/* the camera's exposure and gain in every frame's metadata: at the scene's settings, then
	 * at a gain asked of the camera (read back from its Gain feature) */
	char gdir[160];
	snprintf(gdir, sizeof gdir, "%s/cap_gain", base);
	char *gargv[] = {(char *)polarcam,
	                 "capture",
	                 "aravis:127.0.0.1?packet_size=65000",
	                 "-n",
	                 "2",
	                 "-o",
	                 gdir,
	                 "--gain",
	                 "6",
	                 "--json",
	                 NULL};
	cap = spawn(gargv, &cfd, errp);
	CHECK(cap > 0);
	if (cap > 0) {
		wait_line(cfd, "\n", EXIT_MS, out, sizeof out);
		CHECK_EQ_INT(pc_child_wait(cap, EXIT_MS, NULL), 0);
		close(cfd);
	}
	/* a camera that sets its gain itself (GainAuto Continuous, set here over GenICam): its
	 * frames say the gain is unknown (null), not the value read at the start; a gain asked
	 * for turns the adjustment off */
	char adir[160], a6dir[160];
	snprintf(adir, sizeof adir, "%s/cap_auto", base);
	snprintf(a6dir, sizeof a6dir, "%s/cap_auto6", base);
	ArvAuto auto_after = ARV_AUTO_CONTINUOUS;
	{
		GError *err = NULL;
		ArvCamera *cam = arv_camera_new("127.0.0.1", &err);
		if (cam)
			arv_camera_set_gain_auto(cam, ARV_AUTO_CONTINUOUS, &err);
		CHECK(cam && !err && arv_camera_get_gain_auto(cam, NULL) == ARV_AUTO_CONTINUOUS);
		g_clear_error(&err);
		g_clear_object(&cam);
		char *aargv[] = {(char *)polarcam,
		                 "capture",
		                 "aravis:127.0.0.1?packet_size=65000",
		                 "-n",
		                 "2",
		                 "-o",
		                 adir,
		                 "--json",
		                 NULL};
		char *a6argv[] = {(char *)polarcam,
		                  "capture",
		                  "aravis:127.0.0.1?packet_size=65000",
		                  "-n",
		                  "2",
		                  "-o",
		                  a6dir,
		                  "--gain",
		                  "6",
		                  "--json",
		                  NULL};
		char **runs[2] = {aargv, a6argv};
		for (int k = 0; k < 2; k++) {
			cap = spawn(runs[k], &cfd, errp);
			CHECK(cap > 0);
			if (cap > 0) {
				wait_line(cfd, "\n", EXIT_MS, out, sizeof out);
				CHECK_EQ_INT(pc_child_wait(cap, EXIT_MS, NULL), 0);
				close(cfd);
			}
		}
		if ((cam = arv_camera_new("127.0.0.1", &err)))
			auto_after = arv_camera_get_gain_auto(cam, &err);
		CHECK(cam && !err);
		g_clear_error(&err);
		g_clear_object(&cam);
	}
	CHECK_EQ_INT(stop_server(srv, fd), 0);
	{
		pc_recording *ra = NULL, *r6 = NULL;
		CHECK_EQ_INT(pc_recording_open(&ra, adir), 0);
		CHECK_EQ_INT(pc_recording_open(&r6, a6dir), 0);
		if (ra && r6 && pc_recording_count(ra) && pc_recording_count(r6)) {
			const pc_recording_frame *fa = pc_recording_get_frame(ra, 0),
			                         *f6 = pc_recording_get_frame(r6, 1);
			printf("GainAuto Continuous: the frames' gain %g dB (unknown), exposure %g "
			       "us; "
			       "asked for 6 dB: %g dB, GainAuto then %s\n",
			       fa->gain_db, fa->exposure_us, f6->gain_db,
			       auto_after == ARV_AUTO_OFF ? "Off" : "not Off");
			CHECK(isnan(fa->gain_db) && isfinite(fa->exposure_us));
			CHECK_NEAR(f6->gain_db, 6, 0);
			CHECK(auto_after == ARV_AUTO_OFF);
		}
		pc_recording_free(ra);
		pc_recording_free(r6);
	}
	{
		pc_recording *rr = NULL, *cc = NULL, *gg = NULL;
		CHECK_EQ_INT(pc_recording_open(&rr, rdir), 0);
		CHECK_EQ_INT(pc_recording_open(&cc, cdir), 0);
		CHECK_EQ_INT(pc_recording_open(&gg, gdir), 0);
		if (rr && cc && gg && pc_recording_count(cc) && pc_recording_count(gg)) {
			const pc_recording_frame *fr = pc_recording_get_frame(rr, 0),
			                         *fc = pc_recording_get_frame(cc, 0),
			                         *fg = pc_recording_get_frame(gg, 1);
			printf(
			    "frame metadata over GigE Vision: exposure %g us, gain %g dB (render: "
			    "%g us, %g dB); asked for 6 dB: %g dB\n",
			    fc->exposure_us, fc->gain_db, fr->exposure_us, fr->gain_db,
			    fg->gain_db);
			CHECK_NEAR(fc->exposure_us, round(fr->exposure_us), 0);
			CHECK_NEAR(fc->gain_db, fr->gain_db, 0);
			CHECK_NEAR(fg->gain_db, 6, 0);
		}
		pc_recording_free(rr);
		pc_recording_free(cc);
		pc_recording_free(gg);
	}
	pc_recording *r = NULL, *c = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, rdir), 0);
	CHECK_EQ_INT(pc_recording_open(&c, cdir), 0);
	if (r && c) {
		CHECK_EQ_INT(pc_recording_count(c), 4);
		for (size_t k = 0; k < 4 && k < pc_recording_count(c); k++) {
			pc_view a, b;
			CHECK_EQ_INT(pc_recording_read(r, k, &a), 0);
			CHECK_EQ_INT(pc_recording_read(c, k, &b), 0);
			CHECK_EQ_INT(a.format, b.format);
			CHECK_EQ_INT(a.width, b.width);
			size_t diff = 0;
			for (uint32_t y = 0; y < a.height && a.width == b.width; y++)
				diff += memcmp(PC_ROW(&a, uint8_t, y), PC_ROW(&b, uint8_t, y),
				               (size_t)a.width * 2) != 0;
			CHECK_EQ_INT(diff, 0);
			pc_view_free(&a);
			pc_view_free(&b);
		}
	}
	pc_recording_free(r);
	pc_recording_free(c);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	if (!polarcam)
		SKIP("POLARCAM (the built CLI) not set: run through ctest");
	if (!pc_test_tmpdir(base, sizeof base, "pc_gige"))
		SKIP("no temporary directory");
	snprintf(rec_dir, sizeof rec_dir, "%s/rec", base);
	make_recording();
	test_serve_equals_render();

	int fd;
	pid_t srv = start_server(NULL, NULL, &fd);
	CHECK(srv > 0);
	if (srv > 0) {
		test_client();
		test_realtime();
		test_fast_restart();
		test_compliance(PC_FAULT_NONE);
		test_capture();
		test_kill(srv, fd);
	}
	/* packets lost on purpose: frames arrive flagged incomplete and are counted */
	srv = start_server("--lost-packets", "0.05", &fd);
	CHECK(srv > 0);
	if (srv > 0) {
		test_compliance(PC_FAULT_CORRUPT);
		CHECK_EQ_INT(stop_server(srv, fd), 0);
	}
	pc_devices_shutdown();
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", base);
	return pc_test_finish("gige_e2e");
}
