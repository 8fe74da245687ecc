/* simframes.c - renders simulated raw mosaic frames on the host for the QEMU guest.
 *
 *   pc_guest_simframes OUTDIR N SEED
 *
 * Renders the built-in default scene (IMX250MZR-class sensor, 2448x2048) through the simulator
 * (polarcam/sim.h) and writes frames 0..N-1 as OUTDIR/sim_K.raw: rows of little-endian uint16
 * values (the sensor's bits, LSB-aligned), width * 2 bytes per row, no header; OUTDIR/sim.txt
 * holds "WIDTH HEIGHT BITS N SEED". Rendering takes seconds natively but minutes under the
 * guest's software emulation, so it happens here and the frames travel in the initramfs; the
 * guest sends them through vivid's output and compares what comes back through `v4l2:`.
 * Files are written to temporary names and renamed, so an interrupted run leaves none.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/io.h"
#include "polarcam/sim.h"

static int fail(const char *what, int rc)
{
	fprintf(stderr, "simframes: %s: %s (%s)\n", what, pc_strerror(rc), pc_error_detail());
	return 1;
}

int main(int argc, char **argv)
{
	if (argc != 4) {
		fprintf(stderr, "usage: %s OUTDIR N SEED\n", argv[0]);
		return 2;
	}
	const char *dir = argv[1];
	int n = atoi(argv[2]);
	unsigned long long seed = strtoull(argv[3], NULL, 10);
	if (n < 1 || n > 16) {
		fprintf(stderr, "simframes: N = %s: expected 1..16\n", argv[2]);
		return 2;
	}
	int rc = pc_mkdir_p(dir);
	if (rc)
		return fail(dir, rc);
	pc_scene *scene = NULL;
	pc_sim *sim = NULL;
	rc = pc_scene_load_default(&scene);
	if (rc)
		return fail("default scene", rc);
	pc_sim_options opt = pc_sim_options_default();
	opt.seed = seed;
	rc = pc_sim_new(scene, &opt, &sim);
	pc_scene_free(scene);
	if (rc)
		return fail("pc_sim_new", rc);
	pc_sim_info info;
	pc_sim_get_info(sim, &info);
	pc_view v;
	rc = pc_view_alloc(&v, info.format, info.width, info.height, 64);
	if (rc)
		return fail("frame", rc);
	size_t row = (size_t)info.width * 2;
	uint16_t *u16 = malloc(row * info.height);
	if (!u16)
		return fail("frame", PC_ENOMEM);
	for (int k = 0; k < n; k++) {
		pc_frame_meta meta;
		rc = pc_sim_frame(sim, (uint64_t)k, NULL, &v, &meta);
		if (!rc)
			rc = pc_view_to_u16(&v, u16, row);
		if (rc)
			return fail("pc_sim_frame", rc);
		char path[4096];
		snprintf(path, sizeof path, "%s/sim_%d.raw", dir, k);
		/* uint16 little-endian on disk; this host is little-endian (x86-64), as is the
		 * guest */
		rc = pc_write_file_atomic(path, u16, row * info.height);
		if (rc)
			return fail(path, rc);
	}
	char text[128], path[4096];
	int len = snprintf(text, sizeof text, "%u %u %u %d %llu\n", info.width, info.height,
	                   info.bits, n, seed);
	snprintf(path, sizeof path, "%s/sim.txt", dir);
	rc = pc_write_file_atomic(path, text, (size_t)len);
	if (rc)
		return fail(path, rc);
	printf("simframes: %d frames %ux%u, %u bits, seed %llu in %s\n", n, info.width, info.height,
	       info.bits, seed, dir);
	free(u16);
	pc_view_free(&v);
	pc_sim_free(sim);
	return 0;
}
