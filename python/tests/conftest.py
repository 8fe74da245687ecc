"""Shared helpers of the polarcam Python tests: the CLI (POLARCAM_CLI), a small PNG reader."""
import json
import os
import struct
import subprocess
import zlib

import numpy as np
import pytest

CLI = os.environ.get("POLARCAM_CLI")
SANITIZED = bool(os.environ.get("PCPY_SANITIZED"))
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _cli_runner():
    if not CLI or not os.path.exists(CLI):
        pytest.skip("POLARCAM_CLI (the polarcam program) is not set: run through ctest")

    def run(*args, check=True, stdin=None):
        p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, input=stdin)
        if check and p.returncode != 0:
            raise AssertionError(f"polarcam {' '.join(map(str, args))}: exit {p.returncode}\n"
                                 f"{p.stderr}")
        return p

    return run


@pytest.fixture
def cli():
    """Runs the polarcam command line: cli(args...) -> CompletedProcess (text)."""
    return _cli_runner()


@pytest.fixture(scope="module")
def cli_module():
    """cli for module-scoped fixtures."""
    return _cli_runner()


def write_calibration(path, width, height, dark, bits=12, layout=((90, 45), (135, 0))):
    """A calibration file (docs/calibration.md, version 1) of ideal analysers, unit gain and
    a constant dark offset, written with numpy: the analytic case of the calibrated
    pipeline."""
    ang = np.zeros((height, width))
    for dy in range(2):
        for dx in range(2):
            ang[dy::2, dx::2] = np.radians(layout[dy][dx])
    analysis = 0.5 * np.stack([np.ones_like(ang), np.cos(2 * ang), np.sin(2 * ang)], -1)
    # W+ of the ideal analysers, columns I0, I45, I90, I135 (core/include/polarcam/stokes.h)
    th = np.radians([0, 45, 90, 135])
    pinv = np.linalg.pinv(0.5 * np.stack([np.ones(4), np.cos(2 * th), np.sin(2 * th)], 1))
    lay = ",".join(str(layout[i][j]) for i in range(2) for j in range(2))
    meta = {"polarcam_calibration": 1, "camera": "synthetic", "width": width, "height": height,
            "offset_x": 0, "offset_y": 0, "sensor_width": 0, "sensor_height": 0, "bits": bits,
            "layout": lay, "black_level": float(dark), "saturation": float(2 ** bits - 1),
            "parts": ["dark", "flat", "analyser"], "provenance": {"software": "numpy"}}
    f32 = lambda a: np.ascontiguousarray(a, np.float32)  # noqa: E731
    np.savez(path, meta=np.frombuffer(json.dumps(meta).encode(), np.uint8),
             valid=np.ones((height, width), np.uint8),
             dark=f32(np.full((height, width), dark)), dark_noise=f32(np.ones((height, width))),
             gain=f32(np.ones((height, width))), analysis=f32(analysis),
             residual=f32(np.zeros((height, width))),
             pinv_superpixel=f32(np.broadcast_to(pinv[:, :, None, None],
                                                 (3, 4, height // 2, width // 2))))
    return path


def json_lines(text):
    return [json.loads(line) for line in text.splitlines() if line.strip()]


def read_png_rgb(path):
    """An 8-bit RGB or grey PNG (non-interlaced) as uint8 (H, W, C): the five filter types
    of the PNG specification (ISO/IEC 15948, section 9), enough for libpng/cairo output."""
    with open(path, "rb") as f:
        data = f.read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, hdr = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + n
    w, h, depth, ctype, _, _, interlace = hdr
    assert depth == 8 and interlace == 0 and ctype in (0, 2, 6), hdr
    ch = {0: 1, 2: 3, 6: 4}[ctype]
    raw = zlib.decompress(idat)
    stride = w * ch
    out = np.zeros((h, stride), np.int32)
    prev = np.zeros(stride, np.int32)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        cur = np.zeros(stride, np.int32)
        if ft in (0, 2):
            cur = (line + (prev if ft == 2 else 0)) & 255
        else:
            for x in range(stride):
                a = cur[x - ch] if x >= ch else 0
                b = prev[x]
                c = prev[x - ch] if x >= ch else 0
                if ft == 1:
                    p = a
                elif ft == 3:
                    p = (a + b) // 2
                else:  # Paeth
                    pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[x] = (line[x] + p) & 255
        out[y] = cur
        prev = cur
    return out.astype(np.uint8).reshape(h, w, ch)
