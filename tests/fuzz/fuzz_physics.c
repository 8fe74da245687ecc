/* libFuzzer harness: the physics functions with property oracles. The input is read as doubles
 * mapped into the documented domains (log-uniform over the whole range, so the extremes come up
 * as often as the middle; raw doubles too), and:
 *   - Fresnel (pc_fresnel_eval, n in (0, 1e100], k in [0, 1e100], β in [0, 90°]): finite,
 *     |r_s|, |r_p| ≤ 1, |r_p| ≤ |r_s| (docs/physics-notes.md: Abelès' relation);
 *   - the pBRDF (pc_pbrdf_new accepts n, k ≤ 1e100, σ in [1e-50, 1e3]): every element finite
 *     at any direction, physically realisable, and Lu–Chipman of it in range;
 *   - Lu–Chipman of any finite matrix with the Cloude filter: D, Δ in [0, 1], R in [0, π];
 *     the filter's output is physical; the map kernel matches the scalar code bit for bit;
 *   - pc_sincos_deg: s² + c² = 1 to rounding, exact zeros at multiples of 90°. */
#include <float.h>
#include <math.h>

#include "fuzz.h"
#include "fuzz_lu_chipman.h"
#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"

typedef struct rd {
	const uint8_t *p;
	size_t n;
} rd;

static uint64_t take64(rd *r)
{
	uint64_t v = 0;
	for (int i = 0; i < 8; i++) {
		v = v << 8 | (r->n ? *r->p : 0);
		if (r->n) {
			r->p++;
			r->n--;
		}
	}
	return v;
}

/* a value in [lo, hi] (lo > 0) log-uniformly, or exactly an end, from 8 bytes */
static double take_log(rd *r, double lo, double hi)
{
	uint64_t v = take64(r);
	switch (v & 7) {
	case 0:
		return lo;
	case 1:
		return hi;
	default: /* exp(log(lo)) may round below lo: clamp */
		return fmin(
		    hi, fmax(lo, exp(log(lo) + (double)(v >> 11) * 0x1p-53 * (log(hi) - log(lo)))));
	}
}

static double take_lin(rd *r, double lo, double hi)
{
	uint64_t v = take64(r);
	if ((v & 15) == 0)
		return lo;
	if ((v & 15) == 1)
		return hi;
	return lo + (double)(v >> 11) * 0x1p-53 * (hi - lo);
}

static double take_raw(rd *r)
{
	uint64_t v = take64(r);
	double d;
	memcpy(&d, &v, sizeof d);
	return d;
}

static void fresnel(rd *r)
{
	double n = take_log(r, 1e-300, 1e100), k = take64(r) & 1 ? 0 : take_log(r, 1e-300, 1e100);
	double beta = take_lin(r, 0, M_PI / 2);
	pc_fresnel f;
	pc_fresnel_angle(n, k, beta, &f);
	double rs = hypot(f.rs_re, f.rs_im), rp = hypot(f.rp_re, f.rp_im);
	FUZZ_ASSERT(isfinite(rs) && isfinite(rp) && rs <= 1 + 1e-12 && rp <= 1 + 1e-12,
	            "n=%.17g k=%.17g beta=%.17g: |rs|=%g |rp|=%g", n, k, beta, rs, rp);
	FUZZ_ASSERT(rp <= rs + 1e-9, "n=%.17g k=%.17g beta=%.17g: |rp|=%.17g > |rs|=%.17g", n, k,
	            beta, rp, rs);
}

