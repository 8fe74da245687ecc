/* Internal: the argument types of the pan output-row kernels that demosaic_pan.c and
 * demosaic_pan_lean.c share, and pan-lean's row kernels (demosaic_pan_lean.inc), compiled in
 * their own translation unit (demosaic_pan_lean.c) once per instruction-set level. */
#ifndef PC_DEMOSAIC_PAN_KARGS_H
#define PC_DEMOSAIC_PAN_KARGS_H

#include "cpu_internal.h"

/* pan-guided's: the terms' tent weights vt, their rows' index vdy in p0row (rows y-3 .. y+3) */
typedef struct pan_gorow_args {
	const float *vrow[12][4];
	float vt[12][4];
	int vdy[12][4];
	int nv[12];
	const float *sel[4];
	unsigned own[4];
	const float *p0row[7];
	const float *c1row[7], *c2row[7]; /* pan-chroma's chrominance rows (else unused) */
	const float *fn, *fs;             /* pan-side's factors N and S of the row (else unused) */
	float vtl[12][4][16]; /* vt repeated to 16 lanes (pan_gorow: a load, not a splat) */
	/* pan_gorow_ph's slots (demosaic_pan_kern.inc): each one's term rows and channel, the
	 * lanes of slots 0, 1, 8 where they are the own channel; ph its variant, or -1 */
	const float *prow[12][4];
	unsigned sq[12];
	const float *osel[3];
	int ph;
	/* pan-adapt's: the row's window mean mu and variance var of P̃ = max(P0, 0) + δ, the range
	 * scale e0 + ke·mu, the noise term kn·mu (kn = 0: pan-side's ratio step) */
	const float *mu, *var;
	float ke, e0, kn;
	/* pan-lean's (pan_lgorow): the block row's window means less δ and shrinkage factors
	 * (pan_lwin), the 0/1 lane patterns where channel q is of the pixel's own colour, c_s·g and
	 * the floor F */
	const float *lmu, *llam;
	const float *csame[12];
	float lcs, lF;
	/* pan-lean's: the raw row the next output row's source rows convert first (pan_gorow), its
	 * strip's first sample, and its bytes per sample: the output row prefetches it */
	const unsigned char *pf;
	long pfb;
	/* pan-lean's: the tents of the row's last source row, which pan_lgorow makes (pan_lhrows'
	 * arguments: the ratio row, the W and E factors, the weight patterns, the interleaved tent
	 * row) */
	const float *lrho, *lfw, *lfe;
	const float (*lwt)[7][16];
	float *lh;
	/* floats per column of the tent rows vrow and prow: 1, or pan-lean's PAN_LTS (its four
	 * tents of a source row interleaved, PAN_LTI) */
	long tstep;
} pan_gorow_args;

/* pan-lean's tent rows (pan_lhrows writes them, pan_lgorow reads them): the four tents of a
 * source row interleaved in blocks of 16 columns, tent s of column x at PAN_LTI(x) + 16·s of
 * the row, so that the output row reads 7 rows instead of 28 (docs/demosaicking.md, Round 29);
 * a row of n columns (n a multiple of 16) takes PAN_LTS·n floats */
#define PAN_LTS    4
#define PAN_LTI(x) (PAN_LTS * ((x) & ~15L) + ((x)&15L))

/* pan-lean's block terms for pan_lfach and pan_lfacv (demosaic_pan_lean.inc): ε, κ_n·√g, κ_t, μ, δ,
 * F; and pan_lwin's c_p·g */
typedef struct pan_lpar {
	float eps, kng, kt, mu, delta, F, cp;
} pan_lpar;

/* pan-lean's row kernels (demosaic_pan_lean.inc states each), per instance S (base, avx2,
 * avx512): the block rows, the side factors, the tents, the window sums, the output row */
#define PAN_LEAN_DECL(S)                                                                           \
	void pan_lshue_##S(const float *p0, const float *c1, const float *c2, long x0, long n,     \
	                   float delta, float *u1, float *u2, float *pt);                          \
	void pan_lfach_##S(const float *const u[3], long n, const pan_lpar *lp, float *f0,         \
	                   float *f1, float *eo);                                                  \
	void pan_lfacv_##S(const float *const u[3], const float *const un[3],                      \
	                   const float *const us[3], const float *e0, float *dps, int have,        \
	                   long n, const pan_lpar *lp, float *f0, float *f1);                      \
	void pan_lhrows_##S(const float *rho, const float *fw, const float *fe, long n,            \
	                    const float wt[4][7][16], float *const h[4]);                          \
	void pan_lwin_##S(const float *const p[3], long n, float cp, float F, float delta,         \
	                  float *mo, float *lo);                                                   \
	void pan_lgorow_##S(const pan_gorow_args *a, const float *raw, long n, float delta,        \
	                    float e, float *const out[12], int nt);
PAN_LEAN_DECL(base)
#ifdef PC_CPU_X86
PAN_LEAN_DECL(avx2)
PAN_LEAN_DECL(avx512)
#endif

#endif
