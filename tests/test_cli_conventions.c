/* The conventions every polarcam command follows (README, "Conventions"), checked by running
 * the built CLI ($POLARCAM) as a user would:
 *   - outputs: an existing output is refused with exit status 2 unless --overwrite, for every
 *     command that writes one; --overwrite replaces the folder as a whole (a file left in the
 *     old folder is gone); no temporary folder is left beside it; a folder polarcam did not
 *     write is never replaced; a failure part-way (a file size limit standing in for a full
 *     disk) leaves the old folder byte for byte as it was
 *   - exit statuses: 77 for a backend or device that is absent, 2 for bad arguments
 *   - stdout carries only JSON lines with --json (every line parses) and nothing for commands
 *     that write files without it; stderr has no progress bar when it is not a terminal, and
 *     nothing at all with --quiet
 *   - every command's --help ends with two or three examples, and each example parses
 *     (POLARCAM_PARSE_ONLY=1 stops after the arguments)
 *   - batch processing: `process REC_DIR` and `process --stack` give, frame by frame, the bytes
 *     `process RAW` gives for each frame alone. */
#define _GNU_SOURCE
#include <dirent.h>
#include <jansson.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"

static const char *exe, *src;
/* small recordings: a region of the scenes */
#define ROI "240,200,128,96"
static char dir[64];

static const char *tmp(const char *name)
{
	static char buf[8][512];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
	return buf[k];
}

/* Runs "$POLARCAM args" in dir with stdout to out.txt and stderr to err.txt; pre is put before
 * (environment, ulimit). Returns the exit status. */
static int run_env(const char *pre, const char *args)
{
	char cmd[4096];
	snprintf(cmd, sizeof cmd, "cd '%s' && %s '%s' %s >out.txt 2>err.txt", dir, pre ? pre : "",
	         exe, args);
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int run(const char *args)
{
	return run_env(NULL, args);
}

static char *slurp(const char *path, size_t *len)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return NULL;
	char *b = NULL;
	size_t n = 0, cap = 0;
	for (;;) {
		if (n + 4096 + 1 > cap) {
			cap = 2 * cap + 8192;
			char *nb = realloc(b, cap);
			if (!nb)
				break;
			b = nb;
		}
		size_t r = fread(b + n, 1, 4096, fp);
		n += r;
		if (r < 4096)
			break;
	}
	fclose(fp);
	if (b)
		b[n] = '\0';
	if (len)
		*len = n;
	return b;
}

static bool contains(const char *path, const char *what)
{
	char *s = slurp(path, NULL);
	bool yes = s && strstr(s, what);
	free(s);
	return yes;
}

static size_t file_size(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 ? (size_t)st.st_size : 0;
}

static bool exists(const char *path)
{
	struct stat st;
	return lstat(path, &st) == 0;
}

static bool same_bytes(const char *a, const char *b)
{
	size_t na, nb;
	char *x = slurp(a, &na), *y = slurp(b, &nb);
	bool same = x && y && na == nb && !memcmp(x, y, na);
	free(x);
	free(y);
	return same;
}

/* Entries of dir whose name starts with ".NAME.tmp-": temporary folders left behind. */
static int leftovers(const char *name)
{
	char pre[300];
	snprintf(pre, sizeof pre, ".%s.tmp-", name);
	DIR *d = opendir(dir);
	int n = 0;
	for (struct dirent *e; d && (e = readdir(d));)
		n += !strncmp(e->d_name, pre, strlen(pre));
	if (d)
		closedir(d);
	return n;
}

/* Every line of out.txt is a JSON value; returns the number of lines (-1 if one does not
 * parse). */
static int json_lines(void)
{
	char *s = slurp(tmp("out.txt"), NULL);
	if (!s)
		return -1;
	int n = 0;
	for (char *line = strtok(s, "\n"); line; line = strtok(NULL, "\n")) {
		json_error_t e;
		json_t *j = json_loads(line, 0, &e);
		if (!j) {
			fprintf(stderr, "not JSON: %.200s (%s)\n", line, e.text);
			free(s);
			return -1;
		}
		json_decref(j);
		n++;
	}
	free(s);
	return n;
}

/* ---- outputs ---- */

