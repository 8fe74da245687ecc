/* polarcam/process_recording.h - a recording's frames through the pipeline (what `polarcam
 * process REC_DIR` does): pc_process_files (polarcam/process.h) over the frames meta.json lists,
 * each named by the number of its file (raw_000012.png gives stokes_000012.npy, ...).
 */
#ifndef POLARCAM_PROCESS_RECORDING_H
#define POLARCAM_PROCESS_RECORDING_H

#include "polarcam/export.h"
#include "polarcam/process.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The frames of the recording rec_dir (pc_recording_open: meta.json, or raw_NNNNNN.png alone)
 * into the Stokes folder dir, as pc_process_files with b's stack, pictures_every and progress
 * (its inputs, count and numbers are the recording's). o->mosaic is used as given: take the
 * recording's with pc_recording_frame_mosaic. PC_EFORMAT for a recording without a polarizer
 * mosaic, PC_EINVAL for one without frames. */
PC_API int pc_process_recording(const char *rec_dir, const pc_process_batch *b,
                                const pc_process_opts *o, const char *dir,
                                const pc_stokes_folder_opts *folder, char **meta);

#ifdef __cplusplus
}
#endif
#endif
