/* The Stokes kernels (stokes_kernels.h): the row kernels of stokes_kern.inc built once per
 * instruction-set level (simd.h), and their drivers - the fused bilinear pass over row bands,
 * the row sink of the row-cache methods, the planar pass, and the scalar generic pass. */
#include "stokes_kernels.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "simd.h"

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "stokes_kern.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "stokes_kern.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "stokes_kern.inc"
#include "simd_instance_end.h"
#endif

/* ---- dispatch of one row to the instance of the call's level ---- */

static void row_bilinear(pc_cpu_level l, const float *a, const float *b, const float *c, uint32_t w,
                         const float k1[4], const float k2[4], int exact, float *const o[5], int nt)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		stokes_row_avx512(a, b, c, w, k1, k2, exact, o, nt);
	else if (l >= PC_CPU_AVX2)
		stokes_row_avx2(a, b, c, w, k1, k2, exact, o, nt);
	else
#endif
		stokes_row_base(a, b, c, w, k1, k2, exact, o, 0);
	(void)l;
	(void)nt; /* streaming stores: x86 instances only */
}

static void row_bilinear_cal(pc_cpu_level l, const float *a, const float *b, const float *c,
                             uint32_t w, const float *const P[12], int xkind, int exact,
                             float *const o[5], int nt)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		stokes_row_cal_avx512(a, b, c, w, P, xkind, exact, o, nt);
	else if (l >= PC_CPU_AVX2)
		stokes_row_cal_avx2(a, b, c, w, P, xkind, exact, o, nt);
	else
#endif
		stokes_row_cal_base(a, b, c, w, P, xkind, exact, o, 0);
	(void)l;
	(void)nt; /* streaming stores: x86 instances only */
}

static void row_bilinear_vec(pc_cpu_level l, const float *const H[3], uint32_t w, int exact,
                             float *const o[5], int nt, const pc_st_pf *pf)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		stokes_row_vec_avx512(H, w, exact, o, nt, pf);
	else if (l >= PC_CPU_AVX2)
		stokes_row_vec_avx2(H, w, exact, o, nt, pf);
	else
#endif
		stokes_row_vec_base(H, w, exact, o, 0, pf);
	(void)l;
	(void)nt; /* streaming stores: x86 instances only */
}

static void row_vec_h(pc_cpu_level l, const float *const r[3], uint32_t w, float *h)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		vec_hrow_avx512(r, w, h);
	else if (l >= PC_CPU_AVX2)
		vec_hrow_avx2(r, w, h);
	else
#endif
		vec_hrow_base(r, w, h);
	(void)l;
}

static void row_vec_h_u16(pc_cpu_level l, const pc_st_vrow *r, uint32_t w, float *h)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		vec_hrow_u16_avx512(r, w, h);
	else if (l >= PC_CPU_AVX2)
		vec_hrow_u16_avx2(r, w, h);
	else
#endif
		vec_hrow_u16_base(r, w, h);
	(void)l;
}

static void row_vec_conv(pc_cpu_level l, const int16_t *q, float b0, float b1, float sc, uint32_t w,
                         float *d)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		vec_conv_avx512(q, b0, b1, sc, w, d);
	else if (l >= PC_CPU_AVX2)
		vec_conv_avx2(q, b0, b1, sc, w, d);
	else
#endif
		vec_conv_base(q, b0, b1, sc, w, d);
	(void)l;
}

/* Row y's samples corrected by the compact maps (pc_compact_calib): 16-bit raws converted and
 * corrected in one pass, other types converted first (pc_dm_row_to_float), then corrected. */
