#include "sim_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/decompose.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/picture.h"
#include "polarcam/parallel.h"
#include "polarcam/plot.h"

json_t *pc_sim_effects_json(unsigned effects)
{
	json_t *a = json_array();
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (effects & (1u << i))
			json_array_append_new(a, json_string(pc_sim_effect_name(1u << i)));
	return a;
}

static json_t *vec_json(const double *v, unsigned n)
{
	return cli_json_vec(v, n);
}

json_t *pc_sim_describe(const pc_sim *sim, const pc_scene *scene)
{
	pc_sim_info in;
	pc_sensor_figures f;
	pc_sim_get_info(sim, &in);
	pc_sim_get_sensor(sim, &f);
	json_t *o = json_object();
	char *doc = scene ? pc_scene_to_json(scene) : NULL;
	json_t *sj = doc ? json_loads(doc, 0, NULL) : NULL;
	free(doc);
	if (sj)
		json_object_set_new(o, "scene", sj);
	if (scene)
		json_object_set_new(o, "scene_name", json_string(pc_scene_name(scene)));
	json_object_set_new(o, "seed", json_integer((json_int_t)in.seed));
	json_object_set_new(o, "effects", pc_sim_effects_json(in.effects));
	/* the elements in front of the camera (image-plane Mueller matrices): for a uniform
	 * unpolarized background their first column is the stimulus (polarcam calibrate) */
	pc_sim_states *st = malloc(sizeof *st);
	if (st) {
		pc_sim_get_states(sim, st);
		json_t *pa = json_array();
		for (unsigned a = 0; a < st->n_psa; a++)
			json_array_append_new(pa, cli_json_matrix4(st->psa[a]));
		json_object_set_new(o, "psa_mueller", pa);
		free(st);
	}
	json_t *s = json_object();
	char mos[64];
	pc_mosaic_format(&f.mosaic, mos, sizeof mos);
	json_object_set_new(s, "preset", json_string(f.preset));
	json_object_set_new(s, "width", json_integer(f.width));
	json_object_set_new(s, "height", json_integer(f.height));
	json_object_set_new(s, "pixel_pitch_um", cli_json_real(f.pixel_pitch_um));
	json_object_set_new(s, "bits", json_integer(f.bits));
	json_object_set_new(s, "layout", json_string(mos));
	unsigned nch = in.colour_channels;
	json_object_set_new(s, "qe", vec_json(nch == 3 ? f.qe : &f.qe[1], nch));
	json_object_set_new(s, "wavelength_nm", vec_json(nch == 3 ? f.wavelength_nm : &f.wavelength_nm[1], nch));
	json_object_set_new(s, "full_well_e", cli_json_real(f.full_well_e));
	json_object_set_new(s, "read_noise_e", cli_json_real(f.read_noise_e));
	json_object_set_new(s, "dark_current_e_s", cli_json_real(f.dark_current_e_s));
	json_object_set_new(s, "dsnu_e", cli_json_real(f.dsnu_e));
	json_object_set_new(s, "prnu", cli_json_real(f.prnu));
	json_object_set_new(s, "gain_dn_per_e", cli_json_real(f.gain_dn_per_e));
	json_object_set_new(s, "offset_dn", cli_json_real(f.offset_dn));
	json_object_set_new(s, "extinction_ratio", cli_json_real(f.extinction_ratio)); /* ∞ → null */
	json_object_set_new(s, "extinction_ratio_sigma", json_real(f.extinction_ratio_sigma));
	json_object_set_new(s, "orientation_sigma_deg", cli_json_real(f.orientation_sigma_deg));
	json_object_set_new(s, "orientation_offset_deg", vec_json(f.orientation_offset_deg, 4));
	json_object_set_new(s, "transmission_sigma", cli_json_real(f.transmission_sigma));
	json_object_set_new(s, "transmission", vec_json(f.transmission, 4));
	json_object_set_new(s, "crosstalk", cli_json_real(f.crosstalk));
	json_object_set_new(s, "exposure_us", cli_json_real(f.exposure_us));
	json_object_set_new(s, "gain_db", cli_json_real(f.gain_db));
	json_object_set_new(s, "frame_rate_hz", cli_json_real(f.frame_rate_hz));
	json_object_set_new(s, "effects", pc_sim_effects_json(f.effects));
	json_object_set_new(o, "sensor", s);
	json_t *roi = json_object();
	json_object_set_new(roi, "x", json_integer(in.offset_x));
	json_object_set_new(roi, "y", json_integer(in.offset_y));
	json_object_set_new(roi, "width", json_integer(in.width));
	json_object_set_new(roi, "height", json_integer(in.height));
	json_object_set_new(o, "roi", roi);
	json_object_set_new(o, "n_states", json_integer(in.n_states));
	return o;
}

