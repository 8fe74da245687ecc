/* tests/fuzz/fuzz_image.h - the image harnesses' common check: a file read by pc_image_read
 * (dispatch by extension) and pc_image_read_mosaic (bit depth, values) either fails with an
 * error detail that names the file, or gives a well-formed owned view whose every byte is read. */
#ifndef POLARCAM_FUZZ_IMAGE_H
#define POLARCAM_FUZZ_IMAGE_H

#include "fuzz.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/frame.h"
#include "polarcam/io.h"

static inline void fuzz_check_view(const pc_view *v, const char *path)
{
	const pc_format_info *fi = pc_format_info_get(v->format);
	FUZZ_ASSERT(fi && v->data && v->width > 0 && v->height > 0, "%s", path);
	FUZZ_ASSERT((uint64_t)v->width * v->height <= pc_limit_get(PC_LIMIT_PIXELS), "%ux%u",
		    v->width, v->height);
	size_t row;
	FUZZ_ASSERT(pc_format_row_bytes(v->format, v->width, &row) == 0 && v->stride >= row, "%s",
		    fi->name);
	(void)fuzz_touch(v->data, row, v->stride, v->height);
}

static inline void fuzz_read_image(const char *path, const pc_raw_geometry *g, unsigned bits)
{
	pc_view v;
	unsigned sb = 0;
	pc_error_clear();
	int rc = pc_image_read(path, g, &v, &sb);
	if (rc == 0) {
		fuzz_check_view(&v, path);
		pc_view_free(&v);
	} else {
		const char *base = strrchr(path, '/') + 1;
		FUZZ_ASSERT(strstr(pc_error_detail(), base) || rc == PC_ENOMEM, "rc %d: %s", rc,
			    pc_error_detail());
	}
	unsigned bo = 0;
	rc = pc_image_read_mosaic(path, g, bits, &v, &bo);
	if (rc == 0) {
		fuzz_check_view(&v, path);
		const pc_format_info *fi = pc_format_info_get(v.format);
		/* the promise of pc_image_read_mosaic: every value fits the depth it reports */
		FUZZ_ASSERT(pc_view_check_bits(&v, fi->is_float ? 32 : bo) == 0, "%s: %s", path,
			    pc_error_detail());
		pc_view_free(&v);
	}
}

#endif
