/* The seed paper's Figs. 2–11 under the corrected model, and its claims checked
 * (polarcam/figures.h; physics.md §8, docs/figures.md). */
#include "polarcam/figures.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "polarcam/decompose.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

#define DEG (PC_PI / 180)

typedef struct quantities {
	double dop, D, R, Delta;
} quantities;

const char *pc_verdict_name(pc_verdict v)
{
	static const char *const names[] = {"does not reproduce", "reproduces", "partly"};
	return v >= PC_VERDICT_NO && v <= PC_VERDICT_PARTLY ? names[v] : "?";
}

/* the claims found so far */
typedef struct claims {
	pc_figure_claim *c;
	size_t n, max;
} claims;

static void claim(claims *r, int fig, const char *text, pc_verdict v, pc_verdict vp,
                  const char *evidence)
{
	if (r->n >= r->max)
		return;
	pc_figure_claim *c = &r->c[r->n++];
	c->figure = fig;
	c->text = text;
	c->corrected = v;
	c->printed = vp;
	snprintf(c->evidence, sizeof c->evidence, "%s", evidence);
}

/* D, R, Δ and DoP at one geometry, for the corrected model and for the paper's printed
 * normalisation P_D with 4πσ² (specular part × 2, diffuse (1 − 2ρ^s)/π · a(β): paper eqs. 3, 11,
 * 12 as printed, with everything else corrected). */
static void point(const pc_pbrdf *spec, const pc_pbrdf *full, double ti, double tr, double dphi,
                  quantities *q, quantities *qp)
{
	double f[4][4], fs[4][4];
	pc_pbrdf_eval(full, ti, tr, dphi, f);
	pc_pbrdf_eval(spec, ti, tr, dphi, fs);
	const pc_material *m = pc_pbrdf_material(full);
	double ki[3] = {sin(ti), 0, cos(ti)};
	double kr[3] = {sin(tr) * cos(dphi), sin(tr) * sin(dphi), cos(tr)};
	double c2b = ki[0] * kr[0] + ki[1] * kr[1] + ki[2] * kr[2]; /* cos 2β, paper eq. 4 */
	double beta = 0.5 * acos(c2b > 1 ? 1 : c2b < -1 ? -1 : c2b);
	double a = pc_fresnel_reflectance(m->n, m->k, beta);
	double rho = pc_pbrdf_rho_s_fast(full, cos(ti));
	double fp[4][4];
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			fp[i][j] = 2 * fs[i][j];
	fp[0][0] += (1 - 2 * rho) / PC_PI * a;
	const double(*mats[2])[4] = {f, fp};
	quantities *outs[2] = {q, qp};
	for (int k = 0; k < 2; k++) {
		quantities *o = outs[k];
		o->dop = o->D = o->R = o->Delta = NAN;
		const double(*M)[4] = mats[k];
		if (!(M[0][0] > 0))
			continue;
		o->dop = pc_mueller_dop(M); /* eq. 21 */
		pc_lu_chipman lc;
		if (pc_lu_chipman_decompose(M, PC_LC_NO_FACTORS, &lc) == 0) {
			o->D = lc.D;
			o->R = lc.R;
			o->Delta = lc.Delta;
		}
	}
}

static int make_pair(double n, double k, double sigma, pc_pbrdf **spec, pc_pbrdf **full)
{
	pc_material ms = {n, k, sigma, PC_DIFFUSE_NONE, PC_SHADOW_TS, PC_RHO_QUAD, 64};
	pc_material mf = ms;
	mf.diffuse = PC_DIFFUSE_FRESNEL;
	int rc = pc_pbrdf_new(&ms, spec);
	if (!rc)
		rc = pc_pbrdf_new(&mf, full);
	return rc;
}

static int argmax(const double *y, int n)
{
	int k = 0;
	for (int i = 1; i < n; i++)
		if (y[i] > y[k])
			k = i;
	return k;
}

static int argmin(const double *y, int n)
{
	int k = 0;
	for (int i = 1; i < n; i++)
		if (y[i] < y[k])
			k = i;
	return k;
}

