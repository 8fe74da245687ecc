/* Rendering against independently computed answers, with test-only BRDFs whose results are
 * known in closed form (the physics core's pBRDF is tested against `polarcam pbrdf` in
 * test_sim_pbrdf.c):
 *  - radiometry: an ideal Lambertian depolarizer under a directional light (S0 = E cosθ/π) and a
 *    point light (inverse-square law), pixel rays recomputed here;
 *  - cast shadows: shadowed pixels found with an analytic segment–sphere test;
 *  - Stokes frames and the AoLP convention: a "projector" BRDF (the outgoing field is the
 *    incident field projected perpendicular to k_r, Mueller from Jones via physics.md §1's A)
 *    under a linearly polarized light seen by a downward camera, with and without camera roll;
 *  - the retarder Mueller matrix against the Jones calculus;
 *  - an OBJ cube equals the box primitive; supersampling at 1 sample equals no supersampling;
 *  - every instruction-set instance of the batch shader (polarcam/cpu.h) passes all of the
 *    above, and all give the same Stokes values bit for bit (a pBRDF scene with cast shadows,
 *    spheres, planes and a mesh). */
#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "polarcam/cpu.h"
#include "polarcam/error.h"
#include "polarcam/optics.h"
#include "polarcam/sim.h"
#include "sim_stand_in.h"

typedef double complex cplx;

/* M = A (J ⊗ J*) A⁻¹ with A = [[1,0,0,1],[1,0,0,−1],[0,1,1,0],[0,i,−i,0]] (physics.md §1),
 * written out slowly from the definition. */
static void jones_to_mueller(const cplx J[2][2], double M[4][4])
{
	const cplx A[4][4] = {{1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0}, {0, I, -I, 0}};
	/* A⁻¹ = ½ [[1,1,0,0],[0,0,1,−i],[0,0,1,i],[1,−1,0,0]] */
	const cplx Ai[4][4] = {
	    {0.5, 0.5, 0, 0}, {0, 0, 0.5, -0.5 * I}, {0, 0, 0.5, 0.5 * I}, {0.5, -0.5, 0, 0}};
	cplx K[4][4], T[4][4];
	for (int a = 0; a < 2; a++)
		for (int b = 0; b < 2; b++)
			for (int c = 0; c < 2; c++)
				for (int d = 0; d < 2; d++)
					K[2 * a + c][2 * b + d] = J[a][b] * conj(J[c][d]);
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			T[i][j] = 0;
			for (int k = 0; k < 4; k++)
				T[i][j] += A[i][k] * K[k][j];
		}
	for (int i = 0; i < 4; i++)
		for (int j = 0; j < 4; j++) {
			cplx s = 0;
			for (int k = 0; k < 4; k++)
				s += T[i][k] * Ai[k][j];
			M[i][j] = creal(s);
		}
}

static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static pc_sim *make_sim(const char *text, pc_sim_brdf *brdf)
{
	pc_scene *s = NULL;
	int rc = pc_scene_parse(text, "test", ".", &s);
	if (rc) {
		fprintf(stderr, "scene: %s\n", pc_error_detail());
		return NULL;
	}
	pc_sim_options o = pc_sim_options_default();
	o.brdf = brdf;
	pc_sim *sim = NULL;
	rc = pc_sim_new(s, &o, &sim);
	if (rc)
		fprintf(stderr, "sim: %s\n", pc_error_detail());
	pc_scene_free(s);
	return sim;
}

#define W     48
#define H     32
#define PITCH 3.45e-6
#define FOCAL 0.012

/* Ground point seen by pixel (x, y) of a camera at height h looking straight down with up = +y. */
static void ground_point(int x, int y, double h, double P[3])
{
	double u = (x + 0.5 - W / 2.0) * PITCH, v = (y + 0.5 - H / 2.0) * PITCH;
	double d[3] = {u, -v, -FOCAL}; /* right = +x, up = +y, forward = −z */
	double t = h / FOCAL;
	P[0] = d[0] * t;
	P[1] = d[1] * t;
	P[2] = 0;
}

