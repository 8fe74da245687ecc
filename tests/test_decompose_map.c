/* The batched Lu–Chipman kernel pc_lu_chipman_map (core/decompose_map.c) against the scalar
 * reference pc_lu_chipman_decompose, field by field, on every instruction set this machine runs
 * (AVX2, AVX-512; the portable path is the scalar loop), with and without PC_LC_FILTER.
 *
 * Stated tolerance: zero. The kernel performs the scalar code's operations in the same order,
 * so every output must be bit-identical (NaN where the scalar result is NaN, any payload) and
 * every flag equal; a non-finite matrix (scalar: PC_EINVAL) must give NaN and PC_LC_NONFINITE.
 *
 * The set: the 12 000 round trips of test_decompose (known factors; also checked against the
 * truth with test_decompose's tolerances), pBRDF matrices of two paints with and without the
 * diffuse term (rank-1 coherency; off-lobe m' down to 1e-74, which needs the power-of-two
 * rescaling), noisy non-physical and arbitrary matrices (the Cloude-filter path), matrices
 * placed on both sides of the realisability threshold λ_min = −1e-9·tr H, and the hard cases:
 * D = 0.999999 … 1.0000001, det m' < 0, pure diattenuators/retarders, isotropic and ideal
 * depolarisers, R at 0 and π, rank-1 m', M00 ≤ 0, NaN and ±∞ in every position, m00 = 1e-300
 * with O(1) elements, 1e±200 scales. */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "lc_cases.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

enum { NMAX = 40000 };

typedef struct mats {
	double (*M)[16];
	size_t n;
} mats;

static void add(mats *s, const double M[4][4])
{
	if (s->n < NMAX)
		memcpy(s->M[s->n++], M, 16 * sizeof(double));
}

/* the outputs of one map call */
typedef struct maps {
	double *D, *Dv[3], *R, *ax[3], *Rl, *Rc, *Delta, *di;
	unsigned *flags;
} maps;

static void maps_alloc(maps *m, size_t n)
{
	double **all[] = {&m->D,     &m->Dv[0], &m->Dv[1], &m->Dv[2], &m->R,     &m->ax[0],
	                  &m->ax[1], &m->ax[2], &m->Rl,    &m->Rc,    &m->Delta, &m->di};
	for (size_t k = 0; k < sizeof all / sizeof all[0]; k++) {
		*all[k] = malloc(n * sizeof(double));
		for (size_t i = 0; i < n; i++)
			(*all[k])[i] = 12345.0; /* sentinel: unwritten entries show */
	}
	m->flags = malloc(n * sizeof(unsigned));
	for (size_t i = 0; i < n; i++)
		m->flags[i] = 0xdeadu;
}

static void maps_free(maps *m)
{
	double *all[] = {m->D,     m->Dv[0], m->Dv[1], m->Dv[2], m->R,     m->ax[0],
	                 m->ax[1], m->ax[2], m->Rl,    m->Rc,    m->Delta, m->di};
	for (size_t k = 0; k < sizeof all / sizeof all[0]; k++)
		free(all[k]);
	free(m->flags);
}

static pc_lc_map maps_view(const maps *m, size_t off)
{
	pc_lc_map v = {m->D + off,     {m->Dv[0] + off, m->Dv[1] + off, m->Dv[2] + off},
	               m->R + off,     {m->ax[0] + off, m->ax[1] + off, m->ax[2] + off},
	               m->Rl + off,    m->Rc + off,
	               m->Delta + off, m->di + off,
	               m->flags + off};
	return v;
}

/* bit-identical, or both NaN */
static bool same(double a, double b)
{
	if (isnan(a) || isnan(b))
		return isnan(a) && isnan(b);
	return memcmp(&a, &b, sizeof a) == 0;
}

typedef struct mismatch {
	long field[13];
	long first; /* index of the first mismatching matrix, −1 if none */
} mismatch;

static const char *field_names[13] = {
    "D",       "D_vec[0]", "D_vec[1]",   "D_vec[2]", "R",           "axis[0]", "axis[1]",
    "axis[2]", "R_linear", "R_circular", "Delta",    "depol_index", "flags"};

