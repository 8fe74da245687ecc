/* tests/test_calib_fused.c - the calibrated bilinear pipeline (pc_calib_apply), which reads the
 * calibration in compact form (pc_compact_calib: per raw sample its analysis vector, dark
 * offset and inverse gain in 16 bits, made once per calibration) and solves the least squares
 * per output pixel in the core's fused pass:
 *   1. an identity calibration (dark = the black level, gain 1, ideal analysers) gives the
 *      uncalibrated pipeline's Stokes images (analytic case: the weighted least squares then
 *      equal the uncalibrated estimator; measured bit for bit, checked to 1e-6 relative);
 *   2. a non-ideal calibration (dark, gain, analysers with orientation and extinction errors)
 *      against a double-precision restatement of the model of polarcam/calib.h written here
 *      from the float maps (not the 16-bit ones): I = (raw − dark)/gain, each sample's
 *      equation divided by its a0 (u = a/a0), and per output pixel the weighted least
 *      squares over its 3×3 samples with the bilinear weights (1, ½, ¼; mirrored borders),
 *      S = (Σ K u uᵀ)⁻¹ Σ K u I/a0 solved by Cramer's rule (reference()).
 *      Stated tolerance (float kernel and 16-bit maps together): |ΔS| ≤ 2e-6·S0 + 2e-4 DN,
 *      |ΔDoLP| ≤ 1e-5, |ΔAoLP| ≤ 1e-5 rad where DoLP > 0.05;
 *   3. the same from a packed Mono12p raw and from Mono16 (identical), and the other path
 *      (opts.reference: the corrected float copy of the raw, the reference demosaic and the
 *      float per-pixel pseudo-inverses, a different estimator: bilinear of I and of the
 *      analysis vectors, S = (WᵀW)⁻¹WᵀI, reference_interp()) against its own double reference
 *      with the same tolerance; the fused output against the scene's truth: DoLP RMS ≤ 0.002,
 *      AoLP RMS ≤ 0.1° (the figures of issue 11's must-show), both estimators printed;
 *   4. the validity mask: a saturated sample and a pixel the calibration distrusts (listed in
 *      the compact calibration) each invalidate exactly their 3×3 bilinear support (9 + 9
 *      output pixels);
 *   5. a second call after the calibration is prepared reads cal only (pc_calib_prepared) and
 *      gives identical results;
 *   6. test 2 at every instruction-set level of this machine (pc_cpu_force) and at 38×22
 *      (rows with a scalar tail after the 16-pixel blocks);
 *   7. the core refuses a compact calibration with pseudo-inverses, for other methods, the
 *      reference path, another size, a distrusted sample listed outside the raw, with the
 *      options' black level, and for channels;
 *   8. a calibration without a dark map (the black level as a constant dark, no map read)
 *      against the reference with I = (raw − black level)/gain, at every level;
 *   9. test 2 for the mosaic's three other phases, at both sizes and every level. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/calib.h"
#include "polarcam/cpu.h"
#include "polarcam/error.h"

/* the frame size: 64×48 (whole 16-pixel blocks), then 38×22 (a scalar tail in every row) */
static uint32_t W = 64, H = 48;
/* the mosaic of the calibrations made (test 9 shifts its phase) */
static pc_mosaic MOS;
static bool mos_set = false;

static uint64_t rng_state = 0x243f6a8885a308d3ull;
static double urand(void)
{
	rng_state = rng_state * 6364136223846793005ull + 1442695040888963407ull;
	return (double)(rng_state >> 11) / 9007199254740992.0;
}

