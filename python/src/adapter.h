/* python/src/adapter.h - every call the Python extension makes into the polarcam C library.
 *
 * module.c (the CPython side) includes the library's headers for their types and constants
 * only (pc_view, pc_fplane, pc_mosaic, pc_frame_meta, pc_lu_chipman, ...) and calls library
 * functions only through this file, so that a change of the C API (issue 9: the one front door
 * for demosaic -> Stokes with black level and calibration, the source -> Stokes stream and the
 * simulator description moving from tools/ into the library, pc_version()) is absorbed here.
 *
 * Nothing here touches Python objects or the GIL: module.c calls these with the GIL released
 * (except the cheap look-ups marked "with the GIL"), and turns a negative return into a Python
 * exception with pcpy_error_detail(), which must be read on the same thread before the next
 * library call.
 */
#ifndef POLARCAM_PY_ADAPTER_H
#define POLARCAM_PY_ADAPTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "polarcam/calib.h"
#include "polarcam/decompose.h"
#include "polarcam/demosaic.h"
#include "polarcam/frame.h"
#include "polarcam/mosaic.h"
#include "polarcam/source.h"
#include "polarcam/stokes.h"

/* ---- errors and version ---- */

/* The library version string ("0.1.0"). */
const char *pcpy_version(void);
/* Symbolic name ("PC_EINVAL"), static description and the calling thread's detail message of
 * an error code. */
const char *pcpy_errname(int rc);
const char *pcpy_strerror(int rc);
const char *pcpy_error_detail(void);
/* Sets the calling thread's detail message (for errors found by the adapter itself). */
int pcpy_fail(int rc, const char *msg);

/* ---- raw frames, layouts and methods (with the GIL: cheap) ---- */

typedef enum pcpy_dtype { PCPY_U8 = 1, PCPY_U16, PCPY_F32 } pcpy_dtype;

/* A pc_view over caller memory: uint8 (bits 0 or 8), uint16 (bits 0 = 16, or 9..16: Mono10/12/
 * 14/16 are the LSB-aligned formats of that depth; other depths 9..15 use Mono16 with the
 * value check of that depth) or float32 (bits, if any, only declare the values' scale: see
 * pcpy_full_scale). Does not read the pixels. */
int pcpy_view(void *data, uint32_t width, uint32_t height, size_t stride, pcpy_dtype dtype,
              unsigned bits, pc_view *out);
/* The full scale for the pipeline options: 2^bits - 1 for float32 data with bits given (values
 * in raw units of a bits-deep sensor, e.g. averaged frames); 0 (the format's) otherwise. */
double pcpy_full_scale(const pc_view *v, unsigned bits);
/* The bit depth a view declares (8, 10, 12, 14, 16; 32 for float). */
unsigned pcpy_view_bits(const pc_view *v);
/* Every pixel within bits significant bits (float: finite). PC_ERANGE naming the first pixel
 * otherwise. Reads the whole frame: call without the GIL. */
int pcpy_check_bits(const pc_view *v, unsigned bits);

/* Layout string ([BAYER:]A,B,C,D[@DX,DY], imx250mzr, imx250myr) to a mosaic, and back. */
int pcpy_layout_parse(const char *layout, pc_mosaic *m);
void pcpy_layout_format(const pc_mosaic *m, char *buf, unsigned size);

/* The method for a mosaic: the one named (NULL: bilinear for monochrome mosaics, bayer-first
 * for colour-polarization ones, as `polarcam process`). PC_EINVAL for an unknown name or a
 * method of the other kind of mosaic. */
int pcpy_method(const char *name, const pc_mosaic *m, int *method);
const char *pcpy_method_name(int method);
/* The method table: entry i (NULL past the end). */
const pc_demosaic_method_info *pcpy_method_info(unsigned i);
unsigned pcpy_channels(const pc_mosaic *m);
void pcpy_out_size(int method, uint32_t w, uint32_t h, uint32_t *ow, uint32_t *oh);

/* ---- the pipeline (without the GIL) ---- */

/* Demosaics into nch = pcpy_channels(m) planes; noise_gain as pc_pipeline_opts' (0: estimated). */
int pcpy_demosaic(const pc_view *raw, const pc_mosaic *m, int method, int threads,
                  double full_scale, double noise_gain, const pc_fplane *out);

typedef struct pcpy_stokes_opts {
	int method;
	int threads;
	double full_scale;       /* raw units; 0: the format's (pcpy_full_scale) */
	double black_level;      /* raw units, subtracted before demosaicking; 0: none */
	double saturation_level; /* raw units; samples >= it make outputs invalid; 0: unchecked */
	double dead_level;       /* raw units; samples <= it make outputs invalid; 0: unchecked */
	const pc_analyser_pinv *pinv; /* NULL: ideal analysers */
	double noise_gain;            /* pc_pipeline_opts.noise_gain (0: estimated) */
} pcpy_stokes_opts;

