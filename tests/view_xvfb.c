/* polarcam view in a real X server (Xvfb): the window shows the three panels. The test takes an
 * X screenshot of the root window with xwd, decodes it (XWD, below) and compares the window's
 * pixels with the picture `view --screenshot` wrote of the same frames (the scene is rendered
 * by an ideal, noise-free sensor, so every frame is the same picture). Exit 77 when Xvfb or xwd
 * is missing. */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <png.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "check.h"
#include "children.h"

static void nap_ms(long ms)
{
	struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
	nanosleep(&ts, NULL);
}

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Starts argv (tests/children.h: it dies with this test) with stdout to out_path (NULL:
 * inherited) and stderr to err_path. */
static pid_t spawn(char *const argv[], const char *out_path, const char *err_path)
{
	int o = out_path ? open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644) : -1;
	pid_t pid = pc_child_spawn(argv, o, err_path);
	if (o >= 0)
		close(o);
	return pid;
}

/* Reads Xvfb's display number from the -displayfd pipe: it is written once the server accepts
 * connections. Returns -1 when Xvfb ends or nothing arrives within timeout_s. */
static int read_display(int fd, double timeout_s)
{
	char buf[32];
	size_t len = 0;
	double t0 = now_s();
	while (now_s() - t0 < timeout_s && len < sizeof buf - 1) {
		struct pollfd pf = {fd, POLLIN, 0};
		if (poll(&pf, 1, 200) <= 0)
			continue;
		ssize_t n = read(fd, buf + len, sizeof buf - 1 - len);
		if (n <= 0)
			return -1;
		len += (size_t)n;
		buf[len] = '\0';
		if (strchr(buf, '\n'))
			return atoi(buf);
	}
	return -1;
}

