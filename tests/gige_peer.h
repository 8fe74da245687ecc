/* tests/gige_peer.h - `polarcam serve` and `polarcam capture` as separate processes for the GigE
 * Vision tests (run inside tests/netns.sh; children through tests/children.h, so they die with
 * the test). Readiness is always waited for, never slept. */
#ifndef POLARCAM_TESTS_GIGE_PEER_H
#define POLARCAM_TESTS_GIGE_PEER_H

#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "children.h"

/* Generous limits: they only matter when something hangs, and a loaded 2-core machine running
 * the ASan build is slow to start processes. */
enum { START_MS = 60000, EXIT_MS = 60000, FRAME_MS = 10000 };

/* Starts argv with stdout on a pipe (*out_fd) and stderr to stderr_path (tests/children.h:
 * the child dies with this test). */
static pid_t spawn(char *const argv[], int *out_fd, const char *stderr_path)
{
	int p[2];
	if (pipe(p))
		return -1;
	pid_t pid = pc_child_spawn(argv, p[1], stderr_path);
	close(p[1]);
	if (pid < 0) {
		close(p[0]);
		return -1;
	}
	*out_fd = p[0];
	return pid;
}

/* Reads from fd until a line containing want arrives or timeout_ms passes. */
static bool wait_line(int fd, const char *want, int timeout_ms, char *buf, size_t size)
{
	size_t len = 0;
	buf[0] = '\0';
	while (timeout_ms > 0) {
		struct pollfd pf = {fd, POLLIN, 0};
		int r = poll(&pf, 1, 100);
		timeout_ms -= 100;
		if (r <= 0)
			continue;
		ssize_t n = read(fd, buf + len, size - 1 - len);
		if (n <= 0)
			return false;
		len += (size_t)n;
		buf[len] = '\0';
		if (strstr(buf, want))
			return true;
	}
	return false;
}

/* Starts `polarcam serve ARGS...` (stderr to err_path) and waits for its JSON line, which is
 * copied into ready (may be NULL). */
static pid_t serve_start(const char *polarcam, char *const args[], const char *err_path, int *fd,
                         char *ready, size_t ready_size)
{
	char *argv[16];
	int n = 0;
	argv[n++] = (char *)polarcam;
	argv[n++] = "serve";
	for (int i = 0; args[i] && n < 15; i++)
		argv[n++] = args[i];
	argv[n] = NULL;
	pid_t pid = spawn(argv, fd, err_path);
	char buf[1024];
	buf[0] = '\0';
	if (pid < 0 || !wait_line(*fd, "\"serving\"", START_MS, buf, sizeof buf)) {
		fprintf(stderr, "server did not start: %s\n", buf);
		if (pid > 0) {
			pc_child_stop(pid, SIGKILL, EXIT_MS);
			close(*fd);
		}
		return -1;
	}
	if (ready)
		snprintf(ready, ready_size, "%s", buf);
	return pid;
}

static int stop_server(pid_t pid, int fd)
{
	int st = pc_child_stop(pid, SIGTERM, EXIT_MS);
	close(fd);
	return st;
}

#endif
