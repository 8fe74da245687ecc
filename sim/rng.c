#include "rng.h"

#include <math.h>

/* Philox4x32 round constants (Salmon et al. 2011, section 4.2; the Weyl key increments are the
 * golden ratio and sqrt(3) − 1 in 32-bit fixed point). */
#define PHILOX_M0 0xD2511F53u
#define PHILOX_M1 0xCD9E8D57u
#define PHILOX_W0 0x9E3779B9u
#define PHILOX_W1 0xBB67AE85u

void pc_philox4x32_10(const uint32_t ctr[4], const uint32_t key[2], uint32_t out[4])
{
	uint32_t c0 = ctr[0], c1 = ctr[1], c2 = ctr[2], c3 = ctr[3];
	uint32_t k0 = key[0], k1 = key[1];
	for (int round = 0; round < 10; round++) {
		uint64_t p0 = (uint64_t)PHILOX_M0 * c0;
		uint64_t p1 = (uint64_t)PHILOX_M1 * c2;
		uint32_t n0 = (uint32_t)(p1 >> 32) ^ c1 ^ k0;
		uint32_t n1 = (uint32_t)p1;
		uint32_t n2 = (uint32_t)(p0 >> 32) ^ c3 ^ k1;
		uint32_t n3 = (uint32_t)p0;
		c0 = n0;
		c1 = n1;
		c2 = n2;
		c3 = n3;
		k0 += PHILOX_W0;
		k1 += PHILOX_W1;
	}
	out[0] = c0;
	out[1] = c1;
	out[2] = c2;
	out[3] = c3;
}

/* Counter layout: ctr[0] = y·65536 + x, ctr[1] = purpose | draw << 8, ctr[2..3] = frame. */
void pc_rng_init(pc_rng *r, uint64_t seed, unsigned purpose, uint32_t x, uint32_t y, uint64_t frame)
{
	r->key[0] = (uint32_t)seed;
	r->key[1] = (uint32_t)(seed >> 32);
	r->ctr[0] = (y << 16) | (x & 0xFFFFu);
	r->ctr[1] = purpose & 0xFFu;
	r->ctr[2] = (uint32_t)frame;
	r->ctr[3] = (uint32_t)(frame >> 32);
	r->used = 4;
}

uint32_t pc_rng_u32(pc_rng *r)
{
	if (r->used == 4) {
		pc_philox4x32_10(r->ctr, r->key, r->buf);
		r->ctr[1] += 1u << 8; /* next draw block of this stream */
		r->used = 0;
	}
	return r->buf[r->used++];
}

double pc_rng_uniform(pc_rng *r)
{
	uint32_t a = pc_rng_u32(r) >> 5, b = pc_rng_u32(r) >> 6; /* 27 + 26 = 53 bits */
	double x = (double)a * 67108864.0 + (double)b;
	return (x + 0.5) * (1.0 / 9007199254740992.0);
}

double pc_rng_normal(pc_rng *r)
{
	/* Box–Muller (Box & Muller, Ann. Math. Stat. 29(2):610, 1958); uses one of the pair: the
	 * stream is per pixel and short, caching the other value would make draws depend on the
	 * order of calls across purposes. */
	double u1 = pc_rng_uniform(r), u2 = pc_rng_uniform(r);
	return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

double pc_log_factorial(double k)
{
	if (k < 16) {
		double s = 0;
		for (int i = 2; i <= (int)k; i++)
			s += log((double)i);
		return s;
	}
	/* ln Γ(n), n = k + 1: Stirling series (Abramowitz & Stegun 6.1.41). */
	double n = k + 1, n2 = n * n;
	return (n - 0.5) * log(n) - n + 0.91893853320467274178 /* ln sqrt(2π) */ +
	       (1.0 / 12.0 - (1.0 / 360.0 - (1.0 / 1260.0 - 1.0 / (1680.0 * n2)) / n2) / n2) / n;
}

double pc_rng_poisson(pc_rng *r, double mu)
{
	if (!(mu > 0))
		return 0;
	if (mu < 10) {
		/* Inversion by sequential search of the CDF. */
		double u = pc_rng_uniform(r);
		double p = exp(-mu), cdf = p;
		double k = 0;
		while (u > cdf && k < 200) {
			k += 1;
			p *= mu / k;
			cdf += p;
		}
		return k;
	}
	/* PTRS, Hörmann 1993, section 3 (constants from the paper). */
	double smu = sqrt(mu), lmu = log(mu);
	double b = 0.931 + 2.53 * smu;
	double a = -0.059 + 0.02483 * b;
	double inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
	double v_r = 0.9277 - 3.6224 / (b - 2);
	for (;;) {
		double u = pc_rng_uniform(r) - 0.5;
		double v = pc_rng_uniform(r);
		double us = 0.5 - fabs(u);
		double k = floor((2 * a / us + b) * u + mu + 0.43);
		if (us >= 0.07 && v <= v_r)
			return k;
		if (k < 0 || (us < 0.013 && v > us))
			continue;
		if (log(v * inv_alpha / (a / (us * us) + b)) <= -mu + k * lmu - pc_log_factorial(k))
			return k;
	}
}
