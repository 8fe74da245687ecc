/* sim/scene_impl.h - the parsed scene (internal to sim/). Built by scene.c, read by sim.c. */
#ifndef POLARCAM_SIM_SCENE_IMPL_H
#define POLARCAM_SIM_SCENE_IMPL_H

#include <stdbool.h>
#include <stdint.h>

#include "polarcam/pbrdf.h"
#include "polarcam/sim.h"
#include "vec.h"

#define PC_SIM_MAX_STATES 64
#define PC_SIM_MAX_CH     3

typedef struct pc_sim_material {
	char name[64];
	pc_material m[PC_SIM_MAX_CH]; /* per colour channel (index 0 for monochrome) */
} pc_sim_material;

enum pc_light_type { PC_LIGHT_DIRECTIONAL = 0, PC_LIGHT_POINT };

typedef struct pc_sim_light {
	int type;
	pc_v3 direction;             /* directional: unit vector from the scene towards the light */
	pc_v3 position;              /* point */
	double power[PC_SIM_MAX_CH]; /* W/m² at normal incidence (directional) or W/sr (point) */
	bool has_reference;
	pc_v3 reference;        /* user's polarization reference axis (world) */
	pc_v3 frame_d, frame_s; /* directional: the beam's Stokes frame, computed once */
	unsigned n_states;      /* ≥ 1; > 1 for a PSG sequence */
	double stokes[PC_SIM_MAX_STATES][4]; /* normalized (S0 = 1), in the light's frame */
} pc_sim_light;

enum pc_object_type { PC_OBJ_PLANE = 0, PC_OBJ_SPHERE, PC_OBJ_BOX, PC_OBJ_MESH };

typedef struct pc_mesh {
	unsigned n_vertices, n_triangles;
	pc_v3 *v;        /* world-space vertices */
	pc_v3 *vn;       /* world-space unit vertex normals, or NULL (flat shading) */
	uint32_t *tri;   /* 3 vertex indices per triangle */
	uint32_t *tri_n; /* 3 normal indices per triangle (when vn) */
	/* BVH (bvh.c): nodes in depth-first order; leaves reference a range of tri_order. */
	struct pc_bvh_node *nodes;
	unsigned n_nodes;
	uint32_t *tri_order;
} pc_mesh;

typedef struct pc_sim_object {
	int type;
	unsigned material;
	/* plane: point, unit normal; finite when half_u, half_v > 0 (axes u, v) */
	pc_v3 p, n, u, v;
	double half_u, half_v;
	/* sphere */
	pc_v3 center;
	double radius;
	/* box: centre, half sizes, rotation local→world (rot; world = rot·local + centre) */
	pc_v3 half;
	pc_m3 rot;
	/* mesh */
	pc_mesh *mesh;
	pc_v3 bmin, bmax; /* world bounds (mesh, box, sphere, finite plane) */
} pc_sim_object;

typedef struct pc_sim_camera {
	double focal_length_mm, f_number;
	pc_v3 position, forward, right, up; /* orthonormal; right × up = −forward */
	double principal_x, principal_y;    /* principal point in pixels (default: centre) */
} pc_sim_camera;

struct pc_scene {
	int refcount; /* atomic in scene.c */
	char *name;
	char *source;    /* path or "<default>" */
	char *json_text; /* canonical text of the input (json_dumps of the parsed document) */
	pc_sim_camera camera;
	pc_sensor_figures sensor;
	unsigned effects;
	unsigned supersampling;           /* n for n×n when PC_FX_SUPERSAMPLING */
	double blur_sigma;                /* the PSF's σ in pixels when PC_FX_BLUR */
	double background[PC_SIM_MAX_CH]; /* unpolarized radiance of rays that hit nothing */
	unsigned n_materials, n_lights, n_objects;
	pc_sim_material *materials;
	pc_sim_light *lights;
	pc_sim_object *objects;
	unsigned n_psa;
	double psa[PC_SIM_MAX_STATES][4][4];
	bool psa_declared;
};

/* Reference-counted sharing between a scene and the sims built from it. */
void pc_scene_ref(pc_scene *s);

/* Sensor presets (sensor.c). */
int pc_sensor_preset(const char *name, pc_sensor_figures *fig);

/* Stokes frame of a light's beam at point x (world): unit propagation d and s-axis (p = d × s).
 * Default s = unit(d × ẑ) (s-polarized with respect to the horizontal ground z = 0), world x when
 * d ∥ ẑ, or the light's reference projected ⟂ d. Returns the irradiance factor per unit power
 * (1 for directional, 1/r² for point lights) and the distance to the light (∞ for directional). */
double pc_light_frame(const pc_sim_light *l, pc_v3 x, pc_v3 *d, pc_v3 *s, double *dist);
/* Precomputes what pc_light_frame needs of a light (called once per light by the parser). */
void pc_light_prepare(pc_sim_light *l);

/* Mesh loading (obj.c) and BVH (bvh.c). */
int pc_obj_load(const char *path, const pc_m3 *rot, pc_v3 scale, pc_v3 translate, bool smooth,
                pc_mesh **out);
void pc_mesh_free(pc_mesh *m);
int pc_bvh_build(pc_mesh *m);

/* Ray queries (geometry.c). t in (tmin, tmax). */
typedef struct pc_hit {
	double t;
	pc_v3 n;  /* unit shading normal (not yet flipped towards the viewer) */
	pc_v3 ng; /* unit geometric normal */
	unsigned object;
} pc_hit;

bool pc_scene_intersect(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax, pc_hit *hit);
bool pc_scene_occluded(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax);

/* Any object: nearest (any = false) or some (any = true) hit in (tmin, tmax), with the shading
 * and geometric normals. */
bool pc_object_hit(const pc_sim_object *ob, pc_v3 o, pc_v3 d, double tmin, double tmax, bool any,
                   double *t, pc_v3 *n, pc_v3 *ng);
/* A sphere containing the object (false for unbounded objects: infinite planes). */
bool pc_object_bsphere(const pc_sim_object *ob, pc_v3 *c, double *r);
/* Planes, spheres and boxes: a ray leaving the surface away from the body (or, for a plane,
 * away from the plane) cannot meet the same object again. */
bool pc_object_convex(const pc_sim_object *ob);
/* Primary-ray culling: objects i < n are tested only when the ray's pixel column x lies in
 * [lo[i], hi[i]] (conservative ranges from render.c; lo > hi: never). */
typedef struct pc_cull {
	unsigned n;
	const int32_t *lo, *hi;
} pc_cull;
bool pc_scene_intersect_cull(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax,
                             int32_t x, const pc_cull *cull, pc_hit *hit);
/* pc_scene_occluded ignoring object skip (UINT_MAX: none). */
bool pc_scene_occluded_skip(const pc_scene *s, pc_v3 o, pc_v3 d, double tmin, double tmax,
                            unsigned skip);

#endif
