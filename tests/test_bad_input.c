/* The bad-input table (issue 13): every kind of input the CLI takes — image files (PNG, TIFF,
 * BMP, .npy), headerless raw geometry, recordings and their meta.json, scenes and OBJ meshes,
 * states.json, batch lines of pbrdf and decompose, source URIs, arguments and the limits'
 * environment variables — given wrong, hostile or extreme. For each case the test asserts
 *   - the exit status (2: bad input or arguments; 1: a failure such as memory);
 *   - that the message on stderr names what was wrong (the file, the line, the field or the
 *     option: the "needles"), holds no control bytes, and that stdout holds only JSON lines;
 *   - that nothing was written or overwritten: the case directory (inputs, an existing output
 *     with sentinel content for half the cases, nothing else) is byte-identical afterwards, no
 *     file added, none removed, none changed, no temporary left behind.
 * Each case runs `polarcam` ($POLARCAM) in its own directory; inputs are written by the test
 * (tests/hostile.h), or by polarcam itself where a valid recording is the starting point. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <jansson.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "children.h"
#include "hostile.h"

static const char *polarcam, *srcdir;
static char root[64];

/* ---- snapshots: every file under a directory with its size and content hash ---- */

typedef struct snap {
	char (*name)[600];
	uint64_t *size, *hash;
	size_t n, cap;
} snap;

static uint64_t fnv_file(const char *path, uint64_t *size)
{
	uint64_t h = 1469598103934665603ull;
	*size = 0;
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return 0;
	uint8_t buf[65536];
	size_t got;
	while ((got = fread(buf, 1, sizeof buf, fp)) > 0) {
		for (size_t i = 0; i < got; i++)
			h = (h ^ buf[i]) * 1099511628211ull;
		*size += got;
	}
	fclose(fp);
	return h;
}

static void snap_walk(snap *s, const char *dir, const char *rel)
{
	DIR *d = opendir(dir);
	if (!d)
		return;
	struct dirent *e;
	while ((e = readdir(d))) {
		if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
			continue;
		char path[1024], r[512];
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		snprintf(r, sizeof r, "%s%s%s", rel, *rel ? "/" : "", e->d_name);
		struct stat st;
		if (lstat(path, &st) != 0)
			continue;
		if (s->n == s->cap) {
			s->cap = s->cap ? 2 * s->cap : 64;
			s->name = realloc(s->name, s->cap * sizeof *s->name);
			s->size = realloc(s->size, s->cap * sizeof *s->size);
			s->hash = realloc(s->hash, s->cap * sizeof *s->hash);
		}
		snprintf(s->name[s->n], sizeof s->name[0], "%s%s", r,
		         S_ISDIR(st.st_mode) ? "/" : "");
		s->size[s->n] = 0;
		s->hash[s->n] = S_ISREG(st.st_mode) ? fnv_file(path, &s->size[s->n]) : 0;
		s->n++;
		if (S_ISDIR(st.st_mode))
			snap_walk(s, path, r);
	}
	closedir(d);
}

static void snap_free(snap *s)
{
	free(s->name);
	free(s->size);
	free(s->hash);
	memset(s, 0, sizeof *s);
}

/* Differences between two snapshots, printed; returns their number. */
static int snap_diff(const snap *a, const snap *b, const char *what)
{
	int d = 0;
	for (size_t i = 0; i < a->n; i++) {
		size_t j = 0;
		while (j < b->n && strcmp(a->name[i], b->name[j]))
			j++;
		if (j == b->n) {
			fprintf(stderr, "  %s: %s removed\n", what, a->name[i]);
			d++;
		} else if (a->size[i] != b->size[j] || a->hash[i] != b->hash[j]) {
			fprintf(stderr, "  %s: %s changed\n", what, a->name[i]);
			d++;
		}
	}
	for (size_t j = 0; j < b->n; j++) {
		size_t i = 0;
		while (i < a->n && strcmp(a->name[i], b->name[j]))
			i++;
		if (i == a->n) {
			fprintf(stderr, "  %s: %s added\n", what, b->name[j]);
			d++;
		}
	}
	return d;
}

/* ---- inputs ---- */

static void put(const char *name, const void *data, size_t n)
{
	if (hostile_write(name, data, n))
		fprintf(stderr, "cannot write %s\n", name);
}

static void puts_file(const char *name, const char *text)
{
	put(name, text, strlen(text));
}

static void cp(const char *from, const char *to)
{
	FILE *in = fopen(from, "rb"), *out = fopen(to, "wb");
	char buf[8192];
	size_t n;
	while (in && out && (n = fread(buf, 1, sizeof buf, in)) > 0)
		fwrite(buf, 1, n, out);
	if (in)
		fclose(in);
	if (out)
		fclose(out);
}

/* Replaces the first occurrence of `from` in a text file by `to`. */
static void edit(const char *name, const char *from, const char *to)
{
	FILE *fp = fopen(name, "rb");
	if (!fp)
		return;
	static char buf[1 << 20], out[1 << 20];
	size_t n = fread(buf, 1, sizeof buf - 1, fp);
	fclose(fp);
	buf[n] = '\0';
	char *p = strstr(buf, from);
	if (!p) {
		fprintf(stderr, "edit %s: '%s' not found\n", name, from);
		return;
	}
	size_t pre = (size_t)(p - buf);
	memcpy(out, buf, pre);
	strcpy(out + pre, to);
	strcat(out + pre, p + strlen(from));
	put(name, out, strlen(out));
}

static void npy(const char *name, const char *descr, const char *shape, const void *d, size_t n)
{
	char dict[160];
	snprintf(dict, sizeof dict, "{'descr': '%s', 'fortran_order': False, 'shape': %s, }", descr,
	         shape);
	hostile_npy(name, dict, d, n);
}

/* A valid 8×8 12-bit grey PNG (16-bit samples, values < 4096, sBIT 12): "ok.png". */
static void ok_png(void)
{
	/* written by polarcam itself from a valid .npy, below */
	uint16_t px[64];
	for (int i = 0; i < 64; i++)
		px[i] = (uint16_t)(i * 61 % 4096);
	npy("ok.npy", "<u2", "(8, 8)", px, sizeof px);
}

/* A small valid recording rendered by polarcam: DIR with 2 frames of an 8×8 ROI. */
static char rec_mono[600], rec_colour[600], rec_psg[600];

static int run_quiet(char *const argv[])
{
	pid_t pid = pc_child_spawn(argv, -1, "/dev/null");
	return pc_child_wait(pid, 300000, NULL);
}

