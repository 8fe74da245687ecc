/* The helpers shared by every demosaicking and Stokes kernel (demosaic_common.h). */
#include "demosaic_common.h"

#include <limits.h>
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cpu_internal.h"
#include "polarcam/error.h"
#include "polarcam/format.h"

#ifdef PC_CPU_X86
#include <immintrin.h>
#endif

/* ---- scratch memory: a small pool of freed blocks ----
 * The fast paths allocate their row scratch per row band and free it at the band's end. glibc
 * returns such blocks to the system (a block at or above the mmap threshold is unmapped on
 * free, and the main thread's heap is trimmed once its free top exceeds the trim threshold),
 * so the next band or call touches fresh pages, each a page fault. On the 2-vCPU Zen 5 guest
 * of 2026-12-06 a fault cost about 10 µs: ratio-nr took 63 faults a call, all of them in the
 * main thread's bands, whose first 16 rows took 0.78 ms against 0.13 ms in the other thread,
 * which then waited for it (docs/demosaicking.md, Round 30). Freed blocks of up to
 * PC_POOL_BLOCK bytes are therefore kept, up to PC_POOL_TOTAL bytes in PC_POOL_SLOTS slots,
 * and handed out again to a request of the same size; full-frame buffers are freed as before.
 * Each block carries its size in a 64-byte header. The pool is off under AddressSanitizer
 * (a reused block would hide a use after free from it) and with POLARCAM_SCRATCH_POOL=0
 * (e.g. under valgrind); pc_dm_pool_release frees what it holds (also at exit). */
#define PC_POOL_SLOTS 64
#define PC_POOL_BLOCK ((size_t)4 << 20)
#define PC_POOL_TOTAL ((size_t)32 << 20)
#if defined(__SANITIZE_ADDRESS__)
#define PC_POOL_BUILD 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define PC_POOL_BUILD 0
#endif
#endif
#ifndef PC_POOL_BUILD
#define PC_POOL_BUILD 1
#endif

static struct {
	void *block[PC_POOL_SLOTS];
	size_t size[PC_POOL_SLOTS];
	size_t total;
	unsigned next; /* the slot to evict when all are taken */
	atomic_flag lock;
	atomic_int state; /* 0 not yet read from the environment, 1 on, 2 off */
} pool = {.lock = ATOMIC_FLAG_INIT};

static void pool_lock(void)
{
	while (atomic_flag_test_and_set_explicit(&pool.lock, memory_order_acquire))
		;
}

static void pool_unlock(void)
{
	atomic_flag_clear_explicit(&pool.lock, memory_order_release);
}

int pc_dm_pool_enabled(void)
{
	int st = atomic_load(&pool.state);
	if (st == 0) {
		const char *e = getenv("POLARCAM_SCRATCH_POOL");
		st = PC_POOL_BUILD && !(e && strcmp(e, "0") == 0) ? 1 : 2;
		atomic_store(&pool.state, st);
	}
	return st == 1;
}

void pc_dm_pool_release(void)
{
	pool_lock();
	for (int i = 0; i < PC_POOL_SLOTS; i++) {
		free(pool.block[i]);
		pool.block[i] = NULL;
		pool.size[i] = 0;
	}
	pool.total = 0;
	pool_unlock();
}

size_t pc_dm_pool_bytes(void)
{
	pool_lock();
	size_t t = pool.total;
	pool_unlock();
	return t;
}

__attribute__((destructor)) static void pool_at_exit(void)
{
	pc_dm_pool_release();
}

void *pc_dm_alloc(size_t bytes)
{
	/* 64 bytes of slack after the rounded size (kernels may read a vector past a row), the
	 * header before it */
	if (bytes > SIZE_MAX - 256)
		return NULL;
	const size_t n = (bytes + 63) / 64 * 64 + 64;
	if (pc_dm_pool_enabled() && n <= PC_POOL_BLOCK) {
		pool_lock();
		for (int i = 0; i < PC_POOL_SLOTS; i++)
			if (pool.block[i] && pool.size[i] == n) {
				unsigned char *b = pool.block[i];
				pool.block[i] = NULL;
				pool.total -= n;
				pool_unlock();
				return b + 64;
			}
		pool_unlock();
	}
	unsigned char *b = aligned_alloc(64, n + 64);
	if (!b)
		return NULL;
	memcpy(b, &n, sizeof n);
	return b + 64;
}

