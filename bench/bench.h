/* bench/bench.h - benchmarks behind `polarcam bench NAME`. Each prints a table (and JSON with
 * --json) of ratios against a baseline measured in the same run.
 *
 * The benchmarks link only the libraries; what they need from the program that runs them
 * (messages with its name, option values parsed with errors that name the option, JSON lines,
 * progress on the terminal) comes through a pc_bench_host, so that bench/ does not depend on
 * tools/. */
#ifndef POLARCAM_BENCH_H
#define POLARCAM_BENCH_H

#include <jansson.h>
#include <math.h>
#include <stdbool.h>
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

/* True when argv holds -h or --help (before a "--"). */
static inline bool bench_wants_help(int argc, char **argv)
{
	for (int i = 1; i < argc && strcmp(argv[i], "--"); i++)
		if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help"))
			return true;
	return false;
}

#endif
