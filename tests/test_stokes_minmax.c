/* Imin, Imax, diffuse and specular (pc_stokes_minmax, polarcam/stokes.h): the double reference
 * against a sweep of an ideal analyser (independent of the closed form), the float kernel
 * against the double reference within its stated tolerance, the analytic limits (Imin + Imax =
 * S0; fully polarized light: Imin = 0; unpolarized: Imin = Imax = S0/2), and the pipeline end
 * to end on analyser images of a known mixture of unpolarized and polarized light. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/stokes.h"

/* a small deterministic generator (xorshift64*), uniform in [0, 1) */
static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uni(void)
{
	rng ^= rng >> 12;
	rng ^= rng << 25;
	rng ^= rng >> 27;
	return (double)((rng * 0x2545f4914f6cdd1dull) >> 11) / 9007199254740992.0;
}

/* Extremes of I(θ) = ½·(S0 + S1·cos 2θ + S2·sin 2θ) by a sweep refined by golden-section
 * search: no square root of S1² + S2² anywhere. */
static double sweep_extreme(double s0, double s1, double s2, double sign)
{
	double best = -INFINITY, bt = 0;
	for (int k = 0; k < 3600; k++) {
		double t = M_PI * k / 3600,
		       v = sign * 0.5 * (s0 + s1 * cos(2 * t) + s2 * sin(2 * t));
		if (v > best)
			best = v, bt = t;
	}
	double a = bt - M_PI / 3600, b = bt + M_PI / 3600, g = (sqrt(5) - 1) / 2;
	for (int it = 0; it < 80; it++) {
		double c = b - g * (b - a), d = a + g * (b - a);
		double fc = sign * (s0 + s1 * cos(2 * c) + s2 * sin(2 * c));
		double fd = sign * (s0 + s1 * cos(2 * d) + s2 * sin(2 * d));
		if (fc > fd)
			b = d;
		else
			a = c;
	}
	double t = (a + b) / 2;
	return 0.5 * (s0 + s1 * cos(2 * t) + s2 * sin(2 * t));
}

