/* Mueller imaging (physics.md §7): condition numbers of the documented systems (DoFP alone √2,
 * tetrahedral PSG ≈ √3, quarter-wave PSA at 0°/45° = 2), exact round trips, the rank-3 linear
 * system, the float accumulator against the double reference, the predicted noise gain against
 * Monte Carlo, and the simulator end to end: a sequence of PSG × PSA frames of a surface with a
 * known Mueller matrix, reconstructed within the noise the system predicts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/optics.h"
#include "polarcam/sim.h"

#define PC_TEST_SEED 88172645463325252ull
#include "xorshift.h"

#define DEG (M_PI / 180)

/* tetrahedral PSG: polarizer at 0° then a 132° retarder at ±15.1°, ±51.7° */
static void tetra_psg(double psg[4][4])
{
	const double ang[4] = {15.1, 51.7, -51.7, -15.1};
	for (int g = 0; g < 4; g++) {
		double R[4][4];
		pc_retarder_mueller(ang[g] * DEG, 132 * DEG, R);
		for (int i = 0; i < 4; i++)
			psg[g][i] = R[i][0] + R[i][1]; /* R·(1, 1, 0, 0) */
	}
}

static void qwp_psa(double psa[2][4][4])
{
	pc_retarder_mueller(0, M_PI / 2, psa[0]);
	pc_retarder_mueller(M_PI / 4, M_PI / 2, psa[1]);
}

static void mat_mul(const double a[4][4], const double b[4][4], double c[4][4])
{
	double t[4][4];
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			t[i][j] = 0;
			for (int k = 0; k < 4; k++)
				t[i][j] += a[i][k] * b[k][j];
		}
	memcpy(c, t, sizeof t);
}

/* intensities of one pixel for Mueller matrix M: I[(g + n_psg·a)·4 + c] */
static void synth(const pc_mueller_system *s, const double M[4][4], double *I)
{
	for (unsigned a = 0; a < s->n_psa; a++)
		for (unsigned g = 0; g < s->n_psg; g++)
			for (unsigned c = 0; c < 4; c++) {
				double v = 0;
				for (int k = 0; k < 4; k++)
					for (int l = 0; l < 4; l++)
						v += s->A[4 * a + c][k] * M[k][l] * s->G[l][g];
				I[(g + s->n_psg * a) * 4 + c] = v;
			}
}

static void test_conditioning(void)
{
	pc_mueller_system s;
	double psg[4][4], psa[2][4][4];
	tetra_psg(psg);
	qwp_psa(psa);
	CHECK_EQ_INT(pc_mueller_system_init(&s, 4, psg, 2, psa, NULL), 0);
	CHECK_EQ_INT(s.rank_A, 4);
	CHECK_EQ_INT(s.rank_G, 4);
	CHECK_NEAR(s.cond_A, 2.0, 1e-9);
	CHECK_NEAR(s.cond_G, sqrt(3), 0.01);
	CHECK_NEAR(s.cond_W, s.cond_A * s.cond_G, 1e-12);
	CHECK_EQ_INT(s.determined, 0xFFFF);
	/* DoFP alone with three linear generator states at 0/60/120°: the 3×3 block */
	double lin[3][4];
	for (int g = 0; g < 3; g++) {
		lin[g][0] = 1;
		lin[g][1] = cos(2 * 60 * g * DEG);
		lin[g][2] = sin(2 * 60 * g * DEG);
		lin[g][3] = 0;
	}
	CHECK_EQ_INT(pc_mueller_system_init(&s, 3, lin, 1, NULL, NULL), 0);
	CHECK_EQ_INT(s.rank_A, 3);
	CHECK_EQ_INT(s.rank_G, 3);
	CHECK_NEAR(s.cond_A, sqrt(2), 1e-12); /* physics.md §7 */
	CHECK_EQ_INT(s.determined, 0x777);    /* rows/columns 0..2 */
	CHECK(isnan(s.noise_gain[3][0]) && isnan(s.noise_gain[0][3]));
	/* a fixed retarder alone in front of a DoFP is not enough for the 4th row (rank 3) */
	CHECK_EQ_INT(pc_mueller_system_init(&s, 4, psg, 1, psa, NULL), 0);
	CHECK_EQ_INT(s.rank_A, 3);
	/* two generator states cannot determine even the linear block */
	CHECK_EQ_INT(pc_mueller_system_init(&s, 2, lin, 1, NULL, NULL), PC_ENUMERIC);
	double bad[1][4] = {{1, NAN, 0, 0}};
	CHECK_EQ_INT(pc_mueller_system_init(&s, 1, bad, 1, NULL, NULL), PC_EINVAL);
}

