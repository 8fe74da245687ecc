/* The frozen demosaicking evaluation protocol (polarcam/eval.h). All metrics in double. */
#include "polarcam/eval.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/optics.h"

static const char *ch_name[4] = {"0 deg", "45 deg", "90 deg", "135 deg"};

void pc_eval_truth_free(pc_eval_truth *t)
{
	if (!t)
		return;
	for (int c = 0; c < 4; c++) {
		free(t->ch[c]);
		t->ch[c] = NULL;
	}
}

int pc_eval_truth_from_views(const pc_view views[4], pc_eval_truth *t)
{
	memset(t, 0, sizeof *t);
	for (int c = 0; c < 4; c++) {
		int rc = pc_view_check(&views[c]);
		if (rc)
			return pc_error_prefix(rc, "%s image: ", ch_name[c]);
		if (views[c].width != views[0].width || views[c].height != views[0].height)
			return pc_error(PC_EINVAL,
			                "%s image is %ux%u, the 0 deg image %ux%u: the four "
			                "analyser images must have one size",
			                ch_name[c], views[c].width, views[c].height, views[0].width,
			                views[0].height);
	}
	const pc_format_info *f0 = pc_format_info_get(views[0].format);
	for (int c = 1; c < 4; c++) {
		const pc_format_info *fc = pc_format_info_get(views[c].format);
		if ((fc->bits <= 8) != (f0->bits <= 8) || fc->is_float != f0->is_float)
			return pc_error(PC_EINVAL,
			                "%s image is %s, the 0 deg image %s: the four analyser "
			                "images must share one container",
			                ch_name[c], fc->name, f0->name);
	}
	/* step 1: the container's full scale, not the significant bits */
	t->full_scale = f0->is_float ? 1.0 : f0->bits <= 8 ? 255.0 : 65535.0;
	t->format = f0->is_float ? PC_FMT_FLOAT32 : f0->bits <= 8 ? PC_FMT_MONO8 : PC_FMT_MONO16;
	/* step 2: even size */
	t->width = views[0].width & ~1u;
	t->height = views[0].height & ~1u;
	if (t->width < 2 * PC_EVAL_BORDER + 2 || t->height < 2 * PC_EVAL_BORDER + 2)
		return pc_error(PC_EINVAL,
		                "analyser images of %ux%u: at least %ux%u are needed (the "
		                "protocol excludes a %d-pixel border)",
		                views[0].width, views[0].height, 2 * PC_EVAL_BORDER + 2,
		                2 * PC_EVAL_BORDER + 2, PC_EVAL_BORDER);
	size_t n = (size_t)t->width * t->height;
	float *row = malloc(sizeof(float) * views[0].width);
	if (!row)
		return pc_error(PC_ENOMEM, "evaluation truth");
	for (int c = 0; c < 4; c++) {
		t->ch[c] = malloc(sizeof(double) * n);
		if (!t->ch[c]) {
			free(row);
			pc_eval_truth_free(t);
			return pc_error(PC_ENOMEM, "evaluation truth of %ux%u", t->width,
			                t->height);
		}
		for (uint32_t y = 0; y < t->height; y++) {
			pc_view r = views[c];
			r.data = PC_ROW(&views[c], uint8_t, y);
			r.height = 1;
			int rc = pc_view_to_f32(&r, row, sizeof(float) * views[c].width);
			if (rc) {
				free(row);
				pc_eval_truth_free(t);
				return pc_error_prefix(rc, "%s image, row %u: ", ch_name[c], y);
			}
			for (uint32_t x = 0; x < t->width; x++)
				t->ch[c][(size_t)y * t->width + x] = row[x] / t->full_scale;
		}
	}
	free(row);
	return 0;
}

int pc_eval_mosaic(const pc_eval_truth *t, const pc_mosaic *m, pc_view *raw)
{
	int rc = pc_view_alloc(raw, t->format, t->width, t->height, 0);
	if (rc)
		return rc;
	for (uint32_t y = 0; y < t->height; y++)
		for (uint32_t x = 0; x < t->width; x++) {
			double v = t->ch[pc_mosaic_channel(m, x, y)][(size_t)y * t->width + x] *
			           t->full_scale;
			if (t->format == PC_FMT_MONO8)
				PC_ROW(raw, uint8_t, y)[x] = (uint8_t)lround(v);
			else if (t->format == PC_FMT_MONO16)
				PC_ROW(raw, uint16_t, y)[x] = (uint16_t)lround(v);
			else
				PC_ROW(raw, float, y)[x] = (float)v;
		}
	return 0;
}

