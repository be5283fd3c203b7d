#!/usr/bin/env python3
"""Packing speed and memory against size: the scale table of docs/packing.md.

A 2000-sphere tile of paper 000's spheres and material (d = 1 cm steel, walton-braun
gamma_n = 0.5, mu = 0.3, dt = 10 us) in an open box of the paper's floor area is settled once
(pack_bench --settle), then laid side by side nx x ny times in a box that many times wider:
the settled regime at 2e3 .. 1e6 spheres without settling a million spheres for 0.3 s. The
tiles never overlap (each tile's particles lay inside its own walls). The pouring regime is
each size's own random start (pack_bench places every sphere at t = 0 at a quarter of solid
volume over the floor) timed from rest as it falls.

    bench/pack_scale.py BUILD_DIR [--threads N] [--sizes 2000,20000,...] [--work DIR]

Prints one row per size and regime: particles, steps, wall, particle-steps per wall and per cpu
second, the steady speed (two runs of different length differenced: no set-up), peak memory
and the coordination of the timed state. On a shared host the cpu figures are the comparable
ones. Figures only, like every bench: nothing here asserts a time.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys

TILE = 2000
SIDE_M = 0.18  # the paper's cylinder floor, pi 0.1^2 m^2, as a square
HEIGHT_M = 0.2
# Particle-steps per timed run: ~10 s of wall at the engine's speed on two threads.
PARTICLE_STEPS = 2e8


def scene(count, nx, ny, insertion):
    return {
        "format": "bouncecal-scene/1",
        "name": f"scale_{count}",
        "dimension": 3,
        "particles": {"count": count, "diameter_m": 0.01,
                      "species": [{"name": "steel", "density_kg_per_m3": 7800,
                                   "volume_fraction": 1}]},
        "container": {"type": "box", "min_m": [0, 0, 0],
                      "max_m": [nx * SIDE_M, ny * SIDE_M, HEIGHT_M]},
        "insertion": insertion,
        "material": {"contact_law": {"law": "walton-braun",
                                     "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": 0.5}},
                     "tangential_stiffness_n_per_m": 1e7, "friction": 0.3,
                     "wall_friction": 0.3},
        "physics": {"tangential": True, "rotation": True, "van_der_waals": False,
                    "local_damping": False},
        "time_step_s": 1e-5,
        "duration_s": 0.01,
        "gravity_mps2": 9.8,
        "measurement": {"band_m": [0.005, 0.045], "history_interval_s": 1},
        "outputs": {"directory": "out", "snapshot_interval_s": 0},
    }


def pour(nx, ny):
    return {"type": "pour",
            "region": {"type": "box", "min_m": [0.005, 0.005, 0.01],
                       "max_m": [nx * SIDE_M - 0.005, ny * SIDE_M - 0.005, HEIGHT_M]},
            "batch_interval_s": 0.1, "seed": 1}


def grid(tiles):
    """nx x ny = tiles, as square as it divides."""
    nx = int(math.isqrt(tiles))
    while tiles % nx:
        nx -= 1
    return tiles // nx, nx


def read_atoms(path):
    rows = []
    with open(path) as f:
        lines = f.read().splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("Atoms")) + 2
    for line in lines[start:]:
        fields = line.split()
        if len(fields) < 7:
            break
        rows.append([float(x) for x in fields[2:7]])  # diameter density x y z
    return rows


def write_tiled(path, rows, nx, ny):
    count = len(rows) * nx * ny
    with open(path, "w") as f:
        f.write(f"LAMMPS data file: {nx} x {ny} settled tiles (bench/pack_scale.py)\n\n")
        f.write(f"{count} atoms\n1 atom types\n")
        f.write(f"-0.01 {nx * SIDE_M + 0.01} xlo xhi\n-0.01 {ny * SIDE_M + 0.01} ylo yhi\n")
        f.write(f"-0.01 {HEIGHT_M + 0.01} zlo zhi\n\nAtoms # sphere\n\n")
        atom = 0
        for ix in range(nx):
            for iy in range(ny):
                for d, rho, x, y, z in rows:
                    atom += 1
                    f.write(f"{atom} 1 {d:.9g} {rho:.9g} {x + ix * SIDE_M:.9g} "
                            f"{y + iy * SIDE_M:.9g} {z:.9g}\n")


def bench(pack_bench, scene_path, duration_s, threads, work, settle_s=0):
    command = [pack_bench, scene_path, "--duration", repr(duration_s), "--threads",
               str(threads), "--no-lammps", "--no-liggghts", "--work", work]
    if settle_s:
        command += ["--settle", repr(settle_s)]
    out = subprocess.run(command, check=True, capture_output=True, text=True).stdout
    wall = float(re.search(r"wall ([0-9.]+) s", out).group(1))
    cpu = float(re.search(r"cpu ([0-9.]+) s", out).group(1))
    rate = float(re.search(r"([0-9.e+]+) particle-steps/s \(wall\)", out).group(1))
    per_cpu = float(re.search(r"([0-9.e+]+) per cpu-second", out).group(1))
    memory = float(re.search(r"peak resident memory ([0-9.]+) MiB", out).group(1))
    coordination = float(re.search(r"mean coordination ([0-9.]+)", out).group(1))
    return wall, cpu, rate, per_cpu, memory, coordination, out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--sizes", default="2000,20000,100000,1000000")
    parser.add_argument("--work", default="/tmp/bouncecal_pack_scale")
    parser.add_argument("--settle", type=float, default=0.3)
    parser.add_argument("--particle-steps", type=float, default=PARTICLE_STEPS,
                        help="work per timed run (particles x steps)")
    args = parser.parse_args()
    pack_bench = os.path.join(args.build, "bench", "pack_bench")
    os.makedirs(args.work, exist_ok=True)

    # The settled tile.
    tile_scene = os.path.join(args.work, "tile.json")
    with open(tile_scene, "w") as f:
        json.dump(scene(TILE, 1, 1, pour(1, 1)), f, indent=1)
    tile_work = os.path.join(args.work, "tile")
    bench(pack_bench, tile_scene, 1e-5, args.threads, tile_work, settle_s=args.settle)
    rows = read_atoms(os.path.join(tile_work, "start.data"))

    print("| spheres | regime | steps | wall s | particle-steps/s (wall) | per cpu-second | "
          "steady, per cpu-second | peak memory MiB | bytes/sphere | coordination |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for size in (int(float(s)) for s in args.sizes.split(",")):
        nx, ny = grid(max(1, size // TILE))
        count = TILE * nx * ny
        steps = max(100, int(args.particle_steps / count))
        data = os.path.join(args.work, f"settled_{count}.data")
        write_tiled(data, rows, nx, ny)
        regimes = {
            "settled": scene(count, nx, ny, {"type": "file", "path": data}),
            "pouring": scene(count, nx, ny, pour(nx, ny)),
        }
        for regime, spec in regimes.items():
            path = os.path.join(args.work, f"{regime}_{count}.json")
            with open(path, "w") as f:
                json.dump(spec, f, indent=1)
            # The same start run for `steps` and for 3 x `steps`: the difference of their cpu
            # times is the stepping alone, without the set-up (start file, first neighbour list),
            # which dominates a short run of a large pack.
            short = bench(pack_bench, path, steps * 1e-5, args.threads,
                          os.path.join(args.work, f"{regime}_{count}_short"))
            wall, cpu, rate, per_cpu, memory, coordination, _ = bench(
                pack_bench, path, 3 * steps * 1e-5, args.threads,
                os.path.join(args.work, f"{regime}_{count}"))
            steady = 2 * steps * count / max(cpu - short[1], 1e-9)
            print(f"| {count} | {regime} | {3 * steps} | {wall:.2f} | {rate:.3g} | {per_cpu:.3g} | "
                  f"{steady:.3g} | {memory:.0f} | {memory * 2**20 / count:.0f} | "
                  f"{coordination:.2f} |", flush=True)


if __name__ == "__main__":
    sys.exit(main())
