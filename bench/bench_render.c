/* polarcam bench render: render and sensor time per effect set, against the minimal effect set
 * measured in the same run; peak memory per set. */
#include <getopt.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/parallel.h"
#include "polarcam/sim.h"
#include "polarcam/source.h"

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam bench render [options]\n"
	    "\n"
	    "Renders the default scene with one effect set after another and reports, for each,\n"
	    "the render time (ray casting + pBRDF + analyser, done once per scene state), the "
	    "time\n"
	    "of one raw frame (the sensor chain, paid by every frame), the first frame (both), "
	    "the\n"
	    "throughput in Mpixel/s, the ratio to the minimal effect set measured in the same run\n"
	    "(the baseline) and the peak memory above the process's idle size.\n"
	    "\n"
	    "options:\n"
	    "  --size WxH          image size (default 2448x2048; smaller keeps the field of "
	    "view)\n"
	    "  --frames N          frames timed per set (default 3)\n"
	    "  --repeat R          repeat each measurement R times, keep the fastest (default 2):\n"
	    "                      the machine is shared, the minimum is the least disturbed run\n"
	    "  -t, --threads N     threads (default: all cores)\n"
	    "  --sets LIST         comma-separated subset of the sets below\n"
	    "  --stream S          also stream sim:default (2448x2048, every sensor effect) "
	    "unpaced\n"
	    "                      for S seconds and report its frame rate (default 3; 0 = skip)\n"
	    "  --json              one JSON object on stdout instead of the table\n"
	    "sets: minimal, diffuse, shadowing, cast_shadows, circular, supersampling2, blur1 "
	    "(the\n"
	    "      lens blur at sigma 1 px), mueller,\n"
	    "      noise, prnu_dsnu, extinction_ratio, orientation_error, transmission, "
	    "crosstalk,\n"
	    "      default (the default scene as shipped: diffuse + shadowing + cast shadows +\n"
	    "      circular + the IMX250MZR preset's sensor effects), default+mueller.\n");
}

typedef struct fxset {
	const char *name;
	const char *render_fx; /* render effects on top of the minimal set (JSON object members) */
	const char *sensor_fx; /* sensor effects on (JSON object members) */
	bool mueller_truth;
} fxset;

static const fxset sets[] = {
    {"minimal", "", "", false},
    {"diffuse", "\"diffuse\": true", "", false},
    {"shadowing", "\"shadowing\": true", "", false},
    {"cast_shadows", "\"cast_shadows\": true", "", false},
    {"circular", "\"circular\": true", "", false},
    {"supersampling2", "\"supersampling\": 2", "", false},
    {"blur1", "\"blur\": 1", "", false},
    {"mueller", "\"mueller\": true", "", true},
    {"noise", "", "\"noise\": true", false},
    {"prnu_dsnu", "", "\"prnu_dsnu\": true", false},
    {"extinction_ratio", "", "\"extinction_ratio\": true", false},
    {"orientation_error", "", "\"orientation_error\": true", false},
    {"transmission", "", "\"transmission\": true", false},
    {"crosstalk", "", "\"crosstalk\": true", false},
    {"default", "DEFAULT", "", false},
    {"default+mueller", "DEFAULT", "\"mueller\": true", true},
};

/* The default scene with its effects replaced: render effects from set, every sensor effect
 * off unless listed (the preset declares them all). */
