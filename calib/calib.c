/* calib/calib.c - dark, flat and analyser calibration of a DoFP camera and the calibrated
 * pipeline (polarcam/calib.h; docs/calibration.md gives the procedure and the formulas). */
#include "polarcam/calib.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "calib_internal.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

#define DEG (3.14159265358979323846 / 180.0)

void pc_calib_init(pc_calib *cal)
{
	memset(cal, 0, sizeof *cal);
	cal->pinv_method = -1;
	cal->system_gain_db = NAN;
	cal->dark_gain_db = NAN;
}

void pc_calib_free(pc_calib *cal)
{
	free(cal->dark);
	free(cal->dark_noise);
	free(cal->gain);
	free(cal->analysis);
	free(cal->residual);
	free(cal->pinv_sp);
	free(cal->valid);
	free(cal->provenance);
	free(cal->pinv_px);
	free(cal->apply_ig);
	free(cal->apply_q);
	free(cal->apply_dis);
	pc_calib_init(cal);
}

void pc_calib_unprepare(pc_calib *cal)
{
	free(cal->pinv_px);
	cal->pinv_px = NULL;
	cal->pinv_method = -1;
	free(cal->apply_ig);
	cal->apply_ig = NULL;
	free(cal->apply_q);
	cal->apply_q = NULL;
	free(cal->apply_dis);
	cal->apply_dis = NULL;
	memset(&cal->apply_vec, 0, sizeof cal->apply_vec);
}

static int dup_map(void **dst, const void *src, size_t bytes)
{
	*dst = NULL;
	if (!src)
		return 0;
	if (!(*dst = malloc(bytes)))
		return pc_error(PC_ENOMEM, "calibration map (%zu bytes)", bytes);
	memcpy(*dst, src, bytes);
	return 0;
}

int pc_calib_copy(pc_calib *dst, const pc_calib *src)
{
	pc_calib_init(dst);
	pc_calib t = *src;
	t.dark = t.dark_noise = t.gain = t.analysis = t.residual = t.pinv_sp = NULL;
	t.valid = NULL;
	t.provenance = NULL;
	t.pinv_px = NULL;
	t.pinv_method = -1;
	t.apply_ig = NULL;
	t.apply_q = NULL;
	t.apply_dis = NULL;
	memset(&t.apply_vec, 0, sizeof t.apply_vec);
	size_t np = (size_t)src->geo.width * src->geo.height;
	int rc;
	if ((rc = dup_map((void **)&t.dark, src->dark, np * 4)) ||
	    (rc = dup_map((void **)&t.dark_noise, src->dark_noise, np * 4)) ||
	    (rc = dup_map((void **)&t.gain, src->gain, np * 4)) ||
	    (rc = dup_map((void **)&t.analysis, src->analysis, np * 12)) ||
	    (rc = dup_map((void **)&t.residual, src->residual, np * 4)) ||
	    (rc = dup_map((void **)&t.pinv_sp, src->pinv_sp, np / 4 * 48)) ||
	    (rc = dup_map((void **)&t.valid, src->valid, np)) ||
	    (rc = dup_map((void **)&t.provenance, src->provenance,
	                  src->provenance ? strlen(src->provenance) + 1 : 0))) {
		pc_calib_free(&t);
		return rc;
	}
	*dst = t;
	return 0;
}

/* ---- geometry ---- */

static void geo_text(const pc_calib_geometry *g, char *buf, size_t n)
{
	char m[64];
	pc_mosaic_format(&g->mosaic, m, sizeof m);
	snprintf(buf, n, "%ux%u at ROI (%u,%u), %u bits, layout %s", g->width, g->height,
	         g->offset_x, g->offset_y, g->bits, m);
}

int pc_calib_check(const pc_calib *cal, const pc_calib_geometry *g)
{
	const pc_calib_geometry *c = &cal->geo;
	const char *what = NULL;
	if (g->width != c->width || g->height != c->height)
		what = "size differs";
	else if (g->offset_x != c->offset_x || g->offset_y != c->offset_y)
		what = "ROI offset differs";
	else if (!pc_mosaic_equal(&g->mosaic, &c->mosaic))
		what = "mosaic layout differs";
	else if (g->bits && c->bits && g->bits != c->bits)
		what = "bit depth differs";
	else if (g->sensor_width && c->sensor_width &&
	         (g->sensor_width != c->sensor_width || g->sensor_height != c->sensor_height))
		what = "sensor size differs";
	if (!what)
		return 0;
	char a[160], b[160];
	geo_text(g, a, sizeof a);
	geo_text(c, b, sizeof b);
	return pc_error(PC_EINVAL, "frame %s, calibration %s: %s", a, b, what);
}

/* ---- frame stacks: per-pixel mean (and variance) in double ---- */

typedef struct stack_stats {
	double *mean; /* (H, W) */
	double *var;  /* (H, W) sample variance, or NULL */
	uint8_t *sat; /* (H, W) 1 = at or above saturation in some frame */
	size_t n_sat;
} stack_stats;

static void stats_free(stack_stats *s)
{
	free(s->mean);
	free(s->var);
	free(s->sat);
	memset(s, 0, sizeof *s);
}

static double sat_level(const pc_calib_opts *o, unsigned bits)
{
	if (o && o->saturation > 0)
		return o->saturation;
	return (double)((1u << (bits ? bits : 16)) - 1u);
}

