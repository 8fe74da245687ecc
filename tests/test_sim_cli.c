/* The simulator's commands end to end (called in-process): polarcam render writes raw frames
 * bit-identical to pc_sim_frame and truth equal to pc_sim_truth_rows; bad input exits 2 and
 * writes nothing; polarcam mueller reconstructs a rendered sequence with the documented
 * conditioning; polarcam demo runs on a small scene and writes its report. */
#include <jansson.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "cli.h"
#include "commands.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/sim.h"

static char tmp[] = "/tmp/pc_sim_cli_XXXXXX";

static int run(int (*cmd)(int, char **), const char *name, ...)
{
	char *argv[32];
	int argc = 0;
	argv[argc++] = (char *)name;
	va_list ap;
	va_start(ap, name);
	for (const char *a; argc < 31 && (a = va_arg(ap, const char *));)
		argv[argc++] = (char *)a;
	va_end(ap);
	argv[argc] = NULL;
	pc_cli_command = name;
	fflush(stdout);
	return cmd(argc, argv);
}

static bool exists(const char *dir, const char *name)
{
	char p[1024];
	struct stat st;
	snprintf(p, sizeof p, "%s/%s", dir, name);
	return stat(p, &st) == 0;
}

static void write_file(const char *path, const char *text)
{
	FILE *fp = fopen(path, "w");
	fputs(text, fp);
	fclose(fp);
}

static const char *small_scene =
	"{\"camera\": {\"position\": [0, -7.5, 3.0], \"look_at\": [0, 0.3, 0.7], \"focal_length_mm\": 12},"
	" \"materials\": {\"black\": {\"n\": 1.46, \"k\": 1.28, \"sigma\": 0.2},"
	"                 \"green\": {\"n\": 1.47, \"k\": 0.47, \"sigma\": 0.1}},"
	" \"lights\": [{\"type\": \"directional\", \"direction\": [-0.55, -0.45, 0.70], \"irradiance_w_m2\": 300}],"
	" \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], \"material\": \"green\"},"
	"   {\"type\": \"sphere\", \"center\": [-1.4, 0.4, 1.0], \"radius\": 1.0, \"material\": \"black\"}],"
	" \"effects\": {\"diffuse\": true, \"shadowing\": true, \"cast_shadows\": true},"
	" \"sensor\": {\"preset\": \"imx250mzr\", \"resolution\": [64, 48], \"pixel_pitch_um\": 132,"
	"   \"exposure_us\": 0.5}}";

