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
#include "polarcam/mosaic.h"
#include "polarcam/stokes.h"
#include <math.h>

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

/* An accepted mosaic through the pipeline (pc_stokes_from_raw, IMX250MZR layout, the method
 * from `sel`, fast path or reference): every Stokes, DoLP and AoLP value finite, DoLP in
 * [0, 1], AoLP in [0, π). Small images only (an execution stays in milliseconds). */
static inline void fuzz_pipeline(const pc_view *v, unsigned sel)
{
	if (v->width % 2 || v->height % 2 || v->width < 4 || v->height < 4 ||
	    (uint64_t)v->width * v->height > 128 * 128)
		return;
	static const pc_demosaic_method mono[] = {PC_DM_SUPERPIXEL_HALF,
	                                          PC_DM_SUPERPIXEL,
	                                          PC_DM_BILINEAR,
	                                          PC_DM_BICUBIC,
	                                          PC_DM_PPID,
	                                          PC_DM_RI,
	                                          PC_DM_EARI,
	                                          PC_DM_RATIO};
	const pc_demosaic_method method = mono[sel % 8];
	pc_mosaic m = pc_mosaic_imx250mzr();
	uint32_t ow, oh;
	pc_demosaic_out_size(method, v->width, v->height, &ow, &oh);
	const size_t n = (size_t)ow * oh;
	float *buf = calloc(5 * n, sizeof *buf);
	FUZZ_ASSERT(buf, "malloc");
	pc_stokes_out st;
	pc_fplane *pl[5] = {&st.s0, &st.s1, &st.s2, &st.dolp, &st.aolp};
	for (int k = 0; k < 5; k++) {
		pl[k]->data = buf + (size_t)k * n;
		pl[k]->row_stride = ow;
		pl[k]->pixel_stride = 1;
	}
	pc_demosaic_opts o = {1, (sel >> 3) & 1, 0};
	int rc = pc_stokes_from_raw(v, &m, method, &o, &st);
	FUZZ_ASSERT(rc == 0, "pipeline refused an accepted mosaic: %s", pc_error_detail());
	for (size_t i = 0; i < n; i++) {
		FUZZ_ASSERT(isfinite(st.s0.data[i]) && isfinite(st.s1.data[i]) &&
		                isfinite(st.s2.data[i]),
		            "%s%s: pixel %zu: S = (%g, %g, %g)",
		            pc_demosaic_method_get(method)->name, o.reference ? " (reference)" : "",
		            i, st.s0.data[i], st.s1.data[i], st.s2.data[i]);
		FUZZ_ASSERT(st.dolp.data[i] >= 0 && st.dolp.data[i] <= 1, "DoLP %g",
		            st.dolp.data[i]);
		FUZZ_ASSERT(st.aolp.data[i] >= 0 && st.aolp.data[i] < 3.1415927f, "AoLP %g",
		            st.aolp.data[i]);
	}
	free(buf);
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
		fuzz_pipeline(&v, bits ^ bo);
		pc_view_free(&v);
	}
}

#endif
