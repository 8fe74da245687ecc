/* sim/sim.c - the simulator object: pipeline assembly, per-state signal caches, frames, truth. */
#include "polarcam/sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/limits.h"
#include "polarcam/parallel.h"
#include "sim_impl.h"

pc_sim_options pc_sim_options_default(void)
{
	pc_sim_options o;
	memset(&o, 0, sizeof o);
	return o;
}

static pc_pixfmt natural_format(unsigned bits)
{
	switch (bits) {
	case 8:
		return PC_FMT_MONO8;
	case 10:
		return PC_FMT_MONO10;
	case 12:
		return PC_FMT_MONO12;
	default:
		return PC_FMT_MONO16;
	}
}

void pc_sim_free(pc_sim *sim)
{
	if (!sim)
		return;
	if (sim->pbrdf) {
		for (unsigned i = 0; i < sim->scene->n_materials * sim->nch; i++)
			pc_pbrdf_free(sim->pbrdf[i]);
		free(sim->pbrdf);
	}
	if (sim->rate) {
		for (unsigned i = 0; i < sim->n_states; i++)
			free(sim->rate[i]);
		free(sim->rate);
	}
	free(sim->dsnu);
	pc_scene_free(sim->scene);
	free(sim);
}

int pc_sim_new(const pc_scene *scene, const pc_sim_options *opt, pc_sim **out)
{
	*out = NULL;
	if (!scene)
		return pc_error(PC_EINVAL, "scene is NULL");
	pc_sim_options o = opt ? *opt : pc_sim_options_default();
	const pc_sensor_figures *f = &scene->sensor;
	/* ROI */
	uint32_t rx = o.roi_x, ry = o.roi_y, rw = o.roi_width, rh = o.roi_height;
	if (rw == 0 && rh == 0 && rx == 0 && ry == 0) {
		rw = f->width;
		rh = f->height;
	}
	if (rw == 0 || rh == 0 || (uint64_t)rx + rw > f->width || (uint64_t)ry + rh > f->height)
		return pc_error(PC_EINVAL, "ROI %ux%u at (%u, %u) does not fit the %ux%u sensor",
		                rw, rh, rx, ry, f->width, f->height);
	unsigned bits = f->bits;
	pc_pixfmt fmt = o.format == PC_FMT_INVALID ? natural_format(bits) : o.format;
	const pc_format_info *fi = pc_format_info_get(fmt);
	if (!fi || fi->is_float || fi->bits < bits)
		return pc_error(PC_EINVAL,
		                "pixel format %s cannot hold the sensor's %u-bit values "
		                "(integer formats with at least %u bits)",
		                fi ? fi->name : "?", bits, bits);
	size_t row_bytes;
	int rc = pc_format_row_bytes(fmt, rw, &row_bytes);
	if (rc)
		return pc_error_prefix(rc, "ROI width %u in %s: ", rw, fi->name);

	pc_sim *sim = calloc(1, sizeof *sim);
	if (!sim)
		return pc_error(PC_ENOMEM, "simulator");
	pc_scene_ref((pc_scene *)scene);
	sim->scene = (pc_scene *)scene;
	sim->opt = o;
	sim->fig = *f;
	sim->fx = scene->effects;
	sim->nch = f->mosaic.period == 4 ? 3 : 1;
	sim->circular = sim->fx & PC_FX_CIRCULAR;
	sim->n_psg = 1;
	for (unsigned i = 0; i < scene->n_lights; i++)
		if (scene->lights[i].n_states > 1)
			sim->n_psg = scene->lights[i].n_states;
	sim->n_psa = scene->n_psa;
	sim->n_states = sim->n_psg * sim->n_psa;

	pc_sim_info *in = &sim->info;
	in->width = rw;
	in->height = rh;
	in->sensor_width = f->width;
	in->sensor_height = f->height;
	in->offset_x = rx;
	in->offset_y = ry;
	in->format = fmt;
	in->bits = bits;
	in->mosaic = pc_mosaic_shift(&f->mosaic, rx, ry);
	in->colour_channels = sim->nch;
	in->exposure_us = f->exposure_us;
	in->gain_db = f->gain_db;
	in->frame_rate_hz = f->frame_rate_hz;
	in->n_psg = sim->n_psg;
	in->n_psa = sim->n_psa;
	in->n_states = sim->n_states;
	in->effects = sim->fx;
	in->seed = o.seed;

	/* materials → prepared pBRDFs (only when the physics core is the BRDF) */
	if (!o.brdf) {
		sim->pbrdf = calloc((size_t)scene->n_materials * sim->nch, sizeof *sim->pbrdf);
		if (!sim->pbrdf) {
			pc_sim_free(sim);
			return pc_error(PC_ENOMEM, "materials");
		}
		for (unsigned m = 0; m < scene->n_materials; m++)
			for (unsigned ch = 0; ch < sim->nch; ch++) {
				rc = pc_pbrdf_new(&scene->materials[m].m[sim->nch == 1 ? 0 : ch],
				                  &sim->pbrdf[m * sim->nch + ch]);
				if (rc) {
					rc =
					    pc_error_prefix(rc, "%s: materials.%s: ", scene->source,
					                    scene->materials[m].name);
					pc_sim_free(sim);
					return rc;
				}
			}
	} else if (!o.brdf->eval) {
		pc_sim_free(sim);
		return pc_error(PC_EINVAL, "options.brdf->eval is NULL");
	}
	sim->rate = calloc(sim->n_states, sizeof *sim->rate);
	if (!sim->rate) {
		pc_sim_free(sim);
		return pc_error(PC_ENOMEM, "state caches");
	}
	pc_render_setup(sim);
	pc_sensor_setup(sim);
	*out = sim;
	return 0;
}

