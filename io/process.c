/* Raw mosaic files through the pipeline (polarcam/process.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/process.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "io_internal.h"
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
	struct stat sb;
	if (stat(in->path, &sb) != 0)
		return pc_error(errno == ENOENT ? PC_ENOENT : PC_EIO, "%s: %s", in->path,
		                strerror(errno));
	if (S_ISDIR(sb.st_mode))
		return pc_error(PC_EINVAL, "%s: a folder, not a raw file", in->path);
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
	if (colour && !(mi->flags & PC_DMF_COLOR)) {
		char list[512];
		pc_demosaic_method_names(PC_DMF_COLOR, list, sizeof list);
		return pc_error(PC_EINVAL,
		                "--method %s: works on monochrome mosaics; the mosaic %s is "
		                "colour-polarization (methods for it: %s)",
		                mi->name, layout, list);
	}
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

/* The front door's options for o and a raw of the given format and bit depth; ng_used:
 * pc_pipeline_opts.noise_gain_used (NULL: not wanted). */
static pc_pipeline_opts pipeline_opts(const pc_process_opts *o, pc_pixfmt format, unsigned bits,
                                      double *ng_used)
{
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = o->method;
	po.mosaic = o->mosaic;
	po.threads = o->demosaic.threads;
	po.reference = o->demosaic.reference;
	po.full_scale = o->demosaic.full_scale;
	po.noise_gain = o->noise_gain;
	po.noise_gain_used = ng_used;
	if (!(po.full_scale > 0) && format != PC_FMT_FLOAT32 && bits >= 1 && bits <= 16)
		po.full_scale = (double)((1u << bits) - 1u); /* sBIT: a 12-bit PNG in 16 bits */
	po.black_level = o->stage ? 0 : o->black_level;
	po.saturation_level = pc_process_saturation(o, format, bits);
	po.dead_level = o->dead_level;
	return po;
}

/* Raw → Stokes (st) or analyser images (ch) through the stage or the front door; rgb (colour
 * frames, no stage: a calibration is for monochrome mosaics) also each colour's Stokes; ng_used
 * (NULL: not wanted) the noise gain a noise-aware method used. */
static int run_pipeline(const pc_process_opts *o, const pc_view *raw, const pc_frame_meta *meta,
                        unsigned bits, const pc_stokes_out *st, const pc_stokes_out *rgb,
                        const pc_fplane *ch, pc_validity *valid, double *ng_used)
{
	pc_pipeline_opts po = pipeline_opts(o, raw->format, bits, ng_used);
	if (o->stage) {
		if (o->black_level != 0)
			return pc_error(PC_EINVAL,
			                "a black level of %g and %s: the calibration's dark "
			                "map is the black level; give one or the other",
			                o->black_level,
			                o->stage->name ? o->stage->name : "a calibration");
		pc_frame f;
		memset(&f, 0, sizeof f);
		if (meta)
			f.meta = *meta;
		else
			f.meta.exposure_us = f.meta.gain_db = NAN; /* a file's: unknown */
		f.view = *raw;
		f.mosaic = o->mosaic;
		f.meta.offset_x = o->roi_x;
		f.meta.offset_y = o->roi_y;
		return o->stage->run(o->stage->user, &f, bits, &po, st, ch, valid);
	}
	if (st && rgb)
		return pc_stokes_run_colour(raw, &po, st, rgb, valid);
	return st ? pc_stokes_run(raw, &po, st, valid) : pc_demosaic_run(raw, &po, ch, valid);
}

static bool has_suffix(const char *s, const char *suf)
{
	size_t n = strlen(s), m = strlen(suf);
	return n >= m && !strcmp(s + n - m, suf);
}

/* OUT and OUT_valid.npy as one set: both written complete into a temporary folder beside them,
 * then put in place, so that neither replaces an older one unless both were written. Two
 * renames are not one atomic step; the order makes a kill between them leave a mask missing,
 * never a new OUT beside an older mask: the older mask goes first, then OUT, then the mask. */
