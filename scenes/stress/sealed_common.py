"""Helpers shared by the sealed colour-set generators from colour-sealed9 on (Python 3 standard
library only), kept here, outside every sealed directory, so that a later set imports them
instead of copying them.

The generic helpers of the earlier sets are colour-sealed6/sealed_lib.py's (millimetre meshes,
prisms, tori, discs, lathes about the vertical, ribbons, material records), re-exported here as
`sl`, and ../colour_gen.py's (the colour sensor, the scene record, rect, vectors, the writer),
re-exported as `cg`. colour-sealed6 is frozen by its seal: sealed_lib is only read (bytecode
caching is turned off before importing it, so that no __pycache__ is written into that
directory). What sealed_lib lacks and the sets after colour-sealed8 need is below: rings of
shared vertices joined into a surface (`join_rings`), a loft of elliptical (or polygonal)
sections along any axis, which is also a lathe about any axis and a sphere (`loft`,
`ellipsoid`), a tube along a bent polyline with shared vertices at the bends (`sweep`), a box
turned to any frame as flat facets (`cuboid`), a ribbon laid over a parametric surface
(`surface_band`), a sloping plane's frame (`Slope`), materials from a text table
(`materials`) and a set's scene records, ideal and noisy copies, with its title and exposure
table (`scene`, `scene_set`). Added with colour-sealed10 (at the end, changing nothing above):
a smooth patch of shared vertices over a parametric surface (`patch`), a polyline moved
sideways (`offset`) and points on a horizontal arc (`arc`).
"""
import math
import os
import sys

sys.dont_write_bytecode = True  # nothing is written into colour-sealed6 (sealed)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "colour-sealed6"))
import sealed_lib as sl  # noqa: E402 (colour-sealed6/sealed_lib.py, read only)

cg = sl.cg


def join_rings(mesh, rings, closed=True):
    """Quads between consecutive rings of vertex indices (equal lengths), or triangles where a
    ring is a single vertex (an apex); closed: the last vertex of a ring joins the first."""
    for lo, hi in zip(rings, rings[1:]):
        m = max(len(lo), len(hi))
        for i in range(m if closed else m - 1):
            j = (i + 1) % m
            quad = [lo[i % len(lo)], lo[j % len(lo)], hi[j % len(hi)], hi[i % len(hi)]]
            # an apex gives a triangle (its two corners are one vertex)
            mesh.face([q for k, q in enumerate(quad) if q != quad[k - 1]])


def loft(mesh, c, axes, stations, n=16, phase=0.0, wobble=None):
    """A closed surface of sections along axes[0] through c: stations are (x, ry, rz), an
    ellipse of semi-axes ry along axes[1] and rz along axes[2] at c + x axes[0] (n vertices,
    the first at angle `phase` from axes[1]; n = 6 with ry = rz is a hexagonal prism), a
    section of zero radii is an apex. wobble (optional): per station, n radial factors (an
    irregular stone, a lumpy bead). Shared vertices: smooth with `smooth` true."""
    ex, ey, ez = (cg.unit(a) for a in axes)
    rings = []
    for s, (x, ry, rz) in enumerate(stations):
        o = cg.add(c, ex, x)
        if ry == 0 and rz == 0:
            rings.append([mesh.vert(o)])
            continue
        ring = []
        for i in range(n):
            a = phase + 2 * math.pi * i / n
            f = wobble[s][i] if wobble else 1.0
            ring.append(mesh.vert(cg.add(cg.add(o, ey, f * ry * math.cos(a)), ez,
                                         f * rz * math.sin(a))))
        rings.append(ring)
    join_rings(mesh, rings)


def axes_of(axis):
    """axis and two unit vectors perpendicular to it and to each other (sl.frame)."""
    u, v = sl.frame(axis)
    return [cg.unit(axis), u, v]


def ellipsoid(mesh, c, axes, radii, n=12, rows=6, wobble=None):
    """An ellipsoid of semi-axes radii along axes (rows + 1 stations from pole to pole, poles
    as apexes); wobble as loft's, for the rows - 1 rings between the poles."""
    stations = []
    for k in range(rows + 1):
        t = math.pi * k / rows
        s = math.sin(t) if 0 < k < rows else 0.0
        stations.append((-radii[0] * math.cos(t), radii[1] * s, radii[2] * s))
    wob = None
    if wobble:
        wob = [[1.0] * n] + list(wobble) + [[1.0] * n]
    loft(mesh, c, axes, stations, n, 0.0, wob)


