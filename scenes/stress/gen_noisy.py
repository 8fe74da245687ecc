#!/usr/bin/env python3
"""Prints a stress scene through the IMX250MZR preset (full sensor noise: shot, read, dark,
PRNU/DSNU, analyser errors, crosstalk) at a fraction of its ideal-sensor exposure.

usage: gen_noisy.py SCENE.json high|mid|low > OUT.json

The three exposures are those of noise_{high,mid,low}.json relative to chart.json's ideal
exposure (120, 16 and 3 us against 250 us: 0.48, 0.064 and 0.012), so every scene keeps the
brightness ratios the chart's noisy scenes have (the brightest tenth of the chart at ~53 %,
~7 % and ~1.3 % of full scale). Meshes are referenced by the same relative paths: write OUT
beside the scene's OBJ files (or copy them). docs/demosaicking.md ("Noise") has the results."""
import json
import sys

FRACTION = {"high": 120 / 250, "mid": 16 / 250, "low": 3 / 250}


def noisy(argv, fractions, doc):
    """The scene at argv[1] through the IMX250MZR preset at fractions[argv[2]] of its
    exposure (scenes/heldout/gen_noisy.py uses it with its own levels)."""
    if len(argv) != 3 or argv[2] not in fractions:
        sys.exit(doc)
    with open(argv[1]) as f:
        scene = json.load(f)
    sensor = scene["sensor"]
    if sensor.get("preset") != "ideal":
        sys.exit(f"{argv[1]}: sensor.preset is {sensor.get('preset')!r}, expected 'ideal'")
    level = argv[2]
    sensor["preset"] = "imx250mzr"
    sensor["exposure_us"] = round(sensor["exposure_us"] * fractions[level], 4)
    scene["name"] = f"{scene.get('name', argv[1])} (IMX250MZR preset, {level} exposure: " \
        f"{sensor['exposure_us']} us)"
    return scene


if __name__ == "__main__":
    json.dump(noisy(sys.argv, FRACTION, __doc__), sys.stdout)
    print()
