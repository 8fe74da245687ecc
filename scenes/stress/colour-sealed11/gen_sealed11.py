#!/usr/bin/env python3
"""Writes the eleventh sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed11.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed11.py --print NAME` prints one scene instead.
Every generic helper is imported: ../sealed_common.py (outside the sealed directories: lofts,
ellipsoids, sweeps, boxes as facets, smooth patches, flat rings, the materials table, the mesh
files of a scene and their objects, the scene records with their noisy copies), which
re-exports ../colour-sealed6/sealed_lib.py (`sl`: millimetre meshes, tubes, discs, ribbons,
mesh objects, boxes, spheres; read, never written) and ../colour_gen.py (`cg`: the colour
sensor, the scene record, rect, vectors, the writer). Nothing here is a copy of an earlier
generator's helper; what is below builds this set's own things (a roadworks site, a pub's pool
table, an archery range, a board game night's table).

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). The metals (the road plate's and excavator bucket's steel, the
pool table's chrome corner castings, the bow's aluminium sight and stand, the coins' brass and
cupro-nickel) are assumed metals of the right order (n - ik per channel at 610, 530 and
465 nm, from memory, not a table lookup); the excavator's cab glass is a dielectric of index
1.52. A glossy surface mirrors a light near Brewster's angle with a degree of polarization near
1 only where its k is small (dark or black: fresh bitumen, the cab glass, the pool table's
varnished rails and the black ball, the archers' black gloss score board and bow limbs, the
lacquered rosewood table); a paint of large k reflects less polarized light. None of the
paints, meshes, cameras or layouts of the other colour sets is reused (nor a paint's or metal's
name, nor a paint's k).

Units: metres in the scenes, millimetres in the OBJ files (sl.Mesh; each mesh object has scale
0.001). A mesh placed with `smooth` false shows every facet flat; lofts, ellipsoids and sweeps
share their vertices, and placed with `smooth` true the loader's area-weighted normals round
them. The set's materials are one text table (MATERIALS); each scene's record names those its
objects use.

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
WRITER = "gen_sealed11.py"
TITLE = "colour sealed 11: "
UP = [0, 0, 1]
X, Y = [1, 0, 0], [0, 1, 0]

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "roadworks": 1500,
    "pooltable": 13000,
    "archery": 1700,
    "boardgame": 11500,
    "archery_g10": 538,
    "pooltable_g19": 1459,
}

# every material of the set (sc.materials: paints `name sigma k_R k_G k_B [n]`, n 1.5 unless
# given; metals `name sigma metal n_R n_G n_B k_R k_G k_B`); each scene's record keeps those
# its objects use
MATERIALS = sc.materials("""
# roadworks: barriers, cones, a mini-excavator, tarmac, fresh bitumen, ducts
tarmac_dry             0.45   0.17  0.17  0.18
bitumen_fresh          0.05   0.022 0.021 0.024
paving_slab            0.5    0.82  0.78  0.7
kerbstone_pale         0.35   0.6   0.6   0.57
barrier_red            0.15   1.33  0.13  0.11
barrier_white          0.15   1.47  1.46  1.4
barrier_foot           0.5    0.045 0.045 0.045
traffic_orange         0.12   1.52  0.48  0.07
sleeve_silver          0.25   1.28  1.3   1.3
chevron_board         0.2    1.48  1.28  0.08
chevron_bar          0.2    0.036 0.034 0.041
safety_netting         0.4    1.5   0.56  0.1
digger_paint          0.1    1.5   1.1   0.05
digger_track           0.6    0.062 0.061 0.066
cab_glass              0.03   0.021 0.024 0.029   1.52
bucket_steel           0.2    metal  2.6  2.5  2.3    3.3  3.2  3.0
spoil_clay             0.8    0.62  0.36  0.2
duct_water              0.2    0.1   0.35  1.2
duct_gas            0.2    1.45  1.2   0.1
duct_telecom             0.2    0.12  0.65  0.16
duct_purple            0.2    0.7   0.12  0.85
duct_bore              0.6    0.015 0.015 0.016
road_lining             0.4    1.3   1.3   1.26
amber_lens             0.03   1.4   0.5   0.03
# pooltable: cloth, balls, rails, carpet
baize_green            0.8    0.06  0.45  0.17
rail_mahogany          0.1    0.13  0.055 0.035
sight_pearl            0.15   1.4   1.4   1.36
pocket_leather         0.5    0.03  0.025 0.022
casting_chrome         0.05   metal  2.9  2.8  2.6    3.6  3.5  3.3
ball_ivory             0.02   1.52  1.46  1.28    1.55
ball_yellow            0.02   1.5   1.25  0.06   1.55
ball_blue              0.02   0.06  0.15  1.0    1.55
ball_red               0.02   1.31  0.075 0.062   1.55
ball_purple            0.02   0.45  0.07  0.6    1.55
ball_orange            0.02   1.5   0.5   0.05   1.55
ball_green             0.02   0.05  0.42  0.12   1.55
ball_maroon            0.02   0.55  0.07  0.06   1.55
ball_black             0.02   0.018 0.018 0.02   1.55
cue_ash                0.2    1.35  1.15  0.75
cue_ebony              0.1    0.05  0.04  0.035
cue_turquoise          0.1    0.1   0.8   0.75
chalk_cube             0.6    0.25  0.55  1.25
carpet_wine            0.9    0.35  0.06  0.08
carpet_gold            0.9    1.2   0.85  0.2
carpet_teal            0.9    0.06  0.45  0.42
wall_oxblood           0.5    0.62  0.14  0.12
bench_leather          0.08   0.05  0.13  0.07
# archery: target faces, bosses, lawn, a bow and arrows
face_white             0.6    1.5   1.49  1.46
face_black             0.6    0.041 0.039 0.046
face_blue              0.6    0.1   0.6   1.35
face_red               0.6    1.45  0.16  0.12
face_gold              0.6    1.55  1.3   0.15
boss_straw             0.8    1.1   0.9   0.45
stand_pine             0.5    1.0   0.7   0.38
turf_dark              0.8    0.1   0.3   0.07
turf_light             0.8    0.17  0.46  0.11
number_yellow          0.4    1.5   1.35  0.15
fletch_pink            0.3    1.5   0.2   0.7
fletch_lime            0.3    0.7   1.35  0.1
fletch_cyan            0.3    0.12  1.0   1.3
shaft_carbon           0.05   0.031 0.029 0.036
bow_riser              0.06   1.25  0.08  0.09
scoreboard_gloss       0.08   0.02  0.02  0.022
sight_alu              0.15   metal  1.6  1.0  0.6    8.3  7.0  5.8
treeline_oak           0.9    0.11  0.26  0.08
# boardgame: a ludo board, pawns, dice, chips, cards, sticks, coins on a rosewood table
tabletop_rosewood      0.05   0.11  0.045 0.03
ludo_white             0.1    1.5   1.49  1.43
ludo_red               0.1    1.42  0.09  0.1
ludo_green             0.1    0.07  0.6   0.14
ludo_yellow            0.1    1.55  1.4   0.09
ludo_blue              0.1    0.07  0.3   1.25
ludo_line              0.1    0.028 0.027 0.031
pawn_crimson               0.04   1.35  0.1   0.12
pawn_jade             0.04   0.09  0.55  0.18
pawn_amber            0.04   1.52  1.32  0.12
pawn_cobalt              0.04   0.08  0.24  1.15
dice_body             0.05   1.45  1.44  1.4
dice_pip              0.3    0.025 0.025 0.025
chip_vermilion               0.15   1.3   0.1   0.09
chip_royal              0.15   0.07  0.2   1.1
chip_forest             0.15   0.08  0.5   0.14
chip_black             0.15   0.04  0.04  0.04
chip_ivory             0.15   1.44  1.41  1.24
cardback_garnet           0.2    1.25  0.11  0.12
cardback_rule         0.2    1.48  1.47  1.42
stick_birch            0.3    1.4   1.2   0.8
stick_carmine              0.3    1.4   0.12  0.09
stick_ultramarine             0.3    0.09  0.25  1.15
stick_lemon           0.3    1.5   1.3   0.08
stick_viridian            0.3    0.08  0.55  0.12
coin_brass             0.12   metal  0.5  0.75 1.2    3.2  2.5  2.0
coin_cupronickel       0.12   metal  1.6  1.45 1.35   3.6  3.3  3.0
""")


# ---------------------------------------------------------------------------------------------
# roadworks: a street's roadworks seen from the pavement, 1.75 m up, looking along the road
# (~5 mm per pixel 5 m off, ~20 mm at 20 m): a run of red-and-white barrier boards (250 mm
# segments) along the works, receding from ~30 px a colour period near the camera through the
# lattice's 4 px to below 1 px at 35 m; a cross barrier facing the camera; traffic cones with
# silver sleeves along the lane; orange barrier netting (8 mm strands, 40 x 90 mm meshes) on
# posts; a yellow chevron sign with black chevrons (~5 px bars); a mini-excavator (yellow, dark
# cab glass, ribbed rubber tracks, a steel bucket); a pallet of 50 mm ducts seen end-on (blue,
# yellow, green, purple: ~4 px rings of hue, colour-only detail); a clay spoil heap; a steel
# road plate; a fresh patch of glossy bitumen near Brewster's angle of the bright sky ahead;
# white road paint, a kerb and pale paving; amber warning lamps (glints); the sun from behind
# on the left, the bright sky low ahead, a polarized skylight from above

ROAD_CAMERA = {"position": [-2.5, 0.0, 4.5], "look_at": [0.9, 11.5, 0.0], "up": UP,
               "focal_length_mm": 2.8, "f_number": 8}
ROAD_MESHES = ("barrier_red", "barrier_white", "barrier_foot", "traffic_orange",
               "sleeve_silver", "chevron_board", "chevron_bar", "safety_netting",
               "digger_paint", "digger_track", "cab_glass", "bucket_steel", "spoil_clay",
               "duct_water", "duct_gas", "duct_telecom", "duct_purple", "duct_bore", "road_lining",
               "amber_lens")
DUCTS = ("duct_water", "duct_gas", "duct_telecom", "duct_purple")


def barrier_run(mesh, p0, p1, seg=0.25, z=(0.85, 1.0)):
    """A barrier board from p0 to p1 (x, y) at heights z, red and white segments of seg metres,
    both faces and the top edge; black feet every 2 m with posts."""
    length = math.hypot(p1[0] - p0[0], p1[1] - p0[1])
    d = [(p1[0] - p0[0]) / length, (p1[1] - p0[1]) / length, 0.0]
    n = int(round(length / seg))
    for k in range(n):
        a = [p0[0] + d[0] * seg * k, p0[1] + d[1] * seg * k]
        b = [p0[0] + d[0] * seg * (k + 1), p0[1] + d[1] * seg * (k + 1)]
        m = mesh["barrier_red" if k % 2 == 0 else "barrier_white"]
        m.flat([[a[0], a[1], z[0]], [b[0], b[1], z[0]], [b[0], b[1], z[1]], [a[0], a[1], z[1]]])
        m.flat([[a[0], a[1], z[1]], [b[0], b[1], z[1]], [b[0], b[1], z[1] + 0.004],
                [a[0], a[1], z[1] + 0.004]])
    for k in range(int(length / 2.0) + 1):
        c = [p0[0] + d[0] * 2.0 * k, p0[1] + d[1] * 2.0 * k, 0.04]
        sc.cuboid(mesh["barrier_foot"], c, [d, cg.cross(UP, d), UP], [0.12, 0.5, 0.08])
        sl.tube(mesh["barrier_foot"], [c[0], c[1], 0.08], [c[0], c[1], z[0]], 0.02, 4)


def cone(mesh, x, y):
    """A traffic cone (750 mm, orange) with two silver sleeves on a square black base."""
    sc.cuboid(mesh["barrier_foot"], [x, y, 0.02], [X, Y, UP], [0.38, 0.38, 0.04])
    sc.loft(mesh["traffic_orange"], [x, y, 0.04], [UP, X, Y],
            [(0.0, 0.15, 0.15), (0.7, 0.03, 0.03), (0.71, 0.0, 0.0)], 14)
    for z0, z1 in ((0.3, 0.42), (0.5, 0.58)):
        r0, r1 = 0.15 - 0.12 * z0 / 0.7 + 0.002, 0.15 - 0.12 * z1 / 0.7 + 0.002
        sc.loft(mesh["sleeve_silver"], [x, y, 0.04], [UP, X, Y],
                [(z0, r0, r0), (z1, r1, r1)], 14)


def roadworks_meshes():
    rng = random.Random(11101)
    mesh = sc.meshes_for("roadworks", ROAD_MESHES, WRITER)
    # the barrier along the works' right side (x 1.9, y 3-35) and the cross barrier at y 3
    barrier_run(mesh, [1.9, 5.5], [1.9, 38.0])
    barrier_run(mesh, [1.9, 5.5], [-0.7, 5.5])
    barrier_run(mesh, [1.9, 5.5], [1.9, 38.0], 0.25, (0.3, 0.4))
    # cones along the lane, every 2.5 m
    for k in range(12):
        cone(mesh, 2.45, 6.0 + 2.5 * k)
    # amber lamps on the barrier, every 6 m
    for k in range(6):
        sc.ellipsoid(mesh["amber_lens"], [1.9, 5.5 + 6.0 * k, 1.07], [UP, X, Y],
                     [0.065, 0.09, 0.09], 10, 4)
    # orange barrier netting on the works' left side (x -0.7, y 3-20, 1 m high)
    for j in range(26):
        z = 0.05 + 0.04 * j
        if z > 1.05:
            break
        sl.strip(mesh["safety_netting"], [[-0.7, 5.5, z], [-0.7, 22.5, z]], 0.008, X)
    for k in range(int(17.0 / 0.09)):
        y = 5.5 + 0.09 * k
        sl.strip(mesh["safety_netting"], [[-0.7, y, 0.05], [-0.7, y, 1.05]], 0.008, X)
    for k in range(9):
        sl.tube(mesh["barrier_foot"], [-0.72, 5.5 + 2.1 * k, 0.0], [-0.72, 5.5 + 2.1 * k, 1.1],
                0.02, 4)
    # the chevron sign (0.9 x 0.6 m, yellow, four black chevrons 40 mm wide) facing the camera
    sc.cuboid(mesh["chevron_board"], [0.0, 8.8, 1.25], [X, Y, UP], [0.9, 0.02, 0.6])
    for k in range(4):
        xc = -0.28 + 0.16 * k
        for s in (-1, 1):
            mesh["chevron_bar"].flat([[xc, 8.788, 1.25], [xc + 0.04, 8.788, 1.25],
                                        [xc - 0.1 + 0.04, 8.788, 1.25 + s * 0.22],
                                        [xc - 0.1, 8.788, 1.25 + s * 0.22]])
    sl.tube(mesh["barrier_foot"], [0.0, 8.82, 0.0], [0.0, 8.82, 0.95], 0.025, 6)
    # the mini-excavator at (0.3, 10): tracks, body, cab, boom and bucket
    ex = [0.3, 15.0]
    for s in (-1, 1):
        tx = ex[0] + s * 0.5
        sc.loft(mesh["digger_track"], [tx, ex[1], 0.17], [Y, X, UP],
                [(-0.8, 0.0, 0.0), (-0.8, 0.13, 0.17), (0.8, 0.13, 0.17), (0.8, 0.0, 0.0)], 12)
        for k in range(32):
            y = ex[1] - 0.78 + 0.05 * k
            sc.cuboid(mesh["digger_track"], [tx, y, 0.345], [X, Y, UP], [0.26, 0.02, 0.01])
    sc.cuboid(mesh["digger_paint"], [ex[0], ex[1], 0.55], [X, Y, UP], [1.0, 1.3, 0.38])
    sc.loft(mesh["digger_paint"], [ex[0], ex[1] + 0.55, 0.55], [UP, X, Y],
            [(-0.19, 0.0, 0.0), (-0.19, 0.5, 0.28), (0.2, 0.5, 0.28), (0.2, 0.0, 0.0)], 16)
    cab = [ex[0] - 0.15, ex[1] + 0.1, 1.15]
    sc.cuboid(mesh["cab_glass"], cab, [X, Y, UP], [0.62, 0.8, 0.82])
    sc.cuboid(mesh["digger_paint"], [cab[0], cab[1], 1.58], [X, Y, UP], [0.7, 0.9, 0.05])
    for dx, dy in ((-0.31, -0.4), (0.31, -0.4), (-0.31, 0.4), (0.31, 0.4)):
        sl.tube(mesh["digger_paint"], [cab[0] + dx, cab[1] + dy, 0.74],
                [cab[0] + dx, cab[1] + dy, 1.56], 0.03, 4)
    boom = [[ex[0] + 0.3, ex[1] - 0.5, 0.8], [ex[0] + 0.3, ex[1] - 1.3, 1.7],
            [ex[0] + 0.3, ex[1] - 2.1, 0.9]]
    for a, b in zip(boom, boom[1:]):
        sl.tube(mesh["digger_paint"], a, b, 0.09, 4)
    sc.loft(mesh["bucket_steel"], [ex[0] + 0.3, ex[1] - 2.1, 0.6], [X, Y, UP],
            [(-0.22, 0.0, 0.0), (-0.22, 0.2, 0.26), (0.22, 0.2, 0.26), (0.22, 0.0, 0.0)], 8)
    # the spoil heap beside the excavator (lumpy clay)
    wob = [[rng.uniform(0.85, 1.12) for _ in range(20)] for _ in range(5)]
    sc.ellipsoid(mesh["spoil_clay"], [-0.2, 20.0, 0.0], [UP, X, Y], [0.7, 1.0, 1.6], 20, 6, wob)
    # the pallet of ducts: 6 x 5 pipes of 50 mm, 3 m long along y, ends towards the camera
    for i in range(6):
        for j in range(5):
            c = [1.2 + 0.052 * i + (0.026 if j % 2 else 0.0), 9.5, 0.16 + 0.046 * j]
            paint = DUCTS[(i + 2 * j) % 4]
            sl.tube(mesh[paint], c, cg.add(c, Y, 3.0), 0.025, 8, False)
            sc.annulus(mesh[paint], c, Y, 0.019, 0.025, 8)
            sc.annulus(mesh["duct_bore"], cg.add(c, Y, 0.01), Y, 0.0, 0.019, 8)
    # white road paint: lane line dashes and the edge line
    for k in range(8):
        y = 4.0 + 6.0 * k
        mesh["road_lining"].flat([[3.45, y, 0.002], [3.55, y, 0.002], [3.55, y + 2.0, 0.002],
                                 [3.45, y + 2.0, 0.002]])
    mesh["road_lining"].flat([[6.4, 0.0, 0.002], [6.5, 0.0, 0.002], [6.5, 60.0, 0.002],
                             [6.4, 60.0, 0.002]])
    return sc.mesh_files("roadworks", mesh)


def roadworks_parts():
    objs = [cg.ground("tarmac_dry"),
            sl.box([-3.0, 20.0, 0.06], [4.0, 60.0, 0.12], "paving_slab"),
            sl.box([-1.05, 20.0, 0.065], [0.15, 60.0, 0.13], "kerbstone_pale"),
            cg.rect([0.1, 6.9, 0.003], UP, X, [1.4, 1.4], "bitumen_fresh"),
            sl.box([0.6, 24.0, 0.01], [2.2, 1.3, 0.02], "bucket_steel"),
            sl.box([1.37, 11.0, 0.07], [0.4, 3.2, 0.14], "stand_pine")]
    for n in ROAD_MESHES:
        smooth = n in ("traffic_orange", "sleeve_silver", "amber_lens", "spoil_clay")
        objs.append(sc.mesh_obj("roadworks", n, smooth))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.55, -0.5, 0.75])),
               "irradiance_w_m2": [600, 590, 560]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.24, 0.8, 0.56])),
               "irradiance_w_m2": [70, 78, 92]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.3, 0.2, 1.0])),
               "irradiance_w_m2": [60, 70, 95], "polarization": {"linear_deg": 20, "dop": 0.3}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# pooltable: a pub's pool table seen by a player standing at its end, 1.6 m up (~2.2 mm per
# pixel at the near pockets, ~3 mm at the far ones, ~5 mm on the carpet beyond): green baize,
# eleven glossy balls of 57 mm (~20 px; solids, stripes with white ends, the black; curved hue
# edges, clipped glints of two lamps over the table), varnished mahogany rails with pearl
# diamond sights (15 mm: ~5 px), chrome corner castings, a cue lying across the cloth (a black
# butt with four pale points, turquoise rings, an ash shaft), blue chalk cubes; beyond the table
# a wine-red pub carpet printed with gold and teal lozenges on a 60 mm lattice (colour-only
# detail, ~10 px across and ~2-4 px up the frame, finer with distance), an oxblood wall and a
# glossy green leather bench; the window light low behind the table, mirrored near Brewster's
# angle by the side rails and the black ball

POOL_CAMERA = {"position": [0.75, -2.2, 1.75], "look_at": [0.0, 0.4, 0.5], "up": UP,
               "focal_length_mm": 2.8, "f_number": 8}
POOL_MESHES = ("rail_mahogany", "sight_pearl", "casting_chrome", "ball_ivory", "ball_yellow",
               "ball_blue", "ball_red", "ball_purple", "ball_orange", "ball_green",
               "ball_maroon", "cue_ash", "cue_ebony", "cue_turquoise", "carpet_gold",
               "carpet_teal", "pocket_leather")
BED_Z = 0.79
BALL_R = 0.0285
# balls: (x, y, colour, striped): the cue ball, the black, seven solids and seven stripes, a
# cluster of six still touching near the foot spot
BALLS = [(0.05, -0.55, "ball_ivory", False), (-0.12, -0.2, "ball_black", False),
         (-0.18, 0.12, "ball_yellow", True), (0.22, 0.3, "ball_blue", False),
         (-0.36, 0.38, "ball_red", False), (0.31, 0.62, "ball_purple", True),
         (-0.3, 0.72, "ball_orange", False), (0.36, -0.05, "ball_maroon", True),
         (0.0, 0.45, "ball_green", False), (0.057, 0.45, "ball_red", True),
         (0.0285, 0.4994, "ball_yellow", False), (0.0855, 0.4994, "ball_purple", False),
         (0.057, 0.5487, "ball_blue", True), (-0.0285, 0.4994, "ball_orange", True),
         (0.15, -0.32, "ball_green", True), (-0.25, -0.5, "ball_maroon", False)]


def striped_ball(mesh, c, axis, paint):
    """A stripe of a ball (the white sphere is a scene object): the band within 35 degrees of
    the equator about axis, lifted 0.4 % off the ball."""
    r = BALL_R * 1.025  # the facets' chords outside the sphere
    stations = [(r * math.sin(math.radians(a)), r * math.cos(math.radians(a)),
                 r * math.cos(math.radians(a))) for a in (-35, -20, -7, 7, 20, 35)]
    sc.loft(mesh[paint], c, sc.axes_of(axis), stations, 20)


def pooltable_meshes():
    rng = random.Random(11203)
    mesh = sc.meshes_for("pooltable", POOL_MESHES, WRITER)
    hx, hy = 0.45, 0.9  # half the bed
    # rails: mahogany tops (120 mm wide) round the cushions, pearl diamonds, chrome castings
    top = BED_Z + 0.04
    for s in (-1, 1):
        sc.cuboid(mesh["rail_mahogany"], [s * (hx + 0.11), 0.0, top - 0.05], [X, Y, UP],
                  [0.12, 2 * hy + 0.34, 0.1])
        sc.cuboid(mesh["rail_mahogany"], [0.0, s * (hy + 0.11), top - 0.05], [X, Y, UP],
                  [2 * hx, 0.12, 0.1])
        for k in (1, 2, 3, 5, 6, 7):
            y = -hy + 2 * hy * k / 8
            sc.annulus(mesh["sight_pearl"], [s * (hx + 0.11), y, top + 0.0005], UP, 0.0, 0.009,
                       4)
        for k in (1, 2, 3):
            x = -hx + 2 * hx * k / 4
            sc.annulus(mesh["sight_pearl"], [x, s * (hy + 0.11), top + 0.0005], UP, 0.0, 0.009,
                       4)
        for t in (-1, 1):
            sc.cuboid(mesh["casting_chrome"], [s * (hx + 0.1), t * (hy + 0.1), top - 0.045],
                      [X, Y, UP], [0.1, 0.1, 0.1])
    for x, y in ((-hx, -hy), (hx, -hy), (-hx, hy), (hx, hy), (-hx - 0.01, 0.0), (hx + 0.01, 0.0)):
        sc.annulus(mesh["pocket_leather"], [x, y, BED_Z + 0.001], UP, 0.0, 0.055, 12)
    # striped balls' bands and solids' number spots (white discs), each turned at random
    for x, y, paint, striped in BALLS:
        c = [x, y, BED_Z + BALL_R]
        axis = [rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)]
        if striped:
            striped_ball(mesh, c, axis, paint)
        elif paint not in ("ball_ivory",):
            a = cg.unit(axis)
            sc.annulus(mesh["ball_ivory"], cg.add(c, a, BALL_R * 1.004), a, 0.0, 0.011, 10)
    # the cue lying across the cloth: ebony butt with four ash points and turquoise rings, ash
    # shaft; its butt on the near rail
    butt, tip = [0.52, -0.62, top + 0.02], [-0.3, 0.5, BED_Z + 0.007]
    d = cg.unit([b - a for a, b in zip(butt, tip)])
    length = math.sqrt(sum((b - a) ** 2 for a, b in zip(butt, tip)))
    ax = sc.axes_of(d)

    def rad(t):
        return 0.0145 - 0.008 * t / length

    sc.loft(mesh["cue_ebony"], butt, ax, [(0.0, 0.0, 0.0), (0.0, rad(0), rad(0)),
                                          (0.55, rad(0.55), rad(0.55))], 12)
    sc.loft(mesh["cue_ash"], butt, ax, [(0.55, rad(0.55), rad(0.55)), (length, rad(length),
                                                                        rad(length)),
                                        (length, 0.0, 0.0)], 12)
    for t in (0.05, 0.06, 0.07, 0.545):
        r = rad(t) * 1.03
        sc.loft(mesh["cue_turquoise"], butt, ax, [(t, r, r), (t + 0.004, r, r)], 12)
    for k in range(4):
        phi = math.pi / 2 * k
        pts = []
        for t, w in ((0.25, 0.008), (0.53, 0.0)):
            for s in (-1, 1):
                ang = phi + s * w / rad(t)
                r = rad(t) * 1.01
                pts.append(cg.add(cg.add(cg.add(butt, d, t), ax[1], r * math.cos(ang)), ax[2],
                                  r * math.sin(ang)))
        mesh["cue_ash"].flat([pts[0], pts[1], pts[2]])
        mesh["cue_ash"].flat([pts[0], pts[2], pts[3]])
    # the carpet's lozenges: a 60 mm lattice, gold and teal in turn, beyond and beside the table
    for j in range(82):
        y = -1.2 + 0.06 * j
        for i in range(52):
            x = -1.56 + 0.06 * i + (0.03 if j % 2 else 0.0)
            if abs(x) < hx + 0.2 and abs(y) < hy + 0.19:
                continue
            m = mesh["carpet_gold" if (i + j) % 2 == 0 else "carpet_teal"]
            m.flat([[x - 0.014, y, 0.001], [x, y - 0.02, 0.001], [x + 0.014, y, 0.001],
                    [x, y + 0.02, 0.001]])
    return sc.mesh_files("pooltable", mesh)


def pooltable_parts():
    hx, hy = 0.45, 0.9
    objs = [cg.ground("carpet_wine"),
            cg.rect([0.0, 0.0, BED_Z], UP, X, [2 * hx, 2 * hy], "baize_green"),
            sl.box([0.0, 0.0, BED_Z - 0.2], [2 * hx + 0.32, 2 * hy + 0.32, 0.34],
                   "rail_mahogany"),
            cg.rect([0.0, 3.8, 1.5], [0, -1, 0], X, [6.0, 3.0], "wall_oxblood"),
            sl.box([0.0, 3.55, 0.23], [2.6, 0.5, 0.46], "bench_leather"),
            sl.box([0.0, 3.75, 0.7], [2.6, 0.1, 0.6], "bench_leather")]
    for s in (-1, 1):  # the cushions (baize)
        objs.append(sl.box([s * (hx + 0.025), 0.0, BED_Z + 0.018], [0.05, 2 * hy, 0.036],
                           "baize_green"))
        objs.append(sl.box([0.0, s * (hy + 0.025), BED_Z + 0.018], [2 * hx, 0.05, 0.036],
                           "baize_green"))
        for t in (-1, 1):
            objs.append(sl.box([s * 0.6, t * 1.05, 0.3], [0.12, 0.12, 0.6], "rail_mahogany"))
    for x, y, paint, striped in BALLS:
        objs.append(sl.sphere([x, y, BED_Z + BALL_R], BALL_R, "ball_ivory" if striped else paint))
    for x, y in ((0.5, 0.98), (-0.56, -0.4)):  # chalk cubes on the rails
        objs.append(sl.box([x, y, BED_Z + 0.052], [0.022, 0.022, 0.022], "chalk_cube"))
    for n in POOL_MESHES:
        smooth = n.startswith("ball") or n.startswith("cue")
        objs.append(sc.mesh_obj("pooltable", n, smooth))
    lights = [{"type": "point", "position": [0.0, -0.45, 1.75], "intensity_w_sr": [38, 36, 32]},
              {"type": "point", "position": [0.0, 0.45, 1.75], "intensity_w_sr": [38, 36, 32]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.1, 1.0, 0.68])),
               "irradiance_w_m2": [5, 5.4, 6.2]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.3, -0.4, 1.0])),
               "irradiance_w_m2": [24, 24, 26], "polarization": {"linear_deg": 60, "dop": 0.3}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# archery: an archery club's field seen from behind the shooting line, 1.5 m up, down the range
# (~7 mm per pixel at 10 m, ~21 mm at 30 m, ~35 mm at 50 m): four 122 cm target faces (ten
# rings of 61 mm: white, black, blue, red, gold, thin dividing lines, on straw bosses on pine
# stands, tilted back 12 degrees) at 10, 20, 30 and 50 m, so that a ring is ~9, ~4.4, ~3 and
# ~1.8 px wide and a colour's pair of rings ~18, ~9, ~6 and ~3.5 px; yellow number boards with
# black figures; six arrows in the nearest face (carbon shafts, pink, lime and cyan fletchings:
# ~2 x 7 px, colour-only detail), a ground quiver of arrows and a recurve bow (red riser, black
# gloss limbs, an aluminium sight) on a stand; a black gloss score board on an easel leaning back
# (the bright sky ahead mirrored near Brewster's angle); a mown lawn with light and dark stripes
# 1.5 m wide across the range (from ~60 px a period at 10 m through 4 px at ~40 m to below 1 px),
# white distance lines, a tree line far off; the sun from behind on the left, the bright sky
# ahead and high, a polarized skylight

ARCHERY_CAMERA = {"position": [0.0, 0.0, 1.5], "look_at": [0.0, 30.0, 0.9], "up": UP,
                  "focal_length_mm": 5.0, "f_number": 8}
ARCHERY_MESHES = ("face_white", "face_black", "face_blue", "face_red", "face_gold",
                  "boss_straw", "stand_pine", "turf_light", "number_yellow", "fletch_pink",
                  "fletch_lime", "fletch_cyan", "shaft_carbon", "bow_riser", "sight_alu",
                  "road_lining")
TARGETS = [(-1.0, 10.0, 1), (1.25, 20.0, 2), (4.1, 30.0, 3), (-0.1, 50.0, 4)]
RINGS = ("face_gold", "face_gold", "face_red", "face_red", "face_blue", "face_blue",
         "face_black", "face_black", "face_white", "face_white")
TILT = math.radians(12)
# the figures on the number boards as strokes in a 2 x 3 box (x, y from the top left)
FIGURES = {1: [((1, 0), (1, 3))], 2: [((0, 0), (2, 0)), ((2, 0), (2, 1.5)), ((2, 1.5), (0, 1.5)),
                                      ((0, 1.5), (0, 3)), ((0, 3), (2, 3))],
           3: [((0, 0), (2, 0)), ((2, 0), (2, 3)), ((0, 1.5), (2, 1.5)), ((0, 3), (2, 3))],
           4: [((0, 0), (0, 1.5)), ((0, 1.5), (2, 1.5)), ((1.6, 0), (1.6, 3))]}


def target(mesh, x, y, number, n):
    """A target at (x, y): a straw boss (1.25 m across, 0.3 m thick) on a pine stand, tilted
    back by TILT, its face's ten rings and dividing lines (n segments a ring), and a number
    board above it."""
    c = [x, y, 1.3]
    normal = [0.0, -math.cos(TILT), math.sin(TILT)]
    back = cg.add(c, normal, -0.3)
    sc.loft(mesh["boss_straw"], back, sc.axes_of(normal),
            [(0.0, 0.0, 0.0), (0.0, 0.625, 0.625), (0.3, 0.625, 0.625), (0.3, 0.0, 0.0)], 2 * n)
    face = cg.add(c, normal, 0.002)
    for k, paint in enumerate(RINGS):
        sc.annulus(mesh[paint], face, normal, 0.061 * k, 0.061 * (k + 1), n, phase=90)
    for k in range(1, 10):
        line = "face_white" if RINGS[k] == "face_black" else "face_black"
        sc.annulus(mesh[line], cg.add(face, normal, 0.001), normal, 0.061 * k - 0.0015,
                   0.061 * k + 0.0015, n, phase=90)
    for dx in (-0.5, 0.5):
        sl.tube(mesh["stand_pine"], [x + dx, y + 0.25, 0.0], [x + dx * 0.6, y - 0.05, 1.95],
                0.035, 4)
    sl.tube(mesh["stand_pine"], [x, y + 1.0, 0.0], [x, y + 0.1, 1.8], 0.035, 4)
    board = cg.add(c, UP, 0.95)
    sc.cuboid(mesh["number_yellow"], board, [X, normal, UP], [0.3, 0.02, 0.36])
    front = cg.add(board, normal, 0.012)
    for (a, b), (p, q) in FIGURES[number]:
        pa = cg.add(cg.add(front, X, -0.08 + 0.08 * a), UP, 0.12 - 0.08 * b)
        pb = cg.add(cg.add(front, X, -0.08 + 0.08 * p), UP, 0.12 - 0.08 * q)
        sl.strip(mesh["face_black"], [pa, pb], 0.035, normal)


def arrow(mesh, tip, d, length, fletch):
    """An arrow from its tip at `tip` back along d: a carbon shaft, three vanes (fletch) and a
    nock."""
    d = cg.unit(d)
    nock = cg.add(tip, d, length)
    sl.tube(mesh["shaft_carbon"], tip, nock, 0.0035, 5, False)
    u, v = sl.frame(d)
    for k in range(3):
        a = 2 * math.pi * k / 3
        w = cg.add([x * math.cos(a) for x in u], v, math.sin(a))
        p0, p1 = cg.add(nock, d, -0.11), cg.add(nock, d, -0.03)
        mesh[fletch].flat([p0, p1, cg.add(p1, w, 0.014), cg.add(p0, w, 0.004)])
    sc.ellipsoid(mesh[fletch], cg.add(nock, d, 0.005), sc.axes_of(d), [0.008, 0.004, 0.004], 6,
                 2)


def archery_meshes():
    rng = random.Random(11307)
    mesh = sc.meshes_for("archery", ARCHERY_MESHES, WRITER)
    for x, y, number in TARGETS:
        target(mesh, x, y, number, 48 if y < 25 else 32)
    # mown stripes across the range: light bands 1.5 m wide every 3 m
    for k in range(30):
        y = 7.5 + 3.0 * k
        mesh["turf_light"].flat([[-40.0, y, 0.0005], [40.0, y, 0.0005], [40.0, y + 1.5, 0.0005],
                                 [-40.0, y + 1.5, 0.0005]])
    for y in (10.0, 20.0, 30.0, 50.0):  # distance lines (50 mm white)
        sl.strip(mesh["road_lining"], [[-20.0, y - 1.0, 0.001], [20.0, y - 1.0, 0.001]], 0.05, UP)
    # six arrows in the nearest face
    x0, y0, _ = TARGETS[0]
    fletches = ("fletch_pink", "fletch_lime", "fletch_cyan")
    normal = [0.0, -math.cos(TILT), math.sin(TILT)]
    for k in range(6):
        a, r = rng.uniform(0, 2 * math.pi), rng.uniform(0.02, 0.25)
        tip = cg.add(cg.add([x0, y0, 1.3], X, r * math.cos(a)), UP, r * math.sin(a))
        d = cg.add(normal, [rng.gauss(0, 0.05), 0.0, rng.gauss(0, 0.05)])
        arrow(mesh, tip, d, 0.62, fletches[k % 3])
    # a ground quiver of eight arrows (tips in the ground) and the bow on its stand, at 11 m
    q = [1.5, 11.2, 0.0]
    sl.tube(mesh["sight_alu"], q, cg.add(q, UP, 0.55), 0.008, 6)
    for k in range(8):
        d = [rng.gauss(0, 0.12), rng.gauss(0, 0.12), 1.0]
        arrow(mesh, cg.add(q, [0.03 * math.cos(k), 0.03 * math.sin(k), 0.0], 0.0), d, 0.7,
              fletches[(k + 1) % 3])
    b = [0.55, 11.6, 0.0]
    for dx, dy in ((-0.2, 0.1), (0.2, 0.1), (0.0, -0.22)):
        sl.tube(mesh["sight_alu"], [b[0] + dx, b[1] + dy, 0.0], [b[0], b[1], 0.5], 0.008, 5)
    grip = [b[0], b[1], 0.95]
    sc.loft(mesh["bow_riser"], cg.add(grip, UP, -0.3), [UP, X, Y],
            [(0.0, 0.0, 0.0), (0.0, 0.02, 0.014), (0.25, 0.025, 0.02), (0.35, 0.018, 0.014),
             (0.6, 0.02, 0.016), (0.6, 0.0, 0.0)], 10)
    for s in (-1, 1):
        limb = [cg.add(grip, [0.0, 0.08 * (t ** 2), s * (0.3 + 0.5 * t)], 1.0)
                for t in [k / 10 for k in range(11)]]
        sc.sweep(mesh["shaft_carbon"], limb, 0.014, 6)
    sl.tube(mesh["shaft_carbon"], [b[0], b[1] + 0.08, 0.15], [b[0], b[1] + 0.08, 1.75], 0.0015, 4)
    sl.tube(mesh["sight_alu"], cg.add(grip, UP, 0.12), [b[0], b[1] - 0.25, 1.07], 0.006, 5)
    sl.tube(mesh["shaft_carbon"], cg.add(grip, UP, -0.1), [b[0], b[1] - 0.7, 0.8], 0.008, 6)
    return sc.mesh_files("archery", mesh)


def archery_parts():
    objs = [cg.ground("turf_dark"),
            sl.box([0.0, 140.0, 3.5], [300.0, 6.0, 7.0], "treeline_oak")]
    # the score board on its easel, leaning back 56 degrees from the vertical
    a = math.radians(56)
    objs.append({"type": "box", "center": [-1.55, 12.0, 0.45], "size": [0.9, 0.02, 0.6],
                 "rotation_deg": [-56.0, 0.0, 0.0], "material": "scoreboard_gloss"})
    objs.append(sl.box([-1.55, 12.0 + 0.3 * math.sin(a) + 0.05, 0.25], [0.04, 0.04, 0.5],
                       "stand_pine"))
    for k in range(12):  # lone trees along the tree line
        x = -33.0 + 6.0 * k
        objs.append(sl.sphere([x, 147.0 - 2.0 * (k % 3), 7.5 + 0.7 * (k % 4)], 3.0 + 0.5 * (k % 3),
                              "treeline_oak"))
    for n in ARCHERY_MESHES:
        smooth = n in ("boss_straw", "bow_riser", "shaft_carbon")
        objs.append(sc.mesh_obj("archery", n, smooth))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([-0.6, -0.55, 0.6])),
               "irradiance_w_m2": [640, 620, 580]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.13, 0.29, 0.95])),
               "irradiance_w_m2": [38, 43, 53]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.7, 0.2, 0.7])),
               "irradiance_w_m2": [50, 58, 75], "polarization": {"linear_deg": 80, "dop": 0.4}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# boardgame: a games night's table seen from a chair, 0.42 m above it (~0.55 mm per pixel at the
# bottom of the frame, ~0.8 mm at the top): a glossy ludo board (15 x 15 cells of 16 mm: ~25 px,
# red, green, yellow and blue yards and home columns, black grid lines of 0.8 mm: ~1.3 px, thin
# dark bars on saturated grounds), glossy pawns, two white dice with black pips and a red one
# with white pips, four stacks of clay poker chips (3.3 mm thick: ~5 px a chip, colours in turn
# up a stack: colour-only stripes; white edge inserts), a fan of four playing cards with red
# backs ruled in white every 2.5 mm (~4 px, turned to four angles), pick-up sticks of 3 mm
# (~5 px) banded red, blue, yellow and green (bands of 4-12 mm receding), a pile of brass and
# cupro-nickel coins; a lacquered rosewood table mirroring the window behind near Brewster's
# angle, a lamp overhead (glints), the window light (polarized 0.3)

BOARD_CAMERA = {"position": [0.03, -0.36, 0.42], "look_at": [0.0, 0.06, 0.0], "up": UP,
                "focal_length_mm": 3.2, "f_number": 8}
LUDO = ("ludo_red", "ludo_green", "ludo_yellow", "ludo_blue")
PAWNS = ("pawn_crimson", "pawn_jade", "pawn_amber", "pawn_cobalt")
CHIPS = ("chip_vermilion", "chip_royal", "chip_forest", "chip_black", "chip_ivory")
STICKS = ("stick_carmine", "stick_ultramarine", "stick_lemon", "stick_viridian")
BOARD_MESHES = LUDO + PAWNS + CHIPS + STICKS + ("ludo_white", "ludo_line", "dice_body",
                                                "dice_pip", "cardback_garnet", "cardback_rule",
                                                "stick_birch", "coin_brass", "coin_cupronickel")
CELL = 0.016
BOARD_C = [-0.045, 0.07, 0.004]
BOARD_ROT = math.radians(8)


def board_at(i, j, h=0.0):
    """The point (i, j) cells from the ludo board's corner, h above its face."""
    u = [math.cos(BOARD_ROT), math.sin(BOARD_ROT), 0.0]
    v = [-math.sin(BOARD_ROT), math.cos(BOARD_ROT), 0.0]
    p = cg.add(cg.add(BOARD_C, u, (i - 7.5) * CELL), v, (j - 7.5) * CELL)
    return [p[0], p[1], BOARD_C[2] + 0.0005 + h]


