/* polarcam/camera_profile.h - what polarcam knows about polarization cameras that their GenICam
 * description does not say: which raw pixel formats carry the polarizer mosaic, the ADC bit
 * depth and the mosaic layout at sensor pixel (0,0) (before ROI offsets and ReverseX/Y).
 *
 * Sources (hardware.md): LUCID Arena PolarizeMono* names; FLIR Spinnaker Polarized* names;
 * Basler's polarized models use the standard Mono* names. All IMX250MZR cameras listed read out
 * [90 45; 135 0] at the top-left. */
#ifndef POLARCAM_CAMERA_PROFILE_H
#define POLARCAM_CAMERA_PROFILE_H

#include <stdbool.h>

#include "polarcam/mosaic.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pc_camera_profile {
	const char *vendor;      /* matched case-insensitively as a prefix of the device's vendor */
	const char *model;       /* model prefix ("PHX050S-P"); "" matches every model */
	const char *sensor;      /* "IMX250MZR" */
	const char *raw_formats; /* comma-separated GenICam names carrying the mosaic */
	unsigned bits;           /* ADC bits */
	const char *mosaic;      /* layout for pc_mosaic_parse at sensor pixel (0,0) */
} pc_camera_profile;

/* The profile for a device, or NULL when polarcam knows none (then a polarized pixel-format
 * name alone still marks the data as a mosaic, with the IMX250MZR layout). */
const pc_camera_profile *pc_camera_profile_find(const char *vendor, const char *model);

/* True when name is listed in the profile's raw formats. */
bool pc_camera_profile_has_format(const pc_camera_profile *p, const char *name);

/* The table, NULL-terminated by an entry with vendor NULL. */
const pc_camera_profile *pc_camera_profiles(void);

#ifdef __cplusplus
}
#endif
#endif
