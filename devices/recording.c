/* Recordings: raw_NNNNNN.png (.npy, .raw) + meta.json (layout in polarcam/recording.h). */
#include "polarcam/recording.h"

#include <dirent.h>
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "polarcam/error.h"
#include "polarcam/limits.h"
#include "polarcam/io.h"
#include "json.h"

#define PC_RECORDING_VERSION 1
#define PC_META_REWRITE_S    0.25

struct pc_recording {
	char *dir;
	pc_recording_desc desc;
	char *source, *device_format;
	pc_pixfmt storage;
	pc_recording_frame *frames;
	size_t n, cap;
	bool writing, complete;
	char *error;
	json_t *stats, *extra;
	double last_meta_s;
	uint16_t *row_tmp; /* unpacking packed formats for writing */
	size_t row_tmp_size;
};

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

pc_pixfmt pc_recording_storage_format(pc_pixfmt fmt)
{
	const pc_format_info *fi = pc_format_info_get(fmt);
	if (!fi || fi->is_float)
		return PC_FMT_INVALID;
	if (fi->bits <= 8)
		return PC_FMT_MONO8;
	if (fi->bits <= 10)
		return PC_FMT_MONO10;
	if (fi->bits <= 12)
		return PC_FMT_MONO12;
	if (fi->bits <= 14)
		return PC_FMT_MONO14;
	return PC_FMT_MONO16;
}

static char *path_join(const char *dir, const char *name)
{
	size_t n = strlen(dir) + strlen(name) + 2;
	char *p = malloc(n);
	if (p)
		snprintf(p, n, "%s/%s", dir, name);
	return p;
}

static bool file_exists(const char *dir, const char *name)
{
	char *p = path_join(dir, name);
	struct stat st;
	bool e = p && stat(p, &st) == 0;
	free(p);
	return e;
}

static const char *const store_ext[] = {"png", "npy", "raw"};

const char *pc_recording_store_name(pc_recording_store s)
{
	return (unsigned)s < 3 ? store_ext[s] : NULL;
}

int pc_recording_store_from_name(const char *name, pc_recording_store *out)
{
	for (unsigned i = 0; name && i < 3; i++)
		if (!strcmp(name, store_ext[i])) {
			*out = (pc_recording_store)i;
			return 0;
		}
	return pc_error(PC_EINVAL, "store '%s': expected png, npy or raw", name ? name : "");
}

/* The store of a frame file name "raw_NNNNNN.EXT", or -1. */
static int store_of_file(const char *name)
{
	unsigned num;
	char ext[4];
	int used = 0;
	if (strlen(name) != 14 || strspn(name + 4, "0123456789") != 6 ||
	    sscanf(name, "raw_%6u.%3[a-z]%n", &num, ext, &used) != 2 || used != 14)
		return -1;
	for (int i = 0; i < 3; i++)
		if (!strcmp(ext, store_ext[i]))
			return i;
	return -1;
}

static char *dup_or_null(const char *s)
{
	return s ? strdup(s) : NULL;
}

void pc_recording_free(pc_recording *r)
{
	if (!r)
		return;
	free(r->dir);
	free(r->source);
	free(r->device_format);
	free(r->frames);
	free(r->error);
	free(r->row_tmp);
	json_decref(r->stats);
	json_decref(r->extra);
	free(r);
}

static int check_desc(const pc_recording_desc *d)
{
	const pc_format_info *fi = pc_format_info_get(d->format);
	if (!fi || fi->is_float)
		return pc_error(PC_EINVAL,
		                "recording: pixel format %d: expected an integer raw format",
		                (int)d->format);
	size_t row;
	int rc = pc_format_row_bytes(d->format, d->width, &row);
	if (rc)
		return rc;
	if (d->height == 0)
		return pc_error(PC_EINVAL, "recording: height 0");
	if (d->mosaic.period != 0 && d->mosaic.period != 2 && d->mosaic.period != 4)
		return pc_error(PC_EINVAL, "recording: mosaic period %u: expected 2 or 4",
		                d->mosaic.period);
	if (!pc_recording_store_name(d->store))
		return pc_error(PC_EINVAL, "recording: store %d: expected png, npy or raw",
		                (int)d->store);
	return 0;
}

