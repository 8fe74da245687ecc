/* Frames, pixel formats and mosaics: packing round trips against a bit-level reference,
 * range validation, mosaic phase under crops and flips. */
#include <stdint.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"

/* Slow reference: read bit i of an LSB-first stream. */
static unsigned bit_lsb(const uint8_t *b, size_t i)
{
	return (b[i / 8] >> (i % 8)) & 1u;
}

static void test_packing(void)
{
	enum { W = 8, H = 3 };
	uint16_t src[H][W], back[H][W];
	uint32_t seed = 12345;
	const pc_pixfmt fmts[] = {
	    PC_FMT_MONO8,   PC_FMT_MONO10,       PC_FMT_MONO12,       PC_FMT_MONO14, PC_FMT_MONO16,
	    PC_FMT_MONO10P, PC_FMT_MONO12P,      PC_FMT_MONO12PACKED, PC_FMT_Y10P,   PC_FMT_Y12P,
	    PC_FMT_MONO14P, PC_FMT_MONO10PACKED, PC_FMT_Y10BPACK,     PC_FMT_Y14P};
	for (size_t f = 0; f < sizeof fmts / sizeof fmts[0]; f++) {
		const pc_format_info *fi = pc_format_info_get(fmts[f]);
		CHECK(fi != NULL);
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				seed = seed * 1664525u + 1013904223u;
				src[y][x] = (uint16_t)((seed >> 8) & ((1u << fi->bits) - 1u));
			}
		pc_view v;
		CHECK_EQ_INT(pc_view_alloc(&v, fmts[f], W, H, 7), 0); /* odd stride alignment */
		CHECK_EQ_INT(pc_view_from_u16(&src[0][0], sizeof src[0], &v), 0);
		memset(back, 0xff, sizeof back);
		CHECK_EQ_INT(pc_view_to_u16(&v, &back[0][0], sizeof back[0]), 0);
		CHECK(memcmp(src, back, sizeof src) == 0);
		/* independent bit-level checks of the packed layouts on row 0 */
		const uint8_t *r = v.data;
		if (fmts[f] == PC_FMT_MONO10P || fmts[f] == PC_FMT_MONO12P ||
		    fmts[f] == PC_FMT_MONO14P) {
			for (int x = 0; x < W; x++) {
				unsigned val = 0;
				for (unsigned b = 0; b < fi->bits; b++)
					val |= bit_lsb(r, (size_t)x * fi->bits + b) << b;
				CHECK_EQ_INT(val, src[0][x]);
			}
		} else if (fmts[f] == PC_FMT_Y10P) {
			CHECK_EQ_INT(r[1], src[0][1] >> 2);
			CHECK_EQ_INT((r[4] >> 6) & 3, src[0][3] & 3);
		} else if (fmts[f] == PC_FMT_Y12P) {
			CHECK_EQ_INT(r[1], src[0][1] >> 4);
			CHECK_EQ_INT(r[2] >> 4, src[0][1] & 15);
		} else if (fmts[f] == PC_FMT_Y10BPACK) {
			for (int x = 0; x < W; x++) { /* MSB-first stream */
				unsigned val = 0;
				for (unsigned b = 0; b < 10; b++) {
					size_t i = (size_t)x * 10 + b;
					val = (val << 1) | ((r[i / 8] >> (7 - i % 8)) & 1u);
				}
				CHECK_EQ_INT(val, src[0][x]);
			}
		} else if (fmts[f] == PC_FMT_Y14P) {
			/* 4 high bytes, then the 6-bit lows as an LSB-first stream (kernel docs) */
			for (int x = 0; x < 4; x++) {
				CHECK_EQ_INT(r[x], src[0][x] >> 6);
				unsigned lo = 0;
				for (unsigned b = 0; b < 6; b++)
					lo |= bit_lsb(r + 4, (size_t)x * 6 + b) << b;
				CHECK_EQ_INT(lo, src[0][x] & 63);
			}
		} else if (fmts[f] == PC_FMT_MONO10PACKED) {
			CHECK_EQ_INT(r[0], src[0][0] >> 2);
			CHECK_EQ_INT(r[1] & 3, src[0][0] & 3);
			CHECK_EQ_INT((r[1] >> 4) & 3, src[0][1] & 3);
			CHECK_EQ_INT(r[2], src[0][1] >> 2);
		} else if (fmts[f] == PC_FMT_MONO12PACKED) {
			CHECK_EQ_INT(r[0], src[0][0] >> 4);
			CHECK_EQ_INT(r[1] & 15, src[0][0] & 15);
			CHECK_EQ_INT(r[2], src[0][1] >> 4);
		}
		pc_view_free(&v);
	}
	/* a 12-bit frame holding 4096 is an error naming the pixel */
	uint16_t bad[2][4] = {{1, 2, 3, 4}, {5, 4096, 7, 8}};
	pc_view v = {bad, 4, 2, sizeof bad[0], PC_FMT_MONO12};
	uint16_t out[2][4];
	CHECK_EQ_INT(pc_view_to_u16(&v, &out[0][0], sizeof out[0]), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "(1,1)") != NULL);
	/* Mono10p widths must be multiples of 4 */
	size_t rb;
	CHECK_EQ_INT(pc_format_row_bytes(PC_FMT_MONO10P, 6, &rb), PC_EINVAL);
	CHECK_EQ_INT(pc_format_row_bytes(PC_FMT_MONO10P, 2448, &rb), 0);
	CHECK_EQ_INT(rb, 2448 * 10 / 8);
	/* stride below the row size is rejected */
	pc_view s = {bad, 4, 2, 6, PC_FMT_MONO16};
	CHECK_EQ_INT(pc_view_check(&s), PC_EINVAL);
}

