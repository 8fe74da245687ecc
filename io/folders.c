/* The pipelines' output folders (polarcam/folders.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/folders.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io_internal.h"
#include "json.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/figures.h"
#include "polarcam/picture.h"
#include "polarcam/plot.h"

/* DIR/NAME into buf (PC_EINVAL when too long). */
static int join(char *buf, size_t size, const char *dir, const char *name)
{
	int n = snprintf(buf, size, "%s/%s", dir, name);
	if (n < 0 || (size_t)n >= size)
		return pc_error(PC_EINVAL, "path too long: %s/%s", dir, name);
	return 0;
}

static int write_npy(const char *dir, const char *name, const float *data, unsigned ndim,
                     const size_t *shape)
{
	char path[4096];
	int rc = join(path, sizeof path, dir, name);
	return rc ? rc : pc_npy_write(path, data, PC_DT_F32, ndim, shape);
}

static void magenta(uint32_t x, uint32_t y, uint8_t rgb[3])
{
	(void)x, (void)y;
	rgb[0] = 255, rgb[1] = 0, rgb[2] = 255;
}

int pc_map_write(const char *dir, const char *name, const float *map, uint32_t width,
                 uint32_t height, double lo, double hi, const char *title, const char *label)
{
	return pc_map_write_marked(dir, name, map, width, height, lo, hi, title, label, NULL);
}

/* pc_map_write with the invalid pixels (valid[p] == 0) marked and counted in the legend, and
 * the hatch where hatch_map is above its bound */
int pc_map_write_marked(const char *dir, const char *name, const float *map, uint32_t width,
                        uint32_t height, double lo, double hi, const char *title, const char *label,
                        const pc_map_marks *marks)
{
	if (!dir || !name || !map)
		return pc_error(PC_EINVAL, "map picture: missing argument");
	const size_t np = (size_t)width * height;
	const uint8_t *valid = marks ? marks->valid : NULL;
	long invalid = 0;
	for (size_t i = 0; valid && i < np; i++)
		invalid += !valid[i];
	char path[4096], file[256];
	snprintf(file, sizeof file, "%s.npy", name);
	size_t shape[2] = {height, width};
	int rc = write_npy(dir, file, map, 2, shape);
	if (rc)
		return rc;
	uint8_t *rgb = malloc((size_t)width * height * 3);
	if (!rgb)
		return pc_error(PC_ENOMEM, "%s picture", name);
	pc_fplane pl = {(float *)map, width, 1};
	rc = pc_picture_grey(&pl, width, height, (float)lo, (float)hi, rgb, (size_t)width * 3);
	size_t hatched = 0;
	if (!rc && marks && marks->hatch_map)
		for (uint32_t y = 0; y < height; y++)
			for (uint32_t x = 0; x < width; x++) {
				float v = marks->hatch_map[(size_t)y * width + x];
				if (v > marks->hatch_above) {
					pc_picture_mask_rgb(x, y,
					                    rgb + ((size_t)y * width + x) * 3);
					hatched++;
				}
			}
	if (!rc && invalid)
		pc_picture_mask_invalid(valid, width, width, height, rgb, (size_t)width * 3);
	if (!rc) {
		snprintf(file, sizeof file, "%s.png", name);
		rc = join(path, sizeof path, dir, file);
		pc_colorbar bar = {label, lo, hi, NULL, 0, 0, pc_picture_grey_key, NULL, 0};
		/* pc_picture_grey draws non-finite values magenta: say what they mean when present
		 */
		size_t undefined = 0;
		for (size_t i = 0; i < (size_t)width * height; i++)
			undefined += !isfinite(map[i]);
		char text[64];
		snprintf(text, sizeof text, "NaN %.2g%%",
		         100.0 * (double)undefined / ((double)width * height));
		char btext[64];
		snprintf(btext, sizeof btext, "invalid %.2g%%",
		         100.0 * (double)invalid / ((double)width * height));
		char htext[96];
		snprintf(htext, sizeof htext, "%s",
		         marks && marks->hatch_text ? marks->hatch_text : "hatched");
		pc_legend_note bad = {btext, pc_picture_invalid_rgb, NULL};
		pc_legend_note hatch = {htext, pc_picture_mask_rgb, invalid ? &bad : NULL};
		const pc_legend_note *after = hatched ? &hatch : invalid ? &bad : NULL;
		pc_legend_note note = {text, magenta, after};
		if (!rc)
			rc = pc_image_write_png_ex(path, rgb, width, height, (size_t)width * 3,
			                           title, &bar, undefined ? &note : after, 1600);
	}
	free(rgb);
	return rc;
}

