/* The overshoot limiter of the robust rungs (docs/demosaicking.md, "Robustness"): every
 * interpolated sample of channel c at pixel p is held inside the range of channel c's own
 * measurements in the 5×5 window around p (mirrored borders, as every method):
 *     I_c(p) ← min(max(I_c(p), min_W raw_c), max_W raw_c).
 * Inter-channel methods extrapolate from a guide; where the guide's model does not hold (a
 * bright object on black, a saturated glint, polarization texture) they ring, and in the dark
 * the ringing becomes false polarization (the DoLP of small numbers). Bilinear never leaves
 * that range. Min, max and clamp are exact in float, and the limiter runs on the float outputs
 * of both the fast paths and the double references (rounded to float first), so the two stay
 * as close to each other after it as before. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

int pc_dm_limited(pc_demosaic_method method)
{
	return method == PC_DM_BICUBIC || method == PC_DM_PPID || method == PC_DM_RI ||
	       method == PC_DM_EARI || method == PC_DM_RATIO || method == PC_DM_EARI_ROBUST;
}

void pc_dm_limit_row(const pc_mosaic *m, const float *const r[5], long w, uint32_t y,
		     float *const o[4], size_t pixel_stride, float *scratch)
{
	/* per row k (y-2..y+2): A = min/max over x±1 (the other column parity), B = over x−2, x,
	 * x+2 (the same parity) */
	float *amin[5], *amax[5], *bmin[5], *bmax[5];
	for (int k = 0; k < 5; k++) {
		amin[k] = scratch + (size_t)w * (4 * k);
		amax[k] = scratch + (size_t)w * (4 * k + 1);
		bmin[k] = scratch + (size_t)w * (4 * k + 2);
		bmax[k] = scratch + (size_t)w * (4 * k + 3);
		const float *rr = r[k];
		float *an = amin[k], *ax = amax[k], *bn = bmin[k], *bx = bmax[k];
		PC_SIMD
		for (long x = 0; x < w; x++) {
			float a0 = rr[x - 1], a1 = rr[x + 1], b0 = rr[x - 2], b1 = rr[x], b2 = rr[x + 2];
			an[x] = fminf(a0, a1);
			ax[x] = fmaxf(a0, a1);
			bn[x] = fminf(fminf(b0, b1), b2);
			bx[x] = fmaxf(fmaxf(b0, b1), b2);
		}
	}
	for (unsigned py = 0; py < 2; py++)
		for (unsigned px = 0; px < 2; px++) {
			unsigned c = pc_dm_ch(m, px, py);
			int same_row = ((y ^ py) & 1) == 0;
			float *dst = o[c];
			for (unsigned cp = 0; cp < 2; cp++) { /* columns of parity px ^ cp */
				int same_col = cp == 0;
				if (same_row && same_col)
					continue; /* the pixel's own measurement */
				float *const *mn = same_col ? bmin : amin;
				float *const *mx = same_col ? bmax : amax;
				for (long x = (long)(px ^ cp); x < w; x += 2) {
					float lo, hi;
					if (same_row) {
						lo = fminf(fminf(mn[0][x], mn[2][x]), mn[4][x]);
						hi = fmaxf(fmaxf(mx[0][x], mx[2][x]), mx[4][x]);
					} else {
						lo = fminf(mn[1][x], mn[3][x]);
						hi = fmaxf(mx[1][x], mx[3][x]);
					}
					float *v = dst + (size_t)x * pixel_stride;
					*v = fminf(fmaxf(*v, lo), hi);
				}
			}
		}
}

typedef struct limit_job {
	const pc_dm_input *in;
	const pc_mosaic *m;
	const pc_fplane *out;
	int err;
} limit_job;

static void limit_band(void *ctx, uint32_t y0, uint32_t y1)
{
	limit_job *j = ctx;
	const pc_dm_input *in = j->in;
	const long w = in->width;
	const int h = (int)in->height;
	const size_t L = (size_t)w + 8;
	float *mem = malloc(sizeof(float) * (L * 5 + (size_t)w * 20));
	if (!mem) {
		j->err = 1;
		return;
	}
	float *scratch = mem + L * 5;
	for (uint32_t y = y0; y < y1; y++) {
		const float *r[5];
		for (int k = 0; k < 5; k++) {
			float *row = mem + L * (size_t)k + 4;
			pc_dm_row_to_float(in, (uint32_t)pc_mirror((int)y + k - 2, h), row);
			row[-2] = row[pc_mirror(-2, (int)w)];
			row[w + 1] = row[pc_mirror((int)w + 1, (int)w)];
			r[k] = row;
		}
		float *o[4];
		for (int c = 0; c < 4; c++)
			o[c] = j->out[c].data + (size_t)y * j->out[c].row_stride;
		/* one pixel stride for all four planes in every layout the library makes */
		pc_dm_limit_row(j->m, r, w, y, o, j->out[0].pixel_stride, scratch);
	}
	free(mem);
}

int pc_dm_range_limit(const pc_view *raw, const pc_mosaic *m, int threads, const pc_fplane *out)
{
	for (int c = 1; c < 4; c++)
		if (out[c].pixel_stride != out[0].pixel_stride)
			return pc_error(PC_EINVAL, "output channels with different pixel strides");
	pc_dm_input in;
	void *owned;
	int rc = pc_dm_prepare_input(raw, &in, &owned);
	if (rc)
		return rc;
	limit_job j = { &in, m, out, 0 };
	pc_parallel_rows(in.height, 32, threads, limit_band, &j);
	pc_dm_free(owned);
	return j.err ? pc_error(PC_ENOMEM, "range limiter: row scratch") : 0;
}
