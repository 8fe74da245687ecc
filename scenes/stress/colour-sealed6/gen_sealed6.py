#!/usr/bin/env python3
"""Writes the sixth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed6.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed6.py --print NAME` prints one scene instead.
The generic helpers (millimetre meshes, prisms, tori, lathes, ribbons, materials) are
sealed_lib.py beside this file; the colour sensor, the scene record, rect and the writer are
../colour_gen.py's.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). "Stainless steel" and "chromium" are assumed grey metals of the
right order (n - ik per channel at 610, 530 and 465 nm, from memory, not a table lookup); no
metal of the other sets is reused. None of the paints, meshes, cameras or layouts of the other
colour sets is reused.

Meshes are written in millimetres (placed with scale 0.001). Flat-faced meshes (`smooth` false)
give each facet its own vertices; the smooth ones (kettle, pots, handles, tyres, cable coil)
share vertices so that the loader's area-weighted vertex normals are smooth.

The exposures (EXPOSURE) were set by looking at the rendered raw frames and truth only
(brightness, clipping, hue-edge density, DoLP), before any demosaicking method was run on these
scenes; README.md records the commit that sealed them.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # no __pycache__ in the sealed directory
import sealed_lib as sl  # noqa: E402 (sealed_lib.py beside this file)

cg = sl.cg
WRITER = "gen_sealed6.py"
UP = [0, 0, 1]

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # kitchen: a butcher-block counter before a backsplash of small glazed tiles
    "tile_white": [1.62, 1.62, 1.6], "tile_sage": [0.55, 0.8, 0.6], "tile_grey": [0.9, 0.92, 0.95],
    "grout": [0.42, 0.4, 0.37], "beech_a": [1.35, 0.95, 0.6], "beech_b": [1.2, 0.82, 0.5],
    "beech_c": [1.45, 1.05, 0.68], "grain": [0.7, 0.45, 0.25], "enamel_red": [1.25, 0.08, 0.07],
    "bottle_glass": [0.03, 0.08, 0.03], "tomato": [1.3, 0.1, 0.05], "lemon": [1.7, 1.45, 0.1],
    "parsley": [0.1, 0.5, 0.08], "towel": [1.55, 1.5, 1.35], "towel_stripe": [0.08, 0.2, 0.8],
    "crock": [0.55, 0.95, 1.65], "spoon_wood": [1.1, 0.7, 0.35], "knob_black": [0.05, 0.05, 0.05],
    "cabinet": [0.35, 0.5, 0.55], "board": [1.5, 1.15, 0.8], "handle_black": [0.06, 0.06, 0.07],
    # workshop: a pegboard of hand tools over a plywood bench
    "hardboard": [1.15, 0.72, 0.42], "hole": [0.02, 0.018, 0.015], "ply_a": [1.4, 1.1, 0.72],
    "ply_b": [1.25, 0.95, 0.6], "ply_grain": [0.85, 0.6, 0.35], "grip_red": [1.3, 0.07, 0.06],
    "grip_yellow": [1.7, 1.3, 0.05], "grip_blue": [0.05, 0.2, 1.1], "grip_green": [0.08, 0.8, 0.2],
    "grip_black": [0.07, 0.07, 0.08], "cable_orange": [1.7, 0.5, 0.03],
    "tape_yellow": [1.75, 1.4, 0.04], "drawer": [0.2, 0.35, 0.75], "label": [1.65, 1.65, 1.6],
    "ink": [0.05, 0.05, 0.06], "toolbox_red": [1.4, 0.12, 0.08], "saw_handle": [0.9, 0.4, 0.15],
    "sandpaper": [1.2, 0.85, 0.45],
    # bicycle: a town bicycle against a brick wall in a back yard
    "brick_red": [1.05, 0.32, 0.2], "brick_dark": [0.7, 0.22, 0.15], "brick_buff": [1.25, 0.8, 0.5],
    "brick_plum": [0.6, 0.28, 0.28], "mortar": [1.1, 1.05, 0.95], "slab_a": [0.85, 0.83, 0.8],
    "slab_b": [0.75, 0.74, 0.72], "slab_joint": [0.3, 0.3, 0.3], "frame_teal": [0.05, 0.75, 0.7],
    "tyre": [0.05, 0.05, 0.05], "saddle": [0.45, 0.22, 0.1], "door_green": [0.1, 0.45, 0.2],
    "sill": [1.4, 1.4, 1.35], "pane": [0.03, 0.03, 0.035], "basket": [0.85, 0.6, 0.3],
    "pot_terracotta": [1.2, 0.5, 0.28], "geranium": [1.5, 0.08, 0.2], "leaf": [0.12, 0.55, 0.1],
    "bin_blue": [0.05, 0.25, 0.9],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "steel": {"n": [2.75, 2.6, 2.45], "k": [3.6, 3.4, 3.2]},
    "chromium": {"n": [3.2, 3.05, 2.6], "k": [3.3, 3.3, 3.2]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "kitchen": 3500,
    "workshop": 2000,
    "bicycle": 2000,
    "bicycle_g8": 640,
    "workshop_g20": 200,
}


def materials():
    return sl.Materials(PAINTS, METALS)


def scene(name, title, camera, lights, mats, objs, preset="ideal", **extra):
    sen = cg.sensor(EXPOSURE[name], preset, **({"gain_db": extra.pop("gain_db")}
                                                  if "gain_db" in extra else {}))
    s = cg.scene("colour sealed 6: " + title, camera, lights, mats.used, objs, cg.EFFECTS, sen)
    s.update(extra)
    return s


def wobble(rng, pts, amount):
    """pts displaced along y by a smooth random wave (a grain line's meander)."""
    ph, f = rng.uniform(0, 6.3), rng.uniform(3, 9)
    return [[p[0], p[1] + amount * math.sin(ph + f * p[0]), p[2]] for p in pts]


# ---------------------------------------------------------------------------------------------
# kitchen: a butcher-block counter before a backsplash of 15 mm glazed tiles on a 17 mm grid
# (~10 px at ~1.7 mm per pixel) in dark grout, seen from a standing cook's eye height; a steel
# kettle, a red enamel casserole, a dark glass bottle, a beech chopping board with a tomato, a
# lemon, chopped parsley and a knife, a utensil crock, a striped tea towel; daylight from a
# window on the left, a ceiling lamp and two lamps under the wall cupboard

KITCHEN_CAMERA = {"position": [0.1, -0.9, 1.5], "look_at": [0.0, 0.6, 1.0], "up": UP,
                  "focal_length_mm": 2.6, "f_number": 4}
TILES = ("tile_white", "tile_sage", "tile_grey")


def kitchen_meshes():
    rng = random.Random(6101)
    out = {}
    tiles = {n: sl.Mesh("kitchen, " + n + " tiles", WRITER) for n in TILES}
    for row in range(33):
        z0 = 0.9 + 0.002 + 0.017 * row
        for col in range(-42, 42):
            x0 = 0.017 * col + 0.001
            name = "tile_sage" if 9 <= row <= 11 else ("tile_grey" if rng.random() < 0.08
                                                      else "tile_white")
            tx, tz = rng.gauss(0, 0.02), rng.gauss(0, 0.02)
            pts = []
            for a, b in ((0, 0), (1, 0), (1, 1), (0, 1)):
                du, dv = (a - 0.5) * 0.015, (b - 0.5) * 0.015
                pts.append([x0 + 0.0075 + du, 0.597 + tx * du + tz * dv, z0 + 0.0075 + dv])
            tiles[name].flat(pts)
    out.update({"kitchen_" + n + ".obj": m.text() for n, m in tiles.items()})
    # grain lines on the counter (along x), 6-14 mm apart, meandering
    grain = sl.Mesh("kitchen, counter grain", WRITER)
    y = -0.1
    while y < 0.6:
        xs = [-0.8 + 0.1 * i for i in range(17)]
        pts = wobble(rng, [[x, y, 0.9005] for x in xs], rng.uniform(0.001, 0.004))
        sl.strip(grain, pts, rng.uniform(0.001, 0.0025), UP)
        y += rng.uniform(0.006, 0.014)
    out["kitchen_grain.obj"] = grain.text()
    # the steel kettle and the enamel casserole (lathes), handles
    steel = sl.Mesh("kitchen, steel kettle and knife", WRITER)
    sl.lathe(steel, [-0.3, 0.36, 0.9], [(0.0, 0.0), (0.08, 0.0), (0.095, 0.03), (0.098, 0.08),
                                        (0.09, 0.13), (0.07, 0.165), (0.04, 0.18), (0.0, 0.182)],
             36)
    sl.tube(steel, [-0.21, 0.36, 1.0], [-0.14, 0.36, 1.06], 0.009, 8)
    enamel = sl.Mesh("kitchen, enamel casserole", WRITER)
    sl.lathe(enamel, [0.28, 0.42, 0.9], [(0.0, 0.0), (0.11, 0.0), (0.125, 0.02), (0.125, 0.11),
                                         (0.118, 0.125), (0.06, 0.14), (0.0, 0.142)], 40)
    for s in (-1, 1):
        sl.tube(enamel, [0.28 + s * 0.12, 0.42, 1.0], [0.28 + s * 0.155, 0.42, 1.0], 0.01, 8)
    bottle = sl.Mesh("kitchen, glass bottle", WRITER)
    sl.lathe(bottle, [-0.12, 0.52, 0.9], [(0.0, 0.0), (0.035, 0.0), (0.037, 0.01), (0.037, 0.19),
                                        (0.03, 0.22), (0.013, 0.25), (0.012, 0.29), (0.0, 0.29)],
             28)
    crock = sl.Mesh("kitchen, utensil crock", WRITER)
    sl.lathe(crock, [0.04, 0.5, 0.9], [(0.0, 0.0), (0.06, 0.0), (0.065, 0.14), (0.058, 0.14),
                                      (0.052, 0.02)], 32)
    spoons = sl.Mesh("kitchen, wooden spoons", WRITER)
    for q in range(4):
        a = 2 * math.pi * q / 4 + 0.4
        base = [0.04 + 0.02 * math.cos(a), 0.5 + 0.02 * math.sin(a), 0.93]
        top = [0.04 + 0.09 * math.cos(a), 0.5 + 0.09 * math.sin(a), 1.22 + 0.02 * q]
        sl.tube(spoons, base, top, 0.007, 6)
    # the knife blade lies on the board
    steel.flat([[-0.02, 0.08, 0.9256], [0.16, 0.07, 0.9256], [0.17, 0.088, 0.9256],
                [-0.02, 0.105, 0.9256]])
    for n, m in (("steel", steel), ("enamel", enamel), ("bottle", bottle), ("crock", crock),
                 ("spoons", spoons)):
        out["kitchen_" + n + ".obj"] = m.text()
    # chopped parsley on the board: 3-6 mm bits
    herbs = sl.Mesh("kitchen, parsley", WRITER)
    for q in range(260):
        c = [rng.gauss(0.0, 0.035) - 0.06, rng.gauss(0.0, 0.025) + 0.18, 0.9255]
        sl.disc(herbs, c, UP, rng.uniform(0.0015, 0.003), 5, rng.uniform(0, 6.3))
    out["kitchen_parsley.obj"] = herbs.text()
    # the tea towel's stripes, 6 mm on a 13 mm period
    stripes = sl.Mesh("kitchen, towel stripes", WRITER)
    for q in range(20):
        x = -0.42 + 0.013 * q
        stripes.flat([[x, -0.02, 0.9035], [x + 0.006, -0.02, 0.9035],
                      [x + 0.006, 0.3, 0.9035], [x, 0.3, 0.9035]])
    out["kitchen_towel.obj"] = stripes.text()
    return out


def kitchen_parts():
    m = materials()
    m.paint("grout", 0.6)
    m.many(TILES, 0.04)
    m.many(("beech_a", "beech_b", "beech_c", "grain"), 0.2)
    m.paint("board", 0.35)
    m.metal("steel", 0.06)
    m.paint("enamel_red", 0.04)
    m.paint("bottle_glass", 0.02, n=1.52)
    m.many(("tomato", "lemon"), 0.08)
    m.many(("parsley", "towel", "towel_stripe", "spoon_wood", "cabinet"), 0.5)
    m.paint("crock", 0.06)
    m.paint("knob_black", 0.1)
    m.paint("handle_black", 0.15)
    objs = [cg.ground("beech_b", 0.0),
            cg.rect([0, 0.6, 1.25], [0, -1, 0], [1, 0, 0], [1.6, 0.7], "grout")]
    # the counter: beech staves 40 mm wide along x, three shades
    objs.append(sl.box([0, 0.25, 0.45], [1.8, 0.7, 0.9], "beech_a"))
    for i in range(18):
        objs.append(cg.rect([0, -0.08 + 0.04 * i, 0.9002], UP, [1, 0, 0], [1.8, 0.0395],
                            ("beech_a", "beech_b", "beech_c")[(i * 5) % 3]))
    for n, mat, smooth in (("tile_white", "tile_white", False), ("tile_sage", "tile_sage", False),
                           ("tile_grey", "tile_grey", False), ("grain", "grain", False),
                           ("steel", "steel", True), ("enamel", "enamel_red", True),
                           ("bottle", "bottle_glass", True), ("crock", "crock", True),
                           ("spoons", "spoon_wood", True), ("parsley", "parsley", False),
                           ("towel", "towel_stripe", False)):
        objs.append(sl.mesh_object("kitchen_" + n + ".obj", mat, smooth))
    objs.append(sl.box([0.02, 0.19, 0.9125], [0.36, 0.24, 0.025], "board"))
    objs.append(sl.box([-0.055, 0.09, 0.929], [0.09, 0.02, 0.012], "handle_black", yaw=-3))
    objs.append(sl.sphere([0.13, 0.24, 0.955], 0.03, "tomato"))
    objs.append(sl.sphere([0.12, 0.14, 0.956], 0.031, "lemon"))
    objs.append(sl.sphere([-0.3, 0.36, 1.09], 0.012, "knob_black"))
    objs.append(sl.sphere([0.28, 0.42, 1.05], 0.015, "knob_black"))
    objs.append(cg.rect([-0.27, 0.14, 0.9032], UP, [1, 0, 0], [0.27, 0.32], "towel"))
    # the wall cupboard above the backsplash
    objs.append(sl.box([0, 0.43, 1.78], [1.8, 0.36, 0.7], "cabinet"))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.75, -0.3, 0.6])),
               "irradiance_w_m2": [70, 75, 85]},
              {"type": "point", "position": [0.1, -0.8, 2.4], "intensity_w_sr": [40, 34, 26]},
              {"type": "point", "position": [-0.35, 0.5, 1.41], "intensity_w_sr": [1.2, 1.05, 0.8]},
              {"type": "point", "position": [0.35, 0.5, 1.41], "intensity_w_sr": [1.2, 1.05, 0.8]}]
    return m, objs, lights


