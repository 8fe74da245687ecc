#!/usr/bin/env python3
"""Writes copies of a suite's noisy scenes (every scene whose sensor preset is not "ideal")
through the sensor at an analog gain of GAIN_DB: "gain_db" set and the exposure divided by
10^(GAIN_DB/20), so the mean raw level (DN) stays that of the scene while the system gain K,
and with it the shot noise's variance per DN, grows by 10^(GAIN_DB/20) (docs/scene-format.md:
K = K0·10^(gain_db/20)) and the read noise in DN by as much. Each copy is DST_DIR/NAME_gGAIN.json;
mesh paths are rewritten to stay valid from DST_DIR.

usage: gen_gain.py GAIN_DB SRC_DIR DST_DIR

scenes/stress/gain was written with: gen_gain.py 12 scenes/stress scenes/stress/gain and
gen_gain.py 24 scenes/stress scenes/stress/gain (the chart at the three exposures of
noise_{high,mid,low}.json, at +12 and +24 dB: a camera in low light, docs/demosaicking.md,
Round 40).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from suite_copy import copy_suite  # noqa: E402


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    gain = float(sys.argv[1])
    if not 0 < gain <= 48:
        sys.exit("gen_gain.py: GAIN_DB must be in (0, 48] dB")

    def edit(scene, name):
        sensor = scene.get("sensor", {})
        if sensor.get("preset", "ideal") == "ideal":
            return None
        sensor["gain_db"] = gain
        sensor["exposure_us"] = round(sensor["exposure_us"] / 10 ** (gain / 20), 6)
        scene["name"] = "%s, at %g dB analog gain" % (scene.get("name", name), gain)
        return "%s_g%g.json" % (name[:-5], gain)

    copy_suite(sys.argv[2], sys.argv[3], edit)


main()
