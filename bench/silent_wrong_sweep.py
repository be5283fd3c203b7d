#!/usr/bin/python3
"""Hunts for silent wrong answers: random recordings, each with exact ground truth.

    bench/silent_wrong_sweep.py build/apps/bouncecal [--seed 11] [--count 60] [--workdir DIR]
                                [--only-unreliable-lobe] [--precursors] [--limiter]

Each file is a `bouncecal synth` drop with a random mix of what real recordings bring: sample
rate 8-96 kHz, contact 35 us - 1 ms, plate or counter, restitution 0.3-0.92, noise (white or
pink, SNR to the first or the weakest impact), a linear-phase recording chain, the ball's contact
click, reverb, level jitter, clipping, hum, a codec's band limit, precursor clicks, echoes, and
for a third of them a lossy encoding by ffmpeg (MP3, Vorbis, Opus, AAC). `bouncecal analyze`
with default options then times it, and its eta-bar over the first impacts is compared with the
eta-bar that the exact onsets of the ball's bounces from the sequence's first one on give (a
sequence that skips bounces is wrong even where its own impacts are timed exactly).

A file is SILENT-WRONG when eta-bar is off by more than 0.002 (the paper's gamma_n precision
is ~0.003 in eta) and by more than 3 of its stated sigmas: the tool answered, exit 0, with an
uncertainty that does not cover its error, or when its impacts are not the ball's bounces at
all (no exact eta-bar follows from them). Refusals (no sequence) are honest and only counted.
Deterministic for a given seed. Needs only Python's standard library (and ffmpeg for codecs).
"""
import argparse
import csv
import json
import math
import os
import random
import subprocess
import sys
import tempfile

CODECS = [("mp3", "libmp3lame", "64k"), ("ogg", "libvorbis", "64k"),
          ("opus", "libopus", "32k"), ("m4a", "aac", "96k")]


def random_recording(rng, index):
    """The synth options of one random file and a short description."""
    sample_rate = rng.choice([8000, 11025, 16000, 22050, 32000, 44100, 48000, 96000])
    contact = rng.choice([35e-6, 70e-6, 150e-6, 400e-6, 800e-6, 1e-3])
    surface = rng.choice(["plate", "counter"])
    args = ["--sample-rate-hz", str(sample_rate), "--contact-duration-s", str(contact),
            "--surface", surface, "--restitution", f"{rng.uniform(0.3, 0.92):.3f}",
            "--drop-height-m", f"{rng.uniform(0.05, 0.6):.3f}", "--seed", str(index + 1)]
    snr = rng.choice([None, 12, 20, 30, 45])
    if snr:
        args += ["--snr-db", str(snr), "--snr-reference",
                 "weakest" if rng.random() < 0.5 else "first"]
    if rng.random() < 0.5:
        args += ["--adc", "linear-phase"]
    if rng.random() < 0.4:
        args += ["--click-gain", f"{rng.uniform(0.05, 0.3):.2f}"]
    if rng.random() < 0.3:
        args += ["--reverb-rt60-s", f"{rng.uniform(0.2, 0.8):.2f}"]
    if rng.random() < 0.3:
        args += ["--level-jitter-db", "3"]
    if rng.random() < 0.25:
        args += ["--clip-level", f"{rng.uniform(0.15, 0.5):.2f}"]
    if rng.random() < 0.2:
        args += ["--hum-hz", rng.choice(["50", "60"]),
                 "--hum-dbfs", f"{rng.uniform(-40, -20):.0f}"]
    if rng.random() < 0.2:
        args += ["--band-limit-hz", f"{rng.uniform(0.2, 0.4) * sample_rate:.0f}"]
    if rng.random() < 0.2:
        args += ["--precursor-lead-s", f"{rng.uniform(0.002, 0.008):.4f}",
                 "--precursor-gain-db", f"{rng.uniform(-25, -10):.0f}"]
    if rng.random() < 0.2:
        args += ["--echo-delay-s", f"{rng.uniform(0.002, 0.012):.4f}",
                 "--echo-gain-db", f"{rng.uniform(-10, -3):.0f}"]
    if snr and rng.random() < 0.4:
        args += ["--noise-color", "pink"]
    codec = rng.choice(CODECS) if rng.random() < 0.3 else None
    return args, codec


