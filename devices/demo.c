/* The main job (polarcam/demo.h): render, pipeline with several methods scored against the
 * truth, Mueller imaging of the same scene, pictures and a report. */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/demo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/folders.h"
#include "polarcam/io.h"
#include "polarcam/mueller_imaging.h"
#include "polarcam/parallel.h"
#include "polarcam/picture.h"
#include "polarcam/recording.h"
#include "polarcam/sim.h"
#include "polarcam/stokes.h"

struct pc_demo {
	pc_demo_opts o;
	pc_demosaic_method methods[PC_DM_COUNT];
	pc_scene *scene;
	pc_sim *sim;
	pc_sim_info in;
};

/* what the steps found, for the report */
typedef struct demo_results {
	char method[PC_DM_COUNT][32];
	double seconds[PC_DM_COUNT];
	pc_eval_stokes_metrics acc[PC_DM_COUNT];
	unsigned best;
	long saturated;
	double scale;          /* DN per W m^-2 sr^-1 */
	double s0_hi, dolp_hi; /* the pictures' shared scales (the truth's) */
	bool truth_circular;   /* the truth carries S3: truth/docp, truth/ellipticity written */
	double t_render, t_frame, t_mueller;
	char *simulation; /* pc_sim_describe_json */
	/* Mueller step */
	uint32_t mw, mh;
	pc_mueller_system sys;
	double med[3];
	long used[3], m_saturated, nonphysical;
} demo_results;

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int join(char *buf, size_t size, const char *dir, const char *name)
{
	int n = snprintf(buf, size, "%s/%s", dir, name);
	if (n < 0 || (size_t)n >= size)
		return pc_error(PC_EINVAL, "path too long: %s/%s", dir, name);
	return 0;
}

/* pc_sim_progress_fn → pc_progress with a phase */
typedef struct sim_progress {
	const pc_progress *p;
	const char *phase;
} sim_progress;

static void sim_progress_cb(void *user, uint64_t done, uint64_t total)
{
	const sim_progress *a = user;
	pc_progress_report(a->p, a->phase, done, total);
}

int pc_demo_new(const pc_demo_opts *opts, pc_demo **out)
{
	*out = NULL;
	if (!opts || (opts->n_methods && !opts->methods) || opts->n_methods > PC_DM_COUNT)
		return pc_error(PC_EINVAL, "demo: bad options");
	pc_demo *d = calloc(1, sizeof *d);
	if (!d)
		return pc_error(PC_ENOMEM, "demo");
	d->o = *opts;
	for (unsigned m = 0; m < opts->n_methods; m++)
		d->methods[m] =
		    opts->methods[m] == PC_DM_SUPERPIXEL_HALF ? PC_DM_SUPERPIXEL : opts->methods[m];
	d->o.methods = d->methods;
	int rc = opts->scene_path ? pc_scene_load(opts->scene_path, &d->scene)
	                          : pc_scene_load_default(&d->scene);
	pc_sim_options so = pc_sim_options_default();
	so.seed = opts->seed;
	so.threads = opts->threads;
	if (!rc && (rc = pc_sim_new(d->scene, &so, &d->sim)))
		pc_error_prefix(rc, "scene: ");
	if (!rc) {
		pc_sim_get_info(d->sim, &d->in);
		if (d->in.colour_channels != 1)
			rc = pc_error(PC_EINVAL,
			              "the demo handles monochrome sensors; render colour "
			              "scenes with polarcam render");
	}
	if (rc) {
		pc_demo_free(d);
		return rc;
	}
	*out = d;
	return 0;
}

void pc_demo_get_info(const pc_demo *d, pc_demo_info *info)
{
	info->scene_name = pc_scene_name(d->scene);
	info->width = d->in.width;
	info->height = d->in.height;
	info->effects = d->in.effects;
}

void pc_demo_free(pc_demo *d)
{
	if (!d)
		return;
	pc_sim_free(d->sim);
	pc_scene_free(d->scene);
	free(d);
}

/* Step 1: the truth and raw frame 0 (a recording in out), truth_stokes.npy, the truth's S0 (in
 * DN), DoLP and AoLP planes tp and their pictures. */
