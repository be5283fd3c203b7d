"""bouncecal.calibrate against `bouncecal calibrate`, the analytic check and the sample's truth."""

import json
import pathlib

import numpy
import pytest

import bouncecal

# samples/steel_ball_h0.2m.wav: eta = 0.58 at every impact, so gamma_n = eta / (2 - eta) for the
# paper's law (docs/physics.md section 2).
TRUE_GAMMA_N = 0.58 / (2 - 0.58)
CREATED_AT = 1700000000  # 2023-11-14T22:13:20Z


@pytest.fixture(scope="module")
def fit(steel_sample):
    return bouncecal.calibrate(steel_sample, ball="steel-10mm", drop_height_m=0.2)


def test_calibrate_gives_what_the_command_writes_and_the_same_card(cli, steel_sample, fit,
                                                                   tmp_path):
    # The fit is deterministic (no random draws, results independent of the thread count), so
    # the command's JSON and card must equal the module's exactly, the card byte for byte when
    # both are stamped with the same time.
    card = tmp_path / "cli_card.json"
    expected = cli.json("calibrate", steel_sample, "--ball", "steel-10mm", "--drop-height-m", "0.2",
                        "--card", card, output=tmp_path / "fit.json",
                        env={"SOURCE_DATE_EPOCH": str(CREATED_AT)})
    assert fit.to_dict() == expected
    written = fit.write_card(tmp_path / "module_card.json", created_at=CREATED_AT)
    assert (tmp_path / "module_card.json").read_bytes() == card.read_bytes()
    assert written.to_dict() == json.loads(card.read_text())
    assert written.created_utc == "2023-11-14T22:13:20Z"


def test_the_fit_recovers_the_damping_the_sample_was_made_with(fit):
    # The 95 % interval holds onset timing only (uncertainty.model says so); the default time
    # step biases gamma_n by an amount the analytic check states (time_step_gamma_error, about
    # -4e-4 here, twice the interval's half-width). Corrected by it, the interval must hold the
    # truth. The fit must agree with the closed form gamma = eta-bar / (2 - eta-bar) within what
    # the check says explains a difference (time step, gravity during contact, 2 sigma of
    # eta-bar, optimiser tolerance).
    gamma = fit.parameters.gamma_n
    low, high = fit.confidence_interval.gamma_n
    assert low < gamma < high
    correction = fit.analytic.time_step_gamma_error
    assert low + correction < TRUE_GAMMA_N < high + correction
    check = fit.analytic
    assert check.applicable and not check.warning
    assert abs(gamma - check.gamma_n) <= check.explained
    assert check.gamma_n == pytest.approx(check.energy_loss_mean / (2 - check.energy_loss_mean),
                                          rel=1e-12)
    assert "timing" in fit.uncertainty.model or fit.uncertainty.model
    assert fit.fitted_parameters[0].name == "gamma_n"
    assert isinstance(fit.confidence_interval.gamma_n, numpy.ndarray)


def test_the_card_states_the_fit(fit):
    card = fit.card(created_at=CREATED_AT)
    assert card.format == "bouncecal-material/1"
    assert card.contact_law.law == "walton-braun"
    assert card.contact_law.parameters.gamma_n == fit.parameters.gamma_n
    assert card.ball.preset == "steel-10mm"
    numpy.testing.assert_array_equal(card.fit.confidence_interval.gamma_n,
                                     fit.confidence_interval.gamma_n)
    assert card.fit.uncertainty.model == fit.uncertainty.model
    assert [r.file for r in card.recordings] == ["steel_ball_h0.2m.wav"]


def test_an_analysis_or_its_onsets_fit_like_the_recording(steel_sample):
    # analyze() without a drop height finds the sequences calibrate reads from the recording
    # (the same default options), so fitting the analysis gives the same result to the bit; the
    # onsets with their uncertainties as an (n, 2) array differ only in the sequence's name.
    options = dict(ball="steel-10mm", analytic_check=False)
    from_path = bouncecal.calibrate([steel_sample], **options)
    analysis = bouncecal.analyze(steel_sample)
    from_analysis = bouncecal.calibrate([analysis], **options)
    assert from_analysis.to_dict() == from_path.to_dict()
    sequence = analysis.sequences[0]
    onsets = numpy.column_stack([sequence.onsets_s, sequence.onset_uncertainty_s])
    from_array = bouncecal.calibrate([onsets], **options)
    assert from_array.sequences[0].source == "array 0"
    assert from_array.parameters.to_dict() == from_path.parameters.to_dict()
    assert from_array.confidence_interval.to_dict() == from_path.confidence_interval.to_dict()
    # A card lists the recordings it rests on: the analysis names its file, an array none.
    assert [r.file for r in from_analysis.card(created_at=0).recordings] == [
        "steel_ball_h0.2m.wav"]
    assert from_array.card(created_at=0).recordings == []


