/* sim/blur.c - the lens's point-spread function (effect "blur"): the image-plane Stokes radiance
 * (and Mueller matrices) of every colour channel blurred by a Gaussian of σ pixels before the
 * analysers.
 *
 * Physics. A lens images incoherent light: the image-plane intensity is the geometric image
 * convolved with the intensity point-spread function (Goodman, Introduction to Fourier Optics,
 * 3rd ed., 2005, §6.1.2). Each Stokes parameter is a difference of intensities behind ideal
 * analysers, so through non-polarizing optics each is convolved with the same PSF; the Mueller
 * matrices, linear in the radiance, likewise. The PSF is modelled as a Gaussian, the usual
 * approximation of a lens's blur by aberrations and defocus, and of the diffraction-limited
 * Airy core with σ ≈ 0.21·λ/NA = 0.42·λ·N (Zhang, Zerubia, Olivo-Marin, Applied Optics 46(10)
 * 1819, 2007, table 1, paraxial), i.e. about 0.27 px at f/4, 525 nm and 3.45 µm pixels.
 *
 * Discretisation. The renderer integrates each pixel's footprint (supersampling), so the blur
 * acts on pixel values: weights w_k = exp(−k²/(2σ²)) / Σ_j exp(−j²/(2σ²)), |k| ≤ R = ⌈4σ⌉,
 * applied along rows and then along columns (the Gaussian is separable). The sampled kernel
 * stands for the continuous PSF up to aliasing of order exp(−2π²σ²) (0.7 % at σ = 0.5 px; below
 * 1e-8 from σ = 1 px). At the sensor's edges the image is mirrored (reflect-101: row −1 reads
 * row 1), as a real sensor cannot see beyond them either; a region of interest reads its true
 * neighbours, so a ROI render equals the same crop of a full render.
 *
 * Memory: the row pass keeps (rows + 2R) × columns × channels Stokes vectors (4 doubles; 16
 * more with Mueller truth); the column pass forms each output row on demand. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "polarcam/error.h"
#include "polarcam/parallel.h"
#include "sim_impl.h"

int pc_blur_radius(double sigma)
{
	return (int)ceil(4 * sigma);
}

/* Reflect-101 index of i into [0, n): the period 2n − 2 folded back. */
static uint32_t mirror(int64_t i, uint32_t n)
{
	if (n <= 1)
		return 0;
	int64_t p = 2 * (int64_t)n - 2;
	i %= p;
	if (i < 0)
		i += p;
	return (uint32_t)(i < n ? i : p - i);
}

/* d[q] += w·s[q], q < n: one tap of the kernel on n values. */
static inline void add_tap(double *d, double w, const double *s, unsigned n)
{
	for (unsigned q = 0; q < n; q++)
		d[q] += w * s[q];
}

typedef struct hpass_ctx {
	pc_blur *b;
	const pc_sim *sim;
	uint32_t base; /* the chunk's first row of the region */
	int err;
} hpass_ctx;

/* Rows base + i of the rendered region: rendered in full (every channel), then blurred along the
 * row into b->S (and b->M) at the output columns. */
static void hpass_rows(void *ctx, uint32_t i0, uint32_t i1)
{
	hpass_ctx *c = ctx;
	pc_blur *b = c->b;
	const pc_sim *sim = c->sim;
	const unsigned nch = sim->nch;
	const uint32_t SW = sim->info.sensor_width;
	double *S = malloc((size_t)b->rw * nch * 4 * sizeof *S);
	double *M = b->M ? malloc((size_t)b->rw * nch * 16 * sizeof *M) : NULL;
	if (!S || (b->M && !M)) {
		free(S);
		free(M);
#ifdef _OPENMP
#pragma omp atomic write
#endif
		c->err = PC_ENOMEM;
		return;
	}
	const int R = b->R;
	for (uint32_t i = c->base + i0; i < c->base + i1; i++) {
		pc_render_row rr;
		pc_render_row_begin(sim, b->ry0 + i, &rr);
		pc_render_span(sim, &rr, b->rx0, b->rw, NULL, b->g, S, M);
		for (uint32_t x = 0; x < b->w; x++) {
			const int64_t sx = (int64_t)b->x0 + x;
			const size_t o = ((size_t)i * b->w + x) * nch;
			double *so = b->S + o * 4, *mo = M ? b->M + o * 16 : NULL;
			memset(so, 0, nch * 4 * sizeof *so);
			if (mo)
				memset(mo, 0, nch * 16 * sizeof *mo);
			for (int k = -R; k <= R; k++) {
				const size_t src = (size_t)(mirror(sx + k, SW) - b->rx0) * nch;
				add_tap(so, b->wt[k + R], S + src * 4, nch * 4);
				if (mo)
					add_tap(mo, b->wt[k + R], M + src * 16, nch * 16);
			}
		}
	}
	free(S);
	free(M);
}

