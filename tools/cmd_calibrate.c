/* polarcam calibrate: dark, flat, analyser, ecm, show (calib/include/polarcam/calib.h;
 * procedure and file format: docs/calibration.md). Each subcommand parses, makes one library
 * call and reports. */
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/io.h"
#include "polarcam/folders.h"
#include "polarcam/recording.h"
#include "polarcam/states.h"
#include "polarcam/version.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam calibrate dark REC -o F [options]\n"
	    "       polarcam calibrate flat REC... [--dark F] -o F [options]\n"
	    "       polarcam calibrate analyser REC... [--angles A,B,...|--unknown-angles]\n"
	    "                                 [--dark F] [--flat F] -o F [options]\n"
	    "       polarcam calibrate ecm --states NOMINAL --air REC --polarizer REC\n"
	    "                              --polarizer2 REC --retarder REC [--dark F] -o F\n"
	    "                              [--states-out FILE]\n"
	    "       polarcam calibrate show F [--pictures DIR]\n"
	    "       (every step also takes --overwrite and --json)\n"
	    "\n"
	    "Calibrates a division-of-focal-plane polarization camera from recordings (polarcam\n"
	    "render or capture output, one uniform stimulus each). The steps build one file per\n"
	    "camera (.npz, readable with numpy.load; docs/calibration.md): each step copies the\n"
	    "parts of the file given with --dark/--flat and adds its own.\n"
	    "\n"
	    "  dark      N >= 2 frames with the lens capped: per-pixel offset and temporal noise\n"
	    "  flat      one recording per light level (>= 2 levels) of uniform unpolarized "
	    "light:\n"
	    "            per-pixel gain (the slope through the levels)\n"
	    "  analyser  one recording per polarizer angle (>= 3 angles; >= 4 with\n"
	    "            --unknown-angles) of a uniform linearly polarized field: per-pixel\n"
	    "            analysis vectors and 4x3 analysis matrices. The angle of each recording\n"
	    "            comes from --angles (degrees, in the order of the recordings) or, for a\n"
	    "            rendered recording, from its meta.json\n"
	    "  ecm       eigenvalue calibration of a Mueller imaging setup (Compain et al. 1999):\n"
	    "            4 recordings of one full state cycle each (air, polarizer at 0 deg,\n"
	    "            polarizer near 90 deg, retarder near 30 deg); writes the generator and\n"
	    "            analyser matrices into F and, with --states-out, as a states file that\n"
	    "            polarcam mueller --states reads\n"
	    "  show      JSON summary of a calibration file: parts, residuals, map statistics\n"
	    "\n"
	    "options:\n"
	    "  -o, --output F       the calibration file to write (atomically; an existing F is\n"
	    "                       refused unless --overwrite, or unless it is the --dark/--flat\n"
	    "                       file the step starts from, which is then updated)\n"
	    "  --overwrite          replace F (and --pictures DIR, --states-out FILE)\n"
	    "  --dark F, --flat F   earlier calibration files to start from\n"
	    "  --angles A,B,...     analyser stimuli angles in degrees\n"
	    "  --unknown-angles     estimate the angles (self-calibration)\n"
	    "  --dolp P             the stimuli's DoLP (default: meta.json, else 1)\n"
	    "  --saturation DN      samples at or above it are saturated (default 2^bits - 1)\n"
	    "  --camera TEXT        camera model recorded in the file (default: the recording's\n"
	    "                       source)\n"
	    "  --theta2 DEG, --theta3 DEG  ECM: nominal orientations of the second polarizer and\n"
	    "                       the retarder (default 90 and 30; refined within +-20 deg)\n"
	    "  --pictures DIR       show: write maps of gain, orientation error, extinction ratio\n"
	    "                       into the folder DIR (with meta.json: the summary)\n"
	    "  --json               print the summary as one JSON line on stdout (show always\n"
	    "                       prints it)\n"
	    "Exit status: 0 success, 1 failure, 2 bad arguments or input, or an output exists\n"
	    "(nothing is written).\n"
	    "\n"
	    "examples:\n"
	    "  polarcam calibrate dark rec/dark -o cam.npz\n"
	    "  polarcam calibrate flat rec/fl rec/fh --dark cam.npz -o cam.npz --json\n"
	    "  polarcam calibrate show cam.npz --pictures cam-maps/\n");
}

/* ---- recordings as frame stacks ---- */

typedef struct rec_stack {
	pc_recording *r;
	pc_calib_stack s;
	char source[128];
} rec_stack;

