/* calib/calib_file.c - the calibration file: a NumPy .npz (a zip archive of .npy arrays, as
 * numpy.savez writes it; NumPy's format specification, numpy.lib.format, version 1.0) built in
 * memory with libzip and written atomically (io: temporary file + rename). Members and meanings:
 * docs/calibration.md, "The calibration file". */
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zip.h>

#include "polarcam/calib.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/limits.h"

/* ---- .npy in memory (format 1.0: magic, version, little-endian header length, a Python dict
 * literal padded with spaces to a multiple of 64 bytes, then C-order little-endian data) ---- */

typedef struct npy_buf {
	unsigned char *data;
	size_t size;
} npy_buf;

static int npy_make(const char *descr, unsigned ndim, const size_t *shape, const void *data,
                    size_t elem, npy_buf *out)
{
	char hdr[256], sh[128] = "";
	size_t n = 1;
	for (unsigned i = 0; i < ndim; i++) {
		snprintf(sh + strlen(sh), sizeof sh - strlen(sh), "%zu%s", shape[i],
		         ndim == 1      ? ","
		         : i + 1 < ndim ? ", "
		                        : "");
		n *= shape[i];
	}
	int len = snprintf(hdr, sizeof hdr,
	                   "{'descr': '%s', 'fortran_order': False, 'shape': (%s), }", descr, sh);
	size_t total = 10 + (size_t)len + 1;
	size_t pad = (64 - total % 64) % 64;
	size_t hlen = (size_t)len + pad + 1;
	out->size = 10 + hlen + n * elem;
	out->data = malloc(out->size);
	if (!out->data)
		return pc_error(PC_ENOMEM, "npy member");
	unsigned char *p = out->data;
	memcpy(p, "\x93NUMPY\x01\x00", 8);
	p[8] = (unsigned char)(hlen & 0xff);
	p[9] = (unsigned char)(hlen >> 8);
	memcpy(p + 10, hdr, (size_t)len);
	memset(p + 10 + len, ' ', pad);
	p[10 + hlen - 1] = '\n';
	memcpy(p + 10 + hlen, data,
	       n * elem); /* x86-64 and every supported target: little-endian */
	return 0;
}

/* Parses a member: dtype must be descr, shape is returned (ndim ≤ 4). */
static int npy_parse(const char *file, const char *member, const unsigned char *b, size_t size,
                     const char *descr, unsigned *ndim, size_t shape[4], const unsigned char **data)
{
	if (size < 10 || memcmp(b, "\x93NUMPY", 6) || b[6] != 1)
		return pc_error(PC_EFORMAT, "%s: %s: not a NumPy 1.0 array", file, member);
	size_t hlen = b[8] | (size_t)b[9] << 8;
	if (10 + hlen > size)
		return pc_error(PC_EFORMAT, "%s: %s: truncated header", file, member);
	char h[512];
	if (hlen >= sizeof h)
		return pc_error(PC_EFORMAT, "%s: %s: header too long", file, member);
	memcpy(h, b + 10, hlen);
	h[hlen] = 0;
	char want[64];
	snprintf(want, sizeof want, "'descr': '%s'", descr);
	if (!strstr(h, want))
		return pc_error(PC_EFORMAT, "%s: %s: expected dtype %s", file, member, descr);
	if (!strstr(h, "'fortran_order': False"))
		return pc_error(PC_EFORMAT, "%s: %s: expected C order", file, member);
	const char *s = strstr(h, "'shape': (");
	if (!s)
		return pc_error(PC_EFORMAT, "%s: %s: no shape", file, member);
	s += 10;
	*ndim = 0;
	size_t n = 1;
	/* decimal dimensions only, each below 2^31, the product checked: a shape whose byte count
	 * wraps must not match the member's size */
	while (*s && *s != ')') {
		if (*s < '0' || *s > '9' || *ndim >= 4)
			return pc_error(PC_EFORMAT, "%s: %s: bad shape", file, member);
		size_t v = 0;
		for (; *s >= '0' && *s <= '9'; s++) {
			v = v * 10 + (size_t)(*s - '0');
			if (v >= (size_t)1 << 31)
				return pc_error(PC_EFORMAT, "%s: %s: bad shape", file, member);
		}
		shape[(*ndim)++] = v;
		if (v && n > SIZE_MAX / 8 / v)
			return pc_error(PC_EFORMAT, "%s: %s: bad shape", file, member);
		n *= v;
		while (*s == ',' || *s == ' ')
			s++;
	}
	if (*s != ')')
		return pc_error(PC_EFORMAT, "%s: %s: bad shape", file, member);
	size_t elem = descr[2] == '8' ? 8 : descr[2] == '4' ? 4 : 1;
	if (size < 10 + hlen || size - 10 - hlen != n * elem)
		return pc_error(PC_EFORMAT, "%s: %s: %zu data bytes, the shape needs %zu", file,
		                member, size - 10 - hlen, n * elem);
	*data = b + 10 + hlen;
	return 0;
}

