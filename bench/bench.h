/* bench/bench.h - benchmarks behind `polarcam bench NAME`. Each prints a table (and JSON with
 * --json) of ratios against a baseline measured in the same run.
 *
 * The benchmarks link only the libraries; what they need from the program that runs them
 * (messages with its name, option values parsed with errors that name the option, JSON lines,
 * progress on the terminal) comes through a pc_bench_host, so that bench/ does not depend on
 * tools/. */
#ifndef POLARCAM_BENCH_H
#define POLARCAM_BENCH_H

#include <dirent.h>
#include <jansson.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "polarcam/progress.h"

/* Exit statuses, as the CLI's. */
enum { PC_BENCH_OK = 0, PC_BENCH_FAILURE = 1, PC_BENCH_USAGE = 2 };

typedef struct pc_bench_host {
	/* Prints an error; returns status. */
	int (*error)(int status, const char *fmt, ...)
#if defined(__GNUC__)
	    __attribute__((format(printf, 2, 3)))
#endif
	    ;
	/* Prints a library error (pc_error_detail) after what; returns the exit status for code. */
	int (*fail)(int code, const char *what);
	void (*warn)(const char *fmt, ...)
#if defined(__GNUC__)
	    __attribute__((format(printf, 1, 2)))
#endif
	    ;
	/* An integer in [min, max] / a finite number, or PC_EINVAL naming opt. */
	int (*parse_long)(const char *opt, const char *arg, long min, long max, long *out);
	int (*parse_double)(const char *opt, const char *arg, double *out);
	/* One JSON value as a line on stdout (consumes it). */
	void (*print_json)(json_t *value);
	/* Progress: a phase (its own bar), and the end of the last one. */
	pc_progress progress;
	void (*progress_end)(void *progress_user);
	/* Stop after parsing the arguments, with PC_BENCH_OK (the CLI's POLARCAM_PARSE_ONLY). */
	bool parse_only;
} pc_bench_host;

int pc_bench_physics(const pc_bench_host *host, int argc, char **argv);
int pc_bench_demosaic(const pc_bench_host *host, int argc, char **argv);
int pc_bench_colour(const pc_bench_host *host, int argc, char **argv);
int pc_bench_render(const pc_bench_host *host, int argc, char **argv);
int pc_bench_devices(const pc_bench_host *host, int argc, char **argv);
int pc_bench_calib(const pc_bench_host *host, int argc, char **argv);
int pc_bench_dataset(const pc_bench_host *host, int argc, char **argv);
int pc_bench_soak(const pc_bench_host *host, int argc, char **argv);

/* bench_calib.c: the calibrated bilinear pipeline as `--calibration` runs it (pc_calib_apply,
 * the compact calibration, with the mask) and the uncalibrated one with the black level, the
 * saturation check and the mask (what `process` runs), on bench calib --speed's synthetic W×H
 * calibration and Mono12 frame, reps of each interleaved on threads (0: all): wall ms median
 * and min, [0] uncalibrated, [1] calibrated. For `bench demosaic`'s summary. */
int bench_calib_pair(uint32_t w, uint32_t h, int reps, int threads, double med_ms[2],
                     double min_ms[2]);

/* Benchmarks that stream GigE Vision run in a private network namespace with only loopback:
 * outside one, this re-executes `polarcam bench argv...` under `unshare -n` (never returns when
 * that works; the failure status otherwise); inside one (PC_BENCH_NETNS set) it returns 0. */
int bench_netns_reexec(const pc_bench_host *host, int argc, char **argv);

/* ---- small helpers of the benchmark files ---- */

/* Non-finite numbers become JSON null. */
static inline json_t *bench_json_real(double v)
{
	return isfinite(v) ? json_real(v) : json_null();
}

/* Monotonic time in seconds. */
static inline double bench_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of the whole process (all threads), seconds: unlike wall time, it does not grow
 * while the shared machine's other work holds the cores. */
static inline double bench_cpu_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* qsort comparators: C strings (through char *), doubles ascending */
static inline int bench_cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

static inline int bench_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

/* The line of /proc/loadavg ("" where the system has none). */
static inline void bench_loadavg(char *buf, size_t n)
{
	FILE *fp = fopen("/proc/loadavg", "r");
	buf[0] = '\0';
	if (fp) {
		if (!fgets(buf, (int)n, fp))
			buf[0] = '\0';
		fclose(fp);
	}
	buf[strcspn(buf, "\n")] = '\0';
}

/* The 1, 5 and 15 minute load averages of /proc/loadavg: 0, or -1 (la[] NaN) where the system
 * has none. */
static inline int bench_loadavg_values(double la[3])
{
	la[0] = la[1] = la[2] = NAN;
	FILE *fp = fopen("/proc/loadavg", "r");
	int n = fp ? fscanf(fp, "%lf %lf %lf", &la[0], &la[1], &la[2]) : 0;
	if (fp)
		fclose(fp);
	if (n == 3)
		return 0;
	la[0] = la[1] = la[2] = NAN;
	return -1;
}

/* The entries of directory dir not starting with '.', in name order (a dataset's scenes):
 * *names (free each and the array) and their count; 0 entries when dir cannot be opened. */
static inline size_t bench_list_dir(const char *dir, char ***names)
{
	*names = NULL;
	size_t n = 0;
	DIR *dd = opendir(dir);
	if (!dd)
		return 0;
	struct dirent *de;
	while ((de = readdir(dd))) {
		if (de->d_name[0] == '.')
			continue;
		char **nn = realloc(*names, sizeof **names * (n + 1));
		if (!nn)
			break;
		*names = nn;
		(*names)[n] = strdup(de->d_name);
		if ((*names)[n])
			n++;
	}
	closedir(dd);
	if (n)
		qsort(*names, n, sizeof **names, bench_cmp_str);
	return n;
}

/* True when argv holds -h or --help (before a "--"). */
static inline bool bench_wants_help(int argc, char **argv)
{
	for (int i = 1; i < argc && strcmp(argv[i], "--"); i++)
		if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help"))
			return true;
	return false;
}

#endif