static void row_corr(pc_cpu_level l, const pc_dm_input *in, uint32_t y, float *d,
                     const pc_compact_calib *v)
{
	const size_t o = (size_t)y * v->stride;
	const int16_t *dq = v->dark_q ? v->dark_q + o : NULL,
	              *gq = v->gain_q ? v->gain_q + o : NULL;
	/* the compact correction replaces the input's (check_compact) */
	assert(in->black == 0 && !in->dark && !in->gain_inv);
	if (in->type == PC_DMT_U16) {
		const uint16_t *r =
		    (const uint16_t *)(const void *)(in->data + (size_t)y * in->stride);
#ifdef PC_CPU_X86
		if (l >= PC_CPU_AVX512)
			corr_u16_avx512(r, d, dq, v->dark_base, v->dark_scale, gq, v->gain_base,
			                v->gain_scale, v->width);
		else if (l >= PC_CPU_AVX2)
			corr_u16_avx2(r, d, dq, v->dark_base, v->dark_scale, gq, v->gain_base,
			              v->gain_scale, v->width);
		else
#endif
			corr_u16_base(r, d, dq, v->dark_base, v->dark_scale, gq, v->gain_base,
			              v->gain_scale, v->width);
		(void)l;
		return;
	}
	pc_dm_row_to_float(in, y, d);
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512)
		corr_row_avx512(d, dq, v->dark_base, v->dark_scale, gq, v->gain_base, v->gain_scale,
		                v->width);
	else if (l >= PC_CPU_AVX2)
		corr_row_avx2(d, dq, v->dark_base, v->dark_scale, gq, v->gain_base, v->gain_scale,
		              v->width);
	else
#endif
		corr_row_base(d, dq, v->dark_base, v->dark_scale, gq, v->gain_base, v->gain_scale,
		              v->width);
	(void)l;
}

static void row_channels(pc_cpu_level l, const float *const ch[4], uint32_t w,
                         const float *const *P, int xkind, float *const o[5], int nt)
{
#ifdef PC_CPU_X86
	if (l >= PC_CPU_AVX512) {
		if (P)
			stokes4_row_cal_avx512(ch[0], ch[1], ch[2], ch[3], w, P, xkind, o, nt);
		else
			stokes4_row_avx512(ch[0], ch[1], ch[2], ch[3], w, o, nt);
		return;
	}
	if (l >= PC_CPU_AVX2) {
		if (P)
			stokes4_row_cal_avx2(ch[0], ch[1], ch[2], ch[3], w, P, xkind, o, nt);
		else
			stokes4_row_avx2(ch[0], ch[1], ch[2], ch[3], w, o, nt);
		return;
	}
#endif
	(void)l;
	(void)nt; /* streaming stores: x86 instances only */
	if (P)
		stokes4_row_cal_base(ch[0], ch[1], ch[2], ch[3], w, P, xkind, o, 0);
	else
		stokes4_row_base(ch[0], ch[1], ch[2], ch[3], w, o, 0);
}

/* The calibration rows of output row y, element (i, channel ch[k]) at P[4i + k]. */
static void cal_rows(const pc_st_calib *cal, const unsigned ch[4], uint32_t y, const float *P[12])
{
	for (unsigned i = 0; i < 3; i++)
		for (unsigned k = 0; k < 4; k++)
			P[4 * i + k] = pc_st_calib_row(cal, i, ch[k], y);
}

/* ---- calibration ---- */

void pc_st_calib_init(const pc_analyser_pinv *pinv, uint32_t w, uint32_t h, pc_st_calib *c)
{
	c->pinv = pinv;
	c->plane = (size_t)pinv->grid_w * pinv->grid_h;
	c->w = w;
	c->h = h;
	uint32_t gw = pinv->grid_w;
	c->xkind = gw == 1                 ? PC_ST_X_UNIFORM
	           : gw == w               ? PC_ST_X_PIXEL
	           : (uint64_t)gw * 2 == w ? PC_ST_X_PAIR
	                                   : PC_ST_X_OTHER;
}

/* ---- outputs ---- */

static void out_planes(const pc_stokes_out *out, const pc_fplane *p[5])
{
	p[0] = &out->s0;
	p[1] = &out->s1;
	p[2] = &out->s2;
	p[3] = &out->dolp;
	p[4] = &out->aolp;
}

int pc_st_planar_out(const pc_stokes_out *out)
{
	const pc_fplane *p[5];
	out_planes(out, p);
	for (int k = 0; k < 5; k++)
		if (p[k]->data && p[k]->pixel_stride != 1)
			return 0;
	return 1;
}