static int write_set(const char *out_path, const char *vpath, bool tiff, const float *buf,
                     const size_t shape[3], const uint8_t *mask)
{
	char dir[4096], tmp[4200], t1[4300], t2[4300];
	const char *slash = strrchr(out_path, '/');
	if ((size_t)snprintf(dir, sizeof dir, "%.*s",
	                     slash ? (slash == out_path ? 1 : (int)(slash - out_path)) : 1,
	                     slash ? out_path : ".") >= sizeof dir)
		return pc_error(PC_EINVAL, "-o %s: path too long", out_path);
	int rc = pc_mkdir_p(dir);
	if (rc)
		return rc;
	/* ".polarcam-set.tmp-HOST-PID-XXXXXX"; a run killed between mkdtemp and rmdir left its
	 * folder: those of dead processes go first */
	char prefix[256];
	pc_io_tmp_prefix("polarcam-set", prefix, sizeof prefix);
	pc_io_remove_stale(dir, prefix);
	if ((size_t)snprintf(tmp, sizeof tmp, "%s/%s%ld-XXXXXX", dir, prefix, (long)getpid()) >=
	    sizeof tmp)
		return pc_error(PC_EINVAL, "-o %s: path too long", out_path);
	if (!mkdtemp(tmp))
		return pc_error(errno == EACCES ? PC_EPERM : PC_EIO,
		                "%s: cannot make a temporary folder beside it: %s", out_path,
		                strerror(errno));
	snprintf(t1, sizeof t1, "%s/out.%s", tmp, tiff ? "tif" : "npy");
	snprintf(t2, sizeof t2, "%s/valid.npy", tmp);
	rc = tiff ? pc_tiff_write_array(t1, buf, PC_DT_F32, (uint32_t)shape[0], (uint32_t)shape[1],
	                                (unsigned)shape[2])
	          : pc_npy_write(t1, buf, PC_DT_F32, 3, shape);
	if (!rc)
		rc = pc_npy_write(t2, mask, PC_DT_U8, 2, shape);
	if (rc)
		pc_error_prefix(rc, "-o %s: ", out_path);
	else if ((unlink(vpath) != 0 && errno != ENOENT) || rename(t1, out_path) != 0 ||
	         rename(t2, vpath) != 0)
		rc = pc_error(PC_EIO, "-o %s: cannot rename into place: %s", out_path,
		              strerror(errno));
	unlink(t1);
	unlink(t2);
	rmdir(tmp);
	return rc;
}

int pc_demosaic_file(const pc_raw_input *in, const pc_process_opts *o, const char *out_path,
                     pc_demosaic_file_report *rep)
{
	bool tiff = has_suffix(out_path, ".tif") || has_suffix(out_path, ".tiff") ||
	            has_suffix(out_path, ".TIF") || has_suffix(out_path, ".TIFF");
	if (!tiff && !has_suffix(out_path, ".npy") && !has_suffix(out_path, ".NPY"))
		return pc_error(PC_EINVAL, "-o %s: the output is .npy or .tif/.tiff (float32)",
		                out_path);
	int rc = pc_output_check(out_path, o->overwrite ? PC_OUT_OVERWRITE : 0, false);
	if (rc)
		return rc;
	pc_view raw;
	unsigned bits;
	rc = pc_raw_read(in, &raw, &bits);
	if (rc)
		return rc;
	uint32_t ow, oh;
	pc_demosaic_out_size(o->method, raw.width, raw.height, &ow, &oh);
	unsigned nch = pc_demosaic_channels(&o->mosaic);
	/* 64-byte aligned: large interleaved outputs then take streaming stores (docs/api.md) */
	const size_t bytes = sizeof(float) * ow * oh * nch;
	float *buf = aligned_alloc(64, (bytes + 63) / 64 * 64);
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
	/* the mask is part of the output: the same rule (refused unless --overwrite) */
	if (checked && (rc = pc_output_check(vpath, o->overwrite ? PC_OUT_OVERWRITE : 0, false))) {
		pc_view_free(&raw);
		free(buf);
		return rc;
	}
	pc_validity valid = {checked ? malloc((size_t)ow * oh) : NULL, ow, 0};
	if (checked && !valid.mask) {
		pc_view_free(&raw);
		free(buf);
		return pc_error(PC_ENOMEM, "out of memory for the %ux%u validity mask", ow, oh);
	}
	/* the noise gain a noise-aware method used, as the pipeline returns it: the one given, or
	 * its estimate from the frame; 0 for the other methods */
	double ng = 0;
	const bool ng_given = o->noise_gain > 0 || (o->stage && o->stage->noise_gain > 0);
	double t0 = now_s();
	rc = run_pipeline(o, &raw, in->meta, bits, NULL, NULL, planes, &valid, &ng);
	double secs = now_s() - t0;
	pc_view_free(&raw);
	if (rc) {
		free(buf);
		free(valid.mask);
		return pc_error_prefix(rc, "%s: ", in->path);
	}
	size_t shape[3] = {oh, ow, nch};
	rc = checked ? write_set(out_path, vpath, tiff, buf, shape, valid.mask)
	     : tiff  ? pc_tiff_write_array(out_path, buf, PC_DT_F32, oh, ow, nch)
	             : pc_npy_write(out_path, buf, PC_DT_F32, 3, shape);
	free(buf);
	free(valid.mask);
	if (!rc && rep) {
		*rep = (pc_demosaic_file_report){
		    ow, oh, nch, bits, secs, sat, valid.n_invalid, "", ng, ng > 0 && ng_given};
		snprintf(rep->valid_path, sizeof rep->valid_path, "%s", vpath);
	}
	return rc;
}