static int rec_get(void *user, size_t i, pc_view *out)
{
	return pc_recording_read((const pc_recording *)user, i, out);
}

/* The stimulus of a rendered recording: the first column of the first PSA element's Mueller
 * matrix (a uniform unpolarized background seen through it). */
static void rec_stimulus(const char *dir, double *angle_deg, double *dolp)
{
	char mp[4096];
	if ((size_t)snprintf(mp, sizeof mp, "%s/meta.json", dir) >= sizeof mp)
		return;
	json_t *m = json_load_file(mp, 0, NULL);
	json_t *pm = json_array_get(json_object_get(json_object_get(m, "extra"), "psa_mueller"), 0);
	if (json_is_array(pm) && json_array_size(pm) == 4) {
		double c[3];
		bool ok = true;
		for (int i = 0; i < 3; i++) {
			json_t *x = json_array_get(json_array_get(pm, (size_t)i), 0);
			ok &= json_is_number(x);
			c[i] = json_number_value(x);
		}
		if (ok && c[0] > 0 && hypot(c[1], c[2]) > 1e-6 * c[0]) {
			double a = 0.5 * atan2(c[2], c[1]) * 180 / M_PI;
			*angle_deg = a < 0 ? a + 180 : a;
			*dolp = hypot(c[1], c[2]) / c[0];
		}
	}
	json_decref(m);
}

static int rec_open(const char *dir, rec_stack *rs)
{
	memset(rs, 0, sizeof *rs);
	int rc = pc_recording_open(&rs->r, dir);
	if (rc)
		return rc;
	const pc_recording_desc *d = pc_recording_get_desc(rs->r);
	const pc_format_info *fi = pc_format_info_get(d->format);
	rs->s.name = pc_recording_dir(rs->r);
	rs->s.geo.width = d->width;
	rs->s.geo.height = d->height;
	rs->s.geo.offset_x = d->offset_x;
	rs->s.geo.offset_y = d->offset_y;
	rs->s.geo.sensor_width = d->sensor_width;
	rs->s.geo.sensor_height = d->sensor_height;
	rs->s.geo.bits = fi ? fi->bits : 16;
	rs->s.geo.mosaic = d->mosaic;
	rs->s.n = pc_recording_count(rs->r);
	rs->s.get = rec_get;
	rs->s.user = rs->r;
	rs->s.exposure_us = rs->s.n ? pc_recording_get_frame(rs->r, 0)->exposure_us : NAN;
	/* one analog gain for the stack (NAN: the source did not say) */
	rs->s.gain_db = rs->s.n ? pc_recording_get_frame(rs->r, 0)->gain_db : NAN;
	for (size_t i = 1; i < rs->s.n; i++) {
		const double gi = pc_recording_get_frame(rs->r, i)->gain_db;
		if (!(gi == rs->s.gain_db || (isnan(gi) && isnan(rs->s.gain_db)))) {
			rc = pc_error(
			    PC_EINVAL,
			    "%s: frame %zu is at %g dB of analog gain, frame 0 at %g dB: a "
			    "calibration recording needs one gain",
			    dir, i, gi, rs->s.gain_db);
			pc_recording_free(rs->r);
			rs->r = NULL;
			return rc;
		}
	}
	rs->s.angle_deg = NAN;
	rs->s.dolp = NAN;
	rec_stimulus(dir, &rs->s.angle_deg, &rs->s.dolp);
	snprintf(rs->source, sizeof rs->source, "%s", d->source ? d->source : dir);
	return 0;
}

static void rec_close(rec_stack *rs)
{
	if (rs->r)
		pc_recording_free(rs->r);
	rs->r = NULL;
}

/* ---- reports ---- */

typedef struct map_stats {
	double mean, sd, min, max, p01, p99;
	size_t n;
} map_stats;

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static json_t *stats_json(const double *v, size_t n)
{
	json_t *o = json_object();
	if (!n)
		return o;
	double *t = malloc(n * sizeof *t);
	if (!t)
		return o;
	memcpy(t, v, n * sizeof *t);
	qsort(t, n, sizeof *t, cmp_d);
	double s = 0, ss = 0;
	for (size_t i = 0; i < n; i++)
		s += t[i];
	double mean = s / (double)n;
	for (size_t i = 0; i < n; i++)
		ss += (t[i] - mean) * (t[i] - mean);
	json_object_set_new(o, "mean", cli_json_real(mean));
	json_object_set_new(o, "sd", cli_json_real(n > 1 ? sqrt(ss / (double)(n - 1)) : 0));
	json_object_set_new(o, "min", cli_json_real(t[0]));
	json_object_set_new(o, "p01", cli_json_real(t[n / 100]));
	json_object_set_new(o, "median", cli_json_real(t[n / 2]));
	json_object_set_new(o, "p99", cli_json_real(t[n - 1 - n / 100]));
	json_object_set_new(o, "max", cli_json_real(t[n - 1]));
	json_object_set_new(o, "pixels", json_integer((json_int_t)n));
	free(t);
	return o;
}

