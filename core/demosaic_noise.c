/* A frame's noise gain for pan-adapt: the definition is in demosaic_noise.h. */
#include "demosaic_noise.h"

#include <math.h>
#include <stdlib.h>

#include "polarcam/error.h"

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

int pc_dm_noise_gain(pc_dm_sample_fn get, const void *ctx, uint32_t w, uint32_t h,
                     const pc_mosaic *m, double fs, double *g)
{
	const uint32_t p = m->period;
	if (w <= 2 * p || h <= 2 * p) {
		*g = 0;
		return 0;
	}
	const uint32_t iw = w - 2 * p, ih = h - 2 * p;
	uint32_t s = 1;
	while ((size_t)((iw + s - 1) / s) * ((ih + s - 1) / s) > PC_DM_NG_POINTS)
		s += 2;
	const size_t nx = (iw + s - 1) / s, ny = (ih + s - 1) / s, n = nx * ny;
	double *t = malloc(sizeof(double) * n);
	if (!t)
		return pc_error(PC_ENOMEM, "noise gain: %zu values", n);
	const double floor = PC_DM_NG_FLOOR * fs;
	size_t k = 0;
	for (uint32_t y = p; y < h - p; y += s)
		for (uint32_t x = p; x < w - p; x += s) {
			double nb = (get(ctx, x - p, y) + get(ctx, x + p, y) + get(ctx, x, y - p) +
			             get(ctx, x, y + p)) /
			            4;
			double r = get(ctx, x, y) - nb;
			t[k++] = r * r / (fmax(nb, 0) + floor);
		}
	*g = select_rank(t, n, n / 2) / (1.25 * PC_DM_NG_CHI1);
	free(t);
	return 0;
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

static double get_in(const void *ctx, uint32_t x, uint32_t y)
{
	const pc_dm_input *in = ctx;
	return (double)pc_dm_sample(in, x, y) - in->black_d;
}

int pc_dm_noise_gain_in(const pc_dm_input *in, const pc_mosaic *m, double fs, double *g)
{
	if (in->dark || in->gain_inv)
		return pc_error(PC_EINVAL, "noise gain: an input with dark or gain maps (correct a "
		                           "copy first)");
	return pc_dm_noise_gain(get_in, in, in->width, in->height, m, fs, g);
}