/* ---- writing ---- */

static int add_member(zip_t *z, const char *name, npy_buf *b)
{
	zip_source_t *s = zip_source_buffer(z, b->data, b->size, 1);
	if (!s) {
		free(b->data);
		return pc_error(PC_EIO, "zip: %s: %s", name, zip_strerror(z));
	}
	zip_int64_t idx = zip_file_add(z, name, s, ZIP_FL_OVERWRITE);
	if (idx < 0) {
		zip_source_free(s);
		return pc_error(PC_EIO, "zip: %s: %s", name, zip_strerror(z));
	}
	zip_set_file_compression(z, (zip_uint64_t)idx, ZIP_CM_STORE, 0);
	b->data = NULL;
	return 0;
}

static int add_array(zip_t *z, const char *name, const char *descr, size_t elem, unsigned ndim,
                     const size_t *shape, const void *data)
{
	npy_buf b;
	int rc = npy_make(descr, ndim, shape, data, elem, &b);
	return rc ? rc : add_member(z, name, &b);
}

static const char *const part_names[4] = {"dark", "flat", "analyser", "ecm"};

static char *meta_text(const pc_calib *c)
{
	json_t *m = json_object();
	char lay[64];
	pc_mosaic_format(&c->geo.mosaic, lay, sizeof lay);
	json_object_set_new(m, "polarcam_calibration", json_integer(PC_CALIB_FILE_VERSION));
	json_object_set_new(m, "camera", json_string(c->camera));
	json_object_set_new(m, "width", json_integer(c->geo.width));
	json_object_set_new(m, "height", json_integer(c->geo.height));
	json_object_set_new(m, "offset_x", json_integer(c->geo.offset_x));
	json_object_set_new(m, "offset_y", json_integer(c->geo.offset_y));
	json_object_set_new(m, "sensor_width", json_integer(c->geo.sensor_width));
	json_object_set_new(m, "sensor_height", json_integer(c->geo.sensor_height));
	json_object_set_new(m, "bits", json_integer(c->geo.bits));
	json_object_set_new(m, "layout", json_string(lay));
	json_object_set_new(m, "black_level", json_real(c->black_level));
	json_object_set_new(m, "saturation", json_real(c->saturation));
	json_object_set_new(m, "system_gain",
	                    c->system_gain > 0 ? json_real(c->system_gain) : json_null());
	json_object_set_new(m, "system_gain_db",
	                    c->system_gain > 0 && isfinite(c->system_gain_db)
	                        ? json_real(c->system_gain_db)
	                        : json_null());
	json_object_set_new(m, "dark_gain_db",
	                    c->dark && isfinite(c->dark_gain_db) ? json_real(c->dark_gain_db)
	                                                         : json_null());
	json_t *parts = json_array();
	for (int i = 0; i < 4; i++)
		if (c->parts & (1u << i))
			json_array_append_new(parts, json_string(part_names[i]));
	json_object_set_new(m, "parts", parts);
	if (c->parts & PC_CAL_ECM) {
		json_object_set_new(m, "n_psg", json_integer(c->n_psg));
		json_object_set_new(m, "n_psa", json_integer(c->n_psa));
	}
	json_t *prov = c->provenance ? json_loads(c->provenance, 0, NULL) : NULL;
	json_object_set_new(m, "provenance", prov ? prov : json_object());
	char *t = json_dumps(m, JSON_INDENT(1) | JSON_REAL_PRECISION(17) | JSON_SORT_KEYS);
	json_decref(m);
	return t;
}