json_t *pc_sim_states_json(const pc_sim *sim)
{
	pc_sim_states st;
	pc_sim_info in;
	pc_sim_get_states(sim, &st);
	pc_sim_get_info(sim, &in);
	json_t *o = json_object();
	json_object_set_new(o, "polarcam_states", json_integer(1));
	json_object_set_new(o, "frame_order", json_string("psg_fastest"));
	json_object_set_new(o, "n_psg", json_integer(st.n_psg));
	json_object_set_new(o, "n_psa", json_integer(st.n_psa));
	json_t *g = json_array();
	for (unsigned i = 0; i < st.n_psg; i++)
		json_array_append_new(g, cli_json_vec(st.psg[i], 4));
	json_object_set_new(o, "psg", g);
	json_t *a = json_array();
	for (unsigned i = 0; i < st.n_psa; i++)
		json_array_append_new(a, cli_json_matrix4(st.psa[i]));
	json_object_set_new(o, "psa", a);
	char mos[64];
	pc_mosaic_format(&in.mosaic, mos, sizeof mos);
	json_object_set_new(o, "layout", json_string(mos));
	json_t *an = json_array();
	for (unsigned c = 0; c < 4; c++)
		json_array_append_new(an, cli_json_vec(st.analyser[c], 4));
	json_object_set_new(o, "analyser", an);
	return o;
}

void pc_sim_progress_cb(void *user, uint64_t done, uint64_t total)
{
	pc_sim_progress_adapter *a = user;
	(void)total;
	cli_progress_update(a->bar, a->base + done);
}

double pc_peak_rss_mib(void)
{
	FILE *fp = fopen("/proc/self/status", "r");
	if (!fp)
		return -1;
	char line[256];
	double kb = -1;
	while (fgets(line, sizeof line, fp))
		if (!strncmp(line, "VmHWM:", 6))
			kb = strtod(line + 6, NULL);
	fclose(fp);
	return kb < 0 ? -1 : kb / 1024;
}

int pc_path_join(char *buf, size_t size, const char *dir, const char *name)
{
	int n = snprintf(buf, size, "%s/%s", dir, name);
	if (n < 0 || (size_t)n >= size)
		return pc_error(PC_EINVAL, "path too long: %s/%s", dir, name);
	return 0;
}

static void magenta(uint32_t x, uint32_t y, uint8_t rgb[3])
{
	(void)x, (void)y;
	rgb[0] = 255, rgb[1] = 0, rgb[2] = 255;
}

