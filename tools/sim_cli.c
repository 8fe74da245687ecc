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

int pc_path_join(char *buf, size_t size, const char *dir, const char *name)
{
	int n = snprintf(buf, size, "%s/%s", dir, name);
	if (n < 0 || (size_t)n >= size)
		return pc_error(PC_EINVAL, "path too long: %s/%s", dir, name);
	return 0;
}
