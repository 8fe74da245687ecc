#!/usr/bin/env python3
"""Writes the tenth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed10.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed10.py --print NAME` prints one scene instead.
Every generic helper is imported: ../sealed_common.py (outside the sealed directories: lofts,
ellipsoids, sweeps, boxes as facets, ribbons over surfaces, smooth patches over surfaces,
offset polylines, arcs, the materials table, the scene records with their noisy copies), which
re-exports ../colour-sealed6/sealed_lib.py (`sl`: millimetre meshes, tubes, tori, discs,
ribbons, mesh objects, boxes; read, never written) and ../colour_gen.py (`cg`: the colour
sensor, the scene record, rect, vectors, the writer). Nothing here is a copy of an earlier
generator's helper; what is below builds this set's own things (umbrellas, a wooden train and
its track, a playground, a make-up tester counter).

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). The metals (the drain gratings' cast iron, the playground's
satin steel, the gold-tone lipstick cases and glitter, the silver-tone brush ferrules and
glitter) are assumed metals of the right order (n - ik per channel at 610, 530 and 465 nm, from
memory, not a table lookup); rain water is a dielectric of index 1.33. A glossy surface mirrors
a light near Brewster's angle with a degree of polarization near 1 only where its k is small
(dark, clear or black: the puddles, the walnut floor, black acrylic; in one channel, a
saturated paint's small k there); a paint of large k reflects less polarized light. None of the
paints, meshes, cameras or layouts of the other colour sets is reused (nor a paint's or metal's
name, nor a paint's k).

Units: metres in the scenes, millimetres in the OBJ files (sl.Mesh; each mesh object has scale
0.001). A mesh placed with `smooth` false shows every facet flat; lofts, patches, tori and
sweeps share their vertices, and placed with `smooth` true the loader's area-weighted normals
round them. The set's materials are one text table (MATERIALS); each scene's record names those
its objects use.

EXPOSURE holds the exposures chosen from the simulator's own outputs (raw frame and truth:
levels, clipping, hue edges, DoLP) and nothing else: no demosaicking method had been run on
any of these scenes when they were sealed (README.md gives the sealing commit).
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in a sealed directory
sys.path.insert(0, os.path.dirname(HERE))
import sealed_common as sc  # noqa: E402 (../sealed_common.py)

sl, cg = sc.sl, sc.cg
WRITER = "gen_sealed10.py"
TITLE = "colour sealed 10: "
UP = [0, 0, 1]
X, Y = [1, 0, 0], [0, 1, 0]

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "umbrellas": 2600,
    "trainset": 3600,
    "playground": 1250,
    "makeup": 16500,
    "playground_g7": 560,
    "umbrellas_g22": 205,
}

# every material of the set (sc.materials: paints `name sigma k_R k_G k_B [n]`, n 1.5 unless
# given; metals `name sigma metal n_R n_G n_B k_R k_G k_B`); each scene's record keeps those
# its objects use
MATERIALS = sc.materials("""
# umbrellas: wet nylon canopies, coats, wet paving
nylon_scarlet          0.12   1.4   0.11  0.09
nylon_tangerine        0.12   1.5   0.52  0.05
nylon_canary           0.12   1.5   1.35  0.07
nylon_leaf             0.12   0.16  0.62  0.1
nylon_cyan             0.12   0.1   0.85  1.1
nylon_cobalt           0.12   0.07  0.18  1.05
nylon_purple           0.12   0.55  0.09  0.8
nylon_fuchsia          0.12   1.4   0.14  0.72
nylon_navy             0.12   0.05  0.06  0.33
nylon_ivory            0.12   1.55  1.5   1.38
nylon_black            0.12   0.033 0.034 0.041
coat_charcoal          0.7    0.1   0.1   0.11
coat_camel             0.7    0.86  0.58  0.34
flagstone              0.25   0.7   0.68  0.63
flag_mortar            0.5    0.2   0.2   0.2
rain_puddle            0.04   0.025 0.028 0.032  1.33
asphalt_wet            0.12   0.09  0.09  0.1
kerb_granite           0.3    0.48  0.48  0.5
double_yellow          0.15   1.5   1.12  0.06
drain_iron             0.3    metal  2.2  2.0  1.8    1.9  1.8  1.7
oilcloth               0.1    0.08  0.3   0.18
handle_wood            0.25   0.5   0.27  0.12
# trainset: painted wooden toys, a beech track, a printed felt play rug, a walnut floor
track_beech            0.3    1.3   1.0   0.62
toy_red                0.15   1.3   0.12  0.1
toy_blue               0.15   0.06  0.22  1.0
toy_yellow             0.15   1.5   1.25  0.1
toy_green              0.15   0.1   0.7   0.22
toy_orange             0.15   1.5   0.45  0.08
toy_white              0.15   1.5   1.45  1.35
toy_black              0.12   0.042 0.04  0.047
felt_meadow            0.9    0.22  0.6   0.18
felt_poppy             0.9    1.3   0.16  0.12
felt_lake              0.9    0.1   0.35  1.05
felt_mustard           0.9    1.35  1.05  0.1
felt_slate             0.9    0.42  0.44  0.46
felt_chalk             0.9    1.45  1.42  1.35
floor_walnut           0.15   0.34  0.2   0.11
nursery_wall           0.6    1.2   1.18  1.0
# playground: powder-coated steel, rubber, rope, a glossy slide, wetpour surfacing
play_red               0.2    1.35  0.14  0.1
play_yellow            0.2    1.52  1.3   0.09
play_blue              0.2    0.08  0.3   1.05
play_green             0.2    0.12  0.62  0.2
play_black             0.4    0.052 0.05  0.048
slide_teal             0.04   0.04  0.3   0.34
steel_satin            0.12   metal  2.4  2.3  2.15   3.2  3.05 2.9
wetpour_green          0.6    0.2   0.45  0.2
wetpour_azure          0.6    0.12  0.28  0.55
line_white             0.5    1.2   1.22  1.16
bark_mulch             0.7    0.5   0.3   0.16
grass_sward            0.8    0.16  0.42  0.09
privet                 0.9    0.06  0.17  0.05
# makeup: lipsticks, eyeshadows, a tester counter
lip_cherry             0.08   1.1   0.06  0.08
lip_coral              0.08   1.45  0.42  0.25
lip_fuchsia            0.08   1.25  0.1   0.55
lip_berry              0.08   0.6   0.05  0.22
lip_nude               0.08   1.3   0.72  0.5
lip_plum               0.08   0.42  0.08  0.3
shadow_teal            0.35   0.08  0.55  0.6
shadow_navy            0.35   0.06  0.09  0.42
shadow_bronze          0.35   0.85  0.42  0.16
shadow_mauve           0.35   0.8   0.45  0.7
shadow_emerald         0.35   0.07  0.5   0.2
shadow_peach           0.35   1.45  0.82  0.55
shadow_lilac           0.35   0.85  0.6   1.2
shadow_citrine         0.35   1.4   1.2   0.12
acrylic_black          0.08   0.02  0.02  0.024
bristle_sable          0.3    0.22  0.12  0.07
case_goldtone          0.06   metal  0.35 0.62 1.15   3.0  2.25 1.8
mirror_silvertone      0.02   metal  0.16 0.15 0.16   3.8  3.2  2.7
tester_counter         0.1    1.42  1.4   1.35
swatch_card            0.6    1.5   1.48  1.44
""")


def obj(prefix, name, material, smooth=False):
    return sl.mesh_object(prefix + "_" + name + ".obj", material, smooth)


def files(prefix, mesh):
    """A scene's meshes by file name: prefix + the last word of each material's name (checked
    to be distinct)."""
    out = {prefix + "_" + n.split("_")[-1]: m for n, m in mesh.items()}
    assert len(out) == len(mesh), "two materials of %s end in the same word" % prefix
    return out


def normal_at(point, u, v, du=1e-3, dv=1e-3):
    """The unit normal of a parametric surface point(u, v) from its two tangents."""
    pu = [b - a for a, b in zip(point(u - du, v), point(u + du, v))]
    pv = [b - a for a, b in zip(point(u, v - dv), point(u, v + dv))]
    return cg.unit(cg.cross(pu, pv))


# ---------------------------------------------------------------------------------------------
# umbrellas: a pedestrian street market in the rain seen from a window 10.5 m up, ~49 degrees
# down (~14 mm per pixel at the bottom of the frame, ~20 mm at the top): fourteen shoppers'
# open umbrellas of 8 or 16 gores (two colours alternating gore by gore, a rainbow, a
# patchwork, plain; one red with black dots and seams, one yellow with black pinstripe rings
# every 60 mm: ~3.5-5 px, one navy with ivory dots), so that each canopy's hue edges close in
# from 10-30 px apart at the rim to ~2 px near the centre; an umbrella seller's table of 34
# furled umbrellas in eleven hues side by side (70 mm: ~4-5 px each) with a dark strap each,
# and a market parasol; wet flagstones (0.6 m) with puddles, a granite kerb, a wet road with
# double yellow lines and two drain gratings (slots every 30 mm: ~1-2 px); an overcast sky
# from above, the bright sky low down the street (its reflection in the wet stone and puddles
# near Brewster's angle of water, 53 degrees) and a polarized sky light from the right

UMBRELLA_CAMERA = {"position": [-0.3, 0.0, 10.5], "look_at": [0.4, 9.2, 0.0], "up": UP,
                   "focal_length_mm": 2.8, "f_number": 8}
NYLONS = ("nylon_scarlet", "nylon_tangerine", "nylon_canary", "nylon_leaf", "nylon_cyan",
          "nylon_cobalt", "nylon_purple", "nylon_fuchsia", "nylon_navy", "nylon_ivory",
          "nylon_black")
RAINBOW = ("nylon_scarlet", "nylon_tangerine", "nylon_canary", "nylon_leaf", "nylon_cyan",
           "nylon_cobalt", "nylon_purple", "nylon_fuchsia")
# shoppers: position (x, y), canopy radius, gores, gore paints (in turn), pattern, coat
SHOPPERS = [
    ((-0.6, 5.6), 0.5, 16, RAINBOW, None, "coat_charcoal"),
    ((1.2, 5.2), 0.48, 8, ("nylon_navy", "nylon_ivory"), None, "coat_camel"),
    ((2.6, 6.3), 0.5, 8, ("nylon_scarlet",), "ladybird", "coat_charcoal"),
    ((-1.4, 7.4), 0.62, 16, ("nylon_leaf", "nylon_ivory"), None, "coat_camel"),
    ((0.4, 7.3), 0.5, 8, ("nylon_canary",), "pinstripe", "coat_charcoal"),
    ((2.0, 8.1), 0.47, 8, ("nylon_black",), None, "coat_camel"),
    ((-0.4, 9.2), 0.5, 8, ("nylon_scarlet", "nylon_leaf"), None, "coat_charcoal"),
    ((1.1, 9.7), 0.5, 16, ("nylon_canary", "nylon_cyan"), None, "coat_camel"),
    ((2.8, 9.8), 0.46, 8, ("nylon_navy",), "polka", "coat_charcoal"),
    ((-2.0, 10.0), 0.5, 8, ("nylon_cobalt", "nylon_tangerine"), None, "coat_camel"),
    ((0.0, 11.1), 0.5, 8, ("nylon_fuchsia", "nylon_leaf", "nylon_canary", "nylon_cobalt",
                           "nylon_tangerine", "nylon_cyan", "nylon_purple", "nylon_ivory"),
     None, "coat_charcoal"),
    ((1.9, 11.5), 0.62, 16, ("nylon_purple", "nylon_canary"), None, "coat_camel"),
    ((-1.5, 12.1), 0.5, 8, ("nylon_fuchsia", "nylon_cyan"), None, "coat_charcoal"),
    ((0.9, 12.9), 0.48, 8, ("nylon_cyan",), None, "coat_camel"),
]
UMBRELLA_MESHES = NYLONS + ("coat_charcoal", "coat_camel", "handle_wood", "flagstone",
                            "rain_puddle")


def umbrella(mesh, c, axis, radius, gores, paints, phase, pattern):
    """An open umbrella: its top at c, its shaft along -axis; gores (smooth patches, each in
    paints[k % len]) of a dome falling 0.32 radius at the rim, the fabric sagging between the
    ribs and its rim scalloped; a black tip and shaft; pattern: 'ladybird' (black dots and
    seams), 'pinstripe' (black rings every 60 mm) or 'polka' (ivory dots)."""
    a = cg.unit(axis)
    e1, e2 = sl.frame(a)

    def point(u, s, k, lift=0.0):
        phi = phase + 2 * math.pi * (k + s) / gores
        rho = radius * u * (1 - 0.06 * math.sin(math.pi * s) * u * u)
        h = 0.32 * radius * u ** 1.6 + 0.025 * radius * math.sin(math.pi * s) * u - lift
        return cg.add(cg.add(cg.add(c, e1, rho * math.cos(phi)), e2, rho * math.sin(phi)), a, -h)

    us = [0.04 + 0.96 * i / 8 for i in range(9)]
    ss = [j / 3 for j in range(4)]
    for k in range(gores):
        sc.patch(mesh[paints[k % len(paints)]], lambda u, s, k=k: point(u, s, k), us, ss)
    black = mesh["nylon_black"]
    sl.disc(black, cg.add(c, a, 0.003), a, 0.045 * radius / 0.5, 8)
    sl.tube(black, c, cg.add(c, a, 0.05), 0.005, 6)
    sl.tube(black, c, cg.add(c, a, -0.85), 0.007, 6, False)
    for k in range(gores):
        f = lambda u, s, k=k: point(u, s, k)
        if pattern == "ladybird":
            sc.surface_band(black, lambda s, u, k=k: point(u, s, k, 0.004), lambda u: 0.0,
                            lambda u: 0.05, us)
            for u, s in ((0.45, 0.5), (0.75, 0.3), (0.78, 0.72)):
                sl.disc(black, point(u, s, k, 0.005), normal_at(f, u, s), 0.045, 10)
        elif pattern == "pinstripe":
            for j in range(8):
                u0 = 0.2 + 0.12 * j
                sc.surface_band(black, lambda u, s, k=k: point(u, s, k, 0.004),
                                lambda s, u0=u0: u0, lambda s, u0=u0: u0 + 0.025, ss)
        elif pattern == "polka":
            for u, s in ((0.3, 0.5), (0.55, 0.25), (0.55, 0.75), (0.8, 0.5), (0.92, 0.15)):
                sl.disc(mesh["nylon_ivory"], point(u, s, k, 0.005), normal_at(f, u, s), 0.035,
                        10)


def shopper(mesh, x, y, coat):
    """A shopper in a coat (a loft from the ankles to the shoulders) with a dark head at
    (x, y)."""
    sc.loft(mesh[coat], [x, y, 0.0], [UP, X, Y],
            [(0.0, 0.0, 0.0), (0.02, 0.13, 0.09), (0.6, 0.19, 0.13), (1.3, 0.22, 0.13),
             (1.42, 0.13, 0.1), (1.45, 0.0, 0.0)], 12)
    sc.ellipsoid(mesh["coat_charcoal"], [x, y, 1.57], [UP, X, Y], [0.12, 0.09, 0.1], 8, 4)


def umbrellas_meshes():
    rng = random.Random(10101)
    mesh = {n: sl.Mesh("umbrellas, " + n.replace("_", " "), WRITER) for n in UMBRELLA_MESHES}
    for (x, y), r, gores, paints, pattern, coat in SHOPPERS:
        shopper(mesh, x, y, coat)
        tilt = [rng.uniform(-0.2, 0.2), rng.uniform(-0.25, 0.1), 1.0]
        c = cg.add([x, y, 1.15], cg.unit(tilt), 0.85)
        umbrella(mesh, c, tilt, r, gores, paints, rng.uniform(0, math.pi), pattern)
    # the umbrella seller's table (x -2.9..-2.1, y 5.2..7.6, 0.74 m high): 34 furled umbrellas
    # lying across it side by side (70 mm apart), eleven hues in turn, each with a dark strap
    # and a hooked wooden handle over the table's front edge
    furled = ("nylon_scarlet", "nylon_fuchsia", "nylon_purple", "nylon_cobalt", "nylon_navy",
              "nylon_cyan", "nylon_leaf", "nylon_canary", "nylon_tangerine", "nylon_ivory",
              "nylon_black")
    for k in range(34):
        y = 5.24 + 0.07 * k
        c = [-2.85, y, 0.77]
        sc.loft(mesh[furled[k % 11]], c, [X, Y, UP],
                [(0.0, 0.0, 0.0), (0.04, 0.007, 0.007), (0.5, 0.031, 0.026), (0.56, 0.02, 0.018),
                 (0.6, 0.0, 0.0)], 10)
        sc.loft(mesh["nylon_black"], c, [X, Y, UP],
                [(0.3, 0.0, 0.0), (0.3, 0.0245, 0.021), (0.32, 0.0245, 0.021), (0.32, 0.0, 0.0)],
                10)
        hook = [[-2.25, y, 0.77], [-2.16, y, 0.77], [-2.09, y, 0.74], [-2.07, y, 0.69],
                [-2.09, y, 0.64], [-2.14, y, 0.63]]
        sc.sweep(mesh["handle_wood"], hook, 0.009, 6)
    # the seller's market parasol (2.4 m, yellow and ivory) behind the table
    umbrella(mesh, [-4.0, 8.9, 2.45], UP, 1.2, 8, ("nylon_canary", "nylon_ivory"), 0.2, None)
    sl.tube(mesh["handle_wood"], [-4.0, 8.9, 0.0], [-4.0, 8.9, 1.6], 0.02, 8)
    # flagstones (0.6 m, 10 mm joints of mortar, courses staggered) and puddles
    for j in range(26):
        y0 = 3.0 + 0.6 * j
        for i in range(16):
            x0 = -6.0 + 0.6 * i + (0.3 if j % 2 else 0.0)
            xa, xb = max(x0 + 0.005, -6.0), min(x0 + 0.595, 3.4)
            if xb > xa:
                mesh["flagstone"].flat([[xa, y0 + 0.005, 0.003], [xb, y0 + 0.005, 0.003],
                                        [xb, y0 + 0.595, 0.003], [xa, y0 + 0.595, 0.003]])
    for x, y, r in ((0.3, 4.6, 0.45), (-1.4, 6.1, 0.3), (1.6, 6.6, 0.6), (-1.0, 8.6, 0.5),
                    (2.6, 8.9, 0.35), (0.8, 10.6, 0.7), (-2.8, 11.4, 0.6), (2.5, 12.8, 0.8),
                    (-0.6, 13.6, 0.9), (5.0, 9.5, 1.0), (5.4, 14.0, 1.3)):
        pts = []
        for q in range(16):
            a = 2 * math.pi * q / 16
            rr = r * rng.uniform(0.7, 1.1)
            pts.append([x + rr * math.cos(a), y + 0.8 * rr * math.sin(a), 0.006])
        mesh["rain_puddle"].flat(pts)
    # two drain gratings' slots (15 mm every 30 mm)
    for y in (7.0, 12.5):
        for k in range(15):
            ya = y + 0.03 * k
            mesh["coat_charcoal"].flat([[3.74, ya, 0.012], [4.1, ya, 0.012],
                                        [4.1, ya + 0.015, 0.012], [3.74, ya + 0.015, 0.012]])
    return files("umbrellas", mesh)


def umbrellas_parts():
    objs = [cg.ground("flag_mortar"),
            cg.rect([6.7, 12.0, 0.001], UP, X, [6.0, 30.0], "asphalt_wet"),
            sl.box([3.55, 12.0, 0.06], [0.3, 30.0, 0.12], "kerb_granite"),
            sl.box([-2.5, 6.4, 0.37], [0.8, 2.4, 0.74], "oilcloth")]
    for x in (3.9, 4.1):
        objs.append(sl.box([x + 0.05, 12.0, 0.002], [0.1, 30.0, 0.004], "double_yellow"))
    for y in (7.0, 12.5):
        objs.append(sl.box([3.92, y + 0.22, 0.005], [0.42, 0.48, 0.01], "drain_iron"))
    for n in UMBRELLA_MESHES:
        smooth = n.startswith("nylon") or n.startswith("coat")
        objs.append(obj("umbrellas", n.split("_")[-1], n, smooth))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([0.15, -0.1, 1.0])),
               "irradiance_w_m2": [55, 60, 68]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.05, 1.0, 0.84])),
               "irradiance_w_m2": [35, 37, 41]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.8, 0.3, 0.6])),
               "irradiance_w_m2": [20, 23, 28], "polarization": {"linear_deg": 70, "dop": 0.4}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# trainset: a painted wooden toy train set on a printed felt play rug, seen from a low chair
# (0.4 m up, ~21 degrees down; ~0.9 mm per pixel at the bottom of the frame, ~3.7 mm at the
# top): a beech track (40 mm wide, two grooves 6 mm wide 20 mm apart: thin dark lines, ~4-7 px,
# that curve) winding away in an S, a second track into a tunnel; an engine (red, yellow
# boiler bands, a blue cab with black windows, black wheels), a tender with coal, an open wagon
# of small coloured cargo blocks (12 mm: ~10 px, five hues), a tanker, a carriage with a row of
# dark windows (12 mm apart: ~10 px); a level crossing's red-and-white barrier arms (15 mm
# stripes), lollipop trees, peg dolls; the rug's printed road (white dashes), a river, and
# along its left side two striped border bands receding from the camera (red on green every
# 30 mm, blue on yellow every 20 mm: a period from ~15 and ~9 px where they enter the frame to
# ~2.4 and ~1.6 px at the far end); a varnished walnut floor with board joints (near the
# camera: the sky's light mirrored near Brewster's angle), a low wall under the window; the sun
# from behind the camera on the left, the sky's light through the window ahead (polarized,
# degree 0.5), a ceiling lamp

TRAIN_CAMERA = {"position": [-0.35, -0.3, 0.4], "look_at": [-0.15, 0.75, 0.0], "up": UP,
                "focal_length_mm": 2.8, "f_number": 8}
TOYS = ("toy_red", "toy_blue", "toy_yellow", "toy_green", "toy_orange", "toy_white",
        "toy_black", "track_beech")
FELTS = ("felt_poppy", "felt_lake", "felt_slate", "felt_chalk")
TRACK_TOP = 0.012


def path(*segments):
    """A track's centre line: points every ~5 mm along straights ('s', x0, y0, x1, y1) and
    arcs ('a', cx, cy, r, a0, a1 degrees), at the track's top."""
    pts = []
    for seg in segments:
        if seg[0] == "s":
            x0, y0, x1, y1 = seg[1:]
            n = max(1, int(math.hypot(x1 - x0, y1 - y0) / 0.005))
            new = [[x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n, TRACK_TOP]
                   for k in range(n + 1)]
        else:
            cx, cy, r, a0, a1 = seg[1:]
            n = max(2, int(abs(math.radians(a1 - a0)) * r / 0.005))
            new = sc.arc([cx, cy], r, a0, a1, n, TRACK_TOP)
        pts.extend(new if not pts else new[1:])
    return pts


