#!/usr/bin/env python3
"""Writes the third sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed3.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed3.py --print NAME` prints one scene instead.
The shared helpers (colour sensor, scene, rect, vectors, ...) are ../colour_gen.py.

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). Metals are n - ik per channel at 610, 530 and 465 nm: gold read
approximately off Johnson & Christy, Phys. Rev. B 6, 4370 (1972) (from memory of the curves, to
~10 %, not a table lookup); "tin" (solder, pins) is an assumed grey metal of the right order
(n 1-1.6, k 4-5.3), not a measured one. None of the paints, meshes or layouts of ../colour,
../colour-holdout, ../colour-sealed or ../colour-sealed2 is reused.

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

WRITER = "gen_sealed3.py"

# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # cables: PVC insulation in the IEC / ribbon-cable colour code, a dark mounting plate
    "w_brown": [0.75, 0.35, 0.16], "w_red": [1.65, 0.1, 0.1], "w_orange": [1.7, 0.65, 0.06],
    "w_yellow": [1.7, 1.45, 0.08], "w_green": [0.1, 1.05, 0.25], "w_blue": [0.08, 0.3, 1.45],
    "w_violet": [0.75, 0.2, 1.3], "w_grey": [0.75, 0.75, 0.75], "w_white": [1.5, 1.5, 1.48],
    "w_black": [0.06, 0.06, 0.065], "w_cyan": [0.2, 1.1, 1.5],
    "plate": [0.025, 0.025, 0.03], "rail": [0.65, 0.66, 0.68], "slot": [0.02, 0.02, 0.02],
    # chart: 24 patches after the classic colour checker's hues (eyeballed, not measured), a
    # black surround, a light wooden table
    "c_darkskin": [0.55, 0.3, 0.2], "c_lightskin": [1.45, 0.95, 0.75],
    "c_bluesky": [0.4, 0.6, 0.95], "c_foliage": [0.32, 0.45, 0.15],
    "c_blueflower": [0.7, 0.65, 1.15], "c_bluishgreen": [0.38, 1.3, 1.1],
    "c_orange": [1.65, 0.55, 0.06], "c_purplishblue": [0.2, 0.3, 1.05],
    "c_moderatered": [1.45, 0.3, 0.35], "c_purple": [0.35, 0.12, 0.42],
    "c_yellowgreen": [1.0, 1.3, 0.12], "c_orangeyellow": [1.7, 1.0, 0.05],
    "c_blue": [0.06, 0.15, 0.85], "c_green": [0.2, 0.85, 0.2], "c_red": [1.3, 0.08, 0.1],
    "c_yellow": [1.75, 1.5, 0.03], "c_magenta": [1.45, 0.22, 0.85], "c_cyan": [0.02, 0.7, 1.1],
    "c_white": [1.65, 1.65, 1.63], "c_n8": [1.2, 1.2, 1.2], "c_n65": [0.85, 0.85, 0.85],
    "c_n5": [0.55, 0.55, 0.55], "c_n35": [0.3, 0.3, 0.3], "c_black": [0.09, 0.09, 0.09],
    "c_surround": [0.04, 0.04, 0.045], "table": [1.2, 0.8, 0.45],
    # car park
    "car_red": [1.55, 0.07, 0.09], "car_navy": [0.05, 0.1, 0.55], "car_white": [1.5, 1.5, 1.47],
    "car_black": [0.04, 0.04, 0.045], "car_teal": [0.08, 0.75, 0.7], "tyre": [0.05, 0.05, 0.05],
    "asphalt": [0.28, 0.28, 0.3], "line_white": [1.4, 1.4, 1.38], "kerb": [0.9, 0.88, 0.82],
    "grass": [0.2, 0.75, 0.12],
    # circuit board
    "mask": [0.1, 0.55, 0.2], "mask_cu": [0.25, 0.85, 0.3], "silk": [1.55, 1.55, 1.5],
    "epoxy": [0.05, 0.05, 0.055], "res_beige": [1.35, 1.05, 0.7], "res_blue": [0.3, 0.6, 1.3],
    "b_black": [0.05, 0.05, 0.05], "b_brown": [0.65, 0.3, 0.12], "b_red": [1.55, 0.1, 0.1],
    "b_orange": [1.7, 0.6, 0.05], "b_yellow": [1.7, 1.4, 0.06], "b_green": [0.08, 1.0, 0.2],
    "b_blue": [0.06, 0.25, 1.4], "b_violet": [0.7, 0.15, 1.2], "b_grey": [0.7, 0.7, 0.7],
    "b_white": [1.5, 1.5, 1.5], "led_red": [1.75, 0.05, 0.05], "led_green": [0.05, 1.5, 0.15],
    "led_blue": [0.05, 0.15, 1.6], "led_yellow": [1.75, 1.3, 0.04], "cap_ochre": [1.3, 0.9, 0.4],
    "cap_blue": [0.05, 0.15, 0.6], "cap_stripe": [0.9, 0.9, 0.95],
    # living room
    "floor_wood": [0.95, 0.55, 0.28], "wall_cream": [1.45, 1.35, 1.05],
    "wall_sage": [0.75, 0.95, 0.7], "ceiling": [1.4, 1.4, 1.4], "sofa": [1.3, 0.15, 0.2],
    "cushion": [1.6, 1.2, 0.15], "shelf": [0.5, 0.3, 0.15], "rug_a": [0.2, 0.35, 0.9],
    "rug_b": [1.5, 1.4, 1.2], "rug_c": [1.3, 0.4, 0.1], "leaf": [0.12, 0.7, 0.15],
    "pot": [1.2, 0.5, 0.3], "lamp": [1.5, 1.45, 1.3], "frame": [0.08, 0.07, 0.06],
    "bk_red": [1.4, 0.15, 0.15], "bk_blue": [0.1, 0.3, 1.1], "bk_green": [0.15, 0.8, 0.3],
    "bk_yellow": [1.6, 1.3, 0.15], "bk_white": [1.45, 1.4, 1.3], "bk_black": [0.07, 0.07, 0.08],
    "bk_orange": [1.6, 0.6, 0.1], "bk_purple": [0.6, 0.2, 0.9], "bk_teal": [0.1, 0.8, 0.8],
}

# n, k per channel [R 610, G 530, B 465 nm] (see the module docstring)
METALS = {
    "gold": {"n": [0.21, 0.54, 1.35], "k": [3.24, 2.18, 1.82]},
    "tin": {"n": [1.6, 1.25, 0.95], "k": [5.3, 4.6, 3.9]},
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "cables": 600,
    "chart": 400,
    "carpark": 400,
    "pcb": 600,
    "livingroom_g12": 2800,
    "carpark_g9": 33,
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
    s = cg.scene("colour sealed 3: " + title, camera, lights, materials, objs,
                 effects or EFFECTS, sen or sensor(name))
    s.update(extra)
    return s


class Mesh:
    """A Wavefront OBJ with vertex normals (smooth tubes) being written."""

    def __init__(self, title):
        self.lines = ["# " + title + ", written by " + WRITER]
        self.n = 0

    def vert(self, p, nrm):
        self.lines.append("v %.5f %.5f %.5f" % tuple(p))
        self.lines.append("vn %.3f %.3f %.3f" % tuple(cg.unit(nrm)))
        self.n += 1
        return self.n

    def face(self, idx):
        self.lines.append("f " + " ".join("%d//%d" % (i, i) for i in idx))

    def tube(self, pts, radius, up=(0, 0, 1), angles=(0, 60, 120, 180)):
        """The upper part of a tube of radius around the polyline pts (its centre line): rings
        of vertices at angles (degrees) from the side axis (horizontal, perpendicular to the
        line) over up; smooth normals (radial)."""
        rings = []
        for i, c in enumerate(pts):
            a, b = pts[max(i - 1, 0)], pts[min(i + 1, len(pts) - 1)]
            d = cg.unit(cg.add(b, a, -1))
            side = cg.unit(cg.cross(d, up))
            top = cg.cross(side, d)
            ring = []
            for ang in angles:
                t = math.radians(ang)
                nrm = cg.add([math.cos(t) * x for x in side], top, math.sin(t))
                ring.append(self.vert(cg.add(c, nrm, radius), nrm))
            rings.append(ring)
        for r0, r1 in zip(rings, rings[1:]):
            for k in range(len(angles) - 1):
                self.face([r0[k], r1[k], r1[k + 1], r0[k + 1]])

    def text(self):
        return "\n".join(self.lines) + "\n"


# ---------------------------------------------------------------------------------------------
# cables: loose wires of 1-2.2 px diameter in eleven insulation colours on a dark mounting
# plate, a 10-way rainbow ribbon cable (1.27 mm pitch = 1.27 px), a bundle of six 2 mm wires,
# three thick cables, a perforated rail; glossy PVC (a polarized specular line along each wire)

CABLE_CAMERA = {"position": [0.0, -0.3, 2.9], "look_at": [0, 0, 0], "up": [0, 1, 0],
                "focal_length_mm": 10, "f_number": 4}
WIRE_HUES = ("w_red", "w_blue", "w_yellow", "w_green", "w_white", "w_orange", "w_violet",
             "w_brown", "w_grey", "w_black", "w_cyan")
RIBBON = ("w_brown", "w_red", "w_orange", "w_yellow", "w_green", "w_blue", "w_violet",
          "w_grey", "w_white", "w_black")


def wire_path(rng, step=0.012):
    """A smooth curve across the plate (~0.52 x 0.39 m in view) from one edge to another: a
    chord plus two sinusoidal offsets, sampled every step metres."""
    edges = [lambda t: [-0.3, -0.22 + 0.44 * t], lambda t: [0.3, -0.22 + 0.44 * t],
             lambda t: [-0.3 + 0.6 * t, -0.23], lambda t: [-0.3 + 0.6 * t, 0.23]]
    i = rng.randrange(4)
    j = rng.choice([e for e in range(4) if e != i])
    a, b = edges[i](rng.random()), edges[j](rng.random())
    d = [b[0] - a[0], b[1] - a[1]]
    ln = math.hypot(*d)
    nrm = [-d[1] / ln, d[0] / ln]
    a1, a2, ph = rng.uniform(-0.08, 0.08), rng.uniform(-0.03, 0.03), rng.uniform(0, 6.28)
    n = max(int(ln / step), 4)
    pts = []
    for s in range(n + 1):
        t = s / n
        off = a1 * math.sin(math.pi * t) + a2 * math.sin(2 * math.pi * t + ph) * math.sin(
            math.pi * t)
        pts.append([a[0] + d[0] * t + nrm[0] * off, a[1] + d[1] * t + nrm[1] * off])
    return pts


def offset_path(pts, off):
    """pts (2-D) moved sideways by off (to the left of the direction of travel)."""
    out = []
    for i, p in enumerate(pts):
        a, b = pts[max(i - 1, 0)], pts[min(i + 1, len(pts) - 1)]
        d = cg.unit([b[0] - a[0], b[1] - a[1]])
        out.append([p[0] - d[1] * off, p[1] + d[0] * off])
    return out


def cable_meshes():
    rng = random.Random(5303)
    meshes = {h: Mesh("cables, " + h + " insulation") for h in WIRE_HUES}
    lift = [0.0]

    def lay(hue, pts, radius):
        z = radius + lift[0]
        lift[0] += 0.00012
        meshes[hue].tube([[p[0], p[1], z] for p in pts], radius)

    # three thick cables at the bottom of the pile
    for hue, r in (("w_grey", 0.0028), ("w_black", 0.0024), ("w_orange", 0.002)):
        lay(hue, wire_path(rng), r)
    # the rainbow ribbon: ten conductors 1.27 mm apart, touching
    base = wire_path(rng, 0.008)
    for q, hue in enumerate(RIBBON):
        lay(hue, offset_path(base, (q - 4.5) * 0.00127), 0.00066)
    # a bundle of six 2 mm wires side by side
    base = wire_path(rng, 0.01)
    for q, hue in enumerate(("w_red", "w_black", "w_white", "w_green", "w_blue", "w_yellow")):
        lay(hue, offset_path(base, (q - 2.5) * 0.0021), 0.00102)
    # loose single wires, 1.0-2.2 mm
    for q in range(28):
        lay(WIRE_HUES[q % len(WIRE_HUES)], wire_path(rng), rng.uniform(0.0005, 0.0011))
    return {"cables_" + h + ".obj": m.text() for h, m in meshes.items()}


def cables():
    m = {h: mat(h, 0.12) for h in WIRE_HUES}
    m.update({"plate": mat("plate", 0.8), "rail": mat("rail", 0.25), "slot": mat("slot", 0.8)})
    objs = [cg.ground("plate")]
    # a perforated mounting rail across the top: 35 mm wide, slots 6 x 15 mm every 12.5 mm
    objs.append({"type": "box", "center": [0, 0.155, 0.0035], "size": [0.7, 0.035, 0.007],
                 "material": "rail"})
    x = -0.3
    while x < 0.3:
        objs.append(cg.rect([x, 0.155, 0.00705], [0, 0, 1], [1, 0, 0], [0.006, 0.015], "slot"))
        x += 0.0125
    for h in WIRE_HUES:
        objs.append({"type": "mesh", "file": "cables_" + h + ".obj", "position": [0, 0, 0],
                     "scale": 1, "material": h, "smooth": True})
    lights = [{"type": "directional", "direction": r4(cg.unit([-0.4, -0.5, 0.77])),
               "irradiance_w_m2": [210, 205, 190]},
              {"type": "directional", "direction": r4(cg.unit([0.55, 0.35, 0.76])),
               "irradiance_w_m2": [55, 62, 75]}]
    return scene("cables", "loose 1-2.2 px wires in eleven colours, a rainbow ribbon cable "
                 "at 1.27 px pitch, a six-wire bundle and thick cables on a dark mounting "
                 "plate", CABLE_CAMERA, lights, m, objs)


# ---------------------------------------------------------------------------------------------
# chart: a laminated 24-patch colour chart and a small copy of it on a table, seen 50 degrees
# off the normal, with a lamp near the mirror direction: polarized glare over a few patches

CHART_ROWS = (("c_darkskin", "c_lightskin", "c_bluesky", "c_foliage", "c_blueflower",
               "c_bluishgreen"),
              ("c_orange", "c_purplishblue", "c_moderatered", "c_purple", "c_yellowgreen",
               "c_orangeyellow"),
              ("c_blue", "c_green", "c_red", "c_yellow", "c_magenta", "c_cyan"),
              ("c_white", "c_n8", "c_n65", "c_n5", "c_n35", "c_black"))
CHART_CAMERA = {"position": [0.08, -0.7, 0.58], "look_at": [0.005, 0.0, 0.0], "up": [0, 0, 1],
                "focal_length_mm": 5, "f_number": 4}


def colour_chart(objs, cx, cy, patch, gap, z):
    """A 6 x 4 chart centred at (cx, cy): patches of patch metres, gap metres of black surround
    between and around them."""
    w, h = 6 * patch + 7 * gap, 4 * patch + 5 * gap
    objs.append(cg.rect([cx, cy, z], [0, 0, 1], [1, 0, 0], [w, h], "surround", 5))
    for r, row in enumerate(CHART_ROWS):
        for c, name in enumerate(row):
            px = cx - w / 2 + gap + patch / 2 + c * (patch + gap)
            py = cy + h / 2 - gap - patch / 2 - r * (patch + gap)
            objs.append(cg.rect([px, py, z + 0.0002], [0, 0, 1], [1, 0, 0], [patch, patch],
                                name, 5))


def chart():
    # the laminate: every patch and the surround glossy (sigma 0.05)
    m = {name: mat(name, 0.05) for row in CHART_ROWS for name in row}
    m["surround"] = mat("c_surround", 0.05)
    m["table"] = mat("table", 0.4)
    objs = [cg.ground("table")]
    colour_chart(objs, -0.04, 0.0, 0.03, 0.005, 0.0005)
    colour_chart(objs, 0.125, -0.01, 0.007, 0.0018, 0.0005)
    # the glare lamp: a point light in the mirror direction of the view at a point over the
    # chart's upper left patches, 0.7 m away
    p = [-0.07, 0.03, 0.0]
    v = cg.unit(cg.add(CHART_CAMERA["position"], p, -1))
    mirror = [-v[0], -v[1], v[2]]
    lights = [{"type": "point", "position": r4(cg.add(p, mirror, 0.7)),
               "intensity_w_sr": [9, 9, 8.5]},
              {"type": "directional", "direction": r4(cg.unit([0.5, 0.45, 0.74])),
               "irradiance_w_m2": [140, 140, 135]}]
    return scene("chart", "a laminated 24-patch colour chart (30 mm patches) and a 7 mm copy "
                 "on a table, 50 degrees off the normal, polarized glare from a lamp near the "
                 "mirror direction", CHART_CAMERA, lights, m, objs)


# ---------------------------------------------------------------------------------------------
# carpark: glossy painted cars in a car park under a clear sky seen from a first floor: the
# sky is 87 directional lights whose polarization follows single (Rayleigh) scattering of the
# sun's light, and the sun; the cars' paint, glass and the wet-free asphalt reflect it

CAR_CAMERA = {"position": [-7.5, -14.0, 7.0], "look_at": [-0.3, 1.2, 0.5], "up": [0, 0, 1],
              "focal_length_mm": 3.0, "f_number": 4}
SUN = cg.unit([-0.55, -0.45, 0.7])


def superellipsoid(title, a, b, c, e, nu=40, nv=20):
    """A closed superellipsoid |x/a|^(2/e) + |y/b|^(2/e) + |z/c|^(2/e) = 1 (a rounded box for
    e < 1), centred at the origin; vertex normals from the implicit function's gradient."""
    m = Mesh(title)

    def sp(w, p):
        return math.copysign(abs(w) ** p, w)

    rings = []
    for j in range(1, nv):
        th = math.pi * j / nv - math.pi / 2
        ring = []
        for i in range(nu):
            ph = 2 * math.pi * i / nu
            x = a * sp(math.cos(th), e) * sp(math.cos(ph), e)
            y = b * sp(math.cos(th), e) * sp(math.sin(ph), e)
            z = c * sp(math.sin(th), e)
            q = 2 / e
            g = [sp(x / a, q - 1) / a, sp(y / b, q - 1) / b, sp(z / c, q - 1) / c]
            if abs(g[0]) + abs(g[1]) + abs(g[2]) < 1e-12:
                g = [0, 0, 1]
            ring.append(m.vert([x, y, z], g))
        rings.append(ring)
    for r0, r1 in zip(rings, rings[1:]):
        for i in range(nu):
            k = (i + 1) % nu
            m.face([r0[i], r0[k], r1[k], r1[i]])
    m.face(list(reversed(rings[0])))
    m.face(rings[-1])
    return m.text()


