#!/usr/bin/env python3
"""Prints a held-out planar-pattern scene: the zone plate (rings) or the near-Nyquist patches
(fine), each turned and tilted in 3-D so that perspective changes its frequency across the
frame.

usage: gen_patterns.py rings|fine EXPOSURE_US > NAME.json

rings: white matte rings on a glossy grey dielectric (n 1.4: polarization texture), the plate
       (scale 0.5: radius 0.25 m, rim period 2.5 mm, ~1.9 px) tilted 28 deg about x, 15 about z.
fine:  glossy dark bars, checks and dots (n 1.8) on rough aluminium, tilted 20 deg about x and
       turned 17 deg about z (periods ~2.3-4 px; bars at 27-97 deg after the turn).
Meshes: gen_meshes.py. The stress suite's patterns lie flat, at periods ~3 and ~5 px.
"""
import json
import sys

if len(sys.argv) != 3 or sys.argv[1] not in ("rings", "fine"):
    sys.exit(__doc__)
which = sys.argv[1]
if which == "rings":
    name = "held-out: tilted Fresnel zone plate, matte rings on glossy grey, rim ~1.9 px"
    mesh = {"type": "mesh", "file": "rings.obj", "position": [0, 0, 0.001], "scale": 0.5,
            "rotation_deg": [28, 0, 15], "material": "ink", "smooth": False}
    ground = {"type": "plane", "point": [0, 0, 0], "normal": [0.1214, -0.453, 0.8829],
              "material": "ground"}
    materials = {"ink": {"n": 1.46, "k": 1.1, "sigma": 0.5},
                 "ground": {"n": 1.4, "k": 0.05, "sigma": 0.12}}
    camera = {"position": [0.18, -3.8, 3.1], "look_at": [0, 0, 0], "up": [0, 0, 1]}
    lights = [{"type": "directional", "direction": [-0.4, 0.3, 0.866], "irradiance_w_m2": 250},
              {"type": "point", "position": [1.2, -3.0, 0.6], "intensity_w_sr": 400},
              {"type": "point", "position": [-0.6, -3.0, 2.0], "intensity_w_sr": 500,
               "polarization": {"linear_deg": 45}}]
else:
    name = "held-out: near-Nyquist bars, checks and dots, glossy dark on rough aluminium, tilted"
    mesh = {"type": "mesh", "file": "fine.obj", "position": [0, 0, 0.001], "scale": 1,
            "rotation_deg": [20, 0, 17], "material": "ink", "smooth": False}
    ground = {"type": "plane", "point": [0, 0, 0], "normal": [0.1, -0.3271, 0.9397],
              "material": "ground"}
    materials = {"ink": {"n": 1.8, "sigma": 0.15, "diffuse": "none"},
                 "ground": {"n": 1.2, "k": 7.0, "sigma": 0.4}}
    camera = {"position": [0.0, -2.3, 2.0], "look_at": [0, 0, 0], "up": [0, 0, 1]}
    lights = [{"type": "directional", "direction": [0.3, 0.55, 0.78], "irradiance_w_m2": 200},
              {"type": "point", "position": [-2.0, -1.5, 1.0], "intensity_w_sr": 300,
               "polarization": {"linear_deg": 75, "dop": 0.7}}]
# the ground is the plane the turned mesh lies in: Rz(gamma) Rx(alpha) (0, 0, 1)
camera.update({"focal_length_mm": 12 if which == "rings" else 8, "f_number": 4})
scene = {
    "polarcam_scene": 1,
    "name": name,
    "camera": camera,
    "lights": lights,
    "materials": materials,
    "objects": [ground, mesh],
    "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
    "sensor": {"preset": "ideal", "resolution": [448, 336], "exposure_us": float(sys.argv[2])},
}
print(json.dumps(scene, indent=1))