/* index of the first x ≥ v */
static int xi(const pc_figure *F, double v)
{
	for (int i = 0; i < F->nx; i++)
		if (F->x[i] >= v - 1e-9)
			return i;
	return F->nx - 1;
}

/* fraction of steps in [i0, i1] where y increases (sign = +1) or decreases (−1) */
static double monotone(const double *y, int i0, int i1, int sign)
{
	int good = 0, n = 0;
	for (int i = i0; i < i1; i++) {
		n++;
		if (sign * (y[i + 1] - y[i]) > -1e-12)
			good++;
	}
	return n ? (double)good / n : 1;
}

/* an interior maximum (sign = +1) or minimum (−1): the extremum is not at an end and stands out
 * from both ends by more than 1e-3 */
static bool interior_extremum(const double *y, int n, int sign, int *at)
{
	int k = sign > 0 ? argmax(y, n) : argmin(y, n);
	*at = k;
	return k > 0 && k < n - 1 && sign * (y[k] - y[0]) > 1e-3 && sign * (y[k] - y[n - 1]) > 1e-3;
}

static pc_verdict all_any(int good, int total)
{
	return good == total ? PC_VERDICT_YES : good == 0 ? PC_VERDICT_NO : PC_VERDICT_PARTLY;
}

/* Claim families, evaluated on the corrected curves (y) and on the printed ones (yp). */
static pc_verdict c_interior(const pc_figure *F, int sign, bool printed, char *ev, size_t evn)
{
	int good = 0;
	size_t o = 0;
	for (int c = 0; c < F->nc; c++) {
		const double *y = printed ? F->c[c].yp : F->c[c].y;
		int at;
		bool ok = interior_extremum(y, F->nx, sign, &at);
		good += ok;
		if (!printed)
			o +=
			    (size_t)snprintf(ev + o, o < evn ? evn - o : 0, "%s%s: %s %.3f at %g%s",
			                     c ? "; " : "", F->c[c].label, sign > 0 ? "max" : "min",
			                     y[at], F->x[at], ok ? "" : " (at an end)");
	}
	return all_any(good, F->nc);
}

static pc_verdict c_monotone(const pc_figure *F, double x0, double x1, int sign, bool printed,
                             char *ev, size_t evn)
{
	int good = 0, i0 = xi(F, x0), i1 = xi(F, x1);
	size_t o = 0;
	for (int c = 0; c < F->nc; c++) {
		const double *y = printed ? F->c[c].yp : F->c[c].y;
		double fr = monotone(y, i0, i1, sign);
		good += fr >= 0.999;
		if (!printed)
			o += (size_t)snprintf(ev + o, o < evn ? evn - o : 0,
			                      "%s%s: %.3f -> %.3f (%.0f%% of steps %s)",
			                      c ? "; " : "", F->c[c].label, y[i0], y[i1], 100 * fr,
			                      sign > 0 ? "rising" : "falling");
	}
	return all_any(good, F->nc);
}

/* "a larger curve parameter gives a larger (sign +1) or smaller (−1) value" on [x0, x1]: the
 * curves are ordered at every point of the range. */
static pc_verdict c_ordered(const pc_figure *F, double x0, double x1, int sign, bool printed,
                            char *ev, size_t evn)
{
	int i0 = xi(F, x0), i1 = xi(F, x1), good = 0, n = 0;
	for (int i = i0; i <= i1; i++) {
		bool ok = true;
		for (int c = 0; c + 1 < F->nc; c++) {
			const double *a = printed ? F->c[c].yp : F->c[c].y;
			const double *b = printed ? F->c[c + 1].yp : F->c[c + 1].y;
			if (!(sign * (b[i] - a[i]) > 0))
				ok = false;
		}
		good += ok;
		n++;
	}
	if (!printed) {
		int im = (i0 + i1) / 2;
		size_t o = (size_t)snprintf(ev, evn,
		                            "ordered at %d of %d points in [%g, %g]; at %g:", good,
		                            n, x0, x1, F->x[im]);
		for (int c = 0; c < F->nc; c++)
			o += (size_t)snprintf(ev + o, o < evn ? evn - o : 0, " %s %.3f",
			                      F->c[c].label, F->c[c].y[im]);
	}
	return good == n ? PC_VERDICT_YES : good == 0 ? PC_VERDICT_NO : PC_VERDICT_PARTLY;
}