int pc_st_stream_wanted(const pc_stokes_out *out, uint32_t w, uint32_t h, pc_cpu_level level)
{
	const pc_fplane *p[5];
	out_planes(out, p);
	int n = 0;
	for (int k = 0; k < 5; k++) {
		if (!p[k]->data)
			continue;
		n++;
		if (!pc_dm_planes_aligned(p[k], 1))
			return 0;
	}
	return level >= PC_CPU_AVX2 && (size_t)w * h * 4 * n >= pc_dm_nt_min_bytes();
}

/* Rows y of the wanted planar outputs (NULL where not wanted). */
static void out_rows(const pc_stokes_out *out, uint32_t y, float *o[5])
{
	const pc_fplane *p[5];
	out_planes(out, p);
	for (int k = 0; k < 5; k++)
		o[k] = p[k]->data ? p[k]->data + (size_t)y * p[k]->row_stride : NULL;
}

/* ---- the compact calibration's rows (pc_compact_calib) ---- */

/* A 3-row ring like pc_dm_ring's: each slot the eight horizontal sums of a raw row (vec_hrow),
 * made from one scratch of padded rows: the two normalised analysis components and the
 * corrected samples (or, for 16-bit raws with every map, by vec_hrow_u16 without them). */
typedef struct vec_ring {
	float *buf;
	float *src[3]; /* [0, 1: components v1, v2; 2: corrected samples], padded */
	float *h[3];   /* [slot]: the eight fields, PC_VEC_IX */
	int32_t have[3];
} vec_ring;

static int vec_ring_init(vec_ring *r, uint32_t w)
{
	size_t pitch = ((size_t)w + 2 + 15) / 16 * 16;
	size_t hn = pc_st_vec_len(w);
	r->buf = pc_dm_alloc((3 * pitch + 3 * hn) * sizeof(float));
	if (!r->buf)
		return -1;
	for (int k = 0; k < 3; k++)
		r->src[k] = r->buf + (size_t)k * pitch + 1;
	for (int i = 0; i < 3; i++) {
		r->h[i] = r->buf + 3 * pitch + (size_t)i * hn;
		r->have[i] = -1;
	}
	return 0;
}

/* Row y (mirrored) of the samples, corrected by the compact dark and gain maps when it has
 * them (else by in's black level or maps, pc_dm_row_to_float), and of the two normalised
 * analysis components, padded as pc_dm_row_to_float pads, summed into the slot's eight fields
 * (16-bit raws corrected by the maps, with both component maps: in one pass, vec_hrow_u16,
 * without the padded rows). Returns the slot. */
static int vec_ring_get(vec_ring *r, const pc_dm_input *in, const pc_compact_calib *v,
                        const pc_mosaic *m, pc_cpu_level level, int y)
{
	int sy = pc_mirror(y, (int)v->height);
	for (int i = 0; i < 3; i++)
		if (r->have[i] == sy)
			return i;
	int s = 0;
	for (int i = 1; i < 3; i++)
		if (r->have[i] < r->have[s])
			s = i;
	const size_t o = (size_t)sy * v->stride;
	if (in->type == PC_DMT_U16 && pc_compact_corrects(v) && v->v_q[0] && v->v_q[1]) {
		/* the common case in one pass, without the padded rows (the same values) */
		pc_st_vrow vr = {
		    .raw = (const uint16_t *)(const void *)(in->data + (size_t)sy * in->stride),
		    .dq = v->dark_q ? v->dark_q + o : NULL,
		    .gq = v->gain_q ? v->gain_q + o : NULL,
		    .q = {v->v_q[0] + o, v->v_q[1] + o},
		    .db = v->dark_base,
		    .ds = v->dark_scale,
		    .gb = v->gain_base,
		    .gs = v->gain_scale,
		    .sc = {v->v_scale[0], v->v_scale[1]}};
		assert(in->black == 0 && !in->dark && !in->gain_inv);
		for (int k = 0; k < 2; k++)
			for (int p = 0; p < 2; p++)
				vr.base[k][p] =
				    v->v_base[pc_dm_ch(m, (unsigned)p, (unsigned)sy)][k];
		row_vec_h_u16(level, &vr, v->width, r->h[s]);
		r->have[s] = sy;
		return s;
	}
	float *d = r->src[2];
	if (pc_compact_corrects(v)) {
		row_corr(level, in, (uint32_t)sy, d, v);
		d[-1] = d[v->width > 1 ? 1 : 0];
		d[v->width] = d[v->width > 1 ? v->width - 2 : 0];
	} else {
		pc_dm_row_to_float(in, (uint32_t)sy, d);
	}
	for (int k = 0; k < 2; k++) {
		const float b0 = v->v_base[pc_dm_ch(m, 0, (unsigned)sy)][k],
		            b1 = v->v_base[pc_dm_ch(m, 1, (unsigned)sy)][k];
		if (v->v_q[k]) {
			row_vec_conv(level, v->v_q[k] + o, b0, b1, v->v_scale[k], v->width,
			             r->src[k]);
		} else {
			for (int x = -1; x <= (int)v->width; x++)
				r->src[k][x] = (x & 1) ? b1 : b0; /* mirrored: the same columns */
		}
	}
	row_vec_h(level, (const float *const *)r->src, v->width, r->h[s]);
	r->have[s] = sy;
	return s;
}

