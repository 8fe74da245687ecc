/* Internal to core: the colour-polarization method with colour and polarization factorised
 * (demosaic_fact.c, "pan-fact"). Not a public header. */
#ifndef POLARCAM_DEMOSAIC_FACT_H
#define POLARCAM_DEMOSAIC_FACT_H

#include "demosaic_pan.h"

/* The double reference (pc_dm_pan_ref's arguments). */
int pc_dm_pan_fact_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out);

/* pan-fact's reference and fast path (NULL for other methods). */
const pc_dm_pan_fns *pc_dm_fact_fns_get(pc_demosaic_method m);

#endif
