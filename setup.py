"""Builds the cmbrl Python package through CMake (see pyproject.toml): the compiled module
(cmbrl/_cmbrl*.so) and the pure-Python files as CMake lays them out in <build>/python/cmbrl."""
import os
import pathlib
import re
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py
from setuptools.dist import Distribution

ROOT = pathlib.Path(__file__).resolve().parent


def version():
    """The CMake project's version, the one `cmbrl --version` and cmbrl.__version__ give."""
    match = re.search(r"project\(cmbrl VERSION (\d+\.\d+\.\d+)", (ROOT / "CMakeLists.txt").read_text())
    if not match:
        raise RuntimeError("CMakeLists.txt names no project version")
    return match.group(1)


class CMakeBuildPy(build_py):
    """Configures (or reuses) the CMake build folder, builds the module, and copies the package
    CMake laid out into the wheel's tree."""

    def run(self):
        build_dir = pathlib.Path(os.environ.get("CMBRL_BUILD_DIR", ROOT / "build")).resolve()
        if not (build_dir / "CMakeCache.txt").exists():
            subprocess.check_call(["cmake", "-S", str(ROOT), "-B", str(build_dir),
                                   "-DCMAKE_BUILD_TYPE=Release", "-DCMBRL_BUILD_TESTS=OFF"])
        subprocess.check_call(["cmake", "--build", str(build_dir), "--target", "cmbrl_python"])
        package = build_dir / "python" / "cmbrl"
        target = pathlib.Path(self.build_lib) / "cmbrl"
        if target.exists():
            shutil.rmtree(target)
        shutil.copytree(package, target, ignore=shutil.ignore_patterns("__pycache__"))


class BinaryDistribution(Distribution):
    """The wheel holds a compiled module: tag it for this platform and interpreter."""

    def has_ext_modules(self):
        return True


setup(version=version(), packages=["cmbrl", "cmbrl.diagnostics"],
      package_dir={"": "python"}, cmdclass={"build_py": CMakeBuildPy},
      distclass=BinaryDistribution, zip_safe=False)