/* The summary of a calibration (show, and every step's report). pictures: directory or NULL. */
static json_t *summary(const pc_calib *c, const char *pictures, int *rc_out)
{
	json_t *o = json_object();
	*rc_out = 0;
	const uint32_t W = c->geo.width, H = c->geo.height;
	const size_t np = (size_t)W * H;
	char lay[64];
	pc_mosaic_format(&c->geo.mosaic, lay, sizeof lay);
	json_t *parts = json_array();
	static const char *const names[4] = {"dark", "flat", "analyser", "ecm"};
	for (int i = 0; i < 4; i++)
		if (c->parts & (1u << i))
			json_array_append_new(parts, json_string(names[i]));
	json_object_set_new(o, "parts", parts);
	json_object_set_new(o, "camera", json_string(c->camera));
	json_object_set_new(o, "width", json_integer(W));
	json_object_set_new(o, "height", json_integer(H));
	json_object_set_new(o, "offset_x", json_integer(c->geo.offset_x));
	json_object_set_new(o, "offset_y", json_integer(c->geo.offset_y));
	json_object_set_new(o, "bits", json_integer(c->geo.bits));
	json_object_set_new(o, "layout", json_string(lay));
	json_object_set_new(o, "black_level", cli_json_real(c->black_level));
	json_object_set_new(o, "saturation", cli_json_real(c->saturation));
	json_object_set_new(o, "system_gain",
	                    c->system_gain > 0 ? cli_json_real(c->system_gain) : json_null());
	json_object_set_new(o, "system_gain_db",
	                    c->system_gain > 0 && isfinite(c->system_gain_db)
	                        ? cli_json_real(c->system_gain_db)
	                        : json_null());
	json_object_set_new(o, "dark_gain_db",
	                    c->dark && isfinite(c->dark_gain_db) ? cli_json_real(c->dark_gain_db)
	                                                         : json_null());
	size_t nv = 0;
	for (size_t p = 0; c->valid && p < np; p++)
		nv += c->valid[p] != 0;
	json_object_set_new(o, "pixels_invalid",
	                    json_integer((json_int_t)(c->valid ? np - nv : 0)));
	double *v = malloc(np * sizeof *v);
	float *pic = pictures ? malloc(np * sizeof *pic) : NULL;
	if (!v || (pictures && !pic)) {
		free(v);
		free(pic);
		*rc_out = PC_ENOMEM;
		return o;
	}
#define COLLECT(expr)                                                                              \
	do {                                                                                       \
		n = 0;                                                                             \
		for (uint32_t y = 0; y < H; y++)                                                   \
			for (uint32_t x = 0; x < W; x++) {                                         \
				size_t p = (size_t)y * W + x;                                      \
				double val = (expr);                                               \
				if (pic)                                                           \
					pic[p] = (float)val;                                       \
				if (!c->valid || c->valid[p])                                      \
					v[n++] = val;                                              \
			}                                                                          \
	} while (0)
	size_t n;
	int rc = 0;
	if (c->dark) {
		COLLECT(c->dark[p]);
		json_object_set_new(o, "dark_dn", stats_json(v, n));
		COLLECT(c->dark_noise[p]);
		json_object_set_new(o, "dark_noise_dn", stats_json(v, n));
	}
	if (c->gain) {
		COLLECT(c->gain[p]);
		json_object_set_new(o, "gain", stats_json(v, n));
		if (pic && !rc)
			rc = pc_map_write(pictures, "gain", pic, W, H, 0.9, 1.1,
			                  "Relative gain (flat)", "gain");
	}
	if (c->analysis) {
		const float *a = c->analysis;
		/* per pixel: transmission t = 2·a0, diattenuation d = |(a1, a2)|/a0 (ER = (1 +
		 * d)/(1 − d)), orientation ½·atan2(a2, a1) minus the nominal channel angle
		 * (physics.md §6) */
		COLLECT(2 * a[3 * p]);
		json_object_set_new(o, "transmission", stats_json(v, n));
		COLLECT(hypot(a[3 * p + 1], a[3 * p + 2]) / a[3 * p]);
		json_object_set_new(o, "diattenuation", stats_json(v, n));
		COLLECT((1 + hypot(a[3 * p + 1], a[3 * p + 2]) / a[3 * p]) /
		        fmax(1e-9, 1 - hypot(a[3 * p + 1], a[3 * p + 2]) / a[3 * p]));
		json_object_set_new(o, "extinction_ratio", stats_json(v, n));
		if (pic && !rc)
			rc = pc_map_write(pictures, "extinction_ratio", pic, W, H, 0, 600,
			                  "Extinction ratio per pixel", "ER");
		COLLECT(remainder(0.5 * atan2(a[3 * p + 2], a[3 * p + 1]) * 180 / M_PI -
		                      45.0 * pc_mosaic_channel(&c->geo.mosaic, x, y),
		                  180.0));
		json_object_set_new(o, "orientation_error_deg", stats_json(v, n));
		if (pic && !rc)
			rc = pc_map_write(pictures, "orientation_error", pic, W, H, -3, 3,
			                  "Analyser orientation error (deg)", "deg");
		if (c->residual) {
			COLLECT(c->residual[p]);
			json_object_set_new(o, "fit_residual_dn", stats_json(v, n));
		}
	}
#undef COLLECT
	if (c->parts & PC_CAL_ECM) {
		json_t *Wj = json_array(), *Aj = json_array();
		for (int r = 0; r < 4; r++)
			json_array_append_new(Wj, cli_json_vec(c->ecm_W[r], c->n_psg));
		for (unsigned k = 0; k < 4 * c->n_psa; k++)
			json_array_append_new(Aj, cli_json_vec(c->ecm_A[k], 4));
		json_object_set_new(o, "ecm_generator", Wj);
		json_object_set_new(o, "ecm_analyser", Aj);
	}
	if (c->provenance) {
		json_t *pj = json_loads(c->provenance, 0, NULL);
		if (pj)
			json_object_set_new(o, "provenance", pj);
	}
	if (pictures)
		json_object_set_new(o, "pictures", json_string(pictures));
	free(v);
	free(pic);
	*rc_out = rc;
	return o;
}

