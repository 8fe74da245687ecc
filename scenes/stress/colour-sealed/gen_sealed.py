#!/usr/bin/env python3
"""Writes the sealed colour scenes (README.md beside this file) and their meshes.

Python 3 standard library only; deterministic (a fixed-seed random.Random): `python3
gen_sealed.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed.py --print NAME` prints one scene instead.

Paints are dielectrics (n = 1.5) whose colour comes from per-channel extinction coefficients
k = [R, G, B] as in ../colour/gen_colour.py (the pBRDF's diffuse term, physics.md section 2: a
channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at all); muted
paints mix the channels. Metals have no diffuse term ("diffuse": "none") and per-channel
complex indices n - ik at the IMX250MYR's channel wavelengths (610, 530, 465 nm,
docs/scene-format.md, "Sensor"), interpolated linearly in wavelength in the tables of
H.-J. Hagemann, W. Gudat and C. Kunz, "Optical constants from the far infrared to the x-ray
region: Mg, Al, Cu, Ag, Au, Bi, C, and Al2O3", DESY report SR-74/7 (1974), tables 3 and 5
(the rows bracketing those wavelengths are in HGK below).

The exposures (EXPOSURE) were set by looking at the rendered raw frames and truth only
(brightness, clipping, DoLP/AoLP pictures), before any demosaicking method was run on these
scenes; README.md records the commit that sealed them.
"""
import json
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

# Hagemann, Gudat & Kunz (1974): (wavelength nm, n, k) rows bracketing 465, 530 and 610 nm
HGK = {
    "copper": [(442.8, 1.169, 2.36), (476.9, 1.152, 2.50), (516.6, 1.121, 2.60),
               (539.1, 1.037, 2.59), (590.4, 0.468, 2.81), (619.9, 0.272, 3.24)],
    "gold": [(442.8, 1.826, 1.81), (476.8, 1.541, 1.71), (516.6, 0.878, 2.01),
             (563.5, 0.613, 2.64), (619.9, 0.487, 3.31)],
    "silver": [(413.3, 0.226, 2.28), (495.9, 0.237, 3.09), (619.9, 0.269, 4.18)],
    "aluminium": [(413.3, 0.548, 5.00), (495.9, 0.771, 5.91), (619.9, 1.292, 7.28)],
}
CHANNEL_NM = (610.0, 530.0, 465.0)  # R, G, B of the imx250myr preset


def metal_index(name):
    """Per-channel (n, k) of a metal: linear interpolation in wavelength in HGK."""
    rows = HGK[name]
    ns, ks = [], []
    for lam in CHANNEL_NM:
        for (l0, n0, k0), (l1, n1, k1) in zip(rows, rows[1:]):
            if l0 <= lam <= l1:
                t = (lam - l0) / (l1 - l0)
                ns.append(round(n0 + t * (n1 - n0), 3))
                ks.append(round(k0 + t * (k1 - k0), 3))
                break
    return ns, ks


def metal(name, sigma):
    n, k = metal_index(name)
    return {"n": n, "k": k, "sigma": sigma, "diffuse": "none"}


