/* The fast float paths of the demosaicking ladder. Each method streams the raw once in row
 * bands (pc_parallel_rows): input rows are converted to padded float rows (mirrored one pixel
 * beyond each end) in a small ring, and the row kernels of demosaic_kern.inc write the outputs
 * directly (8-wide GCC vector code; on x86-64 with AVX2 a second instance uses 256-bit
 * instructions and non-temporal stores for aligned planes, chosen at run time). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "polarcam/stokes.h"
#include "stokes_internal.h"

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PC_HAVE_X86_DISPATCH 1
#include <immintrin.h>
#endif

/* 32- and 64-byte vectors travel between static inline helpers only, never across an ABI
 * boundary, so GCC's note that their calling convention differs without -mavx does not apply. */
#pragma GCC diagnostic ignored "-Wpsabi"

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

static inline v8f vblend_odd8(v8f a, v8f b)
{
	return __builtin_shuffle(a, b, (v8i){ 0, 9, 2, 11, 4, 13, 6, 15 });
}

static inline v16f vblend_odd16(v16f a, v16f b)
{
	return __builtin_shuffle(a, b, (v16i){ 0, 17, 2, 19, 4, 21, 6, 23, 8, 25, 10, 27, 12, 29,
					       14, 31 });
}

static inline v8f vsqrt_lanes(v8f v)
{
	v8f r;
	for (int i = 0; i < 8; i++)
		r[i] = sqrtf(v[i]);
	return r;
}

/* Baseline instance (8 lanes of GCC vector code; SSE2 pairs). */
#define KW 8
#define vf v8f
#define vi v8i
#define vsplat vsplat8
#define vld vld8
#define vabs vabs8
#define vsel vsel8
#define vblend_odd vblend_odd8
#define KFN(name) name##_base
#define KATTR
#define KSTORE(p, v, nt) ((void)(nt), vst8((p), (v)))
#define KSQRT(v) vsqrt_lanes(v)
#define KFMA(a, b, c) ((a) * (b) + (c))
#define KDIV(n, d) ((n) / (d))
#define KRSQRT(p) (vsplat(1.0f) / vsqrt_lanes(p))
#define km v8i
#define KLT(a, b) ((a) < (b))
#define KSEL(m, a, b) vsel((m), (a), (b))
#define KMAX(a, b) vsel((a) > (b), (a), (b))
#define KMIN(a, b) vsel((a) < (b), (a), (b))
#include "demosaic_kern.inc"
#undef KFN
#undef KATTR
#undef KSTORE
#undef KSQRT
#undef KFMA
#undef KRSQRT
#undef KDIV
#undef KSEL
#undef km
#undef KLT
#undef KMAX
#undef KMIN

#ifdef PC_HAVE_X86_DISPATCH
/* 1/d for normal d in [2^-60, 2^60]: the hardware estimate (relative error 2^-14 for
 * rcp14ps) refined by one Newton step r' = r + r·(1 − d·r), which squares the relative error
 * (≤ 4e-9, before rounding). */
#define PC_AVX512_TARGET "avx512f,avx512vl,avx512dq,avx512bw,fma"

static inline __attribute__((always_inline, target(PC_AVX512_TARGET))) v16f rcp_avx512(v16f d)
{
	__m512 r = _mm512_rcp14_ps((__m512)d);
	__m512 e = _mm512_fnmadd_ps((__m512)d, r, _mm512_set1_ps(1.0f));
	return (v16f)_mm512_fmadd_ps(r, e, r);
}

/* AVX2 instance: the same source, 256-bit instructions, streaming stores. */
#define KFN(name) name##_avx2
#define KATTR __attribute__((target("avx2,fma")))
#define KSTORE(p, v, nt)                                                                         \
	do {                                                                                     \
		if (nt)                                                                          \
			_mm256_stream_ps((p), (__m256)(v));                                      \
		else                                                                             \
			vst8((p), (v));                                                          \
	} while (0)