void pc_dm_free(void *p)
{
	if (!p)
		return;
	unsigned char *b = (unsigned char *)p - 64;
	size_t n;
	memcpy(&n, b, sizeof n);
	if (!pc_dm_pool_enabled() || n > PC_POOL_BLOCK) {
		free(b);
		return;
	}
	/* blocks that leave the pool to make room, freed outside the lock */
	void *out[PC_POOL_SLOTS];
	int nout = 0, slot = -1;
	pool_lock();
	for (int i = 0; i < PC_POOL_SLOTS && slot < 0; i++)
		if (!pool.block[i])
			slot = i;
	/* no free slot, or over the total: the oldest blocks in turn make room */
	for (unsigned k = 0; (slot < 0 || pool.total + n > PC_POOL_TOTAL) && k < PC_POOL_SLOTS;
	     k++) {
		int i = (int)(pool.next++ % PC_POOL_SLOTS);
		if (!pool.block[i])
			continue;
		out[nout++] = pool.block[i];
		pool.total -= pool.size[i];
		pool.block[i] = NULL;
		if (slot < 0)
			slot = i;
	}
	pool.block[slot] = b;
	pool.size[slot] = n;
	pool.total += n;
	pool_unlock();
	for (int k = 0; k < nout; k++)
		free(out[k]);
}

void pc_dm_planes_separate(float *base, uint32_t width, uint32_t height, unsigned channels,
                           pc_fplane *planes)
{
	for (unsigned c = 0; c < channels; c++) {
		planes[c].data = base + (size_t)c * width * height;
		planes[c].row_stride = width;
		planes[c].pixel_stride = 1;
	}
}

/* ---- input ---- */

int pc_dm_prepare_input(const pc_view *raw, double black, pc_dm_input *in, void **owned)
{
	*owned = NULL;
	const pc_format_info *fi = pc_format_info_get(raw->format);
	in->width = raw->width;
	in->height = raw->height;
	in->black = (float)black;
	in->black_d = black;
	in->dark = in->gain_inv = NULL;
	in->dark_scale = in->dark_offset = 0;
	if (fi->is_float) {
		int rc = pc_view_check_bits(raw, 32);
		if (rc)
			return pc_error_prefix(rc, "raw: ");
		in->data = raw->data;
		in->stride = raw->stride;
		in->type = PC_DMT_F32;
		return 0;
	}
	if (fi->packing == PC_PACK_NONE) {
		in->data = raw->data;
		in->stride = raw->stride;
		in->type = fi->bits <= 8 ? PC_DMT_U8 : PC_DMT_U16;
		return 0;
	}
	size_t stride = ((size_t)raw->width * 2 + 63) / 64 * 64;
	uint16_t *u = pc_dm_alloc(stride * raw->height);
	if (!u)
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot unpack", raw->width, raw->height);
	int rc = pc_view_to_u16(raw, u, stride);
	if (rc) {
		pc_dm_free(u);
		return pc_error_prefix(rc, "raw: ");
	}
	*owned = u;
	in->data = (const uint8_t *)u;
	in->stride = stride;
	in->type = PC_DMT_U16;
	return 0;
}

void pc_dm_input_dark(pc_dm_input *in, const pc_pipeline_opts *opts)
{
	in->dark = opts->dark;
	in->gain_inv = opts->gain_inv;
	const bool sc = opts->dark && opts->dark_scale != 0 && opts->dark_scale != 1;
	in->dark_scale = sc ? (float)opts->dark_scale : 0.0f;
	in->dark_offset = sc ? (float)(opts->dark_pivot * (1 - opts->dark_scale)) : 0.0f;
}

pc_dm_input pc_dm_input_f32(const float *data, uint32_t width, uint32_t height)
{
	pc_dm_input in = {(const uint8_t *)data,
	                  (size_t)width * sizeof(float),
	                  PC_DMT_F32,
	                  width,
	                  height,
	                  0.0f,
	                  0.0,
	                  NULL,
	                  NULL,
	                  0.0f,
	                  0.0f};
	return in;
}

