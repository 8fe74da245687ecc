/* sim/noise.c - scalar reference, vector kernel instances and dispatch of the per-frame sensor
 * chain and the fixed-pattern deviates (noise.h). */
#include "noise.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"

#include "polarcam/cpu.h"

#if defined(__x86_64__) && defined(__GNUC__)
#define PC_NOISE_X86 1
#include <immintrin.h>
#endif

/* Vectors travel between static inline helpers only, never across an ABI boundary. */
#ifndef __clang__
#pragma GCC diagnostic ignored "-Wpsabi"
#else
/* the instances compute what the scalar reference computes: no fused multiply-adds */
#pragma STDC FP_CONTRACT OFF
#endif

/* ---- scalar reference ---- */

/* Poisson draw of one pixel from its first block's words w (and, after a PTRS rejection, the
 * stream's next blocks). */
static double poisson_pixel(uint64_t seed, const uint32_t ctr0[4], double mu, const uint32_t w[4])
{
	if (!(mu > 0))
		return 0;
	if (mu < PC_PTRS_MIN_MU)
		return pc_poisson_inversion(mu, w[0]);
	pc_ptrs p;
	pc_ptrs_init(&p, mu);
	double lmu = NAN, k;
	uint32_t wu = w[0], wv = w[1];
	pc_rng r;
	memcpy(r.ctr, ctr0, sizeof r.ctr);
	r.key[0] = (uint32_t)seed;
	r.key[1] = (uint32_t)(seed >> 32);
	r.ctr[1] += 1u << 8; /* the continuation starts at the stream's second block */
	r.used = 4;
	for (;;) {
		if (pc_ptrs_fast(&p, wu, wv, &k))
			return k;
		double u = pc_u32_to_uniform(wu) - 0.5, v = pc_u32_to_uniform(wv);
		if (pc_ptrs_slow(&p, v, 0.5 - fabs(u), k, &lmu))
			return k;
		wu = pc_rng_u32(&r);
		wv = pc_rng_u32(&r);
	}
}

/* poisson_pixel for a pixel whose first `done` PTRS attempts (block 0 words 0–1, then the
 * continuation's words in pairs from block 1) were rejected: attempt done + 1 onwards. Only the
 * x86 vector kernels (noise_kern.inc) call it. */
#ifdef PC_NOISE_X86
static double poisson_after(uint64_t seed, const uint32_t ctr0[4], double mu, int done)
{
	pc_ptrs p;
	pc_ptrs_init(&p, mu);
	double lmu = NAN, k;
	pc_rng r;
	memcpy(r.ctr, ctr0, sizeof r.ctr);
	r.key[0] = (uint32_t)seed;
	r.key[1] = (uint32_t)(seed >> 32);
	r.ctr[1] += 1u << 8;
	r.used = 4;
	for (int i = 1; i < done; i++) {
		(void)pc_rng_u32(&r);
		(void)pc_rng_u32(&r);
	}
	for (;;) {
		uint32_t wu = pc_rng_u32(&r), wv = pc_rng_u32(&r);
		if (pc_ptrs_fast(&p, wu, wv, &k))
			return k;
		double u = pc_u32_to_uniform(wu) - 0.5, v = pc_u32_to_uniform(wv);
		if (pc_ptrs_slow(&p, v, 0.5 - fabs(u), k, &lmu))
			return k;
	}
}
#endif

static inline void frame_ctr(const pc_frame_args *a, uint32_t i, uint32_t ctr[4])
{
	ctr[0] = (a->sy << 16) | ((a->sx0 + i) & 0xFFFFu);
	ctr[1] = PC_RNG_FRAME;
	ctr[2] = (uint32_t)a->frame;
	ctr[3] = (uint32_t)(a->frame >> 32);
}

static inline uint16_t frame_pixel(const pc_frame_args *a, uint32_t i)
{
	double mu = (double)a->rate[i] * a->t_s + a->dark_e;
	double e = mu, z = 0;
	if (a->noise) {
		uint32_t ctr[4], w[4];
		const uint32_t key[2] = {(uint32_t)a->seed, (uint32_t)(a->seed >> 32)};
		frame_ctr(a, i, ctr);
		pc_philox4x32_10(ctr, key, w);
		e = poisson_pixel(a->seed, ctr, mu, w);
		if (a->read_e > 0)
			z = pc_u32_to_normal_read(w[2]);
	}
	if (e > a->full_well_e)
		e = a->full_well_e;
	if (a->dsnu)
		e += a->dsnu[i];
	if (a->noise && a->read_e > 0)
		e += a->read_e * z;
	double dn = floor(a->K * e + a->offset_dn + 0.5);
	return (uint16_t)(dn < 0 ? 0 : dn > a->max_dn ? a->max_dn : dn);
}

void pc_noise_frame_row_ref(const pc_frame_args *a)
{
	for (uint32_t i = 0; i < a->n; i++)
		a->out[i] = frame_pixel(a, i);
}

void pc_noise_fixed_row_ref(uint64_t seed, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                            double *z[4])
{
	const uint32_t key[2] = {(uint32_t)seed, (uint32_t)(seed >> 32)};
	for (uint32_t i = 0; i < n; i++) {
		const uint32_t ctr[4] = {(sy << 16) | ((sx0 + i) & 0xFFFFu), PC_RNG_FIXED, 0, 0};
		uint32_t w[4];
		pc_philox4x32_10(ctr, key, w);
		for (int k = 0; k < 4; k++)
			if (mask >> k & 1)
				z[k][i] = pc_u32_to_normal(w[k]);
	}
}

/* ---- vector kernels (x86-64: AVX2 and AVX-512 instances of noise_kern.inc) ---- */