def kitchen():
    m, objs, lights = kitchen_parts()
    return scene("kitchen", "a butcher-block kitchen counter before a backsplash of small "
                 "glazed tiles (~10 px grid), a steel kettle, a red enamel casserole, a glass "
                 "bottle, a chopping board with vegetables and herbs, a striped tea towel",
                 KITCHEN_CAMERA, lights, m, objs, background=[3, 3.2, 3.6])


# ---------------------------------------------------------------------------------------------
# workshop: a pegboard wall of hand tools over a plywood bench, ~1.5 mm per pixel: hardboard
# with 6 mm holes on a 25.4 mm grid (~17 px), chromed spanners in a row, screwdrivers with
# coloured grips, pliers, a hand saw (teeth ~2.7 px), a coil of orange cable, a panel of wire
# mesh (~8 px), a cabinet of small blue drawers with printed labels; a toolbox, nuts and a sheet
# of sandpaper on the bench; a fluorescent tube overhead, a clamp lamp and the camera's flash

WORKSHOP_CAMERA = {"position": [0.06, -1.45, 1.42], "look_at": [0.0, 0.0, 1.17], "up": UP,
                   "focal_length_mm": 2.6, "f_number": 5.6}
GRIPS = ("grip_red", "grip_yellow", "grip_blue", "grip_green", "grip_black")