int pc_recording_create(pc_recording **out, const char *dir, const pc_recording_desc *desc,
                        bool overwrite)
{
	if (!out || !dir || !*dir || !desc)
		return pc_error(PC_EINVAL, "recording: missing argument");
	*out = NULL;
	int rc = check_desc(desc);
	if (rc)
		return rc;
	rc = pc_mkdir_p(dir);
	if (rc)
		return rc;
	if (!overwrite &&
	    (file_exists(dir, "meta.json") || file_exists(dir, "raw_000000.png") ||
	     file_exists(dir, "raw_000000.npy") || file_exists(dir, "raw_000000.raw")))
		return pc_error(PC_EBUSY,
		                "%s: already holds a recording (meta.json / raw_000000.*); "
		                "choose another directory or overwrite",
		                dir);
	/* what writers killed before their rename left (never listed, never read) */
	if ((rc = pc_atomic_sweep(dir, NULL)))
		return rc;
	pc_recording *r = calloc(1, sizeof *r);
	if (!r)
		return pc_error(PC_ENOMEM, "recording");
	r->dir = strdup(dir);
	r->desc = *desc;
	r->source = dup_or_null(desc->source);
	r->device_format = dup_or_null(desc->device_format);
	r->desc.source = r->source;
	r->desc.device_format = r->device_format;
	r->storage = pc_recording_storage_format(desc->format);
	r->writing = true;
	r->last_meta_s = -1e9;
	if (!r->dir || (desc->source && !r->source) || (desc->device_format && !r->device_format)) {
		pc_recording_free(r);
		return pc_error(PC_ENOMEM, "recording");
	}
	*out = r;
	return 0;
}

static json_t *frame_status_json(uint32_t st)
{
	json_t *a = json_array();
	if (st & PC_FRAME_INCOMPLETE)
		json_array_append_new(a, json_string("incomplete"));
	if (st & PC_FRAME_CORRUPT)
		json_array_append_new(a, json_string("corrupt"));
	if (st & PC_FRAME_SIMULATED)
		json_array_append_new(a, json_string("simulated"));
	return a;
}