/* One writing command: first run 0, again 2 naming the output, a stray file in it, then
 * --overwrite 0 with the stray file gone and nothing left beside. */
static void check_overwrite(const char *what, const char *args, const char *out, const char *marker)
{
	char a[2048], stray[600];
	snprintf(a, sizeof a, "%s %s", args, out);
	int st = run(a);
	CHECK_EQ_INT(st, 0);
	if (st)
		fprintf(stderr, "%s: %s\n", what, slurp(tmp("err.txt"), NULL));
	CHECK(exists(tmp(marker)));
	CHECK_EQ_INT(run(a), 2);
	CHECK(contains(tmp("err.txt"), out) && contains(tmp("err.txt"), "--overwrite"));
	bool folder = strchr(marker, '/') != NULL;
	if (folder) {
		snprintf(stray, sizeof stray, "%s/stray.txt", out);
		FILE *fp = fopen(tmp(stray), "w");
		if (fp) {
			fputs("from an older run\n", fp);
			fclose(fp);
		}
	}
	snprintf(a, sizeof a, "%s %s --overwrite", args, out);
	CHECK_EQ_INT(run(a), 0);
	CHECK(exists(tmp(marker)));
	if (folder)
		CHECK(!exists(tmp(stray)));
	CHECK_EQ_INT(leftovers(out), 0);
	if (pc_test_failures)
		fprintf(stderr, "after %s\n", what);
}

/* A set's temporary folder as demosaic names it (io/outdir.c's ".NAME.tmp-HOST-PID-XXXXXX"
 * with NAME "polarcam-set"), holding a file, of a process that has exited (dead) or of this
 * one (alive); its path into p. */
static void stale_set_folder(char *p, size_t size, bool dead)
{
	char host[64] = "host";
	if (gethostname(host, sizeof host) != 0)
		strcpy(host, "host");
	host[sizeof host - 1] = '\0';
	for (char *c = host; *c; c++)
		if (*c == '/' || *c == '-')
			*c = '_';
	pid_t pid = getpid();
	if (dead) {
		pid = fork();
		if (pid == 0)
			_exit(0);
		waitpid(pid, NULL, 0);
	}
	snprintf(p, size, "%s/.polarcam-set.tmp-%s-%ld-%s", dir, host, (long)pid,
	         dead ? "abcdef" : "ghijkl");
	CHECK_EQ_INT(mkdir(p, 0700), 0);
	char f[600];
	snprintf(f, sizeof f, "%s/x", p);
	FILE *fp = fopen(f, "w");
	CHECK(fp != NULL);
	if (fp)
		fclose(fp);
}