def workshop_meshes():
    rng = random.Random(6203)
    out = {}
    holes = sl.Mesh("workshop, pegboard holes", WRITER)
    for i in range(-20, 21):
        for j in range(30):
            sl.disc(holes, [0.0254 * i, -0.0005, 0.97 + 0.0254 * j], [0, -1, 0], 0.003, 8)
    out["workshop_holes.obj"] = holes.text()
    chrome = sl.Mesh("workshop, chromed spanners and pliers' jaws", WRITER)
    for q in range(9):
        x, w, ln = -0.42 + 0.032 * q, 0.007 + 0.0013 * q, 0.11 + 0.014 * q
        top = 1.55
        chrome.flat([[x - w / 2, -0.008, top - ln], [x + w / 2, -0.008, top - ln],
                     [x + w / 2, -0.006, top], [x - w / 2, -0.006, top]])
        sl.disc(chrome, [x, -0.009, top + w], [0, -1, 0.15], 1.3 * w, 10)
        sl.disc(chrome, [x, -0.009, top - ln - w], [0, -1, -0.15], 1.2 * w, 10)
    steel = sl.Mesh("workshop, saw blade, screwdriver shafts, wire mesh", WRITER)
    # the saw: a tapered blade with teeth of 4 mm along its lower edge
    x0, x1, zt = 0.12, 0.48, 1.5
    steel.flat([[x0, -0.004, zt], [x1, -0.004, zt - 0.01], [x1, -0.004, zt - 0.075],
                [x0, -0.004, zt - 0.11]])
    k = 0
    while x0 + 0.004 * (k + 1) < x1:
        xa = x0 + 0.004 * k
        za = zt - 0.11 + 0.035 * (xa - x0) / (x1 - x0)
        steel.flat([[xa, -0.004, za], [xa + 0.004, -0.004, za + 0.0004],
                    [xa + 0.002, -0.004, za - 0.003]])
        k += 1
    # wire mesh: 1.6 mm wires on a 12.5 mm grid, 0.3 x 0.22 m
    for i in range(25):
        x = 0.2 + 0.0125 * i
        sl.strip(steel, [[x, -0.012, 0.99], [x, -0.012, 1.21]], 0.0016, [0, -1, 0])
    for j in range(18):
        z = 0.995 + 0.0125 * j
        sl.strip(steel, [[0.195, -0.013, z], [0.505, -0.013, z]], 0.0016, [0, -1, 0])
    grips = {n: sl.Mesh("workshop, " + n + " grips", WRITER) for n in GRIPS}
    for q in range(7):
        x = -0.1 + 0.035 * q
        grip = GRIPS[q % 5]
        sl.tube(grips[grip], [x, -0.02, 1.44], [x, -0.02, 1.54], 0.012, 10)
        sl.tube(steel, [x, -0.02, 1.44], [x, -0.02, 1.31 - 0.015 * (q % 3)], 0.0028, 6)
    # pliers: two red grips crossing below chromed jaws
    for s in (-1, 1):
        sl.tube(grips["grip_red"], [-0.2, -0.015, 1.3], [-0.2 + s * 0.035, -0.015, 1.17], 0.007,
                8)
    chrome.flat([[-0.21, -0.016, 1.3], [-0.19, -0.016, 1.3], [-0.195, -0.016, 1.36],
                 [-0.205, -0.016, 1.36]])
    out["workshop_chrome.obj"] = chrome.text()
    out["workshop_steel.obj"] = steel.text()
    out.update({"workshop_" + n + ".obj": m.text() for n, m in grips.items()})
    cable = sl.Mesh("workshop, cable coil", WRITER)
    for q in range(6):
        sl.torus(cable, [-0.33 + 0.004 * q, -0.03 - 0.009 * q, 1.2 - 0.003 * q], [0.05, -1, 0.1],
                 0.075 + 0.002 * q, 0.0045, 40, 8)
    out["workshop_cable.obj"] = cable.text()
    # drawer labels: white cards with lines of 3 mm "text" (dark strokes)
    labels = sl.Mesh("workshop, drawer labels", WRITER)
    ink = sl.Mesh("workshop, label print", WRITER)
    for r in range(4):
        for c in range(5):
            x, z = -0.5 + 0.07 * c, 0.965 + 0.045 * r
            labels.flat([[x - 0.022, -0.1612, z - 0.009], [x + 0.022, -0.1612, z - 0.009],
                         [x + 0.022, -0.1612, z + 0.009], [x - 0.022, -0.1612, z + 0.009]])
            for line in range(2):
                xx = x - 0.019
                while xx < x + 0.017:
                    w = rng.uniform(0.0008, 0.0025)
                    zz = z + 0.001 - 0.0075 * line
                    ink.flat([[xx, -0.1618, zz], [xx + w, -0.1618, zz],
                              [xx + w, -0.1618, zz + 0.004], [xx, -0.1618, zz + 0.004]])
                    xx += w + rng.uniform(0.0008, 0.003)
    out["workshop_labels.obj"] = labels.text()
    out["workshop_ink.obj"] = ink.text()
    # nuts and bolts on the bench: hexagons of 6-13 mm
    nuts = sl.Mesh("workshop, nuts", WRITER)
    for q in range(70):
        c = [rng.gauss(0.05, 0.06), rng.uniform(-0.3, -0.2), 0.9305]
        sl.disc(nuts, c, UP, rng.uniform(0.003, 0.0065), 6, rng.uniform(0, 1))
    out["workshop_nuts.obj"] = nuts.text()
    grain = sl.Mesh("workshop, bench grain", WRITER)
    z = 0.9302
    yv = -0.45
    while yv < 0.0:
        pts = wobble(rng, [[-0.7 + 0.1 * i, yv, z] for i in range(15)], rng.uniform(0.001, 0.005))
        sl.strip(grain, pts, rng.uniform(0.0012, 0.003), UP)
        yv += rng.uniform(0.007, 0.016)
    out["workshop_grain.obj"] = grain.text()
    return out


