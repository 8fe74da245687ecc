/* Scene families and datasets (polarcam/family.h, polarcam/dataset.h):
 *  - spec validation names the field and what was expected; nothing is written for a bad spec;
 *  - sample i is a pure function of (spec, seed, i): the same dataset (manifest bytes) from 1,
 *    2, 4 and 7 shards and 1 or 2 threads; another seed gives other samples;
 *  - a run killed mid-way (SIGKILL) and restarted, with a stale temporary sample directory and a
 *    torn manifest line, completes to identical hashes; a lost manifest line is re-hashed;
 *  - verify finds a flipped byte, an extra file and a missing sample; merge refuses while
 *    samples are missing and writes nothing;
 *  - a sample's scene.json re-renders alone (polarcam render) to identical raw and truth bytes;
 *  - float16 truth is the round-to-nearest-even binary16 of the float32 truth (checked against
 *    the compiler's _Float16 conversion and hand-made values);
 *  - SHA-256 against the FIPS 180-2 test vector; the scheduler environment → shard;
 *  - the demosaicking family is sensibly exposed (few saturated pixels, not black). */
#include <dirent.h>
#include <errno.h>
#include <jansson.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/dataset.h"
#include "polarcam/error.h"
#include "polarcam/family.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"

static char tmp[] = "/tmp/pc_dataset_XXXXXX";
static char spec_path[1200];

/* A small family: 48x32, every kind of draw, a mesh. */
static const char *small_spec =
    "{\"polarcam_family\": 1, \"name\": \"small\", \"resolution\": [48, 32], \"truth\": "
    "\"float32\","
    " \"sensor\": {\"preset\": {\"choice\": [\"imx250mzr\", \"ideal\"]}, \"gain_db\": [0, 6],"
    "   \"exposure\": {\"auto_percentile\": 99, \"auto_level\": [0.5, 0.9]}},"
    " \"camera\": {\"distance\": [3, 6], \"azimuth_deg\": [0, 360], \"elevation_deg\": [15, 50],"
    "   \"roll_deg\": [-10, 10], \"target\": [[-0.3, 0.3], [-0.3, 0.3], [0.2, 0.5]], \"fov_deg\": "
    "[30, 50]},"
    " \"materials\": [{\"kind\": \"dielectric\", \"n\": [1.3, 1.8], \"k\": [0, 0.2], \"sigma\": "
    "{\"log_uniform\": [0.05, 0.5]}},"
    "   {\"weight\": 0.5, \"kind\": \"metal\", \"n\": [0.2, 2], \"k\": [2, 6], \"sigma\": [0.05, "
    "0.3], \"diffuse\": \"none\"}],"
    " \"ground\": {\"probability\": 1, \"materials\": [{\"n\": 1.5, \"sigma\": 0.3}]},"
    " \"objects\": {\"count\": {\"int\": [1, 4]}, \"region\": [[-1.5, 1.5], [-1.5, 1.5], [0.2, "
    "0.8]],"
    "   \"rest_on_ground\": true, \"shapes\": [{\"type\": \"sphere\", \"radius\": [0.2, 0.6]},"
    "   {\"type\": \"box\", \"size\": [0.3, 0.8], \"rotation_deg\": [0, 0, [0, 90]]},"
    "   {\"type\": \"mesh\", \"file\": \"torus.obj\", \"scale\": [0.4, 0.8], \"rotation_deg\": "
    "[[0, 90], 0, 0]}]},"
    " \"lights\": {\"count\": {\"int\": [1, 2]}, \"type\": {\"choice\": [\"directional\", "
    "\"point\"]},"
    "   \"azimuth_deg\": [0, 360], \"elevation_deg\": [20, 70], \"irradiance_w_m2\": "
    "{\"log_uniform\": [50, 300]},"
    "   \"distance\": [3, 6], \"polarization\": {\"unpolarized\": 1, \"linear\": 1, \"circular\": "
    "1, \"elliptical\": 1},"
    "   \"dop\": [0.2, 1]},"
    " \"background\": [0.1, 1],"
    " \"effects\": {\"diffuse\": true, \"cast_shadows\": {\"choice\": [true, false]}}}";

static char *slurp(const char *path, size_t *n)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return NULL;
	fseek(fp, 0, SEEK_END);
	long len = ftell(fp);
	fseek(fp, 0, SEEK_SET);
	char *b = malloc((size_t)len + 1);
	if (b && fread(b, 1, (size_t)len, fp) != (size_t)len) {
		free(b);
		b = NULL;
	}
	fclose(fp);
	if (b) {
		b[len] = 0;
		if (n)
			*n = (size_t)len;
	}
	return b;
}

