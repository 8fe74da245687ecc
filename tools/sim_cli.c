#include "sim_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/picture.h"
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
	return pc_json_vec(v, n);
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
	json_t *s = json_object();
	char mos[64];
	pc_mosaic_format(&f.mosaic, mos, sizeof mos);
	json_object_set_new(s, "preset", json_string(f.preset));
	json_object_set_new(s, "width", json_integer(f.width));
	json_object_set_new(s, "height", json_integer(f.height));
	json_object_set_new(s, "pixel_pitch_um", pc_json_real(f.pixel_pitch_um));
	json_object_set_new(s, "bits", json_integer(f.bits));
	json_object_set_new(s, "layout", json_string(mos));
	unsigned nch = in.colour_channels;
	json_object_set_new(s, "qe", vec_json(nch == 3 ? f.qe : &f.qe[1], nch));
	json_object_set_new(s, "wavelength_nm", vec_json(nch == 3 ? f.wavelength_nm : &f.wavelength_nm[1], nch));
	json_object_set_new(s, "full_well_e", pc_json_real(f.full_well_e));
	json_object_set_new(s, "read_noise_e", pc_json_real(f.read_noise_e));
	json_object_set_new(s, "dark_current_e_s", pc_json_real(f.dark_current_e_s));
	json_object_set_new(s, "dsnu_e", pc_json_real(f.dsnu_e));
	json_object_set_new(s, "prnu", pc_json_real(f.prnu));
	json_object_set_new(s, "gain_dn_per_e", pc_json_real(f.gain_dn_per_e));
	json_object_set_new(s, "offset_dn", pc_json_real(f.offset_dn));
	json_object_set_new(s, "extinction_ratio", pc_json_real(f.extinction_ratio)); /* ∞ → null */
	json_object_set_new(s, "orientation_sigma_deg", pc_json_real(f.orientation_sigma_deg));
	json_object_set_new(s, "orientation_offset_deg", vec_json(f.orientation_offset_deg, 4));
	json_object_set_new(s, "transmission_sigma", pc_json_real(f.transmission_sigma));
	json_object_set_new(s, "transmission", vec_json(f.transmission, 4));
	json_object_set_new(s, "crosstalk", pc_json_real(f.crosstalk));
	json_object_set_new(s, "exposure_us", pc_json_real(f.exposure_us));
	json_object_set_new(s, "gain_db", pc_json_real(f.gain_db));
	json_object_set_new(s, "frame_rate_hz", pc_json_real(f.frame_rate_hz));
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
		json_array_append_new(g, pc_json_vec(st.psg[i], 4));
	json_object_set_new(o, "psg", g);
	json_t *a = json_array();
	for (unsigned i = 0; i < st.n_psa; i++)
		json_array_append_new(a, pc_json_matrix4(st.psa[i]));
	json_object_set_new(o, "psa", a);
	char mos[64];
	pc_mosaic_format(&in.mosaic, mos, sizeof mos);
	json_object_set_new(o, "layout", json_string(mos));
	json_t *an = json_array();
	for (unsigned c = 0; c < 4; c++)
		json_array_append_new(an, pc_json_vec(st.analyser[c], 4));
	json_object_set_new(o, "analyser", an);
	return o;
}

void pc_sim_progress_cb(void *user, uint64_t done, uint64_t total)
{
	pc_sim_progress_adapter *a = user;
	(void)total;
	pc_progress_update(a->bar, a->base + done);
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
		if (!rc)
			rc = pc_image_write_png(path, rgb, width, height, (size_t)width * 3, title, &bar,
						1600);
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
