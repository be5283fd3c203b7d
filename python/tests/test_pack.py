"""bouncecal.pack against free fall and `bouncecal pack`."""

import copy
import json

import numpy
import pytest

import bouncecal

G = 9.81

# One sphere released from rest in an empty cylinder for 0.05 s: it never reaches the floor
# (tests/consumer/main.cc runs the same scene through the installed C++ package).
FREE_FALL = {
    "format": "bouncecal-scene/1",
    "particles": {"count": 1, "diameter_m": 0.01, "species": [{"density_kg_per_m3": 7800}]},
    "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.2},
    "insertion": {"type": "random",
                  "region": {"type": "cylinder", "radius_m": 0.02, "z_min_m": 0.1,
                             "z_max_m": 0.12}},
    "material": {"contact_law": {"law": "walton-braun"}},
    "time_step_s": 1e-5, "duration_s": 0.05, "gravity_mps2": G,
    "measurement": {"band_m": [0.005, 0.02]},
}

# 40 spheres dropped into a cylinder and left to settle for 0.3 s: contacts with the floor,
# the wall and each other.
SMALL_POUR = copy.deepcopy(FREE_FALL)
SMALL_POUR["particles"]["count"] = 40
SMALL_POUR["insertion"]["region"].update({"z_min_m": 0.01, "z_max_m": 0.1})
SMALL_POUR["duration_s"] = 0.3
SMALL_POUR["measurement"]["band_m"] = [0.0, 0.02]


def test_a_sphere_falls_freely_at_g():
    # Velocity Verlet is exact under a constant force: only rounding (1e-9 relative) separates
    # the final speed from g t.
    result = bouncecal.pack(FREE_FALL)
    state = result.final_state
    assert state.position_m.shape == (1, 3) and state.velocity_mps.shape == (1, 3)
    assert result.simulated_s == pytest.approx(0.05, abs=1e-12)
    assert state.velocity_mps[0, 2] == pytest.approx(-G * result.simulated_s, rel=1e-9)
    assert state.velocity_mps[0, :2].tolist() == [0, 0]
    # The history samples the scene's 0.01 s interval from t = 0 to the end.
    numpy.testing.assert_allclose(result.history.time_s, numpy.linspace(0, 0.05, 6), atol=1e-12)
    assert result.history.particles.dtype == numpy.int64
    # The kinetic energy is m (g t)^2 / 2 at every history sample.
    mass = 7800 * numpy.pi * 0.01 ** 3 / 6
    numpy.testing.assert_allclose(result.history.kinetic_energy_j,
                                  mass * (G * result.history.time_s) ** 2 / 2, rtol=1e-9)


def test_pack_gives_the_summary_the_command_writes(cli, tmp_path):
    # The run is deterministic for a scene and seed, whatever the threads; only the wall-clock
    # figures differ between two runs. The module adds history, profile and final_state (the
    # command's CSV files).
    scene = tmp_path / "pour.json"
    scene.write_text(json.dumps(SMALL_POUR))
    expected = cli.json("pack", scene, "--output", tmp_path / "out", output=tmp_path / "s.json")
    result = bouncecal.pack(str(scene), threads=2).to_dict()
    for extra in ("history", "profile", "final_state"):
        del result[extra]
    for timing in ("wall_s", "total_wall_s", "particle_steps_per_s", "threads"):
        del result[timing], expected[timing]
    assert result == expected
    assert expected["particles"] == 40 and expected["packing_density"] > 0