static void make_recordings(void)
{
	struct {
		char *dir;
		const char *scene, *roi;
	} r[3] = {{rec_mono, "ideal_small.json", "100,100,8,8"},
	          {rec_colour, "colour_small.json", "0,0,8,8"},
	          {rec_psg, "mueller_tetrahedral.json", "0,0,8,8"}};
	for (int i = 0; i < 3; i++) {
		char scene[512];
		snprintf(scene, sizeof scene, "%s/scenes/%s", srcdir, r[i].scene);
		snprintf(r[i].dir, 600, "%s/rec%d", root, i);
		char *argv[] = {(char *)polarcam,
		                "render",
		                scene,
		                "-o",
		                r[i].dir,
		                "--roi",
		                (char *)r[i].roi,
		                "--no-truth",
		                i < 2 ? "-n" : NULL,
		                "2",
		                NULL};
		int st = run_quiet(argv);
		if (st != 0)
			fprintf(stderr, "render %s: status %d\n", r[i].scene, st);
	}
}

/* copies recording src (files only) into ./name */
static void copy_rec(const char *src, const char *name)
{
	mkdir(name, 0777);
	DIR *d = opendir(src);
	struct dirent *e;
	while (d && (e = readdir(d))) {
		if (e->d_name[0] == '.')
			continue;
		char a[1024], b[1024];
		snprintf(a, sizeof a, "%s/%s", src, e->d_name);
		snprintf(b, sizeof b, "%s/%s", name, e->d_name);
		cp(a, b);
	}
	if (d)
		closedir(d);
}

static const char *scene_json(const char *sensor, const char *objects, const char *materials)
{
	static char buf[8192];
	snprintf(
	    buf, sizeof buf,
	    "{\"polarcam_scene\": 1, \"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0],"
	    " \"focal_length_mm\": 12}, \"materials\": {%s}, \"lights\": [{\"type\": "
	    "\"directional\", \"direction\": [0, 0, 1], \"irradiance_w_m2\": 100}], \"objects\": "
	    "[%s], \"sensor\": {\"preset\": \"ideal\", \"resolution\": [8, 8]%s}}\n",
	    materials ? materials : "\"m\": {\"n\": 1.5, \"k\": 0, \"sigma\": 0.2}",
	    objects ? objects
	            : "{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1], "
	              "\"material\": \"m\"}",
	    sensor ? sensor : "");
	return buf;
}

static void scene_file(const char *sensor, const char *objects, const char *materials)
{
	puts_file("s.json", scene_json(sensor, objects, materials));
}

static void mesh_scene(const char *obj_text)
{
	puts_file("m.obj", obj_text);
	scene_file(NULL,
	           "{\"type\": \"mesh\", \"file\": \"m.obj\", \"material\": \"m\"}, {\"type\": "
	           "\"plane\", \"point\": [0, 0, -1], \"normal\": [0, 0, 1], \"material\": \"m\"}",
	           NULL);
}

/* ---- the cases ---- */

