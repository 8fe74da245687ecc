#!/usr/bin/env python3
"""Prints a held-out scene through the IMX250MZR preset (full sensor noise: shot, read, dark,
PRNU/DSNU, analyser errors, crosstalk) at a fraction of its ideal-sensor exposure.

usage: gen_noisy.py SCENE.json bright|dim|dark > OUT.json

Fractions 0.6, 0.09 and 0.018 of the ideal exposure: other exposures than the stress suite's
(0.48, 0.064, 0.012). Meshes are referenced by the same relative paths: write OUT beside the
scene's OBJ files.
"""
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "stress"))
from gen_noisy import noisy  # noqa: E402 (the stress suite's generator, other levels)

FRACTION = {"bright": 0.6, "dim": 0.09, "dark": 0.018}

print(json.dumps(noisy(sys.argv, FRACTION, __doc__), indent=1))