static double psnr(double sse, double n)
{
	return sse > 0 ? 10 * log10(n / sse) : INFINITY;
}

static void stokes(const double I[4], double s[5])
{
	s[0] = (I[0] + I[1] + I[2] + I[3]) / 2;
	s[1] = I[0] - I[2];
	s[2] = I[1] - I[3];
	double n = sqrt(s[1] * s[1] + s[2] * s[2]);
	double d = s[0] > 0 ? n / s[0] : 0;
	s[3] = d < 0 ? 0 : d > 1 ? 1 : d;
	s[4] = 0.5 * atan2(s[2], s[1]);
}

int pc_eval_score(const pc_eval_truth *t, const pc_fplane est[4], double est_scale,
                  pc_eval_metrics *out)
{
	memset(out, 0, sizeof *out);
	if (!(est_scale > 0))
		return pc_error(PC_EINVAL, "evaluation: estimate scale %g must be > 0", est_scale);
	const uint32_t b = PC_EVAL_BORDER;
	if (t->width <= 2 * b || t->height <= 2 * b)
		return pc_error(PC_EINVAL, "evaluation: image %ux%u smaller than its border",
		                t->width, t->height);
	double sse_i[4] = {0}, sse_s[3] = {0}, sse_d = 0, a2 = 0, wa2 = 0, wsum = 0;
	double n = 0;
	for (uint32_t y = b; y < t->height - b; y++)
		for (uint32_t x = b; x < t->width - b; x++) {
			size_t i = (size_t)y * t->width + x;
			double It[4], Ie[4], st[5], se[5];
			for (int c = 0; c < 4; c++) {
				It[c] = t->ch[c][i];
				Ie[c] = est[c].data[(size_t)y * est[c].row_stride +
				                    (size_t)x * est[c].pixel_stride] /
				        est_scale;
				sse_i[c] += (Ie[c] - It[c]) * (Ie[c] - It[c]);
			}
			stokes(It, st);
			stokes(Ie, se);
			/* S0/2, (S1+1)/2, (S2+1)/2: differences are halves of the Stokes
			 * differences */
			for (int k = 0; k < 3; k++)
				sse_s[k] += 0.25 * (se[k] - st[k]) * (se[k] - st[k]);
			sse_d += (se[3] - st[3]) * (se[3] - st[3]);
			double d = fabs(se[4] - st[4]) * 180 / M_PI; /* in [0°, 180°] */
			d = fmod(d, 180.0);
			if (d > 90)
				d = 180 - d;
			a2 += d * d;
			wa2 += st[3] * d * d;
			wsum += st[3];
			n++;
		}
	double mi = 0;
	for (int c = 0; c < 4; c++) {
		out->psnr_i_ch[c] = psnr(sse_i[c], n);
		mi += out->psnr_i_ch[c];
	}
	out->psnr_i = mi / 4;
	out->psnr_s0 = psnr(sse_s[0], n);
	out->psnr_s1 = psnr(sse_s[1], n);
	out->psnr_s2 = psnr(sse_s[2], n);
	out->psnr_dolp = psnr(sse_d, n);
	out->aolp_rmse_deg = sqrt(a2 / n);
	out->aolp_wrmse_deg = wsum > 0 ? sqrt(wa2 / wsum) : 0;
	return 0;
}

