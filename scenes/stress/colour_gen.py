"""Helpers shared by the colour scene generators: colour-holdout/gen_holdout.py,
colour-sealed2/gen_sealed2.py and colour-sealed3/gen_sealed3.py (Python 3 standard library
only).

colour-sealed/gen_sealed.py has its own copies of most of these (paints, sensor, scene, ground,
unit, Obj): that directory is frozen by its seal (its README: no file there but the README may
change after commit 695381e), so it keeps them. A new generator imports them from here.

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


def add(a, b, s=1.0):
    """a + s * b."""
    return [x + s * y for x, y in zip(a, b)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def rect(center, normal, u, size, material, digits=4):
    """A finite plane object: size[0] along u, size[1] along normal x u (docs/scene-format.md,
    "Objects")."""
    return {"type": "plane", "point": rounded(center, digits), "normal": rounded(normal, digits),
            "size": rounded(size, digits), "u_axis": rounded(u, digits), "material": material}


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

