/* A recording's frames through the pipeline (polarcam/process_recording.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/process_recording.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/recording.h"

int pc_process_recording(const char *rec_dir, const pc_process_batch *b, const pc_process_opts *o,
                         const char *dir, const pc_stokes_folder_opts *folder, char **meta)
{
	if (meta)
		*meta = NULL;
	if (!rec_dir || !b || !o || !dir || !folder)
		return pc_error(PC_EINVAL, "process: missing argument");
	pc_recording *r = NULL;
	int rc = pc_recording_open(&r, rec_dir);
	if (rc)
		return rc;
	const pc_recording_desc *d = pc_recording_get_desc(r);
	size_t n = pc_recording_count(r);
	if (!d->polarized)
		rc = pc_error(PC_EFORMAT, "%s: the recording's frames carry no polarizer mosaic",
		              rec_dir);
	else if (!n)
		rc = pc_error(PC_EINVAL, "%s: the recording holds no frame", rec_dir);
	pc_raw_input *in = rc ? NULL : calloc(n, sizeof *in);
	uint64_t *num = rc ? NULL : calloc(n, sizeof *num);
	char **paths = rc ? NULL : calloc(n, sizeof *paths);
	pc_frame_meta *fm = rc ? NULL : calloc(n, sizeof *fm);
	if (!rc && (!in || !num || !paths || !fm))
		rc = pc_error(PC_ENOMEM, "%s: %zu frames", rec_dir, n);
	for (size_t i = 0; !rc && i < n; i++) {
		const char *file = pc_recording_get_frame(r, i)->file;
		size_t len = strlen(rec_dir) + strlen(file) + 2;
		if (!(paths[i] = malloc(len))) {
			rc = pc_error(PC_ENOMEM, "%s", rec_dir);
			break;
		}
		snprintf(paths[i], len, "%s/%s", rec_dir, file);
		/* raw_NNNNNN.png (the reader checked the name) */
		num[i] = strtoull(file + 4, NULL, 10);
		/* the frame's exposure and analog gain (a calibration's noise gain follows it) */
		const pc_recording_frame *rf = pc_recording_get_frame(r, i);
		fm[i] = (pc_frame_meta){.sequence = rf->sequence,
		                        .timestamp_ns = rf->timestamp_ns,
		                        .exposure_us = rf->exposure_us,
		                        .gain_db = rf->gain_db,
		                        .status = rf->status,
		                        .offset_x = d->offset_x,
		                        .offset_y = d->offset_y};
		in[i] = (pc_raw_input){paths[i], NULL, 0, &fm[i]};
	}
	if (!rc) {
		pc_process_batch rb = *b;
		rb.inputs = in;
		rb.count = n;
		rb.numbers = num;
		rc = pc_process_files(&rb, o, dir, folder, meta);
	}
	for (size_t i = 0; paths && i < n; i++)
		free(paths[i]);
	free(paths);
	free(fm);
	free(num);
	free(in);
	pc_recording_free(r);
	return rc;
}
