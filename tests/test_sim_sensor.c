/* The sensor model validated like a real camera (EMVA 1288 release 4.0 methods) and its
 * bookkeeping:
 *  - photon transfer: temporal variance (frame-difference method) against mean recovers the
 *    configured system gain K, read noise σ_d and full well;
 *  - DoLP statistics: the distribution of the per-superpixel DoLP estimate over many pixels and
 *    frames matches an independent Monte Carlo of the noise model (own generator, Knuth's Poisson
 *    sampler; two-sample Kolmogorov–Smirnov), and the low-DoLP bias matches the Rayleigh mean;
 *  - every sensor effect at neutral parameters gives bit-identical frames to the effect off;
 *  - frames are reproducible by number; ROI frames are bit-identical crops; row bands in any
 *    order equal the whole frame; packed formats hold the same values;
 *  - exposure scales the mean linearly.
 * Test-only BRDFs (a Lambertian depolarizer, a polarization-preserving "projector") give
 * uniform scenes; the physics core is not involved. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/sim.h"
#include "sim_stand_in.h"

/* A downward camera over a ground plane, light from straight above: uniform scenes. */
#define SCENE_FMT                                                                                  \
	"{\"camera\": {\"position\": [0, 0, 10], \"direction\": [0, 0, -1], \"up\": [0, 1, 0],"    \
	" \"focal_length_mm\": 12},"                                                               \
	" \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},"                                   \
	" \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], "                     \
	"\"irradiance_w_m2\": %.17g,"                                                              \
	"   \"reference\": [1, 0, 0], \"polarization\": %s}],"                                     \
	" \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], "           \
	"\"material\": \"m\"}],"                                                                   \
	" \"effects\": {%s}, \"sensor\": {%s}}"

static pc_sim *sim_new(double E, const char *pol, const char *fx, const char *sensor,
                       pc_sim_brdf *brdf, uint64_t seed, const pc_sim_options *opt_in)
{
	char text[8192];
	snprintf(text, sizeof text, SCENE_FMT, E, pol, fx, sensor);
	pc_scene *s = NULL;
	if (pc_scene_parse(text, "test", ".", &s)) {
		fprintf(stderr, "scene: %s\n", pc_error_detail());
		return NULL;
	}
	pc_sim_options o = opt_in ? *opt_in : pc_sim_options_default();
	o.brdf = brdf;
	o.seed = seed;
	pc_sim *sim = NULL;
	if (pc_sim_new(s, &o, &sim))
		fprintf(stderr, "sim: %s\n", pc_error_detail());
	pc_scene_free(s);
	return sim;
}

static uint16_t *frame_u16(pc_sim *sim, uint64_t n, const pc_sim_controls *c)
{
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	pc_view v;
	if (pc_view_alloc(&v, in.format, in.width, in.height, 64))
		return NULL;
	uint16_t *out = malloc(sizeof *out * in.width * in.height);
	int rc = pc_sim_frame(sim, n, c, &v, NULL);
	if (rc)
		fprintf(stderr, "frame: %s\n", pc_error_detail());
	CHECK_EQ_INT(rc, 0);
	CHECK_EQ_INT(pc_view_to_u16(&v, out, in.width * sizeof *out), 0);
	pc_view_free(&v);
	return out;
}

/* ---- photon transfer ---- */

