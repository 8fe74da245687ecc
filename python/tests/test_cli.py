"""Every function of the polarcam module against the command line on the same input: where
the C path is deterministic the values are bit-identical (the module calls the same library
functions; the CLI's JSON prints 17 significant digits, which round-trips a double)."""
import json
import math
import os
import re

import numpy as np
import pytest

import polarcam
from conftest import REPO, json_lines, read_png_rgb

SCENES = os.path.join(REPO, "scenes")
ROI = (0, 0, 320, 240)


@pytest.fixture(scope="module")
def recording(tmp_path_factory):
    """polarcam render --seed 3 --roi (2 frames) into a recording directory, read back."""
    import subprocess

    from conftest import CLI

    if not CLI:
        pytest.skip("POLARCAM_CLI is not set: run through ctest")
    d = tmp_path_factory.mktemp("rec")
    subprocess.run([CLI, "render", "-o", str(d), "--seed", "3", "--frames", "2", "--roi",
                    ",".join(map(str, ROI))], check=True, capture_output=True)
    return d


def stokes_cli_layout(raw, **kw):
    """polarcam.stokes into the output layout of polarcam process: S0, S1, S2 interleaved in
    one (H, W, 3) array, DoLP and AoLP planes."""
    method = kw.get("method")
    h, w = raw.shape if method != "superpixel-half" else (raw.shape[0] // 2, raw.shape[1] // 2)
    s = np.empty((h, w, 3), np.float32)
    dolp, aolp = np.empty((h, w), np.float32), np.empty((h, w), np.float32)
    polarcam.stokes(raw, out=(s[..., 0], s[..., 1], s[..., 2], dolp, aolp), **kw)
    return s, dolp, aolp


def test_render_equals_cli(recording):
    raw, truth, meta = polarcam.render(seed=3, frame=[0, 1], roi=ROI)
    assert raw.shape == (2, ROI[3], ROI[2]) and raw.dtype == np.uint16
    # the raw frames as the CLI wrote them (PNG + sBIT), read back by the file: source
    with polarcam.open(f"file:{recording}") as src:
        frames = list(src)
    assert len(frames) == 2
    for k, fr in enumerate(frames):
        np.testing.assert_array_equal(fr.raw, raw[k])
        assert fr.sequence == meta["sequence"][k] and fr.timestamp_ns == meta["timestamp_ns"][k]
        assert fr.layout == meta["layout"] and fr.bits == meta["bits"] == 12
    cli_truth = np.load(recording / "truth_stokes.npy")
    assert cli_truth.dtype == np.float32 and cli_truth.shape == truth.shape
    np.testing.assert_array_equal(cli_truth, truth)
    rec = json.loads((recording / "meta.json").read_text())
    assert rec["mosaic"] == meta["layout"] and rec["bits"] == meta["bits"]
    assert rec["extra"]["seed"] == 3
    # a different seed is a different frame: the comparison above can fail
    assert not np.array_equal(polarcam.render(seed=4, roi=ROI)[0], raw[0])


@pytest.mark.parametrize("method", ["bilinear", "superpixel-half", "bicubic", "eari", "ratio"])
def test_stokes_equals_process(cli, recording, tmp_path, method):
    png = recording / "raw_000000.png"
    cli("process", png, "-o", tmp_path, "--method", method, "--picture-width", "0")
    with polarcam.open(f"file:{recording}") as src:
        fr = src.read()
    s = np.load(tmp_path / "stokes.npy")
    dolp, aolp = np.load(tmp_path / "dolp.npy"), np.load(tmp_path / "aolp.npy")
    # the CLI's output layout (S0, S1, S2 interleaved in one (H, W, 3) array): bit-identical
    mine = stokes_cli_layout(fr.raw, method=method, layout=fr.layout, bits=fr.bits)
    np.testing.assert_array_equal(mine[0], s)
    np.testing.assert_array_equal(mine[1], dolp)
    np.testing.assert_array_equal(mine[2], aolp)
    # new (planar) arrays: the same S0..S2; methods without a fused Stokes pass take the
    # library's planar SIMD Stokes kernel there, whose DoLP may differ from the interleaved
    # (scalar) one in the last bit (core/demosaic_fast.c pc_stokes_planar_fast)
    st = polarcam.stokes(fr.raw, method=method, layout=fr.layout, bits=fr.bits)
    for i, name in enumerate(("s0", "s1", "s2")):
        np.testing.assert_array_equal(getattr(st, name), s[..., i], err_msg=name)
    np.testing.assert_allclose(st.dolp, dolp, rtol=3e-7, atol=0)
    np.testing.assert_allclose(st.aolp, aolp, rtol=0, atol=4e-7)
    if method == "bilinear":
        # the pictures: polarcam.picture draws the pixels of the annotated PNGs
        h, w = st.s0.shape
        top = int(max(12.0, min(w, h) / 40.0) * 2.2)  # io/plot.c: title band
        for kind, name in (("s0", "s0"), ("dolp", "dolp"), ("aolp", "aolp"),
                           ("aolp_sat", "aolp_sat")):
            png_rgb = read_png_rgb(tmp_path / f"{name}.png")[top:top + h, :w, :3]
            np.testing.assert_array_equal(polarcam.picture(st, kind=kind), png_rgb,
                                          err_msg=kind)


def test_minmax_equals_process(cli, recording, tmp_path):
    """polarcam.minmax and picture kinds imin/imax/diffuse/specular against process --minmax
    --split on the same raw: the arrays bit-identical (the same library kernel on the same
    S0, S1, S2), the pictures the pixels of the annotated PNGs (grey on the S0 picture's
    scale), and both against the formulas in double."""
    png = recording / "raw_000000.png"
    cli("process", png, "-o", tmp_path, "--minmax", "--split", "--picture-width", "0")
    with polarcam.open(f"file:{recording}") as src:
        fr = src.read()
    st = polarcam.stokes(fr.raw, layout=fr.layout, bits=fr.bits)
    mm = polarcam.minmax(st)
    assert isinstance(mm, polarcam.MinMax)
    assert np.count_nonzero(np.load(tmp_path / "valid.npy") == 0) == 0  # no pink marks
    s = np.load(tmp_path / "stokes.npy").astype(np.float64)
    p = np.hypot(s[..., 1], s[..., 2])
    formulas = {"imin": (s[..., 0] - p) / 2, "imax": (s[..., 0] + p) / 2,
                "diffuse": s[..., 0] - p, "specular": p}
    h, w = st.s0.shape
    top = int(max(12.0, min(w, h) / 40.0) * 2.2)  # io/plot.c: title band
    for name in ("imin", "imax", "diffuse", "specular"):
        cli_plane = np.load(tmp_path / f"{name}.npy")
        np.testing.assert_array_equal(getattr(mm, name), cli_plane, err_msg=name)
        np.testing.assert_allclose(getattr(mm, name), formulas[name], rtol=0,
                                   atol=2e-6 * float(np.abs(s[..., 0]).max()), err_msg=name)
        png_rgb = read_png_rgb(tmp_path / f"{name}.png")[top:top + h, :w, :3]
        np.testing.assert_array_equal(polarcam.picture(st, kind=name), png_rgb, err_msg=name)
    # the arrays' form: S0, S1, S2 given apart, the same values
    np.testing.assert_array_equal(polarcam.minmax(st.s0, s1=st.s1, s2=st.s2).specular,
                                  mm.specular)
    # the scale is S0's (not the plane's own): the specular picture of a weakly polarized
    # scene is darker than the plane drawn on its own 99.9th percentile
    own = polarcam.picture(mm.specular, kind="s0")
    assert polarcam.picture(st, kind="specular").mean() < own.mean()
    with pytest.raises(ValueError, match="s1"):
        polarcam.minmax(st.s0)


def test_demosaic_equals_cli(cli, recording, tmp_path):
    png = recording / "raw_000000.png"
    with polarcam.open(f"file:{recording}") as src:
        fr = src.read()
    for method in ("bilinear", "ppid", "ratio"):
        out = tmp_path / f"{method}.npy"
        cli("demosaic", png, "--method", method, "-o", out)
        np.testing.assert_array_equal(
            polarcam.demosaic(fr.raw, method=method, layout=fr.layout, bits=fr.bits),
            np.load(out), err_msg=method)


def test_colour_equals_cli(cli, tmp_path):
    scene = os.path.join(SCENES, "colour_small.json")
    cli("render", scene, "-o", tmp_path / "rec", "--seed", "11")
    raw, truth, meta = polarcam.render(scene, seed=11)
    assert meta["layout"].startswith("RGGB:") and truth.shape[2:] == (3, 4)
    with polarcam.open(f"file:{tmp_path / 'rec'}") as src:
        np.testing.assert_array_equal(src.read().raw, raw)
    np.testing.assert_array_equal(np.load(tmp_path / "rec" / "truth_stokes.npy"), truth)
    # process: the recording's layout and the colour default method (bayer-first)
    cli("process", tmp_path / "rec" / "raw_000000.png", "-o", tmp_path / "p")
    s, dolp, aolp = stokes_cli_layout(raw, layout=meta["layout"], bits=meta["bits"])
    np.testing.assert_array_equal(s, np.load(tmp_path / "p" / "stokes.npy"))
    np.testing.assert_array_equal(dolp, np.load(tmp_path / "p" / "dolp.npy"))
    np.testing.assert_array_equal(aolp, np.load(tmp_path / "p" / "aolp.npy"))
    # stokes_rgb.npy: each colour's Stokes from its own four analyser images, here through
    # the module's demosaic (12 channels, R, G, B x 4 angles) and stokes of 4 channels
    d12 = polarcam.demosaic(raw, layout=meta["layout"], bits=meta["bits"])
    rgb = np.load(tmp_path / "p" / "stokes_rgb.npy")
    assert rgb.shape == s.shape[:2] + (3, 3)
    for c in range(3):
        st = polarcam.stokes(np.ascontiguousarray(d12[..., 4 * c:4 * c + 4]))
        for k, name in enumerate(("s0", "s1", "s2")):
            np.testing.assert_array_equal(getattr(st, name), rgb[:, :, c, k],
                                          err_msg=f"colour {c} {name}")
    # stokes.npy is their mean over the colours (to float rounding)
    np.testing.assert_allclose(rgb.mean(axis=2), s, rtol=0, atol=1e-3 * float(s[..., 0].max()))
    cli("demosaic", tmp_path / "rec" / "raw_000000.png", "--method", "bayer-eari", "-o",
        tmp_path / "d.npy")
    np.testing.assert_array_equal(
        polarcam.demosaic(raw, method="bayer-eari", layout=meta["layout"], bits=12),
        np.load(tmp_path / "d.npy"))


def _cli_mueller(lines):
    return np.array([o["mueller"] for o in lines], dtype=np.float64)


@pytest.mark.parametrize("rho,py_rho", [("table", "table"), ("quad:16", "quad"),
                                        ("quad:8", "quad:8")])
def test_pbrdf_equals_cli(cli, rho, py_rho):
    lines = json_lines(cli("pbrdf", "--n", "1.46", "--k", "1.28", "--sigma", "0.1:0.3:0.1",
                           "--theta-i", "0:80:20", "--theta-r", "55", "--phi", "150",
                           "--rho", rho).stdout)
    # the inputs as the CLI used them (its ranges are START + i*STEP)
    inp = {k: np.array([o[k] for o in lines]) for k in ("n", "k", "sigma", "theta_i",
                                                        "theta_r", "phi")}
    assert len(lines) == 15 and inp["sigma"][::5] == pytest.approx([0.1, 0.2, 0.3])
    f = polarcam.pbrdf(inp["n"], inp["k"], inp["sigma"], inp["theta_i"], inp["theta_r"],
                       inp["phi"], rho=py_rho)
    assert f.shape == (15, 4, 4) and f.dtype == np.float64
    np.testing.assert_array_equal(f, _cli_mueller(lines))
    # broadcasting gives the same matrices as the flat call
    g = polarcam.pbrdf(1.46, 1.28, inp["sigma"][::5, None], inp["theta_i"][None, :5], 55, 150,
                       rho=py_rho)
    assert g.shape == (3, 5, 4, 4)
    np.testing.assert_array_equal(g.reshape(-1, 4, 4), f)


def test_pbrdf_options_equal_cli(cli):
    for diffuse, shadowing in (("geometric", "none"), ("none", "ts")):
        lines = json_lines(cli("pbrdf", "--n", "1.5", "--sigma", "0.25", "--theta-i", "35",
                               "--theta-r", "0:90:30", "--phi", "180", "--diffuse", diffuse,
                               "--shadowing", shadowing, "--rho", "table").stdout)
        f = polarcam.pbrdf(1.5, 0, 0.25, 35, np.arange(0, 91, 30.0), diffuse=diffuse,
                           shadowing=shadowing)
        np.testing.assert_array_equal(f, _cli_mueller(lines))


def _matrices():
    rng = np.random.default_rng(7)
    ms = [np.eye(4),
          np.diag([1.0, 0.9, 0.9, 0.9]),                                  # depolarizer
          np.array([[1, 1, 0, 0], [1, 1, 0, 0], [0, 0, 0, 0], [0, 0, 0, 0]]) / 2.0,  # polarizer
          np.array([[1, 0.3, 0, 0], [0.3, 1, 0, 0], [0, 0, 0.9, 0.1], [0, 0, -0.1, 0.9]]),
          np.zeros((4, 4))]
    for _ in range(8):
        m = rng.normal(size=(4, 4)) * 0.3
        m[0, 0] = 1.5
        ms.append(m)  # mostly non-physical: the Cloude filter path
    return np.array(ms)


def _nan(v):
    return np.nan if v is None else v


@pytest.mark.parametrize("filt", [True, False])
def test_decompose_equals_cli(cli, tmp_path, filt):
    ms = _matrices()
    batch = tmp_path / "m.txt"
    batch.write_text("\n".join(" ".join(repr(float(v)) for v in m.ravel()) for m in ms) + "\n")
    args = ["decompose", "--batch", batch] + ([] if filt else ["--no-filter"])
    lines = json_lines(cli(*args).stdout)
    d = polarcam.decompose(ms, filter=filt)
    names = {"D_singular": polarcam.LC_D_SINGULAR, "R_nonunique": polarcam.LC_R_NONUNIQUE,
             "nonphysical": polarcam.LC_NONPHYSICAL, "filtered": polarcam.LC_FILTERED,
             "clamped": polarcam.LC_CLAMPED, "zero_m00": polarcam.LC_ZERO_M00}
    assert len(lines) == len(ms)
    for i, o in enumerate(lines):
        for key in ("D", "R", "Delta", "m00", "R_linear", "R_circular", "depol_index"):
            np.testing.assert_array_equal(getattr(d, key)[i], _nan(o[key]), err_msg=f"{i} {key}")
        np.testing.assert_array_equal(d.diattenuation[i], [_nan(v) for v in o["diattenuation"]])
        np.testing.assert_array_equal(d.retardance_axis[i],
                                      [_nan(v) for v in o["retardance_axis"]])
        for key in ("M_D", "M_R", "M_Delta"):
            np.testing.assert_array_equal(getattr(d, key)[i],
                                          [[_nan(v) for v in r] for r in o[key]], err_msg=key)
        assert bool(d.physical[i]) == o["physical"] and bool(d.filtered[i]) == o["filtered"]
        assert int(d.flags[i]) == sum(names[n] for n in o["flags"]), (i, o["flags"])


def test_errors_carry_the_library_message(cli, tmp_path):
    """The same bad input gives the CLI's message (the library's detail) and the documented
    exception."""
    bad = tmp_path / "bad.json"
    doc = json.load(open(os.path.join(SCENES, "ideal_small.json")))
    doc["materials"]["black_paint"]["sigma"] = -1
    bad.write_text(json.dumps(doc))
    p = cli("render", bad, "-o", tmp_path / "o", check=False)
    assert p.returncode == 2
    with pytest.raises(ValueError) as e:
        polarcam.render(str(bad))
    assert "sigma" in str(e.value) and str(e.value) in p.stderr, (str(e.value), p.stderr)
    assert e.value.errname == "PC_EINVAL"
    # a 12-bit frame holding 4096: the library's value check names the pixel
    raw = np.full((240, 320), 100, np.uint16)
    raw[5, 7] = 4096
    np.save(tmp_path / "r.npy", raw)
    p = cli("process", tmp_path / "r.npy", "--bits", "12", "-o", tmp_path / "p", check=False)
    assert p.returncode == 2 and not (tmp_path / "p" / "stokes.npy").exists()
    with pytest.raises(ValueError) as e:
        polarcam.stokes(raw, bits=12)
    detail = str(e.value).removeprefix("raw: ")
    assert "pixel (7,5) = 4096" in detail and detail in p.stderr, (str(e.value), p.stderr)
    assert e.value.errname == "PC_ERANGE"
    # an unknown method: the library's list of methods
    p = cli("process", tmp_path / "r.npy", "-o", tmp_path / "p", "--method", "nope",
            check=False)
    with pytest.raises(ValueError) as e:
        polarcam.stokes(raw, method="nope")
    detail = str(e.value).removeprefix("method: ")
    assert "bilinear" in detail and detail in p.stderr, (str(e.value), p.stderr)
    # an odd size: the library's message
    with pytest.raises(ValueError, match="even"):
        polarcam.stokes(raw[:239])
    # a missing scene file: OSError (FileNotFoundError) naming it
    with pytest.raises(OSError) as e:
        polarcam.render(str(tmp_path / "missing.json"))
    assert "missing.json" in str(e.value)


def test_pbrdf_degrees_match_cli_conversion():
    """Angles are degrees as on the command line: theta_i = 0 is normal incidence, and the
    specular direction (theta_r = theta_i, phi = 180) carries the specular peak."""
    f = polarcam.pbrdf(1.5, 0, 0.1, 30, np.array([20.0, 30.0, 40.0]), 180)
    assert f[1, 0, 0] > f[0, 0, 0] and f[1, 0, 0] > f[2, 0, 0]
    assert math.isfinite(f[1, 0, 0])


def test_ratio_nr_noise_gain_cli(cli, tmp_path):
    """ratio-nr's noise model (docs/demosaicking.md Round 40): by default the slope of the frame's
    photon-transfer line, reported in the JSON (meta.json of process: "estimated"); given back
    with --noise-gain or noise_gain= it reproduces the output bit for bit, another gain changes
    it, and the module and the command line agree. The chart through the IMX250MZR preset
    (K 0.39 DN per e-): the estimate lies within a factor of 1.5 of K."""
    scene = os.path.join(SCENES, "stress", "noise_high.json")
    cli("render", scene, "-o", tmp_path / "rec", "--seed", "3")
    raw, _, meta = polarcam.render(scene, seed=3)
    png = tmp_path / "rec" / "raw_000000.png"
    p = cli("demosaic", png, "--method", "ratio-nr", "-o", tmp_path / "e.npy", "--json")
    j = json_lines(p.stdout)[0]
    assert j["noise_gain_from"] == "estimated" and 0.39 / 1.5 < j["noise_gain"] < 0.39 * 1.5, j
    g = j["noise_gain"]
    est = polarcam.demosaic(raw, method="ratio-nr", layout=meta["layout"], bits=meta["bits"])
    np.testing.assert_array_equal(est, np.load(tmp_path / "e.npy"))
    p = cli("demosaic", png, "--method", "ratio-nr", "--noise-gain", repr(g), "-o",
            tmp_path / "g.npy", "--json")
    j2 = json_lines(p.stdout)[0]
    assert j2["noise_gain_from"] == "option" and j2["noise_gain"] == g, j2
    np.testing.assert_array_equal(np.load(tmp_path / "g.npy"), est)
    np.testing.assert_array_equal(
        polarcam.demosaic(raw, method="ratio-nr", layout=meta["layout"], bits=meta["bits"],
                          noise_gain=g), est)
    assert not np.array_equal(
        polarcam.demosaic(raw, method="ratio-nr", layout=meta["layout"], bits=meta["bits"],
                          noise_gain=20 * g), est)
    assert {n["name"] for n in polarcam.methods() if n["noise_gain"]} >= {"ratio-nr"}
    # process: meta.json says estimated (per frame: no one value) or the option's value
    cli("process", png, "--method", "ratio-nr", "-o", tmp_path / "p")
    m = json.loads((tmp_path / "p" / "meta.json").read_text())
    assert m["noise_gain"] is None and m["noise_gain_from"] == "estimated", m
    cli("process", png, "--method", "ratio-nr", "--noise-gain", repr(g), "-o", tmp_path / "q")
    m = json.loads((tmp_path / "q" / "meta.json").read_text())
    assert m["noise_gain"] == g and m["noise_gain_from"] == "option", m
    np.testing.assert_array_equal(np.load(tmp_path / "p" / "dolp.npy"),
                                  np.load(tmp_path / "q" / "dolp.npy"))


def test_noise_gain_equals_cli(cli, tmp_path):
    """pan-adapt's noise gain on the command line (--noise-gain, docs/demosaicking.md Round 15b)
    and in the module, and pan-guard's (for its base pan-adapt): the JSON says which gain was
    used; the estimate it reports, given back with --noise-gain or noise_gain=, reproduces the
    estimated output bit for bit (17 significant digits round-trip a double); bad values and
    methods without a noise model are refused with exit status 2."""
    scene = os.path.join(SCENES, "colour_small.json")
    cli("render", scene, "-o", tmp_path / "rec", "--seed", "11")
    raw, _, meta = polarcam.render(scene, seed=11)
    png = tmp_path / "rec" / "raw_000000.png"
    p = cli("demosaic", png, "--method", "pan-adapt", "-o", tmp_path / "e.npy", "--json")
    j = json_lines(p.stdout)[0]
    assert j["noise_gain_from"] == "estimated" and j["noise_gain"] > 0, j
    est = polarcam.demosaic(raw, method="pan-adapt", layout=meta["layout"], bits=meta["bits"])
    np.testing.assert_array_equal(est, np.load(tmp_path / "e.npy"))
    g = j["noise_gain"]
    p = cli("demosaic", png, "--method", "pan-adapt", "--noise-gain", repr(g), "-o",
            tmp_path / "g.npy", "--json")
    j2 = json_lines(p.stdout)[0]
    assert j2["noise_gain_from"] == "option" and j2["noise_gain"] == g, j2
    np.testing.assert_array_equal(np.load(tmp_path / "g.npy"), est)
    np.testing.assert_array_equal(
        polarcam.demosaic(raw, method="pan-adapt", layout=meta["layout"], bits=meta["bits"],
                          noise_gain=g), est)
    # another gain changes the output (the option is not ignored)
    cli("demosaic", png, "--method", "pan-adapt", "--noise-gain", repr(20 * g), "-o",
        tmp_path / "h.npy")
    assert not np.array_equal(np.load(tmp_path / "h.npy"), est)
    # methods without a noise model: null in the JSON, the option refused
    p = cli("demosaic", png, "--method", "pan-side", "-o", tmp_path / "s.npy", "--json")
    j3 = json_lines(p.stdout)[0]
    assert j3["noise_gain"] is None and j3["noise_gain_from"] is None, j3
    p = cli("demosaic", png, "--method", "pan-side", "--noise-gain", "2", "-o",
            tmp_path / "x.npy", check=False)
    assert p.returncode == 2 and "uses no noise gain" in p.stderr, p.stderr
    # the refusal names exactly the methods that take one, from the table (not a hand list)
    said = re.search(r"the methods that do: ([^)]*)\)", p.stderr)
    assert said, p.stderr
    assert said.group(1).split(", ") == [m["name"] for m in polarcam.methods()
                                         if m["noise_gain"]], p.stderr
    # and a monochrome method on this colour frame names exactly the colour methods
    p = cli("demosaic", png, "--method", "bilinear", "-o", tmp_path / "x.npy", check=False)
    said = re.search(r"methods for it: ([^)]*)\)", p.stderr)
    assert p.returncode != 0 and said, p.stderr
    assert said.group(1).split(", ") == [m["name"] for m in polarcam.methods()
                                         if m["colour"]], p.stderr
    for bad in ("-1", "nan", "inf", "0"):
        p = cli("demosaic", png, "--method", "pan-adapt", "--noise-gain", bad, "-o",
                tmp_path / "x.npy", check=False)
        assert p.returncode == 2 and "--noise-gain" in p.stderr, (bad, p.stderr)
    assert not (tmp_path / "x.npy").exists()
    # which methods take it: the module and `demosaic --list --json` agree (pan-adapt, and
    # pan-guard for its base pan-adapt)
    listed = {m["name"]: m["noise_gain"] for m in json.loads(cli("demosaic", "--list",
                                                                 "--json").stdout)}
    assert listed == {m["name"]: m["noise_gain"] for m in polarcam.methods()}
    assert {"pan-adapt", "pan-guard"} <= {n for n, v in listed.items() if v}
    # pan-guard: the same round trip (its estimate is pan-adapt's, on the same frame), and
    # another gain changes its output
    p = cli("demosaic", png, "--method", "pan-guard", "-o", tmp_path / "ge.npy", "--json")
    j4 = json_lines(p.stdout)[0]
    assert j4["noise_gain_from"] == "estimated" and j4["noise_gain"] == g, j4
    gest = polarcam.demosaic(raw, method="pan-guard", layout=meta["layout"], bits=meta["bits"])
    np.testing.assert_array_equal(gest, np.load(tmp_path / "ge.npy"))
    p = cli("demosaic", png, "--method", "pan-guard", "--noise-gain", repr(g), "-o",
            tmp_path / "gg.npy", "--json")
    assert json_lines(p.stdout)[0]["noise_gain_from"] == "option"
    np.testing.assert_array_equal(np.load(tmp_path / "gg.npy"), gest)
    np.testing.assert_array_equal(
        polarcam.demosaic(raw, method="pan-guard", layout=meta["layout"], bits=meta["bits"],
                          noise_gain=g), gest)
    assert not np.array_equal(
        polarcam.demosaic(raw, method="pan-guard", layout=meta["layout"], bits=meta["bits"],
                          noise_gain=20 * g), gest)
    # process: meta.json says the same, and stokes(noise_gain=) gives its outputs
    cli("process", png, "--method", "pan-adapt", "--noise-gain", "1.5", "-o", tmp_path / "p")
    m = json.loads((tmp_path / "p" / "meta.json").read_text())
    assert m["noise_gain"] == 1.5 and m["noise_gain_from"] == "option", m
    s, dolp, aolp = stokes_cli_layout(raw, method="pan-adapt", layout=meta["layout"],
                                      bits=meta["bits"], noise_gain=1.5)
    np.testing.assert_array_equal(s, np.load(tmp_path / "p" / "stokes.npy"))
    np.testing.assert_array_equal(dolp, np.load(tmp_path / "p" / "dolp.npy"))
    s_est, _, _ = stokes_cli_layout(raw, method="pan-adapt", layout=meta["layout"],
                                    bits=meta["bits"])
    assert not np.array_equal(s, s_est)
    with pytest.raises(ValueError, match="noise_gain"):
        polarcam.stokes(raw, method="pan-adapt", layout=meta["layout"], noise_gain=-1.0)
    with pytest.raises(ValueError, match="noise_gain"):
        polarcam.stokes(np.zeros((8, 8, 4), np.float32), noise_gain=1.5)
