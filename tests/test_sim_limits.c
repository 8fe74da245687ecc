/* The simulator's limits and hostile scenes (issue 13): frame timestamps that cannot be
 * represented are refused instead of an undefined float → uint64 conversion (very low
 * frame_rate_hz, very large frame numbers; pc_sim_check_frames states the largest first frame),
 * the scene resolution is checked against POLARCAM_MAX_PIXELS, OBJ meshes against
 * POLARCAM_MAX_TRIANGLES with strict face tokens and finite placed vertices, and the memory a
 * render needs (pc_sim_memory_bytes, compared with its closed form) against what it may use. */
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "polarcam/sim.h"

static char dir[64];

static const char *scene_text(const char *sensor_extra, const char *objects)
{
	static char buf[4096];
	snprintf(
	    buf, sizeof buf,
	    "{\"polarcam_scene\": 1, \"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]"
	    ", \"focal_length_mm\": 12}, \"materials\": {\"m\": {\"n\": 1.5, \"k\": 0, \"sigma\": "
	    "0.2}}, \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], "
	    "\"irradiance_w_m2\": 100}], \"objects\": [%s], \"sensor\": {\"preset\": \"ideal\", "
	    "\"resolution\": [8, 8]%s}}",
	    objects ? objects
	            : "{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1], "
	              "\"material\": \"m\"}",
	    sensor_extra ? sensor_extra : "");
	return buf;
}

static pc_sim *make_sim(const char *text, pc_scene **scene_out)
{
	pc_scene *s = NULL;
	int rc = pc_scene_parse(text, "t.json", dir, &s);
	if (rc) {
		fprintf(stderr, "scene: %s\n", pc_error_detail());
		return NULL;
	}
	pc_sim_options o = pc_sim_options_default();
	o.threads = 1;
	pc_sim *sim = NULL;
	rc = pc_sim_new(s, &o, &sim);
	if (rc)
		fprintf(stderr, "sim: %s\n", pc_error_detail());
	*scene_out = s;
	return sim;
}

static void test_timestamps(void)
{
	pc_scene *s;
	/* 1e-300 Hz: frame 1 lies 1e309 s away */
	pc_sim *sim = make_sim(scene_text(", \"frame_rate_hz\": 1e-300", NULL), &s);
	CHECK(sim != NULL);
	if (!sim)
		return;
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	pc_view v;
	CHECK_EQ_INT(pc_view_alloc(&v, in.format, in.width, in.height, 1), 0);
	pc_frame_meta meta;
	CHECK_EQ_INT(pc_sim_frame(sim, 0, NULL, &v, &meta), 0);
	CHECK(meta.timestamp_ns == 0);
	CHECK_EQ_INT(pc_sim_frame(sim, 1, NULL, &v, &meta), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "timestamp") != NULL);
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 1), 0);
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 2), PC_ERANGE);
	pc_sim_free(sim);
	pc_scene_free(s);

	/* the default 30 Hz: the largest first frame the message states is accepted, one more is
	 * not; sequence numbers beyond INT64_MAX never */
	sim = make_sim(scene_text(NULL, NULL), &s);
	CHECK(sim != NULL);
	if (!sim) {
		pc_view_free(&v);
		return;
	}
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 999999), 0);
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 1000000), PC_ERANGE); /* PC_LIMIT_FRAMES */
	setenv("POLARCAM_MAX_FRAMES", "10", 1);
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 11), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "POLARCAM_MAX_FRAMES") != NULL);
	CHECK_EQ_INT(pc_sim_check_frames(sim, 0, 10), 0);
	unsetenv("POLARCAM_MAX_FRAMES");
	CHECK_EQ_INT(pc_sim_check_frames(sim, INT64_MAX, 1), PC_ERANGE);
	CHECK_EQ_INT(pc_sim_check_frames(sim, UINT64_MAX, 2), PC_ERANGE);
	const char *d = pc_error_detail(), *at = strstr(d, "at most ");
	CHECK(at != NULL);
	if (at) {
		unsigned long long maxf = strtoull(at + 8, NULL, 10);
		/* 2^63 ns at 30 Hz: 2.77e11 frames */
		CHECK(maxf > 276000000000ull && maxf < 277000000000ull);
		CHECK_EQ_INT(pc_sim_check_frames(sim, maxf, 2), 0);
		CHECK_EQ_INT(pc_sim_check_frames(sim, maxf + 1, 2), PC_ERANGE);
		CHECK_EQ_INT(pc_sim_frame(sim, maxf + 1, NULL, &v, &meta), 0);
		CHECK(meta.timestamp_ns < (1ull << 63));
		CHECK_EQ_INT(pc_sim_frame(sim, (uint64_t)INT64_MAX, NULL, &v, &meta), PC_ERANGE);
	}
	pc_view_free(&v);
	pc_sim_free(sim);
	pc_scene_free(s);
}

static void test_resolution_limit(void)
{
	pc_scene *s = NULL;
	setenv("POLARCAM_MAX_PIXELS", "63", 1);
	CHECK_EQ_INT(pc_scene_parse(scene_text(NULL, NULL), "t.json", dir, &s), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "sensor.resolution") &&
	      strstr(pc_error_detail(), "POLARCAM_MAX_PIXELS") &&
	      strstr(pc_error_detail(), "t.json"));
	setenv("POLARCAM_MAX_PIXELS", "64", 1);
	CHECK_EQ_INT(pc_scene_parse(scene_text(NULL, NULL), "t.json", dir, &s), 0);
	pc_scene_free(s);
	unsetenv("POLARCAM_MAX_PIXELS");
	/* the default: 65535 × 65535 (4.3 G pixels) is refused before anything is allocated */
	const char *t = scene_text(NULL, NULL);
	char big[4096];
	const char *r = strstr(t, "[8, 8]");
	snprintf(big, sizeof big, "%.*s[65534, 65534]%s", (int)(r - t), t, r + 6);
	CHECK_EQ_INT(pc_scene_parse(big, "t.json", dir, &s), PC_ERANGE);
}