static void test_genicam_names(void)
{
	pc_pixfmt f;
	bool pol, col;
	CHECK_EQ_INT(pc_format_from_genicam("PolarizeMono12p", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO12P && pol && !col);
	CHECK_EQ_INT(pc_format_from_genicam("BayerRGPolarized8", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO8 && pol && col);
	CHECK_EQ_INT(pc_format_from_genicam("Mono16", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO16 && !pol);
	CHECK_EQ_INT(pc_format_from_genicam("PolarizedStokes_S0_S1_S2_Mono8", &f, &pol, &col),
	             PC_ENOTSUP);
	CHECK_EQ_INT(pc_format_from_genicam("Y12P", &f, &pol, &col), PC_EINVAL);
	CHECK(pc_format_from_v4l2(PC_FOURCC('Y', '1', '6', ' ')) == PC_FMT_MONO16);
	CHECK(pc_format_from_v4l2(PC_FOURCC('Y', '1', '4', 'P')) == PC_FMT_Y14P);
	CHECK(pc_format_from_v4l2(PC_FOURCC('Y', '1', '0', 'B')) == PC_FMT_Y10BPACK);
	CHECK_EQ_INT(pc_format_from_genicam("Mono14p", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO14P && !pol);
	CHECK_EQ_INT(pc_format_from_genicam("Mono10Packed", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO10PACKED);
	CHECK_EQ_INT(pc_format_from_genicam("Polarized12p", &f, &pol, &col), 0);
	CHECK(f == PC_FMT_MONO12P && pol && !col);
	CHECK_EQ_INT(pc_format_from_genicam("BayerRG8", &f, &pol, &col), PC_ENOTSUP);
	CHECK_EQ_INT(pc_format_from_genicam("NoSuchFormat", &f, &pol, &col), PC_EINVAL);
	/* every table entry resolves to itself; polarized codes are vendor (custom-range) values */
	size_t n;
	const pc_genicam_format *t = pc_genicam_formats(&n);
	CHECK(n >= 20);
	for (size_t i = 0; i < n; i++) {
		CHECK_EQ_INT(pc_format_from_genicam(t[i].name, &f, &pol, &col), 0);
		CHECK(f == t[i].fmt && pol == t[i].polarized && col == t[i].colour);
		if (t[i].polarized && t[i].code)
			CHECK((t[i].code & 0x80000000u) != 0);
		if (!t[i].polarized)
			CHECK_EQ_INT(t[i].code, pc_format_info_get(t[i].fmt)->pfnc_code);
	}
	/* the PFNC code's bits-per-pixel field (bits 16..23) matches the table's packing */
	for (int fi = PC_FMT_INVALID + 1; fi < PC_FMT_COUNT; fi++) {
		const pc_format_info *info = pc_format_info_get((pc_pixfmt)fi);
		if (info->pfnc_code)
			CHECK_EQ_INT((info->pfnc_code >> 16) & 0xff,
			             8 * info->group_bytes / info->group_pixels);
	}
}

/* Packed crops must start on a group; odd crops of unpacked data shift the mosaic. */
static void test_crop_flip(void)
{
	uint16_t px[4][8];
	for (int y = 0; y < 4; y++)
		for (int x = 0; x < 8; x++)
			px[y][x] = (uint16_t)(100 * y + x);
	pc_frame f;
	memset(&f, 0, sizeof f);
	f.view = (pc_view){px, 8, 4, sizeof px[0], PC_FMT_MONO16};
	f.mosaic = pc_mosaic_imx250mzr();
	pc_frame c;
	CHECK_EQ_INT(pc_frame_crop(&f, 3, 1, 4, 2, &c), 0);
	CHECK_EQ_INT(PC_ROW(&c.view, uint16_t, 0)[0], 103);
	CHECK_EQ_INT(c.meta.offset_x, 3);
	CHECK_EQ_INT(c.meta.offset_y, 1);
	for (unsigned y = 0; y < 2; y++)
		for (unsigned x = 0; x < 4; x++)
			CHECK_EQ_INT(pc_mosaic_channel(&c.mosaic, x, y),
			             pc_mosaic_channel(&f.mosaic, x + 3, y + 1));
	CHECK_EQ_INT(pc_frame_crop(&f, 6, 0, 4, 2, &c), PC_ERANGE);
	pc_view packed;
	CHECK_EQ_INT(pc_view_alloc(&packed, PC_FMT_MONO10P, 8, 2, 1), 0);
	pc_view pc;
	CHECK_EQ_INT(pc_view_crop(&packed, 4, 0, 4, 2, &pc), 0);
	CHECK(pc.data == (uint8_t *)packed.data + 5);
	CHECK_EQ_INT(pc_view_crop(&packed, 2, 0, 4, 2, &pc), PC_ENOTSUP);
	pc_view_free(&packed);

	/* A flipped image with the flipped mosaic: every pixel keeps its analyser, mirrored. */
	for (int fx = 0; fx < 2; fx++)
		for (int fy = 0; fy < 2; fy++)
			for (uint32_t w = 3; w <= 6; w++) {
				pc_mosaic m = pc_mosaic_imx250myr();
				pc_mosaic fm = pc_mosaic_flip(&m, fx, fy, w, 5);
				CHECK_EQ_INT(pc_mosaic_check(&fm), 0);
				for (uint32_t y = 0; y < 5; y++)
					for (uint32_t x = 0; x < w; x++) {
						uint32_t sx = fx ? w - 1 - x : x,
						         sy = fy ? 4 - y : y;
						unsigned c0 = pc_mosaic_channel(&m, sx, sy);
						unsigned want = fx != fy ? (4 - c0) % 4 : c0;
						CHECK_EQ_INT(pc_mosaic_channel(&fm, x, y), want);
						CHECK_EQ_INT(pc_mosaic_color(&fm, x, y),
						             pc_mosaic_color(&m, sx, sy));
					}
			}
	pc_view src = {px, 8, 4, sizeof px[0], PC_FMT_MONO16}, dst;
	CHECK_EQ_INT(pc_view_alloc(&dst, PC_FMT_MONO16, 8, 4, 0), 0);
	CHECK_EQ_INT(pc_view_flip(&src, 1, 1, &dst), 0);
	CHECK_EQ_INT(PC_ROW(&dst, uint16_t, 0)[0], 307);
	CHECK_EQ_INT(PC_ROW(&dst, uint16_t, 3)[6], 1);
	pc_view_free(&dst);
}

static void test_check_bits(void)
{
	uint16_t v12[2][2] = {{0, 4095}, {17, 4096}};
	pc_view v = {v12, 2, 2, sizeof v12[0], PC_FMT_MONO16};
	CHECK_EQ_INT(pc_view_check_bits(&v, 12), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "(1,1)") != NULL && strstr(pc_error_detail(), "4096"));
	CHECK_EQ_INT(pc_view_check_bits(&v, 13), 0);
	CHECK_EQ_INT(pc_view_check_bits(&v, 0), PC_EINVAL);
	float fl[2][3] = {{0, 1, 2}, {3, NAN, 5}};
	pc_view vf = {fl, 3, 2, sizeof fl[0], PC_FMT_FLOAT32};
	CHECK_EQ_INT(pc_view_check_bits(&vf, 32), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "(1,1) is NaN") != NULL);
	fl[1][1] = INFINITY;
	CHECK_EQ_INT(pc_view_check_bits(&vf, 32), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "infinite") != NULL);
	fl[1][1] = 4;
	CHECK_EQ_INT(pc_view_check_bits(&vf, 32), 0);
	uint8_t b8[1][4] = {{1, 2, 3, 200}};
	pc_view v8 = {b8, 4, 1, 4, PC_FMT_MONO8};
	CHECK_EQ_INT(pc_view_check_bits(&v8, 7), PC_ERANGE);
}

static void test_mosaic(void)
{
	pc_mosaic m = pc_mosaic_imx250mzr();
	CHECK_EQ_INT(pc_mosaic_channel(&m, 0, 0), 2); /* 90° */
	CHECK_EQ_INT(pc_mosaic_channel(&m, 1, 0), 1); /* 45° */
	CHECK_EQ_INT(pc_mosaic_channel(&m, 0, 1), 3); /* 135° */
	CHECK_EQ_INT(pc_mosaic_channel(&m, 1, 1), 0); /* 0° */
	pc_mosaic p;
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,0", &p), 0);
	CHECK(memcmp(&p, &m, sizeof m) == 0);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,45", &p), PC_EINVAL);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135", &p), PC_EINVAL);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,0,", &p), PC_EINVAL);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,13x,0", &p), PC_EINVAL);
	/* crop at an odd offset: pixel (x, y) of the crop is pixel (x+1, y+3) of the sensor */
	pc_mosaic s = pc_mosaic_shift(&m, 1, 3);
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++)
			CHECK_EQ_INT(pc_mosaic_channel(&s, x, y),
			             pc_mosaic_channel(&m, x + 1, y + 3));
	/* colour: 4x4 period, colour of the 2x2 block */
	pc_mosaic c = pc_mosaic_imx250myr();
	CHECK_EQ_INT(pc_mosaic_color(&c, 0, 0), PC_CFA_R);
	CHECK_EQ_INT(pc_mosaic_color(&c, 3, 1), PC_CFA_G);
	CHECK_EQ_INT(pc_mosaic_color(&c, 2, 3), PC_CFA_B);
	CHECK_EQ_INT(pc_mosaic_channel(&c, 3, 3), 0);
	pc_mosaic cs = pc_mosaic_shift(&c, 2, 2);
	CHECK_EQ_INT(pc_mosaic_color(&cs, 0, 0), PC_CFA_B);
	/* horizontal flip of a 4-wide image: pixel x shows sensor pixel 3-x, 45° <-> 135° */
	pc_mosaic fx = pc_mosaic_flip(&m, 1, 0, 4, 2);
	CHECK_EQ_INT(pc_mosaic_channel(&fx, 0, 0), 3);  /* sensor (3,0) is 45°, mirrored 135° */
	CHECK_EQ_INT(pc_mosaic_channel(&fx, 1, 0), 2);  /* sensor (2,0) is 90°, stays 90° */
	pc_mosaic fxy = pc_mosaic_flip(&m, 1, 1, 4, 2); /* 180° rotation keeps angles */
	CHECK_EQ_INT(pc_mosaic_channel(&fxy, 0, 0), 0); /* sensor (3,1) is 0° */

	/* layout strings: parse(format(m)) == m for every phase of both sensors */
	for (unsigned dy = 0; dy < 4; dy++)
		for (unsigned dx = 0; dx < 4; dx++) {
			pc_mosaic ms[2] = {pc_mosaic_shift(&m, dx, dy),
			                   pc_mosaic_shift(&c, dx, dy)};
			for (int k = 0; k < 2; k++) {
				char buf[64];
				pc_mosaic back;
				CHECK_EQ_INT(pc_mosaic_check(&ms[k]), 0);
				pc_mosaic_format(&ms[k], buf, sizeof buf);
				CHECK_EQ_INT(pc_mosaic_parse(buf, &back), 0);
				CHECK(memcmp(&back, &ms[k], sizeof back) == 0);
				if (memcmp(&back, &ms[k], sizeof back) != 0)
					fprintf(stderr, "  layout '%s' (shift %u,%u)\n", buf, dx,
					        dy);
			}
		}
	pc_mosaic q;
	CHECK_EQ_INT(pc_mosaic_parse("RGGB:90,45,135,0", &q), 0);
	CHECK(memcmp(&q, &c, sizeof q) == 0);
	CHECK_EQ_INT(pc_mosaic_parse("imx250myr", &q), 0);
	CHECK(memcmp(&q, &c, sizeof q) == 0);
	CHECK_EQ_INT(pc_mosaic_parse("gbrg:0,45,90,135@3,1", &q), 0);
	CHECK_EQ_INT(q.period, 4);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,0@1,1", &q), 0);
	CHECK_EQ_INT(pc_mosaic_channel(&q, 0, 0), 0);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,0@2,0", &q), PC_EINVAL); /* mono phase is 0..1 */
	CHECK_EQ_INT(pc_mosaic_parse("RGBG:90,45,135,0", &q), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "RGBG") != NULL);
	CHECK_EQ_INT(pc_mosaic_parse("", &q), PC_EINVAL);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,135,0 ", &q), PC_EINVAL);
	CHECK_EQ_INT(pc_mosaic_parse("90,45,180,0", &q), PC_EINVAL);
	/* invalid mosaics are caught */
	pc_mosaic bad = m;
	bad.channel[0][0] = 1;
	CHECK_EQ_INT(pc_mosaic_check(&bad), PC_EINVAL);
	bad = c;
	bad.color[0][1] = PC_CFA_B; /* a colour block split */
	CHECK_EQ_INT(pc_mosaic_check(&bad), PC_EINVAL);
	bad = c;
	for (int y = 0; y < 2; y++)
		for (int x = 0; x < 2; x++)
			bad.color[y][x] = PC_CFA_B; /* B twice, no R */
	CHECK_EQ_INT(pc_mosaic_check(&bad), PC_EINVAL);
	bad = m;
	bad.period = 3;
	CHECK_EQ_INT(pc_mosaic_check(&bad), PC_EINVAL);

	/* equality over the period: what pc_mosaic_channel / pc_mosaic_color read */
	CHECK(pc_mosaic_equal(&m, &m) && pc_mosaic_equal(&c, &c));
	CHECK(!pc_mosaic_equal(&m, &c) && !pc_mosaic_equal(&c, &m));
	CHECK(!pc_mosaic_equal(&m, &s));  /* shifted by (1, 3) */
	CHECK(!pc_mosaic_equal(&c, &cs)); /* same analysers, colours moved by (2, 2) */
	pc_mosaic beyond = m;
	beyond.channel[3][3] = 1; /* outside the 2x2 period: never read */
	CHECK(pc_mosaic_equal(&m, &beyond));
	pc_mosaic inside = c;
	inside.color[3][3] = PC_CFA_R;
	CHECK(!pc_mosaic_equal(&c, &inside));
}

int main(void)
{
	test_packing();
	test_genicam_names();
	test_mosaic();
	test_crop_flip();
	test_check_bits();
	return pc_test_finish("test_frame");
}
