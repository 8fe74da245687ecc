#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "cli.h"
#include "commands.h"

static const struct {
	const char *name;
	const char *summary;
	int (*run)(int argc, char **argv);
} pc_benches[] = {
	{ "physics", "Lu-Chipman and PBRDF throughput, rho^s accuracy vs cost", pc_bench_physics },
	{ "demosaic", "demosaicking accuracy vs time per 2448x2048 frame, Pareto plot", pc_bench_demosaic },
	{ "render", "render time per effect set, Mpixel/s, peak memory", pc_bench_render },
	{ "devices", "serve -> capture over loopback, live pipeline", pc_bench_devices },
	{ "calib", "analyser calibration: angles x frames -> residual error, acquisition time", pc_bench_calib },
	{ "dataset", "dataset samples/s per core, bytes per sample, 10^6-sample projection", pc_bench_dataset },
};

int cmd_bench(int argc, char **argv)
{
	size_t n = sizeof pc_benches / sizeof pc_benches[0];
	if (argc < 2 || !strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
		FILE *fp = argc < 2 ? stderr : stdout;
		fprintf(fp, "usage: polarcam bench NAME [OPTIONS]   (polarcam bench NAME --help)\n\n"
			    "Benchmarks report ratios against baselines measured in the same run.\n\n");
		for (size_t i = 0; i < n; i++)
			fprintf(fp, "  %-9s %s\n", pc_benches[i].name, pc_benches[i].summary);
		return argc < 2 ? PC_EXIT_USAGE : PC_EXIT_OK;
	}
	for (size_t i = 0; i < n; i++)
		if (!strcmp(argv[1], pc_benches[i].name))
			return pc_benches[i].run(argc - 1, argv + 1);
	return pc_cli_error(PC_EXIT_USAGE, "unknown benchmark '%s' (physics, demosaic, render, devices, calib, dataset)",
			    argv[1]);
}
