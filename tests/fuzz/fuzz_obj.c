/* libFuzzer harness: Wavefront OBJ meshes (pc_obj_load, then the BVH build), with smoothing on
 * or off from the last byte. A mesh that loads has finite vertices and in-range indices. */
#include <math.h>

#include "fuzz.h"
#include "polarcam/error.h"
#include "scene_impl.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	const char *p = fuzz_file("in.obj", data, size);
	pc_m3 rot = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
	pc_mesh *m = NULL;
	bool smooth = size && (data[size - 1] & 1);
	if (pc_obj_load(p, &rot, v3(1, 1, 1), v3(0, 0, 0), smooth, &m) != 0) {
		FUZZ_ASSERT(m == NULL && strstr(pc_error_detail(), "in.obj"), "%s",
		            pc_error_detail());
		return 0;
	}
	for (unsigned i = 0; i < m->n_vertices; i++)
		FUZZ_ASSERT(isfinite(m->v[i].x) && isfinite(m->v[i].y) && isfinite(m->v[i].z),
		            "vertex %u", i);
	for (unsigned t = 0; t < 3 * m->n_triangles; t++)
		FUZZ_ASSERT(m->tri[t] < m->n_vertices, "triangle index %u", t / 3);
	if (pc_bvh_build(m) == 0)
		FUZZ_ASSERT(m->nodes != NULL, "no BVH");
	pc_mesh_free(m);
	return 0;
}
