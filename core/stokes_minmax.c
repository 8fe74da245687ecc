/* Imin, Imax and the diffuse/specular split from S0, S1, S2 (polarcam/stokes.h; the formulas
 * and their sources: docs/physics-notes.md, "Imin, Imax and the diffuse/specular split"). */
#include <math.h>

#include "polarcam/error.h"
#include "polarcam/stokes.h"

void pc_stokes_minmax1(double s0, double s1, double s2, double out[4])
{
	/* I(θ) = ½·(S0 + S1·cos 2θ + S2·sin 2θ) swings by ±½·√(S1² + S2²) around ½·S0 */
	const double p = hypot(s1, s2);
	out[0] = 0.5 * (s0 - p);
	out[1] = 0.5 * (s0 + p);
	out[2] = s0 - p; /* 2·Imin: the unpolarized (diffuse) part */
	out[3] = p;      /* Imax − Imin: the polarized (specular) part */
}

static int check_plane(const pc_fplane *p, uint32_t w, const char *what)
{
	if (p->pixel_stride < 1 || p->row_stride < (size_t)(w - 1) * p->pixel_stride + 1)
		return pc_error(PC_EINVAL, "Imin/Imax: %s strides %zu/%zu too small for width %u",
		                what, p->row_stride, p->pixel_stride, w);
	return 0;
}

int pc_stokes_minmax(const pc_fplane *s0, const pc_fplane *s1, const pc_fplane *s2, uint32_t width,
                     uint32_t height, const pc_minmax_out *out)
{
	if (!s0 || !s1 || !s2 || !s0->data || !s1->data || !s2->data || !out)
		return pc_error(PC_EINVAL,
		                "Imin/Imax: S0, S1 and S2 planes and outputs are needed");
	if (width == 0 || height == 0)
		return pc_error(PC_EINVAL, "Imin/Imax: empty size %ux%u", width, height);
	const pc_fplane *in[3] = {s0, s1, s2};
	const pc_fplane *o[4] = {&out->imin, &out->imax, &out->diffuse, &out->specular};
	static const char *names[7] = {"S0", "S1", "S2", "Imin", "Imax", "diffuse", "specular"};
	int n = 0, rc = 0;
	for (int k = 0; k < 3 && !rc; k++)
		rc = check_plane(in[k], width, names[k]);
	for (int k = 0; k < 4 && !rc; k++)
		if (o[k]->data) {
			n++;
			rc = check_plane(o[k], width, names[3 + k]);
		}
	if (rc)
		return rc;
	if (!n)
		return pc_error(PC_EINVAL, "Imin/Imax: no output asked for");
	for (uint32_t y = 0; y < height; y++) {
		const float *a = s0->data + (size_t)y * s0->row_stride;
		const float *b = s1->data + (size_t)y * s1->row_stride;
		const float *c = s2->data + (size_t)y * s2->row_stride;
		for (uint32_t x = 0; x < width; x++) {
			const float v0 = a[(size_t)x * s0->pixel_stride];
			/* hypotf: no overflow or underflow of S1² + S2² for any finite input */
			const float p = hypotf(b[(size_t)x * s1->pixel_stride],
			                       c[(size_t)x * s2->pixel_stride]);
			const float r[4] = {0.5f * (v0 - p), 0.5f * (v0 + p), v0 - p, p};
			for (int k = 0; k < 4; k++)
				if (o[k]->data)
					o[k]->data[(size_t)y * o[k]->row_stride +
					           (size_t)x * o[k]->pixel_stride] = r[k];
		}
	}
	return 0;
}