def test_an_analysis_passes_its_flight_uncertainties_to_the_fit(steel_sample):
    # A leading run the detector doubts as a whole states the flight after it
    # (incoming_flight_uncertainty_s, docs/json.md); calibrate must take it from an analysis as it
    # does from the recording, or the interval would narrow by the doubt. 1 ms on the flight that
    # ends eta-bar's first three losses is 20 times the sample's onset sigmas.
    options = dict(ball="steel-10mm", analytic_check=False)
    analysis = bouncecal.analyze(steel_sample)
    stated = bouncecal.calibrate([analysis], **options).fitted_parameters[0].standard_error
    analysis.sequences[0].incoming_flight_uncertainty_s[3] = 1e-3
    doubted = bouncecal.calibrate([analysis], **options).fitted_parameters[0].standard_error
    assert doubted > 2 * stated


def test_a_card_needs_the_ball(steel_sample, tmp_path):
    fit = bouncecal.calibrate(steel_sample, analytic_check=False)
    assert fit.ball_given is False
    with pytest.raises(bouncecal.ConfigError, match="ball=NAME"):
        fit.card()
    with pytest.raises(bouncecal.ConfigError):
        fit.write_card(tmp_path / "card.json")
    assert not (tmp_path / "card.json").exists()


def test_an_unwritable_card_raises_output_error(fit, tmp_path):
    target = tmp_path / "no such folder" / "card.json"
    with pytest.raises(bouncecal.OutputError) as raised:
        fit.write_card(target)
    assert isinstance(raised.value, OSError) and raised.value.exit_status == 4
    assert str(target.parent) in str(raised.value)


def test_a_missing_recording_raises_the_commands_message(cli, tmp_path):
    missing = str(tmp_path / "drop.wav")
    message, status = cli.error("calibrate", missing)
    with pytest.raises(bouncecal.InputError) as raised:
        bouncecal.calibrate([missing])
    assert str(raised.value) == message and status == 2


def test_an_unknown_objective_raises_the_commands_message(cli, steel_sample):
    message, _ = cli.error("calibrate", steel_sample, "--objective", "residuals")
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.calibrate(steel_sample, objective="residuals")
    assert str(raised.value) == message


def test_an_onset_uncertainty_out_of_range_is_one_rule_spelt_by_each_front_end(cli, steel_sample):
    # ImpactTimesOptions::Validate: the same sentence naming the flag there and the keyword here.
    message, status = cli.error("calibrate", steel_sample, "--onset-uncertainty-s", "-1")
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.calibrate(steel_sample, onset_uncertainty_s=-1.0)
    assert "--onset-uncertainty-s must be a positive number" in message and status == 3
    assert str(raised.value) == message.replace("--onset-uncertainty-s", "onset_uncertainty_s")


@pytest.mark.parametrize("arguments, error, words", [
    ({"inputs": []}, bouncecal.ConfigError, "give at least one input"),
    ({"inputs": [numpy.array([[0.1, 0.2, 0.3]])]}, bouncecal.InputError, "inputs[0]"),
    ({"inputs": [numpy.array([0.1, numpy.nan, 0.3])]}, bouncecal.InputError, "row 1"),
    ({"diameter_m": 0.01}, bouncecal.ConfigError, "diameter_m needs density_kg_per_m3"),
    ({"drop_height_uncertainty_m": 0.001}, bouncecal.ConfigError, "needs drop_height_m"),
    ({"confidence_level": 1.0}, bouncecal.ConfigError, "confidence_level must be in (0, 1)"),
    ({"ranges": {"gamma_n": (0.1,)}}, bouncecal.ConfigError, "ranges['gamma_n']"),
    ({"onset_uncertainty_s": 0}, bouncecal.ConfigError, "onset_uncertainty_s"),
])
def test_bad_arguments_raise_one_line_errors(steel_sample, arguments, error, words):
    arguments = {"inputs": steel_sample, **arguments}
    with pytest.raises(error) as raised:
        bouncecal.calibrate(**arguments)
    assert words in str(raised.value) and "\n" not in str(raised.value)


