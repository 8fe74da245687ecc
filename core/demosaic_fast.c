/* The one-pass fast float kernels of the demosaicking ladder: bilinear and the super-pixels
 * (demosaic_fast.h), and bilinear into 16-bit planes (pc_demosaic_bilinear_u16). Each streams
 * the raw once in row bands (pc_parallel_rows): input rows are converted to padded float rows
 * (mirrored one pixel beyond each end) in a small ring, and the row kernel of demosaic_kern.inc
 * writes the outputs directly (width-generic vector code: 8-wide baseline, and AVX2 with
 * non-temporal stores for large aligned planes, which AVX-512 hosts run too). */
#include "demosaic_fast.h"

#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/parallel.h"
#include "simd.h"
#ifdef PC_CPU_X86
#include <immintrin.h>
#endif

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_kern.inc"
#include "simd_instance_end.h"

/* no AVX-512 instance: on the AVX-512 host the AVX2 row kernel takes 0.83-0.95 of the 16-lane
 * one's time (ten alternating pairs), 0.69 when the host's memory runs fast, the same outputs
 * (docs/demosaicking.md, Round 44b); an AVX-512 host runs the AVX2 kernel */
#endif

/* ---- bilinear ---- */
typedef struct bil_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	pc_cpu_level level;
	int planar, nt, err;
	int ntil; /* an interleaved output streamed (pc_dm_stream_wanted_il) */
} bil_job;

static void bilinear_band(void *ctx, uint32_t y0, uint32_t y1)
{
	bil_job *j = ctx;
	uint32_t w = j->in->width;
	pc_dm_ring rg;
	float *tmp = NULL;
	if (pc_dm_ring_init(&rg, w) || (!j->planar && !(tmp = pc_dm_alloc(4 * (size_t)w * 4)))) {
		pc_dm_ring_free(&rg);
		j->err = 1;
		return;
	}
	for (uint32_t y = y0; y < y1; y++) {
		const float *a = pc_dm_ring_get(&rg, j->in, (int)y - 1);
		const float *b = pc_dm_ring_get(&rg, j->in, (int)y);
		const float *c = pc_dm_ring_get(&rg, j->in, (int)y + 1);
		unsigned slot[4] = {pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
		                    pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1)};
		float *o[4];
		for (int k = 0; k < 4; k++)
			o[k] = j->planar
			           ? j->out[slot[k]].data + (size_t)y * j->out[slot[k]].row_stride
			           : tmp + (size_t)k * w;
#ifdef PC_CPU_X86
		if (j->level >= PC_CPU_AVX2)
			bilinear_row_avx2(a, b, c, w, o, j->nt);
		else
#endif
			bilinear_row_base(a, b, c, w, o, 0);
		if (!j->planar) {
			const float *src[4];
			for (int k = 0; k < 4; k++)
				src[slot[k]] = o[k];
			pc_dm_put_rows(j->out, 4, y, src, 0, w, j->level, j->ntil);
		}
	}
	if (j->nt || j->ntil)
		pc_dm_sfence();
	pc_dm_free(tmp);
	pc_dm_ring_free(&rg);
}

int pc_dm_bilinear(const pc_dm_call *call, const pc_fplane *out)
{
	const pc_dm_input *in = call->in;
	bil_job j = {in, call->m, out, call->level, 1, 0, 0, 0};
	j.planar = pc_dm_planes_planar(out, 4);
	j.nt = j.planar && pc_dm_stream_wanted(out, 4, in->width, in->height, call->level);
	j.ntil = pc_dm_stream_wanted_il(out, 4, in->width, in->height, call->level);
	pc_parallel_rows(in->height, 0, call->threads, bilinear_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "bilinear: row buffers") : 0;
}

/* ---- super-pixel ---- */
typedef struct sp_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	pc_cpu_level level;
	int half, err;
	int planar; /* every plane has pixel stride 1 */
	int nt;     /* planar planes streamed (pc_dm_stream_wanted) */
	int ntil;   /* an interleaved output streamed (pc_dm_stream_wanted_il) */
} sp_job;

