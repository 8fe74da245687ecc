/* The validity mask (validity.h): saturated or dead raw samples dilated by the method's
 * support (and samples a trust map distrusts). Row bands on threads; per band, each raw row's flags
 * are dilated horizontally once (kept in a small cache while the vertical window passes over them)
 * and the rows of the window are ORed. Frames without a flagged sample in a window cost one
 * comparison per sample. */
#include "validity.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"

/* omp simd with the reductions of the flag and count loops (ignored without OpenMP) */
#ifdef _OPENMP
#define PC_SIMD_OR_ANY _Pragma("omp simd reduction(|:any)")
#else
#define PC_SIMD_OR_ANY
#endif

typedef struct vjob {
	const pc_dm_input *in;
	pc_dm_support sup;
	int use_sat, use_dead;
	const uint8_t *trusted;          /* NULL: every sample */
	const uint32_t *dis_row, *dis_x; /* listed distrusted samples (pc_dm_levels) */
	double sat, dead;                /* float samples */
	uint32_t isat;                   /* integer samples: flagged when >= isat (65536: never) */
	uint32_t idead1;                 /* ... or < idead1 (0: never) */
	uint32_t ow, oh;
	uint8_t *mask;
	size_t stride;
	atomic_uint_fast64_t invalid;
	atomic_int err;
} vjob;

/* Flags (0/1) of integer samples r[0..w): >= hi or < lo1. Returns whether any is set. */
#define PC_FLAG_INT(T)                                                                             \
	static unsigned flag_##T(const T *restrict r, uint32_t w, uint32_t hi, uint32_t lo1,       \
	                         uint8_t *restrict p)                                              \
	{                                                                                          \
		unsigned any = 0;                                                                  \
		PC_SIMD_OR_ANY                                                                     \
		for (uint32_t x = 0; x < w; x++) {                                                 \
			uint32_t v = r[x];                                                         \
			unsigned f = (unsigned)(v >= hi) | (unsigned)(v < lo1);                    \
			p[x] = (uint8_t)f;                                                         \
			any |= f;                                                                  \
		}                                                                                  \
		return any;                                                                        \
	}
PC_FLAG_INT(uint8_t)
PC_FLAG_INT(uint16_t)
#undef PC_FLAG_INT

static unsigned flag_float(const float *restrict r, uint32_t w, double hi, double lo,
                           uint8_t *restrict p)
{
	unsigned any = 0;
	PC_SIMD_OR_ANY
	for (uint32_t x = 0; x < w; x++) {
		unsigned f = (unsigned)((double)r[x] >= hi) | (unsigned)((double)r[x] <= lo);
		p[x] = (uint8_t)f;
		any |= f;
	}
	return any;
}

/* p |= (t == 0) over n bytes; returns whether any t is 0 */
static unsigned flag_distrusted(const uint8_t *restrict t, uint32_t n, uint8_t *restrict p)
{
	unsigned any = 0;
	PC_SIMD_OR_ANY
	for (uint32_t x = 0; x < n; x++) {
		unsigned f = (unsigned)(t[x] == 0);
		p[x] = (uint8_t)(p[x] | f);
		any |= f;
	}
	return any;
}

/* Flags (0/1) of raw row y into p[0..w). Returns whether any is set. */
static int flag_row(const vjob *j, uint32_t y, uint8_t *p)
{
	const pc_dm_input *in = j->in;
	const uint8_t *row = in->data + (size_t)y * in->stride;
	unsigned any;
	switch (in->type) {
	case PC_DMT_U8:
		any = flag_uint8_t(row, in->width, j->isat, j->idead1, p);
		break;
	case PC_DMT_U16:
		any = flag_uint16_t((const uint16_t *)(const void *)row, in->width, j->isat,
		                    j->idead1, p);
		break;
	default:
		any = flag_float((const float *)(const void *)row, in->width,
		                 j->use_sat ? j->sat : INFINITY, j->use_dead ? j->dead : -INFINITY,
		                 p);
		break;
	}
	if (j->trusted)
		any |= flag_distrusted(j->trusted + (size_t)y * in->width, in->width, p);
	if (j->dis_row)
		for (uint32_t i = j->dis_row[y]; i < j->dis_row[y + 1]; i++) {
			p[j->dis_x[i]] = 1;
			any = 1;
		}
	return any != 0;
}

/* o |= q over n bytes */
static void or_into(uint8_t *restrict o, const uint8_t *restrict q, uint32_t n)
{
	PC_SIMD
	for (uint32_t x = 0; x < n; x++)
		o[x] |= q[x];
}

/* out = !acc; returns the number of set acc bytes */
static unsigned invert_count(uint8_t *restrict out, const uint8_t *restrict acc, uint32_t n)
{
	unsigned cnt = 0;
#ifdef _OPENMP
#pragma omp simd reduction(+ : cnt)
#endif
	for (uint32_t x = 0; x < n; x++) {
		cnt += acc[x];
		out[x] = (uint8_t)(acc[x] ^ 1u);
	}
	return cnt;
}

/* Per-band state: a cache of horizontally dilated flag rows, one slot per row of the
 * support plus one (k slots, however wide the method's support: igri2's ±40 needs 82). */
typedef struct vband {
	int k;
	int32_t *key;
	uint8_t *any;
	uint8_t **hd; /* ow bytes each */
	uint8_t *pad; /* one raw row of flags with `margin` mirrored bytes on each side */
	int margin;
} vband;

static uint32_t anchor(const pc_dm_support *s, uint32_t X)
{
	return X * s->scale / s->block * s->block;
}