static uint32_t be32(const uint8_t *p)
{
	return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

typedef struct img {
	uint32_t w, h;
	uint8_t *rgb;
} img;

/* X Window Dump (X11 XWDFileHeader, version 7): 25 big-endian CARD32 fields, the window name,
 * ncolors 12-byte colour entries, then bytes_per_line * height of ZPixmap data. */
static int read_xwd(const char *path, img *out)
{
	FILE *fp = fopen(path, "rb");
	if (!fp)
		return -1;
	uint8_t h[100];
	int rc = -1;
	if (fread(h, 1, 100, fp) == 100) {
		uint32_t hsize = be32(h), version = be32(h + 4), format = be32(h + 8);
		uint32_t w = be32(h + 16), ht = be32(h + 20), byte_order = be32(h + 28);
		uint32_t bpp = be32(h + 44), bpl = be32(h + 48), rmask = be32(h + 56);
		uint32_t gmask = be32(h + 60), bmask = be32(h + 64), ncolors = be32(h + 76);
		uint32_t bytes_pp = bpp / 8; /* Xvfb's 24-bit screens: 3 bytes, lines padded */
		if (version == 7 && format == 2 && (bpp == 32 || bpp == 24) && w && ht &&
		    w < 10000 && ht < 10000 && bpl >= bytes_pp * w &&
		    fseek(fp, (long)hsize + 12L * ncolors, SEEK_SET) == 0) {
			uint8_t *line = malloc(bpl);
			out->w = w;
			out->h = ht;
			out->rgb = malloc((size_t)w * ht * 3);
			rc = 0;
			for (uint32_t y = 0; y < ht && !rc; y++) {
				if (fread(line, 1, bpl, fp) != bpl) {
					rc = -1;
					break;
				}
				for (uint32_t x = 0; x < w; x++) {
					const uint8_t *p = line + bytes_pp * x;
					uint32_t v = 0;
					for (uint32_t b = 0; b < bytes_pp;
					     b++) /* byte_order 1: MSB first */
						v |= (uint32_t)p[b]
						     << (8 * (byte_order ? bytes_pp - 1 - b : b));
					uint8_t *o = out->rgb + ((size_t)y * w + x) * 3;
					o[0] = (uint8_t)((v & rmask) >> __builtin_ctz(rmask));
					o[1] = (uint8_t)((v & gmask) >> __builtin_ctz(gmask));
					o[2] = (uint8_t)((v & bmask) >> __builtin_ctz(bmask));
				}
			}
			free(line);
		}
	}
	fclose(fp);
	return rc;
}

static int read_png_rgb(const char *path, img *out)
{
	png_image im;
	memset(&im, 0, sizeof im);
	im.version = PNG_IMAGE_VERSION;
	if (!png_image_begin_read_from_file(&im, path))
		return -1;
	im.format = PNG_FORMAT_RGB;
	out->w = im.width;
	out->h = im.height;
	out->rgb = malloc(PNG_IMAGE_SIZE(im));
	if (!png_image_finish_read(&im, NULL, out->rgb, 0, NULL)) {
		png_image_free(&im);
		return -1;
	}
	return 0;
}

int main(void)
{
	const char *polarcam = getenv("POLARCAM"), *src = getenv("PC_SOURCE_DIR");
	if (!polarcam || !src)
		SKIP("POLARCAM / PC_SOURCE_DIR not set: run through ctest");
	if (system("command -v Xvfb >/dev/null && command -v xwd >/dev/null") != 0)
		SKIP("Xvfb or xwd missing (Debian: xvfb, x11-apps)");
	char tmp[64];
	if (!pc_test_tmpdir(tmp, sizeof tmp, "pc_view"))
		SKIP("no temporary directory");
	/* Xvfb picks a free display itself (-displayfd) and writes its number when it is ready:
	 * two builds' tests running at once cannot take the same display, and nothing is guessed
	 * from lock files or sleeps */
	char xerr[96];
	snprintf(xerr, sizeof xerr, "%s/xvfb.err", tmp);
	int dp[2];
	if (pipe(dp))
		SKIP("no pipe");
	char dfd[16];
	snprintf(dfd, sizeof dfd, "%d", dp[1]);
	char *xargv[] = {"Xvfb",        "-displayfd", dfd,   "-screen", "0",
	                 "2400x900x24", "-nolisten",  "tcp", NULL};
	pid_t xsrv = spawn(xargv, NULL, xerr);
	close(dp[1]);
	int dpy = xsrv > 0 ? read_display(dp[0], 120) : -1;
	close(dp[0]);
	if (dpy < 0) {
		fprintf(stderr, "Xvfb did not start (its messages: %s)\n", xerr);
		return 1;
	}
	char dname[16];
	snprintf(dname, sizeof dname, ":%d", dpy);
	setenv("DISPLAY", dname, 1);

	char uri[600], shot[96], xwd_path[96], out[96], cmd[1400];
	snprintf(uri, sizeof uri, "sim:%s/scenes/ideal_small.json?fps=15", src);
	snprintf(shot, sizeof shot, "%s/expected.png", tmp);
	snprintf(xwd_path, sizeof xwd_path, "%s/screen.xwd", tmp);
	snprintf(out, sizeof out, "%s/view.json", tmp);
	/* the picture the window must show: the same view, headless (every frame of this
	 * noise-free scene is the same picture) */
	snprintf(cmd, sizeof cmd,
	         "env -u DISPLAY '%s' view '%s' --width 1200 --frames 1 "
	         "--screenshot '%s' >/dev/null",
	         polarcam, uri, shot);
	CHECK_EQ_INT(system(cmd), 0);
	img pic = {0};
	CHECK_EQ_INT(read_png_rgb(shot, &pic), 0);
	CHECK_EQ_INT(pic.w, 1200);

	char verr[96];
	snprintf(verr, sizeof verr, "%s/view.err", tmp);
	char *vargv[] = {(char *)polarcam, "view", uri, "--width", "1200", NULL};
	pid_t v = spawn(vargv, out, verr);
	/* screenshots of the root window until the picture is on screen (rows below the overlay
	 * text; the window's position is searched), the window's program ends, or 120 s pass
	 * (a loaded machine running the sanitizer build starts Qt slowly) */
	img screen = {0};
	uint32_t best = 0, total = 0, bx = 0, by = 0;
	char *wargv[] = {"xwd", "-root", "-silent", "-display", dname, NULL};
	for (uint32_t y = 40; y < pic.h; y += 23)
		for (uint32_t x = 0; x < pic.w; x += 17)
			total++;
	int vst = -1;
	double t0 = now_s();
	for (int i = 0; now_s() - t0 < 120 && pic.rgb && best < total * 99 / 100; i++) {
		nap_ms(500);
		if (waitpid(v, &vst, WNOHANG) == v) {
			pc_child_forget(v);
			fprintf(stderr,
			        "view ended before its window showed the picture (status "
			        "%d; its messages: %s)\n",
			        vst, verr);
			v = -1;
			break;
		}
		free(screen.rgb);
		screen.rgb = NULL;
		if (pc_child_wait(spawn(wargv, xwd_path, NULL), 60000, NULL) != 0 ||
		    read_xwd(xwd_path, &screen) != 0)
			continue;
		best = 0;
		for (uint32_t oy = 0; oy + pic.h <= screen.h && oy < 80; oy++)
			for (uint32_t ox = 0; ox + pic.w <= screen.w && ox < 200; ox++) {
				uint32_t same = 0;
				for (uint32_t y = 40; y < pic.h; y += 23)
					for (uint32_t x = 0; x < pic.w; x += 17)
						same += !memcmp(
						    pic.rgb + ((size_t)y * pic.w + x) * 3,
						    screen.rgb +
						        ((size_t)(y + oy) * screen.w + x + ox) * 3,
						    3);
				if (same > best) {
					best = same;
					bx = ox;
					by = oy;
				}
			}
		if (getenv("PC_TEST_VERBOSE"))
			printf("screenshot %d: best %u of %u at (%u,%u)\n", i, best, total, bx, by);
	}
	printf("window at (%u,%u): %u of %u sampled pixels equal the picture\n", bx, by, best,
	       total);
	CHECK(best >= total * 99 / 100);
	CHECK(v > 0);
	if (v > 0)
		CHECK_EQ_INT(pc_child_stop(v, SIGTERM, 60000), 0);
	pc_child_stop(xsrv, SIGTERM, 60000);
	free(pic.rgb);
	free(screen.rgb);
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("view_xvfb");
}