/* The files of a Stokes folder, as meta.json lists them. */
static json_t *files_json(unsigned files, bool numbered, bool stack, bool valid, bool colour)
{
	enum { VALID = 1u << 30, COLOUR = 1u << 29, UNSTACKED = 1u << 28 };
	static const struct {
		unsigned flag;
		const char *name[4];
	} t[12] = {{PC_SF_STOKES, {"stokes.npy"}},
	           {PC_SF_STOKES | COLOUR | UNSTACKED, {"stokes_rgb.npy"}},
	           {PC_SF_S0, {"s0.npy"}},
	           {PC_SF_DOLP, {"dolp.npy"}},
	           {PC_SF_AOLP, {"aolp.npy"}},
	           {PC_SF_MINMAX, {"imin.npy", "imax.npy"}},
	           {PC_SF_SPLIT, {"diffuse.npy", "specular.npy"}},
	           {VALID, {"valid.npy"}},
	           {PC_SF_PICTURES, {"s0.png", "dolp.png", "aolp.png", "aolp_sat.png"}},
	           {PC_SF_PICTURES | PC_SF_MINMAX, {"imin.png", "imax.png"}},
	           {PC_SF_PICTURES | PC_SF_SPLIT, {"diffuse.png", "specular.png"}},
	           {PC_SF_PICTURES | COLOUR, {"s0_rgb.png", "dolp_rgb.png"}}};
	if (valid)
		files |= VALID;
	if (colour)
		files |= COLOUR;
	if (!stack)
		files |= UNSTACKED; /* stokes_rgb.npy is not stacked */
	json_t *a = json_array();
	for (int k = 0; k < 12; k++)
		for (int i = 0; i < 4 && t[k].name[i] && (files & t[k].flag) == t[k].flag; i++) {
			const char *n = t[k].name[i];
			char buf[64];
			if (numbered && (!stack || (t[k].flag & PC_SF_PICTURES))) {
				const char *dot = strrchr(n, '.');
				snprintf(buf, sizeof buf, "%.*s_NNNNNN%s", (int)(dot - n), n, dot);
				n = buf;
			}
			json_array_append_new(a, json_string(n));
		}
	return a;
}

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