static void test_outputs(void)
{
	char a[2048];
	snprintf(a, sizeof a, "render '%s/scenes/ideal_small.json' -n 2 --seed 2 --roi %s -o", src,
	         ROI);
	check_overwrite("render", a, "rec", "rec/meta.json");
	check_overwrite("process", "process rec/raw_000000.png -o", "p", "p/meta.json");
	check_overwrite("process batch", "process rec -o", "pb", "pb/meta.json");
	check_overwrite("demosaic", "demosaic rec/raw_000000.png -o", "i.npy", "i.npy");
	/* the validity mask beside it belongs to the set: alone it is refused as well, and
	 * nothing (neither i.npy nor a temporary) is written then */
	CHECK(exists(tmp("i_valid.npy")));
	CHECK_EQ_INT(remove(tmp("i.npy")), 0);
	CHECK_EQ_INT(run("demosaic rec/raw_000000.png -o i.npy"), 2);
	CHECK(contains(tmp("err.txt"), "i_valid.npy") && contains(tmp("err.txt"), "--overwrite"));
	CHECK(!exists(tmp("i.npy")));
	CHECK_EQ_INT(run("demosaic rec/raw_000000.png -o i.npy --overwrite"), 0);
	CHECK(exists(tmp("i.npy")) && exists(tmp("i_valid.npy")));
	CHECK_EQ_INT(leftovers("i.npy") + leftovers("polarcam-set"), 0);
	/* a demosaic killed outright leaves its set's temporary folder; the next one beside it
	 * removes it (its process is gone), and keeps one of a live process */
	char stale[512], live[512];
	stale_set_folder(stale, sizeof stale, true);
	stale_set_folder(live, sizeof live, false);
	CHECK_EQ_INT(leftovers("polarcam-set"), 2);
	CHECK_EQ_INT(run("demosaic rec/raw_000000.png -o i.npy --overwrite"), 0);
	CHECK(!exists(stale) && exists(live));
	CHECK_EQ_INT(leftovers("polarcam-set"), 1);
	char lf[600];
	snprintf(lf, sizeof lf, "%s/x", live);
	remove(lf);
	rmdir(live);
	snprintf(a, sizeof a,
	         "capture 'sim:%s/scenes/ideal_small.json?fps=0' --roi %s -n 2 "
	         "--process -o",
	         src, ROI);
	check_overwrite("capture", a, "cap", "cap/meta.json");
	snprintf(a, sizeof a, "render '%s/scenes/mueller_tetrahedral.json' --roi 0,0,64,48 -o seq",
	         src);
	CHECK_EQ_INT(run(a), 0);
	check_overwrite("mueller", "mueller seq --no-mueller -o", "m", "m/mueller.json");
	check_overwrite("figures", "figures -o", "fig", "fig/figures.md");
	snprintf(a, sizeof a,
	         "demo --scene '%s/scenes/ideal_small.json' --methods bilinear,ratio "
	         "--no-mueller -o",
	         src);
	check_overwrite("demo", a, "demo", "demo/report.json");
	snprintf(a, sizeof a, "render '%s/scenes/calib/dark.json' -n 2 --roi %s -o dark", src, ROI);
	CHECK_EQ_INT(run(a), 0);
	CHECK_EQ_INT(run("calibrate dark dark -o cal.npz"), 0);
	check_overwrite("calibrate show", "calibrate show cal.npz --pictures", "maps",
	                "maps/meta.json");
	/* calibrate -o: an existing file is refused, but the file a step starts from (--dark,
	 * --flat) may be its output: the step updates it */
	CHECK_EQ_INT(run("calibrate dark dark -o cal.npz"), 2);
	CHECK(contains(tmp("err.txt"), "cal.npz: exists"));
	run("calibrate flat rec rec --dark cal.npz -o cal.npz");
	CHECK(!contains(tmp("err.txt"), "exists"));

	/* a folder polarcam did not write is not replaced, even with --overwrite */
	mkdir(tmp("mine"), 0777);
	FILE *fp = fopen(tmp("mine/thesis.tex"), "w");
	if (fp) {
		fputs("\\documentclass{article}\n", fp);
		fclose(fp);
	}
	CHECK_EQ_INT(run("process rec/raw_000000.png -o mine --overwrite"), 2);
	CHECK(contains(tmp("err.txt"), "did not write"));
	CHECK(exists(tmp("mine/thesis.tex")) && !exists(tmp("mine/meta.json")));
	CHECK_EQ_INT(leftovers("mine"), 0);
	/* nor the current directory */
	CHECK_EQ_INT(run("process rec/raw_000000.png -o . --overwrite"), 2);

	/* a failure part-way: the old folder stays as it was, byte for byte. A file size limit
	 * makes the writes fail as a full disk would (SIGXFSZ ignored: EFBIG) */
	CHECK_EQ_INT(run("process rec/raw_000000.png -o p --overwrite --picture-width 0"), 0);
	size_t before = file_size(tmp("p/stokes.npy"));
	CHECK(before > 0);
	char keep[600];
	snprintf(keep, sizeof keep, "cp -r '%s/p' '%s/p.before'", dir, dir);
	CHECK_EQ_INT(system(keep), 0);
	CHECK(run_env("trap '' XFSZ; ulimit -f 64;",
	              "process rec/raw_000001.png -o p --overwrite --picture-width 0") != 0);
	CHECK(contains(tmp("err.txt"), "write") || contains(tmp("err.txt"), "large"));
	CHECK(same_bytes(tmp("p/stokes.npy"), tmp("p.before/stokes.npy")));
	CHECK(same_bytes(tmp("p/meta.json"), tmp("p.before/meta.json")));
	CHECK(contains(tmp("p/meta.json"), "raw_000000.png"));
	CHECK_EQ_INT(leftovers("p"), 0);
}

/* ---- exit statuses ---- */