static void calib_alloc(pc_calib *cal, bool ideal)
{
	const size_t np = (size_t)W * H;
	pc_calib_init(cal);
	cal->geo = (pc_calib_geometry){W, H, 0, 0, W, H, 12, mos_set ? MOS : pc_mosaic_imx250mzr()};
	cal->black_level = 64;
	cal->saturation = 4095;
	cal->parts = PC_CAL_DARK | PC_CAL_FLAT | PC_CAL_ANALYSER;
	cal->dark = malloc(np * sizeof(float));
	cal->gain = malloc(np * sizeof(float));
	cal->analysis = malloc(3 * np * sizeof(float));
	cal->pinv_sp = calloc(3 * np, sizeof(float)); /* superpixel methods only */
	cal->valid = malloc(np);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			size_t p = (size_t)y * W + x;
			unsigned c = pc_mosaic_channel(&cal->geo.mosaic, x, y);
			double th = c * M_PI / 4, ex = 1, t = 1;
			cal->dark[p] = 64;
			cal->gain[p] = 1;
			if (!ideal) {
				th += (urand() - 0.5) * 4 * M_PI / 180;
				ex = 0.9 + 0.09 * urand();
				t = 1 + 0.05 * (urand() - 0.5);
				cal->dark[p] = (float)(64 + 6 * (urand() - 0.5));
				cal->gain[p] = (float)(1 + 0.1 * (urand() - 0.5));
			}
			cal->analysis[3 * p] = (float)(0.5 * t);
			cal->analysis[3 * p + 1] = (float)(0.5 * t * ex * cos(2 * th));
			cal->analysis[3 * p + 2] = (float)(0.5 * t * ex * sin(2 * th));
			if (ideal) { /* exact zeros where cos/sin round off */
				if (c == 1 || c == 3)
					cal->analysis[3 * p + 1] = 0;
				if (c == 2)
					cal->analysis[3 * p + 2] = 0;
			}
			cal->valid[p] = 1;
		}
}

/* A smooth polarized scene: DoLP 0.2..0.6, AoLP turning, S0 1200..2800. */
static void scene(uint32_t x, uint32_t y, double S[3])
{
	double s0 = 2000 + 800 * sin(x * 0.1) * cos(y * 0.07);
	double P = 0.4 + 0.2 * sin(0.05 * (x + y)), a = 0.03 * x + 0.02 * y;
	S[0] = s0;
	S[1] = s0 * P * cos(2 * a);
	S[2] = s0 * P * sin(2 * a);
}

/* The scene seen through the calibration's model: raw = dark + gain·(a·S), rounded; 12-bit
 * Mono12 in a 16-bit container. */
static void make_raw(const pc_calib *cal, pc_view *raw)
{
	CHECK_EQ_INT(pc_view_alloc(raw, PC_FMT_MONO12, W, H, 64), 0);
	for (uint32_t y = 0; y < H; y++)
		for (uint32_t x = 0; x < W; x++) {
			size_t p = (size_t)y * W + x;
			double S[3];
			scene(x, y, S);
			const float *v = cal->analysis + 3 * p;
			double i = v[0] * S[0] + v[1] * S[1] + v[2] * S[2];
			PC_ROW(raw, uint16_t, y)
			[x] = (uint16_t)lround(cal->dark[p] + cal->gain[p] * i);
		}
}

static int mir(int v, int n)
{
	return v < 0 ? -v : v >= n ? 2 * n - 2 - v : v;
}

/* bilinear of channel c at (x, y) over a double plane f with nc components per pixel */
static double bil(const double *f, int nc, int k, const pc_mosaic *m, unsigned c, int x, int y)
{
	double s = 0;
	int n = 0;
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++) {
			int xx = mir(x + dx, (int)W), yy = mir(y + dy, (int)H);
			/* the channel of the unmirrored neighbour: the mosaic's phase is mirrored
			 * too, and on even sizes a mirrored neighbour has the neighbour's channel
			 */
			if (pc_mosaic_channel(m, (unsigned)(x + dx + 2), (unsigned)(y + dy + 2)) !=
			    c)
				continue;
			s += f[((size_t)yy * W + (size_t)xx) * (size_t)nc + (size_t)k];
			n++;
		}
	return s / n;
}

/* S = a⁻¹b for the symmetric 3×3 a by Cramer's rule */
static void solve3(double a[3][3], const double b[3], double S[3])
{
	double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
	             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
	             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
	for (int k = 0; k < 3; k++) {
		double t[3][3];
		memcpy(t, a, sizeof t);
		for (int i = 0; i < 3; i++)
			t[i][k] = b[i];
		S[k] = (t[0][0] * (t[1][1] * t[2][2] - t[1][2] * t[2][1]) -
		        t[0][1] * (t[1][0] * t[2][2] - t[1][2] * t[2][0]) +
		        t[0][2] * (t[1][0] * t[2][1] - t[1][1] * t[2][0])) /
		       det;
	}
}