static void random_mueller(double M[4][4])
{
	/* a retarder · diattenuator · depolarizer product with random parameters */
	double R[4][4], D[4][4] = {{0}}, P[4][4] = {{0}};
	pc_retarder_mueller(urand() * M_PI, urand() * M_PI, R);
	double d = 0.9 * urand(), ang = urand() * M_PI, c = cos(2 * ang), s = sin(2 * ang);
	double q = sqrt(1 - d * d);
	double dv[3] = {d * c, d * s, 0};
	D[0][0] = 1;
	for (int i = 0; i < 3; i++)
		D[0][i + 1] = D[i + 1][0] = dv[i];
	for (int i = 0; i < 3; i++)
		for (int j = 0; j < 3; j++)
			D[i + 1][j + 1] =
			    q * (i == j) + (d > 0 ? (1 - q) * dv[i] * dv[j] / (d * d) : 0);
	P[0][0] = 1;
	for (int i = 1; i < 4; i++)
		P[i][i] = 0.3 + 0.7 * urand();
	mat_mul(R, D, M);
	mat_mul(P, M, M);
	double scale = 0.5 + urand();
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			M[i][j] *= scale;
}

static void test_round_trip(void)
{
	pc_mueller_system s;
	double psg[4][4], psa[2][4][4];
	tetra_psg(psg);
	qwp_psa(psa);
	pc_mueller_system_init(&s, 4, psg, 2, psa, NULL);
	double worst = 0;
	for (int t = 0; t < 200; t++) {
		double M[4][4], I[32], R[4][4];
		random_mueller(M);
		synth(&s, M, I);
		pc_mueller_solve(&s, I, R);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				worst = fmax(worst, fabs(R[i][j] - M[i][j]));
	}
	CHECK(worst < 1e-12);

	/* the float accumulator over an image against the double reference */
	const uint32_t W = 37, H = 11;
	float *planes = malloc(sizeof(float) * 8 * 4 * W * H),
	      *Mimg = calloc(16 * W * H, sizeof(float));
	double(*truth)[4][4] = malloc(sizeof(double) * 16 * W * H);
	for (uint32_t p = 0; p < W * H; p++) {
		double I[32];
		random_mueller(truth[p]);
		synth(&s, truth[p], I);
		for (int j = 0; j < 8; j++)
			for (int c = 0; c < 4; c++)
				planes[((size_t)j * 4 + c) * W * H + p] =
				    (float)(1000 * I[j * 4 + c]);
	}
	for (unsigned j = 0; j < 8; j++) {
		pc_fplane ch[4];
		for (int c = 0; c < 4; c++) {
			ch[c].data = planes + ((size_t)j * 4 + c) * W * H;
			ch[c].row_stride = W;
			ch[c].pixel_stride = 1;
		}
		CHECK_EQ_INT(pc_mueller_accumulate(&s, j, ch, W, H, 0, Mimg), 0);
	}
	pc_mueller_finish(&s, W, H, Mimg);
	double rel = 0;
	for (uint32_t p = 0; p < W * H; p++)
		for (int k = 0; k < 16; k++)
			rel = fmax(rel, fabs(Mimg[16 * p + k] / 1000 - truth[p][k / 4][k % 4]) /
			                    fabs(truth[p][0][0]));
	CHECK(rel < 2e-6); /* float accumulation, stated in mueller_imaging.h */
	pc_fplane none[4] = {{0}};
	CHECK_EQ_INT(pc_mueller_accumulate(&s, 8, none, W, H, 0, Mimg), PC_EINVAL);
	free(planes);
	free(Mimg);
	free(truth);

	/* linear system: the 3×3 block is exact, the rest NaN */
	double lin[3][4];
	for (int g = 0; g < 3; g++) {
		lin[g][0] = 1;
		lin[g][1] = cos(2 * 60 * g * DEG);
		lin[g][2] = sin(2 * 60 * g * DEG);
		lin[g][3] = 0;
	}
	pc_mueller_system_init(&s, 3, lin, 1, NULL, NULL);
	double M[4][4], I[12], R[4][4];
	random_mueller(M);
	synth(&s, M, I);
	pc_mueller_solve(&s, I, R);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			if (i < 3 && j < 3)
				CHECK_NEAR(R[i][j], M[i][j], 1e-12);
			else
				CHECK(isnan(R[i][j]));
		}
}

