/* The renderer with the physics core's pBRDF against the pBRDF itself: a flat plane seen at a
 * known geometry (θ_i, θ_r, Δφ) must give E·cosθ_i·R(ψ_out)·f(θ_i, θ_r, Δφ)·R(ψ_in)·S_light,
 * where f is `polarcam pbrdf`'s Mueller matrix in the macro frames of physics.md §1 and the
 * rotations R(ψ) between the macro frames and the light's / the camera's Stokes frames are
 * derived here from the frame vectors (not from the renderer): agreement to 1e-9 relative.
 * Also: the diffuse and shadowing effects switched off equal materials declaring "none". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "polarcam/error.h"
#include "polarcam/pbrdf.h"
#include "polarcam/sim.h"

static void cross(const double a[3], const double b[3], double c[3])
{
	c[0] = a[1] * b[2] - a[2] * b[1];
	c[1] = a[2] * b[0] - a[0] * b[2];
	c[2] = a[0] * b[1] - a[1] * b[0];
}
static double dot(const double a[3], const double b[3])
{
	return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static void unit(double a[3])
{
	double l = sqrt(dot(a, a));
	for (int i = 0; i < 3; i++)
		a[i] /= l;
}

/* Stokes vector in frame (s_a, p_a) → frame (s_b, p_b) of the same beam: with
 * s_b = cosψ s_a + sinψ p_a, E_sb = cosψ E_sa + sinψ E_pa, E_pb = −sinψ E_sa + cosψ E_pa, hence
 * S1' = cos2ψ S1 + sin2ψ S2, S2' = −sin2ψ S1 + cos2ψ S2, S0 and S3 unchanged. */
static void rotate_frame(const double sa[3], const double pa[3], const double sb[3], double S[4])
{
	double psi = atan2(dot(sb, pa), dot(sb, sa));
	double c = cos(2 * psi), s = sin(2 * psi);
	double s1 = c * S[1] + s * S[2], s2 = -s * S[1] + c * S[2];
	S[1] = s1;
	S[2] = s2;
}

/* The Mueller matrix printed by `$POLARCAM pbrdf` (independent process, 17 digits), or 0. */
static int cli_pbrdf(double n, double k, double sigma, double ti, double tr, double phi,
                     double f[4][4])
{
	const char *exe = getenv("POLARCAM");
	if (!exe)
		return 0;
	char cmd[1024];
	snprintf(cmd, sizeof cmd,
	         "%s pbrdf --n %.17g --k %.17g --sigma %.17g --theta-i %.17g "
	         "--theta-r %.17g --phi %.17g --rho table 2>/dev/null",
	         exe, n, k, sigma, ti, tr, phi);
	FILE *p = popen(cmd, "r");
	if (!p)
		return 0;
	char buf[8192];
	size_t len = fread(buf, 1, sizeof buf - 1, p);
	buf[len] = '\0';
	pclose(p);
	const char *m = strstr(buf, "\"mueller\"");
	if (!m)
		return 0;
	m = strchr(m, '[');
	int got = 0;
	for (int i = 0; i < 16 && m; i++) {
		while (*m && (*m == '[' || *m == ',' || *m == ' ' || *m == ']'))
			m++;
		char *end;
		f[i / 4][i % 4] = strtod(m, &end);
		if (end == m)
			return 0;
		m = end;
		got++;
	}
	return got == 16;
}

