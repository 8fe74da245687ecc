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

#endif