/* The ranges that converting source row sy will read (vec_ring_get): the raw row and the
 * compact maps' rows, contiguous ones merged. */
static void vec_prefetch(const pc_dm_input *in, const pc_compact_calib *v, int sy, pc_st_pf *pf)
{
	static const size_t bps[3] = {1, 2, 4}; /* PC_DMT_U8, U16, F32 */
	pf->count = 0;
	const char *p[6];
	size_t n[6];
	int k = 0;
	p[k] = (const char *)in->data + (size_t)sy * in->stride;
	n[k++] = (size_t)in->width * bps[in->type];
	const int16_t *maps[4] = {v->v_q[0], v->v_q[1], v->dark_q, v->gain_q};
	for (int i = 0; i < 4; i++)
		if (maps[i]) {
			p[k] = (const char *)(maps[i] + (size_t)sy * v->stride);
			n[k++] = (size_t)v->width * sizeof(int16_t);
		}
	for (int i = 0; i < k; i++) {
		if (pf->count && pf->p[pf->count - 1] + pf->n[pf->count - 1] == p[i]) {
			pf->n[pf->count - 1] += n[i];
		} else {
			pf->p[pf->count] = p[i];
			pf->n[pf->count++] = n[i];
		}
	}
}

/* ---- fused bilinear + Stokes ---- */
typedef struct fused_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_st_calib *cal;
	const pc_compact_calib *vec;
	const pc_stokes_out *out;
	pc_cpu_level level;
	int planar, nt, exact, err;
} fused_job;

