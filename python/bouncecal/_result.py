"""What the module's functions return: the command line's JSON as Python objects.

A Result is a dict with the keys of the JSON the matching command writes (``bouncecal analyze
--json``, ``calibrate --json``, ...), each also readable as an attribute: ``r["sequences"]`` and
``r.sequences`` are the same object. Numbers in sequence are numpy arrays. Lists of per-event
records (an analysis' impacts and rejected events, a drop's impacts and trajectory) are Tables:
Results whose every key is a column, a numpy array (or a list of strings) with one entry per
event. ``to_dict()`` and ``to_json()`` give back the JSON's shape: lists for arrays, a list of
records for a Table, None for what is not a finite number.
"""

import json
import math

import numpy


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