# name: k[R, G, B] (n = 1.5)
PAINTS = {
    # saturated
    "red": [1.8, 0.05, 0.05], "yellow": [1.8, 1.5, 0.05], "blue": [0.05, 0.15, 1.8],
    "orange": [1.8, 0.6, 0.05], "violet": [0.8, 0.05, 1.6], "teal": [0.05, 1.3, 1.0],
    # foliage and soil
    "leaf_dark": [0.12, 0.55, 0.08], "leaf_mid": [0.25, 0.95, 0.12],
    "leaf_yellow": [0.8, 1.2, 0.1], "leaf_olive": [0.55, 0.6, 0.15],
    "leaf_brown": [0.75, 0.4, 0.12], "leaf_autumn": [1.5, 0.5, 0.06],
    "leaf_red": [1.2, 0.12, 0.1], "petal_pink": [1.7, 0.6, 1.1],
    "petal_white": [1.5, 1.5, 1.4], "petal_violet": [0.9, 0.35, 1.6],
    "soil": [0.45, 0.3, 0.12],
    # muted (moderate saturation): textiles, gravel
    "m_red": [1.25, 0.45, 0.35], "m_navy": [0.3, 0.38, 1.05], "m_forest": [0.35, 0.85, 0.4],
    "m_mustard": [1.25, 1.0, 0.3], "m_cream": [1.2, 1.1, 0.85], "m_plum": [0.9, 0.35, 0.75],
    "m_sage": [0.7, 0.9, 0.6], "m_rust": [1.1, 0.5, 0.25], "m_ochre": [1.1, 0.85, 0.35],
    "m_slate": [0.5, 0.6, 0.75], "m_sand": [1.0, 0.9, 0.65], "m_brown": [0.6, 0.4, 0.25],
    # pastels (gradients)
    "p_peach": [1.6, 1.1, 0.8], "p_mint": [0.9, 1.5, 1.1], "p_lilac": [1.2, 1.0, 1.6],
    "p_lemon": [1.5, 1.5, 0.7], "p_sky": [0.8, 1.2, 1.6], "p_white": [1.4, 1.4, 1.35],
    # still life
    "wood": [1.0, 0.55, 0.25], "wall": [0.8, 0.9, 0.75], "cloth_blue": [0.1, 0.2, 0.55],
    "lime": [0.7, 1.6, 0.05], "white": [1.4, 1.4, 1.4],
}

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "foliage": 450,
    "stilllife": 900,
    "textile": 650,
    "gradients": 300,
    "metals": 120,
    "fruit": 450,
    "stilllife_g12": 100,
    "foliage_g12": 100,
}

EFFECTS = {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3}
# top-down camera (as in ../colour-holdout): ~1.74 mm per pixel at the z = 0 plane
TOP = {"position": [0, -1.0, 6.0], "look_at": [0, 0, 0], "up": [0, 1, 0],
       "focal_length_mm": 12, "f_number": 4}
# daylight: a warm sun and a cool sky fill (RGB irradiances)
DAYLIGHT = [{"type": "directional", "direction": [-0.4, -0.35, 0.85],
             "irradiance_w_m2": [260, 245, 220]},
            {"type": "directional", "direction": [0.45, 0.5, 0.74],
             "irradiance_w_m2": [70, 90, 125]}]


def r4(v):
    return [round(x, 4) for x in v]


def paints(names, sigma, prefix=""):
    return {prefix + n: {"n": 1.5, "k": PAINTS[n], "sigma": sigma} for n in names}


def sensor(name, preset="ideal", **kw):
    s = {"preset": preset, "resolution": [512, 384], "exposure_us": EXPOSURE[name]}
    if preset == "ideal":
        # the ideal sensor with the IMX250MYR's colour layer and channel QEs
        s["layout"] = "RGGB:90,45,135,0"
        s["qe"] = [0.22, 0.30, 0.24]
    s.update(kw)
    return s


def scene(name, title, camera, lights, materials, objs, effects=None, sen=None):
    return {"polarcam_scene": 1, "name": "colour sealed: " + title, "camera": camera,
            "lights": lights, "materials": materials, "objects": objs,
            "effects": effects or EFFECTS, "sensor": sen or sensor(name)}


def ground(material, z=0.0):
    return {"type": "plane", "point": [0, 0, z], "normal": [0, 0, 1], "material": material}


def mesh(file, material, smooth=False):
    return {"type": "mesh", "file": file, "position": [0, 0, 0], "scale": 1,
            "material": material, "smooth": smooth}


def rot(v, yaw, ax, ay):
    """R = Rz(yaw) Ry(ay) Rx(ax) applied to v (radians)."""
    x, y, z = v
    y, z = y * math.cos(ax) - z * math.sin(ax), y * math.sin(ax) + z * math.cos(ax)
    x, z = x * math.cos(ay) + z * math.sin(ay), -x * math.sin(ay) + z * math.cos(ay)
    x, y = x * math.cos(yaw) - y * math.sin(yaw), x * math.sin(yaw) + y * math.cos(yaw)
    return [x, y, z]


class Obj:
    """A Wavefront OBJ being written: polygons (one `f` record each, negative indices)."""

    def __init__(self, title):
        self.lines = ["# " + title + ", written by gen_sealed.py"]

    def poly(self, pts):
        for p in pts:
            self.lines.append("v %.4f %.4f %.5f" % tuple(p))
        self.lines.append("f " + " ".join(str(-len(pts) + i) for i in range(len(pts))))

    def text(self):
        return "\n".join(self.lines) + "\n"


