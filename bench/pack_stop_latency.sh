#!/usr/bin/env bash
# How long `bouncecal pack` takes to stop after SIGTERM: the time from the signal to the exit of
# the process (finishing the step or block it is in, the checkpoint, the CSVs and summary.json),
# on a pour of COUNT spheres (default 20000: paper 000's pour, ten times wider). The signal is
# sent DELAYS seconds after the output folder appears (the handler is installed by then), one
# fresh run per delay; prints one row per run and the worst (docs/scenes.md, "Checkpoints and
# interruption").
#
#   bench/pack_stop_latency.sh BUILD_DIR [COUNT] [THREADS]     e.g. bench/pack_stop_latency.sh build
#
# Environment: STOP_DELAYS="4 7 10 13 16" (seconds), STOP_WORK=/tmp/bouncecal_stop_latency.
set -euo pipefail
build=${1:?usage: pack_stop_latency.sh BUILD_DIR [COUNT] [THREADS]}
count=${2:-20000}
threads=${3:-1}
delays=${STOP_DELAYS:-4 7 10 13 16}
work=${STOP_WORK:-/tmp/bouncecal_stop_latency}
exe="$build/apps/bouncecal"
mkdir -p "$work"

# Paper 000's pour (1 cm steel, walton-braun gamma_n = 0.5, friction, rotation, 10 us step) in a
# cylinder wide and tall enough that the first batch takes most of the spheres: the run is in
# its costly part (thousands of spheres moving, contacts forming) within seconds.
scene="$work/pour_$count.json"
radius=$(awk -v n="$count" 'BEGIN { printf "%.4f", 0.15 * sqrt(n / 20000) }')
cat >"$scene" <<JSON
{"format": "bouncecal-scene/1", "name": "stop_latency_$count",
 "particles": {"count": $count, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
 "container": {"type": "cylinder", "radius_m": $radius, "height_m": 0.6},
 "insertion": {"type": "pour", "batch_interval_s": 0.1, "seed": 1,
               "region": {"type": "cylinder", "radius_m": $(awk -v r="$radius" 'BEGIN { print r - 0.005 }'),
                          "z_min_m": 0.1, "z_max_m": 0.6}},
 "material": {"contact_law": {"law": "walton-braun",
                              "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
              "tangential_stiffness_n_per_m": 1e7, "friction": 0.3, "wall_friction": 0.3},
 "physics": {"tangential": true, "rotation": true},
 "time_step_s": 1e-5, "duration_s": 3, "gravity_mps2": 9.8,
 "measurement": {"band_m": [0.005, 0.1], "history_interval_s": 0.05}}
JSON

now() { date +%s.%N; }
field() { sed -n "s/^  \"$1\": \\([^,]*\\),*$/\\1/p" "$2"; }

echo "$count spheres, $threads thread(s), $(nproc) cores, load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| signal after (s) | stopped at step | status | signal to exit (s) | checkpoint (MB) |"
echo "| --- | --- | --- | --- | --- |"
worst=0
for delay in $delays; do
  out="$work/out"
  rm -rf "$out"
  "$exe" pack "$scene" --threads "$threads" --output "$out" >"$work/log.txt" 2>&1 &
  pid=$!
  while [ ! -d "$out" ]; do sleep 0.01; done
  sleep "$delay"
  start=$(now)
  kill -TERM "$pid"
  status=0
  wait "$pid" || status=$?
  seconds=$(awk -v a="$start" -v b="$(now)" 'BEGIN { printf "%.3f", b - a }')
  steps=$(field steps "$out/summary.json" || true)
  size=$(awk -v b="$(stat -c %s "$out/checkpoint.bcpack" 2>/dev/null || echo 0)" \
    'BEGIN { printf "%.1f", b / 1e6 }')
  echo "| $delay | ${steps:-?} | $status | $seconds | $size |"
  worst=$(awk -v a="$worst" -v b="$seconds" 'BEGIN { print (b > a ? b : a) }')
done
echo "worst signal to exit: $worst s"
