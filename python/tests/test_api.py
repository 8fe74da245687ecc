"""The polarcam module's own behaviour, against independently computed values: analytic
Stokes fields through the mosaic, numpy restatements of the documented formulas, round trips,
and the documented exceptions."""
import json
import os
import sys
import threading

import numpy as np
import pytest

import polarcam
from conftest import REPO

ANGLES = np.radians([0.0, 45.0, 90.0, 135.0])
IMX = [[2, 1], [3, 0]]  # layout 90,45,135,0: analyser channel at (y % 2, x % 2)


def mosaic_of_field(s0, s1, s2, layout=IMX, dtype=np.float32):
    """A raw mosaic of ideal analysers seeing Stokes images s0, s1, s2 (H, W):
    I_c = (S0 + S1 cos 2θ_c + S2 sin 2θ_c) / 2 (docs/physics.md §6, ideal analysers)."""
    h, w = s0.shape
    raw = np.empty((h, w), np.float64)
    for dy in range(2):
        for dx in range(2):
            c = layout[dy][dx]
            raw[dy::2, dx::2] = 0.5 * (s0 + s1 * np.cos(2 * ANGLES[c]) +
                                       s2 * np.sin(2 * ANGLES[c]))[dy::2, dx::2]
    return raw.astype(dtype)


def test_version():
    assert isinstance(polarcam.__version__, str)
    assert all(p.isdigit() for p in polarcam.__version__.split(".")), polarcam.__version__
    cm = open(os.path.join(REPO, "CMakeLists.txt")).read()
    assert f"VERSION {polarcam.__version__}" in cm


def test_every_public_function_has_a_docstring_and_a_stub():
    stub = open(os.path.join(os.path.dirname(polarcam.__file__), "__init__.pyi")).read()
    for name in polarcam.__all__:
        obj = getattr(polarcam, name)
        if callable(obj) and not isinstance(obj, type):
            assert obj.__doc__ and len(obj.__doc__) > 40, name
            assert f"def {name}(" in stub, name
        elif isinstance(obj, type):
            assert obj.__doc__, name
            assert f"class {name}" in stub, name


def test_stokes_of_a_uniform_field_is_exact():
    """Bilinear interpolation of constant channels is exact: the analytic Stokes vector comes
    back (float32), whatever the layout phase."""
    h, w = 16, 20
    for s in ((100.0, 30.0, -20.0), (7.0, 0.0, 7.0), (50.0, -50.0, 0.0)):
        f = [np.full((h, w), v) for v in s]
        for layout, lay in ((IMX, "90,45,135,0"), ([[0, 1], [3, 2]], "0,45,135,90")):
            st = polarcam.stokes(mosaic_of_field(*f, layout=layout), layout=lay)
            np.testing.assert_allclose(st.s0, s[0], rtol=1e-6)
            np.testing.assert_allclose(st.s1, s[1], atol=1e-4)
            np.testing.assert_allclose(st.s2, s[2], atol=1e-4)
            dolp = np.hypot(s[1], s[2]) / s[0]
            np.testing.assert_allclose(st.dolp, dolp, atol=1e-6)
            aolp = (0.5 * np.arctan2(s[2], s[1])) % np.pi
            if dolp > 0:
                d = np.abs(st.aolp - aolp)
                assert np.all(np.minimum(d, np.pi - d) < 1e-5)


def test_aolp_convention():
    """AoLP in [0, π), counter-clockwise from the image x axis: S2 > 0 is 45°, S1 < 0 is 90°."""
    ones = np.ones((8, 8))
    for (s1, s2), deg in (((1, 0), 0), ((0, 1), 45), ((-1, 0), 90), ((0, -1), 135)):
        st = polarcam.stokes(mosaic_of_field(2 * ones, s1 * ones, s2 * ones))
        np.testing.assert_allclose(np.degrees(st.aolp), deg, atol=1e-4)
        assert np.all((st.aolp >= 0) & (st.aolp < np.pi))


