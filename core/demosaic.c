/* The demosaicking ladder: method table, argument validation, input preparation, dispatch to
 * the double-precision reference (demosaic_ref.c) or the fast float kernels (demosaic_fast.c). */
#include "polarcam/demosaic.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_internal.h"
#include "polarcam/error.h"
#include "polarcam/format.h"

static const pc_demosaic_method_info pc_dm_table[PC_DM_COUNT] = {
	[PC_DM_SUPERPIXEL_HALF] = { PC_DM_SUPERPIXEL_HALF, "superpixel-half",
				    "no interpolation error, half resolution; 2x2 IFoV misregistration "
				    "shows as false DoLP on edges",
				    "cheapest: one read of the raw, a quarter-size output",
				    "the 2x2 super-pixel of DoFP sensors (e.g. Ratliff et al. 2009)",
				    PC_DMF_MONO | PC_DMF_HALF_RES },
	[PC_DM_SUPERPIXEL] = { PC_DM_SUPERPIXEL, "superpixel",
			       "full-size output of the 2x2 super-pixel values; blocky, lowest "
			       "accuracy", "memory-bound, like a copy",
			       "the 2x2 super-pixel replicated over its block",
			       PC_DMF_MONO },
	[PC_DM_BILINEAR] = { PC_DM_BILINEAR, "bilinear",
			     "the baseline every gain below is measured against: per-channel tent "
			     "interpolation, false DoLP on edges (Lapray NIR: S0 48.7 dB, DoLP 36.0 dB)",
			     "memory-bound: 3x3 neighbourhood, one pass",
			     "Gao & Gruev, Opt. Express 19(27) 2011, bilinear DoFP interpolation",
			     PC_DMF_MONO },
	[PC_DM_BICUBIC] = { PC_DM_BICUBIC, "bicubic",
			    "sharper than bilinear, per channel, overshoot limited; S0/DoLP dB over "
			    "bilinear, mean (worst scene): Lapray +1.72/+0.82 (+0.46/+0.00), Zhang "
			    "+1.10/+1.17 (+0.78/+0.98), stress +0.18/-0.17 (+0.01/-0.83)",
			    "7x7 neighbourhood, separable; about 1.2-1.3x bilinear's time",
			    "Keys cubic convolution (a = -1/2) per channel, as in Gao & Gruev 2011",
			    PC_DMF_MONO },
	[PC_DM_PPID] = { PC_DM_PPID, "ppid",
			 "inter-channel: differences to an edge-aware pseudo-panchromatic image, "
			 "overshoot limited; mean (worst): Lapray -0.02/-0.20 (-3.19/-1.44), Zhang "
			 "+4.71/+3.11 (+4.71/+2.79), stress +3.57/+1.64 (+0.39/-0.13)",
			 "5x5 neighbourhood, three fused passes; about 3.5x bilinear's time",
			 "Mihoubi, Losson, Mathon, Macaire, IEEE TCI 3(4) 2017; for PFAs: Mihoubi, "
			 "Lapray, Bigue, Sensors 18(11) 3688, 2018",
			 PC_DMF_MONO },
	[PC_DM_RI] = { PC_DM_RI, "ri",
		       "inter-channel: guided-filter tentative estimates plus interpolated "
		       "residuals, overshoot limited; mean (worst): Lapray +1.21/+1.08 "
		       "(-0.52/+0.16), Zhang +3.78/+3.01 (+3.24/+2.97), stress +3.88/+1.11 "
		       "(+1.32/-0.29)",
		       "guided filters (5x5 windows) per channel; about 11x bilinear's time",
		       "Kiku, Monno, Tanaka, Okutomi, ICIP 2013; for DoFP: Ahmed, Zhao, Gruev, "
		       "Zhang, Bermak, Opt. Express 25(9) 2017",
		       PC_DMF_MONO },
	[PC_DM_EARI] = { PC_DM_EARI, "eari",
			 "inter-channel: residual interpolation guided by an edge-aware "
			 "intensity image (our detector), overshoot limited; mean (worst): Lapray "
			 "+3.37/+1.90 (+1.32/+0.34), Zhang +3.46/+3.32 (+2.79/+3.01), stress "
			 "+2.88/+1.04 (+1.51/-0.14)",
			 "like ri plus an edge-aware guide pass; about 10x bilinear's time",
			 "Morimatsu, Monno, Tanaka, Okutomi, ICIP 2020 (arXiv:2007.14292)",
			 PC_DMF_MONO },
	[PC_DM_BAYER_FIRST] = { PC_DM_BAYER_FIRST, "bayer-first",
				"colour-polarization: bilinear Bayer demosaicking of each analyser "
				"sub-image, then bilinear up-sampling of the analysers",
				"a colour pass plus three bilinear passes; about 22x bilinear's time",
				"the colour-first baseline of colour-polarization demosaicking "
				"(Morimatsu et al. 2020, Sec. 3.2)",
				PC_DMF_COLOR },
	[PC_DM_BAYER_EARI] = { PC_DM_BAYER_EARI, "bayer-eari",
			       "colour-polarization: bilinear Bayer demosaicking of each analyser "
			       "sub-image, then EARI across the analysers of each colour; better "
			       "polarization than bayer-first",
			       "bayer-first's colour step plus three EARI runs; about 50x bilinear's time",
			       "colour-first as Morimatsu et al. 2020, with the polarization step of "
			       "their EARI",
			       PC_DMF_COLOR },
	[PC_DM_RATIO] = { PC_DM_RATIO, "ratio",
			  "inter-channel: our EARI guide, channels as guide x interpolated ratio "
			  "(raw + 1 % FS)/(guide + 1 % FS), twice, overshoot limited; mean (worst): "
			  "Lapray +3.19/+1.74 (+0.69/-0.03), Zhang +4.42/+4.11 (+3.83/+4.02), stress "
			  "+2.21/+1.08 (+1.37/+0.26); the fast robust choice",
			  "the guide pass plus two ratio passes (3x3 tents); about 2.7x bilinear's time",
			  "ours: the guide of Morimatsu et al. ICIP 2020 with smooth-hue-transition "
			  "(ratio) interpolation, Cok, US patent 4,642,678 (1987), iterated",
			  PC_DMF_MONO },
	[PC_DM_EARI_MLRI] = { PC_DM_EARI_MLRI, "eari-mlri",
			      "anchor: EARI as its authors define it (their polarization-invariant "
			      "edge-aware guide, minimized-Laplacian RI in 11x11 windows); mean "
			      "(worst): Lapray +3.60/+1.74 (+0.91/-0.20), Zhang +3.96/+4.07 "
			      "(+3.14/+3.75), stress +5.24/+1.09 (+1.20/-4.58: rings into black)",
			      "multi-pass float path, ~14 planes; about 60-200x bilinear (not yet "
			      "within budget)",
			      "Morimatsu, Monno, Tanaka, Okutomi, ICIP 2020 (arXiv:2007.14292) and their "
			      "release; MLRI: Kiku et al., IEEE TIP 25(3) 2016",
			      PC_DMF_MONO },
	[PC_DM_EARI_ROBUST] = { PC_DM_EARI_ROBUST, "eari-robust",
				"inter-channel: eari-mlri with the overshoot limiter (no ringing into "
				"the dark); the most accurate, no scene below -0.3 dB; mean (worst): "
				"Lapray +3.51/+1.78 (+1.01/-0.12), Zhang +3.69/+3.74 (+3.03/+3.51), "
				"stress +5.35/+2.29 (+1.87/+0.59)",
				"eari-mlri's cost plus one 5x5 min/max pass (not yet within 5x "
				"bilinear)",
				"ours: Morimatsu et al. ICIP 2020's guide and Kiku et al. TIP 2016's "
				"MLRI, held to each channel's local sample range",
				PC_DMF_MONO },
	[PC_DM_PCDP] = { PC_DM_PCDP, "pcdp",
			 "anchor: residual interpolation with the other channels' bilinear "
			 "estimates as guide, the orthogonal one weighted sqrt(2); mean (worst): "
			 "Lapray +3.01/+0.78 (+0.97/-0.54), Zhang +3.88/+4.01 (+3.08/+3.78), stress "
			 "+2.58/+0.76 (+1.32/-0.89)",
			 "four bilinear planes plus four residual tents",
			 "Wu et al., Opt. Express 29(14) 2021 (polarization channel difference prior)",
			 PC_DMF_MONO },
	[PC_DM_IGRI2] = { PC_DM_IGRI2, "igri2",
			  "anchor: residual interpolation on the rotated diagonal lattices, then "
			  "across them, then MLRI with the mean as guide; mean (worst): Lapray "
			  "+2.91/+1.41 (-0.50/-0.72), Zhang +5.80/+4.47 (+5.24/+4.45), stress "
			  "+5.72/-0.13 (+0.81/-7.74: rings into black)",
			  "the double reference (no fast path yet): hundreds of times bilinear",
			  "Morimatsu, Monno, Tanaka, Okutomi, IEEE Sensors J. 21(24) 2021 (IGRI2) and "
			  "their release",
			  PC_DMF_MONO },
};

