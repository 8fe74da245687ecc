#!/usr/bin/env python3
"""Writes the planar pattern meshes of the demosaicking stress suite (scenes/stress/*.obj).

Python 3 standard library only; deterministic (the OBJ files are checked in, this script is how
they were made: `python3 scenes/stress/gen_meshes.py` in the repository rewrites them). Every
mesh lies in the plane z = 0 (the scenes lift it a little above a background plane), lengths in
metres, faces counter-clockwise seen from +z.

  star.obj      Siemens star: 48 bright wedges of 72 around the centre (radius 0.30 m), each
                wedge a fan of 6 triangles so the rim is round. At the scenes' ~2.9 mm per pixel
                its period runs from ~1 px near the centre (aliased for every method) to 24 px
                at the rim: every orientation and every frequency.
  gratings.obj  16 bar gratings, 0.16 m square: orientations 0, 22.5, ..., 157.5 degrees, each
                at two periods (9 mm and 15 mm, ~3 and ~5 px), half duty cycle.
  text.obj      text-like patterns: lines of 5x7 bitmap glyphs at four sizes (cell 3.5, 5, 7
                and 10 mm: strokes of ~1.2 to ~3.5 px).
"""
import math
import os
import re

HERE = os.path.dirname(os.path.abspath(__file__))


class Mesh:
    def __init__(self):
        self.v = []
        self.f = []

    def quad(self, pts):
        i = len(self.v) + 1
        self.v.extend(pts)
        self.f.append((i, i + 1, i + 2, i + 3))

    def tri(self, pts):
        i = len(self.v) + 1
        self.v.extend(pts)
        self.f.append((i, i + 1, i + 2))

    def write(self, name, comment):
        with open(os.path.join(HERE, name), "w") as fp:
            fp.write("# %s\n# written by gen_meshes.py\n" % comment)
            for x, y in self.v:
                fp.write("v %.6f %.6f 0\n" % (x, y))
            for f in self.f:
                fp.write("f %s\n" % " ".join(str(k) for k in f))


def star():
    m = Mesh()
    n, r, seg = 48, 0.30, 6
    for k in range(n):
        a0 = 2 * math.pi * k / n
        a1 = a0 + math.pi / n
        for s in range(seg):
            t0 = a0 + (a1 - a0) * s / seg
            t1 = a0 + (a1 - a0) * (s + 1) / seg
            m.tri([(0.0, 0.0), (r * math.cos(t0), r * math.sin(t0)),
                   (r * math.cos(t1), r * math.sin(t1))])
    m.write("star.obj", "Siemens star, 48 wedges, radius 0.30 m")


def gratings():
    m = Mesh()
    size, gap = 0.16, 0.02
    periods = (0.009, 0.015)
    for row, period in enumerate(periods):
        for k in range(8):
            ang = math.radians(22.5 * k)
            # patch centre: 8 orientations in two rows of four per period
            col, sub = k % 4, k // 4
            cx = (col - 1.5) * (size + gap)
            cy = ((row * 2 + sub) - 1.5) * (size + gap)
            c, s = math.cos(ang), math.sin(ang)
            half = size / 2
            # bars along direction (c, s), stacked along (-s, c); clipped to the square by
            # keeping whole bars whose four corners lie inside it (the rest of the square stays
            # background)
            nb = int(2 * half / period) + 4
            for b in range(-nb, nb + 1):
                o0, o1 = b * period, b * period + period / 2
                # bar: points p = u*(c, s) + o*(-s, c), u in [-L, L]
                # longest u keeping the bar inside the square
                L = half * 2
                for _ in range(60):
                    pts = [(u * c - o * s, u * s + o * c) for u, o in
                           ((-L, o0), (L, o0), (L, o1), (-L, o1))]
                    if all(abs(px) <= half and abs(py) <= half for px, py in pts):
                        break
                    L *= 0.93
                if L < 0.01:
                    continue
                m.quad([(cx + px, cy + py) for px, py in pts])
    m.write("gratings.obj", "16 bar gratings: 8 orientations x periods 9 and 15 mm")


# a 5x7 bitmap font: each glyph 7 rows of 5 bits, top row first
FONT = {
    "A": "01110 10001 10001 11111 10001 10001 10001", "B": "11110 10001 11110 10001 10001 10001 11110",
    "C": "01111 10000 10000 10000 10000 10000 01111", "D": "11110 10001 10001 10001 10001 10001 11110",
    "E": "11111 10000 11110 10000 10000 10000 11111", "I": "11111 00100 00100 00100 00100 00100 11111",
    "L": "10000 10000 10000 10000 10000 10000 11111", "M": "10001 11011 10101 10101 10001 10001 10001",
    "N": "10001 11001 10101 10011 10001 10001 10001", "O": "01110 10001 10001 10001 10001 10001 01110",
    "P": "11110 10001 10001 11110 10000 10000 10000", "R": "11110 10001 10001 11110 10100 10010 10001",
    "S": "01111 10000 01110 00001 00001 10001 01110", "T": "11111 00100 00100 00100 00100 00100 00100",
    "W": "10001 10001 10001 10101 10101 11011 10001", "X": "10001 01010 00100 00100 00100 01010 10001",
    "Z": "11111 00010 00100 01000 10000 10000 11111", "0": "01110 10011 10101 10101 11001 10001 01110",
    "1": "00100 01100 00100 00100 00100 00100 01110", "2": "01110 10001 00010 00100 01000 10000 11111",
    "4": "00010 00110 01010 10010 11111 00010 00010", "5": "11111 10000 11110 00001 00001 10001 01110",
    "7": "11111 00001 00010 00100 01000 01000 01000", "8": "01110 10001 01110 10001 10001 10001 01110",
    "/": "00001 00010 00010 00100 01000 01000 10000", "=": "00000 00000 11111 00000 11111 00000 00000",
}


def text():
    m = Mesh()
    lines = ("POLARCAM DEMOSAIC 0124578", "STOKES S0 S1 S2 = DOLP/AOLP",
             "ZEBRA WIRE MESH 1872", "MIX TEXT 5/8 ON LINES")
    cells = (0.0035, 0.005, 0.007, 0.010)
    y = 0.30
    for line, cell in zip(lines, cells):
        x0 = -0.62
        for ch in line:
            g = FONT.get(ch)
            if g:
                rows = g.split()
                for r, bits in enumerate(rows):
                    # one quad per run of set bits
                    for run in re.finditer("1+", bits):
                        x, x1 = x0 + run.start() * cell, x0 + run.end() * cell
                        yy = y - r * cell
                        m.quad([(x, yy - cell), (x1, yy - cell), (x1, yy), (x, yy)])
            x0 += 6 * cell
        y -= 9 * cell + 0.03
    # a second block: the same lines rotated by 30 degrees (oblique strokes)
    base = len(m.v)
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    for i in range(base):
        x, yy = m.v[i]
        xr, yr = x * c - yy * s, x * s + yy * c
        m.v.append((xr * 0.8 + 0.05, yr * 0.8 - 0.38))
    m.f.extend(tuple(k + base for k in f) for f in list(m.f))
    m.write("text.obj", "text-like 5x7 bitmap glyph lines at four sizes, upright and at 30 deg")


if __name__ == "__main__":
    star()
    gratings()
    text()
