#include "polarcam/mueller_imaging.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"

/* Eigen-decomposition of a symmetric 4×4 matrix by cyclic Jacobi rotations (Golub & Van Loan,
 * Matrix Computations, 4th ed., §8.5.2): S = V·diag(e)·Vᵀ. Converges quadratically; 4×4
 * needs a handful of sweeps. */
static void jacobi4(double S[4][4], double e[4], double V[4][4])
{
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			V[i][j] = i == j;
	for (int sweep = 0; sweep < 60; sweep++) {
		double off = 0, diag = 0;
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				if (i == j)
					diag += S[i][j] * S[i][j];
				else
					off += S[i][j] * S[i][j];
			}
		if (off <= 1e-32 * diag)
			break;
		for (int p = 0; p < 3; p++)
			for (int q = p + 1; q < 4; q++) {
				if (S[p][q] == 0)
					continue;
				double th = (S[q][q] - S[p][p]) / (2 * S[p][q]);
				double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
				double c = 1 / sqrt(t * t + 1), s = t * c;
				for (int k = 0; k < 4; k++) {
					double kp = S[k][p], kq = S[k][q];
					S[k][p] = c * kp - s * kq;
					S[k][q] = s * kp + c * kq;
				}
				for (int k = 0; k < 4; k++) {
					double pk = S[p][k], qk = S[q][k];
					S[p][k] = c * pk - s * qk;
					S[q][k] = s * pk + c * qk;
				}
				for (int k = 0; k < 4; k++) {
					double vp = V[k][p], vq = V[k][q];
					V[k][p] = c * vp - s * vq;
					V[k][q] = s * vp + c * vq;
				}
			}
	}
	for (int i = 0; i < 4; i++)
		e[i] = S[i][i];
}

/* Pseudo-inverse pieces of an n×4 matrix X (rows) through XᵀX = V·diag(e)·Vᵀ: the Moore–Penrose
 * inverse X⁺ = V·diag(1/e_i, for e_i above the rank threshold)·Vᵀ·Xᵀ (Golub & Van Loan §5.5.2).
 * Returns the rank and the condition number of the determined part; inv_gram = (XᵀX)⁺ and the
 * mask of determined coordinates (unit vectors inside the range). */
static unsigned pinv_setup(const double *X, size_t ld, unsigned n, double inv_gram[4][4],
			   double *cond, unsigned *mask)
{
	double S[4][4] = { { 0 } }, e[4], V[4][4];
	for (unsigned r = 0; r < n; r++)
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				S[i][j] += X[r * ld + (size_t)i] * X[r * ld + (size_t)j];
	jacobi4(S, e, V);
	double emax = fmax(fmax(e[0], e[1]), fmax(e[2], e[3]));
	double emin = INFINITY;
	unsigned rank = 0;
	bool keep[4];
	for (int i = 0; i < 4; i++) {
		keep[i] = e[i] > 1e-12 * emax;
		if (keep[i]) {
			rank++;
			emin = fmin(emin, e[i]);
		}
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double s = 0;
			for (int k = 0; k < 4; k++)
				if (keep[k])
					s += V[i][k] * V[j][k] / e[k];
			inv_gram[i][j] = s;
		}
	*cond = rank ? sqrt(emax / emin) : INFINITY;
	/* coordinate i is determined when the unit vector e_i lies in the kept eigenspace */
	*mask = 0;
	for (int i = 0; i < 4; i++) {
		double proj = 0;
		for (int k = 0; k < 4; k++)
			if (keep[k])
				proj += V[i][k] * V[i][k];
		if (proj > 1 - 1e-9)
			*mask |= 1u << i;
	}
	return rank;
}

