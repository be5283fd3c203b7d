#!/usr/bin/env python3
"""The speed/accuracy trade of a packing scene: final state and cost against step and stiffness.

Runs `bouncecal pack` on a scene with its contact stiffness scaled (normal and tangential
together, so their ratio stays the scene's) and its time step set to a fraction of the stability
limit of that stiffness (the smaller of the normal and tangential limits that `pack` reports),
for several insertion seeds, and prints a Markdown table: area/volume fraction by the scene's
window or band (both estimators), mean coordination, steps per run (the cost, independent of the
machine's load) and wall time per run. A user picks the cheapest row whose answer lies within the seed spread of the finest.

    scripts/packing_step_map.py SCENE --bouncecal build/apps/bouncecal
        [--stiffness 100,1000] [--fractions 0.05,0.1,0.2,0.4,0.8] [--seeds 5]
        [--threads 1] [--work /tmp/packing_step_map] [--nice 5]

Standard library only. Runs are cached in --work and reused while their scene text is the same.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys


def run_pack(args, scene, folder, duration=None):
    os.makedirs(folder, exist_ok=True)
    scene_path = os.path.join(folder, "scene.json")
    scene = json.loads(json.dumps(scene))
    scene["outputs"]["directory"] = "out"
    scene["outputs"]["snapshot_interval_s"] = 0
    text = json.dumps(scene, indent=1)
    summary_path = os.path.join(folder, "out", "summary.json")
    # A cached run counts only for the same scene text (a changed scene file runs again).
    same_scene = os.path.exists(scene_path) and open(scene_path).read() == text
    with open(scene_path, "w") as f:
        f.write(text)
    if not same_scene or not os.path.exists(summary_path):
        command = ["nice", "-n", str(args.nice), args.bouncecal, "pack", scene_path,
                   "--threads", str(args.threads)]
        if duration is not None:
            # A zero-length run only reports the limits; the scene's own step may exceed a
            # stiffer spring's limit, which a real run would refuse.
            command += ["--duration-s", str(duration), "--allow-unstable-step"]
        done = subprocess.run(command, capture_output=True, text=True)
        if done.returncode != 0:
            sys.exit(f"{folder}: bouncecal pack failed ({done.returncode}): "
                     f"{done.stdout}{done.stderr}")
    with open(summary_path) as f:
        return json.load(f)


def with_stiffness(base, stiffness):
    scene = json.loads(json.dumps(base))
    material = scene["material"]
    normal = material["contact_law"]["parameters"]["stiffness_n_per_m"]
    material["contact_law"]["parameters"]["stiffness_n_per_m"] = stiffness
    if "tangential_stiffness_n_per_m" in material:
        material["tangential_stiffness_n_per_m"] *= stiffness / normal
    return scene


def stability_limit_s(args, scene, folder):
    """The smaller of the normal and tangential step limits, from a zero-length run."""
    summary = run_pack(args, scene, folder, duration=0)
    limits = [summary["time_step_limit_s"]]
    if summary.get("tangential_time_step_limit_s"):
        limits.append(summary["tangential_time_step_limit_s"])
    return min(limits)


def fmt(values, digits=3):
    mean = statistics.fmean(values)
    if len(values) < 2:
        return f"{mean:.{digits}f}"
    return f"{mean:.{digits}f} ± {statistics.stdev(values):.{digits}f}"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--bouncecal", default="build/apps/bouncecal")
    parser.add_argument("--stiffness", default="", help="N/m, comma-separated (default: the "
                        "scene's)")
    parser.add_argument("--fractions", default="0.05,0.1,0.2,0.4,0.8",
                        help="steps as fractions of the stability limit, or 'scene': the "
                        "scene's own time_step_s (seed statistics of the scene as shipped)")
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--work", default="/tmp/packing_step_map")
    parser.add_argument("--nice", type=int, default=5)
    args = parser.parse_args()
    with open(args.scene) as f:
        base = json.load(f)
    name = base["name"]
    default_k = base["material"]["contact_law"]["parameters"]["stiffness_n_per_m"]
    stiffnesses = [float(k) for k in args.stiffness.split(",") if k] or [default_k]
    own_step = args.fractions == "scene"
    fractions = [None] if own_step else [float(x) for x in args.fractions.split(",") if x]
    print(f"{name}: {args.seeds} seed(s), {base['duration_s']} s, {args.threads} thread(s); "
          f"mean ± sd over the seeds\n")
    print("| stiffness (N/m) | step (us) | step / limit | fraction (exact) | by count | "
          "coordination | steps per run | wall per run (s) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for stiffness in stiffnesses:
        scene_k = with_stiffness(base, stiffness)
        limit = stability_limit_s(args, scene_k, os.path.join(args.work, f"{name}_k{stiffness:g}"
                                                                         "_limit"))
        for fraction in fractions:
            step = base["time_step_s"] if own_step else fraction * limit
            fraction = step / limit
            results = []
            for seed in range(1, args.seeds + 1):
                scene = json.loads(json.dumps(scene_k))
                scene["time_step_s"] = step
                scene["insertion"]["seed"] = seed
                folder = os.path.join(args.work, f"{name}_k{stiffness:g}_dt{step:.6g}_s{seed}")
                results.append(run_pack(args, scene, folder))
            column = lambda key: [r[key] for r in results]  # noqa: E731
            print(f"| {stiffness:g} | {step * 1e6:.3g} | {fraction:.3g} | "
                  f"{fmt(column('packing_density'))} | "
                  f"{fmt(column('packing_density_by_count'))} | "
                  f"{fmt(column('mean_coordination'), 2)} | "
                  f"{statistics.fmean(column('steps')):.3g} | "
                  f"{statistics.fmean(column('wall_s')):.1f} |", flush=True)


if __name__ == "__main__":
    main()
