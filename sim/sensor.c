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

static const char *const preset_names[] = { "ideal", "imx250mzr", "imx250myr", NULL };

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
	} else {
		return PC_EINVAL;
	}
	snprintf(f->preset, sizeof f->preset, "%s", name);
	return 0;
}

/* ---- per-pixel analyser (physics.md §6 step 2) ---- */

void pc_sensor_fixed(const pc_sim *sim, uint32_t sx, uint32_t sy, unsigned mask, double z[4])
{
	z[0] = z[1] = z[2] = z[3] = 0;
	mask &= sim->fp_mask;
	if (!mask)
		return;
	const uint32_t ctr[4] = { (sy << 16) | (sx & 0xFFFFu), PC_RNG_FIXED, 0, 0 };
	const uint32_t key[2] = { (uint32_t)sim->opt.seed, (uint32_t)(sim->opt.seed >> 32) };
	uint32_t w[4];
	pc_philox4x32_10(ctr, key, w);
	for (int i = 0; i < 4; i++)
		if (mask >> i & 1)
			z[i] = pc_u32_to_normal(w[i]);
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

/* An ideal analyser at the nominal angle: a = ½(1, cos2θ, sin2θ, 0). */
static void analyse_ideal(const pc_sim *sim, uint32_t sx, uint32_t sy, const double z[4], double a[4])
{
	(void)z;
	double th = 45.0 * DEG * pc_mosaic_channel(&sim->fig.mosaic, sx, sy);
	a[0] = 0.5;
	a[1] = 0.5 * cos(2 * th);
	a[2] = 0.5 * sin(2 * th);
	a[3] = 0;
}

/* With the declared non-idealities: a = (t/2)(1, d cos2θ, d sin2θ, 0), d = (ER − 1)/(ER + 1),
 * θ = nominal + systematic offset + N(0, σ_θ), t = t_channel·(1 + N(0, σ_t)); the random parts
 * are fixed per pixel (keyed by seed and position, not by frame). */
static void analyse_real(const pc_sim *sim, uint32_t sx, uint32_t sy, const double z[4], double a[4])
{
	const pc_sensor_figures *f = &sim->fig;
	unsigned c = pc_mosaic_channel(&f->mosaic, sx, sy);
	double th = 45.0 * DEG * c, d = 1, t = 1;
	if (sim->fx & PC_FX_ORIENTATION) {
		double e = f->orientation_offset_deg[c];
		if (f->orientation_sigma_deg > 0)
			e += f->orientation_sigma_deg * z[0];
		th += e * DEG;
	}
	if (sim->fx & PC_FX_EXTINCTION)
		d = isinf(f->extinction_ratio) ? 1 : (f->extinction_ratio - 1) / (f->extinction_ratio + 1);
	if (sim->fx & PC_FX_TRANSMISSION) {
		t = f->transmission[c];
		if (f->transmission_sigma > 0)
			t *= 1 + f->transmission_sigma * z[1];
	}
	a[0] = 0.5 * t;
	a[1] = 0.5 * t * d * cos(2 * th);
	a[2] = 0.5 * t * d * sin(2 * th);
	a[3] = 0;
}

double pc_sensor_prnu(const pc_sim *sim, const double z[4])
{
	if (!(sim->fx & PC_FX_PRNU_DSNU))
		return 1;
	return 1 + sim->fig.prnu * z[2];
}

double pc_sensor_dsnu(const pc_sim *sim, const double z[4])
{
	return sim->fig.dsnu_e * z[3];
}

/* ---- the per-frame chain (steps 3–6), one row of the ROI into LSB-aligned uint16 ---- */

static inline void frame_row_body(const pc_sim *sim, uint64_t n, double t_s, double K, uint32_t y,
				  uint16_t *row, const bool noise, const bool dsnu)
{
	const uint32_t W = sim->info.width;
	const uint32_t sy = sim->info.offset_y + y;
	const float *rate = sim->rate[n % sim->n_states] + (size_t)y * W;
	const float *ds = dsnu ? sim->dsnu + (size_t)y * W : NULL;
	const double fw = sim->fig.full_well_e, off = sim->fig.offset_dn;
	const double dark = noise ? sim->fig.dark_current_e_s * t_s : 0;
	const double sd = sim->fig.read_noise_e, maxv = sim->max_dn;
	for (uint32_t x = 0; x < W; x++) {
		const uint32_t sx = sim->info.offset_x + x;
		double mu = (double)rate[x] * t_s + dark;
		double e = mu;
		/* one stream per pixel and frame: the Poisson draw (usually two words), then the
		 * read noise (one word) — typically a single Philox block */
		pc_rng r;
		if (noise) {
			pc_rng_init(&r, sim->opt.seed, PC_RNG_FRAME, sx, sy, n);
			e = pc_rng_poisson(&r, mu);
		}
		if (e > fw)
			e = fw;
		if (dsnu)
			e += ds[x];
		if (noise && sd > 0)
			e += sd * pc_rng_normal(&r);
		double dn = floor(K * e + off + 0.5);
		row[x] = (uint16_t)(dn < 0 ? 0 : dn > maxv ? maxv : dn);
	}
}

static void row_plain(const pc_sim *s, uint64_t n, double t, double K, uint32_t y, uint16_t *row)
{
	frame_row_body(s, n, t, K, y, row, false, false);
}
static void row_noise(const pc_sim *s, uint64_t n, double t, double K, uint32_t y, uint16_t *row)
{
	frame_row_body(s, n, t, K, y, row, true, false);
}
static void row_dsnu(const pc_sim *s, uint64_t n, double t, double K, uint32_t y, uint16_t *row)
{
	frame_row_body(s, n, t, K, y, row, false, true);
}
static void row_noise_dsnu(const pc_sim *s, uint64_t n, double t, double K, uint32_t y, uint16_t *row)
{
	frame_row_body(s, n, t, K, y, row, true, true);
}

void pc_sensor_setup(pc_sim *sim)
{
	const pc_sensor_figures *f = &sim->fig;
	bool analyser_real = sim->fx & (PC_FX_EXTINCTION | PC_FX_ORIENTATION | PC_FX_TRANSMISSION);
	sim->analyse = analyser_real ? analyse_real : analyse_ideal;
	bool noise = sim->fx & PC_FX_NOISE;
	bool dsnu = sim->fx & PC_FX_PRNU_DSNU;
	sim->frame_row = noise ? (dsnu ? row_noise_dsnu : row_noise) : (dsnu ? row_dsnu : row_plain);
	sim->max_dn = (1u << f->bits) - 1u;
	sim->fp_mask = 0;
	if ((sim->fx & PC_FX_ORIENTATION) && f->orientation_sigma_deg > 0)
		sim->fp_mask |= PC_FP_ORIENT;
	if ((sim->fx & PC_FX_TRANSMISSION) && f->transmission_sigma > 0)
		sim->fp_mask |= PC_FP_TRANS;
	if (sim->fx & PC_FX_PRNU_DSNU)
		sim->fp_mask |= PC_FP_PRNU | PC_FP_DSNU;
	/* Camera equation for a distant scene (Smith, Modern Optical Engineering, 4th ed., §8.2;
	 * EMVA 1288 §2.1 for photons = A·E·t·λ/(hc)): sensor irradiance E = π·L/(4N²) for radiance
	 * L through an f/N lens (no vignetting or lens transmission loss modelled), photons per
	 * second = E·A_pix·λ/(hc). The η applied is the QE for unpolarized light as EMVA reports for
	 * polarization sensors; the analyser row a (t/2 for an ideal polarizer) is compensated by 2:
	 * electrons = 2η·(a·S). */
	const double h = 6.62607015e-34, c = 299792458.0;
	double N = sim->scene->camera.f_number;
	double A = sim->pitch_m * sim->pitch_m;
	for (unsigned ch = 0; ch < 3; ch++) {
		double lambda = f->wavelength_nm[sim->nch == 1 ? 1 : ch] * 1e-9;
		double qe = f->qe[sim->nch == 1 ? 1 : ch];
		sim->e_per_radiance[ch] = 2 * qe * (3.14159265358979323846 / (4 * N * N)) * A *
					  lambda / (h * c);
	}
}
