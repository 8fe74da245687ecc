/* sim/sim_impl.h - the simulator object (internal to sim/): render (render.c), sensor chain
 * (sensor.c), caches and API (sim.c). */
#ifndef POLARCAM_SIM_SIM_IMPL_H
#define POLARCAM_SIM_SIM_IMPL_H

#include "polarcam/pbrdf.h"
#include "polarcam/sim.h"
#include "scene_impl.h"

typedef struct pc_sim pc_sim;

/* Per-pixel work units chosen once in pc_sim_new from the effect set (the "pipeline"). */
typedef void (*pc_shade_fn)(const pc_sim *sim, unsigned ch, unsigned g, pc_v3 dir, double S[4],
			    double M[4][4]);
typedef void (*pc_analyse_fn)(const pc_sim *sim, uint32_t sx, uint32_t sy, const double z[4],
			      double a[4]);
typedef void (*pc_frame_row_fn)(const pc_sim *sim, uint64_t n, double exposure_s, double gain,
				uint32_t y, uint16_t *row);

struct pc_sim {
	pc_scene *scene;          /* shared, reference-counted */
	pc_sim_options opt;
	pc_sim_info info;
	pc_sensor_figures fig;
	unsigned fx;              /* effects in force */
	unsigned nch;             /* colour channels rendered: 1 or 3 */
	bool circular;            /* carry S3 */
	/* BRDF: either the physics core (pbrdf[material·nch + ch]) or an override */
	pc_pbrdf **pbrdf;
	pc_sim_brdf brdf;
	/* camera */
	double pitch_m, focal_m, cx, cy;
	/* supersampling: ss×ss sub-pixel offsets in (−0.5, 0.5) */
	unsigned ss;
	double ss_off[16];
	/* electrons per second per unit radiance (W·m⁻²·sr⁻¹) of unpolarized light, per channel */
	double e_per_radiance[3];
	/* sequences */
	unsigned n_psg, n_psa, n_states;
	/* pipeline */
	pc_shade_fn shade;
	pc_analyse_fn analyse;
	pc_frame_row_fn frame_row;
	/* caches (ROI-sized): electron rate per state [e⁻/s], DSNU offsets [e⁻] */
	float **rate;
	float *dsnu;
	uint32_t max_dn;
	unsigned fp_mask;         /* fixed-pattern deviates the declared effects use */
};

/* render.c */
void pc_render_setup(pc_sim *sim);
/* Stokes radiance (image-plane frame, W·m⁻²·sr⁻¹) of sensor pixel (sx, sy) for PSG state g and
 * colour channel ch, averaged over the pixel footprint; M (may be NULL) the Mueller matrix. */
void pc_render_pixel(const pc_sim *sim, uint32_t sx, uint32_t sy, unsigned ch, unsigned g,
		     double S[4], double M[4][4]);

/* sensor.c */
void pc_sensor_setup(pc_sim *sim);
/* The pixel's colour channel index (0 for monochrome; R/G/B = 0/1/2). */
unsigned pc_sensor_channel(const pc_sim *sim, uint32_t sx, uint32_t sy);
/* The fixed-pattern normal deviates of sensor pixel (sx, sy): z[0] orientation, z[1]
 * transmission, z[2] PRNU, z[3] DSNU — one Philox block keyed by (seed, pixel); only the
 * deviates in mask (bit i for z[i]) that the declared effects use are computed, the others
 * are 0. */
enum { PC_FP_ORIENT = 1, PC_FP_TRANS = 2, PC_FP_PRNU = 4, PC_FP_DSNU = 8, PC_FP_ALL = 15 };
void pc_sensor_fixed(const pc_sim *sim, uint32_t sx, uint32_t sy, unsigned mask, double z[4]);
/* Fixed-pattern factors from those deviates. */
double pc_sensor_prnu(const pc_sim *sim, const double z[4]);
double pc_sensor_dsnu(const pc_sim *sim, const double z[4]);

#endif