static void test_exit_statuses(void)
{
	/* a backend that is not built in, or a device that is absent: 77 */
	CHECK_EQ_INT(run("capture libcamera:no-such-camera -n 1 -o lc"), 77);
	CHECK(!exists(tmp("lc")));
	CHECK_EQ_INT(run("capture v4l2:/dev/polarcam-no-such-node -n 1 -o v"), 77);
	CHECK(contains(tmp("err.txt"), "polarcam-no-such-node"));
	/* no display for the window */
	CHECK_EQ_INT(run_env("env -u DISPLAY -u WAYLAND_DISPLAY", "view sim:default --frames 1"),
	             77);
	/* bad arguments: 2 */
	CHECK_EQ_INT(run("capture nosuch:x -n 1 -o x"), 2);
	CHECK_EQ_INT(run("process"), 2);
	CHECK_EQ_INT(run("render --frames 0 -o x"), 2);
	/* the help names them */
	CHECK_EQ_INT(run("--help"), 0);
	CHECK(contains(tmp("out.txt"), "77"));
}

/* ---- stdout and stderr ---- */

static void check_split(const char *args, int want_lines)
{
	char a[2048];
	snprintf(a, sizeof a, "%s --json", args);
	CHECK_EQ_INT(run_env("POLARCAM_PROGRESS=", a), 0);
	int n = json_lines();
	CHECK(n >= 1);
	if (want_lines > 0)
		CHECK_EQ_INT(n, want_lines);
	/* not a terminal: no progress bar */
	CHECK(!contains(tmp("err.txt"), "\r") && !contains(tmp("err.txt"), "elapsed"));
	snprintf(a, sizeof a, "%s --json --quiet", args);
	CHECK_EQ_INT(run(a), 0);
	CHECK_EQ_INT(json_lines(), n);
	CHECK_EQ_INT(file_size(tmp("err.txt")), 0);
	/* --quiet, and progress forced: still nothing */
	CHECK_EQ_INT(run_env("POLARCAM_PROGRESS=1", a), 0);
	CHECK_EQ_INT(file_size(tmp("err.txt")), 0);
	if (pc_test_failures)
		fprintf(stderr, "after %s\n", args);
}

static void test_stdout_stderr(void)
{
	char a[2048];
	snprintf(a, sizeof a, "render '%s/scenes/ideal_small.json' -n 3 --roi %s -o r2 --overwrite",
	         src, ROI);
	check_split(a, 1);
	check_split("process r2 -o p2 --overwrite", 1);
	check_split("process r2/raw_000000.png -o p3 --overwrite", 1);
	check_split("demosaic r2/raw_000000.png -o i2.npy --overwrite", 1);
	snprintf(a, sizeof a,
	         "capture 'sim:%s/scenes/ideal_small.json?fps=0' --roi %s -n 2 -o c2 "
	         "--overwrite",
	         src, ROI);
	check_split(a, 1);
	check_split("mueller seq -o m2 --overwrite", 1);
	check_split("figures -o f2 --overwrite", 0);
	check_split("pbrdf --n 1.5 --sigma 0.2 --theta-i 0:80:20 --theta-r 30", 5);
	check_split("decompose 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", 1);
	check_split("demosaic --list", 1);
	check_split("devices", 0);
	/* without --json a command that writes files prints nothing on stdout */
	CHECK_EQ_INT(run("process r2/raw_000001.png -o p4"), 0);
	CHECK_EQ_INT(file_size(tmp("out.txt")), 0);
	CHECK(contains(tmp("err.txt"), "p4"));
	snprintf(a, sizeof a, "render '%s/scenes/ideal_small.json' --roi %s -o r3", src, ROI);
	CHECK_EQ_INT(run(a), 0);
	CHECK_EQ_INT(file_size(tmp("out.txt")), 0);
	/* errors still reach stderr with --quiet */
	CHECK_EQ_INT(run("process r2/raw_000001.png -o p4 --quiet"), 2);
	CHECK(contains(tmp("err.txt"), "error"));
}

/* ---- --help examples ---- */

