#!/usr/bin/env python3
"""Map of paper 004's unstated choices against all its observables at once.

Runs `bouncecal pack` on variants of samples/scenes/paper004_disks_friction_vdw.json (local
damping scope and alpha, cohesion h_min, viscous damping, first-contact stop, friction) for
several insertion seeds and prints a Markdown table: final area fraction by both estimators
(exact window area and the paper's centre count), mean coordination and the window density at
the paper's two times (0.0475 s and 0.147 s), each as mean +- sd over the seeds.

    scripts/paper004_choice_map.py --bouncecal build/apps/bouncecal [--seeds 5] [--duration 0.2]
        [--work /tmp/p004map] [--rows literal,contact-4nm,...] [--nice 10]

Reference (paper 004): 0.4712 at t = 0, 0.6894 at 0.0475 s, steady 0.8236 from 0.147 s,
coordination 3.609; frictionless 0.8696. Standard library only.
"""
import argparse
import csv
import json
import math
import os
import statistics
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASE = os.path.join(REPO, "samples", "scenes", "paper004_disks_friction_vdw.json")

# Each row: the changes to the shipped friction + vdW scene. scope: unbalanced-force (PFC, the
# literal reading), contact-forces, or None (no local damping). hmin: van der Waals minimum gap
# in m, None: no van der Waals. zeta: the linear dashpot's damping ratio.
ROWS = [
    ("literal", "literal: alpha 0.7 on all forces, h_min 0.4 nm, stop (variant scene _literal)",
     dict(scope="unbalanced-force", alpha=0.7, hmin=4e-10, zeta=0.0, stop=True)),
    ("pfc-novdw", "alpha 0.7 on all forces, no vdW, stop",
     dict(scope="unbalanced-force", alpha=0.7, hmin=None, zeta=0.0, stop=True)),
    ("contact-0.4nm", "alpha 0.7 contact-only, h_min 0.4 nm, stop",
     dict(scope="contact-forces", alpha=0.7, hmin=4e-10, zeta=0.0, stop=True)),
    ("contact-4nm", "alpha 0.7 contact-only, h_min 4 nm, stop",
     dict(scope="contact-forces", alpha=0.7, hmin=4e-9, zeta=0.0, stop=True)),
    ("contact-10nm", "alpha 0.7 contact-only, h_min 10 nm, stop",
     dict(scope="contact-forces", alpha=0.7, hmin=1e-8, zeta=0.0, stop=True)),
    ("contact-novdw", "alpha 0.7 contact-only, no vdW, stop",
     dict(scope="contact-forces", alpha=0.7, hmin=None, zeta=0.0, stop=True)),
    ("contact-10nm-nostop", "alpha 0.7 contact-only, h_min 10 nm, no stop",
     dict(scope="contact-forces", alpha=0.7, hmin=1e-8, zeta=0.0, stop=False)),
    ("contact0.3-10nm", "alpha 0.3 contact-only, h_min 10 nm, stop",
     dict(scope="contact-forces", alpha=0.3, hmin=1e-8, zeta=0.0, stop=True)),
    ("viscous-novdw", "no local damping, zeta 0.1, no vdW, no stop (the LAMMPS referee case)",
     dict(scope=None, alpha=0.0, hmin=None, zeta=0.1, stop=False)),
    ("viscous-10nm", "no local damping, zeta 0.1, h_min 10 nm, no stop",
     dict(scope=None, alpha=0.0, hmin=1e-8, zeta=0.1, stop=False)),
    ("viscous-4nm", "no local damping, zeta 0.1, h_min 4 nm, no stop",
     dict(scope=None, alpha=0.0, hmin=4e-9, zeta=0.1, stop=False)),
    ("viscous-10nm-stop", "**no local damping, zeta 0.1, h_min 10 nm, stop (shipped)**",
     dict(scope=None, alpha=0.0, hmin=1e-8, zeta=0.1, stop=True)),
    ("viscous-0.4nm-stop", "no local damping, zeta 0.1, h_min 0.4 nm, stop",
     dict(scope=None, alpha=0.0, hmin=4e-10, zeta=0.1, stop=True)),
    ("viscous-4nm-stop", "no local damping, zeta 0.1, h_min 4 nm, stop",
     dict(scope=None, alpha=0.0, hmin=4e-9, zeta=0.1, stop=True)),
    ("viscous0.05-10nm-stop", "no local damping, zeta 0.05, h_min 10 nm, stop",
     dict(scope=None, alpha=0.0, hmin=1e-8, zeta=0.05, stop=True)),
    ("viscous0.3-10nm-stop", "no local damping, zeta 0.3, h_min 10 nm, stop",
     dict(scope=None, alpha=0.0, hmin=1e-8, zeta=0.3, stop=True)),
    ("pfc0.3-novdw", "alpha 0.3 on all forces, no vdW, stop",
     dict(scope="unbalanced-force", alpha=0.3, hmin=None, zeta=0.0, stop=True)),
    ("pfc0.93-novdw", "alpha 0.93 on all forces (fall at 0.07 g), no vdW, stop, 0.4 s",
     dict(scope="unbalanced-force", alpha=0.93, hmin=None, zeta=0.0, stop=True, duration=0.4)),
    ("pfc0.93-10nm", "alpha 0.93 on all forces (fall at 0.07 g), h_min 10 nm, stop, 0.4 s",
     dict(scope="unbalanced-force", alpha=0.93, hmin=1e-8, zeta=0.0, stop=True, duration=0.4)),
    ("frictionless-literal", "frictionless, no vdW, alpha 0.7 on all forces, stop",
     dict(scope="unbalanced-force", alpha=0.7, hmin=None, zeta=0.0, stop=True, friction=0.0)),
    ("frictionless-viscous", "frictionless, no vdW, no local damping, zeta 0.1, stop",
     dict(scope=None, alpha=0.0, hmin=None, zeta=0.1, stop=True, friction=0.0)),
    ("frictionless-viscous-0.4", "frictionless, no vdW, no local damping, zeta 0.1, stop, 0.4 s",
     dict(scope=None, alpha=0.0, hmin=None, zeta=0.1, stop=True, friction=0.0, duration=0.4)),
    ("frictionless-contact", "frictionless, no vdW, alpha 0.7 contact-only, stop",
     dict(scope="contact-forces", alpha=0.7, hmin=None, zeta=0.0, stop=True, friction=0.0)),
]


