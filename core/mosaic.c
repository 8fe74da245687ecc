#include "polarcam/mosaic.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static void mosaic_fill_mono(pc_mosaic *m, const unsigned ch[2][2])
{
	memset(m, 0, sizeof *m);
	m->period = 2;
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			m->channel[y][x] = (uint8_t)ch[y & 1][x & 1];
}

pc_mosaic pc_mosaic_imx250mzr(void)
{
	/* Sony IMX250MZR datasheet / hardware.md: top-left [90 45; 135 0]. */
	static const unsigned ch[2][2] = { { 2, 1 }, { 3, 0 } };
	pc_mosaic m;
	mosaic_fill_mono(&m, ch);
	return m;
}

pc_mosaic pc_mosaic_imx250myr(void)
{
	pc_mosaic m = pc_mosaic_imx250mzr();
	static const uint8_t bayer[2][2] = { { PC_CFA_R, PC_CFA_G }, { PC_CFA_G, PC_CFA_B } };
	m.period = 4;
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 4; x++)
			m.color[y][x] = bayer[y >> 1][x >> 1];
	return m;
}

int pc_mosaic_from_angles(const int angles_deg[4], pc_mosaic *out)
{
	unsigned ch[2][2];
	unsigned seen = 0;
	for (int i = 0; i < 4; i++) {
		int a = angles_deg[i];
		if (a != 0 && a != 45 && a != 90 && a != 135)
			return pc_error(PC_EINVAL, "mosaic angle %d (position %d): expected 0, 45, 90 or 135",
					a, i + 1);
		unsigned c = (unsigned)a / 45u;
		if (seen & (1u << c))
			return pc_error(PC_EINVAL, "mosaic angle %d appears twice: the layout must be a "
						   "permutation of 0, 45, 90, 135", a);
		seen |= 1u << c;
		ch[i >> 1][i & 1] = c;
	}
	mosaic_fill_mono(out, ch);
	return 0;
}

int pc_mosaic_parse(const char *layout, pc_mosaic *out)
{
	if (!layout)
		return pc_error(PC_EINVAL, "layout missing: expected four angles such as 90,45,135,0");
	int a[4];
	const char *p = layout;
	for (int i = 0; i < 4; i++) {
		char *end;
		errno = 0;
		long v = strtol(p, &end, 10);
		if (end == p || errno || v < -1000 || v > 1000)
			return pc_error(PC_EINVAL, "layout '%s': angle %d is not an integer "
						   "(expected four angles such as 90,45,135,0)", layout, i + 1);
		a[i] = (int)v;
		p = end;
		if (i < 3) {
			if (*p != ',')
				return pc_error(PC_EINVAL, "layout '%s': expected ',' after angle %d "
							   "(four angles such as 90,45,135,0)", layout, i + 1);
			p++;
		}
	}
	if (*p != '\0')
		return pc_error(PC_EINVAL, "layout '%s': trailing characters after four angles", layout);
	int rc = pc_mosaic_from_angles(a, out);
	if (rc)
		return pc_error_prefix(rc, "layout '%s': ", layout);
	return 0;
}

void pc_mosaic_format(const pc_mosaic *m, char *buf, unsigned size)
{
	const char *prefix = m->period == 4 ? "RGGB:" : "";
	snprintf(buf, size, "%s%u,%u,%u,%u", prefix, 45u * m->channel[0][0], 45u * m->channel[0][1],
		 45u * m->channel[1][0], 45u * m->channel[1][1]);
}

pc_mosaic pc_mosaic_shift(const pc_mosaic *m, uint32_t x0, uint32_t y0)
{
	pc_mosaic r = *m;
	unsigned p = m->period;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++) {
			r.channel[y][x] = m->channel[(y + y0) % p][(x + x0) % p];
			r.color[y][x] = m->color[(y + y0) % p][(x + x0) % p];
		}
	return r;
}

pc_mosaic pc_mosaic_flip(const pc_mosaic *m, int flip_x, int flip_y, uint32_t w, uint32_t h)
{
	/* Mirroring one image axis maps an analyser at θ to 180° − θ: channels 1 (45°) and 3
	 * (135°) swap, 0° and 90° stay. Pixel x of the flipped image is pixel w-1-x. */
	pc_mosaic r = *m;
	unsigned p = m->period;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++) {
			unsigned sx = flip_x ? (unsigned)((w - 1 - x % w) % p) : x % p;
			unsigned sy = flip_y ? (unsigned)((h - 1 - y % h) % p) : y % p;
			unsigned c = m->channel[sy][sx];
			if (flip_x != flip_y && (c == 1 || c == 3))
				c = 4 - c;
			r.channel[y][x] = (uint8_t)c;
			r.color[y][x] = m->color[sy][sx];
		}
	return r;
}

void pc_mosaic_channel_pos(const pc_mosaic *m, unsigned c, unsigned *dx, unsigned *dy)
{
	for (unsigned y = 0; y < 2; y++)
		for (unsigned x = 0; x < 2; x++)
			if (m->channel[y][x] == c) {
				*dx = x;
				*dy = y;
				return;
			}
	*dx = *dy = 0;
}