/* The dilated flags of raw row r (cached). */
static const uint8_t *hd_row(const vjob *j, vband *b, int32_t r, int *any)
{
	int victim = 0;
	for (int i = 0; i < b->k; i++) {
		if (b->key[i] == r) {
			*any = b->any[i];
			return b->hd[i];
		}
		if (b->key[i] < b->key[victim])
			victim = i;
	}
	const pc_dm_input *in = j->in;
	const int w = (int)in->width, m = b->margin;
	uint8_t *p = b->pad + m, *o = b->hd[victim];
	int a = flag_row(j, (uint32_t)r, p);
	b->key[victim] = r;
	b->any[victim] = (uint8_t)a;
	*any = a;
	if (!a)
		return o; /* not read */
	for (int i = 1; i <= m; i++) {
		p[-i] = p[pc_mirror(-i, w)];
		p[w - 1 + i] = p[pc_mirror(w - 1 + i, w)];
	}
	const int lo = j->sup.lo, hi = j->sup.hi;
	if (j->sup.block == 1 && j->sup.scale == 1) {
		/* one shifted row at a time: plain byte loops that vectorise */
		memcpy(o, p + lo, j->ow);
		for (int d = lo + 1; d <= hi; d++)
			or_into(o, p + d, j->ow);
	} else {
		for (uint32_t X = 0; X < j->ow; X++) {
			int ax = (int)anchor(&j->sup, X);
			unsigned v = 0;
			for (int d = lo; d <= hi; d++)
				v |= p[pc_mirror(ax + d, w)];
			o[X] = (uint8_t)v;
		}
	}
	return o;
}

static void vband_run(void *ctx, uint32_t Y0, uint32_t Y1)
{
	vjob *j = ctx;
	const pc_dm_support *s = &j->sup;
	const uint32_t ow = j->ow, w = j->in->width;
	vband b;
	memset(&b, 0, sizeof b);
	b.k = s->hi - s->lo + 2;
	b.margin = (s->hi > -s->lo ? s->hi : -s->lo) + 1;
	uint8_t *buf = malloc((size_t)b.k * ow + w + 2 * (size_t)b.margin + 2 * (size_t)ow);
	b.key = malloc((size_t)b.k * sizeof *b.key);
	b.any = malloc((size_t)b.k);
	b.hd = malloc((size_t)b.k * sizeof *b.hd);
	if (!buf || !b.key || !b.any || !b.hd) {
		free(buf);
		free(b.key);
		free(b.any);
		free(b.hd);
		atomic_store(&j->err, 1);
		return;
	}
	for (int i = 0; i < b.k; i++) {
		b.key[i] = -1;
		b.hd[i] = buf + (size_t)i * ow;
	}
	b.pad = buf + (size_t)b.k * ow;
	uint8_t *acc = b.pad + w + 2 * (size_t)b.margin, *tmp = acc + ow;
	uint64_t invalid = 0;
	for (uint32_t Y = Y0; Y < Y1; Y++) {
		uint8_t *out = j->mask ? j->mask + (size_t)Y * j->stride : tmp;
		int ay = (int)anchor(s, Y), seen = 0;
		for (int d = s->lo; d <= s->hi; d++) {
			int any;
			const uint8_t *h =
			    hd_row(j, &b, pc_mirror(ay + d, (int)j->in->height), &any);
			if (!any)
				continue;
			if (!seen)
				memcpy(acc, h, ow);
			else
				or_into(acc, h, ow);
			seen = 1;
		}
		if (!seen) {
			memset(out, 1, ow);
			continue;
		}
		invalid += invert_count(out, acc, ow);
	}
	atomic_fetch_add(&j->invalid, invalid);
	free(buf);
	free(b.key);
	free(b.any);
	free(b.hd);
}

int pc_dm_validity(const pc_dm_input *in, const pc_dm_support *sup, const pc_dm_levels *lv,
                   uint32_t ow, uint32_t oh, int threads, uint8_t *mask, size_t stride,
                   uint64_t *n_invalid)
{
	*n_invalid = 0;
	int use_sat = lv->saturation > 0, use_dead = lv->dead > 0;
	if (!use_sat && !use_dead && !lv->trusted && !lv->dis_row) {
		if (mask)
			for (uint32_t Y = 0; Y < oh; Y++)
				memset(mask + (size_t)Y * stride, 1, ow);
		return 0;
	}
	vjob *j = calloc(1, sizeof *j);
	if (!j)
		return pc_error(PC_ENOMEM, "validity mask");
	j->in = in;
	j->sup = *sup;
	j->use_sat = use_sat;
	j->use_dead = use_dead;
	j->trusted = lv->trusted;
	j->dis_row = lv->dis_row;
	j->dis_x = lv->dis_x;
	j->sat = lv->saturation;
	j->dead = lv->dead;
	/* integer samples: >= sat is >= ceil(sat), <= dead is < floor(dead) + 1 */
	j->isat =
	    use_sat ? (lv->saturation > 65536 ? 65536u : (uint32_t)ceil(lv->saturation)) : 65536u;
	j->idead1 = use_dead ? (uint32_t)floor(lv->dead > 65535 ? 65535 : lv->dead) + 1u : 0u;
	j->ow = ow;
	j->oh = oh;
	j->mask = mask;
	j->stride = stride;
	atomic_init(&j->invalid, 0);
	atomic_init(&j->err, 0);
	pc_parallel_rows(oh, 0, threads, vband_run, j);
	int err = atomic_load(&j->err);
	*n_invalid = atomic_load(&j->invalid);
	free(j);
	return err ? pc_error(PC_ENOMEM, "validity mask: row buffers") : 0;
}
