#!/usr/bin/env bash
# Set-up command 1: install what building and running `bouncecal` needs, build the command in
# Release (only the command: no tests, benchmarks, Python module or packing engine, whose force
# loops are most of a build's CPU), and run the main job on a shipped sample.
# scripts/run_tests.sh installs and builds the rest, the engine included.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
BOUNCECAL_BUILD_TARGETS=bouncecal scripts/build.sh -DBOUNCECAL_BUILD_BENCH=OFF \
  -DBOUNCECAL_BUILD_TESTS=OFF -DBOUNCECAL_PACKING_ENGINE=OFF
build/apps/bouncecal version
# The main job: the paper's experiment (1 cm steel ball, 0.20 m drop, eta-bar = 0.58), printing
# the fitted gamma_n with its analytic check, confidence interval and optimiser summary. The ball
# and the drop height are stated: calibrate assumes neither.
build/apps/bouncecal calibrate samples/steel_ball_h0.2m.wav --ball steel-10mm --drop-height-m 0.2
