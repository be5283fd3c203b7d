#!/usr/bin/python3
"""Times every sequence member of kept silent_wrong_sweep.py files against its exact onset.

    bench/sweep_members.py build/apps/bouncecal WORKDIR... [--against OTHER_BOUNCECAL]
                           [--jobs 2] [--save RESULTS.json] [--reuse RESULTS.json]

Re-analyses each file a `silent_wrong_sweep.py --workdir WORKDIR` run left (its N.csv truth and
the N.wav, or the lossy N.mp3 / .ogg / .opus / .m4a it was scored on) and matches every member
of the first sequence to the nearest exact ball impact. A member's error is its onset minus that
impact's, less the sequence's median over its band-detected members (one constant per drop: only
relative times enter intervals). Members are reported in four classes, the ones the detector
times differently: band-detected and residual-only (Impact::residual_only, found only in the
ringing) in PCM at 20 kHz and above, every residual-only member of a lossy file, and of a PCM
file below 20 kHz. For each: the median, p90 and p95 of |error|, the median stated sigma, and
how many lie within 1.96 and beyond 3 stated sigmas. A member on the wrong sound (a precursor,
a late bounce) counts with its whole error: the tails are mostly those.

With --against, the same files are analysed by the other binary too and compared member by
member (same file, same exact impact): how many moved by more than 5 us, got closer or further,
by more than 200 us either way, and how many crossed 3 stated sigmas; then each file's eta-bar
as silent_wrong_sweep.py scores it (silent wrong, sequences gained and lost, and how many of the
changed eta-bars came closer to the exact onsets' or went further, and how many stated sigmas
grew or shrank by more than 10 %; the 12 that grew most are listed with their ratio and how
far each was off, as a right answer widened many times is what a doubt rule costs, and the
first 4 that shrank). This is
how a timing change is judged before the sweep is rerun from scratch: the same files (10782
with a sequence on the machine of 2026-12-06), both binaries, in a few minutes (--reuse reads
the first binary's results from an earlier --save instead of running it again: half the time
when one base is compared with several changes). A saved member also holds its onset and peak
level (`onset`, `peak_dbfs`), so a rule on a sequence's timing and levels can be modelled offline
over every file before it is built (2026-12-07: the leading-ratio doubt of leading_sounds.h).
Deterministic; needs only Python's standard library.
"""
import argparse
import csv
import glob
import json
import math
import os
import statistics
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from silent_wrong_sweep import eta_bar, verdict  # noqa: E402

LOSSY_EXTENSIONS = ("mp3", "ogg", "opus", "m4a")
CLASSES = [
    ("PCM >= 20 kHz, band-detected", lambda m, f: not f["lossy"] and f["rate"] >= 20000
     and not m["residual_only"]),
    ("PCM >= 20 kHz, residual-only", lambda m, f: not f["lossy"] and f["rate"] >= 20000
     and m["residual_only"]),
    ("lossy, residual-only", lambda m, f: f["lossy"] and m["residual_only"]),
    ("PCM < 20 kHz, residual-only", lambda m, f: not f["lossy"] and f["rate"] < 20000
     and m["residual_only"]),
]


def sweep_files(workdirs):
    files = []
    for workdir in workdirs:
        for truth_csv in sorted(glob.glob(os.path.join(workdir, "*.csv"))):
            index = os.path.basename(truth_csv)[:-4]
            audio = os.path.join(workdir, f"{index}.wav")
            for extension in LOSSY_EXTENSIONS:
                encoded = os.path.join(workdir, f"{index}.{extension}")
                if os.path.exists(encoded):
                    audio = encoded
            files.append((f"{workdir}#{index}", audio, truth_csv))
    return files


def analyse(bouncecal, entry):
    key, audio, truth_csv = entry
    with open(truth_csv) as f:
        truth = [float(row["onset_s"]) for row in csv.DictReader(
            line for line in f if not line.startswith("#")) if row["kind"] == "ball_impact"]
    run = subprocess.run([bouncecal, "analyze", audio, "--json", "-"], capture_output=True,
                         text=True)
    if run.returncode or not truth:
        return key, None
    recording = json.loads(run.stdout)["recordings"][0]
    sequence = recording["sequences"][0] if recording["sequences"] else None
    members = [i for i in recording["impacts"] if i.get("sequence") == 0]
    if not members:
        return key, None
    rows = []
    for impact in members:
        nearest = min(range(len(truth)), key=lambda j: abs(truth[j] - impact["onset_s"]))
        rows.append({"truth": nearest, "error": impact["onset_s"] - truth[nearest],
                     "sigma": impact["onset_uncertainty_s"], "onset": impact["onset_s"],
                     "peak_dbfs": impact["peak_dbfs"],
                     "residual_only": impact["residual_only"]})
    band = [r["error"] for r in rows if not r["residual_only"]] or [r["error"] for r in rows]
    constant = statistics.median(band)
    for r in rows:
        r["error"] -= constant
    result = {"rate": recording["sample_rate_hz"], "lossy": recording["lossy"], "members": rows}
    measured = sequence and sequence.get("energy_loss_mean_first_n")
    if measured is not None:
        count = sequence["first_n"]
        first = rows[0]["truth"]
        exact = eta_bar(truth[first:first + count + 2], count)
        sigma = sequence["energy_loss_mean_first_n_uncertainty"]
        z, wrong = verdict(measured, exact, sigma)
        result["eta_bar"] = {"measured": measured, "sigma": sigma,
                             "exact": None if math.isnan(exact) else exact,
                             "z": None if math.isnan(exact) else z, "wrong": wrong}
    return key, result