def along(pts, dist):
    """The point dist along the polyline pts and its unit direction there."""
    for p, q in zip(pts, pts[1:]):
        d = [b - a for a, b in zip(p, q)]
        seg = math.sqrt(cg.dot(d, d))
        if dist <= seg:
            return cg.add(p, d, dist / seg), cg.unit(d)
        dist -= seg
    return pts[-1], cg.unit([b - a for a, b in zip(pts[-2], pts[-1])])


def track(mesh, pts):
    """A wooden track along pts: its top (40 mm), sides (12 mm) and two grooves."""
    left, right = sc.offset(pts, 0.02), sc.offset(pts, -0.02)
    for a, b, c, d in zip(left, left[1:], right[1:], right):
        mesh["track_beech"].flat([a, b, c, d])
    for side in (left, right):
        for a, b in zip(side, side[1:]):
            mesh["track_beech"].flat([a, b, [b[0], b[1], 0.002], [a[0], a[1], 0.002]])
    for off in (-0.01, 0.01):
        groove = [cg.add(p, UP, 0.0003) for p in sc.offset(pts, off)]
        sl.strip(mesh["toy_black"], groove, 0.006, UP)


def wagon_frame(pts, dist):
    """The frame of a wagon whose centre is dist along the track pts: (centre at the track's top,
    forward, side, up)."""
    c, f = along(pts, dist)
    return c, f, cg.unit(cg.cross(UP, f)), UP