#ifdef PC_CPU_X86
/* A block row's eight full-size output rows streamed, d[c][k] row k of channel c:
 * d[c][k][x] = src[c][x & ~1], each 8 columns the even lanes of src[c] copied into the odd ones
 * (moveldup). Line by line across the eight rows, as the bilinear writes its four (row after
 * row took 1.26-1.54x the bilinear's time, line by line 0.95-1.05x; docs/demosaicking.md, Round
 * 44c); d 64-byte aligned, the last columns short of 16 scalar. */
__attribute__((target("avx2"))) static void sp_stream_rows(float *const d[4][2],
                                                           const float *const src[4], uint32_t w)
{
	for (size_t x = 0; x + 16 <= w; x += 16)
		for (unsigned c = 0; c < 4; c++) {
			__m256 a = _mm256_moveldup_ps(_mm256_loadu_ps(src[c] + x)),
			       b = _mm256_moveldup_ps(_mm256_loadu_ps(src[c] + x + 8));
			_mm256_stream_ps(d[c][0] + x, a);
			_mm256_stream_ps(d[c][0] + x + 8, b);
			_mm256_stream_ps(d[c][1] + x, a);
			_mm256_stream_ps(d[c][1] + x + 8, b);
		}
	for (size_t x = w / 16 * 16; x < w; x++)
		for (unsigned c = 0; c < 4; c++)
			d[c][0][x] = d[c][1][x] = src[c][x & ~(size_t)1];
}
#endif

/* One output row of a channel from its block row's samples src[0], src[2], ...: the half-size
 * row (each sample once) or the full-size one (each twice) */
static void sp_row(float *restrict d, const float *restrict src, uint32_t ow, int half)
{
	/* size_t indices: with 32-bit ones GCC keeps 2·x's wrap-around and loads lane by lane */
	if (half)
		for (size_t x = 0; x < ow; x++)
			d[x] = src[2 * x];
	else
		for (size_t x = 0; x < ow / 2; x++)
			d[2 * x] = d[2 * x + 1] = src[2 * x];
}

/* Each 2x2 block's four samples, per block row: written straight into planar outputs (streamed
 * when large, pc_dm_stream_wanted, like the bilinear's rows), else made in a row buffer per
 * channel and written by pc_dm_put_rows (any strides; an interleaved array pixel by pixel,
 * streamed when large). The full-size output's two rows of a block row are the same row. */
static void superpixel_band(void *ctx, uint32_t y0, uint32_t y1)
{
	sp_job *j = ctx;
	uint32_t w = j->in->width, ow = j->half ? w / 2 : w;
	float *r = pc_dm_alloc(2 * ((size_t)w + 2) * sizeof(float));
	/* a row buffer per channel for outputs that are not planar (pc_dm_put_rows) */
	float *lines = j->planar ? NULL : pc_dm_alloc(4 * ((size_t)w + 16) * sizeof(float));
	if (!r || (!j->planar && !lines)) {
		pc_dm_free(r);
		pc_dm_free(lines);
		j->err = 1;
		return;
	}
	float *r0 = r + 1, *r1 = r + w + 3;
	const uint32_t nrows = j->half ? 1u : 2u;
	/* bands start on even rows (pc_parallel_rows bands are multiples of 8 rows) */
	for (uint32_t by = y0 & ~1u; by < y1; by += 2) {
		pc_dm_row_to_float(j->in, by, r0);
		pc_dm_row_to_float(j->in, by + 1, r1);
		const float *rows[2] = {r0, r1};
		const float *line[4], *src[4];
		float *dst[4][2] = {{NULL}};
		for (unsigned c = 0; c < 4; c++) {
			unsigned dx, dy;
			pc_mosaic_channel_pos(j->m, c, &dx, &dy);
			src[c] = rows[dy] + dx;
			for (uint32_t k = 0; k < nrows; k++)
				dst[c][k] = j->out[c].data + (size_t)(j->half ? by / 2 : by + k) *
				                                 j->out[c].row_stride;
		}
#ifdef PC_CPU_X86
		if (j->nt) { /* full-size planar rows, streamed */
			sp_stream_rows(dst, src, ow);
			continue;
		}
#endif
		for (unsigned c = 0; c < 4; c++) {
			for (uint32_t k = 0; k < nrows && j->planar; k++)
				sp_row(dst[c][k], src[c], ow, j->half);
			if (!j->planar) {
				float *l = lines + (size_t)c * ((size_t)w + 16);
				sp_row(l, src[c], ow, j->half);
				line[c] = l;
			}
		}
		for (uint32_t k = 0; k < nrows && !j->planar; k++)
			pc_dm_put_rows(j->out, 4, j->half ? by / 2 : by + k, line, 0, ow, j->level,
			               j->ntil);
	}
	if (j->nt || j->ntil)
		pc_dm_sfence();
	pc_dm_free(r);
	pc_dm_free(lines);
}

