/* tools/source_cli.h - the stream options of the device commands (capture, view): the source
 * URI, format, ROI, controls, buffers and timeout, parsed into a pc_stream_request
 * (polarcam/stream.h). */
#ifndef CLI_TOOLS_SOURCE_CLI_H
#define CLI_TOOLS_SOURCE_CLI_H

#include "polarcam/stream.h"

typedef struct cli_stream_args {
	pc_stream_request req; /* uri, --format, --roi, --exposure, --gain, --fps, --buffers */
	int timeout_ms;        /* --timeout-ms (default 5000) */
} cli_stream_args;

void cli_stream_args_init(cli_stream_args *a);
/* Consumes argv[*i] (and its value) if it is one of the options above: returns 1 when
 * consumed, 0 when not one of ours, or a negative error (detail set, naming the option). */
int cli_stream_args_parse(cli_stream_args *a, int argc, char **argv, int *i);
/* Help text lines for those options. */
const char *cli_stream_args_help(void);

/* The levels of a live stream (polarcam/stream.h): --black-level DN, --saturation DN|none,
 * --dead-level DN, --calibration FILE, --noise-gain G. Same contract as cli_stream_args_parse. */
int cli_levels_parse(pc_stream_levels *lv, int argc, char **argv, int *i);
const char *cli_levels_help(void);

#endif
