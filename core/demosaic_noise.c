/* A frame's noise gain for pan-adapt: the definition is in demosaic_noise.h. */
#include "demosaic_noise.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "cpu_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

#ifdef PC_CPU_X86
#include <immintrin.h>
#endif

static void swap_d(double *v, size_t i, size_t j)
{
	double t = v[i];
	v[i] = v[j];
	v[j] = t;
}

/* The element of rank k of v[0..n) (k < n), v reordered: selection (Hoare, "Algorithm 65:
 * Find", CACM 4(7) 1961) around the median of three, with a three-way partition (Dijkstra's
 * Dutch national flag) so that equal values end it; linear time on average. */
static double select_rank(double *v, size_t n, size_t k)
{
	size_t lo = 0, hi = n; /* the rank-k element lies in v[lo..hi) */
	while (hi - lo > 1) {
		double a = v[lo], b = v[lo + (hi - lo) / 2], c = v[hi - 1];
		double piv = a < b ? (b < c ? b : (a < c ? c : a)) : (a < c ? a : (b < c ? c : b));
		/* [lo, lt) < piv, [lt, i) == piv, [gt, hi) > piv */
		size_t lt = lo, i = lo, gt = hi;
		while (i < gt) {
			if (v[i] < piv)
				swap_d(v, lt++, i++);
			else if (v[i] > piv)
				swap_d(v, i, --gt);
			else
				i++;
		}
		if (k < lt)
			hi = lt;
		else if (k >= gt)
			lo = gt;
		else
			return piv;
	}
	return v[lo];
}

/* The element of rank k of the n values t[0..n) (k < n), t reordered. t(p) ≥ +0 and finite
 * (a square over a positive floor), so the values order as their IEEE-754 bit patterns do as
 * unsigned integers: a most-significant-digit radix selection (11-bit digits: a histogram, the
 * digit's bucket that holds rank k, the others dropped) narrows the candidates without a
 * data-dependent branch per comparison, select_rank finishing the last few. The same element
 * as select_rank's on the whole array (the rank-k value is unique). Values outside that range
 * (a zero floor) go to select_rank alone. */
static double select_median(double *t, size_t n, size_t k)
{
	int ok = 1;
	for (size_t i = 0; i < n; i++)
		ok &= t[i] >= 0 && t[i] <= DBL_MAX && !signbit(t[i]);
	if (!ok)
		return select_rank(t, n, k);
	uint32_t hist[1 << 11];
	for (int shift = 53; n > 64 && shift >= 0; shift -= 11) {
		memset(hist, 0, sizeof hist);
		for (size_t i = 0; i < n; i++) {
			uint64_t b;
			memcpy(&b, &t[i], sizeof b);
			hist[(b >> shift) & 2047]++;
		}
		uint64_t d = 0;
		while (k >= hist[d])
			k -= hist[d++];
		size_t m = 0;
		for (size_t i = 0; i < n; i++) {
			uint64_t b;
			memcpy(&b, &t[i], sizeof b);
			t[m] = t[i];
			m += ((b >> shift) & 2047) == d;
		}
		n = m;
	}
	return select_rank(t, n, k);
}

/* The grid of pc_dm_noise_gain (demosaic_noise.h): start P, stride s, nx × ny samples; 0 when
 * the frame has no interior sample */
/* every s-th of iw × ih points in each direction, s the smallest odd stride leaving at most
 * PC_DM_NG_POINTS: nx × ny of them */
static size_t grid_stride(uint32_t iw, uint32_t ih, uint32_t *s, size_t *nx, size_t *ny)
{
	*s = 1;
	while ((size_t)((iw + *s - 1) / *s) * ((ih + *s - 1) / *s) > PC_DM_NG_POINTS)
		*s += 2;
	*nx = (iw + *s - 1) / *s;
	*ny = (ih + *s - 1) / *s;
	return *nx * *ny;
}

static size_t grid(uint32_t w, uint32_t h, uint32_t p, uint32_t *s, size_t *nx, size_t *ny)
{
	if (w <= 2 * p || h <= 2 * p)
		return 0;
	return grid_stride(w - 2 * p, h - 2 * p, s, nx, ny);
}

/* max(a, 0) for the finite values of a raw (fmax's value but for the sign of a zero, which the
 * positive floor added to it makes irrelevant), inline: libm's fmax is a call per use */