static void check_geometry(double ti_deg, double tr_deg, double dphi_deg, const char *pol,
                           bool diffuse)
{
	const double D = M_PI / 180, ti = ti_deg * D, tr = tr_deg * D, dphi = dphi_deg * D;
	const double n = 1.46, k = 1.28, sigma = 0.2, E = 50;
	/* light from φ_i = 0, camera along k_r at φ_r = Δφ, both aimed at the origin */
	double L[3] = {sin(ti), 0, cos(ti)};
	double kr[3] = {sin(tr) * cos(dphi), sin(tr) * sin(dphi), cos(tr)};
	double ref[3] = {1, 1, 0.3}; /* a light reference that is neither s nor p */
	char text[4096];
	snprintf(text, sizeof text,
	         "{\"camera\": {\"position\": [%.17g, %.17g, %.17g], \"look_at\": [0, 0, 0],"
	         "   \"principal_point\": [8.5, 8.5], \"focal_length_mm\": 50},"
	         " \"sensor\": {\"resolution\": [16, 16]},"
	         " \"materials\": {\"paint\": {\"n\": %.17g, \"k\": %.17g, \"sigma\": %.17g}},"
	         " \"lights\": [{\"type\": \"directional\", \"direction\": [%.17g, %.17g, %.17g],"
	         "   \"irradiance_w_m2\": %g, \"reference\": [%g, %g, %g], \"polarization\": %s}],"
	         " \"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, "
	         "1], \"material\": \"paint\"}],"
	         " \"effects\": {\"diffuse\": %s, \"shadowing\": true, \"circular\": true}}",
	         5 * kr[0], 5 * kr[1], 5 * kr[2], n, k, sigma, L[0], L[1], L[2], E, ref[0], ref[1],
	         ref[2], pol, diffuse ? "true" : "false");
	pc_scene *sc = NULL;
	int rc = pc_scene_parse(text, "plane", ".", &sc);
	CHECK_EQ_INT(rc, 0);
	if (rc) {
		fprintf(stderr, "%s\n", pc_error_detail());
		return;
	}
	pc_sim *sim = NULL;
	CHECK_EQ_INT(pc_sim_new(sc, NULL, &sim), 0);
	pc_scene_free(sc);
	if (!sim)
		return;
	double row[16 * 4];
	CHECK_EQ_INT(pc_sim_truth_rows(sim, 0, 8, 9, row, NULL), 0);
	const double *S_pix =
	    row + 4 * 8; /* pixel (8, 8): its centre ray hits the origin exactly */

	/* the light's Stokes vector in its own frame (s_L = ref ⟂ d, p_L = d × s_L) */
	pc_sim_states st;
	pc_sim_get_states(sim, &st);
	double S[4];
	memcpy(S, st.psg[0], sizeof S);
	double d[3] = {-L[0], -L[1], -L[2]}, sL[3], pL[3];
	double rd = dot(ref, d);
	for (int i = 0; i < 3; i++)
		sL[i] = ref[i] - rd * d[i];
	unit(sL);
	cross(d, sL, pL);
	/* → incident macro frame s_Mi = (−sinφ_i, cosφ_i, 0), p_Mi = d_i × s_Mi (physics.md §1) */
	double sMi[3] = {0, 1, 0}, pMi[3];
	cross(d, sMi, pMi);
	rotate_frame(sL, pL, sMi, S);
	/* the pBRDF in macro frames, in-process and from the command line */
	pc_material m = {
	    n, k, sigma, diffuse ? PC_DIFFUSE_FRESNEL : PC_DIFFUSE_NONE, PC_SHADOW_TS, PC_RHO_TABLE,
	    0};
	pc_pbrdf *pb = NULL;
	CHECK_EQ_INT(pc_pbrdf_new(&m, &pb), 0);
	double f[4][4], fc[4][4];
	CHECK_EQ_INT(pc_pbrdf_eval(pb, ti, tr, dphi, f), 0);
	pc_pbrdf_free(pb);
	static int cli_note;
	if (diffuse && !cli_pbrdf(n, k, sigma, ti_deg, tr_deg, dphi_deg, fc)) {
		if (!cli_note++)
			fprintf(stderr,
			        "note: `polarcam pbrdf` gave no Mueller matrix: compared with "
			        "pc_pbrdf_eval in-process only\n");
	} else if (diffuse)
		for (int i = 0; i < 4; i++)
			for (int j = 0; j < 4; j++)
				CHECK_NEAR(fc[i][j], f[i][j], 1e-12 * fabs(f[0][0]));
	double So[4];
	for (int i = 0; i < 4; i++) {
		So[i] = 0;
		for (int j = 0; j < 4; j++)
			So[i] += f[i][j] * S[j];
		So[i] *= E * cos(ti);
	}
	/* outgoing macro frame s_Mr = (sinφ_r, −cosφ_r, 0), p_Mr = d_r × s_Mr, d_r = k_r → the
	 * camera's frame: s = camera x (right) ⟂ k_r, p = k_r × s */
	double sMr[3] = {sin(dphi), -cos(dphi), 0}, pMr[3];
	cross(kr, sMr, pMr);
	double fwd[3] = {-kr[0], -kr[1], -kr[2]}, up[3] = {0, 0, 1}, right[3];
	cross(fwd, up, right);
	unit(right);
	rotate_frame(sMr, pMr, right, So);
	double scale = fabs(So[0]);
	for (int i = 0; i < 4; i++) {
		if (!(fabs(S_pix[i] - So[i]) <= 1e-9 * scale))
			fprintf(stderr, "θi=%g θr=%g Δφ=%g %s: S%d = %.17g, expected %.17g\n",
			        ti_deg, tr_deg, dphi_deg, pol, i, S_pix[i], So[i]);
		CHECK_NEAR(S_pix[i], So[i], 1e-9 * scale);
	}
	CHECK(So[0] > 0);
	pc_sim_free(sim);
}

