/* Camera profiles and the mapping from a camera's pixel format NAME to the raw format and the
 * mosaic (polarcam/camera_profile.h), checked against the layouts drawn from the datasheets
 * (written out here by hand, independent of pc_mosaic's constructors) and against packed row
 * sizes computed by hand. */
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "polarcam/camera_profile.h"
#include "polarcam/error.h"
#include "polarcam/format.h"

/* Sony IMX250MYR at sensor pixel (0,0): 2x2 polarizer blocks [90 45; 135 0] under RGGB.
 *   y=0  R90  R45 G90  G45
 *   y=1  R135 R0  G135 G0
 *   y=2  G90  G45 B90  B45
 *   y=3  G135 G0  B135 B0 */
static const char myr_colour[4][5] = {"RRGG", "RRGG", "GGBB", "GGBB"};
static const int myr_angle[4][4] = {
    {90, 45, 90, 45}, {135, 0, 135, 0}, {90, 45, 90, 45}, {135, 0, 135, 0}};

static char colour_letter(const pc_mosaic *m, uint32_t x, uint32_t y)
{
	switch (pc_mosaic_color(m, x, y)) {
	case PC_CFA_R:
		return 'R';
	case PC_CFA_G:
		return 'G';
	case PC_CFA_B:
		return 'B';
	default:
		return '-';
	}
}

/* Mismatches between m at (x, y) and the sensor pixel (sx(x), sy(y)) of the hand-drawn table,
 * over a 4x4 period; mirrored_x: the readout is mirrored (an analyser at θ becomes 180° − θ). */
static unsigned compare_myr(const pc_mosaic *m, uint32_t ox, uint32_t oy, bool mirrored_x,
                            uint32_t w)
{
	unsigned bad = 0;
	for (uint32_t y = 0; y < 4; y++)
		for (uint32_t x = 0; x < 4; x++) {
			uint32_t rx = ox + x, sy = oy + y;
			uint32_t sx = mirrored_x ? w - 1 - rx : rx;
			int a = myr_angle[sy % 4][sx % 4];
			if (mirrored_x)
				a = (180 - a) % 180;
			bad += (int)pc_mosaic_channel(m, x, y) * 45 != a;
			bad += colour_letter(m, x, y) != myr_colour[sy % 4][sx % 4];
		}
	return bad;
}

static void test_profiles_valid(void)
{
	unsigned n = 0;
	for (const pc_camera_profile *p = pc_camera_profiles(); p->vendor; p++, n++) {
		pc_mosaic m;
		CHECK_EQ_INT(pc_mosaic_parse(p->mosaic, &m), 0);
		CHECK_EQ_INT(pc_mosaic_check(&m), 0);
		bool colour_sensor = strstr(p->sensor, "IMX250MYR") != NULL;
		CHECK_EQ_INT(m.period, colour_sensor ? 4 : 2);
		/* every listed raw format is one polarcam reads, under the profile's mosaic */
		char list[256];
		snprintf(list, sizeof list, "%s", p->raw_formats);
		for (char *save = NULL, *t = strtok_r(list, ",", &save); t;
		     t = strtok_r(NULL, ",", &save)) {
			pc_camera_format cf;
			int rc = pc_camera_format_get(p, t, NULL, &cf);
			CHECK_EQ_INT(rc, 0);
			if (rc)
				fprintf(stderr, "%s %s: %s: %s\n", p->vendor, p->model, t,
				        pc_error_detail());
			CHECK(cf.polarized);
			CHECK_EQ_INT(cf.colour, colour_sensor);
			CHECK(memcmp(&cf.sensor_mosaic, &m, sizeof m) == 0);
		}
	}
	CHECK(n >= 9);
}

static void test_lookup_order(void)
{
	/* model prefixes: a colour model whose name extends a monochrome one is found as itself */
	const struct {
		const char *vendor, *model, *sensor;
	} c[] = {
	    {"FLIR", "BFS-U3-51S5PC-C", "IMX250MYR"},
	    {"FLIR", "BFS-U3-51S5P-C", "IMX250MZR"},
	    {"FLIR", "Blackfly S BFS-U3-51S5PC", "IMX250MYR"},
	    {"LUCID Vision Labs", "TRI050S-QC", "IMX250MYR"},
	    {"LUCID Vision Labs", "TRI050S-PC", "IMX250MZR"},
	    {"polarcam", "polarcam-sim-colour", "simulated IMX250MYR"},
	    {"polarcam", "polarcam-sim", "simulated IMX250MZR"},
	};
	for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
		const pc_camera_profile *p = pc_camera_profile_find(c[i].vendor, c[i].model);
		CHECK(p != NULL);
		if (p && strcmp(p->sensor, c[i].sensor)) {
			fprintf(stderr, "%s %s: profile sensor %s, expected %s\n", c[i].vendor,
			        c[i].model, p->sensor, c[i].sensor);
			CHECK(false);
		}
	}
	CHECK(pc_camera_profile_find("Acme", "X1") == NULL);
}

