"""Builds the deformflow extension with the project's CMake (the module links the same C++
library as the tools; its dependencies are Debian packages CMake finds, which setuptools alone
could not). DEFORMFLOW_BUILD=DIR reuses an existing CMake build folder instead of a fresh one."""
import os
import pathlib
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent.parent


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = pathlib.Path(os.environ.get("DEFORMFLOW_BUILD") or pathlib.Path(self.build_temp).resolve() / "cmake")
        build.mkdir(parents=True, exist_ok=True)
        subprocess.run(["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                        "-DDEFORMFLOW_PYTHON=ON", f"-DPython3_EXECUTABLE={sys.executable}"], check=True)
        jobs = str(os.cpu_count() or 1)
        subprocess.run(["cmake", "--build", str(build), "--target", "deformflow", "-j", jobs], check=True)
        built = next((build / "python").glob("deformflow*.so"))
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, target)


setup(ext_modules=[Extension("deformflow", sources=[])], cmdclass={"build_ext": CMakeBuild})
