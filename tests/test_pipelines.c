/* The library's pipelines (what the CLI commands call), held against each other and against
 * values worked out by hand:
 * - states.json written and read back exactly; bad files named by file and field;
 * - a Mueller sequence rendered into a recording (pc_render_recording) and reconstructed from the
 *   recording, from its frame files and from the sim: source streaming the same scene and seed:
 *   the three Mueller images are identical bit for bit, and equal the scalar reference
 *   pc_mueller_solve on the demosaicked intensities;
 * - capture stopped by its progress callback: PC_ECANCELED, the frames written so far intact and
 *   meta.json saying complete = false;
 * - the Stokes folder's stokes.npy the same from interleaved and from separate planes;
 * - the demo's Stokes scoring (pc_eval_stokes, pc_eval_truth_planes) on numbers worked out by
 *   hand. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/capture.h"
#include "polarcam/error.h"
#include "polarcam/eval.h"
#include "polarcam/folders.h"
#include "polarcam/io.h"
#include "polarcam/mueller_frames.h"
#include "polarcam/recording.h"
#include "polarcam/render_recording.h"
#include "polarcam/states.h"

static char tmp[64];

static const char *tpath(const char *name)
{
	static char buf[8][600];
	static int k;
	k = (k + 1) % 8;
	snprintf(buf[k], sizeof buf[k], "%s/%s", tmp, name);
	return buf[k];
}

static void write_text(const char *path, const char *text)
{
	FILE *fp = fopen(path, "w");
	if (fp) {
		fputs(text, fp);
		fclose(fp);
	}
}

/* a plane under a tetrahedral PSG, a quarter-wave PSA, 32×24, noise on, 12 bits, black level
 * 64 DN */
static const char *seq_scene =
    "{\"camera\": {\"position\": [0, -3, 6], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]},"
    " \"materials\": {\"m\": {\"n\": 1.5, \"k\": 0.3, \"sigma\": 0.15}},"
    " \"lights\": [{\"type\": \"directional\", \"direction\": [0.3, -0.5, 0.8],"
    "   \"irradiance_w_m2\": 100, \"states\": ["
    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": 15.1, \"retardance_deg\": 132}},"
    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": 51.7, \"retardance_deg\": 132}},"
    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": -51.7, \"retardance_deg\": 132}},"
    "     {\"polarizer_deg\": 0, \"retarder\": {\"angle_deg\": -15.1, \"retardance_deg\": 132}}]}],"
    " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], \"material\": "
    "\"m\"}],"
    " \"effects\": {\"circular\": true, \"mueller\": true, \"noise\": true},"
    " \"sensor\": {\"preset\": \"imx250mzr\", \"resolution\": [32, 24], \"exposure_us\": 400,"
    "   \"offset_dn\": 64,"
    "   \"psa\": [{\"retarder\": {\"angle_deg\": 0, \"retardance_deg\": 90}},"
    "            {\"retarder\": {\"angle_deg\": 45, \"retardance_deg\": 90}}]}}";

static void test_states(void)
{
	pc_sim_states st, back;
	memset(&st, 0, sizeof st);
	st.n_psg = 3;
	st.n_psa = 2;
	for (unsigned i = 0; i < 3; i++)
		for (int k = 0; k < 4; k++)
			st.psg[i][k] =
			    k == 0 ? 1 : sin(1.0 + i + 0.37 * k) / 3; /* not short decimals */
	for (unsigned a = 0; a < 2; a++)
		for (int r = 0; r < 4; r++)
			for (int c = 0; c < 4; c++)
				st.psa[a][r][c] = cos(0.1 * (a + 1) * (4 * r + c + 1));
	for (int c = 0; c < 4; c++)
		for (int k = 0; k < 4; k++)
			st.analyser[c][k] = 0.5 * cos(0.3 * c + k);
	pc_mosaic m = pc_mosaic_imx250mzr();
	CHECK_EQ_INT(pc_states_write(tpath("states.json"), &st, &m), 0);
	char layout[64];
	CHECK_EQ_INT(pc_states_read(tpath("states.json"), &back, layout, sizeof layout), 0);
	CHECK(!strcmp(layout, "90,45,135,0"));
	CHECK(back.n_psg == 3 && back.n_psa == 2);
	CHECK(!memcmp(back.psg, st.psg, sizeof st.psg) && !memcmp(back.psa, st.psa, sizeof st.psa));
	CHECK(!memcmp(back.analyser, st.analyser, sizeof st.analyser));
	/* a file without analyser rows gets the ideal ones; a bad matrix is named */
	write_text(tpath("s2.json"),
	           "{\"polarcam_states\": 1, \"frame_order\": \"psg_fastest\","
	           " \"psg\": [[1, 0, 0, 0]], \"psa\": [[[1,0,0,0],[0,1,0,0],[0,0,1,0],"
	           "[0,0,0,1]]]}");
	CHECK_EQ_INT(pc_states_read(tpath("s2.json"), &back, NULL, 0), 0);
	CHECK_NEAR(back.analyser[1][2], 0.5, 1e-15); /* 45°: ½(1, cos 90°, sin 90°, 0) */
	CHECK_NEAR(back.analyser[2][1], -0.5, 1e-15);
	write_text(tpath("s3.json"),
	           "{\"polarcam_states\": 1, \"frame_order\": \"psg_fastest\","
	           " \"psg\": [[1, 0, 0, 0]], \"psa\": [[[1,0,0,0],[0,1,0],[0,0,1,0],"
	           "[0,0,0,1]]]}");
	CHECK_EQ_INT(pc_states_read(tpath("s3.json"), &back, NULL, 0), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "s3.json: psa[0]") != NULL);
	CHECK_EQ_INT(pc_states_read(tpath("none.json"), &back, NULL, 0), PC_ENOENT);
}

