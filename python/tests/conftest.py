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


@pytest.fixture
def cli():
    """Runs the polarcam command line: cli(args...) -> CompletedProcess (text)."""
    if not CLI or not os.path.exists(CLI):
        pytest.skip("POLARCAM_CLI (the polarcam program) is not set: run through ctest")

    def run(*args, check=True, stdin=None):
        p = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, input=stdin)
        if check and p.returncode != 0:
            raise AssertionError(f"polarcam {' '.join(map(str, args))}: exit {p.returncode}\n"
                                 f"{p.stderr}")
        return p

    return run


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