static const char *cam_down =
    "\"camera\": {\"position\": [0, 0, 10], \"direction\": [0, 0, -1], \"up\": [0, 1, 0],"
    " \"focal_length_mm\": 12},"
    "\"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 3.45},"
    "\"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},";

/* The ground plane under cam_down lit by a point light at (1, 2, 3) of the given intensity
 * (JSON: a number or [R, G, B]), written into text. */
static const char *point_scene(char *text, size_t size, const char *intensity)
{
	snprintf(text, size,
	         "{%s \"lights\": [{\"type\": \"point\", \"position\": [1, 2, 3], "
	         "\"intensity_w_sr\": %s}],"
	         " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], "
	         "\"material\": \"m\"}]}",
	         cam_down, intensity);
	return text;
}

static void test_radiometry(void)
{
	pc_sim_brdf lam = {brdf_lambert, NULL};
	char text[4096];
	/* directional light at 40° from the zenith: S0 = E cos40°/π everywhere */
	snprintf(text, sizeof text,
	         "{%s \"lights\": [{\"type\": \"directional\", \"direction\": [%.17g, 0, %.17g],"
	         " \"irradiance_w_m2\": 50}],"
	         " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], "
	         "\"material\": \"m\"}]}",
	         cam_down, sin(40 * M_PI / 180), cos(40 * M_PI / 180));
	pc_sim *sim = make_sim(text, &lam);
	CHECK(sim != NULL);
	if (!sim)
		return;
	double *S = malloc(sizeof(double) * 4 * W * H);
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 0, H, S, NULL), 0);
	double want = 50 * cos(40 * M_PI / 180) / M_PI, maxrel = 0;
	for (int i = 0; i < W * H; i++) {
		maxrel = fmax(maxrel, fabs(S[4 * i] - want) / want);
		CHECK(S[4 * i + 1] == 0 && S[4 * i + 2] == 0);
		CHECK(isnan(S[4 * i + 3])); /* S3 not carried without the circular effect */
	}
	CHECK(maxrel < 1e-13);
	pc_sim_free(sim);

	/* point light: S0 = I cosθ/(π r²) at each pixel's ground point */
	sim = make_sim(point_scene(text, sizeof text, "100"), &lam);
	CHECK(sim != NULL);
	if (!sim) {
		free(S);
		return;
	}
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 0, H, S, NULL), 0);
	maxrel = 0;
	for (int y = 0; y < H; y++)
		for (int x = 0; x < W; x++) {
			double P[3], L[3] = {1, 2, 3};
			ground_point(x, y, 10, P);
			double r2 = 0;
			for (int k = 0; k < 3; k++)
				r2 += (L[k] - P[k]) * (L[k] - P[k]);
			double w = 100 * (3 / sqrt(r2)) / (M_PI * r2);
			maxrel = fmax(maxrel, fabs(S[4 * (y * W + x)] - w) / w);
		}
	CHECK(maxrel < 1e-12);
	/* rows [5, 9) alone give the same values as the full render */
	double band[4 * W * 4];
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 5, 9, band, NULL), 0);
	CHECK(memcmp(band, S + 4 * W * 5, sizeof band) == 0);
	pc_sim_free(sim);

	/* a monochrome sensor takes the green value of an RGB light (docs/scene-format.md), as it
	 * does of a material's n and k and of the background: [7, 100, 1000] renders as 100 */
	sim = make_sim(point_scene(text, sizeof text, "[7, 100, 1000]"), &lam);
	CHECK(sim != NULL);
	if (sim) {
		double *R = malloc(sizeof(double) * 4 * W * H);
		CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 0, H, R, NULL), 0);
		for (int i = 0; i < 4 * W * H; i += 4)
			CHECK(R[i] == S[i] && R[i + 1] == S[i + 1] && R[i + 2] == S[i + 2]);
		free(R);
		pc_sim_free(sim);
	}
	free(S);
}

