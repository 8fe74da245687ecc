/* The demosaicking front door (polarcam/demosaic.h): one validation, one path from the method
 * table (demosaic_plan.c), the validity of every output pixel; and the method table's public
 * accessors. */
#include "polarcam/demosaic.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_noise.h"
#include "demosaic_plan.h"
#include "polarcam/error.h"

const pc_demosaic_method_info *pc_demosaic_method_get(pc_demosaic_method m)
{
	const pc_dm_method_def *d = pc_dm_method_def_get(m);
	return d ? &d->info : NULL;
}

size_t pc_demosaic_method_names(unsigned flags, char *buf, size_t size)
{
	size_t len = 0;
	if (size)
		buf[0] = 0;
	for (int i = 0; i < PC_DM_COUNT; i++) {
		const pc_demosaic_method_info *mi =
		    &pc_dm_method_def_get((pc_demosaic_method)i)->info;
		if ((mi->flags & flags) != flags)
			continue;
		const char *sep = len ? ", " : "";
		if (len < size)
			snprintf(buf + len, size - len, "%s%s", sep, mi->name);
		len += strlen(sep) + strlen(mi->name);
	}
	return len;
}

int pc_demosaic_method_from_name(const char *name, pc_demosaic_method *m)
{
	for (int i = 0; i < PC_DM_COUNT; i++)
		if (name &&
		    strcmp(name, pc_dm_method_def_get((pc_demosaic_method)i)->info.name) == 0) {
			*m = (pc_demosaic_method)i;
			return 0;
		}
	char list[1024];
	pc_demosaic_method_names(0, list, sizeof list);
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
	pc_dm_planes_separate(base, width, height, channels, planes);
}

pc_pipeline_opts pc_pipeline_defaults(void)
{
	pc_pipeline_opts o;
	memset(&o, 0, sizeof o);
	o.method = PC_DM_BILINEAR;
	o.mosaic = pc_mosaic_imx250mzr();
	return o;
}

static int check_planes(const pc_dm_plan *p, const pc_fplane *out)
{
	if (!out)
		return pc_error(PC_EINVAL, "output planes missing");
	for (unsigned c = 0; c < p->nch; c++) {
		if (!out[c].data)
			return pc_error(PC_EINVAL, "output channel %u: no data pointer", c);
		if (out[c].pixel_stride < 1 ||
		    out[c].row_stride < (size_t)(p->ow - 1) * out[c].pixel_stride + 1)
			return pc_error(PC_EINVAL,
			                "output channel %u: strides %zu/%zu too small for "
			                "width %u",
			                c, out[c].row_stride, out[c].pixel_stride, p->ow);
	}
	return 0;
}

int pc_demosaic_run(const pc_view *raw, const pc_pipeline_opts *opts, const pc_fplane *out,
                    pc_validity *valid)
{
	pc_dm_plan p;
	int rc = pc_dm_plan_begin(raw, opts, &p);
	if (rc)
		return rc;
	if (opts->pinv || opts->compact)
		rc = pc_error(PC_EINVAL, "calibrated analysers (pseudo-inverses or analysis "
		                         "vectors) apply to Stokes outputs (pc_stokes_run), not to "
		                         "demosaicked channels");
	if (rc || (rc = check_planes(&p, out)) || (rc = pc_dm_plan_check_validity(&p, valid))) {
		pc_dm_plan_end(&p);
		return rc;
	}
	if (opts->dark || opts->gain_inv) {
		/* per-pixel correction: demosaic a corrected float copy */
		float *img;
		pc_view v;
		pc_pipeline_opts o;
		if (!(rc = pc_dm_plan_corrected(&p, &img, &v, &o)))
			rc = pc_demosaic_run(&v, &o, out, NULL);
		free(img);
	} else {
		rc = pc_dm_plan_demosaic(&p, out);
	}
	if (!rc && valid)
		rc = pc_dm_plan_validity(&p, valid);
	pc_dm_plan_end(&p);
	return rc;
}

int pc_validity_run(const pc_view *raw, const pc_pipeline_opts *opts, pc_validity *valid)
{
	if (!valid)
		return pc_error(PC_EINVAL, "validity: no output given");
	pc_dm_plan p;
	int rc = pc_dm_plan_begin(raw, opts, &p);
	if (rc)
		return rc;
	if (!(rc = pc_dm_plan_check_validity(&p, valid)))
		rc = pc_dm_plan_validity(&p, valid);
	pc_dm_plan_end(&p);
	return rc;
}

int pc_demosaic_noise_gain(const pc_view *raw, const pc_pipeline_opts *opts, double *g)
{
	if (!g)
		return pc_error(PC_EINVAL, "noise gain: no output given");
	if (!opts)
		return pc_error(PC_EINVAL, "pipeline options missing");
	pc_pipeline_opts o0 = *opts;
	o0.noise_gain = 0; /* not used here */
	o0.noise_gain_used = NULL;
	pc_dm_plan p;
	int rc = pc_dm_plan_begin(raw, &o0, &p);
	if (rc)
		return rc;
	const pc_dm_input *in;
	if (o0.dark || o0.gain_inv) {
		/* the corrected float copy that pc_demosaic_run demosaics */
		float *img;
		pc_view v;
		pc_pipeline_opts o;
		if (!(rc = pc_dm_plan_corrected(&p, &img, &v, &o)))
			rc = pc_demosaic_noise_gain(&v, &o, g);
		free(img);
	} else if (!p.colour && (p.def->info.flags & PC_DMF_NOISE_GAIN)) {
		/* ratio-nr: the slope of the frame's photon-transfer line (demosaic_noise.h) */
		if (!(rc = pc_dm_plan_noise(&p, NULL)))
			*g = p.noise_gain;
	} else if (!(rc = pc_dm_plan_input(&p, &in))) {
		rc = pc_dm_noise_gain_in(in, &p.opts.mosaic, p.full_scale, g);
	}
	pc_dm_plan_end(&p);
	return rc;
}

int pc_demosaic(const pc_view *raw, const pc_mosaic *m, pc_demosaic_method method,
                const pc_demosaic_opts *opts, const pc_fplane *out)
{
	if (!m)
		return pc_mosaic_check(m); /* "mosaic missing" */
	pc_pipeline_opts o = pc_dm_opts_legacy(m, method, opts);
	return pc_demosaic_run(raw, &o, out, NULL);
}