def leaf_outline(length, width, nseg=5):
    """A leaf (two arcs meeting in points) of the given size, in its own plane, 2 nseg points."""
    pts = []
    for s in (1, -1):
        for i in range(nseg):
            t = math.pi * i / nseg
            x = 0.5 * length * math.cos(t)
            y = s * 0.5 * width * math.sin(t) ** 1.3
            pts.append([x * s, y, 0.0])
    return pts


# ---------------------------------------------------------------------------------------------
# foliage: leaves and petals at several scales over soil, top-down in daylight

FOLIAGE_MATS = ["leaf_dark", "leaf_mid", "leaf_yellow", "leaf_olive", "leaf_brown",
                "leaf_autumn", "leaf_red"]
FOLIAGE_WEIGHTS = [5, 6, 3, 3, 2, 1.5, 1]
PETALS = ["petal_pink", "petal_white", "petal_violet", "yellow"]


def foliage_meshes():
    rng = random.Random(1412)
    px = 0.00174
    objs = {m: Obj("foliage leaves, " + m) for m in FOLIAGE_MATS + PETALS}
    # leaf lengths 3-130 px, uniform within octaves with count ~ 1/length^2 (each octave covers
    # about the same area), at random positions, headings and tilts up to ~45 degrees
    octaves = [(80, 130, 30), (48, 80, 70), (24, 48, 200), (12, 24, 350), (6, 12, 400),
               (3, 6, 250)]
    leaves = []
    for lo, hi, n in octaves:
        for _ in range(n):
            length = rng.uniform(lo, hi) * px
            width = length * rng.uniform(0.3, 0.6)
            mat = rng.choices(FOLIAGE_MATS, FOLIAGE_WEIGHTS)[0]
            leaves.append((length, width, mat))
    rng.shuffle(leaves)
    for i, (length, width, mat) in enumerate(leaves):
        cx, cy = rng.uniform(-0.48, 0.48), rng.uniform(-0.37, 0.37)
        yaw = rng.uniform(0, 2 * math.pi)
        ax, ay = rng.uniform(-0.8, 0.8), rng.uniform(-0.5, 0.5)
        cz = 0.002 + 0.00006 * i + 0.5 * length * abs(math.sin(ay)) + \
            0.5 * width * abs(math.sin(ax))
        pts = [[p[0] + cx, p[1] + cy, p[2] + cz]
               for p in (rot(q, yaw, ax, ay) for q in leaf_outline(length, width, 4))]
        objs[mat].poly(pts)
    # small flowers on top: five-petal rosettes of 5-14 px
    for i in range(40):
        mat = PETALS[i % len(PETALS)]
        d = rng.uniform(5, 14) * px
        cx, cy = rng.uniform(-0.46, 0.46), rng.uniform(-0.35, 0.35)
        cz = 0.002 + 0.00006 * len(leaves) + 0.001 * i
        yaw0 = rng.uniform(0, 2 * math.pi)
        for p in range(5):
            yaw = yaw0 + 2 * math.pi * p / 5
            c = [cx + 0.25 * d * math.cos(yaw), cy + 0.25 * d * math.sin(yaw), cz]
            pts = [[q[0] + c[0], q[1] + c[1], q[2] + c[2]]
                   for q in (rot(v, yaw, 0, 0) for v in leaf_outline(0.5 * d, 0.3 * d, 4))]
            objs[mat].poly(pts)
    return {"foliage_" + m + ".obj": o.text() for m, o in objs.items()}


def foliage_objs():
    objs = [ground("soil")]
    for m in FOLIAGE_MATS + PETALS:
        objs.append(mesh("foliage_" + m + ".obj", m))
    return objs


def foliage_mats():
    m = paints(FOLIAGE_MATS, 0.2)
    m.update(paints(PETALS, 0.35))
    m["leaf_dark"]["sigma"] = 0.12  # waxy
    m["leaf_brown"]["sigma"] = 0.45  # dry
    m.update(paints(("soil",), 0.6))
    return m


def foliage():
    return scene("foliage", "leaves of 4-80 px over soil with small flowers, tilted up to "
                 "~45 degrees, in daylight (multi-scale natural clutter)", TOP, DAYLIGHT,
                 foliage_mats(), foliage_objs())