def car_meshes():
    return {"car_body.obj": superellipsoid("car body, 4.3 x 1.8 x 0.9 m", 2.15, 0.9, 0.45,
                                           0.3),
            "car_cabin.obj": superellipsoid("car cabin, 2.3 x 1.5 x 0.8 m", 1.15, 0.75, 0.4,
                                            0.55)}


def sky_lights():
    """The sky as directional lights: rings at elevations 8-88 degrees, their irradiance the
    sky radiance (blue, brighter towards the horizon and the sun) times the solid angle they
    stand for; their polarization single scattering's: perpendicular to the plane of sun and
    sky point, degree 0.75 sin^2(g) / (1 + cos^2(g)) at scattering angle g (Rayleigh;
    Coulson, Polarization and Intensity of Light in the Atmosphere (1988), ch. 5: 0.75 for a
    clear sky's maximum)."""
    out = []
    rings = ((8, 24), (22, 22), (38, 18), (55, 14), (72, 8), (88, 1))
    for q, (el, naz) in enumerate(rings):
        lo = 0 if q == 0 else (rings[q - 1][0] + el) / 2
        hi = 90 if q == len(rings) - 1 else (el + rings[q + 1][0]) / 2
        omega = 2 * math.pi * (math.sin(math.radians(hi)) - math.sin(math.radians(lo))) / naz
        for i in range(naz):
            az = 2 * math.pi * (i + 0.5 * (q % 2)) / naz
            ce = math.cos(math.radians(el))
            d = [ce * math.cos(az), ce * math.sin(az), math.sin(math.radians(el))]
            cg_ = max(-1.0, min(1.0, cg.dot(d, SUN)))
            g = math.acos(cg_)
            dop = 0.75 * (1 - cg_ * cg_) / (1 + cg_ * cg_)
            rad = (0.7 + 0.5 * (1 - el / 90)) * (1 + 2.5 * math.exp(-g / 0.4))
            e = [round(rad * omega * x, 3) for x in (38, 52, 80)]
            light = {"type": "directional", "direction": r4(d), "irradiance_w_m2": e}
            perp = cg.cross(SUN, d)
            if dop > 0.01 and math.sqrt(cg.dot(perp, perp)) > 1e-3:
                light["polarization"] = {"linear_deg": 0, "dop": round(dop, 3)}
                light["reference"] = r4(cg.unit(perp))
            out.append(light)
    out.append({"type": "directional", "direction": r4(SUN), "irradiance_w_m2": [520, 500, 470]})
    return out