static int cmp_results(const pc_mueller_result *a, const pc_mueller_result *b)
{
	size_t n = (size_t)a->width * a->height;
	if (a->width != b->width || a->height != b->height)
		return 0;
	return !memcmp(a->M, b->M, n * 16 * sizeof(float)) &&
	       !memcmp(a->maps, b->maps, n * 3 * sizeof(float));
}

static void test_mueller(void)
{
	write_text(tpath("seq.json"), seq_scene);
	pc_render_opts ro = {
	    tpath("seq.json"), NULL,        pc_sim_options_default(), 0, 0, true, false,
	    {NULL, NULL},      PC_STORE_PNG};
	ro.sim.seed = 5;
	pc_render_report rep;
	CHECK_EQ_INT(pc_render_recording(tpath("rec"), &ro, &rep), 0);
	CHECK(rep.frames == 8 && rep.width == 32 && rep.height == 24);
	free(rep.timings);
	/* the same directory again is refused, and nothing is touched */
	CHECK_EQ_INT(pc_render_recording(tpath("rec"), &ro, NULL), PC_EEXIST);

	pc_mueller_request rq = {
	    NULL, NULL, {PC_DM_BILINEAR, NAN, 1, {PC_REBUILD_OFF, 0}, 0, 0}, {NULL, NULL}};
	pc_mueller_result a, b, c;
	pc_mueller_used ua, ub, uc;
	CHECK_EQ_INT(pc_mueller_from_recording(tpath("rec"), &rq, &a, &ua), 0);
	CHECK(ua.frames_used == 8 && ua.frames_given == 8);
	CHECK_NEAR(ua.black_level, 64, 0); /* the sensor's offset, from meta.json */

	const char *files[8];
	char names[8][600];
	for (int j = 0; j < 8; j++) {
		snprintf(names[j], sizeof names[j], "%s/rec/raw_%06d.png", tmp, j);
		files[j] = names[j];
	}
	pc_mueller_request rf = rq;
	rf.states_path = tpath("rec/states.json");
	rf.run.black_level = ua.black_level;
	CHECK_EQ_INT(pc_mueller_from_files(files, 8, &rf, &b, &ub), 0);
	CHECK_EQ_INT(pc_mueller_from_files(files, 7, &rf, &c, &uc), PC_EINVAL); /* one too few */

	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0", tpath("seq.json"));
	pc_source *src = NULL;
	pc_sim_states st;
	CHECK_EQ_INT(pc_states_read(tpath("rec/states.json"), &st, NULL, 0), 0);
	CHECK_EQ_INT(pc_source_open(&src, uri), 0);
	if (src) {
		CHECK_EQ_INT(pc_source_buffers_alloc(src, 4), 0);
		CHECK_EQ_INT(pc_source_start(src), 0);
		pc_mueller_request rs = rf;
		rs.states_path = NULL;
		CHECK_EQ_INT(pc_mueller_from_source(src, &st, 60000, &rs, &c, &uc), 0);
		pc_source_close(src);
		CHECK(cmp_results(&a, &c));
		pc_mueller_result_free(&c);
	}
	CHECK(cmp_results(&a, &b));

	/* pixel (10, 7) against the scalar reference on the demosaicked intensities */
	const uint32_t x = 10, y = 7;
	double I[8 * 4];
	for (unsigned j = 0; j < 8; j++) {
		pc_view raw;
		CHECK_EQ_INT(pc_image_read_mosaic(files[j], NULL, 0, &raw, NULL), 0);
		float buf[32 * 24 * 4];
		pc_fplane ch[4];
		pc_fplanes_separate(buf, 32, 24, 4, ch);
		pc_mosaic m = pc_mosaic_imx250mzr();
		CHECK_EQ_INT(pc_demosaic(&raw, &m, PC_DM_BILINEAR, NULL, ch), 0);
		for (int k = 0; k < 4; k++)
			I[4 * j + (unsigned)k] = ch[k].data[y * 32 + x] - ua.black_level;
		pc_view_free(&raw);
	}
	double M[4][4];
	pc_mueller_solve(&a.sys, I, M);
	double worst = 0;
	for (int k = 0; k < 16; k++)
		worst = fmax(worst, fabs(a.M[16 * (y * 32 + x) + (unsigned)k] - M[k / 4][k % 4]) /
		                        M[0][0]);
	printf("Mueller pixel (10, 7) vs pc_mueller_solve: max |dM|/M00 = %.2e\n", worst);
	CHECK(worst < 1e-5); /* float accumulation (mueller_imaging.h: ~1e-6) */
	pc_mueller_result_free(&a);
	pc_mueller_result_free(&b);
}

