/* polarcam pbrdf: the corrected polarized BRDF Mueller matrix (physics.md §2) as JSON lines. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam pbrdf --n N [--k K] --sigma S --theta-i DEG --theta-r DEG [--phi "
	    "DEG]\n"
	    "                      [--diffuse fresnel|geometric|none] [--shadowing ts|none]\n"
	    "                      [--rho quad:N|table]\n"
	    "       polarcam pbrdf --batch FILE|- [--diffuse ...] [--shadowing ...] [--rho ...]\n"
	    "\n"
	    "Evaluates the microfacet polarized BRDF of a rough surface (seed paper eqs. 2-12 as\n"
	    "corrected in docs/physics.md: 8*pi*sigma^2 facet normalisation, vector facet\n"
	    "geometry) and prints one JSON object per line:\n"
	    "  {\"mueller\": [[4 numbers] x 4], \"dop\": x, \"D\": x, \"R\": x, \"Delta\": x, "
	    "\"rho_s\": x,\n"
	    "   \"n\", \"k\", \"sigma\", \"theta_i\", \"theta_r\", \"phi\": the inputs, \"flags\": "
	    "[...]}\n"
	    "mueller is the BRDF Mueller matrix in 1/sr, mapping the incident Stokes vector "
	    "(frame\n"
	    "s_i = (0,1,0), p_i = d_i x s_i) to the reflected one (s_r = (sin phi, -cos phi, 0)).\n"
	    "phi = 180 is the forward (specular) plane, theta_i = theta_r with phi = 0 is exact\n"
	    "backscatter. dop is eq. 21 for unpolarised light; D, R (radians, [0, pi]) and Delta\n"
	    "(eq. 18) come from the Lu-Chipman decomposition (null where undefined, e.g. D = 1 at\n"
	    "Brewster's angle without a diffuse term, or below the horizon where the matrix is "
	    "0).\n"
	    "rho_s is the specular albedo used in the diffuse term (null for --diffuse none).\n"
	    "flags: \"outside_validity\" (sigma > 0.5), \"mirror\" (sigma < 0.01: rho_s is the\n"
	    "Fresnel mirror limit), \"below_horizon\" (theta = 90: the matrix is 0), \"zero\" "
	    "(the\n"
	    "matrix is 0 above the horizon: off the specular lobe without a diffuse term),\n"
	    "\"D_singular\". sigma must be at least 1e-50 (below it the specular peak leaves the\n"
	    "double range); angles are exact at multiples of 90 degrees.\n"
	    "\n"
	    "options:\n"
	    "  --n N             refractive index n > 0 of n~ = n - ik\n"
	    "  --k K             extinction coefficient k >= 0 (default 0)\n"
	    "  --sigma S         rms facet slope per axis, > 0 (not an rms height)\n"
	    "  --theta-i DEG     incidence zenith angle in [0, 90]\n"
	    "  --theta-r DEG     viewing zenith angle in [0, 90]\n"
	    "  --phi DEG         relative azimuth phi_r - phi_i (default 180)\n"
	    "                    sigma and the three angles may be ranges START:STOP:STEP, one "
	    "line\n"
	    "                    per value (loops: sigma, theta-i, theta-r, phi, the last "
	    "fastest)\n"
	    "  --diffuse MODE    fresnel (default: paper eq. 11 with the Fresnel factor),\n"
	    "                    geometric (Fresnel factor 1 in eq. 9), none (specular only)\n"
	    "  --shadowing MODE  ts (Torrance-Sparrow V-groove, default) or none\n"
	    "  --rho MODE        quad:N (slope-space N x N rule, default quad:16) or table (64 x "
	    "32\n"
	    "                    bicubic table); polarcam bench physics shows their error and "
	    "cost\n"
	    "  --batch FILE|-    read lines 'n k sigma theta_i theta_r phi' (degrees; '#' "
	    "comments)\n"
	    "                    and print one object per line with its \"line\"; a bad line "
	    "prints\n"
	    "                    {\"line\": L, \"error\": ..., \"code\": ...}, the rest go on\n"
	    "  --json            accepted: the output is always JSON lines\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or a bad batch line.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam pbrdf --n 1.46 --k 1.28 --sigma 0.2 --theta-i 40 --theta-r 55 --phi 150\n"
	    "  polarcam pbrdf --n 1.5 --sigma 0.1:0.5:0.1 --theta-i 0:85:5 --theta-r 30 --rho "
	    "quad:32\n"
	    "  polarcam pbrdf --batch inputs.txt --diffuse none\n");
}

typedef struct pbrdf_opts {
	pc_diffuse diffuse;
	pc_shadowing shadowing;
	pc_rho_mode rho_mode;
	int rho_order;
} pbrdf_opts;

/* A cache of one prepared material: consecutive lines or range values with the same (n, k, σ)
 * reuse it. */