#define KSQRT(v) ((v8f)_mm256_sqrt_ps((__m256)(v)))
#define KFMA(a, b, c) ((v8f)_mm256_fmadd_ps((__m256)(a), (__m256)(b), (__m256)(c)))
#define KDIV(n, d) ((n) / (d))
#define KRSQRT(p) ((v8f)_mm256_rsqrt_ps((__m256)(p)))
#define km v8i
#define KLT(a, b) ((a) < (b))
#define KSEL(m, a, b) ((v8f)_mm256_blendv_ps((__m256)(b), (__m256)(a), (__m256)(m)))
#define KMAX(a, b) ((v8f)_mm256_max_ps((__m256)(a), (__m256)(b)))
#define KMIN(a, b) ((v8f)_mm256_min_ps((__m256)(a), (__m256)(b)))
#include "demosaic_kern.inc"
#undef KFN
#undef KATTR
#undef KSTORE
#undef KSQRT
#undef KFMA
#undef KRSQRT
#undef KDIV
#undef KSEL
#undef km
#undef KLT
#undef KMAX
#undef KMIN
#endif

#undef KW
#undef vf
#undef vi
#undef vsplat
#undef vld
#undef vabs
#undef vsel
#undef vblend_odd

#ifdef PC_HAVE_X86_DISPATCH
/* AVX-512 instance: the same source 16 lanes wide (one 64-byte store per output row and 16
 * pixels), 32 vector registers, comparisons into mask registers. */
#define KW 16
#define vf v16f
#define vi v16i
#define vsplat vsplat16
#define vld vld16
#define vabs vabs16
#define vsel vsel16
#define vblend_odd vblend_odd16
#define KFN(name) name##_avx512
#define KATTR __attribute__((target(PC_AVX512_TARGET)))
#define KSTORE(p, v, nt)                                                                         \
	do {                                                                                     \
		if (nt)                                                                          \
			_mm512_stream_ps((p), (__m512)(v));                                      \
		else                                                                             \
			vst16((p), (v));                                                         \
	} while (0)
#define KSQRT(v) ((v16f)_mm512_sqrt_ps((__m512)(v)))
#define KFMA(a, b, c) ((v16f)_mm512_fmadd_ps((__m512)(a), (__m512)(b), (__m512)(c)))
#define KDIV(n, d) ((n) * rcp_avx512(d))
#define KRSQRT(p) ((v16f)_mm512_rsqrt14_ps((__m512)(p)))
#define km __mmask16
#define KLT(a, b) _mm512_cmp_ps_mask((__m512)(a), (__m512)(b), _CMP_LT_OQ)
#define KSEL(m, a, b) ((v16f)_mm512_mask_blend_ps((m), (__m512)(b), (__m512)(a)))
#define KMAX(a, b) ((v16f)_mm512_max_ps((__m512)(a), (__m512)(b)))
#define KMIN(a, b) ((v16f)_mm512_min_ps((__m512)(a), (__m512)(b)))
#include "demosaic_kern.inc"
#undef KFN
#undef KATTR
#undef KSTORE
#undef KSQRT
#undef KFMA
#undef KRSQRT
#undef KDIV
#undef KSEL
#undef km
#undef KLT
#undef KMAX
#undef KMIN
#undef KW
#undef vf
#undef vi
#undef vsplat
#undef vld
#undef vabs
#undef vsel
#undef vblend_odd

static int use_avx512(void)
{
	static int cached = -1;
	if (cached < 0) {
		const char *e = getenv("POLARCAM_NO_AVX512");
		__builtin_cpu_init();
		cached = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
			 __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
			 !(e && *e && *e != '0');
	}
	return cached;
}

static int use_avx2(void)
{
	static int cached = -1;
	if (cached < 0) {
		const char *e = getenv("POLARCAM_NO_AVX2");
		__builtin_cpu_init();
		cached = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
			 !(e && *e && *e != '0');
	}
	return cached;
}
#endif

