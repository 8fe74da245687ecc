/* devices/dataset.c - datasets of scene-family samples (polarcam/dataset.h): the sample writer
 * (family render → files in a temporary directory → hashes → rename), the shard manifests,
 * merge and verify. */
#include "polarcam/dataset.h"

#include <dirent.h>
#include <signal.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <math.h>
#include <nettle/sha2.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "polarcam/error.h"
#include "polarcam/family.h"
#include "polarcam/format.h"
#include "polarcam/io.h"
#include "polarcam/mosaic.h"
#include "polarcam/recording.h"
#include "polarcam/render_recording.h"

#define MAX_COUNT 100000000ull /* samples/NNNNNNNN */

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- files ---- */

int pc_sha256_file(const char *path, char hex[65], uint64_t *bytes)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(PC_EIO, "%s: %s", path, strerror(errno));
	struct sha256_ctx c;
	sha256_init(&c);
	static _Thread_local uint8_t buf[1 << 16];
	uint64_t n = 0;
	size_t k;
	while ((k = fread(buf, 1, sizeof buf, fp)) > 0) {
		sha256_update(&c, k, buf);
		n += k;
	}
	int err = ferror(fp);
	fclose(fp);
	if (err)
		return pc_error(PC_EIO, "%s: read error", path);
	uint8_t d[SHA256_DIGEST_SIZE];
	sha256_digest(&c, sizeof d, d);
	for (int i = 0; i < SHA256_DIGEST_SIZE; i++)
		snprintf(hex + 2 * i, 3, "%02x", d[i]);
	if (bytes)
		*bytes = n;
	return 0;
}

static int read_text(const char *path, char **out, size_t max)
{
	*out = NULL;
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return errno == ENOENT ? PC_ENOENT
		                       : pc_error(PC_EIO, "%s: %s", path, strerror(errno));
	size_t cap = 4096, n = 0;
	char *b = malloc(cap);
	int rc = 0;
	while (b) {
		if (n + 1 >= cap) {
			if (cap >= max) {
				rc = pc_error(PC_EINVAL, "%s: larger than %zu bytes", path, max);
				break;
			}
			char *nb = realloc(b, cap * 2);
			if (!nb)
				break;
			b = nb;
			cap *= 2;
		}
		size_t k = fread(b + n, 1, cap - 1 - n, fp);
		n += k;
		if (k == 0)
			break;
	}
	fclose(fp);
	if (!b)
		return pc_error(PC_ENOMEM, "%s", path);
	if (rc) {
		free(b);
		return rc;
	}
	b[n] = 0;
	*out = b;
	return 0;
}

static int copy_file_atomic(const char *src, const char *dst)
{
	char *t = NULL;
	FILE *fp = fopen(src, "rb");
	if (!fp)
		return pc_error(PC_EIO, "%s: %s", src, strerror(errno));
	fseek(fp, 0, SEEK_END);
	long n = ftell(fp);
	fseek(fp, 0, SEEK_SET);
	if (n < 0 || n > (1l << 30) || !(t = malloc((size_t)n + 1)) ||
	    fread(t, 1, (size_t)n, fp) != (size_t)n) {
		fclose(fp);
		free(t);
		return pc_error(PC_EIO, "%s: cannot be read", src);
	}
	fclose(fp);
	int rc = pc_write_file_atomic(dst, t, (size_t)n);
	free(t);
	return rc;
}

static int rm_rf(const char *path)
{
	DIR *d = opendir(path);
	if (!d)
		return unlink(path) == 0 || errno == ENOENT ? 0 : -1;
	struct dirent *e;
	char p[4096];
	while ((e = readdir(d))) {
		if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
			continue;
		snprintf(p, sizeof p, "%s/%s", path, e->d_name);
		rm_rf(p);
	}
	closedir(d);
	return rmdir(path);
}

static void fsync_dir(const char *path)
{
	int fd = open(path, O_RDONLY | O_DIRECTORY);
	if (fd >= 0) {
		(void)fsync(fd);
		close(fd);
	}
}