/* The double reference of the fused path at output pixel (x, y): each sample's equation
 * I_s = a_s·S divided by its a0, then the weighted least squares over the 3×3 neighbourhood,
 * min Σ K_s (I_s/a0_s − u_s·S)² with u_s = a_s/a0_s and the bilinear kernel's weights K = 1
 * (own sample), ½ (edge neighbours), ¼ (corners), mirrored borders; normal equations
 * (Σ K u uᵀ) S = Σ K u I/a0 (pc_compact_calib). Written from the definition, sample by sample,
 * not from the kernel's separable sums. */
static void reference(const pc_calib *cal, const double *I, const double *A, int x, int y,
                      double S[3])
{
	(void)cal;
	double a[3][3] = {{0}}, b[3] = {0};
	for (int dy = -1; dy <= 1; dy++)
		for (int dx = -1; dx <= 1; dx++) {
			const double k = (dx ? 0.5 : 1) * (dy ? 0.5 : 1);
			size_t p = (size_t)mir(y + dy, (int)H) * W + (size_t)mir(x + dx, (int)W);
			const double u[3] = {1, A[3 * p + 1] / A[3 * p], A[3 * p + 2] / A[3 * p]};
			for (int i = 0; i < 3; i++) {
				for (int j = 0; j < 3; j++)
					a[i][j] += k * u[i] * u[j];
				b[i] += k * u[i] * I[p] / A[3 * p];
			}
		}
	solve3(a, b, S);
}

/* The double reference of the reference path (opts.reference: the float per-pixel
 * pseudo-inverses of pc_calib_pinv) at (x, y): bilinear of I and of the analysis vectors per
 * channel, S = (WᵀW)⁻¹WᵀI. */
static void reference_interp(const pc_calib *cal, const double *I, const double *A, int x, int y,
                             double S[3])
{
	const pc_mosaic *m = &cal->geo.mosaic;
	double Wm[4][3], iv[4];
	for (unsigned c = 0; c < 4; c++) {
		iv[c] = bil(I, 1, 0, m, c, x, y);
		for (int k = 0; k < 3; k++)
			Wm[c][k] = bil(A, 3, k, m, c, x, y);
	}
	double a[3][3] = {{0}}, b[3] = {0};
	for (int i = 0; i < 3; i++) {
		for (int j = 0; j < 3; j++)
			for (int c = 0; c < 4; c++)
				a[i][j] += Wm[c][i] * Wm[c][j];
		for (int c = 0; c < 4; c++)
			b[i] += Wm[c][i] * iv[c];
	}
	solve3(a, b, S);
}

typedef struct outs {
	float *buf;
	uint8_t *mask;
	pc_stokes_out st;
	pc_validity v;
} outs;

/* outputs in one block; aligned to 64 bytes, the planes of a 64×48 frame take the streaming
 * stores (POLARCAM_NT_MIN_BYTES=0, set in main), those of 38×22 (rows of 152 bytes) not */
static void outs_init_aligned(outs *o, bool aligned)
{
	size_t n = 5 * (size_t)W * H * sizeof(float);
	o->buf = aligned ? aligned_alloc(64, (n + 63) / 64 * 64) : malloc(n);
	o->mask = malloc((size_t)W * H);
	memset(&o->st, 0, sizeof o->st);
	pc_fplane *pl[5] = {&o->st.s0, &o->st.s1, &o->st.s2, &o->st.dolp, &o->st.aolp};
	for (int k = 0; k < 5; k++)
		*pl[k] = (pc_fplane){o->buf + (size_t)k * W * H, W, 1};
	o->v = (pc_validity){o->mask, W, 0};
}

static void outs_init(outs *o)
{
	outs_init_aligned(o, false);
}

/* The outputs o of cal on raw against the double reference of the model (I: corrected
 * samples, A: analysis vectors), within the stated tolerance. */
typedef void (*ref_fn)(const pc_calib *, const double *, const double *, int, int, double[3]);

/* a distrusted sample whose 3×3 outputs (flagged invalid) compare_with skips (test 10) */
static int skip_x = -9, skip_y = -9;