static void spit(const char *path, const char *text)
{
	FILE *fp = fopen(path, "w");
	fputs(text, fp);
	fclose(fp);
}

static bool same_file(const char *a, const char *b)
{
	size_t na, nb;
	char *x = slurp(a, &na), *y = slurp(b, &nb);
	bool eq = x && y && na == nb && !memcmp(x, y, na);
	if (!eq)
		fprintf(stderr, "differ: %s %s\n", a, b);
	free(x);
	free(y);
	return eq;
}

static int make(const char *dir, uint64_t seed, uint64_t count, uint32_t shard, uint32_t shards,
                int threads)
{
	pc_dataset_options o;
	memset(&o, 0, sizeof o);
	o.spec = spec_path;
	o.dir = dir;
	o.seed = seed;
	o.count = count;
	o.shard = shard;
	o.shards = shards;
	o.threads = threads;
	pc_dataset_result r;
	int rc = pc_dataset_run(&o, &r);
	if (rc)
		fprintf(stderr, "dataset run: %s\n", pc_error_detail());
	return rc;
}

/* ---- validation ---- */

static void bad_spec(const char *edit_from, const char *edit_to, const char *want)
{
	char *s = malloc(strlen(small_spec) + strlen(edit_to) + 64);
	const char *at = strstr(small_spec, edit_from);
	CHECK(at != NULL);
	if (!at) {
		free(s);
		return;
	}
	size_t k = (size_t)(at - small_spec);
	memcpy(s, small_spec, k);
	strcpy(s + k, edit_to);
	strcat(s, at + strlen(edit_from));
	char dir[1100];
	snprintf(dir, sizeof dir, "%s", tmp);
	pc_family *f = NULL;
	int rc = pc_family_parse(s, "x.json", dir, &f);
	CHECK(rc < 0 && !f);
	if (rc >= 0)
		fprintf(stderr, "accepted: %s\n", edit_to);
	if (rc < 0 && !strstr(pc_error_detail(), want))
		fprintf(stderr, "expected '%s' in: %s\n", want, pc_error_detail());
	CHECK(rc < 0 && strstr(pc_error_detail(), want));
	pc_family_free(f);
	free(s);
}

static void test_validation(void)
{
	bad_spec("\"polarcam_family\": 1", "\"polarcam_family\": 2", "polarcam_family: must be 1");
	bad_spec("\"gain_db\": [0, 6]", "\"gain_db\": [6, 0]", "sensor.gain_db: [6, 0] needs");
	bad_spec("\"gain_db\": [0, 6]", "\"gain_db\": [0, 6], \"gian\": 1",
	         "unknown field \"gian\"");
	bad_spec("{\"log_uniform\": [50, 300]}", "{\"log_uniform\": [0, 300]}",
	         "log_uniform needs lo > 0");
	bad_spec("{\"int\": [1, 4]}", "{\"int\": [1, 4.5]}", "int needs integer bounds");
	bad_spec("\"torus.obj\"", "\"nothere.obj\"", "nothere.obj: cannot be opened");
	bad_spec("[48, 32]", "[49, 32]", "needs multiples of 2");
	bad_spec("\"circular\": 1,", "\"circular\": -1,", "weight of \"circular\" must be");
	bad_spec("\"choice\": [true, false]}", "\"choice\": [true, 3]}",
	         "effects.cast_shadows.choice[1]: expected true or false");
	/* the lens blur: a sigma in pixels or false, as the scene format (not true) */
	bad_spec("\"choice\": [true, false]}", "\"choice\": [true, false]}, \"blur\": true",
	         "effects.blur: expected the point-spread function's sigma in pixels");
	bad_spec("\"choice\": [true, false]}", "\"choice\": [true, false]}, \"blur\": 0.3",
	         "effects.blur: expected the point-spread function's sigma in pixels");
	/* a rare true among the choices: the field check refuses it, not only the first samples */
	bad_spec("\"choice\": [true, false]}",
	         "\"choice\": [true, false]}, \"blur\": {\"choice\": [1.0, true], \"weights\": "
	         "[1000, 1]}",
	         "effects.blur.choice[1]: expected the point-spread function's sigma");
	bad_spec("{\"choice\": [\"imx250mzr\", \"ideal\"]}", "\"imx999\"",
	         "sensor.preset: expected a sensor preset");
	bad_spec("\"weight\": 0.5,", "\"weight\": 0,", "materials: [1].weight must be");
	bad_spec("\"effects\": {\"diffuse\": true, \"cast_shadows\": {\"choice\": [true, false]}}",
	         "\"effects\": {\"choice\": [{\"noise\": false}, {\"difuse\": true}]}",
	         "effects.choice[1]: unknown field \"difuse\"");
	bad_spec("\"auto_level\": [0.5, 0.9]", "\"us\": 100, \"auto_level\": [0.5, 0.9]",
	         "either \"us\"");
	/* syntax */
	pc_family *f = NULL;
	CHECK(pc_family_parse("{\"polarcam_family\": 1,", "y.json", tmp, &f) < 0 &&
	      strstr(pc_error_detail(), "y.json: line 1"));
	/* a bad spec writes nothing */
	char d[1200], p[1300];
	snprintf(d, sizeof d, "%s/bad", tmp);
	snprintf(p, sizeof p, "%s/bad.json", tmp);
	spit(p, "{\"polarcam_family\": 1, \"resolution\": [8, 8]}");
	pc_dataset_options o;
	memset(&o, 0, sizeof o);
	o.spec = p;
	o.dir = d;
	o.count = 2;
	o.shards = 1;
	pc_dataset_result r;
	CHECK(pc_dataset_run(&o, &r) < 0);
	struct stat st;
	CHECK(stat(d, &st) != 0);
}

