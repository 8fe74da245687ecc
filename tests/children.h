/* tests/children.h - child processes of a test program that never outlive it.
 *
 * Every child is started by pc_child_spawn, which
 *   - sets PR_SET_PDEATHSIG (SIGKILL) in the child, so a test that dies by any means (SIGKILL
 *     from ctest's timeout, a crash, an ASan abort) takes its children with it; the check of
 *     getppid() after the prctl closes the window where the parent died before it;
 *   - records the child, so that exit() (atexit) and SIGTERM/SIGINT/SIGHUP kill and reap every
 *     child still running.
 * pc_child_wait waits with a deadline and kills the child when it passes, so no exit path
 * blocks forever on a hung child. Tests that start servers also run inside tests/netns.sh (a
 * private PID namespace): this header is the second line of defence, and the only one where
 * namespaces are not permitted. Linux only (prctl). */
#ifndef POLARCAM_TESTS_CHILDREN_H
#define POLARCAM_TESTS_CHILDREN_H

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

enum { PC_CHILD_MAX = 32 };
static pid_t pc_children[PC_CHILD_MAX];

static void pc_child_kill_all(void)
{
	for (int i = 0; i < PC_CHILD_MAX; i++)
		if (pc_children[i] > 0) {
			kill(pc_children[i], SIGKILL);
			waitpid(pc_children[i], NULL, 0);
			pc_children[i] = 0;
		}
}

static void pc_child_on_signal(int sig)
{
	pc_child_kill_all(); /* kill and waitpid are async-signal-safe */
	signal(sig, SIG_DFL);
	raise(sig);
}

static void pc_child_forget(pid_t pid)
{
	for (int i = 0; i < PC_CHILD_MAX; i++)
		if (pc_children[i] == pid)
			pc_children[i] = 0;
}

/* Starts argv[0] (searched in PATH when it has no '/') with stdout to out_fd (-1: inherited)
 * and stderr to the file err_path (NULL: inherited). Returns the pid, or -1. */
static pid_t pc_child_spawn(char *const argv[], int out_fd, const char *err_path)
{
	static bool installed;
	if (!installed) {
		installed = true;
		atexit(pc_child_kill_all);
		struct sigaction sa;
		memset(&sa, 0, sizeof sa);
		sa.sa_handler = pc_child_on_signal;
		sigaction(SIGTERM, &sa, NULL);
		sigaction(SIGINT, &sa, NULL);
		sigaction(SIGHUP, &sa, NULL);
	}
	int slot = -1;
	for (int i = 0; i < PC_CHILD_MAX && slot < 0; i++)
		if (pc_children[i] <= 0)
			slot = i;
	if (slot < 0)
		return -1;
	pid_t parent = getpid();
	fflush(NULL);
	pid_t pid = fork();
	if (pid == 0) {
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		if (getppid() != parent)
			_exit(127);
		if (out_fd >= 0 && out_fd != 1) {
			dup2(out_fd, 1);
			close(out_fd);
		}
		if (err_path) {
			int e = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
			if (e >= 0) {
				dup2(e, 2);
				close(e);
			}
		}
		execvp(argv[0], argv);
		_exit(127);
	}
	if (pid > 0)
		pc_children[slot] = pid;
	return pid;
}

/* Waits up to timeout_ms for the child; kills it (SIGKILL) when the time passes. Returns the
 * exit status as a shell would (128 + signal when killed), or -1 with *timed_out set. */
static int pc_child_wait(pid_t pid, int timeout_ms, bool *timed_out)
{
	if (timed_out)
		*timed_out = false;
	if (pid <= 0)
		return -1;
	int st = 0;
	struct timespec t0, t;
	clock_gettime(CLOCK_MONOTONIC, &t0);
	for (;;) {
		pid_t r = waitpid(pid, &st, WNOHANG);
		if (r == pid)
			break;
		if (r < 0 && errno != EINTR) {
			pc_child_forget(pid);
			return -1;
		}
		clock_gettime(CLOCK_MONOTONIC, &t);
		long waited = (t.tv_sec - t0.tv_sec) * 1000L + (t.tv_nsec - t0.tv_nsec) / 1000000L;
		if (waited >= timeout_ms) {
			fprintf(stderr, "child %d still running after %d ms: killed\n", (int)pid,
			        timeout_ms);
			kill(pid, SIGKILL);
			waitpid(pid, NULL, 0);
			pc_child_forget(pid);
			if (timed_out)
				*timed_out = true;
			return -1;
		}
		struct timespec ts = {0, 10000000};
		nanosleep(&ts, NULL);
	}
	pc_child_forget(pid);
	return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

/* Sends sig and waits (timeout_ms, then SIGKILL). */
static int pc_child_stop(pid_t pid, int sig, int timeout_ms)
{
	if (pid <= 0)
		return -1;
	kill(pid, sig);
	return pc_child_wait(pid, timeout_ms, NULL);
}

#endif
