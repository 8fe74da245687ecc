#!/usr/bin/env python3
"""Writes the held-out colour stress scenes (README.md beside this file) and their mesh.

Python 3 standard library only; deterministic: `python3 gen_holdout.py` in this directory
rewrites every .json and disc.obj here (the files are checked in, this is how they were made).
`python3 gen_holdout.py --print NAME` prints one scene instead.

Colours come from per-channel extinction coefficients k = [R, G, B] as in ../colour/gen_colour.py
(in the pBRDF's diffuse term, physics.md section 2, a channel with k ~ 1.3-1.8 scatters back
brightly and one with k ~ 0.03 hardly at all); this palette adds hues the colour suite does not
use (orange, lime, violet, teal, pink, ...). The exposures (EXPOSURE) were set by looking at the
rendered raw frames and truth only (brightness, saturation, DoLP), before any method was run on
these scenes.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import colour_gen as cg  # noqa: E402 (../colour_gen.py: the helpers shared with colour-sealed2)

# name: k[R, G, B] (n = 1.5 for all)
PAINTS = {
    "red": [1.8, 0.03, 0.03],
    "green": [0.03, 1.8, 0.03],
    "blue": [0.03, 0.03, 1.8],
    "yellow": [1.8, 1.6, 0.03],
    "magenta": [1.6, 0.03, 1.8],
    "cyan": [0.03, 1.6, 1.8],
    "orange": [1.8, 0.6, 0.03],
    "lime": [0.7, 1.8, 0.03],
    "violet": [0.7, 0.03, 1.8],
    "teal": [0.03, 1.4, 0.8],
    "pink": [1.8, 0.5, 1.0],
    "sky": [0.4, 0.9, 1.8],
    "white": [1.4, 1.4, 1.4],
    "grey": [0.35, 0.35, 0.35],
    "black": [0.02, 0.02, 0.02],
}
HUES = ["red", "teal", "yellow", "violet", "lime", "pink", "blue", "orange", "cyan", "green",
        "magenta", "sky"]

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "diagonal": 280,
    "curved": 400,
    "isolum": 400,
    "primaries": 300,
    "gratings2": 400,
    "lowlight": 3,
    "highlights": 380,
    "aolp": 120,
    "text2": 400,
}

# a camera looking almost straight down at the z = 0 plane from 6 m: ~1.74 mm per pixel
CAMERA = cg.TOP
LIGHTS = [{"type": "directional", "direction": [-0.35, -0.45, 0.82], "irradiance_w_m2": 250},
          {"type": "directional", "direction": [0.5, 0.2, 0.84], "irradiance_w_m2": 120}]
EFFECTS = cg.EFFECTS


def r4(v):
    return cg.rounded(v, 5)


def mats(names, sigma, prefix=""):
    return cg.paints(PAINTS, names, sigma, prefix)


def sensor(name, preset="ideal", **kw):
    return cg.sensor(EXPOSURE[name], preset, **kw)


def scene(name, title, objs, materials, lights=None, camera=None, sen=None, effects=None):
    return cg.scene("colour hold-out: " + title, camera or CAMERA, lights or LIGHTS, materials,
                    objs, effects or EFFECTS, sen or sensor(name))


def tile(x, y, size, material, z=0.002, angle_deg=0.0):
    a = math.radians(angle_deg)
    return {"type": "plane", "point": r4([x, y, z]), "normal": [0, 0, 1],
            "size": r4(size), "u_axis": r4([math.cos(a), math.sin(a), 0]), "material": material}


ground = cg.ground


def diagonal():
    # 6 x 5 cells of 0.13 m (~75 px), each an axis-aligned square of one hue (abutting: the
    # cell borders are horizontal/vertical hue edges) carrying a 0.08 m square of another hue
    # rotated by an angle that is not a multiple of 45 degrees, mostly: oblique hue edges at
    # 30 angles
    objs = [ground("grey")]
    s, nx, ny = 0.13, 6, 5
    k = 0
    for j in range(ny):
        for i in range(nx):
            x, y = (i - (nx - 1) / 2) * s, (j - (ny - 1) / 2) * s
            a = HUES[(i + 2 * j) % len(HUES)]
            b = HUES[(i * 5 + j * 7 + 3) % len(HUES)]
            if b == a:
                b = "white" if k % 2 else "black"
            objs.append(tile(x, y, [s, s], a))
            objs.append(tile(x, y, [0.08, 0.08], b, z=0.004, angle_deg=3.0 + 87.0 * k / 29))
            k += 1
    return scene("diagonal", "rotated squares of one hue on squares of another: oblique hue "
                 "edges at 30 angles from 3 to 90 degrees", objs, mats(PAINTS, 0.25))


def disc_mesh():
    lines = ["# unit disc in z = 0 (96 segments), written by gen_holdout.py"]
    n = 96
    lines.append("v 0 0 0")
    for k in range(n):
        a = 2 * math.pi * k / n
        lines.append("v %.6f %.6f 0" % (math.cos(a), math.sin(a)))
    for k in range(n):
        lines.append("f 1 %d %d" % (2 + k, 2 + (k + 1) % n))
    return "\n".join(lines) + "\n"


def disc(x, y, r, material, z):
    return {"type": "mesh", "file": "disc.obj", "position": r4([x, y, z]),
            "scale": r4([r, r, 1]), "material": material, "smooth": False}


def curved_objs():
    # discs of radius 2-40 px and targets of concentric rings (widths 3, 5, 8 px) of
    # alternating hues on a cyan-green ground: curved hue edges at every orientation
    px = 0.00174
    objs = [ground("teal")]
    # targets: concentric discs stacked upwards, each smaller one above the larger
    for (cx, cy, w, n, pair) in ((-0.25, 0.12, 3, 12, ("red", "lime")),
                                 (0.22, 0.13, 5, 8, ("blue", "yellow")),
                                 (0.0, -0.16, 8, 6, ("magenta", "green"))):
        for q in range(n):
            r = (n - q) * w * px
            objs.append(disc(cx, cy, r, pair[q % 2], 0.002 + 0.0005 * q))
    # loose discs of growing radius along the bottom and the top
    radii = (2, 3, 4.5, 6, 9, 13, 19, 27)
    hues = ("orange", "violet", "pink", "red", "sky", "yellow", "blue", "magenta")
    for q, (r, h) in enumerate(zip(radii, hues)):
        objs.append(disc(-0.40 + 0.105 * q, -0.29 + 0.012 * q, r * px, h, 0.002))
        objs.append(disc(0.40 - 0.1 * q, 0.30 - 0.004 * q, r * px * 0.8, HUES[(q + 5) % 12],
                         0.002))
    return objs


def curved():
    return scene("curved", "discs of 2-27 px radius and ring targets (3, 5, 8 px rings) in "
                 "abutting hues: curved hue edges", curved_objs(), mats(PAINTS, 0.25))


# pairs of paints whose pseudo-panchromatic brightness (QE-weighted R + 2G + B) is about equal
# in this lighting (checked on the rendered truth, README.md): hue edges P0 does not see
ISO_PAIRS = [
    ("iso_r", [1.05, 0.25, 0.25], "iso_g", [0.22, 0.62, 0.22]),
    ("iso_b", [0.25, 0.35, 1.6], "iso_y", [0.8, 0.8, 0.1]),
    ("iso_m", [0.9, 0.2, 0.9], "iso_c", [0.2, 0.62, 0.72]),
    ("iso_w", [0.7, 0.55, 0.45], "iso_k", [0.45, 0.55, 0.7]),
]


def isolum():
    # an 8 x 6 checkerboard of ~26 px cells in each of four regions, each region one pair of
    # paints of (about) equal brightness and different hue; cells offset by a third of a cell
    # per row so corners do not line up
    m = {}
    for a, ka, b, kb in ISO_PAIRS:
        m[a] = {"n": 1.5, "k": ka, "sigma": 0.3}
        m[b] = {"n": 1.5, "k": kb, "sigma": 0.3}
    objs = [ground("iso_w")]
    s = 0.045
    for r, (a, _, b, _) in enumerate(ISO_PAIRS):
        ox, oy = (-0.215 if r % 2 == 0 else 0.215), (0.155 if r < 2 else -0.155)
        for j in range(6):
            for i in range(8):
                x = ox + (i - 3.5) * s + (j % 3) * s / 3
                y = oy + (j - 2.5) * s
                objs.append(tile(x, y, [s, s], a if (i + j) % 2 == 0 else b))
    m["iso_w"]["sigma"] = 0.3
    return scene("isolum", "checkerboards of paint pairs of about equal brightness and "
                 "different hue, low to medium chroma contrast", objs, m)


def primaries():
    # rows of pure red, green and blue tiles abutting, each row shifted by one tile (every pair
    # meets horizontally, vertically and at corners), four zones of tile size 5, 7, 10, 14 px
    px = 0.00174
    objs = [ground("black")]
    prim = ("red", "green", "blue")
    zones = ((-0.21, 0.16, 5), (0.21, 0.16, 7), (-0.21, -0.16, 10), (0.21, -0.16, 14))
    for zx, zy, t in zones:
        s = t * px
        n = int(0.36 / s)
        m = int(0.26 / s)
        for j in range(m):
            for i in range(n):
                c = prim[(i + j) % 3] if t != 10 else prim[(i + 2 * j + (i // 2)) % 3]
                objs.append(tile(zx + (i - (n - 1) / 2) * s, zy + (j - (m - 1) / 2) * s,
                                 [s, s], c))
    return scene("primaries", "abutting pure red, green and blue tiles of 5, 7, 10 and 14 px",
                 objs, mats(("red", "green", "blue", "black"), 0.2))


def gratings2():
    # the monochrome suite's 16 bar gratings (../gratings.obj) scaled to periods ~4.0 and
    # ~6.6 px and turned by 11.25 degrees (orientations between the colour suite's), green
    # glossy bars on matte magenta paper
    m = mats(("green",), 0.05)
    m["paper"] = {"n": 1.5, "k": [1.6, 0.05, 1.4], "sigma": 0.6}
    objs = [ground("paper"),
            {"type": "mesh", "file": "../gratings.obj", "position": [0, 0.005, 0.001],
             "scale": 0.77, "rotation_deg": [0, 0, 11.25], "material": "green",
             "smooth": False}]
    return scene("gratings2", "bar gratings at periods ~4.0 and ~6.6 px, orientations 11.25 + "
                 "22.5 k degrees: green glossy bars on matte magenta", objs, m)


def lowlight():
    # the curved scene through the IMX250MYR preset at +24 dB analog gain and a very short
    # exposure: few electrons per pixel, noise amplified
    s = scene("lowlight", "the curved-edge scene through the IMX250MYR preset at +24 dB gain "
              "and a short exposure (few electrons per pixel)", curved_objs(),
              mats(PAINTS, 0.25), sen=sensor("lowlight", preset="imx250myr", gain_db=24))
    return s


def highlights():
    # light paints exposed close to full scale (one or two channels of several tiles clip),
    # with glossy coloured spheres whose glints saturate every channel
    names = ("white", "yellow", "cyan", "pink", "sky", "lime", "orange", "magenta")
    m = mats(names, 0.3)
    m.update(mats(("red", "green", "blue", "white", "yellow"), 0.06, prefix="g_"))
    objs = [ground("white")]
    s = 0.11
    for j in range(5):
        for i in range(7):
            objs.append(tile((i - 3) * s, (j - 2) * s, [s, s],
                             names[(i * 3 + j * 5) % len(names)]))
    for q, (x, y, r, c) in enumerate(((-0.22, 0.05, 0.06, "g_red"), (0.0, -0.12, 0.05,
                                                                     "g_green"),
                                      (0.24, 0.10, 0.07, "g_blue"), (0.1, 0.2, 0.04,
                                                                     "g_yellow"),
                                      (-0.3, -0.2, 0.045, "g_white"))):
        objs.append({"type": "sphere", "center": [x, y, r], "radius": r, "material": c})
    return scene("highlights", "light paints near full scale (single channels clip) and "
                 "glossy coloured spheres with saturated glints", objs, m)


def aolp():
    # glossy coloured tiles tilted 40 degrees towards eight azimuths, each catching its own
    # light of a ring at 10 degrees elevation in mirror geometry: specular reflection at ~40
    # degrees incidence, polarized perpendicular to each tile's plane of incidence, so
    # neighbouring tiles differ in AoLP (and the colours' DoLP differ: the diffuse part of the
    # strong channel dilutes it)
    lights = []
    view = [0, 1.0, 6.0]
    nv = math.sqrt(sum(x * x for x in view))
    v = [x / nv for x in view]
    tilt = math.radians(40)
    names = ("red", "green", "blue", "yellow", "magenta", "cyan", "orange", "white")
    m = mats(names, 0.12)
    m["ground"] = {"n": 1.5, "k": [0.05, 0.05, 0.05], "sigma": 0.4}
    objs = [ground("ground")]
    normals = []
    for a in range(8):
        phi = 2 * math.pi * a / 8 + math.radians(10)
        n = [math.sin(tilt) * math.cos(phi), math.sin(tilt) * math.sin(phi), math.cos(tilt)]
        d = sum(x * y for x, y in zip(n, v))
        L = [2 * d * x - y for x, y in zip(n, v)]
        lights.append({"type": "directional", "direction": r4(L), "irradiance_w_m2": 200})
        normals.append(n)
    s, nx, ny = 0.12, 7, 5
    for j in range(ny):
        for i in range(nx):
            a = (i * 3 + j * 5) % 8
            n = normals[a]
            # u axis: horizontal, perpendicular to the tilt direction
            u = [-n[1], n[0], 0]
            nu = math.sqrt(u[0] ** 2 + u[1] ** 2)
            objs.append({"type": "plane",
                         "point": r4([(i - 3) * s, (j - 2) * s, 0.05]),
                         "normal": r4(n), "size": [0.15, 0.15],
                         "u_axis": r4([u[0] / nu, u[1] / nu, 0]),
                         "material": names[(i + 2 * j) % len(names)]})
    eff = dict(EFFECTS, cast_shadows=False)
    return scene("aolp", "glossy coloured tiles tilted towards eight azimuths in mirror "
                 "geometry of eight lights: strongly polarized colours with AoLP edges", objs, m,
                 lights=lights, effects=eff)


def text2():
    # the monochrome suite's glyph lines (../text.obj) at half scale, turned by -12 degrees:
    # strokes ~1.0-2.9 px, dark blue glossy ink on matte yellow paper (the inverse luminance
    # relation of the colour suite's red on cyan)
    m = {"ink": {"n": 1.5, "k": [0.05, 0.25, 1.8], "sigma": 0.04},
         "paper": {"n": 1.5, "k": [1.7, 1.5, 0.05], "sigma": 0.6}}
    objs = [ground("paper"),
            {"type": "mesh", "file": "../text.obj", "position": [0, 0.07, 0.001],
             "scale": 0.5, "rotation_deg": [0, 0, -12], "material": "ink", "smooth": False}]
    return scene("text2", "the glyph lines at half scale (strokes ~1-2.9 px), turned by -12 "
                 "degrees: blue glossy ink on matte yellow paper", objs, m)


SCENES = {"diagonal": diagonal, "curved": curved, "isolum": isolum, "primaries": primaries,
          "gratings2": gratings2, "lowlight": lowlight, "highlights": highlights, "aolp": aolp,
          "text2": text2}


cg.write_all(HERE, SCENES, lambda: {"disc.obj": disc_mesh()}, sys.argv)