/* ---- determinism ---- */

static void test_scenes(void)
{
	pc_family *f = NULL;
	CHECK(pc_family_load(spec_path, &f) == 0);
	if (!f)
		return;
	char *a, *b, *c;
	uint64_t sa, sb, sc;
	CHECK(pc_family_scene(f, 5, 3, &a, &sa) == 0);
	CHECK(pc_family_scene(f, 5, 3, &b, &sb) == 0);
	CHECK(pc_family_scene(f, 6, 3, &c, &sc) == 0);
	CHECK(!strcmp(a, b) && sa == sb);
	CHECK(strcmp(a, c) != 0 && sa != sc);
	free(a);
	free(b);
	free(c);
	/* every drawn scene is valid and distinct over many indices (the generator's branches) */
	int distinct = 0;
	char *prev = NULL;
	for (uint64_t i = 0; i < 200; i++) {
		char *t;
		uint64_t s;
		CHECK(pc_family_scene(f, 1, i, &t, &s) == 0);
		pc_scene *scene = NULL;
		int rc = pc_scene_parse(t, "drawn", tmp, &scene);
		if (rc)
			fprintf(stderr, "sample %llu: %s\n", (unsigned long long)i,
			        pc_error_detail());
		CHECK(rc == 0);
		pc_scene_free(scene);
		distinct += prev && strcmp(prev, t);
		free(prev);
		prev = t;
	}
	free(prev);
	CHECK(distinct == 199);
	pc_family_free(f);
	/* effect sets: one set drawn per sample, both sets drawn over 40 samples */
	const char *from =
	    "\"effects\": {\"diffuse\": true, \"cast_shadows\": {\"choice\": [true, false]}}";
	const char *to = "\"effects\": {\"choice\": [{\"noise\": false, \"diffuse\": true},"
	                 " {\"supersampling\": 2, \"crosstalk\": false}], \"weights\": [1, 3]}";
	const char *at = strstr(small_spec, from);
	CHECK(at != NULL);
	if (!at)
		return;
	char *t = malloc(strlen(small_spec) + strlen(to) + 1);
	memcpy(t, small_spec, (size_t)(at - small_spec));
	strcpy(t + (at - small_spec), to);
	strcat(t, at + strlen(from));
	CHECK(pc_family_parse(t, "sets.json", tmp, &f) == 0);
	free(t);
	int set_a = 0, set_b = 0;
	for (uint64_t i = 0; f && i < 40; i++) {
		char *text;
		uint64_t ss;
		CHECK(pc_family_scene(f, 2, i, &text, &ss) == 0);
		json_t *j = json_loads(text, 0, NULL);
		json_t *fx = json_object_get(j, "effects");
		bool in_a = json_is_false(json_object_get(fx, "noise")) &&
		            json_is_true(json_object_get(fx, "diffuse"));
		bool in_b = json_integer_value(json_object_get(fx, "supersampling")) == 2 &&
		            json_is_false(json_object_get(fx, "crosstalk"));
		CHECK(in_a != in_b); /* exactly one set, whole */
		set_a += in_a;
		set_b += in_b;
		json_decref(j);
		free(text);
	}
	CHECK(set_a >= 3 && set_b >= 15 && set_a < set_b); /* weights 1 : 3 */
	pc_family_free(f);
}

