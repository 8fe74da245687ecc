#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "cli.h"
#include "commands.h"

static void progress_end(void *bar)
{
	cli_progress_end(bar);
}

static const struct {
	const char *name;
	const char *summary;
	int (*run)(const pc_bench_host *host, int argc, char **argv);
} benches[] = {
    {"physics", "Lu-Chipman and PBRDF throughput, rho^s accuracy vs cost", pc_bench_physics},
    {"demosaic", "demosaicking accuracy vs time per 2448x2048 frame, Pareto plot",
     pc_bench_demosaic},
    {"colour", "colour-polarization demosaicking per scene vs bayer-first, time vs bilinear",
     pc_bench_colour},
    {"render", "render time per effect set, Mpixel/s, peak memory", pc_bench_render},
    {"devices", "serve -> capture over loopback, live pipeline", pc_bench_devices},
    {"calib", "analyser calibration: angles x frames -> residual error, acquisition time",
     pc_bench_calib},
    {"dataset", "dataset samples/s per core, bytes per sample, 10^6-sample projection",
     pc_bench_dataset},
    {"soak", "serve -> capture -> live pipeline for N minutes: RSS, fds, threads flat",
     pc_bench_soak},
};

int cli_cmd_bench(int argc, char **argv)
{
	size_t n = sizeof benches / sizeof benches[0];
	if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
		FILE *fp = argc < 2 ? stderr : stdout;
		fprintf(fp,
		        "usage: polarcam bench NAME [OPTIONS]   (polarcam bench NAME --help)\n\n"
		        "Benchmarks report ratios against baselines measured in the same run.\n\n");
		for (size_t i = 0; i < n; i++)
			fprintf(fp, "  %-9s %s\n", benches[i].name, benches[i].summary);
		fprintf(fp, "\nexamples:\n"
		            "  polarcam bench physics\n"
		            "  polarcam bench demosaic --reps 3 -o bench-demosaic --overwrite\n"
		            "  polarcam bench render --json\n");
		return argc < 2 ? CLI_EXIT_USAGE : CLI_EXIT_OK;
	}
	for (size_t i = 0; i < n; i++)
		if (!strcmp(argv[1], benches[i].name)) {
			cli_progress bar = {0};
			const pc_bench_host host = {cli_error,
			                            cli_fail,
			                            cli_warn,
			                            cli_parse_long,
			                            cli_parse_double,
			                            cli_print_json,
			                            {cli_progress_fn, &bar},
			                            progress_end,
			                            cli_parse_only()};
			int status = benches[i].run(&host, argc - 1, argv + 1);
			cli_progress_end(&bar);
			return status;
		}
	return cli_error(CLI_EXIT_USAGE,
	                 "unknown benchmark '%s' (physics, demosaic, colour, render, devices, "
	                 "calib, dataset, soak)",
	                 argv[1]);
}
