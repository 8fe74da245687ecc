/* The physics commands end to end: `polarcam pbrdf` and `polarcam decompose` run as processes
 * ($POLARCAM), their JSON lines parsed with jansson and checked against physics.md's reference
 * values, ranges, batch mode with line-numbered errors, and exit status 2 with a message naming
 * the argument for every kind of bad input. */
#include <jansson.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "check.h"

static const char *polarcam;
static char tmpdir[64];

typedef struct result {
	int status;
	char out[1 << 16];
	char err[4096];
	json_t *lines[64];
	int nlines;
} result;

static void slurp(const char *path, char *buf, size_t cap)
{
	FILE *fp = fopen(path, "r");
	size_t n = fp ? fread(buf, 1, cap - 1, fp) : 0;
	buf[n] = '\0';
	if (fp)
		fclose(fp);
}

/* Runs "polarcam ARGS" with stdin from `input` (may be NULL); parses stdout as JSON lines. */
static void run(result *r, const char *args, const char *input)
{
	char in[300], out[300], err[300], cmd[2048];
	snprintf(in, sizeof in, "%s/in.txt", tmpdir);
	snprintf(out, sizeof out, "%s/out.txt", tmpdir);
	snprintf(err, sizeof err, "%s/err.txt", tmpdir);
	FILE *fp = fopen(in, "w");
	if (fp) {
		fputs(input ? input : "", fp);
		fclose(fp);
	}
	snprintf(cmd, sizeof cmd, "'%s' %s <'%s' >'%s' 2>'%s'", polarcam, args, in, out, err);
	int st = system(cmd);
	r->status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
	slurp(out, r->out, sizeof r->out);
	slurp(err, r->err, sizeof r->err);
	r->nlines = 0;
	if (strstr(args, "--help"))
		return; /* text, not JSON lines */
	char *save = NULL;
	for (char *l = strtok_r(r->out, "\n", &save); l && r->nlines < 64;
	     l = strtok_r(NULL, "\n", &save)) {
		json_error_t je;
		json_t *j = json_loads(l, 0, &je);
		CHECK(j != NULL); /* every stdout line is one JSON object */
		if (!j)
			fprintf(stderr, "not JSON (%s): %.200s\n", je.text, l);
		if (j)
			r->lines[r->nlines++] = j;
	}
}

static void release(result *r)
{
	for (int i = 0; i < r->nlines; i++)
		json_decref(r->lines[i]);
	r->nlines = 0;
}

static double num(json_t *o, const char *key)
{
	json_t *v = json_object_get(o, key);
	return json_is_number(v) ? json_number_value(v) : NAN;
}

static double mat(json_t *o, const char *key, int i, int j)
{
	json_t *v = json_array_get(json_array_get(json_object_get(o, key), (size_t)i), (size_t)j);
	return json_is_number(v) ? json_number_value(v) : NAN;
}

static bool has_flag(json_t *o, const char *name)
{
	json_t *a = json_object_get(o, "flags");
	for (size_t i = 0; i < json_array_size(a); i++)
		if (!strcmp(json_string_value(json_array_get(a, i)), name))
			return true;
	return false;
}

static void expect_usage_error(const char *args, const char *input, const char *must_name)
{
	static result r;
	run(&r, args, input);
	CHECK_EQ_INT(r.status, 2);
	if (!strstr(r.err, must_name)) {
		fprintf(stderr, "stderr of 'polarcam %s' does not name '%s': %s\n", args, must_name,
		        r.err);
		CHECK(0);
	}
	release(&r);
}

