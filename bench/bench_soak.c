/* polarcam bench soak: serve -> capture -> live pipeline at the camera's full size (2448x2048
 * for the default scene) and 30 frames/s for N minutes, sampling the process's resident memory,
 * open file descriptors and threads every minute: they must stay flat.
 *
 * One process inside a private network namespace (bench_netns.c): the GigE Vision camera of
 * `polarcam serve` (devices/gige_server.c) serving K frames of the scene rendered once
 * (--cycle K, so that the camera keeps the rate the simulator could not) and its client,
 * polarcam's aravis: source. Each period (a minute):
 *   live     for most of it, frames streamed through the live Stokes pipeline
 *            (pc_stokes_stream_process); every whole frame is compared byte for byte with the
 *            frame the simulator regenerates from (seed, frame number): acquisition frame j is
 *            source frame j mod K, anchored at the first frame whose content matches
 *   capture  pc_capture of --capture-frames frames with --process into DIR (raw store, the
 *            recording replaced every period): the queue, the writer thread, the recording
 *            files, all opened and closed again; its frames are compared the same way
 *   sample   after malloc_trim: the heap in use (glibc's mallinfo2: bytes allocated and not
 *            freed, in every arena and in mmapped chunks), the anonymous resident memory
 *            (RssAnon: heap pages, thread stacks, anonymous mappings) and VmRSS (reported
 *            only: file-backed pages come and go with the page cache), open file descriptors
 *            (/proc/self/fd), threads (/proc/self/status)
 * A warm-up period of 10 s live + one capture comes first (OpenMP's threads, Aravis's caches
 * appear on first use, not as leaks); its sample is the baseline.
 *
 * Pass: at every sample the file descriptors and the threads equal the baseline's; the heap in
 * use and the anonymous RSS grow no faster than HEAP_SLOPE_KIB and ANON_SLOPE_KIB per period
 * over the later half of the soak and stay within a cap of the baseline that allows the
 * untraced drift (the limits below); no frame received or recorded differs from the
 * simulator's. The achieved frame rate, damaged and dropped frames
 * are reported beside: a loaded machine may not sustain 30 fps, which is not a leak.
 * SIGINT/SIGTERM end the soak after the current phase, with the verdict over the periods done.
 *
 * Why these and not plain RSS against a tolerance: with one malloc arena per thread (glibc's
 * default, up to 8 per core), malloc_trim returns the free pages inside every arena but trims
 * the top chunk of the main arena only; a thread arena keeps a top chunk resident up to the trim
 * threshold, which glibc raises to twice the largest block freed from mmap (a 2448x2048 frame:
 * ~20 MB). Which thread's arena a frame-sized buffer lands in, and whether it ends at the top,
 * depends on timing: RSS moved by steps of one 1-byte-per-pixel buffer (4.8 MiB) between runs
 * and between periods, and under load (10) a baseline 9.6 MiB low failed the old max(16 MiB,
 * 5 %) limit with no leak. So the soak runs with one arena (mallopt M_ARENA_MAX = 1, set before
 * any thread allocates), where malloc_trim returns every free page; measured at 2448x2048: RSS
 * flat to 0.1 MiB over two periods where it had grown 4.8 MiB per period. The heap in use does
 * not depend on where the allocator put anything: a malloc leak grows it byte for byte,
 * whatever the load. RssAnon catches what bypasses malloc (mmap); VmRSS is reported.
 * Checked by hand (docs/reliability.md): 1 and 3 MiB malloc'ed and touched per period, never
 * freed, fail the verdict (the heap's slope), as do 1 and 3 MiB mmapped per period (RssAnon's).
 * Without glibc 2.33's mallinfo2 the heap in use is unknown and RssAnon is judged alone.
 *
 * Under AddressSanitizer the heap is ASan's (its quarantine holds freed memory, mallinfo2 does
 * not see it) and RSS holds its shadow, so memory is reported but not judged there
 * (LeakSanitizer checks for leaks at the exit of such a build). */
#define _GNU_SOURCE /* malloc_trim */
#include <dirent.h>
#include <ftw.h>
#include <jansson.h>
#include <math.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
/* mallinfo2 came with glibc 2.33 (mallinfo's int fields wrap above 2 GiB); without it the heap
 * in use is not known and RssAnon is judged alone */
#if defined(__GLIBC_PREREQ) && !defined(HAVE_MALLINFO2) /* -DHAVE_MALLINFO2=0: the fallback */
#if __GLIBC_PREREQ(2, 33)
#define HAVE_MALLINFO2 1
#endif
#endif
#endif
#ifndef HAVE_MALLINFO2
#define HAVE_MALLINFO2 0
#endif