def workshop_parts():
    m = materials()
    m.paint("hardboard", 0.5)
    m.paint("hole", 0.8)
    m.many(("ply_a", "ply_grain"), 0.25)
    m.metal("chromium", 0.04)
    m.metal("steel", 0.12)
    m.many(GRIPS, 0.06)
    m.paint("cable_orange", 0.1)
    m.paint("drawer", 0.15)
    m.many(("label", "ink", "sandpaper", "saw_handle"), 0.5)
    m.paint("toolbox_red", 0.05)
    m.paint("tape_yellow", 0.1)
    objs = [cg.ground("ply_b", 0.0),
            cg.rect([0, 0, 1.35], [0, -1, 0], [1, 0, 0], [1.2, 0.85], "hardboard")]
    m.paint("ply_b", 0.5)
    objs.append(sl.box([0, -0.25, 0.465], [1.4, 0.5, 0.93], "ply_a"))
    for n, mat, smooth in (("holes", "hole", False), ("chrome", "chromium", False),
                           ("steel", "steel", False), ("cable", "cable_orange", True),
                           ("labels", "label", False), ("ink", "ink", False),
                           ("nuts", "steel", False), ("grain", "ply_grain", False)):
        objs.append(sl.mesh_object("workshop_" + n + ".obj", mat, smooth))
    for n in GRIPS:
        objs.append(sl.mesh_object("workshop_" + n + ".obj", n, True))
    objs.append(sl.box([0.09, -0.005, 1.455], [0.045, 0.008, 0.03], "saw_handle"))
    objs.append(sl.box([0.09, -0.005, 1.455], [0.03, 0.012, 0.11], "saw_handle"))
    objs.append(sl.box([-0.36, -0.0805, 1.08], [0.25, 0.16, 0.2], "drawer"))
    objs.append(sl.box([0.38, -0.03, 1.3], [0.07, 0.04, 0.07], "tape_yellow"))
    objs.append(sl.box([0.38, -0.22, 1.0], [0.42, 0.2, 0.14], "toolbox_red"))
    objs.append(cg.rect([-0.05, -0.12, 0.9303], UP, [1, 0, 0], [0.23, 0.28], "sandpaper"))
    lights = [{"type": "point", "position": [0.0, -0.6, 2.2], "intensity_w_sr": [42, 45, 48]},
              {"type": "point", "position": [0.3, -0.6, 2.2], "intensity_w_sr": [42, 45, 48]},
              {"type": "point", "position": [-0.55, -0.5, 1.6], "intensity_w_sr": [15, 12, 8.4]},
              {"type": "point", "position": [0.12, -1.42, 1.48], "intensity_w_sr": [18, 18, 18]}]
    return m, objs, lights


