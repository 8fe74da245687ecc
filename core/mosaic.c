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
	/* Sony IMX250MZR datasheet / docs/hardware.md: top-left [90 45; 135 0]. */
	static const unsigned ch[2][2] = {{2, 1}, {3, 0}};
	pc_mosaic m;
	mosaic_fill_mono(&m, ch);
	return m;
}

pc_mosaic pc_mosaic_imx250myr(void)
{
	pc_mosaic m = pc_mosaic_imx250mzr();
	static const uint8_t bayer[2][2] = {{PC_CFA_R, PC_CFA_G}, {PC_CFA_G, PC_CFA_B}};
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
			return pc_error(PC_EINVAL,
			                "mosaic angle %d (position %d): expected 0, 45, 90 or 135",
			                a, i + 1);
		unsigned c = (unsigned)a / 45u;
		if (seen & (1u << c))
			return pc_error(PC_EINVAL,
			                "mosaic angle %d appears twice: the layout must be a "
			                "permutation of 0, 45, 90, 135",
			                a);
		seen |= 1u << c;
		ch[i >> 1][i & 1] = c;
	}
	mosaic_fill_mono(out, ch);
	return 0;
}

static int ascii_ieq(const char *a, const char *b, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		char x = a[i], y = b[i];
		if (x >= 'a' && x <= 'z')
			x = (char)(x - 'a' + 'A');
		if (y >= 'a' && y <= 'z')
			y = (char)(y - 'a' + 'A');
		if (x != y)
			return 0;
	}
	return 1;
}

/* Bayer orders of the four 2×2 polarizer blocks (row-major) in a 4×4 colour-polarization period. */
static const struct {
	const char *name;
	uint8_t c[4];
} pc_bayer_orders[] = {
    {"RGGB", {PC_CFA_R, PC_CFA_G, PC_CFA_G, PC_CFA_B}},
    {"BGGR", {PC_CFA_B, PC_CFA_G, PC_CFA_G, PC_CFA_R}},
    {"GRBG", {PC_CFA_G, PC_CFA_R, PC_CFA_B, PC_CFA_G}},
    {"GBRG", {PC_CFA_G, PC_CFA_B, PC_CFA_R, PC_CFA_G}},
};

/* Parses an unsigned decimal in [0, max] at *p, advancing *p. */
static int parse_small(const char **p, long max, long *out)
{
	char *end;
	errno = 0;
	long v = strtol(*p, &end, 10);
	if (end == *p || errno || v < 0 || v > max || **p == '+' || **p == '-' || **p == ' ')
		return -1;
	*p = end;
	*out = v;
	return 0;
}

