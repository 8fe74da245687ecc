#!/usr/bin/env python3
"""Prints the held-out scene `facets`: flat-faceted glossy polyhedra (facets.obj, an 80-face
geodesic sphere) under a half ring of lights and a polarized light: every facet mirrors a
different light at a different plane of incidence, so DoLP is high at many AoLP and steps
sharply at every facet edge.

usage: gen_facets.py EXPOSURE_US > facets.json

Three polyhedra of different sizes and turns (black glass n 1.65, white glaze n 1.35 with a
diffuse body, polished steel n 2.5 + 3.4i) on a dark floor. The stress suite's gloss scene has
smooth spheres (AoLP turns continuously); here it jumps.
"""
import json
import math
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__)
lights = []
for k in range(7):
    a = math.pi * (0.1 + 0.8 * k / 6)
    d = [round(math.cos(a) * 0.8, 4), round(0.35, 4), round(math.sin(a) * 0.8 + 0.1, 4)]
    n = math.sqrt(sum(x * x for x in d))
    lights.append({"type": "directional", "direction": [round(x / n, 4) for x in d],
                   "irradiance_w_m2": 180})
lights.append({"type": "point", "position": [-2.5, -4.0, 1.5], "intensity_w_sr": 900,
               "polarization": {"linear_deg": 100}})
objs = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "floor"},
        {"type": "mesh", "file": "facets.obj", "position": [-1.3, 0.2, 0.62], "scale": 0.6,
         "rotation_deg": [20, 35, 10], "material": "black_glass", "smooth": False},
        {"type": "mesh", "file": "facets.obj", "position": [0.45, 0.5, 0.75], "scale": 0.75,
         "rotation_deg": [-15, 10, 50], "material": "glaze", "smooth": False},
        {"type": "mesh", "file": "facets.obj", "position": [1.7, -0.5, 0.42], "scale": 0.42,
         "rotation_deg": [40, -25, 75], "material": "steel", "smooth": False}]
scene = {
    "polarcam_scene": 1,
    "name": "held-out: faceted glossy polyhedra, DoLP steps at facet edges, many AoLP",
    "camera": {"position": [0.2, -6.0, 2.4], "look_at": [0.1, 0, 0.5], "up": [0, 0, 1],
               "focal_length_mm": 2.4, "f_number": 4},
    "lights": lights,
    "materials": {"floor": {"n": 1.5, "k": 0.2, "sigma": 0.45},
                  "black_glass": {"n": 1.65, "sigma": 0.02, "diffuse": "none"},
                  "glaze": {"n": 1.35, "k": 0.02, "sigma": 0.05},
                  "steel": {"n": 2.5, "k": 3.4, "sigma": 0.06}},
    "objects": objs,
    "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
    "sensor": {"preset": "ideal", "resolution": [448, 336], "exposure_us": float(sys.argv[1])},
}
print(json.dumps(scene, indent=1))
