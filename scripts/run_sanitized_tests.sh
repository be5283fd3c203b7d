#!/usr/bin/env bash
# Builds with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and runs the test
# suite there, except the tests labelled `long` or `external` (cmake/BouncecalTesting.cmake):
# those simulate long or repeat a path over hundreds of seeds, or spend their time in LAMMPS,
# LIGGGHTS or Chromium; they run in the Release stage, and each module names beside its list the
# shorter test that drives the same code under the sanitizers. BOUNCECAL_SANITIZE_LONG=1 runs them
# here too. Any sanitizer report fails the run.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh --tests
# No -DNDEBUG: assert() and Eigen's index checks run here, the one build where a failure is cheap
# to read. -O0 -g1: unoptimised, and line tables only (enough for file:line in every report) instead of
# full debug info. The sanitizers' documentation suggests -O1 for speed, but here the build is
# the cost and the tests are not: on 2 cores -O1 took 459 s to build and 39.5 s to test, -O0
# 233 s and 44 s (the packing engines' template instantiations under ASan+UBSan: 98 s -> 46 s
# for engine_3d.cc alone). -O0 finds at least what -O1 finds (no access is optimised away).
# Benchmarks are not built: they measure speed, which a sanitized build does not have.
# -no-pie: UBSan's per-check data at -O0 is ~170 MB of pointers, which a position-independent
# executable relocates at every start; the CLI tests start the sanitized `bouncecal` hundreds of times,
# and without PIE each start costs half the CPU (0.6 s instead of 1.15 s, measured 2026-11-28).
# With both, the ctest below took 405 s wall (800 test-seconds) against 1386 s (2744) before,
# measured on one 2-core host on 2026-11-28 (the earlier run on a busier host).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O0 -g1" -DBOUNCECAL_SANITIZE=ON \
  -DCMAKE_EXE_LINKER_FLAGS=-no-pie -DBOUNCECAL_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
skip_long=(-LE 'long|external')
[ "${BOUNCECAL_SANITIZE_LONG:-0}" = 1 ] && skip_long=()
ctest --test-dir build-asan --output-on-failure -j"$(nproc)" "${skip_long[@]}"
