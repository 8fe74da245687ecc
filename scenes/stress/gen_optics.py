#!/usr/bin/env python3
"""Writes copies of a suite's scenes seen through a lens that blurs: each scene with the
simulator's "blur" effect (a Gaussian point-spread function of SIGMA pixels on the image-plane
radiance, docs/scene-format.md) and nothing else changed; mesh paths are rewritten to stay
valid from DST_DIR.

usage: gen_optics.py SIGMA SRC_DIR DST_DIR

scenes/stress/optics was written with: gen_optics.py 0.7 scenes/stress scenes/stress/optics
(a good machine-vision lens: MTF 50 % at 0.27 cycles/pixel).
"""
import json
import os
import sys


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    sigma = float(sys.argv[1])
    if not 0.5 <= sigma <= 8:
        sys.exit("gen_optics.py: SIGMA must be in [0.5, 8] pixels")
    src, dst = sys.argv[2], sys.argv[3]
    os.makedirs(dst, exist_ok=True)
    for name in sorted(os.listdir(src)):
        if not name.endswith(".json"):
            continue
        with open(os.path.join(src, name)) as f:
            scene = json.load(f)
        scene.setdefault("effects", {})["blur"] = sigma
        scene["name"] = "%s, through a lens of PSF sigma %g px" % (scene.get("name", name), sigma)
        for obj in scene.get("objects", []):
            if "file" in obj:
                obj["file"] = os.path.relpath(os.path.join(src, obj["file"]), dst)
        with open(os.path.join(dst, name), "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")


main()
