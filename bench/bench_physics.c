/* polarcam bench physics: Lu–Chipman throughput against a textbook eigen-route baseline measured
 * in the same run (1 and 2 threads; the scalar path and the batched map kernel), pBRDF evaluations
 * per second with and without the diffuse term, material creation cost, and the ρ^s
 * accuracy-vs-cost table (every quadrature order, the per-material evaluation table, the 64×32
 * table mode) against a high-order reference. */
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bench.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

/* the program running the benchmark (bench.h) */
static const pc_bench_host *host;

#define DEG (PC_PI / 180)

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static uint64_t rng = 0x6a09e667f3bcc909ull;
static double urand(void)
{
	rng ^= rng << 13;
	rng ^= rng >> 7;
	rng ^= rng << 17;
	return (double)(rng >> 11) * 0x1p-53;
}

static volatile double sink; /* keeps results alive */

/* ---------------------------------------------------------------------------------------- */
/* Baseline: the paper's route, done plainly (eqs. 13–19): m' as in physics.md §3, then
 * m_Δ = ±(m' m'ᵀ)^{1/2} from a cyclic Jacobi eigen-decomposition, m_R = m_Δ⁻¹ m',
 * R = arccos(tr(M_R)/2 − 1) (eq. 19), Δ = 1 − |tr m_Δ|/3 (eq. 18). */
static void jacobi3(double a[3][3], double v[3][3])
{
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			v[i][j] = i == j;
	for (int sweep = 0; sweep < 30; sweep++) {
		double off = fabs(a[0][1]) + fabs(a[0][2]) + fabs(a[1][2]);
		if (off < 1e-300)
			break;
		for (int p = 0; p < 3; p++)
			for (int q = p + 1; q < 3; q++) {
				if (a[p][q] == 0)
					continue;
				double th = (a[q][q] - a[p][p]) / (2 * a[p][q]);
				double t = (th >= 0 ? 1 : -1) / (fabs(th) + sqrt(th * th + 1));
				double c = 1 / sqrt(t * t + 1), s = t * c;
				for (int k = 0; k < 3; k++) {
					double x = a[k][p], y = a[k][q];
					a[k][p] = c * x - s * y;
					a[k][q] = s * x + c * y;
				}
				for (int k = 0; k < 3; k++) {
					double x = a[p][k], y = a[q][k];
					a[p][k] = c * x - s * y;
					a[q][k] = s * x + c * y;
				}
				for (int k = 0; k < 3; k++) {
					double x = v[k][p], y = v[k][q];
					v[k][p] = c * x - s * y;
					v[k][q] = s * x + c * y;
				}
			}
	}
}

static void baseline_lc(const double M[4][4], double *D, double *R, double *Delta)
{
	double m[4][4];
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			m[i][j] = M[i][j] / M[0][0];
	double d = sqrt(m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[0][3] * m[0][3]);
	*D = d;
	double s = sqrt(1 - d * d), Mi[4][4], Mp[4][4];
	Mi[0][0] = 1;
	for (int i = 0; i < 3; i++) {
		Mi[0][i + 1] = Mi[i + 1][0] = -m[0][i + 1];
		for (int j = 0; j < 3; j++)
			Mi[i + 1][j + 1] =
			    (i == j ? s : 0) +
			    (d > 0 ? (1 - s) * m[0][i + 1] * m[0][j + 1] / (d * d) : 0);
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double acc = 0;
			for (int k = 0; k < 4; k++)
				acc += m[i][k] * Mi[k][j];
			Mp[i][j] = acc / (1 - d * d);
		}
	double mp[3][3], S[3][3], V[3][3];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			mp[i][j] = Mp[i + 1][j + 1];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			S[i][j] = mp[i][0] * mp[j][0] + mp[i][1] * mp[j][1] + mp[i][2] * mp[j][2];
	jacobi3(S, V);
	double det = mp[0][0] * (mp[1][1] * mp[2][2] - mp[1][2] * mp[2][1]) -
	             mp[0][1] * (mp[1][0] * mp[2][2] - mp[1][2] * mp[2][0]) +
	             mp[0][2] * (mp[1][0] * mp[2][1] - mp[1][1] * mp[2][0]);
	double sg = det < 0 ? -1 : 1, md[3][3], mi[3][3], tr = 0;
	double l[3];
	for (int k = 0; k < 3; k++)
		l[k] = sqrt(S[k][k] > 0 ? S[k][k] : 0);
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++) {
			md[i][j] = sg * (V[i][0] * l[0] * V[j][0] + V[i][1] * l[1] * V[j][1] +
			                 V[i][2] * l[2] * V[j][2]);
			mi[i][j] = sg * (V[i][0] / l[0] * V[j][0] + V[i][1] / l[1] * V[j][1] +
			                 V[i][2] / l[2] * V[j][2]);
		}
	for (int i = 0; i < 3; i++)
		tr += md[i][i];
	double trR = 1;
	for (int i = 0; i < 3; i++)
		trR += mi[i][0] * mp[0][i] + mi[i][1] * mp[1][i] + mi[i][2] * mp[2][i];
	double c = trR / 2 - 1;
	*R = acos(c > 1 ? 1 : c < -1 ? -1 : c);
	*Delta = 1 - fabs(tr) / 3;
}