const pc_demosaic_method_info *pc_demosaic_method_get(pc_demosaic_method m)
{
	if ((int)m < 0 || (int)m >= PC_DM_COUNT)
		return NULL;
	return &pc_dm_table[m];
}

int pc_demosaic_method_from_name(const char *name, pc_demosaic_method *m)
{
	char list[256];
	size_t off = 0;
	for (int i = 0; i < PC_DM_COUNT; i++) {
		if (name && strcmp(name, pc_dm_table[i].name) == 0) {
			*m = (pc_demosaic_method)i;
			return 0;
		}
		off += (size_t)snprintf(list + off, sizeof list - off, "%s%s", i ? ", " : "",
					pc_dm_table[i].name);
		if (off >= sizeof list)
			off = sizeof list - 1;
	}
	return pc_error(PC_EINVAL, "demosaicking method '%s': unknown (expected one of %s)",
			name ? name : "", list);
}

unsigned pc_demosaic_channels(const pc_mosaic *m)
{
	return m && m->period == 4 ? 12u : 4u;
}

void pc_demosaic_out_size(pc_demosaic_method m, uint32_t width, uint32_t height, uint32_t *ow,
			  uint32_t *oh)
{
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(m);
	int half = mi && (mi->flags & PC_DMF_HALF_RES);
	*ow = half ? width / 2 : width;
	*oh = half ? height / 2 : height;
}

