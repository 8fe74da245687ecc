/* libFuzzer harness: scene JSON (pc_scene_parse; OBJ files it names are looked up in the scratch
 * directory and usually missing). A scene that parses is rendered: an 8×8 region of interest
 * (any camera, lights, materials and effects, at the cost of 64 pixels), state 0 with its Stokes
 * ground truth, then frame 0. Properties: S0, S1, S2 of the truth are finite (S3 too when the
 * scene declares "circular"), S0 ≥ 0, and every raw value fits the sensor's bit depth. */
#include <math.h>

#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/frame.h"
#include "polarcam/sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char *text = fuzz_text(data, size);
	pc_scene *scene = NULL;
	int rc = pc_scene_parse(text, "fuzz.json", fuzz_dir(), &scene);
	free(text);
	if (rc) {
		FUZZ_ASSERT(scene == NULL, "scene set on failure");
		FUZZ_ASSERT(strstr(pc_error_detail(), "fuzz.json") || rc == PC_ENOMEM, "%s",
		            pc_error_detail());
		return 0;
	}
	pc_sim_options o = pc_sim_options_default();
	o.threads = 1;
	o.roi_width = o.roi_height = 8;
	pc_sim *sim = NULL;
	if (pc_sim_new(scene, &o, &sim) == 0) {
		pc_sim_info in;
		pc_sim_get_info(sim, &in);
		const size_t n = (size_t)in.width * in.height * in.colour_channels * 4;
		float *ts = malloc(n * sizeof *ts);
		FUZZ_ASSERT(ts, "malloc");
		if (pc_sim_prepare(sim, 0, ts, NULL, NULL, NULL) == 0) {
			const bool circ = in.effects & PC_FX_CIRCULAR;
			for (size_t i = 0; i < n; i += 4) {
				FUZZ_ASSERT(isfinite(ts[i]) && ts[i] >= 0 && isfinite(ts[i + 1]) &&
				                isfinite(ts[i + 2]) &&
				                (!circ || isfinite(ts[i + 3])),
				            "truth pixel %zu: %g %g %g %g", i / 4, ts[i], ts[i + 1],
				            ts[i + 2], ts[i + 3]);
			}
			pc_view v;
			if (pc_view_alloc(&v, in.format, in.width, in.height, 1) == 0) {
				pc_frame_meta meta;
				if (pc_sim_frame(sim, 0, NULL, &v, &meta) == 0)
					FUZZ_ASSERT(pc_view_check_bits(&v, in.bits) == 0, "%s",
					            pc_error_detail());
				pc_view_free(&v);
			}
		}
		free(ts);
		pc_sim_free(sim);
	}
	pc_scene_free(scene);
	return 0;
}