int pc_eval_method_raw(const pc_eval_truth *t, const pc_view *raw, const pc_mosaic *m,
                       pc_demosaic_method method, const pc_demosaic_opts *opts,
                       pc_eval_metrics *out)
{
	if (raw->width != t->width || raw->height != t->height)
		return pc_error(PC_EINVAL, "evaluation: raw %ux%u, truth %ux%u: sizes differ",
		                raw->width, raw->height, t->width, t->height);
	uint32_t ow, oh;
	pc_demosaic_out_size(method, t->width, t->height, &ow, &oh);
	float *buf = malloc(sizeof(float) * ow * oh * 4);
	float *full = NULL;
	if (!buf)
		return pc_error(PC_ENOMEM, "evaluation: demosaicked images");
	pc_fplane est[4];
	pc_fplanes_separate(buf, ow, oh, 4, est);
	pc_demosaic_opts o = opts ? *opts : (pc_demosaic_opts){0, false, 0};
	if (!(o.full_scale > 0))
		o.full_scale = t->full_scale;
	int rc = pc_demosaic(raw, m, method, &o, est);
	if (!rc && (ow != t->width || oh != t->height)) {
		/* half resolution: replicate each super-pixel over its 2×2 block */
		full = malloc(sizeof(float) * t->width * t->height * 4);
		if (!full) {
			rc = pc_error(PC_ENOMEM, "evaluation: replicated images");
		} else {
			pc_fplane rep[4];
			pc_fplanes_separate(full, t->width, t->height, 4, rep);
			for (int c = 0; c < 4; c++)
				for (uint32_t y = 0; y < t->height; y++)
					for (uint32_t x = 0; x < t->width; x++)
						rep[c].data[(size_t)y * t->width + x] =
						    est[c].data[(size_t)(y / 2) * ow + x / 2];
			memcpy(est, rep, sizeof rep);
		}
	}
	if (!rc)
		rc = pc_eval_score(t, est, t->full_scale, out);
	free(full);
	free(buf);
	return rc;
}

int pc_eval_method_raw_colour(const pc_eval_truth t[3], const pc_view *raw, const pc_mosaic *m,
                              pc_demosaic_method method, const pc_demosaic_opts *opts,
                              pc_eval_metrics *out)
{
	memset(out, 0, sizeof *out);
	for (int k = 0; k < 3; k++) {
		if (raw->width != t[k].width || raw->height != t[k].height)
			return pc_error(
			    PC_EINVAL,
			    "evaluation: raw %ux%u, colour %d's truth %ux%u: sizes differ",
			    raw->width, raw->height, k, t[k].width, t[k].height);
		if (t[k].full_scale != t[0].full_scale)
			return pc_error(PC_EINVAL,
			                "evaluation: colour %d's truth has full scale %g, colour "
			                "0's %g: expected one full scale",
			                k, t[k].full_scale, t[0].full_scale);
	}
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(method);
	if (!mi)
		return pc_error(PC_EINVAL, "evaluation: method %d: unknown", (int)method);
	if (!(mi->flags & PC_DMF_COLOR))
		return pc_error(PC_EINVAL,
		                "evaluation: %s is not a colour-polarization method (the "
		                "colour scores need the twelve colour planes)",
		                mi->name);
	const uint32_t w = raw->width, h = raw->height;
	float *buf = malloc(sizeof(float) * (size_t)w * h * 12);
	if (!buf)
		return pc_error(PC_ENOMEM, "evaluation: colour planes of %ux%u", w, h);
	pc_fplane est[12];
	pc_fplanes_separate(buf, w, h, 12, est);
	pc_demosaic_opts o = opts ? *opts : (pc_demosaic_opts){0, false, 0};
	if (!(o.full_scale > 0))
		o.full_scale = t[0].full_scale;
	int rc = pc_demosaic(raw, m, method, &o, est);
	/* scored on the truths' full scale, as pc_eval_method_raw */
	for (int k = 0; k < 3 && !rc; k++) {
		pc_eval_metrics mk;
		rc = pc_eval_score(&t[k], &est[4 * k], t[k].full_scale, &mk);
		for (size_t q = 0; !rc && q < sizeof mk / sizeof(double); q++)
			(&out->psnr_i)[q] += (&mk.psnr_i)[q] / 3;
	}
	if (rc)
		memset(out, 0, sizeof *out);
	free(buf);
	return rc;
}

int pc_eval_method(const pc_eval_truth *t, pc_demosaic_method method, const pc_demosaic_opts *opts,
                   pc_eval_metrics *out)
{
	pc_mosaic m = pc_mosaic_imx250mzr();
	pc_view raw;
	int rc = pc_eval_mosaic(t, &m, &raw);
	if (rc)
		return rc;
	rc = pc_eval_method_raw(t, &raw, &m, method, opts, out);
	pc_view_free(&raw);
	return rc;
}