void pc_blur_end(pc_blur *b)
{
	free(b->wt);
	free(b->S);
	free(b->M);
	memset(b, 0, sizeof *b);
}

int pc_blur_begin(const pc_sim *sim, unsigned g, uint32_t x0, uint32_t w, uint32_t y0, uint32_t h,
                  bool mueller, pc_blur *b, pc_sim_progress_fn progress, void *user, uint64_t *done,
                  uint64_t total)
{
	memset(b, 0, sizeof *b);
	const double sigma = sim->scene->blur_sigma;
	const uint32_t SW = sim->info.sensor_width, SH = sim->info.sensor_height;
	const int R = pc_blur_radius(sigma);
	b->R = R;
	b->g = g;
	b->x0 = x0;
	b->w = w;
	/* the rendered region: the output's rows and columns ± R, inside the sensor (mirrored
	 * reads beyond the sensor's edges land inside it) */
	const int64_t rx0 = (int64_t)x0 - R, rx1 = (int64_t)x0 + w + R;
	const int64_t ry0 = (int64_t)y0 - R, ry1 = (int64_t)y0 + h + R;
	b->rx0 = (uint32_t)(rx0 < 0 ? 0 : rx0);
	b->rw = (uint32_t)((rx1 > SW ? SW : rx1) - b->rx0);
	b->ry0 = (uint32_t)(ry0 < 0 ? 0 : ry0);
	b->rh = (uint32_t)((ry1 > SH ? SH : ry1) - b->ry0);
	b->wt = malloc((size_t)(2 * R + 1) * sizeof *b->wt);
	const size_t cells = (size_t)b->rh * w * sim->nch;
	b->S = malloc(cells * 4 * sizeof *b->S);
	b->M = mueller ? malloc(cells * 16 * sizeof *b->M) : NULL;
	if (!b->wt || !b->S || (mueller && !b->M)) {
		pc_blur_end(b);
		return pc_error(PC_ENOMEM, "lens blur: %u x %u pixels of Stokes%s radiance", w,
		                (unsigned)(ry1 - ry0), mueller ? " and Mueller" : "");
	}
	double sum = 0;
	for (int k = -R; k <= R; k++)
		sum += b->wt[k + R] = exp(-(double)k * k / (2 * sigma * sigma));
	for (int k = 0; k <= 2 * R; k++)
		b->wt[k] /= sum;
	const uint32_t chunk = 256;
	for (uint32_t i = 0; i < b->rh; i += chunk) {
		const uint32_t n = b->rh - i < chunk ? b->rh - i : chunk;
		hpass_ctx hc = {b, sim, i, 0};
		pc_parallel_rows(n, 2, sim->opt.threads, hpass_rows, &hc);
		if (hc.err) {
			pc_blur_end(b);
			return pc_error(hc.err, "lens blur: render row buffers");
		}
		if (done) {
			*done += n;
			if (progress)
				progress(user, *done, total);
		}
	}
	return 0;
}

void pc_blur_span(const pc_blur *b, const pc_sim *sim, uint32_t sy, uint32_t sx0, uint32_t n,
                  const uint8_t *chan, double *S, double *M)
{
	const unsigned nch = sim->nch, nout = chan ? 1 : nch;
	const uint32_t SH = sim->info.sensor_height;
	const int R = b->R;
	for (uint32_t i = 0; i < n; i++) {
		const size_t col = (size_t)(sx0 + i - b->x0);
		for (unsigned co = 0; co < nout; co++) {
			const unsigned ch = chan ? chan[i] : co;
			double *so = S + ((size_t)i * nout + co) * 4;
			double *mo = M ? M + ((size_t)i * nout + co) * 16 : NULL;
			memset(so, 0, 4 * sizeof *so);
			if (mo)
				memset(mo, 0, 16 * sizeof *mo);
			for (int k = -R; k <= R; k++) {
				const size_t row = mirror((int64_t)sy + k, SH) - b->ry0;
				const size_t o = (row * b->w + col) * nch + ch;
				add_tap(so, b->wt[k + R], b->S + o * 4, 4);
				if (mo)
					add_tap(mo, b->wt[k + R], b->M + o * 16, 16);
			}
		}
	}
}