static void write_obj(const char *name, const char *text)
{
	char p[128];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	FILE *fp = fopen(p, "w");
	if (fp) {
		fputs(text, fp);
		fclose(fp);
	}
}

static int load_mesh(const char *name, const char *scale)
{
	char obj[256];
	snprintf(obj, sizeof obj,
	         "{\"type\": \"mesh\", \"file\": \"%s\", \"scale\": %s, \"material\": \"m\"}", name,
	         scale);
	pc_scene *s = NULL;
	int rc = pc_scene_parse(scene_text(NULL, obj), "t.json", dir, &s);
	pc_scene_free(s);
	return rc;
}

static void test_obj(void)
{
	const char *verts = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 2 2 0\n";
	char text[512];
	snprintf(text, sizeof text, "%sf 1 2 3\nf 2 4 3\nf 3 4 5\n", verts);
	write_obj("ok.obj", text);
	CHECK_EQ_INT(load_mesh("ok.obj", "1"), 0);
	/* strict face tokens: junk after an index, texture junk, zero indices */
	static const char *const bad[] = {"f 1 2 3x\n", "f 1/abc 2 3\n", "f 1/2/3/4 2 3\n",
	                                  "f 0 1 2\n",  "f 1//0 2 3\n",  "f 1 2 -9\n",
	                                  "f 1 2 +3\n"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		snprintf(text, sizeof text, "%s%s", verts, bad[i]);
		write_obj("bad.obj", text);
		int rc = load_mesh("bad.obj", "1");
		CHECK(rc == PC_EFORMAT);
		CHECK(strstr(pc_error_detail(), "bad.obj") && strstr(pc_error_detail(), "line 6"));
		if (rc != PC_EFORMAT)
			fprintf(stderr, "  accepted: %s", bad[i]);
	}
	/* vertices that leave the range once scaled */
	write_obj("far.obj", "v 1e300 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
	CHECK_EQ_INT(load_mesh("far.obj", "1"), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "line 1") != NULL);
	write_obj("far2.obj", "v 1e95 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
	CHECK_EQ_INT(load_mesh("far2.obj", "1e10"), PC_EFORMAT);
	/* the triangle limit */
	setenv("POLARCAM_MAX_TRIANGLES", "2", 1);
	CHECK_EQ_INT(load_mesh("ok.obj", "1"), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "ok.obj: line 8") &&
	      strstr(pc_error_detail(), "POLARCAM_MAX_TRIANGLES"));
	setenv("POLARCAM_MAX_TRIANGLES", "3", 1);
	CHECK_EQ_INT(load_mesh("ok.obj", "1"), 0);
	setenv("POLARCAM_MAX_TRIANGLES", "x", 1);
	CHECK_EQ_INT(load_mesh("ok.obj", "1"), PC_EINVAL);
	unsetenv("POLARCAM_MAX_TRIANGLES");
}

static void test_memory(void)
{
	pc_scene *s;
	/* 2 PSG states (a sequence of polarizations on the light), PRNU/DSNU on */
	pc_sim *sim = make_sim(scene_text(NULL, NULL), &s);
	CHECK(sim != NULL);
	if (!sim)
		return;
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	const uint64_t npix = (uint64_t)in.width * in.height;
	/* the closed form of sim.h: one state × 4 bytes, row buffers of one thread (C = 1:
	 * (20 + 4) doubles per column), one 16-bit frame, and the truth (4 floats) */
	const uint64_t want_no_truth = npix * 4 + (uint64_t)in.width * 24 * 8 + npix * 2;
	CHECK_EQ_INT(pc_sim_memory_bytes(sim, false), want_no_truth);
	CHECK_EQ_INT(pc_sim_memory_bytes(sim, true), want_no_truth + npix * 16);
	const char *src = NULL;
	CHECK(pc_sim_memory_available(&src) > 0 && src != NULL);
	CHECK_EQ_INT(pc_sim_check_memory(sim, true), 0);
	setenv("POLARCAM_MAX_MEMORY", "1k", 1);
	CHECK_EQ_INT(pc_sim_check_memory(sim, true), PC_ENOMEM);
	CHECK(strstr(pc_error_detail(), "8x8") && strstr(pc_error_detail(), "POLARCAM_MAX_MEMORY"));
	setenv("POLARCAM_MAX_MEMORY", "1G", 1);
	CHECK_EQ_INT(pc_sim_check_memory(sim, true), 0);
	setenv("POLARCAM_MAX_MEMORY", "lots", 1);
	CHECK_EQ_INT(pc_sim_check_memory(sim, true), PC_EINVAL);
	unsetenv("POLARCAM_MAX_MEMORY");
	pc_sim_free(sim);
	pc_scene_free(s);
}

int main(void)
{
	snprintf(dir, sizeof dir, "/tmp/pc_sim_limits_XXXXXX");
	if (!mkdtemp(dir))
		SKIP("cannot create a temporary directory: %s", strerror(errno));
	test_timestamps();
	test_resolution_limit();
	test_obj();
	test_memory();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", dir);
	return pc_test_finish("test_sim_limits");
}
