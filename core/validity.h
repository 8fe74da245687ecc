/* Internal to core: the validity mask of a demosaicked (or Stokes) output (validity.c) - an
 * output pixel is invalid when any raw sample its value depends on is saturated (>= the
 * saturation level) or dead (<= the dead level). What it depends on is the method's support,
 * stated in the method table and checked against the references by perturbation in
 * tests/test_demosaic.c. Not a public header. */
#ifndef POLARCAM_VALIDITY_H
#define POLARCAM_VALIDITY_H

#include <stdint.h>

#include "demosaic_common.h"

/* The raw samples an output pixel (X, Y) depends on: rows mirror(ay + lo .. ay + hi) and
 * columns mirror(ax + lo .. ax + hi), with the anchor ax = (X·scale) rounded down to a multiple
 * of block (ay likewise): block 1, scale 1 is the box of radius r = -lo = hi around the pixel;
 * block 2 the pixel's 2×2 super-pixel (lo 0, hi 1); scale 2 a half-size output. */
typedef struct pc_dm_support {
	int lo, hi;
	unsigned block, scale;
} pc_dm_support;

/* Levels in raw units (before the black level); 0: not checked. trusted: per raw sample
 * (width × height bytes, row stride width), 0 flags the sample as a saturated one is flagged;
 * NULL: all trusted. dis_row, dis_x: more samples flagged so, as a list (row y's at columns
 * dis_x[dis_row[y] .. dis_row[y + 1]), pc_compact_calib); NULL: none. */
typedef struct pc_dm_levels {
	double saturation, dead;
	const uint8_t *trusted;
	const uint32_t *dis_row, *dis_x;
} pc_dm_levels;

/* Writes mask (ow × oh bytes, row stride `stride`; NULL: count only) with 1 for valid and 0 for
 * invalid output pixels and returns their count in *n_invalid. PC_ENOMEM for row buffers. */
int pc_dm_validity(const pc_dm_input *in, const pc_dm_support *sup, const pc_dm_levels *lv,
                   uint32_t ow, uint32_t oh, int threads, uint8_t *mask, size_t stride,
                   uint64_t *n_invalid);

#endif
