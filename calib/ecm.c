/* calib/ecm.c - the eigenvalue calibration method (Compain, Poirier & Drévillon, "General and
 * self-consistent method for the calibration of polarization modulators, polarimeters, and
 * Mueller-matrix ellipsometers", Appl. Opt. 38(16) 3490, 1999; "ECM" below, equation numbers
 * of that paper). Linear algebra: LAPACK (dgeev, dsyev, dgesv).
 *
 *   B_i = A·M_i·W (eq. 1): intensity matrices of reference samples i, A the analyser
 *   ((4·n_psa) × 4 here: four DoFP channels per PSA state), W the generator (4 × 4).
 *   C_i = B_0⁺·B_i = W⁻¹·M_i·W (eq. 4, with B_0 = A·W of air and A of full column rank):
 *   C_i is similar to M_i, so its eigenvalues are those of M_i and give the sample's τ, ψ, Δ
 *   (eqs. 8–10). W solves M_i·X − X·C_i = 0 for every sample (eq. 11); with
 *   H_i = I⊗M_i − C_iᵀ⊗I (column-major vec) and K = Σ H_iᵀH_i (eq. 13), W is the eigenvector
 *   of K's smallest eigenvalue λ16, the other 15 being clearly non-zero when the samples are
 *   well chosen (eq. 14: λ15/λ16 measures it). The samples' unknown orientations are those that
 *   minimise λ16 (the paper's §4.B). A = B_0·W⁻¹ (eq. 15).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/calib.h"
#include "calib_internal.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"

#define DEG (3.14159265358979323846 / 180.0)

/* LAPACK (Fortran calling convention, column-major). */
extern void dgeev_(const char *jobvl, const char *jobvr, const int *n, double *a, const int *lda,
                   double *wr, double *wi, double *vl, const int *ldvl, double *vr, const int *ldvr,
                   double *work, const int *lwork, int *info);
extern void dsyev_(const char *jobz, const char *uplo, const int *n, double *a, const int *lda,
                   double *w, double *work, const int *lwork, int *info);
extern void dgesv_(const int *n, const int *nrhs, double *a, const int *lda, int *ipiv, double *b,
                   const int *ldb, int *info);

void pc_ecm_sample_mueller(double tau, double psi, double delta, double theta, double M[4][4])
{
	/* ECM eq. 9: M₀ = τ[[1, cos2ψ, 0, 0], [cos2ψ, 1, 0, 0], [0, 0, sin2ψ cosΔ, sin2ψ sinΔ],
	 * [0, 0, −sin2ψ sinΔ, sin2ψ cosΔ]] (transmission axis along x when cos 2ψ > 0), then
	 * M = R(−θ)·M₀·R(θ) with R the rotator of physics.md §2 (pc_mueller_rotator). */
	double c = cos(2 * psi), s = sin(2 * psi);
	double M0[4][4] = {{tau, tau * c, 0, 0},
	                   {tau * c, tau, 0, 0},
	                   {0, 0, tau * s * cos(delta), tau * s * sin(delta)},
	                   {0, 0, -tau * s * sin(delta), tau * s * cos(delta)}};
	double Rp[4][4], Rm[4][4], T[4][4];
	pc_mueller_rotator(theta, Rp);
	pc_mueller_rotator(-theta, Rm);
	pc_mueller_mul(M0, Rp, T);
	pc_mueller_mul(Rm, T, M);
}

/* Solves the 4×4 system a·x = b for nrhs right-hand sides (column-major b); 0 or −1. */
static int solve4(const double a_cm[16], double *b, int nrhs)
{
	double a[16];
	memcpy(a, a_cm, sizeof a);
	int n = 4, ipiv[4], info = 0;
	dgesv_(&n, &nrhs, a, &n, ipiv, b, &n, &info);
	return info ? -1 : 0;
}

/* The sample's parameters from the eigenvalues of C (ECM eqs. 8–10): the complex pair
 * τ sin2ψ e^{±iΔ} and the real pair 2τcos²ψ, 2τsin²ψ. polarizer: Δ may be undefined (all real:
 * then Δ = 0). */