static void test_sharding(void)
{
	enum { N = 9 };
	char ref[1200], d[1200], a[1400], b[1400];
	snprintf(ref, sizeof ref, "%s/ref", tmp);
	CHECK(make(ref, 11, N, 0, 1, 1) == 0);
	CHECK(pc_dataset_merge(ref, NULL) == 0);
	snprintf(a, sizeof a, "%s/manifest.jsonl", ref);
	const uint32_t shardings[] = {2, 4, 7};
	for (int k = 0; k < 3; k++) {
		snprintf(d, sizeof d, "%s/sh%u", tmp, shardings[k]);
		for (uint32_t s = shardings[k]; s-- > 0;) /* shards in reverse order, 2 threads */
			CHECK(make(d, 11, N, s, shardings[k], 2) == 0);
		uint64_t n = 0;
		CHECK(pc_dataset_merge(d, &n) == 0 && n == N);
		snprintf(b, sizeof b, "%s/manifest.jsonl", d);
		CHECK(same_file(a, b));
		pc_dataset_verify_result r;
		CHECK(pc_dataset_verify(d, &r) == 0 && r.ok == N && r.count == N);
	}
	/* another seed: other samples */
	snprintf(d, sizeof d, "%s/seed12", tmp);
	CHECK(make(d, 12, 2, 0, 1, 0) == 0);
	char x[1400], y[1400];
	snprintf(x, sizeof x, "%s/samples/00000001/raw_000000.png", ref);
	snprintf(y, sizeof y, "%s/samples/00000001/raw_000000.png", d);
	size_t nx, ny;
	char *px = slurp(x, &nx), *py = slurp(y, &ny);
	CHECK(px && py && (nx != ny || memcmp(px, py, nx)));
	free(px);
	free(py);
	/* the same directory refuses another seed or count */
	CHECK(make(ref, 12, N, 0, 1, 1) == PC_EBUSY);
	CHECK(make(ref, 11, N + 1, 0, 1, 1) == PC_EBUSY);
	/* a second run of a complete shard makes nothing and keeps the manifest */
	CHECK(make(ref, 11, N, 0, 1, 1) == 0);
	CHECK(pc_dataset_merge(ref, NULL) == 0);
	snprintf(b, sizeof b, "%s/sh2/manifest.jsonl", tmp);
	CHECK(same_file(a, b));
}

/* ---- kill and restart ---- */

static int count_samples(const char *dir)
{
	char p[1300];
	snprintf(p, sizeof p, "%s/samples", dir);
	DIR *d = opendir(p);
	if (!d)
		return 0;
	int n = 0;
	struct dirent *e;
	while ((e = readdir(d)))
		n += e->d_name[0] != '.';
	closedir(d);
	return n;
}

