#!/usr/bin/env python3
"""Prints the held-out scene `glints`: a very dark scene of black glossy objects in which a few
small lights make saturated specular glints.

usage: gen_glints.py EXPOSURE_US > glints.json

Black glossy dielectrics (n 1.5-1.7, no diffuse body) on a black rough floor, small chrome
and black beads (radius 1.5-4 cm: glints of a few pixels), a black box turned so that one face
mirrors a light: most of the frame far below 1 % of full scale, the glints far above it (the
sensor clips them). Three small point lights, one polarized at 20 deg; no ambient light.
The stress chart has its three glints on otherwise well-lit patches.
"""
import json
import math
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__)
materials = {
    "floor": {"n": 1.2, "sigma": 0.9, "diffuse": "none"},
    "black_a": {"n": 1.5, "sigma": 0.05, "diffuse": "none"},
    "black_b": {"n": 1.7, "sigma": 0.12, "diffuse": "none"},
    "chrome": {"n": 3.2, "k": 3.3, "sigma": 0.03},
}
objs = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "floor"},
        {"type": "sphere", "center": [-1.1, 0.3, 0.45], "radius": 0.45, "material": "black_a"},
        {"type": "sphere", "center": [0.9, 0.6, 0.38], "radius": 0.38, "material": "black_b"},
        {"type": "box", "center": [0.0, -0.4, 0.2], "size": [0.7, 0.4, 0.4],
         "rotation_deg": [0, 0, 28], "material": "black_a"}]
# a spiral of small beads: glints of a few pixels at every position
for k in range(18):
    a = 2.4 * k
    r = 0.35 + 0.075 * k
    objs.append({"type": "sphere", "center": [round(r * math.cos(a), 3), round(r * math.sin(a) + 0.1, 3),
                 0.015 + 0.0015 * k], "radius": round(0.015 + 0.0015 * k, 4),
                 "material": "chrome" if k % 3 else "black_b"})
scene = {
    "polarcam_scene": 1,
    "name": "held-out: dark scene of black gloss with small saturated glints",
    "camera": {"position": [0.3, -4.8, 3.4], "look_at": [0, 0.1, 0.2], "up": [0, 0, 1],
               "focal_length_mm": 2.6, "f_number": 4},
    "lights": [
        {"type": "point", "position": [-2.5, 1.5, 3.5], "intensity_w_sr": 300},
        {"type": "point", "position": [2.0, -3.5, 2.5], "intensity_w_sr": 200},
        {"type": "point", "position": [0.5, 3.0, 1.2], "intensity_w_sr": 250,
         "polarization": {"linear_deg": 20}},
    ],
    "materials": materials,
    "objects": objs,
    "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
    "sensor": {"preset": "ideal", "resolution": [448, 336], "exposure_us": float(sys.argv[1])},
}
print(json.dumps(scene, indent=1))
