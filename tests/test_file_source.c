/* Recordings and the file: source: a recording written with pc_recording reads back bit for
 * bit; the file: source delivers the recorded values (checked against the values we wrote,
 * not against the reader), crops at odd offsets with the mosaic shifted, converts to packed
 * formats losslessly, pads strides, continues sequence and time when looping, ends with
 * PC_EEND; malformed recordings are refused naming the file and field; the compliance test
 * passes on file:, also over a colour-polarization (IMX250MYR) recording, whose mosaic is read
 * back from meta.json and moved by ROI offsets as worked out by hand. */
#include <dirent.h>
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

enum { W = 10, H = 6, N = 5 };

/* The value written at (x, y) of frame k: a 12-bit pattern unique per pixel and frame. */
static uint16_t value(unsigned k, unsigned x, unsigned y)
{
	return (uint16_t)((k * 997u + y * 131u + x * 17u + (x * y) % 7u) & 0xfffu);
}

static void rm_rf(const char *dir)
{
	DIR *d = opendir(dir);
	if (!d)
		return;
	struct dirent *e;
	char p[512];
	while ((e = readdir(d)))
		if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
			snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
			unlink(p);
		}
	closedir(d);
	rmdir(dir);
}

static void write_file(const char *dir, const char *name, const char *text)
{
	char p[512];
	snprintf(p, sizeof p, "%s/%s", dir, name);
	FILE *fp = fopen(p, "w");
	if (fp) {
		fputs(text, fp);
		fclose(fp);
	}
}

static void make_recording(const char *dir)
{
	pc_recording_desc d = {0};
	d.source = "test";
	d.format = PC_FMT_MONO12;
	d.device_format = "PolarizeMono12";
	d.width = W;
	d.height = H;
	d.sensor_width = W;
	d.sensor_height = H;
	d.polarized = true;
	d.mosaic = pc_mosaic_imx250mzr();
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_create(&r, dir, &d, false), 0);
	if (!r)
		return;
	pc_frame f;
	memset(&f, 0, sizeof f);
	CHECK_EQ_INT(pc_view_alloc(&f.view, PC_FMT_MONO12, W, H, 64), 0);
	for (unsigned k = 0; k < N; k++) {
		for (unsigned y = 0; y < H; y++)
			for (unsigned x = 0; x < W; x++)
				PC_ROW(&f.view, uint16_t, y)[x] = value(k, x, y);
		f.meta.sequence = 10 + 2 * k;       /* gaps of one frame */
		f.meta.timestamp_ns = 1000000u * k; /* 1 ms apart */
		f.meta.exposure_us = 100 + k;
		f.meta.gain_db = k == 2 ? NAN : 0.5 * k; /* frame 2: the source did not say */
		CHECK_EQ_INT(pc_recording_add(r, &f), 0);
	}
	f.meta.sequence = 3; /* going backwards is refused */
	CHECK_EQ_INT(pc_recording_add(r, &f), PC_EINVAL);
	CHECK_EQ_INT(pc_recording_set_json(r, "stats", "{\"completed\": 5}"), 0);
	CHECK_EQ_INT(pc_recording_set_json(r, "stats", "[1]"), PC_EINVAL);
	CHECK_EQ_INT(pc_recording_finish(r, NULL), 0);
	pc_view_free(&f.view);
	pc_recording_free(r);
	/* a second recording into the same directory is refused */
	CHECK_EQ_INT(pc_recording_create(&r, dir, &d, false), PC_EBUSY);
}

static void test_read_back(const char *dir)
{
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (!r)
		return;
	CHECK_EQ_INT(pc_recording_count(r), N);
	CHECK(pc_recording_is_complete(r));
	const pc_recording_desc *d = pc_recording_get_desc(r);
	CHECK_EQ_INT(d->format, PC_FMT_MONO12);
	CHECK(d->device_format && !strcmp(d->device_format, "PolarizeMono12"));
	CHECK_EQ_INT(d->mosaic.channel[0][0], 2);
	CHECK_EQ_INT(pc_recording_get_frame(r, 3)->sequence, 16);
	CHECK_NEAR(pc_recording_get_frame(r, 3)->exposure_us, 103, 0);
	/* the analog gain, and an unknown one kept unknown (null in meta.json, NAN back) */
	CHECK_NEAR(pc_recording_get_frame(r, 3)->gain_db, 1.5, 0);
	CHECK(isnan(pc_recording_get_frame(r, 2)->gain_db));
	{
		char mp[700];
		snprintf(mp, sizeof mp, "%s/meta.json", dir);
		json_t *m = json_load_file(mp, 0, NULL);
		json_t *g2 =
		    json_object_get(json_array_get(json_object_get(m, "frames"), 2), "gain_db");
		CHECK(m && g2 && json_is_null(g2));
		json_decref(m);
	}
	unsigned mism = 0;
	for (unsigned k = 0; k < N; k++) {
		pc_view v;
		CHECK_EQ_INT(pc_recording_read(r, k, &v), 0);
		for (unsigned y = 0; y < H; y++)
			for (unsigned x = 0; x < W; x++)
				mism += PC_ROW(&v, uint16_t, y)[x] != value(k, x, y);
		pc_view_free(&v);
	}
	CHECK_EQ_INT(mism, 0);
	pc_recording_free(r);
}