def test_single_precision_gives_the_summary_pack_precision_single_writes(cli, tmp_path):
    # The same option as the command's: the same bits (the run is deterministic in either
    # precision) and a summary that says which arithmetic made it.
    scene = tmp_path / "pour.json"
    scene.write_text(json.dumps(SMALL_POUR))
    expected = cli.json("pack", scene, "--precision", "single", "--output", tmp_path / "out",
                        output=tmp_path / "s.json")
    result = bouncecal.pack(str(scene), precision="single").to_dict()
    for extra in ("history", "profile", "final_state"):
        del result[extra]
    for timing in ("wall_s", "total_wall_s", "particle_steps_per_s", "threads"):
        del result[timing], expected[timing]
    assert result == expected
    assert expected["contact_precision"] == "single"
    assert bouncecal.pack(FREE_FALL).contact_precision == "double"


def test_a_scene_dict_runs_like_the_same_scene_file(tmp_path):
    scene = tmp_path / "pour.json"
    scene.write_text(json.dumps(SMALL_POUR))
    from_file = bouncecal.pack(scene)
    from_dict = bouncecal.pack(SMALL_POUR)
    assert from_dict.packing_density == from_file.packing_density
    numpy.testing.assert_array_equal(from_dict.final_state.position_m,
                                     from_file.final_state.position_m)
    assert from_dict.scene.endswith("(scene dict)")
    profile = from_dict.profile
    assert profile.height_m.shape == profile.density.shape and len(profile) > 0
    assert numpy.all((profile.density >= 0) & (profile.density < 1))


def test_a_bad_scene_file_raises_the_commands_message(cli, tmp_path):
    bad = copy.deepcopy(FREE_FALL)
    bad["particles"]["cuont"] = 3
    scene = tmp_path / "bad.json"
    scene.write_text(json.dumps(bad))
    message, status = cli.error("pack", scene, "--output", tmp_path / "out")
    with pytest.raises(bouncecal.InputError) as raised:
        bouncecal.pack(scene)
    assert str(raised.value) == message and status == 2
    with pytest.raises(bouncecal.InputError, match="cuont"):
        bouncecal.pack(bad)


@pytest.mark.parametrize("arguments, words", [
    ({"duration_s": 1e-6}, "below the scene's time_step_s"),
    ({"duration_s": -1.0}, "duration_s must be in [0, 1e6]"),
    ({"threads": 0}, "threads"),
    ({"precision": "half"}, 'precision must be "double" or "single"'),
])
def test_bad_options_raise_config_errors(arguments, words):
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.pack(FREE_FALL, **arguments)
    assert words in str(raised.value)


def test_a_scene_that_is_neither_a_path_nor_a_dict_is_refused():
    with pytest.raises(bouncecal.ConfigError, match="scene must be"):
        bouncecal.pack(42)
    with pytest.raises(bouncecal.ConfigError, match="not a finite number"):
        bouncecal.pack({**FREE_FALL, "time_step_s": float("inf")})


def boiling_scene(step_s):
    """40 frictionless spheres for 0.5 s: at 2e-5 s (0.86 of one contact's stability limit) they
    never settle, at 1e-5 s they come to rest (tests/pack_cli_test.cc, WriteBoilingScene)."""
    return {
        "format": "bouncecal-scene/1",
        "particles": {"count": 40, "diameter_m": 0.01,
                      "species": [{"density_kg_per_m3": 7800}]},
        "container": {"type": "cylinder", "radius_m": 0.03, "height_m": 0.1},
        "insertion": {"type": "random",
                      "region": {"type": "cylinder", "radius_m": 0.03,
                                 "z_min_m": 0.0, "z_max_m": 0.05}},
        "physics": {"tangential": False, "rotation": False},
        "material": {"contact_law": {"law": "walton-braun"}},
        "time_step_s": step_s, "duration_s": 0.5,
        "measurement": {"band_m": [0.005, 0.02]},
    }


def test_a_boiling_pack_returns_its_result_with_a_runtime_warning():
    with pytest.warns(RuntimeWarning, match="boil"):
        result = bouncecal.pack(boiling_scene(2e-5))
    assert result["boiling"] is True
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a settled pack warns of nothing
        settled = bouncecal.pack(boiling_scene(1e-5))
    assert settled["boiling"] is False