static void test_kill_restart(const char *polarcam)
{
	enum { N = 9 };
	char d[1200], a[1400], b[1400];
	snprintf(d, sizeof d, "%s/killed", tmp);
	if (!polarcam) {
		fprintf(stderr,
		        "POLARCAM not set: the kill test needs the CLI (run through ctest)\n");
		return;
	}
	pid_t pid = fork();
	if (pid == 0) {
		freopen("/dev/null", "w", stdout);
		execl(polarcam, "polarcam", "dataset", spec_path, "-o", d, "--count", "9", "--seed",
		      "11", "-t", "1", (char *)NULL);
		_exit(127);
	}
	/* kill it once 3 samples are in place (poll), before it finishes */
	struct timespec ts = {0, 2000000};
	int status = 0;
	bool killed = false;
	for (int k = 0; k < 60000; k++) {
		if (count_samples(d) >= 3) {
			kill(pid, SIGKILL);
			killed = true;
			break;
		}
		if (waitpid(pid, &status, WNOHANG) == pid) {
			pid = -1;
			break;
		}
		nanosleep(&ts, NULL);
	}
	if (pid > 0)
		waitpid(pid, &status, 0);
	CHECK(killed);
	int before = count_samples(d);
	CHECK(before >= 3 && before < N);
	/* what a kill can leave besides: a half-written sample directory and a torn line */
	char p[2000], host[256];
	if (gethostname(host, sizeof host) || !*host)
		snprintf(host, sizeof host, "host");
	host[sizeof host - 1] = 0;
	for (char *ch = host; *ch; ch++)
		if (*ch == '/' || *ch == '.')
			*ch = '_';
	/* a pid that is not running (pid_max is at most 2^22) */
	snprintf(p, sizeof p, "%s/samples/.%08d.tmp.%s.%d", d, 7, host, 9999999);
	mkdir(p, 0755);
	snprintf(p, sizeof p, "%s/samples/.%08d.tmp.%s.%d/raw_000000.png", d, 7, host, 9999999);
	spit(p, "partial");
	/* a live run's temporary directory (of a process that is running: our parent) stays */
	char live[2000];
	snprintf(live, sizeof live, "%s/samples/.%08d.tmp.%s.%ld", d, 8, host, (long)getppid());
	mkdir(live, 0755);
	snprintf(p, sizeof p, "%s/manifests/shard-0-of-1.jsonl", d);
	FILE *fp = fopen(p, "a");
	fputs("{\"files\":{\"meta.json\":{\"by", fp);
	fclose(fp);
	/* restart (in process, another thread count) */
	CHECK(make(d, 11, N, 0, 1, 2) == 0);
	CHECK(count_samples(d) == N);
	snprintf(p, sizeof p, "%s/samples/.%08d.tmp.%s.%d", d, 7, host, 9999999);
	struct stat st;
	CHECK(stat(p, &st) != 0);    /* the stale temporary directory is gone */
	CHECK(stat(live, &st) == 0); /* the live one is not */
	rmdir(live);
	CHECK(pc_dataset_merge(d, NULL) == 0);
	snprintf(a, sizeof a, "%s/ref/manifest.jsonl", tmp);
	snprintf(b, sizeof b, "%s/manifest.jsonl", d);
	CHECK(same_file(a, b));
	/* a sample renamed into place whose manifest line was lost: re-hashed, not re-rendered */
	snprintf(p, sizeof p, "%s/manifests/shard-0-of-1.jsonl", d);
	char *m = slurp(p, NULL);
	char *l4 = m ? strstr(m, "\"index\":4,") : NULL;
	if (l4) {
		char *start = l4;
		while (start > m && start[-1] != '\n')
			start--;
		char *end = strchr(l4, '\n');
		memmove(start, end + 1, strlen(end + 1) + 1);
		spit(p, m);
	}
	free(m);
	CHECK(l4 != NULL);
	pc_dataset_options o;
	memset(&o, 0, sizeof o);
	o.spec = spec_path;
	o.dir = d;
	o.seed = 11;
	o.count = N;
	o.shards = 1;
	pc_dataset_result r;
	CHECK(pc_dataset_run(&o, &r) == 0 && r.made == 0 && r.repaired == 1 && r.skipped == N);
	CHECK(pc_dataset_merge(d, NULL) == 0);
	CHECK(same_file(a, b));
}

/* ---- verify and merge refuse ---- */

static void test_verify(void)
{
	char d[1200], p[4000];
	snprintf(d, sizeof d, "%s/sh4", tmp);
	pc_dataset_verify_result r;
	/* a flipped byte */
	snprintf(p, sizeof p, "%s/samples/00000002/truth_stokes.npy", d);
	FILE *fp = fopen(p, "r+b");
	CHECK(fp != NULL);
	if (fp) {
		fseek(fp, 500, SEEK_SET);
		int c = fgetc(fp);
		fseek(fp, 500, SEEK_SET);
		fputc(c ^ 1, fp);
		fclose(fp);
	}
	CHECK(pc_dataset_verify(d, &r) == 0 && r.corrupt == 1 && r.ok == r.count - 1 &&
	      r.first_bad == 2 && strstr(r.first_problem, "truth_stokes.npy"));
	/* an extra file */
	snprintf(p, sizeof p, "%s/samples/00000005/extra.txt", d);
	spit(p, "x");
	CHECK(pc_dataset_verify(d, &r) == 0 && r.corrupt == 2);
	/* a missing sample, and merge refusing while a shard's lines are missing */
	snprintf(d, sizeof d, "%s/sh7", tmp);
	snprintf(p, sizeof p,
	         "rm -rf %s/samples/00000006 %s/manifests/shard-6-of-7.jsonl %s/manifest.jsonl", d,
	         d, d);
	CHECK(system(p) == 0);
	CHECK(pc_dataset_verify(d, &r) == 0 && r.missing == 1 && r.first_bad == 6);
	CHECK(pc_dataset_merge(d, NULL) == PC_EINVAL && strstr(pc_error_detail(), "the first: 6"));
	snprintf(p, sizeof p, "%s/manifest.jsonl", d);
	struct stat st;
	CHECK(stat(p, &st) != 0);
	/* the missing shard again: complete */
	CHECK(make(d, 11, 9, 6, 7, 0) == 0);
	CHECK(pc_dataset_verify(d, &r) == 0 && r.ok == 9);
}

/* ---- re-render with polarcam render ---- */