void pc_sim_get_info(const pc_sim *sim, pc_sim_info *info)
{
	*info = sim->info;
}

void pc_sim_get_sensor(const pc_sim *sim, pc_sensor_figures *fig)
{
	*fig = sim->fig;
	fig->effects = sim->fx & (PC_FX_NOISE | PC_FX_PRNU_DSNU | PC_FX_EXTINCTION |
	                          PC_FX_ORIENTATION | PC_FX_TRANSMISSION | PC_FX_CROSSTALK);
}

void pc_sim_get_states(const pc_sim *sim, pc_sim_states *st)
{
	memset(st, 0, sizeof *st);
	st->n_psg = sim->n_psg;
	st->n_psa = sim->n_psa;
	/* the first light with a sequence defines the PSG (all sequences have equal length) */
	const pc_sim_light *l = &sim->scene->lights[0];
	for (unsigned i = 0; i < sim->scene->n_lights; i++)
		if (sim->scene->lights[i].n_states > 1) {
			l = &sim->scene->lights[i];
			break;
		}
	for (unsigned g = 0; g < sim->n_psg; g++)
		memcpy(st->psg[g], l->stokes[g % l->n_states], sizeof st->psg[g]);
	memcpy(st->psa, sim->scene->psa, sizeof(double) * 16 * sim->n_psa);
	for (unsigned c = 0; c < 4; c++) {
		double th = c * 3.14159265358979323846 / 4;
		st->analyser[c][0] = 0.5;
		st->analyser[c][1] = 0.5 * cos(2 * th);
		st->analyser[c][2] = 0.5 * sin(2 * th);
		st->analyser[c][3] = 0;
	}
}

bool pc_sim_is_prepared(const pc_sim *sim, unsigned state)
{
	return state < sim->n_states && sim->rate[state] != NULL;
}

/* ---- prepare: render the PSG state once, fill the caches of all its PSA states ----
 *
 * One pass over the rows renders each pixel, draws its fixed-pattern deviates (one Philox block
 * per pixel: orientation, transmission, PRNU, DSNU), applies the analyser and the PSA states and
 * writes the electron rates; the DSNU image is filled on the first prepare. Without crosstalk
 * the rates get their PRNU at once; with crosstalk they go to a grid with a one-pixel halo and
 * the pixel's PRNU factor waits in the first destination image until the crosstalk pass. */

typedef struct prep_ctx {
	pc_sim *sim;
	unsigned g;
	float *truth_s, *truth_m;
	float **dst;         /* n_psa destination images (ROI) */
	float **halo;        /* n_psa images of (W+2)·(H+2), or NULL */
	float *dsnu;         /* the DSNU image to fill (first prepare), or NULL */
	bool psa_identity;   /* one PSA state, the identity: skip its product */
	const pc_blur *blur; /* effect "blur": the blurred radiance instead of the render */
	int err;
} prep_ctx;

/* Analysed electron rate (before PRNU and crosstalk) of a pixel of colour channel pch and
 * analyser channel ach with Stokes radiance S, for each PSA state. */
