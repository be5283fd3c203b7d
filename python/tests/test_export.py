"""bouncecal.export and export_check against the closed form, `bouncecal export` and LAMMPS."""

import json
import math
import os
import shutil
import subprocess

import pytest

import bouncecal
from conftest import SOURCE_DIR

GAMMA_N = 0.4
CARD = {
    "format": "bouncecal-material/1",
    "contact_law": {"law": "walton-braun",
                    "parameters": {"stiffness_n_per_m": 1e7, "gamma_n": GAMMA_N}},
    "ball": {"diameter_m": 0.01, "density_kg_per_m3": 7800.0,
             "mass_kg": 7800.0 * math.pi * 0.01 ** 3 / 6},
    "fit": {"drop_height_m": 0.2},
}
SCENE = SOURCE_DIR / "samples" / "scenes" / "paper000_cylinder_pour.json"


@pytest.fixture
def card_file(tmp_path):
    path = tmp_path / "steel.json"
    path.write_text(json.dumps(CARD))
    return path


def test_the_drop_deck_promises_the_laws_closed_form_restitution():
    # The paper's law maps to the engines' spring-dashpot with equal e and contact duration, so
    # the deck must expect e = sqrt((1 - gamma) / (1 + gamma)) (docs/physics.md section 2) to
    # rounding.
    deck = bouncecal.export(CARD)
    assert deck.expected_restitution == pytest.approx(math.sqrt((1 - GAMMA_N) / (1 + GAMMA_N)),
                                                      rel=1e-12)
    assert deck.output_dir is None and deck.packing is None
    assert deck.drop_height_m == 0.2  # the card's fit height
    assert deck.input_file_name in deck.files and "deck.json" in deck.files
    assert deck.run_command.startswith("lmp")
    assert 0 < deck.time_step_error_bound <= 0.002


def test_export_writes_the_files_the_command_writes(cli, card_file, tmp_path):
    cli.run("export", "--material", card_file, "--engine", "lammps", "-o", tmp_path / "cli",
            "--scene", SCENE)
    deck = bouncecal.export(card_file, "lammps", tmp_path / "module", scene=SCENE)
    written = sorted(os.listdir(tmp_path / "module"))
    assert written == sorted(os.listdir(tmp_path / "cli"))
    assert written == sorted([*deck.files, *deck.packing.files])
    for name in written:
        assert (tmp_path / "module" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert "in.pack" in deck.packing.files


def test_a_missing_card_raises_the_commands_message(cli, tmp_path):
    missing = tmp_path / "card.json"
    message, status = cli.error("export", "--material", missing, "--engine", "lammps", "-o",
                                tmp_path / "deck")
    with pytest.raises(bouncecal.InputError) as raised:
        bouncecal.export(missing, output_dir=tmp_path / "deck")
    assert str(raised.value) == message and status == 2
    assert not (tmp_path / "deck").exists()


def test_an_option_a_library_message_names_is_the_keyword_here_and_the_flag_on_the_cli(
        cli, card_file, tmp_path):
    # The deck's unstable step is refused by one library message naming the option to use in
    # its neutral form (`max_step_error`, bouncecal/option_error.h): each front end spells it.
    message, status = cli.error("export", "--material", card_file, "--engine", "lammps",
                                "--time-step-s", "1e-3", "-o", tmp_path / "cli")
    assert "get one from --max-step-error" in message and "`" not in message
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.export(card_file, time_step_s=1e-3)
    text = str(raised.value)
    assert "get one from max_step_error" in text and "--" not in text and "`" not in text
    assert text == message.replace("--max-step-error", "max_step_error")
    assert raised.value.exit_status == status


@pytest.mark.parametrize("arguments, error, words", [
    ({"engine": "gromacs"}, bouncecal.ConfigError, "gromacs"),
    ({"material": 7}, bouncecal.ConfigError, "material must be"),
    ({"material": {**CARD, "format": "x"}}, bouncecal.InputError, "format"),
    ({"bounces": 0}, bouncecal.ConfigError, "bounces"),
])
def test_bad_arguments_raise_one_line_errors(arguments, error, words):
    arguments = {"material": CARD, **arguments}
    with pytest.raises(error) as raised:
        bouncecal.export(**arguments)
    assert words in str(raised.value) and "\n" not in str(raised.value)


@pytest.mark.skipif(shutil.which("lmp") is None, reason="LAMMPS (lmp) is not installed")
def test_lammps_bounces_as_the_deck_promised(tmp_path):
    deck = bouncecal.export(CARD, "lammps", tmp_path)
    subprocess.run(deck.run_command, shell=True, cwd=tmp_path, check=True,
                   capture_output=True, timeout=300)
    check = bouncecal.export_check(tmp_path)
    assert check.passed and check.judged > 0 and check.within == check.judged
    assert len(check.bounces) == len(check.bounces.restitution) >= check.judged