/* Row y corrected per pixel: (sample − dark)·gain_inv, the arithmetic of the calibration's
 * correction (polarcam/calib.h) in float, with the black level where there is no dark map. */
static void row_corrected(const pc_dm_input *in, uint32_t y, float *dst)
{
	const uint8_t *row = in->data + (size_t)y * in->stride;
	const uint32_t w = in->width;
	const size_t o = (size_t)y * w;
	const float k = in->black;
	const float *dk = in->dark ? in->dark + o : NULL;
	const float *ig = in->gain_inv ? in->gain_inv + o : NULL;
	switch (in->type) {
	case PC_DMT_U8:
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = row[x];
		break;
	case PC_DMT_U16: {
		const uint16_t *r = (const uint16_t *)(const void *)row;
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = r[x];
		break;
	}
	case PC_DMT_F32:
		memcpy(dst, row, (size_t)w * sizeof(float));
		break;
	}
	const float ds = in->dark_scale, d0 = in->dark_offset;
	if (dk && ds != 0 && ds != 1) {
		/* the dark map about a level (pc_pipeline_opts.dark_scale) */
		if (ig) {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = (dst[x] - (d0 + ds * dk[x])) * ig[x];
		} else {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = dst[x] - (d0 + ds * dk[x]);
		}
	} else if (dk && ig) {
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = (dst[x] - dk[x]) * ig[x];
	} else if (dk) {
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = dst[x] - dk[x];
	} else {
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = (dst[x] - k) * ig[x];
	}
}

void pc_dm_pf_row(pc_dm_pf *pf, const pc_dm_input *in, uint32_t y)
{
	if (y >= in->height) {
		pf->cur = pf->end = 0;
		return;
	}
	const uintptr_t row = (uintptr_t)(in->data + (size_t)y * in->stride);
	pf->end = row + (size_t)in->width * pc_dm_type_bytes(in->type);
	pf->cur = row & ~(uintptr_t)63; /* from the line holding the row's first byte */
}

unsigned pc_dm_pf_step(pc_dm_pf *pf, unsigned n)
{
	unsigned k = 0;
	for (; k < n && pf->cur < pf->end; k++, pf->cur += 64)
		__builtin_prefetch((const void *)pf->cur, 0, 3);
	return k;
}

unsigned pc_dm_pf_finish(pc_dm_pf *pf)
{
	return pc_dm_pf_step(pf, UINT_MAX);
}

void pc_dm_row_to_float(const pc_dm_input *in, uint32_t y, float *dst)
{
	/* the next row into cache while the caller works on this one: the fast paths convert
	 * rows in increasing order, one per output row, and a row's first touch of the raw (out
	 * of cache in a large frame) otherwise stalls on every load (ratio-nr: 9 % of its samples
	 * in this loop; 0.97x its time with the prefetch, docs/demosaicking.md, Round 30; the
	 * row-cache methods and pan-lean spread it instead, pc_dm_pf) */
	pc_dm_pf pf;
	pc_dm_pf_row(&pf, in, y + 1);
	pc_dm_pf_finish(&pf);
	pc_dm_row_convert(in, y, dst);
}

void pc_dm_row_convert(const pc_dm_input *in, uint32_t y, float *dst)
{
	const uint8_t *row = in->data + (size_t)y * in->stride;
	uint32_t w = in->width;
	const float k = in->black;
	if (in->dark || in->gain_inv) {
		row_corrected(in, y, dst);
		dst[-1] = dst[w > 1 ? 1 : 0];
		dst[w] = dst[w > 1 ? w - 2 : 0];
		return;
	}
	/* without a black level, the conversion alone (one operation less per sample) */
	switch (in->type) {
	case PC_DMT_U8:
		if (k == 0) {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = row[x];
		} else {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = (float)row[x] - k;
		}
		break;
	case PC_DMT_U16: {
		const uint16_t *r = (const uint16_t *)(const void *)row;
		if (k == 0) {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = r[x];
		} else {
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = (float)r[x] - k;
		}
		break;
	}
	case PC_DMT_F32:
		if (k == 0) {
			memcpy(dst, row, (size_t)w * sizeof(float));
		} else {
			const float *r = (const float *)(const void *)row;
			PC_SIMD
			for (uint32_t x = 0; x < w; x++)
				dst[x] = r[x] - k;
		}
		break;
	}
	dst[-1] = dst[w > 1 ? 1 : 0];
	dst[w] = dst[w > 1 ? w - 2 : 0];
}