static void compare_one(const double *M16, unsigned options, const maps *m, size_t i, mismatch *mm)
{
	pc_lu_chipman lc;
	double M[4][4];
	memcpy(M, M16, sizeof M);
	int rc = pc_lu_chipman_decompose((const double(*)[4])M, options | PC_LC_NO_FACTORS, &lc);
	if (rc) {
		CHECK_EQ_INT(rc, PC_EINVAL);
		lc.D = lc.R = lc.R_linear = lc.R_circular = lc.Delta = lc.depol_index = NAN;
		for (int k = 0; k < 3; k++)
			lc.D_vec[k] = lc.R_axis[k] = NAN;
		lc.flags = PC_LC_NONFINITE;
	}
	const double ref[12] = {lc.D,        lc.D_vec[0],   lc.D_vec[1],  lc.D_vec[2],
	                        lc.R,        lc.R_axis[0],  lc.R_axis[1], lc.R_axis[2],
	                        lc.R_linear, lc.R_circular, lc.Delta,     lc.depol_index};
	const double got[12] = {m->D[i],  m->Dv[0][i], m->Dv[1][i], m->Dv[2][i],
	                        m->R[i],  m->ax[0][i], m->ax[1][i], m->ax[2][i],
	                        m->Rl[i], m->Rc[i],    m->Delta[i], m->di[i]};
	bool bad = false;
	for (int k = 0; k < 12; k++)
		if (!same(ref[k], got[k])) {
			mm->field[k]++;
			bad = true;
		}
	if (m->flags[i] != lc.flags) {
		mm->field[12]++;
		bad = true;
	}
	if (bad && mm->first < 0) {
		mm->first = (long)i;
		fprintf(stderr, "first mismatch at matrix %zu (options %u):\n", i, options);
		for (int k = 0; k < 12; k++)
			fprintf(stderr, "  %-12s scalar %.17g  map %.17g\n", field_names[k], ref[k],
			        got[k]);
		fprintf(stderr, "  flags        scalar 0x%x  map 0x%x\n  M =", lc.flags,
		        m->flags[i]);
		for (int k = 0; k < 16; k++)
			fprintf(stderr, " %.17g", M16[k]);
		fprintf(stderr, "\n");
	}
}

/* ---------------------------------------------------------------------------------------- */
/* the test set */

static void add_round_trips(mats *s, long *n_rt, lc_case *cases)
{
	long k = 0;
	for (int kind = 0; kind < LC_NKINDS; kind++) {
		int n = kind == LC_GENERAL ? 5000 : 1000;
		for (int t = 0; t < n; t++) {
			lc_make_case((enum lc_kind)kind, &cases[k]);
			add(s, cases[k].M);
			k++;
		}
	}
	*n_rt = k;
}

static void add_pbrdf(mats *s)
{
	const pc_material mats_[] = {
	    {1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0},
	    {1.47, 0.47, 0.1, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0},
	    {1.46, 1.28, 0.05, PC_DIFFUSE_NONE, PC_SHADOW_TS, PC_RHO_QUAD, 0},
	    {0.2, 3.0, 0.3, PC_DIFFUSE_NONE, PC_SHADOW_NONE, PC_RHO_QUAD, 0},
	};
	for (size_t k = 0; k < sizeof mats_ / sizeof mats_[0]; k++) {
		pc_pbrdf *p = NULL;
		CHECK_EQ_INT(pc_pbrdf_new(&mats_[k], &p), 0);
		if (!p)
			continue;
		for (int t = 0; t < 1500; t++) {
			double f[4][4];
			double ti = 1.55 * urand(), tr = 1.55 * urand(), ph = 2 * PC_PI * urand();
			if (t % 5 == 0) /* in-plane and backscatter geometries */
				ph = t % 10 == 0 ? PC_PI : 0;
			if (pc_pbrdf_eval(p, ti, tr, ph, f) == 0)
				add(s, f);
		}
		pc_pbrdf_free(p);
	}
}

static void add_noisy(mats *s)
{
	for (int t = 0; t < 4000; t++) {
		lc_case c;
		lc_make_case(t % 3 == 0 ? LC_DET_NEG : LC_GENERAL, &c);
		double noise = t % 4 == 0 ? 0.3 : 0.05 * urand();
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				c.M[i][j] += noise * c.m00 * nrand();
		if (t % 10 == 0) /* arbitrary matrices */
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					c.M[i][j] = i + j ? nrand() * 0.4 : 1;
		add(s, c.M);
	}
}

/* H = V diag(λ) Vᴴ with a random unitary V and λ_min = −c·1e-9·tr H, c near 1: on both sides of
 * the realisability threshold of pc_mueller_is_physical */
