#!/usr/bin/env python3
"""Writes the second sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed2.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed2.py --print NAME` prints one scene instead.
The shared helpers (paints, colour sensor, scene, OBJ writer, ...) are ../colour_gen.py.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated: water 1.33, window glass 1.52): a channel with k ~ 1.3-1.8 scatters back
brightly, one with k ~ 0.03 hardly at all (../colour/gen_colour.py). None of the paints, meshes
or layouts of ../colour, ../colour-holdout or ../colour-sealed is reused.

The exposures (EXPOSURE) were set by looking at the rendered raw frames and truth only
(brightness, clipping, hue-edge density, DoLP/AoLP pictures), before any demosaicking method
was run on these scenes; README.md records the commit that sealed them.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import colour_gen as cg  # noqa: E402 (../colour_gen.py)

WRITER = "gen_sealed2.py"

# name: k[R, G, B] (n = 1.5 unless the material says otherwise)
PAINTS = {
    # portrait
    "skin": [1.45, 0.95, 0.7], "skin_lip": [1.3, 0.45, 0.45], "iris": [0.3, 0.2, 0.12],
    "hair_dark": [0.16, 0.1, 0.06], "hair_auburn": [0.75, 0.3, 0.12],
    "hair_blond": [1.3, 1.0, 0.5], "sweater": [0.25, 0.6, 0.55], "backdrop": [0.55, 0.6, 0.7],
    # street
    "asphalt": [0.22, 0.22, 0.24], "concrete": [0.8, 0.78, 0.72], "brick": [1.0, 0.42, 0.3],
    "stucco": [1.35, 1.2, 0.8], "frame_white": [1.4, 1.4, 1.38], "sign_red": [1.75, 0.12, 0.1],
    "sign_blue": [0.08, 0.3, 1.5], "letter_yellow": [1.7, 1.45, 0.1],
    "awning_green": [0.1, 1.0, 0.35], "door_blue": [0.12, 0.45, 1.2],
    "car_red": [1.6, 0.08, 0.12], "marking": [1.5, 1.5, 1.45],
    "marking_yellow": [1.6, 1.2, 0.08],
    # print
    "paper": [1.45, 1.45, 1.4], "ink_c": [0.06, 1.2, 1.65], "ink_m": [1.55, 0.08, 1.1],
    "ink_y": [1.65, 1.5, 0.06], "ink_k": [0.05, 0.05, 0.06], "ink_r": [1.6, 0.1, 0.08],
    "ink_g": [0.08, 1.3, 0.2], "ink_b": [0.1, 0.12, 1.5], "ink_skin": [1.5, 1.0, 0.75],
    "ink_grey": [0.6, 0.6, 0.6],
    # rooftops
    "terracotta": [1.5, 0.55, 0.25], "slate": [0.3, 0.35, 0.45], "verdigris": [0.4, 1.15, 0.95],
    "tin_red": [1.55, 0.15, 0.1], "wall_ochre": [1.4, 1.0, 0.35], "wall_pink": [1.5, 0.9, 0.9],
    "wall_white": [1.35, 1.35, 1.3], "window_dark": [0.05, 0.06, 0.08],
    "sky": [0.35, 0.65, 1.4],
    # water
    "water": [0.03, 0.22, 0.18], "hull_yellow": [1.6, 1.3, 0.05], "hull_white": [1.45, 1.42, 1.36],
    "hull_navy": [0.06, 0.1, 0.6], "pier_wood": [0.8, 0.5, 0.28], "tree": [0.12, 0.55, 0.1],
    "house_blue": [0.4, 0.7, 1.4], "house_orange": [1.6, 0.7, 0.15],
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "portrait": 1800,
    "street": 220,
    "print": 300,
    "rooftops": 400,
    "water": 200,
    "portrait_g6": 450,
    "street_g18": 9,
}

EFFECTS = cg.EFFECTS


def r4(v):
    return cg.rounded(v, 4)


def mat(name, sigma, n=1.5):
    return {"n": n, "k": PAINTS[name], "sigma": sigma}


def sensor(name, preset="ideal", **kw):
    return cg.sensor(EXPOSURE[name], preset, **kw)


def scene(name, title, camera, lights, materials, objs, effects=None, sen=None, **extra):
    s = cg.scene("colour sealed 2: " + title, camera, lights, materials, objs,
                 effects or EFFECTS, sen or sensor(name))
    s.update(extra)
    return s


def rect(center, normal, u, size, material):
    """A finite plane: size[0] along u, size[1] along normal x u."""
    return {"type": "plane", "point": r4(center), "normal": r4(normal), "size": r4(size),
            "u_axis": r4(u), "material": material}


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def add(a, b, s=1.0):
    return [x + s * y for x, y in zip(a, b)]


# ---------------------------------------------------------------------------------------------
# portrait: a softly shaded head of skin paint before a backdrop, dark hair with hair-fine
# strands (0.4-1.5 px) crossing the forehead and temples, auburn and blond strands on the hair

HEAD_C, HEAD_R = [0.0, 0.0, 0.3], 0.1
PORTRAIT_CAMERA = {"position": [0.06, -1.0, 0.33], "look_at": [0.0, 0.0, 0.285],
                   "up": [0, 0, 1], "focal_length_mm": 5, "f_number": 4}
PORTRAIT_LIGHTS = [{"type": "point", "position": [-0.45, -0.55, 0.65], "intensity_w_sr": 30},
                   {"type": "directional", "direction": [0.75, -0.5, 0.43],
                    "irradiance_w_m2": [35, 42, 55]},
                   {"type": "point", "position": [0.25, 0.45, 0.7],
                    "intensity_w_sr": [25, 22, 18]}]


def on_head(theta, phi, lift):
    """A point lift above the head sphere at polar angle theta (from +z) and azimuth phi (from
    +x towards +y: the face looks along -y, phi = -pi/2)."""
    r = HEAD_R + lift
    return [HEAD_C[0] + r * math.sin(theta) * math.cos(phi),
            HEAD_C[1] + r * math.sin(theta) * math.sin(phi), HEAD_C[2] + r * math.cos(theta)]


def strand(obj, pts, width):
    """A strand along the polyline pts: one quad per segment, width across (in the plane
    perpendicular to the head's radius)."""
    for a, b in zip(pts, pts[1:]):
        d = cg.unit(add(b, a, -1))
        rad = cg.unit(add(a, HEAD_C, -1))
        side = cg.unit(cross(d, rad))
        h = 0.5 * width
        obj.poly([add(a, side, -h), add(a, side, h), add(b, side, h), add(b, side, -h)])


def hair_walk(rng, theta, phi, dphi, lift, steps, dtheta, wobble):
    """A strand's centre line on the head: steps points, theta growing by uniform(dtheta) per
    step (downwards), phi by dphi, which drifts by uniform(+-wobble)."""
    pts = []
    for _ in range(steps):
        pts.append(on_head(theta, phi, lift))
        theta += rng.uniform(*dtheta)
        dphi += rng.uniform(-wobble, wobble)
        phi += dphi
    return pts


def hair_meshes():
    rng = random.Random(3101)
    px = 1.0 * 3.45e-3 / 5  # ~0.7 mm per pixel at the head
    objs = {m: cg.Obj("portrait hair strands, " + m, WRITER)
            for m in ("hair_dark", "hair_auburn", "hair_blond")}
    # stray strands from the hairline over the forehead and temples: start on the hair cap's
    # edge, run down and sideways over the skin
    for i in range(110):
        phi, theta = -math.pi / 2 + rng.uniform(-1.1, 1.1), rng.uniform(0.45, 0.6)
        dphi, n = rng.uniform(-0.05, 0.05), rng.randint(8, 16)
        pts = hair_walk(rng, theta, phi, dphi, 0.0008 + 0.00002 * i, n, (0.03, 0.06), 0.02)
        strand(objs["hair_dark"], pts, rng.uniform(0.4, 1.5) * px)
    # strands over the hair itself: lighter hues on the dark cap, from the crown downwards
    for i in range(160):
        m = "hair_auburn" if i % 3 else "hair_blond"
        phi, theta = rng.uniform(-math.pi, math.pi), rng.uniform(0.0, 0.25)
        pts = hair_walk(rng, theta, phi, rng.uniform(-0.04, 0.04), 0.016 + 0.00003 * i, 14,
                        (0.045, 0.055), 0.005)
        strand(objs[m], pts, rng.uniform(0.5, 1.5) * px)
    # long strands down the sides of the head (over the hair cap and the temples, across the
    # silhouette against the backdrop)
    for i in range(120):
        phi = (0.0 if i % 2 else math.pi) + rng.uniform(-0.45, 0.45)
        theta = rng.uniform(0.2, 0.5)
        pts = hair_walk(rng, theta, phi, rng.uniform(-0.03, 0.03), 0.0045 + 0.00003 * i, 12,
                        (0.07, 0.1), 0.005)
        strand(objs["hair_dark"], pts, rng.uniform(0.4, 1.2) * px)
    # eyebrows: short dark strands
    for side in (-1, 1):
        for i in range(30):
            phi = -math.pi / 2 + side * rng.uniform(0.18, 0.55)
            theta = rng.uniform(1.02, 1.1)
            pts = [on_head(theta, phi, 0.0006),
                   on_head(theta - 0.03, phi + side * 0.08, 0.0006)]
            strand(objs["hair_dark"], pts, rng.uniform(0.6, 1.2) * px)
    return {"portrait_" + m + ".obj": o.text() for m, o in objs.items()}


def portrait_parts():
    m = {"skin": mat("skin", 0.35), "lip": mat("skin_lip", 0.2), "iris": mat("iris", 0.05),
         "hair_dark": mat("hair_dark", 0.12), "hair_auburn": mat("hair_auburn", 0.12),
         "hair_blond": mat("hair_blond", 0.15), "sweater": mat("sweater", 0.7),
         "backdrop": mat("backdrop", 0.8)}
    objs = [{"type": "plane", "point": [0, 0.5, 0], "normal": [0, -1, 0], "material": "backdrop"},
            {"type": "sphere", "center": HEAD_C, "radius": HEAD_R, "material": "skin"},
            # the hair: a dark cap over the top and back of the head
            {"type": "sphere", "center": [0.0, 0.02, 0.318], "radius": 0.1,
             "material": "hair_dark"},
            # neck and shoulders
            {"type": "sphere", "center": [0.0, 0.01, 0.18], "radius": 0.05, "material": "skin"},
            {"type": "box", "center": [0.0, 0.03, 0.07], "size": [0.42, 0.2, 0.16],
             "material": "sweater"},
            {"type": "sphere", "center": r4(on_head(1.95, -math.pi / 2, -0.01)),
             "radius": 0.014, "material": "lip"},
            {"type": "sphere", "center": r4(on_head(1.62, -math.pi / 2, -0.006)),
             "radius": 0.013, "material": "skin"}]
    for side in (-1, 1):
        objs.append({"type": "sphere", "center": r4(on_head(1.3, -math.pi / 2 + side * 0.36,
                                                            -0.006)),
                     "radius": 0.011, "material": "iris"})
    for h in ("hair_dark", "hair_auburn", "hair_blond"):
        objs.append({"type": "mesh", "file": "portrait_" + h + ".obj", "position": [0, 0, 0],
                     "scale": 1, "material": h, "smooth": False})
    return m, objs


def portrait():
    m, objs = portrait_parts()
    return scene("portrait", "a softly lit head of skin paint, dark hair with hair-fine strands "
                 "(0.4-1.5 px) over the forehead, lighter strands on the hair, a teal sweater",
                 PORTRAIT_CAMERA, PORTRAIT_LIGHTS, m, objs)


def noisy(base, name, gain_db, what):
    """The scene base() through the IMX250MYR preset (full sensor noise) at gain_db, with
    EXPOSURE[name]."""
    s = base()
    s["name"] = "colour sealed 2: the %s scene through the IMX250MYR preset at %+d dB analog " \
        "gain (%s)" % (base.__name__, gain_db, what)
    s["sensor"] = sensor(name, preset="imx250myr", gain_db=gain_db)
    return s


# ---------------------------------------------------------------------------------------------
# street: a brick shop front and a stucco house along a street, seen obliquely from the far
# pavement: glass windows near Brewster's angle mirroring the sky (high DoLP), painted signs
# with block letters of 2-4 px strokes, a striped awning, a red car, asphalt with markings

STREET_CAMERA = {"position": [-13.0, -10.0, 1.6], "look_at": [1.0, 0.0, 2.8], "up": [0, 0, 1],
                 "focal_length_mm": 3.5, "f_number": 4}
FACADE_N = [0, -1, 0]
FACADE_U = [1, 0, 0]


def street_lights():
    # the sky as a directional light in the mirror direction of the view at the middle of the
    # upper windows (incidence ~56 degrees, Brewster's angle for n 1.52): the windows mirror it
    # strongly polarized; a warm low sun from the right-behind the camera
    p = [1.5, 0.0, 2.9]
    v = cg.unit(add(STREET_CAMERA["position"], p, -1))
    d = sum(a * b for a, b in zip(FACADE_N, v))
    sky = [2 * d * a - b for a, b in zip(FACADE_N, v)]
    return [{"type": "directional", "direction": r4(sky), "irradiance_w_m2": [110, 135, 175]},
            {"type": "directional", "direction": [0.35, -0.75, 0.56],
             "irradiance_w_m2": [260, 235, 195]}]


GLYPHS = ["111101111101101", "110101110101110", "111100100100111", "101101111101101",
          "111010010010111", "100100100100111", "111100111100111", "101111111101101",
          "111101101101111", "111100111001111"]


def facade_text(objs, x0, z0, cell, text, material, y=-0.012):
    """Block letters (3 x 5 cells, a 1-cell gap) on the facade plane, left-bottom at (x0, z0):
    one rectangle per horizontal run of cells in a row."""
    for g, c in enumerate(text):
        bits = GLYPHS[c]
        for row in range(5):
            col = 0
            while col < 3:
                if bits[3 * row + col] == "1":
                    end = col
                    while end + 1 < 3 and bits[3 * row + end + 1] == "1":
                        end += 1
                    w = (end - col + 1) * cell
                    cx = x0 + (4 * g + col) * cell + w / 2
                    cz = z0 + (4 - row) * cell + cell / 2
                    objs.append(rect([cx, y, cz], FACADE_N, FACADE_U, [w, cell], material))
                    col = end + 1
                else:
                    col += 1


def street_parts():
    m = {"asphalt": mat("asphalt", 0.6), "concrete": mat("concrete", 0.5),
         "brick": mat("brick", 0.55), "stucco": mat("stucco", 0.5),
         "frame": mat("frame_white", 0.3), "sign_red": mat("sign_red", 0.2),
         "sign_blue": mat("sign_blue", 0.2), "letter": mat("letter_yellow", 0.25),
         "awning": mat("awning_green", 0.45), "awning_white": mat("frame_white", 0.45),
         "door": mat("door_blue", 0.15), "car": mat("car_red", 0.07),
         "marking": mat("marking", 0.5), "marking_y": mat("marking_yellow", 0.5),
         "glass": {"n": 1.52, "k": [0.02, 0.025, 0.03], "sigma": 0.05}}
    objs = [cg.ground("asphalt"),
            # pavement along the facades and its kerb
            {"type": "box", "center": [0.0, -1.25, 0.07], "size": [30, 2.5, 0.14],
             "material": "concrete"},
            # facades: brick shop front (x < 3.2), stucco house (x > 3.2)
            rect([-2.0, 0.0, 5.0], FACADE_N, FACADE_U, [10.4, 10.0], "brick"),
            rect([7.6, 0.0, 5.0], FACADE_N, FACADE_U, [8.8, 10.0], "stucco")]
    # shop window and door of the brick house
    objs.append(rect([0.2, -0.01, 1.35], FACADE_N, FACADE_U, [3.0, 2.1], "frame"))
    objs.append(rect([0.2, -0.02, 1.35], FACADE_N, FACADE_U, [2.8, 1.9], "glass"))
    # upper windows: white frames, glass
    for x in (-2.4, -0.6, 1.2, 2.6, 4.6, 6.2, 7.8):
        for z in (3.6, 6.2):
            objs.append(rect([x, -0.01, z], FACADE_N, FACADE_U, [1.05, 1.55], "frame"))
            objs.append(rect([x, -0.02, z], FACADE_N, FACADE_U, [0.85, 1.35], "glass"))
            objs.append(rect([x, -0.03, z], FACADE_N, FACADE_U, [0.06, 1.35], "frame"))
    # the stucco house's blue door and its glass
    objs.append(rect([5.4, -0.01, 1.1], FACADE_N, FACADE_U, [1.1, 2.2], "door"))
    objs.append(rect([5.4, -0.02, 1.65], FACADE_N, FACADE_U, [0.6, 0.7], "glass"))
    # signs: red board with yellow letters over the shop window, blue board on the stucco house
    objs.append(rect([0.2, -0.015, 2.75], FACADE_N, FACADE_U, [3.0, 0.5], "sign_red"))
    facade_text(objs, -1.18, 2.58, 0.07, [3, 1, 7, 2, 0, 4, 8, 6, 5, 9], "letter",
                y=-0.02)
    objs.append(rect([7.2, -0.015, 2.6], FACADE_N, FACADE_U, [2.2, 0.4], "sign_blue"))
    facade_text(objs, 6.22, 2.475, 0.05, [6, 0, 9, 4, 2, 8, 7, 1, 3, 5],
                "letter", y=-0.02)
    # a striped awning sloping out below the sign (stripes 0.12 m, green and white)
    an = cg.unit([0, -0.6, 0.8])
    slope = cross(an, FACADE_U)
    top = [0.2, 0.0, 2.45]
    length = 0.9
    mid = add(top, slope, -length / 2)
    for k in range(26):
        x = -1.36 + 0.12 * k
        objs.append(rect([x, mid[1], mid[2]], an, FACADE_U, [0.12, length],
                         "awning" if k % 2 == 0 else "awning_white"))
    # a red car at the kerb (body, glass cabin)
    objs.append({"type": "box", "center": [5.0, -3.6, 0.65], "size": [4.2, 1.8, 0.9],
                 "material": "car"})
    objs.append({"type": "box", "center": [4.8, -3.6, 1.35], "size": [2.2, 1.6, 0.55],
                 "material": "glass"})
    # road markings: a white edge line, a yellow centre line, a crossing of 0.5 m stripes
    objs.append(rect([0.0, -2.7, 0.003], [0, 0, 1], [1, 0, 0], [30, 0.12], "marking"))
    objs.append(rect([0.0, -6.5, 0.003], [0, 0, 1], [1, 0, 0], [30, 0.1], "marking_y"))
    objs.append(rect([0.0, -6.7, 0.003], [0, 0, 1], [1, 0, 0], [30, 0.1], "marking_y"))
    for k in range(8):
        objs.append(rect([2.4 + 1.0 * k - 4.0, -5.4, 0.004], [0, 0, 1], [1, 0, 0],
                         [0.5, 4.6], "marking"))
    return m, objs


def street():
    m, objs = street_parts()
    return scene("street", "a brick shop front and a stucco house seen obliquely: windows near "
                 "Brewster's angle mirroring the sky (high DoLP), signs with 2-4 px block "
                 "letters, a striped awning, a red car, asphalt with markings", STREET_CAMERA,
                 street_lights(), m, objs, background=[45, 55, 75])



# ---------------------------------------------------------------------------------------------
# print: a colour print on a desk, seen slightly obliquely: a CMYK halftone picture (square
# dots, screens at 15/75/0/45 degrees, pitch ~4.3 px: the colour lattice's period) and a test
# print with coloured line pairs of 1-3 px, a magenta/green hairline grid and colour bars

PRINT_CAMERA = {"position": [0.0, -2.4, 5.6], "look_at": [0.0, 0.0, 0.0], "up": [0, 1, 0],
                "focal_length_mm": 12, "f_number": 4}
SCREENS = (("ink_y", 0.0, 0.0075), ("ink_c", 15.0, 0.0075), ("ink_m", 75.0, 0.0075),
           ("ink_k", 45.0, 0.0075))
HALFTONE = (-0.42, -0.03, -0.26, 0.2)  # x0, x1, y0, y1 of the halftone picture


def tone(ink, x, y):
    """The halftone picture's ink coverage (0-1) per ink at (x, y): a sunset over a sea and a
    sun disc, made of smooth gradients and one sharp-edged disc."""
    u = (x - HALFTONE[0]) / (HALFTONE[1] - HALFTONE[0])
    v = (y - HALFTONE[2]) / (HALFTONE[3] - HALFTONE[2])
    sun = math.hypot(u - 0.62, v - 0.58) < 0.14
    if v > 0.4:  # sky: yellow near the horizon to magenta-blue above
        t = (v - 0.4) / 0.6
        cov = {"ink_y": 0.9 * (1 - t), "ink_m": 0.3 + 0.5 * t, "ink_c": 0.6 * t * t,
               "ink_k": 0.0}
        if sun:
            cov = {"ink_y": 0.95, "ink_m": 0.15, "ink_c": 0.0, "ink_k": 0.0}
    else:  # sea: cyan with dark waves
        t = v / 0.4
        wave = 0.5 + 0.5 * math.sin(40 * u + 9 * t * t + 3 * math.sin(7 * u))
        cov = {"ink_y": 0.25 * t, "ink_m": 0.2 * (1 - t), "ink_c": 0.55 + 0.35 * (1 - t),
               "ink_k": 0.45 * wave * (1 - t)}
    return cov[ink]


def halftone_meshes():
    out = {}
    x0, x1, y0, y1 = HALFTONE
    for ink, ang, pitch in SCREENS:
        o = cg.Obj("print halftone screen, " + ink, WRITER)
        a = math.radians(ang)
        ca, sa = math.cos(a), math.sin(a)
        n = int(0.8 / pitch)
        for j in range(-n, n + 1):
            for i in range(-n, n + 1):
                x, y = i * pitch * ca - j * pitch * sa, i * pitch * sa + j * pitch * ca
                if not (x0 <= x <= x1 and y0 <= y <= y1):
                    continue
                c = tone(ink, x, y)
                if c < 0.04:
                    continue
                # a square dot of area c * pitch^2, turned with its screen
                h = 0.5 * pitch * math.sqrt(min(c, 0.97))
                pts = [[x + (sx * ca - sy * sa) * h, y + (sx * sa + sy * ca) * h]
                       for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
                z = 0.0004 + 0.0002 * [s[0] for s in SCREENS].index(ink)
                o.poly([[p[0], p[1], z] for p in pts])
        out["print_" + ink + ".obj"] = o.text()
    return out


def print_scene():
    m = {"paper": mat("paper", 0.45)}
    for ink in ("ink_c", "ink_m", "ink_y", "ink_k", "ink_r", "ink_g", "ink_b", "ink_skin",
                "ink_grey"):
        m[ink] = mat(ink, 0.3)
    objs = [cg.ground("paper")]
    for ink, _, _ in SCREENS:
        objs.append({"type": "mesh", "file": "print_" + ink + ".obj", "position": [0, 0, 0],
                     "scale": 1, "material": ink, "smooth": False})
    px = 0.00174
    z = 0.0004
    # test print, upper right: line pairs of two inks, line widths 1, 1.5, 2, 2.5 and 3 px,
    # horizontal lines in blocks 40 px wide; pairs red/cyan, blue/yellow, magenta/green
    pairs = (("ink_r", "ink_c"), ("ink_b", "ink_y"), ("ink_m", "ink_g"))
    for p, (a, b) in enumerate(pairs):
        for q, w in enumerate((1.0, 1.5, 2.0, 2.5, 3.0)):
            bx = 0.02 + q * 0.085
            by = 0.29 - p * 0.095
            lw = w * px
            k = 0
            yy = by
            while yy - lw > by - 0.08:
                objs.append(rect([bx + 0.035, yy - lw / 2, z], [0, 0, 1], [1, 0, 0],
                                 [0.07, lw], a if k % 2 == 0 else b))
                yy -= lw
                k += 1
    # lower right: a magenta-on-green hairline grid (1.3 px lines, period 5.5 px) turned 30 deg
    gx, gy, half = 0.12, -0.16, 0.1
    objs.append(rect([gx, gy, z], [0, 0, 1], [1, 0, 0], [2 * half, 2 * half], "ink_g"))
    a = math.radians(30)
    for axis in (0, 1):
        u = [math.cos(a), math.sin(a), 0] if axis == 0 else [-math.sin(a), math.cos(a), 0]
        v = [-u[1], u[0], 0]
        off = -half
        while off <= half:
            c = [gx + v[0] * off, gy + v[1] * off, z + 0.0001 * (1 + axis)]
            # clipped to the square by its length: chords of the inscribed circle
            ln = 2 * math.sqrt(max(half * half - off * off, 0.0))
            if ln > 2 * px:
                objs.append(rect(c, [0, 0, 1], u, [ln, 1.3 * px], "ink_m"))
            off += 5.5 * px
    # a row of colour bars between them: 20 px patches of every ink and two tints, abutting
    bars = ("ink_c", "ink_m", "ink_y", "ink_k", "ink_r", "ink_g", "ink_b", "ink_skin",
            "ink_grey", "ink_c")
    for q, ink in enumerate(bars):
        objs.append(rect([0.03 + (q + 0.5) * 20 * px, -0.025, z], [0, 0, 1], [1, 0, 0],
                         [20 * px, 0.05], ink))
    lights = [{"type": "directional", "direction": [-0.3, -0.25, 0.92],
               "irradiance_w_m2": [240, 235, 215]},
              {"type": "directional", "direction": [0.45, 0.1, 0.89],
               "irradiance_w_m2": [70, 75, 85]}]
    return scene("print", "a CMYK halftone picture (square dots, screens 0/15/45/75 degrees, "
                 "pitch ~4.3 px) and a colour test print (line pairs of 1-3 px, a magenta on "
                 "green hairline grid, colour bars), seen slightly obliquely", PRINT_CAMERA,
                 lights, m, objs)


# ---------------------------------------------------------------------------------------------
# rooftops: gabled roofs of several hues under a sky plane whose diffuse polarization grows
# smoothly towards the horizon (the simulator has no sky model: a matte sky-blue plane overhead
# seen at 60-88 degrees from its normal stands in for it)

ROOF_CAMERA = {"position": [0.0, -25.0, 16.0], "look_at": [0.0, 30.0, 13.5], "up": [0, 0, 1],
               "focal_length_mm": 3, "f_number": 4}
ROOFS = ("terracotta", "slate", "verdigris", "tin_red")
WALLS = ("wall_ochre", "wall_pink", "wall_white")


def house(objs, x, y, w, d, h, roof, wall, pitch_deg):
    """A house of w (x) by d (y) by h with a gable roof whose ridge runs along x."""
    objs.append({"type": "box", "center": r4([x, y, h / 2]), "size": r4([w, d, h]),
                 "material": wall})
    p = math.radians(pitch_deg)
    half = d / 2 / math.cos(p)
    rise = d / 2 * math.tan(p)
    for s in (-1, 1):
        n = [0, s * math.sin(p), math.cos(p)]
        objs.append(rect([x, y + s * d / 4, h + rise / 2], n, [1, 0, 0], [w + 0.3, half + 0.15],
                         roof))
    # two dark windows on the front wall
    for k in (-1, 1):
        objs.append(rect([x + k * w / 4, y - d / 2 - 0.01, h * 0.55], [0, -1, 0], [1, 0, 0],
                         [0.9, 1.2], "window_dark"))


def rooftops_parts():
    rng = random.Random(4409)
    m = {r: mat(r, 0.3) for r in ROOFS}
    m["slate"]["sigma"] = 0.15
    m["tin_red"]["sigma"] = 0.1
    m.update({w: mat(w, 0.6) for w in WALLS})
    m["window_dark"] = mat("window_dark", 0.05)
    m["sky"] = mat("sky", 0.9)
    m["street"] = mat("asphalt", 0.6)
    objs = [cg.ground("street"),
            {"type": "plane", "point": [0, 0, 60], "normal": [0, 0, -1], "material": "sky"}]
    for row in range(9):
        y = 2 + 6.5 * row
        x = -8 - 2.2 * row + rng.uniform(-1, 1)
        while x < 8 + 2.2 * row:
            w = rng.uniform(4, 7)
            house(objs, x + w / 2, y + rng.uniform(-0.6, 0.6), w - 0.3, rng.uniform(4.5, 5.5),
                  rng.uniform(5, 9), ROOFS[rng.randrange(4)], WALLS[rng.randrange(3)],
                  rng.uniform(25, 45))
            x += w
    # the skyline: apartment blocks behind the last row hide the ground's horizon
    x = -40.0
    while x < 40:
        w = rng.uniform(8, 14)
        h = rng.uniform(14, 24)
        objs.append({"type": "box", "center": r4([x + w / 2, 66 + rng.uniform(-2, 2), h / 2]),
                     "size": r4([w - 0.5, 8, h]), "material": WALLS[rng.randrange(3)]})
        x += w
    lights = [{"type": "directional", "direction": [-0.45, -0.3, 0.84],
               "irradiance_w_m2": [250, 235, 205]},
              # lights the sky plane from below (cast shadows are off)
              {"type": "directional", "direction": [0.2, 0.3, -0.93],
               "irradiance_w_m2": [120, 150, 200]}]
    eff = dict(EFFECTS, cast_shadows=False)
    return m, objs, lights, eff


def rooftops():
    m, objs, lights, eff = rooftops_parts()
    return scene("rooftops", "gabled roofs (terracotta, slate, verdigris, red tin) over "
                 "ochre, pink and white walls under a sky plane whose polarization grows "
                 "smoothly towards the horizon", ROOF_CAMERA, lights, m, objs, effects=eff)


# ---------------------------------------------------------------------------------------------
# water: a rippled lake seen from a low bank towards a low sun: a glitter path near Brewster's
# angle (strongly polarized, clipped), boats and a pier, coloured houses and trees on the far
# bank; exposed so that the glitter clips

WATER_CAMERA = {"position": [0.0, -6.0, 4.0], "look_at": [0.0, 14.0, 1.5], "up": [0, 0, 1],
                "focal_length_mm": 3, "f_number": 4}
WAVES = ((0.07, 4.0, 0.25, 0.0), (0.05, 2.6, -0.45, 1.3), (0.03, 1.7, 1.1, 2.1))
# (amplitude m, wavelength m, heading rad, phase)


def water_mesh():
    # a trapezoid widening with the distance from the camera (the view's footprint)
    nx, ny = 40, 90
    y0, y1 = -4.0, 40.0
    lines = ["# water surface (ripples: four sinusoids), written by " + WRITER]
    for j in range(ny):
        t = j / (ny - 1)
        y = y0 + (y1 - y0) * t ** 1.5
        half = 3.0 + 0.35 * (y + 6.0)
        for i in range(nx):
            x = -half + 2 * half * i / (nx - 1)
            z, gx, gy = 0.0, 0.0, 0.0
            for a, lam, hd, ph in WAVES:
                k = 2 * math.pi / lam
                kx, ky = k * math.cos(hd), k * math.sin(hd)
                z += a * math.sin(kx * x + ky * y + ph)
                gx += a * kx * math.cos(kx * x + ky * y + ph)
                gy += a * ky * math.cos(kx * x + ky * y + ph)
            n = cg.unit([-gx, -gy, 1.0])
            lines.append("v %.4f %.4f %.4f" % (x, y, z))
            lines.append("vn %.4f %.4f %.4f" % tuple(n))
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i + 1
            b, c, d = a + 1, a + nx + 1, a + nx
            lines.append("f %d//%d %d//%d %d//%d %d//%d" % (a, a, b, b, c, c, d, d))
    return "\n".join(lines) + "\n"


def water():
    m = {"water": {"n": 1.33, "k": PAINTS["water"], "sigma": 0.06},
         "bank": mat("tree", 0.7), "tree": mat("tree", 0.5),
         "hull_yellow": mat("hull_yellow", 0.1), "hull_white": mat("hull_white", 0.1),
         "hull_navy": mat("hull_navy", 0.1), "wood": mat("pier_wood", 0.5),
         "house_blue": mat("house_blue", 0.5), "house_orange": mat("house_orange", 0.5),
         "wall_white": mat("wall_white", 0.5), "roof": mat("terracotta", 0.4)}
    objs = [{"type": "mesh", "file": "water.obj", "position": [0, 0, 0], "scale": 1,
             "material": "water", "smooth": True},
            # the far bank: a grassy strip
            {"type": "box", "center": [0, 43.0, 0.3], "size": [80, 6, 0.6], "material": "bank"}]
    # houses and trees on the far bank
    rng = random.Random(808)
    x = -20.0
    q = 0
    while x < 20:
        w = rng.uniform(2.5, 4.5)
        h = rng.uniform(3, 6)
        wall = ("house_blue", "house_orange", "wall_white")[q % 3]
        objs.append({"type": "box", "center": r4([x + w / 2, 42.0, 0.6 + h / 2]),
                     "size": r4([w - 0.4, 3, h]), "material": wall})
        objs.append({"type": "box", "center": r4([x + w / 2, 42.0, 0.6 + h + 0.3]),
                     "size": r4([w - 0.2, 3.2, 0.6]), "material": "roof"})
        r = rng.uniform(0.8, 1.6)
        objs.append({"type": "sphere", "center": r4([x + w + 0.3, 40.6, 0.6 + 1.5 * r]),
                     "radius": round(r, 3), "material": "tree"})
        x += w + 0.8
        q += 1
    # a pier from the left and three boats
    objs.append({"type": "box", "center": [-5.0, 4.0, 0.35], "size": [1.4, 9.0, 0.12],
                 "material": "wood"})
    for k in range(6):
        objs.append({"type": "box", "center": [-5.6 + 1.2 * (k % 2), 0.5 + 1.6 * (k // 2),
                                               0.05],
                     "size": [0.15, 0.15, 0.7], "material": "wood"})
    for (bx, by, w, hull, yaw) in ((-2.6, 3.0, 3.2, "hull_yellow", 12),
                                   (2.2, 6.5, 4.0, "hull_white", -20),
                                   (5.5, 11.0, 3.5, "hull_navy", 35)):
        objs.append({"type": "box", "center": [bx, by, 0.25], "size": [w, 1.3, 0.5],
                     "rotation_deg": [0, 0, yaw], "material": hull})
    # a low sun ahead (elevation ~25 degrees: the glitter at ~65 degrees incidence, near
    # Brewster's 53) and the sky behind the camera
    lights = [{"type": "directional", "direction": r4(cg.unit([0.12, 0.9, 0.42])),
               "irradiance_w_m2": [280, 255, 215]},
              {"type": "directional", "direction": [0.25, -0.7, 0.67],
               "irradiance_w_m2": [190, 210, 250]}]
    return scene("water", "a rippled lake towards a low sun: a strongly polarized glitter path "
                 "(clipped), boats and a pier, coloured houses and trees on the far bank",
                 WATER_CAMERA, lights, m, objs, background=[30, 40, 55])


SCENES = {"portrait": portrait, "street": street, "print": print_scene,
          "rooftops": rooftops, "water": water,
          "portrait_g6": lambda: noisy(portrait, "portrait_g6", 6, "an indoor portrait"),
          "street_g18": lambda: noisy(street, "street_g18", 18, "a street at dusk")}


def meshes():
    out = {}
    out.update(hair_meshes())
    out.update(halftone_meshes())
    out["water.obj"] = water_mesh()
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
