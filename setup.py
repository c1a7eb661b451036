"""Build the geotex extension with the project's CMake (pip install . calls this through pyproject.toml).

The C++ library and the pybind11 module are built in build-pip/ (GEOTEX_PIP_BUILD_DIR) with the
interpreter pip runs under; the compiled module and its generated stubs are copied into the package."""

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
        subprocess.check_call([
            "cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
            "-DGEOTEX_BUILD_TESTS=OFF", "-DGEOTEX_BUILD_BENCH=OFF", "-DGEOTEX_BUILD_PYTHON=ON",
            f"-DPython3_EXECUTABLE={sys.executable}",
        ])
        subprocess.check_call(["cmake", "--build", str(build), "--target", "geotex_python_stubs", "-j", jobs])
        built = build / "python" / "geotex"
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        module = next(built.glob("_geotex*.so"))
        shutil.copyfile(module, target)
        for extra in ("__init__.pyi", "py.typed"):
            shutil.copyfile(built / extra, target.parent / extra)


setup(ext_modules=[Extension("geotex._geotex", sources=[])], cmdclass={"build_ext": CMakeBuild})
