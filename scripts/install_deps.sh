#!/usr/bin/env bash
# Installs the Debian packages bouncecal needs. Works as root (CI) and through sudo.
#
#   scripts/install_deps.sh            what building and running the `bouncecal` command needs
#                                      (set-up command 1, scripts/run_sample.sh)
#   scripts/install_deps.sh --tests    that, plus what the test suite, the benchmarks, the Python
#                                      module and the format check need (set-up command 2,
#                                      scripts/run_tests.sh, and CI)
#
# Extra arguments are more package names (scripts/run_fuzz.sh adds clang).
set -euo pipefail

# The compiler, CMake and the libraries of the top-level CMakeLists.txt: libsndfile, FFTW,
# NLopt, Eigen (build only), the FFmpeg headers (the libraries are loaded at run time for
# M4A/AAC, WebM, ...), nlohmann-json, fmt and CLI11 (header-only, the command line).
packages=(
  build-essential cmake pkg-config
  libsndfile1-dev libfftw3-dev libnlopt-cxx-dev libeigen3-dev
  libavformat-dev libavcodec-dev libswresample-dev libavutil-dev
  nlohmann-json3-dev libfmt-dev libcli11-dev
)

test_packages=(
  # GoogleTest and Google Benchmark (tests/, bench/); git and clang-format for
  # scripts/check_format.sh.
  libgtest-dev libgmock-dev libbenchmark-dev git clang-format
  # The Python module and its tests (docs/python.md): pandas for to_dataframe(), venv and pip for
  # the `pip install --no-build-isolation .` test, mypy for stubtest (the .pyi stubs against the
  # module).
  python3-dev python3-numpy python3-pybind11 python3-pytest python3-pandas python3-venv python3-pip
  python3-mypy
  # --plot and pack's density curves (gnuplot); the HTML report's headless-browser test.
  gnuplot-nox chromium
  # The ffmpeg command encodes the lossy recordings of the codec tests and bench/codec_timing_bench.
  ffmpeg
  # tests/json_schema_test.py validates every command's JSON against docs/schema/.
  python3 python3-jsonschema
  # The exported decks are verified by running them (export-check tests).
  lammps liggghts mpi-default-bin
)

if [ "${1:-}" = "--tests" ]; then
  shift
  packages+=("${test_packages[@]}")
fi
packages+=("$@")

if [ "$(id -u)" -eq 0 ]; then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
else
  echo "install_deps.sh: run as root or install sudo" >&2
  exit 1
fi

missing=()
for package in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" ||
    missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing: ${missing[*]}"
  "${as_root[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${as_root[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}"
fi