def carpark():
    m = {"car_red": mat("car_red", 0.12), "car_navy": mat("car_navy", 0.12),
         "car_white": mat("car_white", 0.12), "car_black": mat("car_black", 0.12),
         "car_teal": mat("car_teal", 0.12), "tyre": mat("tyre", 0.5),
         "glass": {"n": 1.52, "k": [0.03, 0.035, 0.04], "sigma": 0.08},
         "asphalt": mat("asphalt", 0.55), "line": mat("line_white", 0.5),
         "kerb": mat("kerb", 0.5), "grass": mat("grass", 0.7)}
    objs = [cg.ground("asphalt"),
            # a kerb and a grass verge behind the row of cars
            {"type": "box", "center": [0, 4.2, 0.08], "size": [40, 0.3, 0.16],
             "material": "kerb"},
            {"type": "box", "center": [0, 9.3, 0.05], "size": [40, 10, 0.1],
             "material": "grass"}]
    # bay lines, 0.12 m wide, bays 2.6 m
    for k in range(-4, 5):
        objs.append(cg.rect([-1.3 + 2.6 * k, 1.6, 0.003], [0, 0, 1], [0, 1, 0], [5.0, 0.12],
                            "line"))
    objs.append(cg.rect([0, -0.9, 0.003], [0, 0, 1], [1, 0, 0], [24, 0.12], "line"))
    rng = random.Random(7717)
    for k, paint in enumerate(("car_teal", "car_red", "car_white", "car_navy", "car_black")):
        x = -5.2 + 2.6 * k + rng.uniform(-0.2, 0.2)
        y = 1.7 + rng.uniform(-0.3, 0.3)
        yaw = 90 + rng.uniform(-6, 6)
        c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))
        objs.append({"type": "mesh", "file": "car_body.obj", "position": r4([x, y, 0.75]),
                     "scale": 1, "rotation_deg": [0, 0, round(yaw, 2)], "material": paint})
        objs.append({"type": "mesh", "file": "car_cabin.obj",
                     "position": r4([x - 0.25 * c, y - 0.25 * s, 1.22]), "scale": 1,
                     "rotation_deg": [0, 0, round(yaw, 2)], "material": "glass"})
        for fx, fy in ((1.35, 0.8), (1.35, -0.8), (-1.35, 0.8), (-1.35, -0.8)):
            objs.append({"type": "sphere", "center": r4([x + fx * c - fy * s,
                                                         y + fx * s + fy * c, 0.33]),
                         "radius": 0.33, "material": "tyre"})
    return scene("carpark", "five glossy painted cars in a car park under a clear sky of "
                 "87 Rayleigh-polarized directional lights and the sun, seen from a first floor",
                 CAR_CAMERA, sky_lights(), m, objs)