/* The command names from `polarcam --help`, then each help's examples. */
static void test_help_examples_all(void)
{
	CHECK_EQ_INT(run("--help"), 0);
	char *help = slurp(tmp("out.txt"), NULL);
	char names[40][32];
	int ncmd = 0;
	char *p = help ? strstr(help, "commands:\n") : NULL;
	if (p)
		p += 10;
	while (p && *p == ' ' && ncmd < 40) {
		if (sscanf(p, " %31s", names[ncmd]) == 1)
			ncmd++;
		p = strchr(p, '\n');
		if (p)
			p++;
	}
	free(help);
	CHECK(ncmd >= 15);
	for (int c = 0; c < ncmd; c++) {
		char a[128];
		snprintf(a, sizeof a, "%.31s --help", names[c]);
		CHECK_EQ_INT(run(a), 0);
		char *h = slurp(tmp("out.txt"), NULL);
		char *ex = h ? strstr(h, "\nexamples:\n") : NULL;
		CHECK(ex != NULL);
		if (!ex)
			fprintf(stderr, "%s --help: no examples\n", names[c]);
		int nex = 0;
		for (char *e = ex ? ex + 11 : NULL; e && *e;) {
			char *nl = strchr(e, '\n');
			if (nl)
				*nl = '\0';
			char want[64];
			snprintf(want, sizeof want, "  polarcam %.31s ", names[c]);
			bool ok = !strncmp(e, want, strlen(want)) ||
			          !strcmp(e + 2, want + 2 + 0) /* no arguments */ ||
			          (strlen(e) == strlen(want) - 1 && !strncmp(e, want, strlen(e)));
			CHECK(ok);
			if (!ok)
				fprintf(stderr, "%s: not an example of it: '%s'\n", names[c], e);
			nex++;
			char cmd[4096];
			snprintf(cmd, sizeof cmd,
			         "cd '%s' && POLARCAM_PARSE_ONLY=1 '%s' %s >out2.txt 2>&1", dir,
			         exe, e + strlen("  polarcam "));
			int st = system(cmd);
			int code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
			if (code != 0) {
				char *o = slurp(tmp("out2.txt"), NULL);
				fprintf(stderr, "example does not parse (exit %d): %s\n%s\n", code,
				        e, o ? o : "");
				free(o);
			}
			CHECK_EQ_INT(code, 0);
			e = nl ? nl + 1 : NULL;
		}
		CHECK(nex >= 2 && nex <= 3);
		if (nex < 2 || nex > 3)
			fprintf(stderr, "%s --help: %d examples\n", names[c], nex);
		free(h);
	}
}

/* ---- batch processing ---- */

/* The data of a .npy (after its header) and its length. */
static char *npy_data(const char *path, size_t *len)
{
	size_t n;
	char *b = slurp(path, &n);
	if (!b || n < 10 || memcmp(b, "\x93NUMPY", 6)) {
		free(b);
		return NULL;
	}
	size_t hl = (size_t)(unsigned char)b[8] | (size_t)(unsigned char)b[9] << 8;
	size_t off = 10 + hl;
	if (off > n) {
		free(b);
		return NULL;
	}
	memmove(b, b + off, n - off);
	*len = n - off;
	return b;
}