/* setups, one per input; each runs in the case's (empty) directory */
static void s_png_trunc(void)
{
	hostile_png("in.png", 64, 64, 16, 64);
	truncate("in.png", 60);
}
static void s_png_claim(void)
{
	hostile_png("in.png", 100000, 100000, 16, 0);
}
static void s_png_bomb(void)
{
	hostile_png("in.png", 2000, 2000, 8, 2000);
}
static void s_png_rgb(void)
{
	char p[600];
	snprintf(p, sizeof p, "%s/tests/fuzz/corpus/png/picture_rgb.png", srcdir);
	cp(p, "in.png");
}
static void s_png_text(void)
{
	puts_file("in.png", "this is not a PNG file\n");
}
static void s_png_empty(void)
{
	put("in.png", "", 0);
}
static void s_png_odd(void)
{
	hostile_png("in.png", 5, 4, 8, 4);
}
static void s_png_tiny(void)
{
	hostile_png("in.png", 2, 2, 8, 2);
}
static void s_png_12(void)
{
	char p[640];
	snprintf(p, sizeof p, "%s/raw_000000.png", rec_mono);
	cp(p, "in.png");
}
static void s_tif_pal(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_PALETTE, 4, 4);
}
static void s_tif_pal2(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_PALETTE_NOPHOTO, 4, 4);
}
static void s_tif_ycc(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_YCBCR_TILED, 16, 16);
}
static void s_tif_s16(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_SIGNED16, 4, 4);
}
static void s_tif_claim(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_GREY8, 8, 8);
	hostile_tiff_set("in.tif", TIFFTAG_IMAGEWIDTH, 100000);
	hostile_tiff_set("in.tif", TIFFTAG_IMAGELENGTH, 100000);
}
static void s_tif_off(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_GREY8, 8, 8);
	hostile_tiff_set("in.tif", TIFFTAG_STRIPOFFSETS, 1u << 30);
}
static void s_tif_trunc(void)
{
	hostile_tiff("in.tif", HOSTILE_TIFF_GREY8, 64, 64);
	truncate("in.tif", 200);
}
static void s_tif_rgb(void)
{
	char p[600];
	snprintf(p, sizeof p, "%s/tests/fuzz/corpus/tiff/demosaic_f32x4.tif", srcdir);
	cp(p, "in.tif");
}
static void s_bmp_claim(void)
{
	hostile_bmp("in.bmp", 1 << 20, 1 << 20, 16);
}
static void s_bmp_trunc(void)
{
	hostile_bmp("in.bmp", 400, 400, 100);
}
static void s_bmp_colour(void)
{
	hostile_bmp("in.bmp", 4, 4, 16);
	FILE *fp = fopen("in.bmp", "r+b");
	fseek(fp, 54 + 4 * 7, SEEK_SET);
	fputc(0xff, fp);
	fclose(fp);
}
static void s_bmp_rle(void)
{
	hostile_bmp("in.bmp", 4, 4, 16);
	FILE *fp = fopen("in.bmp", "r+b");
	fseek(fp, 30, SEEK_SET);
	fputc(1, fp);
	fclose(fp);
}
static void s_bmp_16(void)
{
	hostile_bmp("in.bmp", 4, 4, 32);
	FILE *fp = fopen("in.bmp", "r+b");
	fseek(fp, 28, SEEK_SET);
	fputc(16, fp);
	fclose(fp);
}
static void s_npy_huge(void)
{
	npy("in.npy", "<u2", "(10000000, 10000000)", NULL, 0);
}
static void s_npy_f8(void)
{
	double *d = calloc(600 * 600, sizeof *d);
	d[1000] = 1e39;
	npy("in.npy", "<f8", "(600, 600)", d, 600 * 600 * sizeof *d);
	free(d);
}
static void s_npy_fmax(void)
{
	float f[64];
	for (int i = 0; i < 64; i++)
		f[i] = (i & 1) ? 3.4e38f : -3.4e38f;
	npy("in.npy", "<f4", "(8, 8)", f, sizeof f);
}
static void s_npy_nan(void)
{
	float f[64] = {0};
	f[9] = NAN;
	npy("in.npy", "<f4", "(8, 8)", f, sizeof f);
}
static void s_npy_fortran(void)
{
	uint8_t b[64] = {0};
	hostile_npy("in.npy", "{'descr': '|u1', 'fortran_order': True, 'shape': (8, 8), }", b, 64);
}
static void s_npy_be(void)
{
	uint8_t b[256] = {0};
	npy("in.npy", ">f4", "(8, 8)", b, 256);
}
static void s_npy_3d(void)
{
	uint8_t b[128] = {0};
	npy("in.npy", "|u1", "(2, 8, 8)", b, 128);
}
static void s_npy_neg(void)
{
	uint8_t b[64] = {0};
	npy("in.npy", "|u1", "(-8, 8)", b, 64);
}
static void s_npy_magic(void)
{
	puts_file("in.npy", "NUMPY? no, this is text\n");
}
static void s_npy_ver(void)
{
	uint8_t b[16] = {0x93, 'N', 'U', 'M', 'P', 'Y', 9, 0, 4, 0, '{', '}', ' ', '\n'};
	put("in.npy", b, sizeof b);
}
static void s_npy_hlen(void)
{
	uint8_t b[12] = {0x93, 'N', 'U', 'M', 'P', 'Y', 2, 0, 0xff, 0xff, 0xff, 0x00};
	put("in.npy", b, sizeof b);
}
static void s_npy_ovf(void)
{
	uint8_t b[64] = {0};
	npy("in.npy", "<f8", "(4294967296, 4294967296)", b, 64);
}
static void s_npy_u2big(void)
{
	uint16_t px[64] = {0};
	px[10] = 5000;
	npy("in.npy", "<u2", "(8, 8)", px, sizeof px);
}
static void s_raw(void)
{
	uint8_t b[100];
	for (int i = 0; i < 100; i++)
		b[i] = (uint8_t)i;
	put("r.bin", b, sizeof b);
}
static void s_raw12(void)
{
	uint16_t m[64];
	for (int i = 0; i < 64; i++)
		m[i] = (uint16_t)(i * 50);
	m[27] = 55245;
	put("r.bin", m, sizeof m);
}
static void s_rec_corrupt(void)
{
	copy_rec(rec_colour, "rec");
	truncate("rec/meta.json", 200);
}
static void s_rec_nomosaic(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"mosaic\"", "\"mosaik\"");
}
static void s_rec_order(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"sequence\": 1", "\"sequence\": 0");
}
static void s_rec_missing(void)
{
	copy_rec(rec_mono, "rec");
	unlink("rec/raw_000001.png");
}
static void s_rec_ts(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"timestamp_ns\": 0", "\"timestamp_ns\": -5");
}
static void s_rec_ver(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"polarcam_recording\": 1", "\"polarcam_recording\": 2");
}
static void s_rec_bits(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"bits\": 12", "\"bits\": 10");
}
static void s_rec_width(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"width\": 8", "\"width\": 0");
}
/* found by fuzz_meta: a meta.json without "frames" crashed the reader (SIGSEGV) */
static void s_rec_noframes(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"frames\"", "\"framez\"");
}
static void s_rec_name(void)
{
	copy_rec(rec_mono, "rec");
	edit("rec/meta.json", "\"raw_000001.png\"", "\"raw_00000x.png\"");
}
static void s_sc_notjson(void)
{
	puts_file("s.json", "{\"polarcam_scene\": 1, \"camera\": [\n");
}
static void s_sc_key(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "\"camera\"", "\"camrea\": 1, \"camera\"");
}
static void s_sc_nocam(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json",
	     "\"camera\": {\"position\": [0, -5, 2], \"look_at\": [0, 0, 0], "
	     "\"focal_length_mm\": 12}, ",
	     "");
}
static void s_sc_res(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "[8, 8]", "[65534, 65534]");
}
static void s_sc_resodd(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "[8, 8]", "[9, 8]");
}
static void s_sc_sigma(void)
{
	scene_file(NULL, NULL, "\"m\": {\"n\": 1.5, \"k\": 0, \"sigma\": 1e-160}");
}
static void s_sc_n(void)
{
	scene_file(NULL, NULL, "\"m\": {\"n\": -1, \"k\": 0, \"sigma\": 0.2}");
}
static void s_sc_sigmastr(void)
{
	scene_file(NULL, NULL, "\"m\": {\"n\": 1.5, \"k\": 0, \"sigma\": \"abc\"}");
}
static void s_sc_fps(void)
{
	scene_file(", \"frame_rate_hz\": 1e-300", NULL, NULL);
}
static void s_sc_meshmissing(void)
{
	scene_file(NULL, "{\"type\": \"mesh\", \"file\": \"nowhere.obj\", \"material\": \"m\"}",
	           NULL);
}
static void s_obj_face(void)
{
	mesh_scene("v 0 0 0\nv 1 0 0\nv 0 1 0\n\n# x\nf 1/abc 2 3\n");
}
static void s_obj_far(void)
{
	mesh_scene("v 1e300 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n");
}
static void s_obj_many(void)
{
	mesh_scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3 4\n");
}
static void s_obj_index(void)
{
	mesh_scene("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
}
static void s_sc_nul(void)
{
	const char *t = scene_json(NULL, NULL, NULL);
	char b[8192];
	size_t n = strlen(t);
	memcpy(b, t, n);
	b[20] = '\0';
	put("s.json", b, n);
}
static void s_sc_nolights(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json",
	     "[{\"type\": \"directional\", \"direction\": [0, 0, 1], \"irradiance_w_m2\": "
	     "100}]",
	     "[]");
}
static void s_sc_irr(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "\"irradiance_w_m2\": 100", "\"irradiance_w_m2\": -100");
}
static void s_sc_dup(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "\"camera\"", "\"name\": \"a\", \"name\": \"b\", \"camera\"");
}
static void s_sc_ss(void)
{
	scene_file(NULL, NULL, NULL);
	edit("s.json", "\"sensor\"", "\"effects\": {\"supersampling\": 17}, \"sensor\"");
}
static void s_sc_bits(void)
{
	scene_file(", \"bits\": 9", NULL, NULL);
}
static void s_sc_ok(void)
{
	scene_file(NULL, NULL, NULL);
}
static void s_existing_rec(void)
{
	scene_file(NULL, NULL, NULL);
	copy_rec(rec_mono, "out");
}
static void s_batch_p(void)
{
	char b[1024];
	static const char head[] =
	    "1.5 0 0.2 30 30 180\n1.5 0 x 30 30 180\n1.5 0 0.2 30 30 180\0junk\n"
	    "1.5 0 \033[31mRED\x01 30 30 180\n1.5 0 0.2 30 30 1";
	int o = (int)sizeof head - 1;
	memcpy(b, head, sizeof head - 1);
	memset(b + o, '0', 130);
	o += 130;
	o += snprintf(b + o, sizeof b - (size_t)o,
	              "junk\n1 2 3\n1.5 0 0.2 95 30 180\n"
	              "1.5 0 1e-160 0 0 0\n");
	put("batch.txt", b, (size_t)o);
}
static void s_batch_d(void)
{
	const char b[] = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 0 0 0 0 1 0 0 0 0 1 0 0 0 0\n"
	                 "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1 7\n1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1e400\n"
	                 "1 0 0 0 0 1 0 0\0 0 0 1 0 0 0 0 1\n";
	put("batch.txt", b, sizeof b - 1);
}
static void s_states(const char *text)
{
	copy_rec(rec_psg, "rec");
	puts_file("st.json", text);
}
static void s_st_notjson(void)
{
	s_states("{\"polarcam_states\": 1,\n \"psg\": [");
}
static void s_st_psg3(void)
{
	s_states("{\"polarcam_states\": 1, \"frame_order\": \"psg_fastest\", \"psg\": [[1, 0, 0]], "
	         "\"psa\": [[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}");
}
static void s_st_nomagic(void)
{
	s_states("{\"frame_order\": \"psg_fastest\"}");
}
static void s_st_order(void)
{
	s_states(
	    "{\"polarcam_states\": 1, \"frame_order\": \"psa_fastest\", \"psg\": [[1, 0, 0, 0]], "
	    "\"psa\": [[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]]}");
}
static void calib_seed(void)
{
	char p[600];
	snprintf(p, sizeof p, "%s/tests/fuzz/corpus/calib/dark_flat_analyser.npz", srcdir);
	cp(p, "c.npz");
}
static void s_cal_trunc(void)
{
	calib_seed();
	truncate("c.npz", 1500);
}
static void s_cal_text(void)
{
	puts_file("c.npz", "not a zip archive\n");
}
static void s_cal_flip(void)
{
	calib_seed();
	FILE *fp = fopen("c.npz", "r+b");
	fseek(fp, 200, SEEK_SET);
	int c = fgetc(fp);
	fseek(fp, 200, SEEK_SET);
	fputc(c ^ 0x5a, fp);
	fclose(fp);
}
static void s_parent_file(void)
{
	ok_png();
	puts_file("afile", "x");
}
static void s_longname(void)
{
	ok_png();
}

