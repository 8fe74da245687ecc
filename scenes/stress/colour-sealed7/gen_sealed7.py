#!/usr/bin/env python3
"""Writes the seventh sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed7.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed7.py --print NAME` prints one scene instead.
The generic helpers (millimetre meshes, prisms, tori, lathes, ribbons, materials) are
../colour-sealed6/sealed_lib.py, imported from there (that directory is frozen by its seal; it
is read, never written); the colour sensor, the scene record, rect and the writer are
../colour_gen.py's. The few helpers sealed_lib lacks (a lathe about any axis, a box as mesh
facets, a chain of tubes along a polyline, a ring of ribbon) are below.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). "Nickel", "zinc" and "bronze" are assumed metals of the right
order (n - ik per channel at 610, 530 and 465 nm, from memory, not a table lookup); no metal of
the other sets is reused. None of the paints, meshes, cameras or layouts of the other colour
sets is reused.

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
WRITER = "gen_sealed7.py"
UP = [0, 0, 1]

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # court: a hard tennis court seen from beside the net post
    "court_blue": [0.1, 0.28, 0.72], "court_green": [0.22, 0.58, 0.28],
    "court_line": [1.58, 1.6, 1.56], "net_cord": [0.035, 0.035, 0.04],
    "net_tape": [1.55, 1.57, 1.55], "ball_felt": [1.3, 1.6, 0.12], "windbreak": [0.04, 0.16, 0.09],
    "banner_navy": [0.05, 0.07, 0.33], "banner_print": [1.5, 1.5, 1.45],
    "bench_red": [1.25, 0.1, 0.09], "racket_frame": [1.55, 0.3, 0.04],
    "racket_string": [1.5, 1.45, 0.35], "cone_orange": [1.65, 0.4, 0.03],
    "cone_yellow": [1.6, 1.35, 0.06], "cone_blue": [0.07, 0.18, 1.0],
    "cone_red": [1.2, 0.05, 0.25], "kids_line": [1.6, 0.55, 0.05], "bag_purple": [0.55, 0.1, 0.7],
    # tackle: an open tackle box on a shop counter, seen from above
    "counter_slate": [0.16, 0.2, 0.26], "tray_grey": [0.2, 0.2, 0.22],
    "tray_wall": [0.28, 0.28, 0.3], "worm_chartreuse": [1.15, 1.65, 0.1],
    "worm_pink": [1.65, 0.25, 0.85], "worm_purple": [0.35, 0.08, 0.75],
    "worm_oil": [0.5, 0.42, 0.12], "bait_lime": [0.7, 1.5, 0.12], "bait_bar": [0.06, 0.12, 0.05],
    "bait_belly": [1.6, 0.45, 0.08], "bait_white": [1.55, 1.55, 1.5],
    "float_red": [1.5, 0.06, 0.05], "line_yellow": [1.65, 1.55, 0.05],
    "line_red": [1.5, 0.08, 0.12], "line_clear": [0.7, 0.9, 0.9], "spoon_red": [1.45, 0.09, 0.06],
    "tag_white": [1.6, 1.6, 1.58], "tag_ink": [0.05, 0.05, 0.07],
    # greenhouse: a slatted bench of seedling trays, pots and a watering can
    "cedar_a": [1.2, 0.7, 0.42], "cedar_b": [1.05, 0.6, 0.34], "tray_black": [0.045, 0.045, 0.05],
    "compost": [0.16, 0.1, 0.06], "seedling_green": [0.22, 0.7, 0.12],
    "seedling_red": [0.62, 0.14, 0.16], "seedling_pale": [0.6, 1.1, 0.28],
    "clay": [1.15, 0.45, 0.24], "glass_pane": [0.02, 0.025, 0.025], "gravel": [0.75, 0.7, 0.62],
    "stick_white": [1.55, 1.55, 1.5], "stick_ink": [0.06, 0.06, 0.07],
    "packet_a": [1.6, 0.9, 0.05], "packet_b": [0.08, 0.55, 1.2], "packet_c": [1.4, 0.12, 0.6],
    "glove_blue": [0.06, 0.3, 0.9],
    # pews: a parish church's nave down the aisle, sun through the south windows
    "oak_dark": [0.42, 0.24, 0.12], "oak_end": [0.5, 0.3, 0.15], "limewash": [1.45, 1.4, 1.25],
    "flag_a": [0.85, 0.8, 0.72], "flag_b": [0.7, 0.68, 0.64], "flag_joint": [0.25, 0.24, 0.22],
    "runner_red": [0.95, 0.06, 0.08], "runner_gold": [1.4, 1.0, 0.2],
    "book_navy": [0.05, 0.08, 0.4], "book_maroon": [0.6, 0.05, 0.1],
    "book_green": [0.05, 0.35, 0.15], "kneeler_a": [0.1, 0.45, 0.5], "kneeler_b": [1.2, 0.75, 0.1],
    "altar_cloth": [1.6, 1.6, 1.55], "dossal": [0.9, 0.04, 0.12], "pipe_shade": [0.3, 0.12, 0.06],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "nickel": {"n": [1.95, 1.8, 1.7], "k": [3.8, 3.5, 3.2]},
    "zinc": {"n": [1.4, 1.1, 0.9], "k": [5.2, 4.8, 4.2]},
    "bronze": {"n": [0.95, 1.12, 1.3], "k": [3.1, 2.55, 2.15]},
    "pipe_metal": {"n": [1.7, 1.6, 1.5], "k": [3.4, 3.3, 3.1]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "court": 450,
    "tackle": 9000,
    "greenhouse": 2500,
    "pews": 12000,
    "court_g5": 200,
    "pews_g23": 1300,
}


def materials():
    return sl.Materials(PAINTS, METALS)


def scene(name, title, camera, lights, mats, objs, preset="ideal", **extra):
    sen = cg.sensor(EXPOSURE[name], preset, **({"gain_db": extra.pop("gain_db")}
                                                  if "gain_db" in extra else {}))
    s = cg.scene("colour sealed 7: " + title, camera, lights, mats.used, objs, cg.EFFECTS, sen)
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


def snake(mesh, pts, radius, sides=8):
    """A chain of tubes along the polyline pts (a soft-plastic worm, a hook's wire)."""
    for a, b in zip(pts, pts[1:]):
        sl.tube(mesh, a, b, radius, sides, caps=False)


def ring_ribbon(mesh, c, r, width, n=48, z=None):
    """A flat horizontal ring of ribbon (a coil of line lying on the counter)."""
    pts = [[c[0] + r * math.cos(2 * math.pi * i / n), c[1] + r * math.sin(2 * math.pi * i / n),
            c[2] if z is None else z] for i in range(n + 1)]
    sl.strip(mesh, pts, width, UP)


# ---------------------------------------------------------------------------------------------
# court: a hard tennis court seen from beside the net post, ~1.6 m up: the net's 45 mm mesh of
# black cord runs away from the camera (about 16 px near the post, 3 px at the far post), white
# lines 50 mm (2-8 px), a blue playing area in a green surround, orange mini-tennis lines,
# balls, a racket (strings ~12 mm), a red bench, a dark green windbreak with a printed banner;
# an afternoon sun from the far left, ~50° up (the net's shadow on the near court), a polarized sky

COURT_CAMERA = {"position": [6.9, -3.4, 1.55], "look_at": [-0.6, 1.2, 0.45], "up": UP,
                "focal_length_mm": 2.4, "f_number": 8}


CONES = ("cone_orange", "cone_yellow", "cone_blue", "cone_red")


def net_top(x):
    """The net's height at x (1.07 m at the posts at x = +-6.4, 0.914 m at the centre)."""
    return 0.914 + 0.156 * (x / 6.4) ** 2


def court_meshes():
    rng = random.Random(7101)
    out = {}
    lines = sl.Mesh("court, white lines", WRITER)
    w = 0.05

    def line(x0, y0, x1, y1):
        if x0 == x1:
            lines.flat([[x0 - w / 2, y0, 0.002], [x0 + w / 2, y0, 0.002], [x0 + w / 2, y1, 0.002],
                        [x0 - w / 2, y1, 0.002]])
        else:
            lines.flat([[x0, y0 - w / 2, 0.002], [x1, y0 - w / 2, 0.002], [x1, y0 + w / 2, 0.002],
                        [x0, y0 + w / 2, 0.002]])

    for s in (-1, 1):
        line(s * 5.485, -11.885, s * 5.485, 11.885)
        line(s * 4.115, -11.885, s * 4.115, 11.885)
        line(-5.485, s * 11.885, 5.485, s * 11.885)
        line(-4.115, s * 6.4, 4.115, s * 6.4)
    line(0, -6.4, 0, 6.4)
    out["court_lines.obj"] = lines.text()
    # mini-tennis lines (orange, 40 mm) across the near half, curved corners of a junior court
    kids = sl.Mesh("court, orange mini-tennis lines", WRITER)
    for y in (-1.2, -2.6):
        kids.flat([[-3.0, y - 0.02, 0.0025], [3.0, y - 0.02, 0.0025], [3.0, y + 0.02, 0.0025],
                   [-3.0, y + 0.02, 0.0025]])
    arc = [[2.0 + 1.2 * math.cos(math.pi * k / 24), -2.6 + 1.2 * math.sin(math.pi * k / 24),
            0.0025] for k in range(25)]
    sl.strip(kids, arc, 0.04, UP)
    out["court_kids.obj"] = kids.text()
    # the net: cords 3 mm on a 45 mm mesh, the white tape (50 mm) and the centre strap
    cord = sl.Mesh("court, net cords", WRITER)
    tape = sl.Mesh("court, net tape and strap", WRITER)
    n = int(12.8 / 0.045)
    for i in range(n + 1):
        x = -6.4 + 0.045 * i
        sl.strip(cord, [[x, 0.0, 0.03], [x, 0.0, net_top(x) - 0.02]], 0.003, [0, 1, 0])
    z = 0.05
    while z < 1.05:
        if z < 0.914 - 0.02:
            sl.strip(cord, [[-6.4, 0.001, z], [6.4, 0.001, z]], 0.003, [0, 1, 0])
        else:
            xe = 6.4 * math.sqrt((z + 0.02 - 0.914) / 0.156)
            for s in (-1, 1):
                sl.strip(cord, [[s * xe, 0.001, z], [s * 6.4, 0.001, z]], 0.003, [0, 1, 0])
        z += 0.045
    xs = [-6.4 + 0.4 * k for k in range(33)]
    sl.strip(tape, [[x, -0.002, net_top(x) - 0.02] for x in xs], 0.05, [0, 1, 0])
    tape.flat([[-0.025, -0.002, 0.0], [0.025, -0.002, 0.0], [0.025, -0.002, 0.89],
               [-0.025, -0.002, 0.89]])
    out["court_cord.obj"] = cord.text()
    out["court_tape.obj"] = tape.text()
    # zinc-coated posts and the winder, the bench's frame
    posts = sl.Mesh("court, posts", WRITER)
    for s in (-1, 1):
        sl.tube(posts, [s * 6.4, 0.0, 0.0], [s * 6.4, 0.0, 1.1], 0.04, 16)
        sl.tube(posts, [s * 6.4, -0.04, 0.6], [s * 6.4, -0.16, 0.6], 0.008, 8)
    for x in (-2.2, -0.4):
        sl.tube(posts, [x, 14.0, 0.0], [x, 14.0, 0.45], 0.02, 10)
    # the windbreak banner's print: block letters of 0.3 m strokes 60 mm wide
    prints = sl.Mesh("court, banner print", WRITER)
    x = -4.6
    while x < 3.5:
        wdt = rng.uniform(0.04, 0.08)
        prints.flat([[x, 17.97, 1.45], [x + wdt, 17.97, 1.45], [x + wdt, 17.97, 1.8],
                     [x, 17.97, 1.8]])
        if rng.random() < 0.5:
            prints.flat([[x, 17.97, 1.76], [x + 0.2, 17.97, 1.76], [x + 0.2, 17.97, 1.8],
                         [x, 17.97, 1.8]])
        x += wdt + rng.uniform(0.05, 0.22)
    out["court_print.obj"] = prints.text()
    out["court_posts.obj"] = posts.text()
    # a racket on the near court: an oval frame, strings on ~12 mm
    frame = sl.Mesh("court, racket frame", WRITER)
    strings = sl.Mesh("court, racket strings", WRITER)
    rc, ra, rb = [4.2, -1.6, 0.015], 0.17, 0.13
    pts = [[rc[0] + ra * math.cos(2 * math.pi * k / 40),
            rc[1] + rb * math.sin(2 * math.pi * k / 40), rc[2]] for k in range(41)]
    snake(frame, pts, 0.011, 8)
    sl.tube(frame, [rc[0] - ra, rc[1], rc[2]], [rc[0] - ra - 0.33, rc[1] - 0.05, rc[2]], 0.016, 8)
    for k in range(-12, 13):
        x = rc[0] + 0.0125 * k
        h = rb * math.sqrt(max(0.0, 1 - (0.0125 * k / ra) ** 2))
        sl.strip(strings, [[x, rc[1] - h, 0.016], [x, rc[1] + h, 0.016]], 0.0018, UP)
    for k in range(-9, 10):
        y = rc[1] + 0.0125 * k
        h = ra * math.sqrt(max(0.0, 1 - (0.0125 * k / rb) ** 2))
        sl.strip(strings, [[rc[0] - h, y, 0.017], [rc[0] + h, y, 0.017]], 0.0018, UP)
    out["court_racket.obj"] = frame.text()
    # training cones (lathes) in four colours along the near service area
    for q, n in enumerate(CONES):
        cone = sl.Mesh("court, " + n + " cones", WRITER)
        for k in range(3):
            c = [-3.0 + 1.9 * k + 0.45 * q, -0.9 - 0.5 * q - 0.3 * k, 0.0]
            sl.lathe(cone, c, [(0.0, 0.0), (0.09, 0.0), (0.09, 0.012), (0.03, 0.17),
                               (0.0, 0.175)], 20)
        out["court_" + n + ".obj"] = cone.text()
    out["court_strings.obj"] = strings.text()
    return out


def court_parts():
    rng = random.Random(7111)
    m = materials()
    m.paint("court_green", 0.25)
    m.paint("court_blue", 0.25)
    m.many(CONES, 0.1)
    m.many(("court_line", "kids_line"), 0.2)
    m.paint("net_cord", 0.3)
    m.paint("net_tape", 0.25)
    m.paint("ball_felt", 0.6)
    m.paint("windbreak", 0.5)
    m.many(("banner_navy", "banner_print"), 0.2)
    m.paint("bench_red", 0.05)
    m.paint("racket_frame", 0.04)
    m.paint("racket_string", 0.2)
    m.paint("bag_purple", 0.3)
    m.metal("zinc", 0.1)
    objs = [cg.ground("court_green"),
            cg.rect([0, 0, 0.001], UP, [1, 0, 0], [10.97, 23.77], "court_blue"),
            cg.rect([0, 18.0, 1.5], [0, -1, 0], [1, 0, 0], [30.0, 3.0], "windbreak"),
            cg.rect([-0.5, 17.98, 1.62], [0, -1, 0], [1, 0, 0], [9.0, 0.6], "banner_navy")]
    for n, mat, smooth in (("lines", "court_line", False), ("kids", "kids_line", False),
                           ("cord", "net_cord", False), ("tape", "net_tape", False),
                           ("posts", "zinc", True), ("print", "banner_print", False),
                           ("racket", "racket_frame", True), ("strings", "racket_string", False)):
        objs.append(sl.mesh_object("court_" + n + ".obj", mat, smooth))
    for n in CONES:
        objs.append(sl.mesh_object("court_" + n + ".obj", n, True))
    for q in range(26):
        if q < 14:
            c = [rng.uniform(-1.0, 5.5), rng.uniform(-3.0, -0.3), 0.0335]
        else:
            c = [rng.uniform(-4.0, 4.0), rng.uniform(0.5, 9.0), 0.0335]
        objs.append(sl.sphere(c, 0.0335, "ball_felt"))
    objs.append(sl.box([-1.3, 14.0, 0.47], [2.2, 0.4, 0.04], "bench_red"))
    objs.append(sl.box([-1.3, 14.18, 0.75], [2.2, 0.04, 0.3], "bench_red"))
    objs.append(sl.box([5.9, -1.0, 0.16], [0.75, 0.3, 0.32], "bag_purple", yaw=25))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.45, 0.55, 0.7])),
               "irradiance_w_m2": [560, 520, 450]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.4, -0.2, 0.9])),
               "irradiance_w_m2": [70, 90, 130],
               "polarization": {"linear_deg": 60, "dop": 0.4}}]
    return m, objs, lights


