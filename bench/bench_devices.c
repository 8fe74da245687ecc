/* polarcam bench devices: GigE Vision serve -> capture over loopback at 2448x2048 Mono16 and
 * capture -> pipeline live, inside a private network namespace (the benchmark re-executes
 * itself under `unshare -n` with only loopback up, so nothing it sends leaves the machine).
 *
 * Phases, all measured in the same run (ratios against the baselines of this run):
 *   transport   the camera sends pre-rendered simulator frames (copy only) as fast as the
 *               camera model allows (1000 fps requested, unpaced): frames/s, MB/s; it saturates
 *               the path on purpose, so packets go missing there by design
 *   serve30     the same at the goal rate (30 fps): achieved rate / goal, missing packets
 *   live        serve with frames rendered while streaming (the simulator's sensor chain per
 *               frame, render-ahead): achieved rate, next to the simulator's own frame rate
 *   pipeline    capture -> demosaic + Stokes (pc_stokes_from_raw) per frame at 30 fps: per
 *               frame processing time against the frame period, drops, and the latency trend
 *               (a growing queue shows as latency rising frame after frame)
 *   alone       the pipeline on one frame without transport (its baseline)
 *   disk-png, disk-npy, disk-raw
 *               capture to disk (pc_capture: acquisition, the bounded queue, the writer
 *               thread) of --disk-frames frames at 30 fps in each store: the sustained rate
 *               is what the writer can keep up with indefinitely, 1 / (mean seconds per frame
 *               written, fsync included); the recorded rate is frames / (capture time, the
 *               queue's drain included); ratios against the 30 fps goal and against raw
 *               (the cheapest store) of this run
 *
 * Frame rates are steady-state rates: (frames received - 1) / (time the last one was received -
 * time the first one was received), both taken when the client's dequeue returns. The start of
 * a phase (the camera starting, the first frame's latency) is outside that window; counting it,
 * as frames / phase length did, put the 30 fps phases a few percent under 30 depending on how
 * long the start took, not on how fast frames flowed. */
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include "bench.h"
#include "polarcam/capture.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/parallel.h"
#include "polarcam/source.h"
#include "polarcam/stream.h"

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

typedef struct bench_opts {
	const char *scene;
	uint64_t packet_size;
	double seconds;
	unsigned cycle;
	const char *format;
	bool quick, json;
	pc_demosaic_method method;
	const char *method_name;
	const char *dir;      /* where the disk phases write (NULL: a temporary directory) */
	unsigned disk_frames; /* frames per disk phase */
} bench_opts;

typedef struct disk_result {
	const char *store;
	uint64_t frames, lost, skipped, file_bytes;
	double seconds, write_ms_mean, write_ms_max, sustained_fps, recorded_fps;
	long long peak;
	bool complete;
	int error;
	char errmsg[256];
} disk_result;

typedef struct phase_result {
	double fps, mbps, seconds;
	uint64_t frames, failed, dropped, underruns, missing_packets, resent_packets;
	double proc_ms_mean, proc_ms_max;
	uint64_t proc_n;
	double lat_first_ms, lat_last_ms, lat_slope_ms_per_s;
	int error;
	char errmsg[256];
} phase_result;

static uint64_t realtime_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_REALTIME, &ts);
	return (uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec;
}

/* Least-squares slope of y over x. */
static double slope(const double *x, const double *y, size_t n)
{
	if (n < 3)
		return 0;
	double mx = 0, my = 0, sxx = 0, sxy = 0;
	for (size_t i = 0; i < n; i++) {
		mx += x[i];
		my += y[i];
	}
	mx /= (double)n;
	my /= (double)n;
	for (size_t i = 0; i < n; i++) {
		sxx += (x[i] - mx) * (x[i] - mx);
		sxy += (x[i] - mx) * (y[i] - my);
	}
	return sxx > 0 ? sxy / sxx : 0;
}

/* Streams from the camera on 127.0.0.1 for `seconds` at `fps`; with process, every frame goes
 * through the pipeline. */
