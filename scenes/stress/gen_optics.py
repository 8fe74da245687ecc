#!/usr/bin/env python3
"""Writes copies of a suite's scenes seen through a lens that blurs: each scene with the
simulator's "blur" effect (a Gaussian point-spread function of SIGMA pixels on the image-plane
radiance, docs/scene-format.md) and nothing else changed; mesh paths are rewritten to stay
valid from DST_DIR.

usage: gen_optics.py SIGMA SRC_DIR DST_DIR

scenes/stress/optics was written with: gen_optics.py 0.7 scenes/stress scenes/stress/optics
(a good machine-vision lens: MTF 50 % at 0.27 cycles/pixel).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from suite_copy import copy_suite  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sigma = float(sys.argv[1])
    if not 0.5 <= sigma <= 8:
        sys.exit("gen_optics.py: SIGMA must be in [0.5, 8] pixels")

    def edit(scene, name):
        scene.setdefault("effects", {})["blur"] = sigma
        scene["name"] = "%s, through a lens of PSF sigma %g px" % (scene.get("name", name), sigma)
        return name

    copy_suite(sys.argv[2], sys.argv[3], edit)


main()