/* Non-temporal stores only pay for outputs much larger than the caches; the kernels use them
 * on 64-byte aligned row starts (whole cache lines; the AVX-512 stores need it). */
#define PC_NT_MIN_BYTES nt_min_bytes()

/* 32 MB, except on AMD processors, where the default is never; POLARCAM_NT_MIN_BYTES
 * overrides it (the tests use 0 to exercise the streaming paths on small frames). On the AMD
 * EPYC (Zen 3, 2 cores, KVM) of round 3 (docs/status/pipeline.md) every streaming kernel ran
 * slower with non-temporal stores than with ordinary ones, one thread, same run: fused
 * bilinear pipeline 23 → 12 ms, bilinear 10 → 6.7 ms, ratio pipeline 33 → 27 ms; a plain
 * stream of the same bytes was fast either way, so it is the mix of compute and streaming
 * stores that stalls there. The AVX-512 machine the kernels were first tuned on gained from
 * them. */
static size_t nt_min_bytes(void)
{
	static size_t cached = (size_t)-1; /* not read yet */
	if (cached == (size_t)-1) {
		const char *e = getenv("POLARCAM_NT_MIN_BYTES");
		char *end;
		unsigned long long v = e && *e ? strtoull(e, &end, 10) : 0;
		size_t dflt = (size_t)32 << 20;
#ifdef PC_HAVE_X86_DISPATCH
		__builtin_cpu_init();
		if (__builtin_cpu_is("amd"))
			dflt = (size_t)-2; /* never */
#endif
		cached = e && *e && !*end && v < (size_t)-1 ? (size_t)v : dflt;
	}
	return cached;
}

static int planes_aligned(const pc_fplane *p, unsigned n);

/* Copies n rows of w floats with non-temporal stores (dst rows 64-byte aligned), one row after
 * the other so that every store sequence fills whole cache lines. For the row-cache methods
 * (demosaic_ic.c), which compute a row in cache and then write it out; PC_ENOTSUP without
 * AVX2, where the caller keeps ordinary stores. */
#ifdef PC_HAVE_X86_DISPATCH
__attribute__((target("avx2"))) static void stream_rows_avx2(float *const dst[],
							     const float *const src[], unsigned n,
							     uint32_t w)
{
	for (unsigned k = 0; k < n; k++) {
		uint32_t x = 0;
		for (; x + 16 <= w; x += 16) {
			_mm256_stream_ps(dst[k] + x, _mm256_loadu_ps(src[k] + x));
			_mm256_stream_ps(dst[k] + x + 8, _mm256_loadu_ps(src[k] + x + 8));
		}
		for (; x < w; x++)
			dst[k][x] = src[k][x];
	}
	_mm_sfence();
}
#endif

int pc_dm_stream_rows(float *const dst[], const float *const src[], unsigned n, uint32_t w)
{
#ifdef PC_HAVE_X86_DISPATCH
	if (use_avx2()) {
		stream_rows_avx2(dst, src, n, w);
		return 0;
	}
#endif
	(void)dst;
	(void)src;
	(void)n;
	(void)w;
	return PC_ENOTSUP;
}

int pc_dm_stream_wanted(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h)
{
#ifdef PC_HAVE_X86_DISPATCH
	return use_avx2() && planes_aligned(p, n) && (size_t)w * h * 4 * n >= PC_NT_MIN_BYTES;
#else
	(void)p;
	(void)n;
	(void)w;
	(void)h;
	return 0;
#endif
}


static int planes_aligned(const pc_fplane *p, unsigned n)
{
	for (unsigned c = 0; c < n; c++)
		if (!p[c].data || ((uintptr_t)p[c].data & 63) || ((p[c].row_stride * 4) & 63) ||
		    p[c].pixel_stride != 1)
			return 0;
	return 1;
}

/* ---- row ring: padded float rows y-1, y, y+1 ---- */
typedef struct ring {
	float *buf;
	size_t pitch; /* floats per padded row */
	float *row[3];
	int32_t have[3]; /* which mirrored source row each slot holds */
} ring;

