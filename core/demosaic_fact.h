/* Internal to core: the colour-polarization method with colour and polarization factorised
 * (demosaic_fact.c, "pan-fact"). Not a public header. */
#ifndef POLARCAM_DEMOSAIC_FACT_H
#define POLARCAM_DEMOSAIC_FACT_H

#include "demosaic_pan.h"

/* The method's constants (demosaic_fact.c states the definition), shared by the reference and
 * the fast path (demosaic_pan.c) */
#define FACT_EPS   1e-4 /* floor of an interpolated colour: of the block full scale, of a ratio */
#define FACT_DELTA 0.01 /* δ of the ratio step, fraction of M's full scale */
#define FACT_DH    1e-4 /* δ_h of the hue's ratios, fraction of full scale */

/* The double reference (pc_dm_pan_ref's arguments). */
int pc_dm_pan_fact_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out);

/* The fast float path (pc_dm_pan_fast's arguments; demosaic_pan.c). */
int pc_dm_pan_fact_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out);

/* pan-fact's reference and fast path (NULL for other methods). */
const pc_dm_pan_fns *pc_dm_fact_fns_get(pc_demosaic_method m);

#endif