# ---------------------------------------------------------------------------------------------
# pcb: a populated circuit board under a ring light, seen from 0.6 m (0.17 mm per pixel):
# axial resistors with 3.4 px colour bands, ICs with tin pins at 3.7 and 7.3 px pitch, LEDs,
# chip capacitors, gold vias, copper traces under green solder mask, white silkscreen

PCB_CAMERA = {"position": [0.0, -0.06, 0.6], "look_at": [0, 0, 0], "up": [0, 1, 0],
              "focal_length_mm": 12, "f_number": 5.6}
BANDS = ("b_black", "b_brown", "b_red", "b_orange", "b_yellow", "b_green", "b_blue",
         "b_violet", "b_grey", "b_white")


def pcb_meshes():
    body = Mesh("axial resistor body, 6.3 mm x 2.4 mm, axis x")
    body.tube([[-0.00315 + 0.00063 * i, 0, 0] for i in range(11)], 0.0012, up=(0, 0, 1),
              angles=(-90, -60, -30, 0, 30, 60, 90, 120, 150, 180, 210, 240, 270))
    band = Mesh("resistor colour band, 0.6 mm wide, axis x")
    band.tube([[-0.0003, 0, 0], [0.0003, 0, 0]], 0.00124,
              angles=(-90, -60, -30, 0, 30, 60, 90, 120, 150, 180, 210, 240, 270))
    lead = Mesh("resistor lead, 0.6 mm tinned wire, 3.2 mm, axis x")
    lead.tube([[-0.0016, 0, 0], [0, 0, 0], [0.0016, 0, 0]], 0.0003)
    return {"pcb_res_body.obj": body.text(), "pcb_res_band.obj": band.text(),
            "pcb_res_lead.obj": lead.text()}


