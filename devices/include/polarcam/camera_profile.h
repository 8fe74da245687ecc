/* polarcam/camera_profile.h - what polarcam knows about polarization cameras that their GenICam
 * description does not say: which raw pixel formats carry the polarizer mosaic, the ADC bit
 * depth and the mosaic layout at sensor pixel (0,0) (before ROI offsets and ReverseX/Y).
 *
 * Sources (docs/hardware.md): LUCID Arena PolarizeMono* names; FLIR Spinnaker Polarized* and
 * BayerRGPolarized* names; Basler's polarized models use the standard Mono* names. All IMX250MZR
 * cameras listed read out [90 45; 135 0] at the top-left; the colour-polarization IMX250MYR
 * cameras (LUCID TRI050S-Q, FLIR BFS-U3-51S5PC) put those 2x2 blocks under an RGGB Bayer
 * pattern ("RGGB:90,45,135,0", polarcam/mosaic.h). */
#ifndef POLARCAM_CAMERA_PROFILE_H
#define POLARCAM_CAMERA_PROFILE_H

#include <stdbool.h>

#include "polarcam/export.h"
#include "polarcam/format.h"
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
PC_API const pc_camera_profile *pc_camera_profile_find(const char *vendor, const char *model);

/* True when name is listed in the profile's raw formats. */
PC_API bool pc_camera_profile_has_format(const pc_camera_profile *p, const char *name);

/* What a camera's pixel format, identified by its GenICam enumeration NAME, delivers. */
typedef struct pc_camera_format {
	pc_pixfmt format;        /* the raw container (BayerRGPolarized12p: PC_FMT_MONO12P) */
	bool polarized;          /* the pixels lie under the polarizer mosaic */
	bool colour;             /* ... with a colour filter on top (sensor_mosaic has period 4) */
	pc_mosaic sensor_mosaic; /* at sensor pixel (0,0), before ReverseX/Y and the ROI offset */
} pc_camera_format;

/* Maps a pixel format name of a camera with profile p (NULL: unknown camera) to its raw format
 * and mosaic. Only the name decides, never the enumeration value: vendors' custom values collide
 * with each other and with Aravis's (LUCID's PolarizeMono16 is Aravis's CUSTOM_BAYER_RG_16).
 * The mosaic is mosaic_override (the user's, may be NULL), else the profile's, else IMX250MZR
 * (IMX250MYR for colour names). A BayerRGPolarized* name over a monochrome layout puts that
 * layout's 2x2 blocks under RGGB with red at sensor pixel (0,0), as the name says.
 * Errors: those of pc_format_from_genicam (PC_ENOTSUP for colour or processed formats without
 * a raw mosaic, PC_EINVAL for unknown names), PC_EINVAL for an invalid override. */
PC_API int pc_camera_format_get(const pc_camera_profile *p, const char *name,
                                const pc_mosaic *mosaic_override, pc_camera_format *out);

/* The table, NULL-terminated by an entry with vendor NULL. */
PC_API const pc_camera_profile *pc_camera_profiles(void);

#ifdef __cplusplus
}
#endif
#endif