def wheels(mesh, c, f, s, length):
    for x in (-0.3 * length, 0.3 * length):
        for side in (-1, 1):
            w = cg.add(cg.add(c, f, x), s, side * 0.02)
            w = cg.add(w, UP, 0.009)
            sc.loft(mesh["toy_black"], w, [s, f, UP], [(-0.003, 0.0, 0.0), (-0.003, 0.009, 0.009),
                                                      (0.003, 0.009, 0.009), (0.003, 0.0, 0.0)], 10)
            sl.disc(mesh["toy_yellow"], cg.add(w, s, side * 0.0032), s, 0.004, 8)
    for x in (-0.5 * length - 0.003, 0.5 * length + 0.003):  # the magnetic couplings
        sl.disc(mesh["toy_black"], cg.add(cg.add(c, f, x), UP, 0.018), f, 0.006, 8)


def box_on(mesh, c, f, s, x, z, size):
    """A box size (along, across, up) centred x along f and z above c."""
    sc.cuboid(mesh, cg.add(cg.add(c, f, x), UP, z), [f, s, UP], size)


def windows(mesh, c, f, s, xs, z, w, h, half):
    """Dark windows (w x h) on both sides of a body half wide, centred at xs along f, z up."""
    for x in xs:
        for side in (-1, 1):
            p = cg.add(cg.add(cg.add(c, f, x), s, side * (half + 0.0004)), UP, z)
            mesh.flat([cg.add(cg.add(p, f, -w / 2), UP, -h / 2), cg.add(cg.add(p, f, w / 2), UP,
                                                                      -h / 2),
                       cg.add(cg.add(p, f, w / 2), UP, h / 2), cg.add(cg.add(p, f, -w / 2), UP,
                                                                     h / 2)])