def workshop():
    m, objs, lights = workshop_parts()
    return scene("workshop", "a pegboard of hand tools over a plywood bench (holes ~17 px "
                 "apart, chromed spanners, coloured screwdriver grips, a saw, wire mesh, a "
                 "cable coil, labelled drawers), lit by a fluorescent tube, a clamp lamp and a "
                 "flash", WORKSHOP_CAMERA, lights, m, objs, background=[1, 1, 1])


def workshop_g20():
    m, objs, lights = workshop_parts()
    return scene("workshop_g20", "the workshop scene through the IMX250MYR preset at +20 dB "
                 "analog gain (a short exposure, no flash fill)", WORKSHOP_CAMERA, lights, m,
                 objs, preset="imx250myr", gain_db=20, background=[1, 1, 1])


# ---------------------------------------------------------------------------------------------
# bicycle: a town bicycle leaning against a brick wall in a back yard, ~4.6 mm per pixel:
# stretcher-bond bricks of four clays (courses 75 mm: ~16 px, mortar ~2 px), a green plank door,
# a window with a white sill and a dark pane, a blue bin, geraniums in a terracotta pot, paving
# slabs; the bicycle's teal frame (glossy tubes), black tyres, steel rims, 32 spokes a wheel
# (sub-pixel), a chain ring and a wicker basket; a low afternoon sun and the sky