def sweep(mesh, path, radius, sides=8):
    """A tube of `sides` faces along the polyline path (at least two points), one ring of shared
    vertices at each point, perpendicular to the mean of the two segments there (a bent rod, a
    cord, a chain's wire); its frame is carried along the path so that it does not twist. No
    caps (an open tube; the ends are meant to be hidden or too small to see)."""
    if radius <= 0 or len(path) < 2:
        return
    rings = []
    u = None
    for k, p in enumerate(path):
        t = cg.unit([b - a for a, b in zip(path[max(k - 1, 0)], path[min(k + 1, len(path) - 1)])])
        if u is None:
            u = sl.frame(t)[0]
        else:
            u = cg.unit(cg.add(u, t, -cg.dot(u, t)))
        v = cg.cross(t, u)
        rings.append([mesh.vert(q) for q in sl.ring_points(p, u, v, radius, sides)])
    join_rings(mesh, rings)


def cuboid(mesh, c, axes, size):
    """A box of edge lengths size along the three (perpendicular) axes, centred on c, as six
    flat facets (many small boxes in one mesh instead of one object each)."""
    e = [cg.unit(a) for a in axes]

    def corner(signs):
        p = list(c)
        for k in range(3):
            p = cg.add(p, e[k], signs[k] * size[k] / 2)
        return p

    for k in range(3):
        i, j = (k + 1) % 3, (k + 2) % 3
        for s in (-1, 1):
            quad = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                signs = [0, 0, 0]
                signs[k], signs[i], signs[j] = s, a, b * s
                quad.append(corner(signs))
            mesh.flat(quad)


def surface_band(mesh, point, u0, u1, vs):
    """A ribbon over a parametric surface point(u, v): between the curves u = u0(v) and
    u = u1(v) (functions of v) for v in vs; one flat facet per step of v (a stripe painted on a
    curved body, lifted by the surface function itself)."""
    for a, b in zip(vs, vs[1:]):
        mesh.flat([point(u0(a), a), point(u0(b), b), point(u1(b), b), point(u1(a), a)])


def materials(table):
    """Named materials from a text table, one a line: `name sigma kR kG kB [n]` (a paint: a
    dielectric of index n, 1.5 unless given, coloured by its extinction coefficients) or `name
    sigma metal nR nG nB kR kG kB` (a metal); '#' starts a comment. One table serves a whole
    set: scene() keeps, of it, what the scene's objects use."""
    out = {}
    for line in table.splitlines():
        f = line.split("#")[0].split()
        if not f:
            continue
        name, sigma, v = f[0], float(f[1]), f[2:]
        if v[0] == "metal":
            nk = [float(x) for x in v[1:]]
            out[name] = {"n": nk[:3], "k": nk[3:], "sigma": sigma}
        else:
            nk = [float(x) for x in v]
            out[name] = {"n": nk[3] if len(nk) > 3 else 1.5, "k": nk[:3], "sigma": sigma}
    return out


def scene(title, exposure, name, what, camera, lights, mats, objs, preset="ideal", gain_db=None,
          background=None):
    """The scene record of a set: its title ("colour sealed 9: " ...) and `what`, the sensor at
    exposure[name] (the ideal sensor with the colour layer, or a preset at gain_db), of the
    materials mats (materials()) those that objs use, cg.EFFECTS and the background radiance
    if given."""
    kw = {} if gain_db is None else {"gain_db": gain_db}
    used = {o["material"] for o in objs}
    mats = {n: m for n, m in mats.items() if n in used}
    s = cg.scene(title + what, camera, lights, mats, objs, cg.EFFECTS,
                 cg.sensor(exposure[name], preset, **kw))
    if background is not None:
        s["background"] = background
    return s


def scene_set(title, exposure, ideal, noisy):
    """A set's scenes as cg.write_all wants them (name: a function returning the record).
    ideal: name -> (parts, camera, what, background), parts() returning (materials, objects,
    lights); noisy: name -> (an ideal scene's name, gain_db, why): that scene through the
    imx250myr preset at gain_db (its exposure is exposure[name])."""

    def make(name):
        base, gain, why = noisy.get(name, (name, None, None))
        parts, camera, what, background = ideal[base]
        mats, objs, lights = parts()
        if gain is None:
            return scene(title, exposure, name, what, camera, lights, mats, objs,
                         background=background)
        what = "the %s scene through the IMX250MYR preset at +%d dB analog gain (%s)" % (
            base, gain, why)
        return scene(title, exposure, name, what, camera, lights, mats, objs, "imx250myr", gain,
                     background)

    return {name: (lambda name=name: make(name)) for name in list(ideal) + list(noisy)}