def court():
    m, objs, lights = court_parts()
    return scene("court", "a hard tennis court seen from beside the net post (the net's mesh "
                 "from ~16 to ~3 px, white lines, a blue court in a green surround, balls, a "
                 "racket, a bench, a windbreak with a banner) in an afternoon sun",
                 COURT_CAMERA, lights, m, objs, background=[30, 40, 60])


def court_g5():
    m, objs, lights = court_parts()
    return scene("court_g5", "the court scene through the IMX250MYR preset at +5 dB analog "
                 "gain (a fast shutter for the players)", COURT_CAMERA, lights, m, objs,
                 preset="imx250myr", gain_db=5, background=[30, 40, 60])


# ---------------------------------------------------------------------------------------------
# tackle: an open tackle box on a slate-blue shop counter seen from above (~0.8 mm per pixel): a
# dark tray of compartments holding soft-plastic worms (chartreuse, pink, purple, motor oil),
# crankbaits with painted bars (~4-7 px), nickel spoons, floats, hooks and swivels; hanks of
# hi-vis line (0.6 mm strands ~3 px apart) lying on the counter; two overhead tubes and a
# window on the left

TACKLE_CAMERA = {"position": [0.03, -0.22, 0.6], "look_at": [0.0, 0.0, 0.0], "up": [0, 1, 0],
                 "focal_length_mm": 2.6, "f_number": 8}