static int write_meta(pc_recording *r)
{
	char mosaic[32] = "";
	if (r->desc.mosaic.period)
		pc_mosaic_format(&r->desc.mosaic, mosaic, sizeof mosaic);
	const pc_format_info *si = pc_format_info_get(r->storage);
	json_t *m = json_object();
	json_object_set_new(m, "polarcam_recording", json_integer(PC_RECORDING_VERSION));
	json_object_set_new(m, "source", r->source ? json_string(r->source) : json_null());
	json_object_set_new(m, "format", json_string(si->name));
	json_object_set_new(m, "bits", json_integer(si->bits));
	json_object_set_new(m, "device_format",
	                    json_string(r->device_format
	                                    ? r->device_format
	                                    : pc_format_info_get(r->desc.format)->name));
	json_object_set_new(m, "width", json_integer(r->desc.width));
	json_object_set_new(m, "height", json_integer(r->desc.height));
	json_object_set_new(m, "offset_x", json_integer(r->desc.offset_x));
	json_object_set_new(m, "offset_y", json_integer(r->desc.offset_y));
	json_object_set_new(m, "sensor_width", json_integer(r->desc.sensor_width));
	json_object_set_new(m, "sensor_height", json_integer(r->desc.sensor_height));
	json_object_set_new(m, "polarized", json_boolean(r->desc.polarized));
	json_object_set_new(m, "mosaic", mosaic[0] ? json_string(mosaic) : json_null());
	json_object_set_new(m, "store", json_string(store_ext[r->desc.store]));
	json_t *fr = json_array();
	for (size_t i = 0; i < r->n; i++) {
		const pc_recording_frame *f = &r->frames[i];
		json_t *o = json_object();
		json_object_set_new(o, "file", json_string(f->file));
		json_object_set_new(o, "sequence", json_integer((json_int_t)f->sequence));
		json_object_set_new(o, "timestamp_ns", json_integer((json_int_t)f->timestamp_ns));
		/* null: the source did not say (NAN) */
		json_object_set_new(o, "exposure_us", pc_json_real(f->exposure_us));
		json_object_set_new(o, "gain_db", pc_json_real(f->gain_db));
		json_object_set_new(o, "status", frame_status_json(f->status));
		json_array_append_new(fr, o);
	}
	json_object_set_new(m, "frames", fr);
	json_object_set_new(m, "complete", json_boolean(r->complete));
	json_object_set_new(m, "error", r->error ? json_string(r->error) : json_null());
	if (r->stats)
		json_object_set(m, "stats", r->stats);
	if (r->extra)
		json_object_set(m, "extra", r->extra);
	char *text = json_dumps(m, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	json_decref(m);
	if (!text)
		return pc_error(PC_ENOMEM, "%s/meta.json", r->dir);
	char *path = path_join(r->dir, "meta.json");
	int rc = path ? pc_write_file_atomic(path, text, strlen(text)) : PC_ENOMEM;
	free(path);
	free(text);
	return rc;
}

/* A frame in the storage format without padding: the view itself when it is already that,
 * else unpacked or copied into row_tmp. */
static int storage_view(pc_recording *r, const pc_view *v, pc_view *out)
{
	const pc_format_info *fi = pc_format_info_get(v->format);
	const pc_format_info *si = pc_format_info_get(r->storage);
	const size_t bpp = si->group_bytes, row = (size_t)v->width * bpp;
	if (fi->packing == PC_PACK_NONE && fi->group_bytes == bpp && v->stride == row) {
		*out = (pc_view){v->data, v->width, v->height, row, r->storage};
		return 0;
	}
	size_t need = (size_t)v->width * v->height;
	if (r->row_tmp_size < need) {
		free(r->row_tmp);
		r->row_tmp = malloc(need * sizeof *r->row_tmp);
		r->row_tmp_size = r->row_tmp ? need : 0;
	}
	if (!r->row_tmp)
		return pc_error(PC_ENOMEM, "unpacking a %ux%u frame", v->width, v->height);
	*out = (pc_view){r->row_tmp, v->width, v->height, row, r->storage};
	if (fi->packing == PC_PACK_NONE && fi->group_bytes == bpp) {
		for (uint32_t y = 0; y < v->height; y++)
			memcpy((uint8_t *)r->row_tmp + y * row, PC_ROW(v, const uint8_t, y), row);
		return 0;
	}
	return pc_view_to_u16(v, r->row_tmp, row);
}

static int write_frame(pc_recording *r, const char *path, const pc_view *v)
{
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (r->desc.store == PC_STORE_PNG && fi->packing == PC_PACK_NONE)
		return pc_png_write(path, v); /* any stride */
	pc_view u;
	int rc = storage_view(r, v, &u);
	if (rc)
		return rc;
	switch (r->desc.store) {
	case PC_STORE_NPY: {
		size_t shape[2] = {u.height, u.width};
		return pc_npy_write(path, u.data, u.format == PC_FMT_MONO8 ? PC_DT_U8 : PC_DT_U16,
		                    2, shape);
	}
	case PC_STORE_RAW:
		return pc_raw_write(path, &u);
	default:
		return pc_png_write(path, &u);
	}
}

int pc_recording_add(pc_recording *r, const pc_frame *f)
{
	if (!r || !f)
		return pc_error(PC_EINVAL, "recording: missing argument");
	if (!r->writing)
		return pc_error(PC_ESTATE, "%s: recording is finished or read-only", r->dir);
	const pc_view *v = &f->view;
	int rc = pc_view_check(v);
	if (rc)
		return rc;
	if (v->format != r->desc.format || v->width != r->desc.width || v->height != r->desc.height)
		return pc_error(
		    PC_EINVAL, "%s: frame %s %ux%u does not match the recording's %s %ux%u", r->dir,
		    pc_format_info_get(v->format)->name, v->width, v->height,
		    pc_format_info_get(r->desc.format)->name, r->desc.width, r->desc.height);
	if (r->n && f->meta.sequence <= r->frames[r->n - 1].sequence)
		return pc_error(PC_EINVAL, "%s: frame sequence %llu after %llu: must increase",
		                r->dir, (unsigned long long)f->meta.sequence,
		                (unsigned long long)r->frames[r->n - 1].sequence);
	if (r->n >= 999999)
		return pc_error(PC_EOVERFLOW, "%s: a recording holds at most 999999 frames",
		                r->dir);
	if (r->n == r->cap) {
		size_t cap = r->cap ? 2 * r->cap : 64;
		pc_recording_frame *nf = realloc(r->frames, cap * sizeof *nf);
		if (!nf)
			return pc_error(PC_ENOMEM, "recording frame list");
		r->frames = nf;
		r->cap = cap;
	}
	pc_recording_frame *rf = &r->frames[r->n];
	memset(rf, 0, sizeof *rf);
	snprintf(rf->file, sizeof rf->file, "raw_%06zu.%s", r->n, store_ext[r->desc.store]);
	rf->sequence = f->meta.sequence;
	rf->timestamp_ns = f->meta.timestamp_ns;
	rf->exposure_us = f->meta.exposure_us;
	rf->gain_db = f->meta.gain_db;
	rf->status = f->meta.status;

	char *path = path_join(r->dir, rf->file);
	if (!path)
		return pc_error(PC_ENOMEM, "recording");
	rc = write_frame(r, path, v);
	free(path);
	if (rc)
		return rc;
	r->n++;
	double t = now_s();
	if (t - r->last_meta_s >= PC_META_REWRITE_S) {
		r->last_meta_s = t;
		rc = write_meta(r);
	}
	return rc;
}

int pc_recording_set_json(pc_recording *r, const char *key, const char *text)
{
	if (!r || !key)
		return pc_error(PC_EINVAL, "recording: missing argument");
	json_t **slot = !strcmp(key, "stats")   ? &r->stats
	                : !strcmp(key, "extra") ? &r->extra
	                                        : NULL;
	if (!slot)
		return pc_error(PC_EINVAL, "recording: key '%s': expected stats or extra", key);
	json_t *j = NULL;
	if (text) {
		json_error_t e;
		j = json_loads(text, 0, &e);
		if (!j || !json_is_object(j)) {
			json_decref(j);
			return pc_error(PC_EINVAL, "recording %s: not a JSON object (%s)", key,
			                j ? "not an object" : e.text);
		}
	}
	json_decref(*slot);
	*slot = j;
	return 0;
}

int pc_recording_finish(pc_recording *r, const char *error)
{
	if (!r)
		return pc_error(PC_EINVAL, "recording: missing argument");
	if (!r->writing)
		return pc_error(PC_ESTATE, "%s: recording is not being written", r->dir);
	free(r->error);
	r->error = NULL;
	if (error && !(r->error = strdup(error)))
		return pc_error(PC_ENOMEM, "recording");
	r->complete = error == NULL;
	int rc = write_meta(r);
	r->writing = false;
	return rc;
}

/* ---- reading ---- */

const pc_recording_desc *pc_recording_get_desc(const pc_recording *r)
{
	return &r->desc;
}

size_t pc_recording_count(const pc_recording *r)
{
	return r->n;
}

const pc_recording_frame *pc_recording_get_frame(const pc_recording *r, size_t i)
{
	return i < r->n ? &r->frames[i] : NULL;
}

bool pc_recording_is_complete(const pc_recording *r)
{
	return r->complete;
}

const char *pc_recording_dir(const pc_recording *r)
{
	return r->dir;
}

double pc_recording_black_level(const pc_recording *r)
{
	json_t *off = json_object_get(json_object_get(r->extra, "sensor"), "offset_dn");
	return json_is_number(off) ? json_number_value(off) : 0;
}

int pc_recording_frame_mosaic(const char *path, pc_mosaic *m)
{
	struct stat sb;
	if (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode)) { /* a recording itself */
		pc_recording *r = NULL;
		if (pc_recording_open(&r, path) != 0) {
			pc_error_clear();
			return 0;
		}
		const pc_recording_desc *d = pc_recording_get_desc(r);
		int ok = d->polarized;
		if (ok)
			*m = d->mosaic;
		pc_recording_free(r);
		return ok;
	}
	pc_recording_frame_meta fm;
	int found = pc_recording_frame_info(path, &fm);
	if (found < 0)
		return found;
	if (found && fm.polarized)
		*m = fm.mosaic;
	return found && fm.polarized;
}

