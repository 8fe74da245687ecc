#!/usr/bin/env python3
"""Benchmark of the polarcam Python module (not a test: it prints, it does not judge).

In one run, on one 2448x2048 12-bit frame of the default scene (or --raw FILE.npy):
  1. polarcam.stokes (bilinear -> S0, S1, S2, DoLP, AoLP) against the same C pipeline timed in
     C without the interpreter (goal: <= 1.1x), with new output arrays and with out=;
  2. against polanalyser's bilinear pipeline when polanalyser is importable (it is not a
     Debian package: skipped with a message), and against OUR plain-numpy restatement of that
     pipeline (bilinear by a 3x3 convolution of each analyser's samples, Stokes by the
     analyser pseudo-inverse, DoLP, AoLP; float64 as polanalyser), labelled as ours;
  3. two Python threads on two cores against one (goal >= 1.7x one thread's throughput: the
     GIL is released while the library computes), for bilinear (memory-bound) and ratio-nr
     (compute-bound), each beside the C library's own scaling from one thread to two (one
     call with threads=1 against threads=2, timed in C) in the same rounds: when Python's
     two-thread ratio matches the library's, the limit is the machine (memory bandwidth),
     not the GIL; and bilinear again on a 640x512 crop (a live-view ROI) whose data fit in
     the CPU's last-level cache, where the memory bus does not bound two threads;
  4. the calibrated pipeline: stokes(raw, calibration=Calibration) of a full-frame calibration
     file (written here with numpy: per-pixel dark, gain and analysers with the spreads of the
     imx250mzr_nonuniform preset) against the uncalibrated stokes(raw, black_level=...), and
     per-pixel pseudo-inverses passed as an array (the front door's fused calibrated path).
Times are medians of interleaved repeats; the machine may be shared, so the ratios (measured
in the same run) and the load average are what to read.

usage: python3 python/bench_polarcam.py [--raw FILE.npy] [--repeats N] [--threads-repeats N]
                                        [--threads-rounds R] [--calibrated-only | --threads-only]
       (PYTHONPATH=build/python when polarcam is not installed)
"""
import argparse
import json
import os
import statistics
import sys
import tempfile
import threading
import time

import numpy as np

# this file sits beside the package's sources (python/polarcam/, without the built module):
# import the built or installed package instead
_here = os.path.dirname(os.path.abspath(__file__))
sys.path[:] = [p for p in sys.path if os.path.abspath(p or os.curdir) != _here]
import polarcam  # noqa: E402
from polarcam import _polarcam  # noqa: E402


def load():
    return os.getloadavg()[0]


def median_ms(ts):
    return 1e3 * statistics.median(ts)


