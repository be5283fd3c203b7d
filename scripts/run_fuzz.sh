#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/, clang with ASan+UBSan) into build-fuzz/ and runs each from
# its seed corpus in fuzz/corpus/<target>/ for a bounded time. Any crash, sanitizer report, leak
# or timeout fails the run and leaves the reproducer in build-fuzz/findings/<target>/: turn it
# into a regression test (tests/bad_input_test.cc) before fixing.
#
#   BOUNCECAL_FUZZ_SECONDS=30   seconds per target (default 30)
#
# In CI this is a regression check, not a campaign: every run first replays the committed seed
# corpus (libFuzzer executes every input of both corpus folders before mutating), then mutates
# for the given time. 30 s: from an empty scratch corpus the scene and start-positions targets
# reached 95 % of the coverage a 60 s run ends with after about 24 s and 13 s (previous session's
# logs, idle machine); the last few edges of a 60 s run came one or two at a time. Longer
# campaigns: BOUNCECAL_FUZZ_SECONDS=3600 scripts/run_fuzz.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
# The build's packages, and clang with its libFuzzer/sanitizer runtimes, needed only here (the
# fuzz build has no tests, benchmarks or Python module).
scripts/install_deps.sh clang libclang-rt-14-dev
seconds="${BOUNCECAL_FUZZ_SECONDS:-30}"
# -O1 -g1, libFuzzer's documented flags, instead of RelWithDebInfo's -O2 -g: the four targets
# built in 215 instead of 254 s (347 / 419 CPU s, 2 cores, 2026-12-04) and ran 70-88 % as many
# inputs per second (recording 148 / 208, scene 7171 / 8177), which the 30 s per target can
# spare; line tables still give every report its file:line.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
  -DBOUNCECAL_FUZZ=ON -DBOUNCECAL_BUILD_TESTS=OFF -DBOUNCECAL_BUILD_BENCH=OFF \
  -DBOUNCECAL_PACKING_ENGINE=OFF >/dev/null
targets=(recording material_card scene particle_file)
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]/#/fuzz_}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
# Leaks inside third-party decoders (libvorbis through libsndfile) are reported upstream, not
# ours to fix; the file names each one.
export LSAN_OPTIONS="suppressions=${PWD}/fuzz/lsan_suppressions.txt"
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# libFuzzer runs one process on one core: the targets run side by side, as many at once as there
# are cores (2 in CI: 4 x 30 s in 60 s of wall time instead of 120, each target still given its
# whole core).
run_target() {
  local target="$1" status=0
  # The seed corpus stays untouched; new inputs go to a scratch corpus inside build-fuzz.
  local work="build-fuzz/corpus/${target}" findings="build-fuzz/findings/${target}"
  mkdir -p "${work}" "${findings}"
  build-fuzz/fuzz/fuzz_"${target}" -max_total_time="${seconds}" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="${findings}/" \
    "${work}" "fuzz/corpus/${target}" >"build-fuzz/${target}.log" 2>&1 || status=$?
  echo "${status}" >"build-fuzz/${target}.status"
}
for target in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  echo "fuzz_${target}: ${seconds} s"
  rm -f "build-fuzz/${target}.status"
  run_target "${target}" &
done
wait
failed=()
for target in "${targets[@]}"; do
  echo "=== fuzz_${target}"
  tail -n 20 "build-fuzz/${target}.log"
  status="$(cat "build-fuzz/${target}.status" 2>/dev/null || echo "none")"
  if [ "${status}" != 0 ]; then
    echo "fuzz_${target}: FAILED (status ${status}); reproducer in build-fuzz/findings/${target}/, log in build-fuzz/${target}.log" >&2
    failed+=("${target}")
  fi
done
# Every target runs even after a finding, so one CI run shows all of them.
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: all targets ran ${seconds} s each without a finding"
