#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "polarcam/error.h"

const char *cli_name = "";
bool cli_quiet;

void cli_info(const char *fmt, ...)
{
	if (cli_quiet)
		return;
	va_list ap;
	fprintf(stderr, "polarcam %s: ", cli_name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

bool cli_parse_only(void)
{
	const char *e = getenv("POLARCAM_PARSE_ONLY");
	return e && !strcmp(e, "1");
}

int cli_error(int status, const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "polarcam %s: error: ", cli_name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	return status;
}

void cli_warn(const char *fmt, ...)
{
	if (cli_quiet)
		return;
	va_list ap;
	fprintf(stderr, "polarcam %s: warning: ", cli_name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
}

int cli_status(int code)
{
	switch (code) {
	case PC_OK:
		return CLI_EXIT_OK;
	case PC_EINVAL:
	case PC_ERANGE:
	case PC_EFORMAT:
	case PC_ENOENT:
	case PC_EEXIST:
		return CLI_EXIT_USAGE;
	case PC_EUNAVAIL:
		return CLI_EXIT_UNAVAILABLE;
	default:
		return CLI_EXIT_FAILURE;
	}
}

int cli_fail(int code, const char *what)
{
	const char *d = pc_error_detail();
	if (what && *what)
		cli_error(0, "%s: %s", what, *d ? d : pc_strerror(code));
	else
		cli_error(0, "%s", *d ? d : pc_strerror(code));
	return cli_status(code);
}

int cli_parse_double(const char *opt, const char *arg, double *out)
{
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value (expected a number)", opt);
	char *end;
	errno = 0;
	double v = strtod(arg, &end);
	if (end == arg || *end != '\0')
		return pc_error(PC_EINVAL, "%s '%s': not a number", opt, arg);
	if (!isfinite(v) || errno == ERANGE)
		return pc_error(PC_EINVAL, "%s '%s': expected a finite number", opt, arg);
	*out = v;
	return 0;
}

int cli_parse_long(const char *opt, const char *arg, long min, long max, long *out)
{
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value (expected an integer)", opt);
	char *end;
	errno = 0;
	long v = strtol(arg, &end, 10);
	if (end == arg || *end != '\0' || errno)
		return pc_error(PC_EINVAL, "%s '%s': not an integer", opt, arg);
	if (v < min || v > max)
		return pc_error(PC_EINVAL, "%s %ld: expected an integer in [%ld, %ld]", opt, v, min, max);
	*out = v;
	return 0;
}

int cli_parse_u64(const char *opt, const char *arg, uint64_t *out)
{
	if (!arg || !*arg || *arg == '-')
		return pc_error(PC_EINVAL, "%s '%s': expected a non-negative integer", opt,
				arg ? arg : "");
	char *end;
	errno = 0;
	unsigned long long v = strtoull(arg, &end, 0);
	if (end == arg || *end != '\0' || errno)
		return pc_error(PC_EINVAL, "%s '%s': not a non-negative integer", opt, arg);
	*out = v;
	return 0;
}

int cli_parse_range(const char *opt, const char *arg, double **values, size_t *count)
{
	*values = NULL;
	*count = 0;
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value", opt);
	const char *c1 = strchr(arg, ':');
	if (!c1) {
		double v;
		int rc = cli_parse_double(opt, arg, &v);
		if (rc)
			return rc;
		*values = malloc(sizeof(double));
		if (!*values)
			return pc_error(PC_ENOMEM, "%s", opt);
		(*values)[0] = v;
		*count = 1;
		return 0;
	}
	char buf[3][64];
	const char *parts[3];
	const char *p = arg;
	for (int i = 0; i < 3; i++) {
		const char *e = i < 2 ? strchr(p, ':') : p + strlen(p);
		if (!e || (size_t)(e - p) >= sizeof buf[i])
			return pc_error(PC_EINVAL, "%s '%s': expected a number or a range start:stop:step",
					opt, arg);
		memcpy(buf[i], p, (size_t)(e - p));
		buf[i][e - p] = '\0';
		parts[i] = buf[i];
		p = e + 1;
	}
	if (strchr(parts[2], ':'))
		return pc_error(PC_EINVAL, "%s '%s': a range has exactly three parts start:stop:step", opt,
				arg);
	double a, b, s;
	static const char *names[3] = { "start", "stop", "step" };
	double *dst[3] = { &a, &b, &s };
	for (int i = 0; i < 3; i++) {
		char o[96];
		snprintf(o, sizeof o, "%s (range %s)", opt, names[i]);
		int rc = cli_parse_double(o, parts[i], dst[i]);
		if (rc)
			return rc;
	}
	if (s == 0 || (b - a) / s < 0)
		return pc_error(PC_EINVAL, "%s '%s': the step must be non-zero and go from start towards "
					   "stop", opt, arg);
	double nf = floor((b - a) / s + 1e-9) + 1;
	if (nf > 1e7)
		return pc_error(PC_EINVAL, "%s '%s': more than 10^7 values", opt, arg);
	size_t n = (size_t)nf;
	double *v = malloc(n * sizeof *v);
	if (!v)
		return pc_error(PC_ENOMEM, "%s", opt);
	for (size_t i = 0; i < n; i++)
		v[i] = a + (double)i * s;
	*values = v;
	*count = n;
	return 0;
}

bool cli_wants_help(int argc, char **argv)
{
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--") == 0)
			break;
		if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0)
			return true;
	}
	return false;
}

void cli_print_json(json_t *value)
{
	char *s = json_dumps(value, JSON_COMPACT | JSON_REAL_PRECISION(17) | JSON_ENSURE_ASCII);
	if (s) {
		fputs(s, stdout);
		fputc('\n', stdout);
		free(s);
	}
	json_decref(value);
}

json_t *cli_json_real(double v)
{
	return isfinite(v) ? json_real(v) : json_null();
}

json_t *cli_json_vec(const double *v, unsigned n)
{
	json_t *a = json_array();
	for (unsigned i = 0; i < n; i++)
		json_array_append_new(a, cli_json_real(v[i]));
	return a;
}

json_t *cli_json_matrix4(const double m[4][4])
{
	json_t *a = json_array();
	for (int i = 0; i < 4; i++)
		json_array_append_new(a, cli_json_vec(m[i], 4));
	return a;
}

double cli_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void cli_progress_begin(cli_progress *p, const char *label, uint64_t total)
{
	memset(p, 0, sizeof *p);
	p->label = label;
	p->total = total;
	const char *env = getenv("POLARCAM_PROGRESS");
	if (cli_quiet)
		p->enabled = false;
	else if (env && *env)
		p->enabled = strcmp(env, "0") != 0;
	else
		p->enabled = isatty(STDERR_FILENO);
	p->t_start = p->t_last = cli_now();
}

void cli_progress_update(cli_progress *p, uint64_t done)
{
	if (!p->enabled)
		return;
	double t = cli_now();
	if (done < p->total && t - p->t_last < 0.1)
		return;
	p->t_last = t;
	double frac = p->total ? (double)done / (double)p->total : 1.0;
	int width = 30, fill = (int)(frac * width + 0.5);
	char bar[32];
	for (int i = 0; i < width; i++)
		bar[i] = i < fill ? '#' : '.';
	bar[width] = '\0';
	double el = t - p->t_start;
	double eta = frac > 0 ? el * (1 - frac) / frac : 0;
	fprintf(stderr, "\r%s [%s] %5.1f%% %.1fs elapsed, %.1fs left  ", p->label, bar, 100 * frac, el,
		eta);
	fflush(stderr);
	p->drawn = true;
}

void cli_progress_end(cli_progress *p)
{
	if (p->enabled && p->drawn) {
		cli_progress_update(p, p->total);
		fputc('\n', stderr);
	}
	p->drawn = false;
}

int cli_progress_fn(void *user, const char *phase, uint64_t done, uint64_t total)
{
	cli_progress *p = user;
	if (!p->label || strcmp(p->label, phase)) {
		if (p->label)
			cli_progress_end(p);
		cli_progress_begin(p, phase, total);
	}
	cli_progress_update(p, done);
	return 0;
}

volatile sig_atomic_t cli_stop_requested;

/* The first signal asks the running call to stop cleanly; a second one, while it is still
 * finishing, takes the default action at once (files stay whole: every writer is atomic). */
static void on_signal(int sig)
{
	if (cli_stop_requested) {
		signal(sig, SIG_DFL);
		raise(sig);
		return;
	}
	cli_stop_requested = 1;
}

void cli_catch_signals(void)
{
	struct sigaction sa;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_signal;
	sa.sa_flags = SA_RESTART; /* the library's reads and writes go on; it polls the flag */
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
}

int cli_progress_stoppable(void *user, const char *phase, uint64_t done, uint64_t total)
{
	if (user)
		cli_progress_fn(user, phase, done, total);
	return cli_stop_requested;
}

int cli_lines_open(cli_lines *l, const char *path)
{
	memset(l, 0, sizeof *l);
	if (!path || !*path)
		return pc_error(PC_EINVAL, "--batch: missing file name (or - for stdin)");
	if (strcmp(path, "-") == 0) {
		l->fp = stdin;
		l->name = "stdin";
		return 0;
	}
	l->fp = fopen(path, "r");
	if (!l->fp)
		return pc_error(PC_ENOENT, "--batch %s: %s", path, strerror(errno));
	l->name = path;
	return 0;
}

int cli_lines_next(cli_lines *l, char **line)
{
	for (;;) {
		errno = 0;
		ssize_t n = getline(&l->buf, &l->cap, l->fp);
		if (n < 0) {
			if (ferror(l->fp))
				return pc_error(PC_EIO, "%s line %lu: %s", l->name, l->lineno + 1,
						strerror(errno ? errno : EIO));
			return 0;
		}
		l->lineno++;
		char *s = l->buf;
		while (*s == ' ' || *s == '\t')
			s++;
		if (*s == '\0' || *s == '\n' || *s == '\r' || *s == '#')
			continue;
		*line = s;
		return 1;
	}
}

void cli_lines_close(cli_lines *l)
{
	if (l->fp && l->fp != stdin)
		fclose(l->fp);
	free(l->buf);
	memset(l, 0, sizeof *l);
}

int cli_parse_fields(const char *line, const char *const *names, int want, double *out)
{
	char list[256] = "";
	for (int i = 0; i < want && names; i++) {
		size_t len = strlen(list);
		snprintf(list + len, sizeof list - len, "%s%s", i ? " " : "", names[i]);
	}
	const char *p = line;
	int got = 0;
	for (;;) {
		while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == ',')
			p++;
		if (!*p)
			break;
		const char *e = p;
		while (*e && *e != ' ' && *e != '\t' && *e != '\r' && *e != '\n' && *e != ',')
			e++;
		if (got < want) {
			char tok[128], opt[160];
			size_t len = (size_t)(e - p) < sizeof tok - 1 ? (size_t)(e - p) : sizeof tok - 1;
			memcpy(tok, p, len);
			tok[len] = '\0';
			snprintf(opt, sizeof opt, "field %d (%s)", got + 1, names ? names[got] : "value");
			int rc = cli_parse_double(opt, tok, &out[got]);
			if (rc)
				return rc;
		}
		got++;
		p = e;
	}
	if (got != want)
		return pc_error(PC_EINVAL, "expected %d numbers (%s), got %d", want, list, got);
	return 0;
}

json_t *cli_json_error_line(unsigned long line, int code)
{
	const char *d = pc_error_detail();
	return json_pack("{s:I, s:s, s:s}", "line", (json_int_t)line, "error",
			 *d ? d : pc_strerror(code), "code", pc_errname(code));
}

void cli_batch_error(const cli_lines *in, int rc, int *status)
{
	pc_error_prefix(rc, "%s line %lu: ", in->name, in->lineno);
	cli_print_json(cli_json_error_line(in->lineno, rc));
	cli_error(0, "%s", pc_error_detail());
	if (*status == CLI_EXIT_OK)
		*status = cli_status(rc);
}
