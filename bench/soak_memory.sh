#!/usr/bin/env bash
# Peak memory (max RSS, GNU time) of `bouncecal pack` against the particle count, and of
# `bouncecal analyze` against the recording length: each should be a straight line, and the
# slope is the memory per particle / per second of audio. Prints a Markdown table and the slope
# of a least-squares line through each series (docs/packing.md, "Memory").
#
#   bench/soak_memory.sh BUILD_DIR [COUNTS...]      e.g. bench/soak_memory.sh build 2000 20000
#
# Environment: SOAK_MINUTES="1 5 15" recording lengths in minutes (default "1 5 15"; the issue's
# 2 h needs ~1.3 GB of WAV in the work folder), SOAK_WORK=/tmp/bouncecal_soak.
set -euo pipefail
build=${1:?usage: soak_memory.sh BUILD_DIR [COUNTS...]}
shift
counts=("${@:-2000 20000 100000}")
read -r -a counts <<<"${counts[*]}"
minutes=${SOAK_MINUTES:-1 5 15}
work=${SOAK_WORK:-/tmp/bouncecal_soak}
exe="$build/apps/bouncecal"
mkdir -p "$work"

peak_kb() { /usr/bin/time -f '%M' "$@" 2>&1 >/dev/null | tail -1; }

# Spheres of 1 cm at a solid fraction of 0.15 in a cube: random placement finds room quickly,
# and the run is 20 steps (the memory is taken at set-up and the first neighbour list).
scene_for() {
  local n=$1 side
  side=$(awk -v n="$n" 'BEGIN { printf "%.4f", (n * 5.236e-7 / 0.15) ^ (1 / 3) }')
  cat >"$work/soak_$n.json" <<JSON
{"format": "bouncecal-scene/1", "name": "soak_$n",
 "particles": {"count": $n, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
 "container": {"type": "box", "min_m": [0, 0, 0], "max_m": [$side, $side, $side]},
 "insertion": {"type": "random", "region": {"type": "box", "min_m": [0, 0, 0],
                                            "max_m": [$side, $side, $side]}},
 "material": {"contact_law": {"law": "walton-braun"}},
 "time_step_s": 1e-5, "duration_s": 0.0002,
 "measurement": {"band_m": [0.005, 0.02]}}
JSON
  echo "$work/soak_$n.json"
}

fit() {  # "x y" lines -> slope and intercept of the least-squares line
  awk '{ n++; sx += $1; sy += $2; sxx += $1 * $1; sxy += $1 * $2 }
       END { s = (n * sxy - sx * sy) / (n * sxx - sx * sx); printf "%.6g %.6g\n", s, (sy - s * sx) / n }'
}

echo "| spheres | peak RSS (MB) |"
echo "| --- | --- |"
: >"$work/pack.txt"
for n in "${counts[@]}"; do
  kb=$(peak_kb "$exe" pack "$(scene_for "$n")" --output "$work/out_$n")
  echo "| $n | $(awk -v k="$kb" 'BEGIN { printf "%.1f", k / 1024 }') |"
  echo "$n $kb" >>"$work/pack.txt"
done
read -r slope intercept < <(fit <"$work/pack.txt")
awk -v s="$slope" -v i="$intercept" 'BEGIN { printf "pack: %.0f bytes per sphere + %.1f MB\n", s * 1024, i / 1024 }'

echo
echo "| recording (min) | peak RSS (MB) |"
echo "| --- | --- |"
: >"$work/analyze.txt"
for m in $minutes; do
  wav="$work/rec_${m}min.wav"
  s=$((m * 60))
  "$exe" synth -o "$wav" --drops $((s / 8)) --drop-gap-s 8 --duration-s "$s" >/dev/null
  kb=$(peak_kb "$exe" analyze "$wav")
  echo "| $m | $(awk -v k="$kb" 'BEGIN { printf "%.1f", k / 1024 }') |"
  echo "$s $kb" >>"$work/analyze.txt"
  rm -f "$wav"
done
read -r slope intercept < <(fit <"$work/analyze.txt")
awk -v s="$slope" -v i="$intercept" 'BEGIN { printf "analyze: %.1f kB per second of audio + %.1f MB\n", s, i / 1024 }'