def foliage_g12():
    return scene("foliage_g12", "the foliage through the IMX250MYR preset at +12 dB analog "
                 "gain, mid exposure", TOP, DAYLIGHT, foliage_mats(), foliage_objs(),
                 sen=sensor("foliage_g12", preset="imx250myr", gain_db=12))


# ---------------------------------------------------------------------------------------------
# still life: painted dielectrics and metals on a wooden table before a wall, a key point
# light and a cool fill

def cylinder_obj(radius, height, title, n=48):
    """An upright closed cylinder (z from 0 to height), sides with outward vertex normals."""
    lines = ["# " + title + ", written by gen_sealed.py"]
    for k in range(n):
        a = 2 * math.pi * k / n
        c, s = math.cos(a), math.sin(a)
        lines.append("v %.5f %.5f 0" % (radius * c, radius * s))
        lines.append("v %.5f %.5f %.5f" % (radius * c, radius * s, height))
        lines.append("vn %.5f %.5f 0" % (c, s))
    lines.append("v 0 0 %.5f" % height)
    lines.append("vn 0 0 1")
    top_c, top_n = 2 * n + 1, n + 1
    for k in range(n):
        j = (k + 1) % n
        b0, t0, b1, t1 = 2 * k + 1, 2 * k + 2, 2 * j + 1, 2 * j + 2
        lines.append("f %d//%d %d//%d %d//%d %d//%d" % (b0, k + 1, b1, j + 1, t1, j + 1, t0,
                                                       k + 1))
        lines.append("f %d//%d %d//%d %d//%d" % (top_c, top_n, t0, top_n, t1, top_n))
    return "\n".join(lines) + "\n"


STILL_CAMERA = {"position": [0.05, -1.55, 0.75], "look_at": [0.0, 0.08, 0.07], "up": [0, 0, 1],
                "focal_length_mm": 5, "f_number": 4}
STILL_LIGHTS = [{"type": "point", "position": [-0.9, -0.9, 1.3], "intensity_w_sr": 700},
                {"type": "directional", "direction": [0.7, -0.45, 0.55],
                 "irradiance_w_m2": [60, 75, 100]},
                {"type": "directional", "direction": [0.1, -0.6, 0.79],
                 "irradiance_w_m2": 60}]


def stilllife_parts():
    m = paints(("wood",), 0.35)
    m.update(paints(("wall",), 0.7))
    m.update(paints(("cloth_blue",), 0.8))
    m["ceramic_red"] = {"n": 1.5, "k": PAINTS["red"], "sigma": 0.05}
    m["glaze_blue"] = {"n": 1.55, "k": PAINTS["blue"], "sigma": 0.03}
    m["plastic_yellow"] = {"n": 1.5, "k": PAINTS["yellow"], "sigma": 0.1}
    m["book_teal"] = {"n": 1.5, "k": PAINTS["teal"], "sigma": 0.45}
    m["cup_white"] = {"n": 1.5, "k": PAINTS["white"], "sigma": 0.08}
    m["lime"] = {"n": 1.5, "k": PAINTS["lime"], "sigma": 0.2}
    m["paint_orange"] = {"n": 1.5, "k": PAINTS["orange"], "sigma": 0.15}
    m["gold"] = metal("gold", 0.15)
    m["copper"] = metal("copper", 0.25)
    m["silver"] = metal("silver", 0.08)
    m["aluminium"] = metal("aluminium", 0.35)
    objs = [ground("wood"),
            {"type": "plane", "point": [0, 0.45, 0], "normal": [0, -1, 0], "material": "wall"},
            # a folded blue cloth on the table, right
            {"type": "box", "center": [0.2, 0.12, 0.004], "size": [0.3, 0.22, 0.008],
             "rotation_deg": [0, 0, 12], "material": "cloth_blue"},
            # a teal book, left, with an orange-painted box on it
            {"type": "box", "center": [-0.2, 0.18, 0.02], "size": [0.2, 0.14, 0.04],
             "rotation_deg": [0, 0, -18], "material": "book_teal"},
            {"type": "box", "center": [-0.2, 0.19, 0.07], "size": [0.07, 0.07, 0.06],
             "rotation_deg": [0, 0, 25], "material": "paint_orange"},
            {"type": "sphere", "center": [-0.07, -0.02, 0.055], "radius": 0.055,
             "material": "ceramic_red"},
            {"type": "sphere", "center": [0.08, 0.04, 0.045], "radius": 0.045,
             "material": "gold"},
            {"type": "sphere", "center": [0.21, 0.1, 0.04], "radius": 0.032,
             "material": "silver"},
            {"type": "sphere", "center": [-0.04, -0.16, 0.022], "radius": 0.022,
             "material": "lime"},
            {"type": "box", "center": [0.22, -0.08, 0.03], "size": [0.06, 0.06, 0.06],
             "rotation_deg": [0, 0, 35], "material": "plastic_yellow"},
            {"type": "box", "center": [-0.28, -0.06, 0.03], "size": [0.05, 0.08, 0.06],
             "rotation_deg": [0, 0, 10], "material": "glaze_blue"},
            {"type": "mesh", "file": "pot.obj", "position": [0.02, 0.22, 0], "scale": 1,
             "material": "copper", "smooth": True},
            {"type": "mesh", "file": "cup.obj", "position": [-0.14, 0.04, 0], "scale": 1,
             "material": "cup_white", "smooth": True},
            {"type": "box", "center": [0.12, -0.14, 0.006], "size": [0.16, 0.02, 0.012],
             "rotation_deg": [0, 0, -30], "material": "aluminium"}]
    return m, objs