int pc_write_map(const char *dir, const char *name, const float *map, uint32_t width,
		 uint32_t height, double lo, double hi, const char *title, const char *label)
{
	char path[4096], file[256];
	snprintf(file, sizeof file, "%s.npy", name);
	int rc = pc_path_join(path, sizeof path, dir, file);
	size_t shape[2] = { height, width };
	if (rc || (rc = pc_npy_write(path, map, PC_DT_F32, 2, shape)))
		return rc;
	uint8_t *rgb = malloc((size_t)width * height * 3);
	if (!rgb)
		return pc_error(PC_ENOMEM, "%s picture", name);
	pc_fplane pl = { (float *)map, width, 1 };
	rc = pc_picture_grey(&pl, width, height, (float)lo, (float)hi, rgb, (size_t)width * 3);
	if (!rc) {
		snprintf(file, sizeof file, "%s.png", name);
		rc = pc_path_join(path, sizeof path, dir, file);
		pc_colorbar bar = { label, lo, hi, NULL, 0, 0, pc_picture_grey_key, NULL };
		/* pc_picture_grey draws non-finite values magenta: say what they mean when present */
		size_t undefined = 0;
		for (size_t i = 0; i < (size_t)width * height; i++)
			undefined += !isfinite(map[i]);
		char text[64];
		snprintf(text, sizeof text, "NaN %.2g%%", 100.0 * (double)undefined /
								  ((double)width * height));
		pc_legend_note note = { text, magenta };
		if (!rc)
			rc = pc_image_write_png_ex(path, rgb, width, height, (size_t)width * 3, title,
						   &bar, undefined ? &note : NULL, 1600);
	}
	free(rgb);
	return rc;
}

static int st_err(const char *path, const char *field, const char *what)
{
	return pc_error(PC_EFORMAT, "%s: %s: %s", path, field, what);
}

static int read_vec(json_t *v, double *out, unsigned n)
{
	if (!json_is_array(v) || json_array_size(v) != n)
		return -1;
	for (unsigned i = 0; i < n; i++) {
		json_t *e = json_array_get(v, i);
		if (!json_is_number(e) || !isfinite(json_number_value(e)))
			return -1;
		out[i] = json_number_value(e);
	}
	return 0;
}

int pc_states_read(const char *path, pc_sim_states *st, char *layout, size_t layout_size)
{
	json_error_t je;
	json_t *d = json_load_file(path, JSON_REJECT_DUPLICATES, &je);
	if (!d) {
		if (!strcmp(je.text, "unable to open") || strstr(je.text, "unable to open"))
			return pc_error(PC_ENOENT, "%s: cannot open states file", path);
		return pc_error(PC_EFORMAT, "%s: line %d: %s", path, je.line, je.text);
	}
	memset(st, 0, sizeof *st);
	int rc = 0;
	json_t *v = json_object_get(d, "polarcam_states");
	if (!json_is_integer(v) || json_integer_value(v) != 1) {
		rc = st_err(path, "polarcam_states", "missing or not 1 (not a polarcam states file)");
		goto out;
	}
	v = json_object_get(d, "frame_order");
	if (!json_is_string(v) || strcmp(json_string_value(v), "psg_fastest")) {
		rc = st_err(path, "frame_order", "expected \"psg_fastest\"");
		goto out;
	}
	json_t *g = json_object_get(d, "psg"), *a = json_object_get(d, "psa");
	if (!json_is_array(g) || json_array_size(g) < 1 || json_array_size(g) > 64) {
		rc = st_err(path, "psg", "expected 1 to 64 Stokes vectors");
		goto out;
	}
	if (!json_is_array(a) || json_array_size(a) < 1 || json_array_size(a) > 64) {
		rc = st_err(path, "psa", "expected 1 to 64 Mueller matrices");
		goto out;
	}
	st->n_psg = (unsigned)json_array_size(g);
	st->n_psa = (unsigned)json_array_size(a);
	for (unsigned i = 0; i < st->n_psg; i++)
		if (read_vec(json_array_get(g, i), st->psg[i], 4)) {
			char f[32];
			snprintf(f, sizeof f, "psg[%u]", i);
			rc = st_err(path, f, "expected 4 finite numbers");
			goto out;
		}
	for (unsigned i = 0; i < st->n_psa; i++) {
		json_t *m = json_array_get(a, i);
		bool ok = json_is_array(m) && json_array_size(m) == 4;
		for (unsigned r = 0; ok && r < 4; r++)
			ok = !read_vec(json_array_get(m, r), st->psa[i][r], 4);
		if (!ok) {
			char f[32];
			snprintf(f, sizeof f, "psa[%u]", i);
			rc = st_err(path, f, "expected 4 rows of 4 finite numbers");
			goto out;
		}
	}
	json_t *an = json_object_get(d, "analyser");
	if (an) {
		bool ok = json_is_array(an) && json_array_size(an) == 4;
		for (unsigned c = 0; ok && c < 4; c++)
			ok = !read_vec(json_array_get(an, c), st->analyser[c], 4);
		if (!ok) {
			rc = st_err(path, "analyser", "expected 4 rows of 4 finite numbers");
			goto out;
		}
	} else {
		for (unsigned c = 0; c < 4; c++) {
			double th = c * M_PI / 4;
			st->analyser[c][0] = 0.5;
			st->analyser[c][1] = 0.5 * cos(2 * th);
			st->analyser[c][2] = 0.5 * sin(2 * th);
		}
	}
	v = json_object_get(d, "layout");
	if (layout && layout_size) {
		if (v && !json_is_string(v)) {
			rc = st_err(path, "layout", "expected a layout string such as \"90,45,135,0\"");
			goto out;
		}
		snprintf(layout, layout_size, "%s", v ? json_string_value(v) : "");
	}
out:
	json_decref(d);
	return rc;
}

