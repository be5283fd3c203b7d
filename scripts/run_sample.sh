#!/usr/bin/env bash
# Set-up command 1: install, build in Release, and run the main job on a shipped sample.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh -DBOUNCECAL_BUILD_BENCH=OFF -DBOUNCECAL_BUILD_TESTS=OFF
build/apps/bouncecal version