def stilllife():
    m, objs = stilllife_parts()
    return scene("stilllife", "painted ceramic, plastic and metal (Au, Cu, Ag, Al) objects on "
                 "a wooden table before a wall, a key point light and a cool fill",
                 STILL_CAMERA, STILL_LIGHTS, m, objs)


def stilllife_g12():
    m, objs = stilllife_parts()
    return scene("stilllife_g12", "the still life through the IMX250MYR preset at +12 dB "
                 "analog gain, mid exposure", STILL_CAMERA, STILL_LIGHTS, m, objs,
                 sen=sensor("stilllife_g12", preset="imx250myr", gain_db=12))


# ---------------------------------------------------------------------------------------------
# metals: coloured metals with highlights near and at full scale

def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def mirror_plate(center, size, material, cam, light, off_deg):
    """A rectangle whose normal is the bisector of the directions to the camera and to the point
    light (mirror geometry at its centre) turned by off_deg about the rectangle's horizontal
    axis u: the light's mirror reflection falls off across the plate."""
    v = unit([a - b for a, b in zip(cam["position"], center)])
    ld = unit([a - b for a, b in zip(light["position"], center)])
    h = unit([a + b for a, b in zip(v, ld)])
    u = unit([-h[1], h[0], 0])
    w = [u[1] * h[2] - u[2] * h[1], u[2] * h[0] - u[0] * h[2], u[0] * h[1] - u[1] * h[0]]
    a = math.radians(off_deg)
    n = [math.cos(a) * x + math.sin(a) * y for x, y in zip(h, w)]
    return {"type": "plane", "point": r4(center), "normal": r4(n), "size": size,
            "u_axis": r4(u), "material": material}


def metals():
    m = {"velvet": {"n": 1.5, "k": [0.15, 0.08, 0.35], "sigma": 0.9}}
    for name, sig in (("gold", 0.12), ("copper", 0.18), ("silver", 0.1),
                      ("aluminium", 0.2)):
        m[name] = metal(name, sig)
    m["gold_rough"] = metal("gold", 0.3)
    m["copper_rough"] = metal("copper", 0.35)
    m["gold_plate"] = metal("gold", 0.25)
    m["copper_plate"] = metal("copper", 0.3)
    cam = {"position": [0, -1.3, 0.9], "look_at": [0, 0.05, 0.05], "up": [0, 0, 1],
           "focal_length_mm": 5, "f_number": 4}
    lights = [{"type": "point", "position": [0.5, -0.6, 1.0], "intensity_w_sr": 900}]
    for q in range(4):
        a = math.radians(30 + 90 * q)
        lights.append({"type": "directional", "irradiance_w_m2": 150,
                       "direction": r4([0.82 * math.cos(a), 0.82 * math.sin(a), 0.57])})
    objs = [ground("velvet"),
            {"type": "sphere", "center": [-0.16, 0.0, 0.06], "radius": 0.06,
             "material": "gold"},
            {"type": "sphere", "center": [0.0, 0.1, 0.05], "radius": 0.05,
             "material": "copper"},
            {"type": "sphere", "center": [0.15, -0.02, 0.045], "radius": 0.045,
             "material": "gold_rough"},
            {"type": "sphere", "center": [0.25, 0.15, 0.04], "radius": 0.04,
             "material": "silver"},
            {"type": "sphere", "center": [-0.04, -0.12, 0.03], "radius": 0.03,
             "material": "copper_rough"},
            {"type": "sphere", "center": [-0.3, 0.16, 0.035], "radius": 0.035,
             "material": "aluminium"},
            mirror_plate([-0.22, -0.08, 0.04], [0.1, 0.07], "gold_plate", cam, lights[0], 14),
            mirror_plate([0.1, 0.24, 0.05], [0.12, 0.08], "copper_plate", cam, lights[0], -14),
            {"type": "mesh", "file": "bar.obj", "position": [0.3, -0.14, 0], "scale": 1,
             "material": "gold", "smooth": True}]
    return scene("metals", "gold, copper, silver and aluminium spheres, plates and a bar on "
                 "dark velvet: coloured highlights near and at full scale", cam, lights, m,
                 objs)


