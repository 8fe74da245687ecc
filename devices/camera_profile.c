#include "polarcam/camera_profile.h"

#include <stddef.h>
#include <string.h>
#include <strings.h>

#include "polarcam/error.h"
#include "polarcam/format.h"

#define BAYER_RG_POLARIZED                                                                         \
	"BayerRGPolarized8,BayerRGPolarized10p,BayerRGPolarized12p,BayerRGPolarized16"

/* Models are matched by prefix, first match wins: a colour model whose name extends a
 * monochrome one (BFS-U3-51S5PC, BFS-U3-51S5P) comes first. */
static const pc_camera_profile pc_profiles[] = {
    /* polarcam's own simulated camera (polarcam serve) with a colour scene */
    {"polarcam", "polarcam-sim-colour", "simulated IMX250MYR", BAYER_RG_POLARIZED, 12,
     "RGGB:90,45,135,0"},
    /* polarcam's own simulated camera (polarcam serve) */
    {"polarcam", "", "simulated IMX250MZR",
     "PolarizeMono8,PolarizeMono12,PolarizeMono12p,PolarizeMono16,Mono8,Mono10,Mono12,"
     "Mono12p,Mono16",
     12, "90,45,135,0"},
    /* LUCID Phoenix / Triton 5.0 MP polarized (IMX250MZR) */
    {"LUCID", "PHX050S-P", "IMX250MZR",
     "PolarizeMono8,PolarizeMono12,PolarizeMono12p,PolarizeMono12Packed,PolarizeMono16", 12,
     "90,45,135,0"},
    {"LUCID", "TRI050S-P", "IMX250MZR",
     "PolarizeMono8,PolarizeMono12,PolarizeMono12p,PolarizeMono12Packed,PolarizeMono16", 12,
     "90,45,135,0"},
    /* LUCID Triton 5.0 MP colour polarized (IMX250MYR) */
    {"LUCID", "TRI050S-Q", "IMX250MYR", BAYER_RG_POLARIZED, 12, "RGGB:90,45,135,0"},
    /* FLIR Blackfly S colour polarized (IMX250MYR) */
    {"FLIR", "Blackfly S BFS-U3-51S5PC", "IMX250MYR", BAYER_RG_POLARIZED, 12, "RGGB:90,45,135,0"},
    {"FLIR", "BFS-U3-51S5PC", "IMX250MYR", BAYER_RG_POLARIZED, 12, "RGGB:90,45,135,0"},
    /* FLIR Blackfly S polarized (IMX250MZR) */
    {"FLIR", "Blackfly S BFS-U3-51S5P", "IMX250MZR",
     "Polarized8,Polarized10p,Polarized12p,"
     "Polarized16,Mono8,Mono10p,Mono12p,Mono16",
     12, "90,45,135,0"},
    {"FLIR", "BFS-U3-51S5P", "IMX250MZR",
     "Polarized8,Polarized10p,Polarized12p,Polarized16,"
     "Mono8,Mono10p,Mono12p,Mono16",
     12, "90,45,135,0"},
    /* Basler ace acA2440-75umPOL: standard mono names over the polarizer mosaic */
    {"Basler", "acA2440-75umPOL", "IMX250MZR", "Mono8,Mono12,Mono12p", 12, "90,45,135,0"},
    {NULL, NULL, NULL, NULL, 0, NULL},
};

const pc_camera_profile *pc_camera_profiles(void)
{
	return pc_profiles;
}

const pc_camera_profile *pc_camera_profile_find(const char *vendor, const char *model)
{
	if (!vendor || !model)
		return NULL;
	for (const pc_camera_profile *p = pc_profiles; p->vendor; p++)
		if (strncasecmp(vendor, p->vendor, strlen(p->vendor)) == 0 &&
		    strncmp(model, p->model, strlen(p->model)) == 0)
			return p;
	return NULL;
}

bool pc_camera_profile_has_format(const pc_camera_profile *p, const char *name)
{
	if (!p || !name || !*name)
		return false;
	size_t n = strlen(name);
	for (const char *s = p->raw_formats; s && *s;) {
		const char *e = strchr(s, ',');
		size_t len = e ? (size_t)(e - s) : strlen(s);
		if (len == n && strncmp(s, name, n) == 0)
			return true;
		s = e ? e + 1 : NULL;
	}
	return false;
}

/* The colour-polarization mosaic a BayerRG name states over a monochrome 2x2 analyser block:
 * the block repeated, under RGGB colour blocks with red at pixel (0,0). */
static pc_mosaic rggb_over(const pc_mosaic *mono)
{
	pc_mosaic m = *mono;
	static const uint8_t rggb[2][2] = {{PC_CFA_R, PC_CFA_G}, {PC_CFA_G, PC_CFA_B}};
	m.period = 4;
	for (unsigned y = 0; y < 4; y++)
		for (unsigned x = 0; x < 4; x++) {
			m.channel[y][x] = mono->channel[y & 1][x & 1];
			m.color[y][x] = rggb[y >> 1][x >> 1];
		}
	return m;
}

int pc_camera_format_get(const pc_camera_profile *p, const char *name,
                         const pc_mosaic *mosaic_override, pc_camera_format *out)
{
	if (!name || !out)
		return pc_error(PC_EINVAL, "camera format: missing argument");
	memset(out, 0, sizeof *out);
	bool pol = false, col = false;
	int rc = pc_format_from_genicam(name, &out->format, &pol, &col);
	if (rc)
		return rc;
	out->polarized = pol || pc_camera_profile_has_format(p, name);
	out->colour = col;
	if (!out->polarized)
		return 0;
	pc_mosaic m;
	if (mosaic_override) {
		m = *mosaic_override;
		rc = pc_mosaic_check(&m);
	} else if (p) {
		rc = pc_mosaic_parse(p->mosaic, &m);
	} else {
		m = col ? pc_mosaic_imx250myr() : pc_mosaic_imx250mzr();
	}
	if (rc)
		return pc_error_prefix(rc, "camera format %s: mosaic: ", name);
	if (col && m.period == 2)
		m = rggb_over(&m);
	out->colour = m.period == 4;
	out->sensor_mosaic = m;
	return 0;
}
