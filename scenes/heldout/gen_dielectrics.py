#!/usr/bin/env python3
"""Prints the held-out scene `dielectrics`: glossy dielectric boxes and spheres of refractive
index 1.3 to 2.0, turned to many orientations, under low and polarized lights.

usage: gen_dielectrics.py EXPOSURE_US > dielectrics.json

Five indices (1.3, 1.45, 1.6, 1.8, 2.0: Brewster's angle 52-63 deg) as boxes turned about all
three axes (faces at many planes of incidence: the reflected light's AoLP turns with them) and
as spheres; the low indices are glossy with a diffuse body, the high ones clear (specular
only). Lights: a low sun from the left (15 deg above the floor: grazing reflections near
Brewster's angle off the floor-facing faces), a point light behind the camera, and a point
light linearly polarized at 135 deg. The stress suite's dielectrics have n 1.5-1.55 under a
symmetric ring of lights.
"""
import json
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__)
ns = (1.3, 1.45, 1.6, 1.8, 2.0)
materials = {"floor": {"n": 1.5, "k": 0.35, "sigma": 0.35}}
objs = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "floor"}]
for i, n in enumerate(ns):
    clear = n >= 1.6
    materials[f"box_{i}"] = {"n": n, "sigma": 0.06 + 0.03 * i,
                             **({"diffuse": "none"} if clear else {})}
    materials[f"ball_{i}"] = {"n": n, "sigma": 0.04, **({"diffuse": "none"} if clear else {})}
    x = (i - 2) * 0.95
    objs.append({"type": "box", "center": [x, 0.45, 0.32], "size": [0.5, 0.42, 0.36],
                 "rotation_deg": [17 * i - 30, 11 * i + 8, 37 * i + 12],
                 "material": f"box_{i}"})
    objs.append({"type": "sphere", "center": [x + 0.2, -0.65, 0.24], "radius": 0.24,
                 "material": f"ball_{i}"})
scene = {
    "polarcam_scene": 1,
    "name": "held-out: dielectric boxes and spheres, n 1.3-2.0, many orientations, "
            "grazing and polarized lights",
    "camera": {"position": [-0.8, -7.4, 2.9], "look_at": [0.15, 0.1, 0.1], "up": [0, 0, 1],
               "focal_length_mm": 2.9, "f_number": 4},
    "lights": [
        {"type": "directional", "direction": [-0.966, 0.0, 0.259], "irradiance_w_m2": 220},
        {"type": "point", "position": [-1.0, -9.0, 4.5], "intensity_w_sr": 6000},
        {"type": "point", "position": [3.5, -2.0, 3.0], "intensity_w_sr": 1500,
         "polarization": {"linear_deg": 135}},
    ],
    "materials": materials,
    "objects": objs,
    "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
    "sensor": {"preset": "ideal", "resolution": [448, 336], "exposure_us": float(sys.argv[1])},
}
print(json.dumps(scene, indent=1))