int pc_recording_frame_info(const char *path, pc_recording_frame_meta *fm)
{
	const char *slash = strrchr(path, '/');
	const char *file = slash ? slash + 1 : path;
	char dir[4096];
	if (!slash)
		snprintf(dir, sizeof dir, ".");
	else if ((size_t)snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path),
	                          path) >= sizeof dir)
		return 0;
	if (!file_exists(dir, "meta.json"))
		return 0;
	pc_recording *r = NULL;
	int rc = pc_recording_open(&r, dir);
	if (rc) {
		/* a frame named like a recording's beside a meta.json that does not open:
		 * processing a colour recording's frame as monochrome would be silently wrong */
		unsigned num;
		char tail;
		if (strlen(file) == 14 && sscanf(file, "raw_%6u.pn%c", &num, &tail) == 2 &&
		    tail == 'g')
			return pc_error_prefix(rc,
			                       "%s is a recording's frame, but its description is "
			                       "unreadable (give --layout to process it anyway): ",
			                       path);
		pc_error_clear(); /* some other meta.json: not a recording */
		return 0;
	}
	int found = 0;
	const pc_recording_desc *d = pc_recording_get_desc(r);
	for (size_t i = 0; !found && i < pc_recording_count(r); i++)
		found = !strcmp(pc_recording_get_frame(r, i)->file, file);
	if (found) {
		memset(fm, 0, sizeof *fm);
		fm->mosaic = d->mosaic;
		fm->polarized = d->polarized;
		fm->black_level = pc_recording_black_level(r);
		fm->bits = pc_format_info_get(d->format)->bits;
		fm->offset_x = d->offset_x;
		fm->offset_y = d->offset_y;
		fm->sensor_width = d->sensor_width;
		fm->sensor_height = d->sensor_height;
	}
	pc_recording_free(r);
	return found;
}