static void add_threshold(mats *s)
{
	for (int t = 0; t < 2000; t++) {
		/* V = Vr + i Vi, columns made orthonormal by Gram–Schmidt */
		double Vr[4][4], Vi[4][4];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				Vr[i][j] = nrand();
				Vi[i][j] = nrand();
			}
		for (int j = 0; j < 4; j++) {
			for (int k = 0; k < j; k++) { /* d = <v_k, v_j>, v_j −= d v_k */
				double dr = 0, di = 0;
				for (int i = 0; i < 4; i++) {
					dr += Vr[i][k] * Vr[i][j] + Vi[i][k] * Vi[i][j];
					di += Vr[i][k] * Vi[i][j] - Vi[i][k] * Vr[i][j];
				}
				for (int i = 0; i < 4; i++) {
					double xr = dr * Vr[i][k] - di * Vi[i][k];
					double xi = dr * Vi[i][k] + di * Vr[i][k];
					Vr[i][j] -= xr;
					Vi[i][j] -= xi;
				}
			}
			double nr = 0;
			for (int i = 0; i < 4; i++)
				nr += Vr[i][j] * Vr[i][j] + Vi[i][j] * Vi[i][j];
			nr = sqrt(nr);
			for (int i = 0; i < 4; i++) {
				Vr[i][j] /= nr;
				Vi[i][j] /= nr;
			}
		}
		double lam[4] = {urand(), urand(), urand(), 0};
		if (t % 4 == 0)
			lam[1] = lam[2] =
			    0; /* rank 1 (non-depolarising) plus the threshold eigenvalue */
		double tr = lam[0] + lam[1] + lam[2];
		double c = 1 + (urand() - 0.5) * (t % 2 ? 1e-3 : 1e-6);
		lam[3] = -c * 1e-9 * tr / (1 - c * 1e-9);
		/* H = Σ_k λ_k v_k v_kᴴ */
		double Hr[4][4], Hi[4][4], M[4][4];
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				double hr = 0, hi = 0;
				for (int k = 0; k < 4; k++) {
					hr += lam[k] * (Vr[i][k] * Vr[j][k] + Vi[i][k] * Vi[j][k]);
					hi += lam[k] * (Vi[i][k] * Vr[j][k] - Vr[i][k] * Vi[j][k]);
				}
				Hr[i][j] = hr;
				Hi[i][j] = hi;
			}
		pc_coherency_to_mueller(Hr, Hi, M);
		add(s, M);
	}
}

static void add_hard(mats *s)
{
	double M[4][4];
	/* D at and around the flag threshold 1 − 1e-6, times a retarder */
	const double Ds[] = {0.999999, 0.9999995, 0.99999949, 0.9999990001, 1.0, 1.0000001};
	for (size_t c = 0; c < sizeof Ds / sizeof Ds[0]; c++)
		for (int t = 0; t < 100; t++) {
			double n[3], Dv[3], R3[3][3], MD[4][4], MR[4][4], ax[3];
			unit3(n);
			for (int i = 0; i < 3; i++)
				Dv[i] = Ds[c] * n[i];
			make_MD(Dv, MD);
			if (Ds[c] > 1)
				for (int i = 0; i < 3; i++)
					MD[0][i + 1] = Dv[i];
			unit3(ax);
			rodrigues(ax, 0.3 + 2.5 * urand(), R3);
			make_MR(R3, MR);
			pc_mueller_mul(MR, MD, M);
			add(s, M);
		}
	/* M00 ≤ 0, zero matrix, ideal depolariser, identity, mirror, rank-1 m' */
	memset(M, 0, sizeof M);
	add(s, M);
	M[0][0] = -1;
	M[1][1] = 0.5;
	add(s, M);
	M[0][0] = -0.0;
	add(s, M);
	memset(M, 0, sizeof M);
	M[0][0] = 2;
	add(s, M);
	for (int i = 0; i < 4; i++)
		M[i][i] = 1;
	add(s, M);
	M[2][2] = M[3][3] = -1;
	add(s, M);
	M[1][1] = -1; /* det m' < 0, all −1 */
	add(s, M);
	memset(M, 0, sizeof M);
	M[0][0] = 1;
	M[1][1] = 0.5;
	add(s, M);
	M[2][1] = 0.25;
	add(s, M);
	/* non-finite elements in every position */
	const double bads[] = {NAN, INFINITY, -INFINITY};
	for (int e = 0; e < 16; e++)
		for (int b = 0; b < 3; b++) {
			lc_case c;
			lc_make_case(LC_GENERAL, &c);
			c.M[e / 4][e % 4] = bads[b];
			add(s, c.M);
		}
	/* extreme scales: the whole matrix, m' alone, and a tiny m00 */
	const double scales[] = {1e-200, 1e-40, 1e-31, 1e-29, 1e29, 1e31, 1e40, 1e200};
	for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++)
		for (int t = 0; t < 20; t++) {
			lc_case c;
			lc_make_case((enum lc_kind)(t % LC_NKINDS), &c);
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					c.M[i][j] *= t % 2 ? scales[k] : (i && j ? scales[k] : 1);
			add(s, c.M);
		}
	for (int t = 0; t < 20; t++) {
		lc_case c;
		lc_make_case(LC_GENERAL, &c);
		c.M[0][0] = 1e-300;
		add(s, c.M);
	}
	/* R exactly 0 and π with D = 0 (axis NaN at 0) */
	for (int t = 0; t < 50; t++) {
		lc_case c;
		lc_make_case(t % 2 ? LC_PURE_RET : LC_ISO_DEPOL, &c);
		add(s, c.M);
	}
}