static void pbrdf(rd *r, uint8_t mode)
{
	pc_material m = {take_log(r, 1e-300, 1e100),
	                 0,
	                 take_log(r, PC_PBRDF_SIGMA_MIN, 1e3),
	                 (pc_diffuse)(mode % 3),
	                 (pc_shadowing)((mode >> 2) & 1),
	                 (pc_rho_mode)((mode >> 3) & 1),
	                 2 + (mode >> 4) % 3};
	if (take64(r) & 1)
		m.k = take_log(r, 1e-300, 1e100);
	if (m.rho_mode == PC_RHO_TABLE && m.sigma > PC_RHO_TABLE_SIGMA_MAX)
		m.rho_mode = PC_RHO_QUAD;
	pc_pbrdf *p = NULL;
	int rc = pc_pbrdf_new(&m, &p);
	FUZZ_ASSERT(rc == 0, "in-range material refused: n=%.17g k=%.17g sigma=%.17g: %s", m.n, m.k,
	            m.sigma, pc_error_detail());
	for (int g = 0; g < 4; g++) {
		double ti = take_lin(r, 0, 90), tr = take_lin(r, 0, 90),
		       ph = take_lin(r, -360, 360);
		if (g == 1)
			tr = ti, ph = 180; /* the exact specular direction */
		double f[4][4];
		pc_pbrdf_eval_deg(p, ti, tr, ph, f);
		for (int i = 0; i < 16; i++)
			FUZZ_ASSERT(isfinite(f[i / 4][i % 4]),
			            "n=%.17g k=%.17g sigma=%.17g (%.17g, %.17g, %.17g): f[%d] = %g",
			            m.n, m.k, m.sigma, ti, tr, ph, i, f[i / 4][i % 4]);
		/* realisable where the matrix holds full precision: a subnormal f00 keeps a few
		 * digits, whose rounding alone breaks the check (n = 1, k = 4e-208, σ = 1e-50:
		 * f00 = 4e-317; finding_subnormal_specular; docs/reliability.md) */
		if (!(f[0][0] >= DBL_MIN))
			continue;
		FUZZ_ASSERT(pc_mueller_is_physical(f, 1e-9),
		            "not physical: n=%.17g k=%.17g sigma=%.17g (%.17g, %.17g, %.17g)", m.n,
		            m.k, m.sigma, ti, tr, ph);
		pc_lu_chipman lc;
		FUZZ_ASSERT(pc_lu_chipman_decompose(f, PC_LC_FILTER, &lc) == 0, "decompose");
		FUZZ_ASSERT(lc.D >= 0 && lc.D <= 1, "D = %g", lc.D);
	}
	pc_pbrdf_free(p);
}

static void decompose(rd *r, uint8_t mode)
{
	double M[4][4];
	double scale = take_log(r, 1e-320, 1e300);
	for (int i = 0; i < 16; i++) {
		double v = mode & 1 ? take_raw(r) : take_lin(r, -1, 1) * scale;
		M[i / 4][i % 4] = isfinite(v) ? v : 0;
	}
	if (mode & 2) { /* a dominant m00; the sum of three entries near DBL_MAX overflows: cap it
		         * (the library refuses a non-finite matrix by design) */
		M[0][0] = fabs(M[0][0]) + fabs(M[0][1]) + fabs(M[1][0]);
		if (!isfinite(M[0][0]))
			M[0][0] = DBL_MAX;
	}
	fuzz_lc_ranges(M);
	double F[4][4];
	bool changed;
	pc_mueller_cloude_filter(M, F, &changed);
	/* finite wherever representable: the filtered entries are at most 4·max|M_ij| (optics.h),
	 * so a matrix with entries above DBL_MAX/4 may rightly give ±inf */
	double mmx = 0;
	bool fin = true;
	for (int i = 0; i < 16; i++) {
		fin &= isfinite(F[i / 4][i % 4]);
		mmx = fmax(mmx, fabs(M[i / 4][i % 4]));
	}
	FUZZ_ASSERT(fin || mmx > DBL_MAX / 8, "filter output not finite (max|M_ij| = %g)", mmx);
	/* (a filtered matrix whose entries are subnormal keeps only a few significant digits: its
	 * rounding alone can break realisability, so the check needs full-precision entries) */
	double fmx = 0;
	for (int i = 0; i < 16; i++)
		fmx = fmax(fmx, fabs(F[i / 4][i % 4]));
	if (fin && F[0][0] > 0 && changed && fmx > 0x1p-960 && !pc_mueller_is_physical(F, 1e-6)) {
		for (int i = 0; i < 4; i++)
			fprintf(stderr, "M %.17g %.17g %.17g %.17g | F %.17g %.17g %.17g %.17g\n",
			        M[i][0], M[i][1], M[i][2], M[i][3], F[i][0], F[i][1], F[i][2],
			        F[i][3]);
		FUZZ_ASSERT(0, "filtered matrix not physical (min eigenvalue/trace %g)",
		            pc_mueller_min_coherency_eig(F));
	}
	fuzz_lc_map_vs_scalar(M);
}

static void sincos(rd *r)
{
	double d =
	    take64(r) & 1 ? take_raw(r) : 90.0 * (double)(int64_t)(take64(r) % 2000001 - 1000000);
	if (!isfinite(d))
		return;
	double s, c;
	pc_sincos_deg(d, &s, &c);
	FUZZ_ASSERT(fabs(s * s + c * c - 1) <= 4e-16, "deg %.17g: s=%.17g c=%.17g", d, s, c);
	if (fmod(d, 90.0) == 0)
		FUZZ_ASSERT((s == 0 || fabs(s) == 1) && (c == 0 || fabs(c) == 1), "deg %.17g", d);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	fuzz_dir();
	if (size < 2)
		return 0;
	rd r = {data + 2, size - 2};
	switch (data[0] & 3) {
	case 0:
		fresnel(&r);
		break;
	case 1:
		pbrdf(&r, data[1]);
		break;
	case 2:
		decompose(&r, data[1]);
		break;
	default:
		sincos(&r);
		break;
	}
	return 0;
}
