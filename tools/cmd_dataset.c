/* polarcam dataset: scene-family datasets (polarcam/dataset.h): make a shard, verify, merge. */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "commands.h"
#include "polarcam/dataset.h"
#include "polarcam/error.h"

static void usage(FILE *fp)
{
	fprintf(
	    fp,
	    "usage: polarcam dataset SPEC -o DIR --count N [options]\n"
	    "       polarcam dataset verify DIR [--json]\n"
	    "       polarcam dataset merge DIR [--json]\n"
	    "\n"
	    "Renders samples 0..N-1 of the scene family SPEC (docs/dataset.md; for example\n"
	    "scenes/dataset/demosaic.json) into DIR: per sample a directory samples/NNNNNNNN/ "
	    "with\n"
	    "the raw frames (PNG at the sensor's bit depth), the ground truth (.npy), scene.json\n"
	    "(re-renders alone with polarcam render) and meta.json, made in a temporary directory\n"
	    "and renamed into place; one manifest line per sample with the SHA-256 of each file.\n"
	    "Sample i depends on (SPEC, seed, i) only: shards, threads and interruptions do not\n"
	    "change the dataset. A run skips the samples that exist and redoes partial ones.\n"
	    "\n"
	    "options:\n"
	    "  -o, --output DIR       dataset directory (created if missing)\n"
	    "  -n, --count N          number of samples (1..100000000)\n"
	    "  -s, --seed S           family seed (default 0)\n"
	    "      --shard I/M        make the samples i with i mod M = I (default: from the\n"
	    "                         scheduler, SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT or\n"
	    "                         JOB_COMPLETION_INDEX with --shards or POLARCAM_SHARDS; else "
	    "0/1)\n"
	    "      --shards M         the shard count for JOB_COMPLETION_INDEX (Kubernetes)\n"
	    "      --resolution WxH   replace the spec's resolution\n"
	    "  -t, --threads N        threads per sample (default: all cores)\n"
	    "      --json             print the summary as one JSON line\n"
	    "  -h, --help             this help\n"
	    "\n"
	    "verify: every sample 0..N-1 present with the files and hashes of the manifest\n"
	    "(manifest.jsonl, or the shard manifests before a merge); exit 1 when not.\n"
	    "merge: the shard manifests -> DIR/manifest.jsonl (sorted by index); refuses, writing\n"
	    "nothing, while samples are missing.\n"
	    "\n"
	    "Progress goes to stderr when it is a terminal (POLARCAM_PROGRESS=1 forces it, =0\n"
	    "silences it); under a scheduler only the summary line is printed.\n"
	    "A dataset directory is resumable, so it is the one output a run adds to instead of\n"
	    "refusing (each sample is still made beside it and renamed into place whole).\n"
	    "Exit status: 0 success, 1 failure (or verify found problems), 2 bad arguments or "
	    "spec.\n"
	    "\n"
	    "examples:\n"
	    "  polarcam dataset scenes/dataset/demosaic.json -o ds/ --count 100 --seed 1\n"
	    "  polarcam dataset scenes/dataset/demosaic.json -o ds/ --count 100 --shard 0/4 "
	    "--json\n"
	    "  polarcam dataset verify ds/ --json\n");
}

static int parse_shard(const char *arg, uint32_t *i, uint32_t *m)
{
	unsigned long long a, b;
	char tail;
	if (sscanf(arg, "%llu/%llu%c", &a, &b, &tail) != 2 || strchr(arg, '-') || b < 1 ||
	    b > 1000000 || a >= b)
		return cli_error(CLI_EXIT_USAGE,
		                 "--shard '%s': expected I/M with 0 <= I < M <= 1000000", arg);
	*i = (uint32_t)a;
	*m = (uint32_t)b;
	return 0;
}

/* The arguments of `dataset verify|merge`: one DIR and --json. */
static int parse_dir_args(int argc, char **argv, const char *sub, const char **dir, bool *json)
{
	for (int k = 2; k < argc; k++) {
		if (!strcmp(argv[k], "--json"))
			*json = true;
		else if (argv[k][0] == '-')
			return cli_error(CLI_EXIT_USAGE, "dataset %s: unknown option '%s'", sub,
			                 argv[k]);
		else if (*dir)
			return cli_error(CLI_EXIT_USAGE,
			                 "dataset %s: one directory, got '%s' and '%s'", sub, *dir,
			                 argv[k]);
		else
			*dir = argv[k];
	}
	if (!*dir)
		return cli_error(CLI_EXIT_USAGE, "dataset %s: DIR is required (see --help)", sub);
	return 0;
}