/* table rows leave the optional last fields (env, existing_out) out */
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

typedef struct bad_case {
	const char *name;
	void (*setup)(void);
	const char *args[20]; /* after "polarcam"; NULL-terminated */
	int status;
	const char *needles[4]; /* each must appear in stderr */
	const char *env;        /* "NAME=value" for this case, or NULL */
	int existing_out;       /* create out/ with a sentinel first (must stay untouched, even
	                         * with --overwrite, which run_case adds) */
} bad_case;

#define OUT "-o", "out"
static const bad_case cases[] = {
    /* PNG */
    {"png truncated", s_png_trunc, {"process", "in.png", OUT}, 2, {"in.png"}},
    {"png claims 100000^2",
     s_png_claim,
     {"process", "in.png", OUT},
     2,
     {"in.png", "POLARCAM_MAX_PIXELS"}},
    {"png bomb over a lowered limit",
     s_png_bomb,
     {"process", "in.png", OUT},
     2,
     {"in.png", "4000000 pixels"},
     "POLARCAM_MAX_PIXELS=1M",
     1},
    {"png colour", s_png_rgb, {"process", "in.png", OUT}, 2, {"in.png", "colour"}},
    {"png is text", s_png_text, {"process", "in.png", OUT}, 2, {"in.png"}},
    {"png empty", s_png_empty, {"demosaic", "in.png", "-o", "out.npy"}, 2, {"in.png"}},
    {"png odd width", s_png_odd, {"process", "in.png", OUT}, 2, {"in.png", "even"}},
    {"png 2x2", s_png_tiny, {"demosaic", "in.png", "-o", "out.npy"}, 2, {"in.png", "at least 4"}},
    {"png 12-bit read as 8",
     s_png_12,
     {"process", "in.png", "--bits", "8", OUT},
     2,
     {"in.png", "bit depth"},
     NULL,
     1},
    {"png 12-bit with --bits 4",
     s_png_12,
     {"process", "in.png", "--bits", "4", OUT},
     2,
     {"in.png"}},
    /* TIFF */
    {"tiff palette", s_tif_pal, {"process", "in.tif", OUT}, 2, {"in.tif", "palette"}},
    {"tiff palette without photometric",
     s_tif_pal2,
     {"process", "in.tif", OUT},
     2,
     {"in.tif", "palette"},
     NULL,
     1},
    {"tiff YCbCr tiles", s_tif_ycc, {"process", "in.tif", OUT}, 2, {"in.tif", "YCbCr"}},
    {"tiff signed samples",
     s_tif_s16,
     {"demosaic", "in.tif", "-o", "out.npy"},
     2,
     {"in.tif", "signed"}},
    {"tiff claims 100000^2",
     s_tif_claim,
     {"process", "in.tif", OUT},
     2,
     {"in.tif", "POLARCAM_MAX_PIXELS"},
     NULL,
     1},
    {"tiff strip beyond the file", s_tif_off, {"process", "in.tif", OUT}, 2, {"in.tif", "beyond"}},
    {"tiff truncated", s_tif_trunc, {"process", "in.tif", OUT}, 2, {"in.tif"}},
    {"tiff 4 channels", s_tif_rgb, {"process", "in.tif", OUT}, 2, {"in.tif", "samples per pixel"}},
    /* BMP */
    {"bmp claims 2^20 x 2^20",
     s_bmp_claim,
     {"process", "in.bmp", OUT},
     2,
     {"in.bmp", "POLARCAM_MAX_PIXELS"}},
    {"bmp truncated", s_bmp_trunc, {"process", "in.bmp", OUT}, 2, {"in.bmp", "truncated"}, NULL, 1},
    {"bmp colour palette", s_bmp_colour, {"process", "in.bmp", OUT}, 2, {"in.bmp", "colour"}},
    {"bmp compressed", s_bmp_rle, {"process", "in.bmp", OUT}, 2, {"in.bmp", "compressed"}},
    {"bmp 16-bit", s_bmp_16, {"process", "in.bmp", OUT}, 2, {"in.bmp", "16-bit"}},
    /* .npy */
    {"npy declares (1e7, 1e7)",
     s_npy_huge,
     {"process", "in.npy", OUT},
     2,
     {"in.npy", "truncated"},
     NULL,
     1},
    {"npy float64 beyond float32",
     s_npy_f8,
     {"process", "in.npy", OUT},
     2,
     {"in.npy", "(400,1)", "1e+39"}},
    {"npy float32 at 3.4e38",
     s_npy_fmax,
     {"process", "in.npy", OUT},
     2,
     {"in.npy", "(0,0)", "2^24"}},
    {"npy NaN", s_npy_nan, {"process", "in.npy", OUT}, 2, {"in.npy", "(1,1)", "NaN"}},
    {"npy Fortran order", s_npy_fortran, {"process", "in.npy", OUT}, 2, {"in.npy", "Fortran"}},
    {"npy big-endian", s_npy_be, {"demosaic", "in.npy", "-o", "out.npy"}, 2, {"in.npy", "dtype"}},
    {"npy 3-D", s_npy_3d, {"process", "in.npy", OUT}, 2, {"in.npy", "3-D"}, NULL, 1},
    {"npy negative dimension", s_npy_neg, {"process", "in.npy", OUT}, 2, {"in.npy", "shape"}},
    {"npy bad magic", s_npy_magic, {"process", "in.npy", OUT}, 2, {"in.npy", "magic"}},
    {"npy version 9", s_npy_ver, {"process", "in.npy", OUT}, 2, {"in.npy", "version"}},
    {"npy header 16 MB", s_npy_hlen, {"process", "in.npy", OUT}, 2, {"in.npy", "implausible"}},
    {"npy shape overflows", s_npy_ovf, {"process", "in.npy", OUT}, 2, {"in.npy", "2^64"}},
    {"npy value above --bits 12",
     s_npy_u2big,
     {"process", "in.npy", "--bits", "12", OUT},
     2,
     {"in.npy", "5000"},
     NULL,
     1},
    /* headerless raw geometry */
    {"raw stride 2^64-1",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--offset", "10",
      "--stride", "18446744073709551615", "-o", "out.npy"},
     2,
     {"r.bin", "beyond any file"}},
    {"raw offset beyond the file",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--offset", "90",
      "-o", "out.npy"},
     2,
     {"r.bin", "truncated", "106"}},
    {"raw stride 2^63",
     s_raw,
     {"process", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--stride",
      "9223372036854775808", OUT},
     2,
     {"r.bin"},
     NULL,
     1},
    {"raw width 0",
     s_raw,
     {"demosaic", "r.bin", "--width", "0", "--height", "4", "--format", "Mono8", "-o", "out.npy"},
     2,
     {"--width"}},
    {"raw width 2^30+1",
     s_raw,
     {"demosaic", "r.bin", "--width", "1073741825", "--height", "4", "--format", "Mono8", "-o",
      "out.npy"},
     2,
     {"--width", "[1, 1073741824]"}},
    {"raw stride with junk",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--stride",
      "10junk", "-o", "out.npy"},
     2,
     {"--stride", "10junk"}},
    {"raw offset negative",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--offset", "-1",
      "-o", "out.npy"},
     2,
     {"--offset"}},
    {"raw offset hexadecimal",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--offset", "0x10",
      "-o", "out.npy"},
     2,
     {"--offset", "0x10"}},
    {"raw unknown format",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Bogus12", "-o", "out.npy"},
     2,
     {"--format", "Bogus12"}},
    {"raw geometry incomplete",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--format", "Mono8", "-o", "out.npy"},
     2,
     {"--height"}},
    {"raw Mono10p width 6",
     s_raw,
     {"demosaic", "r.bin", "--width", "6", "--height", "4", "--format", "Mono10p", "-o", "out.npy"},
     2,
     {"r.bin"}},
    {"raw width 5 (odd)",
     s_raw,
     {"process", "r.bin", "--width", "6", "--height", "5", "--format", "Mono8", OUT},
     2,
     {"r.bin", "even"},
     NULL,
     1},
    {"raw Mono12 holding 55245",
     s_raw12,
     {"process", "r.bin", "--width", "8", "--height", "8", "--format", "Mono12", OUT},
     2,
     {"r.bin", "pixel (3,3) = 55245"},
     NULL,
     1},
    {"--bits 17",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--bits", "17",
      "-o", "out.npy"},
     2,
     {"--bits", "[1, 16]"}},
    {"--threads 0",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--threads", "0",
      "-o", "out.npy"},
     2,
     {"--threads"}},
    /* recordings */
    {"colour recording, corrupt meta.json",
     s_rec_corrupt,
     {"process", "rec/raw_000000.png", OUT},
     2,
     {"rec/raw_000000.png", "meta.json"},
     NULL,
     1},
    {"meta.json polarized without mosaic",
     s_rec_nomosaic,
     {"process", "rec/raw_000000.png", OUT},
     2,
     {"meta.json", "mosaic"}},
    {"meta.json frames out of order",
     s_rec_order,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "sequence"}},
    {"recording frame missing",
     s_rec_missing,
     {"capture", "file:rec", "-n", "2", OUT},
     2,
     {"rec/raw_000001.png", "missing"}},
    {"meta.json negative timestamp",
     s_rec_ts,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "timestamp_ns"},
     NULL,
     1},
    {"meta.json version 2",
     s_rec_ver,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "polarcam_recording"}},
    {"meta.json bits do not match the format",
     s_rec_bits,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "bits"}},
    {"meta.json width 0",
     s_rec_width,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "width"}},
    {"meta.json frame file name",
     s_rec_name,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "frames[1].file"},
     NULL,
     1},
    {"meta.json without frames",
     s_rec_noframes,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json", "frames", "missing"}},
    {"meta.json corrupt, capture",
     s_rec_corrupt,
     {"capture", "file:rec", "-n", "1", OUT},
     2,
     {"meta.json"}},
    /* scenes and meshes */
    {"scene not JSON", s_sc_notjson, {"render", "s.json", OUT}, 2, {"s.json", "line"}},
    {"scene unknown key", s_sc_key, {"render", "s.json", OUT}, 2, {"s.json", "camrea"}, NULL, 1},
    {"scene without camera", s_sc_nocam, {"render", "s.json", OUT}, 2, {"s.json", "camera"}},
    {"scene resolution 65534^2",
     s_sc_res,
     {"render", "s.json", OUT},
     2,
     {"s.json", "sensor.resolution", "POLARCAM_MAX_PIXELS"}},
    {"scene resolution odd",
     s_sc_resodd,
     {"render", "s.json", OUT},
     2,
     {"s.json", "sensor.resolution"}},
    {"scene sigma 1e-160", s_sc_sigma, {"render", "s.json", OUT}, 2, {"s.json", "sigma"}, NULL, 1},
    {"scene n = -1", s_sc_n, {"render", "s.json", OUT}, 2, {"s.json", "materials.m.n"}},
    {"scene sigma a string", s_sc_sigmastr, {"render", "s.json", OUT}, 2, {"s.json", "sigma"}},
    {"scene 1e-300 Hz, 2 frames",
     s_sc_fps,
     {"render", "s.json", "-n", "2", OUT},
     2,
     {"timestamp"},
     NULL,
     1},
    {"scene mesh file missing",
     s_sc_meshmissing,
     {"render", "s.json", OUT},
     2,
     {"s.json", "nowhere.obj"}},
    {"obj face token junk", s_obj_face, {"render", "s.json", OUT}, 2, {"m.obj", "line 6", "1/abc"}},
    {"obj vertex 1e300", s_obj_far, {"render", "s.json", OUT}, 2, {"m.obj", "line 1"}, NULL, 1},
    {"obj over the triangle limit",
     s_obj_many,
     {"render", "s.json", OUT},
     2,
     {"m.obj", "POLARCAM_MAX_TRIANGLES"},
     "POLARCAM_MAX_TRIANGLES=1"},
    {"obj index out of range",
     s_obj_index,
     {"render", "s.json", OUT},
     2,
     {"m.obj", "line 4", "out of range"}},
    {"scene with a NUL byte", s_sc_nul, {"render", "s.json", OUT}, 2, {"s.json", "NUL"}},
    {"scene without lights",
     s_sc_nolights,
     {"render", "s.json", OUT},
     2,
     {"s.json", "lights"},
     NULL,
     1},
    {"scene negative irradiance",
     s_sc_irr,
     {"render", "s.json", OUT},
     2,
     {"s.json", "irradiance_w_m2"}},
    {"scene duplicate key", s_sc_dup, {"render", "s.json", OUT}, 2, {"s.json", "name"}},
    {"scene supersampling 17", s_sc_ss, {"render", "s.json", OUT}, 2, {"s.json", "supersampling"}},
    {"scene 9-bit sensor",
     s_sc_bits,
     {"render", "s.json", OUT},
     2,
     {"s.json", "sensor.bits"},
     NULL,
     1},
    {"render beyond POLARCAM_MAX_MEMORY",
     s_sc_ok,
     {"render", "s.json", OUT},
     1,
     {"POLARCAM_MAX_MEMORY", "8x8"},
     "POLARCAM_MAX_MEMORY=1k"},
    {"POLARCAM_MAX_PIXELS not a size",
     s_sc_ok,
     {"render", "s.json", OUT},
     2,
     {"POLARCAM_MAX_PIXELS='many'"},
     "POLARCAM_MAX_PIXELS=many",
     1},
    /* render arguments */
    {"render --first 2^63",
     s_sc_ok,
     {"render", "s.json", "--first", "9223372036854775808", OUT},
     2,
     {"--first", "[0, 9223372036854775807]"}},
    {"render --first 2^64-1 -n 2",
     s_sc_ok,
     {"render", "s.json", "--first", "18446744073709551615", "-n", "2", OUT},
     2,
     {"--first"},
     NULL,
     1},
    {"render --first beyond the timestamps",
     s_sc_ok,
     {"render", "s.json", "--first", "276701161105", "-n", "2", OUT},
     2,
     {"at most 276701161104"}},
    {"render over POLARCAM_MAX_FRAMES",
     s_sc_ok,
     {"render", "s.json", "-n", "3", OUT},
     2,
     {"frames", "POLARCAM_MAX_FRAMES"},
     "POLARCAM_MAX_FRAMES=2"},
    {"capture over POLARCAM_MAX_FRAMES",
     NULL,
     {"capture", "sim:default", "-n", "5", OUT},
     2,
     {"-n", "POLARCAM_MAX_FRAMES"},
     "POLARCAM_MAX_FRAMES=4",
     1},
    {"render --seed 0x10",
     s_sc_ok,
     {"render", "s.json", "--seed", "0x10", OUT},
     2,
     {"--seed", "0x10"}},
    {"render --seed 10junk",
     s_sc_ok,
     {"render", "s.json", "--seed", "10junk", OUT},
     2,
     {"--seed"},
     NULL,
     1},
    {"render -n 0", s_sc_ok, {"render", "s.json", "-n", "0", OUT}, 2, {"--frames"}},
    {"render -n 1000001",
     s_sc_ok,
     {"render", "s.json", "-n", "1000001", OUT},
     2,
     {"--frames", "1000000"}},
    {"render --roi with three numbers",
     s_sc_ok,
     {"render", "s.json", "--roi", "1,2,3", OUT},
     2,
     {"--roi"}},
    {"render --roi of width 0",
     s_sc_ok,
     {"render", "s.json", "--roi", "0,0,0,8", OUT},
     2,
     {"--roi"},
     NULL,
     1},
    {"render --roi beyond the sensor",
     s_sc_ok,
     {"render", "s.json", "--roi", "4,4,8,8", OUT},
     2,
     {"ROI"}},
    {"render into a recording",
     s_existing_rec,
     {"render", "s.json", OUT},
     2,
     {"out", "--overwrite"}},
    {"render -o without a value", s_sc_ok, {"render", "s.json", "-o"}, 2, {"-o"}},
    {"render scene missing", s_sc_ok, {"render", "nosuch.json", OUT}, 2, {"nosuch.json"}, NULL, 1},
    /* pbrdf and decompose arguments */
    {"pbrdf --n 0",
     NULL,
     {"pbrdf", "--n", "0", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30"},
     2,
     {"--n"}},
    {"pbrdf --k -1",
     NULL,
     {"pbrdf", "--n", "1.5", "--k", "-1", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30"},
     2,
     {"--k"}},
    {"pbrdf --sigma 1e-160",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "1e-160", "--theta-i", "0", "--theta-r", "0"},
     2,
     {"sigma = 1e-160", "1e-50"}},
    {"pbrdf --sigma 1e-320 (subnormal)",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "1e-320", "--theta-i", "0", "--theta-r", "0"},
     2,
     {"sigma = 9.99989e-321", "1e-50"}},
    {"pbrdf --sigma 1e-400",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "1e-400", "--theta-i", "0", "--theta-r", "0"},
     2,
     {"--sigma", "smallest double"}},
    {"pbrdf --theta-i 91",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "0.2", "--theta-i", "91", "--theta-r", "30"},
     2,
     {"--theta-i"}},
    {"pbrdf --phi nan",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30", "--phi",
      "nan"},
     2,
     {"--phi"}},
    {"pbrdf --rho quad:1025",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30", "--rho",
      "quad:1025"},
     2,
     {"--rho"}},
    {"pbrdf --n 1e101",
     NULL,
     {"pbrdf", "--n", "1e101", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30"},
     2,
     {"1e+101", "1e100"}},
    {"pbrdf --sigma step 0",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "0:1:0", "--theta-i", "30", "--theta-r", "30"},
     2,
     {"--sigma", "step"}},
    {"pbrdf --diffuse foo",
     NULL,
     {"pbrdf", "--n", "1.5", "--sigma", "0.2", "--theta-i", "30", "--theta-r", "30", "--diffuse",
      "foo"},
     2,
     {"--diffuse", "foo"}},
    {"pbrdf batch lines",
     s_batch_p,
     {"pbrdf", "--batch", "batch.txt"},
     2,
     {"batch.txt line 2: field 3 (sigma)", "line 3: byte 20 is a NUL",
      "line 4: field 3 (sigma) '\\x1b[31mRED\\x01'", "line 5: field 6 (phi)"}},
    {"pbrdf batch lines, more",
     s_batch_p,
     {"pbrdf", "--batch", "batch.txt"},
     2,
     {"line 6: expected 6 numbers", "line 7", "theta_i", "line 8: sigma = 1e-160"}},
    {"pbrdf batch file missing",
     NULL,
     {"pbrdf", "--batch", "nosuch.txt"},
     2,
     {"--batch", "nosuch.txt"}},
    {"decompose 15 numbers",
     NULL,
     {"decompose", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0"},
     2,
     {"expected 16", "got 15"}},
    {"decompose element x",
     NULL,
     {"decompose", "1", "0", "x", "0", "0", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0"},
     2,
     {"element 3 (m02)"}},
    {"decompose 1e400",
     NULL,
     {"decompose", "1e400", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0"},
     2,
     {"element 1 (m00)"}},
    {"decompose batch lines",
     s_batch_d,
     {"decompose", "--batch", "batch.txt"},
     2,
     {"line 2: expected 16 numbers", "line 3: expected 16 numbers", "line 4: field 16 (m33)",
      "line 5: byte 16 is a NUL"}},
    {"decompose unknown option", NULL, {"decompose", "--filter"}, 2, {"--filter"}},
    /* states.json and Mueller imaging */
    {"states.json not JSON",
     s_st_notjson,
     {"mueller", "rec", "--states", "st.json", OUT},
     2,
     {"st.json", "line"}},
    {"states.json psg of 3 numbers",
     s_st_psg3,
     {"mueller", "rec", "--states", "st.json", OUT},
     2,
     {"st.json", "psg[0]"},
     NULL,
     1},
    {"states.json not a states file",
     s_st_nomagic,
     {"mueller", "rec", "--states", "st.json", OUT},
     2,
     {"st.json", "polarcam_states"}},
    {"states.json frame order",
     s_st_order,
     {"mueller", "rec", "--states", "st.json", OUT},
     2,
     {"st.json", "frame_order"}},
    /* calibration files */
    {"calibration truncated",
     s_cal_trunc,
     {"calibrate", "show", "c.npz", "--pictures", "out"},
     2,
     {"c.npz"}},
    {"calibration not a zip",
     s_cal_text,
     {"calibrate", "show", "c.npz", "--pictures", "out"},
     2,
     {"c.npz", "zip"},
     NULL,
     1},
    {"calibration with a flipped byte",
     s_cal_flip,
     {"calibrate", "show", "c.npz", "--pictures", "out"},
     2,
     {"c.npz"}},
    /* other arguments and URIs */
    {"demosaic --method nosuch",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--method",
      "nosuch", "-o", "out.npy"},
     2,
     {"--method", "nosuch"}},
    {"demosaic --layout 1,2,3",
     s_raw,
     {"demosaic", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--layout",
      "1,2,3", "-o", "out.npy"},
     2,
     {"--layout"}},
    {"process --picture-width abc",
     s_raw,
     {"process", "r.bin", "--width", "4", "--height", "4", "--format", "Mono8", "--picture-width",
      "abc", OUT},
     2,
     {"--picture-width"},
     NULL,
     1},
    {"capture sim: seed=x", NULL, {"capture", "sim:default?seed=x", "-n", "1", OUT}, 2, {"seed=x"}},
    {"capture sim: unknown option",
     NULL,
     {"capture", "sim:default?nosuch=1", "-n", "1", OUT},
     2,
     {"nosuch"}},
    {"capture file: missing",
     NULL,
     {"capture", "file:nowhere", "-n", "1", OUT},
     2,
     {"nowhere"},
     NULL,
     1},
    {"capture -n 0", NULL, {"capture", "sim:default", "-n", "0", OUT}, 2, {"-n"}},
    {"capture unknown scheme", NULL, {"capture", "ftp:x", "-n", "1", OUT}, 2, {"ftp"}},
    {"capture URI option twice",
     NULL,
     {"capture", "sim:default?seed=1&seed=2", "-n", "1", OUT},
     2,
     {"seed", "twice"}},
    {"output under a file",
     s_parent_file,
     {"demosaic", "ok.npy", "-o", "afile/out.npy"},
     1,
     {"afile/out.npy"}},
    {"output name over NAME_MAX",
     s_longname,
     {"demosaic", "ok.npy", "-o", "@LONG256"},
     2,
     {"aaaaaaaaaa", "too long"}},
};
#undef OUT

static int count_needles(const char *s, const char *n)
{
	return strstr(s, n) != NULL;
}

static void slurp(const char *path, char *buf, size_t cap)
{
	FILE *fp = fopen(path, "rb");
	size_t n = fp ? fread(buf, 1, cap - 1, fp) : 0;
	buf[n] = '\0';
	if (fp)
		fclose(fp);
}

static char long256[260], long254[260];

static void run_case(size_t i, const bad_case *c)
{
	char dir[128];
	snprintf(dir, sizeof dir, "%s/case%03zu", root, i);
	mkdir(dir, 0777);
	char cwd[1024];
	if (!getcwd(cwd, sizeof cwd) || chdir(dir) != 0) {
		CHECK(0);
		return;
	}
	if (c->setup)
		c->setup();
	if (c->existing_out) {
		mkdir("out", 0777);
		puts_file("out/sentinel.txt", "an earlier result that must stay\n");
		/* an earlier polarcam output (its description), which --overwrite may replace */
		puts_file("out/meta.json", "{\"earlier\": true}\n");
		puts_file("out.npy", "an earlier output that must stay\n");
	}
	if (c->env) {
		char e[128];
		snprintf(e, sizeof e, "%s", c->env);
		char *eq = strchr(e, '=');
		*eq = '\0';
		setenv(e, eq + 1, 1);
	}
	snap before = {0}, after = {0};
	snap_walk(&before, ".", "");
	char *argv[24] = {(char *)polarcam};
	int a = 1;
	for (int k = 0; k < 20 && c->args[k] && a < 23; k++)
		argv[a++] = !strcmp(c->args[k], "@LONG256") ? long256 : (char *)c->args[k];
	/* the earlier output must stay even when the user allows replacing it (without
	 * --overwrite the output rule refuses before the input is read) */
	if (c->existing_out && a < 23)
		argv[a++] = (char *)"--overwrite";
	argv[a] = NULL;
	int out = open("../stdout.txt", O_WRONLY | O_CREAT | O_TRUNC, 0644);
	pid_t pid = pc_child_spawn(argv, out, "../stderr.txt");
	close(out);
	int st = pc_child_wait(pid, 120000, NULL);
	snap_walk(&after, ".", "");
	if (c->env) {
		char e[128];
		snprintf(e, sizeof e, "%s", c->env);
		*strchr(e, '=') = '\0';
		unsetenv(e);
	}
	static char err[1 << 16], outbuf[1 << 16];
	slurp("../stderr.txt", err, sizeof err);
	slurp("../stdout.txt", outbuf, sizeof outbuf);
	bool ok = st == c->status;
	if (!ok)
		fprintf(stderr, "case %zu (%s): exit status %d, want %d\n", i, c->name, st,
		        c->status);
	for (int k = 0; k < 4 && c->needles[k]; k++)
		if (!count_needles(err, c->needles[k])) {
			fprintf(stderr, "case %zu (%s): message lacks '%s'\n", i, c->name,
			        c->needles[k]);
			ok = false;
		}
	/* a message on one line per error, nothing for a terminal to interpret, no crash report */
	for (const char *p = err; *p; p++)
		if ((unsigned char)*p < 0x20 && *p != '\n') {
			fprintf(stderr, "case %zu (%s): control byte %#x in the message\n", i,
			        c->name, (unsigned char)*p);
			ok = false;
			break;
		}
	if (strstr(err, "Sanitizer") || strstr(err, "runtime error")) {
		fprintf(stderr, "case %zu (%s): sanitizer report\n", i, c->name);
		ok = false;
	}
	if (!strstr(err, "polarcam ")) {
		fprintf(stderr, "case %zu (%s): no polarcam message\n", i, c->name);
		ok = false;
	}
	/* stdout: JSON lines only (batch error objects), never a success summary */
	char *save = NULL;
	for (char *l = strtok_r(outbuf, "\n", &save); l; l = strtok_r(NULL, "\n", &save)) {
		json_error_t je;
		json_t *j = json_loads(l, 0, &je);
		if (!j) {
			fprintf(stderr, "case %zu (%s): stdout line not JSON: %.120s\n", i, c->name,
			        l);
			ok = false;
		}
		json_decref(j);
	}
	char what[160];
	snprintf(what, sizeof what, "case %zu (%s)", i, c->name);
	if (snap_diff(&before, &after, what))
		ok = false;
	CHECK(ok);
	if (!ok)
		fprintf(stderr, "  stderr: %.600s\n", err);
	snap_free(&before);
	snap_free(&after);
	if (chdir(cwd) != 0)
		CHECK(0);
}

/* The positive control of the last case: a legal 254-byte name is written (the temporary
 * sibling used to exceed NAME_MAX), and no temporary remains. */
static void long_name_ok(void)
{
	char dir[128];
	snprintf(dir, sizeof dir, "%s/longname", root);
	mkdir(dir, 0777);
	char cwd[1024];
	if (!getcwd(cwd, sizeof cwd) || chdir(dir) != 0)
		return;
	ok_png();
	/* no validity mask: its name (OUT_valid.npy) could not be 254 bytes too */
	char *argv[] = {(char *)polarcam, "demosaic",     "ok.npy", "-o",
	                long254,          "--saturation", "none",   NULL};
	int st = pc_child_wait(pc_child_spawn(argv, open("/dev/null", O_WRONLY), "../stderr.txt"),
	                       120000, NULL);
	CHECK_EQ_INT(st, 0);
	CHECK(access(long254, F_OK) == 0);
	snap s = {0};
	snap_walk(&s, ".", "");
	CHECK_EQ_INT(s.n, 2); /* ok.npy and the output, nothing else */
	snap_free(&s);
	if (chdir(cwd) != 0)
		CHECK(0);
}

/* Float raws at the accepted bound (±2^24, io_internal.h) on an adversarial pattern (±v, 0,
 * v·1e-30 at random): every demosaicking method, fast and reference, gives finite Stokes, DoLP
 * and AoLP. 3.4e38 gave all-non-finite Stokes with exit 0; beyond the bound is refused (table). */
static bool npy_all_finite(const char *path)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return false;
	uint8_t h[10];
	bool ok = fread(h, 1, 10, fp) == 10;
	unsigned hl = h[8] | h[9] << 8;
	fseek(fp, 10 + (long)hl, SEEK_SET);
	float f[4096];
	size_t n;
	while (ok && (n = fread(f, sizeof f[0], 4096, fp)) > 0)
		for (size_t i = 0; i < n; i++)
			ok &= isfinite(f[i]) != 0;
	fclose(fp);
	return ok;
}

