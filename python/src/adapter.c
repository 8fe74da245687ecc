/* python/src/adapter.c - the Python extension's calls into the polarcam C library (see
 * adapter.h). Everything that depends on the shape of the C API is here. */
#include "adapter.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/format.h"
#include "polarcam/optics.h"
#include "polarcam/pbrdf.h"
#include "polarcam/picture.h"
#include "polarcam/sim.h"
#include "polarcam/stream.h"

#ifndef PCPY_VERSION
#error "PCPY_VERSION (the project version) must be defined by the build"
#endif

/* ---- errors and version ---- */

/* Until <polarcam/version.h> (issue 9) provides pc_version(): the project version CMake
 * passes. */
const char *pcpy_version(void)
{
	return PCPY_VERSION;
}

const char *pcpy_errname(int rc)
{
	return pc_errname(rc);
}

const char *pcpy_strerror(int rc)
{
	return pc_strerror(rc);
}

const char *pcpy_error_detail(void)
{
	return pc_error_detail();
}

int pcpy_fail(int rc, const char *msg)
{
	return pc_error(rc, "%s", msg);
}

/* ---- raw frames, layouts, methods ---- */

int pcpy_view(void *data, uint32_t width, uint32_t height, size_t stride, pcpy_dtype dtype,
              unsigned bits, pc_view *out)
{
	pc_pixfmt f = PC_FMT_INVALID;
	switch (dtype) {
	case PCPY_U8:
		if (bits > 8)
			return pc_error(
			    PC_EINVAL,
			    "bits=%u: uint8 data holds at most 8 bits (pass uint16 data "
			    "for 9..16-bit frames)",
			    bits);
		f = PC_FMT_MONO8;
		break;
	case PCPY_U16:
		if (bits && (bits < 9 || bits > 16))
			return pc_error(PC_EINVAL,
			                "bits=%u: uint16 data holds 9..16-bit frames (pass uint8 "
			                "data for 8-bit frames)",
			                bits);
		/* the LSB-aligned container format says the depth (as pc_image_read_mosaic) */
		f = bits == 10   ? PC_FMT_MONO10
		    : bits == 12 ? PC_FMT_MONO12
		    : bits == 14 ? PC_FMT_MONO14
		                 : PC_FMT_MONO16;
		break;
	case PCPY_F32:
		/* bits of float data: the scale of the values (pcpy_full_scale), not a container */
		f = PC_FMT_FLOAT32;
		break;
	}
	*out = (pc_view){data, width, height, stride, f};
	int rc = pc_view_check(out);
	return rc ? pc_error_prefix(rc, "raw: ") : 0;
}

unsigned pcpy_view_bits(const pc_view *v)
{
	const pc_format_info *fi = pc_format_info_get(v->format);
	return fi->is_float ? 32 : fi->bits;
}

int pcpy_check_bits(const pc_view *v, unsigned bits)
{
	/* the 16-bit container: pc_view_check_bits trusts a Mono12 label to hold 12 bits */
	pc_view c = *v;
	const pc_format_info *fi = pc_format_info_get(v->format);
	if (!fi->is_float && fi->packing == PC_PACK_NONE && fi->bits > 8)
		c.format = PC_FMT_MONO16;
	/* Fast pass for the common case (every value fits): any bit at or above `bits` set, one
	 * vectorisable OR per row; pc_view_check_bits unpacks each row first. The library's check
	 * then finds and names the first bad pixel. */
	if (!fi->is_float && fi->packing == PC_PACK_NONE && bits >= 1 && bits < 16) {
		unsigned acc = 0;
		for (uint32_t y = 0; y < v->height && !acc; y++) {
			const uint8_t *row = pc_view_row_unchecked(v, y);
			if (fi->bits > 8) {
				const uint16_t *r = (const uint16_t *)(const void *)row;
				uint16_t a = 0;
				for (uint32_t x = 0; x < v->width; x++)
					a |= (uint16_t)(r[x] >> bits);
				acc = a;
			} else {
				uint8_t a = 0;
				for (uint32_t x = 0; x < v->width; x++)
					a |= (uint8_t)(row[x] >> (bits < 8 ? bits : 7));
				acc = bits < 8 ? a : 0;
			}
		}
		if (!acc)
			return 0;
	}
	int rc = pc_view_check_bits(&c, bits);
	return rc ? pc_error_prefix(rc, "raw: ") : 0;
}

