/* sim/sim_impl.h - the simulator object (internal to sim/): render (render.c), sensor chain
 * (sensor.c), caches and API (sim.c). */
#ifndef POLARCAM_SIM_SIM_IMPL_H
#define POLARCAM_SIM_SIM_IMPL_H

#include "polarcam/pbrdf.h"
#include "polarcam/sim.h"
#include "scene_impl.h"

typedef struct pc_sim pc_sim;

/* Per-pixel work units chosen once in pc_sim_new from the effect set (the "pipeline"). */

/* Objects with primary-ray culling (render.c); further objects are always tested. */
#define PC_CULL_MAX 32
#define PC_SS_MAX   16

/* What one sensor row's camera rays share (render.c): the ray bases of its sub-rows and the
 * columns in which each culled object can be hit. */
typedef struct pc_render_row {
	uint32_t sy;
	unsigned nsub;
	pc_v3 base[PC_SS_MAX];
	int32_t lo[PC_SS_MAX][PC_CULL_MAX], hi[PC_SS_MAX][PC_CULL_MAX];
} pc_render_row;
/* Analyser row a (physics.md §6) of a pixel of analyser channel c (0..3 for 0°..135°) with its
 * orientation, transmission and extinction-ratio deviates. */
typedef void (*pc_analyse_fn)(const pc_sim *sim, unsigned c, double zo, double zt, double ze,
                              double a[4]);
typedef void (*pc_frame_row_fn)(const pc_sim *sim, uint64_t n, double exposure_s, double gain,
                                uint32_t y, uint16_t *row);

struct pc_sim {
	pc_scene *scene; /* shared, reference-counted */
	pc_sim_options opt;
	pc_sim_info info;
	pc_sensor_figures fig;
	unsigned fx;   /* effects in force */
	unsigned nch;  /* colour channels rendered: 1 or 3 */
	bool circular; /* carry S3 */
	/* BRDF: either the physics core (pbrdf[material·nch + ch]) or an override */
	pc_pbrdf **pbrdf;
	pc_sim_brdf brdf;
	/* camera */
	double pitch_m, focal_m, cx, cy;
	/* supersampling: ss×ss sub-pixel offsets in (−0.5, 0.5) */
	unsigned ss;
	double ss_off[PC_SS_MAX];
	/* primary-ray culling: bounding spheres (radius 0: unbounded, never culled) */
	unsigned n_cull;
	pc_v3 cull_c[PC_CULL_MAX];
	double cull_r[PC_CULL_MAX];
	/* primary rays from the camera centre: sphere o − c and |o − c|² − r², plane (p − o)·n */
	pc_v3 prim_oc[PC_CULL_MAX];
	double prim_c[PC_CULL_MAX], prim_num[PC_CULL_MAX];
	/* electrons per second per unit radiance (W·m⁻²·sr⁻¹) of unpolarized light, per channel */
	double e_per_radiance[3];
	/* sequences */
	unsigned n_psg, n_psa, n_states;
	/* pipeline */
	pc_analyse_fn analyse;
	pc_frame_row_fn frame_row;
	/* caches (ROI-sized): electron rate per state [e⁻/s], DSNU offsets [e⁻] */
	float **rate;
	float *dsnu;
	uint32_t max_dn;
	unsigned fp_mask; /* fixed-pattern deviates the declared effects use */
};

/* render.c */
void pc_render_setup(pc_sim *sim);
/* Prepares sensor row sy for pc_render_pixel. */
void pc_render_row_begin(const pc_sim *sim, uint32_t sy, pc_render_row *rr);

/* shade.c */
/* Stokes radiance (image-plane frame, W·m⁻²·sr⁻¹) of sensor pixels (sx0 + i, rr->sy), i < n, for
 * PSG state g, averaged over each pixel's footprint: for colour channel chan[i] into S[4i..]
 * (M[16i..] the Mueller matrix, row-major; M may be NULL), or, with chan NULL, for every
 * channel c < nch into S[(i·nch + c)·4 ..] and M[(i·nch + c)·16 ..]. */
void pc_render_span(const pc_sim *sim, const pc_render_row *rr, uint32_t sx0, uint32_t n,
                    const uint8_t *chan, unsigned g, double *S, double *M);
/* One pixel, colour channel ch. */
void pc_render_pixel(const pc_sim *sim, const pc_render_row *rr, uint32_t sx, unsigned ch,
                     unsigned g, double S[4], double M[4][4]);

/* blur.c: the lens's Gaussian PSF (effect "blur"). pc_blur_begin renders the region of sensor
 * columns [x0, x0 + w) and rows [y0, y0 + h) widened by the kernel's radius (inside the sensor)
 * for PSG state g and blurs it along the rows; pc_blur_span then gives the blurred Stokes (and
 * Mueller, when begun with mueller) of pixels (sx0 + i, sy) inside that region, in
 * pc_render_span's layout. Progress (optional) counts the region's rows into *done. */
typedef struct pc_blur {
	int R;            /* kernel radius ⌈4σ⌉ */
	unsigned g;       /* PSG state */
	uint32_t x0, w;   /* output columns */
	uint32_t rx0, rw; /* rendered columns */
	uint32_t ry0, rh; /* rendered rows (= the row pass's rows) */
	double *wt;       /* 2R + 1 weights */
	double *S, *M;    /* row pass: rh × w × nch Stokes (4) and Mueller (16) */
} pc_blur;
int pc_blur_radius(double sigma);
int pc_blur_begin(const pc_sim *sim, unsigned g, uint32_t x0, uint32_t w, uint32_t y0, uint32_t h,
                  bool mueller, pc_blur *b, pc_sim_progress_fn progress, void *user, uint64_t *done,
                  uint64_t total);
void pc_blur_span(const pc_blur *b, const pc_sim *sim, uint32_t sy, uint32_t sx0, uint32_t n,
                  const uint8_t *chan, double *S, double *M);
void pc_blur_end(pc_blur *b);

/* sensor.c */
void pc_sensor_setup(pc_sim *sim);
/* The pixel's colour channel index (0 for monochrome; R/G/B = 0/1/2). */
unsigned pc_sensor_channel(const pc_sim *sim, uint32_t sx, uint32_t sy);
/* The fixed-pattern normal deviates of sensor pixels (sx0 + i, sy), i < n: orientation z0[i],
 * transmission z1[i], PRNU z2[i], DSNU z3[i] — one Philox block keyed by (seed, pixel) each —
 * and the extinction-ratio deviate z4[i] (word 0 of a second block, counter word 2 = 1, drawn
 * only when the scene declares an ER spread); only the deviates in mask (bit k for zk) that the
 * declared effects use are written. */
enum {
	PC_FP_ORIENT = 1,
	PC_FP_TRANS = 2,
	PC_FP_PRNU = 4,
	PC_FP_DSNU = 8,
	PC_FP_ER = 16,
	PC_FP_ALL = 31
};
void pc_sensor_fixed_row(const pc_sim *sim, uint32_t sy, uint32_t sx0, uint32_t n, unsigned mask,
                         double *z0, double *z1, double *z2, double *z3, double *z4);

#endif
