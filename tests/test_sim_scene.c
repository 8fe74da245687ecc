/* Scene files: the default scene parses with the documented contents; every kind of bad input
 * is rejected with a message naming the file, the line (syntax) or the field path, and the
 * reason; OBJ meshes load relative to the scene file and bad OBJ lines are named. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <jansson.h>
#include <unistd.h>

#include "../sim/scene_impl.h"
#include "check.h"
#include "polarcam/error.h"
#include "polarcam/sim.h"

/* A minimal valid scene with one substitution: the JSON fragment "@X@" is replaced. */
static const char *base =
    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], \"irradiance_w_m2\": 10}],"
    " \"materials\": {\"paint\": {\"n\": 1.5, \"k\": 0, \"sigma\": 0.2}},"
    " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 1], \"radius\": 1, \"material\": "
    "\"paint\"}]"
    "@X@}";

static char *with(const char *x)
{
	static char buf[8192];
	const char *at = strstr(base, "@X@");
	snprintf(buf, sizeof buf, "%.*s%s%s", (int)(at - base), base, x, at + 3);
	return buf;
}

/* expects failure with code and every needle in the message */
static void expect_error(const char *text, int code, const char *n1, const char *n2)
{
	pc_scene *s = NULL;
	int rc = pc_scene_parse(text, "t.json", ".", &s);
	const char *msg = pc_error_detail();
	CHECK_EQ_INT(rc, code);
	CHECK(s == NULL);
	if (n1 && !strstr(msg, n1))
		fprintf(stderr, "message '%s' lacks '%s'\n", msg, n1);
	if (n2 && !strstr(msg, n2))
		fprintf(stderr, "message '%s' lacks '%s'\n", msg, n2);
	CHECK(!n1 || strstr(msg, n1));
	CHECK(!n2 || strstr(msg, n2));
	CHECK(strncmp(msg, "t.json", 6) == 0);
}

static void test_default(void)
{
	pc_scene *s;
	CHECK_EQ_INT(pc_scene_load_default(&s), 0);
	CHECK_EQ_INT(s->sensor.width, 2448);
	CHECK_EQ_INT(s->sensor.height, 2048);
	CHECK_EQ_INT(s->n_materials, 2);
	int black = -1, green = -1;
	for (unsigned i = 0; i < s->n_materials; i++) {
		if (!strcmp(s->materials[i].name, "black_paint"))
			black = (int)i;
		if (!strcmp(s->materials[i].name, "green_paint"))
			green = (int)i;
	}
	CHECK(black >= 0 && green >= 0);
	if (black >= 0 && green >= 0) {
		/* the seed paper's paints (physics.md §8) */
		CHECK(s->materials[black].m[0].n == 1.46 && s->materials[black].m[0].k == 1.28 &&
		      s->materials[black].m[0].sigma == 0.2);
		CHECK(s->materials[green].m[0].n == 1.47 && s->materials[green].m[0].k == 0.47 &&
		      s->materials[green].m[0].sigma == 0.1);
	}
	int spheres = 0, planes = 0;
	for (unsigned i = 0; i < s->n_objects; i++) {
		spheres += s->objects[i].type == PC_OBJ_SPHERE;
		planes += s->objects[i].type == PC_OBJ_PLANE;
	}
	CHECK(spheres >= 2 && planes == 1);
	CHECK_EQ_INT(s->n_lights, 2); /* key light and back light */
	CHECK_EQ_INT(s->lights[0].type, PC_LIGHT_DIRECTIONAL);
	CHECK_EQ_INT(s->lights[1].type, PC_LIGHT_DIRECTIONAL);
	unsigned fx = pc_scene_effects(s);
	CHECK(fx & PC_FX_DIFFUSE);
	CHECK(fx & PC_FX_NOISE);
	CHECK(!(fx & PC_FX_MUELLER));
	CHECK(!strcmp(s->sensor.preset, "imx250mzr"));
	char *js = pc_scene_to_json(s);
	CHECK(js && strstr(js, "black_paint"));
	free(js);
	pc_scene_free(s);
}

