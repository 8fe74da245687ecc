/* Internal to core: CPU facts the kernels need beyond the instruction-set level (cpu.c). */
#ifndef POLARCAM_CPU_INTERNAL_H
#define POLARCAM_CPU_INTERNAL_H

#include "polarcam/cpu.h"

/* Whether the processor is AMD's (detected once with the level): non-temporal stores measured
 * slower on AMD's processors without AVX-512 (demosaic_common.c). */
int pc_cpu_is_amd(void);

/* Kernel instances exist for x86-64 with GCC and clang (both define __GNUC__); elsewhere
 * every kernel has its baseline instance only. */
#if defined(__x86_64__) && defined(__GNUC__)
#define PC_CPU_X86 1
#endif

#endif
