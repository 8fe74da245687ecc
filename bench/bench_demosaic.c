#include <stdio.h>

#include "bench.h"

/* Placeholder until issue 3 lands this benchmark. */
int pc_bench_demosaic(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	fprintf(stderr, "polarcam bench demosaic: not implemented yet (issue 3)\n");
	return 1;
}