/* ---------------------------------------------------------------------------------------- */

static const struct {
	double n, k, sigma;
} green = {1.47, 0.47, 0.1}, black = {1.46, 1.28, 0.2};
static const double theta_r_set[4] = {15, 30, 45, 60};
static const double sigma_set[3] = {0.2, 0.5, 0.7};

int pc_figures_compute(pc_figure figs[12])
{
	pc_pbrdf *gs = NULL, *gf = NULL, *bs = NULL, *bf = NULL;
	pc_pbrdf *rs[3] = {NULL}, *rf[3] = {NULL};
	int rc = make_pair(green.n, green.k, green.sigma, &gs, &gf);
	if (!rc)
		rc = make_pair(black.n, black.k, black.sigma, &bs, &bf);
	for (int i = 0; i < 3 && !rc; i++)
		rc = make_pair(black.n, black.k, sigma_set[i], &rs[i], &rf[i]);
	if (rc)
		goto out;
	quantities q, qp;
	/* Fig. 2 */
	pc_figure *F = &figs[2];
	memset(F, 0, sizeof *F);
	F->num = 2;
	F->title = "DoP vs incidence angle, theta_r = 60 deg, dphi = 180 deg";
	F->xname = "theta_i_deg";
	F->xlabel = "incidence angle theta_i (deg)";
	F->yname = "DoP";
	F->ylabel = "degree of polarization (eq. 21)";
	F->nc = 2;
	snprintf(F->c[0].label, sizeof F->c[0].label, "green paint");
	snprintf(F->c[1].label, sizeof F->c[1].label, "black paint");
	F->nx = 179;
	for (int i = 0; i < F->nx; i++) {
		F->x[i] = 0.5 * i;
		point(gs, gf, F->x[i] * DEG, 60 * DEG, PC_PI, &q, &qp);
		F->c[0].y[i] = q.dop;
		F->c[0].yp[i] = qp.dop;
		point(bs, bf, F->x[i] * DEG, 60 * DEG, PC_PI, &q, &qp);
		F->c[1].y[i] = q.dop;
		F->c[1].yp[i] = qp.dop;
	}
	/* Figs. 3–5 (vs θ_i), 6–8 (vs Δφ), 9–11 (vs θ_i, σ) */
	static const char *qn[3] = {"D", "R_rad", "Delta"};
	static const char *ql[3] = {"diattenuation D", "retardance R (rad)",
	                            "depolarization Delta (eq. 18)"};
	for (int g = 0; g < 3; g++)
		for (int qi = 0; qi < 3; qi++) {
			F = &figs[3 + 3 * g + qi];
			F->num = 3 + 3 * g + qi;
			F->yname = qn[qi];
			F->ylabel = ql[qi];
			F->title = g == 0 ? "vs incidence angle, dphi = 180 deg, black paint"
			           : g == 1
			               ? "vs relative azimuth, theta_i = 60 deg, black paint"
			               : "vs incidence angle, theta_r = 30 deg, dphi = 180 deg";
			F->xname = g == 1 ? "dphi_deg" : "theta_i_deg";
			F->xlabel = g == 1 ? "relative azimuth dphi (deg)"
			                   : "incidence angle theta_i (deg)";
			F->nc = g == 2 ? 3 : 4;
			for (int c = 0; c < F->nc; c++) {
				if (g == 2)
					snprintf(F->c[c].label, sizeof F->c[c].label,
					         "sigma = %.1f", sigma_set[c]);
				else
					snprintf(F->c[c].label, sizeof F->c[c].label,
					         "theta_r = %.0f", theta_r_set[c]);
			}
			F->nx = g == 1 ? 181 : 179;
			for (int i = 0; i < F->nx; i++)
				F->x[i] = g == 1 ? i : 0.5 * i;
		}
	for (int g = 0; g < 3; g++)
		for (int c = 0; c < (g == 2 ? 3 : 4); c++)
			for (int i = 0; i < figs[3 + 3 * g].nx; i++) {
				double x = figs[3 + 3 * g].x[i];
				if (g == 0)
					point(bs, bf, x * DEG, theta_r_set[c] * DEG, PC_PI, &q,
					      &qp);
				else if (g == 1)
					point(bs, bf, 60 * DEG, theta_r_set[c] * DEG, x * DEG, &q,
					      &qp);
				else
					point(rs[c], rf[c], x * DEG, 30 * DEG, PC_PI, &q, &qp);
				double v[3] = {q.D, q.R, q.Delta}, vp[3] = {qp.D, qp.R, qp.Delta};
				for (int qi = 0; qi < 3; qi++) {
					figs[3 + 3 * g + qi].c[c].y[i] = v[qi];
					figs[3 + 3 * g + qi].c[c].yp[i] = vp[qi];
				}
			}
out:
	pc_pbrdf_free(gs);
	pc_pbrdf_free(gf);
	pc_pbrdf_free(bs);
	pc_pbrdf_free(bf);
	for (int i = 0; i < 3; i++) {
		pc_pbrdf_free(rs[i]);
		pc_pbrdf_free(rf[i]);
	}
	return rc;
}