/* meta.json of a processed frame or batch: what every Stokes folder of process says */
static json_t *process_meta(const pc_process_opts *o, const char *input, uint32_t rw, uint32_t rh,
                            unsigned bits, double sat, bool checked, uint64_t n_invalid)
{
	char layout[64];
	pc_mosaic_format(&o->mosaic, layout, sizeof layout);
	json_t *j = json_object();
	if (input)
		json_object_set_new(j, "input", json_string(input));
	json_object_set_new(j, "width", json_integer(rw));
	json_object_set_new(j, "height", json_integer(rh));
	json_object_set_new(j, "bits", json_integer(bits));
	json_object_set_new(j, "layout", json_string(layout));
	json_object_set_new(j, "method", json_string(pc_demosaic_method_get(o->method)->name));
	json_object_set_new(j, "reference", json_boolean(o->demosaic.reference));
	/* a noise-aware method's noise gain: the one given, the calibration's (at its flats' gain),
	 * or estimated from each frame */
	const bool ng = pc_demosaic_method_get(o->method)->flags & PC_DMF_NOISE_GAIN;
	const double ngv = !ng                 ? 0
	                   : o->noise_gain > 0 ? o->noise_gain
	                   : o->stage          ? o->stage->noise_gain
	                                       : 0;
	json_object_set_new(j, "noise_gain", ngv > 0 ? pc_json_real(ngv) : json_null());
	json_object_set_new(j, "noise_gain_from",
	                    !ng                 ? json_null()
	                    : o->noise_gain > 0 ? json_string("option")
	                    : ngv > 0           ? json_string("calibration")
	                                        : json_string("estimated"));
	json_object_set_new(j, "black_level", pc_json_real(o->stage ? 0 : o->black_level));
	json_object_set_new(j, "saturation_level", sat > 0 ? pc_json_real(sat) : json_null());
	json_object_set_new(j, "dead_level",
	                    o->dead_level > 0 ? pc_json_real(o->dead_level) : json_null());
	json_object_set_new(j, "invalid_pixels",
	                    checked ? json_integer((json_int_t)n_invalid) : json_null());
	json_object_set_new(j, "calibration",
	                    o->stage && o->stage->name ? json_string(o->stage->name) : json_null());
	json_object_set_new(j, "aolp_convention",
	                    json_string("radians in [0, pi), from the image x axis, "
	                                "counter-clockwise as seen by the viewer"));
	return j;
}

/* One frame's planes: S0, S1, S2 interleaved (H, W, 3) as stokes.npy holds them, DoLP, AoLP. */
typedef struct frame_buf {
	float *stokes, *dolp, *aolp, *s0; /* s0: a contiguous copy for stacks of s0.npy */
	float *mm;  /* Imin, Imax, diffuse, specular planes for stacks (PC_SF_MINMAX/SPLIT) */
	float *rgb; /* colour frames: R, G, B × S0, S1, S2 (H, W, 3, 3), then their DoLP */
	pc_stokes_out so, cso[3];
	pc_validity valid; /* mask NULL when no level is checked */
	uint32_t w, h;
} frame_buf;

static int frame_buf_alloc(frame_buf *f, uint32_t w, uint32_t h, bool s0, bool checked, bool mm,
                           bool colour)
{
	size_t n = (size_t)w * h;
	memset(f, 0, sizeof *f);
	if (colour) {
		if (!(f->rgb = malloc(sizeof(float) * n * 12)))
			return pc_error(PC_ENOMEM, "out of memory for %ux%u colour Stokes images",
			                w, h);
		float *d = f->rgb + 9 * n; /* no per-colour AoLP: nothing writes or draws it */
		for (size_t c = 0; c < 3; c++)
			f->cso[c] = (pc_stokes_out){{f->rgb + 3 * c, (size_t)w * 9, 9},
			                            {f->rgb + 3 * c + 1, (size_t)w * 9, 9},
			                            {f->rgb + 3 * c + 2, (size_t)w * 9, 9},
			                            {d + c * n, w, 1},
			                            {NULL, 0, 0}};
	}
	f->mm = mm ? malloc(sizeof(float) * n * 4) : NULL;
	f->stokes = malloc(sizeof(float) * n * 3);
	f->dolp = malloc(sizeof(float) * n);
	f->aolp = malloc(sizeof(float) * n);
	f->s0 = s0 ? malloc(sizeof(float) * n) : NULL;
	f->valid = (pc_validity){checked ? malloc(n) : NULL, w, 0};
	if (!f->stokes || !f->dolp || !f->aolp || (s0 && !f->s0) || (checked && !f->valid.mask) ||
	    (mm && !f->mm))
		return pc_error(PC_ENOMEM, "out of memory for %ux%u Stokes images", w, h);
	f->so = (pc_stokes_out){{f->stokes, (size_t)w * 3, 3},
	                        {f->stokes + 1, (size_t)w * 3, 3},
	                        {f->stokes + 2, (size_t)w * 3, 3},
	                        {f->dolp, w, 1},
	                        {f->aolp, w, 1}};
	f->w = w;
	f->h = h;
	return 0;
}