#include "bench.h"
#include "polarcam/capture.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"
#include "polarcam/stream.h"

#if defined(__SANITIZE_ADDRESS__)
#define RSS_JUDGED 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RSS_JUDGED 0
#endif
#endif
#ifndef RSS_JUDGED
#define RSS_JUDGED 1
#endif
/* Limits of the growth, judged so that they scale with the length of the soak. Without a leak
 * the heap in use drifts up by 5-10 kB per period (docs/reliability.md), which a fixed limit
 * from the baseline would turn into a failure of any soak long enough (600 periods: 3-6 MiB).
 * So a leak is judged by its rate: the least-squares slope per period of the samples of the
 * later half of the soak (periods done/2 .. done; with one period, the baseline and it), where
 * one-off growth of the first periods (caches filled on first use) is over, must stay within
 * *_SLOPE_KIB; and every sample within *_CAP_MIB + DRIFT_KIB per period of the baseline, for a
 * leak that stops (a one-off jump) or one the later half hides. Measured without a leak at
 * 2448x2048, two 15 s periods beside two `yes` (load 7-8, 3 runs): heap slope +3.0 to +3.7 kB
 * per period, RssAnon +8 to +20 kB. A leak of 1 MiB per period fails the heap slope from two
 * periods on (16 times the limit), through malloc or mmap (RssAnon); a 1-byte-per-pixel frame (4.8
 * MiB) fails either cap at the first. */
#define HEAP_SLOPE_KIB 64.0
#define ANON_SLOPE_KIB 256.0
#define HEAP_CAP_MIB   4.0
#define ANON_CAP_MIB   8.0
#define DRIFT_KIB      16.0 /* the caps' allowance per period: twice the drift measured */

static const pc_bench_host *host;
static volatile sig_atomic_t soak_stop;

static void on_signal(int sig)
{
	(void)sig;
	soak_stop = 1;
}

typedef struct soak_opts {
	const char *scene;
	double minutes, period_s, fps;
	unsigned cycle, capture_frames;
	const char *dir, *format;
	bool json, quick;
} soak_opts;

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *f)
{
	(void)st;
	(void)f;
	if (flag == FTW_DP ? rmdir(path) : unlink(path))
		return 0; /* what cannot be removed stays; the rest goes */
	return 0;
}

/* ---- the frames the simulator regenerates ---- */

typedef struct refs {
	uint8_t **row0; /* frame k, rows of width * 2 bytes one after the other */
	unsigned k;
	uint32_t width, height;
} refs;

static int make_refs(const soak_opts *o, refs *r)
{
	memset(r, 0, sizeof *r);
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=0&fps=0", o->scene);
	pc_source *s = NULL;
	int rc = pc_source_open(&s, uri);
	if (!rc)
		rc = pc_source_buffers_alloc(s, 1);
	if (!rc)
		rc = pc_source_start(s);
	r->row0 = calloc(o->cycle, sizeof *r->row0);
	for (unsigned k = 0; !rc && k < o->cycle; k++) {
		pc_buffer *b = NULL;
		if ((rc = pc_source_dequeue(s, 600000, &b)))
			break;
		const pc_view *v = &b->frame.view;
		r->width = v->width;
		r->height = v->height;
		size_t row = (size_t)v->width * 2;
		if (pc_format_info_get(v->format)->group_bytes != 2 ||
		    !(r->row0[k] = malloc(row * v->height)))
			rc = pc_error(PC_EFORMAT, "soak: expected a 9..16-bit simulator");
		for (uint32_t y = 0; !rc && y < v->height; y++)
			memcpy(r->row0[k] + y * row, PC_ROW(v, const uint8_t, y), row);
		r->k = k + 1;
		pc_source_requeue(s, b);
	}
	pc_source_close(s);
	return rc;
}

static void free_refs(refs *r)
{
	for (unsigned k = 0; r->row0 && k < r->k; k++)
		free(r->row0[k]);
	free(r->row0);
}

static bool same(const refs *r, unsigned k, const pc_view *v)
{
	if (v->width != r->width || v->height != r->height ||
	    pc_format_info_get(v->format)->group_bytes != 2 ||
	    pc_format_info_get(v->format)->packing != PC_PACK_NONE)
		return false;
	size_t row = (size_t)v->width * 2;
	for (uint32_t y = 0; y < v->height; y++)
		if (memcmp(r->row0[k] + y * row, PC_ROW(v, const uint8_t, y), row))
			return false;
	return true;
}