#define EVN 1024

static void check_claims(const pc_figure *figs, claims *r)
{
	char ev[EVN], dummy[EVN];
	pc_verdict v, vp;
	const pc_figure *F = &figs[2];
	{
		size_t o = 0;
		for (int c = 0; c < 2; c++) {
			int k = argmax(F->c[c].y, F->nx), kp = argmax(F->c[c].yp, F->nx);
			o += (size_t)snprintf(
			    ev + o, EVN - o,
			    "%s%s: peak DoP %.3f at theta_i = %g (printed: %.3f at %g)",
			    c ? "; " : "", F->c[c].label, F->c[c].y[k], F->x[k], F->c[c].yp[kp],
			    F->x[kp]);
		}
		claim(r, 2,
		      "computed DoP agrees with the measurements of Thilak et al. (peak near the "
		      "specular angle)",
		      PC_VERDICT_PARTLY, PC_VERDICT_PARTLY,
		      ev); /* no measured data here: only the shape can be compared */
	}
	F = &figs[3];
	v = c_interior(F, +1, false, ev, EVN);
	vp = c_interior(F, +1, true, dummy, EVN);
	claim(r, 3, "D has a maximum inside theta_i in (0, 90)", v, vp, ev);
	v = c_monotone(F, 0, 60, +1, false, ev, EVN);
	vp = c_monotone(F, 0, 60, +1, true, dummy, EVN);
	claim(r, 3, "D increases with theta_i on (0, 60)", v, vp, ev);
	v = c_ordered(F, 0, 89, +1, false, ev, EVN);
	vp = c_ordered(F, 0, 89, +1, true, dummy, EVN);
	claim(r, 3, "a larger theta_r gives a larger D overall", v, vp, ev);

	F = &figs[4];
	v = c_monotone(F, 0, 89, -1, false, ev, EVN);
	vp = c_monotone(F, 0, 89, -1, true, dummy, EVN);
	claim(r, 4, "R decreases as theta_i increases, for every theta_r", v, vp, ev);
	v = c_ordered(F, 0, 89, +1, false, ev, EVN);
	vp = c_ordered(F, 0, 89, +1, true, dummy, EVN);
	{
		/* in-plane R depends on β = (θ_i + θ_r)/2 only (physics.md §2): same β, same R */
		int i = xi(F, 45), j = xi(F, 30);
		char more[256];
		snprintf(more, sizeof more,
		         "; R(theta_i 45, theta_r 15) = %.6f vs R(theta_i 30, theta_r 30) = %.6f "
		         "(same beta): R depends on theta_i + theta_r only",
		         F->c[0].y[i], F->c[1].y[j]);
		strncat(ev, more, EVN - strlen(ev) - 1);
	}
	claim(r, 4, "a larger theta_r gives a larger R overall", v, vp, ev);

	F = &figs[5];
	v = c_interior(F, -1, false, ev, EVN);
	vp = c_interior(F, -1, true, dummy, EVN);
	claim(r, 5, "Delta has a minimum inside theta_i in (0, 90) (falls, then rises)", v, vp, ev);
	v = c_ordered(F, 0, 45, +1, false, ev, EVN);
	vp = c_ordered(F, 0, 45, +1, true, dummy, EVN);
	claim(r, 5, "for theta_i in (0, 45) a larger theta_r depolarizes more", v, vp, ev);

	F = &figs[6];
	v = c_monotone(F, 0, 180, +1, false, ev, EVN);
	vp = c_monotone(F, 0, 180, +1, true, dummy, EVN);
	claim(r, 6, "D increases with dphi on (0, 180)", v, vp, ev);
	{
		/* steepest rise near 90°? */
		size_t o = 0;
		int good = 0, goodp = 0;
		for (int c = 0; c < F->nc; c++) {
			int kmax = 1, kmaxp = 1;
			for (int i = 1; i < F->nx; i++) {
				if (F->c[c].y[i] - F->c[c].y[i - 1] >
				    F->c[c].y[kmax] - F->c[c].y[kmax - 1])
					kmax = i;
				if (F->c[c].yp[i] - F->c[c].yp[i - 1] >
				    F->c[c].yp[kmaxp] - F->c[c].yp[kmaxp - 1])
					kmaxp = i;
			}
			good += fabs(F->x[kmax] - 90) <= 30;
			goodp += fabs(F->x[kmaxp] - 90) <= 30;
			o += (size_t)snprintf(ev + o, EVN - o, "%s%s: steepest at %g",
			                      c ? "; " : "", F->c[c].label, F->x[kmax] - 0.5);
		}
		claim(r, 6, "the rise of D is steepest near dphi = 90", all_any(good, F->nc),
		      all_any(goodp, F->nc), ev);
	}
	v = c_ordered(F, 0, 30, -1, false, ev, EVN);
	vp = c_ordered(F, 0, 30, -1, true, dummy, EVN);
	claim(r, 6, "at small dphi a larger theta_r gives a smaller D", v, vp, ev);
	v = c_ordered(F, 150, 180, +1, false, ev, EVN);
	vp = c_ordered(F, 150, 180, +1, true, dummy, EVN);
	claim(r, 6, "at large dphi a larger theta_r gives a larger D", v, vp, ev);

	F = &figs[7];
	v = c_interior(F, +1, false, ev, EVN);
	vp = c_interior(F, +1, true, dummy, EVN);
	claim(r, 7, "R rises then falls with dphi: a maximum inside (0, 180)", v, vp, ev);
	v = c_ordered(F, 0, 180, -1, false, ev, EVN);
	vp = c_ordered(F, 0, 180, -1, true, dummy, EVN);
	claim(r, 7, "a larger theta_r gives a smaller R overall", v, vp, ev);

	F = &figs[8];
	v = c_monotone(F, 0, 180, -1, false, ev, EVN);
	vp = c_monotone(F, 0, 180, -1, true, dummy, EVN);
	claim(r, 8, "Delta decreases as dphi increases", v, vp, ev);
	{
		size_t o = 0;
		double spread_lo = 0, spread_hi = 0;
		int i0 = 0, i1 = F->nx - 1;
		double mn0 = 1e9, mx0 = -1e9, mn1 = 1e9, mx1 = -1e9;
		for (int c = 0; c < F->nc; c++) {
			mn0 = fmin(mn0, F->c[c].y[i0]);
			mx0 = fmax(mx0, F->c[c].y[i0]);
			mn1 = fmin(mn1, F->c[c].y[i1]);
			mx1 = fmax(mx1, F->c[c].y[i1]);
		}
		spread_lo = mx0 - mn0;
		spread_hi = mx1 - mn1;
		o += (size_t)snprintf(
		    ev + o, EVN - o,
		    "spread of Delta over theta_r: %.3f at dphi = 0, %.3f at dphi = 180", spread_lo,
		    spread_hi);
		double p0 = 1e9, p1 = -1e9, p2 = 1e9, p3 = -1e9;
		for (int c = 0; c < F->nc; c++) {
			p0 = fmin(p0, F->c[c].yp[i0]);
			p1 = fmax(p1, F->c[c].yp[i0]);
			p2 = fmin(p2, F->c[c].yp[i1]);
			p3 = fmax(p3, F->c[c].yp[i1]);
		}
		claim(r, 8, "at large dphi the curves for different theta_r nearly coincide",
		      spread_hi < 0.5 * spread_lo ? PC_VERDICT_YES : PC_VERDICT_NO,
		      (p3 - p2) < 0.5 * (p1 - p0) ? PC_VERDICT_YES : PC_VERDICT_NO, ev);
	}

	F = &figs[9];
	v = c_interior(F, +1, false, ev, EVN);
	vp = c_interior(F, +1, true, dummy, EVN);
	claim(r, 9, "D rises then falls with theta_i: a maximum inside (0, 90), for every sigma", v,
	      vp, ev);
	{
		double m[3], mp[3];
		for (int c = 0; c < 3; c++) {
			m[c] = F->c[c].y[argmax(F->c[c].y, F->nx)];
			mp[c] = F->c[c].yp[argmax(F->c[c].yp, F->nx)];
		}
		snprintf(ev, EVN, "max D: %.4f (sigma 0.2), %.4f (0.5), %.4f (0.7)", m[0], m[1],
		         m[2]);
		claim(r, 9, "a rougher surface has a larger maximum D",
		      m[0] < m[1] && m[1] < m[2] ? PC_VERDICT_YES : PC_VERDICT_NO,
		      mp[0] < mp[1] && mp[1] < mp[2] ? PC_VERDICT_YES : PC_VERDICT_NO, ev);
	}
	F = &figs[10];
	{
		double worst = 0, worstp = 0;
		for (int i = 0; i < F->nx; i++)
			for (int c = 1; c < 3; c++) {
				worst = fmax(worst, fabs(F->c[c].y[i] - F->c[0].y[i]));
				if (isfinite(F->c[c].yp[i]) && isfinite(F->c[0].yp[i]))
					worstp = fmax(worstp, fabs(F->c[c].yp[i] - F->c[0].yp[i]));
			}
		snprintf(
		    ev, EVN,
		    "largest difference of R between sigma = 0.2, 0.5, 0.7: %.2e rad (in-plane R "
		    "is arg(r_s/r_p) at beta = (theta_i + theta_r)/2 for every sigma)",
		    worst);
		claim(r, 10, "R vs theta_i does not depend on sigma",
		      worst < 1e-9 ? PC_VERDICT_YES : PC_VERDICT_NO,
		      worstp < 1e-9 ? PC_VERDICT_YES : PC_VERDICT_NO, ev);
	}
	F = &figs[11];
	v = c_interior(F, -1, false, ev, EVN);
	vp = c_interior(F, -1, true, dummy, EVN);
	claim(r, 11, "Delta falls then rises with theta_i: a minimum inside (0, 90)", v, vp, ev);
	v = c_ordered(F, 45, 89, +1, false, ev, EVN);
	vp = c_ordered(F, 45, 89, +1, true, dummy, EVN);
	claim(r, 11, "for theta_i in (45, 90) a rougher surface depolarizes more", v, vp, ev);
}

size_t pc_figures_check(const pc_figure figs[12], pc_figure_claim *out, size_t max)
{
	claims r = {out, 0, max};
	check_claims(figs, &r);
	return r.n;
}
