/* The process's peak memory, for timings and reports (polarcam/io.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/io.h"

double pc_peak_rss_mib(void)
{
	FILE *fp = fopen("/proc/self/status", "r");
	if (!fp)
		return -1;
	char line[256];
	double kb = -1;
	while (fgets(line, sizeof line, fp))
		if (!strncmp(line, "VmHWM:", 6))
			kb = strtod(line + 6, NULL);
	fclose(fp);
	return kb < 0 ? -1 : kb / 1024;
}