static void test_rerender(const char *polarcam)
{
	if (!polarcam)
		return;
	/* every sample of the reference: scene.json + its seed → the same bytes */
	int meshes = 0;
	for (int i = 0; i < 9; i++) {
		char s[1400], m[1500], out[1400], cmd[5000], a[1500], b[1500];
		snprintf(s, sizeof s, "%s/ref/samples/%08d", tmp, i);
		snprintf(m, sizeof m, "%s/meta.json", s);
		json_t *meta = json_load_file(m, 0, NULL);
		CHECK(meta != NULL);
		if (!meta)
			continue;
		json_t *extra = json_object_get(meta, "extra");
		json_int_t seed = json_integer_value(
		    json_object_get(json_object_get(extra, "sample"), "sim_seed"));
		json_t *scene = json_object_get(extra, "scene");
		json_t *objs = json_object_get(scene, "objects");
		for (size_t k = 0; k < json_array_size(objs); k++)
			meshes += json_object_get(json_array_get(objs, k), "file") != NULL;
		/* the sample is a recording: the file: source and the pipeline read it, with the
		 * black level of its scene's sensor */
		pc_recording *rec = NULL;
		CHECK(pc_recording_open(&rec, s) == 0);
		if (rec) {
			json_t *off =
			    json_object_get(json_object_get(scene, "sensor"), "offset_dn");
			CHECK(pc_recording_is_complete(rec) && pc_recording_count(rec) >= 1);
			if (off)
				CHECK(pc_recording_black_level(rec) == json_number_value(off));
			pc_recording_free(rec);
		}
		snprintf(out, sizeof out, "%s/rr%d", tmp, i);
		snprintf(cmd, sizeof cmd,
		         "'%s' render '%s/scene.json' --seed %lld -o '%s' > /dev/null", polarcam, s,
		         (long long)seed, out);
		CHECK(system(cmd) == 0);
		snprintf(a, sizeof a, "%s/raw_000000.png", s);
		snprintf(b, sizeof b, "%s/raw_000000.png", out);
		CHECK(same_file(a, b));
		snprintf(a, sizeof a, "%s/truth_stokes.npy", s);
		snprintf(b, sizeof b, "%s/truth_stokes.npy", out);
		CHECK(same_file(a, b));
		/* meta.json: the same frames and simulator as render's, the sample beside them */
		snprintf(b, sizeof b, "%s/meta.json", out);
		json_t *rm = json_load_file(b, 0, NULL);
		CHECK(rm != NULL);
		if (rm) {
			json_t *rx = json_object_get(rm, "extra");
			CHECK(json_equal(json_object_get(meta, "frames"),
			                 json_object_get(rm, "frames")));
			CHECK(json_equal(json_object_get(extra, "sensor"),
			                 json_object_get(rx, "sensor")));
			CHECK(json_equal(json_object_get(extra, "effects"),
			                 json_object_get(rx, "effects")));
			json_decref(rm);
		}
		json_decref(meta);
	}
	CHECK(meshes >= 1); /* the mesh path through DIR/meshes was exercised */
}

/* ---- float16 ---- */

