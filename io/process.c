/* Raw mosaic files through the pipeline (polarcam/process.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/process.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/stokes.h"

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int pc_raw_read(const pc_raw_input *in, pc_view *raw, unsigned *bits)
{
	if (!in || !in->path)
		return pc_error(PC_EINVAL, "no raw file given");
	int rc = pc_image_read_mosaic(in->path, in->geometry, in->bits, raw, bits);
	if (rc)
		return rc;
	if (raw->width % 2 || raw->height % 2 || raw->width < 4 || raw->height < 4) {
		rc = pc_error(PC_EINVAL,
		              "%s: size %ux%u: a polarizer mosaic needs an even width and "
		              "height of at least 4 (whole 2x2 analyser blocks)",
		              in->path, raw->width, raw->height);
		pc_view_free(raw);
	}
	return rc;
}

int pc_process_method(const char *name, const pc_mosaic *m, pc_demosaic_method *out)
{
	bool colour = m->period == 4;
	int rc = pc_demosaic_method_from_name(name     ? name
	                                      : colour ? "bayer-first"
	                                               : "bilinear",
	                                      out);
	if (rc)
		return pc_error_prefix(rc, "--method: ");
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(*out);
	char layout[64];
	pc_mosaic_format(m, layout, sizeof layout);
	if (colour && !(mi->flags & PC_DMF_COLOR))
		return pc_error(PC_EINVAL,
		                "--method %s: works on monochrome mosaics; the mosaic %s is "
		                "colour-polarization (methods for it: bayer-first, "
		                "bayer-eari)",
		                mi->name, layout);
	if (!colour && !(mi->flags & PC_DMF_MONO))
		return pc_error(PC_EINVAL,
		                "--method %s: needs a colour-polarization mosaic such as "
		                "RGGB:90,45,135,0; the mosaic %s is monochrome",
		                mi->name, layout);
	return 0;
}

double pc_process_saturation(const pc_process_opts *o, pc_pixfmt format, unsigned bits)
{
	if (o->saturation_level > 0)
		return o->saturation_level;
	if (o->saturation_level < 0)
		return 0;
	if (o->stage)
		return o->stage->saturation_level > 0 ? o->stage->saturation_level : 0;
	if (format == PC_FMT_FLOAT32 || bits == 0 || bits > 16)
		return 0;
	return (double)((1u << bits) - 1u);
}

/* The front door's options for o and a raw of the given format and bit depth. */
static pc_pipeline_opts pipeline_opts(const pc_process_opts *o, pc_pixfmt format, unsigned bits)
{
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = o->method;
	po.mosaic = o->mosaic;
	po.threads = o->demosaic.threads;
	po.reference = o->demosaic.reference;
	po.full_scale = o->demosaic.full_scale;
	if (!(po.full_scale > 0) && format != PC_FMT_FLOAT32 && bits >= 1 && bits <= 16)
		po.full_scale = (double)((1u << bits) - 1u); /* sBIT: a 12-bit PNG in 16 bits */
	po.black_level = o->stage ? 0 : o->black_level;
	po.saturation_level = pc_process_saturation(o, format, bits);
	po.dead_level = o->dead_level;
	return po;
}

/* Raw → Stokes (st) or analyser images (ch) through the stage or the front door. */
static int run_pipeline(const pc_process_opts *o, const pc_view *raw, unsigned bits,
                        const pc_stokes_out *st, const pc_fplane *ch, pc_validity *valid)
{
	pc_pipeline_opts po = pipeline_opts(o, raw->format, bits);
	if (o->stage) {
		if (o->black_level != 0)
			return pc_error(PC_EINVAL,
			                "a black level of %g and %s: the calibration's dark "
			                "map is the black level; give one or the other",
			                o->black_level,
			                o->stage->name ? o->stage->name : "a calibration");
		pc_frame f;
		memset(&f, 0, sizeof f);
		f.view = *raw;
		f.mosaic = o->mosaic;
		f.meta.offset_x = o->roi_x;
		f.meta.offset_y = o->roi_y;
		return o->stage->run(o->stage->user, &f, bits, &po, st, ch, valid);
	}
	return st ? pc_stokes_run(raw, &po, st, valid) : pc_demosaic_run(raw, &po, ch, valid);
}

static bool has_suffix(const char *s, const char *suf)
{
	size_t n = strlen(s), m = strlen(suf);
	return n >= m && !strcmp(s + n - m, suf);
}

