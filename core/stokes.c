/* The Stokes front doors (polarcam/stokes.h): raw → Stokes through one validation and the
 * method table's path (fused bilinear, row-cache rows into the Stokes row kernel, or channel
 * images then Stokes), ideal or calibrated analysers, and the validity of every output pixel;
 * Stokes from analyser images; the analyser-matrix pseudo-inverse. Kernels: stokes_kernels.c. */
#include "polarcam/stokes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_plan.h"
#include "polarcam/error.h"
#include "stokes_kernels.h"

float pc_aolp_f(float s1, float s2)
{
	return pc_st_aolp(s1, s2);
}

void pc_stokes_ideal_analyser(double w[4][3])
{
	for (int c = 0; c < 4; c++) {
		double th = M_PI / 4 * c;
		w[c][0] = 0.5;
		w[c][1] = 0.5 * cos(2 * th);
		w[c][2] = 0.5 * sin(2 * th);
	}
	/* exact values where cos/sin round off: 2θ = 90°, 180°, 270° */
	w[1][1] = 0;
	w[2][2] = 0;
	w[3][1] = 0;
}

double pc_mat3_inverse(const double a[3][3], double inv[3][3])
{
	double adj[3][3];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3,
			          j2 = (j + 2) % 3;
			adj[j][i] = a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1];
		}
	const double det = a[0][0] * adj[0][0] + a[0][1] * adj[1][0] + a[0][2] * adj[2][0];
	double n1 = 0, ni = 0;
	for (int j = 0; j < 3; j++) {
		double cs = 0, ci = 0;
		for (int i = 0; i < 3; i++) {
			cs += fabs(a[i][j]);
			ci += fabs(adj[i][j]);
		}
		n1 = cs > n1 ? cs : n1;
		ni = ci > ni ? ci : ni;
	}
	const double rc = fabs(det) / (n1 * ni);
	if (!(fabs(det) > 0) || !isfinite(det) || !isfinite(rc))
		return 0;
	if (inv && rc >= PC_RCOND_MIN)
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				inv[i][j] = adj[i][j] / det;
	return rc;
}

int pc_stokes_pinv1(const double w[4][3], double pinv[3][4])
{
	double a[3][3] = {{0}};
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			for (int c = 0; c < 4; c++)
				a[i][j] += w[c][i] * w[c][j];
	double inv[3][3];
	const double rc = pc_mat3_inverse(a, inv);
	if (rc < PC_RCOND_MIN)
		return pc_error(PC_ENUMERIC,
		                "analyser matrix is (nearly) rank-deficient: W^T W has "
		                "reciprocal condition %.3g",
		                rc);
	for (int i = 0; i < 3; i++)
		for (int c = 0; c < 4; c++) {
			double s = 0;
			for (int k = 0; k < 3; k++)
				s += inv[i][k] * w[c][k];
			pinv[i][c] = s;
		}
	return 0;
}

int pc_stokes_pinv(const float *w, size_t n, float *pinv)
{
	if (!w || !pinv)
		return pc_error(PC_EINVAL, "analyser matrices missing");
	for (size_t k = 0; k < n; k++) {
		double wd[4][3], p[3][4];
		for (int c = 0; c < 4; c++)
			for (int i = 0; i < 3; i++) {
				wd[c][i] = w[12 * k + 3 * c + i];
				if (!isfinite(wd[c][i]))
					return pc_error(PC_ERANGE,
					                "analyser matrix %zu: element (%d,%d) "
					                "is not finite",
					                k, c, i);
			}
		int rc = pc_stokes_pinv1(wd, p);
		if (rc)
			return pc_error_prefix(rc, "analyser matrix %zu: ", k);
		for (int i = 0; i < 3; i++)
			for (int c = 0; c < 4; c++)
				pinv[(size_t)(4 * i + c) * n + k] = (float)p[i][c];
	}
	return 0;
}

static int check_out(const pc_stokes_out *out, uint32_t w)
{
	if (!out)
		return pc_error(PC_EINVAL, "Stokes outputs missing");
	const pc_fplane *p[5] = {&out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp};
	static const char *names[5] = {"S0", "S1", "S2", "DoLP", "AoLP"};
	int n = 0;
	for (int k = 0; k < 5; k++) {
		if (!p[k]->data)
			continue;
		n++;
		if (p[k]->pixel_stride < 1 ||
		    p[k]->row_stride < (size_t)(w - 1) * p[k]->pixel_stride + 1)
			return pc_error(PC_EINVAL,
			                "%s output: strides %zu/%zu too small for width %u",
			                names[k], p[k]->row_stride, p[k]->pixel_stride, w);
	}
	if (!n)
		return pc_error(PC_EINVAL, "no Stokes output requested");
	return 0;
}

static int check_pinv(const pc_analyser_pinv *pinv, uint32_t w, uint32_t h)
{
	if (!pinv->m || pinv->grid_w == 0 || pinv->grid_h == 0)
		return pc_error(PC_EINVAL, "Stokes: analyser pseudo-inverse grid empty");
	if (pinv->grid_w > w || pinv->grid_h > h)
		return pc_error(PC_EINVAL,
		                "Stokes: analyser pseudo-inverse grid %ux%u larger than "
		                "the %ux%u output",
		                pinv->grid_w, pinv->grid_h, w, h);
	return 0;
}