def train(mesh, pts, head, rng):
    """The engine with its front head along pts, then the tender, the open wagon, the tanker
    and the carriage behind it (towards the start of pts)."""
    c, f, s, _ = wagon_frame(pts, head - 0.055)
    wheels(mesh, c, f, s, 0.11)
    box_on(mesh["toy_red"], c, f, s, 0.0, 0.024, [0.11, 0.036, 0.012])
    sc.loft(mesh["toy_red"], cg.add(cg.add(c, f, -0.02), UP, 0.046), [f, s, UP],
            [(0.0, 0.0, 0.0), (0.0, 0.017, 0.017), (0.07, 0.017, 0.017), (0.07, 0.0, 0.0)], 16)
    for x in (0.018, 0.04):
        sc.loft(mesh["toy_yellow"], cg.add(cg.add(c, f, x), UP, 0.046), [f, s, UP],
                [(0.0, 0.0, 0.0), (0.0, 0.0175, 0.0175), (0.004, 0.0175, 0.0175),
                 (0.004, 0.0, 0.0)], 16)
    sl.disc(mesh["toy_black"], cg.add(cg.add(c, f, 0.0503), UP, 0.046), f, 0.013, 12)
    sc.loft(mesh["toy_black"], cg.add(cg.add(c, f, 0.035), UP, 0.06), [UP, f, s],
            [(0.0, 0.006, 0.006), (0.022, 0.006, 0.006), (0.026, 0.008, 0.008),
             (0.026, 0.0, 0.0)], 10)
    box_on(mesh["toy_blue"], c, f, s, -0.04, 0.05, [0.03, 0.038, 0.04])
    box_on(mesh["toy_black"], c, f, s, -0.04, 0.072, [0.04, 0.046, 0.005])
    windows(mesh["toy_black"], c, f, s, (-0.04,), 0.056, 0.016, 0.014, 0.019)
    # the tender: green, heaped with coal
    c, f, s, _ = wagon_frame(pts, head - 0.155)
    wheels(mesh, c, f, s, 0.07)
    box_on(mesh["toy_green"], c, f, s, 0.0, 0.034, [0.07, 0.036, 0.03])
    for _ in range(18):
        p = cg.add(cg.add(cg.add(c, f, rng.uniform(-0.026, 0.026)), s, rng.uniform(-0.013, 0.013)),
                   UP, 0.05)
        sc.ellipsoid(mesh["toy_black"], p, [UP, f, s], [0.004, 0.006, 0.005], 6, 3)
    # the open wagon: yellow, three rows of cargo blocks (12 mm) in four hues
    c, f, s, _ = wagon_frame(pts, head - 0.245)
    wheels(mesh, c, f, s, 0.08)
    box_on(mesh["toy_yellow"], c, f, s, 0.0, 0.03, [0.08, 0.036, 0.022])
    cargo = ("toy_red", "toy_blue", "toy_green", "toy_white", "toy_orange")
    for i in range(6):
        for j in range(3):
            sc.cuboid(mesh[cargo[(i + 2 * j) % 5]],
                      cg.add(cg.add(cg.add(c, f, -0.031 + 0.0124 * i), s, -0.0124 + 0.0124 * j),
                             UP, 0.047), [f, s, UP], [0.0118, 0.0118, 0.012])
    # the tanker: a blue tank with a white band on a black chassis
    c, f, s, _ = wagon_frame(pts, head - 0.345)
    wheels(mesh, c, f, s, 0.08)
    box_on(mesh["toy_black"], c, f, s, 0.0, 0.023, [0.08, 0.034, 0.008])
    sc.loft(mesh["toy_blue"], cg.add(cg.add(c, f, -0.035), UP, 0.044), [f, s, UP],
            [(0.0, 0.0, 0.0), (0.0, 0.016, 0.016), (0.07, 0.016, 0.016), (0.07, 0.0, 0.0)], 16)
    sc.loft(mesh["toy_white"], cg.add(cg.add(c, f, -0.004), UP, 0.044), [f, s, UP],
            [(0.0, 0.0, 0.0), (0.0, 0.0165, 0.0165), (0.008, 0.0165, 0.0165), (0.008, 0.0, 0.0)],
            16)
    # the carriage: orange, a blue roof, six dark windows a side 12 mm apart
    c, f, s, _ = wagon_frame(pts, head - 0.45)
    wheels(mesh, c, f, s, 0.09)
    box_on(mesh["toy_orange"], c, f, s, 0.0, 0.04, [0.09, 0.036, 0.04])
    box_on(mesh["toy_blue"], c, f, s, 0.0, 0.063, [0.094, 0.042, 0.006])
    windows(mesh["toy_black"], c, f, s, [-0.03 + 0.012 * k for k in range(6)], 0.047, 0.008,
            0.012, 0.018)