static int step_truth(pc_demo *d, const char *out, pc_view *raw, float *tp, demo_results *r)
{
	const uint32_t W = d->in.width, H = d->in.height;
	const size_t np = (size_t)W * H;
	float *ts = malloc(np * 4 * sizeof *ts);
	if (!ts)
		return pc_error(PC_ENOMEM, "ground truth of %ux%u", W, H);
	sim_progress sp = {&d->o.progress, "render"};
	double t0 = now_s();
	int rc = pc_sim_prepare(d->sim, 0, ts, NULL, sim_progress_cb, &sp);
	r->t_render = now_s() - t0;
	if (rc) {
		free(ts);
		return pc_error_prefix(rc, "render: ");
	}
	pc_frame fr;
	if ((rc = pc_view_alloc(raw, d->in.format, W, H, 64)))
		goto out;
	t0 = now_s();
	rc = pc_sim_frame(d->sim, 0, NULL, raw, &fr.meta);
	r->t_frame = now_s() - t0;
	if (rc) {
		pc_error_prefix(rc, "frame: ");
		goto out;
	}
	char source[1024], path[4096];
	snprintf(source, sizeof source, "sim:%s?seed=%llu",
	         d->o.scene_path ? d->o.scene_path : "default", (unsigned long long)d->o.seed);
	pc_recording_desc desc = {source,
	                          d->in.format,
	                          NULL,
	                          W,
	                          H,
	                          d->in.offset_x,
	                          d->in.offset_y,
	                          d->in.sensor_width,
	                          d->in.sensor_height,
	                          true,
	                          d->in.mosaic,
	                          PC_STORE_PNG};
	fr.view = *raw;
	fr.mosaic = d->in.mosaic;
	pc_recording *rec = NULL;
	if ((rc = pc_recording_create(&rec, out, &desc, false)) ||
	    (rc = pc_recording_add(rec, &fr))) {
		pc_recording_free(rec);
		pc_error_prefix(rc, "%s: ", out);
		goto out;
	}
	r->simulation = pc_sim_describe_json(d->sim, d->scene);
	rc = r->simulation ? pc_recording_set_json(rec, "extra", r->simulation) : PC_ENOMEM;
	if (!rc)
		rc = pc_recording_finish(rec, NULL);
	pc_recording_free(rec);
	if (rc) {
		pc_error_prefix(rc, "meta.json: ");
		goto out;
	}
	size_t shp[3] = {H, W, 4};
	if ((rc = join(path, sizeof path, out, "truth_stokes.npy")) ||
	    (rc = pc_npy_write(path, ts, PC_DT_F32, 3, shp)))
		goto out;
	/* truth in DN (the pipeline's units): pictures of truth and estimate share one scale */
	r->scale = pc_sim_dn_per_radiance(d->sim, NULL, 0);
	const double full = (double)((1u << d->in.bits) - 1);
	pc_eval_truth_planes(ts, np, r->scale, tp, tp + np, tp + 2 * np);
	for (uint32_t y = 0; y < H; y++) {
		const uint16_t *row = PC_ROW(raw, uint16_t, y);
		for (uint32_t x = 0; x < W; x++)
			r->saturated += row[x] >= full;
	}
	pc_stokes_out so = {
	    {tp, W, 1}, {NULL, 0, 0}, {NULL, 0, 0}, {tp + np, W, 1}, {tp + 2 * np, W, 1}};
	/* one scale for the truth's and every estimate's pictures: the truth's S0 99.9th
	 * percentile, at most the S0 a saturated super-pixel gives (2 x full scale: an estimate
	 * cannot exceed it, the truth can), and the truth's automatic DoLP range (over the pixels
	 * above the default mask) */
	const pc_fplane ts0 = {tp, W, 1};
	r->s0_hi = fmin(pc_picture_quantile(&ts0, W, H, 0.999), 2 * full);
	if (!(r->s0_hi > 0))
		r->s0_hi = 1;
	r->dolp_hi =
	    pc_pictures_dolp_auto(tp + np, tp, np, PC_PICTURES_MASK_DEFAULT_REL * r->s0_hi);
	pc_stokes_folder_opts fo = {
	    .files = PC_SF_PICTURES,
	    .pictures = {.title_prefix = "truth", .s0_hi = r->s0_hi, .dolp_hi = r->dolp_hi}};
	if ((rc = join(path, sizeof path, out, "truth")) ||
	    (rc = pc_stokes_folder_write(path, &so, W, H, &fo)))
		pc_error_prefix(rc, "%s: ", path);
	/* circular polarization where the truth carries S3 (the scene's "circular" effect; a
	 * camera of linear analysers cannot measure it): DoCP and ellipticity, S0 in DN for the
	 * mask */
	bool has_s3 = false;
	for (size_t i = 0; i < np && !has_s3; i++)
		has_s3 = isfinite(ts[4 * i + 3]);
	r->truth_circular = has_s3;
	if (!rc && has_s3) {
		pc_fplane s4[4] = {{tp, W, 1},
		                   {ts + 1, 4 * (size_t)W, 4},
		                   {ts + 2, 4 * (size_t)W, 4},
		                   {ts + 3, 4 * (size_t)W, 4}};
		/* S1..S3 in radiance units beside S0 in DN: only ratios to S0 are drawn, so
		 * scale them to DN as well */
		for (size_t i = 0; i < np; i++)
			for (int k = 1; k < 4; k++)
				ts[4 * i + k] = (float)(ts[4 * i + k] * r->scale);
		pc_pictures_opts cp = {"truth", 0, 0, NULL, r->s0_hi, -1};
		if ((rc = pc_circular_folder_write(path, s4, W, H, &cp)))
			pc_error_prefix(rc, "%s: ", path);
	}
out:
	free(ts);
	return rc;
}

