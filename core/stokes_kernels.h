/* Internal to core: the Stokes kernels (stokes_kernels.c) - S0, S1, S2, DoLP and AoLP rows from
 * analyser rows (ideal analysers, or calibrated ones through per-pixel pseudo-inverses), the
 * fused bilinear demosaic + Stokes pass, and the scalar formulas every vector kernel is held to.
 * Formulas and conventions: polarcam/stokes.h. Not a public header. */
#ifndef POLARCAM_STOKES_KERNELS_H
#define POLARCAM_STOKES_KERNELS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "demosaic_common.h"
#include "polarcam/cpu.h"
#include "polarcam/stokes.h"

/* atan(t) ≈ t·P(t²) on [0, 1], P of degree 7 fitted by least squares at 2000 Chebyshev nodes
 * (our own fit; evaluated in float its maximum error is 1.3e-7 rad, asserted against double
 * atan2 in tests/test_stokes.c). */
#define PC_ATAN_C0 0.999999437f
#define PC_ATAN_C1 -0.333301089f
#define PC_ATAN_C2 0.199485329f
#define PC_ATAN_C3 -0.13915916f
#define PC_ATAN_C4 0.0965653358f
#define PC_ATAN_C5 -0.0560667876f
#define PC_ATAN_C6 0.0219490069f
#define PC_ATAN_C7 -0.00407394544f

#define PC_PIF   3.14159265358979323846f
#define PC_PI_2F 1.57079632679489661923f

/* DoLP = min(|(s1, s2)| / s0, 1), 0 where s0 <= 0, with |(s1, s2)| = max·√(1 + (min/max)²)
 * (no overflow or underflow of s1² + s2², as in the vector kernels). */
static inline float pc_st_dolp(float s0, float s1, float s2)
{
	float ax = fabsf(s1), ay = fabsf(s2);
	float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
	if (!(s0 > 0) || !(mx > 0))
		return 0.0f;
	float t = mn / mx, q = mx * sqrtf(1.0f + t * t) / s0;
	return q < 1.0f ? q : 1.0f;
}

/* AoLP = ½·atan2(s2, s1) mapped to [0, π) (pc_aolp_f of polarcam/stokes.h). */
static inline float pc_st_aolp(float s1, float s2)
{
	float ax = fabsf(s1), ay = fabsf(s2);
	float mx = ax > ay ? ax : ay, mn = ax > ay ? ay : ax;
	float t = mx > 0 ? mn / mx : 0.0f;
	float u = t * t;
	float p = PC_ATAN_C7;
	p = p * u + PC_ATAN_C6;
	p = p * u + PC_ATAN_C5;
	p = p * u + PC_ATAN_C4;
	p = p * u + PC_ATAN_C3;
	p = p * u + PC_ATAN_C2;
	p = p * u + PC_ATAN_C1;
	p = p * u + PC_ATAN_C0;
	float r = p * t; /* atan(min/max) in [0, π/4] */
	if (ay > ax)
		r = PC_PI_2F - r;
	if (s1 < 0)
		r = PC_PIF - r;
	if (s2 < 0)
		r = -r;
	float h = 0.5f * r;
	if (h < 0)
		h += PC_PIF;
	if (h >= PC_PIF)
		h -= PC_PIF;
	return h;
}

/* ---- calibrated analysers ---- */

/* How the pseudo-inverse grid's columns map onto output columns: one matrix for all, one per
 * two columns (a per-super-pixel grid on a full-size output), one per column, or another
 * ratio (the generic kernel only). */
enum { PC_ST_X_UNIFORM, PC_ST_X_PAIR, PC_ST_X_PIXEL, PC_ST_X_OTHER };

/* A pc_analyser_pinv mapped onto a w × h output. */
typedef struct pc_st_calib {
	const pc_analyser_pinv *pinv;
	size_t plane; /* grid_w · grid_h: floats between matrix elements */
	uint32_t w, h;
	int xkind;
} pc_st_calib;

void pc_st_calib_init(const pc_analyser_pinv *pinv, uint32_t w, uint32_t h, pc_st_calib *c);

/* Element (i, c) of the matrix row gy: P[4i + c][gx] (grid column gx). */
static inline const float *pc_st_calib_row(const pc_st_calib *c, unsigned i, unsigned ch,
                                           uint32_t y)
{
	uint32_t gy = (uint32_t)((uint64_t)y * c->pinv->grid_h / c->h);
	return c->pinv->m + (size_t)(4 * i + ch) * c->plane + (size_t)gy * c->pinv->grid_w;
}

/* Where field f of column x sits in a row of the compact calibration's horizontal sums
 * (vec_hrow, stokes_kern.inc): the eight fields interleaved by 16-pixel blocks, so that a
 * kernel reads one stream per row at constant offsets. */
#define PC_VEC_IX(f, x) ((size_t)((x) >> 4) * 128 + (size_t)(f)*16 + (size_t)((x)&15))