@pytest.mark.parametrize("drop_height_m, first", [(None, 1), (0.2, 0)])
def test_measured_and_simulated_impacts_are_numbered_alike(cli, steel_sample, tmp_path,
                                                           drop_height_m, first):
    # impact_index is the impact's 0-based place in its measured sequence, for the measurement
    # and for the fitted drop alike, so entry j of both is one impact and a plot of both against
    # impact_index lines up. Without a height e_1 is not measured and the drop starts from the
    # first measured apex: both start at impact 1. The command's JSON is the same serializer's.
    keywords = {} if drop_height_m is None else {"drop_height_m": drop_height_m}
    fit = bouncecal.calibrate(steel_sample, analytic_check=False, **keywords)
    sequence = fit.sequences[0]
    measured, simulated = sequence.measured.impact_index, sequence.simulated.impact_index
    assert measured[0] == first and simulated[0] == first
    assert len(simulated) >= len(measured)
    numpy.testing.assert_array_equal(simulated[:len(measured)], measured)
    # Entry j of the fitted drop is its impact j, which lands where the measured impact of the
    # same impact_index was heard: the drop follows the sample's onsets to 0.2 ms over these
    # flights, while one impact off would be 50 ms or more (the last flights are 0.05-0.11 s).
    onsets = bouncecal.analyze(steel_sample, **keywords).sequences[0].onsets_s
    for j, index in enumerate(simulated):
        assert abs(sequence.simulated_onsets_s[j] - onsets[index]) < 2e-3, (j, index)
    arguments = [] if drop_height_m is None else ["--drop-height-m", drop_height_m]
    document = cli.json("calibrate", steel_sample, *arguments,
                        output=tmp_path / "fit.json")
    assert document["sequences"][0]["simulated"]["impact_index"] == simulated.tolist()


@pytest.mark.parametrize("command", ["analyze", "calibrate"])
def test_a_rebound_above_the_drop_height_names_the_keyword_in_python_and_the_flag_on_the_cli(
        cli, steel_sample, command):
    # The sample's first rebound rises to 0.084 m, above a 0.05 m release. One library message
    # (calibrate::RefuseReboundAboveRelease) naming the field: each front end spells it its way.
    message, status = cli.error(command, steel_sample, "--drop-height-m", "0.05")
    assert "first rebound rose to 0.08" in message and "omit --drop-height-m" in message
    with pytest.raises(bouncecal.ConfigError) as raised:
        getattr(bouncecal, command)(steel_sample, drop_height_m=0.05)
    text = str(raised.value)
    assert "omit drop_height_m" in text and "--" not in text
    assert text == message.replace("--drop-height-m", "drop_height_m")
    assert raised.value.exit_status == status == 3


def test_each_input_takes_its_own_drop_height_as_on_the_command_line(cli, steel_sample, tmp_path):
    # The shipped samples were dropped from 0.2 m (one drop) and 0.15 m (two drops): a list gives
    # each input its height, in order, and the fit is the command's with --drop-height-m given
    # once per recording, number for number.
    stereo = str(pathlib.Path(steel_sample).with_name("steel_ball_stereo_44k.wav"))
    fit = bouncecal.calibrate([steel_sample, stereo], ball="steel-10mm", drop_height_m=[0.2, 0.15])
    expected = cli.json("calibrate", steel_sample, stereo, "--ball", "steel-10mm",
                        "--drop-height-m", "0.2", "--drop-height-m", "0.15",
                        output=tmp_path / "fit.json")
    assert fit.to_dict() == expected
    assert [s.drop_height_m for s in fit.sequences] == [0.2, 0.15, 0.15]
    # A count that matches neither one nor the inputs names the keyword.
    with pytest.raises(bouncecal.ConfigError, match="drop_height_m gives 3 values for 2 inputs"):
        bouncecal.calibrate([steel_sample, stereo], ball="steel-10mm",
                            drop_height_m=[0.2, 0.15, 0.1])


def test_contact_duration_sets_the_stiffness_as_on_the_command_line(cli, steel_sample, tmp_path):
    fit = bouncecal.calibrate(steel_sample, ball="steel-10mm", drop_height_m=0.2,
                              contact_duration_s=1e-4)
    expected = cli.json("calibrate", steel_sample, "--ball", "steel-10mm", "--drop-height-m", "0.2",
                        "--contact-duration-s", "1e-4", output=tmp_path / "fit.json")
    assert fit.to_dict() == expected
    with pytest.raises(bouncecal.ConfigError, match="contact_duration_s needs the ball"):
        bouncecal.calibrate(steel_sample, drop_height_m=0.2, contact_duration_s=1e-4)


def test_a_short_recording_averages_what_it_gives_unless_first_n_is_given():
    # A steel-on-lead drop (e = 0.5) from 0.30 m of which three impacts were heard: 2 energy
    # losses with the height. As on the command line (DropHeightCli), first_n left out averages
    # the 2 with a warning, first_n=3 refuses, first_n=2 fits the same without the warning.
    fall = 0.2473  # sqrt(2 * 0.30 / 9.81)
    onsets = numpy.array([0.5, 0.5 + fall, 0.5 + 1.5 * fall])
    default = bouncecal.calibrate([onsets], drop_height_m=0.3, analytic_check=False)
    assert default.sequences[0].first_n == 2
    assert any("gives 2 energy losses" in w and "first_n=2" in w for w in default.warnings)
    chosen = bouncecal.calibrate([onsets], drop_height_m=0.3, analytic_check=False, first_n=2)
    assert chosen.parameters.to_dict() == default.parameters.to_dict()
    assert not chosen.warnings
    with pytest.raises(bouncecal.ConfigError, match="first_n 3 needs that many"):
        bouncecal.calibrate([onsets], drop_height_m=0.3, first_n=3)
