"""repr() and the notebook display of results: a summary within 2000 characters, not the JSON."""

import os
import pathlib

import pytest

import bouncecal
from conftest import SOURCE_DIR, STEREO_SAMPLE

LIMIT = 2000  # characters; issue 33: the raw dict of a ping-pong analysis was 14 864
# A real ping-pong recording, 48 impacts (recordings/SOURCES.md in the shared folder).
SHARED_DIR = pathlib.Path(os.environ.get("BOUNCECAL_SHARED_DIR", SOURCE_DIR / ".." / "shared"))
PINGPONG = SHARED_DIR / "recordings" / "eeps-pingpong" / "pingpong.wav"


@pytest.fixture(scope="module")
def fit(steel_sample):
    return bouncecal.calibrate(steel_sample, ball="steel-10mm", drop_height_m=0.2)


@pytest.fixture(scope="module")
def results(steel_sample, fit):
    return {
        "analysis": bouncecal.analyze(steel_sample, drop_height_m=0.2),
        "two sequences": bouncecal.analyze(STEREO_SAMPLE),
        "fit": fit,
        "card": fit.card(created_at=0),
        "drop": bouncecal.simulate_drop(max_impacts=20),
        "export": bouncecal.export(fit.card(created_at=0)),
        "pack": bouncecal.pack(SOURCE_DIR / "samples" / "scenes" / "paper000_cylinder_pour.json",
                               duration_s=0),
    }


def test_every_result_and_table_is_summarised_within_the_limit(results):
    for name, result in results.items():
        shown = [(name, result)] + [(f"{name}.{key}", value) for key, value in result.items()
                                    if isinstance(value, bouncecal.Result)]
        for label, value in shown:
            assert len(repr(value)) <= LIMIT, label
            assert len(value._repr_html_()) <= LIMIT, label
            assert len(value.to_json()) > 0  # everything stays available
            assert repr(value).startswith(f"<bouncecal.{type(value).__name__}"), label


def test_a_long_recordings_summary_is_short_and_says_what_it_holds():
    if not PINGPONG.is_file():
        pytest.skip(f"{PINGPONG} (the shared recordings) is not on this machine")
    result = bouncecal.analyze(PINGPONG)
    assert len(result.to_json()) > 5 * LIMIT  # what repr printed before
    text = repr(result)
    assert len(text) <= LIMIT and len(result._repr_html_()) <= LIMIT
    assert f"{len(result.impacts)} impacts in {len(result.sequences)} sequence" in text
    assert all(field in text for field in result)  # the fields list
    assert "pingpong.wav" in text


def test_an_analysis_summary_gives_each_sequences_eta_bar(results):
    result = results["analysis"]
    sequence = result.sequences[0]
    text = repr(result)
    assert f"eta-bar of the first 3 = {sequence.energy_loss_mean_first_n:.4g}" in text
    assert f"{len(sequence.onsets_s)} impacts" in text
    assert "1 rejected event" in text
    two = repr(results["two sequences"])
    assert "sequence 0:" in two and "sequence 1:" in two


def test_a_fits_summary_gives_the_parameter_and_its_interval(fit):
    low, high = fit.confidence_interval.gamma_n
    expected = (f"gamma_n: {fit.parameters.gamma_n:.4g}, 95 % interval [{low:.4g}, {high:.4g}]")
    assert expected in repr(fit)
    html = fit._repr_html_()
    assert "gamma_n" in html and f"{high:.4g}" in html and "<table>" in html
    assert repr(fit).startswith("<bouncecal.Calibration bouncecal-fit/1")


def test_a_tables_summary_gives_its_size_and_columns_and_the_html_its_first_rows(results):
    impacts = results["analysis"].impacts
    text = repr(impacts)
    assert text.startswith(f"<bouncecal.Table of {len(impacts)} rows × 9 columns")
    assert "onset_s (float64)" in text and "timed_from_response (bool)" in text
    html = impacts._repr_html_()
    assert f"{impacts.onset_s[0]:.4g}" in html and f"… {len(impacts) - 3} more rows" in html


def test_text_in_a_result_is_escaped_in_html():
    result = bouncecal.Result(note="<script>alert(1)</script> & more")
    assert "<script>" not in result._repr_html_() and "&lt;script&gt;" in result._repr_html_()


def test_a_result_of_any_size_stays_within_the_limit():
    # Long fields are shortened, never the limit broken: many fields, long text, deep tables.
    huge = bouncecal.Result({f"field_{i:04d}": "x" * 500 for i in range(300)})
    huge["table"] = bouncecal.Table({f"column_{i}": list("ab") for i in range(200)})
    for value in (huge, huge["table"]):
        assert len(repr(value)) <= LIMIT and len(value._repr_html_()) <= LIMIT
    assert "field_0000" in repr(huge)


def test_a_fits_warnings_are_shown_with_the_options_they_name_as_keywords(steel_sample):
    # A tennis ball with the law's default stiffness would touch for 0.26 ms, not ~5 ms: the
    # library's warning names the option neutrally (`contact_duration_s=0.005`), as in the JSON
    # document, and the summary spells it as the keyword.
    fit = bouncecal.calibrate(steel_sample, ball="tennis")
    warning = next(w for w in fit.warnings if "contact last" in w)
    assert "`contact_duration_s=0.005`" in warning
    text = repr(fit).replace("\n      ", " ")
    assert "give contact_duration_s=0.005 (or your measured one)" in text and "`" not in text
