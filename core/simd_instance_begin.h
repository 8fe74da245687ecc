/* Internal: opens one instance of a width-generic float kernel (simd.h). Before including it,
 * define PC_INST as PC_INST_BASELINE, PC_INST_AVX2 or PC_INST_AVX512; after the kernel source,
 * include simd_instance_end.h. Defines:
 *   KFN(name)  the instance's function name        KATTR  its target attribute
 *   KW         lanes per vector (8 or 16)          vf, vi  the float and int32 vector types
 *   vsplat(f), vld(p), vld_dup(p) (lanes 2i, 2i+1 = p[i]), vld_zip(p, q) (lanes 2i, 2i+1 =
 *   p[i], q[i]), vswap_pairs(v) (lanes 2i, 2i+1 exchanged), vabs(v), vsel(m, a, b),
 *   vblend_odd(a, b) (even lanes from a, odd from b), vpack_even(a, b) (a's even lanes, then
 *   b's), vdup_lo(v) and vdup_hi(v) (lanes 2i, 2i+1 = v[i], or v[KW/2 + i]), vlane_up(p, a)
 *   (lane 0 = p[KW − 1], lane i = a[i − 1])
 *   KSTORE(p, v, nt)  store one vector (nt: non-temporal allowed; p 64-byte aligned then)
 *   KSQRT, KFMA(a, b, c) = a·b + c, KDIV (≈ n/d), KRSQRT (≈ 1/√p), KMAX, KMIN
 *   km, KLT(a, b) (a lane mask of a < b, ordered), KSEL(m, a, b) (a where m, else b)
 * No include guard: it is included once per instance. */
#define PC_INST_BASELINE 0
#define PC_INST_AVX2     1
#define PC_INST_AVX512   2

#if PC_INST == PC_INST_BASELINE
/* 8 lanes of generic vector code (SSE2 pairs on x86-64) */
#define KW        8
#define vf        v8f
#define vi        v8i
#define KFN(name) name##_base
#define KATTR
#define KSTORE(p, v, nt) ((void)(nt), KFN(h_st)((p), (v)))
#define KSQRT(v)         KFN(h_sqrt_lanes)(v)
#define KFMA(a, b, c)    ((a) * (b) + (c))
#define KDIV(n, d)       ((n) / (d))
#define KRSQRT(p)        (vsplat(1.0f) / KFN(h_sqrt_lanes)(p))
#define km               v8i
#define KLT(a, b)        KFN(h_lt)((a), (b))
#define KSEL(m, a, b)    vsel((m), (a), (b))
#define KMAX(a, b)       vsel(KFN(h_lt)((b), (a)), (a), (b))
#define KMIN(a, b)       vsel(KFN(h_lt)((a), (b)), (a), (b))

#elif PC_INST == PC_INST_AVX2
/* the same source, 256-bit instructions, streaming stores */
#define KW        8
#define vf        v8f
#define vi        v8i
#define KFN(name) name##_avx2
#define KATTR     __attribute__((target("avx2,fma")))
#define KSTORE(p, v, nt)                                                                           \
	do {                                                                                       \
		if (nt)                                                                            \
			_mm256_stream_ps((p), (__m256)(v));                                        \
		else                                                                               \
			KFN(h_st)((p), (v));                                                       \
	} while (0)
#define KSQRT(v)      ((v8f)_mm256_sqrt_ps((__m256)(v)))
#define KFMA(a, b, c) ((v8f)_mm256_fmadd_ps((__m256)(a), (__m256)(b), (__m256)(c)))
#define KDIV(n, d)    ((n) / (d))
#define KRSQRT(p)     ((v8f)_mm256_rsqrt_ps((__m256)(p)))
#define km            v8i
#define KLT(a, b)     ((a) < (b))
#define KSEL(m, a, b) ((v8f)_mm256_blendv_ps((__m256)(b), (__m256)(a), (__m256)(m)))
#define KMAX(a, b)    ((v8f)_mm256_max_ps((__m256)(a), (__m256)(b)))
#define KMIN(a, b)    ((v8f)_mm256_min_ps((__m256)(a), (__m256)(b)))

#elif PC_INST == PC_INST_AVX512
/* the same source 16 lanes wide (one 64-byte store per output row and 16 pixels), 32 vector
 * registers, comparisons into mask registers */
#define KW        16
#define vf        v16f
#define vi        v16i
#define KFN(name) name##_avx512
#define KATTR     __attribute__((target(PC_AVX512_TARGET)))
#define KSTORE(p, v, nt)                                                                           \
	do {                                                                                       \
		if (nt)                                                                            \
			_mm512_stream_ps((p), (__m512)(v));                                        \
		else                                                                               \
			KFN(h_st)((p), (v));                                                       \
	} while (0)
#define KSQRT(v)      ((v16f)_mm512_sqrt_ps((__m512)(v)))
#define KFMA(a, b, c) ((v16f)_mm512_fmadd_ps((__m512)(a), (__m512)(b), (__m512)(c)))
#define KDIV(n, d)    ((n)*rcp_avx512(d))
#define KRSQRT(p)     ((v16f)_mm512_rsqrt14_ps((__m512)(p)))
#define km            __mmask16
#define KLT(a, b)     _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_LT_OQ)
#define KSEL(m, a, b) ((v16f)_mm512_mask_blend_ps((m), (__m512)(b), (__m512)(a)))
#define KMAX(a, b)    ((v16f)_mm512_max_ps((__m512)(a), (__m512)(b)))
#define KMIN(a, b)    ((v16f)_mm512_min_ps((__m512)(a), (__m512)(b)))

#else
#error "PC_INST: define it as PC_INST_BASELINE, PC_INST_AVX2 or PC_INST_AVX512"
#endif

#define vsplat      KFN(h_splat)
#define vld         KFN(h_ld)
#define vld_dup     KFN(h_ld_dup)
#define vabs        KFN(h_abs)
#define vsel        KFN(h_sel)
#define vblend_odd  KFN(h_blend_odd)
#define vld_zip     KFN(h_ld_zip)
#define vswap_pairs KFN(h_swap_pairs)
#define vpack_even  KFN(h_pack_even)
#define vdup_lo     KFN(h_dup_lo)
#define vdup_hi     KFN(h_dup_hi)
#define vlane_up    KFN(h_lane_up)
#include "simd_helpers.inc"
