/* Internal to core: the colour-polarization method guided by a pseudo-panchromatic image
 * (demosaic_pan.c): all sixteen samples of a 4×4 period share one scene. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_PAN_H
#define POLARCAM_DEMOSAIC_PAN_H

#include "demosaic_common.h"

/* The double reference: img the raw minus black (C order, w × h, w and h even, >= 8); out the
 * twelve planes (channel 4·k + c); fs the signal's full scale. */
int pc_dm_pan_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                  const pc_fplane *out);

/* pan-guided's double reference and fast path (the same arguments). */
int pc_dm_pan_guided_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out);
int pc_dm_pan_guided_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out);

/* pan-chroma's double reference and fast path (the same arguments). */
int pc_dm_pan_chroma_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                         const pc_fplane *out);
int pc_dm_pan_chroma_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                          pc_cpu_level level, const pc_fplane *out);

/* pan-side's double reference and fast path (the same arguments). */
int pc_dm_pan_side_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                       const pc_fplane *out);
int pc_dm_pan_side_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                        pc_cpu_level level, const pc_fplane *out);

/* pan-dir's double reference and fast path (the same arguments). */
int pc_dm_pan_dir_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
                      const pc_fplane *out);
int pc_dm_pan_dir_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                       pc_cpu_level level, const pc_fplane *out);

/* The fast float path on the prepared input (raw rows converted as they are needed): row bands
 * on threads, intermediate rows in per-thread rings. PC_ENOMEM for its row buffers. */
int pc_dm_pan_fast(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
                   pc_cpu_level level, const pc_fplane *out);

/* The colour methods of this file, which the front door runs instead of a colour step and a
 * monochrome step: pc_dm_pan_fns_get gives their reference and fast path (NULL for other
 * methods). */
typedef struct pc_dm_pan_fns {
	int (*ref)(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m, double fs,
	           const pc_fplane *out);
	int (*fast)(const pc_dm_input *in, const pc_mosaic *m, double fs, int threads,
	            pc_cpu_level level, const pc_fplane *out);
} pc_dm_pan_fns;

const pc_dm_pan_fns *pc_dm_pan_fns_get(pc_demosaic_method m);

#endif
