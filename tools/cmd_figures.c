/* polarcam figures: the seed paper's Figs. 2–11 under the corrected model (physics.md §8) as CSV
 * and PNG, with each of the paper's claims checked numerically (polarcam/figures.h). */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/figures.h"
#include "polarcam/folders.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam figures -o DIR [--overwrite] [--json]\n"
	    "\n"
	    "Reproduces Figs. 2-11 of the seed paper (Zhang, Wang, He, Acta Optica Sinica 38(3)\n"
	    "0329002, 2018) with the corrected model of docs/physics.md (8*pi*sigma^2 facet\n"
	    "normalisation, Torrance-Sparrow shadowing, Fresnel-weighted diffuse term with\n"
	    "rho^s by quad:64), and checks each of the paper's claims about them.\n"
	    "Parameters (physics.md section 8; the paper does not give theta_r for Figs. 3-8):\n"
	    "  Fig. 2     DoP vs theta_i, theta_r = 60, dphi = 180: green paint 1.47-0.47i, s "
	    "0.1;\n"
	    "             black paint 1.46-1.28i, s 0.2 (dashed: the paper's printed 4*pi*s^2)\n"
	    "  Figs. 3-5  D, R, Delta vs theta_i, dphi = 180, theta_r = 15, 30, 45, 60 (black "
	    "paint)\n"
	    "  Figs. 6-8  D, R, Delta vs dphi, theta_i = 60, theta_r = 15, 30, 45, 60 (black "
	    "paint)\n"
	    "  Figs. 9-11 D, R, Delta vs theta_i, theta_r = 30, dphi = 180, sigma = 0.2, 0.5, 0.7\n"
	    "Writes into DIR: figNN.csv (x and one column per curve, and the same curves under "
	    "the\n"
	    "printed 4*pi*sigma^2 normalisation), figNN.png, and figures.md (each claim, whether\n"
	    "it reproduces, with the numbers). Angles in degrees, R in radians.\n"
	    "\n"
	    "options:\n"
	    "  -o, --output DIR  output folder, made beside DIR and renamed into place when\n"
	    "                    complete (refused when it exists, unless --overwrite)\n"
	    "  --overwrite       replace DIR as a whole when it exists\n"
	    "  --json            print one JSON line per claim on stdout\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or DIR exists.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam figures -o figures/\n"
	    "  polarcam figures -o figures/ --overwrite --json\n");
}

/* the figures, the claims, the files and the report */
static int run(const char *dir, bool overwrite, bool json)
{
	pc_figure *figs = calloc(12, sizeof *figs);
	pc_figure_claim *claims = calloc(PC_FIGURE_MAX_CLAIMS, sizeof *claims);
	if (!figs || !claims) {
		free(figs);
		free(claims);
		return cli_error(CLI_EXIT_FAILURE, "out of memory");
	}
	cli_progress bar = {0};
	pc_progress pr = {cli_progress_fn, &bar};
	int rc = pc_figures_compute(figs);
	size_t n = rc ? 0 : pc_figures_check(figs, claims, PC_FIGURE_MAX_CLAIMS);
	if (!rc)
		rc = pc_figures_write(dir, overwrite ? PC_OUT_OVERWRITE : 0, figs, claims, n, &pr);
	cli_progress_end(&bar);
	for (size_t k = 0; !rc && json && k < n; k++)
		cli_print_json(json_pack(
		    "{s:i, s:s, s:s, s:s, s:s}", "figure", claims[k].figure, "claim",
		    claims[k].text, "corrected", pc_verdict_name(claims[k].corrected), "printed",
		    pc_verdict_name(claims[k].printed), "evidence", claims[k].evidence));
	free(figs);
	free(claims);
	if (rc)
		return cli_fail(rc, NULL);
	cli_info("wrote fig02..fig11 (.csv, .png) and figures.md to %s", dir);
	return CLI_EXIT_OK;
}

int cli_cmd_figures(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option lo[] = {{"output", required_argument, NULL, 'o'},
	                                   {"json", no_argument, NULL, 'j'},
	                                   {"overwrite", no_argument, NULL, 'W'},
	                                   {NULL, 0, NULL, 0}};
	const char *dir = NULL;
	bool json = false, overwrite = false;
	int c;
	opterr = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, ":o:", lo, NULL)) != -1) {
		if (c == 'o')
			dir = optarg;
		else if (c == 'j')
			json = true;
		else if (c == 'W')
			overwrite = true;
		else if (c == ':')
			return cli_error(CLI_EXIT_USAGE, "%s: missing value", argv[optind - 1]);
		else
			return cli_error(CLI_EXIT_USAGE,
			                 "unknown option '%s' (polarcam figures --help)",
			                 argv[optind - 1]);
	}
	if (optind < argc)
		return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s'", argv[optind]);
	if (!dir)
		return cli_error(CLI_EXIT_USAGE, "-o DIR is required (polarcam figures --help)");
	if (cli_parse_only())
		return CLI_EXIT_OK;
	return run(dir, overwrite, json);
}
