#include <stdio.h>

#include "bench.h"

/* Placeholder until issue 5 lands this benchmark. */
int pc_bench_devices(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	fprintf(stderr, "polarcam bench devices: not implemented yet (issue 5)\n");
	return 1;
}