typedef struct pbrdf_cache {
	pc_pbrdf *p;
	double n, k, sigma;
} pbrdf_cache;

static int get_material(pbrdf_cache *c, const pbrdf_opts *o, double n, double k, double sigma,
                        const pc_pbrdf **out)
{
	if (c->p && c->n == n && c->k == k && c->sigma == sigma) {
		*out = c->p;
		return 0;
	}
	pc_pbrdf_free(c->p);
	c->p = NULL;
	pc_material m = {n, k, sigma, o->diffuse, o->shadowing, o->rho_mode, o->rho_order};
	int rc = pc_pbrdf_new(&m, &c->p);
	if (rc)
		return rc;
	c->n = n;
	c->k = k;
	c->sigma = sigma;
	*out = c->p;
	return 0;
}

static int check_theta(const char *opt, double deg)
{
	if (!(deg >= 0 && deg <= 90))
		return pc_error(PC_EINVAL, "%s %g: must be in [0, 90] degrees", opt, deg);
	return 0;
}

/* One evaluation as a JSON object (line = 0: no "line" field). */
static json_t *evaluate(const pc_pbrdf *p, double ti_deg, double tr_deg, double phi_deg,
                        unsigned long line)
{
	const pc_material *m = pc_pbrdf_material(p);
	double f[4][4];
	pc_pbrdf_eval_deg(p, ti_deg, tr_deg, phi_deg, f);
	json_t *flags = json_array();
	if (pc_pbrdf_flags(p) & PC_PBRDF_OUTSIDE_VALIDITY)
		json_array_append_new(flags, json_string("outside_validity"));
	if (pc_pbrdf_flags(p) & PC_PBRDF_MIRROR)
		json_array_append_new(flags, json_string("mirror"));
	double dop = NAN, D = NAN, R = NAN, Delta = NAN;
	if (f[0][0] > 0) {
		dop = pc_mueller_dop(f);
		pc_lu_chipman lc;
		if (pc_lu_chipman_decompose(f, PC_LC_NO_FACTORS, &lc) == 0) {
			D = lc.D;
			R = lc.R;
			Delta = lc.Delta;
			if (lc.flags & PC_LC_D_SINGULAR)
				json_array_append_new(flags, json_string("D_singular"));
		}
	} else {
		/* all zero: at or below the horizon, or (without a diffuse term) off the lobe */
		double st, ct, sr, cr;
		pc_sincos_deg(ti_deg, &st, &ct);
		pc_sincos_deg(tr_deg, &sr, &cr);
		bool horizon = !(ct > PC_PBRDF_COS_HORIZON) || !(cr > PC_PBRDF_COS_HORIZON);
		json_array_append_new(flags, json_string(horizon ? "below_horizon" : "zero"));
	}
	double sti, cti;
	pc_sincos_deg(ti_deg, &sti, &cti);
	double rho = m->diffuse == PC_DIFFUSE_NONE ? NAN : pc_pbrdf_rho_s_fast(p, cti);
	json_t *o = json_object();
	if (line)
		json_object_set_new(o, "line", json_integer((json_int_t)line));
	json_object_set_new(o, "mueller", cli_json_matrix4(f));
	json_object_set_new(o, "dop", cli_json_real(dop));
	json_object_set_new(o, "D", cli_json_real(D));
	json_object_set_new(o, "R", cli_json_real(R));
	json_object_set_new(o, "Delta", cli_json_real(Delta));
	json_object_set_new(o, "rho_s", cli_json_real(rho));
	json_object_set_new(o, "n", json_real(m->n));
	json_object_set_new(o, "k", json_real(m->k));
	json_object_set_new(o, "sigma", json_real(m->sigma));
	json_object_set_new(o, "theta_i", json_real(ti_deg));
	json_object_set_new(o, "theta_r", json_real(tr_deg));
	json_object_set_new(o, "phi", json_real(phi_deg));
	json_object_set_new(o, "flags", flags);
	return o;
}

static void warn_material(const pc_pbrdf *p, double sigma)
{
	static double last = -1;
	if ((pc_pbrdf_flags(p) & PC_PBRDF_OUTSIDE_VALIDITY) && sigma != last) {
		cli_warn("sigma = %g > %g: outside the single-scattering V-groove model's validity "
		         "(energy is lost)",
		         sigma, PC_PBRDF_SIGMA_VALID_MAX);
		last = sigma;
	}
}

