/* io/io_internal.h - helpers the readers share (private to io/). */
#ifndef POLARCAM_IO_INTERNAL_H
#define POLARCAM_IO_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

/* Size in bytes of the open file fp; UINT64_MAX when it is not a regular file (a pipe has no
 * length to check against). */
uint64_t pc_io_file_size(FILE *fp);

/* Before decoding or allocating an image of width × height pixels that needs `bytes` bytes:
 * the pixel and byte limits of polarcam/limits.h. 0 or PC_ERANGE with a detail naming path. */
int pc_io_check_image(const char *path, uint64_t width, uint64_t height, uint64_t bytes);

/* Largest magnitude accepted in a float raw mosaic (pc_image_read_mosaic): 2^24 ≈ 1.7e7.
 * Float raws are intensities relative to a full scale of 1.0 (pc_dm_full_scale); the ratio-
 * based demosaicking methods divide by the guide plus full scale/65536 and, with mixed signs
 * and tiny neighbours, left float32's range from about 1e11 on (all-non-finite Stokes at
 * ±3.4e38). Measured: every method, fast and reference, finite up to 1e9 on an adversarial
 * pattern (±v, 0, v·1e-30 at random); 2^24 keeps a factor of 60 below that and still holds
 * any integer count a 24-bit converter produces. */
#define PC_RAW_FLOAT_MAX 0x1p24

/* Temporary names of a command's outputs (io/outdir.c): ".NAME.tmp-HOST-" into out (NAME cut to
 * 100 bytes), to which the writer appends "PID-XXXXXX" (mkdtemp). pc_io_remove_stale removes
 * the folders under parent named prefix + PID + "-" + 6 characters whose process is gone (a
 * run killed outright); folders of live processes and of other hosts stay. */
void pc_io_tmp_prefix(const char *name, char *out, size_t size);
void pc_io_remove_stale(const char *parent, const char *prefix);

struct pc_stokes_out;
struct pc_minmax_out;
struct pc_pictures_opts;
struct pc_validity;
/* pc_pictures_write_minmax (polarcam/io.h) from Imin/Imax planes already computed by
 * pc_stokes_minmax (io/pictures.c): a folder that writes the .npy files and the pictures
 * computes them once. st gives the S0 scale. */
int pc_pictures_write_minmax_planes(const char *dir, const struct pc_stokes_out *st,
                                    const struct pc_minmax_out *mo, uint32_t width, uint32_t height,
                                    const struct pc_pictures_opts *opts,
                                    const struct pc_validity *valid, bool minmax, bool split);

struct pc_colorbar;
struct pc_legend_note;
/* pc_image_render_rgb8 (polarcam/plot.h) with xrgb: NULL, or width × height words in which
 * cairo's copy of the picture is made, and xout: NULL, or the words of the annotated picture
 * (pc_image_annotated_size of the same arguments) in which it is drawn (io/plot.c), so that
 * the live window's panels (pc_pictures_live_draw) allocate neither per frame. */
int pc_image_render_rgb8_xrgb(const uint8_t *rgb, uint32_t width, uint32_t height, size_t stride,
                              const char *title, const struct pc_colorbar *bar,
                              const struct pc_legend_note *note, uint32_t image_width, uint8_t *out,
                              uint32_t out_width, uint32_t out_height, size_t out_stride,
                              uint32_t *xrgb, uint32_t *xout);

#endif
