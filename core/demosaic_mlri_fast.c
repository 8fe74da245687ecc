/* The fast float path of eari-mlri and eari-robust (references: demosaic_mlri.c, whose
 * header defines the method): the same passes on float planes padded with mirrored samples
 * (so the inner loops have no index arithmetic), every box sum a running sum in double as in
 * the reference (exactly 0 over a window of zeros, as there), row bands on OpenMP threads
 * (pc_parallel_rows). Memory: about 14 float planes of the frame. Held to the reference within 1e-5
 * of full scale (tests/test_demosaic.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "demosaic_anchors.h"
#include "polarcam/error.h"
#include "polarcam/parallel.h"

#define PAD         8
#define MLRI_R      5
#define MACHINE_EPS 2.220446049250313e-16

typedef struct plane {
	float *b; /* base of the padded plane */
	long s;   /* row stride */
} plane;

/* pixel (x, y) of the image, -PAD <= x < w + PAD */
#define P(pl, x, y) ((pl).b[((long)(y) + PAD) * (pl).s + (long)(x) + PAD])

typedef struct mjob {
	const pc_dm_input *in;
	const pc_mosaic *m;
	long w, h;
	double fs;
	plane R, G, D[4], Q, H, S[8], A, B, W, T, X;
	unsigned c;
	int stage;
	const pc_fplane *out;
	int err;
} mjob;

/* Fills the padding of rows [y0, y1) (columns) from the mirrored interior; rows outside the
 * image are copies of mirrored rows (done once for the whole plane by pad_rows). */
static void pad_cols(plane p, long w, long y0, long y1)
{
	for (long y = y0; y < y1; y++)
		for (int i = 1; i <= PAD; i++) {
			P(p, -i, y) = P(p, pc_mirror(-i, (int)w), y);
			P(p, w - 1 + i, y) = P(p, pc_mirror((int)w - 1 + i, (int)w), y);
		}
}

static void pad_rows(plane p, long h)
{
	for (int i = 1; i <= PAD; i++) {
		memcpy(&P(p, -PAD, -i), &P(p, -PAD, pc_mirror(-i, (int)h)),
		       sizeof(float) * (size_t)p.s);
		memcpy(&P(p, -PAD, h - 1 + i), &P(p, -PAD, pc_mirror((int)h - 1 + i, (int)h)),
		       sizeof(float) * (size_t)p.s);
	}
}

/* Horizontal running box of src rows [y0, y1) into dst (interior columns); exactly 0 where the
 * window holds no nonzero sample, as the reference's box (its comment says why). */
static void hbox(plane src, plane dst, long w, long y0, long y1)
{
	for (long y = y0; y < y1; y++) {
		const float *r = &P(src, 0, y);
		float *d = &P(dst, 0, y);
		double s = 0;
		long nz = 0;
		for (int dx = -MLRI_R; dx <= MLRI_R; dx++) {
			s += r[dx];
			nz += r[dx] != 0;
		}
		for (long x = 0; x < w; x++) {
			d[x] = nz ? (float)s : 0;
			const float a = r[x + MLRI_R + 1], b = r[x - MLRI_R];
			s += (double)a - (double)b;
			nz += (a != 0) - (b != 0);
		}
	}
}

/* Vertical running box of src (rows padded) into dst rows [y0, y1), the same way (acc, cnt:
 * w doubles and w longs of scratch). */
static void vbox(plane src, plane dst, long w, long y0, long y1, double *acc, long *cnt)
{
	for (long x = 0; x < w; x++) {
		double s = 0;
		long nz = 0;
		for (int dy = -MLRI_R; dy <= MLRI_R; dy++) {
			s += P(src, x, y0 + dy);
			nz += P(src, x, y0 + dy) != 0;
		}
		acc[x] = s;
		cnt[x] = nz;
	}
	for (long y = y0; y < y1; y++) {
		float *d = &P(dst, 0, y);
		const float *add = &P(src, 0, y + MLRI_R + 1), *sub = &P(src, 0, y - MLRI_R);
		for (long x = 0; x < w; x++) {
			d[x] = cnt[x] ? (float)acc[x] : 0;
			acc[x] += (double)add[x] - (double)sub[x];
			cnt[x] += (add[x] != 0) - (sub[x] != 0);
		}
	}
}