static int run_batch(const char *path, const pbrdf_opts *o)
{
	cli_lines in;
	int rc = cli_lines_open(&in, path);
	if (rc)
		return cli_fail(rc, NULL);
	static const char *const names[6] = {"n", "k", "sigma", "theta_i", "theta_r", "phi"};
	pbrdf_cache cache = {0};
	int status = CLI_EXIT_OK;
	char *line;
	while ((rc = cli_lines_next(&in, &line)) > 0) {
		double v[6];
		const pc_pbrdf *p = NULL;
		rc = cli_parse_fields_n(line, in.len, names, 6, v);
		if (!rc)
			rc = check_theta("theta_i", v[3]);
		if (!rc)
			rc = check_theta("theta_r", v[4]);
		if (!rc)
			rc = get_material(&cache, o, v[0], v[1], v[2], &p);
		if (rc) {
			cli_batch_error(&in, rc, &status);
			continue;
		}
		warn_material(p, v[2]);
		cli_print_json(evaluate(p, v[3], v[4], v[5], in.lineno));
	}
	if (rc < 0)
		status = cli_fail(rc, NULL);
	pc_pbrdf_free(cache.p);
	cli_lines_close(&in);
	return status;
}

/* --n ... --phi with ranges: one line per value */
static int run_ranges(const pbrdf_opts *op, const char *arg_n, const char *arg_k,
                      const char *arg_sigma, const char *arg_ti, const char *arg_tr,
                      const char *arg_phi)
{
	const pbrdf_opts o = *op;
	int rc;
	double n, k;
	if ((rc = cli_parse_double("--n", arg_n, &n)) || (rc = cli_parse_double("--k", arg_k, &k)))
		return cli_fail(rc, NULL);
	if (!(n > 0))
		return cli_error(CLI_EXIT_USAGE, "--n %g: must be > 0", n);
	if (!(k >= 0))
		return cli_error(CLI_EXIT_USAGE, "--k %g: must be >= 0 (n~ = n - ik)", k);
	double *sg = NULL, *ti = NULL, *tr = NULL, *ph = NULL;
	size_t nsg = 0, nti = 0, ntr = 0, nph = 0;
	int status = CLI_EXIT_OK;
	if ((rc = cli_parse_range("--sigma", arg_sigma, &sg, &nsg)) ||
	    (rc = cli_parse_range("--theta-i", arg_ti, &ti, &nti)) ||
	    (rc = cli_parse_range("--theta-r", arg_tr, &tr, &ntr)) ||
	    (rc = cli_parse_range("--phi", arg_phi, &ph, &nph))) {
		status = cli_fail(rc, NULL);
		goto out;
	}
	for (size_t i = 0; i < nsg; i++)
		if (!(sg[i] > 0)) {
			status =
			    cli_error(CLI_EXIT_USAGE, "--sigma %g: must be > 0 (rms slope)", sg[i]);
			goto out;
		}
	for (size_t i = 0; i < nti; i++)
		if ((rc = check_theta("--theta-i", ti[i])))
			goto bad;
	for (size_t i = 0; i < ntr; i++)
		if ((rc = check_theta("--theta-r", tr[i])))
			goto bad;
	pbrdf_cache cache = {0};
	for (size_t a = 0; a < nsg; a++) {
		const pc_pbrdf *p;
		if ((rc = get_material(&cache, &o, n, k, sg[a], &p))) {
			pc_pbrdf_free(cache.p);
			goto bad;
		}
		warn_material(p, sg[a]);
		for (size_t b = 0; b < nti; b++)
			for (size_t c2 = 0; c2 < ntr; c2++)
				for (size_t d = 0; d < nph; d++)
					cli_print_json(evaluate(p, ti[b], tr[c2], ph[d], 0));
	}
	pc_pbrdf_free(cache.p);
	goto out;
bad:
	status = cli_fail(rc, NULL);
out:
	free(sg);
	free(ti);
	free(tr);
	free(ph);
	return status;
}

enum { O_N = 1000, O_K, O_SIGMA, O_TI, O_TR, O_PHI, O_DIFFUSE, O_SHADOW, O_RHO, O_BATCH };