static void fused_band(void *ctx, uint32_t y0, uint32_t y1)
{
	fused_job *j = ctx;
	uint32_t w = j->in->width;
	pc_dm_ring rg = {0}; /* the raw rows, unless the compact calibration's ring reads them */
	vec_ring vr = {0};
	float *tmp = NULL;
	if ((!j->vec && pc_dm_ring_init(&rg, w)) ||
	    (!j->planar && !(tmp = pc_dm_alloc(5 * (size_t)w * 4))) ||
	    (j->vec && vec_ring_init(&vr, w))) {
		pc_dm_ring_free(&rg);
		pc_dm_free(tmp);
		pc_dm_free(vr.buf);
		j->err = 1;
		return;
	}
	const pc_fplane *planes[5];
	out_planes(j->out, planes);
	for (uint32_t y = y0; y < y1; y++) {
		const float *a = NULL, *b = NULL, *c = NULL, *H[3];
		if (j->vec) {
			for (int d = 0; d < 3; d++)
				H[d] = vr.h[vec_ring_get(&vr, j->in, j->vec, j->m, j->level,
				                         (int)y + d - 1)];
		} else {
			a = pc_dm_ring_get(&rg, j->in, (int)y - 1);
			b = pc_dm_ring_get(&rg, j->in, (int)y);
			c = pc_dm_ring_get(&rg, j->in, (int)y + 1);
		}
		unsigned ch[4] = {pc_dm_ch(j->m, 0, y), pc_dm_ch(j->m, 1, y),
		                  pc_dm_ch(j->m, 0, y + 1), pc_dm_ch(j->m, 1, y + 1)};
		float *o[5];
		for (int k = 0; k < 5; k++)
			o[k] = !planes[k]->data ? NULL
			       : j->planar ? planes[k]->data + (size_t)y * planes[k]->row_stride
			                   : tmp + (size_t)k * w;
		if (j->vec) {
			/* the next row to convert: y + 2 (mirrored), unless the band ends */
			pc_st_pf pf = {0};
			if (y + 2 < y1 + 1)
				vec_prefetch(j->in, j->vec,
				             pc_mirror((int)y + 2, (int)j->in->height), &pf);
			row_bilinear_vec(j->level, H, w, j->exact, o, j->nt, &pf);
		} else if (j->cal) {
			const float *P[12];
			cal_rows(j->cal, ch, y, P);
			row_bilinear_cal(j->level, a, b, c, w, P, j->cal->xkind, j->exact, o,
			                 j->nt);
		} else {
			/* S1 = I0 − I90 and S2 = I45 − I135 as signed sums of the four slots */
			float k1[4], k2[4];
			for (int k = 0; k < 4; k++) {
				k1[k] = ch[k] == 0 ? 1.0f : ch[k] == 2 ? -1.0f : 0.0f;
				k2[k] = ch[k] == 1 ? 1.0f : ch[k] == 3 ? -1.0f : 0.0f;
			}
			row_bilinear(j->level, a, b, c, w, k1, k2, j->exact, o, j->nt);
		}
		if (!j->planar)
			for (int k = 0; k < 5; k++) {
				if (!o[k])
					continue;
				float *d = planes[k]->data + (size_t)y * planes[k]->row_stride;
				for (uint32_t x = 0; x < w; x++)
					d[(size_t)x * planes[k]->pixel_stride] = o[k][x];
			}
	}
	if (j->nt)
		pc_dm_sfence();
	pc_dm_free(tmp);
	pc_dm_free(vr.buf);
	pc_dm_ring_free(&rg);
}

int pc_st_fused_bilinear(const pc_dm_input *in, const pc_mosaic *m, const pc_st_calib *cal,
                         const pc_compact_calib *vec, int threads, pc_cpu_level level,
                         const pc_stokes_out *out)
{
	fused_job j = {in, m, cal, vec, out, level, 1, 0, 0, 0};
	const pc_fplane *planes[5];
	out_planes(out, planes);
	int aligned = 1, n = 0;
	for (int k = 0; k < 5; k++) {
		if (!planes[k]->data)
			continue;
		n++;
		if (planes[k]->pixel_stride != 1)
			j.planar = 0;
		if (!pc_dm_planes_aligned(planes[k], 1))
			aligned = 0;
	}
	/* float raws may be tiny or huge: exact quotients (see dolp_aolp) */
	j.exact = in->type == PC_DMT_F32;
	j.nt = level >= PC_CPU_AVX2 && j.planar && aligned &&
	       (size_t)in->width * in->height * 4 * n >= pc_dm_nt_min_bytes();
	pc_parallel_rows(in->height, 0, threads, fused_band, &j);
	return j.err ? pc_error(PC_ENOMEM, "stokes: row buffers") : 0;
}

/* ---- the row sink ---- */

void pc_st_sink_row(void *sink, uint32_t y, const float *const ch[4])
{
	const pc_st_sink *s = sink;
	float *o[5];
	out_rows(s->out, y, o);
	if (s->cal) {
		static const unsigned id[4] = {0, 1, 2, 3};
		const float *P[12];
		cal_rows(s->cal, id, y, P);
		row_channels(s->level, ch, s->w, P, s->cal->xkind, o, s->nt);
	} else {
		row_channels(s->level, ch, s->w, NULL, 0, o, s->nt);
	}
	if (s->nt)
		pc_dm_sfence();
}

/* ---- Stokes from planar channel images ---- */
typedef struct planar_job {
	const pc_fplane *in;
	uint32_t w;
	const pc_st_calib *cal;
	const pc_stokes_out *out;
	pc_cpu_level level;
	int nt;
} planar_job;