WORMS = ("worm_chartreuse", "worm_pink", "worm_purple", "worm_oil")


def tackle_meshes():
    rng = random.Random(7203)
    out = {}
    walls = sl.Mesh("tackle, tray walls", WRITER)
    x0, x1, y0, y1, h = -0.17, 0.15, -0.11, 0.12, 0.035
    for x in (x0, -0.06, 0.05, x1):
        box_mesh(walls, [x, (y0 + y1) / 2, h / 2], [0.003, y1 - y0, h])
    for y in (y0, 0.0, y1):
        box_mesh(walls, [(x0 + x1) / 2, y, h / 2], [x1 - x0, 0.003, h])
    out["tackle_walls.obj"] = walls.text()
    worms = {n: sl.Mesh("tackle, " + n + " worms", WRITER) for n in WORMS}
    for q in range(14):
        c = [rng.uniform(-0.16, -0.075), rng.uniform(-0.1, -0.015)]
        a, ln = rng.uniform(0, 6.3), rng.uniform(0.07, 0.11)
        wav, ph = rng.uniform(8, 25), rng.uniform(0, 6.3)
        pts = []
        for k in range(13):
            t = (k / 12 - 0.5) * ln
            off = 0.006 * math.sin(ph + wav * t)
            pts.append([c[0] + t * math.cos(a) - off * math.sin(a),
                        c[1] + t * math.sin(a) + off * math.cos(a), 0.006 + 0.0008 * q])
        snake(worms[WORMS[q % 4]], pts, rng.uniform(0.0018, 0.0032), 8)
    out.update({"tackle_" + n + ".obj": m.text() for n, m in worms.items()})
    # crankbaits: bodies of alternating bands (bars ~3.5 mm) about a horizontal axis
    body = sl.Mesh("tackle, crankbait bodies", WRITER)
    bars = sl.Mesh("tackle, crankbait bars", WRITER)
    belly = sl.Mesh("tackle, crankbait bellies and lips", WRITER)
    for q in range(5):
        c = [-0.045 + 0.02 * (q % 2), -0.095 + 0.02 * q, 0.012]
        ax = cg.unit([math.cos(0.3 * q - 0.2), math.sin(0.3 * q - 0.2), 0])
        ln = 0.07
        prof = [(0.012 * math.sin(math.pi * max(0.02, min(0.98, k / 14))), ln * (k / 14 - 0.5))
                for k in range(15)]
        for k in range(14):
            seg = bars if (k % 3 == 1 and 3 <= k <= 11) else body
            lathe_axis(seg, c, ax, prof[k:k + 2], 16)
        box_mesh(belly, cg.add(c, ax, 0.042), [0.016, 0.014, 0.002], math.degrees(0.3 * q - 0.2))
    out["tackle_body.obj"] = body.text()
    out["tackle_bars.obj"] = bars.text()
    out["tackle_belly.obj"] = belly.text()
    # nickel spoons (ovals tilted a little), swivels, hooks
    nickel = sl.Mesh("tackle, spoons, swivels, hooks", WRITER)
    red = sl.Mesh("tackle, spoons' red stripes", WRITER)
    for q in range(7):
        c = [0.07 + 0.012 * q, -0.09 + 0.013 * q, 0.008]
        a = rng.uniform(0, 3.1)
        ca, sa = math.cos(a), math.sin(a)
        tilt = rng.uniform(-0.25, 0.25)
        pts = []
        for k in range(16):
            t = 2 * math.pi * k / 16
            u, v = 0.03 * math.cos(t), 0.011 * math.sin(t)
            # tilted about the long axis and dished a little (its ends 0.3 mm up)
            pts.append([c[0] + u * ca - v * sa, c[1] + u * sa + v * ca,
                        c[2] + tilt * v + 0.1 * abs(u) * 0.1])
        nickel.flat(pts)
        if q % 2:
            red.flat([[c[0] + (s * 0.004) * ca - (t * 0.008) * sa,
                       c[1] + (s * 0.004) * sa + (t * 0.008) * ca,
                       c[2] + tilt * t * 0.008 + 0.0015]
                      for s, t in ((-1, -1), (1, -1), (1, 1), (-1, 1))])
    for q in range(9):
        c = [rng.uniform(0.065, 0.14), rng.uniform(0.02, 0.1), 0.003]
        sl.torus(nickel, c, UP, 0.003, 0.0007, 12, 5)
        hook = [[c[0] + 0.004, c[1], 0.003], [c[0] + 0.03, c[1] + 0.004, 0.003],
                [c[0] + 0.036, c[1] + 0.012, 0.003], [c[0] + 0.03, c[1] + 0.018, 0.003],
                [c[0] + 0.024, c[1] + 0.012, 0.003]]
        snake(nickel, hook, 0.0005, 5)
    out["tackle_nickel.obj"] = nickel.text()
    out["tackle_red.obj"] = red.text()
    # floats: red tops and white bottoms, lying on their sides
    ftop = sl.Mesh("tackle, float tops", WRITER)
    fbot = sl.Mesh("tackle, float bottoms", WRITER)
    for q in range(6):
        c = [-0.15 + 0.025 * q, 0.03 + 0.012 * (q % 3), 0.011]
        ax = cg.unit([0.3, 1, 0])
        prof = [(0.011 * math.sin(math.pi * k / 12), 0.022 * (k / 12 - 0.5)) for k in range(13)]
        lathe_axis(ftop, c, ax, prof[:7], 16)
        lathe_axis(fbot, c, ax, prof[6:], 16)
        sl.tube(fbot, cg.add(c, ax, -0.011), cg.add(c, ax, -0.03), 0.0012, 6)
    out["tackle_ftop.obj"] = ftop.text()
    out["tackle_fbot.obj"] = fbot.text()
    # hanks of line on the counter: rings of 0.6 mm strand ~2.5 mm apart
    for name, c in (("yellow", [0.24, 0.05]), ("red", [0.22, -0.1]), ("clear", [-0.25, -0.05])):
        hank = sl.Mesh("tackle, " + name + " line", WRITER)
        for k in range(10):
            ring_ribbon(hank, [c[0] + rng.gauss(0, 0.001), c[1] + rng.gauss(0, 0.001), 0.0004],
                        0.035 + 0.0025 * k, 0.0006, 56)
        out["tackle_line_" + name + ".obj"] = hank.text()
    # a price tag with printed figures
    ink = sl.Mesh("tackle, tag print", WRITER)
    x = 0.185
    while x < 0.27:
        w = rng.uniform(0.0008, 0.002)
        ink.flat([[x, 0.118, 0.0006], [x + w, 0.118, 0.0006], [x + w, 0.128, 0.0006],
                  [x, 0.128, 0.0006]])
        x += w + rng.uniform(0.001, 0.003)
    out["tackle_ink.obj"] = ink.text()
    return out


