#!/usr/bin/env python3
"""Writes the ninth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed9.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed9.py --print NAME` prints one scene instead.
Every generic helper is imported: ../sealed_common.py (outside the sealed directories: lofts,
ellipsoids, sweeps, boxes as facets, ribbons over surfaces, sloping planes, the materials
table, the scene records with their noisy copies), which re-exports
../colour-sealed6/sealed_lib.py (`sl`: millimetre meshes, tubes, tori, discs, ribbons, mesh
objects, boxes; read, never written) and ../colour_gen.py (`cg`: the colour sensor, the scene
record, rect, vectors, the writer). Nothing here is a copy of an earlier generator's helper;
what is below builds this set's own things (huts, fish, beads, chains, pencils).

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). The metals (the jeweller's 18 ct gold and sterling silver, the
tin's tinplate, the pencils' gold foil, the sharpener's magnesium, the prawn tray's steel) are
assumed metals of the right order (n - ik per channel at 610, 530 and 465 nm, from memory, not
a table lookup); the gem stones, glass and ice are dielectrics of their own refractive index
(ruby and sapphire 1.77, emerald 1.58, window glass 1.52, ice 1.31). None of the paints,
meshes, cameras or layouts of the other colour sets is reused (nor a paint's or metal's name,
nor a paint's k).

Units: metres in the scenes, millimetres in the OBJ files (sl.Mesh; each mesh object has scale
0.001). A mesh placed with `smooth` false shows every facet flat; lofts, tori and sweeps share
their vertices, and placed with `smooth` true the loader's area-weighted normals round them.
The set's materials are one text table (MATERIALS); each scene's record names those its objects
use.

EXPOSURE holds the exposures chosen from the simulator's own outputs (raw frame and truth:
levels, clipping, hue edges, DoLP) and nothing else: no demosaicking method had been run on
any of these scenes when they were sealed (README.md gives the sealing commit).
"""
import math
import os
import random
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.dont_write_bytecode = True  # no __pycache__ in a sealed directory
sys.path.insert(0, os.path.dirname(HERE))
import sealed_common as sc  # noqa: E402 (../sealed_common.py)

sl, cg = sc.sl, sc.cg
WRITER = "gen_sealed9.py"
TITLE = "colour sealed 9: "
UP = [0, 0, 1]
X, Y = [1, 0, 0], [0, 1, 0]

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "huts": 1750,
    "fishmonger": 3450,
    "jeweller": 17000,
    "pencils": 7000,
    "huts_g4": 1100,
    "jeweller_g17": 2400,
}


# every material of the set (sc.materials: paints `name sigma k_R k_G k_B [n]`, n 1.5 unless
# given; metals `name sigma metal n_R n_G n_B k_R k_G k_B`); each scene's record keeps those
# its objects use
MATERIALS = sc.materials("""
# huts
hut_white              0.1    1.6   1.58  1.52
hut_sky                0.1    0.45  0.95  1.45
hut_red                0.1    1.35  0.1   0.1
hut_mint               0.1    0.5   1.05  0.7
hut_coral              0.1    1.45  0.5   0.38
hut_yellow             0.1    1.55  1.3   0.1
hut_blue               0.1    0.06  0.2   0.9
hut_glass              0.02   0.01  0.012 0.012  1.52
roof_felt              0.4    0.3   0.36  0.33
plinth                 0.25   0.14  0.13  0.12
promenade              0.8    0.55  0.52  0.47
promenade_joint        0.5    0.2   0.2   0.19
beach_sand             0.6    0.75  0.6   0.4
buoy_orange            0.05   1.55  0.4   0.05
# fishmonger
ice_crushed            0.25   1.35  1.4   1.45   1.31
ice_bed                0.3    1.05  1.1   1.15   1.31
fish_silver            0.08   1.2   1.25  1.3
mackerel_back          0.08   0.08  0.75  0.6
fish_black             0.05   0.03  0.028 0.034
mullet_red             0.06   1.45  0.3   0.28
salmon_flesh           0.08   1.55  0.5   0.2
salmon_fat             0.1    1.55  1.25  1.05
prawn_pink             0.2    1.5   0.55  0.4
lemon_peel             0.2    1.55  1.3   0.08
parsley_leaf           0.3    0.1   0.55  0.08
tag_chalk              0.7    1.52  1.47  1.4
stall_tiles            0.05   0.1   0.35  0.75
prawn_tray_steel       0.1    metal  2.75 2.55 2.35   3.75 3.55 3.3
# jeweller
velvet_black           0.9    0.05  0.045 0.06
bead_turquoise         0.05   0.12  1.0   0.85
bead_coral             0.05   1.45  0.38  0.3
bead_lapis             0.05   0.08  0.15  0.75
bead_amber             0.05   1.4   0.75  0.08
bead_jade              0.05   0.15  0.75  0.3
bead_rose              0.05   1.4   0.85  0.9
pearl                  0.06   1.5   1.42  1.3
tray_cream             0.6    1.35  1.22  0.9
ruby                   0.01   0.9   0.02  0.06   1.77
sapphire               0.01   0.02  0.08  0.75   1.77
emerald                0.01   0.04  0.55  0.18   1.58
gold_18ct              0.05   metal  0.3  0.6  1.2    3.1  2.3  1.85
silver_925             0.04   metal  0.14 0.14 0.16   3.9  3.25 2.6
# pencils
lacquer_lemon          0.12   1.55  1.45  0.06
lacquer_orange         0.12   1.55  0.6   0.04
lacquer_vermilion      0.12   1.45  0.22  0.06
lacquer_crimson        0.12   0.95  0.05  0.12
lacquer_pink           0.12   1.55  0.5   1.0
lacquer_violet         0.12   0.4   0.1   0.85
lacquer_ultramarine    0.12   0.06  0.12  0.95
lacquer_sky            0.12   0.3   0.9   1.5
lacquer_emerald        0.12   0.05  0.65  0.35
lacquer_grass          0.12   0.45  1.0   0.08
lacquer_ochre          0.12   1.2   0.75  0.15
lacquer_umber          0.12   0.45  0.22  0.08
stroke_vermilion       0.6    1.45  0.22  0.06
stroke_ultramarine     0.6    0.06  0.12  0.95
stroke_lemon           0.6    1.55  1.45  0.06
stroke_emerald         0.6    0.05  0.65  0.35
stroke_pink            0.6    1.55  0.5   1.0
cedar                  0.4    1.35  0.95  0.55
mat_green              0.5    0.05  0.28  0.15
mat_line               0.5    1.0   1.25  0.95
birch_desk             0.3    1.2   0.95  0.62
sketch_paper           0.6    1.6   1.58  1.5
tin_navy               0.08   0.05  0.07  0.3
eraser_pink            0.5    1.3   0.55  0.6
tinplate               0.08   metal  1.6  1.45 1.25   5.2  4.6  3.9
gold_foil              0.1    metal  0.3  0.6  1.2    3.1  2.3  1.85
sharpener_magnesium    0.15   metal  0.5  0.4  0.3    5.4  4.7  4.0
""")


