"""An analysis as one row per impact (records(), to_dataframe()), as `bouncecal analyze --csv`
writes it, and Tables as DataFrames. pandas is optional: the tests that need it skip without it,
the rows themselves are checked without it."""

import contextlib
import csv
import io
import json
import math
import subprocess
import sys

import numpy
import pytest

import bouncecal
from conftest import STEREO_SAMPLE

COLUMNS = ["file", "channel", "sequence", "k", "onset_s", "onset_uncertainty_s",
           "incoming_flight_uncertainty_s", "peak_dbfs", "interval_s", "bounce_height_m", "restitution", "restitution_uncertainty",
           "energy_loss", "energy_loss_uncertainty", "residual_only", "timed_from_response"]
FLAGS = ("residual_only", "timed_from_response")  # written true / false
# Half a unit in the last place the CSV writes each column with (calibrate::AnalysisCsv): onsets,
# intervals and heights with 9 decimals, e and eta with 6, the peak level with 2.
CSV_ROUNDING = {"onset_s": 5e-10, "onset_uncertainty_s": 5e-10,
                "incoming_flight_uncertainty_s": 5e-10, "interval_s": 5e-10,
                "bounce_height_m": 5e-10, "peak_dbfs": 5e-3, "restitution": 5e-7,
                "restitution_uncertainty": 5e-7, "energy_loss": 5e-7,
                "energy_loss_uncertainty": 5e-7}


def cli_rows(cli, recording, tmp_path, *arguments):
    output = tmp_path / "impacts.csv"
    cli.run("analyze", recording, *arguments, "--csv", output)
    with open(output, newline="") as file:
        return list(csv.DictReader(file))


@pytest.mark.parametrize("recording, arguments", [
    ("steel", ["--drop-height-m", "0.2"]),
    ("steel", []),  # no e_1: the first impact's row has no restitution
    ("stereo", ["--channel", "1"]),  # two sequences
])
def test_the_rows_are_the_commands_csv_rows(cli, steel_sample, tmp_path, recording, arguments):
    path = steel_sample if recording == "steel" else str(STEREO_SAMPLE)
    expected = cli_rows(cli, path, tmp_path, *arguments)
    keywords = {"drop_height_m": 0.2} if "--drop-height-m" in arguments else {}
    if "--channel" in arguments:
        keywords["channel"] = 1
    rows = bouncecal.analyze(path, **keywords).records()
    assert len(rows) == len(expected) > 0
    assert all(list(row) == COLUMNS for row in rows)
    for number, (row, line) in enumerate(zip(rows, expected)):
        assert list(line) == COLUMNS
        for column in COLUMNS:
            text, value = line[column], row[column]
            if column == "file":
                assert value == text
            elif text == "":
                assert value is None, (number, column)
            elif column in FLAGS:
                assert isinstance(value, bool) and value == (text == "true"), (number, column)
                assert text in ("true", "false"), (number, column)
            elif column in CSV_ROUNDING:
                assert abs(value - float(text)) <= CSV_ROUNDING[column], (number, column)
            else:
                assert value == int(text), (number, column)


def test_every_impact_of_a_sequence_is_numbered_as_eta_k_is(steel_sample):
    result = bouncecal.analyze(steel_sample)  # no height: e_k from the second impact on
    sequence = result.sequences[0]
    rows = [row for row in result.records() if row.sequence == 0]
    assert [row.k for row in rows] == list(range(1, len(sequence.onsets_s) + 1))
    assert rows[0].restitution is None and rows[0].interval_s == sequence.intervals_s[0]
    assert rows[-1].interval_s is None  # no flight after the last impact
    with_e = [row for row in rows if row.energy_loss is not None]
    assert [row.k - 1 for row in with_e] == sequence.restitution_impact_index.tolist()
    assert [row.energy_loss for row in with_e] == sequence.energy_loss.tolist()


def test_an_analysis_read_back_from_its_json_gives_the_same_rows(steel_sample):
    # The rows are built from the document's shape (calibrate::ImpactRows, as the CSV's are), so
    # an analysis saved with to_json() and loaded again gives them without re-analysing.
    result = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    loaded = bouncecal.Analysis(json.loads(result.to_json()))
    assert loaded.records() == result.records() and len(loaded.records()) == len(result.impacts)