/* Which source frame a whole acquisition frame must be: anchored at the first one that matches
 * any regenerated frame, then (anchor + sequence difference) mod K. */
typedef struct anchor {
	bool set;
	uint64_t seq;
	unsigned k;
} anchor;

static bool frame_ok(const refs *r, anchor *a, uint64_t seq, const pc_view *v)
{
	if (!a->set) {
		for (unsigned k = 0; k < r->k; k++)
			if (same(r, k, v)) {
				*a = (anchor){true, seq, k};
				return true;
			}
		return false;
	}
	return same(r, (unsigned)((a->k + (seq - a->seq)) % r->k), v);
}

/* ---- samples ---- */

typedef struct sample {
	double rss_mib, anon_mib; /* VmRSS, RssAnon */
	double heap_mib;          /* in use: allocated and not freed (NAN: not known) */
	long fds, threads;
} sample;

static void take_sample(sample *s)
{
	s->heap_mib = NAN;
#if defined(__GLIBC__)
	malloc_trim(0);
#endif
#if HAVE_MALLINFO2
	struct mallinfo2 mi = mallinfo2();
	s->heap_mib = (double)(mi.uordblks + mi.hblkhd) / (1024 * 1024);
#endif
	s->rss_mib = s->anon_mib = NAN;
	s->threads = -1;
	FILE *fp = fopen("/proc/self/status", "r");
	char line[256];
	while (fp && fgets(line, sizeof line, fp)) {
		long v;
		if (sscanf(line, "VmRSS: %ld kB", &v) == 1)
			s->rss_mib = (double)v / 1024;
		else if (sscanf(line, "RssAnon: %ld kB", &v) == 1)
			s->anon_mib = (double)v / 1024;
		else if (sscanf(line, "Threads: %ld", &v) == 1)
			s->threads = v;
	}
	if (fp)
		fclose(fp);
	s->fds = -1;
	DIR *d = opendir("/proc/self/fd");
	if (d) {
		long n = 0;
		struct dirent *de;
		while ((de = readdir(d)))
			n += de->d_name[0] != '.';
		closedir(d);
		s->fds = n - 1; /* the directory being read */
	}
}

/* ---- a period ---- */

typedef struct period {
	uint64_t frames, damaged, dropped, underruns, missing_packets, differ, processed;
	double fps, proc_ms;
	uint64_t cap_frames, cap_skipped, cap_lost, cap_differ;
	bool cap_complete;
	int error;
	char errmsg[256];
	sample s;
} period;

static void set_error(period *p, int rc, const char *what)
{
	if (p->error)
		return;
	p->error = rc;
	snprintf(p->errmsg, sizeof p->errmsg, "%s: %s", what, pc_error_detail());
}

static void stream_request(const soak_opts *o, pc_stream_request *sr, char *uri, size_t n)
{
	snprintf(uri, n, "aravis:127.0.0.1?packet_size=65000");
	pc_stream_request_init(sr);
	sr->uri = uri;
	sr->format = o->format;
	sr->fps = o->fps;
	sr->buffers = 16;
}

/* The live pipeline for `seconds`. */
static void live(const soak_opts *o, const refs *r, double seconds, pc_stokes_stream *ss, period *p)
{
	char uri[128];
	pc_stream_request sr;
	stream_request(o, &sr, uri, sizeof uri);
	pc_source *s = NULL;
	int rc = pc_stream_open(&sr, &s);
	if (!rc)
		rc = pc_source_start(s);
	if (rc) {
		set_error(p, rc, "live: opening the camera");
		pc_source_close(s);
		return;
	}
	anchor a = {0};
	double t0 = bench_now(), t_first = 0, t_last = 0, proc = 0;
	while (!soak_stop && bench_now() - t0 < seconds) {
		pc_buffer *b = NULL;
		if ((rc = pc_source_dequeue(s, 5000, &b))) {
			set_error(p, rc, "live: dequeue");
			break;
		}
		t_last = bench_now();
		if (p->frames++ == 0)
			t_first = t_last;
		if (b->frame.meta.status) {
			p->damaged++;
		} else {
			p->differ += !frame_ok(r, &a, b->frame.meta.sequence, &b->frame.view);
			if ((rc = pc_stokes_stream_process(ss, &b->frame)))
				set_error(p, rc, "live: the pipeline");
			proc += pc_stokes_stream_seconds(ss);
			p->processed++;
		}
		if ((rc = pc_source_requeue(s, b))) {
			set_error(p, rc, "live: requeue");
			break;
		}
	}
	if (pc_source_get_state(s) == PC_SOURCE_STREAMING)
		pc_source_stop(s);
	pc_source_stats st;
	pc_source_get_stats(s, &st);
	p->dropped += st.dropped;
	p->underruns += st.underruns;
	p->missing_packets += st.missing_packets;
	p->fps =
	    p->frames > 1 && t_last > t_first ? (double)(p->frames - 1) / (t_last - t_first) : 0;
	p->proc_ms = p->processed ? 1e3 * proc / (double)p->processed : 0;
	pc_source_close(s);
}

