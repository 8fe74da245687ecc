/* tools/source_cli.h - what the device commands (capture, view, devices, bench devices) share:
 * JSON for formats and statistics, and opening a source with the user's format, ROI and
 * controls, refusing (never silently accepting) what the source would adjust. */
#ifndef CLI_TOOLS_SOURCE_CLI_H
#define CLI_TOOLS_SOURCE_CLI_H

#include <jansson.h>
#include <stdbool.h>

#include "polarcam/source.h"

json_t *cli_json_source_stats(const pc_source_stats *st);
json_t *cli_json_source_format(const pc_source_format *f);

/* Options common to the commands that stream. */
typedef struct cli_stream_args {
	const char *uri;
	const char *format; /* --format NAME */
	bool roi_set;       /* --roi X,Y,W,H */
	uint32_t roi[4];
	double exposure_us, gain_db, fps; /* < 0: leave alone */
	unsigned buffers;                 /* --buffers (default 8) */
	int timeout_ms;                   /* --timeout-ms (default 5000) */
} cli_stream_args;

void cli_stream_args_init(cli_stream_args *a);
/* Consumes argv[*i] (and its value) if it is one of the options above: returns 1 when
 * consumed, 0 when not one of ours, or a negative error (detail set, naming the option). */
int cli_stream_args_parse(cli_stream_args *a, int argc, char **argv, int *i);
/* Help text lines for those options. */
const char *cli_stream_args_help(void);

/* Opens the source, negotiates format/ROI (an adjusted answer is an error that shows what the
 * source proposes), sets the controls, allocates the buffers. The source is READY. */
int pc_stream_open(const cli_stream_args *a, pc_source **out);

#endif

/* ---- live processing: a raw frame -> S0, DoLP, AoLP -> one picture of three panels ---- */
#include "polarcam/demosaic.h"
#include "polarcam/stokes.h"

typedef struct pc_live {
	pc_demosaic_method method;
	uint32_t w, h; /* output size of the method */
	float *planes; /* s0, dolp, aolp (each w*h) */
	pc_stokes_out out;
	uint8_t *rgb;     /* 3 panels side by side: (3w) x h RGB8 */
	double process_s; /* time of the last pc_stokes_from_raw */
} pc_live;

/* Runs the pipeline on a frame (which must carry a polarizer mosaic). Sizes follow the frame. */
int pc_live_process(pc_live *lv, const pc_frame *f);
/* Draws S0 (grey, 0 to the 99.9th percentile), DoLP (grey, 0..1) and AoLP (hue = AoLP,
 * value = DoLP) side by side into lv->rgb ((3w) x h, stride 9w). */
int pc_live_compose(pc_live *lv);
void pc_live_free(pc_live *lv);