int pcpy_layout_parse(const char *layout, pc_mosaic *m)
{
	int rc = pc_mosaic_parse(layout, m);
	return rc ? pc_error_prefix(rc, "layout: ") : 0;
}

void pcpy_layout_format(const pc_mosaic *m, char *buf, unsigned size)
{
	pc_mosaic_format(m, buf, size);
}

int pcpy_method(const char *name, const pc_mosaic *m, int *method)
{
	bool colour = m->period == 4;
	pc_demosaic_method dm = colour ? PC_DM_BAYER_FIRST : PC_DM_BILINEAR;
	if (name) {
		int rc = pc_demosaic_method_from_name(name, &dm);
		if (rc)
			return pc_error_prefix(rc, "method: ");
	}
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(dm);
	unsigned need = colour ? PC_DMF_COLOR : PC_DMF_MONO;
	if (!(mi->flags & need)) {
		char lay[64], list[512] = "";
		pc_mosaic_format(m, lay, sizeof lay);
		for (unsigned i = 0; i < PC_DM_COUNT; i++) {
			const pc_demosaic_method_info *o =
			    pc_demosaic_method_get((pc_demosaic_method)i);
			if (o && (o->flags & need)) {
				if (*list)
					strncat(list, ", ", sizeof list - strlen(list) - 1);
				strncat(list, o->name, sizeof list - strlen(list) - 1);
			}
		}
		return pc_error(PC_EINVAL,
		                "method '%s' works on %s mosaics, the layout %s is %s: use one of "
		                "%s",
		                mi->name, colour ? "monochrome" : "colour-polarization", lay,
		                colour ? "colour-polarization" : "monochrome", list);
	}
	*method = (int)dm;
	return 0;
}

const char *pcpy_method_name(int method)
{
	const pc_demosaic_method_info *mi = pc_demosaic_method_get((pc_demosaic_method)method);
	return mi ? mi->name : "?";
}

const pc_demosaic_method_info *pcpy_method_info(unsigned i)
{
	return i < PC_DM_COUNT ? pc_demosaic_method_get((pc_demosaic_method)i) : NULL;
}

unsigned pcpy_channels(const pc_mosaic *m)
{
	return pc_demosaic_channels(m);
}

void pcpy_out_size(int method, uint32_t w, uint32_t h, uint32_t *ow, uint32_t *oh)
{
	pc_demosaic_out_size((pc_demosaic_method)method, w, h, ow, oh);
}

/* ---- the pipeline ---- */

int pcpy_demosaic(const pc_view *raw, const pc_mosaic *m, int method, int threads,
                  double full_scale, double noise_gain, const pc_fplane *out)
{
	pc_pipeline_opts o = pc_pipeline_defaults();
	o.method = (pc_demosaic_method)method;
	o.mosaic = *m;
	o.threads = threads;
	o.full_scale = full_scale;
	o.noise_gain = noise_gain;
	return pc_demosaic_run(raw, &o, out, NULL);
}

double pcpy_full_scale(const pc_view *v, unsigned bits)
{
	if (v->format == PC_FMT_FLOAT32 && bits)
		return ldexp(1.0, (int)bits) - 1.0;
	return 0; /* the library's default: 2^bits - 1 of the format, 1.0 for float */
}

int pcpy_stokes(const pc_view *raw, const pc_mosaic *m, const pcpy_stokes_opts *o,
                const pc_stokes_out *out, pc_validity *valid)
{
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.method = (pc_demosaic_method)o->method;
	po.mosaic = *m;
	po.threads = o->threads;
	po.full_scale = o->full_scale;
	po.black_level = o->black_level;
	po.saturation_level = o->saturation_level;
	po.dead_level = o->dead_level;
	po.pinv = o->pinv;
	po.noise_gain = o->noise_gain;
	return pc_stokes_run(raw, &po, out, valid);
}

bool pcpy_stokes_streams(const pc_stokes_out *out, uint32_t w, uint32_t h)
{
	return pc_stokes_streams(out, w, h);
}