static inline void prep_rate(const prep_ctx *c, const double *Sin, unsigned pch, unsigned ach,
                             double zo, double zt, double ze, float *out_rate)
{
	const pc_sim *sim = c->sim;
	double S[4] = {Sin[0], Sin[1], Sin[2], sim->circular ? Sin[3] : 0}, Sp[4];
	/* S3 is not carried without "circular" (and not coupled: scene validation) */
	double an[4];
	sim->analyse(sim, ach, zo, zt, ze, an);
	const double ke = sim->e_per_radiance[pch];
	if (c->psa_identity) {
		double v = an[0] * S[0] + an[1] * S[1] + an[2] * S[2] + an[3] * S[3];
		out_rate[0] = (float)((v < 0 ? 0 : v) * ke);
		return;
	}
	for (unsigned a = 0; a < sim->n_psa; a++) {
		const double(*P)[4] = sim->scene->psa[a];
		for (int i = 0; i < 4; i++)
			Sp[i] = P[i][0] * S[0] + P[i][1] * S[1] + P[i][2] * S[2] + P[i][3] * S[3];
		double v = an[0] * Sp[0] + an[1] * Sp[1] + an[2] * Sp[2] + an[3] * Sp[3];
		if (v < 0)
			v = 0; /* only from rounding: a physical Stokes vector gives a·S ≥ 0 */
		out_rate[a] = (float)(v * ke);
	}
}

static void prep_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	prep_ctx *c = ctx;
	const pc_sim *sim = c->sim;
	const uint32_t W = sim->info.width, H = sim->info.height;
	const uint32_t ox = sim->info.offset_x, oy = sim->info.offset_y;
	const uint32_t SW = sim->info.sensor_width, SH = sim->info.sensor_height;
	const bool halo = c->halo != NULL, prnu_on = sim->fx & PC_FX_PRNU_DSNU;
	const uint32_t cols = halo ? W + 2 : W;
	/* deviates a row does not draw stay 0 (calloc) or hold an earlier row's, unused, values */
	double *zb = calloc(5 * (size_t)cols, sizeof *zb);
	if (!zb) {
#ifdef _OPENMP
#pragma omp atomic write
#endif
		c->err = PC_ENOMEM;
		return;
	}
	double *z[5] = {zb, zb + cols, zb + 2 * (size_t)cols, zb + 3 * (size_t)cols,
	                zb + 4 * (size_t)cols};
	/* a row's Stokes vectors (every channel when the row writes truth) and Mueller matrices */
	const unsigned nch = sim->nch;
	double *Srow = malloc((size_t)cols * nch * 4 * sizeof *Srow);
	double *Mrow = c->truth_m ? malloc((size_t)cols * nch * 16 * sizeof *Mrow) : NULL;
	uint8_t *chan = malloc(cols);
	if (!Srow || (c->truth_m && !Mrow) || !chan) {
		free(zb);
		free(Srow);
		free(Mrow);
		free(chan);
#ifdef _OPENMP
#pragma omp atomic write
#endif
		c->err = PC_ENOMEM;
		return;
	}
	float rates[PC_SIM_MAX_STATES];
	for (uint32_t yy = y0; yy < y1; yy++) {
		/* halo grid row yy covers sensor row oy + yy − 1 (−1 .. H) */
		int64_t sy = halo ? (int64_t)oy + yy - 1 : (int64_t)oy + yy;
		if (sy < 0 || sy >= SH)
			continue; /* outside the sensor: the crosstalk pass uses the pixel itself */
		const bool row_in_roi = !halo || (yy >= 1 && yy <= H);
		const uint32_t ry = halo ? yy - 1 : yy;
		int64_t sx0 = halo ? (int64_t)ox - 1 : (int64_t)ox;
		uint32_t xlo = sx0 < 0 ? 1 : 0, xhi = cols;
		if (sx0 + xhi > SW)
			xhi = (uint32_t)(SW - sx0);
		unsigned mask = PC_FP_ORIENT | PC_FP_TRANS | PC_FP_ER;
		if (row_in_roi && prnu_on)
			mask |= PC_FP_PRNU | (c->dsnu ? PC_FP_DSNU : 0);
		pc_sensor_fixed_row(sim, (uint32_t)sy, (uint32_t)(sx0 + xlo), xhi - xlo, mask,
		                    z[0] + xlo, z[1] + xlo, z[2] + xlo, z[3] + xlo, z[4] + xlo);
		pc_render_row rr;
		if (!c->blur)
			pc_render_row_begin(sim, (uint32_t)sy, &rr);
		/* colour and analyser channel of the row's pixels by column phase */
		const pc_mosaic *mo = &sim->fig.mosaic;
		unsigned pch[4], ach[4];
		for (unsigned k = 0; k < mo->period; k++) {
			pch[k] = pc_sensor_channel(sim, (uint32_t)(sx0 + xlo) + k, (uint32_t)sy);
			ach[k] = pc_mosaic_channel(mo, (uint32_t)(sx0 + xlo) + k, (uint32_t)sy);
		}
		const unsigned pmask = mo->period - 1u;
		for (uint32_t xx = xlo; xx < xhi; xx++)
			chan[xx] = (uint8_t)pch[(xx - xlo) & pmask];
		/* truth needs every channel of the ROI's pixels */
		const bool truth_row = row_in_roi && (c->truth_s || c->truth_m);
		const bool all_ch = truth_row && nch > 1;
		const unsigned nout = all_ch ? nch : 1;
		if (c->blur)
			pc_blur_span(c->blur, sim, (uint32_t)sy, (uint32_t)(sx0 + xlo), xhi - xlo,
			             all_ch ? NULL : chan + xlo, Srow + (size_t)xlo * nout * 4,
			             truth_row && c->truth_m ? Mrow + (size_t)xlo * nout * 16
			                                     : NULL);
		else
			pc_render_span(
			    sim, &rr, (uint32_t)(sx0 + xlo), xhi - xlo, all_ch ? NULL : chan + xlo,
			    c->g, Srow + (size_t)xlo * nout * 4,
			    truth_row && c->truth_m ? Mrow + (size_t)xlo * nout * 16 : NULL);
		for (uint32_t xx = xlo; xx < xhi; xx++) {
			const uint32_t k = (xx - xlo) & pmask;
			const bool in_roi = row_in_roi && (!halo || (xx >= 1 && xx <= W));
			const uint32_t rx = halo ? xx - 1 : xx;
			const size_t pix = (size_t)ry * W + rx;
			if (in_roi && truth_row) {
				for (unsigned ch = 0; ch < nout; ch++) {
					const double *Sp = Srow + ((size_t)xx * nout + ch) * 4;
					if (c->truth_s)
						for (int q = 0; q < 4; q++)
							c->truth_s[(pix * nch + ch) * 4 + q] =
							    (float)Sp[q];
					if (c->truth_m)
						for (int q = 0; q < 16; q++)
							c->truth_m[(pix * nch + ch) * 16 +
							           q] = (float)
							    Mrow[((size_t)xx * nout + ch) * 16 + q];
				}
			}
			const double *Spix = Srow + ((size_t)xx * nout + (all_ch ? pch[k] : 0)) * 4;
			prep_rate(c, Spix, pch[k], ach[k], z[0][xx], z[1][xx], z[4][xx], rates);
			float prnu = prnu_on ? (float)(1 + sim->fig.prnu * z[2][xx]) : 1.0f;
			if (halo) {
				for (unsigned a = 0; a < sim->n_psa; a++)
					c->halo[a][(size_t)yy * (W + 2) + xx] = rates[a];
				if (in_roi && prnu_on)
					c->dst[0][pix] = prnu; /* consumed by the crosstalk pass */
			} else {
				for (unsigned a = 0; a < sim->n_psa; a++)
					c->dst[a][pix] = (float)((double)rates[a] * (double)prnu);
			}
			if (in_roi && c->dsnu)
				c->dsnu[pix] = (float)(sim->fig.dsnu_e * z[3][xx]);
		}
	}
	free(zb);
	free(Srow);
	free(Mrow);
	free(chan);
}

