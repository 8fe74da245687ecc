/* sim/sensor.c - the sensor model of physics.md §6 (EMVA 1288 linear model, release 4.0,
 * European Machine Vision Association, 2021, §2): presets, the per-pixel analyser with its
 * non-idealities, fixed-pattern noise, and the per-frame chain
 *   photons → analyser → (crosstalk) → electrons ~ Poisson(η·µ_p·(1+PRNU)) + Poisson(µ_I·t)
 *   → clip at full well → + DSNU + N(0, σ_d) → ×K + offset → round → clip to 2^bits − 1.
 * The electron rate before noise is cached per state by sim.c; this file turns it into frames.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "noise.h"
#include "rng.h"
#include "sim_impl.h"

#define DEG (3.14159265358979323846 / 180.0)

/* ---- presets (docs/scene-format.md lists the figures and their sources) ---- */

static void preset_imx250_common(pc_sensor_figures *f)
{
	f->width = 2448;
	f->height = 2048;
	f->pixel_pitch_um = 3.45;
	f->bits = 12;
	f->qe[0] = f->qe[1] = f->qe[2] = 0.38;
	f->wavelength_nm[0] = f->wavelength_nm[1] = f->wavelength_nm[2] = 525;
	f->full_well_e = 10500;
	f->read_noise_e = 2.3;
	f->dark_current_e_s = 3;
	f->dsnu_e = 1.5;
	f->prnu = 0.007;
	f->gain_dn_per_e = 4095.0 / 10500.0; /* full well ↦ full scale at 0 dB */
	f->offset_dn = 0;
	f->extinction_ratio = 300;
	f->orientation_sigma_deg = 0.2;
	f->transmission_sigma = 0.01;
	f->crosstalk = 0.01;
	f->exposure_us = 10000;
	f->gain_db = 0;
	f->frame_rate_hz = 30;
	for (int i = 0; i < 4; i++) {
		f->orientation_offset_deg[i] = 0;
		f->transmission[i] = 1;
	}
	f->mosaic = pc_mosaic_imx250mzr();
}

static const char *const preset_names[] = {"ideal", "imx250mzr", "imx250myr",
                                           "imx250mzr_nonuniform", NULL};

const char *const *pc_sensor_preset_names(void)
{
	return preset_names;
}

int pc_sensor_preset(const char *name, pc_sensor_figures *f)
{
	memset(f, 0, sizeof *f);
	if (!strcmp(name, "ideal")) {
		/* the IMX250MZR geometry, gain and full well, with every non-ideality neutral */
		preset_imx250_common(f);
		f->read_noise_e = f->dark_current_e_s = f->dsnu_e = f->prnu = 0;
		f->extinction_ratio = INFINITY;
		f->orientation_sigma_deg = f->transmission_sigma = f->crosstalk = 0;
		f->effects = 0;
	} else if (!strcmp(name, "imx250mzr")) {
		preset_imx250_common(f);
		f->effects = PC_FX_NOISE | PC_FX_PRNU_DSNU | PC_FX_EXTINCTION | PC_FX_ORIENTATION |
		             PC_FX_TRANSMISSION | PC_FX_CROSSTALK;
	} else if (!strcmp(name, "imx250myr")) {
		preset_imx250_common(f);
		/* colour: the CFA costs transmission; per-channel QE for unpolarized light at the
		 * channels' effective wavelengths (assumed, see docs/scene-format.md) */
		f->qe[0] = 0.22;
		f->qe[1] = 0.30;
		f->qe[2] = 0.24;
		f->wavelength_nm[0] = 610;
		f->wavelength_nm[1] = 530;
		f->wavelength_nm[2] = 465;
		f->extinction_ratio = 200; /* lower in red: physics.md §6 */
		f->mosaic = pc_mosaic_imx250myr();
		f->effects = PC_FX_NOISE | PC_FX_PRNU_DSNU | PC_FX_EXTINCTION | PC_FX_ORIENTATION |
		             PC_FX_TRANSMISSION | PC_FX_CROSSTALK;
	} else if (!strcmp(name, "imx250mzr_nonuniform")) {
		/* The IMX250MZR with the analyser non-uniformity a full characterisation finds
		 * (docs/calibration.md, "The realistic preset", gives each figure's source):
		 * per-pixel ER log-normal around 200 (σ of ln ER 0.35: 5–95 % ≈ 110–360),
		 * orientation errors σ 0.8° per pixel plus systematic channel offsets of a few
		 * tenths of a degree, transmission σ 2 % per pixel plus channel mismatch of ±2 %,
		 * PRNU 1 %. */
		preset_imx250_common(f);
		f->extinction_ratio = 200;
		f->extinction_ratio_sigma = 0.35;
		f->orientation_sigma_deg = 0.8;
		f->orientation_offset_deg[0] = 0.3;
		f->orientation_offset_deg[1] = -0.4;
		f->orientation_offset_deg[2] = 0.2;
		f->orientation_offset_deg[3] = -0.5;
		f->transmission_sigma = 0.02;
		f->transmission[0] = 1.0;
		f->transmission[1] = 0.98;
		f->transmission[2] = 1.02;
		f->transmission[3] = 0.99;
		f->prnu = 0.01;
		f->effects = PC_FX_NOISE | PC_FX_PRNU_DSNU | PC_FX_EXTINCTION | PC_FX_ORIENTATION |
		             PC_FX_TRANSMISSION | PC_FX_CROSSTALK;
	} else {
		return PC_EINVAL;
	}
	snprintf(f->preset, sizeof f->preset, "%s", name);
	return 0;
}