def make_scene(base, change, seed, duration, out_dir):
    scene = json.loads(json.dumps(base))
    scene["insertion"]["seed"] = seed
    scene["duration_s"] = duration
    material = scene["material"]
    physics = scene["physics"]
    material["contact_law"]["parameters"]["damping_ratio"] = change["zeta"]
    if change["scope"] is None:
        physics["local_damping"] = False
    else:
        physics["local_damping"] = True
        material["local_damping"] = change["alpha"]
        if change["scope"] != "unbalanced-force":  # the default stays unwritten
            material["local_damping_scope"] = change["scope"]
    if change["hmin"] is None:
        physics["van_der_waals"] = False
    else:
        physics["van_der_waals"] = True
        material["vdw_min_gap_m"] = change["hmin"]
    physics["stop_at_first_contact"] = change["stop"]
    friction = change.get("friction", 0.364)
    if friction == 0:
        physics["tangential"] = False
        physics["rotation"] = False
    material["friction"] = friction
    material["wall_friction"] = friction
    scene["outputs"]["directory"] = out_dir
    scene["measurement"]["history_interval_s"] = 0.0025
    return scene


def density_at(history, time_s):
    """The window density at time_s, linear between the two history rows around it."""
    for (t0, d0), (t1, d1) in zip(history, history[1:]):
        if t0 <= time_s <= t1:
            return d0 + (d1 - d0) * (time_s - t0) / (t1 - t0) if t1 > t0 else d0
    return float("nan")


def run_one(args, base, change, seed):
    key = f"{change['key']}_s{seed}"
    folder = os.path.join(args.work, key)
    os.makedirs(folder, exist_ok=True)
    scene_path = os.path.join(folder, "scene.json")
    text = json.dumps(make_scene(base, change, seed, change.get("duration", args.duration), "out"),
                      indent=1)
    summary_path = os.path.join(folder, "out", "summary.json")
    # A cached run counts only for the same scene text (a changed base scene runs again).
    same_scene = os.path.exists(scene_path) and open(scene_path).read() == text
    with open(scene_path, "w") as f:
        f.write(text)
    if not same_scene or not os.path.exists(summary_path):
        command = ["nice", "-n", str(args.nice), args.bouncecal, "pack", scene_path]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{key}: bouncecal pack failed ({done.returncode}): {done.stdout}{done.stderr}")
    with open(summary_path) as f:
        summary = json.load(f)
    with open(os.path.join(folder, "out", "history.csv")) as f:
        history = [(float(r["time_s"]), float(r["packing_density"])) for r in csv.DictReader(f)]
    return dict(exact=summary["packing_density"], count=summary["packing_density_by_count"],
                z=summary["mean_coordination"], at0=density_at(history, 0.0),
                at1=density_at(history, 0.0475), at2=density_at(history, 0.147),
                ke=summary["kinetic_energy_j"])


def pull_off_in_weights(base, hmin):
    """Van der Waals at contact, A R / (12 h_min^2), over the weight of one disk (a sphere's mass)."""
    if hmin is None:
        return "-"
    diameter = base["particles"]["diameter_m"]
    density = base["particles"]["species"][0]["density_kg_per_m3"]
    weight = density * math.pi / 6 * diameter**3 * base["gravity_mps2"]
    force = base["material"]["hamaker_j"] * (diameter / 2) / (12 * hmin**2)
    return f"{force / weight:.3g}"


def fmt(values, digits=3):
    values = [v for v in values if v == v]
    if not values:
        return "-"
    mean = statistics.fmean(values)
    sd = statistics.stdev(values) if len(values) > 1 else 0.0
    return f"{mean:.{digits}f} ± {sd:.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bouncecal", default=os.path.join(REPO, "build", "apps", "bouncecal"))
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--duration", type=float, default=0.2)
    parser.add_argument("--work", default="/tmp/paper004_choice_map")
    parser.add_argument("--rows", default="", help="comma-separated row keys (default: all)")
    parser.add_argument("--nice", type=int, default=10)
    args = parser.parse_args()
    with open(BASE) as f:
        base = json.load(f)
    wanted = [r for r in args.rows.split(",") if r]
    rows = [r for r in ROWS if not wanted or r[0] in wanted]
    print(f"{args.seeds} seeds, {args.duration} s each; mean ± sd over the seeds\n")
    print("| choice | pull-off / weight | area fraction (exact) | by count (paper's) | "
          "coordination | at 0.0475 s | at 0.147 s |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    print("| paper 004 | ? | 0.8236 | 0.8236 | 3.609 | 0.6894 | 0.8236 |")
    for key, label, change in rows:
        change = dict(change, key=key)
        results = [run_one(args, base, change, seed) for seed in range(1, args.seeds + 1)]
        column = lambda name: [r[name] for r in results]  # noqa: E731
        print(f"| {label} | {pull_off_in_weights(base, change['hmin'])} | "
              f"{fmt(column('exact'))} | {fmt(column('count'))} | "
              f"{fmt(column('z'), 2)} | {fmt(column('at1'))} | {fmt(column('at2'))} |",
              flush=True)


if __name__ == "__main__":
    main()