/* Crosstalk (physics.md §6 step 2): each pixel keeps (1 − 4c) of its own analysed signal and
 * receives c of each 4-neighbour's; a neighbour outside the sensor counts as the pixel itself
 * (so a uniform scene stays uniform). Then PRNU (its factor waits in dst[0]). */
typedef struct xt_ctx {
	pc_sim *sim;
	float **halo, **dst;
} xt_ctx;

static void crosstalk_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	xt_ctx *c = ctx;
	pc_sim *sim = c->sim;
	const uint32_t W = sim->info.width, ox = sim->info.offset_x, oy = sim->info.offset_y;
	const uint32_t SW = sim->info.sensor_width, SH = sim->info.sensor_height;
	const double k = sim->fig.crosstalk;
	const bool prnu_on = sim->fx & PC_FX_PRNU_DSNU;
	for (uint32_t y = y0; y < y1; y++) {
		uint32_t sy = oy + y;
		for (uint32_t x = 0; x < W; x++) {
			uint32_t sx = ox + x;
			size_t i = (size_t)y * W + x;
			double prnu = prnu_on ? c->dst[0][i] : 1.0;
			for (unsigned a = 0; a < sim->n_psa; a++) {
				const float *up = c->halo[a] + (size_t)y * (W + 2),
				            *mid = up + (W + 2), *dn = mid + (W + 2);
				double self = mid[x + 1];
				double l = sx > 0 ? mid[x] : self,
				       r = sx + 1 < SW ? mid[x + 2] : self;
				double u = sy > 0 ? up[x + 1] : self,
				       d = sy + 1 < SH ? dn[x + 1] : self;
				double v = (1 - 4 * k) * self + k * (l + r + u + d);
				c->dst[a][i] = (float)(v * prnu);
			}
		}
	}
}