/* Adds this step's record to the provenance list. */
static void add_provenance(pc_calib *c, json_t *step)
{
	json_t *p = c->provenance ? json_loads(c->provenance, 0, NULL) : NULL;
	if (!json_is_object(p)) {
		json_decref(p);
		p = json_object();
		json_object_set_new(p, "software", json_string("polarcam " PC_VERSION_STRING));
		json_object_set_new(p, "steps", json_array());
	}
	json_array_append_new(json_object_get(p, "steps"), step);
	free(c->provenance);
	c->provenance = json_dumps(p, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(p);
}

static void progress_cb(void *user, uint64_t done, uint64_t total)
{
	cli_progress *bar = user;
	bar->total = total;
	cli_progress_update(bar, done);
}

/* ---- the subcommands ---- */

typedef struct args {
	const char *out, *dark, *flat, *angles, *states, *states_out, *pictures, *camera;
	const char *ecm[4];
	bool unknown, json, overwrite;
	double dolp, saturation, theta2, theta3;
	int first; /* first positional argument */
} args;

static int parse(int argc, char **argv, args *a)
{
	static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
	                                     {"dark", required_argument, NULL, 'D'},
	                                     {"flat", required_argument, NULL, 'F'},
	                                     {"angles", required_argument, NULL, 'A'},
	                                     {"unknown-angles", no_argument, NULL, 'U'},
	                                     {"dolp", required_argument, NULL, 'P'},
	                                     {"saturation", required_argument, NULL, 'S'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {"states", required_argument, NULL, 's'},
	                                     {"states-out", required_argument, NULL, 'T'},
	                                     {"air", required_argument, NULL, '0'},
	                                     {"polarizer", required_argument, NULL, '1'},
	                                     {"polarizer2", required_argument, NULL, '2'},
	                                     {"retarder", required_argument, NULL, '3'},
	                                     {"theta2", required_argument, NULL, 'a'},
	                                     {"theta3", required_argument, NULL, 'b'},
	                                     {"pictures", required_argument, NULL, 'p'},
	                                     {"camera", required_argument, NULL, 'c'},
	                                     {"overwrite", no_argument, NULL, 'W'},
	                                     {NULL, 0, NULL, 0}};
	memset(a, 0, sizeof *a);
	a->dolp = NAN;
	a->theta2 = 90;
	a->theta3 = 30;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":o:", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			a->out = optarg;
			break;
		case 'D':
			a->dark = optarg;
			break;
		case 'F':
			a->flat = optarg;
			break;
		case 'A':
			a->angles = optarg;
			break;
		case 'U':
			a->unknown = true;
			break;
		case 'J':
			a->json = true;
			break;
		case 'W':
			a->overwrite = true;
			break;
		case 's':
			a->states = optarg;
			break;
		case 'T':
			a->states_out = optarg;
			break;
		case 'p':
			a->pictures = optarg;
			break;
		case 'c':
			a->camera = optarg;
			break;
		case '0':
		case '1':
		case '2':
		case '3':
			a->ecm[c - '0'] = optarg;
			break;
		case 'P':
			if ((rc = cli_parse_double("--dolp", optarg, &a->dolp)))
				return cli_fail(rc, NULL);
			if (!(a->dolp > 0 && a->dolp <= 1))
				return cli_error(CLI_EXIT_USAGE, "--dolp %g: must be in (0, 1]",
				                 a->dolp);
			break;
		case 'S':
			if ((rc = cli_parse_double("--saturation", optarg, &a->saturation)))
				return cli_fail(rc, NULL);
			if (!(a->saturation > 0))
				return cli_error(CLI_EXIT_USAGE, "--saturation %g: must be > 0",
				                 a->saturation);
			break;
		case 'a':
			if ((rc = cli_parse_double("--theta2", optarg, &a->theta2)))
				return cli_fail(rc, NULL);
			break;
		case 'b':
			if ((rc = cli_parse_double("--theta3", optarg, &a->theta3)))
				return cli_fail(rc, NULL);
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
			                 argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)",
			                 argv[optind - 1]);
		}
	}
	a->first = optind;
	return 0;
}