/* Step 2: the pipeline with each method, timed and scored; pictures of every method on the
 * truth's scales, stokes.npy of bilinear. */
static int step_pipeline(pc_demo *d, const char *out, const pc_view *raw, const float *tp,
                         demo_results *r)
{
	const uint32_t W = d->in.width, H = d->in.height;
	const size_t np = (size_t)W * H;
	const double full = (double)((1u << d->in.bits) - 1);
	float *ep = malloc(np * 5 * sizeof *ep);
	uint8_t *vmask = malloc(np);
	if (!ep || !vmask) {
		free(ep);
		free(vmask);
		return pc_error(PC_ENOMEM, "Stokes images of %ux%u", W, H);
	}
	const pc_stokes_out eo = {{ep, W, 1},
	                          {ep + np, W, 1},
	                          {ep + 2 * np, W, 1},
	                          {ep + 3 * np, W, 1},
	                          {ep + 4 * np, W, 1}};
	pc_demosaic_opts dopt = {d->o.threads, false, 0};
	/* Every method is timed the same way: the same call (raw -> S0, S1, S2, DoLP, AoLP into
	 * the same buffers, pc_stokes_from_raw, each method on its own path), one untimed run
	 * first (thread start-up, first-touch and the method's own buffers), then the fastest of
	 * DEMO_REPS runs. */
	enum { DEMO_REPS = 3 };
	int rc = 0;
	for (unsigned m = 0; !rc && m < d->o.n_methods; m++) {
		const char *name = pc_demosaic_method_get(d->methods[m])->name;
		r->seconds[m] = INFINITY;
		for (int k = 0; k <= DEMO_REPS && !rc; k++) {
			double t0 = now_s();
			rc = pc_stokes_from_raw(raw, &d->in.mosaic, d->methods[m], &dopt, &eo);
			double t = now_s() - t0;
			if (k > 0 && t < r->seconds[m])
				r->seconds[m] = t;
		}
		if (rc) {
			pc_error_prefix(rc, "%s: ", name);
			break;
		}
		snprintf(r->method[m], sizeof r->method[m], "%s", name);
		rc = pc_eval_stokes(eo.s0.data, eo.dolp.data, eo.aolp.data, tp, tp + np,
		                    tp + 2 * np, W, H, full, &r->acc[m]);
		if (rc)
			break;
		if (r->acc[m].dolp_rms < r->acc[r->best].dolp_rms)
			r->best = m;
		bool bilinear = d->methods[m] == PC_DM_BILINEAR;
		{ /* pictures of every method, on the truth's scales, the pixels that depend on
		   * a saturated sample marked (untimed: the validity of this method's support) */
			pc_pipeline_opts vo = pc_pipeline_defaults();
			vo.method = d->methods[m];
			vo.mosaic = d->in.mosaic;
			vo.threads = d->o.threads;
			vo.saturation_level = full;
			pc_validity valid = {vmask, W, 0};
			if ((rc = pc_validity_run(raw, &vo, &valid))) {
				pc_error_prefix(rc, "%s: validity: ", name);
				break;
			}
			char sub[96], dir[4096];
			if (snprintf(sub, sizeof sub, "pipeline_%.40s", name) >= (int)sizeof sub)
				sub[sizeof sub - 1] = '\0';
			pc_stokes_folder_opts fo = {.files = PC_SF_PICTURES,
			                            .pictures = {.title_prefix = r->method[m],
			                                         .s0_hi = r->s0_hi,
			                                         .dolp_hi = r->dolp_hi}};
			fo.no_valid_file = true;
			if ((rc = join(dir, sizeof dir, out, sub)) ||
			    (rc = pc_stokes_folder_write_valid(dir, &eo, W, H, &fo, &valid))) {
				pc_error_prefix(rc, "%s: ", dir);
				break;
			}
		}
		/* stokes.npy (H, W, 3): S0, S1, S2 in DN from the bilinear pipeline */
		pc_stokes_folder_opts fs = {.files = PC_SF_STOKES};
		if (bilinear && (rc = pc_stokes_folder_write(out, &eo, W, H, &fs)))
			break;
	}
	free(ep);
	free(vmask);
	return rc;
}

