/* polarcam bench dataset: samples per second per core of `polarcam dataset` at 1224x1024 and
 * 2448x2048 (float32 and float16 truth), bytes per sample, and the projection for 10^6 samples
 * (core-hours, TB). One thread per sample, so the rate is per core; the CPU time of the process
 * is the measure (wall time is printed beside it: on a shared machine it is longer). The
 * baseline in the same run is the render alone (the family's scene → simulator → truth →
 * frames), against which the writing, hashing and manifest cost is a ratio. */
#include <getopt.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "polarcam/dataset.h"
#include "polarcam/error.h"

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam bench dataset [options]\n"
	    "\n"
	    "Makes a few samples of a scene family (polarcam dataset, one thread) at 1224x1024 "
	    "and\n"
	    "2448x2048 with float32 and float16 truth and prints samples/s per core (CPU time),\n"
	    "bytes per sample, and what 10^6 samples cost: core-hours and TB. The render alone is\n"
	    "the baseline: 'x render' is the whole pipeline's time over it.\n"
	    "\n"
	    "options:\n"
	    "  --spec FILE      the family (default scenes/dataset/demosaic.json here, or under\n"
	    "                   $PC_SOURCE_DIR)\n"
	    "  --count N        samples per row at 1224x1024 (default 3; half, at least 1, at\n"
	    "                   2448x2048)\n"
	    "  --dir DIR        where to write (default a temporary directory, removed after)\n"
	    "  --json           one JSON object per row\n");
}

static double cpu_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The spec with its truth dtype replaced, into path. */
static int spec_with_truth(const char *spec, const char *dtype, const char *path)
{
	json_error_t je;
	json_t *j = json_load_file(spec, 0, &je);
	if (!j)
		return pc_error(PC_EINVAL, "%s: line %d: %s", spec, je.line, je.text);
	json_object_set_new(j, "truth", json_string(dtype));
	/* mesh files stay where the spec is: absolute paths */
	char dir[4096];
	snprintf(dir, sizeof dir, "%s", spec);
	char *sl = strrchr(dir, '/');
	if (sl)
		*sl = 0;
	else
		snprintf(dir, sizeof dir, ".");
	char abs[4096];
	if (!realpath(dir, abs)) {
		json_decref(j);
		return pc_error(PC_EIO, "%s: cannot be resolved", dir);
	}
	json_t *shapes = json_object_get(json_object_get(j, "objects"), "shapes");
	for (size_t i = 0; i < json_array_size(shapes); i++) {
		json_t *f = json_object_get(json_array_get(shapes, i), "file");
		json_t *list = json_is_object(f) ? json_object_get(f, "choice") : NULL;
		size_t n = list ? json_array_size(list) : f ? 1 : 0;
		for (size_t k = 0; k < n; k++) {
			json_t *s = list ? json_array_get(list, k) : f;
			const char *v = json_string_value(s);
			if (v && v[0] != '/') {
				char p[8300];
				snprintf(p, sizeof p, "%s/%s", abs, v);
				json_string_set(s, p);
			}
		}
	}
	int rc = json_dump_file(j, path, JSON_INDENT(1))
	             ? pc_error(PC_EIO, "%s: cannot write", path)
	             : 0;
	json_decref(j);
	return rc;
}