static int ring_init(ring *r, uint32_t w)
{
	r->pitch = ((size_t)w + 2 + 15) / 16 * 16;
	r->buf = pc_dm_alloc(3 * r->pitch * sizeof(float));
	if (!r->buf)
		return -1;
	for (int i = 0; i < 3; i++) {
		r->row[i] = r->buf + i * r->pitch + 1;
		r->have[i] = -1;
	}
	return 0;
}

/* The padded row for source row y (mirrored), converting it if not already in the ring. */
static const float *ring_get(ring *r, const pc_dm_input *in, int y)
{
	int sy = pc_mirror(y, (int)in->height);
	for (int i = 0; i < 3; i++)
		if (r->have[i] == sy)
			return r->row[i];
	/* evict the slot holding the smallest row (bands walk downwards) */
	int k = 0;
	for (int i = 1; i < 3; i++)
		if (r->have[i] < r->have[k])
			k = i;
	pc_dm_row_to_float(in, (uint32_t)sy, r->row[k]);
	r->have[k] = sy;
	return r->row[k];
}

/* ---- bilinear ---- */
typedef struct bil_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	int planar, nt, err;
} bil_job;

static void bilinear_band(void *ctx, uint32_t y0, uint32_t y1)
{
	bil_job *j = ctx;
	uint32_t w = j->in->width;
	ring rg;
	float *tmp = NULL;
	if (ring_init(&rg, w) || (!j->planar && !(tmp = pc_dm_alloc(4 * (size_t)w * 4)))) {
		pc_dm_free(rg.buf);
		j->err = 1;
		return;
	}
	for (uint32_t y = y0; y < y1; y++) {
		const float *a = ring_get(&rg, j->in, (int)y - 1);
		const float *b = ring_get(&rg, j->in, (int)y);
		const float *c = ring_get(&rg, j->in, (int)y + 1);
		unsigned slot[4] = { pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
				     pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1) };
		float *o[4];
		for (int k = 0; k < 4; k++)
			o[k] = j->planar ? j->out[slot[k]].data + (size_t)y * j->out[slot[k]].row_stride
					 : tmp + (size_t)k * w;
#ifdef PC_HAVE_X86_DISPATCH
		if (use_avx2() && use_avx512())
			bilinear_row_avx512(a, b, c, w, o, j->nt);
		else if (use_avx2())
			bilinear_row_avx2(a, b, c, w, o, j->nt);
		else
#endif
			bilinear_row_base(a, b, c, w, o, 0);
		if (!j->planar)
			for (int k = 0; k < 4; k++) {
				const pc_fplane *p = &j->out[slot[k]];
				float *d = p->data + (size_t)y * p->row_stride;
				for (uint32_t x = 0; x < w; x++)
					d[(size_t)x * p->pixel_stride] = o[k][x];
			}
	}
#ifdef PC_HAVE_X86_DISPATCH
	if (j->nt)
		_mm_sfence();
#endif
	pc_dm_free(tmp);
	pc_dm_free(rg.buf);
}

static int fast_bilinear(const pc_dm_input *in, const pc_mosaic *m, int threads,
			 const pc_fplane *out)
{
	bil_job j = { in, m, out, 1, 0, 0 };
	for (int c = 0; c < 4; c++)
		if (out[c].pixel_stride != 1)
			j.planar = 0;
	j.nt = j.planar && planes_aligned(out, 4) &&
	       (size_t)in->width * in->height * 16 >= PC_NT_MIN_BYTES;
	pc_parallel_rows(in->height, 0, threads, bilinear_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "bilinear: row buffers") : 0;
}

/* ---- super-pixel ---- */
typedef struct sp_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	int half, err;
} sp_job;

