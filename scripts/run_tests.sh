#!/usr/bin/env bash
# Set-up command 2: install, build everything (tests and benchmarks), run the whole test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh --tests
scripts/build.sh -DBOUNCECAL_BUILD_TESTS=ON -DBOUNCECAL_BUILD_BENCH=ON -DBOUNCECAL_WARNINGS_AS_ERRORS=ON
cd build
ctest --output-on-failure -j"$(nproc)"