def tackle():
    m = materials()
    m.paint("counter_slate", 0.1)
    m.paint("tray_grey", 0.08)
    m.paint("tray_wall", 0.08)
    m.many(WORMS, 0.05)
    m.many(("bait_lime", "bait_bar", "bait_belly"), 0.03)
    m.many(("line_yellow", "line_red", "line_clear"), 0.1)
    m.many(("float_red", "bait_white"), 0.04)
    m.paint("spoon_red", 0.08)
    m.metal("nickel", 0.05)
    m.many(("tag_white", "tag_ink"), 0.5)
    objs = [cg.ground("counter_slate"),
            cg.rect([-0.01, 0.005, 0.001], UP, [1, 0, 0], [0.32, 0.23], "tray_grey"),
            cg.rect([0.225, 0.123, 0.0004], UP, [1, 0, 0], [0.1, 0.03], "tag_white")]
    for n, mat, smooth in (("walls", "tray_wall", False), ("body", "bait_lime", True),
                           ("bars", "bait_bar", True), ("belly", "bait_belly", False),
                           ("nickel", "nickel", False), ("red", "spoon_red", False),
                           ("ftop", "float_red", True), ("fbot", "bait_white", True),
                           ("line_yellow", "line_yellow", False), ("line_red", "line_red", False),
                           ("line_clear", "line_clear", False), ("ink", "tag_ink", False)):
        objs.append(sl.mesh_object("tackle_" + n + ".obj", mat, smooth))
    for n in WORMS:
        objs.append(sl.mesh_object("tackle_" + n + ".obj", n, True))
    lights = [{"type": "point", "position": [-0.1, 0.1, 1.4], "intensity_w_sr": [9, 10, 10.5]},
              {"type": "point", "position": [0.25, 0.1, 1.4], "intensity_w_sr": [9, 10, 10.5]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.9, 0.2, 0.45])),
               "irradiance_w_m2": [40, 44, 52], "polarization": {"linear_deg": 20, "dop": 0.3}}]
    return scene("tackle", "an open tackle box on a shop counter seen from above (soft-plastic "
                 "worms, barred crankbaits, nickel spoons, floats, hooks, hanks of hi-vis line "
                 "~3 px apart)", TACKLE_CAMERA, lights, m, objs, background=[1, 1, 1])