static void test_pbrdf(void)
{
	static result r;
	/* physics.md §2 reference 1 */
	run(&r, "pbrdf --n 1.5 --sigma 0.2 --theta-i 30 --theta-r 30 --phi 180 --rho quad:64",
	    NULL);
	CHECK_EQ_INT(r.status, 0);
	CHECK_EQ_INT(r.nlines, 1);
	if (r.nlines == 1) {
		json_t *o = r.lines[0];
		CHECK_REL(mat(o, "mueller", 0, 0), 6.772339e-02, 1e-6);
		CHECK_REL(mat(o, "mueller", 1, 1), 5.507109e-02, 1e-6);
		CHECK_REL(mat(o, "mueller", 3, 3), -5.066541e-02, 1e-6);
		CHECK_NEAR(num(o, "D"), 0.318699, 6e-7);
		CHECK_NEAR(num(o, "dop"), num(o, "D"), 1e-12);
		CHECK_NEAR(num(o, "R"), 3.14159265358979, 1e-9);
		CHECK_NEAR(num(o, "Delta"), 0.209795, 6e-7);
		CHECK(num(o, "rho_s") > 0.04 && num(o, "rho_s") < 0.045);
		CHECK_NEAR(num(o, "theta_i"), 30, 0);
		CHECK(json_is_array(json_object_get(o, "flags")));
	}
	release(&r);
	/* reference 2, default options */
	run(&r, "pbrdf --n 1.46 --k 1.28 --sigma 0.2 --theta-i 40 --theta-r 55 --phi 150", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK_REL(mat(r.lines[0], "mueller", 2, 3), -7.800504e-02, 1e-6);
		CHECK_NEAR(num(r.lines[0], "R"), 2.590406, 6e-7);
	}
	release(&r);
	/* ranges: 3 σ × 3 θ_i × 1 θ_r × 3 φ = 27 lines, σ slowest, φ fastest */
	run(&r, "pbrdf --n 1.5 --sigma 0.1:0.3:0.1 --theta-i 0:60:30 --theta-r 45 --phi 0:180:90",
	    NULL);
	CHECK_EQ_INT(r.status, 0);
	CHECK_EQ_INT(r.nlines, 27);
	if (r.nlines == 27) {
		CHECK_NEAR(num(r.lines[0], "sigma"), 0.1, 1e-12);
		CHECK_NEAR(num(r.lines[8], "sigma"), 0.1, 1e-12);
		CHECK_NEAR(num(r.lines[9], "sigma"), 0.2, 1e-12);
		CHECK_NEAR(num(r.lines[1], "phi"), 90, 1e-12);
		CHECK_NEAR(num(r.lines[3], "theta_i"), 30, 1e-12);
	}
	release(&r);
	/* the other modes run; σ > 0.5 warns and flags */
	run(&r,
	    "pbrdf --n 1.5 --sigma 0.7 --theta-i 20 --theta-r 50 --diffuse geometric "
	    "--shadowing none --rho table",
	    NULL);
	CHECK_EQ_INT(r.status, 0);
	CHECK(strstr(r.err, "warning") != NULL);
	CHECK(r.nlines == 1 && has_flag(r.lines[0], "outside_validity"));
	release(&r);
	/* without a diffuse term at Brewster's angle D = 1: R and Delta are null */
	run(&r,
	    "pbrdf --n 1.5 --sigma 0.2 --theta-i 56.309932474020215 --theta-r 56.309932474020215 "
	    "--diffuse none",
	    NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK(json_is_null(json_object_get(r.lines[0], "R")));
		CHECK(json_is_null(json_object_get(r.lines[0], "rho_s")));
		CHECK_NEAR(num(r.lines[0], "D"), 1, 1e-9);
	}
	release(&r);

	/* batch: a bad line yields an error object with its line number, the others go on */
	run(&r, "pbrdf --batch -",
	    "# n k sigma theta_i theta_r phi\n"
	    "1.5 0 0.2 30 30 180\n"
	    "1.5 0 -0.2 30 30 180\n"
	    "\n"
	    "1.5 0 0.2 30 95 180\n"
	    "1.5 0 0.2 30 30\n"
	    "1.46 1.28 0.2 40 55 150\n");
	CHECK_EQ_INT(r.status, 2);
	CHECK_EQ_INT(r.nlines, 5);
	if (r.nlines == 5) {
		CHECK_NEAR(num(r.lines[0], "line"), 2, 0);
		CHECK_REL(mat(r.lines[0], "mueller", 0, 1), 2.158337e-02, 1e-6);
		CHECK_NEAR(num(r.lines[1], "line"), 3, 0);
		CHECK(strstr(json_string_value(json_object_get(r.lines[1], "error")), "sigma"));
		CHECK(!strcmp(json_string_value(json_object_get(r.lines[1], "code")), "PC_EINVAL"));
		CHECK_NEAR(num(r.lines[2], "line"), 5, 0);
		CHECK(strstr(json_string_value(json_object_get(r.lines[2], "error")), "theta_r"));
		CHECK_NEAR(num(r.lines[3], "line"), 6, 0);
		CHECK_NEAR(num(r.lines[4], "line"), 7, 0);
		CHECK_REL(mat(r.lines[4], "mueller", 3, 3), -1.590317e-01, 1e-6);
	}
	release(&r);

	expect_usage_error("pbrdf --n 1.5 --sigma 0 --theta-i 30 --theta-r 30", NULL, "--sigma");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.1:-0.1:0.1 --theta-i 30 --theta-r 30", NULL,
	                   "--sigma");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.2 --theta-i 30 --theta-r 91", NULL,
	                   "--theta-r");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.2 --theta-i -1 --theta-r 30", NULL,
	                   "--theta-i");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.2 --theta-i x --theta-r 30", NULL, "--theta-i");
	expect_usage_error("pbrdf --n 1.5 --sigma nan --theta-i 30 --theta-r 30", NULL, "--sigma");
	expect_usage_error("pbrdf --n 0 --sigma 0.2 --theta-i 30 --theta-r 30", NULL, "--n");
	expect_usage_error("pbrdf --n 1.5 --k -1 --sigma 0.2 --theta-i 30 --theta-r 30", NULL,
	                   "--k");
	expect_usage_error("pbrdf --sigma 0.2 --theta-i 30 --theta-r 30", NULL, "--n");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.2 --theta-i 30 --theta-r 30 --rho quad:1", NULL,
	                   "--rho");
	expect_usage_error("pbrdf --n 1.5 --sigma 0.2 --theta-i 30 --theta-r 30 --diffuse x", NULL,
	                   "--diffuse");
	expect_usage_error("pbrdf --n 1.5 --sigma 2 --theta-i 30 --theta-r 30 --rho table", NULL,
	                   "sigma");
	expect_usage_error("pbrdf --batch /nonexistent/file", NULL, "/nonexistent/file");
}