int pc_mosaic_parse(const char *layout, pc_mosaic *out)
{
	if (!layout)
		return pc_error(PC_EINVAL,
		                "layout missing: expected four angles such as 90,45,135,0");
	if (!strcmp(layout, "imx250mzr") || !strcmp(layout, "IMX250MZR")) {
		*out = pc_mosaic_imx250mzr();
		return 0;
	}
	if (!strcmp(layout, "imx250myr") || !strcmp(layout, "IMX250MYR")) {
		*out = pc_mosaic_imx250myr();
		return 0;
	}
	const char *p = layout;
	int bayer = -1;
	const char *colon = strchr(layout, ':');
	if (colon) {
		for (size_t i = 0; i < sizeof pc_bayer_orders / sizeof pc_bayer_orders[0]; i++)
			if (colon - layout == 4 && ascii_ieq(layout, pc_bayer_orders[i].name, 4))
				bayer = (int)i;
		if (bayer < 0)
			return pc_error(PC_EINVAL,
			                "layout '%s': '%.*s' is not a Bayer order (expected "
			                "RGGB, BGGR, GRBG or GBRG before ':')",
			                layout, (int)(colon - layout), layout);
		p = colon + 1;
	}
	int a[4];
	for (int i = 0; i < 4; i++) {
		char *end;
		errno = 0;
		long v = strtol(p, &end, 10);
		if (end == p || errno || v < -1000 || v > 1000)
			return pc_error(PC_EINVAL,
			                "layout '%s': angle %d is not an integer "
			                "(expected four angles such as 90,45,135,0)",
			                layout, i + 1);
		a[i] = (int)v;
		p = end;
		if (i < 3) {
			if (*p != ',')
				return pc_error(PC_EINVAL,
				                "layout '%s': expected ',' after angle %d "
				                "(four angles such as 90,45,135,0)",
				                layout, i + 1);
			p++;
		}
	}
	long dx = 0, dy = 0;
	if (*p == '@') {
		p++;
		long maxd = bayer >= 0 ? 3 : 1;
		if (parse_small(&p, maxd, &dx) || *p != ',' || (p++, parse_small(&p, maxd, &dy)))
			return pc_error(PC_EINVAL,
			                "layout '%s': expected '@DX,DY' with phase offsets "
			                "in 0..%ld after the angles",
			                layout, maxd);
	}
	if (*p != '\0')
		return pc_error(PC_EINVAL,
		                "layout '%s': trailing characters '%s' after the layout "
		                "(expected [RGGB:]A,B,C,D[@DX,DY])",
		                layout, p);
	int rc = pc_mosaic_from_angles(a, out);
	if (rc)
		return pc_error_prefix(rc, "layout '%s': ", layout);
	if (bayer >= 0) {
		out->period = 4;
		for (int y = 0; y < 4; y++)
			for (int x = 0; x < 4; x++)
				out->color[y][x] =
				    pc_bayer_orders[bayer].c[(y >> 1) * 2 + (x >> 1)];
	}
	*out = pc_mosaic_shift(out, (uint32_t)dx, (uint32_t)dy);
	return 0;
}

int pc_mosaic_check(const pc_mosaic *m)
{
	if (!m)
		return pc_error(PC_EINVAL, "mosaic missing");
	if (m->period != 2 && m->period != 4)
		return pc_error(PC_EINVAL,
		                "mosaic period %u: expected 2 (monochrome) or 4 "
		                "(colour-polarization)",
		                m->period);
	/* The polarizer pattern repeats every 2×2 pixels and holds each analyser once. */
	unsigned seen = 0;
	for (unsigned y = 0; y < 2; y++)
		for (unsigned x = 0; x < 2; x++) {
			if (m->channel[y][x] > 3)
				return pc_error(PC_EINVAL,
				                "mosaic channel %u at (%u,%u): expected 0..3",
				                m->channel[y][x], x, y);
			seen |= 1u << m->channel[y][x];
		}
	if (seen != 15)
		return pc_error(PC_EINVAL, "mosaic: the 2x2 block must hold each of 0, 45, 90, 135 "
		                           "degrees once");
	for (unsigned y = 0; y < m->period; y++)
		for (unsigned x = 0; x < m->period; x++)
			if (m->channel[y][x] != m->channel[y & 1][x & 1])
				return pc_error(PC_EINVAL,
				                "mosaic: the polarizer pattern must repeat "
				                "every 2x2 pixels (differs at (%u,%u))",
				                x, y);
	if (m->period == 2) {
		for (unsigned y = 0; y < 2; y++)
			for (unsigned x = 0; x < 2; x++)
				if (m->color[y][x] != PC_CFA_NONE)
					return pc_error(PC_EINVAL,
					                "mosaic: a period-2 mosaic has no "
					                "colour filter");
		return 0;
	}
	unsigned ox, oy;
	if (pc_mosaic_color_origin(m, &ox, &oy))
		return pc_error(PC_EINVAL, "mosaic: the colour filter must cover whole 2x2 "
		                           "polarizer blocks in a Bayer order");
	pc_mosaic a = pc_mosaic_shift(m, ox, oy);
	unsigned b00 = a.color[0][0], b01 = a.color[0][2], b10 = a.color[2][0], b11 = a.color[2][2];
	int gg_main = b00 == PC_CFA_G && b11 == PC_CFA_G,
	    gg_anti = b01 == PC_CFA_G && b10 == PC_CFA_G;
	unsigned rb = gg_main ? (b01 | b10 << 2) : (b00 | b11 << 2);
	if (!(gg_main || gg_anti) ||
	    (rb != (PC_CFA_R | PC_CFA_B << 2) && rb != (PC_CFA_B | PC_CFA_R << 2)))
		return pc_error(PC_EINVAL, "mosaic: the colour blocks are not a Bayer pattern "
		                           "(one R, one B, two G on a diagonal)");
	return 0;
}