/* ---- per-pixel analyser (physics.md §6 step 2) ---- */

void pc_sensor_fixed_row(const pc_sim *sim, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                         double *z0, double *z1, double *z2, double *z3, double *z4)
{
	mask &= sim->fp_mask;
	if (mask & PC_FP_ALL & ~PC_FP_ER) {
		double *z[4] = {z0, z1, z2, z3};
		pc_noise_fixed_row(sim->opt.seed, sy, sx0, n, mask & ~PC_FP_ER, z);
	}
	if (mask & PC_FP_ER) {
		/* the ER deviate: word 0 of the pixel's second fixed-pattern block; drawn once per
		 * prepared state, so scalar code costs nothing per frame */
		const uint32_t key[2] = {(uint32_t)sim->opt.seed, (uint32_t)(sim->opt.seed >> 32)};
		for (uint32_t i = 0; i < n; i++) {
			const uint32_t ctr[4] = {(sy << 16) | ((sx0 + i) & 0xFFFFu), PC_RNG_FIXED,
			                         1, 0};
			uint32_t w[4];
			pc_philox4x32_10(ctr, key, w);
			z4[i] = pc_u32_to_normal(w[0]);
		}
	}
}

unsigned pc_sensor_channel(const pc_sim *sim, uint32_t sx, uint32_t sy)
{
	if (sim->nch == 1)
		return 0;
	switch (pc_mosaic_color(&sim->fig.mosaic, sx, sy)) {
	case PC_CFA_R:
		return 0;
	case PC_CFA_B:
		return 2;
	default:
		return 1;
	}
}

/* cos 2θ and sin 2θ of the nominal analyser angles θ = 45°·c, exactly. */
static const double cos2_nominal[4] = {1, 0, -1, 0}, sin2_nominal[4] = {0, 1, 0, -1};

/* An ideal analyser at the nominal angle: a = ½(1, cos2θ, sin2θ, 0). */
static void analyse_ideal(const pc_sim *sim, unsigned c, double zo, double zt, double ze,
                          double a[4])
{
	(void)sim;
	(void)zo;
	(void)zt;
	(void)ze;
	a[0] = 0.5;
	a[1] = 0.5 * cos2_nominal[c];
	a[2] = 0.5 * sin2_nominal[c];
	a[3] = 0;
}

/* cos x and sin x; for |x| ≤ 0.1 (orientation errors of a few degrees) by their Taylor series
 * to x¹² and x¹¹ (truncation < 2e-22 relative, below double rounding), otherwise libm. */
static inline void small_sincos(double x, double *c, double *s)
{
	if (fabs(x) <= 0.1) {
		double x2 = x * x;
		*c = 1 - x2 * (1.0 / 2 -
		               x2 * (1.0 / 24 -
		                     x2 * (1.0 / 720 -
		                           x2 * (1.0 / 40320 -
		                                 x2 * (1.0 / 3628800 - x2 * (1.0 / 479001600))))));
		*s = x *
		     (1 - x2 * (1.0 / 6 - x2 * (1.0 / 120 -
		                                x2 * (1.0 / 5040 - x2 * (1.0 / 362880 -
		                                                         x2 * (1.0 / 39916800))))));
	} else {
		*c = cos(x);
		*s = sin(x);
	}
}

/* With the declared non-idealities: a = (t/2)(1, d cos2θ, d sin2θ, 0), d = (ER − 1)/(ER + 1),
 * ER = ER_median·exp(σ_lnER·z) (log-normal; σ_lnER = 0: every pixel ER_median),
 * θ = nominal + e, e = systematic offset + N(0, σ_θ), t = t_channel·(1 + N(0, σ_t)); the random
 * parts are fixed per pixel (keyed by seed and position, not by frame). cos 2θ and sin 2θ by
 * the angle-addition formulas from the exact nominal values and cos 2e, sin 2e. */
