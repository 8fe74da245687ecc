#include "source_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "polarcam/error.h"

void cli_stream_args_init(cli_stream_args *a)
{
	pc_stream_request_init(&a->req);
	a->timeout_ms = 5000;
}

const char *cli_stream_args_help(void)
{
	return "  --format NAME       pixel format by its GenICam name (Mono12, PolarizeMono12p, "
	       "...)\n"
	       "  --roi X,Y,W,H       region of interest on the sensor (odd offsets shift the "
	       "mosaic)\n"
	       "  --exposure US       exposure time in microseconds\n"
	       "  --gain DB           gain in dB (the camera's Gain feature)\n"
	       "  --fps F             frame rate\n"
	       "  --buffers N         frames the source can fill ahead (default 8)\n"
	       "  --timeout-ms MS     longest wait for a frame (default 5000)\n";
}

int cli_stream_args_parse(cli_stream_args *a, int argc, char **argv, int *i)
{
	const char *o = argv[*i];
	static const char *const ours[] = {"--format", "--roi",     "--exposure",   "--gain",
	                                   "--fps",    "--buffers", "--timeout-ms", NULL};
	bool mine = false;
	for (const char *const *p = ours; *p; p++)
		mine |= !strcmp(o, *p);
	if (!mine)
		return 0;
	if (*i + 1 >= argc)
		return pc_error(PC_EINVAL, "%s needs a value", o);
	const char *v = argv[++*i];
	long l;
	int rc = 0;
	if (!strcmp(o, "--format")) {
		a->req.format = v;
	} else if (!strcmp(o, "--roi")) {
		unsigned long r[4];
		char tail;
		if (sscanf(v, "%lu,%lu,%lu,%lu%c", &r[0], &r[1], &r[2], &r[3], &tail) != 4 ||
		    strchr(v, '-') || r[0] > 1u << 20 || r[1] > 1u << 20 || r[2] < 1 ||
		    r[2] > 1u << 20 || r[3] < 1 || r[3] > 1u << 20)
			return pc_error(PC_EINVAL, "--roi '%s': expected X,Y,W,H (W, H >= 1)", v);
		for (int k = 0; k < 4; k++)
			a->req.roi[k] = (uint32_t)r[k];
		a->req.roi_set = true;
	} else if (!strcmp(o, "--exposure")) {
		rc = cli_parse_double(o, v, &a->req.exposure_us);
		if (!rc && a->req.exposure_us <= 0)
			rc = pc_error(PC_EINVAL, "--exposure %s: expected > 0", v);
	} else if (!strcmp(o, "--gain")) {
		rc = cli_parse_double(o, v, &a->req.gain_db);
		if (!rc && a->req.gain_db < 0)
			rc = pc_error(PC_EINVAL, "--gain %s: expected >= 0", v);
	} else if (!strcmp(o, "--fps")) {
		rc = cli_parse_double(o, v, &a->req.fps);
		if (!rc && a->req.fps <= 0)
			rc = pc_error(PC_EINVAL, "--fps %s: expected > 0", v);
	} else if (!strcmp(o, "--buffers")) {
		rc = cli_parse_long(o, v, 1, 64, &l);
		a->req.buffers = (unsigned)l;
	} else if (!strcmp(o, "--timeout-ms")) {
		rc = cli_parse_long(o, v, 1, 3600000, &l);
		a->timeout_ms = (int)l;
	}
	return rc ? rc : 1;
}

const char *cli_levels_help(void)
{
	return "  --black-level DN    subtracted from every raw value (default: what the source\n"
	       "                      declares - the simulator's sensor offset, a recording's\n"
	       "                      meta.json - else 0)\n"
	       "  --saturation DN|none  pixels whose value depends on a sample >= DN are invalid,\n"
	       "                      counted and marked with a pink checker (default: full scale\n"
	       "                      2^bits - 1, or the calibration's)\n"
	       "  --dead-level DN     likewise for samples <= DN (default: not checked)\n"
	       "  --calibration FILE  a `polarcam calibrate` file: dark, gain, calibrated\n"
	       "                      analysers; refused unless the frames match it\n"
	       "  --noise-gain DN_PER_E  the noise gain of noise-aware methods (ratio-nr; see\n"
	       "                      `polarcam demosaic --list`). Default: the calibration's\n"
	       "                      system gain, scaled to each frame's analog gain when both\n"
	       "                      are known, else estimated from each frame\n";
}

int cli_levels_parse(pc_stream_levels *lv, int argc, char **argv, int *i)
{
	const char *o = argv[*i];
	if (strcmp(o, "--black-level") && strcmp(o, "--saturation") && strcmp(o, "--dead-level") &&
	    strcmp(o, "--calibration") && strcmp(o, "--noise-gain"))
		return 0;
	if (*i + 1 >= argc)
		return pc_error(PC_EINVAL, "%s needs a value", o);
	const char *v = argv[++*i];
	if (!strcmp(o, "--calibration")) {
		lv->calibration = v;
		return 1;
	}
	if (!strcmp(o, "--saturation") && !strcmp(v, "none")) {
		lv->saturation_level = -1;
		return 1;
	}
	double d;
	int rc = cli_parse_double(o, v, &d);
	if (rc)
		return rc;
	if (!strcmp(o, "--noise-gain")) {
		if (!(d > 0) || !isfinite(d))
			return pc_error(
			    PC_EINVAL,
			    "--noise-gain %s: expected a finite gain > 0 (raw units per "
			    "electron)",
			    v);
		lv->noise_gain = d;
		return 1;
	}
	bool black = !strcmp(o, "--black-level");
	if (!(d >= 0) || (!black && !(d > 0)))
		return pc_error(PC_EINVAL, "%s %s: expected a level %s 0 in raw units", o, v,
		                black ? ">=" : ">");
	if (black)
		lv->black_level = d;
	else if (!strcmp(o, "--saturation"))
		lv->saturation_level = d;
	else
		lv->dead_level = d;
	return 1;
}