static int superpixel(const pc_dm_call *call, int half, const pc_fplane *out)
{
	uint32_t ow = half ? call->in->width / 2 : call->in->width,
	         oh = half ? call->in->height / 2 : call->in->height;
	sp_job j = {call->in, call->m, out, call->level, half, 0, 1, 0, 0};
	j.planar = pc_dm_planes_planar(out, 4);
	/* streamed: the full-size rows (sp_stream_rows); half-size rows are written as made */
	j.nt = !half && pc_dm_stream_wanted(out, 4, ow, oh, call->level);
	j.ntil = pc_dm_stream_wanted_il(out, 4, ow, oh, call->level);
	pc_parallel_rows(call->in->height, 8, call->threads, superpixel_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "superpixel: row buffers") : 0;
}

int pc_dm_superpixel(const pc_dm_call *call, const pc_fplane *out)
{
	return superpixel(call, 0, out);
}

int pc_dm_superpixel_half(const pc_dm_call *call, const pc_fplane *out)
{
	return superpixel(call, 1, out);
}

/* ---- bilinear into 16-bit planes ---- */
typedef struct b16_job {
	const pc_view *raw;
	const pc_mosaic *m;
	unsigned frac;
	uint16_t *const *out;
	size_t ostride;
	pc_cpu_level level;
} b16_job;

/* One row: S, H, V, D as in bilinear_row, in integers. With q = 2 − frac, a value v·2^frac is
 * (4v) >> q rounded: (4v + (q ? 1 << (q − 1) : 0)) >> q, where 4v is an exact integer. */
static inline __attribute__((always_inline)) void
b16_row(const uint16_t *restrict a, const uint16_t *restrict b, const uint16_t *restrict c, long w,
        unsigned q, uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2,
        uint16_t *restrict o3)
{
	const uint32_t rnd = q ? 1u << (q - 1) : 0;
#define PC_B16_PIXEL(x, xm, xp)                                                                    \
	do {                                                                                       \
		uint32_t S4 = 4u * b[x], H4 = 2u * ((uint32_t)b[xm] + b[xp]);                      \
		uint32_t V4 = 2u * ((uint32_t)a[x] + c[x]);                                        \
		uint32_t D4 = ((uint32_t)a[xm] + a[xp]) + ((uint32_t)c[xm] + c[xp]);               \
		int odd = (int)((x)&1);                                                            \
		o0[x] = (uint16_t)(((odd ? H4 : S4) + rnd) >> q);                                  \
		o1[x] = (uint16_t)(((odd ? S4 : H4) + rnd) >> q);                                  \
		o2[x] = (uint16_t)(((odd ? D4 : V4) + rnd) >> q);                                  \
		o3[x] = (uint16_t)(((odd ? V4 : D4) + rnd) >> q);                                  \
	} while (0)
	PC_B16_PIXEL(0, 1, 1);
	PC_SIMD
	for (long x = 1; x < w - 1; x++)
		PC_B16_PIXEL(x, x - 1, x + 1);
	PC_B16_PIXEL(w - 1, w - 2, w - 2);
#undef PC_B16_PIXEL
}