/* The Mueller-imaging variant of a scene: w×h (same sensor area), the lights carry the
 * tetrahedral PSG (polarizer 0° + 132° retarder at ±15.1°, ±51.7°; physics.md §7), a
 * quarter-wave plate at 0° and 45° in front of the camera, circular + mueller effects. */
static char *mueller_variant(const char *scene_text, uint32_t w, uint32_t h, double pitch_um,
                             double exposure_us)
{
	json_t *d = json_loads(scene_text, 0, NULL);
	if (!d)
		return NULL;
	/* every light passes through the same generator states (each in its own Stokes frame), so
	 * that the reconstruction and the Mueller ground truth (summed over lights) agree */
	json_t *lights = json_object_get(d, "lights");
	size_t li;
	json_t *l;
	json_array_foreach(lights, li, l)
	{
		json_object_del(l, "polarization");
		json_t *st = json_array();
		const double ang[4] = {15.1, 51.7, -51.7, -15.1};
		for (int i = 0; i < 4; i++)
			json_array_append_new(st, json_pack("{s:f, s:{s:f, s:f}}", "polarizer_deg",
			                                    0.0, "retarder", "angle_deg", ang[i],
			                                    "retardance_deg", 132.0));
		json_object_set_new(l, "states", st);
	}
	json_t *fx = json_object_get(d, "effects");
	if (!fx) {
		fx = json_object();
		json_object_set_new(d, "effects", fx);
	}
	json_object_set_new(fx, "circular", json_true());
	json_object_set_new(fx, "mueller", json_true());
	json_t *sen = json_object_get(d, "sensor");
	if (!sen) {
		sen = json_object();
		json_object_set_new(d, "sensor", sen);
	}
	json_object_set_new(sen, "resolution", json_pack("[i, i]", (int)w, (int)h));
	json_object_set_new(sen, "pixel_pitch_um", json_real(pitch_um));
	json_object_set_new(sen, "exposure_us", json_real(exposure_us));
	json_object_set_new(sen, "psa",
	                    json_pack("[{s:{s:f, s:f}}, {s:{s:f, s:f}}]", "retarder", "angle_deg",
	                              0.0, "retardance_deg", 90.0, "retarder", "angle_deg", 45.0,
	                              "retardance_deg", 90.0));
	char *txt = json_dumps(d, JSON_COMPACT | JSON_REAL_PRECISION(17));
	json_decref(d);
	return txt;
}

/* The Mueller scene's simulator. */
static int mueller_sim(pc_demo *d, uint32_t mw, uint32_t mh, pc_scene **mscene, pc_sim **msim)
{
	pc_sensor_figures fig;
	pc_sim_get_sensor(d->sim, &fig);
	char *doc = pc_scene_to_json(d->scene);
	/* same sensor area: 4× the pitch; 1/16 of the exposure keeps the signal per pixel */
	double ratio = (double)d->in.sensor_width / mw;
	char *mtext = doc ? mueller_variant(doc, mw, mh, fig.pixel_pitch_um * ratio,
	                                    fig.exposure_us / (ratio * ratio))
	                  : NULL;
	free(doc);
	if (!mtext)
		return pc_error(PC_ENOMEM, "cannot build the Mueller scene");
	pc_sim_options so = pc_sim_options_default();
	so.seed = d->o.seed;
	so.threads = d->o.threads;
	int rc = pc_scene_parse(mtext, "demo Mueller scene", ".", mscene);
	if (!rc)
		rc = pc_sim_new(*mscene, &so, msim);
	free(mtext);
	return rc ? pc_error_prefix(rc, "Mueller scene: ") : 0;
}

/* Frames 0..n−1 of the Mueller sequence through the run; sat[i] marks pixels saturated in some
 * frame. */
static int mueller_frames(pc_demo *d, pc_sim *msim, const pc_sim_info *in, uint8_t *sat,
                          pc_mueller_result *res)
{
	pc_sim_states st;
	pc_sim_get_states(msim, &st);
	pc_mueller_system sys;
	int rc = pc_mueller_system_init(&sys, st.n_psg, st.psg, st.n_psa, st.psa, st.analyser);
	pc_mueller_run_opts ro = {PC_DM_BILINEAR, 0, d->o.threads, {PC_REBUILD_OFF, 0}, 0, 0};
	pc_mueller_run *run = NULL;
	if (!rc)
		rc = pc_mueller_run_new(&sys, &in->mosaic, &ro, &run);
	const uint16_t full = (uint16_t)((1u << in->bits) - 1);
	for (unsigned j = 0; !rc && j < in->n_states; j++) {
		pc_view v = {0};
		if (!(rc = pc_view_alloc(&v, in->format, in->width, in->height, 64)))
			rc = pc_sim_frame(msim, j, NULL, &v, NULL);
		if (!rc && in->bits > 8)
			for (uint32_t y = 0; y < v.height; y++) {
				const uint16_t *row = PC_ROW(&v, uint16_t, y);
				for (uint32_t x = 0; x < v.width; x++)
					if (row[x] >= full)
						sat[(size_t)y * v.width + x] = 1;
			}
		if (!rc)
			rc = pc_mueller_run_add(run, j, &v);
		pc_view_free(&v);
		pc_progress_report(&d->o.progress, "mueller frames", j + 1, in->n_states);
	}
	if (!rc)
		rc = pc_mueller_run_finish(run, res);
	pc_mueller_run_free(run);
	return rc;
}

