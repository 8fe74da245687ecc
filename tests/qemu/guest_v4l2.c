/* guest_v4l2.c - the V4L2 checks that run inside the QEMU guest against the real vivid driver.
 *
 * Started by tests/qemu/run-guest.sh as the guest's only program after vivid was loaded with
 * n_devs=1 node_types=0x101 (a capture and an output node). Prints one line per check:
 * "PASS name: what was seen", "FAIL name: why", "SKIP name: why"; exits 0 only when every check
 * passed. The checks run in one boot, in an order that leaves the destructive ones (fatal error,
 * disconnect) for last.
 */

#include <errno.h>
#include <glob.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>
#include <time.h>

#include "guest_common.h"
#include "polarcam/compliance.h"
#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"
#include "polarcam/source.h"
#include "polarcam/v4l2.h"

static char cap_path[256], out_path[256];   /* the single-planar vivid instance */
static char mcap_path[256], mout_path[256]; /* the multi-planar one (multiplanar=2) */

/* ---- helpers ---- */

static uint32_t fcc(const char *s)
{
	return PC_FOURCC(s[0], s[1], s[2], s[3]);
}

/* The capture node on `input`, with vivid's on-screen text off so that frames hold only the
 * test pattern (or, in loopback, only what was sent). */
static pc_v4l2 *open_capture(const char *check, unsigned input)
{
	pc_v4l2 *dev;
	if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev)) {
		gt_fail(check, "open: %s", pc_error_detail());
		return NULL;
	}
	if (pc_v4l2_select_io(dev, input)) {
		gt_fail(check, "input %u: %s", input, pc_error_detail());
		pc_v4l2_close(dev);
		return NULL;
	}
	pc_v4l2_ctrl c;
	if (pc_v4l2_ctrl_find(dev, "OSD Text Mode", &c) == 0 && pc_v4l2_ctrl_set(dev, c.id, 2)) {
		gt_fail(check, "OSD Text Mode: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return NULL;
	}
	return dev;
}

static int set_cvt(pc_v4l2 *dev, uint32_t w, uint32_t h, double fps, pc_dv_timings *got)
{
	pc_dv_timings t;
	int rc = pc_dv_timings_cvt_rb2(w, h, fps, &t);
	if (!rc)
		rc = pc_v4l2_set_dv_timings(dev, &t);
	if (!rc && got)
		rc = pc_v4l2_get_dv_timings(dev, got);
	return rc;
}

static pc_view buffer_view(const pc_v4l2_format *f, void *data)
{
	pc_view v = {data, f->width, f->height, f->bytesperline, f->format};
	return v;
}

typedef struct capture_stats {
	unsigned frames, errors, gaps;
	uint32_t first_seq, last_seq;
	uint64_t first_ts, last_ts;
	unsigned seq_back, seq_repeat, ts_back;
	uint16_t vmin, vmax;
	double seconds;
} capture_stats;

/* Streams n frames from dev (format already set), checking every frame: bytesused, sequence
 * and timestamp order, and - through pc_view_to_u16 - that no value exceeds the format's bit
 * depth (Y10/Y12 hold LSB-aligned values). Returns 0 or the PC_E* code with its detail set. */
static int capture_frames(pc_v4l2 *dev, unsigned n, capture_stats *st, uint8_t *first_copy)
{
	memset(st, 0, sizeof *st);
	st->vmin = UINT16_MAX;
	pc_v4l2_format f;
	int rc = pc_v4l2_get_format(dev, &f);
	if (rc)
		return rc;
	uint16_t *row16 = malloc((size_t)f.width * f.height * 2);
	if (!row16)
		return pc_error(PC_ENOMEM, "out of memory");
	rc = pc_v4l2_stream_start(dev, 4);
	double t0 = gt_now();
	for (unsigned i = 0; !rc && i < n; i++) {
		pc_v4l2_buffer b;
		rc = pc_v4l2_dequeue(dev, 5000, &b);
		if (rc)
			break;
		if (b.error)
			st->errors++;
		if (b.bytesused < f.sizeimage)
			rc = pc_error(PC_EIO, "frame %u: bytesused %zu < sizeimage %zu", i,
			              b.bytesused, f.sizeimage);
		if (i == 0) {
			st->first_seq = b.sequence;
			st->first_ts = b.timestamp_ns;
			if (!b.timestamp_monotonic)
				rc =
				    pc_error(PC_EIO, "frame 0: timestamps are not CLOCK_MONOTONIC");
		} else {
			/* vivid, lagging under emulation, can give two consecutive buffers the
			 * same sequence number: counted, not an error; going back is. */
			if ((uint32_t)(b.sequence - st->last_seq) == 0)
				st->seq_repeat++;
			else if ((uint32_t)(b.sequence - st->last_seq) > 0x80000000u)
				st->seq_back++;
			else if (b.sequence != st->last_seq + 1)
				st->gaps += b.sequence - st->last_seq - 1;
			if (b.timestamp_ns <= st->last_ts)
				st->ts_back++;
		}
		if (getenv("PC_GUEST_VERBOSE"))
			gt_info("frame %u: index %u seq %u ts %llu bytesused %zu", i, b.index,
			        b.sequence, (unsigned long long)b.timestamp_ns, b.bytesused);
		st->last_seq = b.sequence;
		st->last_ts = b.timestamp_ns;
		pc_view v = buffer_view(&f, b.data);
		if (!rc)
			rc = pc_view_to_u16(&v, row16, (size_t)f.width * 2);
		if (!rc) {
			for (size_t k = 0; k < (size_t)f.width * f.height; k++) {
				if (row16[k] < st->vmin)
					st->vmin = row16[k];
				if (row16[k] > st->vmax)
					st->vmax = row16[k];
			}
			if (i == 0 && first_copy)
				for (uint32_t y = 0; y < f.height; y++)
					memcpy(first_copy + (size_t)y * f.width * 2,
					       row16 + (size_t)y * f.width, (size_t)f.width * 2);
			st->frames++;
		}
		int rq = pc_v4l2_queue(dev, b.index, 0);
		if (!rc)
			rc = rq;
	}
	st->seconds = gt_now() - t0;
	free(row16);
	int rs = pc_v4l2_stream_stop(dev);
	return rc ? rc : rs;
}

/* ---- the checks ---- */

static void check_list(void)
{
	pc_v4l2_node *nodes = NULL;
	size_t n = 0;
	int rc = pc_v4l2_list("/dev", &nodes, &n);
	if (rc) {
		gt_fail("list", "pc_v4l2_list: %s", pc_error_detail());
		return;
	}
	for (size_t i = 0; i < n; i++) {
		const pc_v4l2_node *d = &nodes[i];
		gt_info("node %s: driver=%s card='%s' bus=%s capture=%d output=%d formats=%zu%s%s",
		        d->info.path, d->info.driver, d->info.card, d->info.bus_info,
		        d->info.capture, d->info.output, d->nformats_total,
		        d->error ? " error: " : "", d->error ? d->error_detail : "");
		if (strcmp(d->info.driver, "vivid") != 0 || d->error)
			continue;
		if (d->info.capture && !cap_path[0])
			snprintf(cap_path, sizeof cap_path, "%s", d->info.path);
		if (d->info.output && !out_path[0])
			snprintf(out_path, sizeof out_path, "%s", d->info.path);
		if (d->info.capture_mplane && !mcap_path[0])
			snprintf(mcap_path, sizeof mcap_path, "%s", d->info.path);
		if (d->info.output_mplane && !mout_path[0])
			snprintf(mout_path, sizeof mout_path, "%s", d->info.path);
	}
	free(nodes);
	if (cap_path[0] && out_path[0])
		gt_pass("list",
		        "%zu nodes; vivid capture %s, output %s; multi-planar capture %s, "
		        "output %s",
		        n, cap_path, out_path, mcap_path[0] ? mcap_path : "none",
		        mout_path[0] ? mout_path : "none");
	else
		gt_fail("list", "no vivid capture+output pair among %zu nodes", n);
}

