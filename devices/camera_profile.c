#include "polarcam/camera_profile.h"

#include <stddef.h>
#include <string.h>
#include <strings.h>

static const pc_camera_profile pc_profiles[] = {
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