static void test_noise_gain(void)
{
	pc_mueller_system s;
	double psg[4][4], psa[2][4][4];
	tetra_psg(psg);
	qwp_psa(psa);
	pc_mueller_system_init(&s, 4, psg, 2, psa, NULL);
	double M[4][4];
	random_mueller(M);
	const int n = 20000;
	const double sigma = 0.01;
	double sum[4][4] = {{0}}, sum2[4][4] = {{0}};
	for (int t = 0; t < n; t++) {
		double I[32], R[4][4];
		synth(&s, M, I);
		for (int k = 0; k < 32; k++)
			I[k] += sigma * nrand();
		pc_mueller_solve(&s, I, R);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++) {
				double e = R[i][j] - M[i][j];
				sum[i][j] += e;
				sum2[i][j] += e * e;
			}
	}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			double sd = sqrt(sum2[i][j] / n - (sum[i][j] / n) * (sum[i][j] / n));
			double want = sigma * s.noise_gain[i][j];
			CHECK_NEAR(sd / want, 1, 0.04); /* 1/sqrt(2n) = 0.5 %: generous */
			CHECK(fabs(sum[i][j] / n) < 5 * want / sqrt(n)); /* unbiased */
		}
}

/* ---- the simulator end to end ---- */

static double M0[4][4];

static int brdf_fixed(void *u, unsigned m, unsigned ch, const double ki[3], const double kr[3],
                      const double si[3], const double sr[3], double f[4][4])
{
	(void)u;
	(void)m;
	(void)ch;
	(void)si;
	(void)sr;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			f[i][j] = ki[2] > 0 && kr[2] > 0 ? M0[i][j] / M_PI : 0;
	return 0;
}

