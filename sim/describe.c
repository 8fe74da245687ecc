/* The simulator described as JSON, for meta.json and reports (polarcam/sim.h). */
#include "polarcam/sim.h"

#include <jansson.h>
#include <stdlib.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/mosaic.h"

/* The effect names of a PC_FX_* set. */
static json_t *effects_json(unsigned effects)
{
	json_t *a = json_array();
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (effects & (1u << i))
			json_array_append_new(a, json_string(pc_sim_effect_name(1u << i)));
	return a;
}

char *pc_sim_describe_json(const pc_sim *sim, const pc_scene *scene)
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
	json_object_set_new(o, "effects", effects_json(in.effects));
	/* the elements in front of the camera (image-plane Mueller matrices): for a uniform
	 * unpolarized background their first column is the stimulus (polarcam calibrate) */
	pc_sim_states *st = malloc(sizeof *st);
	if (st) {
		pc_sim_get_states(sim, st);
		json_t *pa = json_array();
		for (unsigned a = 0; a < st->n_psa; a++)
			json_array_append_new(pa, pc_json_matrix4(st->psa[a]));
		json_object_set_new(o, "psa_mueller", pa);
		free(st);
	}
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
	json_object_set_new(s, "qe", pc_json_vec(nch == 3 ? f.qe : &f.qe[1], nch));
	json_object_set_new(s, "wavelength_nm",
	                    pc_json_vec(nch == 3 ? f.wavelength_nm : &f.wavelength_nm[1], nch));
	json_object_set_new(s, "full_well_e", pc_json_real(f.full_well_e));
	json_object_set_new(s, "read_noise_e", pc_json_real(f.read_noise_e));
	json_object_set_new(s, "dark_current_e_s", pc_json_real(f.dark_current_e_s));
	json_object_set_new(s, "dsnu_e", pc_json_real(f.dsnu_e));
	json_object_set_new(s, "prnu", pc_json_real(f.prnu));
	json_object_set_new(s, "gain_dn_per_e", pc_json_real(f.gain_dn_per_e));
	json_object_set_new(s, "offset_dn", pc_json_real(f.offset_dn));
	json_object_set_new(s, "extinction_ratio", pc_json_real(f.extinction_ratio)); /* ∞ → null */
	json_object_set_new(s, "extinction_ratio_sigma", json_real(f.extinction_ratio_sigma));
	json_object_set_new(s, "orientation_sigma_deg", pc_json_real(f.orientation_sigma_deg));
	json_object_set_new(s, "orientation_offset_deg", pc_json_vec(f.orientation_offset_deg, 4));
	json_object_set_new(s, "transmission_sigma", pc_json_real(f.transmission_sigma));
	json_object_set_new(s, "transmission", pc_json_vec(f.transmission, 4));
	json_object_set_new(s, "crosstalk", pc_json_real(f.crosstalk));
	json_object_set_new(s, "exposure_us", pc_json_real(f.exposure_us));
	json_object_set_new(s, "gain_db", pc_json_real(f.gain_db));
	json_object_set_new(s, "frame_rate_hz", pc_json_real(f.frame_rate_hz));
	json_object_set_new(s, "effects", effects_json(f.effects));
	json_object_set_new(o, "sensor", s);
	json_t *roi = json_object();
	json_object_set_new(roi, "x", json_integer(in.offset_x));
	json_object_set_new(roi, "y", json_integer(in.offset_y));
	json_object_set_new(roi, "width", json_integer(in.width));
	json_object_set_new(roi, "height", json_integer(in.height));
	json_object_set_new(o, "roi", roi);
	json_object_set_new(o, "n_states", json_integer(in.n_states));
	char *text = json_dumps(o, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(o);
	if (!text)
		pc_error(PC_ENOMEM, "simulator description");
	return text;
}