/* A plane as a contiguous (H, W) array: itself when it is one, else a copy in *tmp. */
static const float *contiguous(const pc_fplane *p, uint32_t w, uint32_t h, float **tmp)
{
	*tmp = NULL;
	if (p->pixel_stride == 1 && p->row_stride == w)
		return p->data;
	float *t = malloc(sizeof(float) * w * h);
	if (!t)
		return NULL;
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++)
			t[(size_t)y * w + x] =
			    p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
	*tmp = t;
	return t;
}

static int write_plane(const char *dir, const char *name, const pc_fplane *p, uint32_t w,
                       uint32_t h)
{
	if (!p->data)
		return pc_error(PC_EINVAL, "%s/%s: no such plane was computed", dir, name);
	float *tmp;
	const float *d = contiguous(p, w, h, &tmp);
	if (!d)
		return pc_error(PC_ENOMEM, "%s/%s", dir, name);
	size_t shape[2] = {h, w};
	int rc = write_npy(dir, name, d, 2, shape);
	free(tmp);
	return rc;
}

/* An .npy file of shape (h, w, ...) (ndim dimensions, the last ones multiplying to nk) holding
 * the nk planes s[] interleaved per pixel, in their order. */
static int write_interleaved(const char *dir, const char *name, const pc_fplane *const *s, int nk,
                             uint32_t w, uint32_t h, unsigned ndim, const size_t *shape)
{
	float *t = malloc(sizeof(float) * w * h * (size_t)nk);
	if (!t)
		return pc_error(PC_ENOMEM, "%s/%s", dir, name);
	for (uint32_t y = 0; y < h; y++)
		for (uint32_t x = 0; x < w; x++)
			for (int k = 0; k < nk; k++)
				t[((size_t)y * w + x) * (size_t)nk + (size_t)k] =
				    s[k]->data[(size_t)y * s[k]->row_stride +
				               (size_t)x * s[k]->pixel_stride];
	int rc = write_npy(dir, name, t, ndim, shape);
	free(t);
	return rc;
}

/* stokes.npy (H, W, 3): directly when s0, s1, s2 already interleave that way. */
static int write_stokes3(const char *dir, const char *name, const pc_stokes_out *st, uint32_t w,
                         uint32_t h)
{
	const pc_fplane *s[3] = {&st->s0, &st->s1, &st->s2};
	bool inter = true;
	for (int k = 0; k < 3; k++) {
		if (!s[k]->data)
			return pc_error(PC_EINVAL, "%s/%s: S0, S1 and S2 are needed", dir, name);
		inter &= s[k]->data == st->s0.data + k && s[k]->pixel_stride == 3 &&
		         s[k]->row_stride == (size_t)w * 3;
	}
	size_t shape[3] = {h, w, 3};
	if (inter)
		return write_npy(dir, name, st->s0.data, 3, shape);
	return write_interleaved(dir, name, s, 3, w, h, 3, shape);
}