/* ---------------------------------------------------------------------------------------- */

enum { NM = 4096 };

static void make_matrices(double (*Ms)[4][4])
{
	pc_material m = {1.46, 1.28, 0.2, PC_DIFFUSE_FRESNEL, PC_SHADOW_TS, PC_RHO_QUAD, 0};
	pc_pbrdf *p = NULL;
	pc_pbrdf_new(&m, &p);
	for (int n = 0; n < NM; n++) {
		if (n % 2 == 0) {
			/* pBRDF matrices of black paint at random geometries */
			do
				pc_pbrdf_eval(p, 80 * DEG * urand(), 80 * DEG * urand(),
				              2 * PC_PI * urand(), Ms[n]);
			while (!(Ms[n][0][0] > 1e-3));
		} else {
			/* a random depolarising, diattenuating, retarding product-like matrix */
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					Ms[n][i][j] = (i == j ? 0.7 : 0) + 0.3 * (urand() - 0.5);
			Ms[n][0][0] = 1;
		}
	}
	pc_pbrdf_free(p);
}

/* ns per decomposition, best of `reps` runs of `iters` decompositions, on `threads` threads. */
typedef enum lc_kind { LC_BASELINE, LC_FULL, LC_FAST } lc_kind;

static double time_lc(const double (*Ms)[4][4], lc_kind kind, unsigned opts, int threads,
                      long iters, int reps)
{
	double best = INFINITY;
	for (int r = 0; r < reps; r++) {
		double t0 = now_s(), acc = 0;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) reduction(+ : acc) schedule(static)
#endif
		for (long i = 0; i < iters; i++) {
			const double(*M)[4] = Ms[i & (NM - 1)];
			if (kind == LC_BASELINE) {
				double D, R, Del;
				baseline_lc(M, &D, &R, &Del);
				acc += R + Del;
			} else {
				pc_lu_chipman lc;
				pc_lu_chipman_decompose(M, opts, &lc);
				acc += lc.R + lc.Delta;
			}
		}
		double dt = now_s() - t0;
		sink = acc;
		if (dt < best)
			best = dt;
	}
	(void)threads;
	return best / (double)iters * 1e9;
}

/* ns per decomposition through the batched kernel pc_lu_chipman_map: each thread decomposes
 * chunks of LC_CHUNK consecutive matrices of the cycled set into its own output arrays (all
 * outputs, or D, R and Δ only as the D/R/Δ maps of `polarcam mueller` need). */
enum { LC_CHUNK = 256 };

static double time_map(const double (*Ms)[4][4], unsigned opts, bool all, int threads, long iters,
                       int reps)
{
	const long nch = iters / LC_CHUNK;
	double best = INFINITY;
	for (int r = 0; r < reps; r++) {
		double t0 = now_s(), acc = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : acc)
#endif
		{
			double D[LC_CHUNK], R[LC_CHUNK], De[LC_CHUNK], Dv[3][LC_CHUNK],
			    ax[3][LC_CHUNK], Rl[LC_CHUNK], Rc[LC_CHUNK], di[LC_CHUNK];
			unsigned fl[LC_CHUNK];
			pc_lc_map out = {
			    D,   {NULL, NULL, NULL}, R, {NULL, NULL, NULL}, NULL, NULL, De, NULL,
			    NULL};
			if (all) {
				pc_lc_map a = {D,  {Dv[0], Dv[1], Dv[2]},
				               R,  {ax[0], ax[1], ax[2]},
				               Rl, Rc,
				               De, di,
				               fl};
				out = a;
			}
#ifdef _OPENMP
#pragma omp for schedule(static)
#endif
			for (long c = 0; c < nch; c++) {
				size_t off = (size_t)(c * LC_CHUNK) & (NM - 1);
				pc_lu_chipman_map(&Ms[off][0][0], LC_CHUNK, opts, &out);
				acc += R[c & (LC_CHUNK - 1)] + De[c & (LC_CHUNK - 1)];
			}
		}
		double dt = now_s() - t0;
		sink = acc;
		if (dt < best)
			best = dt;
	}
	(void)threads;
	return best / (double)(nch * LC_CHUNK) * 1e9;
}

