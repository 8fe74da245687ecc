/* sim/scene_default.c - the built-in default scene (the main job's scene). The seed paper's two
 * paints (physics.md §8): black paint ñ = 1.46 − 1.28i, σ = 0.2, and green paint
 * ñ = 1.47 − 0.47i, σ = 0.1, on spheres and a ground plane under a directional light placed
 * behind the spheres so that the camera sees forward-scattered glints (high DoLP) on the
 * ground and the polarization pattern across each sphere. IMX250MZR-class sensor. */
#include "polarcam/sim.h"

static const char pc_default_scene[] =
    "{\n"
    "  \"polarcam_scene\": 1,\n"
    "  \"name\": \"default\",\n"
    "  \"camera\": {\"position\": [0, -7.5, 3.0], \"look_at\": [0, 0.3, 0.7],\n"
    "             \"up\": [0, 0, 1], \"focal_length_mm\": 12, \"f_number\": 4},\n"
    "  \"lights\": [{\"type\": \"directional\", \"direction\": [-0.55, -0.45, 0.70],\n"
    "              \"irradiance_w_m2\": 300, \"polarization\": \"unpolarized\"},\n"
    "             {\"type\": \"directional\", \"direction\": [0.35, 0.80, 0.48],\n"
    "              \"irradiance_w_m2\": 80, \"polarization\": \"unpolarized\"}],\n"
    "  \"materials\": {\n"
    "    \"black_paint\": {\"n\": 1.46, \"k\": 1.28, \"sigma\": 0.2},\n"
    "    \"green_paint\": {\"n\": 1.47, \"k\": 0.47, \"sigma\": 0.1}\n"
    "  },\n"
    "  \"objects\": [\n"
    "    {\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 0, 1], \"material\": "
    "\"green_paint\"},\n"
    "    {\"type\": \"sphere\", \"center\": [-1.4, 0.4, 1.0], \"radius\": 1.0, \"material\": "
    "\"black_paint\"},\n"
    "    {\"type\": \"sphere\", \"center\": [1.3, -0.5, 0.8], \"radius\": 0.8, \"material\": "
    "\"green_paint\"},\n"
    "    {\"type\": \"sphere\", \"center\": [0.3, 2.2, 0.6], \"radius\": 0.6, \"material\": "
    "\"black_paint\"}\n"
    "  ],\n"
    "  \"effects\": {\"diffuse\": true, \"shadowing\": true, \"cast_shadows\": true, \"circular\": "
    "true},\n"
    "  \"sensor\": {\"preset\": \"imx250mzr\", \"exposure_us\": 600}\n"
    "}\n";

const char *pc_scene_default_text(void)
{
	return pc_default_scene;
}
