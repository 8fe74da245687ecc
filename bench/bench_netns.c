/* Benchmarks that stream GigE Vision run inside a private network namespace with only loopback
 * up, so that nothing they send leaves the machine: they re-execute themselves under
 * `unshare -n` (bench.h). */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "bench.h"

int bench_netns_reexec(const pc_bench_host *host, int argc, char **argv)
{
	if (getenv("PC_BENCH_NETNS"))
		return 0; /* inside already */
	setenv("PC_BENCH_NETNS", "1", 1);
	char **nargv = calloc((size_t)argc + 10, sizeof *nargv);
	if (!nargv)
		return host->error(PC_BENCH_FAILURE, "out of memory");
	int n = 0;
	nargv[n++] = "unshare";
	nargv[n++] = "-n";
	nargv[n++] = "sh";
	nargv[n++] = "-c";
	nargv[n++] = "ip link set lo up && exec \"$@\"";
	char self[4096];
	ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
	if (len <= 0) {
		free(nargv);
		return host->error(PC_BENCH_FAILURE, "cannot find this program (/proc/self/exe)");
	}
	self[len] = '\0';
	nargv[n++] = "sh";
	nargv[n++] = self;
	nargv[n++] = "bench";
	for (int i = 0; i < argc; i++)
		nargv[n++] = argv[i];
	nargv[n] = NULL;
	fflush(NULL);
	execvp("unshare", nargv);
	free(nargv);
	return host->error(PC_BENCH_FAILURE,
	                   "cannot run in a private network namespace (unshare -n needs root; "
	                   "Debian: util-linux, iproute2): refusing to stream GigE Vision outside "
	                   "one");
}