static void test_photon_transfer(void)
{
	pc_sim_brdf lam = {brdf_lambert, NULL};
	const double K = 0.25, sd = 3.0, fw = 12000, off = 40;
	char sensor[512];
	snprintf(sensor, sizeof sensor,
	         "\"preset\": \"ideal\", \"resolution\": [256, 256], \"bits\": 12, "
	         "\"gain_dn_per_e\": %g,"
	         " \"read_noise_e\": %g, \"full_well_e\": %g, \"offset_dn\": %g, "
	         "\"dark_current_e_s\": 0",
	         K, sd, fw, off);
	pc_sim *sim = sim_new(100, "\"unpolarized\"", "\"noise\": true", sensor, &lam, 1, NULL);
	pc_sim *dark = sim_new(0, "\"unpolarized\"", "\"noise\": true", sensor, &lam, 2, NULL);
	CHECK(sim && dark);
	if (!sim || !dark)
		return;
	const int N = 256 * 256;
	CHECK_EQ_INT(pc_sim_prepare(sim, 0, NULL, NULL, NULL, NULL), 0);
	double mean_dn;
	pc_sim_controls c = {10, 0};
	CHECK_EQ_INT(pc_sim_mean_dn(sim, 0, &c, 64, 64, &mean_dn), 0);
	double e_per_us = (mean_dn - off) / K / 10; /* electrons per µs of exposure */
	/* the cached signal is float32: against the double truth through pc_sim_dn_per_radiance
	 * (ideal analyser, unpolarized light: ½·S0), to float precision */
	double S[4 * 256];
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 64, 65, S, NULL), 0);
	CHECK_NEAR((mean_dn - off) / (pc_sim_dn_per_radiance(sim, &c, 0) * 0.5 * S[4 * 64]), 1,
	           1e-6);
	CHECK(e_per_us * 10 < 0.1 * fw); /* the calibration point is far from saturation */
	/* mean and temporal variance from two frames (EMVA 1288 §6.3: var = var(A − B)/2) */
	double mu[16], var[16];
	int np = 0;
	double fr[] = {0, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 1.5};
	for (size_t i = 0; i < sizeof fr / sizeof fr[0]; i++) {
		pc_sim *s = fr[i] == 0 ? dark : sim;
		pc_sim_controls cc = {fr[i] == 0 ? 1000 : fr[i] * fw / e_per_us, 0};
		/* four frame pairs: the temporal variance to ~0.3 % */
		double sm = 0, vsum = 0;
		for (int pair = 0; pair < 4; pair++) {
			uint16_t *a = frame_u16(s, 10 + 2 * (uint64_t)pair, &cc);
			uint16_t *b = frame_u16(s, 11 + 2 * (uint64_t)pair, &cc);
			double sdiff = 0, sdiff2 = 0;
			for (int k = 0; k < N; k++) {
				sm += a[k] + b[k];
				double d = (double)a[k] - b[k];
				sdiff += d;
				sdiff2 += d * d;
			}
			vsum += (sdiff2 / N - (sdiff / N) * (sdiff / N)) / 2;
			free(a);
			free(b);
		}
		mu[np] = sm / (8 * N);
		var[np] = vsum / 4;
		np++;
	}
	/* dark: σ²_y.dark = K²σ_d² + 1/12 (quantization) */
	double sd_est = sqrt(var[0] - 1.0 / 12) / K;
	CHECK_NEAR(sd_est / sd, 1, 0.05);
	CHECK_NEAR(mu[0], off, 0.05);
	/* K: least-squares slope of σ²_y − σ²_y.dark against µ_y − µ_y.dark over the linear range
	 */
	double sxx = 0, sxy = 0;
	for (int i = 1; i <= 8; i++) {
		double x = mu[i] - mu[0], y = var[i] - var[0];
		sxx += x * x;
		sxy += x * y;
	}
	double K_est = sxy / sxx;
	CHECK_NEAR(K_est / K, 1, 0.02);
	printf("photon transfer: K = %.4f DN/e- (configured %.4f), read noise = %.3f e- (%.3f), ",
	       K_est, K, sd_est, sd);
	/* saturation: every pixel at full well, the variance collapses to the read noise */
	double fw_est = (mu[np - 1] - mu[0]) / K_est;
	CHECK_NEAR(fw_est / fw, 1, 0.025);
	printf("full well = %.0f e- (%.0f)\n", fw_est, fw);
	CHECK(var[np - 1] < var[0] * 1.5);
	pc_sim_free(sim);
	pc_sim_free(dark);
}

/* ---- DoLP statistics against an independent Monte Carlo ---- */

