"""bouncecal.simulate_drop against closed forms and `bouncecal simulate drop --json`."""

import math

import numpy
import pytest

import bouncecal

G = 9.81


def test_simulate_drop_gives_exactly_what_the_command_writes(cli, tmp_path):
    # Same options, same library call: equal to the last bit. Recording the trajectory (the
    # module's default, not the command's without --trajectory) must not change the drop.
    expected = cli.json("simulate", "drop", "--law", "walton-braun", "--gamma", "0.4",
                        "--drop-height-m", "0.15", "--quiet", output=tmp_path / "drop.json")
    result = bouncecal.simulate_drop("walton-braun", {"gamma_n": 0.4}, drop_height_m=0.15)
    plain = result.to_dict()
    del plain["trajectory"]
    assert plain == expected


def test_the_exact_path_loses_the_closed_form_energy_and_flies_ballistically():
    # dem/src/drop_test.cc, ExactPathAgreesWithClosedFormAndBallistics, through the module: e_1 is
    # sqrt((1 - gamma) / (1 + gamma)) up to gravity acting during the contact, a relative effect
    # of order g t_c / v_out (tolerance twice that), and consecutive onsets are separated by the
    # contact plus the ballistic flight 2 v_out / g (to rounding of times near 1 s: 1e-12 s).
    for gamma in (0.1, 0.5, 0.9):
        drop = bouncecal.simulate_drop("walton-braun", {"gamma_n": gamma}, integrator="exact")
        impacts = drop.impacts
        assert len(impacts) >= 3
        e = math.sqrt((1 - gamma) / (1 + gamma))
        tolerance = 2 * G * impacts.contact_duration_s[0] / impacts.speed_out_mps[0]
        assert abs(impacts.restitution[0] - e) < tolerance * e
        released = impacts.released[:-1]
        gaps = numpy.diff(impacts.time_s)[released]
        flights = (impacts.contact_duration_s + 2 * impacts.speed_out_mps / G)[:-1][released]
        numpy.testing.assert_allclose(gaps, flights, rtol=0, atol=1e-12)
        numpy.testing.assert_allclose(impacts.energy_loss, 1 - impacts.restitution ** 2,
                                      rtol=0, atol=1e-15)


def test_the_trajectory_rises_to_the_height_each_rebound_speed_gives():
    # Flights are closed-form parabolas; a sample lies at most half an interval from the apex,
    # where the height is below v^2 / 2g by at most g (interval / 2)^2 / 2 (1.2e-8 m at 1e-4 s).
    interval = 1e-4
    drop = bouncecal.simulate_drop("walton-braun", {"gamma_n": 0.3}, drop_height_m=0.2,
                                   trajectory_interval_s=interval, max_impacts=6)
    trajectory = drop.trajectory
    assert trajectory.time_s.shape == trajectory.height_m.shape == trajectory.velocity_mps.shape
    assert trajectory.height_m[0] == pytest.approx(0.2, abs=1e-15)
    times = drop.impacts.time_s
    for k in range(len(times) - 1):
        flight = (trajectory.time_s > times[k]) & (trajectory.time_s < times[k + 1])
        apex = drop.impacts.speed_out_mps[k] ** 2 / (2 * G)
        highest = trajectory.height_m[flight].max()
        assert apex - G * (interval / 2) ** 2 / 2 - 1e-12 <= highest <= apex + 1e-12, k


def test_simulate_drop_returns_numpy_columns():
    drop = bouncecal.simulate_drop(parameters={"gamma_n": 0.5})
    count = len(drop.impacts)
    assert count > 3
    for name in ("time_s", "restitution", "energy_loss", "contact_duration_s", "max_overlap_m",
                 "speed_in_mps", "speed_out_mps"):
        assert drop.impacts[name].dtype == numpy.float64 and drop.impacts[name].shape == (count,)
    assert drop.impacts.released.dtype == numpy.bool_
    assert drop.ball.mass_kg == pytest.approx(7800 * math.pi * 0.01 ** 3 / 6, rel=1e-12)
    assert drop.contact_law.law == "walton-braun"
    assert drop.contact_law.parameters.gamma_n == 0.5


def test_a_law_dict_as_a_card_states_it_is_the_same_law():
    by_name = bouncecal.simulate_drop("linear-dashpot", {"damping_ratio": 0.2}, ball="glass-10mm")
    card_law = {"law": "linear-dashpot", "parameters": {"damping_ratio": 0.2}}
    by_dict = bouncecal.simulate_drop(card_law, ball="glass-10mm")
    assert by_dict.to_dict() == by_name.to_dict()


def test_a_law_parameter_out_of_range_raises_the_commands_message(cli):
    message, status = cli.error("simulate", "drop", "--gamma", "1.5")
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.simulate_drop("walton-braun", {"gamma_n": 1.5})
    assert str(raised.value) == message and status == 3


def test_an_unknown_law_raises_the_commands_message(cli):
    message, _ = cli.error("simulate", "drop", "--law", "walton")
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.simulate_drop("walton")
    assert str(raised.value) == message


@pytest.mark.parametrize("flags, keywords", [
    (["--diameter-m", "20"], {"diameter_m": 20.0}),
    (["--density-kg-per-m3", "0.5"], {"density_kg_per_m3": 0.5}),
    (["--mass-kg", "-1"], {"mass_kg": -1.0}),
])
def test_a_ball_out_of_range_is_refused_by_one_rule_spelt_by_each_front_end(cli, flags, keywords):
    # One rule for both (calibrate::ResolveBall): the same sentence, with the flag on the command
    # line where Python names the keyword, and the same exit status.
    message, status = cli.error("simulate", "drop", *flags)
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.simulate_drop(**keywords)
    for flag in ("--diameter-m", "--density-kg-per-m3", "--mass-kg"):
        message = message.replace(flag, flag[2:].replace("-", "_"))
    assert str(raised.value) == message and "--" not in message
    assert raised.value.exit_status == status == 3


@pytest.mark.parametrize("arguments, words", [
    ({"parameters": {"gamma_n": "0.4"}}, "parameters['gamma_n'] must be a number"),
    ({"parameters": [0.4]}, "parameters must be a dict"),
    ({"law": {"law": "walton-braun", "paramters": {}}}, "paramters"),
    ({"law": 3}, "law must be a law name"),
    ({"ball": "steel-10mm", "diameter_m": 0.02}, "names a preset"),
    ({"ball": "marble"}, "marble"),
    ({"density_kg_per_m3": 7800, "mass_kg": 0.004}, "give one of them"),
    ({"diameter_m": 20.0}, "diameter_m = 20 m is outside"),
    ({"integrator": "leapfrog"}, "leapfrog"),
    ({"drop_height_m": -1.0}, "drop_height_m"),
])
def test_bad_arguments_raise_one_line_config_errors(arguments, words):
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.simulate_drop(**arguments)
    assert words in str(raised.value) and "\n" not in str(raised.value)