int pcpy_stokes_channels(const pc_fplane in[4], uint32_t w, uint32_t h,
                         const pc_analyser_pinv *pinv, const pc_stokes_out *out)
{
	return pc_stokes_from_channels(in, w, h, pinv, out);
}

int pcpy_pinv(const float *w, size_t n, float *pinv)
{
	return pc_stokes_pinv(w, n, pinv);
}

/* ---- calibration files ---- */

struct pcpy_calib {
	pc_calib cal;
	/* readers: pc_calib_stokes with the method already cached (it only reads the pc_calib);
	 * writer: anything that may (re)build the cache */
	pthread_rwlock_t lock;
};

int pcpy_calib_read(const char *path, pcpy_calib **out)
{
	*out = NULL;
	pcpy_calib *c = calloc(1, sizeof *c);
	if (!c)
		return pc_error(PC_ENOMEM, "calibration %s", path);
	pc_calib_init(&c->cal);
	int rc = pc_calib_read(path, &c->cal);
	if (rc) {
		pc_calib_free(&c->cal);
		free(c);
		return rc;
	}
	if (pthread_rwlock_init(&c->lock, NULL)) {
		pc_calib_free(&c->cal);
		free(c);
		return pc_error(PC_ENOMEM, "calibration %s: no lock", path);
	}
	*out = c;
	return 0;
}

void pcpy_calib_free(pcpy_calib *c)
{
	if (!c)
		return;
	pthread_rwlock_destroy(&c->lock);
	pc_calib_free(&c->cal);
	free(c);
}

const pc_calib *pcpy_calib_get(const pcpy_calib *c)
{
	return &c->cal;
}

static bool calib_superpixel(int method)
{
	return method == PC_DM_SUPERPIXEL || method == PC_DM_SUPERPIXEL_HALF;
}

/* Whether pc_calib_stokes with this method only reads the pc_calib (call with a lock held). */
static bool calib_cached(const pc_calib *cal, int method)
{
	return pc_calib_prepared(cal, (pc_demosaic_method)method);
}

int pcpy_calib_stokes(pcpy_calib *c, const pc_view *raw, const pc_mosaic *m, unsigned bits,
                      int method, int threads, double noise_gain, double gain_db,
                      const pc_stokes_out *out, uint8_t *valid, uint64_t *n_invalid)
{
	pc_calib_geometry g = c->cal.geo;
	g.width = raw->width;
	g.height = raw->height;
	g.sensor_width = g.sensor_height = 0;
	g.bits = bits;
	if (m)
		g.mosaic = *m;
	size_t nbad = 0;
	int rc;
	pthread_rwlock_rdlock(&c->lock);
	if (calib_cached(&c->cal, method)) {
		rc = pc_calib_stokes_gain(&c->cal, raw, &g, (pc_demosaic_method)method, threads,
		                          noise_gain, gain_db, out, valid, &nbad, NULL);
		pthread_rwlock_unlock(&c->lock);
	} else {
		pthread_rwlock_unlock(&c->lock);
		pthread_rwlock_wrlock(&c->lock);
		rc = pc_calib_stokes_gain(&c->cal, raw, &g, (pc_demosaic_method)method, threads,
		                          noise_gain, gain_db, out, valid, &nbad, NULL);
		pthread_rwlock_unlock(&c->lock);
	}
	if (n_invalid)
		*n_invalid = nbad;
	return rc;
}

int pcpy_calib_pinv_grid(const pcpy_calib *c, int method, uint32_t *gw, uint32_t *gh)
{
	const pc_calib *cal = &c->cal;
	if (!(cal->parts & PC_CAL_ANALYSER))
		return pc_error(PC_EINVAL,
		                "the calibration has no analyser part (polarcam calibrate "
		                "analyser)");
	*gw = calib_superpixel(method) ? cal->geo.width / 2 : cal->geo.width;
	*gh = calib_superpixel(method) ? cal->geo.height / 2 : cal->geo.height;
	return 0;
}