static int stop_after_two(void *user, const char *phase, uint64_t done, uint64_t total)
{
	(void)user, (void)phase, (void)total;
	return done >= 2;
}

static void test_capture_stop(void)
{
	pc_capture_opts o;
	memset(&o, 0, sizeof o);
	pc_stream_request_init(&o.stream);
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=1&fps=0", tpath("seq.json"));
	o.stream.uri = uri;
	o.frames = 6;
	o.dir = tpath("cap");
	o.process = true;
	o.timeout_ms = 60000;
	o.progress = (pc_progress){stop_after_two, NULL};
	pc_capture_report rep;
	CHECK_EQ_INT(pc_capture(&o, &rep), 0);
	CHECK_EQ_INT(rep.error, PC_ECANCELED);
	CHECK(rep.frames == 2);
	CHECK(rep.json && strstr(rep.json, "\"frames\":2") && strstr(rep.json, "interrupted"));
	pc_capture_report_free(&rep);
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, tpath("cap")), 0);
	if (r) {
		CHECK(pc_recording_count(r) == 2 && !pc_recording_is_complete(r));
		pc_recording_free(r);
	}
	/* the last frame's Stokes images were written all the same (keep_every 0: the last only) */
	pc_array d;
	CHECK_EQ_INT(pc_npy_read(tpath("cap/processed/dolp_000001.npy"), &d), 0);
	CHECK(d.ndim == 2 && d.shape[0] == 24 && d.shape[1] == 32);
	pc_array_free(&d);
	CHECK(access(tpath("cap/processed/dolp_000000.npy"), F_OK) != 0);
	CHECK(access(tpath("cap/processed/s0_000001.png"), F_OK) == 0);
	/* a method for the other kind of mosaic: nothing is recorded */
	o.method = "bayer-first";
	o.dir = tpath("cap2");
	o.progress = (pc_progress){NULL, NULL};
	CHECK_EQ_INT(pc_capture(&o, &rep), PC_EINVAL);
	pc_capture_report_free(&rep);
	CHECK(access(tpath("cap2"), F_OK) != 0);
}