int pc_calib_write(const char *path, const pc_calib *c)
{
	zip_error_t ze;
	zip_error_init(&ze);
	zip_source_t *mem = zip_source_buffer_create(NULL, 0, 0, &ze);
	zip_t *z = mem ? zip_open_from_source(mem, ZIP_TRUNCATE, &ze) : NULL;
	if (!z) {
		if (mem)
			zip_source_free(mem);
		int rc = pc_error(PC_EIO, "%s: zip: %s", path, zip_error_strerror(&ze));
		zip_error_fini(&ze);
		return rc;
	}
	zip_error_fini(&ze);
	zip_source_keep(mem);
	const uint32_t W = c->geo.width, H = c->geo.height;
	const size_t s2[2] = {H, W}, s3[3] = {H, W, 3}, s4[4] = {3, 4, H / 2, W / 2};
	int rc = 0;
	char *meta = meta_text(c);
	if (!meta)
		rc = pc_error(PC_ENOMEM, "%s: metadata", path);
	size_t ml = meta ? strlen(meta) : 0;
	if (!rc)
		rc = add_array(z, "meta.npy", "|u1", 1, 1, &ml, meta);
	free(meta);
	if (!rc && c->valid)
		rc = add_array(z, "valid.npy", "|u1", 1, 2, s2, c->valid);
	if (!rc && c->dark)
		rc = add_array(z, "dark.npy", "<f4", 4, 2, s2, c->dark);
	if (!rc && c->dark_noise)
		rc = add_array(z, "dark_noise.npy", "<f4", 4, 2, s2, c->dark_noise);
	if (!rc && c->gain)
		rc = add_array(z, "gain.npy", "<f4", 4, 2, s2, c->gain);
	if (!rc && c->analysis)
		rc = add_array(z, "analysis.npy", "<f4", 4, 3, s3, c->analysis);
	if (!rc && c->residual)
		rc = add_array(z, "residual.npy", "<f4", 4, 2, s2, c->residual);
	if (!rc && c->pinv_sp)
		rc = add_array(z, "pinv_superpixel.npy", "<f4", 4, 4, s4, c->pinv_sp);
	if (!rc && (c->parts & PC_CAL_ECM)) {
		double Wm[4 * PC_CALIB_MAX_STATES], Am[4 * PC_CALIB_MAX_STATES * 4];
		for (int a = 0; a < 4; a++)
			for (unsigned g = 0; g < c->n_psg; g++)
				Wm[a * c->n_psg + g] = c->ecm_W[a][g];
		for (unsigned k = 0; k < 4 * c->n_psa; k++)
			for (int a = 0; a < 4; a++)
				Am[k * 4 + a] = c->ecm_A[k][a];
		const size_t sw[2] = {4, c->n_psg}, sa[2] = {4 * (size_t)c->n_psa, 4};
		rc = add_array(z, "ecm_generator.npy", "<f8", 8, 2, sw, Wm);
		if (!rc)
			rc = add_array(z, "ecm_analyser.npy", "<f8", 8, 2, sa, Am);
	}
	if (rc) {
		zip_discard(z);
		zip_source_free(mem);
		return rc;
	}
	if (zip_close(z) < 0) {
		rc = pc_error(PC_EIO, "%s: zip: %s", path, zip_strerror(z));
		zip_discard(z);
		zip_source_free(mem);
		return rc;
	}
	zip_stat_t st;
	unsigned char *bytes = NULL;
	if (zip_source_stat(mem, &st) < 0 || zip_source_open(mem) < 0) {
		zip_source_free(mem);
		return pc_error(PC_EIO, "%s: zip: reading the archive back failed", path);
	}
	bytes = malloc(st.size ? st.size : 1);
	if (!bytes || zip_source_read(mem, bytes, st.size) != (zip_int64_t)st.size) {
		free(bytes);
		zip_source_close(mem);
		zip_source_free(mem);
		return pc_error(bytes ? PC_EIO : PC_ENOMEM,
		                "%s: zip: reading the archive back failed", path);
	}
	zip_source_close(mem);
	zip_source_free(mem);
	rc = pc_write_file_atomic(path, bytes, st.size);
	free(bytes);
	return rc;
}

