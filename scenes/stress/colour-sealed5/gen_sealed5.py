#!/usr/bin/env python3
"""Writes the fifth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed5.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed5.py --print NAME` prints one scene instead.
The shared helpers (colour sensor, scene, rect, vectors, ...) are ../colour_gen.py.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). "Brass" is an assumed yellow metal of the right order (n - ik per
channel at 610, 530 and 465 nm, between copper's and zinc's, from memory, not a table lookup);
no metal of the other sets is reused. None of the paints, meshes, cameras or layouts of the
other colour sets is reused; the sky of `fields` (directional lights with single-scattering
polarization) is the one ../colour-sealed3 introduced and ../colour-sealed4 coarsened, written
again here (those generators are frozen by their seals) with another sun.

Meshes are written in millimetres (placed with scale 0.001) to keep the files small. Flat-faced
meshes (`smooth` false) give each polygon its own vertices; the smooth ones (bowls, spice
mounds, tunnels: surfaces of revolution and sweeps) share vertices so that the loader's
area-weighted vertex normals are smooth.

The exposures (EXPOSURE) were set by looking at the rendered raw frames and truth only
(brightness, clipping, hue-edge density, DoLP pictures), before any demosaicking method was run
on these scenes; README.md records the commit that sealed them.
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import colour_gen as cg  # noqa: E402 (../colour_gen.py)

WRITER = "gen_sealed5.py"

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # spices: ground spices and whole ones in bowls on a jute cloth, flecks of other shades
    "paprika": [1.35, 0.12, 0.06], "turmeric": [1.75, 1.05, 0.04], "cumin": [0.8, 0.55, 0.25],
    "sumac": [0.6, 0.1, 0.16], "curry": [1.4, 0.95, 0.2], "mint": [0.25, 0.5, 0.12],
    "rose": [1.4, 0.45, 0.6], "pepper": [0.13, 0.11, 0.1], "chilli": [1.2, 0.22, 0.05],
    "cardamom": [0.5, 0.75, 0.3], "ginger": [1.5, 1.2, 0.62], "lavender": [0.55, 0.4, 0.95],
    "fleck_dark": [0.22, 0.14, 0.07], "fleck_light": [1.55, 1.4, 1.0],
    "fleck_red": [0.9, 0.07, 0.05], "jute": [0.95, 0.72, 0.42], "jute_dark": [0.6, 0.42, 0.22],
    "bowl_blue": [0.05, 0.18, 0.95], "bowl_clay": [1.15, 0.5, 0.3], "cinnamon": [0.7, 0.35, 0.15],
    "dried_chilli": [1.0, 0.05, 0.04], "crate": [1.2, 0.9, 0.55],
    # bricks: glossy ABS toy bricks on an oak floor
    "abs_red": [1.55, 0.06, 0.05], "abs_yellow": [1.75, 1.4, 0.04], "abs_blue": [0.04, 0.3, 1.3],
    "abs_green": [0.05, 0.85, 0.2], "abs_white": [1.6, 1.6, 1.58], "abs_black": [0.05, 0.05, 0.06],
    "abs_orange": [1.75, 0.55, 0.03], "abs_lime": [0.9, 1.5, 0.05], "oak_a": [1.2, 0.8, 0.42],
    "oak_b": [1.05, 0.68, 0.34], "oak_c": [1.3, 0.9, 0.5],
    # cobbles: wet granite setts, a lane at night
    "sett_grey": [0.5, 0.5, 0.52], "sett_blue": [0.32, 0.36, 0.45], "sett_pink": [0.75, 0.5, 0.42],
    "sett_ochre": [0.75, 0.62, 0.38], "joint": [0.06, 0.055, 0.05], "puddle": [0.02, 0.02, 0.02],
    "kerb": [0.6, 0.6, 0.58], "slab": [0.5, 0.49, 0.46], "render": [1.2, 1.1, 0.9],
    "brick_dark": [0.45, 0.18, 0.12], "window_lit": [1.7, 1.55, 1.1], "sign_red": [1.6, 0.1, 0.1],
    "sign_cyan": [0.08, 1.1, 1.5], "door": [0.1, 0.25, 0.15], "lamp_post": [0.1, 0.1, 0.1],
    # fields: farmland seen from a light aircraft
    "rapeseed": [1.75, 1.5, 0.08], "lavender_row": [0.75, 0.45, 1.3], "vine": [0.2, 0.55, 0.12],
    "wheat": [1.4, 1.05, 0.45], "furrow_dark": [0.35, 0.22, 0.12],
    "furrow_light": [0.75, 0.55, 0.32],
    "pasture": [0.3, 0.75, 0.15], "maize": [0.1, 0.45, 0.08], "sunflower": [1.3, 0.9, 0.05],
    "soil_dry": [0.95, 0.75, 0.5], "river": [0.03, 0.06, 0.06], "tunnel": [1.5, 1.5, 1.48],
    "roof_red": [1.1, 0.25, 0.15], "asphalt": [0.22, 0.22, 0.23], "line": [1.6, 1.6, 1.6],
    "hedge": [0.08, 0.3, 0.07], "tree": [0.12, 0.4, 0.1], "farm_wall": [1.3, 1.25, 1.1],
    "greenhouse": [0.03, 0.04, 0.04],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "brass": {"n": [0.45, 0.62, 1.0], "k": [3.4, 2.7, 2.1]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "spices": 1200,
    "bricks": 320,
    "cobbles": 2000,
    "fields": 450,
    "bricks_g3": 180,
    "cobbles_g27": 120,
}

EFFECTS = cg.EFFECTS


def r4(v):
    return cg.rounded(v, 4)


def mat(name, sigma, n=1.5):
    return {"n": n, "k": PAINTS[name], "sigma": sigma}


def metal(name, sigma):
    return dict(METALS[name], sigma=sigma)


def sensor(name, preset="ideal", **kw):
    return cg.sensor(EXPOSURE[name], preset, **kw)


def scene(name, title, camera, lights, materials, objs, effects=None, sen=None, **extra):
    s = cg.scene("colour sealed 5: " + title, camera, lights, materials, objs,
                 effects or EFFECTS, sen or sensor(name))
    s.update(extra)
    return s


class MmObj:
    """A Wavefront OBJ in millimetres (placed with scale 0.001), vertices given in metres.
    poly() writes a polygon with its own vertices (negative indices: flat faces); vertex() and
    face() share vertices (absolute indices: smooth surfaces)."""

    def __init__(self, title):
        self.lines = ["# " + title + ", millimetres, written by " + WRITER]
        self.nv = 0

    def vertex(self, p):
        self.lines.append("v %.1f %.1f %.1f" % (p[0] * 1e3, p[1] * 1e3, p[2] * 1e3))
        self.nv += 1
        return self.nv

    def face(self, idx):
        self.lines.append("f " + " ".join(str(i) for i in idx))

    def poly(self, pts):
        for p in pts:
            self.vertex(p)
        self.face(range(self.nv - len(pts) + 1, self.nv + 1))

    def text(self):
        return "\n".join(self.lines) + "\n"


def mm_mesh(file, material, smooth=False):
    return {"type": "mesh", "file": file, "position": [0, 0, 0], "scale": 0.001,
            "material": material, "smooth": smooth}


def revolve(mesh, c, profile, n, ph=0.0):
    """A surface of revolution about the vertical axis through c (x, y, z): profile a list of
    (r, z) from one end to the other, n segments around; shared vertices (smooth)."""
    rings = []
    for r, z in profile:
        ring = []
        for i in range(n):
            a = ph + 2 * math.pi * i / n
            ring.append(mesh.vertex([c[0] + r * math.cos(a), c[1] + r * math.sin(a), c[2] + z]))
        rings.append(ring)
    for q in range(len(rings) - 1):
        a, b = rings[q], rings[q + 1]
        for i in range(n):
            j = (i + 1) % n
            mesh.face([a[i], a[j], b[j], b[i]])


# ---------------------------------------------------------------------------------------------
# spices: a market stall from above at ~45 degrees, ~1.5 mm per pixel: twelve bowls (brass,
# blue-glazed, terracotta) of ground and whole spices piled into cones and domes, their surface
# flecked with grains of other shades (2-5 mm: 1.3-3.5 px), on a jute cloth; cinnamon sticks and
# dried chillies between the bowls; daylight from the open side, sky fill and a warm bulb

SPICES_CAMERA = {"position": [0.05, -0.95, 1.05], "look_at": [0.0, 0.13, 0.0], "up": [0, 0, 1],
                 "focal_length_mm": 3.5, "f_number": 5.6}
# spice, fleck paint, grain size (m), shape ("cone" or "dome"), bowl material
SPICES = (
    ("paprika", "fleck_dark", 0.002, "cone", "brass"), ("turmeric", "fleck_red", 0.002, "cone",
                                                         "bowl_clay"),
    ("mint", "fleck_light", 0.003, "dome", "bowl_blue"), ("sumac", "fleck_dark", 0.0025, "cone",
                                                          "brass"),
    ("curry", "fleck_red", 0.002, "dome", "bowl_blue"), ("rose", "fleck_light", 0.004, "dome",
                                                         "brass"),
    ("pepper", "fleck_light", 0.0035, "dome", "bowl_clay"), ("chilli", "fleck_light", 0.003,
                                                             "cone", "brass"),
    ("cardamom", "fleck_dark", 0.005, "dome", "bowl_clay"), ("ginger", "fleck_dark", 0.002,
                                                             "cone", "bowl_blue"),
    ("lavender", "fleck_light", 0.003, "dome", "brass"), ("cumin", "fleck_light", 0.0025, "cone",
                                                         "bowl_blue"),
)
BOWL_PAINTS = ("brass", "bowl_blue", "bowl_clay")
FLECKS = ("fleck_dark", "fleck_light", "fleck_red")


def bowl_layout():
    rng = random.Random(5203)
    out = []
    for q, sp in enumerate(SPICES):
        row, col = divmod(q, 4)
        x = -0.315 + 0.21 * col + rng.uniform(-0.012, 0.012)
        y = -0.1 + 0.25 * row + rng.uniform(-0.012, 0.012)
        radius = rng.uniform(0.085, 0.095)
        height = rng.uniform(0.05, 0.065)
        pile = rng.uniform(0.08, 0.14) if sp[3] == "cone" else rng.uniform(0.025, 0.045)
        out.append((sp, (x, y), radius, height, pile))
    return out


def mound_z(shape, r, r0, base, pile):
    t = min(1.0, r / r0)
    if shape == "cone":
        # a cone with a rounded apex
        return base + pile * (1 - math.sqrt(t * t + 0.01) + 0.1) / 1.1
    return base + pile * (1 - t * t) ** 0.6


def spices_meshes():
    rng = random.Random(5209)
    bowls = {n: MmObj("spices, " + n + " bowls") for n in BOWL_PAINTS}
    mounds = {}
    flecks = {n: MmObj("spices, " + n + " grains") for n in FLECKS}
    for (name, fleck, grain, shape, bowl), (x, y), rad, h, pile in bowl_layout():
        # the bowl: outside wall, rim, inside wall down to the spice
        prof = [(0.58 * rad, 0.0), (0.7 * rad, 0.1 * h), (0.86 * rad, 0.35 * h),
                (0.96 * rad, 0.65 * h), (rad, 0.9 * h), (rad, h), (0.93 * rad, h),
                (0.9 * rad, 0.86 * h), (0.58 * rad, 0.0)]
        revolve(bowls[bowl], (x, y, 0.0), prof, 40)
        # the spice: a cone or dome from just inside the rim
        r0, base = 0.9 * rad, 0.86 * h
        m = mounds.setdefault(name, MmObj("spices, " + name))
        prof = [(r0 * (1 - i / 14) + 0.0005, mound_z(shape, r0 * (1 - i / 14), r0, base, pile))
                for i in range(15)]
        revolve(m, (x, y, 0.0), prof, 36, ph=rng.uniform(0, 1))
        # grains of another shade lying on the surface
        area = math.pi * r0 * r0 * (1.6 if shape == "cone" else 1.1)
        for k in range(int(area * 0.25 / (grain * grain))):
            rr = r0 * math.sqrt(rng.random()) * 0.97
            a = rng.uniform(0, 2 * math.pi)
            s = grain * rng.uniform(0.6, 1.3)
            pts = []
            for da, dr in ((0, 0), (s / max(rr, 0.01), s * 0.3), (s * 0.4 / max(rr, 0.01), -s)):
                r1 = max(0.0, min(r0, rr + dr))
                a1 = a + da
                pts.append([x + r1 * math.cos(a1), y + r1 * math.sin(a1),
                            mound_z(shape, r1, r0, base, pile) + 0.0007])
            flecks[fleck].poly(pts)
    out = {"spices_bowl_" + n + ".obj": m.text() for n, m in bowls.items()}
    out.update({"spices_" + n + ".obj": m.text() for n, m in mounds.items()})
    out.update({"spices_grain_" + n + ".obj": m.text() for n, m in flecks.items()})
    return out


def spices():
    rng = random.Random(5227)
    m = {n: mat(n, 0.7) for n, _, _, _, _ in SPICES}
    m.update({n: mat(n, 0.7) for n in FLECKS})
    m["pepper"]["sigma"] = 0.25  # whole peppercorns and pods have a sheen
    m["cardamom"]["sigma"] = 0.3
    m["brass"] = metal("brass", 0.12)
    m["bowl_blue"] = mat("bowl_blue", 0.05)
    m["bowl_clay"] = mat("bowl_clay", 0.4)
    m["jute"] = mat("jute", 0.9)
    m["jute_dark"] = mat("jute_dark", 0.9)
    m["cinnamon"] = mat("cinnamon", 0.6)
    m["dried_chilli"] = mat("dried_chilli", 0.15)
    m["crate"] = mat("crate", 0.7)
    objs = [cg.ground("jute")]
    # the cloth's weave: darker bands every 25 mm both ways (a coarse check under the bowls)
    for i in range(-20, 21):
        objs.append(cg.rect([0.025 * i, 0.15, 0.0004], [0, 0, 1], [0, 1, 0], [1.6, 0.006],
                            "jute_dark"))
    for i in range(-14, 34):
        objs.append(cg.rect([0.0, 0.025 * i, 0.0005], [0, 0, 1], [1, 0, 0], [1.2, 0.005],
                            "jute_dark"))
    # the back of the stall: a wooden crate
    objs.append({"type": "box", "center": [0.0, 0.78, 0.12], "size": [1.4, 0.2, 0.24],
                 "material": "crate"})
    for n in BOWL_PAINTS:
        objs.append(mm_mesh("spices_bowl_" + n + ".obj", n, smooth=True))
    for n, _, _, _, _ in SPICES:
        objs.append(mm_mesh("spices_" + n + ".obj", n, smooth=True))
    for n in FLECKS:
        objs.append(mm_mesh("spices_grain_" + n + ".obj", n))
    # cinnamon sticks and dried chillies lying between the bowls
    for q in range(18):
        row, col = rng.randrange(3), rng.randrange(5)
        x = -0.42 + 0.21 * col + rng.uniform(-0.02, 0.02)
        y = 0.02 + 0.25 * row + rng.uniform(-0.03, 0.03)
        yaw = rng.uniform(0, 180)
        if q % 2:
            objs.append({"type": "box", "center": r4([x, y, 0.006]),
                         "size": [0.1, 0.012, 0.011], "rotation_deg": [0, 0, round(yaw, 1)],
                         "material": "cinnamon"})
        else:
            objs.append({"type": "box", "center": r4([x, y, 0.005]),
                         "size": [0.07, 0.011, 0.01], "rotation_deg": [0, 0, round(yaw, 1)],
                         "material": "dried_chilli"})
    lights = [{"type": "directional", "direction": r4(cg.unit([0.35, -0.55, 0.75])),
               "irradiance_w_m2": [140, 140, 150]},
              {"type": "directional", "direction": [0, 0, 1], "irradiance_w_m2": [35, 40, 52]},
              {"type": "point", "position": [-0.25, 0.3, 0.9], "intensity_w_sr": [5, 3.8, 2]}]
    return scene("spices", "a market stall of twelve bowls (brass, blue-glazed, terracotta) of "
                 "ground and whole spices piled in cones and domes, flecked with grains of 1.3-3.5 "
                 "px, on a jute cloth, with cinnamon sticks and dried chillies, in daylight",
                 SPICES_CAMERA, lights, m, objs)


# ---------------------------------------------------------------------------------------------
# bricks: toy building bricks (glossy ABS, eight colours, studs 4.8 mm on an 8 mm pitch: ~3.4 px
# studs at a ~5.6 px pitch across the frame, ~4 px down it, foreshortened) on an oak floor, seen
# from ~1.9 m (~1.4 mm per pixel): a baseplate with a walled tower and ~180 loose bricks;
# a window behind the scene mirrors in the brick tops and the varnished floor (glare near
# Brewster's angle), a fill from the camera's side

BRICKS_CAMERA = {"position": [0.3, -1.2, 1.25], "look_at": [0.0, 0.15, 0.0], "up": [0, 0, 1],
                 "focal_length_mm": 4.5, "f_number": 5.6}
ABS = ("abs_red", "abs_yellow", "abs_blue", "abs_green", "abs_white", "abs_black", "abs_orange",
       "abs_lime")
UNIT, BH = 0.008, 0.0096
BASE = (0.06, 0.13, 24)  # baseplate centre x, y and studs per side


def brick_layout():
    """Every brick: (centre x, y, bottom z, studs nx, ny, yaw degrees, colour, studs shown)."""
    rng = random.Random(5303)
    out = []
    bx, by, bn = BASE
    # the tower on the baseplate: a 12 x 8 stud wall ring, 1-stud thick, 6 courses
    tx, ty = bx + 0.044, by + 0.06
    for c in range(6):
        z = 0.0032 + c * BH
        col = ABS[(c * 3) % 8] if c % 3 else "abs_white"
        off = 2 * (c % 2)
        for side in (-1, 1):
            # the long walls along x (12 studs) and short walls along y (8 studs)
            k = -6 + off
            while k < 6:
                n = min(4, 6 - k)
                out.append((tx + (k + n / 2) * UNIT, ty + side * 3.5 * UNIT, z, n, 1, 0, col,
                            c == 5))
                k += n
            if off:
                out.append((tx - 5 * UNIT, ty + side * 3.5 * UNIT, z, 2, 1, 0, col, c == 5))
            k = -3 + off // 2
            while k < 3:
                n = min(4, 3 - k)
                out.append((tx + side * 5.5 * UNIT, ty + (k + n / 2) * UNIT, z, 1, n, 0, col,
                            c == 5))
                k += n
            if off:
                out.append((tx + side * 5.5 * UNIT, ty - 3.5 * UNIT + UNIT, z, 1, 1, 0, col,
                            c == 5))
    # loose bricks on the floor around the baseplate, some stacked in pairs
    placed = [(bx, by, 0.125)]
    sizes = ((2, 4), (2, 4), (2, 2), (1, 4), (2, 3), (1, 2), (1, 6), (2, 6))
    tries = 0
    while len(placed) < 180 and tries < 40000:
        tries += 1
        x, y = rng.uniform(-0.55, 0.55), rng.uniform(-0.2, 0.75)
        nx, ny = sizes[rng.randrange(len(sizes))]
        rad = 0.5 * UNIT * math.hypot(nx, ny) + 0.002
        if any(math.hypot(x - px, y - py) < rad + pr for px, py, pr in placed):
            continue
        placed.append((x, y, rad))
        yaw = rng.uniform(0, 180)
        col = ABS[rng.randrange(8)]
        two = rng.random() < 0.25
        out.append((x, y, 0.0, nx, ny, yaw, col, not two))
        if two:
            out.append((x, y, BH, nx, ny, yaw, ABS[rng.randrange(8)], True))
    return out


def stud(mesh, c, z):
    """A stud: a hexagonal prism of 4.8 mm across and 1.7 mm high at c, its foot at z (shared
    vertices, flat faces written as one polygon each)."""
    ring = [[c[0] + 0.0024 * math.cos(math.pi * i / 3), c[1] + 0.0024 * math.sin(math.pi * i / 3)]
            for i in range(6)]
    lo = [mesh.vertex([p[0], p[1], z]) for p in ring]
    hi = [mesh.vertex([p[0], p[1], z + 0.0017]) for p in ring]
    mesh.face(hi)
    for i in range(6):
        j = (i + 1) % 6
        mesh.face([lo[i], lo[j], hi[j], hi[i]])


def bricks_meshes():
    studs = {n: MmObj("bricks, " + n + " studs") for n in ABS}
    bx, by, bn = BASE
    tx, ty = bx + 0.044, by + 0.06
    for i in range(bn):
        for j in range(bn):
            x = bx + (i - (bn - 1) / 2) * UNIT
            y = by + (j - (bn - 1) / 2) * UNIT
            if abs(x - tx) < 6 * UNIT and abs(y - ty) < 4 * UNIT:
                continue  # under the tower
            stud(studs["abs_green"], (x, y), 0.0032)
    for x, y, z, nx, ny, yaw, col, shown in brick_layout():
        if not shown:
            continue
        a = math.radians(yaw)
        ca, sa = math.cos(a), math.sin(a)
        for i in range(nx):
            for j in range(ny):
                u, v = (i - (nx - 1) / 2) * UNIT, (j - (ny - 1) / 2) * UNIT
                stud(studs[col], (x + u * ca - v * sa, y + u * sa + v * ca), z + BH)
    return {"bricks_studs_" + n + ".obj": m.text() for n, m in studs.items()}


def bricks_scene():
    m = {n: mat(n, 0.05) for n in ABS}
    m["abs_green_plate"] = mat("abs_green", 0.08)
    for n in ("oak_a", "oak_b", "oak_c"):
        m[n] = mat(n, 0.2)
    objs = [cg.ground("oak_a")]
    # oak planks 0.14 m wide along y, three shades, the joints between them in the darker one
    for i in range(-12, 13):
        objs.append(cg.rect([0.14 * i, 0.5, 0.0002], [0, 0, 1], [0, 1, 0], [6.0, 0.137],
                            ("oak_a", "oak_b", "oak_c")[(i * 7) % 3]))
    bx, by, bn = BASE
    objs.append({"type": "box", "center": [bx, by, 0.0016], "size": [bn * UNIT, bn * UNIT, 0.0032],
                 "material": "abs_green_plate"})
    for x, y, z, nx, ny, yaw, col, shown in brick_layout():
        b = {"type": "box", "center": r4([x, y, z + BH / 2]),
             "size": r4([nx * UNIT - 0.0002, ny * UNIT - 0.0002, BH]), "material": col}
        if yaw:
            b["rotation_deg"] = [0, 0, round(yaw, 2)]
        objs.append(b)
    for n in ABS:
        objs.append(mm_mesh("bricks_studs_" + n + ".obj", n))
    lights = [{"type": "directional", "direction": r4(cg.unit([-0.12, 0.8, 0.62])),
               "irradiance_w_m2": [120, 125, 135]},
              {"type": "directional", "direction": r4(cg.unit([0.35, -0.6, 0.72])),
               "irradiance_w_m2": [60, 56, 50]},
              {"type": "point", "position": [-0.3, 0.2, 2.2], "intensity_w_sr": [9, 7.5, 5.5]}]
    return m, objs, lights


def bricks():
    m, objs, lights = bricks_scene()
    return scene("bricks", "toy building bricks in eight glossy colours (studs ~3.4 px at a ~5.6 "
                 "px pitch) on an oak floor: a baseplate with a walled tower and ~180 loose "
                 "bricks, a window behind mirrored in the brick tops and the varnished floor",
                 BRICKS_CAMERA, lights, m, objs)


def bricks_g3():
    m, objs, lights = bricks_scene()
    return scene("bricks_g3", "the bricks scene through the IMX250MYR preset at +3 dB analog "
                 "gain (a bright playroom)", BRICKS_CAMERA, lights, m, objs,
                 sen=sensor("bricks_g3", preset="imx250myr", gain_db=3))


# ---------------------------------------------------------------------------------------------
# cobbles: a lane of wet granite setts at night, seen from eye height looking ~20 degrees down
# the lane (setts 34 px wide near the bottom, ~10 x 2 px at the far end): a sodium lamp and a
# cool white LED lamp hung over the lane, a shop front with a lit window, a red and a cyan sign
# each lit by its own lamp; the setts' water film (n 1.33, sigma 0.08, each sett tilted by a few
# degrees) and puddles (sigma 0.02) mirror the lamps in streaks near Brewster's angle of water;
# a dusk sky

COBBLES_CAMERA = {"position": [0.5, -1.0, 1.7], "look_at": [0.6, 5.0, 0.0], "up": [0, 0, 1],
                  "focal_length_mm": 3.3, "f_number": 2.8}
SETTS = ("sett_grey", "sett_blue", "sett_pink", "sett_ochre")


def cobbles_meshes():
    rng = random.Random(5401)
    meshes = {n: MmObj("cobbles, " + n + " setts") for n in SETTS}
    # courses of setts 0.1-0.14 m long, 0.1 m deep, across the lane (x -2.5 .. 2.5)
    y = -0.5
    while y < 22.0:
        d = 0.1 + 0.012 * rng.random()
        x = -2.5 - rng.uniform(0, 0.12)
        while x < 2.5:
            w = rng.uniform(0.1, 0.14)
            g = rng.uniform(0.008, 0.014)
            tx, ty = rng.gauss(0, 0.05), rng.gauss(0, 0.05)
            z = 0.02 + rng.uniform(-0.004, 0.004)
            cx, cy = x + w / 2, y + d / 2
            pts = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                px, py = cx + a * (w - g) / 2, cy + b * (d - g) / 2
                pts.append([px, py, z + tx * (px - cx) + ty * (py - cy)])
            name = SETTS[min(int(rng.random() ** 1.6 * 4), 3)]
            meshes[name].poly(pts)
            x += w
        y += d
    return {"cobbles_" + n + ".obj": m.text() for n, m in meshes.items()}


def cobbles_scene():
    rng = random.Random(5407)
    m = {n: mat(n, 0.08, n=1.33) for n in SETTS}
    m["joint"] = mat("joint", 0.3, n=1.33)
    m["puddle"] = mat("puddle", 0.02, n=1.33)
    for n in ("kerb", "slab"):
        m[n] = mat(n, 0.15, n=1.33)
    for n in ("render", "brick_dark", "window_lit", "door", "sign_red", "sign_cyan"):
        m[n] = mat(n, 0.5)
    m["lamp_post"] = mat("lamp_post", 0.2)
    up = [0, 0, 1]
    objs = [cg.ground("joint")]
    for n in SETTS:
        objs.append(mm_mesh("cobbles_" + n + ".obj", n))
    # puddles in the hollows
    for q in range(9):
        x, y = rng.uniform(-2.2, 2.2), rng.uniform(1.5, 16)
        a = rng.uniform(0, math.pi)
        objs.append(cg.rect([x, y, 0.0245], up, [math.cos(a), math.sin(a), 0],
                            [rng.uniform(0.4, 1.4), rng.uniform(0.25, 0.7)], "puddle"))
    # the kerb and the pavement on the right, the shop front behind it
    objs.append({"type": "box", "center": [2.6, 10, 0.07], "size": [0.2, 24, 0.14],
                 "material": "kerb"})
    for k in range(40):
        objs.append(cg.rect([3.35, -1.5 + 0.6 * k, 0.141], up, [1, 0, 0], [1.3, 0.585], "slab"))
    objs.append(cg.rect([4.0, 10, 3.0], [-1, 0, 0], [0, 1, 0], [24, 6], "render"))
    objs.append(cg.rect([3.99, 4.5, 1.4], [-1, 0, 0], [0, 1, 0], [2.6, 1.6], "window_lit"))
    objs.append(cg.rect([3.99, 6.4, 1.15], [-1, 0, 0], [0, 1, 0], [1.0, 2.1], "door"))
    objs.append(cg.rect([3.98, 9.0, 2.7], [-1, 0, 0], [0, 1, 0], [2.4, 0.6], "sign_red"))
    objs.append(cg.rect([3.98, 16.0, 2.6], [-1, 0, 0], [0, 1, 0], [0.8, 0.8], "sign_cyan"))
    # the dark brick wall on the left and a lamp post
    objs.append(cg.rect([-2.7, 10, 3.0], [1, 0, 0], [0, 1, 0], [24, 6], "brick_dark"))
    objs.append({"type": "box", "center": [-2.35, 13.6, 1.7], "size": [0.1, 0.1, 3.4],
                 "material": "lamp_post"})
    lights = [
        # a sodium lamp on a post on the left, a white LED lamp hung over the lane's middle
        {"type": "point", "position": [-2.1, 14.0, 3.5], "intensity_w_sr": [260, 150, 30]},
        {"type": "point", "position": [0.4, 6.5, 4.6], "intensity_w_sr": [225, 235, 260]},
        # the shop window's light spilling out, the signs' lamps
        {"type": "point", "position": [3.4, 4.5, 1.3], "intensity_w_sr": [45, 40, 28]},
        {"type": "point", "position": [3.5, 9.0, 2.3], "intensity_w_sr": [40, 4, 5]},
        {"type": "point", "position": [3.5, 16.0, 2.3], "intensity_w_sr": [3, 25, 40]},
    ]
    return m, objs, lights


def cobbles():
    m, objs, lights = cobbles_scene()
    return scene("cobbles", "a lane of wet granite setts at night under a sodium and an LED "
                 "lamp, a shop window and a red and a cyan sign, the lamps mirrored in "
                 "the wet stones and puddles near Brewster's angle of water", COBBLES_CAMERA,
                 lights, m, objs, background=[0.6, 0.9, 2.2])


def cobbles_g27():
    m, objs, lights = cobbles_scene()
    return scene("cobbles_g27", "the cobbles scene through the IMX250MYR preset at +27 dB "
                 "analog gain (handheld at night)", COBBLES_CAMERA, lights, m, objs,
                 sen=sensor("cobbles_g27", preset="imx250myr", gain_db=27),
                 background=[0.6, 0.9, 2.2])


# ---------------------------------------------------------------------------------------------
# fields: farmland seen from a light aircraft at ~320 m, ~44 degrees off the vertical (~0.45 m
# per pixel at the centre): a patchwork of fields, row crops whose rows are 1.7-5.6 px apart
# (maize, lavender, vines, furrows), rapeseed, wheat, sunflowers, pasture, a row of plastic
# polytunnels, a farm with red roofs and a glasshouse, hedgerows, trees, a road and a river
# (water n 1.33, ruffled: sigma 0.06) mirroring a clear, polarized sky

FIELDS_CAMERA = {"position": [10.0, -260.0, 320.0], "look_at": [0.0, 60.0, 0.0],
                 "up": [0, 0, 1], "focal_length_mm": 3.5, "f_number": 5.6}
FIELDS_SUN = cg.unit([0.7, 0.2, 0.68])
SKY_RINGS = ((12, 6), (42, 5), (80, 1))
# field: centre x, y, size along u, across, heading of u (deg), paint, rows (paint, width,
# period in m) or None
FIELDS = (
    ((-120, 10), (110, 90), 8, "maize", ("soil_dry", 0.35, 0.75)),
    ((-5, 5), (100, 85), 8, "lavender_row", ("soil_dry", 0.6, 1.6)),
    ((105, 15), (95, 90), 5, "rapeseed", None),
    ((-130, 115), (105, 100), -4, "wheat", ("furrow_light", 0.3, 12.0)),
    ((-20, 110), (95, 95), -4, "vine", ("soil_dry", 1.6, 2.5)),
    ((95, 120), (100, 100), 3, "furrow_dark", ("furrow_light", 0.55, 1.2)),
    ((-125, 220), (110, 100), 2, "sunflower", None),
    ((-15, 225), (100, 100), 2, "pasture", None),
    ((110, 230), (100, 105), 6, "maize", ("soil_dry", 0.35, 0.75)),
    ((-125, -85), (110, 90), 10, "pasture", None),
    ((-5, -85), (100, 85), 10, "wheat", ("furrow_light", 0.3, 12.0)),
    ((105, -80), (95, 90), 3, "lavender_row", ("soil_dry", 0.6, 1.6)),
    ((-10, 330), (380, 100), 0, "rapeseed", None),
)
TUNNELS = ((95, 120), 3, 8, 7.5, 80.0)  # centre, heading, count, width (m), length (m)


def sky_lights(sun, scale=1.0):
    """The clear sky as directional lights (../colour-sealed4/gen_sealed4.py's sky, written
    again): rings at elevations 12, 42, 80 degrees, their irradiance the sky radiance (blue,
    brighter towards the horizon and the sun) times the solid angle they stand for; their
    polarization single scattering's: perpendicular to the plane of sun and sky point, degree
    0.75 sin^2(g) / (1 + cos^2(g)) at scattering angle g (Rayleigh). The sun last."""
    out = []
    rings = SKY_RINGS
    for q, (el, naz) in enumerate(rings):
        lo = 0 if q == 0 else (rings[q - 1][0] + el) / 2
        hi = 90 if q == len(rings) - 1 else (el + rings[q + 1][0]) / 2
        omega = 2 * math.pi * (math.sin(math.radians(hi)) - math.sin(math.radians(lo))) / naz
        for i in range(naz):
            az = 2 * math.pi * (i + 0.5 * (q % 2)) / naz + 0.3
            ce = math.cos(math.radians(el))
            d = [ce * math.cos(az), ce * math.sin(az), math.sin(math.radians(el))]
            c = max(-1.0, min(1.0, cg.dot(d, sun)))
            g = math.acos(c)
            dop = 0.75 * (1 - c * c) / (1 + c * c)
            rad = (0.7 + 0.5 * (1 - el / 90)) * (1 + 2.5 * math.exp(-g / 0.4))
            e = [round(scale * rad * omega * x, 3) for x in (38, 52, 80)]
            light = {"type": "directional", "direction": r4(d), "irradiance_w_m2": e}
            perp = cg.cross(sun, d)
            if dop > 0.01 and math.sqrt(cg.dot(perp, perp)) > 1e-3:
                light["polarization"] = {"linear_deg": 0, "dop": round(dop, 3)}
                light["reference"] = r4(cg.unit(perp))
            out.append(light)
    out.append({"type": "directional", "direction": r4(sun),
                "irradiance_w_m2": [round(scale * x, 1) for x in (520, 500, 470)]})
    return out


def fields_meshes():
    """The rows of the row crops (one file per row paint), the polytunnels, the river."""
    rows = {}
    for (c, size, head, paint, row) in FIELDS:
        if not row:
            continue
        rp, w, period = row
        mesh = rows.setdefault(rp, MmObj("fields, " + rp + " rows"))
        a = math.radians(head)
        u, v = [math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]
        k = -size[1] / 2 + period / 2
        while k < size[1] / 2:
            pts = []
            for s, t in ((-1, -w / 2), (1, -w / 2), (1, w / 2), (-1, w / 2)):
                px = c[0] + s * size[0] / 2 * u[0] + (k + t) * v[0]
                py = c[1] + s * size[0] / 2 * u[1] + (k + t) * v[1]
                pts.append([px, py, 0.02])
            mesh.poly(pts)
            k += period
    out = {"fields_rows_" + n + ".obj": m.text() for n, m in rows.items()}
    # polytunnels: half cylinders (16 segments) along u
    tun = MmObj("fields, polytunnels")
    (tcx, tcy), head, count, tw, tl = TUNNELS
    a = math.radians(head)
    u, v = [math.cos(a), math.sin(a)], [-math.sin(a), math.cos(a)]
    for q in range(count):
        off = (q - (count - 1) / 2) * (tw + 3.0)
        ends = []
        for s in (-1, 1):
            ring = []
            for i in range(17):
                th = math.pi * i / 16
                across = off + tw / 2 * math.cos(th)
                ring.append(tun.vertex([tcx + s * tl / 2 * u[0] + across * v[0],
                                        tcy + s * tl / 2 * u[1] + across * v[1],
                                        0.02 + 3.0 * math.sin(th)]))
            ends.append(ring)
        for i in range(16):
            tun.face([ends[0][i], ends[0][i + 1], ends[1][i + 1], ends[1][i]])
    out["fields_tunnels.obj"] = tun.text()
    # the river: a meandering band 14-20 m wide from the top left to the bottom right
    riv = MmObj("fields, river")
    prev = None
    for i in range(61):
        t = i / 60
        y = 400 - 560 * t
        x = -230 + 420 * t + 55 * math.sin(2 * math.pi * 1.6 * t)
        dx = 420 + 55 * 2 * math.pi * 1.6 * math.cos(2 * math.pi * 1.6 * t)
        dy = -560.0
        n = math.hypot(dx, dy)
        w = 8 + 2 * math.sin(7 * t)
        left = riv.vertex([x - dy / n * w, y + dx / n * w, 0.05])
        right = riv.vertex([x + dy / n * w, y - dx / n * w, 0.05])
        if prev:
            riv.face([prev[0], prev[1], right, left])
        prev = (left, right)
    out["fields_river.obj"] = riv.text()
    return out


def river_x(y):
    t = (400 - y) / 560
    return -230 + 420 * t + 55 * math.sin(2 * math.pi * 1.6 * t)


def fields():
    rng = random.Random(5507)
    m = {n: mat(n, 0.6) for n in ("rapeseed", "lavender_row", "vine", "wheat", "furrow_dark",
                                  "furrow_light", "pasture", "maize", "sunflower", "soil_dry",
                                  "asphalt", "line", "hedge", "tree", "farm_wall")}
    m["river"] = mat("river", 0.25, n=1.33)
    m["tunnel"] = mat("tunnel", 0.1)
    m["roof_red"] = mat("roof_red", 0.4)
    m["greenhouse"] = {"n": 1.52, "k": PAINTS["greenhouse"], "sigma": 0.03}
    up = [0, 0, 1]
    objs = [cg.ground("pasture")]
    for (c, size, head, paint, row) in FIELDS:
        a = math.radians(head)
        objs.append(cg.rect([c[0], c[1], 0.01], up, [math.cos(a), math.sin(a), 0], size, paint))
    for n in sorted({row[0] for _, _, _, _, row in FIELDS if row}):
        objs.append(mm_mesh("fields_rows_" + n + ".obj", n))
    objs.append(mm_mesh("fields_tunnels.obj", "tunnel", smooth=True))
    objs.append(mm_mesh("fields_river.obj", "river"))
    # hedgerows along the field borders (x = -65, 50; y = -40, 62, 168, 275)
    for x in (-65, 50):
        objs.append({"type": "box", "center": [x, 100, 1.2], "size": [2.5, 480, 2.4],
                     "material": "hedge"})
    for y in (-40, 62, 168, 275):
        objs.append({"type": "box", "center": [0, y, 1.2], "size": [420, 2.5, 2.4],
                     "material": "hedge"})
    # a road along y = 168 beside its hedge, with a centre line
    objs.append(cg.rect([0, 173, 0.04], up, [1, 0, 0], [500, 6], "asphalt"))
    for k in range(-40, 41):
        objs.append(cg.rect([6 * k, 173, 0.05], up, [1, 0, 0], [3, 0.15], "line"))
    # trees: along the river banks and in the hedgerows
    for q in range(70):
        y = rng.uniform(-120, 380)
        x = river_x(y) + rng.choice((-1, 1)) * rng.uniform(13, 20)
        objs.append({"type": "sphere", "center": r4([x, y, 4.0]),
                     "radius": round(rng.uniform(3, 5.5), 2), "material": "tree"})
    for q in range(30):
        if q % 2:
            x, y = rng.choice((-65, 50)), rng.uniform(-100, 330)
        else:
            x, y = rng.uniform(-200, 200), rng.choice((-40, 62, 275))
        objs.append({"type": "sphere", "center": r4([x, y, 4.5]),
                     "radius": round(rng.uniform(3.5, 6), 2), "material": "tree"})
    # the farm: three buildings with red roofs (sloping planes) and a glasshouse
    for (x, y, w, d, yaw) in ((60, 65, 30, 14, 5), (85, 75, 18, 10, 95), (40, 82, 22, 12, 5)):
        a = math.radians(yaw)
        u = [math.cos(a), math.sin(a), 0]
        v = [-math.sin(a), math.cos(a), 0]
        objs.append({"type": "box", "center": [x, y, 2.5], "size": [w, d, 5],
                     "rotation_deg": [0, 0, yaw], "material": "farm_wall"})
        for s in (-1, 1):
            nrm = cg.unit(cg.add([0, 0, 1], v, s * 0.6))
            cpt = cg.add([x, y, 5 + d / 4 * 0.6], v, s * d / 4)
            objs.append(cg.rect(cpt, nrm, u, [w + 1, d / 2 * 1.17 + 0.3], "roof_red"))
    objs.append({"type": "box", "center": [20, 70, 2.0], "size": [24, 10, 4.0],
                 "rotation_deg": [0, 0, 5], "material": "greenhouse"})
    return scene("fields", "farmland from a light aircraft at ~320 m: row crops with rows "
                 "1.7-5.6 px apart, rapeseed, wheat, sunflowers, pasture, polytunnels, a farm "
                 "with a glasshouse, hedgerows, trees, a road and a river mirroring a clear sky "
                 "of 12 Rayleigh-polarized directional lights and the sun", FIELDS_CAMERA,
                 sky_lights(FIELDS_SUN), m, objs, background=[30, 42, 70])


SCENES = {"spices": spices, "bricks": bricks, "cobbles": cobbles, "fields": fields,
          "bricks_g3": bricks_g3, "cobbles_g27": cobbles_g27}


def meshes():
    out = {}
    out.update(spices_meshes())
    out.update(bricks_meshes())
    out.update(cobbles_meshes())
    out.update(fields_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