typedef struct lc_ctx {
	const float *M;
	float *Mw; /* = M when the rebuild writes the circular entries back, else NULL */
	float *D, *R, *Delta, *residual;
	uint32_t width;
	unsigned determined;
	const pc_rebuild_opts *rb; /* non-NULL: rebuild the circular entries from the 3×3 */
	long singular, nonphysical, bad; /* counted per band, summed under a lock-free atomic */
	long rb_rejected, rb_undefined;
} lc_ctx;

/* the 3×3 linear block: bits 4k + l, k, l < 3 */
#define PC_LINEAR_BLOCK 0x777u

/* Rebuild only where it applies: the linear block determined, not the whole matrix. */
static bool rebuild_applies(const pc_rebuild_opts *rb, unsigned determined)
{
	return rb && rb->sign != PC_REBUILD_OFF && determined != 0xFFFFu &&
	       (determined & PC_LINEAR_BLOCK) == PC_LINEAR_BLOCK;
}

static void lc_rows(void *ctx, uint32_t y0, uint32_t y1)
{
	/* chunks of a row through the batched Lu–Chipman kernel (bit-identical to
	 * pc_lu_chipman_decompose with PC_LC_FILTER | PC_LC_NO_FACTORS per pixel) */
	enum { CH = 256 };
	lc_ctx *c = ctx;
	long singular = 0, nonphys = 0, bad = 0, rejected = 0, undefined = 0;
	double Mb[16 * CH], D[CH], R[CH], De[CH];
	unsigned fl[CH];
	const pc_lc_map out = { D, { NULL, NULL, NULL }, R, { NULL, NULL, NULL }, NULL, NULL,
				De, NULL, fl };
	for (uint32_t y = y0; y < y1; y++)
		for (uint32_t x0 = 0; x0 < c->width; x0 += CH) {
			size_t n = c->width - x0 < CH ? c->width - x0 : CH;
			size_t i0 = (size_t)y * c->width + x0;
			if (c->determined != 0xFFFFu && !c->rb) {
				for (size_t j = 0; j < n; j++)
					c->D[i0 + j] = c->R[i0 + j] = c->Delta[i0 + j] = NAN;
				continue;
			}
			for (size_t k = 0; k < 16 * n; k++)
				Mb[k] = c->M[16 * i0 + k];
			if (c->rb) {
				/* physics.md §7: the 4×4 of the pBRDF family from its 3×3 */
				for (size_t j = 0; j < n; j++) {
					double N[3][3], R4[4][4];
					const float *m = c->M + 16 * (i0 + j);
					float *mw = c->Mw ? c->Mw + 16 * (i0 + j) : NULL;
					pc_rebuild_info in;
					for (int k = 0; k < 3; k++)
						for (int l = 0; l < 3; l++)
							N[k][l] = m[4 * k + l];
					if (pc_mueller_rebuild_from_linear(N, c->rb->sign, c->rb->tol, R4,
									   &in)) {
						in.flags = PC_RB_ZERO; /* non-finite input */
						in.residual = NAN;
						for (int k = 0; k < 4; k++)
							for (int l = 0; l < 4; l++)
								R4[k][l] = NAN;
					}
					if (c->residual)
						c->residual[i0 + j] = (float)in.residual;
					/* M00 ≤ 0 (background, shadow) is no rejection: nothing
					 * was there to rebuild */
					rejected += (in.flags & (PC_RB_INCONSISTENT | PC_RB_NONPHYSICAL)) != 0;
					undefined += (in.flags & PC_RB_SIGN_UNDEFINED) != 0;
					for (int k = 0; k < 4; k++)
						for (int l = 0; l < 4; l++) {
							Mb[16 * j + 4 * (size_t)k + (size_t)l] = R4[k][l];
							if (mw && (k == 3 || l == 3))
								mw[4 * k + l] = (float)R4[k][l];
						}
				}
			}
			if (pc_lu_chipman_map(Mb, n, PC_LC_FILTER | PC_LC_NO_FACTORS, &out)) {
				for (size_t j = 0; j < n; j++)
					c->D[i0 + j] = c->R[i0 + j] = c->Delta[i0 + j] = NAN;
				bad += (long)n;
				continue;
			}
			for (size_t j = 0; j < n; j++) {
				size_t i = i0 + j;
				if (fl[j] & PC_LC_NONFINITE) {
					c->D[i] = c->R[i] = c->Delta[i] = NAN;
					bad++;
					continue;
				}
				c->D[i] = (float)D[j];
				c->R[i] = (float)R[j];
				c->Delta[i] = (float)De[j];
				singular += (fl[j] & (PC_LC_D_SINGULAR | PC_LC_ZERO_M00)) != 0;
				/* not physical: rejected by the check, or M00 ≤ 0 (never checked) */
				nonphys += (fl[j] & (PC_LC_NONPHYSICAL | PC_LC_ZERO_M00)) != 0;
			}
		}
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->singular += singular;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->nonphysical += nonphys;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->bad += bad;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->rb_rejected += rejected;
#ifdef _OPENMP
#pragma omp atomic
#endif
	c->rb_undefined += undefined;
}