/* ---------------------------------------------------------------------------------------- */

static void run_isa(const mats *s, pc_lc_isa isa, const char *name)
{
	const unsigned opts[] = {0, PC_LC_NO_FACTORS, PC_LC_FILTER,
	                         PC_LC_FILTER | PC_LC_NO_FACTORS};
	for (size_t o = 0; o < sizeof opts / sizeof opts[0]; o++) {
		maps m;
		maps_alloc(&m, s->n);
		pc_lc_map v = maps_view(&m, 0);
		int rc = pc_lu_chipman_map_isa(&s->M[0][0], s->n, opts[o], &v, isa);
		if (rc == PC_ENOTSUP) {
			printf("%-9s not available on this machine\n", name);
			maps_free(&m);
			return;
		}
		CHECK_EQ_INT(rc, 0);
		mismatch mm = {{0}, -1};
		for (size_t i = 0; i < s->n; i++)
			compare_one(s->M[i], opts[o], &m, i, &mm);
		long tot = 0;
		for (int k = 0; k < 13; k++) {
			tot += mm.field[k];
			if (mm.field[k])
				fprintf(stderr, "%s options %u: %ld mismatches in %s\n", name,
				        opts[o], mm.field[k], field_names[k]);
		}
		CHECK_EQ_INT(tot, 0);
		printf(
		    "%-9s options %u: %zu matrices, %ld fields differ from the scalar reference\n",
		    name, opts[o], s->n, tot);

		/* tails and offsets: short calls at odd offsets, only D, R, Δ requested; the rest
		 * stays untouched */
		maps m2;
		maps_alloc(&m2, s->n);
		size_t off = 0;
		for (size_t len = 1; off < s->n && len < 40; len += 3) {
			size_t l = len < s->n - off ? len : s->n - off;
			pc_lc_map v2 = {m2.D + off,
			                {NULL, NULL, NULL},
			                m2.R + off,
			                {NULL, NULL, NULL},
			                NULL,
			                NULL,
			                m2.Delta + off,
			                NULL,
			                NULL};
			CHECK_EQ_INT(pc_lu_chipman_map_isa(s->M[off], l, opts[o], &v2, isa), 0);
			off += l + 101; /* skip some: spread over the set */
		}
		long diff = 0, touched = 0;
		off = 0;
		for (size_t len = 1; off < s->n && len < 40; len += 3) {
			size_t l = len < s->n - off ? len : s->n - off;
			for (size_t i = off; i < off + l; i++) {
				diff += !same(m2.D[i], m.D[i]) + !same(m2.R[i], m.R[i]) +
				        !same(m2.Delta[i], m.Delta[i]);
				touched += m2.Rl[i] != 12345.0 || m2.di[i] != 12345.0 ||
				           m2.flags[i] != 0xdeadu || m2.ax[0][i] != 12345.0;
			}
			for (size_t i = off + l; i < off + l + 101 && i < s->n; i++)
				touched += m2.D[i] != 12345.0; /* nothing beyond n written */
			off += l + 101;
		}
		CHECK_EQ_INT(diff, 0);
		CHECK_EQ_INT(touched, 0);
		maps_free(&m2);
		maps_free(&m);
	}
}