# ---------------------------------------------------------------------------------------------
# greenhouse: a slatted cedar bench (slats 28 mm, gaps 9 mm) with two module trays of
# seedlings (cells 24 mm: ~13 px; green, red-leaved and pale seedlings of 3-6 px leaves on dark
# compost), clay pots, a zinc watering can, seed packets, white plant labels; the greenhouse's
# glass behind in zinc glazing bars, gravel below; a high sun and the sky

GREEN_CAMERA = {"position": [-0.15, -0.95, 1.6], "look_at": [0.05, 0.3, 0.75], "up": UP,
                "focal_length_mm": 2.4, "f_number": 8}
SEEDLINGS = ("seedling_green", "seedling_red", "seedling_pale")


def greenhouse_meshes():
    rng = random.Random(7307)
    out = {}
    slats = {n: sl.Mesh("greenhouse, " + n + " slats", WRITER) for n in ("cedar_a", "cedar_b")}
    for i in range(17):
        y = -0.28 + 0.037 * i
        slats[("cedar_a", "cedar_b")[i % 2]].flat([[-0.9, y, 0.8], [0.9, y, 0.8],
                                                   [0.9, y + 0.028, 0.8], [-0.9, y + 0.028, 0.8]])
    out.update({"greenhouse_" + n + ".obj": m.text() for n, m in slats.items()})
    rims = sl.Mesh("greenhouse, module tray rims", WRITER)
    leaves = {n: sl.Mesh("greenhouse, " + n + " leaves", WRITER) for n in SEEDLINGS}
    for t, (tx, kind) in enumerate(((-0.42, 0), (-0.05, 1))):
        for i in range(13):
            x = tx + 0.024 * i
            sl.strip(rims, [[x, -0.2, 0.845], [x, 0.16, 0.845]], 0.0025, UP)
        for j in range(16):
            y = -0.2 + 0.024 * j
            sl.strip(rims, [[tx, y, 0.845], [tx + 0.288, y, 0.845]], 0.0025, UP)
        for i in range(12):
            for j in range(15):
                if rng.random() < 0.12:
                    continue
                if kind == 0:
                    name = SEEDLINGS[(i // 4) % 2 * 2]
                else:
                    name = SEEDLINGS[1] if (i + j // 3) % 2 else SEEDLINGS[0]
                c = [tx + 0.012 + 0.024 * i, -0.188 + 0.024 * j, 0.846]
                for leaf in range(rng.choice((2, 2, 3, 4))):
                    a = rng.uniform(0, 6.3)
                    r = rng.uniform(0.003, 0.007)
                    lc = [c[0] + 0.6 * r * math.cos(a), c[1] + 0.6 * r * math.sin(a),
                          c[2] + rng.uniform(0.004, 0.02)]
                    sl.disc(leaves[name], lc, cg.unit([math.cos(a) * 0.6, math.sin(a) * 0.6, 1]),
                            r, 7, rng.uniform(0, 1))
    out["greenhouse_rims.obj"] = rims.text()
    pots = sl.Mesh("greenhouse, clay pots", WRITER)
    for c, r in (([0.38, -0.1, 0.8], 0.06), ([0.52, 0.0, 0.8], 0.05), ([0.45, 0.16, 0.8], 0.07),
                 ([0.65, -0.15, 0.8], 0.045)):
        sl.lathe(pots, c, [(0.0, 0.0), (0.7 * r, 0.0), (r, 1.6 * r), (1.1 * r, 1.6 * r),
                           (1.1 * r, 1.85 * r), (0.93 * r, 1.85 * r), (0.9 * r, 1.5 * r),
                           (0.0, 1.5 * r)], 28)
        for leaf in range(int(160 * r)):
            a = rng.uniform(0, 6.3)
            rr = rng.uniform(0, 0.8 * r)
            lc = [c[0] + rr * math.cos(a), c[1] + rr * math.sin(a), c[2] + 1.5 * r
                  + rng.uniform(0.01, 0.06)]
            sl.disc(leaves["seedling_green"], lc, cg.unit([rng.gauss(0, 0.6), rng.gauss(0, 0.6),
                                                           1]), rng.uniform(0.005, 0.012), 6)
    out["greenhouse_pots.obj"] = pots.text()
    out.update({"greenhouse_" + n + ".obj": m.text() for n, m in leaves.items()})
    can = sl.Mesh("greenhouse, watering can and glazing bars", WRITER)
    sl.lathe(can, [0.1, 0.4, 0.8], [(0.0, 0.0), (0.1, 0.0), (0.105, 0.01), (0.105, 0.22),
                                       (0.09, 0.25), (0.0, 0.25)], 32)
    sl.tube(can, [0.18, 0.37, 0.85], [0.42, 0.34, 1.14], 0.011, 10)
    sl.torus(can, [0.1, 0.4, 1.1], [0, 1, 0], 0.09, 0.008, 32, 8)
    for i in range(7):
        x = -1.2 + 0.4 * i
        can.flat([[x - 0.012, 0.599, 0.8], [x + 0.012, 0.599, 0.8], [x + 0.012, 0.599, 2.4],
                  [x - 0.012, 0.599, 2.4]])
    for z in (1.2, 1.8):
        can.flat([[-1.4, 0.598, z - 0.012], [1.4, 0.598, z - 0.012], [1.4, 0.598, z + 0.012],
                  [-1.4, 0.598, z + 0.012]])
    out["greenhouse_zinc.obj"] = can.text()
    sticks = sl.Mesh("greenhouse, plant labels", WRITER)
    ink = sl.Mesh("greenhouse, plant label print", WRITER)
    for q in range(6):
        x, y = -0.4 + 0.065 * q, -0.21
        sticks.flat([[x, y, 0.85], [x + 0.016, y, 0.85], [x + 0.016, y, 0.93], [x, y, 0.93]])
        z = 0.86
        while z < 0.92:
            h = rng.uniform(0.001, 0.0025)
            ink.flat([[x + 0.004, y - 0.0005, z], [x + 0.012, y - 0.0005, z],
                      [x + 0.012, y - 0.0005, z + h], [x + 0.004, y - 0.0005, z + h]])
            z += h + rng.uniform(0.002, 0.004)
    out["greenhouse_sticks.obj"] = sticks.text()
    out["greenhouse_ink.obj"] = ink.text()
    return out


def greenhouse():
    m = materials()
    m.paint("gravel", 0.6)
    m.many(("cedar_a", "cedar_b"), 0.3)
    m.paint("tray_black", 0.07)
    m.paint("compost", 0.7)
    m.many(SEEDLINGS, 0.15)
    m.paint("clay", 0.45)
    m.paint("glass_pane", 0.01, n=1.52)
    m.metal("zinc", 0.07)
    m.many(("stick_white", "stick_ink"), 0.3)
    m.many(("packet_a", "packet_b", "packet_c"), 0.12)
    m.paint("glove_blue", 0.4)
    objs = [cg.ground("gravel"),
            cg.rect([0, 0.6, 1.6], [0, -1, 0], [1, 0, 0], [3.0, 1.6], "glass_pane"),
            cg.rect([0, 0.6, 0.4], [0, -1, 0], [1, 0, 0], [3.0, 0.8], "cedar_b")]
    for tx in (-0.42, -0.05):
        objs.append(sl.box([tx + 0.144, -0.02, 0.82], [0.288, 0.36, 0.05], "tray_black"))
        objs.append(cg.rect([tx + 0.144, -0.02, 0.8448], UP, [1, 0, 0], [0.288, 0.36], "compost"))
    for n, mat, smooth in (("cedar_a", "cedar_a", False), ("cedar_b", "cedar_b", False),
                           ("rims", "tray_black", False), ("pots", "clay", True),
                           ("zinc", "zinc", False), ("sticks", "stick_white", False),
                           ("ink", "stick_ink", False)):
        objs.append(sl.mesh_object("greenhouse_" + n + ".obj", mat, smooth))
    for n in SEEDLINGS:
        objs.append(sl.mesh_object("greenhouse_" + n + ".obj", n, False))
    for q, p in enumerate(("packet_a", "packet_b", "packet_c")):
        objs.append(sl.box([0.32 + 0.1 * q, -0.24, 0.803], [0.08, 0.12, 0.004], p, yaw=8 * q - 6))
    objs.append(sl.box([0.7, 0.15, 0.81], [0.2, 0.09, 0.02], "glove_blue", yaw=30))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([0.35, -0.55, 0.76])),
               "irradiance_w_m2": [480, 470, 430]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.3, 0.6, 0.74])),
               "irradiance_w_m2": [60, 75, 105],
               "polarization": {"linear_deg": 100, "dop": 0.6}}]
    return scene("greenhouse", "a slatted greenhouse bench of seedling trays (cells ~13 px, "
                 "green and red-leaved seedlings), clay pots, a zinc watering can, seed packets "
                 "and labels, the glass wall behind", GREEN_CAMERA, lights, m, objs,
                 background=[20, 24, 30])