static void test_stokes_folder(void)
{
	enum { W = 5, H = 3, N = W * H };
	float inter[N * 3], sep[N * 3], dolp[N], aolp[N];
	for (int i = 0; i < N; i++) {
		for (int k = 0; k < 3; k++)
			inter[3 * i + k] = sep[k * N + i] = (float)(i * 10 + k) + 0.25f;
		dolp[i] = 0.01f * (float)i;
		aolp[i] = 0.1f * (float)i;
	}
	pc_stokes_out a = {{inter, W * 3, 3},
	                   {inter + 1, W * 3, 3},
	                   {inter + 2, W * 3, 3},
	                   {dolp, W, 1},
	                   {aolp, W, 1}};
	pc_stokes_out b = {
	    {sep, W, 1}, {sep + N, W, 1}, {sep + 2 * N, W, 1}, {dolp, W, 1}, {aolp, W, 1}};
	pc_stokes_folder_opts o = {.files = PC_SF_STOKES | PC_SF_S0 | PC_SF_AOLP};
	CHECK_EQ_INT(pc_stokes_folder_write(tpath("sfa"), &a, W, H, &o), 0);
	CHECK_EQ_INT(pc_stokes_folder_write(tpath("sfb"), &b, W, H, &o), 0);
	pc_array x, y, s0;
	CHECK_EQ_INT(pc_npy_read(tpath("sfa/stokes.npy"), &x), 0);
	CHECK_EQ_INT(pc_npy_read(tpath("sfb/stokes.npy"), &y), 0);
	CHECK_EQ_INT(pc_npy_read(tpath("sfa/s0.npy"), &s0), 0);
	CHECK(x.ndim == 3 && x.shape[0] == H && x.shape[1] == W && x.shape[2] == 3);
	CHECK(y.ndim == 3 && !memcmp(x.data, inter, sizeof inter) &&
	      !memcmp(y.data, inter, sizeof inter));
	CHECK(s0.ndim == 2 && ((float *)s0.data)[7] == inter[21]);
	CHECK(access(tpath("sfa/dolp.npy"), F_OK) != 0); /* not asked for */
	pc_array_free(&x);
	pc_array_free(&y);
	pc_array_free(&s0);
}

static void test_eval_stokes(void)
{
	/* truth Stokes (S0, S1, S2, S3): DoLP 1/2 at AoLP 0; DoLP 1/2 at AoLP 3π/4 (S2 < 0);
	 * S0 = 0 (dark) */
	const float ts[3 * 4] = {2, 1, 0, NAN, 2, 0, -1, NAN, 0, 0, 0, NAN};
	float s0[3], dl[3], ao[3];
	pc_eval_truth_planes(ts, 3, 10, s0, dl, ao);
	CHECK_NEAR(s0[0], 20, 0);
	CHECK_NEAR(dl[0], 0.5, 1e-7);
	CHECK_NEAR(ao[0], 0, 0);
	CHECK_NEAR(dl[1], 0.5, 1e-7);
	CHECK_NEAR(ao[1], 3 * M_PI / 4, 1e-6);
	CHECK_NEAR(dl[2], 0, 0);
	/* estimates: S0 10 % high on pixel 0, exact on pixel 1; DoLP +0.1 and −0.1; AoLP 0.1 rad
	 * off across the 0/π seam (π − 0.05 vs 0.05) and 0.2 rad off; full scale 100 leaves the
	 * dark pixel out (S0 below 2 % of it) */
	const float e_s0[3] = {22, 20, 0}, e_dl[3] = {0.6f, 0.4f, 0};
	const float t_ao[3] = {0.05f, 1.0f, 0}, e_ao[3] = {(float)(M_PI - 0.05), 1.2f, 0};
	pc_eval_stokes_metrics m;
	CHECK_EQ_INT(pc_eval_stokes(e_s0, e_dl, e_ao, s0, dl, t_ao, 3, 1, 100, &m), 0);
	CHECK(m.pixels == 2 && m.aolp_pixels == 2);
	CHECK_NEAR(m.s0_rel_rms, sqrt(0.01 / 2), 1e-6);
	CHECK_NEAR(m.dolp_bias, 0, 1e-7);
	CHECK_NEAR(m.dolp_rms, 0.1, 1e-6);
	/* weights 0.5 and 0.5: mean of 0.1 and 0.2 rad */
	CHECK_NEAR(m.aolp_err_deg, 0.15 * 180 / M_PI, 1e-4);
	CHECK_NEAR(m.aolp_median_deg, 0.15 * 180 / M_PI, 1e-4);
	const float est[4] = {1, 2, NAN, 3}, tru[4] = {1.5f, 2, 2, 0}, w[4] = {1, 1, 1, 0};
	long used;
	CHECK_NEAR(pc_eval_median_abs_err(est, tru, w, 4, 0.5, false, &used), 0.25, 1e-7);
	CHECK(used == 2);
}

int main(void)
{
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_pipelines"))
		SKIP("cannot create a temporary directory");
	test_states();
	test_mueller();
	test_capture_stop();
	test_stokes_folder();
	test_eval_stokes();
	char cmd[600];
	snprintf(cmd, sizeof cmd, "rm -rf %s", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_pipelines");
}
