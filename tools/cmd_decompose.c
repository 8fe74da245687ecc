/* polarcam decompose: Lu–Chipman decomposition of Mueller matrices (physics.md §3, §4) as JSON
 * lines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam decompose [--no-filter] m00 m01 m02 m03 m10 ... m33\n"
	    "       polarcam decompose [--no-filter] --batch FILE|-\n"
	    "\n"
	    "Lu-Chipman polar decomposition M = M_Delta M_R M_D (docs/physics.md section 3) of a\n"
	    "Mueller matrix given row by row (16 numbers; negative numbers are fine). Prints one\n"
	    "JSON object per matrix:\n"
	    "  {\"D\", \"R\", \"Delta\", \"diattenuation\": [3], \"retardance_axis\": [3],\n"
	    "   \"M_D\", \"M_R\", \"M_Delta\": 4x4 (of M/M00), \"physical\": bool, \"filtered\": "
	    "bool,\n"
	    "   \"flags\": [...], \"m00\", \"R_linear\", \"R_circular\", \"depol_index\"}\n"
	    "D = |D vector| (diattenuation vector = first row of M/M00); R = retardance in "
	    "radians,\n"
	    "[0, pi], from atan2 (exact near 0 and pi); retardance_axis = unit (a1, a2, a3) with\n"
	    "a = (mR[1][2] - mR[2][1], mR[2][0] - mR[0][2], mR[0][1] - mR[1][0]) of the 3x3 "
	    "block:\n"
	    "a1, a2 linear, a3 circular; R_linear = linear retardance, R_circular = optical\n"
	    "rotation psi (M_R = M_linear(R_linear) M_rotator(psi), the rotator turning the plane\n"
	    "of polarisation by +psi from s towards p); Delta = 1 - |tr m_Delta|/3 (paper eq. "
	    "18);\n"
	    "depol_index = Gil-Bernabeu depolarisation index (1 pure, 0 ideal depolariser).\n"
	    "physical: the coherency matrix of M is positive semi-definite (eigenvalues >= -1e-9\n"
	    "of its trace). By default a non-physical M is Cloude-filtered first (negative\n"
	    "coherency eigenvalues set to 0; \"filtered\": true) and D, Delta are kept in [0, 1].\n"
	    "Undefined values are null: with D >= 1 - 1e-6 (flag D_singular) R, Delta, M_R and\n"
	    "M_Delta are undefined; flag R_nonunique when m' is (nearly) singular; zero_m00 when\n"
	    "M00 <= 0; clamped when D or Delta were clamped after filtering.\n"
	    "\n"
	    "options:\n"
	    "  --no-filter       decompose the matrix as given, even if it is not physical\n"
	    "  --batch FILE|-    read 16 numbers per line ('#' comments); prints one object per\n"
	    "                    line with its \"line\"; a bad line prints {\"line\": L, "
	    "\"error\":\n"
	    "                    ..., \"code\": ...} and the others are still processed\n"
	    "  --json            accepted: the output is always JSON lines\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or a bad batch line.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam decompose 1 0.3 0 0  0.3 1 0 0  0 0 0.9 0.1  0 0 -0.1 0.9\n"
	    "  polarcam decompose --no-filter 1 0 0 0 0 1 0 0 0 0 -1 0 0 0 0 -1\n"
	    "  polarcam decompose --batch matrices.txt\n");
}

static const char *const pc_m_names[16] = {"m00", "m01", "m02", "m03", "m10", "m11", "m12", "m13",
                                           "m20", "m21", "m22", "m23", "m30", "m31", "m32", "m33"};

static json_t *result_json(const pc_lu_chipman *lc, unsigned long line)
{
	static const struct {
		unsigned bit;
		const char *name;
	} fl[] = {{PC_LC_D_SINGULAR, "D_singular"},   {PC_LC_R_NONUNIQUE, "R_nonunique"},
	          {PC_LC_NONPHYSICAL, "nonphysical"}, {PC_LC_FILTERED, "filtered"},
	          {PC_LC_CLAMPED, "clamped"},         {PC_LC_ZERO_M00, "zero_m00"}};
	json_t *flags = json_array();
	for (size_t i = 0; i < sizeof fl / sizeof fl[0]; i++)
		if (lc->flags & fl[i].bit)
			json_array_append_new(flags, json_string(fl[i].name));
	json_t *o = json_object();
	if (line)
		json_object_set_new(o, "line", json_integer((json_int_t)line));
	json_object_set_new(o, "D", cli_json_real(lc->D));
	json_object_set_new(o, "R", cli_json_real(lc->R));
	json_object_set_new(o, "Delta", cli_json_real(lc->Delta));
	json_object_set_new(o, "diattenuation", cli_json_vec(lc->D_vec, 3));
	json_object_set_new(o, "retardance_axis", cli_json_vec(lc->R_axis, 3));
	json_object_set_new(o, "M_D", cli_json_matrix4(lc->M_D));
	json_object_set_new(o, "M_R", cli_json_matrix4(lc->M_R));
	json_object_set_new(o, "M_Delta", cli_json_matrix4(lc->M_Delta));
	json_object_set_new(o, "physical", json_boolean(lc->physical));
	json_object_set_new(o, "filtered", json_boolean(lc->filtered));
	json_object_set_new(o, "flags", flags);
	json_object_set_new(o, "m00", cli_json_real(lc->m00));
	json_object_set_new(o, "R_linear", cli_json_real(lc->R_linear));
	json_object_set_new(o, "R_circular", cli_json_real(lc->R_circular));
	json_object_set_new(o, "depol_index", cli_json_real(lc->depol_index));
	return o;
}

static int run_batch(const char *path, unsigned options)
{
	cli_lines in;
	int rc = cli_lines_open(&in, path);
	if (rc)
		return cli_fail(rc, NULL);
	int status = CLI_EXIT_OK;
	char *line;
	while ((rc = cli_lines_next(&in, &line)) > 0) {
		double m[16];
		pc_lu_chipman lc;
		rc = cli_parse_fields_n(line, in.len, pc_m_names, 16, m);
		if (!rc)
			rc = pc_lu_chipman_decompose((const double(*)[4])m, options, &lc);
		if (rc) {
			cli_batch_error(&in, rc, &status);
			continue;
		}
		cli_print_json(result_json(&lc, in.lineno));
	}
	if (rc < 0)
		status = cli_fail(rc, NULL);
	cli_lines_close(&in);
	return status;
}

int cli_cmd_decompose(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	unsigned options = PC_LC_FILTER;
	const char *batch = NULL;
	double m[16];
	int count = 0, rc;
	bool only_positional = false;
	/* hand-parsed: a matrix element may be negative ("-0.5") and must not look like an option
	 */
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		double v;
		if (!only_positional && !strcmp(a, "--")) {
			only_positional = true;
		} else if (!only_positional && !strcmp(a, "--json")) {
			/* the output is JSON lines anyway */
		} else if (!only_positional && !strcmp(a, "--no-filter")) {
			options &= ~(unsigned)PC_LC_FILTER;
		} else if (!only_positional && !strcmp(a, "--batch")) {
			if (i + 1 >= argc)
				return cli_error(CLI_EXIT_USAGE,
				                 "--batch: missing FILE (or - for stdin)");
			batch = argv[++i];
		} else if (!only_positional && !strncmp(a, "--batch=", 8)) {
			batch = a + 8;
		} else if (!only_positional && a[0] == '-' && a[1] && a[1] != '.' &&
		           !(a[1] >= '0' && a[1] <= '9')) {
			return cli_error(CLI_EXIT_USAGE,
			                 "unknown option '%s' (polarcam decompose --help)", a);
		} else {
			if (count < 16) {
				char opt[48];
				snprintf(opt, sizeof opt, "element %d (%s)", count + 1,
				         pc_m_names[count]);
				if ((rc = cli_parse_double(opt, a, &v)))
					return cli_fail(rc, NULL);
				m[count] = v;
			}
			count++;
		}
	}
	if (batch) {
		if (count)
			return cli_error(
			    CLI_EXIT_USAGE,
			    "--batch reads the matrices from FILE; do not also give %d "
			    "numbers on the command line",
			    count);
		if (cli_parse_only())
			return CLI_EXIT_OK;
		return run_batch(batch, options);
	}
	if (count != 16)
		return cli_error(CLI_EXIT_USAGE,
		                 "expected 16 matrix elements m00 m01 ... m33 (row by row), got %d",
		                 count);
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_lu_chipman lc;
	rc = pc_lu_chipman_decompose((const double(*)[4])m, options, &lc);
	if (rc)
		return cli_fail(rc, NULL);
	cli_print_json(result_json(&lc, 0));
	return CLI_EXIT_OK;
}
