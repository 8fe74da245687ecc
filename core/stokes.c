/* Stokes images, DoLP and AoLP (formulas and conventions in polarcam/stokes.h). */
#include "polarcam/stokes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "stokes_internal.h"

float pc_aolp_f(float s1, float s2)
{
	float ax = fabsf(s1), ay = fabsf(s2);
	float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
	float t = mx > 0 ? mn / mx : 0.0f;
	float u = t * t;
	float p = PC_ATAN_C7;
	p = p * u + PC_ATAN_C6;
	p = p * u + PC_ATAN_C5;
	p = p * u + PC_ATAN_C4;
	p = p * u + PC_ATAN_C3;
	p = p * u + PC_ATAN_C2;
	p = p * u + PC_ATAN_C1;
	p = p * u + PC_ATAN_C0;
	float r = p * t; /* atan(min/max) in [0, π/4] */
	if (ay > ax)
		r = PC_PI_2F - r;
	if (s1 < 0)
		r = PC_PIF - r;
	if (s2 < 0)
		r = -r;
	float h = 0.5f * r;
	if (h < 0)
		h += PC_PIF;
	if (h >= PC_PIF)
		h -= PC_PIF;
	return h;
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

int pc_stokes_pinv1(const double w[4][3], double pinv[3][4])
{
	double a[3][3] = { { 0 } };
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			for (int c = 0; c < 4; c++)
				a[i][j] += w[c][i] * w[c][j];
	/* inverse by cofactors; the 1-norm condition number guards against rank deficiency */
	double inv[3][3];
	inv[0][0] = a[1][1] * a[2][2] - a[1][2] * a[2][1];
	inv[0][1] = a[0][2] * a[2][1] - a[0][1] * a[2][2];
	inv[0][2] = a[0][1] * a[1][2] - a[0][2] * a[1][1];
	inv[1][0] = a[1][2] * a[2][0] - a[1][0] * a[2][2];
	inv[1][1] = a[0][0] * a[2][2] - a[0][2] * a[2][0];
	inv[1][2] = a[0][2] * a[1][0] - a[0][0] * a[1][2];
	inv[2][0] = a[1][0] * a[2][1] - a[1][1] * a[2][0];
	inv[2][1] = a[0][1] * a[2][0] - a[0][0] * a[2][1];
	inv[2][2] = a[0][0] * a[1][1] - a[0][1] * a[1][0];
	double det = a[0][0] * inv[0][0] + a[0][1] * inv[1][0] + a[0][2] * inv[2][0];
	double n1 = 0, ni = 0;
	for (int j = 0; j < 3; j++) {
		double cs = 0, ci = 0;
		for (int i = 0; i < 3; i++) {
			cs += fabs(a[i][j]);
			ci += fabs(inv[i][j]);
		}
		n1 = cs > n1 ? cs : n1;
		ni = ci > ni ? ci : ni;
	}
	if (!(fabs(det) > 0) || !isfinite(det) || fabs(det) / (n1 * ni) < 1e-10)
		return pc_error(PC_ENUMERIC, "analyser matrix is (nearly) rank-deficient: W^T W has "
					     "reciprocal condition %.3g", det == 0 ? 0.0
									: fabs(det) / (n1 * ni));
	for (int i = 0; i < 3; i++)
		for (int c = 0; c < 4; c++) {
			double s = 0;
			for (int k = 0; k < 3; k++)
				s += inv[i][k] / det * w[c][k];
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
					return pc_error(PC_ERANGE, "analyser matrix %zu: element (%d,%d) "
								   "is not finite", k, c, i);
			}
		int rc = pc_stokes_pinv1(wd, p);
		if (rc)
			return pc_error_prefix(rc, "analyser matrix %zu: ", k);
		for (int i = 0; i < 3; i++)
			for (int c = 0; c < 4; c++)
				pinv[12 * k + 4 * i + c] = (float)p[i][c];
	}
	return 0;
}

/* ---- Stokes from analyser images ---- */
typedef struct st_ch_job {
	const pc_fplane *in;
	uint32_t w, h;
	const pc_analyser_pinv *pinv;
	const pc_stokes_out *out;
} st_ch_job;

static void put(const pc_fplane *p, uint32_t x, uint32_t y, float v)
{
	if (p->data)
		p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride] = v;
}

static void stokes_channels_band(void *ctx, uint32_t y0, uint32_t y1)
{
	const st_ch_job *j = ctx;
	int want_da = j->out->dolp.data || j->out->aolp.data;
	for (uint32_t y = y0; y < y1; y++) {
		const float *row[4];
		for (int c = 0; c < 4; c++)
			row[c] = j->in[c].data + (size_t)y * j->in[c].row_stride;
		const float *pm = NULL;
		uint32_t gy = j->pinv ? (uint32_t)((uint64_t)y * j->pinv->grid_h / j->h) : 0;
		for (uint32_t x = 0; x < j->w; x++) {
			float i0 = row[0][(size_t)x * j->in[0].pixel_stride];
			float i1 = row[1][(size_t)x * j->in[1].pixel_stride];
			float i2 = row[2][(size_t)x * j->in[2].pixel_stride];
			float i3 = row[3][(size_t)x * j->in[3].pixel_stride];
			float s0, s1, s2;
			if (j->pinv) {
				uint32_t gx = (uint32_t)((uint64_t)x * j->pinv->grid_w / j->w);
				pm = j->pinv->m + 12 * ((size_t)gy * j->pinv->grid_w + gx);
				s0 = pm[0] * i0 + pm[1] * i1 + pm[2] * i2 + pm[3] * i3;
				s1 = pm[4] * i0 + pm[5] * i1 + pm[6] * i2 + pm[7] * i3;
				s2 = pm[8] * i0 + pm[9] * i1 + pm[10] * i2 + pm[11] * i3;
			} else {
				s0 = 0.5f * ((i0 + i1) + (i2 + i3));
				s1 = i0 - i2;
				s2 = i1 - i3;
			}
			put(&j->out->s0, x, y, s0);
			put(&j->out->s1, x, y, s1);
			put(&j->out->s2, x, y, s2);
			if (want_da) {
				float d = pc_dolp_f(s0, s1, s2);
				put(&j->out->dolp, x, y, d);
				put(&j->out->aolp, x, y, pc_aolp_f(s1, s2));
			}
		}
	}
}