/* raw -> Stokes/DoLP/AoLP: the library's front door (pc_stokes_run). NULL planes of out are not
 * wanted; valid (may be NULL) receives the validity mask and count. */
int pcpy_stokes(const pc_view *raw, const pc_mosaic *m, const pcpy_stokes_opts *o,
                const pc_stokes_out *out, pc_validity *valid);
/* Whether pcpy_stokes writes these outputs with non-temporal stores (pc_stokes_streams; with
 * the GIL: cheap). */
bool pcpy_stokes_streams(const pc_stokes_out *out, uint32_t w, uint32_t h);
/* Four analyser images -> Stokes/DoLP/AoLP. */
int pcpy_stokes_channels(const pc_fplane in[4], uint32_t w, uint32_t h,
                         const pc_analyser_pinv *pinv, const pc_stokes_out *out);
/* n analyser matrices (n x 4 x 3 floats) -> n pseudo-inverses as twelve planes (3 x 4 x n,
 * the layout of pc_analyser_pinv). */
int pcpy_pinv(const float *w, size_t n, float *pinv);

/* ---- calibration files (calib/, docs/calibration.md) ---- */

/* A calibration read once and shared by threads: pc_calib_stokes keeps a cache of per-pixel
 * pseudo-inverses for one demosaicking method inside the pc_calib, so calls are serialised
 * only while that cache is (re)built; calls with the cached method run in parallel. */
typedef struct pcpy_calib pcpy_calib;
/* Reads and validates a calibration file (pc_calib_read). */
int pcpy_calib_read(const char *path, pcpy_calib **out);
void pcpy_calib_free(pcpy_calib *c);
/* The calibration's contents (geometry, levels, maps), read-only, valid until pcpy_calib_free. */
const pc_calib *pcpy_calib_get(const pcpy_calib *c);
/* The calibrated pipeline (pc_calib_stokes_gain) on a raw of the calibration's size: m NULL
 * takes the calibration's layout, bits 0 does not compare the bit depth; the ROI offset is taken
 * to be the calibration's (an array carries none). noise_gain (0: the calibration's system gain
 * at gain_db, NAN unknown) for noise-aware methods. valid (output size, row stride = output
 * width; may be NULL) and n_invalid as pc_calib_stokes. */
int pcpy_calib_stokes(pcpy_calib *c, const pc_view *raw, const pc_mosaic *m, unsigned bits,
                      int method, int threads, double noise_gain, double gain_db,
                      const pc_stokes_out *out, uint8_t *valid, uint64_t *n_invalid);
/* The grid of per-output-pixel pseudo-inverses pc_calib_stokes uses for a method, and a copy of
 * it (3 x 4 x gh x gw floats, the layout of pc_analyser_pinv) into dst. */
int pcpy_calib_pinv_grid(const pcpy_calib *c, int method, uint32_t *gw, uint32_t *gh);
int pcpy_calib_pinv_copy(pcpy_calib *c, int method, int threads, float *dst);

/* ---- pictures (without the GIL) ---- */

typedef enum pcpy_picture_kind {
	PCPY_PIC_GREY = 0, /* image linear lo..hi (lo/hi NaN: 0 .. 99.9th percentile) */
	PCPY_PIC_SIGNED,   /* image linear lo..hi (NaN: -q .. q, q = the larger 99.9th
	                      percentile of either sign), for S1 and S2 */
	PCPY_PIC_DOLP,     /* image 0..1 (+ low-signal mask from s0) */
	PCPY_PIC_AOLP,     /* hue = aolp, value = dolp (+ mask) */
	PCPY_PIC_AOLP_SAT, /* hue = aolp, saturation = dolp (+ mask) */
	PCPY_PIC_AOLP_HUE, /* hue = aolp only */
	PCPY_PIC_ON_S0,    /* image linear lo..hi (NaN: 0 .. the 99.9th percentile of s0, or of
	                      the image without s0): Imin, Imax, diffuse, specular */
} pcpy_picture_kind;

/* The false colours of `polarcam process`'s s0.png, dolp.png, aolp.png and aolp_sat.png
 * (without title and colour bar) into rgb (h x w x 3, stride bytes per row). img is the image
 * for GREY and DOLP (the DoLP), the AoLP for the AOLP kinds; dolp for AOLP/AOLP_SAT; s0 (may
 * be NULL: no mask) for the low-signal mask; mask_s0 as pc_pictures_opts (0: 1 % of the S0
 * 99.9th percentile, < 0: none). */
int pcpy_picture(pcpy_picture_kind kind, const pc_fplane *img, const pc_fplane *dolp,
                 const pc_fplane *s0, uint32_t w, uint32_t h, float lo, float hi, double mask_s0,
                 uint8_t *rgb, size_t stride);

/* ---- physics ---- */

/* Materials by (n, k, sigma) with the shared options, prepared once and kept in a small cache
 * owned by the caller. */