int pcpy_calib_pinv_copy(pcpy_calib *c, int method, int threads, float *dst)
{
	pthread_rwlock_wrlock(&c->lock);
	pc_analyser_pinv p;
	int rc = pc_calib_pinv(&c->cal, (pc_demosaic_method)method, threads, &p);
	if (!rc)
		memcpy(dst, p.m, 12 * sizeof(float) * p.grid_w * p.grid_h);
	pthread_rwlock_unlock(&c->lock);
	return rc;
}

/* ---- pictures ----
 * The composition of io/pictures.c (pc_pictures_write_opts) without the annotation: S0 grey
 * from 0 to its 99.9th percentile, DoLP grey 0..1, AoLP hue with DoLP as value or saturation,
 * the low-signal hatch at 1 % of the S0 scale. */
int pcpy_picture(pcpy_picture_kind kind, const pc_fplane *img, const pc_fplane *dolp,
                 const pc_fplane *s0, uint32_t w, uint32_t h, float lo, float hi, double mask_s0,
                 uint8_t *rgb, size_t stride)
{
	int rc;
	if (!isfinite(mask_s0))
		return pc_error(PC_EINVAL, "mask_s0=%g: must be finite", mask_s0);
	switch (kind) {
	case PCPY_PIC_GREY:
		if (isnan(lo))
			lo = 0;
		if (isnan(hi)) {
			hi = pc_picture_quantile(img, w, h, 0.999);
			if (!(hi > 0))
				hi = 1;
		}
		return pc_picture_grey(img, w, h, lo, hi, rgb, stride);
	case PCPY_PIC_ON_S0:
		/* the S0 picture's scale, as pc_pictures_write_minmax (polarcam/io.h) */
		if (isnan(lo))
			lo = 0;
		if (isnan(hi)) {
			hi = pc_picture_quantile(s0 ? s0 : img, w, h, 0.999);
			if (!(hi > 0))
				hi = 1;
		}
		return pc_picture_grey(img, w, h, lo, hi, rgb, stride);
	case PCPY_PIC_SIGNED: {
		float q = fmaxf(fabsf(pc_picture_quantile(img, w, h, 0.001)),
		                fabsf(pc_picture_quantile(img, w, h, 0.999)));
		if (!(q > 0))
			q = 1;
		return pc_picture_grey(img, w, h, isnan(lo) ? -q : lo, isnan(hi) ? q : hi, rgb,
		                       stride);
	}
	case PCPY_PIC_DOLP:
		rc =
		    pc_picture_grey(img, w, h, isnan(lo) ? 0 : lo, isnan(hi) ? 1 : hi, rgb, stride);
		break;
	case PCPY_PIC_AOLP:
	case PCPY_PIC_AOLP_SAT:
	case PCPY_PIC_AOLP_HUE:
		rc = pc_picture_aolp(img, dolp, w, h,
		                     kind == PCPY_PIC_AOLP       ? PC_AOLP_VALUE
		                     : kind == PCPY_PIC_AOLP_SAT ? PC_AOLP_SATURATION
		                                                 : PC_AOLP_HUE_ONLY,
		                     1.0f, rgb, stride);
		break;
	default:
		return pc_error(PC_EINVAL, "picture: unknown kind %d", (int)kind);
	}
	if (rc || !s0 || mask_s0 < 0 || kind == PCPY_PIC_AOLP_HUE)
		return rc;
	float mask = (float)mask_s0;
	if (mask_s0 == 0) {
		float top = pc_picture_quantile(s0, w, h, 0.999);
		if (!(top > 0))
			top = 1;
		/* PC_PICTURES_MASK_DEFAULT_REL of polarcam/io.h */
		mask = (float)(0.01 * top);
	}
	pc_picture_mask_low(s0, w, h, mask, rgb, stride);
	return 0;
}

/* ---- physics ---- */

/* Prepared materials are kept across calls (pc_pbrdf_new builds the material's rho^s table:
 * milliseconds, while an evaluation takes microseconds): a process-wide cache of up to
 * PCPY_PBRDF_KEEP materials, each pinned by the calls using it (so that one thread never frees
 * a material another is evaluating; pc_pbrdf objects are immutable and thread-safe). A call
 * keeps its own list of pinned entries; a material that finds the shared cache full of pinned
 * entries stays private to the call. */
#define PCPY_PBRDF_KEEP 64

