/* libFuzzer harness: calibration files (pc_calib_read: a NumPy .npz, i.e. a zip of .npy members
 * with JSON metadata; docs/calibration.md). A file that reads has a sane geometry (even, at
 * least 4×4, within the pixel limit), the maps its parts declare, finite values and positive
 * gains where it promises them, a system gain that is 0 (unknown) or finite and positive, and
 * can be checked against its own geometry. */
#include <math.h>

#include "fuzz.h"
#include "polarcam/calib.h"
#include "polarcam/error.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *p = fuzz_file("in.npz", data, size);
	pc_calib c;
	if (pc_calib_read(p, &c) != 0) {
		FUZZ_ASSERT(strstr(pc_error_detail(), "in.npz"), "%s", pc_error_detail());
		return 0;
	}
	const pc_calib_geometry *g = &c.geo;
	FUZZ_ASSERT(g->width >= 4 && g->height >= 4 && g->width % 2 == 0 && g->height % 2 == 0 &&
	                (uint64_t)g->width * g->height <= pc_limit_get(PC_LIMIT_PIXELS),
	            "%ux%u", g->width, g->height);
	const size_t n = (size_t)g->width * g->height;
	FUZZ_ASSERT(!(c.parts & PC_CAL_DARK) || (c.dark && c.dark_noise), "dark maps");
	FUZZ_ASSERT(!(c.parts & PC_CAL_FLAT) || c.gain, "gain map");
	FUZZ_ASSERT(!(c.parts & PC_CAL_ANALYSER) || (c.analysis && c.pinv_sp), "analyser maps");
	FUZZ_ASSERT(c.system_gain == 0 || (isfinite(c.system_gain) && c.system_gain > 0),
	            "system gain %g", c.system_gain);
	FUZZ_ASSERT(isnan(c.system_gain_db) || (c.system_gain > 0 && fabs(c.system_gain_db) <= 100),
	            "system gain's dB %g (system gain %g)", c.system_gain_db, c.system_gain);
	{
		/* the noise gain at any frame gain: 0 without a system gain, else finite and > 0 */
		const double ng = pc_calib_noise_gain(&c, 40, NULL);
		FUZZ_ASSERT(c.system_gain > 0 ? isfinite(ng) && ng > 0 : ng == 0,
		            "noise gain %g at 40 dB", ng);
		/* the dark frames' gain only with a dark map, and its scale at any frame gain
		 * finite and > 0 */
		FUZZ_ASSERT(isnan(c.dark_gain_db) || (c.dark && fabs(c.dark_gain_db) <= 100),
		            "dark gain %g dB", c.dark_gain_db);
		const double dr = pc_calib_dark_scale(&c, -40, NULL);
		FUZZ_ASSERT(isfinite(dr) && dr > 0, "dark scale %g at -40 dB", dr);
	}
	for (size_t i = 0; i < n; i++) {
		FUZZ_ASSERT(!c.dark || isfinite(c.dark[i]), "dark[%zu]", i);
		FUZZ_ASSERT(!c.gain || c.gain[i] > 0, "gain[%zu]", i);
		if (c.valid)
			(void)fuzz_touch(c.valid + i, 1, 1, 1);
	}
	if (c.pinv_sp)
		(void)fuzz_touch(c.pinv_sp, (size_t)(g->width / 2) * (g->height / 2) * 12 * 4, 0,
		                 1);
	FUZZ_ASSERT(pc_calib_check(&c, g) == 0, "own geometry refused: %s", pc_error_detail());
	pc_calib_free(&c);
	return 0;
}
