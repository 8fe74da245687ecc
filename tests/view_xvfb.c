/* polarcam view in a real X server (Xvfb): the window shows the three panels. The test takes an
 * X screenshot of the root window with xwd, decodes it (XWD, below) and compares the window's
 * pixels with the picture `view --screenshot` wrote of the same frames (the scene is rendered
 * by an ideal, noise-free sensor, so every frame is the same picture). Exit 77 when Xvfb or xwd
 * is missing. */
#include <errno.h>
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

static void nap_ms(long ms)
{
	struct timespec ts = {ms / 1000, (ms % 1000) * 1000000L};
	nanosleep(&ts, NULL);
}

static pid_t spawn(char *const argv[], const char *out_path)
{
	pid_t pid = fork();
	if (pid == 0) {
		FILE *o = out_path ? freopen(out_path, "w", stdout) : NULL;
		(void)o;
		FILE *e = freopen("/dev/null", "w", stderr);
		(void)e;
		execvp(argv[0], argv);
		_exit(127);
	}
	return pid;
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
	char tmp[] = "/tmp/pc_view_XXXXXX";
	if (!mkdtemp(tmp))
		SKIP("no temporary directory");
	/* a display number nobody uses */
	int dpy = 0;
	char sock[64];
	for (dpy = 77; dpy < 120; dpy++) {
		snprintf(sock, sizeof sock, "/tmp/.X11-unix/X%d", dpy);
		if (access(sock, F_OK) != 0)
			break;
	}
	char dname[16];
	snprintf(dname, sizeof dname, ":%d", dpy);
	char *xargv[] = {"Xvfb", dname, "-screen", "0", "2400x900x24", "-nolisten", "tcp", NULL};
	pid_t xsrv = spawn(xargv, NULL);
	for (int i = 0; i < 100 && access(sock, F_OK) != 0; i++)
		nap_ms(100);
	if (access(sock, F_OK) != 0) {
		kill(xsrv, SIGKILL);
		waitpid(xsrv, NULL, 0);
		SKIP("Xvfb did not start");
	}
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

	char *vargv[] = {(char *)polarcam, "view", uri, "--width", "1200", NULL};
	pid_t v = spawn(vargv, out);
	/* screenshots of the root window until the picture is on screen (rows below the overlay
	 * text; the window's position is searched) or 30 s pass */
	img screen = {0};
	uint32_t best = 0, total = 0, bx = 0, by = 0;
	snprintf(cmd, sizeof cmd, "xwd -root -silent -display %s > %s", dname, xwd_path);
	for (uint32_t y = 40; y < pic.h; y += 23)
		for (uint32_t x = 0; x < pic.w; x += 17)
			total++;
	for (int i = 0; i < 60 && pic.rgb && best < total * 99 / 100; i++) {
		nap_ms(500);
		free(screen.rgb);
		screen.rgb = NULL;
		if (system(cmd) != 0 || read_xwd(xwd_path, &screen) != 0)
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
	kill(v, SIGTERM);
	int st = 0;
	waitpid(v, &st, 0);
	CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
	kill(xsrv, SIGTERM);
	waitpid(xsrv, NULL, 0);
	free(pic.rgb);
	free(screen.rgb);
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
	if (system(cmd) != 0)
		fprintf(stderr, "could not remove %s\n", tmp);
	return pc_test_finish("view_xvfb");
}
