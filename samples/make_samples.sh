#!/usr/bin/env bash
# Regenerates the synthetic sample recordings and their ground truth.
#   samples/make_samples.sh BOUNCECAL_EXECUTABLE OUTPUT_DIR
# The commands are listed with their purpose in samples/README.md; a test
# (tests/samples_test.cc) reruns this script and checks the shipped files still match.
set -euo pipefail
bouncecal="$1"
out="$2"
mkdir -p "$out"

# 1 cm steel ball, 0.20 m drop, e = sqrt(1 - 0.58) (the paper's eta-bar), 70 us contact,
# 1 mm steel plate modes, mild room (RT60 0.3 s, DRR 15 dB), 35 dB SNR.
"$bouncecal" synth -o "$out/steel_ball_h0.2m.wav" --truth "$out/steel_ball_h0.2m.csv" \
  --drop-height-m 0.2 --restitution 0.648074069840786 --contact-duration-s 70e-6 \
  --surface plate --reverb-rt60-s 0.3 --reverb-drr-db 15 --snr-db 35 \
  --sample-rate-hz 48000 --format pcm16 --seed 1

# Ping-pong-like and hard: long ringing counter modes, e rising as the ball slows, an echo 9 ms
# after each hit at -12 dB, a precursor 7 ms before, RT60 0.4 s, 50 Hz hum, a knock 0.35 s
# before the release... and 20 dB SNR re the first impact (the late impacts sink into it).
"$bouncecal" synth -o "$out/pingpong_hard.wav" --truth "$out/pingpong_hard.csv" \
  --drop-height-m 0.25 --restitution 0.95 --restitution-slope-per-mps -0.02 --release-s 0.8 \
  --surface counter --contact-duration-s 50e-6 --level-jitter-db 1 \
  --reverb-rt60-s 0.4 --reverb-drr-db 12 --echo-delay-s 0.009 --echo-gain-db -12 \
  --precursor-lead-s 0.007 --precursor-gain-db -22 --hum-hz 50 --hum-dbfs -40 \
  --knock-s 0.35 --event-amplitude 0.25 --snr-db 20 --tail-s 0.5 \
  --sample-rate-hz 48000 --format pcm16 --seed 2

# Stereo at 44.1 kHz, two drops 0.8 s apart: the second microphone hears everything 0.25 ms
# later, 4 dB quieter and with its own noise 6 dB worse; e falls with impact speed.
"$bouncecal" synth -o "$out/steel_ball_stereo_44k.wav" --truth "$out/steel_ball_stereo_44k.csv" \
  --drop-height-m 0.15 --restitution 0.8 --restitution-slope-per-mps -0.06 --drops 2 \
  --drop-gap-s 0.8 --min-flight-s 0.01 --contact-duration-s 60e-6 --reverb-rt60-s 0.25 \
  --snr-db 30 --channels 2 --channel-delay-s 0.00025 --channel-gain-db -4 \
  --channel-snr-offset-db -6 --tail-s 0.5 --sample-rate-hz 44100 --format pcm16 --seed 3