static int sample_params(const double C[4][4], bool polarizer, double *tau, double *psi,
                         double *delta)
{
	double a[16], wr[4], wi[4], work[64];
	for (int r = 0; r < 4; r++)
		for (int c = 0; c < 4; c++)
			a[r + 4 * c] = C[r][c];
	int n = 4, one = 1, lw = 64, info = 0;
	dgeev_("N", "N", &n, a, &n, wr, wi, NULL, &one, NULL, &one, work, &lw, &info);
	if (info)
		return -1;
	int ci = -1;
	double maxim = 0;
	for (int i = 0; i < 4; i++)
		if (wi[i] > maxim) {
			maxim = wi[i];
			ci = i;
		}
	double scale = fmax(fmax(fabs(wr[0]), fabs(wr[1])), fmax(fabs(wr[2]), fabs(wr[3])));
	double r1, r2;
	if (ci >= 0 && maxim > 1e-6 * scale) {
		*delta = atan2(wi[ci], wr[ci]);
		int cj = -1; /* the conjugate partner of ci */
		for (int i = 0; i < 4; i++)
			if (i != ci && wi[i] < 0 &&
			    (cj < 0 || fabs(wi[i] + wi[ci]) < fabs(wi[cj] + wi[ci])))
				cj = i;
		double re[2] = {0, 0};
		int k = 0;
		for (int i = 0; i < 4; i++)
			if (i != ci && i != cj && k < 2)
				re[k++] = wr[i];
		r1 = fmax(re[0], re[1]);
		r2 = fmin(re[0], re[1]);
	} else {
		if (!polarizer)
			return -2; /* a retarder needs Δ away from 0 and π */
		double s[4];
		memcpy(s, wr, sizeof s);
		for (int i = 0; i < 4; i++)
			for (int j = i + 1; j < 4; j++)
				if (s[j] > s[i]) {
					double t = s[i];
					s[i] = s[j];
					s[j] = t;
				}
		r1 = s[0];
		r2 = fmax(s[3], 0);
		*delta = s[1] + s[2] >= 0 ? 0 : 3.14159265358979323846;
	}
	if (!(r1 > 0))
		return -1;
	if (r2 < 0)
		r2 = 0;
	*tau = (r1 + r2) / 2;
	*psi = atan(sqrt(r2 / r1));
	return 0;
}

/* K = Σ_i H_iᵀH_i for the samples 1..3 (air gives H = 0) and its eigen-decomposition. */
static int k_matrix(const double M[4][4][4], const double C[4][4][4], double eval[16],
                    double evec[256])
{
	double K[256] = {0};
	for (int i = 1; i < 4; i++) {
		double H[16][16] = {{0}};
		for (int r = 0; r < 4; r++)
			for (int c = 0; c < 4; c++)
				for (int k = 0; k < 4; k++) {
					H[r + 4 * c][k + 4 * c] += M[i][r][k];
					H[r + 4 * c][r + 4 * k] -= C[i][k][c];
				}
		for (int a = 0; a < 16; a++)
			for (int b = 0; b < 16; b++) {
				double s = 0;
				for (int k = 0; k < 16; k++)
					s += H[k][a] * H[k][b];
				K[a + 16 * b] += s;
			}
	}
	int n = 16, lw = 16 * 34, info = 0;
	double work[16 * 34];
	dsyev_(evec ? "V" : "N", "U", &n, K, &n, eval, work, &lw, &info);
	if (info)
		return -1;
	if (evec)
		memcpy(evec, K, sizeof K);
	return 0;
}

typedef struct ecm_ctx {
	double C[4][4][4];
	double tau[4], psi[4], delta[4];
} ecm_ctx;

static double objective(const ecm_ctx *e, const double theta[4], double M[4][4][4])
{
	for (int i = 1; i < 4; i++)
		pc_ecm_sample_mueller(e->tau[i], e->psi[i], e->delta[i], theta[i], M[i]);
	double ev[16];
	if (k_matrix((const double(*)[4][4])M, (const double(*)[4][4])e->C, ev, NULL))
		return INFINITY;
	return ev[0] / ev[1];
}

/* Golden-section minimisation of the objective over theta[idx] in [lo, hi]. */
static void golden(const ecm_ctx *e, double theta[4], int idx, double lo, double hi)
{
	double M[4][4][4];
	const double g = (sqrt(5.0) - 1) / 2;
	double a = lo, b = hi, x1 = b - g * (b - a), x2 = a + g * (b - a);
	theta[idx] = x1;
	double f1 = objective(e, theta, M);
	theta[idx] = x2;
	double f2 = objective(e, theta, M);
	for (int it = 0; it < 80 && b - a > 1e-10; it++) {
		if (f1 < f2) {
			b = x2;
			x2 = x1;
			f2 = f1;
			x1 = b - g * (b - a);
			theta[idx] = x1;
			f1 = objective(e, theta, M);
		} else {
			a = x1;
			x1 = x2;
			f1 = f2;
			x2 = a + g * (b - a);
			theta[idx] = x2;
			f2 = objective(e, theta, M);
		}
	}
	theta[idx] = (a + b) / 2;
}

