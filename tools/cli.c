#define _POSIX_C_SOURCE 200809L
#include "cli.h"

#include <errno.h>
#include <float.h>
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

/* Messages go to a terminal: every byte that is not printable UTF-8 is escaped
 * (cli_quote), whatever the message quotes (file names, tokens of a binary file). */
__attribute__((format(printf, 2, 0))) static void cli_vmessage(const char *kind, const char *fmt,
                                                               va_list ap)
{
	char msg[2048], q[4 * sizeof msg + 8];
	int n = vsnprintf(msg, sizeof msg, fmt, ap);
	size_t len = n < 0 ? 0 : (size_t)n < sizeof msg ? (size_t)n : sizeof msg - 1;
	fprintf(stderr, "polarcam %s: %s: %s\n", cli_name, kind, cli_quote(msg, len, q, sizeof q));
}

int cli_error(int status, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	cli_vmessage("error", fmt, ap);
	va_end(ap);
	return status;
}

void cli_warn(const char *fmt, ...)
{
	if (cli_quiet)
		return;
	va_list ap;
	va_start(ap, fmt);
	cli_vmessage("warning", fmt, ap);
	va_end(ap);
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

/* Untrusted text (arguments, lines of a batch file) echoed in a message: at most `max` bytes,
 * control bytes and bytes that are not UTF-8 written as \xNN, so that a binary file cannot
 * drive the terminal (ESC sequences) or hide the rest of a message. */
const char *cli_quote(const char *s, size_t len, char *buf, size_t size)
{
	static const char hex[] = "0123456789abcdef";
	if (size < 8) {
		if (size)
			buf[0] = '\0';
		return buf;
	}
	const size_t room = size - 4; /* "..." and the NUL stay available */
	size_t o = 0, i = 0;
	while (i < len) {
		unsigned char c = (unsigned char)s[i];
		size_t n = 0; /* length of a valid UTF-8 sequence starting here (0: none) */
		if (c >= 0x20 && c < 0x7f) {
			n = 1;
		} else if (c >= 0xc2 && c <= 0xf4) {
			/* well-formed UTF-8 (RFC 3629 table): no overlong forms, no surrogates,
			 * nothing above U+10FFFF; the second byte's range depends on the first */
			n = c < 0xe0 ? 2 : c < 0xf0 ? 3 : 4;
			unsigned char lo = c == 0xe0 ? 0xa0 : c == 0xf0 ? 0x90 : 0x80;
			unsigned char hi = c == 0xed ? 0x9f : c == 0xf4 ? 0x8f : 0xbf;
			for (size_t k = 1; k < n; k++) {
				unsigned char b = i + k < len ? (unsigned char)s[i + k] : 0;
				if (b < (k == 1 ? lo : 0x80) || b > (k == 1 ? hi : 0xbf))
					n = 0;
			}
		}
		size_t piece = n ? n : 4;
		if (o + piece > room)
			break;
		if (n) {
			memcpy(buf + o, s + i, n);
			i += n;
			o += n;
		} else {
			buf[o++] = '\\';
			buf[o++] = 'x';
			buf[o++] = hex[c >> 4];
			buf[o++] = hex[c & 15];
			i++;
		}
	}
	if (i < len) {
		memcpy(buf + o, "...", 3);
		o += 3;
	}
	buf[o] = '\0';
	return buf;
}

#define PC_QUOTE_MAX 160

int cli_parse_double(const char *opt, const char *arg, double *out)
{
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value (expected a number)", opt);
	char q[PC_QUOTE_MAX];
	cli_quote(arg, strlen(arg), q, sizeof q);
	char *end;
	errno = 0;
	double v = strtod(arg, &end);
	if (end == arg || *end != '\0')
		return pc_error(PC_EINVAL, "%s '%s': not a number", opt, q);
	if (!isfinite(v))
		return pc_error(PC_EINVAL, "%s '%s': expected a finite number", opt, q);
	if (errno == ERANGE) {
		/* strtod reports ERANGE for overflow (±HUGE_VAL, caught above) and for underflow:
		 * a subnormal result is the nearest double and is kept (the caller's range check
		 * then speaks about the value); a result of 0 from non-zero digits is refused. */
		if (v == 0)
			return pc_error(PC_EINVAL,
			                "%s '%s': below the smallest double (4.9e-324): "
			                "it would read as 0",
			                opt, q);
		if (fabs(v) > DBL_MAX)
			return pc_error(PC_EINVAL, "%s '%s': beyond the double range (1.8e308)",
			                opt, q);
	}
	*out = v;
	return 0;
}

int cli_parse_picture_opt(const char *opt, const char *arg, double *mask_s0, double *dolp_hi)
{
	int rc;
	if (!strcmp(opt, "--dolp-max")) {
		if (arg && !strcmp(arg, "auto")) {
			*dolp_hi = -1;
			return 0;
		}
		if (!(rc = cli_parse_double(opt, arg, dolp_hi)) && !(*dolp_hi > 0 && *dolp_hi <= 1))
			rc = pc_error(PC_ERANGE, "--dolp-max %s: expected auto or a DoLP in (0, 1]",
			              arg);
		return rc;
	}
	if (!(rc = cli_parse_double(opt, arg, mask_s0)) && !(*mask_s0 >= 0))
		rc = pc_error(PC_ERANGE, "--mask-s0 %s: expected a threshold >= 0 (0: no mask)",
		              arg);
	if (!rc && *mask_s0 == 0)
		*mask_s0 = -1;
	return rc;
}

/* Decimal digits only (no sign, no space, no 0x, no octal reading of a leading 0): the value,
 * or 1 when the text is not an integer, 2 when it exceeds UINT64_MAX. */
static int parse_decimal_u64(const char *s, uint64_t *out)
{
	if (!*s)
		return 1;
	uint64_t v = 0;
	for (; *s; s++) {
		if (*s < '0' || *s > '9')
			return 1;
		unsigned d = (unsigned)(*s - '0');
		if (v > (UINT64_MAX - d) / 10) {
			for (s++; *s; s++) /* junk after an overflow is still junk */
				if (*s < '0' || *s > '9')
					return 1;
			return 2;
		}
		v = v * 10 + d;
	}
	*out = v;
	return 0;
}

int cli_parse_long(const char *opt, const char *arg, long min, long max, long *out)
{
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value (expected an integer)", opt);
	char q[PC_QUOTE_MAX];
	cli_quote(arg, strlen(arg), q, sizeof q);
	bool neg = arg[0] == '-' && min < 0;
	uint64_t u = 0;
	int bad = parse_decimal_u64(arg + (neg ? 1 : 0), &u);
	if (bad == 1)
		return pc_error(PC_EINVAL, "%s '%s': not an integer (decimal digits%s expected)",
		                opt, q, min < 0 ? ", optionally after '-'," : "");
	if (bad == 2 || (!neg && u > (uint64_t)max) ||
	    (neg && (min >= 0 || u > (uint64_t)(-(min + 1)) + 1)))
		return pc_error(PC_EINVAL, "%s '%s': expected an integer in [%ld, %ld]", opt, q,
		                min, max);
	long v = neg ? (long)(-(int64_t)(u - 1) - 1) : (long)u;
	if (v < min || v > max)
		return pc_error(PC_EINVAL, "%s '%s': expected an integer in [%ld, %ld]", opt, q,
		                min, max);
	*out = v;
	return 0;
}

int cli_parse_u64_range(const char *opt, const char *arg, uint64_t min, uint64_t max, uint64_t *out)
{
	if (!arg || !*arg)
		return pc_error(PC_EINVAL, "%s: missing value (expected a non-negative integer)",
		                opt);
	char q[PC_QUOTE_MAX];
	cli_quote(arg, strlen(arg), q, sizeof q);
	uint64_t v = 0;
	int bad = parse_decimal_u64(arg, &v);
	if (bad == 1)
		return pc_error(PC_EINVAL,
		                "%s '%s': not a non-negative integer (decimal digits "
		                "expected)",
		                opt, q);
	if (bad == 2 || v < min || v > max)
		return pc_error(PC_EINVAL, "%s '%s': expected an integer in [%llu, %llu]", opt, q,
		                (unsigned long long)min, (unsigned long long)max);
	*out = v;
	return 0;
}

int cli_parse_u64(const char *opt, const char *arg, uint64_t *out)
{
	return cli_parse_u64_range(opt, arg, 0, UINT64_MAX, out);
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
			return pc_error(PC_EINVAL,
			                "%s '%s': expected a number or a range start:stop:step",
			                opt, arg);
		memcpy(buf[i], p, (size_t)(e - p));
		buf[i][e - p] = '\0';
		parts[i] = buf[i];
		p = e + 1;
	}
	if (strchr(parts[2], ':'))
		return pc_error(PC_EINVAL,
		                "%s '%s': a range has exactly three parts start:stop:step", opt,
		                arg);
	double a, b, s;
	static const char *names[3] = {"start", "stop", "step"};
	double *dst[3] = {&a, &b, &s};
	for (int i = 0; i < 3; i++) {
		char o[96];
		snprintf(o, sizeof o, "%s (range %s)", opt, names[i]);
		int rc = cli_parse_double(o, parts[i], dst[i]);
		if (rc)
			return rc;
	}
	if (s == 0 || (b - a) / s < 0)
		return pc_error(PC_EINVAL,
		                "%s '%s': the step must be non-zero and go from start towards "
		                "stop",
		                opt, arg);
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
	fprintf(stderr, "\r%s [%s] %5.1f%% %.1fs elapsed, %.1fs left  ", p->label, bar, 100 * frac,
	        el, eta);
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
		char *s = l->buf, *end = l->buf + n;
		while (s < end && (*s == ' ' || *s == '\t'))
			s++;
		if (s == end || *s == '\n' || *s == '\r' || *s == '#')
			continue;
		/* the data line: up to the newline, NUL bytes included (cli_parse_fields_n
		 * refuses them rather than reading a binary line up to its first NUL) */
		if (end > s && end[-1] == '\n')
			end--;
		l->len = (size_t)(end - s);
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

int cli_parse_fields_n(const char *line, size_t n, const char *const *names, int want, double *out)
{
	const char *nul = memchr(line, '\0', n);
	if (nul)
		return pc_error(PC_EFORMAT,
		                "byte %zu is a NUL: not a line of text (a binary file?)",
		                (size_t)(nul - line) + 1);
	char list[256] = "";
	for (int i = 0; i < want && names; i++) {
		size_t len = strlen(list);
		snprintf(list + len, sizeof list - len, "%s%s", i ? " " : "", names[i]);
	}
	const char *p = line, *end = line + n;
	int got = 0;
	for (;;) {
		while (p < end &&
		       (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n' || *p == ','))
			p++;
		if (p == end)
			break;
		const char *e = p;
		while (e < end && *e != ' ' && *e != '\t' && *e != '\r' && *e != '\n' && *e != ',')
			e++;
		if (got < want) {
			/* the whole token, however long: a number may carry many digits, and text
			 * cut at a fixed length would hide junk behind them */
			char *tok = strndup(p, (size_t)(e - p)), opt[160];
			if (!tok)
				return pc_error(PC_ENOMEM, "field %d", got + 1);
			snprintf(opt, sizeof opt, "field %d (%s)", got + 1,
			         names ? names[got] : "value");
			int rc = cli_parse_double(opt, tok, &out[got]);
			free(tok);
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

int cli_parse_fields(const char *line, const char *const *names, int want, double *out)
{
	return cli_parse_fields_n(line, strlen(line), names, want, out);
}

json_t *cli_json_error_line(unsigned long line, int code)
{
	const char *d = pc_error_detail();
	char q[4 * 1024 + 8]; /* JSON strings must be UTF-8: the detail may quote binary input */
	if (*d)
		d = cli_quote(d, strlen(d), q, sizeof q);
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