# ---------------------------------------------------------------------------------------------
# pews: a parish church's nave seen down the aisle from the west door (~1.4 m up): rows of dark
# oak pews with bronze book rails, hymn books (spines ~4-8 px) and kneelers, a red runner with
# gold borders on stone flags, the chancel with an altar, candlesticks, a red dossal and the
# organ's front pipes (~9 px apart); the sun through three south windows (bright shafts on the
# pews), pendant lamps

PEWS_CAMERA = {"position": [0.25, -1.2, 1.45], "look_at": [-0.1, 10.0, 1.25], "up": UP,
               "focal_length_mm": 2.6, "f_number": 5.6}
BOOKS = ("book_navy", "book_maroon", "book_green")


def pews_meshes():
    rng = random.Random(7409)
    out = {}
    oak = sl.Mesh("pews, pews", WRITER)
    ends = sl.Mesh("pews, pew ends", WRITER)
    rails = sl.Mesh("pews, bronze rails, candlesticks, altar rail", WRITER)
    books = {n: sl.Mesh("pews, " + n + " hymn books", WRITER) for n in BOOKS}
    kneel = {n: sl.Mesh("pews, " + n + " kneelers", WRITER) for n in ("kneeler_a", "kneeler_b")}
    for row in range(9):
        y = 0.8 * row
        for s in (-1, 1):
            xa, xb = s * 0.75, s * 3.9
            cx, wd = (xa + xb) / 2, abs(xb - xa)
            box_mesh(oak, [cx, y, 0.44], [wd, 0.42, 0.05])
            box_mesh(oak, [cx, y + 0.23, 0.7], [wd, 0.05, 0.55])
            box_mesh(oak, [cx, y + 0.16, 0.92], [wd, 0.12, 0.02])
            box_mesh(ends, [xa + s * 0.03, y + 0.02, 0.5], [0.06, 0.52, 1.0])
            sl.tube(rails, [xa + s * 0.07, y + 0.2, 0.97], [xb, y + 0.2, 0.97], 0.009, 8, False)
            x = xa + s * 0.15
            while abs(x) < abs(xb) - 0.1:
                w = rng.uniform(0.025, 0.045)
                box_mesh(books[BOOKS[rng.randrange(3)]], [x, y + 0.16, 0.93 + 0.09],
                         [w, 0.1, 0.16], rng.gauss(0, 4))
                x += s * (w + rng.uniform(0.003, 0.03))
                if rng.random() < 0.05:
                    x += s * 0.25
            for k in range(4):
                xk = xa + s * (0.4 + 0.75 * k + rng.uniform(-0.1, 0.1))
                box_mesh(kneel[("kneeler_a", "kneeler_b")[(row + k) % 2]],
                         [xk, y + 0.3, 0.25], [0.36, 0.05, 0.22], rng.gauss(0, 3))
    # stone flags in the aisle and chancel (0.6 m) with 8 mm joints
    flags = {n: sl.Mesh("pews, " + n + " flags", WRITER) for n in ("flag_a", "flag_b")}
    for i in range(-2, 2):
        for j in range(-3, 25):
            x, yy = 0.6 * i + (0.3 if j % 2 else 0), 0.5 * j
            flags[("flag_a", "flag_b")[rng.random() < 0.45]].flat(
                [[x + 0.004, yy + 0.004, 0.001], [x + 0.596, yy + 0.004, 0.001],
                 [x + 0.596, yy + 0.496, 0.001], [x + 0.004, yy + 0.496, 0.001]])
    # the runner's gold borders (40 mm, 30 mm in from each edge) and a key pattern of bars
    gold = sl.Mesh("pews, runner borders", WRITER)
    for s in (-1, 1):
        sl.strip(gold, [[s * 0.37, -1.5, 0.004], [s * 0.37, 9.2, 0.004]], 0.04, UP)
    yy = -1.2
    while yy < 9.0:
        gold.flat([[-0.3, yy, 0.004], [0.3, yy, 0.004], [0.3, yy + 0.03, 0.004],
                   [-0.3, yy + 0.03, 0.004]])
        yy += 0.45
    # the chancel: altar rail, candlesticks, organ pipes at the east wall
    sl.tube(rails, [-2.4, 8.6, 0.85], [2.4, 8.6, 0.85], 0.02, 10, False)
    for k in range(13):
        sl.tube(rails, [-2.4 + 0.4 * k, 8.6, 0.2], [-2.4 + 0.4 * k, 8.6, 0.85], 0.012, 8)
    for x in (-0.55, 0.55):
        sl.lathe(rails, [x, 10.6, 1.0], [(0.0, 0.0), (0.07, 0.0), (0.05, 0.04), (0.02, 0.08),
                                         (0.018, 0.45), (0.05, 0.48), (0.0, 0.5)], 16)
    pipes = sl.Mesh("pews, organ pipes", WRITER)
    for k in range(27):
        x = -2.6 + 0.2 * k
        top = 4.4 + 0.06 * min(k, 26 - k) + (0.25 if k % 2 else 0.0)
        sl.tube(pipes, [x, 11.3, 2.6], [x, 11.3, top], 0.055, 12)
        sl.lathe(pipes, [x, 11.3, 2.2], [(0.0, 0.0), (0.01, 0.0), (0.055, 0.4)], 12)
    out["pews_oak.obj"] = oak.text()
    out["pews_ends.obj"] = ends.text()
    out["pews_bronze.obj"] = rails.text()
    out["pews_gold.obj"] = gold.text()
    out["pews_pipes.obj"] = pipes.text()
    out.update({"pews_" + n + ".obj": m.text() for n, m in books.items()})
    out.update({"pews_" + n + ".obj": m.text() for n, m in kneel.items()})
    out.update({"pews_" + n + ".obj": m.text() for n, m in flags.items()})
    # the south (left) wall: piers between three window openings; the north wall whole
    wall = sl.Mesh("pews, walls", WRITER)
    edges = [-2.0, 0.4, 1.8, 3.6, 5.0, 6.8, 8.2, 12.0]
    for k in range(0, len(edges) - 1):
        ya, yb = edges[k], edges[k + 1]
        if k % 2 == 0:
            wall.flat([[-4.0, ya, 0.0], [-4.0, yb, 0.0], [-4.0, yb, 7.0], [-4.0, ya, 7.0]])
        else:
            wall.flat([[-4.0, ya, 0.0], [-4.0, yb, 0.0], [-4.0, yb, 1.9], [-4.0, ya, 1.9]])
            wall.flat([[-4.0, ya, 4.8], [-4.0, yb, 4.8], [-4.0, yb, 7.0], [-4.0, ya, 7.0]])
    wall.flat([[4.0, -2.0, 0.0], [4.0, 12.0, 0.0], [4.0, 12.0, 7.0], [4.0, -2.0, 7.0]])
    wall.flat([[-4.0, 11.4, 0.0], [4.0, 11.4, 0.0], [4.0, 11.4, 7.0], [-4.0, 11.4, 7.0]])
    wall.flat([[-4.0, -2.0, 0.0], [4.0, -2.0, 0.0], [4.0, -2.0, 7.0], [-4.0, -2.0, 7.0]])
    out["pews_walls.obj"] = wall.text()
    return out