static void test_source(const char *dir)
{
	char uri[600];
	snprintf(uri, sizeof uri, "file:%s", dir);
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, uri), 0);
	if (!s)
		return;
	/* ROI 5x4 at (3,1), packed Mono12p needs an even width: adjusted to 4 */
	pc_source_format f = {0};
	f.format = PC_FMT_MONO12P;
	f.offset_x = 3;
	f.offset_y = 1;
	f.width = 5;
	f.height = 4;
	f.stride = 40;
	pc_format_verdict v;
	CHECK_EQ_INT(pc_source_try_format(s, &f, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_ADJUSTED);
	CHECK_EQ_INT(f.width, 4);
	CHECK_EQ_INT(pc_source_set_format(s, &f), 0);
	/* mosaic at (3,1) of [90 45; 135 0]: row 1 col 1 -> 0°, as independent arithmetic */
	CHECK_EQ_INT(f.mosaic.channel[0][0], 0);
	CHECK_EQ_INT(f.mosaic.channel[0][1], 3);
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 2), 0);
	CHECK_EQ_INT(pc_source_start(s), 0);
	unsigned mism = 0;
	for (unsigned k = 0; k < N; k++) {
		pc_buffer *b = NULL;
		CHECK_EQ_INT(pc_source_dequeue(s, 1000, &b), 0);
		if (!b)
			break;
		CHECK_EQ_INT(b->frame.meta.sequence, 10 + 2 * k);
		CHECK_EQ_INT(b->frame.view.stride, 40);
		uint16_t u[4 * 4];
		CHECK_EQ_INT(pc_view_to_u16(&b->frame.view, u, 8), 0);
		for (unsigned y = 0; y < 4; y++)
			for (unsigned x = 0; x < 4; x++)
				mism += u[y * 4 + x] != value(k, x + 3, y + 1);
		CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	}
	CHECK_EQ_INT(mism, 0);
	pc_buffer *b = NULL;
	CHECK_EQ_INT(pc_source_dequeue(s, 100, &b), PC_EEND);
	pc_source_stats st;
	CHECK_EQ_INT(pc_source_get_stats(s, &st), 0);
	CHECK_EQ_INT(st.completed, N);
	CHECK_EQ_INT(st.dropped, N - 1); /* the recording skips every other sequence number */
	pc_source_close(s);

	/* looping continues sequence and time; fps paces */
	snprintf(uri, sizeof uri, "file:%s?loop=1&fps=500", dir);
	CHECK_EQ_INT(pc_source_open(&s, uri), 0);
	if (!s)
		return;
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 3), 0);
	CHECK_EQ_INT(pc_source_start(s), 0);
	uint64_t seq[2 * N], ts[2 * N];
	for (unsigned k = 0; k < 2 * N; k++) {
		CHECK_EQ_INT(pc_source_dequeue(s, 1000, &b), 0);
		if (!b)
			break;
		seq[k] = b->frame.meta.sequence;
		ts[k] = b->frame.meta.timestamp_ns;
		pc_source_requeue(s, b);
	}
	CHECK_EQ_INT(seq[N], 10 + 9); /* lap 2 starts one after the span 10..18 */
	CHECK_EQ_INT(ts[N], 4000000 + 1000000);
	pc_source_close(s);

	CHECK_EQ_INT(pc_source_open(&s, "file:/nonexistent/dir"), PC_ENOENT);
	snprintf(uri, sizeof uri, "file:%s?loop=maybe", dir);
	CHECK_EQ_INT(pc_source_open(&s, uri), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "loop") != NULL);
}

static void log_fail(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	(void)ctx;
	if (r == PC_CHECK_FAIL)
		fprintf(stderr, "compliance FAIL: %s: %s\n", check, detail);
}

