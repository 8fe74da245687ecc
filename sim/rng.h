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

#include <math.h>
#include <stdint.h>
#include <string.h>

/* What a stream is for; part of the counter so that streams never overlap. */
enum pc_rng_purpose {
	PC_RNG_FRAME = 1,  /* per frame: shot + dark electrons, then read noise */
	PC_RNG_FIXED = 16, /* fixed pattern (frame-independent): orientation, transmission,
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
/* ---- arithmetic shared by the scalar code and the vector kernels (noise_kern.inc) ----
 * Every function below uses only +, −, ×, ÷, sqrt, floor, comparisons and bit operations, in a
 * fixed order (the build is ISO C: no FMA contraction), so a vector kernel that performs the
 * same operations lane by lane produces bit-identical results: frames do not depend on the
 * instruction set the dispatcher picks. The polynomial macros take the variable and evaluate by
 * Horner's rule for either a double or a GCC vector of doubles. */

/* ln 2 split for exact e·ln2_hi (20 significant bits) plus the rest. */
#define PC_LN2_HI 0.6931467056274414
#define PC_LN2_LO 4.7493250390316726e-07
#define PC_SQRT2  1.4142135623730951

/* log(1 + f) = 2 atanh(s), s = f/(2 + f), |s| ≤ 0.1716 for √½ ≤ 1 + f ≤ √2:
 * 2 atanh(s) = 2s + s·R, R = Σ_{j≥1} 2 s^{2j}/(2j + 1) (Abramowitz & Stegun 4.5.2 via
 * ln((1+s)/(1−s))), truncated after s^{20} (relative error < 3e-17), z = s², evaluated by
 * Estrin's scheme (short dependency chains); log(1 + f) = f − (f²/2 − s·(f²/2 + R)), the
 * rounding-friendly form of f − s·(f − R). */
#define PC_LOG_R(z)                                                                                \
	((z) *                                                                                     \
	 (((2.0 / 3 + (z) * (2.0 / 5)) + ((z) * (z)) * (2.0 / 7 + (z) * (2.0 / 9))) +              \
	  (((z) * (z)) * ((z) * (z))) *                                                            \
	      (((2.0 / 11 + (z) * (2.0 / 13)) + ((z) * (z)) * (2.0 / 15 + (z) * (2.0 / 17))) +     \
	       (((z) * (z)) * ((z) * (z))) * (2.0 / 19 + (z) * (2.0 / 21)))))

/* Natural logarithm of a positive, finite, normal x, to about one ulp (tested against libm). */
static inline double pc_log_pure(double x)
{
	uint64_t b;
	memcpy(&b, &x, sizeof b);
	/* exponent as an exact double: (2^52 + E) − 2^52 − 1023 */
	uint64_t eb = (b >> 52) | 0x4330000000000000ull;
	double e;
	memcpy(&e, &eb, sizeof e);
	e = e - 4503599627370496.0 - 1023.0;
	uint64_t mb = (b & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull;
	double m;
	memcpy(&m, &mb, sizeof m);
	if (m > PC_SQRT2) {
		m = m * 0.5;
		e = e + 1.0;
	}
	double f = m - 1.0;
	double s = f / (2.0 + f);
	double z = s * s;
	double R = PC_LOG_R(z);
	double hfsq = 0.5 * f * f;
	return e * PC_LN2_HI + (f - (hfsq - (s * (hfsq + R) + e * PC_LN2_LO)));
}

/* exp(x) for |x| ≤ 700, to about one ulp (tested against libm), from +, −, ×, floor and bit
 * operations only (so the vector kernels reproduce it): x = n·ln2 + r with n = ⌊x/ln2 + ½⌋ and
 * r = (x − n·ln2_hi) − n·ln2_lo (n·ln2_hi is exact: ln2_hi has 20 significant bits), |r| ≤ 0.347;
 * e^r by its Taylor series to r¹³ (truncation r¹⁴/14! < 5e-18 relative; Abramowitz & Stegun
 * 4.2.1) in Horner's rule; 2ⁿ assembled in the exponent field ((n + 1023) read from the mantissa
 * of 2⁵² + n + 1023, exact for these n). */
#define PC_LOG2E 1.4426950408889634
#define PC_EXP_POLY(r)                                                                             \
	(1.0 +                                                                                     \
	 (r) *                                                                                     \
	     (1.0 +                                                                                \
	      (r) *                                                                                \
	          (1.0 / 2 +                                                                       \
	           (r) *                                                                           \
	               (1.0 / 6 +                                                                  \
	                (r) *                                                                      \
	                    (1.0 / 24 +                                                            \
	                     (r) *                                                                 \
	                         (1.0 / 120 +                                                      \
	                          (r) *                                                            \
	                              (1.0 / 720 +                                                 \
	                               (r) *                                                       \
	                                   (1.0 / 5040 +                                           \
	                                    (r) *                                                  \
	                                        (1.0 / 40320 +                                     \
	                                         (r) *                                             \
	                                             (1.0 / 362880 +                               \
	                                              (r) *                                        \
	                                                  (1.0 / 3628800 +                         \
	                                                   (r) *                                   \
	                                                       (1.0 / 39916800 +                   \
	                                                        (r) *                              \
	                                                            (1.0 / 479001600 +             \
	                                                             (r) *                         \
	                                                                 (1.0 /                    \
	                                                                  6227020800.0))))))))))))))
static inline double pc_exp_pure(double x)
{
	double n = floor(x * PC_LOG2E + 0.5);
	double r = (x - n * PC_LN2_HI) - n * PC_LN2_LO;
	double big =
	    n + 1023.0 + 4503599627370496.0; /* 2^52 + n + 1023: the mantissa holds n + 1023 */
	uint64_t b;
	memcpy(&b, &big, sizeof b);
	b = (b & 0x7FFull) << 52;
	double scale;
	memcpy(&scale, &b, sizeof scale);
	return PC_EXP_POLY(r) * scale;
}

/* Wichura's AS 241 (PPND16) rational approximations, coefficients from the paper: the central
 * region |q| ≤ 0.425 in t = 0.180625 − q², and the intermediate region in r = sqrt(−ln p) − 1.6
 * (r ≤ 5, i.e. p ≥ 1.4e-11: every p a 32-bit uniform produces). */
#define PC_AS241_CA(t)                                                                             \
	(((((((2.5090809287301226727e+3 * (t) + 3.3430575583588128105e+4) * (t) +                  \
	      6.7265770927008700853e+4) *                                                          \
	         (t) +                                                                             \
	     4.5921953931549871457e+4) *                                                           \
	        (t) +                                                                              \
	    1.3731693765509461125e+4) *                                                            \
	       (t) +                                                                               \
	   1.9715909503065514427e+3) *                                                             \
	      (t) +                                                                                \
	  1.3314166789178437745e+2) *                                                              \
	     (t) +                                                                                 \
	 3.3871328727963666080e+0)
#define PC_AS241_CB(t)                                                                             \
	(((((((5.2264952788528545610e+3 * (t) + 2.8729085735721942674e+4) * (t) +                  \
	      3.9307895800092710610e+4) *                                                          \
	         (t) +                                                                             \
	     2.1213794301586595867e+4) *                                                           \
	        (t) +                                                                              \
	    5.3941960214247511077e+3) *                                                            \
	       (t) +                                                                               \
	   6.8718700749205790830e+2) *                                                             \
	      (t) +                                                                                \
	  4.2313330701600911252e+1) *                                                              \
	     (t) +                                                                                 \
	 1.0)
#define PC_AS241_TA(t)                                                                             \
	(((((((7.74545014278341407640e-4 * (t) + 2.27238449892691845833e-2) * (t) +                \
	      2.41780725177450611770e-1) *                                                         \
	         (t) +                                                                             \
	     1.27045825245236838258e+0) *                                                          \
	        (t) +                                                                              \
	    3.64784832476320460504e+0) *                                                           \
	       (t) +                                                                               \
	   5.76949722146069140550e+0) *                                                            \
	      (t) +                                                                                \
	  4.63033784615654529590e+0) *                                                             \
	     (t) +                                                                                 \
	 1.42343711074968357734e+0)
#define PC_AS241_TB(t)                                                                             \
	(((((((1.05075007164441684324e-9 * (t) + 5.47593808499534494600e-4) * (t) +                \
	      1.51986665636164571966e-2) *                                                         \
	         (t) +                                                                             \
	     1.48103976427480074590e-1) *                                                          \
	        (t) +                                                                              \
	    6.89767334985100004550e-1) *                                                           \
	       (t) +                                                                               \
	   1.67638483018380384940e+0) *                                                            \
	      (t) +                                                                                \
	  2.05319162663775882187e+0) *                                                             \
	     (t) +                                                                                 \
	 1.0)

/* Hörmann's PTRS constants for mean mu (W. Hörmann, "The transformed rejection method for
 * generating Poisson random variables", Insurance: Mathematics and Economics 12(1):39–45,
 * 1993, section 3): b, a and v_r, the fast-acceptance bound. */
#define PC_PTRS_B(smu) (0.931 + 2.53 * (smu))
#define PC_PTRS_A(b)   (-0.059 + 0.02483 * (b))
/* The fast acceptance v ≤ v_r = 0.9277 − 3.6224/(b − 2), multiplied out by b − 2 > 0 (b ≥ 8.9
 * for mu ≥ 10): the same test without a division (a squeeze: a point it accepts is inside the
 * acceptance region, so rounding at its edge only moves work to the exact slow test). */
#define PC_PTRS_FAST_V(v, b) (((v)-0.9277) * ((b)-2.0) <= -3.6224)
#define PC_PTRS_INV_ALPHA(b) (1.1239 + 1.1328 / ((b)-3.4))
/* The candidate k of one attempt with u in (−½, ½), us = ½ − |u|. */
#define PC_PTRS_K(a, b, mu, u, us) ((2.0 * (a) / (us) + (b)) * (u) + (mu) + 0.43)

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
/* Its second region alone (|p − ½| > 0.425; the kernels' tail pass). */
double pc_normal_quantile_tail(double p);
/* Standard normal by inversion of one 32-bit uniform: one word per deviate, no rejection, so
 * draws stay aligned across pixels; the tails are cut at ±6.34σ (probability 2.3e-10). */
static inline double pc_u32_to_normal(uint32_t u)
{
	return pc_normal_quantile(pc_u32_to_uniform(u));
}
double pc_rng_normal(pc_rng *r);

/* The read noise's standard normal from one 32-bit word, cheaper: where |q| ≤ 0.425 (85 % of
 * the words) AS 241's single-precision PPND7 central region (Wichura 1988, the same paper:
 * |error| < 1e-6 absolute in z, against 1e-15) in float arithmetic, 2·KL lanes per vector in the
 * kernels; the PPND16 tail (pc_normal_quantile) beyond. q = (s + ½)·2⁻³² from the signed word
 * s = u − 2³¹, rounded to float (relative 6e-8: symmetric, unlike 1 − p in float). The region
 * test is on the float q, in both the scalar reference and the kernels. The read noise is
 * σ_read·z electrons (about 2 e⁻) before a gain of ~0.4 DN/e⁻: an error of 1e-6 in z moves one
 * pixel in ~10⁶ by 1 DN at a rounding edge, below what any statistic of a frame resolves. */
#define PC_PPND7_A(r)                                                                              \
	(((5.9109374720e+1f * (r) + 1.5929113202e+2f) * (r) + 5.0434271938e+1f) * (r) +            \
	 3.3871327179e+0f)
#define PC_PPND7_B(r)                                                                              \
	(((6.7187563600e+1f * (r) + 7.8757757664e+1f) * (r) + 1.7895169469e+1f) * (r) + 1.0f)
static inline float pc_u32_to_q_f(uint32_t u)
{
	return ((float)(int32_t)(u ^ 0x80000000u) + 0.5f) * 0x1p-32f;
}
static inline double pc_u32_to_normal_read(uint32_t u)
{
	float q = pc_u32_to_q_f(u);
	if ((double)q < -(double)0.425f || (double)q > (double)0.425f)
		return pc_normal_quantile_tail(pc_u32_to_uniform(u));
	float r = 0.180625f - q * q;
	return (double)(q * PC_PPND7_A(r) / PC_PPND7_B(r));
}

/* ln(k!) (exact sums below 16, Stirling series with 4 correction terms above: |error| < 1e-13).
 * The Stirling branch as a macro of k and ln(k + 1) for the vector kernels:
 * ln Γ(n), n = k + 1 (Abramowitz & Stegun 6.1.41). */
#define PC_LOG_FACTORIAL_STIRLING(k, logn)                                                         \
	(((k) + 1.0 - 0.5) * (logn) - ((k) + 1.0) + 0.91893853320467274178 /* ln sqrt(2π) */ +     \
	 (1.0 / 12.0 -                                                                             \
	  (1.0 / 360.0 - (1.0 / 1260.0 - 1.0 / (1680.0 * (((k) + 1.0) * ((k) + 1.0)))) /           \
	                     (((k) + 1.0) * ((k) + 1.0))) /                                        \
	      (((k) + 1.0) * ((k) + 1.0))) /                                                       \
	     ((k) + 1.0))
double pc_log_factorial(double k);
/* ln(k!) for k < PC_LF_TABLE, the values pc_log_factorial returns (a table filled once, on
 * first use, by pc_log_factorial_table()): the frame kernels gather from it. */
#define PC_LF_TABLE 16384
const double *pc_log_factorial_table(void);

/* Poisson(mu), mu ≥ 0, from 32-bit uniforms: inversion for mu < PC_PTRS_MIN_MU, Hörmann's PTRS
 * transformed rejection otherwise. Exact for every mu the sensor can produce (mu ≤ 1e9);
 * returns a double to cover large means. */
#define PC_PTRS_MIN_MU 10.0
double pc_rng_poisson(pc_rng *r, double mu);
/* Inversion by sequential search from one word (mu < PC_PTRS_MIN_MU): the smallest k with
 * u ≤ Σ_{j≤k} e^{−mu}·mu^j/j!, the terms by p_k = p_{k−1}·(mu·(1/k)) (Devroye, Non-Uniform
 * Random Variate Generation, 1986, X.3.2), at most 200 terms. */
double pc_poisson_inversion(double mu, uint32_t w);

/* PTRS in pieces, for the frame kernels: the constants of a mean, one attempt's fast
 * acceptance from two words (1: accepted, *k set; 0: *k is the candidate, run the slow test),
 * and the slow test (1: accept k). *lmu caches ln mu (NaN: not yet computed). */
typedef struct pc_ptrs {
	double mu, b, a;
} pc_ptrs;
static inline void pc_ptrs_init(pc_ptrs *p, double mu)
{
	p->mu = mu;
	p->b = PC_PTRS_B(sqrt(mu));
	p->a = PC_PTRS_A(p->b);
}
static inline int pc_ptrs_fast(const pc_ptrs *p, uint32_t wu, uint32_t wv, double *k)
{
	double u = pc_u32_to_uniform(wu) - 0.5, v = pc_u32_to_uniform(wv);
	double us = 0.5 - fabs(u);
	*k = floor(PC_PTRS_K(p->a, p->b, p->mu, u, us));
	return us >= 0.07 && PC_PTRS_FAST_V(v, p->b);
}
/* The slow test of Hörmann's PTRS, ln(v·α⁻¹/(a/us² + b)) ≤ −mu + k·ln mu − ln k! (his step
 * 3.3 with the transformation's derivative), evaluated as v·α⁻¹ ≤ e^r·(a/us² + b) with
 * r = −mu + k·ln mu − ln k! (= ln of the Poisson pmf at k, ≤ 0; floored at −700, where e^r is
 * below every left-hand side a 32-bit v produces): an exponential and one division fewer than the
 * logarithm of a quotient. */
#define PC_PTRS_R_FLOOR (-700.0)
int pc_ptrs_slow(const pc_ptrs *p, double v, double us, double k, double *lmu);

#endif