static inline double pos0(double a)
{
	return a > 0 ? a : 0;
}

/* t(p) of one grid sample from its value c and its four same-channel neighbours at ±P (west,
 * east, north, south, summed in that order): the one expression every grid walker uses */
static inline double ng_value(double c, double we, double ea, double no, double so, double floor)
{
	double nb = (we + ea + no + so) / 4;
	double r = c - nb;
	return r * r / (pos0(nb) + floor);
}

/* The grid's rows [r0, r1) into t (row r at t + r·nx): through get (pc_dm_noise_gain), or, when
 * get is NULL, read straight from in's rows as (double)pc_dm_sample − black_d, the value get_in
 * would return (pc_dm_noise_gain_in) */
typedef struct ng_job {
	pc_dm_sample_fn get;
	const void *ctx;
	const pc_dm_input *in;
	uint32_t w, p, s;
	size_t nx;
	double floor;
	double *t;
	unsigned ox, oy;   /* the block grid's origin */
	double sign[2][2]; /* +1 on the 0° and 90° samples of a block, −1 on 45° and 135° */
	uint32_t sb;    /* the block grid's stride, nbx blocks a row, its values after t's n[0] */
	size_t nbx, ny; /* ny: the sample grid's rows */
	size_t n[2];    /* the two grids' numbers of values */
	double med[2];  /* their medians */
	int avx512;     /* 16-bit raws: the grid rows eight points at a time (ng_u16_x8) */
} ng_job;

/* Each grid row also prefetches, point by point, the next grid row's three rows (the rows are
 * far apart, and the frame is read from memory here for the first time: docs/demosaicking.md,
 * Round 28). FAST may take the row's first points (advancing x and t) before the loop does the
 * rest: ng_u16_x8 for 16-bit raws at AVX-512. */
#define NG_ROWS(T, FAST)                                                                           \
	do {                                                                                       \
		const T *rn = (const T *)(const void *)(in->data + (size_t)(y - p) * in->stride),  \
		        *rc = (const T *)(const void *)(in->data + (size_t)y * in->stride),        \
		        *rs = (const T *)(const void *)(in->data + (size_t)(y + p) * in->stride);  \
		const size_t nx = y + s + p < in->height ? (size_t)s * in->stride : 0;             \
		uint32_t x = p;                                                                    \
		FAST;                                                                              \
		for (; x < w - p; x += s) {                                                        \
			__builtin_prefetch((const uint8_t *)(rn + x) + nx);                        \
			__builtin_prefetch((const uint8_t *)(rc + x) + nx);                        \
			__builtin_prefetch((const uint8_t *)(rs + x) + nx);                        \
			*t++ = ng_value((double)(float)rc[x] - bl, (double)(float)rc[x - p] - bl,  \
			                (double)(float)rc[x + p] - bl, (double)(float)rn[x] - bl,  \
			                (double)(float)rs[x] - bl, floor);                         \
		}                                                                                  \
	} while (0)

#ifdef PC_CPU_X86
/* Eight 16-bit samples at x + k·s (k = 0..7) of row r, as doubles: each the 32-bit word at its
 * address (the sample and the one after it, which the callers keep inside the frame: see
 * ng_u16_x8 and nb_u16_x8) masked to its 16 bits */
__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw"))) static inline __m512d
ng_gather8(const uint16_t *r, __m256i idx)
{
	const __m256i v = _mm256_i32gather_epi32((const int *)(const void *)r, idx, 2);
	return _mm512_cvtepi32_pd(_mm256_and_si256(v, _mm256_set1_epi32(0xffff)));
}

/* NG_ROWS's FAST for a 16-bit raw (its rows rn, rc, rs and prefetch offset nx): the row's
 * points from x = p eight at a time while eight remain, ng_value's operations in its order, in
 * double, so the same values bit for bit, into *t (advanced); returns the first point left to
 * NG_ROWS's loop. The words gathered reach one sample past rc[x + p] (x + p ≤ w − 1: rc[w] lies
 * in row y + 1, and y + p < h) and past rn[x], rs[x] (x ≤ w − p − 1 < w − 1). */