static void test_compliance(const char *dir)
{
	char uri[600];
	snprintf(uri, sizeof uri, "file:%s?loop=1", dir);
	pc_compliance_options o = {0};
	o.log = log_fail;
	pc_compliance_result res;
	CHECK_EQ_INT(pc_source_compliance(uri, &o, &res), 0);
	CHECK_EQ_INT(res.failed, 0);
	CHECK(res.passed > 30);
	/* a finite recording: allowed to end */
	snprintf(uri, sizeof uri, "file:%s", dir);
	o.finite = true;
	CHECK_EQ_INT(pc_source_compliance(uri, &o, &res), 0);
	CHECK_EQ_INT(res.failed, 0);
}

/* A colour-polarization recording (IMX250MYR, 16x12, 10-bit values of the same pattern): the
 * mosaic comes back from meta.json, an ROI at (3,2) moves both analysers and colours, and the
 * compliance test passes. */
static void test_colour(const char *base)
{
	enum { CW = 16, CH = 12, CN = 3 };
	char dir[512], uri[600];
	snprintf(dir, sizeof dir, "%s/colour", base);
	pc_recording_desc d = {0};
	d.source = "test";
	d.format = PC_FMT_MONO10;
	d.device_format = "BayerRGPolarized10p";
	d.width = d.sensor_width = CW;
	d.height = d.sensor_height = CH;
	d.polarized = true;
	CHECK_EQ_INT(pc_mosaic_parse("RGGB:90,45,135,0", &d.mosaic), 0);
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_create(&r, dir, &d, false), 0);
	if (!r)
		return;
	pc_frame f;
	memset(&f, 0, sizeof f);
	CHECK_EQ_INT(pc_view_alloc(&f.view, PC_FMT_MONO10, CW, CH, 64), 0);
	for (unsigned k = 0; k < CN; k++) {
		for (unsigned y = 0; y < CH; y++)
			for (unsigned x = 0; x < CW; x++)
				PC_ROW(&f.view, uint16_t, y)[x] = value(k, x, y) & 0x3ffu;
		f.meta.sequence = k;
		f.meta.timestamp_ns = 1000000u * k;
		CHECK_EQ_INT(pc_recording_add(r, &f), 0);
	}
	CHECK_EQ_INT(pc_recording_finish(r, NULL), 0);
	pc_view_free(&f.view);
	pc_recording_free(r);

	snprintf(uri, sizeof uri, "file:%s", dir);
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, uri), 0);
	if (!s)
		return;
	pc_source_format q = {0};
	q.offset_x = 3;
	q.offset_y = 2;
	q.width = 8;
	q.height = 8;
	pc_format_verdict v;
	CHECK_EQ_INT(pc_source_try_format(s, &q, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	CHECK_EQ_INT(pc_source_set_format(s, &q), 0);
	/* pixel (x, y) of the ROI is sensor pixel (x + 3, y + 2) of
	 *   R90  R45 G90  G45
	 *   R135 R0  G135 G0
	 *   G90  G45 B90  B45
	 *   G135 G0  B135 B0 */
	static const char col[4][5] = {"RRGG", "RRGG", "GGBB", "GGBB"};
	static const int ang[2][2] = {{90, 45}, {135, 0}};
	static const char letter[4] = {'-', 'R', 'G', 'B'};
	CHECK_EQ_INT(q.mosaic.period, 4);
	unsigned bad = 0;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++) {
			bad += (int)pc_mosaic_channel(&q.mosaic, x, y) * 45 !=
			       ang[(y + 2) & 1][(x + 3) & 1];
			bad += letter[pc_mosaic_color(&q.mosaic, x, y)] !=
			       col[(y + 2) & 3][(x + 3) & 3];
		}
	CHECK_EQ_INT(bad, 0);
	CHECK_EQ_INT(pc_source_buffers_alloc(s, 2), 0);
	CHECK_EQ_INT(pc_source_start(s), 0);
	unsigned mism = 0;
	for (unsigned k = 0; k < CN; k++) {
		pc_buffer *b = NULL;
		CHECK_EQ_INT(pc_source_dequeue(s, 1000, &b), 0);
		if (!b)
			break;
		CHECK(memcmp(&b->frame.mosaic, &q.mosaic, sizeof q.mosaic) == 0);
		for (unsigned y = 0; y < 8; y++)
			for (unsigned x = 0; x < 8; x++)
				mism += PC_ROW(&b->frame.view, uint16_t, y)[x] !=
				        (value(k, x + 3, y + 2) & 0x3ffu);
		CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	}
	CHECK_EQ_INT(mism, 0);
	pc_source_close(s);

	snprintf(uri, sizeof uri, "file:%s?loop=1", dir);
	pc_compliance_options o = {0};
	o.log = log_fail;
	pc_compliance_result res;
	CHECK_EQ_INT(pc_source_compliance(uri, &o, &res), 0);
	CHECK_EQ_INT(res.failed, 0);
	CHECK(res.passed > 30);
	rm_rf(dir);
}