int pc_ecm_solve(const double *const B[4], unsigned n_psg, unsigned n_psa,
                 const double theta_guess_deg[2], pc_ecm_result *r)
{
	memset(r, 0, sizeof *r);
	if (n_psg != 4)
		return pc_error(PC_EINVAL,
		                "ECM: %u generator states: exactly 4 are needed (a 4x4 "
		                "generator matrix)",
		                n_psg);
	if (n_psa < 1 || n_psa > PC_CALIB_MAX_STATES)
		return pc_error(PC_EINVAL, "ECM: %u analyser states", n_psa);
	const unsigned R = 4 * n_psa;
	for (int i = 0; i < 4; i++)
		for (unsigned k = 0; k < R * 4; k++)
			if (!isfinite(B[i][k]))
				return pc_error(PC_EINVAL, "ECM: sample %d: non-finite intensity",
				                i);
	/* B_0⁺ = (B_0ᵀB_0)⁻¹B_0ᵀ; C_i = B_0⁺B_i */
	double N[16], Bt[4 * 4 * PC_CALIB_MAX_STATES];
	for (int a = 0; a < 4; a++)
		for (int b = 0; b < 4; b++) {
			double s = 0;
			for (unsigned k = 0; k < R; k++)
				s += B[0][k * 4 + a] * B[0][k * 4 + b];
			N[a + 4 * b] = s;
		}
	for (int a = 0; a < 4; a++)
		for (unsigned k = 0; k < R; k++)
			Bt[a + 4 * k] = B[0][k * 4 + a]; /* column k of B_0ᵀ */
	if (solve4(N, Bt, (int)R))
		return pc_error(PC_ENUMERIC,
		                "ECM: the air measurement B_0 = A·W is singular (is every "
		                "generator and analyser state distinct?)");
	ecm_ctx e;
	memset(&e, 0, sizeof e);
	for (int i = 0; i < 4; i++)
		for (int a = 0; a < 4; a++)
			for (int b = 0; b < 4; b++) {
				double s = 0;
				for (unsigned k = 0; k < R; k++)
					s += Bt[a + 4 * k] * B[i][k * 4 + b];
				e.C[i][a][b] = s;
			}
	static const char *const names[4] = {"air", "polarizer 1", "polarizer 2", "retarder"};
	e.tau[0] = 1;
	for (int i = 1; i < 4; i++) {
		int rc = sample_params((const double(*)[4])e.C[i], i < 3, &e.tau[i], &e.psi[i],
		                       &e.delta[i]);
		if (rc)
			return pc_error(
			    PC_ENUMERIC, "ECM: %s: %s", names[i],
			    rc == -2 ? "its eigenvalues are all real: the retardance must be "
			               "away from 0 and 180 deg (a quarter-wave plate is best)"
			             : "eigenvalues undefined (singular fit)");
	}
	double theta[4] = {0, 0, (theta_guess_deg ? theta_guess_deg[0] : 90) * DEG,
	                   (theta_guess_deg ? theta_guess_deg[1] : 30) * DEG};
	const double span = 20 * DEG;
	double g2 = theta[2], g3 = theta[3];
	/* coordinate descent with golden-section line searches over shrinking brackets (the
	 * valley of λ16 may be diagonal in (θ2, θ3)), until both angles move by < 1e-10 rad */
	for (int pass = 0; pass < 400; pass++) {
		double o2 = theta[2], o3 = theta[3];
		double w = pass < 2
		               ? span
		               : fmax(4 * fmax(fabs(theta[2] - g2), fabs(theta[3] - g3)), 1e-7);
		if (pass >= 2)
			w = fmin(w, span);
		golden(&e, theta, 2, fmax(g2 - span, theta[2] - w), fmin(g2 + span, theta[2] + w));
		golden(&e, theta, 3, fmax(g3 - span, theta[3] - w), fmin(g3 + span, theta[3] + w));
		if (pass >= 2 && fabs(theta[2] - o2) < 1e-10 && fabs(theta[3] - o3) < 1e-10)
			break;
		g2 = pass >= 1 ? g2 : g2;
	}
	double M[4][4][4], ev[16], V[256];
	memset(M, 0, sizeof M);
	for (int k = 0; k < 4; k++)
		M[0][k][k] = 1;
	for (int i = 1; i < 4; i++)
		pc_ecm_sample_mueller(e.tau[i], e.psi[i], e.delta[i], theta[i], M[i]);
	if (k_matrix((const double(*)[4][4])M, (const double(*)[4][4])e.C, ev, V))
		return pc_error(PC_ENUMERIC, "ECM: eigen-decomposition of K failed");
	r->lambda16 = ev[0];
	r->lambda15 = ev[1];
	if (!(ev[1] > 1e3 * fmax(ev[0], 0)) || !(ev[1] > 1e-12 * ev[15]))
		return pc_error(PC_ENUMERIC,
		                "ECM: K's null space is not one-dimensional "
		                "(λ15/λ16 = %.3g, λ15/λ1 = %.3g): the reference samples "
		                "do not determine the generator (singular fit)",
		                ev[0] > 0 ? ev[1] / ev[0] : INFINITY, ev[1] / ev[15]);
	double Wcm[16]; /* W = vec⁻¹(eigenvector of λ16), column-major */
	memcpy(Wcm, V, sizeof Wcm);
	double m0 = 0;
	for (int g = 0; g < 4; g++)
		m0 += Wcm[0 + 4 * g];
	m0 /= 4;
	if (!(fabs(m0) > 0))
		return pc_error(PC_ENUMERIC, "ECM: the generator's intensities sum to 0");
	for (int k = 0; k < 16; k++)
		Wcm[k] /= m0;
	for (int a = 0; a < 4; a++)
		for (int g = 0; g < 4; g++)
			r->W[a][g] = Wcm[a + 4 * g];
	/* A = B_0·W⁻¹: solve Wᵀ·Aᵀ = B_0ᵀ */
	double Wt[16], rhs[4 * 4 * PC_CALIB_MAX_STATES];
	for (int a = 0; a < 4; a++)
		for (int b = 0; b < 4; b++)
			Wt[a + 4 * b] = Wcm[b + 4 * a];
	for (unsigned k = 0; k < R; k++)
		for (int a = 0; a < 4; a++)
			rhs[a + 4 * k] = B[0][k * 4 + a];
	if (solve4(Wt, rhs, (int)R))
		return pc_error(PC_ENUMERIC, "ECM: the recovered generator matrix is singular");
	for (unsigned k = 0; k < R; k++)
		for (int a = 0; a < 4; a++)
			r->A[k][a] = rhs[a + 4 * k];
	/* residual of the model on every sample */
	double worst = 0;
	for (int i = 0; i < 4; i++) {
		double num = 0, den = 0;
		for (unsigned k = 0; k < R; k++)
			for (int g = 0; g < 4; g++) {
				double s = 0;
				for (int a = 0; a < 4; a++)
					for (int b = 0; b < 4; b++)
						s += r->A[k][a] * M[i][a][b] * r->W[b][g];
				double d = s - B[i][k * 4 + g];
				num += d * d;
				den += B[i][k * 4 + g] * B[i][k * 4 + g];
			}
		worst = fmax(worst, den > 0 ? sqrt(num / den) : 0);
		r->tau[i] = e.tau[i];
		r->psi_deg[i] = e.psi[i] / DEG;
		r->delta_deg[i] = e.delta[i] / DEG;
		r->theta_deg[i] = theta[i] / DEG;
	}
	r->residual = worst;
	return 0;
}