static uint64_t sm_state;
static uint64_t splitmix64(void)
{
	uint64_t z = (sm_state += 0x9E3779B97F4A7C15ull);
	z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
	z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
	return z ^ (z >> 31);
}
static double ref_uniform(void)
{
	return ((double)(splitmix64() >> 11) + 0.5) / 9007199254740992.0;
}
/* Knuth, TAOCP vol. 2, §3.4.1: multiply uniforms until the product drops below e^{−λ}. */
static double ref_poisson(double lambda)
{
	double L = exp(-lambda), p = 1;
	int k = 0;
	do {
		k++;
		p *= ref_uniform();
	} while (p > L);
	return k - 1;
}
static double ref_normal(void)
{
	return sqrt(-2 * log(ref_uniform())) * cos(2 * M_PI * ref_uniform());
}

static int cmp_d(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

/* two-sample Kolmogorov–Smirnov statistic */
static double ks2(double *a, int n, double *b, int m)
{
	qsort(a, (size_t)n, sizeof *a, cmp_d);
	qsort(b, (size_t)m, sizeof *b, cmp_d);
	int i = 0, j = 0;
	double d = 0;
	while (i < n && j < m) {
		double x = a[i] <= b[j] ? a[i] : b[j];
		while (i < n && a[i] <= x)
			i++;
		while (j < m && b[j] <= x)
			j++;
		d = fmax(d, fabs((double)i / n - (double)j / m));
	}
	return d;
}

/* superpixel DoLP from four analyser values (electrons), channel c at angle 45°·c */
static double dolp4(const double I[4])
{
	double s0 = (I[0] + I[1] + I[2] + I[3]) / 2, s1 = I[0] - I[2], s2 = I[1] - I[3];
	return sqrt(s1 * s1 + s2 * s2) / s0;
}

static void dolp_case(double p, double E)
{
	pc_sim_brdf pr = {brdf_projector, NULL};
	const double K = 1, sd = 2.3, off = 100;
	char pol[128], sensor[512];
	snprintf(pol, sizeof pol, "{\"linear_deg\": 20, \"dop\": %g}", p);
	snprintf(
	    sensor, sizeof sensor,
	    "\"preset\": \"ideal\", \"resolution\": [96, 96], \"bits\": 16, \"gain_dn_per_e\": %g,"
	    " \"read_noise_e\": %g, \"full_well_e\": 1e9, \"offset_dn\": %g, \"dark_current_e_s\": "
	    "0,"
	    " \"exposure_us\": 1000",
	    K, sd, off);
	pc_sim *sim = sim_new(E, pol, "\"noise\": true", sensor, &pr, 5, NULL);
	CHECK(sim != NULL);
	if (!sim)
		return;
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	const int Wd = 96, Hd = 96, frames = 6, nsp = (Wd / 2) * (Hd / 2);
	CHECK_EQ_INT(pc_sim_prepare(sim, 0, NULL, NULL, NULL, NULL), 0);
	/* per-superpixel means in electrons (channel order from the mosaic) */
	double *mean = malloc(sizeof(double) * 4 * nsp);
	for (int by = 0; by < Hd / 2; by++)
		for (int bx = 0; bx < Wd / 2; bx++)
			for (int dy = 0; dy < 2; dy++)
				for (int dx = 0; dx < 2; dx++) {
					uint32_t x = 2 * bx + dx, y = 2 * by + dy;
					unsigned c = pc_mosaic_channel(&in.mosaic, x, y);
					double m;
					pc_sim_mean_dn(sim, 0, NULL, x, y, &m);
					mean[4 * (by * (Wd / 2) + bx) + c] = (m - off) / K;
				}
	double *a = malloc(sizeof(double) * nsp * frames);
	int na = 0;
	for (int f = 0; f < frames; f++) {
		uint16_t *fr = frame_u16(sim, (uint64_t)f, NULL);
		for (int by = 0; by < Hd / 2; by++)
			for (int bx = 0; bx < Wd / 2; bx++) {
				double I[4];
				for (int dy = 0; dy < 2; dy++)
					for (int dx = 0; dx < 2; dx++) {
						uint32_t x = 2 * bx + dx, y = 2 * by + dy;
						I[pc_mosaic_channel(&in.mosaic, x, y)] =
						    (fr[y * Wd + x] - off) / K;
					}
				a[na++] = dolp4(I);
			}
		free(fr);
	}
	/* the reference: the same physical model with an unrelated generator */
	const int reps = 12, nb = nsp * reps;
	double *b = malloc(sizeof(double) * nb);
	sm_state = 0x1234567ull + (uint64_t)(p * 1000);
	for (int r = 0; r < reps; r++)
		for (int i = 0; i < nsp; i++) {
			double I[4];
			for (int c = 0; c < 4; c++) {
				double e = ref_poisson(mean[4 * i + c]) + sd * ref_normal();
				double dn = floor(K * e + off + 0.5);
				I[c] = (fmin(fmax(dn, 0), 65535) - off) / K;
			}
			b[r * nsp + i] = dolp4(I);
		}
	double ma = 0, mb = 0, va = 0, vb = 0;
	for (int i = 0; i < na; i++)
		ma += a[i] / na;
	for (int i = 0; i < nb; i++)
		mb += b[i] / nb;
	for (int i = 0; i < na; i++)
		va += (a[i] - ma) * (a[i] - ma) / (na - 1);
	for (int i = 0; i < nb; i++)
		vb += (b[i] - mb) * (b[i] - mb) / (nb - 1);
	double D = ks2(a, na, b, nb);
	printf("DoLP p=%.1f at %.0f e- per pixel: mean %.4f (reference MC %.4f), std %.4f (%.4f), "
	       "KS D = %.4f (critical %.4f at 0.1%%)\n",
	       p, mean[0], ma, mb, sqrt(va), sqrt(vb), D,
	       1.95 * sqrt((double)(na + nb) / ((double)na * nb)));
	double crit = 1.95 * sqrt((double)(na + nb) / ((double)na * nb)); /* α = 0.001 */
	if (!(D < crit))
		fprintf(stderr,
		        "DoLP p=%g: KS D = %.4f > %.4f (mean %.4f vs %.4f, std %.4f vs %.4f)\n", p,
		        D, crit, ma, mb, sqrt(va), sqrt(vb));
	CHECK(D < crit);
	/* analytic checks with the mean signal per channel m (electrons) */
	double m = 0;
	for (int i = 0; i < 4 * nsp; i++)
		m += mean[i] / (4 * nsp);
	double s2 = 2 * (m + sd * sd + 1.0 / 12); /* variance of S1 and of S2 */
	if (p == 0) {
		/* no polarization: |(S1, S2)| is Rayleigh, E[DoLP] ≈ σ√(π/2)/S0: a positive bias */
		CHECK_NEAR(ma / (sqrt(s2 * M_PI / 2) / (2 * m)), 1, 0.03);
	} else {
		/* high DoLP, first-order propagation through P/S0 with P the polarized part:
		 * var(P) = var(S1) = 2(m + σ²), var(S0) = m + σ², cov(P, S0) = P/2 (Poisson), so
		 * var(DoLP) = [2(m + σ²) + p²(σ² − m)]/(2m)² (≈ 1/S0 as physics.md §6 says) */
		double sdev = sqrt(s2 + p * p * (sd * sd - m)) / (2 * m);
		CHECK_NEAR(sqrt(va) / sdev, 1, 0.08);
		CHECK_NEAR(ma, p, 0.01);
	}
	free(mean);
	free(a);
	free(b);
	pc_sim_free(sim);
}

static void test_dolp_statistics(void)
{
	dolp_case(0.0, 0.5); /* ≈ 95 e⁻ per pixel: the bias regime */
	dolp_case(0.5, 0.5);
}

/* ---- neutral effects, reproducibility, ROI, bands, packing, exposure ---- */

static const char *noisy_sensor =
    "\"preset\": \"imx250mzr\", \"resolution\": [64, 48], \"exposure_us\": 300";

static int frames_equal(pc_sim *a, pc_sim *b, uint64_t n)
{
	uint16_t *fa = frame_u16(a, n, NULL), *fb = frame_u16(b, n, NULL);
	pc_sim_info in;
	pc_sim_get_info(a, &in);
	int eq = fa && fb && !memcmp(fa, fb, sizeof(uint16_t) * in.width * in.height);
	free(fa);
	free(fb);
	return eq;
}

static void neutral_pair(const char *fx_off, const char *fx_on, const char *sensor_on)
{
	pc_sim_brdf pr = {brdf_projector, NULL};
	char s_on[1024];
	snprintf(s_on, sizeof s_on, "%s, %s", noisy_sensor, sensor_on);
	pc_sim *a =
	    sim_new(50, "{\"linear_deg\": 30, \"dop\": 0.4}", fx_off, noisy_sensor, &pr, 9, NULL);
	pc_sim *b = sim_new(50, "{\"linear_deg\": 30, \"dop\": 0.4}", fx_on, s_on, &pr, 9, NULL);
	CHECK(a && b);
	if (a && b) {
		pc_sim_info ia, ib;
		pc_sim_get_info(a, &ia);
		pc_sim_get_info(b, &ib);
		CHECK(ia.effects !=
		      ib.effects); /* the effect really is on in one and off in the other */
		int eq = frames_equal(a, b, 3);
		if (!eq)
			fprintf(stderr, "neutral %s differs from %s\n", fx_on, fx_off);
		CHECK(eq);
	}
	pc_sim_free(a);
	pc_sim_free(b);
}

static void test_neutral_effects(void)
{
	/* the preset declares every sensor effect; switch one off, or keep it on at neutral values
	 */
	neutral_pair("\"extinction_ratio\": false", "\"extinction_ratio\": true",
	             "\"extinction_ratio\": 1e300");
	neutral_pair("\"orientation_error\": false", "\"orientation_error\": true",
	             "\"orientation_sigma_deg\": 0, \"orientation_offset_deg\": [0, 0, 0, 0]");
	neutral_pair("\"transmission\": false", "\"transmission\": true",
	             "\"transmission_sigma\": 0, \"transmission\": [1, 1, 1, 1]");
	neutral_pair("\"crosstalk\": false", "\"crosstalk\": true", "\"crosstalk\": 0");
	neutral_pair("\"prnu_dsnu\": false", "\"prnu_dsnu\": true", "\"prnu\": 0, \"dsnu_e\": 0");
	neutral_pair("\"circular\": false", "\"circular\": true", "\"bits\": 12");
	neutral_pair("\"mueller\": false", "\"mueller\": true", "\"bits\": 12");
	neutral_pair("\"cast_shadows\": false", "\"cast_shadows\": true", "\"bits\": 12");
	/* and a non-neutral value does change the frame */
	pc_sim_brdf pr = {brdf_projector, NULL};
	char s_on[1024];
	snprintf(s_on, sizeof s_on, "%s, \"crosstalk\": 0.05", noisy_sensor);
	pc_sim *a = sim_new(50, "{\"linear_deg\": 30, \"dop\": 0.4}", "\"crosstalk\": false",
	                    noisy_sensor, &pr, 9, NULL);
	pc_sim *b = sim_new(50, "{\"linear_deg\": 30, \"dop\": 0.4}", "\"crosstalk\": true", s_on,
	                    &pr, 9, NULL);
	CHECK(a && b && !frames_equal(a, b, 3));
	pc_sim_free(a);
	pc_sim_free(b);
}

static void test_reproducible(void)
{
	pc_sim_brdf pr = {brdf_projector, NULL};
	const char *pol = "{\"linear_deg\": 30, \"dop\": 0.4}";
	pc_sim *a = sim_new(50, pol, "", noisy_sensor, &pr, 77, NULL);
	pc_sim *b = sim_new(50, pol, "", noisy_sensor, &pr, 77, NULL);
	pc_sim *c = sim_new(50, pol, "", noisy_sensor, &pr, 78, NULL);
	CHECK(a && b && c);
	if (!a || !b || !c)
		return;
	/* frame 5 first in b: frames depend on their number only, not on what came before */
	uint16_t *b5 = frame_u16(b, 5, NULL), *a4 = frame_u16(a, 4, NULL),
	         *a5 = frame_u16(a, 5, NULL);
	uint16_t *c5 = frame_u16(c, 5, NULL);
	size_t n = 64 * 48;
	CHECK(!memcmp(a5, b5, n * 2));
	CHECK(memcmp(a4, a5, n * 2) != 0);
	CHECK(memcmp(c5, a5, n * 2) != 0);

	/* row bands in reverse order, into a padded stride */
	pc_view v;
	CHECK_EQ_INT(pc_view_alloc(&v, PC_FMT_MONO12, 64, 48, 256), 0);
	for (int y1 = 48; y1 > 0; y1 -= 7) {
		int y0 = y1 - 7 < 0 ? 0 : y1 - 7;
		CHECK_EQ_INT(pc_sim_frame_rows(a, 5, NULL, &v, (uint32_t)y0, (uint32_t)y1), 0);
	}
	uint16_t *band = malloc(n * 2);
	pc_view_to_u16(&v, band, 64 * 2);
	CHECK(!memcmp(band, a5, n * 2));
	pc_view_free(&v);
	/* packed Mono12p holds the same values */
	CHECK_EQ_INT(pc_view_alloc(&v, PC_FMT_MONO12P, 64, 48, 1), 0);
	CHECK_EQ_INT(pc_sim_frame(a, 5, NULL, &v, NULL), 0);
	pc_view_to_u16(&v, band, 64 * 2);
	CHECK(!memcmp(band, a5, n * 2));
	pc_view_free(&v);
	/* a view of the wrong size or depth is refused */
	CHECK_EQ_INT(pc_view_alloc(&v, PC_FMT_MONO8, 64, 48, 1), 0);
	CHECK_EQ_INT(pc_sim_frame(a, 5, NULL, &v, NULL), PC_EINVAL);
	pc_view_free(&v);

	/* ROI at an odd offset: a bit-identical crop of the full frame (noise, crosstalk halo,
	 * fixed patterns all follow the absolute sensor position) */
	pc_sim_options o = pc_sim_options_default();
	o.roi_x = 3;
	o.roi_y = 5;
	o.roi_width = 20;
	o.roi_height = 11;
	pc_sim *r = sim_new(50, pol, "", noisy_sensor, &pr, 77, &o);
	CHECK(r != NULL);
	if (r) {
		pc_sim_info in;
		pc_sim_get_info(r, &in);
		CHECK_EQ_INT(in.width, 20);
		CHECK_EQ_INT(in.offset_x, 3);
		pc_mosaic full = pc_mosaic_imx250mzr();
		CHECK_EQ_INT(pc_mosaic_channel(&in.mosaic, 0, 0), pc_mosaic_channel(&full, 3, 5));
		uint16_t *r5 = frame_u16(r, 5, NULL);
		int same = 1;
		for (int y = 0; y < 11; y++)
			for (int x = 0; x < 20; x++)
				same &= r5[y * 20 + x] == a5[(y + 5) * 64 + x + 3];
		CHECK(same);
		pc_frame_meta meta;
		pc_view rv;
		pc_view_alloc(&rv, in.format, 20, 11, 64);
		CHECK_EQ_INT(pc_sim_frame(r, 7, NULL, &rv, &meta), 0);
		CHECK_EQ_INT(meta.sequence, 7);
		CHECK_EQ_INT(meta.offset_x, 3);
		CHECK(meta.status & PC_FRAME_SIMULATED);
		CHECK_EQ_INT(meta.timestamp_ns, 7 * 1000000000ull / 30);
		pc_view_free(&rv);
		free(r5);
		pc_sim_free(r);
	}
	/* a ROI outside the sensor is refused */
	o.roi_x = 60;
	CHECK(sim_new(50, pol, "", noisy_sensor, &pr, 77, &o) == NULL);

	/* exposure: the mean DN above the offset scales linearly (no re-render) */
	double m1, m2;
	pc_sim_controls c1 = {100, 0}, c2 = {300, 0}, c3 = {300, 6};
	CHECK_EQ_INT(pc_sim_mean_dn(a, 0, &c1, 10, 10, &m1), 0);
	CHECK_EQ_INT(pc_sim_mean_dn(a, 0, &c2, 10, 10, &m2), 0);
	pc_sensor_figures fig;
	pc_sim_get_sensor(a, &fig);
	double dsnu_dn = 0; /* DSNU is an offset: remove it by a third point */
	double m0;
	pc_sim_controls c0 = {1e-3, 0};
	CHECK_EQ_INT(pc_sim_mean_dn(a, 0, &c0, 10, 10, &m0), 0);
	dsnu_dn = m0 - fig.offset_dn;
	CHECK_NEAR((m2 - fig.offset_dn - dsnu_dn) / (m1 - fig.offset_dn - dsnu_dn), 3, 1e-3);
	double m3;
	CHECK_EQ_INT(pc_sim_mean_dn(a, 0, &c3, 10, 10, &m3), 0);
	CHECK_NEAR((m3 - fig.offset_dn) / (m2 - fig.offset_dn), pow(10, 6.0 / 20), 1e-9);
	pc_sim_controls bad = {-1, 0};
	CHECK_EQ_INT(pc_sim_mean_dn(a, 0, &bad, 10, 10, &m3), PC_EINVAL);
	free(a4);
	free(a5);
	free(b5);
	free(c5);
	free(band);
	pc_sim_free(a);
	pc_sim_free(b);
	pc_sim_free(c);
}

/* Lambertian with albedo 1, 2, 3 for colour channels R, G, B */
static int brdf_rgb(void *u, unsigned m, unsigned ch, const double ki[3], const double kr[3],
                    const double si[3], const double sr[3], double f[4][4])
{
	(void)u;
	(void)m;
	(void)si;
	(void)sr;
	memset(f, 0, 16 * sizeof(double));
	if (ki[2] > 0 && kr[2] > 0)
		f[0][0] = (1.0 + ch) / (2 * M_PI);
	return 0;
}

/* Colour sensor: each pixel sees its CFA colour's radiance with that channel's QE and photon
 * energy; the truth has three channels. */
static void test_colour(void)
{
	pc_sim_brdf b = {brdf_rgb, NULL};
	pc_sim *sim = sim_new(
	    20, "\"unpolarized\"", "",
	    "\"preset\": \"ideal\", \"layout\": \"RGGB:90,45,135,0\", \"resolution\": [16, 16],"
	    " \"exposure_us\": 1,"
	    " \"qe\": [0.2, 0.3, 0.25], \"wavelength_nm\": [600, 530, 460]",
	    &b, 1, NULL);
	CHECK(sim != NULL);
	if (!sim)
		return;
	pc_sim_info in;
	pc_sim_get_info(sim, &in);
	CHECK_EQ_INT(in.colour_channels, 3);
	CHECK_EQ_INT(in.mosaic.period, 4);
	double S[16 * 3 * 4];
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 8, 9, S, NULL), 0);
	/* pixel (8, 8): radiance per channel ∝ albedo 1, 2, 3 */
	CHECK_NEAR(S[(8 * 3 + 1) * 4] / S[(8 * 3 + 0) * 4], 2, 1e-12);
	CHECK_NEAR(S[(8 * 3 + 2) * 4] / S[(8 * 3 + 0) * 4], 3, 1e-12);
	CHECK_EQ_INT(pc_sim_prepare(sim, 0, NULL, NULL, NULL, NULL), 0);
	/* mean DN of a pixel above offset = K·t·η·(λ/hc)·…·albedo: ratios of neighbouring R, G, B
	 * pixels (same analyser channel, unpolarized light) are (η λ albedo) ratios */
	const double qe[3] = {0.2, 0.3, 0.25}, lam[3] = {600, 530, 460};
	double m[3] = {0, 0, 0};
	int seen[3] = {0, 0, 0};
	for (uint32_t y = 4; y < 8; y++)
		for (uint32_t x = 4; x < 8; x++) {
			if (pc_mosaic_channel(&in.mosaic, x, y) != 0)
				continue; /* the 0° analyser of each colour block */
			pc_cfa_color col = pc_mosaic_color(&in.mosaic, x, y);
			int k = col == PC_CFA_R ? 0 : col == PC_CFA_G ? 1 : 2;
			double v;
			pc_sim_mean_dn(sim, 0, NULL, x, y, &v);
			if (!seen[k]) {
				m[k] = v;
				seen[k] = 1;
			}
		}
	CHECK(seen[0] && seen[1] && seen[2]);
	for (int k = 1; k < 3; k++)
		CHECK_NEAR((m[k] / m[0]) / (qe[k] * lam[k] * (1 + k) / (qe[0] * lam[0])), 1, 2e-3);
	CHECK_NEAR(pc_sim_dn_per_radiance(sim, NULL, 2) / pc_sim_dn_per_radiance(sim, NULL, 0),
	           qe[2] * lam[2] / (qe[0] * lam[0]), 1e-12);
	pc_sim_free(sim);
}