/* Runs fn over [0, rows) in chunks so that progress is reported from the calling thread. */
typedef struct chunk_ctx {
	pc_rows_fn fn;
	void *ctx;
	uint32_t base;
} chunk_ctx;

static void chunk_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	chunk_ctx *c = ctx;
	c->fn(c->ctx, c->base + y0, c->base + y1);
}

static void run_rows(const pc_sim *sim, uint32_t rows, pc_rows_fn fn, void *ctx,
                     pc_sim_progress_fn progress, void *user, uint64_t *done, uint64_t total)
{
	const uint32_t chunk = 512;
	for (uint32_t y = 0; y < rows; y += chunk) {
		uint32_t n = rows - y < chunk ? rows - y : chunk;
		chunk_ctx cc = {fn, ctx, y};
		pc_parallel_rows(n, 4, sim->opt.threads, chunk_rows, &cc);
		*done += n;
		if (progress)
			progress(user, *done, total);
	}
}

int pc_sim_prepare(pc_sim *sim, unsigned state, float *truth_stokes, float *truth_mueller,
                   pc_sim_progress_fn progress, void *progress_user)
{
	if (state >= sim->n_states)
		return pc_error(PC_EINVAL, "state %u: the scene has %u states", state,
		                sim->n_states);
	if (truth_mueller && !(sim->fx & PC_FX_MUELLER))
		return pc_error(PC_ENOTSUP, "Mueller ground truth needs \"mueller\": true in the "
		                            "scene's effects");
	const uint32_t W = sim->info.width, H = sim->info.height;
	const size_t npix = (size_t)W * H;
	unsigned g = state % sim->n_psg;
	bool all_cached = true;
	for (unsigned a = 0; a < sim->n_psa; a++)
		if (!sim->rate[g + a * sim->n_psg])
			all_cached = false;
	if (all_cached && !truth_stokes && !truth_mueller)
		return 0;
	float *dsnu_new = NULL;
	if ((sim->fx & PC_FX_PRNU_DSNU) && !sim->dsnu) {
		/* filled by this render: the same Philox block as the pixel's other fixed patterns
		 */
		dsnu_new = malloc(npix * sizeof *dsnu_new);
		if (!dsnu_new)
			return pc_error(PC_ENOMEM, "DSNU image (%zu pixels)", npix);
	}
	float *dst[PC_SIM_MAX_STATES] = {0}, *halo[PC_SIM_MAX_STATES] = {0};
	int rc = 0;
	for (unsigned a = 0; a < sim->n_psa; a++) {
		dst[a] = malloc(npix * sizeof(float));
		if (!dst[a]) {
			rc = pc_error(PC_ENOMEM, "signal cache (%zu pixels)", npix);
			goto out;
		}
	}
	bool xt = sim->fx & PC_FX_CROSSTALK; /* declared: done, even at crosstalk = 0 */
	if (xt)
		for (unsigned a = 0; a < sim->n_psa; a++) {
			halo[a] = calloc((size_t)(W + 2) * (H + 2), sizeof(float));
			if (!halo[a]) {
				rc = pc_error(PC_ENOMEM, "crosstalk buffer (%zu pixels)",
				              (size_t)(W + 2) * (H + 2));
				goto out;
			}
		}
	bool ident = sim->n_psa == 1;
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++)
			ident &= sim->scene->psa[0][i][j] == (i == j);
	/* the lens blur: the pixels prep_rows renders (the ROI, with the crosstalk's one-pixel halo
	 * inside the sensor) blurred from a region widened by the kernel */
	pc_blur blur = {0}, *bp = NULL;
	uint64_t done = 0, total = xt ? (uint64_t)(H + 2) + H : H;
	if (sim->fx & PC_FX_BLUR) {
		const uint32_t hh = xt ? 1 : 0, ox = sim->info.offset_x, oy = sim->info.offset_y;
		const uint32_t SW = sim->info.sensor_width, SH = sim->info.sensor_height;
		const uint32_t bx0 = ox >= hh ? ox - hh : 0, by0 = oy >= hh ? oy - hh : 0;
		const uint32_t bx1 = ox + W + hh < SW ? ox + W + hh : SW,
		               by1 = oy + H + hh < SH ? oy + H + hh : SH;
		const int R = pc_blur_radius(sim->scene->blur_sigma);
		total += (uint64_t)(by1 - by0) + 2 * (uint64_t)R;
		rc = pc_blur_begin(sim, g, bx0, bx1 - bx0, by0, by1 - by0, truth_mueller != NULL,
		                   &blur, progress, progress_user, &done, total);
		if (rc)
			goto out;
		bp = &blur;
		total = done + (xt ? (uint64_t)(H + 2) + H : H);
	}
	prep_ctx pc = {sim, g, truth_stokes, truth_mueller, dst, xt ? halo : NULL, dsnu_new, ident,
	               bp,  0};
	run_rows(sim, xt ? H + 2 : H, prep_rows, &pc, progress, progress_user, &done, total);
	pc_blur_end(&blur);
	if (pc.err) {
		rc = pc_error(pc.err, "render row buffers");
		goto out;
	}
	if (xt) {
		xt_ctx xc = {sim, halo, dst};
		run_rows(sim, H, crosstalk_rows, &xc, progress, progress_user, &done, total);
	}
	for (unsigned a = 0; a < sim->n_psa; a++) {
		unsigned s = g + a * sim->n_psg;
		free(sim->rate[s]);
		sim->rate[s] = dst[a];
		dst[a] = NULL;
	}
	if (dsnu_new) {
		sim->dsnu = dsnu_new;
		dsnu_new = NULL;
	}