typedef struct pbrdf_entry {
	pc_material m; /* the key: every field */
	pc_pbrdf *p;
	unsigned pins;
	uint64_t used; /* last use, for eviction */
} pbrdf_entry;

static struct {
	pthread_mutex_t lock;
	pbrdf_entry e[PCPY_PBRDF_KEEP];
	unsigned n;
	uint64_t clock;
} g_pbrdf = {.lock = PTHREAD_MUTEX_INITIALIZER};

struct pcpy_pbrdf_cache {
	pc_material base;
	struct {
		pc_pbrdf *p;
		double n, k, sigma;
		bool shared; /* pinned in g_pbrdf (else owned by this call) */
	} * e;
	size_t n, cap;
	size_t last; /* the entry of the previous element (consecutive elements share it) */
};

static bool same_material(const pc_material *a, const pc_material *b)
{
	return a->n == b->n && a->k == b->k && a->sigma == b->sigma && a->diffuse == b->diffuse &&
	       a->shadowing == b->shadowing && a->rho_mode == b->rho_mode &&
	       a->rho_order == b->rho_order;
}

int pcpy_pbrdf_cache_new(int diffuse, int shadowing, int rho_mode, int rho_order,
                         pcpy_pbrdf_cache **out)
{
	pcpy_pbrdf_cache *c = calloc(1, sizeof *c);
	if (!c)
		return pc_error(PC_ENOMEM, "pbrdf material cache");
	c->base.diffuse = (pc_diffuse)diffuse;
	c->base.shadowing = (pc_shadowing)shadowing;
	c->base.rho_mode = (pc_rho_mode)rho_mode;
	c->base.rho_order = rho_order;
	*out = c;
	return 0;
}

void pcpy_pbrdf_cache_free(pcpy_pbrdf_cache *c)
{
	if (!c)
		return;
	pthread_mutex_lock(&g_pbrdf.lock);
	for (size_t i = 0; i < c->n; i++)
		if (c->e[i].shared)
			for (unsigned j = 0; j < g_pbrdf.n; j++)
				if (g_pbrdf.e[j].p == c->e[i].p)
					g_pbrdf.e[j].pins--;
	pthread_mutex_unlock(&g_pbrdf.lock);
	for (size_t i = 0; i < c->n; i++)
		if (!c->e[i].shared)
			pc_pbrdf_free(c->e[i].p);
	free(c->e);
	free(c);
}

/* The prepared material m: pinned from the shared cache, or made (and shared when there is
 * room). */
static int material(pcpy_pbrdf_cache *c, const pc_material *m, const pc_pbrdf **out)
{
	if (c->n == c->cap) {
		size_t cap = c->cap ? 2 * c->cap : 8;
		void *e = realloc(c->e, cap * sizeof *c->e);
		if (!e)
			return pc_error(PC_ENOMEM, "pbrdf material cache");
		c->e = e;
		c->cap = cap;
	}
	pc_pbrdf *p = NULL;
	pthread_mutex_lock(&g_pbrdf.lock);
	for (unsigned j = 0; j < g_pbrdf.n && !p; j++)
		if (same_material(&g_pbrdf.e[j].m, m)) {
			p = g_pbrdf.e[j].p;
			g_pbrdf.e[j].pins++;
			g_pbrdf.e[j].used = ++g_pbrdf.clock;
		}
	pthread_mutex_unlock(&g_pbrdf.lock);
	bool shared = p != NULL;
	if (!p) {
		int rc = pc_pbrdf_new(m, &p); /* the slow part, outside the lock */
		if (rc)
			return rc;
		pc_pbrdf *victim = NULL;
		pthread_mutex_lock(&g_pbrdf.lock);
		unsigned slot = g_pbrdf.n;
		if (slot == PCPY_PBRDF_KEEP) {
			slot = UINT32_MAX;
			for (unsigned j = 0; j < g_pbrdf.n; j++)
				if (!g_pbrdf.e[j].pins &&
				    (slot == UINT32_MAX ||
				     g_pbrdf.e[j].used < g_pbrdf.e[slot].used))
					slot = j;
			if (slot != UINT32_MAX)
				victim = g_pbrdf.e[slot].p;
		} else {
			g_pbrdf.n++;
		}
		if (slot != UINT32_MAX) {
			g_pbrdf.e[slot] = (pbrdf_entry){*m, p, 1, ++g_pbrdf.clock};
			shared = true;
		}
		pthread_mutex_unlock(&g_pbrdf.lock);
		pc_pbrdf_free(victim);
	}
	c->e[c->n].p = p;
	c->e[c->n].n = m->n;
	c->e[c->n].k = m->k;
	c->e[c->n].sigma = m->sigma;
	c->e[c->n].shared = shared;
	c->last = c->n++;
	*out = p;
	return 0;
}