static void test_render(void)
{
	char scene[512], out[512], bad[512];
	snprintf(scene, sizeof scene, "%s/small.json", tmp);
	snprintf(out, sizeof out, "%s/r", tmp);
	write_file(scene, small_scene);
	CHECK_EQ_INT(run(cmd_render, "render", "--help", NULL), 0);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, "--frames", "2", "--seed", "7",
			 "--first", "3", NULL), 0);
	CHECK(exists(out, "raw_000000.png") && exists(out, "raw_000001.png"));
	CHECK(exists(out, "meta.json") && exists(out, "truth_stokes.npy"));
	CHECK(!exists(out, "truth_mueller.npy") && !exists(out, "states.json"));
	/* the recording's second frame is frame 4 of seed 7, bit for bit */
	pc_scene *s;
	pc_sim *sim;
	CHECK_EQ_INT(pc_scene_load(scene, &s), 0);
	pc_sim_options o = pc_sim_options_default();
	o.seed = 7;
	CHECK_EQ_INT(pc_sim_new(s, &o, &sim), 0);
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	pc_view a, b;
	pc_view_alloc(&a, in.format, 64, 48, 64);
	CHECK_EQ_INT(pc_sim_frame(sim, 4, NULL, &a, NULL), 0);
	pc_recording *rec = NULL;
	CHECK_EQ_INT(pc_recording_open(&rec, out), 0);
	if (rec) {
		CHECK_EQ_INT(pc_recording_count(rec), 2);
		CHECK_EQ_INT(pc_recording_get_frame(rec, 1)->sequence, 4);
		CHECK(pc_recording_is_complete(rec));
		CHECK_EQ_INT(pc_recording_read(rec, 1, &b), 0);
		int same = 1;
		for (uint32_t y = 0; y < 48; y++)
			same &= !memcmp(PC_ROW(&a, uint16_t, y), PC_ROW(&b, uint16_t, y), 64 * 2);
		CHECK(same);
		pc_view_free(&b);
		pc_recording_free(rec);
	}
	/* truth_stokes.npy = pc_sim_truth_rows in float */
	pc_array t;
	char p[1024];
	snprintf(p, sizeof p, "%s/truth_stokes.npy", out);
	CHECK_EQ_INT(pc_npy_read(p, &t), 0);
	CHECK(t.ndim == 3 && t.shape[0] == 48 && t.shape[1] == 64 && t.shape[2] == 4);
	double *S = malloc(sizeof(double) * 4 * 64 * 48);
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 0, 48, S, NULL), 0);
	int eq = 1, lit = 0;
	for (int i = 0; i < 64 * 48 * 3; i++) {
		if (i % 4 == 3)
			continue;
		eq &= ((float *)t.data)[i] == (float)S[i];
		lit += i % 4 == 0 && S[i] > 0;
	}
	CHECK(eq);
	CHECK(lit > 100);
	free(S);
	pc_array_free(&t);
	/* meta.json records scene, sensor, seed, effects, timings */
	snprintf(p, sizeof p, "%s/meta.json", out);
	json_t *m = json_load_file(p, 0, NULL);
	json_t *ex = json_object_get(m, "extra");
	CHECK(json_integer_value(json_object_get(ex, "seed")) == 7);
	CHECK(json_is_array(json_object_get(ex, "effects")));
	CHECK(json_is_object(json_object_get(ex, "sensor")));
	CHECK(json_is_object(json_object_get(ex, "scene")));
	CHECK(json_is_number(json_object_get(json_object_get(ex, "timings"), "render_s")));
	json_decref(m);
	/* the directory holds a recording: refused without --overwrite */
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, "--overwrite", "--no-truth", NULL), 0);
	/* bad input: exit 2, nothing written */
	snprintf(bad, sizeof bad, "%s/bad.json", tmp);
	write_file(bad, "{\"camera\": {\"position\": [0, 0, 1], \"look_at\": [0, 0, 0]},\n \"lights\": 3}");
	snprintf(out, sizeof out, "%s/nothing", tmp);
	CHECK_EQ_INT(run(cmd_render, "render", bad, "-o", out, NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", "/nonexistent.json", "-o", out, NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, "--frames", "0", NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, "--roi", "1,2,3", NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, "--roi", "60,0,8,8", NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "--bogus", NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_render, "render", scene, NULL), PC_EXIT_USAGE);
	struct stat st;
	CHECK(stat(out, &st) != 0); /* no directory, no partial files */
	pc_view_free(&a);
	pc_sim_free(sim);
	pc_scene_free(s);
}

static void test_mueller(void)
{
	char scene[512], out[512], res[512];
	snprintf(scene, sizeof scene, "%s/seq.json", tmp);
	snprintf(out, sizeof out, "%s/seq", tmp);
	snprintf(res, sizeof res, "%s/mres", tmp);
	/* the small scene with a tetrahedral PSG and a quarter-wave PSA */
	json_t *d = json_loads(small_scene, 0, NULL);
	json_t *l = json_array_get(json_object_get(d, "lights"), 0);
	json_object_set_new(l, "states", json_pack("[{s:f,s:{s:f,s:f}},{s:f,s:{s:f,s:f}},{s:f,s:{s:f,s:f}},{s:f,s:{s:f,s:f}}]",
		"polarizer_deg", 0.0, "retarder", "angle_deg", 15.1, "retardance_deg", 132.0,
		"polarizer_deg", 0.0, "retarder", "angle_deg", 51.7, "retardance_deg", 132.0,
		"polarizer_deg", 0.0, "retarder", "angle_deg", -51.7, "retardance_deg", 132.0,
		"polarizer_deg", 0.0, "retarder", "angle_deg", -15.1, "retardance_deg", 132.0));
	json_t *fx = json_object_get(d, "effects");
	json_object_set_new(fx, "circular", json_true());
	json_object_set_new(fx, "mueller", json_true());
	json_object_set_new(json_object_get(d, "sensor"), "psa",
			    json_pack("[{s:{s:f,s:f}},{s:{s:f,s:f}}]", "retarder", "angle_deg", 0.0,
				      "retardance_deg", 90.0, "retarder", "angle_deg", 45.0,
				      "retardance_deg", 90.0));
	json_dump_file(d, scene, 0);
	json_decref(d);
	CHECK_EQ_INT(run(cmd_render, "render", scene, "-o", out, NULL), 0);
	CHECK(exists(out, "raw_000007.png") && !exists(out, "raw_000008.png"));
	CHECK(exists(out, "states.json") && exists(out, "truth_mueller.npy"));
	CHECK(exists(out, "truth_stokes_psg03.npy"));
	CHECK_EQ_INT(run(cmd_mueller, "mueller", "--help", NULL), 0);
	CHECK_EQ_INT(run(cmd_mueller, "mueller", out, "-o", res, "--method", "superpixel", NULL), 0);
	CHECK(exists(res, "D.npy") && exists(res, "R.png") && exists(res, "Delta.npy"));
	char p[1024];
	snprintf(p, sizeof p, "%s/mueller.json", res);
	json_t *m = json_load_file(p, 0, NULL);
	CHECK_NEAR(json_number_value(json_object_get(m, "cond_A")), 2.0, 1e-9);
	CHECK_NEAR(json_number_value(json_object_get(m, "cond_W")), 2.0 * 1.7378, 1e-3);
	CHECK_EQ_INT(json_integer_value(json_object_get(m, "width")), 32); /* superpixel: half */
	json_decref(m);
	pc_array a;
	snprintf(p, sizeof p, "%s/mueller.npy", res);
	CHECK_EQ_INT(pc_npy_read(p, &a), 0);
	CHECK(a.ndim == 4 && a.shape[0] == 24 && a.shape[1] == 32 && a.shape[2] == 4);
	pc_array_free(&a);
	/* frame files in order + --states; too few frames is bad input */
	char f0[600], f1[600], st[600];
	snprintf(f0, sizeof f0, "%s/raw_000000.png", out);
	snprintf(f1, sizeof f1, "%s/raw_000001.png", out);
	snprintf(st, sizeof st, "%s/states.json", out);
	CHECK_EQ_INT(run(cmd_mueller, "mueller", f0, f1, "--states", st, "-o", res, NULL),
		     PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_mueller, "mueller", f0, "-o", res, NULL), PC_EXIT_USAGE);
	CHECK_EQ_INT(run(cmd_mueller, "mueller", out, "-o", res, "--method", "nope", NULL),
		     PC_EXIT_USAGE);
}

static void test_demo(void)
{
	char scene[512], out[512];
	snprintf(scene, sizeof scene, "%s/small.json", tmp);
	snprintf(out, sizeof out, "%s/demo", tmp);
	CHECK_EQ_INT(run(cmd_demo, "demo", "--help", NULL), 0);
	CHECK_EQ_INT(run(cmd_demo, "demo", "--scene", scene, "-o", out, "--methods", "bilinear,superpixel",
			 NULL), 0);
	CHECK(exists(out, "report.md") && exists(out, "report.json") && exists(out, "raw_000000.png"));
	CHECK(exists(out, "truth/dolp.png") && exists(out, "pipeline_bilinear/aolp.png"));
	CHECK(exists(out, "mueller/D.png") && exists(out, "mueller/truth_Delta.npy"));
	CHECK(exists(out, "stokes.npy"));
	CHECK_EQ_INT(run(cmd_demo, "demo", "--methods", "nope", NULL), PC_EXIT_USAGE);
}

int main(void)
{
	if (!mkdtemp(tmp))
		SKIP("cannot create a temporary directory");
	setenv("POLARCAM_PROGRESS", "0", 1);
	test_render();
	test_mueller();
	test_demo();
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_sim_cli");
}