out:
	for (unsigned a = 0; a < sim->n_psa; a++) {
		free(dst[a]);
		free(halo[a]);
	}
	free(dsnu_new);
	return rc;
}

/* ---- frames ---- */

/* Writes *t_s and *K on every path (NaN on error), so that callers' outputs are never read
 * uninitialised whatever the compiler can prove about pc_error()'s return value. */
static int resolve_controls(const pc_sim *sim, const pc_sim_controls *c, double *t_s, double *K)
{
	*t_s = *K = NAN;
	double exp_us = c ? c->exposure_us : sim->fig.exposure_us;
	double gain_db = c ? c->gain_db : sim->fig.gain_db;
	if (!(exp_us > 0) || !isfinite(exp_us) || exp_us > 1e9)
		return pc_error(PC_EINVAL, "exposure %g µs: must be in (0, 1e9]", exp_us);
	if (!(gain_db >= 0) || gain_db > 60)
		return pc_error(PC_EINVAL, "gain %g dB: must be in [0, 60]", gain_db);
	*t_s = exp_us * 1e-6;
	*K = sim->fig.gain_dn_per_e * pow(10, gain_db / 20);
	return 0;
}

static int check_dst(const pc_sim *sim, const pc_view *dst)
{
	int rc = pc_view_check(dst);
	if (rc)
		return rc;
	if (dst->width != sim->info.width || dst->height != sim->info.height)
		return pc_error(PC_EINVAL, "frame view is %ux%u, the simulator produces %ux%u",
		                dst->width, dst->height, sim->info.width, sim->info.height);
	const pc_format_info *fi = pc_format_info_get(dst->format);
	if (fi->is_float || fi->bits < sim->info.bits)
		return pc_error(PC_EINVAL, "frame view format %s cannot hold %u-bit values",
		                fi->name, sim->info.bits);
	return 0;
}

typedef struct frame_ctx {
	const pc_sim *sim;
	uint64_t n;
	double t_s, K;
	pc_view *dst;
	int err;
} frame_ctx;

static int frame_band(const pc_sim *sim, uint64_t n, double t_s, double K, pc_view *dst,
                      uint32_t y0, uint32_t y1)
{
	const pc_format_info *fi = pc_format_info_get(dst->format);
	const uint32_t W = sim->info.width;
	bool direct16 = fi->packing == PC_PACK_NONE && fi->group_bytes == 2;
	uint16_t *tmp = NULL;
	if (!direct16) {
		tmp = malloc((size_t)W * sizeof *tmp);
		if (!tmp)
			return pc_error(PC_ENOMEM, "frame row");
	}
	int rc = 0;
	for (uint32_t y = y0; y < y1 && !rc; y++) {
		uint8_t *row = PC_ROW(dst, uint8_t, y);
		if (direct16) {
			sim->frame_row(sim, n, t_s, K, y, (uint16_t *)row);
		} else if (dst->format == PC_FMT_MONO8) {
			sim->frame_row(sim, n, t_s, K, y, tmp);
			for (uint32_t x = 0; x < W; x++)
				row[x] = (uint8_t)tmp[x];
		} else {
			sim->frame_row(sim, n, t_s, K, y, tmp);
			pc_view one = {row, W, 1, dst->stride, dst->format};
			rc = pc_view_from_u16(tmp, W * sizeof *tmp, &one);
		}
	}
	free(tmp);
	return rc;
}

static void frame_rows_par(void *ctx, uint32_t y0, uint32_t y1)
{
	frame_ctx *c = ctx;
	int rc = frame_band(c->sim, c->n, c->t_s, c->K, c->dst, y0, y1);
	if (rc) {
#ifdef _OPENMP
#pragma omp atomic write
#endif
		c->err = rc;
	}
}