int pcpy_pbrdf_eval(pcpy_pbrdf_cache *c, double n, double k, double sigma, double theta_i_deg,
                    double theta_r_deg, double phi_deg, double f[4][4])
{
	/* the checks and the degree conversion of `polarcam pbrdf` (tools/cmd_pbrdf.c) */
	if (!(theta_i_deg >= 0 && theta_i_deg <= 90))
		return pc_error(PC_EINVAL, "theta_i %g: must be in [0, 90] degrees", theta_i_deg);
	if (!(theta_r_deg >= 0 && theta_r_deg <= 90))
		return pc_error(PC_EINVAL, "theta_r %g: must be in [0, 90] degrees", theta_r_deg);
	if (!isfinite(phi_deg))
		return pc_error(PC_EINVAL, "phi %g: must be finite", phi_deg);
	const pc_pbrdf *p = NULL;
	if (c->n && c->e[c->last].n == n && c->e[c->last].k == k && c->e[c->last].sigma == sigma)
		p = c->e[c->last].p;
	for (size_t i = 0; i < c->n && !p; i++)
		if (c->e[i].n == n && c->e[i].k == k && c->e[i].sigma == sigma) {
			p = c->e[i].p;
			c->last = i;
		}
	if (!p) {
		pc_material m = c->base;
		m.n = n;
		m.k = k;
		m.sigma = sigma;
		int rc = material(c, &m, &p);
		if (rc)
			return rc;
	}
	/* degrees as the CLI: sines and cosines exact at multiples of 90° */
	return pc_pbrdf_eval_deg(p, theta_i_deg, theta_r_deg, phi_deg, f);
}

int pcpy_pbrdf_diffuse(const char *name, int *out)
{
	if (!strcmp(name, "fresnel"))
		*out = PC_DIFFUSE_FRESNEL;
	else if (!strcmp(name, "geometric"))
		*out = PC_DIFFUSE_GEOMETRIC;
	else if (!strcmp(name, "none"))
		*out = PC_DIFFUSE_NONE;
	else
		return pc_error(PC_EINVAL, "diffuse='%s': expected fresnel, geometric or none",
		                name);
	return 0;
}

int pcpy_pbrdf_shadowing(const char *name, int *out)
{
	if (!strcmp(name, "ts"))
		*out = PC_SHADOW_TS;
	else if (!strcmp(name, "none"))
		*out = PC_SHADOW_NONE;
	else
		return pc_error(PC_EINVAL, "shadowing='%s': expected ts or none", name);
	return 0;
}

int pcpy_pbrdf_rho(const char *name, int *mode, int *order)
{
	*order = 0;
	if (!strcmp(name, "table")) {
		*mode = PC_RHO_TABLE;
		return 0;
	}
	if (!strcmp(name, "quad")) {
		*mode = PC_RHO_QUAD;
		return 0;
	}
	if (!strncmp(name, "quad:", 5)) {
		char *end;
		long n = strtol(name + 5, &end, 10);
		if (end != name + 5 && !*end && n >= 2 && n <= 1024) {
			*mode = PC_RHO_QUAD;
			*order = (int)n;
			return 0;
		}
	}
	return pc_error(PC_EINVAL, "rho='%s': expected table, quad or quad:N (N in [2, 1024])",
	                name);
}

int pcpy_decompose(const double m[4][4], bool filter, pc_lu_chipman *out)
{
	return pc_lu_chipman_decompose(m, filter ? PC_LC_FILTER : 0, out);
}

/* ---- the simulator ---- */

