"""The Python package's build for pip (pyproject.toml): setuptools packs python/bouncecal and an
extension that CMake builds, so `pip install --no-build-isolation .` compiles exactly what
`cmake --build build --target bouncecal_python` does (docs/python.md, "pip install").

CMake's build folder is build-pip/ in the checkout (ignored by git), kept between installs, so a
second install only rebuilds what changed. Environment: CMAKE_BUILD_PARALLEL_LEVEL sets the jobs
(default: every core); ccache, when on PATH, is the compiler launcher unless
BOUNCECAL_PIP_NO_CCACHE is set; BOUNCECAL_PIP_CMAKE_ARGS adds configure arguments;
BOUNCECAL_PIP_BUILD_DIR names a CMake build of this checkout that is already configured for the
same interpreter (the tests' build): its bouncecal_python target is built there as it is
configured, and setuptools' own files go there too.
"""

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
GIVEN_BUILD_DIR = os.environ.get("BOUNCECAL_PIP_BUILD_DIR")
CMAKE_BUILD_DIR = pathlib.Path(GIVEN_BUILD_DIR).resolve() if GIVEN_BUILD_DIR else ROOT / "build-pip"


def project_version():
    """The version of CMakeLists.txt's project(), the one bouncecal.__version__ reports."""
    text = (ROOT / "CMakeLists.txt").read_text()
    match = re.search(r"project\(bouncecal\s+VERSION\s+([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no `project(bouncecal VERSION x.y.z)`")
    return match.group(1)


class CMakeBuild(build_ext):
    """Builds bouncecal._bouncecal with CMake instead of compiling sources itself."""

    def build_extension(self, ext):
        if shutil.which("cmake") is None:
            raise RuntimeError("building bouncecal needs cmake (Debian: apt-get install cmake)")
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(CMAKE_BUILD_DIR),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DBOUNCECAL_BUILD_PYTHON=ON",  # a missing piece is an error, not a silent skip
            "-DBOUNCECAL_BUILD_TESTS=OFF",
            "-DBOUNCECAL_BUILD_BENCH=OFF",
            "-DBOUNCECAL_INSTALL=OFF",
            # The interpreter pip runs is the one the extension must load into (a venv's).
            f"-DPython3_EXECUTABLE={sys.executable}",
        ]
        if shutil.which("ccache") and not os.environ.get("BOUNCECAL_PIP_NO_CCACHE"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        configure += shlex.split(os.environ.get("BOUNCECAL_PIP_CMAKE_ARGS", ""))
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 1)
        build = ["cmake", "--build", str(CMAKE_BUILD_DIR), "--target", "bouncecal_python",
                 "-j", jobs]
        if not GIVEN_BUILD_DIR:  # a given build keeps its own configuration
            subprocess.run(configure, check=True)
        subprocess.run(build, check=True)

        built = sorted((CMAKE_BUILD_DIR / "python" / "bouncecal").glob("_bouncecal*.so"))
        if len(built) != 1:
            raise RuntimeError(f"expected one extension in {CMAKE_BUILD_DIR}, found {built}")
        target = pathlib.Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built[0], target)


# setuptools' build and egg-info folders, beside CMake's, emptied first: setuptools never removes
# a file from them, so a file taken out of the package would still be shipped. egg_info needs
# its folder to exist.
SETUPTOOLS_DIR = CMAKE_BUILD_DIR / "setuptools"
shutil.rmtree(SETUPTOOLS_DIR, ignore_errors=True)
SETUPTOOLS_DIR.mkdir(parents=True)

setup(
    version=project_version(),
    packages=["bouncecal"],
    package_dir={"": "python"},
    package_data={"bouncecal": ["*.pyi", "py.typed"]},
    ext_modules=[Extension("bouncecal._bouncecal", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # Not build/: that is where CONTRIBUTING.md's CMake build lives.
    options={"build": {"build_base": str(SETUPTOOLS_DIR)},
             "egg_info": {"egg_base": str(SETUPTOOLS_DIR)}},
    zip_safe=False,
)