int pc_sim_frame_rows(const pc_sim *sim, uint64_t n, const pc_sim_controls *controls, pc_view *dst,
                      uint32_t y0, uint32_t y1)
{
	int rc = check_dst(sim, dst);
	if (rc)
		return rc;
	if (y0 > y1 || y1 > sim->info.height)
		return pc_error(PC_EINVAL, "rows [%u, %u) outside the frame's %u rows", y0, y1,
		                sim->info.height);
	unsigned s = (unsigned)(n % sim->n_states);
	if (!sim->rate[s])
		return pc_error(PC_ESTATE,
		                "state %u of frame %llu is not prepared (pc_sim_prepare)", s,
		                (unsigned long long)n);
	double t_s, K;
	if ((rc = resolve_controls(sim, controls, &t_s, &K)))
		return rc;
	return frame_band(sim, n, t_s, K, dst, y0, y1);
}

/* timestamp_ns = n / frame_rate_hz, rounded; PC_ERANGE when it is not below 2^63 (recordings
 * store it as a signed 64-bit JSON integer), never an out-of-range float conversion. */
static int frame_timestamp(const pc_sim *sim, uint64_t n, uint64_t *ts)
{
	const double t = (double)n * 1e9 / sim->fig.frame_rate_hz + 0.5;
	if (!(t < 0x1p63))
		return pc_error(PC_ERANGE,
		                "frame %llu: timestamp %llu / %g Hz = %.4g s does not fit "
		                "64-bit nanoseconds (2^63 ns = 292 years)",
		                (unsigned long long)n, (unsigned long long)n,
		                sim->fig.frame_rate_hz, t * 1e-9);
	*ts = (uint64_t)t;
	return 0;
}

int pc_sim_check_frames(const pc_sim *sim, uint64_t first, uint64_t count)
{
	if (count == 0)
		return 0;
	int rc = pc_limit_check(PC_LIMIT_FRAMES, count, "frames");
	if (rc)
		return rc;
	const uint64_t max_seq = (uint64_t)INT64_MAX;
	/* the largest n with n·1e9/fps + 0.5 < 2^63 */
	double lim = (0x1p63 - 1024) * sim->fig.frame_rate_hz / 1e9;
	uint64_t max_n = lim >= 0x1p63 ? max_seq : (uint64_t)lim;
	if (max_n > max_seq)
		max_n = max_seq;
	if (first > max_n || count - 1 > max_n - first)
		return pc_error(
		    PC_ERANGE,
		    "frames %llu to %llu: frame numbers and their timestamps "
		    "(n / %g Hz in ns) must fit 64-bit signed integers; with "
		    "%llu frames the first frame can be at most %llu",
		    (unsigned long long)first, (unsigned long long)(first + (count - 1)),
		    sim->fig.frame_rate_hz, (unsigned long long)count,
		    (unsigned long long)(max_n - (count - 1 <= max_n ? count - 1 : max_n)));
	uint64_t ts;
	return frame_timestamp(sim, first + (count - 1), &ts);
}

int pc_sim_frame(pc_sim *sim, uint64_t n, const pc_sim_controls *controls, pc_view *dst,
                 pc_frame_meta *meta)
{
	int rc = check_dst(sim, dst);
	if (rc)
		return rc;
	double t_s, K;
	if ((rc = resolve_controls(sim, controls, &t_s, &K)))
		return rc;
	uint64_t ts = 0; /* set by frame_timestamp when it returns 0 (GCC cannot see it) */
	if ((rc = frame_timestamp(sim, n, &ts)))
		return rc;
	unsigned s = (unsigned)(n % sim->n_states);
	if (!sim->rate[s] && (rc = pc_sim_prepare(sim, s, NULL, NULL, NULL, NULL)))
		return rc;
	frame_ctx fc = {sim, n, t_s, K, dst, 0};
	pc_parallel_rows(sim->info.height, 16, sim->opt.threads, frame_rows_par,
	                 &fc); /* small bands: rows differ in cost */
	if (fc.err)
		return fc.err;
	if (meta) {
		memset(meta, 0, sizeof *meta);
		meta->sequence = n;
		meta->timestamp_ns = ts;
		meta->exposure_us = t_s * 1e6;
		meta->gain_db = controls ? controls->gain_db : sim->fig.gain_db;
		meta->status = PC_FRAME_SIMULATED;
		meta->offset_x = sim->info.offset_x;
		meta->offset_y = sim->info.offset_y;
	}
	return 0;
}