def resistor(objs, x, y, yaw, body, bands):
    c, s = math.cos(math.radians(yaw)), math.sin(math.radians(yaw))

    def at(u, z):
        return r4([x + u * c, y + u * s, z])

    rot = [0, 0, yaw]
    z = 0.0014
    objs.append({"type": "mesh", "file": "pcb_res_body.obj", "position": at(0, z), "scale": 1,
                 "rotation_deg": rot, "material": body})
    for q, b in enumerate(bands):
        u = (-0.0021 + 0.0011 * q) if q < 3 else 0.0022
        objs.append({"type": "mesh", "file": "pcb_res_band.obj", "position": at(u, z),
                     "scale": 1, "rotation_deg": rot, "material": b})
    for side in (-1, 1):
        objs.append({"type": "mesh", "file": "pcb_res_lead.obj",
                     "position": at(side * 0.0047, 0.0006), "scale": 1, "rotation_deg": rot,
                     "material": "tin"})
        objs.append({"type": "sphere", "center": at(side * 0.0064, -0.0004), "radius": 0.0011,
                     "material": "tin"})


def ic(objs, x, y, w, h, pitch, n_x, n_y, rot90=False):
    """A black package w x h with tin gull-wing pins: n_x per long side at pitch (and n_y per
    short side, 0 for a two-sided package)."""
    objs.append({"type": "box", "center": r4([x, y, 0.0008]), "size": r4([w, h, 0.0016]),
                 "material": "epoxy"})
    for side in (-1, 1):
        for q in range(n_x):
            px = x + (q - (n_x - 1) / 2) * pitch
            objs.append({"type": "box", "center": r4([px, y + side * (h / 2 + 0.0005), 0.0003]),
                         "size": r4([pitch * 0.45, 0.001, 0.0006]), "material": "tin"})
        for q in range(n_y):
            py = y + (q - (n_y - 1) / 2) * pitch
            objs.append({"type": "box", "center": r4([x + side * (w / 2 + 0.0005), py, 0.0003]),
                         "size": r4([0.001, pitch * 0.45, 0.0006]), "material": "tin"})
    # pin-1 dot
    objs.append({"type": "sphere", "center": r4([x - w / 2 + 0.0012, y - h / 2 + 0.0012,
                                                 0.0012]),
                 "radius": 0.0005, "material": "silk"})