static void frame_buf_free(frame_buf *f)
{
	free(f->stokes);
	free(f->dolp);
	free(f->aolp);
	free(f->s0);
	free(f->mm);
	free(f->rgb);
	free(f->valid.mask);
	memset(f, 0, sizeof *f);
}

/* The stacked arrays of a batch: (N, H, W, 3) stokes.npy, (N, H, W) s0, dolp, aolp, imin,
 * imax, diffuse, specular (as asked) and, when a level is checked, valid.npy (N, H, W) uint8. */
enum { STACK_N = 9 };
typedef struct stack {
	pc_npy_stream s[STACK_N];
	bool open[STACK_N];
} stack;

enum { STACK_VALID = 1u << 30 };
static const char *const stack_names[STACK_N] = {"stokes.npy", "s0.npy",      "dolp.npy",
                                                 "aolp.npy",   "valid.npy",   "imin.npy",
                                                 "imax.npy",   "diffuse.npy", "specular.npy"};
static const unsigned stack_flags[STACK_N] = {PC_SF_STOKES, PC_SF_S0,    PC_SF_DOLP,
                                              PC_SF_AOLP,   STACK_VALID, PC_SF_MINMAX,
                                              PC_SF_MINMAX, PC_SF_SPLIT, PC_SF_SPLIT};

static int stack_open(stack *st, const char *dir, unsigned files, size_t n, uint32_t w, uint32_t h)
{
	for (int k = 0; k < STACK_N; k++) {
		if (!(files & stack_flags[k]))
			continue;
		char path[4096];
		size_t shape[4] = {n, h, w, 3};
		if ((size_t)snprintf(path, sizeof path, "%s/%s", dir, stack_names[k]) >=
		    sizeof path)
			return pc_error(PC_EINVAL, "%s: path too long", dir);
		int rc = pc_npy_stream_open(&st->s[k], path, k == 4 ? PC_DT_U8 : PC_DT_F32,
		                            k == 0 ? 4 : 3, shape);
		if (rc)
			return rc;
		st->open[k] = true;
	}
	return 0;
}

static int stack_add(stack *st, frame_buf *f)
{
	size_t n = (size_t)f->w * f->h;
	if (f->s0)
		for (size_t i = 0; i < n; i++)
			f->s0[i] = f->stokes[3 * i];
	if (f->mm) {
		pc_minmax_out mo = {{f->mm, f->w, 1},
		                    {f->mm + n, f->w, 1},
		                    {f->mm + 2 * n, f->w, 1},
		                    {f->mm + 3 * n, f->w, 1}};
		int rc = pc_stokes_minmax(&f->so.s0, &f->so.s1, &f->so.s2, f->w, f->h, &mo);
		if (rc)
			return rc;
	}
	const void *data[STACK_N] = {f->stokes, f->s0, f->dolp, f->aolp, f->valid.mask};
	for (int k = 5; k < STACK_N && f->mm; k++)
		data[k] = f->mm + (size_t)(k - 5) * n;
	for (int k = 0; k < STACK_N; k++) {
		if (!st->open[k])
			continue;
		size_t bytes = k == 4 ? n : sizeof(float) * n * (k ? 1 : 3);
		int rc = pc_npy_stream_write(&st->s[k], data[k], bytes);
		if (rc) {
			st->open[k] = false; /* aborted by the failed write */
			return rc;
		}
	}
	return 0;
}

static int stack_close(stack *st, bool commit)
{
	int rc = 0;
	for (int k = 0; k < STACK_N; k++) {
		if (!st->open[k])
			continue;
		st->open[k] = false;
		if (commit && !rc)
			rc = pc_npy_stream_commit(&st->s[k]);
		else
			pc_npy_stream_abort(&st->s[k]);
	}
	return rc;
}