/* One 16-bit raw row's inputs for the fused conversion and horizontal sums (vec_hrow_u16,
 * stokes_kern.inc): the raw row, the compact maps' rows (pc_compact_calib: dq NULL, the
 * constant dark db; gq NULL, no gain) and the two normalised components' rows q[k], whose
 * column x is base[k][x & 1] + sc[k]·q[k][x]. */
typedef struct pc_st_vrow {
	const uint16_t *raw;
	const int16_t *dq, *gq, *q[2];
	float db, ds, gb, gs, base[2][2], sc[2];
} pc_st_vrow;

/* The floats of one such row of width w. */
static inline size_t pc_st_vec_len(uint32_t w)
{
	return ((size_t)w + 15) / 16 * 128;
}

/* S = M⁻¹b at column x of the fused pipeline with analysis vectors from the horizontal sums
 * H[0..2] of raw rows y−1, y, y+1, scalar (the vector kernels' tails): the formulas of
 * vec_blk (stokes_kern.inc) one pixel at a time. */
static inline void pc_st_vec_px(const float *const H[3], long x, float s[3])
{
	float f[8];
	for (int k = 0; k < 8; k++) {
		size_t i = PC_VEC_IX(k, x);
		f[k] = H[1][i] * 2.0f + (H[0][i] + H[2][i]);
	}
	const float m00 = 16.0f, m01 = f[0], m02 = f[1], m11 = f[2], m12 = f[3], m22 = f[4];
	float c00 = m11 * m22 - m12 * m12, c11 = m00 * m22 - m02 * m02;
	float c22 = m00 * m11 - m01 * m01, c01 = m02 * m12 - m01 * m22;
	float c02 = m01 * m12 - m02 * m11, c12 = m01 * m02 - m00 * m12;
	float inv = 1.0f / (m00 * c00 + (m01 * c01 + m02 * c02));
	s[0] = (c00 * f[5] + (c01 * f[6] + c02 * f[7])) * inv;
	s[1] = (c11 * f[6] + (c01 * f[5] + c12 * f[7])) * inv;
	s[2] = (c22 * f[7] + (c02 * f[5] + c12 * f[6])) * inv;
}

/* Whether the compact calibration corrects the samples itself (a dark or gain map, or a
 * constant dark): then the options give no black level, dark or gain maps (pc_stokes_run
 * checks it). */
static inline int pc_compact_corrects(const pc_compact_calib *v)
{
	return v->dark_q || v->gain_q || v->dark_base != 0;
}

/* Memory that the rows after this one will read (the next raw row and calibration rows),
 * prefetched a slice per 16-pixel block while this row computes, so that the reads overlap the
 * arithmetic instead of stalling the row conversions. Up to 6 ranges of n bytes. */
typedef struct pc_st_pf {
	const char *p[6];
	size_t n[6];
	int count;
} pc_st_pf;

/* ---- kernels ---- */

/* The fused pipeline for monochrome mosaics: bilinear channels straight into S0, S1, S2, DoLP
 * and AoLP, in row bands, without channel images. cal NULL: ideal analysers; else its xkind
 * must not be PC_ST_X_OTHER. vec (not together with cal): the analysers as analysis vectors
 * of the samples (the raw's size, m's channels). Any output strides. */
int pc_st_fused_bilinear(const pc_dm_input *in, const pc_mosaic *m, const pc_st_calib *cal,
                         const pc_compact_calib *vec, int threads, pc_cpu_level level,
                         const pc_stokes_out *out);

/* A row sink (demosaic_common.h) that turns each demosaicked row into Stokes rows: planar
 * outputs only; cal as above. */
typedef struct pc_st_sink {
	const pc_stokes_out *out;
	const pc_st_calib *cal;
	uint32_t w;
	int nt; /* non-temporal stores (pc_st_stream_wanted) */
	pc_cpu_level level;
} pc_st_sink;
void pc_st_sink_row(void *sink, uint32_t y, const float *const ch[4]);

/* Stokes from four planar channel images (vectorised); PC_ENOTSUP when an input or output is
 * not planar, or cal's xkind is PC_ST_X_OTHER. */
int pc_st_planar(const pc_fplane in[4], uint32_t w, uint32_t h, const pc_st_calib *cal, int threads,
                 pc_cpu_level level, const pc_stokes_out *out);

/* Stokes from four channel images with any strides and any grid (scalar). */
void pc_st_generic(const pc_fplane in[4], uint32_t w, uint32_t h, const pc_st_calib *cal,
                   int threads, const pc_stokes_out *out);

/* Whether the wanted outputs (all planar and aligned) are written with non-temporal stores. */
int pc_st_stream_wanted(const pc_stokes_out *out, uint32_t w, uint32_t h, pc_cpu_level level);

/* Whether every wanted output is planar (pixel_stride 1). */
int pc_st_planar_out(const pc_stokes_out *out);

#endif