def obj(prefix, name, material, smooth=False):
    return sl.mesh_object(prefix + "_" + name + ".obj", material, smooth)


# ---------------------------------------------------------------------------------------------
# huts: a row of ten beach huts on a seaside promenade seen obliquely from the promenade, 1.6 m
# up: fronts of vertical boards 100 mm wide painted in alternating stripes (sky/white,
# red/white, mint/coral of about equal brightness, blue/yellow, ...) or one colour, so that
# the stripes' period (200 mm) falls from ~15 px at the nearest hut (half out of the frame)
# through ~7, ~5 and ~4 px to ~2 px at the farthest; gloss paint (sigma 0.1), gloss doors,
# gable windows (glass), felt roofs, white barge boards, bunting of small flags along the
# eaves, three deckchairs with striped canvas (50 mm stripes: a period of ~4.5-5.5 px), a
# lifebuoy on a post, concrete slabs with dark joints, the beach beyond the row and in the
# near corner; a low sun over the sea from the front right, the sky's light (polarized: 0.6)

HUTS_CAMERA = {"position": [-8.0, -6.0, 1.6], "look_at": [9.0, 0.0, 1.25], "up": UP,
               "focal_length_mm": 4.6, "f_number": 8}
HUT_PAINTS = ("hut_white", "hut_sky", "hut_red", "hut_mint", "hut_coral", "hut_yellow",
              "hut_blue")
# per hut: the two stripe paints (equal: one colour) and the door's
HUTS = [("hut_sky", "hut_white", "hut_blue"), ("hut_red", "hut_white", "hut_white"),
        ("hut_mint", "hut_coral", "hut_yellow"), ("hut_yellow", "hut_yellow", "hut_blue"),
        ("hut_blue", "hut_yellow", "hut_red"), ("hut_coral", "hut_white", "hut_mint"),
        ("hut_sky", "hut_sky", "hut_white"), ("hut_mint", "hut_yellow", "hut_coral"),
        ("hut_red", "hut_sky", "hut_white"), ("hut_coral", "hut_coral", "hut_sky")]
HUT_W, HUT_PITCH, EAVES, RIDGE, BASE = 1.9, 2.4, 2.1, 2.7, 0.15


def gable_top(x, x0):
    """Height of a hut's front outline at x (the gable over the eaves)."""
    return EAVES + (RIDGE - EAVES) * (1 - abs(x - x0 - HUT_W / 2) / (HUT_W / 2))