int main(void)
{
	/* 1. the double reference against the analyser sweep, and its identities */
	for (int i = 0; i < 200; i++) {
		double s0 = 4095 * uni(), dolp = 1.2 * uni(), phi = M_PI * uni();
		double s1 = s0 * dolp * cos(2 * phi), s2 = s0 * dolp * sin(2 * phi), r[4];
		pc_stokes_minmax1(s0, s1, s2, r);
		CHECK_NEAR(r[0], sweep_extreme(s0, s1, s2, -1), 1e-9 * (s0 + 1));
		CHECK_NEAR(r[1], sweep_extreme(s0, s1, s2, +1), 1e-9 * (s0 + 1));
		CHECK_NEAR(r[0] + r[1], s0, 1e-12 * (s0 + 1));   /* Imin + Imax = S0 */
		CHECK_NEAR(r[2] + r[3], s0, 1e-12 * (s0 + 1));   /* diffuse + specular = S0 */
		CHECK_NEAR(r[2], 2 * r[0], 1e-12 * (s0 + 1));    /* diffuse = 2·Imin */
		CHECK_NEAR(r[3], r[1] - r[0], 1e-12 * (s0 + 1)); /* specular = Imax − Imin */
	}
	/* analytic limits: fully polarized light (DoLP 1) has Imin = 0, unpolarized Imin = Imax */
	for (int k = 0; k < 8; k++) {
		double s0 = 100.0 * (k + 1), phi = 0.3 * k, r[4];
		pc_stokes_minmax1(s0, s0 * cos(2 * phi), s0 * sin(2 * phi), r);
		CHECK_NEAR(r[0], 0, 1e-12 * s0);
		CHECK_NEAR(r[1], s0, 1e-12 * s0);
		CHECK_NEAR(r[3], s0, 1e-12 * s0);
		pc_stokes_minmax1(s0, 0, 0, r);
		CHECK(r[0] == s0 / 2 && r[1] == s0 / 2 && r[2] == s0 && r[3] == 0);
	}

	/* 2. the float kernel against the reference: (H, W, 3) interleaved input as stokes.npy
	 * holds it, planar outputs with a padded row, and inputs over 70 decades (hypotf must not
	 * overflow S1² + S2² at 1e30 nor underflow it at 1e-30) and noisy DoLP above 1 */
	enum { W = 37, H = 23, PAD = 5 };
	float *st = malloc(sizeof(float) * W * H * 3),
	      *o = malloc(sizeof(float) * 4 * (W + PAD) * H);
	for (int i = 0; i < W * H; i++) {
		double mag = pow(10, -30 + 60 * uni()), dolp = 1.3 * uni(), phi = M_PI * uni();
		if (i % 3 == 0)
			mag = 4095 * uni();
		if (i % 11 == 0)
			dolp = 1; /* fully polarized */
		if (i % 13 == 0)
			dolp = 0; /* unpolarized */
		st[3 * i] = (float)mag;
		st[3 * i + 1] = (float)(mag * dolp * cos(2 * phi));
		st[3 * i + 2] = (float)(mag * dolp * sin(2 * phi));
	}
	pc_fplane s0 = {st, 3 * W, 3}, s1 = {st + 1, 3 * W, 3}, s2 = {st + 2, 3 * W, 3};
	const size_t plane = (size_t)(W + PAD) * H;
	pc_minmax_out out = {{o, W + PAD, 1},
	                     {o + plane, W + PAD, 1},
	                     {o + 2 * plane, W + PAD, 1},
	                     {o + 3 * plane, W + PAD, 1}};
	for (size_t i = 0; i < 4 * plane; i++)
		o[i] = -7.0f; /* the padding must stay untouched */
	CHECK_EQ_INT(pc_stokes_minmax(&s0, &s1, &s2, W, H, &out), 0);
	double worst = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			int i = y * W + x;
			double r[4], a = st[3 * i], p = hypot(st[3 * i + 1], st[3 * i + 2]);
			pc_stokes_minmax1(a, st[3 * i + 1], st[3 * i + 2], r);
			const double tol = ldexp(1, -22) * (fabs(a) + p);
			for (int k = 0; k < 4; k++) {
				double f = o[k * plane + (size_t)y * (W + PAD) + (size_t)x];
				CHECK_NEAR(f, r[k], tol);
				if (tol > 0)
					worst = fmax(worst, fabs(f - r[k]) / tol);
			}
		}
	for (int k = 0; k < 4; k++)
		for (int y = 0; y < H; y++)
			for (int x = W; x < W + PAD; x++)
				CHECK(o[k * plane + (size_t)y * (W + PAD) + (size_t)x] == -7.0f);
	printf("float kernel: worst error %.3f of the tolerance 2^-22·(|S0| + |S_lin|)\n", worst);

	/* NaN propagates, nothing is clipped: DoLP 2 gives a negative Imin */
	float bad[6] = {NAN, 1, 1, 10, 20, 0}, ob[2] = {0, 0};
	pc_fplane b0 = {bad, 6, 3}, b1 = {bad + 1, 6, 3}, b2 = {bad + 2, 6, 3};
	pc_minmax_out ob_out = {{ob, 2, 1}, {NULL, 0, 0}, {NULL, 0, 0}, {NULL, 0, 0}};
	CHECK_EQ_INT(pc_stokes_minmax(&b0, &b1, &b2, 2, 1, &ob_out), 0);
	CHECK(isnan(ob[0]));
	CHECK_NEAR(ob[1], -5, 0);

	/* 3. end to end: analyser images of A unpolarized + B polarized at φ (Malus:
	 * I_c = A/2 + B·cos²(θ_c − φ)), through the Stokes kernels: Imin = A/2, Imax = A/2 + B */
	{
		enum { N = 16 };
		float ch[4][N], s[3][N], mm[4][N];
		double A[N], B[N];
		for (int i = 0; i < N; i++) {
			A[i] = 1000 * uni();
			B[i] = 1000 * uni();
			double phi = M_PI * uni();
			for (int c = 0; c < 4; c++)
				ch[c][i] =
				    (float)(A[i] / 2 + B[i] * pow(cos(M_PI / 4 * c - phi), 2));
		}
		pc_fplane in[4] = {{ch[0], N, 1}, {ch[1], N, 1}, {ch[2], N, 1}, {ch[3], N, 1}};
		pc_stokes_out so = {
		    {s[0], N, 1}, {s[1], N, 1}, {s[2], N, 1}, {NULL, 0, 0}, {NULL, 0, 0}};
		CHECK_EQ_INT(pc_stokes_from_channels(in, N, 1, NULL, &so), 0);
		pc_minmax_out mo = {{mm[0], N, 1}, {mm[1], N, 1}, {mm[2], N, 1}, {mm[3], N, 1}};
		CHECK_EQ_INT(pc_stokes_minmax(&so.s0, &so.s1, &so.s2, N, 1, &mo), 0);
		for (int i = 0; i < N; i++) {
			const double tol = 1e-4 * (A[i] + B[i]); /* float Stokes of sums of ~1e3 */
			CHECK_NEAR(mm[0][i], A[i] / 2, tol);
			CHECK_NEAR(mm[1][i], A[i] / 2 + B[i], tol);
			CHECK_NEAR(mm[2][i], A[i], tol); /* diffuse: the unpolarized part */
			CHECK_NEAR(mm[3][i], B[i], tol); /* specular: the polarized part */
		}
	}

	/* 4. refusals: nothing asked for, missing input, strides too small */
	pc_minmax_out none = {{NULL, 0, 0}, {NULL, 0, 0}, {NULL, 0, 0}, {NULL, 0, 0}};
	CHECK_EQ_INT(pc_stokes_minmax(&s0, &s1, &s2, W, H, &none), PC_EINVAL);
	CHECK_EQ_INT(pc_stokes_minmax(NULL, &s1, &s2, W, H, &out), PC_EINVAL);
	pc_fplane narrow = {st, 3 * W - 3, 3};
	CHECK_EQ_INT(pc_stokes_minmax(&narrow, &s1, &s2, W, H, &out), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "S0 strides") != NULL);
	free(st);
	free(o);
	return pc_test_finish("test_stokes_minmax");
}
