/* The counter-based generator behind reproducible frames: Philox4x32-10 against Random123's
 * published known-answer vectors, uniform/normal moments, Poisson samples against the exact
 * pmf (chi-square) for small and large means, ln k! against direct sums, determinism. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/noise.h"
#include "../sim/rng.h"
#include "check.h"

static void test_kat(void)
{
	/* Random123 kat_vectors, philox4x32 10 rounds */
	static const uint32_t ctr[3][4] = {{0, 0, 0, 0},
	                                   {0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff},
	                                   {0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344}};
	static const uint32_t key[3][2] = {
	    {0, 0}, {0xffffffff, 0xffffffff}, {0xa4093822, 0x299f31d0}};
	static const uint32_t want[3][4] = {{0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8},
	                                    {0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd},
	                                    {0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1}};
	for (int i = 0; i < 3; i++) {
		uint32_t out[4];
		pc_philox4x32_10(ctr[i], key[i], out);
		for (int k = 0; k < 4; k++)
			CHECK_EQ_INT(out[k], want[i][k]);
	}
}

static void test_moments(void)
{
	const int n = 200000;
	double su = 0, su2 = 0, sn = 0, sn2 = 0, sn4 = 0, umin = 1, umax = 0;
	for (int i = 0; i < n; i++) {
		pc_rng r;
		pc_rng_init(&r, 7, PC_RNG_TEST, (uint32_t)(i % 65536), (uint32_t)(i / 65536), 3);
		double u = pc_rng_uniform(&r), z = pc_rng_normal(&r);
		su += u;
		su2 += u * u;
		umin = fmin(umin, u);
		umax = fmax(umax, u);
		sn += z;
		sn2 += z * z;
		sn4 += z * z * z * z;
	}
	/* tolerances: 5 standard errors */
	CHECK_NEAR(su / n, 0.5, 5 * sqrt(1.0 / 12 / n));
	CHECK_NEAR(su2 / n - (su / n) * (su / n), 1.0 / 12, 5 * sqrt(1.0 / 180 / n));
	CHECK(umin > 0 && umax < 1);
	CHECK_NEAR(sn / n, 0, 5 / sqrt(n));
	CHECK_NEAR(sn2 / n, 1, 5 * sqrt(2.0 / n));
	CHECK_NEAR(sn4 / n, 3, 5 * sqrt(96.0 / n)); /* Gaussian kurtosis */
	/* the normal's CDF at a few points (binomial standard errors) */
}

/* Chi-square of Poisson(mu) samples against the exact pmf on bins with expected count ≥ 20. */
static void check_poisson(double mu, int n)
{
	int kmax = (int)(mu + 12 * sqrt(mu) + 20);
	double *pmf = calloc((size_t)kmax + 1, sizeof *pmf);
	long *cnt = calloc((size_t)kmax + 1, sizeof *cnt);
	for (int k = 0; k <= kmax; k++)
		pmf[k] = exp(-mu + k * log(mu) - lgamma(k + 1.0));
	double s = 0, s2 = 0;
	for (int i = 0; i < n; i++) {
		pc_rng r;
		pc_rng_init(&r, 11, PC_RNG_TEST, (uint32_t)(i & 0xffff), (uint32_t)(i >> 16),
		            (uint64_t)(mu * 1000));
		double k = pc_rng_poisson(&r, mu);
		CHECK(k >= 0 && k == floor(k));
		s += k;
		s2 += k * k;
		if (k <= kmax)
			cnt[(int)k]++;
	}
	double mean = s / n, var = s2 / n - mean * mean;
	CHECK_NEAR(mean, mu, 5 * sqrt(mu / n));
	CHECK_NEAR(var, mu, 6 * mu * sqrt(2.0 / n) + 5 * sqrt(mu) / n);
	/* merge bins into groups with expected ≥ 20 */
	double chi2 = 0, e = 0, o = 0;
	int dof = -1;
	for (int k = 0; k <= kmax; k++) {
		e += pmf[k] * n;
		o += (double)cnt[k];
		if (e >= 20 || k == kmax) {
			chi2 += (o - e) * (o - e) / e;
			dof++;
			e = o = 0;
		}
	}
	/* 99.99th percentile of chi-square(dof) ≈ dof + 3.72·sqrt(2·dof) + 8 (Wilson–Hilferty,
	 * generous): a correct sampler fails this with probability < 1e-4 */
	double crit = dof + 3.72 * sqrt(2.0 * dof) + 8;
	if (!(chi2 < crit))
		fprintf(stderr, "Poisson mu=%g: chi2 = %.1f with %d dof (crit %.1f)\n", mu, chi2,
		        dof, crit);
	CHECK(chi2 < crit);
	free(pmf);
	free(cnt);
}