def cell(mesh, i, j, w=1, h=1, lift=0.0):
    mesh.flat([board_at(i, j, lift), board_at(i + w, j, lift), board_at(i + w, j + h, lift),
               board_at(i, j + h, lift)])


def ludo(mesh):
    """The board's print: yards (6 x 6 cells with a white 4 x 4 and four coloured spots),
    home columns, start cells, the centre's four triangles and the track's grid lines."""
    yards = ((0, 0), (9, 0), (9, 9), (0, 9))
    for k, (i, j) in enumerate(yards):
        paint = mesh[LUDO[k]]
        cell(paint, i, j, 6, 6)
        cell(mesh["ludo_white"], i + 1, j + 1, 4, 4, 0.0001)
        for a, b in ((2, 2), (4, 2), (2, 4), (4, 4)):
            sc.annulus(paint, board_at(i + a, j + b, 0.0002), UP, 0.0, 0.6 * CELL, 16)
    cell(mesh["ludo_white"], 6, 0, 3, 15)
    cell(mesh["ludo_white"], 0, 6, 15, 3)
    for k in range(1, 6):  # home columns and start cells
        cell(mesh["ludo_red"], 7, k, lift=0.0001)
        cell(mesh["ludo_green"], 14 - k, 7, lift=0.0001)
        cell(mesh["ludo_yellow"], 7, 14 - k, lift=0.0001)
        cell(mesh["ludo_blue"], k, 7, lift=0.0001)
    cell(mesh["ludo_red"], 8, 1, lift=0.0001)
    cell(mesh["ludo_green"], 13, 8, lift=0.0001)
    cell(mesh["ludo_yellow"], 6, 13, lift=0.0001)
    cell(mesh["ludo_blue"], 1, 6, lift=0.0001)
    mid = board_at(7.5, 7.5, 0.0002)
    corners = [board_at(6, 6, 0.0002), board_at(9, 6, 0.0002), board_at(9, 9, 0.0002),
               board_at(6, 9, 0.0002)]
    for k, paint in enumerate(("ludo_red", "ludo_green", "ludo_yellow", "ludo_blue")):
        mesh[paint].flat([corners[k], corners[(k + 1) % 4], mid])
    line = mesh["ludo_line"]
    w = 0.0008
    for k in range(16):  # grid lines over the two arms of the cross
        full = 6 <= k <= 9
        sl.strip(line, [board_at(k, 0 if full else 6, 0.0003), board_at(k, 15 if full else 9,
                                                                       0.0003)], w, UP)
        sl.strip(line, [board_at(0 if full else 6, k, 0.0003), board_at(15 if full else 9, k,
                                                                       0.0003)], w, UP)
    for k in range(4):
        sl.strip(line, [corners[k], corners[(k + 2) % 4]], w, UP)