/* An optional frame number: absent or null is unknown (NAN). */
static int opt_num(const pc_json_src *js, json_t *o, const char *where, const char *key,
                   double *out)
{
	*out = NAN;
	json_t *v = json_object_get(o, key);
	if (!v || json_is_null(v))
		return 0;
	return pc_json_get_num(js, o, where, key, PC_JSON_OPTIONAL, -INFINITY, false, INFINITY,
	                       out);
}

static int parse_frames(pc_recording *r, const pc_json_src *js, json_t *arr)
{
	if (!json_is_array(arr))
		return pc_json_error(js, "frames", "expected an array, got %s", pc_json_kind(arr));
	size_t n = json_array_size(arr);
	if (n > 999999)
		return pc_json_error(js, "frames", "%zu frames: at most 999999", n);
	int lrc = pc_limit_check(PC_LIMIT_FRAMES, n, js->file);
	if (lrc)
		return lrc;
	r->frames = calloc(n ? n : 1, sizeof *r->frames);
	if (!r->frames)
		return pc_error(PC_ENOMEM, "%s", js->file);
	r->cap = n;
	for (size_t i = 0; i < n; i++) {
		json_t *o = json_array_get(arr, i);
		char where[64], p[96];
		pc_json_path_index(where, sizeof where, "frames", i);
		int rc = pc_json_need_object(js, o, where);
		if (rc)
			return rc;
		pc_recording_frame *f = &r->frames[i];
		const char *name = NULL;
		pc_json_path(p, sizeof p, where, "file");
		if ((rc = pc_json_get_str(js, o, where, "file", PC_JSON_REQUIRED, &name)))
			return rc;
		if (store_of_file(name) < 0)
			return pc_json_error(js, p, "expected \"raw_NNNNNN.png\" (or .npy, .raw)");
		snprintf(f->file, sizeof f->file, "%s", name);
		if ((rc = pc_json_get_u64(js, o, where, "sequence", PC_JSON_REQUIRED, INT64_MAX,
		                          &f->sequence)) ||
		    (rc = pc_json_get_u64(js, o, where, "timestamp_ns", PC_JSON_REQUIRED, INT64_MAX,
		                          &f->timestamp_ns)) ||
		    (rc = opt_num(js, o, where, "exposure_us", &f->exposure_us)) ||
		    (rc = opt_num(js, o, where, "gain_db", &f->gain_db)))
			return rc;
		json_t *st = json_object_get(o, "status");
		pc_json_path(p, sizeof p, where, "status");
		if (st && !json_is_array(st))
			return pc_json_error(js, p, "expected an array of strings");
		for (size_t k = 0; st && k < json_array_size(st); k++) {
			const char *s = json_string_value(json_array_get(st, k));
			if (s && !strcmp(s, "incomplete"))
				f->status |= PC_FRAME_INCOMPLETE;
			else if (s && !strcmp(s, "corrupt"))
				f->status |= PC_FRAME_CORRUPT;
			else if (s && !strcmp(s, "simulated"))
				f->status |= PC_FRAME_SIMULATED;
			else {
				char q[128];
				pc_json_path_index(q, sizeof q, p, k);
				return pc_json_error(js, q,
				                     "expected \"incomplete\", \"corrupt\" or "
				                     "\"simulated\"");
			}
		}
		pc_json_path(p, sizeof p, where, "sequence");
		if (i > 0 && f->sequence <= r->frames[i - 1].sequence)
			return pc_json_error(
			    js, p, "= %llu: must be greater than the previous frame's %llu",
			    (unsigned long long)f->sequence,
			    (unsigned long long)r->frames[i - 1].sequence);
		pc_json_path(p, sizeof p, where, "timestamp_ns");
		if (i > 0 && f->timestamp_ns < r->frames[i - 1].timestamp_ns)
			return pc_json_error(js, p, "earlier than the previous frame's");
		r->n = i + 1;
	}
	return 0;
}