/* A compact calibration (pc_pipeline_opts.compact): the raw's size, the fused bilinear fast
 * path, finite parameters, its dark map or opts', not both. */
static int check_compact(const pc_dm_plan *p, const pc_compact_calib *v)
{
	if (p->opts.pinv)
		return pc_error(PC_EINVAL, "Stokes: a compact calibration and analyser "
		                           "pseudo-inverses given together; give one");
	if (v->stride < v->width)
		return pc_error(PC_EINVAL,
		                "Stokes: compact calibration: row stride %zu below the "
		                "width %u",
		                v->stride, v->width);
	if (v->width != p->raw->width || v->height != p->raw->height)
		return pc_error(PC_EINVAL, "Stokes: compact calibration %ux%u for a %ux%u raw",
		                v->width, v->height, p->raw->width, p->raw->height);
	if (!p->def->fused_bilinear || p->colour || p->opts.reference)
		return pc_error(PC_ENOTSUP,
		                "Stokes: a compact calibration needs the fused bilinear fast path "
		                "(method bilinear, monochrome mosaic, not the reference)");
	if (pc_compact_corrects(v) &&
	    (p->opts.dark || p->opts.gain_inv || p->opts.black_level != 0))
		return pc_error(PC_EINVAL,
		                "Stokes: the compact calibration has a dark level or dark "
		                "or gain maps, and the options a black level, dark or "
		                "gain maps; give one or the other");
	bool ok = isfinite(v->dark_base) && isfinite(v->dark_scale) && isfinite(v->gain_base) &&
	          isfinite(v->gain_scale);
	for (int k = 0; k < 2; k++) {
		ok = ok && isfinite(v->v_scale[k]);
		for (int c = 0; c < 4; c++)
			ok = ok && isfinite(v->v_base[c][k]);
	}
	if (!ok)
		return pc_error(PC_EINVAL, "Stokes: compact calibration: a base or scale is not "
		                           "finite");
	/* without gain_q no gain is applied: a gain_base there would be ignored silently */
	if ((!v->gain_q && (v->gain_base != 0 || v->gain_scale != 0)) ||
	    (!v->dark_q && v->dark_scale != 0))
		return pc_error(PC_EINVAL,
		                "Stokes: compact calibration: gain_base/gain_scale without gain_q "
		                "(or dark_scale without dark_q); a constant inverse gain needs a "
		                "gain map of zeros (gain_q) with gain_scale 0");
	return pc_dm_check_distrust(v, v->width, v->height);
}

/* Stokes from channel images: the vectorised planar kernel where it applies, else the scalar
 * one. */
static void stokes_channels(const pc_fplane in[4], uint32_t w, uint32_t h,
                            const pc_analyser_pinv *pinv, int threads, pc_cpu_level level,
                            bool reference, const pc_stokes_out *out)
{
	pc_st_calib cal;
	if (pinv)
		pc_st_calib_init(pinv, w, h, &cal);
	if (!reference && pc_st_planar(in, w, h, pinv ? &cal : NULL, threads, level, out) == 0)
		return;
	pc_st_generic(in, w, h, pinv ? &cal : NULL, threads, out);
}

int pc_stokes_from_channels(const pc_fplane in[4], uint32_t width, uint32_t height,
                            const pc_analyser_pinv *pinv, const pc_stokes_out *out)
{
	if (!in || width == 0 || height == 0)
		return pc_error(PC_EINVAL, "Stokes: no input or empty size %ux%u", width, height);
	for (int c = 0; c < 4; c++)
		if (!in[c].data || in[c].pixel_stride < 1)
			return pc_error(PC_EINVAL, "Stokes: analyser image %d missing", c);
	int rc = check_out(out, width);
	if (!rc && pinv)
		rc = check_pinv(pinv, width, height);
	if (rc)
		return rc;
	stokes_channels(in, width, height, pinv, 0, pc_cpu_active(), false, out);
	return 0;
}

/* Demosaic into channel images, then Stokes (colour: the colour average of each analyser; with
 * rgb, first each colour's own Stokes from its four analyser images). */
static int stokes_two_step(pc_dm_plan *p, const pc_stokes_out *out, const pc_stokes_out *rgb)
{
	const uint32_t ow = p->ow, oh = p->oh;
	const unsigned nch = p->nch;
	const size_t plane = (size_t)ow * oh;
	float *buf = pc_dm_alloc(plane * nch * sizeof(float));
	if (!buf)
		return pc_error(PC_ENOMEM, "Stokes: %u channel images of %ux%u", nch, ow, oh);
	pc_fplane ch[PC_DEMOSAIC_MAX_CHANNELS];
	pc_dm_planes_separate(buf, ow, oh, nch, ch);
	int rc = pc_dm_plan_demosaic(p, ch);
	for (unsigned c = 0; !rc && rgb && c < 3; c++)
		stokes_channels(&ch[4 * c], ow, oh, NULL, p->opts.threads, p->level, false,
		                &rgb[c]);
	if (!rc && nch == 12) {
		/* colour: the colour average of each analyser image, in place in planes 0..3 */
		for (unsigned c = 0; c < 4; c++)
			for (size_t i = 0; i < plane; i++)
				ch[c].data[i] =
				    (ch[c].data[i] + ch[4 + c].data[i] + ch[8 + c].data[i]) / 3.0f;
	}
	if (!rc)
		stokes_channels(ch, ow, oh, p->opts.pinv, p->opts.threads, p->level, false, out);
	pc_dm_free(buf);
	return rc;
}