__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw"))) static uint32_t
ng_u16_x8(const uint16_t *rn, const uint16_t *rc, const uint16_t *rs, size_t nx, uint32_t p,
          uint32_t s, uint32_t w, double bl, double floor, double **tp)
{
	const __m512d vb = _mm512_set1_pd(bl), vf = _mm512_set1_pd(floor), q = _mm512_set1_pd(0.25),
	              z = _mm512_setzero_pd();
	const __m256i step = _mm256_mullo_epi32(_mm256_set1_epi32((int)s),
	                                        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
	const __m256i vp = _mm256_set1_epi32((int)p);
	double *t = *tp;
	uint32_t x = p;
	for (; x + 7 * s < w - p; x += 8 * s) {
		for (uint32_t k = 0; k < 8 * s * 2; k += 64) {
			_mm_prefetch((const char *)(rn + x) + nx + k, _MM_HINT_T0);
			_mm_prefetch((const char *)(rc + x) + nx + k, _MM_HINT_T0);
			_mm_prefetch((const char *)(rs + x) + nx + k, _MM_HINT_T0);
		}
		const __m256i ix = _mm256_add_epi32(_mm256_set1_epi32((int)x), step);
		const __m512d c = _mm512_sub_pd(ng_gather8(rc, ix), vb),
		              we = _mm512_sub_pd(ng_gather8(rc, _mm256_sub_epi32(ix, vp)), vb),
		              ea = _mm512_sub_pd(ng_gather8(rc, _mm256_add_epi32(ix, vp)), vb),
		              no = _mm512_sub_pd(ng_gather8(rn, ix), vb),
		              so = _mm512_sub_pd(ng_gather8(rs, ix), vb);
		const __m512d nb =
		    _mm512_mul_pd(_mm512_add_pd(_mm512_add_pd(_mm512_add_pd(we, ea), no), so), q);
		const __m512d r = _mm512_sub_pd(c, nb);
		_mm512_storeu_pd(
		    t, _mm512_div_pd(_mm512_mul_pd(r, r), _mm512_add_pd(_mm512_max_pd(nb, z), vf)));
		t += 8;
	}
	*tp = t;
	return x;
}
#define NG_U16_FAST                                                                                \
	if (j->avx512)                                                                             \
	x = ng_u16_x8(rn, rc, rs, nx, p, s, w, bl, floor, &t)
#else
#define NG_U16_FAST (void)0
#endif

static void ng_rows(void *ctx, uint32_t r0, uint32_t r1)
{
	const ng_job *j = ctx;
	const pc_dm_input *in = j->in;
	const uint32_t p = j->p, s = j->s, w = j->w;
	const double floor = j->floor;
	for (uint32_t gy = r0; gy < r1; gy++) {
		const uint32_t y = p + gy * s;
		double *t = j->t + (size_t)gy * j->nx;
		if (j->get) {
			const pc_dm_sample_fn get = j->get;
			const void *c = j->ctx;
			for (uint32_t x = p; x < w - p; x += s)
				*t++ = ng_value(get(c, x, y), get(c, x - p, y), get(c, x + p, y),
				                get(c, x, y - p), get(c, x, y + p), floor);
			continue;
		}
		const double bl = in->black_d;
		switch (in->type) {
		case PC_DMT_U8:
			NG_ROWS(uint8_t, (void)0);
			break;
		case PC_DMT_U16:
			NG_ROWS(uint16_t, NG_U16_FAST);
			break;
		default:
			NG_ROWS(float, (void)0);
		}
	}
}
#undef NG_ROWS
#undef NG_U16_FAST

/* The block estimate's grid (demosaic_noise.h): 2×2 blocks from (ox, oy), every s-th block in
 * each direction (s odd), nx × ny of them; 0 when the frame holds no whole block */
static size_t bgrid(uint32_t w, uint32_t h, unsigned ox, unsigned oy, uint32_t *s, size_t *nx,
                    size_t *ny)
{
	if (w < ox + 2 || h < oy + 2)
		return 0;
	return grid_stride((w - ox) / 2, (h - oy) / 2, s, nx, ny);
}

/* u(b) of one block from its samples in raster order (a b / c d) and the signs of j: the one
 * expression both block walkers use */
static inline double nb_value(const ng_job *j, double a, double b, double c, double d)
{
	double r = j->sign[0][0] * a + j->sign[0][1] * b + j->sign[1][0] * c + j->sign[1][1] * d;
	double l = 4 * j->floor + pos0(a) + pos0(b) + pos0(c) + pos0(d);
	return r * r / l;
}

/* (prefetching the next block row's two rows as NG_ROWS does; FAST as NG_ROWS's, advancing
 * gx, x and t: nb_u16_x8) */
#define NB_ROWS(T, FAST)                                                                           \
	do {                                                                                       \
		const T *r0 = (const T *)(const void *)(in->data + (size_t)y * in->stride),        \
		        *r1 = (const T *)(const void *)(in->data + (size_t)(y + 1) * in->stride);  \
		const size_t nx = y + s2 + 1 < in->height ? (size_t)s2 * in->stride : 0;           \
		size_t gx = 0;                                                                     \
		FAST;                                                                              \
		for (; gx < j->nbx; gx++, x += s2) {                                               \
			__builtin_prefetch((const uint8_t *)(r0 + x) + nx);                        \
			__builtin_prefetch((const uint8_t *)(r1 + x) + nx);                        \
			*t++ =                                                                     \
			    nb_value(j, (double)(float)r0[x] - bl, (double)(float)r0[x + 1] - bl,  \
			             (double)(float)r1[x] - bl, (double)(float)r1[x + 1] - bl);    \
		}                                                                                  \
	} while (0)

#ifdef PC_CPU_X86
/* NB_ROWS's FAST for a 16-bit raw (its rows r0, r1 and prefetch offset nx): the row's blocks
 * eight at a time while eight remain, from the column *xp, each block row's two samples one
 * 32-bit word (the block's columns x and x + 1), split; nb_value's operations in its order, in
 * double, so the same values bit for bit, into *tp; *xp and *tp advanced, returns the blocks
 * done. */
__attribute__((target("avx512f,avx512vl,avx512dq,avx512bw"))) static size_t
nb_u16_x8(const ng_job *j, const uint16_t *r0, const uint16_t *r1, size_t nx, double bl,
          uint32_t *xp, double **tp)
{
	const uint32_t s2 = 2 * j->sb;
	const __m512d vb = _mm512_set1_pd(bl), z = _mm512_setzero_pd(),
	              l4 = _mm512_set1_pd(4 * j->floor), s00 = _mm512_set1_pd(j->sign[0][0]),
	              s01 = _mm512_set1_pd(j->sign[0][1]), s10 = _mm512_set1_pd(j->sign[1][0]),
	              s11 = _mm512_set1_pd(j->sign[1][1]);
	const __m256i step = _mm256_mullo_epi32(_mm256_set1_epi32((int)s2),
	                                        _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)),
	              lo = _mm256_set1_epi32(0xffff);
	uint32_t x = *xp;
	double *t = *tp;
	size_t gx = 0;
	for (; gx + 8 <= j->nbx; gx += 8, x += 8 * s2) {
		for (uint32_t k = 0; k < 8 * s2 * 2; k += 64) {
			_mm_prefetch((const char *)(r0 + x) + nx + k, _MM_HINT_T0);
			_mm_prefetch((const char *)(r1 + x) + nx + k, _MM_HINT_T0);
		}
		const __m256i ix = _mm256_add_epi32(_mm256_set1_epi32((int)x), step);
		const __m256i w0 = _mm256_i32gather_epi32((const int *)(const void *)r0, ix, 2),
		              w1 = _mm256_i32gather_epi32((const int *)(const void *)r1, ix, 2);
		const __m512d a = _mm512_sub_pd(_mm512_cvtepi32_pd(_mm256_and_si256(w0, lo)), vb),
		              b = _mm512_sub_pd(_mm512_cvtepi32_pd(_mm256_srli_epi32(w0, 16)), vb),
		              c = _mm512_sub_pd(_mm512_cvtepi32_pd(_mm256_and_si256(w1, lo)), vb),
		              d = _mm512_sub_pd(_mm512_cvtepi32_pd(_mm256_srli_epi32(w1, 16)), vb);
		const __m512d r = _mm512_add_pd(
		    _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(s00, a), _mm512_mul_pd(s01, b)),
		                  _mm512_mul_pd(s10, c)),
		    _mm512_mul_pd(s11, d));
		const __m512d l = _mm512_add_pd(
		    _mm512_add_pd(
		        _mm512_add_pd(_mm512_add_pd(l4, _mm512_max_pd(a, z)), _mm512_max_pd(b, z)),
		        _mm512_max_pd(c, z)),
		    _mm512_max_pd(d, z));
		_mm512_storeu_pd(t, _mm512_div_pd(_mm512_mul_pd(r, r), l));
		t += 8;
	}
	*xp = x;
	*tp = t;
	return gx;
}
#define NB_U16_FAST                                                                                \
	if (j->avx512)                                                                             \
	gx = nb_u16_x8(j, r0, r1, nx, bl, &x, &t)