static void planar_band(void *ctx, uint32_t y0, uint32_t y1)
{
	planar_job *j = ctx;
	static const unsigned id[4] = {0, 1, 2, 3};
	for (uint32_t y = y0; y < y1; y++) {
		const float *r[4];
		for (int c = 0; c < 4; c++)
			r[c] = j->in[c].data + (size_t)y * j->in[c].row_stride;
		float *o[5];
		out_rows(j->out, y, o);
		if (j->cal) {
			const float *P[12];
			cal_rows(j->cal, id, y, P);
			row_channels(j->level, r, j->w, P, j->cal->xkind, o, j->nt);
		} else {
			row_channels(j->level, r, j->w, NULL, 0, o, j->nt);
		}
	}
	if (j->nt)
		pc_dm_sfence();
}

int pc_st_planar(const pc_fplane in[4], uint32_t w, uint32_t h, const pc_st_calib *cal, int threads,
                 pc_cpu_level level, const pc_stokes_out *out)
{
	for (int c = 0; c < 4; c++)
		if (in[c].pixel_stride != 1)
			return PC_ENOTSUP;
	if (!pc_st_planar_out(out) || (cal && cal->xkind == PC_ST_X_OTHER))
		return PC_ENOTSUP;
	planar_job j = {in, w, cal, out, level, pc_st_stream_wanted(out, w, h, level)};
	pc_parallel_rows(h, 0, threads, planar_band, &j);
	return 0;
}

/* ---- the generic scalar pass ---- */
typedef struct generic_job {
	const pc_fplane *in;
	uint32_t w;
	const pc_st_calib *cal;
	const pc_stokes_out *out;
} generic_job;

static void put(const pc_fplane *p, uint32_t x, uint32_t y, float v)
{
	if (p->data)
		p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride] = v;
}

static void generic_band(void *ctx, uint32_t y0, uint32_t y1)
{
	const generic_job *j = ctx;
	const int want_da = j->out->dolp.data || j->out->aolp.data;
	const pc_analyser_pinv *pi = j->cal ? j->cal->pinv : NULL;
	for (uint32_t y = y0; y < y1; y++) {
		const float *row[4];
		for (int c = 0; c < 4; c++)
			row[c] = j->in[c].data + (size_t)y * j->in[c].row_stride;
		const float *P[12];
		if (pi) {
			static const unsigned id[4] = {0, 1, 2, 3};
			cal_rows(j->cal, id, y, P);
		}
		for (uint32_t x = 0; x < j->w; x++) {
			float v[4];
			for (int c = 0; c < 4; c++)
				v[c] = row[c][(size_t)x * j->in[c].pixel_stride];
			float s0, s1, s2;
			if (pi) {
				uint32_t gx = (uint32_t)((uint64_t)x * pi->grid_w / j->w);
				float s[3];
				for (int i = 0; i < 3; i++)
					s[i] = (P[4 * i][gx] * v[0] + P[4 * i + 1][gx] * v[1]) +
					       (P[4 * i + 2][gx] * v[2] + P[4 * i + 3][gx] * v[3]);
				s0 = s[0];
				s1 = s[1];
				s2 = s[2];
			} else {
				s0 = 0.5f * ((v[0] + v[1]) + (v[2] + v[3]));
				s1 = v[0] - v[2];
				s2 = v[1] - v[3];
			}
			put(&j->out->s0, x, y, s0);
			put(&j->out->s1, x, y, s1);
			put(&j->out->s2, x, y, s2);
			if (want_da) {
				put(&j->out->dolp, x, y, pc_st_dolp(s0, s1, s2));
				put(&j->out->aolp, x, y, pc_st_aolp(s1, s2));
			}
		}
	}
}

void pc_st_generic(const pc_fplane in[4], uint32_t w, uint32_t h, const pc_st_calib *cal,
                   int threads, const pc_stokes_out *out)
{
	generic_job j = {in, w, cal, out};
	pc_parallel_rows(h, 0, threads, generic_band, &j);
}