/* stokes_rgb.npy (H, W, 3, 3) from the three colours' S0, S1, S2 */
static int write_stokes_rgb(const char *dir, const char *name, const pc_stokes_out *rgb, uint32_t w,
                            uint32_t h)
{
	const pc_fplane *s[9];
	for (int c = 0; c < 3; c++) {
		s[3 * c] = &rgb[c].s0, s[3 * c + 1] = &rgb[c].s1, s[3 * c + 2] = &rgb[c].s2;
		for (int k = 0; k < 3; k++)
			if (!s[3 * c + k]->data)
				return pc_error(PC_EINVAL,
				                "%s/%s: S0, S1 and S2 of each colour are "
				                "needed",
				                dir, name);
	}
	size_t shape[4] = {h, w, 3, 3};
	return write_interleaved(dir, name, s, 9, w, h, 4, shape);
}

/* valid.npy (H, W) uint8: 1 valid, 0 invalid */
static int write_valid(const char *dir, const char *name, const pc_validity *v, uint32_t w,
                       uint32_t h)
{
	char path[4096];
	int rc = join(path, sizeof path, dir, name);
	if (rc)
		return rc;
	size_t shape[2] = {h, w};
	if (v->row_stride == w)
		return pc_npy_write(path, v->mask, PC_DT_U8, 2, shape);
	uint8_t *t = malloc((size_t)w * h);
	if (!t)
		return pc_error(PC_ENOMEM, "%s", path);
	for (uint32_t y = 0; y < h; y++)
		memcpy(t + (size_t)y * w, v->mask + (size_t)y * v->row_stride, w);
	rc = pc_npy_write(path, t, PC_DT_U8, 2, shape);
	free(t);
	return rc;
}

/* imin/imax.npy and diffuse/specular.npy (PC_SF_MINMAX, PC_SF_SPLIT) from the four planes at
 * buf (pc_stokes_minmax's, each w·h) */
static int write_minmax(const char *dir, const float *buf, uint32_t w, uint32_t h, unsigned files,
                        const char *sfx)
{
	static const char *names[4] = {"imin", "imax", "diffuse", "specular"};
	size_t shape[2] = {h, w};
	char name[64];
	int rc = 0;
	for (int k = 0; k < 4 && !rc; k++) {
		if (!(files & (k < 2 ? PC_SF_MINMAX : PC_SF_SPLIT)))
			continue;
		snprintf(name, sizeof name, "%s%s.npy", names[k], sfx);
		rc = write_npy(dir, name, buf + (size_t)k * w * h, 2, shape);
	}
	return rc;
}

int pc_stokes_folder_write(const char *dir, const pc_stokes_out *st, uint32_t width,
                           uint32_t height, const pc_stokes_folder_opts *opts)
{
	return pc_stokes_folder_write_valid(dir, st, width, height, opts, NULL);
}