int pc_dm_raw_to_float(const pc_view *raw, double black, float **out)
{
	size_t n = (size_t)raw->width * raw->height;
	float *f = malloc(n * sizeof *f);
	if (!f)
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot convert to float", raw->width,
		                raw->height);
	int rc = pc_view_to_f32(raw, f, (size_t)raw->width * sizeof *f);
	if (rc) {
		free(f);
		return pc_error_prefix(rc, "raw: ");
	}
	if (black != 0) {
		const float k = (float)black;
		for (size_t i = 0; i < n; i++)
			f[i] -= k;
	}
	*out = f;
	return 0;
}

int pc_dm_raw_to_double(const pc_view *raw, double black, double **out)
{
	float *f = NULL;
	int rc = pc_dm_raw_to_float(raw, 0, &f);
	if (rc)
		return rc;
	size_t n = (size_t)raw->width * raw->height;
	double *d = malloc(n * sizeof *d);
	if (!d) {
		free(f);
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot allocate the reference's input",
		                raw->width, raw->height);
	}
	for (size_t i = 0; i < n; i++)
		d[i] = (double)f[i] - black;
	free(f);
	*out = d;
	return 0;
}

/* ---- the 3-row ring ---- */

int pc_dm_ring_init(pc_dm_ring *r, uint32_t w)
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

const float *pc_dm_ring_get(pc_dm_ring *r, const pc_dm_input *in, int y)
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

void pc_dm_ring_free(pc_dm_ring *r)
{
	pc_dm_free(r->buf);
	r->buf = NULL;
}

/* ---- streaming stores ---- */

/* 32 MB, except on AMD processors without AVX-512 (Zen 3 and earlier), where the default is
 * never; POLARCAM_NT_MIN_BYTES overrides it (the tests use 0 to exercise the streaming paths on
 * small frames). On the AMD EPYC of round 3 (Zen 3: AVX2, no AVX-512; 2 cores, KVM;
 * docs/status/pipeline.md) every streaming kernel ran slower with non-temporal stores than
 * with ordinary ones, one thread, same run: fused bilinear pipeline 23 → 12 ms, bilinear
 * 10 → 6.7 ms, ratio pipeline 33 → 27 ms; a plain stream of the same bytes was fast either
 * way, so it is the mix of compute and streaming stores that stalls there. The AVX-512
 * machine the kernels were first tuned on (round 2) gained from them, and so does the AMD
 * EPYC of 2026-12-02 (family 1Ah, Zen 5, with AVX-512; docs/demosaicking.md has the same-run
 * A/B). AMD processors implement AVX-512 from Zen 4 on, so "AMD without AVX-512" is the
 * generation that measured slower (a hypervisor that hides AVX-512 from a newer guest gets
 * ordinary stores too, round 3's behaviour). Read once: every thread computes the same
 * value. */
size_t pc_dm_nt_min_bytes(void)
{
	static _Atomic size_t cached = (size_t)-1; /* not read yet */
	size_t c = cached;
	if (c == (size_t)-1) {
		const char *e = getenv("POLARCAM_NT_MIN_BYTES");
		char *end;
		unsigned long long v = e && *e ? strtoull(e, &end, 10) : 0;
		int before_zen4 = pc_cpu_is_amd() && pc_cpu_supported() < PC_CPU_AVX512;
		size_t dflt = before_zen4 ? (size_t)-2 /* never */ : (size_t)32 << 20;
		c = e && *e && !*end && v < (size_t)-1 ? (size_t)v : dflt;
		cached = c;
	}
	return c;
}

int pc_dm_planes_planar(const pc_fplane *p, unsigned n)
{
	for (unsigned c = 0; c < n; c++)
		if (p[c].pixel_stride != 1)
			return 0;
	return 1;
}

