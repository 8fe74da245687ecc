/* The sim: source: frames bit-identical to `polarcam render` with the same seed (the CLI, run
 * as a separate program), ROI frames at odd offsets equal crops of those frames with the
 * mosaic phase moved accordingly, packed formats and padded strides carry the same values,
 * the pacing schedule is computed from the stream start (arithmetic of the pacer, no timing),
 * every injected fault surfaces through the compliance test, the compliance test passes; all of
 * it for a monochrome (ideal_small) and a colour-polarization (colour_small, IMX250MYR) scene. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../devices/backend_util.h"
#include "check.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

static char scene[512];
static char tmp[64];
static bool colour; /* the scene's sensor is colour-polarization (IMX250MYR) */

static void log_fail(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	(void)ctx;
	if (r == PC_CHECK_FAIL)
		fprintf(stderr, "compliance FAIL: %s: %s\n", check, detail);
}

/* The rendered frames, read back from render's PNGs. */
static pc_view rendered[3];

static int render(const char *polarcam)
{
	char cmd[1400];
	snprintf(cmd, sizeof cmd,
	         "'%s' render '%s' -o '%s/render%d' -n 3 -s 5 --no-truth >/dev/null", polarcam,
	         scene, tmp, colour);
	if (system(cmd) != 0)
		return -1;
	char dir[128];
	snprintf(dir, sizeof dir, "%s/render%d", tmp, colour);
	pc_recording *r = NULL;
	int rc = pc_recording_open(&r, dir);
	for (int k = 0; !rc && k < 3; k++)
		rc = pc_recording_read(r, (size_t)k, &rendered[k]);
	pc_recording_free(r);
	return rc;
}

static pc_source *open_stream(const char *opts, const pc_source_format *req)
{
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0%s", scene, opts);
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, uri), 0);
	if (!s)
		return NULL;
	if (req) {
		pc_source_format f = *req;
		pc_format_verdict v;
		CHECK_EQ_INT(pc_source_try_format(s, &f, &v), 0);
		CHECK_EQ_INT(v, PC_FORMAT_VALID);
		CHECK_EQ_INT(pc_source_set_format(s, &f), 0);
	}
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 3), 0);
	CHECK_EQ_INT(pc_source_start(s), 0);
	return s;
}

/* Frames 0..2 against the rendered ones: ROI (ox, oy) crop, any format, any stride. */
static void compare(pc_source *s, uint32_t ox, uint32_t oy)
{
	for (unsigned k = 0; k < 3; k++) {
		pc_buffer *b = NULL;
		CHECK_EQ_INT(pc_source_dequeue(s, 10000, &b), 0);
		if (!b) {
			fprintf(stderr, "dequeue: %s\n", pc_error_detail());
			return;
		}
		const pc_view *v = &b->frame.view;
		CHECK_EQ_INT(b->frame.meta.sequence, k);
		uint16_t *u = malloc((size_t)v->width * v->height * 2);
		CHECK_EQ_INT(pc_view_to_u16(v, u, (size_t)v->width * 2), 0);
		unsigned mism = 0;
		for (uint32_t y = 0; y < v->height; y++)
			for (uint32_t x = 0; x < v->width; x++)
				mism += u[(size_t)y * v->width + x] !=
				        PC_ROW(&rendered[k], uint16_t, y + oy)[x + ox];
		CHECK_EQ_INT(mism, 0);
		free(u);
		/* IMX250MZR [90 45; 135 0] (IMX250MYR: those blocks under RGGB) moved by hand to
		 * the ROI origin */
		static const int a[2][2] = {{90, 45}, {135, 0}};
		static const pc_cfa_color rggb[2][2] = {{PC_CFA_R, PC_CFA_G}, {PC_CFA_G, PC_CFA_B}};
		CHECK_EQ_INT(b->frame.mosaic.period, colour ? 4 : 2);
		for (unsigned y = 0; y < 4; y++)
			for (unsigned x = 0; x < 4; x++) {
				CHECK_EQ_INT(pc_mosaic_channel(&b->frame.mosaic, x, y) * 45,
				             a[(y + oy) & 1][(x + ox) & 1]);
				CHECK_EQ_INT(pc_mosaic_color(&b->frame.mosaic, x, y),
				             colour ? rggb[((y + oy) >> 1) & 1][((x + ox) >> 1) & 1]
				                    : PC_CFA_NONE);
			}
		CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	}
}

