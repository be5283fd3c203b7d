#!/usr/bin/env bash
# Installs every Debian package the toolkit builds and tests with. Works as root (CI) and through
# sudo; pass extra package names as arguments.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git clang-format
  libsndfile1-dev libfftw3-dev libnlopt-cxx-dev libeigen3-dev
  libavformat-dev libavcodec-dev libswresample-dev libavutil-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev libfmt-dev
  python3-dev python3-numpy python3-pybind11 python3-pytest
  gnuplot-nox chromium
  # The ffmpeg command encodes the lossy recordings of the codec tests and bench/codec_timing_bench.
  ffmpeg
  # tests/json_schema_test.py validates every command's JSON against docs/schema/.
  python3 python3-jsonschema
  lammps liggghts mpi-default-bin
  "$@"
)

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
