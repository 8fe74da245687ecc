#!/usr/bin/env python3
"""Writes the meshes of the held-out demosaicking scenes (scenes/heldout/*.obj).

Python 3 standard library only; deterministic (the OBJ files are checked in, this script is how
they were made: `python3 scenes/heldout/gen_meshes.py` rewrites them). Lengths in metres,
faces counter-clockwise seen from +z (planar meshes lie in z = 0; the scenes place, scale and
rotate them). The patterns differ from the stress suite's (radial star, bars at multiples of
22.5 deg with periods ~3 and ~5 px, 5x7 glyphs):

  rings.obj    a Fresnel zone plate: rings k = 0, 2, 4, ... between radii R*sqrt(k/N) and
               R*sqrt((k+1)/N), N = 100, R = 0.5 m: the local period R^2/(N r) falls as 1/r,
               from the centre's disc to ~2 px at the rim in the rings scene (every
               orientation, a chirp through the 2x2 mosaic's Nyquist limits at 4 and 2 px).
  fine.obj     twelve 0.12 m patches of near-Nyquist texture: bar gratings at periods 3.5,
               4.25, 5 and 6 mm (~2.3-4 px in the fine scene) at 10, 35, 55 and 80 deg,
               checkerboards of 2.6 and 3.3 mm squares, grids of square dots at 3 and 4.5 mm
               pitch (half-pitch dots).
  facets.obj   a flat-faceted geodesic sphere (icosahedron, each face split in four, vertices
               on the unit sphere: 80 faces): sharp DoLP/AoLP steps at every facet edge.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


class Mesh:
    def __init__(self):
        self.v = []
        self.f = []

    def poly(self, pts):
        i = len(self.v) + 1
        self.v.extend(pts)
        self.f.append(tuple(range(i, i + len(pts))))

    def write(self, name, comment):
        with open(os.path.join(HERE, name), "w") as fp:
            fp.write("# %s\n# written by gen_meshes.py\n" % comment)
            for p in self.v:
                p = tuple(p) + (0.0,) * (3 - len(p))
                fp.write("v %.6f %.6f %.6f\n" % p)
            for f in self.f:
                fp.write("f %s\n" % " ".join(str(k) for k in f))


def rings():
    m = Mesh()
    n_zones, big_r = 100, 0.5
    for k in range(0, n_zones, 2):
        r0 = big_r * math.sqrt(k / n_zones)
        r1 = big_r * math.sqrt((k + 1) / n_zones)
        # chords of <= 24 mm: the sagitta c^2/(8 r) stays below 0.15 mm, far below a pixel
        ns = max(24, int(2 * math.pi * r1 / 0.024))
        base = len(m.v) + 1
        for s in range(ns):
            t = 2 * math.pi * s / ns
            m.v.append((r1 * math.cos(t), r1 * math.sin(t)))
            if r0 > 0:
                m.v.append((r0 * math.cos(t), r0 * math.sin(t)))
        if r0 == 0:
            m.f.append(tuple(range(base, base + ns)))
            continue
        for s in range(ns):
            a, b = base + 2 * s, base + 2 * ((s + 1) % ns)
            m.f.append((b + 1, b, a, a + 1))
    m.write("rings.obj", "Fresnel zone plate, 100 zones, radius 0.5 m")


def bars(m, cx, cy, half, period, ang_deg):
    c, s = math.cos(math.radians(ang_deg)), math.sin(math.radians(ang_deg))
    nb = int(2 * half / period) + 4
    for b in range(-nb, nb + 1):
        o0, o1 = b * period, b * period + period / 2
        # the bar u*(c, s) + o*(-s, c), u in [-L, L], shortened until its corners lie in the patch
        big_l = half * 2
        for _ in range(80):
            pts = [(u * c - o * s, u * s + o * c) for u, o in
                   ((-big_l, o0), (big_l, o0), (big_l, o1), (-big_l, o1))]
            if all(abs(px) <= half and abs(py) <= half for px, py in pts):
                break
            big_l *= 0.95
        if big_l > 0.01:
            m.poly([(cx + px, cy + py) for px, py in pts])


def checks(m, cx, cy, half, square):
    n = int(2 * half / square)
    for i in range(n):
        for j in range(n):
            if (i + j) % 2 == 0:
                x0, y0 = cx - half + i * square, cy - half + j * square
                m.poly([(x0, y0), (x0 + square, y0), (x0 + square, y0 + square),
                        (x0, y0 + square)])


def dots(m, cx, cy, half, pitch):
    n = int(2 * half / pitch)
    d = pitch / 2
    for i in range(n):
        for j in range(n):
            x0, y0 = cx - half + i * pitch, cy - half + j * pitch
            m.poly([(x0, y0), (x0 + d, y0), (x0 + d, y0 + d), (x0, y0 + d)])


def fine():
    m = Mesh()
    size, gap, half = 0.12, 0.02, 0.06
    cells = [("bars", 0.0035, 10), ("bars", 0.00425, 35), ("bars", 0.005, 55), ("bars", 0.006, 80),
             ("bars", 0.0035, 55), ("bars", 0.00425, 80), ("bars", 0.005, 10), ("bars", 0.006, 35),
             ("checks", 0.0026, 0), ("checks", 0.0033, 0), ("dots", 0.003, 0), ("dots", 0.0045, 0)]
    for idx, (kind, p, ang) in enumerate(cells):
        cx = (idx % 4 - 1.5) * (size + gap)
        cy = (1 - idx // 4) * (size + gap)
        if kind == "bars":
            bars(m, cx, cy, half, p, ang)
        elif kind == "checks":
            checks(m, cx, cy, half, p)
        else:
            dots(m, cx, cy, half, p)
    m.write("fine.obj", "12 near-Nyquist patches: bars 3.5-6 mm at 10/35/55/80 deg, checks, dots")


def facets():
    t = (1 + math.sqrt(5)) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]

    def unit(p):
        n = math.sqrt(sum(x * x for x in p))
        return tuple(x / n for x in p)

    v = [unit(p) for p in v]
    m = Mesh()
    for a, b, c in f:
        pa, pb, pc = v[a], v[b], v[c]
        ab = unit(tuple((x + y) / 2 for x, y in zip(pa, pb)))
        bc = unit(tuple((x + y) / 2 for x, y in zip(pb, pc)))
        ca = unit(tuple((x + y) / 2 for x, y in zip(pc, pa)))
        for tri in ((pa, ab, ca), (ab, pb, bc), (ca, bc, pc), (ab, bc, ca)):
            m.poly(list(tri))
    m.write("facets.obj", "geodesic sphere, 80 flat faces, unit radius")


if __name__ == "__main__":
    rings()
    fine()
    facets()