static void stream_phase(const bench_opts *o, double fps, bool process, phase_result *r)
{
	memset(r, 0, sizeof *r);
	pc_stream_request sa;
	pc_stream_request_init(&sa);
	char uri[128];
	snprintf(uri, sizeof uri, "aravis:127.0.0.1?packet_size=%llu",
	         (unsigned long long)o->packet_size);
	sa.uri = uri;
	sa.format = o->format;
	sa.fps = fps;
	sa.buffers = 16;
	const int timeout_ms = 5000;
	pc_source *s = NULL;
	pc_stokes_stream *lv = NULL;
	int rc = pc_stokes_stream_new(o->method, &lv);
	if (!rc)
		rc = pc_stream_open(&sa, &s);
	if (!rc)
		rc = pc_source_start(s);
	size_t cap = (size_t)(fps * o->seconds * 1.5) + 64;
	double *lt = malloc(cap * sizeof *lt), *lx = malloc(cap * sizeof *lx);
	size_t nl = 0;
	double t0 = bench_now(), proc_sum = 0, t_first = 0, t_last = 0;
	pc_source_format f;
	memset(&f, 0, sizeof f);
	if (s)
		pc_source_get_format(s, &f);
	while (!rc && bench_now() - t0 < o->seconds) {
		pc_buffer *b = NULL;
		rc = pc_source_dequeue(s, timeout_ms, &b);
		if (rc)
			break;
		t_last = bench_now();
		if (r->frames == 0)
			t_first = t_last;
		/* the first half second warms up (allocations, caches): not in the statistics */
		bool warm = bench_now() - t0 >= 0.5;
		if (process) {
			rc = pc_stokes_stream_process(lv, &b->frame);
			double ps = pc_stokes_stream_seconds(lv);
			if (warm) {
				proc_sum += ps;
				r->proc_n++;
				if (ps * 1e3 > r->proc_ms_max)
					r->proc_ms_max = ps * 1e3;
			}
		}
		if (warm && nl < cap && lt && lx) {
			lt[nl] = bench_now() - t0;
			lx[nl] =
			    (double)((int64_t)(realtime_ns() - b->frame.meta.timestamp_ns)) / 1e6;
			nl++;
		}
		r->frames++;
		int rc2 = pc_source_requeue(s, b);
		if (!rc)
			rc = rc2;
	}
	r->seconds = t_last - t_first; /* the window of the rate: first to last frame */
	if (rc) {
		r->error = rc;
		snprintf(r->errmsg, sizeof r->errmsg, "%s", pc_error_detail());
	}
	if (s && pc_source_get_state(s) == PC_SOURCE_STREAMING)
		pc_source_stop(s);
	if (s) {
		pc_source_stats st;
		pc_source_get_stats(s, &st);
		r->failed = st.failed;
		r->dropped = st.dropped;
		r->underruns = st.underruns;
		r->missing_packets = st.missing_packets;
		r->resent_packets = st.resent_packets;
	}
	r->fps = r->frames >= 2 && r->seconds > 0 ? (double)(r->frames - 1) / r->seconds : 0;
	r->mbps = r->fps * (double)f.frame_bytes / 1e6;
	if (process && r->proc_n)
		r->proc_ms_mean = 1e3 * proc_sum / (double)r->proc_n;
	if (nl > 2) {
		/* medians of the first and last tenth, and the trend over the whole phase */
		size_t k = nl / 10 ? nl / 10 : 1;
		double a = 0, z = 0;
		for (size_t i = 0; i < k; i++) {
			a += lx[i];
			z += lx[nl - 1 - i];
		}
		r->lat_first_ms = a / (double)k;
		r->lat_last_ms = z / (double)k;
		r->lat_slope_ms_per_s = slope(lt, lx, nl);
	}
	free(lt);
	free(lx);
	pc_stokes_stream_free(lv);
	pc_source_close(s);
}

