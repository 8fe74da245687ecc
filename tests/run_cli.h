/* tests/run_cli.h - tests of the CLI run the polarcam executable ($POLARCAM, set by ctest) as a
 * user would, without a shell: run_cli("render", "scene.json", "-o", dir, NULL) returns its exit
 * status. */
#ifndef POLARCAM_TESTS_RUN_CLI_H
#define POLARCAM_TESTS_RUN_CLI_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

/* the CLI's exit statuses */
enum { CLI_STATUS_FAILURE = 1, CLI_STATUS_USAGE = 2 };

/* $POLARCAM when it is executable, else NULL (the test then skips). */
static inline const char *run_cli_exe(void)
{
	const char *p = getenv("POLARCAM");
	return p && access(p, X_OK) == 0 ? p : NULL;
}

/* Runs "$POLARCAM command args... (NULL-terminated)": its exit status, -1 when it did not exit. */
static inline int run_cli(const char *command, ...)
{
	const char *exe = run_cli_exe();
	char *argv[48];
	int argc = 0;
	argv[argc++] = (char *)exe;
	argv[argc++] = (char *)command;
	va_list ap;
	va_start(ap, command);
	for (const char *a; argc < 47 && (a = va_arg(ap, const char *));)
		argv[argc++] = (char *)a;
	va_end(ap);
	argv[argc] = NULL;
	if (!exe)
		return -1;
	fflush(stdout);
	fflush(stderr);
	pid_t pid = fork();
	if (pid == 0) {
		execv(exe, argv);
		_exit(127);
	}
	int st;
	if (pid < 0 || waitpid(pid, &st, 0) != pid)
		return -1;
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

#endif