int pc_sim_mean_dn(const pc_sim *sim, unsigned state, const pc_sim_controls *controls, uint32_t x,
                   uint32_t y, double *mean_dn)
{
	if (state >= sim->n_states || !sim->rate[state])
		return pc_error(PC_ESTATE, "state %u is not prepared", state);
	if (x >= sim->info.width || y >= sim->info.height)
		return pc_error(PC_EINVAL, "pixel (%u, %u) outside the %ux%u frame", x, y,
		                sim->info.width, sim->info.height);
	double t_s, K;
	int rc = resolve_controls(sim, controls, &t_s, &K);
	if (rc)
		return rc;
	size_t i = (size_t)y * sim->info.width + x;
	double e = sim->rate[state][i] * t_s;
	if (sim->fx & PC_FX_NOISE)
		e += sim->fig.dark_current_e_s * t_s;
	if (e > sim->fig.full_well_e)
		e = sim->fig.full_well_e;
	if (sim->dsnu)
		e += sim->dsnu[i];
	*mean_dn = K * e + sim->fig.offset_dn;
	return 0;
}

double pc_sim_dn_per_radiance(const pc_sim *sim, const pc_sim_controls *controls, unsigned ch)
{
	double t_s = 0, K = 0;
	if (ch >= sim->nch || resolve_controls(sim, controls, &t_s, &K))
		return NAN;
	return K * t_s * sim->e_per_radiance[ch];
}

/* ---- truth in double ---- */

typedef struct truth_ctx {
	const pc_sim *sim;
	unsigned g;
	uint32_t y_base;
	double *stokes, *mueller;
	const pc_blur *blur; /* effect "blur": rows from the blurred region */
} truth_ctx;

static void truth_rows_fn(void *ctx, uint32_t y0, uint32_t y1)
{
	truth_ctx *c = ctx;
	const pc_sim *sim = c->sim;
	const uint32_t W = sim->info.width;
	for (uint32_t y = y0; y < y1; y++) {
		pc_render_row rr;
		const uint32_t sy = sim->info.offset_y + c->y_base + y;
		size_t i = (size_t)y * W * sim->nch;
		/* every channel of each pixel, straight into the caller's rows */
		double *S = c->stokes ? c->stokes + 4 * i : NULL;
		double *M = c->mueller ? c->mueller + 16 * i : NULL;
		if (c->blur) {
			for (uint32_t x0 = 0; x0 < W; x0 += 256) {
				double Sb[256 * PC_SIM_MAX_CH * 4];
				uint32_t n = W - x0 < 256 ? W - x0 : 256;
				pc_blur_span(c->blur, sim, sy, sim->info.offset_x + x0, n, NULL,
				             S ? S + (size_t)x0 * sim->nch * 4 : Sb,
				             M ? M + (size_t)x0 * sim->nch * 16 : NULL);
			}
			continue;
		}
		pc_render_row_begin(sim, sy, &rr);
		if (S) {
			pc_render_span(sim, &rr, sim->info.offset_x, W, NULL, c->g, S, M);
		} else {
			/* Mueller only: the span still needs Stokes room */
			for (uint32_t x0 = 0; x0 < W; x0 += 256) {
				double Sb[256 * PC_SIM_MAX_CH * 4];
				uint32_t n = W - x0 < 256 ? W - x0 : 256;
				pc_render_span(sim, &rr, sim->info.offset_x + x0, n, NULL, c->g, Sb,
				               M + (size_t)x0 * sim->nch * 16);
			}
		}
	}
}

int pc_sim_truth_rows(const pc_sim *sim, unsigned state, uint32_t y0, uint32_t y1, double *stokes,
                      double *mueller)
{
	if (state >= sim->n_states)
		return pc_error(PC_EINVAL, "state %u: the scene has %u states", state,
		                sim->n_states);
	if (y0 > y1 || y1 > sim->info.height)
		return pc_error(PC_EINVAL, "rows [%u, %u) outside the frame's %u rows", y0, y1,
		                sim->info.height);
	if (mueller && !(sim->fx & PC_FX_MUELLER))
		return pc_error(PC_ENOTSUP, "Mueller ground truth needs \"mueller\": true in the "
		                            "scene's effects");
	truth_ctx c = {sim, state % sim->n_psg, y0, stokes, mueller, NULL};
	pc_blur blur = {0};
	if ((sim->fx & PC_FX_BLUR) && y1 > y0) {
		int rc = pc_blur_begin(sim, c.g, sim->info.offset_x, sim->info.width,
		                       sim->info.offset_y + y0, y1 - y0, mueller != NULL, &blur,
		                       NULL, NULL, NULL, 0);
		if (rc)
			return rc;
		c.blur = &blur;
	}
	/* stokes/mueller point at row y0: shift the row index */
	pc_parallel_rows(y1 - y0, 0, sim->opt.threads, truth_rows_fn, &c);
	pc_blur_end(&blur);
	return 0;
}