void pc_fplanes_interleaved(float *base, uint32_t width, unsigned channels, pc_fplane *planes)
{
	for (unsigned c = 0; c < channels; c++) {
		planes[c].data = base + c;
		planes[c].row_stride = (size_t)width * channels;
		planes[c].pixel_stride = channels;
	}
}

void pc_fplanes_separate(float *base, uint32_t width, uint32_t height, unsigned channels,
			 pc_fplane *planes)
{
	for (unsigned c = 0; c < channels; c++) {
		planes[c].data = base + (size_t)c * width * height;
		planes[c].row_stride = width;
		planes[c].pixel_stride = 1;
	}
}

void *pc_dm_alloc(size_t bytes)
{
	return aligned_alloc(64, (bytes + 63) / 64 * 64 + 64);
}

void pc_dm_free(void *p)
{
	free(p);
}

void pc_dm_row_to_float(const pc_dm_input *in, uint32_t y, float *dst)
{
	const uint8_t *row = in->data + (size_t)y * in->stride;
	uint32_t w = in->width;
	switch (in->type) {
	case PC_DMT_U8:
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = row[x];
		break;
	case PC_DMT_U16: {
		const uint16_t *r = (const uint16_t *)(const void *)row;
		PC_SIMD
		for (uint32_t x = 0; x < w; x++)
			dst[x] = r[x];
		break;
	}
	case PC_DMT_F32:
		memcpy(dst, row, (size_t)w * sizeof(float));
		break;
	}
	dst[-1] = dst[w > 1 ? 1 : 0];
	dst[w] = dst[w > 1 ? w - 2 : 0];
}

