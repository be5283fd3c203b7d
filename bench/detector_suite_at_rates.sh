#!/usr/bin/env bash
# The detector development suite (../shared/detector-suite) at other sample rates: every recording
# resampled by ffmpeg (its default resampler, as a phone app or an editor would), its exact truth
# unchanged (onsets are file times), scored by the suite's own run.sh and score.py (recall >= 0.95,
# no false alarm, p95 onset error <= 200 us, eta-bar within 0.01). A held-out file at 16 kHz is
# scored the same way; the suite itself is 48 kHz but for three files.
#
#   bench/detector_suite_at_rates.sh BOUNCECAL [RATE_HZ ...]     default rates: 16000 22050
#
# Environment: SUITE=../shared/detector-suite, SUITE_RATES_WORK=/tmp/bouncecal_suite_rates (the
# resampled copies are kept there and made again only when missing). Prints each rate's SUMMARY
# line and the cases that fail. Needs ffmpeg and /usr/bin/python3 with numpy and scipy.
set -euo pipefail
bin=$(realpath "${1:?usage: detector_suite_at_rates.sh BOUNCECAL [RATE_HZ ...]}")
shift
rates=("$@")
[ ${#rates[@]} -gt 0 ] || rates=(16000 22050)
here=$(cd "$(dirname "$0")/.." && pwd)
suite=${SUITE:-$here/../shared/detector-suite}
work=${SUITE_RATES_WORK:-/tmp/bouncecal_suite_rates}
[ -d "$suite/recordings" ] || { echo "detector_suite_at_rates.sh: no suite at $suite (set SUITE)" >&2; exit 2; }
command -v ffmpeg >/dev/null || { echo "detector_suite_at_rates.sh: needs ffmpeg (apt-get install ffmpeg)" >&2; exit 2; }
for rate in "${rates[@]}"; do
  copy="$work/$rate"
  mkdir -p "$copy/recordings"
  # run.sh scores the recordings beside it: the copies get the suite's scripts.
  cp "$suite/run.sh" "$suite/score.py" "$copy/"
  for wav in "$suite"/recordings/*.wav; do
    name=$(basename "$wav" .wav)
    if [ ! -s "$copy/recordings/$name.wav" ]; then
      ffmpeg -nostdin -loglevel error -y -i "$wav" -ar "$rate" -c:a pcm_s16le "$copy/recordings/$name.tmp.wav"
      mv "$copy/recordings/$name.tmp.wav" "$copy/recordings/$name.wav"
    fi
    cp "$suite/recordings/$name.json" "$copy/recordings/"
  done
  bash "$copy/run.sh" "$bin" "$copy/out" >"$copy/score.txt" 2>&1
  echo "== $rate Hz: $(grep SUMMARY "$copy/score.txt")"
  grep -E " fail$" "$copy/score.txt" || true
done
