/* GigE Vision with a colour-polarization camera, against a real protocol peer: `polarcam serve
 * scenes/colour_small.json` (an IMX250MYR sensor; a separate process) on 127.0.0.1 and
 * polarcam's aravis: source, inside a private network namespace (tests/netns.sh). The reference
 * frames come from `polarcam render` of the same scene and seed (another process, no GigE
 * Vision); mosaics are checked against the IMX250MYR layout written out here by hand.
 *   - the camera offers BayerRGPolarized8/10p/12p/16 only, and their enumeration values are
 *     ones that mean other things elsewhere (LUCID's PolarizeMono values, one of them Aravis's
 *     CUSTOM_BAYER_RG_16): aravis: still maps them, by name, to colour-polarization frames
 *   - `polarcam capture` records frames bit-identical to `render`, 0 missing packets, and
 *     meta.json names the colour mosaic and the device format, with render's format and bits
 *   - ROIs at odd offsets (and 2 mod 4), ReverseX, the 8/10p/12p/16-bit formats deliver the
 *     rendered pixels (narrower formats: the top bits) under the mosaic moved by hand
 *   - the compliance test passes on aravis: with the colour camera
 *   - `capture --process` runs the colour pipeline (bayer-first by default) on the recorded
 *     mosaic: the same images as `polarcam process` of the recorded raw with that layout, unlike
 *     with the layout one pixel off; a monochrome method is refused before anything is written
 *   - serve refuses a source whose mosaic its model name cannot describe (BGGR), naming it */
#include <arv.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "gige_peer.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/gige_server.h"
#include "polarcam/io.h"
#include "polarcam/recording.h"
#include "polarcam/source.h"

enum { NREF = 6, SEED = 11 };

static const char *polarcam;
static char base[64];
static char scene[512];
static pc_view ref[NREF]; /* render's frames 0..NREF-1 (Mono12) */

/* Sony IMX250MYR at sensor pixel (0,0): 2x2 polarizer blocks [90 45; 135 0] under RGGB.
 *   y=0  R90  R45 G90  G45
 *   y=1  R135 R0  G135 G0
 *   y=2  G90  G45 B90  B45
 *   y=3  G135 G0  B135 B0 */
static const char myr_colour[4][5] = {"RRGG", "RRGG", "GGBB", "GGBB"};
static const int myr_angle[2][2] = {{90, 45}, {135, 0}};

/* Mismatches of the 4x4 period of m against the layout moved by hand: pixel (x, y) of the ROI
 * at (ox, oy) of a readout mirrored (rev_x) over width w. */
static unsigned mosaic_mismatches(const pc_mosaic *m, uint32_t ox, uint32_t oy, bool rev_x,
                                  uint32_t w)
{
	static const char letter[4] = {'-', 'R', 'G', 'B'};
	unsigned bad = m->period != 4;
	for (uint32_t y = 0; y < 4; y++)
		for (uint32_t x = 0; x < 4; x++) {
			uint32_t sx = rev_x ? w - 1 - (ox + x) : ox + x, sy = oy + y;
			int a = myr_angle[sy & 1][sx & 1];
			if (rev_x)
				a = (180 - a) %
				    180; /* a mirror maps an analyser at θ to 180° − θ */
			bad += (int)pc_mosaic_channel(m, x, y) * 45 != a;
			bad += letter[pc_mosaic_color(m, x, y) & 3] != myr_colour[sy & 3][sx & 3];
		}
	return bad;
}