/* Validates everything a caller can get wrong; the kernels then assume a sound call. */
static int check_call(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
		      const pc_fplane *out)
{
	int rc = pc_view_check(raw);
	if (rc)
		return pc_error_prefix(rc, "raw: ");
	rc = pc_mosaic_check(m);
	if (rc)
		return rc;
	const pc_demosaic_method_info *mi = pc_demosaic_method_get(method);
	if (!mi)
		return pc_error(PC_EINVAL, "demosaicking method %d: unknown", (int)method);
	int colour = m->period == 4;
	if (colour && !(mi->flags & PC_DMF_COLOR))
		return pc_error(PC_EINVAL, "method %s works on monochrome polarizer mosaics only; "
					   "this mosaic has a colour filter (try bayer-first or "
					   "bayer-eari)", mi->name);
	if (!colour && !(mi->flags & PC_DMF_MONO))
		return pc_error(PC_EINVAL, "method %s works on colour-polarization mosaics only",
				mi->name);
	uint32_t minsz = colour ? 8 : 4;
	if (raw->width % 2 || raw->height % 2)
		return pc_error(PC_EINVAL, "raw size %ux%u: width and height must be even (whole 2x2 "
					   "analyser blocks); crop one column or row", raw->width,
				raw->height);
	if (raw->width < minsz || raw->height < minsz)
		return pc_error(PC_EINVAL, "raw size %ux%u: at least %ux%u pixels are needed",
				raw->width, raw->height, minsz, minsz);
	if (raw->width > (1u << 30) || raw->height > (1u << 30))
		return pc_error(PC_EINVAL, "raw size %ux%u: too large", raw->width, raw->height);
	if (!out)
		return pc_error(PC_EINVAL, "output planes missing");
	uint32_t ow, oh;
	pc_demosaic_out_size(method, raw->width, raw->height, &ow, &oh);
	unsigned nch = pc_demosaic_channels(m);
	for (unsigned c = 0; c < nch; c++) {
		if (!out[c].data)
			return pc_error(PC_EINVAL, "output channel %u: no data pointer", c);
		if (out[c].pixel_stride < 1 ||
		    out[c].row_stride < (size_t)(ow - 1) * out[c].pixel_stride + 1)
			return pc_error(PC_EINVAL, "output channel %u: strides %zu/%zu too small for "
						   "width %u", c, out[c].row_stride,
					out[c].pixel_stride, ow);
	}
	return 0;
}

double pc_dm_full_scale(const pc_view *raw, const pc_demosaic_opts *opts)
{
	if (opts && opts->full_scale > 0 && isfinite(opts->full_scale))
		return opts->full_scale;
	const pc_format_info *fi = pc_format_info_get(raw->format);
	return fi->is_float ? 1.0 : (double)((1u << fi->bits) - 1u);
}

/* Converts any raw to a double image (the reference's input). */
static int raw_to_double(const pc_view *raw, double **out)
{
	size_t n = (size_t)raw->width * raw->height;
	float *f = malloc(n * sizeof *f);
	double *d = malloc(n * sizeof *d);
	if (!f || !d) {
		free(f);
		free(d);
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot allocate the reference's input",
				raw->width, raw->height);
	}
	int rc = pc_view_to_f32(raw, f, (size_t)raw->width * sizeof *f);
	if (rc) {
		free(f);
		free(d);
		return pc_error_prefix(rc, "raw: ");
	}
	for (size_t i = 0; i < n; i++)
		d[i] = f[i];
	free(f);
	*out = d;
	return 0;
}