BICYCLE_CAMERA = {"position": [0.35, -4.0, 1.1], "look_at": [0.15, 0.0, 0.8], "up": UP,
                  "focal_length_mm": 3.0, "f_number": 8}
BRICKS = ("brick_red", "brick_dark", "brick_buff", "brick_plum")


def bicycle_meshes():
    rng = random.Random(6307)
    out = {}
    bricks = {n: sl.Mesh("bicycle, " + n + " bricks", WRITER) for n in BRICKS}
    for row in range(32):
        z = 0.075 * row
        x = -1.6 - (0.1125 if row % 2 else 0.0)
        while x < 2.0:
            name = BRICKS[min(int(rng.random() ** 1.4 * 4), 3)]
            if not (0.75 < x < 1.55 and z < 2.05) and not (-1.05 < x < -0.25 and 1.2 < z < 2.0):
                bricks[name].flat([[x + 0.005, -0.005, z + 0.005], [x + 0.22, -0.005, z + 0.005],
                                   [x + 0.22, -0.005, z + 0.07], [x + 0.005, -0.005, z + 0.07]])
            x += 0.225
    out.update({"bicycle_" + n + ".obj": m.text() for n, m in bricks.items()})
    frame = sl.Mesh("bicycle, frame", WRITER)
    rear, front = [-0.5, -0.3, 0.34], [0.55, -0.3, 0.34]
    crank, seat, head = [-0.05, -0.3, 0.3], [-0.18, -0.3, 0.85], [0.45, -0.3, 0.82]
    for a, b in ((rear, crank), (rear, seat), (crank, seat), (crank, [0.42, -0.3, 0.7]),
                 ([0.42, -0.3, 0.7], head), (seat, head), (head, front)):
        sl.tube(frame, a, b, 0.016, 10, caps=False)
    out["bicycle_frame.obj"] = frame.text()
    tyres = sl.Mesh("bicycle, tyres", WRITER)
    steel = sl.Mesh("bicycle, rims, spokes, bars, chain ring", WRITER)
    for c in (rear, front):
        sl.torus(tyres, c, [0, 1, 0], 0.315, 0.021, 64, 8)
        sl.torus(steel, c, [0, 1, 0], 0.29, 0.008, 64, 6)
        for k in range(32):
            a = 2 * math.pi * k / 32
            hub = [c[0] + 0.02 * math.cos(a), c[1] + (0.03 if k % 2 else -0.03), c[2]]
            rim = [c[0] + 0.285 * math.cos(a + 0.3), c[1], c[2] + 0.285 * math.sin(a + 0.3)]
            sl.tube(steel, hub, rim, 0.001, 4, caps=False)
    sl.torus(steel, [crank[0], -0.33, crank[2]], [0, 1, 0], 0.09, 0.004, 40, 6)
    sl.tube(steel, [0.42, -0.3, 0.82], [0.4, -0.3, 1.0], 0.012, 8)
    sl.tube(steel, [0.4, -0.6, 1.0], [0.4, 0.0, 1.0], 0.011, 8)
    sl.tube(steel, [-0.18, -0.3, 0.85], [-0.2, -0.3, 0.95], 0.012, 8)
    out["bicycle_tyres.obj"] = tyres.text()
    out["bicycle_steel.obj"] = steel.text()
    # door planks' joints, the wicker basket's weave (strands ~9 mm apart)
    weave = sl.Mesh("bicycle, basket weave and door joints", WRITER)
    for i in range(6):
        x = 0.77 + 0.13 * i
        weave.flat([[x, -0.012, 0.0], [x + 0.008, -0.012, 0.0], [x + 0.008, -0.012, 2.0],
                    [x, -0.012, 2.0]])
    for j in range(20):
        z = 0.78 + 0.009 * j
        weave.flat([[0.48, -0.41, z], [0.72, -0.41, z], [0.72, -0.41, z + 0.004],
                    [0.48, -0.41, z + 0.004]])
    out["bicycle_weave.obj"] = weave.text()
    leaves = sl.Mesh("bicycle, geranium leaves", WRITER)
    flowers = sl.Mesh("bicycle, geranium flowers", WRITER)
    for q in range(140):
        c = [-1.3 + rng.gauss(0, 0.09), -0.25 + rng.gauss(0, 0.08), 0.45 + abs(rng.gauss(0, 0.1))]
        sl.disc(leaves, c, cg.unit([rng.gauss(0, 0.5), -1, rng.uniform(0.2, 1.5)]),
                rng.uniform(0.015, 0.03), 7, rng.uniform(0, 1))
    for q in range(60):
        c = [-1.3 + rng.gauss(0, 0.09), -0.3 + rng.gauss(0, 0.08), 0.55 + abs(rng.gauss(0, 0.1))]
        sl.disc(flowers, c, cg.unit([rng.gauss(0, 0.4), -1, rng.uniform(0.3, 1.0)]),
                rng.uniform(0.008, 0.016), 6, rng.uniform(0, 1))
    out["bicycle_leaves.obj"] = leaves.text()
    out["bicycle_flowers.obj"] = flowers.text()
    return out