def huts_meshes():
    rng = random.Random(9101)
    paint = {n: sl.Mesh("huts, " + n + " boards", WRITER) for n in HUT_PAINTS}
    glass = sl.Mesh("huts, gable windows", WRITER)
    roof = sl.Mesh("huts, felt roofs", WRITER)
    concrete = sl.Mesh("huts, plinths and steps", WRITER)
    for i, (a, b, door) in enumerate(HUTS):
        x0 = HUT_PITCH * i
        xc = x0 + HUT_W / 2
        # the body (side and back walls) in the first stripe colour, the plinth and a step
        sc.cuboid(paint[a], [xc, 1.1, (BASE + EAVES) / 2], [X, Y, UP],
                  [HUT_W, 2.2, EAVES - BASE])
        sc.cuboid(concrete, [xc, 1.1, BASE / 2], [X, Y, UP], [HUT_W + 0.1, 2.3, BASE])
        sc.cuboid(concrete, [xc, -0.3, 0.05], [X, Y, UP], [1.0, 0.35, 0.1])
        # the front: 19 boards of 100 mm, alternately a and b, up into the gable
        for k in range(19):
            xa, xb = x0 + 0.1 * k, x0 + 0.1 * (k + 1)
            pts = [[xa, -0.003, BASE], [xb, -0.003, BASE], [xb, -0.003, gable_top(xb, x0)]]
            if xa < xc < xb:
                pts.append([xc, -0.003, RIDGE])
            pts.append([xa, -0.003, gable_top(xa, x0)])
            paint[a if k % 2 == 0 else b].flat(pts)
        # the door (0.8 x 1.85 m) and the gable window in a white frame
        paint[door].flat([[xc - 0.4, -0.008, BASE], [xc + 0.4, -0.008, BASE],
                          [xc + 0.4, -0.008, BASE + 1.85], [xc - 0.4, -0.008, BASE + 1.85]])
        paint["hut_white"].flat([[xc - 0.22, -0.01, 2.19], [xc + 0.22, -0.01, 2.19],
                                 [xc + 0.22, -0.01, 2.55], [xc - 0.22, -0.01, 2.55]])
        glass.flat([[xc - 0.18, -0.013, 2.23], [xc + 0.18, -0.013, 2.23],
                    [xc + 0.18, -0.013, 2.51], [xc - 0.18, -0.013, 2.51]])
        # barge boards (white, 120 mm) along the gable's edges; roof slopes with an overhang
        for s in (-1, 1):
            e0 = [xc + s * (HUT_W / 2 + 0.1), -0.02, EAVES - 0.07]
            sl.strip(paint["hut_white"], [e0, [xc, -0.02, RIDGE + 0.03]], 0.12, [0, -1, 0])
            roof.flat([[xc + s * (HUT_W / 2 + 0.12), -0.15, EAVES - 0.08],
                       [xc, -0.15, RIDGE + 0.04], [xc, 2.35, RIDGE + 0.04],
                       [xc + s * (HUT_W / 2 + 0.12), 2.35, EAVES - 0.08]])
    # bunting along the eaves: a cord and triangular flags (180 x 220 mm) every 250 mm
    cord = [[-0.1 + 0.25 * k, -0.2, 2.3 - 0.06 * math.sin(math.pi * ((0.25 * k) % HUT_PITCH)
                                                        / HUT_PITCH)] for k in range(96)]
    sl.strip(paint["hut_white"], cord, 0.012, [0, -1, 0])
    flags = ("hut_red", "hut_yellow", "hut_blue", "hut_white", "hut_mint")
    for k, p in enumerate(cord[:-1]):
        tilt = rng.uniform(-0.03, 0.03)
        paint[flags[k % 5]].flat([[p[0] + 0.035, -0.205, p[2]], [p[0] + 0.215, -0.205 + tilt,
                                                                 p[2]],
                                  [p[0] + 0.125, -0.205 + tilt / 2, p[2] - 0.22]])
    # three deckchairs on the promenade turned towards the sun: a canvas sling of 50 mm stripes
    # from the top bar to the front bar (sagging), on white painted rails
    for x, y, yaw, pair in ((13.2, -1.6, -50, ("hut_red", "hut_white")),
                            (14.3, -1.9, -35, ("hut_blue", "hut_yellow")),
                            (15.5, -1.3, -45, ("hut_mint", "hut_white"))):
        across = [math.cos(math.radians(yaw)), math.sin(math.radians(yaw)), 0.0]
        back = [-across[1], across[0], 0.0]

        def at(u, d, z, x=x, y=y, across=across, back=back):
            return cg.add(cg.add([x, y, z], across, u), back, d)

        def sling(u, v, at=at):
            return at(u, 0.45 - 0.75 * v, 0.95 - 0.55 * v - 0.12 * math.sin(math.pi * v))

        for k in range(10):
            sc.surface_band(paint[pair[k % 2]], sling, lambda v, k=k: 0.05 * k,
                            lambda v, k=k: 0.05 * (k + 1), [i / 8 for i in range(9)])
        for u in (-0.02, 0.52):
            sc.sweep(paint["hut_white"], [at(u, 0.55, 1.0), at(u, -0.35, 0.3), at(u, -0.45, 0.0)],
                     0.012, 6)
            sc.sweep(paint["hut_white"], [at(u, 0.5, 0.0), at(u, -0.2, 0.45)], 0.012, 6)
    out = {"huts_" + n[4:]: m for n, m in paint.items()}
    out.update(huts_glass=glass, huts_roof=roof, huts_concrete=concrete)
    # the promenade's slabs (0.9 x 0.6 m) and dark joints of 15 mm
    joints = sl.Mesh("huts, slab joints", WRITER)
    for k in range(1, 18):
        sl.strip(joints, [[-9.0, -0.6 * k, 0.001], [26.0, -0.6 * k, 0.001]], 0.015, UP)
    for k in range(39):
        x = -9.0 + 0.9 * k
        sl.strip(joints, [[x, -10.5, 0.001], [x, -0.6, 0.001]], 0.015, UP)
    out["huts_joints"] = joints
    # a lifebuoy (0.75 m) on a post between the third and fourth huts
    buoy = sl.Mesh("huts, lifebuoy", WRITER)
    sl.torus(buoy, [3 * HUT_PITCH - 0.25, -0.35, 1.25], [0, -1, 0], 0.3, 0.075, 32, 10)
    out["huts_buoy"] = buoy
    return out


def huts_parts():
    objs = [cg.ground("beach_sand"),
            cg.rect([8.0, -6.0, 0.0], UP, X, [40.0, 12.0], "promenade"),
            sl.box([3 * HUT_PITCH - 0.25, -0.25, 0.8], [0.08, 0.08, 1.6], "plinth")]
    for n in HUT_PAINTS:
        objs.append(obj("huts", n[4:], n))
    for n, mat in (("glass", "hut_glass"), ("roof", "roof_felt"), ("concrete", "plinth"),
                   ("joints", "promenade_joint")):
        objs.append(obj("huts", n, mat))
    objs.append(obj("huts", "buoy", "buoy_orange", True))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([0.7, -0.55, 0.35])),
               "irradiance_w_m2": [620, 590, 520]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.2, -0.35, 0.9])),
               "irradiance_w_m2": [110, 130, 170], "polarization": {"linear_deg": 30, "dop": 0.6}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# fishmonger: a fishmonger's counter seen from the customer's side, from above (~1.3-1.7 mm per
# pixel): a bed of crushed ice (flattish faceted chunks 18-30 mm, sigma 0.25) sloping 12 degrees
# towards the customer, two sea bass (silver, a dark back, a lateral line), three mackerel
# (blue-green backs with 25 dark wavy bars of 2.5 mm every 8.4 mm: ~5-6.5 px), two red mullet
# with a yellow stripe, a side of salmon (orange with 47 white fat chevrons of 1.5 mm every
# 9 mm: ~7 px), a steel tray of cooked prawns, lemon halves, parsley, slate price tags with
# chalk figures; two lamps over the counter and a window's light (polarized: degree 0.5)

FISH_CAMERA = {"position": [0.04, -0.72, 1.72], "look_at": [-0.06, 0.4, 0.95], "up": UP,
               "focal_length_mm": 3.0, "f_number": 8}
COUNTER = sc.Slope([0, 0, 0.9], 12)