/* Compared pixels: truth signal above 100 DN per frame (S0 of a generator state) and no frame
 * saturated (the bilinear demosaic spreads a saturated pixel to its neighbours: they are
 * excluded too). */
static float *mueller_weights(const float *tM, const uint8_t *sat, uint32_t mw, uint32_t mh,
                              double mscale, long *n_saturated)
{
	size_t mnp = (size_t)mw * mh;
	float *w = malloc(mnp * sizeof *w);
	if (!w)
		return NULL;
	for (size_t i = 0; i < mnp; i++) {
		uint32_t x = (uint32_t)(i % mw), y = (uint32_t)(i / mw);
		bool s = false;
		for (int dy = -1; dy <= 1; dy++)
			for (int dx = -1; dx <= 1; dx++) {
				int64_t xx = (int64_t)x + dx, yy = (int64_t)y + dy;
				if (xx >= 0 && yy >= 0 && xx < mw && yy < mh)
					s |= sat[(size_t)yy * mw + (size_t)xx] != 0;
			}
		w[i] = !s && tM[16 * i] * mscale > 100 ? 1.0f : 0.0f;
		*n_saturated += s;
	}
	return w;
}

/* The maps, their truth and the comparison. */
static int mueller_compare(const char *dir, const pc_mueller_result *res, const float *tM,
                           const float *tmaps, const float *w, demo_results *r)
{
	const uint32_t mw = r->mw, mh = r->mh;
	const size_t mnp = (size_t)mw * mh;
	const char *names[3] = {"D", "R", "Delta"}, *labels[3] = {"D", "R (rad)", "Delta"};
	const double his[3] = {1, M_PI, 1};
	int rc = 0;
	for (int k = 0; k < 3 && !rc; k++) {
		char nm[32], title[96];
		snprintf(title, sizeof title, "%s from 8 simulated frames (cond %.2f)", names[k],
		         res->sys.cond_W);
		/* R where the light is depolarized is undefined: hatched, by each map's own Δ */
		char htext[64];
		snprintf(htext, sizeof htext, "Delta > %.2g: R undefined", PC_MUELLER_R_MASK_DELTA);
		pc_map_marks me = {res->valid, k == 1 ? res->maps + 2 * mnp : NULL,
		                   PC_MUELLER_R_MASK_DELTA, htext};
		pc_map_marks mt = {NULL, k == 1 ? tmaps + 2 * mnp : NULL, PC_MUELLER_R_MASK_DELTA,
		                   htext};
		if ((rc = pc_map_write_marked(dir, names[k], res->maps + (size_t)k * mnp, mw, mh, 0,
		                              his[k], title, labels[k], &me)))
			break;
		snprintf(nm, sizeof nm, "truth_%s", names[k]);
		snprintf(title, sizeof title, "%s ground truth", names[k]);
		if ((rc = pc_map_write_marked(dir, nm, tmaps + (size_t)k * mnp, mw, mh, 0, his[k],
		                              title, labels[k], &mt)))
			break;
		/* retardance is defined where the light keeps its polarization: compare R only
		 * where the truth depolarization Δ < 0.5 */
		const float *wk = w;
		float *wr = NULL;
		if (k == 1) {
			wr = malloc(mnp * sizeof *wr);
			if (wr)
				for (size_t i = 0; i < mnp; i++)
					wr[i] = tmaps[2 * mnp + i] < (float)PC_MUELLER_R_MASK_DELTA
					            ? w[i]
					            : 0;
			wk = wr ? wr : w;
		}
		r->med[k] =
		    pc_eval_median_abs_err(res->maps + (size_t)k * mnp, tmaps + (size_t)k * mnp, wk,
		                           mnp, 0.5, k == 1, &r->used[k]);
		free(wr);
	}
	if (rc)
		return pc_error_prefix(rc, "%s: ", dir);
	char path[4096];
	size_t ms[4] = {mh, mw, 4, 4};
	if ((rc = join(path, sizeof path, dir, "truth_mueller.npy")) ||
	    (rc = pc_npy_write(path, tM, PC_DT_F32, 4, ms)) ||
	    (rc = join(path, sizeof path, dir, "mueller.npy")) ||
	    (rc = pc_npy_write(path, res->M, PC_DT_F32, 4, ms)))
		return rc;
	return 0;
}

