/* Internal to core's float kernels: GCC/clang vector types and helpers shared by the kernel
 * instances (demosaic_fast.c, stokes_kernels.c). A kernel source is written once, width-generic,
 * and included once per instruction-set level of polarcam/cpu.h between
 * simd_instance_begin.h and simd_instance_end.h, which name the instance, map the operations
 * onto that level's instructions and define the instance's own helpers (simd_helpers.inc:
 * clang refuses vector arguments between functions of different targets, even inlined).
 *
 * Including this header also sets the floating-point rules of the including file: no fused
 * multiply-adds except the explicit KFMA (GCC does not contract in ISO C mode; clang would where
 * the target has FMA, so that the instances of one kernel would differ). */
#ifndef POLARCAM_SIMD_H
#define POLARCAM_SIMD_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "cpu_internal.h"

#ifdef PC_CPU_X86
#include <immintrin.h>
#endif

#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#else
/* 32- and 64-byte vectors travel between static inline helpers only, never across an ABI
 * boundary, so GCC's note that their calling convention differs without -mavx does not apply. */
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

/* __builtin_shufflevector: clang, and GCC from 12; older GCC has __builtin_shuffle. */
#if defined(__clang__) || __GNUC__ >= 12
#define PC_HAVE_SHUFFLEVECTOR 1
#endif

typedef float v4f __attribute__((vector_size(16)));
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
typedef float v16f __attribute__((vector_size(64)));
typedef int32_t v16i __attribute__((vector_size(64)));

/* The target attribute of the AVX-512 instances. */
#define PC_AVX512_TARGET "avx512f,avx512vl,avx512dq,avx512bw,fma"

#ifdef PC_CPU_X86
/* 1/d for normal d whose reciprocal is normal: the hardware estimate (relative error 2^-14 for
 * rcp14ps) refined by one Newton step r' = r + r·(1 − d·r), which squares the relative error
 * (≤ 4e-9, before rounding). */
static inline __attribute__((always_inline, target(PC_AVX512_TARGET))) v16f rcp_avx512(v16f d)
{
	__m512 r = _mm512_rcp14_ps((__m512)d);
	__m512 e = _mm512_fnmadd_ps((__m512)d, r, _mm512_set1_ps(1.0f));
	return (v16f)_mm512_fmadd_ps(r, e, r);
}
#endif

#endif
