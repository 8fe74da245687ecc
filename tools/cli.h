/* tools/cli.h - what every polarcam command shares: argument parsing with errors that name the
 * argument, exit statuses, JSON lines on stdout, progress on stderr. */
#ifndef CLI_TOOLS_CLI_H
#define CLI_TOOLS_CLI_H

#include <jansson.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* Exit statuses of every command (README, "Conventions"). */
enum {
	CLI_EXIT_OK = 0,
	CLI_EXIT_FAILURE = 1,      /* the work failed (I/O, device, numerics) */
	CLI_EXIT_USAGE = 2,        /* bad arguments, bad input data, an output that exists */
	CLI_EXIT_UNAVAILABLE = 77, /* a backend not built in, a device or display absent */
};

/* The running command's name ("pbrdf"), set by main, used in messages. */
extern const char *cli_name;

/* The output rule of every command: stdout carries results only (JSON lines with --json; the
 * command's table where it prints one), stderr carries progress, messages, warnings and errors.
 * --quiet (-q), taken out of argv by main for every command, leaves only errors on stderr. */
extern bool cli_quiet;

/* A message on stderr ("polarcam CMD: <fmt>") unless --quiet. */
void cli_info(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* True when POLARCAM_PARSE_ONLY=1: commands stop after parsing their arguments, with exit
 * status 0 (the test of the examples in every --help uses it). */
bool cli_parse_only(void);

/* Prints "polarcam CMD: error: <fmt>" to stderr and returns status. */
int cli_error(int status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Prints "polarcam CMD: error: <what>: <pc_error_detail() or pc_strerror(code)>" and returns
 * cli_status(code). */
int cli_fail(int code, const char *what);

/* Exit status for a library error code: CLI_EXIT_USAGE for input errors (PC_EINVAL, PC_ERANGE,
 * PC_EFORMAT, PC_ENOENT) and an output that exists (PC_EEXIST), CLI_EXIT_UNAVAILABLE for
 * PC_EUNAVAIL, CLI_EXIT_FAILURE for the others. */
int cli_status(int code);

/* Prints a warning to stderr (unless --quiet). */
void cli_warn(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

/* Parses a finite double (subnormal values are kept; text that underflows to 0 or overflows is
 * refused); on failure sets the error detail naming opt and returns PC_EINVAL. */
int cli_parse_double(const char *opt, const char *arg, double *out);
/* Integers are decimal: digits only (a leading '-' where min < 0), no sign, space, 0x prefix or
 * octal reading of a leading 0; text after the digits and values outside [min, max] are refused
 * with a message that names opt and states the range. */
int cli_parse_long(const char *opt, const char *arg, long min, long max, long *out);
int cli_parse_u64_range(const char *opt, const char *arg, uint64_t min, uint64_t max,
                        uint64_t *out);
/* [0, UINT64_MAX] */
int cli_parse_u64(const char *opt, const char *arg, uint64_t *out);

/* The pictures' --mask-s0 T and --dolp-max V|auto (process, view; their help texts) into the
 * conventions of pc_pictures_opts (polarcam/io.h): *mask_s0 T > 0, or -1 for 0 (no mask);
 * *dolp_hi V in (0, 1], or -1 for auto. Errors name the option. */
int cli_parse_picture_opt(const char *opt, const char *arg, double *mask_s0, double *dolp_hi);

/* Untrusted text (an argument, a token of a batch line) for a message: the first len bytes of s
 * with control bytes and bytes that are not UTF-8 written as \xNN, cut with "..." to fit size
 * (>= 8). Returns buf. cli_error and cli_warn pass every message through it. */
const char *cli_quote(const char *s, size_t len, char *buf, size_t size);

/* A numeric option that may be a range "start:stop:step" (inclusive of stop within
 * step·1e-9). values is malloc'd. */
int cli_parse_range(const char *opt, const char *arg, double **values, size_t *count);

/* True when argv holds -h or --help. */
bool cli_wants_help(int argc, char **argv);

/* Prints one JSON value as a compact line on stdout (17 significant digits) and decrefs it. */
void cli_print_json(json_t *value);

/* Non-finite numbers become JSON null. */
json_t *cli_json_real(double v);
json_t *cli_json_matrix4(const double m[4][4]);
json_t *cli_json_vec(const double *v, unsigned n);

/* Progress on stderr for long work: shown when stderr is a terminal or POLARCAM_PROGRESS=1,
 * never when POLARCAM_PROGRESS=0 or --quiet. Rate-limited to ~10 updates per second. */
typedef struct cli_progress {
	const char *label;
	uint64_t total;
	double t_start, t_last;
	bool enabled;
	bool drawn;
} cli_progress;

void cli_progress_begin(cli_progress *p, const char *label, uint64_t total);
void cli_progress_update(cli_progress *p, uint64_t done);
void cli_progress_end(cli_progress *p);

/* A pc_progress_fn (polarcam/progress.h) drawing cli_progress bars: user is a zeroed
 * cli_progress; each new phase ends the bar of the previous one and starts its own, labelled
 * with the phase. Finish with cli_progress_end. Never asks to stop. */
int cli_progress_fn(void *user, const char *phase, uint64_t done, uint64_t total);

/* Long commands (capture, render, view, serve) stop cleanly on SIGINT/SIGTERM:
 * cli_catch_signals() installs the handlers, which set cli_stop_requested; a second signal
 * while the command is still finishing ends the process at once (the signal's default). */
extern volatile sig_atomic_t cli_stop_requested;
void cli_catch_signals(void);
/* cli_progress_fn (user may be NULL: no bar) that asks the library call to stop once a signal
 * came. */
int cli_progress_stoppable(void *user, const char *phase, uint64_t done, uint64_t total);

/* Monotonic time in seconds. */
double cli_now(void);

/* Line-oriented input for --batch FILE|-: "-" is stdin. Blank lines and lines starting with '#'
 * are skipped; line numbers count every line (1-based), for error messages. */
typedef struct cli_lines {
	FILE *fp;
	const char *name; /* the path as given, "stdin" for "-" */
	char *buf;
	size_t cap;
	unsigned long lineno;
	size_t len; /* bytes of the last data line (NUL bytes included, newline excluded) */
} cli_lines;

/* Opens path (error detail names it). */
int cli_lines_open(cli_lines *l, const char *path);
/* The next data line in *line (valid until the next call): 1, 0 at the end, < 0 on a read error. */
int cli_lines_next(cli_lines *l, char **line);
void cli_lines_close(cli_lines *l);

/* Parses exactly `want` whitespace-separated finite numbers; names[i] names field i in errors
 * ("field 3 (sigma) 'abc': not a number", "expected 6 numbers (n k sigma ...), got 5"). */
int cli_parse_fields(const char *line, const char *const *names, int want, double *out);
/* The same for the first n bytes of line, which may hold NUL bytes (refused: PC_EFORMAT naming
 * the byte): pass cli_lines.len for a batch line. */
int cli_parse_fields_n(const char *line, size_t n, const char *const *names, int want, double *out);

/* {"line": L, "error": <detail>, "code": "PC_E..."}: the batch-mode error object. */
json_t *cli_json_error_line(unsigned long line, int code);

/* A bad batch line: prefixes the detail with "FILE line L: ", prints the error object on stdout
 * and the message on stderr, and sets *status (if still 0) to the exit status for rc. */
void cli_batch_error(const cli_lines *in, int rc, int *status);

#endif