/* switched-off effects equal materials that declare the neutral choice */
static void check_neutral(const char *effect, const char *material_field)
{
#define NEUTRAL_FMT                                                                                \
	"{\"camera\": {\"position\": [0, -4, 2.5], \"look_at\": [0, 0, 0.5]},"                     \
	" \"sensor\": {\"resolution\": [32, 24], \"pixel_pitch_um\": 100},"                        \
	" \"materials\": {\"paint\": {\"n\": 1.47, \"k\": 0.47, \"sigma\": 0.1%s}},"               \
	" \"lights\": [{\"type\": \"point\", \"position\": [1, 2, 3], \"intensity_w_sr\": 100}],"  \
	" \"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0.5], \"radius\": 0.5, "           \
	"\"material\": \"paint\"},"                                                                \
	"   {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,1], \"material\": "         \
	"\"paint\"}],"                                                                             \
	" \"effects\": {\"%s\": %s}}"
	char a[2048], b[2048], mf[128];
	snprintf(mf, sizeof mf, ", %s", material_field);
	snprintf(a, sizeof a, NEUTRAL_FMT, "", effect, "false");
	snprintf(b, sizeof b, NEUTRAL_FMT, mf, effect, "true");
	pc_scene *sa = NULL, *sb = NULL;
	CHECK_EQ_INT(pc_scene_parse(a, "a", ".", &sa), 0);
	CHECK_EQ_INT(pc_scene_parse(b, "b", ".", &sb), 0);
	pc_sim *xa = NULL, *xb = NULL;
	if (sa && sb) {
		pc_sim_new(sa, NULL, &xa);
		pc_sim_new(sb, NULL, &xb);
	}
	CHECK(xa && xb);
	if (xa && xb) {
		double *A = malloc(sizeof(double) * 4 * 32 * 24),
		       *B = malloc(sizeof(double) * 4 * 32 * 24);
		pc_sim_truth_rows(xa, 0, 0, 24, A, NULL);
		pc_sim_truth_rows(xb, 0, 0, 24, B, NULL);
		int same = 1;
		for (int i = 0; i < 32 * 24; i++)
			for (int c = 0; c < 3; c++)
				same &= A[4 * i + c] == B[4 * i + c];
		CHECK(same);
		free(A);
		free(B);
	}
	pc_sim_free(xa);
	pc_sim_free(xb);
	pc_scene_free(sa);
	pc_scene_free(sb);
}

int main(void)
{
	/* physics.md §2's second reference geometry, in-plane forward, near-normal and grazing */
	check_geometry(40, 55, 150, "{\"linear_deg\": 30}", true);
	check_geometry(40, 55, 150, "\"unpolarized\"", true);
	check_geometry(30, 30, 180, "{\"linear_deg\": 70, \"dop\": 0.6}", true);
	check_geometry(60, 20, 95, "{\"circular\": 1}", true);
	check_geometry(10, 75, 210, "{\"stokes\": [0.3, -0.5, 0.4]}", false);
	check_geometry(80, 70, 170, "{\"linear_deg\": -20}", true);
	check_neutral("diffuse", "\"diffuse\": \"none\"");
	check_neutral("shadowing", "\"shadowing\": \"none\"");
	return pc_test_finish("test_sim_pbrdf");
}