static void test_batch(void)
{
	char a[2048];
	snprintf(a, sizeof a, "render '%s/scenes/ideal_small.json' -n 3 --seed 4 --roi %s -o br",
	         src, ROI);
	CHECK_EQ_INT(run(a), 0);
	CHECK_EQ_INT(run("process br -o bp --method ratio"), 0);
	CHECK_EQ_INT(run("process br/raw_000000.png br/raw_000001.png br/raw_000002.png -o bf "
	                 "--method ratio"),
	             0);
	CHECK_EQ_INT(run("process br -o bs --method ratio --stack"), 0);
	static const char *q[3] = {"stokes", "dolp", "aolp"};
	size_t ls[3];
	char *stack[3];
	for (int k = 0; k < 3; k++) {
		char p[64];
		snprintf(p, sizeof p, "bs/%s.npy", q[k]);
		stack[k] = npy_data(tmp(p), &ls[k]);
		CHECK(stack[k] != NULL);
	}
	for (int f = 0; f < 3; f++) {
		char one[64], a1[128];
		snprintf(one, sizeof one, "one%d", f);
		snprintf(a1, sizeof a1, "process br/raw_%06d.png -o %s --method ratio", f, one);
		CHECK_EQ_INT(run(a1), 0);
		for (int k = 0; k < 3; k++) {
			char p1[96], p2[96], p3[96];
			snprintf(p1, sizeof p1, "%s/%s.npy", one, q[k]);
			snprintf(p2, sizeof p2, "bp/%s_%06d.npy", q[k], f);
			snprintf(p3, sizeof p3, "bf/%s_%06d.npy", q[k], f);
			CHECK(same_bytes(tmp(p1), tmp(p2)));
			CHECK(same_bytes(tmp(p1), tmp(p3)));
			size_t l1;
			char *d1 = npy_data(tmp(p1), &l1);
			CHECK(d1 && stack[k] && ls[k] == 3 * l1);
			if (d1 && stack[k] && ls[k] == 3 * l1)
				CHECK(!memcmp(d1, stack[k] + (size_t)f * l1, l1));
			free(d1);
		}
	}
	for (int k = 0; k < 3; k++)
		free(stack[k]);
	/* the stack's header says (N, H, W, 3) */
	char *hdr = slurp(tmp("bs/stokes.npy"), NULL);
	CHECK(hdr && strstr(hdr + 10, "'shape': (3, 96, 128, 3)"));
	free(hdr);
	/* pictures of the first frame only, by default */
	CHECK(exists(tmp("bp/dolp_000000.png")) && !exists(tmp("bp/dolp_000001.png")));
	CHECK_EQ_INT(run("process br -o bq --pictures-every 2 --no-pictures"), 0);
	CHECK(!exists(tmp("bq/dolp_000000.png")));
	CHECK_EQ_INT(run("process br -o bq --pictures-every 2 --overwrite"), 0);
	CHECK(exists(tmp("bq/dolp_000002.png")) && !exists(tmp("bq/dolp_000001.png")));
	/* A recording with a black level (offset_dn 64) and an odd ROI origin (the mosaic's phase
	 * shifts by one pixel both ways): its folder is processed as its frames are one by one,
	 * with the recording's black level and layout, not the defaults. */
	char sp[600];
	snprintf(sp, sizeof sp, "%s/scenes/ideal_small.json", src);
	char *sc = slurp(sp, NULL);
	const char *key = "\"preset\": \"ideal\"";
	char *at = sc ? strstr(sc, key) : NULL;
	CHECK(at != NULL);
	if (at) {
		FILE *sf = fopen(tmp("black.json"), "wb");
		if (sf) {
			fprintf(sf, "%.*s%s, \"offset_dn\": 64%s", (int)(at - sc), sc, key,
			        at + strlen(key));
			fclose(sf);
		}
		CHECK_EQ_INT(run("render black.json -n 2 --seed 4 --roi 241,201,128,96 -o bk"), 0);
		CHECK(contains(tmp("bk/meta.json"), "\"offset_dn\": 64"));
		CHECK_EQ_INT(run("process bk -o bkp --json"), 0);
		CHECK(contains(tmp("out.txt"), "\"black_level_from\":\"recording\""));
		CHECK_EQ_INT(run("process bk/raw_000001.png -o bk1 --json"), 0);
		CHECK(contains(tmp("out.txt"), "\"black_level_from\":\"recording\""));
		CHECK(same_bytes(tmp("bk1/stokes.npy"), tmp("bkp/stokes_000001.npy")));
		CHECK(same_bytes(tmp("bk1/dolp.npy"), tmp("bkp/dolp_000001.npy")));
		/* and the defaults would differ: the check above can fail */
		CHECK_EQ_INT(run("process bk/raw_000001.png -o bk0 --black-level 0 --layout "
		                 "90,45,135,0"),
		             0);
		CHECK(!same_bytes(tmp("bk0/stokes.npy"), tmp("bkp/stokes_000001.npy")));
	}
	free(sc);
	/* a bad frame in the batch: exit 2, naming it, nothing put in place */
	FILE *fp = fopen(tmp("bad.png"), "wb");
	if (fp) {
		fputs("not a PNG", fp);
		fclose(fp);
	}
	CHECK_EQ_INT(run("process br/raw_000000.png bad.png -o bx"), 2);
	CHECK(contains(tmp("err.txt"), "bad.png"));
	CHECK(!exists(tmp("bx")) && leftovers("bx") == 0);
}

/* ---- messages: each names the file and what was expected ---- */