static void superpixel_band(void *ctx, uint32_t y0, uint32_t y1)
{
	sp_job *j = ctx;
	uint32_t w = j->in->width;
	float *r = pc_dm_alloc(2 * ((size_t)w + 2) * sizeof(float));
	if (!r) {
		j->err = 1;
		return;
	}
	float *r0 = r + 1, *r1 = r + w + 3;
	/* bands start on even rows (pc_parallel_rows bands are multiples of 8 rows) */
	for (uint32_t by = y0 & ~1u; by < y1; by += 2) {
		pc_dm_row_to_float(j->in, by, r0);
		pc_dm_row_to_float(j->in, by + 1, r1);
		const float *rows[2] = { r0, r1 };
		for (unsigned c = 0; c < 4; c++) {
			unsigned dx, dy;
			pc_mosaic_channel_pos(j->m, c, &dx, &dy);
			const float *src = rows[dy] + dx;
			const pc_fplane *p = &j->out[c];
			if (j->half) {
				float *d = p->data + (size_t)(by / 2) * p->row_stride;
				for (uint32_t x = 0; x < w / 2; x++)
					d[(size_t)x * p->pixel_stride] = src[2 * x];
			} else {
				for (uint32_t k = 0; k < 2; k++) {
					float *d = p->data + (size_t)(by + k) * p->row_stride;
					for (uint32_t x = 0; x < w; x++)
						d[(size_t)x * p->pixel_stride] = src[x & ~1u];
				}
			}
		}
	}
	pc_dm_free(r);
}

static int fast_superpixel(const pc_dm_input *in, const pc_mosaic *m, int half, int threads,
			   const pc_fplane *out)
{
	sp_job j = { in, m, out, half, 0 };
	pc_parallel_rows(in->height, 8, threads, superpixel_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "superpixel: row buffers") : 0;
}

int pc_demosaic_ic(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
		   double full_scale, int threads, const pc_fplane *out);

int pc_demosaic_fast(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
		     double full_scale, int threads, const pc_fplane *out)
{
	if (m->period == 4)
		return PC_ENOTSUP;
	switch (method) {
	case PC_DM_BICUBIC:
	case PC_DM_PPID:
	case PC_DM_RI:
	case PC_DM_EARI:
	case PC_DM_RATIO:
		return pc_demosaic_ic(in, m, method, full_scale, threads, out);
	case PC_DM_EARI_MLRI:
	case PC_DM_EARI_ROBUST:
		return pc_demosaic_fast_mlri(in, m, method, full_scale, threads, out);
	case PC_DM_PCDP:
		return pc_demosaic_fast_pcdp(in, m, threads, out);
	case PC_DM_BILINEAR:
		return fast_bilinear(in, m, threads, out);
	case PC_DM_SUPERPIXEL:
		return fast_superpixel(in, m, 0, threads, out);
	case PC_DM_SUPERPIXEL_HALF:
		return fast_superpixel(in, m, 1, threads, out);
	default:
		return PC_ENOTSUP;
	}
}

/* ---- fused bilinear + Stokes ---- */
typedef struct st_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_stokes_out *out;
	int planar, nt, err;
} st_job;

