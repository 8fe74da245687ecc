/* sim/rng.h - counter-based random numbers for reproducible frames (internal to sim/).
 *
 * Philox4x32-10 (Salmon, Moraes, Dror, Shaw, "Parallel random numbers: as easy as 1, 2, 3",
 * SC'11, 2011): a bijection of a 128-bit counter under a 64-bit key. We key it with the user's
 * seed and put (pixel, purpose, draw, frame) in the counter, so every random number of every
 * pixel of every frame is addressed directly: no state is carried between pixels, rows, bands or
 * threads, and any frame or row band is reproducible on its own.
 */
#ifndef POLARCAM_SIM_RNG_H
#define POLARCAM_SIM_RNG_H

#include <stdint.h>

/* What a stream is for; part of the counter so that streams never overlap. */
enum pc_rng_purpose {
	PC_RNG_FRAME = 1,       /* per frame: shot + dark electrons, then read noise */
	PC_RNG_FIXED = 16,      /* fixed pattern (frame-independent): orientation, transmission,
				 * PRNU, DSNU normals from the stream's first four words */
	PC_RNG_TEST = 200,
};

/* One Philox4x32-10 block: out = Philox(ctr, key). Round constants from Salmon et al. 2011,
 * section 4.2 (the Weyl key increments are the golden ratio and sqrt(3) − 1 in 32-bit fixed
 * point). Inline: it is the inner loop of every noisy frame. */
static inline void pc_philox4x32_10(const uint32_t ctr[4], const uint32_t key[2], uint32_t out[4])
{
	uint32_t c0 = ctr[0], c1 = ctr[1], c2 = ctr[2], c3 = ctr[3];
	uint32_t k0 = key[0], k1 = key[1];
	for (int round = 0; round < 10; round++) {
		uint64_t p0 = (uint64_t)0xD2511F53u * c0;
		uint64_t p1 = (uint64_t)0xCD9E8D57u * c2;
		uint32_t n0 = (uint32_t)(p1 >> 32) ^ c1 ^ k0;
		uint32_t n2 = (uint32_t)(p0 >> 32) ^ c3 ^ k1;
		c1 = (uint32_t)p1;
		c3 = (uint32_t)p0;
		c0 = n0;
		c2 = n2;
		k0 += 0x9E3779B9u;
		k1 += 0xBB67AE85u;
	}
	out[0] = c0;
	out[1] = c1;
	out[2] = c2;
	out[3] = c3;
}

/* A stream of random numbers for one (seed, purpose, pixel, frame); draws after the first four
 * words advance a draw counter inside the Philox counter. */
typedef struct pc_rng {
	uint32_t ctr[4], key[2];
	uint32_t buf[4];
	unsigned used;
} pc_rng;

/* x, y < 65536 (pixel position on the full sensor). */
/* Counter layout: ctr[0] = y·65536 + x, ctr[1] = purpose | draw << 8, ctr[2..3] = frame. */
static inline void pc_rng_init(pc_rng *r, uint64_t seed, unsigned purpose, uint32_t x, uint32_t y,
			       uint64_t frame)
{
	r->key[0] = (uint32_t)seed;
	r->key[1] = (uint32_t)(seed >> 32);
	r->ctr[0] = (y << 16) | (x & 0xFFFFu);
	r->ctr[1] = purpose & 0xFFu;
	r->ctr[2] = (uint32_t)frame;
	r->ctr[3] = (uint32_t)(frame >> 32);
	r->used = 4;
}

static inline uint32_t pc_rng_u32(pc_rng *r)
{
	if (r->used == 4) {
		pc_philox4x32_10(r->ctr, r->key, r->buf);
		r->ctr[1] += 1u << 8; /* next draw block of this stream */
		r->used = 0;
	}
	return r->buf[r->used++];
}
/* Uniform in the open interval (0, 1) with 53 random bits. */
double pc_rng_uniform(pc_rng *r);
/* Uniform in (0, 1) from one 32-bit word: (u + ½)·2⁻³², the noise kernels' resolution. */
static inline double pc_u32_to_uniform(uint32_t u)
{
	return ((double)u + 0.5) * (1.0 / 4294967296.0);
}
/* Standard normal quantile Φ⁻¹(p) for p in [2⁻³³, 1 − 2⁻³³] (Wichura's algorithm AS 241,
 * Applied Statistics 37(3):477–484, 1988, its first two regions: |error| < 1e-15 there). */
double pc_normal_quantile(double p);
/* Standard normal by inversion of one 32-bit uniform: one word per deviate, no rejection, so
 * draws stay aligned across pixels; the tails are cut at ±6.34σ (probability 2.3e-10). */
static inline double pc_u32_to_normal(uint32_t u)
{
	return pc_normal_quantile(pc_u32_to_uniform(u));
}
double pc_rng_normal(pc_rng *r);
/* Poisson(mu), mu ≥ 0, from 32-bit uniforms: inversion for mu < 10, Hörmann's PTRS transformed
 * rejection
 * (W. Hörmann, "The transformed rejection method for generating Poisson random variables",
 * Insurance: Mathematics and Economics 12(1):39–45, 1993) otherwise. Exact for every mu the
 * sensor can produce (mu ≤ 1e9); returns a double to cover large means. */
double pc_rng_poisson(pc_rng *r, double mu);

/* ln(k!) (exact sums below 16, Stirling series with 4 correction terms above: |error| < 1e-13). */
double pc_log_factorial(double k);

#endif