static void test_errors(void)
{
	expect_error("{\"camera\": [1, 2,\n\n  }", PC_EFORMAT, "line 3", NULL);
	expect_error(with(", \"sensor\": {\"preset\": \"imx999\"}"), PC_EINVAL, "sensor.preset",
	             "imx250mzr");
	expect_error(with(", \"effects\": {\"difuse\": true}"), PC_EINVAL, "effects.difuse",
	             "unknown effect");
	expect_error(with(", \"effects\": {\"supersampling\": 40}"), PC_EINVAL,
	             "effects.supersampling", "[1, 16]");
	/* the lens blur's sigma: a number of pixels in [0.5, 8], or false */
	expect_error(with(", \"effects\": {\"blur\": true}"), PC_EINVAL, "effects.blur",
	             "sigma in pixels");
	expect_error(with(", \"effects\": {\"blur\": 0.2}"), PC_EINVAL, "effects.blur", "[0.5, 8]");
	expect_error(with(", \"effects\": {\"blur\": 9}"), PC_EINVAL, "effects.blur", "[0.5, 8]");
	expect_error(with(", \"effects\": {\"blur\": \"1\"}"), PC_EINVAL, "effects.blur",
	             "a string");
	expect_error(with(", \"sensor\": {\"bits\": 11}"), PC_EINVAL, "sensor.bits",
	             "8, 10, 12 or 16");
	expect_error(with(", \"sensor\": {\"resolution\": [101, 100]}"), PC_EINVAL,
	             "sensor.resolution", "multiples");
	expect_error(with(", \"sensor\": {\"layout\": \"90,45,90,0\"}"), PC_EINVAL, "sensor.layout",
	             NULL);
	expect_error(with(", \"sensor\": {\"extinction_ratio\": 0.5}"), PC_EINVAL,
	             "sensor.extinction_ratio", "> 1");
	expect_error(with(", \"sensor\": {\"psa\": [{\"retarder\": {\"angle_deg\": 0, "
	                  "\"retardance_deg\": 90}}]}"),
	             PC_EINVAL, "sensor.psa", "circular");
	expect_error(with(", \"extra\": 1"), PC_EINVAL, "extra", "unknown field");
	expect_error(with(", \"background\": -1"), PC_EINVAL, "background = -1", "must be in [0");

	const char *bad_mat =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"k\": -1, \"sigma\": 0.2}},"
	    " \"objects\": []}";
	expect_error(bad_mat, PC_EINVAL, "materials.paint.k = -1", "must be in [0");
	const char *bad_sigma = "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	                        " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, "
	                        "1], \"irradiance_w_m2\": 10}],"
	                        " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": -1}},"
	                        " \"objects\": []}";
	expect_error(bad_sigma, PC_EINVAL, "materials.paint.sigma = -1", "must be");
	const char *bad_rho =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1, \"rho\": \"quadx\"}},"
	    " \"objects\": []}";
	expect_error(bad_rho, PC_EINVAL, "materials.paint.rho", "'quadx': expected table or quad");
	const char *bad_shadowing =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1, \"shadowing\": \"TS\"}},"
	    " \"objects\": []}";
	expect_error(bad_shadowing, PC_EINVAL, "materials.paint.shadowing", "'TS': expected ts");
	const char *num_diffuse =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1, \"diffuse\": 1}},"
	    " \"objects\": []}";
	expect_error(num_diffuse, PC_EINVAL, "materials.paint.diffuse", "expected a string");
	const char *no_mat = "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	                     " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	                     "\"irradiance_w_m2\": 10}],"
	                     " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}},"
	                     " \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], "
	                     "\"radius\": 1, \"material\": \"gold\"}]}";
	expect_error(no_mat, PC_EINVAL, "objects[0].material", "'gold'");
	const char *bad_field = "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	                        " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, "
	                        "1], \"irradiance_w_m2\": 10}],"
	                        " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}},"
	                        " \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], "
	                        "\"radius\": 1, \"normal\": [0,0,1], \"material\": \"paint\"}]}";
	expect_error(bad_field, PC_EINVAL, "objects[0].normal", "not a field of a sphere");
	const char *zero_radius = "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	                          " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, "
	                          "1], \"irradiance_w_m2\": 10}],"
	                          " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}},"
	                          " \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], "
	                          "\"radius\": 0, \"material\": \"paint\"}]}";
	expect_error(zero_radius, PC_EINVAL, "objects[0].radius", "> 0");
	const char *circ =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 1], \"intensity_w_sr\": 10,"
	    "   \"polarization\": {\"circular\": 1}}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}}, \"objects\": []}";
	expect_error(circ, PC_EINVAL, "lights[0].polarization", "circular");
	const char *stokes =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 1], \"intensity_w_sr\": 10,"
	    "   \"states\": [\"unpolarized\", {\"stokes\": [1, 1, 0]}]}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}}, \"objects\": []}";
	expect_error(stokes, PC_EINVAL, "lights[0].states[1].stokes", "> 1");
	const char *cam =
	    "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"point\", \"position\": [0, 1, 1], \"intensity_w_sr\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}}, \"objects\": []}";
	expect_error(cam, PC_EINVAL, "camera.up", "parallel");
	const char *dir_point =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"intensity_w_sr\": 10}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}}, \"objects\": []}";
	expect_error(dir_point, PC_EINVAL, "lights[0]", "irradiance_w_m2");
	expect_error("[1, 2]", PC_EINVAL, "expected an object", NULL);
}