static void test_f16(void)
{
	const float in[] = {1.0f,           -2.0f,
	                    65504.0f,       65520.0f,
	                    1e9f,           6.103515625e-05f,
	                    5.9604645e-08f, 2.98e-08f,
	                    2.9802322e-08f, 1.00048828125f,
	                    1.00146484375f, 0.0f,
	                    -0.0f,          NAN,
	                    INFINITY,       0.333333343f};
	const uint16_t want[] = {0x3C00, 0xC000, 0x7BFF, 0x7C00, 0x7C00, 0x0400, 0x0001, 0x0000,
	                         0x0000, 0x3C00, 0x3C02, 0x0000, 0x8000, 0x7E00, 0x7C00, 0x3555};
	uint16_t got[16];
	pc_f32_to_f16(in, got, 16);
	for (int i = 0; i < 16; i++) {
		if (got[i] != want[i])
			fprintf(stderr, "f16(%g) = %04x, expected %04x\n", (double)in[i], got[i],
			        want[i]);
		CHECK(got[i] == want[i]);
	}
#if defined(__FLT16_MAX__)
	/* every float32 exponent and many significands against the compiler's conversion */
	int diff = 0;
	for (uint32_t k = 0; k < 2000000; k++) {
		uint32_t bits = k * 2147u ^ (k << 13);
		float x;
		memcpy(&x, &bits, sizeof x);
		if (x != x)
			continue;
		_Float16 h = (_Float16)x;
		uint16_t hb, mine;
		memcpy(&hb, &h, sizeof hb);
		pc_f32_to_f16(&x, &mine, 1);
		diff += hb != mine;
	}
	CHECK(diff == 0);
#endif
	/* a float16 dataset's truth = f16(float32 truth) */
	char spec2[1300], d[1200], a[1400], b[1400];
	snprintf(spec2, sizeof spec2, "%s/f16/spec.json", tmp);
	snprintf(d, sizeof d, "%s/f16", tmp);
	mkdir(d, 0755);
	char *t = strdup(small_spec), *at = strstr(t, "\"float32\"");
	memcpy(at, "\"float16\"", 9);
	/* the mesh, beside the spec */
	char cmd[4000];
	snprintf(cmd, sizeof cmd, "cp '%s/torus.obj' '%s/'", tmp, d);
	CHECK(system(cmd) == 0);
	spit(spec2, t);
	free(t);
	pc_dataset_options o;
	memset(&o, 0, sizeof o);
	o.spec = spec2;
	snprintf(a, sizeof a, "%s/data", d);
	o.dir = a;
	o.seed = 11;
	o.count = 2;
	o.shards = 1;
	pc_dataset_result r;
	CHECK(pc_dataset_run(&o, &r) == 0);
	pc_array h, f;
	snprintf(a, sizeof a, "%s/data/samples/00000001/truth_stokes.npy", d);
	snprintf(b, sizeof b, "%s/ref/samples/00000001/truth_stokes.npy", tmp);
	size_t nh = 0;
	char *raw = slurp(a, &nh);
	bool f2 = false; /* the header (after the magic's NUL bytes) names the dtype */
	for (size_t k = 0; raw && k + 14 <= nh && k < 128; k++)
		f2 |= !memcmp(raw + k, "'descr': '<f2'", 14);
	CHECK(f2);
	CHECK(pc_npy_read(b, &f) == 0);
	size_t n = pc_array_count(&f);
	CHECK(nh == 128 + 2 * n);
	if (raw && nh == 128 + 2 * n) {
		uint16_t *conv = malloc(n * sizeof *conv);
		pc_f32_to_f16(f.data, conv, n);
		CHECK(!memcmp(raw + 128, conv, 2 * n));
		free(conv);
	}
	(void)h;
	free(raw);
	pc_array_free(&f);
}

/* ---- SHA-256, environment ---- */

static void test_sha_env(void)
{
	char p[1300], hex[65];
	uint64_t n;
	snprintf(p, sizeof p, "%s/abc", tmp);
	spit(p, "abc");
	CHECK(pc_sha256_file(p, hex, &n) == 0 && n == 3);
	CHECK(!strcmp(hex, "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"));
	uint32_t s = 9, m = 9;
	const char *sch = NULL;
	unsetenv("SLURM_ARRAY_TASK_ID");
	unsetenv("JOB_COMPLETION_INDEX");
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) == 0);
	setenv("SLURM_ARRAY_TASK_ID", "5", 1);
	setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
	setenv("SLURM_ARRAY_TASK_MIN", "3", 1);
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) == 1 && s == 2 && m == 4 &&
	      !strcmp(sch, "slurm"));
	setenv("SLURM_ARRAY_TASK_ID", "7", 1);
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) < 0 &&
	      strstr(pc_error_detail(), "outside"));
	setenv("SLURM_ARRAY_TASK_ID", "x", 1);
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) < 0 &&
	      strstr(pc_error_detail(), "SLURM_ARRAY_TASK_ID='x'"));
	unsetenv("SLURM_ARRAY_TASK_ID");
	unsetenv("SLURM_ARRAY_TASK_COUNT");
	unsetenv("SLURM_ARRAY_TASK_MIN");
	setenv("JOB_COMPLETION_INDEX", "3", 1);
	unsetenv("POLARCAM_SHARDS");
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) < 0 &&
	      strstr(pc_error_detail(), "--shards"));
	CHECK(pc_dataset_shard_from_env(8, &s, &m, &sch) == 1 && s == 3 && m == 8 &&
	      !strcmp(sch, "kubernetes"));
	setenv("POLARCAM_SHARDS", "3", 1);
	CHECK(pc_dataset_shard_from_env(0, &s, &m, &sch) < 0); /* index 3 of 3 */
	unsetenv("JOB_COMPLETION_INDEX");
	unsetenv("POLARCAM_SHARDS");
}

/* ---- the CLI: bad arguments exit 2 and write nothing; verify's status ---- */

