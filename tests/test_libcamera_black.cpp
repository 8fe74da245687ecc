/* test_libcamera_black.cpp - the black level the `libcamera:` source declares, from the
 * per-frame metadata libcamera hands over (controls::SensorBlackLevels in a ControlList, built
 * here with libcamera's own control map, as a pipeline handler fills a request's metadata).
 * Expected values are worked by hand from the control's definition (control_ids.yaml: four
 * levels R, Gr, Gb, B "out of a 16-bit pixel range"), not by the code under test, and one is a
 * published figure: Raspberry Pi's IPA defaults to a level of 4096, commented there as "64 in
 * 10 bits scaled to 16 bits" (its controller/rpi/black_level.cpp).
 * What this does not test: that a real camera reports the control, and the source's dequeue
 * path that stores it (no raw-monochrome libcamera camera here; test_libcamera_stream skips). */
#include "check.h"

#include <libcamera/control_ids.h>
#include <libcamera/controls.h>

#include "libcamera_black.h"

using namespace libcamera;

static ControlList with_levels(int32_t r, int32_t gr, int32_t gb, int32_t b)
{
	ControlList md(controls::controls);
	md.set(controls::SensorBlackLevels, {r, gr, gb, b});
	return md;
}

int main()
{
	double dn = -1;

	/* Raspberry Pi's default: 4096 on the 16-bit scale is 64 DN of 10-bit samples */
	ControlList rpi = with_levels(4096, 4096, 4096, 4096);
	CHECK(rpi.contains(controls::SensorBlackLevels.id()));
	CHECK(pc_libcamera_black_level_dn(rpi, 10, &dn));
	CHECK_NEAR(dn, 64.0, 0);
	/* the same level for the other depths of the formats the source reads (R8, R12, R16) */
	CHECK(pc_libcamera_black_level_dn(rpi, 8, &dn));
	CHECK_NEAR(dn, 16.0, 0);
	CHECK(pc_libcamera_black_level_dn(rpi, 12, &dn));
	CHECK_NEAR(dn, 256.0, 0);
	CHECK(pc_libcamera_black_level_dn(rpi, 16, &dn));
	CHECK_NEAR(dn, 4096.0, 0);

	/* a level that is no whole DN at 12 bits: 4100 / 16 = 256.25 */
	CHECK(pc_libcamera_black_level_dn(with_levels(4100, 4100, 4100, 4100), 12, &dn));
	CHECK_NEAR(dn, 256.25, 0);

	/* four different levels: their mean, (3840 + 4096 + 4096 + 4352) / 4 = 4096 -> 256 DN */
	CHECK(pc_libcamera_black_level_dn(with_levels(3840, 4096, 4096, 4352), 12, &dn));
	CHECK_NEAR(dn, 256.0, 0);

	/* none declared: no control, zero, a negative mean; *dn is left alone */
	dn = -1;
	ControlList empty(controls::controls);
	CHECK(!pc_libcamera_black_level_dn(empty, 12, &dn));
	CHECK(!pc_libcamera_black_level_dn(with_levels(0, 0, 0, 0), 12, &dn));
	CHECK(!pc_libcamera_black_level_dn(with_levels(-16, -16, -16, -16), 12, &dn));
	/* a depth the 16-bit scale cannot express */
	CHECK(!pc_libcamera_black_level_dn(rpi, 0, &dn));
	CHECK(!pc_libcamera_black_level_dn(rpi, 17, &dn));
	CHECK_NEAR(dn, -1.0, 0);

	/* other metadata beside it changes nothing */
	ControlList md = with_levels(4096, 4096, 4096, 4096);
	md.set(controls::ExposureTime, 10000);
	md.set(controls::AnalogueGain, 2.0f);
	CHECK(pc_libcamera_black_level_dn(md, 10, &dn));
	CHECK_NEAR(dn, 64.0, 0);

	return pc_test_finish("test_libcamera_black");
}