#define PC_B16_INSTANCE(name, attr)                                                                \
	static attr void name(const uint16_t *restrict a, const uint16_t *restrict b,              \
	                      const uint16_t *restrict c, long w, unsigned q,                      \
	                      uint16_t *restrict o0, uint16_t *restrict o1, uint16_t *restrict o2, \
	                      uint16_t *restrict o3)                                               \
	{                                                                                          \
		b16_row(a, b, c, w, q, o0, o1, o2, o3);                                            \
	}
PC_B16_INSTANCE(b16_row_base, )
#ifdef PC_CPU_X86
PC_B16_INSTANCE(b16_row_avx2, __attribute__((target("avx2,fma"))))
PC_B16_INSTANCE(b16_row_avx512, __attribute__((target(PC_AVX512_TARGET))))
#endif
#undef PC_B16_INSTANCE

static void b16_band(void *ctx, uint32_t y0, uint32_t y1)
{
	b16_job *j = ctx;
	const pc_view *r = j->raw;
	for (uint32_t y = y0; y < y1; y++) {
		const uint16_t *a =
		    PC_ROW(r, const uint16_t, (uint32_t)pc_mirror((int)y - 1, (int)r->height));
		const uint16_t *b = PC_ROW(r, const uint16_t, y);
		const uint16_t *c =
		    PC_ROW(r, const uint16_t, (uint32_t)pc_mirror((int)y + 1, (int)r->height));
		uint16_t *o[4];
		unsigned slot[4] = {pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
		                    pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1)};
		for (int k = 0; k < 4; k++)
			o[k] = (uint16_t *)((uint8_t *)j->out[slot[k]] + (size_t)y * j->ostride);
#ifdef PC_CPU_X86
		if (j->level >= PC_CPU_AVX512)
			b16_row_avx512(a, b, c, r->width, 2 - j->frac, o[0], o[1], o[2], o[3]);
		else if (j->level >= PC_CPU_AVX2)
			b16_row_avx2(a, b, c, r->width, 2 - j->frac, o[0], o[1], o[2], o[3]);
		else
#endif
			b16_row_base(a, b, c, r->width, 2 - j->frac, o[0], o[1], o[2], o[3]);
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
		return pc_error(PC_ENOTSUP,
		                "16-bit bilinear: raw format %s; expected a 16-bit "
		                "container (Mono10/12/14/16)",
		                fi->name);
	if (frac_bits > 2 || fi->bits + frac_bits > 16)
		return pc_error(PC_ERANGE,
		                "16-bit bilinear: %u-bit data with %u fraction bits do not "
		                "fit 16 bits (frac_bits 0..2, bits + frac_bits <= 16)",
		                fi->bits, frac_bits);
	if (raw->width % 2 || raw->height % 2 || raw->width < 4 || raw->height < 4)
		return pc_error(PC_EINVAL,
		                "raw size %ux%u: width and height must be even and at "
		                "least 4",
		                raw->width, raw->height);
	if (!out || out_stride < (size_t)raw->width * 2)
		return pc_error(PC_EINVAL,
		                "16-bit bilinear: output planes missing or stride %zu "
		                "below %u bytes",
		                out_stride, 2 * raw->width);
	for (int c = 0; c < 4; c++)
		if (!out[c])
			return pc_error(PC_EINVAL, "16-bit bilinear: output plane %d missing", c);
	b16_job j = {raw, m, frac_bits, out, out_stride, pc_cpu_active()};
	pc_parallel_rows(raw->height, 0, threads, b16_band, &j);
	return 0;
}