def pews_parts():
    m = materials()
    m.paint("flag_joint", 0.6)
    m.many(("flag_a", "flag_b"), 0.3)
    m.paint("oak_dark", 0.12)
    m.paint("oak_end", 0.1)
    m.metal("bronze", 0.08)
    m.metal("pipe_metal", 0.05)
    m.many(BOOKS, 0.3)
    m.many(("kneeler_a", "kneeler_b"), 0.6)
    m.many(("runner_red", "runner_gold"), 0.6)
    m.paint("limewash", 0.6)
    m.paint("altar_cloth", 0.5)
    m.paint("dossal", 0.5)
    m.paint("pipe_shade", 0.2)
    objs = [cg.ground("flag_joint"),
            cg.rect([0, 3.85, 0.003], UP, [1, 0, 0], [0.8, 10.7], "runner_red"),
            sl.box([0, 10.6, 0.5], [1.8, 0.7, 1.0], "altar_cloth"),
            cg.rect([0, 11.35, 2.0], [0, -1, 0], [1, 0, 0], [2.2, 2.4], "dossal"),
            sl.box([0, 11.2, 4.75], [5.8, 0.3, 0.2], "pipe_shade"),
            sl.box([0, 9.4, 0.1], [8.0, 1.6, 0.2], "flag_b"),
            cg.rect([0, 5.0, 7.0], UP, [1, 0, 0], [8.2, 14.2], "oak_dark")]
    for n, mat, smooth in (("oak", "oak_dark", False), ("ends", "oak_end", False),
                           ("bronze", "bronze", True), ("gold", "runner_gold", False),
                           ("pipes", "pipe_metal", True), ("walls", "limewash", False),
                           ("flag_a", "flag_a", False), ("flag_b", "flag_b", False)):
        objs.append(sl.mesh_object("pews_" + n + ".obj", mat, smooth))
    for n in BOOKS + ("kneeler_a", "kneeler_b"):
        objs.append(sl.mesh_object("pews_" + n + ".obj", n, False))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.75, -0.25, 0.6])),
               "irradiance_w_m2": [110, 105, 95]},
              {"type": "point", "position": [0.0, 2.0, 4.0], "intensity_w_sr": [40, 34, 24]},
              {"type": "point", "position": [0.0, 6.0, 4.0], "intensity_w_sr": [40, 34, 24]},
              {"type": "point", "position": [0.0, 9.6, 3.5], "intensity_w_sr": [45, 39, 30]}]
    return m, objs, lights


def pews():
    m, objs, lights = pews_parts()
    return scene("pews", "a parish church's nave down the aisle (oak pews, bronze rails, hymn "
                 "books, kneelers, a red runner on stone flags, the altar, candlesticks and "
                 "the organ's pipes ~9 px apart), sun shafts through the south windows",
                 PEWS_CAMERA, lights, m, objs, background=[0.5, 0.5, 0.6])


def pews_g23():
    m, objs, lights = pews_parts()
    return scene("pews_g23", "the church scene through the IMX250MYR preset at +23 dB analog "
                 "gain (a dim nave, a handheld exposure)", PEWS_CAMERA, lights, m, objs,
                 preset="imx250myr", gain_db=23, background=[0.5, 0.5, 0.6])


SCENES = {"court": court, "tackle": tackle, "greenhouse": greenhouse, "pews": pews,
          "court_g5": court_g5, "pews_g23": pews_g23}


def meshes():
    out = {}
    out.update(court_meshes())
    out.update(tackle_meshes())
    out.update(greenhouse_meshes())
    out.update(pews_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