static void check_round_trip_truth(const mats *s, const lc_case *cases, long n_rt)
{
	/* the map's D, R, Δ against the known factors, test_decompose's tolerances: D 1e-13, R and
	 * Δ 1e-12 (×1e4 for D = 0.99999 and 1 − 2e-6, the LC_D_NEAR1 block) */
	maps m;
	maps_alloc(&m, (size_t)n_rt);
	pc_lc_map v = maps_view(&m, 0);
	CHECK_EQ_INT(pc_lu_chipman_map(&s->M[0][0], (size_t)n_rt, PC_LC_NO_FACTORS, &v), 0);
	double wD = 0, wR = 0, wDel = 0;
	for (long i = 0; i < n_rt; i++) {
		const lc_case *c = &cases[i];
		double Dt = sqrt(c->Dv[0] * c->Dv[0] + c->Dv[1] * c->Dv[1] + c->Dv[2] * c->Dv[2]);
		double Deltat = 1 - fabs(c->lam[0] + c->lam[1] + c->lam[2]) / 3;
		double sc = Dt > 0.9999 ? 1e4 : 1;
		CHECK_NEAR(m.D[i], Dt, 1e-13);
		CHECK_NEAR(m.R[i], c->R, 1e-12 * sc);
		CHECK_NEAR(m.Delta[i], Deltat, 1e-12 * sc);
		CHECK_EQ_INT(m.flags[i] & PC_LC_D_SINGULAR, 0);
		if (sc == 1) {
			wD = fmax(wD, fabs(m.D[i] - Dt));
			wR = fmax(wR, fabs(m.R[i] - c->R));
			wDel = fmax(wDel, fabs(m.Delta[i] - Deltat));
		}
	}
	printf("map vs known factors (%ld round trips, D < 0.9999): |dD| %.1e |dR| %.1e "
	       "|dDelta| %.1e\n",
	       n_rt, wD, wR, wDel);
	maps_free(&m);
}

/* The set covers every branch: count the scalar reference's flags under PC_LC_FILTER, and the
 * threshold matrices on each side of the realisability test. */
static void check_coverage(const mats *s, size_t thr0, size_t thr1)
{
	long nf[8] = {0}, phys_thr = 0;
	for (size_t i = 0; i < s->n; i++) {
		pc_lu_chipman lc;
		double M[4][4];
		memcpy(M, s->M[i], sizeof M);
		if (pc_lu_chipman_decompose((const double(*)[4])M, PC_LC_FILTER, &lc)) {
			nf[6]++;
			continue;
		}
		for (int b = 0; b < 6; b++)
			nf[b] += (lc.flags >> b) & 1u;
		if (i >= thr0 && i < thr1)
			phys_thr += lc.physical;
	}
	printf("coverage (scalar, PC_LC_FILTER): D singular %ld, R non-unique %ld, non-physical "
	       "%ld, filtered %ld, clamped %ld, M00 <= 0 %ld, non-finite %ld; threshold set %ld "
	       "physical / %ld not\n",
	       nf[0], nf[1], nf[2], nf[3], nf[4], nf[5], nf[6], phys_thr,
	       (long)(thr1 - thr0) - phys_thr);
	CHECK(nf[0] >= 100 && nf[1] >= 20 && nf[2] >= 3000 && nf[3] >= 3000 && nf[4] >= 1);
	CHECK(nf[5] >= 3 && nf[6] == 48);
	CHECK(phys_thr >= 500 && (long)(thr1 - thr0) - phys_thr >= 500);
}

/* The caller: pc_mueller_maps (core/mueller_imaging.c, `polarcam mueller` and `polarcam demo`)
 * runs the map kernel in row chunks; its float maps and pixel counts must equal what the
 * per-pixel scalar code it replaced produced (PC_LC_FILTER | PC_LC_NO_FACTORS, float outputs,
 * non-finite pixels NaN and counted as bad). */