/* Does the segment P→L pass through the sphere (c, r)? Returns the distance margin. */
static double segment_sphere_margin(const double P[3], const double L[3], const double c[3],
                                    double r)
{
	double d[3], pc[3];
	for (int k = 0; k < 3; k++) {
		d[k] = L[k] - P[k];
		pc[k] = c[k] - P[k];
	}
	double t = dot(pc, d) / dot(d, d);
	t = t < 0 ? 0 : t > 1 ? 1 : t;
	double q[3] = {P[0] + t * d[0] - c[0], P[1] + t * d[1] - c[1], P[2] + t * d[2] - c[2]};
	return sqrt(dot(q, q)) - r; /* < 0: occluded */
}

static void test_shadows(void)
{
	pc_sim_brdf lam = {brdf_lambert, NULL};
	char text[4096];
	/* the camera sees the ground from above; a sphere near the light casts a shadow */
	for (int shadows = 0; shadows <= 1; shadows++) {
		snprintf(text, sizeof text,
		         "{%s \"lights\": [{\"type\": \"point\", \"position\": [0.3, 0, 6], "
		         "\"intensity_w_sr\": 100}],"
		         " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": "
		         "[0,0,1], \"material\": \"m\"},"
		         "   {\"type\": \"sphere\", \"center\": [0.5, 0.1, 4.5], \"radius\": 0.3, "
		         "\"material\": \"m\"}],"
		         " \"effects\": {\"cast_shadows\": %s}}",
		         cam_down, shadows ? "true" : "false");
		pc_sim *sim = make_sim(text, &lam);
		CHECK(sim != NULL);
		if (!sim)
			return;
		double *S = malloc(sizeof(double) * 4 * W * H);
		CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 0, H, S, NULL), 0);
		int n_shadow = 0, checked = 0;
		const double L[3] = {0.3, 0, 6}, C[3] = {0.5, 0.1, 4.5}, cam[3] = {0, 0, 10};
		for (int y = 0; y < H; y++)
			for (int x = 0; x < W; x++) {
				double P[3];
				ground_point(x, y, 10, P);
				/* skip pixels whose ray sees the sphere, and near-tangent cases */
				if (segment_sphere_margin(cam, P, C, 0.3) < 1e-6)
					continue;
				double m = segment_sphere_margin(P, L, C, 0.3);
				if (fabs(m) < 1e-6)
					continue;
				checked++;
				double v = S[4 * (y * W + x)];
				if (shadows && m < 0) {
					n_shadow++;
					CHECK(v == 0);
				} else {
					CHECK(v > 0);
				}
			}
		CHECK(checked > W * H / 2);
		if (shadows)
			CHECK(n_shadow > 20); /* the test geometry does produce a shadow */
		free(S);
		pc_sim_free(sim);
	}
}

/* AoLP in [0, π) from S1, S2 */
static double aolp(const double S[4])
{
	double a = 0.5 * atan2(S[2], S[1]);
	return a < 0 ? a + M_PI : a;
}

static void test_aolp_convention(void)
{
	pc_sim_brdf pr = {brdf_projector, NULL};
	char text[4096];
	for (int roll = 0; roll <= 1; roll++) {
		double rho = roll ? 20 * M_PI / 180 : 0;
		/* the light shines straight down, linearly polarized at 30° in its own frame (s =
		 * world x, p = d × s = −y): the field is along (cos30°, −sin30°, 0). The downward
		 * camera's image x axis is (cos ρ, sin ρ, 0), so AoLP = −30° − ρ (mod 180°). */
		snprintf(text, sizeof text,
		         "{\"camera\": {\"position\": [0, 0, 10], \"direction\": [0, 0, -1],"
		         "   \"up\": [%.17g, %.17g, 0], \"focal_length_mm\": 12, "
		         "\"principal_point\": [24.5, 16.5]},"
		         " \"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 3.45},"
		         " \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},"
		         " \"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 1], "
		         "\"irradiance_w_m2\": 1,"
		         "   \"reference\": [1, 0, 0], \"polarization\": {\"linear_deg\": 30}}],"
		         " \"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": "
		         "[0,0,1], \"material\": \"m\"}]}",
		         -sin(rho), cos(rho));
		pc_sim *sim = make_sim(text, &pr);
		CHECK(sim != NULL);
		if (!sim)
			return;
		double S[4 * W];
		CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 16, 17, S, NULL), 0);
		const double *c =
		    S + 4 * 24; /* pixel (24, 16): its centre is on the optical axis */
		double want = fmod(-30 * M_PI / 180 - rho + 2 * M_PI, M_PI);
		CHECK_NEAR(aolp(c), want, 1e-12);
		CHECK_NEAR(sqrt(c[1] * c[1] + c[2] * c[2]) / c[0], 1, 1e-12);
		CHECK_NEAR(c[0], 1 / M_PI, 1e-15);
		/* off-axis pixels: the projection keeps the AoLP within the tilt of the ray (<
		 * 0.3°) */
		for (int x = 0; x < W; x++)
			CHECK_NEAR(aolp(S + 4 * x), want, 0.005);
		pc_sim_free(sim);
	}
}

