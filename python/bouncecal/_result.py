"""What the module's functions return: the command line's JSON as Python objects.

A Result is a dict with the keys of the JSON the matching command writes (``bouncecal analyze
--json``, ``calibrate --json``, ...), each also readable as an attribute: ``r["sequences"]`` and
``r.sequences`` are the same object. Numbers in sequence are numpy arrays. Lists of per-event
records (an analysis' impacts and rejected events, a drop's impacts and trajectory) are Tables:
Results whose every key is a column, a numpy array (or a list of strings) with one entry per
event. ``to_dict()`` and ``to_json()`` give back the JSON's shape: lists for arrays, a list of
records for a Table, None for what is not a finite number. ``repr()`` and a notebook show a
summary (bouncecal._summary), not the whole JSON.
"""

import json
import math

import numpy

from . import _frames, _summary


class Result(dict):
    """A dict with the JSON's keys, each also readable as an attribute."""

    __slots__ = ()

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(
                f"{type(self).__name__} has no field {name!r}; its fields are "
                f"{', '.join(self) or '(none)'}"
            ) from None

    def __dir__(self):
        return sorted(set(super().__dir__()) | set(self))

    def to_dict(self):
        """The JSON value as plain Python: dicts, lists, str, int, float, bool and None."""
        return {key: _plain(value) for key, value in self.items()}

    def to_json(self, indent=2):
        """The JSON text of to_dict()."""
        return json.dumps(self.to_dict(), indent=indent, allow_nan=False)

    def __repr__(self):
        """A summary: the kind of result, its key figures, the sizes of what it holds and its
        fields, within 2000 characters. to_json() shows everything."""
        return _summary.text(self)

    def _repr_html_(self):
        """The summary as HTML, for notebooks."""
        return _summary.html_text(self)


class Table(Result):
    """Per-event records as columns of equal length (numpy arrays, or lists of strings)."""

    __slots__ = ()

    def __len__(self):
        """The number of records (rows), not of columns."""
        for column in self.values():
            return len(column)
        return 0

    def records(self):
        """The rows, each a Result {column: value}."""
        columns = list(self.items())
        return [Result((key, _scalar(column[i])) for key, column in columns)
                for i in range(len(self))]

    def to_dict(self):
        """The JSON value: a list of records (see records())."""
        return [{key: _plain(value) for key, value in row.items()} for row in self.records()]

    def to_dataframe(self):
        """The records as a pandas DataFrame, one row per event (pandas is imported here, and
        only here). A 2-D column (n, d) becomes d columns NAME_0 ... NAME_{d-1}."""
        return _frames.table_frame(self)


class Analysis(Result):
    """The result of analyze(): one recording's impacts, bounce sequences, e_k and eta_k."""

    __slots__ = ()

    def records(self):
        """One Result per detected impact, in time order, with the columns of `bouncecal
        analyze --csv`: file, channel, sequence, k, onset_s, onset_uncertainty_s,
        incoming_flight_uncertainty_s, peak_dbfs, interval_s, bounce_height_m, restitution, restitution_uncertainty, energy_loss,
        energy_loss_uncertainty, residual_only, timed_from_response (docs/json.md). k is the
        impact's 1-based place in its sequence (eta_k's k, restitution_impact_index + 1);
        sequence and k are None for an impact in no sequence, and what the sequence does not
        give (e_k of its first impact without a drop height, the flight after its last) is
        None."""
        return [Result(row) for row in _frames.impact_rows(self)]

    def to_dataframe(self):
        """records() as a pandas DataFrame (pandas is imported here, and only here): float
        columns with NaN, sequence and k as pandas' nullable Int64 with <NA>, the two flags
        bool."""
        return _frames.impact_frame(self)


class Calibration(Result):
    """The result of calibrate(), which can also make the fit's material card."""

    __slots__ = ("_card_source",)

    def card(self, created_at=None):
        """The material card (bouncecal-material/1) as a Result. created_at: seconds since
        1970-01-01 UTC stamped into it (default: SOURCE_DATE_EPOCH when set, else now)."""
        return self._card_source.card(created_at)

    def write_card(self, path, created_at=None):
        """Write the material card to path (atomically) and return it as a Result."""
        return self._card_source.write_card(path, created_at)


def _scalar(value):
    if isinstance(value, numpy.generic):
        return value.item()
    return value


def _plain(value):
    if isinstance(value, Result):
        return value.to_dict()
    if isinstance(value, numpy.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [_plain(item) for item in value]
    if isinstance(value, numpy.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
