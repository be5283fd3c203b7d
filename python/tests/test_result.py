"""Result, Table and the exceptions: the conventions every function's output follows."""

import json
import math

import numpy
import pytest

import bouncecal


def walk(value, path="result"):
    """Every (path, Result) inside value."""
    if isinstance(value, bouncecal.Result):
        yield path, value
        for key, item in value.items():
            yield from walk(item, f"{path}.{key}")
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from walk(item, f"{path}[{index}]")


@pytest.fixture(scope="module")
def results(steel_sample):
    fit = bouncecal.calibrate(steel_sample, ball="steel-10mm", drop_height_m=0.2)
    return {
        "analyze": bouncecal.analyze(steel_sample, drop_height_m=0.2),
        "simulate_drop": bouncecal.simulate_drop(max_impacts=5),
        "calibrate": fit,
        "card": fit.card(created_at=0),
        "export": bouncecal.export(fit.card(created_at=0)),
    }


def test_every_field_reads_as_an_attribute_and_none_is_shadowed(results):
    # A key named like a dict method (items, values, ...) would read as the method: none may.
    for name, result in results.items():
        for path, record in walk(result, name):
            for key, value in record.items():
                assert getattr(record, key) is value, f"{path}.{key}"


def test_a_missing_field_is_an_attribute_error_listing_the_fields():
    result = bouncecal.simulate_drop(max_impacts=2)
    with pytest.raises(AttributeError, match="has no field 'impact'.*impacts"):
        result.impact  # noqa: B018


def test_every_result_writes_as_json_with_null_for_what_is_not_a_number(results):
    for name, result in results.items():
        text = result.to_json()
        assert json.loads(text) == result.to_dict(), name
    # A rise the detector did not measure (NaN in the column) is null in the JSON.
    impacts = results["analyze"].impacts
    novelty = impacts.ringing_novelty_db
    rows = impacts.to_dict()
    for value, row in zip(novelty, rows):
        assert (row["ringing_novelty_db"] is None) == (not math.isfinite(value))


def test_a_table_has_one_record_per_row():
    table = bouncecal.simulate_drop(max_impacts=4).impacts
    assert len(table) == 4 == len(table.records())
    first = table.records()[0]
    assert isinstance(first, bouncecal.Result)
    assert first.time_s == table.time_s[0] and type(first.time_s) is float
    assert type(first.released) is bool
    assert bouncecal.Table().records() == [] and len(bouncecal.Table()) == 0


def test_numbers_in_sequence_are_numpy_arrays_of_int64_or_float64(results):
    fit = results["calibrate"]
    assert fit.uncertainty.recordings[0].parameter_values.dtype == numpy.float64
    assert fit.sequences[0].measured.impact_index.dtype == numpy.int64
    assert fit.model_adequacy.speed_range_mps.shape == (2,)
    assert isinstance(fit.warnings, list)


@pytest.mark.parametrize("error, bases, status", [
    (bouncecal.InputError, (bouncecal.Error, ValueError), 2),
    (bouncecal.ConfigError, (bouncecal.Error, ValueError), 3),
    (bouncecal.OutputError, (bouncecal.Error, OSError), 4),
    (bouncecal.CheckFailedError, (bouncecal.Error,), 5),
])
def test_each_error_is_the_python_error_it_behaves_like_and_has_the_commands_exit_status(
        error, bases, status):
    # README.md, exit status: 2 input file, 3 option, 4 output file, 5 failed check.
    assert issubclass(error, bases)
    assert error.exit_status == status


def test_the_version_is_the_libraries():
    assert bouncecal.__version__.count(".") == 2