def fish_body(mesh, u, v, phi, length, height, thick):
    """A fish lying on its side on the ice, its back towards the customer: a loft along its
    length (head at u, v on the counter, towards phi), a forked tail fin. Returns its surface
    as a function of (t along the body from the head, theta around it from the back edge: 90
    degrees is the side facing up, lift a factor on the radii) for stripes and eyes."""
    a, b = COUNTER.along(phi)
    b = [-x for x in b]  # the back towards the customer

    def shape(t):
        return math.sin(math.pi * min(t, 0.999)) ** 0.6 * (1 - 0.45 * t)

    c0 = COUNTER.at(u, v, 0.45 * thick)
    stations = [(length * t, 0.5 * height * shape(t), 0.5 * thick * shape(t))
                for t in [k / 12 for k in range(13)]]
    stations[0] = (0.0, 0.0, 0.0)
    stations[-1] = (length, 0.0, 0.0)
    sc.loft(mesh, c0, [a, b, COUNTER.n], stations, 14)
    tail = cg.add(c0, a, length * 0.97)
    for s in (-1, 1):
        mesh.flat([tail, cg.add(cg.add(tail, a, 0.2 * length), b, s * 0.42 * height),
                   cg.add(cg.add(tail, a, 0.14 * length), b, s * 0.08 * height)])

    def surface(t, theta, lift=1.0):
        th = math.radians(theta)
        r = lift * 0.5 * shape(t)
        return cg.add(cg.add(cg.add(c0, a, length * t), b, r * height * math.cos(th)),
                      COUNTER.n, r * thick * math.sin(th))

    return surface


def band(mesh, f, th0, th1, t0, t1, lift, steps=12):
    """A stripe along a fish (f: fish_body's surface) between angles th0 and th1 (in steps of
    at most 12 degrees, so that it stays outside the body)."""
    n = max(1, math.ceil((th1 - th0) / 12))
    for k in range(n):
        a, b = th0 + (th1 - th0) * k / n, th0 + (th1 - th0) * (k + 1) / n
        sc.surface_band(mesh, lambda th, t: f(t, th, lift), lambda t, a=a: a, lambda t, b=b: b,
                        [t0 + (t1 - t0) * j / steps for j in range(steps + 1)])


def fish_meshes():
    rng = random.Random(9203)
    names = ("ice_crushed", "fish_silver", "mackerel_back", "fish_black", "mullet_red",
             "salmon_flesh", "salmon_fat", "prawn_pink", "lemon_peel", "parsley", "tag_chalk")
    mesh = {n: sl.Mesh("fishmonger, " + n.replace("_", " "), WRITER) for n in names}
    clear = []  # footprints (u, v, radius) kept free of ice chunks

    def eye(f, height):
        for r, n, lift in ((0.075, "fish_silver", 1.02), (0.045, "fish_black", 1.05)):
            sl.disc(mesh[n], f(0.09, 90, lift), COUNTER.n, r * height, 10)

    def footprint(u, v, phi, length, width):
        a = COUNTER.along(phi)[0]
        for k in range(int(length / width) + 1):
            clear.append((u + a[0] * width * k, v + cg.dot(a, COUNTER.v) * width * k, width * 0.6))

    # two sea bass: silver, a dark back, a dark lateral line
    for u, v, phi in ((-0.46, 0.07, 4), (-0.44, 0.2, -3)):
        f = fish_body(mesh["fish_silver"], u, v, phi, 0.34, 0.085, 0.04)
        band(mesh["fish_black"], f, 0, 28, 0.05, 0.96, 1.015)
        band(mesh["fish_black"], f, 56, 60, 0.2, 0.96, 1.015)
        eye(f, 0.085)
        footprint(u, v, phi, 0.4, 0.085)
    # three mackerel: blue-green backs with dark wavy bars, silver bellies
    for u, v, phi in ((-0.43, 0.34, 3), (-0.41, 0.42, -2), (-0.44, 0.5, 4)):
        f = fish_body(mesh["fish_silver"], u, v, phi, 0.28, 0.055, 0.035)
        band(mesh["mackerel_back"], f, 0, 95, 0.07, 0.96, 1.015)
        ph = rng.uniform(0, math.pi)
        for k in range(25):
            t = 0.16 + 0.03 * k
            sc.surface_band(mesh["fish_black"], lambda tt, th: f(tt, th, 1.035),
                            lambda th, t=t: t + 0.012 * math.sin(math.radians(4 * th) + ph),
                            lambda th, t=t: t + 0.009 + 0.012 * math.sin(math.radians(4 * th)
                                                                         + ph),
                            [8 + 9 * j for j in range(10)])
        eye(f, 0.055)
        footprint(u, v, phi, 0.34, 0.055)
    # two red mullet with a yellow stripe
    for u, v, phi in ((-0.42, 0.62, 2), (-0.4, 0.71, -3)):
        f = fish_body(mesh["mullet_red"], u, v, phi, 0.24, 0.06, 0.032)
        band(mesh["lemon_peel"], f, 40, 52, 0.15, 0.9, 1.015)
        eye(f, 0.06)
        footprint(u, v, phi, 0.28, 0.06)
    # a side of salmon (0.46 x 0.15 m, 22 mm thick at the head end) with white fat lines
    sa, sb = COUNTER.along(-8)
    s0 = COUNTER.at(0.0, 0.08)

    def fillet(x, w, lift=0.0):
        th = 0.022 * (1 - 0.6 * x / 0.46) * max(0.0, 1 - (2 * w / 0.15 - 1) ** 2) ** 0.5
        return cg.add(cg.add(cg.add(s0, sa, x), sb, w), COUNTER.n, 0.004 + th + lift)

    xs = [0.46 * k / 23 for k in range(24)]
    ws = [0.15 * k / 10 for k in range(11)]
    grid = [[mesh["salmon_flesh"].vert(fillet(x, w)) for w in ws] for x in xs]
    sc.join_rings(mesh["salmon_flesh"], grid, closed=False)
    for k in range(47):  # chevrons 9 mm apart, the last 25 mm short of the tail
        x0 = 0.012 + 0.009 * k
        sl.strip(mesh["salmon_fat"], [fillet(x0 + 0.014 * abs(2 * w / 0.15 - 1) - 0.007, w,
                                             0.0004)
                                      for w in [0.15 * j / 8 for j in range(1, 8)]], 0.0015,
                 COUNTER.n)
    sl.strip(mesh["fish_silver"], [fillet(x, 0.0, 0.0003) for x in xs], 0.008, COUNTER.n)
    footprint(0.02, 0.1, -8, 0.48, 0.15)
    # cooked prawns in a steel tray (0.26 x 0.18 m) at the back right
    for k in range(36):
        c = COUNTER.at(rng.uniform(0.16, 0.38), rng.uniform(0.56, 0.7), rng.uniform(0.025, 0.04))
        a, b = COUNTER.along(rng.uniform(0, 360))
        pts = [cg.add(cg.add(c, a, 0.025 * math.cos(q)), b, 0.025 * math.sin(q))
               for q in [math.radians(-40 + 25 * j) for j in range(10)]]
        sc.sweep(mesh["prawn_pink"], pts, 0.0055, 8)
    clear.append((0.27, 0.63, 0.16))
    # lemon halves (cut face down), parsley sprigs
    for u, v in ((0.02, 0.36), (0.08, 0.4), (0.03, 0.45), (0.1, 0.33), (0.4, 0.42)):
        r = rng.uniform(0.026, 0.032)
        sc.loft(mesh["lemon_peel"], COUNTER.at(u, v), [COUNTER.n, COUNTER.u, COUNTER.v],
                [(0.0, r, r * 0.95), (0.5 * r, 0.9 * r, 0.86 * r), (0.85 * r, 0.55 * r, 0.5 * r),
                 (r, 0.0, 0.0)], 16)
        clear.append((u, v, r + 0.005))
    for u, v in ((0.16, 0.42), (0.33, 0.45), (-0.06, 0.42), (0.12, 0.5)):
        for _ in range(30):
            p = COUNTER.at(u + rng.gauss(0, 0.018), v + rng.gauss(0, 0.014),
                           rng.uniform(0.006, 0.03))
            nrm = cg.unit(cg.add(COUNTER.n, [rng.gauss(0, 0.5) for _ in range(3)]))
            sl.disc(mesh["parsley"], p, nrm, rng.uniform(0.007, 0.011), 5)
        clear.append((u, v, 0.035))
    # slate price tags standing on the ice with chalk figures (strokes 1.5-2 mm)
    for u, v in ((-0.06, 0.28), (0.04, 0.66), (0.3, 0.3)):
        face = cg.unit(cg.add(COUNTER.n, [0, -1.2, 0]))
        right = cg.unit(cg.cross(face, UP))
        up = cg.cross(right, face)
        c = COUNTER.at(u, v, 0.035)
        sc.cuboid(mesh["fish_black"], c, [right, up, face], [0.09, 0.06, 0.004])
        x = -0.036
        for _ in range(5):
            segs = rng.sample(range(7), rng.randint(3, 6))
            for q in segs:
                (x0, y0), (x1, y1) = (((0, 1), (1, 1)), ((1, 1), (1, 0)), ((1, 0), (1, -1)),
                                      ((0, -1), (1, -1)), ((0, 0), (0, -1)),
                                      ((0, 1), (0, 0)), ((0, 0), (1, 0)))[q]
                p0 = cg.add(cg.add(c, right, x + 0.01 * x0), up, 0.014 * y0)
                p1 = cg.add(cg.add(c, right, x + 0.01 * x1), up, 0.014 * y1)
                sl.strip(mesh["tag_chalk"], [cg.add(p0, face, 0.0022), cg.add(p1, face, 0.0022)],
                         0.0018, face)
            x += 0.0155
        clear.append((u, v, 0.05))
    # crushed ice: irregular glossy chunks (radius 8-14 mm) wherever nothing lies
    n = 0
    while n < 1500:
        u, v = rng.uniform(-0.5, 0.5), rng.uniform(-0.02, 0.8)
        if any((u - cu) ** 2 + (v - cv) ** 2 < r * r for cu, cv, r in clear):
            continue
        r = rng.uniform(0.009, 0.015)
        axes = sc.axes_of(cg.add(COUNTER.n, [rng.gauss(0, 0.4) for _ in range(3)]))
        sc.ellipsoid(mesh["ice_crushed"], COUNTER.at(u, v, 0.3 * r), axes,
                     [r * rng.uniform(0.4, 0.6), r, r * rng.uniform(0.6, 0.9)], 5, 2,
                     [[rng.uniform(0.75, 1.15) for _ in range(5)]])
        n += 1
    return {"fishmonger_" + n.split("_")[-1]: m for n, m in mesh.items()}