#else
#define NB_U16_FAST (void)0
#endif

/* The block grid's rows [r0, r1) into t (row r at t + r·nx): u(b) of each block, through get
 * or straight from in's rows as ng_rows reads them */
static void nb_rows(void *ctx, uint32_t g0, uint32_t g1)
{
	const ng_job *j = ctx;
	const pc_dm_input *in = j->in;
	const uint32_t s2 = 2 * j->sb;
	for (uint32_t gy = g0; gy < g1; gy++) {
		const uint32_t y = j->oy + gy * s2;
		uint32_t x = j->ox;
		double *t = j->t + j->n[0] + (size_t)gy * j->nbx;
		if (j->get) {
			const pc_dm_sample_fn get = j->get;
			const void *c = j->ctx;
			for (size_t gx = 0; gx < j->nbx; gx++, x += s2)
				*t++ = nb_value(j, get(c, x, y), get(c, x + 1, y), get(c, x, y + 1),
				                get(c, x + 1, y + 1));
			continue;
		}
		const double bl = in->black_d;
		switch (in->type) {
		case PC_DMT_U8:
			NB_ROWS(uint8_t, (void)0);
			break;
		case PC_DMT_U16:
			NB_ROWS(uint16_t, NB_U16_FAST);
			break;
		default:
			NB_ROWS(float, (void)0);
		}
	}
}
#undef NB_ROWS
#undef NB_U16_FAST

