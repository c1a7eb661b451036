"""Build the geotex extension with the project's CMake (pip install . calls this through pyproject.toml).

The C++ library, the pybind11 module and the geotex CLI are built in build-pip/ (GEOTEX_PIP_BUILD_DIR)
with the interpreter pip runs under; the compiled module, its generated stubs and the CLI binary
(geotex/bin/geotex, run by the `geotex` command and `python -m geotex`) are copied into the package.

GEOTEX_PIP_REUSE=1 with GEOTEX_PIP_BUILD_DIR naming an already configured build tree (e.g. build/)
builds the needed targets there without configuring it again: the wheel from the same objects the tests
ran (scripts/test.sh does this; nothing is compiled twice)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        build = Path(os.environ.get("GEOTEX_PIP_BUILD_DIR", ROOT / "build-pip")).resolve()
        jobs = os.environ.get("GEOTEX_JOBS", str(os.cpu_count() or 2))
        reuse = os.environ.get("GEOTEX_PIP_REUSE") == "1" and (build / "CMakeCache.txt").is_file()
        if not reuse:
            subprocess.check_call([
                "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                "-DGEOTEX_BUILD_TESTS=OFF", "-DGEOTEX_BUILD_BENCH=OFF", "-DGEOTEX_BUILD_PYTHON=ON",
                f"-DPython3_EXECUTABLE={sys.executable}",
            ])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "geotex_python_stubs", "geotex_cli",
                               "-j", jobs])
        built = build / "python" / "geotex"
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        module = next(built.glob("_geotex*.so"))
        shutil.copyfile(module, target)
        for extra in ("__init__.pyi", "py.typed"):
            shutil.copyfile(built / extra, target.parent / extra)
        (target.parent / "bin").mkdir(exist_ok=True)
        shutil.copy2(build / "geotex", target.parent / "bin" / "geotex")  # keeps the executable bit
        # The shipped real models (spot.obj, CC0, with its licence): the installed `geotex demo` finds them
        # at geotex/data beside geotex/bin.
        (target.parent / "data").mkdir(exist_ok=True)
        for name in ("spot.obj", "README.md"):
            shutil.copyfile(ROOT / "data" / name, target.parent / "data" / name)


setup(ext_modules=[Extension("geotex._geotex", sources=[])], cmdclass={"build_ext": CMakeBuild})