int pc_mueller_system_init(pc_mueller_system *s, unsigned n_psg, const double (*psg)[4],
			   unsigned n_psa, const double (*psa)[4][4], const double (*analyser)[4])
{
	memset(s, 0, sizeof *s);
	if (n_psg < 1 || n_psg > PC_MUELLER_MAX_STATES || n_psa < 1 || n_psa > PC_MUELLER_MAX_STATES)
		return pc_error(PC_EINVAL, "%u generator and %u analyser states: each must be in [1, %d]",
				n_psg, n_psa, PC_MUELLER_MAX_STATES);
	if (!psg)
		return pc_error(PC_EINVAL, "generator states missing");
	if (!psa && n_psa != 1)
		return pc_error(PC_EINVAL, "%u analyser states but no analyser matrices", n_psa);
	s->n_psg = n_psg;
	s->n_psa = n_psa;
	double ideal[4][4];
	for (int c = 0; c < 4; c++) {
		double th = c * 0.78539816339744830962; /* 45°·c */
		ideal[c][0] = 0.5;
		ideal[c][1] = 0.5 * cos(2 * th);
		ideal[c][2] = 0.5 * sin(2 * th);
		ideal[c][3] = 0;
	}
	const double(*w)[4] = analyser ? analyser : (const double(*)[4])ideal;
	for (unsigned g = 0; g < n_psg; g++)
		for (int i = 0; i < 4; i++) {
			if (!isfinite(psg[g][i]))
				return pc_error(PC_EINVAL, "generator state %u: non-finite Stokes element %d",
						g, i);
			s->G[i][g] = psg[g][i];
		}
	for (unsigned a = 0; a < n_psa; a++)
		for (int c = 0; c < 4; c++)
			for (int j = 0; j < 4; j++) {
				double v = 0;
				for (int k = 0; k < 4; k++) {
					double p = psa ? psa[a][k][j] : (k == j);
					if (!isfinite(p) || !isfinite(w[c][k]))
						return pc_error(PC_EINVAL, "analyser state %u: non-finite "
									   "element", a);
					v += w[c][k] * p;
				}
				s->A[4 * a + (unsigned)c][j] = v;
			}
	double iA[4][4], iG[4][4];
	unsigned mA, mG;
	/* G⁺ from the rows of Gᵀ */
	double Gt[PC_MUELLER_MAX_STATES][4];
	for (unsigned g = 0; g < n_psg; g++)
		for (int i = 0; i < 4; i++)
			Gt[g][i] = s->G[i][g];
	s->rank_A = pinv_setup(&s->A[0][0], 4, 4 * n_psa, iA, &s->cond_A, &mA);
	s->rank_G = pinv_setup(&Gt[0][0], 4, n_psg, iG, &s->cond_G, &mG);
	if (s->rank_A < 3)
		return pc_error(PC_ENUMERIC, "the analyser states have rank %u: at least 3 needed "
					     "(the 4 mosaic channels alone give 3)", s->rank_A);
	if (s->rank_G < 3)
		return pc_error(PC_ENUMERIC, "the %u generator states have rank %u: at least 3 "
					     "linearly independent Stokes vectors are needed", n_psg,
				s->rank_G);
	s->cond_W = s->cond_A * s->cond_G;
	/* A⁺ = (AᵀA)⁺Aᵀ (4 × 4n_psa); G⁺ = Gᵀ(GGᵀ)⁺ (n_psg × 4) */
	for (int i = 0; i < 4; i++)
		for (unsigned r = 0; r < 4 * n_psa; r++) {
			double v = 0;
			for (int k = 0; k < 4; k++)
				v += iA[i][k] * s->A[r][k];
			s->Ap[i][r] = v;
		}
	for (unsigned g = 0; g < n_psg; g++)
		for (int l = 0; l < 4; l++) {
			double v = 0;
			for (int k = 0; k < 4; k++)
				v += Gt[g][k] * iG[k][l];
			s->Gp[g][l] = v;
		}
	s->determined = 0;
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++) {
			bool det = (mA >> k & 1) && (mG >> l & 1);
			if (det)
				s->determined |= 1u << (4 * k + l);
			s->noise_gain[k][l] = det ? sqrt(iA[k][k] * iG[l][l]) : NAN;
		}
	return 0;
}

void pc_mueller_solve(const pc_mueller_system *s, const double *I, double M[4][4])
{
	const unsigned R = 4 * s->n_psa;
	for (int k = 0; k < 4; k++)
		for (int l = 0; l < 4; l++) {
			if (!(s->determined >> (4 * k + l) & 1)) {
				M[k][l] = NAN;
				continue;
			}
			double v = 0;
			for (unsigned g = 0; g < s->n_psg; g++) {
				double t = 0;
				for (unsigned r = 0; r < R; r++) {
					unsigned a = r / 4, c = r % 4;
					t += s->Ap[k][r] * I[(g + s->n_psg * a) * 4 + c];
				}
				v += t * s->Gp[g][l];
			}
			M[k][l] = v;
		}
}

typedef struct acc_ctx {
	const pc_fplane *ch;
	uint32_t width;
	float *M;
	float coef[4][16]; /* [c][4k + l]: Ap[k][4a + c]·Gp[g][l] for this frame */
} acc_ctx;

static void acc_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	const acc_ctx *a = ctx;
	for (uint32_t y = y0; y < y1; y++) {
		const float *p[4];
		for (int c = 0; c < 4; c++)
			p[c] = a->ch[c].data + (size_t)y * a->ch[c].row_stride;
		float *m = a->M + (size_t)y * a->width * 16;
		for (uint32_t x = 0; x < a->width; x++, m += 16) {
			float I0 = p[0][(size_t)x * a->ch[0].pixel_stride];
			float I1 = p[1][(size_t)x * a->ch[1].pixel_stride];
			float I2 = p[2][(size_t)x * a->ch[2].pixel_stride];
			float I3 = p[3][(size_t)x * a->ch[3].pixel_stride];
			for (int kl = 0; kl < 16; kl++)
				m[kl] += a->coef[0][kl] * I0 + a->coef[1][kl] * I1 +
					 a->coef[2][kl] * I2 + a->coef[3][kl] * I3;
		}
	}
}

int pc_mueller_accumulate(const pc_mueller_system *s, unsigned frame, const pc_fplane ch[4],
			  uint32_t width, uint32_t height, int threads, float *M)
{
	if (frame >= s->n_psg * s->n_psa)
		return pc_error(PC_EINVAL, "frame %u: the sequence has %u frames", frame,
				s->n_psg * s->n_psa);
	for (int c = 0; c < 4; c++)
		if (!ch[c].data)
			return pc_error(PC_EINVAL, "frame %u: analyser image %d missing", frame, c);
	if (!M || width == 0 || height == 0)
		return pc_error(PC_EINVAL, "empty Mueller image");
	unsigned g = frame % s->n_psg, a = frame / s->n_psg;
	acc_ctx ctx = { ch, width, M, { { 0 } } };
	for (int c = 0; c < 4; c++)
		for (int k = 0; k < 4; k++)
			for (int l = 0; l < 4; l++)
				ctx.coef[c][4 * k + l] =
					(s->determined >> (4 * k + l) & 1)
						? (float)(s->Ap[k][4 * a + (unsigned)c] * s->Gp[g][l])
						: 0.0f;
	pc_parallel_rows(height, 0, threads, acc_rows, &ctx);
	return 0;
}

void pc_mueller_finish(const pc_mueller_system *s, uint32_t width, uint32_t height, float *M)
{
	if (s->determined == 0xFFFFu)
		return;
	for (size_t i = 0; i < (size_t)width * height; i++)
		for (int kl = 0; kl < 16; kl++)
			if (!(s->determined >> kl & 1))
				M[16 * i + (size_t)kl] = NAN;
}
