"""Helpers shared by the colour scene generators: colour-holdout/gen_holdout.py and
colour-sealed2/gen_sealed2.py (Python 3 standard library only).

colour-sealed/gen_sealed.py has its own copies of some of these (paints, sensor, scene, ground,
Obj, rot, unit, clip_rect, cylinder_obj): that directory is frozen by its seal (its README: no
file there but the README may change after commit 695381e), so it keeps them; a new set imports
them from here instead.

Paints are dielectrics (n = 1.5) coloured by per-channel extinction coefficients k = [R, G, B]
as in colour/gen_colour.py (the pBRDF's diffuse term, physics.md section 2: a channel with
k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at all). The colour sensor is the
`ideal` preset with the IMX250MYR's colour layer (`layout` RGGB:90,45,135,0) and channel QEs
[0.22, 0.30, 0.24], or the `imx250myr` preset itself (docs/scene-format.md, "Sensor").
"""
import json
import math
import os

RESOLUTION = [512, 384]
EFFECTS = {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3}
# a camera looking almost straight down at the z = 0 plane from 6 m: ~1.74 mm per pixel
TOP = {"position": [0, -1.0, 6.0], "look_at": [0, 0, 0], "up": [0, 1, 0],
       "focal_length_mm": 12, "f_number": 4}


def rounded(v, digits):
    return [round(x, digits) for x in v]


def paints(table, names, sigma, prefix=""):
    """Materials {prefix + name: paint} for the names, k from table[name], n = 1.5."""
    return {prefix + n: {"n": 1.5, "k": table[n], "sigma": sigma} for n in names}


def sensor(exposure_us, preset="ideal", **kw):
    """The 512x384 colour sensor at exposure_us: `ideal` with the IMX250MYR's colour layer and
    channel QEs, or another preset (kw: e.g. gain_db)."""
    s = {"preset": preset, "resolution": list(RESOLUTION), "exposure_us": exposure_us}
    if preset == "ideal":
        # the ideal sensor with the IMX250MYR's colour layer and channel QEs
        s["layout"] = "RGGB:90,45,135,0"
        s["qe"] = [0.22, 0.30, 0.24]
    s.update(kw)
    return s


def scene(name, camera, lights, materials, objs, effects, sen):
    return {"polarcam_scene": 1, "name": name, "camera": camera, "lights": lights,
            "materials": materials, "objects": objs, "effects": effects, "sensor": sen}


def ground(material, z=0):
    return {"type": "plane", "point": [0, 0, z], "normal": [0, 0, 1], "material": material}


def unit(v):
    n = math.sqrt(sum(x * x for x in v))
    return [x / n for x in v]


def rot(v, yaw, ax, ay):
    """R = Rz(yaw) Ry(ay) Rx(ax) applied to v (radians)."""
    x, y, z = v
    y, z = y * math.cos(ax) - z * math.sin(ax), y * math.sin(ax) + z * math.cos(ax)
    x, z = x * math.cos(ay) + z * math.sin(ay), -x * math.sin(ay) + z * math.cos(ay)
    x, y = x * math.cos(yaw) - y * math.sin(yaw), x * math.sin(yaw) + y * math.cos(yaw)
    return [x, y, z]


class Obj:
    """A Wavefront OBJ being written: polygons (one `f` record each, negative indices)."""

    def __init__(self, title, writer):
        self.lines = ["# " + title + ", written by " + writer]

    def poly(self, pts):
        for p in pts:
            self.lines.append("v %.4f %.4f %.5f" % tuple(p))
        self.lines.append("f " + " ".join(str(-len(pts) + i) for i in range(len(pts))))

    def text(self):
        return "\n".join(self.lines) + "\n"


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


def write_all(here, scenes, meshes, argv):
    """The generators' main: `--print NAME` prints one scene; otherwise every mesh (name: text)
    and every scene (name: function returning it) is written to NAME.obj / NAME.json in here."""
    if len(argv) == 3 and argv[1] == "--print":
        print(json.dumps(scenes[argv[2]](), indent=1))
        return
    for name, text in meshes().items():
        with open(os.path.join(here, name), "w") as f:
            f.write(text)
    for name, fn in scenes.items():
        with open(os.path.join(here, name + ".json"), "w") as f:
            f.write(json.dumps(fn(), indent=1) + "\n")