static json_t *phase_json(const char *name, double goal, const phase_result *r)
{
	json_t *j = json_object();
	json_object_set_new(j, "phase", json_string(name));
	json_object_set_new(j, "goal_fps", goal > 0 ? bench_json_real(goal) : json_null());
	json_object_set_new(j, "fps", bench_json_real(r->fps));
	json_object_set_new(j, "ratio_to_goal",
	                    goal > 0 ? bench_json_real(r->fps / goal) : json_null());
	json_object_set_new(j, "mb_per_s", bench_json_real(r->mbps));
	json_object_set_new(j, "frames", json_integer((json_int_t)r->frames));
	json_object_set_new(j, "seconds", bench_json_real(r->seconds));
	json_object_set_new(j, "failed", json_integer((json_int_t)r->failed));
	json_object_set_new(j, "dropped", json_integer((json_int_t)r->dropped));
	json_object_set_new(j, "underruns", json_integer((json_int_t)r->underruns));
	json_object_set_new(j, "missing_packets", json_integer((json_int_t)r->missing_packets));
	json_object_set_new(j, "resent_packets", json_integer((json_int_t)r->resent_packets));
	if (r->proc_ms_mean > 0) {
		json_object_set_new(j, "process_ms_mean", bench_json_real(r->proc_ms_mean));
		json_object_set_new(j, "process_ms_max", bench_json_real(r->proc_ms_max));
		json_object_set_new(j, "latency_first_ms", bench_json_real(r->lat_first_ms));
		json_object_set_new(j, "latency_last_ms", bench_json_real(r->lat_last_ms));
		json_object_set_new(j, "latency_trend_ms_per_s",
		                    bench_json_real(r->lat_slope_ms_per_s));
	}
	json_object_set_new(j, "error", r->error ? json_string(r->errmsg) : json_null());
	return j;
}

static void print_phase(const bench_opts *o, const char *name, double goal, const phase_result *r)
{
	if (o->json) {
		host->print_json(phase_json(name, goal, r));
		return;
	}
	printf("%-10s %8.1f fps", name, r->fps);
	if (goal > 0)
		printf(" (%5.2fx the %g fps goal)", r->fps / goal, goal);
	else
		printf("                        ");
	printf(" %7.0f MB/s  frames %-5llu missing packets %llu%s, dropped %llu, failed %llu, "
	       "underruns %llu",
	       r->mbps, (unsigned long long)r->frames, (unsigned long long)r->missing_packets,
	       goal > 0 ? "" : " (unpaced: expected)", (unsigned long long)r->dropped,
	       (unsigned long long)r->failed, (unsigned long long)r->underruns);
	if (r->proc_ms_mean > 0)
		printf("\n           pipeline %.1f ms/frame (max %.1f) = %.2f of the frame period; "
		       "latency %.1f -> %.1f ms (trend %+.2f ms/s)",
		       r->proc_ms_mean, r->proc_ms_max, r->proc_ms_mean * goal / 1e3,
		       r->lat_first_ms, r->lat_last_ms, r->lat_slope_ms_per_s);
	if (r->error)
		printf("\n           stopped: %s", r->errmsg);
	printf("\n");
	fflush(stdout);
}

/* The file system a directory is on, by statfs magic (the common ones). */
static const char *fs_name(const char *dir)
{
	struct statfs sf;
	if (statfs(dir, &sf) != 0)
		return "?";
	switch ((unsigned long)sf.f_type) {
	case 0xEF53:
		return "ext4";
	case 0x58465342:
		return "xfs";
	case 0x9123683E:
		return "btrfs";
	case 0x01021994:
		return "tmpfs (memory)";
	case 0x6969:
		return "nfs";
	case 0x794c7630:
		return "overlayfs";
	default:
		return "other";
	}
}