/* Step 3: Mueller imaging of the same scene at a quarter of the resolution. */
static int step_mueller(pc_demo *d, const char *out, demo_results *r)
{
	const uint32_t mw = d->in.sensor_width / 4 / 2 * 2, mh = d->in.sensor_height / 4 / 2 * 2;
	const size_t mnp = (size_t)mw * mh;
	r->mw = mw;
	r->mh = mh;
	pc_scene *mscene = NULL;
	pc_sim *msim = NULL;
	pc_mueller_result res = {0};
	float *tM = malloc(mnp * 16 * sizeof *tM), *tmaps = malloc(mnp * 3 * sizeof *tmaps);
	float *w = NULL;
	uint8_t *sat = calloc(mnp, 1);
	int rc = !tM || !tmaps || !sat ? pc_error(PC_ENOMEM, "Mueller images of %ux%u", mw, mh) : 0;
	if (!rc)
		rc = mueller_sim(d, mw, mh, &mscene, &msim);
	pc_sim_info in;
	double t0 = now_s();
	if (!rc) {
		pc_sim_get_info(msim, &in);
		for (unsigned g = 0; g < in.n_psg && !rc; g++) {
			if ((rc = pc_sim_prepare(msim, g, NULL, g == 0 ? tM : NULL, NULL, NULL)))
				pc_error_prefix(rc, "Mueller render: ");
			pc_progress_report(&d->o.progress, "mueller render", g + 1, in.n_psg);
		}
	}
	if (!rc && (rc = mueller_frames(d, msim, &in, sat, &res)))
		pc_error_prefix(rc, "Mueller imaging: ");
	r->t_mueller = now_s() - t0;
	if (!rc) {
		r->sys = res.sys;
		r->nonphysical = res.nonphysical;
		/* truth maps from the truth Mueller image */
		pc_mueller_maps(tM, mw, mh, 0xFFFFu, d->o.threads, tmaps, tmaps + mnp,
		                tmaps + 2 * mnp, NULL);
		w = mueller_weights(tM, sat, mw, mh, pc_sim_dn_per_radiance(msim, NULL, 0),
		                    &r->m_saturated);
		if (!w)
			rc = pc_error(PC_ENOMEM, "Mueller weights");
	}
	char dir[4096];
	if (!rc && ((rc = join(dir, sizeof dir, out, "mueller")) || (rc = pc_mkdir_p(dir))))
		pc_error_prefix(rc, "%s: ", dir);
	if (!rc)
		rc = mueller_compare(dir, &res, tM, tmaps, w, r);
	free(w);
	free(sat);
	free(tM);
	free(tmaps);
	pc_mueller_result_free(&res);
	pc_sim_free(msim);
	pc_scene_free(mscene);
	return rc;
}

