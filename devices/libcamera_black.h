/* devices/libcamera_black.h - internal (C++): the black level a libcamera frame declares, for
 * devices/libcamera_source.cpp and its test (tests/test_libcamera_black.cpp). */
#ifndef POLARCAM_DEVICES_LIBCAMERA_BLACK_H
#define POLARCAM_DEVICES_LIBCAMERA_BLACK_H

#include <libcamera/controls.h>

/* The black level in a request's metadata, in DN of delivered samples of `bits` significant
 * bits (1..16): controls::SensorBlackLevels holds four levels, in the order R, Gr, Gb, B,
 * "returned as numbers out of a 16-bit pixel range (as if pixels ranged from 0 to 65535)"
 * (libcamera's control_ids.yaml, 0.0.3), so DN = level / 2^(16 - bits). A polarization sensor
 * has no colour filter: the four are one level on a monochrome sensor, and their mean is taken
 * when they differ (pc_source_info holds one level). False (and *dn untouched) when the metadata
 * has no SensorBlackLevels, bits is out of range, or the mean is not above 0 (no level
 * declared, as for the other sources). */
bool pc_libcamera_black_level_dn(const libcamera::ControlList &metadata, unsigned bits, double *dn);

#endif