static void test_malformed(const char *base)
{
	char dir[512];
	snprintf(dir, sizeof dir, "%s/bad", base);
	mkdir(dir, 0755);
	pc_recording *r = NULL;
	write_file(dir, "meta.json", "{\"polarcam_recording\": 1,\n \"bits\": 12,,\n}");
	CHECK_EQ_INT(pc_recording_open(&r, dir), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "meta.json: line 2") != NULL);
	write_file(dir, "meta.json",
	           "{\"polarcam_recording\": 1, \"bits\": 12, \"format\": "
	           "\"Mono12\", \"width\": 4, \"height\": 2, \"frames\": [{\"file\": "
	           "\"raw_000000.png\", \"sequence\": 5, \"timestamp_ns\": 0}, "
	           "{\"file\": \"raw_000001.png\", \"sequence\": 5, "
	           "\"timestamp_ns\": 1}]}");
	CHECK_EQ_INT(pc_recording_open(&r, dir), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "frames[1].sequence") != NULL);
	write_file(dir, "meta.json",
	           "{\"polarcam_recording\": 1, \"bits\": 10, \"format\": "
	           "\"Mono12\", \"width\": 4, \"height\": 2, \"frames\": []}");
	CHECK_EQ_INT(pc_recording_open(&r, dir), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "bits") != NULL);
	write_file(dir, "meta.json",
	           "{\"polarcam_recording\": 1, \"bits\": 12, \"format\": "
	           "\"Mono12\", \"width\": 4, \"height\": 2, \"mosaic\": "
	           "\"90,45,90,0\", \"frames\": []}");
	CHECK_EQ_INT(pc_recording_open(&r, dir), PC_EFORMAT);
	CHECK(strstr(pc_error_detail(), "mosaic") != NULL);
	/* meta.json right, but the PNG is 8x4 instead of 4x2 */
	write_file(dir, "meta.json",
	           "{\"polarcam_recording\": 1, \"bits\": 12, \"format\": "
	           "\"Mono12\", \"width\": 4, \"height\": 2, \"frames\": [{\"file\": "
	           "\"raw_000000.png\", \"sequence\": 0, \"timestamp_ns\": 0}]}");
	pc_view v;
	CHECK_EQ_INT(pc_view_alloc(&v, PC_FMT_MONO12, 8, 4, 1), 0);
	memset(v.data, 0, v.stride * 4);
	char p[600];
	snprintf(p, sizeof p, "%s/raw_000000.png", dir);
	CHECK_EQ_INT(pc_png_write(p, &v), 0);
	pc_view_free(&v);
	CHECK_EQ_INT(pc_recording_open(&r, dir), 0);
	if (r) {
		pc_view out;
		CHECK_EQ_INT(pc_recording_read(r, 0, &out), PC_EFORMAT);
		CHECK(strstr(pc_error_detail(), "raw_000000.png") != NULL);
		pc_recording_free(r);
	}
	/* the same through a source: the error surfaces from dequeue */
	char uri[600];
	snprintf(uri, sizeof uri, "file:%s", dir);
	pc_source *s = NULL;
	CHECK_EQ_INT(pc_source_open(&s, uri), 0);
	if (s) {
		pc_buffer *b = NULL;
		CHECK_EQ_INT(pc_source_buffers_alloc(s, 1), 0);
		CHECK_EQ_INT(pc_source_start(s), 0);
		CHECK_EQ_INT(pc_source_dequeue(s, 100, &b), PC_EFORMAT);
		pc_source_close(s);
	}
	rm_rf(dir);
}

int main(void)
{
	char base[64];
	if (!pc_test_tmpdir(base, sizeof base, "pc_test_file"))
		SKIP("cannot create a temporary directory");
	char dir[256];
	snprintf(dir, sizeof dir, "%s/rec", base);
	make_recording(dir);
	test_read_back(dir);
	test_source(dir);
	test_compliance(dir);
	test_colour(base);
	test_malformed(base);
	rm_rf(dir);
	rmdir(base);
	return pc_test_finish("test_file_source");
}
