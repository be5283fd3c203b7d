#!/usr/bin/python3
"""Sounds before a drop that time like bounces: how often does a sequence start at one?

    bench/knock_sweep.py build/apps/bouncecal [other/bouncecal ...] [--count 150] [--seed 1000]
                         [--workdir DIR]

Each file is a `bouncecal synth` drop (restitution 0.5-0.92, no scatter, released from 0.1-0.5 m
at 0.8-2 s, SNR 20-45 dB) with 2-6 knocks, handling thumps and stray noise bursts at random
times before its first impact, each 0.1-0.6 of full scale (the ball's first impact peaks near
0.5-0.7). Before a drop the window of a bounce before the first is wide (ratio_step_tolerance of
a long flight), so such sounds land in it often; silent_wrong_sweep.py has none of them. Each
binary given analyses the same files with default options (no drop height), and a sequence is
KNOCK-START when its first onset is not within 5 ms of a ball impact (KNOCK-START-WRONG where
its eta-bar is off the drop's own from its first bounce by more than 0.002 and 3 stated sigmas:
a confident wrong answer), SILENT-WRONG (as in silent_wrong_sweep.py) when its eta-bar of the
first 3 is off the exact onsets' from the same first impact on by more than 0.002 and 3 stated
sigmas. Deterministic for a given seed. Needs
only Python's standard library.
"""
import argparse
import csv
import json
import math
import os
import random
import subprocess
import tempfile

EXTRA_KINDS = ("knock", "thump", "stray")


def synth_options(rng, index):
    e = rng.uniform(0.5, 0.92)
    h = rng.uniform(0.1, 0.5)
    release = rng.uniform(0.8, 2.0)
    first_impact = release + math.sqrt(2 * h / 9.81)
    args = ["--restitution", f"{e:.3f}", "--drop-height-m", f"{h:.3f}", "--release-s",
            f"{release:.3f}", "--snr-db", f"{rng.uniform(20, 45):.0f}", "--seed", str(index + 1),
            "--event-amplitude", f"{rng.uniform(0.1, 0.6):.2f}"]
    for _ in range(rng.randint(2, 6)):
        args += [rng.choice(["--knock-s", "--thump-s", "--stray-s"]),
                 f"{rng.uniform(0.05, first_impact - 0.02):.4f}"]
    return args


def judge(analysis, bounces):
    """'knock-start' (honest: within 0.002 or 3 stated sigmas of the drop's eta-bar from its
    first bounce), 'knock-start-wrong' (not), 'silent-wrong', 'right', or None without an
    eta-bar of the first 3."""
    if not analysis["sequences"]:
        return None
    sequence = analysis["sequences"][0]
    onsets = sequence["onsets_s"]
    eta = sequence.get("energy_loss_mean_first_n")
    if eta is None:
        return None
    first = min(range(len(bounces)), key=lambda k: abs(bounces[k] - onsets[0]))
    knock_start = abs(bounces[first] - onsets[0]) > 5e-3
    # A sequence that starts at a sound before the drop is held against the drop's own eta-bar:
    # its first flights are not the ball's, whatever the later ones are.
    t = bounces[0:5] if knock_start else bounces[first:first + 5]
    if len(t) < 5:
        return "knock-start" if knock_start else None
    exact = sum(1 - ((t[j + 2] - t[j + 1]) / (t[j + 1] - t[j])) ** 2 for j in range(3)) / 3
    error = abs(eta - exact)
    sigma = sequence["energy_loss_mean_first_n_uncertainty"]
    wrong = error > 0.002 and error > 3 * sigma
    if knock_start:
        return "knock-start-wrong" if wrong else "knock-start"
    return "silent-wrong" if wrong else "right"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("binaries", nargs="+")
    parser.add_argument("--count", type=int, default=150)
    parser.add_argument("--seed", type=int, default=1000)
    parser.add_argument("--workdir")
    args = parser.parse_args()
    workdir = args.workdir or tempfile.mkdtemp(prefix="bouncecal_knocks_")
    os.makedirs(workdir, exist_ok=True)
    counts = {b: {"sequences": 0, "knock-start": 0, "knock-start-wrong": 0, "silent-wrong": 0}
              for b in args.binaries}
    for index in range(args.count):
        rng = random.Random(args.seed + index)
        options = synth_options(rng, index)
        wav = os.path.join(workdir, f"k{index}.wav")
        truth = os.path.join(workdir, f"k{index}.csv")
        subprocess.run([args.binaries[0], "synth", "-o", wav, "--truth", truth] + options,
                       check=True, capture_output=True)
        with open(truth) as file:
            bounces = [float(row["onset_s"]) for row in csv.DictReader(file)
                       if row["kind"] not in EXTRA_KINDS]
        for binary in args.binaries:
            report = os.path.join(workdir, f"k{index}.json")
            subprocess.run([binary, "analyze", wav, "--json", report], capture_output=True)
            if not os.path.exists(report):
                continue
            with open(report) as file:
                verdict = judge(json.load(file), bounces)
            os.remove(report)
            if verdict is None:
                continue
            counts[binary]["sequences"] += 1
            if verdict != "right":
                counts[binary]["knock-start"] += verdict.startswith("knock-start")
                counts[binary]["knock-start-wrong"] += verdict == "knock-start-wrong"
                counts[binary]["silent-wrong"] += verdict == "silent-wrong"
                print(f"#{index} {binary}: {verdict} | {' '.join(options)}")
    for binary, count in counts.items():
        print(f"SUMMARY {binary}: files {args.count}, sequences with eta-bar {count['sequences']}, "
              f"starting at a sound before the drop {count['knock-start']} (of them off the "
              f"drop's eta-bar by > 0.002 and 3 sigmas: {count['knock-start-wrong']}), other "
              f"silent wrong {count['silent-wrong']}")


if __name__ == "__main__":
    main()
