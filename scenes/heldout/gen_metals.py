#!/usr/bin/env python3
"""Prints the held-out scene `metals`: rough metal spheres at five roughnesses under three light
placements, one of them polarized.

usage: gen_metals.py EXPOSURE_US > metals.json

Four metals (rows) by five rms facet slopes sigma 0.02, 0.05, 0.1, 0.2, 0.35 (columns) on a
matte grey floor. Complex indices at ~550 nm, rounded (Palik, Handbook of Optical Constants
of Solids, 1985): silver 0.12 + 3.3i, copper 1.0 + 2.6i, chromium 3.2 + 3.3i, titanium
1.9 + 2.6i. Lights: a point light above-left of the camera, a grazing directional light from
behind-right (rim glints near the metals' principal angle, where reflection polarizes most),
and a directional light linearly polarized at 60 deg (DoLP 0.9) from above-right, which metals
keep, rotated by their retardance. The stress suite has one aluminium-like and one gold
material at sigma 0.1-0.25 only.
"""
import json
import sys

if len(sys.argv) != 2:
    sys.exit(__doc__)
metals = {"silver": (0.12, 3.3), "copper": (1.0, 2.6), "chromium": (3.2, 3.3),
          "titanium": (1.9, 2.6)}
sigmas = (0.02, 0.05, 0.1, 0.2, 0.35)
materials = {"floor": {"n": 1.5, "k": 0.9, "sigma": 0.5}}
objs = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "floor"}]
for r, (name, (n, k)) in enumerate(metals.items()):
    for c, s in enumerate(sigmas):
        mat = f"{name}_{c}"
        materials[mat] = {"n": n, "k": k, "sigma": s}
        objs.append({"type": "sphere", "center": [round((c - 2) * 0.78, 3),
                     round((1.5 - r) * 0.78, 3), 0.33], "radius": 0.33, "material": mat})
scene = {
    "polarcam_scene": 1,
    "name": "held-out: rough metals (Ag, Cu, Cr, Ti) at sigma 0.02-0.35, three lights, one polarized",
    "camera": {"position": [0.4, -5.2, 5.6], "look_at": [0, 0.1, 0.2], "up": [0, 0, 1],
               "focal_length_mm": 3, "f_number": 4},
    "lights": [
        {"type": "point", "position": [-3.0, -4.0, 5.0], "intensity_w_sr": 2500},
        {"type": "directional", "direction": [0.55, 0.75, 0.37], "irradiance_w_m2": 120},
        {"type": "directional", "direction": [0.6, -0.2, 0.77], "irradiance_w_m2": 90,
         "polarization": {"linear_deg": 60, "dop": 0.9}},
    ],
    "materials": materials,
    "objects": objs,
    "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
    "sensor": {"preset": "ideal", "resolution": [448, 336], "exposure_us": float(sys.argv[1])},
}
print(json.dumps(scene, indent=1))