static void test_decompose(void)
{
	static result r;
	/* the reference-1 matrix from physics.md §2 */
	run(&r,
	    "decompose 6.772339e-02 2.158337e-02 0 0 2.158337e-02 5.507109e-02 0 0 "
	    "0 0 -5.066541e-02 0 0 0 0 -5.066541e-02",
	    NULL);
	CHECK_EQ_INT(r.status, 0);
	CHECK_EQ_INT(r.nlines, 1);
	if (r.nlines == 1) {
		json_t *o = r.lines[0];
		CHECK_NEAR(num(o, "D"), 0.318699, 2e-6);
		CHECK_NEAR(num(o, "R"), 3.14159265358979, 1e-9);
		CHECK_NEAR(num(o, "Delta"), 0.209795, 2e-6);
		CHECK(json_is_true(json_object_get(o, "physical")));
		CHECK(json_is_false(json_object_get(o, "filtered")));
		CHECK_NEAR(mat(o, "M_D", 0, 1), num(o, "D"), 1e-15);
		CHECK_EQ_INT(json_array_size(json_object_get(o, "diattenuation")), 3);
		CHECK_EQ_INT(json_array_size(json_object_get(o, "retardance_axis")), 3);
		CHECK(json_is_number(json_object_get(o, "depol_index")));
	}
	release(&r);
	/* non-physical diag(1, 1, 1, −1): filtered by default, not with --no-filter */
	run(&r, "decompose 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 -1", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK(json_is_true(json_object_get(r.lines[0], "filtered")));
		CHECK(json_is_false(json_object_get(r.lines[0], "physical")));
	}
	release(&r);
	run(&r, "decompose --no-filter 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 -1", NULL);
	CHECK(r.nlines == 1 && json_is_false(json_object_get(r.lines[0], "filtered")));
	release(&r);
	/* a pure polariser: D = 1 flagged, R and Δ null */
	run(&r, "decompose 1 1 0 0 1 1 0 0 0 0 0 0 0 0 0 0", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK(has_flag(r.lines[0], "D_singular"));
		CHECK(json_is_null(json_object_get(r.lines[0], "R")));
		CHECK(json_is_null(json_object_get(r.lines[0], "Delta")));
	}
	release(&r);
	/* batch with a bad line */
	run(&r, "decompose --batch -",
	    "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n"
	    "1 0 0\n"
	    "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 nan\n"
	    "2 0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\n");
	CHECK_EQ_INT(r.status, 2);
	CHECK_EQ_INT(r.nlines, 4);
	if (r.nlines == 4) {
		CHECK_NEAR(num(r.lines[0], "R"), 0, 1e-15);
		CHECK_NEAR(num(r.lines[1], "line"), 2, 0);
		CHECK(strstr(json_string_value(json_object_get(r.lines[1], "error")), "16"));
		CHECK(strstr(json_string_value(json_object_get(r.lines[2], "error")), "m33"));
		CHECK_NEAR(num(r.lines[3], "Delta"), 1, 0);
	}
	release(&r);
	expect_usage_error("decompose 1 2 3", NULL, "16");
	expect_usage_error("decompose 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 5", NULL, "16");
	expect_usage_error("decompose 1 0 0 0 0 1 0 0 0 0 1 0 0 x 0 1", NULL, "m31");
	expect_usage_error("decompose 1 0 0 0 0 1 0 0 0 0 1 0 0 inf 0 1", NULL, "m31");
	expect_usage_error("decompose --bogus", NULL, "--bogus");
	expect_usage_error("decompose --batch", NULL, "--batch");
}