#ifdef PC_NOISE_X86
/* 32×32 → 64-bit products of the even and the odd lanes (vpmuludq), recombined into the high
 * and low words. */
#define KFN(name) name##_avx2
#define KATTR     __attribute__((target("avx2,fma")))
#define KL        4
#define KMULHILO(a, m, hi, lo)                                                                     \
	do {                                                                                       \
		__m256i a_ = (__m256i)(a), m_ = _mm256_set1_epi32((int)(m));                       \
		__m256i pe_ = _mm256_mul_epu32(a_, m_);                                            \
		__m256i po_ = _mm256_mul_epu32(_mm256_srli_epi64(a_, 32), m_);                     \
		(lo) = (PU)_mm256_blend_epi32(pe_, _mm256_slli_epi64(po_, 32), 0xAA);              \
		(hi) = (PU)_mm256_blend_epi32(_mm256_srli_epi64(pe_, 32), po_, 0xAA);              \
	} while (0)
#define KSQRT(v) ((VD)_mm256_sqrt_pd((__m256d)(v)))
/* Stores the lanes of v selected by the bits of m contiguously at p. */
#define KCOMPRESS_D(p, m, v)                                                                       \
	do {                                                                                       \
		for (unsigned b_ = (m), j_ = 0; b_; b_ &= b_ - 1)                                  \
			(p)[j_++] = (v)[__builtin_ctz(b_)];                                        \
	} while (0)
#define KCOMPRESS_U         KCOMPRESS_D
#define KGATHER_D(tab, idx) ((VD)_mm256_i64gather_pd((tab), (__m256i)(idx), 8))
#define KFLOOR(v)           ((VD)_mm256_floor_pd((__m256d)(v)))
#define KMOVEMASK(m)        ((unsigned)_mm256_movemask_pd((__m256d)(m)))
#include "noise_kern.inc"
#undef KFN
#undef KATTR
#undef KL
#undef KMULHILO
#undef KSQRT
#undef KCOMPRESS_D
#undef KCOMPRESS_U
#undef KGATHER_D
#undef KFLOOR
#undef KMOVEMASK

#define KFN(name) name##_avx512
#define KATTR     __attribute__((target("avx512f,avx512vl,avx512dq,avx512bw,avx2,fma")))
#define KL        8
/* AVX-512: the words move between lanes with masked in-lane shuffles (one instruction each
 * instead of a shift and a blend). */
#define KMULHILO(a, m, hi, lo)                                                                     \
	do {                                                                                       \
		__m512i a_ = (__m512i)(a), m_ = _mm512_set1_epi32((int)(m));                       \
		__m512i pe_ = _mm512_mul_epu32(a_, m_);                                            \
		__m512i po_ = _mm512_mul_epu32(_mm512_srli_epi64(a_, 32), m_);                     \
		(lo) = (PU)_mm512_mask_shuffle_epi32(pe_, 0xAAAA, po_, _MM_PERM_CCAA);             \
		(hi) = (PU)_mm512_mask_shuffle_epi32(po_, 0x5555, pe_, _MM_PERM_DDBB);             \
	} while (0)
#define KSQRT(v)             ((VD)_mm512_sqrt_pd((__m512d)(v)))
#define KCOMPRESS_D(p, m, v) _mm512_mask_compressstoreu_pd((p), (__mmask8)(m), (__m512d)(v))
#define KCOMPRESS_U(p, m, v) _mm256_mask_compressstoreu_epi32((p), (__mmask8)(m), (__m256i)(v))
#define KGATHER_D(tab, idx)  ((VD)_mm512_i64gather_pd((__m512i)(idx), (tab), 8))
#define KFLOOR(v)                                                                                  \
	((VD)_mm512_roundscale_pd((__m512d)(v), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC))
#define KMOVEMASK(m) ((unsigned)_mm512_movepi64_mask((__m512i)(m)))
#include "noise_kern.inc"
#undef KFN
#undef KATTR
#undef KL
#undef KMULHILO
#undef KSQRT
#undef KCOMPRESS_D
#undef KCOMPRESS_U
#undef KGATHER_D
#undef KFLOOR
#undef KMOVEMASK

#endif

/* Instance i runs where polarcam/cpu.h's level i does (0 baseline: the scalar reference). */
static int cpu_has(int isa)
{
	return isa >= 0 && isa <= (int)pc_cpu_supported();
}

static int isa_in_use = -1;

int pc_noise_isa(void)
{
	int isa = __atomic_load_n(&isa_in_use, __ATOMIC_RELAXED);
	return isa >= 0 ? isa : (int)pc_cpu_active();
}

int pc_noise_set_isa(int isa)
{
	if (isa < 0 || isa > 2 || !cpu_has(isa))
		return -1;
	int old = pc_noise_isa();
	__atomic_store_n(&isa_in_use, isa, __ATOMIC_RELAXED);
	return old;
}

const char *pc_noise_isa_name(int isa)
{
	return isa == 2 ? "avx512" : isa == 1 ? "avx2" : "scalar";
}

void pc_noise_frame_row(const pc_frame_args *a)
{
	switch (pc_noise_isa()) {
#ifdef PC_NOISE_X86
	case 2:
		frame_row_avx512(a);
		return;
	case 1:
		frame_row_avx2(a);
		return;
#endif
	default:
		pc_noise_frame_row_ref(a);
	}
}

void pc_noise_fixed_row(uint64_t seed, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                        double *z[4])
{
	switch (pc_noise_isa()) {
#ifdef PC_NOISE_X86
	case 2:
		fixed_row_avx512(seed, sy, sx0, n, mask, z);
		return;
	case 1:
		fixed_row_avx2(seed, sy, sx0, n, mask, z);
		return;
#endif
	default:
		pc_noise_fixed_row_ref(seed, sy, sx0, n, mask, z);
	}
}