/* pc_capture from the camera at 30 fps into dir/STORE, then the files removed. */
static void disk_phase(const bench_opts *o, const char *dir, pc_recording_store store,
                       disk_result *r)
{
	memset(r, 0, sizeof *r);
	r->store = pc_recording_store_name(store);
	char uri[128], sub[1200];
	snprintf(uri, sizeof uri, "aravis:127.0.0.1?packet_size=%llu",
	         (unsigned long long)o->packet_size);
	snprintf(sub, sizeof sub, "%s/disk-%s", dir, r->store);
	pc_capture_opts co;
	memset(&co, 0, sizeof co);
	pc_stream_request_init(&co.stream);
	co.stream.uri = uri;
	co.stream.format = o->format;
	co.stream.fps = 30;
	co.stream.buffers = 16;
	co.frames = o->disk_frames;
	co.dir = sub;
	co.overwrite = true;
	co.timeout_ms = 5000;
	co.store = store;
	co.progress = host->progress;
	pc_capture_report rep;
	int rc = pc_capture(&co, &rep);
	if (host->progress_end)
		host->progress_end(host->progress.user);
	if (rc) {
		r->error = rc;
		snprintf(r->errmsg, sizeof r->errmsg, "%s", pc_error_detail());
		return;
	}
	json_t *j = json_loads(rep.json, 0, NULL);
	json_t *q = json_object_get(j, "queue");
	r->frames = rep.frames;
	r->lost = rep.lost;
	r->skipped = rep.skipped;
	r->complete = rep.complete;
	r->seconds = json_number_value(json_object_get(j, "seconds"));
	r->write_ms_mean = json_number_value(json_object_get(q, "write_ms_mean"));
	r->write_ms_max = json_number_value(json_object_get(q, "write_ms_max"));
	r->peak = (long long)json_integer_value(json_object_get(q, "peak"));
	r->sustained_fps = r->write_ms_mean > 0 ? 1e3 / r->write_ms_mean : 0;
	r->recorded_fps = r->seconds > 0 ? (double)r->frames / r->seconds : 0;
	if (rep.error) {
		r->error = rep.error;
		snprintf(r->errmsg, sizeof r->errmsg, "%.255s", rep.message);
	}
	char f[1300];
	struct stat st;
	snprintf(f, sizeof f, "%s/raw_000000.%s", sub, r->store);
	if (stat(f, &st) == 0)
		r->file_bytes = (uint64_t)st.st_size;
	json_decref(j);
	pc_capture_report_free(&rep);
	/* the frames are not kept: a benchmark leaves nothing behind */
	for (uint64_t k = 0; k < r->frames + r->lost + 16; k++) {
		snprintf(f, sizeof f, "%s/raw_%06llu.%s", sub, (unsigned long long)k, r->store);
		unlink(f);
	}
	snprintf(f, sizeof f, "%s/meta.json", sub);
	unlink(f);
	rmdir(sub);
}

static void print_disk(const bench_opts *o, const disk_result *r, double raw_fps)
{
	double ratio = raw_fps > 0 ? r->sustained_fps / raw_fps : NAN;
	if (o->json) {
		json_t *j = json_object();
		char name[32];
		snprintf(name, sizeof name, "disk-%s", r->store);
		json_object_set_new(j, "phase", json_string(name));
		json_object_set_new(j, "goal_fps", json_real(30));
		json_object_set_new(j, "sustained_fps", bench_json_real(r->sustained_fps));
		json_object_set_new(j, "ratio_to_goal", bench_json_real(r->sustained_fps / 30));
		json_object_set_new(j, "ratio_to_raw", bench_json_real(ratio));
		json_object_set_new(j, "recorded_fps", bench_json_real(r->recorded_fps));
		json_object_set_new(j, "write_ms_mean", bench_json_real(r->write_ms_mean));
		json_object_set_new(j, "write_ms_max", bench_json_real(r->write_ms_max));
		json_object_set_new(j, "file_bytes", json_integer((json_int_t)r->file_bytes));
		json_object_set_new(
		    j, "mb_per_s", bench_json_real(r->sustained_fps * (double)r->file_bytes / 1e6));
		json_object_set_new(j, "frames", json_integer((json_int_t)r->frames));
		json_object_set_new(j, "queue_peak", json_integer(r->peak));
		json_object_set_new(j, "lost", json_integer((json_int_t)r->lost));
		json_object_set_new(j, "skipped", json_integer((json_int_t)r->skipped));
		json_object_set_new(j, "complete", json_boolean(r->complete));
		json_object_set_new(j, "error", r->error ? json_string(r->errmsg) : json_null());
		host->print_json(j);
		return;
	}
	printf("disk-%-5s %8.1f fps sustained (%5.2fx the 30 fps goal, %.2fx raw) %6.1f ms/frame "
	       "(max %.1f), %.1f MB/frame = %.0f MB/s; recorded %.1f fps, %llu frames, queue "
	       "peak %lld, lost %llu, damaged skipped %llu%s%s\n",
	       r->store, r->sustained_fps, r->sustained_fps / 30, ratio, r->write_ms_mean,
	       r->write_ms_max, (double)r->file_bytes / 1e6,
	       r->sustained_fps * (double)r->file_bytes / 1e6, r->recorded_fps,
	       (unsigned long long)r->frames, r->peak, (unsigned long long)r->lost,
	       (unsigned long long)r->skipped, r->error ? "; " : "", r->error ? r->errmsg : "");
	fflush(stdout);
}