static void test_poisson(void)
{
	check_poisson(0.5, 100000);
	check_poisson(3, 100000);
	check_poisson(9.99, 100000); /* inversion, just below the switch */
	check_poisson(10, 100000);   /* PTRS, at the switch */
	check_poisson(37.5, 100000);
	check_poisson(1000, 100000);
	check_poisson(25000, 50000);
	pc_rng r;
	pc_rng_init(&r, 1, PC_RNG_TEST, 0, 0, 0);
	CHECK(pc_rng_poisson(&r, 0) == 0);
	CHECK(pc_rng_poisson(&r, -1) == 0);
}

/* Φ(Φ⁻¹(p)) = p, with Φ from erfc (independent of AS 241), over the whole range a 32-bit
 * uniform produces; symmetry; monotonicity */
static void test_quantile(void)
{
	double prev = -INFINITY;
	for (int i = 0; i <= 4000; i++) {
		/* log-spaced from 2^-33 up to ½ and symmetrically down to 1 − 2^-33; dyadic values
		 * so that 1 − p is exact */
		double e = i <= 2000 ? -33 + 32 * i / 2000.0 : -1 - 32 * (i - 2000) / 2000.0;
		double p = ldexp(floor(ldexp(exp2(e), 40)), -40);
		if (i > 2000)
			p = 1 - p;
		if (p <= 0 || p >= 1)
			continue;
		double z = pc_normal_quantile(p);
		double back = p < 0.5 ? 0.5 * erfc(-z / sqrt(2)) : 1 - 0.5 * erfc(z / sqrt(2));
		CHECK_NEAR(back, p, 1e-14 * fmin(p, 1 - p) + 1e-17);
		CHECK(z >= prev);
		prev = z;
		CHECK_NEAR(pc_normal_quantile(1 - p), -z, 1e-12 * (1 + fabs(z)));
	}
	CHECK(pc_normal_quantile(0.5) == 0);
	CHECK_NEAR(pc_u32_to_normal(0), -6.34, 0.01); /* the tail cut documented in rng.h */
}

/* The read noise's float PPND7 central region against the double AS 241 quantile: every 4096th
 * word and both ends of the central region, |error| ≤ 1e-6 (Wichura's bound for PPND7 is
 * ~1e-7 relative; float rounding adds up to ~6e-8 relative); the tail is PPND16 itself; odd
 * symmetry; and the distribution: the fraction of words at or below z = −2, −1, 0, 1, 2 equals
 * Φ(z) to the word resolution. */
static void test_normal_read(void)
{
	double worst = 0;
	uint64_t below[5] = {0}, n = 0;
	const double zs[5] = {-2, -1, 0, 1, 2};
	for (uint64_t w = 0; w < (1ull << 32); w += 4096) {
		for (uint64_t d = 0; d < 2; d++) {
			uint32_t u = (uint32_t)(w + d * 1234);
			double zr = pc_u32_to_normal_read(u), zd = pc_u32_to_normal(u);
			worst = fmax(worst, fabs(zr - zd));
			CHECK_NEAR(pc_u32_to_normal_read(~u), -zr, 1e-6 * (1 + fabs(zr)));
			for (int k = 0; k < 5; k++)
				below[k] += zr <= zs[k];
			n++;
		}
	}
	/* where the regions meet: q = ±0.425 */
	for (int s = -1; s <= 1; s += 2)
		for (int64_t dw = -2000; dw <= 2000; dw++) {
			int64_t w = (int64_t)2147483648 + s * (int64_t)(0.425 * 4294967296.0) + dw;
			double zr = pc_u32_to_normal_read((uint32_t)w),
			       zd = pc_u32_to_normal((uint32_t)w);
			worst = fmax(worst, fabs(zr - zd));
		}
	fprintf(stderr,
	        "test_sim_rng: read-noise normal (float PPND7 centre) within %.2g of AS 241 "
	        "(double)\n",
	        worst);
	CHECK(worst <= 1e-6);
	for (int k = 0; k < 5; k++) {
		double phi = 0.5 * erfc(-zs[k] / sqrt(2));
		CHECK_NEAR((double)below[k] / (double)n, phi, 2e-6);
	}
}