/* A capture with --process into dir (replaced), its frames checked. */
static void capture(const soak_opts *o, const refs *r, const char *dir, period *p)
{
	char uri[128];
	pc_capture_opts co;
	memset(&co, 0, sizeof co);
	stream_request(o, &co.stream, uri, sizeof uri);
	co.frames = o->capture_frames;
	co.dir = dir;
	co.overwrite = true;
	co.process = true;
	co.timeout_ms = 5000;
	co.store = PC_STORE_RAW;
	pc_capture_report rep;
	int rc = pc_capture(&co, &rep);
	if (rc) {
		set_error(p, rc, "capture");
		pc_capture_report_free(&rep);
		return;
	}
	p->cap_frames = rep.frames;
	p->cap_skipped = rep.skipped;
	p->cap_lost = rep.lost;
	p->cap_complete = rep.complete;
	pc_capture_report_free(&rep);
	pc_recording *rec = NULL;
	if ((rc = pc_recording_open(&rec, dir))) {
		set_error(p, rc, "capture: reading the recording");
		return;
	}
	anchor a = {0};
	for (size_t i = 0; i < pc_recording_count(rec); i++) {
		pc_view v;
		if (pc_recording_read(rec, i, &v)) {
			p->cap_differ++;
			pc_error_clear();
			continue;
		}
		p->cap_differ += !frame_ok(r, &a, pc_recording_get_frame(rec, i)->sequence, &v);
		pc_view_free(&v);
	}
	pc_recording_free(rec);
}

static void run_period(const soak_opts *o, const refs *r, const char *dir, double live_s, period *p)
{
	memset(p, 0, sizeof *p);
	pc_stokes_stream *ss = NULL;
	int rc = pc_stokes_stream_new(PC_DM_BILINEAR, &ss);
	if (rc)
		set_error(p, rc, "the pipeline");
	else
		live(o, r, live_s, ss, p);
	pc_stokes_stream_free(ss);
	if (!soak_stop)
		capture(o, r, dir, p);
	take_sample(&p->s);
}

/* ---- reporting ---- */

/* Least-squares slope of v[1..n] (one sample per period) in MiB per minute; NAN below 3. */
/* The least-squares slope of v[a..b] against the index (per index step), b > a: the ordinary
 * least-squares estimate sum((x - mean x)(y - mean y)) / sum((x - mean x)^2) (e.g. Press et al.,
 * Numerical Recipes, 3rd ed., eq. 15.2.6). */
static double slope(const double *v, int a, int b)
{
	double n = b - a + 1, mx = 0, my = 0, sxx = 0, sxy = 0;
	for (int m = a; m <= b; m++) {
		mx += m;
		my += v[m];
	}
	mx /= n;
	my /= n;
	for (int m = a; m <= b; m++) {
		sxx += (m - mx) * (m - mx);
		sxy += (m - mx) * (v[m] - my);
	}
	return sxy / sxx;
}

/* the trend over every period, for the record (per minute; NAN under 3 periods) */
static double trend_per_min(const double *v, int n, double period_s)
{
	return n < 3 ? NAN : slope(v, 1, n) * (60 / period_s);
}

