#!/usr/bin/env python3
"""Writes monochrome copies of colour suites: every SRC_DIR/*.json scene through the monochrome
polarization sensor (Sony's IMX250MZR mosaic, no colour layer) with nothing else changed. A
monochrome sensor renders a material's G values (docs/scene-format.md), so each copy is the
scene's green channel: its luminance edges, textures, glints, dark regions and polarized
reflections stay, its red/blue-only hue detail becomes whatever green shows of it.

- preset "ideal" (with the colour layer's "layout" and "qe"): the ideal preset's own layout and
  QE (0.38), the exposure times 0.30/0.38 (the colour layer's green QE over the monochrome one),
  so that the raw levels are those of the scene's green channel;
- preset "imx250myr": "imx250mzr" (the same sensor without the colour layer, docs/scene-format.md),
  the exposure times 0.30/0.38 as above and the analog gain kept, so the levels and the noise
  in DN stay those of the green channel (the extinction ratio is the mono preset's, 300 against
  200).

Each copy is DST_DIR/PREFIX-NAME.json, PREFIX the source directory's name without "colour-"
(colour-sealed12/bowling.json → sealed12-bowling.json); mesh paths are rewritten to stay valid
from DST_DIR.

usage: gen_mono.py DST_DIR SRC_DIR...

scenes/stress/mono-sealed was written with: gen_mono.py scenes/stress/mono-sealed
scenes/stress/colour-sealed scenes/stress/colour-sealed2 ... scenes/stress/colour-sealed12
(its README).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from suite_copy import copy_suite  # noqa: E402

QE_GREEN, QE_MONO = 0.30, 0.38  # imx250myr's green and imx250mzr's / ideal's QE


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    dst = sys.argv[1]
    for src in sys.argv[2:]:
        prefix = os.path.basename(os.path.normpath(src))
        if prefix.startswith("colour-"):
            prefix = prefix[len("colour-"):]

        def edit(scene, name, prefix=prefix, src=src):
            sensor = scene.get("sensor", {})
            preset = sensor.get("preset", "ideal")
            if preset == "ideal":
                if not str(sensor.get("layout", "")).startswith("RGGB:"):
                    sys.exit("gen_mono.py: %s/%s: an ideal sensor without the RGGB colour layer"
                             % (src, name))
                sensor.pop("layout", None)
                sensor.pop("qe", None)
            elif preset == "imx250myr":
                if "layout" in sensor or "qe" in sensor:
                    sys.exit("gen_mono.py: %s/%s: imx250myr with its own layout or qe"
                             % (src, name))
                sensor["preset"] = "imx250mzr"
            else:
                sys.exit("gen_mono.py: %s/%s: sensor preset %r is neither ideal nor imx250myr"
                         % (src, name, preset))
            sensor["exposure_us"] = round(sensor["exposure_us"] * QE_GREEN / QE_MONO, 6)
            scene["name"] = "%s, through the monochrome sensor" % scene.get("name", name)
            return "%s-%s" % (prefix, name)

        copy_suite(src, dst, edit)


main()