int pc_mosaic_color_origin(const pc_mosaic *m, unsigned *ox, unsigned *oy)
{
	if (m->period != 4)
		return PC_EINVAL;
	for (unsigned sy = 0; sy < 2; sy++)
		for (unsigned sx = 0; sx < 2; sx++) {
			/* blocks start at x ≡ sx, y ≡ sy (mod 2): colour constant on each block */
			int ok = 1;
			for (unsigned y = 0; y < 4 && ok; y++)
				for (unsigned x = 0; x < 4 && ok; x++) {
					unsigned bx =
					    (x + 4 - sx) / 2 * 2 + sx; /* block start, mod 4 */
					unsigned by = (y + 4 - sy) / 2 * 2 + sy;
					if (m->color[y][x] == PC_CFA_NONE ||
					    m->color[y][x] != m->color[by % 4][bx % 4])
						ok = 0;
				}
			if (ok) {
				*ox = sx;
				*oy = sy;
				return 0;
			}
		}
	return PC_EINVAL;
}

void pc_mosaic_format(const pc_mosaic *m, char *buf, unsigned size)
{
	unsigned ox = 0, oy = 0;
	if (m->period == 4 && pc_mosaic_color_origin(m, &ox, &oy) == 0) {
		/* m is the aligned pattern a seen from a crop at (dx, dy): a = shift(m, -dx, -dy)
		 */
		unsigned dx = (2 - ox) % 2, dy = (2 - oy) % 2;
		pc_mosaic a = pc_mosaic_shift(m, 4 - dx, 4 - dy);
		char cfa[5];
		static const char letter[4] = {'?', 'R', 'G', 'B'};
		cfa[0] = letter[a.color[0][0] & 3];
		cfa[1] = letter[a.color[0][2] & 3];
		cfa[2] = letter[a.color[2][0] & 3];
		cfa[3] = letter[a.color[2][2] & 3];
		cfa[4] = '\0';
		if (dx || dy)
			snprintf(buf, size, "%s:%u,%u,%u,%u@%u,%u", cfa, 45u * a.channel[0][0],
			         45u * a.channel[0][1], 45u * a.channel[1][0],
			         45u * a.channel[1][1], dx, dy);
		else
			snprintf(buf, size, "%s:%u,%u,%u,%u", cfa, 45u * a.channel[0][0],
			         45u * a.channel[0][1], 45u * a.channel[1][0],
			         45u * a.channel[1][1]);
		return;
	}
	snprintf(buf, size, "%u,%u,%u,%u", 45u * m->channel[0][0], 45u * m->channel[0][1],
	         45u * m->channel[1][0], 45u * m->channel[1][1]);
}

bool pc_mosaic_equal(const pc_mosaic *a, const pc_mosaic *b)
{
	if (a->period != b->period)
		return false;
	for (unsigned y = 0; y < a->period && y < 4; y++)
		for (unsigned x = 0; x < a->period && x < 4; x++)
			if (a->channel[y][x] != b->channel[y][x] ||
			    a->color[y][x] != b->color[y][x])
				return false;
	return true;
}

pc_mosaic pc_mosaic_shift(const pc_mosaic *m, uint32_t x0, uint32_t y0)
{
	pc_mosaic r = *m;
	unsigned p = m->period;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++) {
			r.channel[y][x] = m->channel[(y + y0 % p) % p][(x + x0 % p) % p];
			r.color[y][x] = m->color[(y + y0 % p) % p][(x + x0 % p) % p];
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
			/* (w - 1 - x) mod p, computed without going negative */
			unsigned sx =
			    flip_x ? (unsigned)(((uint64_t)w + 4u * p - 1u - x) % p) : x % p;
			unsigned sy =
			    flip_y ? (unsigned)(((uint64_t)h + 4u * p - 1u - y) % p) : y % p;
			unsigned c = m->channel[sy][sx];
			if ((flip_x != 0) != (flip_y != 0) && (c == 1 || c == 3))
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