def run_all(bouncecal, files, jobs):
    with ThreadPoolExecutor(jobs) as pool:
        return dict(pool.map(lambda entry: analyse(bouncecal, entry), files))


def quantile(sorted_values, p):
    return sorted_values[min(len(sorted_values) - 1, int(p * len(sorted_values)))]


def report(name, results):
    print(f"{name}: {sum(1 for r in results.values() if r)} files with a sequence, "
          f"{sum(1 for r in results.values() if r and 'eta_bar' in r)} with an eta-bar, "
          f"{sum(1 for r in results.values() if r and r.get('eta_bar', {}).get('wrong'))} "
          "silent wrong")
    print(f"  {'class':32s} {'members':>7s} {'|err| med':>9s} {'p90':>7s} {'p95':>7s} "
          f"{'sigma med':>9s} {'<=1.96s':>8s} {'>3s':>7s}  (us)")
    for label, member_of in CLASSES:
        chosen = [m for r in results.values() if r for m in r["members"] if member_of(m, r)]
        if not chosen:
            print(f"  {label:32s} {0:7d}")
            continue
        errors = sorted(abs(m["error"]) * 1e6 for m in chosen)
        sigmas = sorted(m["sigma"] * 1e6 for m in chosen)
        ratios = [abs(m["error"]) / m["sigma"] for m in chosen if m["sigma"] > 0]
        within = sum(1 for z in ratios if z <= 1.96) / max(1, len(ratios))
        beyond = sum(1 for z in ratios if z > 3) / max(1, len(ratios))
        print(f"  {label:32s} {len(chosen):7d} {quantile(errors, 0.5):9.0f} "
              f"{quantile(errors, 0.9):7.0f} {quantile(errors, 0.95):7.0f} "
              f"{quantile(sigmas, 0.5):9.0f} {within:8.3f} {beyond:7.4f}")


