#include <stdio.h>

#include "bench.h"

/* Placeholder until issue 2 lands this benchmark. */
int pc_bench_physics(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	fprintf(stderr, "polarcam bench physics: not implemented yet (issue 2)\n");
	return 1;
}