/* Material keywords map to the physics core's modes; absent keys keep the defaults; a global
 * effect switched off overrides the material. */
static void test_material_keywords(void)
{
	const char *t =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10}],"
	    " \"materials\": {\"a\": {\"n\": 1.5, \"sigma\": 0.1, \"diffuse\": \"geometric\","
	    "   \"shadowing\": \"none\", \"rho\": \"quad\"}, \"b\": {\"n\": 1.5, \"sigma\": 0.1}},"
	    " \"objects\": [], \"effects\": {\"diffuse\": true, \"shadowing\": true}}";
	pc_scene *s;
	CHECK_EQ_INT(pc_scene_parse(t, "t.json", ".", &s), 0);
	if (!s)
		return;
	CHECK_EQ_INT(s->n_materials, 2);
	for (unsigned i = 0; i < s->n_materials; i++) {
		const pc_sim_material *m = &s->materials[i];
		bool a = !strcmp(m->name, "a");
		CHECK_EQ_INT(m->m[0].diffuse, a ? PC_DIFFUSE_GEOMETRIC : PC_DIFFUSE_FRESNEL);
		CHECK_EQ_INT(m->m[0].shadowing, a ? PC_SHADOW_NONE : PC_SHADOW_TS);
		CHECK_EQ_INT(m->m[0].rho_mode, a ? PC_RHO_QUAD : PC_RHO_TABLE);
	}
	pc_scene_free(s);
	/* effects.diffuse off: no diffuse term whatever the material says */
	char *t2 = strdup(t);
	char *d = strstr(t2, "\"diffuse\": true");
	memcpy(d, "\"diffuse\":false", 15); /* same length as "diffuse": true */
	CHECK_EQ_INT(pc_scene_parse(t2, "t.json", ".", &s), 0);
	if (s) {
		for (unsigned i = 0; i < s->n_materials; i++)
			CHECK_EQ_INT(s->materials[i].m[0].diffuse, PC_DIFFUSE_NONE);
		pc_scene_free(s);
	}
	free(t2);
}

