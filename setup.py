"""The build of `pip install .` (pyproject.toml): CMake builds the extension wisp._wisp for the
Python that runs pip, and setuptools installs it with python/wisp.

WISP_BUILD_DIR=DIR builds in DIR (an existing build tree is reused, so a tree already built
only checks that the module is up to date); otherwise in setuptools' temporary folder, which
takes a few minutes on 2 cores. CMAKE_ARGS adds options to the configuration."""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = pathlib.Path(__file__).resolve().parent


def version() -> str:
    """project(wisp VERSION x.y.z) of CMakeLists.txt: the one place the version is written."""
    m = re.search(r"project\(wisp VERSION ([0-9.]+)", (ROOT / "CMakeLists.txt").read_text())
    if not m:
        sys.exit("setup.py: no project(wisp VERSION ...) in CMakeLists.txt")
    return m.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        build = pathlib.Path(os.environ.get("WISP_BUILD_DIR") or
                             pathlib.Path(self.build_temp).resolve() / "cmake")
        if not (build / "CMakeCache.txt").exists():
            configure = ["cmake", "-S", str(ROOT), "-B", str(build), "-DCMAKE_BUILD_TYPE=Release",
                         "-DWISP_BUILD_TESTS=OFF", "-DWISP_BUILD_BENCHMARKS=OFF",
                         f"-DPython_EXECUTABLE={sys.executable}"]
            if shutil.which("ninja"):
                configure += ["-G", "Ninja"]
            configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
            subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build), "--target", "_wisp"], check=True)
        built = sorted((build / "python" / "wisp").glob("_wisp*.so"))
        if not built:
            sys.exit(f"setup.py: the build left no _wisp*.so in {build / 'python' / 'wisp'}")
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built[0], target)


setup(version=version(),
      ext_modules=[Extension("wisp._wisp", sources=[])],
      cmdclass={"build_ext": CMakeBuild})