FISH_MESHES = (("crushed", "ice_crushed", False), ("silver", "fish_silver", True),
               ("back", "mackerel_back", False), ("black", "fish_black", False),
               ("red", "mullet_red", True), ("flesh", "salmon_flesh", True),
               ("fat", "salmon_fat", False), ("pink", "prawn_pink", True),
               ("peel", "lemon_peel", True), ("parsley", "parsley_leaf", False),
               ("chalk", "tag_chalk", False))


def fishmonger_parts():
    objs = [cg.rect(COUNTER.at(0.0, 0.45, -0.002), COUNTER.n, X, [1.6, 1.0], "ice_bed"),
            cg.rect([0.0, 1.05, 1.4], [0, -1, 0], X, [2.0, 1.2], "stall_tiles"),
            sl.box(COUNTER.at(0.27, 0.63, 0.012), [0.27, 0.19, 0.03], "prawn_tray_steel")]
    objs[-1]["rotation_deg"] = [12, 0, 0]  # the steel tray lies on the slope
    for n, mat, smooth in FISH_MESHES:
        objs.append(obj("fishmonger", n, mat, smooth))
    lights = [{"type": "point", "position": [-0.3, 0.2, 2.2], "intensity_w_sr": [30, 28, 24]},
              {"type": "point", "position": [0.4, 0.45, 2.2], "intensity_w_sr": [30, 28, 24]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.8, 0.2, 0.55])),
               "irradiance_w_m2": [45, 50, 60], "polarization": {"linear_deg": 60, "dop": 0.5}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# jeweller: a jeweller's window tray seen from 0.5 m (~0.45-0.65 mm per pixel) on a board of
# black velvet sloping 20 degrees: two bracelets of 4 mm beads (~9 px) alternating two stones
# (turquoise/coral, lapis/amber: a colour period of ~19 px), a loom-woven band of 2 mm seed
# beads (~4.3 px; borders alternating bead by bead: ~8.5 px, chevrons two beads wide), a strand
# of 3 mm beads of random stones (a hue change every ~7 px), a loop of 7 mm pearls, an 18 ct
# gold and a sterling silver chain (links 2.4 mm long every 1.6 mm: ~3 px), a cream ring tray
# of five rolls holding six rings (gold and silver bands; ruby, sapphire, emerald stones,
# faceted); two small spot lamps in front, one behind (glints near Brewster's angle), a soft
# light from above