int pc_dm_planes_aligned(const pc_fplane *p, unsigned n)
{
	for (unsigned c = 0; c < n; c++)
		if (!p[c].data || ((uintptr_t)p[c].data & 63) || ((p[c].row_stride * 4) & 63) ||
		    p[c].pixel_stride != 1)
			return 0;
	return 1;
}

int pc_dm_stream_wanted(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h, pc_cpu_level level)
{
	return level >= PC_CPU_AVX2 && pc_dm_planes_aligned(p, n) &&
	       (size_t)w * h * 4 * n >= pc_dm_nt_min_bytes();
}

/* Whether the n planes are one interleaved (H, W, n) array, n = 4 or 12 */
static int planes_interleaved(const pc_fplane *out, unsigned n)
{
	int il = n == 4 || n == 12;
	for (unsigned c = 0; il && c < n; c++)
		il = out[c].pixel_stride == n && out[c].row_stride == out[0].row_stride &&
		     out[c].data == out[0].data + c;
	return il;
}

int pc_dm_stream_wanted_il(const pc_fplane *p, unsigned n, uint32_t w, uint32_t h,
                           pc_cpu_level level)
{
	return level >= PC_CPU_AVX2 && planes_interleaved(p, n) && !((uintptr_t)p[0].data & 63) &&
	       !((p[0].row_stride * 4) & 63) && (size_t)w * h * 4 * n >= pc_dm_nt_min_bytes();
}

#ifdef PC_CPU_X86
__attribute__((target("avx2"))) static void
stream_rows_avx2(float *const dst[], const float *const src[], unsigned n, uint32_t w)
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

int pc_dm_stream_rows(float *const dst[], const float *const src[], unsigned n, uint32_t w,
                      pc_cpu_level level)
{
#ifdef PC_CPU_X86
	if (level >= PC_CPU_AVX2) {
		stream_rows_avx2(dst, src, n, w);
		return 0;
	}
#endif
	(void)dst;
	(void)src;
	(void)n;
	(void)w;
	(void)level;
	return PC_ENOTSUP;
}

#ifdef PC_CPU_X86
/* One output vector of pc_dm_put_rows' interleaved rows: streamed (nt, d 64-byte aligned) or
 * stored through the cache */
__attribute__((target("avx512f"))) static inline void put_st512(float *d, __m512 v, int nt)
{
	if (nt)
		_mm512_stream_ps(d, v);
	else
		_mm512_storeu_ps(d, v);
}

__attribute__((target("avx2"))) static inline void put_st256(float *d, __m256 v, int nt)
{
	if (nt)
		_mm256_stream_ps(d, v);
	else
		_mm256_storeu_ps(d, v);
}

/* Sixteen pixels of four channels, a[c] + x (c = 0..3), into d, each pixel's four values side
 * by side: a 4 × 4 transpose in each 128-bit lane (lane l of r[m] then holds pixel 4l + m), then
 * lane l of r[0..3] is output vector l (a 4 × 4 transpose of the lanes). */
__attribute__((target("avx512f"))) static inline void
put_transpose4(const float *a0, const float *a1, const float *a2, const float *a3, __m512 r[4])
{
	const __m512 t0 = _mm512_unpacklo_ps(_mm512_loadu_ps(a0), _mm512_loadu_ps(a1)),
	             t1 = _mm512_unpackhi_ps(_mm512_loadu_ps(a0), _mm512_loadu_ps(a1)),
	             t2 = _mm512_unpacklo_ps(_mm512_loadu_ps(a2), _mm512_loadu_ps(a3)),
	             t3 = _mm512_unpackhi_ps(_mm512_loadu_ps(a2), _mm512_loadu_ps(a3));
	const __m512d u0 = _mm512_castps_pd(t0), u1 = _mm512_castps_pd(t1),
	              u2 = _mm512_castps_pd(t2), u3 = _mm512_castps_pd(t3);
	r[0] = _mm512_castpd_ps(_mm512_unpacklo_pd(u0, u2));
	r[1] = _mm512_castpd_ps(_mm512_unpackhi_pd(u0, u2));
	r[2] = _mm512_castpd_ps(_mm512_unpacklo_pd(u1, u3));
	r[3] = _mm512_castpd_ps(_mm512_unpackhi_pd(u1, u3));
}