static void test_retarder(void)
{
	/* the stand-in's closed-form real-Jones Mueller matrix = the complex definition */
	for (int t = 0; t < 20; t++) {
		double a = sin(1.3 * t + 0.2), b = cos(0.7 * t), c = sin(2.1 * t - 1),
		       d = cos(1.9 * t + 0.5);
		cplx J[2][2] = {{a, b}, {c, d}};
		double Mj[4][4], Mc[4][4];
		jones_to_mueller(J, Mj);
		stand_in_real_jones_mueller(a, b, c, d, Mc);
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(Mc[i][j], Mj[i][j], 1e-14);
	}
	/* pc_retarder_mueller against R(−θ)·diag(1, e^{−iδ})·R(θ) through the Jones calculus */
	const double angles[] = {0, 0.3, M_PI / 4, 1.2, -0.7},
	             deltas[] = {M_PI / 2, 2.3, M_PI, 0.4};
	for (size_t a = 0; a < 5; a++)
		for (size_t d = 0; d < 4; d++) {
			double th = angles[a], de = deltas[d], c = cos(th), s = sin(th);
			cplx R[2][2] = {{c, s}, {-s, c}}, Ri[2][2] = {{c, -s}, {s, c}};
			cplx D[2][2] = {{1, 0}, {0, cexp(-I * de)}}, T[2][2], J[2][2];
			for (int i = 0; i < 2; i++)
				for (int j = 0; j < 2; j++)
					T[i][j] = D[i][0] * R[0][j] + D[i][1] * R[1][j];
			for (int i = 0; i < 2; i++)
				for (int j = 0; j < 2; j++)
					J[i][j] = Ri[i][0] * T[0][j] + Ri[i][1] * T[1][j];
			double Mj[4][4], Mr[4][4];
			jones_to_mueller(J, Mj);
			pc_retarder_mueller(th, de, Mr);
			for (int i = 0; i < 4; i++)
				for (int j = 0; j < 4; j++)
					CHECK_NEAR(Mr[i][j], Mj[i][j], 1e-14);
		}
}