static bool is_dir(const char *path)
{
	struct stat st;
	return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

static int cmp_str(const void *a, const void *b)
{
	return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The regular files of a directory, sorted (malloc'd names). */
static int list_files(const char *dir, char ***names, size_t *n)
{
	*names = NULL;
	*n = 0;
	DIR *d = opendir(dir);
	if (!d)
		return pc_error(PC_EIO, "%s: %s", dir, strerror(errno));
	size_t cap = 0;
	struct dirent *e;
	int rc = 0;
	while ((e = readdir(d))) {
		if (e->d_name[0] == '.')
			continue;
		if (*n == cap) {
			cap = cap ? 2 * cap : 16;
			char **nn = realloc(*names, cap * sizeof *nn);
			if (!nn) {
				rc = pc_error(PC_ENOMEM, "file list");
				break;
			}
			*names = nn;
		}
		if (!((*names)[(*n)++] = strdup(e->d_name))) {
			(*n)--;
			rc = pc_error(PC_ENOMEM, "file list");
			break;
		}
	}
	closedir(d);
	if (*n)
		qsort(*names, *n, sizeof **names, cmp_str);
	return rc;
}

static void free_list(char **names, size_t n)
{
	for (size_t i = 0; i < n; i++)
		free(names[i]);
	free(names);
}

/* ---- manifest lines ---- */

static void sample_rel(uint64_t i, char *buf, size_t n)
{
	snprintf(buf, n, "samples/%08llu", (unsigned long long)i);
}

/* The manifest line of complete sample i (no newline), from the files on disk. */
static int manifest_line(const char *dir, uint64_t i, char **line, uint64_t *bytes)
{
	char rel[64], sdir[4096];
	sample_rel(i, rel, sizeof rel);
	snprintf(sdir, sizeof sdir, "%s/%s", dir, rel);
	char **names;
	size_t n;
	int rc = list_files(sdir, &names, &n);
	if (rc)
		return rc;
	json_t *files = json_object();
	uint64_t total = 0;
	for (size_t k = 0; k < n && !rc; k++) {
		char p[4400], hex[65];
		uint64_t b;
		snprintf(p, sizeof p, "%s/%s", sdir, names[k]);
		if (!(rc = pc_sha256_file(p, hex, &b))) {
			json_object_set_new(
			    files, names[k],
			    json_pack("{s:I, s:s}", "bytes", (json_int_t)b, "sha256", hex));
			total += b;
		}
	}
	free_list(names, n);
	json_t *o =
	    json_pack("{s:I, s:s, s:o}", "index", (json_int_t)i, "sample", rel, "files", files);
	*line = rc ? NULL : json_dumps(o, JSON_COMPACT | JSON_SORT_KEYS);
	json_decref(o);
	if (!rc && !*line)
		rc = pc_error(PC_ENOMEM, "manifest line");
	if (bytes)
		*bytes = total;
	return rc;
}

/* Lines of a manifest file by index: complete lines only (a run killed while appending leaves
 * a partial last line, which is dropped). lines[i] for i < count, NULL where absent. */
static int read_manifest(const char *path, uint64_t count, char **lines, const char **bad)
{
	char *text;
	int rc = read_text(path, &text, (size_t)1 << 34);
	if (rc == PC_ENOENT)
		return 0;
	if (rc)
		return rc;
	char *p = text;
	unsigned line = 0;
	while (*p) {
		char *nl = strchr(p, '\n');
		line++;
		if (!nl)
			break; /* partial last line */
		*nl = 0;
		json_t *j = json_loads(p, 0, NULL);
		json_t *ix = j ? json_object_get(j, "index") : NULL;
		if (!json_is_integer(ix) || json_integer_value(ix) < 0 ||
		    (uint64_t)json_integer_value(ix) >= count ||
		    !json_is_object(json_object_get(j, "files"))) {
			json_decref(j);
			rc = pc_error(PC_EFORMAT,
			              "%s: line %u: not a manifest line of this dataset "
			              "(expected {\"index\": 0..%llu, \"files\": {...}, ...})",
			              path, line, (unsigned long long)count - 1);
			break;
		}
		uint64_t i = (uint64_t)json_integer_value(ix);
		json_decref(j);
		if (lines[i] && strcmp(lines[i], p)) {
			rc = pc_error(PC_EFORMAT,
			              "%s: line %u: sample %llu listed twice with different "
			              "files",
			              path, line, (unsigned long long)i);
			break;
		}
		if (!lines[i] && !(lines[i] = strdup(p))) {
			rc = pc_error(PC_ENOMEM, "manifest");
			break;
		}
		p = nl + 1;
	}
	free(text);
	if (rc && bad)
		*bad = path;
	return rc;
}

/* Writes the given lines (sorted by index) atomically. */
static int write_manifest(const char *path, char **lines, uint64_t count)
{
	size_t n = 0;
	for (uint64_t i = 0; i < count; i++)
		if (lines[i])
			n += strlen(lines[i]) + 1;
	char *t = malloc(n + 1), *q = t;
	if (!t)
		return pc_error(PC_ENOMEM, "manifest");
	for (uint64_t i = 0; i < count; i++)
		if (lines[i]) {
			size_t k = strlen(lines[i]);
			memcpy(q, lines[i], k);
			q[k] = '\n';
			q += k + 1;
		}
	int rc = pc_write_file_atomic(path, t, n);
	free(t);
	return rc;
}

static int append_line(const char *path, const char *line)
{
	int fd = open(path, O_WRONLY | O_CREAT | O_APPEND, 0644);
	if (fd < 0)
		return pc_error(PC_EIO, "%s: %s", path, strerror(errno));
	size_t n = strlen(line);
	char *t = malloc(n + 1);
	if (!t) {
		close(fd);
		return pc_error(PC_ENOMEM, "manifest line");
	}
	memcpy(t, line, n);
	t[n] = '\n';
	ssize_t w = write(fd, t, n + 1); /* one write: O_APPEND keeps lines whole between writers */
	free(t);
	int rc = w == (ssize_t)(n + 1) && fsync(fd) == 0
	             ? 0
	             : pc_error(PC_EIO, "%s: write failed", path);
	close(fd);
	return rc;
}

/* ---- dataset.json ---- */

/* The canonical dataset.json text of (family, seed, count). */
static char *dataset_text(const pc_family *f, uint64_t seed, uint64_t count)
{
	char *spec = pc_family_to_json(f);
	json_t *sj = spec ? json_loads(spec, 0, NULL) : NULL;
	free(spec);
	if (!sj)
		return NULL;
	json_t *o =
	    json_pack("{s:i, s:o, s:I, s:I, s:s}", "polarcam_dataset", 1, "family", sj, "seed",
	              (json_int_t)seed, "count", (json_int_t)count, "layout",
	              "samples/NNNNNNNN/{raw_NNNNNN.png, truth_stokes.npy, scene.json, meta.json}");
	char *t = json_dumps(o, JSON_INDENT(1) | JSON_SORT_KEYS | JSON_REAL_PRECISION(17));
	json_decref(o);
	if (!t)
		return NULL;
	size_t n = strlen(t);
	char *r = realloc(t, n + 2);
	if (!r) {
		free(t);
		return NULL;
	}
	r[n] = '\n';
	r[n + 1] = 0;
	return r;
}

/* dataset.json: count and seed (for verify and merge). */
static int read_dataset(const char *dir, uint64_t *count, uint64_t *seed)
{
	char p[4096], *t;
	snprintf(p, sizeof p, "%s/dataset.json", dir);
	int rc = read_text(p, &t, 64u << 20);
	if (rc == PC_ENOENT)
		return pc_error(PC_ENOENT, "%s: no dataset.json: not a polarcam dataset", dir);
	if (rc)
		return rc;
	json_error_t je;
	json_t *j = json_loads(t, 0, &je);
	free(t);
	json_t *c = j ? json_object_get(j, "count") : NULL,
	       *s = j ? json_object_get(j, "seed") : NULL;
	if (!json_is_integer(c) || json_integer_value(c) < 1 ||
	    (uint64_t)json_integer_value(c) > MAX_COUNT || !json_is_integer(s)) {
		json_decref(j);
		return pc_error(PC_EFORMAT,
		                "%s: expected a polarcam dataset description with \"count\" "
		                "(1..%llu) and \"seed\"",
		                p, MAX_COUNT);
	}
	*count = (uint64_t)json_integer_value(c);
	if (seed)
		*seed = (uint64_t)json_integer_value(s);
	json_decref(j);
	return 0;
}

/* ---- one sample ---- */

/* What the sample is, under meta.json's "extra": "sample" (index, seeds, exposure, statistics,
 * the truth file) beside the simulator's description, and "scene", the sample's scene. */
static int sample_extra(const pc_family *f, const pc_family_sample *s, uint64_t seed,
                        const char *truth_file, char **text)
{
	json_t *x = s->sim_json ? json_loads(s->sim_json, 0, NULL) : NULL;
	json_t *scene = json_loads(s->scene_json, 0, NULL);
	if (!x || !scene) {
		json_decref(x);
		json_decref(scene);
		return pc_error(PC_ENOMEM, "meta.json");
	}
	json_t *m = json_object();
	json_object_set_new(m, "polarcam_sample", json_integer(1));
	json_object_set_new(m, "family", json_string(pc_family_name(f)));
	json_object_set_new(m, "family_seed", json_integer((json_int_t)seed));
	json_object_set_new(m, "index", json_integer((json_int_t)s->index));
	json_object_set_new(m, "sim_seed", json_integer((json_int_t)s->sim_seed));
	json_object_set_new(m, "rerender",
	                    json_sprintf("polarcam render scene.json --seed %llu -n %u",
	                                 (unsigned long long)s->sim_seed, s->n_frames));
	if (truth_file) {
		json_t *t = json_object();
		json_object_set_new(t, "file", json_string(truth_file));
		json_object_set_new(t, "dtype",
		                    json_string(s->truth == PC_TRUTH_F16 ? "float16" : "float32"));
		json_object_set_new(t, "what",
		                    json_string("Stokes radiance S0..S3, W m^-2 sr^-1, image-"
		                                "plane frame (docs/scene-format.md); S3 NaN "
		                                "without the circular effect"));
		json_object_set_new(m, "truth", t);
	}
	json_object_set_new(m, "exposure_us", json_real(s->exposure_us));
	json_object_set_new(m, "dn_per_radiance", json_real(s->dn_per_radiance));
	json_object_set_new(m, "saturated_fraction", json_real(s->saturated_fraction));
	json_object_set_new(m, "median_dn", json_real(s->median_dn));
	json_object_set_new(m, "p99_dn", json_real(s->p99_dn));
	json_object_set_new(x, "sample", m);
	json_object_set_new(x, "scene", scene);
	*text = json_dumps(x, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(x);
	return *text ? 0 : pc_error(PC_ENOMEM, "meta.json");
}

/* The sample directory tmp: a recording (raw_NNNNNN.png + meta.json, the writers of `polarcam
 * render`, polarcam/recording.h) with the truth (pc_truth_write) and scene.json beside it. */
static int write_sample_files(const pc_family *f, const pc_family_sample *s, uint64_t seed,
                              const char *tmp)
{
	char p[4400], source[256];
	snprintf(source, sizeof source, "family:%s?seed=%llu&sample=%llu", pc_family_name(f),
	         (unsigned long long)seed, (unsigned long long)s->index);
	const pc_sim_info *in = &s->info;
	pc_recording_desc desc = {source,       in->format,       NULL,
	                          in->width,    in->height,       in->offset_x,
	                          in->offset_y, in->sensor_width, in->sensor_height,
	                          true,         in->mosaic,       PC_STORE_PNG};
	pc_recording *rec = NULL;
	int rc = pc_recording_create(&rec, tmp, &desc, false);
	for (unsigned k = 0; k < s->n_frames && !rc; k++) {
		pc_frame fr = {s->frames[k], s->frame_meta[k], in->mosaic};
		rc = pc_recording_add(rec, &fr);
	}
	const char *truth_file = s->truth_stokes ? "truth_stokes.npy" : NULL;
	if (!rc && truth_file) {
		snprintf(p, sizeof p, "%s/%s", tmp, truth_file);
		rc = pc_truth_write(p, in, s->truth_stokes, false,
		                    s->truth == PC_TRUTH_F16 ? PC_DT_F16 : PC_DT_F32);
	}
	if (!rc) {
		snprintf(p, sizeof p, "%s/scene.json", tmp);
		size_t n = strlen(s->scene_json);
		char *t = malloc(n + 2);
		if (!t)
			rc = pc_error(PC_ENOMEM, "scene");
		else {
			memcpy(t, s->scene_json, n);
			t[n] = '\n';
			rc = pc_write_file_atomic(p, t, n + 1);
			free(t);
		}
	}
	char *extra = NULL;
	if (!rc)
		rc = sample_extra(f, s, seed, truth_file, &extra);
	if (!rc)
		rc = pc_recording_set_json(rec, "extra", extra);
	free(extra);
	if (!rc)
		rc = pc_recording_finish(rec, NULL);
	pc_recording_free(rec);
	return rc;
}

/* ---- run ---- */

int pc_dataset_shard_from_env(uint32_t shards_hint, uint32_t *shard, uint32_t *shards,
                              const char **scheduler)
{
	const char *id = getenv("SLURM_ARRAY_TASK_ID"), *cnt = getenv("SLURM_ARRAY_TASK_COUNT");
	const char *mn = getenv("SLURM_ARRAY_TASK_MIN");
	const char *kidx = getenv("JOB_COMPLETION_INDEX"), *kcnt = getenv("POLARCAM_SHARDS");
	unsigned long long a, b, c = 0;
	char tail;
	if (id && *id) {
		if (sscanf(id, "%llu%c", &a, &tail) != 1)
			return pc_error(PC_EINVAL, "SLURM_ARRAY_TASK_ID='%s': expected an integer",
			                id);
		if (!cnt || sscanf(cnt, "%llu%c", &b, &tail) != 1 || b < 1 || b > UINT32_MAX)
			return pc_error(PC_EINVAL,
			                "SLURM_ARRAY_TASK_COUNT='%s': expected a positive "
			                "integer (an array job sets it with the task id)",
			                cnt ? cnt : "");
		if (mn && *mn && sscanf(mn, "%llu%c", &c, &tail) != 1)
			return pc_error(PC_EINVAL, "SLURM_ARRAY_TASK_MIN='%s': expected an integer",
			                mn);
		if (a < c || a - c >= b)
			return pc_error(PC_EINVAL,
			                "SLURM_ARRAY_TASK_ID=%llu outside the array of %llu tasks "
			                "from %llu (sharding needs the ids MIN..MIN+COUNT-1, "
			                "e.g. --array=0-%llu)",
			                a, b, c, b - 1);
		*shard = (uint32_t)(a - c);
		*shards = (uint32_t)b;
		*scheduler = "slurm";
		return 1;
	}
	if (kidx && *kidx) {
		if (sscanf(kidx, "%llu%c", &a, &tail) != 1)
			return pc_error(PC_EINVAL, "JOB_COMPLETION_INDEX='%s': expected an integer",
			                kidx);
		b = shards_hint;
		if (!b &&
		    (!kcnt || sscanf(kcnt, "%llu%c", &b, &tail) != 1 || b < 1 || b > UINT32_MAX))
			return pc_error(PC_EINVAL,
			                "JOB_COMPLETION_INDEX=%llu needs the number of shards: "
			                "--shards M or POLARCAM_SHARDS (the Job's completions)",
			                a);
		if (a >= b)
			return pc_error(PC_EINVAL, "JOB_COMPLETION_INDEX=%llu outside %llu shards",
			                a, b);
		*shard = (uint32_t)a;
		*shards = (uint32_t)b;
		*scheduler = "kubernetes";
		return 1;
	}
	return 0;
}

/* Ensures dataset.json, the directories and the meshes. */
static int prepare_dir(const pc_dataset_options *o, const pc_family *f)
{
	char p[4096];
	int rc = pc_mkdir_p(o->dir);
	const char *sub[] = {"samples", "manifests", "meshes"};
	for (int i = 0; i < 3 && !rc; i++) {
		snprintf(p, sizeof p, "%s/%s", o->dir, sub[i]);
		rc = pc_mkdir_p(p);
	}
	if (rc)
		return rc;
	char *want = dataset_text(f, o->seed, o->count), *have = NULL;
	if (!want)
		return pc_error(PC_ENOMEM, "dataset.json");
	snprintf(p, sizeof p, "%s/dataset.json", o->dir);
	rc = read_text(p, &have, 64u << 20);
	if (rc == PC_ENOENT)
		rc = pc_write_file_atomic(p, want, strlen(want));
	else if (!rc && strcmp(have, want))
		rc = pc_error(PC_EBUSY,
		              "%s holds another dataset (its dataset.json differs in the "
		              "family spec, the seed or the count): use another directory",
		              o->dir);
	free(want);
	free(have);
	for (unsigned i = 0; !rc && i < pc_family_mesh_count(f); i++) {
		const char *src, *name;
		pc_family_mesh(f, i, &src, &name);
		char dst[4400], h1[65], h2[65];
		snprintf(dst, sizeof dst, "%s/meshes/%s", o->dir, name);
		if (access(dst, F_OK) == 0) {
			rc = pc_sha256_file(src, h1, NULL);
			if (!rc)
				rc = pc_sha256_file(dst, h2, NULL);
			if (!rc && strcmp(h1, h2))
				rc = pc_error(PC_EBUSY, "%s differs from the spec's %s", dst, src);
		} else {
			rc = copy_file_atomic(src, dst);
		}
	}
	return rc;
}

static void host_name(char *buf, size_t n)
{
	if (gethostname(buf, n) != 0 || !*buf)
		snprintf(buf, n, "host");
	buf[n - 1] = 0;
	for (char *c = buf; *c; c++)
		if (*c == '/' || *c == '.')
			*c = '_';
}

/* Removes this shard's temporary sample directories left by killed runs: those of this host
 * whose process is gone, and any older than an hour (another host's). A live run of the same
 * shard keeps its own. */
static void remove_stale(const pc_dataset_options *o)
{
	char p[4096], host[256];
	host_name(host, sizeof host);
	snprintf(p, sizeof p, "%s/samples", o->dir);
	DIR *d = opendir(p);
	if (!d)
		return;
	struct dirent *e;
	while ((e = readdir(d))) {
		unsigned long long i;
		if (e->d_name[0] != '.' || sscanf(e->d_name, ".%8llu.tmp.", &i) != 1)
			continue;
		if (i % o->shards != o->shard)
			continue;
		char q[4400];
		snprintf(q, sizeof q, "%s/%s", p, e->d_name);
		const char *tail = e->d_name + 14; /* after ".NNNNNNNN.tmp." */
		size_t hl = strlen(host);
		bool mine = strlen(e->d_name) > 14 && !strncmp(tail, host, hl) && tail[hl] == '.';
		long pid = mine ? strtol(tail + hl + 1, NULL, 10) : 0;
		struct stat st;
		bool old = stat(q, &st) == 0 && time(NULL) - st.st_mtime > 3600;
		if ((mine && pid > 0 && kill((pid_t)pid, 0) != 0 && errno == ESRCH) || old)
			rm_rf(q);
	}
	closedir(d);
}

int pc_dataset_run(const pc_dataset_options *o, pc_dataset_result *r)
{
	memset(r, 0, sizeof *r);
	r->min_median_dn = INFINITY;
	if (!o->spec || !o->dir)
		return pc_error(PC_EINVAL, "dataset: a spec and a directory are required");
	if (o->count < 1 || o->count > MAX_COUNT)
		return pc_error(PC_EINVAL, "dataset: count %llu: expected 1..%llu",
		                (unsigned long long)o->count, MAX_COUNT);
	if (o->seed > (uint64_t)INT64_MAX)
		return pc_error(PC_EINVAL, "dataset: seed %llu: expected 0..2^63-1 (JSON integers)",
		                (unsigned long long)o->seed);
	if (o->shards < 1 || o->shard >= o->shards)
		return pc_error(PC_EINVAL, "dataset: shard %u of %u: expected 0 <= I < M", o->shard,
		                o->shards);
	pc_family *f = NULL;
	int rc = pc_family_load(o->spec, &f);
	if (!rc && (o->width || o->height))
		rc = pc_family_set_resolution(f, o->width, o->height);
	if (!rc)
		rc = prepare_dir(o, f);
	char mpath[4096];
	snprintf(mpath, sizeof mpath, "%s/manifests/shard-%u-of-%u.jsonl", o->dir, o->shard,
	         o->shards);
	char **lines = NULL;
	if (!rc && !(lines = calloc(o->count, sizeof *lines)))
		rc = pc_error(PC_ENOMEM, "manifest of %llu samples", (unsigned long long)o->count);
	if (!rc)
		rc = read_manifest(mpath, o->count, lines, NULL);
	if (!rc) {
		/* a partial last line (killed while appending) goes now */
		rc = write_manifest(mpath, lines, o->count);
		remove_stale(o);
	}
	char host[256];
	host_name(host, sizeof host);
	r->total = o->shard < o->count ? (o->count - 1 - o->shard) / o->shards + 1 : 0;
	uint64_t done = 0;
	for (uint64_t i = o->shard; !rc && i < o->count; i += o->shards) {
		char rel[64], final[4096], tmp[4200];
		sample_rel(i, rel, sizeof rel);
		snprintf(final, sizeof final, "%s/%s", o->dir, rel);
		if (is_dir(final)) {
			if (!lines[i]) {
				/* complete (renamed into place) but killed before its manifest line
				 */
				rc = manifest_line(o->dir, i, &lines[i], NULL);
				if (!rc)
					rc = append_line(mpath, lines[i]);
				r->repaired++;
			}
			r->skipped++;
		} else {
			if (o->stop_after && r->made >= o->stop_after)
				break;
			double t0 = now_s();
			pc_family_sample s;
			rc = pc_family_render(f, o->seed, i, o->threads, &s);
			double t1 = now_s();
			r->render_s += t1 - t0;
			if (!rc) {
				snprintf(tmp, sizeof tmp, "%s/samples/.%08llu.tmp.%s.%ld", o->dir,
				         (unsigned long long)i, host, (long)getpid());
				rm_rf(tmp);
				if (mkdir(tmp, 0755))
					rc = pc_error(PC_EIO, "%s: %s", tmp, strerror(errno));
				if (!rc)
					rc = write_sample_files(f, &s, o->seed, tmp);
				if (!rc && rename(tmp, final)) {
					/* another run of this shard (a requeued task whose first
					 * run is still alive) put the same sample in place first:
					 * the same bytes */
					if ((errno == ENOTEMPTY || errno == EEXIST) &&
					    is_dir(final))
						rm_rf(tmp);
					else
						rc = pc_error(PC_EIO, "%s -> %s: %s", tmp, final,
						              strerror(errno));
				}
				if (rc)
					rm_rf(tmp);
				else {
					char sd[4200];
					snprintf(sd, sizeof sd, "%s/samples", o->dir);
					fsync_dir(sd);
				}
				if (!rc && s.saturated_fraction >= r->worst_saturated) {
					r->worst_saturated = s.saturated_fraction;
					r->worst_index = i;
				}
				if (!rc && s.median_dn < r->min_median_dn)
					r->min_median_dn = s.median_dn;
				pc_family_sample_free(&s);
			}
			uint64_t b = 0;
			if (!rc)
				rc = manifest_line(o->dir, i, &lines[i], &b);
			if (!rc)
				rc = append_line(mpath, lines[i]);
			r->bytes += b;
			r->write_s += now_s() - t1;
			if (!rc)
				r->made++;
		}
		done++;
		if (!rc && pc_progress_report(&o->progress, "samples", done, r->total))
			rc = pc_error(PC_ECANCELED,
			              "dataset: stopped after %llu of %llu samples of shard %u/%u",
			              (unsigned long long)done, (unsigned long long)r->total,
			              o->shard, o->shards);
	}
	if (!rc)
		rc = write_manifest(mpath, lines, o->count); /* sorted, whole lines */
	for (uint64_t i = 0; lines && i < o->count; i++)
		free(lines[i]);
	free(lines);
	pc_family_free(f);
	return rc;
}

/* ---- merge and verify ---- */

/* Every shard manifest's lines into lines[]. */
static int read_all_manifests(const char *dir, uint64_t count, char **lines)
{
	char p[4096];
	snprintf(p, sizeof p, "%s/manifests", dir);
	char **names;
	size_t n;
	int rc = list_files(p, &names, &n);
	if (rc == PC_EIO)
		return pc_error(PC_ENOENT, "%s/manifests: missing (no shard has run)", dir);
	for (size_t k = 0; k < n && !rc; k++) {
		size_t len = strlen(names[k]);
		if (len < 6 || strcmp(names[k] + len - 6, ".jsonl"))
			continue;
		char q[4400];
		snprintf(q, sizeof q, "%s/%s", p, names[k]);
		rc = read_manifest(q, count, lines, NULL);
	}
	free_list(names, n);
	return rc;
}

int pc_dataset_merge(const char *dir, uint64_t *count_out)
{
	uint64_t count;
	int rc = read_dataset(dir, &count, NULL);
	if (rc)
		return rc;
	char **lines = calloc(count, sizeof *lines);
	if (!lines)
		return pc_error(PC_ENOMEM, "manifest of %llu samples", (unsigned long long)count);
	rc = read_all_manifests(dir, count, lines);
	uint64_t missing = 0, first = 0;
	for (uint64_t i = 0; i < count; i++)
		if (!lines[i] && !missing++)
			first = i;
	if (!rc && missing)
		rc = pc_error(PC_EINVAL,
		              "%s: %llu of %llu samples have no manifest line (the first: "
		              "%llu): run the missing shards first; nothing written",
		              dir, (unsigned long long)missing, (unsigned long long)count,
		              (unsigned long long)first);
	if (!rc) {
		char p[4096];
		snprintf(p, sizeof p, "%s/manifest.jsonl", dir);
		rc = write_manifest(p, lines, count);
	}
	for (uint64_t i = 0; i < count; i++)
		free(lines[i]);
	free(lines);
	if (!rc && count_out)
		*count_out = count;
	return rc;
}

static void bad(pc_dataset_verify_result *r, uint64_t i, bool corrupt, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void bad(pc_dataset_verify_result *r, uint64_t i, bool corrupt, const char *fmt, ...)
{
	if (corrupt)
		r->corrupt++;
	else
		r->missing++;
	if (r->corrupt + r->missing == 1) {
		r->first_bad = i;
		va_list ap;
		va_start(ap, fmt);
		vsnprintf(r->first_problem, sizeof r->first_problem, fmt, ap);
		va_end(ap);
	}
}

int pc_dataset_verify(const char *dir, pc_dataset_verify_result *r)
{
	memset(r, 0, sizeof *r);
	uint64_t count;
	int rc = read_dataset(dir, &count, NULL);
	if (rc)
		return rc;
	r->count = count;
	char **lines = calloc(count, sizeof *lines);
	if (!lines)
		return pc_error(PC_ENOMEM, "manifest of %llu samples", (unsigned long long)count);
	char p[4096];
	snprintf(p, sizeof p, "%s/manifest.jsonl", dir);
	if (access(p, F_OK) == 0)
		rc = read_manifest(p, count, lines, NULL);
	else
		rc = read_all_manifests(dir, count, lines);
	for (uint64_t i = 0; !rc && i < count; i++) {
		char rel[64], sdir[4096];
		sample_rel(i, rel, sizeof rel);
		snprintf(sdir, sizeof sdir, "%s/%s", dir, rel);
		if (!lines[i]) {
			bad(r, i, false, "sample %llu: no manifest line", (unsigned long long)i);
			continue;
		}
		if (!is_dir(sdir)) {
			bad(r, i, false, "%s: missing", rel);
			continue;
		}
		json_t *j = json_loads(lines[i], 0, NULL);
		json_t *files = json_object_get(j, "files");
		char **names;
		size_t n;
		bool ok = true;
		if (list_files(sdir, &names, &n)) {
			bad(r, i, true, "%s: cannot be listed", rel);
			json_decref(j);
			continue;
		}
		if (n != json_object_size(files)) {
			ok = false;
			bad(r, i, true, "%s: %zu files, the manifest lists %zu", rel, n,
			    json_object_size(files));
		}
		for (size_t k = 0; k < n && ok; k++) {
			json_t *want = json_object_get(files, names[k]);
			char q[4400], hex[65];
			uint64_t b;
			snprintf(q, sizeof q, "%s/%s", sdir, names[k]);
			if (!want) {
				ok = false;
				bad(r, i, true, "%s/%s: not in the manifest", rel, names[k]);
			} else if (pc_sha256_file(q, hex, &b)) {
				ok = false;
				bad(r, i, true, "%s/%s: unreadable", rel, names[k]);
			} else {
				r->bytes += b;
				if ((json_int_t)b !=
				        json_integer_value(json_object_get(want, "bytes")) ||
				    !json_is_string(json_object_get(want, "sha256")) ||
				    strcmp(hex,
				           json_string_value(json_object_get(want, "sha256")))) {
					ok = false;
					bad(r, i, true,
					    "%s/%s: size or SHA-256 differs from the manifest", rel,
					    names[k]);
				}
			}
		}
		free_list(names, n);
		json_decref(j);
		if (ok)
			r->ok++;
	}
	for (uint64_t i = 0; i < count; i++)
		free(lines[i]);
	free(lines);
	return rc;
}