/* --diffuse, --shadowing, --rho: 0 or an exit status after the message */
static int parse_mode(pbrdf_opts *o, int c, const char *arg)
{
	int rc;
	if (c == O_DIFFUSE) {
		if (!strcmp(arg, "fresnel"))
			o->diffuse = PC_DIFFUSE_FRESNEL;
		else if (!strcmp(arg, "geometric"))
			o->diffuse = PC_DIFFUSE_GEOMETRIC;
		else if (!strcmp(arg, "none"))
			o->diffuse = PC_DIFFUSE_NONE;
		else
			return cli_error(CLI_EXIT_USAGE,
			                 "--diffuse '%s': expected fresnel, geometric or none",
			                 arg);
	} else if (c == O_SHADOW) {
		if (!strcmp(arg, "ts"))
			o->shadowing = PC_SHADOW_TS;
		else if (!strcmp(arg, "none"))
			o->shadowing = PC_SHADOW_NONE;
		else
			return cli_error(CLI_EXIT_USAGE, "--shadowing '%s': expected ts or none",
			                 arg);
	} else {
		if (!strcmp(arg, "table")) {
			o->rho_mode = PC_RHO_TABLE;
		} else if (!strncmp(arg, "quad:", 5)) {
			long N;
			if ((rc = cli_parse_long("--rho quad:N", arg + 5, 2, 1024, &N)))
				return cli_fail(rc, NULL);
			o->rho_mode = PC_RHO_QUAD;
			o->rho_order = (int)N;
		} else {
			return cli_error(CLI_EXIT_USAGE,
			                 "--rho '%s': expected quad:N (N in [2, 1024]) or table",
			                 arg);
		}
	}
	return 0;
}

int cli_cmd_pbrdf(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	static const struct option lo[] = {
	    {"n", required_argument, NULL, O_N},
	    {"k", required_argument, NULL, O_K},
	    {"sigma", required_argument, NULL, O_SIGMA},
	    {"theta-i", required_argument, NULL, O_TI},
	    {"theta-r", required_argument, NULL, O_TR},
	    {"phi", required_argument, NULL, O_PHI},
	    {"diffuse", required_argument, NULL, O_DIFFUSE},
	    {"shadowing", required_argument, NULL, O_SHADOW},
	    {"rho", required_argument, NULL, O_RHO},
	    {"batch", required_argument, NULL, O_BATCH},
	    {"json", no_argument, NULL, 'J'},
	    {NULL, 0, NULL, 0},
	};
	pbrdf_opts o = {PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0};
	const char *arg_n = NULL, *arg_k = "0", *arg_sigma = NULL, *arg_ti = NULL, *arg_tr = NULL,
	           *arg_phi = "180", *batch = NULL;
	int c, rc;
	opterr = 0;
	optind = 1;
	while ((c = getopt_long(argc, argv, ":", lo, NULL)) != -1) {
		switch (c) {
		case O_N:
			arg_n = optarg;
			break;
		case O_K:
			arg_k = optarg;
			break;
		case O_SIGMA:
			arg_sigma = optarg;
			break;
		case O_TI:
			arg_ti = optarg;
			break;
		case O_TR:
			arg_tr = optarg;
			break;
		case O_PHI:
			arg_phi = optarg;
			break;
		case O_DIFFUSE:
		case O_SHADOW:
		case O_RHO:
			if ((rc = parse_mode(&o, c, optarg)))
				return rc; /* an exit status */
			break;
		case O_BATCH:
			batch = optarg;
			break;
		case 'J': /* the output is JSON lines anyway */
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s: missing value", argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE,
			                 "unknown option '%s' (polarcam pbrdf --help)",
			                 argv[optind - 1]);
		}
	}
	if (optind < argc)
		return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s' (polarcam pbrdf --help)",
		                 argv[optind]);
	if (batch) {
		if (arg_n || arg_sigma || arg_ti || arg_tr)
			return cli_error(CLI_EXIT_USAGE,
			                 "--batch reads n, k, sigma and the angles from its lines; "
			                 "do not also give --n/--sigma/--theta-i/--theta-r");
		if (cli_parse_only())
			return CLI_EXIT_OK;
		return run_batch(batch, &o);
	}
	const struct {
		const char *opt, *val;
	} req[] = {
	    {"--n", arg_n}, {"--sigma", arg_sigma}, {"--theta-i", arg_ti}, {"--theta-r", arg_tr}};
	for (size_t i = 0; i < sizeof req / sizeof req[0]; i++)
		if (!req[i].val)
			return cli_error(CLI_EXIT_USAGE, "%s is required (polarcam pbrdf --help)",
			                 req[i].opt);
	if (cli_parse_only())
		return CLI_EXIT_OK;
	return run_ranges(&o, arg_n, arg_k, arg_sigma, arg_ti, arg_tr, arg_phi);
}
