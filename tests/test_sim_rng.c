/* The counter-based generator behind reproducible frames: Philox4x32-10 against Random123's
 * published known-answer vectors, uniform/normal moments, Poisson samples against the exact
 * pmf (chi-square) for small and large means, ln k! against direct sums, determinism. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../sim/rng.h"
#include "check.h"

static void test_kat(void)
{
	/* Random123 kat_vectors, philox4x32 10 rounds */
	static const uint32_t ctr[3][4] = { { 0, 0, 0, 0 },
					    { 0xffffffff, 0xffffffff, 0xffffffff, 0xffffffff },
					    { 0x243f6a88, 0x85a308d3, 0x13198a2e, 0x03707344 } };
	static const uint32_t key[3][2] = { { 0, 0 }, { 0xffffffff, 0xffffffff },
					    { 0xa4093822, 0x299f31d0 } };
	static const uint32_t want[3][4] = { { 0x6627e8d5, 0xe169c58d, 0xbc57ac4c, 0x9b00dbd8 },
					     { 0x408f276d, 0x41c83b0e, 0xa20bc7c6, 0x6d5451fd },
					     { 0xd16cfe09, 0x94fdcceb, 0x5001e420, 0x24126ea1 } };
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
		fprintf(stderr, "Poisson mu=%g: chi2 = %.1f with %d dof (crit %.1f)\n", mu, chi2, dof,
			crit);
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

int main(void)
{
	test_kat();
	test_moments();
	test_poisson();
	test_quantile();
	test_log_factorial();
	test_determinism();
	return pc_test_finish("test_sim_rng");
}
