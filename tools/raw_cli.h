/* tools/raw_cli.h - the raw-input options shared by polarcam demosaic and process: the file,
 * its geometry when headerless, its bit depth, the mosaic layout, the method. */
#ifndef CLI_TOOLS_RAW_CLI_H
#define CLI_TOOLS_RAW_CLI_H

#include <stdbool.h>

#include "polarcam/calib.h"
#include "polarcam/demosaic.h"
#include "polarcam/io.h"
#include "polarcam/process.h"

typedef struct cli_raw {
	const char *path;   /* RAW (the first, with several) */
	const char **paths; /* every RAW given (malloc'd when many files are allowed) */
	size_t npaths;
	const char *out;    /* -o */
	const char *layout; /* --layout (default: RAW's recording's meta.json, or 90,45,135,0) */
	const char *method; /* --method (default bilinear; bayer-first for colour layouts) */
	unsigned bits;      /* --bits (0: from the file) */
	int threads;        /* --threads (0: all) */
	bool reference;     /* --reference */
	bool have_geometry; /* --width/--height/--format given */
	double black_level; /* --black-level (NAN: the recording's, else 0) */
	double saturation;  /* --saturation (0: the raw's full scale; -1: none) */
	double dead;        /* --dead-level (0: none) */
	double noise_gain;  /* --noise-gain (0: estimated from each frame) */
	const char *calibration; /* --calibration FILE */
	const char *black_from;  /* "option", "recording", "calibration" or "none" */
	uint32_t roi_x, roi_y;   /* the recording's ROI origin */
	pc_raw_geometry geometry;
	/* resolved */
	char layout_buf[64];
	pc_mosaic mosaic;
	pc_demosaic_method dm;
} cli_raw;

/* Help text of the shared options, for the commands' usage(). */
extern const char cli_raw_help[];

/* Parses argv (argv[0] = command). Options it does not know are returned through *extra (argv
 * indices, NULL-terminated list allocated by the caller with argc entries) when extra is not
 * NULL, otherwise they are errors. With many, several RAW files (or a recording folder) are
 * taken into o->paths; free them with cli_raw_free. Returns 0 or a CLI_EXIT_* status after
 * printing the error. */
int cli_raw_parse(int argc, char **argv, cli_raw *o, int *extra, bool many);
void cli_raw_free(cli_raw *o);

/* The parsed options as the library takes them (polarcam/process.h). With --calibration, the
 * file is read into *cal (pc_calib_read; free with pc_calib_free) and the stage put in *stage
 * and the options; returns 0 or a CLI_EXIT_* status after printing the error. */
pc_raw_input cli_raw_input(const cli_raw *o);
pc_process_opts cli_raw_process(const cli_raw *o);
int cli_raw_calibration(const cli_raw *o, pc_calib *cal, pc_raw_stage *stage, pc_process_opts *po);

#endif
