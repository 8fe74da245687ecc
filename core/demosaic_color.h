/* Internal to core: step 1 of the colour-polarization methods (demosaic_color.c) - Bayer
 * demosaicking of each analyser's half-resolution sub-image, giving for each colour k a
 * full-resolution monochrome polarizer mosaic M_k that step 2 demosaics with a monochrome
 * method. Not a public header. */
#ifndef POLARCAM_DEMOSAIC_COLOR_H
#define POLARCAM_DEMOSAIC_COLOR_H

#include "demosaic_common.h"

/* The monochrome polarizer part of a colour mosaic (the mosaic of every M_k). */
pc_mosaic pc_dm_color_mono(const pc_mosaic *m);

/* Step 1 of the reference in double: img the raw (minus black), C order w × h; mk[k] w × h. */
void pc_dm_color_split_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                           double *mk[3]);

/* The two steps' double reference (the specification of bayer-first, second = PC_DM_BILINEAR,
 * and of bayer-eari, PC_DM_EARI): step 1 (pc_dm_color_split_ref), then second's monochrome
 * reference (pc_dm_ref, full scale fs) on each M_k into out[4k + c]. PC_ENOMEM for the M_k,
 * or pc_dm_ref's error. */
int pc_dm_bayer_first_ref(const double *img, uint32_t w, uint32_t h, const pc_mosaic *m,
                          pc_demosaic_method second, double fs, const pc_fplane *out);

/* Step 1 in float on row bands; PC_ENOMEM for its column tables. */
int pc_dm_color_split(const float *img, uint32_t w, uint32_t h, const pc_mosaic *m, int threads,
                      float *mk[3]);

/* bayer-first (step 1, then the monochrome bilinear of each M_k) in one row-band pass over the
 * prepared input into the 12 planes out[4k + c]: the composed weights applied
 * to the raw (docs/demosaicking.md, Round 15d), the outputs within 3 pixels of a border by the
 * definition itself. PC_ENOMEM for its buffers. */
int pc_dm_bayer_first(const pc_dm_input *in, const pc_mosaic *m, int threads, pc_cpu_level level,
                      const pc_fplane *out);

/* The same pass on a caller's consecutive row ranges, for methods that use bayer-first's
 * output row by row (pan-guard's fast path): a band keeps its buffers and its ring of raw rows
 * between calls, so increasing ranges read each raw row once. _rows writes output rows
 * [y0, y1) into out, whose row 0 holds row y0 (row_stride apart); the outputs equal
 * pc_dm_bayer_first's bit for bit. _new returns NULL when out of memory. One band per thread. */
typedef struct pc_dm_bf_band pc_dm_bf_band;
pc_dm_bf_band *pc_dm_bayer_first_band_new(const pc_dm_input *in, const pc_mosaic *m,
                                          pc_cpu_level level);
void pc_dm_bayer_first_band_rows(pc_dm_bf_band *b, uint32_t y0, uint32_t y1, const pc_fplane *out);
void pc_dm_bayer_first_band_free(pc_dm_bf_band *b);
/* Green's analyser mean of output row y alone, into out[0, width): (((G_0 + G_1) + G_2) + G_3)·¼
 * of the four green outputs of _rows, equal to it bit for bit on integer raws (the interior by
 * one filter on the raw masked to green, docs/demosaicking.md Round 18d; the pixels within 3 of
 * a border by the definition, as _rows). Shares the band's ring of raw rows with _rows. */
void pc_dm_bayer_first_band_gmean(pc_dm_bf_band *b, uint32_t y, float *out);
/* Lends _gmean raw row y (0 <= y < height) as the caller already converted it: src[0, width)
 * must equal pc_dm_row_to_float's row y and stay valid until the next _gmean call returns, which
 * then does not convert the row (unless the band holds it already: then nothing happens). The
 * band keeps a copy of the row's ends only; _rows and a border row of _gmean convert the row
 * again. */
void pc_dm_bayer_first_band_put_row(pc_dm_bf_band *b, uint32_t y, const float *src);

#endif