def chip(mesh, c, paint, phase):
    """A clay poker chip (39 mm, 3.3 mm thick) at c (its bottom face's centre), its top face
    and its edge in paint, six white edge inserts."""
    r, t = 0.0195, 0.0033
    sc.loft(mesh[paint], c, [UP, X, Y], [(0.0, r, r), (t, r, r)], 24, phase)
    sc.annulus(mesh[paint], cg.add(c, UP, t), UP, 0.0, r, 24)
    for k in range(6):
        a = phase + 2 * math.pi * k / 6
        pts = []
        for da in (-0.2, 0.2):
            e = [math.cos(a + da), math.sin(a + da), 0.0]
            pts.append(cg.add(c, e, r * 1.003))
        mesh["chip_ivory"].flat([pts[0], pts[1], cg.add(pts[1], UP, t), cg.add(pts[0], UP, t)])


def die(mesh, c, yaw, body, pip):
    """A die of 16 mm at c (its centre), turned by yaw about the vertical: pips on the top (5)
    and the two sides towards the camera (2 and 3)."""
    f = [math.cos(yaw), math.sin(yaw), 0.0]
    s = cg.cross(UP, f)
    sc.cuboid(mesh[body], c, [f, s, UP], [0.016, 0.016, 0.016])
    faces = ((UP, f, s, ((0, 0), (-1, -1), (1, 1), (-1, 1), (1, -1))),
             ([-x for x in s], f, UP, ((-1, -1), (1, 1))),
             ([-x for x in f], s, UP, ((0, 0), (-1, -1), (1, 1))))
    for n, a, b, spots in faces:
        for p, q in spots:
            centre = cg.add(cg.add(cg.add(c, n, 0.0081), a, 0.0045 * p), b, 0.0045 * q)
            sc.annulus(mesh[pip], centre, n, 0.0, 0.0016, 8)