static void float_bound_ok(void)
{
	char dir[128];
	snprintf(dir, sizeof dir, "%s/floatbound", root);
	mkdir(dir, 0777);
	char cwd[1024];
	if (!getcwd(cwd, sizeof cwd) || chdir(dir) != 0)
		return;
	float f[32 * 32];
	uint32_t r = 1;
	for (int i = 0; i < 32 * 32; i++) {
		r = r * 1103515245u + 12345u;
		unsigned k = (r >> 16) % 4;
		f[i] = k == 0 ? 0x1p24f : k == 1 ? -0x1p24f : k == 2 ? 0.0f : 0x1p24f * 1e-30f;
	}
	npy("in.npy", "<f4", "(32, 32)", f, sizeof f);
	static const char *const methods[][2] = {{"superpixel-half", NULL},
	                                         {"superpixel", NULL},
	                                         {"bilinear", NULL},
	                                         {"bicubic", NULL},
	                                         {"ppid", NULL},
	                                         {"ri", NULL},
	                                         {"eari", NULL},
	                                         {"ratio", NULL},
	                                         {"bayer-first", "RGGB:90,45,135,0"},
	                                         {"bayer-eari", "RGGB:90,45,135,0"}};
	for (size_t m = 0; m < sizeof methods / sizeof methods[0]; m++)
		for (int ref = 0; ref < 2; ref++) {
			char *argv[12] = {
			    (char *)polarcam,     "process", "in.npy", "-o", "o", "--method",
			    (char *)methods[m][0]};
			int a = 7;
			if (methods[m][1]) {
				argv[a++] = "--layout";
				argv[a++] = (char *)methods[m][1];
			}
			if (ref)
				argv[a++] = "--reference";
			argv[a] = NULL;
			int st = pc_child_wait(
			    pc_child_spawn(argv, open("/dev/null", O_WRONLY), "../stderr.txt"),
			    120000, NULL);
			bool ok = st == 0 && npy_all_finite("o/stokes.npy") &&
			          npy_all_finite("o/dolp.npy") && npy_all_finite("o/aolp.npy");
			CHECK(ok);
			if (!ok)
				fprintf(
				    stderr,
				    "  float raw at 2^24, %s%s: status %d or non-finite output\n",
				    methods[m][0], ref ? " --reference" : "", st);
			if (system("rm -rf o") != 0)
				CHECK(0);
		}
	if (chdir(cwd) != 0)
		CHECK(0);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	srcdir = getenv("PC_SOURCE_DIR");
	if (!polarcam || !srcdir)
		SKIP("POLARCAM and PC_SOURCE_DIR are set by ctest");
	setenv("POLARCAM_PROGRESS", "0", 1);
	(void)pc_child_stop; /* children.h: only spawn and wait are needed here */
	snprintf(root, sizeof root, "/tmp/pc_bad_input_XXXXXX");
	if (!mkdtemp(root))
		SKIP("cannot create a temporary directory: %s", strerror(errno));
	memset(long256, 'a', 252);
	strcpy(long256 + 252, ".npy");
	memset(long254, 'b', 250);
	strcpy(long254 + 250, ".npy");
	make_recordings();
	size_t n = sizeof cases / sizeof cases[0];
	for (size_t i = 0; i < n; i++)
		run_case(i, &cases[i]);
	long_name_ok();
	float_bound_ok();
	printf("bad-input table: %zu cases\n", n);
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", root);
	return pc_test_finish("test_bad_input");
}
