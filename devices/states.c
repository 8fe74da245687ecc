/* states.json, written and read (polarcam/states.h). */
#include "polarcam/states.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/io.h"

int pc_states_write(const char *path, const pc_sim_states *st, const pc_mosaic *mosaic)
{
	json_t *o = json_object();
	json_object_set_new(o, "polarcam_states", json_integer(1));
	json_object_set_new(o, "frame_order", json_string("psg_fastest"));
	json_object_set_new(o, "n_psg", json_integer(st->n_psg));
	json_object_set_new(o, "n_psa", json_integer(st->n_psa));
	json_t *g = json_array();
	for (unsigned i = 0; i < st->n_psg; i++)
		json_array_append_new(g, pc_json_vec(st->psg[i], 4));
	json_object_set_new(o, "psg", g);
	json_t *a = json_array();
	for (unsigned i = 0; i < st->n_psa; i++)
		json_array_append_new(a, pc_json_matrix4(st->psa[i]));
	json_object_set_new(o, "psa", a);
	if (mosaic) {
		char mos[64];
		pc_mosaic_format(mosaic, mos, sizeof mos);
		json_object_set_new(o, "layout", json_string(mos));
	}
	json_t *an = json_array();
	for (unsigned c = 0; c < 4; c++)
		json_array_append_new(an, pc_json_vec(st->analyser[c], 4));
	json_object_set_new(o, "analyser", an);
	char *txt = json_dumps(o, JSON_INDENT(1) | JSON_REAL_PRECISION(17));
	json_decref(o);
	int rc =
	    txt ? pc_write_file_atomic(path, txt, strlen(txt)) : pc_error(PC_ENOMEM, "%s", path);
	free(txt);
	return rc;
}

/* An array of 1..64 entries. */
static int state_list(const pc_json_src *js, json_t *d, const char *key, const char *what,
                      json_t **out)
{
	json_t *v = json_object_get(d, key);
	if (!json_is_array(v) || json_array_size(v) < 1 || json_array_size(v) > 64)
		return pc_json_error(js, key, "expected 1 to 64 %s", what);
	*out = v;
	return 0;
}

/* Four rows of four finite numbers. */
static int rows4(const pc_json_src *js, const json_t *m, const char *path, double out[4][4])
{
	bool ok = json_is_array(m) && json_array_size(m) == 4;
	for (unsigned r = 0; ok && r < 4; r++) {
		const json_t *row = json_array_get(m, r);
		ok = json_is_array(row) && json_array_size(row) == 4;
		for (unsigned k = 0; ok && k < 4; k++) {
			const json_t *e = json_array_get(row, k);
			ok = json_is_number(e) && isfinite(json_number_value(e));
			if (ok)
				out[r][k] = json_number_value(e);
		}
	}
	return ok ? 0 : pc_json_error(js, path, "expected 4 rows of 4 finite numbers");
}

int pc_states_read(const char *path, pc_sim_states *st, char *layout, size_t layout_size)
{
	json_t *d = NULL;
	int rc = pc_json_load(path, true, &d);
	if (rc)
		return rc;
	memset(st, 0, sizeof *st);
	const pc_json_src js = {path, PC_EFORMAT};
	char p[32];
	json_t *v = json_object_get(d, "polarcam_states"), *g = NULL, *a = NULL;
	if (!json_is_integer(v) || json_integer_value(v) != 1) {
		rc = pc_json_error(&js, "polarcam_states",
		                   "missing or not 1 (not a polarcam states file)");
		goto out;
	}
	v = json_object_get(d, "frame_order");
	if (!json_is_string(v) || strcmp(json_string_value(v), "psg_fastest")) {
		rc = pc_json_error(&js, "frame_order", "expected \"psg_fastest\"");
		goto out;
	}
	if ((rc = state_list(&js, d, "psg", "Stokes vectors", &g)) ||
	    (rc = state_list(&js, d, "psa", "Mueller matrices", &a)))
		goto out;
	st->n_psg = (unsigned)json_array_size(g);
	st->n_psa = (unsigned)json_array_size(a);
	for (unsigned i = 0; i < st->n_psg; i++) {
		pc_json_path_index(p, sizeof p, "psg", i);
		if (pc_json_nums(&js, json_array_get(g, i), p, st->psg[i], 4)) {
			rc = pc_json_error(&js, p, "expected 4 finite numbers");
			goto out;
		}
	}
	for (unsigned i = 0; i < st->n_psa; i++) {
		pc_json_path_index(p, sizeof p, "psa", i);
		if ((rc = rows4(&js, json_array_get(a, i), p, st->psa[i])))
			goto out;
	}
	json_t *an = json_object_get(d, "analyser");
	if (an) {
		if ((rc = rows4(&js, an, "analyser", st->analyser)))
			goto out;
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
			rc = pc_json_error(&js, "layout",
			                   "expected a layout string such as \"90,45,135,0\"");
			goto out;
		}
		snprintf(layout, layout_size, "%s", v ? json_string_value(v) : "");
	}
out:
	json_decref(d);
	return rc;
}