/* pc_stokes_run, and with rgb (colour mosaics, ideal analysers) each colour's Stokes too. */
static int stokes_run(const pc_view *raw, const pc_pipeline_opts *opts, const pc_stokes_out *out,
                      const pc_stokes_out *rgb, pc_validity *valid)
{
	pc_dm_plan p;
	int rc = pc_dm_plan_begin(raw, opts, &p);
	if (rc)
		return rc;
	if (rgb && (!p.colour || opts->pinv || opts->compact))
		rc = pc_error(PC_EINVAL, "colour Stokes: %s",
		              p.colour ? "ideal analysers only"
		                       : "the mosaic is not colour-polarization");
	for (int c = 0; c < 3 && rgb && !rc; c++)
		rc = check_out(&rgb[c], p.ow);
	if (rc || (rc = check_out(out, p.ow)) || (rc = pc_dm_plan_check_validity(&p, valid)) ||
	    (opts->pinv && (rc = check_pinv(opts->pinv, p.ow, p.oh))) ||
	    (opts->compact && (rc = check_compact(&p, opts->compact)))) {
		pc_dm_plan_end(&p);
		return rc;
	}
	pc_st_calib cal, *calp = NULL;
	if (opts->pinv) {
		pc_st_calib_init(opts->pinv, p.ow, p.oh, &cal);
		calp = &cal;
	}
	/* the path: fused where the method, the outputs and the grid allow */
	const bool fast = !p.colour && !opts->reference && (!calp || cal.xkind != PC_ST_X_OTHER);
	const pc_dm_input *in = NULL;
	if (fast && (p.def->fused_bilinear || (p.def->rows && pc_st_planar_out(out))))
		rc = pc_dm_plan_input(&p, &in);
	if (rc) {
		pc_dm_plan_end(&p);
		return rc;
	}
	const bool corrected = opts->dark || opts->gain_inv;
	if (in && p.def->fused_bilinear) {
		/* one pass: each raw row corrected (dark, gain) as it is read into the ring */
		pc_dm_input ci = *in;
		pc_dm_input_dark(&ci, opts);
		rc = pc_st_fused_bilinear(&ci, &opts->mosaic, calp, opts->compact, opts->threads,
		                          p.level, out);
	} else if (corrected) {
		/* the other paths: a corrected float copy through the same front door */
		float *img;
		pc_view v;
		pc_pipeline_opts o;
		if (!(rc = pc_dm_plan_corrected(&p, &img, &v, &o)))
			rc = stokes_run(&v, &o, out, rgb, NULL);
		free(img);
	} else if (in) {
		pc_st_sink sink = {out, calp, p.ow, pc_st_stream_wanted(out, p.ow, p.oh, p.level),
		                   p.level};
		pc_dm_row_sink rs = {pc_st_sink_row, &sink};
		rc = pc_dm_plan_noise(&p, NULL);
		if (!rc) {
			pc_dm_call c = pc_dm_plan_call(&p);
			rc = p.def->rows(&c, &rs);
		}
		if (!rc)
			pc_dm_plan_noise_report(&p);
	} else {
		rc = stokes_two_step(&p, out, rgb);
	}
	if (!rc && valid)
		rc = pc_dm_plan_validity(&p, valid);
	pc_dm_plan_end(&p);
	return rc;
}

int pc_stokes_run(const pc_view *raw, const pc_pipeline_opts *opts, const pc_stokes_out *out,
                  pc_validity *valid)
{
	return stokes_run(raw, opts, out, NULL, valid);
}

int pc_stokes_run_colour(const pc_view *raw, const pc_pipeline_opts *opts, const pc_stokes_out *out,
                         const pc_stokes_out rgb[3], pc_validity *valid)
{
	if (!rgb)
		return pc_error(PC_EINVAL, "colour Stokes: missing argument");
	return stokes_run(raw, opts, out, rgb, valid);
}

int pc_stokes_from_raw(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
                       const pc_demosaic_opts *opts, const pc_stokes_out *out)
{
	if (!m)
		return pc_mosaic_check(m); /* "mosaic missing" */
	pc_pipeline_opts o = pc_dm_opts_legacy(m, method, opts);
	return pc_stokes_run(raw, &o, out, NULL);
}

bool pc_stokes_streams(const pc_stokes_out *out, uint32_t width, uint32_t height)
{
	return out && pc_st_stream_wanted(out, width, height, pc_cpu_active());
}