static int open_meta(pc_recording *r, const char *path)
{
	json_t *m = NULL;
	int rc = pc_json_load(path, true, &m);
	if (rc)
		return rc;
	const pc_json_src js = {path, PC_EFORMAT};
	uint64_t ver = 0, bits = 0, w = 0, h = 0, ox = 0, oy = 0, sw = 0, sh = 0;
	rc = pc_json_get_u64(&js, m, "", "polarcam_recording", PC_JSON_REQUIRED, 1000, &ver);
	if (!rc && ver != PC_RECORDING_VERSION)
		rc = pc_json_error(&js, "polarcam_recording",
		                   "= %llu: this polarcam reads version %d",
		                   (unsigned long long)ver, PC_RECORDING_VERSION);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "bits", PC_JSON_REQUIRED, 16, &bits);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "width", PC_JSON_REQUIRED, 1u << 20, &w);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "height", PC_JSON_REQUIRED, 1u << 20, &h);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "offset_x", PC_JSON_OPTIONAL, 1u << 20, &ox);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "offset_y", PC_JSON_OPTIONAL, 1u << 20, &oy);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "sensor_width", PC_JSON_OPTIONAL, 1u << 21, &sw);
	if (!rc)
		rc = pc_json_get_u64(&js, m, "", "sensor_height", PC_JSON_OPTIONAL, 1u << 21, &sh);
	if (!rc && (w == 0 || h == 0))
		rc = pc_json_error(&js, w == 0 ? "width" : "height", "= 0: must be > 0");
	const char *fmt = json_string_value(json_object_get(m, "format"));
	pc_pixfmt pf = fmt ? pc_format_from_name(fmt) : PC_FMT_INVALID;
	if (!rc && (pf == PC_FMT_INVALID || pc_recording_storage_format(pf) != pf))
		rc = pc_json_error(&js, "format",
		                   "'%s': expected Mono8, Mono10, Mono12, Mono14 or Mono16",
		                   fmt ? fmt : "(missing)");
	if (!rc && pc_format_info_get(pf)->bits != bits)
		rc = pc_json_error(&js, "bits", "= %llu: does not match format %s",
		                   (unsigned long long)bits, fmt);
	json_t *pol = json_object_get(m, "polarized");
	bool polarized = false;
	if (!rc)
		rc = pc_json_get_bool(&js, m, "", "polarized", PC_JSON_OPTIONAL, &polarized);
	json_t *mos = json_object_get(m, "mosaic");
	pc_mosaic mosaic;
	memset(&mosaic, 0, sizeof mosaic);
	if (!rc && mos && !json_is_null(mos)) {
		const char *t = json_string_value(mos);
		if (!t)
			rc = pc_json_error(&js, "mosaic",
			                   "expected a string such as \"90,45,135,0\", got %s",
			                   pc_json_kind(mos));
		else if ((rc = pc_mosaic_parse(t, &mosaic)))
			rc = pc_error_prefix(PC_EFORMAT, "%s: mosaic: ", path);
	}
	if (!rc && pol && polarized && mosaic.period == 0)
		rc = pc_json_error(&js, "mosaic",
		                   "missing, but 'polarized' is true (a polarized recording states "
		                   "its mosaic, e.g. \"90,45,135,0\")");
	json_t *store = json_object_get(m, "store");
	pc_recording_store sv = PC_STORE_PNG;
	if (!rc && store && pc_recording_store_from_name(json_string_value(store), &sv))
		rc = pc_json_error(&js, "store", "expected \"png\", \"npy\" or \"raw\"");
	const char *src = json_string_value(json_object_get(m, "source"));
	const char *dev = json_string_value(json_object_get(m, "device_format"));
	if (!rc &&
	    ((src && !(r->source = strdup(src))) || (dev && !(r->device_format = strdup(dev)))))
		rc = pc_error(PC_ENOMEM, "%s", path);
	if (!rc)
		rc = parse_frames(r, &js, json_object_get(m, "frames"));
	bool complete = true;
	if (!rc)
		rc = pc_json_get_bool(&js, m, "", "complete", PC_JSON_OPTIONAL, &complete);
	if (!rc) {
		r->complete = complete;
		const char *err = json_string_value(json_object_get(m, "error"));
		if (err)
			r->error = strdup(err);
		r->storage = pf;
		r->desc.format = pf;
		r->desc.source = r->source;
		r->desc.device_format = r->device_format;
		r->desc.width = (uint32_t)w;
		r->desc.height = (uint32_t)h;
		r->desc.offset_x = (uint32_t)ox;
		r->desc.offset_y = (uint32_t)oy;
		r->desc.sensor_width = sw ? (uint32_t)sw : (uint32_t)(w + ox);
		r->desc.sensor_height = sh ? (uint32_t)sh : (uint32_t)(h + oy);
		r->desc.polarized = pol ? polarized : mosaic.period != 0;
		r->desc.mosaic = mosaic;
		r->desc.store = sv;
		r->stats = json_incref(json_object_get(m, "stats"));
		r->extra = json_incref(json_object_get(m, "extra"));
	}
	json_decref(m);
	return rc;
}

