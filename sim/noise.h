/* sim/noise.h - the per-frame sensor chain and the fixed-pattern deviates, row by row
 * (internal to sim/). noise.c holds the scalar reference and the dispatcher; noise_kern.inc
 * the vector kernels, compiled once per instruction set. Every kernel instance produces the
 * same bits as the scalar reference (rng.h: the shared arithmetic is IEEE-exact and
 * order-fixed); tests/test_sim_rng.c checks it for every instance this machine can run. */
#ifndef POLARCAM_SIM_NOISE_H
#define POLARCAM_SIM_NOISE_H

#include <stdbool.h>
#include <stdint.h>

/* One row segment of a frame: pixels (sx0 + i, sy), i < n, of the full sensor. */
typedef struct pc_frame_args {
	uint64_t seed, frame;
	uint32_t sx0, sy, n;
	const float *rate; /* electron rate [e⁻/s] (PRNU applied) */
	const float *dsnu; /* DSNU offsets [e⁻], or NULL */
	double t_s;        /* exposure [s] */
	double dark_e;     /* dark electrons per pixel (with noise; else 0) */
	double full_well_e, K, offset_dn, read_e, max_dn;
	bool noise;    /* shot + dark (Poisson) and read noise */
	uint16_t *out; /* n LSB-aligned values */
} pc_frame_args;

/* The chain of physics.md §6 steps 3–6 (see sensor.c) for one row segment. Per pixel one
 * Philox4x32-10 block keyed by seed with counter (y·65536 + x, PC_RNG_FRAME, frame): words 0
 * and 1 drive the Poisson draw (the first PTRS attempt, or the inversion below mean 10), word 2
 * the read noise; a PTRS rejection continues with the stream's next blocks. */
void pc_noise_frame_row(const pc_frame_args *a);
/* The scalar reference of the same (tests). */
void pc_noise_frame_row_ref(const pc_frame_args *a);

/* Fixed-pattern normal deviates of pixels (sx0 + i, sy), i < n: deviate k (mask bit k) from
 * word k of the Philox block with counter (y·65536 + x, PC_RNG_FIXED, 0, 0). */
void pc_noise_fixed_row(uint64_t seed, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                        double *z[4]);
void pc_noise_fixed_row_ref(uint64_t seed, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                            double *z[4]);

/* Kernel instances: 0 = the scalar reference, 1 = AVX2, 2 = AVX-512 (x86-64, GCC or clang).
 * pc_noise_isa() is the one in use (pc_cpu_active() of polarcam/cpu.h: the best this CPU runs,
 * capped by POLARCAM_CPU); pc_noise_set_isa() forces one that the CPU supports and returns
 * the previous (tests); it returns −1 when the CPU cannot run the one asked for. */
int pc_noise_isa(void);
int pc_noise_set_isa(int isa);
const char *pc_noise_isa_name(int isa);

#endif