static void test_log_factorial(void)
{
	double s = 0;
	for (int k = 0; k <= 400; k++) {
		if (k >= 2)
			s += log((double)k);
		CHECK_NEAR(pc_log_factorial(k), s, 1e-12 * (1 + s));
	}
}

static void test_determinism(void)
{
	pc_rng a, b, c;
	pc_rng_init(&a, 42, PC_RNG_FRAME, 100, 200, 5);
	pc_rng_init(&b, 42, PC_RNG_FRAME, 100, 200, 5);
	pc_rng_init(&c, 42, PC_RNG_FRAME, 100, 200, 6);
	int same = 1, diff = 0;
	for (int i = 0; i < 16; i++) {
		uint32_t x = pc_rng_u32(&a), y = pc_rng_u32(&b), z = pc_rng_u32(&c);
		same &= x == y;
		diff += x != z;
	}
	CHECK(same);
	CHECK(diff >= 15);
	/* neighbouring pixels and purposes give unrelated streams */
	pc_rng_init(&a, 42, PC_RNG_FRAME, 101, 200, 5);
	pc_rng_init(&b, 42, PC_RNG_FIXED, 100, 200, 5);
	pc_rng_init(&c, 42, PC_RNG_FRAME, 100, 200, 5);
	uint32_t z = pc_rng_u32(&c);
	CHECK(pc_rng_u32(&a) != z);
	CHECK(pc_rng_u32(&b) != z);
}

/* The scalar-shared logarithm against libm: within 1 ulp over the whole exponent range. */
static void test_log_pure(void)
{
	double worst = 0;
	for (int i = 0; i < 200000; i++) {
		pc_rng r;
		pc_rng_init(&r, 5, PC_RNG_TEST, (uint32_t)(i & 0xffff), (uint32_t)(i >> 16), 0);
		double x = exp((pc_rng_uniform(&r) - 0.5) * 1400); /* 1e-304 .. 1e304 */
		if (i < 1000)
			x = 1 + (i - 500) * 1e-6; /* near 1, where log is small */
		double want = log(x), got = pc_log_pure(x);
		double ulp = nextafter(fabs(want), INFINITY) - fabs(want);
		if (want != 0)
			worst = fmax(worst, fabs(got - want) / ulp);
		else
			CHECK(got == 0);
	}
	CHECK(worst <= 1.0);
	CHECK(pc_log_pure(1) == 0);
	CHECK_NEAR(pc_log_pure(2), M_LN2, 1e-16);
}

/* The scalar-shared exponential against libm over the range the sensor chain uses (−10 .. 0,
 * the inversion's e^−mu) and the whole documented range |x| ≤ 700. */
static void test_exp_pure(void)
{
	double worst = 0, worst_inv = 0;
	for (int i = 0; i < 200000; i++) {
		pc_rng r;
		pc_rng_init(&r, 6, PC_RNG_TEST, (uint32_t)(i & 0xffff), (uint32_t)(i >> 16), 0);
		double u = pc_rng_uniform(&r);
		double x = i % 2 ? -10 * u : (u - 0.5) * 1400;
		double want = exp(x), got = pc_exp_pure(x);
		double ulp = nextafter(want, INFINITY) - want;
		double d = fabs(got - want) / ulp;
		worst = fmax(worst, d);
		if (i % 2)
			worst_inv = fmax(worst_inv, d);
	}
	printf("test_sim_rng: pc_exp_pure within %.2f ulp of libm (%.2f on [-10, 0])\n", worst,
	       worst_inv);
	CHECK(worst <= 2.0);
	CHECK(pc_exp_pure(0) == 1);
	CHECK_NEAR(pc_exp_pure(-1), exp(-1), 2e-16);
}