def numpy_pipeline(raw):
    """OUR numpy restatement of polanalyser's bilinear -> Stokes -> DoLP/AoLP (not
    polanalyser itself): each analyser's samples spread by the bilinear kernel
    [1 2 1; 2 4 2; 1 2 1] / 4 over a zero-filled plane, S = A+ I with A the ideal analyser
    matrix 0.5 (1, cos 2t, sin 2t), DoLP = |S12| / S0, AoLP = atan2(S2, S1) / 2 mod pi."""
    h, w = raw.shape
    img = raw.astype(np.float64)
    # layout 90,45,135,0: (row, column) of each angle's samples in the 2x2 block
    pos = {0: (1, 1), 45: (0, 1), 90: (0, 0), 135: (1, 0)}
    chans = []
    for ang in (0, 45, 90, 135):
        dy, dx = pos[ang]
        sparse = np.zeros((h + 2, w + 2))
        sparse[1 + dy:h + 1:2, 1 + dx:w + 1:2] = img[dy::2, dx::2]
        c = (4 * sparse[1:-1, 1:-1] + 2 * (sparse[:-2, 1:-1] + sparse[2:, 1:-1] +
                                           sparse[1:-1, :-2] + sparse[1:-1, 2:]) +
             sparse[:-2, :-2] + sparse[:-2, 2:] + sparse[2:, :-2] + sparse[2:, 2:]) / 4
        chans.append(c)
    images = np.stack(chans, axis=-1)  # (H, W, 4)
    t = np.radians([0, 45, 90, 135])
    A = 0.5 * np.stack([np.ones(4), np.cos(2 * t), np.sin(2 * t)], axis=1)  # (4, 3)
    stokes = images @ np.linalg.pinv(A).T  # (H, W, 3)
    s0, s1, s2 = stokes[..., 0], stokes[..., 1], stokes[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        dolp = np.sqrt(s1 ** 2 + s2 ** 2) / s0
    aolp = np.mod(0.5 * np.arctan2(s2, s1), np.pi)
    return s0, s1, s2, dolp, aolp


def polanalyser_pipeline(pa, raw):
    img = pa.demosaicing(raw, pa.COLOR_PolarMono)
    images = np.stack(img, axis=-1) if isinstance(img, list) else img
    stokes = pa.calcStokes(images, np.radians([0, 45, 90, 135]))
    return pa.cvtStokesToDoLP(stokes), pa.cvtStokesToAoLP(stokes)


def write_calibration(path, h, w, bits, seed=1):
    """A calibration file (docs/calibration.md) of a non-ideal camera: dark 60 DN + 1 DN
    spread, gain 1 +- 1 %, analysers with orientation errors of 0.8 deg, transmission 2 %,
    diattenuation 0.95 (the spreads of the imx250mzr_nonuniform preset)."""
    rng = np.random.default_rng(seed)
    th = np.zeros((h, w))
    for dy, row in enumerate(((90, 45), (135, 0))):
        for dx, a in enumerate(row):
            th[dy::2, dx::2] = a
    th = np.radians(th + rng.normal(0, 0.8, (h, w)))
    t = 1 + rng.normal(0, 0.02, (h, w))
    d = 0.95
    analysis = 0.5 * t[..., None] * np.stack([np.ones((h, w)), d * np.cos(2 * th),
                                              d * np.sin(2 * th)], -1)
    # W+ per 2x2 block: the four pixels' analysis vectors, rows in analyser order 0/45/90/135
    order = {0: (1, 1), 45: (0, 1), 90: (0, 0), 135: (1, 0)}
    Wb = np.stack([analysis[dy::2, dx::2] for dy, dx in (order[a] for a in (0, 45, 90, 135))],
                  axis=2)  # (H/2, W/2, 4, 3)
    pinv_sp = np.linalg.pinv(Wb).transpose(2, 3, 0, 1)
    meta = {"polarcam_calibration": 1, "camera": "bench", "width": w, "height": h,
            "offset_x": 0, "offset_y": 0, "sensor_width": 0, "sensor_height": 0, "bits": bits,
            "layout": "90,45,135,0", "black_level": 60.0, "saturation": float(2 ** bits - 1),
            "parts": ["dark", "flat", "analyser"], "provenance": {"software": "bench"}}
    f32 = lambda a: np.ascontiguousarray(a, np.float32)  # noqa: E731
    np.savez(path, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8),
             valid=np.ones((h, w), np.uint8), dark=f32(60 + rng.normal(0, 1, (h, w))),
             dark_noise=f32(np.ones((h, w))), gain=f32(1 + rng.normal(0, 0.01, (h, w))),
             analysis=f32(analysis), residual=f32(np.zeros((h, w))), pinv_superpixel=f32(pinv_sp))