/* The output rule for -o F (and --states-out): F may be replaced with --overwrite, or when it is
 * the --dark/--flat file the step starts from (the step then updates it: the new file holds
 * its parts and the step's). Then the parse-only stop. Returns 0 to go on, 1 to stop (status in
 * *st). */
static int outputs_ok(const args *a, int *st)
{
	const char *base = a->flat ? a->flat : a->dark;
	struct stat so, sb;
	bool update = base && stat(a->out, &so) == 0 && stat(base, &sb) == 0 &&
	              so.st_dev == sb.st_dev && so.st_ino == sb.st_ino;
	int rc = pc_output_check(a->out, a->overwrite || update ? PC_OUT_OVERWRITE : 0, false);
	if (!rc && a->states_out)
		rc = pc_output_check(a->states_out, a->overwrite ? PC_OUT_OVERWRITE : 0, false);
	*st = rc ? cli_fail(rc, NULL) : CLI_EXIT_OK;
	return rc || cli_parse_only();
}

/* Reads --dark/--flat into base (flat wins: it already holds the dark it was made with). */
static int load_base(const args *a, pc_calib *base, bool *have)
{
	*have = false;
	const char *f = a->flat ? a->flat : a->dark;
	if (!f)
		return 0;
	int rc = pc_calib_read(f, base);
	if (rc)
		return cli_fail(rc, NULL);
	if (a->flat && !(base->parts & PC_CAL_FLAT)) {
		pc_calib_free(base);
		return cli_error(CLI_EXIT_USAGE, "%s: --flat: the file has no flat part", a->flat);
	}
	if (!a->flat && !(base->parts & PC_CAL_DARK)) {
		pc_calib_free(base);
		return cli_error(CLI_EXIT_USAGE, "%s: --dark: the file has no dark part", a->dark);
	}
	*have = true;
	return 0;
}

static int finish(pc_calib *cal, const args *a, json_t *step)
{
	add_provenance(cal, step);
	int rc = pc_calib_write(a->out, cal);
	if (rc)
		return cli_fail(rc, NULL);
	int src;
	json_t *s = summary(cal, NULL, &src);
	json_object_set_new(s, "output", json_string(a->out));
	if (a->json) {
		cli_print_json(s);
	} else {
		json_t *parts = json_object_get(s, "parts");
		char list[64] = "";
		for (size_t i = 0; i < json_array_size(parts); i++)
			snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s",
			         i ? ", " : "", json_string_value(json_array_get(parts, i)));
		cli_info("wrote %s (%s; %lld invalid pixels); polarcam calibrate show %s for the "
		         "details",
		         a->out, list,
		         (long long)json_integer_value(json_object_get(s, "pixels_invalid")),
		         a->out);
		json_decref(s);
	}
	return CLI_EXIT_OK;
}