/* figures: all files written; Fig. 10's R columns agree across σ (physics.md §2 invariant) */
/* The hard cases of issue 13 through the commands (docs/physics-notes.md, "Extreme inputs"):
 * finite matrices at the analytic limits, not NaN flagged below_horizon or all zero. */
static void test_hard_cases_cli(void)
{
	static result r;
	/* perfect conductor: K·diag(1, 1, −1, −1), K = 1/(8πσ² cos²θ) without a diffuse term */
	const char *cond[] = {"--n 1.5 --k 1e90", "--n 1e100", "--n 1e100 --k 1e100"};
	for (int i = 0; i < 3; i++) {
		char a[200];
		snprintf(a, sizeof a,
		         "pbrdf %s --sigma 0.2 --theta-i 30 --theta-r 30 --diffuse none", cond[i]);
		run(&r, a, NULL);
		CHECK_EQ_INT(r.status, 0);
		CHECK_EQ_INT(r.nlines, 1);
		if (r.nlines == 1) {
			const double K = 1 / (8 * M_PI * 0.04 * 0.75);
			CHECK_REL(mat(r.lines[0], "mueller", 0, 0), K, 1e-12);
			CHECK_REL(mat(r.lines[0], "mueller", 1, 1), K, 1e-12);
			CHECK_REL(mat(r.lines[0], "mueller", 2, 2), -K, 1e-12);
			CHECK_REL(mat(r.lines[0], "mueller", 3, 3), -K, 1e-12);
			CHECK(!has_flag(r.lines[0], "below_horizon"));
		}
		release(&r);
	}
	/* ñ → 0 at normal incidence: r_s = 1, r_p = −1: K·diag(1, 1, −1, −1), K = 1/(8πσ²) */
	run(&r, "pbrdf --n 1e-200 --sigma 0.2 --theta-i 0 --theta-r 0 --diffuse none", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK_REL(mat(r.lines[0], "mueller", 0, 0), 1 / (8 * M_PI * 0.04), 1e-12);
		CHECK_REL(mat(r.lines[0], "mueller", 3, 3), -1 / (8 * M_PI * 0.04), 1e-12);
	}
	release(&r);
	/* σ = 1e-20 exactly at the specular direction: F(30°)/(8πσ² cos²30°), not 0; glass:
	 * F = (R_s + R_p)/2 at 30° for n = 1.5 */
	run(&r, "pbrdf --n 1.5 --sigma 1e-20 --theta-i 30 --theta-r 30 --diffuse none", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		double c = cos(M_PI / 6), s2 = 0.25, w = sqrt(2.25 - s2);
		double rs = (c - w) / (c + w), rp = (2.25 * c - w) / (2.25 * c + w);
		double F = 0.5 * (rs * rs + rp * rp);
		CHECK_REL(mat(r.lines[0], "mueller", 0, 0), F / (8 * M_PI * 1e-40 * 0.75), 1e-12);
	}
	release(&r);
	/* σ below 1e-50: refused naming sigma */
	expect_usage_error("pbrdf --n 1.5 --sigma 1e-160 --theta-i 0 --theta-r 0", NULL, "sigma");
	expect_usage_error("pbrdf --n 1.5 --sigma 1e-320 --theta-i 0 --theta-r 0", NULL, "1e-50");
	/* Lu–Chipman: the identity and an ideal polarizer times 1e308 are physical; a normalised
	 * m33 of 1e-310 gives Δ = 1 − 1e-310/3 = 1 */
	run(&r, "decompose 1e308 0 0 0 0 1e308 0 0 0 0 1e308 0 0 0 0 1e308", NULL);
	CHECK_EQ_INT(r.status, 0);
	if (r.nlines == 1) {
		CHECK(json_is_true(json_object_get(r.lines[0], "physical")));
		CHECK_NEAR(num(r.lines[0], "D"), 0, 0);
		CHECK_NEAR(num(r.lines[0], "R"), 0, 1e-15);
		CHECK_NEAR(num(r.lines[0], "Delta"), 0, 1e-15);
	}
	release(&r);
	run(&r, "decompose 0.5e308 0.5e308 0 0 0.5e308 0.5e308 0 0 0 0 0 0 0 0 0 0", NULL);
	if (r.nlines == 1) {
		CHECK(json_is_true(json_object_get(r.lines[0], "physical")));
		CHECK_NEAR(num(r.lines[0], "D"), 1, 1e-15);
	}
	release(&r);
	run(&r, "decompose 1e10 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1e-300", NULL);
	if (r.nlines == 1)
		CHECK_NEAR(num(r.lines[0], "Delta"), 1, 1e-15);
	release(&r);
}