/* Writes a (2, 2) .npy of dtype descr (4-byte items) by hand. */
static void write_npy(const char *path, const char *descr)
{
	char hdr[128];
	int n = snprintf(hdr, sizeof hdr,
	                 "{'descr': '%s', 'fortran_order': False, 'shape': (2, 2), }", descr);
	while ((n + 10 + 1) % 64)
		hdr[n++] = ' ';
	hdr[n++] = '\n';
	FILE *fp = fopen(path, "wb");
	if (!fp)
		return;
	unsigned char pre[10] = {0x93,
	                         'N',
	                         'U',
	                         'M',
	                         'P',
	                         'Y',
	                         1,
	                         0,
	                         (unsigned char)(n & 0xff),
	                         (unsigned char)(n >> 8)};
	fwrite(pre, 1, sizeof pre, fp);
	fwrite(hdr, 1, (size_t)n, fp);
	int32_t v[4] = {1, 2, 3, 4};
	fwrite(v, sizeof v, 1, fp);
	fclose(fp);
}

static void test_messages(void)
{
	/* rec/ (test_outputs): 12-bit frames in 16-bit PNGs. --bits 8 names the depth the file
	 * holds (it said "16-bit data") */
	CHECK_EQ_INT(run("process rec/raw_000000.png --bits 8 -o msg1"), 2);
	CHECK(contains(tmp("err.txt"), "holds 12-bit data in 16-bit samples, not 8-bit data"));
	CHECK(!exists(tmp("msg1")));
	/* an int32 .npy: the dtype as written, without a stray quote (outputs msgN:
	 * test_stdout_stderr wrote m2) */
	write_npy(tmp("i4.npy"), "<i4");
	CHECK_EQ_INT(run("process i4.npy -o msg2"), 2);
	CHECK(contains(tmp("err.txt"), "i4.npy: dtype '<i4' not supported"));
	CHECK(!contains(tmp("err.txt"), "'<i4''"));
	/* a raw file that is not there, and a folder that is no recording */
	CHECK_EQ_INT(run("process no_such.png -o msg3"), 2);
	CHECK(contains(tmp("err.txt"), "no_such.png: No such file or directory"));
	CHECK(!exists(tmp("msg3")));
	/* a scene that cannot be opened: the system's reason */
	CHECK_EQ_INT(run("render no_such_scene.json -o msg4"), 2);
	CHECK(contains(tmp("err.txt"), "no_such_scene.json: cannot open the scene file: No such "
	                               "file or directory"));
	/* mueller of a recording made without polarization states */
	CHECK_EQ_INT(run("mueller rec -o msg5"), 2);
	CHECK(contains(tmp("err.txt"), "no states.json"));
	CHECK(!exists(tmp("msg5")));
	/* view --screenshot names a PNG or is refused before anything is opened (it wrote PNG
	 * data under a .jpg name) */
	CHECK_EQ_INT(run_env("env -u DISPLAY -u WAYLAND_DISPLAY",
	                     "view sim:default --frames 1 --screenshot shot.jpg"),
	             2);
	CHECK(contains(tmp("err.txt"), "shot.jpg: screenshots are written as PNG only"));
	CHECK(!exists(tmp("shot.jpg")));
	/* a DoLP range outside (0, 1] */
	CHECK_EQ_INT(run("process rec/raw_000000.png --dolp-max 2 -o msg6"), 2);
	CHECK(contains(tmp("err.txt"), "--dolp-max 2: expected auto or a DoLP in (0, 1]"));
	/* and accepted: automatic, printed on the key (the title says it too) */
	CHECK_EQ_INT(run("process rec/raw_000000.png --dolp-max auto -o msg7"), 0);
	CHECK(exists(tmp("msg7/dolp.png")));
}

int main(void)
{
	exe = getenv("POLARCAM");
	src = getenv("PC_SOURCE_DIR");
	if (!exe || !src || access(exe, X_OK) != 0)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	snprintf(dir, sizeof dir, "/tmp/pc_conv_XXXXXX");
	if (!mkdtemp(dir))
		SKIP("no temporary directory");
	test_outputs();
	test_exit_statuses();
	test_stdout_stderr();
	test_help_examples_all();
	test_batch();
	test_messages();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_cli_conventions");
}
