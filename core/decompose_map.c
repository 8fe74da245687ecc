/* Batched Lu–Chipman decomposition for D, R, Δ maps (physics.md §3, §4): the fast path of
 * pc_lu_chipman_decompose (core/decompose.c, PC_LC_NO_FACTORS) vectorised across matrices in
 * structure-of-arrays form. decompose_map_kern.inc holds the kernel (GCC vector extensions); on
 * x86-64 it is compiled once for AVX2 (4 lanes) and once for AVX-512 (8 lanes), chosen at run
 * time by polarcam/cpu.h. Both are bit-identical to the scalar code
 * (tests/test_decompose_map.c). Elsewhere, and on x86-64 CPUs without AVX2, the map is the scalar
 * reference matrix by matrix: a 2-lane SSE2/NEON-width instance of the kernel was measured
 * slower than the scalar code (305 vs 220 ns per matrix; it pays for both sides of every select
 * and the transposition with only two lanes). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/decompose.h"

#include "cpu_internal.h"
#include "decompose_internal.h"
#include "polarcam/cpu.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"

#ifdef PC_CPU_X86
#define PC_LC_X86_DISPATCH 1
#include <immintrin.h>
#ifndef __clang__
/* vectors travel between static inline helpers of one instance only, never across an ABI
 * boundary */
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
#endif
/* bit-identical to the scalar reference: no fused multiply-adds in any instance (GCC does not
 * contract in ISO C mode; clang would where the target has FMA) */
#ifdef __clang__
#pragma STDC FP_CONTRACT OFF
#endif

/* One matrix through the scalar reference, written into the map at index i. */
static void pc_lc_map_scalar(const double *m16, unsigned options, const pc_lc_map *out, size_t i)
{
	pc_lu_chipman lc;
	double M[4][4];
	memcpy(M, m16, sizeof M);
	if (pc_lu_chipman_decompose((const double(*)[4])M, options | PC_LC_NO_FACTORS, &lc)) {
		/* only non-finite input fails */
		lc.D = lc.R = lc.R_linear = lc.R_circular = lc.Delta = lc.depol_index = NAN;
		for (int k = 0; k < 3; k++)
			lc.D_vec[k] = lc.R_axis[k] = NAN;
		lc.flags = PC_LC_NONFINITE;
	}
	if (out->D)
		out->D[i] = lc.D;
	if (out->R)
		out->R[i] = lc.R;
	if (out->R_linear)
		out->R_linear[i] = lc.R_linear;
	if (out->R_circular)
		out->R_circular[i] = lc.R_circular;
	if (out->Delta)
		out->Delta[i] = lc.Delta;
	if (out->depol_index)
		out->depol_index[i] = lc.depol_index;
	for (int k = 0; k < 3; k++) {
		if (out->D_vec[k])
			out->D_vec[k][i] = lc.D_vec[k];
		if (out->R_axis[k])
			out->R_axis[k][i] = lc.R_axis[k];
	}
	if (out->flags)
		out->flags[i] = lc.flags;
}

#ifdef PC_LC_X86_DISPATCH
typedef double pc_vd4 __attribute__((vector_size(32)));
typedef long pc_vm4 __attribute__((vector_size(32)));
typedef double pc_vd8 __attribute__((vector_size(64)));
typedef long pc_vm8 __attribute__((vector_size(64)));

#define KFN(name) pc_lc_##name##_avx2
#define KATTR     __attribute__((target("avx2")))
#define VD        pc_vd4
#define VM        pc_vm4
#define VW        4
#define VSQRT(v)  ((pc_vd4)_mm256_sqrt_pd((__m256d)(v)))
#define VANY(m)   (!_mm256_testz_si256((__m256i)(m), (__m256i)(m)))
#include "decompose_map_kern.inc"
#undef KFN
#undef KATTR
#undef VD
#undef VM
#undef VW
#undef VSQRT
#undef VANY