int pc_demosaic_file(const pc_raw_input *in, const pc_process_opts *o, const char *out_path,
                     pc_demosaic_file_report *rep)
{
	bool tiff = has_suffix(out_path, ".tif") || has_suffix(out_path, ".tiff") ||
	            has_suffix(out_path, ".TIF") || has_suffix(out_path, ".TIFF");
	if (!tiff && !has_suffix(out_path, ".npy") && !has_suffix(out_path, ".NPY"))
		return pc_error(PC_EINVAL, "-o %s: the output is .npy or .tif/.tiff (float32)",
		                out_path);
	pc_view raw;
	unsigned bits;
	int rc = pc_raw_read(in, &raw, &bits);
	if (rc)
		return rc;
	uint32_t ow, oh;
	pc_demosaic_out_size(o->method, raw.width, raw.height, &ow, &oh);
	unsigned nch = pc_demosaic_channels(&o->mosaic);
	float *buf = malloc(sizeof(float) * ow * oh * nch);
	if (!buf) {
		pc_view_free(&raw);
		return pc_error(PC_ENOMEM, "out of memory for %ux%ux%u floats", oh, ow, nch);
	}
	pc_fplane planes[PC_DEMOSAIC_MAX_CHANNELS];
	pc_fplanes_interleaved(buf, ow, nch, planes);
	/* the mask beside the output: OUT_valid.npy */
	double sat = pc_process_saturation(o, raw.format, bits);
	bool checked = sat > 0 || o->dead_level > 0 || o->stage;
	char vpath[4096] = "";
	if (checked) {
		size_t stem =
		    strlen(out_path) -
		    (has_suffix(out_path, ".tiff") || has_suffix(out_path, ".TIFF") ? 5 : 4);
		if ((size_t)snprintf(vpath, sizeof vpath, "%.*s_valid.npy", (int)stem, out_path) >=
		    sizeof vpath) {
			pc_view_free(&raw);
			free(buf);
			return pc_error(PC_EINVAL, "-o %s: path too long", out_path);
		}
		/* checked before anything is written: the mask's name must be a legal file name */
		const char *vslash = strrchr(vpath, '/');
		size_t vbase = strlen(vslash ? vslash + 1 : vpath);
		if (vbase > NAME_MAX) {
			pc_view_free(&raw);
			free(buf);
			return pc_error(
			    PC_EINVAL,
			    "-o %s: the validity mask beside it, %s, would be a file name of "
			    "%zu bytes: too long (at most %d); choose a shorter output name, or "
			    "--saturation none without a dead level for no mask",
			    out_path, vslash ? vslash + 1 : vpath, vbase, NAME_MAX);
		}
	}
	pc_validity valid = {checked ? malloc((size_t)ow * oh) : NULL, ow, 0};
	if (checked && !valid.mask) {
		pc_view_free(&raw);
		free(buf);
		return pc_error(PC_ENOMEM, "out of memory for the %ux%u validity mask", ow, oh);
	}
	double t0 = now_s();
	rc = run_pipeline(o, &raw, bits, NULL, planes, &valid);
	double secs = now_s() - t0;
	pc_view_free(&raw);
	if (rc) {
		free(buf);
		free(valid.mask);
		return pc_error_prefix(rc, "%s: ", in->path);
	}
	size_t shape[3] = {oh, ow, nch};
	rc = tiff ? pc_tiff_write_array(out_path, buf, PC_DT_F32, oh, ow, nch)
	          : pc_npy_write(out_path, buf, PC_DT_F32, 3, shape);
	if (!rc && checked)
		rc = pc_npy_write(vpath, valid.mask, PC_DT_U8, 2, shape);
	free(buf);
	free(valid.mask);
	if (!rc && rep) {
		*rep = (pc_demosaic_file_report){ow, oh, nch, bits, secs, sat, valid.n_invalid, ""};
		snprintf(rep->valid_path, sizeof rep->valid_path, "%s", vpath);
	}
	return rc;
}

static const char *const process_files[] = {"stokes.npy", "dolp.npy", "aolp.npy",     "s0.png",
                                            "dolp.png",   "aolp.png", "aolp_sat.png", "valid.npy"};

/* Means of S0 and DoLP over the valid pixels (all pixels without a mask): invalid ones depend
 * on saturated or dead samples and stay out of the statistics. */
static json_t *valid_stats(const pc_stokes_out *so, uint32_t w, uint32_t h, const pc_validity *v)
{
	double s0 = 0, dolp = 0;
	uint64_t n = 0;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++) {
			if (v->mask && !v->mask[(size_t)y * v->row_stride + x])
				continue;
			s0 += so->s0.data[(size_t)y * so->s0.row_stride +
			                  (size_t)x * so->s0.pixel_stride];
			dolp += so->dolp.data[(size_t)y * so->dolp.row_stride +
			                      (size_t)x * so->dolp.pixel_stride];
			n++;
		}
	json_t *j = json_object();
	json_object_set_new(j, "pixels", json_integer((json_int_t)n));
	json_object_set_new(j, "s0_mean", n ? pc_json_real(s0 / (double)n) : json_null());
	json_object_set_new(j, "dolp_mean", n ? pc_json_real(dolp / (double)n) : json_null());
	return j;
}