int pc_dm_prepare_input(const pc_view *raw, pc_dm_input *in, void **owned)
{
	*owned = NULL;
	const pc_format_info *fi = pc_format_info_get(raw->format);
	in->width = raw->width;
	in->height = raw->height;
	if (fi->is_float) {
		int rc = pc_view_check_bits(raw, 32);
		if (rc)
			return pc_error_prefix(rc, "raw: ");
		in->data = raw->data;
		in->stride = raw->stride;
		in->type = PC_DMT_F32;
		return 0;
	}
	if (fi->packing == PC_PACK_NONE) {
		in->data = raw->data;
		in->stride = raw->stride;
		in->type = fi->bits <= 8 ? PC_DMT_U8 : PC_DMT_U16;
		return 0;
	}
	size_t stride = ((size_t)raw->width * 2 + 63) / 64 * 64;
	uint16_t *u = pc_dm_alloc(stride * raw->height);
	if (!u)
		return pc_error(PC_ENOMEM, "raw %ux%u: cannot unpack", raw->width, raw->height);
	int rc = pc_view_to_u16(raw, u, stride);
	if (rc) {
		pc_dm_free(u);
		return pc_error_prefix(rc, "raw: ");
	}
	*owned = u;
	in->data = (const uint8_t *)u;
	in->stride = stride;
	in->type = PC_DMT_U16;
	return 0;
}

int pc_demosaic_color(const pc_view *raw, const double *img_ref, const pc_mosaic *m,
		      pc_demosaic_method method, const pc_demosaic_opts *opts, double full_scale,
		      const pc_fplane *out);

int pc_demosaic(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
		const pc_demosaic_opts *opts, const pc_fplane *out)
{
	int rc = check_call(raw, m, method, out);
	if (rc)
		return rc;
	double fs = pc_dm_full_scale(raw, opts);
	if (m->period == 4) {
		double *img = NULL;
		if (opts && opts->reference) {
			if (pc_format_info_get(raw->format)->is_float &&
			    (rc = pc_view_check_bits(raw, 32)))
				return pc_error_prefix(rc, "raw: ");
			if ((rc = raw_to_double(raw, &img)))
				return rc;
		}
		rc = pc_demosaic_color(raw, img, m, method, opts, fs, out);
		free(img);
		return rc;
	}
	if (!(opts && opts->reference)) {
		pc_dm_input in;
		void *owned;
		rc = pc_dm_prepare_input(raw, &in, &owned);
		if (rc)
			return rc;
		rc = pc_demosaic_fast(&in, m, method, fs, opts ? opts->threads : 0, out);
		pc_dm_free(owned);
		/* the row-cache paths limit inline; the others here (demosaic_robust.c) */
		if (!rc && method == PC_DM_EARI_ROBUST)
			rc = pc_dm_range_limit(raw, m, opts ? opts->threads : 0, out);
		if (rc != PC_ENOTSUP)
			return rc;
		/* no fast path for this method (yet): its reference is the implementation */
	}
	if (pc_format_info_get(raw->format)->is_float) {
		rc = pc_view_check_bits(raw, 32);
		if (rc)
			return pc_error_prefix(rc, "raw: ");
	}
	double *img = NULL;
	rc = raw_to_double(raw, &img);
	if (rc)
		return rc;
	rc = pc_demosaic_ref(img, raw->width, raw->height, m, method, fs, out);
	free(img);
	/* the robust methods' overshoot limiter (the fast paths apply it row by row) */
	if (!rc && pc_dm_limited(method))
		rc = pc_dm_range_limit(raw, m, opts ? opts->threads : 0, out);
	return rc;
}
