/* tests/fuzz/fuzz.h - what the libFuzzer harnesses share.
 *
 * Each harness defines LLVMFuzzerTestOneInput. Built with clang's -fsanitize=fuzzer (PC_FUZZ,
 * `./do fuzz`) libFuzzer drives it; built by any compiler with tests/fuzz/replay.c it replays the
 * checked-in corpus as a ctest (fuzz_replay_*), so every finding stays a regression test.
 *
 * Readers take paths, so inputs go through a per-process directory on tmpfs (/dev/shm when it
 * exists). The size limits of polarcam/limits.h are lowered at start-up so that an input cannot
 * make one execution take seconds (a 100 M pixel PNG bomb is legal under the defaults); the
 * limits themselves are checked by tests/test_io_hostile.c. A broken property is reported with
 * FUZZ_ASSERT, which prints the condition and aborts (a libFuzzer crash). */
#ifndef POLARCAM_FUZZ_H
#define POLARCAM_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "polarcam/limits.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define FUZZ_ASSERT(cond, ...)                                                                     \
	do {                                                                                       \
		if (!(cond)) {                                                                     \
			fprintf(stderr, "%s:%d: property failed: %s: ", __FILE__, __LINE__,        \
			        #cond);                                                            \
			fprintf(stderr, __VA_ARGS__);                                              \
			fputc('\n', stderr);                                                       \
			abort();                                                                   \
		}                                                                                  \
	} while (0)

static char fuzz_dir_buf[96];

static inline void fuzz_cleanup(void)
{
	if (!fuzz_dir_buf[0])
		return;
	char cmd[160];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", fuzz_dir_buf);
	if (system(cmd) != 0)
		fuzz_dir_buf[0] = '\0';
}

/* The process's scratch directory (created on first use, removed at exit), and the limits. */
static inline const char *fuzz_dir(void)
{
	if (!fuzz_dir_buf[0]) {
		struct stat st;
		const char *base =
		    stat("/dev/shm", &st) == 0 && S_ISDIR(st.st_mode) ? "/dev/shm" : "/tmp";
		snprintf(fuzz_dir_buf, sizeof fuzz_dir_buf, "%s/pc_fuzz_%ld_XXXXXX", base,
		         (long)getpid());
		if (!mkdtemp(fuzz_dir_buf)) {
			perror("fuzz: mkdtemp");
			abort();
		}
		atexit(fuzz_cleanup);
		pc_limit_set(PC_LIMIT_PIXELS, 1u << 22);
		pc_limit_set(PC_LIMIT_BYTES, 64u << 20);
		pc_limit_set(PC_LIMIT_TRIANGLES, 1u << 16);
		pc_limit_set(PC_LIMIT_MEMORY, 256u << 20);
	}
	return fuzz_dir_buf;
}

/* Writes data to NAME in the scratch directory; returns its path (static buffer). */
static inline const char *fuzz_file(const char *name, const uint8_t *data, size_t n)
{
	static char path[256];
	snprintf(path, sizeof path, "%s/%s", fuzz_dir(), name);
	FILE *fp = fopen(path, "wb");
	if (!fp) {
		perror(path);
		abort();
	}
	if (n && fwrite(data, 1, n, fp) != n) {
		perror(path);
		abort();
	}
	fclose(fp);
	return path;
}

/* A NUL-terminated copy of the input (text parsers); free() it. */
static inline char *fuzz_text(const uint8_t *data, size_t n)
{
	char *t = malloc(n + 1);
	if (!t)
		abort();
	if (n)
		memcpy(t, data, n);
	t[n] = '\0';
	return t;
}

/* Sum of every byte of a view's pixels: ASan sees each one read. */
static inline unsigned fuzz_touch(const void *data, size_t row_bytes, size_t stride, uint32_t rows)
{
	unsigned s = 0;
	const uint8_t *p = data;
	for (uint32_t y = 0; y < rows; y++)
		for (size_t x = 0; x < row_bytes; x++)
			s += p[(size_t)y * stride + x];
	return s;
}

#endif