def compare(base, other):
    def by_member(results):
        out = {}
        for key, r in results.items():
            for m in (r or {}).get("members", []):
                out[(key, m["truth"])] = (m, r)
        return out
    a, b = by_member(base), by_member(other)
    common = set(a) & set(b)
    print(f"members: {len(a)} -> {len(b)}, {len(common)} in both")
    for label, member_of in CLASSES:
        chosen = [k for k in common if member_of(*a[k])]
        moved = [k for k in chosen if abs(a[k][0]["error"] - b[k][0]["error"]) > 5e-6]
        closer = [k for k in moved if abs(b[k][0]["error"]) < abs(a[k][0]["error"])]
        much_closer = sum(1 for k in moved
                          if abs(b[k][0]["error"]) < abs(a[k][0]["error"]) - 200e-6)
        much_further = sum(1 for k in moved
                           if abs(b[k][0]["error"]) > abs(a[k][0]["error"]) + 200e-6)
        beyond_a = sum(1 for k in chosen if abs(a[k][0]["error"]) > 3 * a[k][0]["sigma"])
        beyond_b = sum(1 for k in chosen if abs(b[k][0]["error"]) > 3 * b[k][0]["sigma"])
        print(f"  {label:32s} {len(chosen):6d} moved {len(moved):5d}: closer {len(closer):5d} "
              f"further {len(moved) - len(closer):5d}, by > 200 us {much_closer:4d} / "
              f"{much_further:4d}; beyond 3 sigmas {beyond_a} -> {beyond_b}")
    bars_a = {k: r["eta_bar"] for k, r in base.items() if r and "eta_bar" in r}
    bars_b = {k: r["eta_bar"] for k, r in other.items() if r and "eta_bar" in r}
    gained = sorted(set(bars_b) - set(bars_a))
    lost = sorted(set(bars_a) - set(bars_b))
    new_wrong = sorted(k for k in bars_b if bars_b[k]["wrong"] and not bars_a.get(k, {}).get(
        "wrong"))
    gone_wrong = sorted(k for k in bars_a if bars_a[k]["wrong"] and not bars_b.get(k, {}).get(
        "wrong"))
    changed = [k for k in set(bars_a) & set(bars_b)
               if abs(bars_a[k]["measured"] - bars_b[k]["measured"]) > 1e-9]
    print(f"eta-bars: {len(bars_a)} -> {len(bars_b)} (gained {len(gained)}, lost {len(lost)}), "
          f"{len(changed)} changed; silent wrong {len(gone_wrong)} gone {gone_wrong[:8]}, "
          f"{len(new_wrong)} new {new_wrong[:8]}")
    # A refusal is honest, but one of an answer that was right is a loss to its user.
    lost_right = [k for k in lost if not bars_a[k]["wrong"]]
    if lost_right:
        print(f"  lost eta-bars that were right: {len(lost_right)} {lost_right[:8]}")

    def off(bar):
        return abs(bar["measured"] - bar["exact"])

    judged = [k for k in changed if bars_a[k]["exact"] is not None]
    closer = [k for k in judged if off(bars_b[k]) < off(bars_a[k])]
    much_closer = sum(1 for k in judged if off(bars_b[k]) < off(bars_a[k]) - 0.001)
    much_further = sum(1 for k in judged if off(bars_b[k]) > off(bars_a[k]) + 0.001)
    print(f"  changed eta-bars closer to the exact {len(closer)}, further "
          f"{len(judged) - len(closer)}; by > 0.001 {much_closer} / {much_further}")
    # A change of stated uncertainty alone moves no eta-bar but can make or mend a silent wrong
    # answer, and a wider sigma on answers that were right costs every user of the file.
    both = [k for k in set(bars_a) & set(bars_b)
            if "sigma" in bars_a[k] and "sigma" in bars_b[k]]
    wider = [k for k in both if bars_b[k]["sigma"] > 1.1 * bars_a[k]["sigma"]]
    narrower = [k for k in both if bars_b[k]["sigma"] < bars_a[k]["sigma"] / 1.1]
    right_wider = [k for k in wider if bars_a[k]["exact"] is not None
                   and off(bars_a[k]) <= bars_a[k]["sigma"]]
    print(f"  eta-bar sigmas by more than 10 %: wider {len(wider)} (of them within one sigma "
          f"of the exact before: {len(right_wider)}), narrower {len(narrower)}")
    # The widest few, with how far each was off: a right answer widened many times is a cost.
    def growth(key):  # a sigma of exactly 0 (exact onsets) grows without bound
        return bars_b[key]["sigma"] / max(bars_a[key]["sigma"], 1e-12)

    for key in sorted(wider, key=growth, reverse=True)[:12]:
        error = f"off {off(bars_a[key]):.4f}" if bars_a[key]["exact"] is not None else "no exact"
        print(f"  wider: {key} +-{bars_a[key]['sigma']:.4f} -> {bars_b[key]['sigma']:.4f} "
              f"({growth(key):.1f}x), {error}")
    for key in sorted(narrower)[:4]:
        print(f"  narrower: {key} +-{bars_a[key]['sigma']:.4f} -> {bars_b[key]['sigma']:.4f}")
    moved_z = sorted(((abs(bars_b[k]["z"]) - abs(bars_a[k]["z"]), k) for k in changed
                      if bars_a[k]["z"] is not None and bars_b[k]["z"] is not None),
                     reverse=True)
    for delta, key in [(d, k) for d, k in moved_z if d > 0][:5]:
        print(f"  further: {key} z {bars_a[key]['z']:+.2f} -> {bars_b[key]['z']:+.2f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bouncecal")
    parser.add_argument("workdirs", nargs="+")
    parser.add_argument("--against", help="a second bouncecal to compare member by member")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--save", help="write the per-member results (JSON) here")
    parser.add_argument("--reuse", help="results saved by --save: the first bouncecal's are read "
                        "from there (the same files, the same binary) instead of run again")
    options = parser.parse_args()
    files = sweep_files(options.workdirs)
    if not files:
        print(f"no silent_wrong_sweep.py files (N.csv with N.wav) in {options.workdirs}",
              file=sys.stderr)
        return 2
    base = None
    if options.reuse:
        with open(options.reuse) as f:
            saved = json.load(f).get(options.bouncecal)
        # Only where every file was measured: a saved run over fewer folders would miss some.
        if saved is not None and all(key in saved for key, _, _ in files):
            base = {key: saved[key] for key, _, _ in files}
        else:
            print(f"{options.reuse} holds no run of {options.bouncecal} over these files: "
                  "running it", file=sys.stderr)
    if base is None:
        base = run_all(options.bouncecal, files, options.jobs)
    report(options.bouncecal, base)
    results = {options.bouncecal: base}
    if options.against:
        other = run_all(options.against, files, options.jobs)
        report(options.against, other)
        compare(base, other)
        results[options.against] = other
    if options.save:
        with open(options.save, "w") as f:
            json.dump(results, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())
