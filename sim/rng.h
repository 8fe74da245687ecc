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
	PC_RNG_SHOT = 1,        /* per frame: shot + dark electrons */
	PC_RNG_READ = 2,        /* per frame: read noise */
	PC_RNG_DSNU = 16,       /* fixed pattern (frame-independent) */
	PC_RNG_PRNU = 17,
	PC_RNG_ORIENT = 18,
	PC_RNG_TRANS = 19,
	PC_RNG_TEST = 200,
};

/* One Philox4x32-10 block: out = Philox(ctr, key). */
void pc_philox4x32_10(const uint32_t ctr[4], const uint32_t key[2], uint32_t out[4]);

/* A stream of random numbers for one (seed, purpose, pixel, frame); draws after the first four
 * words advance a draw counter inside the Philox counter. */
typedef struct pc_rng {
	uint32_t ctr[4], key[2];
	uint32_t buf[4];
	unsigned used;
} pc_rng;

/* x, y < 65536 (pixel position on the full sensor). */
void pc_rng_init(pc_rng *r, uint64_t seed, unsigned purpose, uint32_t x, uint32_t y, uint64_t frame);
uint32_t pc_rng_u32(pc_rng *r);
/* Uniform in the open interval (0, 1) with 53 random bits. */
double pc_rng_uniform(pc_rng *r);
/* Standard normal (Box–Muller; both values of a pair are used: the second is cached). */
double pc_rng_normal(pc_rng *r);
/* Poisson(mu), mu ≥ 0: inversion for mu < 10, Hörmann's PTRS transformed rejection
 * (W. Hörmann, "The transformed rejection method for generating Poisson random variables",
 * Insurance: Mathematics and Economics 12(1):39–45, 1993) otherwise. Exact for every mu the
 * sensor can produce (mu ≤ 1e9); returns a double to cover large means. */
double pc_rng_poisson(pc_rng *r, double mu);

/* ln(k!) (exact sums below 16, Stirling series with 4 correction terms above: |error| < 1e-13). */
double pc_log_factorial(double k);

#endif