static int write_meta(const char *dir, json_t *j, char **meta)
{
	char *txt = json_dumps(j, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	char path[4096];
	int rc;
	if (!txt)
		rc = pc_error(PC_ENOMEM, "meta.json");
	else if ((size_t)snprintf(path, sizeof path, "%s/meta.json", dir) >= sizeof path)
		rc = pc_error(PC_EINVAL, "%s: path too long", dir);
	else
		rc = pc_write_file_atomic(path, txt, strlen(txt));
	free(txt);
	if (!rc && meta && !(*meta = pc_json_text(j)))
		rc = pc_error(PC_ENOMEM, "meta.json");
	return rc;
}

/* A batch (numbered) or a single file (plain names) into the folder tmp. */
static int run_batch(const pc_process_batch *b, const pc_process_opts *o, bool numbered,
                     const char *tmp, const pc_stokes_folder_opts *folder, json_t **meta_out)
{
	frame_buf f = {0};
	stack st;
	memset(&st, 0, sizeof st);
	json_t *frames = json_array();
	uint32_t rw0 = 0, rh0 = 0;
	unsigned bits0 = 0;
	double t_all = 0, sat = 0;
	bool checked = false;
	uint64_t n_invalid = 0;
	int rc = 0;
	const bool stack_on = numbered && b->stack;
	/* colour frames: R, G, B Stokes for stokes_rgb.npy and the colour pictures */
	const bool colour =
	    o->mosaic.period == 4 && !o->stage && (folder->files & (PC_SF_STOKES | PC_SF_PICTURES));
	for (size_t k = 0; k < b->count && !rc; k++) {
		const pc_raw_input *in = &b->inputs[k];
		uint64_t number = b->numbers ? b->numbers[k] : k;
		pc_view raw;
		unsigned bits;
		if ((rc = pc_raw_read(in, &raw, &bits)))
			break;
		if (k == 0) {
			uint32_t w, h;
			pc_demosaic_out_size(o->method, raw.width, raw.height, &w, &h);
			rw0 = raw.width, rh0 = raw.height, bits0 = bits;
			sat = pc_process_saturation(o, raw.format, bits);
			checked = sat > 0 || o->dead_level > 0 || o->stage;
			rc = frame_buf_alloc(
			    &f, w, h, stack_on && (folder->files & PC_SF_S0), checked,
			    stack_on && (folder->files & (PC_SF_MINMAX | PC_SF_SPLIT)), colour);
			if (!rc && stack_on)
				rc = stack_open(&st, tmp,
				                folder->files | (checked ? STACK_VALID : 0),
				                b->count, w, h);
		} else if (raw.width != rw0 || raw.height != rh0 || bits != bits0) {
			rc = pc_error(PC_EINVAL,
			              "%s: %ux%u, %u-bit, but %s is %ux%u, %u-bit: a batch "
			              "is one size and bit depth",
			              in->path, raw.width, raw.height, bits, b->inputs[0].path, rw0,
			              rh0, bits0);
		}
		double t0 = now_s(), dt = 0, ng = 0;
		if (!rc) {
			rc = run_pipeline(o, &raw, in->meta, bits, &f.so, colour ? f.cso : NULL,
			                  NULL, &f.valid, &ng);
			dt = now_s() - t0;
			t_all += dt;
			if (rc)
				pc_error_prefix(rc, "%s: ", in->path);
		}
		pc_view_free(&raw);
		if (rc)
			break;
		pc_stokes_folder_opts fo = *folder;
		fo.numbered = numbered;
		fo.number = number;
		fo.no_valid_file = stack_on;
		bool pictures = (folder->files & PC_SF_PICTURES) &&
		                (!numbered || (b->pictures_every && k % b->pictures_every == 0));
		fo.files = (stack_on ? 0 : folder->files) & ~(unsigned)PC_SF_PICTURES;
		fo.no_minmax_files = stack_on;
		if (stack_on)
			fo.files |= folder->files & (PC_SF_MINMAX | PC_SF_SPLIT);
		if (pictures)
			fo.files |= PC_SF_PICTURES;
		fo.colour = colour ? f.cso : NULL;
		if (stack_on)
			rc = stack_add(&st, &f);
		if (!rc)
			rc = pc_stokes_folder_write_valid(tmp, &f.so, f.w, f.h, &fo, &f.valid);
		n_invalid += f.valid.n_invalid;
		json_t *fj = json_pack("{s:s, s:I, s:o, s:b}", "input", in->path, "number",
		                       (json_int_t)number, "pipeline_seconds", pc_json_real(dt),
		                       "pictures", pictures);
		json_object_set_new(fj, "invalid_pixels",
		                    checked ? json_integer((json_int_t)f.valid.n_invalid)
		                            : json_null());
		/* a noise-aware method's noise gain for this frame (the calibration's at the
		 * frame's analog gain, or the frame's estimate) */
		if (pc_demosaic_method_get(o->method)->flags & PC_DMF_NOISE_GAIN)
			json_object_set_new(fj, "noise_gain", pc_json_real(ng));
		if (in->meta)
			json_object_set_new(fj, "gain_db", pc_json_real(in->meta->gain_db));
		if (!numbered)
			json_object_set_new(fj, "valid_statistics",
			                    valid_stats(&f.so, f.w, f.h, &f.valid));
		json_array_append_new(frames, fj);
		if (!rc && pc_progress_report(&b->progress, "process", k + 1, b->count))
			rc = pc_error(PC_ECANCELED, "stopped after %zu of %zu frames", k + 1,
			              b->count);
	}
	if (!rc)
		rc = stack_close(&st, true);
	stack_close(&st, false);
	frame_buf_free(&f);
	if (rc) {
		json_decref(frames);
		return rc;
	}
	json_t *j = process_meta(o, numbered ? NULL : b->inputs[0].path, rw0, rh0, bits0, sat,
	                         checked, n_invalid);
	if (numbered) {
		json_object_set_new(j, "frames", frames);
		json_object_set_new(j, "stack", json_boolean(stack_on));
		json_object_set_new(j, "pictures_every",
		                    b->pictures_every >= b->count && b->count > 0
		                        ? json_null() /* the first frame only */
		                        : json_integer((json_int_t)b->pictures_every));
	} else {
		json_t *f0 = json_array_get(frames, 0);
		json_object_set(j, "pipeline_seconds", json_object_get(f0, "pipeline_seconds"));
		json_object_set(j, "valid_statistics", json_object_get(f0, "valid_statistics"));
		json_decref(frames);
	}
	if (numbered)
		json_object_set_new(j, "pipeline_seconds", pc_json_real(t_all));
	json_object_set_new(j, "files",
	                    files_json(folder->files, numbered, stack_on, checked, colour));
	*meta_out = j;
	return 0;
}

static int process_folder(const pc_process_batch *b, const pc_process_opts *o, bool numbered,
                          const char *dir, const pc_stokes_folder_opts *folder, char **meta)
{
	if (meta)
		*meta = NULL;
	if (!b->count)
		return pc_error(PC_EINVAL, "no raw file given");
	/* inputs that are not there are named before the output is looked at */
	for (size_t k = 0; k < b->count; k++) {
		struct stat sb;
		if (!b->inputs[k].path || stat(b->inputs[k].path, &sb) != 0)
			return pc_error(PC_ENOENT, "%s: %s",
			                b->inputs[k].path ? b->inputs[k].path : "",
			                strerror(errno));
	}
	pc_outdir od;
	int rc = pc_outdir_begin(&od, dir, o->overwrite ? PC_OUT_OVERWRITE : 0);
	if (rc)
		return rc;
	json_t *j = NULL;
	rc = run_batch(b, o, numbered, od.tmp, folder, &j);
	if (!rc)
		rc = write_meta(od.tmp, j, meta);
	json_decref(j);
	if (!rc)
		rc = pc_outdir_commit(&od);
	pc_outdir_abort(&od);
	if (rc && meta) {
		free(*meta);
		*meta = NULL;
	}
	return rc;
}

int pc_process_file(const pc_raw_input *in, const pc_process_opts *o, const char *dir,
                    const pc_stokes_folder_opts *folder, char **meta)
{
	pc_process_batch b = {in, 1, NULL, false, 1, {NULL, NULL}};
	return process_folder(&b, o, false, dir, folder, meta);
}

int pc_process_files(const pc_process_batch *b, const pc_process_opts *o, const char *dir,
                     const pc_stokes_folder_opts *folder, char **meta)
{
	if (!b || (b->count && !b->inputs))
		return pc_error(PC_EINVAL, "process: missing argument");
	return process_folder(b, o, true, dir, folder, meta);
}