static int serve(const bench_opts *o, unsigned cycle, pc_gige_server **srv, double *prep_s)
{
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=0&fps=0", o->scene);
	pc_gige_server_options so;
	memset(&so, 0, sizeof so);
	so.source_uri = uri;
	so.cycle = cycle;
	so.ahead = 4;
	so.frame_rate_hz = 30;
	double t0 = bench_now();
	int rc = pc_gige_server_start(srv, &so);
	*prep_s = bench_now() - t0;
	return rc;
}

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam bench devices [options]\n\n"
	    "GigE Vision over loopback (polarcam's camera and the aravis: source in one process,\n"
	    "inside a private network namespace) and the live pipeline; see "
	    "bench/bench_devices.c.\n\n"
	    "  --scene S          simulator scene (default: the built-in 2448x2048 scene)\n"
	    "  --packet-size N    GigE Vision packet size (default 65000, loopback's MTU allows "
	    "it;\n"
	    "                     8972 is a jumbo frame on real Ethernet; Aravis's automatic "
	    "choice\n"
	    "                     is 1400 on loopback)\n"
	    "  --method M         demosaicking method of the pipeline phases (default bilinear)\n"
	    "  --format NAME      pixel format (default Mono16)\n"
	    "  --seconds S        seconds per phase (default 5)\n"
	    "  --cycle K          distinct pre-rendered frames the camera cycles through (default "
	    "4)\n"
	    "  --disk-frames N    frames per disk phase (default 30)\n"
	    "  --dir DIR          where the disk phases write (default: a new directory in\n"
	    "                     $TMPDIR or /tmp; the frames are removed after each phase)\n"
	    "  --quick            small scene, 1 s phases (a smoke run, for the test suite)\n"
	    "  --json             one JSON line per phase\n\n"
	    "Phases: transport (pre-rendered frames, 1000 fps asked: unpaced, it saturates the\n"
	    "path on purpose, so missing packets there are expected), serve30 (the same paced at\n"
	    "30 fps: should lose nothing), pipeline (30 fps with demosaic + Stokes per frame),\n"
	    "alone (the pipeline without transport), live (frames rendered while streaming),\n"
	    "disk-png, disk-npy, disk-raw (capture to files at 30 fps: the sustained rate is\n"
	    "1 / the writer's mean time per frame, fsync included; the recorded rate counts the\n"
	    "queue's drain).\n"
	    "fps is the steady-state rate: (frames received - 1) divided by the time\n"
	    "from the first to the last frame the client received; the stream's\n"
	    "start-up is not counted.\n");
}