int pc_calib_ecm(const pc_calib_stack samples[4], unsigned n_psg, unsigned n_psa,
                 const double theta_guess_deg[2], const pc_calib *base, const pc_calib_opts *o,
                 pc_calib *out, pc_ecm_result *res)
{
	pc_calib_init(out);
	const unsigned nf = n_psg * n_psa;
	if (nf == 0 || n_psa > PC_CALIB_MAX_STATES || n_psg > PC_CALIB_MAX_STATES)
		return pc_error(PC_EINVAL, "ECM: %u x %u states", n_psg, n_psa);
	const pc_calib_geometry *g = base ? &base->geo : &samples[0].geo;
	if (g->mosaic.period != 2)
		return pc_error(PC_ENOTSUP, "ECM: colour-polarization mosaics are not supported");
	const uint32_t W = g->width, H = g->height;
	const size_t np = (size_t)W * H;
	/* the samples' intensity matrices are compared with the air's: one analog gain */
	double gain_db;
	int rc = pc_calib_one_gain(samples, 4, "ECM", "the exposure", &gain_db);
	if (rc)
		return rc;
	double dr; /* the base's dark at that gain */
	if ((rc = pc_calib_base_dark_scale(base, gain_db, "ECM: recordings", &dr)))
		return rc;
	double *B[4] = {0};
	float *row = malloc(np * sizeof *row);
	if (!row)
		return pc_error(PC_ENOMEM, "ECM");
	double sat =
	    base && (!o || !(o->saturation > 0))
	        ? base->saturation
	        : (o && o->saturation > 0 ? o->saturation : (double)((1u << g->bits) - 1u));
	uint64_t done = 0, total = 0;
	for (int i = 0; i < 4; i++)
		total += samples[i].n;
	for (int i = 0; i < 4 && !rc; i++) {
		const pc_calib_stack *s = &samples[i];
		pc_calib tmp;
		pc_calib_init(&tmp);
		tmp.geo = *g;
		if ((rc = pc_calib_check(&tmp, &s->geo))) {
			rc = pc_error_prefix(rc, "%s: ", s->name);
			break;
		}
		if (s->n < nf || s->n % nf) {
			rc = pc_error(PC_EINVAL,
			              "%s: %zu frames: expected a multiple of the %u states "
			              "(%u generator x %u analyser)",
			              s->name, s->n, nf, n_psg, n_psa);
			break;
		}
		if (!(B[i] = calloc((size_t)4 * nf, sizeof(double)))) {
			rc = pc_error(PC_ENOMEM, "ECM");
			break;
		}
		for (size_t j = 0; j < s->n && !rc; j++) {
			pc_view v = {0};
			if ((rc = s->get(s->user, j, &v))) {
				rc = pc_error_prefix(rc, "%s: frame %zu: ", s->name, j);
				break;
			}
			rc = v.width != W || v.height != H
			         ? pc_error(PC_EINVAL, "%s: frame %zu is %ux%u, expected %ux%u",
			                    s->name, j, v.width, v.height, W, H)
			         : pc_view_to_f32(&v, row, (size_t)W * sizeof(float));
			pc_view_free(&v);
			if (rc)
				break;
			double sum[4] = {0}, n[4] = {0};
			size_t nsat = 0;
			for (uint32_t y = 0; y < H; y++)
				for (uint32_t x = 0; x < W; x++) {
					size_t p = (size_t)y * W + x;
					if (row[p] >= sat) {
						nsat++;
						continue;
					}
					if (base && base->valid && !base->valid[p])
						continue;
					double val = row[p] - pc_calib_dark_at(base, p, dr);
					if (base && base->gain)
						val /= base->gain[p];
					unsigned c = pc_mosaic_channel(&g->mosaic, x, y);
					sum[c] += val;
					n[c]++;
				}
			if (nsat > np / 1000) {
				rc = pc_error(PC_EINVAL,
				              "%s: frame %zu: %zu pixels saturated: lower the "
				              "exposure",
				              s->name, j, nsat);
				break;
			}
			unsigned st = (unsigned)(j % nf), gg = st % n_psg, aa = st / n_psg;
			for (int c = 0; c < 4; c++)
				B[i][(4 * aa + c) * n_psg + gg] +=
				    (n[c] ? sum[c] / n[c] : 0) / (double)(s->n / nf);
			done++;
			if (o && o->progress)
				o->progress(o->progress_user, done, total);
		}
	}
	free(row);
	pc_ecm_result r;
	if (!rc)
		rc = pc_ecm_solve((const double *const *)B, n_psg, n_psa, theta_guess_deg, &r);
	for (int i = 0; i < 4; i++)
		free(B[i]);
	if (rc)
		return rc;
	if (base)
		rc = pc_calib_copy(out, base);
	else {
		out->geo = *g;
		out->saturation = sat;
	}
	if (rc)
		return rc;
	out->n_psg = n_psg;
	out->n_psa = n_psa;
	memcpy(out->ecm_W, r.W, sizeof r.W);
	memcpy(out->ecm_A, r.A, sizeof r.A);
	out->parts |= PC_CAL_ECM;
	if (res)
		*res = r;
	return 0;
}
