"""Memory: no leaks over many calls (Python objects by tracemalloc, the library's C memory by
the resident set size), and large inputs used in place (peak resident size and tracemalloc
around a call, with a copy as the positive control that shows the meter works)."""
import gc
import os
import tempfile
import tracemalloc

import numpy as np
import pytest

import polarcam
from conftest import REPO, SANITIZED, write_calibration

pytestmark = pytest.mark.skipif(
    SANITIZED, reason="resident sizes are meaningless under AddressSanitizer (shadow memory, "
                      "quarantine); the sanitized build runs the other Python tests")


def _status(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1]) * 1024
    raise KeyError(key)


def rss():
    return _status("VmRSS")


def reset_peak():
    """Resets the peak resident size (VmHWM) to the current one (Linux >= 4.0)."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError as e:
        pytest.skip(f"cannot reset the peak resident size: {e}")


def peak():
    return _status("VmHWM")


def _round(fn, n):
    gc.collect()
    tracemalloc.start()
    t0, r0 = tracemalloc.get_traced_memory()[0], rss()
    for _ in range(n):
        fn()
    gc.collect()
    t1, r1 = tracemalloc.get_traced_memory()[0], rss()
    tracemalloc.stop()
    return t1 - t0, r1 - r0


def growth(fn, n, warm=50):
    """(traced Python bytes, resident bytes) gained over n calls after warm calls: the smaller
    of two rounds, because an interpreter table that grows once (a dict resized, an arena) is
    not a leak, while a leak grows in every round."""
    for _ in range(warm):
        fn()
    a, b = _round(fn, n), _round(fn, n)
    return min(a[0], b[0]), min(a[1], b[1])


def _raises(fn, exc):
    def call():
        try:
            fn()
        except exc:
            return
        raise AssertionError("no exception")
    return call


RAW = polarcam.render(roi=(0, 0, 64, 48))[0]
F4 = polarcam.demosaic(RAW)
M = np.stack([np.eye(4), np.diag([1.0, 0.5, 0.5, 0.2])])
PINV = polarcam.analyser_pinv(np.array([[.5, .5, 0], [.5, 0, .5], [.5, -.5, 0], [.5, 0, -.5]],
                                       np.float32))
OUT = polarcam.stokes(RAW)
BAD = RAW.astype(np.int32)
TMP = tempfile.TemporaryDirectory(prefix="polarcam-memory-")
CAL_PATH = write_calibration(os.path.join(TMP.name, "cal.npz"), 64, 48, dark=60.0)
CAL = polarcam.Calibration(CAL_PATH)

CALLS = {
    "stokes": lambda: polarcam.stokes(RAW, bits=12, threads=1),
    "stokes_out": lambda: polarcam.stokes(RAW, out=OUT, threads=1),
    "stokes_channels": lambda: polarcam.stokes(F4),
    "stokes_calibrated": lambda: polarcam.stokes(RAW, calibration=PINV, threads=1),
    "stokes_black": lambda: polarcam.stokes(RAW, black_level=10.0, threads=1),
    "stokes_valid": lambda: polarcam.stokes(RAW, saturation_level=4000, dead_level=1,
                                            threads=1),
    "stokes_calibration_file": lambda: polarcam.stokes(RAW, calibration=CAL, threads=1),
    "calibration_maps": lambda: (CAL.analysis, CAL.pinv_superpixel, CAL.provenance,
                                 CAL.parts, CAL.layout),
    "error_calibration": _raises(lambda: polarcam.stokes(RAW[:32], calibration=CAL),
                                 ValueError),
    "demosaic": lambda: polarcam.demosaic(RAW, method="eari", threads=1),
    "picture": lambda: polarcam.picture(OUT, kind="aolp"),
    "picture_specular": lambda: polarcam.picture(OUT, kind="specular"),
    "minmax": lambda: polarcam.minmax(OUT),
    "error_minmax": _raises(lambda: polarcam.minmax(OUT.s0), ValueError),
    "pbrdf": lambda: polarcam.pbrdf(1.5, 0.1, [0.1, 0.2], 30, 40, 150),
    "decompose": lambda: polarcam.decompose(M),
    "analyser_pinv": lambda: polarcam.analyser_pinv(np.ones((4, 3), np.float32) +
                                                    np.eye(4, 3, dtype=np.float32)),
    "methods": polarcam.methods,
    "error_dtype": _raises(lambda: polarcam.stokes(BAD), TypeError),
    "error_library": _raises(lambda: polarcam.stokes(RAW[:47]), ValueError),
    "error_bits": _raises(lambda: polarcam.stokes(RAW, bits=9), ValueError),
    "error_pbrdf": _raises(lambda: polarcam.pbrdf(1.5, 0, [0.2, -1], 10, 30), ValueError),
    "error_decompose": _raises(lambda: polarcam.decompose(np.full((4, 4), np.nan)),
                               ValueError),
}


@pytest.mark.parametrize("name", sorted(CALLS))
def test_ten_thousand_calls_leak_nothing(name):
    fn = CALLS[name]
    refs = [__import__("sys").getrefcount(x) for x in (RAW, F4, M, PINV, OUT, CAL)]
    traced, resident = growth(fn, 10000)
    # a leaked object per call would be >= 10000 x 16 bytes; a leaked C buffer of the smallest
    # output (64 x 48 floats) 120 MB
    assert traced < 16 * 1024, (name, traced)
    assert resident < 2 * 1024 * 1024, (name, resident)
    assert refs == [__import__("sys").getrefcount(x) for x in (RAW, F4, M, PINV, OUT, CAL)], name


@pytest.mark.parametrize("name", ["render", "open", "open_error", "calibration_read",
                                  "calibration_path", "calibration_error"])
def test_sources_and_simulator_leak_nothing(name):
    scene = os.path.join(REPO, "scenes", "ideal_small.json")

    def render():
        polarcam.render(scene, roi=(0, 0, 8, 8), threads=1)

    def open_():
        with polarcam.open(f"sim:{scene}?fps=0&threads=1", roi=(0, 0, 8, 8)) as s:
            s.read()
            s.stats()
            s.controls()

    fn = {"render": render, "open": open_,
          "open_error": _raises(lambda: polarcam.open("sim:default?bogus=1"), ValueError),
          "calibration_read": lambda: polarcam.Calibration(CAL_PATH).gain,
          "calibration_path": lambda: polarcam.stokes(RAW, calibration=CAL_PATH, threads=1),
          "calibration_error": _raises(lambda: polarcam.Calibration(CAL_PATH + ".missing"),
                                       FileNotFoundError)}[name]
    # slower calls (a simulator is built each time): fewer of them, the same per-call bound
    traced, resident = growth(fn, 100, warm=20)
    assert traced < 16 * 1024, (name, traced)
    assert resident < 2 * 1024 * 1024, (name, resident)


def _peak_during(fn):
    gc.collect()
    base = rss()
    reset_peak()
    tracemalloc.start()
    fn()
    traced_peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return peak() - base, traced_peak


def test_large_inputs_are_not_copied():
    h, w = 4096, 4096  # 32 MiB of uint16
    raw = np.random.default_rng(0).integers(0, 4096, (h, w), dtype=np.uint16)
    nbytes = raw.nbytes
    out = tuple(np.ones((h, w), np.float32) for _ in range(5))  # written: resident
    # the meter: a copy of the input shows as a peak of its size
    copy_peak, copy_traced = _peak_during(lambda: np.ascontiguousarray(raw[:, ::-1]))
    assert copy_peak > 0.9 * nbytes and copy_traced > 0.9 * nbytes, (copy_peak, copy_traced)
    for method in ("bilinear", "eari"):
        p, t = _peak_during(lambda: polarcam.stokes(raw, method=method, bits=12, out=out))
        assert p < 0.25 * nbytes, (method, p, nbytes)
        assert t < 64 * 1024, (method, t)
    # a crop of a larger frame: used in place too
    sub = raw[2:4002, 8:4008]
    sub_out = tuple(o[:4000, :4000] for o in out)
    p, t = _peak_during(lambda: polarcam.stokes(sub, out=sub_out))
    assert p < 0.25 * nbytes and t < 64 * 1024, (p, t)
    # float32 input
    f = raw.astype(np.float32)
    p, t = _peak_during(lambda: polarcam.stokes(f, out=out))
    assert p < 0.25 * f.nbytes and t < 64 * 1024, (p, t)
    # demosaic into a caller's array
    d = np.ones((h, w, 4), np.float32)
    p, t = _peak_during(lambda: polarcam.demosaic(raw, out=d))
    assert p < 0.25 * nbytes and t < 64 * 1024, (p, t)