static int check_out(const pc_stokes_out *out, uint32_t w)
{
	if (!out)
		return pc_error(PC_EINVAL, "Stokes outputs missing");
	const pc_fplane *p[5] = { &out->s0, &out->s1, &out->s2, &out->dolp, &out->aolp };
	static const char *names[5] = { "S0", "S1", "S2", "DoLP", "AoLP" };
	int n = 0;
	for (int k = 0; k < 5; k++) {
		if (!p[k]->data)
			continue;
		n++;
		if (p[k]->pixel_stride < 1 || p[k]->row_stride < (size_t)(w - 1) * p[k]->pixel_stride + 1)
			return pc_error(PC_EINVAL, "%s output: strides %zu/%zu too small for width %u",
					names[k], p[k]->row_stride, p[k]->pixel_stride, w);
	}
	if (!n)
		return pc_error(PC_EINVAL, "no Stokes output requested");
	return 0;
}

int pc_stokes_from_channels(const pc_fplane in[4], uint32_t width, uint32_t height,
			    const pc_analyser_pinv *pinv, const pc_stokes_out *out)
{
	if (!in || width == 0 || height == 0)
		return pc_error(PC_EINVAL, "Stokes: no input or empty size %ux%u", width, height);
	for (int c = 0; c < 4; c++)
		if (!in[c].data || in[c].pixel_stride < 1)
			return pc_error(PC_EINVAL, "Stokes: analyser image %d missing", c);
	if (pinv && (!pinv->m || pinv->grid_w == 0 || pinv->grid_h == 0))
		return pc_error(PC_EINVAL, "Stokes: analyser pseudo-inverse grid empty");
	int rc = check_out(out, width);
	if (rc)
		return rc;
	if (!pinv && pc_stokes_planar_fast(in, width, height, out) == 0)
		return 0;
	st_ch_job j = { in, width, height, pinv, out };
	pc_parallel_rows(height, 0, 0, stokes_channels_band, &j);
	return 0;
}

int pc_stokes_from_raw(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
		       const pc_demosaic_opts *opts, const pc_stokes_out *out)
{
	int rc = pc_view_check(raw);
	if (rc)
		return pc_error_prefix(rc, "raw: ");
	rc = pc_mosaic_check(m);
	if (rc)
		return rc;
	uint32_t ow, oh;
	pc_demosaic_out_size(method, raw->width, raw->height, &ow, &oh);
	rc = check_out(out, ow);
	if (rc)
		return rc;
	int reference = opts && opts->reference;
	if (method == PC_DM_BILINEAR && m->period == 2 && !reference && raw->width % 2 == 0 &&
	    raw->height % 2 == 0 && raw->width >= 4 && raw->height >= 4) {
		pc_dm_input in;
		void *owned;
		rc = pc_dm_prepare_input(raw, &in, &owned);
		if (rc)
			return rc;
		rc = pc_stokes_bilinear_fused(&in, m, opts ? opts->threads : 0, out);
		pc_dm_free(owned);
		return rc;
	}
	if (m->period == 2 && !reference && ow == raw->width && raw->width % 2 == 0 &&
	    raw->height % 2 == 0 && raw->width >= 4 && raw->height >= 4) {
		/* row-cache methods: demosaic rows turned into Stokes rows in cache */
		pc_dm_input in;
		void *owned;
		rc = pc_dm_prepare_input(raw, &in, &owned);
		if (rc)
			return rc;
		rc = pc_stokes_ic_fused(&in, m, method, pc_dm_full_scale(raw, opts),
					opts ? opts->threads : 0, out);
		pc_dm_free(owned);
		if (rc != PC_ENOTSUP)
			return rc;
	}
	unsigned nch = pc_demosaic_channels(m);
	size_t plane = (size_t)ow * oh;
	float *buf = pc_dm_alloc(plane * nch * sizeof(float));
	if (!buf)
		return pc_error(PC_ENOMEM, "Stokes: %u channel images of %ux%u", nch, ow, oh);
	pc_fplane ch[PC_DEMOSAIC_MAX_CHANNELS];
	pc_fplanes_separate(buf, ow, oh, nch, ch);
	rc = pc_demosaic(raw, m, method, opts, ch);
	if (!rc && nch == 12) {
		/* colour: the colour average of each analyser image, in place in planes 0..3 */
		for (unsigned c = 0; c < 4; c++)
			for (size_t i = 0; i < plane; i++)
				ch[c].data[i] = (ch[c].data[i] + ch[4 + c].data[i] + ch[8 + c].data[i]) /
						3.0f;
	}
	if (!rc)
		rc = pc_stokes_from_channels(ch, ow, oh, NULL, out);
	pc_dm_free(buf);
	return rc;
}