#define KFN(name) pc_lc_##name##_avx512
/* GCC prefers 256-bit vectors unless told; clang takes the explicit 512-bit width as it is */
#ifdef __clang__
#define KATTR __attribute__((target("avx512f,avx512vl,avx512dq"), min_vector_width(512)))
#else
#define KATTR __attribute__((target("avx512f,avx512vl,avx512dq,prefer-vector-width=512")))
#endif
#define VD       pc_vd8
#define VM       pc_vm8
#define VW       8
#define VSQRT(v) ((pc_vd8)_mm512_sqrt_pd((__m512d)(v)))
#define VANY(m)  (_mm512_test_epi64_mask((__m512i)(m), (__m512i)(m)) != 0)
#include "decompose_map_kern.inc"
#undef KFN
#undef KATTR
#undef VD
#undef VM
#undef VW
#undef VSQRT
#undef VANY

#endif /* PC_LC_X86_DISPATCH */

/* The instance polarcam/cpu.h asks for (AVX-512, AVX2 or the scalar reference). */
static pc_lc_isa pc_lc_auto_isa(void)
{
#ifdef PC_LC_X86_DISPATCH
	switch (pc_cpu_active()) {
	case PC_CPU_AVX512:
		return PC_LC_ISA_AVX512;
	case PC_CPU_AVX2:
		return PC_LC_ISA_AVX2;
	default:
		break;
	}
#endif
	return PC_LC_ISA_PORTABLE;
}

const char *pc_lu_chipman_map_isa_name(void)
{
	switch (pc_lc_auto_isa()) {
	case PC_LC_ISA_AVX512:
		return "avx512";
	case PC_LC_ISA_AVX2:
		return "avx2";
	default:
		return "scalar";
	}
}

int pc_lu_chipman_map_isa(const double *M, size_t n, unsigned options, const pc_lc_map *out,
                          pc_lc_isa isa)
{
	if (n == 0)
		return 0;
	if (!M || !out)
		return pc_error(PC_EINVAL, "pc_lu_chipman_map: NULL argument");
	if (options & ~(unsigned)(PC_LC_FILTER | PC_LC_NO_FACTORS))
		return pc_error(PC_EINVAL,
		                "pc_lu_chipman_map: options 0x%x: only PC_LC_FILTER and "
		                "PC_LC_NO_FACTORS are allowed",
		                options);
	if (n > SIZE_MAX / 16)
		return pc_error(PC_EOVERFLOW, "pc_lu_chipman_map: n = %zu matrices", n);
	if (isa == PC_LC_ISA_AUTO)
		isa = pc_lc_auto_isa();
	switch (isa) {
	case PC_LC_ISA_PORTABLE: /* the scalar reference, matrix by matrix */
		for (size_t i = 0; i < n; i++)
			pc_lc_map_scalar(M + 16 * i, options, out, i);
		return 0;
#ifdef PC_LC_X86_DISPATCH
	case PC_LC_ISA_AVX2:
		if (pc_cpu_supported() < PC_CPU_AVX2)
			break;
		for (size_t i = 0; i < n; i += 4)
			pc_lc_lc_block_avx2(M, i, n - i < 4 ? n - i : 4, options, out);
		return 0;
	case PC_LC_ISA_AVX512:
		if (pc_cpu_supported() < PC_CPU_AVX512)
			break;
		for (size_t i = 0; i < n; i += 8)
			pc_lc_lc_block_avx512(M, i, n - i < 8 ? n - i : 8, options, out);
		return 0;
#endif
	default:
		break;
	}
	return pc_error(PC_ENOTSUP, "pc_lu_chipman_map: instruction set %d not available here",
	                (int)isa);
}

int pc_lu_chipman_map(const double *M, size_t n, unsigned options, const pc_lc_map *out)
{
	return pc_lu_chipman_map_isa(M, n, options, out, PC_LC_ISA_AUTO);
}