int pc_stokes_folder_write_valid(const char *dir, const pc_stokes_out *st, uint32_t width,
                                 uint32_t height, const pc_stokes_folder_opts *opts,
                                 const pc_validity *valid)
{
	if (valid && valid->mask && valid->row_stride < width)
		return pc_error(PC_EINVAL,
		                "Stokes folder: validity row stride %zu below the width %u",
		                valid->row_stride, width);
	if (!dir || !st || !opts)
		return pc_error(PC_EINVAL, "Stokes folder: missing argument");
	char sfx[32] = "", name[64];
	if (opts->numbered)
		snprintf(sfx, sizeof sfx, "_%06llu", (unsigned long long)opts->number);
	int rc = pc_mkdir_p(dir);
	if (!rc && (opts->files & PC_SF_STOKES)) {
		snprintf(name, sizeof name, "stokes%s.npy", sfx);
		rc = write_stokes3(dir, name, st, width, height);
	}
	static const struct {
		unsigned flag;
		const char *name;
		size_t plane; /* offset of the pc_fplane in pc_stokes_out */
	} planes[3] = {{PC_SF_S0, "s0", offsetof(pc_stokes_out, s0)},
	               {PC_SF_DOLP, "dolp", offsetof(pc_stokes_out, dolp)},
	               {PC_SF_AOLP, "aolp", offsetof(pc_stokes_out, aolp)}};
	for (int k = 0; k < 3 && !rc; k++)
		if (opts->files & planes[k].flag) {
			snprintf(name, sizeof name, "%s%s.npy", planes[k].name, sfx);
			rc = write_plane(
			    dir, name,
			    (const pc_fplane *)(const void *)((const char *)st + planes[k].plane),
			    width, height);
		}
	if (!rc && opts->colour && (opts->files & PC_SF_STOKES)) {
		snprintf(name, sizeof name, "stokes_rgb%s.npy", sfx);
		rc = write_stokes_rgb(dir, name, opts->colour, width, height);
	}
	/* Imin/Imax once for their .npy files and their pictures */
	const bool mm_files =
	               (opts->files & (PC_SF_MINMAX | PC_SF_SPLIT)) && !opts->no_minmax_files,
	           mm_pics = (opts->files & (PC_SF_MINMAX | PC_SF_SPLIT)) &&
	                     (opts->files & PC_SF_PICTURES);
	float *mm = NULL;
	pc_minmax_out mo = {{NULL, 0, 0}, {NULL, 0, 0}, {NULL, 0, 0}, {NULL, 0, 0}};
	if (!rc && (mm_files || mm_pics)) {
		const size_t n = (size_t)width * height;
		if (!(mm = malloc(sizeof(float) * n * 4)))
			rc = pc_error(PC_ENOMEM, "%s: %ux%u Imin/Imax images", dir, width, height);
		else {
			pc_minmax_out m = {{mm, width, 1},
			                   {mm + n, width, 1},
			                   {mm + 2 * n, width, 1},
			                   {mm + 3 * n, width, 1}};
			mo = m;
			rc = pc_stokes_minmax(&st->s0, &st->s1, &st->s2, width, height, &mo);
		}
	}
	if (!rc && mm_files)
		rc = write_minmax(dir, mm, width, height, opts->files, sfx);
	if (!rc && valid && valid->mask && !opts->no_valid_file) {
		snprintf(name, sizeof name, "valid%s.npy", sfx);
		rc = write_valid(dir, name, valid, width, height);
	}
	if (!rc && (opts->files & PC_SF_PICTURES)) {
		pc_pictures_opts po = opts->pictures;
		if (opts->numbered)
			po.suffix = sfx;
		rc = pc_pictures_write_valid(dir, st, width, height, &po, valid);
		if (!rc && opts->colour)
			rc = pc_pictures_write_colour(dir, opts->colour, width, height, &po, valid);
		if (!rc && mm_pics)
			rc = pc_pictures_write_minmax_planes(dir, st, &mo, width, height, &po,
			                                     valid, opts->files & PC_SF_MINMAX,
			                                     opts->files & PC_SF_SPLIT);
	}
	free(mm);
	return rc;
}

int pc_circular_folder_write(const char *dir, const pc_fplane s[4], uint32_t width, uint32_t height,
                             const pc_pictures_opts *pictures)
{
	if (!dir || !s)
		return pc_error(PC_EINVAL, "circular outputs: missing argument");
	for (int k = 0; k < 4; k++)
		if (!s[k].data || s[k].pixel_stride < 1)
			return pc_error(PC_EINVAL, "circular outputs: S%d missing", k);
	const size_t n = (size_t)width * height;
	float *buf = malloc(sizeof(float) * n * 2);
	if (!buf)
		return pc_error(PC_ENOMEM, "%s: %ux%u DoCP images", dir, width, height);
	float *docp = buf, *ell = buf + n;
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			double S[4];
			for (int k = 0; k < 4; k++)
				S[k] = s[k].data[(size_t)y * s[k].row_stride +
				                 (size_t)x * s[k].pixel_stride];
			const size_t i = (size_t)y * width + x;
			/* DoCP |S3|/S0 (pc_stokes_docp: 0 without light), clipped to 1 as DoLP;
			 * ellipticity angle χ with sin 2χ = S3/√(S1² + S2² + S3²) (the polarized
			 * part's ellipse; Born & Wolf, Principles of Optics, §1.4.2, the Stokes
			 * parameters of an ellipse; S3's sign: physics.md §1) */
			bool finite =
			    isfinite(S[0]) && isfinite(S[1]) && isfinite(S[2]) && isfinite(S[3]);
			docp[i] = finite ? (float)fmin(1, fabs(pc_stokes_docp(S))) : NAN;
			ell[i] = !finite    ? NAN
			         : S[0] > 0 ? (float)(0.5 * atan2(S[3], hypot(S[1], S[2])))
			                    : 0.0f;
		}
	int rc = pc_mkdir_p(dir);
	size_t shape[2] = {height, width};
	if (!rc)
		rc = write_npy(dir, "docp.npy", docp, 2, shape);
	if (!rc)
		rc = write_npy(dir, "ellipticity.npy", ell, 2, shape);
	pc_fplane pd = {docp, width, 1}, pe = {ell, width, 1};
	if (!rc && pictures)
		rc = pc_pictures_write_circular(dir, &s[0], &pd, &pe, width, height, pictures);
	free(buf);
	return rc;
}

