#include "rng.h"

#include <math.h>
#include <pthread.h>

double pc_rng_uniform(pc_rng *r)
{
	uint32_t a = pc_rng_u32(r) >> 5, b = pc_rng_u32(r) >> 6; /* 27 + 26 = 53 bits */
	double x = (double)a * 67108864.0 + (double)b;
	return (x + 0.5) * (1.0 / 9007199254740992.0);
}

double pc_normal_quantile(double p)
{
	/* AS 241 (PPND16), its first two regions (rng.h); the logarithm is pc_log_pure so that the
	 * vector kernels reproduce this function bit for bit. */
	double q = p - 0.5;
	if (fabs(q) <= 0.425) {
		double t = 0.180625 - q * q;
		return q * PC_AS241_CA(t) / PC_AS241_CB(t);
	}
	return pc_normal_quantile_tail(p);
}

double pc_normal_quantile_tail(double p)
{
	double q = p - 0.5;
	double t = sqrt(-pc_log_pure(q < 0 ? p : 1 - p)) - 1.6;
	double z = PC_AS241_TA(t) / PC_AS241_TB(t);
	return q < 0 ? -z : z;
}

double pc_rng_normal(pc_rng *r)
{
	return pc_u32_to_normal(pc_rng_u32(r));
}

static double log_factorial_formula(double k)
{
	if (k < 16) {
		double s = 0;
		for (int i = 2; i <= (int)k; i++)
			s += pc_log_pure((double)i);
		return s;
	}
	return PC_LOG_FACTORIAL_STIRLING(k, pc_log_pure(k + 1));
}

static double lf_table[PC_LF_TABLE];
static pthread_once_t lf_once = PTHREAD_ONCE_INIT;

static void lf_fill(void)
{
	for (int k = 0; k < PC_LF_TABLE; k++)
		lf_table[k] = log_factorial_formula(k);
}

const double *pc_log_factorial_table(void)
{
	pthread_once(&lf_once, lf_fill);
	return lf_table;
}

double pc_log_factorial(double k)
{
	if (k >= 0 && k < PC_LF_TABLE)
		return pc_log_factorial_table()[(int)k];
	return log_factorial_formula(k);
}

int pc_ptrs_slow(const pc_ptrs *p, double v, double us, double k, double *lmu)
{
	if (k < 0 || (us < 0.013 && v > us))
		return 0;
	if (isnan(*lmu))
		*lmu = pc_log_pure(p->mu);
	double inv_alpha = PC_PTRS_INV_ALPHA(p->b);
	double r = -p->mu + k * *lmu - pc_log_factorial(k);
	if (r < PC_PTRS_R_FLOOR)
		r = PC_PTRS_R_FLOOR;
	return v * inv_alpha <= pc_exp_pure(r) * (p->a / (us * us) + p->b);
}

double pc_rng_poisson(pc_rng *r, double mu)
{
	if (!(mu > 0))
		return 0;
	if (mu < PC_PTRS_MIN_MU)
		return pc_poisson_inversion(mu, pc_rng_u32(r));
	/* PTRS (rng.h). The fast acceptance (~86 % of draws) needs no logarithm. */
	pc_ptrs p;
	pc_ptrs_init(&p, mu);
	double lmu = NAN;
	for (;;) {
		uint32_t wu = pc_rng_u32(r), wv = pc_rng_u32(r);
		double k;
		int rc = pc_ptrs_fast(&p, wu, wv, &k);
		if (rc > 0)
			return k;
		double u = pc_u32_to_uniform(wu) - 0.5, v = pc_u32_to_uniform(wv);
		if (pc_ptrs_slow(&p, v, 0.5 - fabs(u), k, &lmu))
			return k;
	}
}

double pc_poisson_inversion(double mu, uint32_t w)
{
	/* Inversion by sequential search of the CDF. */
	double u = pc_u32_to_uniform(w);
	double p = pc_exp_pure(-mu), cdf = p;
	double k = 0;
	while (u > cdf && k < 200) {
		k += 1;
		p = p * (mu * (1.0 / k));
		cdf = cdf + p;
	}
	return k;
}