static int sub_stacks(int argc, char **argv, const char *what)
{
	args a;
	int st = parse(argc, argv, &a);
	if (st)
		return st;
	if (!a.out)
		return cli_error(CLI_EXIT_USAGE, "-o F is required (see --help)");
	int nrec = argc - a.first;
	if (nrec < 1)
		return cli_error(CLI_EXIT_USAGE, "no recordings given (see --help)");
	if (!strcmp(what, "dark") && nrec != 1)
		return cli_error(CLI_EXIT_USAGE, "dark takes one recording, %d given", nrec);
	if (outputs_ok(&a, &st))
		return st;
	rec_stack *rs = calloc((size_t)nrec, sizeof *rs);
	pc_calib_stack *stk = calloc((size_t)nrec, sizeof *stk);
	double *angles = calloc((size_t)nrec, sizeof *angles);
	pc_calib base, out;
	pc_calib_init(&base);
	pc_calib_init(&out);
	bool have_base = false;
	int rc = 0, status = CLI_EXIT_OK;
	if (!rs || !stk || !angles) {
		status = cli_error(CLI_EXIT_FAILURE, "out of memory");
		goto done;
	}
	if (strcmp(what, "dark") && (status = load_base(&a, &base, &have_base)))
		goto done;
	for (int i = 0; i < nrec; i++) {
		if ((rc = rec_open(argv[a.first + i], &rs[i]))) {
			status = cli_fail(rc, NULL);
			goto done;
		}
		stk[i] = rs[i].s;
		if (isfinite(a.dolp))
			stk[i].dolp = a.dolp;
	}
	if (a.angles) {
		const char *p = a.angles;
		int k = 0;
		while (*p) {
			char *end;
			double v = strtod(p, &end);
			if (end == p || !isfinite(v))
				break;
			if (k < nrec)
				stk[k].angle_deg = v;
			k++;
			p = end;
			if (*p == ',')
				p++;
			else
				break;
		}
		if (*p || k != nrec) {
			status = cli_error(CLI_EXIT_USAGE,
			                   "--angles '%s': expected %d comma-separated "
			                   "angles in degrees (one per recording)",
			                   a.angles, nrec);
			goto done;
		}
	}
	cli_progress bar;
	cli_progress_begin(&bar, what, 1);
	pc_calib_opts o = {.saturation = a.saturation,
	                   .unknown_angles = a.unknown,
	                   .progress = progress_cb,
	                   .progress_user = &bar};
	if (!strcmp(what, "dark"))
		rc = pc_calib_dark(&stk[0], &o, &out);
	else if (!strcmp(what, "flat"))
		rc = pc_calib_flat(stk, (size_t)nrec, have_base ? &base : NULL, &o, &out);
	else
		rc = pc_calib_analyser(stk, (size_t)nrec, have_base ? &base : NULL, &o, &out,
		                       angles);
	cli_progress_end(&bar);
	if (rc) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	if (a.camera || !*out.camera)
		snprintf(out.camera, sizeof out.camera, "%s", a.camera ? a.camera : rs[0].source);
	json_t *step = json_object();
	json_object_set_new(step, "step", json_string(what));
	json_t *ins = json_array();
	size_t frames = 0;
	for (int i = 0; i < nrec; i++) {
		json_t *in = json_object();
		json_object_set_new(in, "recording", json_string(argv[a.first + i]));
		json_object_set_new(in, "source", json_string(rs[i].source));
		json_object_set_new(in, "frames", json_integer((json_int_t)stk[i].n));
		json_object_set_new(in, "exposure_us", cli_json_real(stk[i].exposure_us));
		json_object_set_new(in, "gain_db", cli_json_real(stk[i].gain_db));
		if (!strcmp(what, "analyser")) {
			json_object_set_new(in, "angle_deg", cli_json_real(angles[i]));
			json_object_set_new(in, "dolp",
			                    cli_json_real(isfinite(stk[i].dolp) ? stk[i].dolp : 1));
		}
		json_array_append_new(ins, in);
		frames += stk[i].n;
	}
	json_object_set_new(step, "inputs", ins);
	json_object_set_new(step, "frames", json_integer((json_int_t)frames));
	if (!strcmp(what, "analyser"))
		json_object_set_new(step, "angles", json_string(a.unknown ? "estimated" : "known"));
	if (have_base)
		json_object_set_new(step, "base", json_string(a.flat ? a.flat : a.dark));
	status = finish(&out, &a, step);
done:
	for (int i = 0; rs && i < nrec; i++)
		rec_close(&rs[i]);
	free(rs);
	free(stk);
	free(angles);
	pc_calib_free(&base);
	pc_calib_free(&out);
	return status;
}