static unsigned chan(const pc_mosaic *m, long x, long y)
{
	return m->channel[y & 1][x & 1];
}

enum { ST_RAW, ST_D, ST_G, ST_Q, ST_H, ST_V, ST_ABW, ST_T, ST_OUT };

/* which: for ST_Q the quantity index (0..7), kept in j->stage's upper bits */
static void band(void *ctx, uint32_t y0u, uint32_t y1u)
{
	mjob *j = ctx;
	const long w = j->w, y0 = y0u, y1 = y1u;
	const int stage = j->stage & 0xff, q = j->stage >> 8;
	switch (stage) {
	case ST_RAW:
		for (long y = y0; y < y1; y++)
			pc_dm_row_to_float(j->in, (uint32_t)y, &P(j->R, 0, y));
		pad_cols(j->R, w, y0, y1);
		break;
	case ST_D:
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
#define HD(xx, yy) (P(j->R, xx, yy) - 0.5f * (P(j->R, (xx)-1, yy) + P(j->R, (xx) + 1, yy)))
#define VD(xx, yy) (P(j->R, xx, yy) - 0.5f * (P(j->R, xx, (yy)-1) + P(j->R, xx, (yy) + 1)))
				P(j->D[0], x, y) = fabsf(HD(x, y - 1) - HD(x, y));
				P(j->D[1], x, y) = fabsf(HD(x, y + 1) - HD(x, y));
				P(j->D[2], x, y) = fabsf(VD(x - 1, y) - VD(x, y));
				P(j->D[3], x, y) = fabsf(VD(x + 1, y) - VD(x, y));
#undef HD
#undef VD
			}
		for (int d = 0; d < 4; d++)
			pad_cols(j->D[d], w, y0, y1);
		break;
	case ST_G: {
		const float eps = (float)(MACHINE_EPS * j->fs);
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				float X[4] = {0, 0, 0, 0}, wd[4] = {0, 0, 0, 0};
				static const float k[3] = {0.125f, 0.25f, 0.125f};
				for (int t = -1; t <= 1; t++) {
					X[0] +=
					    k[t + 1] * (P(j->R, x + t, y - 1) + P(j->R, x + t, y));
					X[1] +=
					    k[t + 1] * (P(j->R, x + t, y) + P(j->R, x + t, y + 1));
					X[2] +=
					    k[t + 1] * (P(j->R, x - 1, y + t) + P(j->R, x, y + t));
					X[3] +=
					    k[t + 1] * (P(j->R, x, y + t) + P(j->R, x + 1, y + t));
				}
				for (int a = -2; a <= 2; a++)
					for (int b = 0; b <= 2; b++) {
						wd[0] += P(j->D[0], x + a, y - b);
						wd[1] += P(j->D[1], x + a, y + b);
						wd[2] += P(j->D[2], x - b, y + a);
						wd[3] += P(j->D[3], x + b, y + a);
					}
				float num = 0, den = 0;
				for (int d = 0; d < 4; d++) {
					float W = 1.0f / (wd[d] / 15 + eps);
					num += W * X[d];
					den += W;
				}
				P(j->G, x, y) = num / (den + eps);
			}
		pad_cols(j->G, w, y0, y1);
		break;
	}
	case ST_Q: /* quantity q of channel c into Q */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				float v = 0;
				if (chan(j->m, x, y) == j->c) {
					float gv = P(j->G, x, y), iv = P(j->R, x, y);
					float lg = 4 * gv - P(j->G, x - 2, y) - P(j->G, x + 2, y) -
					           P(j->G, x, y - 2) - P(j->G, x, y + 2);
					float li = 4 * iv - P(j->R, x - 2, y) - P(j->R, x + 2, y) -
					           P(j->R, x, y - 2) - P(j->R, x, y + 2);
					switch (q) {
					case 0:
						v = 1;
						break;
					case 1:
						v = lg * li;
						break;
					case 2:
						v = lg * lg;
						break;
					case 3:
						v = gv;
						break;
					case 4:
						v = iv;
						break;
					case 5:
						v = gv * gv;
						break;
					case 6:
						v = iv * iv;
						break;
					default:
						v = gv * iv;
						break;
					}
				}
				P(j->Q, x, y) = v;
			}
		pad_cols(j->Q, w, y0, y1);
		break;
	case ST_H: /* horizontal box of X into H */
		hbox(j->X, j->H, w, y0, y1);
		break;
	case ST_V: { /* vertical box of H into S[q] (q = 8: into X) */
		double *acc = malloc(sizeof(double) * (size_t)w);
		long *cnt = malloc(sizeof(long) * (size_t)w);
		if (!acc || !cnt) {
			free(acc);
			free(cnt);
			j->err = 1;
			break;
		}
		plane dst = q < 8 ? j->S[q] : j->X;
		vbox(j->H, dst, w, y0, y1, acc, cnt);
		free(acc);
		free(cnt);
		break;
	}
	case ST_ABW: {
		const double eps = MACHINE_EPS * j->fs * j->fs, fs2 = j->fs * j->fs;
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				double M = P(j->S[0], x, y), N = M > 0 ? M : 1;
				double LGLI = P(j->S[1], x, y), LG2 = P(j->S[2], x, y);
				double Gs = P(j->S[3], x, y), Is = P(j->S[4], x, y);
				double G2 = P(j->S[5], x, y), I2 = P(j->S[6], x, y),
				       GI = P(j->S[7], x, y);
				double a = (LGLI / N) / (LG2 / N + eps);
				double b = Is / N - a * Gs / N;
				double d2 = (G2 * a * a + b * b * M + I2 + 2 * a * b * Gs -
				             2 * b * Is - 2 * a * GI) /
				            N;
				double wt = 1.0 / fmax(d2 / fs2, 0.01);
				P(j->A, x, y) = (float)(a * wt);
				P(j->B, x, y) = (float)(b * wt);
				P(j->W, x, y) = (float)wt;
			}
		pad_cols(j->A, w, y0, y1);
		pad_cols(j->B, w, y0, y1);
		pad_cols(j->W, w, y0, y1);
		break;
	}
	case ST_T: /* tentative and residual: S[0..2] hold the boxed A, B, W */
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				double ws = fmax(P(j->S[0 + 5], x, y), 0.01);
				double t =
				    P(j->S[3], x, y) / ws * P(j->G, x, y) + P(j->S[4], x, y) / ws;
				float tt = (float)fmin(fmax(t, 0), j->fs);
				P(j->T, x, y) = tt;
				P(j->Q, x, y) = P(j->R, x, y) - tt;
			}
		pad_cols(j->T, w, y0, y1);
		pad_cols(j->Q, w, y0, y1);
		break;
	case ST_OUT: {
		const pc_fplane *o = &j->out[j->c];
		for (long y = y0; y < y1; y++)
			for (long x = 0; x < w; x++) {
				float s = 0, ws = 0;
				for (int dy = -1; dy <= 1; dy++)
					for (int dx = -1; dx <= 1; dx++)
						if (chan(j->m, x + dx, y + dy) == j->c) {
							float wt =
							    (float)((2 - abs(dx)) * (2 - abs(dy)));
							s += wt * P(j->Q, x + dx, y + dy);
							ws += wt;
						}
				o->data[(size_t)y * o->row_stride + (size_t)x * o->pixel_stride] =
				    P(j->T, x, y) + s / ws;
			}
		break;
	}
	default:
		break;
	}
}