JEWEL_CAMERA = {"position": [0.01, -0.3, 0.33], "look_at": [0.0, 0.08, 0.028], "up": UP,
                "focal_length_mm": 3.4, "f_number": 8}
BOARD = sc.Slope([0, 0, 0], 20)
BEADS = ("bead_turquoise", "bead_coral", "bead_lapis", "bead_amber", "bead_jade", "bead_rose")
GEMS = ("ruby", "sapphire", "emerald")


def bead(mesh, p, r):
    sc.ellipsoid(mesh, p, [BOARD.n, BOARD.u, BOARD.v], [r, r, r], 10, 5)


def chain(mesh, pts, link=0.0024, wire=0.00032):
    """Links (small tori, alternately flat and on edge) every 2/3 of a link along pts."""
    step, k, carry = 2 * link / 3, 0, 0.0
    for p, q in zip(pts, pts[1:]):
        d = [b - a for a, b in zip(p, q)]
        seg = math.sqrt(cg.dot(d, d))
        t = carry
        while t < seg:
            c = cg.add(p, d, t / seg)
            side = cg.unit(cg.cross(BOARD.n, d))
            axis = BOARD.n if k % 2 == 0 else side
            sl.torus(mesh, cg.add(c, BOARD.n, wire + (0.0 if k % 2 == 0 else link / 3)), axis,
                     link / 2 - wire, wire, 8, 4)
            t += step
            k += 1
        carry = t - seg


def gem(mesh, c, axis, r):
    """A faceted stone (eight-sided brilliant, table up along axis) of girdle radius r."""
    sc.loft(mesh, c, sc.axes_of(axis), [(-0.8 * r, 0.0, 0.0), (0.0, r, r),
                                        (0.25 * r, 0.62 * r, 0.62 * r), (0.3 * r, 0.0, 0.0)], 8,
            math.pi / 8)


def seed_bead(mesh, c, axis, r=0.00095, half=0.0008):
    """A seed bead: a short hexagonal barrel of radius r along axis, rounded ends."""
    sc.loft(mesh, c, sc.axes_of(axis), [(-half, 0.0, 0.0), (-0.8 * half, r, r),
                                        (0.8 * half, r, r), (half, 0.0, 0.0)], 6)


def jeweller_meshes():
    rng = random.Random(9307)
    names = BEADS + ("pearl", "gold_18ct", "silver_925", "tray_cream") + GEMS
    mesh = {n: sl.Mesh("jeweller, " + n.replace("_", " "), WRITER) for n in names}
    # two bracelets of 4 mm beads on a 4.3 mm pitch, two stones alternating
    for (u, v), pair in (((-0.088, 0.018), (0, 1)), ((-0.026, 0.012), (2, 3))):
        n = 42
        for k in range(n):
            a = 2 * math.pi * k / n
            bead(mesh[BEADS[pair[k % 2]]], BOARD.at(u + 0.0288 * math.cos(a),
                                                   v + 0.0288 * math.sin(a), 0.002), 0.002)
    # a loom-woven band of 2 mm seed beads (10 x 66) lying slantwise over the lower right: two
    # border rows each side alternating coral and turquoise bead by bead, between them chevrons
    # of four stones in bands two beads wide
    along, across = BOARD.along(10)
    start = BOARD.at(0.008, -0.014, 0.00095)
    pattern = ("bead_coral", "bead_amber", "bead_turquoise", "bead_lapis")
    for col in range(66):
        for row in range(10):
            c = cg.add(cg.add(start, along, 0.0019 * col), across, 0.0021 * row)
            if row in (0, 1, 8, 9):
                k = 2 * ((col + row) % 2)
            else:
                k = (abs(col % 12 - 6) + row) // 2 % 4
            seed_bead(mesh[pattern[k]], c, across)
    # a strand of 3 mm beads of random stones in a loose curve through the middle
    for k in range(64):
        t = k / 63
        u, v = -0.14 + 0.2 * t, 0.058 + 0.008 * math.sin(3 * math.pi * t) - 0.01 * t
        bead(mesh[BEADS[rng.randrange(6)]], BOARD.at(u, v, 0.0015), 0.0015)
    # a loop of 7 mm pearls at the top right
    for k in range(39):
        a = 2 * math.pi * k / 39
        bead(mesh["pearl"], BOARD.at(0.078 + 0.045 * math.cos(a), 0.15 + 0.045 * math.sin(a),
                                     0.0035), 0.0035)
    # chains: 18 ct gold across the middle, sterling silver below it
    chain(mesh["gold_18ct"], [BOARD.at(-0.15 + 0.3 * t / 20,
                                       0.094 - 0.01 * math.sin(math.pi * t / 20))
                              for t in range(21)])
    chain(mesh["silver_925"], [BOARD.at(-0.01 + 0.16 * t / 16,
                                        0.066 + 0.006 * math.sin(1.3 * t) + 0.012 * t / 16)
                               for t in range(17)])
    # the ring tray: five cream rolls (radius 8 mm) across the top left, rings standing in them
    for k in range(5):
        v = 0.115 + 0.017 * k
        sc.sweep(mesh["tray_cream"], [BOARD.at(-0.16, v, 0.008), BOARD.at(0.02, v, 0.008)],
                 0.008, 14)
    stones = ("ruby", "sapphire", "emerald", "ruby", "sapphire", "emerald")
    for k in range(6):
        u, v = -0.13 + 0.026 * k, 0.1235 + 0.017 * (k % 4)
        band = "gold_18ct" if k % 2 == 0 else "silver_925"
        c = BOARD.at(u, v, 0.016)
        sl.torus(mesh[band], c, BOARD.v, 0.0095, 0.0012, 32, 8)
        top = cg.add(c, BOARD.n, 0.0095 + 0.0012)
        gem(mesh[stones[k]], cg.add(top, BOARD.n, 0.0022), BOARD.n, 0.0032)
        for s in (-1, 1):  # the setting's claws
            sc.sweep(mesh[band], [cg.add(top, BOARD.u, 0.0022 * s),
                                  cg.add(cg.add(top, BOARD.u, 0.0030 * s), BOARD.n, 0.0032)],
                     0.0005, 5)
    return {"jeweller_" + n.split("_")[-1]: m for n, m in mesh.items()}


