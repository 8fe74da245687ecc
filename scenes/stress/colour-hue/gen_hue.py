#!/usr/bin/env python3
"""Writes the colour-hue development scenes (README.md beside this file) and their meshes.

Python 3 standard library only; deterministic: `python3 gen_hue.py` in this directory rewrites
every .json and .obj here (the files are checked in, this is how they were made).
`python3 gen_hue.py --print NAME` prints one scene instead.

Fine detail in hue pairs (docs/demosaicking.md, Round 16): bars, checks, halftone dots and line
pairs of two paints whose pseudo-panchromatic brightness differs little (green against magenta:
P0 counts green twice, so the pair's R + G + B contrast is halved in P0) or whose hue flips
(red against cyan), at 2.5-8 px periods, the red and blue lattices' Nyquist period (8 px) and
below. Paints as ../colour_gen.py (per-channel extinction coefficients, n = 1.5). Exposures
were set from the rendered raw frames only (a few pixels at most at full scale), before any
method was run on these scenes.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import colour_gen as cg  # noqa: E402 (../colour_gen.py: the shared helpers)

WRITER = "gen_hue.py"
PX = 0.00174  # metres per pixel at z = 0 under cg.TOP (about)

# name: k[R, G, B]
PAINTS = {
    "green": [0.03, 1.8, 0.03],
    "magenta": [1.6, 0.03, 1.7],
    "red": [1.8, 0.03, 0.03],
    "cyan": [0.03, 1.6, 1.8],
    "lime": [0.8, 1.8, 0.05],
    "violet": [0.8, 0.04, 1.8],
    "blue": [0.03, 0.1, 1.8],
    "yellow": [1.8, 1.6, 0.03],
    "orange": [1.8, 0.6, 0.03],
    "teal": [0.03, 1.3, 0.9],
    "white": [1.4, 1.4, 1.4],
}

EXPOSURE = {"gm_bars": 560, "rc_checks": 300, "halftone": 340, "polar_bars": 200,
            "gm_bars_g18": 7}

LIGHTS = [{"type": "directional", "direction": [-0.3, -0.4, 0.87], "irradiance_w_m2": 230},
          {"type": "directional", "direction": [0.45, 0.25, 0.86], "irradiance_w_m2": 110}]


def mats(names, sigma):
    return cg.paints(PAINTS, names, sigma)


def scene(name, title, objs, materials, lights=None, sen=None):
    return cg.scene("colour hue pairs: " + title, cg.TOP, lights or LIGHTS, materials, objs,
                    cg.EFFECTS, sen or cg.sensor(EXPOSURE[name]))


def mesh(file, material):
    return {"type": "mesh", "file": file, "position": [0, 0, 0], "scale": 1,
            "material": material, "smooth": False}


def to3(p, z):
    return [p[0], p[1], z]


def bars_in_disc(obj, cx, cy, radius, period, angle_deg, z):
    """Bars of width period/2 across a disc (all in metres), turned by angle_deg."""
    a = math.radians(angle_deg)
    u, v = (math.cos(a), math.sin(a)), (-math.sin(a), math.cos(a))  # u along the bars
    n = int(radius / period) + 1
    for k in range(-n, n + 1):
        d0, d1 = k * period, k * period + period / 2
        dm = (d0 + d1) / 2
        if abs(dm) >= radius:
            continue
        half = math.sqrt(radius * radius - dm * dm)
        pts = [(cx + s * half * u[0] + d * v[0], cy + s * half * u[1] + d * v[1])
               for s, d in ((-1, d0), (1, d0), (1, d1), (-1, d1))]
        obj.poly([to3(p, z) for p in pts])


def checks_in_disc(obj, cx, cy, radius, cell, angle_deg, z):
    """The dark squares of a checkerboard of cell size `cell` whose centres lie in the disc."""
    a = math.radians(angle_deg)
    ca, sa = math.cos(a), math.sin(a)
    n = int(radius / cell) + 1
    for j in range(-n, n + 1):
        for i in range(-n, n + 1):
            if (i + j) % 2:
                continue
            x, y = (i + 0.5) * cell, (j + 0.5) * cell
            if x * x + y * y >= radius * radius:
                continue
            pts = []
            for sx, sy in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)):
                qx, qy = x + sx * cell, y + sy * cell
                pts.append((cx + qx * ca - qy * sa, cy + qx * sa + qy * ca))
            obj.poly([to3(p, z) for p in pts])


def disc_poly(obj, cx, cy, r, z, n=48):
    obj.poly([[cx + r * math.cos(2 * math.pi * k / n), cy + r * math.sin(2 * math.pi * k / n),
               z] for k in range(n)])


# gm_bars: 5 periods x 3 rows of angles, discs of radius 42 px at 100/110 px spacing
GM_PERIODS = (2.5, 3.3, 4.5, 6.0, 8.0)
GM_ANGLES = (0.0, 30.0, 67.5)


def gm_bars_mesh():
    o = cg.Obj("green bars on magenta, periods 2.5-8 px", WRITER)
    for j, ang in enumerate(GM_ANGLES):
        for i, t in enumerate(GM_PERIODS):
            bars_in_disc(o, (i - 2) * 100 * PX, (1 - j) * 110 * PX, 42 * PX, t * PX,
                         ang + 7 * i, 0.001)
    return o.text()


def gm_bars_scene(name, title, sen=None):
    m = mats(("green",), 0.08)
    m["paper"] = {"n": 1.5, "k": PAINTS["magenta"], "sigma": 0.5}
    return scene(name, title, [cg.ground("paper"), mesh("gm_bars.obj", "green")], m, sen=sen)


def gm_bars():
    return gm_bars_scene("gm_bars", "glossy green bars on matte magenta, periods 2.5, 3.3, "
                         "4.5, 6, 8 px at 0-95 degrees")


def gm_bars_g18():
    return gm_bars_scene("gm_bars_g18", "gm_bars through the IMX250MYR preset at +18 dB and a "
                         "short exposure", sen=cg.sensor(EXPOSURE["gm_bars_g18"],
                                                         "imx250myr", gain_db=18))


# rc_checks: two rows of four discs (radius 48 px): red/cyan checks above, lime/violet below,
# cells 1.5, 2, 3, 4 px (periods 3-8 px) at 0, 20, 45, 10 degrees
RC_CELLS = (1.5, 2.0, 3.0, 4.0)
RC_ANGLES = (0.0, 20.0, 45.0, 10.0)
RC_ROWS = (("red", "cyan"), ("lime", "violet"))


def rc_meshes():
    out = {}
    for row, (a, b) in enumerate(RC_ROWS):
        top = cg.Obj("checks, %s squares" % a, WRITER)
        under = cg.Obj("check backgrounds, %s discs" % b, WRITER)
        for i, (c, ang) in enumerate(zip(RC_CELLS, RC_ANGLES)):
            cx, cy = (i - 1.5) * 120 * PX, (0.5 - row) * 170 * PX
            disc_poly(under, cx, cy, 50 * PX, 0.001)
            checks_in_disc(top, cx, cy, 48 * PX, c * PX, ang, 0.0015)
        out["rc_%s.obj" % a] = top.text()
        out["rc_%s_disc.obj" % b] = under.text()
    return out


def rc_checks():
    m = mats(("red", "cyan", "lime", "violet"), 0.3)
    m["grey"] = {"n": 1.5, "k": [0.5, 0.5, 0.5], "sigma": 0.4}
    objs = [cg.ground("grey")]
    for a, b in RC_ROWS:
        objs.append(mesh("rc_%s_disc.obj" % b, b))
        objs.append(mesh("rc_%s.obj" % a, a))
    return scene("rc_checks", "checkerboards of red/cyan and lime/violet, cells 1.5-4 px, "
                 "turned 0-45 degrees", objs, m)


# halftone: three rotated screens of square dots (cyan, magenta, yellow) over a 250 x 190 px
# picture of smooth tone ramps on white paper, and line pairs of 1-3 px beside it
HT_BOX = (-225 * PX, 25 * PX, -95 * PX, 95 * PX)
HT_SCREENS = (("cyan", 22.0, 4.3), ("magenta", 68.0, 4.3), ("yellow", 3.0, 4.8))


def ht_cover(ink, u, v):
    """Coverage 0-1 of an ink at relative picture position (u, v) in [0, 1]^2: crossing ramps,
    so every pair of inks overlaps somewhere."""
    if ink == "cyan":
        return 0.85 * u
    if ink == "magenta":
        return 0.15 + 0.7 * v * (0.5 + 0.5 * math.sin(3.0 * u))
    return 0.8 * (1 - u) * (0.3 + 0.7 * (1 - v))


LINE_PAIRS = (("green", "magenta"), ("red", "cyan"), ("blue", "yellow"))
LINE_WIDTHS = (1.0, 1.5, 2.0, 3.0)


def ht_meshes():
    out = {}
    x0, x1, y0, y1 = HT_BOX
    for s, (ink, ang, pitch_px) in enumerate(HT_SCREENS):
        o = cg.Obj("halftone screen, " + ink, WRITER)
        a = math.radians(ang)
        ca, sa = math.cos(a), math.sin(a)
        p = pitch_px * PX
        n = int(1.2 * max(x1 - x0, y1 - y0) / p)
        xc, yc = (x0 + x1) / 2, (y0 + y1) / 2
        for j in range(-n, n + 1):
            for i in range(-n, n + 1):
                x, y = xc + i * p * ca - j * p * sa, yc + i * p * sa + j * p * ca
                if not (x0 <= x <= x1 and y0 <= y <= y1):
                    continue
                c = ht_cover(ink, (x - x0) / (x1 - x0), (y - y0) / (y1 - y0))
                if c < 0.05:
                    continue
                h = 0.5 * p * math.sqrt(min(c, 0.95))
                pts = [[x + (sx * ca - sy * sa) * h, y + (sx * sa + sy * ca) * h,
                        0.0004 + 0.0002 * s] for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
                o.poly(pts)
        out["ht_%s.obj" % ink] = o.text()
    # line pairs right of the picture: per colour pair one column of four groups (widths 1, 1.5,
    # 2, 3 px), lines of the first colour on a band of the second, turned by 4, 49, 86 degrees
    for q, (a, b) in enumerate(LINE_PAIRS):
        lines = cg.Obj("line pairs, %s lines" % a, WRITER)
        band = cg.Obj("line pairs, %s bands" % b, WRITER)
        for g, wpx in enumerate(LINE_WIDTHS):
            cx, cy = (75 + 60 * q) * PX, (135 - 90 * g) * PX
            disc_poly(band, cx, cy, 27 * PX, 0.0003)
            bars_in_disc(lines, cx, cy, 26 * PX, 2 * wpx * PX, (4, 49, 86)[q] + 3 * g, 0.0005)
        out["ht_lines_%s.obj" % a] = lines.text()
        out["ht_bands_%s.obj" % b] = band.text()
    return out


def halftone():
    m = mats(("cyan", "magenta", "yellow", "green", "red", "blue"), 0.35)
    m["paper"] = {"n": 1.5, "k": PAINTS["white"], "sigma": 0.5}
    objs = [cg.ground("paper")]
    for ink, _, _ in HT_SCREENS:
        objs.append(mesh("ht_%s.obj" % ink, ink))
    for a, b in LINE_PAIRS:
        objs.append(mesh("ht_bands_%s.obj" % b, b))
        objs.append(mesh("ht_lines_%s.obj" % a, a))
    return scene("halftone", "cyan, magenta and yellow screens of square dots (pitch 4.3-4.8 "
                 "px) and line pairs of 1-3 px in hue pairs", objs, m)


# polar_bars: four glossy plates tilted 40 degrees towards four azimuths, each in mirror
# geometry of its own light (polarized specular reflection, different AoLP per plate), carrying
# bars of a hue pair on a plate of the other colour
PB = (("green", "magenta", 4.2, 15.0), ("red", "cyan", 3.6, 80.0),
      ("lime", "violet", 5.5, 35.0), ("orange", "teal", 6.8, 120.0))


def pb_frame(q):
    tilt = math.radians(40)
    phi = math.pi / 2 * q + math.radians(25)
    n = [math.sin(tilt) * math.cos(phi), math.sin(tilt) * math.sin(phi), math.cos(tilt)]
    u = cg.unit([-n[1], n[0], 0])
    v = cg.cross(n, u)
    c = [(-0.5 + (q % 2)) * 0.27, (0.5 - q // 2) * 0.2, 0.06]
    return c, n, u, v


def pb_meshes():
    out = {}
    for q, (a, b, t, ang) in enumerate(PB):
        c, n, u, v = pb_frame(q)
        o = cg.Obj("tilted bars, %s on %s" % (a, b), WRITER)
        flat = cg.Obj("flat", WRITER)
        bars_in_disc(flat, 0, 0, 50 * PX, t * PX, ang, 0)
        # map the flat bars (x, y) onto the plate: c + x u + y v + 0.4 mm n
        for line in flat.lines[1:]:
            if line.startswith("v "):
                x, y, _ = (float(s) for s in line.split()[1:])
                o.lines.append("v %.5f %.5f %.5f" % tuple(
                    c[i] + x * u[i] + y * v[i] + 0.0004 * n[i] for i in range(3)))
            else:
                o.lines.append(line)
        out["pb_%d.obj" % q] = o.text()
    return out


def polar_bars():
    view = cg.unit([0, 1.0, 6.0])
    lights = []
    objs = [cg.ground("ground")]
    m = {"ground": {"n": 1.5, "k": [0.05, 0.05, 0.05], "sigma": 0.4}}
    m.update(mats([x for p in PB for x in p[:2]], 0.1))
    for q, (a, b, _, _) in enumerate(PB):
        c, n, u, _ = pb_frame(q)
        d = cg.dot(n, view)
        L = [2 * d * ni - vi for ni, vi in zip(n, view)]
        lights.append({"type": "directional", "direction": cg.rounded(L, 5),
                       "irradiance_w_m2": 160})
        objs.append(cg.rect(c, n, u, [0.2, 0.17], b))
        objs.append(mesh("pb_%d.obj" % q, a))
    lights.append({"type": "directional", "direction": [0, 0, 1], "irradiance_w_m2": 60})
    return scene("polar_bars", "glossy plates tilted 40 degrees in mirror geometry, each with "
                 "bars of a hue pair (3.6-6.8 px): polarized hue detail", objs, m, lights=lights)


SCENES = {"gm_bars": gm_bars, "rc_checks": rc_checks, "halftone": halftone,
          "polar_bars": polar_bars, "gm_bars_g18": gm_bars_g18}


def meshes():
    out = {"gm_bars.obj": gm_bars_mesh()}
    out.update(rc_meshes())
    out.update(ht_meshes())
    out.update(pb_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