PEGS = [(-0.235, 0.62), (-0.215, 0.665), (-0.235, 0.71), (-0.215, 0.755), (-0.235, 0.8)]


def trainset_meshes():
    rng = random.Random(10203)
    mesh = {n: sl.Mesh("trainset, " + n.replace("_", " "), WRITER) for n in TOYS + FELTS}
    # track A: from the bottom of the frame straight away, a left curve, a right curve, away
    a = path(("s", -0.15, 0.2, -0.15, 0.4), ("a", 0.0, 0.4, 0.15, 180.0, 90.0),
             ("a", 0.0, 0.7, 0.15, 270.0, 360.0), ("s", 0.15, 0.7, 0.15, 2.2))
    track(mesh, a)
    # track B: along the left, into a tunnel
    b = path(("s", -0.3, 0.25, -0.3, 2.2))
    track(mesh, b)
    train(mesh, a, 0.62, rng)
    # the tunnel: a green half-cylinder shell (radius 70 mm) over track B, y 1.1-1.35
    sc.patch(mesh["toy_green"], lambda u, v: [-0.3 + 0.07 * math.cos(math.pi * v), 1.1 + 0.25 * u,
                                              0.07 * math.sin(math.pi * v)],
             [0.0, 1.0], [k / 12 for k in range(13)])
    # a level crossing over track A's far straight (y 1.2): posts and two barrier arms of 15 mm
    # red and white segments
    for side in (-1, 1):
        x0 = 0.15 + side * 0.045
        sc.cuboid(mesh["toy_white"], [x0, 1.2 - side * 0.04, 0.03], [X, Y, UP],
                  [0.012, 0.012, 0.06])
        for k in range(8):
            sc.cuboid(mesh["toy_red" if k % 2 == 0 else "toy_white"],
                      [x0 - side * (0.0075 + 0.015 * k), 1.2 - side * 0.04, 0.052], [X, Y, UP],
                      [0.015, 0.006, 0.006])
    # peg dolls between the tracks (x -0.24..-0.22, y 0.62..0.8)
    for k, colour in enumerate(("toy_red", "toy_blue", "toy_yellow", "toy_green", "toy_orange")):
        x, y = PEGS[k]
        sc.loft(mesh[colour], [x, y, 0.0], [UP, X, Y],
                [(0.0, 0.0, 0.0), (0.0, 0.009, 0.009), (0.035, 0.008, 0.008),
                 (0.038, 0.0, 0.0)], 10)
    # the rug's print: a road with white dashes, a river, the striped border bands on the left
    road = [[p[0], p[1], 0.0022] for p in sc.arc([-0.1, 2.0], 0.95, 235.0, 300.0, 60)]
    sl.strip(mesh["felt_slate"], road, 0.06, UP)
    for k in range(0, len(road) - 3, 5):
        sl.strip(mesh["felt_chalk"], [cg.add(p, UP, 0.0002) for p in road[k:k + 3]], 0.003, UP)
    river = [[0.02 - 0.01 * k, 1.45 + 0.04 * math.sin(k / 5.0), 0.0022] for k in range(37)]
    sl.strip(mesh["felt_lake"], river, 0.07, UP)
    for k in range(44):
        y = 0.45 + 0.03 * k
        mesh["felt_poppy"].flat([[-0.5, y, 0.0024], [-0.44, y, 0.0024], [-0.44, y + 0.015, 0.0024],
                                 [-0.5, y + 0.015, 0.0024]])
    for k in range(66):
        y = 0.45 + 0.02 * k
        mesh["felt_lake"].flat([[-0.43, y, 0.0024], [-0.37, y, 0.0024], [-0.37, y + 0.01, 0.0024],
                                [-0.43, y + 0.01, 0.0024]])
    # the oak floor's board joints (boards 120 mm wide along y, ends staggered)
    for k in range(20):
        x = -1.2 + 0.12 * k
        sl.strip(mesh["toy_black"], [[x, -0.5, 0.0004], [x, 2.7, 0.0004]], 0.002, UP)
        for j in range(3):
            y = 0.2 + 0.9 * j + 0.37 * (k % 3)
            sl.strip(mesh["toy_black"], [[x, y, 0.0004], [x + 0.12, y, 0.0004]], 0.002, UP)
    return files("trainset", mesh)


def trainset_parts():
    objs = [cg.ground("floor_walnut"),
            cg.rect([-0.24, 1.105, 0.0015], UP, X, [0.52, 1.31], "felt_meadow"),
            cg.rect([-0.4, 1.105, 0.002], UP, X, [0.06, 1.31], "felt_mustard"),
            cg.rect([0.0, 2.7, 0.45], [0, -1, 0], X, [4.0, 0.9], "nursery_wall"),
            sl.box([0.0, 2.69, 0.05], [4.0, 0.02, 0.1], "toy_white")]
    for x, y in ((-0.05, 1.0), (0.4, 1.4), (-0.15, 1.65), (0.0, 1.95)):
        objs.append(sl.box([x, y, 0.03], [0.01, 0.01, 0.06], "track_beech"))
        objs.append(sl.sphere([x, y, 0.085], 0.03, "toy_green"))
    for x, y in PEGS:  # the peg dolls' heads
        objs.append(sl.sphere([x, y, 0.046], 0.009, "track_beech"))
    for n in TOYS + FELTS:
        smooth = n not in ("track_beech",) and not n.startswith("felt")
        objs.append(obj("trainset", n.split("_")[-1], n, smooth))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.55, -0.35, 0.6])),
               "irradiance_w_m2": [250, 240, 220]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.15, 1.0, 0.67])),
               "irradiance_w_m2": [11, 12, 14.5], "polarization": {"linear_deg": 20, "dop": 0.5}},
              {"type": "point", "position": [0.2, 0.4, 2.3], "intensity_w_sr": [60, 52, 40]}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# playground: a children's playground on a sunny afternoon seen by a parent at its edge (1.6 m
# up, ~7 degrees down; ~5.5 mm per pixel at the bottom of the frame): a picket fence of
# palings (80 mm wide every 120 mm, painted red, yellow, green and blue in turn) running
# diagonally away across the frame, so that the hue changes every ~10 px where it enters the
# frame and every ~1.1 px at its far end; a play tower (blue posts, a red pyramid roof) with a
# glossy teal slide, a climbing wall with holds and a black rope net (cells of 200 mm: ~5 px,
# ropes ~1.3 px), a swing frame with two seats, a roundabout of eight red and yellow segments
# with steel handles, a ladybird spring rider (red with black spots) on a bed of wood chips
# (20-45 mm: ~3-7 px), a blue path with a white hopscotch; green wetpour surfacing, a lawn, a
# privet hedge behind the fence, the sky (background); the sun from behind on the right, the
# sky's light from above in front (polarized, degree 0.5)

PLAY_CAMERA = {"position": [0.3, -3.0, 1.6], "look_at": [1.2, 7.0, 0.3], "up": UP,
               "focal_length_mm": 2.6, "f_number": 8}
PLAY_MESHES = ("play_red", "play_yellow", "play_blue", "play_green", "play_black", "slide_teal",
               "steel_satin", "wetpour_azure", "line_white", "bark_mulch")
FENCE = ([-2.6, 1.0], [7.0, 17.0])
TOWER = [3.9, 8.6]  # the play tower's centre; platform 1.2 m square, 1.0 m up


