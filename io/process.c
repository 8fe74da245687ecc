/* Raw mosaic files through the pipeline (polarcam/process.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/process.h"

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
		rc = pc_error(PC_EINVAL, "%s: size %ux%u: a polarizer mosaic needs an even width and "
					 "height of at least 4 (whole 2x2 analyser blocks)",
			      in->path, raw->width, raw->height);
		pc_view_free(raw);
	}
	return rc;
}

int pc_process_method(const char *name, const pc_mosaic *m, pc_demosaic_method *out)
{
	bool colour = m->period == 4;
	int rc = pc_demosaic_method_from_name(name ? name : colour ? "bayer-first" : "bilinear",
					      out);
	if (rc)
		return pc_error_prefix(rc, "--method: ");
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(*out);
	char layout[64];
	pc_mosaic_format(m, layout, sizeof layout);
	if (colour && !(mi->flags & PC_DMF_COLOR))
		return pc_error(PC_EINVAL, "--method %s: works on monochrome mosaics; the mosaic %s is "
					   "colour-polarization (methods for it: bayer-first, "
					   "bayer-eari)", mi->name, layout);
	if (!colour && !(mi->flags & PC_DMF_MONO))
		return pc_error(PC_EINVAL, "--method %s: needs a colour-polarization mosaic such as "
					   "RGGB:90,45,135,0; the mosaic %s is monochrome", mi->name,
				layout);
	return 0;
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
	double t0 = now_s();
	rc = pc_demosaic(&raw, &o->mosaic, o->method, &o->demosaic, planes);
	double secs = now_s() - t0;
	pc_view_free(&raw);
	if (rc) {
		free(buf);
		return pc_error_prefix(rc, "%s: ", in->path);
	}
	size_t shape[3] = { oh, ow, nch };
	rc = tiff ? pc_tiff_write_array(out_path, buf, PC_DT_F32, oh, ow, nch)
		  : pc_npy_write(out_path, buf, PC_DT_F32, 3, shape);
	free(buf);
	if (!rc && rep)
		*rep = (pc_demosaic_file_report){ ow, oh, nch, bits, secs };
	return rc;
}

static const char *const process_files[] = { "stokes.npy", "dolp.npy", "aolp.npy", "s0.png",
					     "dolp.png",   "aolp.png", "aolp_sat.png" };

/* meta.json of a processed frame */
static json_t *process_meta(const pc_raw_input *in, const pc_process_opts *o, uint32_t rw,
			    uint32_t rh, unsigned bits, double seconds)
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
	json_object_set_new(j, "pipeline_seconds", pc_json_real(seconds));
	json_object_set_new(j, "aolp_convention",
			    json_string("radians in [0, pi), from the image x axis, "
					"counter-clockwise as seen by the viewer"));
	json_t *files = json_array();
	for (size_t k = 0; k < sizeof process_files / sizeof process_files[0]; k++)
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
	float *stokes = malloc(sizeof(float) * n * 3), *dolp = malloc(sizeof(float) * n),
	      *aolp = malloc(sizeof(float) * n);
	if (!stokes || !dolp || !aolp) {
		rc = pc_error(PC_ENOMEM, "out of memory for %ux%u Stokes images", w, h);
		pc_view_free(&raw);
		goto out;
	}
	pc_stokes_out so = { { stokes, (size_t)w * 3, 3 }, { stokes + 1, (size_t)w * 3, 3 },
			     { stokes + 2, (size_t)w * 3, 3 }, { dolp, w, 1 }, { aolp, w, 1 } };
	double t0 = now_s();
	rc = pc_stokes_from_raw(&raw, &o->mosaic, o->method, &o->demosaic, &so);
	double t_pipe = now_s() - t0;
	uint32_t rw = raw.width, rh = raw.height;
	pc_view_free(&raw);
	if (rc) {
		pc_error_prefix(rc, "%s: ", in->path);
		goto out;
	}
	if ((rc = pc_stokes_folder_write(dir, &so, w, h, folder)))
		goto out;
	json_t *j = process_meta(in, o, rw, rh, bits, t_pipe);
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
	return rc;
}
