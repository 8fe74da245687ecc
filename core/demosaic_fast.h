/* Internal to core: the one-pass fast float kernels of the demosaicking ladder
 * (demosaic_fast.c), monochrome mosaics. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_FAST_H
#define POLARCAM_DEMOSAIC_FAST_H

#include "demosaic_common.h"

/* Bilinear into four channel planes of any strides (non-temporal stores for large aligned
 * planar outputs). */
int pc_dm_bilinear(const pc_dm_call *call, const pc_fplane *out);

/* The 2×2 super-pixel, replicated over its block (full size) or one pixel per block (half
 * size). */
int pc_dm_superpixel(const pc_dm_call *call, const pc_fplane *out);
int pc_dm_superpixel_half(const pc_dm_call *call, const pc_fplane *out);

#endif