def boardgame_meshes():
    rng = random.Random(11409)
    mesh = sc.meshes_for("boardgame", BOARD_MESHES, WRITER)
    ludo(mesh)
    # pawns: a cone with a ball head, two of each colour
    for k in range(8):
        i, j = [(7.5, 2.5), (2.5, 2.5), (12.5, 7.5), (11.5, 11.5), (7.5, 12.5), (3.5, 12.5),
                (1.5, 7.5), (10.5, 3.5)][k]
        p = board_at(i, j)
        paint = PAWNS[k // 2]
        sc.loft(mesh[paint], p, [UP, X, Y], [(0.0, 0.0, 0.0), (0.0, 0.007, 0.007),
                                             (0.003, 0.007, 0.007), (0.017, 0.0035, 0.0035),
                                             (0.018, 0.0, 0.0)], 14)
        sc.ellipsoid(mesh[paint], cg.add(p, UP, 0.021), [UP, X, Y], [0.0045, 0.0045, 0.0045], 10,
                     5)
    # dice beside the board
    die(mesh, [0.11, -0.02, 0.008], 0.4, "dice_body", "dice_pip")
    die(mesh, [0.135, 0.005, 0.008], -0.3, "dice_body", "dice_pip")
    die(mesh, [0.095, 0.025, 0.008], 1.0, "chip_vermilion", "dice_body")
    # four stacks of chips to the right of the board (colours in turn up each stack)
    for s, (x, y, n) in enumerate(((0.11, 0.08, 11), (0.152, 0.095, 8), (0.125, 0.125, 14),
                                   (0.165, 0.05, 6))):
        for k in range(n):
            paint = CHIPS[(k + s) % 4] if (k + 2 * s) % 5 else "chip_ivory"
            chip(mesh, [x + rng.uniform(-0.0008, 0.0008), y + rng.uniform(-0.0008, 0.0008),
                        0.0033 * k], paint, rng.uniform(0, 1))
    # a fan of four cards (63 x 88 mm) face down at the front left, red backs ruled in white
    for k in range(4):
        ang = math.radians(-30 + 17 * k)
        u, v = [math.cos(ang), math.sin(ang), 0.0], [-math.sin(ang), math.cos(ang), 0.0]
        o = [-0.13 + 0.012 * k, -0.085, 0.0003 + 0.0004 * k]

        def at(a, b, h=0.0):
            p = cg.add(cg.add(o, u, a), v, b)
            return [p[0], p[1], p[2] + h]

        mesh["cardback_rule"].flat([at(-0.0315, 0.0), at(0.0315, 0.0), at(0.0315, 0.088),
                                     at(-0.0315, 0.088)])
        mesh["cardback_garnet"].flat([at(-0.0275, 0.004, 0.0001), at(0.0275, 0.004, 0.0001),
                                   at(0.0275, 0.084, 0.0001), at(-0.0275, 0.084, 0.0001)])
        for q in range(21):
            a = -0.025 + 0.0025 * q
            sl.strip(mesh["cardback_rule"], [at(a, 0.006, 0.0002), at(a, 0.082, 0.0002)],
                     0.001, UP)
    # pick-up sticks (3 mm, 180 mm) crossing at the front right, banded in colour
    for k in range(10):
        c = [0.06 + rng.uniform(-0.03, 0.03), -0.075 + rng.uniform(-0.02, 0.02), 0.0015 + 0.003 *
             (k % 3)]
        ang = rng.uniform(0, math.pi)
        d = [math.cos(ang), math.sin(ang), 0.0]
        colour = STICKS[k % 4]
        marks = [(-0.09, -0.075, "stick_birch"), (-0.075, -0.06, colour),
                 (-0.06, -0.055, "stick_birch"), (-0.055, -0.05, STICKS[(k + 1) % 4]),
                 (-0.05, 0.05, "stick_birch"), (0.05, 0.055, STICKS[(k + 1) % 4]),
                 (0.055, 0.06, "stick_birch"), (0.06, 0.075, colour),
                 (0.075, 0.09, "stick_birch")]
        for a, b, paint in marks:
            sl.tube(mesh[paint], cg.add(c, d, a), cg.add(c, d, b), 0.0015, 6,
                    a == -0.09 or b == 0.09)
    # coins: a small pile of brass and cupro-nickel coins (22-25 mm)
    for k in range(9):
        c = [-0.14 + rng.uniform(-0.015, 0.015), 0.11 + rng.uniform(-0.015, 0.015),
             0.0045 + 0.0018 * k]
        paint = ("coin_brass", "coin_cupronickel")[k % 2]
        r = 0.011 + 0.0015 * (k % 3)
        nrm = cg.unit([rng.gauss(0, 0.05), rng.gauss(0, 0.05), 1.0])
        sc.loft(mesh[paint], c, sc.axes_of(nrm), [(0.0, 0.0, 0.0), (0.0, r, r), (0.0017, r, r),
                                                  (0.0017, 0.0, 0.0)], 16)
    return sc.mesh_files("boardgame", mesh)


def boardgame_parts():
    objs = [cg.ground("tabletop_rosewood"),
            sl.box([BOARD_C[0], BOARD_C[1], 0.002], [0.25, 0.25, 0.004], "ludo_white",
                   math.degrees(BOARD_ROT))]
    for n in BOARD_MESHES:
        smooth = n.startswith("pawn") or n.startswith("coin")
        objs.append(sc.mesh_obj("boardgame", n, smooth))
    lights = [{"type": "point", "position": [-0.1, 0.0, 0.9], "intensity_w_sr": [9, 8.6, 7.8]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.05, 1.0, 0.66])),
               "irradiance_w_m2": [2.5, 2.6, 3.0]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.4, -0.3, 1.0])),
               "irradiance_w_m2": [4, 4, 4.4], "polarization": {"linear_deg": 30, "dop": 0.3}}]
    return MATERIALS, objs, lights