static char *scene_for(const fxset *s, uint32_t w, uint32_t h)
{
	json_t *d = json_loads(pc_scene_default_text(), 0, NULL);
	if (!d)
		return NULL;
	json_t *sen = json_object_get(d, "sensor");
	/* keep the field of view and the signal per pixel when the size changes */
	double ratio = 2448.0 / w;
	json_object_set_new(sen, "resolution", json_pack("[i, i]", (int)w, (int)h));
	json_object_set_new(sen, "pixel_pitch_um", json_real(3.45 * ratio));
	json_t *exp = json_object_get(sen, "exposure_us");
	json_object_set_new(sen, "exposure_us",
	                    json_real(json_number_value(exp) / (ratio * ratio)));
	if (strcmp(s->render_fx, "DEFAULT")) {
		char buf[512];
		snprintf(buf, sizeof buf,
		         "{\"noise\": false, \"prnu_dsnu\": false, \"extinction_ratio\": false, "
		         "\"orientation_error\": false, \"transmission\": false, \"crosstalk\": "
		         "false%s%s%s%s}",
		         *s->render_fx ? ", " : "", s->render_fx, *s->sensor_fx ? ", " : "",
		         s->sensor_fx);
		json_t *fx = json_loads(buf, 0, NULL);
		json_object_set_new(d, "effects", fx);
	} else if (*s->sensor_fx) {
		char buf[256];
		snprintf(buf, sizeof buf, "{%s}", s->sensor_fx);
		json_t *fx = json_object_get(d, "effects");
		json_t *add = json_loads(buf, 0, NULL);
		json_object_update(fx, add);
		json_decref(add);
	}
	char *t = json_dumps(d, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(d);
	return t;
}

/* Resets the kernel's peak-RSS counter (Linux ≥ 4.0), so that VmHWM measures one set. */
static void reset_peak(void)
{
	FILE *fp = fopen("/proc/self/clear_refs", "w");
	if (fp) {
		fputs("5", fp);
		fclose(fp);
	}
}

static double rss_mib(const char *key)
{
	FILE *fp = fopen("/proc/self/status", "r");
	if (!fp)
		return NAN;
	char line[256];
	double kb = NAN;
	size_t kl = strlen(key);
	while (fgets(line, sizeof line, fp))
		if (!strncmp(line, key, kl))
			kb = strtod(line + kl, NULL);
	fclose(fp);
	return kb / 1024;
}

static double cpu_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Frames per second of the sim: source streaming the default scene unpaced for `seconds`
 * (after one warm-up frame): the live simulator's ceiling, the sensor chain per frame. */
static double stream_fps(double seconds, long threads, uint64_t *frames)
{
	char uri[64];
	snprintf(uri, sizeof uri, "sim:default?fps=0&threads=%ld", threads);
	pc_source *s = NULL;
	int rc = pc_source_open(&s, uri);
	if (!rc)
		rc = pc_source_buffers_alloc(s, 3);
	if (!rc)
		rc = pc_source_start(s);
	double t0 = 0, t1 = 0;
	uint64_t n = 0;
	while (!rc) {
		pc_buffer *b = NULL;
		if ((rc = pc_source_dequeue(s, 600000, &b)))
			break;
		t1 = bench_now();
		if (n++ == 0)
			t0 = t1;
		rc = pc_source_requeue(s, b);
		if (t1 - t0 >= seconds && n >= 3)
			break;
	}
	if (s && pc_source_get_state(s) == PC_SOURCE_STREAMING)
		pc_source_stop(s);
	pc_source_close(s);
	*frames = n;
	return !rc && n >= 2 ? (double)(n - 1) / (t1 - t0) : NAN;
}

typedef struct result {
	const char *name;
	double setup_s, render_s, frame_s, render_cpu, frame_cpu, peak_mib;
	unsigned effects;
	int rc;
} result;

int pc_bench_render(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	if (bench_wants_help(argc, argv)) {
		usage(stdout);
		return PC_BENCH_OK;
	}
	static const struct option opts[] = {
	    {"size", required_argument, NULL, 'S'},    {"frames", required_argument, NULL, 'n'},
	    {"threads", required_argument, NULL, 't'}, {"sets", required_argument, NULL, 'L'},
	    {"json", no_argument, NULL, 'J'},          {"repeat", required_argument, NULL, 'R'},
	    {"stream", required_argument, NULL, 'T'},  {NULL, 0, NULL, 0}};
	unsigned W = 2448, H = 2048;
	long frames = 3, threads = 0, repeat = 2;
	double stream_s = 3;
	const char *only = NULL;
	bool json = false;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":t:", opts, NULL)) != -1) {
		switch (c) {
		case 'S':
			if (sscanf(optarg, "%ux%u", &W, &H) != 2 || W < 8 || H < 8 || W > 16384 ||
			    H > 16384 || W % 2 || H % 2)
				return host->error(PC_BENCH_USAGE,
				                   "--size '%s': expected WxH, even, 8..16384",
				                   optarg);
			break;
		case 'n':
			if ((rc = host->parse_long("--frames", optarg, 1, 1000, &frames)))
				return host->fail(rc, NULL);
			break;
		case 't':
			if ((rc = host->parse_long("--threads", optarg, 1, 1024, &threads)))
				return host->fail(rc, NULL);
			break;
		case 'L':
			only = optarg;
			break;
		case 'R':
			if ((rc = host->parse_long("--repeat", optarg, 1, 100, &repeat)))
				return host->fail(rc, NULL);
			break;
		case 'J':
			json = true;
			break;
		case 'T':
			if ((rc = host->parse_double("--stream", optarg, &stream_s)) ||
			    stream_s < 0 || stream_s > 600)
				return host->error(PC_BENCH_USAGE,
				                   "--stream '%s': seconds in [0, 600]", optarg);
			break;
		default:
			return host->error(PC_BENCH_USAGE, "bad option '%s' (see --help)",
			                   argv[optind - 1]);
		}
	}
	const size_t nsets = sizeof sets / sizeof sets[0];
	if (only) {
		char buf[512];
		snprintf(buf, sizeof buf, ",%s,", only);
		for (char *p = strtok(buf + 1, ","); p; p = strtok(NULL, ",")) {
			bool ok = false;
			for (size_t i = 0; i < nsets; i++)
				ok |= !strcmp(p, sets[i].name);
			if (!ok)
				return host->error(PC_BENCH_USAGE,
				                   "--sets: unknown set '%s' (see --help)", p);
		}
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	result res[sizeof sets / sizeof sets[0]];
	memset(res, 0, sizeof res);
	int nthreads = threads ? (int)threads : pc_parallel_max_threads();
	double idle = rss_mib("VmRSS:");
	const double mpix = (double)W * H / 1e6;
	for (size_t i = 0; i < nsets; i++) {
		res[i].name = sets[i].name;
		res[i].rc = 1; /* not run */
		if (only && i != 0) {
			char pat[64], buf[512];
			snprintf(pat, sizeof pat, ",%s,", sets[i].name);
			snprintf(buf, sizeof buf, ",%s,", only);
			if (!strstr(buf, pat))
				continue;
		}
		char *text = scene_for(&sets[i], W, H);
		pc_scene *scene = NULL;
		pc_sim *sim = NULL;
		float *tm = NULL;
		pc_view v = {0};
		rc = text ? pc_scene_parse(text, sets[i].name, ".", &scene) : PC_ENOMEM;
		free(text);
		pc_sim_options o = pc_sim_options_default();
		o.seed = 1;
		o.threads = (int)threads;
		reset_peak();
		double t0 = bench_now();
		if (!rc)
			rc = pc_sim_new(scene, &o, &sim);
		res[i].setup_s = bench_now() - t0;
		if (!rc && sets[i].mueller_truth) {
			tm = malloc((size_t)W * H * 16 * sizeof *tm);
			rc = tm ? 0 : PC_ENOMEM;
		}
		res[i].render_s = res[i].frame_s = res[i].render_cpu = res[i].frame_cpu = INFINITY;
		pc_sim_info in;
		for (long r = 0; r < repeat && !rc; r++) {
			/* a fresh simulator per repetition: nothing cached */
			if (r > 0) {
				pc_sim_free(sim);
				sim = NULL;
				rc = pc_sim_new(scene, &o, &sim);
				if (rc)
					break;
			}
			t0 = bench_now();
			double c0 = cpu_now();
			rc = pc_sim_prepare(sim, 0, NULL, tm, NULL, NULL);
			res[i].render_s = fmin(res[i].render_s, bench_now() - t0);
			res[i].render_cpu = fmin(res[i].render_cpu, cpu_now() - c0);
			if (rc)
				break;
			if (!v.data) {
				pc_sim_get_info(sim, &in);
				res[i].effects = in.effects;
				if ((rc = pc_view_alloc(&v, in.format, in.width, in.height, 64)))
					break;
			}
			t0 = bench_now();
			c0 = cpu_now();
			for (long f = 0; f < frames && !rc; f++)
				rc = pc_sim_frame(sim, (uint64_t)f, NULL, &v, NULL);
			res[i].frame_s = fmin(res[i].frame_s, (bench_now() - t0) / (double)frames);
			res[i].frame_cpu =
			    fmin(res[i].frame_cpu, (cpu_now() - c0) / (double)frames);
		}
		res[i].peak_mib = rss_mib("VmHWM:") - idle;
		res[i].rc = rc;
		if (rc)
			fprintf(stderr, "polarcam bench render: %s: %s\n", sets[i].name,
			        pc_error_detail());
		pc_view_free(&v);
		free(tm);
		pc_sim_free(sim);
		pc_scene_free(scene);
	}
	const result *base = &res[0];
	double frame_mib = (double)W * H * 2 / (1 << 20);
	uint64_t stream_n = 0;
	double sfps = stream_s > 0 ? stream_fps(stream_s, threads, &stream_n) : NAN;
	if (json) {
		json_t *o = json_object();
		json_object_set_new(o, "width", json_integer(W));
		json_object_set_new(o, "height", json_integer(H));
		json_object_set_new(o, "threads", json_integer(nthreads));
		json_object_set_new(o, "frames_timed", json_integer(frames));
		json_object_set_new(o, "sim_stream_fps", bench_json_real(sfps));
		json_object_set_new(o, "sim_stream_frames", json_integer((json_int_t)stream_n));
		json_object_set_new(o, "raw_frame_mib", json_real(frame_mib));
		json_object_set_new(o, "baseline", json_string(base->name));
		json_t *a = json_array();
		for (size_t i = 0; i < nsets; i++) {
			if (res[i].rc)
				continue;
			json_t *e = json_object();
			json_object_set_new(e, "set", json_string(res[i].name));
			json_t *fx = json_array();
			for (unsigned b = 0; b < PC_FX_COUNT_; b++)
				if (res[i].effects & (1u << b))
					json_array_append_new(
					    fx, json_string(pc_sim_effect_name(1u << b)));
			json_object_set_new(e, "effects", fx);
			json_object_set_new(e, "setup_s", json_real(res[i].setup_s));
			json_object_set_new(e, "render_s", json_real(res[i].render_s));
			json_object_set_new(e, "render_cpu_s", json_real(res[i].render_cpu));
			json_object_set_new(e, "frame_cpu_s", json_real(res[i].frame_cpu));
			json_object_set_new(e, "frame_s", json_real(res[i].frame_s));
			json_object_set_new(e, "first_frame_s",
			                    json_real(res[i].render_s + res[i].frame_s));
			json_object_set_new(e, "render_mpix_s", json_real(mpix / res[i].render_s));
			json_object_set_new(e, "frame_mpix_s", json_real(mpix / res[i].frame_s));
			json_object_set_new(e, "render_ratio",
			                    json_real(res[i].render_s / base->render_s));
			json_object_set_new(e, "frame_ratio",
			                    json_real(res[i].frame_s / base->frame_s));
			json_object_set_new(e, "peak_mib", bench_json_real(res[i].peak_mib));
			json_array_append_new(a, e);
		}
		json_object_set_new(o, "sets", a);
		host->print_json(o);
	} else {
		printf("polarcam bench render: default scene %ux%u (%.2f Mpixel), %d thread%s, %ld "
		       "frame%s "
		       "timed per set\n"
		       "baseline = minimal (specular pBRDF only, ideal noise-free sensor), same "
		       "run\n\n",
		       W, H, mpix, nthreads, nthreads == 1 ? "" : "s", frames,
		       frames == 1 ? "" : "s");
		printf("%-18s %8s %8s %7s %7s %8s %8s %7s %7s %10s %8s\n", "effect set", "render s",
		       "Mpix/s", "x base", "cpu s", "frame s", "Mpix/s", "x base", "cpu s",
		       "1st frame", "peak MiB");
		for (size_t i = 0; i < nsets; i++) {
			if (res[i].rc)
				continue;
			printf(
			    "%-18s %8.3f %8.2f %7.2f %7.3f %8.3f %8.2f %7.2f %7.3f %10.3f %8.0f\n",
			    res[i].name, res[i].render_s, mpix / res[i].render_s,
			    res[i].render_s / base->render_s, res[i].render_cpu, res[i].frame_s,
			    mpix / res[i].frame_s, res[i].frame_s / base->frame_s, res[i].frame_cpu,
			    res[i].render_s + res[i].frame_s, res[i].peak_mib);
		}
		printf("\nrender: ray casting, pBRDF and analyser, once per scene state (cached); "
		       "frame: the "
		       "sensor chain, per frame; 1st frame = both; wall seconds (fastest of %ld), "
		       "cpu s = "
		       "process CPU time over all threads. Setup (pBRDF tables, BVH) is excluded.\n"
		       "peak MiB: the process's peak resident memory above its idle size during "
		       "the set; "
		       "one raw %ux%u 16-bit frame is %.1f MiB.\n",
		       repeat, W, H, frame_mib);
		if (stream_s > 0)
			printf("sim: stream, default scene 2448x2048 with every sensor effect, "
			       "unpaced: "
			       "%.1f frames/s (%llu frames; the IMX250MZR delivers 75)\n",
			       sfps, (unsigned long long)stream_n);
	}
	return PC_BENCH_OK;
}