void pc_mueller_maps_rebuild(float *M, uint32_t width, uint32_t height, unsigned determined,
			     const pc_rebuild_opts *rb, int threads, float *D, float *R,
			     float *Delta, float *residual, long counts[3], long rb_counts[2])
{
	bool use = rebuild_applies(rb, determined);
	lc_ctx lc = { M, M, D, R, Delta, use ? residual : NULL, width, determined,
		      use ? rb : NULL, 0, 0, 0, 0, 0 };
	pc_parallel_rows(height, 0, threads, lc_rows, &lc);
	if (counts) {
		counts[0] = lc.singular;
		counts[1] = lc.nonphysical;
		counts[2] = lc.bad;
	}
	if (rb_counts) {
		rb_counts[0] = lc.rb_rejected;
		rb_counts[1] = lc.rb_undefined;
	}
}

void pc_mueller_maps(const float *M, uint32_t width, uint32_t height, unsigned determined,
		     int threads, float *D, float *R, float *Delta, long counts[3])
{
	lc_ctx lc = { M, NULL, D, R, Delta, NULL, width, determined, NULL, 0, 0, 0, 0, 0 };
	pc_parallel_rows(height, 0, threads, lc_rows, &lc);
	if (counts) {
		counts[0] = lc.singular;
		counts[1] = lc.nonphysical;
		counts[2] = lc.bad;
	}
}

