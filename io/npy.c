#include "polarcam/io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

/* NumPy .npy format: numpy/lib/format.py docs (NEP 1). Magic "\x93NUMPY", version, header
 * length (u16 for 1.0, u32 for 2.0), an ASCII Python dict, padded with spaces and '\n' so that
 * the data starts at a multiple of 64 bytes. */

static const char *dtype_descr(pc_dtype t)
{
	switch (t) {
	case PC_DT_U8:
		return "|u1";
	case PC_DT_U16:
		return "<u2";
	case PC_DT_F32:
		return "<f4";
	case PC_DT_F64:
		return "<f8";
	}
	return NULL;
}

static size_t dtype_size(pc_dtype t)
{
	switch (t) {
	case PC_DT_U8:
		return 1;
	case PC_DT_U16:
		return 2;
	case PC_DT_F32:
		return 4;
	case PC_DT_F64:
		return 8;
	}
	return 0;
}

size_t pc_array_count(const pc_array *a)
{
	size_t n = 1;
	for (unsigned i = 0; i < a->ndim; i++)
		n *= a->shape[i];
	return n;
}

void pc_array_free(pc_array *a)
{
	if (!a)
		return;
	free(a->data);
	a->data = NULL;
}

/* The header of a C-order array; *count receives its element count. */
static int write_header(FILE *fp, const char *path, pc_dtype dtype, unsigned ndim,
			const size_t *shape, size_t *count)
{
	const char *descr = dtype_descr(dtype);
	if (!descr || ndim < 1 || ndim > 4)
		return pc_error(PC_EINVAL, "%s: unsupported dtype or ndim %u", path, ndim);
	char shp[128];
	size_t off = 0;
	*count = 1;
	for (unsigned i = 0; i < ndim; i++) {
		off += (size_t)snprintf(shp + off, sizeof shp - off, "%zu,%s", shape[i],
					(ndim > 1 && i + 1 < ndim) ? " " : "");
		*count *= shape[i];
	}
	if (ndim > 1 && off > 0 && shp[off - 1] == ',')
		shp[--off] = '\0';
	char hdr[256];
	int hl = snprintf(hdr, sizeof hdr, "{'descr': '%s', 'fortran_order': False, 'shape': (%s), }",
			  descr, shp);
	size_t total = 10 + (size_t)hl + 1;
	size_t padded = (total + 63) / 64 * 64;
	size_t pad = padded - total;
	unsigned char pre[10] = { 0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, 0, 0 };
	size_t hlen = (size_t)hl + pad + 1;
	pre[8] = (unsigned char)(hlen & 0xff);
	pre[9] = (unsigned char)(hlen >> 8);
	fwrite(pre, 1, 10, fp);
	fwrite(hdr, 1, (size_t)hl, fp);
	for (size_t i = 0; i < pad; i++)
		fputc(' ', fp);
	fputc('\n', fp);
	return 0;
}

int pc_npy_write(const char *path, const void *data, pc_dtype dtype, unsigned ndim,
		 const size_t *shape)
{
	pc_npy_stream s;
	int rc = pc_npy_stream_open(&s, path, dtype, ndim, shape);
	if (!rc)
		rc = pc_npy_stream_write(&s, data, s.bytes);
	return rc ? rc : pc_npy_stream_commit(&s);
}

int pc_npy_stream_open(pc_npy_stream *s, const char *path, pc_dtype dtype, unsigned ndim,
		       const size_t *shape)
{
	memset(s, 0, sizeof *s);
	size_t count = 0;
	if (!dtype_descr(dtype) || ndim < 1 || ndim > 4)
		return pc_error(PC_EINVAL, "%s: unsupported dtype or ndim %u", path, ndim);
	int rc = pc_atomic_open(&s->af, path);
	if (rc)
		return rc;
	if ((rc = write_header(s->af.fp, path, dtype, ndim, shape, &count))) {
		pc_atomic_abort(&s->af);
		return rc;
	}
	s->bytes = count * dtype_size(dtype);
	return 0;
}

int pc_npy_stream_write(pc_npy_stream *s, const void *data, size_t bytes)
{
	if (!s->af.fp)
		return pc_error(PC_ESTATE, ".npy stream not open");
	if (bytes > s->bytes - s->written) {
		int rc = pc_error(PC_EINVAL, "%s: %zu bytes more than the array holds",
				  s->af.path, bytes - (s->bytes - s->written));
		pc_npy_stream_abort(s);
		return rc;
	}
	if (bytes && fwrite(data, 1, bytes, s->af.fp) != bytes) {
		int rc = pc_error(PC_EIO, "%s: write failed: %s", s->af.path, strerror(errno));
		pc_npy_stream_abort(s);
		return rc;
	}
	s->written += bytes;
	return 0;
}

int pc_npy_stream_commit(pc_npy_stream *s)
{
	if (!s->af.fp)
		return pc_error(PC_ESTATE, ".npy stream not open");
	if (s->written != s->bytes) {
		int rc = pc_error(PC_ESTATE, "%s: %zu of %zu bytes written", s->af.path, s->written,
				  s->bytes);
		pc_npy_stream_abort(s);
		return rc;
	}
	return pc_atomic_commit(&s->af);
}

