#!/usr/bin/env python3
"""Writes the fourth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed4.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed4.py --print NAME` prints one scene instead.
The shared helpers (colour sensor, scene, rect, vectors, ...) are ../colour_gen.py.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). Metals are n - ik per channel at 610, 530 and 465 nm: gold as
../colour-sealed3/gen_sealed3.py has it (read approximately off Johnson & Christy, Phys. Rev. B
6, 4370 (1972), to ~10 %); "aluminium" is an assumed grey metal of the right order (n 1-1.5,
k 6-7.4, near Rakic, Appl. Opt. 34, 4755 (1995), from memory), not a table lookup. None of the
paints, meshes, cameras or layouts of the other colour sets is reused; the sky (directional
lights with single-scattering polarization) is the one ../colour-sealed3 introduced, written
again here (that generator is frozen by its seal) with other suns.

Meshes are written in millimetres (placed with scale 0.001) to keep the files small; their
faces are flat (`smooth` false) unless stated.

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

WRITER = "gen_sealed4.py"

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # mosaic: stone and glass (smalti) tesserae, light cement grout, a marble surround
    "t_white": [1.5, 1.48, 1.42], "t_cream": [1.45, 1.3, 0.95], "t_beige": [1.25, 1.0, 0.7],
    "t_black": [0.06, 0.06, 0.07], "t_terracotta": [1.2, 0.42, 0.22],
    "t_red": [1.5, 0.1, 0.12], "t_blue": [0.07, 0.22, 1.2], "t_turquoise": [0.08, 0.95, 1.0],
    "t_green": [0.12, 0.75, 0.22], "t_ochre": [1.5, 1.0, 0.18], "grout": [1.05, 1.03, 0.97],
    "marble": [1.35, 1.3, 1.22], "marble_vein": [0.55, 0.55, 0.58],
    # meadow: grass blades (fresh, mid, dark, dry), soil, flowers
    "g_fresh": [0.35, 1.0, 0.12], "g_mid": [0.15, 0.65, 0.1], "g_dark": [0.06, 0.35, 0.07],
    "g_dry": [1.05, 0.9, 0.45], "soil": [0.55, 0.42, 0.2], "f_yellow": [1.7, 1.45, 0.03],
    "f_white": [1.55, 1.55, 1.5], "f_red": [1.6, 0.07, 0.06], "f_blue": [0.25, 0.45, 1.5],
    "f_pink": [1.4, 0.45, 1.05], "f_centre": [1.6, 1.0, 0.05],
    # conveyor: belt, packaging, print
    "belt": [0.07, 0.07, 0.075], "belt_rib": [0.16, 0.16, 0.17], "floor": [0.5, 0.52, 0.5],
    "floor_line": [1.6, 1.3, 0.05], "kraft": [1.0, 0.62, 0.32], "label": [1.55, 1.55, 1.5],
    "ink_black": [0.05, 0.05, 0.05], "ink_red": [1.45, 0.08, 0.1], "ink_blue": [0.05, 0.2, 1.1],
    "ink_green": [0.08, 0.8, 0.2], "ink_yellow": [1.7, 1.45, 0.05],
    "ink_magenta": [1.45, 0.15, 0.9],
    "ink_cyan": [0.05, 0.85, 1.25], "box_white": [1.5, 1.5, 1.46], "box_black": [0.07, 0.07, 0.08],
    "bottle_green": [0.08, 0.55, 0.15], "bottle_amber": [1.0, 0.45, 0.05],
    "can_red": [1.5, 0.06, 0.07], "can_silver": [1.1, 1.12, 1.15], "pouch_orange": [1.7, 0.6, 0.05],
    # solar: cells under textured glass, busbars, backsheet, roof tiles, chimney brick
    "cell": [0.03, 0.05, 0.16], "busbar": [1.2, 1.2, 1.22], "backsheet": [1.45, 1.45, 1.42],
    "tile_a": [1.1, 0.38, 0.2], "tile_b": [0.95, 0.33, 0.18], "tile_c": [1.2, 0.5, 0.28],
    "ridge": [0.7, 0.25, 0.14], "brick": [0.9, 0.35, 0.22], "wall": [1.4, 1.35, 1.2],
    "gutter": [1.3, 1.3, 1.3], "dormer": [0.25, 0.25, 0.27], "pane": [0.03, 0.035, 0.04],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "gold": {"n": [0.21, 0.54, 1.35], "k": [3.24, 2.18, 1.82]},
    "aluminium": {"n": [1.3, 0.95, 0.7], "k": [7.4, 6.6, 5.9]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "mosaic": 400,
    "meadow": 1000,
    "conveyor": 1100,
    "solar": 400,
    "mosaic_g21": 18,
    "conveyor_g15": 200,
}

EFFECTS = cg.EFFECTS


def r4(v):
    return cg.rounded(v, 4)


def mat(name, sigma):
    return {"n": 1.5, "k": PAINTS[name], "sigma": sigma}


def metal(name, sigma):
    return dict(METALS[name], sigma=sigma)


def sensor(name, preset="ideal", **kw):
    return cg.sensor(EXPOSURE[name], preset, **kw)


def scene(name, title, camera, lights, materials, objs, effects=None, sen=None, **extra):
    s = cg.scene("colour sealed 4: " + title, camera, lights, materials, objs,
                 effects or EFFECTS, sen or sensor(name))
    s.update(extra)
    return s


class MmObj:
    """A Wavefront OBJ in millimetres (placed with scale 0.001): polygons, one `f` record each
    (negative indices), vertices given in metres."""

    def __init__(self, title):
        self.lines = ["# " + title + ", millimetres, written by " + WRITER]

    def poly(self, pts):
        for p in pts:
            self.lines.append("v %.1f %.1f %.2f" % (p[0] * 1e3, p[1] * 1e3, p[2] * 1e3))
        self.lines.append("f " + " ".join(str(-len(pts) + i) for i in range(len(pts))))

    def text(self):
        return "\n".join(self.lines) + "\n"


def mm_mesh(file, material):
    return {"type": "mesh", "file": file, "position": [0, 0, 0], "scale": 0.001,
            "material": material, "smooth": False}


def quad(c, u, half, z, tilt=(0.0, 0.0)):
    """A square of half-size half centred at c (x, y), edge along u (a unit 2-vector), at height
    z, tilted by slopes tilt (dz/dx, dz/dy)."""
    v = [-u[1], u[0]]
    pts = []
    for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        x = c[0] + half[0] * a * u[0] + half[1] * b * v[0]
        y = c[1] + half[0] * a * u[1] + half[1] * b * v[1]
        pts.append([x, y, z + tilt[0] * (x - c[0]) + tilt[1] * (y - c[1])])
    return pts


# the sky's rings (elevation in degrees, number of lights): 12 lights and the sun, coarser than
# ../colour-sealed3's 87 to keep the render cost of the dense meshes here near that set's
SKY_RINGS = ((12, 6), (42, 5), (80, 1))


def sky_lights(sun, scale=1.0):
    """The clear sky as directional lights: rings at elevations 8-88 degrees, their irradiance
    the sky radiance (blue, brighter towards the horizon and the sun) times the solid angle they
    stand for; their polarization single scattering's: perpendicular to the plane of sun and
    sky point, degree 0.75 sin^2(g) / (1 + cos^2(g)) at scattering angle g (Rayleigh;
    Coulson, Polarization and Intensity of Light in the Atmosphere (1988), ch. 5: 0.75 for a
    clear sky's maximum). The sun last."""
    out = []
    rings = SKY_RINGS
    for q, (el, naz) in enumerate(rings):
        lo = 0 if q == 0 else (rings[q - 1][0] + el) / 2
        hi = 90 if q == len(rings) - 1 else (el + rings[q + 1][0]) / 2
        omega = 2 * math.pi * (math.sin(math.radians(hi)) - math.sin(math.radians(lo))) / naz
        for i in range(naz):
            az = 2 * math.pi * (i + 0.5 * (q % 2)) / naz
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


# ---------------------------------------------------------------------------------------------
# mosaic: a floor mosaic of 9.5 mm tesserae on a 12 mm grid (~4-6 px across, 3-5 px down the
# frame: the colour lattice's period), 2-3 mm light grout lines between them, seen
# obliquely; a checked border, a cream field with corner lozenges, a central medallion laid in
# concentric rings (opus vermiculatum) around an eight-petal rosette; glass (smalti) and gold
# tesserae are glossy and tilted by a few degrees (scattered polarized glints), stone ones matte

MOSAIC_CAMERA = {"position": [0.05, -1.3, 1.8], "look_at": [0.0, 0.12, 0.0], "up": [0, 1, 0],
                 "focal_length_mm": 3.3, "f_number": 4}
MOSAIC_CENTRE = (0.0, 0.12)
MOSAIC_HALF = (0.6, 0.5)
MEDALLION_R = 0.3
GLASS = ("t_red", "t_blue", "t_turquoise", "t_green", "gold")
STONE = ("t_white", "t_cream", "t_beige", "t_black", "t_terracotta", "t_ochre")
PITCH = 0.012


def mosaic_colour(x, y, rng):
    """The colour of the grid tessera centred at (x, y) (outside the medallion)."""
    dx, dy = x - MOSAIC_CENTRE[0], y - MOSAIC_CENTRE[1]
    ex = MOSAIC_HALF[0] - abs(dx)
    ey = MOSAIC_HALF[1] - abs(dy)
    e = min(ex, ey)
    if e < PITCH * 2:
        return "t_black"
    if e < PITCH * 6:
        # a band of 2 x 2 checks of black and terracotta, an ochre line inside it
        i, j = int(math.floor(x / (2 * PITCH))), int(math.floor(y / (2 * PITCH)))
        return ("t_terracotta", "t_black")[(i + j) % 2]
    if e < PITCH * 7:
        return "t_ochre"
    if e < PITCH * 8:
        return "t_red"
    # lozenges in the four corners of the field
    cx = math.copysign(MOSAIC_HALF[0] - 0.16, dx)
    cy = math.copysign(MOSAIC_HALF[1] - 0.15, dy)
    d = abs(dx - cx) + abs(dy - cy)
    if d < 0.055:
        return "t_green" if d < 0.03 else "t_turquoise"
    if d < 0.07:
        return "t_black"
    return rng.choice(("t_cream", "t_cream", "t_white", "t_beige"))


def medallion_colour(r, th):
    """The colour of a ring tessera at radius r, angle th (radians) in the medallion."""
    petal = 0.16 * (0.55 + 0.45 * abs(math.cos(4 * th)))
    if r < 0.025:
        return "gold"
    if r < petal:
        return "t_red" if r < petal - 0.03 else "t_ochre"
    if r < 0.18:
        return "t_white"
    if r < 0.2:
        return "t_black"
    if r < 0.25:
        # a wave band: blue and turquoise
        return "t_blue" if math.sin(12 * th + 40 * r) > 0 else "t_turquoise"
    if r < 0.265:
        return "gold"
    if r < 0.29:
        return "t_green"
    return "t_black"


def mosaic_meshes():
    rng = random.Random(4407)
    names = GLASS + STONE
    meshes = {n: MmObj("mosaic, " + n + " tesserae") for n in names}

    def tessera(name, c, ang, size):
        glass = name in GLASS
        tilt = (rng.gauss(0, 0.05), rng.gauss(0, 0.05)) if glass else (rng.gauss(0, 0.015),
                                                                         rng.gauss(0, 0.015))
        u = [math.cos(ang), math.sin(ang)]
        h = (size / 2 * rng.uniform(0.92, 1.06), size / 2 * rng.uniform(0.92, 1.06))
        meshes[name].poly(quad(c, u, h, 0.004 + rng.uniform(-0.0004, 0.0004), tilt))

    # the grid: rows of tesserae 9.5 mm, jittered, outside the medallion
    nx, ny = int(2 * MOSAIC_HALF[0] / PITCH), int(2 * MOSAIC_HALF[1] / PITCH)
    for j in range(ny):
        for i in range(nx):
            x = MOSAIC_CENTRE[0] - MOSAIC_HALF[0] + (i + 0.5) * PITCH
            y = MOSAIC_CENTRE[1] - MOSAIC_HALF[1] + (j + 0.5) * PITCH
            if math.hypot(x - MOSAIC_CENTRE[0], y - MOSAIC_CENTRE[1]) < MEDALLION_R + 0.004:
                continue
            x += rng.uniform(-0.0007, 0.0007)
            y += rng.uniform(-0.0007, 0.0007)
            tessera(mosaic_colour(x, y, rng), (x, y), math.radians(rng.uniform(-5, 5)),
                    0.0095)
    # the medallion: concentric rings of tesserae turned along the ring
    r = 0.009
    tessera("gold", MOSAIC_CENTRE, 0.3, 0.012)
    while r < MEDALLION_R - 0.004:
        n = int(2 * math.pi * r / PITCH)
        ph = rng.uniform(0, 2 * math.pi)
        for q in range(n):
            th = ph + 2 * math.pi * q / n
            c = (MOSAIC_CENTRE[0] + r * math.cos(th), MOSAIC_CENTRE[1] + r * math.sin(th))
            size = min(0.0095, 2 * math.pi * r / n - 0.0025)
            tessera(medallion_colour(r, th), c, th + math.radians(rng.uniform(-4, 4)), size)
        r += PITCH
    return {"mosaic_" + n + ".obj": m.text() for n, m in meshes.items()}


def mosaic_scene():
    m = {n: mat(n, 0.08) for n in GLASS if n != "gold"}
    m.update({n: mat(n, 0.35) for n in STONE})
    m["gold"] = metal("gold", 0.1)
    m["grout"] = mat("grout", 0.8)
    m["marble"] = mat("marble", 0.3)
    m["marble_vein"] = mat("marble_vein", 0.3)
    objs = [cg.ground("grout")]
    # the marble surround: slabs of 0.4 m, each with a dark vein across it
    rng = random.Random(4411)
    for i in range(-4, 5):
        for j in range(-3, 6):
            x, y = 0.4 * i, 0.12 + 0.4 * j
            if abs(x) < MOSAIC_HALF[0] + 0.2 and abs(y - MOSAIC_CENTRE[1]) < MOSAIC_HALF[1] + 0.2:
                continue
            objs.append(cg.rect([x, y, 0.003], [0, 0, 1], [1, 0, 0], [0.397, 0.397], "marble"))
            a = rng.uniform(0, math.pi)
            objs.append(cg.rect([x + rng.uniform(-0.1, 0.1), y + rng.uniform(-0.1, 0.1), 0.0032],
                                [0, 0, 1], [math.cos(a), math.sin(a), 0],
                                [0.3, rng.uniform(0.004, 0.012)], "marble_vein"))
    # a marble frame 0.2 m wide around the mosaic
    fx, fy = MOSAIC_HALF[0] + 0.1, MOSAIC_HALF[1] + 0.1
    cx, cy = MOSAIC_CENTRE
    for c, s in (([cx, cy + fy, 0.003], [2 * fx + 0.2, 0.198]),
                 ([cx, cy - fy, 0.003], [2 * fx + 0.2, 0.198]),
                 ([cx + fx, cy, 0.003], [0.198, 2 * fy - 0.2]),
                 ([cx - fx, cy, 0.003], [0.198, 2 * fy - 0.2])):
        objs.append(cg.rect(c, [0, 0, 1], [1, 0, 0], s, "marble"))
    for n in GLASS + STONE:
        objs.append(mm_mesh("mosaic_" + n + ".obj", n))
    lights = [{"type": "directional", "direction": r4(cg.unit([-0.45, 0.7, 0.55])),
               "irradiance_w_m2": [190, 190, 200]},
              {"type": "directional", "direction": r4(cg.unit([0.5, -0.3, 0.8])),
               "irradiance_w_m2": [45, 42, 38]}]
    return m, objs, lights


def mosaic():
    m, objs, lights = mosaic_scene()
    return scene("mosaic", "a floor mosaic of 9 mm stone, glass and gold tesserae on a 12 mm "
                 "grid (3-6 px) with light grout lines, a checked border and a medallion laid "
                 "in rings, seen obliquely in window light", MOSAIC_CAMERA, lights, m, objs)


def mosaic_g21():
    m, objs, lights = mosaic_scene()
    return scene("mosaic_g21", "the mosaic scene in a dim church through the IMX250MYR preset "
                 "at +21 dB analog gain", MOSAIC_CAMERA, lights, m, objs,
                 sen=sensor("mosaic_g21", preset="imx250myr", gain_db=21))


# ---------------------------------------------------------------------------------------------
# meadow: fine grass blades (3-6 mm wide: 1.3-3 px) in four greens and straw with small flowers
# (buttercups, daisies, poppies, cornflowers, clover) on their stems over soil, seen from 1.6 m
# at ~45 degrees, under a clear sky of directional lights with Rayleigh polarization and the sun;
# the blades' waxy surface (sigma 0.3) reflects the polarized sky

MEADOW_CAMERA = {"position": [0.0, -1.0, 1.6], "look_at": [0.0, 0.55, 0.0], "up": [0, 0, 1],
                 "focal_length_mm": 3.6, "f_number": 5.6}
MEADOW_SUN = cg.unit([0.6, 0.35, 0.72])
BLADES = ("g_fresh", "g_mid", "g_dark", "g_dry")
FLOWERS = (("f_yellow", 0.008, 5, "f_yellow"), ("f_white", 0.011, 8, "f_centre"),
           ("f_red", 0.016, 4, "ink_black"), ("f_blue", 0.01, 7, "f_blue"),
           ("f_pink", 0.007, 9, "f_pink"))
FLOWER_PAINTS = ("f_yellow", "f_white", "f_red", "f_blue", "f_pink", "f_centre", "ink_black")


def meadow_meshes():
    rng = random.Random(6121)
    meshes = {n: MmObj("meadow, " + n + " grass blades") for n in BLADES}
    heads = {n: MmObj("meadow, " + n + " flower heads") for n in FLOWER_PAINTS}

    def blade(name, x, y, h, w, az, lean):
        """A blade: a quad to mid-height and a triangle to the tip, leaning by lean (rad) in
        direction az, its face turned by a random angle."""
        face = rng.uniform(0, math.pi)
        fx, fy = math.cos(face) * w / 2, math.sin(face) * w / 2
        dx, dy = math.cos(az), math.sin(az)

        def at(t):
            # a curve bending further the higher it goes
            s = math.sin(lean) * h * t * t
            return [x + dx * s, y + dy * s, h * t * math.cos(lean * t)]

        b, m, t = at(0), at(0.55), at(1.0)
        ww = 0.6
        meshes[name].poly([[b[0] - fx, b[1] - fy, b[2]], [b[0] + fx, b[1] + fy, b[2]],
                           [m[0] + fx * ww, m[1] + fy * ww, m[2]],
                           [m[0] - fx * ww, m[1] - fy * ww, m[2]]])
        meshes[name].poly([[m[0] - fx * ww, m[1] - fy * ww, m[2]],
                           [m[0] + fx * ww, m[1] + fy * ww, m[2]], t])
        return t

    # blades over the ground the camera sees (y -0.15..1.45, x widening with distance)
    for q in range(4200):
        y = rng.uniform(-0.15, 1.45)
        x = rng.uniform(-1, 1) * (0.5 + 0.35 * (y + 0.15))
        name = BLADES[min(int(rng.random() ** 1.3 * 4.2), 3)]
        blade(name, x, y, rng.uniform(0.1, 0.38), rng.uniform(0.003, 0.006),
              rng.uniform(0, 2 * math.pi), rng.uniform(0.1, 0.9))
    # flowers: a stem (a thin mid-green blade) and a head of petals around a centre
    for q in range(170):
        y = rng.uniform(-0.1, 1.4)
        x = rng.uniform(-1, 1) * (0.45 + 0.35 * (y + 0.1))
        petal, rad, n, centre = FLOWERS[rng.randrange(len(FLOWERS))]
        rad *= rng.uniform(0.8, 1.25)
        tip = blade("g_mid", x, y, rng.uniform(0.12, 0.32), 0.0025,
                    rng.uniform(0, 2 * math.pi), rng.uniform(0.05, 0.3))
        tx, ty = rng.gauss(0, 0.3), rng.gauss(0, 0.3)
        ph = rng.uniform(0, 2 * math.pi)
        for k in range(n):
            # a petal: a kite from the centre outwards
            a = ph + 2 * math.pi * k / n
            da = math.pi / n * 0.8
            pts = []
            for rr, aa in ((0.15, a), (0.7, a - da), (1.0, a), (0.7, a + da)):
                px, py = rr * rad * math.cos(aa), rr * rad * math.sin(aa)
                pts.append([tip[0] + px, tip[1] + py, tip[2] + tx * px + ty * py])
            heads[petal].poly(pts)
        cpts = []
        for k in range(6):
            a = ph + 2 * math.pi * k / 6
            px, py = 0.3 * rad * math.cos(a), 0.3 * rad * math.sin(a)
            cpts.append([tip[0] + px, tip[1] + py, tip[2] + tx * px + ty * py + 0.0008])
        heads[centre].poly(cpts)
    out = {"meadow_" + n + ".obj": m.text() for n, m in meshes.items()}
    out.update({"meadow_head_" + n + ".obj": m.text() for n, m in heads.items()})
    return out


def meadow():
    m = {n: mat(n, 0.3) for n in BLADES}
    m["soil"] = mat("soil", 0.9)
    for n in FLOWER_PAINTS:
        m[n] = mat(n, 0.35)
    m["f_yellow"]["sigma"] = 0.12  # buttercups are glossy
    objs = [cg.ground("soil")]
    for n in BLADES:
        objs.append(mm_mesh("meadow_" + n + ".obj", n))
    for n in FLOWER_PAINTS:
        objs.append(mm_mesh("meadow_head_" + n + ".obj", n))
    return scene("meadow", "fine grass blades (1.3-3 px) in four greens and straw with "
                 "buttercups, daisies, poppies, cornflowers and clover over soil, under a clear "
                 "sky of 12 Rayleigh-polarized directional lights and the sun", MEADOW_CAMERA,
                 sky_lights(MEADOW_SUN), m, objs)


# ---------------------------------------------------------------------------------------------
# conveyor: packaged goods on a ribbed rubber conveyor belt under a bar of LED spots, seen from
# above at ~40 degrees (~1.7 mm per pixel): kraft boxes with printed labels (barcodes of 0.5-1.5
# px bars, text lines, logos), shrink-wrapped packs of bottles and cans (glossy film: sigma 0.03
# domes), glossy printed pouches, aluminium side rails, a painted floor with a yellow line

CONVEYOR_CAMERA = {"position": [0.25, -1.1, 1.25], "look_at": [0.0, 0.35, 0.1],
                   "up": [0, 0, 1], "focal_length_mm": 2.9, "f_number": 4}


def barcode(mesh, rng, x0, y0, w, h, z, along_x=True):
    """EAN-like bars: modules of 0.33 mm x 1-4 over w (m), h tall, at height z."""
    x = x0
    dark = True
    while x < x0 + w:
        mw = 0.00033 * rng.choice((1, 1, 2, 3, 4))
        if dark:
            if along_x:
                mesh.poly([[x, y0, z], [x + mw, y0, z], [x + mw, y0 + h, z], [x, y0 + h, z]])
            else:
                mesh.poly([[y0, x, z], [y0 + h, x, z], [y0 + h, x + mw, z], [y0, x + mw, z]])
        x += mw
        dark = not dark


def text_lines(mesh, rng, x0, y0, w, lines, size, z):
    """Lines of 'text': words of glyph-sized blocks (size m tall), line pitch 1.6 size."""
    for li in range(lines):
        y = y0 - li * size * 1.6
        x = x0
        while x < x0 + w * rng.uniform(0.6, 1.0):
            word = rng.randint(2, 8)
            for k in range(word):
                gw = size * rng.uniform(0.35, 0.7)
                # a glyph as two strokes: a vertical stem and a bar
                mesh.poly([[x, y, z], [x + size * 0.15, y, z], [x + size * 0.15, y + size, z],
                           [x, y + size, z]])
                yy = y + size * rng.choice((0.0, 0.45, 0.85))
                mesh.poly([[x, yy, z], [x + gw, yy, z], [x + gw, yy + size * 0.15, z],
                           [x, yy + size * 0.15, z]])
                x += gw + size * 0.15
            x += size * 0.6


def conveyor_meshes():
    rng = random.Random(8803)
    ink = MmObj("conveyor, black print (barcodes, text)")
    ribs = MmObj("conveyor, belt ribs")
    # belt ribs: 4 mm every 11 mm across the 0.8 m belt
    y = -0.6
    while y < 1.6:
        ribs.poly([[-0.4, y, 0.0012], [0.4, y, 0.0012], [0.4, y + 0.004, 0.0012],
                   [-0.4, y + 0.004, 0.0012]])
        y += 0.011
    # print on the labels and boxes (positions as in conveyor(): LABELS)
    for (x, y, z, w, h) in LABELS:
        barcode(ink, rng, x - w / 2 + 0.008, y - h / 2 + 0.006, w * 0.55, h * 0.35, z + 0.0003)
        text_lines(ink, rng, x - w / 2 + 0.008, y + h / 2 - 0.014, w - 0.016, 4, 0.004,
                   z + 0.0003)
    for (x, y, z, w) in BOX_TEXT:
        text_lines(ink, rng, x, y, w, 3, 0.008, z + 0.0003)
    return {"conveyor_ink.obj": ink.text(), "conveyor_ribs.obj": ribs.text()}


# boxes: centre (x, y), size, paint, whether it has a label, and a number not used (the boxes
# stand square to the belt)
BOXES = (
    ([-0.2, -0.25], [0.3, 0.22, 0.18], "kraft", True, 8),
    ([0.17, -0.2], [0.22, 0.3, 0.12], "box_white", True, -5),
    ([-0.12, 0.42], [0.36, 0.26, 0.2], "kraft", True, 3),
    ([0.2, 0.75], [0.2, 0.2, 0.1], "box_black", True, -12),
    ([-0.18, 1.1], [0.28, 0.24, 0.16], "kraft", False, 6),
)
# labels: centre x, y, top z of the box, width, height (m)
LABELS = tuple((c[0] + 0.02, c[1] - 0.01, s[2], 0.1, 0.07) for c, s, p, lab, yaw in BOXES
               if lab)
BOX_TEXT = ((-0.3, -0.2, 0.18, 0.09), (-0.25, 0.5, 0.2, 0.12))


def conveyor_scene():
    rng = random.Random(8807)
    m = {"belt": mat("belt", 0.45), "belt_rib": mat("belt_rib", 0.45),
         "floor": mat("floor", 0.35), "floor_line": mat("floor_line", 0.5),
         "kraft": mat("kraft", 0.75), "label": mat("label", 0.2),
         "ink_black": mat("ink_black", 0.3), "box_white": mat("box_white", 0.25),
         "box_black": mat("box_black", 0.2), "alu": metal("aluminium", 0.25)}
    for n in ("ink_red", "ink_blue", "ink_green", "ink_yellow", "ink_magenta", "ink_cyan"):
        m[n] = mat(n, 0.25)
    # shrink-wrap film over bottles and cans, glossy printed pouches
    for n in ("bottle_green", "bottle_amber", "can_red", "can_silver"):
        m[n] = mat(n, 0.03)
    m["pouch_orange"] = mat("pouch_orange", 0.06)
    m["pouch_cyan"] = mat("ink_cyan", 0.06)
    m["pouch_magenta"] = mat("ink_magenta", 0.06)
    up = [0, 0, 1]
    objs = [cg.ground("floor", -0.6),
            cg.rect([0.9, 0.5, -0.599], up, [0, 1, 0], [4.0, 0.08], "floor_line"),
            cg.rect([0.0, 0.5, 0.0], up, [0, 1, 0], [3.0, 0.8], "belt"),
            mm_mesh("conveyor_ribs.obj", "belt_rib"), mm_mesh("conveyor_ink.obj", "ink_black")]
    # side rails and their supports
    for side in (-1, 1):
        objs.append({"type": "box", "center": [side * 0.43, 0.5, 0.0], "size": [0.05, 3.0, 0.09],
                     "material": "alu"})
        for y in (-0.4, 0.6, 1.6):
            objs.append({"type": "box", "center": [side * 0.43, y, -0.32],
                         "size": [0.04, 0.04, 0.55], "material": "alu"})
    # boxes with labels: a white label, a coloured logo band, print (the ink mesh)
    inks = ("ink_red", "ink_blue", "ink_green", "ink_magenta")
    for q, (c, s, paint, lab, yaw) in enumerate(BOXES):
        objs.append({"type": "box", "center": [c[0], c[1], s[2] / 2], "size": s,
                     "material": paint})
        if lab:
            objs.append(cg.rect([c[0] + 0.02, c[1] - 0.01, s[2] + 0.0002], up, [1, 0, 0],
                                [0.1, 0.07], "label"))
            objs.append(cg.rect([c[0] + 0.02, c[1] - 0.01 + 0.026, s[2] + 0.0003], up,
                                [1, 0, 0], [0.1, 0.012], inks[q % 4]))
        # a logo: three coloured stripes at an angle
        for k in range(3):
            a = math.radians(30 + 7 * q)
            objs.append(cg.rect([c[0] - s[0] / 4 + 0.012 * k, c[1] + s[1] / 4, s[2] + 0.0002],
                                up, [math.cos(a), math.sin(a), 0], [0.07, 0.006],
                                inks[(q + k) % 4]))
    # a shrink-wrapped pack of 2 x 3 green bottles (their shoulders under the film: spheres)
    for i in range(3):
        for j in range(2):
            objs.append({"type": "sphere", "center": r4([-0.13 + 0.075 * i, 0.05 + 0.075 * j,
                                                         0.2]),
                         "radius": 0.037, "material": "bottle_green"})
            objs.append({"type": "sphere", "center": r4([-0.13 + 0.075 * i, 0.05 + 0.075 * j,
                                                         0.24]),
                         "radius": 0.014, "material": "bottle_amber"})
    objs.append({"type": "box", "center": [-0.055, 0.0875, 0.1], "size": [0.225, 0.15, 0.2],
                 "material": "bottle_green"})
    # a tray of 4 x 3 cans under film, red with silver lids
    for i in range(4):
        for j in range(3):
            x, y = 0.14 + 0.068 * i - 0.1, 0.28 + 0.068 * j
            objs.append({"type": "sphere", "center": r4([x, y, 0.09]), "radius": 0.034,
                         "material": "can_red"})
            objs.append({"type": "sphere", "center": r4([x, y, 0.116]), "radius": 0.018,
                         "material": "can_silver"})
    objs.append({"type": "box", "center": [0.142, 0.348, 0.045], "size": [0.28, 0.21, 0.09],
                 "material": "can_red"})
    # glossy pouches lying slightly tilted, printed with bands
    for q in range(5):
        x, y = rng.uniform(-0.3, 0.3), rng.uniform(0.85, 1.5)
        a = rng.uniform(0, math.pi)
        tilt = rng.uniform(-0.25, 0.25)
        nrm = cg.unit([math.sin(tilt), rng.uniform(-0.2, 0.2), 1])
        u = cg.unit(cg.cross([-math.sin(a), math.cos(a), 0], nrm))
        paint = ("pouch_orange", "pouch_cyan", "pouch_magenta")[q % 3]
        objs.append(cg.rect([x, y, 0.03], nrm, u, [0.16, 0.11], paint))
        for k in range(3):
            objs.append(cg.rect(cg.add([x, y, 0.031], u, -0.05 + 0.03 * k), nrm, u,
                                [0.008, 0.1], ("label", "ink_yellow", "ink_blue")[k]))
    # the LED bar: six spots along the belt 0.9 m above it, and the hall's fill light
    lights = [{"type": "point", "position": [0.15, -0.3 + 0.4 * k, 0.95],
               "intensity_w_sr": [11, 11.5, 12]} for k in range(6)]
    lights.append({"type": "directional", "direction": r4(cg.unit([-0.3, -0.5, 0.8])),
                   "irradiance_w_m2": [40, 40, 40]})
    return m, objs, lights


def conveyor():
    m, objs, lights = conveyor_scene()
    return scene("conveyor", "packaged goods on a ribbed conveyor belt under an LED bar: kraft "
                 "boxes with printed labels and barcodes, shrink-wrapped bottles and cans, "
                 "glossy printed pouches, aluminium rails", CONVEYOR_CAMERA, lights, m, objs)


def conveyor_g15():
    m, objs, lights = conveyor_scene()
    return scene("conveyor_g15", "the conveyor scene at a short exposure (motion) through the "
                 "IMX250MYR preset at +15 dB analog gain", CONVEYOR_CAMERA, lights, m, objs,
                 sen=sensor("conveyor_g15", preset="imx250myr", gain_db=15))


# ---------------------------------------------------------------------------------------------
# solar: a rooftop photovoltaic array (2 rows of 5 panels, 6 x 10 monocrystalline cells of
# 156 mm with chamfered corners, three busbars 52 mm apart: ~4.5 px) on a tiled roof pitched 30
# degrees, seen from a neighbouring building ~14.5 m away at ~56 degrees off the panels' normal
# (Brewster's angle of glass): the textured cover glass (sigma 0.1) mirrors the polarized sky

SOLAR_CAMERA = {"position": [2.0, -12.0, 6.6], "look_at": [0.0, 0.5, 5.3], "up": [0, 0, 1],
                "focal_length_mm": 4.3, "f_number": 5.6}
SOLAR_SUN = cg.unit([-0.75, -0.25, 0.62])
ROOF_PITCH = math.radians(30)


def roof_point(u, v, h=0.0):
    """A point on the roof: u along the eaves (x), v up the slope from the eaves (y = 0, z = 4),
    h above the roof surface."""
    c, s = math.cos(ROOF_PITCH), math.sin(ROOF_PITCH)
    return [u, v * c - h * s, 4.0 + v * s + h * c]


def solar_meshes():
    rng = random.Random(3131)
    cells = MmObj("solar, cells (under glass)")
    bars = MmObj("solar, busbars")
    back = MmObj("solar, backsheet")
    frames = MmObj("solar, panel frames")
    tiles = {n: MmObj("solar, " + n + " roof tiles") for n in ("tile_a", "tile_b", "tile_c")}
    rows = MmObj("solar, shadowed tile edges")
    cs, gap, ch = 0.156, 0.003, 0.02
    pw, ph = 6 * cs + 7 * gap + 0.06, 10 * cs + 11 * gap + 0.06
    for pr in range(2):
        for pc in range(5):
            u0 = -2.6 + pc * (pw + 0.02)
            v0 = 1.0 + pr * (ph + 0.03)
            # the frame (35 mm aluminium edge) and backsheet
            frames.poly([roof_point(u0, v0, 0.1), roof_point(u0 + pw, v0, 0.1),
                         roof_point(u0 + pw, v0 + ph, 0.1), roof_point(u0, v0 + ph, 0.1)])
            back.poly([roof_point(u0 + 0.03, v0 + 0.03, 0.102),
                       roof_point(u0 + pw - 0.03, v0 + 0.03, 0.102),
                       roof_point(u0 + pw - 0.03, v0 + ph - 0.03, 0.102),
                       roof_point(u0 + 0.03, v0 + ph - 0.03, 0.102)])
            for i in range(6):
                for j in range(10):
                    a = u0 + 0.03 + gap + i * (cs + gap)
                    b = v0 + 0.03 + gap + j * (cs + gap)
                    cells.poly([roof_point(a + ch, b, 0.104), roof_point(a + cs - ch, b, 0.104),
                                roof_point(a + cs, b + ch, 0.104),
                                roof_point(a + cs, b + cs - ch, 0.104),
                                roof_point(a + cs - ch, b + cs, 0.104),
                                roof_point(a + ch, b + cs, 0.104),
                                roof_point(a, b + cs - ch, 0.104),
                                roof_point(a, b + ch, 0.104)])
                    for k in range(3):
                        x = a + cs / 6 + k * cs / 3
                        bars.poly([roof_point(x - 0.0008, b, 0.1045),
                                   roof_point(x + 0.0008, b, 0.1045),
                                   roof_point(x + 0.0008, b + cs, 0.1045),
                                   roof_point(x - 0.0008, b + cs, 0.1045)])
    # clay tiles: courses 0.33 m up the slope, tiles 0.3 m wide, offset by half a tile per course
    for course in range(17):
        v = course * 0.33
        off = 0.15 * (course % 2)
        u = -4.5 - off
        while u < 4.5:
            n = ("tile_a", "tile_b", "tile_c")[rng.randrange(3)]
            tiles[n].poly([roof_point(u + 0.004, v, 0.0), roof_point(u + 0.296, v, 0.0),
                           roof_point(u + 0.296, v + 0.33, 0.0),
                           roof_point(u + 0.004, v + 0.33, 0.0)])
            u += 0.3
        # the shadowed lower edge of the course above
        rows.poly([roof_point(-4.5, v + 0.31, 0.001), roof_point(4.5, v + 0.31, 0.001),
                   roof_point(4.5, v + 0.33, 0.001), roof_point(-4.5, v + 0.33, 0.001)])
    out = {"solar_cells.obj": cells.text(), "solar_busbars.obj": bars.text(),
           "solar_backsheet.obj": back.text(), "solar_frames.obj": frames.text(),
           "solar_tile_edges.obj": rows.text()}
    out.update({"solar_" + n + ".obj": m.text() for n, m in tiles.items()})
    return out


def solar():
    m = {"cell": {"n": 1.52, "k": PAINTS["cell"], "sigma": 0.1},
         "busbar": {"n": 1.52, "k": PAINTS["busbar"], "sigma": 0.1},
         "backsheet": {"n": 1.52, "k": PAINTS["backsheet"], "sigma": 0.1},
         "alu": metal("aluminium", 0.3), "tile_edge": mat("ridge", 0.6),
         "brick": mat("brick", 0.8), "wall": mat("wall", 0.7), "gutter": mat("gutter", 0.3),
         "dormer": mat("dormer", 0.4), "pane": {"n": 1.52, "k": PAINTS["pane"], "sigma": 0.03},
         "lawn": mat("g_mid", 0.8)}
    for n in ("tile_a", "tile_b", "tile_c"):
        m[n] = mat(n, 0.5)
    objs = [cg.ground("lawn"),
            # the house's front wall under the eaves, and the gutter
            cg.rect([0, -0.05, 2.0], [0, -1, 0], [1, 0, 0], [9.0, 4.0], "wall"),
            {"type": "box", "center": [0, -0.1, 3.97], "size": [9.2, 0.14, 0.12],
             "material": "gutter"}]
    # two windows in the wall
    for x in (-2.5, 1.5):
        objs.append(cg.rect([x, -0.06, 2.6], [0, -1, 0], [1, 0, 0], [1.2, 1.3], "dormer"))
        objs.append(cg.rect([x, -0.07, 2.6], [0, -1, 0], [1, 0, 0], [1.05, 1.15], "pane"))
    for n in ("tile_a", "tile_b", "tile_c"):
        objs.append(mm_mesh("solar_" + n + ".obj", n))
    objs += [mm_mesh("solar_tile_edges.obj", "tile_edge"),
             mm_mesh("solar_frames.obj", "alu"), mm_mesh("solar_backsheet.obj", "backsheet"),
             mm_mesh("solar_cells.obj", "cell"), mm_mesh("solar_busbars.obj", "busbar")]
    # a brick chimney near the ridge
    top = roof_point(3.3, 4.6)
    objs.append({"type": "box", "center": r4([3.3, top[1], top[2] + 0.3]),
                 "size": [0.6, 0.5, 1.6], "material": "brick"})
    return scene("solar", "a rooftop array of ten photovoltaic panels (cells with chamfered "
                 "corners, busbars at ~4.5 px) on a tiled roof, seen near Brewster's angle of the "
                 "glass, mirroring a clear sky of 12 Rayleigh-polarized directional lights",
                 SOLAR_CAMERA, sky_lights(SOLAR_SUN), m, objs, background=[30, 42, 70])


SCENES = {"mosaic": mosaic, "meadow": meadow, "conveyor": conveyor, "solar": solar,
          "mosaic_g21": mosaic_g21, "conveyor_g15": conveyor_g15}


def meshes():
    out = {}
    out.update(mosaic_meshes())
    out.update(meadow_meshes())
    out.update(conveyor_meshes())
    out.update(solar_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