/* Rows [r0, r1) of both grids, the sample grid's ny rows first, then the block grid's: one
 * parallel pass for the two */
static void ng_both_rows(void *ctx, uint32_t r0, uint32_t r1)
{
	const ng_job *j = ctx;
	const uint32_t ny = (uint32_t)j->ny;
	if (r0 < ny)
		ng_rows(ctx, r0, r1 < ny ? r1 : ny);
	if (r1 > ny)
		nb_rows(ctx, (r0 > ny ? r0 : ny) - ny, r1 - ny);
}

/* The medians of the two grids' values, one a band (each thread selects in its own part of t) */
static void ng_medians(void *ctx, uint32_t k0, uint32_t k1)
{
	ng_job *j = ctx;
	for (uint32_t k = k0; k < k1; k++)
		j->med[k] = select_median(j->t + (k ? j->n[0] : 0), j->n[k], j->n[k] / 2);
}

/* g of the frame of j (its w and sampler set) on threads threads: each grid's values (one pass)
 * and their medians (one a thread), the smaller of the two estimates */
static int ng_gain(ng_job *j, uint32_t h, const pc_mosaic *m, double fs, int threads, double *g)
{
	j->p = m->period;
	j->s = 1;
	const size_t n = grid(j->w, h, j->p, &j->s, &j->nx, &j->ny);
	if (!n) {
		*g = 0;
		return 0;
	}
	/* the block grid */
	unsigned ox = 0, oy = 0;
	if (m->period == 4)
		(void)pc_mosaic_color_origin(m, &ox, &oy);
	j->ox = ox;
	j->oy = oy;
	for (unsigned dy = 0; dy < 2; dy++)
		for (unsigned dx = 0; dx < 2; dx++)
			j->sign[dy][dx] = (pc_mosaic_channel(m, ox + dx, oy + dy) & 1) ? -1 : 1;
	size_t nby = 0;
	j->sb = 1;
	const size_t nb = bgrid(j->w, h, ox, oy, &j->sb, &j->nbx, &nby);
	j->t = malloc(sizeof(double) * (n + nb));
	if (!j->t)
		return pc_error(PC_ENOMEM, "noise gain: %zu values", n + nb);
	j->n[0] = n;
	j->n[1] = nb;
	j->floor = PC_DM_NG_FLOOR * fs;
	pc_parallel_rows((uint32_t)(j->ny + nby), 0, threads, ng_both_rows, j);
	pc_parallel_rows(nb ? 2 : 1, 1, threads, ng_medians, j);
	free(j->t);
	const double gp = j->med[0] / (1.25 * PC_DM_NG_CHI1);
	*g = nb ? fmin(gp, j->med[1] / PC_DM_NG_CHI1) : gp;
	return 0;
}

