/* The fast paths' raw rows (demosaic_common.h): pc_dm_row_convert gives exactly what
 * pc_dm_row_to_float gives (the conversion without the next row's prefetch: 8-bit, 16-bit and
 * float samples, with and without a black level, with a dark map and inverse gains, and the
 * one-pixel mirror on either side), and the spread prefetch's cursor (pc_dm_pf) walks a row's
 * 64-byte lines once each, first to last, whatever the row's alignment: the lines it issues,
 * counted through pc_dm_pf_step's and pc_dm_pf_finish's returns, are the lines the row spans,
 * never more, and nothing past the last row. That the prefetch saves time is measured, not
 * tested (docs/demosaicking.md, Round 36). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/demosaic_common.h"
#include "check.h"
#include "polarcam/error.h"

/* Lines of 64 bytes that bytes [a, a + n) of memory span */
static unsigned lines_spanned(uintptr_t a, size_t n)
{
	return (unsigned)(((a + n - 1) >> 6) - (a >> 6) + 1);
}

static void cursor(void)
{
	static uint8_t buf[64 * 200 + 128] __attribute__((aligned(64)));
	const uint32_t widths[] = {1, 31, 32, 33, 100, 2448 / 4};
	const pc_dm_type types[] = {PC_DMT_U8, PC_DMT_U16, PC_DMT_F32};
	for (size_t wi = 0; wi < sizeof widths / sizeof widths[0]; wi++)
		for (int ti = 0; ti < 3; ti++)
			for (size_t off = 0; off < 64; off += 13) {
				const size_t bpp = pc_dm_type_bytes(types[ti]);
				const size_t nb = widths[wi] * bpp;
				pc_dm_input in = {buf + off, nb + 7, types[ti], widths[wi], 3, 0,
				                  0,         NULL,   NULL,      0,          0};
				for (uint32_t y = 0; y < 3; y++) {
					pc_dm_pf pf;
					pc_dm_pf_row(&pf, &in, y);
					const uintptr_t first = pf.cur;
					unsigned n = 0, k;
					while ((k = pc_dm_pf_step(&pf, 3)) > 0) {
						CHECK(k <= 3);
						n += k;
					}
					n += pc_dm_pf_finish(&pf);
					const uintptr_t row =
					    (uintptr_t)(buf + off + y * in.stride);
					CHECK_EQ_INT((int)n, (int)lines_spanned(row, nb));
					CHECK(first == (row & ~(uintptr_t)63));
					CHECK_EQ_INT((int)pc_dm_pf_step(&pf, 1), 0);
					/* the rest at once, from the start */
					pc_dm_pf_row(&pf, &in, y);
					CHECK_EQ_INT((int)pc_dm_pf_finish(&pf),
					             (int)lines_spanned(row, nb));
				}
				pc_dm_pf pf;
				pc_dm_pf_row(&pf, &in, 3); /* past the last row: nothing */
				CHECK_EQ_INT((int)pc_dm_pf_finish(&pf), 0);
			}
}

/* pc_dm_row_convert against pc_dm_row_to_float, bit for bit, mirrors included */
static void convert_same(void)
{
	enum { W = 37, H = 4 };
	static uint8_t u8[H][W];
	static uint16_t u16[H][W];
	static float f32[H][W], dark[H * W], gain[H * W];
	uint32_t r = 12345;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			r = r * 1664525u + 1013904223u;
			u8[y][x] = (uint8_t)(r >> 24);
			u16[y][x] = (uint16_t)(r >> 20);
			f32[y][x] = (float)(r >> 8) / 65536.0f;
			dark[y * W + x] = (float)(r % 17);
			gain[y * W + x] = 0.9f + (float)(r % 11) / 50.0f;
		}
	const void *data[3] = {u8, u16, f32};
	const pc_dm_type types[3] = {PC_DMT_U8, PC_DMT_U16, PC_DMT_F32};
	int compared = 0;
	for (int t = 0; t < 3; t++)
		for (int mode = 0; mode < 7; mode++) {
			/* 0 plain, 1 black level, 2 dark map, 3 dark and gains, 4 black and gains,
			 * 5 the dark map scaled about a level (pc_pipeline_opts.dark_scale), 6 that
			 * and gains */
			const bool dk = mode == 2 || mode == 3 || mode >= 5,
			           gn = mode == 3 || mode == 4 || mode == 6;
			pc_dm_input in = {data[t],
			                  W * pc_dm_type_bytes(types[t]),
			                  types[t],
			                  W,
			                  H,
			                  mode == 1 || mode == 4 ? 64.5f : 0,
			                  mode == 1 || mode == 4 ? 64.5 : 0,
			                  dk ? dark : NULL,
			                  gn ? gain : NULL,
			                  0,
			                  0};
			const double ds = 3.981, pivot = 8; /* +12 dB about a black level of 8 */
			if (mode >= 5) {
				pc_pipeline_opts po = pc_pipeline_defaults();
				po.dark = dark;
				po.gain_inv = in.gain_inv;
				po.dark_scale = ds;
				po.dark_pivot = pivot;
				pc_dm_input_dark(&in, &po);
			}
			for (uint32_t y = 0; y < H; y++) {
				float a[W + 2], b[W + 2];
				memset(a, 0xa5, sizeof a);
				memset(b, 0x5a, sizeof b);
				pc_dm_row_to_float(&in, y, a + 1);
				pc_dm_row_convert(&in, y, b + 1);
				CHECK(memcmp(a, b, sizeof a) == 0);
				/* and the values themselves, so that a shared fault cannot pass */
				for (int x = 0; x < W; x++) {
					double v = types[t] == PC_DMT_U8    ? u8[y][x]
					           : types[t] == PC_DMT_U16 ? u16[y][x]
					                                    : f32[y][x];
					if (mode == 1 || mode == 4)
						v -= 64.5;
					else if (mode >= 5)
						v -= pivot + ds * (dark[y * W + x] - pivot);
					else if (mode >= 2)
						v -= dark[y * W + x];
					if (gn)
						v *= gain[y * W + x];
					CHECK(fabs(b[x + 1] - v) <= 1e-6 * (fabs(v) + 1));
					compared++;
				}
				CHECK(b[0] == b[2] && b[W + 1] == b[W - 1]);
			}
		}
	printf("  pc_dm_row_convert: %d samples as pc_dm_row_to_float gives them\n", compared);
}

/* the front door refuses a dark map's scale that is not finite and >= 0, naming it */
static void bad_scale(void)
{
	enum { W = 16, H = 16 };
	static uint16_t raw[H][W];
	static float dark[H * W], out[4][H * W];
	pc_view v = {raw, W, H, W * sizeof(uint16_t), PC_FMT_MONO16};
	pc_fplane ch[4];
	for (int c = 0; c < 4; c++)
		ch[c] = (pc_fplane){out[c], W, 1};
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.dark = dark;
	const double bad[3][2] = {{NAN, 0}, {-1, 0}, {2, INFINITY}};
	for (int k = 0; k < 3; k++) {
		po.dark_scale = bad[k][0];
		po.dark_pivot = bad[k][1];
		CHECK_EQ_INT(pc_demosaic_run(&v, &po, ch, NULL), PC_EINVAL);
		CHECK(strstr(pc_error_detail(), "dark_scale") != NULL);
	}
	po.dark_scale = 2;
	po.dark_pivot = 1;
	CHECK_EQ_INT(pc_demosaic_run(&v, &po, ch, NULL), 0);
}

int main(void)
{
	cursor();
	convert_same();
	bad_scale();
	return pc_test_finish("test_row_fetch");
}
