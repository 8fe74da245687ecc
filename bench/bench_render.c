#include <stdio.h>

#include "bench.h"

/* Placeholder until issue 4 lands this benchmark. */
int pc_bench_render(int argc, char **argv)
{
	(void)argc;
	(void)argv;
	fprintf(stderr, "polarcam bench render: not implemented yet (issue 4)\n");
	return 1;
}