def playground_meshes():
    rng = random.Random(10307)
    mesh = {n: sl.Mesh("playground, " + n.replace("_", " "), WRITER) for n in PLAY_MESHES}
    # the picket fence: palings (pointed, 0.9 m) every 120 mm in four colours, two rails behind
    (x0, y0), (x1, y1) = FENCE
    length = math.hypot(x1 - x0, y1 - y0)
    d = [(x1 - x0) / length, (y1 - y0) / length, 0.0]
    n = [d[1], -d[0], 0.0]  # towards the playground
    paints = ("play_red", "play_yellow", "play_green", "play_blue")
    for k in range(int(length / 0.12)):
        a = cg.add([x0, y0, 0.0], d, 0.12 * k)
        b = cg.add(a, d, 0.08)
        m = cg.add(a, d, 0.04)
        mesh[paints[k % 4]].flat([a, b, cg.add(b, UP, 0.84), cg.add(m, UP, 0.92),
                                  cg.add(a, UP, 0.84)])
    for h in (0.2, 0.7):
        sc.cuboid(mesh["play_green"], cg.add(cg.add([x0, y0, h], d, length / 2), n, -0.03),
                  [d, n, UP], [length, 0.02, 0.08])
    # the play tower: four posts, a platform, a pyramid roof; a slide and a rope net
    tx, ty = TOWER
    for sx in (-1, 1):
        for sy in (-1, 1):
            sc.cuboid(mesh["play_blue"], [tx + 0.6 * sx, ty + 0.6 * sy, 1.0], [X, Y, UP],
                      [0.08, 0.08, 2.0])
    sc.cuboid(mesh["play_green"], [tx, ty, 0.98], [X, Y, UP], [1.3, 1.3, 0.04])
    apex = [tx, ty, 2.45]
    corners = [[tx - 0.75, ty - 0.75, 1.95], [tx + 0.75, ty - 0.75, 1.95],
               [tx + 0.75, ty + 0.75, 1.95], [tx - 0.75, ty + 0.75, 1.95]]
    for a, b in zip(corners, corners[1:] + corners[:1]):
        mesh["play_red"].flat([a, b, apex])
    # the slide: a chute from the platform's front edge, curving down towards the camera's left
    def chute(u, v):
        t = u
        cx = tx - 0.3 - 1.1 * t - 0.25 * math.sin(math.pi * t)
        cy = ty - 0.65 - 1.6 * t
        cz = 1.0 - 0.8 * (3 * t * t - 2 * t ** 3) + 0.05
        w = (v - 0.5) * 0.5
        return [cx + 0.85 * w, cy - 0.45 * w, cz + 0.6 * (2 * abs(v - 0.5)) ** 3 * 0.25]
    sc.patch(mesh["slide_teal"], chute, [k / 16 for k in range(17)], [k / 8 for k in range(9)])
    # the rope net down the tower's left side: ropes every 200 mm both ways, sagging
    def net(u, v):
        return [tx + 0.65 + 0.9 * v - 0.08 * math.sin(math.pi * u) * math.sin(math.pi * v),
                ty - 0.6 + 1.2 * u, 1.0 - 1.0 * v]
    for k in range(7):
        sc.sweep(mesh["play_black"], [net(k / 6, j / 8) for j in range(9)], 0.01, 5)
    for j in range(1, 8):
        sc.sweep(mesh["play_black"], [net(k / 12, j / 7) for k in range(13)], 0.01, 5)
    # a climbing wall on the tower's front (yellow, 1.2 x 0.95 m) with 24 holds in three colours
    sc.cuboid(mesh["play_yellow"], [tx + 0.15, ty - 0.63, 0.5], [X, Y, UP], [0.9, 0.03, 0.95])
    for k in range(24):
        h = [tx - 0.25 + 0.8 * rng.random(), ty - 0.65, 0.08 + 0.82 * rng.random()]
        sc.ellipsoid(mesh[("play_red", "play_blue", "play_green")[k % 3]], h, [Y, X, UP],
                     [0.025, rng.uniform(0.03, 0.05), rng.uniform(0.025, 0.04)], 8, 4)
    # the swing frame (green tubes, an A at each end) and two seats on ropes
    for x in (0.9, 2.7):
        for dy in (-0.5, 0.5):
            sc.sweep(mesh["play_green"], [[x, 5.4 + dy, 0.0], [x, 5.4, 2.0]], 0.04, 8)
    sc.sweep(mesh["play_green"], [[0.85, 5.4, 2.0], [2.75, 5.4, 2.0]], 0.04, 8)
    for x, swing in ((1.45, 0.15), (2.15, -0.1)):
        seat = [x, 5.4 + swing, 0.45]
        for dx in (-0.2, 0.2):
            sc.sweep(mesh["play_black"], [[x + dx, 5.4, 2.0], [x + dx, seat[1], 0.47]], 0.008, 4)
        sc.cuboid(mesh["play_black"], seat, [X, Y, UP], [0.44, 0.16, 0.03])
    # the roundabout: a disc of eight segments, red and yellow, a steel post and handles
    rc = [1.6, 3.0]
    for k in range(8):
        pts = [[rc[0], rc[1], 0.25]] + [[p[0], p[1], 0.25] for p in
                                        sc.arc(rc, 0.8, 45 * k + 10, 45 * k + 55, 6)]
        mesh["play_red" if k % 2 == 0 else "play_yellow"].flat(pts)
    sc.loft(mesh["play_yellow"], [rc[0], rc[1], 0.0], [UP, X, Y],
            [(0.0, 0.8, 0.8), (0.249, 0.8, 0.8), (0.249, 0.0, 0.0)], 48)
    sl.tube(mesh["steel_satin"], [rc[0], rc[1], 0.25], [rc[0], rc[1], 0.9], 0.03, 10)
    for k in range(4):
        a = math.radians(45 * k + 32)
        out = [rc[0] + 0.7 * math.cos(a), rc[1] + 0.7 * math.sin(a)]
        sc.sweep(mesh["steel_satin"], [[out[0], out[1], 0.25], [out[0], out[1], 0.75],
                                       [rc[0] + 0.05 * math.cos(a), rc[1] + 0.05 * math.sin(a),
                                        0.85]], 0.016, 6)
    # the ladybird spring rider: a red shell with black spots and head on a spring
    lb = [-0.9, 2.6, 0.55]
    sc.ellipsoid(mesh["play_red"], lb, [X, Y, UP], [0.36, 0.24, 0.2], 16, 8)
    sc.ellipsoid(mesh["play_black"], [lb[0] + 0.34, lb[1], lb[2] + 0.02], [X, Y, UP],
                 [0.1, 0.12, 0.1], 10, 5)
    for u, v in ((0.0, 0.0), (0.6, 0.7), (-0.6, 0.7), (2.5, 0.8), (-2.5, 0.8), (1.6, 1.0),
                 (-1.6, 1.0), (3.14, 0.5)):
        p = [lb[0] + 0.36 * math.cos(u) * math.sin(v) * 1.01,
             lb[1] + 0.24 * math.sin(u) * math.sin(v) * 1.01, lb[2] + 0.2 * math.cos(v) * 1.01]
        nrm = cg.unit([(p[0] - lb[0]) / 0.36 ** 2, (p[1] - lb[1]) / 0.24 ** 2,
                       (p[2] - lb[2]) / 0.2 ** 2])
        sl.disc(mesh["play_black"], p, nrm, 0.045, 10)
    coil = [[lb[0] + 0.07 * math.cos(q), lb[1] + 0.07 * math.sin(q), 0.35 * q / (12 * math.pi)]
            for q in [math.pi * j / 6 for j in range(73)]]
    sc.sweep(mesh["play_green"], coil, 0.012, 5)
    # the blue path from the near left to the tower, a white hopscotch on it
    path_pts = [[-0.6 + 3.0 * t + 0.5 * math.sin(math.pi * t), 0.8 + 5.4 * t, 0.004]
                for t in [k / 30 for k in range(31)]]
    sl.strip(mesh["wetpour_azure"], path_pts, 0.9, UP)
    for k in range(8):
        c, f = along(path_pts, 0.6 + 0.45 * k)
        side = cg.cross(UP, f)
        cells = [0.0] if k % 3 == 2 else [-0.19, 0.19]
        for off in cells:
            q = cg.add(cg.add(c, side, off), UP, 0.002)
            corners = [cg.add(cg.add(q, f, sf * 0.18), side, ss * 0.18)
                       for sf, ss in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
            sl.strip(mesh["line_white"], corners + corners[:1], 0.035, UP)
    # a bed of wood chips round the spring rider, between the fence and the path (flat irregular
    # pieces of 20-45 mm, tilted at random)
    n_chips = 0
    while n_chips < 2400:
        c = [rng.uniform(-2.0, 0.4), rng.uniform(1.0, 3.6), rng.uniform(0.004, 0.02)]
        t = (c[1] - 0.8) / 5.4
        if (c[0] - x0) * n[0] + (c[1] - y0) * n[1] < 0.15 or \
                c[0] > -0.6 + 3.0 * t + 0.5 * math.sin(math.pi * t) - 0.5:
            continue
        n_chips += 1
        a, e = rng.uniform(0, math.pi), rng.uniform(0.01, 0.022)
        d, w = [math.cos(a), math.sin(a), rng.uniform(-0.3, 0.3)], [-math.sin(a), math.cos(a),
                                                                    rng.uniform(-0.3, 0.3)]
        mesh["bark_mulch"].flat([cg.add(c, d, e), cg.add(c, w, 0.5 * e), cg.add(c, d, -0.8 * e),
                                 cg.add(c, w, -0.6 * e)])
    return files("playground", mesh)


def playground_parts():
    (x0, y0), (x1, y1) = FENCE
    length = math.hypot(x1 - x0, y1 - y0)
    d = [(x1 - x0) / length, (y1 - y0) / length, 0.0]
    n = [d[1], -d[0], 0.0]
    mid = cg.add([x0, y0, 0.0], d, length / 2)
    objs = [cg.ground("grass_sward"),
            cg.rect(cg.add(mid, n, 6.0), UP, d, [length + 8.0, 12.0], "wetpour_green"),
            sl.box(cg.add(cg.add(mid, n, -1.5), UP, 0.8), [length + 8.0, 0.9, 1.6],
                   "privet", math.degrees(math.atan2(d[1], d[0])))]
    objs[2]["center"][2] = 0.8
    for nm in PLAY_MESHES:
        objs.append(obj("playground", nm.split("_")[-1], nm, nm in ("slide_teal", "play_black",
                                                                    "play_red")))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([0.5, -0.6, 0.6])),
               "irradiance_w_m2": [620, 600, 560]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.1, 0.9, 0.45])),
               "irradiance_w_m2": [90, 105, 140], "polarization": {"linear_deg": 0, "dop": 0.5}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# makeup: a cosmetics counter's tester display seen from 0.6 m, ~45 degrees down (~0.53 mm per