static int cli(const char *polarcam, const char *args)
{
	char cmd[8400];
	snprintf(cmd, sizeof cmd, "'%s' %s >/dev/null 2>&1", polarcam, args);
	int st = system(cmd);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void test_cli(const char *polarcam)
{
	if (!polarcam)
		return;
	char a[4000], d[1200];
	struct stat st;
	snprintf(d, sizeof d, "%s/cli", tmp);
	const char *bad[] = {"--shard 4/4",           "--shard 1-2", "--shard x",
	                     "--resolution 0x5",      "--count 0",   "--count 3 --seed -1",
	                     "--count 3 --frobnicate"};
	for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
		snprintf(a, sizeof a, "dataset '%s' -o '%s' %s%s", spec_path, d, bad[i],
		         strstr(bad[i], "--count") ? "" : " --count 3");
		int rc = cli(polarcam, a);
		if (rc != 2)
			fprintf(stderr, "polarcam %s: exit %d, expected 2\n", a, rc);
		CHECK(rc == 2);
		CHECK(stat(d, &st) != 0);
	}
	/* a malformed scheduler environment is a usage error too */
	setenv("SLURM_ARRAY_TASK_ID", "2", 1);
	setenv("SLURM_ARRAY_TASK_COUNT", "2", 1);
	snprintf(a, sizeof a, "dataset '%s' -o '%s' --count 3", spec_path, d);
	CHECK(cli(polarcam, a) == 2);
	unsetenv("SLURM_ARRAY_TASK_ID");
	unsetenv("SLURM_ARRAY_TASK_COUNT");
	CHECK(stat(d, &st) != 0);
	/* verify: 0 complete, 1 when not, 2 on no dataset */
	snprintf(a, sizeof a, "dataset verify '%s/ref'", tmp);
	CHECK(cli(polarcam, a) == 0);
	snprintf(a, sizeof a, "dataset verify '%s/sh4'", tmp); /* corrupted by test_verify */
	CHECK(cli(polarcam, a) == 1);
	snprintf(a, sizeof a, "dataset verify '%s/nothing-here'", tmp);
	CHECK(cli(polarcam, a) >= 1);
	CHECK(cli(polarcam, "dataset --help") == 0);
}

/* ---- exposure of the shipped family ---- */

static void test_demosaic_family(const char *src)
{
	if (!src)
		return;
	char p[1300];
	snprintf(p, sizeof p, "%s/scenes/dataset/demosaic.json", src);
	pc_family *f = NULL;
	CHECK(pc_family_load(p, &f) == 0);
	if (!f)
		return;
	CHECK(pc_family_set_resolution(f, 160, 128) == 0);
	double worst_sat = 0, worst_median = 1e9;
	for (uint64_t i = 0; i < 16; i++) {
		pc_family_sample s;
		CHECK(pc_family_render(f, 0, i, 0, &s) == 0);
		double fs = (double)((1u << s.info.bits) - 1);
		worst_sat = fmax(worst_sat, s.saturated_fraction);
		worst_median = fmin(worst_median, s.median_dn / fs);
		pc_family_sample_free(&s);
	}
	printf("test_dataset: demosaic family, 16 samples at 160x128: worst saturated %.2f %%, "
	       "darkest median %.1f %% of full scale\n",
	       100 * worst_sat, 100 * worst_median);
	CHECK(worst_sat < 0.02);     /* few saturated pixels: the glints */
	CHECK(worst_median > 0.005); /* not black */
	pc_family_free(f);
}

int main(void)
{
	if (!mkdtemp(tmp)) {
		perror("mkdtemp");
		return 1;
	}
	const char *src = getenv("PC_SOURCE_DIR"), *polarcam = getenv("POLARCAM");
	char obj[1300];
	snprintf(obj, sizeof obj, "%s/torus.obj", tmp);
	if (src) {
		char cmd[3000];
		snprintf(cmd, sizeof cmd, "cp '%s/scenes/torus.obj' '%s'", src, obj);
		CHECK(system(cmd) == 0);
	} else {
		/* a small tetrahedron instead of the shipped torus */
		spit(obj, "v 0 0 0.5\nv 0.5 0 -0.3\nv -0.3 0.4 -0.3\nv -0.3 -0.4 -0.3\n"
		          "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
	}
	snprintf(spec_path, sizeof spec_path, "%s/small.json", tmp);
	spit(spec_path, small_spec);
	test_validation();
	test_scenes();
	test_sharding();
	test_kill_restart(polarcam);
	test_verify();
	test_rerender(polarcam);
	test_f16();
	test_sha_env();
	test_cli(polarcam);
	test_demosaic_family(src);
	char cmd[1200];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (!pc_test_failures)
		(void)system(cmd);
	return pc_test_finish("test_dataset");
}