# ---------------------------------------------------------------------------------------------
# textile: a tartan (stripes 2-12 px), gravel (stones 3-8 px) and pinstripes, muted hues

TARTAN = ["m_red", "m_navy", "m_forest", "m_mustard", "m_cream", "m_plum"]
GRAVEL = ["m_sage", "m_rust", "m_ochre", "m_slate", "m_sand", "m_brown"]


def tartan_objs(rng):
    px = 0.00174
    objs = []
    cx, cy, ang = -0.21, 0.0, math.radians(17)
    ca, sa = math.cos(ang), math.sin(ang)
    half_w, half_h = 0.2, 0.3
    for layer, (axis, half_len, half_span) in enumerate(((0, half_w, half_h),
                                                         (1, half_h, half_w))):
        pos = -half_span
        q = 0
        while pos < half_span:
            w = rng.choice((2, 3, 4, 6, 8, 12)) * px
            w = min(w, half_span - pos)
            mid = pos + w / 2
            mat = TARTAN[(q * 5 + layer * 2 + q // 3) % len(TARTAN)]
            if axis == 0:  # horizontal stripe (along u), offset along v
                lx, ly, size = 0.0, mid, [2 * half_len, w]
            else:  # vertical stripe (along v), offset along u
                lx, ly, size = mid, 0.0, [w, 2 * half_len]
            x, y = cx + ca * lx - sa * ly, cy + sa * lx + ca * ly
            # the vertical stripes lie above the horizontal ones, every second one is left out
            if axis == 0 or q % 2 == 0:
                objs.append({"type": "plane", "point": r4([x, y, 0.002 + 0.001 * layer]),
                             "normal": [0, 0, 1], "size": r4(size), "u_axis": r4([ca, sa, 0]),
                             "material": mat})
            pos += w
            q += 1
    return objs


def textile_meshes():
    rng = random.Random(2603)
    px = 0.00174
    out = {}
    objs = {m: Obj("textile gravel, " + m) for m in GRAVEL}
    # gravel: quadrilateral stones of 3-8 px, random heading, right upper region
    for i in range(1600):
        s = rng.uniform(3, 9) * px
        cx, cy = rng.uniform(0.03, 0.45), rng.uniform(-0.02, 0.34)
        yaw = rng.uniform(0, math.pi)
        pts = []
        for c in range(4):
            a = yaw + math.pi / 2 * c + rng.uniform(-0.3, 0.3)
            r = 0.5 * s * rng.uniform(0.7, 1.1)
            pts.append([cx + r * math.cos(a), cy + r * math.sin(a), 0.002 + 0.00002 * i])
        objs[GRAVEL[rng.randrange(len(GRAVEL))]].poly(pts)
    for m, o in objs.items():
        out["textile_" + m + ".obj"] = o.text()
    # pinstripes at -35 degrees, 2 and 3 px wide, plum and sage on the cream ground (lower right)
    pin = {m: Obj("textile pinstripes, " + m) for m in ("m_plum", "m_forest")}
    a = math.radians(-35)
    d = [math.cos(a), math.sin(a)]
    nrm = [-d[1], d[0]]
    x0, x1, y0, y1 = 0.03, 0.45, -0.34, -0.06
    k = 0
    off = -0.35
    while off < 0.35:
        w = (2 if k % 2 == 0 else 3) * px
        c = [0.24 + nrm[0] * off, -0.2 + nrm[1] * off]
        # a long thin rectangle, clipped to the region by construction of its length
        half = 0.4
        pts = [[c[0] - d[0] * half + nrm[0] * sgn * w / 2, c[1] - d[1] * half +
                nrm[1] * sgn * w / 2] for sgn in (-1, 1)]
        pts += [[c[0] + d[0] * half + nrm[0] * sgn * w / 2, c[1] + d[1] * half +
                 nrm[1] * sgn * w / 2] for sgn in (1, -1)]
        pts = clip_rect(pts, x0, x1, y0, y1)
        if len(pts) >= 3:
            pin["m_plum" if k % 2 == 0 else "m_forest"].poly([[p[0], p[1], 0.003]
                                                              for p in pts])
        off += (5 + (k % 3)) * px
        k += 1
    for m, o in pin.items():
        out["textile_pin_" + m + ".obj"] = o.text()
    return out


def clip_rect(pts, x0, x1, y0, y1):
    """Sutherland-Hodgman clipping of a convex polygon to an axis-aligned rectangle."""
    def clip(poly, inside, cut):
        res = []
        for i in range(len(poly)):
            p, q = poly[i - 1], poly[i]
            if inside(q):
                if not inside(p):
                    res.append(cut(p, q))
                res.append(q)
            elif inside(p):
                res.append(cut(p, q))
        return res

    def at_x(x):
        return lambda p, q: [x, p[1] + (q[1] - p[1]) * (x - p[0]) / (q[0] - p[0])]

    def at_y(y):
        return lambda p, q: [p[0] + (q[0] - p[0]) * (y - p[1]) / (q[1] - p[1]), y]

    for inside, cut in ((lambda p: p[0] >= x0, at_x(x0)), (lambda p: p[0] <= x1, at_x(x1)),
                        (lambda p: p[1] >= y0, at_y(y0)), (lambda p: p[1] <= y1, at_y(y1))):
        pts = clip(pts, inside, cut)
        if not pts:
            break
    return pts


def textile():
    rng = random.Random(77)
    m = paints(TARTAN, 0.5)
    m.update(paints(GRAVEL, 0.4))
    m.update(paints(("m_sand",), 0.6, prefix="g_"))
    objs = [ground("g_m_sand")]
    objs += tartan_objs(rng)
    for g in GRAVEL:
        objs.append(mesh("textile_" + g + ".obj", g))
    for p in ("m_plum", "m_forest"):
        objs.append(mesh("textile_pin_" + p + ".obj", p))
    objs.append({"type": "plane", "point": [0.24, -0.2, 0.0015], "normal": [0, 0, 1],
                 "size": [0.42, 0.28], "u_axis": [1, 0, 0], "material": "m_cream"})
    return scene("textile", "a tartan turned by 17 degrees (stripes 2-12 px), gravel of 3-8 px "
                 "stones and 2-3 px pinstripes at -35 degrees, in muted hues (moderate "
                 "saturation)", TOP, DAYLIGHT, m, objs)


# ---------------------------------------------------------------------------------------------
# gradients: large matte pastel shapes under a warm point light and a cool directional light,
# no cast shadows: smooth hue and brightness gradients, soft shading

def gradients():
    m = paints(("p_peach", "p_mint", "p_lilac", "p_lemon", "p_sky"), 0.45)
    m.update(paints(("p_white",), 0.6))
    cam = {"position": [0, -1.9, 1.3], "look_at": [0, 0.1, 0.05], "up": [0, 0, 1],
           "focal_length_mm": 5, "f_number": 4}
    lights = [{"type": "point", "position": [-0.6, -0.1, 0.45],
               "intensity_w_sr": [160, 110, 60]},
              {"type": "directional", "direction": [0.6, -0.2, 0.77],
               "irradiance_w_m2": [40, 70, 130]}]
    objs = [ground("p_white"),
            {"type": "plane", "point": [0, 0.6, 0], "normal": [0, -1, 0], "material": "p_white"},
            {"type": "sphere", "center": [-0.18, 0.1, 0.12], "radius": 0.12,
             "material": "p_peach"},
            {"type": "sphere", "center": [0.12, 0.2, 0.15], "radius": 0.15, "material": "p_sky"},
            {"type": "sphere", "center": [0.08, -0.14, 0.07], "radius": 0.07,
             "material": "p_mint"},
            {"type": "sphere", "center": [-0.3, -0.12, 0.05], "radius": 0.05,
             "material": "p_lemon"},
            {"type": "sphere", "center": [0.32, -0.02, 0.08], "radius": 0.08,
             "material": "p_lilac"}]
    eff = dict(EFFECTS, cast_shadows=False)
    return scene("gradients", "large matte pastel spheres on a white floor and wall under a "
                 "warm point light and a cool directional light, no cast shadows: smooth "
                 "colour gradients", cam, lights, m, objs, effects=eff)


# ---------------------------------------------------------------------------------------------
# fruit: glossy fruit in a cluster on a cloth (large smooth regions, curved hue edges)

def fruit():
    rng = random.Random(5)
    m = {"cloth": {"n": 1.5, "k": [0.7, 0.75, 0.85], "sigma": 0.7},
         "orange": {"n": 1.5, "k": PAINTS["orange"], "sigma": 0.22},
         "apple_red": {"n": 1.5, "k": [1.6, 0.15, 0.1], "sigma": 0.12},
         "apple_green": {"n": 1.5, "k": [0.7, 1.5, 0.12], "sigma": 0.12},
         "lemon": {"n": 1.5, "k": [1.7, 1.5, 0.1], "sigma": 0.25},
         "plum": {"n": 1.5, "k": [0.5, 0.06, 0.7], "sigma": 0.1},
         "grape": {"n": 1.5, "k": [0.55, 1.1, 0.1], "sigma": 0.06}}
    cam = {"position": [0, -1.3, 1.2], "look_at": [0, 0.02, 0.04], "up": [0, 0, 1],
           "focal_length_mm": 5, "f_number": 4}
    lights = [{"type": "directional", "direction": [-0.45, -0.4, 0.8],
               "irradiance_w_m2": [250, 240, 225]},
              {"type": "directional", "direction": [0.6, -0.3, 0.74],
               "irradiance_w_m2": [60, 70, 90]}]
    objs = [ground("cloth")]
    for (x, y, r, mat) in ((-0.12, 0.05, 0.075, "orange"), (0.06, 0.1, 0.07, "apple_red"),
                           (0.2, -0.02, 0.065, "apple_green"), (-0.02, -0.1, 0.06, "lemon"),
                           (-0.26, -0.08, 0.055, "orange"), (0.28, 0.16, 0.05, "plum"),
                           (-0.22, 0.2, 0.06, "apple_red")):
        objs.append({"type": "sphere", "center": [x, y, r], "radius": r, "material": mat})
    # a bunch of grapes: spheres of 1.6-2 cm, front right
    for i in range(22):
        r = rng.uniform(0.016, 0.02)
        x, y = 0.15 + rng.uniform(-0.06, 0.06), -0.17 + rng.uniform(-0.05, 0.05)
        z = r + 0.018 * (i // 9)
        objs.append({"type": "sphere", "center": r4([x, y, z]), "radius": round(r, 4),
                     "material": "grape"})
    return scene("fruit", "glossy oranges, apples, a lemon, a plum and grapes on a pale cloth "
                 "in daylight: large smooth regions and curved hue edges", cam, lights, m, objs)


SCENES = {"foliage": foliage, "stilllife": stilllife, "textile": textile,
          "gradients": gradients, "metals": metals, "fruit": fruit,
          "stilllife_g12": stilllife_g12, "foliage_g12": foliage_g12}


def meshes():
    out = {}
    out.update(foliage_meshes())
    out.update(textile_meshes())
    out["pot.obj"] = cylinder_obj(0.05, 0.09, "copper pot (r 5 cm, h 9 cm)")
    out["cup.obj"] = cylinder_obj(0.035, 0.08, "white cup (r 3.5 cm, h 8 cm)")
    out["bar.obj"] = cylinder_obj(0.02, 0.14, "gold bar (r 2 cm, h 14 cm)")
    return out


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "--print":
        print(json.dumps(SCENES[sys.argv[2]](), indent=1))
        return
    for name, text in meshes().items():
        with open(os.path.join(HERE, name), "w") as f:
            f.write(text)
    for name, fn in SCENES.items():
        with open(os.path.join(HERE, name + ".json"), "w") as f:
            f.write(json.dumps(fn(), indent=1) + "\n")


main()