/* The frame and fixed-pattern kernels: every vector instance this CPU can run produces exactly
 * the scalar reference's values, over means from 0 through the inversion/PTRS switch to
 * saturation, with and without DSNU, read noise and noise, at odd offsets and lengths (vector
 * tails). */
static void test_kernels(void)
{
	enum { N = 777 };
	static float rate[N], dsnu[N];
	static uint16_t got[N], want[N];
	static double zg[4][N], zw[4][N];
	for (int i = 0; i < N; i++) {
		pc_rng r;
		pc_rng_init(&r, 9, PC_RNG_TEST, (uint32_t)i, 0, 0);
		double u = pc_rng_uniform(&r);
		/* rates × 1 ms: 0, below 10, around 10, up to beyond the full well */
		rate[i] = (float)(i % 11 == 0  ? 0
		                  : i % 5 == 0 ? u * 2e4
		                  : i % 7 == 0 ? 9e3 + u * 2e3
		                               : u * 1.2e7);
		dsnu[i] = (float)(pc_rng_uniform(&r) * 4 - 2);
	}
	int base = pc_noise_isa(), tested = 0;
	for (int isa = 0; isa <= 2; isa++) {
		if (pc_noise_set_isa(isa) < 0)
			continue;
		tested++;
		for (int c = 0; c < 8; c++) {
			pc_frame_args a = {.seed = 0x123456789abcdefull + (uint64_t)c,
			                   .frame = 1000000007ull * (uint64_t)c,
			                   .sx0 = (uint32_t)(3 * c),
			                   .sy = (uint32_t)(17 * c + 1),
			                   .n = (uint32_t)(N - 13 * c),
			                   .rate = rate,
			                   .dsnu = c & 1 ? dsnu : NULL,
			                   .t_s = 1e-3,
			                   .dark_e = c & 2 ? 0.5 : 0,
			                   .full_well_e = 10500,
			                   .K = 4095.0 / 10500,
			                   .offset_dn = c & 4 ? 64 : 0,
			                   .read_e = c == 3 ? 0 : 2.3,
			                   .max_dn = 4095,
			                   .noise = c != 5,
			                   .out = got};
			pc_noise_frame_row(&a);
			a.out = want;
			pc_noise_frame_row_ref(&a);
			CHECK(!memcmp(got, want, a.n * sizeof *got));
			double *pg[4] = {zg[0], zg[1], zg[2], zg[3]},
			       *pw[4] = {zw[0], zw[1], zw[2], zw[3]};
			unsigned mask = c == 0 ? 15 : (unsigned)(c & 15);
			memset(zg, 0, sizeof zg);
			memset(zw, 0, sizeof zw);
			pc_noise_fixed_row(a.seed, a.sy, a.sx0, a.n, mask, pg);
			pc_noise_fixed_row_ref(a.seed, a.sy, a.sx0, a.n, mask, pw);
			CHECK(!memcmp(zg, zw, sizeof zg));
		}
	}
	CHECK(tested >= 1);
	CHECK(pc_noise_set_isa(base) >= 0);
	printf("test_sim_rng: kernels identical to the scalar reference on %d instance%s (in use: "
	       "%s)\n",
	       tested, tested == 1 ? "" : "s", pc_noise_isa_name(base));
}

int main(void)
{
	test_kat();
	test_moments();
	test_poisson();
	test_quantile();
	test_normal_read();
	test_log_factorial();
	test_determinism();
	test_log_pure();
	test_exp_pure();
	test_kernels();
	return pc_test_finish("test_sim_rng");
}