void pc_npy_stream_abort(pc_npy_stream *s)
{
	pc_atomic_abort(&s->af);
}

/* Finds 'key': in the header dict and returns a pointer just after the colon. */
static const char *dict_value(const char *hdr, const char *key)
{
	char pat[32];
	snprintf(pat, sizeof pat, "'%s'", key);
	const char *p = strstr(hdr, pat);
	if (!p)
		return NULL;
	p += strlen(pat);
	while (*p == ' ')
		p++;
	if (*p != ':')
		return NULL;
	p++;
	while (*p == ' ')
		p++;
	return p;
}

int pc_npy_read(const char *path, pc_array *out)
{
	memset(out, 0, sizeof *out);
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path, strerror(errno));
	unsigned char pre[12];
	int rc = 0;
	char *hdr = NULL;
	if (fread(pre, 1, 10, fp) != 10 || memcmp(pre, "\x93NUMPY", 6) != 0) {
		rc = pc_error(PC_EFORMAT, "%s: not a NumPy .npy file (bad magic)", path);
		goto out;
	}
	size_t hlen;
	if (pre[6] == 1) {
		hlen = pre[8] | ((size_t)pre[9] << 8);
	} else if (pre[6] == 2 || pre[6] == 3) {
		if (fread(pre + 10, 1, 2, fp) != 2) {
			rc = pc_error(PC_EFORMAT, "%s: truncated .npy header", path);
			goto out;
		}
		hlen = pre[8] | ((size_t)pre[9] << 8) | ((size_t)pre[10] << 16) | ((size_t)pre[11] << 24);
	} else {
		rc = pc_error(PC_EFORMAT, "%s: .npy version %u.%u not supported", path, pre[6], pre[7]);
		goto out;
	}
	if (hlen > 65536) {
		rc = pc_error(PC_EFORMAT, "%s: .npy header of %zu bytes is implausible", path, hlen);
		goto out;
	}
	hdr = malloc(hlen + 1);
	if (!hdr || fread(hdr, 1, hlen, fp) != hlen) {
		rc = pc_error(PC_EFORMAT, "%s: truncated .npy header", path);
		goto out;
	}
	hdr[hlen] = '\0';
	const char *d = dict_value(hdr, "descr");
	const char *fo = dict_value(hdr, "fortran_order");
	const char *sh = dict_value(hdr, "shape");
	if (!d || !fo || !sh) {
		rc = pc_error(PC_EFORMAT, "%s: .npy header lacks descr, fortran_order or shape", path);
		goto out;
	}
	if (strncmp(fo, "False", 5) != 0) {
		rc = pc_error(PC_EFORMAT, "%s: Fortran-order arrays are not supported (save C order)",
			      path);
		goto out;
	}
	if (!strncmp(d, "'|u1'", 5) || !strncmp(d, "'<u1'", 5))
		out->dtype = PC_DT_U8;
	else if (!strncmp(d, "'<u2'", 5))
		out->dtype = PC_DT_U16;
	else if (!strncmp(d, "'<f4'", 5))
		out->dtype = PC_DT_F32;
	else if (!strncmp(d, "'<f8'", 5))
		out->dtype = PC_DT_F64;
	else {
		/* the descr as written, between its quotes */
		int n = 0;
		if (*d == '\'' || *d == '"')
			while (n < 16 && d[1 + n] && d[1 + n] != *d)
				n++;
		rc = pc_error(PC_EFORMAT, "%s: dtype '%.*s' not supported (expected u1, <u2, <f4 or "
					  "<f8)", path, n, d + 1);
		goto out;
	}
	if (*sh != '(') {
		rc = pc_error(PC_EFORMAT, "%s: malformed shape in .npy header", path);
		goto out;
	}
	sh++;
	size_t count = 1;
	while (*sh && *sh != ')') {
		while (*sh == ' ' || *sh == ',')
			sh++;
		if (*sh == ')')
			break;
		char *end;
		unsigned long long v = strtoull(sh, &end, 10);
		if (end == sh || out->ndim >= 4) {
			rc = pc_error(PC_EFORMAT, "%s: shape not understood or more than 4 dimensions",
				      path);
			goto out;
		}
		out->shape[out->ndim++] = (size_t)v;
		if (v && count > SIZE_MAX / 16 / v) {
			rc = pc_error(PC_EOVERFLOW, "%s: array size overflows", path);
			goto out;
		}
		count *= (size_t)v;
		sh = end;
	}
	if (out->ndim == 0) {
		rc = pc_error(PC_EFORMAT, "%s: 0-dimensional arrays are not images", path);
		goto out;
	}
	size_t bytes = count * dtype_size(out->dtype);
	out->data = malloc(bytes ? bytes : 1);
	if (!out->data) {
		rc = pc_error(PC_ENOMEM, "%s: %zu bytes", path, bytes);
		goto out;
	}
	if (fread(out->data, 1, bytes, fp) != bytes) {
		rc = pc_error(PC_EFORMAT, "%s: truncated: the header promises %zu data bytes", path,
			      bytes);
		goto out;
	}
out:
	free(hdr);
	fclose(fp);
	if (rc)
		pc_array_free(out);
	return rc;
}