static int run_render(void)
{
	char rdir[160];
	snprintf(rdir, sizeof rdir, "%s/render", base);
	char n[8], seed[16];
	snprintf(n, sizeof n, "%d", NREF);
	snprintf(seed, sizeof seed, "%d", SEED);
	char *argv[] = {(char *)polarcam, "render", scene, "-o", rdir, "-n", n, "-s", seed,
	                "--no-truth",     NULL};
	int devnull = open("/dev/null", O_WRONLY);
	int st = pc_child_wait(pc_child_spawn(argv, devnull, NULL), EXIT_MS, NULL);
	if (devnull >= 0)
		close(devnull);
	CHECK_EQ_INT(st, 0);
	pc_recording *r = NULL;
	int rc = st ? -1 : pc_recording_open(&r, rdir);
	CHECK_EQ_INT(rc, 0);
	for (unsigned k = 0; !rc && k < NREF; k++)
		rc = pc_recording_read(r, k, &ref[k]);
	CHECK_EQ_INT(rc, 0);
	if (r) {
		/* render's own description: the colour mosaic, the sensor's 12 bits */
		const pc_recording_desc *d = pc_recording_get_desc(r);
		CHECK_EQ_INT(d->format, PC_FMT_MONO12);
		CHECK_EQ_INT(mosaic_mismatches(&d->mosaic, 0, 0, false, 0), 0);
	}
	pc_recording_free(r);
	return rc;
}

/* ---- the camera as any GigE Vision client sees it ---- */

static void test_description(void)
{
	GError *err = NULL;
	ArvCamera *cam = arv_camera_new("127.0.0.1", &err);
	CHECK(cam != NULL);
	if (!cam) {
		fprintf(stderr, "arv_camera_new: %s\n", err ? err->message : "?");
		g_clear_error(&err);
		return;
	}
	guint n = 0;
	const char **names = arv_camera_dup_available_pixel_formats_as_strings(cam, &n, &err);
	gint64 *codes = arv_camera_dup_available_pixel_formats(cam, &n, &err);
	CHECK(err == NULL);
	g_clear_error(&err);
	static const char *const want[4] = {"BayerRGPolarized8", "BayerRGPolarized10p",
	                                    "BayerRGPolarized12p", "BayerRGPolarized16"};
	unsigned found = 0, others = 0;
	int64_t code16 = 0;
	for (guint i = 0; names && codes && i < n; i++) {
		bool known = false;
		for (int k = 0; k < 4; k++)
			if (!strcmp(names[i], want[k])) {
				found |= 1u << k;
				known = true;
				if (k == 3)
					code16 = codes[i];
			}
		others += !known;
	}
	CHECK_EQ_INT(found, 15);
	CHECK_EQ_INT(others, 0); /* no monochrome names over a colour sensor */
	/* the value of BayerRGPolarized16 is LUCID's PolarizeMono16, Aravis's
	 * CUSTOM_BAYER_RG_16: only the name can tell what the frames are */
	CHECK_EQ_INT(code16, 0x81100007);
	CHECK_EQ_INT(code16, ARV_PIXEL_FORMAT_CUSTOM_BAYER_RG_16);
	const char *model = arv_camera_get_model_name(cam, NULL);
	CHECK(model && !strcmp(model, "polarcam-sim-colour"));
	g_free(names);
	g_free(codes);
	g_object_unref(cam);
}

/* ---- aravis: in this process ---- */

static pc_source *open_cam(const char *opts, const char *fmt_name, uint32_t ox, uint32_t oy,
                           uint32_t w, uint32_t h)
{
	char uri[128];
	snprintf(uri, sizeof uri, "aravis:127.0.0.1?packet_size=1500%s", opts);
	pc_source *s = NULL;
	int rc = pc_source_open(&s, uri);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		fprintf(stderr, "open %s: %s\n", uri, pc_error_detail());
		return NULL;
	}
	pc_source_format f;
	memset(&f, 0, sizeof f);
	snprintf(f.format_name, sizeof f.format_name, "%s", fmt_name);
	f.offset_x = ox;
	f.offset_y = oy;
	f.width = w;
	f.height = h;
	pc_format_verdict v;
	CHECK_EQ_INT(pc_source_try_format(s, &f, &v), 0);
	CHECK_EQ_INT(v, PC_FORMAT_VALID);
	rc = pc_source_set_format(s, &f);
	if (!rc)
		rc = pc_source_buffers_alloc(s, 4);
	if (!rc)
		rc = pc_source_start(s);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		fprintf(stderr, "%s %s: %s\n", uri, fmt_name, pc_error_detail());
		pc_source_close(s);
		return NULL;
	}
	return s;
}

