"""Builds polarcam._polarcam with the project's CMake (python/CMakeLists.txt) and packages it.

pip runs this from a checkout (pip >= 21.3 builds local directories in place), so the
repository is the parent of this directory. Environment:
  POLARCAM_CMAKE_ARGS      extra CMake arguments ("-DPC_WITH_ARAVIS=OFF ...")
  CMAKE_BUILD_PARALLEL_LEVEL  parallel build jobs (default: the number of CPUs)
"""
import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def project_version():
    path = os.path.join(ROOT, "CMakeLists.txt")
    try:
        with open(path, encoding="utf-8") as f:
            m = re.search(r"project\(polarcam\s+VERSION\s+([0-9.]+)", f.read())
    except OSError:
        m = None
    if not m:
        sys.exit(f"polarcam: {path} not found or without a version: build from a checkout "
                 "of the polarcam repository (pip install ./python)")
    return m.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.path.join(os.path.abspath(self.build_temp), "cmake")
        cfg = ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release",
               f"-DPython3_EXECUTABLE={sys.executable}", "-DPC_WITH_PYTHON=ON",
               "-DPC_BUILD_TESTS=OFF", "-DPC_WERROR=OFF", "-DPC_PYTHON_BUNDLE=ON"]
        cfg += shlex.split(os.environ.get("POLARCAM_CMAKE_ARGS", ""))
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        if shutil.which("cmake") is None:
            sys.exit("polarcam: cmake is needed to build the library (Debian: ./do deps, or "
                     "apt-get install cmake build-essential pkg-config libpng-dev "
                     "libtiff-dev libjansson-dev libcairo2-dev)")
        subprocess.check_call(cfg)
        subprocess.check_call(["cmake", "--build", build, "--target", "pc_python", "-j", jobs])
        pkg = os.path.join(build, "python", "polarcam")
        built = [f for f in os.listdir(pkg) if f.startswith("_polarcam") and f.endswith(".so")]
        if len(built) != 1:
            sys.exit(f"polarcam: expected one _polarcam*.so in {pkg}, found {built}")
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(os.path.join(pkg, built[0]), dest)
        # the shared libpolarcam the module links (RPATH $ORIGIN), under its SONAME
        libs = [f for f in os.listdir(pkg) if f.startswith("libpolarcam.so.")]
        if len(libs) != 1:
            sys.exit(f"polarcam: expected one libpolarcam.so.* in {pkg}, found {libs}")
        shutil.copyfile(os.path.join(pkg, libs[0]), os.path.join(os.path.dirname(dest), libs[0]))


setup(
    version=project_version(),
    packages=["polarcam"],
    package_data={"polarcam": ["__init__.pyi", "py.typed"]},
    ext_modules=[Extension("polarcam._polarcam", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