static void analyse_real(const pc_sim *sim, unsigned c, double zo, double zt, double ze,
                         double a[4])
{
	const pc_sensor_figures *f = &sim->fig;
	double c2 = cos2_nominal[c], s2 = sin2_nominal[c], d = 1, t = 1;
	if (sim->fx & PC_FX_ORIENTATION) {
		double e = f->orientation_offset_deg[c];
		if (f->orientation_sigma_deg > 0)
			e += f->orientation_sigma_deg * zo;
		double ce, se;
		small_sincos(2 * e * DEG, &ce, &se);
		double cc = c2 * ce - s2 * se, ss = s2 * ce + c2 * se;
		c2 = cc;
		s2 = ss;
	}
	if (sim->fx & PC_FX_EXTINCTION) {
		double er = f->extinction_ratio;
		if (f->extinction_ratio_sigma > 0 && !isinf(er))
			er *= exp(f->extinction_ratio_sigma * ze);
		d = isinf(er) ? 1 : (er - 1) / (er + 1);
	}
	if (sim->fx & PC_FX_TRANSMISSION) {
		t = f->transmission[c];
		if (f->transmission_sigma > 0)
			t *= 1 + f->transmission_sigma * zt;
	}
	a[0] = 0.5 * t;
	a[1] = 0.5 * t * d * c2;
	a[2] = 0.5 * t * d * s2;
	a[3] = 0;
}

/* ---- the per-frame chain (steps 3–6), one row of the ROI into LSB-aligned uint16 ---- */

static void frame_row(const pc_sim *sim, uint64_t n, double t_s, double K, uint32_t y,
                      uint16_t *row)
{
	const uint32_t W = sim->info.width;
	const bool noise = sim->fx & PC_FX_NOISE;
	pc_frame_args a = {
	    .seed = sim->opt.seed,
	    .frame = n,
	    .sx0 = sim->info.offset_x,
	    .sy = sim->info.offset_y + y,
	    .n = W,
	    .rate = sim->rate[n % sim->n_states] + (size_t)y * W,
	    .dsnu = (sim->fx & PC_FX_PRNU_DSNU) ? sim->dsnu + (size_t)y * W : NULL,
	    .t_s = t_s,
	    .dark_e = noise ? sim->fig.dark_current_e_s * t_s : 0,
	    .full_well_e = sim->fig.full_well_e,
	    .K = K,
	    .offset_dn = sim->fig.offset_dn,
	    .read_e = sim->fig.read_noise_e,
	    .max_dn = sim->max_dn,
	    .noise = noise,
	    .out = row,
	};
	pc_noise_frame_row(&a);
}

void pc_sensor_setup(pc_sim *sim)
{
	const pc_sensor_figures *f = &sim->fig;
	bool analyser_real = sim->fx & (PC_FX_EXTINCTION | PC_FX_ORIENTATION | PC_FX_TRANSMISSION);
	sim->analyse = analyser_real ? analyse_real : analyse_ideal;
	sim->frame_row = frame_row;
	sim->max_dn = (1u << f->bits) - 1u;
	sim->fp_mask = 0;
	if ((sim->fx & PC_FX_ORIENTATION) && f->orientation_sigma_deg > 0)
		sim->fp_mask |= PC_FP_ORIENT;
	if ((sim->fx & PC_FX_TRANSMISSION) && f->transmission_sigma > 0)
		sim->fp_mask |= PC_FP_TRANS;
	if (sim->fx & PC_FX_PRNU_DSNU)
		sim->fp_mask |= PC_FP_PRNU | PC_FP_DSNU;
	if ((sim->fx & PC_FX_EXTINCTION) && f->extinction_ratio_sigma > 0 &&
	    !isinf(f->extinction_ratio))
		sim->fp_mask |= PC_FP_ER;
	/* Camera equation for a distant scene (Smith, Modern Optical Engineering, 4th ed., §8.2;
	 * EMVA 1288 §2.1 for photons = A·E·t·λ/(hc)): sensor irradiance E = π·L/(4N²) for radiance
	 * L through an f/N lens (no vignetting or lens transmission loss modelled), photons per
	 * second = E·A_pix·λ/(hc). The η applied is the QE for unpolarized light as EMVA reports
	 * for polarization sensors; the analyser row a (t/2 for an ideal polarizer) is compensated
	 * by 2: electrons = 2η·(a·S). */
	const double h = 6.62607015e-34, c = 299792458.0;
	double N = sim->scene->camera.f_number;
	double A = sim->pitch_m * sim->pitch_m;
	for (unsigned ch = 0; ch < 3; ch++) {
		double lambda = f->wavelength_nm[sim->nch == 1 ? 1 : ch] * 1e-9;
		double qe = f->qe[sim->nch == 1 ? 1 : ch];
		sim->e_per_radiance[ch] =
		    2 * qe * (3.14159265358979323846 / (4 * N * N)) * A * lambda / (h * c);
	}
}