static void compare_with(ref_fn ref, const pc_calib *cal, const double *I, const double *A,
                         const outs *o, const char *what)
{
	const size_t np = (size_t)W * H;
	double wS = 0, wD = 0, wA = 0;
	for (int y = 0; y < (int)H; y++)
		for (int x = 0; x < (int)W; x++) {
			if (abs(x - skip_x) <= 1 && abs(y - skip_y) <= 1)
				continue;
			size_t p = (size_t)y * W + (size_t)x;
			double S[3];
			ref(cal, I, A, x, y, S);
			for (int k = 0; k < 3; k++)
				wS = fmax(wS, fabs(o->buf[(size_t)k * np + p] - S[k]) /
				                  (2e-6 * S[0] + 2e-4));
			double dolp = hypot(S[1], S[2]) / S[0];
			wD = fmax(wD, fabs(o->buf[3 * np + p] - dolp));
			if (dolp > 0.05) {
				double aolp = fmod(0.5 * atan2(S[2], S[1]) + M_PI, M_PI);
				double d = fabs(o->buf[4 * np + p] - aolp);
				wA = fmax(wA, fmin(d, M_PI - d));
			}
		}
	printf("non-ideal calibration vs the double reference%s (%ux%u): worst |dS| %.3g of the "
	       "tolerance, dDoLP %.2g, dAoLP %.2g rad\n",
	       what, W, H, wS, wD, wA);
	CHECK(wS <= 1);
	CHECK(wD <= 1e-5);
	CHECK(wA <= 1e-5);
}

static void compare_reference(const pc_calib *cal, const pc_view *raw, const double *I,
                              const double *A, const outs *o, const char *what)
{
	(void)raw;
	compare_with(reference, cal, I, A, o, what);
}

/* RMS of DoLP and AoLP (rad) errors of an estimator (ref, or o's outputs when ref is NULL)
 * against the scene's truth (scene), over the pixels one away from the border */
static void truth_rms(ref_fn ref, const pc_calib *cal, const double *I, const double *A,
                      const outs *o, double *dolp_rms, double *aolp_rms)
{
	const size_t np = (size_t)W * H;
	double sd = 0, sa = 0;
	size_t n = 0;
	for (int y = 1; y + 1 < (int)H; y++)
		for (int x = 1; x + 1 < (int)W; x++) {
			double S[3], T[3];
			if (ref)
				ref(cal, I, A, x, y, S);
			else
				for (int k = 0; k < 3; k++)
					S[k] = o->buf[(size_t)k * np + (size_t)y * W + (size_t)x];
			scene((uint32_t)x, (uint32_t)y, T);
			double d = hypot(S[1], S[2]) / S[0] - hypot(T[1], T[2]) / T[0];
			double a = fabs(0.5 * (atan2(S[2], S[1]) - atan2(T[2], T[1])));
			a = fmod(a, M_PI);
			a = fmin(a, M_PI - a);
			sd += d * d;
			sa += a * a;
			n++;
		}
	*dolp_rms = sqrt(sd / (double)n);
	*aolp_rms = sqrt(sa / (double)n);
}

/* Drops what was prepared once from the calibration's maps (they were changed). */
static int run_ref(pc_calib *cal, const pc_view *raw, outs *o, bool reference)
{
	pc_frame f;
	memset(&f, 0, sizeof f);
	f.view = *raw;
	f.mosaic = cal->geo.mosaic;
	pc_pipeline_opts po = pc_pipeline_defaults();
	po.saturation_level = cal->saturation;
	po.threads = 2;
	po.reference = reference;
	return pc_calib_apply(cal, &f, 12, &po, &o->st, NULL, &o->v);
}

static int run(pc_calib *cal, const pc_view *raw, outs *o)
{
	return run_ref(cal, raw, o, false);
}

/* The double reference's inputs of a W × H raw: I = (raw − dark)/gain per pixel and the
 * calibration's analysis vectors, in fresh arrays. */
static void ref_inputs(const pc_calib *cal, const pc_view *raw, double **I, double **A)
{
	const size_t np = (size_t)W * H;
	*I = malloc(np * sizeof **I);
	*A = malloc(3 * np * sizeof **A);
	for (size_t p = 0; p < np; p++) {
		(*I)[p] =
		    ((double)PC_ROW(raw, uint16_t, p / W)[p % W] - cal->dark[p]) / cal->gain[p];
		for (int k = 0; k < 3; k++)
			(*A)[3 * p + k] = cal->analysis[3 * p + k];
	}
}

/* cal on raw at every instruction-set level this machine has, against the double reference;
 * outputs 64-byte aligned (at 64×48 the streaming stores, main sets POLARCAM_NT_MIN_BYTES=0) */