/* ---- reading ---- */

/* max: the largest size the member can have (its .npy header and the array the metadata
 * implies); the archive's own claim is checked against it, and against what its compressed
 * bytes can hold (stored: equal; deflate: at most 1032:1, RFC 1951), before allocating. */
static int read_member(zip_t *z, const char *file, const char *name, bool required, uint64_t max,
                       zip_file_t **fp, size_t *size)
{
	*fp = NULL;
	*size = 0;
	zip_int64_t idx = zip_name_locate(z, name, 0);
	if (idx < 0)
		return required ? pc_error(PC_EFORMAT, "%s: member %s missing", file, name) : 0;
	zip_stat_t st;
	if (zip_stat_index(z, (zip_uint64_t)idx, 0, &st) < 0 ||
	    (st.valid & (ZIP_STAT_SIZE | ZIP_STAT_COMP_SIZE | ZIP_STAT_COMP_METHOD)) !=
	        (ZIP_STAT_SIZE | ZIP_STAT_COMP_SIZE | ZIP_STAT_COMP_METHOD))
		return pc_error(PC_EFORMAT, "%s: %s: unreadable", file, name);
	if (st.comp_method != ZIP_CM_STORE && st.comp_method != ZIP_CM_DEFLATE)
		return pc_error(PC_EFORMAT,
		                "%s: %s: compression method %d (expected stored or "
		                "deflate, as numpy.savez writes)",
		                file, name, (int)st.comp_method);
	if (st.size > max || (st.comp_method == ZIP_CM_STORE && st.size != st.comp_size) ||
	    (st.comp_method == ZIP_CM_DEFLATE && st.size / 1032 > st.comp_size))
		return pc_error(PC_EFORMAT,
		                "%s: %s: the archive claims %llu bytes (%llu compressed); "
		                "at most %llu expected",
		                file, name, (unsigned long long)st.size,
		                (unsigned long long)st.comp_size, (unsigned long long)max);
	*fp = zip_fopen_index(z, (zip_uint64_t)idx, 0);
	if (!*fp)
		return pc_error(PC_EFORMAT, "%s: %s: %s", file, name, zip_strerror(z));
	*size = st.size;
	return 0;
}

/* Exactly n bytes of member f (libzip checks the CRC at the member's end). */
static int read_exact(zip_file_t *f, const char *file, const char *name, void *dst, size_t n,
                      size_t total)
{
	zip_int64_t got = n ? zip_fread(f, dst, n) : 0;
	if (got != (zip_int64_t)n)
		return pc_error(PC_EFORMAT, "%s: %s: corrupt (read %lld of %zu bytes)", file, name,
		                (long long)got, total);
	return 0;
}

/* Loads member name (if present, or required) as descr with the given shape into a new
 * buffer: the .npy header is read and checked first, then the array straight into the buffer
 * (one copy; the 200-MB maps of a full sensor used to be read into a temporary first). */