/* Matrices of the set whose map-kernel outputs differ from the scalar path in any bit. */
static long map_vs_scalar(const double (*Ms)[4][4], unsigned opts)
{
	static double D[NM], R[NM], De[NM], Rl[NM], Rc[NM], di[NM], Dv[3][NM], ax[3][NM];
	static unsigned fl[NM];
	pc_lc_map out = {D, {Dv[0], Dv[1], Dv[2]}, R, {ax[0], ax[1], ax[2]}, Rl, Rc, De, di, fl};
	if (pc_lu_chipman_map(&Ms[0][0][0], NM, opts, &out))
		return NM;
	long bad = 0;
	for (int n = 0; n < NM; n++) {
		pc_lu_chipman lc;
		pc_lu_chipman_decompose(Ms[n], opts | PC_LC_NO_FACTORS, &lc);
		const double a[12] = {lc.D,          lc.R,           lc.Delta,     lc.R_linear,
		                      lc.R_circular, lc.depol_index, lc.D_vec[0],  lc.D_vec[1],
		                      lc.D_vec[2],   lc.R_axis[0],   lc.R_axis[1], lc.R_axis[2]};
		const double b[12] = {D[n],     R[n],     De[n],    Rl[n],    Rc[n],    di[n],
		                      Dv[0][n], Dv[1][n], Dv[2][n], ax[0][n], ax[1][n], ax[2][n]};
		bool diff = fl[n] != lc.flags;
		for (int k = 0; k < 12; k++)
			diff |= !(isnan(a[k]) && isnan(b[k])) && memcmp(&a[k], &b[k], sizeof a[k]);
		bad += diff;
	}
	return bad;
}

/* ---------------------------------------------------------------------------------------- */

typedef struct rho_case {
	double n, k, sigma, theta;
	double ref;
} rho_case;

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

int pc_bench_physics(const pc_bench_host *h, int argc, char **argv)
{
	host = h;
	bool json = false, quick = false;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--json"))
			json = true;
		else if (!strcmp(argv[i], "--quick"))
			quick = true;
		else if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
			printf(
			    "usage: polarcam bench physics [--quick] [--json]\n\n"
			    "Lu-Chipman decompositions per second (1 and 2 threads; scalar path "
			    "and\n"
			    "the batched map kernel pc_lu_chipman_map) against a textbook "
			    "eigen-route\n"
			    "baseline timed in the same run; pBRDF evaluations per "
			    "second\n"
			    "with and without the diffuse term; material creation cost; the rho^s\n"
			    "accuracy-vs-cost table for each quadrature order, the per-material "
			    "eval\n"
			    "table and the 64x32 table mode against a high-order reference (order "
			    "512,\n"
			    "256 with --quick). --quick: smaller sample, ~5 s. --json: one JSON "
			    "object on\n"
			    "stdout after the tables (tables then go to stderr).\n"
			    "Environment: POLARCAM_CPU=avx2 / POLARCAM_CPU=baseline time the "
			    "narrower\n"
			    "map kernels (AVX2 / the scalar loop).\n");
			return 0;
		} else {
			fprintf(stderr, "polarcam bench physics: unknown option '%s'\n", argv[i]);
			return 2;
		}
	}
	if (host->parse_only)
		return PC_BENCH_OK;
	FILE *out = json ? stderr : stdout;
	json_t *root = json_object();
	int max_threads = 1;
#ifdef _OPENMP
	max_threads = omp_get_max_threads();