/* Mean (Welford: numerically stable variance) over the stack's frames. */
static int stack_read(const pc_calib_stack *s, const pc_calib_geometry *want, bool want_var,
                      double saturation, stack_stats *st, uint64_t *done, uint64_t total,
                      const pc_calib_opts *o)
{
	memset(st, 0, sizeof *st);
	if (s->n == 0)
		return pc_error(PC_EINVAL, "%s: no frames", s->name);
	if (want) {
		int rc = 0;
		pc_calib tmp;
		pc_calib_init(&tmp);
		tmp.geo = *want;
		if ((rc = pc_calib_check(&tmp, &s->geo)))
			return pc_error_prefix(rc, "%s: ", s->name);
	}
	const uint32_t W = s->geo.width, H = s->geo.height;
	const size_t np = (size_t)W * H;
	st->mean = calloc(np, sizeof *st->mean);
	st->var = want_var ? calloc(np, sizeof *st->var) : NULL;
	st->sat = calloc(np, 1);
	float *row = malloc(np * sizeof *row);
	if (!st->mean || (want_var && !st->var) || !st->sat || !row) {
		free(row);
		stats_free(st);
		return pc_error(PC_ENOMEM, "%s: %zu pixels", s->name, np);
	}
	for (size_t i = 0; i < s->n; i++) {
		pc_view v = {0};
		int rc = s->get(s->user, i, &v);
		if (rc) {
			free(row);
			stats_free(st);
			return pc_error_prefix(rc, "%s: frame %zu: ", s->name, i);
		}
		if (v.width != W || v.height != H) {
			pc_view_free(&v);
			free(row);
			stats_free(st);
			return pc_error(PC_EINVAL,
			                "%s: frame %zu is %ux%u, the recording says %ux%u", s->name,
			                i, v.width, v.height, W, H);
		}
		rc = pc_view_to_f32(&v, row, (size_t)W * sizeof(float));
		pc_view_free(&v);
		if (rc) {
			free(row);
			stats_free(st);
			return pc_error_prefix(rc, "%s: frame %zu: ", s->name, i);
		}
		const double k = (double)(i + 1);
		for (size_t p = 0; p < np; p++) {
			double x = row[p];
			if (x >= saturation)
				st->sat[p] = 1;
			double d = x - st->mean[p];
			st->mean[p] += d / k;
			if (want_var)
				st->var[p] += d * (x - st->mean[p]);
		}
		if (done) {
			(*done)++;
			if (o && o->progress)
				o->progress(o->progress_user, *done, total);
		}
	}
	free(row);
	if (want_var)
		for (size_t p = 0; p < np; p++)
			st->var[p] = s->n > 1 ? st->var[p] / (double)(s->n - 1) : 0;
	for (size_t p = 0; p < np; p++)
		st->n_sat += st->sat[p];
	return 0;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* Median and the robust σ (1.4826·MAD, Rousseeuw & Croux, JASA 88(424) 1273, 1993). */
static int robust_stats(const double *v, size_t n, double *median, double *sigma)
{
	double *t = malloc(n * sizeof *t);
	if (!t)
		return pc_error(PC_ENOMEM, "robust statistics");
	memcpy(t, v, n * sizeof *t);
	qsort(t, n, sizeof *t, cmp_double);
	*median = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
	for (size_t i = 0; i < n; i++)
		t[i] = fabs(t[i] - *median);
	qsort(t, n, sizeof *t, cmp_double);
	double mad = n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
	*sigma = 1.4826 * mad;
	free(t);
	return 0;
}

static int start_from(pc_calib *out, const pc_calib *base, const pc_calib_geometry *g)
{
	int rc = 0;
	if (base) {
		if ((rc = pc_calib_copy(out, base)))
			return rc;
	} else {
		pc_calib_init(out);
		out->geo = *g;
		out->saturation = (double)((1u << (g->bits ? g->bits : 16)) - 1u);
	}
	size_t np = (size_t)out->geo.width * out->geo.height;
	if (!out->valid) {
		if (!(out->valid = malloc(np)))
			return pc_error(PC_ENOMEM, "validity map");
		memset(out->valid, 1, np);
	}
	return 0;
}

static int check_mono(const pc_calib_geometry *g, const char *name)
{
	if (g->mosaic.period != 2)
		return pc_error(PC_ENOTSUP,
		                "%s: colour-polarization mosaics are not calibrated yet "
		                "(monochrome 2x2 mosaics only)",
		                name);
	if (g->width < 4 || g->height < 4 || g->width % 2 || g->height % 2)
		return pc_error(PC_EINVAL,
		                "%s: %ux%u: calibration needs even sizes of at least 4x4", name,
		                g->width, g->height);
	return 0;
}

/* ---- dark ---- */

int pc_calib_dark(const pc_calib_stack *s, const pc_calib_opts *o, pc_calib *out)
{
	pc_calib_init(out);
	int rc;
	if (s->n < 2)
		return pc_error(PC_EINVAL,
		                "%s: %zu dark frame%s: at least 2 are needed for the temporal "
		                "noise",
		                s->name, s->n, s->n == 1 ? "" : "s");
	if ((rc = check_mono(&s->geo, s->name)))
		return rc;
	stack_stats st;
	uint64_t done = 0;
	double sat = sat_level(o, s->geo.bits);
	if ((rc = stack_read(s, NULL, true, sat, &st, &done, s->n, o)))
		return rc;
	const size_t np = (size_t)s->geo.width * s->geo.height;
	if (st.n_sat * 10 > np) {
		rc = pc_error(PC_EINVAL,
		              "%s: %zu of %zu pixels saturated: not dark frames (lens cap on?)",
		              s->name, st.n_sat, np);
		stats_free(&st);
		return rc;
	}
	if ((rc = start_from(out, NULL, &s->geo))) {
		stats_free(&st);
		return rc;
	}
	out->saturation = sat;
	out->dark = malloc(np * sizeof(float));
	out->dark_noise = malloc(np * sizeof(float));
	double med = 0, sig = 0;
	if (!out->dark || !out->dark_noise) {
		rc = pc_error(PC_ENOMEM, "dark maps");
		goto fail;
	}
	if ((rc = robust_stats(st.mean, np, &med, &sig)))
		goto fail;
	/* a pixel's offset is known to σ_t/sqrt(N); hot pixels lie beyond 8 robust σ of the
	 * offset distribution plus that uncertainty */
	double sum = 0;
	size_t nvalid = 0;
	for (size_t p = 0; p < np; p++) {
		out->dark[p] = (float)st.mean[p];
		out->dark_noise[p] = (float)sqrt(st.var[p]);
		double lim = 8 * sqrt(sig * sig + st.var[p] / (double)s->n) + 0.5;
		if (st.sat[p] || fabs(st.mean[p] - med) > lim)
			out->valid[p] = 0;
		else {
			sum += st.mean[p];
			nvalid++;
		}
	}
	out->black_level = nvalid ? sum / (double)nvalid : med;
	out->dark_gain_db = s->gain_db;
	out->parts = PC_CAL_DARK;
	stats_free(&st);
	return 0;
fail:
	stats_free(&st);
	pc_calib_free(out);
	return rc;
}

int pc_calib_base_dark_scale(const pc_calib *base, double gain_db, const char *what, double *r)
{
	*r = base ? pc_calib_dark_scale(base, gain_db, NULL) : 1;
	if (!(*r > 0 && *r < INFINITY))
		return pc_error(PC_EINVAL,
		                "%s at %g dB of analog gain and dark frames at %g dB: the dark map "
		                "cannot be scaled to them (factor %g)",
		                what, gain_db, base->dark_gain_db, *r);
	return 0;
}

/* ---- flat ---- */

int pc_calib_one_gain(const pc_calib_stack *s, size_t n, const char *step, const char *vary,
                      double *gain_db)
{
	*gain_db = NAN;
	size_t at = 0; /* the stack *gain_db is from */
	for (size_t l = 0; l < n; l++) {
		const double gl = s[l].gain_db;
		if (!isfinite(gl))
			continue;
		if (isfinite(*gain_db) && fabs(gl - *gain_db) > 1e-3)
			return pc_error(PC_EINVAL,
			                "%s: %s is at %g dB of analog gain, %s at %g dB: the "
			                "recordings need one gain (vary %s, not the gain)",
			                step, s[at].name ? s[at].name : "a recording", *gain_db,
			                s[l].name ? s[l].name : "another", gl, vary);
		if (!isfinite(*gain_db))
			at = l;
		*gain_db = gl;
	}
	return 0;
}

int pc_calib_flat(const pc_calib_stack *levels, size_t n_levels, const pc_calib *base,
                  const pc_calib_opts *o, pc_calib *out)
{
	pc_calib_init(out);
	if (n_levels < 2)
		return pc_error(PC_EINVAL,
		                "flat: %zu level%s given: at least 2 light levels are needed "
		                "(the gain is a slope)",
		                n_levels, n_levels == 1 ? "" : "s");
	int rc;
	const pc_calib_geometry *g = base ? &base->geo : &levels[0].geo;
	if ((rc = check_mono(g, levels[0].name)))
		return rc;
	const size_t np = (size_t)g->width * g->height;
	double sat =
	    base && (!o || !(o->saturation > 0)) ? base->saturation : sat_level(o, g->bits);
	double max_frac = o && o->max_saturated_frac > 0 ? o->max_saturated_frac : 1e-4;
	double *y = malloc(n_levels * np * sizeof *y);
	uint8_t *bad = calloc(np, 1);
	double lm[4 * 64];
	if (!y || !bad) {
		free(y);
		free(bad);
		return pc_error(PC_ENOMEM, "flat");
	}
	if (n_levels > 64) {
		free(y);
		free(bad);
		return pc_error(PC_EINVAL, "flat: at most 64 levels");
	}
	/* one analog gain for every level (the gain map is relative, but the photon transfer
	 * varies the exposure at one gain: EMVA 1288) */
	double gain_db;
	if ((rc = pc_calib_one_gain(levels, n_levels, "flat", "the exposure or the light",
	                            &gain_db))) {
		free(y);
		free(bad);
		return rc;
	}
	/* the base's dark at that gain */
	double dr;
	if ((rc = pc_calib_base_dark_scale(base, gain_db, "flat: recordings", &dr))) {
		free(y);
		free(bad);
		return rc;
	}
	uint64_t done = 0, total = 0;
	bool ptc = true; /* the photon transfer: every level has frames to vary over */
	for (size_t l = 0; l < n_levels; l++) {
		total += levels[l].n;
		ptc &= levels[l].n >= 2;
	}
	double pv[64], pm[64]; /* per level: mean temporal variance and mean level above dark */
	for (size_t l = 0; l < n_levels; l++) {
		stack_stats st;
		if ((rc = stack_read(&levels[l], g, ptc, sat, &st, &done, total, o)))
			goto out;
		if ((double)st.n_sat > max_frac * (double)np) {
			rc = pc_error(PC_EINVAL,
			              "%s: %zu of %zu pixels saturated (at %g DN or above): "
			              "lower the exposure or the light",
			              levels[l].name, st.n_sat, np, sat);
			stats_free(&st);
			goto out;
		}
		double s[4] = {0}, n[4] = {0}, sv = 0;
		for (uint32_t yy = 0; yy < g->height; yy++)
			for (uint32_t x = 0; x < g->width; x++) {
				size_t p = (size_t)yy * g->width + x;
				double v = st.mean[p] - pc_calib_dark_at(base, p, dr);
				y[l * np + p] = v;
				bad[p] |= st.sat[p];
				unsigned c = pc_mosaic_channel(&g->mosaic, x, yy);
				if (!st.sat[p] && (!base || !base->valid || base->valid[p])) {
					s[c] += v;
					n[c]++;
					if (st.var)
						sv += st.var[p];
				}
			}
		for (int c = 0; c < 4; c++)
			lm[l * 4 + c] = n[c] > 0 ? s[c] / n[c] : 0;
		const double nall = n[0] + n[1] + n[2] + n[3];
		pv[l] = nall > 0 ? sv / nall : 0;
		pm[l] = nall > 0 ? (s[0] + s[1] + s[2] + s[3]) / nall : 0;
		stats_free(&st);
	}
	/* the levels must differ: the gain is the slope of pixel against channel mean */
	double lo = INFINITY, hi = -INFINITY;
	for (size_t l = 0; l < n_levels; l++) {
		double m = (lm[l * 4] + lm[l * 4 + 1] + lm[l * 4 + 2] + lm[l * 4 + 3]) / 4;
		lo = fmin(lo, m);
		hi = fmax(hi, m);
	}
	if (!(hi - lo > 0.05 * fabs(hi)) || !(hi > 0)) {
		rc = pc_error(PC_ENUMERIC,
		              "flat: the levels' means span %.4g to %.4g DN: they must "
		              "differ by at least 5 %% (singular fit)",
		              lo, hi);
		goto out;
	}
	if ((rc = start_from(out, base, g)))
		goto out;
	out->saturation = sat;
	if (!(out->gain = malloc(np * sizeof(float)))) {
		rc = pc_error(PC_ENOMEM, "gain map");
		goto out;
	}
	/* per pixel: least squares y_l = b + g·m_l (m_l the channel mean of level l), slope g */
	double gs = 0;
	size_t gn = 0;
	for (uint32_t yy = 0; yy < g->height; yy++)
		for (uint32_t x = 0; x < g->width; x++) {
			size_t p = (size_t)yy * g->width + x;
			unsigned c = pc_mosaic_channel(&g->mosaic, x, yy);
			double sm = 0, sy = 0, smm = 0, smy = 0, nl = (double)n_levels;
			for (size_t l = 0; l < n_levels; l++) {
				double m = lm[l * 4 + c], v = y[l * np + p];
				sm += m;
				sy += v;
				smm += m * m;
				smy += m * v;
			}
			double den = nl * smm - sm * sm;
			double gp = den > 0 ? (nl * smy - sm * sy) / den : 0;
			out->gain[p] = (float)gp;
			if (bad[p] || !(gp > 0.2 && gp < 5))
				out->valid[p] = 0; /* dead, saturated or absurd */
			if (out->valid[p]) {
				gs += gp;
				gn++;
			}
		}
	double gmean = gn ? gs / (double)gn : 1;
	for (size_t p = 0; p < np; p++)
		out->gain[p] = out->valid[p] ? (float)(out->gain[p] / gmean) : 1.0f;
	out->parts |= PC_CAL_FLAT;
	/* the photon transfer (EMVA 1288): var = K·level + dark variance, least squares */
	out->system_gain = 0;
	out->system_gain_db = NAN;
	if (ptc) {
		double a = 0, b = 0, c = 0, d = 0, nl = (double)n_levels;
		for (size_t l = 0; l < n_levels; l++) {
			a += pm[l];
			b += pv[l];
			c += pm[l] * pm[l];
			d += pm[l] * pv[l];
		}
		const double den = nl * c - a * a, k = den > 0 ? (nl * d - a * b) / den : 0;
		out->system_gain = isfinite(k) && k > 0 ? k : 0;
		if (out->system_gain > 0)
			out->system_gain_db = gain_db;
	}
	rc = 0;
out:
	free(y);
	free(bad);
	if (rc)
		pc_calib_free(out);
	return rc;
}

/* ---- analyser ---- */

/* pinv of the 3×3 symmetric matrix (Cramer); returns the reciprocal condition estimate. */
static double inv3(const double a[3][3], double inv[3][3])
{
	double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
	double c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
	double c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
	double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
	double nrm = 0;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			nrm = fmax(nrm, fabs(a[i][j]));
	if (!(fabs(det) > 1e-14 * nrm * nrm * nrm))
		return 0;
	inv[0][0] = c00 / det;
	inv[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) / det;
	inv[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) / det;
	inv[1][0] = c01 / det;
	inv[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) / det;
	inv[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) / det;
	inv[2][0] = c02 / det;
	inv[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) / det;
	inv[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) / det;
	double ninv = 0;
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			ninv = fmax(ninv, fabs(inv[i][j]));
	return 1 / (nrm * ninv);
}

/* Per pixel a_p = (U Uᵀ)⁻¹ U I_p with U the 3×K stimulus matrix; residual RMS (K > 3). */
static int fit_vectors(const double *I, size_t K, size_t np, const double (*u)[3], double *a,
                       double *res, double *rcond_out)
{
	double N[3][3] = {{0}}, Ni[3][3];
	for (size_t k = 0; k < K; k++)
		for (int i = 0; i < 3; i++)
			for (int j = 0; j < 3; j++)
				N[i][j] += u[k][i] * u[k][j];
	double rcond = inv3(N, Ni);
	if (rcond_out)
		*rcond_out = rcond;
	if (!(rcond > 1e-8))
		return PC_ENUMERIC;
	for (size_t p = 0; p < np; p++) {
		double b[3] = {0, 0, 0};
		for (size_t k = 0; k < K; k++)
			for (int i = 0; i < 3; i++)
				b[i] += u[k][i] * I[k * np + p];
		for (int i = 0; i < 3; i++)
			a[3 * p + i] = Ni[i][0] * b[0] + Ni[i][1] * b[1] + Ni[i][2] * b[2];
		if (res) {
			double ss = 0;
			for (size_t k = 0; k < K; k++) {
				double e =
				    I[k * np + p] - (a[3 * p] * u[k][0] + a[3 * p + 1] * u[k][1] +
				                     a[3 * p + 2] * u[k][2]);
				ss += e * e;
			}
			res[p] = K > 3 ? sqrt(ss / (double)(K - 3)) : 0;
		}
	}
	return 0;
}

static void stim_vec(double s0, double P, double theta, double u[3])
{
	u[0] = s0;
	u[1] = s0 * P * cos(2 * theta);
	u[2] = s0 * P * sin(2 * theta);
}

/* Mean orientation error over valid pixels: ½·atan2(a2, a1) minus the nominal channel angle,
 * wrapped to (−90°, 90°]. */
static double mean_orientation_error(const pc_calib_geometry *g, const double *a,
                                     const uint8_t *valid)
{
	double s = 0;
	size_t n = 0;
	for (uint32_t y = 0; y < g->height; y++)
		for (uint32_t x = 0; x < g->width; x++) {
			size_t p = (size_t)y * g->width + x;
			if (valid && !valid[p])
				continue;
			double th = 0.5 * atan2(a[3 * p + 2], a[3 * p + 1]);
			double e = th - pc_mosaic_channel(&g->mosaic, x, y) * 45 * DEG;
			e = remainder(e, 180 * DEG);
			s += e;
			n++;
		}
	return n ? s / (double)n : 0;
}

/* Super-pixel pseudo-inverses from the per-pixel analysis vectors. */
static int build_pinv_sp(pc_calib *cal)
{
	const uint32_t W = cal->geo.width, H = cal->geo.height, gw = W / 2, gh = H / 2;
	free(cal->pinv_sp);
	cal->pinv_sp = malloc((size_t)gw * gh * 12 * sizeof(float));
	if (!cal->pinv_sp)
		return pc_error(PC_ENOMEM, "super-pixel pseudo-inverses");
	for (uint32_t j = 0; j < gh; j++)
		for (uint32_t i = 0; i < gw; i++) {
			double w[4][3], pinv[3][4];
			for (uint32_t dy = 0; dy < 2; dy++)
				for (uint32_t dx = 0; dx < 2; dx++) {
					uint32_t x = 2 * i + dx, y = 2 * j + dy;
					unsigned c = pc_mosaic_channel(&cal->geo.mosaic, x, y);
					const float *a = cal->analysis + 3 * ((size_t)y * W + x);
					for (int k = 0; k < 3; k++)
						w[c][k] = a[k];
				}
			/* the twelve planes of pc_analyser_pinv: element (r, c) at (4r + c)·n */
			const size_t n = (size_t)gw * gh, cell = (size_t)j * gw + i;
			if (pc_stokes_pinv1(w, pinv)) {
				double id[4][3];
				pc_stokes_ideal_analyser(id);
				pc_stokes_pinv1(id, pinv);
				for (uint32_t dy = 0; dy < 2; dy++)
					for (uint32_t dx = 0; dx < 2; dx++)
						cal->valid[(size_t)(2 * j + dy) * W + 2 * i + dx] =
						    0;
			}
			for (int r = 0; r < 3; r++)
				for (int c = 0; c < 4; c++)
					cal->pinv_sp[(size_t)(4 * r + c) * n + cell] =
					    (float)pinv[r][c];
		}
	return 0;
}

int pc_calib_analyser(const pc_calib_stack *stim, size_t K, const pc_calib *base,
                      const pc_calib_opts *o, pc_calib *out, double *angles_out)
{
	pc_calib_init(out);
	bool unknown = o && o->unknown_angles;
	if (K < 3 || (unknown && K < 4))
		return pc_error(PC_EINVAL,
		                "analyser: %zu stimul%s given: at least %d analyser angles "
		                "are needed%s",
		                K, K == 1 ? "us" : "i", unknown ? 4 : 3,
		                unknown ? " with unknown angles (3 per pixel + the angles)"
		                        : " (3 unknowns "
		                          "per pixel)");
	if (K > 256)
		return pc_error(PC_EINVAL, "analyser: at most 256 stimuli");
	const pc_calib_geometry *g = base ? &base->geo : &stim[0].geo;
	int rc;
	if ((rc = check_mono(g, stim[0].name)))
		return rc;
	double theta[256], P[256];
	for (size_t k = 0; k < K; k++) {
		P[k] = isfinite(stim[k].dolp) && stim[k].dolp > 0 ? stim[k].dolp : 1;
		if (stim[k].dolp > 1)
			return pc_error(PC_EINVAL, "%s: DoLP %g > 1", stim[k].name, stim[k].dolp);
		theta[k] = stim[k].angle_deg * DEG;
		if (!unknown && !isfinite(theta[k]))
			return pc_error(PC_EINVAL,
			                "%s: the stimulus angle is unknown (give the angles, "
			                "or use the unknown-angles mode)",
			                stim[k].name);
	}
	/* the stimuli are compared as equal intensities s0: one analog gain */
	double gain_db;
	if ((rc = pc_calib_one_gain(stim, K, "analyser", "the polarizer's angle", &gain_db)))
		return rc;
	double dr;
	if ((rc = pc_calib_base_dark_scale(base, gain_db, "analyser: recordings", &dr)))
		return rc;
	const size_t np = (size_t)g->width * g->height;
	double sat =
	    base && (!o || !(o->saturation > 0)) ? base->saturation : sat_level(o, g->bits);
	double max_frac = o && o->max_saturated_frac > 0 ? o->max_saturated_frac : 1e-4;
	double *I = malloc(K * np * sizeof *I), *a = malloc(3 * np * sizeof *a);
	double *res = malloc(np * sizeof *res);
	uint8_t *bad = calloc(np, 1);
	if (!I || !a || !res || !bad) {
		rc = pc_error(PC_ENOMEM, "analyser fit (%zu pixels x %zu stimuli)", np, K);
		goto out;
	}
	uint64_t done = 0, total = 0;
	for (size_t k = 0; k < K; k++)
		total += stim[k].n;
	for (size_t k = 0; k < K; k++) {
		stack_stats st;
		if ((rc = stack_read(&stim[k], g, false, sat, &st, &done, total, o)))
			goto out;
		if ((double)st.n_sat > max_frac * (double)np) {
			rc = pc_error(PC_EINVAL,
			              "%s: %zu of %zu pixels saturated (at %g DN or above): "
			              "lower the exposure",
			              stim[k].name, st.n_sat, np, sat);
			stats_free(&st);
			goto out;
		}
		for (size_t p = 0; p < np; p++) {
			double v = st.mean[p] - pc_calib_dark_at(base, p, dr);
			if (base && base->gain)
				v /= base->gain[p];
			I[k * np + p] = v;
			bad[p] |= st.sat[p];
		}
		stats_free(&st);
	}
	if ((rc = start_from(out, base, g)))
		goto out;
	out->saturation = sat;
	for (size_t p = 0; p < np; p++)
		if (bad[p])
			out->valid[p] = 0;
	double u[256][3], rcond = 0;
	if (unknown) {
		/* initial angles: the ideal-analyser Stokes of the sensor-wide channel means */
		double m[256][4];
		for (size_t k = 0; k < K; k++) {
			double s[4] = {0}, n[4] = {0};
			for (uint32_t y = 0; y < g->height; y++)
				for (uint32_t x = 0; x < g->width; x++) {
					size_t p = (size_t)y * g->width + x;
					if (!out->valid[p])
						continue;
					unsigned c = pc_mosaic_channel(&g->mosaic, x, y);
					s[c] += I[k * np + p];
					n[c]++;
				}
			for (int c = 0; c < 4; c++)
				m[k][c] = n[c] ? s[c] / n[c] : 0;
			theta[k] = 0.5 * atan2(m[k][1] - m[k][3], m[k][0] - m[k][2]);
		}
		unsigned iters = o->iterations ? o->iterations : 50;
		for (unsigned it = 0; it < iters; it++) {
			for (size_t k = 0; k < K; k++)
				stim_vec(1, P[k], theta[k], u[k]);
			if ((rc = fit_vectors(I, K, np, (const double(*)[3])u, a, NULL, &rcond)))
				break;
			/* each angle: Gauss–Newton on Σ_p (I_pk − a_p·u(θ))² over valid pixels */
			double maxstep = 0;
			for (size_t k = 0; k < K; k++) {
				double c2 = cos(2 * theta[k]), s2 = sin(2 * theta[k]);
				double jj = 0, jr = 0;
				for (size_t p = 0; p < np; p++) {
					if (!out->valid[p])
						continue;
					const double *ap = a + 3 * p;
					double f = ap[0] + P[k] * (ap[1] * c2 + ap[2] * s2);
					double d = 2 * P[k] * (-ap[1] * s2 + ap[2] * c2);
					double r = I[k * np + p] - f;
					jj += d * d;
					jr += d * r;
				}
				double step = jj > 0 ? jr / jj : 0;
				theta[k] += step;
				maxstep = fmax(maxstep, fabs(step));
			}
			/* gauge: the angles are relative; fix the mean analyser orientation error
			 * to 0 */
			for (size_t k = 0; k < K; k++)
				stim_vec(1, P[k], theta[k], u[k]);
			if ((rc = fit_vectors(I, K, np, (const double(*)[3])u, a, NULL, &rcond)))
				break;
			double e = mean_orientation_error(g, a, out->valid);
			for (size_t k = 0; k < K; k++)
				theta[k] -= e;
			if (maxstep < 1e-9 && fabs(e) < 1e-9)
				break;
		}
		if (rc) {
			rc = pc_error(
			    PC_ENUMERIC,
			    "analyser: the estimated angles collapsed (singular "
			    "fit): the stimuli must cover at least 3 distinct angles mod 180°");
			goto out;
		}
	}
	for (size_t k = 0; k < K; k++)
		stim_vec(1, P[k], theta[k], u[k]);
	if ((rc = fit_vectors(I, K, np, (const double(*)[3])u, a, res, &rcond))) {
		char list[512] = "";
		for (size_t k = 0; k < K && strlen(list) < 480; k++)
			snprintf(list + strlen(list), sizeof list - strlen(list), "%s%.4g",
			         k ? "," : "", theta[k] / DEG);
		rc = pc_error(PC_ENUMERIC,
		              "analyser: the angles %s deg do not determine cos 2θ and "
		              "sin 2θ (singular fit, reciprocal condition %.3g): use angles spread "
		              "over 180°",
		              list, rcond);
		goto out;
	}
	/* scale: mean a0 over valid pixels = ½ */
	double s = 0;
	size_t n = 0;
	for (size_t p = 0; p < np; p++)
		if (out->valid[p]) {
			s += a[3 * p];
			n++;
		}
	if (!(s > 0) || n == 0) {
		rc = pc_error(PC_ENUMERIC, "analyser: no signal (mean response %g DN)",
		              n ? s / n : 0);
		goto out;
	}
	double scale = 0.5 / (s / (double)n);
	free(out->analysis);
	free(out->residual);
	out->analysis = malloc(3 * np * sizeof(float));
	out->residual = malloc(np * sizeof(float));
	if (!out->analysis || !out->residual) {
		rc = pc_error(PC_ENOMEM, "analysis maps");
		goto out;
	}
	for (size_t p = 0; p < np; p++) {
		for (int i = 0; i < 3; i++)
			out->analysis[3 * p + i] = (float)(a[3 * p + i] * scale);
		out->residual[p] = (float)res[p];
		/* a pixel that barely responds or barely analyses cannot be inverted */
		double a0 = a[3 * p] * scale, d = hypot(a[3 * p + 1], a[3 * p + 2]) * scale;
		if (!(a0 > 0.05) || !(d > 0.05 * a0))
			out->valid[p] = 0;
	}
	if ((rc = build_pinv_sp(out)))
		goto out;
	if (angles_out)
		for (size_t k = 0; k < K; k++)
			angles_out[k] = remainder(theta[k] / DEG, 180.0) < 0
			                    ? remainder(theta[k] / DEG, 180.0) + 180
			                    : remainder(theta[k] / DEG, 180.0);
	out->parts |= PC_CAL_ANALYSER;
	pc_calib_unprepare(out); /* made from the old analysers */
	rc = 0;
out:
	free(I);
	free(a);
	free(res);
	free(bad);
	if (rc)
		pc_calib_free(out);
	return rc;
}

/* ---- applying ---- */

int pc_calib_correct(const pc_calib *cal, const pc_view *raw, float *out, uint8_t *valid_out,
                     size_t *n_invalid)
{
	const uint32_t W = cal->geo.width, H = cal->geo.height;
	if (raw->width != W || raw->height != H)
		return pc_error(PC_EINVAL, "frame %ux%u, calibration %ux%u: size differs",
		                raw->width, raw->height, W, H);
	int rc = pc_view_to_f32(raw, out, (size_t)W * sizeof(float));
	if (rc)
		return rc;
	size_t bad = 0;
	const double sat = cal->saturation > 0 ? cal->saturation : INFINITY;
	for (size_t p = 0; p < (size_t)W * H; p++) {
		double x = out[p];
		bool ok = (!cal->valid || cal->valid[p]) && x < sat;
		double v = x - pc_calib_dark_at(cal, p, 1);
		if (cal->gain)
			v /= cal->gain[p];
		out[p] = (float)v;
		if (valid_out)
			valid_out[p] = ok;
		bad += !ok;
	}
	if (n_invalid)
		*n_invalid = bad;
	return 0;
}

/* per-pixel pseudo-inverses in place (pc_calib_pinv) */
typedef struct pinv_ctx {
	float *buf;
	size_t np;
	uint32_t W;
	uint32_t *bad; /* per row: 1 + the first singular pixel's x, or 0 */
} pinv_ctx;

static void pinv_rows(void *vctx, uint32_t y0, uint32_t y1)
{
	const pinv_ctx *c = vctx;
	for (uint32_t y = y0; y < y1; y++)
		for (uint32_t x = 0; x < c->W; x++) {
			size_t p = (size_t)y * c->W + x;
			double w[4][3], pinv[3][4];
			for (int ch = 0; ch < 4; ch++)
				for (int k = 0; k < 3; k++)
					w[ch][k] = c->buf[(size_t)(4 * k + ch) * c->np + p];
			if (pc_stokes_pinv1(w, pinv)) {
				if (!c->bad[y])
					c->bad[y] = x + 1;
				continue;
			}
			for (int i = 0; i < 3; i++)
				for (int ch = 0; ch < 4; ch++)
					c->buf[(size_t)(4 * i + ch) * c->np + p] =
					    (float)pinv[i][ch];
		}
}

static bool is_superpixel(pc_demosaic_method m)
{
	return m == PC_DM_SUPERPIXEL || m == PC_DM_SUPERPIXEL_HALF;
}

/* The first row's flag of bad[] (per output row: 0, or 1 + the column of a singular analyser
 * matrix, or UINT32_MAX when the row's check had no memory) as the error, 0 if none. */
static int singular_rows(const uint32_t *bad, uint32_t H)
{
	for (uint32_t y = 0; y < H; y++)
		if (bad[y] == UINT32_MAX)
			return pc_error(PC_ENOMEM, "calibration: analyser check rows");
		else if (bad[y])
			return pc_error(
			    PC_ENUMERIC,
			    "calibration: the analyser matrix of output pixel (%u,%u) is "
			    "singular (its demosaicked analysis vectors do not span S1, S2)",
			    bad[y] - 1, y);
	return 0;
}

int pc_calib_pinv(pc_calib *cal, pc_demosaic_method method, int threads, pc_analyser_pinv *pinv)
{
	if (!(cal->parts & PC_CAL_ANALYSER) || !cal->analysis || !cal->pinv_sp)
		return pc_error(PC_EINVAL,
		                "the calibration has no analyser part (polarcam calibrate "
		                "analyser)");
	const uint32_t W = cal->geo.width, H = cal->geo.height;
	if (is_superpixel(method)) {
		pinv->m = cal->pinv_sp;
		pinv->grid_w = W / 2;
		pinv->grid_h = H / 2;
		return 0;
	}
	if (cal->pinv_px && cal->pinv_method == (int)method) {
		pinv->m = cal->pinv_px;
		pinv->grid_w = W;
		pinv->grid_h = H;
		return 0;
	}
	uint32_t ow, oh;
	pc_demosaic_out_size(method, W, H, &ow, &oh);
	if (ow != W || oh != H)
		return pc_error(PC_ENOTSUP, "calibrated Stokes for a method with output %ux%u", ow,
		                oh);
	const size_t np = (size_t)W * H;
	/* in place: component k of the analysis vectors demosaicked into planes 4k..4k+3 (W's
	 * element (c, k) at (4k + c)·np), then per pixel the pseudo-inverse's element (i, c) into
	 * (4i + c)·np - the same twelve slots */
	free(cal->pinv_px);
	cal->pinv_px = NULL;
	cal->pinv_method = -1;
	float *buf = malloc(12 * np * sizeof *buf), *map = malloc(np * sizeof *map);
	uint32_t *bad = calloc(H, sizeof *bad);
	int rc = 0;
	if (!buf || !map || !bad) {
		rc = pc_error(PC_ENOMEM, "per-pixel analysis matrices (%zu pixels)", np);
		goto out;
	}
	pc_demosaic_opts dopt = {.threads = threads};
	for (int k = 0; k < 3 && !rc; k++) {
		for (size_t p = 0; p < np; p++)
			map[p] = cal->analysis[3 * p + (size_t)k];
		pc_view v = {map, W, H, (size_t)W * sizeof(float), PC_FMT_FLOAT32};
		pc_fplane planes[4];
		pc_fplanes_separate(buf + (size_t)k * 4 * np, W, H, 4, planes);
		rc = pc_demosaic(&v, &cal->geo.mosaic, method, &dopt, planes);
	}
	if (rc)
		goto out;
	pinv_ctx pc = {buf, np, W, bad};
	pc_parallel_rows(H, 0, threads, pinv_rows, &pc);
	if ((rc = singular_rows(bad, H)))
		goto out;
	cal->pinv_px = buf;
	buf = NULL;
	cal->pinv_method = (int)method;
	pinv->m = cal->pinv_px;
	pinv->grid_w = W;
	pinv->grid_h = H;
out:
	free(buf);
	free(map);
	free(bad);
	return rc;
}

int pc_calib_stokes(pc_calib *cal, const pc_view *raw, const pc_calib_geometry *g,
                    pc_demosaic_method method, int threads, const pc_stokes_out *out,
                    uint8_t *valid_out, size_t *n_invalid)
{
	return pc_calib_stokes_gain(cal, raw, g, method, threads, 0, NAN, out, valid_out, n_invalid,
	                            NULL);
}

int pc_calib_stokes_gain(pc_calib *cal, const pc_view *raw, const pc_calib_geometry *g,
                         pc_demosaic_method method, int threads, double noise_gain, double gain_db,
                         const pc_stokes_out *out, uint8_t *valid_out, size_t *n_invalid,
                         double *noise_gain_used)
{
	int rc;
	if (g && (rc = pc_calib_check(cal, g)))
		return rc;
	pc_frame f;
	memset(&f, 0, sizeof f);
	f.view = *raw;
	f.meta.exposure_us = NAN; /* not known here */
	f.meta.gain_db = gain_db;
	f.mosaic = cal->geo.mosaic;
	f.meta.offset_x = cal->geo.offset_x;
	f.meta.offset_y = cal->geo.offset_y;
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = method;
	po.mosaic = cal->geo.mosaic;
	po.threads = threads;
	po.saturation_level = cal->saturation;
	po.noise_gain = noise_gain;
	po.noise_gain_used = noise_gain_used;
	uint32_t ow, oh;
	pc_demosaic_out_size(method, cal->geo.width, cal->geo.height, &ow, &oh);
	pc_validity v = {valid_out, ow, 0};
	rc = pc_calib_apply(cal, &f, g ? g->bits : 0, &po, out, NULL,
	                    valid_out || n_invalid ? &v : NULL);
	if (!rc && n_invalid)
		*n_invalid = (size_t)v.n_invalid;
	return rc;
}

/* ---- the calibration as a pipeline stage (pc_calib_apply) ---- */

typedef struct apply_ctx {
	const pc_view *raw;
	uint32_t maxv;  /* the largest value the bit depth allows */
	uint32_t *rows; /* per row: samples above it */
} apply_ctx;

/* The range check of 16-bit containers (nothing is clamped silently; packed formats cannot
 * exceed their depth, float ones the core checks for NaN and infinity): per row the samples
 * above the bit depth. The correction (raw − dark)·(1/gain) and the flags (saturated, dead,
 * distrusted) happen in the core's pipeline (pc_pipeline_opts.dark, gain_inv or compact;
 * saturation_level, dead_level, trusted). */
#ifdef _OPENMP
#define PC_CAL_SIMD_OR _Pragma("omp simd reduction(| : any)")
#else
#define PC_CAL_SIMD_OR
#endif

static void apply_rows(void *vctx, uint32_t y0, uint32_t y1)
{
	const apply_ctx *c = vctx;
	const uint32_t W = c->raw->width;
	for (uint32_t y = y0; y < y1; y++) {
		const uint16_t *r = (const uint16_t *)(const void *)((const uint8_t *)c->raw->data +
		                                                     (size_t)y * c->raw->stride);
		/* the bits above the depth (maxv is 2^bits − 1) of the whole row, then the count
		 * only in a row that has some */
		uint32_t any = 0, nr = 0;
		PC_CAL_SIMD_OR
		for (uint32_t x = 0; x < W; x++)
			any |= r[x];
		if (any & ~c->maxv)
			for (uint32_t x = 0; x < W; x++)
				nr += r[x] > c->maxv;
		c->rows[y] = nr;
	}
}

/* 1/gain, once per calibration (0 or negative gains: 1) */
static int inverse_gain(pc_calib *cal)
{
	if (!cal->gain || cal->apply_ig)
		return 0;
	const size_t np = (size_t)cal->geo.width * cal->geo.height;
	float *ig = malloc(np * sizeof *ig);
	if (!ig)
		return pc_error(PC_ENOMEM, "calibrated pipeline: inverse gains (%zu pixels)", np);
	for (size_t p = 0; p < np; p++)
		ig[p] = cal->gain[p] > 0 ? 1.0f / cal->gain[p] : 1.0f;
	cal->apply_ig = ig;
	return 0;
}

/* ---- the compact calibration (pc_compact_calib) for the fused bilinear pipeline ---- */

/* every output pixel's least-squares matrix from the 16-bit vectors, checked as
 * pc_calib_pinv checks (wls_invertible) */
typedef struct vcheck_ctx {
	const pc_compact_calib *v;
	const pc_mosaic *m;
	uint32_t *bad; /* per row: 1 + the first singular pixel's x, or 0 */
} vcheck_ctx;

/* row y (mirrored) of component k of u = (1, v1, v2) as doubles, padded one sample each side
 * (mirrored) */
static void vec_row(const vcheck_ctx *c, int y, int k, double *d)
{
	const pc_compact_calib *v = c->v;
	const int w = (int)v->width;
	y = y < 0 ? -y : y >= (int)v->height ? 2 * (int)v->height - 2 - y : y;
	if (k == 0) {
		for (int x = 0; x < w + 2; x++)
			d[x] = 1;
		return;
	}
	const int16_t *q = v->v_q[k - 1] ? v->v_q[k - 1] + (size_t)y * v->stride : NULL;
	const double b0 = v->v_base[pc_mosaic_channel(c->m, 0, (unsigned)y)][k - 1];
	const double b1 = v->v_base[pc_mosaic_channel(c->m, 1, (unsigned)y)][k - 1];
	for (int x = 0; x < w; x++)
		d[x + 1] = ((x & 1) ? b1 : b0) + (q ? (double)v->v_scale[k - 1] * q[x] : 0);
	d[0] = d[w > 1 ? 2 : 1];
	d[w + 1] = d[w > 1 ? w - 1 : 1];
}

/* Whether the fused kernel's matrix at column x is safely invertible: M = Σ K_s u_s u_sᵀ over
 * the 3×3 neighbourhood (K = 1, ½, ¼: the bilinear weights; u = (1, v1, v2) the normalised
 * analysis vectors, the estimator of pc_compact_calib; r[k][0..2]: component k of rows y−1,
 * y, y+1), by the test of pc_stokes_pinv1 (pc_mat3_inverse: reciprocal 1-norm condition
 * number at least PC_RCOND_MIN). */
static bool wls_invertible(double *r[3][3], int x)
{
	double m[3][3] = {{0}};
	for (int d = 0; d < 3; d++)
		for (int dx = -1; dx <= 1; dx++) {
			const double k = (d == 1 ? 1 : 0.5) * (dx ? 0.5 : 1);
			for (int i = 0; i < 3; i++)
				for (int j = 0; j < 3; j++)
					m[i][j] += k * r[i][d][x + dx] * r[j][d][x + dx];
		}
	return pc_mat3_inverse(m, NULL) >= PC_RCOND_MIN;
}

static void vcheck_rows(void *vctx, uint32_t y0, uint32_t y1)
{
	const vcheck_ctx *c = vctx;
	const int w = (int)c->v->width;
	double *buf = malloc(9 * ((size_t)w + 2) * sizeof *buf);
	if (!buf) {
		c->bad[y0] = UINT32_MAX; /* reported as out of memory */
		return;
	}
	for (uint32_t y = y0; y < y1; y++) {
		double *r[3][3]; /* [component][row y−1, y, y+1] */
		for (int k = 0; k < 3; k++)
			for (int d = 0; d < 3; d++) {
				r[k][d] = buf + (size_t)(3 * k + d) * ((size_t)w + 2) + 1;
				vec_row(c, (int)y + d - 1, k, r[k][d] - 1);
			}
		for (int x = 0; x < w; x++)
			if (!wls_invertible(r, x)) {
				c->bad[y] = (uint32_t)x + 1;
				break;
			}
	}
	free(buf);
}

/* One map in 16 bits: base = its mean (per mosaic channel when by_channel), scale = its largest
 * |value − base| over 32767, q = round((value − base)/scale): every value kept to scale/2. All
 * pixels count, the distrusted ones too, so that distrusting a pixel changes no other output;
 * a distrusted value outside the trusted pixels' range was replaced before (tame_distrusted),
 * so that a degenerate one cannot coarsen the step of the whole map. value(p) =
 * src[stride·p]; fails on a value that is not finite. */
static int quantise(const pc_calib *cal, const float *src, size_t stride, bool by_channel,
                    float *base, float *scale, int16_t *q, size_t qstride, const char *what)
{
	const uint32_t W = cal->geo.width;
	const size_t np = (size_t)W * cal->geo.height;
	double sum[4] = {0}, n[4] = {0};
	for (size_t p = 0; p < np; p++) {
		double a = src[stride * p];
		if (!isfinite(a))
			return pc_error(PC_ENUMERIC,
			                "calibration: the %s of pixel (%zu,%zu) is not finite",
			                what, p % W, p / W);
		unsigned g = by_channel ? pc_mosaic_channel(&cal->geo.mosaic, (unsigned)(p % W),
		                                            (unsigned)(p / W))
		                        : 0;
		sum[g] += a;
		n[g]++;
	}
	for (int g = 0; g < (by_channel ? 4 : 1); g++)
		base[g] = n[g] > 0 ? (float)(sum[g] / n[g]) : 0.0f;
	double amax = 0;
	for (size_t p = 0; p < np; p++) {
		unsigned g = by_channel ? pc_mosaic_channel(&cal->geo.mosaic, (unsigned)(p % W),
		                                            (unsigned)(p / W))
		                        : 0;
		/* a comparison, not fmax: the same maximum of these finite values (checked above),
		 * and GCC 12.2 for AArch64 crashes vectorising the fmax reduction at -O3
		 * (internal compiler error in vect_transform_reduction) */
		const double dv = fabs(src[stride * p] - base[g]);
		if (dv > amax)
			amax = dv;
	}
	/* just above max/32767, so that the largest deviation rounds inside the range */
	*scale = (float)(amax / 32767 * (1 + 1e-6));
	for (size_t p = 0; p < np; p++) {
		unsigned g = by_channel ? pc_mosaic_channel(&cal->geo.mosaic, (unsigned)(p % W),
		                                            (unsigned)(p / W))
		                        : 0;
		double d = *scale > 0 ? (src[stride * p] - base[g]) / *scale : 0;
		q[p / W * qstride + p % W] = (int16_t)lrint(fmin(fmax(d, -32767), 32767));
	}
	return 0;
}

/* A distrusted pixel's value of map f (np values, per mosaic channel when by_channel) that is
 * not finite or lies outside the range of the trusted pixels' values (of its channel) becomes
 * the trusted pixels' mean: a dead pixel (a0 = 0 or nearly, so v = a/a0 and 1/(gain·a0) huge)
 * or a far-off hot pixel's dark would otherwise set the 16-bit step of the whole map
 * (quantise). Every output that reads a distrusted sample is flagged invalid anyway (its
 * bilinear support); a distrusted pixel inside the range keeps its value, so distrusting it
 * changes no other output. Returns the number replaced. */
static size_t tame_distrusted(const pc_calib *cal, float *f, bool by_channel)
{
	const uint32_t W = cal->geo.width;
	const size_t np = (size_t)W * cal->geo.height;
	if (!cal->valid)
		return 0;
	double lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY},
	       hi[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
	double sum[4] = {0}, n[4] = {0};
	for (size_t p = 0; p < np; p++) {
		if (!cal->valid[p])
			continue;
		unsigned g = by_channel ? pc_mosaic_channel(&cal->geo.mosaic, (unsigned)(p % W),
		                                            (unsigned)(p / W))
		                        : 0;
		lo[g] = fmin(lo[g], f[p]);
		hi[g] = fmax(hi[g], f[p]);
		sum[g] += f[p];
		n[g]++;
	}
	size_t k = 0;
	for (size_t p = 0; p < np; p++) {
		if (cal->valid[p])
			continue;
		unsigned g = by_channel ? pc_mosaic_channel(&cal->geo.mosaic, (unsigned)(p % W),
		                                            (unsigned)(p / W))
		                        : 0;
		if (!(f[p] >= lo[g] && f[p] <= hi[g])) { /* also NaN, and no trusted pixel */
			f[p] = n[g] > 0 ? (float)(sum[g] / n[g]) : 0.0f;
			k++;
		}
	}
	return k;
}

/* The compact calibration of pc_calib_apply's bilinear path, once per calibration: the
 * analysis vectors, the dark map and the inverse gains in 16 bits (quantise; a vector component
 * per channel, the maps over the sensor), then every output pixel's least-squares matrix M
 * (wls_invertible) checked for rank as pc_calib_pinv does (PC_ENUMERIC naming the first singular
 * one). A trusted pixel needs a0 > 0 (each sample's equation is divided by it); a distrusted one is
 * stored as its channel's mean (quantise). */
static int compact_calib(pc_calib *cal, int threads)
{
	if (cal->apply_q)
		return 0;
	const uint32_t W = cal->geo.width, H = cal->geo.height;
	const size_t np = (size_t)W * H;
	pc_compact_calib v;
	memset(&v, 0, sizeof v);
	v.width = W;
	v.height = H;
	/* the maps' rows interleaved (row y: v1, v2, then the dark where there is a map, then the
	 * inverse gain), one stream to read; without a dark map the black level is a constant,
	 * read from no map. Each sample's equation divided by its a0 (pc_compact_calib): v = (a1,
	 * a2)/a0 and gain_inv/a0, made in float as the pipeline reads them, then quantised. */
	const size_t nmap = 3 + (cal->dark != NULL);
	int16_t *q = malloc(nmap * np * sizeof *q);
	float *nv = malloc(3 * np * sizeof *nv);
	uint32_t *bad = calloc(H, sizeof *bad), *dis = NULL;
	int rc = 0;
	if (!q || !bad || !nv) {
		rc = pc_error(PC_ENOMEM, "calibration: compact maps (%zu pixels)", np);
		goto out;
	}
	for (size_t p = 0; p < np && !rc; p++) {
		const float *a = cal->analysis + 3 * p;
		if (cal->valid && !cal->valid[p] && !(a[0] > 0 && isfinite(a[0]))) {
			nv[p] = nv[np + p] = nv[2 * np + p] = NAN; /* tame_distrusted replaces it */
			continue;
		}
		if (!(a[0] > 0) || !isfinite(a[0])) {
			rc = pc_error(PC_ENUMERIC,
			              "calibration: the analysis vector of trusted pixel (%zu,%zu) "
			              "has a0 = %g "
			              "(its transmission must be positive)",
			              p % W, p / W, (double)a[0]);
			break;
		}
		nv[p] = a[1] / a[0];
		nv[np + p] = a[2] / a[0];
		nv[2 * np + p] = (cal->apply_ig ? cal->apply_ig[p] : 1.0f) / a[0];
	}
	for (int k = 0; k < 3 && !rc; k++)
		tame_distrusted(cal, nv + (size_t)k * np, k < 2);
	v.stride = nmap * (size_t)W;
	for (int k = 0; k < 2 && !rc; k++) {
		float base[4] = {0}; /* read even when quantise failed */
		v.v_q[k] = q + (size_t)k * W;
		rc = quantise(cal, nv + (size_t)k * np, 1, true, base, &v.v_scale[k],
		              q + (size_t)k * W, v.stride, "analysis vector");
		for (int c = 0; c < 4; c++)
			v.v_base[c][k] = base[c];
	}
	int16_t *next = q + 2 * (size_t)W;
	if (!rc && cal->dark) {
		v.dark_q = next;
		/* a far-off distrusted (hot) pixel's dark tamed in a copy (tame_distrusted) */
		const float *dk = cal->dark;
		float *dcopy = cal->valid ? malloc(np * sizeof *dcopy) : NULL;
		if (dcopy) {
			memcpy(dcopy, cal->dark, np * sizeof *dcopy);
			tame_distrusted(cal, dcopy, false);
			dk = dcopy;
		} else if (cal->valid) {
			rc = pc_error(PC_ENOMEM, "calibration: dark map copy (%zu pixels)", np);
		}
		if (!rc)
			rc = quantise(cal, dk, 1, false, &v.dark_base, &v.dark_scale, next,
			              v.stride, "dark offset");
		free(dcopy);
		next += W;
	} else if (!rc) {
		v.dark_base = (float)cal->black_level; /* exactly */
	}
	if (!rc) {
		v.gain_q = next;
		rc = quantise(cal, nv + 2 * np, 1, false, &v.gain_base, &v.gain_scale, next,
		              v.stride, "inverse gain");
	}
	if (rc)
		goto out;
	vcheck_ctx vc = {&v, &cal->geo.mosaic, bad};
	pc_parallel_rows(H, 0, threads, vcheck_rows, &vc);
	rc = singular_rows(bad, H);
	/* the distrusted samples as a list (pc_compact_calib): a frame then reads no trust map */
	size_t nd = 0;
	for (size_t p = 0; !rc && cal->valid && p < np; p++)
		nd += !cal->valid[p];
	/* none: no list, and a frame's validity skips it altogether */
	if (!rc && nd > UINT32_MAX)
		rc = pc_error(PC_ERANGE, "calibration: %zu distrusted samples: at most %u", nd,
		              (unsigned)UINT32_MAX);
	if (!rc && nd && !(dis = malloc(((size_t)H + 1 + nd) * sizeof *dis)))
		rc = pc_error(PC_ENOMEM, "calibration: %zu distrusted samples", nd);
	if (!rc && dis) {
		uint32_t *xs = dis + H + 1, n = 0;
		for (uint32_t y = 0; y < H; y++) {
			dis[y] = n;
			for (uint32_t x = 0; x < W; x++)
				if (!cal->valid[(size_t)y * W + x])
					xs[n++] = x;
		}
		dis[H] = n;
		v.distrust_row = dis;
		v.distrust_x = xs;
	}
	if (!rc) {
		free(cal->apply_dis);
		cal->apply_q = q;
		cal->apply_dis = dis;
		cal->apply_vec = v;
		q = NULL;
		dis = NULL;
	}
out:
	free(q);
	free(nv);
	free(dis);
	free(bad);
	return rc;
}

/* whether pc_calib_apply runs the method with the compact calibration */
static bool uses_vectors(pc_demosaic_method m, bool reference)
{
	return m == PC_DM_BILINEAR && !reference;
}

int pc_calib_prepare(pc_calib *cal, pc_demosaic_method method, int threads)
{
	int rc = inverse_gain(cal);
	if (!rc && (cal->parts & PC_CAL_ANALYSER)) {
		if (uses_vectors(method, false)) {
			rc = compact_calib(cal, threads);
		} else {
			pc_analyser_pinv pinv;
			rc = pc_calib_pinv(cal, method, threads, &pinv);
		}
	}
	return rc;
}

bool pc_calib_prepared(const pc_calib *cal, pc_demosaic_method method)
{
	return (!cal->gain || cal->apply_ig) &&
	       (!(cal->parts & PC_CAL_ANALYSER) || is_superpixel(method) ||
	        (uses_vectors(method, false) ? cal->apply_q != NULL
	                                     : cal->pinv_px && cal->pinv_method == (int)method));
}

int pc_calib_apply(pc_calib *cal, const pc_frame *f, unsigned bits, const pc_pipeline_opts *o,
                   const pc_stokes_out *st, const pc_fplane *ch, pc_validity *valid)
{
	if (!cal || !f || !o || (!st && !ch))
		return pc_error(PC_EINVAL, "calibrated pipeline: missing argument");
	if (o->pinv || o->compact)
		return pc_error(PC_EINVAL, "calibrated pipeline: the analysers come from the "
		                           "calibration, not from the options");
	if (o->black_level != 0)
		return pc_error(PC_EINVAL,
		                "calibrated pipeline: a black level of %g DN was given, but "
		                "the calibration's dark map (or its black level, %g DN) is the "
		                "black level; give one or the other",
		                o->black_level, cal->black_level);
	if (o->dark || o->gain_inv || o->dark_scale != 0)
		return pc_error(PC_EINVAL, "calibrated pipeline: the dark and gain maps (and the "
		                           "dark map's scale) come from the calibration, not from "
		                           "the options");
	const pc_view *raw = &f->view;
	int rc = pc_view_check(raw);
	if (rc)
		return rc;
	pc_calib_geometry g = {raw->width, raw->height, f->meta.offset_x, f->meta.offset_y, 0,
	                       0,          bits,        f->mosaic};
	if (f->mosaic.period == 4)
		return pc_error(PC_EINVAL,
		                "frame of a colour-polarization mosaic: the calibration is "
		                "for a monochrome polarizer mosaic (colour sensors are not "
		                "calibrated yet)");
	if ((rc = pc_calib_check(cal, &g)))
		return rc;
	/* what is computed once per calibration (1/gain, the per-pixel pseudo-inverses) */
	if ((rc = inverse_gain(cal)))
		return rc;
	pc_analyser_pinv pinv;
	const bool vec = uses_vectors(o->method, o->reference);
	if (st && (cal->parts & PC_CAL_ANALYSER) &&
	    (rc = vec ? compact_calib(cal, o->threads)
	              : pc_calib_pinv(cal, o->method, o->threads, &pinv)))
		return rc;
	const uint32_t H = cal->geo.height;
	const pc_format_info *fi = pc_format_info_get(raw->format);
	const double sat = o->saturation_level;
	if (raw->format == PC_FMT_MONO10 || raw->format == PC_FMT_MONO12 ||
	    raw->format == PC_FMT_MONO14) {
		/* per call (no scratch in cal: concurrent calls on a prepared calibration are safe)
		 */
		uint32_t *rows = malloc((size_t)H * sizeof *rows);
		if (!rows)
			return pc_error(PC_ENOMEM, "calibrated pipeline (%u rows)", H);
		apply_ctx c = {raw, (1u << fi->bits) - 1u, rows};
		pc_parallel_rows(H, 0, o->threads, apply_rows, &c);
		uint64_t nrange = 0;
		for (uint32_t y = 0; y < H; y++)
			nrange += rows[y];
		free(rows);
		if (nrange)
			return pc_error(PC_ERANGE,
			                "%llu samples out of range (above the %u-bit range of %s)",
			                (unsigned long long)nrange, fi->bits, fi->name);
	}
	pc_pipeline_opts po = *o;
	po.mosaic = cal->geo.mosaic;
	/* the noise-aware methods' noise gain, unless given: the system gain the calibration's
	 * flats measured (docs/calibration.md) */
	if (!(po.noise_gain > 0) && cal->system_gain > 0) {
		po.noise_gain = pc_calib_noise_gain(cal, f->meta.gain_db, NULL);
		if (!(po.noise_gain > 0 && isfinite(po.noise_gain)) &&
		    (pc_demosaic_method_get(po.method)->flags & PC_DMF_NOISE_GAIN))
			return pc_error(PC_EINVAL,
			                "a frame at %g dB of analog gain and a calibration whose "
			                "flats were at %g dB: the system gain scaled to the frame "
			                "(%g) is not a usable noise gain",
			                f->meta.gain_db, cal->system_gain_db, po.noise_gain);
	}
	/* the dark map at the frame's analog gain (pc_calib_dark_scale): scaled about the black
	 * level by the core's correction, or in the compact calibration its base and scale */
	double dr;
	if ((rc = pc_calib_base_dark_scale(cal, f->meta.gain_db, "a frame", &dr)))
		return rc;
	pc_compact_calib cv;
	po.dark = cal->dark;
	po.gain_inv = cal->apply_ig;
	po.dark_scale = dr; /* 1 (no dark map, a gain unknown or equal): the map as it is */
	po.dark_pivot = cal->black_level;
	po.black_level = cal->dark ? 0 : cal->black_level;
	/* the validity: the core's rule (saturated, dead) on the raw samples, and the samples the
	 * calibration distrusts (listed in the compact calibration where it is used) */
	po.trusted = cal->valid;
	/* the signal's full scale for edge-aware weights: saturation above the black level */
	if (sat > cal->black_level)
		po.full_scale = sat - cal->black_level + po.black_level;
	if (st && (cal->parts & PC_CAL_ANALYSER)) {
		if (vec) {
			/* the dark and gain maps too, in 16 bits (compact_calib) */
			po.compact = &cal->apply_vec;
			po.trusted = NULL;
			po.dark = po.gain_inv = NULL;
			po.black_level = 0;
			if (dr != 1 && cal->apply_vec.dark_q) {
				/* dark = base + scale·q, so its part above the black level
				 * B times r is (B + r·(base − B)) + (r·scale)·q */
				cv = cal->apply_vec;
				const double bl = cal->black_level;
				cv.dark_base = (float)(bl + dr * ((double)cv.dark_base - bl));
				cv.dark_scale = (float)(dr * (double)cv.dark_scale);
				po.compact = &cv;
			}
		} else {
			po.pinv = &pinv;
		}
	}
	return st ? pc_stokes_run(raw, &po, st, valid) : pc_demosaic_run(raw, &po, ch, valid);
}

double pc_calib_noise_gain(const pc_calib *cal, double gain_db, bool *scaled)
{
	/* the analog gain multiplies the system gain K of EMVA Standard 1288 (the DN per
	 * electron); a gain in dB is 20·log10 of that factor (GenICam SFNC: Gain, GainDB). The
	 * simulator's sensor model is the same (polarcam/sim.h, gain_db) */
	const bool sc = cal->system_gain > 0 && isfinite(cal->system_gain_db) && isfinite(gain_db);
	if (scaled)
		*scaled = sc;
	if (!(cal->system_gain > 0))
		return 0;
	return sc ? cal->system_gain * pow(10.0, (gain_db - cal->system_gain_db) / 20.0)
	          : cal->system_gain;
}

double pc_calib_dark_scale(const pc_calib *cal, double gain_db, bool *scaled)
{
	/* the dark signal above the black level is electrons (DSNU, dark current) times the
	 * system gain K, and K follows the analog gain as pc_calib_noise_gain's does (EMVA
	 * Standard 1288, the sensor model: μ_y.dark = μ_y.offset + K·μ_d) */
	const bool sc = cal->dark && isfinite(cal->dark_gain_db) && isfinite(gain_db);
	if (scaled)
		*scaled = sc;
	return sc ? pow(10.0, (gain_db - cal->dark_gain_db) / 20.0) : 1.0;
}

static int stage_run(void *user, const pc_frame *f, unsigned bits, const pc_pipeline_opts *o,
                     const pc_stokes_out *st, const pc_fplane *ch, pc_validity *valid)
{
	return pc_calib_apply(user, f, bits, o, st, ch, valid);
}

pc_raw_stage pc_calib_stage(pc_calib *cal, const char *name)
{
	return (pc_raw_stage){stage_run, cal, name, cal->saturation, cal->system_gain};
}