static int load_map(zip_t *z, const char *file, const char *name, const char *descr, unsigned ndim,
                    const size_t *shape, bool required, void **out)
{
	*out = NULL;
	size_t elem0 = descr[2] == '8' ? 8 : descr[2] == '4' ? 4 : 1;
	uint64_t max = 10 + 512;
	{
		uint64_t n0 = elem0;
		for (unsigned i = 0; i < ndim; i++)
			n0 *= shape[i]; /* shapes from the metadata: at most 65535² × 12 × 8 */
		max += n0;
	}
	zip_file_t *f;
	size_t size;
	int rc = read_member(z, file, name, required, max, &f, &size);
	if (rc || !f)
		return rc;
	/* the header: magic, version, length, then the dictionary (< 512 bytes, npy_parse) */
	unsigned char hdr[10 + 512];
	size_t hl = size < 10 ? size : 10;
	if (!(rc = read_exact(f, file, name, hdr, hl, size)) && hl == 10 &&
	    !memcmp(hdr, "\x93NUMPY", 6)) {
		size_t hlen = hdr[8] | (size_t)hdr[9] << 8;
		if (hlen < 512 && 10 + hlen <= size) {
			rc = read_exact(f, file, name, hdr + 10, hlen, size);
			hl += hlen;
		}
	}
	unsigned nd;
	size_t sh[4];
	const unsigned char *data;
	/* npy_parse reads only the header bytes and checks the data size against size */
	if (!rc)
		rc = npy_parse(file, name, hdr, size, descr, &nd, sh, &data);
	bool ok = !rc && nd == ndim;
	size_t n = 1;
	for (unsigned i = 0; ok && i < nd; i++) {
		ok = sh[i] == shape[i];
		n *= sh[i];
	}
	if (!rc && !ok) {
		char want[96] = "";
		for (unsigned i = 0; i < ndim; i++)
			snprintf(want + strlen(want), sizeof want - strlen(want), "%s%zu",
			         i ? "," : "", shape[i]);
		rc = pc_error(PC_EFORMAT,
		              "%s: %s: shape does not match the metadata (expected (%s))", file,
		              name, want);
	}
	size_t elem = descr[2] == '8' ? 8 : descr[2] == '4' ? 4 : 1;
	if (!rc && !(*out = malloc(n * elem > 0 ? n * elem : 1)))
		rc = pc_error(PC_ENOMEM, "%s: %s", file, name);
	if (!rc)
		rc = read_exact(f, file, name, *out, n * elem, size);
	/* one more read meets the member's end, where libzip compares the CRC */
	unsigned char extra;
	if (!rc && zip_fread(f, &extra, 1) != 0)
		rc = pc_error(PC_EFORMAT, "%s: %s: corrupt (%s)", file, name, zip_file_strerror(f));
	if (rc) {
		free(*out);
		*out = NULL;
	}
	zip_fclose(f);
	return rc;
}

/* A whole (small) member into a new buffer (*buf NULL when absent and not required). */
static int read_member_buf(zip_t *z, const char *file, const char *name, bool required,
                           uint64_t max, unsigned char **buf, size_t *size)
{
	*buf = NULL;
	zip_file_t *f;
	int rc = read_member(z, file, name, required, max, &f, size);
	if (rc || !f)
		return rc;
	*buf = malloc(*size ? *size : 1);
	if (!*buf)
		rc = pc_error(PC_ENOMEM, "%s: %s", file, name);
	else
		rc = read_exact(f, file, name, *buf, *size, *size);
	unsigned char extra;
	if (!rc && zip_fread(f, &extra, 1) != 0)
		rc = pc_error(PC_EFORMAT, "%s: %s: corrupt (%s)", file, name, zip_file_strerror(f));
	zip_fclose(f);
	if (rc) {
		free(*buf);
		*buf = NULL;
	}
	return rc;
}