# pixel at the bottom of the frame, ~0.7 mm at the top): on a white gloss counter, a black
# acrylic stand of ten lipsticks (gold-tone cases, six shades: cherry, coral, fuchsia, berry,
# nude, plum) before a black acrylic tray (the light box behind it mirrored near Brewster's
# angle), an eyeshadow palette of sixteen pans (16 mm, black dividers of 2.5 mm: ~4 px, thin
# dark bars between saturated pans), a striped highlighter of nine stripes 2.5 mm wide (~4 px:
# colour-only detail), a pot of gold- and silver-tone glitter flakes, a pouch of fuchsia and
# teal sequins (2.8 mm apart: ~5 px, in bands four wide), four bottles of nail varnish with
# ribbed black caps (ribs every 2.7 mm: ~4.5 px), a card of lipstick swatches side by side
# (3.2 mm: ~6 px), two brushes (black handles, silver-tone ferrules, sable tufts); two
# spotlights in front, a light box behind (low), the shop's light from above (polarized 0.3)

MAKEUP_CAMERA = {"position": [0.0, -0.34, 0.42], "look_at": [0.0, 0.075, 0.0], "up": UP,
                 "focal_length_mm": 3.2, "f_number": 8}
LIPS = ("lip_cherry", "lip_coral", "lip_fuchsia", "lip_berry", "lip_nude", "lip_plum")
SHADOWS = ("shadow_teal", "shadow_navy", "shadow_bronze", "shadow_mauve", "shadow_emerald",
           "shadow_peach", "shadow_lilac", "shadow_citrine")
MAKEUP_MESHES = LIPS + SHADOWS + ("acrylic_black", "bristle_sable", "case_goldtone",
                                  "mirror_silvertone")
SPOTS = ([-0.15, -0.28, 0.6], [0.2, -0.12, 0.55])