/* 8- and 10-bit sensors: natural formats, full scale, and the dark signal of a long exposure
 * (mean µ_I·t, Poisson variance) */
static void test_bits_dark(void)
{
	pc_sim_brdf lam = {brdf_lambert, NULL};
	pc_sim *s8 =
	    sim_new(1e4, "\"unpolarized\"", "",
	            "\"preset\": \"ideal\", \"resolution\": [16, 16], \"bits\": 8", &lam, 1, NULL);
	pc_sim *s10 =
	    sim_new(1e4, "\"unpolarized\"", "",
	            "\"preset\": \"ideal\", \"resolution\": [16, 16], \"bits\": 10", &lam, 1, NULL);
	CHECK(s8 && s10);
	if (s8 && s10) {
		pc_sim_info a, b;
		pc_sim_get_info(s8, &a);
		pc_sim_get_info(s10, &b);
		CHECK_EQ_INT(a.format, PC_FMT_MONO8);
		CHECK_EQ_INT(b.format, PC_FMT_MONO10);
		uint16_t *f8 = frame_u16(s8, 0, NULL), *f10 = frame_u16(s10, 0, NULL);
		CHECK(f8 && f10 && f8[0] == 255 && f10[0] == 1023); /* saturated: full scale */
		free(f8);
		free(f10);
	}
	pc_sim_free(s8);
	pc_sim_free(s10);
	/* dark: 1000 e⁻/s for 0.5 s = 500 e⁻, K = 1, no read noise */
	pc_sim *d =
	    sim_new(0, "\"unpolarized\"", "\"noise\": true",
	            "\"preset\": \"ideal\", \"resolution\": [128, 128], \"bits\": 16,"
	            " \"gain_dn_per_e\": 1, \"dark_current_e_s\": 1000, \"exposure_us\": 5e5,"
	            " \"full_well_e\": 1e5",
	            &lam, 3, NULL);
	CHECK(d != NULL);
	if (d) {
		uint16_t *f = frame_u16(d, 0, NULL);
		double s = 0, s2 = 0;
		for (int i = 0; i < 128 * 128; i++) {
			s += f[i];
			s2 += (double)f[i] * f[i];
		}
		double mean = s / (128 * 128), var = s2 / (128 * 128) - mean * mean;
		CHECK_NEAR(mean, 500, 5 * sqrt(500.0 / (128 * 128)));
		CHECK_NEAR(var / (500 + 1.0 / 12), 1, 0.05);
		free(f);
		pc_sim_free(d);
	}
}

int main(void)
{
	test_colour();
	test_bits_dark();
	test_photon_transfer();
	test_dolp_statistics();
	test_neutral_effects();
	test_reproducible();
	return pc_test_finish("test_sim_sensor");
}