/* A directory of raw_NNNNNN.png without meta.json. */
static int open_bare(pc_recording *r, const char *dir)
{
	size_t n = 0;
	for (;; n++) {
		char name[32];
		snprintf(name, sizeof name, "raw_%06zu.png", n);
		if (n > 999999 || !file_exists(dir, name))
			break;
	}
	if (n == 0)
		return pc_error(PC_ENOENT,
		                "%s: no meta.json and no raw_000000.png: not a recording", dir);
	char *p = path_join(dir, "raw_000000.png");
	if (!p)
		return pc_error(PC_ENOMEM, "%s", dir);
	pc_view v;
	unsigned bits = 0;
	int rc = pc_image_read(p, NULL, &v, &bits);
	free(p);
	if (rc)
		return rc;
	uint32_t w = v.width, h = v.height;
	pc_pixfmt vf = v.format;
	pc_view_free(&v);
	if (vf == PC_FMT_FLOAT32 || bits < 1 || bits > 16)
		return pc_error(PC_EFORMAT, "%s/raw_000000.png: expected 8- or 16-bit grey", dir);
	static const pc_pixfmt by_bits[17] = {
	    PC_FMT_INVALID, PC_FMT_MONO8,  PC_FMT_MONO8,  PC_FMT_MONO8,  PC_FMT_MONO8,
	    PC_FMT_MONO8,   PC_FMT_MONO8,  PC_FMT_MONO8,  PC_FMT_MONO8,  PC_FMT_MONO10,
	    PC_FMT_MONO10,  PC_FMT_MONO12, PC_FMT_MONO12, PC_FMT_MONO14, PC_FMT_MONO14,
	    PC_FMT_MONO16,  PC_FMT_MONO16,
	};
	pc_pixfmt pf = vf == PC_FMT_MONO8 ? PC_FMT_MONO8 : by_bits[bits];
	r->frames = calloc(n, sizeof *r->frames);
	if (!r->frames)
		return pc_error(PC_ENOMEM, "%s", dir);
	for (size_t i = 0; i < n; i++) {
		snprintf(r->frames[i].file, sizeof r->frames[i].file, "raw_%06zu.png", i);
		r->frames[i].sequence = i;
	}
	r->n = r->cap = n;
	r->storage = pf;
	r->desc.format = pf;
	r->desc.width = r->desc.sensor_width = w;
	r->desc.height = r->desc.sensor_height = h;
	r->desc.polarized = true;
	r->desc.mosaic = pc_mosaic_imx250mzr();
	r->complete = true;
	return 0;
}