static json_t *period_json(int minute, const period *p, const sample *base)
{
	json_t *j = json_object();
	json_object_set_new(j, "minute", json_integer(minute));
	json_object_set_new(j, "live_fps", bench_json_real(p->fps));
	json_object_set_new(j, "frames", json_integer((json_int_t)p->frames));
	json_object_set_new(j, "damaged", json_integer((json_int_t)p->damaged));
	json_object_set_new(j, "dropped", json_integer((json_int_t)p->dropped));
	json_object_set_new(j, "missing_packets", json_integer((json_int_t)p->missing_packets));
	json_object_set_new(j, "underruns", json_integer((json_int_t)p->underruns));
	json_object_set_new(j, "differ", json_integer((json_int_t)(p->differ + p->cap_differ)));
	json_object_set_new(j, "pipeline_ms", bench_json_real(p->proc_ms));
	json_object_set_new(j, "capture_frames", json_integer((json_int_t)p->cap_frames));
	json_object_set_new(j, "capture_complete", json_boolean(p->cap_complete));
	json_object_set_new(j, "capture_skipped", json_integer((json_int_t)p->cap_skipped));
	json_object_set_new(j, "capture_lost", json_integer((json_int_t)p->cap_lost));
	json_object_set_new(j, "rss_mib", bench_json_real(p->s.rss_mib));
	json_object_set_new(j, "rss_delta_mib", bench_json_real(p->s.rss_mib - base->rss_mib));
	json_object_set_new(j, "anon_mib", bench_json_real(p->s.anon_mib));
	json_object_set_new(j, "anon_delta_mib", bench_json_real(p->s.anon_mib - base->anon_mib));
	json_object_set_new(j, "heap_mib", bench_json_real(p->s.heap_mib));
	json_object_set_new(j, "heap_delta_mib", bench_json_real(p->s.heap_mib - base->heap_mib));
	json_object_set_new(j, "fds", json_integer(p->s.fds));
	json_object_set_new(j, "threads", json_integer(p->s.threads));
	json_object_set_new(j, "error", p->error ? json_string(p->errmsg) : json_null());
	return j;
}

static void print_period(const soak_opts *o, int minute, const period *p, const sample *base)
{
	if (o->json) {
		host->print_json(period_json(minute, p, base));
		return;
	}
	printf(
	    "%6d %7.1f %7llu %7llu %7llu %6llu %8.1f   %3llu %-3s %4llu %4llu %9.1f %+7.1f %+7.2f "
	    "%5ld %+3ld %6ld %+3ld%s%s\n",
	    minute, p->fps, (unsigned long long)p->frames, (unsigned long long)p->damaged,
	    (unsigned long long)p->dropped, (unsigned long long)(p->differ + p->cap_differ),
	    p->proc_ms, (unsigned long long)p->cap_frames, p->cap_complete ? "yes" : "no",
	    (unsigned long long)p->cap_skipped, (unsigned long long)p->cap_lost, p->s.rss_mib,
	    p->s.anon_mib - base->anon_mib, p->s.heap_mib - base->heap_mib, p->s.fds,
	    p->s.fds - base->fds, p->s.threads, p->s.threads - base->threads, p->error ? "  " : "",
	    p->error ? p->errmsg : "");
	fflush(stdout);
}

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam bench soak [--minutes N] [options]\n\n"
	    "serve -> capture -> live pipeline for N minutes in one process, inside a private\n"
	    "network namespace (see bench/bench_soak.c): each minute the live Stokes pipeline on\n"
	    "the camera's frames, then a capture --process of a few frames, then a sample of the\n"
	    "process's heap in use, RSS, open file descriptors and threads. Every frame received "
	    "or recorded is\n"
	    "compared with the frame the simulator regenerates from (seed, frame number).\n\n"
	    "  --minutes N         minutes to run (default 60; fractions allowed)\n"
	    "  --fps F             the camera's frame rate (default 30)\n"
	    "  --scene S           simulator scene (default: the built-in 2448x2048 scene)\n"
	    "  --cycle K           frames rendered once and served in turn (default 4)\n"
	    "  --capture-frames N  frames of each minute's capture (default 15)\n"
	    "  --period S          seconds between samples (default 60)\n"
	    "  --dir DIR           where the captures go (default: a new directory in $TMPDIR\n"
	    "                      or /tmp, removed at the end)\n"
	    "  --quick             small scene (scenes/ideal_small.json), for smoke runs\n"
	    "  --json              one JSON line per minute and one with the verdict\n\n"
	    "Pass: after a warm-up (10 s live + one capture, whose sample is the baseline), every\n"
	    "sample has the baseline's file descriptors and threads; the heap in use (malloc's\n"
	    "count of bytes not freed) grows at most %g kB per period and the anonymous RSS at\n"
	    "most %g kB (least-squares slope over the later half of the periods), each sample\n"
	    "within %g MiB (heap) and %g MiB (RssAnon) + %g kB per period of the baseline's;\n"
	    "and no frame differs from the simulator's. Exit 0 pass, 1 fail.\n"
	    "The achieved frame rate is reported beside it.\n",
	    HEAP_SLOPE_KIB, ANON_SLOPE_KIB, HEAP_CAP_MIB, ANON_CAP_MIB, DRIFT_KIB);
}

