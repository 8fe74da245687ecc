# Prints one scene of the colour stress suite (README.md):
#   python3 gen_colour.py patches|gloss|text|gratings|noisy EXPOSURE_US
# Colours come from per-channel extinction coefficients k = [R, G, B] (docs/scene-format.md,
# "Materials"): in the pBRDF's diffuse term (physics.md §2) a channel with k ~ 1.3-1.8 scatters
# back brightly (the monochrome suite's "bright" paint has k 1.28) and one with k ~ 0.03 hardly
# at all (checked on the rendered truth), so a paint's colour is set by which channels have
# large k.
import json, math, os, sys

# name: (n, k[R, G, B]): saturated paints and two neutrals
PAINTS = {
    "red": (1.5, [1.8, 0.03, 0.03]),
    "green": (1.5, [0.03, 1.8, 0.03]),
    "blue": (1.5, [0.03, 0.03, 1.8]),
    "yellow": (1.5, [1.8, 1.6, 0.03]),
    "magenta": (1.5, [1.6, 0.03, 1.8]),
    "cyan": (1.5, [0.03, 1.6, 1.8]),
    "white": (1.5, [1.4, 1.4, 1.4]),
    "black": (1.5, [0.02, 0.02, 0.02]),
}
ORDER = ["red", "cyan", "yellow", "blue", "green", "magenta", "white", "black"]


def materials(sigma, diffuse=True):
    m = {}
    for name, (n, k) in PAINTS.items():
        m[name] = {"n": n, "k": k, "sigma": sigma}
        if not diffuse:
            m[name]["diffuse"] = "none"
    return m


def sensor(preset, exposure_us):
    s = {"preset": preset, "resolution": [512, 384], "exposure_us": exposure_us}
    if preset == "ideal":
        # the ideal sensor with the IMX250MYR's colour layer and channel QEs
        s["layout"] = "RGGB:90,45,135,0"
        s["qe"] = [0.22, 0.30, 0.24]
    return s


def patches(exposure_us, preset="ideal"):
    # abutting 0.13 x 0.13 tiles (~22 px), every pair of hues side by side, some tilted so that
    # their gloss is polarized differently; no gaps: every tile edge is a hue edge
    objs = [{"type": "plane", "point": [0, 0, 0], "normal": [0, 0, 1], "material": "white"}]
    mats = materials(0.08)
    mats.update({"g_" + k: v for k, v in materials(0.02, diffuse=True).items()})
    nx, ny, s = 12, 9, 0.13
    for j in range(ny):
        for i in range(nx):
            c = ORDER[(i * 3 + j * 5 + (i * j) % 3) % len(ORDER)]
            glossy = (i + 2 * j) % 4 == 0
            x = (i - (nx - 1) / 2) * s
            y = (j - (ny - 1) / 2) * s
            objs.append({"type": "plane", "point": [round(x, 4), round(y, 4), 0.002],
                         "normal": [0, 0, 1], "size": [s, s], "u_axis": [1, 0, 0],
                         "material": ("g_" if glossy else "") + c})
    return {
        "name": "colour stress: abutting saturated matte and glossy colour tiles (hue edges everywhere, ~22 px tiles)",
        "camera": {"position": [0, -2.2, 6.0], "look_at": [0, 0, 0], "up": [0, 1, 0],
                   "focal_length_mm": 12, "f_number": 4},
        "lights": [{"type": "directional", "direction": [0.3, -0.5, 0.81], "irradiance_w_m2": 300},
                   {"type": "point", "position": [-0.3, 1.0, 2.0], "intensity_w_sr": 300}],
        "materials": mats, "objects": objs,
        "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
        "sensor": sensor(preset, exposure_us)}


def gloss(exposure_us):
    lights = []
    for k in range(12):
        a = 2 * math.pi * k / 12
        d = [0.9 * math.cos(a), 0.42, 0.9 * math.sin(a) + 0.15]
        n = math.sqrt(sum(x * x for x in d))
        lights.append({"type": "directional", "direction": [round(x / n, 4) for x in d],
                       "irradiance_w_m2": 250})
    lights.append({"type": "directional", "direction": [0.35, -0.85, 0.4], "irradiance_w_m2": 150,
                   "polarization": {"linear_deg": 30}})
    objs = [{"type": "plane", "point": [0, 0, -1.0], "normal": [0, 0, 1], "material": "m_blue"}]
    sph = [([-2.2, 0.5, 0.0], 0.9, "red"), ([-0.1, 0.0, 0.0], 0.85, "green"),
           ([1.9, 0.6, 0.0], 0.9, "blue"), ([-1.2, -1.2, -0.55], 0.42, "yellow"),
           ([0.9, -1.4, -0.6], 0.38, "magenta"), ([2.6, -1.5, -0.62], 0.36, "cyan")]
    for c, r, m in sph:
        objs.append({"type": "sphere", "center": c, "radius": r, "material": m})
    mats = materials(0.1)
    mats["m_blue"] = {"n": 1.5, "k": [0.1, 0.6, 1.0], "sigma": 0.5}
    return {
        "name": "colour stress: saturated glossy plastic spheres on a matte backdrop under a ring of lights and one polarized light (high DoLP on coloured surfaces)",
        "camera": {"position": [0, -8, 2.2], "look_at": [0.1, 0, -0.2], "focal_length_mm": 12, "f_number": 4},
        "lights": lights, "materials": mats, "objects": objs,
        "effects": {"diffuse": True, "shadowing": True, "cast_shadows": True, "supersampling": 3},
        "sensor": dict(sensor("ideal", exposure_us), pixel_pitch_um=16)}


def mesh_scene(which, exposure_us):
    # the monochrome suite's meshes (../gen_meshes.py) in colour: ink and paper of
    # complementary hues, so the strokes are hue edges as much as intensity edges
    here = os.path.dirname(os.path.abspath(__file__))
    base = json.load(open(os.path.join(here, "..", which + ".json")))
    mats = materials(0.04)
    mats["paper"] = {"n": 1.5, "k": [0.04, 1.6, 1.5], "sigma": 0.6}  # cyan, matte
    mats["ink"] = {"n": 1.5, "k": [1.8, 0.03, 0.4], "sigma": 0.04}  # red, glossy
    objs = []
    for o in base["objects"]:
        o = dict(o)
        if o["type"] == "mesh":
            o["file"] = "../" + o["file"]
            o["material"] = "ink"
        else:
            o["material"] = "paper"
        objs.append(o)
    s = dict(base)
    s["name"] = "colour stress: " + which + " of the monochrome suite in glossy red ink on matte cyan"
    s["materials"] = mats
    s["objects"] = objs
    s["sensor"] = dict(base["sensor"], **sensor("ideal", exposure_us))
    return s


def main():
    which, exposure_us = sys.argv[1], float(sys.argv[2])
    if which == "patches":
        s = patches(exposure_us)
    elif which == "noisy":
        s = patches(exposure_us, preset="imx250myr")
        s["name"] = "colour stress: the colour tiles through the IMX250MYR preset (shot, read and dark noise, PRNU/DSNU, ER 200, crosstalk) at a short exposure"
    elif which == "gloss":
        s = gloss(exposure_us)
    else:
        s = mesh_scene(which, exposure_us)
    s = dict({"polarcam_scene": 1}, **s)
    print(json.dumps(s, indent=1))


main()
