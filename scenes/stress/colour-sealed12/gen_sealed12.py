#!/usr/bin/env python3
"""Writes the twelfth sealed colour set (README.md beside this file) and its meshes.

Python 3 standard library only; deterministic (fixed-seed random.Random): `python3
gen_sealed12.py` in this directory rewrites every .json and .obj here (the files are checked in,
this is how they were made). `python3 gen_sealed12.py --print NAME` prints one scene instead.
Every generic helper is imported: ../sealed_common.py (outside the sealed directories: lofts,
ellipsoids, boxes as facets, smooth patches, flat rings, the materials table, the mesh files of
a scene and their objects, the scene records with their noisy copies, and, added with this set,
flat rectangles), which re-exports ../colour-sealed6/sealed_lib.py (`sl`:
millimetre meshes, tubes, ribbons, mesh objects, boxes, spheres; read, never written) and
../colour_gen.py (`cg`: the colour sensor, the scene record, rect, vectors, the writer). Nothing
here is a copy of an earlier generator's helper; what is below builds this set's own things (a
bowling alley, a laboratory bench, a recording studio's mixing console, a campsite).

Paints are dielectrics coloured by per-channel extinction coefficients k = [R, G, B] (n = 1.5
unless stated): a channel with k ~ 1.3-1.8 scatters back brightly, one with k ~ 0.03 hardly at
all (../colour/gen_colour.py). The metals (the ball return's chrome rails, the bench's steel
tray and spatula, the console's satin steel fader caps and nickel jack sockets, the campsite's
steel stove and aluminium kettle and pegs) are assumed metals of the right order (n - ik per
channel at 610, 530 and 465 nm, from memory, not a table lookup). A glossy surface mirrors a
light near Brewster's angle with a degree of polarization near 1 only where its k is small
(dark or black: the ball return's hood and the dark balls, the bench's black epoxy top, the
studio monitors' piano-black cabinets and the console's armrest, the kayak's dark hull and the
cool box's lid); a paint of large k reflects less polarized light. None of the paints, meshes,
cameras or layouts of the other colour sets is reused (nor a paint's or metal's name, nor a
paint's k).

Units: metres in the scenes, millimetres in the OBJ files (sl.Mesh; each mesh object has scale
0.001). A mesh placed with `smooth` false shows every facet flat; lofts and ellipsoids share
their vertices, and placed with `smooth` true the loader's area-weighted normals round them. The
set's materials are one text table (MATERIALS); each scene's record names those its objects use.

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
WRITER = "gen_sealed12.py"
TITLE = "colour sealed 12: "
UP = [0, 0, 1]
X, Y = [1, 0, 0], [0, 1, 0]

# exposure per scene, us (set from the rendered raw frames: see the module docstring)
EXPOSURE = {
    "bowling": 22000,
    "labbench": 18000,
    "console": 26000,
    "campsite": 1600,
    "campsite_g11": 451,
    "bowling_g16": 3487,
}

# every material of the set (sc.materials: paints `name sigma k_R k_G k_B [n]`, n 1.5 unless
# given; metals `name sigma metal n_R n_G n_B k_R k_G k_B`); each scene's record keeps those
# its objects use
MATERIALS = sc.materials("""
# bowling: lacquered lanes, gutters, pins, balls, a ball return, masking panels
approach_maple         0.06   1.38  1.12  0.72
board_sapwood          0.1    1.44  1.2   0.8
board_heartwood        0.1    1.24  0.93  0.56
dowel_walnut           0.1    0.09  0.05  0.035
gutter_shadow          0.3    0.034 0.033 0.038
capping_cream          0.2    1.41  1.37  1.21
kickback_indigo        0.3    0.16  0.12  0.95
pinstripe_jet          0.3    0.027 0.026 0.03
pindeck_plum           0.5    0.05  0.03  0.06
pin_enamel             0.05   1.53  1.52  1.47
neck_scarlet           0.05   1.38  0.085 0.07
mask_tangerine         0.3    1.54  0.62  0.06
mask_magenta           0.3    1.3   0.11  0.72
mask_cyan              0.3    0.08  0.95  1.28
mask_chartreuse        0.3    1.05  1.42  0.09
hood_gloss             0.03   0.024 0.022 0.026   1.52
rail_chrome            0.05   metal  2.95 2.85 2.65   3.7  3.6  3.4
bowl_violet            0.02   0.5   0.08  0.95   1.55
bowl_coral             0.02   1.48  0.36  0.22   1.55
bowl_petrol            0.02   0.05  0.3   0.42   1.55
bowl_onyx              0.02   0.032 0.027 0.035   1.55
bowl_lilac             0.02   1.1   0.7   1.3    1.55
carpet_navy            0.9    0.07  0.08  0.2
# labbench: black epoxy top, plates, tip boxes, Petri dishes, a ruler, steel
epoxy_black            0.04   0.016 0.017 0.019
splash_tile            0.3    1.32  1.34  1.33
plate_polystyrene      0.2    1.46  1.46  1.44
dye_crystalviolet      0.15   0.5   0.06  0.9
dye_phenolred          0.15   1.35  0.2   0.26
dye_bromothymol        0.15   0.1   0.62  1.0
dye_tartrazine         0.15   1.5   1.34  0.07
dye_malachite          0.15   0.08  0.72  0.38
tipbox_azure           0.4    0.12  0.5   1.22
tip_straw              0.2    1.5   1.36  0.38
cap_rose               0.1    1.45  0.3   0.6
cap_mint               0.1    0.35  1.2   0.55
cap_sky                0.1    0.32  0.82  1.36
cap_apricot            0.1    1.5   0.8   0.3
agar_blood             0.3    0.85  0.07  0.06
agar_chocolate         0.3    0.46  0.21  0.08
agar_macconkey         0.3    1.0   0.14  0.5
agar_sabouraud         0.3    1.3   1.08  0.45
colony_cream           0.3    1.45  1.36  1.05
ruler_yellow           0.15   1.53  1.38  0.13
tick_black             0.15   0.03  0.029 0.033
tray_steel             0.35   metal  2.55 2.45 2.25   3.25 3.15 2.95
# console: channel strips, knobs, faders, meters, monitors, an armrest
panel_graphite         0.4    0.092 0.088 0.1
strip_slate            0.4    0.22  0.24  0.28
knob_scarlet           0.2    1.32  0.12  0.1
knob_azure             0.2    0.1   0.4   1.25
knob_emerald           0.2    0.07  0.65  0.22
knob_saffron           0.2    1.5   1.15  0.1
knob_ash               0.2    0.56  0.55  0.53
slot_black             0.5    0.022 0.022 0.024
fadercap_steel         0.35   metal  2.3  2.2  2.05   2.9  2.8  2.6
jack_nickel            0.15   metal  1.9  1.75 1.6   3.5  3.3  3.05
meter_green            0.1    0.12  1.45  0.25
meter_amber            0.1    1.55  0.95  0.05
meter_red              0.1    1.48  0.1   0.13
scribble_tape          0.5    1.46  1.44  1.3
marker_ink             0.5    0.032 0.03  0.04
monitor_piano          0.02   0.019 0.018 0.02    1.52
armrest_vinyl          0.12   0.045 0.04  0.04
studio_floor           0.5    0.55  0.32  0.18
# campsite: tents, guy lines, a windbreak, a kayak, a cool box, a stove, a field
field_meadow           0.8    0.14  0.36  0.09
track_gravel           0.7    0.72  0.66  0.55
fly_tomato             0.2    1.4   0.22  0.1
fly_olive              0.2    0.5   0.55  0.12
fly_turquoise          0.2    0.08  0.85  0.9
fly_mustard            0.2    1.45  1.05  0.12
fly_navy               0.2    0.07  0.12  0.55
door_charcoal          0.3    0.07  0.068 0.078
zip_black              0.3    0.025 0.024 0.027
guyline_white          0.3    1.44  1.42  1.38
windbreak_red          0.4    1.32  0.15  0.21
windbreak_blue         0.4    0.14  0.28  1.15
windbreak_yellow       0.4    1.52  1.4   0.2
kayak_hull             0.03   0.03  0.05  0.07   1.52
coolbox_lid            0.04   0.06  0.05  0.16   1.52
coolbox_white          0.2    1.42  1.42  1.38
stove_steel            0.2    metal  2.45 2.35 2.2    3.1  3.0  2.85
kettle_alu             0.1    metal  1.5  0.9  0.58   8.1  6.9  5.7
hedge_hawthorn         0.9    0.08  0.22  0.06
""")


# ---------------------------------------------------------------------------------------------
# bowling: a bowling alley seen from the concourse behind the approach, 1.8 m up, looking down
# five lanes (~8 mm per pixel at the ball return, ~11 mm at the foul line, ~42 mm at the pins
# 24 m off): lacquered maple lanes of 39 boards of 27 mm in two tones (a two-board period of
# ~5 px at the foul line, ~2 px at 20 m), walnut dowel arrows and dots, a black foul
# line, dark gutters, cream cappings, indigo kickbacks with thin black pinstripes, pins with
# two scarlet neck stripes (~1 px: colour-only detail), masking panels over the pin decks
# printed with colour stripes of 240, 160, 100 and 60 mm (~5.5, ~3.6, ~2.3, ~1.4 px a period),
# a ball return between the middle lanes (a piano-black hood, chrome rails, glossy balls with
# clipped glints); lamps over the approach and lanes mirrored by the lanes' lacquer and the
# hood, a polarized fill, a dark void above

BOWL_CAMERA = {"position": [0.45, -6.0, 1.8], "look_at": [0.2, 6.0, 0.0], "up": UP,
               "focal_length_mm": 2.0, "f_number": 8}
LANE_W = 1.066
LANE_PITCH = 1.62
LANE_LEN = 18.3
MASKS = ("mask_tangerine", "mask_magenta", "mask_cyan", "mask_chartreuse")
BOWL_MESHES = ("board_sapwood", "board_heartwood", "dowel_walnut", "pinstripe_jet",
               "pin_enamel", "neck_scarlet", "hood_gloss", "rail_chrome",
               "kickback_indigo") + MASKS


def stripes(mesh_a, mesh_b, o, u, v, width, height, period):
    """A panel from o along u (width) and v (height), in stripes of `period` along u: the
    first half of each period in mesh_a, the second in mesh_b (either may be None)."""
    k = 0
    while k * period / 2 < width - 1e-9:
        a, b = k * period / 2, min((k + 1) * period / 2, width)
        m = (mesh_a, mesh_b)[k % 2]
        if m is not None:
            sc.rectangle(m, cg.add(o, u, a), u, v, b - a, height)
        k += 1


def pin(mesh, c):
    """A bowling pin (380 mm, 121 mm at the belly) standing at c, two scarlet neck stripes."""
    prof = [(0.0, 0.0), (0.0, 0.026), (0.06, 0.055), (0.11, 0.06), (0.2, 0.04), (0.25, 0.023),
            (0.3, 0.028), (0.35, 0.028), (0.375, 0.014), (0.381, 0.0)]
    sc.loft(mesh["pin_enamel"], c, [UP, X, Y], [(h, r, r) for h, r in prof], 8)
    for h in (0.245, 0.265):
        r = 0.0248 * 1.04
        sc.loft(mesh["neck_scarlet"], c, [UP, X, Y], [(h, r, r), (h + 0.01, r, r)], 8)


def bowling_meshes():
    rng = random.Random(12101)
    mesh = sc.meshes_for("bowling", BOWL_MESHES, WRITER)
    board = LANE_W / 39
    for lane in range(-2, 3):
        x0 = lane * LANE_PITCH - LANE_W / 2
        # the lane's boards in two tones (sapwood / heartwood) from the foul line to the pins
        stripes(mesh["board_sapwood"], mesh["board_heartwood"], [x0, 0.0, 0.0], X, Y,
                LANE_W, LANE_LEN + 0.6, 2 * board)
        # arrows at 4.6 m (every fifth board) and dots at 2.1 m
        for k in (5, 10, 15, 20, 25, 30, 35):
            x = x0 + (k - 0.5) * board
            y = 4.3 + 0.15 * abs(k - 20) / 5
            mesh["dowel_walnut"].flat([[x - 0.012, y, 0.001], [x + 0.012, y, 0.001],
                                       [x, y + 0.15, 0.001]])
            sc.annulus(mesh["dowel_walnut"], [x, 2.1, 0.001], UP, 0.0, 0.009, 6)
        sc.rectangle(mesh["pinstripe_jet"], [x0, -0.005, 0.001], X, Y, LANE_W, 0.01)
        # the pins: a full rack on the middle three lanes, a leave of four on the outer two
        spots = [(r, i) for r in range(4) for i in range(r + 1)]
        if abs(lane) == 2:
            spots = [spots[i] for i in (3, 5, 6, 9)]
        for r, i in spots:
            pin(mesh, [lane * LANE_PITCH + 0.305 * (i - r / 2) + rng.uniform(-0.01, 0.01),
                       LANE_LEN + 0.264 * r, 0.0])
        # the masking panel over the pin deck: four fields of colour stripes
        o = [x0 - 0.25, LANE_LEN + 1.3, 0.95]
        for f, period in enumerate((0.24, 0.16, 0.1, 0.06)):
            stripes(mesh[MASKS[f]], mesh[MASKS[(f + 1 + lane) % 4]],
                    cg.add(o, X, 0.3915 * f), X, UP, 0.3915, 0.75, period)
    # kickbacks (indigo side panels at the pin decks) with thin black pinstripes
    for k in range(-2, 4):
        x = (k - 0.5) * LANE_PITCH
        sc.rectangle(mesh["kickback_indigo"], [x, LANE_LEN - 1.2, 0.08], Y, UP, 2.2, 0.8)
        for j in range(5):
            sc.rectangle(mesh["pinstripe_jet"], [x - 0.001, LANE_LEN - 1.2, 0.2 + 0.14 * j], Y,
                         UP, 2.2, 0.012)
    # the ball return between the middle lanes: a piano-black hood on two chrome rails
    xr = LANE_PITCH / 2
    sc.loft(mesh["hood_gloss"], [xr, -1.2, 0.0], [Y, X, UP],
            [(0.0, 0.0, 0.0), (0.0, 0.3, 0.75), (0.5, 0.3, 0.78), (0.9, 0.26, 0.7),
             (0.9, 0.0, 0.0)], 16)
    for s in (-1, 1):
        sl.tube(mesh["rail_chrome"], [xr + s * 0.07, -1.2, 0.26], [xr + s * 0.07, -3.4, 0.26],
                0.012, 6)
    return sc.mesh_files("bowling", mesh)


BALLS = (("bowl_violet", -1.55), ("bowl_coral", -1.85), ("bowl_petrol", -2.13),
         ("bowl_onyx", -2.43), ("bowl_lilac", -2.72))


def bowling_parts():
    objs = [cg.ground("carpet_navy"),
            sl.box([0.0, -2.3, -0.05], [9.0, 4.6, 0.1], "approach_maple"),
            cg.rect([0.0, LANE_LEN + 3.0, 2.2], [0, -1, 0], X, [14.0, 4.4], "pindeck_plum"),
            ]
    for lane in range(-3, 3):  # gutters and cappings between the lanes
        x = (lane + 0.5) * LANE_PITCH
        for s in (-1, 1):
            objs.append(cg.rect([x + s * 0.18, LANE_LEN / 2, -0.002], UP, Y, [LANE_LEN, 0.24],
                                "gutter_shadow"))
        objs.append(sl.box([x, LANE_LEN / 2, 0.02], [0.08, LANE_LEN, 0.04], "capping_cream"))
    for paint, y in BALLS:
        objs.append(sl.sphere([LANE_PITCH / 2, y, 0.38], 0.108, paint))
    for n in BOWL_MESHES:
        smooth = n in ("pin_enamel", "neck_scarlet", "hood_gloss", "rail_chrome")
        objs.append(sc.mesh_obj("bowling", n, smooth))
    lights = [{"type": "point", "position": [x, y, 3.0], "intensity_w_sr": [150, 142, 125]}
              for x, y in ((-1.6, -1.5), (1.6, -1.5), (-1.6, 5.0), (1.6, 11.0))]
    lights += [{"type": "point", "position": [0.0, LANE_LEN - 0.5, 2.6],
                "intensity_w_sr": [160, 156, 148]},
               {"type": "directional", "direction": sl.r4(cg.unit([0.2, -0.4, 1.0])),
                "irradiance_w_m2": [3, 3, 3.3], "polarization": {"linear_deg": 40, "dop": 0.3}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# labbench: a microbiology bench seen by a standing scientist, 0.55 m above its black epoxy
# top, 0.55 m back (~0.8 mm per pixel at the bottom of the frame, ~1.3 mm at the top): a 384-well
# plate of dye dilutions (4.5 mm wells: ~3-5 px, colour-only detail), a blue box of yellow
# pipette tips (9 mm pitch), a rack of microtubes with rose, mint, sky and apricot caps, four
# Petri dishes of 90 mm (blood, chocolate, MacConkey and Sabouraud agar) with cream colonies of
# 1-3 mm (fine luminance texture), a yellow ruler with black millimetre ticks (thin dark bars
# on a saturated ground, ~1.3 px a period, 5 and 10 mm marks longer), a steel tray and
# spatula; the window ahead mirrored by the black epoxy near Brewster's angle, a lamp overhead

LAB_CAMERA = {"position": [0.02, -0.55, 0.55], "look_at": [0.0, 0.08, 0.0], "up": UP,
              "focal_length_mm": 3.0, "f_number": 8}
DYES = ("dye_crystalviolet", "dye_phenolred", "dye_bromothymol", "dye_tartrazine",
        "dye_malachite")
CAPS = ("cap_rose", "cap_mint", "cap_sky", "cap_apricot")
AGARS = ("agar_blood", "agar_chocolate", "agar_macconkey", "agar_sabouraud")
LAB_MESHES = DYES + CAPS + AGARS + ("tipbox_azure", "tip_straw", "colony_cream",
                                    "ruler_yellow", "tick_black", "tray_steel")


def grid(nu, nv, pitch, at, place):
    """place(i, j, p) for each cell of an nu x nv grid of `pitch`, p = at(u, v) its centre."""
    for i in range(nu):
        for j in range(nv):
            place(i, j, at((i - (nu - 1) / 2) * pitch, (j - (nv - 1) / 2) * pitch))


def plate_at(c, yaw):
    """The point (u, v) along a plate turned by yaw (degrees) about the vertical through c."""
    a = math.radians(yaw)

    def at(u, v, h=0.0):
        return [c[0] + u * math.cos(a) - v * math.sin(a), c[1] + u * math.sin(a) +
                v * math.cos(a), c[2] + h]

    return at


def labbench_meshes():
    rng = random.Random(12203)
    mesh = sc.meshes_for("labbench", LAB_MESHES, WRITER)
    # the 384-well plate: dilution rows of five dyes, every third column blank
    wells = plate_at([-0.07, 0.03, 0.0145], 6)

    def well(i, j, p):
        if i % 3 != 2:
            sc.annulus(mesh[DYES[(i // 3 + j // 4) % 5]], p, UP, 0.0, 0.0018, 4, phase=45)

    grid(24, 16, 0.0045, wells, well)
    # the tip box: a blue rack of 8 x 12 yellow tips at 9 mm
    tips = plate_at([0.09, 0.05, 0.06], -12)
    sc.cuboid(mesh["tipbox_azure"], tips(0, 0, -0.03), [X, Y, UP], [0.122, 0.082, 0.06])
    grid(12, 8, 0.009, tips, lambda i, j, p: sc.annulus(mesh["tip_straw"], p, UP, 0.0022,
                                                         0.0034, 6))
    # the microtube rack: 4 x 10 caps in turn of four colours at 13 mm
    tubes = plate_at([0.02, 0.2, 0.048], 3)
    grid(10, 4, 0.013, tubes, lambda i, j, p: sc.annulus(mesh[CAPS[(i + j) % 4]], p, UP, 0.0,
                                                          0.0052, 8))
    # four Petri dishes: agar discs of 85 mm with colonies
    for k, paint in enumerate(AGARS):
        c = [-0.2 + 0.095 * (k % 2), -0.12 + 0.1 * (k // 2), 0.0105]
        sc.annulus(mesh[paint], cg.add(c, UP, -0.0005), UP, 0.0, 0.0425, 24)
        for _ in range(45):
            r, a = 0.04 * math.sqrt(rng.random()), rng.uniform(0, 2 * math.pi)
            sc.annulus(mesh["colony_cream"], [c[0] + r * math.cos(a), c[1] + r * math.sin(a),
                                              c[2]], UP, 0.0, rng.uniform(0.0006, 0.0016), 6)
    # the ruler (300 x 30 mm) with millimetre ticks, lying across the front at an angle
    ruler = plate_at([0.06, -0.13, 0.0015], 14)
    ru, rv = plate_at([0.0, 0.0, 0.0], 14)(1, 0), plate_at([0.0, 0.0, 0.0], 14)(0, 1)
    sc.rectangle(mesh["ruler_yellow"], ruler(-0.155, -0.015), ru, rv, 0.31, 0.03)
    for k in range(301):
        length = 0.009 if k % 10 == 0 else 0.006 if k % 5 == 0 else 0.0035
        sc.rectangle(mesh["tick_black"], ruler(-0.15 + 0.001 * k - 0.0002, 0.015 - length,
                                               0.0002), ru, rv, 0.0004, length)
    # the steel tray and a spatula
    sc.cuboid(mesh["tray_steel"], [0.19, -0.02, 0.004], [X, Y, UP], [0.08, 0.06, 0.008])
    sl.tube(mesh["tray_steel"], [-0.02, -0.2, 0.003], [0.12, -0.17, 0.003], 0.0025, 6)
    return sc.mesh_files("labbench", mesh)


def labbench_parts():
    objs = [cg.ground("epoxy_black"),
            cg.rect([0.0, 0.36, 0.05], [0, -1, 0], X, [1.6, 0.1], "splash_tile"),
            sl.box([-0.07, 0.03, 0.007], [0.128, 0.086, 0.0145], "plate_polystyrene", 6),
            sl.box([0.02, 0.2, 0.022], [0.14, 0.06, 0.044], "plate_polystyrene", 3)]
    for n in LAB_MESHES:
        objs.append(sc.mesh_obj("labbench", n))
    lights = [{"type": "point", "position": [0.1, -0.1, 1.1], "intensity_w_sr": [7, 6.8, 6.3]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.1, 1.0, 0.72])),
               "irradiance_w_m2": [3.5, 3.7, 4.2]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.4, -0.2, 1.0])),
               "irradiance_w_m2": [3, 3, 3.2], "polarization": {"linear_deg": 110, "dop": 0.3}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# console: a recording studio's mixing console seen from the engineer's chair, 1.2 m up and
# 0.6 m behind the armrest (~1.2 mm per pixel at the faders, ~1.6 mm at the meter bridge): 20
# channel strips of 32 mm (slate on a graphite frame), each with six knobs in rows of colour
# (scarlet gain, azure and emerald EQ, saffron aux, ash pan: caps of 12 mm, ~9 px, in the rows'
# colours on ash skirts, ~25 px apart), a black fader slot with a satin steel cap, a white
# scribble strip with a black marker name (thin dark strokes), a meter of 16 LED segments of
# 3 mm (green, amber, red: ~2 px a period, colour stripes), jack sockets in nickel on the
# meter bridge; a piano-black armrest and two piano-black monitors mirroring the window light
# near Brewster's angle, an ochre floor, the dark studio beyond

DESK_CAMERA = {"position": [0.05, -0.75, 1.22], "look_at": [0.0, 0.3, 0.7], "up": UP,
               "focal_length_mm": 2.6, "f_number": 8}
KNOBS = ("knob_scarlet", "knob_azure", "knob_azure", "knob_emerald", "knob_saffron",
         "knob_ash")
LEDS = ("meter_green",) * 10 + ("meter_amber",) * 4 + ("meter_red",) * 2
DESK_MESHES = ("knob_scarlet", "knob_azure", "knob_emerald", "knob_saffron", "knob_ash",
               "slot_black", "fadercap_steel", "jack_nickel", "meter_green", "meter_amber",
               "meter_red",
               "scribble_tape", "marker_ink", "strip_slate")
DESK_TILT = 14  # the console's surface rises 14 degrees away from the engineer


def console_meshes():
    rng = random.Random(12305)
    mesh = sc.meshes_for("console", DESK_MESHES, WRITER)
    desk = sc.Slope([0.0, -0.05, 0.78], DESK_TILT)
    for ch in range(20):
        u = -0.32 + 0.032 * ch
        sc.rectangle(mesh["strip_slate"], desk.at(u - 0.014, 0.0, 0.0005), desk.u, desk.v,
                     0.028, 0.5)
        for k, paint in enumerate(KNOBS):  # knobs: a skirt and a cap
            c = desk.at(u, 0.2 + 0.04 * k, 0.0)
            sc.loft(mesh["knob_ash" if paint != "knob_ash" else "slot_black"], c,
                    [desk.n, desk.u, desk.v], [(0.0, 0.0085, 0.0085), (0.004, 0.0085, 0.0085)],
                    8)
            sc.loft(mesh[paint], c,
                    [desk.n, desk.u, desk.v], [(0.004, 0.006, 0.006), (0.016, 0.0055, 0.0055),
                                               (0.016, 0.0, 0.0)], 8, rng.uniform(0, 1))
        # the fader: a slot 100 mm long and a steel cap
        sc.rectangle(mesh["slot_black"], desk.at(u - 0.0015, 0.03, 0.0008), desk.u, desk.v,
                     0.003, 0.1)
        cap = desk.at(u, 0.04 + 0.08 * rng.random(), 0.008)
        sc.cuboid(mesh["fadercap_steel"], cap, [desk.u, desk.v, desk.n], [0.02, 0.012, 0.016])
        # the scribble strip and a name in marker (three strokes)
        sc.rectangle(mesh["scribble_tape"], desk.at(u - 0.013, 0.15, 0.0008), desk.u, desk.v,
                     0.026, 0.018)
        for s in range(3):
            a = desk.at(u - 0.009 + 0.006 * s, 0.154 + 0.004 * (s % 2), 0.001)
            sl.strip(mesh["marker_ink"], [a, cg.add(a, desk.v, 0.008 + 0.002 * (ch % 3))],
                     0.0012, desk.n)
        # the meter: 16 segments of 3 mm (2 mm lit, 1 mm gap)
        for k, paint in enumerate(LEDS):
            sc.rectangle(mesh[paint], desk.at(u - 0.004, 0.46 + 0.003 * k, 0.0008), desk.u,
                         desk.v, 0.008, 0.002)
        # two jack sockets on the meter bridge's front
        for z in (0.0, 0.03):
            sc.annulus(mesh["jack_nickel"], [u, 0.45, 1.02 + z], [0, -1, 0], 0.003, 0.006, 8)
    return sc.mesh_files("console", mesh)


def console_parts():
    desk = sc.Slope([0.0, -0.05, 0.78], DESK_TILT)
    objs = [cg.ground("studio_floor"),
            {"type": "box", "center": sl.r4(desk.at(0.0, 0.25, -0.02)),
             "size": [0.76, 0.56, 0.04], "rotation_deg": [DESK_TILT, 0.0, 0.0],
             "material": "panel_graphite"},
            sl.box([0.0, 0.47, 0.98], [0.76, 0.06, 0.12], "panel_graphite"),
            sl.box([0.0, 0.3, 0.38], [0.8, 0.6, 0.76], "panel_graphite"),
            sl.box([0.0, -0.12, 0.76], [0.8, 0.12, 0.06], "armrest_vinyl")]
    for s in (-1, 1):  # the monitors on stands
        objs.append(sl.box([s * 0.46, 0.72, 1.2], [0.22, 0.26, 0.36], "monitor_piano",
                           -s * 20))
        objs.append(sl.box([s * 0.46, 0.72, 0.5], [0.06, 0.06, 1.0], "jack_nickel"))
    for n in DESK_MESHES:
        objs.append(sc.mesh_obj("console", n, n.startswith("knob")))
    lights = [{"type": "point", "position": [0.0, 0.2, 2.4], "intensity_w_sr": [36, 34, 30]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.0, 1.0, 0.73])),
               "irradiance_w_m2": [1.2, 1.3, 1.5]},
              {"type": "directional", "direction": sl.r4(cg.unit([0.5, -0.3, 1.0])),
               "irradiance_w_m2": [3, 3, 3.3], "polarization": {"linear_deg": 150, "dop": 0.3}}]
    return MATERIALS, objs, lights


# ---------------------------------------------------------------------------------------------
# campsite: a campsite field seen by a camper standing by a tent, 1.7 m up (~3 mm per pixel at
# 3 m, ~16 mm at 15 m, ~50 mm at 45 m): dome tents in tomato, olive, turquoise, mustard and
# navy fly sheets with charcoal doors and black zips (thin dark bars on saturated grounds),
# white guy lines (4 mm: below a pixel beyond 2 m), a windbreak of red, blue and yellow stripes
# of 150 mm at an angle to the view (~14 px a stripe at its near end, ~6 px at its far end), a
# dark glossy kayak upturned on the grass and a cool box with a navy gloss lid (the bright sky
# ahead mirrored near Brewster's angle), a steel stove and an aluminium kettle (glints), rows of
# tents receding to 55 m (colour-only detail), a gravel track, a hawthorn hedge; the sun from
# behind on the right, the bright sky ahead, a polarized skylight, the sky (the background)

CAMP_CAMERA = {"position": [0.0, 0.0, 1.7], "look_at": [0.3, 12.0, 0.6], "up": UP,
               "focal_length_mm": 3.2, "f_number": 8}
FLIES = ("fly_tomato", "fly_olive", "fly_turquoise", "fly_mustard", "fly_navy")
WINDBREAK = ("windbreak_red", "windbreak_blue", "windbreak_yellow")
CAMP_MESHES = FLIES + WINDBREAK + ("door_charcoal", "zip_black", "guyline_white",
                                   "kettle_alu", "stove_steel", "kayak_hull")
# tents: (x, y, yaw, fly, half-length, half-width, height)
TENTS = [(-2.2, 5.0, 20, "fly_tomato", 1.2, 0.9, 1.1), (3.8, 9.5, -30, "fly_turquoise", 1.5,
                                                         1.1, 1.3),
         (-3.5, 13.0, 60, "fly_olive", 1.0, 0.8, 1.0), (0.8, 16.0, 5, "fly_mustard", 1.3, 1.0,
                                                        1.2),
         (5.0, 20.0, -50, "fly_navy", 1.6, 1.2, 1.4)]


def dome(mesh, c, yaw, fly, a, b, h):
    """A dome tent at c turned by yaw degrees: its fly (half an ellipsoid) and, on the side
    towards the camera, a charcoal door with a black zip round it; four guy lines to pegs."""
    e = math.radians(yaw)
    ax = [[math.cos(e), math.sin(e), 0.0], [-math.sin(e), math.cos(e), 0.0], UP]
    sc.ellipsoid(mesh[fly], c, [UP, ax[0], ax[1]], [h, a, b], 14, 8)

    def surf(t, p, lift):
        return cg.add(cg.add(cg.add(c, ax[0], lift * a * math.cos(t) * math.cos(p)), ax[1],
                             -lift * b * math.cos(t) * math.sin(p)), UP, lift * h * math.sin(t))

    door = [math.radians(d) for d in range(5, 56, 10)]
    sides = [math.radians(70 + d) for d in range(0, 41, 10)]
    sc.patch(mesh["door_charcoal"], lambda u, v: surf(u, v, 1.01), door, sides)
    for p in (sides[0], sides[-1]):
        sc.surface_band(mesh["zip_black"], lambda u, v: surf(v, u, 1.015), lambda v: p - 0.02,
                        lambda v: p + 0.02, door)
    for s in (-1, 1):
        for t in (-1, 1):
            top = surf(math.radians(40), math.atan2(t * b, s * a), 1.0)
            peg = cg.add(cg.add(c, ax[0], s * (a + 0.8)), ax[1], t * (b + 0.6))
            sl.strip(mesh["guyline_white"], [top, peg], 0.004, cg.cross(cg.unit(
                [q - p for p, q in zip(top, peg)]), UP))


def campsite_meshes():
    rng = random.Random(12407)
    mesh = sc.meshes_for("campsite", CAMP_MESHES, WRITER)
    for x, y, yaw, fly, a, b, h in TENTS:
        dome(mesh, [x, y, 0.0], yaw, fly, a, b, h)
    for k in range(24):  # rows of tents receding, 22-55 m
        x, y = rng.uniform(-25, 25), 22.0 + 33.0 * k / 24
        s = rng.uniform(0.7, 1.2)
        sc.ellipsoid(mesh[FLIES[k % 5]], [x, y, 0.0], [UP, X, Y], [1.2 * s, 1.4 * s, 1.1 * s],
                     10, 4)
    # the windbreak: 6 m of stripes of 150 mm in turn of three colours, 1.4 m high
    p0, p1 = [0.3, 3.2, 0.0], [3.4, 8.4, 0.0]
    d = cg.unit([q - p for p, q in zip(p0, p1)])
    for k in range(40):
        sc.rectangle(mesh[WINDBREAK[k % 3]], cg.add(p0, d, 0.15 * k), d, UP, 0.15, 1.4)
    # the kayak, upturned on the grass (3.8 m, its hull's upper half above the ground)
    k = [math.cos(math.radians(78)), math.sin(math.radians(78)), 0.0]
    sc.ellipsoid(mesh["kayak_hull"], [-1.3, 8.5, 0.0], [k, cg.cross(UP, k), UP],
                 [1.9, 0.3, 0.2], 12, 10)
    # the stove on the cool box, and the kettle on the stove
    sc.cuboid(mesh["stove_steel"], [-0.8, 3.0, 0.5], [X, Y, UP], [0.34, 0.28, 0.1])
    sc.loft(mesh["kettle_alu"], [-0.8, 3.0, 0.55], [UP, X, Y],
            [(0.0, 0.0, 0.0), (0.0, 0.09, 0.09), (0.12, 0.1, 0.1), (0.16, 0.05, 0.05),
             (0.17, 0.0, 0.0)], 14)
    return sc.mesh_files("campsite", mesh)


def campsite_parts():
    objs = [cg.ground("field_meadow"),
            cg.rect([-6.0, 30.0, 0.003], UP, Y, [60.0, 2.5], "track_gravel"),
            sl.box([0.0, 62.0, 1.5], [120.0, 2.0, 3.0], "hedge_hawthorn"),
            sl.box([-0.8, 3.0, 0.22], [0.5, 0.34, 0.44], "coolbox_white"),
            sl.box([-0.8, 3.0, 0.45], [0.52, 0.36, 0.02], "coolbox_lid")]
    for n in CAMP_MESHES:
        smooth = n.startswith("fly") or n in ("kettle_alu", "kayak_hull")
        objs.append(sc.mesh_obj("campsite", n, smooth))
    lights = [{"type": "directional", "direction": sl.r4(cg.unit([0.5, -0.6, 0.6])),
               "irradiance_w_m2": [620, 600, 560]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.1, 0.8, 0.6])),
               "irradiance_w_m2": [55, 62, 78]},
              {"type": "directional", "direction": sl.r4(cg.unit([-0.5, 0.2, 1.0])),
               "irradiance_w_m2": [55, 64, 85], "polarization": {"linear_deg": 70, "dop": 0.4}}]
    return MATERIALS, objs, lights


SCENES = sc.scene_set(TITLE, EXPOSURE, {
    "bowling": (bowling_parts, BOWL_CAMERA, "a bowling alley seen from the concourse behind "
                "the approach (five lacquered maple lanes with arrows and dots, pins, masking "
                "panels printed in colour stripes, indigo kickbacks, a ball return with glossy "
                "balls)", None),
    "labbench": (labbench_parts, LAB_CAMERA, "a microbiology bench (a 384-well plate of dye "
                 "dilutions, a box of pipette tips, a microtube rack, Petri dishes with "
                 "colonies, a ruler, a steel tray) on a black epoxy top", None),
    "console": (console_parts, DESK_CAMERA, "a recording studio's mixing console seen from "
                "the engineer's chair (channel strips of coloured knobs, faders, scribble "
                "strips, LED meters, jack sockets, piano-black monitors and armrest)", None),
    "campsite": (campsite_parts, CAMP_CAMERA, "a campsite field (dome tents with guy lines, a "
                 "striped windbreak, an upturned kayak, a cool box with a stove and kettle, "
                 "rows of tents receding, a gravel track, a hedge)", [16, 20, 30]),
}, {
    "campsite_g11": ("campsite", 11, "a short exposure at dusk"),
    "bowling_g16": ("bowling", 16, "the house lights dimmed, handheld"),
})


def meshes():
    """Every mesh of the set: file name -> OBJ text (each *_meshes gives name -> sl.Mesh)."""
    makers = (bowling_meshes, labbench_meshes, console_meshes, campsite_meshes)
    return {name + ".obj": mesh.text() for make in makers for name, mesh in make().items()}


cg.write_all(HERE, SCENES, meshes, sys.argv)
