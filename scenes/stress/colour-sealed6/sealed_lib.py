"""Generic helpers of gen_sealed6.py (this directory): meshes in millimetres, primitives (prisms,
tubes, tori, discs, surfaces of revolution), material and object records. Python 3 standard
library only. The colour sensor, the scene record, rect, the vector helpers and the writer's
main are ../colour_gen.py's (imported here and re-exported as `cg`).

Written for this set instead of copying the helpers of ../colour-sealed4/gen_sealed4.py and
../colour-sealed5/gen_sealed5.py (those directories are frozen by their seals, so they keep
theirs); a later set may import this module or copy it into its own directory (this one is
frozen by its seal too: SHA256SUMS).
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import colour_gen as cg  # noqa: E402,F401 (../colour_gen.py)


def r4(v):
    return cg.rounded(v, 4)


class Mesh:
    """A Wavefront OBJ held as vertex and face lists, vertices in metres, written in
    millimetres (place it with mesh_object(): scale 0.001). Faces are lists of 1-based vertex
    indices; flat() adds a polygon with its own vertices (a flat facet), shared vertices come
    from vert()."""

    def __init__(self, title, writer):
        self.head = "# %s, millimetres, written by %s" % (title, writer)
        self.verts = []
        self.faces = []

    def vert(self, p):
        self.verts.append(p)
        return len(self.verts)

    def face(self, idx):
        self.faces.append(list(idx))

    def flat(self, pts):
        first = len(self.verts) + 1
        self.verts.extend(pts)
        self.faces.append(list(range(first, first + len(pts))))

    def empty(self):
        return not self.faces

    def text(self):
        out = [self.head]
        out.extend("v %.1f %.1f %.1f" % (1e3 * p[0], 1e3 * p[1], 1e3 * p[2]) for p in self.verts)
        out.extend("f " + " ".join(map(str, f)) for f in self.faces)
        return "\n".join(out) + "\n"


def mesh_object(file, material, smooth=False):
    """The scene object of a millimetre mesh."""
    return {"type": "mesh", "file": file, "position": [0, 0, 0], "scale": 0.001,
            "material": material, "smooth": smooth}


def box(center, size, material, yaw=0.0):
    """A box (edge lengths size), turned by yaw degrees about the vertical."""
    b = {"type": "box", "center": r4(center), "size": r4(size), "material": material}
    if yaw:
        b["rotation_deg"] = [0, 0, round(yaw, 2)]
    return b


def sphere(center, radius, material):
    return {"type": "sphere", "center": r4(center), "radius": round(radius, 4),
            "material": material}


def frame(axis):
    """Two unit vectors perpendicular to axis and to each other."""
    a = cg.unit(axis)
    helper = [0, 0, 1] if abs(a[2]) < 0.9 else [1, 0, 0]
    u = cg.unit(cg.cross(a, helper))
    return u, cg.cross(a, u)


def ring_points(c, u, v, r, n, phase=0.0):
    return [cg.add(cg.add(c, u, r * math.cos(phase + 2 * math.pi * i / n)), v,
                   r * math.sin(phase + 2 * math.pi * i / n)) for i in range(n)]


def tube(mesh, a, b, radius, sides=8, caps=True):
    """A straight prism of `sides` faces and circumradius `radius` from point a to point b (a
    rod, a handle, a spoke); its side faces share vertices, the caps are flat."""
    u, v = frame([q - p for p, q in zip(a, b)])
    lo = [mesh.vert(p) for p in ring_points(a, u, v, radius, sides)]
    hi = [mesh.vert(p) for p in ring_points(b, u, v, radius, sides)]
    for i in range(sides):
        j = (i + 1) % sides
        mesh.face([lo[i], lo[j], hi[j], hi[i]])
    if caps:
        mesh.face(lo[::-1])
        mesh.face(hi)


def disc(mesh, c, normal, r, n=8, phase=0.0):
    """A flat regular n-gon of circumradius r at c facing normal."""
    u, v = frame(normal)
    mesh.flat(ring_points(c, u, v, r, n, phase))


def torus(mesh, c, normal, big, small, n_big=48, n_small=10):
    """A torus about the axis `normal` through c (a tyre, a coil), shared vertices."""
    u, v = frame(normal)
    w = cg.unit(normal)
    rings = []
    for i in range(n_big):
        a = 2 * math.pi * i / n_big
        radial = cg.add([x * math.cos(a) for x in u], v, math.sin(a))
        centre = cg.add(c, radial, big)
        rings.append([mesh.vert(cg.add(cg.add(centre, radial, small * math.cos(2 * math.pi * k
                                                                               / n_small)),
                                       w, small * math.sin(2 * math.pi * k / n_small)))
                      for k in range(n_small)])
    for i in range(n_big):
        p, q = rings[i], rings[(i + 1) % n_big]
        for k in range(n_small):
            m = (k + 1) % n_small
            mesh.face([p[k], q[k], q[m], p[m]])


def lathe(mesh, c, profile, n=32):
    """A surface of revolution about the vertical through c: profile (radius, height) pairs
    from one end to the other; shared vertices (meant for smooth meshes)."""
    rows = []
    for rad, h in profile:
        rows.append([mesh.vert(p) for p in ring_points([c[0], c[1], c[2] + h], [1, 0, 0],
                                                         [0, 1, 0], rad, n)])
    for lower, upper in zip(rows, rows[1:]):
        for i in range(n):
            j = (i + 1) % n
            mesh.face([lower[i], lower[j], upper[j], upper[i]])


def strip(mesh, pts, width, normal):
    """A flat ribbon of `width` along the polyline pts, in the plane perpendicular to normal
    (grain lines, wires seen face-on): one facet per segment."""
    for p, q in zip(pts, pts[1:]):
        side = cg.unit(cg.cross(normal, [b - a for a, b in zip(p, q)]))
        h = width / 2
        mesh.flat([cg.add(p, side, -h), cg.add(q, side, -h), cg.add(q, side, h),
                   cg.add(p, side, h)])


class Materials:
    """Named materials from a table of paints k[R, G, B] (dielectrics, n 1.5 unless given) and
    one of metals (n and k per channel)."""

    def __init__(self, paints, metals):
        self.paints, self.metals, self.used = paints, metals, {}

    def paint(self, name, sigma, n=1.5, as_name=None):
        self.used[as_name or name] = {"n": n, "k": self.paints[name], "sigma": sigma}
        return as_name or name

    def metal(self, name, sigma, as_name=None):
        self.used[as_name or name] = dict(self.metals[name], sigma=sigma)
        return as_name or name

    def many(self, names, sigma, n=1.5):
        for name in names:
            self.paint(name, sigma, n)