static void run(mjob *j, int stage, int threads)
{
	j->stage = stage;
	pc_parallel_rows((uint32_t)j->h, 0, threads, band, j);
}

/* box of X (interior computed, columns padded) into S[q] (q = 8: back into X), padded */
static void box(mjob *j, int q, int threads)
{
	pad_rows(j->X, j->h);
	run(j, ST_H, threads);
	pad_rows(j->H, j->h);
	run(j, ST_V | (q << 8), threads);
	plane d = q < 8 ? j->S[q] : j->X;
	pad_cols(d, j->w, 0, j->h);
	pad_rows(d, j->h);
}

static int mlri_fast(const pc_dm_input *in, const pc_mosaic *m, pc_demosaic_method method,
                     double full_scale, int threads, const pc_fplane *out)
{
	if (m->period != 2)
		return PC_ENOTSUP;
	mjob j;
	memset(&j, 0, sizeof j);
	j.in = in;
	j.m = m;
	j.w = in->width;
	j.h = in->height;
	j.fs = full_scale;
	j.out = out;
	if (j.w < PAD + 1 || j.h < PAD + 1)
		return PC_ENOTSUP; /* tiny frames: the reference mirrors further out */
	const long s = j.w + 2 * PAD;
	const size_t plane_sz = (size_t)s * (size_t)(j.h + 2 * PAD);
	enum { NPL = 22 };
	float *mem = pc_dm_alloc(sizeof(float) * plane_sz * NPL);
	if (!mem)
		return pc_error(PC_ENOMEM, "%s: %ldx%ld planes",
		                pc_demosaic_method_get(method)->name, j.w, j.h);
	plane *all[NPL] = {&j.R,    &j.G,    &j.D[0], &j.D[1], &j.D[2], &j.D[3], &j.Q,    &j.H,
	                   &j.S[0], &j.S[1], &j.S[2], &j.S[3], &j.S[4], &j.S[5], &j.S[6], &j.S[7],
	                   &j.A,    &j.B,    &j.W,    &j.T,    &j.X,    NULL};
	for (int k = 0; k < NPL && all[k]; k++)
		*all[k] = (plane){mem + plane_sz * (size_t)k, s};
	run(&j, ST_RAW, threads);
	pad_rows(j.R, j.h);
	run(&j, ST_D, threads);
	for (int d = 0; d < 4; d++)
		pad_rows(j.D[d], j.h);
	run(&j, ST_G, threads);
	pad_rows(j.G, j.h);
	for (unsigned c = 0; c < 4 && !j.err; c++) {
		j.c = c;
		for (int q = 0; q < 8; q++) {
			plane keep = j.X;
			j.X = j.Q; /* the quantity is boxed straight from Q */
			run(&j, ST_Q | (q << 8), threads);
			box(&j, q, threads);
			j.X = keep;
		}
		run(&j, ST_ABW, threads);
		/* box A, B, W into S[3], S[4], S[5] (the window sums are no longer needed) */
		plane src[3] = {j.A, j.B, j.W};
		for (int k = 0; k < 3; k++) {
			plane keep = j.X;
			j.X = src[k];
			box(&j, 3 + k, threads);
			j.X = keep;
		}
		run(&j, ST_T, threads);
		pad_rows(j.T, j.h);
		pad_rows(j.Q, j.h);
		run(&j, ST_OUT, threads);
	}
	pc_dm_free(mem);
	if (j.err)
		return pc_error(PC_ENOMEM, "%s: row scratch", pc_demosaic_method_get(method)->name);
	return 0;
}

int pc_dm_mlri_fast(const pc_dm_call *call, const pc_fplane *out)
{
	int rc = mlri_fast(call->in, call->m, call->method, call->full_scale, call->threads, out);
	if (rc == PC_ENOTSUP) /* tiny frames: the reference mirrors further out (and limits) */
		return pc_dm_ref_of_call(call, out);
	if (!rc && pc_dm_limited(call->method))
		rc = pc_dm_range_limit(call->in, call->m, call->threads, call->level, out);
	return rc;
}