static int run_verify(int argc, char **argv)
{
	bool json = false;
	const char *dir = NULL;
	int rc = parse_dir_args(argc, argv, "verify", &dir, &json);
	if (rc)
		return rc;
	if (cli_parse_only())
		return CLI_EXIT_OK;
	pc_dataset_verify_result r;
	double t0 = cli_now();
	rc = pc_dataset_verify(dir, &r);
	if (rc)
		return cli_fail(rc, dir);
	bool good = r.ok == r.count;
	if (json) {
		json_t *o =
		    json_pack("{s:s, s:b, s:I, s:I, s:I, s:I, s:I, s:f}", "dir", dir, "complete",
		              good, "count", (json_int_t)r.count, "ok", (json_int_t)r.ok, "missing",
		              (json_int_t)r.missing, "corrupt", (json_int_t)r.corrupt, "bytes",
		              (json_int_t)r.bytes, "seconds", cli_now() - t0);
		if (!good)
			json_object_set_new(o, "first_problem", json_string(r.first_problem));
		cli_print_json(o);
	} else {
		printf("%s: %llu of %llu samples complete with matching SHA-256 (%.1f MB hashed); "
		       "%llu missing, %llu corrupt%s%s\n",
		       dir, (unsigned long long)r.ok, (unsigned long long)r.count,
		       (double)r.bytes / 1e6, (unsigned long long)r.missing,
		       (unsigned long long)r.corrupt,
		       good ? "" : "; first: ", good ? "" : r.first_problem);
	}
	return good ? CLI_EXIT_OK : CLI_EXIT_FAILURE;
}

static int run_merge(int argc, char **argv)
{
	bool json = false;
	const char *dir = NULL;
	int rc = parse_dir_args(argc, argv, "merge", &dir, &json);
	if (rc)
		return rc;
	if (cli_parse_only())
		return CLI_EXIT_OK;
	uint64_t n = 0;
	rc = pc_dataset_merge(dir, &n);
	if (rc)
		return cli_fail(rc, dir);
	if (json)
		cli_print_json(json_pack("{s:s, s:I, s:s}", "dir", dir, "samples", (json_int_t)n,
		                         "manifest", "manifest.jsonl"));
	else
		printf("%s/manifest.jsonl: %llu samples\n", dir, (unsigned long long)n);
	return CLI_EXIT_OK;
}