/* meta.json of a processed frame */
static json_t *process_meta(const pc_raw_input *in, const pc_process_opts *o, uint32_t rw,
                            uint32_t rh, unsigned bits, double seconds, double sat,
                            const pc_validity *valid)
{
	char layout[64];
	pc_mosaic_format(&o->mosaic, layout, sizeof layout);
	json_t *j = json_object();
	json_object_set_new(j, "input", json_string(in->path));
	json_object_set_new(j, "width", json_integer(rw));
	json_object_set_new(j, "height", json_integer(rh));
	json_object_set_new(j, "bits", json_integer(bits));
	json_object_set_new(j, "layout", json_string(layout));
	json_object_set_new(j, "method", json_string(pc_demosaic_method_get(o->method)->name));
	json_object_set_new(j, "reference", json_boolean(o->demosaic.reference));
	json_object_set_new(j, "black_level", pc_json_real(o->stage ? 0 : o->black_level));
	json_object_set_new(j, "saturation_level", sat > 0 ? pc_json_real(sat) : json_null());
	json_object_set_new(j, "dead_level",
	                    o->dead_level > 0 ? pc_json_real(o->dead_level) : json_null());
	json_object_set_new(j, "invalid_pixels",
	                    valid->mask ? json_integer((json_int_t)valid->n_invalid) : json_null());
	json_object_set_new(j, "calibration",
	                    o->stage && o->stage->name ? json_string(o->stage->name) : json_null());
	json_object_set_new(j, "pipeline_seconds", pc_json_real(seconds));
	json_object_set_new(j, "aolp_convention",
	                    json_string("radians in [0, pi), from the image x axis, "
	                                "counter-clockwise as seen by the viewer"));
	json_t *files = json_array();
	for (size_t k = 0; k < sizeof process_files / sizeof process_files[0]; k++)
		if (valid->mask || strcmp(process_files[k], "valid.npy"))
			json_array_append_new(files, json_string(process_files[k]));
	json_object_set_new(j, "files", files);
	return j;
}

int pc_process_file(const pc_raw_input *in, const pc_process_opts *o, const char *dir,
                    const pc_stokes_folder_opts *folder, char **meta)
{
	if (meta)
		*meta = NULL;
	pc_view raw;
	unsigned bits;
	int rc = pc_raw_read(in, &raw, &bits);
	if (rc)
		return rc;
	uint32_t w, h;
	pc_demosaic_out_size(o->method, raw.width, raw.height, &w, &h);
	size_t n = (size_t)w * h;
	double sat = pc_process_saturation(o, raw.format, bits);
	bool checked = sat > 0 || o->dead_level > 0 || o->stage;
	pc_validity valid = {checked ? malloc(n) : NULL, w, 0};
	float *stokes = malloc(sizeof(float) * n * 3), *dolp = malloc(sizeof(float) * n),
	      *aolp = malloc(sizeof(float) * n);
	if (!stokes || !dolp || !aolp || (checked && !valid.mask)) {
		rc = pc_error(PC_ENOMEM, "out of memory for %ux%u Stokes images", w, h);
		pc_view_free(&raw);
		goto out;
	}
	pc_stokes_out so = {{stokes, (size_t)w * 3, 3},
	                    {stokes + 1, (size_t)w * 3, 3},
	                    {stokes + 2, (size_t)w * 3, 3},
	                    {dolp, w, 1},
	                    {aolp, w, 1}};
	double t0 = now_s();
	rc = run_pipeline(o, &raw, bits, &so, NULL, &valid);
	double t_pipe = now_s() - t0;
	uint32_t rw = raw.width, rh = raw.height;
	pc_view_free(&raw);
	if (rc) {
		pc_error_prefix(rc, "%s: ", in->path);
		goto out;
	}
	if ((rc = pc_stokes_folder_write_valid(dir, &so, w, h, folder, &valid)))
		goto out;
	json_t *j = process_meta(in, o, rw, rh, bits, t_pipe, sat, &valid);
	json_object_set_new(j, "valid_statistics", valid_stats(&so, w, h, &valid));
	char *txt = json_dumps(j, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	char path[4096];
	if (!txt)
		rc = pc_error(PC_ENOMEM, "meta.json");
	else if ((size_t)snprintf(path, sizeof path, "%s/meta.json", dir) >= sizeof path)
		rc = pc_error(PC_EINVAL, "%s: path too long", dir);
	else
		rc = pc_write_file_atomic(path, txt, strlen(txt));
	free(txt);
	if (!rc && meta && !(*meta = pc_json_text(j)))
		rc = PC_ENOMEM;
	json_decref(j);
out:
	free(stokes);
	free(dolp);
	free(aolp);
	free(valid.mask);
	return rc;
}