static void test_against_render(void)
{
	pc_source *s = open_stream("", NULL);
	if (s) {
		pc_source_format f;
		pc_source_get_format(s, &f);
		CHECK_EQ_INT(f.width, rendered[0].width);
		CHECK_EQ_INT(f.height, rendered[0].height);
		compare(s, 0, 0);
		pc_source_close(s);
	}
	/* ROIs at odd offsets (and 2 mod 4, which moves a colour mosaic's colours), Mono12p,
	 * padded stride */
	const uint32_t off[2][2] = {{3, 1}, {2, 3}};
	for (int i = 0; i < 2; i++) {
		pc_source_format req;
		memset(&req, 0, sizeof req);
		req.format = PC_FMT_MONO12P;
		req.offset_x = off[i][0];
		req.offset_y = off[i][1];
		req.width = 100;
		req.height = 37;
		req.stride = 256;
		s = open_stream("", &req);
		if (s) {
			compare(s, off[i][0], off[i][1]);
			pc_source_close(s);
		}
	}
	/* the default format itself can be an odd ROI with a padded stride (misbehaving camera) */
	s = open_stream("&roi=5,2,64,48&stride_pad=40", NULL);
	if (s) {
		pc_source_format f;
		pc_source_get_format(s, &f);
		CHECK_EQ_INT(f.offset_x, 5);
		CHECK_EQ_INT(f.stride, 64 * 2 + 40);
		compare(s, 5, 2);
		pc_source_close(s);
	}
}

static void test_pacer(void)
{
	/* frame k is due at t0 + k * period: never an accumulation of sleeps */
	pc_pacer p;
	pc_pacer_start(&p, 30.0, 1000, 0);
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 0), 1000);
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 3), 1000 + 100000000);
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 300000), 1000 + 10000000000000ull); /* 10^4 s */
	/* a rate change at frame 30 keeps frame 30's time and continues at the new period */
	pc_pacer_set_rate(&p, 10.0, 30);
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 30), 1000 + 1000000000ull);
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 40), 1000 + 2000000000ull);
	pc_pacer_start(&p, 0, 5, 0); /* unpaced */
	CHECK_EQ_INT(pc_pacer_due_ns(&p, 1000), 5);
}

static void test_compliance(void)
{
	static const struct {
		const char *opts;
		pc_fault_kind fault;
	} runs[] = {
	    {"", PC_FAULT_NONE},
	    {"&roi=1,1,40,30&stride_pad=8", PC_FAULT_NONE},
	    {"&drop_every=3", PC_FAULT_DROP},
	    {"&timeout_every=4", PC_FAULT_TIMEOUT},
	    {"&corrupt_every=2", PC_FAULT_CORRUPT},
	    {"&disconnect_after=3", PC_FAULT_DISCONNECT},
	};
	for (size_t i = 0; i < sizeof runs / sizeof runs[0]; i++) {
		char uri[700];
		snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0%s", scene, runs[i].opts);
		pc_compliance_options o;
		memset(&o, 0, sizeof o);
		o.log = log_fail;
		o.expect_fault = runs[i].fault;
		o.timeout_ms = 200;
		o.starve_ms = 100;
		pc_compliance_result res;
		CHECK_EQ_INT(pc_source_compliance(uri, &o, &res), 0);
		if (res.failed)
			fprintf(stderr, "in %s\n", uri);
		CHECK_EQ_INT(res.failed, 0);
		CHECK(res.passed > 20);
	}
	/* a fault the source does not inject is reported as a failure: the test can fail */
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?seed=5&fps=0", scene);
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.expect_fault = PC_FAULT_DROP;
	pc_compliance_result res;
	CHECK_EQ_INT(pc_source_compliance(uri, &o, &res), 0);
	CHECK(res.failed >= 1);
	CHECK(strstr(res.first_failure, "dropped") != NULL);
}

static void test_errors(void)
{
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, "sim:/no/such/scene.json"), PC_ENOENT);
	char uri[700];
	snprintf(uri, sizeof uri, "sim:%s?roi=600,0,100,10", scene);
	CHECK(pc_source_open(&s, uri) == PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "roi") != NULL);
	snprintf(uri, sizeof uri, "sim:%s?drop_every=1", scene);
	CHECK_EQ_INT(pc_source_open(&s, uri), PC_EINVAL);
	CHECK(s == NULL);
}

int main(void)
{
	const char *src = getenv("PC_SOURCE_DIR"), *polarcam = getenv("POLARCAM");
	if (!src || !polarcam)
		SKIP("PC_SOURCE_DIR / POLARCAM not set: run through ctest");
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_simsrc"))
		SKIP("no temporary directory");
	test_pacer();
	/* a monochrome and a colour-polarization scene through the same checks */
	for (int c = 0; c < 2; c++) {
		colour = c;
		snprintf(scene, sizeof scene, "%s/scenes/%s", src,
		         colour ? "colour_small.json" : "ideal_small.json");
		CHECK_EQ_INT(render(polarcam), 0);
		if (rendered[2].data)
			test_against_render();
		test_compliance();
		for (int k = 0; k < 3; k++)
			pc_view_free(&rendered[k]);
	}
	test_errors();
	char cmd[128];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("test_sim_source");
}