static void check_formats(void)
{
	pc_v4l2 *dev;
	if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev)) {
		gt_fail("formats", "%s", pc_error_detail());
		return;
	}
	uint32_t f[128];
	size_t n = 0;
	if (pc_v4l2_enum_formats(dev, f, 128, &n)) {
		gt_fail("formats", "%s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	const char *want[] = {"GREY", "Y10 ", "Y12 ", "Y16 "};
	int found = 0;
	char list[1024] = "", all[1024] = "", b[5];
	for (size_t i = 0; i < n && i < 128; i++) {
		strncat(all, " ", sizeof all - strlen(all) - 1);
		strncat(all, pc_fourcc_str(f[i], b), sizeof all - strlen(all) - 1);
		if (pc_format_from_v4l2(f[i]) != PC_FMT_INVALID) {
			strncat(list, " ", sizeof list - strlen(list) - 1);
			strncat(list, pc_fourcc_str(f[i], b), sizeof list - strlen(list) - 1);
		}
		for (int k = 0; k < 4; k++)
			if (f[i] == fcc(want[k]))
				found++;
	}
	gt_info("capture formats:%s", all);
	if (found == 4)
		gt_pass("formats", "%zu capture formats, polarcam reads%s", n, list);
	else
		gt_fail("formats", "only %d of GREY/Y10/Y12/Y16 among %zu formats", found, n);
	pc_v4l2_close(dev);
}

/* Valid / adjusted / invalid answers from the driver on the webcam input. */
static void check_negotiation(void)
{
	const char *name = "negotiate";
	pc_v4l2 *dev = open_capture(name, 0);
	if (!dev)
		return;
	pc_v4l2_format g, g2;
	int bad = 0;
	if (pc_v4l2_try_format(dev, fcc("GREY"), 640, 480, 0, &g) || g.fourcc != fcc("GREY") ||
	    g.width != 640 || g.height != 480 || g.format != PC_FMT_MONO8 || g.bytesperline < 640) {
		gt_fail(name, "GREY 640x480 not accepted as asked: %s", pc_error_detail());
		bad++;
	}
	if (pc_v4l2_try_format(dev, fcc("Y16 "), 641, 479, 0, &g) ||
	    (g.width == 641 && g.height == 479) ||
	    pc_v4l2_try_format(dev, g.fourcc, g.width, g.height, 0, &g2) || g2.width != g.width ||
	    g2.height != g.height || g.format != PC_FMT_MONO16) {
		gt_fail(name,
		        "Y16 641x479: expected an adjusted size that is then accepted (got %ux%u)",
		        g.width, g.height);
		bad++;
	} else {
		gt_info("Y16 641x479 adjusted to %ux%u", g.width, g.height);
	}
	/* A fourcc vivid does not offer: the driver substitutes one polarcam cannot read (YUYV);
	 * set_format must refuse rather than stream garbage. */
	int rc = pc_v4l2_try_format(dev, PC_FOURCC('P', 'C', 'Z', 'Z'), 640, 480, 0, &g);
	char b[5];
	if (rc || g.fourcc == PC_FOURCC('P', 'C', 'Z', 'Z')) {
		gt_fail(name, "unknown fourcc: try_format rc %d fourcc %s", rc,
		        pc_fourcc_str(g.fourcc, b));
		bad++;
	}
	rc = pc_v4l2_set_format(dev, PC_FOURCC('P', 'C', 'Z', 'Z'), 640, 480, 0, &g);
	if (rc != PC_EFORMAT) {
		gt_fail(name, "set_format with an unknown fourcc returned %s, expected PC_EFORMAT",
		        pc_errname(rc));
		bad++;
	} else {
		gt_info("unknown fourcc refused: %s", pc_error_detail());
	}
	if (!bad)
		gt_pass(name,
		        "GREY 640x480 valid, Y16 641x479 adjusted to %ux%u, unknown fourcc -> "
		        "PC_EFORMAT",
		        g2.width, g2.height);
	pc_v4l2_close(dev);
}

static void check_capture(const char *fourcc, uint32_t w, uint32_t h, unsigned input, unsigned n)
{
	char name[64];
	snprintf(name, sizeof name, "capture-%.4s-%ux%u", fourcc, w, h);
	for (char *p = name; *p; p++)
		if (*p == ' ')
			*p = '_';
	pc_v4l2 *dev = open_capture(name, input);
	if (!dev)
		return;
	if (input == 3 && set_cvt(dev, w, h, 30.0, NULL)) {
		gt_fail(name, "DV timings: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	pc_v4l2_format g;
	if (pc_v4l2_set_format(dev, fcc(fourcc), w, h, 0, &g)) {
		gt_fail(name, "set_format: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	if (g.width != w || g.height != h || g.fourcc != fcc(fourcc)) {
		gt_fail(name, "driver answered %ux%u", g.width, g.height);
		pc_v4l2_close(dev);
		return;
	}
	capture_stats st;
	int rc = capture_frames(dev, n, &st, NULL);
	const pc_format_info *fi = pc_format_info_get(g.format);
	unsigned maxv = fi->bits >= 16 ? 65535u : (1u << fi->bits) - 1u;
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (st.frames != n || st.seq_back || st.ts_back || st.errors)
		gt_fail(name,
		        "%u/%u frames, %u sequence reversals, %u timestamp reversals, %u error "
		        "flags",
		        st.frames, n, st.seq_back, st.ts_back, st.errors);
	else if (st.vmax <= st.vmin || st.vmax > maxv)
		gt_fail(name, "values %u..%u (a %u-bit format holds 0..%u)", st.vmin, st.vmax,
		        fi->bits, maxv);
	else
		gt_pass(name,
		        "%u frames, bytesperline %zu, seq %u..%u (%u dropped, %u repeated), values "
		        "%u..%u of %u, %.1f frames/s",
		        st.frames, g.bytesperline, st.first_seq, st.last_seq, st.gaps,
		        st.seq_repeat, st.vmin, st.vmax, maxv,
		        (st.frames - 1) / (st.last_ts - st.first_ts > 0
		                               ? (double)(st.last_ts - st.first_ts) * 1e-9
		                               : 1.0));
	pc_v4l2_close(dev);
}

/* A padded stride asked of the driver (vivid honours bytesperline) must give the same image. */
static void check_stride(void)
{
	const char *name = "stride";
	pc_v4l2 *dev = open_capture(name, 0);
	if (!dev)
		return;
	const uint32_t w = 640, h = 480;
	uint8_t *a = malloc((size_t)w * h * 2), *b = malloc((size_t)w * h * 2);
	pc_v4l2_format g1, g2;
	capture_stats st;
	int rc = !a || !b ? pc_error(PC_ENOMEM, "out of memory") : 0;
	if (!rc)
		rc = pc_v4l2_set_format(dev, fcc("GREY"), w, h, 0, &g1);
	if (!rc)
		rc = capture_frames(dev, 2, &st, a);
	if (!rc)
		rc = pc_v4l2_set_format(dev, fcc("GREY"), w, h, 704, &g2);
	if (!rc)
		rc = capture_frames(dev, 2, &st, b);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (g2.bytesperline != 704)
		gt_skip(name, "the driver ignored bytesperline 704 (answered %zu)",
		        g2.bytesperline);
	else if (memcmp(a, b, (size_t)w * h * 2) != 0)
		gt_fail(name, "the image read with bytesperline 704 differs from bytesperline %zu",
		        g1.bytesperline);
	else
		gt_pass(name, "GREY 640x480 with bytesperline %zu and %zu: identical images",
		        g1.bytesperline, g2.bytesperline);
	free(a);
	free(b);
	pc_v4l2_close(dev);
}

static void check_controls(void)
{
	const char *name = "controls";
	pc_v4l2 *dev = open_capture(name, 0);
	if (!dev)
		return;
	int bad = 0;
	pc_v4l2_ctrl c;
	int64_t v = -1;
	if (pc_v4l2_ctrl_query(dev, 0x00980912u /* AUTOGAIN */, &c) == 0 &&
	    pc_v4l2_ctrl_set(dev, c.id, 0)) {
		gt_fail(name, "autogain off: %s", pc_error_detail());
		bad++;
	}
	if (pc_v4l2_ctrl_query(dev, PC_V4L2_CID_GAIN, &c)) {
		gt_fail(name, "gain: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	int64_t target = c.minimum + (c.maximum - c.minimum) / 3;
	if (pc_v4l2_ctrl_set(dev, c.id, target) || pc_v4l2_ctrl_get(dev, c.id, &v) || v != target) {
		gt_fail(name, "gain %lld: read back %lld (%s)", (long long)target, (long long)v,
		        pc_error_detail());
		bad++;
	}
	int rc = pc_v4l2_ctrl_set(dev, c.id, c.maximum + 1);
	int64_t after = -1;
	pc_v4l2_ctrl_get(dev, c.id, &after);
	if (rc != PC_ERANGE || after != target) {
		gt_fail(name,
		        "gain above maximum: %s, value now %lld (expected PC_ERANGE, unchanged)",
		        pc_errname(rc), (long long)after);
		bad++;
	}
	rc = pc_v4l2_ctrl_query(dev, PC_V4L2_CID_EXPOSURE_ABSOLUTE, &c);
	if (rc != PC_ENOENT && rc != 0) {
		gt_fail(name, "exposure query: %s", pc_error_detail());
		bad++;
	}
	double fps = 0, got = 0, back = 0;
	pc_v4l2_format g;
	if (pc_v4l2_set_format(dev, fcc("GREY"), 640, 480, 0, &g) ||
	    pc_v4l2_get_frame_rate(dev, &fps) || pc_v4l2_set_frame_rate(dev, 15.0, &got) ||
	    pc_v4l2_get_frame_rate(dev, &back) || back != got) {
		gt_fail(name, "frame rate: %s (was %g, set 15 -> %g, read %g)", pc_error_detail(),
		        fps, got, back);
		bad++;
	}
	if (!bad)
		gt_pass(name,
		        "gain %lld set and read back, %lld refused with PC_ERANGE and left "
		        "unchanged, exposure %s, frame rate %g -> asked 15 -> %g fps",
		        (long long)target, (long long)target + 0,
		        rc == 0 ? "present" : "absent (vivid)", fps, got);
	pc_v4l2_close(dev);
}

/* Our CVT reduced-blanking v2 timings against the kernel's own detection (vivid replaces
 * custom timings by what v4l2_detect_cvt() computes from the totals). */
static void check_dv_timings(void)
{
	const char *name = "dv-timings";
	pc_v4l2 *dev = open_capture(name, 3);
	if (!dev)
		return;
	static const uint32_t sizes[][2] = {{1920, 1080}, {2448, 2048}, {1280, 1024}};
	int bad = 0;
	for (int i = 0; i < 3; i++) {
		pc_dv_timings mine, kern;
		if (pc_dv_timings_cvt_rb2(sizes[i][0], sizes[i][1], 30.0, &mine) ||
		    set_cvt(dev, sizes[i][0], sizes[i][1], 30.0, &kern)) {
			gt_fail(name, "%ux%u: %s", sizes[i][0], sizes[i][1], pc_error_detail());
			bad++;
			continue;
		}
		/* The kernel rebuilds the pixel clock from an integer line frequency
		 * (pixelclock / total width, truncated) and rounds it down to 1 kHz, so it may
		 * differ from the exact CVT value by up to one line-width's worth of Hz plus 1 kHz.
		 */
		uint64_t total_w =
		    (uint64_t)mine.width + mine.hfrontporch + mine.hsync + mine.hbackporch;
		uint64_t dclk = mine.pixelclock_hz > kern.pixelclock_hz
		                    ? mine.pixelclock_hz - kern.pixelclock_hz
		                    : kern.pixelclock_hz - mine.pixelclock_hz;
		pc_dv_timings k2 = kern;
		k2.pixelclock_hz = mine.pixelclock_hz;
		if (memcmp(&mine, &k2, sizeof mine) != 0 || dclk > total_w + 1000) {
			gt_fail(
			    name,
			    "%ux%u: ours pclk %llu vfp %u vbp %u, kernel pclk %llu vfp %u vbp %u",
			    sizes[i][0], sizes[i][1], (unsigned long long)mine.pixelclock_hz,
			    mine.vfrontporch, mine.vbackporch,
			    (unsigned long long)kern.pixelclock_hz, kern.vfrontporch,
			    kern.vbackporch);
			bad++;
		} else {
			gt_info("CVT RB2 %ux%u@30: pclk %llu Hz (kernel %llu), vfp %u, %.3f fps",
			        mine.width, mine.height, (unsigned long long)mine.pixelclock_hz,
			        (unsigned long long)kern.pixelclock_hz, mine.vfrontporch,
			        pc_dv_timings_fps(&mine));
		}
	}
	if (!bad)
		gt_pass(name,
		        "CVT RB v2 timings for 1920x1080, 2448x2048, 1280x1024 equal the kernel's "
		        "v4l2_detect_cvt() (every porch and sync; pixel clock within the kernel's "
		        "rounding)");
	pc_v4l2_close(dev);
}

/* ---- through the frame-source API: v4l2:/dev/videoN ---- */

static int source_uri(char *buf, size_t size, const char *opts)
{
	return snprintf(buf, size, "v4l2:%s%s%s", cap_path, opts && *opts ? "?" : "",
	                opts ? opts : "");
}

/* Opens the source and negotiates fmt exactly (try must say valid), allocates 4 buffers. */
static pc_source *source_setup(const char *name, const char *opts, pc_pixfmt pf, uint32_t w,
                               uint32_t h, pc_source_format *got)
{
	char uri[512];
	source_uri(uri, sizeof uri, opts);
	pc_source *src = NULL;
	int rc = pc_source_open(&src, uri);
	pc_source_format f;
	pc_format_verdict v = PC_FORMAT_INVALID;
	if (!rc) {
		memset(&f, 0, sizeof f);
		f.format = pf;
		f.width = w;
		f.height = h;
		rc = pc_source_try_format(src, &f, &v);
	}
	if (!rc && v != PC_FORMAT_VALID)
		rc = pc_error(PC_EFORMAT, "%s %ux%u: verdict %s (%s)", pc_format_info_get(pf)->name,
		              w, h, pc_format_verdict_name(v), pc_error_detail());
	if (!rc)
		rc = pc_source_set_format(src, &f);
	if (!rc)
		rc = pc_source_buffers_alloc(src, 4);
	if (rc) {
		gt_fail(name, "%s: %s", uri, pc_error_detail());
		pc_source_close(src);
		return NULL;
	}
	pc_source_get_format(src, got);
	return src;
}

/* Frames through pc_source: pc_frame with view, metadata and mosaic. */
static void check_source_capture(pc_pixfmt pf, uint32_t w, uint32_t h, unsigned input, unsigned n)
{
	char name[64], opts[64];
	snprintf(name, sizeof name, "source-%s-%ux%u", pc_format_info_get(pf)->name, w, h);
	snprintf(opts, sizeof opts, "input=%u", input);
	pc_source_format f;
	pc_source *src = source_setup(name, opts, pf, w, h, &f);
	if (!src)
		return;
	uint16_t *u16 = malloc((size_t)w * h * 2);
	int rc = u16 ? pc_source_start(src) : pc_error(PC_ENOMEM, "out of memory");
	unsigned frames = 0, bad_mosaic = 0;
	uint64_t first = 0, last = 0;
	uint16_t vmax = 0;
	pc_mosaic want = pc_mosaic_imx250mzr();
	for (unsigned i = 0; !rc && i < n; i++) {
		pc_buffer *b;
		rc = pc_source_dequeue(src, 5000, &b);
		if (rc)
			break;
		const pc_frame *fr = &b->frame;
		if (i == 0)
			first = fr->meta.sequence;
		last = fr->meta.sequence;
		if (fr->mosaic.period != 2 ||
		    memcmp(fr->mosaic.channel, want.channel, sizeof want.channel))
			bad_mosaic++;
		rc = pc_view_to_u16(&fr->view, u16, (size_t)w * 2);
		for (size_t k = 0; !rc && k < (size_t)w * h; k++)
			if (u16[k] > vmax)
				vmax = u16[k];
		frames++;
		int rq = pc_source_requeue(src, b);
		if (!rc)
			rc = rq;
	}
	pc_source_stats st;
	int rs = pc_source_stop(src);
	if (!rc)
		rc = rs;
	if (!rc)
		rc = pc_source_get_stats(src, &st);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (frames != n || bad_mosaic || st.completed != n || vmax == 0)
		gt_fail(name,
		        "%u frames, %u with a wrong mosaic, stats completed %llu, max value %u",
		        frames, bad_mosaic, (unsigned long long)st.completed, vmax);
	else
		gt_pass(name,
		        "%u pc_frames (%s, stride %zu, IMX250MZR mosaic), sequence %llu..%llu, "
		        "stats: completed %llu dropped %llu failed %llu",
		        frames, f.format_name, f.stride, (unsigned long long)first,
		        (unsigned long long)last, (unsigned long long)st.completed,
		        (unsigned long long)st.dropped, (unsigned long long)st.failed);
	free(u16);
	pc_source_close(src);
}

/* Format names in a request: V4L2 fourccs, polarcam/GenICam names and vendors' polarized names
 * resolve through the format table; an unknown fourcc is adjusted to one the node offers. */
static void check_source_names(void)
{
	const char *name = "source-format-names";
	char uri[512];
	source_uri(uri, sizeof uri, "input=0");
	pc_source *src = NULL;
	if (pc_source_open(&src, uri)) {
		gt_fail(name, "%s: %s", uri, pc_error_detail());
		return;
	}
	static const struct {
		const char *req;
		pc_format_verdict want;
		pc_pixfmt fmt;
	} cases[] = {
	    {"Y16", PC_FORMAT_VALID, PC_FMT_MONO16},
	    {"Mono12", PC_FORMAT_VALID, PC_FMT_MONO12},
	    {"PolarizeMono12", PC_FORMAT_VALID, PC_FMT_MONO12},
	    {"Polarized8", PC_FORMAT_VALID, PC_FMT_MONO8},
	    {"Y10P", PC_FORMAT_ADJUSTED, PC_FMT_MONO10}, /* vivid has no packed formats */
	    {"XYZW", PC_FORMAT_ADJUSTED, PC_FMT_INVALID},
	};
	int bad = 0;
	for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
		pc_source_format f;
		memset(&f, 0, sizeof f);
		snprintf(f.format_name, sizeof f.format_name, "%s", cases[i].req);
		f.width = 640;
		f.height = 480;
		pc_format_verdict v = PC_FORMAT_INVALID;
		int rc = pc_source_try_format(src, &f, &v);
		gt_info("'%s' -> %s %s (%s)", cases[i].req, pc_format_verdict_name(v),
		        f.format_name, rc ? pc_error_detail() : "ok");
		if (rc || v != cases[i].want ||
		    (cases[i].fmt != PC_FMT_INVALID && f.format != cases[i].fmt)) {
			gt_fail(name, "'%s': %s verdict %s format %d", cases[i].req, pc_errname(rc),
			        pc_format_verdict_name(v), (int)f.format);
			bad++;
		}
	}
	if (!bad)
		gt_pass(name,
		        "Y16, Mono12, PolarizeMono12, Polarized8 valid; Y10P adjusted to Y10; "
		        "unknown fourcc adjusted to an offered format");
	pc_source_close(src);
}

/* Frame rate and exposure/gain through the source's controls on the webcam input. */
static void check_source_controls(void)
{
	const char *name = "source-controls";
	pc_source_format f;
	pc_source *src = source_setup(name, "input=0&gain_db_step=0.1", PC_FMT_MONO8, 640, 480, &f);
	if (!src)
		return;
	pc_control_info ci;
	double applied = 0, back = 0, g = 0;
	int bad = 0;
	int rc =
	    pc_source_buffers_free(src); /* frame rate changes need OPEN/READY without streaming */
	if (!rc)
		rc = pc_source_control_query(src, PC_CTRL_FRAME_RATE_HZ, &ci);
	if (!rc)
		rc = pc_source_control_set(src, PC_CTRL_FRAME_RATE_HZ, ci.max, &applied);
	if (!rc)
		rc = pc_source_control_get(src, PC_CTRL_FRAME_RATE_HZ, &back);
	if (rc || applied != ci.max || back != applied) {
		gt_fail(name, "frame rate: %s (range %g..%g step %g, set max -> %g, read %g)",
		        pc_error_detail(), ci.min, ci.max, ci.step, applied, back);
		bad++;
	}
	rc = pc_source_control_set(src, PC_CTRL_FRAME_RATE_HZ, ci.max * 2 + 1, NULL);
	if (rc != PC_ERANGE) {
		gt_fail(name, "frame rate above the range: %s", pc_errname(rc));
		bad++;
	}
	pc_control_info gi;
	rc = pc_source_control_query(src, PC_CTRL_GAIN_DB, &gi);
	if (!rc)
		rc = pc_source_control_set(src, PC_CTRL_GAIN_DB, 5.0, &applied);
	if (!rc)
		rc = pc_source_control_get(src, PC_CTRL_GAIN_DB, &g);
	if (rc || fabs(applied - 5.0) > 1e-9 || fabs(g - 5.0) > 1e-9) {
		gt_fail(name, "gain_db: %s (range %g..%g, set 5 -> %g, read %g)", pc_error_detail(),
		        gi.min, gi.max, applied, g);
		bad++;
	}
	pc_control_info ei;
	rc = pc_source_control_query(src, PC_CTRL_EXPOSURE_US, &ei);
	if (rc != PC_ENOTSUP) {
		gt_fail(name, "exposure on vivid (which has none): %s", pc_errname(rc));
		bad++;
	}
	/* the frames' gain: the value set (setting it turned vivid's autogain off); with autogain
	 * turned on again (through a second handle, as another program would) unknown, NAN */
	double fg[2] = {NAN, 0};
	for (int k = 0; k < 2 && !bad; k++) {
		pc_v4l2 *dev = k ? open_capture(name, 0) : NULL;
		rc = k && !dev ? PC_EIO : 0;
		pc_v4l2_ctrl c;
		if (!rc && dev && pc_v4l2_ctrl_query(dev, 0x00980912u /* AUTOGAIN */, &c) == 0)
			rc = pc_v4l2_ctrl_set(dev, c.id, 1);
		if (dev)
			pc_v4l2_close(dev);
		if (!rc && !(rc = pc_source_buffers_alloc(src, 4)) &&
		    !(rc = pc_source_start(src))) {
			pc_buffer *b;
			if (!(rc = pc_source_dequeue(src, 5000, &b))) {
				fg[k] = b->frame.meta.gain_db;
				rc = pc_source_requeue(src, b);
			}
			pc_source_stop(src);
		}
		if (!rc)
			rc = pc_source_buffers_free(src);
	}
	if (!bad && (rc || fabs(fg[0] - 5.0) > 1e-9 || !isnan(fg[1]))) {
		gt_fail(name,
		        "frames' gain_db %g with the gain set, %g with autogain on (expected 5, "
		        "NaN): %s",
		        fg[0], fg[1], rc ? pc_error_detail() : "");
		bad++;
	}
	if (!bad)
		gt_pass(name,
		        "frame rate %g..%g Hz (step %g) set to %g and read back, out of range -> "
		        "PC_ERANGE; gain_db %g..%g set 5 dB = raw 50, frames say 5 dB, with "
		        "autogain on unknown (%g); exposure: PC_ENOTSUP (%s)",
		        ci.min, ci.max, ci.step, back, gi.min, gi.max, fg[1], pc_error_detail());
	pc_source_close(src);
}

typedef struct comp_ctx {
	const char *name;
	pc_v4l2 *trigger_dev; /* fault to press when streaming starts */
	uint32_t trigger_id;
	bool triggered;
} comp_ctx;

static void comp_log(void *vctx, pc_check_result r, const char *check, const char *detail)
{
	comp_ctx *c = vctx;
	if (r == PC_CHECK_FAIL)
		gt_fail(c->name, "%s: %s", check, detail);
	else
		gt_info("%s %s: %s", r == PC_CHECK_PASS ? "ok  " : "skip", check, detail);
	if (c->trigger_dev && !c->triggered && !strcmp(check, "stream: start")) {
		c->triggered = true;
		if (pc_v4l2_ctrl_set(c->trigger_dev, c->trigger_id, 1))
			gt_fail(c->name, "could not inject the fault: %s", pc_error_detail());
	}
}

/* The devices area's compliance test against `v4l2:`; faults come from vivid's own error
 * injection: a control set before the run (drops) or pressed when streaming starts. */
static void check_compliance(const char *name, const char *opts, pc_fault_kind fault,
                             const char *vivid_ctrl, int64_t value, bool at_start)
{
	comp_ctx c = {name, NULL, 0, false};
	pc_v4l2 *dev = NULL;
	pc_v4l2_ctrl ctl;
	if (vivid_ctrl) {
		if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev) ||
		    pc_v4l2_ctrl_find(dev, vivid_ctrl, &ctl)) {
			gt_skip(name, "vivid control '%s': %s", vivid_ctrl, pc_error_detail());
			pc_v4l2_close(dev);
			return;
		}
		if (at_start) {
			c.trigger_dev = dev;
			c.trigger_id = ctl.id;
		} else if (pc_v4l2_ctrl_set(dev, ctl.id, value)) {
			gt_fail(name, "%s = %lld: %s", vivid_ctrl, (long long)value,
			        pc_error_detail());
			pc_v4l2_close(dev);
			return;
		}
	}
	char uri[512];
	source_uri(uri, sizeof uri, opts);
	pc_compliance_options o;
	memset(&o, 0, sizeof o);
	o.frames = 10;
	o.expect_fault = fault;
	o.log = comp_log;
	o.log_ctx = &c;
	pc_compliance_result res;
	int rc = pc_source_compliance(uri, &o, &res);
	if (dev && !at_start)
		pc_v4l2_ctrl_set(dev, ctl.id, 0);
	pc_v4l2_close(dev);
	if (rc)
		gt_fail(name, "%s: %s", uri, pc_error_detail());
	else if (res.failed)
		gt_fail(name, "%s: %u of %u checks failed, first: %s", uri, res.failed,
		        res.passed + res.failed, res.first_failure);
	else
		gt_pass(name, "%s: %u checks passed, %u skipped (fault: %s)", uri, res.passed,
		        res.skipped, pc_fault_name(fault));
}

/* A deterministic polarizer-mosaic frame: what an IMX250MZR-layout sensor records of a scene
 * whose intensity S0 ramps along x, degree of linear polarization along y and angle of
 * polarization along x (turned by k * 22.5 degrees in frame k). Each pixel sees its analyser
 * angle theta from the mosaic table: I = (S0 + S1 cos 2theta + S2 sin 2theta) / 2
 * (Malus's law for an ideal linear analyser, physics.md section 1). Values span the format. */
static void mosaic_pattern(uint16_t *dst, uint32_t w, uint32_t h, unsigned bits, unsigned k)
{
	/* Per column and analyser channel the two terms of Malus's law, in 1/256 units; per row
	 * only integer arithmetic (the guest's floating point is emulated in software). */
	const double pi = 3.14159265358979323846;
	pc_mosaic m = pc_mosaic_imx250mzr();
	const int64_t full = (int64_t)((1u << bits) - 1u);
	int64_t *p = malloc(w * sizeof *p), *q = malloc(4 * (size_t)w * sizeof *q);
	if (!p || !q) {
		free(p);
		free(q);
		memset(dst, 0, (size_t)w * h * 2);
		return;
	}
	for (uint32_t x = 0; x < w; x++) {
		double aolp = pi * (double)x / (double)w + (double)k * pi / 8.0;
		double half_s0 = 0.5 * (double)full * (0.15 + 0.8 * (double)x / (double)(w - 1));
		p[x] = llround(256.0 * half_s0);
		for (unsigned c = 0; c < 4; c++) {
			double theta = (pi / 4.0) * c;
			q[c * w + x] = llround(256.0 * half_s0 *
			                       (cos(2.0 * aolp) * cos(2.0 * theta) +
			                        sin(2.0 * aolp) * sin(2.0 * theta)));
		}
	}
	for (uint32_t y = 0; y < h; y++) {
		int64_t dolp16 =
		    (int64_t)(0.9 * 65536.0 * (double)y / (double)(h - 1)); /* DoLP, Q16 */
		uint16_t *row = dst + (size_t)y * w;
		for (uint32_t x = 0; x < w; x++) {
			unsigned c = pc_mosaic_channel(&m, x, y);
			int64_t v = (p[x] + ((q[c * w + x] * dolp16) >> 16) + 128) >> 8;
			row[x] = (uint16_t)(v < 0 ? 0 : v > full ? full : v);
		}
	}
	free(p);
	free(q);
}

/* vivid's video loopback: frames written to the HDMI output come back on the HDMI input. Both
 * ends get the same CVT timings; "Loop Video" on, on-screen text off. The output side is driven
 * through the node layer, the capture side through the `v4l2:` frame source: every pc_frame
 * must equal, value for value after unpacking, one of the frames we sent. */
enum { NOUT = 4 };

/* ref: NOUT frames (w x h uint16, values within the format's bits) to send; NULL = generate
 * mosaic_pattern() frames. what: where the frames come from, for the report. */
static void check_loop(const char *tag, const char *fourcc, uint32_t w, uint32_t h, unsigned n,
                       uint16_t *const given[NOUT], const char *what)
{
	char name[64];
	snprintf(name, sizeof name, "loop-%s-%.4s-%ux%u", tag, fourcc, w, h);
	for (char *p = name; *p; p++)
		if (*p == ' ')
			*p = '_';
	pc_pixfmt pf = pc_format_from_v4l2(fcc(fourcc));
	pc_v4l2 *cap = open_capture(name, 3), *out = NULL;
	pc_source *src = NULL;
	uint16_t *ref[NOUT] = {NULL}, *got = NULL;
	pc_v4l2_format fo;
	pc_v4l2_ctrl loopc;
	int rc = cap ? 0 : PC_EIO;
	/* device-wide state prepared through the node layer: timings, loop control */
	if (!rc)
		rc = set_cvt(cap, w, h, 30.0, NULL);
	if (!rc)
		rc = pc_v4l2_ctrl_find(cap, "Loop Video", &loopc);
	if (!rc)
		rc = pc_v4l2_ctrl_set(cap, loopc.id, 1);
	pc_v4l2_close(cap);
	if (!rc)
		rc = pc_v4l2_open(out_path, PC_V4L2_OUTPUT, &out);
	if (!rc)
		rc = pc_v4l2_select_io(out, 1);
	if (!rc)
		rc = set_cvt(out, w, h, 30.0, NULL);
	if (!rc)
		rc = pc_v4l2_set_format(out, fcc(fourcc), w, h, 0, &fo);
	if (!rc && (fo.width != w || fo.height != h))
		rc = pc_error(PC_EINVAL, "output format %ux%u", fo.width, fo.height);
	unsigned bits = pf != PC_FMT_INVALID ? pc_format_info_get(pf)->bits : 8;
	size_t npix = (size_t)w * h;
	for (int k = 0; !rc && k < NOUT; k++) {
		ref[k] = malloc(npix * 2);
		if (!ref[k])
			rc = pc_error(PC_ENOMEM, "out of memory");
		else if (given)
			memcpy(ref[k], given[k], npix * 2);
		else
			mosaic_pattern(ref[k], w, h, bits, (unsigned)k);
	}
	got = rc ? NULL : malloc(npix * 2);
	if (!rc && !got)
		rc = pc_error(PC_ENOMEM, "out of memory");
	if (!rc)
		rc = pc_v4l2_stream_start(out, NOUT);
	/* fill every output buffer; buffer i carries pattern i for the whole run */
	for (unsigned i = 0; !rc && i < pc_v4l2_buffer_count(out) && i < NOUT; i++) {
		pc_v4l2_buffer b;
		rc = pc_v4l2_output_acquire(out, 1000, &b);
		if (rc)
			break;
		pc_view v = buffer_view(&fo, b.data);
		rc = pc_view_from_u16(ref[b.index % NOUT], (size_t)w * 2, &v);
		if (!rc)
			rc = pc_v4l2_queue(out, b.index, 0);
	}
	pc_source_format fc;
	if (!rc) {
		src = source_setup(name, "input=3", pf, w, h, &fc);
		if (!src) {
			pc_v4l2_close(out);
			return; /* source_setup reported it */
		}
		rc = pc_source_start(src);
	}
	unsigned match = 0, frames = 0;
	double t0 = gt_now();
	for (unsigned i = 0; !rc && i < n; i++) {
		pc_buffer *b;
		rc = pc_source_dequeue(src, 5000, &b);
		if (rc)
			break;
		rc = pc_view_to_u16(&b->frame.view, got, (size_t)w * 2);
		/* the reference whose middle row matches is compared in full first (a full compare
		 * against every reference costs seconds under emulation), the others only if needed
		 */
		int which = -1, first = 0;
		size_t mid = (size_t)(h / 2) * w;
		for (int k = 0; k < NOUT; k++)
			if (memcmp(got + mid, ref[k] + mid, (size_t)w * 2) == 0) {
				first = k;
				break;
			}
		for (int j = 0; !rc && j < NOUT && which < 0; j++) {
			int k = (first + j) % NOUT;
			if (memcmp(got, ref[k], npix * 2) == 0)
				which = k;
		}
		frames++;
		if (which >= 0)
			match++;
		if (getenv("PC_GUEST_VERBOSE"))
			gt_info("captured seq %llu: pattern %d",
			        (unsigned long long)b->frame.meta.sequence, which);
		int rq = pc_source_requeue(src, b);
		if (!rc)
			rc = rq;
		/* hand consumed output buffers straight back (their pattern is unchanged) */
		pc_v4l2_buffer ob;
		while (!rc && pc_v4l2_output_acquire(out, 0, &ob) == 0)
			rc = pc_v4l2_queue(out, ob.index, 0);
	}
	double secs = gt_now() - t0;
	if (src)
		pc_source_stop(src);
	if (out)
		pc_v4l2_stream_stop(out);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (match != n)
		gt_fail(name, "%u of %u captured frames equal a frame we sent", match, frames);
	else
		gt_pass(name,
		        "%u/%u pc_frames from v4l2: byte-identical to the %s sent (stride out "
		        "%zu, in %zu; %.1f frames/s)",
		        match, n, what, fo.bytesperline, fc.stride, n / secs);
	for (int k = 0; k < NOUT; k++)
		free(ref[k]);
	free(got);
	pc_source_close(src);
	pc_v4l2_close(out);
}

/* The simulator's frames rendered on the host (tests/qemu/simframes.c) sent through the loop as
 * Y12 (the sensor's 12 bits). Frames 0..2 of seed 7 fill output buffers 0..3 (frame 0 twice). */
static void check_loop_sim(const char *dir)
{
	const char *name = "loop-sim";
	char path[512];
	snprintf(path, sizeof path, "%s/sim.txt", dir);
	FILE *f = fopen(path, "r");
	unsigned w = 0, h = 0, bits = 0, n = 0;
	unsigned long long seed = 0;
	if (!f || fscanf(f, "%u %u %u %u %llu", &w, &h, &bits, &n, &seed) != 5 || !w || !h || !n ||
	    bits > 16) {
		gt_fail(name, "%s: missing or malformed", path);
		if (f)
			fclose(f);
		return;
	}
	fclose(f);
	uint16_t *frames[NOUT] = {NULL};
	size_t bytes = (size_t)w * h * 2;
	int ok = 1;
	for (unsigned k = 0; ok && k < NOUT; k++) {
		frames[k] = malloc(bytes);
		snprintf(path, sizeof path, "%s/sim_%u.raw", dir, k % n);
		f = fopen(path, "rb");
		ok = frames[k] && f && fread(frames[k], 1, bytes, f) == bytes;
		if (f)
			fclose(f);
	}
	if (!ok) {
		gt_fail(name, "%s: cannot read %zu bytes", path, bytes);
	} else {
		const char *fourcc = bits <= 8    ? "GREY"
		                     : bits <= 10 ? "Y10 "
		                     : bits <= 12 ? "Y12 "
		                                  : "Y16 ";
		char what[96];
		snprintf(what, sizeof what,
		         "simulator's raw frames (default scene, seed %llu, %u-bit)", seed, bits);
		check_loop("sim", fourcc, w, h, 10, frames, what);
	}
	for (unsigned k = 0; k < NOUT; k++)
		free(frames[k]);
}

static volatile sig_atomic_t ticks;
static void on_tick(int sig)
{
	(void)sig;
	ticks++;
}

/* A signal every millisecond during streaming (handler installed without SA_RESTART, so poll()
 * and ioctl() return EINTR): no error may leak out and no frame may be lost to it. */
static void check_eintr(void)
{
	const char *name = "eintr";
	pc_v4l2 *dev = open_capture(name, 0);
	if (!dev)
		return;
	pc_v4l2_format g;
	struct sigaction sa, old;
	memset(&sa, 0, sizeof sa);
	sa.sa_handler = on_tick;
	sigemptyset(&sa.sa_mask);
	sa.sa_flags = 0;
	struct itimerval it = {{0, 1000}, {0, 1000}}, off = {{0, 0}, {0, 0}};
	int rc = pc_v4l2_set_format(dev, fcc("GREY"), 640, 480, 0, &g);
	capture_stats st;
	if (!rc) {
		sigaction(SIGALRM, &sa, &old);
		setitimer(ITIMER_REAL, &it, NULL);
		rc = capture_frames(dev, 8, &st, NULL);
		setitimer(ITIMER_REAL, &off, NULL);
		sigaction(SIGALRM, &old, NULL);
	}
	if (rc)
		gt_fail(name, "%s (after %d signals)", pc_error_detail(), (int)ticks);
	else if (ticks < 20 || st.frames != 8)
		gt_fail(name, "%d signals, %u frames", (int)ticks, st.frames);
	else
		gt_pass(name, "8 frames while %d SIGALRM interrupted the waits", (int)ticks);
	pc_v4l2_close(dev);
}

/* vivid starts its 32-bit sequence 128 frames before the wrap: through `v4l2:` the 64-bit
 * sequence must run on across 2^32, strictly increasing, with drops counted sanely. */
static void check_source_seq_wrap(void)
{
	const char *name = "source-sequence-wrap";
	pc_v4l2 *dev = NULL;
	pc_v4l2_ctrl c;
	if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev) ||
	    pc_v4l2_ctrl_find(dev, "Wrap Sequence Number", &c) || pc_v4l2_ctrl_set(dev, c.id, 1)) {
		gt_skip(name, "vivid 'Wrap Sequence Number': %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	pc_source_format f;
	pc_source *src = source_setup(name, "input=3&dv=640x480@60", PC_FMT_MONO8, 640, 480, &f);
	int rc = src ? pc_source_start(src) : PC_EIO;
	uint64_t first = 0, last = 0;
	unsigned frames = 0, back = 0;
	const uint64_t wrap = 0x100000000ull;
	while (!rc && frames < 600 && last < wrap + 8) {
		pc_buffer *b;
		rc = pc_source_dequeue(src, 5000, &b);
		if (rc)
			break;
		uint64_t sq = b->frame.meta.sequence;
		if (frames == 0)
			first = sq;
		else if (sq <= last)
			back++;
		last = sq;
		frames++;
		rc = pc_source_requeue(src, b);
	}
	pc_source_stats st;
	memset(&st, 0, sizeof st);
	if (src) {
		pc_source_stop(src);
		pc_source_get_stats(src, &st);
	}
	if (rc && src)
		gt_fail(name, "after %u frames: %s", frames, pc_error_detail());
	else if (src && (first < wrap - 256 || first >= wrap || last < wrap + 8 || back ||
	                 st.dropped + frames != last - first + 1))
		gt_fail(name, "sequence %llu..%llu over %u frames, %u not increasing, dropped %llu",
		        (unsigned long long)first, (unsigned long long)last, frames, back,
		        (unsigned long long)st.dropped);
	else if (src)
		gt_pass(name,
		        "sequence %llu -> %llu across 2^32 in %u frames, strictly increasing, "
		        "dropped %llu (= the gaps)",
		        (unsigned long long)first, (unsigned long long)last, frames,
		        (unsigned long long)st.dropped);
	pc_source_close(src);
	pc_v4l2_ctrl_set(dev, c.id, 0);
	pc_v4l2_close(dev);
}

/* ---- vivid's error injection (controls present unless vivid was loaded with no_error_inj) ---- */

/* Opens the webcam input in GREY 640x480, finds control `ctrl`; NULL with a SKIP/FAIL printed. */
static pc_v4l2 *fault_setup(const char *name, const char *ctrl, pc_v4l2_ctrl *c)
{
	pc_v4l2 *dev = open_capture(name, 0);
	if (!dev)
		return NULL;
	pc_v4l2_format g;
	if (pc_v4l2_set_format(dev, fcc("GREY"), 640, 480, 0, &g)) {
		gt_fail(name, "set_format: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return NULL;
	}
	if (pc_v4l2_ctrl_find(dev, ctrl, c)) {
		gt_skip(name, "vivid has no '%s' control (loaded with no_error_inj=1?)", ctrl);
		pc_v4l2_close(dev);
		return NULL;
	}
	return dev;
}

static void check_fault_error_flag(void)
{
	const char *name = "fault-buffer-error";
	pc_v4l2_ctrl c;
	pc_v4l2 *dev = fault_setup(name, "Inject V4L2_BUF_FLAG_ERROR", &c);
	if (!dev)
		return;
	int rc = pc_v4l2_stream_start(dev, 4);
	unsigned flagged = 0, frames = 0;
	for (unsigned i = 0; !rc && i < 6; i++) {
		if (i == 1)
			rc = pc_v4l2_ctrl_set(dev, c.id, 1);
		pc_v4l2_buffer b;
		if (!rc)
			rc = pc_v4l2_dequeue(dev, 5000, &b);
		if (rc)
			break;
		frames++;
		flagged += b.error;
		rc = pc_v4l2_queue(dev, b.index, 0);
	}
	pc_v4l2_stream_stop(dev);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (flagged != 1)
		gt_fail(name, "%u of %u frames carried V4L2_BUF_FLAG_ERROR after one injection",
		        flagged, frames);
	else
		gt_pass(name, "one injected error: exactly 1 of %u frames flagged", frames);
	pc_v4l2_close(dev);
}

static void check_fault_drops(void)
{
	const char *name = "fault-dropped";
	pc_v4l2_ctrl c;
	pc_v4l2 *dev = fault_setup(name, "Percentage of Dropped Buffers", &c);
	if (!dev)
		return;
	capture_stats st;
	int rc = pc_v4l2_ctrl_set(dev, c.id, 50);
	if (!rc)
		rc = capture_frames(dev, 12, &st, NULL);
	pc_v4l2_ctrl_set(dev, c.id, 0);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (st.gaps == 0 || st.seq_back)
		gt_fail(name, "50%% dropped: %u sequence gaps, %u reversals over %u frames",
		        st.gaps, st.seq_back, st.frames);
	else
		gt_pass(name,
		        "50%% dropped by the driver: %u frames received, sequence %u..%u shows %u "
		        "missing",
		        st.frames, st.first_seq, st.last_seq, st.gaps);
	pc_v4l2_close(dev);
}

static void check_fault_seq_wrap(void)
{
	const char *name = "fault-sequence-wrap";
	pc_v4l2_ctrl c;
	pc_v4l2 *dev = fault_setup(name, "Wrap Sequence Number", &c);
	if (!dev)
		return;
	capture_stats st;
	int rc = pc_v4l2_ctrl_set(dev, c.id, 1);
	if (!rc)
		rc = capture_frames(dev, 3, &st, NULL);
	pc_v4l2_ctrl_set(dev, c.id, 0);
	if (rc)
		gt_fail(name, "%s", pc_error_detail());
	else if (st.first_seq < 0xffff0000u)
		gt_fail(name, "first sequence %u, expected just below 2^32", st.first_seq);
	else
		gt_pass(name, "the driver starts at sequence %u (%u below 2^32)", st.first_seq,
		        (unsigned)(0u - st.first_seq));
	pc_v4l2_close(dev);
}

/* A fatal driver error (vb2_queue_error) and a disconnect must surface as errors, not hangs. */
static void check_fault_fatal(const char *name, const char *ctrl, int expect)
{
	pc_v4l2_ctrl c;
	pc_v4l2 *dev = fault_setup(name, ctrl, &c);
	if (!dev)
		return;
	int rc = pc_v4l2_stream_start(dev, 4);
	pc_v4l2_buffer b;
	if (!rc)
		rc = pc_v4l2_dequeue(dev, 5000, &b);
	if (!rc)
		rc = pc_v4l2_queue(dev, b.index, 0);
	if (!rc)
		rc = pc_v4l2_ctrl_set(dev, c.id, 1);
	if (rc) {
		gt_fail(name, "before the fault: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	unsigned before = 0;
	for (unsigned i = 0; i < 8 && rc == 0; i++) {
		rc = pc_v4l2_dequeue(dev, 3000, &b);
		if (!rc) {
			before++;
			rc = pc_v4l2_queue(dev, b.index, 0);
		}
	}
	if (rc == expect)
		gt_pass(name, "%s after %u more frames: %s", pc_errname(rc), before,
		        pc_error_detail());
	else
		gt_fail(name, "expected %s, got %s (%s)", pc_errname(expect), pc_errname(rc),
		        rc ? pc_error_detail() : "no error in 8 frames");
	int rs = pc_v4l2_stream_stop(dev);
	if (rs)
		gt_fail(name, "stream_stop after the fault: %s", pc_error_detail());
	pc_v4l2_close(dev);
}

/* ---- the polarcam command line inside the guest ---- */

/* Runs cmd through the shell, returns its exit status and up to size-1 bytes of its stdout. */
static int run_cmd(const char *cmd, char *out, size_t size)
{
	FILE *p = popen(cmd, "r");
	if (!p)
		return -1;
	size_t n = 0;
	int c;
	while ((c = fgetc(p)) != EOF)
		if (n + 1 < size)
			out[n++] = (char)c;
	out[n] = '\0';
	int st = pclose(p);
	return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void check_cli_devices(const char *cli)
{
	const char *name = "cli-devices";
	char cmd[512], out[16384];
	snprintf(cmd, sizeof cmd, "%s devices --json 2>&1", cli);
	int st = run_cmd(cmd, out, sizeof out);
	char want_cap[300];
	snprintf(want_cap, sizeof want_cap, "\"uri\":\"v4l2:%s\"", cap_path);
	const char *line = strstr(out, want_cap);
	const char *eol = line ? strchr(line, '\n') : NULL;
	char l[2048] = "";
	if (line)
		snprintf(l, sizeof l, "%.*s", eol ? (int)(eol - line) : (int)strlen(line), line);
	if (st != 0 || !line)
		gt_fail(name, "exit %d, no entry for %s in: %.300s", st, cap_path, out);
	else if (!strstr(l, "\"formats\":[\"GREY\",\"Y10\",\"Y12\",\"Y16\"]") ||
	         !strstr(l, "\"usable\":true") || !strstr(l, "\"vendor\":\"vivid\""))
		gt_fail(name, "%s entry: %s", cap_path, l);
	else
		gt_pass(name, "polarcam devices --json lists %s: %.200s", cap_path, strchr(l, '"'));
}

/* "key": false anywhere in a JSON text (whitespace allowed around the colon) */
static bool json_false(const char *text, const char *key)
{
	char k[64];
	snprintf(k, sizeof k, "\"%s\"", key);
	for (const char *p = strstr(text, k); p; p = strstr(p + 1, k)) {
		const char *q = p + strlen(k);
		while (*q == ' ' || *q == '\n' || *q == '\t')
			q++;
		if (*q != ':')
			continue;
		q++;
		while (*q == ' ' || *q == '\n' || *q == '\t')
			q++;
		if (!strncmp(q, "false", 5))
			return true;
	}
	return false;
}

static bool file_exists(const char *path)
{
	FILE *f = fopen(path, "rb");
	if (f)
		fclose(f);
	return f != NULL;
}

static void check_cli_capture(const char *cli)
{
	const char *name = "cli-capture";
	char cmd[512], out[4096];
	snprintf(cmd, sizeof cmd,
	         "%s capture 'v4l2:%s?input=0' -n 3 -o /tmp/cap --format Mono16 "
	         "--roi 0,0,640,480 2>&1",
	         cli, cap_path);
	int st = run_cmd(cmd, out, sizeof out);
	if (st != 0 || !file_exists("/tmp/cap/raw_000002.png") ||
	    !file_exists("/tmp/cap/meta.json"))
		gt_fail(name, "exit %d: %.400s", st, out);
	else
		gt_pass(name,
		        "polarcam capture v4l2: 3 frames Mono16 640x480 -> raw_00000[0-2].png + "
		        "meta.json: %.200s",
		        out);
}

/* A camera that disappears mid-stream: vivid's Disconnect while `polarcam capture` records. The
 * command must fail with a clear error and keep what it recorded. */
static void check_cli_disconnect(const char *cli)
{
	const char *name = "cli-capture-disconnect";
	pc_v4l2 *dev = NULL;
	pc_v4l2_ctrl c;
	if (pc_v4l2_open(cap_path, PC_V4L2_CAPTURE, &dev) ||
	    pc_v4l2_ctrl_find(dev, "Disconnect", &c)) {
		gt_skip(name, "vivid Disconnect control: %s", pc_error_detail());
		pc_v4l2_close(dev);
		return;
	}
	char cmd[512];
	snprintf(cmd, sizeof cmd,
	         "%s capture 'v4l2:%s?input=0' -n 400 -o /tmp/capd --format Mono8 "
	         "--roi 0,0,640,480 > /tmp/capd.out 2> /tmp/capd.err; echo $? > "
	         "/tmp/capd.status",
	         cli, cap_path);
	pid_t pid = fork();
	if (pid == 0) {
		execl("/bin/sh", "sh", "-c", cmd, (char *)NULL);
		_exit(127);
	}
	/* wait until a few frames are on disk, then pull the plug. The recording is made in a
	 * temporary sibling folder (/tmp/.capd.tmp-HOST-PID-XXXXXX, polarcam/io.h's pc_outdir)
	 * and renamed to /tmp/capd only when capture ends: the frames show up there first. Had
	 * the wait looked only at /tmp/capd, it would time out while the 400 frames were
	 * recorded and press Disconnect too late (the run exited 0 with 400 frames). */
	double t0 = gt_now();
	bool seen = false;
	while (!seen && gt_now() - t0 < 60.0) {
		glob_t g;
		memset(&g, 0, sizeof g);
		seen = glob("/tmp/.capd.tmp-*/raw_000002.png", 0, NULL, &g) == 0 ||
		       file_exists("/tmp/capd/raw_000002.png");
		globfree(&g);
		if (!seen)
			usleep(20000);
	}
	int rc = pc_v4l2_ctrl_set(dev, c.id, 1);
	int status = 0;
	waitpid(pid, &status, 0);
	pc_v4l2_close(dev);
	static char out[65536];
	char err[2048] = "";
	out[0] = '\0';
	FILE *f = fopen("/tmp/capd.status", "r");
	int st = -1;
	if (f) {
		if (fscanf(f, "%d", &st) != 1)
			st = -1;
		fclose(f);
	}
	f = fopen("/tmp/capd.err", "r");
	if (f) {
		size_t n = fread(err, 1, sizeof err - 1, f);
		err[n] = '\0';
		fclose(f);
	}
	f = fopen("/tmp/capd/meta.json", "r");
	if (f) {
		size_t n = fread(out, 1, sizeof out - 1, f);
		out[n] = '\0';
		fclose(f);
	}
	if (rc)
		gt_fail(name, "pressing Disconnect: %s", pc_error_detail());
	else if (!seen)
		gt_fail(name,
		        "no third frame within 60 s (neither /tmp/capd nor its temporary "
		        "folder); exit %d, stderr: %.300s",
		        st, err);
	else if (st != 1 || !strstr(err, "disconnect") ||
	         !file_exists("/tmp/capd/raw_000002.png") || !json_false(out, "complete"))
		gt_fail(name, "exit %d, stderr: %.300s, meta.json: %.200s", st, err, out);
	else
		gt_pass(name,
		        "exit 1 after the disconnect, frames kept, meta.json complete=false; "
		        "stderr: %.200s",
		        err);
}

int main(int argc, char **argv)
{
	const char *sim_dir = NULL, *cli = NULL;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--sim") && i + 1 < argc) {
			sim_dir = argv[++i];
		} else if (!strcmp(argv[i], "--cli") && i + 1 < argc) {
			cli = argv[++i];
		} else {
			fprintf(stderr, "usage: %s [--sim DIR] [--cli POLARCAM]\n", argv[0]);
			return 2;
		}
	}
	setvbuf(stdout, NULL, _IONBF, 0);
	gt_info("guest: polarcam V4L2 checks against vivid");
	check_list();
	if (!cap_path[0])
		return gt_finish();
	check_formats();
	check_negotiation();
	check_capture("GREY", 640, 480, 0, 6);
	check_capture("Y10 ", 640, 480, 0, 6);
	check_capture("Y12 ", 640, 480, 0, 6);
	check_capture("Y16 ", 640, 480, 0, 6);
	check_stride();
	check_controls();
	check_dv_timings();
	check_capture("GREY", 2448, 2048, 3, 6);
	check_capture("Y16 ", 2448, 2048, 3, 6);
	check_loop("pattern", "GREY", 2448, 2048, 10, NULL, "mosaic pattern frames");
	check_loop("pattern", "Y16 ", 2448, 2048, 10, NULL, "mosaic pattern frames");
	if (sim_dir)
		check_loop_sim(sim_dir);
	else
		gt_skip("loop-sim", "no simulator frames given (--sim DIR)");
	check_source_capture(PC_FMT_MONO8, 640, 480, 0, 6);
	check_source_capture(PC_FMT_MONO16, 640, 480, 0, 6);
	check_source_names();
	/* the same through the multi-planar API (vivid's second instance, multiplanar=2) */
	if (mcap_path[0] && mout_path[0]) {
		char keep_cap[256], keep_out[256];
		memcpy(keep_cap, cap_path, sizeof keep_cap);
		memcpy(keep_out, out_path, sizeof keep_out);
		memcpy(cap_path, mcap_path, sizeof cap_path);
		memcpy(out_path, mout_path, sizeof out_path);
		gt_prefix = "mplane-";
		check_capture("Y12 ", 640, 480, 0, 4);
		check_source_capture(PC_FMT_MONO16, 640, 480, 0, 4);
		check_loop("pattern", "GREY", 1920, 1080, 6, NULL, "mosaic pattern frames");
		check_compliance("compliance", "input=3&dv=640x480@60", PC_FAULT_NONE, NULL, 0,
		                 false);
		gt_prefix = "";
		memcpy(cap_path, keep_cap, sizeof cap_path);
		memcpy(out_path, keep_out, sizeof out_path);
	} else {
		gt_fail("mplane", "vivid's multi-planar instance has no capture+output nodes");
	}
	check_source_controls();
	check_compliance("compliance", "input=3&dv=640x480@60&gain_db_step=0.1", PC_FAULT_NONE,
	                 NULL, 0, false);
	check_compliance("compliance-drop", "input=3&dv=640x480@60", PC_FAULT_DROP,
	                 "Percentage of Dropped Buffers", 50, false);
	check_compliance("compliance-corrupt", "input=3&dv=640x480@60", PC_FAULT_CORRUPT,
	                 "Inject V4L2_BUF_FLAG_ERROR", 1, true);
	if (cli) {
		check_cli_devices(cli);
		check_cli_capture(cli);
	} else {
		gt_skip("cli", "no polarcam binary given (--cli PATH)");
	}
	check_eintr();
	check_fault_error_flag();
	check_fault_drops();
	check_fault_seq_wrap();
	check_source_seq_wrap();
	check_fault_fatal("fault-fatal", "Inject Fatal Streaming Error", PC_EIO);
	check_fault_fatal("fault-disconnect", "Disconnect", PC_EDISCONNECTED);
	/* vivid registers its nodes again once the last user closed them */
	if (cli)
		check_cli_disconnect(cli);
	check_compliance("compliance-disconnect", "input=3&dv=640x480@60", PC_FAULT_DISCONNECT,
	                 "Disconnect", 1, true);
	return gt_finish();
}
