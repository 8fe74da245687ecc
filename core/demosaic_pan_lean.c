/* pan-lean's row kernels (demosaic_pan_lean.inc) for pan_band's fifth mode (demosaic_pan.c), in
 * their own translation unit so that it compiles beside demosaic_pan.c (each is among the
 * longest of the library's to compile, the sanitizer build's most of all). */
#include <float.h>
#include <math.h>

#include "demosaic_pan.h"
#include "demosaic_pan_kargs.h"
#include "simd.h"

#define PC_INST PC_INST_BASELINE
#include "simd_instance_begin.h"
#include "demosaic_pan_lean.inc"
#include "simd_instance_end.h"

#ifdef PC_CPU_X86
#define PC_INST PC_INST_AVX2
#include "simd_instance_begin.h"
#include "demosaic_pan_lean.inc"
#include "simd_instance_end.h"

#define PC_INST PC_INST_AVX512
#include "simd_instance_begin.h"
#include "demosaic_pan_lean.inc"
#include "simd_instance_end.h"
#endif