static void test_figures(void)
{
	static result r;
	char args[400], path[400];
	snprintf(args, sizeof args, "figures -o '%s/figs'", tmpdir);
	run(&r, args, NULL);
	CHECK_EQ_INT(r.status, 0);
	for (int f = 2; f <= 11; f++) {
		snprintf(path, sizeof path, "%s/figs/fig%02d.png", tmpdir, f);
		CHECK(access(path, R_OK) == 0);
	}
	snprintf(path, sizeof path, "%s/figs/figures.md", tmpdir);
	CHECK(access(path, R_OK) == 0);
	snprintf(path, sizeof path, "%s/figs/fig10.csv", tmpdir);
	FILE *fp = fopen(path, "r");
	CHECK(fp != NULL);
	int rows = 0;
	char line[4096];
	while (fp && fgets(line, sizeof line, fp)) {
		double x, a, b, c;
		if (rows++ == 0)
			continue; /* header */
		CHECK_EQ_INT(sscanf(line, "%lf,%lf,%lf,%lf", &x, &a, &b, &c), 4);
		CHECK_NEAR(a, b, 1e-12);
		CHECK_NEAR(a, c, 1e-12);
	}
	if (fp)
		fclose(fp);
	CHECK_EQ_INT(rows, 180);
	release(&r);
	expect_usage_error("figures", NULL, "-o");
}

static void test_help(void)
{
	static result r;
	run(&r, "pbrdf --help", NULL);
	CHECK_EQ_INT(r.status, 0);
	run(&r, "decompose --help", NULL);
	CHECK_EQ_INT(r.status, 0);
	CHECK(strstr(r.out, "usage: polarcam decompose") != NULL);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	if (!polarcam || access(polarcam, X_OK) != 0)
		SKIP("POLARCAM (path of the built CLI) is not set or not executable");
	if (!pc_test_tmpdir(tmpdir, sizeof tmpdir, "pc_physics_cli"))
		SKIP("cannot create a temporary directory");
	test_pbrdf();
	test_decompose();
	test_hard_cases_cli();
	test_figures();
	test_help();
	char cmd[400];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmpdir);
	return pc_test_finish("test_physics_cli");
}