struct pcpy_render {
	pc_sim *sim;
	pc_scene *scene;
	pc_sim_info in;
	int prepared; /* state whose truth is in the caches' last render, -1: none */
	pc_view tmp;  /* frames in the sensor's format when it is not 16-bit LSB-aligned */
};

int pcpy_render_new(const char *scene_path, const char *scene_text, uint64_t seed,
                    const uint32_t roi[4], int threads, pcpy_render **out, pcpy_render_info *info)
{
	pcpy_render *r = calloc(1, sizeof *r);
	if (!r)
		return pc_error(PC_ENOMEM, "render");
	r->prepared = -1;
	int rc = scene_text   ? pc_scene_parse(scene_text, "scene", NULL, &r->scene)
	         : scene_path ? pc_scene_load(scene_path, &r->scene)
	                      : pc_scene_load_default(&r->scene);
	pc_sim_options o = pc_sim_options_default();
	o.seed = seed;
	o.threads = threads;
	if (roi) {
		o.roi_x = roi[0];
		o.roi_y = roi[1];
		o.roi_width = roi[2];
		o.roi_height = roi[3];
	}
	if (!rc)
		rc = pc_sim_new(r->scene, &o, &r->sim);
	if (rc) {
		pcpy_render_free(r);
		return rc;
	}
	pc_sim_get_info(r->sim, &r->in);
	const pc_sim_info *in = &r->in;
	memset(info, 0, sizeof *info);
	info->width = in->width;
	info->height = in->height;
	info->sensor_width = in->sensor_width;
	info->sensor_height = in->sensor_height;
	info->offset_x = in->offset_x;
	info->offset_y = in->offset_y;
	info->bits = in->bits;
	info->colour_channels = in->colour_channels;
	info->n_psg = in->n_psg;
	info->n_psa = in->n_psa;
	info->n_states = in->n_states;
	info->mueller = (in->effects & PC_FX_MUELLER) != 0;
	info->effects = in->effects;
	snprintf(info->format, sizeof info->format, "%s", pc_format_info_get(in->format)->name);
	pc_mosaic_format(&in->mosaic, info->layout, sizeof info->layout);
	snprintf(info->scene_name, sizeof info->scene_name, "%s",
	         pc_scene_name(r->scene) ? pc_scene_name(r->scene) : "");
	info->exposure_us = in->exposure_us;
	info->gain_db = in->gain_db;
	info->frame_rate_hz = in->frame_rate_hz;
	pc_sensor_figures fig;
	pc_sim_get_sensor(r->sim, &fig);
	info->black_level_dn = fig.offset_dn;
	for (unsigned c = 0; c < in->colour_channels && c < 3; c++)
		info->dn_per_radiance[c] = pc_sim_dn_per_radiance(r->sim, NULL, c);
	const pc_format_info *fi = pc_format_info_get(in->format);
	if (fi->packing != PC_PACK_NONE || fi->bits <= 8) {
		if ((rc = pc_view_alloc(&r->tmp, in->format, in->width, in->height, 64))) {
			pcpy_render_free(r);
			return rc;
		}
	}
	*out = r;
	return 0;
}

unsigned pcpy_render_state(const pcpy_render *r, uint64_t n)
{
	return (unsigned)(n % r->in.n_psg);
}

int pcpy_render_frame(pcpy_render *r, uint64_t n, uint16_t *raw, float *truth, float *mueller,
                      pc_frame_meta *meta)
{
	unsigned g = pcpy_render_state(r, n);
	int rc;
	/* as `polarcam render`: the state's signal (and truth) once, then the frame */
	if (truth || mueller || !pc_sim_is_prepared(r->sim, g)) {
		if ((rc = pc_sim_prepare(r->sim, g, truth,
		                         (r->in.effects & PC_FX_MUELLER) ? mueller : NULL, NULL,
		                         NULL)))
			return rc;
	}
	size_t stride = (size_t)r->in.width * 2;
	if (!r->tmp.data) {
		pc_view v = {raw, r->in.width, r->in.height, stride, r->in.format};
		return pc_sim_frame(r->sim, n, NULL, &v, meta);
	}
	if ((rc = pc_sim_frame(r->sim, n, NULL, &r->tmp, meta)))
		return rc;
	return pc_view_to_u16(&r->tmp, raw, stride);
}