def bicycle():
    m = materials()
    m.paint("mortar", 0.6)
    m.many(BRICKS, 0.5)
    m.many(("slab_a", "slab_b", "slab_joint"), 0.4)
    m.paint("frame_teal", 0.05)
    m.paint("tyre", 0.3)
    m.metal("steel", 0.08)
    m.paint("saddle", 0.2)
    m.paint("door_green", 0.1)
    m.paint("sill", 0.3)
    m.paint("pane", 0.02, n=1.52)
    m.paint("basket", 0.5)
    m.paint("pot_terracotta", 0.5)
    m.paint("geranium", 0.4)
    m.paint("leaf", 0.25)
    m.paint("bin_blue", 0.12)
    objs = [cg.ground("slab_joint"),
            cg.rect([0.2, 0.0, 1.2], [0, -1, 0], [1, 0, 0], [3.6, 2.4], "mortar")]
    for i in range(-4, 5):
        for j in range(7):
            objs.append(cg.rect([0.6 * i + 0.2, -0.3 - 0.6 * j, 0.002], UP, [1, 0, 0],
                                [0.59, 0.59], ("slab_a", "slab_b")[(i * 3 + j) % 2]))
    for n in BRICKS:
        objs.append(sl.mesh_object("bicycle_" + n + ".obj", n))
    objs.append(cg.rect([1.15, -0.01, 1.025], [0, -1, 0], [1, 0, 0], [0.8, 2.05], "door_green"))
    objs.append(cg.rect([-0.65, -0.01, 1.6], [0, -1, 0], [1, 0, 0], [0.8, 0.8], "pane"))
    objs.append(sl.box([-0.65, -0.05, 1.18], [0.9, 0.1, 0.05], "sill"))
    objs.append(sl.box([1.85, -0.35, 0.5], [0.55, 0.6, 1.0], "bin_blue"))
    objs.append(sl.box([0.6, -0.41, 0.86], [0.26, 0.26, 0.16], "basket"))
    objs.append(sl.box([-0.2, -0.3, 0.965], [0.22, 0.1, 0.04], "saddle"))
    for n, mat, smooth in (("frame", "frame_teal", True), ("tyres", "tyre", True),
                           ("steel", "steel", True), ("weave", "saddle", False),
                           ("leaves", "leaf", False), ("flowers", "geranium", False)):
        objs.append(sl.mesh_object("bicycle_" + n + ".obj", mat, smooth))
    objs.append(sl.box([-1.3, -0.25, 0.18], [0.36, 0.36, 0.36], "pot_terracotta"))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.8, -0.45, 0.42])),
               "irradiance_w_m2": [520, 470, 400]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.3, -0.5, 0.8])),
               "irradiance_w_m2": [60, 80, 120],
               "polarization": {"linear_deg": 90, "dop": 0.3}}]
    return m, objs, lights


def bicycle_g8():
    m, objs, lights = bicycle()
    return scene("bicycle_g8", "the bicycle scene through the IMX250MYR preset at +8 dB analog "
                 "gain (a fast shutter)", BICYCLE_CAMERA, lights, m, objs, preset="imx250myr",
                 gain_db=8, background=[25, 32, 45])


def bicycle_scene():
    m, objs, lights = bicycle()
    return scene("bicycle", "a town bicycle against a brick wall in a back yard (courses ~16 "
                 "px, sub-pixel spokes), a green door, a window, a blue bin, geraniums, paving "
                 "slabs, in a low afternoon sun", BICYCLE_CAMERA, lights, m, objs,
                 background=[25, 32, 45])


SCENES = {"kitchen": kitchen, "workshop": workshop, "bicycle": bicycle_scene,
          "bicycle_g8": bicycle_g8, "workshop_g20": workshop_g20}


def meshes():
    out = {}
    out.update(kitchen_meshes())
    out.update(workshop_meshes())
    out.update(bicycle_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
