/* Internal to core: the row-cache fast paths of the inter-channel methods (bicubic, PPID, RI,
 * EARI, ratio; demosaic_ic.c), monochrome mosaics. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_IC_H
#define POLARCAM_DEMOSAIC_IC_H

#include "demosaic_common.h"

/* Demosaics into four channel planes of any strides (non-temporal stores for large aligned
 * planar outputs). */
int pc_dm_ic(const pc_dm_call *call, const pc_fplane *out);

/* Demosaics row by row, handing each finished row (in cache) to sink instead of writing
 * channel images: the fused Stokes pipeline. */
int pc_dm_ic_rows(const pc_dm_call *call, const pc_dm_row_sink *sink);

#endif
