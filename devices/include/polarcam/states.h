/* polarcam/states.h - states.json: the polarization states of a frame sequence, for Mueller
 * imaging (docs/scene-format.md, "Frame sequences"). `polarcam render` writes it beside the
 * frames of a scene with state sequences; `polarcam mueller` reads it.
 *
 *   { "polarcam_states": 1, "frame_order": "psg_fastest",
 *     "n_psg": G, "n_psa": A,
 *     "psg": [[S0, S1, S2, S3], ...],          G generator Stokes vectors (normalized, S0 = 1)
 *     "psa": [[[4 x 4]], ...],                A analyser-element Mueller matrices
 *     "layout": "90,45,135,0",                the frames' mosaic (optional)
 *     "analyser": [[4], [4], [4], [4]] }      the channel analyser rows (optional: ideal)
 *
 * Frame j was taken under generator state j mod G and analyser state j / G.
 */
#ifndef POLARCAM_STATES_H
#define POLARCAM_STATES_H

#include <stddef.h>

#include "polarcam/export.h"
#include "polarcam/mosaic.h"
#include "polarcam/sim.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Writes st (and the frames' mosaic, may be NULL) as path, atomically. */
PC_API int pc_states_write(const char *path, const pc_sim_states *st, const pc_mosaic *mosaic);

/* Reads path into st; layout (may be NULL) receives the "layout" string ("" when absent). A
 * file without "analyser" gets the ideal rows ½(1, cos 2θ, sin 2θ, 0). Errors name the file and
 * the field (PC_EFORMAT; PC_ENOENT when it cannot be opened). */
PC_API int pc_states_read(const char *path, pc_sim_states *st, char *layout, size_t layout_size);

#ifdef __cplusplus
}
#endif
#endif