static void test_states_and_psa(void)
{
	const char *t =
	    "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	    "\"irradiance_w_m2\": 10,"
	    "   \"states\": [{\"linear_deg\": 0}, {\"linear_deg\": 60}, {\"linear_deg\": 120},"
	    "                {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": 45, "
	    "\"retardance_deg\": 90}}]}],"
	    " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}}, \"objects\": [],"
	    " \"effects\": {\"circular\": true},"
	    " \"sensor\": {\"psa\": [\"none\", {\"retarder\": {\"angle_deg\": 30, "
	    "\"retardance_deg\": 90}}]}}";
	pc_scene *s;
	CHECK_EQ_INT(pc_scene_parse(t, "t.json", ".", &s), 0);
	if (!s)
		return;
	CHECK_EQ_INT(s->lights[0].n_states, 4);
	CHECK_NEAR(s->lights[0].stokes[1][1], cos(2 * 60 * M_PI / 180), 1e-15);
	CHECK_NEAR(s->lights[0].stokes[1][2], sin(2 * 60 * M_PI / 180), 1e-15);
	/* polarizer at 0° then a quarter-wave plate at 45°: fully circular, S3 = +1 (sim.h) */
	CHECK_NEAR(s->lights[0].stokes[3][3], 1, 1e-15);
	CHECK_NEAR(s->lights[0].stokes[3][1], 0, 1e-15);
	CHECK_EQ_INT(s->n_psa, 2);
	CHECK(s->psa[0][1][1] == 1 && s->psa[0][3][3] == 1 && s->psa[0][0][1] == 0);
	pc_scene_free(s);
}

static void test_obj(void)
{
	char dir[64];
	CHECK(pc_test_tmpdir(dir, sizeof dir, "pc_sim_scene") != NULL);
	char path[256], scene[256];
	snprintf(path, sizeof path, "%s/tet.obj", dir);
	FILE *fp = fopen(path, "w");
	/* a tetrahedron: 4 vertices, 4 faces (one quad-free), comments and ignored records */
	fprintf(fp, "# tetrahedron\no tet\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n"
	            "f 1 3 2\nf 1 2 4\nf 1/1 4 3\nf -3 -2 -1\n");
	fclose(fp);
	snprintf(scene, sizeof scene, "%s/s.json", dir);
	fp = fopen(scene, "w");
	fprintf(fp, "{\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0]},"
	            " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 1, 1], "
	            "\"irradiance_w_m2\": 10}],"
	            " \"materials\": {\"paint\": {\"n\": 1.5, \"sigma\": 0.1}},"
	            " \"objects\": [{\"type\": \"mesh\", \"file\": \"tet.obj\", \"scale\": 2, "
	            "\"position\": [1, 0, 0],"
	            " \"material\": \"paint\"}]}");
	fclose(fp);
	pc_scene *s = NULL;
	CHECK_EQ_INT(pc_scene_load(scene, &s), 0);
	if (s) {
		CHECK_EQ_INT(s->objects[0].mesh->n_triangles, 4);
		CHECK_EQ_INT(s->objects[0].mesh->n_vertices, 4);
		CHECK_NEAR(s->objects[0].mesh->v[1].x, 3, 1e-15); /* 1·2 + 1 */
		/* a ray towards the tetrahedron's face x+y+z = 2 (scaled) hits it */
		pc_hit h;
		CHECK(pc_scene_intersect(s, v3(5, 0.3, 0.3), v3(-1, 0, 0), 0, 100, &h));
		CHECK_NEAR(h.t, 5 - (1 + 2 - 0.6), 1e-12);
		pc_scene_free(s);
	}
	/* a face index out of range names the OBJ file and line */
	fp = fopen(path, "w");
	fprintf(fp, "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 7\n");
	fclose(fp);
	CHECK(pc_scene_load(scene, &s) == PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "tet.obj: line 5") != NULL);
	CHECK(strstr(pc_error_detail(), "objects[0].file") != NULL);
	CHECK(strstr(pc_error_detail(), "out of range") != NULL);
	remove(path);
	remove(scene);
	rmdir(dir);
	CHECK(pc_scene_load("/nonexistent/scene.json", &s) == PC_ENOENT);
	CHECK(strstr(pc_error_detail(), "/nonexistent/scene.json") != NULL);
}

/* Calls fn(path, file name) for every example scene (scenes/, .json files); returns how many, or -1
 * when PC_SOURCE_DIR is not set (the scenes are not reachable). */