static void every_level(pc_calib *cal, const pc_view *raw, const double *I, const double *A,
                        const char *label)
{
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
		outs o;
		outs_init_aligned(&o, true);
		CHECK_EQ_INT(run(cal, raw, &o), 0);
		char what[96];
		snprintf(what, sizeof what, "%s, %s", label, pc_cpu_level_name((pc_cpu_level)l));
		compare_reference(cal, raw, I, A, &o, what);
		free(o.buf);
		free(o.mask);
	}
	pc_cpu_force(PC_CPU_LEVELS);
}

/* 6. the compact path at every instruction-set level this machine has and at a width with a
 * scalar tail, against the double reference; 7. the core's refusals of a compact calibration */
static void levels_and_sizes(void)
{
	static const uint32_t sizes[2][2] = {{64, 48}, {38, 22}};
	for (int z = 0; z < 2; z++) {
		W = sizes[z][0];
		H = sizes[z][1];
		pc_calib cal;
		calib_alloc(&cal, false);
		pc_view raw;
		make_raw(&cal, &raw);
		const size_t np = (size_t)W * H;
		double *I, *A;
		ref_inputs(&cal, &raw, &I, &A);
		every_level(&cal, &raw, I, A, "");
		if (z == 1) {
			/* 7. refusals: with pseudo-inverses, for another method, the reference
			 * path, another size, with the options' black level, and for channels */
			const pc_compact_calib *cc = &cal.apply_vec;
			CHECK(cc->v_q[0] != NULL && cc->v_q[1] != NULL && cc->gain_q != NULL);
			outs o;
			outs_init(&o);
			pc_pipeline_opts po = pc_pipeline_defaults();
			po.compact = cc;
			pc_analyser_pinv pv = {cal.analysis, 1, 1};
			po.pinv = &pv;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_EINVAL);
			printf("compact + pinv: %s\n", pc_error_detail());
			po.pinv = NULL;
			po.method = PC_DM_EARI;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_ENOTSUP);
			printf("compact + eari: %s\n", pc_error_detail());
			po.method = PC_DM_BILINEAR;
			po.reference = true;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_ENOTSUP);
			po.reference = false;
			po.black_level = 64;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_EINVAL);
			printf("compact + black level: %s\n", pc_error_detail());
			po.black_level = 0;
			pc_compact_calib other = *cc;
			other.width = W - 2;
			po.compact = &other;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_EINVAL);
			printf("compact of another size: %s\n", pc_error_detail());
			/* an inverse gain without its map would be ignored: refused */
			other = *cc;
			other.gain_q = NULL;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_EINVAL);
			CHECK(strstr(pc_error_detail(), "without gain_q") != NULL);
			printf("compact, gain_base without gain_q: %s\n", pc_error_detail());
			/* a distrusted sample listed outside the raw */
			uint32_t *drow = calloc((size_t)H + 1, sizeof *drow), dx[2] = {W, 0};
			uint8_t *vm = malloc((size_t)W * H);
			CHECK(drow && vm);
			for (uint32_t y = 1; y <= H; y++)
				drow[y] = 1;
			other = *cc;
			other.distrust_row = drow;
			other.distrust_x = dx;
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), PC_EINVAL);
			CHECK(strstr(pc_error_detail(), "outside") != NULL);
			printf("compact, distrusted sample outside: %s\n", pc_error_detail());
			/* the validity alone (pc_validity_run) checks the list as well: no write
			 * beyond the mask's row */
			if (drow && vm) {
				pc_validity v = {vm, W, 0};
				CHECK_EQ_INT(pc_validity_run(&raw, &po, &v), PC_EINVAL);
				CHECK(strstr(pc_error_detail(), "outside") != NULL);
				drow[3] = 2; /* offsets that decrease after row 3 */
				dx[0] = 0;
				CHECK_EQ_INT(pc_validity_run(&raw, &po, &v), PC_EINVAL);
				CHECK(strstr(pc_error_detail(), "decreases") != NULL);
				other.distrust_x = NULL;
				CHECK_EQ_INT(pc_validity_run(&raw, &po, &v), PC_EINVAL);
				CHECK(strstr(pc_error_detail(), "go together") != NULL);
			}
			free(drow);
			free(vm);
			po.compact = cc;
			pc_fplane ch[4];
			pc_fplanes_separate(o.buf, W, H, 4, ch);
			CHECK_EQ_INT(pc_demosaic_run(&raw, &po, ch, NULL), PC_EINVAL);
			CHECK_EQ_INT(pc_stokes_run(&raw, &po, &o.st, NULL), 0);
			/* analysers that cannot be inverted at (10, 12): refused once, when the
			 * compact calibration is made, naming the pixel */
			for (int y = 9; y <= 11; y++)
				for (int x = 11; x <= 13; x++)
					for (int k = 0; k < 3; k++)
						cal.analysis[3 * ((size_t)y * W + (size_t)x) +
						             (size_t)k] = k == 0   ? 0.5f
						                          : k == 1 ? 0.25f
						                                   : 0.0f;
			pc_calib_unprepare(&cal); /* the calibration changed */
			CHECK_EQ_INT(run(&cal, &raw, &o), PC_ENUMERIC);
			printf("singular: %s\n", pc_error_detail());
			CHECK(strstr(pc_error_detail(), "(12,10)") != NULL);
			free(o.buf);
			free(o.mask);
		}
		if (z == 0) {
			/* 8. no dark map: the black level is the dark, a constant (no map read) */
			free(cal.dark);
			cal.dark = NULL;
			cal.parts &= ~(unsigned)PC_CAL_DARK;
			pc_calib_unprepare(&cal);
			for (size_t p = 0; p < np; p++)
				I[p] = ((double)PC_ROW(&raw, uint16_t, p / W)[p % W] -
				        cal.black_level) /
				       cal.gain[p];
			every_level(&cal, &raw, I, A, ", no dark map");
			CHECK(cal.apply_vec.dark_q == NULL && cal.apply_vec.gain_q != NULL);
		}
		free(I);
		free(A);
		pc_view_free(&raw);
		pc_calib_free(&cal);
	}
}