/* Streams n frames: each must be render's frame (sequence - first) cropped at (ox, oy) of the
 * readout (mirrored when rev_x), shifted right by `shift`, under the layout moved by hand.
 * Returns the frames whose content was compared. */
static unsigned stream_and_compare(pc_source *s, unsigned n, uint32_t ox, uint32_t oy, bool rev_x,
                                   unsigned shift)
{
	unsigned mism = 0, compared = 0, mosaic_bad = 0, damaged = 0;
	uint64_t first = 0;
	uint16_t *u = NULL;
	const uint32_t w = ref[0].width;
	for (unsigned k = 0; k < n; k++) {
		pc_buffer *b = NULL;
		int rc = pc_source_dequeue(s, FRAME_MS, &b);
		CHECK_EQ_INT(rc, 0);
		if (rc) {
			fprintf(stderr, "dequeue %u: %s\n", k, pc_error_detail());
			break;
		}
		const pc_view *v = &b->frame.view;
		if (k == 0)
			first = b->frame.meta.sequence;
		uint64_t j = b->frame.meta.sequence - first;
		mosaic_bad += mosaic_mismatches(&b->frame.mosaic, ox, oy, rev_x, w);
		if (b->frame.meta.status != 0 || j >= NREF) {
			damaged += b->frame.meta.status != 0; /* packets lost under load */
			CHECK_EQ_INT(pc_source_requeue(s, b), 0);
			continue;
		}
		if (!u)
			u = malloc((size_t)v->width * v->height * 2);
		CHECK_EQ_INT(pc_view_to_u16(v, u, (size_t)v->width * 2), 0);
		for (uint32_t y = 0; y < v->height; y++)
			for (uint32_t x = 0; x < v->width; x++) {
				uint32_t sx = rev_x ? w - 1 - (ox + x) : ox + x;
				mism += u[(size_t)y * v->width + x] !=
				        (PC_ROW(&ref[j], uint16_t, oy + y)[sx] >> shift);
			}
		compared++;
		CHECK_EQ_INT(pc_source_requeue(s, b), 0);
	}
	free(u);
	CHECK_EQ_INT(mism, 0);
	CHECK_EQ_INT(mosaic_bad, 0);
	CHECK(damaged * 3 <= n);
	if (damaged)
		printf("note: %u frames damaged (load)\n", damaged);
	return compared;
}

static void test_client(void)
{
	static const struct {
		const char *opts, *fmt;
		uint32_t ox, oy, w, h;
		bool rev_x;
		unsigned shift;
	} c[] = {
	    {"", "BayerRGPolarized12p", 0, 0, 0, 0, false, 0},
	    {"", "BayerRGPolarized16", 3, 1, 64, 48, false, 0},
	    {"", "BayerRGPolarized12p", 2, 3, 40, 30, false, 0},
	    {"&reverse_x=1", "BayerRGPolarized16", 1, 2, 64, 48, true, 0},
	    {"&reverse_x=0", "BayerRGPolarized8", 0, 0, 0, 0, false, 4},
	    {"", "BayerRGPolarized10p", 5, 1, 32, 20, false, 2},
	};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		pc_source *s = open_cam(c[i].opts, c[i].fmt, c[i].ox, c[i].oy, c[i].w, c[i].h);
		if (!s)
			continue;
		pc_source_format f;
		pc_source_get_format(s, &f);
		CHECK(f.polarized);
		CHECK(!strcmp(f.format_name, c[i].fmt));
		CHECK_EQ_INT(
		    mosaic_mismatches(&f.mosaic, c[i].ox, c[i].oy, c[i].rev_x, ref[0].width), 0);
		unsigned got = stream_and_compare(s, 4, c[i].ox, c[i].oy, c[i].rev_x, c[i].shift);
		CHECK(got >= 2);
		pc_source_close(s);
	}
}