const char *pcpy_effect_name(unsigned effects, unsigned i)
{
	for (unsigned b = 0; b < 32; b++)
		if (effects & (1u << b)) {
			if (i == 0)
				return pc_sim_effect_name(1u << b);
			i--;
		}
	return NULL;
}

char *pcpy_render_scene_json(const pcpy_render *r)
{
	return pc_scene_to_json(r->scene);
}

void pcpy_render_free(pcpy_render *r)
{
	if (!r)
		return;
	pc_sim_free(r->sim);
	pc_scene_free(r->scene);
	pc_view_free(&r->tmp);
	free(r);
}

/* ---- frame sources ---- */

/* Format/ROI negotiation, controls and buffers as `polarcam capture` does them: the library's
 * pc_stream_open. */
int pcpy_source_open(const char *uri, const pcpy_stream_args *a, pc_source **out)
{
	pc_stream_request r;
	pc_stream_request_init(&r);
	r.uri = uri;
	r.format = a->format;
	r.roi_set = a->roi_set;
	memcpy(r.roi, a->roi, sizeof r.roi);
	r.exposure_us = a->exposure_us;
	r.gain_db = a->gain_db;
	r.fps = a->frame_rate_hz;
	r.buffers = a->buffers;
	return pc_stream_open(&r, out);
}

void pcpy_source_close(pc_source *s)
{
	pc_source_close(s);
}

int pcpy_source_start(pc_source *s)
{
	return pc_source_start(s);
}

int pcpy_source_stop(pc_source *s)
{
	return pc_source_stop(s);
}

bool pcpy_source_streaming(const pc_source *s)
{
	return pc_source_get_state(s) == PC_SOURCE_STREAMING;
}

const char *pcpy_source_state(const pc_source *s)
{
	return pc_source_state_name(pc_source_get_state(s));
}

int pcpy_source_format(pc_source *s, pc_source_format *f)
{
	return pc_source_get_format(s, f);
}

int pcpy_source_info(pc_source *s, pc_source_info *info)
{
	return pc_source_get_info(s, info);
}

int pcpy_source_stats(pc_source *s, pc_source_stats *st)
{
	return pc_source_get_stats(s, st);
}

int pcpy_source_read(pc_source *s, int timeout_ms, uint16_t *dst, size_t dst_stride,
                     pc_frame_meta *meta, pc_mosaic *mosaic, unsigned *bits)
{
	pc_buffer *b;
	int rc = pc_source_dequeue(s, timeout_ms, &b);
	if (rc)
		return rc;
	rc = pc_view_to_u16(&b->frame.view, dst, dst_stride);
	*meta = b->frame.meta;
	*mosaic = b->frame.mosaic;
	*bits = pc_format_info_get(b->frame.view.format)->bits;
	int rq = pc_source_requeue(s, b);
	return rc ? rc : rq;
}

int pcpy_control_id(const char *name)
{
	for (int i = 0; i < PC_CTRL_COUNT; i++)
		if (!strcmp(name, pc_control_name((pc_control_id)i)))
			return i;
	return -1;
}

const char *pcpy_control_name(int id)
{
	return pc_control_name((pc_control_id)id);
}

int pcpy_control_count(void)
{
	return PC_CTRL_COUNT;
}

int pcpy_control_query(pc_source *s, int id, pc_control_info *info)
{
	return pc_source_control_query(s, (pc_control_id)id, info);
}

int pcpy_control_get(pc_source *s, int id, double *v)
{
	return pc_source_control_get(s, (pc_control_id)id, v);
}

int pcpy_control_set(pc_source *s, int id, double v, double *applied)
{
	int rc = pc_source_control_set(s, (pc_control_id)id, v, applied);
	return rc ? pc_error_prefix(rc, "%s: ", pc_control_name((pc_control_id)id)) : 0;
}

const char *pcpy_backend(unsigned i, bool *built, const char **summary)
{
	const pc_source_backend *b = pc_source_backend_get(i);
	if (!b)
		return NULL;
	*built = b->ops != NULL;
	*summary = b->summary;
	return b->scheme;
}