int pc_recording_open(pc_recording **out, const char *dir)
{
	if (!out || !dir || !*dir)
		return pc_error(PC_EINVAL, "recording: missing directory");
	*out = NULL;
	struct stat st;
	if (stat(dir, &st) != 0)
		return pc_error(PC_ENOENT, "%s: %s", dir, strerror(errno));
	if (!S_ISDIR(st.st_mode))
		return pc_error(PC_EINVAL,
		                "%s: not a directory (a recording is a directory of "
		                "raw_NNNNNN.png and meta.json)",
		                dir);
	pc_recording *r = calloc(1, sizeof *r);
	if (!r || !(r->dir = strdup(dir))) {
		free(r);
		return pc_error(PC_ENOMEM, "recording");
	}
	char *meta = path_join(dir, "meta.json");
	int rc;
	if (!meta)
		rc = pc_error(PC_ENOMEM, "recording");
	else if (stat(meta, &st) == 0)
		rc = open_meta(r, meta);
	else
		rc = open_bare(r, dir);
	/* every frame meta.json lists must be there: a reader (capture file:, process) must not
	 * find out after writing the frames before a missing one */
	for (size_t i = 0; !rc && i < r->n; i++)
		if (!file_exists(dir, r->frames[i].file))
			rc = pc_error(PC_ENOENT,
			              "%s/%s: listed in %s/meta.json as frame %zu, missing", dir,
			              r->frames[i].file, dir, i);
	free(meta);
	if (rc) {
		pc_recording_free(r);
		return rc;
	}
	*out = r;
	return 0;
}

int pc_recording_read(const pc_recording *r, size_t i, pc_view *out)
{
	if (!r || !out)
		return pc_error(PC_EINVAL, "recording: missing argument");
	memset(out, 0, sizeof *out);
	if (i >= r->n)
		return pc_error(PC_ERANGE, "%s: frame %zu: the recording has %zu frames", r->dir, i,
		                r->n);
	char *p = path_join(r->dir, r->frames[i].file);
	if (!p)
		return pc_error(PC_ENOMEM, "recording");
	unsigned bits = 0;
	pc_view v;
	int rc = 0;
	const pc_format_info *fi = pc_format_info_get(r->storage);
	if (store_of_file(r->frames[i].file) == PC_STORE_RAW) {
		/* headerless: the geometry is meta.json's, and the file holds exactly that */
		pc_raw_geometry g = {r->desc.width, r->desc.height, r->storage, 0, 0};
		uint64_t want = (uint64_t)r->desc.width * r->desc.height * fi->group_bytes;
		struct stat st;
		if (stat(p, &st) != 0)
			rc = pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", p,
			              strerror(errno));
		else if ((uint64_t)st.st_size != want)
			rc = pc_error(PC_EFORMAT,
			              "%s: %lld bytes, meta.json says %ux%u %s (%llu bytes)", p,
			              (long long)st.st_size, r->desc.width, r->desc.height,
			              fi->name, (unsigned long long)want);
		else
			rc = pc_image_read(p, &g, &v, &bits);
	} else {
		rc = pc_image_read(p, NULL, &v, &bits);
	}
	if (rc) {
		free(p);
		return rc;
	}
	bool is8 = v.format == PC_FMT_MONO8;
	if (v.width != r->desc.width || v.height != r->desc.height || (fi->bits <= 8) != is8 ||
	    v.format == PC_FMT_FLOAT32 || (!is8 && bits != fi->bits && bits != 16)) {
		rc = pc_error(PC_EFORMAT,
		              "%s: %ux%u with %u significant bits, meta.json says %ux%u %s", p,
		              v.width, v.height, bits, r->desc.width, r->desc.height, fi->name);
		pc_view_free(&v);
		free(p);
		return rc;
	}
	if (!is8 && fi->bits < 16) {
		uint16_t maxv = (uint16_t)((1u << fi->bits) - 1);
		for (uint32_t y = 0; y < v.height && !rc; y++) {
			const uint16_t *row = PC_ROW(&v, const uint16_t, y);
			for (uint32_t x = 0; x < v.width; x++)
				if (row[x] > maxv) {
					rc = pc_error(PC_EFORMAT,
					              "%s: pixel (%u,%u) = %u exceeds the %u-bit "
					              "range of the recording",
					              p, x, y, row[x], fi->bits);
					break;
				}
		}
	}
	free(p);
	if (rc) {
		pc_view_free(&v);
		return rc;
	}
	v.format = r->storage;
	*out = v;
	return 0;
}