static void test_mesh_equals_box(void)
{
	char dir[64];
	CHECK(pc_test_tmpdir(dir, sizeof dir, "pc_sim_render") != NULL);
	char obj[256];
	snprintf(obj, sizeof obj, "%s/cube.obj", dir);
	FILE *fp = fopen(obj, "w");
	/* unit cube centred at the origin, quads (fan-triangulated by the loader) */
	fprintf(fp, "v -.5 -.5 -.5\nv .5 -.5 -.5\nv .5 .5 -.5\nv -.5 .5 -.5\n"
	            "v -.5 -.5 .5\nv .5 -.5 .5\nv .5 .5 .5\nv -.5 .5 .5\n"
	            "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n");
	fclose(fp);
	pc_sim_brdf lam = {brdf_lambert, NULL};
#define FMT_BOX                                                                                    \
	"{\"camera\": {\"position\": [2.5, -3, 2.2], \"look_at\": [0, 0, 0.5], "                   \
	"\"focal_length_mm\": 8},"                                                                 \
	" \"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 100},"                        \
	" \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},"                                   \
	" \"lights\": [{\"type\": \"point\", \"position\": [3, -1, 4], \"intensity_w_sr\": 100}]," \
	" \"objects\": [%s], \"effects\": {\"cast_shadows\": true}}"
	char a[2048], b[2048], ob[1024];
	snprintf(ob, sizeof ob,
	         "{\"type\": \"box\", \"center\": [0, 0, 0.5], \"size\": [1, 1, 1],"
	         " \"rotation_deg\": [0, 0, 30], \"material\": \"m\"}");
	snprintf(a, sizeof a, FMT_BOX, ob);
	snprintf(ob, sizeof ob,
	         "{\"type\": \"mesh\", \"file\": \"%s\", \"position\": [0, 0, 0.5],"
	         " \"rotation_deg\": [0, 0, 30], \"smooth\": false, \"material\": \"m\"}",
	         obj);
	snprintf(b, sizeof b, FMT_BOX, ob);
	pc_sim *sa = make_sim(a, &lam), *sb = make_sim(b, &lam);
	CHECK(sa && sb);
	if (sa && sb) {
		double *A = malloc(sizeof(double) * 4 * W * H),
		       *B = malloc(sizeof(double) * 4 * W * H);
		CHECK_EQ_INT(pc_sim_truth_rows(sa, 0, 0, H, A, NULL), 0);
		CHECK_EQ_INT(pc_sim_truth_rows(sb, 0, 0, H, B, NULL), 0);
		int lit = 0, differ = 0;
		for (int i = 0; i < W * H; i++) {
			lit += A[4 * i] > 0;
			if (fabs(A[4 * i] - B[4 * i]) > 1e-9 * (A[4 * i] + 1e-300))
				differ++;
		}
		CHECK(lit > 100);   /* the box is in view and lit */
		CHECK(differ <= 3); /* only where a ray grazes an edge exactly */
		free(A);
		free(B);
	}
	pc_sim_free(sa);
	pc_sim_free(sb);
	remove(obj);
	rmdir(dir);
}

static void test_supersampling_neutral(void)
{
	pc_sim_brdf lam = {brdf_lambert, NULL};
#define FMT_SS                                                                                     \
	"{\"camera\": {\"position\": [0, -4, 2], \"look_at\": [0, 0, 0.6], \"focal_length_mm\": "  \
	"8},"                                                                                      \
	" \"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 100},"                        \
	" \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.1}},"                                   \
	" \"lights\": [{\"type\": \"point\", \"position\": [1, -1, 4], \"intensity_w_sr\": 100}]," \
	" \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0.6], \"radius\": 0.6, "           \
	"\"material\": \"m\"},"                                                                    \
	"   {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], \"material\": "         \
	"\"m\"}]%s}"
	char a[2048], b[2048], c[2048];
	snprintf(a, sizeof a, FMT_SS, "");
	snprintf(b, sizeof b, FMT_SS, ", \"effects\": {\"supersampling\": 1}");
	snprintf(c, sizeof c, FMT_SS, ", \"effects\": {\"supersampling\": 4}");
	pc_sim *sa = make_sim(a, &lam), *sb = make_sim(b, &lam), *sc = make_sim(c, &lam);
	CHECK(sa && sb && sc);
	if (sa && sb && sc) {
		double *A = malloc(sizeof(double) * 4 * W * H),
		       *B = malloc(sizeof(double) * 4 * W * H);
		double *C = malloc(sizeof(double) * 4 * W * H);
		pc_sim_truth_rows(sa, 0, 0, H, A, NULL);
		pc_sim_truth_rows(sb, 0, 0, H, B, NULL);
		pc_sim_truth_rows(sc, 0, 0, H, C, NULL);
		CHECK(memcmp(A, B, sizeof(double) * 4 * W * H) == 0);
		/* 4×4 samples change the sphere's silhouette pixels only; its mean over the image
		 * agrees with one sample per pixel to the aliasing error */
		double sa_ = 0, sc_ = 0;
		int edges = 0;
		for (int i = 0; i < W * H; i++) {
			sa_ += A[4 * i];
			sc_ += C[4 * i];
			edges += fabs(A[4 * i] - C[4 * i]) > 0.01 * A[4 * i];
		}
		CHECK_NEAR(sc_ / sa_, 1, 0.02);
		if (!(edges > 0 && edges < W * H / 5))
			fprintf(stderr, "supersampling: %d edge pixels of %d\n", edges, W * H);
		CHECK(edges > 0 && edges < W * H / 5);
		free(A);
		free(B);
		free(C);
	}
	pc_sim_free(sa);
	pc_sim_free(sb);
	pc_sim_free(sc);
}