__attribute__((target("avx512f"))) static void put4_avx512(const float *const s[4], long x,
                                                           float *d, int nt)
{
	__m512 r[4];
	put_transpose4(s[0] + x, s[1] + x, s[2] + x, s[3] + x, r);
	const __m512 p0 = _mm512_shuffle_f32x4(r[0], r[1], 0x44), /* lanes 0, 1 of r0, r1 */
	    p1 = _mm512_shuffle_f32x4(r[2], r[3], 0x44),
	             p2 = _mm512_shuffle_f32x4(r[0], r[1], 0xee), /* lanes 2, 3 */
	    p3 = _mm512_shuffle_f32x4(r[2], r[3], 0xee);
	put_st512(d, _mm512_shuffle_f32x4(p0, p1, 0x88), nt);
	put_st512(d + 16, _mm512_shuffle_f32x4(p0, p1, 0xdd), nt);
	put_st512(d + 32, _mm512_shuffle_f32x4(p2, p3, 0x88), nt);
	put_st512(d + 48, _mm512_shuffle_f32x4(p2, p3, 0xdd), nt);
}

/* Twelve channels: per group of four the in-lane transpose (lane l of r[g][m] holds pixel
 * 4l + m's channels 4g .. 4g + 3); output vector 3l + j takes chunks 4j .. 4j + 3 of lane l's
 * sequence, chunk c from r[c % 3][c / 3], with three lane shuffles ((l) * 0x55: lane l four
 * times). */
#define PUT12_LANE(l)                                                                              \
	do {                                                                                       \
		for (int j = 0; j < 3; j++) {                                                      \
			const int c = 4 * j;                                                       \
			const __m512 P = _mm512_shuffle_f32x4(                                     \
			    r[c % 3][c / 3], r[(c + 1) % 3][(c + 1) / 3], (l)*0x55);               \
			const __m512 Q = _mm512_shuffle_f32x4(                                     \
			    r[(c + 2) % 3][(c + 2) / 3], r[(c + 3) % 3][(c + 3) / 3], (l)*0x55);   \
			put_st512(d + 16 * (3 * (l) + j), _mm512_shuffle_f32x4(P, Q, 0x88), nt);   \
		}                                                                                  \
	} while (0)
__attribute__((target("avx512f"))) static void put12_avx512(const float *const s[12], long x,
                                                            float *d, int nt)
{
	__m512 r[3][4];
	for (int g = 0; g < 3; g++)
		put_transpose4(s[4 * g] + x, s[4 * g + 1] + x, s[4 * g + 2] + x, s[4 * g + 3] + x,
		               r[g]);
	PUT12_LANE(0);
	PUT12_LANE(1);
	PUT12_LANE(2);
	PUT12_LANE(3);
}
#undef PUT12_LANE

/* The same at AVX2, eight pixels: the in-lane transposes (lane l of r[m] holds pixel 4l + m),
 * then each output vector is two 16-byte chunks, each from lane l of one of them
 * (_mm256_permute2f128_ps: l for the first operand, 2 + l for the second) */
__attribute__((target("avx2"))) static inline void
put_transpose4_avx2(const float *a0, const float *a1, const float *a2, const float *a3, __m256 r[4])
{
	const __m256 t0 = _mm256_unpacklo_ps(_mm256_loadu_ps(a0), _mm256_loadu_ps(a1)),
	             t1 = _mm256_unpackhi_ps(_mm256_loadu_ps(a0), _mm256_loadu_ps(a1)),
	             t2 = _mm256_unpacklo_ps(_mm256_loadu_ps(a2), _mm256_loadu_ps(a3)),
	             t3 = _mm256_unpackhi_ps(_mm256_loadu_ps(a2), _mm256_loadu_ps(a3));
	const __m256d u0 = _mm256_castps_pd(t0), u1 = _mm256_castps_pd(t1),
	              u2 = _mm256_castps_pd(t2), u3 = _mm256_castps_pd(t3);
	r[0] = _mm256_castpd_ps(_mm256_unpacklo_pd(u0, u2));
	r[1] = _mm256_castpd_ps(_mm256_unpackhi_pd(u0, u2));
	r[2] = _mm256_castpd_ps(_mm256_unpacklo_pd(u1, u3));
	r[3] = _mm256_castpd_ps(_mm256_unpackhi_pd(u1, u3));
}

