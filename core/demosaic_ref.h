/* Internal to core: the double-precision references of the monochrome demosaicking methods
 * (demosaic_ref.c), the specification every fast kernel is tested against. Not a public
 * header. */
#ifndef POLARCAM_DEMOSAIC_REF_H
#define POLARCAM_DEMOSAIC_REF_H

#include "demosaic_common.h"

/* img: the raw minus the black level in double, C order, width × height; m a monochrome mosaic
 * (a colour mosaic's monochrome part for the colour methods' second step); full_scale as in
 * pc_dm_call (> 0); noise_gain: ratio-nr's (pc_dm_call.noise_gain), the other methods ignore
 * it. PC_ENOTSUP for methods without a monochrome reference. */
int pc_dm_ref(const double *img, uint32_t width, uint32_t height, const pc_mosaic *m,
              pc_demosaic_method method, double full_scale, double noise_gain,
              const pc_fplane *out);

#endif