int cli_cmd_dataset(int argc, char **argv)
{
	if (cli_wants_help(argc, argv)) {
		usage(stdout);
		return CLI_EXIT_OK;
	}
	if (argc >= 2 && !strcmp(argv[1], "verify"))
		return run_verify(argc, argv);
	if (argc >= 2 && !strcmp(argv[1], "merge"))
		return run_merge(argc, argv);
	static const struct option opts[] = {{"output", required_argument, NULL, 'o'},
	                                     {"count", required_argument, NULL, 'n'},
	                                     {"seed", required_argument, NULL, 's'},
	                                     {"shard", required_argument, NULL, 'S'},
	                                     {"shards", required_argument, NULL, 'M'},
	                                     {"resolution", required_argument, NULL, 'R'},
	                                     {"threads", required_argument, NULL, 't'},
	                                     {"json", no_argument, NULL, 'J'},
	                                     {NULL, 0, NULL, 0}};
	pc_dataset_options o;
	memset(&o, 0, sizeof o);
	o.shards = 1;
	bool json = false, shard_set = false;
	long count = 0, threads = 0, shards_hint = 0;
	int c, rc;
	optind = 1;
	opterr = 0;
	while ((c = getopt_long(argc, argv, ":o:n:s:t:", opts, NULL)) != -1) {
		switch (c) {
		case 'o':
			o.dir = optarg;
			break;
		case 'n':
			if ((rc = cli_parse_long("--count", optarg, 1, 100000000, &count)))
				return cli_fail(rc, NULL);
			break;
		case 's':
			if ((rc = cli_parse_u64("--seed", optarg, &o.seed)))
				return cli_fail(rc, NULL);
			break;
		case 'S':
			if ((rc = parse_shard(optarg, &o.shard, &o.shards)))
				return rc;
			shard_set = true;
			break;
		case 'M':
			if ((rc = cli_parse_long("--shards", optarg, 1, 1000000, &shards_hint)))
				return cli_fail(rc, NULL);
			break;
		case 'R': {
			unsigned w, h;
			char tail;
			if (sscanf(optarg, "%ux%u%c", &w, &h, &tail) != 2 || strchr(optarg, '-') ||
			    w < 4 || h < 4 || w > 16384 || h > 16384)
				return cli_error(CLI_EXIT_USAGE,
				                 "--resolution '%s': expected WxH, 4..16384 each",
				                 optarg);
			o.width = w;
			o.height = h;
			break;
		}
		case 't':
			if ((rc = cli_parse_long("--threads", optarg, 1, 1024, &threads)))
				return cli_fail(rc, NULL);
			break;
		case 'J':
			json = true;
			break;
		case ':':
			return cli_error(CLI_EXIT_USAGE, "%s needs a value (see --help)",
			                 argv[optind - 1]);
		default:
			return cli_error(CLI_EXIT_USAGE, "unknown option '%s' (see --help)",
			                 argv[optind - 1]);
		}
	}
	if (optind != argc - 1)
		return cli_error(CLI_EXIT_USAGE,
		                 optind < argc ? "one SPEC, got '%s' and more"
		                               : "SPEC is required (see --help)",
		                 optind < argc ? argv[optind] : "");
	o.spec = argv[optind];
	if (!o.dir)
		return cli_error(CLI_EXIT_USAGE, "-o DIR is required (see --help)");
	if (!count)
		return cli_error(CLI_EXIT_USAGE, "--count N is required (see --help)");
	o.count = (uint64_t)count;
	o.threads = (int)threads;
	const char *scheduler = NULL;
	if (!shard_set) {
		rc = pc_dataset_shard_from_env((uint32_t)shards_hint, &o.shard, &o.shards,
		                               &scheduler);
		if (rc < 0)
			return cli_error(CLI_EXIT_USAGE, "%s", pc_error_detail());
	}
	if (cli_parse_only())
		return CLI_EXIT_OK;
	cli_progress bar = {0};
	o.progress = (pc_progress){cli_progress_stoppable, &bar};
	cli_catch_signals();
	/* POLARCAM_DATASET_STOP_AFTER: stop after making that many samples (tests of resumption) */
	const char *stop = getenv("POLARCAM_DATASET_STOP_AFTER");
	if (stop && *stop)
		o.stop_after = strtoull(stop, NULL, 10);
	double t0 = cli_now();
	pc_dataset_result r;
	rc = pc_dataset_run(&o, &r);
	cli_progress_end(&bar);
	if (rc)
		return cli_status(rc) == CLI_EXIT_USAGE
		           ? cli_error(CLI_EXIT_USAGE, "%s", pc_error_detail())
		           : cli_fail(rc, o.dir);
	double secs = cli_now() - t0;
	if (json) {
		json_t *j =
		    json_pack("{s:s, s:I, s:I, s:I, s:I, s:I, s:I, s:I, s:f, s:f, s:f}", "dir",
		              o.dir, "shard", (json_int_t)o.shard, "shards", (json_int_t)o.shards,
		              "total", (json_int_t)r.total, "made", (json_int_t)r.made, "skipped",
		              (json_int_t)r.skipped, "repaired", (json_int_t)r.repaired, "bytes",
		              (json_int_t)r.bytes, "seconds", secs, "render_s", r.render_s,
		              "write_s", r.write_s);
		json_object_set_new(j, "scheduler",
		                    scheduler ? json_string(scheduler) : json_null());
		if (r.made) {
			json_object_set_new(j, "worst_saturated_fraction",
			                    json_real(r.worst_saturated));
			json_object_set_new(j, "worst_saturated_index",
			                    json_integer((json_int_t)r.worst_index));
			json_object_set_new(j, "min_median_dn", json_real(r.min_median_dn));
		}
		cli_print_json(j);
	} else {
		printf(
		    "%s: shard %u/%u%s%s: %llu samples made, %llu already complete (%llu manifest "
		    "lines repaired), %.1f MB written in %.1f s",
		    o.dir, o.shard, o.shards, scheduler ? " from " : "", scheduler ? scheduler : "",
		    (unsigned long long)r.made, (unsigned long long)r.skipped,
		    (unsigned long long)r.repaired, (double)r.bytes / 1e6, secs);
		if (r.made)
			printf("; worst sample %llu with %.2f %% of its pixels saturated, darkest "
			       "median "
			       "%.0f DN",
			       (unsigned long long)r.worst_index, 100 * r.worst_saturated,
			       r.min_median_dn);
		printf("\n");
	}
	return CLI_EXIT_OK;
}