def precursor_recording(rng, index):
    """A drop with a click before every bounce, 9-14 dB under it and 2-8 ms ahead, under 3 dB of
    level jitter: where the click rings into its bounce, the detector times one or the other bounce
    by bounce (docs/codecs.md, "In every file, and in both directions"). WAV only, 22-96 kHz."""
    args = ["--sample-rate-hz", str(rng.choice([22050, 32000, 44100, 48000, 96000])),
            "--contact-duration-s", str(rng.choice([35e-6, 70e-6, 150e-6, 400e-6])),
            "--surface", rng.choice(["plate", "counter"]),
            "--restitution", f"{rng.uniform(0.5, 0.9):.3f}",
            "--drop-height-m", f"{rng.uniform(0.1, 0.6):.3f}", "--seed", str(index + 1),
            "--precursor-lead-s", f"{rng.uniform(0.002, 0.008):.4f}",
            "--precursor-gain-db", f"{rng.uniform(-14, -9):.1f}",
            "--level-jitter-db", "3", "--snr-db", "40"]
    if rng.random() < 0.5:
        args += ["--adc", "linear-phase"]
    return args, None


def limiter_args(seed, index):
    """A phone's gain stage for file `index` (--limiter, synth --limiter-gain-db): an automatic gain
    control, then a look-ahead peak limiter at -1 dBFS. Half the files: the gain steered toward
    -24 to -12 dBFS at 3-20 dB/s from 10-30 dB, where it stood in the quiet before the drop (the
    drops peak at -6 to 0 dBFS, so the first bounces are limited by up to ~30 dB and the gain then
    comes down); the other half: a gain that stays at 3-15 dB (an AGC that adapts only to speech).
    More fixed gain leaves a plate's ringing at the ceiling for seconds, with no rise to find.
    Drawn from a stream of its own, so a seed's files are the same drops with and without it."""
    rng = random.Random(f"{seed}-limiter-{index}")
    args = ["--limiter-lookahead-s", str(rng.choice([0.5e-3, 1e-3, 2e-3, 5e-3])),
            "--limiter-release-s", str(rng.choice([0.02, 0.06, 0.2]))]
    if rng.random() < 0.5:
        return args + ["--limiter-gain-db", f"{rng.uniform(10, 30):.1f}",
                       "--agc-target-dbfs", f"{rng.uniform(-24, -12):.1f}",
                       "--agc-slew-db-per-s", str(rng.choice([3, 6, 20])),
                       "--agc-level-time-s", str(rng.choice([0.1, 0.3]))]
    return args + ["--limiter-gain-db", f"{rng.uniform(3, 15):.1f}"]


def eta_bar(onsets, count):
    intervals = [b - a for a, b in zip(onsets, onsets[1:])]
    ratios = [b / a for a, b in zip(intervals, intervals[1:])]
    used = ratios[:count]
    return sum(1 - e * e for e in used) / len(used) if used else float("nan")


