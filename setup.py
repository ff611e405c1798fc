"""The wheel of the Python package (pyproject.toml): the package CMake assembles in
<build>/python/ramtk — the compiled ramtk._core, the Python layer, its stubs (py.typed) and the
robot models as package data — copied into the wheel as a platform wheel.

RAMTK_BUILD_DIR: the CMake build folder (default ./build). Unless RAMTK_WHEEL_PREBUILT=1, the
target ramtk_python is built there first (configured in Release when the folder has no build)."""
import os
import re
import shutil
import subprocess

from setuptools import Distribution, setup
from setuptools.command.build_py import build_py

HERE = os.path.dirname(os.path.abspath(__file__))
BUILD_DIR = os.path.abspath(os.environ.get("RAMTK_BUILD_DIR", os.path.join(HERE, "build")))
PACKAGE = os.path.join(BUILD_DIR, "python", "ramtk")


def version():
    with open(os.path.join(HERE, "CMakeLists.txt"), encoding="utf-8") as f:
        return re.search(r"project\(ramtk VERSION ([0-9.]+)", f.read()).group(1)


def build_with_cmake():
    if os.environ.get("RAMTK_WHEEL_PREBUILT") == "1":
        return
    if not os.path.exists(os.path.join(BUILD_DIR, "CMakeCache.txt")):
        subprocess.check_call(["cmake", "-S", HERE, "-B", BUILD_DIR, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"])
    subprocess.check_call(["cmake", "--build", BUILD_DIR, "--target", "ramtk_python"])


class BuildPackageFromCMake(build_py):
    """Copies the package CMake assembled instead of the source folder's Python files alone."""

    def run(self):
        build_with_cmake()
        if not any(f.startswith("_core.") and f.endswith(".so") for f in os.listdir(PACKAGE)):
            raise SystemExit(f"{PACKAGE} has no compiled _core module: build the target ramtk_python first")
        target = os.path.join(self.build_lib, "ramtk")
        shutil.rmtree(target, ignore_errors=True)
        shutil.copytree(PACKAGE, target, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


class BinaryDistribution(Distribution):
    """A platform wheel (cp311-cp311-linux_x86_64): the package holds a compiled module."""

    def has_ext_modules(self):
        return True


WORK = os.path.join(BUILD_DIR, "python-wheel")
os.makedirs(WORK, exist_ok=True)
setup(
    version=version(),
    packages=["ramtk"],
    package_dir={"ramtk": "python/ramtk"},
    cmdclass={"build_py": BuildPackageFromCMake},
    distclass=BinaryDistribution,
    options={"build": {"build_base": os.path.join(WORK, "build")}, "egg_info": {"egg_base": WORK}},
    zip_safe=False,
)