def test_stokes_from_channels_matches_the_formulas():
    rng = np.random.default_rng(1)
    i = rng.uniform(0, 1000, (12, 14, 4)).astype(np.float32)
    i[0, 0] = 0  # S0 = 0: DoLP 0
    st = polarcam.stokes(i)
    i64 = i.astype(np.float64)
    s0 = (i64[..., 0] + i64[..., 1] + i64[..., 2] + i64[..., 3]) / 2
    s1, s2 = i64[..., 0] - i64[..., 2], i64[..., 1] - i64[..., 3]
    np.testing.assert_allclose(st.s0, s0, rtol=1e-6)
    np.testing.assert_allclose(st.s1, s1, rtol=1e-6, atol=1e-3)
    np.testing.assert_allclose(st.s2, s2, rtol=1e-6, atol=1e-3)
    ref = np.where(s0 > 0, np.minimum(np.hypot(s1, s2) / np.where(s0 > 0, s0, 1), 1), 0)
    np.testing.assert_allclose(st.dolp, ref, atol=2e-6)
    assert st.dolp[0, 0] == 0
    # the demosaicked route equals the raw route (bilinear is linear)
    raw = polarcam.render(roi=(0, 0, 64, 48))[0]
    d = polarcam.demosaic(raw, bits=12)
    a, b = polarcam.stokes(d), polarcam.stokes(raw, bits=12)
    for name in ("s0", "s1", "s2"):
        np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-6, atol=1e-3)


def test_inputs_in_place_crops_and_phase():
    """Crops of a larger frame are used in place (row stride); an odd crop offset shifts the
    layout phase (@DX,DY) and gives the same values as a contiguous copy."""
    raw = polarcam.render(roi=(0, 0, 128, 96))[0]
    sub = raw[3:83, 5:105]
    assert not sub.flags.c_contiguous
    a = polarcam.stokes(sub, layout="90,45,135,0@1,1", bits=12)
    b = polarcam.stokes(np.ascontiguousarray(sub), layout="90,45,135,0@1,1", bits=12)
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)
    # the same region cropped at the sensor by the simulator: identical pixels
    roi = polarcam.render(roi=(5, 3, 100, 80))[0]
    np.testing.assert_array_equal(roi, sub)
    # demosaic into a caller's channel-major array (any positive strides)
    out = np.zeros((4, 80, 100), np.float32)
    polarcam.demosaic(sub, layout="90,45,135,0@1,1", bits=12, out=out.transpose(1, 2, 0))
    np.testing.assert_array_equal(out.transpose(1, 2, 0),
                                  polarcam.demosaic(np.ascontiguousarray(sub),
                                                    layout="90,45,135,0@1,1", bits=12))


def test_dtypes_and_copies():
    raw16 = polarcam.render(roi=(0, 0, 64, 48))[0]
    ref = polarcam.stokes(raw16.astype(np.float32))
    for dt in (np.uint16, np.float32):
        st = polarcam.stokes(raw16.astype(dt))
        np.testing.assert_allclose(st.s0, ref.s0, rtol=1e-6)
    raw8 = (raw16 >> 4).astype(np.uint8)
    np.testing.assert_allclose(polarcam.stokes(raw8).s0,
                               polarcam.stokes(raw8.astype(np.float32)).s0, rtol=1e-6)
    for bad in (np.int32, np.float64, np.int16, bool):
        with pytest.raises(TypeError, match="uint8, uint16 or float32"):
            polarcam.stokes(raw16.astype(bad))
    with pytest.raises(TypeError, match="numpy.ndarray"):
        polarcam.stokes(raw16.tolist())
    for bad in (np.asfortranarray(raw16), raw16[:, ::-1], raw16[::-1], raw16[:, ::2],
                raw16.byteswap().view(raw16.dtype.newbyteorder())):
        with pytest.raises(ValueError, match="ascontiguousarray"):
            polarcam.stokes(bad)
    with pytest.raises(ValueError, match=r"float32 \(H, W, 4\)"):
        polarcam.stokes(raw16[None])