static int parse(int argc, char **argv, soak_opts *o)
{
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		int rc = 0;
		long l;
		if (!strcmp(a, "--json")) {
			o->json = true;
		} else if (!strcmp(a, "--quick")) {
			o->quick = true;
		} else if (i + 1 < argc && !strcmp(a, "--minutes")) {
			rc = host->parse_double(a, argv[++i], &o->minutes);
			if (!rc && !(o->minutes > 0 && o->minutes <= 7 * 24 * 60))
				rc = pc_error(PC_EINVAL, "--minutes %g: expected (0, 10080]",
				              o->minutes);
		} else if (i + 1 < argc && !strcmp(a, "--fps")) {
			rc = host->parse_double(a, argv[++i], &o->fps);
			if (!rc && !(o->fps > 0 && o->fps <= 1000))
				rc = pc_error(PC_EINVAL, "--fps %g: expected (0, 1000]", o->fps);
		} else if (i + 1 < argc && !strcmp(a, "--period")) {
			rc = host->parse_double(a, argv[++i], &o->period_s);
			if (!rc && !(o->period_s >= 10 && o->period_s <= 3600))
				rc = pc_error(PC_EINVAL, "--period %g: expected 10..3600 s",
				              o->period_s);
		} else if (i + 1 < argc && !strcmp(a, "--scene")) {
			o->scene = argv[++i];
		} else if (i + 1 < argc && !strcmp(a, "--dir")) {
			o->dir = argv[++i];
		} else if (i + 1 < argc && !strcmp(a, "--cycle")) {
			rc = host->parse_long(a, argv[++i], 1, 64, &l);
			o->cycle = (unsigned)l;
		} else if (i + 1 < argc && !strcmp(a, "--capture-frames")) {
			rc = host->parse_long(a, argv[++i], 1, 1000, &l);
			o->capture_frames = (unsigned)l;
		} else {
			return host->error(PC_BENCH_USAGE,
			                   "unknown or incomplete option '%s' (see --help)", a);
		}
		if (rc)
			return host->fail(rc, "arguments");
	}
	return 0;
}