static void stokes_band(void *ctx, uint32_t y0, uint32_t y1)
{
	st_job *j = ctx;
	uint32_t w = j->in->width;
	ring rg;
	float *tmp = NULL;
	if (ring_init(&rg, w) || (!j->planar && !(tmp = pc_dm_alloc(5 * (size_t)w * 4)))) {
		pc_dm_free(rg.buf);
		j->err = 1;
		return;
	}
	const pc_fplane *planes[5] = { &j->out->s0, &j->out->s1, &j->out->s2, &j->out->dolp,
				       &j->out->aolp };
	const int exact = j->in->type == PC_DMT_F32;
	for (uint32_t y = y0; y < y1; y++) {
		const float *a = ring_get(&rg, j->in, (int)y - 1);
		const float *b = ring_get(&rg, j->in, (int)y);
		const float *c = ring_get(&rg, j->in, (int)y + 1);
		unsigned ch[4] = { pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
				   pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1) };
		/* S1 = I0 − I90 and S2 = I45 − I135 as signed sums of the four slots */
		float k1[4], k2[4];
		for (int k = 0; k < 4; k++) {
			k1[k] = ch[k] == 0 ? 1.0f : ch[k] == 2 ? -1.0f : 0.0f;
			k2[k] = ch[k] == 1 ? 1.0f : ch[k] == 3 ? -1.0f : 0.0f;
		}
		float *o[5];
		for (int k = 0; k < 5; k++)
			o[k] = !planes[k]->data ? NULL
			       : j->planar	? planes[k]->data + (size_t)y * planes[k]->row_stride
						: tmp + (size_t)k * w;
#ifdef PC_HAVE_X86_DISPATCH
		if (use_avx2() && use_avx512())
			stokes_row_avx512(a, b, c, w, k1, k2, exact, o, j->nt);
		else if (use_avx2())
			stokes_row_avx2(a, b, c, w, k1, k2, exact, o, j->nt);
		else
#endif
			stokes_row_base(a, b, c, w, k1, k2, exact, o, 0);
		if (!j->planar)
			for (int k = 0; k < 5; k++) {
				if (!o[k])
					continue;
				float *d = planes[k]->data + (size_t)y * planes[k]->row_stride;
				for (uint32_t x = 0; x < w; x++)
					d[(size_t)x * planes[k]->pixel_stride] = o[k][x];
			}
	}
#ifdef PC_HAVE_X86_DISPATCH
	if (j->nt)
		_mm_sfence();
#endif
	pc_dm_free(tmp);
	pc_dm_free(rg.buf);
}

int pc_stokes_bilinear_fused(const pc_dm_input *in, const pc_mosaic *m, int threads,
			     const pc_stokes_out *out)
{
	st_job j = { in, m, out, 1, 0, 0 };
	const pc_fplane *planes[5] = { &out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp };
	int aligned = 1, n = 0;
	for (int k = 0; k < 5; k++) {
		if (!planes[k]->data)
			continue;
		n++;
		if (planes[k]->pixel_stride != 1)
			j.planar = 0;
		if (!planes_aligned(planes[k], 1))
			aligned = 0;
	}
	j.nt = j.planar && aligned && (size_t)in->width * in->height * 4 * n >= PC_NT_MIN_BYTES;
	pc_parallel_rows(in->height, 0, threads, stokes_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "stokes: row buffers") : 0;
}

/* ---- Stokes from planar analyser images (the non-bilinear pipelines) ---- */
typedef struct st4_job {
	const pc_fplane *in;
	uint32_t w;
	const pc_stokes_out *out;
	int nt;
} st4_job;

static void stokes4_band(void *ctx, uint32_t y0, uint32_t y1)
{
	st4_job *j = ctx;
	const pc_fplane *planes[5] = { &j->out->s0, &j->out->s1, &j->out->s2, &j->out->dolp,
				       &j->out->aolp };
	for (uint32_t y = y0; y < y1; y++) {
		const float *r[4];
		for (int c = 0; c < 4; c++)
			r[c] = j->in[c].data + (size_t)y * j->in[c].row_stride;
		float *o[5];
		for (int k = 0; k < 5; k++)
			o[k] = planes[k]->data ? planes[k]->data + (size_t)y * planes[k]->row_stride : NULL;
#ifdef PC_HAVE_X86_DISPATCH
		if (use_avx2() && use_avx512())
			stokes4_row_avx512(r[0], r[1], r[2], r[3], j->w, o, j->nt);
		else if (use_avx2())
			stokes4_row_avx2(r[0], r[1], r[2], r[3], j->w, o, j->nt);
		else
#endif
			stokes4_row_base(r[0], r[1], r[2], r[3], j->w, o, 0);
	}
#ifdef PC_HAVE_X86_DISPATCH
	if (j->nt)
		_mm_sfence();
#endif
}

