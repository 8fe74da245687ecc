/* Helpers shared by the calibration steps (calib.c, ecm.c). */
#ifndef POLARCAM_CALIB_INTERNAL_H
#define POLARCAM_CALIB_INTERNAL_H

#include <stddef.h>

#include "polarcam/calib.h"

/* The analog gain the n stacks share (their gain_db; NAN when none says): PC_EINVAL naming two
 * stacks at different known gains ("STEP: A is at X dB of analog gain, B at Y dB: the
 * recordings need one gain (vary VARY, not the gain)"). Stacks of unknown gain match any. */
int pc_calib_one_gain(const pc_calib_stack *s, size_t n, const char *step, const char *vary,
                      double *gain_db);

/* The factor of base's dark map at the analog gain gain_db of WHAT (e.g. "flat: recordings", "a
 * frame"; pc_calib_dark_scale; 1 without a base) into *r: PC_EINVAL naming it and both gains
 * when the factor is out of range (10^(dB/20) over- or underflowing) */
int pc_calib_base_dark_scale(const pc_calib *base, double gain_db, const char *what, double *r);

/* The dark (or, without a dark map, the black level) of pixel p of c (NULL: 0) at the analog
 * gain whose pc_calib_dark_scale is r: the map's part above the black level times r */
static inline double pc_calib_dark_at(const pc_calib *c, size_t p, double r)
{
	if (!c)
		return 0;
	if (!c->dark)
		return c->black_level;
	return r != 1 ? c->black_level + r * ((double)c->dark[p] - c->black_level)
	              : (double)c->dark[p];
}

#endif