/* 9. the other three phases of the IMX250MZR mosaic (a crop at an odd offset: [45 90; 0 135],
 * [135 0; 90 45], [0 135; 45 90]), both sizes, every level, against the double reference */
static void phases(void)
{
	static const int ang[3][4] = {{45, 90, 0, 135}, {135, 0, 90, 45}, {0, 135, 45, 90}};
	static const uint32_t sizes[2][2] = {{64, 48}, {38, 22}};
	for (int ph = 0; ph < 3; ph++)
		for (int z = 0; z < 2; z++) {
			W = sizes[z][0];
			H = sizes[z][1];
			CHECK_EQ_INT(pc_mosaic_from_angles(ang[ph], &MOS), 0);
			mos_set = true;
			pc_calib cal;
			calib_alloc(&cal, false);
			pc_view raw;
			make_raw(&cal, &raw);
			double *I, *A;
			ref_inputs(&cal, &raw, &I, &A);
			char what[64];
			snprintf(what, sizeof what, ", phase %d,%d,%d,%d", ang[ph][0], ang[ph][1],
			         ang[ph][2], ang[ph][3]);
			every_level(&cal, &raw, I, A, what);
			free(I);
			free(A);
			pc_view_free(&raw);
			pc_calib_free(&cal);
		}
	mos_set = false;
}

/* 10. a dead pixel (a0 = 0, or nearly) that the calibration distrusts: the calibration is
 * used (the pixel's maps stored as its channel's mean, not dividing by its a0), its 3×3
 * outputs are flagged, every other output matches the double reference at every level as
 * before; the same pixel trusted is refused naming it, when preparing and when reading the
 * file (each trusted sample's equation is divided by its a0) */