int pc_dm_noise_gain(pc_dm_sample_fn get, const void *ctx, uint32_t w, uint32_t h,
                     const pc_mosaic *m, double fs, double *g)
{
	ng_job j = {.get = get, .ctx = ctx, .w = w};
	return ng_gain(&j, h, m, fs, 1, g);
}

typedef struct dimg {
	const double *img;
	uint32_t w;
} dimg;

static double get_d(const void *ctx, uint32_t x, uint32_t y)
{
	const dimg *d = ctx;
	return d->img[(size_t)y * d->w + x];
}

int pc_dm_noise_gain_d(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       double *g)
{
	dimg d = {img, w};
	return pc_dm_noise_gain(get_d, &d, w, h, m, fs, g);
}

int pc_dm_noise_gain_in_mt(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                           double *g)
{
	if (in->dark || in->gain_inv)
		return pc_error(PC_EINVAL, "noise gain: an input with dark or gain maps (correct a "
		                           "copy first)");
	ng_job j = {.in = in, .w = in->width, .avx512 = pc_cpu_active() >= PC_CPU_AVX512};
	return ng_gain(&j, in->height, m, fs, threads, g);
}

int pc_dm_noise_gain_in(const pc_dm_input *in, const pc_mosaic *m, double fs, double *g)
{
	return pc_dm_noise_gain_in_mt(in, m, fs, 1, g);
}

/* ---- the photon-transfer line (demosaic_noise.h, pc_dm_noise_ptc) ---- */

#define PTC_CELLS   4096
#define PTC_CHI2_99 9.2103403719761836 /* χ²₂'s 99 % point: −2·ln 0.01 */
#define PTC_TRIM_C  0.97333973         /* E[x² | |x| ≤ 3] for x ~ N(0, 1) */

typedef struct ptc_block {
	double mu, d2, g2;
	uint32_t cell;
} ptc_block;

/* The number of blocks of phase o along an axis of length n with origins o + 2P·s·i and
 * o + 2P·s·i + P < n */
static size_t ptc_count(uint32_t n, uint32_t o, uint32_t p, size_t s)
{
	return n > o + p ? (size_t)(n - o - p - 1) / (2 * (size_t)p * s) + 1 : 0;
}

/* One group's variance s² (demosaic_noise.h) from its blocks' d² and h² + v², d2[0..n) and
 * g2[0..n); scratch holds n doubles. *used: the blocks of the last selection (n when s² comes
 * from the median alone). */
static double ptc_group(const double *d2, const double *g2, size_t n, double *scratch, size_t *used)
{
	memcpy(scratch, d2, sizeof(double) * n);
	double s2 = select_rank(scratch, n, n / 2) / PC_DM_NG_CHI1;
	*used = n;
	for (int it = 0; it < 8 && s2 > 0; it++) {
		/* branch-free (the selection is near half of the blocks: branches would
		 * mispredict), the same sum in the same order */
		const double tg = PTC_CHI2_99 * s2, td = 9 * s2;
		double sum = 0;
		size_t k = 0;
		for (size_t i = 0; i < n; i++) {
			const bool in = (g2[i] <= tg) & (d2[i] <= td);
			sum += in ? d2[i] : 0;
			k += in;
		}
		if (k < 16)
			break;
		const double s2n = sum / (double)k / PTC_TRIM_C;
		*used = k;
		const bool done = fabs(s2n - s2) <= 1e-3 * s2;
		s2 = s2n;
		if (done)
			break;
	}
	return s2;
}