static void log_fail(void *ctx, pc_check_result r, const char *check, const char *detail)
{
	(void)ctx;
	if (r == PC_CHECK_FAIL)
		fprintf(stderr, "compliance FAIL: %s: %s\n", check, detail);
}

static void test_compliance(void)
{
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.log = log_fail;
	o.frames = 8;
	o.timeout_ms = FRAME_MS;
	pc_compliance_result res;
	CHECK_EQ_INT(pc_source_compliance("aravis:127.0.0.1?packet_size=1500", &o, &res), 0);
	CHECK_EQ_INT(res.failed, 0);
	CHECK(res.passed >= 40);
}

/* ---- the CLI ---- */

static int run(char *const argv[], char *out, size_t size)
{
	char errp[160];
	snprintf(errp, sizeof errp, "%s/cli.err", base);
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	if (pid < 0)
		return 127;
	wait_line(fd, "\n", EXIT_MS, out, size);
	int st = pc_child_wait(pid, EXIT_MS, NULL);
	close(fd);
	return st;
}

static char *read_text(const char *path)
{
	FILE *fp = fopen(path, "r");
	if (!fp)
		return NULL;
	char *t = calloc(1, 1 << 20);
	if (t)
		(void)!fread(t, 1, (1 << 20) - 1, fp);
	fclose(fp);
	return t;
}

static void test_capture(void)
{
	char cdir[160], out[4096];
	snprintf(cdir, sizeof cdir, "%s/cap", base);
	/* the camera keeps what earlier clients set: ask for the full sensor at its default */
	char *argv[] = {(char *)polarcam,
	                "capture",
	                "aravis:127.0.0.1?packet_size=65000&reverse_x=0",
	                "-n",
	                "4",
	                "-o",
	                cdir,
	                "--format",
	                "BayerRGPolarized12p",
	                "--roi",
	                "0,0,120,100",
	                "--json",
	                NULL};
	CHECK_EQ_INT(run(argv, out, sizeof out), 0);
	CHECK(strstr(out, "\"frames\":4") != NULL);
	CHECK(strstr(out, "\"missing_packets\":0") != NULL);
	pc_recording *c = NULL;
	CHECK_EQ_INT(pc_recording_open(&c, cdir), 0);
	if (c) {
		const pc_recording_desc *d = pc_recording_get_desc(c);
		CHECK_EQ_INT(d->format, PC_FMT_MONO12); /* as render: Mono12, 12 bits */
		CHECK(d->device_format && !strcmp(d->device_format, "BayerRGPolarized12p"));
		CHECK(d->polarized);
		CHECK_EQ_INT(mosaic_mismatches(&d->mosaic, 0, 0, false, 0), 0);
		CHECK_EQ_INT(pc_recording_count(c), 4);
		for (size_t k = 0; k < 4 && k < pc_recording_count(c); k++) {
			pc_view b;
			CHECK_EQ_INT(pc_recording_read(c, k, &b), 0);
			CHECK_EQ_INT(b.format, ref[k].format);
			CHECK_EQ_INT(b.width, ref[k].width);
			size_t diff = 0;
			for (uint32_t y = 0; y < b.height && b.width == ref[k].width; y++)
				diff += memcmp(PC_ROW(&ref[k], uint8_t, y), PC_ROW(&b, uint8_t, y),
				               (size_t)b.width * 2) != 0;
			CHECK_EQ_INT(diff, 0);
			pc_view_free(&b);
		}
	}
	pc_recording_free(c);
	char mp[200];
	snprintf(mp, sizeof mp, "%s/meta.json", cdir);
	char *meta = read_text(mp);
	CHECK(meta && strstr(meta, "\"mosaic\": \"RGGB:90,45,135,0\"") &&
	      strstr(meta, "\"bits\": 12") && strstr(meta, "\"format\": \"Mono12\""));
	free(meta);
}