static int for_each_example(void (*fn)(const char *path, const char *name))
{
	const char *src = getenv("PC_SOURCE_DIR");
	if (!src)
		return -1;
	char dir[1024], path[2048];
	snprintf(dir, sizeof dir, "%s/scenes", src);
	DIR *d = opendir(dir);
	CHECK(d != NULL);
	if (!d)
		return 0;
	int n = 0;
	for (struct dirent *e; (e = readdir(d));) {
		size_t l = strlen(e->d_name);
		if (l < 6 || strcmp(e->d_name + l - 5, ".json"))
			continue;
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		fn(path, e->d_name);
		n++;
	}
	closedir(d);
	return n;
}

static void check_loads(const char *path, const char *name)
{
	(void)name;
	pc_scene *s = NULL;
	int rc = pc_scene_load(path, &s);
	if (rc)
		fprintf(stderr, "%s\n", pc_error_detail());
	CHECK_EQ_INT(rc, 0);
	pc_scene_free(s);
}

/* every example scene in scenes/ loads; scenes/default.json is the built-in default scene; the
 * JSON Schema in docs/ is valid JSON */
static void test_examples(void)
{
	int n = for_each_example(check_loads);
	if (n < 0)
		return;
	CHECK(n >= 5);
	const char *src = getenv("PC_SOURCE_DIR");
	char path[2048];
	snprintf(path, sizeof path, "%s/scenes/default.json", src);
	json_t *a = json_load_file(path, 0, NULL),
	       *b = json_loads(pc_scene_default_text(), 0, NULL);
	CHECK(a && b && json_equal(a, b));
	json_decref(a);
	json_decref(b);
	snprintf(path, sizeof path, "%s/docs/scene.schema.json", src);
	a = json_load_file(path, 0, NULL);
	CHECK(a != NULL);
	json_decref(a);
}

/* The example scenes are exposed like a user would expose them: only glints at full scale
 * (< 15 % of frame 0's raw pixels) and a median signal above 5 % of full scale. Overexposed
 * examples (most of the frame at 4095) measure no polarization and teach the wrong thing. */
static void check_exposure(const char *path, const char *name)
{
	pc_scene *s = NULL;
	pc_sim *sim = NULL;
	pc_view v = {0};
	uint16_t *u = NULL;
	CHECK_EQ_INT(pc_scene_load(path, &s), 0);
	pc_sim_options o = pc_sim_options_default();
	if (s && !pc_sim_new(s, &o, &sim)) {
		pc_sim_info in;
		pc_sim_get_info(sim, &in);
		size_t np = (size_t)in.width * in.height;
		u = malloc(np * sizeof *u);
		CHECK(u && !pc_view_alloc(&v, in.format, in.width, in.height, 64));
		CHECK_EQ_INT(pc_sim_frame(sim, 0, NULL, &v, NULL), 0);
		CHECK_EQ_INT(pc_view_to_u16(&v, u, (size_t)in.width * sizeof *u), 0);
		const unsigned full = (1u << in.bits) - 1;
		size_t sat = 0, *hist = calloc(full + 1, sizeof *hist);
		for (size_t i = 0; i < np; i++) {
			sat += u[i] >= full;
			hist[u[i] > full ? full : u[i]]++;
		}
		size_t acc = 0;
		unsigned median = 0;
		while (median < full && (acc += hist[median]) < np / 2)
			median++;
		free(hist);
		double fs = (double)sat / (double)np, fm = (double)median / full;
		if (!(fs < 0.15) || !(fm > 0.05))
			fprintf(stderr, "%s: %.1f %% saturated, median %u of %u\n", name, 100 * fs,
			        median, full);
		CHECK(fs < 0.15);
		CHECK(fm > 0.05);
	} else {
		CHECK(!"pc_sim_new");
	}
	pc_view_free(&v);
	free(u);
	pc_sim_free(sim);
	pc_scene_free(s);
}

static void test_example_exposure(void)
{
	for_each_example(check_exposure);
}

int main(void)
{
	test_examples();
	test_example_exposure();
	test_default();
	test_errors();
	test_states_and_psa();
	test_material_keywords();
	test_obj();
	return pc_test_finish("test_sim_scene");
}