static int meta_int(json_t *m, const char *file, const char *key, long lo, long hi, long *v)
{
	json_t *x = json_object_get(m, key);
	if (!json_is_integer(x) || json_integer_value(x) < lo || json_integer_value(x) > hi)
		return pc_error(PC_EFORMAT, "%s: meta.%s: expected an integer in [%ld, %ld]", file,
		                key, lo, hi);
	*v = (long)json_integer_value(x);
	return 0;
}

/* meta's optional analog gain KEY (WHOSE, for the message) in dB into *out: a number in [−100,
 * 100], or null or absent (*out untouched: unknown); PC_EFORMAT naming the field otherwise */
static int opt_gain_db(json_t *m, const char *key, const char *whose, const char *path, double *out)
{
	json_t *v = json_object_get(m, key);
	if (!v || json_is_null(v))
		return 0;
	if (!json_is_number(v) || !isfinite(json_number_value(v)) ||
	    fabs(json_number_value(v)) > 100)
		return pc_error(PC_EFORMAT,
		                "%s: meta.%s: expected %s analog gain in dB (a number in [-100, "
		                "100]) or null",
		                path, key, whose);
	*out = json_number_value(v);
	return 0;
}

int pc_calib_read(const char *path, pc_calib *c)
{
	pc_calib_init(c);
	int err = 0;
	zip_t *z = zip_open(path, ZIP_RDONLY | ZIP_CHECKCONS, &err);
	if (!z) {
		zip_error_t ze;
		zip_error_init_with_code(&ze, err);
		int rc = pc_error(
		    err == ZIP_ER_NOENT || err == ZIP_ER_OPEN ? PC_ENOENT : PC_EFORMAT,
		    "%s: not a readable calibration file (zip: %s)", path, zip_error_strerror(&ze));
		zip_error_fini(&ze);
		return rc;
	}
	unsigned char *mb = NULL;
	size_t ms = 0;
	json_t *m = NULL;
	int rc = read_member_buf(z, path, "meta.npy", true, 1u << 20, &mb, &ms);
	unsigned nd = 0;
	size_t sh[4];
	const unsigned char *md = NULL;
	if (!rc)
		rc = npy_parse(path, "meta.npy", mb, ms, "|u1", &nd, sh, &md);
	if (!rc && nd != 1)
		rc = pc_error(PC_EFORMAT, "%s: meta.npy: expected a 1-D array of JSON text", path);
	if (!rc) {
		json_error_t je;
		m = json_loadb((const char *)md, sh[0], JSON_REJECT_DUPLICATES, &je);
		if (!json_is_object(m))
			rc = pc_error(PC_EFORMAT, "%s: meta.npy: not a JSON object (%s)", path,
			              je.text);
	}
	long v = 0, w = 0, h = 0;
	if (!rc && !(rc = meta_int(m, path, "polarcam_calibration", 1, 1000000, &v)) &&
	    v > PC_CALIB_FILE_VERSION)
		rc = pc_error(PC_EFORMAT,
		              "%s: calibration file version %ld: this polarcam reads up "
		              "to version %d",
		              path, v, PC_CALIB_FILE_VERSION);
	if (!rc && !(rc = meta_int(m, path, "width", 4, 65535, &w)) &&
	    !(rc = meta_int(m, path, "height", 4, 65535, &h))) {
		c->geo.width = (uint32_t)w;
		c->geo.height = (uint32_t)h;
		if (w % 2 || h % 2)
			rc = pc_error(PC_EFORMAT, "%s: meta: %ldx%ld is not even", path, w, h);
		/* the maps are this size (the analysis map 12 bytes per pixel): the limits of
		 * polarcam/limits.h before anything is read */
		char what[600];
		snprintf(what, sizeof what, "%s: %ldx%ld calibration", path, w, h);
		if (!rc)
			rc = pc_limit_check(PC_LIMIT_PIXELS, (uint64_t)w * (uint64_t)h, what);
		if (!rc)
			rc = pc_limit_check(PC_LIMIT_BYTES, (uint64_t)w * (uint64_t)h * 12, what);
	}
	if (!rc && !(rc = meta_int(m, path, "offset_x", 0, 65535, &v)))
		c->geo.offset_x = (uint32_t)v;
	if (!rc && !(rc = meta_int(m, path, "offset_y", 0, 65535, &v)))
		c->geo.offset_y = (uint32_t)v;
	if (!rc && !(rc = meta_int(m, path, "sensor_width", 0, 65535, &v)))
		c->geo.sensor_width = (uint32_t)v;
	if (!rc && !(rc = meta_int(m, path, "sensor_height", 0, 65535, &v)))
		c->geo.sensor_height = (uint32_t)v;
	if (!rc && !(rc = meta_int(m, path, "bits", 1, 16, &v)))
		c->geo.bits = (unsigned)v;
	if (!rc) {
		json_t *lay = json_object_get(m, "layout");
		if (!json_is_string(lay) || pc_mosaic_parse(json_string_value(lay), &c->geo.mosaic))
			rc =
			    pc_error(PC_EFORMAT, "%s: meta.layout: expected a mosaic layout", path);
	}
	if (!rc) {
		json_t *b = json_object_get(m, "black_level"),
		       *s = json_object_get(m, "saturation");
		json_t *cam = json_object_get(m, "camera");
		if (!json_is_number(b) || !json_is_number(s))
			rc = pc_error(PC_EFORMAT,
			              "%s: meta: black_level and saturation must be numbers", path);
		else {
			c->black_level = json_number_value(b);
			c->saturation = json_number_value(s);
		}
		if (json_is_string(cam))
			snprintf(c->camera, sizeof c->camera, "%s", json_string_value(cam));
		/* optional (files before it have none): a number > 0, or null */
		json_t *k = json_object_get(m, "system_gain");
		if (!rc && k && !json_is_null(k)) {
			if (!json_is_number(k) || !(json_number_value(k) > 0) ||
			    !(json_number_value(k) <= 1e6))
				rc = pc_error(
				    PC_EFORMAT,
				    "%s: meta.system_gain: expected a number in (0, 1e6] (DN "
				    "per electron) or null",
				    path);
			else
				c->system_gain = json_number_value(k);
		}
		/* optional: the flats' analog gain in dB, with a system gain; the dark frames',
		 * with a dark part (checked with the parts below); or null */
		if (!rc &&
		    !(rc = opt_gain_db(m, "system_gain_db", "the flats'", path,
		                       &c->system_gain_db)) &&
		    isfinite(c->system_gain_db) && !(c->system_gain > 0))
			rc = pc_error(PC_EFORMAT,
			              "%s: meta.system_gain_db: given without a system_gain", path);
		if (!rc)
			rc = opt_gain_db(m, "dark_gain_db", "the dark frames'", path,
			                 &c->dark_gain_db);
	}
	json_t *parts = rc ? NULL : json_object_get(m, "parts");
	if (!rc && !json_is_array(parts))
		rc = pc_error(PC_EFORMAT, "%s: meta.parts: expected an array", path);
	for (size_t i = 0; !rc && i < json_array_size(parts); i++) {
		const char *p = json_string_value(json_array_get(parts, i));
		int k = 0;
		while (k < 4 && !(p && !strcmp(p, part_names[k])))
			k++;
		if (k == 4)
			rc = pc_error(PC_EFORMAT, "%s: meta.parts[%zu]: unknown part", path, i);
		else
			c->parts |= 1u << k;
	}
	if (!rc && isfinite(c->dark_gain_db) && !(c->parts & PC_CAL_DARK))
		rc = pc_error(PC_EFORMAT, "%s: meta.dark_gain_db: given without a dark part", path);
	if (!rc) {
		json_t *prov = json_object_get(m, "provenance");
		c->provenance =
		    prov ? json_dumps(prov, JSON_COMPACT | JSON_REAL_PRECISION(17)) : NULL;
	}
	const size_t s2[2] = {(size_t)h, (size_t)w}, s3[3] = {(size_t)h, (size_t)w, 3};
	const size_t s4[4] = {3, 4, (size_t)h / 2, (size_t)w / 2};
	bool dark = c->parts & PC_CAL_DARK, flat = c->parts & PC_CAL_FLAT;
	bool an = c->parts & PC_CAL_ANALYSER;
	if (!rc)
		rc = load_map(z, path, "valid.npy", "|u1", 2, s2, dark || flat || an,
		              (void **)&c->valid);
	if (!rc)
		rc = load_map(z, path, "dark.npy", "<f4", 2, s2, dark, (void **)&c->dark);
	if (!rc)
		rc = load_map(z, path, "dark_noise.npy", "<f4", 2, s2, dark,
		              (void **)&c->dark_noise);
	if (!rc)
		rc = load_map(z, path, "gain.npy", "<f4", 2, s2, flat, (void **)&c->gain);
	if (!rc)
		rc = load_map(z, path, "analysis.npy", "<f4", 3, s3, an, (void **)&c->analysis);
	if (!rc)
		rc = load_map(z, path, "residual.npy", "<f4", 2, s2, false, (void **)&c->residual);
	if (!rc)
		rc = load_map(z, path, "pinv_superpixel.npy", "<f4", 4, s4, an,
		              (void **)&c->pinv_sp);
	if (!rc && (c->parts & PC_CAL_ECM)) {
		long g = 0, a = 0;
		if (!(rc = meta_int(m, path, "n_psg", 1, PC_CALIB_MAX_STATES, &g)) &&
		    !(rc = meta_int(m, path, "n_psa", 1, PC_CALIB_MAX_STATES, &a))) {
			c->n_psg = (unsigned)g;
			c->n_psa = (unsigned)a;
			double *Wm = NULL, *Am = NULL;
			const size_t sw[2] = {4, (size_t)g}, sa[2] = {4 * (size_t)a, 4};
			if (!(rc = load_map(z, path, "ecm_generator.npy", "<f8", 2, sw, true,
			                    (void **)&Wm)) &&
			    !(rc = load_map(z, path, "ecm_analyser.npy", "<f8", 2, sa, true,
			                    (void **)&Am))) {
				for (int r = 0; r < 4; r++)
					for (long k = 0; k < g; k++)
						c->ecm_W[r][k] = Wm[r * g + k];
				for (long k = 0; k < 4 * a; k++)
					for (int r = 0; r < 4; r++)
						c->ecm_A[k][r] = Am[k * 4 + r];
			}
			free(Wm);
			free(Am);
		}
	}
	/* values: every map finite, gains positive */
	size_t np = (size_t)w * (size_t)h;
	for (size_t p = 0; !rc && p < np; p++) {
		if ((c->dark && !isfinite(c->dark[p])) || (c->gain && !(c->gain[p] > 0)) ||
		    (c->analysis &&
		     !(isfinite(c->analysis[3 * p]) && isfinite(c->analysis[3 * p + 1]) &&
		       isfinite(c->analysis[3 * p + 2]))))
			rc = pc_error(PC_EFORMAT,
			              "%s: pixel (%zu, %zu): non-finite map value or gain "
			              "≤ 0",
			              path, p % (size_t)w, p / (size_t)w);
		/* each trusted sample's equation is divided by its transmission a0 (the fused
		 * pipeline's weighted least squares, pc_compact_calib) */
		else if (c->analysis && (!c->valid || c->valid[p]) && !(c->analysis[3 * p] > 0))
			rc = pc_error(PC_EFORMAT,
			              "%s: analysis.npy: trusted pixel (%zu, %zu) has a0 = %g; "
			              "expected a positive transmission (or 0 in valid.npy)",
			              path, p % (size_t)w, p / (size_t)w,
			              (double)c->analysis[3 * p]);
	}
	free(mb);
	json_decref(m);
	zip_discard(z);
	if (rc)
		pc_calib_free(c);
	return rc;
}
