#!/usr/bin/env python3
"""Every JSON document a bouncecal command writes validates against its schema in docs/schema/.

Usage: json_schema_test.py BOUNCECAL SOURCE_DIR. Runs each command once on the shipped samples
(short runs), reads the document from a file or from standard output ("-"), and checks it with
python3-jsonschema (scripts/install_deps.sh). Exit 0 when all validate, 1 otherwise, 77 (ctest's
skip code) when jsonschema is not installed.
"""
import json
import pathlib
import subprocess
import sys
import tempfile

try:
    import jsonschema
except ImportError:
    print("python3-jsonschema is not installed (scripts/install_deps.sh); skipped")
    sys.exit(77)

bouncecal, source = sys.argv[1], pathlib.Path(sys.argv[2])
samples = source / "samples"
schemas = source / "docs" / "schema"
failures = []


def run(arguments):
    result = subprocess.run([bouncecal] + arguments, capture_output=True, text=True, timeout=600)
    if result.returncode != 0:
        failures.append(f"{' '.join(arguments)}: exit {result.returncode}: {result.stderr.strip()}")
        return None
    return result.stdout


def check(name, document, schema_file):
    schema = json.loads((schemas / schema_file).read_text())
    jsonschema.Draft7Validator.check_schema(schema)
    errors = sorted(jsonschema.Draft7Validator(schema).iter_errors(document), key=str)
    for error in errors:
        failures.append(f"{name}: {'/'.join(map(str, error.path))}: {error.message}")
    print(f"{name}: {'ok' if not errors else f'{len(errors)} error(s)'} against {schema_file}")


with tempfile.TemporaryDirectory(prefix="bouncecal_json_schema_") as folder:
    out = pathlib.Path(folder)
    steel = str(samples / "steel_ball_h0.2m.wav")
    pingpong = str(samples / "pingpong_hard.wav")
    # analyze: one shape for one recording and for several, both through "-".
    # Each recording with its own release height (the ping-pong sample fell from 0.25 m).
    for name, inputs, heights in (("analyze (one)", [steel], ["0.2"]),
                                  ("analyze (two)", [steel, pingpong], ["0.2", "0.25"])):
        height_options = [option for height in heights for option in ("--drop-height-m", height)]
        text = run(["analyze"] + inputs + height_options + ["--json", "-"])
        if text is not None:
            check(name, json.loads(text), "analysis.schema.json")
    fit, card = out / "fit.json", out / "card.json"
    if run(["calibrate", str(samples / "steel_ball_h0.2m.csv"), "--ball", "steel-10mm",
            "--drop-height-m", "0.2", "--json", str(fit), "--card", str(card)]) is not None:
        check("calibrate --json", json.loads(fit.read_text()), "fit.schema.json")
        check("calibrate --card", json.loads(card.read_text()), "material.schema.json")
    text = run(["calibrate", str(samples / "steel_ball_h0.2m.csv"), "--ball", "steel-10mm",
                "--drop-height-m", "0.2", "--compare-laws", "--laws",
                "walton-braun,linear-dashpot", "--json", "-"])
    if text is not None:
        check("calibrate --compare-laws --json", json.loads(text), "law-comparison.schema.json")
    text = run(["simulate", "drop", "--gamma", "0.5", "--json", "-"])
    if text is not None:
        check("simulate drop --json", json.loads(text), "drop.schema.json")
    text = run(["sweep", "--values", "0.3,0.5", "--json", "-"])
    if text is not None:
        check("sweep --json", json.loads(text), "sweep.schema.json")
    text = run(["compare", str(samples / "steel_ball_h0.2m.csv"), "--drop-height-m", "0.2",
                "--gamma", "0.4", "--json", "-"])
    if text is not None:
        check("compare --json", json.loads(text), "trajectory-comparison.schema.json")
    if card.exists():  # the card's height, ball and drag (issue 28)
        text = run(["compare", str(samples / "steel_ball_h0.2m.csv"), "--material", str(card),
                    "--json", "-"])
        if text is not None:
            check("compare --material --json", json.loads(text),
                  "trajectory-comparison.schema.json")
    text = run(["pack", str(samples / "scenes" / "paper004_binary_c1.json"), "--duration-s", "0",
                "-o", str(out / "pack"), "--json", "-"])
    if text is not None:
        check("pack --json", json.loads(text), "pack.schema.json")

for failure in failures:
    print("FAILED:", failure)
sys.exit(1 if failures else 0)