/* Reads DIR/NAME.npy as floats; NULL on failure. */
static float *read_npy(const char *dir, const char *name, size_t *count)
{
	char p[300];
	snprintf(p, sizeof p, "%s/%s.npy", dir, name);
	pc_array a;
	if (pc_npy_read(p, &a) != 0 || a.dtype != PC_DT_F32) {
		fprintf(stderr, "%s: %s\n", p, pc_error_detail());
		return NULL;
	}
	*count = pc_array_count(&a);
	return a.data;
}

static size_t count_diff(const float *a, const float *b, size_t n, double tol)
{
	size_t d = 0;
	for (size_t i = 0; i < n; i++)
		d += !(fabs((double)a[i] - (double)b[i]) <= tol);
	return d;
}

static void test_process(void)
{
	char cdir[160], pdir[200], pdir2[200], raw[220], out[4096];
	snprintf(cdir, sizeof cdir, "%s/cap_proc", base);
	char *argv[] = {(char *)polarcam,
	                "capture",
	                "aravis:127.0.0.1?packet_size=65000&reverse_x=0",
	                "-n",
	                "2",
	                "-o",
	                cdir,
	                "--format",
	                "BayerRGPolarized12p",
	                "--roi",
	                "0,0,120,100",
	                "--process",
	                "--json",
	                NULL};
	CHECK_EQ_INT(run(argv, out, sizeof out), 0);
	CHECK(strstr(out, "\"method\":\"bayer-first\"") != NULL);
	/* the same last frame through `polarcam process` with the recorded layout, and with the
	 * layout one pixel off */
	snprintf(raw, sizeof raw, "%s/raw_000001.png", cdir);
	snprintf(pdir, sizeof pdir, "%s/proc_ok", base);
	snprintf(pdir2, sizeof pdir2, "%s/proc_off", base);
	char *p1[] = {(char *)polarcam, "process",          raw,        "-o",          pdir,
	              "--layout",       "RGGB:90,45,135,0", "--method", "bayer-first", NULL};
	char *p2[] = {(char *)polarcam,       "process",  raw,           "-o", pdir2, "--layout",
	              "RGGB:90,45,135,0@1,0", "--method", "bayer-first", NULL};
	CHECK_EQ_INT(run(p1, out, sizeof out), 0);
	CHECK_EQ_INT(run(p2, out, sizeof out), 0);
	char cproc[200];
	snprintf(cproc, sizeof cproc, "%s/processed", cdir);
	size_t n_cap = 0, n_ok = 0, n_off = 0;
	float *cap = read_npy(cproc, "dolp_000001", &n_cap); /* the last frame's */
	float *ok = read_npy(pdir, "dolp", &n_ok);
	float *off = read_npy(pdir2, "dolp", &n_off);
	CHECK(cap && ok && off);
	CHECK_EQ_INT(n_cap, 120 * 100);
	if (cap && ok && off && n_cap == n_ok && n_cap == n_off) {
		CHECK_EQ_INT(count_diff(cap, ok, n_cap, 1e-6), 0);
		CHECK(count_diff(cap, off, n_cap, 1e-3) > n_cap / 4);
	}
	free(cap);
	free(ok);
	free(off);
	/* a monochrome method on colour frames: refused (exit 2) before anything is written */
	char bdir[160];
	snprintf(bdir, sizeof bdir, "%s/cap_bilinear", base);
	char *argv2[] = {(char *)polarcam,
	                 "capture",
	                 "aravis:127.0.0.1?packet_size=65000",
	                 "-n",
	                 "2",
	                 "-o",
	                 bdir,
	                 "--process",
	                 "--method",
	                 "bilinear",
	                 NULL};
	CHECK_EQ_INT(run(argv2, out, sizeof out), 2);
	CHECK(access(bdir, F_OK) != 0);
	char errp[160];
	snprintf(errp, sizeof errp, "%s/cli.err", base);
	char *err = read_text(errp);
	CHECK(err && strstr(err, "--method bilinear") && strstr(err, "bayer-first"));
	free(err);
}

