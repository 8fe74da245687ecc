/* False-colour pictures (conventions in polarcam/picture.h). */
#include "polarcam/picture.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"

static float getf(const pc_fplane *p, uint32_t x, uint32_t y)
{
	return p->data[(size_t)y * p->row_stride + (size_t)x * p->pixel_stride];
}

static uint8_t to8(double v)
{
	if (!(v > 0))
		return 0;
	if (v >= 1)
		return 255;
	return (uint8_t)(v * 255.0 + 0.5);
}

void pc_hsv_to_rgb8(double h, double s, double v, uint8_t rgb[3])
{
	h = h - floor(h);
	double hh = h * 6.0;
	int i = (int)hh;
	if (i > 5)
		i = 5;
	double f = hh - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
	double r, g, b;
	switch (i) {
	case 0:
		r = v, g = t, b = p;
		break;
	case 1:
		r = q, g = v, b = p;
		break;
	case 2:
		r = p, g = v, b = t;
		break;
	case 3:
		r = p, g = q, b = v;
		break;
	case 4:
		r = t, g = p, b = v;
		break;
	default:
		r = v, g = p, b = q;
		break;
	}
	rgb[0] = to8(r);
	rgb[1] = to8(g);
	rgb[2] = to8(b);
}

static int check(const pc_fplane *p, uint32_t w, uint32_t h, const uint8_t *rgb, size_t stride,
                 const char *what)
{
	if (!p || !p->data || p->pixel_stride < 1 || w == 0 || h == 0)
		return pc_error(PC_EINVAL, "%s picture: no input or empty size", what);
	if (!rgb || stride < (size_t)w * 3)
		return pc_error(PC_EINVAL, "%s picture: RGB buffer stride %zu below %u bytes", what,
		                stride, 3 * w);
	return 0;
}

int pc_picture_grey(const pc_fplane *in, uint32_t width, uint32_t height, float lo, float hi,
                    uint8_t *rgb, size_t rgb_stride)
{
	int rc = check(in, width, height, rgb, rgb_stride, "grey");
	if (rc)
		return rc;
	if (!(hi > lo) || !isfinite(lo) || !isfinite(hi))
		return pc_error(PC_EINVAL, "grey picture: display range [%g, %g] is empty", lo, hi);
	double k = 1.0 / ((double)hi - lo);
	for (uint32_t y = 0; y < height; y++) {
		uint8_t *d = rgb + (size_t)y * rgb_stride;
		for (uint32_t x = 0; x < width; x++, d += 3) {
			float v = getf(in, x, y);
			if (!isfinite(v)) {
				d[0] = 255, d[1] = 0, d[2] = 255;
				continue;
			}
			d[0] = d[1] = d[2] = to8((v - lo) * k);
		}
	}
	return 0;
}

int pc_picture_aolp(const pc_fplane *aolp, const pc_fplane *dolp, uint32_t width, uint32_t height,
                    pc_aolp_style style, float dolp_max, uint8_t *rgb, size_t rgb_stride)
{
	int rc = check(aolp, width, height, rgb, rgb_stride, "AoLP");
	if (rc)
		return rc;
	if (style != PC_AOLP_HUE_ONLY && (!dolp || !dolp->data))
		return pc_error(PC_EINVAL, "AoLP picture: this style needs the DoLP image");
	if (!(dolp_max > 0) || !isfinite(dolp_max))
		return pc_error(PC_EINVAL, "AoLP picture: DoLP scale %g must be > 0", dolp_max);
	for (uint32_t y = 0; y < height; y++) {
		uint8_t *d = rgb + (size_t)y * rgb_stride;
		for (uint32_t x = 0; x < width; x++, d += 3) {
			float a = getf(aolp, x, y);
			float p = style == PC_AOLP_HUE_ONLY ? 1.0f : getf(dolp, x, y) / dolp_max;
			if (!isfinite(a) || !isfinite(p)) {
				d[0] = 255, d[1] = 0, d[2] = 255;
				continue;
			}
			if (p > 1)
				p = 1;
			if (p < 0)
				p = 0;
			double hue = a / M_PI;
			if (style == PC_AOLP_SATURATION)
				pc_hsv_to_rgb8(hue, p, 1.0, d);
			else
				pc_hsv_to_rgb8(hue, 1.0, p, d);
		}
	}
	return 0;
}