def test_bad_input_gives_the_documented_exception():
    raw = polarcam.render(roi=(0, 0, 64, 48))[0]
    with pytest.raises(ValueError, match="even"):
        polarcam.stokes(raw[:47])
    hot = raw.copy()
    hot[1, 2] = 2000
    with pytest.raises(ValueError, match=r"pixel \(2,1\) = 2000: above the 10-bit range"):
        polarcam.stokes(hot, bits=10)
    polarcam.stokes(hot, bits=11)  # fits
    with pytest.raises(ValueError, match="layout"):
        polarcam.stokes(raw, layout="0,45,90,91")
    with pytest.raises(ValueError, match="colour-polarization"):
        polarcam.stokes(raw, layout="RGGB:90,45,135,0", method="bilinear")
    f = raw.astype(np.float32)
    f[3, 4] = np.nan
    with pytest.raises(ValueError, match=r"pixel \(4,3\)") as e:
        polarcam.demosaic(f)
    assert e.value.errname == "PC_ERANGE"
    with pytest.raises(ValueError, match="bits"):
        polarcam.stokes(raw, bits=40)
    with pytest.raises(ValueError, match="out"):
        polarcam.stokes(raw, out=[np.zeros((48, 64), np.float32)] * 4)
    with pytest.raises(ValueError, match="shape"):
        polarcam.stokes(raw, out=[np.zeros((48, 63), np.float32)] * 5)
    ro = np.zeros((48, 64), np.float32)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        polarcam.stokes(raw, out=[ro, None, None, None, None])
    with pytest.raises(ValueError, match=r"theta_i 95"):
        polarcam.pbrdf(1.5, 0, 0.2, [10, 95], 30)
    with pytest.raises(ValueError, match=r"sigma = -1"):
        polarcam.pbrdf(1.5, 0, [0.2, -1], 10, 30)
    with pytest.raises(ValueError, match="rho"):
        polarcam.pbrdf(1.5, 0, 0.2, 10, 30, rho="quad:1")
    m = np.stack([np.eye(4)] * 3)
    m[1, 2, 3] = np.inf
    with pytest.raises(ValueError, match=r"M\[1\]"):
        polarcam.decompose(m)
    with pytest.raises(ValueError, match="4, 4"):
        polarcam.decompose(np.eye(3))
    with pytest.raises(ValueError, match="kind"):
        polarcam.picture(np.zeros((4, 4), np.float32), kind="hue")


def test_out_reuses_arrays_and_skips_none():
    raw = polarcam.render(roi=(0, 0, 64, 48))[0]
    first = polarcam.stokes(raw, bits=12)
    again = polarcam.stokes(raw, bits=12, out=first)
    assert all(a is b for a, b in zip(first, again))
    sentinel = np.full((48, 64), -7, np.float32)
    st = polarcam.stokes(raw, bits=12, out=(None, None, None, sentinel, None))
    assert st.s0 is None and st.dolp is sentinel
    np.testing.assert_array_equal(sentinel, first.dolp)
    assert isinstance(st, polarcam.Stokes) and len(st) == 5


STOKES_FIELDS = ("s0", "s1", "s2", "dolp", "aolp")


def off_line(shape, dtype=np.float32, offset=16):
    """A C-contiguous array starting `offset` bytes past a 64-byte boundary (numpy's own large
    arrays start 16 bytes past one)."""
    n = int(np.prod(shape)) * np.dtype(dtype).itemsize
    buf = np.zeros(n + 128, np.uint8)
    k = (offset - buf.ctypes.data) % 64
    a = buf[k:k + n].view(dtype).reshape(shape)
    assert a.ctypes.data % 64 == offset
    return a


def test_new_arrays_start_on_a_cache_line():
    """Every new array the module returns starts on a 64-byte boundary, is C-contiguous,
    writeable and keeps its memory alive on its own."""
    raw, truth, _ = polarcam.render(roi=(0, 0, 96, 64))
    st = polarcam.stokes(raw, bits=12)
    found = {"raw": raw, "truth": truth, "demosaic": polarcam.demosaic(raw),
             "half": polarcam.demosaic(raw, method="superpixel-half"),
             "picture": polarcam.picture(st, kind="aolp"),
             "pbrdf": polarcam.pbrdf(1.5, 0.1, [0.1, 0.2], 30, 40, 150),
             "pinv": polarcam.analyser_pinv(np.ones((5, 4, 3), np.float32) +
                                            np.eye(4, 3, dtype=np.float32)),
             "decompose.D": polarcam.decompose(np.eye(4)).D}
    found.update({f"stokes.{k}": getattr(st, k) for k in STOKES_FIELDS})
    mm = polarcam.minmax(st)
    found.update({f"minmax.{k}": getattr(mm, k) for k in ("imin", "imax", "diffuse", "specular")})
    with polarcam.open("sim:default?seed=3&fps=0", roi=(0, 0, 64, 32)) as src:
        found["frame"] = src.read().raw
    for name, a in found.items():
        assert a.ctypes.data % 64 == 0, name
        assert a.flags.c_contiguous and a.flags.writeable and a.flags.aligned, name
    # the memory outlives every other reference to the result
    s0 = polarcam.stokes(raw, bits=12).s0
    import gc
    gc.collect()
    np.testing.assert_array_equal(s0, st.s0)
    s0 += 1  # writeable, and not shared with st
    assert not np.array_equal(s0, st.s0)


