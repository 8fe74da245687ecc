/* Internal to core's float kernels: GCC/clang vector types and helpers shared by the kernel
 * instances (demosaic_fast.c, stokes_kernels.c). A kernel source is written once, width-generic,
 * and included once per instruction-set level of polarcam/cpu.h between
 * simd_instance_begin.h and simd_instance_end.h, which name the instance and map the
 * operations onto that level's instructions.
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

/* Helpers for both widths: broadcast (not lane inserts), unaligned load/store, select by a
 * comparison mask, |v|, and the even/odd lane blend (lane parity = column parity: x is a
 * multiple of the width). */
#define PC_VEC_HELPERS(W)                                                                        \
	static inline v##W##f vsplat##W(float f)                                                 \
	{                                                                                        \
		v##W##f z = { 0 };                                                               \
		return z + f;                                                                    \
	}                                                                                        \
	static inline v##W##f vld##W(const float *p)                                             \
	{                                                                                        \
		v##W##f v;                                                                       \
		memcpy(&v, p, sizeof v);                                                         \
		return v;                                                                        \
	}                                                                                        \
	static inline void vst##W(float *p, v##W##f v)                                           \
	{                                                                                        \
		memcpy(p, &v, sizeof v);                                                         \
	}                                                                                        \
	static inline v##W##f vsel##W(v##W##i m, v##W##f a, v##W##f b)                           \
	{                                                                                        \
		return (v##W##f)(((v##W##i)a & m) | ((v##W##i)b & ~m));                          \
	}                                                                                        \
	static inline v##W##f vabs##W(v##W##f a)                                                 \
	{                                                                                        \
		v##W##i z = { 0 };                                                               \
		return (v##W##f)((v##W##i)a & (z + 0x7fffffff));                                 \
	}
PC_VEC_HELPERS(8)
PC_VEC_HELPERS(16)
#undef PC_VEC_HELPERS

/* Even lanes from a, odd lanes from b. */
static inline v8f vblend_odd8(v8f a, v8f b)
{
#ifdef PC_HAVE_SHUFFLEVECTOR
	return __builtin_shufflevector(a, b, 0, 9, 2, 11, 4, 13, 6, 15);
#else
	return __builtin_shuffle(a, b, (v8i){ 0, 9, 2, 11, 4, 13, 6, 15 });
#endif
}

static inline v16f vblend_odd16(v16f a, v16f b)
{
#ifdef PC_HAVE_SHUFFLEVECTOR
	return __builtin_shufflevector(a, b, 0, 17, 2, 19, 4, 21, 6, 23, 8, 25, 10, 27, 12, 29, 14,
				       31);
#else
	return __builtin_shuffle(a, b, (v16i){ 0, 17, 2, 19, 4, 21, 6, 23, 8, 25, 10, 27, 12, 29,
					       14, 31 });
#endif
}

/* Lanes 2i and 2i+1 both hold p[i]: W/2 consecutive values, each for two pixels. */
static inline v8f vld_dup8(const float *p)
{
#ifdef PC_HAVE_SHUFFLEVECTOR
	v4f h;
	memcpy(&h, p, sizeof h);
	return __builtin_shufflevector(h, h, 0, 0, 1, 1, 2, 2, 3, 3);
#else
	return (v8f){ p[0], p[0], p[1], p[1], p[2], p[2], p[3], p[3] };
#endif
}

static inline v16f vld_dup16(const float *p)
{
#ifdef PC_HAVE_SHUFFLEVECTOR
	v8f h = vld8(p);
	return __builtin_shufflevector(h, h, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7);
#else
	v16f r;
	for (int i = 0; i < 16; i++)
		r[i] = p[i / 2];
	return r;
#endif
}

static inline v8f vsqrt_lanes8(v8f v)
{
	v8f r;
	for (int i = 0; i < 8; i++)
		r[i] = sqrtf(v[i]);
	return r;
}

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
