"""bouncecal.analyze against `bouncecal analyze --json` and the shipped sample's ground truth."""

import math
import wave

import numpy
import pytest

import bouncecal
from conftest import STEEL_SAMPLE, STEREO_SAMPLE


def cli_recording(json_value, path):
    """The per-recording object of `bouncecal analyze --json` for `path`, wherever the JSON's
    envelope puts it (one object, or an array of them with a summary)."""
    if isinstance(json_value, dict) and "recordings" in json_value:
        # The documented place; the top-level copy of a single recording is the deprecated shape.
        json_value = json_value["recordings"]
    if isinstance(json_value, dict):
        if json_value.get("file") == path:
            return json_value
        json_value = list(json_value.values())
    if isinstance(json_value, list):
        for item in json_value:
            if isinstance(item, (dict, list)):
                found = cli_recording(item, path)
                if found is not None:
                    return found
    return None


def read_pcm16(path):
    """A mono 16-bit WAV as float32 samples scaled as libsndfile scales them (1 / 32768)."""
    with wave.open(str(path)) as wav:
        assert wav.getsampwidth() == 2 and wav.getnchannels() == 1
        frames = wav.readframes(wav.getnframes())
        return numpy.frombuffer(frames, dtype="<i2").astype(numpy.float32) / 32768, \
            wav.getframerate()


@pytest.mark.parametrize("drop_height_m", [None, 0.2])
def test_analyze_gives_exactly_what_the_command_writes_for_the_sample(
        cli, steel_sample, tmp_path, drop_height_m):
    # The same library calls on the same file: every field and every number must be equal, not
    # merely close (the JSON writes doubles with enough digits to read them back exactly).
    extra = [] if drop_height_m is None else ["--drop-height-m", drop_height_m]
    expected = cli_recording(
        cli.json("analyze", steel_sample, *extra, output=tmp_path / "a.json"), steel_sample)
    assert expected is not None
    result = bouncecal.analyze(steel_sample, drop_height_m=drop_height_m)
    assert result.to_dict() == expected


def test_the_steel_sample_loses_the_energy_it_was_synthesised_with(steel_sample):
    # samples/steel_ball_h0.2m.wav was synthesised with eta = 0.58 at every impact (samples/
    # README.md). The detector's onsets are about 10 us off on flights of 0.25-0.40 s, which
    # moves eta-bar by less than 1e-3; 0.005 is the agreement the project asks of a recording
    # and its re-encoded copy. Each eta_k must lie within 4 of its own stated sigmas of 0.58
    # (the stated uncertainty is what a fit weights by; 4 sigma fails once in 16000 draws).
    result = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    assert len(result.sequences) == 1
    sequence = result.sequences[0]
    assert abs(sequence.energy_loss_mean_first_n - 0.58) < 0.005
    assert numpy.all(numpy.abs(sequence.energy_loss - 0.58) < 4 * sequence.energy_loss_uncertainty)
    # e_k = dt_k / dt_{k-1} with dt_0 = 2 sqrt(2 h0 / g): eta_k = 1 - e_k^2 (docs/physics.md 1).
    intervals = numpy.concatenate(
        [[2 * math.sqrt(2 * 0.2 / 9.81)], sequence.intervals_s])
    index = sequence.restitution_impact_index
    numpy.testing.assert_allclose(sequence.restitution, intervals[index + 1] / intervals[index],
                                  rtol=1e-12)
    numpy.testing.assert_allclose(sequence.energy_loss, 1 - sequence.restitution ** 2, rtol=1e-12)


def test_analyze_returns_numpy_columns_of_the_documented_types_and_lengths(steel_sample):
    result = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    impacts = result.impacts
    assert isinstance(impacts, bouncecal.Table)
    count = len(impacts)
    assert count >= len(result.sequences[0].onsets_s) >= 4
    for name in ("onset_s", "onset_uncertainty_s", "peak_dbfs", "rise_db",
                 "ringing_novelty_db", "snr_db", "sequence"):
        column = impacts[name]
        assert isinstance(column, numpy.ndarray) and column.dtype == numpy.float64, name
        assert column.shape == (count,), name
    for name in ("residual_only", "timed_from_response"):
        column = impacts[name]
        assert isinstance(column, numpy.ndarray) and column.dtype == numpy.bool_, name
        assert column.shape == (count,), name
    assert numpy.all(numpy.diff(impacts.onset_s) > 0)
    assert isinstance(result.rejected_events.time_s, numpy.ndarray)
    assert isinstance(result.rejected_events.reason, list)
    assert result.channel_impact_to_noise_db.shape == (1,)
    sequence = result.sequences[0]
    onsets = len(sequence.onsets_s)
    assert sequence.restitution_impact_index.dtype == numpy.int64
    for name, length in (("onsets_s", onsets), ("onset_uncertainty_s", onsets),
                         ("incoming_flight_uncertainty_s", onsets), ("intervals_s", onsets - 1), ("interval_uncertainty_s", onsets - 1),
                         ("bounce_height_m", onsets - 1), ("restitution", onsets - 1),
                         ("energy_loss_uncertainty", onsets - 1)):
        assert sequence[name].dtype == numpy.float64, name
        assert sequence[name].shape == (length,), name
    # The impacts of the sequence are the ones whose sequence column says 0.
    numpy.testing.assert_array_equal(impacts.onset_s[impacts.sequence == 0], sequence.onsets_s)