SCENES = sc.scene_set(TITLE, EXPOSURE, {
    "roadworks": (roadworks_parts, ROAD_CAMERA, "roadworks in a street seen from the pavement "
                  "(a red-and-white barrier run receding, traffic cones with silver sleeves, "
                  "orange barrier netting, a yellow chevron sign, a mini-excavator, a pallet "
                  "of coloured ducts end-on, a spoil heap, a steel road plate, fresh bitumen, "
                  "road paint, a kerb and paving)", None),
    "pooltable": (pooltable_parts, POOL_CAMERA, "a pub's pool table seen by a standing player "
                  "(green baize, glossy solid and striped balls, mahogany rails with pearl "
                  "sights, chrome castings, a cue, chalk; a patterned carpet, an oxblood wall "
                  "and a leather bench beyond)", None),
    "archery": (archery_parts, ARCHERY_CAMERA, "an archery range seen from behind the shooting "
                "line (target faces at 10, 20, 30 and 50 m on straw bosses, number boards, "
                "arrows, a ground quiver, a recurve bow on a stand, a gloss score board, a "
                "striped mown lawn, a tree line)", [14, 18, 28]),
    "boardgame": (boardgame_parts, BOARD_CAMERA, "a games night's table (a ludo board with "
                  "pawns, dice, stacks of poker chips, a fan of playing cards, pick-up sticks, "
                  "coins) on a lacquered rosewood table", None),
}, {
    "archery_g10": ("archery", 10, "a fast shutter on an overcast afternoon"),
    "pooltable_g19": ("pooltable", 19, "a dim pub, handheld"),
})


def meshes():
    """Every mesh of the set: file name -> OBJ text (each *_meshes gives name -> sl.Mesh)."""
    makers = (roadworks_meshes, pooltable_meshes, archery_meshes, boardgame_meshes)
    return {name + ".obj": mesh.text() for make in makers for name, mesh in make().items()}


cg.write_all(HERE, SCENES, meshes, sys.argv)
