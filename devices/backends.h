/* devices/backends.h - internal: the backends' ops tables and enumerators, as the registry sees
 * them. Declared unconditionally; only devices/registry.c decides (with PC_HAVE_*) which of them
 * exist in this build. */
#ifndef POLARCAM_DEVICES_BACKENDS_H
#define POLARCAM_DEVICES_BACKENDS_H

#include "polarcam/source.h"

extern const pc_source_ops pc_sim_source_ops;
extern const pc_source_ops pc_file_source_ops;
extern const pc_source_ops pc_aravis_source_ops;
extern const pc_source_ops pc_v4l2_source_ops;
extern const pc_source_ops pc_libcamera_source_ops;

int pc_aravis_enumerate(unsigned flags, pc_device_fn fn, void *ctx);
int pc_v4l2_enumerate(unsigned flags, pc_device_fn fn, void *ctx);
int pc_libcamera_enumerate(unsigned flags, pc_device_fn fn, void *ctx);
int pc_usb3v_enumerate(pc_device_fn fn, void *ctx);

#endif
