/* The CPU dispatch (polarcam/cpu.h): the detected level against the kernel's own account of the
 * processor (/proc/cpuinfo flags, read independently of the compiler's detection), the
 * POLARCAM_CPU cap in fresh processes, pc_cpu_force and its refusals, and a first call from
 * many threads at once agreeing. Also pc_build_compiler (polarcam/version.h) against this test's
 * own compiler, which the build makes the library's. */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "children.h"
#include "polarcam/cpu.h"
#include "polarcam/error.h"
#include "polarcam/version.h"

#ifdef _OPENMP
#include <omp.h>
#endif

/* The level the flags line of /proc/cpuinfo allows, or -1 where it cannot be read. */
static int level_from_cpuinfo(void)
{
#if defined(__x86_64__) && defined(__GNUC__)
	FILE *f = fopen("/proc/cpuinfo", "r");
	if (!f)
		return -1;
	char line[8192];
	int level = -1;
	while (fgets(line, sizeof line, f)) {
		if (strncmp(line, "flags", 5) != 0)
			continue;
		/* whole words only: "avx512f" must not match "avx512fp16" alone */
		const char *want2[] = {" avx2", " fma"};
		const char *want5[] = {" avx512f", " avx512vl", " avx512dq", " avx512bw"};
		bool has2 = true, has5 = true;
		char *nl = strchr(line, '\n');
		if (nl)
			*nl = ' ';
		for (size_t i = 0; i < 2; i++) {
			char w[32];
			snprintf(w, sizeof w, "%s ", want2[i]);
			has2 &= strstr(line, w) != NULL;
		}
		for (size_t i = 0; i < 4; i++) {
			char w[32];
			snprintf(w, sizeof w, "%s ", want5[i]);
			has5 &= strstr(line, w) != NULL;
		}
		level = has2 ? (has5 ? PC_CPU_AVX512 : PC_CPU_AVX2) : PC_CPU_BASELINE;
		break;
	}
	fclose(f);
	return level;
#else
	return PC_CPU_BASELINE; /* no instances beyond the baseline on this architecture */
#endif
}

/* pc_cpu_active() of a fresh process of this program with POLARCAM_CPU = value (NULL: unset).
 * A cross build's tests run under an emulator (tests/CMakeLists.txt), and so must this program's
 * child: $PC_TEST_EMULATOR, its words separated by spaces, goes before it. */
static int level_in_child(const char *self, const char *value)
{
	if (value)
		setenv("POLARCAM_CPU", value, 1);
	else
		unsetenv("POLARCAM_CPU");
	char *argv[16], emu[256] = "";
	int n = 0;
	const char *e = getenv("PC_TEST_EMULATOR");
	if (e)
		snprintf(emu, sizeof emu, "%s", e);
	for (char *t = strtok(emu, " "); t && n < 13; t = strtok(NULL, " "))
		argv[n++] = t;
	argv[n++] = (char *)self;
	argv[n++] = (char *)"--print-level";
	argv[n] = NULL;
	pid_t pid = pc_child_spawn(argv, -1, NULL);
	int st = pc_child_wait(pid, 30000, NULL);
	unsetenv("POLARCAM_CPU");
	return st;
}

int main(int argc, char **argv)
{
	(void)pc_child_stop; /* children.h helper this test does not need */
	if (argc > 1 && strcmp(argv[1], "--print-level") == 0)
		return (int)pc_cpu_active();

	/* the first call, from many threads at once */
	int seen[64];
	int nthreads = 1;
#ifdef _OPENMP
#pragma omp parallel num_threads(16)
	{
		int t = omp_get_thread_num();
		if (t < 64)
			seen[t] = (int)pc_cpu_active();
#pragma omp single
		nthreads = omp_get_num_threads();
	}
#else
	seen[0] = (int)pc_cpu_active();
#endif
	for (int t = 1; t < nthreads && t < 64; t++)
		CHECK_EQ_INT(seen[t], seen[0]);

	pc_cpu_level sup = pc_cpu_supported();
	int want = level_from_cpuinfo();
	printf("  supported: %s; /proc/cpuinfo: %s\n", pc_cpu_level_name(sup),
	       want < 0 ? "unreadable" : pc_cpu_level_name((pc_cpu_level)want));
	if (want >= 0)
		CHECK_EQ_INT(sup, want);

	/* the automatic choice without the environment variable is the supported level */
	CHECK_EQ_INT(level_in_child(argv[0], NULL), sup);
	/* the cap: never above what the machine has; unknown names give the baseline */
	const char *names[] = {"baseline", "avx2", "avx512"};
	for (int l = 0; l < PC_CPU_LEVELS; l++)
		CHECK_EQ_INT(level_in_child(argv[0], names[l]), l < (int)sup ? l : (int)sup);
	CHECK_EQ_INT(level_in_child(argv[0], "sse9"), PC_CPU_BASELINE);
	CHECK_EQ_INT(level_in_child(argv[0], ""), sup); /* empty: not set */

	/* forcing: every supported level, refusals above it, and back to automatic */
	for (int l = 0; l <= (int)sup; l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
		CHECK_EQ_INT(pc_cpu_active(), l);
	}
	for (int l = (int)sup + 1; l < PC_CPU_LEVELS; l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), PC_ENOTSUP);
		CHECK(strstr(pc_error_detail(), pc_cpu_level_name((pc_cpu_level)l)) != NULL);
	}
	CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)-1), PC_ENOTSUP);
	CHECK_EQ_INT(pc_cpu_force(PC_CPU_LEVELS), 0);
	CHECK_EQ_INT(pc_cpu_active(), sup);
	CHECK(strcmp(pc_cpu_level_name(PC_CPU_AVX2), "avx2") == 0);
	CHECK(strcmp(pc_cpu_level_name(PC_CPU_LEVELS), "?") == 0);
	/* the compiler that built the library, from this file's own macros (clang defines
	 * __GNUC__ too) */
	char cc[64];
#if defined(__clang__)
	snprintf(cc, sizeof cc, "clang %d.%d.%d", __clang_major__, __clang_minor__,
	         __clang_patchlevel__);
#elif defined(__GNUC__)
	snprintf(cc, sizeof cc, "GCC %d.%d.%d", __GNUC__, __GNUC_MINOR__, __GNUC_PATCHLEVEL__);
#else
	snprintf(cc, sizeof cc, "unknown C compiler");
#endif
	printf("  library built by %s (this test: %s)\n", pc_build_compiler(), cc);
	CHECK(strcmp(pc_build_compiler(), cc) == 0);
	return pc_test_finish("test_cpu");
}