static void test_colour_names(void)
{
	/* name -> container, and the packed row size of a 2448-pixel row worked out by hand */
	const struct {
		const char *name;
		pc_pixfmt fmt;
		size_t row2448;
	} names[] = {
	    {"BayerRGPolarized8", PC_FMT_MONO8, 2448},
	    {"BayerRGPolarized10p", PC_FMT_MONO10P, 2448 * 10 / 8},
	    {"BayerRGPolarized12p", PC_FMT_MONO12P, 2448 * 12 / 8},
	    {"BayerRGPolarized16", PC_FMT_MONO16, 2448 * 2},
	};
	const pc_camera_profile *cams[] = {
	    pc_camera_profile_find("LUCID", "TRI050S-Q"),
	    pc_camera_profile_find("FLIR", "BFS-U3-51S5PC"),
	    pc_camera_profile_find("polarcam", "polarcam-sim-colour"),
	    NULL, /* an unknown camera: the name alone says IMX250MYR */
	    /* a monochrome profile: the name puts its blocks under RGGB */
	    pc_camera_profile_find("LUCID", "PHX050S-P"),
	};
	for (size_t c = 0; c < sizeof cams / sizeof cams[0]; c++)
		for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
			pc_camera_format cf;
			CHECK_EQ_INT(pc_camera_format_get(cams[c], names[i].name, NULL, &cf), 0);
			CHECK_EQ_INT(cf.format, names[i].fmt);
			CHECK(cf.polarized && cf.colour);
			CHECK_EQ_INT(cf.sensor_mosaic.period, 4);
			CHECK_EQ_INT(compare_myr(&cf.sensor_mosaic, 0, 0, false, 0), 0);
			size_t row = 0;
			CHECK_EQ_INT(pc_format_row_bytes(cf.format, 2448, &row), 0);
			CHECK_EQ_INT(row, names[i].row2448);
		}
}

static void test_roi_and_mirror(void)
{
	pc_camera_format cf;
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRGPolarized12p", NULL, &cf), 0);
	/* ROIs at odd offsets and offsets beyond one period: the table moved by hand */
	const uint32_t off[][2] = {{1, 0}, {0, 1}, {3, 1}, {1, 3}, {2, 2}, {5, 7}, {6, 4}};
	for (size_t i = 0; i < sizeof off / sizeof off[0]; i++) {
		pc_mosaic m = pc_mosaic_shift(&cf.sensor_mosaic, off[i][0], off[i][1]);
		CHECK_EQ_INT(compare_myr(&m, off[i][0], off[i][1], false, 0), 0);
	}
	/* ReverseX on a 2448-wide sensor (as aravis: applies it), then an ROI at (3,1) */
	pc_mosaic f = pc_mosaic_flip(&cf.sensor_mosaic, 1, 0, 2448, 2048);
	pc_mosaic m = pc_mosaic_shift(&f, 3, 1);
	CHECK_EQ_INT(compare_myr(&m, 3, 1, true, 2448), 0);
}

static void test_collisions_and_errors(void)
{
	/* Only names decide. LUCID's PolarizeMono16 value 0x81100007 is Aravis's
	 * CUSTOM_BAYER_RG_16 (docs/hardware.md), and polarcam serve gives the same value to
	 * BayerRGPolarized16 on its colour camera: the two names still map apart. */
	size_t n;
	const pc_genicam_format *t = pc_genicam_formats(&n);
	uint32_t pm16 = 0;
	for (size_t i = 0; i < n; i++)
		if (!strcmp(t[i].name, "PolarizeMono16"))
			pm16 = t[i].code;
	CHECK_EQ_INT(pm16, 0x81100007u);
	pc_camera_format a, b;
	CHECK_EQ_INT(pc_camera_format_get(NULL, "PolarizeMono16", NULL, &a), 0);
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRGPolarized16", NULL, &b), 0);
	CHECK(a.format == PC_FMT_MONO16 && a.polarized && !a.colour && a.sensor_mosaic.period == 2);
	CHECK(b.format == PC_FMT_MONO16 && b.polarized && b.colour && b.sensor_mosaic.period == 4);
	/* a plain Bayer format carries no polarizer: refused, naming it */
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRG16", NULL, &a), PC_ENOTSUP);
	CHECK(strstr(pc_error_detail(), "BayerRG16") != NULL);
	CHECK_EQ_INT(pc_camera_format_get(NULL, "RGB8", NULL, &a), PC_ENOTSUP);
	/* plain Mono: a mosaic only where the profile says so (Basler) */
	CHECK_EQ_INT(pc_camera_format_get(NULL, "Mono12", NULL, &a), 0);
	CHECK(!a.polarized && !a.colour);
	CHECK_EQ_INT(pc_camera_format_get(pc_camera_profile_find("Basler", "acA2440-75umPOL"),
	                                  "Mono12", NULL, &a),
	             0);
	CHECK(a.polarized && !a.colour && a.sensor_mosaic.period == 2);
	/* the user's mosaic (URI mosaic=): a monochrome layout goes under RGGB for a colour name,
	 * a colour one is taken as it is */
	pc_mosaic o;
	CHECK_EQ_INT(pc_mosaic_parse("0,45,90,135", &o), 0);
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRGPolarized8", &o, &a), 0);
	CHECK(a.colour && pc_mosaic_channel(&a.sensor_mosaic, 2, 1) == 2 &&
	      pc_mosaic_color(&a.sensor_mosaic, 2, 1) == PC_CFA_G &&
	      pc_mosaic_color(&a.sensor_mosaic, 3, 3) == PC_CFA_B);
	CHECK_EQ_INT(pc_mosaic_parse("BGGR:90,45,135,0", &o), 0);
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRGPolarized8", &o, &a), 0);
	CHECK(memcmp(&a.sensor_mosaic, &o, sizeof o) == 0);
	memset(&o, 0, sizeof o);
	o.period = 3;
	CHECK_EQ_INT(pc_camera_format_get(NULL, "BayerRGPolarized8", &o, &a), PC_EINVAL);
	CHECK(strstr(pc_error_detail(), "BayerRGPolarized8") != NULL);
	CHECK_EQ_INT(pc_camera_format_get(NULL, NULL, NULL, &a), PC_EINVAL);
}

int main(void)
{
	test_profiles_valid();
	test_lookup_order();
	test_colour_names();
	test_roi_and_mirror();
	test_collisions_and_errors();
	return pc_test_finish("test_camera_profile");
}