static json_t *mueller_json(const pc_mueller_result *res, const pc_mueller_folder_opts *o)
{
	const pc_mueller_system *sys = &res->sys;
	json_t *js = json_object();
	json_object_set_new(js, "frames", json_integer((json_int_t)sys->n_psg * sys->n_psa));
	json_object_set_new(js, "width", json_integer(res->width));
	json_object_set_new(js, "height", json_integer(res->height));
	json_object_set_new(js, "method", json_string(o->method ? o->method : ""));
	json_object_set_new(js, "black_level", json_real(o->black_level));
	json_object_set_new(js, "cond_A", pc_json_real(sys->cond_A));
	json_object_set_new(js, "cond_G", pc_json_real(sys->cond_G));
	json_object_set_new(js, "cond_W", pc_json_real(sys->cond_W));
	json_object_set_new(js, "rank_A", json_integer(sys->rank_A));
	json_object_set_new(js, "rank_G", json_integer(sys->rank_G));
	json_object_set_new(js, "noise_gain", pc_json_matrix4(sys->noise_gain));
	json_object_set_new(js, "pixels_D_singular", json_integer(res->singular));
	json_object_set_new(js, "pixels_nonphysical_filtered", json_integer(res->nonphysical));
	json_object_set_new(js, "pixels_undecomposable", json_integer(res->bad));
	json_object_set_new(js, "determined", json_integer(sys->determined));
	json_object_set_new(js, "saturation_level",
	                    res->saturation_level > 0 ? pc_json_real(res->saturation_level)
	                                              : json_null());
	json_object_set_new(js, "pixels_invalid",
	                    res->valid ? json_integer(res->invalid) : json_null());
	json_object_set_new(
	    js, "rebuild_circular",
	    json_string(res->rebuilt ? pc_rebuild_sign_name(o->rebuild_sign) : "off"));
	if (res->rebuilt) {
		json_object_set_new(js, "rebuild_tol", json_real(o->rebuild_tol));
		json_object_set_new(js, "pixels_rebuild_rejected", json_integer(res->rb_rejected));
		json_object_set_new(js, "pixels_rebuild_sign_undefined",
		                    json_integer(res->rb_sign_undefined));
	}
	return js;
}