static void test_maps_caller(const mats *s)
{
	const uint32_t W = 301, H = 5; /* a chunk of 256 and a tail per row */
	size_t np = (size_t)W * H;
	float *M = malloc(np * 16 * sizeof(float)), *mp = malloc(3 * np * sizeof(float));
	for (size_t i = 0; i < np; i++) {
		/* spread over the set: round trips, pBRDF, noisy, threshold, hard cases */
		size_t k = (i * 83) % s->n;
		for (int e = 0; e < 16; e++)
			M[16 * i + e] = (float)s->M[k][e];
	}
	M[16 * 7 + 3] = NAN;
	M[16 * 300 + 0] = INFINITY;
	M[16 * 400 + 0] = 0; /* M00 = 0 */
	long counts[3] = {-1, -1, -1}, want[3] = {0, 0, 0};
	pc_mueller_maps(M, W, H, 0xFFFFu, 2, mp, mp + np, mp + 2 * np, counts);
	long diff = 0;
	for (size_t i = 0; i < np; i++) {
		double Md[4][4];
		bool finite = true;
		for (int e = 0; e < 16; e++) {
			Md[e / 4][e % 4] = M[16 * i + e];
			finite &= isfinite(M[16 * i + e]) != 0;
		}
		float d = NAN, r = NAN, de = NAN;
		pc_lu_chipman lc;
		if (!finite || pc_lu_chipman_decompose((const double(*)[4])Md,
		                                       PC_LC_FILTER | PC_LC_NO_FACTORS, &lc)) {
			want[2]++;
		} else {
			d = (float)lc.D;
			r = (float)lc.R;
			de = (float)lc.Delta;
			want[0] += (lc.flags & (PC_LC_D_SINGULAR | PC_LC_ZERO_M00)) != 0;
			want[1] += !lc.physical;
		}
		const float got[3] = {mp[i], mp[np + i], mp[2 * np + i]}, ref[3] = {d, r, de};
		for (int k = 0; k < 3; k++)
			diff += !((isnan(got[k]) && isnan(ref[k])) ||
			          memcmp(&got[k], &ref[k], sizeof got[k]) == 0);
	}
	CHECK_EQ_INT(diff, 0);
	for (int k = 0; k < 3; k++)
		CHECK_EQ_INT(counts[k], want[k]);
	CHECK(want[1] > 100 && want[2] >= 2);
	printf("pc_mueller_maps: %zu pixels equal the per-pixel scalar path (singular %ld, "
	       "non-physical %ld, bad %ld)\n",
	       np, counts[0], counts[1], counts[2]);
	/* an undetermined system: every pixel NaN */
	pc_mueller_maps(M, W, H, 0x7FFFu, 1, mp, mp + np, mp + 2 * np, counts);
	long finite_out = 0;
	for (size_t i = 0; i < 3 * np; i++)
		finite_out += !isnan(mp[i]);
	CHECK_EQ_INT(finite_out, 0);
	free(M);
	free(mp);
}

static void test_errors(void)
{
	double M[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, D = 0;
	pc_lc_map v = {&D,  {NULL, NULL, NULL}, NULL, {NULL, NULL, NULL}, NULL, NULL, NULL, NULL,
	               NULL};
	CHECK_EQ_INT(pc_lu_chipman_map(NULL, 0, 0, &v), 0); /* nothing to do */
	CHECK_EQ_INT(pc_lu_chipman_map(NULL, 1, 0, &v), PC_EINVAL);
	CHECK_EQ_INT(pc_lu_chipman_map(M, 1, 0, NULL), PC_EINVAL);
	CHECK_EQ_INT(pc_lu_chipman_map(M, 1, 1u << 7, &v), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "options") != NULL);
	CHECK_EQ_INT(pc_lu_chipman_map(M, 1, PC_LC_FILTER, &v), 0);
	CHECK_NEAR(D, 0, 0);
	const char *isa = pc_lu_chipman_map_isa_name();
	CHECK(isa && *isa);
	printf("AUTO instruction set here: %s\n", isa);
}

int main(void)
{
	mats s = {malloc(NMAX * sizeof(double[16])), 0};
	lc_case *cases = malloc(12000 * sizeof *cases);
	long n_rt = 0;
	add_round_trips(&s, &n_rt, cases);
	add_pbrdf(&s);
	add_noisy(&s);
	size_t thr0 = s.n;
	add_threshold(&s);
	size_t thr1 = s.n;
	add_hard(&s);
	printf("%zu matrices (%ld round trips)\n", s.n, n_rt);
	CHECK(n_rt >= 10000);
	check_coverage(&s, thr0, thr1);
	run_isa(&s, PC_LC_ISA_PORTABLE, "scalar");
	run_isa(&s, PC_LC_ISA_AVX2, "avx2");
	run_isa(&s, PC_LC_ISA_AVX512, "avx512");
	run_isa(&s, PC_LC_ISA_AUTO, "auto");
	check_round_trip_truth(&s, cases, n_rt);
	test_maps_caller(&s);
	test_errors();
	free(cases);
	free(s.M);
	return pc_test_finish("test_decompose_map");
}