/* The weighted fit of a·μ + b to the groups (demosaic_noise.h) */
static void ptc_line(const double *mu, const double *s2, const double *n, int k, double *a,
                     double *b)
{
	double smax = 0;
	for (int i = 0; i < k; i++)
		smax = s2[i] > smax ? s2[i] : smax;
	*a = *b = 0;
	if (k < 2 || !(smax > 0))
		return;
	double sw = 0, sx = 0, sxx = 0, sy = 0, sxy = 0, w[PC_DM_PTC_BINS];
	for (int i = 0; i < k; i++) {
		const double e = s2[i] + 1e-6 * smax;
		w[i] = n[i] / (e * e);
		sw += w[i];
		sx += w[i] * mu[i];
		sxx += w[i] * mu[i] * mu[i];
		sy += w[i] * s2[i];
		sxy += w[i] * mu[i] * s2[i];
	}
	double cand[3][2] = {
	    {-1, -1}, {sxx > 0 ? fmax(sxy / sxx, 0) : 0, 0}, {0, fmax(sy / sw, 0)}};
	const double det = sw * sxx - sx * sx;
	if (det > 0) {
		cand[0][0] = (sw * sxy - sx * sy) / det;
		cand[0][1] = (sxx * sy - sx * sxy) / det;
	}
	double best = INFINITY;
	for (int c = 0; c < 3; c++) {
		if (!(cand[c][0] >= 0 && cand[c][1] >= 0))
			continue;
		double sse = 0;
		for (int i = 0; i < k; i++) {
			const double r = cand[c][0] * mu[i] + cand[c][1] - s2[i];
			sse += w[i] * r * r;
		}
		if (sse < best) {
			best = sse;
			*a = cand[c][0];
			*b = cand[c][1];
		}
	}
	/* a slope the groups do not determine (not above twice its standard error, the weights
	 * being n/s⁴ against a variance estimate's inverse variance n/(2·s⁴): the levels span too
	 * little of the line, or texture raises every group alike): the line through the origin,
	 * the one-parameter model σ² = a·L that ratio-nr's shrinkage uses, fitted to the same
	 * groups */
	const double se = det > 0 ? sqrt(2 * sw / det) : INFINITY;
	if (*b > 0 && !(*a > 2 * se))
		*a = cand[1][0];
}

int pc_dm_noise_ptc(pc_dm_row_fn row, const void *ctx, uint32_t w, uint32_t h, const pc_mosaic *m,
                    double fs, double lo, double *a, double *b)
{
	const uint32_t p = m->period;
	double b0;
	if (!b)
		b = &b0; /* the offset is fitted all the same: it keeps a unbiased */
	*a = *b = 0;
	/* the walk: row groups y0 = 2P·sy·k (rows y0 .. y0 + 2P − 1 hold one block row of every
	 * phase), in each every sx-th block of every phase along the row */
	size_t sx = 3, per_group;
	for (;; sx += 2) {
		per_group = 0;
		for (uint32_t ox = 0; ox < p; ox++)
			per_group += p * ptc_count(w, ox, p, sx);
		if (per_group <= PC_DM_PTC_BLOCKS / 16)
			break;
	}
	const size_t groups = h / (2 * (size_t)p);
	if (!per_group || !groups)
		return 0;
	const size_t sy = (groups * per_group + PC_DM_PTC_BLOCKS - 1) / PC_DM_PTC_BLOCKS;
	const size_t total = ((groups + sy - 1) / sy) * per_group;
	/* one block from the scratch pool (demosaic_common.c): a fresh allocation of this size
	 * would fault in its pages on every call */
	void *mem = pc_dm_alloc((sizeof(ptc_block) + 3 * sizeof(double)) * total +
	                        sizeof(double) * 2 * p * (size_t)w);
	if (!mem)
		return pc_error(PC_ENOMEM, "noise model: %zu blocks", total);
	ptc_block *blk = mem;
	/* the groups' d² and h² + v², each group's contiguous (a counting sort by group) */
	double *gd2 = (double *)(void *)(blk + total), *gg2 = gd2 + total, *scratch = gg2 + total,
	       *rows = scratch + total;
	size_t n = 0;
	uint32_t hist[PTC_CELLS] = {0};
	for (size_t gy = 0; gy < groups; gy += sy) {
		const uint32_t y0 = (uint32_t)(2 * p * gy);
		for (uint32_t r = 0; r < 2 * p; r++)
			row(ctx, y0 + r, rows + (size_t)r * w);
		for (uint32_t oy = 0; oy < p; oy++) {
			const double *r0 = rows + (size_t)oy * w, *r1 = rows + (size_t)(oy + p) * w;
			for (uint32_t ox = 0; ox < p; ox++)
				for (size_t x = ox; x + p < w; x += 2 * p * sx) {
					const double A = r0[x], B = r0[x + p], C = r1[x],
					             D = r1[x + p];
					if (!(A > lo && B > lo && C > lo && D > lo && A < fs &&
					      B < fs && C < fs && D < fs))
						continue;
					ptc_block *q = &blk[n++];
					const double d = (A - B - C + D) / 2,
					             gh = (A - B + C - D) / 2,
					             gv = (A + B - C - D) / 2;
					q->mu = (A + B + C + D) / 4;
					q->d2 = d * d;
					q->g2 = gh * gh + gv * gv;
					const double c = sqrt(pos0(q->mu) / fs) * PTC_CELLS;
					q->cell = c < PTC_CELLS - 1 ? (uint32_t)c : PTC_CELLS - 1;
					hist[q->cell]++;
				}
		}
	}
	/* groups of about n / BINS blocks by cell; the blocks ordered by group (counting sort) */
	int group[PTC_CELLS];
	size_t first[PC_DM_PTC_BINS + 1] = {0}, before = 0;
	for (int c = 0; c < PTC_CELLS; c++) {
		const size_t k = n ? before * PC_DM_PTC_BINS / n : 0;
		group[c] = (int)(k < PC_DM_PTC_BINS ? k : PC_DM_PTC_BINS - 1);
		first[group[c] + 1] += hist[c];
		before += hist[c];
	}
	for (int k = 0; k < PC_DM_PTC_BINS; k++)
		first[k + 1] += first[k];
	size_t fill[PC_DM_PTC_BINS];
	memcpy(fill, first, sizeof fill);
	double musum[PC_DM_PTC_BINS] = {0}, gmu[PC_DM_PTC_BINS], gs2[PC_DM_PTC_BINS],
	       gn[PC_DM_PTC_BINS];
	for (size_t i = 0; i < n; i++) {
		const int g = group[blk[i].cell];
		const size_t at = fill[g]++;
		gd2[at] = blk[i].d2;
		gg2[at] = blk[i].g2;
		musum[g] += blk[i].mu;
	}
	int k = 0;
	for (int g = 0; g < PC_DM_PTC_BINS; g++) {
		const size_t cnt = first[g + 1] - first[g];
		if (cnt < 64)
			continue;
		size_t used;
		gs2[k] = ptc_group(gd2 + first[g], gg2 + first[g], cnt, scratch, &used);
		gmu[k] = musum[g] / (double)cnt;
		gn[k] = (double)used;
		k++;
	}
	ptc_line(gmu, gs2, gn, k, a, b);
	/* the fit's rounding residue on a noise-free frame (a few textured groups among exact
	 * zeros) is no noise: below 1e-12 of full scale (a) and of its square (b), 0 */
	if (!(*a >= 1e-12 * fs) || !isfinite(*a)) /* (values near a huge float full scale
	                                           * overflow the squares: no estimate) */
		*a = 0;
	if (!(*b >= 1e-12 * fs * fs) || !isfinite(*b))
		*b = 0;
	pc_dm_free(mem);
	return 0;
}