def pcb():
    rng = random.Random(2411)
    m = {"mask": mat("mask", 0.09), "mask_cu": mat("mask_cu", 0.09), "silk": mat("silk", 0.4),
         "epoxy": mat("epoxy", 0.2), "res_beige": mat("res_beige", 0.3),
         "res_blue": mat("res_blue", 0.2), "gold": metal("gold", 0.1), "tin": metal("tin", 0.15),
         "cap_ochre": mat("cap_ochre", 0.35), "cap_blue": mat("cap_blue", 0.15),
         "cap_stripe": mat("cap_stripe", 0.2)}
    m.update({b: mat(b, 0.2) for b in BANDS})
    for led in ("led_red", "led_green", "led_blue", "led_yellow"):
        m[led] = mat(led, 0.05)
    up = [0, 0, 1]
    objs = [cg.ground("mask")]
    # copper traces under the mask: 0.35-0.6 mm (2-3.5 px) at 0, 45 and 90 degrees
    for q in range(26):
        x, y = rng.uniform(-0.045, 0.045), rng.uniform(-0.034, 0.034)
        ang = rng.choice((0, 45, 90, 135))
        ln, w = rng.uniform(0.01, 0.045), rng.choice((0.00035, 0.00045, 0.0006))
        u = [math.cos(math.radians(ang)), math.sin(math.radians(ang)), 0]
        objs.append(cg.rect([x, y, 0.00002], up, u, [ln, w], "mask_cu", 5))
    # gold vias: 1 mm pads with a 0.4 mm dark drill
    for q in range(30):
        x, y = rng.uniform(-0.045, 0.045), rng.uniform(-0.034, 0.034)
        objs.append(cg.rect([x, y, 0.00004], up, [1, 0, 0], [0.001, 0.001], "gold", 5))
        objs.append(cg.rect([x, y, 0.00006], up, [1, 0, 0], [0.0004, 0.0004], "epoxy", 5))
    # resistors in two rows, some turned 90 degrees; beige carbon (4 bands) or blue metal film
    for q in range(10):
        x = -0.036 + 0.0105 * (q % 5) * 1.0
        y = 0.022 - 0.012 * (q // 5)
        bands = [BANDS[rng.randrange(1, 10)], BANDS[rng.randrange(10)],
                 BANDS[rng.randrange(0, 6)], "gold"]
        body = "res_blue" if q % 3 == 2 else "res_beige"
        resistor(objs, x, y, 90 if q in (3, 7) else 0, body, bands)
        # silkscreen outline: 0.25 mm lines (1.4 px)
        for dx, dy, sx, sy in ((0, 0.0021, 0.0075, 0.00025), (0, -0.0021, 0.0075, 0.00025),
                               (0.00375, 0, 0.00025, 0.0042), (-0.00375, 0, 0.00025, 0.0042)):
            if q in (3, 7):
                dx, dy, sx, sy = dy, dx, sy, sx
            objs.append(cg.rect([x + dx, y + dy, 0.00005], up, [1, 0, 0], [sx, sy], "silk", 5))
    # ICs: a QFP-44 (0.65 mm pitch = 3.7 px) and two SOIC-14 (1.27 mm = 7.3 px)
    ic(objs, 0.022, 0.012, 0.01, 0.01, 0.00065, 11, 11)
    ic(objs, 0.024, -0.014, 0.0087, 0.0039, 0.00127, 7, 0)
    ic(objs, -0.01, -0.024, 0.0087, 0.0039, 0.00127, 7, 0)
    # LEDs: 5 mm domes
    for q, led in enumerate(("led_red", "led_green", "led_blue", "led_yellow")):
        objs.append({"type": "sphere", "center": r4([-0.04 + 0.007 * q, -0.009, 0.0005]),
                     "radius": 0.0025, "material": led})
    # chip capacitors 2 x 1.25 mm with tin ends
    for q in range(12):
        x, y = -0.043 + 0.0042 * q, -0.017 + (0.0015 if q % 2 else 0)
        objs.append({"type": "box", "center": r4([x, y, 0.0006]), "size": [0.0014, 0.00125,
                                                                           0.0012],
                     "material": "cap_ochre"})
        for side in (-1, 1):
            objs.append({"type": "box", "center": r4([x + side * 0.0008, y, 0.0006]),
                         "size": [0.0004, 0.0013, 0.00125], "material": "tin"})
    # an electrolytic capacitor seen from above: a blue can with a light stripe
    objs.append({"type": "sphere", "center": [0.04, -0.026, -0.02], "radius": 0.0215,
                 "material": "cap_blue"})
    objs.append(cg.rect([0.0345, -0.026, 0.0016], up, [0, 1, 0], [0.006, 0.002],
                        "cap_stripe"))
    # a 2 x 8 pin header: black plastic, gold pins 0.64 mm square at 2.54 mm (14.5 px)
    objs.append({"type": "box", "center": [0.0, 0.031, 0.00125], "size": [0.0203, 0.0051,
                                                                         0.0025],
                 "material": "epoxy"})
    for q in range(8):
        for r in (-1, 1):
            objs.append({"type": "box", "center": r4([-0.00889 + 0.00254 * q,
                                                      0.031 + r * 0.00127, 0.003]),
                         "size": [0.00064, 0.00064, 0.006], "material": "gold"})
    # ring light: 12 point lights on a 0.12 m ring 0.25 m above the board
    lights = []
    for q in range(12):
        a = 2 * math.pi * q / 12
        lights.append({"type": "point", "position": r4([0.12 * math.cos(a),
                                                        0.12 * math.sin(a) - 0.03, 0.25]),
                       "intensity_w_sr": [1.2, 1.2, 1.15]})
    return scene("pcb", "a populated circuit board under a ring light: resistors with 3.4 px "
                 "colour bands, QFP and SOIC pins at 3.7 and 7.3 px pitch, LEDs, chip "
                 "capacitors, gold vias, traces under green mask, silkscreen", PCB_CAMERA,
                 lights, m, objs)


# ---------------------------------------------------------------------------------------------
# livingroom_g12: a living room in the evening through the imx250myr preset at +12 dB: a warm
# table lamp, the last daylight through a window (the background: clipped), dark corners, a
# bookshelf of 4-12 px spines, a red sofa, a striped rug, a plant

ROOM_CAMERA = {"position": [1.8, -2.2, 1.4], "look_at": [-1.3, 1.0, 0.8], "up": [0, 0, 1],
               "focal_length_mm": 2.2, "f_number": 2.8}


def livingroom():
    rng = random.Random(9020)
    names = ("floor_wood", "wall_cream", "wall_sage", "ceiling", "sofa", "cushion", "shelf",
             "rug_a", "rug_b", "rug_c", "leaf", "pot", "lamp", "frame")
    m = {n: mat(n, 0.5) for n in names}
    m["floor_wood"]["sigma"] = 0.2
    m["pot"]["sigma"] = 0.1
    books = [b for b in PAINTS if b.startswith("bk_")]
    m.update({b: mat(b, 0.3) for b in books})
    m["window_frame"] = mat("ceiling", 0.3)
    m["lawn"] = mat("leaf", 0.8)
    # the room: x -2.5..3, y -4..3, z 0..2.6 (finite planes: daylight enters by the window
    # only); outside, a lawn 0.3 m below the floor
    objs = [cg.ground("lawn", -0.3),
            cg.rect([0.25, -0.5, 0.0], [0, 0, 1], [1, 0, 0], [5.5, 7.0], "floor_wood"),
            cg.rect([0.25, -0.5, 2.6], [0, 0, -1], [1, 0, 0], [5.5, 7.0], "ceiling"),
            cg.rect([0.25, 3.0, 1.3], [0, -1, 0], [1, 0, 0], [5.5, 2.6], "wall_cream"),
            cg.rect([3.0, -0.5, 1.3], [-1, 0, 0], [0, 1, 0], [7.0, 2.6], "wall_cream"),
            cg.rect([0.25, -4.0, 1.3], [0, 1, 0], [1, 0, 0], [5.5, 2.6], "wall_cream")]
    # the left wall x = -2.5 with a window 1.4 x 1.3 m (y -0.2..1.2, z 0.9..2.2): four pieces
    L = [1, 0, 0]
    for cy, cz, sy, sz in ((-2.6, 1.3, 4.8, 2.6), (2.1, 1.3, 1.8, 2.6), (0.5, 0.45, 1.4, 0.9),
                           (0.5, 2.4, 1.4, 0.4)):
        objs.append(cg.rect([-2.5, cy, cz], L, [0, 1, 0], [sy, sz], "wall_sage"))
    # window bars (a cross)
    objs.append(cg.rect([-2.49, 0.5, 1.55], L, [0, 1, 0], [0.05, 1.3], "window_frame"))
    objs.append(cg.rect([-2.49, 0.5, 1.55], L, [0, 1, 0], [1.4, 0.05], "window_frame"))
    # bookshelf against the back wall: 1.6 m wide, four shelves
    x0, x1 = -1.9, -0.3
    for q in range(5):
        objs.append({"type": "box", "center": [(x0 + x1) / 2, 2.82, 0.02 + 0.45 * q],
                     "size": [x1 - x0, 0.34, 0.03], "material": "shelf"})
    for x in (x0, x1):
        objs.append({"type": "box", "center": [x, 2.82, 0.95], "size": [0.03, 0.34, 1.9],
                     "material": "shelf"})
    for q in range(4):
        x = x0 + 0.03
        while True:
            t = rng.uniform(0.015, 0.045)
            if x + t > x1 - 0.03:
                break
            hgt = rng.uniform(0.22, 0.36)
            objs.append({"type": "box", "center": r4([x + t / 2, 2.8 - rng.uniform(0, 0.04),
                                                      0.035 + 0.45 * q + hgt / 2]),
                         "size": r4([t - 0.002, 0.24, hgt]),
                         "material": books[rng.randrange(len(books))]})
            x += t
    # the sofa along the right, cushions; a low table with the lamp; rug; a plant by the window
    objs += [{"type": "box", "center": [1.6, 1.9, 0.22], "size": [2.0, 0.9, 0.44],
              "material": "sofa"},
             {"type": "box", "center": [1.6, 2.25, 0.6], "size": [2.0, 0.25, 0.5],
              "material": "sofa"},
             {"type": "box", "center": [1.1, 2.05, 0.55], "size": [0.4, 0.15, 0.35],
              "rotation_deg": [0, 12, 0], "material": "cushion"},
             {"type": "box", "center": [-1.2, 0.8, 0.5], "size": [0.7, 0.7, 0.04],
              "material": "shelf"},
             {"type": "box", "center": [-1.2, 0.8, 0.24], "size": [0.06, 0.06, 0.48],
              "material": "shelf"},
             {"type": "box", "center": [-1.3, 0.9, 0.72], "size": [0.05, 0.05, 0.4],
              "material": "lamp"},
             {"type": "sphere", "center": [-2.1, -0.7, 0.25], "radius": 0.22,
              "material": "pot"}]
    for q in range(14):
        a = 2 * math.pi * q / 14
        objs.append({"type": "sphere", "center": r4([-2.1 + 0.25 * math.cos(a),
                                                     -0.7 + 0.25 * math.sin(a),
                                                     0.75 + rng.uniform(-0.15, 0.35)]),
                     "radius": round(rng.uniform(0.08, 0.14), 3), "material": "leaf"})
    for q in range(13):
        objs.append(cg.rect([0.2, -0.35 + 0.1 * q, 0.002], [0, 0, 1], [1, 0, 0], [2.2, 0.1],
                            ("rug_a", "rug_b", "rug_c", "rug_b")[q % 4]))
    # a picture on the back wall
    objs.append(cg.rect([0.8, 2.99, 1.55], [0, -1, 0], [1, 0, 0], [0.9, 0.65], "frame"))
    for q, c in enumerate(("rug_c", "bk_teal", "cushion", "bk_blue")):
        objs.append(cg.rect([0.6 + 0.4 * (q % 2), 2.985, 1.4 + 0.3 * (q // 2)], [0, -1, 0],
                            [1, 0, 0], [0.36, 0.26], c))
    lights = [{"type": "point", "position": [-1.3, 0.9, 1.05], "intensity_w_sr": [9, 6.5, 3.5]},
              # the last daylight through the window (cool), falling on the floor
              {"type": "directional", "direction": r4(cg.unit([-0.75, -0.2, 0.62])),
               "irradiance_w_m2": [5, 6.5, 10]}]
    return m, objs, lights


def livingroom_g12():
    m, objs, lights = livingroom()
    return scene("livingroom_g12", "a living room in the evening (warm lamp, the last "
                 "daylight through a window, dark corners, a bookshelf) through the IMX250MYR "
                 "preset at +12 dB analog gain", ROOM_CAMERA, lights, m, objs,
                 sen=sensor("livingroom_g12", preset="imx250myr", gain_db=12),
                 background=[40, 48, 62])


def carpark_g9():
    s = carpark()
    s["name"] = "colour sealed 3: the carpark scene at dusk through the IMX250MYR preset at " \
        "+9 dB analog gain"
    s["sensor"] = sensor("carpark_g9", preset="imx250myr", gain_db=9)
    return s


SCENES = {"cables": cables, "chart": chart, "carpark": carpark, "pcb": pcb,
          "livingroom_g12": livingroom_g12, "carpark_g9": carpark_g9}


def meshes():
    out = {}
    out.update(cable_meshes())
    out.update(car_meshes())
    out.update(pcb_meshes())
    return out


cg.write_all(HERE, SCENES, meshes, sys.argv)
