"""Per-row views of results: an analysis as one row per impact (the rows of `bouncecal analyze
--csv`) and Tables, as records or as pandas DataFrames.

pandas is imported only when a DataFrame is asked for: the module does not need it otherwise.
"""

import numpy

from . import _bouncecal

# The columns of `bouncecal analyze --csv`, in its order (calibrate::kImpactRowColumns).
IMPACT_COLUMNS = _bouncecal._IMPACT_COLUMNS
# Column types of the DataFrame: counts that are None for an impact in no sequence are pandas'
# nullable Int64 (<NA>), so they stay integers whatever the recording.
_DTYPES = {"channel": "int64", "sequence": "Int64", "k": "Int64", "residual_only": "bool",
           "timed_from_response": "bool"}


def impact_rows(analysis):
    """One dict per detected impact, in time order, with IMPACT_COLUMNS: its sequence (None when
    in none), k (1-based position within the sequence, as eta_k is numbered; None when in no
    sequence), its onset and peak, the flight after it and, where the sequence gives them, e_k
    and eta_k with their uncertainties (None otherwise). Built by the library's row builder
    from the analysis' JSON shape, as the command line's --csv is."""
    return _bouncecal._impact_rows(analysis.to_dict())


def impact_frame(analysis):
    """impact_rows(analysis) as a pandas DataFrame (float columns NaN where a row has None)."""
    pandas = _pandas()
    frame = pandas.DataFrame(impact_rows(analysis), columns=list(IMPACT_COLUMNS))
    for column in IMPACT_COLUMNS[1:]:  # all but the file name
        frame[column] = frame[column].astype(_DTYPES.get(column, "float64"))
    return frame


def table_frame(table):
    """A Table's columns as a DataFrame, one row per event; a 2-D column (a position per
    particle) becomes one column per component, NAME_0, NAME_1, ..."""
    pandas = _pandas()
    columns = {}
    for key, column in table.items():
        if isinstance(column, numpy.ndarray) and column.ndim == 2:
            for component in range(column.shape[1]):
                columns[f"{key}_{component}"] = column[:, component]
        else:
            columns[key] = column
    return pandas.DataFrame(columns)


def _pandas():
    try:
        import pandas
    except ImportError as error:
        raise ImportError(
            "to_dataframe() needs pandas (Debian: apt-get install python3-pandas; pip: "
            "pip install pandas); records() gives the same rows without it") from error
    return pandas