static void dead_pixel(void)
{
	W = 64;
	H = 48;
	const uint32_t dx = 20, dy = 17;
	const size_t pd = (size_t)dy * W + dx;
	static const float a0s[2] = {0.0f, 1e-4f};
	for (int t = 0; t < 2; t++) {
		pc_calib cal;
		calib_alloc(&cal, false);
		for (int k = 0; k < 3; k++)
			cal.analysis[3 * pd + (size_t)k] = k ? 0.0f : a0s[t];
		cal.valid[pd] = 0;
		pc_view raw;
		make_raw(&cal, &raw); /* the dead pixel reads its dark */
		double *I, *A;
		ref_inputs(&cal, &raw, &I, &A);
		skip_x = (int)dx;
		skip_y = (int)dy;
		every_level(&cal, &raw, I, A, t ? ", distrusted a0 = 1e-4" : ", distrusted a0 = 0");
		skip_x = skip_y = -9;
		outs o;
		outs_init(&o);
		CHECK_EQ_INT(run(&cal, &raw, &o), 0);
		CHECK_EQ_INT(o.v.n_invalid, 9);
		for (uint32_t y = dy - 1; y <= dy + 1; y++)
			for (uint32_t x = dx - 1; x <= dx + 1; x++)
				CHECK(o.mask[(size_t)y * W + x] == 0);
		if (t == 0) {
			cal.valid[pd] = 1;
			pc_calib_unprepare(&cal);
			CHECK_EQ_INT(run(&cal, &raw, &o), PC_ENUMERIC);
			printf("trusted a0 = 0: %s\n", pc_error_detail());
			CHECK(strstr(pc_error_detail(), "(20,17)") != NULL);
			/* the file's other members (pc_calib_read wants every part's maps) */
			cal.dark_noise = calloc((size_t)W * H, sizeof(float));
			cal.residual = calloc((size_t)W * H, sizeof(float));
			char path[] = "test_calib_fused_dead.npz";
			CHECK_EQ_INT(pc_calib_write(path, &cal), 0);
			pc_calib back;
			pc_calib_init(&back);
			CHECK_EQ_INT(pc_calib_read(path, &back), PC_EFORMAT);
			printf("read: %s\n", pc_error_detail());
			CHECK(strstr(pc_error_detail(), "(20, 17)") != NULL);
			remove(path);
		}
		free(o.buf);
		free(o.mask);
		free(I);
		free(A);
		pc_view_free(&raw);
		pc_calib_free(&cal);
	}
}

