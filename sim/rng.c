#include "rng.h"

#include <math.h>

double pc_rng_uniform(pc_rng *r)
{
	uint32_t a = pc_rng_u32(r) >> 5, b = pc_rng_u32(r) >> 6; /* 27 + 26 = 53 bits */
	double x = (double)a * 67108864.0 + (double)b;
	return (x + 0.5) * (1.0 / 9007199254740992.0);
}

double pc_normal_quantile(double p)
{
	/* AS 241 (PPND16): a rational approximation in r = 0.180625 − q² for |q| ≤ 0.425 and in
	 * sqrt(−ln min(p, 1−p)) − 1.6 out to r ≤ 5 (p ≥ 1.4e-11), which covers every p a 32-bit
	 * uniform produces; coefficients from the paper. */
	double q = p - 0.5;
	if (fabs(q) <= 0.425) {
		double t = 0.180625 - q * q;
		return q *
		       (((((((2.5090809287301226727e+3 * t + 3.3430575583588128105e+4) * t +
			     6.7265770927008700853e+4) * t + 4.5921953931549871457e+4) * t +
			   1.3731693765509461125e+4) * t + 1.9715909503065514427e+3) * t +
			 1.3314166789178437745e+2) * t + 3.3871328727963666080e+0) /
		       (((((((5.2264952788528545610e+3 * t + 2.8729085735721942674e+4) * t +
			     3.9307895800092710610e+4) * t + 2.1213794301586595867e+4) * t +
			   5.3941960214247511077e+3) * t + 6.8718700749205790830e+2) * t +
			 4.2313330701600911252e+1) * t + 1.0);
	}
	double t = sqrt(-log(q < 0 ? p : 1 - p)) - 1.6;
	double z = (((((((7.74545014278341407640e-4 * t + 2.27238449892691845833e-2) * t +
			 2.41780725177450611770e-1) * t + 1.27045825245236838258e+0) * t +
		       3.64784832476320460504e+0) * t + 5.76949722146069140550e+0) * t +
		     4.63033784615654529590e+0) * t + 1.42343711074968357734e+0) /
		   (((((((1.05075007164441684324e-9 * t + 5.47593808499534494600e-4) * t +
			 1.51986665636164571966e-2) * t + 1.48103976427480074590e-1) * t +
		       6.89767334985100004550e-1) * t + 1.67638483018380384940e+0) * t +
		     2.05319162663775882187e+0) * t + 1.0);
	return q < 0 ? -z : z;
}

double pc_rng_normal(pc_rng *r)
{
	return pc_u32_to_normal(pc_rng_u32(r));
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
		double u = pc_u32_to_uniform(pc_rng_u32(r));
		double p = exp(-mu), cdf = p;
		double k = 0;
		while (u > cdf && k < 200) {
			k += 1;
			p *= mu / k;
			cdf += p;
		}
		return k;
	}
	/* PTRS, Hörmann 1993, section 3 (constants from the paper). The fast acceptance (~86 % of
	 * draws) needs no logarithm: ln µ is computed only for the slow test. */
	double smu = sqrt(mu), lmu = NAN;
	double b = 0.931 + 2.53 * smu;
	double a = -0.059 + 0.02483 * b;
	double inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
	double v_r = 0.9277 - 3.6224 / (b - 2);
	for (;;) {
		double u = pc_u32_to_uniform(pc_rng_u32(r)) - 0.5;
		double v = pc_u32_to_uniform(pc_rng_u32(r));
		double us = 0.5 - fabs(u);
		double k = floor((2 * a / us + b) * u + mu + 0.43);
		if (us >= 0.07 && v <= v_r)
			return k;
		if (k < 0 || (us < 0.013 && v > us))
			continue;
		if (isnan(lmu))
			lmu = log(mu);
		if (log(v * inv_alpha / (a / (us * us) + b)) <= -mu + k * lmu - pc_log_factorial(k))
			return k;
	}
}
