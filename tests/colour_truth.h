/* Shared by the colour method tests (test_pan_guard, test_pan_guard_fast, test_pan_guard_bands,
 * test_pan_hue): synthetic colour-polarization scenes with their truth per channel, and twelve
 * planes over one buffer. Include after polarcam/demosaic.h and polarcam/mosaic.h. */
#ifndef PC_TESTS_COLOUR_TRUTH_H
#define PC_TESTS_COLOUR_TRUTH_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "polarcam/demosaic.h"
#include "polarcam/mosaic.h"

static inline float *alloc_planes(uint32_t w, uint32_t h, pc_fplane *p)
{
	float *buf = malloc(sizeof(float) * (size_t)w * h * 12);
	pc_fplanes_separate(buf, w, h, 12, p);
	return buf;
}

/* a scene: truth[q][y·w + x] for the twelve channels, the raw its own channel's sample */
typedef double (*truth_fn)(unsigned k, unsigned c, double x, double y);

static inline void make_raw(truth_fn f, const pc_mosaic *m, uint32_t w, uint32_t h, double *img,
                            double *truth)
{
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			for (unsigned q = 0; q < 12; q++)
				truth[(size_t)q * w * h + (size_t)y * w + x] =
				    f(q / 4, q % 4, x, y);
			unsigned k = pc_mosaic_color(m, x, y) - PC_CFA_R,
			         c = pc_mosaic_channel(m, x, y);
			img[(size_t)y * w + x] = f(k, c, x, y);
		}
}

/* polarization: DoLP 0.4, AoLP 0.5 rad, analyser c at c·45° */
/* the largest relative error of n outputs against a truth with no zero */
static inline double max_rel_error(const float *out, const double *truth, size_t n)
{
	double worst = 0;
	for (size_t i = 0; i < n; i++)
		worst = fmax(worst, fabs(out[i] - truth[i]) / truth[i]);
	return worst;
}

static inline double pol(unsigned c)
{
	return 1 + 0.4 * cos(2 * (c * M_PI / 4 - 0.5));
}

static inline double f_uniform(unsigned k, unsigned c, double x, double y)
{
	(void)x;
	(void)y;
	static const double col[3] = {900, 1500, 600};
	return col[k] * pol(c);
}

static inline double f_grey(unsigned k, unsigned c, double x, double y)
{
	static const double col[3] = {0.8, 1.0, 0.7};
	double t = 1 + 0.5 * sin(2 * M_PI * x / 13.0) * cos(2 * M_PI * y / 17.0) +
	           0.3 * sin(2 * M_PI * (x + y) / 23.0 + 1) + 0.2 * cos(2 * M_PI * (x - y) / 11.0);
	return 1200 * col[k] * t * pol(c);
}

/* soft-edged bars of the given period across a direction 10° from x: the pixel's coverage of a
 * bar in [0, 1], a sine's clipped ramp */
static inline double soft_bars(double x, double y, double period)
{
	const double a = 10 * M_PI / 180, u = x * cos(a) + y * sin(a);
	const double t = 0.5 + 1.5 * sin(2 * M_PI * u / period);
	return t < 0 ? 0 : t > 1 ? 1 : t;
}

/* green bars on magenta of coverage t: P0 (R + 2G + B weights) 0.4·2 = 0.8 on green against
 * 0.9 + 0.8 = 1.7·… on magenta, a contrast of about 0.15 */
static inline double gm_at(unsigned k, unsigned c, double t)
{
	static const double green[3] = {0.05, 0.62, 0.05}, magenta[3] = {0.75, 0.06, 0.6};
	return 3000 * (t * green[k] + (1 - t) * magenta[k]) * pol(c);
}

/* green bars on magenta (test_pan_hue, test_pan_split), period 4.5 px */
static inline double f_gm(unsigned k, unsigned c, double x, double y)
{
	return gm_at(k, c, soft_bars(x, y, 4.5));
}

/* rms error of colour k's analyser mean against the truth's over the interior (B from the
 * borders) */
static inline double rms_colour(const float *out, const double *truth, unsigned k, uint32_t w,
                                uint32_t h, uint32_t B)
{
	const size_t np = (size_t)w * h;
	double e = 0, n = 0;
	for (uint32_t y = B; y < h - B; y++)
		for (uint32_t x = B; x < w - B; x++) {
			size_t i = (size_t)y * w + x;
			double o = 0, t = 0;
			for (unsigned c = 0; c < 4; c++) {
				o += out[(size_t)(4 * k + c) * np + i] / 4.0;
				t += truth[(size_t)(4 * k + c) * np + i] / 4.0;
			}
			e += (o - t) * (o - t);
			n++;
		}
	return sqrt(e / n);
}

#endif