int main(void)
{
	/* aligned planar outputs take the streaming stores (every_level), also on machines whose
	 * default never does (AMD without AVX-512) and on frames this small */
	setenv("POLARCAM_NT_MIN_BYTES", "0", 1);
	/* ---- 1. identity calibration = the uncalibrated pipeline ---- */
	{
		pc_calib cal;
		calib_alloc(&cal, true);
		pc_view raw;
		make_raw(&cal, &raw);
		outs a, b;
		outs_init(&a);
		outs_init(&b);
		CHECK_EQ_INT(run(&cal, &raw, &a), 0);
		pc_pipeline_opts po = pc_pipeline_defaults();
		po.black_level = 64;
		po.saturation_level = 4095;
		CHECK_EQ_INT(pc_stokes_run(&raw, &po, &b.st, &b.v), 0);
		double worst[5] = {0};
		for (size_t p = 0; p < (size_t)W * H; p++)
			for (int k = 0; k < 5; k++) {
				double d = fabs(a.buf[(size_t)k * W * H + p] -
				                b.buf[(size_t)k * W * H + p]);
				if (k == 4)
					d = fmin(d, M_PI - d); /* AoLP wraps at π */
				worst[k] = fmax(worst[k], k < 3 ? d / b.buf[p] : d);
			}
		printf("identity calibration vs uncalibrated: worst |dS|/S0 %.2g %.2g %.2g, "
		       "dDoLP %.2g, dAoLP %.2g rad\n",
		       worst[0], worst[1], worst[2], worst[3], worst[4]);
		for (int k = 0; k < 3; k++)
			CHECK(worst[k] <= 1e-6);
		CHECK(worst[3] <= 1e-6);
		CHECK(worst[4] <= 1e-5);
		CHECK_EQ_INT(a.v.n_invalid, 0);
		CHECK_EQ_INT(b.v.n_invalid, 0);
		free(a.buf);
		free(a.mask);
		free(b.buf);
		free(b.mask);
		pc_view_free(&raw);
		pc_calib_free(&cal);
	}

	/* ---- 2.-5. a non-ideal calibration ---- */
	pc_calib cal;
	calib_alloc(&cal, false);
	pc_view raw;
	make_raw(&cal, &raw);
	const size_t np = (size_t)W * H;
	double *I, *A;
	ref_inputs(&cal, &raw, &I, &A);
	CHECK(!pc_calib_prepared(&cal, PC_DM_BILINEAR));
	outs o;
	outs_init(&o);
	CHECK_EQ_INT(run(&cal, &raw, &o), 0);
	CHECK(pc_calib_prepared(&cal, PC_DM_BILINEAR));
	compare_reference(&cal, &raw, I, A, &o, "");
	CHECK_EQ_INT(o.v.n_invalid, 0);

	/* 3. the corrected-copy path (packed Mono12p) and a Mono16 container give the same */
	{
		pc_view pk, m16;
		CHECK_EQ_INT(pc_view_alloc(&pk, PC_FMT_MONO12P, W, H, 64), 0);
		CHECK_EQ_INT(pc_view_from_u16(raw.data, raw.stride, &pk), 0);
		m16 = raw;
		m16.format = PC_FMT_MONO16;
		outs q, r, t;
		outs_init(&q);
		outs_init(&r);
		outs_init(&t);
		CHECK_EQ_INT(run(&cal, &pk, &q), 0);
		CHECK_EQ_INT(run(&cal, &m16, &r), 0);
		CHECK_EQ_INT(run_ref(&cal, &raw, &t, true), 0);
		double wq = 0, wr = 0, wt = 0;
		for (size_t i = 0; i < 3 * np; i++) {
			double s0 = o.buf[i % np];
			wq = fmax(wq, fabs(q.buf[i] - o.buf[i]) / s0);
			wr = fmax(wr, fabs(r.buf[i] - o.buf[i]) / s0);
			wt = fmax(wt, fabs(t.buf[i] - o.buf[i]) / s0);
		}
		printf("Mono12p, Mono16, reference path vs Mono12 fused: worst |dS|/S0 %.2g, "
		       "%.2g, %.2g\n",
		       wq, wr, wt);
		CHECK(wq == 0);
		CHECK(wr == 0);
		compare_with(reference_interp, &cal, I, A, &t, " (reference path)");
		/* the two estimators against the scene's truth, printed side by side (interpolating
		 * the analysers is the slightly more accurate on this scene); the fused path's
		 * weighted least squares is held to the 0.002 DoLP and 0.1° AoLP */
		double dw, aw, di, ai, dk, ak;
		truth_rms(reference, &cal, I, A, NULL, &dw, &aw);
		truth_rms(reference_interp, &cal, I, A, NULL, &di, &ai);
		truth_rms(NULL, &cal, I, A, &o, &dk, &ak);
		printf("vs the scene's truth (RMS, %ux%u inside): fused DoLP %.3g, AoLP %.3g deg; "
		       "its double reference (weighted least squares) %.3g, %.3g deg; interpolated "
		       "analysers %.3g, %.3g deg\n",
		       W, H, dk, ak * 180 / M_PI, dw, aw * 180 / M_PI, di, ai * 180 / M_PI);
		CHECK(dk <= 0.002);
		CHECK(ak * 180 / M_PI <= 0.1);
		CHECK_EQ_INT(t.v.n_invalid, 0);
		outs *all[3] = {&q, &r, &t};
		for (int k = 0; k < 3; k++) {
			free(all[k]->buf);
			free(all[k]->mask);
		}
		pc_view_free(&pk);
	}

	/* 4. validity: one saturated sample, one distrusted pixel */
	{
		PC_ROW(&raw, uint16_t, 10)[12] = 4095;
		cal.valid[(size_t)30 * W + 40] = 0;
		pc_calib_unprepare(&cal); /* the compact calibration lists the distrusted samples */
		CHECK_EQ_INT(run(&cal, &raw, &o), 0);
		CHECK_EQ_INT(o.v.n_invalid, 18);
		size_t inside = 0;
		for (int y = 0; y < (int)H; y++)
			for (int x = 0; x < (int)W; x++) {
				bool near = (abs(y - 10) <= 1 && abs(x - 12) <= 1) ||
				            (abs(y - 30) <= 1 && abs(x - 40) <= 1);
				inside += near && !o.mask[(size_t)y * W + (size_t)x];
				CHECK(o.mask[(size_t)y * W + (size_t)x] == !near);
			}
		CHECK_EQ_INT(inside, 18);
		/* a sample above the 12-bit range is refused, not clamped */
		PC_ROW(&raw, uint16_t, 3)[3] = 5000;
		CHECK_EQ_INT(run(&cal, &raw, &o), PC_ERANGE);
		printf("out of range: %s\n", pc_error_detail());
		PC_ROW(&raw, uint16_t, 3)[3] = 100;
	}

	free(o.buf);
	free(o.mask);
	free(I);
	free(A);
	pc_view_free(&raw);
	pc_calib_free(&cal);
	levels_and_sizes();
	phases();
	dead_pixel();
	return pc_test_finish("test_calib_fused");
}