static void test_simulated_sequence(void)
{
	/* the object: a retarder (70° at 30°) after a diattenuator (D = 0.4 at 0°), partly
	 * depolarizing */
	double R[4][4], D[4][4] = {{1, 0.4, 0, 0}, {0.4, 1, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 0}};
	double q = sqrt(1 - 0.16);
	D[2][2] = D[3][3] = q;
	double P[4][4] = {{1, 0, 0, 0}, {0, 0.85, 0, 0}, {0, 0, 0.85, 0}, {0, 0, 0, 0.7}};
	pc_retarder_mueller(30 * DEG, 70 * DEG, R);
	mat_mul(R, D, M0);
	mat_mul(P, M0, M0);
	/* downward camera, light from straight above with tetrahedral PSG states, QWP PSA */
	const char *text =
	    "{\"camera\": {\"position\": [0, 0, 10], \"direction\": [0, 0, -1], \"up\": [0, 1, 0]},"
	    " \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},"
	    " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], "
	    "\"irradiance_w_m2\": 20,"
	    "   \"reference\": [1, 0, 0], \"states\": ["
	    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": 15.1, \"retardance_deg\": "
	    "132}},"
	    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": 51.7, \"retardance_deg\": "
	    "132}},"
	    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": -51.7, \"retardance_deg\": "
	    "132}},"
	    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": -15.1, \"retardance_deg\": "
	    "132}}]}],"
	    " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], "
	    "\"material\": \"m\"}],"
	    " \"effects\": {\"circular\": true, \"mueller\": true, \"noise\": true},"
	    " \"sensor\": {\"preset\": \"ideal\", \"resolution\": [64, 64], \"bits\": 16, "
	    "\"offset_dn\": 200,"
	    "   \"gain_dn_per_e\": 1, \"read_noise_e\": 2, \"full_well_e\": 1e6, \"exposure_us\": "
	    "1000,"
	    "   \"psa\": [{\"retarder\": {\"angle_deg\": 0, \"retardance_deg\": 90}},"
	    "            {\"retarder\": {\"angle_deg\": 45, \"retardance_deg\": 90}}]}}";
	pc_scene *sc = NULL;
	CHECK_EQ_INT(pc_scene_parse(text, "seq", ".", &sc), 0);
	if (!sc) {
		fprintf(stderr, "%s\n", pc_error_detail());
		return;
	}
	pc_sim_brdf b = {brdf_fixed, NULL};
	pc_sim_options o = pc_sim_options_default();
	o.brdf = &b;
	o.seed = 3;
	pc_sim *sim = NULL;
	CHECK_EQ_INT(pc_sim_new(sc, &o, &sim), 0);
	pc_scene_free(sc);
	if (!sim)
		return;
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	CHECK_EQ_INT(in.n_states, 8);
	pc_sim_states st;
	pc_sim_get_states(sim, &st);
	pc_mueller_system s;
	CHECK_EQ_INT(pc_mueller_system_init(&s, st.n_psg, st.psg, st.n_psa, st.psa, st.analyser),
	             0);
	CHECK_NEAR(s.cond_A, 2.0, 1e-9);
	/* frames → superpixel analyser images (half resolution) → accumulate */
	const uint32_t w = 32, h = 32;
	float *ch = malloc(sizeof(float) * 4 * w * h), *Mimg = calloc(16 * w * h, sizeof(float));
	pc_view v;
	pc_view_alloc(&v, in.format, 64, 64, 64);
	double mean_dn = 0;
	for (unsigned j = 0; j < 8; j++) {
		CHECK_EQ_INT(pc_sim_frame(sim, j, NULL, &v, NULL), 0);
		for (uint32_t y = 0; y < 64; y++) {
			const uint16_t *row = PC_ROW(&v, uint16_t, y);
			for (uint32_t x = 0; x < 64; x++) {
				unsigned c = pc_mosaic_channel(&in.mosaic, x, y);
				ch[(size_t)c * w * h + (y / 2) * w + x / 2] =
				    (float)(row[x] - 200.0);
				mean_dn += (row[x] - 200.0) / (8 * 64 * 64);
			}
		}
		pc_fplane p[4];
		for (int c = 0; c < 4; c++) {
			p[c].data = ch + (size_t)c * w * h;
			p[c].row_stride = w;
			p[c].pixel_stride = 1;
		}
		CHECK_EQ_INT(pc_mueller_accumulate(&s, j, p, w, h, 0, Mimg), 0);
	}
	/* truth: E·cosθ/π·M0 in the image-plane frame (aligned with the light's frame here) */
	double T[16];
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 32, 33, NULL, NULL), 0);
	double *tm = malloc(sizeof(double) * 16 * 64);
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 32, 33, NULL, tm), 0);
	memcpy(T, tm + 16 * 32, sizeof T);
	for (int k = 0; k < 16; k++)
		CHECK_NEAR(T[k] / T[0], M0[k / 4][k % 4],
		           2e-4); /* off-axis pixel: frames tilt slightly */
	/* normalized reconstruction against M0 within the predicted noise: per intensity
	 * σ ≈ sqrt(mean + σ_d²) DN (Poisson + read noise at K = 1) */
	double sigma_I = sqrt(mean_dn + 4);
	double m00 = 0;
	for (uint32_t p = 0; p < w * h; p++)
		m00 += Mimg[16 * p] / (w * h);
	for (int k = 1; k < 16; k++) {
		double e = 0, e2 = 0;
		for (uint32_t p = 0; p < w * h; p++) {
			double d = Mimg[16 * p + k] / m00 - M0[k / 4][k % 4];
			e += d;
			e2 += d * d;
		}
		double n = w * h, rms = sqrt(e2 / n),
		       pred = sigma_I * s.noise_gain[k / 4][k % 4] / m00;
		/* the noise is not uniform (Poisson varies with the intensity), so allow ±50 % */
		if (!(rms > 0.5 * pred && rms < 1.5 * pred))
			fprintf(stderr, "M[%d][%d]: rms %.4g, predicted %.4g\n", k / 4, k % 4, rms,
			        pred);
		CHECK(rms > 0.5 * pred && rms < 1.5 * pred);
		CHECK(fabs(e / n) < 5 * pred / sqrt(n) + 3e-4);
	}
	free(tm);
	free(ch);
	free(Mimg);
	pc_view_free(&v);
	pc_sim_free(sim);
}

int main(void)
{
	test_conditioning();
	test_round_trip();
	test_noise_gain();
	test_simulated_sequence();
	return pc_test_finish("test_mueller_imaging");
}