static int mueller_folder(const char *dir, const pc_mueller_result *res,
                          const pc_mueller_folder_opts *o, char **json)
{
	const uint32_t w = res->width, h = res->height;
	const size_t np = (size_t)w * h;
	int rc = 0;
	if (!o->no_mueller) {
		size_t shape[4] = {h, w, 4, 4};
		if ((rc = write_npy(dir, "mueller.npy", res->M, 4, shape)))
			return rc;
	}
	pc_map_marks mk = {res->valid, NULL, 0, NULL};
	char htext[64];
	snprintf(htext, sizeof htext, "Delta > %.2g: R undefined", PC_MUELLER_R_MASK_DELTA);
	pc_map_marks mr = {res->valid, res->maps + 2 * np, PC_MUELLER_R_MASK_DELTA, htext};
	if ((rc = pc_map_write_marked(dir, "D", res->maps, w, h, 0, 1,
	                              "Diattenuation D (Lu-Chipman)", "D", &mk)) ||
	    (rc = pc_map_write_marked(dir, "R", res->maps + np, w, h, 0, M_PI,
	                              "Retardance R (Lu-Chipman; hatched where depolarized)",
	                              "R (rad)", &mr)) ||
	    (rc = pc_map_write_marked(dir, "Delta", res->maps + 2 * np, w, h, 0, 1,
	                              "Depolarization Delta (Lu-Chipman)", "Delta", &mk)))
		return rc;
	if (res->valid) {
		char path[4096];
		size_t shape[2] = {h, w};
		if ((rc = join(path, sizeof path, dir, "valid.npy")) ||
		    (rc = pc_npy_write(path, res->valid, PC_DT_U8, 2, shape)))
			return rc;
	}
	if (res->residual &&
	    (rc = pc_map_write(dir, "rebuild_residual", res->residual, w, h, 0, 2 * o->rebuild_tol,
	                       "Residual of the 3x3 fit / M00 (pBRDF family)", "residual")))
		return rc;
	json_t *js = mueller_json(res, o);
	char *txt = json_dumps(js, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	char path[4096];
	if (!txt)
		rc = pc_error(PC_ENOMEM, "mueller.json");
	else if (!(rc = join(path, sizeof path, dir, "mueller.json")))
		rc = pc_write_file_atomic(path, txt, strlen(txt));
	free(txt);
	if (!rc && json && !(*json = pc_json_text(js)))
		rc = pc_error(PC_ENOMEM, "mueller.json");
	json_decref(js);
	return rc;
}

int pc_mueller_folder_write(const char *dir, const pc_mueller_result *res,
                            const pc_mueller_folder_opts *o, char **json)
{
	if (json)
		*json = NULL;
	if (!dir || !res || !o)
		return pc_error(PC_EINVAL, "Mueller folder: missing argument");
	pc_outdir od;
	int rc = pc_outdir_begin(&od, dir, o->overwrite ? PC_OUT_OVERWRITE : 0);
	if (rc)
		return rc;
	rc = mueller_folder(od.tmp, res, o, json);
	if (!rc)
		rc = pc_outdir_commit(&od);
	pc_outdir_abort(&od);
	if (rc && json) {
		free(*json);
		*json = NULL;
	}
	return rc;
}

/* ---- the seed paper's figures ---- */

static int write_csv(const char *dir, const pc_figure *F)
{
	char path[4096];
	snprintf(path, sizeof path, "%s/fig%02d.csv", dir, F->num);
	pc_atomic_file af;
	int rc = pc_atomic_open(&af, path);
	if (rc)
		return rc;
	fprintf(af.fp, "%s", F->xname);
	for (int c = 0; c < F->nc; c++)
		fprintf(af.fp, ",%s %s", F->yname, F->c[c].label);
	for (int c = 0; c < F->nc; c++)
		fprintf(af.fp, ",%s %s (printed 4pi)", F->yname, F->c[c].label);
	fputc('\n', af.fp);
	for (int i = 0; i < F->nx; i++) {
		fprintf(af.fp, "%.10g", F->x[i]);
		for (int c = 0; c < F->nc; c++)
			fprintf(af.fp, ",%.10g", F->c[c].y[i]);
		for (int c = 0; c < F->nc; c++)
			fprintf(af.fp, ",%.10g", F->c[c].yp[i]);
		fputc('\n', af.fp);
	}
	return pc_atomic_commit(&af);
}

static int write_png(const char *dir, const pc_figure *F, bool with_printed)
{
	char path[4096], title[256];
	snprintf(path, sizeof path, "%s/fig%02d.png", dir, F->num);
	snprintf(title, sizeof title, "Fig. %d: %s (corrected model)", F->num, F->title);
	pc_plot *p = pc_plot_new(title, F->xlabel, F->ylabel);
	if (!p)
		return pc_error(PC_ENOMEM, "plot");
	pc_plot_set_xrange(p, F->x[0], F->x[F->nx - 1] > 90 ? 180 : 90);
	int rc = 0;
	for (int c = 0; c < F->nc && !rc; c++)
		rc = pc_plot_add_series(p, F->c[c].label, F->x, F->c[c].y, (size_t)F->nx,
		                        PC_PLOT_LINE);
	for (int c = 0; c < F->nc && with_printed && !rc; c++) {
		char l[96];
		snprintf(l, sizeof l, "%s, printed 4\xcf\x80\xcf\x83\xc2\xb2", F->c[c].label);
		rc = pc_plot_add_series(p, l, F->x, F->c[c].yp, (size_t)F->nx, PC_PLOT_DASHED);
	}
	if (!rc)
		rc = pc_plot_write_png(p, path, 900, 600);
	pc_plot_free(p);
	return rc;
}

static int figures_folder(const char *dir, const pc_figure figs[12], const pc_figure_claim *claims,
                          size_t n_claims, const pc_progress *progress)
{
	int rc = 0;
	for (int f = 2; f <= 11 && !rc; f++) {
		rc = write_csv(dir, &figs[f]);
		if (!rc)
			rc = write_png(dir, &figs[f], f == 2);
		pc_progress_report(progress, "figures", (uint64_t)f, 12);
	}
	if (rc)
		return rc;
	char *md = NULL;
	size_t len = 0;
	FILE *fp = open_memstream(&md, &len);
	if (!fp)
		return pc_error(PC_ENOMEM, "figures.md");
	fprintf(fp,
	        "# The seed paper's claims under the corrected model\n\n"
	        "Generated by `polarcam figures -o DIR` (core/figures.c). Model: "
	        "docs/physics.md (8&pi;&sigma;&sup2;, Torrance–Sparrow G, Fresnel-weighted diffuse "
	        "term, &rho;^s by the 64×64 slope-space rule). \"Printed\" repeats the check with "
	        "the paper's eq. 3 as printed (4&pi;&sigma;&sup2;: specular part doubled, diffuse "
	        "(1 − 2&rho;^s)/&pi;). Black paint ñ = 1.46 − 1.28i, &sigma; = 0.2 unless stated; "
	        "&theta;_r = 15, 30, 45, 60° for Figs. 3–8 (the paper does not give them); angles "
	        "in degrees, R in radians.\n\n"
	        "| Fig. | claim of the paper | corrected model | as printed | numbers "
	        "(corrected) |\n"
	        "|---|---|---|---|---|\n");
	int n_yes = 0, n_no = 0, n_partly = 0;
	for (size_t k = 0; k < n_claims; k++) {
		const pc_figure_claim *c = &claims[k];
		fprintf(fp, "| %d | %s | **%s** | %s | %s |\n", c->figure, c->text,
		        pc_verdict_name(c->corrected), pc_verdict_name(c->printed), c->evidence);
		n_yes += c->corrected == PC_VERDICT_YES;
		n_no += c->corrected == PC_VERDICT_NO;
		n_partly += c->corrected == PC_VERDICT_PARTLY;
	}
	fprintf(fp, "\nCorrected model: %d claims reproduce, %d partly, %d do not.\n", n_yes,
	        n_partly, n_no);
	fclose(fp);
	char path[4096];
	rc = join(path, sizeof path, dir, "figures.md");
	if (!rc)
		rc = pc_write_file_atomic(path, md, len);
	free(md);
	return rc;
}

int pc_figures_write(const char *dir, unsigned flags, const pc_figure figs[12],
                     const pc_figure_claim *claims, size_t n_claims, const pc_progress *progress)
{
	pc_outdir od;
	int rc = pc_outdir_begin(&od, dir, flags);
	if (rc)
		return rc;
	rc = figures_folder(od.tmp, figs, claims, n_claims, progress);
	if (!rc)
		rc = pc_outdir_commit(&od);
	pc_outdir_abort(&od);
	return rc;
}