/* The truth of a scene with every kind of stage work (spheres and planes in the vectorised
 * loops, a box through the per-ray path, cast shadows, the real pBRDF) at one level. */
static double *render_at(pc_cpu_level level)
{
	const char *text = "{\"camera\": {\"position\": [0.4, -4, 2.5], \"look_at\": [0, 0, 0.5], "
	                   "\"focal_length_mm\": 8},"
	                   " \"sensor\": {\"resolution\": [48, 32], \"pixel_pitch_um\": 100},"
	                   " \"materials\": {\"m\": {\"n\": 1.5, \"sigma\": 0.2}, \"k\": {\"n\": "
	                   "1.46, \"k\": 1.28, \"sigma\": 0.3}},"
	                   " \"lights\": [{\"type\": \"point\", \"position\": [1, -1, 4], "
	                   "\"intensity_w_sr\": 100},"
	                   "   {\"type\": \"directional\", \"direction\": [0.3, -0.2, 1], "
	                   "\"irradiance_w_m2\": 20}],"
	                   " \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0.6], "
	                   "\"radius\": 0.6, \"material\": \"m\"},"
	                   "   {\"type\": \"box\", \"center\": [1.2,0.5,0.3], \"size\": "
	                   "[0.5,0.5,0.6], \"material\": \"k\"},"
	                   "   {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], "
	                   "\"material\": \"k\"}],"
	                   " \"effects\": {\"cast_shadows\": true}}";
	if (pc_cpu_force(level))
		return NULL;
	pc_sim *sim = make_sim(text, NULL);
	double *S = sim ? malloc(sizeof(double) * 4 * W * H) : NULL;
	if (S && pc_sim_truth_rows(sim, 0, 0, H, S, NULL)) {
		free(S);
		S = NULL;
	}
	pc_sim_free(sim);
	pc_cpu_force(PC_CPU_LEVELS);
	return S;
}

static void test_instances_agree(void)
{
	double *base = render_at(PC_CPU_BASELINE);
	CHECK(base != NULL);
	if (!base)
		return;
	int lit = 0;
	for (int i = 0; i < W * H; i++)
		lit += base[4 * i] > 0;
	CHECK(lit > W * H / 2); /* the scene is seen, not background */
	for (int l = PC_CPU_AVX2; l <= (int)pc_cpu_supported(); l++) {
		double *S = render_at((pc_cpu_level)l);
		CHECK(S != NULL);
		if (!S)
			continue;
		size_t differ = 0;
		for (int i = 0; i < 4 * W * H; i++)
			differ += memcmp(&S[i], &base[i], sizeof(double)) != 0;
		if (differ)
			fprintf(stderr,
			        "  %s: %zu Stokes values differ from the baseline instance\n",
			        pc_cpu_level_name((pc_cpu_level)l), differ);
		CHECK(differ == 0);
		free(S);
	}
	free(base);
}

int main(void)
{
	/* every batch-shader instance this machine runs, held to the same answers */
	for (int l = 0; l <= (int)pc_cpu_supported(); l++) {
		CHECK_EQ_INT(pc_cpu_force((pc_cpu_level)l), 0);
		test_radiometry();
		test_shadows();
		test_aolp_convention();
		test_retarder();
		test_mesh_equals_box();
		test_supersampling_neutral();
		printf("  shader instance %s: done\n", pc_cpu_level_name((pc_cpu_level)l));
	}
	CHECK_EQ_INT(pc_cpu_force(PC_CPU_LEVELS), 0);
	test_instances_agree();
	return pc_test_finish("test_sim_render");
}