/* ---- Stokes estimates against the simulator's ground truth ---- */

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

static double median(double *v, size_t n)
{
	if (!n)
		return NAN;
	qsort(v, n, sizeof *v, cmp_d);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* ---- the truth's shared pixel-level pattern (polarcam/eval.h) ---- */

/* the correlation of a and b over n pairs (NaN without variation) */
static double correlation(const double *a, const double *b, size_t n)
{
	double sa = 0, sb = 0;
	for (size_t i = 0; i < n; i++) {
		sa += a[i];
		sb += b[i];
	}
	const double ma = sa / (double)n, mb = sb / (double)n;
	double saa = 0, sbb = 0, sab = 0;
	for (size_t i = 0; i < n; i++) {
		const double x = a[i] - ma, y = b[i] - mb;
		saa += x * x;
		sbb += y * y;
		sab += x * y;
	}
	/* variation below 1e-9 of full scale (RMS) is the rounding of a smooth image's mean */
	const double floor = (double)n * 1e-18;
	return saa > floor && sbb > floor ? sab / sqrt(saa * sbb) : NAN;
}

int pc_eval_truth_pattern(const pc_eval_truth *t, pc_eval_pattern *out)
{
	out->corr = out->corr_shift = out->std = NAN;
	out->pixels = 0;
	const uint32_t w = t->width, h = t->height, b = PC_EVAL_BORDER;
	if (w < 2 * b + 4 || h < 2 * b + 4)
		return 0; /* nothing inside the border to measure: NaN */
	/* the candidates p: inside the border, one column short for the pair (p, p + (1, 0)) */
	const uint32_t x0 = b, x1 = w - b - 1, y0 = b, y1 = h - b, cw = x1 - x0;
	const size_t nc = (size_t)cw * (y1 - y0), np = (size_t)w * h;
	/* the mean image, each image's high-pass (made once, read at p and p + (1, 0)), the
	 * candidates' gradients (and a sorted copy), the selected pairs' high-pass values */
	double *mean = malloc(np * sizeof *mean), *hp = malloc(4 * np * sizeof *hp);
	double *grad = malloc(2 * nc * sizeof *grad), *e = NULL;
	if (!mean || !hp || !grad) {
		free(mean);
		free(hp);
		free(grad);
		return pc_error(PC_ENOMEM, "truth pattern (%zu pixels)", nc);
	}
	double *sorted = grad + nc;
	for (size_t i = 0; i < np; i++)
		mean[i] = (t->ch[0][i] + t->ch[1][i] + t->ch[2][i] + t->ch[3][i]) / 4;
	for (int c = 0; c < 4; c++)
		for (uint32_t y = y0; y < y1; y++)
			for (uint32_t x = x0; x <= x1; x++) {
				const double *im = t->ch[c];
				double m = 0;
				for (int dy = -1; dy <= 1; dy++)
					for (int dx = -1; dx <= 1; dx++)
						m += im[(size_t)(y + dy) * w + x + dx];
				hp[c * np + (size_t)y * w + x] = im[(size_t)y * w + x] - m / 9;
			}
	for (uint32_t y = y0; y < y1; y++)
		for (uint32_t x = x0; x < x1; x++) {
			const size_t q = (size_t)y * w + x, k = (size_t)(y - y0) * cw + (x - x0);
			const double gx = (mean[q + 1] - mean[q - 1]) / 2,
			             gy = (mean[q + w] - mean[q - w]) / 2;
			grad[k] = sorted[k] = hypot(gx, gy);
		}
	free(mean);
	mean = NULL;
	qsort(sorted, nc, sizeof *sorted, cmp_d);
	const double cut = sorted[(size_t)(0.3 * (double)(nc - 1))];
	size_t ns = 0; /* the selected pixels (ties at the cut included) */
	for (size_t k = 0; k < nc; k++)
		ns += grad[k] <= cut;
	if (!(e = malloc(8 * (ns ? ns : 1) * sizeof *e))) {
		free(hp);
		free(grad);
		return pc_error(PC_ENOMEM, "truth pattern (%zu pixels)", ns);
	}
	size_t n = 0;
	double ss = 0;
	for (uint32_t y = y0; y < y1; y++)
		for (uint32_t x = x0; x < x1; x++) {
			if (!(grad[(size_t)(y - y0) * cw + (x - x0)] <= cut))
				continue;
			for (int c = 0; c < 4; c++) {
				const double *hc = hp + c * np + (size_t)y * w + x;
				e[(2 * c) * ns + n] = hc[0];
				e[(2 * c + 1) * ns + n] = hc[1];
				ss += hc[0] * hc[0];
			}
			n++;
		}
	double cs = 0, csh = 0;
	for (int c = 0; c < 4; c++)
		for (int d = c + 1; d < 4; d++) {
			cs += correlation(e + (size_t)(2 * c) * ns, e + (size_t)(2 * d) * ns, n);
			csh +=
			    correlation(e + (size_t)(2 * c) * ns, e + (size_t)(2 * d + 1) * ns, n);
		}
	out->corr = cs / 6;
	out->corr_shift = csh / 6;
	out->std = n ? sqrt(ss / (4.0 * (double)n)) : NAN;
	out->pixels = n;
	free(hp);
	free(grad);
	free(e);
	return 0;
}

/* angular difference of two AoLPs in [0, π): in [0, π/2] */
static double aolp_diff(double a, double b)
{
	double d = fabs(a - b);
	return d > M_PI / 2 ? M_PI - d : d;
}

void pc_eval_truth_planes(const float *ts, size_t n, double scale, float *s0, float *dolp,
                          float *aolp)
{
	for (size_t i = 0; i < n; i++) {
		const double S[4] = {ts[4 * i], ts[4 * i + 1], ts[4 * i + 2], 0};
		s0[i] = (float)(S[0] * scale);
		dolp[i] = (float)fmin(1, pc_stokes_dolp(S));
		aolp[i] = (float)pc_stokes_aolp_rad(S);
	}
}

int pc_eval_stokes(const float *s0, const float *dolp, const float *aolp, const float *t_s0,
                   const float *t_dolp, const float *t_aolp, uint32_t W, uint32_t H, double full,
                   pc_eval_stokes_metrics *acc)
{
	memset(acc, 0, sizeof *acc);
	double se = 0, sb = 0, sd = 0, sa = 0, sw = 0;
	long n = 0, na = 0;
	double *ad = malloc(sizeof(double) * (size_t)W * H);
	if (!ad)
		return pc_error(PC_ENOMEM, "scoring %ux%u pixels", W, H);
	for (size_t i = 0; i < (size_t)W * H; i++) {
		double T = t_s0[i], P = t_dolp[i];
		if (!(T > 0.02 * full) || T * (1 + P) / 2 > 0.95 * full)
			continue;
		double r = (s0[i] - T) / T;
		se += r * r;
		sb += dolp[i] - P;
		sd += (dolp[i] - P) * (dolp[i] - P);
		n++;
		if (P > 0.05) {
			double d = aolp_diff(aolp[i], t_aolp[i]);
			sa += P * d;
			sw += P;
			ad[na++] = d;
		}
	}
	acc->pixels = n;
	acc->aolp_pixels = na;
	acc->s0_rel_rms = n ? sqrt(se / n) : NAN;
	acc->dolp_bias = n ? sb / n : NAN;
	acc->dolp_rms = n ? sqrt(sd / n) : NAN;
	acc->aolp_err_deg = sw > 0 ? sa / sw * 180 / M_PI : NAN;
	acc->aolp_median_deg = median(ad, (size_t)na) * 180 / M_PI;
	free(ad);
	return 0;
}

double pc_eval_median_abs_err(const float *est, const float *truth, const float *w, size_t n,
                              double wmin, bool angle_pi, long *used)
{
	double *v = malloc(sizeof(double) * (n ? n : 1));
	size_t k = 0;
	if (!v) {
		if (used)
			*used = 0;
		return NAN;
	}
	for (size_t i = 0; i < n; i++)
		if (w[i] > wmin && isfinite(est[i]) && isfinite(truth[i])) {
			double d = fabs(est[i] - truth[i]);
			if (angle_pi && d > M_PI / 2)
				d = M_PI - d; /* retardance near π: keep the absolute difference */
			v[k++] = d;
		}
	double m = median(v, k);
	free(v);
	if (used)
		*used = (long)k;
	return m;
}
