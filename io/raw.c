/* Headerless raw files (polarcam/io.h): the writer. The reader is pc_image_read with a
 * geometry (io/image.c). */
#include "polarcam/io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static int host_is_little_endian(void)
{
	const uint16_t one = 1;
	uint8_t b;
	memcpy(&b, &one, 1);
	return b == 1;
}

int pc_raw_write(const char *path, const pc_view *v)
{
	if (!path || !v)
		return pc_error(PC_EINVAL, "raw: missing argument");
	int rc = pc_view_check(v);
	if (rc)
		return pc_error_prefix(rc, "%s: ", path);
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (fi->is_float)
		return pc_error(PC_EINVAL, "%s: raw files hold integer pixels, not %s", path,
		                fi->name);
	size_t row;
	if ((rc = pc_format_row_bytes(v->format, v->width, &row)))
		return pc_error_prefix(rc, "%s: ", path);
	/* 16-bit containers are little-endian in the file: swapped row by row on a big-endian
	 * host, written as they are otherwise */
	const int swap =
	    fi->packing == PC_PACK_NONE && fi->group_bytes == 2 && !host_is_little_endian();
	uint8_t *tmp = swap ? malloc(row) : NULL;
	if (swap && !tmp)
		return pc_error(PC_ENOMEM, "%s: row buffer", path);
	pc_atomic_file af;
	if ((rc = pc_atomic_open(&af, path))) {
		free(tmp);
		return rc;
	}
	for (uint32_t y = 0; y < v->height; y++) {
		const uint8_t *src = PC_ROW(v, const uint8_t, y);
		if (swap) {
			for (size_t i = 0; i + 1 < row; i += 2) {
				tmp[i] = src[i + 1];
				tmp[i + 1] = src[i];
			}
			src = tmp;
		}
		if (fwrite(src, 1, row, af.fp) != row) {
			int e = errno;
			pc_atomic_abort(&af);
			free(tmp);
			return pc_error(PC_EIO, "%s: write failed: %s", path, strerror(e));
		}
	}
	free(tmp);
	return pc_atomic_commit(&af);
}
