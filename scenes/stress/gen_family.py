#!/usr/bin/env python3
"""Writes the samples of a dataset made by `polarcam dataset` (docs/dataset.md) as one suite
that `polarcam eval --stress` and `polarcam bench demosaic --stress` run: every
DATASET_DIR/samples/NNNNNNNN/scene.json (a complete scene, the one the sample was rendered from)
as DST_DIR/fNNNNNNNN.json, with mesh paths rewritten to stay valid from DST_DIR. Scenes drawn at
random from a scene family are scenes no method was tuned on: a new seed gives new ones.

usage: gen_family.py DATASET_DIR DST_DIR

docs/demosaicking.md (Round 45) evaluates the ladder on one made with:
  polarcam dataset scenes/dataset/demosaic.json -o DS --count 60 --seed 20261207 \\
      --resolution 640x512
  python3 scenes/stress/gen_family.py DS DIR && polarcam eval --stress DIR
(random glossy objects through the IMX250MZR preset at 0, 6 or 12 dB of gain, auto-exposed).
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from suite_copy import write_scene  # noqa: E402


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    src, dst = sys.argv[1], sys.argv[2]
    samples = os.path.join(src, "samples")
    if not os.path.isdir(samples):
        sys.exit("gen_family.py: %s: no samples/ directory (not a polarcam dataset)" % src)
    names = sorted(n for n in os.listdir(samples)
                   if os.path.isfile(os.path.join(samples, n, "scene.json")))
    if not names:
        sys.exit("gen_family.py: %s: no samples/*/scene.json" % src)
    os.makedirs(dst, exist_ok=True)
    for n in names:
        sdir = os.path.join(samples, n)
        with open(os.path.join(sdir, "scene.json")) as f:
            scene = json.load(f)
        write_scene(scene, sdir, dst, "f%s.json" % n)
    print("%d scenes written to %s" % (len(names), dst))


main()