/* A recording with another colour layout cannot be served as polarcam-sim-colour. */
static void test_serve_refuses_layout(void)
{
	char dir[160];
	snprintf(dir, sizeof dir, "%s/bggr", base);
	pc_recording_desc d;
	memset(&d, 0, sizeof d);
	d.format = PC_FMT_MONO12;
	d.width = d.sensor_width = 16;
	d.height = d.sensor_height = 8;
	d.polarized = true;
	CHECK_EQ_INT(pc_mosaic_parse("BGGR:90,45,135,0", &d.mosaic), 0);
	pc_recording *r = NULL;
	CHECK_EQ_INT(pc_recording_create(&r, dir, &d, false), 0);
	pc_frame f;
	memset(&f, 0, sizeof f);
	CHECK_EQ_INT(pc_view_alloc(&f.view, PC_FMT_MONO12, 16, 8, 64), 0);
	if (r)
		CHECK_EQ_INT(pc_recording_add(r, &f), 0);
	if (r)
		CHECK_EQ_INT(pc_recording_finish(r, NULL), 0);
	pc_recording_free(r);
	pc_view_free(&f.view);
	char src[200], errp[160], out[2048];
	snprintf(src, sizeof src, "file:%s?loop=1", dir);
	snprintf(errp, sizeof errp, "%s/serve_bggr.err", base);
	char *argv[] = {(char *)polarcam, "serve", "--source", src, NULL};
	int fd;
	pid_t pid = spawn(argv, &fd, errp);
	CHECK(pid > 0);
	if (pid <= 0)
		return;
	CHECK(!wait_line(fd, "\"serving\"", START_MS, out, sizeof out));
	CHECK(pc_child_wait(pid, EXIT_MS, NULL) != 0);
	close(fd);
	char *err = read_text(errp);
	CHECK(err && strstr(err, "BGGR:90,45,135,0") && strstr(err, "RGGB:90,45,135,0"));
	if (err && !strstr(err, "BGGR"))
		fprintf(stderr, "serve said: %s\n", err);
	free(err);
}

int main(void)
{
	polarcam = getenv("POLARCAM");
	const char *src = getenv("PC_SOURCE_DIR");
	if (!polarcam || !src)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	snprintf(scene, sizeof scene, "%s/scenes/colour_small.json", src);
	if (!pc_test_tmpdir(base, sizeof base, "pc_gigec"))
		SKIP("no temporary directory");
	if (run_render() == 0) {
		char seed[16], errp[160], ready[1024];
		snprintf(seed, sizeof seed, "%d", SEED);
		snprintf(errp, sizeof errp, "%s/serve.err", base);
		char *args[] = {scene, "--seed", seed, "--fps", "50", NULL};
		int fd;
		pid_t srv = serve_start(polarcam, args, errp, &fd, ready, sizeof ready);
		CHECK(srv > 0);
		if (srv > 0) {
			CHECK(strstr(ready, "\"model\":\"polarcam-sim-colour\"") &&
			      strstr(ready, "\"mosaic\":\"RGGB:90,45,135,0\""));
			test_description();
			test_client();
			test_compliance();
			test_capture();
			test_process();
			CHECK_EQ_INT(stop_server(srv, fd), 0);
		}
		test_serve_refuses_layout();
	}
	for (int k = 0; k < NREF; k++)
		pc_view_free(&ref[k]);
	pc_devices_shutdown();
	char cmd[200];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", base);
	return pc_test_finish("gige_colour");
}