int pc_bench_soak(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	if (bench_wants_help(argc, argv)) {
		usage(stdout);
		return PC_BENCH_OK;
	}
	soak_opts o = {"default", 60, 60, 30, 4, 15, NULL, "PolarizeMono12", false, false};
	int st = parse(argc, argv, &o);
	if (st)
		return st;
	char scene_buf[600];
	if (o.quick && !strcmp(o.scene, "default")) {
		const char *src = getenv("PC_SOURCE_DIR");
		snprintf(scene_buf, sizeof scene_buf, "%s/scenes/ideal_small.json",
		         src ? src : ".");
		o.scene = scene_buf;
	}
	if ((st = bench_netns_reexec(host, argc, argv)))
		return st;
#if defined(__GLIBC__)
	/* one malloc arena, so that malloc_trim returns every free page (see the top); before
	 * any thread of this process allocates */
	mallopt(M_ARENA_MAX, 1);
#endif
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sa.sa_flags = SA_RESTART;
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);

	char tmpdir[600] = "", capdir[700];
	const char *dir = o.dir;
	if (!dir) {
		const char *t = getenv("TMPDIR");
		snprintf(tmpdir, sizeof tmpdir, "%s/polarcam-soak-XXXXXX", t && *t ? t : "/tmp");
		if (!(dir = mkdtemp(tmpdir)))
			return host->error(PC_BENCH_FAILURE, "cannot make a directory in %s",
			                   t && *t ? t : "/tmp");
	}
	snprintf(capdir, sizeof capdir, "%s/capture", dir);
	refs r;
	double t0 = bench_now();
	int rc = make_refs(&o, &r);
	if (rc) {
		free_refs(&r);
		return host->fail(rc, "regenerating the simulator's frames");
	}
	char src_uri[700];
	snprintf(src_uri, sizeof src_uri, "sim:%s?seed=0&fps=0", o.scene);
	pc_gige_server_options so;
	memset(&so, 0, sizeof so);
	so.source_uri = src_uri;
	so.cycle = o.cycle;
	so.frame_rate_hz = o.fps;
	pc_gige_server *srv = NULL;
	if ((rc = pc_gige_server_start(&srv, &so))) {
		free_refs(&r);
		pc_devices_shutdown();
		return host->fail(rc, "starting the camera");
	}
	if (!o.json)
		printf("polarcam bench soak: %g minutes, scene %s (%ux%u), %s at %g fps, %u frames "
		       "served in turn, captures of %u frames into %s; set-up %.1f s\n"
		       "%6s %7s %7s %7s %7s %6s %8s   %-12s %4s %4s %9s %7s %7s %5s %3s %6s %3s\n",
		       o.minutes, o.scene, r.width, r.height, o.format, o.fps, o.cycle,
		       o.capture_frames, capdir, bench_now() - t0, "minute", "fps", "frames",
		       "damaged", "dropped", "differ", "pipe_ms", "capture ok", "skip", "lost",
		       "RSS_MiB", "dAnon", "dHeap", "fds", "d", "thr", "d");
	/* the warm-up, whose sample is the baseline */
	period warm;
	run_period(&o, &r, capdir, 10, &warm);
	sample base = warm.s;
	print_period(&o, 0, &warm, &base);
	const bool heap_judged = RSS_JUDGED && !isnan(base.heap_mib);
	int periods = (int)ceil(o.minutes * 60 / o.period_s - 1e-9);
	int done = 0, bad_fd = 0, bad_thr = 0, bad_heap = 0, bad_anon = 0;
	uint64_t differ = warm.differ + warm.cap_differ, frames = 0, damaged = 0;
	double max_heap = 0, max_anon = 0, max_rss = 0, fps_sum = 0, fps_min = INFINITY;
	double *heap = calloc((size_t)periods + 1, sizeof *heap);
	double *anon = calloc((size_t)periods + 1, sizeof *anon);
	bool errors = warm.error != 0;
	for (int m = 1; m <= periods && !soak_stop; m++) {
		/* the live phase takes what the capture and the sample leave of the period: the
		 * previous period's capture time is the estimate */
		static double cap_s = 5;
		period p;
		memset(&p, 0, sizeof p);
		pc_stokes_stream *ss = NULL;
		if ((rc = pc_stokes_stream_new(PC_DM_BILINEAR, &ss)))
			set_error(&p, rc, "the pipeline");
		else
			live(&o, &r, fmax(5, o.period_s - cap_s), ss, &p);
		pc_stokes_stream_free(ss);
		double tc = bench_now();
		if (!soak_stop)
			capture(&o, &r, capdir, &p);
		cap_s = bench_now() - tc + 0.5;
		take_sample(&p.s);
		print_period(&o, m, &p, &base);
		done++;
		errors |= p.error != 0;
		bad_fd += p.s.fds != base.fds;
		bad_thr += p.s.threads != base.threads;
		double dh = p.s.heap_mib - base.heap_mib, da = p.s.anon_mib - base.anon_mib,
		       dr = p.s.rss_mib - base.rss_mib;
		const double drift_mib = DRIFT_KIB / 1024 * m;
		bad_heap += heap_judged && !(fabs(dh) <= HEAP_CAP_MIB + drift_mib);
		bad_anon += RSS_JUDGED && !(fabs(da) <= ANON_CAP_MIB + drift_mib);
		max_heap = fabs(dh) > fabs(max_heap) ? dh : max_heap;
		max_anon = fabs(da) > fabs(max_anon) ? da : max_anon;
		max_rss = fabs(dr) > fabs(max_rss) ? dr : max_rss;
		heap[m] = p.s.heap_mib;
		anon[m] = p.s.anon_mib;
		differ += p.differ + p.cap_differ;
		frames += p.frames;
		damaged += p.damaged;
		fps_sum += p.fps;
		fps_min = fmin(fps_min, p.fps);
	}
	pc_gige_server_stop(srv);
	pc_devices_shutdown();
	free_refs(&r);
	/* the rate of growth over the later half (see the limits at the top), and the trends over
	 * all the minutes, for the record */
	const int from = done / 2;
	double heap_rate = NAN, anon_rate = NAN;
	if (heap && anon && done > 0) {
		heap[0] = base.heap_mib;
		anon[0] = base.anon_mib;
		heap_rate = 1024 * slope(heap, from, done);
		anon_rate = 1024 * slope(anon, from, done);
	}
	const bool heap_fast = heap_judged && !(heap_rate <= HEAP_SLOPE_KIB);
	const bool anon_fast = RSS_JUDGED && !(anon_rate <= ANON_SLOPE_KIB);
	double heap_slope = trend_per_min(heap, done, o.period_s);
	double anon_slope = trend_per_min(anon, done, o.period_s);
	free(heap);
	free(anon);
	bool pass = done > 0 && !bad_fd && !bad_thr && !bad_heap && !bad_anon && !heap_fast &&
	            !anon_fast && !differ && !errors;
	char crit[600];
	snprintf(crit, sizeof crit,
	         "fds and threads equal to the baseline's at every sample; heap in use%s growing "
	         "at most %g kB per period (least-squares slope of periods %d..%d) and within "
	         "%g MiB + %g kB per period of the baseline's %.1f MiB; anonymous RSS%s at most "
	         "%g kB per period and within %g MiB + %g kB per period of the baseline's %.1f "
	         "MiB; no frame different from the simulator's, no error",
	         heap_judged  ? ""
	         : RSS_JUDGED ? " (not judged: no mallinfo2 before glibc 2.33; RssAnon alone)"
	                      : " (not judged: AddressSanitizer build)",
	         HEAP_SLOPE_KIB, from, done, HEAP_CAP_MIB, DRIFT_KIB, base.heap_mib,
	         RSS_JUDGED ? "" : " (not judged: AddressSanitizer build)", ANON_SLOPE_KIB,
	         ANON_CAP_MIB, DRIFT_KIB, base.anon_mib);
	if (o.json) {
		json_t *j = json_object();
		json_object_set_new(j, "soak_minutes", bench_json_real(done * o.period_s / 60));
		json_object_set_new(j, "pass", json_boolean(pass));
		json_object_set_new(j, "criterion", json_string(crit));
		json_object_set_new(j, "baseline_heap_mib", bench_json_real(base.heap_mib));
		json_object_set_new(j, "baseline_anon_mib", bench_json_real(base.anon_mib));
		json_object_set_new(j, "baseline_rss_mib", bench_json_real(base.rss_mib));
		json_object_set_new(j, "baseline_fds", json_integer(base.fds));
		json_object_set_new(j, "baseline_threads", json_integer(base.threads));
		json_object_set_new(j, "max_heap_delta_mib", bench_json_real(max_heap));
		json_object_set_new(j, "max_anon_delta_mib", bench_json_real(max_anon));
		json_object_set_new(j, "max_rss_delta_mib", bench_json_real(max_rss));
		json_object_set_new(j, "heap_judged", json_boolean(heap_judged));
		json_object_set_new(j, "rss_judged", json_boolean(RSS_JUDGED));
		json_object_set_new(j, "slope_periods", json_pack("[i,i]", from, done));
		json_object_set_new(j, "heap_slope_kib_per_period", bench_json_real(heap_rate));
		json_object_set_new(j, "anon_slope_kib_per_period", bench_json_real(anon_rate));
		json_object_set_new(j, "heap_trend_mib_per_min", bench_json_real(heap_slope));
		json_object_set_new(j, "anon_trend_mib_per_min", bench_json_real(anon_slope));
		json_object_set_new(j, "samples_heap_over", json_integer(bad_heap));
		json_object_set_new(j, "samples_anon_over", json_integer(bad_anon));
		json_object_set_new(j, "samples_fds_differ", json_integer(bad_fd));
		json_object_set_new(j, "samples_threads_differ", json_integer(bad_thr));
		json_object_set_new(j, "frames", json_integer((json_int_t)frames));
		json_object_set_new(j, "damaged", json_integer((json_int_t)damaged));
		json_object_set_new(j, "differ", json_integer((json_int_t)differ));
		json_object_set_new(j, "fps_goal", bench_json_real(o.fps));
		json_object_set_new(j, "fps_mean", bench_json_real(done ? fps_sum / done : NAN));
		json_object_set_new(j, "fps_min", bench_json_real(done ? fps_min : NAN));
		json_object_set_new(j, "interrupted", json_boolean(soak_stop != 0));
		host->print_json(j);
	} else {
		printf("\n%s after %d minute(s)%s: heap in use %+.2f MiB at most from the baseline "
		       "%.1f MiB (%+.1f kB per period over periods %d..%d; trend %+.3f MiB/min), "
		       "anonymous RSS %+.2f MiB from %.1f MiB (%+.1f kB per period; trend %+.3f "
		       "MiB/min), RSS %+.1f MiB from %.1f MiB, fds %s, threads %s, %llu frames "
		       "differ; live rate %.1f fps on average (lowest minute %.1f) for the %g fps "
		       "goal, %llu damaged frames of %llu\ncriterion: %s\n",
		       pass ? "PASS" : "FAIL", done, soak_stop ? " (interrupted)" : "", max_heap,
		       base.heap_mib, heap_rate, from, done, heap_slope, max_anon, base.anon_mib,
		       anon_rate, anon_slope, max_rss, base.rss_mib, bad_fd ? "changed" : "flat",
		       bad_thr ? "changed" : "flat", (unsigned long long)differ,
		       done ? fps_sum / done : NAN, done ? fps_min : NAN, o.fps,
		       (unsigned long long)damaged, (unsigned long long)frames, crit);
	}
	/* the last capture is not kept */
	if (o.dir)
		nftw(capdir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
	else
		nftw(dir, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
	return pass ? PC_BENCH_OK : PC_BENCH_FAILURE;
}