float pc_picture_quantile(const pc_fplane *in, uint32_t width, uint32_t height, double q)
{
	float lo = INFINITY, hi = -INFINITY;
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			float v = getf(in, x, y);
			if (isfinite(v)) {
				lo = v < lo ? v : lo;
				hi = v > hi ? v : hi;
			}
		}
	if (!(hi >= lo))
		return 0;
	if (hi == lo)
		return lo;
	enum { NB = 4096 };
	size_t *hist = calloc(NB, sizeof *hist);
	if (!hist)
		return hi;
	size_t n = 0;
	double k = NB / ((double)hi - lo);
	for (uint32_t y = 0; y < height; y++)
		for (uint32_t x = 0; x < width; x++) {
			float v = getf(in, x, y);
			if (!isfinite(v))
				continue;
			int b = (int)((v - lo) * k);
			hist[b >= NB ? NB - 1 : b]++;
			n++;
		}
	size_t target = (size_t)(q * (double)n), acc = 0;
	int b = 0;
	for (; b < NB - 1; b++) {
		acc += hist[b];
		if (acc > target)
			break;
	}
	free(hist);
	return (float)(lo + (b + 1) / k);
}

void pc_picture_grey_key(double t, double s, uint8_t rgb[3], void *ctx)
{
	(void)s;
	(void)ctx;
	rgb[0] = rgb[1] = rgb[2] = to8(t);
}

void pc_picture_aolp_key(double t, double s, uint8_t rgb[3], void *ctx)
{
	pc_aolp_style style = ctx ? *(const pc_aolp_style *)ctx : PC_AOLP_VALUE;
	if (style == PC_AOLP_SATURATION)
		pc_hsv_to_rgb8(t, s, 1.0, rgb);
	else if (style == PC_AOLP_HUE_ONLY)
		pc_hsv_to_rgb8(t, 1.0, 1.0, rgb);
	else
		pc_hsv_to_rgb8(t, 1.0, s, rgb);
}

void pc_picture_mask_rgb(uint32_t x, uint32_t y, uint8_t rgb[3])
{
	uint8_t v = ((x + y) / 4) % 2 ? PC_PICTURE_MASK_RGB1 : PC_PICTURE_MASK_RGB0;
	rgb[0] = rgb[1] = rgb[2] = v;
}

size_t pc_picture_mask_low(const pc_fplane *s0, uint32_t width, uint32_t height, float threshold,
                           uint8_t *rgb, size_t rgb_stride)
{
	size_t n = 0;
	if (!s0 || !s0->data || !rgb)
		return 0;
	for (uint32_t y = 0; y < height; y++) {
		const float *r = s0->data + (size_t)y * s0->row_stride;
		uint8_t *o = rgb + (size_t)y * rgb_stride;
		for (uint32_t x = 0; x < width; x++) {
			float v = r[(size_t)x * s0->pixel_stride];
			if (v >= threshold && isfinite(v))
				continue;
			pc_picture_mask_rgb(x, y, o + 3 * (size_t)x);
			n++;
		}
	}
	return n;
}

void pc_picture_invalid_rgb(uint32_t x, uint32_t y, uint8_t rgb[3])
{
	bool on = ((x / 2) + (y / 2)) % 2 == 0;
	rgb[0] = on ? PC_PICTURE_INVALID_R : 0;
	rgb[1] = on ? PC_PICTURE_INVALID_G : 0;
	rgb[2] = on ? PC_PICTURE_INVALID_B : 0;
}

size_t pc_picture_mask_invalid(const uint8_t *valid, size_t valid_stride, uint32_t width,
                               uint32_t height, uint8_t *rgb, size_t rgb_stride)
{
	size_t n = 0;
	if (!valid || !rgb)
		return 0;
	for (uint32_t y = 0; y < height; y++) {
		const uint8_t *v = valid + (size_t)y * valid_stride;
		uint8_t *o = rgb + (size_t)y * rgb_stride;
		for (uint32_t x = 0; x < width; x++)
			if (!v[x]) {
				pc_picture_invalid_rgb(x, y, o + 3 * (size_t)x);
				n++;
			}
	}
	return n;
}