int pc_bench_dataset(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	if (bench_wants_help(argc, argv)) {
		usage(stdout);
		return PC_BENCH_OK;
	}
	static const struct option opts[] = {{"spec", required_argument, NULL, 'S'},
	                                     {"count", required_argument, NULL, 'n'},
	                                     {"dir", required_argument, NULL, 'D'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {NULL, 0, NULL, 0}};
	const char *spec = NULL, *dir = NULL;
	long count = 3;
	bool json = false;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
		switch (c) {
		case 'S':
			spec = optarg;
			break;
		case 'n':
			if ((rc = host->parse_long("--count", optarg, 1, 1000, &count)))
				return host->fail(rc, NULL);
			break;
		case 'D':
			dir = optarg;
			break;
		case 'J':
			json = true;
			break;
		default:
			return host->error(PC_BENCH_USAGE, "bad option '%s' (see --help)",
			                   argv[optind - 1]);
		}
	}
	char specbuf[4096];
	if (!spec) {
		const char *src = getenv("PC_SOURCE_DIR");
		snprintf(specbuf, sizeof specbuf, "scenes/dataset/demosaic.json");
		if (access(specbuf, R_OK) && src)
			snprintf(specbuf, sizeof specbuf, "%s/scenes/dataset/demosaic.json", src);
		if (access(specbuf, R_OK))
			return host->error(PC_BENCH_USAGE,
			                   "no scenes/dataset/demosaic.json here: run from "
			                   "the source tree or pass --spec FILE");
		spec = specbuf;
	}
	char tmp[] = "/tmp/pc_bench_dataset_XXXXXX";
	const char *base = dir;
	if (!base) {
		if (!mkdtemp(tmp))
			return host->error(PC_BENCH_FAILURE, "cannot create a temporary directory");
		base = tmp;
	}
	static const struct {
		uint32_t w, h;
		const char *truth;
	} rows[] = {{1224, 1024, "float32"},
	            {1224, 1024, "float16"},
	            {2448, 2048, "float32"},
	            {2448, 2048, "float16"}};
	if (!json)
		printf("polarcam bench dataset: %s, one thread per sample (per core), CPU time\n\n"
		       "%-10s %-8s %5s %10s %9s %8s %12s %10s %12s %9s\n",
		       spec, "size", "truth", "n", "samples/s", "wall s/s", "x render", "MB/sample",
		       "render s", "core-h/1e6", "TB/1e6");
	int status = PC_BENCH_OK;
	for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++) {
		char sp[4400], out[4400];
		snprintf(sp, sizeof sp, "%s/spec-%s.json", base, rows[k].truth);
		snprintf(out, sizeof out, "%s/%ux%u-%s", base, rows[k].w, rows[k].h, rows[k].truth);
		if ((rc = spec_with_truth(spec, rows[k].truth, sp))) {
			status = host->fail(rc, spec);
			break;
		}
		pc_dataset_options o;
		memset(&o, 0, sizeof o);
		o.spec = sp;
		o.dir = out;
		o.seed = 1;
		o.count =
		    rows[k].w > 2000 ? (uint64_t)(count / 2 > 0 ? count / 2 : 1) : (uint64_t)count;
		o.shards = 1;
		o.width = rows[k].w;
		o.height = rows[k].h;
		o.threads = 1;
		pc_dataset_result r;
		double c0 = cpu_now(), t0 = bench_now();
		rc = pc_dataset_run(&o, &r);
		double cpu = cpu_now() - c0, wall = bench_now() - t0;
		if (rc) {
			status = host->fail(rc, out);
			break;
		}
		double per_core = (double)r.made / cpu, bytes = (double)r.bytes / (double)r.made;
		double core_h = 1e6 / per_core / 3600, tb = 1e6 * bytes / 1e12;
		double ratio = (r.render_s + r.write_s) / r.render_s;
		if (json) {
			json_t *j = json_object();
			json_object_set_new(j, "width", json_integer(rows[k].w));
			json_object_set_new(j, "height", json_integer(rows[k].h));
			json_object_set_new(j, "truth", json_string(rows[k].truth));
			json_object_set_new(j, "samples", json_integer((json_int_t)r.made));
			json_object_set_new(j, "samples_per_s_per_core", bench_json_real(per_core));
			json_object_set_new(j, "wall_s_per_sample",
			                    bench_json_real(wall / (double)r.made));
			json_object_set_new(j, "pipeline_over_render", bench_json_real(ratio));
			json_object_set_new(j, "bytes_per_sample", bench_json_real(bytes));
			json_object_set_new(j, "core_hours_per_1e6", bench_json_real(core_h));
			json_object_set_new(j, "tb_per_1e6", bench_json_real(tb));
			host->print_json(j);
		} else {
			printf(
			    "%4ux%-5u %-8s %5llu %10.3f %9.2f %8.2f %12.2f %10.2f %12.0f %9.2f\n",
			    rows[k].w, rows[k].h, rows[k].truth, (unsigned long long)r.made,
			    per_core, wall / (double)r.made, ratio, bytes / 1e6,
			    r.render_s / (double)r.made, core_h, tb);
		}
		fflush(stdout);
	}
	if (!json && status == PC_BENCH_OK) {
		double la[3];
		bench_loadavg_values(la);
		printf("\nsamples/s: per core from the process's CPU time; wall s/s: wall seconds "
		       "per sample "
		       "(longer on a shared machine); x render: (render + write + SHA-256 + "
		       "manifest) / "
		       "render; MB/sample: raw PNG + truth + scene + meta; core-h and TB for 10^6 "
		       "samples "
		       "at that rate and size. Load average at the end: %.2f %.2f %.2f on %ld "
		       "cores.\n",
		       la[0], la[1], la[2], sysconf(_SC_NPROCESSORS_ONLN));
	}
	if (!dir) {
		char cmd[200];
		snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
		if (system(cmd) != 0)
			fprintf(stderr, "bench dataset: could not remove %s\n", tmp);
	}
	return status;
}