def verdict(measured, exact, sigma):
    """(z, wrong) for an eta-bar against the exact onsets': off by more than 0.002 (the paper's
    gamma_n precision is ~0.003 in eta) and by more than 3 stated sigmas, or no exact eta-bar at all
    (the impacts are not the ball's bounces)."""
    z = (measured - exact) / sigma if sigma > 0 else float("inf")
    return z, math.isnan(exact) or (abs(measured - exact) > 0.002 and abs(z) > 3)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bouncecal")
    parser.add_argument("--seed", type=int, default=11)
    parser.add_argument("--count", type=int, default=60)
    parser.add_argument("--workdir", default=None)
    parser.add_argument("--only-unreliable-lobe", action="store_true",
                        help="only the files the response timing stage runs on (a transform "
                             "codec or a rate below 20 kHz; audio/include/bouncecal/audio/"
                             "response_timing.h): the others are analysed as before it")
    parser.add_argument("--precursors", action="store_true",
                        help="every file a drop with a click 9-14 dB under each bounce, 2-8 ms "
                             "ahead of it (precursor_recording), instead of the random mix")
    parser.add_argument("--limiter", action="store_true",
                        help="every file through a phone's gain stage: an AGC and a look-ahead peak "
                             "limiter (limiter_args), which bring the loudest bounces down "
                             "towards the sounds before them")
    options = parser.parse_args()
    workdir = options.workdir or tempfile.mkdtemp(prefix="silent_wrong_")
    os.makedirs(workdir, exist_ok=True)
    rng = random.Random(options.seed)
    tally = {"files": 0, "sequences": 0, "refused": 0, "silent_wrong": 0}
    for index in range(options.count):
        recipe = precursor_recording if options.precursors else random_recording
        args, codec = recipe(rng, index)
        if options.limiter:
            args += limiter_args(options.seed, index)
        rate = int(args[args.index("--sample-rate-hz") + 1])
        if options.only_unreliable_lobe and not codec and rate >= 20000:
            continue
        wav = os.path.join(workdir, f"{index}.wav")
        truth_csv = os.path.join(workdir, f"{index}.csv")
        synth = subprocess.run([options.bouncecal, "synth", "-o", wav, "--truth", truth_csv] + args,
                               capture_output=True, text=True)
        if synth.returncode:
            print(f"#{index} synth refused: {synth.stderr.strip()}")
            continue
        audio = wav
        if codec:
            encoded = os.path.join(workdir, f"{index}.{codec[0]}")
            encode = subprocess.run(["ffmpeg", "-y", "-loglevel", "error", "-i", wav,
                                     "-c:a", codec[1], "-b:a", codec[2], encoded],
                                    capture_output=True)
            audio = encoded if encode.returncode == 0 else wav
        description = " ".join(args) + (f" | {codec[0]} {codec[2]}" if audio != wav else "")
        tally["files"] += 1
        with open(truth_csv) as f:
            truth = [float(row["onset_s"]) for row in csv.DictReader(
                line for line in f if not line.startswith("#")) if row["kind"] == "ball_impact"]
        result_json = os.path.join(workdir, f"{index}.json")
        analyze = subprocess.run([options.bouncecal, "analyze", audio, "--json", result_json],
                                 capture_output=True, text=True)
        if analyze.returncode:
            print(f"#{index} analyze exit {analyze.returncode}: {analyze.stderr.strip()[:160]}"
                  f" | {description}")
            tally["refused"] += 1
            continue
        with open(result_json) as f:
            recording = json.load(f)["recordings"][0]
        sequence = recording["sequences"][0] if recording["sequences"] else None
        measured = sequence and sequence.get("energy_loss_mean_first_n")
        if measured is None:
            print(f"#{index} no eta-bar ({len(recording['impacts'])} impacts, {len(truth)} true)"
                  f" | {description}")
            tally["refused"] += 1
            continue
        tally["sequences"] += 1
        onsets = [i["onset_s"] for i in recording["impacts"] if i.get("sequence") == 0]
        matched = [min(range(len(truth)), key=lambda j: abs(truth[j] - t)) for t in onsets]
        count = sequence["first_n"]
        # The ball's own eta-bar over the bounces from the sequence's first one on: a sequence
        # that takes every other bounce (its interval ratio e^2 times like a ball of restitution
        # e^2) matches truth impacts one by one, and the exact onsets of just those impacts would
        # agree with its eta-bar, but the ball's is that of consecutive bounces.
        used = matched[:count + 2]
        skips = any(b - a != 1 for a, b in zip(used, used[1:]))
        exact = eta_bar(truth[used[0]:used[0] + count + 2], count)
        sigma = sequence["energy_loss_mean_first_n_uncertainty"]
        # A sequence whose impacts are not the ball's bounces (they all lie nearest its last one,
        # so no eta-bar of the ball follows from them: a periodic sound's lattice, 2026-12-03) is
        # wrong whatever its stated sigma.
        not_the_ball = math.isnan(exact)
        z, wrong = verdict(measured, exact, sigma)
        tally["silent_wrong"] += wrong
        worst_us = max(abs(t - truth[j]) for t, j in zip(onsets, matched)) * 1e6
        flag = (("  SILENT-WRONG" if wrong else "") + (" (skips bounces)" if skips else "") +
                (" (not the ball's bounces)" if not_the_ball else ""))
        print(f"#{index} eta-bar {measured:.4f} +- {sigma:.4f}, exact {exact:.4f} (z {z:+.1f}),"
              f" worst onset {worst_us:.0f} us{flag} | {description}")
    print("SUMMARY: " + ", ".join(f"{k} {v}" for k, v in tally.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