def test_aligned_and_unaligned_outputs_hold_the_same_values():
    """The same call into new (aligned) arrays and into out= arrays 16 bytes off a cache line
    (numpy's own alignment) writes the same bits: alignment changes the store instructions the
    library may use (streaming stores into whole lines), never the values. Also with
    POLARCAM_NT_MIN_BYTES=0 in a fresh interpreter, where the aligned outputs of this small
    frame are written with non-temporal stores (on AVX2 machines) and the others are not."""
    raw = polarcam.render(roi=(0, 0, 256, 128))[0]
    for method in ("bilinear", "ratio-nr", "eari"):
        new = polarcam.stokes(raw, method=method, bits=12)
        off = [off_line(raw.shape) for _ in range(5)]
        polarcam.stokes(raw, method=method, bits=12, out=off)
        for name, a, b in zip(STOKES_FIELDS, new, off):
            np.testing.assert_array_equal(a, b, err_msg=f"{method} {name}")
    d = off_line((128, 256, 4))
    polarcam.demosaic(raw, method="ratio-nr", out=d)
    np.testing.assert_array_equal(polarcam.demosaic(raw, method="ratio-nr"), d)
    import subprocess
    code = """if True:
        import sys, numpy as np, polarcam
        from polarcam import _polarcam
        sys.path.insert(0, sys.argv[1])
        from test_api import off_line
        raw = polarcam.render(roi=(0, 0, 256, 128))[0]
        for method in ("bilinear", "ratio-nr", "pan-ratio"):
            layout = "RGGB:90,45,135,0" if method.startswith("pan") else "90,45,135,0"
            new = polarcam.stokes(raw, method=method, layout=layout, bits=12)
            off = [off_line(raw.shape) for _ in range(5)]
            polarcam.stokes(raw, method=method, layout=layout, bits=12, out=off)
            for a, b in zip(new, off):
                np.testing.assert_array_equal(a, b, err_msg=method)
        print(_polarcam._stokes_streams(new), _polarcam._stokes_streams(off))
    """
    env = dict(os.environ, POLARCAM_NT_MIN_BYTES="0",
               PYTHONPATH=os.pathsep.join(filter(None, [
                   os.path.dirname(os.path.dirname(polarcam.__file__)),
                   os.environ.get("PYTHONPATH")])))
    here = os.path.dirname(os.path.abspath(__file__))
    p = subprocess.run([sys.executable, "-c", code, here], env=env, capture_output=True,
                       text=True)
    assert p.returncode == 0, p.stderr
    streamed, off_streamed = p.stdout.split()
    assert off_streamed == "False"
    # the library streams from AVX2 + FMA on (its x86-64 instances; POLARCAM_CPU may cap it)
    try:
        with open("/proc/cpuinfo") as f:
            flags = f.read().split()
    except OSError:
        flags = None
    import platform
    if flags is not None and platform.machine() == "x86_64" and not os.environ.get(
            "POLARCAM_CPU"):
        assert streamed == str("avx2" in flags and "fma" in flags)


def test_black_level():
    """Subtracting a black level before demosaicking equals doing it by hand (float32): the
    library subtracts it inside its fused integer kernels, a few float32 roundings apart from
    the float path (2.4e-7 relative measured; tolerance 1e-6 of each image's scale)."""
    raw = polarcam.render(roi=(0, 0, 64, 48))[0]
    for method in ("bilinear", "superpixel"):
        a = polarcam.stokes(raw, method=method, black_level=64)
        b = polarcam.stokes(raw.astype(np.float32) - 64, method=method)
        for x, y in zip(a, b):
            np.testing.assert_allclose(x, y, rtol=1e-6, atol=1e-6 * float(np.abs(y).max()))
    c = polarcam.stokes(raw, method="superpixel")
    np.testing.assert_allclose(a.s0, c.s0 - 128, rtol=1e-5)