static json_t *report_json(const pc_demo *d, const demo_results *r, double t_total)
{
	json_t *report = json_object();
	json_t *sim = r->simulation ? json_loads(r->simulation, 0, NULL) : NULL;
	if (sim)
		json_object_set_new(report, "simulation", sim);
	json_t *jt = json_object();
	json_object_set_new(jt, "render_s", json_real(r->t_render));
	json_object_set_new(jt, "frame_s", json_real(r->t_frame));
	json_object_set_new(jt, "mueller_s", json_real(r->t_mueller));
	json_object_set_new(jt, "total_s", json_real(t_total));
	json_object_set_new(jt, "peak_rss_mib", pc_json_real(pc_peak_rss_mib()));
	json_object_set_new(report, "timings", jt);
	json_object_set_new(report, "saturated_pixels", json_integer(r->saturated));
	json_object_set_new(report, "dn_per_radiance", json_real(r->scale));
	json_t *jm = json_array();
	for (unsigned m = 0; m < d->o.n_methods; m++) {
		const pc_eval_stokes_metrics *a = &r->acc[m];
		json_t *e = json_object();
		json_object_set_new(e, "method", json_string(r->method[m]));
		json_object_set_new(e, "seconds", json_real(r->seconds[m]));
		json_object_set_new(e, "s0_rel_rms", pc_json_real(a->s0_rel_rms));
		json_object_set_new(e, "dolp_bias", pc_json_real(a->dolp_bias));
		json_object_set_new(e, "dolp_rms", pc_json_real(a->dolp_rms));
		json_object_set_new(e, "aolp_weighted_err_deg", pc_json_real(a->aolp_err_deg));
		json_object_set_new(e, "aolp_median_err_deg", pc_json_real(a->aolp_median_deg));
		json_object_set_new(e, "pixels", json_integer(a->pixels));
		json_array_append_new(jm, e);
	}
	json_object_set_new(report, "pipeline", jm);
	/* the pictures' shared scales */
	json_object_set_new(report, "pictures",
	                    json_pack("{s:f, s:f, s:b}", "s0_hi", r->s0_hi, "dolp_hi", r->dolp_hi,
	                              "truth_circular", r->truth_circular));
	/* how "seconds" was measured: the same for every method */
	json_object_set_new(report, "pipeline_timing",
	                    json_pack("{s:s, s:i, s:i, s:i}", "what",
	                              "raw -> S0, S1, S2, DoLP, AoLP "
	                              "(pc_stokes_from_raw)",
	                              "untimed_runs", 1, "timed_runs", 3, "threads",
	                              d->o.threads > 0 ? d->o.threads : pc_parallel_max_threads()));
	if (d->o.mueller) {
		json_t *mj = json_object();
		json_object_set_new(mj, "width", json_integer(r->mw));
		json_object_set_new(mj, "height", json_integer(r->mh));
		json_object_set_new(mj, "frames", json_integer(r->sys.n_psg * r->sys.n_psa));
		json_object_set_new(mj, "cond_A", pc_json_real(r->sys.cond_A));
		json_object_set_new(mj, "cond_G", pc_json_real(r->sys.cond_G));
		json_object_set_new(mj, "cond_W", pc_json_real(r->sys.cond_W));
		json_object_set_new(mj, "median_abs_err_D", pc_json_real(r->med[0]));
		json_object_set_new(mj, "median_abs_err_R_rad", pc_json_real(r->med[1]));
		json_object_set_new(mj, "median_abs_err_Delta", pc_json_real(r->med[2]));
		json_object_set_new(mj, "pixels_compared", json_integer(r->used[0]));
		json_object_set_new(mj, "pixels_compared_R", json_integer(r->used[1]));
		json_object_set_new(mj, "pixels_nonphysical_filtered",
		                    json_integer(r->nonphysical));
		json_object_set_new(report, "mueller", mj);
	}
	return report;
}

static void report_md(FILE *mf, const pc_demo *d, const demo_results *r, double t_total)
{
	fprintf(mf, "# polarcam demo\n\nScene `%s` (%ux%u), seed %llu. Effects:",
	        pc_scene_name(d->scene), d->in.width, d->in.height, (unsigned long long)d->o.seed);
	for (unsigned i = 0; i < PC_FX_COUNT_; i++)
		if (d->in.effects & (1u << i))
			fprintf(mf, " %s", pc_sim_effect_name(1u << i));
	fprintf(
	    mf,
	    ".\nRender %.2f s (ray casting + pBRDF, once), one noisy frame %.2f s, total %.1f s, "
	    "peak memory %.0f MiB.\n\n",
	    r->t_render, r->t_frame, t_total, pc_peak_rss_mib());
	fprintf(
	    mf,
	    "## Pipeline estimates against the ground truth\n\n"
	    "Raw frame 0 (`raw_000000.png`) demosaicked and turned into Stokes/DoLP/AoLP, compared "
	    "with `truth_stokes.npy` (converted to DN: %.4g DN per W m^-2 sr^-1) over %ld pixels "
	    "that "
	    "are neither dark (S0 < 2 %% of full scale) nor saturated; %ld raw pixels are "
	    "saturated. "
	    "AoLP errors over pixels with truth DoLP > 0.05, weighted by DoLP. Time: raw frame to "
	    "S0, DoLP and AoLP (the same call and outputs for every method), the fastest of 3 "
	    "runs after an untimed one, %d threads; each method takes its own path (bilinear is "
	    "fused into one pass, docs/demosaicking.md).\n\n"
	    "| method | time (ms) | S0 rel. RMS | DoLP bias | DoLP RMS | AoLP err (deg, weighted) "
	    "| AoLP median (deg) |\n"
	    "|---|---|---|---|---|---|---|\n",
	    r->scale, r->acc[0].pixels, r->saturated,
	    d->o.threads > 0 ? d->o.threads : pc_parallel_max_threads());
	for (unsigned m = 0; m < d->o.n_methods; m++) {
		const pc_eval_stokes_metrics *a = &r->acc[m];
		fprintf(mf, "| %s%s | %.2f | %.4f | %+.4f | %.4f | %.2f | %.2f |\n", r->method[m],
		        m == r->best ? " (best DoLP)" : "", 1e3 * r->seconds[m], a->s0_rel_rms,
		        a->dolp_bias, a->dolp_rms, a->aolp_err_deg, a->aolp_median_deg);
	}
	fprintf(
	    mf,
	    "\nThe DoLP bias is positive where the signal is low: the estimator's noise "
	    "floor (physics.md §6). Pictures: `truth/` and `pipeline_<method>/` of every method "
	    "(s0, dolp, aolp, aolp_sat), all on one scale: S0 0..%.4g DN (the truth's 99.9th "
	    "percentile, at most the S0 of a saturated super-pixel), DoLP 0..%.2f (automatic: "
	    "the truth's 99th percentile); `stokes.npy` is the bilinear estimate (H, W, 3) in "
	    "DN. How to read them: docs/pictures.md.\n\n",
	    r->s0_hi, r->dolp_hi);
	if (d->o.mueller)
		fprintf(
		    mf,
		    "## Mueller imaging\n\nThe same scene at %ux%u (same field of view), "
		    "tetrahedral generator (polarizer + 132° retarder at ±15.1°, ±51.7°) × quarter-"
		    "wave analyser at 0°/45° in front of the DoFP: %u frames, cond(A) = %.3f, "
		    "cond(G) = %.3f, cond(W) = %.3f. Per-pixel least squares (bilinear demosaic), "
		    "then "
		    "Lu–Chipman; compared with the decomposition of the Mueller ground truth over "
		    "the lit pixels (signal above 100 DN) that no frame saturates (%ld pixels are "
		    "excluded as saturated or next to a saturated one):\n\n"
		    "| map | median abs. error | pixels |\n|---|---|---|\n| D | %.4f | %ld |\n"
		    "| R (rad, where truth Delta < 0.5) | %.4f | %ld |\n| Delta | %.4f | %ld |\n\n"
		    "%ld pixels had non-physical noisy matrices (Cloude-filtered "
		    "before decomposing). Files: `mueller/` (D, R, Delta and truth_* as .npy and "
		    ".png, mueller.npy, truth_mueller.npy).\n",
		    r->mw, r->mh, r->sys.n_psg * r->sys.n_psa, r->sys.cond_A, r->sys.cond_G,
		    r->sys.cond_W, r->m_saturated, r->med[0], r->used[0], r->med[1], r->used[1],
		    r->med[2], r->used[2], r->nonphysical);
}

