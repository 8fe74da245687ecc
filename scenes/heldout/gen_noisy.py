#!/usr/bin/env python3
"""Prints a held-out scene through the IMX250MZR preset (full sensor noise: shot, read, dark,
PRNU/DSNU, analyser errors, crosstalk) at a fraction of its ideal-sensor exposure.

usage: gen_noisy.py SCENE.json bright|dim|dark > OUT.json

Fractions 0.6, 0.09 and 0.018 of the ideal exposure: other exposures than the stress suite's
(0.48, 0.064, 0.012). Meshes are referenced by the same relative paths: write OUT beside the
scene's OBJ files.
"""
import json
import sys

FRACTION = {"bright": 0.6, "dim": 0.09, "dark": 0.018}

if len(sys.argv) != 3 or sys.argv[2] not in FRACTION:
    sys.exit(__doc__)
with open(sys.argv[1]) as f:
    scene = json.load(f)
sensor = scene["sensor"]
if sensor.get("preset") != "ideal":
    sys.exit(f"{sys.argv[1]}: sensor.preset is {sensor.get('preset')!r}, expected 'ideal'")
level = sys.argv[2]
sensor["preset"] = "imx250mzr"
sensor["exposure_us"] = round(sensor["exposure_us"] * FRACTION[level], 4)
scene["name"] = f"{scene.get('name', sys.argv[1])} (IMX250MZR preset, {level} exposure: " \
    f"{sensor['exposure_us']} us)"
print(json.dumps(scene, indent=1))