def test_calibration():
    """Per-region analyser matrices: a mosaic made with non-ideal analysers W (transmission and
    orientation errors) is recovered exactly with W⁺, not by the ideal formulas."""
    h, w = 32, 40
    s = [np.full((h, w), 200.0), np.full((h, w), 60.0), np.full((h, w), -30.0)]
    theta = ANGLES + np.radians([1.5, -2.0, 0.5, 3.0])
    t = np.array([1.0, 0.95, 1.04, 0.9])
    W = np.stack([0.5 * t * np.ones(4), 0.5 * t * np.cos(2 * theta),
                  0.5 * t * np.sin(2 * theta)], axis=1)  # (4, 3)
    raw = np.empty((h, w))
    for dy in range(2):
        for dx in range(2):
            c = IMX[dy][dx]
            raw[dy::2, dx::2] = W[c, 0] * s[0][dy::2, dx::2] + W[c, 1] * s[1][dy::2, dx::2] + \
                W[c, 2] * s[2][dy::2, dx::2]
    raw = raw.astype(np.float32)
    pinv = polarcam.analyser_pinv(W.astype(np.float32))
    np.testing.assert_allclose(pinv, np.linalg.pinv(W), rtol=1e-5, atol=1e-6)
    st = polarcam.stokes(raw, calibration=pinv)
    np.testing.assert_allclose(st.s0, 200, rtol=1e-5)
    np.testing.assert_allclose(st.s1, 60, rtol=1e-4)
    np.testing.assert_allclose(st.s2, -30, rtol=1e-4)
    ideal = polarcam.stokes(raw)
    assert abs(float(ideal.s1.mean()) - 60) > 1  # the ideal formulas are off: the test can fail
    # a per-region grid of the same matrices (the library's layout (3, 4, GH, GW))
    grid = np.ascontiguousarray(np.broadcast_to(pinv[:, :, None, None], (3, 4, 3, 5)))
    # (a 3 x 5 grid runs in the library's scalar kernel, a 1 x 1 one in a vectorised one)
    np.testing.assert_allclose(polarcam.stokes(raw, calibration=grid).s1, st.s1, rtol=1e-6)
    # analyser_pinv of a grid of matrices gives that layout directly
    Wg = np.ascontiguousarray(np.broadcast_to(W.astype(np.float32), (3, 5, 4, 3)))
    np.testing.assert_array_equal(polarcam.analyser_pinv(Wg), grid)
    with pytest.raises(ValueError, match="rank-deficient"):
        polarcam.analyser_pinv(np.zeros((4, 3), np.float32))
    with pytest.raises(ValueError, match=r"\(3, 4, GH, GW\)"):
        polarcam.stokes(raw, calibration=np.zeros((4, 3), np.float32))
    with pytest.raises(TypeError, match="Calibration"):
        polarcam.stokes(raw, calibration=3)
    with pytest.raises(FileNotFoundError, match="no-such.npz"):
        polarcam.stokes(raw, calibration="no-such.npz")


def test_decompose_analytic():
    """Pure elements: a diattenuator with D = 0.6, a linear retarder of 1 rad, a depolarizer;
    the product of the factors gives M back (physics.md §3)."""
    D = 0.6
    diat = np.array([[1, D, 0, 0], [D, 1, 0, 0], [0, 0, np.sqrt(1 - D * D), 0],
                     [0, 0, 0, np.sqrt(1 - D * D)]]) * 0.5
    r = 1.0
    ret = np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, np.cos(r), np.sin(r)],
                    [0, 0, -np.sin(r), np.cos(r)]])
    dep = np.diag([1.0, 0.7, 0.7, 0.4])
    d = polarcam.decompose(np.stack([diat, ret, dep, dep @ ret @ diat]))
    np.testing.assert_allclose(d.D[:3], [D, 0, 0], atol=1e-12)
    np.testing.assert_allclose(d.R[1], r, atol=1e-12)
    np.testing.assert_allclose(d.Delta[2], 1 - (0.7 + 0.7 + 0.4) / 3, atol=1e-12)
    np.testing.assert_allclose(np.abs(d.retardance_axis[1]), [1, 0, 0], atol=1e-12)
    prod = d.m00[3] * d.M_Delta[3] @ d.M_R[3] @ d.M_D[3]
    np.testing.assert_allclose(prod, dep @ ret @ diat, atol=1e-12)
    assert d.physical.all() and d.flags.dtype == np.uint32
    one = polarcam.decompose(np.eye(4))
    assert one.D.shape == () and one.diattenuation.shape == (3,) and one.M_R.shape == (4, 4)


def test_pbrdf_broadcasting_and_reciprocity():
    n = np.array([1.3, 1.5, 1.7])[:, None, None]
    ti = np.array([10.0, 40.0])[None, :, None]
    tr = np.array([20.0, 50.0, 70.0])[None, None, :]
    f = polarcam.pbrdf(n, 0.1, 0.2, ti, tr, 160)
    assert f.shape == (3, 2, 3, 4, 4)
    assert f[2, 1, 0].tolist() == polarcam.pbrdf(1.7, 0.1, 0.2, 40, 20, 160).tolist()
    # Helmholtz reciprocity of the unpolarized element f00 (exchange theta_i and theta_r)
    a = polarcam.pbrdf(1.5, 0, 0.2, 30, 60, 150, diffuse="none")
    b = polarcam.pbrdf(1.5, 0, 0.2, 60, 30, 150, diffuse="none")
    assert a[0, 0] == pytest.approx(b[0, 0], rel=1e-9)


