#!/usr/bin/env bash
# Configures and builds into build/ (Release). Extra arguments go to cmake's configure step;
# BOUNCECAL_BUILD_TARGETS="a b" builds only those targets (default: all). The packing engine is
# built unless an argument says -DBOUNCECAL_PACKING_ENGINE=OFF (the first README command's
# calibration-only build), even over a build/ that command configured.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBOUNCECAL_PACKING_ENGINE=ON "$@" >/dev/null
targets=()
for target in ${BOUNCECAL_BUILD_TARGETS:-}; do targets+=(--target "${target}"); done
cmake --build build -j"$(nproc)" "${targets[@]}"