def test_samples_in_an_array_give_the_same_impacts_as_the_file(steel_sample):
    # The file is streamed through the detector in blocks, the array in one piece; the detector
    # keeps its own history, so block boundaries change nothing and the results are identical.
    samples, rate = read_pcm16(steel_sample)
    from_array = bouncecal.analyze(samples, sample_rate_hz=rate, drop_height_m=0.2)
    from_file = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    assert from_array.file is None
    assert from_array.duration_s == from_file.duration_s
    for name in from_file.impacts:
        numpy.testing.assert_array_equal(from_array.impacts[name], from_file.impacts[name])
    assert from_array.sequences[0].to_dict() == from_file.sequences[0].to_dict()
    # float64 input is converted to the detector's float32.
    again = bouncecal.analyze(samples.astype(numpy.float64), sample_rate_hz=rate)
    numpy.testing.assert_array_equal(again.impacts.onset_s, from_file.impacts.onset_s)


def test_a_stereo_file_is_analysed_on_the_channel_asked_for():
    # Channel 1 hears every event 0.25 ms later, 6 dB noisier (samples/README.md), so it may
    # find fewer of the late, quiet impacts: pair each of its onsets with channel 0's nearest
    # within 1 ms (bounces are at least 20 ms apart, so a pair is one event). The detector's
    # onsets are good to a few tens of us at 44.1 kHz and 24-30 dB SNR, so the mean shift of
    # ten or more pairs is 0.25 ms +- 0.05 ms; channel 0 read as channel 1 would give 0.
    left = bouncecal.analyze(str(STEREO_SAMPLE), channel=0)
    right = bouncecal.analyze(str(STEREO_SAMPLE), channel=1)
    assert (left.channel, right.channel, left.channel_count) == (0, 1, 2)
    shifts = []
    for onset in right.impacts.onset_s:
        nearest = left.impacts.onset_s[numpy.argmin(numpy.abs(left.impacts.onset_s - onset))]
        if abs(onset - nearest) < 1e-3:
            shifts.append(onset - nearest)
    assert len(shifts) >= 10
    assert abs(numpy.mean(shifts) - 0.25e-3) < 0.05e-3


def test_a_missing_file_raises_input_error_with_the_commands_message(cli, tmp_path):
    missing = str(tmp_path / "nothing.wav")
    message, status = cli.error("analyze", missing)
    with pytest.raises(bouncecal.InputError) as raised:
        bouncecal.analyze(missing)
    assert str(raised.value) == message
    assert raised.value.exit_status == status == 2
    assert isinstance(raised.value, ValueError) and isinstance(raised.value, bouncecal.Error)


def test_a_detector_option_out_of_range_raises_the_commands_message_naming_the_keyword(
        cli, steel_sample):
    # One library message: the command line spells the field as its flag, Python as its keyword.
    message, status = cli.error("analyze", steel_sample, "--rise-threshold-db", "-3")
    assert message.startswith("--rise-threshold-db must be in (0, 60] dB")
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.analyze(steel_sample, rise_threshold_db=-3)
    assert str(raised.value) == message.replace("--rise-threshold-db", "rise_threshold_db")
    assert raised.value.exit_status == status == 3


def test_a_height_the_bounces_contradict_is_recorded_and_a_rebound_above_it_refused(
        steel_sample):
    # The sample was dropped from 0.20 m; its first rebound rises to 0.084 m.
    consistent = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    check = consistent.sequences[0].drop_height_check
    assert check.consistent and abs(check.implied_drop_height_m - 0.2) < 0.01
    assert consistent.sequences[0].drop_height_m == 0.2
    wrong = bouncecal.analyze(steel_sample, drop_height_m=0.5)
    assert not wrong.sequences[0].drop_height_check.consistent
    with pytest.raises(bouncecal.ConfigError) as raised:
        bouncecal.analyze(steel_sample, drop_height_m=0.05)
    assert "omit drop_height_m" in str(raised.value) and "--" not in str(raised.value)


@pytest.mark.parametrize("options, error, words", [
    ({"first_n": 0}, bouncecal.ConfigError, "first_n must be at least 1"),
    ({"drop_height_m": -0.2}, bouncecal.ConfigError, "drop_height_m must be a positive"),
    ({"gravity_mps2": float("nan")}, bouncecal.ConfigError, "gravity_mps2 must be a positive"),
    ({"sample_rate_hz": 48000}, bouncecal.ConfigError, "sample_rate_hz is for an array"),
    ({"channel": 3}, bouncecal.ConfigError, "does not exist"),
])
def test_bad_keywords_raise_one_line_errors_naming_them(steel_sample, options, error, words):
    with pytest.raises(error) as raised:
        bouncecal.analyze(steel_sample, **options)
    assert words in str(raised.value) and "\n" not in str(raised.value)


def test_an_unknown_keyword_is_a_type_error(steel_sample):
    with pytest.raises(TypeError):
        bouncecal.analyze(steel_sample, drop_height=0.2)


@pytest.mark.parametrize("samples, rate, words", [
    (numpy.zeros(48000), None, "sample_rate_hz is needed"),
    (numpy.zeros(48000), 1000, "sample_rate_hz must be a whole number of Hz in 8000..768000"),
    (numpy.zeros((48000, 2)), 48000, "give one channel as a 1-D array"),
    (numpy.zeros(1), 48000, "needs at least two"),
    (numpy.array([0.0, math.nan, 0.0]), 48000, "sample 1 is not a finite number"),
    (["a", "b"], 48000, "not an array of numbers"),
])
def test_bad_sample_arrays_raise_one_line_errors(samples, rate, words):
    with pytest.raises((bouncecal.InputError, bouncecal.ConfigError)) as raised:
        bouncecal.analyze(samples, sample_rate_hz=rate)
    assert words in str(raised.value) and "\n" not in str(raised.value)


def test_silence_gives_no_impacts_and_no_sequences():
    result = bouncecal.analyze(numpy.zeros(48000, dtype=numpy.float32), sample_rate_hz=48000)
    assert len(result.impacts) == 0 and result.impacts.onset_s.shape == (0,)
    assert result.sequences == []
