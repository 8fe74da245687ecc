#include "polarcam/io.h"

#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "polarcam/error.h"

/* IEEE 754 binary16 bits of x, rounded to nearest, ties to even (overflow to ±inf, NaN kept). */
static uint16_t f32_to_f16(float x)
{
	uint32_t b;
	memcpy(&b, &x, sizeof b);
	uint32_t sign = (b >> 16) & 0x8000u, e = (b >> 23) & 0xFFu, m = b & 0x7FFFFFu;
	if (e == 0xFF) /* inf, NaN (quiet, payload's top bits kept) */
		return (uint16_t)(sign | 0x7C00u | (m ? 0x200u | (m >> 13) : 0));
	int ex = (int)e - 127 + 15;
	if (ex >= 31)
		return (uint16_t)(sign | 0x7C00u);
	if (ex <= 0) { /* subnormal half (or zero): shift the full significand */
		if (ex < -10)
			return (uint16_t)sign;
		uint32_t full = m | 0x800000u;
		unsigned shift = (unsigned)(14 - ex);
		uint32_t h = full >> shift, rem = full & ((1u << shift) - 1),
		         half = 1u << (shift - 1);
		if (rem > half || (rem == half && (h & 1)))
			h++;
		return (uint16_t)(sign | h);
	}
	uint32_t h = ((uint32_t)ex << 10) | (m >> 13), rem = m & 0x1FFFu;
	if (rem > 0x1000u || (rem == 0x1000u && (h & 1)))
		h++; /* may carry into the exponent, up to inf: still the right rounding */
	return (uint16_t)(sign | h);
}

void pc_f32_to_f16(const float *in, uint16_t *out, size_t n)
{
	for (size_t i = 0; i < n; i++)
		out[i] = f32_to_f16(in[i]);
}

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
	case PC_DT_F16:
		return "<f2";
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
	case PC_DT_F16:
		return 2;
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
	int hl = snprintf(hdr, sizeof hdr,
	                  "{'descr': '%s', 'fortran_order': False, 'shape': (%s), }", descr, shp);
	size_t total = 10 + (size_t)hl + 1;
	size_t padded = (total + 63) / 64 * 64;
	size_t pad = padded - total;
	unsigned char pre[10] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, 0, 0};
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
		int rc = pc_error(PC_EINVAL, "%s: %zu bytes more than the array holds", s->af.path,
		                  bytes - (s->bytes - s->written));
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
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", path,
		                strerror(errno));
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
		hlen = pre[8] | ((size_t)pre[9] << 8) | ((size_t)pre[10] << 16) |
		       ((size_t)pre[11] << 24);
	} else {
		rc = pc_error(PC_EFORMAT, "%s: .npy version %u.%u not supported", path, pre[6],
		              pre[7]);
		goto out;
	}
	if (hlen > 65536) {
		rc =
		    pc_error(PC_EFORMAT, "%s: .npy header of %zu bytes is implausible", path, hlen);
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
		rc = pc_error(PC_EFORMAT, "%s: .npy header lacks descr, fortran_order or shape",
		              path);
		goto out;
	}
	if (strncmp(fo, "False", 5) != 0) {
		rc = pc_error(PC_EFORMAT,
		              "%s: Fortran-order arrays are not supported (save C order)", path);
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
		rc = pc_error(PC_EFORMAT,
		              "%s: dtype '%.*s' not supported (expected u1, <u2, <f4 or "
		              "<f8)",
		              path, n, d + 1);
		goto out;
	}
	if (*sh != '(') {
		rc = pc_error(PC_EFORMAT, "%s: malformed shape in .npy header", path);
		goto out;
	}
	sh++;
	/* (N,) (N, M) ...: decimal dimensions, commas, spaces, the closing parenthesis */
	bool closed = false;
	while (*sh) {
		while (*sh == ' ')
			sh++;
		if (*sh == ')') {
			closed = true;
			break;
		}
		if (*sh < '0' || *sh > '9' || out->ndim >= 4) {
			rc = pc_error(PC_EFORMAT,
			              "%s: shape not understood or more than 4 dimensions", path);
			goto out;
		}
		uint64_t v = 0;
		for (; *sh >= '0' && *sh <= '9'; sh++) {
			if (v > (UINT64_MAX - 9) / 10) {
				rc = pc_error(PC_EFORMAT, "%s: shape dimension %u too large", path,
				              out->ndim);
				goto out;
			}
			v = v * 10 + (uint64_t)(*sh - '0');
		}
		if (v > SIZE_MAX) {
			rc = pc_error(PC_EFORMAT, "%s: shape dimension %u too large", path,
			              out->ndim);
			goto out;
		}
		out->shape[out->ndim++] = (size_t)v;
		while (*sh == ' ')
			sh++;
		if (*sh == ',')
			sh++;
		else if (*sh != ')') {
			rc = pc_error(PC_EFORMAT, "%s: malformed shape in .npy header", path);
			goto out;
		}
	}
	if (!closed) {
		rc = pc_error(PC_EFORMAT, "%s: malformed shape in .npy header (no ')')", path);
		goto out;
	}
	if (out->ndim == 0) {
		rc = pc_error(PC_EFORMAT, "%s: 0-dimensional arrays are not images", path);
		goto out;
	}
	/* sizes from the header are checked before anything is allocated: against the length of
	 * the file (a header cannot promise more data than follows it), then against the limits */
	const size_t esize = dtype_size(out->dtype);
	uint64_t count = 1;
	bool overflow = false;
	for (unsigned i = 0; i < out->ndim; i++) {
		uint64_t v = out->shape[i];
		if (v && count > UINT64_MAX / esize / v)
			overflow = true;
		else
			count *= v;
	}
	if (overflow) {
		rc =
		    pc_error(PC_EFORMAT, "%s: the header's shape needs more than 2^64 bytes", path);
		goto out;
	}
	const uint64_t bytes = count * esize;
	const uint64_t data_off = (pre[6] == 1 ? 10 : 12) + (uint64_t)hlen;
	const uint64_t fsize = pc_io_file_size(fp);
	if (fsize != UINT64_MAX && (fsize < data_off || fsize - data_off < bytes)) {
		rc = pc_error(PC_EFORMAT,
		              "%s: truncated: the header promises %llu data bytes, the "
		              "file holds %llu",
		              path, (unsigned long long)bytes,
		              (unsigned long long)(fsize > data_off ? fsize - data_off : 0));
		goto out;
	}
	{
		uint64_t h = out->shape[0], w = out->ndim > 1 ? out->shape[1] : 1;
		if ((rc = pc_io_check_image(path, w, h, bytes)))
			goto out;
	}
	if (bytes > SIZE_MAX) {
		rc = pc_error(PC_ERANGE, "%s: %llu bytes do not fit this machine's address space",
		              path, (unsigned long long)bytes);
		goto out;
	}
	out->data = malloc(bytes ? (size_t)bytes : 1);
	if (!out->data) {
		rc = pc_error(PC_ENOMEM, "%s: %llu bytes", path, (unsigned long long)bytes);
		goto out;
	}
	if (fread(out->data, 1, (size_t)bytes, fp) != bytes) {
		rc = pc_error(PC_EFORMAT, "%s: truncated: the header promises %llu data bytes",
		              path, (unsigned long long)bytes);
		goto out;
	}
out:
	free(hdr);
	fclose(fp);
	if (rc)
		pc_array_free(out);
	return rc;
}
