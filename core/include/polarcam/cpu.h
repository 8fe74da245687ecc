/* polarcam/cpu.h - the one CPU dispatch of every kernel.
 *
 * Each vectorised kernel is built once per instruction-set level of the ladder below (with GCC
 * and with clang alike) and asks pc_cpu_active() which one to run. The machine's features are
 * detected once, on the first call from any thread (thread-safe, no locks: every thread
 * computes the same value). Levels are cumulative: AVX-512 implies AVX2.
 *
 *   PC_CPU_BASELINE  the compiler's default target (x86-64: SSE2; other architectures: all
 *                    there is) - portable vector or scalar code
 *   PC_CPU_AVX2      x86-64 with AVX2 and FMA
 *   PC_CPU_AVX512    x86-64 with AVX-512 F, VL, DQ and BW, AVX2 and FMA
 *
 * One environment variable caps the level for a whole process, read once at the first call:
 *   POLARCAM_CPU=baseline|avx2|avx512   (anything else: baseline, the safe choice)
 * and pc_cpu_force() pins a level from inside a program (tests run every instance the machine
 * supports against the references; benchmarks compare instances in one run).
 */
#ifndef POLARCAM_CPU_H
#define POLARCAM_CPU_H

#include "polarcam/export.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum pc_cpu_level {
	PC_CPU_BASELINE = 0,
	PC_CPU_AVX2 = 1,
	PC_CPU_AVX512 = 2,
	PC_CPU_LEVELS
} pc_cpu_level;

/* The highest level this machine and this build support (ignores POLARCAM_CPU and
 * pc_cpu_force). */
PC_API pc_cpu_level pc_cpu_supported(void);

/* The level kernels use: the forced level if any, else pc_cpu_supported() capped by
 * POLARCAM_CPU. */
PC_API pc_cpu_level pc_cpu_active(void);

/* Pins the level kernels use to `level` (at most pc_cpu_supported(); PC_ENOTSUP otherwise,
 * nothing changed), or with PC_CPU_LEVELS returns to the automatic choice. Returns 0.
 * Meant for tests and benchmarks: call it while no kernel runs (a kernel reads the level once
 * per call). */
PC_API int pc_cpu_force(pc_cpu_level level);

/* "baseline", "avx2", "avx512" ("?" for other values). */
PC_API const char *pc_cpu_level_name(pc_cpu_level level);

#ifdef __cplusplus
}
#endif
#endif