static void row_d(const void *ctx, uint32_t y, double *dst)
{
	const dimg *d = ctx;
	memcpy(dst, d->img + (size_t)y * d->w, sizeof(double) * d->w);
}

int pc_dm_noise_ptc_d(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      double lo, double *a, double *b)
{
	dimg d = {img, w};
	return pc_dm_noise_ptc(row_d, &d, w, h, m, fs, lo, a, b);
}

/* Row y as (double)pc_dm_sample − black_d: pc_dm_raw_to_double's values */
static void row_in(const void *ctx, uint32_t y, double *dst)
{
	const pc_dm_input *in = ctx;
	const uint8_t *r = in->data + (size_t)y * in->stride;
	const double bl = in->black_d;
	switch (in->type) {
	case PC_DMT_U8:
		for (uint32_t x = 0; x < in->width; x++)
			dst[x] = (double)(float)r[x] - bl;
		break;
	case PC_DMT_U16:
		for (uint32_t x = 0; x < in->width; x++)
			dst[x] = (double)(float)((const uint16_t *)(const void *)r)[x] - bl;
		break;
	default:
		for (uint32_t x = 0; x < in->width; x++)
			dst[x] = (double)((const float *)(const void *)r)[x] - bl;
	}
}

int pc_dm_noise_ptc_in(const pc_dm_input *in, const pc_mosaic *m, double fs, double *a, double *b)
{
	if (in->dark || in->gain_inv)
		return pc_error(PC_EINVAL,
		                "noise model: an input with dark or gain maps (correct a "
		                "copy first)");
	return pc_dm_noise_ptc(row_in, in, in->width, in->height, m, fs, -in->black_d, a, b);
}
