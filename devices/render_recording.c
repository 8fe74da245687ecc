/* A scene rendered into a recording with its ground truth (polarcam/render_recording.h). */
#define _POSIX_C_SOURCE 200809L
#include "polarcam/render_recording.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "json.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/states.h"

typedef struct job {
	const pc_render_opts *o;
	const char *name; /* the output folder as the caller named it (messages) */
	pc_outdir od;
	const char *dir; /* od.tmp: where the files go until the folder is put in place */
	const pc_scene *scene;
	pc_sim *sim;
	pc_sim_info in;
	uint64_t frames;
	pc_recording *rec;
	uint64_t written; /* frames in the recording */
	bool stop;        /* the progress callback asked to stop */
	char err[512];    /* why the recording ended early, for meta.json */
	double t_prep, t_frames, t_write;
} job;

/* pc_sim_progress_fn → the "render" phase over every state rendered */
typedef struct prep_progress {
	const pc_progress *p;
	uint64_t base, total;
	bool *stop; /* a stop asked for during a state is acted on when the state is done */
} prep_progress;

static void prep_cb(void *user, uint64_t done, uint64_t total)
{
	const prep_progress *a = user;
	(void)total;
	if (pc_progress_report(a->p, "render", a->base + done, a->total))
		*a->stop = true;
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int pc_truth_write(const char *path, const pc_sim_info *in, const float *values, bool mueller,
                   pc_dtype dtype)
{
	if (!path || !in || !values || (dtype != PC_DT_F32 && dtype != PC_DT_F16))
		return pc_error(PC_EINVAL,
		                "truth: path, info, values and a float32/float16 dtype are "
		                "required");
	const bool colour = in->colour_channels == 3;
	/* (H, W[, 3], 4[, 4]) */
	size_t shape[5] = {in->height, in->width, 3, 4, 4}, nd = 2,
	       n = (size_t)in->height * in->width;
	if (colour)
		nd++;
	shape[nd++] = 4;
	if (mueller)
		shape[nd++] = 4;
	for (size_t k = 2; k < nd; k++)
		n *= shape[k];
	int rc;
	if (dtype == PC_DT_F16) {
		uint16_t *h = malloc(n * sizeof *h);
		if (!h)
			return pc_error(PC_ENOMEM, "%s: float16 truth of %ux%u", path, in->width,
			                in->height);
		pc_f32_to_f16(values, h, n);
		rc = pc_npy_write(path, h, PC_DT_F16, (unsigned)nd, shape);
		free(h);
	} else {
		rc = pc_npy_write(path, values, PC_DT_F32, (unsigned)nd, shape);
	}
	return rc; /* pc_npy_write's errors name the path */
}

/* The truth of generator state g (and the Mueller truth with the first one). */
static int write_truth(job *j, unsigned g, bool first, const float *ts, const float *tm)
{
	char path[4096];
	if (j->in.n_psg > 1)
		snprintf(path, sizeof path, "%s/truth_stokes_psg%02u.npy", j->dir, g);
	else
		snprintf(path, sizeof path, "%s/truth_stokes.npy", j->dir);
	int rc = pc_truth_write(path, &j->in, ts, false, PC_DT_F32);
	if (!rc && first && tm) {
		snprintf(path, sizeof path, "%s/truth_mueller.npy", j->dir);
		rc = pc_truth_write(path, &j->in, tm, true, PC_DT_F32);
	}
	return rc;
}

/* Each generator state the frames use, rendered once (with its truth). */
static int prepare(job *j)
{
	const pc_sim_info *in = &j->in;
	const size_t npix = (size_t)in->width * in->height, C = in->colour_channels;
	const bool mueller = j->o->truth && (in->effects & PC_FX_MUELLER);
	float *ts = NULL, *tm = NULL;
	if (j->o->truth) {
		ts = malloc(npix * C * 4 * sizeof *ts);
		tm = mueller ? malloc(npix * C * 16 * sizeof *tm) : NULL;
		if (!ts || (mueller && !tm)) {
			free(ts);
			free(tm);
			return pc_error(PC_ENOMEM, "out of memory for the ground truth of %ux%u",
			                in->width, in->height);
		}
	}
	double t0 = now_s();
	unsigned n_psg_used = j->frames < in->n_psg ? (unsigned)j->frames : in->n_psg;
	/* rows per prepared state: H, or H + 2 (halo) + H (mixing) with crosstalk */
	const uint64_t rows =
	    (in->effects & PC_FX_CROSSTALK) ? 2 * (uint64_t)in->height + 2 : in->height;
	prep_progress pp = {&j->o->progress, 0, (uint64_t)n_psg_used * rows, &j->stop};
	int rc = 0;
	for (unsigned k = 0; k < n_psg_used && !rc; k++) {
		if (j->stop) {
			snprintf(j->err, sizeof j->err,
			         "interrupted while rendering the scene (state %u of %u), before "
			         "the first frame",
			         k, n_psg_used);
			rc = pc_error(PC_ECANCELED, "%s", j->err);
			break;
		}
		unsigned g = (unsigned)((j->o->first + k) % in->n_psg);
		pp.base = (uint64_t)k * rows;
		if ((rc = pc_sim_prepare(j->sim, g, ts, k == 0 ? tm : NULL, prep_cb, &pp)))
			pc_error_prefix(rc, "render: ");
		else if (j->o->truth)
			rc = write_truth(j, g, k == 0, ts, tm);
	}
	j->t_prep = now_s() - t0;
	free(ts);
	free(tm);
	return rc;
}

/* The frames into the recording. */
static int frames(job *j)
{
	pc_view view = {0};
	int rc = pc_view_alloc(&view, j->in.format, j->in.width, j->in.height, 64);
	if (rc)
		return pc_error_prefix(rc, "frame buffer: ");
	for (uint64_t i = 0; i < j->frames && !rc; i++) {
		if (j->stop) {
			snprintf(j->err, sizeof j->err, "interrupted after %llu of %llu frames",
			         (unsigned long long)i, (unsigned long long)j->frames);
			rc = pc_error(PC_ECANCELED, "%s", j->err);
			break;
		}
		pc_frame fr;
		uint64_t n = j->o->first + i;
		double ta = now_s();
		rc = pc_sim_frame(j->sim, n, NULL, &view, &fr.meta);
		double tb = now_s();
		j->t_frames += tb - ta;
		if (rc) {
			snprintf(j->err, sizeof j->err, "frame %llu: %s", (unsigned long long)n,
			         pc_error_detail());
			pc_error_prefix(rc, "frame: ");
			break;
		}
		fr.view = view;
		fr.mosaic = j->in.mosaic;
		if ((rc = pc_recording_add(j->rec, &fr))) {
			snprintf(j->err, sizeof j->err, "%s", pc_error_detail());
			pc_error_prefix(rc, "%s: ", j->name);
			break;
		}
		j->t_write += now_s() - tb;
		j->written = i + 1;
		if (pc_progress_report(&j->o->progress, "frames", i + 1, j->frames))
			j->stop = true;
	}
	pc_view_free(&view);
	return rc;
}

/* meta.json's extra: the simulator's description and the timings (also of a recording that
 * ended early: per_frame_s over the frames made). */
static int set_extra(job *j, double t0, pc_render_report *rep)
{
	int rc = 0;
	char *desc = pc_sim_describe_json(j->sim, j->scene);
	json_t *extra = desc ? json_loads(desc, 0, NULL) : NULL;
	free(desc);
	if (!extra)
		return pc_error(PC_ENOMEM, "meta.json");
	json_t *tj = json_object();
	json_object_set_new(tj, "render_s", json_real(j->t_prep));
	json_object_set_new(tj, "frames_s", json_real(j->t_frames));
	json_object_set_new(tj, "per_frame_s",
	                    j->written ? json_real(j->t_frames / (double)j->written) : json_null());
	json_object_set_new(tj, "write_s", json_real(j->t_write));
	json_object_set_new(tj, "total_s", json_real(now_s() - t0));
	json_object_set_new(tj, "peak_rss_mib", pc_json_real(pc_peak_rss_mib()));
	json_object_set_new(extra, "timings", tj);
	json_object_set_new(extra, "first_frame", json_integer((json_int_t)j->o->first));
	char *et = pc_json_text(extra);
	rc = et ? pc_recording_set_json(j->rec, "extra", et) : PC_ENOMEM;
	free(et);
	if (!rc && rep && !(rep->timings = pc_json_text(tj)))
		rc = PC_ENOMEM;
	json_decref(extra);
	return rc ? pc_error_prefix(rc, "meta.json: ") : 0;
}

/* states.json, meta.json's extra and the end of the recording. */
static int finish(job *j, double t0, pc_render_report *rep)
{
	int rc = 0;
	char path[4096];
	if (j->in.n_states > 1) {
		pc_sim_states st;
		pc_sim_get_states(j->sim, &st);
		snprintf(path, sizeof path, "%s/states.json", j->dir);
		if ((rc = pc_states_write(path, &st, &j->in.mosaic)))
			return pc_error_prefix(rc, "%s: ", path);
	}
	if ((rc = set_extra(j, t0, rep)))
		return rc;
	if ((rc = pc_recording_finish(j->rec, NULL)))
		return pc_error_prefix(rc, "%s: ", j->name);
	return 0;
}

/* The output folder first: an occupied one is refused before any work. */
static int start(job *j)
{
	const pc_render_opts *o = j->o;
	int rc = pc_outdir_begin(&j->od, j->name, o->overwrite ? PC_OUT_OVERWRITE : 0);
	if (rc)
		return rc;
	j->dir = j->od.tmp;
	char source[1024];
	snprintf(source, sizeof source, "sim:%s?seed=%llu",
	         o->scene_path ? o->scene_path : "default", (unsigned long long)o->sim.seed);
	const pc_sim_info *in = &j->in;
	pc_recording_desc desc = {source,       in->format,       NULL,
	                          in->width,    in->height,       in->offset_x,
	                          in->offset_y, in->sensor_width, in->sensor_height,
	                          true,         in->mosaic,       o->store};
	if ((rc = pc_recording_create(&j->rec, j->dir, &desc, false)))
		return pc_error_prefix(rc, "%s: ", j->name);
	return 0;
}

int pc_render_recording(const char *dir, const pc_render_opts *o, pc_render_report *rep)
{
	if (rep)
		memset(rep, 0, sizeof *rep);
	if (!dir || !o)
		return pc_error(PC_EINVAL, "render: missing argument");
	double t0 = now_s();
	job j;
	memset(&j, 0, sizeof j);
	j.o = o;
	j.name = dir;
	pc_scene *loaded = NULL;
	int rc = 0;
	if (!(j.scene = o->scene))
		rc = o->scene_path ? pc_scene_load(o->scene_path, &loaded)
		                   : pc_scene_load_default(&loaded);
	if (!j.scene)
		j.scene = loaded;
	if (!rc && (rc = pc_sim_new(j.scene, &o->sim, &j.sim)))
		pc_error_prefix(rc, "%s: ", o->scene_path ? o->scene_path : "default scene");
	if (!rc) {
		pc_sim_get_info(j.sim, &j.in);
		j.frames = o->frames ? o->frames : j.in.n_states;
		/* refused before anything is written: frame numbers and timestamps that meta.json
		 * cannot hold, and a render that cannot fit in memory */
		if ((rc = pc_sim_check_frames(j.sim, o->first, j.frames)))
			pc_error_prefix(rc, "--first/--frames: ");
		else if ((rc = pc_sim_check_memory(j.sim, o->truth)))
			pc_error_prefix(rc,
			                "%s: ", o->scene_path ? o->scene_path : "default scene");
	}
	if (!rc)
		rc = start(&j);
	if (!rc)
		rc = prepare(&j);
	if (!rc)
		rc = frames(&j);
	if (!rc)
		rc = finish(&j, t0, rep);
	if (j.rec) {
		if (rc) { /* the recording says why it ended; the caller hears the first error */
			char detail[512];
			snprintf(detail, sizeof detail, "%s", pc_error_detail());
			if (set_extra(&j, t0, NULL)) /* the timings so far, when they can be had */
				pc_error_clear();
			pc_recording_finish(j.rec, *j.err ? j.err : "render failed");
			pc_error(rc, "%s", detail);
		}
		pc_recording_free(j.rec);
	}
	/* The folder is put in place whole, or not at all (the old one, if any, stays); a
	 * recording stopped by the caller is put in place with the frames written (meta.json says
	 * complete = false). */
	if (!rc || (rc == PC_ECANCELED && j.written)) {
		char detail[512];
		snprintf(detail, sizeof detail, "%s", rc ? pc_error_detail() : "");
		int crc = pc_outdir_commit(&j.od);
		if (crc)
			rc = crc;
		else if (rc)
			pc_error(rc, "%s", detail);
	} else {
		pc_outdir_abort(&j.od);
	}
	if (rep)
		rep->frames = rc && rc != PC_ECANCELED ? 0 : j.written;
	if (!rc && rep) {
		rep->width = j.in.width;
		rep->height = j.in.height;
	}
	if (rc && rep) {
		free(rep->timings);
		rep->timings = NULL;
	}
	pc_sim_free(j.sim);
	pc_scene_free(loaded);
	return rc;
}
