/* The one CPU dispatch (polarcam/cpu.h): features detected once, one environment cap, one
 * forced level for tests. Lock-free and thread-safe: the detected and capped level is computed
 * by whichever threads get there first (all compute the same value) and published with an
 * atomic store; the forced level is an atomic too. */
#include "polarcam/cpu.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "cpu_internal.h"
#include "polarcam/error.h"

/* bits 0..1: supported level, bits 2..3: level after the POLARCAM_CPU cap, bit 4: AMD,
 * bit 5: computed */
#define ST_DONE 32
static atomic_int cpu_state;
/* forced level, or -1 for the automatic choice */
static atomic_int cpu_forced = -1;

static pc_cpu_level detect(void)
{
#ifdef PC_CPU_X86
	__builtin_cpu_init();
	if (!(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")))
		return PC_CPU_BASELINE;
	if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
	    __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw"))
		return PC_CPU_AVX512;
	return PC_CPU_AVX2;
#else
	return PC_CPU_BASELINE;
#endif
}

static int state(void)
{
	int s = atomic_load_explicit(&cpu_state, memory_order_acquire);
	if (s & ST_DONE)
		return s;
	pc_cpu_level sup = detect(), cap = sup;
	const char *e = getenv("POLARCAM_CPU");
	if (e && *e) {
		pc_cpu_level want = PC_CPU_BASELINE; /* unknown names: the safe choice */
		for (int l = 0; l < PC_CPU_LEVELS; l++)
			if (strcmp(e, pc_cpu_level_name((pc_cpu_level)l)) == 0)
				want = (pc_cpu_level)l;
		cap = want < sup ? want : sup;
	}
	int amd = 0;
#ifdef PC_CPU_X86
	amd = __builtin_cpu_is("amd");
#endif
	s = (int)sup | (int)cap << 2 | amd << 4 | ST_DONE;
	atomic_store_explicit(&cpu_state, s, memory_order_release);
	return s;
}

pc_cpu_level pc_cpu_supported(void)
{
	return (pc_cpu_level)(state() & 3);
}

pc_cpu_level pc_cpu_active(void)
{
	int f = atomic_load_explicit(&cpu_forced, memory_order_relaxed);
	if (f >= 0)
		return (pc_cpu_level)f;
	return (pc_cpu_level)(state() >> 2 & 3);
}

int pc_cpu_force(pc_cpu_level level)
{
	if (level == PC_CPU_LEVELS) {
		atomic_store_explicit(&cpu_forced, -1, memory_order_relaxed);
		return 0;
	}
	if ((int)level < 0 || level > pc_cpu_supported())
		return pc_error(PC_ENOTSUP,
		                "CPU level %s: not supported by this machine or build "
		                "(at most %s)",
		                pc_cpu_level_name(level), pc_cpu_level_name(pc_cpu_supported()));
	atomic_store_explicit(&cpu_forced, (int)level, memory_order_relaxed);
	return 0;
}

const char *pc_cpu_level_name(pc_cpu_level level)
{
	switch (level) {
	case PC_CPU_BASELINE:
		return "baseline";
	case PC_CPU_AVX2:
		return "avx2";
	case PC_CPU_AVX512:
		return "avx512";
	default:
		return "?";
	}
}

int pc_cpu_is_amd(void)
{
	return state() >> 4 & 1;
}