def test_pbrdf_from_threads():
    """Materials prepared once are shared between calls and threads (a cache of 64 with
    eviction): many materials from three threads give the single-threaded values."""
    sig = [np.linspace(0.05, 0.45, 50) + 1e-3 * k for k in range(6)]
    ref = [np.array([polarcam.pbrdf(1.5, 0.2, s, 30, 40, 150) for s in row]) for row in sig]
    got = [None] * 6

    def work(k):
        for j in range(k, 6, 3):
            got[j] = polarcam.pbrdf(1.5, 0.2, sig[j], 30, 40, 150)

    ts = [threading.Thread(target=work, args=(k,)) for k in range(3)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    for r, g in zip(ref, got):
        np.testing.assert_array_equal(r, g)


def test_bit_depth_check_finds_the_first_bad_pixel():
    raw = np.zeros((64, 64), np.uint16)
    for bits in (9, 10, 12, 14, 15):
        polarcam.stokes(raw + (2 ** bits - 1), bits=bits)  # the top value fits
        r = raw.copy()
        r[40, 33] = 2 ** bits
        r[50, 2] = 2 ** bits + 5
        with pytest.raises(ValueError, match=rf"pixel \(33,40\) = {2 ** bits}: above"):
            polarcam.stokes(r, bits=bits)
    r8 = np.full((64, 64), 127, np.uint8)
    polarcam.stokes(r8, bits=7)
    r8[3, 5] = 128
    with pytest.raises(ValueError, match=r"pixel \(5,3\) = 128"):
        polarcam.stokes(r8, bits=7)


def test_picture_colours():
    """The false colours of docs: AoLP 0 is red at DoLP 1, 60° green... (hue = AoLP over
    [0, π)), DoLP 0 is black in 'aolp' and white in 'aolp_sat'; grey is linear."""
    aolp = np.radians(np.array([[0.0, 60.0, 120.0, 30.0]], np.float32))
    dolp = np.array([[1.0, 1.0, 1.0, 0.0]], np.float32)
    rgb = polarcam.picture(aolp.astype(np.float32), kind="aolp", dolp=dolp)
    assert rgb.shape == (1, 4, 3) and rgb.dtype == np.uint8
    assert rgb[0, :3].tolist() == [[255, 0, 0], [0, 255, 0], [0, 0, 255]]
    assert rgb[0, 3].tolist() == [0, 0, 0]
    sat = polarcam.picture(aolp.astype(np.float32), kind="aolp_sat", dolp=dolp)
    assert sat[0, 3].tolist() == [255, 255, 255]
    g = polarcam.picture(np.array([[0.0, 0.5, 1.0]], np.float32), kind="grey", lo=0, hi=1)
    assert g[0, :, 0].tolist() == [0, 128, 255]
    with pytest.raises(ValueError, match="dolp"):
        polarcam.picture(aolp.astype(np.float32), kind="aolp")
    # a Stokes: the low-signal hatch where S0 is low
    raw, _, _ = polarcam.render(roi=(0, 0, 128, 96))
    st = polarcam.stokes(raw)
    plain = polarcam.picture(st, kind="dolp", mask_s0=0)
    masked = polarcam.picture(st, kind="dolp", mask_s0=float(np.percentile(st.s0, 30)))
    hatch = {52, 84}
    low = st.s0 < np.percentile(st.s0, 30)
    assert set(np.unique(masked[low][:, 0])) <= hatch
    np.testing.assert_array_equal(masked[~low], plain[~low])


def test_render_determinism_roi_and_scene_dict():
    raw, truth, meta = polarcam.render(seed=5, frame=[2, 0], roi=(10, 20, 64, 48))
    one, truth2, _ = polarcam.render(seed=5, frame=2, roi=(10, 20, 64, 48))
    np.testing.assert_array_equal(raw[0], one)  # frame N from (seed, N) alone
    np.testing.assert_array_equal(truth, truth2)
    assert not np.array_equal(raw[0], raw[1])  # noise differs between frames
    full = polarcam.render(seed=5, frame=2, roi=(0, 0, 128, 96))[0]
    np.testing.assert_array_equal(full[20:68, 10:74], one)  # a ROI is a crop
    assert meta["layout"] == "90,45,135,0" and meta["offset_x"] == 10
    assert meta["sequence"] == [2, 0] and meta["bits"] == 12 and meta["frame"] == [2, 0]
    gen = polarcam.render(seed=5, frame=(k for k in (1, 3)), roi=(0, 0, 16, 16))[2]
    assert gen["frame"] == [1, 3] and gen["sequence"] == [1, 3]
    path = os.path.join(REPO, "scenes", "ideal_small.json")
    doc = json.load(open(path))
    a = polarcam.render(path, seed=1)
    b = polarcam.render(doc, seed=1)
    np.testing.assert_array_equal(a[0], b[0])
    np.testing.assert_array_equal(a[1], b[1])
    assert b[2]["scene"]["sensor"]["preset"] == "ideal"
    # the truth in DN: an ideal noise-free sensor's bilinear Stokes ≈ dn_per_radiance · truth
    st = polarcam.stokes(a[0], bits=a[2]["bits"], black_level=a[2]["black_level_dn"])
    s0 = a[1][..., 0] * a[2]["dn_per_radiance"]
    lit = (s0 > 200) & (s0 < 3000)  # lit and far from saturation (S0 up to 2 x 4095)
    assert lit.mean() > 0.3
    err = np.abs(st.s0[lit] - s0[lit]) / s0[lit]
    assert np.median(err) < 0.005, np.median(err)
    # the truth is of this scene: another scene's truth does not match
    other = polarcam.render(seed=1)[1][:512, :612, 0] * a[2]["dn_per_radiance"]
    assert np.median(np.abs(st.s0[lit] - other[lit]) / s0[lit]) > 0.05


def test_render_mueller_truth():
    path = os.path.join(REPO, "scenes", "mueller_tetrahedral.json")
    raw, truth, meta = polarcam.render(path, roi=(200, 200, 32, 24))
    m = meta["truth_mueller"]
    assert m.shape == (24, 32, 4, 4) and m.dtype == np.float32
    assert meta["n_states"] > 1
    # the truth Stokes of state 0 is the Mueller truth applied to that state's generator:
    # both non-trivial here
    assert np.isfinite(m).all() and np.abs(m).max() > 0


def test_open_sim_equals_render():
    """Frames from open('sim:default?seed=3') equal render(seed=3) frames (the full sensor)."""
    n = 3
    raw, _, meta = polarcam.render(seed=3, frame=list(range(n)))
    with polarcam.open("sim:default?seed=3") as src:
        assert src.state == "ready"
        frames = [next(src) for _ in range(n)]
        assert src.state == "streaming"
        st = src.stats()
        assert st["completed"] == n and st["dropped"] == 0
    assert src.state == "closed"
    for k, fr in enumerate(frames):
        assert isinstance(fr, polarcam.Frame)
        np.testing.assert_array_equal(fr.raw, raw[k])
        assert fr.sequence == k and fr.bits == 12 and fr.layout == meta["layout"]
        assert fr.status & polarcam.FRAME_SIMULATED
    with pytest.raises(ValueError, match="closed"):
        src.read()


def test_open_controls_roi_and_file_end(tmp_path):
    with polarcam.open("sim:default?seed=1&fps=0", roi=(1, 0, 64, 48), exposure_us=300,
                       gain_db=2) as src:
        assert src.format["width"] == 64 and src.format["layout"] == "45,90,0,135"
        assert src.get("exposure_us") == 300
        c = src.controls()
        assert c["gain_db"]["value"] == 2 and c["exposure_us"]["min"] > 0
        fr = src.read()
        assert fr.raw.shape == (48, 64) and fr.layout == "45,90,0,135" and fr.offset_x == 1
        assert fr.exposure_us == 300 and fr.gain_db == 2
        # the ROI frame is the same crop of the sensor the simulator renders
        with polarcam.open("sim:default?seed=1&fps=0", exposure_us=300, gain_db=2,
                           roi=(0, 0, 66, 48)) as big:
            np.testing.assert_array_equal(big.read().raw[:, 1:65], fr.raw)
        with pytest.raises(ValueError, match="exposure_us"):
            src.set("exposure_us", -5)
        assert src.set("exposure_us", 200) == 200
        assert src.read().exposure_us == pytest.approx(200, rel=1e-12)
        assert src.info["scheme"] == "sim"
    with pytest.raises(TypeError, match="unknown control 'exposure'"):
        polarcam.open("sim:default", exposure=3)
    with pytest.raises(ValueError, match="nosuch"):
        polarcam.open("nosuch:thing")
    with pytest.raises(FileNotFoundError):
        polarcam.open(f"file:{tmp_path}/missing")
    with pytest.raises(ValueError, match="bogus"):
        polarcam.open("sim:default?bogus=1")


def test_file_source_iterates_to_the_end(tmp_path):
    pytest.importorskip("subprocess")
    cli = os.environ.get("POLARCAM_CLI")
    if not cli:
        pytest.skip("POLARCAM_CLI is not set")
    import subprocess

    subprocess.run([cli, "render", "-o", str(tmp_path), "--frames", "3", "--roi",
                    "0,0,32,32"], check=True, capture_output=True)
    with polarcam.open(f"file:{tmp_path}") as src:
        got = [fr.sequence for fr in src]
        assert got == [0, 1, 2]
        assert src.read() is None  # the end of a recording
        assert src.stats()["completed"] == 3


def test_gil_released_during_computation():
    """A second Python thread runs while stokes() computes. With a switch interval of 100 s
    the main thread can only run while the worker has released the GIL, so it must find the
    worker inside the call (no timing involved)."""
    raw = polarcam.render(roi=(0, 0, 512, 512))[0]
    big = np.tile(raw, (4, 4))
    state = {"inside": False, "seen_inside": None}
    started = threading.Event()

    def worker():
        state["inside"] = True
        started.set()
        polarcam.stokes(big, method="eari", threads=1)
        state["inside"] = False

    old = sys.getswitchinterval()
    sys.setswitchinterval(100)
    try:
        t = threading.Thread(target=worker)
        t.start()
        started.wait()
        state["seen_inside"] = state["inside"]
        t.join()
    finally:
        sys.setswitchinterval(old)
    assert state["seen_inside"] is True


def test_noise_gain_given_or_estimated():
    """pan-adapt's noise gain (docs/demosaicking.md, Round 15b): None estimates it from the
    frame, a number is used as given. A smooth colour field (RGGB over 90,45,135,0) with
    Gaussian noise of variance g0·(L + F), F = 1 % of full scale (the estimator's model,
    core/demosaic_noise.h): g0 given and the estimate give the same output to well under the
    noise (the estimate is within ~1 % of g0 here: RMS difference < 1 % of the RMS error
    against the truth), a gain 100x too small leaves more noise (a larger error), and the
    methods without a noise model ignore it."""
    rng = np.random.default_rng(1501)
    h, w, g0, fs = 512, 512, 2.0, 4095.0
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    s0 = 1500 + 500 * np.sin(2 * np.pi * x / 300) * np.cos(2 * np.pi * y / 260)
    col = [0.8 + 0.2 * np.sin(x / 200), np.ones_like(x), 0.7 + 0.2 * np.cos(y / 180)]
    d, phi = 0.3 + 0.2 * np.sin(x / 150), y / 300
    truth = np.empty((h, w, 12))
    for k in range(3):
        for c in range(4):
            truth[..., 4 * k + c] = s0 * col[k] * (1 + d * np.cos(2 * (ANGLES[c] - phi))) / 4
    # the mosaic: colour k of the 2x2 block (RGGB), analyser of the pixel in its block
    kk = np.array([[0, 1], [1, 2]])[(y // 2 % 2).astype(int), (x // 2 % 2).astype(int)]
    cc = np.array(IMX)[(y % 2).astype(int), (x % 2).astype(int)]
    lv = np.take_along_axis(truth, (4 * kk + cc)[..., None], axis=2)[..., 0]
    raw = (lv + np.sqrt(g0 * (lv + 0.01 * fs)) * rng.standard_normal((h, w))).astype(np.float32)
    lay = "RGGB:90,45,135,0"

    def run(g):
        return polarcam.demosaic(raw, method="pan-adapt", layout=lay, bits=12, noise_gain=g)

    def rmse(a):
        return float(np.sqrt(np.mean((a[8:-8, 8:-8] - truth[8:-8, 8:-8]) ** 2)))

    est, given, small = run(None), run(g0), run(g0 / 100)
    np.testing.assert_array_equal(est, polarcam.demosaic(raw, method="pan-adapt", layout=lay,
                                                         bits=12))
    diff = float(np.sqrt(np.mean((est.astype(np.float64) - given) ** 2)))
    assert 0 < diff < 0.01 * rmse(given), (diff, rmse(given))
    assert rmse(given) < rmse(small), (rmse(given), rmse(small))
    np.testing.assert_array_equal(
        polarcam.demosaic(raw, method="pan-side", layout=lay, bits=12, noise_gain=g0),
        polarcam.demosaic(raw, method="pan-side", layout=lay, bits=12))
    for bad in (-1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="noise_gain") as e:
            run(bad)
        assert e.value.errname == "PC_EINVAL"
    with pytest.raises(ValueError, match="noise_gain 0"):
        run(0)
    with pytest.raises(TypeError, match="noise_gain"):
        run("2")
