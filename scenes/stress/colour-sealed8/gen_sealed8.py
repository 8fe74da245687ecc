#!/usr/bin/env python3
"""Writes the eighth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed8.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed8.py --print NAME` prints one scene instead.
The generic helpers (millimetre meshes, prisms, tori, lathes, ribbons, materials) are
../colour-sealed6/sealed_lib.py, imported from there (that directory is frozen by its seal; it
is read, never written); the colour sensor, the scene record, rect and the writer are
../colour_gen.py's. The few helpers sealed_lib lacks (a lathe about any axis, a box as mesh
facets, a chain of tubes along a polyline, a ring of ribbon in any plane) are below, written
here (../colour-sealed7/gen_sealed7.py has similar ones but is not a module to import).

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). The rail steel, the needles' aluminium and the tray's chrome are
assumed metals of the right order (n - ik per channel at 610, 530 and 465 nm, from memory, not a
table lookup); no metal of the other sets is reused. None of the paints, meshes, cameras or
layouts of the other colour sets is reused (nor a paint's or metal's name).

Meshes are written in millimetres (placed with scale 0.001). Flat-faced meshes (`smooth` false)
give each facet its own vertices; the smooth ones (lathes, tori, tubes) share vertices so that
the loader's area-weighted vertex normals are smooth.

The exposures (EXPOSURE) were set by looking at the rendered raw frames and truth only
(brightness, clipping, hue-edge density, DoLP), before any demosaicking method was run on these
scenes; README.md records the commit that sealed them.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "colour-sealed6"))
sys.dont_write_bytecode = True  # no __pycache__ in either sealed directory
import sealed_lib as sl  # noqa: E402 (../colour-sealed6/sealed_lib.py)

cg = sl.cg
WRITER = "gen_sealed8.py"
UP = [0, 0, 1]

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # wool: a knitting-wool shop's wall of pine cubbies holding yarn cakes
    "pine": [1.1, 0.78, 0.45], "cubby_back": [0.5, 0.36, 0.22], "shop_wall": [0.9, 0.85, 0.7],
    "yarn_red": [1.05, 0.09, 0.08], "yarn_green": [0.1, 0.42, 0.1], "yarn_cream": [1.5, 1.4, 1.1],
    "yarn_navy": [0.05, 0.08, 0.3], "yarn_mustard": [1.3, 0.85, 0.06],
    "yarn_teal": [0.06, 0.55, 0.55], "yarn_plum": [0.45, 0.08, 0.35],
    "yarn_grey": [0.35, 0.36, 0.38], "card_white": [1.6, 1.6, 1.55], "card_ink": [0.04, 0.04, 0.05],
    "jar_blue": [0.1, 0.2, 0.6],
    # pool: a swimming pool's edge along the length of the pool
    "deck_tile": [0.95, 0.95, 0.9], "deck_grout": [0.3, 0.32, 0.32], "coping": [1.15, 1.15, 1.1],
    "wall_tile_blue": [0.05, 0.25, 0.85], "wall_tile_sky": [0.35, 0.85, 1.2],
    "wall_tile_white": [1.45, 1.5, 1.5], "pool_water": [0.01, 0.03, 0.035],
    "lane_red": [1.4, 0.07, 0.06], "lane_white": [1.55, 1.55, 1.5],
    "lane_blue": [0.06, 0.15, 0.95], "board_yellow": [1.55, 1.35, 0.05],
    "noodle_pink": [1.6, 0.3, 0.8], "pool_hall": [0.45, 0.5, 0.55],
    # bus: a city bus's lower deck from the aisle, patterned seat fabric, grab poles
    "moquette": [0.03, 0.035, 0.12], "moq_magenta": [1.2, 0.08, 0.6],
    "moq_yellow": [1.45, 1.2, 0.05], "moq_teal": [0.05, 0.75, 0.65],
    "seat_shell": [0.2, 0.21, 0.22], "pole_yellow": [1.5, 1.1, 0.04],
    "vinyl_floor": [0.28, 0.27, 0.25], "vinyl_dot": [0.45, 0.44, 0.4],
    "panel_grey": [0.8, 0.82, 0.85], "stop_red": [1.3, 0.05, 0.06], "bus_ceiling": [1.3, 1.3, 1.3],
    # bakery: a pastry counter from the customer's side, seen from above
    "counter_laminate": [0.08, 0.14, 0.12], "glaze_amber": [0.95, 0.45, 0.12],
    "pastry_crumb": [1.3, 0.95, 0.55], "choc": [0.12, 0.06, 0.035], "icing_pink": [1.6, 0.55, 0.8],
    "sprinkle_red": [1.35, 0.06, 0.08], "sprinkle_yellow": [1.5, 1.3, 0.05],
    "sprinkle_green": [0.15, 0.8, 0.15], "sprinkle_blue": [0.08, 0.25, 1.1],
    "sprinkle_white": [1.6, 1.6, 1.6], "chalkboard": [0.04, 0.045, 0.045],
    "chalk_pink": [1.5, 0.35, 0.7], "chalk_cyan": [0.3, 1.2, 1.4], "chalk_yellow": [1.5, 1.45, 0.3],
    "hole_dark": [0.03, 0.03, 0.03], "doily": [1.55, 1.52, 1.4],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "rail_steel": {"n": [2.6, 2.45, 2.3], "k": [3.6, 3.4, 3.15]},
    "needle_alu": {"n": [1.3, 0.95, 0.7], "k": [7.4, 6.5, 5.6]},
    "tray_chrome": {"n": [3.2, 3.0, 2.6], "k": [3.3, 3.3, 3.2]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "wool": 5500,
    "pool": 350,
    "bus": 4500,
    "bakery": 5000,
    "bakery_g2": 6000,
    "bus_g14": 1170,
}


def materials():
    return sl.Materials(PAINTS, METALS)


def scene(name, title, camera, lights, mats, objs, preset="ideal", **extra):
    sen = cg.sensor(EXPOSURE[name], preset, **({"gain_db": extra.pop("gain_db")}
                                                  if "gain_db" in extra else {}))
    s = cg.scene("colour sealed 8: " + title, camera, lights, mats.used, objs, cg.EFFECTS, sen)
    s.update(extra)
    return s


def lathe_axis(mesh, c, axis, profile, n=24):
    """sl.lathe about any axis through c: profile (radius, distance along axis) pairs."""
    u, v = sl.frame(axis)
    a = cg.unit(axis)
    rows = [[mesh.vert(p) for p in sl.ring_points(cg.add(c, a, h), u, v, rad, n)]
            for rad, h in profile]
    for lower, upper in zip(rows, rows[1:]):
        for i in range(n):
            j = (i + 1) % n
            mesh.face([lower[i], lower[j], upper[j], upper[i]])


def box_mesh(mesh, c, size, yaw=0.0):
    """A box as six flat facets (many small boxes in one mesh rather than as objects)."""
    cy, sy = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))

    def p(dx, dy, dz):
        x, y = dx * size[0] / 2, dy * size[1] / 2
        return [c[0] + cy * x - sy * y, c[1] + sy * x + cy * y, c[2] + dz * size[2] / 2]

    for f in (((-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1)),
              ((-1, -1, 1), (-1, 1, 1), (1, 1, 1), (1, -1, 1)),
              ((-1, -1, -1), (-1, -1, 1), (1, -1, 1), (1, -1, -1)),
              ((-1, 1, -1), (1, 1, -1), (1, 1, 1), (-1, 1, 1)),
              ((-1, -1, -1), (-1, 1, -1), (-1, 1, 1), (-1, -1, 1)),
              ((1, -1, -1), (1, -1, 1), (1, 1, 1), (1, 1, -1))):
        mesh.flat([p(*q) for q in f])


def snake(mesh, pts, radius, sides=6):
    """A chain of tubes along the polyline pts (a sprinkle, a bent rail)."""
    for a, b in zip(pts, pts[1:]):
        sl.tube(mesh, a, b, radius, sides, caps=False)


def ring_flat(mesh, c, normal, r, width, n=32):
    """A flat ring of ribbon of `width` at radius r about c in the plane perpendicular to
    normal (a turn of yarn seen end-on)."""
    u, v = sl.frame(normal)
    pts = sl.ring_points(c, u, v, r, n)
    pts.append(pts[0])
    sl.strip(mesh, pts, width, normal)


# ---------------------------------------------------------------------------------------------
# wool: a knitting-wool shop's wall of pine cubbies (3 x 3, 0.24 m square, boards 18 mm) seen
# face-on from 1.1 m (~1.6 mm per pixel): yarn cakes lying with their flat faces towards the
# camera (radius 36-44 mm), each face a set of turns of yarn (2.6 mm strands on a 3.4 mm
# pitch: ~2 px) in two colours in bands of three turns (~6.5 px bands); two cubbies of red and
# green cakes of about the same brightness; glossy price cards with printed lines, a blue jar of
# aluminium knitting needles on the top; two spot lamps and, from the right, the street's light
# reflected off the glass front opposite (strongly polarized: degree 0.85)

WOOL_CAMERA = {"position": [0.05, -1.1, 1.33], "look_at": [0.0, 0.0, 1.25], "up": UP,
               "focal_length_mm": 2.4, "f_number": 5.6}
# the cubbies' yarn pairs (base, band), row-major from the top left
WOOL_PAIRS = [("yarn_red", "yarn_green"), ("yarn_cream", "yarn_navy"),
              ("yarn_mustard", "yarn_plum"), ("yarn_teal", "yarn_cream"),
              ("yarn_green", "yarn_red"), ("yarn_grey", "yarn_mustard"),
              ("yarn_navy", "yarn_teal"), ("yarn_plum", "yarn_grey"), ("yarn_red", "yarn_cream")]
YARNS = ("yarn_red", "yarn_green", "yarn_cream", "yarn_navy", "yarn_mustard", "yarn_teal",
         "yarn_plum", "yarn_grey")


def cubby_origin(i, j):
    """Lower left corner (x, z) of cubby column i, row j (row 0 at the top)."""
    return -0.39 + 0.258 * i, 1.42 - 0.258 * (j + 1)


def wool_meshes():
    rng = random.Random(8101)
    out = {}
    pine = sl.Mesh("wool, pine cubby boards", WRITER)
    for i in range(4):
        x = -0.39 - 0.018 + 0.258 * i
        box_mesh(pine, [x + 0.009, 0.15, 1.42 - 3 * 0.129], [0.018, 0.3, 3 * 0.258 + 0.018])
    for j in range(4):
        z = 1.42 - 0.258 * j
        box_mesh(pine, [-0.39 + 1.5 * 0.258 - 0.009, 0.15, z - 0.009 + 0.018 * (j == 0)],
                 [3 * 0.258 + 0.018, 0.3, 0.018])
    out["wool_pine.obj"] = pine.text()
    yarn = {n: sl.Mesh("wool, " + n + " yarn", WRITER) for n in YARNS}
    for j in range(3):
        for i in range(3):
            base, band = WOOL_PAIRS[3 * j + i]
            x0, z0 = cubby_origin(i, j)
            # two rows of cakes lying on their sides, fronts at y = 0.02 .. 0.06
            cakes = []
            for row in range(2):
                r = rng.uniform(0.036, 0.044)
                x = x0 + 0.012 + r
                while x + r < x0 + 0.24 - 0.006:
                    cakes.append(([x, z0 + 0.002 + r + row * 2 * r * 0.98], r))
                    x += 2 * r + rng.uniform(0.002, 0.01)
                    r = rng.uniform(0.036, 0.044)
            for (cx, cz), r in cakes:
                y0 = rng.uniform(0.02, 0.05)
                c = [cx, y0, cz]
                ax = [0, 1, 0]
                lathe_axis(yarn[base], c, ax, [(0.0, 0.0), (r, 0.0), (r, 0.09), (0.0, 0.09)], 20)
                ph = rng.uniform(0, 3)
                k = 0
                rr = 0.006 + 0.0034 * rng.random()
                while rr < r - 0.002:
                    if (k + int(ph)) % 6 < 3:
                        ring_flat(yarn[band], [cx, y0 - 0.0005, cz], ax, rr, 0.0026, 24)
                    rr += 0.0034
                    k += 1
    out.update({"wool_" + n + ".obj": m.text() for n, m in yarn.items()})
    # price cards on the boards' edges, each with printed lines
    ink = sl.Mesh("wool, price card print", WRITER)
    for j in range(1, 4):
        for i in range(3):
            x0 = cubby_origin(i, 0)[0] + 0.08
            z = 1.42 - 0.258 * j - 0.004
            zz = z - 0.006
            for line in range(3):
                x = x0 + 0.006
                while x < x0 + 0.07 - 0.006 * line:
                    w = rng.uniform(0.0012, 0.003)
                    ink.flat([[x, -0.0015, zz - 0.002], [x + w, -0.0015, zz - 0.002],
                              [x + w, -0.0015, zz], [x, -0.0015, zz]])
                    x += w + rng.uniform(0.0008, 0.0025)
                zz -= 0.0045
    out["wool_ink.obj"] = ink.text()
    # knitting needles standing in a jar on the top board
    needles = sl.Mesh("wool, knitting needles", WRITER)
    for q in range(9):
        a = rng.uniform(-0.25, 0.25)
        b = [0.25 + 0.004 * q, 0.1 + rng.uniform(-0.02, 0.02), 1.44]
        t = [b[0] + 0.33 * math.sin(a), b[1] + rng.uniform(-0.04, 0.04), b[2] + 0.33 * math.cos(a)]
        sl.tube(needles, b, t, 0.0025 + 0.0005 * (q % 3), 8)
        sl.lathe(needles, t, [(0.0, 0.0), (0.006, 0.0), (0.006, 0.006), (0.0, 0.006)], 10)
    out["wool_needles.obj"] = needles.text()
    return out


def wool():
    m = materials()
    m.paint("pine", 0.3)
    m.paint("cubby_back", 0.5)
    m.paint("shop_wall", 0.5)
    m.many(YARNS, 0.6)
    m.paint("card_white", 0.03)
    m.paint("card_ink", 0.1)
    m.paint("jar_blue", 0.03)
    m.metal("needle_alu", 0.06)
    objs = [cg.rect([0, 0.3, 1.2], [0, -1, 0], [1, 0, 0], [3.0, 2.4], "shop_wall"),
            cg.rect([-0.39 + 1.5 * 0.258, 0.15, 1.42 - 1.5 * 0.258], [0, -1, 0], [1, 0, 0],
                    [3 * 0.258, 3 * 0.258], "cubby_back"),
            cg.ground("shop_wall")]
    for j in range(1, 4):
        for i in range(3):
            x0 = cubby_origin(i, 0)[0] + 0.08
            z = 1.42 - 0.258 * j - 0.004
            objs.append(cg.rect([x0 + 0.04, -0.001, z - 0.01], cg.unit([0, -1, 0.35]), [1, 0, 0],
                                [0.08, 0.022], "card_white"))
    for n, mat, smooth in (("pine", "pine", False), ("ink", "card_ink", False),
                           ("needles", "needle_alu", True)):
        objs.append(sl.mesh_object("wool_" + n + ".obj", mat, smooth))
    for n in YARNS:
        objs.append(sl.mesh_object("wool_" + n + ".obj", n, False))
    jar = sl.sphere([0.27, 0.1, 1.48], 0.055, "jar_blue")
    objs.append(jar)
    lights = [{"type": "point", "position": [-0.35, -1.2, 1.7], "intensity_w_sr": [30, 27, 21]},
              {"type": "point", "position": [0.4, -1.0, 1.55], "intensity_w_sr": [30, 27, 21]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.8, -0.45, 0.4])),
               "irradiance_w_m2": [35, 40, 48], "polarization": {"linear_deg": 70, "dop": 0.85}}]
    return scene("wool", "a knitting-wool shop's wall of pine cubbies of yarn cakes (turns of "
                 "yarn ~2 px, two-colour bands ~6 px; red and green cakes of about equal "
                 "brightness), price cards, a jar of knitting needles",
                 WOOL_CAMERA, lights, m, objs, background=[2, 2, 2])


# ---------------------------------------------------------------------------------------------
# pool: a swimming pool's edge seen along the length of the pool from the deck, 1.7 m up: a deck
# of 50 mm tiles in 4 mm grout (~12 px near the bottom of the frame, ~4 px far off), pale
# coping, the far side's band of blue, sky and white 25 mm wall tiles above the water (~3 px),
# rippled water (n 1.33) with a low sun's glitter off it (the sun ~22° up, ahead), a lane rope of
# red, white and blue floats, a steel ladder, a yellow kickboard and a pink noodle; the
# hall's far wall (dark); two hall lamps

POOL_CAMERA = {"position": [1.3, -1.2, 1.7], "look_at": [-0.5, 2.6, -0.15], "up": UP,
               "focal_length_mm": 2.6, "f_number": 8}


def water_z(x, y):
    return -0.15 + 0.012 * math.sin(3.1 * x + 1.7 * y) + 0.008 * math.sin(5.3 * y - 2.2 * x + 1) \
        + 0.005 * math.sin(8.1 * x + 6.7 * y + 2)


def pool_meshes():
    out = {}
    # deck (x > 0.3): 50 mm tiles with 4 mm grout, as tile facets over a grout plane
    deck = sl.Mesh("pool, deck tiles", WRITER)
    nx, ny = 40, 120
    for i in range(nx):
        for j in range(ny):
            x, y = 0.33 + 0.054 * i, -2.0 + 0.054 * j
            deck.flat([[x, y, 0.001], [x + 0.05, y, 0.001], [x + 0.05, y + 0.05, 0.001],
                       [x, y + 0.05, 0.001]])
    out["pool_deck.obj"] = deck.text()
    # the far side's wall above the water at x = -3.0 (facing the camera across the pool):
    # 25 mm tiles in three colours, a wave of sky-blue through the blue band, white on top
    walls = {n: sl.Mesh("pool, " + n + " wall tiles", WRITER)
             for n in ("wall_tile_blue", "wall_tile_sky", "wall_tile_white")}
    for j in range(int(12.0 / 0.026)):
        y = -1.0 + 0.026 * j
        for k in range(6):
            z = -0.16 + 0.026 * k
            w = 2.0 + 1.6 * math.sin(0.35 * j)
            name = ("wall_tile_white" if k > 4 else
                    "wall_tile_sky" if abs(k - w) < 0.8 else "wall_tile_blue")
            walls[name].flat([[-3.0, y, z], [-3.0, y + 0.024, z], [-3.0, y + 0.024, z + 0.024],
                              [-3.0, y, z + 0.024]])
    out.update({"pool_" + n + ".obj": m.text() for n, m in walls.items()})
    # rippled water: a height field over x in [-3, 0.3], y in [-2, 20] (finer near the camera)
    water = sl.Mesh("pool, water surface", WRITER)
    xs = [0.3 - 0.1 * i for i in range(34)]
    ys, y = [], -2.0
    while y < 20.0:
        ys.append(y)
        y += 0.06 + 0.02 * max(0.0, y)
    grid = [[water.vert([x, yy, water_z(x, yy)]) for x in xs] for yy in ys]
    for a in range(len(ys) - 1):
        for b in range(len(xs) - 1):
            water.face([grid[a][b], grid[a][b + 1], grid[a + 1][b + 1], grid[a + 1][b]])
    out["pool_water.obj"] = water.text()
    # a lane rope 1.6 m from the wall: floats 100 mm across, 120 mm long, alternating colours
    floats = {n: sl.Mesh("pool, " + n + " lane floats", WRITER)
              for n in ("lane_red", "lane_white", "lane_blue")}
    for k in range(110):
        y = -1.8 + 0.125 * k
        name = ("lane_red" if (k // 4) % 3 == 0 else
                "lane_white" if (k // 4) % 3 == 1 else "lane_blue")
        lathe_axis(floats[name], [-1.3, y, -0.14], [0, 1, 0],
                   [(0.0, -0.06), (0.04, -0.05), (0.05, 0.0), (0.04, 0.05), (0.0, 0.06)], 10)
    out.update({"pool_" + n + ".obj": m.text() for n, m in floats.items()})
    # the steel ladder: two bent rails (38 mm tube) over the edge into the water
    ladder = sl.Mesh("pool, ladder rails", WRITER)
    for dy in (0.0, 0.5):
        pts = [[0.9, 3.5 + dy, 0.0], [0.9, 3.5 + dy, 0.7]]
        for k in range(1, 9):
            a = math.pi * k / 8
            pts.append([0.6 + 0.3 * math.cos(a), 3.5 + dy, 0.7 + 0.3 * math.sin(a)])
        pts.append([0.18, 3.5 + dy, -0.15])
        snake(ladder, pts, 0.019, 12)
    out["pool_ladder.obj"] = ladder.text()
    noodle = sl.Mesh("pool, noodle", WRITER)
    pts = [[-0.6 + 0.5 * math.sin(0.9 * t / 10), 0.8 + 1.3 * t / 10 + 0.1 * math.sin(t / 3.0),
            water_z(-0.6, 0.8) + 0.03] for t in range(11)]
    snake(noodle, pts, 0.035, 10)
    out["pool_noodle.obj"] = noodle.text()
    return out


def pool():
    m = materials()
    m.paint("deck_grout", 0.5)
    m.paint("deck_tile", 0.12)
    m.paint("coping", 0.2)
    m.many(("wall_tile_blue", "wall_tile_sky", "wall_tile_white"), 0.06)
    m.paint("pool_water", 0.05, n=1.33)
    m.many(("lane_red", "lane_white", "lane_blue"), 0.08)
    m.paint("board_yellow", 0.1)
    m.paint("noodle_pink", 0.3)
    m.paint("pool_hall", 0.5)
    m.metal("rail_steel", 0.04)
    objs = [cg.rect([2.15, 9.0, 0.0], UP, [1, 0, 0], [3.7, 22.0], "deck_grout"),
            cg.rect([-5.0, 9.0, 0.0], UP, [1, 0, 0], [4.0, 22.0], "deck_tile"),
            cg.rect([-1.35, 9.0, -0.21], UP, [1, 0, 0], [3.3, 22.0], "pool_water"),
            sl.box([0.4, 9.0, 0.015], [0.2, 22.0, 0.03], "coping"),
            cg.rect([0, 20.0, 2.0], [0, -1, 0], [1, 0, 0], [14.0, 6.0], "pool_hall"),
            sl.box([0.95, 0.4, 0.013], [0.3, 0.45, 0.025], "board_yellow")]
    for n, mat, smooth in (("deck", "deck_tile", False),
                           ("wall_tile_blue", "wall_tile_blue", False),
                           ("wall_tile_sky", "wall_tile_sky", False),
                           ("wall_tile_white", "wall_tile_white", False),
                           ("water", "pool_water", True), ("ladder", "rail_steel", True),
                           ("noodle", "noodle_pink", True)):
        objs.append(sl.mesh_object("pool_" + n + ".obj", mat, smooth))
    for n in ("lane_red", "lane_white", "lane_blue"):
        objs.append(sl.mesh_object("pool_" + n + ".obj", n, True))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.4, 0.75, 0.35])),
               "irradiance_w_m2": [300, 290, 260]},
              {"type": "point", "position": [0.5, 2.0, 4.0], "intensity_w_sr": [1500, 1500, 1600]},
              {"type": "point", "position": [0.5, 7.0, 4.0], "intensity_w_sr": [1500, 1500, 1600]}]
    return scene("pool", "an indoor swimming pool's edge along the pool (50 mm deck tiles, a "
                 "band of wall tiles, rippled water with the sun's glitter, a lane rope, a "
                 "stainless ladder, a kickboard and a noodle)",
                 POOL_CAMERA, lights, m, objs, background=[25, 27, 30])


# ---------------------------------------------------------------------------------------------
# bus: a city bus's lower deck seen from the aisle, 1.3 m up, looking forward and to the left:
# four rows of paired seats whose backs and cushions carry moquette (a navy ground with thin
# magenta, yellow and teal zigzag and curved lines of 2-3 mm: ~1-1.5 px at the nearest seat),
# grey seat shells, yellow glossy grab poles (35 mm) with red stop buttons, two steel rails, a
# grey vinyl floor with raised dots (8 mm on an 18 mm grid), light grey side panels and windows
# (the bright street beyond); two ceiling lamps and the sky's light through the left windows
# (polarized: degree 0.75)

BUS_CAMERA = {"position": [0.15, -0.6, 1.3], "look_at": [-0.55, 2.0, 0.75], "up": UP,
              "focal_length_mm": 2.6, "f_number": 5.6}
MOQ = ("moq_magenta", "moq_yellow", "moq_teal")


def bus_meshes():
    rng = random.Random(8307)
    out = {}
    shell = sl.Mesh("bus, seat shells", WRITER)
    lines = {n: sl.Mesh("bus, " + n + " moquette lines", WRITER) for n in MOQ}
    navy = sl.Mesh("bus, moquette ground", WRITER)
    for row in range(4):
        y = 0.4 + 0.78 * row
        for xc in (-1.05, -0.6):
            box_mesh(shell, [xc, y, 0.44], [0.42, 0.44, 0.06])
            box_mesh(shell, [xc, y + 0.22, 0.75], [0.42, 0.06, 0.66])
            # the moquette on the back's rear face (seen from behind) and on the cushion
            navy.flat([[xc - 0.19, y + 0.19, 0.48], [xc + 0.19, y + 0.19, 0.48],
                       [xc + 0.19, y + 0.19, 1.04], [xc - 0.19, y + 0.19, 1.04]])
            navy.flat([[xc - 0.19, y - 0.2, 0.471], [xc + 0.19, y - 0.2, 0.471],
                       [xc + 0.19, y + 0.18, 0.471], [xc - 0.19, y + 0.18, 0.471]])
            # zigzags and arcs across the seat front (y + 0.189) and cushion (z 0.472)
            for q in range(12):
                name = MOQ[q % 3]
                z = 0.5 + 0.045 * q + rng.uniform(-0.005, 0.005)
                pts = []
                for k in range(11):
                    pts.append([xc - 0.18 + 0.036 * k, y + 0.188,
                                z + (0.012 if k % 2 else -0.012)])
                sl.strip(lines[name], pts, 0.0025, [0, -1, 0])
            for q in range(6):
                name = MOQ[(q + 1) % 3]
                c = [xc - 0.12 + 0.12 * (q % 3), y - 0.1 + 0.18 * (q // 3), 0.473]
                pts = [[c[0] + 0.05 * math.cos(math.pi * k / 10),
                        c[1] + 0.05 * math.sin(math.pi * k / 10), c[2]] for k in range(11)]
                sl.strip(lines[name], pts, 0.003, UP)
                pts = [[c[0] + 0.03 * math.cos(math.pi * k / 10),
                        c[1] + 0.03 * math.sin(math.pi * k / 10), c[2]] for k in range(11)]
                sl.strip(lines[MOQ[q % 3]], pts, 0.002, UP)
    out["bus_shell.obj"] = shell.text()
    out["bus_moquette.obj"] = navy.text()
    out.update({"bus_" + n + ".obj": m.text() for n, m in lines.items()})
    poles = sl.Mesh("bus, yellow grab poles", WRITER)
    for row in range(4):
        y = 0.4 + 0.78 * row + 0.26
        sl.tube(poles, [-0.32, y, 0.0], [-0.32, y, 2.1], 0.0175, 14)
    for y in (1.1, 2.7):
        sl.tube(poles, [0.55, y, 0.0], [0.55, y, 2.1], 0.0175, 14)
    out["bus_poles.obj"] = poles.text()
    rail = sl.Mesh("bus, stainless rail", WRITER)
    sl.tube(rail, [-0.32, -0.5, 1.85], [-0.32, 4.0, 1.85], 0.016, 14)
    sl.tube(rail, [0.55, -0.5, 1.85], [0.55, 4.0, 1.85], 0.016, 14)
    out["bus_rail.obj"] = rail.text()
    stop = sl.Mesh("bus, stop buttons", WRITER)
    for row in range(4):
        y = 0.4 + 0.78 * row + 0.26
        box_mesh(stop, [-0.32, y - 0.025, 1.2], [0.05, 0.02, 0.07])
    out["bus_stop.obj"] = stop.text()
    # the aisle's floor: raised dots 8 mm across on an 18 mm grid
    dots = sl.Mesh("bus, floor dots", WRITER)
    for i in range(int(0.6 / 0.018)):
        for j in range(int(2.6 / 0.018)):
            x, y = -0.25 + 0.018 * i, -0.2 + 0.018 * j
            sl.disc(dots, [x, y, 0.001], UP, 0.004, 6)
    out["bus_dots.obj"] = dots.text()
    # the left side: panels below the windows, window pillars
    panel = sl.Mesh("bus, side panels", WRITER)
    panel.flat([[-1.3, -1.0, 0.0], [-1.3, 4.5, 0.0], [-1.3, 4.5, 0.95], [-1.3, -1.0, 0.95]])
    for k in range(6):
        y = -0.4 + 0.95 * k
        panel.flat([[-1.29, y, 0.95], [-1.29, y + 0.1, 0.95], [-1.29, y + 0.1, 1.9],
                    [-1.29, y, 1.9]])
    panel.flat([[-1.3, -1.0, 1.9], [-1.3, 4.5, 1.9], [-1.3, 4.5, 2.3], [-1.3, -1.0, 2.3]])
    panel.flat([[1.3, -1.0, 0.0], [1.3, 4.5, 0.0], [1.3, 4.5, 2.3], [1.3, -1.0, 2.3]])
    panel.flat([[-1.3, 4.5, 0.0], [1.3, 4.5, 0.0], [1.3, 4.5, 2.3], [-1.3, 4.5, 2.3]])
    out["bus_panel.obj"] = panel.text()
    return out


def bus_parts():
    m = materials()
    m.paint("vinyl_floor", 0.08)
    m.paint("vinyl_dot", 0.08)
    m.paint("seat_shell", 0.1)
    m.paint("moquette", 0.7)
    m.many(MOQ, 0.7)
    m.paint("pole_yellow", 0.04)
    m.paint("stop_red", 0.05)
    m.paint("panel_grey", 0.15)
    m.paint("bus_ceiling", 0.5)
    m.metal("rail_steel", 0.05)
    objs = [cg.ground("vinyl_floor"),
            cg.rect([0, 1.75, 2.3], [0, 0, -1], [1, 0, 0], [2.6, 5.5], "bus_ceiling")]
    for n, mat, smooth in (("shell", "seat_shell", False), ("moquette", "moquette", False),
                           ("poles", "pole_yellow", True), ("rail", "rail_steel", True),
                           ("stop", "stop_red", False), ("dots", "vinyl_dot", False),
                           ("panel", "panel_grey", False)):
        objs.append(sl.mesh_object("bus_" + n + ".obj", mat, smooth))
    for n in MOQ:
        objs.append(sl.mesh_object("bus_" + n + ".obj", n, False))
    lights = [{"type": "point", "position": [0.0, 0.5, 2.2], "intensity_w_sr": [25, 25, 26]},
              {"type": "point", "position": [0.0, 2.5, 2.2], "intensity_w_sr": [25, 25, 26]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.75, -0.35, 0.55])),
               "irradiance_w_m2": [110, 120, 140], "polarization": {"linear_deg": 90, "dop": 0.75}}]
    return m, objs, lights


def bus():
    m, objs, lights = bus_parts()
    return scene("bus", "a city bus's lower deck from the aisle (seat backs of navy moquette "
                 "with thin magenta, yellow and teal lines, yellow grab poles, a stainless "
                 "rail, a dotted vinyl floor, windows)", BUS_CAMERA, lights, m, objs,
                 background=[60, 62, 66])


def bus_g14():
    m, objs, lights = bus_parts()
    return scene("bus_g14", "the bus scene through the IMX250MYR preset at +14 dB analog gain "
                 "(a moving bus, a short exposure)", BUS_CAMERA, lights, m, objs,
                 preset="imx250myr", gain_db=14, background=[60, 62, 66])


# ---------------------------------------------------------------------------------------------
# bakery: a pastry counter seen from above, ~40° off the vertical (~1.1 mm per pixel): a
# chrome-plated tray perforated with 3 mm holes on an 8 mm grid (~7 px), six glazed amber buns
# (glossy domes), five ring doughnuts, three with chocolate glaze and sprinkles (1.4 mm across,
# 5-7 mm long: ~1.3 x 4.5-6 px), two with pink icing, two paper doilies (rings), a chalkboard
# with thin pink, cyan and yellow chalk lines on a slate-green counter; two warm spot lamps and
# a window light from the left (polarized: degree 0.4)

BAKERY_CAMERA = {"position": [0.02, -0.5, 0.6], "look_at": [0.0, 0.02, 0.0], "up": [0, 1, 0],
                 "focal_length_mm": 2.6, "f_number": 8}
SPRINKLES = ("sprinkle_red", "sprinkle_yellow", "sprinkle_green", "sprinkle_blue",
             "sprinkle_white")


def bakery_meshes():
    rng = random.Random(8409)
    out = {}
    holes = sl.Mesh("bakery, tray perforations", WRITER)
    for i in range(int(0.36 / 0.008)):
        for j in range(int(0.26 / 0.008)):
            sl.disc(holes, [-0.18 + 0.004 + 0.008 * i, -0.13 + 0.004 + 0.008 * j, 0.0101], UP,
                    0.0015, 6)
    out["bakery_holes.obj"] = holes.text()
    buns = sl.Mesh("bakery, glazed buns", WRITER)
    for q, c in enumerate(([-0.12, 0.07], [-0.04, 0.08], [-0.12, -0.02], [-0.04, -0.01],
                           [-0.125, -0.09], [-0.045, -0.085])):
        r = 0.034 + 0.004 * (q % 2)
        prof = [(r * math.cos(0.5 * math.pi * k / 8), 0.9 * r * math.sin(0.5 * math.pi * k / 8))
                for k in range(9)]
        sl.lathe(buns, [c[0], c[1], 0.0105], prof, 24)
    out["bakery_buns.obj"] = buns.text()
    dough = sl.Mesh("bakery, doughnut sides", WRITER)
    choc = sl.Mesh("bakery, chocolate glaze", WRITER)
    pink = sl.Mesh("bakery, pink icing", WRITER)
    spr = {n: sl.Mesh("bakery, " + n + "s", WRITER) for n in SPRINKLES}
    for q, c in enumerate(([0.05, 0.07], [0.13, 0.06], [0.06, -0.03], [0.135, -0.04],
                           [0.09, -0.1])):
        cc = [c[0], c[1], 0.03]
        sl.torus(dough, cc, UP, 0.028, 0.017, 32, 10)
        # the glaze: a thin cap torus a little above the top
        glaze = choc if q % 2 == 0 else pink
        sl.torus(glaze, [c[0], c[1], 0.036], UP, 0.028, 0.0125, 32, 8)
        if q % 2 == 0:
            for k in range(70):
                a = rng.uniform(0, 2 * math.pi)
                rr = 0.028 + rng.uniform(-0.011, 0.011)
                z = 0.036 + math.sqrt(max(0.0, 0.0125 ** 2 - (rr - 0.028) ** 2)) + 0.0004
                p = [c[0] + rr * math.cos(a), c[1] + rr * math.sin(a), z]
                b = rng.uniform(0, math.pi)
                ln = rng.uniform(0.005, 0.007)
                d = [0.5 * ln * math.cos(b), 0.5 * ln * math.sin(b), 0.0]
                snake(spr[SPRINKLES[k % 5]], [cg.add(p, d, -1), cg.add(p, d, 1)], 0.0007, 5)
    out["bakery_dough.obj"] = dough.text()
    out["bakery_choc.obj"] = choc.text()
    out["bakery_pink.obj"] = pink.text()
    out.update({"bakery_" + n + ".obj": m.text() for n, m in spr.items()})
    # chalkboard lines: script-like loops and underlines in three chalks, 1-2 mm wide
    chalk = {n: sl.Mesh("bakery, " + n + " lines", WRITER)
             for n in ("chalk_pink", "chalk_cyan", "chalk_yellow")}
    for row in range(6):
        name = ("chalk_pink", "chalk_cyan", "chalk_yellow")[row % 3]
        y = 0.12 - 0.025 * row
        x = 0.2
        pts = []
        while x < 0.31:
            pts.append([x, y + 0.006 * math.sin(95 * x + row), 0.0025])
            x += 0.003
        sl.strip(chalk[name], pts, rng.uniform(0.0012, 0.002), UP)
        sl.strip(chalk[name], [[0.2, y - 0.011, 0.0025], [0.28 + 0.01 * (row % 2), y - 0.011,
                                                           0.0025]], 0.0012, UP)
    out.update({"bakery_" + n + ".obj": m.text() for n, m in chalk.items()})
    doily = sl.Mesh("bakery, doilies", WRITER)
    for c in ([-0.27, 0.05], [-0.27, -0.11]):
        for k in range(12):
            ring_flat(doily, [c[0], c[1], 0.0015], UP, 0.012 + 0.005 * k, 0.0025, 40)
    out["bakery_doily.obj"] = doily.text()
    return out


def bakery_parts():
    m = materials()
    m.paint("counter_laminate", 0.15)
    m.metal("tray_chrome", 0.12)
    m.paint("hole_dark", 0.5)
    m.paint("glaze_amber", 0.03)
    m.paint("pastry_crumb", 0.5)
    m.paint("choc", 0.03)
    m.paint("icing_pink", 0.05)
    m.many(SPRINKLES, 0.1)
    m.paint("chalkboard", 0.4)
    m.many(("chalk_pink", "chalk_cyan", "chalk_yellow"), 0.7)
    m.paint("doily", 0.5)
    objs = [cg.ground("counter_laminate"),
            sl.box([0.0, 0.0, 0.005], [0.36, 0.26, 0.01], "tray_chrome"),
            cg.rect([0.255, 0.06, 0.002], UP, [1, 0, 0], [0.13, 0.17], "chalkboard")]
    for n, mat, smooth in (("holes", "hole_dark", False), ("buns", "glaze_amber", True),
                           ("dough", "pastry_crumb", True), ("choc", "choc", True),
                           ("pink", "icing_pink", True), ("doily", "doily", False),
                           ("chalk_pink", "chalk_pink", False), ("chalk_cyan", "chalk_cyan", False),
                           ("chalk_yellow", "chalk_yellow", False)):
        objs.append(sl.mesh_object("bakery_" + n + ".obj", mat, smooth))
    for n in SPRINKLES:
        objs.append(sl.mesh_object("bakery_" + n + ".obj", n, True))
    lights = [{"type": "point", "position": [-0.15, 0.25, 0.9], "intensity_w_sr": [22, 19, 14]},
              {"type": "point", "position": [0.2, 0.3, 0.9], "intensity_w_sr": [22, 19, 14]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.85, 0.3, 0.45])),
               "irradiance_w_m2": [40, 45, 55], "polarization": {"linear_deg": 30, "dop": 0.4}}]
    return m, objs, lights


def bakery():
    m, objs, lights = bakery_parts()
    return scene("bakery", "a pastry counter from above (a perforated tray, glazed buns, "
                 "doughnuts with chocolate glaze and sprinkles or pink icing, doilies, a "
                 "chalkboard)", BAKERY_CAMERA, lights, m, objs, background=[1, 1, 1])


def bakery_g2():
    m, objs, lights = bakery_parts()
    return scene("bakery_g2", "the bakery scene through the IMX250MYR preset at +2 dB analog "
                 "gain", BAKERY_CAMERA, lights, m, objs, preset="imx250myr", gain_db=2,
                 background=[1, 1, 1])


SCENES = {"wool": wool, "pool": pool, "bus": bus, "bakery": bakery, "bakery_g2": bakery_g2,
          "bus_g14": bus_g14}


def meshes():
    out = {}
    out.update(wool_meshes())
    out.update(pool_meshes())
    out.update(bus_meshes())
    out.update(bakery_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