void pc_mueller_result_free(pc_mueller_result *res)
{
	free(res->M);
	free(res->maps);
	free(res->residual);
	res->M = res->maps = res->residual = NULL;
}

int pc_mueller_run(pc_frame_get_fn get, void *user, const pc_sim_states *st,
		   const pc_mosaic *mosaic, pc_demosaic_method method, double black, int threads,
		   const pc_rebuild_opts *rb, cli_progress *bar, pc_mueller_result *res)
{
	memset(res, 0, sizeof *res);
	int rc = pc_mueller_system_init(&res->sys, st->n_psg, st->psg, st->n_psa, st->psa,
					st->analyser);
	if (rc)
		return rc;
	size_t nframes = (size_t)st->n_psg * st->n_psa;
	pc_demosaic_opts dopt = { threads, false, 0 };
	uint32_t W = 0, H = 0, ow = 0, oh = 0;
	float *planes = NULL;
	pc_view raw = { 0 };
	for (size_t j = 0; j < nframes; j++) {
		if ((rc = get(user, j, &raw)))
			goto fail;
		if (j == 0) {
			W = raw.width;
			H = raw.height;
			pc_demosaic_out_size(method, W, H, &ow, &oh);
			res->M = calloc((size_t)ow * oh * 16, sizeof *res->M);
			planes = malloc((size_t)ow * oh * 4 * sizeof *planes);
			if (!res->M || !planes) {
				rc = pc_error(PC_ENOMEM, "Mueller images of %ux%u", ow, oh);
				goto fail;
			}
		} else if (raw.width != W || raw.height != H) {
			rc = pc_error(PC_EINVAL, "frame %zu is %ux%u, frame 0 is %ux%u", j, raw.width,
				      raw.height, W, H);
			goto fail;
		}
		pc_fplane pl[4];
		pc_fplanes_separate(planes, ow, oh, 4, pl);
		if ((rc = pc_demosaic(&raw, mosaic, method, &dopt, pl))) {
			pc_error_prefix(rc, "frame %zu: ", j);
			goto fail;
		}
		if (black != 0)
			for (size_t k = 0; k < (size_t)ow * oh * 4; k++)
				planes[k] -= (float)black;
		if ((rc = pc_mueller_accumulate(&res->sys, (unsigned)j, pl, ow, oh, threads, res->M)))
			goto fail;
		pc_view_free(&raw);
		if (bar)
			cli_progress_update(bar, j + 1);
	}
	pc_mueller_finish(&res->sys, ow, oh, res->M);
	free(planes);
	planes = NULL;
	size_t np = (size_t)ow * oh;
	res->maps = malloc(np * 3 * sizeof *res->maps);
	if (!res->maps) {
		rc = pc_error(PC_ENOMEM, "decomposition maps");
		goto fail;
	}
	long counts[3], rbc[2] = { 0, 0 };
	res->rebuilt = rebuild_applies(rb, res->sys.determined);
	if (res->rebuilt && !(res->residual = malloc(np * sizeof *res->residual))) {
		rc = pc_error(PC_ENOMEM, "rebuild residual map");
		goto fail;
	}
	pc_mueller_maps_rebuild(res->M, ow, oh, res->sys.determined, rb, threads, res->maps,
				res->maps + np, res->maps + 2 * np, res->residual, counts, rbc);
	res->singular = counts[0];
	res->nonphysical = counts[1];
	res->bad = counts[2];
	res->rb_rejected = rbc[0];
	res->rb_sign_undefined = rbc[1];
	res->width = ow;
	res->height = oh;
	return 0;
fail:
	pc_view_free(&raw);
	free(planes);
	pc_mueller_result_free(res);
	return rc;
}