def jeweller_parts():
    objs = [cg.rect(BOARD.at(0.0, 0.06), BOARD.n, X, [0.5, 0.4], "velvet_black")]
    for n in BEADS + ("pearl", "gold_18ct", "silver_925", "tray_cream") + GEMS:
        objs.append(obj("jeweller", n.split("_")[-1], n, n != "tray_cream"))
    lights = [{"type": "point", "position": [-0.12, 0.02, 0.32],
               "intensity_w_sr": [1.2, 1.2, 1.25]},
              {"type": "point", "position": [0.15, -0.05, 0.3],
               "intensity_w_sr": [1.2, 1.2, 1.25]},
              {"type": "point", "position": [0.05, 0.45, 0.2],
               "intensity_w_sr": [1.5, 1.45, 1.4]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.1, -0.3, 1.0])),
               "irradiance_w_m2": [8, 8, 8.5]}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# pencils: an artist's desk seen from the front, ~35 degrees down (~0.7 mm per pixel across,
# ~1.15 mm up the frame): an open tin of twelve lacquered hexagonal coloured pencils (7 mm
# across the flats, side by side: a hue change every ~5 px) with gold-foil lettering, four loose
# pencils and three shavings on a green cutting mat (light grid lines 0.5 mm every 10 mm, bold
# every 50 mm), a sketchbook with six patches of hatching in matte strokes (0.7 mm every
# 3.5-5 mm: ~3-8 px; four of two colours crossing), a magnesium sharpener, an eraser, a birch
# desk; a desk lamp, a window's light from behind on the left and a polarized light (degree
# 0.6) from the right

PENCIL_CAMERA = {"position": [-0.01, -0.5, 0.36], "look_at": [-0.03, -0.01, 0.0], "up": UP,
                 "focal_length_mm": 2.8, "f_number": 8}
LACQUERS = ("lacquer_lemon", "lacquer_orange", "lacquer_vermilion", "lacquer_crimson",
            "lacquer_pink", "lacquer_violet", "lacquer_ultramarine", "lacquer_sky",
            "lacquer_emerald", "lacquer_grass", "lacquer_ochre", "lacquer_umber")
PENCIL_R = 0.0035 / math.cos(math.pi / 6)  # 7 mm across the flats
STROKES = ("vermilion", "ultramarine", "lemon", "emerald", "pink")  # hatching (matte)
TIN = [-0.11, 0.02]  # the tin's floor: its centre (x, y); 190 x 100 mm, 12 mm deep


def pencil(mesh, wood, end, d, colour, length=0.175):
    """A hexagonal pencil lying on a flat from end (its blunt end, on the surface) along the
    horizontal direction d, sharpened: a cedar cone of 18 mm and a lead tip of 6 mm."""
    d = cg.unit(d)
    axes = [d, cg.unit(cg.cross(UP, d)), UP]
    c = cg.add(end, UP, PENCIL_R * math.cos(math.pi / 6))
    sc.loft(mesh[colour], c, axes, [(0.0, 0.0, 0.0), (0.0, PENCIL_R, PENCIL_R),
                                   (length, PENCIL_R, PENCIL_R), (length, 0.0, 0.0)], 6)
    sc.loft(wood, c, axes, [(length, PENCIL_R, PENCIL_R), (length + 0.018, 0.0012, 0.0012),
                            (length + 0.0181, 0.0, 0.0)], 6)
    sc.loft(mesh[colour], c, axes, [(length + 0.018, 0.0012, 0.0012),
                                    (length + 0.024, 0.0, 0.0)], 6)
    return c


def pencils_meshes():
    rng = random.Random(9409)
    mesh = {n: sl.Mesh("pencils, " + n.replace("_", " "), WRITER) for n in LACQUERS}
    wood = sl.Mesh("pencils, cedar", WRITER)
    foil = sl.Mesh("pencils, gold foil lettering", WRITER)
    grid = sl.Mesh("pencils, cutting mat grid", WRITER)
    # the tin's twelve pencils, side by side along y, pointing +x, lettering on the top flats
    top = 0.012 + 0.0005
    for k, colour in enumerate(LACQUERS):
        y = TIN[1] - 0.0396 + 0.0072 * k
        c = pencil(mesh, wood, [TIN[0] - 0.093, y, top], [1, 0, 0], colour, 0.16)
        x = c[0] + 0.03
        h = c[2] + PENCIL_R * math.cos(math.pi / 6) + 0.0002
        while x < c[0] + 0.085:
            w = rng.choice((0.0005, 0.0008, 0.0012))
            foil.flat([[x, y - 0.0012, h], [x + w, y - 0.0012, h], [x + w, y + 0.0012, h],
                       [x, y + 0.0012, h]])
            x += w + rng.uniform(0.0005, 0.0012)
    # loose pencils on the mat and one on the sketchbook
    for (x, y, z, a), colour in (((-0.12, -0.14, 0.0012, 8), "lacquer_crimson"),
                                 ((-0.09, -0.08, 0.0012, -12), "lacquer_sky"),
                                 ((0.02, -0.16, 0.0012, 35), "lacquer_grass"),
                                 ((0.06, 0.09, 0.0062, -20), "lacquer_violet")):
        pencil(mesh, wood, [x, y, z], [math.cos(math.radians(a)), math.sin(math.radians(a)), 0],
               colour)
    # shavings: flat spiral ribbons of cedar with a coloured scalloped rim
    for (x, y), colour in (((-0.035, -0.1), "lacquer_orange"), ((-0.01, -0.125), "lacquer_pink"),
                           ((0.015, -0.095), "lacquer_emerald")):
        inner, rim = [], []
        for j in range(25):
            a = 2 * math.pi * 1.3 * j / 24
            r = 0.004 + 0.008 * j / 24
            inner.append([x + r * math.cos(a), y + r * math.sin(a), 0.0015 + 0.0001 * j])
            rim.append([x + (r + 0.0018) * math.cos(a), y + (r + 0.0018) * math.sin(a),
                        0.0016 + 0.0001 * j])
        sl.strip(wood, inner, 0.0035, UP)
        sl.strip(mesh[colour], rim, 0.0012, UP)
    # hatching on the sketchbook (its page at z 6 mm): patches of parallel strokes, two crossing
    strokes = {n: sl.Mesh("pencils, " + n + " hatching", WRITER) for n in STROKES}
    for (x, y, a, spacing, colours) in ((0.09, -0.02, 30, 0.0045, ("vermilion",)),
                                        (0.15, -0.03, -40, 0.0038, ("ultramarine", "lemon")),
                                        (0.1, -0.08, 75, 0.005, ("emerald", "pink")),
                                        (0.16, -0.085, 10, 0.0035, ("lemon",)),
                                        (0.13, 0.03, 55, 0.0042, ("pink", "emerald")),
                                        (0.07, 0.025, -15, 0.004, ("vermilion",
                                                                   "ultramarine"))):
        for q, colour in enumerate(colours):
            t = math.radians(a + 90 * q)
            d, e = [math.cos(t), math.sin(t), 0.0], [-math.sin(t), math.cos(t), 0.0]
            for k in range(int(0.036 / spacing)):
                off = -0.018 + spacing * k
                half = 0.02 * rng.uniform(0.8, 1.0)
                p0 = cg.add(cg.add([x, y, 0.0061 + 0.00005 * q], e, off), d, -half)
                sl.strip(strokes[colour], [p0, cg.add(p0, d, 2 * half)], 0.0007, UP)
    # the cutting mat's grid: 0.5 mm lines every 10 mm, 1 mm every 50 mm
    for k in range(46):
        w = 0.001 if k % 5 == 0 else 0.0005
        sl.strip(grid, [[-0.24 + 0.01 * k, -0.2, 0.0003], [-0.24 + 0.01 * k, 0.1, 0.0003]], w, UP)
    for k in range(31):
        w = 0.001 if k % 5 == 0 else 0.0005
        sl.strip(grid, [[-0.24, -0.2 + 0.01 * k, 0.0003], [0.21, -0.2 + 0.01 * k, 0.0003]], w, UP)
    out = {"pencils_" + n.split("_")[-1]: m for n, m in mesh.items()}
    out.update({"pencils_stroke_" + n: m for n, m in strokes.items()})
    out.update(pencils_cedar=wood, pencils_foil=foil, pencils_grid=grid)
    return out