def timed(fn, n):
    ts = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return ts


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--raw", help="a (2048, 2448) uint16 .npy raw frame (default: render)")
    ap.add_argument("--repeats", type=int, default=15)
    ap.add_argument("--threads-repeats", type=int, default=10,
                    help="frames per thread in each round of part 3")
    ap.add_argument("--threads-rounds", type=int, default=5,
                    help="rounds of part 3 (one thread, two threads, C alternately)")
    ap.add_argument("--calibrated-only", action="store_true",
                    help="only part 4 (the calibrated pipeline and the calibration file)")
    ap.add_argument("--threads-only", action="store_true",
                    help="only part 3 (one thread against two, bilinear and ratio-nr)")
    a = ap.parse_args()
    print(f"polarcam {polarcam.__version__} Python module benchmark; "
          f"{os.cpu_count()} CPUs, load average {load():.2f} at start")
    if a.raw:
        raw = np.load(a.raw)
        bits = 12
    else:
        t0 = time.perf_counter()
        raw, _, meta = polarcam.render(seed=0)
        bits = meta["bits"]
        print(f"frame: the default scene, seed 0, {raw.shape[1]}x{raw.shape[0]} "
              f"{bits}-bit (rendered in {time.perf_counter() - t0:.1f} s)")
    h, w = raw.shape
    # new arrays of the module (64-byte aligned: the library may stream into them), reused
    out = polarcam.stokes(raw)
    print(f"stores into polarcam's own (H, W) outputs: "
          f"{'non-temporal' if _polarcam._stokes_streams(out) else 'ordinary'} "
          f"(POLARCAM_NT_MIN_BYTES={os.environ.get('POLARCAM_NT_MIN_BYTES', 'unset')})")

    if a.threads_only:
        threads_all(a, raw)
    else:
        if not a.calibrated_only:
            parts_1_to_3(a, raw, out, h, w, bits)
        calibrated(a, raw, out, h, w, bits)
    print(f"\nload average at the end: {load():.2f} (ratios above are same-run)")