int pc_stokes_planar_fast(const pc_fplane in[4], uint32_t width, uint32_t height,
			  const pc_stokes_out *out)
{
	const pc_fplane *planes[5] = { &out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp };
	for (int c = 0; c < 4; c++)
		if (in[c].pixel_stride != 1)
			return PC_ENOTSUP;
	int aligned = 1, n = 0;
	for (int k = 0; k < 5; k++) {
		if (!planes[k]->data)
			continue;
		n++;
		if (planes[k]->pixel_stride != 1)
			return PC_ENOTSUP;
		if (!planes_aligned(planes[k], 1))
			aligned = 0;
	}
	st4_job j = { in, width, out, aligned && (size_t)width * height * 4 * n >= PC_NT_MIN_BYTES };
	pc_parallel_rows(height, 0, 0, stokes4_band, &j);
	return 0;
}

/* One row y of Stokes/DoLP/AoLP from four analyser rows (channel order), into planar outputs
 * (the row-cache methods' fused pipeline, demosaic_ic.c). */
void pc_dm_stokes_row(const float *const ch[4], uint32_t w, uint32_t y, const pc_stokes_out *out,
		      int nt)
{
	const pc_fplane *planes[5] = { &out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp };
	float *o[5];
	for (int k = 0; k < 5; k++)
		o[k] = planes[k]->data ? planes[k]->data + (size_t)y * planes[k]->row_stride : NULL;
#ifdef PC_HAVE_X86_DISPATCH
	if (use_avx2() && use_avx512())
		stokes4_row_avx512(ch[0], ch[1], ch[2], ch[3], w, o, nt);
	else if (use_avx2())
		stokes4_row_avx2(ch[0], ch[1], ch[2], ch[3], w, o, nt);
	else
#endif
		stokes4_row_base(ch[0], ch[1], ch[2], ch[3], w, o, 0);
#ifdef PC_HAVE_X86_DISPATCH
	if (nt)
		_mm_sfence();
#endif
}

bool pc_stokes_streams(const pc_stokes_out *out, uint32_t width, uint32_t height)
{
	return out && pc_dm_stokes_stream_wanted(out, width, height);
}

int pc_dm_stokes_stream_wanted(const pc_stokes_out *out, uint32_t w, uint32_t h)
{
	const pc_fplane *planes[5] = { &out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp };
	int n = 0;
	for (int k = 0; k < 5; k++) {
		if (!planes[k]->data)
			continue;
		n++;
		if (!planes_aligned(planes[k], 1))
			return 0;
	}
#ifdef PC_HAVE_X86_DISPATCH
	return use_avx2() && (size_t)w * h * 4 * n >= PC_NT_MIN_BYTES;
#else
	return 0;
#endif
}

/* ---- bilinear into 16-bit planes ---- */
typedef struct b16_job {
	const pc_view *raw;
	const pc_mosaic *m;
	unsigned frac;
	uint16_t *const *out;
	size_t ostride;
} b16_job;

/* One row: S, H, V, D as in bilinear_row, in integers. With q = 2 − frac, a value v·2^frac is
 * (4v) >> q rounded: (4v + (q ? 1 << (q − 1) : 0)) >> q, where 4v is an exact integer. */