int pc_bench_devices(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	if (bench_wants_help(argc, argv)) {
		usage(stdout);
		return PC_BENCH_OK;
	}
	bench_opts o = {"default", 65000,          5,          4,    "Mono16", false,
	                false,     PC_DM_BILINEAR, "bilinear", NULL, 30};
	char scene_buf[600];
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		int rc = 0;
		long l;
		if (!strcmp(a, "--quick")) {
			o.quick = true;
		} else if (!strcmp(a, "--json")) {
			o.json = true;
		} else if (i + 1 < argc && !strcmp(a, "--scene")) {
			o.scene = argv[++i];
		} else if (i + 1 < argc && !strcmp(a, "--packet-size")) {
			rc = host->parse_long(a, argv[++i], 576, 65000, &l);
			o.packet_size = (uint64_t)l;
		} else if (i + 1 < argc && !strcmp(a, "--method")) {
			o.method_name = argv[++i];
			rc = pc_demosaic_method_from_name(o.method_name, &o.method);
		} else if (i + 1 < argc && !strcmp(a, "--format")) {
			o.format = argv[++i];
		} else if (i + 1 < argc && !strcmp(a, "--seconds")) {
			rc = host->parse_double(a, argv[++i], &o.seconds);
			if (!rc && (o.seconds < 0.2 || o.seconds > 600))
				rc = pc_error(PC_EINVAL, "--seconds %g: expected 0.2..600",
				              o.seconds);
		} else if (i + 1 < argc && !strcmp(a, "--disk-frames")) {
			rc = host->parse_long(a, argv[++i], 1, 100000, &l);
			o.disk_frames = (unsigned)l;
		} else if (i + 1 < argc && !strcmp(a, "--dir")) {
			o.dir = argv[++i];
		} else if (i + 1 < argc && !strcmp(a, "--cycle")) {
			rc = host->parse_long(a, argv[++i], 1, 64, &l);
			o.cycle = (unsigned)l;
		} else {
			return host->error(PC_BENCH_USAGE,
			                   "unknown or incomplete option '%s' (see --help)", a);
		}
		if (rc)
			return host->fail(rc, "arguments");
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	if (o.quick) {
		const char *src = getenv("PC_SOURCE_DIR");
		snprintf(scene_buf, sizeof scene_buf, "%s/scenes/ideal_small.json",
		         src ? src : ".");
		if (!strcmp(o.scene, "default"))
			o.scene = scene_buf;
		o.seconds = 1;
		o.disk_frames = 4;
	}
	/* inside a private network namespace with only loopback (bench_netns.c) */
	int ns = bench_netns_reexec(host, argc, argv);
	if (ns)
		return ns;

	if (!o.json)
		printf("polarcam bench devices: scene %s, %s, packet size %llu, %g s per phase, "
		       "pipeline %s, %d threads (ratios are against baselines of this run)\n",
		       o.scene, o.format, (unsigned long long)o.packet_size, o.seconds,
		       o.method_name, pc_parallel_max_threads());
	pc_gige_server *srv = NULL;
	double prep = 0;
	int rc = serve(&o, o.cycle, &srv, &prep);
	if (rc) {
		pc_devices_shutdown();
		return host->fail(rc, "starting the camera");
	}
	pc_gige_server_stats sst;
	pc_gige_server_get_stats(srv, &sst);
	if (!o.json)
		printf("camera: %ux%u %u-bit sensor, %u pre-rendered frames in %.1f s\n",
		       sst.sensor_width, sst.sensor_height, sst.bits, o.cycle, prep);
	phase_result transport, at30, live, pipe;
	stream_phase(&o, 1000, false, &transport);
	print_phase(&o, "transport", 0, &transport);
	stream_phase(&o, 30, false, &at30);
	print_phase(&o, "serve30", 30, &at30);
	stream_phase(&o, 30, true, &pipe);
	print_phase(&o, "pipeline", 30, &pipe);

	/* capture to disk in each store, from the same camera */
	char tmpdir[600] = "";
	const char *ddir = o.dir;
	if (!ddir) {
		const char *t = getenv("TMPDIR");
		snprintf(tmpdir, sizeof tmpdir, "%s/polarcam-bench-XXXXXX", t && *t ? t : "/tmp");
		ddir = mkdtemp(tmpdir);
	}
	disk_result disk[3];
	bool disk_hard = false;
	memset(disk, 0, sizeof disk);
	if (!ddir) {
		host->warn("no directory for the disk phases (TMPDIR): skipped");
	} else {
		if (!o.json)
			printf("disk phases in %s (%s), %u frames each\n", ddir, fs_name(ddir),
			       o.disk_frames);
		static const pc_recording_store order[3] = {PC_STORE_RAW, PC_STORE_NPY,
		                                            PC_STORE_PNG};
		for (int k = 0; k < 3; k++) {
			disk_phase(&o, ddir, order[k], &disk[k]);
			disk_hard |= disk[k].frames == 0 && disk[k].error;
			print_disk(&o, &disk[k], disk[0].sustained_fps);
		}
		if (!o.dir)
			rmdir(ddir);
	}
	pc_gige_server_stop(srv);

	/* the pipeline alone on one frame of the same size (its baseline) */
	phase_result alone;
	memset(&alone, 0, sizeof alone);
	{
		char uri[700];
		snprintf(uri, sizeof uri, "sim:%s?seed=0&fps=0", o.scene);
		pc_stream_request sa;
		pc_stream_request_init(&sa);
		sa.uri = uri;
		sa.buffers = 1;
		pc_source *s = NULL;
		pc_stokes_stream *lv = NULL;
		double sim_t = 0;
		unsigned sim_n = 0;
		rc = pc_stokes_stream_new(o.method, &lv);
		if (!rc)
			rc = pc_stream_open(&sa, &s);
		if (!rc)
			rc = pc_source_start(s);
		pc_buffer *b = NULL;
		for (unsigned k = 0; !rc && k < 3; k++) { /* simulator frames: its own frame rate */
			double t = bench_now();
			rc = pc_source_dequeue(s, 600000, &b);
			if (!rc && k > 0) {
				sim_t += bench_now() - t;
				sim_n++;
			}
			if (!rc && k < 2)
				rc = pc_source_requeue(s, b);
		}
		double t0 = bench_now();
		while (!rc && bench_now() - t0 < o.seconds) {
			rc = pc_stokes_stream_process(lv, &b->frame);
			alone.frames++;
			alone.proc_ms_mean += pc_stokes_stream_seconds(lv) * 1e3;
		}
		alone.seconds = bench_now() - t0;
		if (alone.frames)
			alone.proc_ms_mean /= (double)alone.frames;
		alone.fps = alone.seconds > 0 ? (double)alone.frames / alone.seconds : 0;
		if (rc) {
			alone.error = rc;
			snprintf(alone.errmsg, sizeof alone.errmsg, "%s", pc_error_detail());
		}
		if (o.json) {
			json_t *j = phase_json("alone", 0, &alone);
			json_object_set_new(j, "process_ms_mean",
			                    bench_json_real(alone.proc_ms_mean));
			json_object_set_new(j, "simulator_frame_s",
			                    sim_n ? bench_json_real(sim_t / sim_n) : json_null());
			host->print_json(j);
		} else {
			printf(
			    "alone      %8.1f fps   pipeline %.1f ms/frame without transport (%s "
			    "demosaic + Stokes + DoLP + AoLP); simulator sensor chain %.2f "
			    "s/frame\n",
			    alone.fps, alone.proc_ms_mean, o.method_name,
			    sim_n ? sim_t / sim_n : NAN);
		}
		pc_stokes_stream_free(lv);
		pc_source_close(s);
	}

	/* live: frames rendered while streaming */
	rc = serve(&o, 0, &srv, &prep);
	if (rc) {
		pc_devices_shutdown();
		return host->fail(rc, "starting the camera (live)");
	}
	stream_phase(&o, 30, false, &live);
	print_phase(&o, "live", 30, &live);
	pc_gige_server_get_stats(srv, &sst);
	if (!o.json)
		printf("           camera: %llu frames served, %llu of them late (waited for the "
		       "simulator)\n",
		       (unsigned long long)sst.served, (unsigned long long)sst.late);
	pc_gige_server_stop(srv);
	pc_devices_shutdown();
	if (!o.json) {
		printf(
		    "\nsummary: serve->capture %.1f fps at the 30 fps goal (%.2fx), %llu missing "
		    "packets at the paced 30 fps (%llu in the pipeline phase); live pipeline %.1f "
		    "ms per frame = %.2fx the 33.3 ms period (alone %.1f ms: %.2fx), latency "
		    "trend %+.2f ms/s\n"
		    "         saturating transport phase (unpaced, 1000 fps asked): %.1f fps = "
		    "%.0f "
		    "MB/s, %llu missing packets (expected when unpaced: the camera sends faster "
		    "than the client takes them)\n",
		    at30.fps, at30.fps / 30, (unsigned long long)at30.missing_packets,
		    (unsigned long long)pipe.missing_packets, pipe.proc_ms_mean,
		    pipe.proc_ms_mean * 30 / 1e3, alone.proc_ms_mean,
		    alone.proc_ms_mean > 0 ? pipe.proc_ms_mean / alone.proc_ms_mean : 0,
		    pipe.lat_slope_ms_per_s, transport.fps, transport.mbps,
		    (unsigned long long)transport.missing_packets);
		if (disk[0].store)
			printf("         capture to disk (sustained, writer alone): raw %.1f fps, "
			       ".npy %.1f fps (%.2fx raw), PNG %.1f fps (%.2fx raw) against the 30 "
			       "fps goal\n",
			       disk[0].sustained_fps, disk[1].sustained_fps,
			       disk[0].sustained_fps > 0
			           ? disk[1].sustained_fps / disk[0].sustained_fps
			           : 0,
			       disk[2].sustained_fps,
			       disk[0].sustained_fps > 0
			           ? disk[2].sustained_fps / disk[0].sustained_fps
			           : 0);
	}
	return transport.error || at30.error || pipe.error || disk_hard ? PC_BENCH_FAILURE
	                                                                : PC_BENCH_OK;
}