typedef struct pcpy_pbrdf_cache pcpy_pbrdf_cache;
int pcpy_pbrdf_cache_new(int diffuse, int shadowing, int rho_mode, int rho_order,
                         pcpy_pbrdf_cache **out);
void pcpy_pbrdf_cache_free(pcpy_pbrdf_cache *c);
/* f in sr^-1 for angles in degrees (as `polarcam pbrdf`): theta in [0, 90] (PC_EINVAL
 * otherwise), material errors as pc_pbrdf_new. */
int pcpy_pbrdf_eval(pcpy_pbrdf_cache *c, double n, double k, double sigma, double theta_i_deg,
                    double theta_r_deg, double phi_deg, double f[4][4]);
/* Name -> enum for the pbrdf options; PC_EINVAL naming the expected values. */
int pcpy_pbrdf_diffuse(const char *name, int *out);
int pcpy_pbrdf_shadowing(const char *name, int *out);
int pcpy_pbrdf_rho(const char *name, int *mode, int *order);

int pcpy_decompose(const double m[4][4], bool filter, pc_lu_chipman *out);

/* ---- the simulator (render) ---- */

typedef struct pcpy_render pcpy_render;
typedef struct pcpy_render_info {
	uint32_t width, height, sensor_width, sensor_height, offset_x, offset_y;
	unsigned bits, colour_channels, n_psg, n_psa, n_states;
	bool mueller; /* the scene declares per-pixel Mueller truth */
	char format[32], layout[64], scene_name[128];
	double exposure_us, gain_db, frame_rate_hz, black_level_dn;
	double dn_per_radiance[3];
	unsigned effects;
} pcpy_render_info;

/* scene_path NULL and scene_text NULL: the default scene; scene_text: a scene document
 * (name for messages, OBJ paths relative to the current directory). roi NULL: full sensor. */
int pcpy_render_new(const char *scene_path, const char *scene_text, uint64_t seed,
                    const uint32_t roi[4], int threads, pcpy_render **out, pcpy_render_info *info);
/* Frame n into raw (h x w uint16, LSB-aligned) and meta; truth (h x w x C x 4 floats, may be
 * NULL) and mueller (h x w x C x 16, may be NULL) of its state. */
int pcpy_render_frame(pcpy_render *r, uint64_t n, uint16_t *raw, float *truth, float *mueller,
                      pc_frame_meta *meta);
/* The state (PSG) a frame is taken under. */
unsigned pcpy_render_state(const pcpy_render *r, uint64_t n);
/* The effects' names: i-th set bit's name, NULL past the end. */
const char *pcpy_effect_name(unsigned effects, unsigned i);
/* The scene document as parsed (compact JSON, malloc'd). */
char *pcpy_render_scene_json(const pcpy_render *r);
void pcpy_render_free(pcpy_render *r);

/* ---- frame sources (open) ---- */

typedef struct pcpy_stream_args {
	const char *format; /* pixel format name, NULL: the source's */
	bool roi_set;
	uint32_t roi[4];
	double exposure_us, gain_db, frame_rate_hz; /* < 0: leave alone */
	unsigned buffers;
} pcpy_stream_args;

/* Opens the source, negotiates format/ROI (an adjusted answer is an error naming what the
 * source proposes), sets the controls and allocates the buffers: the source is READY. */
int pcpy_source_open(const char *uri, const pcpy_stream_args *a, pc_source **out);
void pcpy_source_close(pc_source *s);
int pcpy_source_start(pc_source *s);
int pcpy_source_stop(pc_source *s);
bool pcpy_source_streaming(const pc_source *s);
int pcpy_source_format(pc_source *s, pc_source_format *f);
int pcpy_source_info(pc_source *s, pc_source_info *info);
int pcpy_source_stats(pc_source *s, pc_source_stats *st);
const char *pcpy_source_state(const pc_source *s);
/* Dequeues the next frame (waiting at most timeout_ms, < 0 forever), copies it into dst
 * (LSB-aligned uint16, width x height of the current format, dst_stride bytes per row) and
 * requeues the buffer. meta, mosaic: of the frame. */
int pcpy_source_read(pc_source *s, int timeout_ms, uint16_t *dst, size_t dst_stride,
                     pc_frame_meta *meta, pc_mosaic *mosaic, unsigned *bits);
/* Controls by name ("exposure_us", "gain_db", "frame_rate_hz"): -1 when unknown. */
int pcpy_control_id(const char *name);
const char *pcpy_control_name(int id);
int pcpy_control_count(void);
int pcpy_control_query(pc_source *s, int id, pc_control_info *info);
int pcpy_control_get(pc_source *s, int id, double *v);
int pcpy_control_set(pc_source *s, int id, double v, double *applied);
/* The URI schemes: i-th backend (NULL past the end), whether built in. */
const char *pcpy_backend(unsigned i, bool *built, const char **summary);

#endif