def pencils_parts():
    x, y = TIN
    objs = [cg.ground("birch_desk"),
            cg.rect([-0.015, -0.05, 0.0002], UP, X, [0.45, 0.3], "mat_green"),
            sl.box([0.12, -0.03, 0.003], [0.15, 0.21, 0.006], "sketch_paper"),
            sl.box([x, y, 0.006], [0.19, 0.1, 0.012], "tinplate")]
    # the tin's four walls (navy outside) and its lid beside it
    for dx, dy in ((0, -1), (0, 1), (-1, 0), (1, 0)):
        objs.append(sl.box([x + 0.0955 * dx, y + 0.0505 * dy, 0.006],
                           [0.19 if dx == 0 else 0.001, 0.1 if dy == 0 else 0.001, 0.012],
                           "tin_navy"))
    objs += [sl.box([x, y + 0.13, 0.003], [0.192, 0.102, 0.006], "tin_navy"),
             sl.box([0.05, -0.13, 0.007], [0.026, 0.016, 0.014], "sharpener_magnesium", 25),
             sl.box([0.07, 0.06, 0.005], [0.045, 0.02, 0.01], "eraser_pink", -10)]
    for n in LACQUERS:
        objs.append(obj("pencils", n.split("_")[-1], n))
    for n in STROKES:
        objs.append(obj("pencils", "stroke_" + n, "stroke_" + n))
    objs.append(obj("pencils", "cedar", "cedar"))
    objs.append(obj("pencils", "foil", "gold_foil"))
    objs.append(obj("pencils", "grid", "mat_line"))
    lights = [{"type": "point", "position": [-0.3, 0.1, 0.4], "intensity_w_sr": [3.0, 2.7, 2.2]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.55, 0.65, 0.5])),
               "irradiance_w_m2": [30, 32, 36]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.9, 0.1, 0.5])),
               "irradiance_w_m2": [12, 13, 15], "polarization": {"linear_deg": 100, "dop": 0.6}}]
    return MATERIALS, objs, lights


SCENES = sc.scene_set(TITLE, EXPOSURE, {
    "huts": (huts_parts, HUTS_CAMERA, "a row of painted beach huts on a promenade (striped "
             "board fronts, gloss doors, gable windows, bunting, deckchairs, a lifebuoy), a low "
             "sun over the sea", [30, 38, 55]),
    "fishmonger": (fishmonger_parts, FISH_CAMERA, "a fishmonger's counter from above (crushed "
                   "ice, sea bass, mackerel with dark bars, red mullet, a side of salmon with "
                   "fat lines, prawns in a steel tray, lemons, parsley, slate price tags)",
                   [2, 2, 2]),
    "jeweller": (jeweller_parts, JEWEL_CAMERA, "a jeweller's window tray (bead bracelets "
                 "alternating two stones, a loom-woven band of seed beads, a strand of mixed "
                 "beads, pearls, gold and silver chains, rings with ruby, sapphire and emerald "
                 "stones in a cream ring tray) on black velvet", [1, 1, 1]),
    "pencils": (pencils_parts, PENCIL_CAMERA, "an artist's desk (a tin of twelve lacquered "
                "coloured pencils, loose pencils and shavings on a cutting mat, a sketchbook "
                "with hatching, a sharpener, an eraser)", None),
}, {
    "huts_g4": ("huts", 4, "a fast shutter"),
    "jeweller_g17": ("jeweller", 17, "an evening window, handheld"),
})


def meshes():
    """Every mesh of the set: file name -> OBJ text (each *_meshes gives name -> sl.Mesh)."""
    return {name + ".obj": mesh.text() for make in (huts_meshes, fish_meshes, jeweller_meshes,
                                                     pencils_meshes)
            for name, mesh in make().items()}


cg.write_all(HERE, SCENES, meshes, sys.argv)
