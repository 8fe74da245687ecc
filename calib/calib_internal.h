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

#endif