__attribute__((target("avx2"))) static void put4_avx2(const float *const s[4], long x, float *d,
                                                      int nt)
{
	__m256 r[4];
	put_transpose4_avx2(s[0] + x, s[1] + x, s[2] + x, s[3] + x, r);
	/* pixels 0, 1 | 2, 3 | 4, 5 | 6, 7 */
	put_st256(d, _mm256_permute2f128_ps(r[0], r[1], 0x20), nt);
	put_st256(d + 8, _mm256_permute2f128_ps(r[2], r[3], 0x20), nt);
	put_st256(d + 16, _mm256_permute2f128_ps(r[0], r[1], 0x31), nt);
	put_st256(d + 24, _mm256_permute2f128_ps(r[2], r[3], 0x31), nt);
}

/* output vector k of twelve channels: chunks 2k and 2k + 1, chunk c from r[c % 3][(c / 3) % 4],
 * lane c / 12 */
#define PUT12_AVX2(k)                                                                              \
	put_st256(d + 8 * (k),                                                                     \
	          _mm256_permute2f128_ps(r[(2 * (k)) % 3][(2 * (k) / 3) % 4],                      \
	                                 r[(2 * (k) + 1) % 3][((2 * (k) + 1) / 3) % 4],            \
	                                 (2 * (k) / 12) | (2 + (2 * (k) + 1) / 12) << 4),          \
	          nt)
__attribute__((target("avx2"))) static void put12_avx2(const float *const s[12], long x, float *d,
                                                       int nt)
{
	__m256 r[3][4];
	for (int g = 0; g < 3; g++)
		put_transpose4_avx2(s[4 * g] + x, s[4 * g + 1] + x, s[4 * g + 2] + x,
		                    s[4 * g + 3] + x, r[g]);
	PUT12_AVX2(0);
	PUT12_AVX2(1);
	PUT12_AVX2(2);
	PUT12_AVX2(3);
	PUT12_AVX2(4);
	PUT12_AVX2(5);
	PUT12_AVX2(6);
	PUT12_AVX2(7);
	PUT12_AVX2(8);
	PUT12_AVX2(9);
	PUT12_AVX2(10);
	PUT12_AVX2(11);
}
#undef PUT12_AVX2
#endif

void pc_dm_put_rows(const pc_fplane *out, unsigned n, uint32_t y, const float *const src[],
                    uint32_t x0, uint32_t w, pc_cpu_level level, int nt)
{
	if (!planes_interleaved(out, n)) {
		for (unsigned c = 0; c < n; c++) {
			const pc_fplane *p = &out[c];
			float *d =
			    p->data + (size_t)y * p->row_stride + (size_t)x0 * p->pixel_stride;
			if (p->pixel_stride == 1)
				memcpy(d, src[c], (size_t)(w - x0) * sizeof *d);
			else
				for (uint32_t x = 0; x < w - x0; x++)
					d[(size_t)x * p->pixel_stride] = src[c][x];
		}
		return;
	}
	float *d = out[0].data + (size_t)y * out[0].row_stride + (size_t)x0 * n;
	uint32_t x = 0;
#ifdef PC_CPU_X86
	/* whole vectors fill whole cache lines from an aligned d on */
	nt = nt && !((uintptr_t)d & 63);
	if (level >= PC_CPU_AVX512)
		for (; x + 16 <= w - x0; x += 16) {
			if (n == 4)
				put4_avx512(src, x, d + (size_t)x * 4, nt);
			else
				put12_avx512(src, x, d + (size_t)x * 12, nt);
		}
	else if (level >= PC_CPU_AVX2)
		for (; x + 8 <= w - x0; x += 8) {
			if (n == 4)
				put4_avx2(src, x, d + (size_t)x * 4, nt);
			else
				put12_avx2(src, x, d + (size_t)x * 12, nt);
		}
#else
	(void)level;
	(void)nt;
#endif
	for (; x < w - x0; x++)
		for (unsigned c = 0; c < n; c++)
			d[(size_t)x * n + c] = src[c][x];
}

void pc_dm_sfence(void)
{
#ifdef PC_CPU_X86
	_mm_sfence();
#endif
}