static int write_states(const char *path, const pc_calib *c, const char *layout)
{
	json_t *d = json_object();
	json_object_set_new(d, "polarcam_states", json_integer(1));
	json_object_set_new(d, "frame_order", json_string("psg_fastest"));
	json_object_set_new(d, "n_psg", json_integer(c->n_psg));
	json_object_set_new(d, "n_psa", json_integer(c->n_psa));
	json_object_set_new(d, "calibrated", json_string("ecm"));
	json_t *g = json_array(), *a = json_array(), *an = json_array();
	for (unsigned k = 0; k < c->n_psg; k++) {
		double v[4] = {c->ecm_W[0][k], c->ecm_W[1][k], c->ecm_W[2][k], c->ecm_W[3][k]};
		json_array_append_new(g, cli_json_vec(v, 4));
	}
	/* A's rows r_{a,c} = w_c·P_a with w_c the unit rows: P_a holds rows 4a..4a+3 of A */
	for (unsigned s = 0; s < c->n_psa; s++) {
		double P[4][4];
		for (int r = 0; r < 4; r++)
			memcpy(P[r], c->ecm_A[4 * s + r], sizeof P[r]);
		json_array_append_new(a, cli_json_matrix4(P));
	}
	for (int r = 0; r < 4; r++) {
		double e[4] = {0, 0, 0, 0};
		e[r] = 1;
		json_array_append_new(an, cli_json_vec(e, 4));
	}
	json_object_set_new(d, "psg", g);
	json_object_set_new(d, "psa", a);
	json_object_set_new(d, "analyser", an);
	json_object_set_new(d, "layout", json_string(layout));
	char *t = json_dumps(d, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	json_decref(d);
	int rc = t ? pc_write_file_atomic(path, t, strlen(t)) : PC_ENOMEM;
	free(t);
	return rc;
}

static int sub_ecm(int argc, char **argv)
{
	args a;
	int st = parse(argc, argv, &a);
	if (st)
		return st;
	if (!a.out)
		return cli_error(CLI_EXIT_USAGE, "-o F is required (see --help)");
	if (!a.states)
		return cli_error(CLI_EXIT_USAGE, "--states NOMINAL is required (the nominal states "
		                                 "file: frame order and counts)");
	static const char *const opt[4] = {"--air", "--polarizer", "--polarizer2", "--retarder"};
	for (int i = 0; i < 4; i++)
		if (!a.ecm[i])
			return cli_error(CLI_EXIT_USAGE, "%s REC is required (see --help)", opt[i]);
	if (argc > a.first)
		return cli_error(CLI_EXIT_USAGE, "unexpected argument '%s'", argv[a.first]);
	if (outputs_ok(&a, &st))
		return st;
	pc_sim_states nom;
	char layout[64] = "";
	int rc = pc_states_read(a.states, &nom, layout, sizeof layout);
	if (rc)
		return cli_fail(rc, NULL);
	pc_calib base, out;
	pc_calib_init(&base);
	pc_calib_init(&out);
	bool have_base = false;
	int status = load_base(&a, &base, &have_base);
	if (status)
		return status;
	rec_stack rs[4];
	memset(rs, 0, sizeof rs);
	pc_calib_stack stk[4];
	for (int i = 0; i < 4; i++) {
		if ((rc = rec_open(a.ecm[i], &rs[i]))) {
			status = cli_fail(rc, NULL);
			goto done;
		}
		stk[i] = rs[i].s;
	}
	cli_progress bar;
	cli_progress_begin(&bar, "ecm", 1);
	pc_calib_opts o = {
	    .saturation = a.saturation, .progress = progress_cb, .progress_user = &bar};
	double th[2] = {a.theta2, a.theta3};
	pc_ecm_result r;
	rc = pc_calib_ecm(stk, nom.n_psg, nom.n_psa, th, have_base ? &base : NULL, &o, &out, &r);
	cli_progress_end(&bar);
	if (rc) {
		status = cli_fail(rc, NULL);
		goto done;
	}
	if (a.camera || !*out.camera)
		snprintf(out.camera, sizeof out.camera, "%s", a.camera ? a.camera : rs[0].source);
	json_t *step = json_object();
	json_object_set_new(step, "step", json_string("ecm"));
	json_object_set_new(step, "states", json_string(a.states));
	json_t *sm = json_array();
	static const char *const nm[4] = {"air", "polarizer", "polarizer2", "retarder"};
	for (int i = 0; i < 4; i++) {
		json_t *s = json_object();
		json_object_set_new(s, "sample", json_string(nm[i]));
		json_object_set_new(s, "recording", json_string(a.ecm[i]));
		json_object_set_new(s, "tau", cli_json_real(r.tau[i]));
		json_object_set_new(s, "psi_deg", cli_json_real(r.psi_deg[i]));
		json_object_set_new(s, "retardance_deg", cli_json_real(r.delta_deg[i]));
		json_object_set_new(s, "orientation_deg", cli_json_real(r.theta_deg[i]));
		json_array_append_new(sm, s);
	}
	json_object_set_new(step, "samples", sm);
	json_object_set_new(step, "lambda15_over_lambda16",
	                    cli_json_real(r.lambda16 > 0 ? r.lambda15 / r.lambda16 : INFINITY));
	json_object_set_new(step, "model_residual", cli_json_real(r.residual));
	if (a.states_out) {
		char lay[64];
		pc_mosaic_format(&out.geo.mosaic, lay, sizeof lay);
		if ((rc = write_states(a.states_out, &out, lay))) {
			status = cli_fail(rc, a.states_out);
			goto done;
		}
		json_object_set_new(step, "states_out", json_string(a.states_out));
	}
	status = finish(&out, &a, step);
done:
	for (int i = 0; i < 4; i++)
		rec_close(&rs[i]);
	pc_calib_free(&base);
	pc_calib_free(&out);
	return status;
}

static int sub_show(int argc, char **argv)
{
	args a;
	int st = parse(argc, argv, &a);
	if (st)
		return st;
	if (argc - a.first != 1)
		return cli_error(CLI_EXIT_USAGE, "show takes one calibration file");
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_calib c;
	int rc = pc_calib_read(argv[a.first], &c);
	if (rc)
		return cli_fail(rc, NULL);
	/* the pictures folder is written as a set, with the summary as its meta.json */
	pc_outdir od = {0};
	if (a.pictures &&
	    (rc = pc_outdir_begin(&od, a.pictures, a.overwrite ? PC_OUT_OVERWRITE : 0))) {
		pc_calib_free(&c);
		return cli_fail(rc, NULL);
	}
	json_t *s = summary(&c, od.tmp, &rc);
	pc_calib_free(&c);
	json_object_set_new(s, "file", json_string(argv[a.first]));
	if (a.pictures)
		json_object_set_new(s, "pictures", json_string(a.pictures));
	if (!rc && a.pictures) {
		char path[4096], *t = json_dumps(s, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
		snprintf(path, sizeof path, "%s/meta.json", od.tmp);
		rc =
		    t ? pc_write_file_atomic(path, t, strlen(t)) : pc_error(PC_ENOMEM, "meta.json");
		free(t);
		if (!rc)
			rc = pc_outdir_commit(&od);
	}
	pc_outdir_abort(&od);
	if (rc) {
		json_decref(s);
		return cli_fail(rc, NULL);
	}
	cli_print_json(s);
	return CLI_EXIT_OK;
}

int cli_cmd_calibrate(int argc, char **argv)
{
	if (argc < 2 || (argc == 2 && cli_wants_help(argc, argv))) {
		usage(argc < 2 ? stderr : stdout);
		return argc < 2 ? CLI_EXIT_USAGE : CLI_EXIT_OK;
	}
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	const char *sub = argv[1];
	if (!strcmp(sub, "dark") || !strcmp(sub, "flat") || !strcmp(sub, "analyser"))
		return sub_stacks(argc - 1, argv + 1, sub);
	if (!strcmp(sub, "ecm"))
		return sub_ecm(argc - 1, argv + 1);
	if (!strcmp(sub, "show"))
		return sub_show(argc - 1, argv + 1);
	return cli_error(CLI_EXIT_USAGE,
	                 "unknown subcommand '%s' (dark, flat, analyser, ecm, show)", sub);
}