#endif
	fprintf(
	    out,
	    "polarcam bench physics (%s; %d hardware threads available to OpenMP; Lu-Chipman "
	    "timings are the best of many short windows, the others best of 3; ratios measured in "
	    "this run)\n\n",
	    quick ? "quick" : "full", max_threads);

	/* --- Lu–Chipman --- */
	double(*Ms)[4][4] = malloc(NM * sizeof *Ms);
	if (!Ms)
		return 1;
	make_matrices(Ms);
	double load0[1] = {-1};
	if (getloadavg(load0, 1) != 1)
		load0[0] = -1;
	/* Many short windows, best of them: on a shared machine some windows run uncontended, so
	 * the minimum approaches the idle figure (long windows average the other users' load in).
	 * Every window covers the whole set at least once. */
	const int rl = quick ? 5 : 15, rs = quick ? 20 : 60;
	const double(*Mc)[4][4] = (const double(*)[4][4])Ms;
	double ns_base = time_lc(Mc, LC_BASELINE, 0, 1, 4 * NM, rl);
	double ns_full = time_lc(Mc, LC_FULL, 0, 1, NM, rl);
	double ns_filt = time_lc(Mc, LC_FULL, PC_LC_FILTER, 1, NM, rl);
	double ns_fast1 = time_lc(Mc, LC_FAST, PC_LC_NO_FACTORS, 1, 4 * NM, rs);
	double ns_fast2 = time_lc(Mc, LC_FAST, PC_LC_NO_FACTORS, 2, 8 * NM, rs);
	double ns_ffilt = time_lc(Mc, LC_FAST, PC_LC_FILTER | PC_LC_NO_FACTORS, 1, NM, rs);
	/* the batched kernel */
	double ns_map1 = time_map(Mc, 0, true, 1, 16 * NM, rs);
	double ns_map2 = time_map(Mc, 0, true, 2, 32 * NM, rs);
	double ns_drd1 = time_map(Mc, 0, false, 1, 16 * NM, rs);
	double ns_drd2 = time_map(Mc, 0, false, 2, 32 * NM, rs);
	double ns_mfilt1 = time_map(Mc, PC_LC_FILTER, false, 1, NM, rs);
	double ns_mfilt2 = time_map(Mc, PC_LC_FILTER, false, 2, 2 * NM, rs);
	long map_diff = map_vs_scalar(Mc, 0) + map_vs_scalar(Mc, PC_LC_FILTER);
	/* agreement with the baseline on the physical half (pBRDF matrices) */
	double dR = 0, dDel = 0;
	for (int n = 0; n < NM; n += 2) {
		double D, R, Del;
		pc_lu_chipman lc;
		baseline_lc(Ms[n], &D, &R, &Del);
		pc_lu_chipman_decompose(Ms[n], PC_LC_NO_FACTORS, &lc);
		if (lc.flags & (PC_LC_D_SINGULAR | PC_LC_R_NONUNIQUE))
			continue;
		dR = fmax(dR, fabs(R - lc.R));
		dDel = fmax(dDel, fabs(Del - lc.Delta));
	}
	double load1[1] = {-1};
	if (getloadavg(load1, 1) != 1)
		load1[0] = -1;
	fprintf(out,
	        "Lu-Chipman decomposition (%d matrices cycled: half pBRDF of black paint, half "
	        "random depolarising; 1-minute load average %.2f before, %.2f after)\n",
	        NM, load0[0], load1[0]);
	fprintf(out, "  %-60s %10s %12s %12s %10s\n", "method", "ns/matrix", "M matrices/s",
	        "M/s per core", "vs baseline");
	const struct {
		const char *name;
		double ns;
		int threads;
	} rows[] = {
	    {"baseline: textbook eigen-route, acos (1 thread)", ns_base, 1},
	    {"polarcam, factors + realisability check (1 thread)", ns_full, 1},
	    {"polarcam, + Cloude filter (1 thread)", ns_filt, 1},
	    {"polarcam, PC_LC_NO_FACTORS (1 thread)", ns_fast1, 1},
	    {"polarcam, PC_LC_NO_FACTORS (2 threads)", ns_fast2, 2},
	    {"polarcam, PC_LC_FILTER | PC_LC_NO_FACTORS (1 thread)", ns_ffilt, 1},
	    {"map kernel, all outputs (1 thread)", ns_map1, 1},
	    {"map kernel, all outputs (2 threads)", ns_map2, 2},
	    {"map kernel, D, R, Delta only (1 thread)", ns_drd1, 1},
	    {"map kernel, D, R, Delta only (2 threads)", ns_drd2, 2},
	    {"map kernel + PC_LC_FILTER, D, R, Delta (1 thread)", ns_mfilt1, 1},
	    {"map kernel + PC_LC_FILTER, D, R, Delta (2 threads)", ns_mfilt2, 2},
	};
	json_t *jl = json_array();
	for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
		fprintf(out, "  %-60s %10.1f %12.2f %12.2f %9.2fx\n", rows[i].name, rows[i].ns,
		        1e3 / rows[i].ns, 1e3 / rows[i].ns / rows[i].threads, ns_base / rows[i].ns);
		json_array_append_new(jl, json_pack("{s:s, s:i, s:f, s:f, s:f, s:f}", "method",
		                                    rows[i].name, "threads", rows[i].threads,
		                                    "ns_per_matrix", rows[i].ns, "per_second",
		                                    1e9 / rows[i].ns, "per_second_per_core",
		                                    1e9 / rows[i].ns / rows[i].threads,
		                                    "speedup_vs_baseline", ns_base / rows[i].ns));
	}
	fprintf(out,
	        "  scalar path, per core with PC_LC_NO_FACTORS: %.2f M/s; 2-thread scaling %.2fx\n",
	        1e3 / ns_fast1, ns_fast1 / ns_fast2);
	fprintf(out,
	        "  agreement with the baseline on pBRDF matrices: max |dR| %.1e rad, max |dDelta| "
	        "%.1e\n",
	        dR, dDel);
	fprintf(out,
	        "  map kernel (pc_lu_chipman_map, %s): per core %.2f M/s on 1 thread, %.2f M/s "
	        "per core on 2 threads (all outputs; goal 5 M/s);\n"
	        "    %.2fx the scalar PC_LC_NO_FACTORS path, %.1fx the baseline; D, R, Delta only "
	        "%.2f M/s; with PC_LC_FILTER %.2fx the scalar filter path;\n"
	        "    bit-identical to the scalar path on this set: %s (%ld matrices differ)\n\n",
	        pc_lu_chipman_map_isa_name(), 1e3 / ns_map1, 1e3 / ns_map2 / 2, ns_fast1 / ns_map1,
	        ns_base / ns_map1, 1e3 / ns_drd1, ns_ffilt / ns_mfilt1, map_diff ? "NO" : "yes",
	        map_diff);
	json_object_set_new(
	    root, "lu_chipman_map",
	    json_pack("{s:s, s:f, s:f, s:f, s:f, s:f, s:I}", "isa", pc_lu_chipman_map_isa_name(),
	              "per_core_1_thread", 1e9 / ns_map1, "per_core_2_threads", 1e9 / ns_map2 / 2,
	              "speedup_vs_scalar", ns_fast1 / ns_map1, "speedup_vs_baseline",
	              ns_base / ns_map1, "filter_speedup_vs_scalar", ns_ffilt / ns_mfilt1,
	              "matrices_differing_from_scalar", (json_int_t)map_diff));
	json_object_set_new(root, "lu_chipman", jl);
	json_object_set_new(root, "load_average",
	                    json_pack("{s:f, s:f}", "before", load0[0], "after", load1[0]));
	json_object_set_new(root, "lu_chipman_baseline_agreement",
	                    json_pack("{s:f, s:f}", "max_dR", dR, "max_dDelta", dDel));
	free(Ms);

	/* --- pBRDF evaluation --- */
	enum { NG = 4096 };
	double(*g)[4][3] = malloc(NG * sizeof *g); /* k_i, k_r, s_i, s_r */
	if (!g)
		return 1;
	for (int n = 0; n < NG; n++) {
		double ti = 85 * DEG * urand(), tr = 85 * DEG * urand(), ph = 2 * PC_PI * urand();
		double v[4][3] = {{sin(ti), 0, cos(ti)},
		                  {sin(tr) * cos(ph), sin(tr) * sin(ph), cos(tr)},
		                  {0, 1, 0},
		                  {sin(ph), -cos(ph), 0}};
		memcpy(g[n], v, sizeof v);
	}
	fprintf(
	    out,
	    "pBRDF evaluation, black paint sigma = 0.2, %d random geometries cycled, 1 thread\n",
	    NG);
	fprintf(out, "  %-44s %10s %12s %14s\n", "mode", "ns/eval", "M evals/s", "pc_pbrdf_new ms");
	const struct {
		const char *name;
		pc_diffuse d;
		pc_rho_mode mode;
		int order;
	} em[] = {
	    {"specular only (--diffuse none)", PC_DIFFUSE_NONE, PC_RHO_QUAD, 0},
	    {"with diffuse, quad:16 (default)", PC_DIFFUSE_FRESNEL, PC_RHO_QUAD, 16},
	    {"with diffuse, quad:32", PC_DIFFUSE_FRESNEL, PC_RHO_QUAD, 32},
	    {"with diffuse, geometric rho, quad:16", PC_DIFFUSE_GEOMETRIC, PC_RHO_QUAD, 16},
	    {"with diffuse, table (64 x 32 bicubic)", PC_DIFFUSE_FRESNEL, PC_RHO_TABLE, 16},
	};
	json_t *je = json_array();
	double ns_spec = 0;
	for (size_t e = 0; e < sizeof em / sizeof em[0]; e++) {
		pc_material m = {1.46, 1.28, 0.2, em[e].d, PC_SHADOW_TS, em[e].mode, em[e].order};
		pc_pbrdf *p = NULL;
		double tb = INFINITY;
		for (int r = 0; r < 3; r++) {
			double t0 = now_s();
			pc_pbrdf_new(&m, &p);
			tb = fmin(tb, now_s() - t0);
			if (r < 2)
				pc_pbrdf_free(p);
		}
		long n = quick ? 1000000 : 4000000;
		double best = INFINITY, f[4][4];
		for (int r = 0; r < 3; r++) {
			double t0 = now_s(), acc = 0;
			for (long i = 0; i < n; i++) {
				const double(*v)[3] = g[i & (NG - 1)];
				pc_pbrdf_eval_vec(p, v[0], v[1], v[2], v[3], f);
				acc += f[0][0];
			}
			sink = acc;
			best = fmin(best, now_s() - t0);
		}
		double ns = best / (double)n * 1e9;
		if (e == 0)
			ns_spec = ns;
		fprintf(out, "  %-44s %10.1f %12.2f %14.2f\n", em[e].name, ns, 1e3 / ns, tb * 1e3);
		json_array_append_new(je, json_pack("{s:s, s:f, s:f, s:f, s:f}", "mode", em[e].name,
		                                    "ns_per_eval", ns, "per_second", 1e9 / ns,
		                                    "create_ms", tb * 1e3, "cost_vs_specular_only",
		                                    ns / ns_spec));
		pc_pbrdf_free(p);
	}
	fprintf(out, "\n");
	json_object_set_new(root, "pbrdf", je);
	free(g);

	/* --- ρ^s accuracy vs cost --- */
	const int ref_order = quick ? 256 : 512;
	const double mats[][2] = {{1.5, 0}, {1.46, 1.28}, {0.2, 3.5}};
	const double sigmas[] = {0.02, 0.05, 0.1, 0.2, 0.35, 0.5};
	const double thetas[] = {0, 10, 20, 30, 40, 50, 60, 70, 80, 85, 89};
	int nm = quick ? 2 : 3, ns = quick ? 3 : 6, nt = 11;
	int ncase = nm * ns * nt;
	rho_case *cs = malloc((size_t)ncase * sizeof *cs);
	double *err = malloc((size_t)ncase * sizeof *err);
	if (!cs || !err)
		return 1;
	fprintf(out,
	        "rho^s accuracy vs cost (Fresnel-weighted, TS shadowing; %d materials x %d sigma "
	        "in [0.02, 0.5] x %d theta_i in [0, 89]; reference: order %d)\n",
	        nm, ns, nt, ref_order);
	double t_ref = now_s();
	int c = 0;
	for (int a = 0; a < nm; a++)
		for (int b = 0; b < ns; b++) {
			pc_material m = {mats[a][0],
			                 mats[a][1],
			                 quick ? sigmas[2 * b] : sigmas[b],
			                 PC_DIFFUSE_FRESNEL,
			                 PC_SHADOW_TS,
			                 PC_RHO_QUAD,
			                 8};
			pc_pbrdf *p = NULL;
			pc_pbrdf_new(&m, &p);
			for (int t = 0; t < nt; t++, c++) {
				cs[c] = (rho_case){m.n, m.k, m.sigma, thetas[t] * DEG, 0};
				cs[c].ref = pc_pbrdf_rho_s_quad(p, cs[c].theta, ref_order);
			}
			pc_pbrdf_free(p);
		}
	t_ref = now_s() - t_ref;
	fprintf(out, "  %-30s %9s %11s %11s %11s %12s %10s\n", "mode", "integrand", "us/value",
	        "build ms", "max rel err", "median rel", "max <=80deg");
	const struct {
		const char *name;
		int order;
		int kind; /* 0 direct quadrature, 1 eval table, 2 table mode */
	} rm[] = {
	    {"quad:4 direct", 4, 0},          {"quad:8 direct", 8, 0},
	    {"quad:16 direct", 16, 0},        {"quad:32 direct", 32, 0},
	    {"quad:64 direct", 64, 0},        {"eval table of quad:16", 16, 1},
	    {"eval table of quad:32", 32, 1}, {"table mode 64x32 (quad:16)", 16, 2},
	};
	json_t *jr = json_array();
	for (size_t r = 0; r < sizeof rm / sizeof rm[0]; r++) {
		double t_build = 0, t_eval = 0, maxe = 0, maxe80 = 0;
		long nev = 0;
		pc_pbrdf *p = NULL;
		for (int i = 0; i < ncase; i++) {
			if (!p || cs[i].n != pc_pbrdf_material(p)->n ||
			    cs[i].k != pc_pbrdf_material(p)->k ||
			    cs[i].sigma != pc_pbrdf_material(p)->sigma) {
				pc_pbrdf_free(p);
				pc_material m = {
				    cs[i].n,      cs[i].k,
				    cs[i].sigma,  PC_DIFFUSE_FRESNEL,
				    PC_SHADOW_TS, rm[r].kind == 2 ? PC_RHO_TABLE : PC_RHO_QUAD,
				    rm[r].order};
				double t0 = now_s();
				pc_pbrdf_new(&m, &p);
				t_build += now_s() - t0;
			}
			/* best of 3 timings (of 1 direct quadrature or 1000 table lookups) */
			int reps = rm[r].kind == 0 ? 1 : 1000;
			double v = 0, tbest = INFINITY;
			for (int rep = 0; rep < 3; rep++) {
				double acc = 0, t0 = now_s();
				for (int k = 0; k < reps; k++)
					acc += rm[r].kind == 1
					           ? pc_pbrdf_rho_s_fast(p, cos(cs[i].theta))
					           : pc_pbrdf_rho_s(p, cs[i].theta);
				tbest = fmin(tbest, (now_s() - t0) / reps);
				v = acc / reps;
			}
			t_eval += tbest;
			nev++;
			err[i] = fabs(v - cs[i].ref) / cs[i].ref;
			maxe = fmax(maxe, err[i]);
			if (cs[i].theta <= 80 * DEG + 1e-9)
				maxe80 = fmax(maxe80, err[i]);
		}
		pc_pbrdf_free(p);
		qsort(err, (size_t)ncase, sizeof *err, cmp_d);
		double med = err[ncase / 2];
		double us = t_eval / (double)nev * 1e6;
		double build_ms = rm[r].kind == 0 ? 0 : t_build / (nm * ns) * 1e3;
		char ev[32];
		if (rm[r].kind == 0)
			snprintf(ev, sizeof ev, "%d", rm[r].order * rm[r].order);
		else
			snprintf(ev, sizeof ev, "0");
		char bs[32];
		if (rm[r].kind == 0)
			snprintf(bs, sizeof bs, "-");
		else
			snprintf(bs, sizeof bs, "%.2f", build_ms);
		fprintf(out, "  %-30s %9s %11.3f %11s %11.1e %12.1e %10.1e\n", rm[r].name, ev, us,
		        bs, maxe, med, maxe80);
		json_array_append_new(jr, json_pack("{s:s, s:f, s:f, s:f, s:f, s:f}", "mode",
		                                    rm[r].name, "us_per_value", us, "build_ms",
		                                    build_ms, "max_rel_err", maxe, "median_rel_err",
		                                    med, "max_rel_err_theta_le_80", maxe80));
	}
	fprintf(out,
	        "  (reference: %d values at order %d took %.1f s; eval-table rows time the "
	        "lookup used by pc_pbrdf_eval, build = pc_pbrdf_new per material)\n",
	        ncase, ref_order, t_ref);
	json_object_set_new(root, "rho_s", jr);
	json_object_set_new(root, "rho_s_reference_order", json_integer(ref_order));
	free(cs);
	free(err);
	if (json) {
		char *s = json_dumps(root, JSON_COMPACT | JSON_REAL_PRECISION(6));
		if (s) {
			puts(s);
			free(s);
		}
	}
	json_decref(root);
	return 0;
}