def parts_1_to_3(a, raw, out, h, w, bits):
    # 1. Python vs C (all cores, the library's default)
    polarcam.stokes(raw, out=out)
    np_out = polarcam.Stokes([np.ones((h, w), np.float32) for _ in range(5)])
    c, py_out, py_np, py_new, py_bits, alloc = [], [], [], [], [], []
    for _ in range(a.repeats):  # interleaved: load changes hit all alike
        c += _polarcam._c_pipeline_seconds(raw, out, repeats=1)
        py_out += timed(lambda: polarcam.stokes(raw, out=out), 1)
        py_np += timed(lambda: polarcam.stokes(raw, out=np_out), 1)
        py_new += timed(lambda: polarcam.stokes(raw), 1)
        py_bits += timed(lambda: polarcam.stokes(raw, bits=bits, out=out), 1)
        # the floor of new arrays: five fresh (H, W) float32 arrays written once
        alloc += timed(lambda: [np.empty((h, w), np.float32).fill(0) for _ in range(5)], 1)
    cm = median_ms(c)
    print(f"\n1. bilinear -> Stokes/DoLP/AoLP on {w}x{h}, all cores, median of {a.repeats} "
          f"(load {load():.2f})")
    print(f"   C pipeline (timed in C)                      {cm:8.2f} ms   1.00x")
    np_kind = "non-temporal" if _polarcam._stokes_streams(np_out) else "ordinary"
    for name, ts in (("polarcam.stokes(raw, out=out)", py_out),
                     (f"  out= numpy's arrays ({np_kind} stores)", py_np),
                     ("polarcam.stokes(raw) (new arrays)", py_new),
                     (f"polarcam.stokes(raw, bits={bits}, out=out) (+check)", py_bits)):
        print(f"   {name:45s}{median_ms(ts):8.2f} ms   {median_ms(ts) / cm:.2f}x")
    print(f"   (numpy: 5 new {w}x{h} float32 arrays, filled  {median_ms(alloc):8.2f} ms: the "
          f"cost of fresh memory)")
    # the same on one core (the comparison with single-threaded numpy)
    c1 = _polarcam._c_pipeline_seconds(raw, out, threads=1, repeats=max(3, a.repeats // 3))
    p1 = timed(lambda: polarcam.stokes(raw, out=out, threads=1), max(3, a.repeats // 3))
    print(f"   one core: C {median_ms(c1):.2f} ms, polarcam.stokes {median_ms(p1):.2f} ms "
          f"({median_ms(p1) / median_ms(c1):.2f}x)")

    # 2. polanalyser and our numpy restatement of its pipeline (one core: numpy's loops)
    print(f"\n2. against polanalyser's bilinear pipeline (load {load():.2f})")
    try:
        import polanalyser as pa  # noqa: F401
    except ImportError:
        pa = None
        print("   polanalyser: not importable (it is not a Debian package): skipped")
    n2 = 3
    npy = timed(lambda: numpy_pipeline(raw), n2)
    print(f"   OUR numpy restatement of it (not polanalyser) {median_ms(npy):8.1f} ms   "
          f"polarcam.stokes one core is {median_ms(npy) / median_ms(p1):.0f}x faster, "
          f"all cores {median_ms(npy) / median_ms(py_out):.0f}x")
    ref = numpy_pipeline(raw)
    st = polarcam.stokes(raw)
    inner = (slice(2, -2), slice(2, -2))
    dd = np.abs(st.dolp[inner] - np.clip(np.nan_to_num(ref[3][inner]), 0, 1)).max()
    print(f"   same result: max |DoLP difference| inside the 2-pixel border {dd:.1e}")
    if pa is not None:
        try:
            tp = timed(lambda: polanalyser_pipeline(pa, raw), n2)
            print(f"   polanalyser {getattr(pa, '__version__', '?')}               "
                  f"{median_ms(tp):8.1f} ms   polarcam.stokes is "
                  f"{median_ms(tp) / median_ms(py_out):.0f}x faster (goal >= 20x)")
        except Exception as e:  # an API of another polanalyser version
            print(f"   polanalyser: its pipeline failed here ({e!r}): skipped")

    # 3. two Python threads on two cores against one, beside the library's own scaling
    threads_all(a, raw)


def l3_cache_bytes():
    """The last-level (L3) cache size from Linux's sysfs (cpu0), 0 when it says none."""
    base = "/sys/devices/system/cpu/cpu0/cache"
    try:
        for d in sorted(os.listdir(base)):
            with open(os.path.join(base, d, "level")) as f:
                if f.read().strip() != "3":
                    continue
            with open(os.path.join(base, d, "size")) as f:
                v = f.read().strip()
            mult = {"K": 1 << 10, "M": 1 << 20, "G": 1 << 30}.get(v[-1:], 1)
            return int(v.rstrip("KMG")) * mult
    except (OSError, ValueError):
        pass
    return 0


def threads_all(a, raw):
    """Part 3: the full frame for bilinear and ratio-nr, then bilinear on a 640x512 crop of
    it (a live-view ROI): its input and five outputs, 7.2 MB per thread, fit with the other
    thread's in the 32 MB L3 cache of a current server CPU (printed: the machine's own), so
    the memory bus does not bound two threads there and what is left to limit them is the
    interpreter's lock."""
    for method in ("bilinear", "ratio-nr"):
        threads_scaling(a, raw, method)
    # an even origin keeps the mosaic phase; the crop is a new C-contiguous array
    roi = np.ascontiguousarray(raw[:512, :640])
    l3 = l3_cache_bytes()
    need = 2 * roi.size * (roi.itemsize + 5 * 4)
    print(f"\n(the 640x512 crop: two threads' input and outputs {need / 1e6:.1f} MB; this "
          f"machine's L3 cache {f'{l3 / 2**20:.0f} MiB' if l3 > 0 else 'unknown'}"
          f"{'' if l3 <= 0 else ': they fit' if need <= l3 else ': they do NOT fit'})")
    threads_scaling(a, roi, "bilinear",
                    scale=max(1, (raw.shape[0] * raw.shape[1]) // (roi.shape[0] * roi.shape[1])))


def threads_scaling(a, raw, method, scale=1):
    """Frames per second of one Python thread, of two Python threads (each calling
    polarcam.stokes(raw, method, threads=1, out=its own arrays)), and of the C library called
    with threads=1 and threads=2 (timed in C, no interpreter), in interleaved rounds: each
    ratio two/one is taken within a round, so load changes between rounds do not enter it.
    scale multiplies the frames per round (small frames: rounds of comparable length)."""
    n, rounds = a.threads_repeats * scale, a.threads_rounds
    outs = [polarcam.stokes(raw, method=method) for _ in range(2)]  # aligned, warm
    # numpy's own arrays (16 bytes past a cache line): never streamed, the store-kind baseline
    np_out = polarcam.Stokes([np.ones(raw.shape, np.float32) for _ in range(5)])
    outs.append(np_out)

    def work(k):
        for _ in range(n):
            polarcam.stokes(raw, method=method, out=outs[k], threads=1)

    def two_threads():
        ths = [threading.Thread(target=work, args=(k,)) for k in range(2)]
        for t in ths:
            t.start()
        for t in ths:
            t.join()

    py1, py2, c1, c2, pyo = [], [], [], [], []
    for _ in range(rounds):
        py1.append(n / timed(lambda: work(0), 1)[0])
        pyo.append(n / timed(lambda: work(2), 1)[0])
        py2.append(2 * n / timed(two_threads, 1)[0])
        c1.append(n / sum(_polarcam._c_pipeline_seconds(raw, outs[0], method=method,
                                                         threads=1, repeats=n)))
        c2.append(n / sum(_polarcam._c_pipeline_seconds(raw, outs[0], method=method,
                                                         threads=2, repeats=n)))
    kind = "non-temporal" if _polarcam._stokes_streams(outs[0]) else "ordinary"
    print(f"\n3. {method} -> Stokes/DoLP/AoLP, {raw.shape[1]}x{raw.shape[0]}, one thread "
          f"against two on {os.cpu_count()} "
          f"CPUs: frames/s, median of {rounds} rounds of {n} frames per thread ({kind} "
          f"stores; load {load():.2f})")
    for name, one, two in (("two Python threads, threads=1 each", py1, py2),
                           ("C library, one call threads=1 vs 2", c1, c2)):
        r = [t / o for o, t in zip(one, two)]
        print(f"   {name:37s} {statistics.median(one):7.1f} -> {statistics.median(two):7.1f}"
              f"   {statistics.median(r):.2f}x (rounds {min(r):.2f}-{max(r):.2f})")
    r = [a / b for a, b in zip(py1, pyo)]
    print(f"   one Python thread into numpy's arrays {statistics.median(pyo):7.1f} frames/s "
          f"(ordinary stores, 16 bytes off a line); into the aligned ones "
          f"{statistics.median(r):.2f}x that (rounds {min(r):.2f}-{max(r):.2f})")
    rp = statistics.median([t / o for o, t in zip(py1, py2)])
    rc = statistics.median([t / o for o, t in zip(c1, c2)])
    print(f"   Python's scaling / the library's: {rp / rc:.2f} (1: the GIL takes nothing; "
          f"goal for Python >= 1.7x on two idle cores)")


def calibrated(a, raw, out, h, w, bits):
    # 4. calibrated pipeline
    with tempfile.TemporaryDirectory(prefix="polarcam-bench-") as tmp:
        path = os.path.join(tmp, "cam.npz")
        write_calibration(path, h, w, bits)
        t0 = time.perf_counter()
        cal = polarcam.Calibration(path)
        t_read = time.perf_counter() - t0
        # the same file through numpy (every member read), the baseline of the reading time
        t0 = time.perf_counter()
        with np.load(path) as z:
            _ = [z[k] for k in z.files]
        t_np = time.perf_counter() - t0
        first = timed(lambda: polarcam.stokes(raw, calibration=cal, out=out), 1)
        pinv = cal.pinv("bilinear")
        n4 = max(3, a.repeats // 3)
        unc, calt, arr = [], [], []
        for _ in range(n4):
            unc += timed(lambda: polarcam.stokes(raw, black_level=60.0, out=out), 1)
            calt += timed(lambda: polarcam.stokes(raw, calibration=cal, out=out), 1)
            arr += timed(lambda: polarcam.stokes(raw, black_level=60.0, calibration=pinv,
                                                 out=out), 1)
        um = median_ms(unc)
        print(f"\n4. calibrated bilinear pipeline, all cores, median of {n4} (load "
              f"{load():.2f})")
        print(f"   reading the {w}x{h} calibration file {1e3 * t_read:.0f} ms "
              f"(numpy.load of every member {1e3 * t_np:.0f} ms, {t_read / t_np:.2f}x); first "
              f"calibrated frame (makes the compact calibration once) {median_ms(first):.0f} ms")
        for name, ts in (("stokes(raw, black_level=60) (uncalibrated)", unc),
                         ("stokes(raw, calibration=Calibration)", calt),
                         ("stokes(raw, black_level, calibration=W+ array)", arr)):
            print(f"   {name:47s}{median_ms(ts):8.2f} ms   {median_ms(ts) / um:.2f}x")


if __name__ == "__main__":
    sys.exit(main())