def makeup_meshes():
    rng = random.Random(10409)
    mesh = {n: sl.Mesh("makeup, " + n.replace("_", " "), WRITER) for n in MAKEUP_MESHES}
    # ten lipsticks standing in the stand (its top at 25 mm), bullets cut at 45 degrees
    for k in range(10):
        c = [-0.108 + 0.024 * k, 0.165, 0.025]
        sc.loft(mesh["case_goldtone"], c, [UP, X, Y],
                [(0.0, 0.0085, 0.0085), (0.03, 0.0085, 0.0085), (0.03, 0.0, 0.0)], 20)
        shade = mesh[LIPS[k % 6]]
        angles = [2 * math.pi * j / 16 for j in range(16)]
        ring = [[c[0] + 0.0065 * math.cos(a), c[1] + 0.0065 * math.sin(a), c[2] + 0.03]
                for a in angles]
        cap = [[p[0], p[1], c[2] + 0.048 + 0.0065 * math.sin(a)] for p, a in zip(ring, angles)]
        lo = [shade.vert(p) for p in ring]
        hi = [shade.vert(p) for p in cap]
        sc.join_rings(shade, [lo, hi])
        shade.face(hi)
    # the eyeshadow palette: 4 x 4 pans of 16 mm in a black case, dividers 2.5 mm
    for i in range(4):
        for j in range(4):
            x, y = -0.112 + 0.0185 * i, 0.008 + 0.0185 * j
            mesh[SHADOWS[(i + 3 * j) % 8]].flat([[x, y, 0.0085], [x + 0.016, y, 0.0085],
                                                 [x + 0.016, y + 0.016, 0.0085],
                                                 [x, y + 0.016, 0.0085]])
    # the striped highlighter: nine stripes of 2.5 mm along y, 40 mm long
    stripes = ("lip_cherry", "lip_coral", "shadow_citrine", "shadow_emerald", "shadow_teal",
               "shadow_navy", "shadow_lilac", "lip_fuchsia", "shadow_peach")
    for k, shade in enumerate(stripes):
        x = 0.0 + 0.0025 * k
        mesh[shade].flat([[x, 0.02, 0.0065], [x + 0.0025, 0.02, 0.0065],
                          [x + 0.0025, 0.06, 0.0065], [x, 0.06, 0.0065]])
    # the glitter pot: flakes (1-1.5 mm) of gold and silver tone at random tilts
    for _ in range(160):
        a, r = rng.uniform(0, 2 * math.pi), 0.0135 * math.sqrt(rng.random())
        c = [0.047 + r * math.cos(a), 0.08 + r * math.sin(a), 0.0125]
        sl.disc(mesh[rng.choice(("case_goldtone", "mirror_silvertone"))], c,
                cg.unit([rng.gauss(0, 0.5), rng.gauss(0, 0.5), 1.0]), rng.uniform(0.0006, 0.0009),
                3, rng.uniform(0, 2))
    sc.loft(mesh["acrylic_black"], [0.047, 0.08, 0.0], [UP, X, Y],
            [(0.0, 0.0, 0.0), (0.0, 0.016, 0.016), (0.012, 0.016, 0.016), (0.012, 0.0145, 0.0145),
             (0.0122, 0.0, 0.0)], 24)
    # four nail varnish bottles with ribbed black caps (32 ribs)
    for k, shade in enumerate(("lip_cherry", "shadow_teal", "lip_fuchsia", "shadow_lilac")):
        c = [0.09 + 0.027 * (k % 2), 0.055 + 0.03 * (k // 2) + 0.008 * (k % 2), 0.0]
        sc.loft(mesh[shade], c, [UP, X, Y],
                [(0.0, 0.0, 0.0), (0.0, 0.011, 0.009), (0.026, 0.011, 0.009),
                 (0.03, 0.006, 0.005), (0.031, 0.0, 0.0)], 8, math.pi / 8)
        ribs = [[1.0 if q % 2 == 0 else 0.86 for q in range(32)]] * 2
        sc.loft(mesh["acrylic_black"], cg.add(c, UP, 0.03), [UP, X, Y],
                [(0.0, 0.007, 0.007), (0.022, 0.007, 0.007)], 32, 0.0, ribs)
        sl.disc(mesh["acrylic_black"], cg.add(c, UP, 0.052), UP, 0.0062, 16)
    # a card of lipstick swatches: ten strokes of 3.2 mm side by side, 40 mm long
    for k in range(10):
        x = 0.04 + 0.0032 * k
        y0 = -0.062 + 0.002 * math.sin(k)
        pts = [[x, y0, 0.0012], [x + 0.0032, y0 + 0.001, 0.0012], [x + 0.0032, y0 + 0.04, 0.0012],
               [x + 0.0016, y0 + 0.042, 0.0012], [x, y0 + 0.04, 0.0012]]
        mesh[LIPS[(k * 5) % 6]].flat(pts)
    # a sequined pouch: 3 mm sequins in staggered rows (2.2 mm apart), diagonal bands of fuchsia
    # and teal four sequins wide, each tilted a little at random
    for j in range(24):
        for i in range(14):
            x = 0.09 + 0.0028 * i + (0.0014 if j % 2 else 0.0)
            y = -0.074 + 0.0022 * j
            shade = ("lip_fuchsia", "shadow_teal")[((i + j // 2) // 4) % 2]
            sl.disc(mesh[shade], [x, y, 0.0105 + 0.0001 * j],
                    cg.unit([rng.gauss(0, 0.12), -0.25 + rng.gauss(0, 0.12), 1.0]), 0.0015, 10)
    # two brushes lying diagonally: black handles, silver-tone ferrules, sable tufts
    for (x, y, ang, tuft) in ((-0.12, -0.065, 14, 0.009), (-0.115, -0.035, 5, 0.006)):
        d = [math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0.0]
        c = [x, y, 0.005]
        sc.loft(mesh["acrylic_black"], c, [d, cg.cross(UP, d), UP],
                [(0.0, 0.0, 0.0), (0.0, 0.003, 0.003), (0.06, 0.0045, 0.0045),
                 (0.07, 0.0045, 0.0045), (0.07, 0.0, 0.0)], 10)
        sc.loft(mesh["mirror_silvertone"], c, [d, cg.cross(UP, d), UP],
                [(0.07, 0.0, 0.0), (0.07, 0.0048, 0.0048), (0.088, 0.0052, 0.0052),
                 (0.088, 0.0, 0.0)], 12)
        sc.loft(mesh["bristle_sable"], c, [d, cg.cross(UP, d), UP],
                [(0.088, 0.0, 0.0), (0.088, 0.005, 0.005), (0.1, tuft, 0.006),
                 (0.112, 0.6 * tuft, 0.004), (0.118, 0.0, 0.0)], 12)
    return files("makeup", mesh)


def makeup_parts():
    objs = [cg.ground("tester_counter"),
            sl.box([0.0, 0.24, 0.002], [0.4, 0.12, 0.004], "acrylic_black"),
            sl.box([0.0, 0.165, 0.0125], [0.26, 0.03, 0.025], "acrylic_black"),
            sl.box([-0.075, 0.044, 0.004], [0.082, 0.082, 0.008], "acrylic_black"),
            sl.box([0.011, 0.04, 0.003], [0.03, 0.048, 0.006], "acrylic_black"),
            sl.box([0.057, -0.04, 0.0005], [0.052, 0.058, 0.001], "swatch_card"),
            sl.box([0.109, -0.048, 0.005], [0.044, 0.058, 0.01], "shadow_navy")]
    for n in MAKEUP_MESHES:
        objs.append(obj("makeup", n.split("_")[-1], n, n not in SHADOWS))
    lights = [{"type": "point", "position": SPOTS[0], "intensity_w_sr": [5.0, 4.7, 4.2]},
              {"type": "point", "position": SPOTS[1], "intensity_w_sr": [4.0, 3.8, 3.4]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.0, 1.0, 0.65])),
               "irradiance_w_m2": [3.5, 3.5, 3.7]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.2, 0.1, 1.0])),
               "irradiance_w_m2": [5, 5, 5.5], "polarization": {"linear_deg": 45, "dop": 0.3}}]
    return MATERIALS, objs, lights


SCENES = sc.scene_set(TITLE, EXPOSURE, {
    "umbrellas": (umbrellas_parts, UMBRELLA_CAMERA, "a street market in the rain from a "
                  "third-floor window (shoppers' open umbrellas of 8 and 16 gores, an umbrella "
                  "seller's table of furled umbrellas, a market parasol, wet flagstones with "
                  "puddles, a kerb, a wet road with double yellow lines, drain gratings)", None),
    "trainset": (trainset_parts, TRAIN_CAMERA, "a painted wooden toy train set on a printed "
                 "felt play rug (a beech track in an S and into a tunnel, an engine, a tender, "
                 "an open wagon of cargo blocks, a tanker, a carriage, a level crossing, trees, "
                 "peg dolls, a platform; the rug's road, river and striped borders), an oak "
                 "floor", None),
    "playground": (playground_parts, PLAY_CAMERA, "a children's playground on a sunny "
                   "afternoon (a picket fence of red, yellow, green and blue palings, a play "
                   "tower with a slide and a rope net, swings, a roundabout, a ladybird spring "
                   "rider, a climbing wall, wood chips, a blue path with a hopscotch, wetpour "
                   "surfacing, a lawn, a hedge)",
                   [22, 30, 48]),
    "makeup": (makeup_parts, MAKEUP_CAMERA, "a cosmetics counter's tester display (lipsticks "
               "in a black acrylic stand, an eyeshadow palette, a striped highlighter, a pot of "
               "glitter, a sequined pouch, nail varnish bottles with ribbed caps, a card of "
               "lipstick swatches, brushes) on a white gloss counter", None),
}, {
    "playground_g7": ("playground", 7, "a fast shutter for running children"),
    "umbrellas_g22": ("umbrellas", 22, "a dull day in the rain, handheld"),
})


def meshes():
    """Every mesh of the set: file name -> OBJ text (each *_meshes gives name -> sl.Mesh)."""
    makers = (umbrellas_meshes, trainset_meshes, playground_meshes, makeup_meshes)
    return {name + ".obj": mesh.text() for make in makers for name, mesh in make().items()}


cg.write_all(HERE, SCENES, meshes, sys.argv)