#ifdef PC_HAVE_X86_DISPATCH
__attribute__((target_clones("avx2", "default")))
#endif
static void b16_row(const uint16_t *restrict a, const uint16_t *restrict b,
		    const uint16_t *restrict c, long w, unsigned q, uint16_t *restrict o0,
		    uint16_t *restrict o1, uint16_t *restrict o2, uint16_t *restrict o3)
{
	const uint32_t rnd = q ? 1u << (q - 1) : 0;
#define PC_B16_PIXEL(x, xm, xp)                                                                  \
	do {                                                                                     \
		uint32_t S4 = 4u * b[x], H4 = 2u * ((uint32_t)b[xm] + b[xp]);                   \
		uint32_t V4 = 2u * ((uint32_t)a[x] + c[x]);                                      \
		uint32_t D4 = ((uint32_t)a[xm] + a[xp]) + ((uint32_t)c[xm] + c[xp]);            \
		int odd = (int)((x)&1);                                                          \
		o0[x] = (uint16_t)(((odd ? H4 : S4) + rnd) >> q);                                \
		o1[x] = (uint16_t)(((odd ? S4 : H4) + rnd) >> q);                                \
		o2[x] = (uint16_t)(((odd ? D4 : V4) + rnd) >> q);                                \
		o3[x] = (uint16_t)(((odd ? V4 : D4) + rnd) >> q);                                \
	} while (0)
	PC_B16_PIXEL(0, 1, 1);
	PC_SIMD
	for (long x = 1; x < w - 1; x++)
		PC_B16_PIXEL(x, x - 1, x + 1);
	PC_B16_PIXEL(w - 1, w - 2, w - 2);
#undef PC_B16_PIXEL
}

static void b16_band(void *ctx, uint32_t y0, uint32_t y1)
{
	b16_job *j = ctx;
	const pc_view *r = j->raw;
	for (uint32_t y = y0; y < y1; y++) {
		const uint16_t *a = PC_ROW(r, const uint16_t, (uint32_t)pc_mirror((int)y - 1, (int)r->height));
		const uint16_t *b = PC_ROW(r, const uint16_t, y);
		const uint16_t *c = PC_ROW(r, const uint16_t, (uint32_t)pc_mirror((int)y + 1, (int)r->height));
		uint16_t *o[4];
		unsigned slot[4] = { pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y), pc_dm_ch(j->m, 0, y + 1),
				     pc_dm_ch(j->m, 1, y + 1) };
		for (int k = 0; k < 4; k++)
			o[k] = (uint16_t *)((uint8_t *)j->out[slot[k]] + (size_t)y * j->ostride);
		b16_row(a, b, c, r->width, 2 - j->frac, o[0], o[1], o[2], o[3]);
	}
}

int pc_demosaic_bilinear_u16(const pc_view *raw, const pc_mosaic *m, unsigned frac_bits,
			     int threads, uint16_t *const out[4], size_t out_stride)
{
	int rc = pc_view_check(raw);
	if (rc)
		return pc_error_prefix(rc, "raw: ");
	if ((rc = pc_mosaic_check(m)))
		return rc;
	if (m->period != 2)
		return pc_error(PC_EINVAL, "16-bit bilinear: monochrome polarizer mosaics only");
	const pc_format_info *fi = pc_format_info_get(raw->format);
	if (fi->is_float || fi->packing != PC_PACK_NONE || fi->bits <= 8)
		return pc_error(PC_ENOTSUP, "16-bit bilinear: raw format %s; expected a 16-bit "
					    "container (Mono10/12/14/16)", fi->name);
	if (frac_bits > 2 || fi->bits + frac_bits > 16)
		return pc_error(PC_ERANGE, "16-bit bilinear: %u-bit data with %u fraction bits do not "
					   "fit 16 bits (frac_bits 0..2, bits + frac_bits <= 16)",
				fi->bits, frac_bits);
	if (raw->width % 2 || raw->height % 2 || raw->width < 4 || raw->height < 4)
		return pc_error(PC_EINVAL, "raw size %ux%u: width and height must be even and at "
					   "least 4", raw->width, raw->height);
	if (!out || out_stride < (size_t)raw->width * 2)
		return pc_error(PC_EINVAL, "16-bit bilinear: output planes missing or stride %zu "
					   "below %u bytes", out_stride, 2 * raw->width);
	for (int c = 0; c < 4; c++)
		if (!out[c])
			return pc_error(PC_EINVAL, "16-bit bilinear: output plane %d missing", c);
	b16_job j = { raw, m, frac_bits, out, out_stride };
	pc_parallel_rows(raw->height, 0, threads, b16_band, &j);
	return 0;
}
