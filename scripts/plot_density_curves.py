#!/usr/bin/env python3
"""Window area fraction against time, mean and band over seeds, against a paper's points.

Each curve is LABEL=GLOB, the glob matching the output folders (holding history.csv) of one
set-up's runs over several seeds, for example those scripts/packing_step_map.py or
scripts/paper004_choice_map.py leave in their work folder. Plots the mean over the runs with a
band of +- one standard deviation, and the reference points, with gnuplot.

    scripts/plot_density_curves.py --out docs/packing/paper004_density_vs_time.png \\
        --points 0:0.4712,0.0475:0.6894,0.147:0.8236 --steady 0.8236 \\
        "shipped=/tmp/p004/seedstats/paper004_disks_friction_vdw_*/out" ...

Standard library and gnuplot only.
"""
import argparse
import csv
import glob
import os
import statistics
import subprocess
import sys
import tempfile


def read_history(folder):
    with open(os.path.join(folder, "history.csv")) as f:
        return [(float(r["time_s"]), float(r["packing_density"])) for r in csv.DictReader(f)]


def mean_curve(folders):
    histories = [read_history(folder) for folder in folders]
    length = min(len(h) for h in histories)
    rows = []
    for i in range(length):
        values = [h[i][1] for h in histories]
        sd = statistics.stdev(values) if len(values) > 1 else 0.0
        rows.append((histories[0][i][0], statistics.fmean(values), sd))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("curves", nargs="+", help="LABEL=GLOB of run output folders")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--points", default="", help="reference t:value pairs, comma-separated")
    parser.add_argument("--steady", type=float, help="reference steady value (a dashed line)")
    parser.add_argument("--title", default="area fraction in the measurement window")
    parser.add_argument("--xmax", type=float, default=0.2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as work:
        plots = []
        for index, spec in enumerate(args.curves):
            label, pattern = spec.split("=", 1)
            folders = sorted(glob.glob(pattern))
            if not folders:
                sys.exit(f"{pattern}: no run folders match; run the scenes first")
            data = os.path.join(work, f"curve{index}.dat")
            with open(data, "w") as f:
                for t, mean, sd in mean_curve(folders):
                    f.write(f"{t} {mean} {mean - sd} {mean + sd}\n")
            colour = index + 1
            plots.append(f"'{data}' using 1:3:4 with filledcurves lc {colour} fs transparent "
                         f"solid 0.2 notitle")
            plots.append(f"'{data}' using 1:2 with lines lw 2 lc {colour} "
                         f"title '{label} ({len(folders)} seeds)'")
        if args.points:
            data = os.path.join(work, "points.dat")
            with open(data, "w") as f:
                for pair in args.points.split(","):
                    t, value = pair.split(":")
                    f.write(f"{t} {value}\n")
            plots.append(f"'{data}' using 1:2 with points pt 7 ps 1.5 lc rgb 'black' "
                         f"title 'paper'")
        if args.steady is not None:
            plots.append(f"{args.steady} with lines dt 2 lc rgb 'black' title 'paper, steady'")
        script = "\n".join([
            "set terminal pngcairo size 900,560 font ',11' noenhanced",
            f"set output '{os.path.abspath(args.out)}'",
            f"set title '{args.title}'",
            "set xlabel 'time (s)'",
            "set ylabel 'area fraction'",
            f"set xrange [0:{args.xmax}]",
            "set key bottom right",
            "set grid",
            "plot " + ", \\\n  ".join(plots),
        ])
        subprocess.run(["gnuplot"], input=script, text=True, check=True)


if __name__ == "__main__":
    main()