class Slope:
    """A plane through `origin` rising at `deg` degrees along +y (a sloping counter, a display
    board): unit vectors u (along x), v (up the slope), n (its normal); at(u, v, h) is the
    point u along it, v up it and h above it; along(phi) the in-plane direction phi degrees
    from u and the in-plane direction perpendicular to it (n x that)."""

    def __init__(self, origin, deg):
        a = math.radians(deg)
        self.o = list(origin)
        self.u, self.v, self.n = [1, 0, 0], [0, math.cos(a), math.sin(a)], [0, -math.sin(a),
                                                                                 math.cos(a)]

    def at(self, u, v, h=0.0):
        return cg.add(cg.add(cg.add(self.o, self.u, u), self.v, v), self.n, h)

    def along(self, phi):
        p = math.radians(phi)
        a = cg.add([x * math.cos(p) for x in self.u], self.v, math.sin(p))
        return a, cg.cross(self.n, a)


# Added with colour-sealed10 (the helpers above are unchanged, so colour-sealed9 still
# regenerates byte for byte from this file).
def patch(mesh, point, us, vs):
    """A smooth patch over a parametric surface point(u, v): a grid of shared vertices at every
    (u, v) of us x vs, joined into quads (an umbrella's gore, a slide's chute, a curved sheet);
    placed with `smooth` true the loader's vertex normals round it."""
    rows = [[mesh.vert(point(u, v)) for v in vs] for u in us]
    join_rings(mesh, rows, closed=False)


def offset(pts, d, normal=(0, 0, 1)):
    """The polyline pts moved sideways by d in the plane perpendicular to normal (positive: to
    the left of its direction seen from the normal's side), each point along the mean of its
    two segments' sides (a rail beside a curved track's centre line, a kerb's edge)."""
    out = []
    for k, p in enumerate(pts):
        t = cg.unit([b - a for a, b in zip(pts[max(k - 1, 0)], pts[min(k + 1, len(pts) - 1)])])
        out.append(cg.add(p, cg.unit(cg.cross(list(normal), t)), d))
    return out


def arc(c, r, a0, a1, n, z=0.0):
    """n + 1 points on the horizontal circle of radius r about c (x, y) from a0 to a1 degrees, at
    height z (a curved track's centre line, a ring of posts)."""
    return [[c[0] + r * math.cos(math.radians(a0 + (a1 - a0) * k / n)),
             c[1] + r * math.sin(math.radians(a0 + (a1 - a0) * k / n)), z] for k in range(n + 1)]


# Added with colour-sealed11 (the helpers above are unchanged, so colour-sealed9 and
# colour-sealed10 still regenerate byte for byte from this file).
def meshes_for(scene_name, names, writer):
    """One empty sl.Mesh per material name of a scene (titled "scene, material words")."""
    return {n: sl.Mesh(scene_name + ", " + n.replace("_", " "), writer) for n in names}


def mesh_files(prefix, mesh):
    """A scene's meshes by file name: prefix + "_" + the last word of each material's name
    (checked to be distinct, so that no mesh file is written over another)."""
    out = {prefix + "_" + n.split("_")[-1]: m for n, m in mesh.items()}
    assert len(out) == len(mesh), "two materials of %s end in the same word" % prefix
    return out


def mesh_obj(prefix, material, smooth=False):
    """The scene object of the mesh file mesh_files() names for material (scale 0.001)."""
    return sl.mesh_object(prefix + "_" + material.split("_")[-1] + ".obj", material, smooth)


def annulus(mesh, c, normal, r0, r1, n=32, a0=0.0, a1=360.0, phase=None):
    """A flat ring between radii r0 < r1 about c facing normal, from a0 to a1 degrees (in
    sl.frame(normal)'s axes, phase added if given), as n quads with their own vertices (a
    target's ring, a pipe's end, a chip's face); r0 = 0 gives a fan of n triangles (a disc or a
    sector)."""
    u, v = sl.frame(normal)
    off = phase or 0.0

    def at(r, a):
        t = math.radians(a + off)
        return cg.add(cg.add(c, u, r * math.cos(t)), v, r * math.sin(t))

    for i in range(n):
        a, b = a0 + (a1 - a0) * i / n, a0 + (a1 - a0) * (i + 1) / n
        if r0 > 0:
            mesh.flat([at(r0, a), at(r1, a), at(r1, b), at(r0, b)])
        else:
            mesh.flat([c, at(r1, a), at(r1, b)])


# Added with colour-sealed12 (the helpers above are unchanged, so colour-sealed9,
# colour-sealed10 and colour-sealed11 still regenerate byte for byte from this file).
def rectangle(mesh, o, u, v, width, height):
    """A flat rectangle from the corner o, width along the unit vector u and height along the
    unit vector v (a stripe of a panel, a tick of a scale, a label), one facet."""
    far = cg.add(o, u, width)
    mesh.flat([o, far, cg.add(far, v, height), cg.add(o, v, height)])
