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
	const pc_pixfmt fmts[] = { PC_FMT_MONO8, PC_FMT_MONO10, PC_FMT_MONO12, PC_FMT_MONO14,
				   PC_FMT_MONO16, PC_FMT_MONO10P, PC_FMT_MONO12P,
				   PC_FMT_MONO12PACKED, PC_FMT_Y10P, PC_FMT_Y12P };
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
		if (fmts[f] == PC_FMT_MONO10P || fmts[f] == PC_FMT_MONO12P) {
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
		} else if (fmts[f] == PC_FMT_MONO12PACKED) {
			CHECK_EQ_INT(r[0], src[0][0] >> 4);
			CHECK_EQ_INT(r[1] & 15, src[0][0] & 15);
			CHECK_EQ_INT(r[2], src[0][1] >> 4);
		}
		pc_view_free(&v);
	}
	/* a 12-bit frame holding 4096 is an error naming the pixel */
	uint16_t bad[2][4] = { { 1, 2, 3, 4 }, { 5, 4096, 7, 8 } };
	pc_view v = { bad, 4, 2, sizeof bad[0], PC_FMT_MONO12 };
	uint16_t out[2][4];
	CHECK_EQ_INT(pc_view_to_u16(&v, &out[0][0], sizeof out[0]), PC_ERANGE);
	CHECK(strstr(pc_error_detail(), "(1,1)") != NULL);
	/* Mono10p widths must be multiples of 4 */
	size_t rb;
	CHECK_EQ_INT(pc_format_row_bytes(PC_FMT_MONO10P, 6, &rb), PC_EINVAL);
	CHECK_EQ_INT(pc_format_row_bytes(PC_FMT_MONO10P, 2448, &rb), 0);
	CHECK_EQ_INT(rb, 2448 * 10 / 8);
	/* stride below the row size is rejected */
	pc_view s = { bad, 4, 2, 6, PC_FMT_MONO16 };
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
			CHECK_EQ_INT(pc_mosaic_channel(&s, x, y), pc_mosaic_channel(&m, x + 1, y + 3));
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
	CHECK_EQ_INT(pc_mosaic_channel(&fx, 0, 0), 3); /* sensor (3,0) is 45°, mirrored 135° */
	CHECK_EQ_INT(pc_mosaic_channel(&fx, 1, 0), 2); /* sensor (2,0) is 90°, stays 90° */
	pc_mosaic fxy = pc_mosaic_flip(&m, 1, 1, 4, 2); /* 180° rotation keeps angles */
	CHECK_EQ_INT(pc_mosaic_channel(&fxy, 0, 0), 0); /* sensor (3,1) is 0° */
}

int main(void)
{
	test_packing();
	test_genicam_names();
	test_mosaic();
	return pc_test_finish("test_frame");
}