/* Step 4: report.json and report.md. */
static int step_report(const pc_demo *d, const char *out, const demo_results *r, double t_all,
                       char **md_out)
{
	double t_total = now_s() - t_all;
	json_t *report = report_json(d, r, t_total);
	char *rj = json_dumps(report, JSON_INDENT(1) | JSON_REAL_PRECISION(10));
	json_decref(report);
	char path[4096];
	int rc =
	    !rj ? pc_error(PC_ENOMEM, "report.json") : join(path, sizeof path, out, "report.json");
	if (!rc)
		rc = pc_write_file_atomic(path, rj, strlen(rj));
	free(rj);
	if (rc)
		return pc_error_prefix(rc, "report.json: ");
	char *md = NULL;
	size_t mdlen = 0;
	FILE *mf = open_memstream(&md, &mdlen);
	if (!mf)
		return pc_error(PC_ENOMEM, "report.md");
	report_md(mf, d, r, t_total);
	fclose(mf);
	rc = join(path, sizeof path, out, "report.md");
	if (!rc)
		rc = pc_write_file_atomic(path, md, mdlen);
	if (md_out)
		*md_out = md;
	else
		free(md);
	return rc ? pc_error_prefix(rc, "report.md: ") : 0;
}

int pc_demo_run(pc_demo *d, const char *dir, char **report)
{
	if (report)
		*report = NULL;
	double t_all = now_s();
	const size_t np = (size_t)d->in.width * d->in.height;
	demo_results *r = calloc(1, sizeof *r);
	float *tp = malloc(np * 3 * sizeof *tp);
	pc_view raw = {0};
	pc_outdir od = {0};
	int rc = !r || !tp ? pc_error(PC_ENOMEM, "demo") : 0;
	if (!rc)
		rc = pc_outdir_begin(&od, dir, d->o.overwrite ? PC_OUT_OVERWRITE : 0);
	const char *out = od.tmp; /* the folder is made beside dir and put in place at the end */
	if (!rc)
		rc = step_truth(d, out, &raw, tp, r);
	if (!rc)
		rc = step_pipeline(d, out, &raw, tp, r);
	pc_view_free(&raw);
	free(tp);
	for (unsigned k = 0; k < 3 && r; k++)
		r->med[k] = NAN;
	if (!rc && d->o.mueller)
		rc = step_mueller(d, out, r);
	if (!rc)
		rc = step_report(d, out, r, t_all, report);
	if (!rc)
		rc = pc_outdir_commit(&od);
	pc_outdir_abort(&od);
	if (r)
		free(r->simulation);
	free(r);
	return rc;
}
