"""ctest python_pip: `pip install --no-build-isolation ./python` works offline (--no-index)
with Debian's pip, setuptools and numpy, into a virtual environment that sees the system's
packages, from a fresh copy of the sources; the installed module then works from elsewhere.
Exit 77 (skipped) when pip, setuptools, wheel, venv or numpy is missing."""
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile

root = os.path.abspath(sys.argv[1])
# find_spec, not import: importing pip and then setuptools in one process trips setuptools'
# distutils shim
for mod in ("pip", "setuptools", "wheel", "venv", "numpy"):
    if importlib.util.find_spec(mod) is None:
        print(f"SKIP: the Python module {mod} is missing (Debian: python3-pip python3-numpy)")
        sys.exit(77)

CHECK = r"""
import os, sys
import numpy as np
import polarcam
assert os.path.realpath(polarcam.__file__).startswith(os.path.realpath(sys.prefix)), \
    polarcam.__file__
# a uniform field through the mosaic comes back exactly (bilinear)
ang = np.radians([90, 45, 135, 0])  # the 2x2 block of layout 90,45,135,0, row-major
s0, s1, s2 = 100.0, 30.0, -20.0
block = 0.5 * (s0 + s1 * np.cos(2 * ang) + s2 * np.sin(2 * ang))
raw = np.tile(block.reshape(2, 2), (8, 8)).astype(np.float32)
st = polarcam.stokes(raw)
assert np.allclose(st.s0, s0) and np.allclose(st.s1, s1, atol=1e-4), st.s1
raw, truth, meta = polarcam.render(roi=(0, 0, 32, 32))
assert raw.shape == (32, 32) and meta["bits"] == 12
# the shared libpolarcam in use is the copy installed beside the module
here = os.path.dirname(os.path.realpath(polarcam._polarcam.__file__))
with open("/proc/self/maps") as f:
    libs = {l.split()[-1] for l in f if "libpolarcam.so" in l}
assert libs and all(os.path.dirname(os.path.realpath(p)) == here for p in libs), (libs, here)
print("libpolarcam:", sorted(libs))
print("installed polarcam", polarcam.__version__, "works")
"""

with tempfile.TemporaryDirectory(prefix="polarcam-pip-") as tmp:
    src = os.path.join(tmp, "src")
    shutil.copytree(root, src, ignore=shutil.ignore_patterns(
        ".git", "build*", "*.egg-info", "__pycache__", "polarcam-demo", "out"))
    venv = os.path.join(tmp, "venv")
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", "--system-site-packages",
                    venv], check=True)
    py = os.path.join(venv, "bin", "python")
    env = dict(os.environ, PIP_NO_INDEX="1", PIP_DISABLE_PIP_VERSION_CHECK="1",
               CMAKE_BUILD_PARALLEL_LEVEL=os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2"))
    env.pop("PYTHONPATH", None)
    r = subprocess.run([py, "-m", "pip", "install", "--no-build-isolation", "--no-index",
                        "./python"], cwd=src, env=env, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout[-4000:], r.stderr[-4000:])
        sys.exit(f"pip install failed with exit status {r.returncode}")
    print(r.stdout.strip().splitlines()[-1])
    r = subprocess.run([py, "-c", CHECK], cwd=tmp, env=env, capture_output=True, text=True)
    print(r.stdout, r.stderr)
    sys.exit(r.returncode)