def test_an_analysis_without_its_impacts_says_what_it_needs(steel_sample):
    broken = bouncecal.Analysis(bouncecal.analyze(steel_sample))
    del broken["impacts"]
    with pytest.raises(bouncecal.InputError, match="impacts"):
        broken.records()


def test_an_impact_in_no_sequence_has_a_row_without_sequence_values():
    # Two clicks 0.3 s apart make impacts but no bounce sequence (four are needed).
    rate = 48000
    samples = numpy.zeros(rate, dtype=numpy.float32)
    for start in (0.2, 0.5):
        i = int(start * rate)
        samples[i:i + 200] = 0.5 * numpy.exp(-numpy.arange(200) / 40.0) * numpy.sin(
            numpy.arange(200) * 2.0)
    result = bouncecal.analyze(samples, sample_rate_hz=rate)
    rows = result.records()
    assert len(rows) == len(result.impacts) >= 1 and result.sequences == []
    assert all(row.sequence is None and row.k is None and row.restitution is None for row in rows)
    assert rows[0].file is None  # samples, not a file


def test_importing_bouncecal_does_not_import_pandas():
    code = "import sys, bouncecal; sys.exit('pandas' in sys.modules)"
    assert subprocess.run([sys.executable, "-c", code]).returncode == 0


def test_without_pandas_to_dataframe_says_what_to_install(steel_sample, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` now fails
    result = bouncecal.analyze(steel_sample)
    for value in (result, result.impacts):
        with pytest.raises(ImportError, match="python3-pandas"):
            value.to_dataframe()


def test_the_dataframe_has_one_row_per_impact(steel_sample):
    pandas = pytest.importorskip("pandas")
    result = bouncecal.analyze(steel_sample, drop_height_m=0.2)
    frame = result.to_dataframe()
    assert isinstance(frame, pandas.DataFrame)
    assert list(frame.columns) == COLUMNS and len(frame) == len(result.impacts)
    rows = result.records()
    for column in COLUMNS[4:]:
        if column in FLAGS:
            assert frame[column].dtype == numpy.bool_
            assert frame[column].tolist() == [row[column] for row in rows]
            continue
        assert frame[column].dtype == numpy.float64
        expected = [math.nan if row[column] is None else row[column] for row in rows]
        numpy.testing.assert_array_equal(frame[column].to_numpy(), expected)
    assert str(frame["k"].dtype) == "Int64" and str(frame["sequence"].dtype) == "Int64"
    assert frame["k"].tolist()[:3] == [1, 2, 3]


def test_a_tables_dataframe_has_its_columns_and_splits_vectors(steel_sample):
    pandas = pytest.importorskip("pandas")
    impacts = bouncecal.analyze(steel_sample).impacts
    frame = impacts.to_dataframe()
    assert list(frame.columns) == list(impacts) and len(frame) == len(impacts)
    numpy.testing.assert_array_equal(frame["onset_s"].to_numpy(), impacts.onset_s)
    table = bouncecal.Table(position_m=numpy.arange(6.0).reshape(3, 2),
                            species=["a", "b", "c"])
    split = table.to_dataframe()
    assert isinstance(split, pandas.DataFrame)
    assert list(split.columns) == ["position_m_0", "position_m_1", "species"]
    assert split["position_m_1"].tolist() == [1.0, 3.0, 5.0]


def test_the_notebook_session_of_the_docs_prints_what_the_page_shows(steel_sample, tmp_path,
                                                                      monkeypatch):
    # docs/python.md's DataFrame block is skipped by test_docs_example.py (pandas is optional);
    # here it runs, where pandas is, on the worked example's `recording`, and prints its table.
    pytest.importorskip("pandas")
    from test_docs_example import PAGE, blocks
    found = [(code, output) for code, output, skipped in blocks(PAGE.read_text())
             if skipped and "to_dataframe()" in code]
    assert len(found) == 1
    code, expected = found[0]
    monkeypatch.chdir(tmp_path)  # where the plot goes, when matplotlib is installed
    namespace = {"recording": bouncecal.analyze(steel_sample, drop_height_m=0.2)}
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "docs/python.md, the DataFrame block", "exec"), namespace)
    assert printed.getvalue() == expected
